/* mm/trajectory.h - the desired motion: where the player's input would take the character (the
 * seed's virtual movement), its predicted future and its recorded past.
 *
 * The simulated character has a position on the ground, a velocity and an acceleration, a facing
 * and an angular velocity. Each update moves the velocity toward the velocity the input asks for
 * and the facing toward the direction it asks for, with exact critically damped springs
 * (mm/spring.h): the motion does not depend on the tick rate. Limits act on the targets: the
 * desired velocity is the stick times the gait's maximum speed forward, sideways or backward
 * (an ellipse in the character's frame). The future is predicted by running the same closed form
 * ahead with the input held; the past is read from a history recorded at a fixed rate, whatever
 * the tick rate. Gait style weights (walk, run, ...) move toward the input's gait with their own
 * spring (seed 004).
 *
 *   mm_trajectory t;
 *   mm_trajectory_init(&t, NULL, NULL);
 *   each tick: mm_trajectory_update(&t, &input, dt);
 *              mm_trajectory_sample(&t, &input, times, n, positions, facings);
 *   mm_trajectory_free(&t);
 *
 * Units: metres, seconds, radians; Y up; facing is a rotation about +Y (identity faces +Z).
 *
 * Functions: mm_trajectory_resolve_desc mm_trajectory_defaults mm_trajectory_init mm_trajectory_free
 * mm_trajectory_reset mm_trajectory_teleport mm_trajectory_update mm_trajectory_sample mm_trajectory_desired
 */
#ifndef MM_TRAJECTORY_H
#define MM_TRAJECTORY_H

#include "alloc.h"
#include "input.h"
#include "math.h"
#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct mm_gait_params {
    float forward_speed;     /* m/s at full stick, straight ahead */
    float side_speed;        /* m/s at full stick, sideways (strafing) */
    float backward_speed;    /* m/s at full stick, backwards (strafing) */
    float velocity_halflife; /* s: how quickly the velocity follows (the seed's acceleration and drag) */
    float rotation_halflife; /* s: how quickly the facing follows (the seed's angular speed) */
} mm_gait_params;

/* Zero means default in every field of mm_trajectory_desc (and of its gaits): a zero-initialized
 * desc with one field set is the defaults plus that field; MM_OFF (any negative value) makes a
 * field 0 (a speed of 0, a half-life of 0: at once, no recorded past). Defaults: walk 1.5 / 1.1 /
 * 1.0 m/s (forward / side / backward) with half-lives 0.25 s (velocity) and 0.2 s (facing); run
 * 4.0 / 2.6 / 2.2 m/s, 0.3 s and 0.25 s; crouch 0.9 / 0.7 / 0.6 m/s, 0.25 s and 0.2 s; jump as
 * run; gait_halflife 0.2 s, history_seconds 10 s, history_rate 60 per second. */
typedef struct mm_trajectory_desc {
    mm_gait_params gaits[MM_GAIT_COUNT]; /* per gait */
    float gait_halflife;                 /* s: gait style weights follow the input's gait */
    float history_seconds;               /* s: the recorded past */
    float history_rate;                  /* samples per second of the past */
    const mm_allocator *allocator;
} mm_trajectory_desc;

/* Every field of d at its default (written out). */
void mm_trajectory_defaults(mm_trajectory_desc *d);
/* in with its zero fields at their defaults and its negative ones at 0 (what mm_trajectory_init
 * runs with); out may be in. */
void mm_trajectory_resolve_desc(const mm_trajectory_desc *in, mm_trajectory_desc *out);

typedef struct mm_trajectory {
    mm_vec3 position, velocity, acceleration; /* on the ground (y = 0) */
    mm_quat facing;
    mm_quat target_facing;             /* the last facing asked for (the facing spring's target) */
    mm_vec3 angular_velocity;          /* rad/s about world axes */
    float gait_weights[MM_GAIT_COUNT]; /* style weights, summing to about 1 */
    float gait_rates[MM_GAIT_COUNT];
    double time; /* seconds simulated */
    /* history: positions and facings at times k / history_rate, a ring buffer */
    mm_vec3 *history_position;
    mm_quat *history_facing;
    int history_capacity, history_count, history_head; /* head: index of the newest */
    double history_time;                               /* time of the newest sample */
    mm_trajectory_desc desc;
    mm_allocator allocator;
} mm_trajectory;

/* desc may be NULL (defaults). The character starts at the origin facing +Z, standing, walking. */
mm_result mm_trajectory_init(mm_trajectory *t, const mm_trajectory_desc *desc, const mm_allocator *allocator);
void mm_trajectory_free(mm_trajectory *t);
/* Back to a standing state at position (y ignored) with facing; the history is cleared. */
void mm_trajectory_reset(mm_trajectory *t, mm_vec3 position, mm_quat facing);
/* Moves the simulation to position (y ignored) facing `facing` without stopping it: velocity,
 * acceleration and the facing spring's state carry on, the recorded past moves by the same
 * offset (its shape kept; facings unchanged). Used after a move (mm/moves.h) that carried the
 * character away from the simulation. Non-finite input does nothing. */
void mm_trajectory_teleport(mm_trajectory *t, mm_vec3 position, mm_quat facing);

/* The velocity and facing the input asks for, given the current facing (targets of the springs). */
void mm_trajectory_desired(const mm_trajectory *t, const mm_input *in, mm_vec3 *velocity, mm_quat *facing);

/* Advances by dt seconds (negative, NaN or infinite dt do nothing; a NaN or oversized stick
 * counts as zero or is clamped to the unit circle). Allocates nothing. */
void mm_trajectory_update(mm_trajectory *t, const mm_input *in, float dt);

/* Positions and facings at the given times relative to now (seconds; negative = past, from the
 * history, held at its oldest sample; positive = predicted with the input held). */
void mm_trajectory_sample(const mm_trajectory *t, const mm_input *in, const float *times, int count,
                          mm_vec3 *positions, mm_quat *facings);

#ifdef __cplusplus
}
#endif

#endif /* MM_TRAJECTORY_H */
