/* Mirroring across the world's x = 0 plane, swapping left and right joints.
 *
 * With the reflection M = diag(-1, 1, 1), a joint's mirrored world transform is taken from its
 * partner's: position M p, rotation M R M C, where C is a fixed per-joint correction for how the
 * skeleton's local frames are laid out: for every child k of the joint, C o_k = M o_k', with k'
 * the partner of k (so the children land where the mirrored partner's children are). For symmetric skeletons
 * C is one of the identity and the three half-turns about the axes, found exactly; otherwise the best
 * rotation is fitted. Mirroring twice gives the clip back.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "db/process.h"

/* Name of the partner of name under the config's pairs ("Left"->"Right" and back; a pattern
 * starting with '^' matches only at the start). Returns 0 when no pattern applies. */
static int partner_name(const char *name, const mm_config *cfg, char *out)
{
    for (int p = 0; p < cfg->mirror_pair_count; ++p)
        for (int side = 0; side < 2; ++side) {
            const char *from = side ? cfg->mirror_pairs[p].right : cfg->mirror_pairs[p].left;
            const char *to = side ? cfg->mirror_pairs[p].left : cfg->mirror_pairs[p].right;
            int anchored = from[0] == '^';
            if (anchored) ++from, ++to;
            if (to[0] == '^') ++to;
            size_t fl = strlen(from);
            if (!fl) continue;
            const char *at = anchored ? (strncmp(name, from, fl) == 0 ? name : NULL) : strstr(name, from);
            if (!at) continue;
            size_t pre = (size_t)(at - name);
            int n = snprintf(out, MM_NAME_MAX, "%.*s%s%s", (int)pre, name, to, at + fl);
            if (n > 0 && n < MM_NAME_MAX) return 1;
        }
    return 0;
}

void mm__mirror_map(const mm_skeleton *s, const mm_config *cfg, int *partner)
{
    char other[MM_NAME_MAX];
    for (int j = 0; j < s->joint_count; ++j) {
        partner[j] = j;
        if (partner_name(s->joints[j].name, cfg, other)) {
            int k = mm_skeleton_find(s, other);
            if (k >= 0) partner[j] = k;
        }
    }
}

static mm_vec3 reflect(mm_vec3 v) { return mm_vec3_make(-v.x, v.y, v.z); }
/* M R M for a rotation R: the quaternion (x, -y, -z, w). */
static mm_quat reflect_rotation(mm_quat q) { return mm_quat_make(q.x, -q.y, -q.z, q.w); }

/* The correction C of joint j: maps the offsets of j's (non-translating) children onto the
 * reflected offsets of their partners. Where several fit (a chain's single child along an axis, a
 * leaf), prefer, the parent's correction, wins: with the same correction along a chain the mirrored
 * local rotations stay close to the original ones, instead of differing by half-turns that every
 * transition between a clip and a mirrored clip would have to blend through. */
static mm_quat correction(const mm_skeleton *s, const int *partner, int j, mm_quat prefer)
{
    const mm_quat candidates[4] = {mm_quat_make(0, 0, 0, 1), mm_quat_make(1, 0, 0, 0),
                                   mm_quat_make(0, 1, 0, 0), mm_quat_make(0, 0, 1, 0)};
    int jp = partner[j];
    mm_vec3 from[64], to[64];
    int n = 0;
    for (int k = 0; k < s->joint_count && n < 64; ++k) {
        if (s->joints[k].parent != j || (s->joints[k].flags & MM_JOINT_TRANSLATES)) continue;
        int kp = partner[k];
        if (s->joints[kp].parent != jp) continue;
        from[n] = s->joints[k].offset;
        to[n] = reflect(s->joints[kp].offset);
        ++n;
    }
    if (s->joints[j].has_end_site && s->joints[jp].has_end_site && n < 64) {
        from[n] = s->joints[j].end_site;
        to[n] = reflect(s->joints[jp].end_site);
        ++n;
    }
    if (n == 0) return prefer; /* a leaf: any rotation fits; the parent's keeps the chain's local rotations */
    float best_err = INFINITY, scale = 0.0f;
    mm_quat best = candidates[0];
    for (int i = 0; i < n; ++i) scale = fmaxf(scale, mm_vec3_length(to[i]));
    for (int c = -1; c < 4; ++c) {
        mm_quat q = c < 0 ? prefer : candidates[c];
        float e = 0.0f;
        for (int i = 0; i < n; ++i) e = fmaxf(e, mm_vec3_distance(mm_quat_rotate(q, from[i]), to[i]));
        if (c < 0) {
            if (e <= 1e-3f * fmaxf(scale, 1e-6f)) return prefer;
            continue;
        }
        if (e < best_err) {
            best_err = e;
            best = candidates[c];
        }
    }
    if (best_err <= 1e-3f * fmaxf(scale, 1e-6f)) return best;
    /* Not an axis-aligned symmetry: the smallest rotation taking the main child where it goes. */
    int main_child = 0;
    for (int i = 1; i < n; ++i)
        if (mm_vec3_length(from[i]) > mm_vec3_length(from[main_child])) main_child = i;
    return mm_quat_between(from[main_child], to[main_child]);
}

mm_result mm__clip_mirror(const mm_clip *src, const mm_config *cfg, mm_clip *out, const mm_allocator *a)
{
    const mm_skeleton *s = &src->skeleton;
    int jc = s->joint_count;
    mm_result r = mm_clip_init(out, s, src->frame_count, src->fps, a);
    if (r != MM_OK) return r;
    int *partner = (int *)malloc(sizeof(int) * (size_t)jc);
    mm_quat *fix = (mm_quat *)malloc(sizeof(mm_quat) * (size_t)jc);
    mm_xform *g = (mm_xform *)malloc(sizeof(mm_xform) * (size_t)jc * 2);
    if (!partner || !fix || !g) {
        free(partner);
        free(fix);
        free(g);
        mm_clip_free(out);
        return MM_ERR_OUT_OF_MEMORY;
    }
    mm__mirror_map(s, cfg, partner);
    for (int j = 0; j < jc; ++j)
        fix[j] = correction(s, partner, j,
                            s->joints[j].parent >= 0 ? fix[s->joints[j].parent] : mm_quat_identity());
    mm_xform *mg = g + jc;
    for (int f = 0; f < src->frame_count; ++f) {
        mm_clip_fk(src, f, g);
        for (int j = 0; j < jc; ++j) {
            const mm_xform *p = &g[partner[j]];
            mg[j] = mm_xform_make(mm_quat_normalize(mm_quat_mul(reflect_rotation(p->rotation), fix[j])),
                                  reflect(p->translation));
        }
        mm_quat *rot = mm_clip_rotations(out, f);
        mm_vec3 *pos = mm_clip_positions(out, f);
        mm_global_to_local(s, mg, rot, pos);
        for (int j = 0; j < jc; ++j)
            if (!(s->joints[j].flags & MM_JOINT_TRANSLATES) && s->joints[j].parent >= 0)
                pos[j] = s->joints[j].offset;
    }
    free(partner);
    free(fix);
    free(g);
    return MM_OK;
}
