/* The distance curve builder (offline: it allocates). See mm/distance_curve.h and
 * docs/distance.md, "Distance curves". */
#include <mm/distance_curve_build.h>

#include <math.h>
#include <string.h>

#include "db/distance_curve_private.h"

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
    if (d->frame_count < 2 || d->frame_count > MM__DISTANCE_MAX_FRAMES)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "distance curve: %d frames (2 .. %d)",
                            d->frame_count, MM__DISTANCE_MAX_FRAMES);
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
