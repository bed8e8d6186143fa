/* mm/target_match.h - target matching: bend a move's root motion so that a bone reaches a
 * target at a given time of the clip (Unity's Animator.MatchTarget semantics; seed 000, 三.4).
 *
 * A match names a bone (the caller's index, for its own use), a target position and rotation in
 * world space, a weight mask (per-axis position weights in world axes, and a rotation weight),
 * and a window [start_time, end_time] of clip time in seconds (mm_target_match_set_normalized
 * converts Unity's normalised times). During the window, every tick the caller passes where the
 * bone WILL be at end_time if no further correction is applied (it knows the clip: the root as it
 * is now, moved by the clip's root motion up to end_time, times the bone's transform relative to
 * the root then), and gets back the root correction for this tick. The remaining error is spread
 * over the remaining window in proportion to the time this tick covers, so the bone arrives
 * exactly at end_time, also when the target moves or turns during the window (each tick looks
 * at the target as it is then). Weights between 0 and 1 make the bone arrive at that fraction of
 * the way from where the clip alone would take it to the target; weight 0 leaves an axis alone.
 *
 * The correction is a world-space rigid transform to apply to the root on the left:
 * root = correction * root. It turns about +Y around the bone's predicted end position (so the
 * turn does not move that point; the root stays upright: only the yaw of the rotation is
 * matched) and then translates. Apply it before advancing the clip by dt.
 *
 * The per-tick function never allocates; the match is a plain struct the caller owns.
 *
 * Functions: mm_target_match_init mm_target_match_set_normalized mm_target_match_step
 *            mm_target_match_yaw
 */
#ifndef MM_TARGET_MATCH_H
#define MM_TARGET_MATCH_H

#include <stdbool.h>

#include "math.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct mm_target_match {
    /* what to match (set by mm_target_match_init; the target may change at any tick) */
    int bone;                /* the caller's bone index (not used here) */
    mm_vec3 target_position; /* world, metres */
    mm_quat target_rotation; /* world; only its yaw is matched */
    mm_vec3 position_weight; /* per world axis, in [0, 1] (values outside are clamped) */
    float rotation_weight;   /* in [0, 1] */
    float start_time;        /* clip time, seconds */
    float end_time;          /* clip time, seconds; the bone is on target then */
    /* state: the corrections applied so far (zeroed by init) */
    mm_vec3 applied_translation; /* sum of the translations handed out */
    float applied_yaw;           /* sum of the turns handed out, radians */
} mm_target_match;

/* A match of bone to the target over [start_time, end_time] (seconds), with every weight 1 and
 * nothing applied yet. */
void mm_target_match_init(mm_target_match *m, int bone, mm_vec3 target_position, mm_quat target_rotation,
                          float start_time, float end_time);

/* Sets the window from normalised times (fractions of the clip's duration, in seconds). */
void mm_target_match_set_normalized(mm_target_match *m, float start, float end, float clip_duration);

/* One tick: the clip plays from time to time + dt; predicted_end is the bone's world transform
 * at end_time if no correction were applied from now on. Writes the correction for this tick
 * (the identity outside the window) and returns true when the tick overlaps the window,
 * [time, time + dt] with start_time < ... <= end_time: it does nothing once time >= end_time.
 * On the tick that reaches end_time the whole remaining error is corrected. Non-finite input,
 * dt <= 0 or end_time <= start_time give the identity (and false); the match is unchanged. */
bool mm_target_match_step(mm_target_match *m, float time, float dt, mm_xform predicted_end,
                          mm_xform *correction);

/* The yaw of a rotation in radians, [-pi, pi]: the angle about +Y of its twist (0 for a rotation
 * with no twist about Y, e.g. a pure half-turn about a horizontal axis). */
float mm_target_match_yaw(mm_quat q);

#ifdef __cplusplus
}
#endif

#endif /* MM_TARGET_MATCH_H */
