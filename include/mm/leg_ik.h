/* mm/leg_ik.h - two-bone leg IK on joint positions: the foot moved to a target, the thigh and
 * shin lengths kept, the knee bent toward a pole.
 *
 * A leg is three world positions (hip, knee, ankle). mm_leg_ik_solve moves the foot to a target
 * and gives the new positions and the world-space rotation deltas that turn the old thigh and
 * shin onto the new ones (new world rotation = delta * old), ready to be written back into a pose.
 * Stride warping (mm/warp.h) solves each leg with it, and the character controller solves them
 * again from its eased pelvis height.
 *
 *   mm_leg_pose leg = {hip, knee, ankle};
 *   mm_leg_warp out;
 *   mm_leg_ik_solve(&leg, target, pelvis_forward, 0.0f, &out);   out.pose, out.thigh, out.shin
 *
 * Units: metres, radians; Y up, characters face +Z. Quaternions are {x, y, z, w} (mm/math.h). The
 * solve is free of allocation, computes in double, reports bad parameters with
 * MM_ERR_INVALID_ARGUMENT (MM_ERR_OUT_OF_RANGE when the numbers overflow floats) and then writes
 * the unchanged leg: NaN inputs never give NaN outputs.
 *
 * Functions: mm_leg_ik_solve
 */
#ifndef MM_LEG_IK_H
#define MM_LEG_IK_H

#include "math.h"
#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

#define MM_LEG_IK_MAX_EXTENSION_DEFAULT 0.999f /* a solved leg stretches to at most this of its length */

typedef struct mm_leg_pose {
    mm_vec3 hip, knee, foot; /* world positions (m) of the upper leg, lower leg and ankle joints */
} mm_leg_pose;

typedef struct mm_leg_warp {
    mm_leg_pose pose; /* the solved positions */
    mm_vec3 target;   /* the foot target asked for */
    /* world-space rotation deltas: new world rotation = delta * old (thigh at the hip joint, shin
     * at the knee joint) */
    mm_quat thigh, shin;
} mm_leg_warp;

/* Two-bone IK on positions: the foot moves to target (kept within max_extension of the full
 * leg, 0: MM_LEG_IK_MAX_EXTENSION_DEFAULT, else in [0.1, 1], but never less stretched than the
 * leg is now). The leg is swung onto the new hip-target axis keeping the bend it has; more bend
 * than that goes toward the pole (where the knee points, for example the pelvis's facing; zero:
 * none), and a bend against the pole fades out as the leg straightens (docs/distance.md, "Stride
 * warping"). A target at the foot leaves a bent leg as it is. Lengths are kept exactly (to float
 * rounding). */
mm_result mm_leg_ik_solve(const mm_leg_pose *leg, mm_vec3 target, mm_vec3 pole, float max_extension,
                          mm_leg_warp *out);

#ifdef __cplusplus
}
#endif

#endif /* MM_LEG_IK_H */
