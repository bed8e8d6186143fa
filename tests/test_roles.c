/* Roles reach every layer: the runtime takes its joints (the feet of foot locking, IK and
 * warping, the hands and feet of moves) from the database's bone roles, not from joint names.
 * The built-in set with every joint renamed (LeftFoot -> b_toof_sx, Hips -> b_spih: names that
 * match none of the default joint names), its config's roles, matched bones and mirror pairs
 * renamed the same way, builds a database on which a character moves bit for bit as on the
 * original, whatever desc it is given (the defaults, or the database's own settings). A database
 * without roles (no settings: one built by hand) falls back to the default joint names
 * (mm_role_default_name), the one place they are written. */
#include "test_util.h"

#include <mm/character.h>
#include <mm/config.h>
#include <mm/config_json.h>
#include <mm/database.h>
#include <mm/database_build.h>
#include <mm/input.h>
#include <mm/input_json.h>
#include <mm/moves.h>
#include <mm/search.h>
#include <mm/synth.h>

#include <ctype.h>

/* simulated seconds per run */
#define RUN_SECONDS 24.0f
#define TICK        (1.0f / 60.0f)

/* The new name of a joint: Left / Right as a suffix _sx / _dx, the rest reversed and lowercased,
 * after "b_" (LeftFoot -> b_toof_sx, Hips -> b_spih). */
static void renamed(const char *name, char out[MM_NAME_MAX])
{
    const char *side = "";
    if (strncmp(name, "Left", 4) == 0) name += 4, side = "_sx";
    if (strncmp(name, "Right", 5) == 0) name += 5, side = "_dx";
    size_t n = strlen(name), at = 0;
    out[at++] = 'b', out[at++] = '_';
    for (size_t i = 0; i < n && at + 4 < MM_NAME_MAX; ++i)
        out[at++] = (char)tolower((unsigned char)name[n - 1 - i]);
    for (size_t i = 0; side[i]; ++i) out[at++] = side[i];
    out[at] = '\0';
}

static void rename_field(char *name)
{
    if (!name[0]) return;
    char out[MM_NAME_MAX];
    renamed(name, out);
    memcpy(name, out, MM_NAME_MAX);
}

typedef struct pair {
    mm_database db[2]; /* the original and the renamed set */
} pair;

/* The built-in set and configs/synth.json, as they are (db[0]) and renamed (db[1]). */
static void build_pair(pair *p)
{
    mm_synth_set set;
    assert_int_equal(mm_synth_generate(NULL, &set, NULL), MM_OK);
    mm_config cfg;
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_result r = mm_config_load_json(MM_SOURCE_DIR "/configs/synth.json", &cfg, NULL, &err);
    if (r != MM_OK) print_error("%s\n", err.message);
    assert_int_equal(r, MM_OK);
    mm_clip *sources = calloc((size_t)cfg.clip_count, sizeof(mm_clip));
    assert_non_null(sources);
    for (int i = 0; i < cfg.clip_count; ++i) {
        int found = -1;
        for (int k = 0; k < set.clip_count; ++k) {
            char file[MM_NAME_MAX + 8];
            snprintf(file, sizeof file, "%s.bvh", set.clips[k].name);
            if (strcmp(file, cfg.clips[i].file) == 0) found = k;
        }
        assert_true(found >= 0);
        assert_int_equal(mm_clip_copy(&sources[i], &set.clips[found].clip, NULL), MM_OK);
    }
    mm_synth_set_free(&set);
    for (int v = 0; v < 2; ++v) {
        if (v == 1) { /* every joint renamed, and the config with it (as mm config init writes it) */
            for (int i = 0; i < cfg.clip_count; ++i)
                for (int j = 0; j < sources[i].skeleton.joint_count; ++j)
                    rename_field(sources[i].skeleton.joints[j].name);
            char *roles[] = {cfg.hips,     cfg.root_bone, cfg.facing_bone, cfg.left_foot,  cfg.right_foot,
                             cfg.left_toe, cfg.right_toe, cfg.left_hand,   cfg.right_hand, cfg.head};
            for (size_t k = 0; k < sizeof roles / sizeof roles[0]; ++k) rename_field(roles[k]);
            for (int b = 0; b < cfg.bone_count; ++b) rename_field(cfg.bones[b].name);
            cfg.mirror_pair_count = 1;
            snprintf(cfg.mirror_pairs[0].left, MM_NAME_MAX, "_sx");
            snprintf(cfg.mirror_pairs[0].right, MM_NAME_MAX, "_dx");
        }
        r = mm_database_build(&cfg, sources, NULL, &p->db[v], &err);
        if (r != MM_OK) print_error("%s\n", err.message);
        assert_int_equal(r, MM_OK);
    }
    for (int i = 0; i < cfg.clip_count; ++i) mm_clip_free(&sources[i]);
    free(sources);
    mm_config_free(&cfg);
    /* the same joints, none of them under a default name in the renamed set */
    const mm_database *a = &p->db[0], *b = &p->db[1];
    assert_int_equal(a->joint_count, b->joint_count);
    assert_int_equal(a->frame_count, b->frame_count);
    for (int j = 1; j < b->joint_count; ++j) { /* 0: the simulation bone the build adds */
        assert_string_not_equal(a->joints[j].name, b->joints[j].name);
        for (int k = 0; k < MM_ROLE_COUNT; ++k)
            assert_string_not_equal(b->joints[j].name, mm_role_default_name((mm_role)k));
    }
    assert_non_null(a->settings);
    assert_non_null(b->settings);
    for (int k = 0; k < MM_ROLE_COUNT; ++k) {
        assert_true(a->settings->roles[k] > 0);
        assert_int_equal(a->settings->roles[k], b->settings->roles[k]);
    }
}

static void free_pair(pair *p)
{
    for (int v = 0; v < 2; ++v) mm_database_free(&p->db[v]);
}

/* How a run's character desc is made. */
typedef enum desc_kind {
    DESC_DEFAULTS,      /* mm_character_defaults: no joint named */
    DESC_FROM_DATABASE, /* mm_character_desc_from_database */
    DESC_WARPED         /* the defaults with distance matching and warping on */
} desc_kind;

/* Runs a character on each database of p over the zigzag script and asserts that their poses
 * are the same bits on every tick; the feet are the database's foot roles and foot locking
 * holds them. */
static void run_both(const pair *p, desc_kind kind)
{
    mm_input_script in;
    assert_int_equal(mm_input_script_load_json(MM_SOURCE_DIR "/scripts/input/zigzag.json", &in, NULL), MM_OK);
    mm_searcher s[2];
    mm_character c[2];
    for (int v = 0; v < 2; ++v) {
        mm_character_desc d;
        if (kind == DESC_FROM_DATABASE)
            assert_int_equal(mm_character_desc_from_database(&d, &p->db[v], NULL), MM_OK);
        else
            mm_character_defaults(&d);
        if (kind == DESC_WARPED) d.distance_matching = d.warping = true;
        assert_int_equal(mm_searcher_init(&s[v], &p->db[v], NULL, NULL), MM_OK);
        assert_int_equal(mm_character_init(&c[v], &p->db[v], &s[v], &d, NULL), MM_OK);
        const int32_t *roles = p->db[v].settings->roles;
        assert_int_equal(c[v].foot_joint[0], roles[MM_ROLE_LEFT_FOOT]);
        assert_int_equal(c[v].foot_joint[1], roles[MM_ROLE_RIGHT_FOOT]);
        assert_int_equal(c[v].toe_joint[0], roles[MM_ROLE_LEFT_TOE]);
        assert_int_equal(c[v].toe_joint[1], roles[MM_ROLE_RIGHT_TOE]);
    }
    int n = p->db[0].joint_count, locked = 0, ticks = (int)(RUN_SECONDS / TICK), differ = -1;
    for (int t = 0; t < ticks; ++t) {
        mm_input input;
        mm_input_script_sample_tick(&in, (float)(t + 1) * TICK, TICK, &input);
        for (int v = 0; v < 2; ++v) mm_character_update(&c[v], &input, TICK);
        if (differ < 0 && memcmp(c[0].global, c[1].global, sizeof(mm_xform) * (size_t)n) != 0) differ = t;
        locked += c[0].foot_locked[0] + c[0].foot_locked[1];
    }
    print_message("desc %d: %d ticks, feet held on %d foot-ticks, first tick that differs: %d\n", (int)kind,
                  ticks, locked, differ);
    assert_int_equal(differ, -1);
    assert_true(locked > ticks / 4); /* foot locking is on: the feet were found */
    for (int v = 0; v < 2; ++v) {
        mm_character_free(&c[v]);
        mm_searcher_free(&s[v]);
    }
    mm_input_script_free(&in);
}

static void test_renamed_moves_alike(void **state)
{
    (void)state;
    pair p;
    build_pair(&p);
    run_both(&p, DESC_DEFAULTS);
    run_both(&p, DESC_FROM_DATABASE);
    run_both(&p, DESC_WARPED);
    /* moves: the hands and feet of the roles, from the defaults as from the database */
    for (int v = 0; v < 2; ++v)
        for (int from_db = 0; from_db < 2; ++from_db) {
            mm_moves_desc d;
            if (from_db)
                mm_moves_desc_from_database(&d, &p.db[v]);
            else
                mm_moves_defaults(&d);
            mm_moves m;
            assert_int_equal(mm_moves_init(&m, &p.db[v], NULL, &d, NULL), MM_OK);
            const int32_t *roles = p.db[v].settings->roles;
            assert_int_equal(m.hand[0], roles[MM_ROLE_LEFT_HAND]);
            assert_int_equal(m.hand[1], roles[MM_ROLE_RIGHT_HAND]);
            assert_int_equal(m.foot[0], roles[MM_ROLE_LEFT_FOOT]);
            assert_int_equal(m.foot[1], roles[MM_ROLE_RIGHT_FOOT]);
            assert_int_equal(m.toe[0], roles[MM_ROLE_LEFT_TOE]);
            assert_int_equal(m.toe[1], roles[MM_ROLE_RIGHT_TOE]);
        }
    free_pair(&p);
}

/* Precedence: a joint a desc names wins over the role; a database without settings falls back to
 * the default names; mm_database_role_joint says the same. */
static void test_precedence_and_fallback(void **state)
{
    (void)state;
    pair p;
    build_pair(&p);
    const int32_t *roles = p.db[0].settings->roles;
    int left = roles[MM_ROLE_LEFT_FOOT], right = roles[MM_ROLE_RIGHT_FOOT];
    for (int v = 0; v < 2; ++v)
        for (int k = 0; k < MM_ROLE_COUNT; ++k)
            assert_int_equal(mm_database_role_joint(&p.db[v], (mm_role)k), roles[k]);

    /* the feet named the other way round: the names win */
    mm_character_desc d;
    mm_character_defaults(&d);
    d.left_foot = p.db[1].joints[right].name;
    d.right_foot = p.db[1].joints[left].name;
    mm_searcher s;
    mm_character c;
    assert_int_equal(mm_searcher_init(&s, &p.db[1], NULL, NULL), MM_OK);
    assert_int_equal(mm_character_init(&c, &p.db[1], &s, &d, NULL), MM_OK);
    assert_int_equal(c.foot_joint[0], right);
    assert_int_equal(c.foot_joint[1], left);
    mm_character_free(&c);
    /* a name that names no joint: no foot (the name is not second-guessed) */
    d.left_foot = "NoSuchJoint";
    assert_int_equal(mm_character_init(&c, &p.db[1], &s, &d, NULL), MM_OK);
    assert_int_equal(c.foot_joint[0], -1);
    assert_int_equal(c.foot_joint[1], left);
    mm_character_free(&c);
    mm_searcher_free(&s);

    /* without settings (a database made in code): the default names, found in the original set
     * only */
    for (int v = 0; v < 2; ++v) {
        mm_database bare = p.db[v];
        bare.settings = NULL;
        for (int k = 0; k < MM_ROLE_COUNT; ++k)
            assert_int_equal(mm_database_role_joint(&bare, (mm_role)k), v == 0 ? roles[k] : -1);
        mm_character_defaults(&d);
        assert_int_equal(mm_searcher_init(&s, &bare, NULL, NULL), MM_OK);
        assert_int_equal(mm_character_init(&c, &bare, &s, &d, NULL), MM_OK);
        assert_int_equal(c.foot_joint[0], v == 0 ? left : -1);
        assert_int_equal(c.foot_joint[1], v == 0 ? right : -1);
        mm_character_free(&c);
        mm_searcher_free(&s);
        mm_moves_desc md;
        mm_moves_defaults(&md);
        mm_moves m;
        assert_int_equal(mm_moves_init(&m, &bare, NULL, &md, NULL), MM_OK);
        assert_int_equal(m.hand[0], v == 0 ? roles[MM_ROLE_LEFT_HAND] : -1);
        assert_int_equal(m.foot[1], v == 0 ? right : -1);
    }
    free_pair(&p);
}

/* The toe of an ankle: the toe role where it hangs from the ankle, else the ankle's first child;
 * the default names without settings. A hand-made database of joints only. */
static void test_toe_joint(void **state)
{
    (void)state;
    /* root, hips, knee, ankle, heel (the ankle's first child), ball (its second), a leaf */
    enum { ROOT, HIPS, KNEE, ANKLE, HEEL, BALL, LEAF, COUNT };
    const int parents[COUNT] = {-1, ROOT, HIPS, KNEE, ANKLE, ANKLE, HIPS};
    const char *names[COUNT] = {"root", "pelvis", "knee", "ankle", "heel", "ball", "leaf"};
    mm_joint joints[COUNT];
    memset(joints, 0, sizeof joints);
    for (int j = 0; j < COUNT; ++j) {
        joints[j].parent = parents[j];
        snprintf(joints[j].name, MM_NAME_MAX, "%s", names[j]);
    }
    mm_database_settings settings;
    memset(&settings, 0, sizeof settings);
    for (int k = 0; k < MM_ROLE_COUNT; ++k) settings.roles[k] = -1;
    settings.roles[MM_ROLE_LEFT_FOOT] = ANKLE;
    settings.roles[MM_ROLE_LEFT_TOE] = BALL;
    settings.roles[MM_ROLE_RIGHT_TOE] = LEAF; /* not under the ankle */
    mm_database db;
    memset(&db, 0, sizeof db);
    db.joints = joints;
    db.joint_count = COUNT;
    db.settings = &settings;
    assert_int_equal(mm_database_toe_joint(&db, ANKLE, MM_ROLE_LEFT_TOE), BALL);
    assert_int_equal(mm_database_toe_joint(&db, ANKLE, MM_ROLE_RIGHT_TOE), HEEL);
    assert_int_equal(mm_database_toe_joint(&db, ANKLE, MM_ROLE_HEAD), HEEL); /* no joint: -1 role */
    assert_int_equal(mm_database_toe_joint(&db, LEAF, MM_ROLE_LEFT_TOE), -1);
    assert_int_equal(mm_database_toe_joint(&db, -1, MM_ROLE_LEFT_TOE), -1);
    assert_int_equal(mm_database_toe_joint(&db, COUNT, MM_ROLE_LEFT_TOE), -1);
    assert_int_equal(mm_database_role_joint(&db, MM_ROLE_LEFT_FOOT), ANKLE);
    assert_int_equal(mm_database_role_joint(&db, MM_ROLE_HIPS), -1); /* the config named none */
    assert_int_equal(mm_database_role_joint(&db, MM_ROLE_COUNT), -1);
    assert_int_equal(mm_database_find_joint(&db, "ball"), BALL);
    assert_int_equal(mm_database_find_joint(&db, "Ball"), -1);
    assert_int_equal(mm_database_find_joint(&db, NULL), -1);
    /* without settings: by the default names, which this skeleton does not use */
    db.settings = NULL;
    assert_int_equal(mm_database_role_joint(&db, MM_ROLE_LEFT_FOOT), -1);
    assert_int_equal(mm_database_toe_joint(&db, ANKLE, MM_ROLE_LEFT_TOE), HEEL);
    snprintf(joints[BALL].name, MM_NAME_MAX, "%s", mm_role_default_name(MM_ROLE_LEFT_TOE));
    snprintf(joints[ANKLE].name, MM_NAME_MAX, "%s", mm_role_default_name(MM_ROLE_LEFT_FOOT));
    assert_int_equal(mm_database_role_joint(&db, MM_ROLE_LEFT_FOOT), ANKLE);
    assert_int_equal(mm_database_toe_joint(&db, ANKLE, MM_ROLE_LEFT_TOE), BALL);
}

/* The default names are the config's defaults (mm_config_defaults takes them from the table). */
static void test_default_names(void **state)
{
    (void)state;
    mm_config cfg;
    mm_config_defaults(&cfg);
    const char *fields[MM_ROLE_COUNT] = {cfg.hips,      cfg.left_foot, cfg.right_foot, cfg.left_toe,
                                         cfg.right_toe, cfg.left_hand, cfg.right_hand, cfg.head};
    for (int k = 0; k < MM_ROLE_COUNT; ++k) {
        assert_non_null(mm_role_default_name((mm_role)k));
        assert_string_equal(fields[k], mm_role_default_name((mm_role)k));
    }
    assert_string_equal(cfg.facing_bone, mm_role_default_name(MM_ROLE_HIPS));
    assert_null(mm_role_default_name(MM_ROLE_COUNT));
    assert_null(mm_role_default_name((mm_role)-1));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_renamed_moves_alike),
        cmocka_unit_test(test_precedence_and_fallback),
        cmocka_unit_test(test_toe_joint),
        cmocka_unit_test(test_default_names),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
