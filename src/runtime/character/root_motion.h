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
    /* on a scene's terrain: whether the root's height follows the ground, and its spring's speed */
    bool on_ground;
    float ground_velocity;
    mm_vec3 ground_from; /* where the root was last tick (its speed along the slope) */
} mm_root_motion;

/* Moves r->root by `played` over dt, then (unless free_root: a move plays its clip's root motion
 * alone) pulls it toward the simulation t (sync_halflife), clamps it within sync_max_distance and
 * sync_max_angle of it, turns a small facing error away at full speed (angle_threshold,
 * angle_revise_speed) and, in a scene, pushes it out of the walls as the simulation's capsule
 * (mm_trajectory_collide). The height is kept. */
void mm_root_motion_update(mm_root_motion *r, const mm_character_desc *d, const mm_trajectory *t,
                           const mm_intent *intent, mm_root_played played, bool free_root, float dt);

/* The ground under the root for its height (mm/scene.h): the mean of the ground's height at
 * ROOT_GROUND_SAMPLES points along the root's facing, ROOT_GROUND_SPAN ahead to as far behind (a
 * flight of stairs reads as the slope of its nosings). */
float mm_root_motion_ground(const mm_scene *scene, mm_xform root);

/* On a scene's terrain (not during a move): the root's height follows mm_root_motion_ground
 * through a critically damped spring, aimed ahead by the spring's lag on the slope it climbs;
 * from where it is the first tick (after a move, or a scene set). Off the terrain (scene NULL)
 * it only forgets its spring. */
void mm_root_motion_follow_ground(mm_root_motion *r, const mm_scene *scene, float dt);

#endif
