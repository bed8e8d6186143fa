/* Distance matching and warping against independent truth: root paths whose distance is known in
 * closed form (a constant-speed line, a spring coming to rest, a circle, two stops, a pivot),
 * round trips, the play-rate clamp, stop and pivot predictions against stepping the project's
 * own trajectory simulation, and stride and orientation warping checked by geometry. */
#include <math.h>

#include <mm/character.h>
#include <mm/distance.h>
#include <mm/spring.h>
#include <mm/trajectory.h>

#include "runtime/character/state.h"

#include "test_databases.h"
#include "test_util.h"

#define MAX_CLIP 1024

/* A root path s(t) along the ground direction (dx, dz), sampled at fps, as 3D positions. */
typedef double (*path_fn)(double t);

static int sample_path(path_fn s, double dx, double dz, double fps, int frames, float *xyz)
{
    for (int i = 0; i < frames; ++i) {
        double v = s(i / fps);
        xyz[3 * i + 0] = (float)(dx * v);
        xyz[3 * i + 1] = 0.93f; /* a height, ignored */
        xyz[3 * i + 2] = (float)(dz * v);
    }
    return frames;
}

static mm_distance_curve build(const float *pos, int components, int frames, float fps, int loop)
{
    mm_distance_desc d;
    memset(&d, 0, sizeof d);
    d.positions = pos;
    d.components = components;
    d.frame_count = frames;
    d.fps = fps;
    d.loop = loop;
    mm_distance_curve c;
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_result r = mm_distance_curve_build(&c, &d, &err);
    if (r != MM_OK) print_error("build: %s\n", err.message);
    assert_int_equal(r, MM_OK);
    assert_int_equal(mm_distance_curve_validate(&c, &err), MM_OK);
    return c;
}

/* ---- a constant-speed line --------------------------------------------------------------- */

static double line(double t) { return 1.2 * t; }

static void test_constant_line(void **state)
{
    (void)state;
    static float pos[3 * MAX_CLIP];
    const float fps = 30.0f;
    int n = sample_path(line, 0.6, 0.8, fps, 91, pos); /* 3 s */
    mm_distance_curve c = build(pos, 3, n, fps, 0);
    assert_int_equal(c.segment_count, 1);
    assert_int_equal(c.segments[0].kind, MM_DISTANCE_NONE);
    assert_near(c.path_length, 3.6, 1e-5);
    assert_near(mm_distance_duration(&c), 3.0, 1e-6);
    assert_near(mm_distance_clip_speed(&c), 1.2, 1e-5);
    for (int i = 0; i < n; ++i) assert_near(c.distance[i], 1.2 * i / fps, 1e-5); /* distance = v t */
    for (double t = 0.0; t <= 3.0; t += 0.0137) {
        assert_near(mm_distance_travelled(&c, (float)t), 1.2 * t, 2e-5);
        assert_near(mm_distance_signed(&c, (float)t), 1.2 * t, 2e-5);
    }
    /* the seed's loop: distance d from t takes d / v seconds, fractions of frames included */
    assert_near(mm_distance_time_after(&c, 0.5f, 0.25f), 0.5 + 0.25 / 1.2, 1e-5);
    assert_near(mm_distance_time_after(&c, 1.01f, 0.0f), 1.01, 1e-7);
    /* advance: a character at the clip's speed plays at rate 1 */
    float t = 0.5f, rate = 0.0f;
    const float dt = 1.0f / 60.0f;
    assert_int_equal(mm_distance_advance(&c, t, 1.2f * dt, dt, 0.75f, 1.25f, &t, &rate), MM_OK);
    assert_near(rate, 1.0, 1e-3);
    assert_near(t, 0.5 + dt, 1e-5);
    /* twice as fast: clamped to 1.25, or 2 with the clamp off */
    assert_int_equal(mm_distance_advance(&c, 0.5f, 2.4f * dt, dt, 0.75f, 1.25f, &t, &rate), MM_OK);
    assert_near(rate, 1.25, 1e-6);
    assert_near(t, 0.5 + 1.25 * dt, 1e-5);
    assert_int_equal(mm_distance_advance(&c, 0.5f, 2.4f * dt, dt, 0.0f, 0.0f, &t, &rate), MM_OK);
    assert_near(rate, 2.0, 1e-3);
    assert_near(t, 0.5 + 2.0 * dt, 1e-5);
    /* standing still: the slowest rate allowed, or none without the clamp */
    assert_int_equal(mm_distance_advance(&c, 0.5f, 0.0f, dt, 0.75f, 1.25f, &t, &rate), MM_OK);
    assert_near(rate, 0.75, 1e-6);
    assert_int_equal(mm_distance_advance(&c, 0.5f, 0.0f, dt, 0.0f, 0.0f, &t, &rate), MM_OK);
    assert_near(rate, 0.0, 1e-9);
    assert_near(t, 0.5, 1e-7);
    /* one-shots stop at the last frame */
    assert_int_equal(mm_distance_advance(&c, 2.99f, 1.0f, dt, 0.0f, 0.0f, &t, &rate), MM_OK);
    assert_near(t, 3.0, 1e-6);
    assert_near(mm_distance_time_after(&c, 2.5f, 100.0f), 3.0, 1e-6);
    /* no stop: the distance counts from the start, and matching finds d / v */
    float m = -1.0f;
    assert_int_equal(mm_distance_match_to_target(&c, 0, -1.5f, &m), MM_OK);
    assert_near(m, 1.5 / 1.2, 1e-5);
    assert_int_equal(mm_distance_match_to_target(&c, 0, -100.0f, &m), MM_OK); /* clamped */
    assert_near(m, 3.0, 1e-6);
    assert_int_equal(mm_distance_match_to_target(&c, 0, 5.0f, &m), MM_OK);
    assert_near(m, 0.0, 1e-9);
    mm_distance_curve_free(&c);
}

/* ---- a spring stop ------------------------------------------------------------------------ */

/* Walks 1 s at 1.5 m/s, then the velocity decays with the project's spring (half-life 0.2 s):
 * x = 1.5 + v0 (1 - (1 + y t) e^(-y t)) / y + v0 t e^(-y t) ... in closed form below. */
static double spring_y(void) { return mm_spring_damping(0.2f); }
static double spring_stop(double t)
{
    if (t <= 1.0) return 1.5 * t;
    double y = spring_y(), u = t - 1.0, e = exp(-y * u);
    /* v(u) = v0 (1 + y u) e^(-y u); x(u) = v0 (2 - (2 + y u) e^(-y u)) / y */
    return 1.5 + 1.5 * (2.0 - (2.0 + y * u) * e) / y;
}

static void test_spring_stop(void **state)
{
    (void)state;
    static float pos[3 * MAX_CLIP];
    const float fps = 60.0f;
    int n = sample_path(spring_stop, 1.0, 0.0, fps, 301, pos); /* 5 s */
    mm_distance_curve c = build(pos, 3, n, fps, 0);
    assert_int_equal(c.segment_count, 1);
    assert_int_equal(c.segments[0].kind, MM_DISTANCE_STOP);
    const double rest = 1.5 + 2.0 * 1.5 / spring_y(); /* where it comes to rest: 1.5 + 2 v0 / y */
    assert_near(c.distance[0], -rest, 5e-3);
    assert_near(c.distance[c.segments[0].marker_frame], 0.0, 1e-7);
    for (int i = 0; i < n; ++i) {
        assert_near(c.distance[i], spring_stop(i / fps) - rest, 5e-3);
        if (i) assert_true(c.distance[i] >= c.distance[i - 1]);
    }
    /* match to target: the remaining distance to the true rest point is the one asked for */
    const double wanted[] = {1.8, 1.0, 0.3, 0.05};
    for (int k = 0; k < 4; ++k) {
        float t = -1.0f;
        assert_int_equal(mm_distance_match_to_target(&c, 0, (float)wanted[k], &t), MM_OK);
        assert_near(rest - spring_stop(t), wanted[k], 5e-3);
    }
    float start = -1.0f; /* farther than the clip goes: its first frame */
    assert_int_equal(mm_distance_match_to_target(&c, 0, 2.0f, &start), MM_OK);
    assert_near(start, 0.0, 0);
    mm_distance_curve_free(&c);
}

/* ---- a loop on a circle ------------------------------------------------------------------- */

static void test_loop_circle(void **state)
{
    (void)state;
    static float pos[2 * MAX_CLIP];
    const int n = 120;
    const float fps = 30.0f;
    const double r = 2.0;
    for (int i = 0; i < n; ++i) { /* one turn in 4 s; frame n would be frame 0 again */
        double a = 2.0 * MM_PI * i / n;
        pos[2 * i] = (float)(r * cos(a));
        pos[2 * i + 1] = (float)(r * sin(a));
    }
    mm_distance_curve c = build(pos, 2, n, fps, 1);
    const double chord = 2.0 * r * sin(MM_PI / n), L = n * chord, T = 4.0;
    assert_int_equal(c.segment_count, 1);
    assert_int_equal(c.segments[0].kind, MM_DISTANCE_NONE);
    assert_near(c.path_length, L, 1e-4);
    assert_near(c.path_length, 2.0 * MM_PI * r, 2e-3 * 2.0 * MM_PI * r);
    assert_near(mm_distance_duration(&c), T, 1e-6);
    assert_near(mm_distance_clip_speed(&c), L / T, 1e-4);
    /* the curve keeps growing across the wrap */
    for (double t = 0.0; t < 4.0; t += 0.0731) {
        double d = mm_distance_travelled(&c, (float)t);
        assert_near(d, L / T * t, 1e-4);
        assert_near(mm_distance_travelled(&c, (float)(t + T)), d + L, 2e-4);
        assert_near(mm_distance_travelled(&c, (float)(t + 3.0 * T)), d + 3.0 * L, 5e-4);
    }
    /* advancing over the wrap lands after it; whole loops are skipped at once */
    float t = -1.0f, rate = 0.0f;
    const float dt = 0.1f;
    assert_int_equal(mm_distance_advance(&c, 3.95f, (float)(L / T * dt), dt, 0.75f, 1.25f, &t, &rate), MM_OK);
    assert_near(t, 0.05, 1e-4);
    assert_near(rate, 1.0, 1e-3);
    assert_near(mm_distance_time_after(&c, 1.0f, (float)(2.5 * L)), 1.0 + 2.5 * T, 1e-4);
    assert_near(mm_distance_time_after(&c, 3.9f, (float)(L / T * 0.3)), 4.2, 1e-4);
    mm_distance_curve_free(&c);
}

/* A loop that comes to rest `stops` times per cycle, once exactly at the wrap:
 * v(t) = 0.7 (1 - cos(2 pi stops t / T)), s(t) = 0.7 (t - T / (2 pi stops) sin(2 pi stops t / T)). */
static double loop_T = 4.0;
static int loop_stops = 1;
static double stopping_loop(double t)
{
    double w = 2.0 * MM_PI * loop_stops / loop_T;
    return 0.7 * (t - sin(w * t) / w);
}

static void test_loop_stops(void **state)
{
    (void)state;
    static float pos[2 * MAX_CLIP];
    const float fps = 30.0f;
    const int n = 120;
    for (loop_stops = 1; loop_stops <= 2; ++loop_stops) {
        for (int i = 0; i < n; ++i) { /* along -X, on and on: the loop's root does not come back */
            pos[2 * i] = (float)-stopping_loop(i / fps);
            pos[2 * i + 1] = 0.25f;
        }
        mm_distance_curve c = build(pos, 2, n, fps, 1);
        const double L = stopping_loop(loop_T);
        assert_near(c.path_length, L, 1e-4); /* the wrap step interpolated */
        assert_int_equal(c.segment_count, loop_stops);
        for (int k = 0; k < loop_stops; ++k) {
            const mm_distance_segment *g = &c.segments[k];
            assert_int_equal(g->kind, MM_DISTANCE_STOP);
            int marker = (k + 1) % loop_stops * n / loop_stops; /* the segment ends after its stop */
            assert_int_equal(g->marker_frame, marker);
            int im = (marker - g->first_frame + n) % n;
            double mt = (g->first_frame + im) / fps; /* unwrapped: past the wrap is one loop more */
            for (int i = 0; i < g->frame_count; ++i) {
                int f = (g->first_frame + i) % n;
                assert_near(c.distance[f], stopping_loop((g->first_frame + i) / fps) - stopping_loop(mt),
                            2e-4);
            }
        }
        /* the segment holding the wrap: 0.5 m before the stop at the wrap is before the wrap */
        int seg = mm_distance_segment_at(&c, 0.0f);
        assert_int_equal(c.segments[seg].marker_frame, 0);
        float t = -1.0f;
        assert_int_equal(mm_distance_match_to_target(&c, seg, 0.5f, &t), MM_OK);
        assert_true(t > loop_T / 2 && t < loop_T);
        assert_near(L - stopping_loop(t), 0.5, 1e-3);
        assert_int_equal(mm_distance_match_to_target(&c, seg, -0.005f, &t), MM_OK); /* 5 mm past it */
        assert_true(t > 0.0f && t < loop_T / 2);
        assert_near(stopping_loop(t), 0.005, 2e-4);
        /* the segment ends where the root is under way again (0.1 m/s): farther is clamped there */
        const mm_distance_segment *g = &c.segments[seg];
        assert_int_equal(mm_distance_match_to_target(&c, seg, -1.0f, &t), MM_OK);
        assert_near(t, ((g->first_frame + g->frame_count - 1) % n) / fps, 1e-6);
        /* advancing over the stop at the wrap */
        float rate;
        const double t0 = loop_T - 0.3;
        double d = stopping_loop(loop_T + 0.2) - stopping_loop(t0);
        assert_int_equal(mm_distance_advance(&c, (float)t0, (float)d, 0.5f, 0.0f, 0.0f, &t, &rate), MM_OK);
        assert_near(t, 0.2, 2e-3);
        mm_distance_curve_free(&c);
    }
}

/* ---- two stops, a pivot ------------------------------------------------------------------- */

/* 1.4 m/s, brake at 1.4 m/s^2 to rest at t = 2, stand, speed up again from t = 3, brake to
 * rest at t = 6, stand to the end (7 s). */
static double two_stops(double t)
{
    if (t <= 1.0) return 1.4 * t;
    if (t <= 2.0) return 1.4 + 1.4 * (t - 1.0) - 0.7 * (t - 1.0) * (t - 1.0);
    if (t <= 3.0) return 2.1;
    if (t <= 4.0) return 2.1 + 0.7 * (t - 3.0) * (t - 3.0);
    if (t <= 5.0) return 2.8 + 1.4 * (t - 4.0);
    if (t <= 6.0) return 4.2 + 1.4 * (t - 5.0) - 0.7 * (t - 5.0) * (t - 5.0);
    return 4.9;
}

static void test_two_stops(void **state)
{
    (void)state;
    static float pos[3 * MAX_CLIP];
    const float fps = 30.0f;
    int n = sample_path(two_stops, 0.6, -0.8, fps, 211, pos);
    mm_distance_curve c = build(pos, 3, n, fps, 0);
    assert_int_equal(c.segment_count, 2);
    const mm_distance_segment *s0 = &c.segments[0], *s1 = &c.segments[1];
    assert_int_equal(s0->kind, MM_DISTANCE_STOP);
    assert_int_equal(s1->kind, MM_DISTANCE_STOP);
    assert_int_equal(s0->first_frame, 0);
    assert_in_range(s0->marker_frame, 60, 61); /* at rest from t = 2 */
    assert_in_range(s1->marker_frame, 180, 181);
    /* segment 0 ends once the root speeds up again (0.1 m/s: t = 3.07), segment 1 runs on */
    assert_in_range(s0->first_frame + s0->frame_count, 91, 94);
    assert_int_equal(s1->first_frame, s0->first_frame + s0->frame_count);
    assert_int_equal(s1->first_frame + s1->frame_count, n);
    for (int i = 0; i < n; ++i) {
        double stop = i < s1->first_frame ? 2.1 : 4.9;
        assert_near(c.distance[i], two_stops(i / fps) - stop, 1e-4);
    }
    assert_int_equal(mm_distance_segment_at(&c, 0.5f), 0);
    assert_int_equal(mm_distance_segment_at(&c, 5.0f), 1);
    /* match to each stop */
    float t;
    assert_int_equal(mm_distance_match_to_target(&c, 0, 0.7f, &t), MM_OK);
    assert_near(t, 1.0, 1e-4); /* 0.7 m before rest: where the braking starts */
    assert_int_equal(mm_distance_match_to_target(&c, 1, 0.7f, &t), MM_OK);
    assert_near(t, 5.0, 1e-4);
    assert_int_equal(mm_distance_match_to_target(&c, 1, 0.0f, &t), MM_OK); /* the stop itself */
    assert_near(two_stops(t), 4.9, 1e-4);
    assert_true(t >= 5.9f && t <= 6.0f + 1e-5f);
    assert_int_equal(mm_distance_match_to_target(&c, 0, 10.0f, &t), MM_OK); /* clamped to the start */
    assert_near(t, 0.0, 1e-7);
    assert_int_equal(mm_distance_match_to_target(&c, 2, 1.0f, &t), MM_ERR_INVALID_ARGUMENT);
    mm_distance_curve_free(&c);
}

/* Brakes from 1.4 m/s to turn back at t = 1 (0.7 m out), then away the other way. */
static double pivot_path(double t) { return t <= 2.0 ? 1.4 * t - 0.7 * t * t : -1.4 * (t - 2.0); }

static void test_pivot(void **state)
{
    (void)state;
    static float pos[2 * MAX_CLIP];
    const float fps = 60.0f;
    int n = 181;
    for (int i = 0; i < n; ++i) {
        pos[2 * i] = (float)(-0.8 * pivot_path(i / fps));
        pos[2 * i + 1] = (float)(0.6 * pivot_path(i / fps));
    }
    mm_distance_curve c = build(pos, 2, n, fps, 0);
    assert_int_equal(c.segment_count, 1);
    assert_int_equal(c.segments[0].kind, MM_DISTANCE_PIVOT);
    assert_int_equal(c.segments[0].marker_frame, 60);
    for (int i = 0; i < n; ++i) { /* path length to the pivot, negative before and positive after */
        double t = i / fps, s = pivot_path(t);
        double expected = t <= 1.0 ? s - 0.7 : 0.7 - s;
        assert_near(c.distance[i], expected, 1e-4);
    }
    mm_distance_curve_free(&c);
}

/* Brakes from 1.4 m/s to rest at t = 1 (0.7 m out), then drifts back at sway_speed m/s: the
 * root's sway after a stop, or (faster than the 0.1 m/s stop speed) a walk away the other way. */
static double sway_speed;
static double stop_then_sway(double t)
{
    return t <= 1.0 ? 1.4 * t - 0.7 * t * t : 0.7 - sway_speed * (t - 1.0);
}

static void test_stop_then_sway(void **state)
{
    (void)state;
    static float pos[3 * MAX_CLIP];
    const float fps = 60.0f;
    /* 0.07 m/s back: over the 0.2 s after the rest point it leaves 1.4 cm, more than half the
     * stop speed's 2 cm but less than all of it: a stop, the distance counting on through it */
    const double speeds[2] = {0.07, 0.15};
    for (int k = 0; k < 2; ++k) {
        sway_speed = speeds[k];
        int n = sample_path(stop_then_sway, 0.6, 0.8, fps, 121, pos);
        mm_distance_curve c = build(pos, 3, n, fps, 0);
        assert_int_equal(c.segment_count, 1);
        assert_int_equal(c.segments[0].kind, k == 0 ? MM_DISTANCE_STOP : MM_DISTANCE_PIVOT);
        assert_in_range(c.segments[0].marker_frame, 59, 61);
        for (int i = 0; i < n; ++i) { /* path length to the rest point */
            double t = i / fps, s = stop_then_sway(t);
            double expected = t <= 1.0 ? s - 0.7 : 0.7 - s;
            assert_near(c.distance[i], expected, 2e-3);
        }
        mm_distance_curve_free(&c);
    }
}

/* ---- round trips ---------------------------------------------------------------------------- */

static void test_round_trip(void **state)
{
    (void)state;
    static float pos[3 * MAX_CLIP];
    const float fps = 30.0f;
    int n = sample_path(two_stops, 1.0, 0.0, fps, 211, pos);
    mm_distance_curve c = build(pos, 3, n, fps, 0);
    test_rng rng = {0x9e3779b97f4a7c15ull};
    int checked = 0;
    for (int k = 0; k < 400; ++k) {
        float t0 = (float)test_rng_uniform(&rng, 0.0, 6.9);
        float d = (float)test_rng_uniform(&rng, 0.0, 0.5);
        float dt = 1.0f / 60.0f, t1, rate;
        assert_int_equal(mm_distance_advance(&c, t0, d, dt, 0.0f, 0.0f, &t1, &rate), MM_OK);
        assert_true(t1 >= t0 && t1 <= 7.0f);
        double moved = mm_distance_travelled(&c, t1) - mm_distance_travelled(&c, t0);
        if (t1 < 7.0f - 1e-6f) assert_near(moved, d, 2e-4); /* travelled exactly as far */
        /* and back: the time whose remaining distance is the one at t1 */
        int seg = mm_distance_segment_at(&c, t1);
        const mm_distance_segment *g = &c.segments[seg];
        /* between a segment's last frame and the next segment the curve is not the segment's */
        if (seg != mm_distance_segment_at(&c, t0) || t1 * fps > g->first_frame + g->frame_count - 1) continue;
        float back;
        assert_int_equal(mm_distance_match_to_target(&c, seg, -mm_distance_signed(&c, t1), &back), MM_OK);
        assert_near(mm_distance_signed(&c, back), mm_distance_signed(&c, t1), 2e-4);
        if (fabs(two_stops(t1) - two_stops(t1 - 0.01)) > 1e-3) { /* moving: the time is unique */
            assert_near(back, t1, 2e-3);
            ++checked;
        }
    }
    assert_true(checked > 150);
    mm_distance_curve_free(&c);
}

/* ---- play rate ------------------------------------------------------------------------------ */

static void test_play_rate(void **state)
{
    (void)state;
    float r = 0.0f;
    assert_int_equal(mm_distance_play_rate(1.2f, 1.0f, 0.75f, 1.25f, &r), MM_OK);
    assert_near(r, 1.2, 1e-6);
    assert_int_equal(mm_distance_play_rate(3.0f, 1.0f, 0.75f, 1.25f, &r), MM_OK);
    assert_near(r, 1.25, 0);
    assert_int_equal(mm_distance_play_rate(0.1f, 1.0f, 0.75f, 1.25f, &r), MM_OK);
    assert_near(r, 0.75, 0);
    assert_int_equal(mm_distance_play_rate(3.0f, 1.5f, 0.0f, 0.0f, &r), MM_OK); /* clamp off */
    assert_near(r, 2.0, 1e-6);
    assert_int_equal(mm_distance_play_rate(3.0f, 1.0f, 1.25f, 0.75f, &r), MM_ERR_INVALID_ARGUMENT);
    assert_near(r, 1.0, 0);
    assert_int_equal(mm_distance_play_rate(-1.0f, 1.0f, 0.75f, 1.25f, &r), MM_ERR_INVALID_ARGUMENT);
    assert_int_equal(mm_distance_play_rate(NAN, 1.0f, 0.75f, 1.25f, &r), MM_ERR_INVALID_ARGUMENT);
    assert_true(isfinite(r));
    assert_int_equal(mm_distance_play_rate(1.0f, 0.0f, 0.75f, 1.25f, &r), MM_ERR_OUT_OF_RANGE);
    assert_near(r, 1.0, 0);
    /* stride scale: what the play rate could not make up, clamped */
    assert_int_equal(mm_distance_stride_scale(3.0f, 2.0f, 1.25f, 0.5f, 1.5f, &r), MM_OK);
    assert_near(r, 1.2, 1e-6);
    assert_int_equal(mm_distance_stride_scale(6.0f, 2.0f, 1.25f, 0.5f, 1.5f, &r), MM_OK);
    assert_near(r, 1.5, 0);
    assert_int_equal(mm_distance_stride_scale(1.0f, 2.0f, NAN, 0.5f, 1.5f, &r), MM_ERR_INVALID_ARGUMENT);
    assert_near(r, 1.0, 0);
}

/* ---- bad input ------------------------------------------------------------------------------ */

static void test_bad_input(void **state)
{
    (void)state;
    float pos[3 * 10];
    for (int i = 0; i < 30; ++i) pos[i] = (float)i * 0.01f;
    mm_distance_desc d;
    memset(&d, 0, sizeof d);
    d.positions = pos;
    d.components = 3;
    d.frame_count = 10;
    d.fps = 30.0f;
    mm_distance_curve c;
    mm_error err;
    memset(&err, 0, sizeof err);
    d.components = 4;
    assert_int_equal(mm_distance_curve_build(&c, &d, &err), MM_ERR_INVALID_ARGUMENT);
    d.components = 3;
    d.frame_count = 1;
    assert_int_equal(mm_distance_curve_build(&c, &d, &err), MM_ERR_INVALID_ARGUMENT);
    d.frame_count = 10;
    d.fps = 0.0f;
    assert_int_equal(mm_distance_curve_build(&c, &d, &err), MM_ERR_INVALID_ARGUMENT);
    d.fps = 30.0f;
    d.stop_speed = -1.0f;
    assert_int_equal(mm_distance_curve_build(&c, &d, &err), MM_ERR_INVALID_ARGUMENT);
    d.stop_speed = 0.0f;
    pos[14] = NAN;
    assert_int_equal(mm_distance_curve_build(&c, &d, &err), MM_ERR_BAD_NUMBER);
    assert_non_null(strstr(err.message, "frame 4"));
    assert_null(c.block);
    pos[14] = 0.14f;
    assert_int_equal(mm_distance_curve_build(&c, &d, &err), MM_OK);

    /* per tick: bad numbers are refused, the outputs stay finite */
    float t = 123.0f, rate = 5.0f;
    assert_int_equal(mm_distance_advance(&c, NAN, 0.1f, 0.1f, 0.75f, 1.25f, &t, &rate),
                     MM_ERR_INVALID_ARGUMENT);
    assert_true(isfinite(t) && isfinite(rate));
    assert_int_equal(mm_distance_advance(&c, 0.1f, NAN, 0.1f, 0.75f, 1.25f, &t, &rate),
                     MM_ERR_INVALID_ARGUMENT);
    assert_near(t, 0.1, 1e-7);
    assert_int_equal(mm_distance_advance(&c, 0.1f, 0.1f, 0.0f, 0.75f, 1.25f, &t, &rate),
                     MM_ERR_INVALID_ARGUMENT);
    assert_int_equal(mm_distance_advance(&c, 0.1f, 0.1f, INFINITY, 0.75f, 1.25f, &t, &rate),
                     MM_ERR_INVALID_ARGUMENT);
    assert_int_equal(mm_distance_advance(&c, 0.1f, -0.1f, 0.1f, 0.75f, 1.25f, &t, &rate),
                     MM_ERR_INVALID_ARGUMENT);
    assert_int_equal(mm_distance_advance(&c, 0.1f, 0.1f, 0.1f, -1.0f, 1.25f, &t, &rate),
                     MM_ERR_INVALID_ARGUMENT);
    assert_int_equal(mm_distance_advance(NULL, 0.1f, 0.1f, 0.1f, 0.75f, 1.25f, &t, &rate),
                     MM_ERR_INVALID_ARGUMENT);
    assert_true(isfinite(t) && isfinite(rate));
    assert_int_equal(mm_distance_match_to_target(&c, 0, NAN, &t), MM_ERR_INVALID_ARGUMENT);
    assert_true(isfinite(t));
    assert_int_equal(mm_distance_match_to_target(&c, -1, 0.0f, &t), MM_ERR_INVALID_ARGUMENT);
    assert_true(isfinite(mm_distance_travelled(&c, NAN)));
    assert_true(isfinite(mm_distance_signed(&c, INFINITY)));
    assert_true(isfinite(mm_distance_time_after(&c, 0.1f, NAN)));

    /* a curve read from elsewhere that decreases is refused */
    float travelled[10], distance[10];
    memcpy(travelled, c.travelled, sizeof travelled);
    memcpy(distance, c.distance, sizeof distance);
    mm_distance_curve view = c;
    view.block = NULL;
    view.travelled = travelled;
    view.distance = distance;
    assert_int_equal(mm_distance_curve_validate(&view, &err), MM_OK);
    travelled[5] = travelled[3];
    assert_int_not_equal(mm_distance_curve_validate(&view, &err), MM_OK);
    mm_distance_curve_free(&c);

    /* an in-place clip: nothing to match, it plays on at rate 1 */
    float still[2 * 8] = {0};
    c = build(still, 2, 8, 30.0f, 1);
    assert_int_equal(mm_distance_advance(&c, 0.1f, 0.5f, 0.1f, 0.75f, 1.25f, &t, &rate), MM_ERR_OUT_OF_RANGE);
    assert_near(rate, 1.0, 0);
    assert_near(t, 0.2, 1e-6);
    mm_distance_curve_free(&c);
}

/* ---- stop and pivot prediction --------------------------------------------------------------- */

static void test_predict_stop_closed_form(void **state)
{
    (void)state;
    mm_distance_prediction p;
    const float h = 0.25f;
    const double y = mm_spring_damping(h);
    assert_int_equal(mm_distance_predict_stop(mm_vec3_make(0, 0, 1.5f), mm_vec3_make(0, 0, 0), h, 0.05f, &p),
                     MM_OK);
    assert_int_equal(p.found, 1);
    assert_near(p.offset.z, 2.0 * 1.5 / y, 1e-5); /* integral of v0 (1 + y t) e^(-y t) */
    assert_near(p.offset.x, 0.0, 1e-7);
    assert_near(p.distance, 2.0 * 1.5 / y, 1e-5);
    /* the speed 1.5 (1 + u) e^-u falls to 0.05 at u solved here by bisection */
    double lo = 0.0, hi = 40.0;
    for (int i = 0; i < 200; ++i) {
        double mid = 0.5 * (lo + hi);
        if (1.5 * (1.0 + mid) * exp(-mid) >= 0.05)
            lo = mid;
        else
            hi = mid;
    }
    assert_near(p.time, lo / y, 1e-5);
    /* at rest already */
    assert_int_equal(mm_distance_predict_stop(mm_vec3_make(0.01f, 0, 0), mm_vec3_make(0, 0, 0), h, 0.05f, &p),
                     MM_OK);
    assert_int_equal(p.found, 0);
    /* no spring: at rest at once */
    assert_int_equal(
        mm_distance_predict_stop(mm_vec3_make(0, 0, 1.5f), mm_vec3_make(0, 0, 0), 0.0f, 0.0f, &p), MM_OK);
    assert_near(p.distance, 0.0, 0);
    /* NaN in, zeros out */
    assert_int_equal(mm_distance_predict_stop(mm_vec3_make(NAN, 0, 1), mm_vec3_make(0, 0, 0), h, 0.0f, &p),
                     MM_ERR_INVALID_ARGUMENT);
    assert_true(isfinite(p.offset.x) && isfinite(p.distance) && isfinite(p.time) && p.found == 0);
    assert_int_equal(mm_distance_predict_pivot(mm_vec3_make(0, 0, 1), mm_vec3_make(0, 0, 0),
                                               mm_vec3_make(0, 0, -1), NAN, &p),
                     MM_ERR_INVALID_ARGUMENT);
    assert_true(isfinite(p.offset.z) && p.found == 0);
}

static mm_input stick(float x, float z)
{
    mm_input in;
    memset(&in, 0, sizeof in);
    in.stick[0] = x;
    in.stick[1] = z;
    in.gait = MM_GAIT_WALK;
    return in;
}

/* Runs the trajectory on `first` for `seconds`, then predicts under `then`, and steps the
 * simulation on `then` at 120 Hz to compare: the rest point (stop) or the turning point (pivot). */
static void compare_with_simulation(mm_input first, float seconds, mm_input then, int pivot)
{
    mm_trajectory t;
    assert_int_equal(mm_trajectory_init(&t, NULL, NULL), MM_OK);
    const float dt = 1.0f / 120.0f;
    for (int i = 0; i < (int)(seconds * 120.0f + 0.5f); ++i) mm_trajectory_update(&t, &first, dt);
    mm_distance_prediction stop, piv;
    assert_int_equal(mm_distance_predict_trajectory(&t, &then, 0.05f, &stop, &piv), MM_OK);
    mm_vec3 start = t.position, prev = start, g;
    mm_trajectory_desired(&t, &then, &g, NULL);
    double path = 0.0, gl = mm_vec3_length(g);
    if (!pivot) {
        assert_int_equal(stop.found, 1);
        double last_fast = 0.0;
        for (int i = 1; i <= 120 * 10; ++i) {
            mm_trajectory_update(&t, &then, dt);
            path += mm_vec3_distance(t.position, prev);
            prev = t.position;
            if (mm_vec3_length(t.velocity) >= 0.05f) last_fast = i * dt;
        }
        mm_vec3 moved = mm_vec3_sub(t.position, start);
        assert_near(stop.offset.x, moved.x, 1e-3);
        assert_near(stop.offset.z, moved.z, 1e-3);
        assert_near(stop.distance, path, 1e-3);
        assert_near(stop.time, last_fast, 1.5 * dt);
    } else {
        assert_int_equal(piv.found, 1);
        double along_prev = mm_vec3_dot(t.velocity, g) / gl;
        assert_true(along_prev < 0.0);
        for (int i = 1; i <= 120 * 10; ++i) {
            mm_vec3 p0 = t.position;
            mm_trajectory_update(&t, &then, dt);
            double along = mm_vec3_dot(t.velocity, g) / gl;
            if (along >= 0.0) { /* crossed within this tick: interpolate */
                double a = -along_prev / (along - along_prev);
                mm_vec3 at = mm_vec3_lerp(p0, t.position, (float)a);
                path += mm_vec3_distance(at, p0);
                mm_vec3 moved = mm_vec3_sub(at, start);
                assert_near(piv.offset.x, moved.x, 2e-3);
                assert_near(piv.offset.z, moved.z, 2e-3);
                assert_near(piv.distance, path, 2e-3);
                assert_near(piv.time, (i - 1 + a) * dt, 1.5 * dt);
                mm_trajectory_free(&t);
                return;
            }
            path += mm_vec3_distance(t.position, p0);
            along_prev = along;
        }
        fail_msg("the simulation never turned");
    }
    mm_trajectory_free(&t);
}

static void test_predict_against_simulation(void **state)
{
    (void)state;
    /* let go while walking at full speed, while still speeding up, and while curving */
    compare_with_simulation(stick(0, 1), 3.0f, stick(0, 0), 0);
    compare_with_simulation(stick(0, 1), 0.3f, stick(0, 0), 0);
    mm_input run = stick(0.8f, 0.6f);
    run.gait = MM_GAIT_RUN;
    mm_input run_released = stick(0, 0);
    run_released.gait = MM_GAIT_RUN;
    compare_with_simulation(run, 2.0f, run_released, 0);
    /* turn back: straight, and at 135 degrees */
    compare_with_simulation(stick(0, 1), 2.0f, stick(0, -1), 1);
    compare_with_simulation(stick(0, 1), 2.0f, stick(0.7071f, -0.7071f), 1);
    /* walking the way the stick points: no pivot */
    mm_trajectory t;
    assert_int_equal(mm_trajectory_init(&t, NULL, NULL), MM_OK);
    mm_input fwd = stick(0, 1);
    for (int i = 0; i < 120; ++i) mm_trajectory_update(&t, &fwd, 1.0f / 60.0f);
    mm_distance_prediction piv;
    assert_int_equal(mm_distance_predict_trajectory(&t, &fwd, 0.0f, NULL, &piv), MM_OK);
    assert_int_equal(piv.found, 0);
    mm_trajectory_free(&t);
}

/* ---- stride warping ---------------------------------------------------------------------------- */

/* A leg with thigh and shin 0.45 m, the knee bent forward (+Z) toward the foot. */
static mm_leg_pose make_leg(mm_vec3 hip, mm_vec3 foot)
{
    const double l = 0.45;
    mm_vec3 d = mm_vec3_sub(foot, hip);
    double len = mm_vec3_length(d), h = sqrt(l * l - 0.25 * len * len);
    mm_vec3 u = mm_vec3_scale(d, (float)(1.0 / len));
    mm_vec3 fwd = mm_vec3_make(0, 0, 1);
    mm_vec3 n = mm_vec3_normalize(mm_vec3_sub(fwd, mm_vec3_scale(u, mm_vec3_dot(fwd, u))));
    mm_leg_pose leg;
    leg.hip = hip;
    leg.foot = foot;
    leg.knee =
        mm_vec3_add(hip, mm_vec3_add(mm_vec3_scale(u, (float)(0.5 * len)), mm_vec3_scale(n, (float)h)));
    return leg;
}

static void assert_lengths_kept(const mm_leg_pose *a, const mm_leg_pose *b)
{
    assert_near(mm_vec3_distance(a->hip, a->knee), mm_vec3_distance(b->hip, b->knee), 1e-5);
    assert_near(mm_vec3_distance(a->knee, a->foot), mm_vec3_distance(b->knee, b->foot), 1e-5);
}

static void test_stride_warp(void **state)
{
    (void)state;
    mm_leg_pose legs[2] = {make_leg(mm_vec3_make(0.1f, 0.9f, 0.0f), mm_vec3_make(0.12f, 0.08f, 0.25f)),
                           make_leg(mm_vec3_make(-0.1f, 0.9f, 0.0f), mm_vec3_make(-0.12f, 0.08f, -0.2f))};
    mm_leg_warp out[2];
    float drop = -1.0f;
    const mm_vec3 fwd = mm_vec3_make(0, 0, 2.0f); /* need not be unit */

    /* scale 1: the identity */
    assert_int_equal(mm_warp_stride(legs, 2, fwd, 1.0f, 0.0f, out, &drop), MM_OK);
    assert_near(drop, 0.0, 0);
    for (int k = 0; k < 2; ++k) {
        assert_near(mm_vec3_distance(out[k].pose.knee, legs[k].knee), 0.0, 1e-5);
        assert_near(mm_vec3_distance(out[k].pose.foot, legs[k].foot), 0.0, 1e-5);
        assert_near(mm_quat_angle_between(out[k].thigh, mm_quat_identity()), 0.0, 1e-3);
    }

    /* scale 1.2: the feet's distances from the hips along +Z scale by 1.2; the pelvis stays */
    assert_int_equal(mm_warp_stride(legs, 2, fwd, 1.2f, 0.0f, out, &drop), MM_OK);
    assert_near(drop, 0.0, 0);
    for (int k = 0; k < 2; ++k) {
        assert_near(out[k].pose.foot.z - out[k].pose.hip.z, 1.2 * (legs[k].foot.z - legs[k].hip.z), 1e-5);
        assert_near(out[k].pose.foot.x, legs[k].foot.x, 1e-5);
        assert_near(out[k].pose.foot.y, legs[k].foot.y, 1e-5);
        assert_near(mm_vec3_distance(out[k].pose.hip, legs[k].hip), 0.0, 0);
        assert_lengths_kept(&legs[k], &out[k].pose);
        assert_true(out[k].pose.knee.z > out[k].pose.hip.z - 0.2f); /* the knee still bends forward */
        /* the deltas turn the old bones onto the new ones */
        mm_vec3 thigh = mm_quat_rotate(out[k].thigh, mm_vec3_sub(legs[k].knee, legs[k].hip));
        mm_vec3 shin = mm_quat_rotate(out[k].shin, mm_vec3_sub(legs[k].foot, legs[k].knee));
        assert_near(mm_vec3_distance(thigh, mm_vec3_sub(out[k].pose.knee, out[k].pose.hip)), 0.0, 1e-5);
        assert_near(mm_vec3_distance(shin, mm_vec3_sub(out[k].pose.foot, out[k].pose.knee)), 0.0, 1e-5);
    }

    /* scale 1.6: the front foot 0.4 m ahead is out of reach; the pelvis comes down just enough */
    assert_int_equal(mm_warp_stride(legs, 2, fwd, 1.6f, 0.0f, out, &drop), MM_OK);
    double reach = 0.999 * 0.9, ahead = 0.4, side = 0.02;
    double expected = 0.82 - sqrt(reach * reach - ahead * ahead - side * side);
    assert_near(drop, expected, 1e-5);
    for (int k = 0; k < 2; ++k) {
        assert_near(out[k].pose.hip.y, legs[k].hip.y - expected, 1e-5);
        assert_near(mm_vec3_distance(out[k].pose.foot, out[k].target), 0.0, 1e-3); /* IK reaches */
        assert_near(out[k].pose.foot.z - out[k].pose.hip.z, 1.6 * (legs[k].foot.z - legs[k].hip.z), 1e-5);
        assert_lengths_kept(&legs[k], &out[k].pose);
    }
    assert_near(mm_vec3_distance(out[0].pose.foot, out[0].pose.hip), reach, 1e-5); /* the limiting leg */

    /* a diagonal direction: only the component along it scales */
    const mm_vec3 diag = mm_vec3_make(1, 0, 1);
    assert_int_equal(mm_warp_stride(legs, 2, diag, 0.8f, 0.0f, out, &drop), MM_OK);
    for (int k = 0; k < 2; ++k) {
        mm_vec3 u = mm_vec3_normalize(diag), v = mm_vec3_make(u.z, 0, -u.x);
        mm_vec3 before = mm_vec3_sub(legs[k].foot, legs[k].hip),
                after = mm_vec3_sub(out[k].pose.foot, out[k].pose.hip);
        assert_near(mm_vec3_dot(after, u), 0.8 * mm_vec3_dot(before, u), 1e-5);
        assert_near(mm_vec3_dot(after, v), mm_vec3_dot(before, v), 1e-5);
        assert_lengths_kept(&legs[k], &out[k].pose);
    }

    /* bad input: refused, the output the unchanged (finite) legs */
    assert_int_equal(mm_warp_stride(legs, 2, fwd, NAN, 0.0f, out, &drop), MM_ERR_INVALID_ARGUMENT);
    assert_near(mm_vec3_distance(out[0].pose.foot, legs[0].foot), 0.0, 0);
    assert_int_equal(mm_warp_stride(legs, 2, fwd, -1.0f, 0.0f, out, &drop), MM_ERR_INVALID_ARGUMENT);
    assert_int_equal(mm_warp_stride(legs, 0, fwd, 1.0f, 0.0f, out, &drop), MM_ERR_INVALID_ARGUMENT);
    mm_leg_pose broken[2] = {legs[0], legs[1]};
    broken[1].foot.y = NAN;
    assert_int_equal(mm_warp_stride(broken, 2, fwd, 1.2f, 0.0f, out, &drop), MM_ERR_INVALID_ARGUMENT);
    for (int k = 0; k < 2; ++k)
        assert_true(isfinite(out[k].pose.foot.y) && isfinite(out[k].pose.knee.x) && isfinite(out[k].thigh.w));
    assert_true(isfinite(drop));
}

static void test_leg_ik(void **state)
{
    (void)state;
    mm_leg_pose leg = make_leg(mm_vec3_make(0.0f, 1.0f, 0.0f), mm_vec3_make(0.0f, 0.2f, 0.1f));
    test_rng rng = {12345};
    mm_leg_warp w;
    for (int k = 0; k < 500; ++k) { /* reachable targets are reached, the lengths kept */
        mm_vec3 d = mm_vec3_make((float)test_rng_uniform(&rng, -1, 1), (float)test_rng_uniform(&rng, -1, 0.3),
                                 (float)test_rng_uniform(&rng, -1, 1));
        float r = (float)test_rng_uniform(&rng, 0.05, 0.88);
        mm_vec3 target = mm_vec3_add(leg.hip, mm_vec3_scale(mm_vec3_normalize(d), r));
        assert_int_equal(mm_warp_leg_ik(&leg, target, mm_vec3_make(0, 0, 1), 0.0f, &w), MM_OK);
        assert_near(mm_vec3_distance(w.pose.foot, target), 0.0, 1e-3);
        assert_lengths_kept(&leg, &w.pose);
    }
    /* out of reach: the leg points at the target, stretched to 0.999 of its length */
    mm_vec3 far = mm_vec3_make(0.0f, -1.0f, 0.5f);
    assert_int_equal(mm_warp_leg_ik(&leg, far, mm_vec3_make(0, 0, 1), 0.0f, &w), MM_OK);
    assert_near(mm_vec3_distance(w.pose.foot, leg.hip), 0.999 * 0.9, 1e-5);
    mm_vec3 a = mm_vec3_normalize(mm_vec3_sub(w.pose.foot, leg.hip)),
            b = mm_vec3_normalize(mm_vec3_sub(far, leg.hip));
    assert_near(mm_vec3_dot(a, b), 1.0, 1e-6);
    assert_lengths_kept(&leg, &w.pose);
    /* the knee keeps the side it bends to while the target sweeps across the knee's own line:
     * a leg bent in the x = 0 plane (knee forward, +z), targets moving from in front of the knee
     * to behind it; the knee stays in that plane, forward of the hip-target line, and moves
     * continuously (the knee's side of each new hip-target axis flips where the axis passes the
     * knee) */
    mm_leg_pose bent = {mm_vec3_make(0, 1, 0), mm_vec3_make(0, 0.58f, 0.15f), mm_vec3_make(0, 0.15f, 0.05f)};
    mm_vec3 before = bent.knee;
    for (int k = 0; k <= 100; ++k) {
        mm_vec3 target = mm_vec3_make(0.0f, 0.2f, 0.6f - 0.8f * (float)k / 100.0f);
        assert_int_equal(mm_warp_leg_ik(&bent, target, mm_vec3_make(0, 0, 1), 0.0f, &w), MM_OK);
        assert_near(w.pose.knee.x, 0.0, 1e-5);
        mm_vec3 axis = mm_vec3_sub(w.pose.foot, bent.hip), kh = mm_vec3_sub(w.pose.knee, bent.hip);
        /* forward of the line: the cross product's x (about +X, from axis to knee) is negative */
        assert_true(axis.y * kh.z - axis.z * kh.y < 0.0f);
        if (k > 0) assert_true(mm_vec3_distance(w.pose.knee, before) < 0.03f);
        before = w.pose.knee;
    }
    /* the animated leg passes through straight, its knee going from in front of the hip-foot line
     * to behind it (thigh angle +0.05 to -0.05 rad, the foot straight below the hip), while the
     * target asks for more bend (5 cm nearer the hip): the knee bends toward the pole all along
     * and moves continuously (taking the animated plane's side, it jumped to the back) */
    before = mm_vec3_make(0, 0, 0);
    for (int k = 0; k <= 100; ++k) {
        float theta = 0.05f - 0.1f * (float)k / 100.0f;
        mm_leg_pose passing = {mm_vec3_make(0, 1, 0),
                               mm_vec3_make(0, 1.0f - 0.45f * cosf(theta), 0.45f * sinf(theta)),
                               mm_vec3_make(0, 1.0f - 0.9f * cosf(theta), 0)};
        mm_vec3 target = mm_vec3_add(passing.foot, mm_vec3_make(0, 0.05f, 0));
        assert_int_equal(mm_warp_leg_ik(&passing, target, mm_vec3_make(0, 0, 1), 0.0f, &w), MM_OK);
        assert_near(mm_vec3_distance(w.pose.foot, target), 0.0, 1e-5);
        assert_lengths_kept(&passing, &w.pose);
        assert_true(w.pose.knee.z > 0.05f);
        if (k > 0) assert_true(mm_vec3_distance(w.pose.knee, before) < 0.01f);
        before = w.pose.knee;
    }
    /* a leg clearly bent against the pole (0.3 rad) keeps its bend when the target is its foot */
    mm_leg_pose against = {mm_vec3_make(0, 1, 0),
                           mm_vec3_make(0, 1.0f - 0.45f * cosf(0.3f), -0.45f * sinf(0.3f)),
                           mm_vec3_make(0, 1.0f - 0.9f * cosf(0.3f), 0)};
    assert_int_equal(mm_warp_leg_ik(&against, against.foot, mm_vec3_make(0, 0, 1), 0.0f, &w), MM_OK);
    assert_near(mm_vec3_distance(w.pose.knee, against.knee), 0.0, 1e-5);
    /* a straight leg bends toward the pole */
    mm_leg_pose straight = {mm_vec3_make(0, 1, 0), mm_vec3_make(0, 0.55f, 0), mm_vec3_make(0, 0.1f, 0)};
    assert_int_equal(mm_warp_leg_ik(&straight, mm_vec3_make(0, 0.3f, 0), mm_vec3_make(0, 0, 1), 0.0f, &w),
                     MM_OK);
    assert_true(w.pose.knee.z > 0.1f);
    assert_near(w.pose.foot.y, 0.3, 1e-5);
}

/* ---- orientation warping ------------------------------------------------------------------------ */

static void test_orientation_warp(void **state)
{
    (void)state;
    mm_warp_orientation_result w;
    const float weights[3] = {1.0f, 1.0f, 2.0f};
    mm_warp_orientation_params p;
    memset(&p, 0, sizeof p);
    p.spine_count = 3;
    p.spine_weights = weights;
    const mm_vec3 fz = mm_vec3_make(0, 0, 1);

    /* moving where it faces: the identity */
    assert_int_equal(mm_warp_orientation(fz, mm_vec3_make(0, 0, 3), 0.0f, 0.016f, &p, &w), MM_OK);
    assert_near(w.angle, 0.0, 1e-7);
    assert_near(mm_quat_angle_between(w.lower_body, mm_quat_identity()), 0.0, 1e-6);
    for (int i = 0; i < 3; ++i) assert_near(mm_quat_angle_between(w.spine[i], mm_quat_identity()), 0.0, 1e-6);

    /* 60 degrees to the right (toward +X): the legs take the movement direction, the spine turns
     * them back by its weights (1/4, 1/4, 1/2), the chest is as it was */
    const double a60 = MM_PI / 3.0;
    mm_vec3 move = mm_vec3_make((float)sin(a60), 0, (float)cos(a60));
    assert_int_equal(mm_warp_orientation(fz, move, 0.0f, 0.016f, &p, &w), MM_OK);
    assert_near(w.angle, a60, 1e-6);
    assert_int_equal(w.backward, 0);
    assert_near(mm_vec3_distance(mm_quat_rotate(w.lower_body, fz), move), 0.0, 1e-6);
    assert_near(mm_quat_angle_between(w.spine[0],
                                      mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), (float)(0.75 * a60))),
                0.0, 1e-5);
    assert_near(
        mm_quat_angle_between(w.spine[1], mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), (float)(0.5 * a60))),
        0.0, 1e-5);
    assert_near(mm_quat_angle_between(w.spine[2], mm_quat_identity()), 0.0, 1e-6);
    /* a planted foot turns with the lower body about the root */
    mm_vec3 foot = mm_warp_orientation_point(&w, mm_vec3_make(1, 0, 1), mm_vec3_make(1, 0, 1.5f));
    assert_near(foot.x, 1.0 + 0.5 * sin(a60), 1e-6);
    assert_near(foot.z, 1.0 + 0.5 * cos(a60), 1e-6);

    /* backwards: straight back is no correction, 135 degrees is -45 with the legs backward */
    assert_int_equal(mm_warp_orientation(fz, mm_vec3_make(0, 0, -1), 0.0f, 0.016f, &p, &w), MM_OK);
    assert_near(w.angle, 0.0, 1e-6);
    assert_int_equal(w.backward, 1);
    assert_int_equal(mm_warp_orientation(fz, mm_vec3_make(1, 0, -1), 0.0f, 0.016f, &p, &w), MM_OK);
    assert_near(w.angle, -MM_PI / 4.0, 1e-6);
    assert_int_equal(w.backward, 1);
    /* near 90 degrees the side chosen before is kept */
    p.max_angle = 2.0f;
    mm_vec3 m95 = mm_vec3_make((float)sin(95 * MM_DEG_TO_RAD), 0, (float)cos(95 * MM_DEG_TO_RAD));
    assert_int_equal(mm_warp_orientation(fz, m95, 1.5f, 0.016f, &p, &w), MM_OK);
    assert_near(w.angle, 95 * MM_DEG_TO_RAD, 1e-5);
    assert_int_equal(mm_warp_orientation(fz, m95, -1.0f, 0.016f, &p, &w), MM_OK);
    assert_near(w.angle, -85 * MM_DEG_TO_RAD, 1e-5);
    p.max_angle = 0.0f; /* the default clamp, 90 degrees */
    assert_int_equal(mm_warp_orientation(fz, m95, 1.5f, 0.016f, &p, &w), MM_OK);
    assert_near(w.angle, MM_PI / 2.0, 1e-5);

    /* the clamp */
    p.max_angle = 0.5f;
    assert_int_equal(mm_warp_orientation(fz, move, 0.0f, 0.016f, &p, &w), MM_OK);
    assert_near(w.angle, 0.5, 1e-6);
    p.max_angle = 0.0f;

    /* smoothing: e^(-speed dt), the same in one step or two */
    p.speed = 10.0f;
    assert_int_equal(mm_warp_orientation(fz, move, 0.0f, 0.1f, &p, &w), MM_OK);
    double one = w.angle;
    assert_near(one, a60 * (1.0 - exp(-1.0)), 1e-6);
    assert_int_equal(mm_warp_orientation(fz, move, 0.0f, 0.05f, &p, &w), MM_OK);
    assert_int_equal(mm_warp_orientation(fz, move, w.angle, 0.05f, &p, &w), MM_OK);
    assert_near(w.angle, one, 1e-6);
    /* standing: the correction fades back to 0 */
    assert_int_equal(mm_warp_orientation(fz, mm_vec3_make(0, 0, 0), 0.4f, 10.0f, &p, &w), MM_OK);
    assert_near(w.angle, 0.0, 1e-6);
    p.speed = 0.0f;

    /* the spring: from rest toward a60, the closed form of a critically damped spring
     * (x(t) = a60 (1 - (1 + y t) e^(-y t)), y from the half-life: half-way after one half-life),
     * in one step or in ten with the velocity carried; the velocity out is x'(t) = a60 y^2 t e^(-y t) */
    p.halflife = 0.1f;
    double y = mm_spring_damping(0.1f), t = 0.1;
    assert_int_equal(mm_warp_orientation(fz, move, 0.0f, 0.1f, &p, &w), MM_OK);
    assert_near(w.angle, 0.5 * a60, 1e-5);
    assert_near(w.angle, a60 * (1.0 - (1.0 + y * t) * exp(-y * t)), 1e-5);
    assert_near(w.velocity, a60 * y * y * t * exp(-y * t), 1e-4);
    float angle = 0.0f;
    p.velocity = 0.0f;
    for (int i = 0; i < 10; ++i) {
        assert_int_equal(mm_warp_orientation(fz, move, angle, 0.01f, &p, &w), MM_OK);
        angle = w.angle;
        p.velocity = w.velocity;
    }
    assert_near(angle, a60 * (1.0 - (1.0 + y * t) * exp(-y * t)), 1e-5);
    /* a target that jumps does not jump the rate: the exponential's rate steps from 0 to
     * speed x the jump at once, the spring's rises from 0 */
    p.velocity = 0.0f;
    assert_int_equal(mm_warp_orientation(fz, move, 0.0f, 1.0f / 60.0f, &p, &w), MM_OK);
    assert_true(w.velocity > 0.0f && w.velocity < 0.5 * a60 * 10.0);
    /* clamped: the rate is 0 */
    p.max_angle = 0.2f;
    p.velocity = 5.0f;
    assert_int_equal(mm_warp_orientation(fz, move, 0.19f, 0.1f, &p, &w), MM_OK);
    assert_near(w.angle, 0.2, 1e-6);
    assert_near(w.velocity, 0.0, 0);
    p.max_angle = 0.0f;
    p.velocity = NAN;
    assert_int_equal(mm_warp_orientation(fz, move, 0.0f, 0.1f, &p, &w), MM_ERR_INVALID_ARGUMENT);
    p.velocity = 0.0f;
    p.halflife = -1.0f;
    assert_int_equal(mm_warp_orientation(fz, move, 0.0f, 0.1f, &p, &w), MM_ERR_INVALID_ARGUMENT);
    p.halflife = 0.0f;

    /* bad input: refused, identity out */
    assert_int_equal(mm_warp_orientation(mm_vec3_make(NAN, 0, 1), move, 0.0f, 0.016f, &p, &w),
                     MM_ERR_INVALID_ARGUMENT);
    assert_near(w.angle, 0.0, 0);
    assert_true(isfinite(w.lower_body.w) && isfinite(w.spine[0].y));
    assert_int_equal(mm_warp_orientation(fz, move, NAN, 0.016f, &p, &w), MM_ERR_INVALID_ARGUMENT);
    p.spine_count = MM_WARP_ORIENTATION_MAX_SPINE + 1;
    assert_int_equal(mm_warp_orientation(fz, move, 0.0f, 0.016f, &p, &w), MM_ERR_INVALID_ARGUMENT);
    assert_int_equal(mm_warp_orientation(fz, move, 0.0f, 0.016f, NULL, &w), MM_OK); /* defaults */
    assert_near(w.angle, a60, 1e-6);
}

/* ---- hostile numbers ------------------------------------------------------------------------------ */

/* yaw (rad about +Y) of the rotation taking a to b: b = about_y(yaw) * a when it is a pure yaw */
static double yaw_between(mm_quat a, mm_quat b)
{
    mm_vec3 f = mm_quat_rotate(mm_quat_mul(b, mm_quat_conj(a)), mm_vec3_make(0, 0, 1));
    return atan2(f.x, f.z);
}

static void test_orientation_pose(void **state)
{
    (void)state;
    /* a hand-made chain: root -> pelvis -> spine0 -> spine1 -> chest, plus a thigh on the pelvis */
    const mm_quat parent = mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), 0.7f);
    const mm_quat local[5] = {
        mm_quat_from_axis_angle(mm_vec3_normalize(mm_vec3_make(0.3f, 1, 0.2f)), 0.4f), /* pelvis */
        mm_quat_from_axis_angle(mm_vec3_normalize(mm_vec3_make(1, 0.2f, 0)), 0.15f),   /* spine0 */
        mm_quat_from_axis_angle(mm_vec3_normalize(mm_vec3_make(0, 1, 1)), -0.2f),      /* spine1 */
        mm_quat_from_axis_angle(mm_vec3_normalize(mm_vec3_make(1, 0, 1)), 0.1f),       /* chest */
        mm_quat_from_axis_angle(mm_vec3_normalize(mm_vec3_make(1, 0, 0.1f)), 0.5f),    /* thigh */
    };
    mm_quat world[4];
    world[0] = mm_quat_mul(parent, local[0]);
    for (int i = 1; i < 4; ++i) world[i] = mm_quat_mul(world[i - 1], local[i]);
    const mm_quat thigh = mm_quat_mul(world[0], local[4]);
    mm_warp_orientation_params p;
    memset(&p, 0, sizeof p);
    p.spine_count = 3;
    mm_warp_orientation_result w;
    mm_quat pelvis_local = local[0], spine_local[3] = {local[1], local[2], local[3]};

    /* angle 0: nothing is written, bit for bit */
    assert_int_equal(mm_warp_orientation(mm_vec3_make(0, 0, 1), mm_vec3_make(0, 0, 2), 0.0f, 0.016f, &p, &w),
                     MM_OK);
    assert_int_equal(mm_warp_orientation_pose(&w, parent, world[0], &world[1], 3, &pelvis_local, spine_local),
                     MM_OK);
    assert_memory_equal(&pelvis_local, &local[0], sizeof pelvis_local);
    assert_memory_equal(spine_local, &local[1], sizeof spine_local);

    /* 50 degrees: the pelvis and the thigh hanging from it turn by 50 degrees about +Y, the chest
     * keeps its world rotation, the spine in between turns by a third less per joint */
    const double a = 50.0 * MM_PI / 180.0;
    assert_int_equal(mm_warp_orientation(mm_vec3_make(0, 0, 1), mm_vec3_make((float)sin(a), 0, (float)cos(a)),
                                         0.0f, 0.016f, &p, &w),
                     MM_OK);
    assert_near(w.angle, a, 1e-5);
    assert_int_equal(mm_warp_orientation_pose(&w, parent, world[0], &world[1], 3, &pelvis_local, spine_local),
                     MM_OK);
    mm_quat after[4];
    after[0] = mm_quat_mul(parent, pelvis_local);
    for (int i = 1; i < 4; ++i) after[i] = mm_quat_mul(after[i - 1], spine_local[i - 1]);
    assert_near(
        mm_quat_angle_between(
            after[0], mm_quat_mul(mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), (float)a), world[0])),
        0.0, 1e-5);
    assert_near(yaw_between(thigh, mm_quat_mul(after[0], local[4])), a, 1e-4);
    assert_near(yaw_between(world[1], after[1]), a * 2.0 / 3.0, 1e-4);
    assert_near(yaw_between(world[2], after[2]), a / 3.0, 1e-4);
    assert_near(mm_quat_angle_between(after[3], world[3]), 0.0, 1e-5); /* the chest keeps facing */

    assert_int_equal(
        mm_warp_orientation_pose(NULL, parent, world[0], &world[1], 3, &pelvis_local, spine_local),
        MM_ERR_INVALID_ARGUMENT);
    assert_int_equal(mm_warp_orientation_pose(&w, parent, world[0], &world[1],
                                              MM_WARP_ORIENTATION_MAX_SPINE + 1, &pelvis_local, spine_local),
                     MM_ERR_INVALID_ARGUMENT);
}

static int joint_named(const mm_database *db, const char *name)
{
    for (int j = 0; j < db->joint_count; ++j)
        if (strcmp(db->joints[j].name, name) == 0) return j;
    return -1;
}

/* The controller on the built-in set: strafing diagonally while facing ahead. Without strafe the
 * angle stays exactly 0; with it, it stays within the maximum, moves at most as fast as the
 * smoothing lets it, and when it is not 0 the hips have turned by it (against the pose before the
 * layers) while the head keeps its world rotation. */
static void test_orientation_controller(void **state)
{
    (void)state;
    mm_database db;
    mm_searcher searcher;
    assert_int_equal(test_build_synth_database(&db), 0);
    assert_int_equal(mm_searcher_init(&searcher, &db, NULL, NULL), MM_OK);
    const int hips = joint_named(&db, "Hips"), head = joint_named(&db, "Head");
    assert_true(hips > 0 && head > 0);
    for (int strafe = 0; strafe < 2; ++strafe) {
        mm_character_desc d;
        mm_character_defaults(&d);
        d.warping = true;
        d.no_foot_ik = true;             /* compare with the animated pose: no layer after warping */
        d.stride_min = d.stride_max = 1; /* and no stride warping */
        d.orientation_max = 0.6f;
        d.orientation_speed = 6.0f;
        mm_character c;
        assert_int_equal(mm_character_init(&c, &db, &searcher, &d, NULL), MM_OK);
        mm_input in;
        memset(&in, 0, sizeof in);
        in.stick[0] = 0.6f, in.stick[1] = 0.6f;
        in.strafe = strafe;
        in.has_facing = strafe;
        in.facing[1] = 1.0f;
        const float dt = 1.0f / 60.0f;
        const double bound = 2.0 * 0.6 * (1.0 - exp(-6.0 * dt)) + 1e-5;
        float previous = 0.0f, largest = 0.0f;
        int checked = 0;
        mm_xform *pose = test_malloc(sizeof(mm_xform) * (size_t)db.joint_count);
        for (int tick = 0; tick < 600; ++tick) {
            mm_character_update(&c, &in, dt);
            float a = c.state->warping.orientation_angle;
            if (!strafe) assert_true(a == 0.0f);
            assert_true(fabsf(a) <= 0.6f + 1e-6f);
            assert_true(fabsf(a - previous) <= bound);
            previous = a;
            largest = fmaxf(largest, fabsf(a));
            if (fabsf(a) < 0.05f) continue;
            pose[0] = c.root;
            for (int j = 1; j < db.joint_count; ++j)
                pose[j] =
                    mm_xform_mul(pose[db.joints[j].parent], mm_xform_make(c.state->transition.rotations[j],
                                                                          c.state->transition.positions[j]));
            assert_near(mm_quat_angle_between(c.global[hips].rotation,
                                              mm_quat_mul(mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), a),
                                                          pose[hips].rotation)),
                        0.0, 1e-3);
            assert_near(mm_quat_angle_between(c.global[head].rotation, pose[head].rotation), 0.0, 1e-3);
            ++checked;
        }
        if (strafe) assert_true(checked > 30 && largest > 0.3f);
        test_free(pose);
        mm_character_free(&c);
    }
    mm_searcher_free(&searcher);
    mm_database_free(&db);
}

static float hostile(test_rng *rng)
{
    static const float special[] = {NAN,   INFINITY, -INFINITY, 1e30f, -1e30f,
                                    3e38f, -3e38f,   0.0f,      -1.0f, 1e-30f};
    if (test_rng_next(rng) % 3 == 0) return special[test_rng_next(rng) % 10];
    return (float)test_rng_uniform(rng, -3.0, 3.0);
}

static mm_vec3 hostile3(test_rng *rng) { return mm_vec3_make(hostile(rng), hostile(rng), hostile(rng)); }

static int finite_vec(mm_vec3 v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z); }

/* Stride warping in the controller on the built-in set, stick on and off (starts and stops, which
 * are no loops): the stride scale stays in its clamp and, outside loop cycles (played at their
 * exact ratio) and the falls back to 1 at rest, moves per tick at most by what its 0.1 s half-life
 * filter allows across the clamp; the pelvis drop never jumps by more than its 0.05 s filter allows
 * over a 1 m drop, and the pelvis is lowered by exactly that drop against the pose before the
 * layers. */
static void test_stride_controller(void **state)
{
    (void)state;
    mm_database db;
    mm_searcher searcher;
    assert_int_equal(test_build_synth_database(&db), 0);
    assert_int_equal(mm_searcher_init(&searcher, &db, NULL, NULL), MM_OK);
    mm_character_desc d;
    mm_character_defaults(&d);
    d.warping = true;
    d.distance_matching = true;
    d.no_foot_ik = true;
    mm_character c;
    assert_int_equal(mm_character_init(&c, &db, &searcher, &d, NULL), MM_OK);
    const float dt = 1.0f / 60.0f;
    const double scale_step = (1.0 - exp2(-dt / 0.1)) * (d.stride_max - d.stride_min) + 1e-5;
    const double drop_step = (1.0 - exp2(-dt / 0.05)) * 1.0 + 1e-5;
    float scale = 1.0f, drop = 0.0f;
    int previous_playback = MM_PLAYBACK_CLOCK, smoothed = 0, dropped = 0;
    const int pelvis = c.state->rig.pelvis;
    assert_true(pelvis > 0);
    for (int tick = 0; tick < 1200; ++tick) {
        mm_input in;
        memset(&in, 0, sizeof in);
        int on = (tick / 150) % 2 == 0;
        in.stick[1] = on ? 1.0f : 0.0f;
        in.stick[0] = on ? 0.3f : 0.0f;
        mm_character_update(&c, &in, dt);
        assert_true(c.stride_scale >= d.stride_min - 1e-6f && c.stride_scale <= d.stride_max + 1e-6f);
        assert_true(c.state->warping.stride_drop >= 0.0f && c.state->warping.stride_drop <= 1.0f);
        if (c.playback != MM_PLAYBACK_CYCLE && previous_playback != MM_PLAYBACK_CYCLE &&
            c.stride_scale != 1.0f && scale != 1.0f) {
            assert_true(fabsf(c.stride_scale - scale) <= scale_step);
            ++smoothed;
        }
        assert_true(fabsf(c.state->warping.stride_drop - drop) <= drop_step);
        if (c.state->warping.stride_drop > 0.0f) {
            mm_vec3 lowered = mm_vec3_sub(c.state->transition.positions[pelvis], c.local_positions[pelvis]);
            mm_vec3 world = mm_quat_rotate(c.global[db.joints[pelvis].parent].rotation, lowered);
            assert_near(world.y, c.state->warping.stride_drop, 1e-4);
            ++dropped;
        }
        scale = c.stride_scale, drop = c.state->warping.stride_drop;
        previous_playback = c.playback;
    }
    printf("smoothed scale ticks %d, dropped ticks %d\n", smoothed, dropped);
    mm_character_free(&c);
    mm_searcher_free(&searcher);
    mm_database_free(&db);
}

/* Whatever comes in (NaN, infinities, 1e38), nothing non-finite comes out. */
static void test_hostile_numbers(void **state)
{
    (void)state;
    static float pos[3 * MAX_CLIP];
    int n = sample_path(two_stops, 0.6, 0.8, 30.0, 211, pos);
    mm_distance_curve one = build(pos, 3, n, 30.0f, 0), loop = build(pos, 3, n, 30.0f, 1);
    test_rng rng = {77};
    for (int k = 0; k < 20000; ++k) {
        const mm_distance_curve *c = k & 1 ? &loop : &one;
        float t = 0.0f, rate = 0.0f;
        mm_distance_advance(c, hostile(&rng), hostile(&rng), hostile(&rng), hostile(&rng), hostile(&rng), &t,
                            &rate);
        assert_true(isfinite(t) && isfinite(rate) && t >= 0.0f && t <= mm_distance_duration(c));
        mm_distance_match_to_target(c, (int)(test_rng_next(&rng) % 3), hostile(&rng), &t);
        assert_true(isfinite(t));
        assert_true(isfinite(mm_distance_time_after(c, (float)test_rng_uniform(&rng, 0, 7), hostile(&rng))));
        assert_true(isfinite(mm_distance_signed(c, hostile(&rng))));
        assert_true(isfinite(mm_distance_travelled(c, (float)test_rng_uniform(&rng, -1e6, 1e6))));
        mm_distance_play_rate(hostile(&rng), hostile(&rng), hostile(&rng), hostile(&rng), &rate);
        assert_true(isfinite(rate));

        mm_distance_prediction p;
        mm_distance_predict_stop(hostile3(&rng), hostile3(&rng), hostile(&rng), hostile(&rng), &p);
        assert_true(finite_vec(p.offset) && isfinite(p.distance) && isfinite(p.time));
        mm_distance_predict_pivot(hostile3(&rng), hostile3(&rng), hostile3(&rng), hostile(&rng), &p);
        assert_true(finite_vec(p.offset) && isfinite(p.distance) && isfinite(p.time));

        mm_leg_pose legs[2];
        for (int i = 0; i < 2; ++i) {
            legs[i] = make_leg(mm_vec3_make(0.1f - 0.2f * i, 0.9f, 0.0f),
                               mm_vec3_make(0.1f, 0.1f, 0.2f - 0.4f * i));
            if (test_rng_next(&rng) % 4 == 0) legs[i].foot = hostile3(&rng);
            if (test_rng_next(&rng) % 8 == 0) legs[i].hip = hostile3(&rng);
        }
        mm_leg_warp out[2];
        float drop = 0.0f;
        mm_warp_stride(legs, 2, hostile3(&rng), hostile(&rng), hostile(&rng), out, &drop);
        assert_true(isfinite(drop));
        for (int i = 0; i < 2; ++i)
            assert_true(finite_vec(out[i].pose.hip) && finite_vec(out[i].pose.knee) &&
                        finite_vec(out[i].pose.foot) && isfinite(out[i].thigh.w) && isfinite(out[i].shin.x));
        mm_warp_leg_ik(&legs[0], hostile3(&rng), hostile3(&rng), hostile(&rng), &out[0]);
        assert_true(finite_vec(out[0].pose.knee) && finite_vec(out[0].pose.foot) && isfinite(out[0].thigh.y));

        mm_warp_orientation_result w;
        mm_warp_orientation_params op;
        memset(&op, 0, sizeof op);
        op.max_angle = test_rng_next(&rng) % 2 ? hostile(&rng) : 0.0f;
        op.speed = test_rng_next(&rng) % 2 ? hostile(&rng) : 0.0f;
        op.spine_count = 2;
        mm_warp_orientation(hostile3(&rng), hostile3(&rng), hostile(&rng), hostile(&rng), &op, &w);
        assert_true(isfinite(w.angle) && isfinite(w.lower_body.w) && isfinite(w.spine[0].y) &&
                    isfinite(w.spine[1].w));
        assert_true(finite_vec(mm_warp_orientation_point(&w, mm_vec3_make(0, 0, 0), mm_vec3_make(1, 0, 1))));
    }
    mm_distance_curve_free(&one);
    mm_distance_curve_free(&loop);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_constant_line),
        cmocka_unit_test(test_spring_stop),
        cmocka_unit_test(test_loop_circle),
        cmocka_unit_test(test_loop_stops),
        cmocka_unit_test(test_two_stops),
        cmocka_unit_test(test_pivot),
        cmocka_unit_test(test_stop_then_sway),
        cmocka_unit_test(test_round_trip),
        cmocka_unit_test(test_play_rate),
        cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_predict_stop_closed_form),
        cmocka_unit_test(test_predict_against_simulation),
        cmocka_unit_test(test_stride_warp),
        cmocka_unit_test(test_leg_ik),
        cmocka_unit_test(test_orientation_warp),
        cmocka_unit_test(test_orientation_pose),
        cmocka_unit_test(test_orientation_controller),
        cmocka_unit_test(test_stride_controller),
        cmocka_unit_test(test_hostile_numbers),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
