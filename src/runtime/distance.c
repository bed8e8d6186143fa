/* Distance matching (curves, advance, match to target, play rate), stop and pivot prediction from
 * the trajectory's velocity spring, stride warping and orientation warping. See mm/distance.h
 * and docs/distance.md. Everything below the curve builder runs per tick and never allocates. */
#include <mm/distance.h>

#include <float.h>
#include <math.h>
#include <string.h>

#include <mm/spring.h>

#define MAX_FRAMES (1 << 28)

static int finite3(mm_vec3 v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z); }

/* ---- curves ------------------------------------------------------------------------------ */

/* The ground step from frame i to i + 1 (x, z). */
static void step_vector(const mm_distance_desc *d, int i, double *dx, double *dz)
{
    int k = d->components, zi = k == 3 ? 2 : 1;
    *dx = (double)d->positions[(size_t)(i + 1) * k] - d->positions[(size_t)i * k];
    *dz = (double)d->positions[(size_t)(i + 1) * k + zi] - d->positions[(size_t)i * k + zi];
}

static double clampd(double x, double lo, double hi) { return x < lo ? lo : x > hi ? hi : x; }

/* A loop's missing step n - 1 (from the last frame to the first) from the steps around it: the
 * cubic through steps n - 3, n - 2 (before) and 0, 1 (after), exact where the positions are a
 * cubic in time (steady motion, or slowing to rest at the wrap); the mean of the two neighbours
 * in loops of fewer than 4 frames. */
static double wrap_estimate(const double *v, int n)
{
    if (n < 4) return 0.5 * (v[0] + v[n - 2]);
    return (-v[n - 3] + 4.0 * v[n - 2] + 4.0 * v[0] - v[1]) / 6.0;
}

typedef struct marker {
    int frame, run_end, kind;
} marker;

/* Build-time scratch: step lengths, step vectors, speeds. */
typedef struct scratch {
    double *step; /* [n]: step i from frame i to i + 1; a loop's step n - 1 is the wrap */
    double *sx, *sz;
    double *speed; /* [n] m/s */
} scratch;

/* Sum of the step vectors from step `from` for `count` steps (cyclic in loops, clipped in
 * one-shots). */
static void displacement(const scratch *s, int n, int loop, int from, int count, double *x, double *z)
{
    *x = *z = 0.0;
    int steps = loop ? n : n - 1;
    for (int k = 0; k < count; ++k) {
        int i = from + k;
        if (loop)
            i = ((i % steps) + steps) % steps;
        else if (i < 0 || i >= steps)
            continue;
        *x += s->sx[i];
        *z += s->sz[i];
    }
}

static int classify(const scratch *s, int n, int loop, double fps, double stop_speed, int frame)
{
    int w = (int)lround(0.2 * fps);
    if (w < 1) w = 1;
    double bx, bz, ax, az;
    displacement(s, n, loop, frame - w, w, &bx, &bz);
    displacement(s, n, loop, frame, w, &ax, &az);
    /* arriving at a mean speed of at least half the threshold; leaving faster than the
     * threshold: a root that only sways or shuffles after coming to rest has stopped */
    double least = 0.5 * stop_speed * w / fps, leave = stop_speed * w / fps;
    double lb = sqrt(bx * bx + bz * bz), la = sqrt(ax * ax + az * az);
    if (lb > least && la > leave && bx * ax + bz * az < 0.0) return MM_DISTANCE_PIVOT;
    return MM_DISTANCE_STOP;
}

/* The marker of the slow run [a, b] (indices mod n in loops). */
static marker run_marker(const scratch *s, int n, int loop, double fps, double stop_speed, int a, int b)
{
    double least = INFINITY;
    for (int i = a; i <= b; ++i) least = fmin(least, s->speed[i % n]);
    int f = a;
    while (f < b && !(s->speed[f % n] <= least + 0.25 * stop_speed)) ++f;
    while (f < b && s->speed[(f + 1) % n] < s->speed[f % n]) ++f; /* on while it keeps falling */
    marker m;
    m.frame = f % n;
    m.run_end = b % n;
    m.kind = classify(s, n, loop, fps, stop_speed, m.frame);
    return m;
}

/* Finds the stop and pivot markers in frame order. Returns their count; markers may be NULL. */
static int find_markers(const scratch *s, int n, int loop, double fps, double stop_speed, marker *markers)
{
    int count = 0;
    if (!loop) {
        for (int i = 0; i < n;) {
            if (!(s->speed[i] < stop_speed)) {
                ++i;
                continue;
            }
            int a = i;
            while (i + 1 < n && s->speed[i + 1] < stop_speed) ++i;
            int b = i++;
            if (a == 0) continue; /* starts from rest: not a stop */
            if (markers) markers[count] = run_marker(s, n, loop, fps, stop_speed, a, b);
            ++count;
        }
        return count;
    }
    int fast = -1;
    for (int i = 0; i < n && fast < 0; ++i)
        if (!(s->speed[i] < stop_speed)) fast = i;
    if (fast < 0) return 0; /* at rest throughout */
    for (int k = 1; k < n;) {
        int i = fast + k;
        if (!(s->speed[i % n] < stop_speed)) {
            ++k;
            continue;
        }
        int a = i;
        while (k + 1 < n && s->speed[(fast + k + 1) % n] < stop_speed) ++k;
        int b = fast + k++;
        if (markers) markers[count] = run_marker(s, n, loop, fps, stop_speed, a, b);
        ++count;
    }
    if (markers && count > 1) { /* frame order: start with the smallest marker frame */
        int first = 0;
        for (int k = 1; k < count; ++k)
            if (markers[k].frame < markers[first].frame) first = k;
        for (int r = 0; r < first; ++r) {
            marker m = markers[0];
            memmove(markers, markers + 1, (size_t)(count - 1) * sizeof *markers);
            markers[count - 1] = m;
        }
    }
    return count;
}

mm_result mm_distance_curve_build(mm_distance_curve *c, const mm_distance_desc *d, mm_error *err)
{
    if (!c) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "distance curve: no output");
    memset(c, 0, sizeof *c);
    if (!d || !d->positions)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "distance curve: no positions");
    if (d->components != 2 && d->components != 3)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                            "distance curve: components must be 2 or 3, not %d", d->components);
    if (d->frame_count < 2 || d->frame_count > MAX_FRAMES)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "distance curve: %d frames (2 .. %d)",
                            d->frame_count, MAX_FRAMES);
    if (!(d->fps > 0.0f) || !isfinite(d->fps))
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "distance curve: fps must be > 0");
    if (!(d->stop_speed >= 0.0f) || !isfinite(d->stop_speed))
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "distance curve: stop_speed must be >= 0");
    if (!(d->loop_step >= 0.0f) || !isfinite(d->loop_step))
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "distance curve: loop_step must be >= 0");
    const int n = d->frame_count, k = d->components;
    for (int i = 0; i < n * k; ++i)
        if (!isfinite(d->positions[i]))
            return mm_error_set(err, MM_ERR_BAD_NUMBER, 0, 0, "distance curve: frame %d: non-finite position",
                                i / k);
    const int loop = d->loop != 0;
    const double fps = d->fps,
                 stop_speed = d->stop_speed > 0.0f ? d->stop_speed : MM_DISTANCE_STOP_SPEED_DEFAULT;

    scratch s;
    double *tmp = (double *)mm_alloc_array(d->allocator, (size_t)n * 4, sizeof(double));
    if (!tmp) return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "distance curve: out of memory");
    s.step = tmp;
    s.sx = tmp + n;
    s.sz = tmp + 2 * (size_t)n;
    s.speed = tmp + 3 * (size_t)n;
    for (int i = 0; i + 1 < n; ++i) {
        step_vector(d, i, &s.sx[i], &s.sz[i]);
        s.step[i] = sqrt(s.sx[i] * s.sx[i] + s.sz[i] * s.sz[i]);
    }
    if (loop) { /* the wrap step: given, or interpolated from the steps on both sides */
        s.sx[n - 1] = wrap_estimate(s.sx, n);
        s.sz[n - 1] = wrap_estimate(s.sz, n);
        double w = wrap_estimate(s.step, n), hi = 0.0; /* kept within the neighbours' range */
        for (int j = 0; j < n - 1 && j < 2; ++j) hi = fmax(hi, fmax(s.step[j], s.step[n - 2 - j]));
        s.step[n - 1] = d->loop_step > 0.0f ? d->loop_step : clampd(w, 0.0, hi);
    }
    for (int i = 0; i < n; ++i) {
        if (loop)
            s.speed[i] = 0.5 * (s.step[(i + n - 1) % n] + s.step[i]) * fps;
        else if (i == 0)
            s.speed[i] = s.step[0] * fps;
        else if (i == n - 1)
            s.speed[i] = s.step[n - 2] * fps;
        else
            s.speed[i] = 0.5 * (s.step[i - 1] + s.step[i]) * fps;
    }

    int marker_count = find_markers(&s, n, loop, fps, stop_speed, NULL);
    int segment_count = marker_count > 0 ? marker_count : 1;
    size_t floats = 2 * (size_t)n, bytes = floats * sizeof(float) +
                                           (size_t)segment_count * sizeof(mm_distance_segment) +
                                           (size_t)marker_count * sizeof(marker);
    unsigned char *block = (unsigned char *)mm_alloc(d->allocator, bytes);
    if (!block) {
        mm_free(d->allocator, tmp);
        return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "distance curve: out of memory");
    }
    float *travelled = (float *)block, *distance = travelled + n;
    mm_distance_segment *segments = (mm_distance_segment *)(distance + n);
    marker *markers = (marker *)(segments + segment_count); /* scratch at the end of the block */
    find_markers(&s, n, loop, fps, stop_speed, markers);

    double *trav = s.sx; /* reuse: cumulative path in double */
    trav[0] = 0.0;
    for (int i = 1; i < n; ++i) trav[i] = trav[i - 1] + s.step[i - 1];
    double length = trav[n - 1] + (loop ? s.step[n - 1] : 0.0);
    for (int i = 0; i < n; ++i) travelled[i] = (float)trav[i];

    if (marker_count == 0) {
        segments[0].first_frame = 0;
        segments[0].frame_count = n;
        segments[0].marker_frame = 0;
        segments[0].kind = MM_DISTANCE_NONE;
    } else {
        for (int m = 0; m < marker_count; ++m) {
            mm_distance_segment *g = &segments[m];
            int first, last;
            if (!loop) {
                first = m == 0 ? 0 : markers[m - 1].run_end + 1;
                last = m == marker_count - 1 ? n - 1 : markers[m].run_end;
            } else {
                first = (markers[(m + marker_count - 1) % marker_count].run_end + 1) % n;
                last = markers[m].run_end;
            }
            g->first_frame = first;
            g->frame_count = loop && marker_count == 1 ? n : ((last - first + n) % n) + 1;
            g->marker_frame = markers[m].frame;
            g->kind = markers[m].kind;
        }
        if (loop && marker_count > 1) { /* frame order: the segment holding frame 0 goes last */
            int lowest = 0;
            for (int m = 1; m < marker_count; ++m)
                if (segments[m].first_frame < segments[lowest].first_frame) lowest = m;
            for (int r = 0; r < lowest; ++r) {
                mm_distance_segment g = segments[0];
                memmove(segments, segments + 1, (size_t)(marker_count - 1) * sizeof *segments);
                segments[marker_count - 1] = g;
            }
        }
    }
    for (int m = 0; m < segment_count; ++m) {
        mm_distance_segment *g = &segments[m];
        int im = (g->marker_frame - g->first_frame + n) % n;
        double mark = trav[g->marker_frame] + (g->first_frame + im >= n ? length : 0.0);
        g->marker_travelled = (float)mark;
        for (int i = 0; i < g->frame_count; ++i) {
            int f = (g->first_frame + i) % n;
            distance[f] = (float)(trav[f] + (g->first_frame + i >= n ? length : 0.0) - mark);
        }
    }
    mm_free(d->allocator, tmp);

    c->frame_count = n;
    c->loop = loop;
    c->fps = d->fps;
    c->path_length = (float)length;
    c->segment_count = segment_count;
    c->travelled = travelled;
    c->distance = distance;
    c->segments = segments;
    c->block = block;
    if (d->allocator) c->allocator = *d->allocator;
    return MM_OK;
}

void mm_distance_curve_free(mm_distance_curve *c)
{
    if (!c) return;
    if (c->block) mm_free(c->allocator.alloc ? &c->allocator : NULL, c->block);
    memset(c, 0, sizeof *c);
}

/* The quick check every runtime function makes. */
static int usable(const mm_distance_curve *c)
{
    return c && c->frame_count >= 2 && c->fps > 0.0f && isfinite(c->fps) && c->travelled && c->distance &&
           c->segments && c->segment_count >= 1 && isfinite(c->path_length) && c->path_length >= 0.0f;
}

mm_result mm_distance_curve_validate(const mm_distance_curve *c, mm_error *err)
{
    if (!usable(c))
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "distance curve: bad sizes or arrays");
    const int n = c->frame_count;
    if (n > MAX_FRAMES || c->segment_count > n)
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

static double duration_of(const mm_distance_curve *c)
{
    return (double)(c->loop ? c->frame_count : c->frame_count - 1) / c->fps;
}

float mm_distance_duration(const mm_distance_curve *c) { return usable(c) ? (float)duration_of(c) : 0.0f; }

/* A finite time into the clip: [0, duration) for loops, [0, duration] for one-shots. */
static double into_clip(const mm_distance_curve *c, double t)
{
    double T = duration_of(c);
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
    const double T = duration_of(c), L = c->path_length;
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
    if (!usable(c) || !isfinite(t)) return 0.0f;
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
    if (!usable(c) || !isfinite(t)) return 0;
    int f = (int)floor(into_clip(c, t) * c->fps);
    if (f >= c->frame_count) f = c->frame_count - 1;
    return segment_of_frame(c, f);
}

float mm_distance_signed(const mm_distance_curve *c, float t)
{
    if (!usable(c) || !isfinite(t)) return 0.0f;
    const int n = c->frame_count;
    double tc = into_clip(c, t);
    int f = (int)floor(tc * c->fps);
    if (f >= n) f = n - 1;
    const mm_distance_segment *g = &c->segments[segment_of_frame(c, f)];
    int i = (f - g->first_frame + n) % n;
    double v = travelled_at(c, tc) + (g->first_frame + i >= n ? c->path_length : 0.0);
    return (float)(v - g->marker_travelled);
}

/* ---- distance matching -------------------------------------------------------------------- */

/* The seed's loop: fixed steps (here: to the next frame, so each step is linear and the last
 * fraction exact), accumulating the clip's distance until the character's is reached. */
static double time_after(const mm_distance_curve *c, double t, double dist)
{
    const int n = c->frame_count;
    const double T = duration_of(c), L = c->path_length;
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
    if (!usable(c) || !isfinite(time) || !isfinite(distance)) return time;
    double t = c->loop ? (double)time : into_clip(c, time);
    double r = time_after(c, t, distance);
    return r < FLT_MAX ? (float)r : FLT_MAX; /* unwrapped: very long distances in loops */
}

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
    if (!usable(c)) {
        *out_time = 0.0f;
        return MM_ERR_INVALID_ARGUMENT;
    }
    double t0 = into_clip(c, time), T = duration_of(c);
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
        rate = (time_after(c, t0, distance) - t0) / dt;
    }
    if (clamp) rate = clampd(rate, rate_min, rate_max);
    double t = t0 + rate * dt;
    *out_time = (float)(c->loop ? into_clip(c, t) : clampd(t, 0.0, T));
    *out_rate = (float)(rate < 1e30 ? rate : 1e30); /* finite, whatever dt */
    return r;
}

mm_result mm_distance_match_to_target(const mm_distance_curve *c, int segment, float distance_to_target,
                                      float *out_time)
{
    if (!out_time) return MM_ERR_INVALID_ARGUMENT;
    *out_time = 0.0f;
    if (!usable(c) || segment < 0 || segment >= c->segment_count) return MM_ERR_INVALID_ARGUMENT;
    const int n = c->frame_count;
    const mm_distance_segment *g = &c->segments[segment];
    *out_time = (float)into_clip(c, g->marker_frame / (double)c->fps);
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
    *out_time = (float)into_clip(c, frame / c->fps);
    return MM_OK;
}

float mm_distance_clip_speed(const mm_distance_curve *c)
{
    if (!usable(c)) return 0.0f;
    return (float)(c->path_length / duration_of(c));
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

/* ---- prediction ------------------------------------------------------------------------- */

/* In the spring's own time u = y t: v(u) = g + (j0 + k u) e^(-u), k = j1 / y. */
typedef struct vspring {
    double g[3], j0[3], k[3], y;
} vspring;

static double vs_speed(const vspring *s, double u)
{
    double e = exp(-u), q = 0.0;
    for (int i = 0; i < 3; ++i) {
        double v = s->g[i] + (s->j0[i] + s->k[i] * u) * e;
        q += v * v;
    }
    return sqrt(q);
}

/* Integral of the speed over u in [a, b]: 8-point Gauss-Legendre on panels that double in width
 * (0-1, 1-2, 2-4, ... 32-48), as the speed decays like e^-u; far below float rounding. */
static double vs_path(const vspring *s, double a, double b)
{
    static const double x[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                                0.9602898564975363};
    static const double w[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
                                0.1012285362903763};
    static const double edge[] = {0.0, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 48.0};
    double sum = 0.0;
    for (int p = 0; p + 1 < (int)(sizeof edge / sizeof edge[0]); ++p) {
        double lo = edge[p] > a ? edge[p] : a, hi = edge[p + 1] < b ? edge[p + 1] : b;
        if (!(hi > lo)) continue;
        double mid = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
        for (int k = 0; k < 4; ++k)
            sum += half * w[k] * (vs_speed(s, mid - half * x[k]) + vs_speed(s, mid + half * x[k]));
    }
    return sum;
}

#define HORIZON 48.0 /* u = y t; (1 + u) e^-u is below 1e-19 there */

static void vs_make(vspring *s, mm_vec3 v, mm_vec3 a, mm_vec3 g, double y)
{
    const double vv[3] = {v.x, v.y, v.z}, av[3] = {a.x, a.y, a.z}, gv[3] = {g.x, g.y, g.z};
    s->y = y;
    for (int i = 0; i < 3; ++i) {
        s->g[i] = gv[i];
        s->j0[i] = vv[i] - gv[i];
        s->k[i] = (av[i] + s->j0[i] * y) / y;
    }
}

/* Offset travelled by time t (seconds) from the closed form of mm_spring_velocity_update. */
static mm_vec3 vs_offset(const vspring *s, double t)
{
    double y = s->y, e = exp(-y * t), o[3];
    for (int i = 0; i < 3; ++i) {
        double j1 = s->k[i] * y;
        o[i] = s->g[i] * t + s->j0[i] * (1.0 - e) / y + j1 * ((1.0 - e) / (y * y) - t * e / y);
    }
    return mm_vec3_make((float)o[0], (float)o[1], (float)o[2]);
}

static void prediction_zero(mm_distance_prediction *out)
{
    out->found = 0;
    out->offset = mm_vec3_make(0, 0, 0);
    out->distance = 0.0f;
    out->time = 0.0f;
}

/* Numbers too large for floats overflow to infinity: such a prediction is refused as a whole. */
static mm_result prediction_checked(mm_result r, mm_distance_prediction *out)
{
    if (r == MM_OK && (!finite3(out->offset) || !isfinite(out->distance) || !isfinite(out->time))) {
        prediction_zero(out);
        return MM_ERR_OUT_OF_RANGE;
    }
    return r;
}

static mm_result predict_stop(mm_vec3 velocity, mm_vec3 acceleration, float halflife, float rest_speed,
                              mm_distance_prediction *out)
{
    if (!out) return MM_ERR_INVALID_ARGUMENT;
    prediction_zero(out);
    if (!finite3(velocity) || !finite3(acceleration) || !(halflife >= 0.0f) || !isfinite(halflife) ||
        !(rest_speed >= 0.0f) || !isfinite(rest_speed))
        return MM_ERR_INVALID_ARGUMENT;
    double rest = rest_speed > 0.0f ? rest_speed : MM_DISTANCE_REST_SPEED_DEFAULT;
    double y = mm_spring_damping(halflife);
    if (!isfinite(y)) return MM_OK; /* no spring: at rest at once */
    vspring s;
    vs_make(&s, velocity, acceleration, mm_vec3_make(0, 0, 0), y);
    double o[3];
    for (int i = 0; i < 3; ++i) o[i] = (s.j0[i] + s.k[i]) / y; /* j0 / y + j1 / y^2 */
    out->offset = mm_vec3_make((float)o[0], (float)o[1], (float)o[2]);
    /* the path: split where |j0 + k u| is least (the only place the speed can touch zero) */
    double kk = s.k[0] * s.k[0] + s.k[1] * s.k[1] + s.k[2] * s.k[2];
    double us = kk > 0.0 ? -(s.j0[0] * s.k[0] + s.j0[1] * s.k[1] + s.j0[2] * s.k[2]) / kk : 0.0;
    double path = us > 0.0 && us < HORIZON ? vs_path(&s, 0.0, us) + vs_path(&s, us, HORIZON)
                                           : vs_path(&s, 0.0, HORIZON);
    out->distance = (float)(path / y);
    /* the time: the last moment the speed is at least rest. |j0 + k u|^2 = |j0 + k us|^2 +
     * |k|^2 (u - us)^2, so past u0 = us + 1 the speed falls all the way (its log falls by more
     * than it rises); before u0 the samples are searched from the end. */
    double u0 = us + 1.0 > 0.0 ? us + 1.0 : 0.0, lo, hi;
    if (u0 < HORIZON && vs_speed(&s, u0) >= rest) {
        lo = u0;
        hi = HORIZON;
    } else {
        const double h = 0.05;
        int last = -1;
        for (int i = (int)(fmin(u0, HORIZON) / h) + 1; i >= 0 && last < 0; --i)
            if (vs_speed(&s, i * h) >= rest) last = i;
        if (last < 0) return MM_OK; /* at rest already */
        lo = last * h;
        hi = lo + h;
    }
    for (int it = 0; it < 60; ++it) {
        double mid = 0.5 * (lo + hi);
        if (vs_speed(&s, mid) >= rest)
            lo = mid;
        else
            hi = mid;
    }
    out->found = 1;
    out->time = (float)(0.5 * (lo + hi) / y);
    return MM_OK;
}

mm_result mm_distance_predict_stop(mm_vec3 velocity, mm_vec3 acceleration, float halflife, float rest_speed,
                                   mm_distance_prediction *out)
{
    return prediction_checked(predict_stop(velocity, acceleration, halflife, rest_speed, out), out);
}

static mm_result predict_pivot(mm_vec3 velocity, mm_vec3 acceleration, mm_vec3 target_velocity,
                               float halflife, mm_distance_prediction *out)
{
    if (!out) return MM_ERR_INVALID_ARGUMENT;
    prediction_zero(out);
    if (!finite3(velocity) || !finite3(acceleration) || !finite3(target_velocity) || !(halflife >= 0.0f) ||
        !isfinite(halflife))
        return MM_ERR_INVALID_ARGUMENT;
    double gl = mm_vec3_length(target_velocity);
    if (!(gl > 1e-6)) return MM_OK;
    double gd[3] = {target_velocity.x / gl, target_velocity.y / gl, target_velocity.z / gl};
    double along0 = velocity.x * gd[0] + velocity.y * gd[1] + velocity.z * gd[2];
    if (!(along0 < 0.0)) return MM_OK; /* not moving against the target */
    double y = mm_spring_damping(halflife);
    out->found = 1;
    if (!isfinite(y)) return MM_OK; /* no spring: turns at once, here */
    vspring s;
    vs_make(&s, velocity, acceleration, target_velocity, y);
    double a = s.j0[0] * gd[0] + s.j0[1] * gd[1] + s.j0[2] * gd[2];
    double b = s.k[0] * gd[0] + s.k[1] * gd[1] + s.k[2] * gd[2];
#define ALONG(u) (gl + (a + b * (u)) * exp(-(u)))
    /* one crossing: (a + b u) e^-u has one extremum; the first sample at or above zero */
    const int steps = 960;
    const double h = HORIZON / steps;
    int i = 1;
    while (i < steps && ALONG(i * h) < 0.0) ++i;
    double lo = (i - 1) * h, hi = i * h;
    for (int it = 0; it < 60; ++it) {
        double mid = 0.5 * (lo + hi);
        if (ALONG(mid) < 0.0)
            lo = mid;
        else
            hi = mid;
    }
#undef ALONG
    double u = 0.5 * (lo + hi);
    out->time = (float)(u / y);
    out->offset = vs_offset(&s, u / y);
    out->distance = (float)(vs_path(&s, 0.0, u) / y);
    return MM_OK;
}

mm_result mm_distance_predict_pivot(mm_vec3 velocity, mm_vec3 acceleration, mm_vec3 target_velocity,
                                    float halflife, mm_distance_prediction *out)
{
    return prediction_checked(predict_pivot(velocity, acceleration, target_velocity, halflife, out), out);
}

mm_result mm_distance_predict_trajectory(const mm_trajectory *t, const mm_input *in, float rest_speed,
                                         mm_distance_prediction *stop, mm_distance_prediction *pivot)
{
    if (stop) prediction_zero(stop);
    if (pivot) prediction_zero(pivot);
    if (!t) return MM_ERR_INVALID_ARGUMENT;
    int g = in && (int)in->gait >= 0 && in->gait < MM_GAIT_COUNT ? (int)in->gait : MM_GAIT_WALK;
    float halflife = t->desc.gaits[g].velocity_halflife;
    mm_result r = MM_OK;
    if (stop) r = mm_distance_predict_stop(t->velocity, t->acceleration, halflife, rest_speed, stop);
    if (pivot && r == MM_OK) {
        mm_vec3 target;
        mm_trajectory_desired(t, in, &target, NULL);
        r = mm_distance_predict_pivot(t->velocity, t->acceleration, target, halflife, pivot);
    }
    return r;
}

/* ---- warping ----------------------------------------------------------------------------- */

static int finite_leg(const mm_leg_pose *l)
{
    return finite3(l->hip) && finite3(l->knee) && finite3(l->foot);
}

static mm_vec3 finite_or_zero(mm_vec3 v)
{
    return mm_vec3_make(isfinite(v.x) ? v.x : 0.0f, isfinite(v.y) ? v.y : 0.0f, isfinite(v.z) ? v.z : 0.0f);
}

/* The unchanged leg, as the output of a call that could not warp (non-finite parts zeroed). */
static void leg_identity(const mm_leg_pose *leg, mm_leg_warp *out)
{
    out->pose.hip = finite_or_zero(leg->hip);
    out->pose.knee = finite_or_zero(leg->knee);
    out->pose.foot = finite_or_zero(leg->foot);
    out->target = out->pose.foot;
    out->thigh = mm_quat_identity();
    out->shin = mm_quat_identity();
}

typedef struct dvec {
    double x, y, z;
} dvec;
static dvec dv(mm_vec3 v)
{
    dvec r = {v.x, v.y, v.z};
    return r;
}
static dvec dsub(dvec a, dvec b)
{
    dvec r = {a.x - b.x, a.y - b.y, a.z - b.z};
    return r;
}
static dvec dadd(dvec a, dvec b)
{
    dvec r = {a.x + b.x, a.y + b.y, a.z + b.z};
    return r;
}
static dvec dscale(dvec a, double s)
{
    dvec r = {a.x * s, a.y * s, a.z * s};
    return r;
}

static dvec dcross(dvec a, dvec b)
{
    return (dvec){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
static double ddot(dvec a, dvec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static double dlen(dvec a) { return sqrt(ddot(a, a)); }
static mm_vec3 fv(dvec a) { return mm_vec3_make((float)a.x, (float)a.y, (float)a.z); }

/* The longest the leg may reach: max_extension of its length, or as far as it reaches now. */
static double leg_reach(double l1, double l2, double now, double max_extension)
{
    double r = max_extension * (l1 + l2);
    if (now > r) r = now;
    return r < l1 + l2 ? r : l1 + l2;
}

static int bad_extension(float e) { return !isfinite(e) || e < 0.0f || e > 1.0f || (e > 0.0f && e < 0.1f); }

mm_result mm_warp_leg_ik(const mm_leg_pose *leg, mm_vec3 target, mm_vec3 pole, float max_extension,
                         mm_leg_warp *out)
{
    if (!out) return MM_ERR_INVALID_ARGUMENT;
    if (!leg) {
        memset(out, 0, sizeof *out);
        out->thigh = out->shin = mm_quat_identity();
        return MM_ERR_INVALID_ARGUMENT;
    }
    leg_identity(leg, out);
    if (!finite_leg(leg) || !finite3(target) || !finite3(pole) || bad_extension(max_extension))
        return MM_ERR_INVALID_ARGUMENT;
    double ext = max_extension > 0.0f ? max_extension : MM_WARP_MAX_EXTENSION_DEFAULT;
    dvec hip = dv(leg->hip), knee = dv(leg->knee), foot = dv(leg->foot), tg = dv(target);
    double l1 = dlen(dsub(knee, hip)), l2 = dlen(dsub(foot, knee)), now = dlen(dsub(foot, hip));
    if (l1 < 1e-6 || l2 < 1e-6) return MM_ERR_INVALID_ARGUMENT;
    double rmax = leg_reach(l1, l2, now, ext), rmin = fabs(l1 - l2);
    if (now < rmin) rmin = now;
    dvec d = dsub(tg, hip);
    double len = dlen(d);
    dvec u;
    if (len > 1e-9)
        u = dscale(d, 1.0 / len);
    else if (now > 1e-9)
        u = dscale(dsub(foot, hip), 1.0 / now);
    else
        u = (dvec){0.0, -1.0, 0.0};
    len = clampd(len, rmin, rmax);
    /* the knee: the animated leg swung rigidly onto the new hip-target axis (the smallest turn),
     * so that the knee keeps its side however close the new axis passes to it (the knee's side of
     * that axis flipped from one tick to the next: knee pops of 20 cm); where the leg must bend
     * more than it does, the extra bend goes to the pole's side. A nearly straight leg's own
     * plane is noise that flips as the animated leg passes straight (the knee jumped 19 cm in
     * one tick on the built-in set's demo), so it only carries the bend the animation has. A
     * target at the foot leaves the leg as it is, unless it is nearly straight and bent against
     * the pole. */
    dvec kh = dsub(knee, hip), fh = dsub(foot, hip);
    dvec swung = dv(mm_quat_rotate(mm_quat_between(fv(fh), fv(u)), fv(kh)));
    dvec n = dsub(swung, dscale(u, ddot(swung, u))), p = dv(pole);
    p = dsub(p, dscale(u, ddot(p, u)));
    double pl = dlen(p);
    if (pl > 1e-9 && now > 1e-9) {
        /* a bend against the pole is the animation's only while the leg is clearly bent; as it
         * straightens that part fades (fully dropped from a sine of 0 between thigh and hip-foot
         * line, kept from 0.1, about 6 degrees) */
        double back = ddot(n, p) / pl, bent = dlen(dcross(kh, fh)) / (l1 * now);
        if (back < 0.0) n = dsub(n, dscale(p, back / pl * clampd(1.0 - bent / 0.1, 0.0, 1.0)));
    }
    double have = dlen(n);
    double a = len > 1e-12 ? (l1 * l1 - l2 * l2 + len * len) / (2.0 * len) : 0.0;
    double h2 = l1 * l1 - a * a, h = h2 > 0.0 ? sqrt(h2) : 0.0;
    if (pl > 1e-9 && h > have) n = dadd(n, dscale(p, (h - have) / pl));
    if (dlen(n) < 1e-9 * l1) {
        dvec axis = fabs(u.x) < 0.9 ? (dvec){1.0, 0.0, 0.0} : (dvec){0.0, 0.0, 1.0};
        n = dsub(axis, dscale(u, ddot(axis, u)));
    }
    n = dscale(n, 1.0 / dlen(n));
    dvec knee1 = dadd(hip, dadd(dscale(u, a), dscale(n, h))), foot1 = dadd(hip, dscale(u, len));
    out->pose.knee = fv(knee1);
    out->pose.foot = fv(foot1);
    out->target = target;
    out->thigh = mm_quat_between(fv(kh), fv(dsub(knee1, hip)));
    mm_vec3 shin0 = mm_quat_rotate(out->thigh, fv(dsub(foot, knee)));
    out->shin = mm_quat_normalize(mm_quat_mul(mm_quat_between(shin0, fv(dsub(foot1, knee1))), out->thigh));
    if (!finite_leg(&out->pose) || !isfinite(out->thigh.w + out->thigh.x + out->thigh.y + out->thigh.z) ||
        !isfinite(out->shin.w + out->shin.x + out->shin.y + out->shin.z)) {
        leg_identity(leg, out); /* numbers too large for floats */
        return MM_ERR_OUT_OF_RANGE;
    }
    return MM_OK;
}

mm_result mm_warp_stride(const mm_leg_pose *legs, int leg_count, mm_vec3 direction, float scale,
                         float max_extension, mm_leg_warp *out, float *pelvis_drop)
{
    if (pelvis_drop) *pelvis_drop = 0.0f;
    if (!legs || !out || leg_count < 1 || leg_count > MM_WARP_MAX_LEGS) return MM_ERR_INVALID_ARGUMENT;
    int ok = finite3(direction) && isfinite(scale) && scale > 0.0f && !bad_extension(max_extension);
    for (int i = 0; i < leg_count; ++i) {
        leg_identity(&legs[i], &out[i]);
        ok = ok && finite_leg(&legs[i]);
    }
    if (!ok) return MM_ERR_INVALID_ARGUMENT;
    double ext = max_extension > 0.0f ? max_extension : MM_WARP_MAX_EXTENSION_DEFAULT;
    dvec dir = {direction.x, 0.0, direction.z};
    double dl = dlen(dir);
    if (dl < 1e-6) return MM_OK; /* no direction: nothing to scale */
    dir = dscale(dir, 1.0 / dl);
    dvec targets[MM_WARP_MAX_LEGS];
    double drop = 0.0;
    for (int i = 0; i < leg_count; ++i) {
        dvec hip = dv(legs[i].hip), knee = dv(legs[i].knee), foot = dv(legs[i].foot);
        double along = ddot(dsub(foot, hip), dir);
        targets[i] = dadd(foot, dscale(dir, (scale - 1.0) * along));
        /* how far the hip must come down for |target - hip| <= reach */
        double l1 = dlen(dsub(knee, hip)), l2 = dlen(dsub(foot, knee)), now = dlen(dsub(foot, hip));
        if (l1 < 1e-6 || l2 < 1e-6) return MM_ERR_INVALID_ARGUMENT;
        double r = leg_reach(l1, l2, now, ext);
        double hx = targets[i].x - hip.x, hz = targets[i].z - hip.z, side = r * r - (hx * hx + hz * hz);
        double need = side > 0.0 ? hip.y - targets[i].y - sqrt(side) : hip.y - targets[i].y;
        if (need > drop) drop = need;
    }
    if (!isfinite((float)drop)) return MM_ERR_OUT_OF_RANGE;
    for (int i = 0; i < leg_count; ++i) {
        mm_leg_pose lowered = legs[i];
        lowered.hip.y = (float)(lowered.hip.y - drop);
        lowered.knee.y = (float)(lowered.knee.y - drop);
        lowered.foot.y = (float)(lowered.foot.y - drop);
        mm_result r = mm_warp_leg_ik(&lowered, fv(targets[i]), fv(dir), (float)ext, &out[i]);
        if (r != MM_OK) {
            for (int k = 0; k < leg_count; ++k) leg_identity(&legs[k], &out[k]);
            return r;
        }
    }
    if (pelvis_drop) *pelvis_drop = (float)drop;
    return MM_OK;
}

static mm_quat about_y(double angle)
{
    return mm_quat_make(0.0f, (float)sin(0.5 * angle), 0.0f, (float)cos(0.5 * angle));
}

static void orientation_identity(mm_warp_orientation_result *out)
{
    memset(out, 0, sizeof *out);
    out->lower_body = mm_quat_identity();
    for (int i = 0; i < MM_WARP_ORIENTATION_MAX_SPINE; ++i) out->spine[i] = mm_quat_identity();
}

mm_result mm_warp_orientation(mm_vec3 facing, mm_vec3 movement, float previous_angle, float dt,
                              const mm_warp_orientation_params *params, mm_warp_orientation_result *out)
{
    if (!out) return MM_ERR_INVALID_ARGUMENT;
    orientation_identity(out);
    mm_warp_orientation_params p;
    memset(&p, 0, sizeof p);
    if (params) p = *params;
    if (!finite3(facing) || !finite3(movement) || !isfinite(previous_angle) || !isfinite(dt) || dt < 0.0f ||
        !isfinite(p.max_angle) || p.max_angle < 0.0f || !isfinite(p.speed) || p.speed < 0.0f ||
        !isfinite(p.hysteresis) || p.hysteresis < 0.0f || !isfinite(p.halflife) || p.halflife < 0.0f ||
        !isfinite(p.velocity) || p.spine_count < 0 || p.spine_count > MM_WARP_ORIENTATION_MAX_SPINE)
        return MM_ERR_INVALID_ARGUMENT;
    double weights[MM_WARP_ORIENTATION_MAX_SPINE], total = 0.0;
    for (int i = 0; i < p.spine_count; ++i) {
        double w = p.spine_weights ? p.spine_weights[i] : 1.0;
        if (!isfinite(w) || w < 0.0) return MM_ERR_INVALID_ARGUMENT;
        weights[i] = w;
        total += w;
    }
    if (p.spine_count > 0 && !(total > 0.0)) return MM_ERR_INVALID_ARGUMENT;
    const double max_angle = p.max_angle > 0.0f ? p.max_angle : MM_WARP_ORIENTATION_MAX_DEFAULT;
    const double band = p.hysteresis > 0.0f ? p.hysteresis : 0.17;
    const double half = 0.5 * MM_PI;

    double fx = facing.x, fz = facing.z, mx = movement.x, mz = movement.z;
    double target = 0.0;
    int backward = 0;
    if (fx * fx + fz * fz > 1e-12 && mx * mx + mz * mz > 1e-8) {
        double theta = atan2(fz * mx - fx * mz, fx * mx + fz * mz); /* about +Y, facing to movement */
        double back = theta > 0.0 ? theta - MM_PI : theta + MM_PI;
        if (fabs(theta) <= half - band)
            backward = 0;
        else if (fabs(theta) >= half + band)
            backward = 1;
        else /* near 90 degrees: the side nearer the angle used before */
            backward = fabs(back - previous_angle) < fabs(theta - previous_angle);
        target = clampd(backward ? back : theta, -max_angle, max_angle);
    }
    double angle = target;
    if (p.halflife > 0.0f) {
        float x = previous_angle, v = p.velocity;
        mm_spring_update(&x, &v, (float)target, p.halflife, dt);
        angle = x;
        out->velocity = v;
    } else if (p.speed > 0.0f) {
        angle = previous_angle + (target - previous_angle) * (1.0 - exp(-(double)p.speed * dt));
    }
    if (angle < -max_angle || angle > max_angle) out->velocity = 0.0f;
    angle = clampd(angle, -max_angle, max_angle);

    out->target_angle = (float)target;
    out->angle = (float)angle;
    out->backward = backward;
    out->lower_body = about_y(angle);
    double so_far = 0.0;
    for (int i = 0; i < p.spine_count; ++i) {
        so_far += weights[i] / total;
        double left = i == p.spine_count - 1 ? 0.0 : 1.0 - so_far;
        out->spine[i] = about_y(angle * left);
    }
    return MM_OK;
}

mm_vec3 mm_warp_orientation_point(const mm_warp_orientation_result *w, mm_vec3 pivot, mm_vec3 point)
{
    if (!w || !finite3(pivot) || !finite3(point)) return finite_or_zero(point);
    mm_vec3 r = mm_vec3_add(pivot, mm_quat_rotate(w->lower_body, mm_vec3_sub(point, pivot)));
    return finite3(r) ? r : point;
}

mm_result mm_warp_orientation_pose(const mm_warp_orientation_result *w, mm_quat parent_world,
                                   mm_quat pelvis_world, const mm_quat *spine_world, int spine_count,
                                   mm_quat *pelvis_local, mm_quat *spine_local)
{
    if (!w || !pelvis_local || spine_count < 0 || spine_count > MM_WARP_ORIENTATION_MAX_SPINE ||
        (spine_count > 0 && (!spine_world || !spine_local)))
        return MM_ERR_INVALID_ARGUMENT;
    if (w->angle == 0.0f || !isfinite(w->angle)) return MM_OK; /* identity: leave the pose untouched */
    mm_quat above = mm_quat_normalize(mm_quat_mul(w->lower_body, pelvis_world));
    *pelvis_local = mm_quat_normalize(mm_quat_mul(mm_quat_conj(parent_world), above));
    for (int i = 0; i < spine_count; ++i) {
        /* each joint's new world rotation, taken relative to its parent's new one */
        mm_quat world = mm_quat_normalize(mm_quat_mul(w->spine[i], spine_world[i]));
        spine_local[i] = mm_quat_normalize(mm_quat_mul(mm_quat_conj(above), world));
        above = world;
    }
    return MM_OK;
}
