/* Distance curves: the read-only queries and the validator (the database loader checks every
 * clip's curves with it). See mm/distance_curve.h and docs/distance.md; the builder is in
 * distance_curve_build.c. Nothing here allocates. */
#include <mm/distance_curve.h>

#include <float.h>
#include <math.h>

#include "db/distance_curve_private.h"

int mm__distance_usable(const mm_distance_curve *c)
{
    return c && c->frame_count >= 2 && c->fps > 0.0f && isfinite(c->fps) && c->travelled && c->distance &&
           c->segments && c->segment_count >= 1 && isfinite(c->path_length) && c->path_length >= 0.0f;
}

mm_result mm_distance_curve_validate(const mm_distance_curve *c, mm_error *err)
{
    if (!mm__distance_usable(c))
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "distance curve: bad sizes or arrays");
    const int n = c->frame_count;
    if (n > MM__DISTANCE_MAX_FRAMES || c->segment_count > n)
        return mm_error_set(err, MM_ERR_LIMIT, 0, 0, "distance curve: %d frames, %d segments", n,
                            c->segment_count);
    for (int i = 0; i < n; ++i) {
        if (!isfinite(c->travelled[i]) || !isfinite(c->distance[i]))
            return mm_error_set(err, MM_ERR_BAD_NUMBER, 0, 0, "distance curve: frame %d: non-finite value",
                                i);
        if (i > 0 && c->travelled[i] < c->travelled[i - 1])
            return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0,
                                "distance curve: frame %d: travelled decreases", i);
    }
    if (c->travelled[0] != 0.0f || c->path_length < c->travelled[n - 1])
        return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0,
                            "distance curve: travelled must run from 0 to path_length");
    int covered = 0, next = c->segments[0].first_frame;
    if (!c->loop && next != 0)
        return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0,
                            "distance curve: segment 0 must start at frame 0");
    for (int m = 0; m < c->segment_count; ++m) {
        const mm_distance_segment *g = &c->segments[m];
        if (g->first_frame != next || g->frame_count < 1 || g->first_frame < 0 || g->first_frame >= n ||
            (!c->loop && g->first_frame + g->frame_count > n))
            return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "distance curve: segment %d: bad frames", m);
        int im = (g->marker_frame - g->first_frame + n) % n;
        if (g->marker_frame < 0 || g->marker_frame >= n || im >= g->frame_count ||
            g->kind < MM_DISTANCE_NONE || g->kind > MM_DISTANCE_PIVOT || !isfinite(g->marker_travelled))
            return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "distance curve: segment %d: bad marker", m);
        for (int i = 1; i < g->frame_count; ++i)
            if (c->distance[(g->first_frame + i) % n] < c->distance[(g->first_frame + i - 1) % n])
                return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0,
                                    "distance curve: segment %d: distance decreases", m);
        covered += g->frame_count;
        next = (g->first_frame + g->frame_count) % n;
    }
    if (covered != n || next != c->segments[0].first_frame)
        return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "distance curve: segments cover %d of %d frames",
                            covered, n);
    return MM_OK;
}

double mm__distance_duration(const mm_distance_curve *c)
{
    return (double)(c->loop ? c->frame_count : c->frame_count - 1) / c->fps;
}

float mm_distance_duration(const mm_distance_curve *c)
{
    return mm__distance_usable(c) ? (float)mm__distance_duration(c) : 0.0f;
}

double mm__distance_into_clip(const mm_distance_curve *c, double t)
{
    double T = mm__distance_duration(c);
    if (!isfinite(t)) return 0.0;
    if (!c->loop) return t < 0.0 ? 0.0 : t > T ? T : t;
    double r = t - floor(t / T) * T;
    if (!(r >= 0.0) || (float)r >= (float)T) r = 0.0;
    return r;
}

/* Unwrapped travelled path at time t (double). */
static double travelled_at(const mm_distance_curve *c, double t)
{
    const int n = c->frame_count;
    const double T = mm__distance_duration(c), L = c->path_length;
    double base = 0.0;
    if (c->loop) {
        double k = floor(t / T);
        base = k * L;
        t -= k * T;
    } else {
        t = t < 0.0 ? 0.0 : t > T ? T : t;
    }
    double f = t * c->fps;
    int i = (int)floor(f);
    if (i < 0) i = 0;
    if (!c->loop && i >= n - 1) return c->travelled[n - 1];
    if (i > n - 1) i = n - 1;
    double a = f - i, v0 = c->travelled[i], v1 = i + 1 < n ? c->travelled[i + 1] : L;
    return base + v0 + (v1 - v0) * a;
}

float mm_distance_travelled(const mm_distance_curve *c, float t)
{
    if (!mm__distance_usable(c) || !isfinite(t)) return 0.0f;
    return (float)travelled_at(c, t);
}

static int segment_of_frame(const mm_distance_curve *c, int f)
{
    const int n = c->frame_count;
    for (int m = 0; m < c->segment_count; ++m) {
        const mm_distance_segment *g = &c->segments[m];
        if ((f - g->first_frame + n) % n < g->frame_count) return m;
    }
    return 0;
}

int mm_distance_segment_at(const mm_distance_curve *c, float t)
{
    if (!mm__distance_usable(c) || !isfinite(t)) return 0;
    int f = (int)floor(mm__distance_into_clip(c, t) * c->fps);
    if (f >= c->frame_count) f = c->frame_count - 1;
    return segment_of_frame(c, f);
}

float mm_distance_signed(const mm_distance_curve *c, float t)
{
    if (!mm__distance_usable(c) || !isfinite(t)) return 0.0f;
    const int n = c->frame_count;
    double tc = mm__distance_into_clip(c, t);
    int f = (int)floor(tc * c->fps);
    if (f >= n) f = n - 1;
    const mm_distance_segment *g = &c->segments[segment_of_frame(c, f)];
    int i = (f - g->first_frame + n) % n;
    double v = travelled_at(c, tc) + (g->first_frame + i >= n ? c->path_length : 0.0);
    return (float)(v - g->marker_travelled);
}

/* The seed's loop: fixed steps (here: to the next frame, so each step is linear and the last
 * fraction exact), accumulating the clip's distance until the character's is reached. */
double mm__distance_time_after(const mm_distance_curve *c, double t, double dist)
{
    const int n = c->frame_count;
    const double T = mm__distance_duration(c), L = c->path_length;
    if (!(dist > 0.0)) return t;
    if (c->loop && L > 1e-9) { /* whole loops at once */
        double whole = floor(dist / L);
        t += whole * T;
        dist -= whole * L;
        if (!(dist > 0.0)) return t;
    }
    double acc = 0.0, here = travelled_at(c, t);
    for (int iter = 0; iter < n + 4; ++iter) {
        if (!c->loop && t >= T) return T; /* one-shots stop at the last frame */
        double next = (floor(t * c->fps + 1e-9) + 1.0) / c->fps;
        if (!c->loop && next > T) next = T;
        double there = travelled_at(c, next), step = there - here;
        if (acc + step < dist) { /* not there yet: a whole step (also where the root stands) */
            acc += step;
            t = next;
            here = there;
            continue;
        }
        return t + (dist - acc) / step * (next - t); /* step > 0: acc < dist <= acc + step */
    }
    return t;
}

float mm_distance_time_after(const mm_distance_curve *c, float time, float distance)
{
    if (!mm__distance_usable(c) || !isfinite(time) || !isfinite(distance)) return time;
    double t = c->loop ? (double)time : mm__distance_into_clip(c, time);
    double r = mm__distance_time_after(c, t, distance);
    return r < FLT_MAX ? (float)r : FLT_MAX; /* unwrapped: very long distances in loops */
}

float mm_distance_clip_speed(const mm_distance_curve *c)
{
    if (!mm__distance_usable(c)) return 0.0f;
    return (float)(c->path_length / mm__distance_duration(c));
}
