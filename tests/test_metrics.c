/* The metrics of what a person sees (tools/motion_metrics.c, docs/metrics.md) on hand-built motion
 * with known answers, and the database's side of them on the built-in set. */
#include <math.h>

#include "motion_metrics.h"
#include "test_databases.h"
#include "test_util.h"

/* The body: 0 the simulation root, 1 hips, 2 head, 3 left hand, 4 right hand, 5 left foot (ankle),
 * 6 left toe, 7 right foot, 8 right toe, 9 and 10 the left and right thigh's top, 11 and 12 the
 * left and right knee. */
enum { ROOT, HIPS, HEAD, LHAND, RHAND, LFOOT, LTOE, RFOOT, RTOE, LTHIGH, RTHIGH, LKNEE, RKNEE, N };
static const int CONTACT[4] = {LFOOT, LTOE, RFOOT, RTOE};
static const mm_posture_joints JOINTS = {HIPS, HEAD, LHAND, RHAND, {LKNEE, RKNEE}, {LTHIGH, RTHIGH}};
static const double PLANTED[4] = {0.08, 0.03, 0.08, 0.03};
#define FPS 60.0

/* Standing upright (the head at 1.6 m), or with crouch the hips 0.32 m lower (the head at 1.28 m,
 * 0.8 of 1.6), or with arms_out in a T pose; the feet on the ground at their planted heights. */
static void stand(mm_vec3 *w, float crouch, int arms_out)
{
    w[ROOT] = mm_vec3_make(0, 0, 0);
    w[HIPS] = mm_vec3_make(0, 0.95f - crouch, 0);
    w[HEAD] = mm_vec3_make(0, 1.6f - crouch, 0);
    w[LHAND] = arms_out ? mm_vec3_make(-0.8f, 1.45f, 0) : mm_vec3_make(-0.2f, 0.9f - crouch, 0);
    w[RHAND] = arms_out ? mm_vec3_make(0.8f, 1.45f, 0) : mm_vec3_make(0.2f, 0.9f - crouch, 0);
    w[LFOOT] = mm_vec3_make(-0.1f, 0.08f, 0);
    w[LTOE] = mm_vec3_make(-0.1f, 0.03f, 0.15f);
    w[RFOOT] = mm_vec3_make(0.1f, 0.08f, 0);
    w[RTOE] = mm_vec3_make(0.1f, 0.03f, 0.15f);
    w[LTHIGH] = mm_vec3_make(-0.1f, 0.9f - crouch, 0);
    w[RTHIGH] = mm_vec3_make(0.1f, 0.9f - crouch, 0);
    w[LKNEE] = mm_vec3_make(-0.1f, 0.48f - 0.5f * crouch, 0.6f * crouch); /* forward in a crouch */
    w[RKNEE] = mm_vec3_make(0.1f, 0.48f - 0.5f * crouch, 0.6f * crouch);
}

/* Metrics for frames frames of the body against its own reference (head 1.6 m, the feet's
 * planted heights). */
static void start(motion_metrics *m, long frames)
{
    assert_int_equal(motion_metrics_init(m, N, CONTACT, FPS, frames), 0);
    motion_metrics_reference(m, &JOINTS, 1.6f, PLANTED);
}

/* One frame with the controller's side empty: the labels given, the root where the path is. */
static void frame(motion_metrics *m, const mm_vec3 *w, unsigned labels)
{
    motion_metrics_frame(m, (double)m->frames / FPS, w, labels, NULL, w[ROOT], 0.0f, w[ROOT], 0.0f, 1.0f);
}

static motion_metrics_seen summary(const motion_metrics *m)
{
    motion_metrics_seen s;
    assert_int_equal(motion_metrics_summary(m, &s), 0);
    return s;
}

static void test_below_ground(void **state)
{
    (void)state;
    motion_metrics m;
    start(&m, 10);
    mm_vec3 w[N];
    for (int f = 0; f < 10; ++f) {
        stand(w, 0.0f, 0);
        w[ROOT].y = -0.5f; /* joint 0, the simulation root, does not count */
        if (f == 5) w[LTOE].y = -0.03f;
        motion_metrics_pose(&m, w);
    }
    assert_near(summary(&m).below_ground_cm, 3.0, 0.01);
    /* where: the left toe on frame 5 */
    assert_int_equal(m.worst_below.frame, 5);
    assert_int_equal(m.worst_below.joint, LTOE);
    assert_near(m.worst_below.value, 3.0, 0.01);
    motion_metrics_free(&m);

    /* never below: 0 */
    start(&m, 10);
    stand(w, 0.0f, 0);
    for (int f = 0; f < 10; ++f) motion_metrics_pose(&m, w);
    assert_near(summary(&m).below_ground_cm, 0.0, 0.0);
    motion_metrics_free(&m);

    /* a scene: the ground plane 1 m up, a box whose top is 0.5 m above it at x = 2 and a wall 2 m
     * high at x = 5; a toe 3 cm under the ground plane, then 2 cm into the box's top: 3; a hand deep
     * in the wall is not below ground (it is in the wall: penetration_max_cm) */
    mm_scene scene;
    mm_scene_init(&scene, 1.0f);
    assert_int_equal(mm_scene_add_box(&scene, mm_vec3_make(2, 1, 0), mm_vec3_make(1, 0.5f, 1), 0.0f), MM_OK);
    assert_int_equal(mm_scene_add_box(&scene, mm_vec3_make(5, 1, 0), mm_vec3_make(1, 2, 1), 0.0f), MM_OK);
    for (int on_box = 0; on_box < 2; ++on_box) {
        start(&m, 3);
        motion_metrics_scene(&m, &scene);
        stand(w, 0.0f, 0);
        for (int j = 0; j < N; ++j) w[j].y += on_box ? 1.5f : 1.0f, w[j].x += on_box ? 2.0f : 0.0f;
        motion_metrics_pose(&m, w);
        w[LTOE].y -= on_box ? 0.05f : 0.06f; /* 0.03 above its ground, 2 / 3 cm below */
        motion_metrics_pose(&m, w);
        w[RHAND] = mm_vec3_make(5, 1.5f, 0); /* 1.5 m into the wall's top */
        motion_metrics_pose(&m, w);
        motion_metrics_seen s = summary(&m);
        assert_near(s.below_ground_cm, on_box ? 2.0 : 3.0, 0.01);
        assert_true(m.penetration_max > 0.4);
        /* the head's height is above the ground the feet stand on */
        assert_near(s.head_p50_cm, 160.0, 0.01);
        motion_metrics_free(&m);
    }
}

static void test_calibration(void **state)
{
    (void)state;
    /* 1.5 s of T pose, measured against the motion itself (no database): 1.5 s of calibration
     * pose with the arms out; the crouch asked for does not hide a calibration pose */
    const long frames = 90;
    mm_vec3 *world = malloc(sizeof(mm_vec3) * N * frames);
    for (long f = 0; f < frames; ++f) stand(world + f * N, 0.0f, 1);
    motion_metrics m;
    assert_int_equal(motion_metrics_init(&m, N, CONTACT, FPS, frames), 0);
    motion_metrics_reference_from_motion(&m, &JOINTS, world, frames);
    assert_near(m.reference.head_height, 1.6, 1e-6);
    assert_near(m.planted[1], 0.03, 1e-6);
    mm_input in;
    memset(&in, 0, sizeof in);
    in.gait = MM_GAIT_CROUCH;
    for (long f = 0; f < frames; ++f) {
        motion_metrics_input(&m, (double)f / FPS, &in, mm_vec3_make(0, 0, 0));
        frame(&m, world + f * N, 0);
    }
    motion_metrics_seen s = summary(&m);
    assert_near(s.calibration_s, 1.5, 1.0 / FPS);
    assert_near(s.arms_out_s, 1.5, 1.0 / FPS);
    assert_near(s.crouched_s + s.bent_s + s.lying_s, 0.0, 0.0);
    assert_near(s.hands_apart_max_cm, 160.0, 1e-3);
    motion_metrics_free(&m);
    free(world);
}

static void test_hand_raised(void **state)
{
    (void)state;
    /* walking with the hands by the hips for 0.5 s, then 1 s with the right hand on the head (1.55
     * m: 0.97 of the head's 1.6), then 0.1 s of a hand at the chin (1.5 m) between hanging hands,
     * shorter than a posture run: 1 s of a hand raised, nothing else */
    motion_metrics m;
    start(&m, 130);
    mm_input in;
    memset(&in, 0, sizeof in);
    in.gait = MM_GAIT_WALK;
    for (int f = 0; f < 130; ++f) {
        mm_vec3 w[N];
        stand(w, 0.0f, 0);
        if ((f >= 30 && f < 90) || f == 110) w[RHAND] = mm_vec3_make(0.1f, f == 110 ? 1.5f : 1.55f, 0.05f);
        motion_metrics_input(&m, (double)m.frames / FPS, &in, mm_vec3_make(0, 0, 0));
        frame(&m, w, 0);
    }
    motion_metrics_seen s = summary(&m);
    assert_near(s.hand_raised_s, 1.0, 1e-9);
    assert_near(s.arms_spread_s + s.calibration_s + s.crouched_s + s.bent_s + s.lying_s, 0.0, 0.0);
    assert_near(s.arms_out_s, 0.0, 0.0);
    motion_metrics_free(&m);
}

static void test_knee_raised(void **state)
{
    (void)state;
    /* walking for 0.5 s, then 0.5 s of running strides (a thigh swung to 30 degrees below level),
     * 1 s with the left thigh level (a high-knee step), 0.1 s of the right thigh level between
     * hanging legs (shorter than a posture run), and 0.5 s of a crouch asked for whose knees come
     * level: 1 s of a knee raised, nothing else but the crouch asked for */
    motion_metrics m;
    start(&m, 220);
    mm_input in;
    memset(&in, 0, sizeof in);
    for (int f = 0; f < 220; ++f) {
        mm_vec3 w[N];
        in.gait = f < 30 ? MM_GAIT_WALK : f < 60 ? MM_GAIT_RUN : f < 190 ? MM_GAIT_WALK : MM_GAIT_CROUCH;
        stand(w, f < 190 ? 0.0f : 0.32f, 0);
        if (f >= 30 && f < 60) w[LKNEE] = mm_vec3_add(w[LTHIGH], mm_vec3_make(0, -0.21f, 0.3637f));
        if (f >= 60 && f < 120) w[LKNEE] = mm_vec3_add(w[LTHIGH], mm_vec3_make(0, 0, 0.42f));
        if (f == 150) w[RKNEE] = mm_vec3_add(w[RTHIGH], mm_vec3_make(0, 0, 0.42f));
        if (f >= 190) w[RKNEE] = mm_vec3_add(w[RTHIGH], mm_vec3_make(0, 0, 0.42f));
        motion_metrics_input(&m, (double)m.frames / FPS, &in, mm_vec3_make(0, 0, 0));
        frame(&m, w, 0);
    }
    motion_metrics_seen s = summary(&m);
    assert_near(s.knee_raised_s, 1.0, 1e-9);
    assert_near(s.hand_raised_s + s.arms_spread_s + s.calibration_s + s.bent_s + s.lying_s, 0.0, 0.0);
    /* the crouch is asked for: not counted */
    assert_near(s.crouched_s, 0.0, 0.0);
    motion_metrics_free(&m);
}

static void test_foot_float(void **state)
{
    (void)state;
    /* the left foot labelled from frame 0 on: 30 cm up for its first 6 frames (0.1 s at 60 fps:
     * MOTION_METRICS_FLOAT_LANDING, a foot shown landing), then 4 cm up for 4 frames, then down:
     * 4 cm. The right foot's label off throughout, 50 cm up: not counted. */
    for (int late = 0; late < 2; ++late) {
        motion_metrics m;
        start(&m, 20);
        for (int f = 0; f < 20; ++f) {
            mm_vec3 w[N];
            stand(w, 0.0f, 0);
            /* late: the 30 cm lasts one frame longer, past the landing */
            float up = f < 6 + late ? 0.3f : f < 10 ? 0.04f : 0.0f;
            w[LFOOT].y += up, w[LTOE].y += up;
            w[RFOOT].y += 0.5f, w[RTOE].y += 0.5f;
            frame(&m, w, 0x3u);
        }
        assert_near(summary(&m).foot_float_cm, late ? 30.0 : 4.0, 1e-4);
        /* where: the first frame past the landing (6), the left ankle or toe (both as high) */
        assert_int_equal(m.worst_float.frame, 6);
        assert_true(m.worst_float.joint == LFOOT || m.worst_float.joint == LTOE);
        assert_near(m.worst_float.value, late ? 30.0 : 4.0, 1e-4);
        motion_metrics_free(&m);
    }
}

static void test_pop(void **state)
{
    (void)state;
    /* the left hand displaced by d (|d| = 5 cm) on frame 10 alone: second differences d, 2d, d on
     * frames 10, 11, 12, the rest 0 */
    motion_metrics m;
    start(&m, 20);
    mm_vec3 w[N];
    for (int f = 0; f < 20; ++f) {
        stand(w, 0.0f, 0);
        if (f == 10) w[LHAND] = mm_vec3_add(w[LHAND], mm_vec3_make(0.03f, 0.04f, 0));
        motion_metrics_pose(&m, w);
    }
    motion_metrics_seen s = summary(&m);
    assert_near(s.max_pop_cm, 10.0, 1e-4);
    /* 18 pops (frames 2 to 19): fifteen 0, 5, 10, 5; rank floor(0.99 x 17) = 16 of the sorted: 5 */
    assert_near(s.pop_p99_cm, 5.0, 1e-4);
    /* where: the left hand, the acceleration of 2d at frame 10 */
    assert_int_equal(m.worst_pop.frame, 10);
    assert_int_equal(m.worst_pop.joint, LHAND);
    assert_near(m.worst_pop.value, 10.0, 1e-4);
    motion_metrics_free(&m);
}

static void test_response(void **state)
{
    (void)state;
    /* at 60 fps, moving +Z at 1 m/s; the stick turns to +X at frame 30 (0.5 s): the simulated path
     * moves +X from that frame on, the root from frame 48 (0.8 s). Each response counts from the
     * turn to the end of the first frame that moves the new way: 1/60 s and 0.3 + 1/60 s. */
    motion_metrics m;
    start(&m, 90);
    mm_input in;
    memset(&in, 0, sizeof in);
    mm_vec3 sim = mm_vec3_make(0, 0, 0), root = sim, w[N];
    for (int f = 0; f < 90; ++f) {
        int turned = f >= 30;
        in.stick[0] = turned ? 1.0f : 0.0f;
        in.stick[1] = turned ? 0.0f : 1.0f;
        mm_vec3 desired = turned ? mm_vec3_make(1, 0, 0) : mm_vec3_make(0, 0, 1);
        motion_metrics_input(&m, f / FPS, &in, desired);
        const float step = (float)(1.0 / FPS);
        if (f > 0) {
            sim = mm_vec3_add(sim, turned ? mm_vec3_make(step, 0, 0) : mm_vec3_make(0, 0, step));
            root = mm_vec3_add(root, f >= 48 ? mm_vec3_make(step, 0, 0) : mm_vec3_make(0, 0, step));
        }
        stand(w, 0.0f, 0);
        motion_metrics_frame(&m, f / FPS, w, 0, NULL, sim, 0.0f, root, 0.0f, 1.0f);
    }
    assert_int_equal(m.response_sim.count, 1);
    assert_near(m.response_sim.sum, 1.0 / FPS, 1e-6);
    assert_int_equal(m.response_root.count, 1);
    assert_near(m.response_root.sum, 0.3 + 1.0 / FPS, 1e-6);
    motion_metrics_free(&m);
}

static void test_worst_slide(void **state)
{
    (void)state;
    /* 200 frames, the left heel labelled throughout; it slides at 1 m/s on frames 10-12 and
     * 100-109, and stands otherwise. The worst second (60 frames) holds frames 100-109: the first
     * window that does begins at frame 50; its 60 labelled frames average 1000 / 60 cm/s; it holds
     * 1000 of the 1300 cm/s-frames of slide. */
    motion_metrics m;
    start(&m, 200);
    mm_vec3 w[N];
    float x = 0.0f;
    for (int f = 0; f < 200; ++f) {
        stand(w, 0.0f, 0);
        if ((f >= 10 && f <= 12) || (f >= 100 && f <= 109)) x += (float)(1.0 / FPS);
        w[LFOOT].x += x;
        frame(&m, w, 0x1u);
    }
    double seconds = 0.0, cm_s = 0.0, share = 0.0;
    assert_int_equal(motion_metrics_worst_slide(&m, &seconds, &cm_s, &share), 50);
    assert_near(seconds, 1.0, 1e-9);
    assert_near(cm_s, 1000.0 / 60.0, 0.01);
    assert_near(share, 1000.0 / 1300.0, 1e-3);
    motion_metrics_free(&m);

    /* no slide at all: none */
    start(&m, 100);
    stand(w, 0.0f, 0);
    for (int f = 0; f < 100; ++f) frame(&m, w, 0x1u);
    assert_int_equal(motion_metrics_worst_slide(&m, &seconds, &cm_s, &share), -1);
    motion_metrics_free(&m);
}

static void test_pop_p99(void **state)
{
    (void)state;
    /* the percentile: rank floor(q (n - 1)) of the finite values */
    float v[101];
    for (int i = 0; i < 100; ++i) v[i] = (float)((i * 37) % 100); /* 0 .. 99, shuffled */
    v[100] = NAN;
    assert_near(motion_metrics_percentile(v, 101, 0.99), 98.0, 0.0);
    assert_near(motion_metrics_percentile(v, 101, 0.5), 49.0, 0.0);
    assert_near(motion_metrics_percentile(v, 101, 0.0), 0.0, 0.0);
    assert_near(motion_metrics_percentile(v, 101, 1.0), 99.0, 0.0);
    assert_true(isnan(motion_metrics_percentile(v + 100, 1, 0.5)));
    assert_true(isnan(motion_metrics_percentile(v, 0, 0.5)));
    /* a joint whose second difference on frame f (2 to 101) is a shuffle of 0 .. 9.9 mm, turning
     * back and forth so that it stays near: pops 0 .. 0.99 cm, their 99th percentile 0.98 cm */
    motion_metrics m;
    start(&m, 102);
    mm_vec3 w[N];
    double x0 = 0.0, x1 = 0.0;
    for (int f = 0; f < 102; ++f) {
        double x = f < 2 ? 0.0 : 2.0 * x1 - x0 + (f % 2 ? -1e-4 : 1e-4) * (((f - 2) * 37) % 100);
        x0 = x1, x1 = x;
        stand(w, 0.0f, 0);
        w[HEAD].x = (float)x;
        motion_metrics_pose(&m, w);
    }
    motion_metrics_seen s = summary(&m);
    assert_near(s.pop_p99_cm, 0.98, 2e-4);
    assert_near(s.max_pop_cm, 0.99, 2e-4);
    motion_metrics_free(&m);
}

static void test_contact_share(void **state)
{
    (void)state;
    /* labels 0 .. 9 (bits: left heel, left toe, right heel, right toe) on ten frames: 15 of 40 */
    motion_metrics m;
    start(&m, 10);
    mm_vec3 w[N];
    stand(w, 0.0f, 0);
    for (int j = LFOOT; j <= RTOE; ++j) w[j].y += 0.02f; /* every contact joint 2 cm above its plant */
    for (unsigned f = 0; f < 10; ++f) frame(&m, w, f);
    motion_metrics_seen s = summary(&m);
    assert_near(s.contact_share, 15.0 / 40.0, 1e-12);
    assert_near(s.contact_height_err_cm, 2.0, 1e-4);
    motion_metrics_free(&m);
    /* without a left toe: its label does not count, nor its pairs (bits 0, 2, 3 on 11 of 30) */
    const int no_toe[4] = {LFOOT, -1, RFOOT, RTOE};
    assert_int_equal(motion_metrics_init(&m, N, no_toe, FPS, 10), 0);
    motion_metrics_reference(&m, &JOINTS, 1.6f, PLANTED);
    for (unsigned f = 0; f < 10; ++f) frame(&m, w, f);
    assert_near(summary(&m).contact_share, 11.0 / 30.0, 1e-12);
    motion_metrics_free(&m);
    /* no labels at all (motion alone): null */
    start(&m, 10);
    for (unsigned f = 0; f < 10; ++f) motion_metrics_pose(&m, w);
    s = summary(&m);
    assert_true(isnan(s.contact_share));
    assert_true(isnan(s.contact_height_err_cm));
    motion_metrics_free(&m);
}

static void test_slide_height(void **state)
{
    (void)state;
    /* each contact joint moves along x at its own speed and height above its planted height h
     * (H = 2.5 cm): the left heel at h = 0 at 100 cm/s (w = 1), the left toe at h = H / 2 at 50 cm/s
     * (w = 2 - 2^0.5), the right heel at h = 3 cm at 1000 cm/s (w = 0: not counted), the right toe
     * 1 cm below its planted height at 20 cm/s (w = 1); except that the right heel swings through
     * its planted height on frames 12-17 (6 frames, 0.1 s: MOTION_METRICS_SLIDE_DWELL), too briefly
     * to be planted. Each bone counts from its seventh frame near the ground on. */
    const double speed[4] = {1.0, 0.5, 10.0, 0.2}, h[4] = {0.0, 0.0125, 0.03, -0.01};
    motion_metrics m;
    start(&m, 24);
    mm_vec3 w[N];
    for (int f = 0; f < 24; ++f) {
        stand(w, 0.0f, 0);
        for (int k = 0; k < 4; ++k) {
            w[CONTACT[k]].x = (float)(speed[k] * f / FPS);
            w[CONTACT[k]].y = (float)(PLANTED[k] + (k == 2 && f >= 12 && f < 18 ? 0.0 : h[k]));
        }
        frame(&m, w, 0xf); /* the labels do not matter */
    }
    double half = 2.0 - sqrt(2.0), want = (100.0 + 50.0 * half + 20.0) / (1.0 + half + 1.0);
    assert_near(summary(&m).foot_slide_height_cm_s, want, 1e-3);
    motion_metrics_free(&m);
    /* every foot higher than H: null */
    start(&m, 3);
    stand(w, 0.0f, 0);
    for (int k = 0; k < 4; ++k) w[CONTACT[k]].y += 0.1f;
    for (int f = 0; f < 3; ++f) motion_metrics_pose(&m, w);
    assert_true(isnan(summary(&m).foot_slide_height_cm_s));
    motion_metrics_free(&m);
}

static void test_posture_seconds(void **state)
{
    (void)state;
    /* at 60 fps: 1 s upright, 0.5 s crouched, 5 frames bent (flicker: crouched), 1 s upright, 0.5 s
     * crouched asked for by the input (not counted), 1 s upright */
    const struct {
        int frames;
        int kind; /* 0 upright, 1 crouched, 2 bent */
        int asked;
    } runs[] = {{60, 0, 0}, {30, 1, 0}, {5, 2, 0}, {60, 0, 0}, {30, 1, 1}, {60, 0, 0}};
    motion_metrics m;
    start(&m, 245);
    mm_input in;
    memset(&in, 0, sizeof in);
    for (int r = 0; r < 6; ++r)
        for (int f = 0; f < runs[r].frames; ++f) {
            mm_vec3 w[N];
            stand(w, runs[r].kind == 1 ? 0.32f : 0.0f, 0);
            if (runs[r].kind == 2) { /* the trunk 60 degrees from vertical: the head 0.65 m from the hips */
                w[HEAD] = mm_vec3_make(0.65f * sinf((float)(MM_PI / 3)), 0.95f + 0.65f * 0.5f, 0);
            }
            in.gait = runs[r].asked ? MM_GAIT_CROUCH : MM_GAIT_WALK;
            motion_metrics_input(&m, (double)m.frames / FPS, &in, mm_vec3_make(0, 0, 0));
            frame(&m, w, 0);
        }
    motion_metrics_seen s = summary(&m);
    assert_near(s.crouched_s, 35.0 / FPS, 1e-9);
    assert_near(s.bent_s, 0.0, 0.0);
    assert_near(s.lying_s, 0.0, 0.0);
    assert_near(s.calibration_s, 0.0, 0.0);
    assert_near(s.arms_out_s, 0.0, 0.0);
    /* head heights: 5 at 1.275 m, 60 at 1.28 m, 180 at 1.6 m; ranks floor(q x 244): 4, 12, 122 */
    assert_near(s.head_p2_cm, 127.5, 1e-4);
    assert_near(s.head_p5_cm, 128.0, 1e-4);
    assert_near(s.head_p50_cm, 160.0, 1e-4);
    assert_near(s.hands_apart_max_cm, 40.0, 1e-4);
    /* where: the longest stretch counted, the crouch from frame 60 with the bent flicker, 35 frames
     * (the crouch asked for is as long but not counted) */
    assert_int_equal(s.posture_first, 60);
    assert_int_equal(s.posture_frames, 35);
    assert_int_equal(s.posture_worst, MM_POSTURE_CROUCHED);
    motion_metrics_free(&m);
    /* without a reference the posture's seconds are null, the head's heights are not */
    assert_int_equal(motion_metrics_init(&m, N, CONTACT, FPS, 3), 0);
    mm_vec3 w[N];
    stand(w, 0.0f, 0);
    for (int f = 0; f < 3; ++f) motion_metrics_pose(&m, w);
    s = summary(&m);
    assert_true(isnan(s.crouched_s) && isnan(s.calibration_s) && isnan(s.arms_out_s));
    assert_true(isnan(s.head_p50_cm) && isnan(s.hands_apart_max_cm)); /* no posture joints given */
    motion_metrics_free(&m);
}

/* The built-in set's database: its own walk, played with its own labels, sits on its planted
 * heights, upright. */
static void test_database(void **state)
{
    (void)state;
    mm_database db;
    assert_int_equal(test_build_synth_database(&db), 0);
    motion_metrics_db d;
    assert_int_equal(motion_metrics_database(&db, FPS, &d), 0);
    /* its feet stand where they are planted: the height-weighted slide of its own clips is under
     * the 4 cm/s the output is held to (the swing's passes near the ground are not counted) */
    assert_true(d.foot_slide_height_cm_s >= 0.0 && d.foot_slide_height_cm_s < 4.0);
    assert_true(d.reference > 1.4f && d.reference < 1.8f);
    /* the heels' and toes' planted heights: both above the ground, the toes lower */
    for (int side = 0; side < 2; ++side) {
        assert_true(d.planted[2 * side + 1] > 0.0 && d.planted[2 * side + 1] < d.planted[2 * side]);
        assert_true(d.planted[2 * side] < 0.15);
    }
    /* upright locomotion carries the head upright */
    assert_true(d.head_p5_cm <= d.head_p50_cm && d.head_p50_cm <= 100.0 * d.reference);
    assert_true(d.head_p5_cm > 100.0 * MM_POSTURE_CROUCHED_HEIGHT * d.reference);
    assert_true(d.pop_p99_cm > 0.0 && d.pop_p99_cm <= d.max_pop_cm);
    int contact[4];
    mm_posture_joints pj;
    motion_metrics_roles_of_database(&db, contact, &pj);
    int c = mm_database_find_clip(&db, "walk_1.40");
    assert_true(c >= 0);
    const mm_db_clip *clip = &db.clips[c];
    motion_metrics m;
    assert_int_equal(motion_metrics_init(&m, db.joint_count, contact, 1.0 / db.interval, clip->frame_count),
                     0);
    motion_metrics_reference(&m, &pj, d.reference, d.planted);
    mm_skeleton s;
    assert_int_equal(mm_skeleton_init(&s, db.joint_count, NULL), MM_OK);
    memcpy(s.joints, db.joints, sizeof(mm_joint) * (size_t)db.joint_count);
    mm_xform *g = malloc(sizeof(mm_xform) * (size_t)db.joint_count);
    mm_vec3 *w = malloc(sizeof(mm_vec3) * (size_t)db.joint_count);
    for (int f = clip->first_frame; f < clip->first_frame + clip->frame_count; ++f) {
        mm_fk(&s, mm_database_rotations(&db, f), mm_database_positions(&db, f), g);
        for (int j = 0; j < db.joint_count; ++j) w[j] = g[j].translation;
        motion_metrics_frame(&m, 0.0, w, db.contacts[f], NULL, w[0], 0.0f, w[0], 0.0f, 0.0f);
    }
    motion_metrics_seen r = summary(&m);
    assert_true(r.contact_height_err_cm < 1.0);
    assert_true(r.below_ground_cm < 0.5);
    assert_true(r.contact_share > 0.3 && r.contact_share < 0.9);
    assert_true(r.foot_slide_height_cm_s < 10.0);
    assert_near(r.crouched_s + r.bent_s + r.lying_s + r.calibration_s + r.arms_out_s, 0.0, 0.0);
    motion_metrics_free(&m);
    free(g);
    free(w);
    mm_skeleton_free(&s);
    mm_database_free(&db);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_below_ground),
        cmocka_unit_test(test_calibration),
        cmocka_unit_test(test_hand_raised),
        cmocka_unit_test(test_knee_raised),
        cmocka_unit_test(test_pop),
        cmocka_unit_test(test_worst_slide),
        cmocka_unit_test(test_response),
        cmocka_unit_test(test_pop_p99),
        cmocka_unit_test(test_contact_share),
        cmocka_unit_test(test_slide_height),
        cmocka_unit_test(test_posture_seconds),
        cmocka_unit_test(test_database),
        cmocka_unit_test(test_foot_float),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
