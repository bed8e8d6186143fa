/* mm/leg_ik.h - two-bone leg IK on joint positions: the foot moved to a target, the thigh and
 * shin lengths kept, the knee bent toward a pole.
 *
 * A leg is three world positions (hip, knee, ankle). mm_leg_ik_solve moves the foot to a target
 * and gives the new positions and the world-space rotation deltas that turn the old thigh and
 * shin onto the new ones (new world rotation = delta * old), ready to be written back into a pose.
 * Stride warping (mm/warp.h) solves each leg with it, and the character solves them with it again
 * from its eased pelvis height and for its foot locks (softened near full extension).
 *
 *   mm_leg_pose leg = {hip, knee, ankle};
 *   mm_leg_warp out;
 *   mm_leg_ik_solve(&leg, target, pelvis_forward, NULL, &out);   out.pose, out.thigh, out.shin
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

/* How far a leg may reach. Zero means default in each field. */
typedef struct mm_leg_ik_params {
    float max_extension; /* the solved leg stretches to at most this share of its length, but never
                            less than it is now; in [0.1, 1]; 0: MM_LEG_IK_MAX_EXTENSION_DEFAULT */
    float soft_reach;    /* share of the leg's length over which a far target's reach softens: from
                            (1 - soft_reach) of the length on, the distance asked for approaches the
                            full length exponentially (continuous in value and slope), so the knee
                            moves smoothly near full extension where a hard limit moves it as the
                            square root of what the leg lacks (a millimetre of target moves it
                            centimetres); in [0, 0.5]; 0: no softening */
} mm_leg_ik_params;

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

/* Two-bone IK on positions: the foot moves to target (its distance from the hip softened by
 * params->soft_reach and kept within params->max_extension of the full leg; params NULL: the
 * defaults). The leg is swung onto the new hip-target axis keeping the bend it has; more bend
 * than that goes toward the pole (where the knee points, for example the pelvis's facing; zero:
 * none), and a bend against the pole fades out as the leg straightens (docs/distance.md, "Stride
 * warping"). A target at the foot leaves a bent leg as it is. Lengths are kept exactly (to float
 * rounding). */
mm_result mm_leg_ik_solve(const mm_leg_pose *leg, mm_vec3 target, mm_vec3 pole,
                          const mm_leg_ik_params *params, mm_leg_warp *out);

#ifdef __cplusplus
}
#endif

#endif /* MM_LEG_IK_H */
