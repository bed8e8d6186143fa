/* Legs: foot rockers, the pelvis reach limit and analytic two-bone IK.
 *
 * Foot model: the Foot joint (ankle, "heel" contact) sits ankle_height above the ground when the
 * foot is flat; the Toe joint (ball of the foot, "toe" contact) is toe_offset from it. A planted
 * foot rolls about one of these two joints, never in between, so a contact flag always means that
 * joint does not move:
 *   pitch > 0 (toes up):  heel rocker, the Foot joint stays on its plant;
 *   pitch < 0 (heel up):  toe rocker, the Toe joint stays on its plant;
 *   pitch = 0:            flat, both stay.
 */
#include <math.h>

#include "synth_internal.h"

/* Soft zone below the reach: IK targets are pulled in smoothly from leg_reach - SOFT on, and the
 * pelvis is kept low enough that planted feet never enter it. */
#define SYNTH_IK_SOFT 0.003f

mm_vec3 synth_foot_pivot(const synth_body *b, mm_vec3 plant, float yaw, float pitch)
{
    if (pitch >= 0.0f) return plant;
    mm_vec3 toe = mm_vec3_add(plant, mm_quat_rotate(synth_rot_y(yaw), b->toe_offset));
    return mm_vec3_sub(toe, mm_quat_rotate(synth_foot_rotation(yaw, pitch), b->toe_offset));
}

mm_vec3 synth_foot_pivot_d(const synth_body *b, float yaw, float pitch)
{
    if (pitch >= 0.0f) return mm_vec3_make(0.0f, 0.0f, 0.0f);
    mm_vec3 axis = mm_vec3_make(cosf(yaw), 0.0f, -sinf(yaw)); /* R_y(yaw) * X */
    return mm_vec3_cross(axis, mm_quat_rotate(synth_foot_rotation(yaw, pitch), b->toe_offset));
}

mm_vec3 synth_hip_position(const synth_body *b, int side, mm_vec3 pelvis, mm_quat rot)
{
    int j = side == SYNTH_LEFT ? SJ_LUPLEG : SJ_RUPLEG;
    return mm_vec3_add(pelvis, mm_quat_rotate(rot, b->offset[j]));
}

float synth_pelvis_reach(const synth_body *b, int side, mm_vec3 pelvis, mm_quat rot, mm_vec3 ankle)
{
    int j = side == SYNTH_LEFT ? SJ_LUPLEG : SJ_RUPLEG;
    mm_vec3 off = mm_quat_rotate(rot, b->offset[j]);
    float dx = pelvis.x + off.x - ankle.x, dz = pelvis.z + off.z - ankle.z;
    float r = b->leg_reach - SYNTH_IK_SOFT;
    float v2 = r * r - (dx * dx + dz * dz);
    float v = v2 > 1e-4f ? sqrtf(v2) : 0.01f;
    return ankle.y + v - off.y;
}

mm_vec3 synth_leg_ik(const synth_body *b, mm_vec3 hip, mm_vec3 ankle, mm_vec3 pole, mm_quat *thigh,
                     mm_quat *shin)
{
    const float l1 = b->thigh, l2 = b->shin;
    mm_vec3 d = mm_vec3_sub(ankle, hip);
    float len = mm_vec3_length(d);
    mm_vec3 u = len > 1e-6f ? mm_vec3_scale(d, 1.0f / len) : mm_vec3_make(0.0f, -1.0f, 0.0f);
    /* Soft clamp: C1, approaches leg_reach without reaching it. */
    float r1 = b->leg_reach - SYNTH_IK_SOFT;
    if (len > r1) len = b->leg_reach - SYNTH_IK_SOFT * expf(-(len - r1) / SYNTH_IK_SOFT);
    float lmin = fabsf(l1 - l2) + 0.15f;
    if (len < lmin) len = lmin;
    mm_vec3 target = mm_vec3_add(hip, mm_vec3_scale(u, len));

    mm_vec3 n = mm_vec3_sub(pole, mm_vec3_scale(u, mm_vec3_dot(pole, u)));
    if (mm_vec3_length_sq(n) < 1e-8f) n = mm_vec3_make(0.0f, 0.0f, 1.0f);
    n = mm_vec3_normalize(n);
    float a = (l1 * l1 - l2 * l2 + len * len) / (2.0f * len);
    float h2 = l1 * l1 - a * a;
    float h = h2 > 0.0f ? sqrtf(h2) : 0.0f;
    mm_vec3 knee = mm_vec3_add(hip, mm_vec3_add(mm_vec3_scale(u, a), mm_vec3_scale(n, h)));
    mm_vec3 hinge = mm_vec3_normalize(mm_vec3_cross(n, u));

    const mm_vec3 down = mm_vec3_make(0.0f, -1.0f, 0.0f), x = mm_vec3_make(1.0f, 0.0f, 0.0f);
    *thigh = synth_quat_from_frame(mm_vec3_sub(knee, hip), hinge, down, x);
    *shin = synth_quat_from_frame(mm_vec3_sub(target, knee), hinge, down, x);
    return target;
}
