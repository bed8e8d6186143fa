/* Mirroring across the world's x = 0 plane, swapping left and right joints.
 *
 * A mirrored clip is defined by its world pose. With the reflection M = diag(-1, 1, 1), joint j
 * takes its partner p's world transform reflected: position M x_p, rotation M R_p N_j, where N_j
 * is the reflection of the joint's own rest axes (a reflection in its local frame: what M is in
 * the world's). M R_p N_j is a rotation again, written M R_p M C_j with the rotation C_j = M N_j.
 * The rotations are then made local to each joint's parent.
 *
 * The rest axes: a skeleton's rest pose (every local rotation the identity) is symmetric across
 * some plane through its root, whatever way its bones point: across x = 0 for a T-pose facing +Z
 * (the built-in set, games105, CMU), across z = 0 for LAFAN1's, across a tilted plane when the
 * rest axes are rotated. That plane's reflection S, found from the rest offsets, is every joint's
 * N: it maps each joint's rest axes onto its partner's. The simulation bone's frame is the
 * character's, so its N is M. Where the rest pose is not symmetric at a joint (its children's
 * rest offsets more than 30 degrees from the reflected partners'), the joint's N is fitted to
 * them (the rotation closest to the parent's that maps them) and its descendants start from it.
 * Mirroring twice gives the clip back.
 */
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "db/process.h"

/* Name of the partner of name under the config's pairs ("Left"->"Right" and back; a pattern
 * starting with '^' matches only at the start). Returns 0 when no pattern applies; *word tells
 * whether the pattern stands as a word of its own there: one letter is a side only when no
 * lowercase letter follows it ("lHip", "Hand_L" but not "lowerback"). */
static int partner_name(const char *name, const mm_config *cfg, char *out, int *word)
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
            if (n > 0 && n < MM_NAME_MAX) {
                if (word) *word = fl > 1 || !islower((unsigned char)at[fl]);
                return 1;
            }
        }
    return 0;
}

void mm__mirror_map(const mm_skeleton *s, const mm_config *cfg, int *partner)
{
    char other[MM_NAME_MAX];
    for (int j = 0; j < s->joint_count; ++j) {
        partner[j] = j;
        if (partner_name(s->joints[j].name, cfg, other, NULL)) {
            int k = mm_skeleton_find(s, other);
            if (k >= 0) partner[j] = k;
        }
    }
}

/* Whether joint k's rest offset is a bone of the rest pose: not a translating joint, under a
 * parent. */
static int rest_bone(const mm_skeleton *s, int k)
{
    return s->joints[k].parent >= 0 && !(s->joints[k].flags & MM_JOINT_TRANSLATES);
}

/* The longest chain of bones from the root (End Sites included): a size that does not depend on
 * which way the rest pose's bones point. */
static float longest_chain(const mm_skeleton *s)
{
    float *along = (float *)malloc(sizeof(float) * (size_t)s->joint_count), longest = 0.0f;
    if (!along) return 0.0f;
    for (int j = 0; j < s->joint_count; ++j) {
        int p = s->joints[j].parent;
        along[j] =
            (p >= 0 ? along[p] : 0.0f) + (rest_bone(s, j) ? mm_vec3_length(s->joints[j].offset) : 0.0f);
        float end = along[j] + (s->joints[j].has_end_site ? mm_vec3_length(s->joints[j].end_site) : 0.0f);
        longest = fmaxf(longest, end);
    }
    free(along);
    return longest;
}

mm_result mm__mirror_check(const mm_skeleton *s, const mm_config *cfg, mm_error *err)
{
    int jc = s->joint_count;
    int *partner = (int *)malloc(sizeof(int) * (size_t)jc);
    if (!partner) return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    mm__mirror_map(s, cfg, partner);
    /* lengths closer than 1% of the longest chain of bones are never told apart (a finger's
     * bones) */
    float close = 0.01f * longest_chain(s);
    mm_result r = MM_OK;
    char other[MM_NAME_MAX];
    for (int j = 0; j < jc && r == MM_OK; ++j) {
        const char *name = s->joints[j].name;
        int word = 0, k = partner[j];
        if (k == j && partner_name(name, cfg, other, &word) && word && strcmp(other, name) != 0) {
            r = mm_error_set(err, MM_ERR_NOT_FOUND, 0, 0,
                             "joint '%s' has no partner: no joint is named '%s' (mirror_pairs)", name, other);
        } else if (partner[k] != j) {
            r = mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                             "joint '%s' pairs with '%s', which pairs with '%s' (mirror_pairs)", name,
                             s->joints[k].name, s->joints[partner[k]].name);
        } else if (k > j) {
            float a = mm_vec3_length(s->joints[j].offset), b = mm_vec3_length(s->joints[k].offset);
            float longer = fmaxf(a, b);
            if (fabsf(a - b) > 0.1f * longer && fabsf(a - b) > close)
                r = mm_error_set(
                    err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                    "the bones of joints '%s' (%.4g) and '%s' (%.4g) differ in length by %.0f%%, "
                    "more than 10%%",
                    name, a, s->joints[k].name, b, 100.0f * fabsf(a - b) / longer);
        }
    }
    free(partner);
    return r;
}

static mm_vec3 reflect(mm_vec3 v) { return mm_vec3_make(-v.x, v.y, v.z); }
/* M R M for a rotation R: the quaternion (x, -y, -z, w). */
static mm_quat reflect_rotation(mm_quat q) { return mm_quat_make(q.x, -q.y, -q.z, q.w); }

/* Eigenvector of the largest eigenvalue of the symmetric n x n matrix a (n <= 4; destroyed), by
 * Jacobi rotations. */
static void top_eigenvector(double a[4][4], int n, double *out)
{
    double v[4][4] = {{0}};
    for (int i = 0; i < n; ++i) v[i][i] = 1.0;
    for (int sweep = 0; sweep < 50; ++sweep) {
        double off = 0.0;
        for (int p = 0; p < n; ++p)
            for (int q = p + 1; q < n; ++q) off += a[p][q] * a[p][q];
        if (off < 1e-30) break;
        for (int p = 0; p < n; ++p)
            for (int q = p + 1; q < n; ++q) {
                if (fabs(a[p][q]) < 1e-300) continue;
                double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                double t = (theta >= 0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
                double c = 1.0 / sqrt(t * t + 1.0), s = t * c;
                for (int k = 0; k < n; ++k) { /* columns p and q */
                    double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < n; ++k) { /* rows p and q */
                    double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for (int k = 0; k < n; ++k) {
                    double vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = c * vkp - s * vkq;
                    v[k][q] = s * vkp + c * vkq;
                }
            }
    }
    int best = 0;
    for (int i = 1; i < n; ++i)
        if (a[i][i] > a[best][best]) best = i;
    for (int i = 0; i < n; ++i) out[i] = v[i][best];
}

/* The quaternion of M S for the reflection S across the plane through the origin with unit
 * normal n: (0, -nz, ny, -nx), signed so that the identity and the half-turns about the axes come
 * out exactly as (0, 0, 0, 1), (1, 0, 0, 0), (0, 1, 0, 0), (0, 0, 1, 0). */
static mm_quat plane_correction(const double n[3])
{
    mm_quat q = mm_quat_make(0.0f, (float)-n[2], (float)n[1], (float)-n[0]);
    if (q.w < 0.0f ||
        (q.w == 0.0f && (q.x < 0.0f || (q.x == 0.0f && (q.y < 0.0f || (q.y == 0.0f && q.z < 0.0f))))))
        q = mm_quat_make(-q.x, -q.y, -q.z, -q.w);
    return mm_quat_make(q.x + 0.0f, q.y + 0.0f, q.z + 0.0f, q.w + 0.0f); /* no negative zeros */
}

static void add_outer(double m[4][4], mm_vec3 d, double w)
{
    const double v[3] = {d.x, d.y, d.z};
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) m[r][c] += w * v[r] * v[c];
}

/* Unit vector of v and its length (0 and a zero vector for a vector shorter than tiny). */
static float unit(mm_vec3 v, float tiny, mm_vec3 *out)
{
    float l = mm_vec3_length(v);
    *out = l > tiny ? mm_vec3_scale(v, 1.0f / l) : mm_vec3_make(0, 0, 0);
    return l > tiny ? l : 0.0f;
}

/* The rest pose's plane of symmetry (unit normal n). Partners' rest offsets (a joint without a
 * partner is its own) have directions u, u' with S u = u': their difference is along n, their
 * mean in the plane. n is the top eigenvector of sum w ((u - u')(u - u')^T - m m^T), m the mean,
 * over the offsets both sides hold in one frame (under a joint without a partner: the hips' legs,
 * the chest's shoulders, the spine) when there are partners among them, else over all (CMU's legs
 * and arms start with zero offsets). A plane within 2 degrees of an axis plane is that plane
 * (capture skeletons are drawn on the axes; what is left is their asymmetry). x = 0 when nothing
 * tells. */
static void rest_plane(const mm_skeleton *s, const int *partner, double n[3])
{
    double a[2][4][4] = {{{0}}}; /* [0]: offsets in one frame, [1]: all */
    int pairs[2] = {0, 0}, bones = 0;
    float tiny = 1e-6f * fmaxf(longest_chain(s), 1e-6f);
    for (int j = 0; j < s->joint_count; ++j) {
        int k = partner[j], p = s->joints[j].parent;
        if (k < j || !rest_bone(s, j) || !rest_bone(s, k) || partner[p] != s->joints[k].parent) continue;
        mm_vec3 offsets[2][2] = {{s->joints[j].offset, s->joints[k].offset},
                                 {s->joints[j].end_site, s->joints[k].end_site}};
        int ends = s->joints[j].has_end_site && s->joints[k].has_end_site;
        for (int e = 0; e <= ends; ++e) {
            mm_vec3 uj, uk;
            float lj = unit(offsets[e][0], tiny, &uj), lk = unit(offsets[e][1], tiny, &uk);
            if (lj == 0.0f || lk == 0.0f) continue;
            double w = 0.5 * (lj + lk);
            int shared = e == 0 ? partner[p] == p : k == j; /* the offsets' frame: the parent's, or j's */
            for (int set = shared ? 0 : 1; set < 2; ++set) {
                add_outer(a[set], mm_vec3_sub(uj, uk), w);
                add_outer(a[set], mm_vec3_scale(mm_vec3_add(uj, uk), 0.5f), -w);
                pairs[set] += k != j;
            }
            ++bones;
        }
    }
    n[0] = 1.0, n[1] = n[2] = 0.0;
    if (!bones) return;
    double v[4];
    top_eigenvector(a[pairs[0] > 0 ? 0 : 1], 3, v);
    double len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(len > 0.0)) return;
    for (int i = 0; i < 3; ++i) n[i] = v[i] / len;
    for (int i = 0; i < 3; ++i)
        if (fabs(n[i]) >= cos(2.0 * MM_DEG_TO_RAD)) {
            n[0] = n[1] = n[2] = 0.0;
            n[i] = 1.0;
        }
}

/* The rotation V closest to the identity with V a_i = b_i for unit vectors a_i, b_i (weights
 * w_i), in the least-squares sense (Horn's quaternion method, the identity weighted in a little so
 * that what the pairs leave open stays put). */
static mm_quat fit_rotation(const mm_vec3 *a, const mm_vec3 *b, const float *w, int n)
{
    double S[3][3] = {{0}}, total = 0.0;
    for (int i = 0; i < n; ++i) {
        const double av[3] = {a[i].x, a[i].y, a[i].z}, bv[3] = {b[i].x, b[i].y, b[i].z};
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) S[r][c] += w[i] * av[r] * bv[c];
        total += w[i];
    }
    for (int r = 0; r < 3; ++r) S[r][r] += 1e-6 * total;
    double K[4][4] = {
        {S[0][0] + S[1][1] + S[2][2], S[1][2] - S[2][1], S[2][0] - S[0][2], S[0][1] - S[1][0]},
        {S[1][2] - S[2][1], S[0][0] - S[1][1] - S[2][2], S[0][1] + S[1][0], S[2][0] + S[0][2]},
        {S[2][0] - S[0][2], S[0][1] + S[1][0], -S[0][0] + S[1][1] - S[2][2], S[1][2] + S[2][1]},
        {S[0][1] - S[1][0], S[2][0] + S[0][2], S[1][2] + S[2][1], -S[0][0] - S[1][1] + S[2][2]}};
    double q[4];
    top_eigenvector(K, 4, q);
    return mm_quat_normalize(mm_quat_make((float)q[1], (float)q[2], (float)q[3], (float)q[0]));
}

#define MAX_FIT 64
/* The correction C of joint j: prefer (its parent's, or the rest plane's) unless the rest offsets
 * of j's children (and End Site) point more than 30 degrees away from where C must take them (the
 * reflected offsets of their partners: C o_k = M o_k'); then the rotation closest to prefer that
 * takes them there. */
static mm_quat correction(const mm_skeleton *s, const int *partner, int j, mm_quat prefer, float tiny)
{
    int jp = partner[j];
    mm_vec3 from[MAX_FIT], to[MAX_FIT];
    float w[MAX_FIT];
    int n = 0, off = 0;
    const float cos_limit = (float)cos(30.0 * MM_DEG_TO_RAD);
    for (int k = 0; k <= s->joint_count && n < MAX_FIT; ++k) {
        mm_vec3 o, op;
        if (k == s->joint_count) { /* the End Site */
            if (!s->joints[j].has_end_site || !s->joints[jp].has_end_site) continue;
            o = s->joints[j].end_site;
            op = s->joints[jp].end_site;
        } else {
            if (s->joints[k].parent != j || (s->joints[k].flags & MM_JOINT_TRANSLATES)) continue;
            int kp = partner[k];
            if (s->joints[kp].parent != jp) continue;
            o = s->joints[k].offset;
            op = s->joints[kp].offset;
        }
        float l = unit(mm_quat_rotate(prefer, o), tiny, &from[n]), lp = unit(reflect(op), tiny, &to[n]);
        if (l == 0.0f || lp == 0.0f) continue;
        w[n] = l * lp;
        off |= mm_vec3_dot(from[n], to[n]) < cos_limit;
        ++n;
    }
    if (!off) return prefer;
    return mm_quat_normalize(mm_quat_mul(fit_rotation(from, to, w, n), prefer));
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
    double n[3];
    rest_plane(s, partner, n);
    mm_quat rest = plane_correction(n);
    float tiny = 1e-6f * fmaxf(longest_chain(s), 1e-6f);
    /* the simulation bone is the character's frame: x = 0 is its own plane */
    int simulation = strcmp(s->joints[0].name, MM__ROOT_NAME) == 0;
    for (int j = 0; j < jc; ++j) {
        int p = s->joints[j].parent;
        mm_quat prefer = p < 0 ? rest : (p == 0 && simulation ? rest : fix[p]);
        fix[j] = j == 0 && simulation ? mm_quat_identity() : correction(s, partner, j, prefer, tiny);
    }
    mm_xform *mg = g + jc;
    for (int f = 0; f < src->frame_count; ++f) {
        mm_clip_fk(src, f, g);
        for (int j = 0; j < jc; ++j) {
            const mm_xform *px = &g[partner[j]];
            mg[j] = mm_xform_make(mm_quat_normalize(mm_quat_mul(reflect_rotation(px->rotation), fix[j])),
                                  reflect(px->translation));
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
