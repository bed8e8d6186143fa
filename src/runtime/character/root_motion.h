/* Stage 5, root motion: the character on the ground moves by the root motion played, pulled toward
 * the simulation and clamped to it, with the facing's angle correction. */
#ifndef MM_RUNTIME_ROOT_MOTION_H
#define MM_RUNTIME_ROOT_MOTION_H

#include <stdbool.h>

#include <mm/character.h>

#include "intent.h"
#include "transition.h"

typedef struct mm_root_motion {
    mm_xform root;         /* the character on the ground: position and facing (joint 0) */
    mm_root_played played; /* the root motion of the last tick, with its transition offsets */
} mm_root_motion;

/* Moves r->root by `played` over dt, then (unless free_root: a move plays its clip's root motion
 * alone) pulls it toward the simulation t (sync_halflife), clamps it within sync_max_distance and
 * sync_max_angle of it, turns a small facing error away at full speed (angle_threshold,
 * angle_revise_speed) and, in a scene, pushes it out of the walls as the simulation's capsule
 * (mm_trajectory_collide). The height is kept. */
void mm_root_motion_update(mm_root_motion *r, const mm_character_desc *d, const mm_trajectory *t,
                           const mm_intent *intent, mm_root_played played, bool free_root, float dt);

#endif
