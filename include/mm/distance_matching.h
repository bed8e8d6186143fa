/* mm/distance_matching.h - distance matching: moving a clip's playhead by the distance the
 * character travels instead of by the clock (seed 003).
 *
 * The character's capsule and the clip playing rarely agree about speed or stopping point; the
 * feet then slide. Each tick these functions move a playhead on a clip's distance curves
 * (mm/distance_curve.h): so that the clip's root travels the distance the character travelled,
 * within a play-rate clamp; or to the time whose remaining distance to the segment's stop or pivot
 * is a predicted one (mm/prediction.h); or they give the play rate (and the stride scale the rate
 * could not make up, mm/warp.h) that matches a speed.
 *
 *   each tick (no allocation):
 *     mm_distance_advance(&curve, t, travelled_this_tick, dt, 0.75f, 1.25f, &t, &rate);
 *     mm_distance_match_to_target(&curve, segment, predicted.distance, &t);
 *
 * Units: metres, seconds. Every function is free of allocation, reports bad parameters with
 * MM_ERR_INVALID_ARGUMENT (or MM_ERR_OUT_OF_RANGE when the data cannot answer) and still writes
 * finite outputs: NaN inputs never give NaN outputs.
 *
 * Functions: mm_distance_advance mm_distance_match_to_target mm_distance_play_rate
 *            mm_distance_stride_scale
 */
#ifndef MM_DISTANCE_MATCHING_H
#define MM_DISTANCE_MATCHING_H

#include "distance_curve.h"
#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

#define MM_DISTANCE_RATE_MIN_DEFAULT 0.75f /* play-rate clamp of advance and play rate */
#define MM_DISTANCE_RATE_MAX_DEFAULT 1.25f

/* Seed 003's AdvanceTimeByDistanceMatching. The character travelled `distance` (m, >= 0) in the
 * last dt seconds (> 0); the playhead at `time` moves to where the clip's root has travelled as
 * far, at the play rate (time_after - time) / dt clamped to [rate_min, rate_max]. (0, 0)
 * disables the clamp; otherwise 0 <= rate_min <= rate_max (MM_DISTANCE_RATE_*_DEFAULT: 0.75,
 * 1.25). *out_time: the new time, wrapped into [0, duration) for loops, at most the last frame's
 * time for one-shots; *out_rate (may be NULL): the play rate used. Errors: MM_ERR_INVALID_ARGUMENT
 * (bad numbers: the time is kept, clamped into the clip, rate 0); MM_ERR_OUT_OF_RANGE when the
 * clip's root does not move at all (it then plays at rate 1, clamped). */
mm_result mm_distance_advance(const mm_distance_curve *c, float time, float distance, float dt,
                              float rate_min, float rate_max, float *out_time, float *out_rate);

/* Seed 003's DistanceMatchToTarget: the time in `segment` whose remaining distance to the
 * segment's marker equals distance_to_target (m; negative: already past it), by binary search on
 * the segment's signed distances, linear between frames, clamped to the segment's first and last
 * frame. Where the curve is flat the earliest time is taken. *out_time is in [0, duration).
 * MM_ERR_INVALID_ARGUMENT for a bad segment or a non-finite distance (then the segment's marker
 * time, or 0). */
mm_result mm_distance_match_to_target(const mm_distance_curve *c, int segment, float distance_to_target,
                                      float *out_time);

/* Seed 003's SetPlayRateToMatchSpeed: rate = desired_speed / clip_speed (mm_distance_clip_speed),
 * clamped to [rate_min, rate_max] ((0, 0) disables the clamp). MM_ERR_OUT_OF_RANGE when
 * clip_speed is below 1e-4 m/s (rate 1, clamped); MM_ERR_INVALID_ARGUMENT for a negative or
 * non-finite speed or a bad clamp (rate 1). */
mm_result mm_distance_play_rate(float desired_speed, float clip_speed, float rate_min, float rate_max,
                                float *out_rate);
/* Stride scale for cycles: desired_speed / (clip_speed * play_rate), clamped to [scale_min,
 * scale_max] ((0, 0) disables the clamp). Errors as mm_distance_play_rate (scale 1). */
mm_result mm_distance_stride_scale(float desired_speed, float clip_speed, float play_rate, float scale_min,
                                   float scale_max, float *out_scale);

#ifdef __cplusplus
}
#endif

#endif /* MM_DISTANCE_MATCHING_H */
