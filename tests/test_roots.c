/* Any root arrangement: whichever joint carries the travel (the hips, a root joint above them
 * that stands still, carries part or all of it, stays on the ground or turns, two of them), the
 * database is the same. Takes of the built-in set (and of LAFAN1 when MM_DATA_DIR is set) are
 * rewritten at run time so that their motion moves between those joints with the same world
 * joint positions (checked by FK); the databases built from them must agree: world joint
 * positions within 0.1 mm, features within 1e-4 of their group's scale, a character's run on an
 * input script within 1 mm. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>

#include <mm/character.h>
#include <mm/config_json.h>
#include <mm/database_build.h>
#include <mm/import.h>
#include <mm/input_json.h>
#include <mm/search.h>
#include <mm/synth.h>

#include "test_util.h"

typedef enum arrangement {
    HIPS,        /* as made: the hips carry the travel */
    STATIC_ROOT, /* a Root joint at the origin above the hips, not moving */
    PLACED_ROOT, /* a Root joint elsewhere, turned 40 degrees, not moving */
    PART_ROOT,   /* a Root carrying half the horizontal travel, the hips the rest */
    GROUND_ROOT, /* a Root on the ground under the hips, carrying the horizontal travel */
    YAW_ROOT,    /* a Root on the ground that turns too (the hips' yaw and a wobble) */
    ALL_ROOT,    /* a Root carrying all the travel (the hips only turn) */
    TWO_ROOTS,   /* Reference at the origin, a turning Root on the ground under it, the hips under that */
    ARRANGEMENTS
} arrangement;

static const char *const arrangement_names[ARRANGEMENTS] = {
    "hips", "static root", "placed root", "part root", "ground root", "yaw root", "all root", "two roots"};

static mm_quat yaw(float angle) { return mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), angle); }

/* The world transform of the joint right above the hips at frame f, given the hips' world. */
static mm_xform carrier(arrangement a, mm_xform hips, int f)
{
    mm_vec3 t = hips.translation, ground = mm_vec3_make(t.x, 0.0f, t.z);
    mm_vec3 z = mm_quat_rotate(hips.rotation, mm_vec3_make(0, 0, 1));
    float heading = atan2f(z.x, z.z);
    switch (a) {
    case PLACED_ROOT:
        return mm_xform_make(yaw(0.7f), mm_vec3_make(2.0f, 0.0f, -3.0f));
    case PART_ROOT:
        return mm_xform_make(mm_quat_identity(), mm_vec3_make(0.5f * t.x, 0.0f, 0.5f * t.z));
    case GROUND_ROOT:
        return mm_xform_make(mm_quat_identity(), ground);
    case YAW_ROOT:
        return mm_xform_make(yaw(heading + 0.3f * sinf(0.05f * (float)f)), ground);
    case ALL_ROOT:
        return mm_xform_make(mm_quat_identity(), t);
    case TWO_ROOTS:
        return mm_xform_make(yaw(-heading + 0.2f * cosf(0.03f * (float)f)), ground);
    default:
        return mm_xform_identity();
    }
}

/* src (whose root is the hips) with its motion moved as arrangement a says; prop: the joint
 * above the hips holds another child ("Prop", 10 cm above it), the last joint. Returns the
 * largest distance between a joint's world positions in src and out (float rounding). */
static double rearrange(const mm_clip *src, arrangement a, int prop, mm_clip *out)
{
    if (a == HIPS) {
        assert_int_equal(mm_clip_copy(out, src, NULL), MM_OK);
        return 0.0;
    }
    const mm_skeleton *s = &src->skeleton;
    int tops = a == TWO_ROOTS ? 2 : 1, jc = s->joint_count;
    int n = tops + jc + prop, moving = a != STATIC_ROOT && a != PLACED_ROOT;
    mm_skeleton ns;
    assert_int_equal(mm_skeleton_init(&ns, n, NULL), MM_OK);
    snprintf(ns.joints[0].name, MM_NAME_MAX, "%s", tops == 2 ? "Reference" : "Root");
    ns.joints[0].parent = -1;
    if (tops == 2) {
        snprintf(ns.joints[1].name, MM_NAME_MAX, "Root");
        ns.joints[1].parent = 0;
    }
    ns.joints[tops - 1].flags = moving ? MM_JOINT_TRANSLATES : 0;
    ns.joints[tops - 1].order = MM_EULER_ZYX;
    if (a == PLACED_ROOT) ns.joints[0].offset = mm_vec3_make(2.0f, 0.0f, -3.0f);
    for (int j = 0; j < jc; ++j) {
        ns.joints[tops + j] = s->joints[j];
        ns.joints[tops + j].parent = s->joints[j].parent < 0 ? tops - 1 : s->joints[j].parent + tops;
    }
    if (prop) {
        snprintf(ns.joints[n - 1].name, MM_NAME_MAX, "Prop");
        ns.joints[n - 1].parent = tops - 1;
        ns.joints[n - 1].offset = mm_vec3_make(0.0f, 0.1f, 0.0f);
    }
    assert_int_equal(mm_clip_init(out, &ns, src->frame_count, src->fps, NULL), MM_OK);
    mm_skeleton_free(&ns);
    for (int f = 0; f < src->frame_count; ++f) {
        const mm_quat *sr = mm_clip_rotations(src, f);
        const mm_vec3 *sp = mm_clip_positions(src, f);
        mm_quat *r = mm_clip_rotations(out, f);
        mm_vec3 *p = mm_clip_positions(out, f);
        mm_xform hips = mm_xform_make(sr[0], sp[0]), top = carrier(a, hips, f);
        r[tops - 1] = top.rotation;
        p[tops - 1] = top.translation;
        mm_xform local = mm_xform_mul(mm_xform_inverse(top), hips);
        memcpy(r + tops, sr, sizeof(mm_quat) * (size_t)jc);
        memcpy(p + tops, sp, sizeof(mm_vec3) * (size_t)jc);
        r[tops] = local.rotation;
        p[tops] = local.translation;
    }
    /* the same world joint positions */
    mm_xform *g = malloc(sizeof(mm_xform) * (size_t)jc), *h = malloc(sizeof(mm_xform) * (size_t)n);
    double worst = 0.0;
    for (int f = 0; f < src->frame_count; ++f) {
        mm_clip_fk(src, f, g);
        mm_clip_fk(out, f, h);
        for (int j = 0; j < jc; ++j)
            worst = fmax(worst, mm_vec3_distance(g[j].translation, h[tops + j].translation));
    }
    assert_true(worst < 2e-5);
    free(g);
    free(h);
    return worst;
}

/* The largest distance between two databases' world joint positions (joints matched by name;
 * joints of one only are skipped), and the largest difference of their features in units of the
 * tolerance: 1e-4 of the group's scale, plus what float rounding of the takes' world positions
 * makes of it. A rewritten take holds its world positions to rounding (an ulp or two of its
 * coordinates: the most FK of the rewritten takes differs from the originals'); velocities read
 * them 60 times a second, and trajectory positions past a clip's end carry the last velocity on
 * for up to a second. */
static void compare(const mm_database *a, const mm_database *b, double rounding, double *positions,
                    double *features)
{
    assert_int_equal(a->frame_count, b->frame_count);
    assert_int_equal(a->clip_count, b->clip_count);
    assert_int_equal(a->dims, b->dims);
    mm_skeleton sa, sb;
    assert_int_equal(mm_skeleton_init(&sa, a->joint_count, NULL), MM_OK);
    assert_int_equal(mm_skeleton_init(&sb, b->joint_count, NULL), MM_OK);
    memcpy(sa.joints, a->joints, sizeof(mm_joint) * (size_t)a->joint_count);
    memcpy(sb.joints, b->joints, sizeof(mm_joint) * (size_t)b->joint_count);
    int *match = malloc(sizeof(int) * (size_t)a->joint_count), matched = 0;
    for (int j = 0; j < a->joint_count; ++j)
        matched += (match[j] = mm_skeleton_find(&sb, a->joints[j].name)) >= 0;
    assert_true(matched >= 20);
    mm_xform *ga = malloc(sizeof(mm_xform) * (size_t)a->joint_count);
    mm_xform *gb = malloc(sizeof(mm_xform) * (size_t)b->joint_count);
    *positions = *features = 0.0;
    for (int f = 0; f < a->frame_count; ++f) {
        mm_fk(&sa, mm_database_rotations(a, f), mm_database_positions(a, f), ga);
        mm_fk(&sb, mm_database_rotations(b, f), mm_database_positions(b, f), gb);
        for (int j = 0; j < a->joint_count; ++j) {
            if (match[j] >= 0) {
                *positions = fmax(*positions, mm_vec3_distance(ga[j].translation, gb[match[j]].translation));
            }
        }
    }
    double rate = 1.0 / a->interval;
    for (int g = 0; g < a->group_count; ++g) {
        const mm_feature_group *grp = &a->groups[g];
        int kind = grp->kind;
        double reads = kind == MM_FEATURE_BONE_VELOCITY || kind == MM_FEATURE_ROOT_VELOCITY ? rate
                       : kind == MM_FEATURE_TRAJ_POSITION ? rate * grp->time + 1.0
                                                          : 1.0;
        double tolerance = 1e-4 * grp->scale + 8.0 * rounding * reads;
        for (int f = 0; f < a->frame_count; ++f)
            for (int d = grp->offset; d < grp->offset + grp->dims; ++d) {
                double da = mm_database_feature_raw(a, f, d), db = mm_database_feature_raw(b, f, d);
                *features = fmax(*features, fabs(da - db) / tolerance);
            }
    }
    free(match);
    free(ga);
    free(gb);
    mm_skeleton_free(&sa);
    mm_skeleton_free(&sb);
}

/* The largest distance between two characters' world joints (matched by name) over seconds of
 * the input script. */
static double run_characters(const mm_database *a, const mm_database *b, const char *script, float seconds)
{
    const mm_database *dbs[2] = {a, b};
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
    int *match = malloc(sizeof(int) * (size_t)a->joint_count);
    for (int j = 0; j < a->joint_count; ++j) {
        match[j] = -1;
        for (int k = 0; k < b->joint_count; ++k)
            if (strcmp(a->joints[j].name, b->joints[k].name) == 0) match[j] = k;
    }
    double worst = 0.0;
    for (int t = 0; t < (int)(seconds * 60.0f); ++t) {
        mm_input input;
        mm_input_script_sample(&in, (float)t / 60.0f, &input);
        for (int i = 0; i < 2; ++i) mm_character_update(&c[i], &input, 1.0f / 60.0f);
        for (int j = 0; j < a->joint_count; ++j)
            if (match[j] >= 0)
                worst = fmax(worst,
                             mm_vec3_distance(c[0].global[j].translation, c[1].global[match[j]].translation));
    }
    free(match);
    mm_input_script_free(&in);
    for (int i = 0; i < 2; ++i) {
        mm_character_free(&c[i]);
        mm_searcher_free(&s[i]);
    }
    return worst;
}

static void build(const mm_config *cfg, const mm_clip *sources, mm_database *db)
{
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_config given = *cfg;
    given.standing_make = false; /* the clips given, no standing pose made from them */
    mm_result r = mm_database_build(&given, sources, NULL, db, &err);
    if (r != MM_OK) print_error("%s\n", err.message);
    assert_int_equal(r, MM_OK);
}

/* Builds cfg from every arrangement of sources (each clip also with the arrangement of the next
 * clip: takes of one set that differ) and compares with the sources as they are. */
static void check_arrangements(const mm_config *cfg, const mm_clip *sources, const char *script)
{
    int n = cfg->clip_count;
    mm_database reference;
    build(cfg, sources, &reference);
    mm_clip *moved = calloc((size_t)n, sizeof(mm_clip));
    for (int a = 1; a <= ARRANGEMENTS; ++a) {
        double rounding = 0.0;
        for (int i = 0; i < n; ++i) /* the last round mixes them */
            rounding = fmax(rounding, rearrange(&sources[i],
                                                a < ARRANGEMENTS ? (arrangement)a
                                                                 : (arrangement)((3 * i + 2) % ARRANGEMENTS),
                                                0, &moved[i]));
        mm_database db;
        build(cfg, moved, &db);
        double positions, features;
        compare(&reference, &db, rounding, &positions, &features);
        double character = run_characters(&reference, &db, script, 4.0f);
        print_message(
            "%-12s rounding %.2g m: joints %.2g m, features %.2g of the tolerance, character %.2g m\n",
            a < ARRANGEMENTS ? arrangement_names[a] : "mixed", rounding, positions, features, character);
        assert_true(positions < 1e-4);
        assert_true(features <= 1.0);
        assert_true(character < 1e-3);
        mm_database_free(&db);
        for (int i = 0; i < n; ++i) mm_clip_free(&moved[i]);
    }
    free(moved);
    mm_database_free(&reference);
}

/* A root joint's other children hang from the simulation bone where they were in the world. */
static void test_other_children(void **state)
{
    (void)state;
    mm_synth_set set;
    assert_int_equal(mm_synth_generate(NULL, &set, NULL), MM_OK);
    const mm_clip *walk = NULL;
    for (int i = 0; i < set.clip_count; ++i)
        if (strcmp(set.clips[i].name, "walk_arc_left_r3.0") == 0) walk = &set.clips[i].clip;
    assert_non_null(walk);
    mm_clip moved;
    rearrange(walk, YAW_ROOT, 1, &moved);
    const char *text = "{\"scale\": 1, \"postures\": {\"detect\": false},"
                       " \"clips\": [{\"name\": \"walk\", \"file\": \"walk.bvh\", \"loop\": true}]}";
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    assert_int_equal(mm_config_parse_json(text, strlen(text), "roots", NULL, &cfg, NULL), MM_OK);
    mm_database db;
    build(&cfg, &moved, &db);
    assert_int_equal(db.frame_count, walk->frame_count);
    mm_skeleton s;
    assert_int_equal(mm_skeleton_init(&s, db.joint_count, NULL), MM_OK);
    memcpy(s.joints, db.joints, sizeof(mm_joint) * (size_t)db.joint_count);
    int prop = mm_skeleton_find(&s, "Prop"), hips = mm_skeleton_find(&s, "Hips");
    assert_int_equal(mm_skeleton_find(&s, "Root"), -1); /* folded into the simulation bone */
    assert_int_equal(s.joints[prop].parent, 0);
    assert_int_equal(s.joints[hips].parent, 0);
    mm_xform g[64], h[64];
    double worst = 0.0;
    for (int f = 0; f < db.frame_count; ++f) {
        mm_fk(&s, mm_database_rotations(&db, f), mm_database_positions(&db, f), g);
        mm_clip_fk(&moved, f, h);
        worst =
            fmax(worst, mm_vec3_distance(g[prop].translation, h[moved.skeleton.joint_count - 1].translation));
    }
    assert_true(worst < 1e-5);
    mm_skeleton_free(&s);
    mm_database_free(&db);
    mm_config_free(&cfg);
    mm_clip_free(&moved);
    mm_synth_set_free(&set);
}

/* The roles may name a joint above the hips: a Root on the ground under the hips as root_bone
 * gives the database that the hips as root_bone give the take without it. */
static void test_roles_above(void **state)
{
    (void)state;
    const char *names[2] = {"walk_arc_left_r3.0", "turn_left_90"};
    const char *text = "{\"scale\": 1, \"roles\": {\"root_bone\": \"%s\"}, \"clips\": ["
                       "{\"name\": \"a\", \"file\": \"a.bvh\", \"loop\": true, \"mirror\": true},"
                       "{\"name\": \"b\", \"file\": \"b.bvh\", \"mirror\": true}]}";
    mm_synth_set set;
    assert_int_equal(mm_synth_generate(NULL, &set, NULL), MM_OK);
    mm_clip sources[2], moved[2];
    double rounding = 0.0;
    for (int i = 0; i < 2; ++i) {
        for (int k = 0; k < set.clip_count; ++k)
            if (strcmp(set.clips[k].name, names[i]) == 0)
                assert_int_equal(mm_clip_copy(&sources[i], &set.clips[k].clip, NULL), MM_OK);
        rounding = fmax(rounding, rearrange(&sources[i], GROUND_ROOT, 0, &moved[i]));
    }
    mm_synth_set_free(&set);
    mm_config cfg[2];
    mm_database db[2];
    const char *root_bone[2] = {"Hips", "Root"};
    for (int v = 0; v < 2; ++v) {
        char json[1024];
        snprintf(json, sizeof json, text, root_bone[v]);
        memset(&cfg[v], 0, sizeof cfg[v]);
        assert_int_equal(mm_config_parse_json(json, strlen(json), "roots", NULL, &cfg[v], NULL), MM_OK);
        build(&cfg[v], v ? moved : sources, &db[v]);
    }
    double positions, features;
    compare(&db[0], &db[1], rounding, &positions, &features);
    double character = run_characters(&db[0], &db[1], MM_SOURCE_DIR "/scripts/input/turn_90.json", 4.0f);
    print_message("root_bone Root: joints %.2g m, features %.2g of the tolerance, character %.2g m\n",
                  positions, features, character);
    assert_true(positions < 1e-4);
    assert_true(features <= 1.0);
    assert_true(character < 1e-3);
    for (int v = 0; v < 2; ++v) {
        mm_database_free(&db[v]);
        mm_config_free(&cfg[v]);
        mm_clip_free(&sources[v]);
        mm_clip_free(&moved[v]);
    }
}

static void test_synth(void **state)
{
    (void)state;
    const char *names[] = {"idle",      "walk_1.40",    "run_arc_left_r4.0",
                           "walk_stop", "turn_left_90", "sidestep_right"};
    const char *text =
        "{\"scale\": 1, \"tags\": [\"Walk\"], \"clips\": ["
        "{\"name\": \"idle\", \"file\": \"idle.bvh\", \"type\": \"idle\", \"loop\": true},"
        "{\"name\": \"walk_1.40\", \"file\": \"w.bvh\", \"loop\": true, \"mirror\": true, \"tags\": "
        "{\"Walk\": [[0, 1]]}},"
        "{\"name\": \"run_arc_left_r4.0\", \"file\": \"r.bvh\", \"loop\": true, \"mirror\": true},"
        "{\"name\": \"walk_stop\", \"file\": \"s.bvh\"},"
        "{\"name\": \"turn_left_90\", \"file\": \"t.bvh\", \"mirror\": true},"
        "{\"name\": \"sidestep_right\", \"file\": \"d.bvh\", \"mirror\": true}]}";
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    mm_error err;
    assert_int_equal(mm_config_parse_json(text, strlen(text), "roots", NULL, &cfg, &err), MM_OK);
    mm_synth_set set;
    assert_int_equal(mm_synth_generate(NULL, &set, NULL), MM_OK);
    mm_clip sources[6];
    for (int i = 0; i < 6; ++i) {
        const mm_clip *found = NULL;
        for (int k = 0; k < set.clip_count; ++k)
            if (strcmp(set.clips[k].name, names[i]) == 0) found = &set.clips[k].clip;
        assert_non_null(found);
        assert_int_equal(mm_clip_copy(&sources[i], found, NULL), MM_OK);
    }
    mm_synth_set_free(&set);
    check_arrangements(&cfg, sources, MM_SOURCE_DIR "/scripts/input/turn_90.json");
    for (int i = 0; i < 6; ++i) mm_clip_free(&sources[i]);
    mm_config_free(&cfg);
}

/* LAFAN1's walk4_subject1, its first 20 s in two clips (30 fps, resampled to 60: the arrangement
 * must not change what the splines read), mirrored. */
static void test_lafan1(void **state)
{
    (void)state;
    char path[1024];
    if (!test_shared_data("lafan1/walk4_subject1.bvh", path, sizeof path)) skip();
    char text[4096];
    snprintf(text, sizeof text,
             "{\"extends\": \"%s/configs/mocap.json\", \"clips\": ["
             "{\"name\": \"a\", \"file\": \"%s\", \"ranges\": [[0, 300]], \"mirror\": true},"
             "{\"name\": \"b\", \"file\": \"%s\", \"ranges\": [[300, 600]], \"mirror\": true}]}",
             MM_SOURCE_DIR, path, path);
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    mm_error err;
    memset(&err, 0, sizeof err);
    if (mm_config_parse_json(text, strlen(text), "roots", MM_SOURCE_DIR, &cfg, &err) != MM_OK)
        fail_msg("%s", err.message);
    mm_clip *sources = NULL;
    assert_int_equal(mm_config_load_sources(&cfg, &sources, &err), MM_OK);
    check_arrangements(&cfg, sources, MM_SOURCE_DIR "/scripts/input/straight_walk.json");
    mm_config_free_sources(&cfg, sources);
    mm_config_free(&cfg);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_other_children),
        cmocka_unit_test(test_roles_above),
        cmocka_unit_test(test_synth),
        cmocka_unit_test(test_lafan1),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
