/* A standing pose when the takes have no idle clip (standing.make; docs/database.md, "A standing
 * pose when the takes have no idle"): the built-in set with its idle clip removed gets a clip that
 * holds the stillest standing frame of its takes, upright with both feet planted, named after the
 * frame, mirrored, reported by the build and by the diagnosis; a character told to walk and then
 * stop stands on it without moving its root or its feet. The same takes without the pose (and
 * without the stops that end standing) keep stepping in place. On LAFAN1 too when MM_DATA_DIR is
 * set. */
#include <math.h>

#include <mm/character.h>
#include <mm/config_json.h>
#include <mm/database_build.h>
#include <mm/diagnose.h>
#include <mm/input_json.h>
#include <mm/posture.h>
#include <mm/synth.h>

#include "test_util.h"

#define STANDING_PREFIX "standing_from_"
#define TICK            (1.0f / 60.0f)
#define STILL_ROOT      0.02f /* m: the root moves less over a 2 s window after the stop settles */
#define STILL_FEET      0.01f /* m: and every planted ankle and toe less */
#define STEPPING        0.10f /* m: without the pose, an ankle travels more than this in 2 s */

/* Keeps the clips of cfg that keep(clip) accepts (freeing the others' arrays). */
static void keep_clips(mm_config *cfg, int (*keep)(const mm_config_clip *))
{
    int n = 0;
    for (int i = 0; i < cfg->clip_count; ++i) {
        if (keep(&cfg->clips[i]))
            cfg->clips[n++] = cfg->clips[i];
        else {
            mm_free(&cfg->allocator, cfg->clips[i].ranges);
            mm_free(&cfg->allocator, cfg->clips[i].tag_ranges);
        }
    }
    cfg->clip_count = n;
}

static int not_idle(const mm_config_clip *c) { return c->type != MM_CLIP_IDLE; }
/* neither idle nor a stop (the stops end standing still) */
static int not_idle_nor_stop(const mm_config_clip *c) { return not_idle(c) && !strstr(c->name, "_stop"); }
static int keep_all(const mm_config_clip *c) { return c != NULL; }
/* the run loops alone: a run has no moment with both feet down */
static int run_loops(const mm_config_clip *c) { return strncmp(c->name, "run_", 4) == 0 && c->loop; }
static int lafan_walk(const mm_config_clip *c) { return strcmp(c->name, "walk4_subject1") == 0; }

/* Builds config path with its clips filtered by keep and standing.make = make; with synth, the
 * clips come from mm_synth_generate. Returns 0, or -1 (printing why). */
static int build_threads(const char *path, int synth, int (*keep)(const mm_config_clip *), bool make,
                         int threads, mm_database *db, mm_db_build_report *report)
{
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    char *text = NULL;
    if (mm_config_load_json(path, &cfg, &text, &err) != MM_OK) {
        fprintf(stderr, "%s: %s\n", path, err.message);
        return -1;
    }
    keep_clips(&cfg, keep);
    cfg.standing_make = make;
    mm_clip *sources = NULL;
    if (synth) {
        mm_synth_desc sd;
        memset(&sd, 0, sizeof sd);
        mm_synth_set set;
        if (mm_synth_generate(&sd, &set, &err) != MM_OK) return -1;
        sources = (mm_clip *)calloc((size_t)cfg.clip_count, sizeof(mm_clip));
        for (int i = 0; i < cfg.clip_count; ++i)
            for (int k = 0; k < set.clip_count; ++k)
                if (strcmp(set.clips[k].name, cfg.clips[i].name) == 0)
                    mm_clip_copy(&sources[i], &set.clips[k].clip, NULL);
        mm_synth_set_free(&set);
    } else if (mm_config_load_sources(&cfg, &sources, &err) != MM_OK) {
        fprintf(stderr, "%s: %s\n", path, err.message);
        mm_config_free(&cfg);
        free(text);
        return -1;
    }
    mm_db_build_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.report = report;
    desc.threads = threads;
    mm_result r = mm_database_build(&cfg, sources, &desc, db, &err);
    if (r != MM_OK) fprintf(stderr, "%s: %s\n", path, err.message);
    mm_config_free_sources(&cfg, sources);
    mm_config_free(&cfg);
    free(text);
    return r == MM_OK ? 0 : -1;
}

static int build(const char *path, int synth, int (*keep)(const mm_config_clip *), bool make, mm_database *db,
                 mm_db_build_report *report)
{
    return build_threads(path, synth, keep, make, 1, db, report);
}

static int find_clip(const mm_database *db, const char *name)
{
    for (int c = 0; c < db->clip_count; ++c)
        if (strcmp(db->clips[c].name, name) == 0) return c;
    return -1;
}

static int starts_with(const char *s, const char *prefix) { return strncmp(s, prefix, strlen(prefix)) == 0; }

/* World joint positions of database frame f. */
static void world_of(const mm_database *db, int f, mm_vec3 *out)
{
    mm_xform g[MM_MAX_JOINTS];
    const mm_quat *rot = mm_database_rotations(db, f);
    const mm_vec3 *pos = mm_database_positions(db, f);
    g[0].rotation = rot[0];
    g[0].translation = pos[0];
    mm_skeleton_global_from(db->joints, db->joint_count, 1, rot, pos, g);
    for (int j = 0; j < db->joint_count; ++j) out[j] = g[j].translation;
}

static int joint(const mm_database *db, const char *name)
{
    for (int j = 0; j < db->joint_count; ++j)
        if (strcmp(db->joints[j].name, name) == 0) return j;
    return -1;
}

/* The joints the posture judgement reads, found as the build finds them: the hips, the head and
 * the hands by name, each leg's knee and thigh up from its foot (mm_posture_find_legs). */
static mm_posture_joints posture_joints_of(const mm_database *db)
{
    mm_posture_joints pj = {joint(db, "Hips"),      joint(db, "Head"), joint(db, "LeftHand"),
                            joint(db, "RightHand"), {-1, -1},          {-1, -1}};
    const mm_skeleton rest = {.joint_count = db->joint_count,
                              .joints = (mm_joint *)(uintptr_t)db->joints}; /* only read */
    assert_int_equal(mm_posture_find_legs(&rest, joint(db, "LeftFoot"), joint(db, "RightFoot"), &pj), 2);
    return pj;
}

/* The made clip: an idle loop named after the frame it holds, every frame that frame's pose
 * (the source clip's frame, found again by its time), upright, all four heel and toe contacts
 * planted; its mirror; the report and the diagnosis name it. */
static void check_made_clip(const mm_database *db, const mm_db_build_report *report)
{
    const mm_db_standing_report *s = &report->standing;
    assert_int_equal(s->status, MM_STANDING_MADE);
    assert_true(starts_with(s->clip, STANDING_PREFIX));
    char expect[2 * MM_NAME_MAX];
    snprintf(expect, sizeof expect, STANDING_PREFIX "%.32s_%d", s->from_clip,
             s->from_frame); /* names are cut */
    assert_string_equal(s->clip, expect);
    int c = find_clip(db, s->clip), from = find_clip(db, s->from_clip);
    assert_true(c >= 0 && from >= 0);
    const mm_db_clip *k = &db->clips[c];
    assert_int_equal(k->type, MM_CLIP_IDLE);
    assert_int_equal(k->loop, 1);
    assert_true(k->frame_count * db->interval >= 1.9f);
    /* the pose is the source clip's frame at the reported time, held */
    int f = (int)lroundf((s->from_time - db->clips[from].source_start) / db->interval);
    assert_true(f >= 0 && f < db->clips[from].frame_count);
    int src = db->clips[from].first_frame + f, jc = db->joint_count;
    for (int i = 0; i < k->frame_count; ++i) {
        const mm_quat *a = mm_database_rotations(db, k->first_frame + i), *b = mm_database_rotations(db, src);
        for (int j = 0; j < jc; ++j) assert_true(fabsf(mm_quat_dot(a[j], b[j])) > 1.0f - 1e-6f);
        assert_int_equal(db->contacts[k->first_frame + i], 15); /* both heels and toes planted */
    }
    /* upright by the build's reference, both feet at the ground, side by side */
    mm_vec3 w[MM_MAX_JOINTS];
    world_of(db, k->first_frame, w);
    mm_posture_joints pj = posture_joints_of(db);
    mm_posture_reference ref = {report->reference_head_height};
    assert_int_equal(mm_posture_classify(w, &pj, w[0].y, &ref), MM_POSTURE_UPRIGHT);
    int lf = joint(db, "LeftFoot"), rf = joint(db, "RightFoot");
    mm_vec3 forward = mm_quat_rotate(mm_database_rotations(db, k->first_frame)[0], mm_vec3_make(0, 0, 1));
    mm_vec3 apart = mm_vec3_sub(w[lf], w[rf]);
    float stride = fabsf(apart.x * forward.x + apart.z * forward.z);
    print_message("made %s: clip %s frame %d (%.2f s), root %.3f m/s, joints %.3f m/s, stride %.3f m\n",
                  s->clip, s->from_clip, s->from_frame, s->from_time, s->root_speed, s->joint_speed, stride);
    assert_true(fabsf(stride - s->stride) < 1e-3f);
    assert_true(stride < 0.15f); /* not mid-stride */
    /* its mirror */
    char mirror[2 * MM_NAME_MAX];
    snprintf(mirror, sizeof mirror, "%s_mirror", s->clip);
    assert_true(s->mirrored);
    int m = find_clip(db, mirror);
    assert_true(m >= 0);
    assert_int_equal(db->clips[m].type, MM_CLIP_IDLE);
    assert_int_equal(db->clips[m].mirrored, 1);
    /* the diagnosis still warns, naming the clip and the frame */
    mm_diagnosis d;
    assert_int_equal(mm_database_diagnose(db, report, NULL, &d), MM_OK);
    assert_int_equal(d.standing_clips, 2 * s->poses); /* each mirrored */
    int warned = 0;
    char frame[64];
    snprintf(frame, sizeof frame, "frame %d", s->from_frame);
    for (int i = 0; i < d.count; ++i)
        if (d.items[i].code == MM_DIAG_NO_IDLE)
            warned = strstr(d.items[i].message, s->clip) && strstr(d.items[i].message, frame);
    assert_true(warned);
    /* without the report (a loaded database) it still names the clip */
    assert_int_equal(mm_database_diagnose(db, NULL, NULL, &d), MM_OK);
    assert_int_equal(d.items[0].code, MM_DIAG_NO_IDLE);
    assert_non_null(strstr(d.items[0].message, s->clip));
}

/* Every clip the build made: an idle loop holding one pose, upright, all four contacts planted,
 * named after the frame; the stillest first; mirrors after their poses. Returns how many. */
static int check_every_made_clip(const mm_database *db, const mm_db_build_report *report)
{
    int made = 0, first = -1, jc = db->joint_count;
    mm_posture_joints pj = posture_joints_of(db);
    mm_posture_reference ref = {report->reference_head_height};
    mm_vec3 w[MM_MAX_JOINTS];
    for (int c = 0; c < db->clip_count; ++c) {
        const mm_db_clip *k = &db->clips[c];
        if (!starts_with(k->name, STANDING_PREFIX)) continue;
        if (first < 0) first = c;
        ++made;
        assert_int_equal(k->type, MM_CLIP_IDLE);
        assert_int_equal(k->loop, 1);
        const mm_quat *a = mm_database_rotations(db, k->first_frame);
        for (int i = 0; i < k->frame_count; ++i) {
            const mm_quat *b = mm_database_rotations(db, k->first_frame + i);
            for (int j = 0; j < jc; ++j) assert_true(fabsf(mm_quat_dot(a[j], b[j])) > 1.0f - 1e-6f);
            assert_int_equal(db->contacts[k->first_frame + i], 15);
        }
        world_of(db, k->first_frame, w);
        assert_int_equal(mm_posture_classify(w, &pj, w[0].y, &ref), MM_POSTURE_UPRIGHT);
        print_message("  %s\n", k->name);
    }
    assert_true(first >= 0);
    assert_string_equal(db->clips[first].name, report->standing.clip);
    assert_int_equal(made, 2 * report->standing.poses);
    return made;
}

/* What a run of the stop-and-go script did after its last stop settled: over 2 s windows, the
 * most the root moved, the most a planted ankle or toe moved (labelled planted and locked all
 * the window), the most an animated ankle travelled (before foot IK), and the share of ticks
 * asking for idle. */
typedef struct standing_run {
    float root, planted, ankle_path, idle_share;
    int windows;
} standing_run;

#define SCRIPT_SECONDS 40.0f
#define SETTLE_AFTER   18.0f /* s: the script's last stop is at 15 s; 3 s to settle */
#define WINDOW_SECONDS 2.0f

static standing_run run_stop_and_go(const mm_database *db)
{
    standing_run out;
    memset(&out, 0, sizeof out);
    mm_input_script script;
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(
        mm_input_script_load_json(MM_SOURCE_DIR "/scripts/input/stop_and_go.json", &script, &err), MM_OK);
    mm_character_desc desc;
    assert_int_equal(mm_character_desc_from_database(&desc, db, &err), MM_OK);
    mm_searcher searcher;
    mm_character c;
    assert_int_equal(mm_searcher_init(&searcher, db, NULL, &err), MM_OK);
    assert_int_equal(mm_character_init(&c, db, &searcher, &desc, &err), MM_OK);
    int ticks = (int)lroundf(SCRIPT_SECONDS / TICK), window = (int)lroundf(WINDOW_SECONDS / TICK);
    int settle = (int)lroundf(SETTLE_AFTER / TICK), idle = 0;
    int bone[4] = {c.foot_joint[0], c.toe_joint[0], c.foot_joint[1], c.toe_joint[1]};
    mm_vec3 root0 = {0, 0, 0}, at0[4], raw_last[2];
    int planted[4];
    float path[2] = {0, 0};
    for (int i = 0; i < ticks; ++i) {
        mm_input in;
        mm_input_script_sample_tick(&script, (float)i * TICK, TICK, &in);
        mm_character_update(&c, &in, TICK);
        if (i < settle) continue;
        idle += c.idle;
        int w = (i - settle) % window;
        unsigned label = db->contacts[c.frame];
        if (w == 0) {
            root0 = c.root.translation;
            for (int b = 0; b < 4; ++b) {
                at0[b] = c.global[bone[b]].translation;
                planted[b] = (label >> b) & 1u;
            }
            for (int k = 0; k < 2; ++k) raw_last[k] = c.raw_contact_positions[2 * k];
            path[0] = path[1] = 0.0f;
            continue;
        }
        out.root = fmaxf(out.root, mm_vec3_distance(c.root.translation, root0));
        for (int b = 0; b < 4; ++b) {
            planted[b] = planted[b] && ((label >> b) & 1u) && c.foot_locked[b / 2];
            if (planted[b])
                out.planted = fmaxf(out.planted, mm_vec3_distance(c.global[bone[b]].translation, at0[b]));
        }
        for (int k = 0; k < 2; ++k) {
            path[k] += mm_vec3_distance(c.raw_contact_positions[2 * k], raw_last[k]);
            raw_last[k] = c.raw_contact_positions[2 * k];
            out.ankle_path = fmaxf(out.ankle_path, path[k]);
        }
        if (w == window - 1) ++out.windows;
    }
    out.idle_share = (float)idle / (float)(ticks - settle);
    mm_character_free(&c);
    mm_searcher_free(&searcher);
    mm_input_script_free(&script);
    return out;
}

static void print_run(const char *what, const standing_run *r)
{
    print_message(
        "%s: over %d windows of 2 s after the stop: root moved up to %.2f cm, planted feet %.2f cm, "
        "an ankle travelled up to %.2f cm (animated); idle asked %.0f%% of the ticks\n",
        what, r->windows, 100.0 * r->root, 100.0 * r->planted, 100.0 * r->ankle_path, 100.0 * r->idle_share);
}

static void test_builtin_without_idle(void **state)
{
    (void)state;
    mm_database db;
    mm_db_build_report report;
    assert_int_equal(build(MM_SOURCE_DIR "/configs/synth.json", 1, not_idle, true, &db, &report), 0);
    check_made_clip(&db, &report);
    check_every_made_clip(&db, &report);
    standing_run r = run_stop_and_go(&db);
    print_run("built-in set without idle", &r);
    assert_true(r.windows >= 10);
    assert_true(r.idle_share > 0.99f);
    assert_true(r.root < STILL_ROOT);
    assert_true(r.planted < STILL_FEET);
    assert_true(r.ankle_path < STILL_FEET); /* the animation itself stands still */
    mm_database_free(&db);
}

/* standing.make false: no clip made, the report and the diagnosis say why; without the stops (whose
 * ends stand still) the character keeps stepping where the made pose stands still. */
static void test_pose_is_what_stands(void **state)
{
    (void)state;
    mm_database on, off;
    mm_db_build_report report_on, report_off;
    assert_int_equal(build(MM_SOURCE_DIR "/configs/synth.json", 1, not_idle_nor_stop, true, &on, &report_on),
                     0);
    assert_int_equal(
        build(MM_SOURCE_DIR "/configs/synth.json", 1, not_idle_nor_stop, false, &off, &report_off), 0);
    assert_int_equal(report_on.standing.status, MM_STANDING_MADE);
    assert_int_equal(report_off.standing.status, MM_STANDING_OFF);
    assert_int_equal(on.clip_count, off.clip_count + 2 * report_on.standing.poses);
    for (int c = 0; c < off.clip_count; ++c) assert_int_not_equal(off.clips[c].type, MM_CLIP_IDLE);
    mm_diagnosis d;
    assert_int_equal(mm_database_diagnose(&off, &report_off, NULL, &d), MM_OK);
    assert_int_equal(d.items[0].code, MM_DIAG_NO_IDLE);
    assert_non_null(strstr(d.items[0].message, "standing.make is false"));
    standing_run a = run_stop_and_go(&on), b = run_stop_and_go(&off);
    print_run("without idle and stops, standing made", &a);
    print_run("without idle and stops, standing.make false", &b);
    assert_true(a.root < STILL_ROOT && a.planted < STILL_FEET && a.ankle_path < STILL_FEET);
    assert_true(b.ankle_path > STEPPING); /* it keeps stepping */
    mm_database_free(&on);
    mm_database_free(&off);
}

/* The same bytes with the poses made, whatever the threads. */
static void test_same_bytes_any_threads(void **state)
{
    (void)state;
    mm_database one, three;
    assert_int_equal(build_threads(MM_SOURCE_DIR "/configs/synth.json", 1, not_idle, true, 1, &one, NULL), 0);
    assert_int_equal(build_threads(MM_SOURCE_DIR "/configs/synth.json", 1, not_idle, true, 3, &three, NULL),
                     0);
    assert_true(find_clip(&one, "standing_from_walk_start_16") >= 0);
    assert_int_equal(one.size, three.size);
    assert_memory_equal(one.data, three.data, one.size);
    mm_database_free(&one);
    mm_database_free(&three);
}

/* The config keeps an idle clip: nothing is made. */
static void test_not_needed_with_idle(void **state)
{
    (void)state;
    mm_database db;
    mm_db_build_report report;
    assert_int_equal(build(MM_SOURCE_DIR "/configs/synth.json", 1, keep_all, true, &db, &report), 0);
    assert_int_equal(report.standing.status, MM_STANDING_NOT_NEEDED);
    for (int c = 0; c < db.clip_count; ++c) assert_false(starts_with(db.clips[c].name, STANDING_PREFIX));
    mm_database_free(&db);
}

/* standing.make in JSON: read, defaulted, refused with a wrong type or an unknown key (the field
 * named), and written back by mm_config_save_json only when it differs from the default. */
static void test_config_key(void **state)
{
    (void)state;
    mm_config cfg, back;
    memset(&cfg, 0, sizeof cfg);
    memset(&back, 0, sizeof back);
    mm_error err;
    memset(&err, 0, sizeof err);
    const char *off = "{\"standing\": {\"make\": false}}", *none = "{}",
               *wrong = "{\"standing\": {\"make\": 1}}", *unknown = "{\"standing\": {\"poses\": 3}}";
    assert_int_equal(mm_config_parse_json(none, strlen(none), "none.json", NULL, &cfg, &err), MM_OK);
    assert_true(cfg.standing_make);
    mm_config_free(&cfg);
    assert_int_equal(mm_config_parse_json(off, strlen(off), "off.json", NULL, &cfg, &err), MM_OK);
    assert_false(cfg.standing_make);
    mm_config_free(&cfg);
    assert_int_not_equal(mm_config_parse_json(wrong, strlen(wrong), "wrong.json", NULL, &cfg, &err), MM_OK);
    assert_non_null(strstr(err.message, "standing"));
    mm_config_free(&cfg);
    memset(&err, 0, sizeof err);
    assert_int_not_equal(mm_config_parse_json(unknown, strlen(unknown), "unknown.json", NULL, &cfg, &err),
                         MM_OK);
    assert_non_null(strstr(err.message, "poses"));
    mm_config_free(&cfg);
    /* saved and read back */
    assert_int_equal(mm_config_load_json(MM_SOURCE_DIR "/configs/synth.json", &cfg, NULL, &err), MM_OK);
    cfg.standing_make = false;
    const char *path = MM_TEST_OUT "/standing_off.json";
    assert_int_equal(mm_config_save_json(path, &cfg, &err), MM_OK);
    assert_int_equal(mm_config_load_json(path, &back, NULL, &err), MM_OK);
    assert_false(back.standing_make);
    mm_config_free(&back);
    cfg.standing_make = true;
    assert_int_equal(mm_config_save_json(path, &cfg, &err), MM_OK);
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    static char text[1 << 16];
    text[fread(text, 1, sizeof text - 1, f)] = 0;
    fclose(f);
    assert_null(strstr(text, "standing")); /* the default is not written */
    mm_config_free(&cfg);
    remove(path);
}

/* Takes with no frame to stand on (runs alone): the build succeeds, makes nothing, and says why. */
static void test_nothing_to_stand_on(void **state)
{
    (void)state;
    mm_database db;
    mm_db_build_report report;
    assert_int_equal(build(MM_SOURCE_DIR "/configs/synth.json", 1, run_loops, true, &db, &report), 0);
    assert_true(db.clip_count > 0);
    assert_int_equal(report.standing.status, MM_STANDING_NOT_FOUND);
    assert_int_equal(report.standing.poses, 0);
    assert_int_equal(report.standing.standing_frames, 0);
    for (int c = 0; c < db.clip_count; ++c) assert_int_not_equal(db.clips[c].type, MM_CLIP_IDLE);
    mm_diagnosis d;
    assert_int_equal(mm_database_diagnose(&db, &report, NULL, &d), MM_OK);
    assert_int_equal(d.items[0].code, MM_DIAG_NO_IDLE);
    assert_non_null(strstr(d.items[0].message, "both feet down"));
    mm_database_free(&db);
}

/* LAFAN1's walk4_subject1 without its idle spans. */
static void test_lafan_walk_without_idle(void **state)
{
    (void)state;
    const char *dir = getenv("MM_DATA_DIR");
    if (!dir || !*dir) {
        print_message("MM_DATA_DIR not set: skipped\n");
        skip();
    }
    mm_database db;
    mm_db_build_report report;
    assert_int_equal(build(MM_DATA_CONFIGS "/lafan1.json", 0, lafan_walk, true, &db, &report), 0);
    check_made_clip(&db, &report);
    check_every_made_clip(&db, &report);
    standing_run r = run_stop_and_go(&db);
    print_run("LAFAN1 walk4_subject1 without idle", &r);
    assert_true(r.idle_share > 0.99f);
    assert_true(r.root < STILL_ROOT);
    assert_true(r.planted < STILL_FEET);
    mm_database_free(&db);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_config_key),
        cmocka_unit_test(test_builtin_without_idle),
        cmocka_unit_test(test_pose_is_what_stands),
        cmocka_unit_test(test_same_bytes_any_threads),
        cmocka_unit_test(test_not_needed_with_idle),
        cmocka_unit_test(test_nothing_to_stand_on),
        cmocka_unit_test(test_lafan_walk_without_idle),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
