/* Target matching: a bone reaches a static or moving target exactly at the end of the window,
 * weights leave axes alone, nothing happens outside the window, and bad input does no harm. */
#include <math.h>

#include <mm/target_match.h>

#include "test_util.h"

static const mm_vec3 up = {0.0f, 1.0f, 0.0f};

/* A clip's root motion: the root at clip time t is C(t) = (yaw rate * t, path(t)); the matched
 * bone sits at a fixed transform B relative to the root. The character is A * C(t), where A,
 * the anchor, takes the root corrections. */
typedef struct motion {
    float yaw_rate;   /* rad/s */
    mm_vec3 velocity; /* m/s */
    float wobble;     /* amplitude of a sideways sine, m */
    mm_xform bone;    /* B */
} motion;

static mm_xform clip_root(const motion *m, float t)
{
    mm_vec3 p =
        mm_vec3_add(mm_vec3_scale(m->velocity, t), mm_vec3_make(m->wobble * sinf(3.0f * t), 0.0f, 0.0f));
    return mm_xform_make(mm_quat_from_axis_angle(up, m->yaw_rate * t), p);
}

static mm_xform bone_at(const motion *m, mm_xform anchor, float t)
{
    return mm_xform_mul(mm_xform_mul(anchor, clip_root(m, t)), m->bone);
}

static motion make_motion(float yaw_rate, float wobble)
{
    motion m;
    m.yaw_rate = yaw_rate;
    m.velocity = mm_vec3_make(0.1f, 0.0f, 1.2f);
    m.wobble = wobble;
    m.bone = mm_xform_make(mm_quat_from_axis_angle(up, 0.4f), mm_vec3_make(0.3f, 1.0f, 0.2f));
    return m;
}

typedef void (*target_fn)(mm_target_match *match, float t);

/* Plays ticks of dt from time 0 to 2.5 s; returns the anchor. *active counts the ticks that
 * corrected. */
static mm_xform play(mm_target_match *match, const motion *m, mm_xform anchor, float dt, target_fn target,
                     int *active)
{
    *active = 0;
    for (int k = 0; k < (int)(2.5f / dt); ++k) {
        float t = (float)k * dt;
        if (target) target(match, t + dt < match->end_time ? t + dt : match->end_time);
        mm_xform c;
        bool on = mm_target_match_step(match, t, dt, bone_at(m, anchor, match->end_time), &c);
        if (!on) {
            assert_true(fabsf(c.translation.x) + fabsf(c.translation.y) + fabsf(c.translation.z) == 0.0f);
            assert_true(c.rotation.w == 1.0f);
        }
        *active += on;
        if (on && !(t + dt > match->start_time && t < match->end_time))
            fail_msg("corrected at t = %g outside [%g, %g]", t, match->start_time, match->end_time);
        anchor = mm_xform_mul(c, anchor);
    }
    return anchor;
}

static void expect_at(mm_xform got, mm_vec3 position, float yaw, float eps)
{
    mm_vec3 d = mm_vec3_sub(got.translation, position);
    float dy = remainderf(mm_target_match_yaw(got.rotation) - yaw, (float)(2 * MM_PI));
    if (mm_vec3_length(d) > eps || fabsf(dy) > eps)
        fail_msg("bone at (%.7g %.7g %.7g) yaw %.7g, target (%.7g %.7g %.7g) yaw %.7g", got.translation.x,
                 got.translation.y, got.translation.z, mm_target_match_yaw(got.rotation), position.x,
                 position.y, position.z, yaw);
}

static void test_yaw(void **state)
{
    (void)state;
    assert_true(fabsf(mm_target_match_yaw(mm_quat_from_axis_angle(up, 1.0f)) - 1.0f) < 1e-6f);
    assert_true(fabsf(mm_target_match_yaw(mm_quat_from_axis_angle(up, -2.5f)) + 2.5f) < 1e-6f);
    mm_quat tilted = mm_quat_mul(mm_quat_from_axis_angle(up, 0.7f),
                                 mm_quat_from_axis_angle(mm_vec3_make(1.0f, 0.0f, 0.0f), 0.3f));
    assert_true(fabsf(mm_target_match_yaw(tilted) - 0.7f) < 1e-6f);
    assert_true(mm_target_match_yaw(mm_quat_make(0, 0, 0, 0)) == 0.0f);
}

static void test_linear_motion_static_target(void **state)
{
    (void)state;
    motion m = make_motion(0.0f, 0.0f);
    mm_vec3 target = mm_vec3_make(0.5f, 1.1f, 3.0f);
    float yaw = 0.35f;
    mm_target_match match;
    mm_target_match_init(&match, 7, target, mm_quat_from_axis_angle(up, yaw), 0.0f, 1.0f);
    mm_target_match_set_normalized(&match, 0.25f, 0.75f, 2.0f); /* [0.5, 1.5] */
    assert_int_equal(match.bone, 7);
    assert_true(match.start_time == 0.5f && match.end_time == 1.5f);
    int active = 0;
    mm_xform anchor = play(&match, &m, mm_xform_identity(), 1.0f / 60.0f, NULL, &active);
    assert_in_range(active, 59, 61);
    expect_at(bone_at(&m, anchor, 1.5f), target, yaw, 1e-5f);

    /* the error is spread evenly: the first tick of the window corrects 1/60 of it */
    mm_target_match_init(&match, 0, target, mm_quat_from_axis_angle(up, yaw), 0.5f, 1.5f);
    mm_xform c;
    mm_xform predicted = bone_at(&m, mm_xform_identity(), 1.5f);
    assert_true(mm_target_match_step(&match, 0.5f, 1.0f / 60.0f, predicted, &c));
    mm_vec3 moved = mm_xform_apply_point(c, predicted.translation); /* where the end moves to */
    mm_vec3 want = mm_vec3_lerp(predicted.translation, target, 1.0f / 60.0f);
    assert_true(mm_vec3_distance(moved, want) < 1e-5f);
    assert_true(fabsf(mm_target_match_yaw(c.rotation) -
                      (yaw - mm_target_match_yaw(predicted.rotation)) / 60.0f) < 1e-6f);
}

static void test_turning_motion_static_target(void **state)
{
    (void)state;
    motion m = make_motion(0.8f, 0.3f);
    mm_xform start = mm_xform_make(mm_quat_from_axis_angle(up, 0.5f), mm_vec3_make(-1.0f, 0.0f, 2.0f));
    mm_vec3 target = mm_vec3_make(0.2f, 0.9f, 2.5f);
    float yaw = -2.9f; /* across the +-pi seam from where the clip goes */
    mm_target_match match;
    mm_target_match_init(&match, 0, target, mm_quat_from_axis_angle(up, yaw), 0.3f, 1.7f);
    int active = 0;
    mm_xform anchor = play(&match, &m, start, 1.0f / 30.0f, NULL, &active);
    assert_true(active > 0);
    expect_at(bone_at(&m, anchor, 1.7f), target, yaw, 1e-5f);
}

static void moving_target(mm_target_match *match, float t)
{
    match->target_position = mm_vec3_make(0.5f + 0.8f * t, 1.1f, 3.0f - 0.4f * t);
    match->target_rotation = mm_quat_from_axis_angle(up, 0.2f + 0.5f * t);
}

static void test_moving_target(void **state)
{
    (void)state;
    for (int turning = 0; turning < 2; ++turning) {
        motion m = make_motion(turning ? -0.6f : 0.0f, turning ? 0.2f : 0.0f);
        mm_target_match match;
        mm_target_match_init(&match, 0, mm_vec3_make(0, 0, 0), mm_quat_identity(), 0.4f, 1.4f);
        int active = 0;
        mm_xform anchor = play(&match, &m, mm_xform_identity(), 1.0f / 60.0f, moving_target, &active);
        mm_target_match at_end;
        moving_target(&at_end, 1.4f);
        expect_at(bone_at(&m, anchor, 1.4f), at_end.target_position, 0.2f + 0.5f * 1.4f, 1e-5f);
    }
}

static void test_weights(void **state)
{
    (void)state;
    motion m = make_motion(0.4f, 0.0f);
    mm_xform free_end = bone_at(&m, mm_xform_identity(), 1.5f); /* where the clip alone goes */
    mm_vec3 target = mm_vec3_make(0.5f, 1.6f, 3.0f);
    mm_target_match match;
    mm_target_match_init(&match, 0, target, mm_quat_from_axis_angle(up, 1.0f), 0.5f, 1.5f);
    match.position_weight = mm_vec3_make(1.0f, 0.0f, 0.5f);
    match.rotation_weight = 0.0f;
    int active = 0;
    mm_xform anchor = play(&match, &m, mm_xform_identity(), 1.0f / 60.0f, NULL, &active);
    mm_xform end = bone_at(&m, anchor, 1.5f);
    assert_true(fabsf(end.translation.x - target.x) < 1e-5f);
    assert_true(fabsf(end.translation.y - free_end.translation.y) < 1e-6f); /* y left alone */
    assert_true(fabsf(end.translation.z - 0.5f * (free_end.translation.z + target.z)) < 1e-5f);
    assert_true(fabsf(mm_target_match_yaw(end.rotation) - mm_target_match_yaw(free_end.rotation)) < 1e-6f);
    assert_true(fabsf(mm_target_match_yaw(anchor.rotation)) < 1e-6f); /* the root never turned */

    /* rotation only */
    mm_target_match_init(&match, 0, target, mm_quat_from_axis_angle(up, 1.0f), 0.5f, 1.5f);
    match.position_weight = mm_vec3_make(0.0f, 0.0f, 0.0f);
    anchor = play(&match, &m, mm_xform_identity(), 1.0f / 60.0f, NULL, &active);
    end = bone_at(&m, anchor, 1.5f);
    expect_at(end, free_end.translation, 1.0f, 1e-5f); /* the turn is about the bone's end point */
}

static void test_outside_the_window(void **state)
{
    (void)state;
    motion m = make_motion(0.0f, 0.0f);
    mm_target_match match;
    mm_target_match_init(&match, 0, mm_vec3_make(1, 1, 1), mm_quat_identity(), 0.5f, 1.5f);
    mm_target_match before = match;
    mm_xform c, predicted = bone_at(&m, mm_xform_identity(), 1.5f);
    assert_false(mm_target_match_step(&match, 1.5f, 0.1f, predicted, &c)); /* at the end: passed */
    assert_false(mm_target_match_step(&match, 2.0f, 0.1f, predicted, &c));
    assert_false(mm_target_match_step(&match, 0.3f, 0.2f, predicted, &c)); /* ends at the start */
    assert_false(mm_target_match_step(&match, 0.6f, 0.0f, predicted, &c)); /* no time */
    assert_memory_equal(&match, &before, sizeof match);
    assert_true(c.translation.x == 0.0f && c.translation.y == 0.0f && c.translation.z == 0.0f);
    assert_true(c.rotation.x == 0.0f && c.rotation.y == 0.0f && c.rotation.z == 0.0f && c.rotation.w == 1.0f);
    /* a tick that straddles the end corrects everything at once */
    assert_true(mm_target_match_step(&match, 1.45f, 0.1f, predicted, &c));
    expect_at(mm_xform_mul(c, predicted), mm_vec3_make(1, 1, 1), 0.0f, 1e-6f);
    /* a window with no length does nothing */
    mm_target_match_init(&match, 0, mm_vec3_make(1, 1, 1), mm_quat_identity(), 1.0f, 1.0f);
    assert_false(mm_target_match_step(&match, 0.9f, 0.2f, predicted, &c));
    assert_false(mm_target_match_step(NULL, 0.9f, 0.2f, predicted, &c));
}

static bool finite_xform(mm_xform x)
{
    return isfinite(x.translation.x) && isfinite(x.translation.y) && isfinite(x.translation.z) &&
           isfinite(x.rotation.x) && isfinite(x.rotation.y) && isfinite(x.rotation.z) &&
           isfinite(x.rotation.w);
}

static void test_nan_inputs(void **state)
{
    (void)state;
    motion m = make_motion(0.3f, 0.0f);
    mm_xform predicted = bone_at(&m, mm_xform_identity(), 1.5f), bad = predicted, c;
    mm_target_match match, before;
    mm_target_match_init(&match, 0, mm_vec3_make(1, 1, 1), mm_quat_identity(), 0.5f, 1.5f);
    before = match;
    bad.translation.y = NAN;
    assert_false(mm_target_match_step(&match, 1.0f, 0.1f, bad, &c));
    assert_true(finite_xform(c));
    bad = predicted;
    bad.rotation.w = INFINITY;
    assert_false(mm_target_match_step(&match, 1.0f, 0.1f, bad, &c));
    assert_false(mm_target_match_step(&match, NAN, 0.1f, predicted, &c));
    assert_false(mm_target_match_step(&match, 1.0f, NAN, predicted, &c));
    assert_true(finite_xform(c));
    assert_memory_equal(&match, &before, sizeof match);
    match.target_position.x = NAN;
    assert_false(mm_target_match_step(&match, 1.0f, 0.1f, predicted, &c));
    match.target_position.x = 1.0f;
    match.rotation_weight = NAN;
    assert_false(mm_target_match_step(&match, 1.0f, 0.1f, predicted, &c));
    match.rotation_weight = 1.0f;
    match.end_time = NAN;
    assert_false(mm_target_match_step(&match, 1.0f, 0.1f, predicted, &c));
    match.end_time = 1.5f;
    assert_true(finite_xform(c));
    /* after all that, an ordinary tick works and stays finite */
    assert_true(mm_target_match_step(&match, 1.0f, 0.1f, predicted, &c));
    assert_true(finite_xform(c));
    assert_true(isfinite(match.applied_yaw) && isfinite(match.applied_translation.x));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_yaw),
        cmocka_unit_test(test_linear_motion_static_target),
        cmocka_unit_test(test_turning_motion_static_target),
        cmocka_unit_test(test_moving_target),
        cmocka_unit_test(test_weights),
        cmocka_unit_test(test_outside_the_window),
        cmocka_unit_test(test_nan_inputs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
