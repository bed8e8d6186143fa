/* Distance matching per tick: advance by distance, match to a target distance, play rate and
 * stride scale. See mm/distance_matching.h and docs/distance.md. Nothing here allocates. */
#include <mm/distance_matching.h>

#include <math.h>

#include "db/distance_curve_private.h"

static double clampd(double x, double lo, double hi) { return x < lo ? lo : x > hi ? hi : x; }

/* (0, 0): no clamp (returns 0); a valid clamp: 1; anything else: -1. */
static int clamp_kind(float lo, float hi)
{
    if (lo == 0.0f && hi == 0.0f) return 0;
    if (!isfinite(lo) || !isfinite(hi) || !(lo >= 0.0f) || !(lo <= hi)) return -1;
    return 1;
}

mm_result mm_distance_advance(const mm_distance_curve *c, float time, float distance, float dt,
                              float rate_min, float rate_max, float *out_time, float *out_rate)
{
    float dummy;
    if (!out_rate) out_rate = &dummy;
    *out_rate = 0.0f;
    if (!out_time) return MM_ERR_INVALID_ARGUMENT;
    if (!mm__distance_usable(c)) {
        *out_time = 0.0f;
        return MM_ERR_INVALID_ARGUMENT;
    }
    double t0 = mm__distance_into_clip(c, time), T = mm__distance_duration(c);
    *out_time = (float)t0;
    int clamp = clamp_kind(rate_min, rate_max);
    if (!isfinite(time) || clamp < 0 || !(distance >= 0.0f) || !isfinite(distance) || !(dt > 0.0f) ||
        !isfinite(dt))
        return MM_ERR_INVALID_ARGUMENT;
    double rate;
    mm_result r = MM_OK;
    if (c->path_length < 1e-6f) { /* nothing to match: play on */
        rate = 1.0;
        r = MM_ERR_OUT_OF_RANGE;
    } else {
        rate = (mm__distance_time_after(c, t0, distance) - t0) / dt;
    }
    if (clamp) rate = clampd(rate, rate_min, rate_max);
    double t = t0 + rate * dt;
    *out_time = (float)(c->loop ? mm__distance_into_clip(c, t) : clampd(t, 0.0, T));
    *out_rate = (float)(rate < 1e30 ? rate : 1e30); /* finite, whatever dt */
    return r;
}

mm_result mm_distance_match_to_target(const mm_distance_curve *c, int segment, float distance_to_target,
                                      float *out_time)
{
    if (!out_time) return MM_ERR_INVALID_ARGUMENT;
    *out_time = 0.0f;
    if (!mm__distance_usable(c) || segment < 0 || segment >= c->segment_count) return MM_ERR_INVALID_ARGUMENT;
    const int n = c->frame_count;
    const mm_distance_segment *g = &c->segments[segment];
    *out_time = (float)mm__distance_into_clip(c, g->marker_frame / (double)c->fps);
    if (!isfinite(distance_to_target)) return MM_ERR_INVALID_ARGUMENT;
    const double target = -(double)distance_to_target;
#define SEG_D(i) ((double)c->distance[(g->first_frame + (i)) % n])
    double frame;
    int count = g->frame_count;
    if (target <= SEG_D(0)) {
        frame = g->first_frame;
    } else if (target > SEG_D(count - 1)) {
        frame = g->first_frame + count - 1;
    } else { /* the first j with d[j] >= target; d[j - 1] < target */
        int lo = 1, hi = count - 1;
        while (lo < hi) {
            int mid = lo + (hi - lo) / 2;
            if (SEG_D(mid) >= target)
                hi = mid;
            else
                lo = mid + 1;
        }
        double d0 = SEG_D(lo - 1), d1 = SEG_D(lo);
        frame = g->first_frame + lo - 1 + (target - d0) / (d1 - d0);
    }
#undef SEG_D
    *out_time = (float)mm__distance_into_clip(c, frame / c->fps);
    return MM_OK;
}

static mm_result ratio_clamped(double num, double den, float lo, float hi, float *out)
{
    if (!out) return MM_ERR_INVALID_ARGUMENT;
    *out = 1.0f;
    int clamp = clamp_kind(lo, hi);
    if (clamp < 0 || !(num >= 0.0) || !isfinite(num) || !(den >= 0.0) || !isfinite(den))
        return MM_ERR_INVALID_ARGUMENT;
    mm_result r = MM_OK;
    double v;
    if (den < 1e-4) {
        v = 1.0;
        r = MM_ERR_OUT_OF_RANGE;
    } else {
        v = num / den;
    }
    if (clamp) v = clampd(v, lo, hi);
    *out = (float)v;
    return r;
}

mm_result mm_distance_play_rate(float desired_speed, float clip_speed, float rate_min, float rate_max,
                                float *out_rate)
{
    return ratio_clamped(desired_speed, clip_speed, rate_min, rate_max, out_rate);
}

mm_result mm_distance_stride_scale(float desired_speed, float clip_speed, float play_rate, float scale_min,
                                   float scale_max, float *out_scale)
{
    if (!isfinite(play_rate) || !(play_rate >= 0.0f)) {
        if (out_scale) *out_scale = 1.0f;
        return MM_ERR_INVALID_ARGUMENT;
    }
    return ratio_clamped(desired_speed, (double)clip_speed * play_rate, scale_min, scale_max, out_scale);
}
