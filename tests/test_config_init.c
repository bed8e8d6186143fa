/* mm config init (mm/config_init.h, mm/skeleton_roles.h) on every kind of skeleton: the built-in
 * set (mm synth); takes of it with the joints renamed to each naming convention, and to no
 * convention at all (geometry alone); turned to other axes (the same database); and, with MM_DATA_DIR, short
 * cuts of two LAFAN1 takes, the games105 takes (20 joints, metres, lXxx names, joints listed in
 * different orders) and the PFNN take (CMU names and units). For each: mm config init, then
 * mm db build on its output as it is, and the roles must be the expected joints. Every take is
 * written at run time into MM_TEST_OUT/config_init/. Also: mm_config_save_json reads back as
 * written, the frame spans of a start, and config init keeps an existing file without --force. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <sys/stat.h>

#include <mm/bvh.h>
#include <mm/config_init.h>
#include <mm/config_json.h>
#include <mm/database.h>
#include <mm/synth.h>

#include "test_util.h"

static mm_synth_set set;
static const char *mm_bin;

static int setup(void **state)
{
    (void)state;
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_bin = getenv("MM_BIN");
    char dir[1024];
    snprintf(dir, sizeof dir, "%s/config_init", MM_TEST_OUT);
    mkdir(dir, 0777);
    return mm_synth_generate(NULL, &set, &err) == MM_OK ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    mm_synth_set_free(&set);
    return 0;
}

/* ---- helpers ---------------------------------------------------------------------------- */

static const mm_clip *synth_clip(const char *name)
{
    for (int i = 0; i < set.clip_count; ++i)
        if (strcmp(set.clips[i].name, name) == 0) return &set.clips[i].clip;
    fail_msg("no synth clip %s", name);
    return NULL;
}

static void case_dir(const char *name, char *out, size_t size)
{
    snprintf(out, size, "%s/config_init/%s", MM_TEST_OUT, name);
    mkdir(out, 0777);
}

static void save_bvh(const char *path, const mm_clip *clip)
{
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_result r = mm_bvh_save(path, clip, NULL, &err);
    if (r != MM_OK) print_error("%s: %s\n", path, err.message);
    assert_int_equal(r, MM_OK);
}

/* Runs the mm program with args (a shell command line after "mm"), its output into log; the exit
 * status. */
static int run_mm(const char *args, const char *log)
{
    size_t size = strlen(mm_bin) + strlen(args) + strlen(log) + 16;
    char *cmd = (char *)malloc(size);
    assert_non_null(cmd);
    snprintf(cmd, size, "\"%s\" %s >\"%s\" 2>&1", mm_bin, args, log);
    int status = system(cmd);
    free(cmd);
    return status == -1 ? -1 : (status >> 8) & 0xff;
}

static void print_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    char line[1024];
    while (f && fgets(line, sizeof line, f)) print_message("    %s", line);
    if (f) fclose(f);
}

typedef struct expected {
    const char *roles[MM_BODY_ROLE_COUNT]; /* hips, root_bone, facing_bone, feet, toes, hands, head */
    mm_vec3 forward_axis;
    int mirror; /* the clips are mirrored */
} expected;

/* mm config init FILES -o DIR/config.json, mm db build on it; the config's roles must be e's. */
static void init_and_build(const char *dir, const char *files, const expected *e)
{
    char args[8192], log[1200], config[1100], db[1100];
    snprintf(config, sizeof config, "%s/config.json", dir);
    snprintf(db, sizeof db, "%s/db.mmdb", dir);
    snprintf(log, sizeof log, "%s/init.txt", dir);
    snprintf(args, sizeof args, "config init %s -o \"%s\" --force", files, config);
    int status = run_mm(args, log);
    print_message("  %s:\n", dir);
    print_file(log);
    assert_int_equal(status, 0);
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_config_load_json(config, &cfg, NULL, &err), MM_OK);
    const char *got[MM_BODY_ROLE_COUNT] = {cfg.hips,       cfg.root_bone, cfg.facing_bone, cfg.left_foot,
                                           cfg.right_foot, cfg.left_toe,  cfg.right_toe,   cfg.left_hand,
                                           cfg.right_hand, cfg.head};
    for (int i = 0; i < MM_BODY_ROLE_COUNT; ++i) {
        if (strcmp(got[i], e->roles[i]) != 0)
            fail_msg("%s: roles.%s is %s, not %s", dir, mm_body_role_name((mm_body_role)i), got[i],
                     e->roles[i]);
    }
    assert_float_equal(cfg.forward_axis.x, e->forward_axis.x, 1e-6);
    assert_float_equal(cfg.forward_axis.y, e->forward_axis.y, 1e-6);
    assert_float_equal(cfg.forward_axis.z, e->forward_axis.z, 1e-6);
    assert_true(cfg.clip_count > 0);
    for (int i = 0; i < cfg.clip_count; ++i) assert_int_equal(cfg.clips[i].mirror, e->mirror);
    assert_true(cfg.runtime.walk.set & MM_RUNTIME_FORWARD_SPEED);
    assert_true(cfg.runtime.run.forward_speed >= cfg.runtime.walk.forward_speed);
    mm_config_free(&cfg);
    snprintf(log, sizeof log, "%s/build.txt", dir);
    snprintf(args, sizeof args, "db build \"%s\" -o \"%s\"", config, db);
    status = run_mm(args, log);
    if (status != 0) print_file(log);
    assert_int_equal(status, 0);
    mm_database d;
    assert_int_equal(mm_database_load(db, NULL, &d, &err), MM_OK);
    int mirrored = 0;
    for (int i = 0; i < d.clip_count; ++i) mirrored += d.clips[i].mirrored;
    assert_true(d.frame_count > 0);
    assert_int_equal(mirrored > 0, e->mirror);
    mm_database_free(&d);
}

/* ---- the built-in set ------------------------------------------------------------------- */

static const expected synth_roles = {{"Hips", "Spine2", "Hips", "LeftFoot", "RightFoot", "LeftToe",
                                      "RightToe", "LeftHand", "RightHand", "Head"},
                                     {0, 0, 1},
                                     1};

static void test_builtin_set(void **state)
{
    (void)state;
    if (!mm_bin) skip();
    char dir[1024], args[2048], log[1100];
    case_dir("synth", dir, sizeof dir);
    snprintf(args, sizeof args, "synth \"%s\"", dir);
    snprintf(log, sizeof log, "%s/synth.txt", dir);
    assert_int_equal(run_mm(args, log), 0);
    snprintf(args, sizeof args, "\"%s\"/*.bvh", dir);
    init_and_build(dir, args, &synth_roles);
}

/* ---- naming conventions ----------------------------------------------------------------- */

/* The built-in skeleton's joints as side (0 none, 1 left, 2 right) and part. */
static void split(const char *name, int *side, const char **part)
{
    *side = strncmp(name, "Left", 4) == 0 ? 1 : strncmp(name, "Right", 5) == 0 ? 2 : 0;
    *part = name + (*side == 1 ? 4 : *side == 2 ? 5 : 0);
}

static void lower(const char *in, char *out)
{
    for (; *in; ++in) *out++ = (char)(*in >= 'A' && *in <= 'Z' ? *in - 'A' + 'a' : *in);
    *out = 0;
}

enum convention {
    C_SUFFIX_UL, /* Foot_L */
    C_SUFFIX_DOT,
    C_SUFFIX_LOWER, /* foot_l */
    C_PREFIX_L_,    /* l_foot */
    C_PREFIX_CAP,   /* LFoot */
    C_PREFIX_LOWER, /* lFoot */
    C_MIXAMO,       /* mixamorig:LeftFoot */
    C_CMU,          /* LeftToeBase */
    C_BIOVISION,    /* LeftAnkle, LeftWrist */
    C_NONE,         /* j00, j01 ... */
    C_COUNT
};
static const char *const convention_names[C_COUNT] = {"suffix_L",  "suffix_dot",  "suffix_lower", "prefix_l_",
                                                      "prefix_L",  "prefix_lXxx", "mixamo",       "cmu",
                                                      "biovision", "anonymous"};

static void rename_joint(int convention, int index, const char *name, char *out)
{
    int side;
    const char *part;
    char low[MM_NAME_MAX];
    split(name, &side, &part);
    lower(part, low);
    static const char *const sides[3][2] = {{"", ""}, {"L", "l"}, {"R", "r"}};
    switch (convention) {
    case C_SUFFIX_UL:
    case C_SUFFIX_DOT:
        if (side)
            sprintf(out, "%s%s%s", part, convention == C_SUFFIX_UL ? "_" : ".", sides[side][0]);
        else
            strcpy(out, name);
        break;
    case C_SUFFIX_LOWER:
        if (side)
            sprintf(out, "%s_%s", low, sides[side][1]);
        else
            strcpy(out, low);
        break;
    case C_PREFIX_L_:
        if (side)
            sprintf(out, "%s_%s", sides[side][1], low);
        else
            strcpy(out, low);
        break;
    case C_PREFIX_CAP:
    case C_PREFIX_LOWER:
        if (side)
            sprintf(out, "%s%s", sides[side][convention == C_PREFIX_CAP ? 0 : 1], part);
        else
            strcpy(out, name);
        break;
    case C_MIXAMO: /* LeftToeBase, LeftToe_End */
        sprintf(out, "mixamorig:%s%s", name, strcmp(part, "Toe") == 0 ? "Base" : "");
        break;
    case C_CMU:
        sprintf(out, "%s%s", name, strcmp(part, "Toe") == 0 ? "Base" : "");
        break;
    case C_BIOVISION: {
        static const char *const from[] = {"UpLeg",   "Leg",  "Foot",  "Toe",    "Shoulder", "Arm",
                                           "ForeArm", "Hand", "Spine", "Spine1", "Spine2"};
        static const char *const to[] = {"Hip",   "Knee",  "Ankle",   "Toe",   "Collar", "Shoulder",
                                         "Elbow", "Wrist", "Abdomen", "Chest", "Chest2"};
        const char *p = part;
        for (size_t i = 0; i < sizeof from / sizeof from[0]; ++i)
            if (strcmp(part, from[i]) == 0) p = to[i];
        sprintf(out, "%s%s", side == 1 ? "Left" : side == 2 ? "Right" : "", p);
        break;
    }
    default:
        sprintf(out, "j%02d", index);
        break;
    }
}

/* Mixamo's skeleton has more joints than the built-in one: an end joint above the head and
 * beyond each toe (HeadTop_End, LeftToe_End) and the fingers (LeftHandIndex1, 2) where the
 * built-in one has End Sites. Adds them to clip (in place) as the last joints. */
static void add_mixamo_ends(mm_clip *clip)
{
    const mm_skeleton *s = &clip->skeleton;
    int n = s->joint_count, extra = 0, parent[8];
    char names[8][MM_NAME_MAX + 16];
    mm_vec3 offsets[8];
    for (int j = 0; j < n; ++j) {
        const char *name = s->joints[j].name;
        if (!s->joints[j].has_end_site) continue;
        mm_vec3 e = s->joints[j].end_site;
        if (strstr(name, "Hand")) { /* two finger joints along the End Site */
            parent[extra] = j;
            offsets[extra] = mm_vec3_scale(e, 0.5f);
            snprintf(names[extra++], sizeof names[0], "%sIndex1", name);
            parent[extra] = n + extra - 1;
            offsets[extra] = mm_vec3_scale(e, 0.5f);
            snprintf(names[extra++], sizeof names[0], "%sIndex2", name);
        } else {
            parent[extra] = j;
            offsets[extra] = e;
            if (strcmp(name, "Head") == 0)
                snprintf(names[extra++], sizeof names[0], "HeadTop_End");
            else
                snprintf(names[extra++], sizeof names[0], "%s_End", name);
        }
    }
    mm_skeleton big;
    assert_int_equal(mm_skeleton_init(&big, n + extra, NULL), MM_OK);
    memcpy(big.joints, s->joints, sizeof(mm_joint) * (size_t)n);
    for (int k = 0; k < extra; ++k) {
        mm_joint *jt = &big.joints[n + k];
        memset(jt, 0, sizeof *jt);
        snprintf(jt->name, MM_NAME_MAX, "%.*s", MM_NAME_MAX - 1, names[k]);
        jt->parent = parent[k];
        jt->offset = offsets[k];
        jt->order = MM_EULER_ZYX;
        big.joints[parent[k]].has_end_site = false;
    }
    mm_clip more;
    assert_int_equal(mm_clip_init(&more, &big, clip->frame_count, clip->fps, NULL), MM_OK);
    for (int f = 0; f < clip->frame_count; ++f) {
        memcpy(mm_clip_rotations(&more, f), mm_clip_rotations(clip, f), sizeof(mm_quat) * (size_t)n);
        memcpy(mm_clip_positions(&more, f), mm_clip_positions(clip, f), sizeof(mm_vec3) * (size_t)n);
    }
    mm_skeleton_free(&big);
    mm_clip_free(clip);
    *clip = more;
}

/* A take of the built-in set in convention c. */
static void make_variant(int c, const char *take, mm_clip *out)
{
    const mm_clip *src = synth_clip(take);
    assert_int_equal(mm_clip_copy(out, src, NULL), MM_OK);
    if (c == C_MIXAMO) add_mixamo_ends(out);
    for (int j = 0; j < out->skeleton.joint_count; ++j) {
        char name[MM_NAME_MAX];
        rename_joint(c, j, out->skeleton.joints[j].name, name);
        snprintf(out->skeleton.joints[j].name, MM_NAME_MAX, "%s", name);
    }
}

static void test_conventions(void **state)
{
    (void)state;
    if (!mm_bin) skip();
    static const char *const takes[] = {"idle",          "walk_1.40",     "walk_start",
                                        "sidestep_left", "walk_backward", "run_3.80"};
    const mm_skeleton *s = &synth_clip("idle")->skeleton;
    for (int c = 0; c < C_COUNT; ++c) {
        char dir[1024], files[4096] = "";
        case_dir(convention_names[c], dir, sizeof dir);
        for (size_t t = 0; t < sizeof takes / sizeof takes[0]; ++t) {
            mm_clip clip;
            make_variant(c, takes[t], &clip);
            char path[1200];
            snprintf(path, sizeof path, "%s/%s.bvh", dir, takes[t]);
            save_bvh(path, &clip);
            mm_clip_free(&clip);
            size_t len = strlen(files);
            snprintf(files + len, sizeof files - len, " \"%s\"", path);
        }
        expected e = synth_roles;
        static char names[MM_BODY_ROLE_COUNT][MM_NAME_MAX];
        for (int i = 0; i < MM_BODY_ROLE_COUNT; ++i) {
            rename_joint(c, mm_skeleton_find(s, synth_roles.roles[i]), synth_roles.roles[i], names[i]);
            e.roles[i] = names[i];
        }
        e.mirror = c != C_NONE; /* no names, no mirror pairs */
        init_and_build(dir, files, &e);
    }
}

/* The roles' confidences from the library: names and geometry agree on every role of the named
 * variants; geometry alone gives 0.8 at most. */
static void test_confidences(void **state)
{
    (void)state;
    const mm_skeleton *s = &synth_clip("idle")->skeleton;
    for (int c = 0; c < C_COUNT; ++c) {
        mm_clip clips[2];
        make_variant(c, "walk_1.40", &clips[0]);
        make_variant(c, "idle", &clips[1]);
        mm_skeleton_roles r;
        mm_error err;
        memset(&err, 0, sizeof err);
        assert_int_equal(mm_skeleton_roles_find(clips, 2, &r, &err), MM_OK);
        for (int i = 0; i < MM_BODY_ROLE_COUNT; ++i) {
            assert_int_equal(r.roles[i].joint, mm_skeleton_find(s, synth_roles.roles[i]));
            if (c == C_NONE) {
                assert_true(r.roles[i].confidence <= 0.8f && r.roles[i].confidence >= 0.7f);
                assert_int_equal(r.roles[i].evidence, MM_EVIDENCE_GEOMETRY);
            } else if (c == C_MIXAMO && i == MM_BODY_HEAD) { /* the top end is HeadTop_End */
                assert_float_equal(r.roles[i].confidence, 0.9f, 1e-6);
                assert_string_equal(clips[0].skeleton.joints[r.roles[i].other].name, "mixamorig:HeadTop_End");
            } else {
                assert_float_equal(r.roles[i].confidence, 1.0f, 1e-6);
            }
        }
        assert_float_equal(r.forward_confidence, 1.0f, 1e-6);
        assert_int_equal(r.forward_evidence, MM_EVIDENCE_GEOMETRY | MM_EVIDENCE_MOTION);
        assert_int_equal(r.mirror, c != C_NONE);
        if (c != C_NONE) {
            assert_int_equal(r.paired_joints, c == C_MIXAMO ? 22 : 16); /* and the ends, the fingers */
            assert_int_equal(r.unpaired_joints, 0);
            assert_true(r.sides_from_names);
        }
        assert_true(r.side_agreement > 0.95f);
        mm_clip_free(&clips[0]);
        mm_clip_free(&clips[1]);
    }
}

/* ---- axes ------------------------------------------------------------------------------ */

/* mm config init TAKES OPTIONS -o DIR/config.json, then mm db build; the config into cfg, the
 * database into d, the report into DIR/init.txt. */
static void init_build_load(const char *dir, const char *files, const char *options, mm_config *cfg,
                            mm_database *d)
{
    char args[8192], log[1200], config[1100], db[1100];
    snprintf(config, sizeof config, "%s/config.json", dir);
    snprintf(db, sizeof db, "%s/db.mmdb", dir);
    snprintf(log, sizeof log, "%s/init.txt", dir);
    snprintf(args, sizeof args, "config init %s %s -o \"%s\" --force", files, options, config);
    int status = run_mm(args, log);
    print_message("  %s:\n", dir);
    print_file(log);
    assert_int_equal(status, 0);
    mm_error err;
    memset(&err, 0, sizeof err);
    memset(cfg, 0, sizeof *cfg);
    assert_int_equal(mm_config_load_json(config, cfg, NULL, &err), MM_OK);
    snprintf(log, sizeof log, "%s/build.txt", dir);
    snprintf(args, sizeof args, "db build \"%s\" -o \"%s\"", config, db);
    status = run_mm(args, log);
    if (status != 0) print_file(log);
    assert_int_equal(status, 0);
    assert_int_equal(mm_database_load(db, NULL, d, &err), MM_OK);
}

/* The largest distance between the world joint positions of two databases' frames (FK from the
 * simulation bone); they must have the same frames and joints. */
static double world_difference(const mm_database *a, const mm_database *b)
{
    assert_int_equal(a->frame_count, b->frame_count);
    assert_int_equal(a->joint_count, b->joint_count);
    int jc = a->joint_count;
    mm_skeleton sa = {jc, (mm_joint *)a->joints, {0}}, sb = {jc, (mm_joint *)b->joints, {0}};
    mm_xform *ga = (mm_xform *)malloc(sizeof(mm_xform) * (size_t)jc),
             *gb = (mm_xform *)malloc(sizeof(mm_xform) * (size_t)jc);
    assert_non_null(ga);
    assert_non_null(gb);
    double worst = 0.0;
    for (int f = 0; f < a->frame_count; ++f) {
        size_t at = (size_t)f * (size_t)jc;
        mm_fk(&sa, a->rotations + at, a->positions + at, ga);
        mm_fk(&sb, b->rotations + at, b->positions + at, gb);
        for (int j = 0; j < jc; ++j)
            worst = fmax(worst, mm_vec3_length(mm_vec3_sub(ga[j].translation, gb[j].translation)));
    }
    free(ga);
    free(gb);
    return worst;
}

/* Takes of the built-in set turned to other axes (their root joint's channels turned at run time;
 * every joint's world position checked by FK to be the original's turned) give, through mm config
 * init and mm db build, the original's database: every world joint within 0.1 mm. A take standing
 * along +Z is found so; one facing +X needs --forward. */
static void test_axes(void **state)
{
    (void)state;
    static const char *const takes[] = {"walk_1.40", "idle", "walk_start"};
    static const struct {
        const char *name;
        int up, forward; /* the files' axes */
        const char *options;
    } cases[] = {
        {"axes_y_up", MM_AXIS_POS_Y, MM_AXIS_POS_Z, ""},
        {"axes_z_up", MM_AXIS_POS_Z, MM_AXIS_NEG_Y, ""},
        {"axes_neg_z_up", MM_AXIS_NEG_Z, MM_AXIS_POS_Y, ""},
        {"axes_x_up_facing_neg_z", MM_AXIS_POS_X, MM_AXIS_NEG_Z, "--forward -Z"},
        {"axes_y_up_facing_x", MM_AXIS_POS_Y, MM_AXIS_POS_X, "--forward +X"},
    };
    mm_database reference;
    memset(&reference, 0, sizeof reference);
    static char reference_spans[1300];
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        char dir[1024], files[4096] = "";
        case_dir(cases[c].name, dir, sizeof dir);
        /* the turn from mm's world to the files' (the inverse of what the build applies) */
        const mm_quat to_file = mm_quat_conj(mm_axes_turn(cases[c].up, cases[c].forward));
        const mm_vec3 up_in_file = mm_quat_rotate(to_file, mm_vec3_make(0, 1, 0));
        assert_float_equal(up_in_file.x, (cases[c].up % 3 == 0 ? (cases[c].up < 3 ? 1 : -1) : 0), 1e-6);
        assert_float_equal(up_in_file.y, (cases[c].up % 3 == 1 ? (cases[c].up < 3 ? 1 : -1) : 0), 1e-6);
        assert_float_equal(up_in_file.z, (cases[c].up % 3 == 2 ? (cases[c].up < 3 ? 1 : -1) : 0), 1e-6);
        for (size_t t = 0; t < sizeof takes / sizeof takes[0]; ++t) {
            const mm_clip *original = synth_clip(takes[t]);
            mm_clip clip;
            assert_int_equal(mm_clip_copy(&clip, original, NULL), MM_OK);
            int jc = clip.skeleton.joint_count;
            for (int f = 0; f < clip.frame_count; ++f) { /* the root's channels turned */
                mm_clip_rotations(&clip, f)[0] = mm_quat_mul(to_file, mm_clip_rotations(&clip, f)[0]);
                mm_clip_positions(&clip, f)[0] = mm_quat_rotate(to_file, mm_clip_positions(&clip, f)[0]);
            }
            mm_xform *g0 = (mm_xform *)malloc(sizeof(mm_xform) * (size_t)jc),
                     *g1 = (mm_xform *)malloc(sizeof(mm_xform) * (size_t)jc);
            assert_non_null(g0);
            assert_non_null(g1);
            for (int f = 0; f < clip.frame_count; f += 7) {
                mm_clip_fk(original, f, g0);
                mm_clip_fk(&clip, f, g1);
                for (int j = 0; j < jc; ++j) {
                    mm_vec3 want = mm_quat_rotate(to_file, g0[j].translation), got = g1[j].translation;
                    if (mm_vec3_length(mm_vec3_sub(want, got)) > 1e-5f)
                        fail_msg("%s frame %d joint %d: FK off the turned world", takes[t], f, j);
                }
            }
            free(g0);
            free(g1);
            float confidence = 0.0f;
            assert_int_equal(mm_clip_up_axis(&clip, &confidence), cases[c].up);
            char path[1200];
            snprintf(path, sizeof path, "%s/%s.bvh", dir, takes[t]);
            save_bvh(path, &clip);
            mm_clip_free(&clip);
            size_t len = strlen(files);
            snprintf(files + len, sizeof files - len, " \"%s\"", path);
        }
        if (!mm_bin) continue;
        mm_config cfg;
        mm_database d;
        init_build_load(dir, files, cases[c].options, &cfg, &d);
        assert_int_equal(cfg.axes_up, cases[c].up);
        assert_int_equal(mm_axes_forward(cfg.axes_up, cfg.axes_forward), cases[c].forward);
        mm_config_free(&cfg);
        /* mm bvh spans turns the take too, by the up it finds and by the config's axes: the spans
         * of the original */
        for (int with_config = 0; with_config < 2; ++with_config) {
            char args[4096], log[1200], spans[1300];
            snprintf(log, sizeof log, "%s/spans%d.json", dir, with_config);
            snprintf(args, sizeof args, "bvh spans \"%s/walk_start.bvh\" %s%s%s", dir,
                     with_config ? "--config \"" : "", with_config ? dir : "",
                     with_config ? "/config.json\"" : "");
            assert_int_equal(run_mm(args, log), 0);
            FILE *f = fopen(log, "rb");
            assert_non_null(f);
            size_t n = fread(args, 1, sizeof args - 1, f);
            fclose(f);
            args[n] = 0;
            const char *from = strstr(args, "\"upright_head_height\"");
            assert_non_null(from);
            if (c == 0 && !with_config) snprintf(reference_spans, sizeof reference_spans, "%s", from);
            snprintf(spans, sizeof spans, "%s", from);
            if (strcmp(spans, reference_spans) != 0)
                fail_msg("%s: bvh spans%s gave\n%s\nnot\n%s", cases[c].name, with_config ? " --config" : "",
                         spans, reference_spans);
            if (!strstr(args, mm_axis_name(cases[c].up)))
                fail_msg("%s: bvh spans: no up %s", cases[c].name, mm_axis_name(cases[c].up));
        }
        if (c == 0) {
            reference = d;
            continue;
        }
        double worst = world_difference(&reference, &d);
        print_message("  %s: world joints within %.3g mm of the +Y up build\n", cases[c].name,
                      worst * 1000.0);
        assert_true(worst < 1e-4);
        mm_database_free(&d);
    }
    if (mm_bin) mm_database_free(&reference);
    /* takes standing along different axes: an error naming both; --up decides */
    mm_clip turned;
    assert_int_equal(mm_clip_copy(&turned, synth_clip("walk_1.40"), NULL), MM_OK);
    mm_clip_turn(&turned, mm_quat_conj(mm_axes_turn(MM_AXIS_POS_Z, -1)));
    mm_config_init_take two[2] = {{"a.bvh", NULL, NULL, "a", synth_clip("idle")},
                                  {"b.bvh", NULL, NULL, "b", &turned}};
    mm_config cfg;
    mm_config_init_report rep;
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_config_init(two, 2, NULL, &cfg, &rep, &err), MM_ERR_INVALID_ARGUMENT);
    print_message("  %s: %s\n", err.file, err.message);
    assert_non_null(strstr(err.message, "stands along +Z"));
    assert_non_null(strstr(err.message, "but along +Y in a.bvh"));
    assert_string_equal(err.file, "b.bvh");
    mm_config_init_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.up_given = true;
    desc.up_axis = MM_AXIS_POS_Y;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_config_init(two, 2, &desc, &cfg, &rep, &err), MM_OK);
    assert_true(rep.up_given);
    assert_int_equal(cfg.axes_up, MM_AXIS_POS_Y);
    mm_config_free(&cfg);
    mm_clip_free(&turned);
}

/* A config's axes: read, validated, written back. */
static void test_axes_json(void **state)
{
    (void)state;
    char dir[1024], path[1200];
    case_dir("axes_json", dir, sizeof dir);
    snprintf(path, sizeof path, "%s/config.json", dir);
    static const struct {
        const char *text;
        mm_result result;
        const char *message; /* in the error */
        int up, forward;
    } cases[] = {
        {"{\"axes\": {\"up\": \"+Z\"}}", MM_OK, NULL, MM_AXIS_POS_Z, -1},
        {"{\"axes\": {\"up\": \"-z\", \"forward\": \"X\"}}", MM_OK, NULL, MM_AXIS_NEG_Z, MM_AXIS_POS_X},
        {"{}", MM_OK, NULL, MM_AXIS_POS_Y, -1},
        {"{\"axes\": {\"up\": \"up\"}}", MM_ERR_SYNTAX, "axes.up: 'up' is not an axis", 0, 0},
        {"{\"axes\": {\"up\": 2}}", MM_ERR_SYNTAX, "axes.up must be a string", 0, 0},
        {"{\"axes\": {\"up\": \"+Z\", \"forward\": \"-Z\"}}", MM_ERR_OUT_OF_RANGE,
         "forward -Z lies along up +Z", 0, 0},
        {"{\"axes\": {\"side\": \"+X\"}}", MM_ERR_UNKNOWN_KEYWORD, "axes.side", 0, 0},
        {"{\"axes\": \"+Z\"}", MM_ERR_SYNTAX, "axes must be an object", 0, 0},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        FILE *f = fopen(path, "wb");
        assert_non_null(f);
        fputs(cases[i].text, f);
        fclose(f);
        mm_config cfg;
        memset(&cfg, 0, sizeof cfg);
        mm_error err;
        memset(&err, 0, sizeof err);
        mm_result r = mm_config_load_json(path, &cfg, NULL, &err);
        if (r != cases[i].result) fail_msg("%s: %s (%s)", cases[i].text, mm_result_str(r), err.message);
        if (r != MM_OK) {
            if (!strstr(err.message, cases[i].message)) fail_msg("%s: '%s'", cases[i].text, err.message);
            continue;
        }
        assert_int_equal(cfg.axes_up, cases[i].up);
        assert_int_equal(cfg.axes_forward, cases[i].forward);
        /* written and read back */
        char again[1300];
        snprintf(again, sizeof again, "%s/again.json", dir);
        assert_int_equal(mm_config_save_json(again, &cfg, &err), MM_OK);
        mm_config back;
        memset(&back, 0, sizeof back);
        assert_int_equal(mm_config_load_json(again, &back, NULL, &err), MM_OK);
        assert_int_equal(back.axes_up, cases[i].up);
        assert_int_equal(back.axes_forward, cases[i].forward);
        mm_config_free(&back);
        mm_config_free(&cfg);
    }
    /* the turns: +Z up, -Y forward is the rotation of -90 degrees about X */
    mm_quat q = mm_axes_turn(MM_AXIS_POS_Z, -1);
    mm_vec3 v = mm_quat_rotate(q, mm_vec3_make(0, 0, 1)), w = mm_quat_rotate(q, mm_vec3_make(0, -1, 0));
    assert_float_equal(v.y, 1.0f, 1e-6);
    assert_float_equal(w.z, 1.0f, 1e-6);
    for (int up = 0; up < 6; ++up)
        for (int fw = 0; fw < 6; ++fw) {
            if (up % 3 == fw % 3) continue;
            q = mm_axes_turn(up, fw);
            int axes[2] = {up, fw};
            for (int k = 0; k < 2; ++k) {
                float e[3] = {0, 0, 0};
                e[axes[k] % 3] = axes[k] < 3 ? 1.0f : -1.0f;
                mm_vec3 to = mm_quat_rotate(q, mm_vec3_make(e[0], e[1], e[2]));
                assert_float_equal(k == 0 ? to.y : to.z, 1.0f, 1e-6);
            }
            assert_float_equal(mm_quat_length(q), 1.0f, 1e-6);
        }
    for (int a = 0; a < 6; ++a) assert_int_equal(mm_axis_parse(mm_axis_name(a)), a);
    assert_int_equal(mm_axis_parse("+W"), -1);
    assert_int_equal(mm_axis_parse("+"), -1);
    assert_int_equal(mm_axis_parse("+ZZ"), -1);
}

/* ---- motion capture --------------------------------------------------------------------- */

/* Frames [begin, end) of a BVH file, in its own units, written to path. */
static void cut_take(const char *source, int begin, int end, const char *path)
{
    mm_bvh bvh;
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_bvh_load(source, NULL, &bvh, &err), MM_OK);
    mm_clip clip, cut;
    assert_int_equal(mm_bvh_to_clip(&bvh, NULL, &clip, &err), MM_OK);
    mm_bvh_free(&bvh);
    if (end > clip.frame_count) end = clip.frame_count;
    assert_int_equal(mm_clip_init(&cut, &clip.skeleton, end - begin, clip.fps, NULL), MM_OK);
    size_t n = (size_t)(end - begin) * (size_t)clip.skeleton.joint_count;
    memcpy(cut.rotations, mm_clip_rotations(&clip, begin), n * sizeof(mm_quat));
    memcpy(cut.positions, mm_clip_positions(&clip, begin), n * sizeof(mm_vec3));
    save_bvh(path, &cut);
    mm_clip_free(&clip);
    mm_clip_free(&cut);
}

static void test_lafan1(void **state)
{
    (void)state;
    char src[1024], dir[1024], a[1200], b[1200], files[4096];
    if (!mm_bin || !test_shared_data("lafan1/walk4_subject1.bvh", src, sizeof src)) skip();
    case_dir("lafan1", dir, sizeof dir);
    snprintf(a, sizeof a, "%s/walk4_subject1_cut.bvh", dir);
    cut_take(src, 0, 900, a); /* 30 s: standing, walking */
    test_shared_data("lafan1/multipleActions1_subject1.bvh", src, sizeof src);
    snprintf(b, sizeof b, "%s/multipleActions1_subject1_cut.bvh", dir);
    cut_take(src, 2900, 3500, b); /* 20 s: walking, then running */
    snprintf(files, sizeof files, "\"%s\" \"%s\"", a, b);
    static const expected e = {{"Hips", "Spine2", "Hips", "LeftFoot", "RightFoot", "LeftToe", "RightToe",
                                "LeftHand", "RightHand", "Head"},
                               {0, 1, 0},
                               1};
    init_and_build(dir, files, &e);
}

static void test_games105(void **state)
{
    (void)state;
    char src[1024], dir[1024], files[4096] = "";
    if (!mm_bin || !test_shared_data("games105", src, sizeof src)) skip();
    case_dir("games105", dir, sizeof dir);
    /* run_forward lists the joints in another order */
    static const char *const takes[] = {"walk_forward", "idle", "run_forward", "walk_and_turn_left"};
    for (size_t t = 0; t < sizeof takes / sizeof takes[0]; ++t) {
        size_t len = strlen(files);
        snprintf(files + len, sizeof files - len, " \"%s/%s.bvh\"", src, takes[t]);
    }
    static const expected e = {{"RootJoint", "lowerback_torso", "RootJoint", "lAnkle", "rAnkle", "lToeJoint",
                                "rToeJoint", "lWrist", "rWrist", "torso_head"},
                               {0, 0, 1},
                               1};
    init_and_build(dir, files, &e);
}

static void test_pfnn(void **state)
{
    (void)state;
    char src[1024], dir[1024], files[2048];
    if (!mm_bin || !test_shared_data("pfnn/bvh/LocomotionFlat09_000.bvh", src, sizeof src)) skip();
    case_dir("pfnn", dir, sizeof dir);
    snprintf(files, sizeof files, "\"%s\"", src);
    static const expected e = {{"Hips", "Spine1", "Hips", "LeftFoot", "RightFoot", "LeftToeBase",
                                "RightToeBase", "LeftHand", "RightHand", "Head"},
                               {0, 0, 1},
                               1};
    init_and_build(dir, files, &e);
}

/* ---- the pieces ------------------------------------------------------------------------- */

/* walk_start stands, then walks off: an idle span first, locomotion after, nothing left out. */
static void test_spans(void **state)
{
    (void)state;
    const mm_clip *c = synth_clip("walk_start");
    mm_take_spans s;
    const mm_take_joints joints = {
        mm_skeleton_find(&c->skeleton, "Hips"), mm_skeleton_find(&c->skeleton, "Spine2"),
        mm_skeleton_find(&c->skeleton, "Head"), mm_skeleton_find(&c->skeleton, "LeftHand"),
        mm_skeleton_find(&c->skeleton, "RightHand")};
    assert_int_equal(mm_take_spans_find(c, &joints, NULL, &s), MM_OK);
    assert_true(s.arms_found);
    assert_int_equal(s.excluded_count, 0);
    assert_int_equal(s.idle_count, 1);
    assert_int_equal(s.idle[0].begin, 0);
    assert_true(s.idle[0].end >= (int)c->fps);
    assert_int_equal(s.locomotion_count, 1);
    assert_int_equal(s.locomotion[0].begin, s.idle[0].end);
    assert_int_equal(s.locomotion[0].end, c->frame_count);
    mm_take_spans_free(&s);
    /* hips "lower" than 2 m (the deprecated rule): the whole take is left out */
    mm_take_spans_desc d;
    mm_take_spans_desc_defaults(&d);
    d.low_hips = 2.0f;
    assert_int_equal(mm_take_spans_find(c, &joints, &d, &s), MM_OK);
    assert_int_equal(s.excluded_count, 1);
    assert_int_equal(s.idle_count + s.locomotion_count, 0);
    mm_take_spans_free(&s);
    /* a needed joint out of range */
    mm_take_joints bad = joints;
    bad.head = 999;
    assert_int_equal(mm_take_spans_find(c, &bad, NULL, &s), MM_ERR_INVALID_ARGUMENT);
}

/* A config with every kind of field, written and read back. */
static void test_save_json(void **state)
{
    (void)state;
    mm_config c, back;
    mm_config_defaults(&c);
    c.scale = 0.01f;
    c.interval = 1.0f / 30.0f;
    snprintf(c.hips, MM_NAME_MAX, "pelvis");
    c.forward_axis = mm_vec3_make(0, 1, 0);
    c.contact_speed = 0.3f;
    c.contact_planted_tolerance = 0.02f;
    c.postures_pad = 0.5f;
    c.traj_count = 2;
    c.traj_times[0] = -0.3f;
    c.traj_times[1] = 0.6f;
    c.mirror_pair_count = 1;
    snprintf(c.mirror_pairs[0].left, MM_NAME_MAX, "^l");
    snprintf(c.mirror_pairs[0].right, MM_NAME_MAX, "^r");
    c.tag_count = 2;
    snprintf(c.tag_names[0], MM_TAG_NAME_MAX, "Walk");
    snprintf(c.tag_names[1], MM_TAG_NAME_MAX, "DoNotUse");
    c.runtime.set = MM_RUNTIME_SYNC_HALFLIFE | MM_RUNTIME_WARPING;
    c.runtime.sync_halflife = 0.1f;
    c.runtime.warping = true;
    c.runtime.run.set = MM_RUNTIME_FORWARD_SPEED;
    c.runtime.run.forward_speed = 3.05f;
    mm_config_clip clips[2];
    mm_config_range ranges[2] = {{0, 100}, {150, 300}};
    mm_config_tag_range tags[2] = {{1, 0.5f, 1.25f}, {0, 0.0f, 2.0f}};
    memset(clips, 0, sizeof clips);
    snprintf(clips[0].name, MM_NAME_MAX, "walk");
    snprintf(clips[0].file, MM_PATH_MAX, "takes/walk.bvh");
    clips[0].mirror = true;
    clips[0].range_count = 2;
    clips[0].ranges = ranges;
    clips[0].tag_range_count = 2;
    clips[0].tag_ranges = tags;
    snprintf(clips[1].name, MM_NAME_MAX, "rest");
    snprintf(clips[1].file, MM_PATH_MAX, "takes/all.fbx");
    snprintf(clips[1].take, MM_NAME_MAX, "Take 2");
    clips[1].type = MM_CLIP_IDLE;
    clips[1].loop = true;
    c.clips = clips;
    c.clip_count = 2;
    mm_config_blend blend = {"mix", 0, 1, 0.25f};
    c.blends = &blend;
    c.blend_count = 1;
    char path[1024];
    snprintf(path, sizeof path, "%s/config_init/saved.json", MM_TEST_OUT);
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_config_save_json(path, &c, &err), MM_OK);
    memset(&back, 0, sizeof back);
    assert_int_equal(mm_config_load_json(path, &back, NULL, &err), MM_OK);
    assert_float_equal(back.interval, c.interval, 0.0);
    assert_float_equal(back.scale, 0.01f, 0.0);
    assert_string_equal(back.hips, "pelvis");
    assert_float_equal(back.forward_axis.y, 1.0f, 0.0);
    assert_float_equal(back.contact_speed, 0.3f, 0.0);
    assert_float_equal(back.contact_planted_tolerance, 0.02f, 0.0);
    assert_float_equal(back.postures_pad, 0.5f, 0.0);
    assert_int_equal(back.traj_count, 2);
    assert_float_equal(back.traj_times[0], -0.3f, 0.0);
    assert_int_equal(back.bone_count, 3);
    assert_int_equal(back.bones[2].features, MM_MATCH_VELOCITY);
    assert_string_equal(back.mirror_pairs[0].left, "^l");
    assert_int_equal(back.mirror_pair_count, 1);
    assert_int_equal(back.tag_count, 2);
    assert_int_equal(back.runtime.set, c.runtime.set);
    assert_float_equal(back.runtime.sync_halflife, 0.1f, 0.0);
    assert_true(back.runtime.warping);
    assert_int_equal(back.runtime.run.set, MM_RUNTIME_FORWARD_SPEED);
    assert_float_equal(back.runtime.run.forward_speed, 3.05f, 0.0);
    assert_int_equal(back.runtime.walk.set, 0);
    assert_int_equal(back.clip_count, 2);
    assert_int_equal(back.clips[0].range_count, 2);
    assert_int_equal(back.clips[0].ranges[1].end, 300);
    assert_true(back.clips[0].mirror);
    assert_int_equal(back.clips[0].tag_range_count, 2);
    int donotuse = 0;
    for (int i = 0; i < 2; ++i)
        if (back.clips[0].tag_ranges[i].tag == 1) {
            assert_float_equal(back.clips[0].tag_ranges[i].end, 1.25f, 0.0);
            donotuse = 1;
        }
    assert_true(donotuse);
    assert_string_equal(back.clips[1].take, "Take 2");
    assert_int_equal(back.clips[1].type, MM_CLIP_IDLE);
    assert_true(back.clips[1].loop);
    assert_int_equal(back.clips[1].range_count, 0);
    assert_int_equal(back.blend_count, 1);
    assert_int_equal(back.blends[0].right, 1);
    assert_float_equal(back.blends[0].weight, 0.25f, 0.0);
    mm_config_free(&back);
}

/* An existing config is kept unless --force is given. */
static void test_no_overwrite(void **state)
{
    (void)state;
    if (!mm_bin) skip();
    char dir[1024], take[1200], config[1200], args[4096], log[1200];
    case_dir("overwrite", dir, sizeof dir);
    snprintf(take, sizeof take, "%s/walk.bvh", dir);
    save_bvh(take, synth_clip("walk_start"));
    snprintf(config, sizeof config, "%s/config.json", dir);
    FILE *f = fopen(config, "wb");
    assert_non_null(f);
    fputs("{}\n", f);
    fclose(f);
    snprintf(log, sizeof log, "%s/init.txt", dir);
    snprintf(args, sizeof args, "config init \"%s\" -o \"%s\"", take, config);
    assert_int_equal(run_mm(args, log), 1);
    struct stat st;
    assert_int_equal(stat(config, &st), 0);
    assert_int_equal(st.st_size, 3);
    snprintf(args, sizeof args, "config init \"%s\" -o \"%s\" --force --name-prefix p_ --no-tuning", take,
             config);
    assert_int_equal(run_mm(args, log), 0);
    mm_config cfg;
    mm_error err;
    memset(&err, 0, sizeof err);
    memset(&cfg, 0, sizeof cfg);
    assert_int_equal(mm_config_load_json(config, &cfg, NULL, &err), MM_OK);
    assert_string_equal(cfg.clips[0].name, "p_walk");
    assert_string_equal(cfg.clips[1].name, "p_walk_idle");
    assert_string_equal(cfg.clips[0].file, "walk.bvh"); /* beside the config */
    assert_int_equal(cfg.runtime.set, 0);               /* --no-tuning */
    assert_float_equal(cfg.contact_speed, 0.6f, 0.0);
    mm_config_free(&cfg);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_spans),       cmocka_unit_test(test_save_json),
        cmocka_unit_test(test_confidences), cmocka_unit_test(test_axes),
        cmocka_unit_test(test_axes_json),   cmocka_unit_test(test_no_overwrite),
        cmocka_unit_test(test_builtin_set), cmocka_unit_test(test_conventions),
        cmocka_unit_test(test_lafan1),      cmocka_unit_test(test_games105),
        cmocka_unit_test(test_pfnn),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
