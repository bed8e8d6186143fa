/* Idle that loops (idle_loop.make; docs/database.md, "Idle that loops"): the built-in set with its
 * idle clip replaced by a hand-made one that stands still, swaying with a known period while the
 * left arm rises slowly, gets a loop clip one period long, from the end of the still stretch, whose
 * seam is continuous (the cut alone would jump); a character standing on it for 10 s makes no
 * transition and no pop above the database's own, where without the loop it jumps back from the
 * clip's end again and again. A clip that never stands still gets no loop; idle_loop.make false
 * makes none. */
#include <math.h>

#include <mm/character.h>
#include <mm/config_json.h>
#include <mm/database_build.h>
#include <mm/synth.h>

#include "test_databases.h"
#include "test_util.h"

#define TICK           (1.0f / 60.0f)
#define CLIP_SECONDS   4.0f
#define SWAY_PERIOD    1.25f  /* s: the hand-made idle repeats its sway in this time (75 frames) */
#define SWAY_ANGLE     0.05f  /* rad: the chest's pitch sways by this either way */
#define SWAY_SHIFT     0.01f  /* m: and the hips sway sideways by this either way (the feet stay) */
#define LEAN_RATE      0.02f  /* rad/s: and the left arm rises at this rate: no two periods the same */
#define RESTLESS_ANGLE 0.6f   /* rad: the restless clip swings its chest this far, once a second */
#define END_WINDOW     30     /* frames: the loop ends within this of the still stretch's end */
#define SEAM_JUMP      0.001f /* m per frame^2: the largest change of velocity across the seam */
#define CUT_JUMP       0.003f /* m: the cut alone, uncorrected, moves a joint more than this */
#define STAND_SECONDS  15.0f
#define HANDOVER       5.0f  /* s: the clip's end (4 s) is past: the character stands on the loop */
#define JUMPING_BACK   3     /* transitions over 10 s without the loop, at least */
#define POP_SLACK      1.05f /* the character's largest pop over the database's own */
#define JOINTS         64    /* room for the built-in skeleton's joints */

typedef enum idle_kind { IDLE_SWAYING, IDLE_RESTLESS } idle_kind;

/* The synth idle's first pose, held for CLIP_SECONDS, the chest swaying with SWAY_PERIOD and the left
 * arm rising (IDLE_SWAYING), or swinging far and fast (IDLE_RESTLESS). */
static void hand_made_idle(const mm_clip *synth_idle, idle_kind kind, mm_clip *out)
{
    int n = (int)lroundf(CLIP_SECONDS * synth_idle->fps);
    assert_int_equal(mm_clip_init(out, &synth_idle->skeleton, n, synth_idle->fps, NULL), MM_OK);
    int spine = mm_skeleton_find(&synth_idle->skeleton, "Spine");
    int left_arm = mm_skeleton_find(&synth_idle->skeleton, "LeftArm");
    assert_true(spine > 0 && left_arm > 0);
    size_t nj = (size_t)synth_idle->skeleton.joint_count;
    for (int f = 0; f < n; ++f) {
        float t = (float)f / synth_idle->fps;
        memcpy(mm_clip_rotations(out, f), mm_clip_rotations(synth_idle, 0), nj * sizeof(mm_quat));
        memcpy(mm_clip_positions(out, f), mm_clip_positions(synth_idle, 0), nj * sizeof(mm_vec3));
        mm_quat *chest = &mm_clip_rotations(out, f)[spine], *arm = &mm_clip_rotations(out, f)[left_arm];
        if (kind == IDLE_SWAYING) {
            float sway = SWAY_ANGLE * sinf(6.2831853f * t / SWAY_PERIOD);
            *chest = mm_quat_mul(*chest, mm_quat_from_axis_angle(mm_vec3_make(1, 0, 0), sway));
            mm_clip_positions(out, f)[0].x += SWAY_SHIFT * sinf(6.2831853f * t / SWAY_PERIOD);
            *arm = mm_quat_mul(*arm, mm_quat_from_axis_angle(mm_vec3_make(0, 0, 1), LEAN_RATE * t));
        } else {
            float swing = RESTLESS_ANGLE * sinf(6.2831853f * t);
            *chest = mm_quat_mul(*chest, mm_quat_from_axis_angle(mm_vec3_make(1, 0, 0), swing));
        }
    }
}

/* The built-in set with its idle clip (not a loop) made of kind. */
static void build(idle_kind kind, bool make, mm_database *db, mm_db_build_report *report)
{
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    char *text = NULL;
    assert_int_equal(mm_config_load_json(MM_SOURCE_DIR "/configs/synth.json", &cfg, &text, &err), MM_OK);
    cfg.idle_loop_make = make;
    mm_clip *sources = test_synth_sources(&cfg);
    assert_non_null(sources);
    int idle = -1;
    for (int i = 0; i < cfg.clip_count; ++i)
        if (cfg.clips[i].type == MM_CLIP_IDLE) idle = i;
    assert_true(idle >= 0);
    mm_clip synth_idle = sources[idle];
    hand_made_idle(&synth_idle, kind, &sources[idle]);
    mm_clip_free(&synth_idle);
    cfg.clips[idle].loop = false;
    mm_db_build_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.report = report;
    mm_result r = mm_database_build(&cfg, sources, &desc, db, &err);
    if (r != MM_OK) print_message("build: %s\n", err.message);
    assert_int_equal(r, MM_OK);
    mm_config_free_sources(&cfg, sources);
    mm_config_free(&cfg);
    free(text);
}

static int find_clip(const mm_database *db, const char *name)
{
    for (int c = 0; c < db->clip_count; ++c)
        if (strcmp(db->clips[c].name, name) == 0) return c;
    return -1;
}

/* The joints of database frame f relative to the simulation bone (joint 0). */
static void character_frame(const mm_database *db, int f, mm_vec3 *out)
{
    mm_quat rot[JOINTS];
    mm_vec3 pos[JOINTS];
    mm_xform g[JOINTS];
    mm_database_local_pose(db, f, rot, pos);
    g[0] = mm_xform_make(mm_quat_identity(), mm_vec3_make(0, 0, 0));
    mm_skeleton_global_from(db->joints, db->joint_count, 1, rot, pos, g);
    for (int j = 0; j < db->joint_count; ++j) out[j] = g[j].translation;
}

/* The largest over joints of |a - 2b + c| (a second difference) or, c NULL, of |a - b|. */
static float largest(const mm_vec3 *a, const mm_vec3 *b, const mm_vec3 *c, int joints)
{
    float most = 0.0f;
    for (int j = 0; j < joints; ++j) {
        mm_vec3 d = mm_vec3_sub(a[j], b[j]);
        if (c) d = mm_vec3_add(mm_vec3_sub(d, b[j]), c[j]);
        most = fmaxf(most, mm_vec3_length(d));
    }
    return most;
}

static void test_loop_at_the_period(void **state)
{
    (void)state;
    mm_database db;
    mm_db_build_report report;
    build(IDLE_SWAYING, true, &db, &report);
    assert_true(db.joint_count <= JOINTS);
    const mm_db_idle_loop_report *said = &report.idle_loops;
    print_message("idle loops: %d made of %d (%d not still, %d no seam)\n", said->made, said->idle_clips,
                  said->no_still, said->no_match);
    assert_true(said->make);
    assert_int_equal(said->idle_clips, 1);
    assert_int_equal(said->made, 1);
    int idle = find_clip(&db, "idle"), loop = find_clip(&db, "idle_loop");
    assert_true(idle >= 0 && loop >= 0);
    const mm_db_clip *x = &db.clips[idle], *l = &db.clips[loop];
    assert_int_equal(l->type, MM_CLIP_IDLE);
    assert_int_equal(l->loop, 1);
    assert_int_equal(x->loop, 0);
    /* one period long, ending in the still stretch's last END_WINDOW frames (the whole clip stands) */
    int period = (int)lroundf(SWAY_PERIOD / db.interval);
    int begin = (int)lroundf((l->source_start - x->source_start) / db.interval);
    int end = begin + period;
    print_message("loop: frames [%d, %d) of %d, seam %.2f cm before its blend\n", begin, end, x->frame_count,
                  100.0 * said->worst_error);
    assert_int_equal(l->frame_count, period);
    assert_true(end >= x->frame_count - 1 - END_WINDOW && end <= x->frame_count - 1);
    assert_true(said->worst_error < 0.05f);
    /* the wrap: last frame -> first continues as the frames inside do */
    int jc = db.joint_count, n = l->frame_count, f0 = l->first_frame;
    mm_vec3 p[4][JOINTS]; /* frames n-2, n-1, 0, 1 */
    character_frame(&db, f0 + n - 2, p[0]);
    character_frame(&db, f0 + n - 1, p[1]);
    character_frame(&db, f0, p[2]);
    character_frame(&db, f0 + 1, p[3]);
    float step_inside = 0.0f;
    mm_vec3 a[JOINTS], b[JOINTS];
    character_frame(&db, f0, a);
    for (int f = 1; f < n; ++f) {
        character_frame(&db, f0 + f, b);
        step_inside = fmaxf(step_inside, largest(b, a, NULL, jc));
        memcpy(a, b, sizeof a);
    }
    float seam_step = largest(p[2], p[1], NULL, jc);
    float seam_bend = fmaxf(largest(p[2], p[1], p[0], jc), largest(p[3], p[2], p[1], jc));
    /* the cut alone: the source's frame end-1 followed by frame begin */
    mm_vec3 cut_last[JOINTS], cut_first[JOINTS];
    character_frame(&db, x->first_frame + end - 1, cut_last);
    character_frame(&db, x->first_frame + begin, cut_first);
    float cut_step = largest(cut_first, cut_last, NULL, jc);
    print_message(
        "seam: step %.3f cm (inside up to %.3f), change of velocity %.4f cm; the cut alone %.3f cm\n",
        100.0 * seam_step, 100.0 * step_inside, 100.0 * seam_bend, 100.0 * cut_step);
    assert_true(cut_step > CUT_JUMP);
    assert_true(seam_step <= step_inside * 1.5f + 1e-5f);
    assert_true(seam_bend < SEAM_JUMP);
    mm_database_free(&db);
}

typedef struct stand_run {
    int transitions; /* over the last 10 s */
    float pop;       /* m: the largest second difference of a joint's world position, same window */
} stand_run;

static stand_run stand(const mm_database *db)
{
    stand_run out = {0, 0.0f};
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_character_desc desc;
    assert_int_equal(mm_character_desc_from_database(&desc, db, &err), MM_OK);
    mm_searcher searcher;
    mm_character c;
    assert_int_equal(mm_searcher_init(&searcher, db, NULL, &err), MM_OK);
    assert_int_equal(mm_character_init(&c, db, &searcher, &desc, &err), MM_OK);
    int ticks = (int)lroundf(STAND_SECONDS / TICK), from = (int)lroundf(HANDOVER / TICK), before = 0;
    mm_vec3 last[2][JOINTS];
    mm_input in;
    memset(&in, 0, sizeof in);
    for (int i = 0; i < ticks; ++i) {
        mm_character_update(&c, &in, TICK);
        if (i == from) before = c.transitions;
        if (i >= from + 2) {
            mm_vec3 now[JOINTS];
            for (int j = 0; j < db->joint_count; ++j) now[j] = c.global[j].translation;
            out.pop = fmaxf(out.pop, largest(now, last[1], last[0], db->joint_count));
        }
        memcpy(last[0], last[1], sizeof last[0]);
        for (int j = 0; j < db->joint_count; ++j) last[1][j] = c.global[j].translation;
    }
    out.transitions = c.transitions - before;
    mm_character_free(&c);
    mm_searcher_free(&searcher);
    return out;
}

/* The database's own largest pop over its idle clips played in order (world positions, joint 0 as
 * played). */
static float idle_pop(const mm_database *db)
{
    float most = 0.0f;
    for (int c = 0; c < db->clip_count; ++c) {
        const mm_db_clip *k = &db->clips[c];
        if (k->type != MM_CLIP_IDLE) continue;
        mm_vec3 p[3][JOINTS];
        for (int f = 0; f < k->frame_count + (k->loop ? 2 : 0); ++f) {
            mm_quat rot[JOINTS];
            mm_vec3 pos[JOINTS];
            mm_xform g[JOINTS];
            mm_database_local_pose(db, k->first_frame + f % k->frame_count, rot, pos);
            g[0] = mm_xform_make(rot[0], pos[0]);
            mm_skeleton_global_from(db->joints, db->joint_count, 1, rot, pos, g);
            memcpy(p[0], p[1], sizeof p[0]);
            memcpy(p[1], p[2], sizeof p[0]);
            for (int j = 0; j < db->joint_count; ++j) p[2][j] = g[j].translation;
            if (f >= 2 && f < k->frame_count) most = fmaxf(most, largest(p[2], p[1], p[0], db->joint_count));
        }
    }
    return most;
}

static void test_standing_plays_on(void **state)
{
    (void)state;
    mm_database with, without;
    mm_db_build_report report;
    build(IDLE_SWAYING, true, &with, &report);
    build(IDLE_SWAYING, false, &without, &report);
    assert_false(report.idle_loops.make);
    assert_int_equal(report.idle_loops.made, 0);
    assert_int_equal(find_clip(&without, "idle_loop"), -1);
    stand_run looped = stand(&with), cut = stand(&without);
    float own = idle_pop(&without);
    print_message("standing 10 s: %d transitions, pop %.4f cm with the loop; %d, %.4f cm without; the data's "
                  "own pop %.4f cm\n",
                  looped.transitions, 100.0 * looped.pop, cut.transitions, 100.0 * cut.pop, 100.0 * own);
    assert_true(cut.transitions >= JUMPING_BACK);
    assert_int_equal(looped.transitions, 0);
    assert_true(looped.pop <= own * POP_SLACK);
    mm_database_free(&with);
    mm_database_free(&without);
}

static void test_restless_gets_none(void **state)
{
    (void)state;
    mm_database db;
    mm_db_build_report report;
    build(IDLE_RESTLESS, true, &db, &report);
    assert_int_equal(report.idle_loops.idle_clips, 1);
    assert_int_equal(report.idle_loops.made, 0);
    assert_int_equal(report.idle_loops.no_still, 1);
    for (int c = 0; c < db.clip_count; ++c) assert_null(strstr(db.clips[c].name, "_loop"));
    mm_database_free(&db);
}

static mm_result parse(const char *text, mm_config *cfg, mm_error *err)
{
    return mm_config_parse_json(text, strlen(text), "config", NULL, cfg, err);
}

static void test_config_key(void **state)
{
    (void)state;
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_config cfg;
    const char *text = "{\"idle_loop\": {\"make\": false}, \"clips\": []}";
    assert_int_equal(parse(text, &cfg, &err), MM_OK);
    assert_false(cfg.idle_loop_make);
    mm_config_free(&cfg);
    assert_int_equal(parse("{\"clips\": []}", &cfg, &err), MM_OK);
    assert_true(cfg.idle_loop_make);
    mm_config_free(&cfg);
    assert_int_not_equal(parse("{\"idle_loop\": {\"make\": 1}, \"clips\": []}", &cfg, &err), MM_OK);
    assert_non_null(strstr(err.message, "idle_loop"));
    assert_int_not_equal(parse("{\"idle_loop\": {\"length\": 1}, \"clips\": []}", &cfg, &err), MM_OK);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_loop_at_the_period),
        cmocka_unit_test(test_standing_plays_on),
        cmocka_unit_test(test_restless_gets_none),
        cmocka_unit_test(test_config_key),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
