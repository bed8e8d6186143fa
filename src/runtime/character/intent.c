/* Stage 1: the simulation and the intent. */
#include "intent.h"

#include <math.h>

void mm_intent_update(mm_trajectory *t, const mm_input *in, float dt, mm_intent *out)
{
    mm_vec3 before = t->position;
    mm_trajectory_update(t, in, dt);
    float dx = t->position.x - before.x, dz = t->position.z - before.z;
    out->travelled = sqrtf(dx * dx + dz * dz);
    mm_trajectory_desired(t, in, &out->desired_velocity, &out->desired_facing);
    out->gait = mm_input_gait(in);
    out->strafe = in && in->strafe;
}

float mm_intent_ground_speed(const mm_trajectory *t)
{
    return sqrtf(t->velocity.x * t->velocity.x + t->velocity.z * t->velocity.z);
}
