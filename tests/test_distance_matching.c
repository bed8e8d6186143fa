/* Distance matching against independent truth: on root paths whose distance is known in closed
 * form (a constant-speed line, a spring coming to rest, a circle, loops that stop, two stops) the
 * playhead advanced by distance travels exactly as far, matching to a target distance finds the
 * time the path gives, round trips agree, the play-rate and stride-scale clamps hold, and bad or
 * hostile numbers give finite outputs. The curves themselves are test_distance_curve's. */
#include <math.h>

#include <mm/distance_curve.h>
#include <mm/distance_curve_build.h>
#include <mm/distance_matching.h>

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

static void test_spring_stop(void **state)
{
    (void)state;
    static float pos[3 * MAX_CLIP];
    const float fps = 60.0f;
    int n = sample_path(spring_stop, 1.0, 0.0, fps, 301, pos); /* 5 s */
    mm_distance_curve c = build(pos, 3, n, fps, 0);
    const double rest = 1.5 + 2.0 * 1.5 / spring_y(); /* where it comes to rest: 1.5 + 2 v0 / y */
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
    /* advancing over the wrap lands after it */
    float t = -1.0f, rate = 0.0f;
    const float dt = 0.1f;
    assert_int_equal(mm_distance_advance(&c, 3.95f, (float)(L / T * dt), dt, 0.75f, 1.25f, &t, &rate), MM_OK);
    assert_near(t, 0.05, 1e-4);
    assert_near(rate, 1.0, 1e-3);
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
        /* the segment holding the wrap: 0.5 m before the stop at the wrap is before the wrap */
        int seg = mm_distance_segment_at(&c, 0.0f);
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

/* ---- two stops ---------------------------------------------------------------------------- */

static void test_two_stops(void **state)
{
    (void)state;
    static float pos[3 * MAX_CLIP];
    const float fps = 30.0f;
    int n = sample_path(two_stops, 0.6, -0.8, fps, 211, pos);
    mm_distance_curve c = build(pos, 3, n, fps, 0);
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
    mm_distance_curve c = build(pos, 3, 10, 30.0f, 0);

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
    mm_distance_curve_free(&c);

    /* an in-place clip: nothing to match, it plays on at rate 1 */
    float still[2 * 8] = {0};
    c = build(still, 2, 8, 30.0f, 1);
    assert_int_equal(mm_distance_advance(&c, 0.1f, 0.5f, 0.1f, 0.75f, 1.25f, &t, &rate), MM_ERR_OUT_OF_RANGE);
    assert_near(rate, 1.0, 0);
    assert_near(t, 0.2, 1e-6);
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
        float t = 0.0f, rate = 0.0f;
        mm_distance_advance(c, hostile(&rng), hostile(&rng), hostile(&rng), hostile(&rng), hostile(&rng), &t,
                            &rate);
        assert_true(isfinite(t) && isfinite(rate) && t >= 0.0f && t <= mm_distance_duration(c));
        mm_distance_match_to_target(c, (int)(test_rng_next(&rng) % 3), hostile(&rng), &t);
        assert_true(isfinite(t));
        mm_distance_play_rate(hostile(&rng), hostile(&rng), hostile(&rng), hostile(&rng), &rate);
        assert_true(isfinite(rate));
    }
    mm_distance_curve_free(&one);
    mm_distance_curve_free(&loop);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_constant_line),   cmocka_unit_test(test_spring_stop),
        cmocka_unit_test(test_loop_circle),     cmocka_unit_test(test_loop_stops),
        cmocka_unit_test(test_two_stops),       cmocka_unit_test(test_round_trip),
        cmocka_unit_test(test_play_rate),       cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_hostile_numbers),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
