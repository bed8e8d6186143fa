/* mm/warp.h - stride warping and orientation warping: the pose bent where changing the clip's time
 * cannot make it agree with the character's motion (seed 003).
 *
 *   - Stride warping: feet scaled along the movement direction about their hips (the stride the
 *     play rate could not make up, mm_distance_stride_scale in mm/distance_matching.h), the pelvis
 *     lowered when a leg could no longer reach, each leg solved by two-bone IK (mm/leg_ik.h).
 *   - Orientation warping: the lower body turned toward the movement direction, the spine
 *     counter-rotated by weights so the upper body keeps facing where it faced.
 *
 *   each tick (no allocation):
 *     mm_warp_stride(legs, 2, velocity, stride_scale, 0.0f, out, &drop);     out[k].pose, .thigh
 *     mm_warp_orientation(facing, velocity, angle, dt, &params, &w);        angle = w.angle
 *     mm_warp_orientation_pose(&w, parent_world, pelvis_world, spine_world, n, &pelvis, spine);
 *
 * Units: metres, seconds, radians; Y up, characters face +Z; directions are taken on the ground
 * plane (x, z). Quaternions are {x, y, z, w} (mm/math.h). Every function is free of allocation,
 * reports bad parameters with MM_ERR_INVALID_ARGUMENT (or MM_ERR_OUT_OF_RANGE when the numbers
 * overflow floats) and still writes finite outputs (the unchanged legs, identity rotations): NaN
 * inputs never give NaN outputs.
 *
 * Functions: mm_warp_stride mm_warp_orientation mm_warp_orientation_pose mm_warp_orientation_point
 */
#ifndef MM_WARP_H
#define MM_WARP_H

#include "leg_ik.h"
#include "math.h"
#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

#define MM_WARP_ORIENTATION_MAX_DEFAULT 1.5708f /* rad: largest orientation correction (90 deg) */
#define MM_WARP_ORIENTATION_MAX_SPINE   8       /* spine joints sharing the counter-rotation */
#define MM_WARP_MAX_LEGS                8

/* ---- stride warping --------------------------------------------------------------------- */

/* Stride warping: each foot's target is the foot moved along the movement direction (y ignored)
 * so that its distance from the hip's projection on the ground, along that direction, is scaled
 * by scale (> 0); the pelvis (all hips together) is lowered only as far as needed for every leg
 * to reach within max_extension (0: MM_LEG_IK_MAX_EXTENSION_DEFAULT); then two-bone IK
 * (mm_leg_ik_solve) with the direction as pole. Scale 1 and a zero direction are the identity.
 * leg_count 1 .. MM_WARP_MAX_LEGS. *pelvis_drop (may be NULL): m lowered (>= 0). */
mm_result mm_warp_stride(const mm_leg_pose *legs, int leg_count, mm_vec3 direction, float scale,
                         float max_extension, mm_leg_warp *out, float *pelvis_drop);

/* ---- orientation warping ---------------------------------------------------------------- */

/* Defaults: max_angle 90 deg, speed 0 (no smoothing), equal spine weights. */
typedef struct mm_warp_orientation_params {
    float max_angle;            /* rad, largest correction; 0: MM_WARP_ORIENTATION_MAX_DEFAULT */
    float speed;                /* 1/s: the angle follows its target as 1 - e^(-speed dt); 0: at once */
    float halflife;             /* s: > 0 follows it through a critically damped spring instead (the
                                 * angle's rate stays continuous when the target jumps); speed unused */
    float velocity;             /* rad/s: the angle's rate after the last call (halflife mode) */
    float hysteresis;           /* rad: near 90 deg keep the side (forward/backward) chosen before; 0: 0.17 */
    int spine_count;            /* 0 .. MM_WARP_ORIENTATION_MAX_SPINE */
    const float *spine_weights; /* [spine_count] >= 0 (normalised to sum 1); NULL: equal */
} mm_warp_orientation_params;

typedef struct mm_warp_orientation_result {
    float target_angle; /* rad about +Y from the facing to the movement (flipped when backward) */
    float angle;        /* rad, the correction applied (smoothed, clamped) */
    float velocity;     /* rad/s: the angle's rate (halflife mode; 0 otherwise or when clamped) */
    int backward;       /* 1: the movement is more than 90 deg from the facing and the legs take
                         * the backward direction */
    mm_quat lower_body; /* world rotation about +Y by angle: the pelvis and legs */
    /* per spine joint, from the pelvis up: its world-space delta about +Y, lower_body rotated
     * back by the weights so far; after the last one the upper body is as it was */
    mm_quat spine[MM_WARP_ORIENTATION_MAX_SPINE];
} mm_warp_orientation_result;

/* Orientation warping. facing and movement are directions on the ground (y ignored; a movement
 * shorter than 1e-4 asks for no correction); previous_angle is the last call's angle (0 at the
 * start); dt >= 0 seconds. Angle 0 gives identities. params may be NULL. */
mm_result mm_warp_orientation(mm_vec3 facing, mm_vec3 movement, float previous_angle, float dt,
                              const mm_warp_orientation_params *params, mm_warp_orientation_result *out);
/* Applies an orientation warp to a pose's rotations. The pelvis's world rotation becomes
 * w->lower_body * pelvis_world (so the legs below it turn with it), and spine joint i's world
 * rotation becomes w->spine[i] * spine_world[i]; spine[0] hangs from the pelvis and spine[i] from
 * spine[i - 1]. Writes the new local rotations: *pelvis_local (the pelvis's parent has world
 * rotation parent_world) and spine_local[spine_count] (0 .. MM_WARP_ORIENTATION_MAX_SPINE). The
 * joints above the last spine joint keep their world rotation. When w->angle is 0 nothing is
 * written (the pose stays bit for bit). MM_ERR_INVALID_ARGUMENT for NULL or a bad count. */
mm_result mm_warp_orientation_pose(const mm_warp_orientation_result *w, mm_quat parent_world,
                                   mm_quat pelvis_world, const mm_quat *spine_world, int spine_count,
                                   mm_quat *pelvis_local, mm_quat *spine_local);
/* A point (for example a planted foot) turned with the lower body about pivot (the root). */
mm_vec3 mm_warp_orientation_point(const mm_warp_orientation_result *w, mm_vec3 pivot, mm_vec3 point);

#ifdef __cplusplus
}
#endif

#endif /* MM_WARP_H */
