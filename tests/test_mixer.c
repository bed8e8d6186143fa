/* The crossfade mixer: weights against hand-computed values, the sum, eviction and cancellation at
 * the threshold exactly, uncancellable moves, playheads, and the pose blend against closed-form
 * rotations. */
#include <math.h>

#include <mm/mixer.h>

#include "test_util.h"

#define EPS 1e-6f

static void assert_weights(const mm_mixer *m, const float *expected, int count)
{
    assert_int_equal(m->count, count);
    for (int i = 0; i < count; ++i) {
        if (fabsf(m->slots[i].weight - expected[i]) > EPS)
            fail_msg("slot %d: weight %.9g, expected %.9g", i, m->slots[i].weight, expected[i]);
    }
    assert_true(fabsf(mm_mixer_weight_sum(m) - 1.0f) <= EPS);
}

/* The seed's example: over 0.2 s, after 0.1 s the new source holds half and the old ones half of
 * what they held, in the same proportions; at 0.2 s the old ones are freed. */
static void test_linear_weights(void **state)
{
    (void)state;
    mm_mixer m;
    mm_mixer_init(&m, 7, 0.25f);
    assert_weights(&m, (const float[]){1.0f}, 1);
    assert_int_equal(m.slots[0].source, 7);
    assert_true(m.slots[0].fraction == 0.25f);
    assert_true(mm_mixer_start(&m, 10, 0.0f, 0.2f, false));
    assert_weights(&m, (const float[]){0.0f, 1.0f}, 2); /* the first tick shows the old pose */
    assert_int_equal(m.slots[0].source, 10);
    assert_int_equal(m.slots[1].source, 7);
    mm_mixer_advance(&m, 0.05f);
    assert_weights(&m, (const float[]){0.25f, 0.75f}, 2);
    mm_mixer_advance(&m, 0.05f);
    assert_weights(&m, (const float[]){0.5f, 0.5f}, 2);
    /* a second transition halfway: the two older ones keep their 1:1 proportion */
    assert_true(mm_mixer_start(&m, 20, 0.0f, 0.2f, false));
    assert_weights(&m, (const float[]){0.0f, 0.5f, 0.5f}, 3);
    mm_mixer_advance(&m, 0.1f);
    assert_weights(&m, (const float[]){0.5f, 0.25f, 0.25f}, 3);
    /* uneven shares: 0.75 and 0.25 fall to 0.375 and 0.125 halfway */
    mm_mixer_init(&m, 1, 0.0f);
    assert_true(mm_mixer_start(&m, 2, 0.0f, 0.4f, false));
    mm_mixer_advance(&m, 0.3f);
    assert_weights(&m, (const float[]){0.75f, 0.25f}, 2);
    assert_true(mm_mixer_start(&m, 3, 0.0f, 0.2f, false));
    mm_mixer_advance(&m, 0.1f);
    assert_weights(&m, (const float[]){0.5f, 0.375f, 0.125f}, 3);
    /* at the end the older ones reach 0 together and are freed */
    mm_mixer_advance(&m, 0.1f);
    assert_weights(&m, (const float[]){1.0f}, 1);
    assert_int_equal(m.slots[0].source, 3);
    mm_mixer_advance(&m, 1.0f); /* nothing left to move */
    assert_weights(&m, (const float[]){1.0f}, 1);
    assert_int_equal(m.started, 2); /* since the last init */
    assert_int_equal(m.cancelled, 0);
}

/* One long step lands where many short ones do (weights are linear in time). */
static void test_step_independent(void **state)
{
    (void)state;
    mm_mixer a, b;
    mm_mixer_init(&a, 0, 0.0f);
    assert_true(mm_mixer_start(&a, 1, 0.0f, 0.3f, false));
    b = a;
    mm_mixer_advance(&a, 0.24f);
    for (int i = 0; i < 24; ++i) mm_mixer_advance(&b, 0.01f);
    assert_int_equal(a.count, 2);
    assert_int_equal(b.count, 2);
    assert_true(fabsf(a.slots[0].weight - 0.8f) < 1e-5f);
    assert_true(fabsf(b.slots[0].weight - 0.8f) < 1e-5f);
    assert_true(fabsf(a.slots[1].weight - 0.2f) < 1e-5f);
}

/* Fills five slots with weights 1/2, 1/4, 1/8, 1/16, 1/16 (exact in float). */
static void five_slots(mm_mixer *m)
{
    mm_mixer_init(m, 100, 0.0f);
    for (int k = 1; k <= 4; ++k) {
        assert_true(mm_mixer_start(m, 100 + k, 0.0f, 1.0f, false));
        mm_mixer_advance(m, 0.5f);
    }
    assert_weights(m, (const float[]){0.5f, 0.25f, 0.125f, 0.0625f, 0.0625f}, 5);
}

/* The slot to be evicted holding exactly the threshold is evicted; a hair more cancels. */
static void test_cancel_threshold(void **state)
{
    (void)state;
    mm_mixer m, before;
    five_slots(&m);
    m.cancel_weight = nextafterf(0.0625f, 0.0f);
    before = m;
    assert_false(mm_mixer_start(&m, 200, 0.0f, 0.2f, false));
    assert_int_equal(m.cancelled, 1);
    m.cancelled = 0;
    assert_memory_equal(&m, &before, sizeof m); /* nothing else changed */

    m.cancel_weight = 0.0625f;
    assert_true(mm_mixer_start(&m, 200, 0.0f, 0.2f, false));
    /* the evicted 1/16 is shared in proportion: each of the rest divided by 15/16 */
    assert_weights(&m, (const float[]){0.0f, 8.0f / 15.0f, 4.0f / 15.0f, 2.0f / 15.0f, 1.0f / 15.0f}, 5);
    assert_int_equal(m.slots[0].source, 200);
    assert_int_equal(m.slots[1].source, 104);
    assert_int_equal(m.slots[4].source, 101); /* 100, the oldest, is gone */
    mm_mixer_advance(&m, 0.1f);
    assert_weights(&m, (const float[]){0.5f, 4.0f / 15.0f, 2.0f / 15.0f, 1.0f / 15.0f, 0.5f / 15.0f}, 5);

    /* the default threshold: an oldest slot at 0.9^4 = 0.6561 cancels, one at 0.05 does not */
    assert_true(MM_MIXER_CANCEL_WEIGHT == 0.2f);
    mm_mixer_init(&m, 0, 0.0f);
    for (int k = 1; k <= 4; ++k) {
        assert_true(mm_mixer_start(&m, k, 0.0f, 1.0f, false));
        mm_mixer_advance(&m, 0.1f);
    }
    assert_int_equal(m.count, 5);
    assert_true(fabsf(m.slots[4].weight - 0.6561f) < 1e-5f);
    assert_false(mm_mixer_start(&m, 5, 0.0f, 1.0f, false));
    assert_int_equal(m.count, 5);
    assert_int_equal(m.slots[0].source, 4);
    assert_int_equal(m.cancelled, 1);
    assert_int_equal(m.started, 4);
    /* the weights move on; once the oldest is at most 0.2 the same move goes through */
    int ticks = 0;
    while (!mm_mixer_start(&m, 5, 0.0f, 1.0f, false)) {
        mm_mixer_advance(&m, 0.1f);
        ++ticks;
    }
    /* the oldest falls linearly from 0.6561 to 0 over the 0.9 s left: at or under 0.2 after 0.63 s */
    assert_int_equal(ticks, 7);
    assert_int_equal(m.slots[0].source, 5);
}

/* An uncancellable source evicts the oldest whatever its weight; the rest are renormalised. */
static void test_uncancellable(void **state)
{
    (void)state;
    mm_mixer m;
    mm_mixer_init(&m, 0, 0.0f);
    for (int k = 1; k <= 4; ++k) {
        assert_true(mm_mixer_start(&m, k, 0.0f, 1.0f, false));
        mm_mixer_advance(&m, 0.1f);
    }
    float w[5];
    for (int i = 0; i < 5; ++i) w[i] = m.slots[i].weight;
    assert_false(mm_mixer_start(&m, 9, 0.0f, 1.0f, false));
    assert_true(mm_mixer_start(&m, 9, 0.0f, 1.0f, true));
    assert_int_equal(m.count, 5);
    assert_int_equal(m.slots[0].source, 9);
    assert_int_equal(m.slots[4].source, 1);
    float rest = 1.0f - w[4];
    const float expected[5] = {0.0f, w[0] / rest, w[1] / rest, w[2] / rest, w[3] / rest};
    assert_weights(&m, expected, 5);
    mm_mixer_advance(&m, 0.25f);
    const float later[5] = {0.25f, 0.75f * w[0] / rest, 0.75f * w[1] / rest, 0.75f * w[2] / rest,
                            0.75f * w[3] / rest};
    assert_weights(&m, later, 5);
    mm_mixer_advance(&m, 0.75f);
    assert_weights(&m, (const float[]){1.0f}, 1);
}

/* Zero time, same-tick transitions, hostile numbers. */
static void test_edges(void **state)
{
    (void)state;
    mm_mixer m;
    mm_mixer_init(&m, 0, 0.0f);
    assert_true(mm_mixer_start(&m, 1, 0.0f, 0.2f, false));
    mm_mixer_advance(&m, 0.1f);
    assert_true(mm_mixer_start(&m, 2, 0.0f, 0.0f, false)); /* at once */
    assert_weights(&m, (const float[]){1.0f}, 1);
    assert_true(mm_mixer_start(&m, 3, 0.0f, NAN, false)); /* not finite: at once */
    assert_weights(&m, (const float[]){1.0f}, 1);
    /* two transitions in one tick: the first, still at weight 0, is dropped by the second */
    assert_true(mm_mixer_start(&m, 4, 0.0f, 0.2f, false));
    assert_true(mm_mixer_start(&m, 5, 0.0f, 0.2f, false));
    assert_weights(&m, (const float[]){0.0f, 1.0f}, 2);
    assert_int_equal(m.slots[1].source, 3);
    mm_mixer_advance(&m, NAN);
    mm_mixer_advance(&m, -1.0f);
    mm_mixer_advance(&m, INFINITY);
    assert_weights(&m, (const float[]){0.0f, 1.0f}, 2);
    mm_mixer_advance(&m, 1e30f);
    assert_weights(&m, (const float[]){1.0f}, 1);
    assert_true(mm_mixer_start(&m, 6, 2.0f, 0.2f, false)); /* a fraction out of [0, 1) is 0 */
    assert_true(m.slots[0].fraction == 0.0f);
    mm_mixer_init(NULL, 0, 0.0f);
    assert_false(mm_mixer_start(NULL, 0, 0.0f, 0.2f, false));
    mm_mixer_advance(NULL, 0.1f);
    assert_int_equal(mm_mixer_play(NULL, NULL, 0, 1.0f), 0);
    assert_true(mm_mixer_weight_sum(NULL) == 0.0f);
}

static uint32_t lcg(uint32_t *s)
{
    *s = *s * 1664525u + 1013904223u;
    return *s >> 8;
}

/* Random starts (some uncancellable) and steps: the sum stays 1, weights in [0, 1], at most five
 * slots; and the same sequence gives the same bits. */
static void run_random(uint32_t seed, mm_mixer *out)
{
    mm_mixer m;
    mm_mixer_init(&m, 0, 0.0f);
    uint32_t s = seed;
    for (int i = 0; i < 20000; ++i) {
        uint32_t r = lcg(&s);
        if (r % 4 == 0) {
            float time = (float)(lcg(&s) % 50) / 100.0f;
            mm_mixer_start(&m, i, 0.0f, time, lcg(&s) % 8 == 0);
        }
        mm_mixer_advance(&m, (float)(lcg(&s) % 40) / 1000.0f);
        assert_true(m.count >= 1 && m.count <= MM_MIXER_SLOTS);
        if (fabsf(mm_mixer_weight_sum(&m) - 1.0f) > 1e-5f)
            fail_msg("step %d: sum %.9g", i, mm_mixer_weight_sum(&m));
        for (int k = 0; k < m.count; ++k) assert_true(m.slots[k].weight >= 0.0f && m.slots[k].weight <= 1.0f);
        for (int k = 1; k < m.count; ++k) assert_true(m.slots[k].weight > 0.0f); /* freed at 0 */
    }
    assert_true(m.started > 1000);
    assert_true(m.cancelled > 0);
    *out = m;
}

static void test_sum_and_determinism(void **state)
{
    (void)state;
    mm_mixer a, b;
    run_random(1, &a);
    run_random(1, &b);
    assert_memory_equal(&a, &b, sizeof a);
}

/* Playheads follow the next-frame table and stop at the end of their clip. */
static void test_play(void **state)
{
    (void)state;
    const int next[7] = {1, 2, 3, -1, 5, 6, -1}; /* clips 0-3 and 4-6 */
    mm_mixer m;
    mm_mixer_init(&m, 0, 0.0f);
    assert_true(mm_mixer_start(&m, 4, 0.5f, 0.2f, false));
    assert_int_equal(mm_mixer_play(&m, next, 7, 1.5f), 1u); /* 4.5 + 1.5 = 6.0: its clip's last frame */
    assert_int_equal(m.slots[0].source, 6);
    assert_true(m.slots[0].fraction == 0.0f);
    assert_int_equal(m.slots[1].source, 1);
    assert_true(m.slots[1].fraction == 0.5f);
    /* slot 0 stays at its clip's end; slot 1 reaches frame 3, its clip's last: bits 0 and 1 */
    assert_int_equal(mm_mixer_play(&m, next, 7, 1.5f), 3u);
    assert_int_equal(m.slots[0].source, 6);
    assert_true(m.slots[0].fraction == 0.0f);
    assert_int_equal(m.slots[1].source, 3);
    assert_true(m.slots[1].fraction == 0.0f);
    /* negative or not finite: no move; a source outside the table: left alone */
    m.slots[1].source = 2;
    assert_int_equal(mm_mixer_play(&m, next, 7, -1.0f), 1u);
    assert_int_equal(mm_mixer_play(&m, next, 7, NAN), 1u);
    assert_int_equal(m.slots[1].source, 2);
    m.slots[1].source = 99;
    assert_int_equal(mm_mixer_play(&m, next, 7, 1.0f), 1u);
    assert_int_equal(m.slots[1].source, 99);
}

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
        cmocka_unit_test(test_linear_weights),
        cmocka_unit_test(test_step_independent),
        cmocka_unit_test(test_cancel_threshold),
        cmocka_unit_test(test_uncancellable),
        cmocka_unit_test(test_edges),
        cmocka_unit_test(test_sum_and_determinism),
        cmocka_unit_test(test_play),
        cmocka_unit_test(test_pose_blend),
        cmocka_unit_test(test_pose_blend_reference),
        cmocka_unit_test(test_pose_blend_identical),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
