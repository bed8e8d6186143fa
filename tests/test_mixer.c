/* The crossfade mixer: weights against hand-computed values, the sum, eviction and cancellation at
 * the threshold exactly, uncancellable moves, playheads. The pose blend is test_pose's. */
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
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
