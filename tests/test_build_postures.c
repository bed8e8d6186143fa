/* The database build's postures (docs/database.md, "Postures"): calibration poses cut out of
 * locomotion clips with their margin, crouched frames tagged Crouch, a knee raised and the hands
 * spread briefly cut out, on hand-made takes whose postures are known frame by frame. */
#include <math.h>
#include <mm/database_build.h>

#include "test_takes.h"
#include "test_util.h"

#define FPS    30.0f
#define FRAMES 300 /* 10 s */
/* the hand-made take: a T pose over source frames [60, 120), a crouch over [180, 240) */
#define T_BEGIN      60
#define T_END        120
#define CROUCH_BEGIN 180
#define CROUCH_END   240

/* Walks straight along +Z at 1 m/s; arms straight out in the T pose, the hips 0.3 m lower in the
 * crouch (the head at 0.8 of its upright height above the ground). */
static void make_take(mm_clip *clip)
{
    mm_skeleton s;
    test_take_skeleton(&s);
    assert_int_equal(mm_clip_init(clip, &s, FRAMES, FPS, NULL), MM_OK);
    mm_skeleton_free(&s);
    for (int f = 0; f < FRAMES; ++f) {
        int t_pose = f >= T_BEGIN && f < T_END, crouch = f >= CROUCH_BEGIN && f < CROUCH_END;
        mm_clip_positions(clip, f)[0] = mm_vec3_make(0.0f, crouch ? 0.7f : 1.0f, (float)f / FPS);
        if (t_pose) {
            mm_clip_positions(clip, f)[3] = mm_vec3_make(0.8f, 0.15f, 0.0f);
            mm_clip_positions(clip, f)[4] = mm_vec3_make(-0.8f, 0.15f, 0.0f);
        }
    }
}

static void make_config(mm_config *cfg)
{
    mm_config_defaults(cfg);
    cfg->scale = 1.0f;
    cfg->root_smoothing = 0.0f;
    cfg->clip_count = 1;
    cfg->clips = calloc(1, sizeof(mm_config_clip));
    snprintf(cfg->clips[0].name, MM_NAME_MAX, "take");
    snprintf(cfg->clips[0].file, MM_PATH_MAX, "take.bvh");
}

static void test_calibration_cut_and_crouch_tagged(void **state)
{
    (void)state;
    mm_clip take;
    make_take(&take);
    mm_config cfg;
    make_config(&cfg);
    mm_db_build_report report;
    mm_db_build_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.report = &report;
    mm_database db;
    assert_int_equal(mm_database_build(&cfg, &take, &desc, &db, NULL), MM_OK);
    /* the reference: the head 1.55 m up, the ground 0.05 m up (the feet's toes) */
    assert_near(report.reference_head_height, 1.5, 1e-4);
    assert_int_equal(report.source_frames[MM_POSTURE_CALIBRATION], T_END - T_BEGIN);
    assert_int_equal(report.source_frames[MM_POSTURE_CROUCHED], CROUCH_END - CROUCH_BEGIN);
    assert_int_equal(report.source_frames[MM_POSTURE_UPRIGHT], FRAMES - 120);
    /* the T pose and 0.25 s (8 frames) on each side left out, the crouch a clip of its own less
     * 8 frames at each end: [0, 52), [128, 172), [188, 232), [248, 300) */
    int pad = (int)lroundf(cfg.postures_pad * FPS);
    const int pieces[4][2] = {{0, T_BEGIN - pad},
                              {T_END + pad, CROUCH_BEGIN - pad},
                              {CROUCH_BEGIN + pad, CROUCH_END - pad},
                              {CROUCH_END + pad, FRAMES}};
    assert_int_equal(db.clip_count, 4);
    for (int c = 0; c < 4; ++c) {
        char name[32];
        snprintf(name, sizeof name, "take#%d", c);
        assert_string_equal(db.clips[c].name, name);
        assert_near(db.clips[c].source_start, pieces[c][0] / FPS, 1e-5);
        assert_near((db.clips[c].frame_count - 1) * db.interval, (pieces[c][1] - 1 - pieces[c][0]) / FPS,
                    1e-4);
    }
    /* the crouch's clip, and nothing else, carries the new tag Crouch */
    assert_int_equal(db.tag_count, 1);
    assert_string_equal(db.tag_names[0], "Crouch");
    for (int f = 0; f < db.frame_count; ++f)
        assert_int_equal(db.frame_tags[f] & 1u, (uint64_t)(db.frame_clip[f] == 2));
    mm_database_free(&db);

    /* a tag of the config named crouch in any case is the one used */
    cfg.tag_count = 2;
    snprintf(cfg.tag_names[0], MM_TAG_NAME_MAX, "DoNotUse");
    snprintf(cfg.tag_names[1], MM_TAG_NAME_MAX, "crouch");
    assert_int_equal(mm_database_build(&cfg, &take, NULL, &db, NULL), MM_OK);
    assert_int_equal(db.tag_count, 2);
    uint64_t any = 0;
    for (int f = 0; f < db.frame_count; ++f) any |= db.frame_tags[f];
    assert_int_equal(any, 2u);
    mm_database_free(&db);

    /* off: the take as given */
    cfg.postures_detect = false;
    assert_int_equal(mm_database_build(&cfg, &take, &desc, &db, NULL), MM_OK);
    assert_int_equal(db.clip_count, 1);
    assert_int_equal(db.frame_count, (FRAMES - 1) * 2 + 1);
    for (int f = 0; f < db.frame_count; ++f) assert_int_equal(db.frame_tags[f], 0);
    assert_true(report.reference_head_height == 0.0f);
    mm_database_free(&db);

    /* idle clips are judged too; other kinds (and loop clips' cuts) are not */
    cfg.postures_detect = true;
    cfg.clips[0].loop = true;
    assert_int_equal(mm_database_build(&cfg, &take, NULL, &db, NULL), MM_OK);
    assert_int_equal(db.clip_count, 1);
    mm_database_free(&db);
    mm_config_free(&cfg);
    mm_clip_free(&take);
}

/* Legs with knees: hips 1 m up, the head 0.55 m above them, each leg a thigh from 5 cm under the
 * hips (0.45 m), a shin (0.42 m), a foot and a toe; hands hanging beside the spine. */
static void make_legged_skeleton(mm_skeleton *s)
{
    enum { COUNT = 13 };
    assert_int_equal(mm_skeleton_init(s, COUNT, NULL), MM_OK);
    const char *names[COUNT] = {"Hips",      "Spine2",    "Head",     "LeftHand", "RightHand",
                                "LeftUpLeg", "LeftLeg",   "LeftFoot", "LeftToe",  "RightUpLeg",
                                "RightLeg",  "RightFoot", "RightToe"};
    const int parents[COUNT] = {-1, 0, 1, 1, 1, 0, 5, 6, 7, 0, 9, 10, 11};
    const float off[COUNT][3] = {{0, 1, 0},          {0, 0.3f, 0},       {0, 0.25f, 0},  {0.2f, -0.45f, 0},
                                 {-0.2f, -0.45f, 0}, {0.1f, -0.05f, 0},  {0, -0.45f, 0}, {0, -0.42f, 0},
                                 {0, -0.05f, 0.15f}, {-0.1f, -0.05f, 0}, {0, -0.45f, 0}, {0, -0.42f, 0},
                                 {0, -0.05f, 0.15f}};
    for (int j = 0; j < COUNT; ++j) {
        snprintf(s->joints[j].name, MM_NAME_MAX, "%s", names[j]);
        s->joints[j].parent = parents[j];
        s->joints[j].offset = mm_vec3_make(off[j][0], off[j][1], off[j][2]);
        s->joints[j].order = MM_EULER_ZYX;
    }
    s->joints[0].flags = MM_JOINT_TRANSLATES;
}

/* A knee raised is left out like a calibration pose; the hands spread wide are left out however
 * briefly, a run shorter than a posture's (MM_POSTURE_MIN_SECONDS) too. */
static void test_knee_raised_and_brief_spread(void **state)
{
    (void)state;
    enum { KNEE_BEGIN = 60, KNEE_END = 120, SPREAD_BEGIN = 180, SPREAD_END = 185 };
    mm_skeleton s;
    make_legged_skeleton(&s);
    mm_clip take;
    assert_int_equal(mm_clip_init(&take, &s, FRAMES, FPS, NULL), MM_OK);
    mm_skeleton_free(&s);
    const float quarter = 0.5f * (float)MM_PI;
    for (int f = 0; f < FRAMES; ++f) {
        mm_clip_positions(&take, f)[0] = mm_vec3_make(0.0f, 1.0f, (float)f / FPS);
        if (f >= KNEE_BEGIN && f < KNEE_END) { /* the left thigh level, forward; the shin hanging */
            mm_clip_rotations(&take, f)[5] = mm_quat_from_axis_angle(mm_vec3_make(1, 0, 0), -quarter);
            mm_clip_rotations(&take, f)[6] = mm_quat_from_axis_angle(mm_vec3_make(1, 0, 0), quarter);
        }
        if (f >= SPREAD_BEGIN && f < SPREAD_END) { /* the hands 1.4 m apart: 0.86 of the stature */
            mm_clip_positions(&take, f)[3] = mm_vec3_make(0.7f, -0.35f, 0.0f);
            mm_clip_positions(&take, f)[4] = mm_vec3_make(-0.7f, -0.35f, 0.0f);
        }
    }
    mm_config cfg;
    make_config(&cfg);
    mm_db_build_report report;
    mm_db_build_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.report = &report;
    mm_database db;
    assert_int_equal(mm_database_build(&cfg, &take, &desc, &db, NULL), MM_OK);
    /* the head 1.55 m up, the ground the toes' 0.03 */
    assert_near(report.reference_head_height, 1.52, 1e-4);
    assert_int_equal(report.source_frames[MM_POSTURE_KNEE_RAISED], KNEE_END - KNEE_BEGIN);
    assert_int_equal(report.source_frames[MM_POSTURE_ARMS_SPREAD], SPREAD_END - SPREAD_BEGIN);
    assert_int_equal(report.source_frames[MM_POSTURE_UPRIGHT], FRAMES - 65);
    /* each left out with 0.25 s (8 frames) on each side: [0, 52), [128, 172), [193, 300) */
    int pad = (int)lroundf(cfg.postures_pad * FPS);
    const int pieces[3][2] = {
        {0, KNEE_BEGIN - pad}, {KNEE_END + pad, SPREAD_BEGIN - pad}, {SPREAD_END + pad, FRAMES}};
    assert_int_equal(db.clip_count, 3);
    for (int c = 0; c < 3; ++c) {
        assert_near(db.clips[c].source_start, pieces[c][0] / FPS, 1e-5);
        assert_near((db.clips[c].frame_count - 1) * db.interval, (pieces[c][1] - 1 - pieces[c][0]) / FPS,
                    1e-4);
    }
    mm_database_free(&db);
    mm_config_free(&cfg);
    mm_clip_free(&take);
}

/* No tag left for Crouch: a clear error that says how out. */
static void test_no_room_for_the_tag(void **state)
{
    (void)state;
    mm_clip take;
    make_take(&take);
    mm_config cfg;
    make_config(&cfg);
    cfg.tag_count = MM_MAX_TAGS;
    for (int t = 0; t < MM_MAX_TAGS; ++t) snprintf(cfg.tag_names[t], MM_TAG_NAME_MAX, "tag%d", t);
    mm_database db;
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_database_build(&cfg, &take, NULL, &db, &err), MM_ERR_LIMIT);
    assert_non_null(strstr(err.message, "postures.detect"));
    mm_config_free(&cfg);
    mm_clip_free(&take);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_calibration_cut_and_crouch_tagged),
        cmocka_unit_test(test_knee_raised_and_brief_spread),
        cmocka_unit_test(test_no_room_for_the_tag),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
