/* Stage 2: the playhead, by the clock or by distance matching (docs/distance.md, "In the
 * controller"). */
#include "playback.h"

#include <math.h>
#include <string.h>

/* s: the window either side of the playhead over which a one-shot clip's root speed is measured
 * for the stride scale (the root's speed swings within each step, and a scale following it would
 * stretch and shrink the legs every tick, dragging the planted foot along) */
#define STRIDE_SPEED_WINDOW 0.25f
/* s: outside loop cycles the stride scale follows its target with this half-life, also back to 1
 * at rest (a change of scale moves a planted foot by the change times its distance from the hip) */
#define STRIDE_SCALE_HALFLIFE 0.1f
/* m/s: below this the simulation counts as standing for stride warping */
#define STRIDE_MIN_SPEED 0.05f
/* the slowest play rate the look-ahead for a coming contact assumes (a clip standing still would
 * put every contact infinitely far) */
#define CONTACT_LOOKAHEAD_MIN_RATE 0.1f
/* s: after a change of clip the play rate goes from the old clip's to the new one's with this
 * half-life: a rate that steps (1.0 to 1.25 after a jump) steps the root's velocity and every
 * joint's in the clip with it */
#define PLAY_RATE_JUMP_HALFLIFE 0.1f
/* the largest play rate a stop or pivot match may ask for */
#define PLAY_RATE_LIMIT 16.0f

void mm_playback_by_clock(mm_playback *p)
{
    p->mode = MM_PLAYBACK_CLOCK;
    p->play_rate = 1.0f;
    p->stride_scale = 1.0f;
    p->rate_clip = 0;
    p->rate_kept = 0.0f;
}

/* A one-shot clip: advance by distance, or match to the predicted stop or pivot. Returns the play
 * rate; sets p->mode and p->stride_scale. */
static float one_shot_rate(mm_playback *p, const mm_distance_curve *curve, const mm_playback_params *params,
                           const mm_trajectory *t, const mm_input *in, const mm_intent *intent, float time,
                           float speed, float travelled, float dt)
{
    float rate = 1.0f;
    int segment = mm_distance_segment_at(curve, time);
    int kind = curve->segments[segment].kind;
    float before = mm_distance_signed(curve, time); /* < 0: the stop or pivot is ahead */
    mm_vec3 desired = intent->desired_velocity;
    float wanted = sqrtf(desired.x * desired.x + desired.z * desired.z);
    mm_distance_prediction stop, pivot;
    memset(&stop, 0, sizeof stop);
    memset(&pivot, 0, sizeof pivot);
    if (kind != MM_DISTANCE_NONE && before < 0.0f) mm_distance_predict_trajectory(t, in, 0.0f, &stop, &pivot);
    float target = -1.0f;
    if (kind == MM_DISTANCE_STOP && before < 0.0f && stop.found && wanted < params->idle_speed &&
        mm_distance_match_to_target(curve, segment, stop.distance, &target) == MM_OK) {
        p->mode = MM_PLAYBACK_STOP; /* braking: the clip's stop where the character's is */
    } else if (kind == MM_DISTANCE_PIVOT && before < 0.0f && pivot.found &&
               mm_distance_match_to_target(curve, segment, pivot.distance, &target) == MM_OK) {
        p->mode = MM_PLAYBACK_PIVOT;
    } else if (kind == MM_DISTANCE_STOP && before >= 0.0f) {
        p->mode = MM_PLAYBACK_CLOCK; /* past the stop: played out */
    } else {
        float next;
        mm_distance_advance(curve, time, travelled, dt, params->rate_min, params->rate_max, &next, &rate);
        p->mode = MM_PLAYBACK_DISTANCE;
    }
    if (p->mode == MM_PLAYBACK_STOP || p->mode == MM_PLAYBACK_PIVOT) {
        /* toward the matched time, never backwards, within the clamp */
        rate = (target - time) / dt;
        if (params->rate_min > 0.0f || params->rate_max > 0.0f)
            rate = fminf(fmaxf(rate, params->rate_min), params->rate_max);
        if (!(rate >= 0.0f)) rate = 0.0f;
    }
    if (!params->distance_matching) rate = 1.0f, p->mode = MM_PLAYBACK_CLOCK; /* warping only */
    /* the clip's root speed over a step, not this tick's */
    float duration = mm_distance_duration(curve), h = STRIDE_SPEED_WINDOW;
    float a = fmaxf(time - h, 0.0f), b = fminf(time + h, duration);
    float clip_speed =
        b - a > 1e-3f ? (mm_distance_travelled(curve, b) - mm_distance_travelled(curve, a)) / (b - a) : 0.0f;
    if (clip_speed * rate > 1e-2f && speed > STRIDE_MIN_SPEED) {
        float scale = speed / (clip_speed * rate);
        if (params->stride_min > 0.0f || params->stride_max > 0.0f)
            scale = fminf(fmaxf(scale, params->stride_min), params->stride_max);
        p->stride_scale = isfinite(scale) && scale > 0.0f ? scale : 1.0f;
    }
    return rate;
}

/* The play rate and the stride scale asked for this tick (before the stride scale's easing). */
static void match_target(mm_playback *p, const mm_playback_params *params, const mm_distance_curve *curve,
                         int clip_first_frame, const mm_trajectory *t, const mm_input *in,
                         const mm_intent *intent, float dt)
{
    mm_playback_by_clock(p);
    if (!curve) return;
    float speed = mm_intent_ground_speed(t);
    if (!isfinite(speed)) speed = 0.0f;
    float travelled = intent->travelled;
    if (!isfinite(travelled) || travelled < 0.0f) travelled = 0.0f;
    float time = (float)((double)(p->frame - clip_first_frame) + p->fraction) / curve->fps;
    float rate = 1.0f;
    if (curve->loop) { /* a cycle: desired speed / the clip's average speed, clamped */
        float clip_speed = mm_distance_clip_speed(curve);
        if (params->distance_matching) {
            mm_distance_play_rate(speed, clip_speed, params->rate_min, params->rate_max, &rate);
            p->mode = MM_PLAYBACK_CYCLE;
        }
        mm_distance_stride_scale(speed, clip_speed, rate, params->stride_min, params->stride_max,
                                 &p->stride_scale);
    } else {
        rate = one_shot_rate(p, curve, params, t, in, intent, time, speed, travelled, dt);
    }
    p->play_rate = isfinite(rate) && rate >= 0.0f ? fminf(rate, PLAY_RATE_LIMIT) : 1.0f;
    if (!params->warping || !(speed > STRIDE_MIN_SPEED)) p->stride_scale = 1.0f;
}

void mm_playback_match_distance(mm_playback *p, const mm_playback_params *params,
                                const mm_distance_curve *curve, int clip_first_frame, const mm_trajectory *t,
                                const mm_input *in, const mm_intent *intent, float dt)
{
    float previous = p->stride_scale, previous_rate = p->play_rate, kept = p->rate_kept;
    int previous_clip = p->rate_clip;
    match_target(p, params, curve, clip_first_frame, t, in, intent, dt);
    if (curve && params->distance_matching) {
        if (previous_clip != 0 && previous_clip != clip_first_frame + 1 && isfinite(previous_rate))
            kept = previous_rate - p->play_rate; /* a change of clip: the rate played goes on */
        else
            kept *= exp2f(-dt / PLAY_RATE_JUMP_HALFLIFE);
        if (!isfinite(kept)) kept = 0.0f;
        p->play_rate = fminf(fmaxf(p->play_rate + kept, 0.0f), PLAY_RATE_LIMIT);
        p->rate_kept = kept;
        p->rate_clip = clip_first_frame + 1;
    }
    if (params->warping && p->mode != MM_PLAYBACK_CYCLE && isfinite(previous) && previous > 0.0f) {
        float scale = previous + (p->stride_scale - previous) * (1.0f - exp2f(-dt / STRIDE_SCALE_HALFLIFE));
        p->stride_scale = fabsf(scale - 1.0f) < 1e-4f && p->stride_scale == 1.0f ? 1.0f : scale;
    }
}

bool mm_playback_advance(mm_playback *p, const int32_t *frame_next, float interval, float dt)
{
    p->fraction += (double)p->play_rate * (double)dt / (double)interval;
    /* no epsilon: the fraction is a double advanced by dt / interval, so a tick of the database's
     * interval (or a power-of-two multiple or divisor of it) lands exactly on a frame and other
     * rates drift by double rounding only */
    while (p->fraction >= 1.0) {
        p->fraction -= 1.0;
        int next = frame_next[p->frame];
        if (next < 0) {
            p->fraction = 0.0;
            return true;
        }
        p->frame = next;
    }
    return false;
}

float mm_playback_time_to_contact(const mm_playback *p, const int32_t *frame_next, const uint8_t *contacts,
                                  float interval, int foot, float window)
{
    unsigned mask = 3u << (2 * foot);
    double step = (double)interval /
                  (p->play_rate > CONTACT_LOOKAHEAD_MIN_RATE ? p->play_rate : CONTACT_LOOKAHEAD_MIN_RATE);
    double t = (1.0 - p->fraction) * step;
    for (int f = frame_next[p->frame]; f >= 0 && t <= window; f = frame_next[f], t += step)
        if (contacts[f] & mask) return (float)t;
    return -1.0f;
}
