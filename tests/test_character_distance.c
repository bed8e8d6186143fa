/* Distance matching and warping in the character controller on the built-in set: orientation
 * warping while strafing, stride warping through starts and stops. */
#include <math.h>

#include <mm/character.h>

#include "runtime/character/state.h"

#include "test_databases.h"
#include "test_util.h"

static int joint_named(const mm_database *db, const char *name)
{
    for (int j = 0; j < db->joint_count; ++j)
        if (strcmp(db->joints[j].name, name) == 0) return j;
    return -1;
}

/* The controller on the built-in set: strafing diagonally while facing ahead. Without strafe the
 * angle stays exactly 0; with it, it stays within the maximum, moves at most as fast as the
 * smoothing lets it, and when it is not 0 the hips have turned by it (against the pose before the
 * layers) while the head keeps its world rotation. */
static void test_orientation_controller(void **state)
{
    (void)state;
    mm_database db;
    mm_searcher searcher;
    assert_int_equal(test_build_synth_database(&db), 0);
    assert_int_equal(mm_searcher_init(&searcher, &db, NULL, NULL), MM_OK);
    const int hips = joint_named(&db, "Hips"), head = joint_named(&db, "Head");
    assert_true(hips > 0 && head > 0);
    for (int strafe = 0; strafe < 2; ++strafe) {
        mm_character_desc d;
        mm_character_defaults(&d);
        d.warping = true;
        d.no_foot_ik = true;             /* compare with the animated pose: no layer after warping */
        d.stride_min = d.stride_max = 1; /* and no stride warping */
        d.orientation_max = 0.6f;
        d.orientation_speed = 6.0f;
        mm_character c;
        assert_int_equal(mm_character_init(&c, &db, &searcher, &d, NULL), MM_OK);
        mm_input in;
        memset(&in, 0, sizeof in);
        in.stick[0] = 0.6f, in.stick[1] = 0.6f;
        in.strafe = strafe;
        in.has_facing = strafe;
        in.facing[1] = 1.0f;
        const float dt = 1.0f / 60.0f;
        const double bound = 2.0 * 0.6 * (1.0 - exp(-6.0 * dt)) + 1e-5;
        float previous = 0.0f, largest = 0.0f;
        int checked = 0;
        mm_xform *pose = test_malloc(sizeof(mm_xform) * (size_t)db.joint_count);
        for (int tick = 0; tick < 600; ++tick) {
            mm_character_update(&c, &in, dt);
            float a = c.state->warping.orientation_angle;
            if (!strafe) assert_true(a == 0.0f);
            assert_true(fabsf(a) <= 0.6f + 1e-6f);
            assert_true(fabsf(a - previous) <= bound);
            previous = a;
            largest = fmaxf(largest, fabsf(a));
            if (fabsf(a) < 0.05f) continue;
            pose[0] = c.root;
            for (int j = 1; j < db.joint_count; ++j)
                pose[j] =
                    mm_xform_mul(pose[db.joints[j].parent], mm_xform_make(c.state->transition.rotations[j],
                                                                          c.state->transition.positions[j]));
            assert_near(mm_quat_angle_between(c.global[hips].rotation,
                                              mm_quat_mul(mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), a),
                                                          pose[hips].rotation)),
                        0.0, 1e-3);
            assert_near(mm_quat_angle_between(c.global[head].rotation, pose[head].rotation), 0.0, 1e-3);
            ++checked;
        }
        if (strafe) assert_true(checked > 30 && largest > 0.3f);
        test_free(pose);
        mm_character_free(&c);
    }
    mm_searcher_free(&searcher);
    mm_database_free(&db);
}

/* Stride warping in the controller on the built-in set, stick on and off (starts and stops, which
 * are no loops): the stride scale stays in its clamp and, outside loop cycles (played at their
 * exact ratio) and the falls back to 1 at rest, moves per tick at most by what its 0.1 s half-life
 * filter allows across the clamp; the pelvis drop never jumps by more than its 0.05 s filter allows
 * over a 1 m drop, and the pelvis is lowered by exactly that drop against the pose before the
 * layers. */
static void test_stride_controller(void **state)
{
    (void)state;
    mm_database db;
    mm_searcher searcher;
    assert_int_equal(test_build_synth_database(&db), 0);
    assert_int_equal(mm_searcher_init(&searcher, &db, NULL, NULL), MM_OK);
    mm_character_desc d;
    mm_character_defaults(&d);
    d.warping = true;
    d.distance_matching = true;
    d.no_foot_ik = true;
    mm_character c;
    assert_int_equal(mm_character_init(&c, &db, &searcher, &d, NULL), MM_OK);
    const float dt = 1.0f / 60.0f;
    const double scale_step = (1.0 - exp2(-dt / 0.1)) * (d.stride_max - d.stride_min) + 1e-5;
    const double drop_step = (1.0 - exp2(-dt / 0.05)) * 1.0 + 1e-5;
    float scale = 1.0f, drop = 0.0f;
    int previous_playback = MM_PLAYBACK_CLOCK, smoothed = 0, dropped = 0;
    const int pelvis = c.state->rig.pelvis;
    assert_true(pelvis > 0);
    for (int tick = 0; tick < 1200; ++tick) {
        mm_input in;
        memset(&in, 0, sizeof in);
        int on = (tick / 150) % 2 == 0;
        in.stick[1] = on ? 1.0f : 0.0f;
        in.stick[0] = on ? 0.3f : 0.0f;
        mm_character_update(&c, &in, dt);
        assert_true(c.stride_scale >= d.stride_min - 1e-6f && c.stride_scale <= d.stride_max + 1e-6f);
        assert_true(c.state->warping.stride_drop >= 0.0f && c.state->warping.stride_drop <= 1.0f);
        if (c.playback != MM_PLAYBACK_CYCLE && previous_playback != MM_PLAYBACK_CYCLE &&
            c.stride_scale != 1.0f && scale != 1.0f) {
            assert_true(fabsf(c.stride_scale - scale) <= scale_step);
            ++smoothed;
        }
        assert_true(fabsf(c.state->warping.stride_drop - drop) <= drop_step);
        if (c.state->warping.stride_drop > 0.0f) {
            mm_vec3 lowered = mm_vec3_sub(c.state->transition.positions[pelvis], c.local_positions[pelvis]);
            mm_vec3 world = mm_quat_rotate(c.global[db.joints[pelvis].parent].rotation, lowered);
            assert_near(world.y, c.state->warping.stride_drop, 1e-4);
            ++dropped;
        }
        scale = c.stride_scale, drop = c.state->warping.stride_drop;
        previous_playback = c.playback;
    }
    printf("smoothed scale ticks %d, dropped ticks %d\n", smoothed, dropped);
    mm_character_free(&c);
    mm_searcher_free(&searcher);
    mm_database_free(&db);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_orientation_controller),
        cmocka_unit_test(test_stride_controller),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
