/* The frame spans of a take (mm/take_spans.h) and the A pose (mm/posture.h) on a hand-built body:
 * single poses (T pose, A pose at 30 and 45 degrees, arms hanging, arms forward, a bent arm,
 * crouched) judged by mm_posture_a_pose_shape; a take built pose by pose (a T pose, standing,
 * walking, an A pose held, lying down, lying, getting up, a quick sweep of the arms through the A
 * shape into a T pose, walking) whose frames must get the right kinds and spans; and, with
 * MM_DATA_DIR, a LAFAN1 take that opens with a T pose, and the same take with its T pose lowered to
 * an A pose: mm config init leaves either out. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <sys/stat.h>

#include <mm/bvh.h>
#include <mm/config_init.h>
#include <mm/config_json.h>
#include <mm/posture.h>
#include <mm/take_spans.h>

#include "test_util.h"

/* ---- a hand-built body ------------------------------------------------------------------ */

enum {
    HIPS,
    CHEST,
    HEAD,
    L_ARM,
    L_FOREARM,
    L_HAND,
    R_ARM,
    R_FOREARM,
    R_HAND,
    L_UPLEG,
    L_LEG,
    L_FOOT,
    R_UPLEG,
    R_LEG,
    R_FOOT,
    JOINTS
};
static const char *const names[JOINTS] = {"Hips",     "Chest",    "Head",         "LeftArm",   "LeftForeArm",
                                          "LeftHand", "RightArm", "RightForeArm", "RightHand", "LeftUpLeg",
                                          "LeftLeg",  "LeftFoot", "RightUpLeg",   "RightLeg",  "RightFoot"};
static const int parents[JOINTS] = {-1,        HIPS, CHEST,   CHEST, L_ARM, L_FOREARM, CHEST, R_ARM,
                                    R_FOREARM, HIPS, L_UPLEG, L_LEG, HIPS,  R_UPLEG,   R_LEG};
#define UPPER_ARM 0.28f
#define FOREARM   0.26f
#define FPS       30.0f

/* A pose: the hips' place, the body turned tilt degrees back about X (90: lying on the back), the
 * arms down arm_down degrees from level out to the sides (0: a T pose, 90: hanging), swung
 * swing degrees forward (the right arm back), the legs stride degrees apart, and bent the elbows
 * by elbow degrees. Facing +Z, left is +X. */
typedef struct pose {
    mm_vec3 hips;
    float tilt, arm_down, swing, stride, elbow;
    float lean; /* the trunk leans forward by this (deg), the legs stay */
} pose;

static mm_vec3 rot_x(mm_vec3 v, float degrees)
{
    float a = degrees * (float)MM_DEG_TO_RAD;
    return mm_vec3_make(v.x, v.y * cosf(a) - v.z * sinf(a), v.y * sinf(a) + v.z * cosf(a));
}

static void world_of(const pose *p, mm_vec3 w[JOINTS])
{
    mm_vec3 l[JOINTS];
    l[HIPS] = mm_vec3_make(0, 0, 0);
    l[CHEST] = rot_x(mm_vec3_make(0, 0.45f, 0), p->lean);
    l[HEAD] = rot_x(mm_vec3_make(0, 0.67f, 0), p->lean);
    for (int side = 0; side < 2; ++side) {
        float sx = side == 0 ? 1.0f : -1.0f, swing = side == 0 ? p->swing : -p->swing;
        int arm = side == 0 ? L_ARM : R_ARM;
        float a = p->arm_down * (float)MM_DEG_TO_RAD;
        mm_vec3 dir = rot_x(mm_vec3_make(sx * cosf(a), -sinf(a), 0), -swing);
        mm_vec3 fore = rot_x(mm_vec3_make(sx * cosf(a), -sinf(a), 0), -swing - p->elbow);
        l[arm] = rot_x(mm_vec3_make(sx * 0.18f, 0.45f, 0), p->lean);
        l[arm + 1] = mm_vec3_add(l[arm], mm_vec3_scale(rot_x(dir, p->lean), UPPER_ARM));
        l[arm + 2] = mm_vec3_add(l[arm + 1], mm_vec3_scale(rot_x(fore, p->lean), FOREARM));
        int leg = side == 0 ? L_UPLEG : R_UPLEG;
        float s = (side == 0 ? p->stride : -p->stride) * (float)MM_DEG_TO_RAD;
        mm_vec3 down = mm_vec3_make(0, -cosf(s), sinf(s));
        l[leg] = mm_vec3_make(sx * 0.1f, 0, 0);
        l[leg + 1] = mm_vec3_add(l[leg], mm_vec3_scale(down, 0.45f));
        l[leg + 2] = mm_vec3_add(l[leg + 1], mm_vec3_scale(down, 0.42f));
    }
    for (int j = 0; j < JOINTS; ++j) w[j] = mm_vec3_add(p->hips, rot_x(l[j], -p->tilt));
}

static pose standing(float z)
{
    pose p = {mm_vec3_make(0, 0.95f, z), 0, 85, 0, 0, 0, 0};
    return p;
}

static void make_skeleton(mm_skeleton *s)
{
    assert_int_equal(mm_skeleton_init(s, JOINTS, NULL), MM_OK);
    pose rest = standing(0);
    rest.arm_down = 0;
    mm_vec3 w[JOINTS];
    world_of(&rest, w);
    for (int j = 0; j < JOINTS; ++j) {
        snprintf(s->joints[j].name, MM_NAME_MAX, "%s", names[j]);
        s->joints[j].parent = parents[j];
        s->joints[j].offset = parents[j] < 0 ? w[j] : mm_vec3_sub(w[j], w[parents[j]]);
    }
    s->joints[L_HAND].has_end_site = s->joints[R_HAND].has_end_site = true;
    s->joints[L_HAND].end_site = mm_vec3_make(0.08f, 0, 0);
    s->joints[R_HAND].end_site = mm_vec3_make(-0.08f, 0, 0);
}

static void set_frame(mm_clip *c, int f, const pose *p)
{
    mm_vec3 w[JOINTS];
    world_of(p, w);
    for (int j = 0; j < JOINTS; ++j) {
        mm_clip_rotations(c, f)[j] = mm_quat_identity();
        mm_clip_positions(c, f)[j] = parents[j] < 0 ? w[j] : mm_vec3_sub(w[j], w[parents[j]]);
    }
}

static const mm_posture_joints POSTURE_JOINTS = {HIPS, HEAD, L_HAND, R_HAND, {-1, -1}, {-1, -1}};
static const mm_posture_reference REF = {1.62f};

static int a_shape(const pose *p, const mm_posture_arms *arms)
{
    mm_vec3 w[JOINTS];
    world_of(p, w);
    return mm_posture_a_pose_shape(w, arms, &POSTURE_JOINTS, 0.08f, &REF);
}

/* ---- single poses ----------------------------------------------------------------------- */

static void test_a_pose_shape(void **state)
{
    (void)state;
    mm_skeleton s;
    make_skeleton(&s);
    mm_posture_arms arms;
    assert_true(mm_posture_find_arms(&s, L_HAND, R_HAND, &arms));
    assert_int_equal(arms.elbow[0], L_FOREARM);
    assert_int_equal(arms.shoulder[0], L_ARM);
    assert_int_equal(arms.elbow[1], R_FOREARM);
    assert_int_equal(arms.shoulder[1], R_ARM);
    /* no hand, or a chain too short: not found */
    mm_posture_arms none;
    assert_false(mm_posture_find_arms(&s, -1, R_HAND, &none));
    assert_int_equal(none.shoulder[1], -1);
    assert_false(mm_posture_find_arms(&s, CHEST, R_HAND, &none)); /* 0.45 m to the hips, then no more */

    pose p = standing(0);
    p.arm_down = 45; /* an A pose */
    assert_true(a_shape(&p, &arms));
    p.arm_down = 30;
    assert_true(a_shape(&p, &arms));
    p.arm_down = 55;
    assert_true(a_shape(&p, &arms));
    p.arm_down = 0; /* a T pose: the other calibration pose, classify's */
    assert_false(a_shape(&p, &arms));
    p.arm_down = 85; /* standing, arms down */
    assert_false(a_shape(&p, &arms));
    p.arm_down = 70;
    assert_false(a_shape(&p, &arms));
    /* 39 degrees down but forward, not to the sides (arms reaching ahead) */
    p.arm_down = 80;
    p.swing = 50;
    assert_false(a_shape(&p, &arms));
    /* the elbows bent 70 degrees: not straight */
    p.arm_down = 45;
    p.swing = 0;
    p.elbow = 70;
    assert_false(a_shape(&p, &arms));
    /* crouched (the hips down 0.3 m) or bent over: not upright */
    p.elbow = 0;
    p.hips.y -= 0.3f;
    assert_false(a_shape(&p, &arms));
    p.hips.y += 0.3f;
    p.lean = 60;
    assert_false(a_shape(&p, &arms));
    /* lying on the back with the arms at 45 degrees */
    p.lean = 0;
    p.tilt = 90;
    p.hips.y = 0.2f;
    assert_false(a_shape(&p, &arms));
    /* what classify says of them: the T pose is calibration, the A pose upright */
    mm_vec3 w[JOINTS];
    pose t = standing(0);
    t.arm_down = 0;
    world_of(&t, w);
    assert_int_equal(mm_posture_classify(w, &POSTURE_JOINTS, 0.08f, &REF), MM_POSTURE_CALIBRATION);
    pose a = standing(0);
    a.arm_down = 45;
    world_of(&a, w);
    assert_int_not_equal(mm_posture_classify(w, &POSTURE_JOINTS, 0.08f, &REF), MM_POSTURE_CALIBRATION);
    mm_skeleton_free(&s);
}

/* ---- a take ----------------------------------------------------------------------------- */

/* Segments of the take, in frames at FPS. */
enum {
    T0 = 0,       /* T pose */
    STAND1 = 60,  /* standing, arms down */
    WALK1 = 150,  /* walking 1.3 m/s, arms swinging */
    STAND2 = 330, /* standing */
    A0 = 375,     /* A pose held */
    STAND3 = 435, /* standing */
    DOWN0 = 495,  /* lying down: 1.5 s */
    LYING0 = 540, /* lying on the back */
    UP0 = 630,    /* getting up: 1.5 s */
    STAND4 = 675, /* standing */
    SWEEP0 = 735, /* the arms raised from hanging to level in 1 s */
    T1 = 765,     /* T pose */
    WALK2 = 795,  /* walking */
    END = 975
};

static pose pose_at(int f, float *z)
{
    pose p = standing(*z);
    float t = (float)f / FPS;
    if (f < STAND1 || (f >= T1 && f < WALK2)) {
        p.arm_down = 0;
    } else if ((f >= WALK1 && f < STAND2) || f >= WALK2) {
        *z += 1.3f / FPS;
        p.hips.z = *z;
        p.hips.y = 0.95f - 0.02f * cosf(4.0f * (float)MM_PI * t / 1.1f);
        p.swing = 25.0f * sinf(2.0f * (float)MM_PI * t / 1.1f);
        p.stride = 0.8f * p.swing;
    } else if (f >= A0 && f < STAND3) {
        p.arm_down = 40;
    } else if (f >= DOWN0 && f < UP0 + 45) {
        /* down, lying, up: the body turned back to 90 degrees with the hips down at 0.15 m */
        float u = f < LYING0 ? (float)(f - DOWN0) / 45.0f : f < UP0 ? 1.0f : 1.0f - (float)(f - UP0) / 45.0f;
        p.tilt = 90.0f * u;
        p.hips.y = 0.95f - 0.8f * u;
        p.arm_down = 80;
    } else if (f >= SWEEP0 && f < T1) {
        p.arm_down = 85.0f * (1.0f - (float)(f - SWEEP0) / 30.0f);
    }
    return p;
}

static int in_ranges(const mm_config_range *r, int count, int f)
{
    for (int i = 0; i < count; ++i)
        if (f >= r[i].begin && f < r[i].end) return 1;
    return 0;
}

static void test_take(void **state)
{
    (void)state;
    mm_skeleton s;
    make_skeleton(&s);
    mm_clip clip;
    assert_int_equal(mm_clip_init(&clip, &s, END, FPS, NULL), MM_OK);
    float z = 0.0f;
    for (int f = 0; f < END; ++f) {
        pose p = pose_at(f, &z);
        set_frame(&clip, f, &p);
    }
    /* FK gives the hand-built world back */
    mm_xform g[JOINTS];
    mm_vec3 w[JOINTS];
    z = 0.0f;
    for (int f = 0; f < END; ++f) {
        pose p = pose_at(f, &z);
        world_of(&p, w);
        mm_clip_fk(&clip, f, g);
        for (int j = 0; j < JOINTS; ++j)
            assert_true(mm_vec3_length(mm_vec3_sub(g[j].translation, w[j])) < 1e-5f);
    }
    const mm_take_joints joints = {HIPS, CHEST, HEAD, L_HAND, R_HAND};
    mm_take_spans sp;
    assert_int_equal(mm_take_spans_find(&clip, &joints, NULL, &sp), MM_OK);
    assert_true(sp.arms_found);
    assert_int_equal(sp.frame_count, END);
    assert_near(sp.upright_head_height, 1.62 - 0.08, 0.03);
    char got[END + 1];
    for (int f = 0; f < END; ++f) got[f] = "ucbltsAgd"[sp.kinds[f]];
    got[END] = 0;
    print_message("kinds: %s\n", got);
    static const struct {
        int begin, end, kind;
        const char *what;
    } want[] = {
        {T0 + 1, STAND1 - 1, MM_POSTURE_CALIBRATION, "the T pose"},
        {STAND1 + 2, WALK1, MM_POSTURE_UPRIGHT, "standing"},
        {WALK1, STAND2, MM_POSTURE_UPRIGHT, "walking"},
        {A0 + 4, STAND3 - 4, MM_SPAN_A_POSE, "the A pose"},
        {STAND3 + 4, DOWN0, MM_POSTURE_UPRIGHT, "standing"},
        {LYING0 - 5, UP0 + 5, MM_POSTURE_LYING, "lying"},
        {STAND4 + 4, SWEEP0, MM_POSTURE_UPRIGHT, "standing"},
        {T1 + 1, WALK2 - 1, MM_POSTURE_CALIBRATION, "the T pose after the sweep"},
        {WALK2 + 2, END, MM_POSTURE_UPRIGHT, "walking"},
    };
    for (size_t i = 0; i < sizeof want / sizeof want[0]; ++i)
        for (int f = want[i].begin; f < want[i].end; ++f)
            if (sp.kinds[f] != want[i].kind)
                fail_msg("frame %d (%s): %s, not %s", f, want[i].what, mm_span_kind_name(sp.kinds[f]),
                         mm_span_kind_name(want[i].kind));
    /* lying down and getting up: the frames between lying and upright that are bent or crouched */
    int down = 0, up = 0;
    for (int f = DOWN0; f < LYING0; ++f) down += sp.kinds[f] == MM_SPAN_GETTING_UP;
    for (int f = UP0; f < STAND4; ++f) up += sp.kinds[f] == MM_SPAN_GETTING_UP;
    assert_true(down >= 5);
    assert_true(up >= 5);
    for (int f = DOWN0; f < STAND4; ++f)
        if (sp.kinds[f] != MM_POSTURE_LYING && sp.kinds[f] != MM_SPAN_GETTING_UP &&
            sp.kinds[f] != MM_POSTURE_UPRIGHT)
            fail_msg("frame %d (lying down, getting up): %s", f, mm_span_kind_name(sp.kinds[f]));
    /* the sweep of the arms passes 15-60 degrees down moving: never an A pose */
    for (int f = SWEEP0; f < T1; ++f) assert_int_not_equal(sp.kinds[f], MM_SPAN_A_POSE);
    for (int f = 0; f < END; ++f)
        if (sp.kinds[f] == MM_SPAN_A_POSE) assert_true(f >= A0 && f < STAND3);
    /* the spans: left out the poses that are not motion with 1 s around; walking is locomotion,
     * standing idle (long enough after the pad) */
    int pad = (int)FPS;
    for (int f = 0; f < END; ++f) {
        int out = in_ranges(sp.excluded, sp.excluded_count, f), idle = in_ranges(sp.idle, sp.idle_count, f),
            loco = in_ranges(sp.locomotion, sp.locomotion_count, f);
        assert_true(out + idle + loco <= 1);
        int pose_out =
            f < STAND1 + pad ||
            (f >= A0 + 4 - pad && f < STAND3 - 4 + pad) /* the hands still from 0.1 s in */ ||
            (f >= DOWN0 + 10 - pad &&
             f < STAND4 - 10 + pad) /* the first and last 1/3 s of the way down and up are still upright */;
        if (pose_out && !out) fail_msg("frame %d is not left out", f);
        if ((f >= WALK1 + 10 && f < STAND2 - 10) || (f >= WALK2 + pad + 10 && f < END - 10))
            if (!loco) fail_msg("frame %d (walking) is not locomotion", f);
    }
    assert_true(in_ranges(sp.idle, sp.idle_count, STAND1 + pad + 10));
    mm_take_spans_free(&sp);

    /* without hands no calibration pose is looked for: the T and A poses are then motion */
    const mm_take_joints no_hands = {HIPS, CHEST, HEAD, -1, -1};
    assert_int_equal(mm_take_spans_find(&clip, &no_hands, NULL, &sp), MM_OK);
    assert_false(sp.arms_found);
    for (int f = 0; f < END; ++f) {
        assert_int_not_equal(sp.kinds[f], MM_SPAN_A_POSE);
        assert_int_not_equal(sp.kinds[f], MM_POSTURE_CALIBRATION);
    }
    mm_take_spans_free(&sp);
    /* the names and what is left out */
    assert_string_equal(mm_span_kind_name(MM_SPAN_A_POSE), "a_pose");
    assert_string_equal(mm_span_kind_name(MM_SPAN_GETTING_UP), "getting_up");
    assert_string_equal(mm_span_kind_name(MM_POSTURE_LYING), "lying");
    assert_null(mm_span_kind_name(MM_SPAN_KIND_COUNT));
    assert_true(mm_span_left_out(MM_SPAN_A_POSE) && mm_span_left_out(MM_POSTURE_CALIBRATION));
    assert_false(mm_span_left_out(MM_POSTURE_CROUCHED) || mm_span_left_out(MM_POSTURE_ARMS_SPREAD));
    mm_clip_free(&clip);
    mm_skeleton_free(&s);
}

/* A take over an obstacle course: walking on the floor (4 s), on a platform 0.8 m up (3 s), on the
 * floor again (3 s) with a tuck jump in it (0.5 s in the air, the feet drawn up to the hips' old
 * height). With one floor for the take the platform (30% of it) would lift the upright head height
 * by 0.8 m and make every floor frame a crouch; the ground under each frame keeps them upright, and
 * the jump keeps the floor it leaves. */
static void test_ground(void **state)
{
    (void)state;
    mm_skeleton s;
    make_skeleton(&s);
    const int n = 300, up = 120, down = 210, jump = 250, land = 265;
    mm_clip clip;
    assert_int_equal(mm_clip_init(&clip, &s, n, FPS, NULL), MM_OK);
    float z = 0.0f;
    for (int f = 0; f < n; ++f) {
        float t = (float)f / FPS;
        z += 1.3f / FPS;
        pose p = standing(z);
        p.swing = 25.0f * sinf(2.0f * (float)MM_PI * t / 1.1f);
        p.stride = 0.8f * p.swing;
        if (f >= up && f < down) p.hips.y += 0.8f;
        mm_vec3 w[JOINTS];
        if (f >= jump && f < land) { /* in the air, the knees drawn up: the feet 0.5 m up, the hips 1.2 m */
            p.hips.y = 1.2f;
            p.stride = 0.0f;
            world_of(&p, w);
            for (int side = 0; side < 2; ++side) {
                int leg = side == 0 ? L_UPLEG : R_UPLEG;
                w[leg + 1] = mm_vec3_add(w[leg], mm_vec3_make(0, -0.2f, 0.35f));
                w[leg + 2] = mm_vec3_add(w[leg + 1], mm_vec3_make(0, -0.4f, -0.1f));
            }
        } else {
            world_of(&p, w);
        }
        for (int j = 0; j < JOINTS; ++j) {
            mm_clip_rotations(&clip, f)[j] = mm_quat_identity();
            mm_clip_positions(&clip, f)[j] = parents[j] < 0 ? w[j] : mm_vec3_sub(w[j], w[parents[j]]);
        }
    }
    const mm_take_joints joints = {HIPS, CHEST, HEAD, L_HAND, R_HAND};
    mm_take_spans sp;
    assert_int_equal(mm_take_spans_find(&clip, &joints, NULL, &sp), MM_OK);
    print_message("upright head height %.3f m\n", (double)sp.upright_head_height);
    assert_near(sp.upright_head_height, 1.62 - 0.08, 0.05);
    for (int f = 0; f < n; ++f)
        if (sp.kinds[f] != MM_POSTURE_UPRIGHT)
            fail_msg("frame %d: %s, not upright", f, mm_span_kind_name(sp.kinds[f]));
    assert_int_equal(sp.excluded_count, 0);
    assert_int_equal(sp.locomotion_count, 1);
    mm_take_spans_free(&sp);
    mm_clip_free(&clip);
    mm_skeleton_free(&s);
}

/* ---- LAFAN1 ----------------------------------------------------------------------------- */

/* The frames of the take's opening run where the hands are more than 1.2 m apart at more than
 * 1.2 m up (a T pose; measured by FK, apart from the posture module); -1 when the take does not
 * open so. */
static int opening_t_pose_end(const mm_clip *c, int left, int right)
{
    mm_xform *g = (mm_xform *)malloc(sizeof(mm_xform) * (size_t)c->skeleton.joint_count);
    assert_non_null(g);
    int f = 0;
    for (; f < c->frame_count; ++f) {
        mm_clip_fk(c, f, g);
        mm_vec3 l = g[left].translation, r = g[right].translation;
        if (!(mm_vec3_length(mm_vec3_sub(l, r)) > 1.2f && l.y > 1.2f && r.y > 1.2f)) break;
    }
    free(g);
    return f > 0 ? f : -1;
}

/* mm_config_init on the first 20 s of walk4_subject1 (opening with a T pose) and on it with the T
 * pose lowered 30 degrees at the shoulders into an A pose: no clip holds those frames. */
static void test_lafan1(void **state)
{
    (void)state;
    char src[1024];
    if (!test_shared_data("lafan1/walk4_subject1.bvh", src, sizeof src)) skip();
    mm_bvh bvh;
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_bvh_load(src, NULL, &bvh, &err), MM_OK);
    mm_bvh_import_desc imp;
    memset(&imp, 0, sizeof imp);
    imp.scale = 0.01f;
    mm_clip full, clip;
    assert_int_equal(mm_bvh_to_clip(&bvh, &imp, &full, &err), MM_OK);
    mm_bvh_free(&bvh);
    int n = 600;
    assert_int_equal(mm_clip_init(&clip, &full.skeleton, n, full.fps, NULL), MM_OK);
    size_t count = (size_t)n * (size_t)full.skeleton.joint_count;
    memcpy(clip.rotations, full.rotations, count * sizeof(mm_quat));
    memcpy(clip.positions, full.positions, count * sizeof(mm_vec3));
    mm_clip_free(&full);
    const mm_skeleton *s = &clip.skeleton;
    int left = mm_skeleton_find(s, "LeftHand"), right = mm_skeleton_find(s, "RightHand");
    int t_end = opening_t_pose_end(&clip, left, right);
    print_message("walk4_subject1 opens with a T pose over frames [0, %d)\n", t_end);
    assert_true(t_end >= 30);
    for (int variant = 0; variant < 2; ++variant) {
        if (variant == 1) { /* the T pose lowered: each upper arm turned 30 degrees down about its
                               horizontal normal, in the world, then made local again */
            int jc = s->joint_count;
            mm_xform *g = (mm_xform *)malloc(sizeof(mm_xform) * (size_t)jc);
            assert_non_null(g);
            const char *const uppers[2] = {"LeftArm", "RightArm"};
            float lowest = 90.0f, highest = 0.0f;
            for (int f = 0; f < t_end; ++f) {
                mm_clip_fk(&clip, f, g);
                for (int k = 0; k < 2; ++k) {
                    int j = mm_skeleton_find(s, uppers[k]), p = s->joints[j].parent;
                    mm_vec3 hand = g[k == 0 ? left : right].translation,
                            d = mm_vec3_sub(hand, g[j].translation);
                    mm_vec3 axis = mm_vec3_normalize(mm_vec3_cross(mm_vec3_make(0, 1, 0), d));
                    mm_quat turn = mm_quat_from_axis_angle(axis, 30.0f * (float)MM_DEG_TO_RAD);
                    mm_quat world = mm_quat_mul(turn, g[j].rotation);
                    mm_clip_rotations(&clip, f)[j] =
                        mm_quat_normalize(mm_quat_mul(mm_quat_conj(g[p].rotation), world));
                }
                /* the arms now 30-50 degrees down: checked by FK */
                mm_clip_fk(&clip, f, g);
                for (int k = 0; k < 2; ++k) {
                    int j = mm_skeleton_find(s, uppers[k]);
                    mm_vec3 d = mm_vec3_sub(g[k == 0 ? left : right].translation, g[j].translation);
                    float down = atan2f(-d.y, sqrtf(d.x * d.x + d.z * d.z)) * (float)MM_RAD_TO_DEG;
                    lowest = fminf(lowest, down);
                    highest = fmaxf(highest, down);
                }
            }
            print_message("  A pose: the arms %.1f to %.1f degrees down\n", (double)lowest, (double)highest);
            assert_true(lowest > 25.0f && highest < 60.0f);
            free(g);
            assert_int_equal(opening_t_pose_end(&clip, left, right), -1);
        }
        mm_config_init_take take = {"walk4_subject1.bvh", NULL, NULL, "walk4", &clip};
        mm_config cfg;
        mm_config_init_report rep;
        memset(&err, 0, sizeof err);
        mm_config_init_desc desc;
        memset(&desc, 0, sizeof desc);
        desc.scale = 1.0;
        assert_int_equal(mm_config_init(&take, 1, &desc, &cfg, &rep, &err), MM_OK);
        print_message("  %s: T pose %.2f s, A pose %.2f s left out; %d clips\n",
                      variant ? "A pose" : "T pose", (double)rep.kind_seconds[MM_POSTURE_CALIBRATION],
                      (double)rep.kind_seconds[MM_SPAN_A_POSE], cfg.clip_count);
        assert_int_equal(rep.calibration_starts, 1);
        /* the A pose from when the hands are still: all but the ends of the T pose's run */
        assert_true(rep.kind_seconds[variant ? MM_SPAN_A_POSE : MM_POSTURE_CALIBRATION] * clip.fps >=
                    0.8f * t_end);
        assert_true(cfg.clip_count >= 1);
        for (int i = 0; i < cfg.clip_count; ++i)
            for (int r = 0; r < cfg.clips[i].range_count; ++r) {
                print_message("    %s [%d, %d)\n", cfg.clips[i].name, cfg.clips[i].ranges[r].begin,
                              cfg.clips[i].ranges[r].end);
                assert_true(cfg.clips[i].ranges[r].begin >= t_end);
            }
        mm_config_free(&cfg);
    }
    mm_clip_free(&clip);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_a_pose_shape),
        cmocka_unit_test(test_take),
        cmocka_unit_test(test_ground),
        cmocka_unit_test(test_lafan1),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
