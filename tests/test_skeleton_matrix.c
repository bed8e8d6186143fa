/* The matrix of skeletons (docs/skeletons.md): one dataset per run (argv[1]: builtin, lafan1,
 * games105, pfnn), a few short takes of it, and variants of them made at run time
 * (skeleton_variants.h, each checked by FK against the original before it is used): joints
 * renamed to each naming convention, re-rooted, rest axes rotated, other units, every rotation
 * order (all the same motion), and resampled to 30, 60 and 120 fps.
 *
 * For each FK-identical variant: mm_config_init on the takes as read back from BVH, the database
 * built from that config as it is, and compared with the original's: world joints within 0.1 mm,
 * features within 1e-4 of their group's scale, the speed envelopes within 1e-3 m/s; then characters on both
 * play the shipped scripts and must agree within 1 mm, or part at a tie that rounding decides (reported with
 * its tick). End to end through the CLI (mm config init, mm db build, mm simulate --metrics) on the original
 * and on each resampled variant: the runtime targets (docs/skeletons.md) on the scripts and two
 * random seeds, but for each dataset's known misses. Without MM_DATA_DIR only the built-in set
 * runs. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stddef.h>
#include <sys/stat.h>

#include <mm/bvh.h>
#include <mm/character.h>
#include <mm/config_init.h>
#include <mm/config_json.h>
#include <mm/database_build.h>
#include <mm/import.h>
#include <mm/input_json.h>
#include <mm/search.h>
#include <mm/synth.h>

#include "runtime/character/state.h"

#include "feet_ties.h"
#include "skeleton_variants.h"
#include "test_util.h"

#define SCRIPTS_DIR       MM_SOURCE_DIR "/scripts/input/"
#define CHARACTER_SECONDS 20.0f /* s of each script the characters of two databases play */
#define SIMULATE_SECONDS  20    /* s of mm simulate per script and seed */
#define SAME_JOINTS_M     1e-4  /* m: two databases' world joints */
#define SAME_CHARACTER_M  2e-3  /* m: two characters' world joints */
#define SAME_VELOCITY     1e-3  /* m/s, rad/s: the simulation bone's velocities */
#define PLAYHEAD_SAME     1e-4  /* frames: two playheads that agree to rounding */
#define NEAR_TIE          5e-3  /* relative difference of two winners' costs that is a tie */
#define LABELS_AHEAD      60    /* frames: the contact labels ahead of the playhead the feet look at */

/* The runtime targets (issue 21) */
#define TARGET_SLIDE_CM_S 2.0  /* foot_slide_cm_s below this */
#define TARGET_TRAJ_CM    5.0  /* traj_err_cm below this */
#define TARGET_POP_RATIO  1.25 /* max_pop_cm at most this times db_max_pop_cm */
#define TARGET_BELOW_CM   1.0  /* below_ground_cm at most this */

/* ---- datasets --------------------------------------------------------------------------------- */

typedef struct take_source {
    const char *file; /* under MM_DATA_DIR; for the built-in set the clip's name */
    int begin, end;   /* frames of the file; end 0: to its end */
} take_source;

typedef struct dataset {
    const char *name;
    take_source takes[16];
    const char *scripts[12]; /* the shipped scripts the runtime targets are measured on */
} dataset;

enum { T_SLIDE = 1, T_RAW = 2, T_TRAJ = 4, T_POP = 8, T_NAN = 16, T_BELOW = 32 };
static const char *const target_names[6] = {"slide", "raw slide", "trajectory", "pop", "NaN", "below ground"};

/* The runtime targets each dataset misses today on an input (a script, or random_N), on the
 * original takes or on any of their resampled variants (docs/skeletons.md has the figures): not
 * asserted there, printed; every other target on every input is asserted. A known miss that is
 * met is printed too. */
typedef struct known_miss {
    const char *dataset, *input;
    unsigned targets;
} known_miss;

static const known_miss known_misses[] = {
    {"builtin", "straight_run", T_POP},
    {"builtin", "stop_and_go", T_POP},
    {"builtin", "turn_180", T_POP},
    {"builtin", "walk_run", T_POP},
    {"builtin", "demo", T_POP},
    {"builtin", "random_1", T_POP},
    {"builtin", "random_2", T_POP},
    {"lafan1", "straight_run", T_POP},
    {"lafan1", "stop_and_go", T_POP},
    /* at 120 fps just over its bar (3.23 cm against 1.25 x 2.57) with the play rate kept across a
     * change of clip (docs/transitions.md, "Pops after the pose weighed back") */
    {"lafan1", "straight_walk", T_POP},
    {"lafan1", "turn_90", T_POP},
    {"lafan1", "turn_180", T_POP},
    /* at 120 fps just over its bar (3.22 cm against 1.25 x 2.57) */
    {"lafan1", "circle", T_POP},
    {"lafan1", "zigzag", T_POP},
    /* slide 1.72, 1.97, 2.87 and 4.94 cm/s as recorded and resampled to 30, 60 and 120 fps (met
     * as recorded and at 30 fps since the simulation stands with the idle): the cut's sidesteps end
     * in stops that the search plays while strafing at 1 m/s, not the rate (docs/skeletons.md, "The
     * strafe and the rates") */
    {"lafan1", "strafe", T_SLIDE | T_POP},
    {"lafan1", "walk_run", T_POP},
    {"lafan1", "demo", T_POP},
    {"lafan1", "random_1", T_POP},
    {"lafan1", "random_2", T_POP},
    {"games105", "turn_90", T_POP},
    {"games105", "random_1", T_POP},
    {"games105", "random_2", T_POP},
    /* 2.3-4.7 cm/s at every rate: the take's stances dragged through sharp turns and jumps that
     * keep a foot planted (docs/skeletons.md, "The PFNN take's random input") */
    {"pfnn", "random_1", T_SLIDE},
    {"pfnn", "random_2", T_SLIDE},
};

static unsigned known_missed(const char *dataset_name, const char *input)
{
    unsigned m = 0;
    for (size_t i = 0; i < sizeof known_misses / sizeof known_misses[0]; ++i)
        if (strcmp(known_misses[i].dataset, dataset_name) == 0 && strcmp(known_misses[i].input, input) == 0)
            m |= known_misses[i].targets;
    return m;
}

#define ALL_SCRIPTS                                                                                          \
    {                                                                                                        \
        "straight_walk", "straight_run", "stop_and_go", "turn_90", "turn_180", "circle", "zigzag", "strafe", \
            "walk_run", "demo"                                                                               \
    }
#define THREE_SCRIPTS                                                                                        \
    {                                                                                                        \
        "straight_walk", "turn_90", "stop_and_go"                                                            \
    }

static const dataset datasets[] = {
    {"builtin",
     {{"idle", 0, 0},
      {"walk_1.40", 0, 0},
      {"walk_start", 0, 0},
      {"walk_stop", 0, 0},
      {"run_3.80", 0, 0},
      {"turn_left_90", 0, 0},
      {"sidestep_right", 0, 0},
      {"walk_backward", 0, 0}},
     ALL_SCRIPTS},
    {"lafan1",
     {{"lafan1/multipleActions1_subject2.bvh", 2700, 3600},
      {"lafan1/multipleActions1_subject1.bvh", 2900, 3500}},
     ALL_SCRIPTS},
    {"games105",
     {{"games105/idle.bvh", 0, 0},
      {"games105/walk_and_turn_left.bvh", 0, 0},
      {"games105/walk_and_ture_right.bvh", 0, 0},
      {"games105/walkF.bvh", 0, 0}},
     THREE_SCRIPTS},
    {"pfnn", {{"pfnn/bvh/LocomotionFlat09_000.bvh", 0, 0}}, THREE_SCRIPTS},
};
#define DATASETS (int)(sizeof datasets / sizeof datasets[0])

#define MAX_TAKES 64

static const dataset *ds;
static int take_count;
static mm_clip originals[MAX_TAKES]; /* metres */
static char take_names[MAX_TAKES][MM_NAME_MAX];
/* the built-in set's runtime targets are on the whole set (what mm synth writes), the matrix on
 * the takes above */
static int whole_count;
static mm_clip whole_set[MAX_TAKES];
static char whole_names[MAX_TAKES][MM_NAME_MAX];
static double file_unit; /* metres per unit of the dataset's files */
static char out_dir[1024];
static const char *mm_bin;
/* MM_MATRIX_INPUTS, a comma list of inputs (scripts' names, random_1, random_2): the runtime targets
 * on those alone and the database comparison left out (a quick look at one miss); NULL: everything */
static const char *only_inputs;

/* Whether the input named tag runs (only_inputs). */
static int input_wanted(const char *tag)
{
    if (!only_inputs) return 1;
    size_t n = strlen(tag);
    for (const char *p = only_inputs; *p;) {
        size_t len = strcspn(p, ",");
        if (len == n && strncmp(p, tag, n) == 0) return 1;
        p += len + (p[len] == ',');
    }
    return 0;
}

/* ---- loading ---------------------------------------------------------------------------------- */

static void load_originals(void)
{
    take_count = 0;
    file_unit = 1.0;
    if (strcmp(ds->name, "builtin") == 0) {
        mm_synth_set set;
        assert_int_equal(mm_synth_generate(NULL, &set, NULL), MM_OK);
        assert_true(set.clip_count <= MAX_TAKES);
        for (whole_count = 0; whole_count < set.clip_count; ++whole_count) {
            assert_int_equal(mm_clip_copy(&whole_set[whole_count], &set.clips[whole_count].clip, NULL),
                             MM_OK);
            snprintf(whole_names[whole_count], MM_NAME_MAX, "%s", set.clips[whole_count].name);
        }
        for (; ds->takes[take_count].file; ++take_count) {
            snprintf(take_names[take_count], MM_NAME_MAX, "%s", ds->takes[take_count].file);
            int found = 0;
            for (int i = 0; i < set.clip_count && !found; ++i)
                if (strcmp(set.clips[i].name, ds->takes[take_count].file) == 0)
                    found = mm_clip_copy(&originals[take_count], &set.clips[i].clip, NULL) == MM_OK;
            assert_true(found);
        }
        mm_synth_set_free(&set);
        return;
    }
    for (; ds->takes[take_count].file; ++take_count) {
        const take_source *t = &ds->takes[take_count];
        const char *slash = strrchr(t->file, '/');
        snprintf(take_names[take_count], MM_NAME_MAX, "%.50s", slash ? slash + 1 : t->file);
        char *dot = strstr(take_names[take_count], ".bvh");
        if (dot) *dot = 0;
        char path[1024];
        assert_non_null(test_shared_data(t->file, path, sizeof path));
        mm_bvh bvh;
        mm_error err;
        memset(&err, 0, sizeof err);
        if (mm_bvh_load(path, NULL, &bvh, &err) != MM_OK) fail_msg("%s: %s", path, err.message);
        file_unit = mm_bvh_detect_scale(&bvh, NULL);
        assert_true(file_unit > 0.0);
        mm_bvh_import_desc imp;
        memset(&imp, 0, sizeof imp);
        imp.scale = (float)file_unit;
        mm_clip whole;
        assert_int_equal(mm_bvh_to_clip(&bvh, &imp, &whole, &err), MM_OK);
        mm_bvh_free(&bvh);
        int end = t->end > 0 && t->end < whole.frame_count ? t->end : whole.frame_count;
        mm_clip *c = &originals[take_count];
        assert_int_equal(mm_clip_init(c, &whole.skeleton, end - t->begin, whole.fps, NULL), MM_OK);
        size_t n = (size_t)(end - t->begin) * (size_t)whole.skeleton.joint_count;
        memcpy(c->rotations, mm_clip_rotations(&whole, t->begin), n * sizeof(mm_quat));
        memcpy(c->positions, mm_clip_positions(&whole, t->begin), n * sizeof(mm_vec3));
        mm_clip_free(&whole);
    }
}

/* ---- a variant's takes, config and database ----------------------------------------------------- */

typedef enum family { F_ORIGINAL, F_NAMES, F_ROOT, F_AXES, F_UNITS, F_ORDER, F_RATE, FAMILIES } family;

typedef struct variant_set {
    char label[64];
    char dir[1100];
    int take_count;
    const mm_clip *sources; /* [take_count] the originals */
    const char (*names)[MM_NAME_MAX];
    sv_variant takes[MAX_TAKES];
    double rounding; /* m: the largest FK distance of its takes from the originals */
    mm_config cfg;
    mm_database db;
    int built;
    char error[512];
} variant_set;

static void make_take(family f, int which, const mm_clip *src, sv_variant *v)
{
    static const double units[3] = {0.01, 1.0, 0.0254};
    static const float rates[3] = {30.0f, 60.0f, 120.0f};
    switch (f) {
    case F_ORIGINAL:
        sv_units(src, file_unit, v);
        break;
    case F_NAMES:
        sv_rename(src, (sv_naming)which, v);
        break;
    case F_ROOT:
        sv_reroot(src, (sv_root)which, v);
        break;
    case F_AXES:
        sv_rest_axes(src, which, v);
        break;
    case F_UNITS:
        sv_units(src, units[which], v);
        break;
    case F_ORDER:
        sv_rotation_order(src, (mm_euler_order)(MM_EULER_XYZ + which), v);
        break;
    default:
        sv_resample(src, rates[which], v);
        break;
    }
}

static void variant_label(family f, int which, char *out, size_t size)
{
    static const char *const units[3] = {"cm", "m", "inches"};
    static const char *const rates[3] = {"30 fps", "60 fps", "120 fps"};
    switch (f) {
    case F_ORIGINAL:
        snprintf(out, size, "original");
        break;
    case F_NAMES:
        snprintf(out, size, "names %s", sv_naming_names[which]);
        break;
    case F_ROOT:
        snprintf(out, size, "%s", sv_root_names[which]);
        break;
    case F_AXES:
        snprintf(out, size, "bones along %s", sv_axis_names[which]);
        break;
    case F_UNITS:
        snprintf(out, size, "units %s", units[which]);
        break;
    case F_ORDER:
        snprintf(out, size, "order %s", mm_euler_order_name((mm_euler_order)(MM_EULER_XYZ + which)));
        break;
    default:
        snprintf(out, size, "%s", rates[which]);
        break;
    }
}

/* The variant's takes written under out_dir (and read back, FK-checked); files: their paths
 * quoted for a command line. */
static void write_variant(family f, int which, int whole, variant_set *vs, char *files, size_t size)
{
    memset(vs, 0, sizeof *vs);
    vs->take_count = whole ? whole_count : take_count;
    vs->sources = whole ? whole_set : originals;
    vs->names = whole ? (const char(*)[MM_NAME_MAX])whole_names : (const char(*)[MM_NAME_MAX])take_names;
    variant_label(f, which, vs->label, sizeof vs->label);
    snprintf(vs->dir, sizeof vs->dir, "%s/%d_%d", out_dir, (int)f, which);
    mkdir(vs->dir, 0777);
    if (files) files[0] = 0;
    for (int t = 0; t < vs->take_count; ++t) {
        make_take(f, which, &vs->sources[t], &vs->takes[t]);
        char path[1400];
        snprintf(path, sizeof path, "%s/%s.bvh", vs->dir, vs->names[t]);
        sv_save_and_reload(&vs->sources[t], 1.0, &vs->takes[t], path);
        vs->rounding = fmax(vs->rounding, sv_fk_distance(&vs->sources[t], 1.0, &vs->takes[t]));
        if (files) {
            size_t len = strlen(files);
            snprintf(files + len, size - len, " \"%s\"", path);
        }
    }
}

/* mm_config_init on the variant's takes (file units, as mm config init reads them), then the
 * database built from the config as it is. */
static void build_variant(variant_set *vs)
{
    mm_config_init_take it[MAX_TAKES];
    static char paths[MAX_TAKES][1400];
    memset(it, 0, sizeof it);
    for (int t = 0; t < vs->take_count; ++t) {
        snprintf(paths[t], sizeof paths[t], "%s/%s.bvh", vs->dir, vs->names[t]);
        it[t].file = paths[t];
        it[t].clip = &vs->takes[t].clip;
    }
    mm_error err;
    memset(&err, 0, sizeof err);
    memset(&vs->cfg, 0, sizeof vs->cfg);
    if (mm_config_init(it, vs->take_count, NULL, &vs->cfg, NULL, &err) != MM_OK) {
        snprintf(vs->error, sizeof vs->error, "config init: %s", err.message);
        return;
    }
    mm_clip *sources = NULL;
    if (mm_config_load_sources(&vs->cfg, &sources, &err) != MM_OK) {
        snprintf(vs->error, sizeof vs->error, "sources: %s", err.message);
        return;
    }
    mm_result r = mm_database_build(&vs->cfg, sources, NULL, &vs->db, &err);
    mm_config_free_sources(&vs->cfg, sources);
    if (r != MM_OK) {
        snprintf(vs->error, sizeof vs->error, "db build: %s", err.message);
        return;
    }
    vs->built = 1;
}

static void free_variant(variant_set *vs)
{
    for (int t = 0; t < vs->take_count; ++t) sv_free(&vs->takes[t]);
    if (vs->built) mm_database_free(&vs->db);
    mm_config_free(&vs->cfg);
}

/* The joint of b's database that is joint j of a's (the reference: the original's), through
 * the variant's origins; the simulation bone by its name; -1 for none. */
static int match_joint(const variant_set *a, const variant_set *b, int j)
{
    const char *name = a->db.joints[j].name;
    const mm_skeleton *sa = &a->takes[0].clip.skeleton, *sb = &b->takes[0].clip.skeleton;
    int ka = mm_skeleton_find(sa, name);
    for (int k = 0; k < b->db.joint_count; ++k) {
        if (ka < 0) {
            if (strcmp(b->db.joints[k].name, name) == 0) return k;
            continue;
        }
        int kb = mm_skeleton_find(sb, b->db.joints[k].name);
        if (kb >= 0 && b->takes[0].origin[kb] == a->takes[0].origin[ka]) return k;
    }
    return -1;
}

typedef struct db_diff {
    int same_shape;     /* frames, clips, dims equal */
    double joints;      /* m */
    double features;    /* in units of the tolerance */
    int contacts, tags; /* frames whose contact labels, tags differ */
    int settings;       /* the runtime settings differ */
    int segments;       /* distance segments (kinds, frames) that differ, or their counts */
    double travelled;   /* m: distance curves (travelled, to the marker, the markers' travel) */
    double velocity;    /* m/s, rad/s: the simulation bone's velocities */
    double envelope;    /* m/s: the speed envelopes the builds measured (settings) */
    char worst_group[32];
    char worst_joint[160];
    char shape[256];
} db_diff;

static mm_skeleton skeleton_view(const mm_database *db)
{
    mm_skeleton s;
    s.joint_count = db->joint_count;
    s.joints = (mm_joint *)db->joints;
    memset(&s.allocator, 0, sizeof s.allocator);
    return s;
}

/* World joint positions (joints matched by origin) and features (in units of 1e-4 of their
 * group's scale plus what float rounding of the takes makes of it, as tests/test_roots.c). */
static db_diff compare_databases(const variant_set *a, const variant_set *b)
{
    db_diff d;
    memset(&d, 0, sizeof d);
    const mm_database *x = &a->db, *y = &b->db;
    if (x->frame_count != y->frame_count || x->clip_count != y->clip_count || x->dims != y->dims) {
        snprintf(d.shape, sizeof d.shape, "%d frames, %d clips, %d dims against %d, %d, %d", y->frame_count,
                 y->clip_count, y->dims, x->frame_count, x->clip_count, x->dims);
        return d;
    }
    d.same_shape = 1;
    int *match = malloc(sizeof(int) * (size_t)x->joint_count), matched = 0;
    for (int j = 0; j < x->joint_count; ++j) matched += (match[j] = match_joint(a, b, j)) >= 0;
    assert_int_equal(matched, x->joint_count);
    mm_skeleton sx = skeleton_view(x), sy = skeleton_view(y);
    mm_xform *gx = malloc(sizeof(mm_xform) * (size_t)x->joint_count);
    mm_xform *gy = malloc(sizeof(mm_xform) * (size_t)y->joint_count);
    for (int f = 0; f < x->frame_count; ++f) {
        mm_fk(&sx, mm_database_rotations(x, f), mm_database_positions(x, f), gx);
        mm_fk(&sy, mm_database_rotations(y, f), mm_database_positions(y, f), gy);
        for (int j = 0; j < x->joint_count; ++j) {
            double e = mm_vec3_distance(gx[j].translation, gy[match[j]].translation);
            if (e > d.joints) {
                int ci = x->frame_clip[f];
                snprintf(d.worst_joint, sizeof d.worst_joint, "%s in %s at frame %d", x->joints[j].name,
                         x->clips[ci].name, f - x->clips[ci].first_frame);
            }
            d.joints = fmax(d.joints, e);
        }
    }
    for (int f = 0; f < x->frame_count; ++f) {
        d.contacts += x->contacts[f] != y->contacts[f];
        d.tags += x->frame_tags[f] != y->frame_tags[f];
        d.travelled = fmax(d.travelled, fabs(x->distance_travelled[f] - y->distance_travelled[f]));
        d.travelled = fmax(d.travelled, fabs(x->distance_signed[f] - y->distance_signed[f]));
        d.velocity = fmax(d.velocity, mm_vec3_distance(x->root_velocity[f], y->root_velocity[f]));
        d.velocity = fmax(d.velocity, fabs(x->root_angular_velocity[f] - y->root_angular_velocity[f]));
    }
    /* the settings as the configs gave them, to the bit; the speed envelope measured from the root
     * velocities, within their tolerance */
    d.settings = memcmp(x->settings, y->settings, offsetof(mm_database_settings, envelope)) != 0;
    for (int g = 0; g < MM_SETTINGS_ENVELOPE_GAITS; ++g)
        for (int k = 0; k < MM_SETTINGS_ENVELOPE_BINS; ++k)
            d.envelope = fmax(d.envelope, fabs(x->settings->envelope[g][k] - y->settings->envelope[g][k]));
    if (x->distance_segment_count != y->distance_segment_count)
        d.segments = abs(x->distance_segment_count - y->distance_segment_count) + 1;
    else
        for (int k = 0; k < x->distance_segment_count; ++k) {
            const mm_distance_segment *u = &x->distance_segments[k], *v = &y->distance_segments[k];
            d.segments += u->first_frame != v->first_frame || u->frame_count != v->frame_count ||
                          u->marker_frame != v->marker_frame || u->kind != v->kind;
            d.travelled = fmax(d.travelled, fabs(u->marker_travelled - v->marker_travelled));
        }
    double rate = 1.0 / x->interval, rounding = fmax(a->rounding, b->rounding);
    for (int g = 0; g < x->group_count; ++g) {
        const mm_feature_group *grp = &x->groups[g];
        int kind = grp->kind;
        double reads = kind == MM_FEATURE_BONE_VELOCITY || kind == MM_FEATURE_ROOT_VELOCITY ? rate
                       : kind == MM_FEATURE_TRAJ_POSITION ? rate * grp->time + 1.0
                                                          : 1.0;
        double tolerance = 1e-4 * grp->scale + 8.0 * rounding * reads;
        for (int f = 0; f < x->frame_count; ++f)
            for (int k = grp->offset; k < grp->offset + grp->dims; ++k) {
                double e =
                    fabs(mm_database_feature_raw(x, f, k) - mm_database_feature_raw(y, f, k)) / tolerance;
                if (e > d.features)
                    snprintf(d.worst_group, sizeof d.worst_group, "group %d kind %d", g, kind);
                d.features = fmax(d.features, e);
            }
    }
    free(match);
    free(gx);
    free(gy);
    return d;
}

/* Where two characters' runs part, when their world joints end up SAME_CHARACTER_M apart: the
 * first tick at which their playheads (frame and fraction) differ by PLAYHEAD_SAME and the state
 * of both then. That parting is a tie that float rounding decides, reported rather than failed,
 * when
 *   - the playheads are at most one frame apart (the same frame with fractions 0 and almost 1, or
 *     neighbouring frames, or a fraction's drift): a playhead that lands on a whole frame (play
 *     rate 1, or the distance-matching limit) advances or not by the last bit of its fraction, and
 *     the play rates of distance matching carry the rounding of the database on; or
 *   - both searched and chose frames apart whose costs are within NEAR_TIE (a near tie); or
 *   - before it (or before the joints part, when the playheads never do) the frame playing or one
 *     of the LABELS_AHEAD after it had different contact labels in the two databases (the labels
 *     are thresholds that rounding flips on a frame that sits on one, and the feet's locks, their
 *     time to the next contact and the search's contact favour follow them): reported with the
 *     tick and the frame; or
 *   - before it (or before the joints part) a heel lock was released in one run and not in the
 *     other where it was unlock_radius from its animated ankle, within FEET_TIE (feet_unlock_tie,
 * tests/feet_ties.h); or
 *   - the playheads were, before they or the joints parted, either side of a whole frame (322 +
 *     0.99999 and 323 + 0): the labels of two frames, or a clip's last frame (where a jump is
 *     the search's winner) in one and the frame before it (where a jump that plants a swinging
 *     foot waits) in the other.
 * Anything else (another choice, or joints apart while the playheads and labels agree) fails. */
typedef enum parting_kind {
    PART_NONE,
    PART_NEAR_TIE,
    PART_PLAYHEAD,
    PART_LABELS,
    PART_UNLOCK,
    PART_OTHER
} parting_kind;
static const char *const parting_names[6] = {"",
                                             "near tie",
                                             "playheads a frame apart",
                                             "contact labels ahead differ",
                                             "a foot's lock at unlock_radius",
                                             "NOT A TIE"};

typedef struct parting {
    int apart;  /* the first tick at which world joints are SAME_CHARACTER_M apart */
    int tick;   /* the first tick at which the playheads differ by PLAYHEAD_SAME */
    int labels; /* the first tick at which the frames playing have different contact labels */
    int label_frame;
    int unlock; /* the first tick at which the feet's locks part at unlock_radius (feet_unlock_tie) */
    int whole;  /* the first tick at which playheads that agree are on two frames (either side of a
                   whole frame) */
    unsigned label_bits[2]; /* that frame's labels in each database */
    parting_kind kind;
    char state[256];
} parting;

/* Whether two characters searched from playheads either side of a whole frame (322 + 0.99999 and
 * 323 + 0), the one behind still there (it did not jump). */
static bool straddled(const mm_character c[2])
{
    int from[2] = {c[0].last_params.current_frame, c[1].last_params.current_frame};
    int behind = from[0] + 1 == from[1] ? 0 : from[1] + 1 == from[0] ? 1 : -1;
    return behind >= 0 && c[behind].frame == from[behind] && c[behind].frame_fraction >= 1.0 - PLAYHEAD_SAME;
}

/* Characters on both databases play the script: the largest distance of their world joints. */
static double run_characters(const variant_set *a, const variant_set *b, const char *script, parting *parted)
{
    const mm_database *dbs[2] = {&a->db, &b->db};
    mm_searcher s[2];
    mm_character c[2];
    for (int i = 0; i < 2; ++i) {
        mm_character_desc d;
        assert_int_equal(mm_character_desc_from_database(&d, dbs[i], NULL), MM_OK);
        assert_int_equal(mm_searcher_init(&s[i], dbs[i], NULL, NULL), MM_OK);
        assert_int_equal(mm_character_init(&c[i], dbs[i], &s[i], &d, NULL), MM_OK);
    }
    mm_input_script in;
    assert_int_equal(mm_input_script_load_json(script, &in, NULL), MM_OK);
    int *match = malloc(sizeof(int) * (size_t)a->db.joint_count);
    for (int j = 0; j < a->db.joint_count; ++j) match[j] = match_joint(a, b, j);
    double worst = 0.0;
    memset(parted, 0, sizeof *parted);
    parted->tick = parted->apart = parted->labels = parted->whole = parted->unlock = -1;
    for (int t = 0; t < (int)(CHARACTER_SECONDS * 60.0f); ++t) {
        mm_input input;
        mm_input_script_sample(&in, (float)t / 60.0f, &input);
        int searches[2] = {c[0].searches, c[1].searches};
        mm_vec3 held[2][2]; /* the heel locks before the tick */
        feet_ties_before(c, held);
        for (int i = 0; i < 2; ++i) mm_character_update(&c[i], &input, 1.0f / 60.0f);
        if (parted->unlock < 0) parted->unlock = feet_unlock_tie(c, held) ? t : -1;
        double now = 0.0;
        for (int j = 0; j < a->db.joint_count; ++j)
            if (match[j] >= 0)
                now = fmax(now,
                           mm_vec3_distance(c[0].global[j].translation, c[1].global[match[j]].translation));
        double x[2] = {c[0].frame + c[0].frame_fraction, c[1].frame + c[1].frame_fraction};
        for (int i = 0; i < 2 && parted->labels < 0; ++i) /* the labels the feet look at */
            for (int f = c[i].frame, n = 0; f >= 0 && n <= LABELS_AHEAD; f = a->db.frame_next[f], ++n)
                if (a->db.contacts[f] != b->db.contacts[f]) {
                    parted->labels = t;
                    parted->label_frame = f;
                    parted->label_bits[0] = a->db.contacts[f];
                    parted->label_bits[1] = b->db.contacts[f];
                    break;
                }
        if (parted->whole < 0 && c[0].frame != c[1].frame && fabs(x[0] - x[1]) <= PLAYHEAD_SAME)
            parted->whole = t; /* e.g. 322 + 0.99999 and 323 + 0: the labels of two frames */
        if (parted->tick < 0 && fabs(x[0] - x[1]) > PLAYHEAD_SAME) {
            int searched[2] = {c[0].searches > searches[0], c[1].searches > searches[1]};
            float cost[2] = {c[0].last_choice.cost, c[1].last_choice.cost}; /* priced */
            parted->tick = t;
            if (fabs(x[0] - x[1]) <= 1.0 + PLAYHEAD_SAME)
                parted->kind = PART_PLAYHEAD;
            else if (parted->labels >= 0)
                parted->kind = PART_LABELS;
            else if (parted->unlock >= 0)
                parted->kind = PART_UNLOCK;
            else if (parted->whole >= 0 || (searched[0] && searched[1] && straddled(c)))
                parted->kind =
                    PART_PLAYHEAD; /* e.g. a clip's last frame in one, the one before in the other */
            else if (searched[0] && searched[1])
                parted->kind = fabsf(cost[0] - cost[1]) <= NEAR_TIE * fmaxf(fabsf(cost[0]), fabsf(cost[1]))
                                   ? PART_NEAR_TIE
                                   : PART_OTHER;
            else
                parted->kind = PART_OTHER;
            snprintf(parted->state, sizeof parted->state,
                     "frames %d + %.4f and %d + %.4f, searched %d %d, costs %.4g %.4g, play rates %.5f %.5f",
                     c[0].frame, c[0].frame_fraction, c[1].frame, c[1].frame_fraction, searched[0],
                     searched[1], cost[0], cost[1], c[0].play_rate, c[1].play_rate);
        }
        if (parted->apart < 0 && now >= SAME_CHARACTER_M) parted->apart = t;
        worst = fmax(worst, now);
    }
    if (parted->apart >= 0 && parted->tick < 0) { /* the playheads agree: something else moved */
        parted->kind = parted->labels >= 0 && parted->labels <= parted->apart   ? PART_LABELS
                       : parted->unlock >= 0 && parted->unlock <= parted->apart ? PART_UNLOCK
                       : parted->whole >= 0 && parted->whole <= parted->apart   ? PART_PLAYHEAD
                                                                                : PART_OTHER;
        snprintf(parted->state, sizeof parted->state, "the playheads never part; joints apart at tick %d%s",
                 parted->apart,
                 parted->kind == PART_PLAYHEAD ? ", playheads either side of a whole frame before" : "");
    }
    if (parted->kind == PART_PLAYHEAD && parted->tick >= 0 && parted->whole >= 0) {
        size_t used = strlen(parted->state);
        snprintf(parted->state + used, sizeof parted->state - used,
                 "; playheads either side of a whole frame at tick %d", parted->whole);
    }
    if (parted->kind == PART_UNLOCK) {
        size_t used = strlen(parted->state);
        snprintf(parted->state + used, sizeof parted->state - used, "; a lock released at tick %d",
                 parted->unlock);
    }
    if (parted->kind == PART_LABELS) {
        size_t used = strlen(parted->state);
        snprintf(parted->state + used, sizeof parted->state - used,
                 "; labels differ from tick %d (frame %d: %u, %u)", parted->labels, parted->label_frame,
                 parted->label_bits[0], parted->label_bits[1]);
    }
    free(match);
    mm_input_script_free(&in);
    for (int i = 0; i < 2; ++i) {
        mm_character_free(&c[i]);
        mm_searcher_free(&s[i]);
    }
    return worst;
}

/* ---- the database matrix ---------------------------------------------------------------------- */

static int family_size(family f)
{
    switch (f) {
    case F_NAMES:
        return SV_NAMINGS;
    case F_ROOT:
        return SV_ROOTS;
    case F_AXES:
        return 4;
    case F_UNITS:
        return 3;
    case F_ORDER:
        return 6;
    case F_RATE:
        return 3;
    default:
        return 1;
    }
}

/* Differences the matrix finds today and docs/skeletons.md explains (bugs to fix, each with its
 * cause): printed as KNOWN and not counted; all others fail the test. level 'd': the database
 * differs; 'c': characters on script (NULL: any) part. */
typedef struct known_difference {
    const char *dataset, *variant;
    char level;
    const char *script;
} known_difference;

/* None today; an entry names a variant whose database (level 'd') or characters on a script ('c')
 * are known to differ, printed, not failed. */
static const known_difference known_differences[] = {
    {"", "", 0, NULL},
};

static int is_known(const char *variant, char level, const char *script)
{
    for (size_t i = 0; i < sizeof known_differences / sizeof known_differences[0]; ++i) {
        const known_difference *k = &known_differences[i];
        if (strcmp(k->dataset, ds->name) == 0 && strcmp(k->variant, variant) == 0 && k->level == level &&
            (!k->script || (script && strcmp(k->script, script) == 0)))
            return 1;
    }
    return 0;
}

static void test_same_database(void **state)
{
    (void)state;
    if (only_inputs) skip();
    variant_set *ref = calloc(1, sizeof *ref), *vs = calloc(1, sizeof *vs);
    write_variant(F_ORIGINAL, 0, 0, ref, NULL, 0);
    build_variant(ref);
    if (!ref->built) fail_msg("%s original: %s", ds->name, ref->error);
    print_message("%s: %d takes, database %d frames, %d clips\n", ds->name, take_count, ref->db.frame_count,
                  ref->db.clip_count);
    print_message("%-20s %-8s %-9s %-8s %-8s %s\n", "variant", "FK (m)", "joints(m)", "features", "contacts",
                  "database; characters on the scripts");
    int failures = 0, ties = 0;
    for (int f = F_NAMES; f < F_RATE; ++f)
        for (int w = 0; w < family_size((family)f); ++w) {
            write_variant((family)f, w, 0, vs, NULL, 0);
            build_variant(vs);
            db_diff d;
            memset(&d, 0, sizeof d);
            if (vs->built) d = compare_databases(ref, vs);
            /* contact labels and tags are printed, not asserted: a label is a threshold on a foot's
             * height and speed, and rounding flips one on a frame that sits on it */
            int same = vs->built && d.same_shape && d.joints < SAME_JOINTS_M && d.features <= 1.0 &&
                       !d.settings && d.segments == 0 && d.travelled < SAME_JOINTS_M &&
                       d.velocity < SAME_VELOCITY && d.envelope < SAME_VELOCITY;
            int known_db = is_known(vs->label, 'd', NULL);
            if (!same) failures += !known_db;
            if (!vs->built)
                print_message("%-20s %-8.1e FAILED%s: %s\n", vs->label, vs->rounding,
                              known_db ? " KNOWN" : "", vs->error);
            else if (!d.same_shape)
                print_message("%-20s %-8.1e DIFFERENT%s: %s\n", vs->label, vs->rounding,
                              known_db ? " KNOWN" : "", d.shape);
            else if (!same)
                print_message("%-20s %-8.1e %-9.1e %-8.2f %-8d DIFFERENT%s: joints worst at %s, features "
                              "worst in %s, tags %d frames, "
                              "settings %s, distance segments %d, curves %.2g m, root velocity %.2g, speed "
                              "envelope %.2g m/s\n",
                              vs->label, vs->rounding, d.joints, d.features, d.contacts,
                              known_db ? " KNOWN" : "", d.worst_joint, d.worst_group, d.tags,
                              d.settings ? "differ" : "same", d.segments, d.travelled, d.velocity,
                              d.envelope);
            if (same) {
                if (known_db) print_message("%-20s known database difference gone\n", vs->label);
                double within = 0.0;
                int parted_count = 0, k = 0;
                char lines[12][600];
                for (k = 0; k < 12 && ds->scripts[k]; ++k) {
                    char script[1024];
                    snprintf(script, sizeof script, SCRIPTS_DIR "%s.json", ds->scripts[k]);
                    parting parted;
                    double c = run_characters(ref, vs, script, &parted);
                    if (c < SAME_CHARACTER_M) {
                        within = fmax(within, c);
                        continue;
                    }
                    int k_known = is_known(vs->label, 'c', ds->scripts[k]);
                    snprintf(lines[parted_count++], sizeof lines[0],
                             "    %s: %.3g m, parted at tick %d: %s%s (%s)\n", ds->scripts[k], c, parted.tick,
                             parting_names[parted.kind], k_known ? " KNOWN" : "", parted.state);
                    failures += !k_known && parted.kind == PART_OTHER;
                    ties += parted.kind != PART_OTHER;
                }
                print_message("%-20s %-8.1e %-9.1e %-8.2f %-8d same%s; %d scripts within %.0e m%s\n",
                              vs->label, vs->rounding, d.joints, d.features, d.contacts,
                              d.tags ? " (tags differ)" : "", k - parted_count, within,
                              parted_count ? ", parted on:" : "");
                for (int i = 0; i < parted_count; ++i) print_message("%s", lines[i]);
            }
            free_variant(vs);
        }
    free_variant(ref);
    free(ref);
    free(vs);
    print_message("%s: %d runs parted at a tie (reported, not failed), %d differences that are not\n",
                  ds->name, ties, failures);
    assert_int_equal(failures, 0);
}

/* ---- end to end through the CLI, and the runtime targets --------------------------------------- */

static int run_mm(const char *args, const char *log)
{
    size_t size = strlen(mm_bin) + strlen(args) + strlen(log) + 16;
    char *cmd = malloc(size);
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

/* A number of the metrics JSON; NAN when null or missing. */
static double metric(const char *text, const char *key)
{
    char pattern[128];
    snprintf(pattern, sizeof pattern, "\"%s\":", key);
    const char *p = strstr(text, pattern);
    if (!p) return NAN;
    p += strlen(pattern);
    while (*p == ' ') ++p;
    if (strncmp(p, "null", 4) == 0) return NAN;
    return strtod(p, NULL);
}

/* mm simulate on the database with the input (a script's path or "--random N"); the targets that
 * failed (T_* bits), the figures into line. */
static unsigned simulate(const char *dir, const char *input, const char *tag, char *line, size_t size)
{
    char args[8192], log[1400], json[1400];
    snprintf(json, sizeof json, "%s/%s.json", dir, tag);
    snprintf(log, sizeof log, "%s/%s.txt", dir, tag);
    snprintf(args, sizeof args,
             "simulate \"%s/db.mmdb\" %s --seconds %d --metrics \"%s\" -o \"%s/sim_%s.bvh\"", dir, input,
             SIMULATE_SECONDS, json, dir, tag);
    if (run_mm(args, log) != 0) {
        print_file(log);
        fail_msg("%s: mm simulate failed", tag);
    }
    FILE *f = fopen(json, "rb");
    assert_non_null(f);
    static char text[1 << 16];
    size_t n = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[n] = 0;
    double slide = metric(text, "foot_slide_cm_s"), raw = metric(text, "foot_slide_raw_cm_s"),
           traj = metric(text, "traj_err_cm"), pop = metric(text, "max_pop_cm"),
           db_pop = metric(text, "db_max_pop_cm"), nan = metric(text, "nan_frames"),
           below = metric(text, "below_ground_cm");
    unsigned failed = 0;
    if (!(slide < TARGET_SLIDE_CM_S)) failed |= T_SLIDE;
    if (!(raw > 0.0)) failed |= T_RAW;
    if (!(traj < TARGET_TRAJ_CM)) failed |= T_TRAJ;
    if (!(pop <= TARGET_POP_RATIO * db_pop)) failed |= T_POP;
    if (!(nan == 0.0)) failed |= T_NAN;
    if (!(below <= TARGET_BELOW_CM)) failed |= T_BELOW;
    snprintf(line, size, "slide %5.2f (raw %5.1f) traj %4.2f pop %5.2f / db %5.2f below %4.2f nan %g", slide,
             raw, traj, pop, db_pop, below, nan);
    return failed;
}

static void failed_names(unsigned failed, char *out, size_t size)
{
    out[0] = 0;
    for (int i = 0; i < 6; ++i)
        if (failed & (1u << i)) {
            size_t len = strlen(out);
            snprintf(out + len, size - len, "%s%s", len ? ", " : "", target_names[i]);
        }
}

#define RANDOM_SEEDS 2

/* mm config init, mm db build and mm simulate on the takes of a variant set (original and resampled). */
static int cli_targets(family f, int which)
{
    variant_set *vs = calloc(1, sizeof *vs);
    static char files[1 << 16];
    static char args[(1 << 16) + 4096];
    char log[1400];
    int builtin = strcmp(ds->name, "builtin") == 0;
    write_variant(f, which, builtin, vs, files, sizeof files);
    if (builtin && f == F_ORIGINAL) { /* the whole set as mm synth writes it (the same motion) */
        snprintf(args, sizeof args, "synth \"%s\"", vs->dir);
        snprintf(log, sizeof log, "%s/synth.txt", vs->dir);
        assert_int_equal(run_mm(args, log), 0);
    }
    snprintf(args, sizeof args, "config init %s -o \"%s/config.json\" --force", files, vs->dir);
    snprintf(log, sizeof log, "%s/init.txt", vs->dir);
    if (run_mm(args, log) != 0) {
        print_file(log);
        fail_msg("%s %s: mm config init failed", ds->name, vs->label);
    }
    snprintf(args, sizeof args, "db build \"%s/config.json\" -o \"%s/db.mmdb\"", vs->dir, vs->dir);
    snprintf(log, sizeof log, "%s/build.txt", vs->dir);
    if (run_mm(args, log) != 0) {
        print_file(log);
        fail_msg("%s %s: mm db build failed", ds->name, vs->label);
    }
    int misses = 0;
    for (int k = 0; k < 12 + RANDOM_SEEDS; ++k) {
        char input[1100], tag[64];
        if (k < 12) {
            if (!ds->scripts[k]) continue;
            snprintf(input, sizeof input, "--input \"" SCRIPTS_DIR "%s.json\"", ds->scripts[k]);
            snprintf(tag, sizeof tag, "%s", ds->scripts[k]);
        } else {
            snprintf(input, sizeof input, "--random %d", k - 11);
            snprintf(tag, sizeof tag, "random_%d", k - 11);
        }
        if (!input_wanted(tag)) continue;
        char line[512], missed[128], met[128];
        unsigned failed = simulate(vs->dir, input, tag, line, sizeof line),
                 expected = known_missed(ds->name, tag);
        failed_names(failed & ~expected, missed, sizeof missed);
        failed_names(expected & ~failed, met, sizeof met);
        char known_text[128];
        failed_names(failed & expected, known_text, sizeof known_text);
        print_message("%-8s %-14s %s%s%s%s%s%s%s\n", vs->label, tag, line,
                      failed & expected ? "  known misses: " : "", known_text,
                      failed & ~expected ? "  MISSES: " : "", missed,
                      expected & ~failed ? "  known miss met: " : "", met);
        misses += (failed & ~expected) != 0;
    }
    free_variant(vs);
    free(vs);
    return misses;
}

static void test_runtime_targets(void **state)
{
    (void)state;
    if (!mm_bin) skip();
    int misses = cli_targets(F_ORIGINAL, 0);
    for (int w = 0; w < 3; ++w) misses += cli_targets(F_RATE, w);
    assert_int_equal(misses, 0);
}

/* ---- the generator's own checks ------------------------------------------------------------ */

/* The names each convention gives (by hand), and the FK check catching what a generator bug
 * would do: an offset 0.2 mm off, two joints' origins swapped, a resampled take a frame late. */
static void test_variant_checks(void **state)
{
    (void)state;
    static const char *const upleg[SV_NAMINGS] = {"LeftUpLeg",           "UpLeg_L",   "l_upleg", "LUpLeg",
                                                  "mixamorig:LeftUpLeg", "LeftUpLeg", "LeftHip"};
    static const char *const toe[SV_NAMINGS] = {
        "RightToe", "Toe_R", "r_toe", "RToe", "mixamorig:RightToeBase", "RightToeBase", "RightToe"};
    /* games105's style: lHip is the thigh, lAnkle the ankle */
    static const char *const ankle[SV_NAMINGS] = {"LeftAnkle",          "Ankle_L",  "l_ankle",  "LAnkle",
                                                  "mixamorig:LeftFoot", "LeftFoot", "LeftAnkle"};
    mm_skeleton s105;
    assert_int_equal(mm_skeleton_init(&s105, 3, NULL), MM_OK);
    snprintf(s105.joints[0].name, MM_NAME_MAX, "RootJoint");
    snprintf(s105.joints[1].name, MM_NAME_MAX, "lHip");
    snprintf(s105.joints[2].name, MM_NAME_MAX, "lAnkle");
    const mm_clip *walk = &originals[1];
    int j_upleg = mm_skeleton_find(&walk->skeleton, "LeftUpLeg"),
        j_toe = mm_skeleton_find(&walk->skeleton, "RightToe");
    assert_true(j_upleg >= 0 && j_toe >= 0);
    for (int n = 0; n < SV_NAMINGS; ++n) {
        char name[MM_NAME_MAX];
        sv_rename_joint(&walk->skeleton, j_upleg, (sv_naming)n, name);
        assert_string_equal(name, upleg[n]);
        sv_rename_joint(&walk->skeleton, j_toe, (sv_naming)n, name);
        assert_string_equal(name, toe[n]);
        sv_rename_joint(&s105, 2, (sv_naming)n, name);
        assert_string_equal(name, ankle[n]);
        sv_rename_joint(&s105, 0, (sv_naming)n, name);
        assert_string_equal(name, n == SV_NAMES_MIXAMO ? "mixamorig:RootJoint" : "RootJoint");
    }
    mm_skeleton_free(&s105);

    sv_variant *v = calloc(1, sizeof *v);
    sv_rename(walk, SV_NAMES_SUFFIX_LR, v);
    assert_true(sv_fk_distance(walk, 1.0, v) < 1e-6);
    for (int f = 0; f < v->clip.frame_count; ++f)
        mm_clip_positions(&v->clip, f)[j_upleg].x += 2e-4f; /* 0.2 mm */
    double d = sv_fk_distance(walk, 1.0, v);
    assert_true(d > SV_FK_TOLERANCE && d < 3e-4);
    for (int f = 0; f < v->clip.frame_count; ++f) mm_clip_positions(&v->clip, f)[j_upleg].x -= 2e-4f;
    int a = v->origin[j_upleg];
    v->origin[j_upleg] = v->origin[j_toe];
    v->origin[j_toe] = a;
    assert_true(sv_fk_distance(walk, 1.0, v) > 0.5); /* a thigh is not a toe */
    sv_free(v);
    sv_resample(walk, 30.0f, v);
    assert_true(sv_fk_distance(walk, 1.0, v) < 1e-5);
    mm_clip late;
    assert_int_equal(mm_clip_init(&late, &walk->skeleton, walk->frame_count - 1, walk->fps, NULL), MM_OK);
    size_t per = (size_t)walk->skeleton.joint_count;
    memcpy(late.rotations, walk->rotations + per, per * (size_t)late.frame_count * sizeof(mm_quat));
    memcpy(late.positions, walk->positions + per, per * (size_t)late.frame_count * sizeof(mm_vec3));
    assert_true(sv_fk_distance(&late, 1.0, v) > 0.01); /* a frame at 1.4 m/s: 2.3 cm */
    mm_clip_free(&late);
    sv_free(v);
    free(v);
}

/* ---- main ------------------------------------------------------------------------------------- */

static int setup(void **state)
{
    (void)state;
    load_originals();
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    for (int t = 0; t < take_count; ++t) mm_clip_free(&originals[t]);
    for (int t = 0; t < whole_count; ++t) mm_clip_free(&whole_set[t]);
    return 0;
}

int main(int argc, char **argv)
{
    const char *name = argc > 1 ? argv[1] : "builtin";
    for (int i = 0; i < DATASETS; ++i)
        if (strcmp(datasets[i].name, name) == 0) ds = &datasets[i];
    if (!ds) {
        fprintf(stderr, "usage: test_skeleton_matrix builtin|lafan1|games105|pfnn\n");
        return 2;
    }
    if (strcmp(name, "builtin") != 0) TEST_SKIP_WITHOUT_DATA_DIR();
    mm_bin = getenv("MM_BIN");
    only_inputs = getenv("MM_MATRIX_INPUTS");
    if (only_inputs && !only_inputs[0]) only_inputs = NULL;
    snprintf(out_dir, sizeof out_dir, "%s/skeleton_matrix", MM_TEST_OUT);
    mkdir(out_dir, 0777);
    snprintf(out_dir, sizeof out_dir, "%s/skeleton_matrix/%s", MM_TEST_OUT, name);
    mkdir(out_dir, 0777);
    const struct CMUnitTest builtin_tests[] = {
        cmocka_unit_test(test_variant_checks),
        cmocka_unit_test(test_same_database),
        cmocka_unit_test(test_runtime_targets),
    };
    if (strcmp(name, "builtin") == 0) return cmocka_run_group_tests(builtin_tests, setup, teardown);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_same_database),
        cmocka_unit_test(test_runtime_targets),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
