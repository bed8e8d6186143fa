/* Search: the exact method and threads against brute force on a real database, and every filter
 * and bias on small crafted databases. */
#include <math.h>

#include <mm/character.h>
#include <mm/database_build.h>
#include <mm/input.h>
#include <mm/search.h>

#include "math_private.h"
#include "test_databases.h"
#include "test_util.h"

/* ---- a real database: LAFAN1 when MM_DATA_DIR is set, the built-in set otherwise ---------- */

static mm_database real_db;
static const char *real_name;
static int lafan_loaded; /* real_db is LAFAN1 (else the built-in set) */

static int build_real(void)
{
    int lafan = 0;
    int r = test_build_real_database(&real_db, &lafan);
    real_name = lafan ? "LAFAN1" : "built-in set";
    lafan_loaded = lafan;
    return r;
}

static double normal(test_rng *r)
{
    double u = test_rng_uniform(r, 1e-12, 1), v = test_rng_uniform(r, 0, 1);
    return sqrt(-2.0 * log(u)) * cos(2.0 * MM_PI * v);
}

/* The contact favour on three queries of four (i: the query's number, a: a frame whose contacts
 * the pattern is, mostly): factors from 1 to 4, a few below 1 (favoured contacts; the bounds
 * hold for those too), and patterns no frame has. */
static void with_contact_favour(const mm_database *db, int i, int a, mm_search_params *p)
{
    if (i % 4 == 3) return;
    p->contact_pattern = i % 10 == 1 ? i % 16 : (int)db->contacts[a];
    p->contact_mismatch_favour = i % 13 == 0 ? 0.6f : 1.0f + 0.5f * (float)(i % 7);
}

/* Queries of the three kinds, with parameters that vary everything the search reads. */
static void make_case(const mm_database *db, test_rng *r, int i, float *q, mm_search_params *p)
{
    int a = (int)test_rng_uniform(r, 0, db->frame_count), b = (int)test_rng_uniform(r, 0, db->frame_count);
    switch (i % 3) {
    case 0:
        mm_search_query_from_frames(db, a, b, q);
        break;
    case 1:
        mm_search_query_from_frames(db, a, a, q);
        for (int d = 0; d < db->dims; ++d) q[d] += (float)(0.1 * normal(r));
        break;
    default:
        memset(q, 0, sizeof(float) * (size_t)db->dims_padded);
        for (int d = 0; d < db->dims; ++d) q[d] = (float)normal(r);
    }
    mm_search_params_defaults(db, p);
    p->current_frame = i % 5 == 4 ? -1 : a;
    p->pose_trajectory_ratio = (float)test_rng_uniform(r, 0, 1);
    p->next_pose_favour = (float)test_rng_uniform(r, 0.3, 1.2);
    p->loop_anim_favour = (float)test_rng_uniform(r, 0.5, 1.2);
    p->continuing_bias = i % 7 == 0 ? (float)test_rng_uniform(r, 0, 2) : 0.0f;
    p->exclude_window = i % 4 == 1 ? (int)test_rng_uniform(r, 0, 30) : 0;
    p->end_margin = i % 6 == 2 ? (int)test_rng_uniform(r, 0, 20) : 0;
    p->type = (mm_search_type)(i % 9 == 3   ? MM_SEARCH_IDLE
                               : i % 9 == 5 ? MM_SEARCH_LOCOMOTION
                                            : MM_SEARCH_ANY);
    if (db->tag_count > 0 && i % 11 == 7) p->excluded_tags = 1;
    p->joint_position_weights[0] = (float)test_rng_uniform(r, 0, 2);
    p->angle_multiplier = (float)test_rng_uniform(r, 0, 3);
    with_contact_favour(db, i, a, p);
}

static void test_exact_equals_brute(void **state)
{
    (void)state;
    const mm_database *db = &real_db;
    mm_searcher one, two, three;
    mm_searcher_desc d2 = {2, NULL}, d3 = {3, NULL};
    assert_int_equal(mm_searcher_init(&one, db, NULL, NULL), MM_OK);
    assert_int_equal(mm_searcher_init(&two, db, &d2, NULL), MM_OK);
    assert_int_equal(mm_searcher_init(&three, db, &d3, NULL), MM_OK);
    test_rng r = {0x1234567};
    /* MM_TEST_SEARCH_QUERIES shortens the run under slow sanitizers (ThreadSanitizer in CI). */
    int n = getenv("MM_DATA_DIR") ? 1500 : 3000;
    if (getenv("MM_TEST_SEARCH_QUERIES")) n = atoi(getenv("MM_TEST_SEARCH_QUERIES"));
    if (n < 30) n = 30;
    float q[MM_SEARCH_MAX_DIMS];
    int found = 0;
    for (int i = 0; i < n; ++i) {
        mm_search_params p;
        make_case(db, &r, i, q, &p);
        mm_search_result brute, fast, fast2, fast3, brute2;
        mm_searcher_search(&one, q, &p, MM_SEARCH_BRUTE, &brute, 1);
        mm_searcher_search(&one, q, &p, MM_SEARCH_FAST, &fast, 1);
        mm_searcher_search(&two, q, &p, MM_SEARCH_FAST, &fast2, 1);
        mm_searcher_search(&three, q, &p, MM_SEARCH_FAST, &fast3, 1);
        mm_searcher_search(&two, q, &p, MM_SEARCH_BRUTE, &brute2, 1);
        if (fast.frame != brute.frame)
            print_error("%s query %d: brute %d (%.9g), fast %d (%.9g)\n", real_name, i, brute.frame,
                        brute.cost, fast.frame, fast.cost);
        assert_int_equal(fast.frame, brute.frame);
        assert_true(fast.cost == brute.cost);
        assert_int_equal(fast2.frame, brute.frame);
        assert_int_equal(fast3.frame, brute.frame);
        assert_int_equal(brute2.frame, brute.frame);
        if (brute.frame >= 0) {
            ++found;
            /* the winner passes the filters */
            assert_int_not_equal(brute.frame, p.current_frame);
            const mm_db_clip *c = &db->clips[db->frame_clip[brute.frame]];
            if (p.type == MM_SEARCH_IDLE) assert_int_equal(c->type, MM_CLIP_IDLE);
            if (p.type == MM_SEARCH_LOCOMOTION) assert_int_equal(c->type, MM_CLIP_LOCOMOTION);
            assert_false(db->frame_tags[brute.frame] & p.excluded_tags);
            /* the terms add up to the base cost */
            mm_search_terms t;
            mm_search_cost_terms(db, q, &p, brute.frame, &t);
            double sum = (double)t.pose_position + t.pose_velocity + t.root_velocity + t.traj_position +
                         t.traj_direction;
            assert_near(sum, brute.base, 1e-4 * (1 + brute.base));
        }
        /* top 5 agrees too */
        mm_search_result tb[5], tf[5];
        int nb = mm_searcher_search(&one, q, &p, MM_SEARCH_BRUTE, tb, 5);
        int nf = mm_searcher_search(&one, q, &p, MM_SEARCH_FAST, tf, 5);
        assert_int_equal(nb, nf);
        for (int k = 0; k < nb; ++k) assert_int_equal(tb[k].frame, tf[k].frame);
        assert_int_equal(tb[0].frame, brute.frame);
    }
    assert_true(found > n / 3);
    print_message("%s: %d frames, %d queries: fast (1, 2 and 3 threads) = brute force\n", real_name,
                  db->frame_count, n);

    /* The batch call gives the same answers on 1 and 2 threads. */
    int m = 300;
    float *qs = malloc(sizeof(float) * (size_t)m * db->dims_padded);
    mm_search_params *ps = malloc(sizeof(mm_search_params) * (size_t)m);
    mm_search_result *r1 = malloc(sizeof(mm_search_result) * (size_t)m),
                     *r2 = malloc(sizeof(mm_search_result) * (size_t)m);
    for (int i = 0; i < m; ++i) make_case(db, &r, i, qs + (size_t)i * db->dims_padded, &ps[i]);
    mm_searcher_batch(&one, qs, ps, 1, MM_SEARCH_FAST, r1, m);
    mm_searcher_batch(&two, qs, ps, 1, MM_SEARCH_FAST, r2, m);
    for (int i = 0; i < m; ++i) {
        mm_search_result single;
        mm_searcher_search(&one, qs + (size_t)i * db->dims_padded, &ps[i], MM_SEARCH_BRUTE, &single, 1);
        assert_int_equal(r1[i].frame, single.frame);
        assert_int_equal(r2[i].frame, single.frame);
    }
    free(qs);
    free(ps);
    free(r1);
    free(r2);
    mm_searcher_free(&one);
    mm_searcher_free(&two);
    mm_searcher_free(&three);
}

/* The built-in set whatever the real database is (with MM_DATA_DIR set, the test above runs on
 * LAFAN1): the exact method (k 1 and 5) against brute force on the three query kinds, with the
 * ratio, the favours (loop, contact, next frame), the filters and the weights varied. */
static void test_builtin_set_exact(void **state)
{
    (void)state;
    mm_database db;
    assert_int_equal(test_build_synth_database(&db), 0);
    mm_searcher s;
    assert_int_equal(mm_searcher_init(&s, &db, NULL, NULL), MM_OK);
    test_rng r = {0x5eed2};
    int n = getenv("MM_TEST_SEARCH_QUERIES") ? atoi(getenv("MM_TEST_SEARCH_QUERIES")) : 1500;
    if (n < 30) n = 30;
    float q[MM_SEARCH_MAX_DIMS];
    int found = 0;
    for (int i = 0; i < n; ++i) {
        mm_search_params p;
        make_case(&db, &r, i, q, &p);
        mm_search_result brute, fast, tb[5], tf[5];
        mm_searcher_search(&s, q, &p, MM_SEARCH_BRUTE, &brute, 1);
        mm_searcher_search(&s, q, &p, MM_SEARCH_FAST, &fast, 1);
        if (fast.frame != brute.frame)
            print_error("built-in set query %d: brute %d (%.9g), fast %d (%.9g)\n", i, brute.frame,
                        brute.cost, fast.frame, fast.cost);
        assert_int_equal(fast.frame, brute.frame);
        assert_true(fast.frame < 0 || fast.cost == brute.cost);
        found += brute.frame >= 0;
        int nb = mm_searcher_search(&s, q, &p, MM_SEARCH_BRUTE, tb, 5);
        int nf = mm_searcher_search(&s, q, &p, MM_SEARCH_FAST, tf, 5);
        assert_int_equal(nb, nf);
        for (int k = 0; k < nb; ++k) assert_int_equal(tb[k].frame, tf[k].frame);
    }
    assert_true(found > n / 3);
    print_message("built-in set: %d frames, %d queries: fast = brute force\n", db.frame_count, n);
    mm_searcher_free(&s);
    mm_database_free(&db);
}

/* ---- crafted databases -------------------------------------------------------------------- */

static void make_skeleton(mm_skeleton *s)
{
    assert_int_equal(mm_skeleton_init(s, 8, NULL), MM_OK);
    const char *names[8] = {"Hips",    "Spine2",     "LeftUpLeg", "LeftFoot",
                            "LeftToe", "RightUpLeg", "RightFoot", "RightToe"};
    const int parents[8] = {-1, 0, 0, 2, 3, 0, 5, 6};
    const float off[8][3] = {{0, 1, 0},          {0, 0.3f, 0},  {0.1f, 0, 0},  {0, -0.9f, 0},
                             {0, -0.05f, 0.15f}, {-0.1f, 0, 0}, {0, -0.9f, 0}, {0, -0.05f, 0.15f}};
    for (int j = 0; j < 8; ++j) {
        snprintf(s->joints[j].name, MM_NAME_MAX, "%s", names[j]);
        s->joints[j].parent = parents[j];
        s->joints[j].offset = mm_vec3_make(off[j][0], off[j][1], off[j][2]);
    }
    s->joints[0].flags = MM_JOINT_TRANSLATES;
}

/* Walks straight at speed while the feet swing with the given phase and stride. */
static void make_walk(mm_clip *clip, int frames, double speed, double stride)
{
    mm_skeleton s;
    make_skeleton(&s);
    assert_int_equal(mm_clip_init(clip, &s, frames, 60.0f, NULL), MM_OK);
    mm_skeleton_free(&s);
    for (int f = 0; f < frames; ++f) {
        double t = f / 60.0;
        mm_clip_positions(clip, f)[0] = mm_vec3_make(0, 1, (float)(speed * t));
        mm_clip_rotations(clip, f)[2] =
            mm_quat_from_axis_angle(mm_vec3_make(1, 0, 0), (float)(stride * sin(5 * t)));
        mm_clip_rotations(clip, f)[5] =
            mm_quat_from_axis_angle(mm_vec3_make(1, 0, 0), (float)(-stride * sin(5 * t)));
    }
}

/* Four clips: 0 slow walk (loop), 1 the same walk again (not a loop: duplicate frames), 2 fast
 * walk tagged Fast, 3 standing (idle). */
static mm_database crafted;
static mm_searcher crafted_s;

static int build_crafted(void)
{
    mm_clip clips[4];
    make_walk(&clips[0], 120, 1.0, 0.4);
    make_walk(&clips[1], 120, 1.0, 0.4);
    make_walk(&clips[2], 120, 3.0, 0.8);
    make_walk(&clips[3], 120, 0.0, 0.0);
    mm_config cfg;
    mm_config_defaults(&cfg);
    cfg.scale = 1;
    cfg.root_smoothing = 0;
    cfg.left_hand[0] = cfg.right_hand[0] = cfg.head[0] = 0;
    cfg.tag_count = 1;
    snprintf(cfg.tag_names[0], MM_TAG_NAME_MAX, "Fast");
    cfg.clip_count = 4;
    cfg.clips = calloc(4, sizeof(mm_config_clip));
    for (int i = 0; i < 4; ++i) {
        snprintf(cfg.clips[i].name, MM_NAME_MAX, "c%d", i);
        snprintf(cfg.clips[i].file, MM_PATH_MAX, "c%d.bvh", i);
    }
    cfg.clips[0].loop = true;
    cfg.clips[3].type = MM_CLIP_IDLE;
    cfg.clips[2].tag_range_count = 1;
    cfg.clips[2].tag_ranges = calloc(1, sizeof(mm_config_tag_range));
    cfg.clips[2].tag_ranges[0] = (mm_config_tag_range){0, 0.0f, 10.0f};
    mm_result r = mm_database_build(&cfg, clips, NULL, &crafted, NULL);
    for (int i = 0; i < 4; ++i) mm_clip_free(&clips[i]);
    mm_config_free(&cfg);
    if (r != MM_OK) return -1;
    return mm_searcher_init(&crafted_s, &crafted, NULL, NULL) == MM_OK ? 0 : -1;
}

static int best_of(const float *q, const mm_search_params *p)
{
    mm_search_result b, f;
    mm_searcher_search(&crafted_s, q, p, MM_SEARCH_BRUTE, &b, 1);
    mm_searcher_search(&crafted_s, q, p, MM_SEARCH_FAST, &f, 1);
    assert_int_equal(b.frame, f.frame);
    return b.frame;
}

static int clip_of(int f) { return f < 0 ? -1 : crafted.frame_clip[f]; }

#define METHODS_TESTED 3 /* brute, fast, facing */

static void test_filters(void **state)
{
    (void)state;
    const mm_database *db = &crafted;
    float q[MM_SEARCH_MAX_DIMS];
    mm_search_params p;
    mm_search_params_defaults(db, &p);
    p.next_pose_favour = 1.0f;
    int slow = db->clips[0].first_frame + 50, fast = db->clips[2].first_frame + 50;

    /* An exact copy of a frame finds it (cost 0), the duplicate in clip 1 loses on index. */
    mm_search_query_from_frames(db, db->clips[1].first_frame + 50, db->clips[1].first_frame + 50, q);
    assert_int_equal(best_of(q, &p), slow);
    /* The current frame is never a candidate; the other copy wins. */
    p.current_frame = slow;
    assert_int_equal(best_of(q, &p), db->clips[1].first_frame + 50);
    /* exclude_window only applies in the current frame's clip */
    p.exclude_window = 10;
    assert_int_equal(best_of(q, &p), db->clips[1].first_frame + 50);
    p.current_frame = -1;
    p.exclude_window = 0;

    /* Type: idle only. */
    mm_search_query_from_frames(db, fast, fast, q);
    assert_int_equal(best_of(q, &p), fast);
    p.type = MM_SEARCH_IDLE;
    assert_int_equal(clip_of(best_of(q, &p)), 3);
    p.type = MM_SEARCH_LOCOMOTION;
    assert_int_not_equal(clip_of(best_of(q, &p)), 3);
    p.type = MM_SEARCH_ANY;
    /* Tags: excluding Fast moves away from clip 2; requiring it keeps to clip 2. */
    p.excluded_tags = mm_search_tag_mask(db, "Fast");
    assert_int_equal(p.excluded_tags, 1);
    assert_int_not_equal(clip_of(best_of(q, &p)), 2);
    p.excluded_tags = 0;
    mm_search_query_from_frames(db, slow, slow, q);
    p.required_tags = 1;
    assert_int_equal(clip_of(best_of(q, &p)), 2);
    p.required_tags = 0;
    /* Requiring a tag that no idle frame has, with type idle: nothing. */
    p.required_tags = 1;
    p.type = MM_SEARCH_IDLE;
    mm_search_result none;
    assert_int_equal(mm_searcher_search(&crafted_s, q, &p, MM_SEARCH_FAST, &none, 1), 0);
    assert_int_equal(none.frame, -1);
    p.required_tags = 0;
    p.type = MM_SEARCH_ANY;

    /* end_margin: the last frame of a non-loop clip, searched for, is out with a margin. */
    int last = db->clips[1].first_frame + db->clips[1].frame_count - 1;
    mm_search_query_from_frames(db, last, last, q);
    assert_int_equal(best_of(q, &p), last);
    p.end_margin = 5;
    int f = best_of(q, &p);
    assert_true(f != last && (clip_of(f) != 1 || f < last - 4));
    p.end_margin = 0;
}

static void check_tree(const mm_searcher *s);

static void test_favours_and_ratio(void **state)
{
    (void)state;
    const mm_database *db = &crafted;
    float q[MM_SEARCH_MAX_DIMS], a[MM_SEARCH_MAX_DIMS], b[MM_SEARCH_MAX_DIMS];
    mm_search_params p;
    mm_search_params_defaults(db, &p);
    p.next_pose_favour = 1.0f;
    int current = db->clips[2].first_frame + 30, next = current + 1;
    int other = db->clips[1].first_frame + 60; /* far from the fast walk */
    mm_search_query_from_frames(db, next, next, a);
    mm_search_query_from_frames(db, other, other, b);
    for (int d = 0; d < db->dims_padded; ++d)
        q[d] = 0.45f * a[d] + 0.55f * b[d]; /* a little closer to other */
    p.current_frame = current;
    int plain = best_of(q, &p);
    assert_int_not_equal(plain, next);
    /* NextPoseFavour: the next frame's cost is multiplied by it; just under the ratio of the best
     * cost to the next frame's, the next frame wins; just over, it does not. */
    mm_search_result best_plain;
    mm_searcher_search(&crafted_s, q, &p, MM_SEARCH_BRUTE, &best_plain, 1);
    mm_search_terms tn;
    mm_search_cost_terms(db, q, &p, next, &tn);
    float base_next =
        tn.pose_position + tn.pose_velocity + tn.root_velocity + tn.traj_position + tn.traj_direction;
    assert_true(base_next > best_plain.cost);
    p.next_pose_favour = 0.99f * best_plain.cost / base_next;
    assert_int_equal(best_of(q, &p), next);
    p.next_pose_favour = 1.01f * best_plain.cost / base_next;
    assert_int_equal(best_of(q, &p), plain);
    p.next_pose_favour = 1.0f;
    /* The continuing bias does the same by subtraction. */
    mm_search_result r;
    mm_searcher_search(&crafted_s, q, &p, MM_SEARCH_BRUTE, &r, 1);
    p.continuing_bias = r.cost; /* the next frame's base is above r.cost, but not by this much */
    mm_search_terms t;
    mm_search_cost_terms(db, q, &p, next, &t);
    float next_base =
        t.pose_position + t.pose_velocity + t.root_velocity + t.traj_position + t.traj_direction;
    p.continuing_bias = next_base - r.cost * 0.5f;
    assert_int_equal(best_of(q, &p), next);
    p.continuing_bias = 0.0f;

    /* LoopAnimFavour: the loop clip 0 against its non-loop duplicate in clip 1 (equal costs: the
     * lower index, in clip 0, wins anyway); a favour above 1 penalises loops and clip 1 wins. */
    p.current_frame = -1;
    mm_search_query_from_frames(db, db->clips[1].first_frame + 40, db->clips[1].first_frame + 40, q);
    for (int d = 0; d < db->dims; ++d) q[d] += 0.05f;
    assert_int_equal(clip_of(best_of(q, &p)), 0);
    p.loop_anim_favour = 1.5f;
    assert_int_equal(clip_of(best_of(q, &p)), 1);
    p.loop_anim_favour = 1.0f;

    /* The contact favour: the frames of clip 2 (all tagged Fast) get contacts of their own, the
     * pattern of the frame playing; a query a little closer to clip 1 is won there, at base bw
     * (the best frame without the tag), against bm (the best with it). A factor on the others
     * just over bm / bw gives the win to clip 2, just under it does not; pattern -1 turns it off. */
    mm_database hand = crafted; /* shares everything but the contacts */
    uint8_t *contacts = calloc((size_t)db->frame_count, 1);
    for (int k = 0; k < db->clips[2].frame_count; ++k)
        contacts[db->clips[2].first_frame + k] = MM_CONTACT_LEFT_HEEL | MM_CONTACT_RIGHT_TOE;
    hand.contacts = contacts;
    mm_searcher hs;
    assert_int_equal(mm_searcher_init(&hs, &hand, NULL, NULL), MM_OK);
    check_tree(&hs);
    for (int d = 0; d < db->dims_padded; ++d) q[d] = 0.45f * a[d] + 0.55f * b[d];
    p.current_frame = -1;
    mm_search_result w, m, got[METHODS_TESTED];
    p.excluded_tags = 1;
    mm_searcher_search(&hs, q, &p, MM_SEARCH_BRUTE, &w, 1);
    p.excluded_tags = 0;
    p.required_tags = 1;
    mm_searcher_search(&hs, q, &p, MM_SEARCH_BRUTE, &m, 1);
    p.required_tags = 0;
    assert_int_equal(clip_of(m.frame), 2);
    assert_true(w.frame >= 0 && clip_of(w.frame) != 2 && m.base > w.base);
    const mm_search_method methods[METHODS_TESTED] = {MM_SEARCH_BRUTE, MM_SEARCH_FAST, MM_SEARCH_FACING};
    p.facing_threshold = 3.3f; /* the pre-filter leaves every frame of these walks in */
    const float factors[3] = {0.99f * m.base / w.base, 1.01f * m.base / w.base, 100.0f};
    const int pattern[3] = {MM_CONTACT_LEFT_HEEL | MM_CONTACT_RIGHT_TOE,
                            MM_CONTACT_LEFT_HEEL | MM_CONTACT_RIGHT_TOE, -1};
    const int winner[3] = {w.frame, m.frame, w.frame};
    for (int k = 0; k < 3; ++k) {
        p.contact_pattern = pattern[k];
        p.contact_mismatch_favour = factors[k];
        for (int j = 0; j < METHODS_TESTED; ++j) {
            mm_searcher_search(&hs, q, &p, methods[j], &got[j], 1);
            assert_int_equal(got[j].frame, winner[k]);
        }
        /* the cost: the base, times the factor where the contacts differ */
        float expect = winner[k] == w.frame && pattern[k] >= 0 ? w.base * factors[k] : got[0].base;
        assert_true(got[0].cost == expect);
        mm_search_result batch;
        mm_searcher_batch(&hs, q, &p, 0, MM_SEARCH_FAST, &batch, 1);
        assert_int_equal(batch.frame, winner[k]);
    }
    p.contact_pattern = -1;
    p.contact_mismatch_favour = 1.0f;
    p.facing_threshold = 1.0f;
    mm_searcher_free(&hs);
    free(contacts);

    /* PoseTrajectoryRatio: 1 matches the trajectory only, 0 the pose only. */
    int pose_frame = db->clips[3].first_frame + 10, traj_frame = db->clips[2].first_frame + 70;
    mm_search_query_from_frames(db, pose_frame, traj_frame, q);
    p.pose_trajectory_ratio = 1.0f;
    int f = best_of(q, &p);
    mm_search_cost_terms(db, q, &p, f, &t);
    assert_near(t.traj_position + t.traj_direction, 0, 1e-6);
    assert_near(t.pose_position + t.pose_velocity, 0, 0); /* weighted 0 */
    p.pose_trajectory_ratio = 0.0f;
    f = best_of(q, &p);
    assert_int_equal(clip_of(f), 3);
    mm_search_cost_terms(db, q, &p, f, &t);
    assert_near(t.pose_position + t.pose_velocity + t.root_velocity, 0, 1e-6);
}

/* ---- the searcher's tree ------------------------------------------------------------------ */

/* Checks lane l of node n and everything below: its frames lie inside its box (in the tree's
 * coordinates, on the axes the boxes use) and match its summaries; returns the frames seen. */
static int check_lane(const mm_searcher *s, int n, int l, int depth)
{
    const mm_database *db = s->db;
    const mm_search_node *node = &s->nodes[n];
    int dims = db->dims_padded, td = s->tree_dims;
    assert_true(depth < 64);
    assert_true(node->begin[l] < node->end[l]);
    const float *lo = s->boxes + (size_t)n * 2 * td * MM_SEARCH_WIDTH;
    const float *hi = lo + (size_t)td * MM_SEARCH_WIDTH;
    unsigned patterns = 0; /* the contact patterns of the lane's frames */
    for (int p = node->begin[l]; p < node->end[l]; ++p) {
        int f = s->order[p];
        patterns |= 1u << db->contacts[f];
        assert_true(f >= node->min_frame[l]);
        assert_int_equal(s->order_tags[p], db->frame_tags[f]);
        assert_int_equal(s->order_clip[p], db->frame_clip[f]);
        assert_true(node->types[l] & (1u << db->clips[db->frame_clip[f]].type));
        assert_int_equal(db->frame_tags[f] & ~node->tags_any[l], 0);
        assert_int_equal(node->tags_all[l] & ~db->frame_tags[f], 0);
        if (db->clips[db->frame_clip[f]].loop)
            assert_true(node->loop[l] & 1);
        else
            assert_false(node->loop[l] & 2);
        assert_memory_equal(s->features + (size_t)p * dims, db->features + (size_t)f * dims,
                            sizeof(float) * (size_t)dims);
        for (int j = 0; j < td; ++j) {
            double z = 0.0;
            for (int k = 0; k < dims; ++k)
                z += s->basis[(size_t)k * td + j] *
                     (s->sqrt_w0[k] * (double)db->features[(size_t)f * dims + k] - s->center[k]);
            assert_true(z >= lo[j * MM_SEARCH_WIDTH + l] && z <= hi[j * MM_SEARCH_WIDTH + l]);
        }
    }
    assert_int_equal(node->contacts[l], patterns);
    if (node->child[l] < 0) {
        assert_true(node->end[l] - node->begin[l] <= MM_SEARCH_LEAF);
        return node->end[l] - node->begin[l];
    }
    /* the child's lanes split this lane's positions, in order */
    const mm_search_node *child = &s->nodes[node->child[l]];
    assert_true(child->count >= 1 && child->count <= MM_SEARCH_WIDTH);
    int at = node->begin[l], seen = 0;
    for (int i = 0; i < child->count; ++i) {
        assert_int_equal(child->begin[i], at);
        at = child->end[i];
        seen += check_lane(s, node->child[l], i, depth + 1);
    }
    assert_int_equal(at, node->end[l]);
    return seen;
}

/* The quantized copy: every dimension of default weight above 0 has one slot; each code stands for
 * its feature within half a step (the end codes also for everything beyond the grid), in the
 * documented layout. This is what the first pass's bound rests on. */
static void check_quantized(const mm_searcher *s)
{
    const mm_database *db = s->db;
    int dims = db->dims_padded, slots = s->quant_slots, head = s->quant_head;
    size_t blocks = ((size_t)db->frame_count + 15) / 16;
    int weighted = 0;
    for (int d = 0; d < dims; ++d) weighted += s->w0[d] > 0.0f;
    assert_int_equal(slots, weighted);
    assert_true(head >= 0 && head <= slots);
    char seen[MM_SEARCH_MAX_DIMS] = {0};
    long interior = 0;
    for (int j = 0; j < slots; ++j) {
        int d = s->quant_order[j];
        assert_true(d >= 0 && d < dims && s->w0[d] > 0.0f && !seen[d]);
        seen[d] = 1;
        assert_true(s->quant_step[d] > 0.0);
        for (int p = 0; p < db->frame_count; ++p) {
            size_t b = (size_t)p / 16;
            const uint8_t *codes = j < head
                                       ? s->quantized + (b * head + j) * 16
                                       : s->quantized + 16 * (blocks * head + b * (slots - head) + j - head);
            int c = codes[p % 16];
            double v = (s->features[(size_t)p * dims + d] - s->quant_lo[d]) / s->quant_step[d];
            if (c > 0) assert_true(v >= c - 0.5 - 1e-9);
            if (c < 255) assert_true(v <= c + 0.5 + 1e-9);
            interior += c > 0 && c < 255;
        }
    }
    assert_true(interior > 0);
}

/* The tree covers every frame once, each lane's box holds its frames, and the work units tile
 * the frames in order. */
static void check_tree(const mm_searcher *s)
{
    const mm_database *db = s->db;
    assert_true(s->tree_dims >= 4 && s->tree_dims <= db->dims_padded + 8 && s->tree_dims % 4 == 0);
    assert_true(s->pose_dims >= 0 && s->pose_dims < s->tree_dims && s->pose_dims % 4 == 0);
    char *seen = calloc((size_t)db->frame_count, 1);
    for (int p = 0; p < db->frame_count; ++p) {
        assert_true(s->order[p] >= 0 && s->order[p] < db->frame_count);
        assert_false(seen[s->order[p]]);
        seen[s->order[p]] = 1;
    }
    free(seen);
    const mm_search_node *root = &s->nodes[0];
    int at = 0, total = 0;
    for (int l = 0; l < root->count; ++l) {
        assert_int_equal(root->begin[l], at);
        at = root->end[l];
        total += check_lane(s, 0, l, 0);
    }
    assert_int_equal(at, db->frame_count);
    assert_int_equal(total, db->frame_count);
    assert_true(s->unit_count >= 1 && s->unit_count <= MM_SEARCH_MAX_UNITS);
    at = 0;
    for (int u = 0; u < s->unit_count; ++u) {
        const mm_search_node *n = &s->nodes[s->units[u] / MM_SEARCH_WIDTH];
        int l = s->units[u] % MM_SEARCH_WIDTH;
        assert_true(l < n->count);
        assert_int_equal(n->begin[l], at);
        at = n->end[l];
    }
    assert_int_equal(at, db->frame_count);
    check_quantized(s);
}

static void test_tree(void **state)
{
    (void)state;
    mm_searcher s;
    assert_int_equal(mm_searcher_init(&s, &real_db, NULL, NULL), MM_OK);
    check_tree(&s);
    mm_searcher_free(&s);
    check_tree(&crafted_s);
}

/* A database of one walk of the given length (a loop) and a standing clip half as long. */
static int build_small(mm_database *db, int frames)
{
    mm_clip clips[2];
    make_walk(&clips[0], frames, 1.3, 0.5);
    make_walk(&clips[1], frames / 2 + 1, 0.0, 0.1);
    mm_config cfg;
    mm_config_defaults(&cfg);
    cfg.scale = 1;
    cfg.root_smoothing = 0;
    cfg.left_hand[0] = cfg.right_hand[0] = cfg.head[0] = 0;
    cfg.clip_count = 2;
    cfg.clips = calloc(2, sizeof(mm_config_clip));
    for (int i = 0; i < 2; ++i) {
        snprintf(cfg.clips[i].name, MM_NAME_MAX, "s%d", i);
        snprintf(cfg.clips[i].file, MM_PATH_MAX, "s%d.bvh", i);
    }
    cfg.clips[0].loop = true;
    cfg.clips[1].type = MM_CLIP_IDLE;
    mm_result r = mm_database_build(&cfg, clips, NULL, db, NULL);
    for (int i = 0; i < 2; ++i) mm_clip_free(&clips[i]);
    mm_config_free(&cfg);
    return r == MM_OK ? 0 : -1;
}

/* Trees of every shape (a single leaf, a root with few lanes, uneven splits) give the brute-force
 * winner, on one thread and over a pool (work units that are leaves). */
static void test_small_trees(void **state)
{
    (void)state;
    const int lengths[] = {2, 9, 17, 23, 40, 77, 150, 333};
    test_rng r = {0xBEEF};
    for (size_t i = 0; i < sizeof lengths / sizeof lengths[0]; ++i) {
        mm_database db;
        assert_int_equal(build_small(&db, lengths[i]), 0);
        mm_searcher one, two;
        mm_searcher_desc d2 = {2, NULL};
        assert_int_equal(mm_searcher_init(&one, &db, NULL, NULL), MM_OK);
        assert_int_equal(mm_searcher_init(&two, &db, &d2, NULL), MM_OK);
        check_tree(&one);
        check_tree(&two);
        float q[MM_SEARCH_MAX_DIMS];
        for (int k = 0; k < 120; ++k) {
            mm_search_params p;
            make_case(&db, &r, k, q, &p);
            mm_search_result brute, fast, fast2;
            mm_searcher_search(&one, q, &p, MM_SEARCH_BRUTE, &brute, 1);
            mm_searcher_search(&one, q, &p, MM_SEARCH_FAST, &fast, 1);
            mm_searcher_search(&two, q, &p, MM_SEARCH_FAST, &fast2, 1);
            assert_int_equal(fast.frame, brute.frame);
            assert_int_equal(fast2.frame, brute.frame);
            if (brute.frame >= 0) assert_true(fast.cost == brute.cost);
        }
        mm_searcher_free(&one);
        mm_searcher_free(&two);
        mm_database_free(&db);
    }
}

/* A query built from a PoseData view equals the one built from the frame itself. */
static void test_query_from_pose(void **state)
{
    (void)state;
    const mm_database *db = &crafted;
    float a[MM_SEARCH_MAX_DIMS], b[MM_SEARCH_MAX_DIMS];
    for (int f = 0; f < db->frame_count; f += 37) {
        mm_pose_data pd;
        mm_database_pose(db, f, &pd);
        mm_search_query_from_pose(db, &pd, a);
        mm_search_query_from_frames(db, f, f, b);
        for (int d = 0; d < db->dims_padded; ++d) assert_near(a[d], b[d], 1e-4);
    }
}

static int setup(void **state)
{
    (void)state;
    return build_real() == 0 && build_crafted() == 0 ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    mm_searcher_free(&crafted_s);
    mm_database_free(&crafted);
    mm_database_free(&real_db);
    return 0;
}

/* ---- the kinds of query games make, and ties ---------------------------------------------- */

/* A query of kind (0 near: frame a plus noise, 1 transition: the pose of a and the trajectory of
 * b, 2 random in feature space), with the database's default parameters and a as current frame. */
static void make_kind(const mm_database *db, test_rng *r, int kind, float *q, mm_search_params *p)
{
    int a = (int)test_rng_uniform(r, 0, db->frame_count), b = (int)test_rng_uniform(r, 0, db->frame_count);
    mm_search_params_defaults(db, p);
    p->current_frame = a;
    if (kind == 0) {
        mm_search_query_from_frames(db, a, a, q);
        for (int d = 0; d < db->dims; ++d) q[d] += (float)(0.1 * normal(r));
    } else if (kind == 1) {
        mm_search_query_from_frames(db, a, b, q);
    } else {
        memset(q, 0, sizeof(float) * (size_t)db->dims_padded);
        for (int d = 0; d < db->dims; ++d) q[d] = (float)normal(r);
    }
}

/* Brute force is the reference: the fast search's winner is the same frame at the same cost; and
 * brute force's own answer obeys the tie rule (no frame within the tolerance of the lowest cost has
 * a lower index: checked over all frames with the cost terms). Returns whether the answer was a
 * tie (another candidate within the tolerance). */
static int check_query(const mm_searcher *s, const float *q, const mm_search_params *p, const char *what,
                       int i)
{
    mm_search_result brute, fast, top[2];
    mm_searcher_search(s, q, p, MM_SEARCH_BRUTE, &brute, 1);
    mm_searcher_search(s, q, p, MM_SEARCH_FAST, &fast, 1);
    if (fast.frame != brute.frame)
        print_error("%s query %d: brute %d (%.9g), fast %d (%.9g)\n", what, i, brute.frame, brute.cost,
                    fast.frame, fast.cost);
    assert_int_equal(fast.frame, brute.frame);
    assert_true(fast.cost == brute.cost);
    /* the first of the best k is the winner whatever k, both methods: the tie rule's frame, its
     * cost and base bit for bit (k 2 and 16: the list holds every tie, or some are left out) */
    for (int m = 0; m < 2; ++m)
        for (int k = 2; k <= 16; k += 14) {
            mm_search_result list[16];
            int found = mm_searcher_search(s, q, p, m ? MM_SEARCH_BRUTE : MM_SEARCH_FAST, list, k);
            assert_true(found >= 1);
            assert_int_equal(list[0].frame, brute.frame);
            assert_memory_equal(&list[0].cost, &brute.cost, sizeof(float));
            assert_memory_equal(&list[0].base, &brute.base, sizeof(float));
            /* hinted: the list's own frames (the tightest bound: the k-th cost itself; reversed,
             * repeated, with -1, a frame past the end and the current frame), then the frames
             * after them (a looser bound): the same list bit for bit */
            for (int h = 0; h < 2; ++h) {
                int hints[MM_SEARCH_MAX_HINTS], count = 0;
                for (int j = found - 1; j >= 0; --j) hints[count++] = list[j].frame + h;
                hints[count++] = list[0].frame + h;
                hints[count++] = -1;
                hints[count++] = s->db->frame_count;
                hints[count++] = p->current_frame;
                mm_search_result again[16];
                int n2 = mm_searcher_search_hinted(s, q, p, m ? MM_SEARCH_BRUTE : MM_SEARCH_FAST, again, k,
                                                   hints, count, NULL);
                assert_int_equal(n2, found);
                assert_memory_equal(again, list, sizeof(mm_search_result) * (size_t)found);
            }
        }
    int n = mm_searcher_search(s, q, p, MM_SEARCH_BRUTE, top, 2);
    return n == 2 && top[1].cost <= brute.cost + 1e-6f * fabsf(brute.cost) && top[1].frame != brute.frame;
}

/* Every kind of query on database db (named name), and what characters searched with on random
 * input (the database's runtime settings: the ratio, favours, tags and type the runtime sets). */
static void kinds_equal_brute(const mm_database *db, const char *name, uint64_t seed)
{
    mm_searcher s;
    assert_int_equal(mm_searcher_init(&s, db, NULL, NULL), MM_OK);
    test_rng r = {seed};
    int n = getenv("MM_TEST_SEARCH_QUERIES") ? atoi(getenv("MM_TEST_SEARCH_QUERIES")) / 3 : 300;
    if (n < 10) n = 10;
    float q[MM_SEARCH_MAX_DIMS];
    const char *names[3] = {"near", "transition", "random"};
    for (int kind = 0; kind < 3; ++kind)
        for (int i = 0; i < n; ++i) {
            mm_search_params p;
            make_kind(db, &r, kind, q, &p);
            with_contact_favour(db, i, p.current_frame, &p);
            check_query(&s, q, &p, names[kind], i);
        }
    /* recorded: characters on random input; each search's query and parameters, and the answer the
     * character got (the fast search) is brute force's */
    mm_character_desc desc;
    assert_int_equal(mm_character_desc_from_database(&desc, db, NULL), MM_OK);
    int recorded = 0, ratios = 0;
    for (int k = 0; k < 4 && recorded < n; ++k) {
        mm_character c;
        mm_input_script script;
        mm_input_random_desc rd = {30.0f, 0, 0, 0, 0, NULL};
        assert_int_equal(mm_input_script_random(&script, 77 + (uint64_t)k, &rd), MM_OK);
        assert_int_equal(mm_character_init(&c, db, &s, &desc, NULL), MM_OK);
        int searches = 0;
        for (int t = 0; t < 30 * 60 && recorded < n; ++t) {
            mm_input in;
            mm_input_script_sample(&script, t / 60.0f, &in);
            mm_character_update(&c, &in, 1.0f / 60.0f);
            if (c.searches == searches) continue;
            searches = c.searches;
            mm_search_result brute;
            mm_searcher_search(&s, c.query, &c.last_params, MM_SEARCH_BRUTE, &brute, 1);
            assert_int_equal(c.last_result.frame, brute.frame);
            check_query(&s, c.query, &c.last_params, "recorded", recorded++);
            ratios += c.last_params.pose_trajectory_ratio != c.desc.params.pose_trajectory_ratio;
        }
        mm_character_free(&c);
        mm_input_script_free(&script);
    }
    assert_true(recorded >= n / 2);
    print_message(
        "%s: near, transition, random (%d each) and %d recorded queries (%d with the ratio the runtime "
        "moved): fast = brute force\n",
        name, n, recorded, ratios);
    mm_searcher_free(&s);
}

static void test_kinds_equal_brute(void **state)
{
    (void)state;
    kinds_equal_brute(&real_db, real_name, 0x5eed);
}

/* The same on the generated built-in set whatever the real database is (with MM_DATA_DIR set, the
 * test above runs on LAFAN1): every kind of query, recorded ones included. */
static void test_builtin_set_kinds_equal_brute(void **state)
{
    (void)state;
    if (!lafan_loaded) skip(); /* the real database is the built-in set: the test above */
    mm_database db;
    assert_int_equal(test_build_synth_database(&db), 0);
    kinds_equal_brute(&db, "built-in set", 0x5eed3);
    mm_database_free(&db);
}

/* The first pass's bound with weights and queries far from the defaults: queries far outside the
 * quantized grid, one dimension weighing 1000 times the others, weights of 0, loop favours of 0 and
 * a NaN in the query; the fast search still returns brute force's winner, and on near queries the
 * bound leaves few frames to evaluate exactly. */
static void test_quantized_bound(void **state)
{
    (void)state;
    const mm_database *db = &real_db;
    mm_searcher s;
    assert_int_equal(mm_searcher_init(&s, db, NULL, NULL), MM_OK);
    test_rng r = {0x9a47};
    float q[MM_SEARCH_MAX_DIMS];
    long bounded = 0, evaluated = 0;
    for (int i = 0; i < 120; ++i) {
        mm_search_params p;
        make_kind(db, &r, i % 3, q, &p);
        switch (i % 6) {
        case 1: /* far outside the grid */
            for (int d = 0; d < db->dims; ++d) q[d] *= 40.0f;
            break;
        case 2: /* one bone's weight dominates, another's is 0 */
            p.joint_position_weights[0] = 1000.0f;
            p.joint_velocity_weights[0] = 0.0f;
            break;
        case 3: /* the trajectory alone */
            p.pose_trajectory_ratio = 1.0f;
            p.loop_anim_favour = 0.0f;
            break;
        case 4: /* tiny weights everywhere but the trajectory directions */
            for (int b = 0; b < MM_MAX_MATCH_BONES; ++b) p.joint_position_weights[b] = 1e-4f;
            p.angle_multiplier = 50.0f;
            break;
        case 5: /* a query exactly on a frame */
            mm_search_query_from_frames(db, p.current_frame, p.current_frame, q);
            p.current_frame = -1;
            break;
        }
        check_query(&s, q, &p, "quantized bound", i);
        if (i % 6 == 0 && i % 3 == 0) { /* near queries with default weights */
            mm_search_result res;
            mm_search_stats st;
            mm_searcher_search_stats(&s, q, &p, MM_SEARCH_FAST, &res, 1, &st);
            bounded += st.frames_bounded;
            evaluated += st.frames_evaluated;
        }
    }
    assert_true(bounded > 0);
    /* the bound prunes most frames it sees on motion capture (LAFAN1: 3% evaluated); the built-in
     * set's near queries (noise 0.1 of a feature's spread) have half its frames about as close */
    if (lafan_loaded)
        assert_true(evaluated * 4 < bounded);
    else
        assert_true(evaluated * 3 < bounded * 2);
    /* a NaN in the query: every cost is NaN; brute force and the fast search agree */
    mm_search_params p;
    make_kind(db, &r, 0, q, &p);
    q[0] = NAN;
    mm_search_result brute, fast;
    mm_searcher_search(&s, q, &p, MM_SEARCH_BRUTE, &brute, 1);
    mm_searcher_search(&s, q, &p, MM_SEARCH_FAST, &fast, 1);
    assert_int_equal(fast.frame, brute.frame);
    print_message("quantized bound: %ld of %ld frames bounded on near queries evaluated exactly\n", evaluated,
                  bounded);
    mm_searcher_free(&s);
}

/* Queries beyond the quantized grid on some dimensions (past its end point by a fraction of a step
 * to several ranges of the grid, below and above): the fast search returns brute force's winner, and
 * on near queries moved far beyond on one dimension the first pass still leaves few frames to
 * evaluate exactly (every frame not at the grid's end code on that dimension has the query's distance
 * beyond the grid in its bound; without it the bound of every frame lacks that distance, which then
 * dominates every cost, and the frames it bounds are nearly all evaluated). */
static void test_quantized_beyond_grid(void **state)
{
    (void)state;
    const mm_database *db = &real_db;
    mm_searcher s;
    assert_int_equal(mm_searcher_init(&s, db, NULL, NULL), MM_OK);
    test_rng r = {0xbe70};
    float q[MM_SEARCH_MAX_DIMS];
    const double past[7] = {0.3, 0.7, 2.5, 12.0, 40.0, 120.0, 5000.0}; /* in steps of the grid */
    long bounded = 0, evaluated = 0;
    for (int i = 0; i < 180; ++i) {
        mm_search_params p;
        make_kind(db, &r, i % 3, q, &p);
        int moved = 1 + i % 3; /* dimensions moved beyond the grid */
        for (int m = 0; m < moved; ++m) {
            int d = s.quant_order[(i * 7 + m * 5) % s.quant_slots];
            double e = past[(i / 3 + m) % 7] * s.quant_step[d];
            q[d] = (i + m) % 2 ? (float)(s.quant_lo[d] - e)
                               : (float)(s.quant_lo[d] + 255.0 * s.quant_step[d] + e);
        }
        if (i % 4 == 1) with_contact_favour(db, i, i, &p);
        check_query(&s, q, &p, "beyond the grid", i);
        double e = past[(i / 3) % 7];
        if (i % 3 == 0 && moved == 1 && e >= 12.0 && e <= 120.0) { /* near, far beyond on one */
            mm_search_result res;
            mm_search_stats st;
            mm_searcher_search_stats(&s, q, &p, MM_SEARCH_FAST, &res, 1, &st);
            bounded += st.frames_bounded;
            evaluated += st.frames_evaluated;
        }
    }
    print_message("beyond the grid: %ld of %ld frames bounded on near queries evaluated exactly\n", evaluated,
                  bounded);
    assert_true(bounded > 0);
    /* LAFAN1: 3% evaluated (34% without the distance beyond the grid); the built-in set's near
     * queries have more frames about as close: 25% (45% without) */
    assert_true(evaluated * (lafan_loaded ? 4 : 3) < bounded);
    mm_searcher_free(&s);
}

/* The scan that replaces the tree walk when the bounds prune almost nothing (random queries): such a
 * query bounds every position of the quantized copy exactly once (the nearest-first phase's leaves,
 * then every other position in memory order: frames bounded = frames), and its answers are brute
 * force's, the k = 5 list included (frames, costs, order), with favours, filters and ratios; queries
 * whose box bounds are all 0 take it; near queries do not (far fewer frames bounded). */
static void test_scan_when_bounds_fail(void **state)
{
    (void)state;
    const mm_database *db = &real_db;
    mm_searcher s;
    assert_int_equal(mm_searcher_init(&s, db, NULL, NULL), MM_OK);
    test_rng r = {0x5ca7};
    float q[MM_SEARCH_MAX_DIMS];
    int scanned = 0, queries = 60;
    for (int i = 0; i < queries; ++i) {
        mm_search_params p;
        make_kind(db, &r, 2, q, &p);
        /* a weight of 0 in the pose block and in the trajectory block: each block's least ratio of the
         * weights to the defaults is 0, so every box bound is 0 and the scan is expected */
        int blind = i % 2 == 0;
        if (blind) {
            p.joint_position_weights[0] = 0.0f;
            p.position_multiplier = 0.0f;
        } else if (i % 3 == 1)
            with_contact_favour(db, i, p.current_frame, &p);
        if (!blind && i % 4 == 3) p.pose_trajectory_ratio = (float)test_rng_uniform(&r, 0, 1);
        if (!blind && i % 5 == 3) p.type = MM_SEARCH_LOCOMOTION;
        if (!blind && i % 3 == 2) p.loop_anim_favour = 0.5f;
        check_query(&s, q, &p, "scan", i);
        mm_search_result fast[5], brute[5];
        mm_search_stats st;
        int n = mm_searcher_search_stats(&s, q, &p, MM_SEARCH_FAST, fast, 5, &st);
        assert_int_equal(mm_searcher_search(&s, q, &p, MM_SEARCH_BRUTE, brute, 5), n);
        for (int j = 0; j < n; ++j) {
            assert_int_equal(fast[j].frame, brute[j].frame);
            assert_true(fast[j].cost == brute[j].cost);
        }
        mm_searcher_search_stats(&s, q, &p, MM_SEARCH_FAST, fast, 1, &st);
        assert_true(st.frames_bounded <= db->frame_count); /* no position twice */
        scanned += blind && st.frames_bounded == db->frame_count;
    }
    print_message("scan: %d of %d queries whose boxes bound nothing scanned every position\n", scanned,
                  queries / 2);
    assert_int_equal(scanned, queries / 2);
    for (int i = 0; i < 30; ++i) { /* near queries keep the tree */
        mm_search_params p;
        make_kind(db, &r, 0, q, &p);
        mm_search_result res;
        mm_search_stats st;
        mm_searcher_search_stats(&s, q, &p, MM_SEARCH_FAST, &res, 1, &st);
        assert_true(st.frames_bounded < db->frame_count / 4);
    }
    mm_searcher_free(&s);
}

/* Ties: the real database with its features on a coarse grid (many frames then have exactly the
 * same features, so exact ties are everywhere), every kind of query; the fast search returns
 * brute force's winner, the lowest index among the tied. */
static void test_ties_every_kind(void **state)
{
    (void)state;
    mm_database coarse = real_db; /* shares everything but the features */
    size_t count = (size_t)real_db.frame_count * real_db.dims_padded;
    float *features = malloc(sizeof(float) * count);
    for (size_t i = 0; i < count; ++i) features[i] = roundf(real_db.features[i] * 2.0f) * 0.5f;
    coarse.features = features;
    mm_searcher s;
    assert_int_equal(mm_searcher_init(&s, &coarse, NULL, NULL), MM_OK);
    check_tree(&s);
    test_rng r = {0x7e5};
    int n = getenv("MM_TEST_SEARCH_QUERIES") ? atoi(getenv("MM_TEST_SEARCH_QUERIES")) / 3 : 300;
    if (n < 10) n = 10;
    float q[MM_SEARCH_MAX_DIMS];
    int ties = 0;
    for (int kind = 0; kind < 4; ++kind)
        for (int i = 0; i < n; ++i) {
            mm_search_params p;
            make_kind(&coarse, &r, kind % 3, q, &p);
            if (kind == 3) { /* the query on the grid too: cost 0 for every frame on its point */
                for (int d = 0; d < coarse.dims; ++d) q[d] = roundf(q[d] * 2.0f) * 0.5f;
                p.current_frame = -1;
            }
            if (i % 2) p.pose_trajectory_ratio = (float)test_rng_uniform(&r, 0, 1);
            with_contact_favour(&coarse, i + kind, i, &p);
            ties += check_query(&s, q, &p, "coarse grid", i);
        }
    print_message("coarse-grid database: %d queries, %d with ties: fast = brute force\n", 4 * n, ties);
    assert_true(ties > n / 2);
    mm_searcher_free(&s);
    free(features);
}

/* The 256-bit kernels (AVX and AVX2, where the machine has them) against the 128-bit ones: every
 * method and kind of query, near and far from the grid, k of 1 and 5, a NaN: the same frames and
 * costs bit for bit, and the same work (frames bounded and evaluated, boxes), so every bound and
 * every quantized mask on the way was the same. */
static void test_wide_kernels(void **state)
{
    (void)state;
    const mm_database *db = &real_db;
    mm_searcher s;
    assert_int_equal(mm_searcher_init(&s, db, NULL, NULL), MM_OK);
    test_rng r = {0x3d1};
    float q[MM_SEARCH_MAX_DIMS];
    const mm_search_method methods[3] = {MM_SEARCH_FAST, MM_SEARCH_BRUTE, MM_SEARCH_FACING};
    for (int i = 0; i < 90; ++i) {
        mm_search_params p;
        make_case(db, &r, i, q, &p);
        if (i % 10 == 4)
            for (int d = 0; d < db->dims; ++d) q[d] *= 40.0f; /* outside the quantized grid */
        if (i == 89) q[1] = NAN;
        mm_search_method m = methods[i % 5 == 2 ? 1 : i % 5 == 3 ? 2 : 0];
        for (int k = 1; k <= 5; k += 4) {
            mm_search_result res[2][5];
            mm_search_stats st[2];
            int n[2];
            for (int wide = 0; wide < 2; ++wide) {
                mm__math_wide_kernels(wide == 1);
                n[wide] = mm_searcher_search_stats(&s, q, &p, m, res[wide], k, &st[wide]);
            }
            mm__math_wide_kernels(true);
            assert_int_equal(n[0], n[1]);
            assert_int_equal(st[0].frames_evaluated, st[1].frames_evaluated);
            assert_int_equal(st[0].frames_bounded, st[1].frames_bounded);
            assert_int_equal(st[0].boxes_tested, st[1].boxes_tested);
            for (int j = 0; j < n[0]; ++j) {
                assert_int_equal(res[0][j].frame, res[1][j].frame);
                assert_memory_equal(&res[0][j].cost, &res[1][j].cost, sizeof(float));
                assert_memory_equal(&res[0][j].base, &res[1][j].base, sizeof(float));
            }
        }
    }
    mm_searcher_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_exact_equals_brute),
        cmocka_unit_test(test_builtin_set_exact),
        cmocka_unit_test(test_filters),
        cmocka_unit_test(test_favours_and_ratio),
        cmocka_unit_test(test_query_from_pose),
        cmocka_unit_test(test_tree),
        cmocka_unit_test(test_small_trees),
        cmocka_unit_test(test_kinds_equal_brute),
        cmocka_unit_test(test_builtin_set_kinds_equal_brute),
        cmocka_unit_test(test_ties_every_kind),
        cmocka_unit_test(test_quantized_bound),
        cmocka_unit_test(test_quantized_beyond_grid),
        cmocka_unit_test(test_scan_when_bounds_fail),
        cmocka_unit_test(test_wide_kernels),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
