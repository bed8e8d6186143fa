/* Springs: the closed forms against a fine numerical integration of the differential equation
 * (an independent method), the half-life definition, and tick-rate independence. */
#include <math.h>

#include <mm/spring.h>

#include "math_private.h"
#include "runtime/spring_private.h"

#include "test_util.h"

/* x'' = -y^2 (x - g) - 2 y x', integrated with RK4 at 1e-5 s: the truth the closed forms must meet. */
static void integrate(double *x, double *v, double g, double y, double t)
{
    int n = (int)(t / 1e-5 + 0.5);
    double h = t / n;
    for (int i = 0; i < n; ++i) {
#define ACC(X, V) (-y * y * ((X)-g) - 2.0 * y * (V))
        double k1x = *v, k1v = ACC(*x, *v);
        double k2x = *v + 0.5 * h * k1v, k2v = ACC(*x + 0.5 * h * k1x, *v + 0.5 * h * k1v);
        double k3x = *v + 0.5 * h * k2v, k3v = ACC(*x + 0.5 * h * k2x, *v + 0.5 * h * k2v);
        double k4x = *v + h * k3v, k4v = ACC(*x + h * k3x, *v + h * k3v);
#undef ACC
        *x += h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
        *v += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    }
}

static void test_half_life(void **state)
{
    (void)state;
    /* from rest, half the distance is left after one half-life; after two, (1 + 2u) e^(-2u) of
     * it, with u = y h (not a quarter: the spring is moving when the second one starts) */
    float x = 10.0f, v = 0.0f;
    mm_spring_update(&x, &v, 0.0f, 0.3f, 0.3f);
    assert_near(x, 5.0, 1e-5);
    assert_true(v < 0.0f);
    double u = mm_spring_damping(0.3f) * 0.3;
    mm_spring_update(&x, &v, 0.0f, 0.3f, 0.3f);
    assert_near(x, 10.0 * (1 + 2 * u) * exp(-2 * u), 1e-4);
    /* no half-life: jump */
    mm_spring_update(&x, &v, 3.0f, 0.0f, 0.01f);
    assert_near(x, 3.0, 0);
    assert_near(v, 0.0, 0);
}

static void test_against_integration(void **state)
{
    (void)state;
    const float x0s[3] = {2.0f, -1.0f, 0.0f}, v0s[3] = {0.0f, 4.0f, -3.0f},
                halflives[3] = {0.05f, 0.2f, 1.0f};
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) {
            float x = x0s[i], v = v0s[i];
            double xd = x, vd = v, y = mm_spring_damping(halflives[k]);
            mm_spring_update(&x, &v, 0.7f, halflives[k], 0.37f);
            integrate(&xd, &vd, 0.7, y, 0.37);
            assert_near(x, xd, 1e-5);
            assert_near(v, vd, 1e-4);
        }
}

static void test_tick_rate_independent(void **state)
{
    (void)state;
    const int rates[3] = {30, 60, 120};
    float end_x[3], end_v[3];
    mm_vec3 end_p[3];
    for (int r = 0; r < 3; ++r) {
        float x = 1.0f, v = -2.0f;
        mm_vec3 p = mm_vec3_make(0, 0, 0), vel = mm_vec3_make(1, 0, 0), acc = mm_vec3_make(0, 0, 0);
        for (int i = 0; i < 3 * rates[r]; ++i) {
            float t = (float)i / rates[r];
            float target = t < 1.0f ? 4.0f : -2.0f; /* the target changes on a tick of every rate */
            mm_spring_update(&x, &v, target, 0.25f, 1.0f / rates[r]);
            mm_vec3 goal = t < 1.5f ? mm_vec3_make(0, 0, 1.5f) : mm_vec3_make(2.0f, 0, 0);
            mm_spring_velocity_update(&p, &vel, &acc, goal, 0.3f, 1.0f / rates[r]);
        }
        end_x[r] = x;
        end_v[r] = v;
        end_p[r] = p;
    }
    for (int r = 1; r < 3; ++r) {
        assert_near(end_x[r], end_x[0], 1e-4);
        assert_near(end_v[r], end_v[0], 1e-4);
        assert_near(mm_vec3_distance(end_p[r], end_p[0]), 0, 1e-3); /* 1 mm after 3 s and 4 m */
    }
}

/* The trajectory spring: its velocity is the critically damped spring, and its position is the
 * integral of that velocity (checked with the numerical integration). */
static void test_velocity_spring(void **state)
{
    (void)state;
    mm_vec3 p = mm_vec3_make(1, 0, 2), v = mm_vec3_make(0.5f, 0, -1), a = mm_vec3_make(0, 0, 3);
    double y = mm_spring_damping(0.4f);
    /* reference: velocity obeys the spring ODE with v'(0) = a0; position integrates it */
    double vz = v.z, az = a.z, pz = p.z, g = 1.8;
    int n = 100000;
    double h = 0.6 / n;
    for (int i = 0; i < n; ++i) { /* semi-implicit small steps, 6e-6 s */
        double acc_dot = -y * y * (vz - g) - 2 * y * az;
        pz += h * (vz + 0.5 * h * az);
        vz += h * az;
        az += h * acc_dot;
    }
    mm_spring_velocity_update(&p, &v, &a, mm_vec3_make(0.5f, 0, 1.8f), 0.4f, 0.6f);
    assert_near(v.z, vz, 1e-3);
    assert_near(a.z, az, 1e-2);
    assert_near(p.z, pz, 1e-3);
    assert_near(v.x, 0.5, 1e-6); /* already at its target, stays */
    assert_near(p.x, 1.3, 1e-5);
}

static void test_quat_spring(void **state)
{
    (void)state;
    mm_quat target = mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), 1.2f);
    mm_quat q = mm_quat_identity();
    mm_vec3 w = mm_vec3_make(0, 0, 0);
    mm_spring_update_quat(&q, &w, target, 0.2f, 0.2f);
    /* half the angle is left after one half-life, about the same axis */
    assert_near(mm_quat_angle_between(q, target), 0.6, 1e-4);
    mm_vec3 axis = mm_vec3_normalize(mm_quat_log(q));
    assert_near(axis.y, 1.0, 1e-5);
    for (int i = 0; i < 200; ++i) mm_spring_update_quat(&q, &w, target, 0.2f, 1.0f / 60.0f);
    assert_near(mm_quat_angle_between(q, target), 0.0, 1e-4);
    assert_near(mm_vec3_length(w), 0.0, 1e-3);
}

/* A step made once for many springs: the same bits as each spring's own update, with a fixed or a
 * moving target, for half-lives and dts of every kind (none: no spring; dt 0: no step). */
static void test_shared_step(void **state)
{
    (void)state;
    const float halflives[] = {0.05f, 0.1f, 0.37f, 2.0f, 0.0f, -1.0f};
    const float dts[] = {1.0f / 60.0f, 1.0f / 30.0f, 0.25f, 0.0f, -0.1f};
    unsigned seed = 7u;
    for (size_t h = 0; h < sizeof halflives / sizeof halflives[0]; ++h)
        for (size_t k = 0; k < sizeof dts / sizeof dts[0]; ++k) {
            mm_spring_step step = mm_spring_step_make(halflives[h], dts[k]);
            for (int trial = 0; trial < 50; ++trial) {
                float r[9];
                for (int i = 0; i < 9; ++i) {
                    seed = seed * 1664525u + 1013904223u;
                    r[i] = (float)(seed >> 8) / (float)(1u << 24) * 4.0f - 2.0f;
                }
                mm_vec3 x0 = mm_vec3_make(r[0], r[1], r[2]), v0 = mm_vec3_make(r[3], r[4], r[5]);
                mm_vec3 target = mm_vec3_make(r[6], r[7], r[8]);
                mm_vec3 xa = x0, va = v0, xb = x0, vb = v0;
                mm_spring_decay_vec3(&xa, &va, halflives[h], dts[k]);
                mm_spring_decay_vec3_step(&xb, &vb, &step);
                assert_memory_equal(&xa, &xb, sizeof xa);
                assert_memory_equal(&va, &vb, sizeof va);
                xa = xb = x0, va = vb = v0;
                mm_spring_update_vec3(&xa, &va, target, halflives[h], dts[k]);
                mm_spring_update_vec3_step(&xb, &vb, target, &step);
                assert_memory_equal(&xa, &xb, sizeof xa);
                assert_memory_equal(&va, &vb, sizeof va);
                /* and each coordinate as the scalar spring moves it */
                float x = x0.y, v = v0.y;
                mm_spring_update(&x, &v, target.y, halflives[h], dts[k]);
                assert_memory_equal(&x, &xb.y, sizeof x);
                assert_memory_equal(&v, &vb.y, sizeof v);
                float xs = x0.y, vs = v0.y; /* and the scalar spring's step */
                mm_spring_update_step(&xs, &vs, target.y, &step);
                assert_memory_equal(&xs, &x, sizeof x);
                assert_memory_equal(&vs, &v, sizeof v);
            }
        }
    /* many springs side by side (mm_spring_decay_vec3_steps): the bits of one step each, signed
     * zeros and springs at rest included */
    for (size_t h = 0; h < sizeof halflives / sizeof halflives[0]; ++h)
        for (size_t k = 0; k < sizeof dts / sizeof dts[0]; ++k) {
            mm_spring_step step = mm_spring_step_make(halflives[h], dts[k]);
            enum { SPRINGS = 41 };
            mm_vec3 xa[SPRINGS], va[SPRINGS], xb[SPRINGS], vb[SPRINGS];
            for (int i = 0; i < SPRINGS; ++i) {
                float r[6];
                for (int c = 0; c < 6; ++c) {
                    seed = seed * 1664525u + 1013904223u;
                    r[c] = (float)(seed >> 8) / (float)(1u << 24) * 4.0f - 2.0f;
                    if (seed % 7u == 0u) r[c] = seed % 2u ? 0.0f : -0.0f;
                }
                xa[i] = xb[i] = mm_vec3_make(r[0], r[1], r[2]);
                va[i] = vb[i] = mm_vec3_make(r[3], r[4], r[5]);
            }
            /* four coordinates wide (AVX) and two (SSE2), every remainder */
            int count = SPRINGS - (int)((h + k) % 4);
            mm__math_wide_kernels((h + k) % 2 == 0);
            for (int i = 0; i < count; ++i) mm_spring_decay_vec3_step(&xa[i], &va[i], &step);
            mm_spring_decay_vec3_steps(xb, vb, count, &step);
            mm__math_wide_kernels(true);
            assert_memory_equal(xa, xb, sizeof xa);
            assert_memory_equal(va, vb, sizeof va);
        }
    /* and they move: a spring of 0.1 s over 0.1 s from rest leaves half of the way (the half-life) */
    mm_spring_step step = mm_spring_step_make(0.1f, 0.1f);
    mm_vec3 x = mm_vec3_make(1, 0, 0), v = mm_vec3_make(0, 0, 0);
    mm_spring_decay_vec3_step(&x, &v, &step);
    assert_float_equal(x.x, 0.5f, 1e-5f);
}

/* The rotation spring in two parts (mm__spring_quat_gap once, mm__spring_update_quat_gap for
 * several steps from the same rotation toward the same target) against mm_spring_update_quat,
 * bit for bit: random rotations, angular velocities, half-lives (0: none) and steps (0 and
 * negative: none). */
static void test_quat_spring_gap(void **state)
{
    (void)state;
    unsigned seed = 7u;
    const float halflives[4] = {0.0f, 0.05f, 0.2f, 1.5f},
                dts[5] = {-0.1f, 0.0f, 1.0f / 60.0f, 0.3333333f, 2.0f};
    for (int n = 0; n < 400; ++n) {
        float r[10];
        for (int c = 0; c < 10; ++c) {
            seed = seed * 1664525u + 1013904223u;
            r[c] = (float)(seed >> 8) / (float)(1u << 24) * 2.0f - 1.0f;
        }
        float spread = n % 4 == 0 ? 3.0f : 0.4f; /* turns past the series' reach, and within it */
        mm_quat q = mm_quat_exp(mm_vec3_make(spread * r[0], spread * r[1], spread * r[2]));
        mm_quat target = mm_quat_exp(mm_vec3_make(spread * r[3], spread * r[4], spread * r[5]));
        if (n % 9 == 0) target = q;
        mm_vec3 w0 = mm_vec3_make(4.0f * r[6], 4.0f * r[7], 4.0f * r[8]);
        mm_vec3 gap = mm__spring_quat_gap(q, target);
        for (int h = 0; h < 4; ++h)
            for (int k = 0; k < 5; ++k) {
                mm_quat qa = q, qb = q;
                mm_vec3 wa = w0, wb = w0;
                mm_spring_update_quat(&qa, &wa, target, halflives[h], dts[k]);
                mm__spring_update_quat_gap(&qb, &wb, gap, target, halflives[h], dts[k]);
                assert_memory_equal(&qa, &qb, sizeof qa);
                assert_memory_equal(&wa, &wb, sizeof wa);
            }
    }
}

/* mm_spring_step_make keeps the steps it made on the thread: whatever it made before (many
 * half-lives and steps, in any order, some the same again), a step is the one its definition
 * gives, bit for bit: the damping, dt, e^(-y dt) (0 without a spring or a step) and whether it
 * moves. */
static void test_step_made_again(void **state)
{
    (void)state;
    enum { PAIRS = 300 };
    float halflives[PAIRS], dts[PAIRS];
    unsigned seed = 11u;
    for (int i = 0; i < PAIRS; ++i) {
        seed = seed * 1664525u + 1013904223u;
        halflives[i] = i % 17 == 0 ? 0.0f : (float)(seed >> 8) / (float)(1u << 24) * 2.0f;
        seed = seed * 1664525u + 1013904223u;
        dts[i] = i % 13 == 0  ? (i % 2 ? -0.0f : -0.01f)
                 : i % 3 == 0 ? 1.0f / 60.0f
                              : (float)(seed >> 8) / (float)(1u << 24);
    }
    for (int pass = 0; pass < 3; ++pass)
        for (int n = 0; n < PAIRS; ++n) {
            int i = pass == 1 ? PAIRS - 1 - n : pass == 2 ? (n * 7) % PAIRS : n;
            mm_spring_step s = mm_spring_step_make(halflives[i], dts[i]);
            double y = mm_spring_damping(halflives[i]), dt = dts[i];
            bool moves = dts[i] > 0.0f;
            double decay = moves && isfinite(y) ? exp(-y * dt) : 0.0;
            assert_memory_equal(&s.damping, &y, sizeof y);
            assert_memory_equal(&s.dt, &dt, sizeof dt);
            assert_memory_equal(&s.decay, &decay, sizeof decay);
            assert_true(s.moves == moves);
        }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_half_life),
        cmocka_unit_test(test_against_integration),
        cmocka_unit_test(test_tick_rate_independent),
        cmocka_unit_test(test_velocity_spring),
        cmocka_unit_test(test_quat_spring),
        cmocka_unit_test(test_shared_step),
        cmocka_unit_test(test_quat_spring_gap),
        cmocka_unit_test(test_step_made_again),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
