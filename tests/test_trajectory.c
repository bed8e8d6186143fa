/* Trajectory simulation: tick-rate independence, speeds and turns against the parameters, the
 * recorded past, and bad input. */
#include <math.h>

#include <mm/input_json.h>
#include <mm/scene.h>
#include <mm/trajectory.h>

#include "runtime/trajectory_private.h"
#include "test_util.h"

static mm_input stick(float x, float z, mm_gait gait)
{
    mm_input in;
    memset(&in, 0, sizeof in);
    in.stick[0] = x;
    in.stick[1] = z;
    in.gait = gait;
    return in;
}

static float yaw(mm_quat q)
{
    mm_vec3 f = mm_quat_rotate(q, mm_vec3_make(0, 0, 1));
    return atan2f(f.x, f.z);
}

/* One script at 30, 60 and 120 Hz: the same motion, future and past within 1 mm. */
static void test_tick_rate_independent(void **state)
{
    (void)state;
    mm_input_script script;
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(
        mm_input_script_load_json(MM_TEST_DATA "/../../scripts/input/turn_90.json", &script, &err), MM_OK);
    const int rates[3] = {30, 60, 120};
    const float times[4] = {-1.0f, -0.3333333f, 0.3333333f, 1.0f};
    mm_vec3 end[3], samples[3][4];
    mm_quat end_facing[3];
    for (int r = 0; r < 3; ++r) {
        mm_trajectory t;
        assert_int_equal(mm_trajectory_init(&t, NULL, NULL), MM_OK);
        mm_input in;
        int ticks = 14 * rates[r];
        for (int i = 0; i < ticks; ++i) {
            mm_input_script_sample(&script, (float)i / rates[r], &in);
            mm_trajectory_update(&t, &in, 1.0f / rates[r]);
        }
        end[r] = t.position;
        end_facing[r] = t.facing;
        mm_quat f[4];
        mm_trajectory_sample(&t, &in, times, 4, samples[r], f);
        mm_trajectory_free(&t);
    }
    for (int r = 1; r < 3; ++r) {
        assert_near(mm_vec3_distance(end[r], end[0]), 0, 1e-3);
        assert_near(mm_quat_angle_between(end_facing[r], end_facing[0]), 0, 1e-3);
        for (int k = 0; k < 4; ++k) assert_near(mm_vec3_distance(samples[r][k], samples[0][k]), 0, 1e-3);
    }
    mm_input_script_free(&script);
}

static void test_speeds_and_turns(void **state)
{
    (void)state;
    mm_trajectory_desc d;
    mm_trajectory_defaults(&d);
    mm_trajectory t;
    assert_int_equal(mm_trajectory_init(&t, &d, NULL), MM_OK);
    mm_input walk = stick(0, 1, MM_GAIT_WALK);
    for (int i = 0; i < 180; ++i) mm_trajectory_update(&t, &walk, 1.0f / 60);
    assert_near(t.velocity.z, d.gaits[MM_GAIT_WALK].forward_speed, 1e-3);
    assert_near(t.velocity.x, 0, 1e-6);
    assert_near(yaw(t.facing), 0, 1e-6);
    /* the prediction goes straight on at that speed, the past straight back */
    const float times[2] = {1.0f, -1.0f};
    mm_vec3 p[2];
    mm_quat f[2];
    mm_trajectory_sample(&t, &walk, times, 2, p, f);
    assert_near(p[0].z - t.position.z, 1.5, 2e-3);
    assert_near(t.position.z - p[1].z, 1.5, 5e-3);

    /* right: the facing turns to +X and the speed is the walk's */
    mm_input right = stick(1, 0, MM_GAIT_WALK);
    for (int i = 0; i < 180; ++i) mm_trajectory_update(&t, &right, 1.0f / 60);
    assert_near(yaw(t.facing), MM_PI / 2, 1e-2);
    assert_near(t.velocity.x, 1.5, 1e-2);
    /* the facing spring: half the turn after one half-life */
    mm_trajectory_reset(&t, mm_vec3_make(0, 0, 0), mm_quat_identity());
    mm_trajectory_update(&t, &right, d.gaits[MM_GAIT_WALK].rotation_halflife);
    assert_near(yaw(t.facing), MM_PI / 4, 1e-3);

    /* run: faster, and the gait style weights follow */
    mm_input run = stick(0, -1, MM_GAIT_RUN);
    for (int i = 0; i < 240; ++i) mm_trajectory_update(&t, &run, 1.0f / 60);
    assert_near(t.velocity.z, -4.0, 1e-2);
    assert_true(t.gait_weights[MM_GAIT_RUN] > 0.99f && t.gait_weights[MM_GAIT_WALK] < 0.01f);

    /* strafing: facing held forward, sideways and backward speeds from the ellipse */
    mm_input strafe = stick(1, 0, MM_GAIT_WALK);
    strafe.strafe = true;
    strafe.has_facing = true;
    strafe.facing[0] = 0;
    strafe.facing[1] = 1;
    for (int i = 0; i < 240; ++i) mm_trajectory_update(&t, &strafe, 1.0f / 60);
    assert_near(yaw(t.facing), 0, 1e-2);
    assert_near(t.velocity.x, d.gaits[MM_GAIT_WALK].side_speed, 1e-2);
    strafe.stick[0] = 0;
    strafe.stick[1] = -1;
    for (int i = 0; i < 240; ++i) mm_trajectory_update(&t, &strafe, 1.0f / 60);
    assert_near(t.velocity.z, -d.gaits[MM_GAIT_WALK].backward_speed, 1e-2);
    /* letting go keeps the last facing */
    mm_input none = stick(0, 0, MM_GAIT_WALK);
    for (int i = 0; i < 240; ++i) mm_trajectory_update(&t, &none, 1.0f / 60);
    assert_near(mm_vec3_length(t.velocity), 0, 1e-2);
    assert_near(yaw(t.facing), 0, 1e-2);
    mm_trajectory_free(&t);
}

static void test_bad_input(void **state)
{
    (void)state;
    mm_trajectory t;
    assert_int_equal(mm_trajectory_init(&t, NULL, NULL), MM_OK);
    mm_input in = stick(NAN, INFINITY, MM_GAIT_WALK);
    mm_trajectory_update(&t, &in, 1.0f / 60);
    in = stick(1e30f, 1e30f, (mm_gait)99);
    const float dts[6] = {0.0f, -1.0f, NAN, INFINITY, 1.0f, 1.0f / 60};
    for (int i = 0; i < 6; ++i) mm_trajectory_update(&t, &in, dts[i]);
    assert_true(isfinite(t.position.x) && isfinite(t.position.z) && isfinite(t.facing.w));
    assert_true(mm_vec3_length(t.velocity) <= 1.5f * 1.001f); /* a huge stick counts as a full one */
    const float times[3] = {NAN, -100.0f, 100.0f};
    mm_vec3 p[3];
    mm_quat f[3];
    mm_trajectory_sample(&t, &in, times, 3, p, f);
    for (int i = 0; i < 3; ++i) assert_true(isfinite(p[i].x) && isfinite(f[i].w));
    mm_trajectory_update(&t, NULL, 0.1f); /* no input: neutral */
    mm_trajectory_free(&t);
    mm_trajectory_desc d;
    mm_trajectory_defaults(&d);
    d.gaits[MM_GAIT_RUN].forward_speed = NAN;
    assert_int_equal(mm_trajectory_init(&t, &d, NULL), MM_ERR_OUT_OF_RANGE);
    mm_trajectory_defaults(&d);
    d.history_rate = MM_OFF; /* 0 samples per second */
    assert_int_equal(mm_trajectory_init(&t, &d, NULL), MM_ERR_OUT_OF_RANGE);
    /* zero means default: a zeroed desc with one field set is the defaults plus that field, and
     * MM_OFF makes a field 0 */
    mm_trajectory_desc zero, want;
    memset(&zero, 0, sizeof zero);
    zero.gaits[MM_GAIT_WALK].side_speed = MM_OFF;
    zero.gait_halflife = 0.5f;
    assert_int_equal(mm_trajectory_init(&t, &zero, NULL), MM_OK);
    mm_trajectory_defaults(&want);
    want.gaits[MM_GAIT_WALK].side_speed = 0.0f;
    want.gait_halflife = 0.5f;
    assert_memory_equal(&t.desc, &want, sizeof want);
    mm_trajectory_free(&t);
}

/* The update that gives the desired velocity and facing (mm__trajectory_update_desired, which
 * reuses those the update moved toward) against mm_trajectory_update then mm_trajectory_desired,
 * bit for bit, on random input in the open and against a wall; and the samples of the future
 * (one facing gap for all of them) against mm_trajectory_predict, which steps each alone. */
static void test_update_desired_bits(void **state)
{
    (void)state;
    mm_scene scene;
    mm_scene_init(&scene, 0.0f);
    assert_int_equal(
        mm_scene_add_box(&scene, mm_vec3_make(0.0f, 1.0f, 3.0f), mm_vec3_make(8.0f, 2.0f, 0.5f), 0.3f),
        MM_OK);
    const float times[5] = {-0.5f, -0.1f, 0.3333333f, 0.6666667f, 1.0f};
    int walls_touched = 0;
    for (int seed = 1; seed <= 6; ++seed) {
        mm_input_script script;
        mm_input_random_desc rd = {30.0f, 0.7f, 0, 0.2f, 0, NULL};
        assert_int_equal(mm_input_script_random(&script, (uint64_t)seed, &rd), MM_OK);
        mm_trajectory a, b;
        assert_int_equal(mm_trajectory_init(&a, NULL, NULL), MM_OK);
        assert_int_equal(mm_trajectory_init(&b, NULL, NULL), MM_OK);
        bool walls = seed % 2 == 0;
        if (walls) {
            mm_trajectory_set_scene(&a, &scene, -1.0f);
            mm_trajectory_set_scene(&b, &scene, -1.0f);
        }
        for (int i = 0; i < 60 * 30; ++i) {
            mm_input in;
            mm_input_script_sample(&script, (float)i / 60.0f, &in);
            mm_vec3 va, vb;
            mm_quat fa, fb;
            mm_trajectory_update(&a, &in, 1.0f / 60.0f);
            mm_trajectory_desired(&a, &in, &va, &fa);
            mm__trajectory_update_desired(&b, &in, 1.0f / 60.0f, &vb, &fb);
            assert_memory_equal(&va, &vb, sizeof va);
            assert_memory_equal(&fa, &fb, sizeof fa);
            assert_memory_equal(&a.position, &b.position, sizeof a.position);
            assert_memory_equal(&a.facing, &b.facing, sizeof a.facing);
            walls_touched += a.contact_count > 0;
            if (walls || i % 7 != 0) continue;
            mm_vec3 positions[5];
            mm_quat facings[5];
            mm_trajectory_sample(&b, &in, times, 5, positions, facings);
            for (int k = 2; k < 5; ++k) {
                mm_vec3 p;
                mm_quat f;
                mm_trajectory_predict(&b, vb, fb, mm_input_gait(&in), times[k], &p, &f, NULL);
                assert_memory_equal(&p, &positions[k], sizeof p);
                assert_memory_equal(&f, &facings[k], sizeof f);
            }
        }
        mm_trajectory_free(&a);
        mm_trajectory_free(&b);
        mm_input_script_free(&script);
    }
    assert_true(walls_touched > 0); /* the wall's path was taken */
}

/* A stick turned 120 degrees for 0.13 s at a walk, then let go: the stop keeps the turn. While
 * stopping, the gap between the velocity's heading and the last velocity asked for shrinks by
 * 2^(-dt / velocity_halflife) each tick (the spring toward zero turns nothing itself), so from the
 * gap g at release it is within 20 degrees after velocity_halflife log2(g / 20 deg), one tick of
 * slack; the speed left then, (1 + y t) e^(-y t) of the release's with y = 2 ln 2 / halflife (about
 * 7% of a walk after 3.2 half-lives), is still a course to measure. Strafing (facing held ahead) the
 * velocity asked for is the stick on the gait's ellipse in the facing's frame: the stop turns
 * toward that. Before, the velocity came to rest on the old course, the turn lost (its heading
 * stayed over 20 degrees off). */
static void test_stop_keeps_last_turn(void **state)
{
    (void)state;
    for (int strafe = 0; strafe < 2; ++strafe) {
        mm_trajectory t;
        assert_int_equal(mm_trajectory_init(&t, NULL, NULL), MM_OK);
        const float dt = 1.0f / 60, halflife = t.desc.gaits[MM_GAIT_WALK].velocity_halflife;
        const float turn = (float)(120 * MM_DEG_TO_RAD), near = (float)(20 * MM_DEG_TO_RAD);
        mm_input in = stick(0, 1, MM_GAIT_WALK);
        in.strafe = strafe, in.has_facing = strafe, in.facing[1] = 1.0f;
        for (int i = 0; i < 180; ++i) mm_trajectory_update(&t, &in, dt);
        in.stick[0] = sinf(turn), in.stick[1] = cosf(turn);
        mm_vec3 asked;
        mm_trajectory_desired(&t, &in, &asked, NULL);
        float want = atan2f(asked.x, asked.z);
        for (int i = 0; i < 8; ++i) mm_trajectory_update(&t, &in, dt);
        float gap = fabsf(remainderf(want - atan2f(t.velocity.x, t.velocity.z), 2.0f * (float)MM_PI));
        assert_true(gap > near); /* the simulation has not turned yet */
        float bound = halflife * log2f(gap / near) + dt, reached = -1.0f;
        in.stick[0] = in.stick[1] = 0.0f;
        for (int i = 1; i <= 180 && reached < 0.0f; ++i) {
            mm_trajectory_update(&t, &in, dt);
            float speed = sqrtf(t.velocity.x * t.velocity.x + t.velocity.z * t.velocity.z);
            if (speed < 0.05f) break;
            if (fabsf(remainderf(want - atan2f(t.velocity.x, t.velocity.z), 2.0f * (float)MM_PI)) < near)
                reached = (float)i * dt;
        }
        assert_true(reached > 0.0f);
        assert_true(reached <= bound);
        mm_trajectory_free(&t);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tick_rate_independent),
        cmocka_unit_test(test_speeds_and_turns),
        cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_update_desired_bits),
        cmocka_unit_test(test_stop_keeps_last_turn),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
