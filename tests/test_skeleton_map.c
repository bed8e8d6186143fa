/* mm/skeleton_map.h on the built-in set: a game skeleton made of the database's joints in another
 * order, with a joint renamed, a joint inserted into the spine, fingers and twist bones. Its pose,
 * rebuilt from the map's local transforms by forward kinematics in the game's order, puts every
 * shared joint where the database pose has it; extra joints keep their rest; twist bones turn
 * about their bone by half the hand's twist (a known turn of the hand, and on the run); the added root is
 * there only when asked for; the game's bone lengths and rest frames are kept when asked for; `mm simulate
 * --skeleton` writes the same motion in the game's names and order; bad maps are errors naming the joint. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mm/bvh.h>
#include <mm/character.h>
#include <mm/skeleton_map.h>

#include "test_databases.h"
#include "test_util.h"

#define TICKS      240 /* 4 s at 60 Hz on random input */
#define SEED       5
#define POS_TOL    2e-5f /* m: float error over a chain of a dozen joints */
#define ROT_TOL    2e-5f /* 1 - |dot| of unit quaternions */
#define FINGER_LEN 0.04f /* m: the extra fingers' bones */

static mm_database db;

/* --- the game's skeleton --- */

typedef struct game_joint {
    char name[MM_NAME_MAX];
    char parent[MM_NAME_MAX]; /* "" for the root */
    mm_vec3 offset;
} game_joint;

static int add(game_joint *g, int n, const char *name, const char *parent, mm_vec3 offset)
{
    snprintf(g[n].name, sizeof g[n].name, "%.*s", MM_NAME_MAX - 1, name);
    snprintf(g[n].parent, sizeof g[n].parent, "%.*s", MM_NAME_MAX - 1, parent);
    g[n].offset = offset;
    return n + 1;
}

/* Database joint j and its subtree in depth-first order, children last first (another order than
 * the database's), with the game's names: Hips is "pelvis"; a joint "SpineExtra" between Spine1 and
 * Spine2 (Spine2's offset split between them); two finger joints under each hand; a twist bone
 * under each forearm (half-way to the hand) and under the right arm. */
static int visit(game_joint *g, int n, int j, const char *parent)
{
    const mm_joint *dj = &db.joints[j];
    const char *name = strcmp(dj->name, "Hips") == 0 ? "pelvis" : dj->name;
    mm_vec3 offset = dj->offset;
    if (strcmp(dj->name, "Spine2") == 0) {
        n = add(g, n, "SpineExtra", parent, mm_vec3_scale(offset, 0.25f));
        parent = "SpineExtra";
        offset = mm_vec3_scale(offset, 0.75f);
    }
    n = add(g, n, name, parent, offset);
    char self[MM_NAME_MAX];
    snprintf(self, sizeof self, "%s", name);
    for (int c = db.joint_count - 1; c > j; --c)
        if (db.joints[c].parent == j) n = visit(g, n, c, self);
    char extra[2 * MM_NAME_MAX], extra2[2 * MM_NAME_MAX];
    if (strstr(dj->name, "Hand")) {
        snprintf(extra, sizeof extra, "%sIndex1", dj->name);
        snprintf(extra2, sizeof extra2, "%sIndex2", dj->name);
        n = add(g, n, extra, self, mm_vec3_make(0.0f, -FINGER_LEN, 0.02f));
        n = add(g, n, extra2, extra, mm_vec3_make(0.0f, -FINGER_LEN, 0.0f));
    }
    if (strstr(dj->name, "ForeArm") || strcmp(dj->name, "RightArm") == 0) {
        snprintf(extra, sizeof extra, "%sTwist", dj->name);
        int child = -1;
        for (int c = j + 1; c < db.joint_count; ++c)
            if (db.joints[c].parent == j) child = c;
        n = add(g, n, extra, self, mm_vec3_scale(db.joints[child].offset, 0.5f));
    }
    return n;
}

/* The game's skeleton (scale: its offsets multiplied). */
static void game_skeleton(mm_skeleton *s, float scale)
{
    game_joint g[64];
    int n = visit(g, 0, 1, "");
    assert_int_equal(mm_skeleton_init(s, n, NULL), MM_OK);
    for (int k = 0; k < n; ++k) {
        memcpy(s->joints[k].name, g[k].name, MM_NAME_MAX);
        s->joints[k].offset = mm_vec3_scale(g[k].offset, scale);
        s->joints[k].order = MM_EULER_ZXY;
        s->joints[k].parent = -1;
        for (int p = 0; p < k; ++p)
            if (strcmp(g[p].name, g[k].parent) == 0) s->joints[k].parent = p;
    }
    assert_int_equal(mm_skeleton_validate(s, NULL), MM_OK);
}

static const mm_skeleton_map_pair PAIRS[] = {{"pelvis", "Hips"}};
static const mm_skeleton_map_follow FOLLOW[] = {
    {"LeftForeArmTwist", "LeftHand", 0.5f, true},
    {"RightForeArmTwist", "RightHand", 0.5f, true},
    {"RightArmTwist", "RightForeArm", 0.5f, false},
};

/* --- checks --- */

static float rot_error(mm_quat a, mm_quat b) { return 1.0f - fabsf(mm_quat_dot(a, b)); }

/* a character over random input, the map applied each tick, check(tick) called */
typedef void (*check_fn)(const mm_skeleton_map *m, const mm_character *c, const mm_quat *lr,
                         const mm_vec3 *lp, const mm_xform *world, void *ctx);

static void run(const mm_skeleton_map *m, check_fn check, void *ctx)
{
    mm_searcher searcher;
    assert_int_equal(mm_searcher_init(&searcher, &db, NULL, NULL), MM_OK);
    mm_character c;
    assert_int_equal(mm_character_init(&c, &db, &searcher, NULL, NULL), MM_OK);
    mm_input_random_desc rd;
    memset(&rd, 0, sizeof rd);
    rd.seconds = TICKS / 60.0f;
    mm_input_script script;
    assert_int_equal(mm_input_script_random(&script, SEED, &rd), MM_OK);
    size_t n = (size_t)m->joint_count;
    mm_quat *lr = malloc(sizeof(mm_quat) * n);
    mm_vec3 *lp = malloc(sizeof(mm_vec3) * n);
    mm_xform *world = malloc(sizeof(mm_xform) * n);
    assert_non_null(lr && lp && world);
    for (int f = 0; f < TICKS; ++f) {
        mm_input in;
        mm_input_script_sample_tick(&script, f / 60.0f, 1.0f / 60.0f, &in);
        mm_character_update(&c, &in, 1.0f / 60.0f);
        mm_skeleton_map_pose(m, c.global, c.local_rotations, lr, lp, world);
        check(m, &c, lr, lp, world, ctx);
    }
    free(lr), free(lp), free(world);
    mm_input_script_free(&script);
    mm_character_free(&c);
    mm_searcher_free(&searcher);
}

/* Forward kinematics of the map's local transforms in its joint order (independent of the map's
 * own world output). */
static void fk(const mm_skeleton_map *m, const mm_quat *lr, const mm_vec3 *lp, mm_xform *out)
{
    for (int o = 0; o < m->joint_count; ++o) {
        mm_xform local = mm_xform_make(lr[o], lp[o]);
        int p = m->joints[o].parent;
        out[o] = p >= 0 ? mm_xform_mul(out[p], local) : local;
    }
}

typedef struct stats {
    float max_twist, max_follow;
    int ticks;
} stats;

static void check_shared(const mm_skeleton_map *m, const mm_character *c, const mm_quat *lr,
                         const mm_vec3 *lp, const mm_xform *world, void *ctx)
{
    stats *st = (stats *)ctx;
    ++st->ticks;
    mm_xform rebuilt[128];
    fk(m, lr, lp, rebuilt);
    for (int o = 0; o < m->joint_count; ++o) {
        const char *name = m->joints[o].name;
        int d = mm_skeleton_find(&(mm_skeleton){db.joint_count, (mm_joint *)db.joints, {0}},
                                 strcmp(name, "pelvis") == 0 ? "Hips" : name);
        assert_true(mm_vec3_distance(rebuilt[o].translation, world[o].translation) < POS_TOL);
        if (d >= 0) { /* a shared joint: where and as the database has it */
            if (mm_vec3_distance(rebuilt[o].translation, c->global[d].translation) > POS_TOL)
                fail_msg("%s: %g m from the database's", name,
                         (double)mm_vec3_distance(rebuilt[o].translation, c->global[d].translation));
            assert_true(rot_error(rebuilt[o].rotation, c->global[d].rotation) < ROT_TOL);
        } else if (strstr(name, "Index")) { /* an extra: at rest */
            assert_memory_equal(&lp[o], &m->joints[o].offset, sizeof(mm_vec3));
            assert_true(rot_error(lr[o], mm_quat_identity()) == 0.0f);
        } else if (strstr(name, "ForeArmTwist")) { /* half the hand's twist about the hand's bone */
            int hand = mm_skeleton_find(&(mm_skeleton){db.joint_count, (mm_joint *)db.joints, {0}},
                                        strstr(name, "Left") ? "LeftHand" : "RightHand");
            mm_vec3 axis = mm_vec3_normalize(db.joints[hand].offset);
            mm_vec3 v = mm_vec3_make(lr[o].x, lr[o].y, lr[o].z);
            assert_true(mm_vec3_length(mm_vec3_cross(v, axis)) < 1e-5f); /* about the bone */
            mm_quat full = mm_quat_mul(lr[o], lr[o]);
            mm_quat swing = mm_quat_mul(c->local_rotations[hand], mm_quat_conj(full));
            /* what is left of the hand's rotation has no part about the bone */
            assert_true(fabsf(mm_vec3_dot(mm_vec3_make(swing.x, swing.y, swing.z), axis)) < 1e-4f);
            if (mm_vec3_length(v) > st->max_twist) st->max_twist = mm_vec3_length(v);
            assert_memory_equal(&lp[o], &m->joints[o].offset, sizeof(mm_vec3));
        } else if (strcmp(name, "RightArmTwist") == 0) { /* half the forearm's whole rotation */
            int fore =
                mm_skeleton_find(&(mm_skeleton){db.joint_count, (mm_joint *)db.joints, {0}}, "RightForeArm");
            assert_true(rot_error(mm_quat_mul(lr[o], lr[o]), c->local_rotations[fore]) < ROT_TOL);
            float turned = 1.0f - fabsf(lr[o].w);
            if (turned > st->max_follow) st->max_follow = turned;
        } else if (strcmp(name, "SimulationRoot") == 0) {
            assert_memory_equal(&world[o], &c->global[0], sizeof(mm_xform));
        } else {
            assert_string_equal(name, "SpineExtra"); /* the one joint left: at rest under Spine1 */
            assert_memory_equal(&lp[o], &m->joints[o].offset, sizeof(mm_vec3));
        }
    }
}

static void test_map_reordered_with_extras(void **state)
{
    (void)state;
    mm_skeleton game;
    game_skeleton(&game, 1.0f);
    /* another order than the database's: Spine before the legs */
    assert_true(mm_skeleton_find(&game, "Spine") < mm_skeleton_find(&game, "LeftUpLeg"));
    assert_true(game.joint_count == db.joint_count - 1 + 1 + 4 + 3);
    for (int with_root = 0; with_root <= 1; ++with_root) {
        mm_skeleton_map_desc d = {
            .pairs = PAIRS, .pair_count = 1, .follow = FOLLOW, .follow_count = 3, .with_root = with_root};
        mm_skeleton_map m;
        mm_error err;
        assert_int_equal(mm_skeleton_map_init(&m, &db, &game, &d, &err), MM_OK);
        assert_int_equal(m.joint_count, game.joint_count + with_root);
        assert_int_equal(m.mapped, db.joint_count - 1);
        /* the game's names in the game's order, after the root when there is one */
        for (int g = 0; g < game.joint_count; ++g)
            assert_string_equal(m.joints[g + with_root].name, game.joints[g].name);
        if (with_root) {
            assert_string_equal(m.joints[0].name, db.joints[0].name);
            assert_int_equal(m.joints[1].parent, 0);
        } else {
            assert_int_equal(m.joints[0].parent, -1);
        }
        stats st = {0, 0, 0};
        run(&m, check_shared, &st);
        assert_int_equal(st.ticks, TICKS);
        /* the followers did turn: the checks above were not on identities */
        assert_true(st.max_follow > 1e-3f);
        print_message("with_root %d: largest twist bone turn sin(a/2) %.4f, arm follower 1-cos(a/2) %.4f\n",
                      with_root, (double)st.max_twist, (double)st.max_follow);
        mm_skeleton_map_free(&m);
    }
    mm_skeleton_free(&game);
}

/* The game's bone lengths (10 % longer) and its own rest frames (every joint's rest turned, its
 * offset expressed in the turned frame: the same rest posture): with game_lengths, the world
 * rotations are the database's times the rest frames', the pelvis stands where the hips do and
 * every bone has the game's length, pointing as the database's bone does. */
typedef struct frames_ctx {
    const mm_skeleton *game;
    const mm_quat *rest_world;
    float scale;
} frames_ctx;

static void check_lengths(const mm_skeleton_map *m, const mm_character *c, const mm_quat *lr,
                          const mm_vec3 *lp, const mm_xform *world, void *ctx)
{
    const frames_ctx *x = (const frames_ctx *)ctx;
    mm_xform rebuilt[128];
    fk(m, lr, lp, rebuilt);
    mm_skeleton dbs = {db.joint_count, (mm_joint *)db.joints, {0}};
    for (int o = 0; o < m->joint_count; ++o) {
        const char *name = m->joints[o].name;
        int d = mm_skeleton_find(&dbs, strcmp(name, "pelvis") == 0 ? "Hips" : name);
        assert_true(mm_vec3_distance(rebuilt[o].translation, world[o].translation) < POS_TOL);
        if (d < 0) continue;
        assert_true(rot_error(rebuilt[o].rotation, mm_quat_mul(c->global[d].rotation, x->rest_world[o])) <
                    ROT_TOL);
        int p = m->joints[o].parent, dp = db.joints[d].parent;
        if (p < 0) {
            assert_true(mm_vec3_distance(rebuilt[o].translation, c->global[d].translation) < POS_TOL);
            continue;
        }
        if (strcmp(m->joints[p].name, dp == 1 ? "pelvis" : db.joints[dp].name) != 0) continue; /* Spine2 */
        mm_vec3 bone = mm_vec3_sub(rebuilt[o].translation, rebuilt[p].translation);
        mm_vec3 want =
            mm_vec3_scale(mm_vec3_sub(c->global[d].translation, c->global[dp].translation), x->scale);
        assert_true(mm_vec3_distance(bone, want) < 1e-4f);
    }
}

static void test_map_game_lengths_and_rest_frames(void **state)
{
    (void)state;
    const float scale = 1.1f;
    mm_skeleton game;
    game_skeleton(&game, scale);
    int n = game.joint_count;
    mm_quat *rest = malloc(sizeof(mm_quat) * (size_t)n), *rest_world = malloc(sizeof(mm_quat) * (size_t)n);
    assert_non_null(rest && rest_world);
    for (int g = 0; g < n; ++g) { /* world rest frames turned by joint: the posture is the same */
        mm_quat w =
            mm_quat_from_axis_angle(mm_vec3_normalize(mm_vec3_make(1.0f, (float)g, 0.5f)), 0.3f * (float)g);
        int p = game.joints[g].parent;
        mm_quat parent = p >= 0 ? rest_world[p] : mm_quat_identity();
        rest_world[g] = w;
        rest[g] = mm_quat_mul(mm_quat_conj(parent), w);
        game.joints[g].offset = mm_quat_inv_rotate(parent, game.joints[g].offset);
    }
    mm_skeleton_map_desc d = {.pairs = PAIRS, .pair_count = 1, .rest_rotations = rest, .game_lengths = true};
    mm_skeleton_map m;
    assert_int_equal(mm_skeleton_map_init(&m, &db, &game, &d, NULL), MM_OK);
    frames_ctx x = {&game, rest_world, scale};
    run(&m, check_lengths, &x);
    /* only the root carries positions in the written pose */
    for (int o = 0; o < m.joint_count; ++o)
        assert_int_equal((m.joints[o].flags & MM_JOINT_TRANSLATES) != 0,
                         m.joints[o].parent < 0 || strcmp(m.joints[o].name, "pelvis") == 0);
    mm_skeleton_map_free(&m);
    free(rest), free(rest_world);
    mm_skeleton_free(&game);
}

/* A hand turned by a known swing and twist: its forearm's twist bone takes exactly half the
 * twist, about the hand's bone, and none of the swing. */
static void test_map_twist_known(void **state)
{
    (void)state;
    mm_skeleton game;
    game_skeleton(&game, 1.0f);
    mm_skeleton_map_desc d = {.pairs = PAIRS, .pair_count = 1, .follow = FOLLOW, .follow_count = 3};
    mm_skeleton_map m;
    assert_int_equal(mm_skeleton_map_init(&m, &db, &game, &d, NULL), MM_OK);
    int n = db.joint_count;
    mm_xform *global = malloc(sizeof(mm_xform) * (size_t)n);
    mm_quat *local = malloc(sizeof(mm_quat) * (size_t)n);
    mm_quat *lr = malloc(sizeof(mm_quat) * (size_t)m.joint_count);
    mm_xform *world = malloc(sizeof(mm_xform) * (size_t)m.joint_count);
    assert_non_null(global && local && lr && world);
    mm_skeleton dbs = {n, (mm_joint *)db.joints, {0}};
    int hand = mm_skeleton_find(&dbs, "LeftHand");
    mm_vec3 axis = mm_vec3_normalize(db.joints[hand].offset);
    mm_vec3 across = mm_vec3_normalize(mm_vec3_cross(axis, mm_vec3_make(0.3f, 0.2f, 1.0f)));
    for (int j = 0; j < n; ++j) {
        local[j] = mm_quat_identity();
        global[j] = mm_xform_identity();
    }
    local[hand] = mm_quat_mul(mm_quat_from_axis_angle(across, 0.5f), mm_quat_from_axis_angle(axis, 0.8f));
    mm_skeleton_map_pose(&m, global, local, lr, NULL, world);
    int twist = mm_skeleton_find(&game, "LeftForeArmTwist");
    assert_true(rot_error(lr[twist], mm_quat_from_axis_angle(axis, 0.4f)) < 1e-6f);
    int right = mm_skeleton_find(&game, "RightForeArmTwist"); /* the right hand did not turn */
    assert_true(rot_error(lr[right], mm_quat_identity()) < 1e-7f);
    free(global), free(local), free(lr), free(world);
    mm_skeleton_map_free(&m);
    mm_skeleton_free(&game);
}

/* mm simulate --skeleton: the game's skeleton written as a BVH (in metres, at rest), a map file
 * naming the pelvis and the twist bones; the motion written in the game's names and order, its
 * shared joints' world positions (mm_bvh_fk, from the files) those of the motion written without. */
static void test_simulate_skeleton(void **state)
{
    (void)state;
    const char *mm = getenv("MM_BIN");
    if (!mm) skip();
    char db_path[512], game_path[512], map_path[512], plain[512], mapped[512], cmd[4096];
    snprintf(db_path, sizeof db_path, "%s/skeleton_map.mmdb", MM_TEST_OUT);
    snprintf(game_path, sizeof game_path, "%s/skeleton_map_game.bvh", MM_TEST_OUT);
    snprintf(map_path, sizeof map_path, "%s/skeleton_map.json", MM_TEST_OUT);
    snprintf(plain, sizeof plain, "%s/skeleton_map_plain.bvh", MM_TEST_OUT);
    snprintf(mapped, sizeof mapped, "%s/skeleton_map_mapped.bvh", MM_TEST_OUT);
    assert_int_equal(mm_database_save(&db, db_path, NULL), MM_OK);
    mm_skeleton game;
    game_skeleton(&game, 1.0f);
    mm_clip rest;
    assert_int_equal(mm_clip_init(&rest, &game, 1, 60.0f, NULL), MM_OK);
    assert_int_equal(mm_bvh_save(game_path, &rest, NULL, NULL), MM_OK);
    mm_clip_free(&rest);
    FILE *f = fopen(map_path, "w");
    assert_non_null(f);
    fprintf(
        f,
        "{\"pairs\": {\"pelvis\": \"Hips\"},\n \"follow\": [{\"joint\": \"LeftForeArmTwist\", \"follows\": "
        "\"LeftHand\", \"weight\": 0.5, \"twist\": true}]}\n");
    fclose(f);
    snprintf(cmd, sizeof cmd, "%s simulate %s --random 3 --seconds 2 -o %s > /dev/null", mm, db_path, plain);
    assert_int_equal(system(cmd), 0);
    snprintf(cmd, sizeof cmd,
             "%s simulate %s --random 3 --seconds 2 -o %s --skeleton %s --skeleton-map %s > /dev/null", mm,
             db_path, mapped, game_path, map_path);
    assert_int_equal(system(cmd), 0);
    mm_bvh a, b;
    assert_int_equal(mm_bvh_load(plain, NULL, &a, NULL), MM_OK);
    assert_int_equal(mm_bvh_load(mapped, NULL, &b, NULL), MM_OK);
    assert_int_equal(b.skeleton.joint_count, game.joint_count);
    for (int g = 0; g < game.joint_count; ++g)
        assert_string_equal(b.skeleton.joints[g].name, game.joints[g].name);
    assert_int_equal(a.frame_count, 120);
    assert_int_equal(b.frame_count, 120);
    double *pa = malloc(sizeof(double) * 3 * (size_t)a.skeleton.joint_count);
    double *pb = malloc(sizeof(double) * 3 * (size_t)b.skeleton.joint_count);
    assert_non_null(pa && pb);
    int compared = 0;
    for (int fr = 0; fr < a.frame_count; ++fr) {
        assert_int_equal(mm_bvh_fk(&a, fr, pa), MM_OK);
        assert_int_equal(mm_bvh_fk(&b, fr, pb), MM_OK);
        for (int g = 0; g < b.skeleton.joint_count; ++g) {
            const char *name = b.skeleton.joints[g].name;
            int d = mm_skeleton_find(&a.skeleton, strcmp(name, "pelvis") == 0 ? "Hips" : name);
            if (d < 0) continue;
            double e = 0.0;
            for (int k = 0; k < 3; ++k)
                e += (pa[3 * d + k] - pb[3 * g + k]) * (pa[3 * d + k] - pb[3 * g + k]);
            if (sqrt(e) > 1e-4) fail_msg("frame %d, %s: %g m apart", fr, name, sqrt(e));
            ++compared;
        }
    }
    assert_int_equal(compared, a.frame_count * (db.joint_count - 1));
    free(pa), free(pb);
    mm_bvh_free(&a), mm_bvh_free(&b);
    /* a map naming a joint the game does not have: an error naming the map file and the joint */
    f = fopen(map_path, "w");
    assert_non_null(f);
    fprintf(f, "{\"pairs\": {\"Pelvis\": \"Hips\"}}\n");
    fclose(f);
    snprintf(cmd, sizeof cmd,
             "%s simulate %s --random 3 --seconds 1 -o %s --skeleton %s --skeleton-map %s 2> %s.err", mm,
             db_path, mapped, game_path, map_path, map_path);
    assert_int_not_equal(system(cmd), 0);
    snprintf(cmd, sizeof cmd, "grep -q \"skeleton_map.json.*'Pelvis'\" %s.err", map_path);
    assert_int_equal(system(cmd), 0);
    mm_skeleton_free(&game);
}

static void test_map_errors(void **state)
{
    (void)state;
    mm_skeleton game;
    game_skeleton(&game, 1.0f);
    mm_skeleton_map m;
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_skeleton_map_pair bad_pair[] = {{"pelvis", "Pelvis"}};
    mm_skeleton_map_desc d = {.pairs = bad_pair, .pair_count = 1};
    assert_int_equal(mm_skeleton_map_init(&m, &db, &game, &d, &err), MM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "'Pelvis'"));
    assert_null(m.joints);
    mm_skeleton_map_follow mapped[] = {{"LeftHand", "LeftForeArm", 0.5f, true}};
    mm_skeleton_map_desc d2 = {.follow = mapped, .follow_count = 1};
    assert_int_equal(mm_skeleton_map_init(&m, &db, &game, &d2, &err), MM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "'LeftHand'"));
    mm_skeleton_map_follow nan_weight[] = {{"LeftForeArmTwist", "LeftHand", NAN, true}};
    mm_skeleton_map_desc d3 = {.follow = nan_weight, .follow_count = 1};
    assert_int_equal(mm_skeleton_map_init(&m, &db, &game, &d3, &err), MM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "LeftForeArmTwist"));
    /* a skeleton sharing no name */
    mm_skeleton other;
    assert_int_equal(mm_skeleton_init(&other, 2, NULL), MM_OK);
    snprintf(other.joints[0].name, MM_NAME_MAX, "a");
    snprintf(other.joints[1].name, MM_NAME_MAX, "b");
    assert_int_equal(mm_skeleton_map_init(&m, &db, &other, NULL, &err), MM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "pairs"));
    /* the root's name taken already */
    snprintf(other.joints[1].name, MM_NAME_MAX, "%s", db.joints[0].name);
    mm_skeleton_map_desc d4 = {.with_root = true};
    assert_int_equal(mm_skeleton_map_init(&m, &db, &other, &d4, &err), MM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, db.joints[0].name));
    /* an invalid skeleton (a parent after its child) */
    other.joints[0].parent = 1;
    assert_int_not_equal(mm_skeleton_map_init(&m, &db, &other, NULL, &err), MM_OK);
    mm_skeleton_free(&other);
    assert_int_equal(mm_skeleton_map_init(&m, NULL, &game, NULL, &err), MM_ERR_INVALID_ARGUMENT);
    mm_skeleton_free(&game);
    mm_skeleton_map_free(NULL);
}

static int setup(void **state)
{
    (void)state;
    return test_build_synth_database(&db) != 0 ? -1 : 0;
}

static int teardown(void **state)
{
    (void)state;
    mm_database_free(&db);
    return 0;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_map_reordered_with_extras),
        cmocka_unit_test(test_map_game_lengths_and_rest_frames),
        cmocka_unit_test(test_map_twist_known),
        cmocka_unit_test(test_map_errors),
        cmocka_unit_test(test_simulate_skeleton),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
