/* The move detector on analytic motion whose events are known by construction: a ballistic jump,
 * a vault over a 1 m box with a hand planted on its top, a drop from a 1 m ledge, standing still
 * (no move); bad input; and, with $MM_DATA_DIR, the climbs and drops of LAFAN1's
 * obstacles1_subject1 checked by eye (docs/moves_data.md), and lafan1_moves.json loading
 * and building. */
#include <math.h>
#include <stdlib.h>

#include <mm/bvh.h>
#include <mm/config_json.h>
#include <mm/database.h>
#include <mm/move_detect.h>
#include <mm/moves.h>

#include "test_databases.h"
#include "test_util.h"

#define FPS 30.0f
#define G   9.81f

/* A body: hips, ankles and toes (sole offset: ankle 8 cm above the toe), hands at the hips' sides
 * unless a hand is given. */
static void pose(mm_vec3 *t, mm_vec3 hips, mm_vec3 feet, const mm_vec3 *right_hand)
{
    t[MM_MOVE_TRACK_HIPS] = hips;
    t[MM_MOVE_TRACK_LEFT_FOOT] = mm_vec3_make(feet.x, feet.y + 0.08f, feet.z + 0.1f);
    t[MM_MOVE_TRACK_RIGHT_FOOT] = mm_vec3_make(feet.x, feet.y + 0.08f, feet.z - 0.1f);
    t[MM_MOVE_TRACK_LEFT_TOE] = mm_vec3_make(feet.x + 0.15f, feet.y, feet.z + 0.1f);
    t[MM_MOVE_TRACK_RIGHT_TOE] = mm_vec3_make(feet.x + 0.15f, feet.y, feet.z - 0.1f);
    t[MM_MOVE_TRACK_LEFT_HAND] = mm_vec3_make(hips.x, hips.y, hips.z + 0.25f);
    t[MM_MOVE_TRACK_RIGHT_HAND] = right_hand ? *right_hand : mm_vec3_make(hips.x, hips.y, hips.z - 0.25f);
}

static int detect(const mm_vec3 *tracks, int n, mm_move *moves, int capacity)
{
    mm_error err;
    memset(&err, 0, sizeof err);
    int count = -1;
    assert_int_equal(mm_moves_detect(tracks, n, FPS, NULL, moves, capacity, &count, &err), MM_OK);
    return count;
}

/* The one move that tracks (n frames, allocated by ballistic or vault) hold; frees them. */
static mm_move detect_one(mm_vec3 *tracks, int n)
{
    mm_move m[4];
    assert_int_equal(detect(tracks, n, m, 4), 1);
    free(tracks);
    return m[0];
}

/* Standing still for take_off + 1 frames at x = 0, a ballistic flight of the whole body with
 * horizontal speed vx, leaving the feet at y0 and landing them at y1 at frame landing, then
 * standing there. */
static mm_vec3 *ballistic(int n, int take_off, int landing, float vx, float y0, float y1)
{
    mm_vec3 *t = calloc((size_t)n * MM_MOVE_TRACK_COUNT, sizeof(mm_vec3));
    float tf = (float)(landing - take_off) / FPS;
    float vy = (y1 - y0 + 0.5f * G * tf * tf) / tf; /* y0 + vy tf - g tf^2 / 2 = y1 */
    for (int f = 0; f < n; ++f) {
        float s = f <= take_off ? 0.0f : f >= landing ? tf : (float)(f - take_off) / FPS;
        float y = f >= landing ? y1 : y0 + vy * s - 0.5f * G * s * s;
        mm_vec3 feet = mm_vec3_make(vx * s, y, 0.0f);
        pose(t + (size_t)f * MM_MOVE_TRACK_COUNT, mm_vec3_make(feet.x, feet.y + 0.9f, 0.0f), feet, NULL);
    }
    return t;
}

static void test_ballistic_jump(void **state)
{
    (void)state;
    enum { N = 100, TAKE_OFF = 30, LANDING = 45 };
    mm_move m = detect_one(ballistic(N, TAKE_OFF, LANDING, 2.0f, 0.0f, 0.0f), N);
    assert_int_equal(m.kind, MM_MOVE_JUMP);
    assert_true(abs(m.take_off - TAKE_OFF) <= 1);
    assert_true(abs(m.landing - LANDING) <= 1);
    assert_int_equal(m.hand_plant, -1);
    assert_true(m.flight);
    assert_float_equal(m.start_height, 0.0f, 0.02f);
    assert_float_equal(m.end_height, 0.0f, 0.02f);
    /* the range: a second before the take-off to a second after the landing */
    assert_true(abs(m.begin - (TAKE_OFF - 30)) <= 1);
    assert_true(m.end >= LANDING + 30 && m.end <= N);
}

static void test_drop_from_a_ledge(void **state)
{
    (void)state;
    enum { N = 100, TAKE_OFF = 30, LANDING = 45 };
    mm_move m = detect_one(ballistic(N, TAKE_OFF, LANDING, 1.5f, 1.0f, 0.0f), N);
    assert_int_equal(m.kind, MM_MOVE_DROP);
    assert_true(abs(m.take_off - TAKE_OFF) <= 1);
    assert_true(abs(m.landing - LANDING) <= 1);
    assert_float_equal(m.start_height, 1.0f, 0.02f);
    assert_float_equal(m.end_height, 0.0f, 0.02f);
    /* a jump onto the ledge is a jump, not a climb (no hands) */
    m = detect_one(ballistic(N, TAKE_OFF, LANDING, 1.5f, 0.0f, 1.0f), N);
    assert_int_equal(m.kind, MM_MOVE_JUMP);
    assert_float_equal(m.end_height, 1.0f, 0.02f);
}

/* Stands at x = 0.5 until the take-off; the right hand reaches the top of a 1 m box (at
 * x = 1.2) by frame plant and stays there until frame release while the body flies over it to
 * land at x = 1.9 (or, with climb, on the box's top). */
static mm_vec3 *vault(int n, int plant, int take_off, int release, int landing, float box, bool climb)
{
    mm_vec3 *t = calloc((size_t)n * MM_MOVE_TRACK_COUNT, sizeof(mm_vec3));
    const mm_vec3 on_box = {1.2f, box, -0.2f};
    float x1 = climb ? 1.2f : 1.9f, y1 = climb ? box : 0.0f;
    for (int f = 0; f < n; ++f) {
        mm_vec3 hips, feet;
        if (f <= take_off) {
            feet = mm_vec3_make(0.5f, 0.0f, 0.0f);
            hips = mm_vec3_make(0.5f, 0.9f, 0.0f);
        } else if (f < landing) { /* over the box: the hips arc up, the feet tucked under them */
            float s = (float)(f - take_off) / (float)(landing - take_off);
            hips = mm_vec3_make(0.5f + (x1 - 0.5f) * s, 0.9f + y1 * s + 0.7f * sinf((float)MM_PI * s), 0.0f);
            feet = mm_vec3_make(hips.x, hips.y - 0.5f, 0.0f);
        } else {
            feet = mm_vec3_make(x1, y1, 0.0f);
            hips = mm_vec3_make(x1, y1 + 0.9f, 0.0f);
        }
        mm_vec3 hand = mm_vec3_make(hips.x, hips.y, hips.z - 0.25f);
        if (f >= plant - 8 && f < plant) { /* reaching: 8 frames from the hip to the box */
            float s = (float)(f - (plant - 8)) / 8.0f;
            mm_vec3 from = mm_vec3_make(0.5f, 0.9f, -0.25f);
            hand = mm_vec3_add(from, mm_vec3_scale(mm_vec3_sub(on_box, from), s));
        } else if (f >= plant && f <= release) {
            hand = on_box;
        }
        pose(t + (size_t)f * MM_MOVE_TRACK_COUNT, hips, feet, &hand);
    }
    return t;
}

static void test_vault_over_a_box(void **state)
{
    (void)state;
    enum { N = 110, PLANT = 28, TAKE_OFF = 30, RELEASE = 40, LANDING = 45 };
    mm_move m = detect_one(vault(N, PLANT, TAKE_OFF, RELEASE, LANDING, 1.0f, false), N);
    assert_int_equal(m.kind, MM_MOVE_VAULT_LOW);
    assert_true(abs(m.take_off - TAKE_OFF) <= 1);
    assert_true(abs(m.hand_plant - PLANT) <= 1);
    assert_true(abs(m.landing - LANDING) <= 1);
    assert_int_equal(m.hand, 1);
    assert_float_equal(m.obstacle_height, 1.0f, 0.02f);
    /* the same over a 2 m wall is a high vault */
    m = detect_one(vault(N, PLANT, TAKE_OFF, RELEASE, LANDING, 2.0f, false), N);
    assert_int_equal(m.kind, MM_MOVE_VAULT_HIGH);
    assert_float_equal(m.obstacle_height, 2.0f, 0.02f);
    /* ending on the box's top is a climb */
    m = detect_one(vault(N, PLANT, TAKE_OFF, RELEASE, LANDING, 1.0f, true), N);
    assert_int_equal(m.kind, MM_MOVE_CLIMB);
    assert_true(abs(m.landing - LANDING) <= 1);
    assert_float_equal(m.end_height, 1.0f, 0.02f);
}

static void test_standing_and_bad_input(void **state)
{
    (void)state;
    enum { N = 60 };
    mm_vec3 *t = ballistic(N, 30, 31, 0.0f, 0.0f, 0.0f); /* never leaves: no flight frame */
    mm_move m[2];
    assert_int_equal(detect(t, N, m, 2), 0);
    /* deterministic: the same input gives the same bits */
    mm_vec3 *j = ballistic(100, 30, 45, 2.0f, 0.0f, 0.0f);
    mm_move a[2], b[2];
    memset(a, 0, sizeof a);
    memset(b, 0, sizeof b);
    assert_int_equal(detect(j, 100, a, 2), 1);
    assert_int_equal(detect(j, 100, b, 2), 1);
    assert_memory_equal(a, b, sizeof a);
    /* capacity 0 still counts */
    mm_error err;
    memset(&err, 0, sizeof err);
    int count = -1;
    assert_int_equal(mm_moves_detect(j, 100, FPS, NULL, NULL, 0, &count, &err), MM_OK);
    assert_int_equal(count, 1);
    t[5 * MM_MOVE_TRACK_COUNT + 2].y = NAN;
    assert_int_equal(mm_moves_detect(t, N, FPS, NULL, m, 2, &count, &err), MM_ERR_BAD_NUMBER);
    assert_non_null(strstr(err.message, "frame 5"));
    assert_int_equal(mm_moves_detect(j, 100, 0.0f, NULL, m, 2, &count, &err), MM_ERR_INVALID_ARGUMENT);
    mm_move_params p;
    mm_move_params_defaults(&p);
    p.level_change = NAN;
    assert_int_equal(mm_moves_detect(j, 100, FPS, &p, m, 2, &count, &err), MM_ERR_OUT_OF_RANGE);
    /* zero means default: a zeroed params finds what the defaults find */
    mm_move by_default[2], by_zero[2];
    int n_default = -1, n_zero = -2;
    assert_int_equal(mm_moves_detect(j, 100, FPS, NULL, by_default, 2, &n_default, &err), MM_OK);
    memset(&p, 0, sizeof p);
    assert_int_equal(mm_moves_detect(j, 100, FPS, &p, by_zero, 2, &n_zero, &err), MM_OK);
    assert_true(n_default >= 1);
    assert_int_equal(n_zero, n_default);
    assert_memory_equal(by_zero, by_default, sizeof(mm_move) * (size_t)n_default);
    assert_string_equal(mm_move_kind_tag(MM_MOVE_VAULT_HIGH), "VaultHigh");
    assert_string_equal(mm_move_kind_name(MM_MOVE_DROP), "drop");
    assert_null(mm_move_kind_name(MM_MOVE_KIND_COUNT));
    free(t);
    free(j);
}

/* ---- LAFAN1 ---- */

static void test_lafan1_obstacles(void **state)
{
    (void)state;
    char path[1024];
    if (!test_shared_data("lafan1/obstacles1_subject1.bvh", path, sizeof path)) skip();
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    assert_int_equal(mm_config_load_json(MM_DATA_CONFIGS "/lafan1.json", &cfg, NULL, &err), MM_OK);
    mm_bvh bvh;
    assert_int_equal(mm_bvh_load(path, NULL, &bvh, &err), MM_OK);
    mm_bvh_import_desc imp;
    memset(&imp, 0, sizeof imp);
    imp.scale = cfg.scale;
    mm_clip clip;
    assert_int_equal(mm_bvh_to_clip(&bvh, &imp, &clip, &err), MM_OK);
    mm_bvh_free(&bvh);
    mm_move m[64];
    int count = 0;
    assert_int_equal(mm_moves_detect_clip(&clip, &cfg, NULL, m, 64, &count, &err), MM_OK);
    /* seen in rendered frames (docs/moves_data.md): a hand on a ~0.95 m box at 1043, the body
       over it and a foot on its top at 1067; the drop off it; the same box again at 49.5 s */
    static const struct {
        mm_move_kind kind;
        int take_off;
        float end_height;
    } seen[] = {{MM_MOVE_CLIMB, 1050, 0.96f},
                {MM_MOVE_DROP, 1215, 0.0f},
                {MM_MOVE_CLIMB, 1485, 0.96f},
                {MM_MOVE_DROP, 1640, 0.0f}};
    for (size_t i = 0; i < sizeof seen / sizeof seen[0]; ++i) {
        int found = 0;
        for (int k = 0; k < count && k < 64; ++k)
            if (m[k].kind == seen[i].kind && abs(m[k].take_off - seen[i].take_off) <= 3 &&
                fabsf(m[k].end_height - seen[i].end_height) < 0.1f)
                found = 1;
        assert_true(found);
    }
    mm_clip_free(&clip);
    mm_config_free(&cfg);
}

static void test_lafan1_moves_config_builds(void **state)
{
    (void)state;
    const char *dir = getenv("MM_DATA_DIR");
    if (!dir || !*dir) skip();
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    assert_int_equal(mm_config_load_json(MM_DATA_CONFIGS "/lafan1_moves.json", &cfg, NULL, &err), MM_OK);
    static const char *const names[] = {"Jump", "VaultLow", "VaultHigh", "Climb",
                                        "Drop", "TakeOff",  "HandPlant", "Landing"};
    for (int i = 0; i < 8; ++i) assert_true(mm_config_tag_index(&cfg, names[i]) >= 0);
    mm_database db;
    assert_int_equal(test_build_data_database("lafan1_moves", &db), 0);
    /* every move clip holds its kind and exactly one TakeOff and one Landing frame */
    int take_off = mm_config_tag_index(&cfg, "TakeOff"), landing = mm_config_tag_index(&cfg, "Landing");
    uint64_t kinds = 0;
    for (int i = 0; i < 5; ++i) kinds |= (uint64_t)1 << mm_config_tag_index(&cfg, names[i]);
    int moves = 0;
    for (int c = 0; c < db.clip_count; ++c) {
        int with_kind = 0, t = 0, l = 0;
        for (int f = db.clips[c].first_frame; f < db.clips[c].first_frame + db.clips[c].frame_count; ++f) {
            uint64_t tags = db.frame_tags[f];
            with_kind += (tags & kinds) != 0;
            t += (int)(tags >> take_off & 1u);
            l += (int)(tags >> landing & 1u);
        }
        if (!with_kind) continue;
        ++moves;
        assert_int_equal(t, 1);
        assert_int_equal(l, 1);
    }
    assert_true(moves >= 20);
    mm_database_free(&db);
    mm_config_free(&cfg);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ballistic_jump),   cmocka_unit_test(test_drop_from_a_ledge),
        cmocka_unit_test(test_vault_over_a_box), cmocka_unit_test(test_standing_and_bad_input),
        cmocka_unit_test(test_lafan1_obstacles), cmocka_unit_test(test_lafan1_moves_config_builds),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
