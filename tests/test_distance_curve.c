/* Distance curves against independent truth: root paths whose distance is known in closed form (a
 * constant-speed line, a spring coming to rest, a circle, loops that stop, two stops, a pivot, a
 * stop followed by a sway), the builder's and the validator's refusals, and hostile numbers given
 * to the queries. Moving a playhead on these curves is test_distance_matching's. */
#include <math.h>

#include <mm/distance_curve.h>
#include <mm/distance_curve_build.h>

#include "test_distance_paths.h"
#include "test_hostile.h"
#include "test_util.h"

/* ---- a constant-speed line --------------------------------------------------------------- */

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
    /* one-shots stop at the last frame */
    assert_near(mm_distance_time_after(&c, 2.5f, 100.0f), 3.0, 1e-6);
    mm_distance_curve_free(&c);
}

/* ---- a spring stop ------------------------------------------------------------------------ */

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
    mm_distance_curve_free(&c);
}

/* ---- loops -------------------------------------------------------------------------------- */

static void test_loop_circle(void **state)
{
    (void)state;
    static float pos[2 * MAX_CLIP];
    const int n = 120;
    const float fps = 30.0f;
    const double r = 2.0;
    circle_loop(pos, n, r); /* one turn in 4 s */
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
    /* whole loops are skipped at once */
    assert_near(mm_distance_time_after(&c, 1.0f, (float)(2.5 * L)), 1.0 + 2.5 * T, 1e-4);
    assert_near(mm_distance_time_after(&c, 3.9f, (float)(L / T * 0.3)), 4.2, 1e-4);
    mm_distance_curve_free(&c);
}

static void test_loop_stops(void **state)
{
    (void)state;
    static float pos[2 * MAX_CLIP];
    const float fps = 30.0f;
    const int n = 120;
    for (loop_stops = 1; loop_stops <= 2; ++loop_stops) {
        stopping_loop_path(pos, n, fps);
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
        /* the segment holding the wrap has the stop at the wrap */
        int seg = mm_distance_segment_at(&c, 0.0f);
        assert_int_equal(c.segments[seg].marker_frame, 0);
        mm_distance_curve_free(&c);
    }
}

/* ---- two stops, a pivot ------------------------------------------------------------------- */

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

    /* bad numbers are refused, the outputs stay finite */
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
}

/* ---- hostile numbers ------------------------------------------------------------------------ */

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
        assert_true(isfinite(mm_distance_time_after(c, (float)test_rng_uniform(&rng, 0, 7), hostile(&rng))));
        assert_true(isfinite(mm_distance_signed(c, hostile(&rng))));
        assert_true(isfinite(mm_distance_travelled(c, (float)test_rng_uniform(&rng, -1e6, 1e6))));
    }
    mm_distance_curve_free(&one);
    mm_distance_curve_free(&loop);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_constant_line),   cmocka_unit_test(test_spring_stop),
        cmocka_unit_test(test_loop_circle),     cmocka_unit_test(test_loop_stops),
        cmocka_unit_test(test_two_stops),       cmocka_unit_test(test_pivot),
        cmocka_unit_test(test_stop_then_sway),  cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_hostile_numbers),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
