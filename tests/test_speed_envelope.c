/* The speed envelope (mm/speed_envelope.h, docs/runtime.md "The speed envelope"): measured on a
 * database built from hand-made takes whose roots move at known speeds in known directions (the
 * envelope written out by hand from them), per gait through the gait tags; the simulated trajectory
 * bounded by it (speed cut, direction kept; none without it); the settings section's copy, through
 * a file and back, checked on load, and the character's desc made of it (or not, when the config
 * turns it off). */
#include <math.h>
#include <stdlib.h>

#include <mm/character.h>
#include <mm/config.h>
#include <mm/database_build.h>
#include <mm/speed_envelope.h>
#include <mm/trajectory.h>

#include "test_takes.h"
#include "test_util.h"

#define FPS   30.0f
#define SPEED 1e-3f /* m/s: speeds measured from finite differences of float positions */

/* A take of `seconds` whose hips move at `speed` m/s in `degrees` from forward (+Z) toward the
 * left (+X), facing +Z throughout. */
static void make_take(mm_clip *clip, float seconds, float speed, float degrees)
{
    mm_skeleton s;
    test_take_skeleton(&s);
    int frames = (int)lroundf(seconds * FPS) + 1;
    assert_int_equal(mm_clip_init(clip, &s, frames, FPS, NULL), MM_OK);
    mm_skeleton_free(&s);
    float a = degrees * (float)MM_DEG_TO_RAD, vx = speed * sinf(a), vz = speed * cosf(a);
    for (int f = 0; f < frames; ++f)
        mm_clip_positions(clip, f)[0] = mm_vec3_make(vx * (float)f / FPS, 1.0f, vz * (float)f / FPS);
}

enum { TAKES = 6 };

/* Forward 1.2 m/s (4 s), left 0.4 (4 s), backward 0.8 (4 s), forward-right (45 degrees right)
 * 0.7 (4 s); a burst to the right at 2 m/s and one forward at 3 m/s, each 0.3 s (too short to
 * count: fewer than MM_SPEED_ENVELOPE_COVER_SECONDS of frames). */
static void make_takes(test_takes *t)
{
    test_takes_start(t);
    const char *names[TAKES] = {"forward", "left", "backward", "diagonal", "burst_right", "burst_forward"};
    const float seconds[TAKES] = {4, 4, 4, 4, 0.3f, 0.3f},
                speeds[TAKES] = {1.2f, 0.4f, 0.8f, 0.7f, 2.0f, 3.0f},
                degrees[TAKES] = {0, 90, 180, -45, -90, 0};
    for (int i = 0; i < TAKES; ++i)
        make_take(test_takes_add(t, names[i], MM_CLIP_LOCOMOTION), seconds[i], speeds[i], degrees[i]);
}

static void build(test_takes *t, mm_database *db)
{
    mm_error err;
    memset(&err, 0, sizeof err);
    if (mm_database_build(&t->cfg, t->clips, NULL, db, &err) != MM_OK) fail_msg("build: %s", err.message);
}

/* By hand from the takes: a bin takes the frames within 30 degrees of its direction (bins 22.5
 * degrees apart): forward 1.2 in bins 15, 0, 1; left 0.4 in 3, 4, 5; backward 0.8 in 7, 8, 9;
 * forward-right 0.7 in 13, 14 and 15 (where the forward take's 1.2 is faster); none in 2, 6, 10,
 * 11, 12 (the right burst is too short). */
static const float expected[MM_SPEED_ENVELOPE_BINS] = {1.2f, 1.2f, 0.0f, 0.4f, 0.4f, 0.4f, 0.0f, 0.8f,
                                                       0.8f, 0.8f, 0.0f, 0.0f, 0.0f, 0.7f, 0.7f, 1.2f};

static void assert_envelope(const float *speeds, const float *want)
{
    for (int k = 0; k < MM_SPEED_ENVELOPE_BINS; ++k)
        if (fabsf(speeds[k] - want[k]) > SPEED)
            fail_msg("bin %d: %g m/s, expected %g", k, speeds[k], want[k]);
}

static void test_measured(void **state)
{
    (void)state;
    test_takes t;
    make_takes(&t);
    mm_database db;
    build(&t, &db);
    mm_speed_envelope env[MM_GAIT_COUNT];
    assert_int_equal(mm_speed_envelope_measure(&db, NULL, env), MM_OK);
    /* no gait tags: every gait plays every frame */
    for (int g = 0; g < MM_GAIT_COUNT; ++g) assert_envelope(env[g].speeds, expected);
    /* the build stored it in the settings */
    for (int g = 0; g < MM_GAIT_COUNT; ++g)
        assert_memory_equal(db.settings->envelope[g], env[g].speeds, sizeof env[g]);
    assert_int_equal(mm_speed_envelope_measure(NULL, NULL, env), MM_ERR_INVALID_ARGUMENT);
    mm_database_free(&db);

    /* tagged Run, the forward take is the run's alone: the walk's forward bins lose it */
    t.cfg.tag_count = 1;
    snprintf(t.cfg.tag_names[0], MM_TAG_NAME_MAX, "Run");
    mm_config_clip *forward = &t.cfg.clips[0];
    forward->tag_ranges = calloc(1, sizeof(mm_config_tag_range));
    forward->tag_range_count = 1;
    forward->tag_ranges[0] = (mm_config_tag_range){0, 0.0f, 4.0f};
    build(&t, &db);
    assert_int_equal(mm_speed_envelope_measure(&db, NULL, env), MM_OK);
    float walk[MM_SPEED_ENVELOPE_BINS];
    memcpy(walk, expected, sizeof walk);
    walk[0] = walk[1] = 0.0f;
    walk[15] = 0.7f; /* the forward-right take alone */
    assert_envelope(env[MM_GAIT_WALK].speeds, walk);
    assert_envelope(env[MM_GAIT_RUN].speeds, expected);
    mm_database_free(&db);
    test_takes_free(&t);
}

/* A trajectory bounded by the hand-made envelope, every gait speed 2 m/s (a circle: the direction
 * asked for is the stick's). */
static void make_trajectory(mm_trajectory *tr, bool bounded)
{
    mm_trajectory_desc d;
    memset(&d, 0, sizeof d);
    for (int g = 0; g < MM_GAIT_COUNT; ++g) {
        d.gaits[g].forward_speed = d.gaits[g].side_speed = d.gaits[g].backward_speed = 2.0f;
        memcpy(d.envelopes[g].speeds, expected, sizeof expected);
    }
    memset(d.envelopes[MM_GAIT_CROUCH].speeds, 0, sizeof d.envelopes[MM_GAIT_CROUCH].speeds); /* none */
    d.bounded = bounded;
    assert_int_equal(mm_trajectory_init(tr, &d, NULL), MM_OK);
}

/* Strafing facing +Z with a full stick `degrees` from forward toward the left. */
static mm_input strafe(float degrees, mm_gait gait)
{
    mm_input in;
    memset(&in, 0, sizeof in);
    float a = degrees * (float)MM_DEG_TO_RAD;
    in.stick[0] = sinf(a), in.stick[1] = cosf(a);
    in.strafe = true, in.has_facing = true;
    in.facing[0] = 0.0f, in.facing[1] = 1.0f;
    in.gait = gait;
    return in;
}

static void test_bounded(void **state)
{
    (void)state;
    mm_trajectory tr;
    make_trajectory(&tr, true);
    const mm_trajectory_desc *d = &tr.desc;
    /* at the bins' directions, their speeds; between two, linear in the angle; a full turn wraps */
    for (int k = 0; k < MM_SPEED_ENVELOPE_BINS; ++k)
        assert_float_equal(mm_trajectory_envelope_speed(d, MM_GAIT_WALK, 2.0f * (float)MM_PI * k / 16.0f),
                           expected[k], 1e-5);
    assert_float_equal(mm_trajectory_envelope_speed(d, MM_GAIT_WALK, (float)(33.75 * MM_DEG_TO_RAD)), 0.6f,
                       1e-5);
    assert_float_equal(mm_trajectory_envelope_speed(d, MM_GAIT_WALK, (float)(-157.5 * MM_DEG_TO_RAD)), 0.8f,
                       1e-5);
    assert_float_equal(mm_trajectory_envelope_speed(d, MM_GAIT_WALK, (float)(-146.25 * MM_DEG_TO_RAD)), 0.4f,
                       1e-5);
    assert_true(isinf(mm_trajectory_envelope_speed(d, MM_GAIT_CROUCH, 0.0f))); /* all 0: no envelope */

    /* the desired velocity: the direction kept, the speed the envelope's there (2 m/s asked) */
    const float degrees[5] = {0.0f, 90.0f, 180.0f, 33.75f, 135.0f};
    const float speeds[5] = {1.2f, 0.4f, 0.8f, 0.6f, 0.0f};
    for (int i = 0; i < 5; ++i) {
        mm_input in = strafe(degrees[i], MM_GAIT_WALK);
        mm_vec3 v;
        mm_trajectory_desired(&tr, &in, &v, NULL);
        assert_float_equal(mm_vec3_length(v), speeds[i], 1e-5);
        float a = degrees[i] * (float)MM_DEG_TO_RAD;
        assert_float_equal(v.x, speeds[i] * sinf(a), 1e-5); /* along the stick */
        assert_float_equal(v.z, speeds[i] * cosf(a), 1e-5);
        /* a stick at half way asks for 1 m/s: over the envelope forward-left, under it forward */
        in.stick[0] *= 0.5f, in.stick[1] *= 0.5f;
        mm_trajectory_desired(&tr, &in, &v, NULL);
        assert_float_equal(mm_vec3_length(v), fminf(speeds[i], 1.0f), 1e-5);
    }
    /* the simulation follows it: after 5 s strafing left, 0.4 m/s to the left */
    mm_input left = strafe(90.0f, MM_GAIT_WALK);
    for (int i = 0; i < 300; ++i) mm_trajectory_update(&tr, &left, 1.0f / 60.0f);
    assert_float_equal(tr.velocity.x, 0.4f, 1e-3);
    assert_float_equal(tr.velocity.z, 0.0f, 1e-3);
    /* a gait without an envelope asks for the gait speed (2 m/s) */
    mm_input crouch = strafe(90.0f, MM_GAIT_CROUCH);
    mm_vec3 v;
    mm_trajectory_desired(&tr, &crouch, &v, NULL);
    assert_float_equal(mm_vec3_length(v), 2.0f, 1e-5);
    mm_trajectory_free(&tr);

    /* not bounded: the gait speeds alone */
    make_trajectory(&tr, false);
    mm_input in = strafe(135.0f, MM_GAIT_WALK);
    mm_trajectory_desired(&tr, &in, &v, NULL);
    assert_float_equal(mm_vec3_length(v), 2.0f, 1e-5);
    assert_true(isinf(mm_trajectory_envelope_speed(&tr.desc, MM_GAIT_WALK, 0.0f)));
    mm_trajectory_free(&tr);

    /* a speed out of range is refused */
    mm_trajectory_desc bad;
    memset(&bad, 0, sizeof bad);
    bad.bounded = true;
    bad.envelopes[MM_GAIT_RUN].speeds[3] = NAN;
    assert_int_equal(mm_trajectory_init(&tr, &bad, NULL), MM_ERR_OUT_OF_RANGE);
    bad.envelopes[MM_GAIT_RUN].speeds[3] = 60.0f;
    assert_int_equal(mm_trajectory_init(&tr, &bad, NULL), MM_ERR_OUT_OF_RANGE);
}

/* The settings' envelope through a file and back, refused when out of range, and the desc made of
 * it (on by default, off by the config). */
static void test_file_and_desc(void **state)
{
    (void)state;
    test_takes t;
    make_takes(&t);
    mm_database db;
    build(&t, &db);
    const char *path = MM_TEST_OUT "/speed_envelope.mmdb";
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_database_save(&db, path, &err), MM_OK);
    mm_database back;
    assert_int_equal(mm_database_load(path, NULL, &back, &err), MM_OK);
    assert_memory_equal(back.settings->envelope, db.settings->envelope, sizeof db.settings->envelope);
    mm_speed_envelope env[MM_GAIT_COUNT];
    assert_int_equal(mm_speed_envelope_measure(&back, NULL, env), MM_OK); /* measured again: the same */
    for (int g = 0; g < MM_GAIT_COUNT; ++g) assert_envelope(back.settings->envelope[g], env[g].speeds);

    mm_character_desc d;
    assert_int_equal(mm_character_desc_from_database(&d, &back, &err), MM_OK);
    assert_true(d.trajectory.bounded);
    for (int g = 0; g < MM_GAIT_COUNT; ++g) assert_envelope(d.trajectory.envelopes[g].speeds, expected);

    /* a speed out of range in the file is refused, naming the envelope */
    size_t at = (size_t)((const unsigned char *)back.settings - (const unsigned char *)back.data);
    unsigned char *copy = aligned_alloc(MM_DB_ALIGN, (back.size + MM_DB_ALIGN) / MM_DB_ALIGN * MM_DB_ALIGN);
    assert_non_null(copy);
    memcpy(copy, back.data, back.size);
    float wrong = -1.0f;
    memcpy(copy + at + offsetof(mm_database_settings, envelope) + 5 * sizeof(float), &wrong, sizeof wrong);
    mm_database bad;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_database_load_memory(copy, back.size, false, &bad, &err), MM_ERR_SYNTAX);
    assert_non_null(strstr(err.message, "envelope of walk, direction 5"));
    free(copy);
    mm_database_free(&back);
    mm_database_free(&db);

    /* runtime.speed_envelope false: stored all the same, not applied */
    t.cfg.runtime.set |= MM_RUNTIME_SPEED_ENVELOPE;
    t.cfg.runtime.speed_envelope = false;
    build(&t, &db);
    assert_int_equal(mm_character_desc_from_database(&d, &db, &err), MM_OK);
    assert_false(d.trajectory.bounded);
    assert_envelope(db.settings->envelope[MM_GAIT_WALK], expected);
    mm_database_free(&db);
    test_takes_free(&t);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_measured),
        cmocka_unit_test(test_bounded),
        cmocka_unit_test(test_file_and_desc),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
