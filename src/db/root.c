/* Resampling a source range and extracting the simulation bone. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "db/process.h"

float mm__wrap_angle(float a)
{
    double w = fmod((double)a + MM_PI, 2.0 * MM_PI);
    if (w <= 0.0) w += 2.0 * MM_PI;
    return (float)(w - MM_PI);
}

float mm__yaw_of(mm_quat q)
{
    mm_vec3 z = mm_quat_rotate(q, mm_vec3_make(0, 0, 1));
    return atan2f(z.x, z.z);
}

mm_quat mm__quat_yaw(float yaw) { return mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), yaw); }

mm_result mm__clip_extract(const mm_clip *src, int begin, int end, float interval, mm_clip *out,
                           const mm_allocator *a)
{
    if (begin < 0 || end > src->frame_count || end - begin < 2) return MM_ERR_OUT_OF_RANGE;
    /* Same rate (to 1e-4 relative): keep the frames as they are. */
    if (fabs((double)src->fps * interval - 1.0) < 1e-4) {
        mm_result r = mm_clip_init(out, &src->skeleton, end - begin, src->fps, a);
        if (r != MM_OK) return r;
        size_t n = (size_t)(end - begin) * (size_t)src->skeleton.joint_count;
        memcpy(out->rotations, mm_clip_rotations(src, begin), n * sizeof(mm_quat));
        memcpy(out->positions, mm_clip_positions(src, begin), n * sizeof(mm_vec3));
        return MM_OK;
    }
    /* The database rate, whole when the interval is 1/N to float precision (the config reads
     * 0.0166667 as 1/60), so that 30 fps frames land exactly on every other database frame. */
    double rate = 1.0 / interval;
    if (fabs(rate - floor(rate + 0.5)) < 1e-5 * rate) rate = floor(rate + 0.5);
    double duration = (double)(end - begin - 1) / src->fps;
    double frames = floor(duration * rate + 1e-4) + 1.0;
    if (frames > MM_MAX_FRAMES) return MM_ERR_LIMIT;
    mm_result r = mm_clip_init(out, &src->skeleton, (int)frames, 1.0f / interval, a);
    if (r != MM_OK) return r;
    /* Sampled on the whole source, so that the splines' tangents at the range's ends come from
     * the frames just outside it when there are some. */
    for (int f = 0; f < out->frame_count; ++f) {
        double x = begin + (double)f * src->fps / rate;
        if (x > end - 1) x = end - 1;
        mm_clip_sample_frame(src, x, MM_INTERP_CUBIC, mm_clip_rotations(out, f), mm_clip_positions(out, f));
    }
    return MM_OK;
}

/* Gaussian smoothing of n samples of dim floats (stride dim) with sigma in samples. Samples
 * beyond the ends are the odd reflection 2 x[0] - x[k], which keeps constant-velocity motion
 * exactly as it is. */
static void smooth(float *x, int n, int dim, float sigma, float *tmp)
{
    if (sigma <= 0.0f || n < 3) return;
    int radius = (int)ceilf(3.0f * sigma);
    memcpy(tmp, x, sizeof(float) * (size_t)n * dim);
    for (int i = 0; i < n; ++i)
        for (int d = 0; d < dim; ++d) {
            double sum = 0.0, wsum = 0.0;
            for (int k = -radius; k <= radius; ++k) {
                int j = i + k;
                double v;
                if (j < 0) {
                    int m = -j < n ? -j : n - 1;
                    v = 2.0 * tmp[d] - tmp[m * dim + d];
                } else if (j >= n) {
                    int m = 2 * (n - 1) - j;
                    if (m < 0) m = 0;
                    v = 2.0 * tmp[(n - 1) * dim + d] - tmp[m * dim + d];
                } else {
                    v = tmp[j * dim + d];
                }
                double w = exp(-0.5 * (double)k * k / ((double)sigma * sigma));
                sum += w * v;
                wsum += w;
            }
            x[i * dim + d] = (float)(sum / wsum);
        }
}

int mm__body_root(const mm_skeleton *s, const mm_config *cfg)
{
    int hips = cfg->hips[0] ? mm_skeleton_find(s, cfg->hips) : -1;
    return hips >= 0 ? hips : 0;
}

/* The joints above the body root (its proper ancestors): folded[j] = 1. */
static void mark_folded(const mm_skeleton *s, int body, unsigned char *folded)
{
    memset(folded, 0, (size_t)s->joint_count);
    for (int j = s->joints[body].parent; j >= 0; j = s->joints[j].parent) folded[j] = 1;
}

/* The rest pose's world positions (identity rotations, rest offsets). */
static void rest_positions(const mm_skeleton *s, mm_vec3 *out)
{
    for (int j = 0; j < s->joint_count; ++j) {
        int p = s->joints[j].parent;
        out[j] = p < 0 ? s->joints[j].offset : mm_vec3_add(out[p], s->joints[j].offset);
    }
}

/* The skeleton that replaces the folded joints by one new joint 0 (name, flags): the kept joints
 * follow in their order; those whose parent was folded (or that were the root) hang from joint 0,
 * translate, and have their rest position as their offset. map[j]: j's new index (-1: folded). */
static mm_result fold_skeleton(const mm_skeleton *s, const unsigned char *folded, const char *name,
                               unsigned flags, mm_skeleton *out, int *map, const mm_allocator *a)
{
    int jc = s->joint_count, kept = 0;
    for (int j = 0; j < jc; ++j) map[j] = folded[j] ? -1 : 1 + kept++;
    mm_vec3 *rest = (mm_vec3 *)malloc(sizeof(mm_vec3) * (size_t)jc);
    if (!rest) return MM_ERR_OUT_OF_MEMORY;
    rest_positions(s, rest);
    mm_result r = mm_skeleton_init(out, kept + 1, a);
    if (r != MM_OK) {
        free(rest);
        return r;
    }
    snprintf(out->joints[0].name, MM_NAME_MAX, "%s", name);
    out->joints[0].parent = -1;
    out->joints[0].flags = flags;
    out->joints[0].order = MM_EULER_NONE;
    for (int j = 0; j < jc; ++j) {
        if (map[j] < 0) continue;
        mm_joint *nj = &out->joints[map[j]];
        *nj = s->joints[j];
        int p = s->joints[j].parent;
        if (p < 0 || folded[p]) { /* hangs from joint 0 at its world place */
            nj->parent = 0;
            nj->flags |= MM_JOINT_TRANSLATES;
            nj->offset = rest[j];
        } else {
            nj->parent = map[p];
        }
    }
    free(rest);
    return MM_OK;
}

mm_result mm__clip_fold_root(const mm_clip *src, int body, mm_clip *out, const mm_allocator *a)
{
    const mm_skeleton *s = &src->skeleton;
    int jc = s->joint_count;
    unsigned char *folded = (unsigned char *)malloc((size_t)jc);
    int *map = (int *)malloc(sizeof(int) * (size_t)jc);
    mm_xform *g = (mm_xform *)malloc(sizeof(mm_xform) * (size_t)jc);
    mm_skeleton ns;
    mm_result r = folded && map && g ? MM_OK : MM_ERR_OUT_OF_MEMORY;
    if (r == MM_OK && (body <= 0 || body >= jc)) r = MM_ERR_INVALID_ARGUMENT;
    if (r == MM_OK) {
        mark_folded(s, body, folded);
        r = fold_skeleton(s, folded, s->joints[0].name, 0, &ns, map, a);
    }
    if (r == MM_OK) {
        r = mm_clip_init(out, &ns, src->frame_count, src->fps, a);
        mm_skeleton_free(&ns);
    }
    if (r == MM_OK)
        for (int f = 0; f < src->frame_count; ++f) {
            mm_clip_fk(src, f, g);
            const mm_quat *sr = mm_clip_rotations(src, f);
            const mm_vec3 *sp = mm_clip_positions(src, f);
            mm_quat *rot = mm_clip_rotations(out, f);
            mm_vec3 *pos = mm_clip_positions(out, f);
            rot[0] = mm_quat_identity();
            pos[0] = mm_vec3_make(0.0f, 0.0f, 0.0f);
            for (int j = 0; j < jc; ++j) {
                if (map[j] < 0) continue;
                int hangs = out->skeleton.joints[map[j]].parent == 0;
                rot[map[j]] = hangs ? g[j].rotation : sr[j];
                pos[map[j]] = hangs ? g[j].translation : sp[j];
            }
        }
    free(folded);
    free(map);
    free(g);
    return r;
}

mm_result mm__clip_add_root(const mm_clip *src, const mm_clip *body, const mm_config *cfg, mm_clip *out,
                            const mm_allocator *a, mm_error *err)
{
    const mm_skeleton *s = &src->skeleton;
    if (!body) body = src;
    if (body->frame_count != src->frame_count)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "the body has %d frames, the source %d",
                            body->frame_count, src->frame_count);
    const mm_skeleton *bs = &body->skeleton;
    int root_bone = mm_skeleton_find(s, cfg->root_bone);
    int facing = mm_skeleton_find(s, cfg->facing_bone);
    if (root_bone < 0)
        return mm_error_set(err, MM_ERR_NOT_FOUND, 0, 0, "roles.root_bone: no joint named '%s'",
                            cfg->root_bone);
    if (facing < 0)
        return mm_error_set(err, MM_ERR_NOT_FOUND, 0, 0, "roles.facing_bone: no joint named '%s'",
                            cfg->facing_bone);
    if (bs->joint_count + 1 > MM_MAX_JOINTS) return mm_error_set(err, MM_ERR_LIMIT, 0, 0, "too many joints");

    int n = src->frame_count, jc = bs->joint_count;
    /* g: the source's globals (the roles), then the body's */
    mm_xform *g = (mm_xform *)malloc(sizeof(mm_xform) * (size_t)(s->joint_count + jc));
    float *track = (float *)malloc(sizeof(float) * 5 * (size_t)n); /* x z | dx dz */
    float *tmp = (float *)malloc(sizeof(float) * 3 * (size_t)n);
    unsigned char *folded = (unsigned char *)malloc((size_t)jc);
    int *map = (int *)malloc(sizeof(int) * (size_t)jc);
    mm_skeleton ns;
    mm_result r = g && track && tmp && folded && map ? MM_OK : MM_ERR_OUT_OF_MEMORY;
    int taken = -1; /* a kept joint named like the simulation bone (one above the hips is left out) */
    if (r == MM_OK) {
        mark_folded(bs, mm__body_root(bs, cfg), folded);
        taken = mm_skeleton_find(bs, MM__ROOT_NAME);
        if (taken >= 0 && folded[taken]) taken = -1;
        if (taken >= 0) r = MM_ERR_DUPLICATE_NAME;
    }
    if (r == MM_OK) r = fold_skeleton(bs, folded, MM__ROOT_NAME, MM_JOINT_TRANSLATES, &ns, map, a);
    if (r == MM_OK) {
        r = mm_clip_init(out, &ns, src->frame_count, src->fps, a);
        mm_skeleton_free(&ns);
    }
    if (r != MM_OK) {
        free(g);
        free(track);
        free(tmp);
        free(folded);
        free(map);
        if (r == MM_ERR_DUPLICATE_NAME)
            return mm_error_set(err, r, 0, 0, "the source already has a joint named '%s'", MM__ROOT_NAME);
        return mm_error_set(err, r, 0, 0, "out of memory");
    }
    /* The roles are read from the body where it has them: its hips were folded before they were
     * resampled, so that their world motion is the splines' whichever joints carried it in the
     * file; the source's local splines under a turning root read other poses between its frames.
     * A role above the hips (folded) is read from the source. */
    int body_root_bone = body != src ? mm_skeleton_find(bs, cfg->root_bone) : -1;
    int body_facing = body != src ? mm_skeleton_find(bs, cfg->facing_bone) : -1;
    if (body_root_bone >= 0 && folded[body_root_bone]) body_root_bone = -1;
    if (body_facing >= 0 && folded[body_facing]) body_facing = -1;
    float *pos = track, *dir = track + 2 * n;
    mm_vec3 axis = mm_vec3_normalize(cfg->forward_axis);
    float last_dx = 0.0f, last_dz = 1.0f;
    for (int f = 0; f < n; ++f) {
        mm_xform *gb = g + s->joint_count;
        mm_clip_fk(src, f, g);
        if (body_root_bone >= 0 || body_facing >= 0) mm_clip_fk(body, f, gb);
        mm_xform rb = body_root_bone >= 0 ? gb[body_root_bone] : g[root_bone];
        mm_xform fb = body_facing >= 0 ? gb[body_facing] : g[facing];
        pos[2 * f] = rb.translation.x;
        pos[2 * f + 1] = rb.translation.z;
        mm_vec3 d = mm_quat_rotate(fb.rotation, axis);
        float len = sqrtf(d.x * d.x + d.z * d.z);
        if (len > 1e-4f) { /* a forward axis pointing straight up keeps the last facing */
            last_dx = d.x / len;
            last_dz = d.z / len;
        }
        dir[2 * f] = last_dx;
        dir[2 * f + 1] = last_dz;
    }
    float sigma = cfg->root_smoothing * src->fps;
    smooth(pos, n, 2, sigma, tmp);
    smooth(dir, n, 2, sigma, tmp);
    for (int f = 0; f < n; ++f) {
        float yaw = atan2f(dir[2 * f], dir[2 * f + 1]);
        mm_xform root = mm_xform_make(mm__quat_yaw(yaw), mm_vec3_make(pos[2 * f], 0.0f, pos[2 * f + 1]));
        mm_xform to_root = mm_xform_inverse(root), *gb = g + s->joint_count;
        mm_clip_fk(body, f, gb);
        const mm_quat *sr = mm_clip_rotations(body, f);
        const mm_vec3 *sp = mm_clip_positions(body, f);
        mm_quat *rot = mm_clip_rotations(out, f);
        mm_vec3 *p = mm_clip_positions(out, f);
        rot[0] = root.rotation;
        p[0] = root.translation;
        for (int j = 0; j < jc; ++j) {
            if (map[j] < 0) continue;
            if (out->skeleton.joints[map[j]].parent == 0) { /* the body (and what else hung above it) */
                mm_xform local = mm_xform_mul(to_root, gb[j]);
                rot[map[j]] = mm_quat_normalize(local.rotation);
                p[map[j]] = local.translation;
            } else {
                rot[map[j]] = sr[j];
                p[map[j]] = sp[j];
            }
        }
    }
    free(g);
    free(track);
    free(tmp);
    free(folded);
    free(map);
    return MM_OK;
}

void mm__root_motion(const mm_clip *clip, mm_vec3 *velocity, float *yaw_rate)
{
    int n = clip->frame_count;
    for (int f = 0; f < n; ++f) {
        int a = f > 0 ? f - 1 : 0, b = f > 0 ? f : (n > 1 ? 1 : 0);
        mm_quat qa = mm_clip_rotations(clip, a)[0], qb = mm_clip_rotations(clip, b)[0];
        mm_vec3 pa = mm_clip_positions(clip, a)[0], pb = mm_clip_positions(clip, b)[0];
        mm_quat here = mm_clip_rotations(clip, f)[0];
        mm_vec3 v = mm_vec3_scale(mm_vec3_sub(pb, pa), clip->fps);
        velocity[f] = a == b ? mm_vec3_make(0, 0, 0) : mm_quat_inv_rotate(here, v);
        yaw_rate[f] = a == b ? 0.0f : mm__wrap_angle(mm__yaw_of(qb) - mm__yaw_of(qa)) * clip->fps;
    }
}
