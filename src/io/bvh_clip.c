/* From parsed BVH to positions and clips: double-precision forward kinematics straight from the
 * channel values (the reference the tools print and the tests compare against), conversion to
 * quaternion clips, and unit detection. */
#include <mm/bvh.h>

#include <math.h>
#include <string.h>

#include "io/file.h"

/* Local translation of joint j at frame f, in file units: position channels replace the OFFSET. */
static void local_translation(const mm_bvh *bvh, int j, const double *row, double t[3])
{
    memcpy(t, &bvh->offsets[3 * j], 3 * sizeof(double));
    const mm_bvh_joint_channels *ch = &bvh->channels[j];
    for (int c = 0; c < ch->count; ++c)
        if (ch->type[c] <= MM_BVH_ZPOSITION) t[ch->type[c]] = row[ch->first + c];
}

/* Local rotation matrix (row-major) of joint j: the product of its rotation channels in file
 * order, R = R_first * R_second * R_third. */
static void local_rotation_matrix(const mm_bvh *bvh, int j, const double *row, double m[9])
{
    static const double identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    memcpy(m, identity, sizeof identity);
    const mm_bvh_joint_channels *ch = &bvh->channels[j];
    for (int c = 0; c < ch->count; ++c) {
        int type = ch->type[c];
        if (type < MM_BVH_XROTATION) continue;
        double a = row[ch->first + c] * (MM_PI / 180.0), cs = cos(a), sn = sin(a);
        double r[9];
        switch (type) {
        case MM_BVH_XROTATION: {
            double x[9] = {1, 0, 0, 0, cs, -sn, 0, sn, cs};
            memcpy(r, x, sizeof r);
        } break;
        case MM_BVH_YROTATION: {
            double y[9] = {cs, 0, sn, 0, 1, 0, -sn, 0, cs};
            memcpy(r, y, sizeof r);
        } break;
        default: {
            double z[9] = {cs, -sn, 0, sn, cs, 0, 0, 0, 1};
            memcpy(r, z, sizeof r);
        } break;
        }
        double p[9];
        for (int i = 0; i < 3; ++i)
            for (int k = 0; k < 3; ++k)
                p[3 * i + k] = m[3 * i] * r[k] + m[3 * i + 1] * r[3 + k] + m[3 * i + 2] * r[6 + k];
        memcpy(m, p, sizeof p);
    }
}

mm_result mm_bvh_fk(const mm_bvh *bvh, int frame, double *out_xyz)
{
    if (!bvh || !out_xyz) return MM_ERR_INVALID_ARGUMENT;
    if (frame < 0 || frame >= bvh->frame_count) return MM_ERR_OUT_OF_RANGE;
    int n = bvh->skeleton.joint_count;
    double *rot = (double *)mm_alloc_array(&bvh->allocator, (size_t)n * 9, sizeof(double));
    if (!rot) return MM_ERR_OUT_OF_MEMORY;
    const double *row = bvh->values + (size_t)frame * bvh->channel_count;
    for (int j = 0; j < n; ++j) {
        double t[3], r[9];
        local_translation(bvh, j, row, t);
        local_rotation_matrix(bvh, j, row, r);
        int p = bvh->skeleton.joints[j].parent;
        if (p < 0) {
            memcpy(&rot[9 * j], r, sizeof r);
            memcpy(&out_xyz[3 * j], t, sizeof t);
            continue;
        }
        const double *pr = &rot[9 * p], *pt = &out_xyz[3 * p];
        for (int i = 0; i < 3; ++i) {
            out_xyz[3 * j + i] = pr[3 * i] * t[0] + pr[3 * i + 1] * t[1] + pr[3 * i + 2] * t[2] + pt[i];
            for (int k = 0; k < 3; ++k)
                rot[9 * j + 3 * i + k] =
                    pr[3 * i] * r[k] + pr[3 * i + 1] * r[3 + k] + pr[3 * i + 2] * r[6 + k];
        }
    }
    mm_free(&bvh->allocator, rot);
    return MM_OK;
}

/* Local rotation of joint j as a unit quaternion, composed in double precision. */
static mm_quat local_rotation_quat(const mm_bvh *bvh, int j, const double *row)
{
    double q[4] = {0, 0, 0, 1}; /* x y z w */
    const mm_bvh_joint_channels *ch = &bvh->channels[j];
    for (int c = 0; c < ch->count; ++c) {
        int type = ch->type[c];
        if (type < MM_BVH_XROTATION) continue;
        double h = 0.5 * row[ch->first + c] * (MM_PI / 180.0);
        double b[4] = {0, 0, 0, cos(h)};
        b[type - MM_BVH_XROTATION] = sin(h);
        double r[4] = {q[3] * b[0] + q[0] * b[3] + q[1] * b[2] - q[2] * b[1],
                       q[3] * b[1] - q[0] * b[2] + q[1] * b[3] + q[2] * b[0],
                       q[3] * b[2] + q[0] * b[1] - q[1] * b[0] + q[2] * b[3],
                       q[3] * b[3] - q[0] * b[0] - q[1] * b[1] - q[2] * b[2]};
        memcpy(q, r, sizeof r);
    }
    return mm_quat_normalize(mm_quat_make((float)q[0], (float)q[1], (float)q[2], (float)q[3]));
}

static void frame_to_local(const mm_bvh *bvh, int frame, double scale, mm_quat *rot, mm_vec3 *pos)
{
    const double *row = bvh->values + (size_t)frame * bvh->channel_count;
    for (int j = 0; j < bvh->skeleton.joint_count; ++j) {
        double t[3];
        local_translation(bvh, j, row, t);
        pos[j] = mm_vec3_make((float)(t[0] * scale), (float)(t[1] * scale), (float)(t[2] * scale));
        rot[j] = local_rotation_quat(bvh, j, row);
    }
}

double mm_bvh_detect_scale(const mm_bvh *bvh, double *out_height)
{
    if (out_height) *out_height = 0.0;
    if (!bvh || bvh->skeleton.joint_count < 1) return 0.0;
    float height;
    if (bvh->frame_count > 0) {
        mm_quat rot[MM_MAX_JOINTS];
        mm_vec3 pos[MM_MAX_JOINTS];
        frame_to_local(bvh, 0, 1.0, rot, pos);
        height = mm_skeleton_estimate_height(&bvh->skeleton, rot, pos);
    } else {
        height = mm_skeleton_estimate_height(&bvh->skeleton, NULL, NULL);
    }
    if (out_height) *out_height = height;
    return mm_unit_scale_for_height(height);
}

mm_result mm_bvh_to_clip(const mm_bvh *bvh, const mm_bvh_import_desc *desc, mm_clip *out, mm_error *err)
{
    if (!out) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no output clip given");
    memset(out, 0, sizeof *out);
    if (!bvh || bvh->skeleton.joint_count < 1)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no BVH given");
    double scale = 1.0;
    if (desc && desc->auto_scale) {
        double height = 0.0;
        scale = mm_bvh_detect_scale(bvh, &height);
        if (scale == 0.0)
            return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0,
                                "cannot detect the unit: the character is %g units tall, which is no human "
                                "height in metres, centimetres, millimetres, inches or feet; give a scale",
                                height);
    } else if (desc && desc->scale != 0.0f) {
        scale = desc->scale;
    }
    if (!isfinite(scale) || scale <= 0.0)
        return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "scale %g must be finite and positive", scale);
    mm_result r = mm_clip_init(out, &bvh->skeleton, bvh->frame_count, (float)(1.0 / bvh->frame_time),
                               desc ? desc->allocator : NULL);
    if (r != MM_OK) return mm_error_set(err, r, 0, 0, "cannot create the clip: %s", mm_result_str(r));
    mm_skeleton_scale(&out->skeleton, (float)scale);
    for (int j = 0; j < out->skeleton.joint_count; ++j) {
        const double *o = &bvh->offsets[3 * j];
        out->skeleton.joints[j].offset =
            mm_vec3_make((float)(o[0] * scale), (float)(o[1] * scale), (float)(o[2] * scale));
    }
    for (int f = 0; f < bvh->frame_count; ++f)
        frame_to_local(bvh, f, scale, mm_clip_rotations(out, f), mm_clip_positions(out, f));
    return MM_OK;
}
