/* Pose similarity and the fusion / link tables on crafted databases whose answers are known, the
 * tables file, and a check on real motion (LAFAN1 with MM_DATA_DIR, else the built-in set). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <unistd.h>

#include <mm/config_json.h>
#include <mm/database_build.h>
#include <mm/similarity.h>
#include <mm/synth.h>

#include "test_databases.h"
#include "test_util.h"

/* Hips 1 m up, a spine joint, feet and toes; the feet pitch (about X) by angles that the motion
 * gives, so the toes move. */
static void make_skeleton(mm_skeleton *s)
{
    assert_int_equal(mm_skeleton_init(s, 6, NULL), MM_OK);
    const char *names[6] = {"Hips", "Spine2", "LeftFoot", "LeftToe", "RightFoot", "RightToe"};
    const int parents[6] = {-1, 0, 0, 2, 0, 4};
    const float off[6][3] = {{0, 1, 0},          {0, 0.3f, 0},      {0.1f, -0.9f, 0},
                             {0, -0.05f, 0.15f}, {-0.1f, -0.9f, 0}, {0, -0.05f, 0.15f}};
    for (int j = 0; j < 6; ++j) {
        snprintf(s->joints[j].name, MM_NAME_MAX, "%s", names[j]);
        s->joints[j].parent = parents[j];
        s->joints[j].offset = mm_vec3_make(off[j][0], off[j][1], off[j][2]);
        s->joints[j].order = MM_EULER_ZYX;
    }
    s->joints[0].flags = MM_JOINT_TRANSLATES;
}

enum motion_kind { PERIODIC, RAMP, TREND };
typedef struct motion {
    enum motion_kind kind;
    int frames;
    double period, shift; /* PERIODIC, TREND: frames */
    double offset, sign;  /* TREND: theta_left = offset + sign * 0.5 sin(2 pi k / period) */
    double walk;          /* forward speed of the whole body (m/s): the character frame removes it */
} motion;

static void angles(const motion *m, int k, double *left, double *right)
{
    double ph = 2.0 * MM_PI * ((double)k + m->shift) / m->period;
    switch (m->kind) {
    case PERIODIC:
        *left = 0.6 * sin(ph);
        *right = 0.6 * cos(ph);
        return;
    case RAMP:
        *left = -0.6 + 1.2 * k / (double)m->frames;
        *right = 0.4 * sin(2.0 * MM_PI * k / 37.0);
        return;
    case TREND:
        *left = m->offset + m->sign * 0.5 * sin(ph);
        *right = 0.0;
        return;
    }
}

static void make_clip(mm_clip *clip, const motion *m)
{
    mm_skeleton s;
    make_skeleton(&s);
    assert_int_equal(mm_clip_init(clip, &s, m->frames, 60.0f, NULL), MM_OK);
    mm_skeleton_free(&s);
    for (int k = 0; k < m->frames; ++k) {
        double l = 0, r = 0;
        angles(m, k, &l, &r);
        mm_clip_positions(clip, k)[0] = mm_vec3_make(0, 1, (float)(m->walk * k / 60.0));
        mm_clip_rotations(clip, k)[2] = mm_quat_from_axis_angle(mm_vec3_make(1, 0, 0), (float)l);
        mm_clip_rotations(clip, k)[4] = mm_quat_from_axis_angle(mm_vec3_make(1, 0, 0), (float)r);
    }
}

/* A database of the given motions; loop[i] marks loop clips. */
static void build_db(mm_database *db, const motion *motions, const bool *loop, int count)
{
    mm_clip *clips = calloc((size_t)count, sizeof(mm_clip));
    for (int i = 0; i < count; ++i) make_clip(&clips[i], &motions[i]);
    mm_config cfg;
    mm_config_defaults(&cfg);
    cfg.scale = 1.0f;
    cfg.root_smoothing = 0.0f;
    cfg.left_hand[0] = cfg.right_hand[0] = cfg.head[0] = 0;
    cfg.standing_make = false; /* the clips given, no standing pose made from them */
    cfg.clip_count = count;
    cfg.clips = calloc((size_t)count, sizeof(mm_config_clip));
    for (int i = 0; i < count; ++i) {
        snprintf(cfg.clips[i].name, MM_NAME_MAX, "clip%d", i);
        snprintf(cfg.clips[i].file, MM_PATH_MAX, "clip%d.bvh", i);
        cfg.clips[i].loop = loop[i];
    }
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_result r = mm_database_build(&cfg, clips, NULL, db, &err);
    if (r != MM_OK) fail_msg("build: %s", err.message);
    for (int i = 0; i < count; ++i) mm_clip_free(&clips[i]);
    free(clips);
    mm_config_free(&cfg);
}

/* Joint weights: 1 on the two toes only (the joints that move). */
static void toe_weights(const mm_database *db, float *w)
{
    for (int j = 0; j < db->joint_count; ++j)
        w[j] = strcmp(db->joints[j].name, "LeftToe") == 0 || strcmp(db->joints[j].name, "RightToe") == 0;
}

static int argbest(mm_sim_measure m, const float *row, int n)
{
    int b = 0;
    for (int j = 1; j < n; ++j)
        if (mm_sim_better(m, row[j], row[b])) b = j;
    return b;
}

/* A clip against itself: every frame's best match is itself (the diagonal), for both measures,
 * with and without rotations and velocities, with a window too. */
static void test_diagonal(void **state)
{
    (void)state;
    motion m = {RAMP, 150, 1, 0, 0, 0, 1.2};
    bool loop = false;
    mm_database db;
    build_db(&db, &m, &loop, 1);
    const unsigned channels[3] = {MM_SIM_POSITION, MM_SIM_POSITION | MM_SIM_ROTATION,
                                  MM_SIM_POSITION | MM_SIM_ROTATION | MM_SIM_VELOCITY};
    float *mat = malloc(sizeof(float) * 150 * 150);
    for (int meas = 0; meas < 2; ++meas)
        for (int c = 0; c < 3; ++c)
            for (int window = 1; window <= 4; window += 3) {
                mm_sim_desc d;
                memset(&d, 0, sizeof d);
                d.measure = (mm_sim_measure)meas;
                d.channels = channels[c];
                d.window = window;
                mm_sim_poses p;
                assert_int_equal(mm_sim_poses_init(&p, &db, &d, NULL), MM_OK);
                assert_int_equal(mm_sim_matrix(&p, 0, 0, 2, mat, NULL), MM_OK);
                /* the last window - 1 rows hold the clip's last frame: only rows before them */
                for (int i = 0; i + window <= 150; ++i) {
                    int b = argbest(p.measure, mat + i * 150, 150);
                    if (b != i)
                        fail_msg("measure %d channels %u window %d: row %d best %d", meas, channels[c],
                                 window, i, b);
                }
                if (meas == MM_SIM_COSINE) {
                    assert_near(mat[0], 1.0, 1e-5);
                    assert_near(mm_sim_pose(&p, 17, 17), 1.0, 1e-5);
                } else {
                    assert_near(mat[0], 0.0, 1e-7);
                }
                /* the matrix is W */
                assert_true(mat[20 * 150 + 33] == mm_sim_window(&p, 20, 33, window));
                mm_sim_poses_free(&p);
            }
    free(mat);
    mm_database_free(&db);
}

/* The root is skipped by the cosine: with default weights joint 0 is left out, and a joint at
 * the root (a zero vector) does not count. The Euclidean distance of a foot pitch is exact. */
static void test_measures(void **state)
{
    (void)state;
    motion m = {RAMP, 40, 1, 0, 0, 0, 0};
    bool loop = false;
    mm_database db;
    build_db(&db, &m, &loop, 1);
    mm_sim_poses p;
    assert_int_equal(mm_sim_poses_init(&p, &db, NULL, NULL), MM_OK);
    assert_int_equal(p.joint_count, db.joint_count - 1); /* joint 0 left out */
    assert_int_equal(p.dims, 3);
    mm_sim_poses_free(&p);
    /* weight on joint 0 only: its vector is zero in every frame, nothing counts: 0 */
    float w[16] = {0};
    w[0] = 1.0f;
    mm_sim_desc d;
    memset(&d, 0, sizeof d);
    d.joint_weights = w;
    assert_int_equal(mm_sim_poses_init(&p, &db, &d, NULL), MM_OK);
    assert_true(p.any_zero[3] == 1);
    assert_near(mm_sim_pose(&p, 3, 9), 0.0, 0);
    mm_sim_poses_free(&p);
    /* joint 0 and the left toe: the root is skipped, the toe's cosine is the result */
    int toe = -1;
    for (int j = 0; j < db.joint_count; ++j)
        if (strcmp(db.joints[j].name, "LeftToe") == 0) toe = j;
    w[toe] = 2.0f;
    assert_int_equal(mm_sim_poses_init(&p, &db, &d, NULL), MM_OK);
    mm_pose_data a;
    (void)a;
    double la, ra, lb, rb;
    angles(&m, 5, &la, &ra);
    angles(&m, 30, &lb, &rb);
    /* toe in the character frame: hips (0,1,0) + foot (0.1,-0.9,0) + Rx(l) (0,-0.05,0.15) */
    double ya = 0.1 - 0.05 * cos(la) - 0.15 * sin(la), za = -0.05 * sin(la) + 0.15 * cos(la);
    double yb = 0.1 - 0.05 * cos(lb) - 0.15 * sin(lb), zb = -0.05 * sin(lb) + 0.15 * cos(lb);
    double cosine =
        (0.01 + ya * yb + za * zb) / sqrt((0.01 + ya * ya + za * za) * (0.01 + yb * yb + zb * zb));
    assert_near(mm_sim_pose(&p, 5, 30), cosine, 2e-6);
    mm_sim_poses_free(&p);
    d.measure = MM_SIM_EUCLIDEAN;
    assert_int_equal(mm_sim_poses_init(&p, &db, &d, NULL), MM_OK);
    /* the root contributes a distance of 0 with weight 1 of 3 */
    assert_near(mm_sim_pose(&p, 5, 30), 2.0 / 3.0 * hypot(ya - yb, za - zb), 1e-6);
    mm_sim_poses_free(&p);
    /* bad settings are named */
    mm_error err;
    memset(&err, 0, sizeof err);
    d.window = MM_SIM_MAX_WINDOW + 1;
    assert_int_equal(mm_sim_poses_init(&p, &db, &d, &err), MM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "window"));
    d.window = 0;
    w[toe] = -1.0f;
    assert_int_equal(mm_sim_poses_init(&p, &db, &d, &err), MM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "LeftToe"));
    mm_database_free(&db);
}

/* A one-shot that is the loop shifted in time by 17 frames is found at its shift in the fusion
 * table (both measures, windows 1 and 6), and the table agrees with mm_sim_window. */
static void test_time_shift(void **state)
{
    (void)state;
    const int period = 60, shift = 17;
    motion ms[3] = {{PERIODIC, period, period, 0, 0, 0, 1.0},
                    {PERIODIC, 50, period, shift, 0, 0, 1.0},
                    {PERIODIC, 45, 45, 0, 0, 0, 0.0}}; /* another loop, faster */
    bool loop[3] = {true, false, true};
    mm_database db;
    build_db(&db, ms, loop, 3);
    for (int meas = 0; meas < 2; ++meas)
        for (int window = 1; window <= 6; window += 5) {
            mm_sim_desc d;
            memset(&d, 0, sizeof d);
            d.measure = (mm_sim_measure)meas;
            d.window = window;
            mm_sim_tables t;
            mm_error err;
            assert_int_equal(mm_sim_tables_build(&db, &d, &t, &err), MM_OK);
            assert_int_equal(t.loop_count, 2);
            assert_int_equal(t.shot_count, 1);
            assert_int_equal(t.fusion_rows, 50);
            assert_int_equal(t.link_rows, period + 45);
            const mm_db_clip *shot = &db.clips[1], *lp = &db.clips[0];
            mm_sim_poses p;
            assert_int_equal(mm_sim_poses_init(&p, &db, &d, NULL), MM_OK);
            for (int i = 0; i + window <= shot->frame_count; ++i) {
                mm_sim_match mt = mm_sim_fusion(&t, shot->first_frame + i, 0);
                assert_int_equal(mt.frame, lp->first_frame + (i + shift) % period);
                if (meas == MM_SIM_COSINE)
                    assert_near(mt.score, 1.0, 1e-5);
                else
                    assert_near(mt.score, 0.0, 1e-5);
                assert_true(mt.score == mm_sim_window(&p, shot->first_frame + i, mt.frame, window));
            }
            /* every fusion entry is the best W over the loop clip, lowest frame on ties */
            for (int i = 0; i < shot->frame_count; i += 7) {
                const mm_db_clip *other = &db.clips[2];
                mm_sim_match mt = mm_sim_fusion(&t, shot->first_frame + i, 2);
                int best = -1;
                float bs = 0;
                for (int j = 0; j < other->frame_count; ++j) {
                    float s = mm_sim_window(&p, shot->first_frame + i, other->first_frame + j, window);
                    if (best < 0 || mm_sim_better(p.measure, s, bs)) best = j, bs = s;
                }
                assert_int_equal(mt.frame, other->first_frame + best);
                assert_true(mt.score == bs);
            }
            /* the link table is W of the loop from each frame and the one-shot from its start */
            for (int f = 0; f < period + 45; f += 5) {
                int frame = f < period ? f : period + 50 + (f - period);
                const float *row = mm_sim_link_row(&t, frame);
                assert_non_null(row);
                assert_true(row[0] == mm_sim_window(&p, frame, shot->first_frame, window));
            }
            /* lookups outside their tables */
            assert_int_equal(mm_sim_fusion(&t, 0, 0).frame, -1);                 /* from a loop */
            assert_int_equal(mm_sim_fusion(&t, shot->first_frame, 1).frame, -1); /* to a one-shot */
            assert_null(mm_sim_link_row(&t, shot->first_frame));
            mm_sim_link_match lm;
            assert_int_equal(mm_sim_link(&t, shot->first_frame, 3, NULL, 0, &lm), -1);
            mm_sim_match best;
            int bc = mm_sim_fusion_best(&t, shot->first_frame + 4, &best);
            assert_true(bc == 0 || bc == 2);
            assert_false(
                mm_sim_better(t.measure, mm_sim_fusion(&t, shot->first_frame + 4, 0).score, best.score));
            if (meas == MM_SIM_EUCLIDEAN) {
                assert_int_equal(bc, 0);
                assert_int_equal(best.frame, (4 + shift) % period);
            }
            mm_sim_poses_free(&p);
            mm_sim_tables_free(&t);
        }
    mm_database_free(&db);
}

/* Motion trend: the loop swings the left foot forward from 0 at its frame 0. One one-shot starts
 * exactly at that pose but swings backward; the other starts 0.05 rad off and swings forward like
 * the loop. One frame prefers the first; a window of 10 frames prefers the second. Then the
 * delayed start: a one-shot starting at the loop's frame 13 is found from frame 10 with 3 frames
 * of delay when 5 rows are scanned. */
static void test_trend_and_delay(void **state)
{
    (void)state;
    const int period = 80;
    motion ms[4] = {{TREND, period, period, 0, 0.0, 1.0, 0.0}, /* loop */
                    {TREND, 40, period, 0, 0.0, -1.0, 0.0},    /* same first pose, opposite trend */
                    {TREND, 40, period, 0, 0.05, 1.0, 0.0},    /* close first pose, same trend */
                    {TREND, 40, period, 13.0, 0.0, 1.0, 0.0}}; /* the loop from its frame 13 */
    bool loop[4] = {true, false, false, false};
    mm_database db;
    build_db(&db, ms, loop, 4);
    float w[16];
    toe_weights(&db, w);
    for (int meas = 0; meas < 2; ++meas) {
        mm_sim_desc d;
        memset(&d, 0, sizeof d);
        d.measure = (mm_sim_measure)meas;
        d.joint_weights = w;
        int candidates[2] = {1, 2};
        mm_sim_link_match lm;
        mm_sim_tables t;
        d.window = 1;
        assert_int_equal(mm_sim_tables_build(&db, &d, &t, NULL), MM_OK);
        assert_int_equal(mm_sim_link(&t, 0, 1, candidates, 2, &lm), 1);
        assert_int_equal(lm.delay, 0);
        assert_int_equal(lm.frame, db.clips[1].first_frame);
        mm_sim_tables_free(&t);
        d.window = 10;
        assert_int_equal(mm_sim_tables_build(&db, &d, &t, NULL), MM_OK);
        assert_int_equal(mm_sim_link(&t, 0, 1, candidates, 2, &lm), 2);
        /* delayed start */
        assert_int_equal(mm_sim_link(&t, 10, 5, NULL, 0, &lm), 3);
        assert_int_equal(lm.delay, 3);
        assert_int_equal(lm.frame, db.clips[3].first_frame);
        if (meas == MM_SIM_COSINE)
            assert_near(lm.score, 1.0, 1e-5);
        else
            assert_near(lm.score, 0.0, 1e-5);
        /* without the delay, the best now is worse */
        mm_sim_link_match now;
        mm_sim_link(&t, 10, 1, NULL, 0, &now);
        assert_int_equal(now.delay, 0);
        assert_true(mm_sim_better(t.measure, lm.score, now.score));
        /* wrapping: from the loop's last frame, 15 rows reach frame 13 */
        assert_int_equal(mm_sim_link(&t, period - 1, 15, NULL, 0, &lm), 3);
        assert_int_equal(lm.delay, 14);
        mm_sim_tables_free(&t);
    }
    mm_database_free(&db);
}

/* Several loops and one-shots of different lengths: 1, 2 and 3 threads give identical bytes. */
static void test_threads(void **state)
{
    (void)state;
    motion ms[6] = {{PERIODIC, 60, 60, 0, 0, 0, 1.0},  {RAMP, 130, 1, 0, 0, 0, 0.5},
                    {PERIODIC, 71, 71, 5, 0, 0, 0.0},  {TREND, 33, 50, 3, 0.1, -1, 0.0},
                    {PERIODIC, 100, 45, 9, 0, 0, 2.0}, {TREND, 90, 90, 0, 0.0, 1, 0.0}};
    bool loop[6] = {true, false, true, false, false, true};
    mm_database db;
    build_db(&db, ms, loop, 6);
    for (int meas = 0; meas < 2; ++meas) {
        mm_sim_desc d;
        memset(&d, 0, sizeof d);
        d.measure = (mm_sim_measure)meas;
        d.window = 7;
        d.channels = MM_SIM_POSITION | MM_SIM_ROTATION | MM_SIM_VELOCITY;
        mm_sim_tables t1, t2, t3;
        d.threads = 1;
        assert_int_equal(mm_sim_tables_build(&db, &d, &t1, NULL), MM_OK);
        d.threads = 2;
        assert_int_equal(mm_sim_tables_build(&db, &d, &t2, NULL), MM_OK);
        d.threads = 3;
        assert_int_equal(mm_sim_tables_build(&db, &d, &t3, NULL), MM_OK);
        assert_int_equal(t1.size, t2.size);
        assert_int_equal(t1.size, t3.size);
        assert_memory_equal(t1.data, t2.data, t1.size);
        assert_memory_equal(t1.data, t3.data, t1.size);
        assert_int_equal(t1.fusion_rows, 130 + 33 + 100);
        assert_int_equal(t1.link_rows, 60 + 71 + 90);
        mm_sim_tables_free(&t1);
        mm_sim_tables_free(&t2);
        mm_sim_tables_free(&t3);
    }
    mm_database_free(&db);
}

static void write_bytes(const char *path, const void *data, size_t size)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1, size, f), size);
    fclose(f);
}

/* Save, load, and refuse: another database, a corrupted byte, a truncated file, bad magic, a
 * newer version. */
static void test_file(void **state)
{
    (void)state;
    motion ms[3] = {
        {PERIODIC, 60, 60, 0, 0, 0, 1.0}, {RAMP, 50, 1, 0, 0, 0, 0.0}, {PERIODIC, 40, 40, 0, 0, 0, 0}};
    bool loop[3] = {true, false, true};
    mm_database db, other;
    build_db(&db, ms, loop, 3);
    ms[1].frames = 51;
    build_db(&other, ms, loop, 3);
    mm_sim_desc d;
    memset(&d, 0, sizeof d);
    d.window = 3;
    mm_sim_tables t, u;
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_sim_tables_build(&db, &d, &t, &err), MM_OK);
    char path[256];
    snprintf(path, sizeof path, "/tmp/mm_test_similarity_%d.sim", (int)getpid());
    assert_int_equal(mm_sim_tables_save(&t, path, &err), MM_OK);
    assert_int_equal(mm_sim_tables_load(path, &db, NULL, &u, &err), MM_OK);
    assert_int_equal(u.size, t.size);
    assert_memory_equal(u.data, t.data, t.size);
    assert_int_equal(u.window, 3);
    assert_int_equal(mm_sim_fusion(&u, 70, 0).frame, mm_sim_fusion(&t, 70, 0).frame);
    mm_sim_tables_free(&u);
    assert_int_equal(mm_sim_tables_load(path, NULL, NULL, &u, &err), MM_OK); /* no database check */
    mm_sim_tables_free(&u);
    assert_int_equal(mm_sim_tables_load(path, &other, NULL, &u, &err), MM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "another database"));
    assert_non_null(strstr(err.file, "mm_test_similarity"));

    unsigned char *copy = malloc(t.size);
    memcpy(copy, t.data, t.size);
    copy[t.size - 70] ^= 1; /* a byte of the link table */
    write_bytes(path, copy, t.size);
    assert_int_equal(mm_sim_tables_load(path, &db, NULL, &u, &err), MM_ERR_SYNTAX);
    assert_non_null(strstr(err.message, "checksum"));
    memcpy(copy, t.data, t.size);
    write_bytes(path, copy, t.size - 64);
    assert_int_equal(mm_sim_tables_load(path, &db, NULL, &u, &err), MM_ERR_UNEXPECTED_EOF);
    copy[0] = 'X';
    write_bytes(path, copy, t.size);
    assert_int_equal(mm_sim_tables_load(path, &db, NULL, &u, &err), MM_ERR_SYNTAX);
    assert_non_null(strstr(err.message, "magic"));
    memcpy(copy, t.data, t.size);
    copy[12] = 99; /* version */
    write_bytes(path, copy, t.size);
    assert_int_equal(mm_sim_tables_load(path, &db, NULL, &u, &err), MM_ERR_OUT_OF_RANGE);
    assert_non_null(strstr(err.message, "version"));
    unlink(path);
    assert_int_equal(mm_sim_tables_load(path, &db, NULL, &u, &err), MM_ERR_IO);
    free(copy);
    mm_sim_tables_free(&t);
    mm_database_free(&db);
    mm_database_free(&other);
}

/* Real motion: the built-in set (or LAFAN1 with MM_DATA_DIR). */
static int build_real(mm_database *db, bool *lafan)
{
    int is_lafan = 0;
    int r = test_build_real_database(db, &is_lafan);
    *lafan = is_lafan != 0;
    return r;
}

static void test_real(void **state)
{
    (void)state;
    mm_database db;
    bool lafan;
    assert_int_equal(build_real(&db, &lafan), 0);
    mm_sim_desc d;
    memset(&d, 0, sizeof d);
    d.window = 8;
    if (lafan) {
        /* no loop clips: the audit use. A long clip against itself: the diagonal. */
        int c = 0;
        for (int k = 1; k < db.clip_count; ++k)
            if (db.clips[k].frame_count > db.clips[c].frame_count && db.clips[k].frame_count < 3000) c = k;
        int n = db.clips[c].frame_count;
        mm_sim_poses p;
        assert_int_equal(mm_sim_poses_init(&p, &db, &d, NULL), MM_OK);
        float *mat = malloc(sizeof(float) * (size_t)n * (size_t)n);
        assert_int_equal(mm_sim_matrix(&p, c, c, 2, mat, NULL), MM_OK);
        int off = 0;
        for (int i = 0; i + 8 <= n; ++i) off += argbest(p.measure, mat + (size_t)i * (size_t)n, n) != i;
        print_message("LAFAN1 %s (%d frames) against itself: %d rows off the diagonal\n", db.clips[c].name, n,
                      off);
        assert_int_equal(off, 0);
        free(mat);
        mm_sim_poses_free(&p);
    } else {
        d.threads = 2;
        mm_sim_tables t;
        assert_int_equal(mm_sim_tables_build(&db, &d, &t, NULL), MM_OK);
        print_message("built-in set: %d loop clips, %d one-shots, tables %zu bytes\n", t.loop_count,
                      t.shot_count, t.size);
        int idle = mm_database_find_clip(&db, "idle"), walk_stop = mm_database_find_clip(&db, "walk_stop"),
            run_start = mm_database_find_clip(&db, "run_start"),
            walk = mm_database_find_clip(&db, "walk_1.40");
        assert_true(idle >= 0 && walk_stop >= 0 && run_start >= 0 && walk >= 0);
        mm_sim_match m;
        /* a stop ends standing: it fuses into the idle loop; a start begins standing */
        int last = db.clips[walk_stop].first_frame + db.clips[walk_stop].frame_count - 1;
        assert_int_equal(mm_sim_fusion_best(&t, last, &m), idle);
        assert_int_equal(mm_sim_fusion_best(&t, db.clips[run_start].first_frame, &m), idle);
        assert_true(m.score > 0.99f);
        /* while walking, a stop fuses into a walk loop (not idle, not a run) */
        int best = mm_sim_fusion_best(&t, db.clips[walk_stop].first_frame, &m);
        print_message("walk_stop frame 0 -> %s frame %d (%.5f)\n", db.clips[best].name,
                      m.frame - db.clips[best].first_frame, (double)m.score);
        assert_non_null(strstr(db.clips[best].name, "walk"));
        /* from standing idle, the best one-shot to start is one that begins standing */
        mm_sim_link_match lm;
        assert_true(mm_sim_link(&t, db.clips[idle].first_frame, 10, NULL, 0, &lm) >= 0);
        print_message("idle -> %s after %d frames (%.5f)\n", db.clips[lm.clip].name, lm.delay,
                      (double)lm.score);
        assert_null(strstr(db.clips[lm.clip].name, "stop"));
        assert_null(strstr(db.clips[lm.clip].name, "run_to"));
        mm_sim_tables u;
        d.threads = 1;
        assert_int_equal(mm_sim_tables_build(&db, &d, &u, NULL), MM_OK);
        assert_memory_equal(u.data, t.data, t.size);
        mm_sim_tables_free(&u);
        mm_sim_tables_free(&t);
    }
    mm_database_free(&db);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_diagonal),   cmocka_unit_test(test_measures),
        cmocka_unit_test(test_time_shift), cmocka_unit_test(test_trend_and_delay),
        cmocka_unit_test(test_threads),    cmocka_unit_test(test_file),
        cmocka_unit_test(test_real),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
