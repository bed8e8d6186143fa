/* mm/drive.h - driving a character from the game's movement instead of a stick, and the root
 * motion handed back to the game's capsule. Part of mm_runtime.
 *
 * The game's AI, navigation or movement component says where the character should go:
 *  - a desired velocity and facing per tick: mm_drive_input_velocity makes the input (mm/input.h)
 *    that asks the simulation (mm/trajectory.h) for exactly that velocity and facing (the slowest
 *    gait whose speeds reach it, strafing toward the facing; faster than the fastest gait: its
 *    top speed in that direction);
 *  - a whole desired path (mm_path: positions and facings over time, linear between points):
 *    mm_drive_input_path asks, each tick, for the velocity that brings the simulation from where
 *    it is to the path's point `lookahead` seconds ahead (pure pursuit: on a straight path at
 *    constant speed it settles on the path with no lag), facing the path's facing; and
 *    mm_path_future gives the search the path itself as the future it matches
 *    (mm_character_set_future), so that a turn or a stop the path makes is seen coming.
 * The character then runs as ever (mm_character_update or mm_moves_update) on that input.
 *
 * Root motion: mm_root_delta_between(before, after) is the character's root's move over a tick,
 * in world and in the character's frame before it (translation and yaw). Two modes:
 *  - the animation drives the capsule: the game reads the root's delta each tick and moves its
 *    capsule by it (collision and all); where the capsule ends elsewhere (a wall), it tells the
 *    character (mm_character_set_root, mm_character_push_simulation);
 *  - the capsule drives the animation: the game moves its capsule itself and puts the simulation
 *    on it each tick (mm_character_push_simulation, or mm_character_teleport_simulation for a
 *    jump cut); the root is pulled toward the simulation as it always is (sync_halflife, within
 *    sync_max_distance and sync_max_angle).
 *
 * Nothing here allocates but mm_path_init.
 *
 * Functions: mm_drive_input_velocity mm_drive_input_path mm_root_delta_between
 *            mm_path_init mm_path_free mm_path_validate mm_path_sample mm_path_future
 */
#ifndef MM_DRIVE_H
#define MM_DRIVE_H

#include "alloc.h"
#include "input.h"
#include "math.h"
#include "result.h"
#include "trajectory.h"

#ifdef __cplusplus
extern "C" {
#endif

/* s: how far ahead on a path the simulation is steered toward (mm_drive_input_path) */
#define MM_DRIVE_LOOKAHEAD 0.4f

/* A point of a path: time (s), position and facing on the ground (world x, z; metres); a facing of
 * zero length faces along the path. */
typedef struct mm_path_point {
    float t;
    float position[2];
    float facing[2];
} mm_path_point;

typedef struct mm_path {
    int point_count;
    mm_path_point *points; /* [point_count], times increasing */
    mm_allocator allocator;
} mm_path;

/* Room for point_count points (zeroed); allocator may be NULL. */
mm_result mm_path_init(mm_path *p, int point_count, const mm_allocator *allocator);
void mm_path_free(mm_path *p);
/* At least one point, times finite and strictly increasing, positions and facings finite.
 * MM_ERR_OUT_OF_RANGE naming the point otherwise. */
mm_result mm_path_validate(const mm_path *p, mm_error *err);

/* The path at time t (linear between points; before the first and after the last: the end
 * point): position (y 0), velocity (the segment's; zero outside the path's times) and facing (a
 * unit direction on the ground: the points' facings interpolated, a point without one facing
 * along the segment; zero when nothing says). Any output may be NULL. */
void mm_path_sample(const mm_path *p, float t, mm_vec3 *position, mm_vec3 *velocity, mm_vec3 *facing);

/* The input asking the simulation t for velocity (world, m/s; y ignored) while facing `facing`
 * (a world direction, y ignored; zero: the direction of the velocity, or, standing, the facing
 * asked for last). */
void mm_drive_input_velocity(const mm_trajectory *t, mm_vec3 velocity, mm_vec3 facing, mm_input *out);

/* The input steering simulation t along path p at time `time`: toward the path's point at
 * time + lookahead (0: MM_DRIVE_LOOKAHEAD) from where the simulation is, facing the path's
 * facing at time + lookahead. */
void mm_drive_input_path(const mm_trajectory *t, const mm_path *p, float time, float lookahead,
                         mm_input *out);

/* The path's future for the search (mm_character_set_future): its positions and facings at
 * time + times[k] (the database's future trajectory times, mm_character_future_times); where the
 * path says no facing (a standing path without facings), `fallback`. */
void mm_path_future(const mm_path *p, float time, const float *times, int count, mm_quat fallback,
                    mm_vec3 *positions, mm_quat *facings);

/* A root's move over a tick. */
typedef struct mm_root_delta {
    mm_vec3 world; /* translation, world */
    mm_vec3 local; /* translation in the character's frame before the move (z forward) */
    float yaw;     /* rad, about +Y (counter-clockwise seen from above), in (-pi, pi] */
} mm_root_delta;

void mm_root_delta_between(mm_xform before, mm_xform after, mm_root_delta *out);

#ifdef __cplusplus
}
#endif

#endif /* MM_DRIVE_H */
