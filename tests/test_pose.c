/* Pose blending against closed-form rotations: two rotations half-way, the hemisphere of a
 * quaternion, weights, a reference that keeps signs, identical poses, blending in place. */
#include <math.h>

#include <mm/pose.h>

#include "test_util.h"

static float angle_about_y(mm_quat q)
{
    mm_vec3 f = mm_quat_rotate(q, mm_vec3_make(0, 0, 1));
    return atan2f(f.x, f.z);
}

/* Two rotations 90 degrees apart at 0.5 give the one of 45 degrees; positions blend linearly; the
 * hemisphere of a quaternion does not matter; other weights follow the normalised sum's closed
 * form. */
static void test_pose_blend(void **state)
{
    (void)state;
    const mm_vec3 up = mm_vec3_make(0, 1, 0);
    mm_quat ra[2] = {mm_quat_identity(), mm_quat_from_axis_angle(mm_vec3_make(1, 0, 0), 0.3f)};
    mm_quat rb[2] = {mm_quat_from_axis_angle(up, (float)MM_PI / 2), ra[1]};
    mm_vec3 pa[2] = {mm_vec3_make(0, 0, 0), mm_vec3_make(1, 2, 3)};
    mm_vec3 pb[2] = {mm_vec3_make(2, 4, -2), mm_vec3_make(1, 2, 3)};
    const mm_quat *r[2] = {ra, rb};
    const mm_vec3 *p[2] = {pa, pb};
    mm_quat out_r[2];
    mm_vec3 out_p[2];
    mm_pose_blend(r, p, (const float[]){0.5f, 0.5f}, 2, 2, NULL, out_r, out_p);
    mm_quat q45 = mm_quat_from_axis_angle(up, (float)MM_PI / 4);
    assert_true(fabsf(fabsf(mm_quat_dot(out_r[0], q45)) - 1.0f) < 1e-6f);
    assert_true(fabsf(angle_about_y(out_r[0]) - (float)MM_PI / 4) < 1e-5f);
    assert_true(mm_vec3_distance(out_p[0], mm_vec3_make(1, 2, -1)) < 1e-6f);
    assert_true(fabsf(fabsf(mm_quat_dot(out_r[1], ra[1])) - 1.0f) < 1e-6f); /* identical joint */
    assert_true(mm_vec3_distance(out_p[1], pa[1]) < 1e-6f);

    /* the same rotation written -q: the same result */
    mm_quat flipped[2] = {mm_quat_make(-rb[0].x, -rb[0].y, -rb[0].z, -rb[0].w), rb[1]};
    const mm_quat *rf[2] = {ra, flipped};
    mm_quat out_f[2];
    mm_pose_blend(rf, p, (const float[]){0.5f, 0.5f}, 2, 2, NULL, out_f, out_p);
    assert_true(fabsf(fabsf(mm_quat_dot(out_f[0], q45)) - 1.0f) < 1e-6f);

    /* weights 1 and 3 (normalised to 1/4, 3/4): half-angle atan2(3/4 sin 45, 1/4 + 3/4 cos 45) */
    mm_pose_blend(r, p, (const float[]){1.0f, 3.0f}, 2, 2, NULL, out_r, out_p);
    double half = atan2(0.75 * sin(MM_PI / 4), 0.25 + 0.75 * cos(MM_PI / 4));
    assert_true(fabs(angle_about_y(out_r[0]) - 2.0 * half) < 1e-5);
    assert_true(mm_vec3_distance(out_p[0], mm_vec3_make(1.5f, 3.0f, -1.5f)) < 1e-6f);

    /* a weight that is negative, NaN or 0 does not count; no weight at all gives pose 0 */
    mm_pose_blend(r, p, (const float[]){NAN, 2.0f}, 2, 2, NULL, out_r, out_p);
    assert_true(fabsf(fabsf(mm_quat_dot(out_r[0], rb[0])) - 1.0f) < 1e-6f);
    assert_true(mm_vec3_distance(out_p[0], pb[0]) < 1e-6f);
    mm_pose_blend(r, p, (const float[]){-1.0f, 0.0f}, 2, 2, NULL, out_r, out_p);
    assert_memory_equal(out_r, ra, sizeof ra);
    assert_memory_equal(out_p, pa, sizeof pa);
}

/* The reference decides the hemisphere: identity and a half turn about X (orthogonal
 * quaternions) at equal weights blend to a quarter turn about +X or -X, whichever is nearer the
 * reference; a zero-weight pose does not change the result with a reference given. */
static void test_pose_blend_reference(void **state)
{
    (void)state;
    const mm_vec3 x = mm_vec3_make(1, 0, 0);
    mm_quat ra[1] = {mm_quat_identity()}, rb[1] = {mm_quat_make(1, 0, 0, 0)};
    mm_quat rc[1] = {mm_quat_from_axis_angle(mm_vec3_make(0.6f, 0.0f, 0.8f), 3.0f)};
    mm_vec3 pz[1] = {mm_vec3_make(0, 0, 0)};
    const mm_quat *r[3] = {rc, ra, rb}; /* pose 0 weighs nothing */
    const mm_vec3 *p[3] = {pz, pz, pz};
    const float w[3] = {0.0f, 0.5f, 0.5f};
    mm_quat out[1];
    mm_vec3 out_p[1];
    for (int sign = -1; sign <= 1; sign += 2) {
        mm_quat ref[1] = {mm_quat_from_axis_angle(x, (float)sign * 1.2f)};
        mm_pose_blend(r, p, w, 3, 1, ref, out, out_p);
        mm_quat expected = mm_quat_from_axis_angle(x, (float)sign * (float)MM_PI / 2);
        assert_true(fabsf(fabsf(mm_quat_dot(out[0], expected)) - 1.0f) < 1e-6f);
    }
    /* without one, the heaviest (the first of the two equals: the identity) is the reference */
    mm_pose_blend(r, p, w, 3, 1, NULL, out, out_p);
    assert_true(fabsf(fabsf(mm_quat_dot(out[0], mm_quat_from_axis_angle(x, (float)MM_PI / 2))) - 1.0f) <
                1e-6f);
}

/* Blending copies of one pose returns it, whatever the weights; out may be pose 0 itself. */
static void test_pose_blend_identical(void **state)
{
    (void)state;
    enum { J = 4 };
    mm_quat rot[J];
    mm_vec3 pos[J];
    for (int j = 0; j < J; ++j) {
        rot[j] =
            mm_quat_from_axis_angle(mm_vec3_normalize(mm_vec3_make(1.0f, (float)j, 0.5f)), 0.7f * (float)j);
        pos[j] = mm_vec3_make((float)j, -2.0f * (float)j, 0.25f);
    }
    const mm_quat *r[5] = {rot, rot, rot, rot, rot};
    const mm_vec3 *p[5] = {pos, pos, pos, pos, pos};
    mm_quat out_r[J];
    mm_vec3 out_p[J];
    mm_pose_blend(r, p, (const float[]){0.1f, 0.2f, 0.3f, 0.15f, 0.25f}, 5, J, NULL, out_r, out_p);
    for (int j = 0; j < J; ++j) {
        assert_true(fabsf(fabsf(mm_quat_dot(out_r[j], rot[j])) - 1.0f) < 1e-6f);
        assert_true(mm_vec3_distance(out_p[j], pos[j]) < 1e-6f);
    }
    mm_quat copy_r[J];
    mm_vec3 copy_p[J];
    memcpy(copy_r, rot, sizeof rot);
    memcpy(copy_p, pos, sizeof pos);
    const mm_quat *r2[2] = {copy_r, rot};
    const mm_vec3 *p2[2] = {copy_p, pos};
    mm_pose_blend(r2, p2, (const float[]){0.5f, 0.5f}, 2, J, NULL, copy_r, copy_p); /* in place */
    for (int j = 0; j < J; ++j) {
        assert_true(fabsf(fabsf(mm_quat_dot(copy_r[j], rot[j])) - 1.0f) < 1e-6f);
        assert_true(mm_vec3_distance(copy_p[j], pos[j]) < 1e-6f);
    }
    /* the same input, the same bits */
    mm_quat again_r[J];
    mm_vec3 again_p[J];
    mm_pose_blend(r, p, (const float[]){0.1f, 0.2f, 0.3f, 0.15f, 0.25f}, 5, J, NULL, again_r, again_p);
    assert_memory_equal(again_r, out_r, sizeof out_r);
    assert_memory_equal(again_p, out_p, sizeof out_p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pose_blend),
        cmocka_unit_test(test_pose_blend_reference),
        cmocka_unit_test(test_pose_blend_identical),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
