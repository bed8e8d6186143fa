/* Stride warping and orientation warping checked by geometry: feet scaled along the movement with
 * the pelvis lowered just enough, the identity at scale 1; the orientation angle, its clamp,
 * hysteresis, smoothing and spring against closed forms; the warp applied to a hand-made chain;
 * hostile numbers give finite poses. */
#include <math.h>

#include <mm/spring.h>
#include <mm/warp.h>

#include "test_hostile.h"
#include "test_legs.h"
#include "test_util.h"

/* ---- stride warping ---------------------------------------------------------------------------- */

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

/* ---- hostile numbers ------------------------------------------------------------------------ */

/* Whatever comes in (NaN, infinities, 1e38), nothing non-finite comes out. */
static void test_hostile_numbers(void **state)
{
    (void)state;
    test_rng rng = {77};
    for (int k = 0; k < 20000; ++k) {
        mm_leg_pose legs[2];
        hostile_legs(&rng, legs);
        mm_leg_warp out[2];
        float drop = 0.0f;
        mm_warp_stride(legs, 2, hostile3(&rng), hostile(&rng), hostile(&rng), out, &drop);
        assert_true(isfinite(drop));
        for (int i = 0; i < 2; ++i)
            assert_true(finite_vec(out[i].pose.hip) && finite_vec(out[i].pose.knee) &&
                        finite_vec(out[i].pose.foot) && isfinite(out[i].thigh.w) && isfinite(out[i].shin.x));

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
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_stride_warp),
        cmocka_unit_test(test_orientation_warp),
        cmocka_unit_test(test_orientation_pose),
        cmocka_unit_test(test_hostile_numbers),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
