/* Blend clips: two clips played on a common, normalised time base and mixed with one weight.
 *
 * Both sources run from phase 0 to 1 over their own durations (periods, for loops); the blend
 * lasts the weighted mean duration. Joint rotations are mixed by slerp and translations linearly.
 * The simulation bone is not mixed in world space (the sources face anywhere): its velocity and
 * turning rate, in its own frame, are mixed and integrated from the origin. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "db/process.h"

typedef struct source {
    const mm_clip *clip;
    mm_vec3 *velocity;
    float *yaw_rate;
    double period; /* seconds spanned by phase 0..1 */
    int loop;
} source;

/* Frame position of phase u in [0, 1]: integer frame and blend fraction toward the next
 * (which wraps to frame 0 for loops). */
static void locate(const source *s, double u, int *f0, int *f1, float *alpha)
{
    int n = s->clip->frame_count;
    double x = u * s->period * s->clip->fps;
    if (s->loop) {
        x = fmod(x, (double)n);
        if (x < 0) x += n;
    } else if (x > n - 1) {
        x = n - 1;
    }
    *f0 = (int)floor(x);
    if (*f0 >= n) *f0 = n - 1;
    *f1 = *f0 + 1 < n ? *f0 + 1 : (s->loop ? 0 : *f0);
    *alpha = (float)(x - *f0);
}

static mm_result source_init(source *s, const mm_clip *clip, int loop)
{
    int n = clip->frame_count;
    s->clip = clip;
    s->loop = loop;
    s->period = loop ? (double)n / clip->fps : (double)(n - 1) / clip->fps;
    s->velocity = (mm_vec3 *)malloc(sizeof(mm_vec3) * (size_t)n);
    s->yaw_rate = (float *)malloc(sizeof(float) * (size_t)n);
    if (!s->velocity || !s->yaw_rate) return MM_ERR_OUT_OF_MEMORY;
    mm__root_motion(clip, s->velocity, s->yaw_rate);
    return MM_OK;
}

mm_result mm__clip_blend(const mm_clip *left, int left_loop, const mm_clip *right, int right_loop,
                         float weight, float interval, mm_clip *out, const mm_allocator *a)
{
    if (left->skeleton.joint_count != right->skeleton.joint_count || left->frame_count < 2 ||
        right->frame_count < 2)
        return MM_ERR_INVALID_ARGUMENT;
    source s[2];
    memset(s, 0, sizeof s);
    mm_result r = source_init(&s[0], left, left_loop);
    if (r == MM_OK) r = source_init(&s[1], right, right_loop);
    int loop = left_loop && right_loop;
    double period = weight * s[0].period + (1.0 - weight) * s[1].period;
    int frames = (int)lround(period / interval) + (loop ? 0 : 1);
    if (frames < 2) frames = 2;
    if (r == MM_OK) r = mm_clip_init(out, &left->skeleton, frames, 1.0f / interval, a);
    if (r != MM_OK) {
        for (int i = 0; i < 2; ++i) {
            free(s[i].velocity);
            free(s[i].yaw_rate);
        }
        return r;
    }
    int jc = left->skeleton.joint_count;
    double yaw = 0.0, x = 0.0, z = 0.0;
    for (int i = 0; i < frames; ++i) {
        double u = loop ? (double)i / frames : (double)i / (frames - 1);
        mm_quat *rot = mm_clip_rotations(out, i);
        mm_vec3 *pos = mm_clip_positions(out, i);
        mm_vec3 vel[2];
        float yaw_rate[2];
        int f0[2], f1[2];
        float al[2];
        for (int k = 0; k < 2; ++k) {
            locate(&s[k], u, &f0[k], &f1[k], &al[k]);
            /* Source speed scaled by how much faster or slower the source plays in the blend. */
            double stretch = s[k].period / period;
            vel[k] = mm_vec3_scale(mm_vec3_lerp(s[k].velocity[f0[k]], s[k].velocity[f1[k]], al[k]),
                                   (float)stretch);
            yaw_rate[k] = (float)(stretch * (s[k].yaw_rate[f0[k]] +
                                             (s[k].yaw_rate[f1[k]] - s[k].yaw_rate[f0[k]]) * al[k]));
        }
        for (int j = 1; j < jc; ++j) {
            mm_quat ql =
                mm_quat_slerp(mm_clip_rotations(left, f0[0])[j], mm_clip_rotations(left, f1[0])[j], al[0]);
            mm_quat qr =
                mm_quat_slerp(mm_clip_rotations(right, f0[1])[j], mm_clip_rotations(right, f1[1])[j], al[1]);
            mm_vec3 pl =
                mm_vec3_lerp(mm_clip_positions(left, f0[0])[j], mm_clip_positions(left, f1[0])[j], al[0]);
            mm_vec3 pr =
                mm_vec3_lerp(mm_clip_positions(right, f0[1])[j], mm_clip_positions(right, f1[1])[j], al[1]);
            rot[j] = mm_quat_slerp(qr, ql, weight);
            pos[j] = mm_vec3_lerp(pr, pl, weight);
        }
        /* Integrate the mixed root motion (backward differences: frame i's velocity carried it
         * from frame i-1 to i). */
        if (i > 0) {
            mm_vec3 v = mm_vec3_lerp(vel[1], vel[0], weight);
            double w = yaw_rate[1] + (yaw_rate[0] - yaw_rate[1]) * weight;
            double mid = yaw + 0.5 * w * interval;
            x += (cos(mid) * v.x + sin(mid) * v.z) * interval;
            z += (-sin(mid) * v.x + cos(mid) * v.z) * interval;
            yaw += w * interval;
        }
        rot[0] = mm__quat_yaw((float)yaw);
        pos[0] = mm_vec3_make((float)x, 0.0f, (float)z);
    }
    for (int k = 0; k < 2; ++k) {
        free(s[k].velocity);
        free(s[k].yaw_rate);
    }
    return MM_OK;
}
