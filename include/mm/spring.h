/* mm/spring.h - exact critically damped springs: the runtime's smoothing that does not depend on
 * the tick rate.
 *
 * Every update is the closed-form solution of the spring's differential equation over dt, so
 * ten steps of 0.01 s land where one step of 0.1 s does (to float rounding). A spring is set by
 * its half-life: starting at rest, after halflife seconds half of the distance to the target is
 * left (exactly: the damping y solves exp(-y h) (1 + y h) = 1/2, y h = 1.67834699...). Limits
 * belong on the target, never on the state, or the closed form no longer holds.
 *
 *   x'' = -y^2 (x - target) - 2 y x'            (critical damping)
 *   x(t) = target + (j0 + j1 t) e^(-y t),  j0 = x0 - target, j1 = v0 + j0 y
 *
 * Functions: mm_spring_damping mm_spring_update mm_spring_update_vec3 mm_spring_decay_vec3
 *            mm_spring_step_make mm_spring_update_step mm_spring_update_vec3_step mm_spring_decay_vec3_step
 *            mm_spring_decay_vec3_steps
 *            mm_spring_update_quat mm_spring_velocity_update
 */
#ifndef MM_SPRING_H
#define MM_SPRING_H

#include <stdbool.h>

#include "math.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Damping y (1/s) of a critically damped spring with this half-life (seconds, > 0). A half-life
 * of 0 or less means no spring: y is infinite and updates jump to the target. */
double mm_spring_damping(float halflife);

/* x and v (value and its rate) move toward a fixed target over dt seconds (dt >= 0). */
void mm_spring_update(float *x, float *v, float target, float halflife, float dt);
void mm_spring_update_vec3(mm_vec3 *x, mm_vec3 *v, mm_vec3 target, float halflife, float dt);
/* An offset decaying to zero (inertialization): the spring with target 0. */
void mm_spring_decay_vec3(mm_vec3 *x, mm_vec3 *v, float halflife, float dt);

/* One step of dt seconds at one half-life, for many springs that share both: the exponential
 * e^(-y dt), the costly part of an update, computed once. The _step updates give the same bits as
 * the updates above with the same half-life and dt. */
typedef struct mm_spring_step {
    double damping; /* y (mm_spring_damping) */
    double dt;      /* s */
    double decay;   /* e^(-y dt) */
    bool moves;     /* dt > 0 (no step otherwise) */
} mm_spring_step;
mm_spring_step mm_spring_step_make(float halflife, float dt);
void mm_spring_update_step(float *x, float *v, float target, const mm_spring_step *step);
void mm_spring_update_vec3_step(mm_vec3 *x, mm_vec3 *v, mm_vec3 target, const mm_spring_step *step);
void mm_spring_decay_vec3_step(mm_vec3 *x, mm_vec3 *v, const mm_spring_step *step);
/* mm_spring_decay_vec3_step on x[i], v[i] for every i in [0, count): the same bits, for less work
 * (the springs side by side). */
void mm_spring_decay_vec3_steps(mm_vec3 *x, mm_vec3 *v, int count, const mm_spring_step *step);

/* A rotation q with angular velocity w (rad/s, world axes) moves toward target, along the
 * shortest way: the spring acts on the rotation vector log(q target^-1). */
void mm_spring_update_quat(mm_quat *q, mm_vec3 *w, mm_quat target, float halflife, float dt);

/* A position whose velocity follows a spring toward a target velocity (the character's
 * trajectory): position, velocity and acceleration advance exactly over dt. */
void mm_spring_velocity_update(mm_vec3 *position, mm_vec3 *velocity, mm_vec3 *acceleration,
                               mm_vec3 target_velocity, float halflife, float dt);

#ifdef __cplusplus
}
#endif

#endif /* MM_SPRING_H */
