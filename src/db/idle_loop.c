/* Idle clips made to loop (db/idle_loop.h). */
#include "db/idle_loop.h"

#include "db/process.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Every frame's joints (1.. : the simulation bone aside) in the character frame: positions, their
 * velocities (backward differences; forward at frame 0), and whether the frame is still. */
typedef struct pose_track {
    int frames, joints; /* joints: the skeleton's less the simulation bone */
    mm_vec3 *position, *velocity;
    unsigned char *still;
} pose_track;

static void track_free(pose_track *t)
{
    free(t->position);
    free(t->velocity);
    free(t->still);
}

static mm_result track_of(const mm_clip *c, pose_track *t)
{
    int n = c->frame_count, jc = c->skeleton.joint_count, m = jc - 1;
    memset(t, 0, sizeof *t);
    t->frames = n;
    t->joints = m;
    size_t cells = (size_t)n * (size_t)(m > 0 ? m : 1);
    t->position = (mm_vec3 *)malloc(sizeof(mm_vec3) * cells);
    t->velocity = (mm_vec3 *)malloc(sizeof(mm_vec3) * cells);
    t->still = (unsigned char *)malloc((size_t)(n > 0 ? n : 1));
    mm_vec3 *root = (mm_vec3 *)malloc(sizeof(mm_vec3) * (size_t)(n > 0 ? n : 1));
    mm_xform *g = (mm_xform *)malloc(sizeof(mm_xform) * (size_t)jc);
    if (!t->position || !t->velocity || !t->still || !root || !g) {
        free(root);
        free(g);
        track_free(t);
        return MM_ERR_OUT_OF_MEMORY;
    }
    for (int f = 0; f < n; ++f) {
        mm_clip_fk(c, f, g);
        root[f] = g[0].translation;
        for (int j = 1; j < jc; ++j)
            t->position[(size_t)f * m + (j - 1)] =
                mm_quat_inv_rotate(g[0].rotation, mm_vec3_sub(g[j].translation, g[0].translation));
    }
    for (int f = 0; f < n; ++f) {
        int a = f > 0 ? f - 1 : 0, b = f > 0 ? f : (n > 1 ? 1 : 0);
        float joint_speed = 0.0f;
        for (int j = 0; j < m; ++j) {
            mm_vec3 v = mm_vec3_scale(
                mm_vec3_sub(t->position[(size_t)b * m + j], t->position[(size_t)a * m + j]), c->fps);
            t->velocity[(size_t)f * m + j] = v;
            joint_speed += mm_vec3_length(v);
        }
        joint_speed = m > 0 ? joint_speed / (float)m : 0.0f;
        float dx = root[b].x - root[a].x, dz = root[b].z - root[a].z;
        float root_speed = sqrtf(dx * dx + dz * dz) * c->fps;
        t->still[f] =
            root_speed < MM__IDLE_LOOP_STILL_ROOT_SPEED && joint_speed < MM__IDLE_LOOP_STILL_JOINT_SPEED;
    }
    free(root);
    free(g);
    return MM_OK;
}

/* m: the RMS over joints of the distance between frames a and b, positions and weighted velocities */
static float pose_distance(const pose_track *t, int a, int b)
{
    int m = t->joints;
    if (m < 1) return 0.0f;
    double sum = 0.0;
    for (int j = 0; j < m; ++j) {
        mm_vec3 dp = mm_vec3_sub(t->position[(size_t)b * m + j], t->position[(size_t)a * m + j]);
        mm_vec3 dv =
            mm_vec3_scale(mm_vec3_sub(t->velocity[(size_t)b * m + j], t->velocity[(size_t)a * m + j]),
                          MM__IDLE_LOOP_VELOCITY_WEIGHT);
        sum += (double)mm_vec3_dot(dp, dp) + (double)mm_vec3_dot(dv, dv);
    }
    return (float)sqrt(sum / m);
}

mm_result mm__idle_loop_find(const mm_clip *clip, mm__idle_loop *out)
{
    memset(out, 0, sizeof *out);
    int n = clip->frame_count;
    int min_frames = (int)lroundf(MM__IDLE_LOOP_MIN_SECONDS * clip->fps);
    int window = (int)lroundf(MM__IDLE_LOOP_END_WINDOW * clip->fps);
    if (min_frames < 2) min_frames = 2;
    if (n < min_frames + 1 || clip->skeleton.joint_count < 2) return MM_OK;
    pose_track t;
    if (track_of(clip, &t) != MM_OK) return MM_ERR_OUT_OF_MEMORY;
    /* the last still stretch that holds a loop and the frame after it: the one a character standing
     * still plays into the clip's end from */
    int s1 = n;
    while (s1 > 0) {
        while (s1 > 0 && !t.still[s1 - 1]) --s1;
        int s0 = s1;
        while (s0 > 0 && t.still[s0 - 1]) --s0;
        if (s1 - s0 >= min_frames + 1) {
            out->still_begin = s0;
            out->still_end = s1;
            break;
        }
        s1 = s0;
    }
    if (s1 == 0) {
        track_free(&t);
        return MM_OK;
    }
    float best = INFINITY;
    int last = out->still_end - 1; /* frame `end` must exist: its pose is the one matched */
    for (int end = last; end >= last - window && end - min_frames >= out->still_begin; --end)
        for (int begin = out->still_begin; begin <= end - min_frames; ++begin) {
            float d = pose_distance(&t, begin, end);
            if (d < best) { /* ties: the later end, the earlier begin (the longer loop) */
                best = d;
                out->begin = begin;
                out->end = end;
            }
        }
    out->error = best;
    out->found = best <= MM__IDLE_LOOP_MAX_ERROR;
    track_free(&t);
    return MM_OK;
}

/* The cubic from 0 (value and slope 0 at s = 0) to value d with slope v (per unit s) at s = 1. */
static float seam_ramp(float s, float d, float v)
{
    float s2 = s * s, s3 = s2 * s;
    return (3.0f * s2 - 2.0f * s3) * d + (s3 - s2) * v;
}

/* The shorter-arc rotation taking a to b, as a rotation vector (b = exp(r) a) */
static mm_vec3 turn_between(mm_quat a, mm_quat b)
{
    mm_quat d = mm_quat_mul(b, mm_quat_conj(a));
    return mm_quat_log(mm_quat_abs(d));
}

/* The loop's simulation bone held at its mean place and facing over the loop, the joints that hang
 * from it keeping their world transforms: the body sways as recorded, the character stands. */
static void hold_root(mm_clip *c)
{
    int n = c->frame_count, jc = c->skeleton.joint_count;
    double x = 0.0, z = 0.0, s = 0.0, k = 0.0;
    for (int f = 0; f < n; ++f) {
        mm_vec3 p = mm_clip_positions(c, f)[0];
        float yaw = mm__yaw_of(mm_clip_rotations(c, f)[0]);
        x += p.x;
        z += p.z;
        s += sin(yaw);
        k += cos(yaw);
    }
    mm_quat held_rotation = mm__quat_yaw((float)atan2(s, k));
    mm_vec3 held_position = mm_vec3_make((float)(x / n), 0.0f, (float)(z / n));
    for (int f = 0; f < n; ++f) {
        mm_quat *rot = mm_clip_rotations(c, f);
        mm_vec3 *pos = mm_clip_positions(c, f);
        for (int j = 1; j < jc; ++j) {
            if (c->skeleton.joints[j].parent != 0) continue;
            mm_quat world_rotation = mm_quat_mul(rot[0], rot[j]);
            mm_vec3 world_position = mm_vec3_add(pos[0], mm_quat_rotate(rot[0], pos[j]));
            rot[j] = mm_quat_normalize(mm_quat_mul(mm_quat_conj(held_rotation), world_rotation));
            pos[j] = mm_quat_inv_rotate(held_rotation, mm_vec3_sub(world_position, held_position));
        }
        rot[0] = held_rotation;
        pos[0] = mm_vec3_make(held_position.x, pos[0].y, held_position.z);
    }
}

mm_result mm__idle_loop_make(const mm_clip *src, const mm__idle_loop *loop, mm_clip *out,
                             const mm_allocator *a)
{
    int n = loop->end - loop->begin, jc = src->skeleton.joint_count;
    if (!loop->found || n < 2 || loop->begin < 0 || loop->end >= src->frame_count)
        return MM_ERR_INVALID_ARGUMENT;
    /* the loop's frames, the frame before (for the velocity at its start) and frame end, the root held */
    int lo = loop->begin > 0 ? loop->begin - 1 : loop->begin, held_count = loop->end + 1 - lo;
    mm_clip held;
    mm_result r = mm_clip_init(&held, &src->skeleton, held_count, src->fps, NULL);
    if (r != MM_OK) return r;
    size_t nj = (size_t)jc;
    for (int f = 0; f < held_count; ++f) {
        memcpy(mm_clip_rotations(&held, f), mm_clip_rotations(src, lo + f), nj * sizeof(mm_quat));
        memcpy(mm_clip_positions(&held, f), mm_clip_positions(src, lo + f), nj * sizeof(mm_vec3));
    }
    hold_root(&held);
    if ((r = mm_clip_init(out, &src->skeleton, n, src->fps, a)) != MM_OK) {
        mm_clip_free(&held);
        return r;
    }
    int b = loop->begin - lo, e = loop->end - lo; /* in held */
    for (int f = 0; f < n; ++f) {
        memcpy(mm_clip_rotations(out, f), mm_clip_rotations(&held, b + f), nj * sizeof(mm_quat));
        memcpy(mm_clip_positions(out, f), mm_clip_positions(&held, b + f), nj * sizeof(mm_vec3));
    }
    int k = (int)lroundf(MM__IDLE_LOOP_BLEND_SECONDS * src->fps);
    if (k > n / 2) k = n / 2;
    /* the frames whose step gives each end's velocity (backward differences, forward at frame 0) */
    int b0 = b > 0 ? b - 1 : b, b1 = b > 0 ? b : b + 1;
    float span = (float)k; /* frames: the ramp's slope is per frame, scaled to its length */
    for (int j = 1; j < jc && k >= 1; ++j) {
        const mm_quat *rb0 = &mm_clip_rotations(&held, b0)[j], *rb1 = &mm_clip_rotations(&held, b1)[j];
        mm_quat qb = mm_clip_rotations(&held, b)[j], qe = mm_clip_rotations(&held, e)[j];
        mm_vec3 turn = turn_between(qb, qe);
        mm_vec3 spin =
            mm_vec3_sub(turn_between(mm_clip_rotations(&held, e - 1)[j], qe), turn_between(*rb0, *rb1));
        mm_vec3 pb = mm_clip_positions(&held, b)[j], pe = mm_clip_positions(&held, e)[j];
        mm_vec3 shift = mm_vec3_sub(pe, pb);
        mm_vec3 drift =
            mm_vec3_sub(mm_vec3_sub(pe, mm_clip_positions(&held, e - 1)[j]),
                        mm_vec3_sub(mm_clip_positions(&held, b1)[j], mm_clip_positions(&held, b0)[j]));
        for (int i = n - k; i < n; ++i) {
            float s = (float)(i - (n - k)) / span;
            mm_vec3 c = mm_vec3_make(seam_ramp(s, turn.x, spin.x * span), seam_ramp(s, turn.y, spin.y * span),
                                     seam_ramp(s, turn.z, spin.z * span));
            mm_quat *q = &mm_clip_rotations(out, i)[j];
            *q = mm_quat_normalize(mm_quat_mul(mm_quat_exp(mm_vec3_scale(c, -1.0f)), *q));
            mm_vec3 cp =
                mm_vec3_make(seam_ramp(s, shift.x, drift.x * span), seam_ramp(s, shift.y, drift.y * span),
                             seam_ramp(s, shift.z, drift.z * span));
            mm_vec3 *p = &mm_clip_positions(out, i)[j];
            *p = mm_vec3_sub(*p, cp);
        }
    }
    mm_clip_free(&held);
    return MM_OK;
}
