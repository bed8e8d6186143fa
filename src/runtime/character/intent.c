/* Stage 1: the simulation and the intent. */
#include "intent.h"

#include <math.h>

#include "runtime/trajectory_private.h"

void mm_intent_update(mm_trajectory *t, const mm_input *in, float dt, mm_intent *out)
{
    mm_vec3 before = t->position;
    mm__trajectory_update_desired(t, in, dt, &out->desired_velocity, &out->desired_facing);
    float dx = t->position.x - before.x, dz = t->position.z - before.z;
    out->travelled = sqrtf(dx * dx + dz * dz);
    out->gait = mm_input_gait(in);
    out->strafe = in && in->strafe;
}

float mm_intent_ground_speed(const mm_trajectory *t)
{
    return sqrtf(t->velocity.x * t->velocity.x + t->velocity.z * t->velocity.z);
}
