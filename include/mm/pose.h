/* mm/pose.h - operations on whole poses: blending several poses, and turning local rotations into
 * model space and back.
 *
 * A pose is joint_count local rotations and positions of a skeleton (mm/skeleton.h: parents
 * before children, joint 0 the root). The crossfade mixer (mm/mixer.h) and the character
 * controller (mm/character.h) blend their sources with these.
 *
 * Units: metres; quaternions are {x, y, z, w} (mm/math.h). Nothing allocates.
 *
 * Functions: mm_pose_blend mm_pose_to_model mm_pose_to_local
 */
#ifndef MM_POSE_H
#define MM_POSE_H

#include "math.h"
#include "skeleton.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Blends pose_count poses of joint_count joints into out: rotations by the normalised weighted
 * sum of the quaternions, each first put in the hemisphere of a reference (q and -q are the same
 * rotation, and the sum must not cancel them); positions linearly. The reference is
 * reference[joint] when given, else the heaviest pose's (the first of equals). A caller blending
 * every tick passes the last tick's output: quaternions far apart (a half turn: dot near 0) then
 * keep their signs and the result moves continuously, where a fixed reference flips one of them
 * as it passes orthogonal to it (for two poses the heaviest gives the same result as either).
 * Weights are normalised by their sum; negative or non-finite weights count as 0; with no
 * positive weight (or pose_count < 2) out is pose 0. A joint whose weighted sum cancels takes the
 * heaviest pose's rotation. out may alias pose 0 (not the reference). */
void mm_pose_blend(const mm_quat *const *rotations, const mm_vec3 *const *positions, const float *weights,
                   int pose_count, int joint_count, const mm_quat *reference, mm_quat *out_rotations,
                   mm_vec3 *out_positions);

/* Local rotations to model space (each joint's rotation in the frame of joint 0: its parents' and
 * its own composed, joint 0 counted as the identity and left as it is) and back, in place; parents
 * from joints[j].parent (< j). The character blends in model space: two poses whose local
 * rotations differ by half a turn about a bone that the child undoes (LAFAN1's mirrored clips
 * have such flips; the joints land in the same places) blend in local space into a pose unlike
 * either, in model space into one between them. */
void mm_pose_to_model(const mm_joint *joints, int joint_count, mm_quat *rotations);
void mm_pose_to_local(const mm_joint *joints, int joint_count, mm_quat *rotations);

#ifdef __cplusplus
}
#endif

#endif /* MM_POSE_H */
