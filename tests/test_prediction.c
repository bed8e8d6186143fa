/* Stop and pivot prediction against independent truth: the closed form of a spring coming to rest,
 * and stepping the project's own trajectory simulation (letting go of the stick, turning back); bad
 * and hostile numbers give zero predictions. */
#include <math.h>

#include <mm/prediction.h>
#include <mm/spring.h>
#include <mm/trajectory.h>

#include "test_hostile.h"
#include "test_util.h"

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

/* ---- hostile numbers ------------------------------------------------------------------------ */

/* Whatever comes in (NaN, infinities, 1e38), nothing non-finite comes out. */
static void test_hostile_numbers(void **state)
{
    (void)state;
    test_rng rng = {77};
    for (int k = 0; k < 20000; ++k) {
        mm_distance_prediction p;
        mm_distance_predict_stop(hostile3(&rng), hostile3(&rng), hostile(&rng), hostile(&rng), &p);
        assert_true(finite_vec(p.offset) && isfinite(p.distance) && isfinite(p.time));
        mm_distance_predict_pivot(hostile3(&rng), hostile3(&rng), hostile3(&rng), hostile(&rng), &p);
        assert_true(finite_vec(p.offset) && isfinite(p.distance) && isfinite(p.time));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_predict_stop_closed_form),
        cmocka_unit_test(test_predict_against_simulation),
        cmocka_unit_test(test_hostile_numbers),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
