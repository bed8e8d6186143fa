/* Two-bone leg IK checked by geometry: reachable targets are reached with the bone lengths kept,
 * out-of-reach ones are pointed at, the knee keeps its side and moves continuously as targets
 * sweep and as the animated leg passes straight, and hostile numbers give finite legs. */
#include <math.h>

#include <mm/leg_ik.h>

#include "test_hostile.h"
#include "test_legs.h"
#include "test_util.h"

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
        assert_int_equal(mm_leg_ik_solve(&leg, target, mm_vec3_make(0, 0, 1), NULL, &w), MM_OK);
        assert_near(mm_vec3_distance(w.pose.foot, target), 0.0, 1e-3);
        assert_lengths_kept(&leg, &w.pose);
    }
    /* out of reach: the leg points at the target, stretched to 0.999 of its length */
    mm_vec3 far = mm_vec3_make(0.0f, -1.0f, 0.5f);
    assert_int_equal(mm_leg_ik_solve(&leg, far, mm_vec3_make(0, 0, 1), NULL, &w), MM_OK);
    assert_near(mm_vec3_distance(w.pose.foot, leg.hip), 0.999 * 0.9, 1e-5);
    mm_vec3 a = mm_vec3_normalize(mm_vec3_sub(w.pose.foot, leg.hip)),
            b = mm_vec3_normalize(mm_vec3_sub(far, leg.hip));
    assert_near(mm_vec3_dot(a, b), 1.0, 1e-6);
    assert_lengths_kept(&leg, &w.pose);
    /* softened: a target at the full length is reached to within soft_reach * length * e^-1 of it
     * (the soft zone starts soft_reach * length short of it), a nearer one exactly; the
     * distance asked for grows smoothly (its slope is continuous where the zone starts) */
    mm_leg_ik_params soft = {1.0f, 0.05f};
    assert_int_equal(mm_leg_ik_solve(&leg, mm_vec3_make(0.0f, 0.1f, 0.0f), mm_vec3_make(0, 0, 1), &soft, &w),
                     MM_OK);
    assert_near(mm_vec3_distance(w.pose.foot, leg.hip), 0.9 - 0.05 * 0.9 * exp(-1.0), 1e-5);
    assert_int_equal(mm_leg_ik_solve(&leg, mm_vec3_make(0.0f, 0.2f, 0.0f), mm_vec3_make(0, 0, 1), &soft, &w),
                     MM_OK);
    assert_near(mm_vec3_distance(w.pose.foot, leg.hip), 0.8, 1e-5);
    double last = 0.0, last_step = -1.0;
    for (int k = 0; k <= 100; ++k) { /* targets from 0.80 to 1.00 m below the hip */
        mm_vec3 target = mm_vec3_make(0.0f, 1.0f - (0.8f + 0.002f * (float)k), 0.0f);
        assert_int_equal(mm_leg_ik_solve(&leg, target, mm_vec3_make(0, 0, 1), &soft, &w), MM_OK);
        double reach = mm_vec3_distance(w.pose.foot, leg.hip);
        if (k > 0) {
            double step = reach - last;
            assert_true(step > 0.0 && step <= 0.002 + 1e-6);
            if (last_step >= 0.0) assert_true(fabs(step - last_step) < 2.5e-4); /* no kink */
            last_step = step;
        }
        last = reach;
    }
    soft.soft_reach = 0.6f; /* out of range */
    assert_int_equal(mm_leg_ik_solve(&leg, mm_vec3_make(0.0f, 0.2f, 0.0f), mm_vec3_make(0, 0, 1), &soft, &w),
                     MM_ERR_INVALID_ARGUMENT);
    /* the knee keeps the side it bends to while the target sweeps across the knee's own line:
     * a leg bent in the x = 0 plane (knee forward, +z), targets moving from in front of the knee
     * to behind it; the knee stays in that plane, forward of the hip-target line, and moves
     * continuously (the knee's side of each new hip-target axis flips where the axis passes the
     * knee) */
    mm_leg_pose bent = {mm_vec3_make(0, 1, 0), mm_vec3_make(0, 0.58f, 0.15f), mm_vec3_make(0, 0.15f, 0.05f)};
    mm_vec3 before = bent.knee;
    for (int k = 0; k <= 100; ++k) {
        mm_vec3 target = mm_vec3_make(0.0f, 0.2f, 0.6f - 0.8f * (float)k / 100.0f);
        assert_int_equal(mm_leg_ik_solve(&bent, target, mm_vec3_make(0, 0, 1), NULL, &w), MM_OK);
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
        assert_int_equal(mm_leg_ik_solve(&passing, target, mm_vec3_make(0, 0, 1), NULL, &w), MM_OK);
        assert_near(mm_vec3_distance(w.pose.foot, target), 0.0, 1e-5);
        assert_lengths_kept(&passing, &w.pose);
        assert_true(w.pose.knee.z > 0.05f);
        if (k > 0) assert_true(mm_vec3_distance(w.pose.knee, before) < 0.01f);
        before = w.pose.knee;
    }
    /* a leg bent against the pole (0.3 rad: hyperextended) is solved on the pole's side, mirrored:
     * the IK never bends a knee backward; a leg bent to a side within 60 degrees of the pole keeps
     * it when the target is its foot */
    mm_leg_pose against = {mm_vec3_make(0, 1, 0),
                           mm_vec3_make(0, 1.0f - 0.45f * cosf(0.3f), -0.45f * sinf(0.3f)),
                           mm_vec3_make(0, 1.0f - 0.9f * cosf(0.3f), 0)};
    assert_int_equal(mm_leg_ik_solve(&against, against.foot, mm_vec3_make(0, 0, 1), NULL, &w), MM_OK);
    assert_near(w.pose.knee.z, 0.45 * sin(0.3), 1e-5);
    assert_near(w.pose.knee.y, against.knee.y, 1e-5);
    assert_near(mm_vec3_distance(w.pose.foot, against.foot), 0.0, 1e-5);
    for (int k = -5; k <= 5; ++k) { /* the knee turned about the leg by up to 55 degrees */
        float yaw = 0.19f * (float)k;
        mm_vec3 side = mm_vec3_make(sinf(yaw), 0, cosf(yaw));
        mm_leg_pose turned = {mm_vec3_make(0, 1, 0),
                              mm_vec3_add(mm_vec3_make(0, 1.0f - 0.45f * cosf(0.3f), 0),
                                          mm_vec3_scale(side, 0.45f * sinf(0.3f))),
                              mm_vec3_make(0, 1.0f - 0.9f * cosf(0.3f), 0)};
        assert_int_equal(mm_leg_ik_solve(&turned, turned.foot, mm_vec3_make(0, 0, 1), NULL, &w), MM_OK);
        assert_near(mm_vec3_distance(w.pose.knee, turned.knee), 0.0, 1e-5);
    }
    /* a straight leg bends toward the pole */
    mm_leg_pose straight = {mm_vec3_make(0, 1, 0), mm_vec3_make(0, 0.55f, 0), mm_vec3_make(0, 0.1f, 0)};
    assert_int_equal(mm_leg_ik_solve(&straight, mm_vec3_make(0, 0.3f, 0), mm_vec3_make(0, 0, 1), NULL, &w),
                     MM_OK);
    assert_true(w.pose.knee.z > 0.1f);
    assert_near(w.pose.foot.y, 0.3, 1e-5);
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
        mm_vec3 target = hostile3(&rng), pole = hostile3(&rng);
        mm_leg_ik_params params = {hostile(&rng), 0.0f};
        params.soft_reach = hostile(&rng);
        mm_leg_ik_solve(&legs[0], target, pole, &params, &out[0]);
        assert_true(finite_vec(out[0].pose.knee) && finite_vec(out[0].pose.foot) && isfinite(out[0].thigh.y));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_leg_ik),
        cmocka_unit_test(test_hostile_numbers),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
