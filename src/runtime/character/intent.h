/* Stage 1, input -> trajectory: the simulation advanced by the player's input, and what the input
 * asks for, derived once per tick and read by every later stage. */
#ifndef MM_RUNTIME_INTENT_H
#define MM_RUNTIME_INTENT_H

#include <stdbool.h>

#include <mm/input.h>
#include <mm/trajectory.h>

typedef struct mm_intent {
    mm_vec3 desired_velocity; /* m/s, world: the stick on the gait's speeds (mm_trajectory_desired) */
    mm_quat desired_facing;   /* the facing asked for */
    mm_gait gait;             /* the input's gait, MM_GAIT_WALK when out of range */
    bool strafe;              /* the input strafes */
    float travelled;          /* m: the simulated root's ground displacement this tick */
} mm_intent;

/* Advances the simulation t by dt under in (may be NULL: no input) and derives out from it. */
void mm_intent_update(mm_trajectory *t, const mm_input *in, float dt, mm_intent *out);

/* m/s: the simulation's speed on the ground. */
float mm_intent_ground_speed(const mm_trajectory *t);

#endif
