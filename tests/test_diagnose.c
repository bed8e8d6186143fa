/* The diagnostics of a database (mm/diagnose.h, docs/database.md "Diagnostics"): each warning on a
 * database built from hand-made takes that lack what it warns about, and not once they have it;
 * the warnings the built-in set (and LAFAN1, with MM_DATA_DIR) give. */
#include <math.h>
#include <mm/diagnose.h>
#include <mm/gait.h>

#include "test_databases.h"
#include "test_takes.h"
#include "test_util.h"

#define FPS 30.0f

/* A take of seconds s whose hips move with velocity (vx, vz) m/s (facing +Z throughout) scaled by
 * ramp(t) in [0, 1]: 1 throughout when ramp is NULL. */
typedef float (*ramp_fn)(float t);
static void make_take(mm_clip *clip, float seconds, float vx, float vz, ramp_fn ramp, float size,
                      const char *left_hand, const char *right_hand)
{
    mm_skeleton s;
    test_take_skeleton_named(&s, size, left_hand, right_hand);
    int frames = (int)lroundf(seconds * FPS) + 1;
    assert_int_equal(mm_clip_init(clip, &s, frames, FPS, NULL), MM_OK);
    mm_skeleton_free(&s);
    float x = 0.0f, z = 0.0f;
    for (int f = 0; f < frames; ++f) {
        mm_clip_positions(clip, f)[0] = mm_vec3_make(x, size, z);
        float k = ramp ? ramp((float)f / FPS) : 1.0f;
        x += vx * k / FPS;
        z += vz * k / FPS;
    }
}

/* Stands 1.5 s, speeds up over 1 s, walks 2 s, slows down over 1 s, stands 1.5 s (7 s). */
static float stop_and_go(float t)
{
    if (t < 1.5f) return 0.0f;
    if (t < 2.5f) return t - 1.5f;
    if (t < 4.5f) return 1.0f;
    if (t < 5.5f) return 5.5f - t;
    return 0.0f;
}

/* Builds t and diagnoses the result (with the build's report when with_report). */
static void diagnose(test_takes *t, int with_report, mm_diagnosis *d)
{
    mm_db_build_report report;
    mm_db_build_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.report = &report;
    mm_database db;
    mm_error err;
    memset(&err, 0, sizeof err);
    if (mm_database_build(&t->cfg, t->clips, &desc, &db, &err) != MM_OK) fail_msg("build: %s", err.message);
    assert_int_equal(mm_database_diagnose(&db, with_report ? &report : NULL, NULL, d), MM_OK);
    mm_database_free(&db);
}

static int count_of(const mm_diagnosis *d, mm_diagnostic_code code)
{
    int n = 0;
    for (int i = 0; i < d->count; ++i) n += d->items[i].code == code;
    return n;
}

/* The message of the first item of code holding text. */
static void assert_says(const mm_diagnosis *d, mm_diagnostic_code code, const char *text)
{
    for (int i = 0; i < d->count; ++i)
        if (d->items[i].code == code && strstr(d->items[i].message, text)) return;
    fail_msg("no %s warning says '%s'", mm_diagnostic_code_name(code), text);
}

static void test_code_names(void **state)
{
    (void)state;
    const char *names[MM_DIAG_CODE_COUNT] = {"no_idle",           "speed_not_covered", "no_stops",
                                             "no_starts",         "role_missing",      "height",
                                             "postures_left_out", "postures_tagged",   "speed_envelope"};
    for (int c = 0; c < MM_DIAG_CODE_COUNT; ++c)
        assert_string_equal(mm_diagnostic_code_name((mm_diagnostic_code)c), names[c]);
    assert_null(mm_diagnostic_code_name(MM_DIAG_CODE_COUNT));
    assert_int_equal(mm_database_diagnose(NULL, NULL, NULL, NULL), MM_ERR_INVALID_ARGUMENT);
}

/* A walk at 1.5 m/s alone: no idle, no stop, no start, the other speeds uncovered; then an idle
 * take and one that starts and stops answer the first three. */
static void test_idle_stops_starts(void **state)
{
    (void)state;
    test_takes t;
    test_takes_start(&t);
    make_take(test_takes_add(&t, "walk", MM_CLIP_LOCOMOTION), 10.0f, 0.0f, 1.5f, NULL, 1.0f, "LeftHand",
              "RightHand");
    mm_diagnosis d;
    diagnose(&t, 1, &d);
    assert_int_equal(count_of(&d, MM_DIAG_NO_IDLE), 1);
    assert_int_equal(count_of(&d, MM_DIAG_NO_STOPS), 1);
    assert_int_equal(count_of(&d, MM_DIAG_NO_STARTS), 1);
    assert_says(&d, MM_DIAG_NO_IDLE, "add an idle clip");
    assert_int_equal(count_of(&d, MM_DIAG_ROLE_MISSING), 0);
    assert_int_equal(count_of(&d, MM_DIAG_HEIGHT), 0);
    assert_int_equal(count_of(&d, MM_DIAG_POSTURES_LEFT_OUT) + count_of(&d, MM_DIAG_POSTURES_TAGGED), 0);
    assert_int_equal(d.idle_clips, 0);
    assert_int_equal(d.stops, 0);
    assert_int_equal(d.starts, 0);
    /* the standing height: the head 1.55 m above the hips' 1 m, over the toes 0.05 m up */
    assert_near(d.height, 1.5 / MM_POSTURE_HEAD_TO_STATURE, 1e-3);
    /* walk forward at the default 1.5 m/s is covered by every frame; the rest by none */
    const mm_speed_coverage *walk = &d.speeds[0];
    assert_int_equal(walk->gait, MM_GAIT_WALK);
    assert_int_equal(walk->direction, 0);
    assert_false(walk->from_settings);
    assert_near(walk->speed, 1.5, 1e-6);
    assert_true(walk->covered);
    assert_true(walk->frames > 500);
    assert_int_equal(walk->near, walk->frames);
    assert_near(walk->p50, 1.5, 0.01);
    for (int k = 1; k < MM_DIAGNOSE_SPEEDS; ++k) assert_false(d.speeds[k].covered);
    assert_int_equal(count_of(&d, MM_DIAG_SPEED_NOT_COVERED), MM_DIAGNOSE_SPEEDS - 1);
    assert_says(&d, MM_DIAG_SPEED_NOT_COVERED, "walk side at 1.10 m/s (the runtime's default)");
    assert_says(&d, MM_DIAG_SPEED_NOT_COVERED, "it has no frame moving sideways");
    /* run forward at 4 m/s: the walk is there, but too slow */
    assert_says(&d, MM_DIAG_SPEED_NOT_COVERED, "run forward at 4.00 m/s");
    assert_says(&d, MM_DIAG_SPEED_NOT_COVERED, "forward it moves at 1.50-1.50 m/s");
    assert_says(&d, MM_DIAG_SPEED_NOT_COVERED, "runtime.run.forward_speed");

    make_take(test_takes_add(&t, "stand", MM_CLIP_IDLE), 5.0f, 0.0f, 0.0f, NULL, 1.0f, "LeftHand",
              "RightHand");
    make_take(test_takes_add(&t, "stop_and_go", MM_CLIP_LOCOMOTION), 7.0f, 0.0f, 1.2f, stop_and_go, 1.0f,
              "LeftHand", "RightHand");
    diagnose(&t, 1, &d);
    assert_int_equal(count_of(&d, MM_DIAG_NO_IDLE), 0);
    assert_int_equal(count_of(&d, MM_DIAG_NO_STOPS), 0);
    assert_int_equal(count_of(&d, MM_DIAG_NO_STARTS), 0);
    assert_int_equal(d.idle_clips, 2); /* stand and the loop the build made of it (idle_loop.make) */
    assert_true(d.stops >= 1);
    assert_int_equal(d.starts, 1);
    test_takes_free(&t);
}

/* The runtime's speeds: the settings' where the config sets them; a speed of 0 asks for nothing. */
static void test_speeds(void **state)
{
    (void)state;
    test_takes t;
    test_takes_start(&t);
    make_take(test_takes_add(&t, "walk", MM_CLIP_LOCOMOTION), 10.0f, 0.0f, 1.5f, NULL, 1.0f, "LeftHand",
              "RightHand");
    make_take(test_takes_add(&t, "side", MM_CLIP_LOCOMOTION), 4.0f, 0.6f, 0.0f, NULL, 1.0f, "LeftHand",
              "RightHand");
    make_take(test_takes_add(&t, "run", MM_CLIP_LOCOMOTION), 4.0f, 0.0f, 3.5f, NULL, 1.0f, "LeftHand",
              "RightHand");
    mm_runtime_config *rt = &t.cfg.runtime;
    rt->walk.set = MM_RUNTIME_SIDE_SPEED | MM_RUNTIME_BACKWARD_SPEED;
    rt->walk.side_speed = 0.6f;
    rt->walk.backward_speed = 0.0f;
    rt->run.set = MM_RUNTIME_FORWARD_SPEED | MM_RUNTIME_SIDE_SPEED | MM_RUNTIME_BACKWARD_SPEED;
    rt->run.forward_speed = 3.5f;
    rt->run.side_speed = 2.0f; /* the sidestep is far too slow */
    rt->run.backward_speed = 0.0f;
    mm_diagnosis d;
    diagnose(&t, 0, &d);
    assert_int_equal(count_of(&d, MM_DIAG_SPEED_NOT_COVERED), 1);
    assert_says(&d, MM_DIAG_SPEED_NOT_COVERED, "run side at 2.00 m/s (the database's runtime settings)");
    assert_says(&d, MM_DIAG_SPEED_NOT_COVERED, "sideways it moves at 0.60-0.60 m/s");
    assert_says(&d, MM_DIAG_SPEED_NOT_COVERED, "runtime.run.side_speed");
    assert_true(d.speeds[1].from_settings && d.speeds[1].covered && d.speeds[1].near > 100);
    assert_true(d.speeds[2].from_settings && d.speeds[2].covered && d.speeds[2].frames == 0);
    assert_false(d.speeds[0].from_settings);
    assert_true(d.speeds[3].covered && d.speeds[3].near > 100 && d.speeds[3].near < d.speeds[3].frames);

    /* a Walk tag keeps the walk out of the run: frames tagged with another gait are not played */
    t.cfg.tag_count = 1;
    snprintf(t.cfg.tag_names[0], MM_TAG_NAME_MAX, "Walk");
    mm_config_clip *walk = &t.cfg.clips[0];
    walk->tag_ranges = calloc(1, sizeof(mm_config_tag_range));
    walk->tag_range_count = 1;
    walk->tag_ranges[0] = (mm_config_tag_range){0, 0.0f, 10.0f};
    rt->run.forward_speed = 1.5f;
    diagnose(&t, 0, &d);
    assert_true(d.speeds[0].covered); /* walk forward 1.5 */
    assert_false(d.speeds[3].covered);
    assert_says(&d, MM_DIAG_SPEED_NOT_COVERED, "run forward at 1.50 m/s");
    test_takes_free(&t);
}

/* Roles naming no joint: the config leaves the hands empty (a name that is no joint fails the build). */
static void test_roles(void **state)
{
    (void)state;
    test_takes t;
    test_takes_start(&t);
    make_take(test_takes_add(&t, "walk", MM_CLIP_LOCOMOTION), 6.0f, 0.0f, 1.5f, NULL, 1.0f, "LHand", "RHand");
    t.cfg.left_hand[0] = t.cfg.right_hand[0] = '\0';
    mm_diagnosis d;
    diagnose(&t, 0, &d);
    assert_int_equal(count_of(&d, MM_DIAG_ROLE_MISSING), 2);
    assert_says(&d, MM_DIAG_ROLE_MISSING, "roles.left_hand names no joint");
    assert_says(&d, MM_DIAG_ROLE_MISSING, "set roles.right_hand in the config");
    snprintf(t.cfg.left_hand, MM_NAME_MAX, "LHand");
    snprintf(t.cfg.right_hand, MM_NAME_MAX, "RHand");
    diagnose(&t, 0, &d);
    assert_int_equal(count_of(&d, MM_DIAG_ROLE_MISSING), 0);
    test_takes_free(&t);
}

/* A body in centimetres read as metres, and one in metres read as centimetres. */
static void test_height(void **state)
{
    (void)state;
    const float sizes[2] = {100.0f, 0.01f};
    for (int i = 0; i < 2; ++i) {
        test_takes t;
        test_takes_start(&t);
        make_take(test_takes_add(&t, "walk", MM_CLIP_LOCOMOTION), 6.0f, 0.0f, 1.5f * sizes[i], NULL, sizes[i],
                  "LeftHand", "RightHand");
        mm_diagnosis d;
        diagnose(&t, 0, &d);
        assert_near(d.height, 1.5 / MM_POSTURE_HEAD_TO_STATURE * sizes[i], 1e-3 * sizes[i]);
        assert_int_equal(count_of(&d, MM_DIAG_HEIGHT), 1);
        assert_says(&d, MM_DIAG_HEIGHT, "the units look wrong");
        assert_says(&d, MM_DIAG_HEIGHT, "scale");
        test_takes_free(&t);
    }
}

/* More than a quarter of the judged frames in a T pose, or crouched: the build's report says so. */
static void test_postures(void **state)
{
    (void)state;
    for (int which = 0; which < 2; ++which) {
        test_takes t;
        test_takes_start(&t);
        mm_clip *take = test_takes_add(&t, "take", MM_CLIP_LOCOMOTION);
        make_take(take, 10.0f, 0.0f, 1.0f, NULL, 1.0f, "LeftHand", "RightHand");
        for (int f = 150; f < 270; ++f) { /* 4 s of 10 */
            if (which == 0) {
                mm_clip_positions(take, f)[3] = mm_vec3_make(0.8f, 0.15f, 0.0f);
                mm_clip_positions(take, f)[4] = mm_vec3_make(-0.8f, 0.15f, 0.0f);
            } else {
                mm_clip_positions(take, f)[0].y = 0.7f;
            }
        }
        mm_diagnosis d;
        diagnose(&t, 1, &d);
        mm_diagnostic_code code = which == 0 ? MM_DIAG_POSTURES_LEFT_OUT : MM_DIAG_POSTURES_TAGGED;
        assert_int_equal(count_of(&d, code), 1);
        assert_int_equal(count_of(&d, which == 0 ? MM_DIAG_POSTURES_TAGGED : MM_DIAG_POSTURES_LEFT_OUT), 0);
        assert_near(d.posture_share[which], 120.0 / 301.0, 1e-6);
        assert_says(&d, code, which == 0 ? "calibration 120" : "crouched 120");
        assert_says(&d, code, "postures.detect");
        /* without the report (a database loaded from its file) nothing is said of postures */
        diagnose(&t, 0, &d);
        assert_int_equal(count_of(&d, code), 0);
        assert_true(d.posture_share[which] == 0.0f);
        test_takes_free(&t);
    }
}

/* The built-in set: nothing to say (its sidesteps and backward walk are untagged: both gaits play
 * them, so the run's sideways and backward speeds are covered; docs/database.md, "Diagnostics"). */
static void test_builtin_set(void **state)
{
    (void)state;
    mm_database db;
    assert_int_equal(test_build_synth_database(&db), 0);
    mm_diagnosis d;
    assert_int_equal(mm_database_diagnose(&db, NULL, NULL, &d), MM_OK);
    for (int i = 0; i < d.count; ++i)
        printf("built-in: %s: %s\n", mm_diagnostic_code_name(d.items[i].code), d.items[i].message);
    assert_int_equal(d.count, 0);
    assert_near(d.height, 1.69, 0.02);
    mm_database_free(&db);
}

/* LAFAN1 (lafan1.json of scripts/data_configs.sh): covered speeds; its build tags more than a
 * quarter of the frames Crouch (walk4_subject1's stooped walk). */
static void test_lafan1(void **state)
{
    (void)state;
    const char *data = getenv("MM_DATA_DIR");
    if (!data || !*data) skip(); /* the built-in set alone */
    mm_database db;
    mm_db_build_report report;
    assert_int_equal(test_build_database_report(MM_DATA_CONFIGS "/lafan1.json", 0, &db, &report), 0);
    mm_diagnosis d;
    assert_int_equal(mm_database_diagnose(&db, &report, NULL, &d), MM_OK);
    for (int i = 0; i < d.count; ++i)
        printf("LAFAN1: %s: %s\n", mm_diagnostic_code_name(d.items[i].code), d.items[i].message);
    /* and lafan1.json's run.side_speed 2.1 m/s is above what its takes cover sideways (about 1.75) */
    assert_int_equal(d.count, 2);
    assert_int_equal(count_of(&d, MM_DIAG_POSTURES_TAGGED), 1);
    assert_says(&d, MM_DIAG_SPEED_ENVELOPE, "run side at 2.10 m/s");
    assert_near(d.height, 1.69, 0.02);
    assert_int_equal(mm_database_diagnose(&db, NULL, NULL, &d), MM_OK);
    assert_int_equal(d.count, 1);
    assert_int_equal(count_of(&d, MM_DIAG_SPEED_ENVELOPE), 1);
    mm_database_free(&db);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_code_names),  cmocka_unit_test(test_idle_stops_starts),
        cmocka_unit_test(test_speeds),      cmocka_unit_test(test_roles),
        cmocka_unit_test(test_height),      cmocka_unit_test(test_postures),
        cmocka_unit_test(test_builtin_set), cmocka_unit_test(test_lafan1),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
