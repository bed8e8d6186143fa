/* mm/distance.h - distance matching, stride warping and orientation warping (seed 003).
 *
 * The character's capsule and the clip playing rarely agree about speed, stopping point or
 * direction; the feet then slide. Distance matching drives the clip's time by distance instead of
 * by the clock, and the two warps bend the pose where time alone cannot help:
 *
 *   - Distance curves, made offline for each clip from its root path: the travelled path length
 *     per frame (monotonic over the whole clip), and per segment the signed distance to the
 *     segment's stop or pivot point (negative before it, 0 at it, positive after it). A stop or
 *     pivot is where the root speed is lowest below a threshold; clips with several stops are
 *     split into segments; loops keep growing across the wrap.
 *   - Advance time by distance matching: move the playhead so the clip's root travels the
 *     distance the character travelled this tick, with a play-rate clamp (default 0.75 - 1.25).
 *   - Distance match to target: the time whose remaining distance to the stop equals a given one.
 *   - Play rate to match speed: desired speed / the clip's average root speed, clamped.
 *   - Stop and pivot points predicted from the trajectory's critically damped velocity spring
 *     (mm/spring.h, mm/trajectory.h), in closed form, so they agree with the simulation.
 *   - Stride warping: feet scaled along the movement direction about their hips, the pelvis
 *     lowered when a leg could no longer reach, two-bone IK.
 *   - Orientation warping: the lower body turned toward the movement direction, the spine
 *     counter-rotated by weights so the upper body keeps facing where it faced.
 *
 *   mm_distance_curve c;
 *   mm_distance_desc d = {0};
 *   d.positions = root_xz; d.components = 2; d.frame_count = n; d.fps = 30; d.loop = 0;
 *   mm_distance_curve_build(&c, &d, &err);               offline; allocates once
 *   each tick (no allocation):
 *     mm_distance_advance(&c, t, travelled_this_tick, dt, 0.75f, 1.25f, &t, &rate);
 *     mm_distance_match_to_target(&c, segment, predicted.distance, &t);
 *   mm_distance_curve_free(&c);
 *
 * Units: metres, seconds, radians; Y up, characters face +Z; distances are measured on the
 * ground plane (x, z). Quaternions are {x, y, z, w} (mm/math.h). Every per-tick function is free
 * of allocation, reports bad parameters with MM_ERR_INVALID_ARGUMENT (or MM_ERR_OUT_OF_RANGE when
 * the data cannot answer) and still writes finite outputs: NaN inputs never give NaN outputs.
 *
 * Functions:
 *   curves:     mm_distance_curve_build mm_distance_curve_free mm_distance_curve_validate
 *               mm_distance_duration mm_distance_travelled mm_distance_signed mm_distance_segment_at
 *   matching:   mm_distance_time_after mm_distance_advance mm_distance_match_to_target
 *               mm_distance_clip_speed mm_distance_play_rate mm_distance_stride_scale
 *   prediction: mm_distance_predict_stop mm_distance_predict_pivot mm_distance_predict_trajectory
 *   warping:    mm_warp_leg_ik mm_warp_stride mm_warp_orientation mm_warp_orientation_point
 */
#ifndef MM_DISTANCE_H
#define MM_DISTANCE_H

#include <stdint.h>

#include "alloc.h"
#include "input.h"
#include "math.h"
#include "result.h"
#include "trajectory.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Defaults. */
#define MM_DISTANCE_STOP_SPEED_DEFAULT  0.1f  /* m/s: below this the root counts as stopping */
#define MM_DISTANCE_RATE_MIN_DEFAULT    0.75f /* play-rate clamp of advance and play rate */
#define MM_DISTANCE_RATE_MAX_DEFAULT    1.25f
#define MM_DISTANCE_REST_SPEED_DEFAULT  0.05f   /* m/s: a predicted stop is reached below this */
#define MM_WARP_MAX_EXTENSION_DEFAULT   0.999f  /* a warped leg stretches to at most this of its length */
#define MM_WARP_ORIENTATION_MAX_DEFAULT 1.5708f /* rad: largest orientation correction (90 deg) */
#define MM_WARP_ORIENTATION_MAX_SPINE   8       /* spine joints sharing the counter-rotation */
#define MM_WARP_MAX_LEGS                8

/* ---- distance curves ------------------------------------------------------------------ */

typedef enum mm_distance_kind {
    MM_DISTANCE_NONE = 0,  /* no stop in the segment: distance from its first frame */
    MM_DISTANCE_STOP = 1,  /* the root comes to rest (or nearly) and goes on the same way, or not */
    MM_DISTANCE_PIVOT = 2, /* the root slows to its lowest speed and leaves the other way (> 90 deg) */
} mm_distance_kind;

/* One segment: consecutive frames (a loop's segment may run past the last frame into the first)
 * measured against one stop or pivot. All fields are 4 bytes wide, for storing as they are. */
typedef struct mm_distance_segment {
    int32_t first_frame;    /* 0-based */
    int32_t frame_count;    /* >= 1; frames first_frame .. first_frame + frame_count - 1 (mod n in loops) */
    int32_t marker_frame;   /* the stop or pivot frame; first_frame for MM_DISTANCE_NONE */
    int32_t kind;           /* mm_distance_kind */
    float marker_travelled; /* travelled path (m) at the marker, counted in the segment's unwrapped
                             * frames: frames past a loop's wrap add the path length once */
} mm_distance_segment;

/* A clip's distance curves: flat float arrays plus a segment table (ready to be stored in a file).
 * A curve made by mm_distance_curve_build owns one block; to read one stored elsewhere, fill the
 * fields yourself with block NULL (and check it with mm_distance_curve_validate). */
typedef struct mm_distance_curve {
    int32_t frame_count; /* >= 2 */
    int32_t loop;        /* 1: the frame after the last is the first */
    float fps;           /* frames per second, > 0 */
    float path_length;   /* m: the whole root path on the ground; a loop's includes the wrap step */
    int32_t segment_count;
    const float *travelled;              /* [frame_count] m from frame 0 along the path, non-decreasing */
    const float *distance;               /* [frame_count] m, signed distance to the segment's marker */
    const mm_distance_segment *segments; /* [segment_count], in frame order, covering every frame once */
    void *block;                         /* owned allocation, or NULL for a view */
    mm_allocator allocator;
} mm_distance_curve;

/* Defaults: stop_speed 0.1 m/s; loop_step interpolated from the steps around the wrap. */
typedef struct mm_distance_desc {
    const float *positions; /* root positions, frame_count rows of `components` floats */
    int components;         /* 2: (x, z) per frame; 3: (x, y, z) per frame (y ignored) */
    int frame_count;        /* >= 2 */
    float fps;              /* > 0 */
    int loop;               /* nonzero: a loop clip */
    float stop_speed;       /* m/s; 0: MM_DISTANCE_STOP_SPEED_DEFAULT */
    float loop_step;        /* m: path from the last frame to the first when a loop wraps; 0: the
                             * cubic through the two steps before and the two after the wrap */
    const mm_allocator *allocator;
} mm_distance_desc;

/* Builds the curves (allocates one block; offline). Stops: each run of frames whose speed (mean
 * of the two adjacent ground steps, times fps) is below stop_speed marks the first frame of the
 * run whose speed is within a quarter of stop_speed of the run's lowest, moved on while the speed
 * keeps falling (the earliest moment at rest, or the bottom of a pivot). A run at the start of a
 * one-shot clip is not a stop (the clip starts from rest: its distance counts from the start). A
 * segment ends with the run after its marker (where the root speeds up again); the last one runs
 * to the end of the clip. err (may be NULL) says which frame or field is wrong.
 * MM_ERR_INVALID_ARGUMENT for bad sizes or parameters, MM_ERR_BAD_NUMBER for a non-finite
 * position, MM_ERR_OUT_OF_MEMORY. On failure c is zeroed. */
mm_result mm_distance_curve_build(mm_distance_curve *c, const mm_distance_desc *desc, mm_error *err);
void mm_distance_curve_free(mm_distance_curve *c);
/* Checks a curve (for example one read from a file): sizes, finite and monotonic values,
 * segments covering every frame once with their marker inside. */
mm_result mm_distance_curve_validate(const mm_distance_curve *c, mm_error *err);

/* Seconds of clip time: (frame_count - 1) / fps for one-shots, frame_count / fps for loops. */
float mm_distance_duration(const mm_distance_curve *c);
/* Path travelled (m) from time 0 to time t, linear between frames. One-shots clamp t to
 * [0, duration]; loops take any t and keep growing: travelled(t + k duration) = travelled(t) +
 * k path_length. 0 for a non-finite t or an invalid curve. */
float mm_distance_travelled(const mm_distance_curve *c, float t);
/* The segment holding clip time t (wrapped or clamped into the clip); 0 when t is not finite. */
int mm_distance_segment_at(const mm_distance_curve *c, float t);
/* Signed distance (m) to the marker of the segment holding time t; continuous within a segment. */
float mm_distance_signed(const mm_distance_curve *c, float t);

/* ---- distance matching (per tick; no allocation) -------------------------------------- */

/* Seed 003's GetTimeAfterDistanceTraveled: from time, steps frame by frame (the curve is linear
 * between frames, so the fraction of the last step is exact) until the clip's root has travelled
 * distance (m, >= 0). Steps where the root does not move are passed through. Loops wrap (the
 * result is unwrapped: >= time, whole loops skipped at once); one-shots stop at the last frame.
 * Returns time itself for a bad argument; at most FLT_MAX. */
float mm_distance_time_after(const mm_distance_curve *c, float time, float distance);

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

/* The clip's average root speed: path_length / duration (m/s); 0 for an invalid curve. */
float mm_distance_clip_speed(const mm_distance_curve *c);
/* Seed 003's SetPlayRateToMatchSpeed: rate = desired_speed / clip_speed, clamped to
 * [rate_min, rate_max] ((0, 0) disables the clamp). MM_ERR_OUT_OF_RANGE when clip_speed is below
 * 1e-4 m/s (rate 1, clamped); MM_ERR_INVALID_ARGUMENT for a negative or non-finite speed or a bad
 * clamp (rate 1). */
mm_result mm_distance_play_rate(float desired_speed, float clip_speed, float rate_min, float rate_max,
                                float *out_rate);
/* Stride scale for cycles: desired_speed / (clip_speed * play_rate), clamped to [scale_min,
 * scale_max] ((0, 0) disables the clamp). Errors as mm_distance_play_rate (scale 1). */
mm_result mm_distance_stride_scale(float desired_speed, float clip_speed, float play_rate, float scale_min,
                                   float scale_max, float *out_scale);

/* ---- stop and pivot prediction (closed form of the trajectory's velocity spring) ---------- */

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
 * if the stick were let go now; pivot = the pivot point under `in`. Either output may be NULL. */
mm_result mm_distance_predict_trajectory(const mm_trajectory *t, const mm_input *in, float rest_speed,
                                         mm_distance_prediction *stop, mm_distance_prediction *pivot);

/* ---- warping (per tick; no allocation) ------------------------------------------------- */

typedef struct mm_leg_pose {
    mm_vec3 hip, knee, foot; /* world positions (m) of the upper leg, lower leg and ankle joints */
} mm_leg_pose;

typedef struct mm_leg_warp {
    mm_leg_pose pose; /* the warped positions */
    mm_vec3 target;   /* the foot target asked for */
    /* world-space rotation deltas: new world rotation = delta * old (thigh at the hip joint, shin
     * at the knee joint) */
    mm_quat thigh, shin;
} mm_leg_warp;

/* Two-bone IK on positions: the foot moves to target (kept within max_extension of the full
 * leg, 0: MM_WARP_MAX_EXTENSION_DEFAULT, but never less stretched than the leg is now). The leg
 * is swung onto the new hip-target axis keeping the bend it has; more bend than that goes toward
 * the pole (where the knee points, for example the pelvis's facing; zero: none), and a bend
 * against the pole fades out as the leg straightens (docs/distance.md, "Stride warping"). A
 * target at the foot leaves a bent leg as it is. Lengths are kept exactly (to float rounding). */
mm_result mm_warp_leg_ik(const mm_leg_pose *leg, mm_vec3 target, mm_vec3 pole, float max_extension,
                         mm_leg_warp *out);

/* Stride warping: each foot's target is the foot moved along the movement direction (y ignored)
 * so that its distance from the hip's projection on the ground, along that direction, is scaled
 * by scale (> 0); the pelvis (all hips together) is lowered only as far as needed for every leg
 * to reach within max_extension (0: default); then two-bone IK with the direction as pole.
 * Scale 1 and a zero direction are the identity. *pelvis_drop (may be NULL): m lowered (>= 0). */
mm_result mm_warp_stride(const mm_leg_pose *legs, int leg_count, mm_vec3 direction, float scale,
                         float max_extension, mm_leg_warp *out, float *pelvis_drop);

/* Defaults: max_angle 90 deg, speed 0 (no smoothing), equal spine weights. */
typedef struct mm_warp_orientation_params {
    float max_angle;            /* rad, largest correction; 0: MM_WARP_ORIENTATION_MAX_DEFAULT */
    float speed;                /* 1/s: the angle follows its target as 1 - e^(-speed dt); 0: at once */
    float halflife;             /* s: > 0 follows it through a critically damped spring instead (the
                                 * angle's rate stays continuous when the target jumps); speed unused */
    float velocity;             /* rad/s: the angle's rate after the last call (halflife mode) */
    float hysteresis;           /* rad: near 90 deg keep the side (forward/backward) chosen before; 0: 0.17 */
    int spine_count;            /* 0 .. MM_WARP_ORIENTATION_MAX_SPINE */
    const float *spine_weights; /* [spine_count] >= 0 (normalised to sum 1); NULL: equal */
} mm_warp_orientation_params;

typedef struct mm_warp_orientation_result {
    float target_angle; /* rad about +Y from the facing to the movement (flipped when backward) */
    float angle;        /* rad, the correction applied (smoothed, clamped) */
    float velocity;     /* rad/s: the angle's rate (halflife mode; 0 otherwise or when clamped) */
    int backward;       /* 1: the movement is more than 90 deg from the facing and the legs take
                         * the backward direction */
    mm_quat lower_body; /* world rotation about +Y by angle: the pelvis and legs */
    /* per spine joint, from the pelvis up: its world-space delta about +Y, lower_body rotated
     * back by the weights so far; after the last one the upper body is as it was */
    mm_quat spine[MM_WARP_ORIENTATION_MAX_SPINE];
} mm_warp_orientation_result;

/* Orientation warping. facing and movement are directions on the ground (y ignored; a movement
 * shorter than 1e-4 asks for no correction); previous_angle is the last call's angle (0 at the
 * start); dt >= 0 seconds. Angle 0 gives identities. params may be NULL. */
mm_result mm_warp_orientation(mm_vec3 facing, mm_vec3 movement, float previous_angle, float dt,
                              const mm_warp_orientation_params *params, mm_warp_orientation_result *out);
/* Applies an orientation warp to a pose's rotations. The pelvis's world rotation becomes
 * w->lower_body * pelvis_world (so the legs below it turn with it), and spine joint i's world
 * rotation becomes w->spine[i] * spine_world[i]; spine[0] hangs from the pelvis and spine[i] from
 * spine[i - 1]. Writes the new local rotations: *pelvis_local (the pelvis's parent has world
 * rotation parent_world) and spine_local[spine_count] (0 .. MM_WARP_ORIENTATION_MAX_SPINE). The
 * joints above the last spine joint keep their world rotation. When w->angle is 0 nothing is
 * written (the pose stays bit for bit). MM_ERR_INVALID_ARGUMENT for NULL or a bad count. */
mm_result mm_warp_orientation_pose(const mm_warp_orientation_result *w, mm_quat parent_world,
                                   mm_quat pelvis_world, const mm_quat *spine_world, int spine_count,
                                   mm_quat *pelvis_local, mm_quat *spine_local);
/* A point (for example a planted foot) turned with the lower body about pivot (the root). */
mm_vec3 mm_warp_orientation_point(const mm_warp_orientation_result *w, mm_vec3 pivot, mm_vec3 point);

#ifdef __cplusplus
}
#endif

#endif /* MM_DISTANCE_H */
