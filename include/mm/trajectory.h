/* mm/trajectory.h - the desired motion: where the player's input would take the character (the
 * seed's virtual movement), its predicted future and its recorded past.
 *
 * The simulated character has a position on the ground, a velocity and an acceleration, a facing
 * and an angular velocity. Each update moves the velocity toward the velocity the input asks for
 * and the facing toward the direction it asks for, with exact critically damped springs
 * (mm/spring.h): the motion does not depend on the tick rate. Limits act on the targets: the
 * desired velocity is the stick times the gait's maximum speed forward, sideways or backward
 * (an ellipse in the character's frame), and, where the desc carries a speed envelope (what the
 * database's own locomotion covers in each direction of travel, mm/speed_envelope.h), at most the
 * envelope's speed in the direction asked for: the direction is kept, the speed cut to what the
 * data can do (docs/runtime.md, "The speed envelope"). The future is predicted by running the same closed
 * form ahead with the input held; the past is read from a history recorded at a fixed rate, whatever the tick
 * rate. Gait style weights (walk, run, ...) move toward the input's gait with their own spring (seed 004).
 *
 * In a scene (mm_trajectory_set_scene) the simulated character is a vertical capsule that collides
 * with the scene's walls and slides along them: the motion is then stepped (at most
 * MM_TRAJECTORY_COLLISION_STEP per step), each step the closed form and then the capsule pushed out
 * of the boxes (mm_scene_collide_capsule) with the velocity and acceleration into them removed.
 * The predicted future runs the same steps, so it stops at a wall or bends along it, and the
 * recorded past is what the collided simulation did. Without a scene, or in one without boxes,
 * nothing changes: the closed form as above, to the bit.
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
 * mm_trajectory_set_scene mm_trajectory_collide mm_trajectory_predict mm_trajectory_envelope_speed
 */
#ifndef MM_TRAJECTORY_H
#define MM_TRAJECTORY_H

#include "alloc.h"
#include "input.h"
#include "math.h"
#include "result.h"
#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Directions of a speed envelope: bin k is the direction 2 pi k / MM_SPEED_ENVELOPE_BINS from
 * straight ahead toward the character's left (+X), so bin 0 is forward, bin BINS/4 left, bin
 * BINS/2 backward, bin 3 BINS/4 right. */
#define MM_SPEED_ENVELOPE_BINS 16
/* m/s: the fastest an envelope's speed may be (as the gait speeds) */
#define MM_SPEED_ENVELOPE_MAX 50.0f

/* The most a gait moves in each direction relative to its facing (m/s at each bin's direction;
 * between two bins, linear in the angle). A gait whose speeds are all 0 has no envelope (the data
 * says nothing about it): its speeds are the ellipse's alone. */
typedef struct mm_speed_envelope {
    float speeds[MM_SPEED_ENVELOPE_BINS];
} mm_speed_envelope;

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
 * run; gait_halflife 0.2 s, history_seconds 10 s, history_rate 60 per second; the collider 0.3 m
 * in radius, 1.8 m high, stepping over 0.3 m; no speed envelope (bounded false). */
typedef struct mm_trajectory_desc {
    mm_gait_params gaits[MM_GAIT_COUNT]; /* per gait */
    float gait_halflife;                 /* s: gait style weights follow the input's gait */
    float history_seconds;               /* s: the recorded past */
    float history_rate;                  /* samples per second of the past */
    float collider_radius;               /* m: the capsule's radius, in a scene */
    float collider_height;               /* m: a box whose bottom is this far above the floor is
                                            walked under, not a wall */
    float collider_step;                 /* m: a box whose top is at most this far above the floor
                                            is stepped over, not a wall (mm_trajectory_set_scene
                                            may raise it) */
    /* The speed envelope (mm/speed_envelope.h measures it from a database): with bounded true,
     * the desired velocity of each gait is at most envelopes[gait]'s speed in its direction (each
     * speed in [0, 50] m/s). mm_character_desc_from_database sets them from the database's
     * settings unless runtime.speed_envelope is false. */
    bool bounded;
    mm_speed_envelope envelopes[MM_GAIT_COUNT];
    const mm_allocator *allocator;
} mm_trajectory_desc;

/* Every field of d at its default (written out). */
void mm_trajectory_defaults(mm_trajectory_desc *d);
/* in with its zero fields at their defaults and its negative ones at 0 (what mm_trajectory_init
 * runs with); out may be in. */
void mm_trajectory_resolve_desc(const mm_trajectory_desc *in, mm_trajectory_desc *out);

/* s: the longest step of the collided simulation */
#define MM_TRAJECTORY_COLLISION_STEP (1.0f / 60.0f)
/* the most wall faces one step slides along (a corner of two, and a margin) */
#define MM_TRAJECTORY_MAX_CONTACTS 4
/* m: a wall this close to the capsule touches it (it rests against it) */
#define MM_TRAJECTORY_CONTACT_SKIN 0.01f
/* m/s: slower, what is left of the velocity asked for along a wall does not turn the facing */
#define MM_TRAJECTORY_SLIDE_MIN_SPEED 0.3f

typedef struct mm_trajectory {
    mm_vec3 position, velocity, acceleration; /* on the ground (y = 0) */
    mm_quat facing;
    mm_quat target_facing;             /* the last facing asked for (the facing spring's target) */
    mm_vec3 last_desired;              /* the last nonzero velocity asked for (a stop turns toward it) */
    mm_vec3 angular_velocity;          /* rad/s about world axes */
    float gait_weights[MM_GAIT_COUNT]; /* style weights, summing to about 1 */
    float gait_rates[MM_GAIT_COUNT];
    double time; /* seconds simulated */
    /* history: positions and facings at times k / history_rate, a ring buffer */
    mm_vec3 *history_position;
    mm_quat *history_facing;
    int history_capacity, history_count, history_head; /* head: index of the newest */
    double history_time;                               /* time of the newest sample */
    /* collision (mm_trajectory_set_scene): the scene (NULL: none), the height of the ground the
     * capsule stands on (the caller keeps it where the character stands; 0 by default), and the
     * height above it up to which a box is not a wall */
    const mm_scene *scene;
    float floor;
    float pass_height;
    /* the walls the simulation rests against after the last update (their faces' normals) */
    mm_vec3 contact_normals[MM_TRAJECTORY_MAX_CONTACTS];
    int contact_count;
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

/* The velocity and facing the input asks for, given the current facing (targets of the springs).
 * Resting against walls (contact_count), the velocity loses its part into them and, unless
 * strafing, the facing turns along what is left (when it is at least MM_TRAJECTORY_SLIDE_MIN_SPEED):
 * the character slides along a wall, or stops at it facing it. */
void mm_trajectory_desired(const mm_trajectory *t, const mm_input *in, mm_vec3 *velocity, mm_quat *facing);

/* The fastest the desc lets gait move in direction (radians from straight ahead toward the left,
 * +X, in the facing's frame): the envelope's speed there (linear between its bins), or INFINITY
 * when the desc is not bounded or the gait has no envelope. */
float mm_trajectory_envelope_speed(const mm_trajectory_desc *d, mm_gait gait, float direction);

/* Advances by dt seconds (negative, NaN or infinite dt do nothing; a NaN or oversized stick
 * counts as zero or is clamped to the unit circle). Allocates nothing. */
void mm_trajectory_update(mm_trajectory *t, const mm_input *in, float dt);

/* The scene the simulated character collides with (NULL: none). A box is a wall when its top is
 * more than pass_height above the floor and its bottom less than collider_height above it
 * (t->floor: the ground under the character, kept by the caller); pass_height < 0 (or NaN) takes the desc's
 * collider_step, INFINITY makes nothing a wall (collision off, the scene kept). The scene must
 * outlive its use. */
void mm_trajectory_set_scene(mm_trajectory *t, const mm_scene *scene, float pass_height);

/* Pushes *position (horizontally) out of the walls as the simulation's capsule (the same rule:
 * radius, floor, heights); writes up to max_normals faces' normals and returns how many faces
 * it touched (0 without a scene). */
int mm_trajectory_collide(const mm_trajectory *t, mm_vec3 *position, mm_vec3 *normals, int max_normals);

/* The simulation `seconds` ahead (at most a minute) with the targets `velocity` and `facing` held
 * and the gait's half-lives, stepped and collided as mm_trajectory_sample's future (in closed form
 * without a scene). *position, *facing_out and *path may be NULL; path: the length of the stepped
 * path (m; without a scene the straight distance).
 * Returns how many steps touched a wall (0 without a scene). */
int mm_trajectory_predict(const mm_trajectory *t, mm_vec3 velocity, mm_quat facing, mm_gait gait,
                          float seconds, mm_vec3 *position, mm_quat *facing_out, float *path);

/* Positions and facings at the given times relative to now (seconds; negative = past, from the
 * history, held at its oldest sample; positive = predicted with the input held). */
void mm_trajectory_sample(const mm_trajectory *t, const mm_input *in, const float *times, int count,
                          mm_vec3 *positions, mm_quat *facings);

#ifdef __cplusplus
}
#endif

#endif /* MM_TRAJECTORY_H */
