#include <mm/clip.h>

#include <float.h>
#include <math.h>
#include <string.h>

mm_result mm_clip_init(mm_clip *clip, const mm_skeleton *skeleton, int frame_count, float fps,
                       const mm_allocator *allocator)
{
    if (!clip) return MM_ERR_INVALID_ARGUMENT;
    memset(clip, 0, sizeof *clip);
    if (!skeleton || skeleton->joint_count < 1 || frame_count < 0 || frame_count > MM_MAX_FRAMES ||
        !isfinite(fps) || fps <= 0.0f)
        return MM_ERR_INVALID_ARGUMENT;
    if (allocator) clip->allocator = *allocator;
    mm_result r = mm_skeleton_copy(&clip->skeleton, skeleton, allocator);
    if (r != MM_OK) return r;
    clip->fps = fps;
    clip->frame_count = frame_count;
    if (frame_count == 0) return MM_OK;
    size_t n = (size_t)frame_count * (size_t)skeleton->joint_count;
    clip->rotations = (mm_quat *)mm_alloc_array(allocator, n, sizeof(mm_quat));
    clip->positions = (mm_vec3 *)mm_alloc_array(allocator, n, sizeof(mm_vec3));
    if (!clip->rotations || !clip->positions) {
        mm_clip_free(clip);
        return MM_ERR_OUT_OF_MEMORY;
    }
    int jc = skeleton->joint_count;
    for (int f = 0; f < frame_count; ++f)
        for (int j = 0; j < jc; ++j) {
            clip->rotations[(size_t)f * jc + j] = mm_quat_identity();
            clip->positions[(size_t)f * jc + j] = skeleton->joints[j].offset;
        }
    return MM_OK;
}

void mm_clip_free(mm_clip *clip)
{
    if (!clip) return;
    mm_free(&clip->allocator, clip->rotations);
    mm_free(&clip->allocator, clip->positions);
    mm_skeleton_free(&clip->skeleton);
    memset(clip, 0, sizeof *clip);
}

mm_result mm_clip_copy(mm_clip *dst, const mm_clip *src, const mm_allocator *allocator)
{
    if (!dst || !src) return MM_ERR_INVALID_ARGUMENT;
    mm_result r = mm_clip_init(dst, &src->skeleton, src->frame_count, src->fps, allocator);
    if (r != MM_OK) return r;
    size_t n = (size_t)src->frame_count * (size_t)src->skeleton.joint_count;
    if (n) {
        memcpy(dst->rotations, src->rotations, n * sizeof(mm_quat));
        memcpy(dst->positions, src->positions, n * sizeof(mm_vec3));
    }
    return MM_OK;
}

float mm_clip_duration(const mm_clip *clip)
{
    return clip->frame_count < 2 ? 0.0f : (float)(clip->frame_count - 1) / clip->fps;
}

void mm_clip_scale(mm_clip *clip, float factor)
{
    mm_skeleton_scale(&clip->skeleton, factor);
    size_t n = (size_t)clip->frame_count * (size_t)clip->skeleton.joint_count;
    for (size_t i = 0; i < n; ++i) clip->positions[i] = mm_vec3_scale(clip->positions[i], factor);
}

void mm_clip_turn(mm_clip *clip, mm_quat turn)
{
    mm_skeleton *s = &clip->skeleton;
    for (int j = 0; j < s->joint_count; ++j) {
        if (s->joints[j].parent >= 0) continue;
        s->joints[j].offset = mm_quat_rotate(turn, s->joints[j].offset);
        for (int f = 0; f < clip->frame_count; ++f) {
            mm_quat *q = &mm_clip_rotations(clip, f)[j];
            mm_vec3 *p = &mm_clip_positions(clip, f)[j];
            *q = mm_quat_normalize(mm_quat_mul(turn, *q));
            *p = mm_quat_rotate(turn, *p);
        }
    }
}

/* The pose between frames f1 and f1 + 1 (a in (0, 1)) on the Catmull-Rom splines through the
 * frames; a missing neighbour (before the first frame, after the last) is the reflection of the
 * frame beyond, which makes that end's tangent the one-sided difference. */
static void sample_cubic(const mm_clip *clip, int f1, float a, mm_quat *out_rotations, mm_vec3 *out_positions)
{
    int n = clip->frame_count, jc = clip->skeleton.joint_count;
    int f0 = f1 - 1, f2 = f1 + 1, f3 = f1 + 2;
    const mm_quat *r1 = mm_clip_rotations(clip, f1), *r2 = mm_clip_rotations(clip, f2);
    const mm_vec3 *p1 = mm_clip_positions(clip, f1), *p2 = mm_clip_positions(clip, f2);
    const mm_quat *r0 = f0 >= 0 ? mm_clip_rotations(clip, f0) : NULL;
    const mm_quat *r3 = f3 < n ? mm_clip_rotations(clip, f3) : NULL;
    const mm_vec3 *p0 = f0 >= 0 ? mm_clip_positions(clip, f0) : NULL;
    const mm_vec3 *p3 = f3 < n ? mm_clip_positions(clip, f3) : NULL;
    for (int j = 0; j < jc; ++j) {
        mm_quat q0 = r0 ? r0[j] : mm_quat_mul(mm_quat_mul(r1[j], mm_quat_inverse(r2[j])), r1[j]);
        mm_quat q3 = r3 ? r3[j] : mm_quat_mul(mm_quat_mul(r2[j], mm_quat_inverse(r1[j])), r2[j]);
        mm_vec3 x0 = p0 ? p0[j] : mm_vec3_sub(mm_vec3_scale(p1[j], 2.0f), p2[j]);
        mm_vec3 x3 = p3 ? p3[j] : mm_vec3_sub(mm_vec3_scale(p2[j], 2.0f), p1[j]);
        out_rotations[j] = mm_quat_catmull_rom(q0, r1[j], r2[j], q3, a);
        out_positions[j] = mm_vec3_catmull_rom(x0, p1[j], p2[j], x3, a);
    }
}

void mm_clip_sample_frame(const mm_clip *clip, double x, mm_interp interp, mm_quat *out_rotations,
                          mm_vec3 *out_positions)
{
    int jc = clip->skeleton.joint_count;
    if (clip->frame_count < 1) {
        for (int j = 0; j < jc; ++j) {
            out_rotations[j] = mm_quat_identity();
            out_positions[j] = clip->skeleton.joints[j].offset;
        }
        return;
    }
    if (!(x > 0.0)) x = 0.0; /* and NaN */
    double last = clip->frame_count - 1;
    if (x > last) x = last;
    int f0 = (int)floor(x);
    if (interp == MM_INTERP_CUBIC) {
        if (f0 == x) { /* on a frame: that frame itself */
            memcpy(out_rotations, mm_clip_rotations(clip, f0), sizeof(mm_quat) * (size_t)jc);
            memcpy(out_positions, mm_clip_positions(clip, f0), sizeof(mm_vec3) * (size_t)jc);
            return;
        }
        sample_cubic(clip, f0, (float)(x - f0), out_rotations, out_positions);
        return;
    }
    int f1 = f0 + 1 < clip->frame_count ? f0 + 1 : f0;
    float a = (float)(x - f0);
    const mm_quat *r0 = mm_clip_rotations(clip, f0), *r1 = mm_clip_rotations(clip, f1);
    const mm_vec3 *p0 = mm_clip_positions(clip, f0), *p1 = mm_clip_positions(clip, f1);
    for (int j = 0; j < jc; ++j) {
        out_rotations[j] = mm_quat_slerp(r0[j], r1[j], a);
        out_positions[j] = mm_vec3_lerp(p0[j], p1[j], a);
    }
}

void mm_clip_sample(const mm_clip *clip, float t, mm_quat *out_rotations, mm_vec3 *out_positions)
{
    mm_clip_sample_frame(clip, isfinite(t) ? (double)t * clip->fps : 0.0, MM_INTERP_LINEAR, out_rotations,
                         out_positions);
}

mm_result mm_clip_resample_interp(mm_clip *dst, const mm_clip *src, float fps, mm_interp interp,
                                  const mm_allocator *allocator)
{
    if (!dst || !src || !isfinite(fps) || fps <= 0.0f ||
        (interp != MM_INTERP_LINEAR && interp != MM_INTERP_CUBIC))
        return MM_ERR_INVALID_ARGUMENT;
    double duration = src->frame_count < 2 ? 0.0 : (double)(src->frame_count - 1) / src->fps;
    double frames = src->frame_count == 0 ? 0.0 : floor(duration * fps + 1e-4) + 1.0;
    if (frames > MM_MAX_FRAMES) return MM_ERR_LIMIT;
    mm_result r = mm_clip_init(dst, &src->skeleton, (int)frames, fps, allocator);
    if (r != MM_OK) return r;
    for (int f = 0; f < dst->frame_count; ++f)
        mm_clip_sample_frame(src, (double)f * src->fps / fps, interp, mm_clip_rotations(dst, f),
                             mm_clip_positions(dst, f));
    return MM_OK;
}

mm_result mm_clip_resample(mm_clip *dst, const mm_clip *src, float fps, const mm_allocator *allocator)
{
    return mm_clip_resample_interp(dst, src, fps, MM_INTERP_LINEAR, allocator);
}

void mm_fk(const mm_skeleton *s, const mm_quat *local_rotations, const mm_vec3 *local_positions,
           mm_xform *out_global)
{
    for (int j = 0; j < s->joint_count; ++j) {
        mm_xform local = mm_xform_make(local_rotations[j], local_positions[j]);
        int p = s->joints[j].parent;
        out_global[j] = p < 0 ? local : mm_xform_mul(out_global[p], local);
    }
}

void mm_clip_fk(const mm_clip *clip, int frame, mm_xform *out_global)
{
    mm_fk(&clip->skeleton, mm_clip_rotations(clip, frame), mm_clip_positions(clip, frame), out_global);
}

void mm_global_to_local(const mm_skeleton *s, const mm_xform *global, mm_quat *out_rotations,
                        mm_vec3 *out_positions)
{
    for (int j = 0; j < s->joint_count; ++j) {
        int p = s->joints[j].parent;
        mm_xform local = p < 0 ? global[j] : mm_xform_mul(mm_xform_inverse(global[p]), global[j]);
        out_rotations[j] = mm_quat_normalize(local.rotation);
        out_positions[j] = local.translation;
    }
}

float mm_skeleton_estimate_height(const mm_skeleton *s, const mm_quat *local_rotations,
                                  const mm_vec3 *local_positions)
{
    /* Global transforms one joint at a time, kept in a fixed buffer: joints are at most
     * MM_MAX_JOINTS, so no allocation is needed. */
    mm_xform global[MM_MAX_JOINTS];
    if (!s || s->joint_count < 1 || s->joint_count > MM_MAX_JOINTS) return 0.0f;
    float lo = FLT_MAX, hi = -FLT_MAX;
    for (int j = 0; j < s->joint_count; ++j) {
        const mm_joint *jt = &s->joints[j];
        mm_xform local = mm_xform_make(local_rotations ? local_rotations[j] : mm_quat_identity(),
                                       local_positions ? local_positions[j] : jt->offset);
        global[j] = jt->parent < 0 ? local : mm_xform_mul(global[jt->parent], local);
        float y = global[j].translation.y;
        lo = fminf(lo, y);
        hi = fmaxf(hi, y);
        if (jt->has_end_site) {
            float ye = mm_xform_apply_point(global[j], jt->end_site).y;
            lo = fminf(lo, ye);
            hi = fmaxf(hi, ye);
        }
    }
    return hi - lo;
}

double mm_unit_scale_for_height(double height)
{
    static const double units[] = {1.0, 0.01, 0.001, 0.0254, 0.3048, 0.056444};
    if (!(height > 0.0) || !isfinite(height)) return 0.0;
    double best = 0.0, best_score = INFINITY;
    for (size_t i = 0; i < sizeof units / sizeof units[0]; ++i) {
        double h = height * units[i];
        if (h < 0.8 || h > 2.6) continue;
        double score = fabs(log(h / 1.75));
        if (score < best_score) {
            best_score = score;
            best = units[i];
        }
    }
    return best;
}
