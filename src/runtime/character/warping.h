/* Stage 6, warping: the pose bent where playback alone cannot match the simulation: the legs turned
 * toward the movement while strafing on a forward clip (orientation warping) and stretched along it
 * by the speed the clamped play rate leaves over (stride warping). docs/distance.md. */
#ifndef MM_RUNTIME_WARPING_H
#define MM_RUNTIME_WARPING_H

#include <stdbool.h>

#include <mm/character.h>

#include "rig.h"

typedef struct mm_warping {
    float orientation_angle;    /* rad about +Y: the lower body's turn */
    float orientation_velocity; /* rad/s: its rate */
    float orientation_goal;     /* rad: the target the angle springs toward, eased toward the warp's */
    float stride_drop;          /* m: the pelvis lowered so that the stretched legs reach */
} mm_warping;

/* What the clip playing does: its root velocity in its own frame (m/s) and whether it is an idle. */
typedef struct mm_warping_clip {
    mm_vec3 root_velocity;
    bool idle;
} mm_warping_clip;

/* Orientation warping: while strafing (strafe) on a forward or backward locomotion clip, the pelvis
 * and legs turn about +Y toward the simulated movement (velocity), the spine turns back by equal
 * shares so the chest keeps its facing; otherwise the angle springs back to 0. Writes the pose
 * below the pelvis. off: a move plays (no warp). */
void mm_warping_orientation(mm_warping *w, const mm_character_desc *d, const mm_rig *rig, mm_xform root,
                            mm_vec3 velocity, mm_warping_clip clip, bool strafe, bool off, float dt,
                            mm_rig_pose *pose);

/* Stride warping: the legs stretched along the simulated movement (velocity) by stride_scale about
 * their hips, the pelvis eased toward the drop they need; the feet keep their world orientation. */
void mm_warping_stride(mm_warping *w, const mm_rig *rig, mm_xform root, mm_vec3 velocity, float stride_scale,
                       float dt, mm_rig_pose *pose);

#endif
