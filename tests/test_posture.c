/* Posture (mm/posture.h): hand-made poses of a body whose upright head is at 1.6 m, and the
 * flicker removal on hand-made sequences. */
#include <math.h>

#include <mm/posture.h>

#include "test_util.h"

/* joints: 0 hips, 1 head, 2 left hand, 3 right hand; with legs 4, 5 the left and right thigh's top,
 * 6, 7 the left and right knee */
static const mm_posture_joints JOINTS = {0, 1, 2, 3, {-1, -1}, {-1, -1}};
static const mm_posture_joints WITH_LEGS = {0, 1, 2, 3, {6, 7}, {4, 5}};
static const mm_posture_reference REF = {1.6f};

/* A body: the hips at height hips_y, the trunk (hips to head, 0.65 m) leaning lean degrees toward
 * +X, the hands hanging beside the hips or (arms_out) straight out at shoulder height. */
static void body(mm_vec3 *w, float hips_y, float lean, int arms_out)
{
    float a = lean * (float)MM_DEG_TO_RAD;
    w[0] = mm_vec3_make(0.0f, hips_y, 0.0f);
    w[1] = mm_vec3_make(0.65f * sinf(a), hips_y + 0.65f * cosf(a), 0.0f);
    if (arms_out) {
        w[2] = mm_vec3_make(-0.8f, w[1].y - 0.15f, 0.0f);
        w[3] = mm_vec3_make(0.8f, w[1].y - 0.15f, 0.0f);
    } else {
        w[2] = mm_vec3_make(-0.2f, hips_y - 0.05f, 0.0f);
        w[3] = mm_vec3_make(0.2f, hips_y - 0.05f, 0.0f);
    }
}

static void test_poses(void **state)
{
    (void)state;
    mm_vec3 w[4];
    body(w, 0.95f, 0.0f, 0); /* the head at 1.6: upright */
    assert_int_equal(mm_posture_classify(w, &JOINTS, 0.0f, &REF), MM_POSTURE_UPRIGHT);
    assert_false(mm_posture_arms_out(w, &JOINTS, &REF));
    body(w, 0.63f, 0.0f, 0); /* the head at 1.28 = 0.8 of the reference, the trunk upright */
    assert_int_equal(mm_posture_classify(w, &JOINTS, 0.0f, &REF), MM_POSTURE_CROUCHED);
    body(w, 0.95f, 60.0f, 0); /* bent 60 degrees at the waist */
    assert_int_equal(mm_posture_classify(w, &JOINTS, 0.0f, &REF), MM_POSTURE_BENT);
    body(w, 0.95f, 30.0f, 0); /* a 30 degree lean with the head at 1.51 (0.94): upright */
    assert_int_equal(mm_posture_classify(w, &JOINTS, 0.0f, &REF), MM_POSTURE_UPRIGHT);
    body(w, 0.15f, 90.0f, 0); /* on the ground */
    assert_int_equal(mm_posture_classify(w, &JOINTS, 0.0f, &REF), MM_POSTURE_LYING);
    body(w, 0.95f, 0.0f, 1); /* a T pose: the hands 1.6 m apart at 1.45 m */
    assert_int_equal(mm_posture_classify(w, &JOINTS, 0.0f, &REF), MM_POSTURE_CALIBRATION);
    assert_true(mm_posture_arms_out(w, &JOINTS, &REF));
    /* the same T pose on ground 2 m up is the same pose */
    for (int j = 0; j < 4; ++j) w[j].y += 2.0f;
    assert_int_equal(mm_posture_classify(w, &JOINTS, 2.0f, &REF), MM_POSTURE_CALIBRATION);
    /* arms out but crouched: the arms spread, a gesture */
    body(w, 0.63f, 0.0f, 1);
    assert_int_equal(mm_posture_classify(w, &JOINTS, 0.0f, &REF), MM_POSTURE_ARMS_SPREAD);
    assert_true(mm_posture_arms_out(w, &JOINTS, &REF));
    /* upright with the hands 1.6 m apart at the hips' height: spread, not a calibration pose */
    body(w, 0.95f, 0.0f, 0);
    w[2].x = -0.8f;
    w[3].x = 0.8f;
    assert_int_equal(mm_posture_classify(w, &JOINTS, 0.0f, &REF), MM_POSTURE_ARMS_SPREAD);
    /* 1.3 m apart (0.75 of the stature 1.74 m): still walking */
    w[2].x = -0.65f;
    w[3].x = 0.65f;
    assert_int_equal(mm_posture_classify(w, &JOINTS, 0.0f, &REF), MM_POSTURE_UPRIGHT);
    /* a hand at the head's height (walking, the other hanging): a hand raised; at 0.85 of the
     * reference, 0.15 of it below the head, still walking, as running's arms pump it there */
    body(w, 0.95f, 0.0f, 0);
    w[3] = mm_vec3_make(0.1f, 1.6f, 0.1f);
    assert_int_equal(mm_posture_classify(w, &JOINTS, 0.0f, &REF), MM_POSTURE_HAND_RAISED);
    w[3].y = 0.85f * 1.6f;
    assert_int_equal(mm_posture_classify(w, &JOINTS, 0.0f, &REF), MM_POSTURE_UPRIGHT);
    /* the same on ground 1 m up, or with the ground unknown (the floor below): judged against the
     * head */
    for (int j = 0; j < 4; ++j) w[j].y += 1.0f;
    assert_int_equal(mm_posture_classify(w, &JOINTS, 1.0f, &REF), MM_POSTURE_UPRIGHT);
    assert_int_equal(mm_posture_classify(w, &JOINTS, 0.0f, &REF), MM_POSTURE_UPRIGHT);
    w[3].y = 2.55f;
    assert_int_equal(mm_posture_classify(w, &JOINTS, 1.0f, &REF), MM_POSTURE_HAND_RAISED);
    /* without hands never a calibration pose; without a reference or a head always upright */
    body(w, 0.95f, 0.0f, 1);
    mm_posture_joints no_hands = {0, 1, -1, -1, {-1, -1}, {-1, -1}},
                      no_head = {0, -1, 2, 3, {-1, -1}, {-1, -1}};
    assert_int_equal(mm_posture_classify(w, &no_hands, 0.0f, &REF), MM_POSTURE_UPRIGHT);
    assert_false(mm_posture_arms_out(w, &no_hands, &REF));
    body(w, 0.15f, 90.0f, 0);
    assert_int_equal(mm_posture_classify(w, &no_head, 0.0f, &REF), MM_POSTURE_UPRIGHT);
    mm_posture_reference none = {0.0f};
    assert_int_equal(mm_posture_classify(w, &JOINTS, 0.0f, &none), MM_POSTURE_UPRIGHT);
    w[1].x = NAN;
    assert_int_equal(mm_posture_classify(w, &JOINTS, 0.0f, &REF), MM_POSTURE_UPRIGHT);
    assert_string_equal(mm_posture_name(MM_POSTURE_CALIBRATION), "calibration");
    assert_string_equal(mm_posture_name(MM_POSTURE_ARMS_SPREAD), "arms_spread");
    assert_string_equal(mm_posture_name(MM_POSTURE_HAND_RAISED), "hand_raised");
    assert_string_equal(mm_posture_name(MM_POSTURE_KNEE_RAISED), "knee_raised");
    assert_null(mm_posture_name(MM_POSTURE_COUNT));
}

/* The body of body() with legs: each thigh 0.45 m from its top (0.1 m to the side of the hips, 5 cm
 * under them) to the knee, the left thigh elevation_deg above level (-90: hanging), forward (+Z),
 * the right hanging. */
static void body_with_legs(mm_vec3 *w, float hips_y, float elevation_deg)
{
    body(w, hips_y, 0.0f, 0);
    float a = elevation_deg * (float)MM_DEG_TO_RAD;
    w[4] = mm_vec3_make(-0.1f, hips_y - 0.05f, 0.0f);
    w[5] = mm_vec3_make(0.1f, hips_y - 0.05f, 0.0f);
    w[6] = mm_vec3_add(w[4], mm_vec3_make(0.0f, 0.45f * sinf(a), 0.45f * cosf(a)));
    w[7] = mm_vec3_add(w[5], mm_vec3_make(0.0f, -0.45f, 0.0f));
}

static void test_knee_raised(void **state)
{
    (void)state;
    mm_vec3 w[8];
    /* standing: both thighs hang, sine -1 */
    body_with_legs(w, 0.95f, -90.0f);
    assert_near(mm_posture_thigh_sine(w, &WITH_LEGS, 0), -1.0, 1e-6);
    assert_int_equal(mm_posture_classify(w, &WITH_LEGS, 0.0f, &REF), MM_POSTURE_UPRIGHT);
    /* a running stride swings the thigh forward to 30 degrees below level (sine -0.5): upright */
    body_with_legs(w, 0.95f, -30.0f);
    assert_near(mm_posture_thigh_sine(w, &WITH_LEGS, 0), -0.5, 1e-6);
    assert_int_equal(mm_posture_classify(w, &WITH_LEGS, 0.0f, &REF), MM_POSTURE_UPRIGHT);
    /* 14.5 degrees below level (sine -0.25) is still a stride; 8.6 (sine -0.15) and level are a
     * knee raised, on either leg */
    body_with_legs(w, 0.95f, -14.48f);
    assert_int_equal(mm_posture_classify(w, &WITH_LEGS, 0.0f, &REF), MM_POSTURE_UPRIGHT);
    body_with_legs(w, 0.95f, -8.63f);
    assert_near(mm_posture_thigh_sine(w, &WITH_LEGS, 0), -0.15, 1e-4);
    assert_int_equal(mm_posture_classify(w, &WITH_LEGS, 0.0f, &REF), MM_POSTURE_KNEE_RAISED);
    body_with_legs(w, 0.95f, 0.0f);
    assert_int_equal(mm_posture_classify(w, &WITH_LEGS, 0.0f, &REF), MM_POSTURE_KNEE_RAISED);
    const mm_posture_joints swapped = {0, 1, 2, 3, {7, 6}, {5, 4}};
    assert_near(mm_posture_thigh_sine(w, &swapped, 1), 0.0, 1e-6);
    assert_int_equal(mm_posture_classify(w, &swapped, 0.0f, &REF), MM_POSTURE_KNEE_RAISED);
    /* without the legs' joints, never */
    assert_int_equal(mm_posture_classify(w, &JOINTS, 0.0f, &REF), MM_POSTURE_UPRIGHT);
    assert_true(isnan(mm_posture_thigh_sine(w, &JOINTS, 0)));
    /* a hand raised wins; so does a crouch (the head at 0.8 of the reference: the thigh comes level
     * in a squat) */
    w[3] = mm_vec3_make(0.1f, 1.6f, 0.1f);
    assert_int_equal(mm_posture_classify(w, &WITH_LEGS, 0.0f, &REF), MM_POSTURE_HAND_RAISED);
    body_with_legs(w, 0.63f, 0.0f);
    assert_int_equal(mm_posture_classify(w, &WITH_LEGS, 0.0f, &REF), MM_POSTURE_CROUCHED);
}

/* A skeleton of the legs (metres): 0 hips; the left leg 1 thigh's top, 2 knee, 3 foot, 4 toe; the
 * right 5 thigh's top, 6 a twist joint 0.2 m down the thigh, 7 knee, 8 foot; 9 a stub under the
 * hips. */
static void test_find_legs(void **state)
{
    (void)state;
    static const int parents[10] = {-1, 0, 1, 2, 3, 0, 5, 6, 7, 0};
    static const float offsets[10][3] = {
        {0, 0.95f, 0},     {-0.1f, -0.05f, 0}, {0, -0.45f, 0}, {0, -0.42f, 0}, {0, -0.05f, 0.12f},
        {0.1f, -0.05f, 0}, {0, -0.2f, 0},      {0, -0.25f, 0}, {0, -0.42f, 0}, {0, -0.1f, 0}};
    mm_skeleton s;
    assert_int_equal(mm_skeleton_init(&s, 10, NULL), MM_OK);
    for (int j = 0; j < 10; ++j) {
        s.joints[j].parent = parents[j];
        s.joints[j].offset = mm_vec3_make(offsets[j][0], offsets[j][1], offsets[j][2]);
    }
    mm_posture_joints pj = JOINTS;
    assert_int_equal(mm_posture_find_legs(&s, 3, 8, &pj), 2);
    assert_int_equal(pj.knee[0], 2);
    assert_int_equal(pj.thigh[0], 1);
    assert_int_equal(pj.knee[1], 7);
    assert_int_equal(pj.thigh[1], 6); /* the twist joint, on the thigh's line */
    /* the toe as the foot: 0.13 m to the ankle is too short a bone, the knee is found past it */
    assert_int_equal(mm_posture_find_legs(&s, 4, -1, &pj), 1);
    assert_int_equal(pj.knee[0], 2);
    assert_int_equal(pj.thigh[0], 1);
    assert_int_equal(pj.knee[1], -1);
    assert_int_equal(pj.thigh[1], -1);
    /* a chain too short (the stub: the hips, then nothing), or out of range: not found */
    assert_int_equal(mm_posture_find_legs(&s, 9, 10, &pj), 0);
    assert_int_equal(pj.knee[0], -1);
    assert_int_equal(pj.thigh[0], -1);
    mm_skeleton_free(&s);
}

static void test_reference_height(void **state)
{
    (void)state;
    float h[100];
    for (int i = 0; i < 100; ++i) h[i] = (float)((i * 37) % 100) / 100.0f; /* 0 .. 0.99, shuffled */
    /* the 0.9 quantile: rank floor(0.9 x 99) = 89 */
    assert_near(mm_posture_reference_height(h, 100), 0.89, 1e-6);
    assert_near(mm_posture_reference_height(h, 0), 0.0, 0.0);
    mm_posture_reference r = {1.84f};
    assert_near(mm_posture_stature(&r), 2.0, 1e-6);
}

/* The posture letters: upright, crouched, bent, lying, calibration (t), arms spread, hand raised,
 * knee raised. */
static const char LETTERS[MM_POSTURE_COUNT + 1] = "ucbltahk";

/* Runs a string of posture letters through the flicker removal: with min_frames for every posture,
 * or with each[posture] when each is not NULL. */
static void flicker_with(const char *in, int min_frames, const int *each, const char *want)
{
    uint8_t p[256];
    int n = (int)strlen(in);
    for (int i = 0; i < n; ++i) p[i] = (uint8_t)(strchr(LETTERS, in[i]) - LETTERS);
    if (each)
        mm_posture_remove_flicker_each(p, n, each);
    else
        mm_posture_remove_flicker(p, n, min_frames);
    char got[257];
    for (int i = 0; i < n; ++i) got[i] = LETTERS[p[i]];
    got[n] = 0;
    assert_string_equal(got, want);
}

/* Every posture's minimum all, but posture p's its. */
static void minima_but(int all, mm_posture p, int its, int each[MM_POSTURE_COUNT])
{
    for (int k = 0; k < MM_POSTURE_COUNT; ++k) each[k] = all;
    each[p] = its;
}

static void flicker(const char *in, int min_frames, const char *want)
{
    flicker_with(in, min_frames, NULL, want);
    /* a minimum for each posture, all the same, is the one minimum */
    int each[MM_POSTURE_COUNT];
    minima_but(min_frames, MM_POSTURE_UPRIGHT, min_frames, each);
    flicker_with(in, 0, each, want);
}

static void test_flicker(void **state)
{
    (void)state;
    /* a short dip in a long run goes */
    flicker("uuuuuuccuuuuuu", 4, "uuuuuuuuuuuuuu");
    /* long runs stay */
    flicker("uuuuccccbbbb", 4, "uuuuccccbbbb");
    /* at the start a short run takes the run after; at the end the run before */
    flicker("ccuuuuuu", 4, "uuuuuuuu");
    flicker("uuuuuubb", 4, "uuuuuuuu");
    /* short runs in a row, together as long as the minimum, are one spell away from upright: they
     * settle among themselves (the first takes the run after it, and so on) and stay */
    flicker("uuuucblcuuuu", 4, "uuuuccccuuuu");
    /* a crouch that leans past the bent threshold for a few frames is one spell */
    flicker("uuuuuuuuccccbbbbbcccuuuuuuuu", 8, "uuuuuuuubbbbbbbbbbbbuuuuuuuu");
    /* together still short, they join the run before */
    flicker("uuuucbluuuu", 4, "uuuuuuuuuuu");
    /* two short runs at the start: the first joins the second, which is then long enough */
    flicker("ccbbbuuuuu", 4, "bbbbbuuuuu");
    /* and when the two are still short together, both join the run after */
    flicker("cbuuuuu", 4, "uuuuuuu");
    /* a crouch of 4 frames between uprights stays, one of 3 goes */
    flicker("uuuuccccuuuubbbuuuu", 4, "uuuuccccuuuuuuuuuuu");
    /* a whole sequence of one short run is left as it is, and everything at a minimum of 1; short
     * runs alone make one run */
    flicker("ccu", 4, "uuu");
    flicker("ccc", 4, "ccc");
    flicker("ucbltu", 1, "ucbltu");
    flicker("", 4, "");
}

/* A minimum for each posture: the hands spread wide kept however brief (a minimum of 1) while the
 * others need 4 frames; a crouch needing 6 frames where a stoop needs 2. */
static void test_flicker_each(void **state)
{
    (void)state;
    int arms[MM_POSTURE_COUNT];
    minima_but(4, MM_POSTURE_ARMS_SPREAD, 1, arms);
    /* a frame of arms spread stays, at the start, in the middle and at the end */
    flicker_with("uuuuuuauuuuuu", 0, arms, "uuuuuuauuuuuu");
    flicker_with("aauuuuu", 0, arms, "aauuuuu");
    flicker_with("uuuuuua", 0, arms, "uuuuuua");
    /* a short run next to it, in the same spell away from upright, takes it */
    flicker_with("uuuuaahuuuu", 0, arms, "uuuuaaauuuu");
    flicker_with("uuuucauuuu", 0, arms, "uuuuaauuuu"); /* one spell with the arms spread */
    /* under the one minimum the brief arms spread goes too */
    flicker("uuuuaahuuuu", 4, "uuuuuuuuuuu");
    int crouch[MM_POSTURE_COUNT];
    minima_but(2, MM_POSTURE_CROUCHED, 6, crouch);
    flicker_with("uuuuccccccuuuu", 0, crouch, "uuuuccccccuuuu");
    flicker_with("uuuuccccuuuu", 0, crouch, "uuuuuuuuuuuu");
    flicker_with("uuuubbbuuuu", 0, crouch, "uuuubbbuuuu");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_poses),     cmocka_unit_test(test_knee_raised),
        cmocka_unit_test(test_find_legs), cmocka_unit_test(test_reference_height),
        cmocka_unit_test(test_flicker),   cmocka_unit_test(test_flicker_each),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
