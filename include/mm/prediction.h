/* mm/prediction.h - stop and pivot prediction: where the character will come to rest, or turn
 * back, from its trajectory's velocity spring, in closed form (seed 003).
 *
 * The trajectory's velocity follows a critically damped spring toward the velocity the input
 * asks for (mm_spring_velocity_update, mm/spring.h, mm/trajectory.h). Solved in closed form rather
 * than stepped, the predictions agree with the simulation whatever the tick. Distance matching
 * (mm/distance_matching.h) plays a clip's stop or pivot to the predicted distance.
 *
 *   mm_distance_prediction stop, pivot;
 *   mm_distance_predict_trajectory(&trajectory, &input, 0.0f, &stop, &pivot);
 *   if (stop.found) mm_distance_match_to_target(&curve, segment, stop.distance, &t);
 *
 * Units: metres, seconds; Y up. Every function is free of allocation, reports bad parameters with
 * MM_ERR_INVALID_ARGUMENT (MM_ERR_OUT_OF_RANGE when the numbers overflow floats) and then writes
 * a zero prediction (found 0): NaN inputs never give NaN outputs.
 *
 * Functions: mm_distance_predict_stop mm_distance_predict_pivot mm_distance_predict_trajectory
 */
#ifndef MM_PREDICTION_H
#define MM_PREDICTION_H

#include "input.h"
#include "math.h"
#include "result.h"
#include "trajectory.h"

#ifdef __cplusplus
extern "C" {
#endif

#define MM_DISTANCE_REST_SPEED_DEFAULT 0.05f /* m/s: a predicted stop is reached below this */

/* The velocity v follows a critically damped spring toward the target velocity g with half-life
 * h (mm_spring_velocity_update): v(t) = g + (j0 + j1 t) e^(-y t), j0 = v0 - g, j1 = a0 + j0 y.
 * With g = 0 the root comes to rest after the offset j0 / y + j1 / y^2. */
typedef struct mm_distance_prediction {
    int found;      /* 1: the point exists (a stop with motion left; a pivot ahead) */
    mm_vec3 offset; /* m: from the current position to the point */
    float distance; /* m: path length along the predicted motion to the point */
    float time;     /* s: until the point (a stop: until the speed stays below rest_speed) */
} mm_distance_prediction;

/* Where the character comes to rest when its velocity (m/s) and acceleration (m/s^2) decay with
 * half-life halflife (s; 0: at once). rest_speed (m/s; 0: MM_DISTANCE_REST_SPEED_DEFAULT) only
 * sets `time` and `found` (found = 0 when the speed stays below it: already at rest). */
mm_result mm_distance_predict_stop(mm_vec3 velocity, mm_vec3 acceleration, float halflife, float rest_speed,
                                   mm_distance_prediction *out);
/* The pivot point: where the velocity, springing toward target_velocity, stops moving against
 * it (its component along target_velocity crosses zero). found = 0 when it does not move against
 * the target now, or the target is zero (use mm_distance_predict_stop). */
mm_result mm_distance_predict_pivot(mm_vec3 velocity, mm_vec3 acceleration, mm_vec3 target_velocity,
                                    float halflife, mm_distance_prediction *out);
/* Both, for a trajectory (mm/trajectory.h) with the input `in` held: stop = where it would rest
 * if the stick were let go now; pivot = the pivot point under `in`. Either output may be NULL.
 * In a scene (mm_trajectory_set_scene) a stop whose way meets a wall is the collided simulation's
 * (mm_trajectory_predict over the stop's time): it ends at the wall, or slides along it, and its
 * distance is the path's. */
mm_result mm_distance_predict_trajectory(const mm_trajectory *t, const mm_input *in, float rest_speed,
                                         mm_distance_prediction *stop, mm_distance_prediction *pivot);

#ifdef __cplusplus
}
#endif

#endif /* MM_PREDICTION_H */
