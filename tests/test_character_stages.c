/* The stages of the character's tick (src/runtime/character/), each on its own, without a
 * database: hand-made skeletons, frame tables, poses and distance curves, against values worked
 * out by hand or by a second method. */
#include <math.h>

#include "test_util.h"

#include <mm/distance_curve.h>
#include <mm/distance_curve_build.h>
#include <mm/spring.h>

#include "runtime/character/feet.h"
#include "runtime/character/intent.h"
#include "runtime/character/matching.h"
#include "runtime/character/playback.h"
#include "runtime/character/rig.h"
#include "runtime/character/root_motion.h"
#include "runtime/character/transition.h"
#include "runtime/character/warping.h"
#include "math_private.h"

/* ---- a small skeleton: root, hips, two legs with toes, a spine of two and a head ---- */

enum { ROOT, HIPS, L_UPLEG, L_LEG, L_FOOT, L_TOE, R_UPLEG, R_LEG, R_FOOT, R_TOE, SPINE, CHEST, HEAD, JOINTS };

typedef struct body {
    mm_joint joints[JOINTS];
    mm_quat rotations[JOINTS];
    mm_vec3 positions[JOINTS];
    mm_xform global[JOINTS];
    mm_rig_pose pose;
    mm_rig rig;
} body;

static void joint(body *b, int j, const char *name, int parent, float x, float y, float z)
{
    snprintf(b->joints[j].name, sizeof b->joints[j].name, "%s", name);
    b->joints[j].parent = parent;
    b->joints[j].offset = mm_vec3_make(x, y, z);
    b->rotations[j] = mm_quat_identity();
    b->positions[j] = b->joints[j].offset;
}

/* Standing at the origin facing +Z, hips at 0.9 m, legs straight down from hips 0.1 m apart (the
 * left one at +X), thighs and shins 0.42 m, ankles 0.06 m above the ground. */
static void make_body(body *b)
{
    memset(b, 0, sizeof *b);
    joint(b, ROOT, "Root", -1, 0, 0, 0);
    joint(b, HIPS, "Hips", ROOT, 0, 0.9f, 0);
    joint(b, L_UPLEG, "LeftUpLeg", HIPS, 0.1f, 0, 0);
    joint(b, L_LEG, "LeftLeg", L_UPLEG, 0, -0.42f, 0);
    joint(b, L_FOOT, "LeftFoot", L_LEG, 0, -0.42f, 0);
    joint(b, L_TOE, "LeftToe", L_FOOT, 0, -0.04f, 0.12f);
    joint(b, R_UPLEG, "RightUpLeg", HIPS, -0.1f, 0, 0);
    joint(b, R_LEG, "RightLeg", R_UPLEG, 0, -0.42f, 0);
    joint(b, R_FOOT, "RightFoot", R_LEG, 0, -0.42f, 0);
    joint(b, R_TOE, "RightToe", R_FOOT, 0, -0.04f, 0.12f);
    joint(b, SPINE, "Spine", HIPS, 0, 0.15f, 0);
    joint(b, CHEST, "Chest", SPINE, 0, 0.2f, 0);
    joint(b, HEAD, "Head", CHEST, 0, 0.3f, 0);
    b->pose.local_rotations = b->rotations;
    b->pose.local_positions = b->positions;
    b->pose.global = b->global;
    b->global[ROOT] = mm_xform_identity();
    mm_rig_init(&b->rig, b->joints, JOINTS, L_FOOT, R_FOOT);
    mm_rig_forward(&b->rig, 1, &b->pose);
}

static void assert_vec3_near(mm_vec3 a, mm_vec3 b, float tolerance)
{
    if (mm_vec3_distance(a, b) > tolerance) {
        print_error("(%g, %g, %g) is not within %g of (%g, %g, %g)\n", (double)a.x, (double)a.y, (double)a.z,
                    (double)tolerance, (double)b.x, (double)b.y, (double)b.z);
        fail();
    }
}

static mm_character_desc defaults(void)
{
    mm_character_desc d;
    mm_character_defaults(&d);
    return d;
}

/* ---- rig ---- */

static void test_rig_finds_legs_pelvis_and_spine(void **state)
{
    (void)state;
    body b;
    make_body(&b);
    assert_int_equal(b.rig.ankle[0], L_FOOT);
    assert_int_equal(b.rig.knee[0], L_LEG);
    assert_int_equal(b.rig.hip[0], L_UPLEG);
    assert_int_equal(b.rig.toe[0], L_TOE);
    assert_int_equal(b.rig.ankle[1], R_FOOT);
    assert_int_equal(b.rig.toe[1], R_TOE);
    assert_int_equal(b.rig.pelvis, HIPS);
    assert_int_equal(b.rig.spine_count, 3); /* Spine, Chest, Head: single children up to the end */
    assert_int_equal(b.rig.spine[0], SPINE);
    assert_int_equal(b.rig.spine[2], HEAD);
    /* world positions by hand: the left ankle 0.84 m below the hips, 0.1 m to the left */
    assert_vec3_near(b.global[L_FOOT].translation, mm_vec3_make(0.1f, 0.06f, 0.0f), 1e-6f);
    assert_vec3_near(b.global[R_TOE].translation, mm_vec3_make(-0.1f, 0.02f, 0.12f), 1e-6f);
    /* a missing ankle (-1, or out of range) leaves its leg out, and the pelvis */
    mm_rig other;
    mm_rig_init(&other, b.joints, JOINTS, L_FOOT, -1);
    assert_int_equal(other.ankle[0], L_FOOT);
    assert_int_equal(other.ankle[1], -1);
    assert_int_equal(other.pelvis, -1);
    /* an ankle that does not hang two joints below the root is no leg */
    mm_rig_init(&other, b.joints, JOINTS, L_FOOT, JOINTS);
    assert_int_equal(other.ankle[1], -1);
    mm_rig_init(&other, b.joints, JOINTS, HIPS, R_FOOT);
    assert_int_equal(other.ankle[0], -1);
}

/* ---- 1. intent ---- */

/* The rest of the body's forward kinematics deferred (mm_rig_forward_pelvis with defer_body, then
 * mm_rig_forward_finish): the pelvis and the legs current after each move, and at the end every
 * joint the bits of mm_rig_forward from joint 1 after each move; without the deferral, the whole
 * body at once. */
static void test_rig_deferred_body(void **state)
{
    (void)state;
    body eager, lazy, direct;
    make_body(&eager);
    make_body(&lazy);
    make_body(&direct);
    lazy.pose.defer_body = true;
    for (int step = 0; step < 3; ++step) {
        body *all[3] = {&eager, &lazy, &direct};
        for (int i = 0; i < 3; ++i) { /* the pelvis moved and turned, a hip and the chest turned */
            body *b = all[i];
            b->positions[HIPS] =
                mm_vec3_add(b->positions[HIPS], mm_vec3_make(0.01f * (float)step, -0.02f, 0.005f));
            b->rotations[HIPS] = mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), 0.1f * (float)(step + 1));
            b->rotations[L_UPLEG] = mm_quat_from_axis_angle(mm_vec3_make(1, 0, 0), -0.2f * (float)step);
            b->rotations[CHEST] = mm_quat_from_axis_angle(mm_vec3_make(0, 0, 1), 0.3f * (float)step);
        }
        mm_rig_forward(&eager.rig, 1, &eager.pose);
        mm_rig_forward_pelvis(&lazy.rig, &lazy.pose);
        mm_rig_forward_pelvis(&direct.rig, &direct.pose);
        assert_true(lazy.pose.body_stale);
        assert_false(direct.pose.body_stale);
        assert_memory_equal(direct.global, eager.global, sizeof eager.global);
        for (int j = HIPS; j <= R_TOE; ++j)
            assert_memory_equal(&lazy.global[j], &eager.global[j], sizeof(mm_xform));
    }
    /* the chest waits: where it stood before the moves */
    assert_true(mm_vec3_distance(lazy.global[CHEST].translation, eager.global[CHEST].translation) > 0.01f);
    mm_rig_forward_finish(&lazy.rig, &lazy.pose);
    assert_false(lazy.pose.defer_body);
    assert_false(lazy.pose.body_stale);
    assert_memory_equal(lazy.global, eager.global, sizeof eager.global);
}

static void test_intent_from_input(void **state)
{
    (void)state;
    mm_trajectory t;
    assert_int_equal(mm_trajectory_init(&t, NULL, NULL), MM_OK);
    mm_input in;
    memset(&in, 0, sizeof in);
    in.stick[1] = 1.0f;
    in.gait = MM_GAIT_RUN;
    mm_intent intent;
    mm_vec3 before = t.position;
    mm_intent_update(&t, &in, 0.1f, &intent);
    /* full stick forward at a run: the run's forward speed along +Z (4 m/s by default) */
    assert_vec3_near(intent.desired_velocity, mm_vec3_make(0, 0, t.desc.gaits[MM_GAIT_RUN].forward_speed),
                     1e-5f);
    assert_int_equal(intent.gait, MM_GAIT_RUN);
    assert_false(intent.strafe);
    /* travelled: the simulation's ground displacement over the tick */
    float dx = t.position.x - before.x, dz = t.position.z - before.z;
    assert_true(intent.travelled > 0.0f);
    assert_float_equal(intent.travelled, sqrtf(dx * dx + dz * dz), 1e-7f);
    assert_float_equal(mm_intent_ground_speed(&t),
                       sqrtf(t.velocity.x * t.velocity.x + t.velocity.z * t.velocity.z), 1e-7f);
    /* a gait out of range walks; no input asks for nothing */
    in.gait = (mm_gait)99;
    in.strafe = true;
    mm_intent_update(&t, &in, 0.1f, &intent);
    assert_int_equal(intent.gait, MM_GAIT_WALK);
    assert_true(intent.strafe);
    mm_intent_update(&t, NULL, 0.1f, &intent);
    assert_float_equal(mm_vec3_length(intent.desired_velocity), 0.0f, 1e-7f);
    assert_int_equal(intent.gait, MM_GAIT_WALK);
    mm_trajectory_free(&t);
}

/* ---- 2. playback ---- */

/* Two clips: frames 0-3 (a one-shot) and 4-6 (frame_next of 6 is -1 too: playback holds it). */
static const int32_t NEXT[7] = {1, 2, 3, -1, 5, 6, -1};

static void test_playback_advance_by_clock_and_rate(void **state)
{
    (void)state;
    mm_playback p;
    memset(&p, 0, sizeof p);
    mm_playback_by_clock(&p);
    assert_int_equal(p.mode, MM_PLAYBACK_CLOCK);
    assert_float_equal(p.play_rate, 1.0f, 0.0f);
    /* 1.5 frame intervals of 1/30 s: frame 1, half way (exactly: the fraction is a double) */
    assert_false(mm_playback_advance(&p, NEXT, 1.0f / 32.0f, 1.5f / 32.0f));
    assert_int_equal(p.frame, 1);
    assert_true(p.fraction == 0.5);
    /* twice the rate: twice as far */
    p.play_rate = 2.0f;
    assert_false(mm_playback_advance(&p, NEXT, 1.0f / 32.0f, 0.75f / 32.0f));
    assert_int_equal(p.frame, 3);
    assert_true(p.fraction == 0.0);
    /* past the clip's end: it ends, held on the last frame at fraction 0 */
    assert_true(mm_playback_advance(&p, NEXT, 1.0f / 32.0f, 1.0f / 32.0f));
    assert_int_equal(p.frame, 3);
    assert_true(p.fraction == 0.0);
}

static void test_playback_time_to_contact(void **state)
{
    (void)state;
    /* the left heel's label turns on at frame 2, the right toe's at frame 3 */
    const uint8_t contacts[7] = {0, 0, MM_CONTACT_LEFT_HEEL, MM_CONTACT_RIGHT_TOE, 0, 0, 0};
    mm_playback p;
    memset(&p, 0, sizeof p);
    p.frame = 0, p.fraction = 0.25, p.play_rate = 1.0f;
    float interval = 1.0f / 30.0f;
    /* frame 2 is 1.75 intervals ahead */
    assert_float_equal(mm_playback_time_to_contact(&p, NEXT, contacts, interval, 0, 1.0f), 1.75f * interval,
                       1e-6f);
    assert_float_equal(mm_playback_time_to_contact(&p, NEXT, contacts, interval, 1, 1.0f), 2.75f * interval,
                       1e-6f);
    /* at twice the rate, half the time; beyond the window: none */
    p.play_rate = 2.0f;
    assert_float_equal(mm_playback_time_to_contact(&p, NEXT, contacts, interval, 0, 1.0f), 0.875f * interval,
                       1e-6f);
    assert_float_equal(mm_playback_time_to_contact(&p, NEXT, contacts, interval, 0, 0.5f * interval), -1.0f,
                       0.0f);
    /* none in the clip (frame 4's clip has no contact) */
    p.frame = 4;
    assert_float_equal(mm_playback_time_to_contact(&p, NEXT, contacts, interval, 0, 1.0f), -1.0f, 0.0f);
}

/* A loop walking +Z at 1 m/s, 30 fps, 60 frames. */
static void walk_loop(mm_distance_curve *curve)
{
    float path[2 * 60];
    for (int f = 0; f < 60; ++f) path[2 * f] = 0.0f, path[2 * f + 1] = (float)f / 30.0f;
    mm_distance_desc d;
    memset(&d, 0, sizeof d);
    d.positions = path, d.components = 2, d.frame_count = 60, d.fps = 30.0f, d.loop = 1;
    assert_int_equal(mm_distance_curve_build(curve, &d, NULL), MM_OK);
}

static void test_playback_distance_matching_on_a_cycle(void **state)
{
    (void)state;
    mm_distance_curve curve;
    walk_loop(&curve);
    mm_trajectory t;
    assert_int_equal(mm_trajectory_init(&t, NULL, NULL), MM_OK);
    mm_intent intent;
    memset(&intent, 0, sizeof intent);
    mm_playback_params params = {true, true, 0.75f, 1.25f, 0.8f, 1.2f, 0.15f};
    mm_playback p;
    memset(&p, 0, sizeof p);
    mm_playback_by_clock(&p);
    /* the simulation at 1.1 m/s on a 1 m/s cycle: played 1.1 times as fast, no stride warp */
    t.velocity = mm_vec3_make(0, 0, 1.1f);
    mm_playback_match_distance(&p, &params, &curve, 0, &t, NULL, &intent, 1.0f / 60.0f);
    assert_int_equal(p.mode, MM_PLAYBACK_CYCLE);
    assert_float_equal(p.play_rate, 1.1f, 1e-4f);
    assert_float_equal(p.stride_scale, 1.0f, 1e-4f);
    /* at 1.8 m/s: the rate clamped at 1.25, the stride makes up for the rest, clamped at 1.2 */
    t.velocity = mm_vec3_make(1.8f, 0, 0);
    mm_playback_match_distance(&p, &params, &curve, 0, &t, NULL, &intent, 1.0f / 60.0f);
    assert_float_equal(p.play_rate, 1.25f, 1e-6f);
    assert_float_equal(p.stride_scale, 1.2f, 1e-6f);
    /* at 1.4 m/s: 1.4 / 1.25 */
    t.velocity = mm_vec3_make(0, 0, -1.4f);
    mm_playback_match_distance(&p, &params, &curve, 0, &t, NULL, &intent, 1.0f / 60.0f);
    assert_float_equal(p.stride_scale, 1.4f / 1.25f, 1e-5f);
    /* warping off: no stride scale; no curve: by the clock */
    params.warping = false;
    mm_playback_match_distance(&p, &params, &curve, 0, &t, NULL, &intent, 1.0f / 60.0f);
    assert_float_equal(p.stride_scale, 1.0f, 0.0f);
    mm_playback_match_distance(&p, &params, NULL, 0, &t, NULL, &intent, 1.0f / 60.0f);
    assert_int_equal(p.mode, MM_PLAYBACK_CLOCK);
    assert_float_equal(p.play_rate, 1.0f, 0.0f);
    mm_trajectory_free(&t);
    mm_distance_curve_free(&curve);
}

/* A jump from a 1 m/s cycle to a 2 m/s one (another clip) while the simulation goes 1.1 m/s: the
 * new clip's rate, 0.55 clamped to 0.75, is reached from the 1.1 played before, not in one tick
 * (the root's velocity and every joint's in the clip would step by the rate's change): on the
 * tick of the change the rate is still 1.1, then 0.75 + 0.35 2^(-t / 0.1 s). Within one clip the
 * rate follows its target at once. */
static void test_playback_rate_after_a_change_of_clip(void **state)
{
    (void)state;
    mm_distance_curve walk, run;
    walk_loop(&walk);
    float path[2 * 60];
    for (int f = 0; f < 60; ++f) path[2 * f] = 0.0f, path[2 * f + 1] = (float)f / 15.0f;
    mm_distance_desc d;
    memset(&d, 0, sizeof d);
    d.positions = path, d.components = 2, d.frame_count = 60, d.fps = 30.0f, d.loop = 1;
    assert_int_equal(mm_distance_curve_build(&run, &d, NULL), MM_OK);
    mm_trajectory t;
    assert_int_equal(mm_trajectory_init(&t, NULL, NULL), MM_OK);
    mm_intent intent;
    memset(&intent, 0, sizeof intent);
    mm_playback_params params = {true, true, 0.75f, 1.25f, 0.8f, 1.2f, 0.15f};
    mm_playback p;
    memset(&p, 0, sizeof p);
    mm_playback_by_clock(&p);
    const float dt = 1.0f / 60.0f;
    t.velocity = mm_vec3_make(0, 0, 1.1f);
    for (int k = 0; k < 3; ++k) mm_playback_match_distance(&p, &params, &walk, 0, &t, NULL, &intent, dt);
    assert_float_equal(p.play_rate, 1.1f, 1e-4f);
    /* the jump: the run clip starts at database frame 100 */
    mm_playback_match_distance(&p, &params, &run, 100, &t, NULL, &intent, dt);
    assert_float_equal(p.play_rate, 1.1f, 1e-4f);
    for (int k = 1; k <= 60; ++k) {
        mm_playback_match_distance(&p, &params, &run, 100, &t, NULL, &intent, dt);
        if (k == 6) assert_float_equal(p.play_rate, 0.75f + 0.35f * 0.5f, 1e-3f);
    }
    assert_float_equal(p.play_rate, 0.75f, 1e-3f);
    /* back to the walk at 1.0 m/s: from 0.75 toward 1.0; by the clock: 1 at once */
    t.velocity = mm_vec3_make(0, 0, 1.0f);
    mm_playback_match_distance(&p, &params, &walk, 0, &t, NULL, &intent, dt);
    assert_float_equal(p.play_rate, 0.75f, 1e-3f);
    mm_playback_match_distance(&p, &params, NULL, 0, &t, NULL, &intent, dt);
    assert_float_equal(p.play_rate, 1.0f, 0.0f);
    mm_trajectory_free(&t);
    mm_distance_curve_free(&walk);
    mm_distance_curve_free(&run);
}

/* ---- 3. search: when ---- */

static void test_matching_due(void **state)
{
    (void)state;
    mm_character_desc d = defaults();
    mm_matching m;
    memset(&m, 0, sizeof m);
    m.idle = true;
    mm_intent intent;
    memset(&intent, 0, sizeof intent);
    float dt = 1.0f / 60.0f;
    /* standing, idle: due once search_interval has passed (0.1 s: on the 6th tick of 1/60 s) */
    int ticks = 0;
    while (!mm_matching_due(&m, &d, &intent, 0.0f, 0.0f, false, false, dt)) ++ticks;
    assert_int_equal(ticks, 5);
    m.since_search = 0.0f;
    /* the stick pushed: idle ends at once (speed over idle_speed + hysteresis), and that searches */
    intent.desired_velocity = mm_vec3_make(0, 0, 1.5f);
    assert_true(mm_matching_due(&m, &d, &intent, 0.0f, 0.0f, false, false, dt));
    assert_false(m.idle);
    m.since_search = 0.0f, m.last_direction = 0.0f;
    /* a sharp turn of the desired direction (over turn_threshold) searches at once; a slight one does not */
    intent.desired_velocity = mm_vec3_make(1.5f * sinf(0.3f), 0, 1.5f * cosf(0.3f));
    assert_false(mm_matching_due(&m, &d, &intent, 1.5f, 1.5f, false, false, dt));
    intent.desired_velocity = mm_vec3_make(1.5f * sinf(0.7f), 0, 1.5f * cosf(0.7f));
    assert_true(mm_matching_due(&m, &d, &intent, 1.5f, 1.5f, false, false, dt));
    m.since_search = 0.0f;
    /* a clip that ended searches; but never while a move plays */
    assert_true(mm_matching_due(&m, &d, &intent, 1.5f, 1.5f, true, false, dt));
    assert_false(mm_matching_due(&m, &d, &intent, 1.5f, 1.5f, true, true, dt));
    /* let go: idle only once the simulation has slowed too, and not while the root motion played is
     * faster than idle_root_speed unless the simulation has stopped */
    intent.desired_velocity = mm_vec3_make(0, 0, 0);
    mm_matching_due(&m, &d, &intent, 1.0f, 0.0f, false, false, dt);
    assert_false(m.idle);
    mm_matching_due(&m, &d, &intent, 0.1f, 2.0f, false, false, dt);
    assert_false(m.idle);
    mm_matching_due(&m, &d, &intent, 0.005f, 2.0f, false, false, dt);
    assert_true(m.idle);
}

/* The ratio the search weighs with: at a run of 3 m/s with the stick let go the velocity must change
 * by more than velocity_change_speed, so the ratio is velocity_change_ratio; right after a jump
 * the pose is weighed back up to the desc's ratio, and one transition_halflife later (the spring's
 * offset halved, by the halflife's definition) the ratio is half-way back up. */
static void test_matching_pose_weighed_back_after_a_jump(void **state)
{
    (void)state;
    mm_character_desc d = defaults();
    mm_matching m;
    memset(&m, 0, sizeof m);
    m.since_jump = INFINITY;
    mm_trajectory t;
    memset(&t, 0, sizeof t);
    t.velocity = mm_vec3_make(0, 0, 3.0f);
    mm_intent intent;
    memset(&intent, 0, sizeof intent);
    float base = d.params.pose_trajectory_ratio, raised = d.velocity_change_ratio;
    assert_true(raised > base + 0.1f);
    assert_true(3.0f > d.velocity_change_speed);
    /* no jump yet: the velocity change's ratio */
    assert_float_equal(mm_matching_ratio(&m, &d, &t, &intent), raised, 1e-6f);
    /* at the jump: the desc's */
    m.since_jump = 0.0f;
    assert_float_equal(mm_matching_ratio(&m, &d, &t, &intent), base, 1e-6f);
    /* one halflife on, counted by the ticks of mm_matching_due: half-way */
    float dt = d.transition_halflife / 12.0f;
    for (int k = 0; k < 12; ++k) mm_matching_due(&m, &d, &intent, 3.0f, 3.0f, false, false, dt);
    assert_float_equal(m.since_jump, d.transition_halflife, 1e-5f);
    assert_float_equal(mm_matching_ratio(&m, &d, &t, &intent), 0.5f * (base + raised), 1e-4f);
    /* long after: the velocity change's again; and with the velocity reached, the desc's */
    m.since_jump = 20.0f * d.transition_halflife;
    assert_float_equal(mm_matching_ratio(&m, &d, &t, &intent), raised, 1e-4f);
    intent.desired_velocity = t.velocity;
    m.since_jump = 0.0f;
    assert_float_equal(mm_matching_ratio(&m, &d, &t, &intent), base, 1e-6f);
}

/* ---- 4. transition ---- */

/* One joint (joint 1) turning about +Y at rate w (rad/s) from angle a0: its rotation at time t. */
static mm_quat turning(float a0, float w, float t)
{
    return mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), a0 + w * t);
}

static void test_transition_inertialize_keeps_pose_and_velocity(void **state)
{
    (void)state;
    enum { N = 2 };
    mm_quat rot[N], prev[N], r0[N], r1[N];
    mm_vec3 pos[N], prev_pos[N], p0[N], p1[N];
    mm_vec3 ro[N], rov[N], po[N], pov[N];
    mm_transition tr;
    memset(&tr, 0, sizeof tr);
    tr.rotations = rot, tr.previous_rotations = prev, tr.positions = pos, tr.previous_positions = prev_pos;
    tr.rotation_offset = ro, tr.rotation_offset_velocity = rov, tr.position_offset = po,
    tr.position_offset_velocity = pov;
    float dt = 1.0f / 60.0f, interval = 1.0f / 30.0f, w = 2.0f;
    /* the animated pose: joint 1 at 0.5 rad turning at 2 rad/s, moving +X at 1 m/s */
    prev[1] = turning(0.5f, w, -dt), rot[1] = turning(0.5f, w, 0.0f);
    prev_pos[1] = mm_vec3_make(-dt, 0, 0), pos[1] = mm_vec3_make(0, 0, 0);
    /* the new clip: the same motion from 0.3 rad, at rest in position */
    r0[1] = turning(0.3f, w, 0.0f), r1[1] = turning(0.3f, w, interval);
    p0[1] = p1[1] = mm_vec3_make(0.2f, 0, 0);
    mm_frame_pair to = {r0, r1, p0, p1};
    mm_transition_inertialize(&tr, N, &to, 0.0f, 1.0f / interval, dt);
    /* the jump happens before this tick's pose: the animated pose is last tick's (0.5 rad), and the
     * new clip, at 0.3 rad on this tick, stood at 0.3 - w dt then: the offset is the difference */
    float offset = 0.5f - (0.3f - w * dt);
    assert_vec3_near(ro[1], mm_vec3_make(0, offset, 0), 1e-5f);
    assert_vec3_near(rov[1], mm_vec3_make(0, 0, 0), 1e-4f); /* the same turning rate */
    assert_vec3_near(po[1], mm_vec3_make(-0.2f, 0, 0), 1e-6f);
    assert_vec3_near(pov[1], mm_vec3_make(1.0f, 0, 0), 1e-4f); /* the output moved, the clip does not */
    /* the offsets then decay like a critically damped spring: after one half-life from rest,
     * half is left (mm/spring.h); the rotation offset had no velocity */
    float h = 0.2f;
    for (int k = 0; k < 12; ++k) { /* 0.2 s in 12 ticks, the pose held where the new clip is */
        rot[1] = r0[1], pos[1] = p0[1];
        mm_transition_decay(&tr, N, h, h, h / 12.0f);
    }
    assert_float_equal(ro[1].y, 0.5f * offset, 1e-5f);
    /* and the pose carries it: the rotation played turned by the offset */
    float angle = 2.0f * atan2f(rot[1].y, rot[1].w);
    assert_float_equal(angle, 0.3f + 0.5f * offset, 1e-5f);
    /* the root motion: what played continues, blending into the new frame's */
    mm_root_played current = {mm_vec3_make(0, 0, 1.5f), 0.4f}, next = {mm_vec3_make(0, 0, 1.0f), 0.0f};
    mm_transition_inertialize_root(&tr, current, next);
    mm_root_played out = mm_transition_decay_root(&tr, next, h, 0.0f);
    assert_vec3_near(out.velocity, current.velocity, 1e-6f);
    assert_float_equal(out.yaw_rate, current.yaw_rate, 1e-6f);
    out = mm_transition_decay_root(&tr, next, h, h);
    assert_float_equal(out.velocity.z, 1.25f, 1e-5f);
    assert_float_equal(out.yaw_rate, 0.2f, 1e-5f);
}

/* A joint swinging about +Y at w under a fixed tilt of 0.8 rad about +X (the old clip: the tilt
 * from the parent's side), jumping to a clip swinging about +Y untilted: the offset (about +X, or
 * near it) does not commute with the new swing. Over the first tick after the jump the output goes
 * on as the old clip would have, to second order in dt: a rate of offset w_out - w_new would turn
 * it by |R(offset) w - w| dt (0.08 rad here) off that. Truth: the old motion continued. */
static mm_quat tilted_swing(float tilt, float a0, float w, float t)
{
    return mm_quat_mul(mm_quat_from_axis_angle(mm_vec3_make(1, 0, 0), tilt), turning(a0, w, t));
}

/* The legs' joints (each hip and what hangs from it) are marked, and their offsets fade with the
 * legs' half-life while the body's fade with its own: a critically damped spring from rest keeps
 * half its offset after one half-life (mm/spring.h), each at its own. */
static void test_transition_legs_fade_with_their_halflife(void **state)
{
    (void)state;
    enum { N = 6 };
    /* 0 root, 1 spine, 2 left hip, 3 left knee (under 2), 4 right hip, 5 right knee (under 4) */
    mm_joint skeleton[N];
    memset(skeleton, 0, sizeof skeleton);
    const int parents[N] = {-1, 0, 0, 2, 0, 4};
    for (int j = 0; j < N; ++j) skeleton[j].parent = parents[j];
    mm_quat rot[N];
    mm_vec3 pos[N], ro[N], rov[N], po[N], pov[N];
    unsigned char legs[N];
    mm_transition tr;
    memset(&tr, 0, sizeof tr);
    tr.rotations = rot, tr.positions = pos, tr.rotation_offset = ro, tr.rotation_offset_velocity = rov,
    tr.position_offset = po, tr.position_offset_velocity = pov, tr.legs = legs;
    const int hips[2] = {2, 4};
    mm_transition_mark_legs(&tr, skeleton, N, hips);
    const unsigned char want[N] = {0, 0, 1, 1, 1, 1};
    for (int j = 0; j < N; ++j) assert_int_equal(legs[j], want[j]);
    const int one_hip[2] = {-1, 4}; /* a missing leg: the other alone */
    mm_transition_mark_legs(&tr, skeleton, N, one_hip);
    const unsigned char want_one[N] = {0, 0, 0, 0, 1, 1};
    for (int j = 0; j < N; ++j) assert_int_equal(legs[j], want_one[j]);
    mm_transition_mark_legs(&tr, skeleton, N, hips);
    for (int j = 0; j < N; ++j) {
        ro[j] = mm_vec3_make(0, 0.4f, 0), po[j] = mm_vec3_make(0.1f, 0, 0);
        rov[j] = pov[j] = mm_vec3_make(0, 0, 0);
    }
    float torso = 0.2f, leg = 0.1f, dt = leg / 24.0f, leg_at_half = 0.0f;
    for (int k = 1; k <= 48; ++k) { /* 0.2 s: two half-lives of the legs', one of the body's */
        for (int j = 0; j < N; ++j) rot[j] = mm_quat_identity(), pos[j] = mm_vec3_make(0, 0, 0);
        mm_transition_decay(&tr, N, torso, leg, dt);
        if (k == 12) leg_at_half = ro[3].y; /* half the legs' half-life */
        if (k == 24) { /* the legs' half-life: half left on every leg joint; the pose carries it */
            for (int j = 1; j < N; ++j)
                if (legs[j]) {
                    assert_float_equal(ro[j].y, 0.2f, 1e-5f);
                    assert_float_equal(po[j].x, 0.05f, 1e-6f);
                    assert_float_equal(pos[j].x, 0.05f, 1e-6f);
                }
            /* the body's at half its own half-life: where the legs' were at half theirs */
            assert_float_equal(ro[1].y, leg_at_half, 1e-5f);
            assert_true(ro[1].y > 0.3f);
        }
    }
    assert_float_equal(ro[1].y, 0.2f, 1e-5f); /* the body's half-life */
    assert_float_equal(po[1].x, 0.05f, 1e-6f);
    assert_true(ro[3].y < 0.1f); /* the legs' further on */
}

/* The contact favour keeps a foot planted only until the character has travelled stance_reach
 * from where it stood when the foot's label (as played, across jumps) turned on: the pattern
 * then has that foot lifted; the other foot's bits stay; a new stance starts from where it begins. */
static void test_matching_stance_ends_after_its_reach(void **state)
{
    (void)state;
    mm_matching m;
    memset(&m, 0, sizeof m);
    m.stance_reach = 0.95f;
    const unsigned left = MM_CONTACT_LEFT_HEEL | MM_CONTACT_LEFT_TOE, right = MM_CONTACT_RIGHT_HEEL;
    mm_xform at = mm_xform_identity();
    mm_matching_track_stances(&m, left, at.translation); /* the left foot planted at the origin */
    for (int k = 1; k <= 10; ++k) { /* walking along +X over it, the label held (0.1 m a tick) */
        at.translation = mm_vec3_make(0.1f * (float)k, 0.0f, 0.0f);
        unsigned label = k >= 5 ? left | right : left; /* the right foot comes down at 0.5 m */
        mm_matching_track_stances(&m, label, at.translation);
        int pattern = mm_matching_contact_pattern(&m, label, at);
        if (k <= 9) /* within reach (0.9 m of 0.95) */
            assert_int_equal(pattern, (int)label);
        else /* past it: the left foot counts as lifted, the right (planted 0.5 m back) kept */
            assert_int_equal(pattern, (int)right);
    }
    /* both labels go off and on again: new stances, from here */
    mm_matching_track_stances(&m, 0u, at.translation);
    mm_matching_track_stances(&m, left | right, at.translation);
    at.translation.x += 0.5f;
    assert_int_equal(mm_matching_contact_pattern(&m, left | right, at), (int)(left | right));
    /* a label without a tracked stance (a tick not yet tracked) is kept as it is */
    assert_int_equal(mm_matching_contact_pattern(&m, MM_CONTACT_RIGHT_TOE, at), MM_CONTACT_RIGHT_TOE);
    /* no reach (0): never */
    m.stance_reach = 0.0f;
    at.translation.x += 10.0f;
    assert_int_equal(mm_matching_contact_pattern(&m, left | right, at), (int)(left | right));
}

static void test_transition_inertialize_keeps_velocity_across_axes(void **state)
{
    (void)state;
    enum { N = 2 };
    mm_quat rot[N], prev[N], r0[N], r1[N];
    mm_vec3 pos[N], prev_pos[N], p0[N], p1[N];
    mm_vec3 ro[N], rov[N], po[N], pov[N];
    mm_transition tr;
    memset(&tr, 0, sizeof tr);
    tr.rotations = rot, tr.previous_rotations = prev, tr.positions = pos, tr.previous_positions = prev_pos;
    tr.rotation_offset = ro, tr.rotation_offset_velocity = rov, tr.position_offset = po,
    tr.position_offset_velocity = pov;
    /* a long half-life: the spring's own pull over one tick (y^2 x dt^2) is negligible here */
    float dt = 1.0f / 60.0f, interval = 1.0f / 60.0f, w = 6.0f, tilt = 0.8f, h = 10.0f;
    prev[1] = tilted_swing(tilt, 0.2f, w, -dt), rot[1] = tilted_swing(tilt, 0.2f, w, 0.0f);
    prev_pos[1] = pos[1] = p0[1] = p1[1] = mm_vec3_make(0, 0, 0);
    /* the new clip at this tick (the jump lands on its frame): untilted, 0.5 rad further round */
    r0[1] = turning(0.7f, w, dt), r1[1] = turning(0.7f, w, dt + interval);
    mm_frame_pair to = {r0, r1, p0, p1};
    mm_transition_inertialize(&tr, N, &to, 0.0f, 1.0f / interval, dt);
    rot[1] = r0[1]; /* this tick's pose as played, then the offsets on it */
    mm_transition_decay(&tr, N, h, h, dt);
    float off = mm_quat_angle_between(rot[1], tilted_swing(tilt, 0.2f, w, dt));
    assert_true(off < 2e-3f);
    /* and one more tick: still on the old motion to second order */
    rot[1] = r1[1];
    mm_transition_decay(&tr, N, h, h, dt);
    assert_true(mm_quat_angle_between(rot[1], tilted_swing(tilt, 0.2f, w, 2.0f * dt)) < 4e-3f);
}

/* ---- 5. root motion ---- */

static void test_root_motion_pull_and_clamps(void **state)
{
    (void)state;
    mm_character_desc d = defaults();
    mm_trajectory t;
    assert_int_equal(mm_trajectory_init(&t, NULL, NULL), MM_OK);
    mm_intent intent;
    memset(&intent, 0, sizeof intent);
    intent.desired_facing = mm_quat_identity();
    mm_root_motion r;
    memset(&r, 0, sizeof r);
    r.root = mm_xform_identity();
    float dt = 0.1f;
    /* played 1 m/s forward, the simulation at the same place: the root goes where it is played */
    t.position = mm_vec3_make(0, 0, 0.1f);
    mm_root_played played = {mm_vec3_make(0, 0, 1.0f), 0.0f};
    mm_root_motion_update(&r, &d, &t, &intent, played, false, dt);
    assert_vec3_near(r.root.translation, mm_vec3_make(0, 0, 0.1f), 1e-6f);
    /* the simulation 0.2 m to the side: pulled 1 - 2^(-dt / sync_halflife) of the way */
    r.root = mm_xform_identity();
    t.position = mm_vec3_make(0.2f, 0, 0.1f);
    mm_root_motion_update(&r, &d, &t, &intent, played, false, dt);
    float pull = 1.0f - exp2f(-dt / d.sync_halflife);
    assert_vec3_near(r.root.translation, mm_vec3_make(0.2f * pull, 0, 0.1f), 1e-6f);
    /* far off: clamped to sync_max_distance from it */
    r.root = mm_xform_identity();
    t.position = mm_vec3_make(5.0f, 0, 0.1f);
    mm_root_motion_update(&r, &d, &t, &intent, played, false, dt);
    float gap = mm_vec3_distance(r.root.translation, t.position);
    assert_float_equal(gap, d.sync_max_distance, 1e-5f);
    /* facing: turned past sync_max_angle from the simulation's, it is held at the clamp */
    r.root = mm_xform_identity();
    t.position = mm_vec3_make(0, 0, 0.1f);
    t.facing = mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), 1.5f);
    mm_root_motion_update(&r, &d, &t, &intent, played, false, dt);
    assert_float_equal(yaw_of(r.root.rotation), 1.5f - d.sync_max_angle, 1e-5f);
    /* a move: its root motion alone, no pull, no clamp; the height kept */
    r.root = mm_xform_make(mm_quat_identity(), mm_vec3_make(0, 0.7f, 0));
    t.position = mm_vec3_make(5.0f, 0, 0);
    mm_root_motion_update(&r, &d, &t, &intent, played, true, dt);
    assert_vec3_near(r.root.translation, mm_vec3_make(0, 0.7f, 0.1f), 1e-6f);
    assert_float_equal(yaw_of(r.root.rotation), 0.0f, 1e-6f);
    mm_trajectory_free(&t);
}

/* ---- 6. warping ---- */

static void test_warping_stride_stretches_the_step(void **state)
{
    (void)state;
    body b;
    make_body(&b);
    /* a step: the left foot 0.3 m ahead, the right 0.3 m behind (thighs swung about X) */
    float swing = asinf(0.3f / 0.84f);
    b.rotations[L_UPLEG] = mm_quat_from_axis_angle(mm_vec3_make(1, 0, 0), -swing);
    b.rotations[R_UPLEG] = mm_quat_from_axis_angle(mm_vec3_make(1, 0, 0), swing);
    mm_rig_forward(&b.rig, 1, &b.pose);
    mm_vec3 left = b.global[L_FOOT].translation;
    assert_float_equal(left.z, 0.3f, 1e-5f);
    mm_warping w;
    memset(&w, 0, sizeof w);
    /* scale 0.8 along +Z: each foot's distance ahead of its hip shrinks to 0.8 of it; over many
     * ticks the pelvis drop eases to what it needs (none: a shorter step reaches) */
    for (int k = 0; k < 60; ++k) {
        make_body(&b);
        b.rotations[L_UPLEG] = mm_quat_from_axis_angle(mm_vec3_make(1, 0, 0), -swing);
        b.rotations[R_UPLEG] = mm_quat_from_axis_angle(mm_vec3_make(1, 0, 0), swing);
        mm_rig_forward(&b.rig, 1, &b.pose);
        mm_warping_stride(&w, &b.rig, mm_xform_identity(), mm_vec3_make(0, 0, 1.0f), 0.8f, 1.0f / 60.0f,
                          &b.pose);
    }
    assert_float_equal(w.stride_drop, 0.0f, 1e-6f);
    assert_float_equal(b.global[L_FOOT].translation.z, 0.24f, 1e-3f);
    assert_float_equal(b.global[R_FOOT].translation.z, -0.24f, 1e-3f);
    /* the bones keep their lengths */
    assert_float_equal(mm_vec3_distance(b.global[L_UPLEG].translation, b.global[L_LEG].translation), 0.42f,
                       1e-5f);
    assert_float_equal(mm_vec3_distance(b.global[L_LEG].translation, b.global[L_FOOT].translation), 0.42f,
                       1e-5f);
    /* a scale of 1 at rest leaves the pose as it is, bit for bit */
    make_body(&b);
    mm_warping rest;
    memset(&rest, 0, sizeof rest);
    mm_xform before = b.global[L_FOOT];
    mm_warping_stride(&rest, &b.rig, mm_xform_identity(), mm_vec3_make(0, 0, 1.0f), 1.0f, 1.0f / 60.0f,
                      &b.pose);
    assert_memory_equal(&before, &b.global[L_FOOT], sizeof before);
}

static void test_warping_orientation_turns_legs_not_chest(void **state)
{
    (void)state;
    mm_character_desc d = defaults();
    body b;
    mm_warping w;
    memset(&w, 0, sizeof w);
    /* strafing right (-X) on a clip that walks forward: over a second the lower body turns toward
     * the movement, -90 degrees about +Y at most (orientation_max), the chest keeps facing +Z */
    mm_warping_clip clip = {mm_vec3_make(0, 0, 1.2f), false};
    for (int k = 0; k < 120; ++k) {
        make_body(&b);
        mm_warping_orientation(&w, &d, &b.rig, mm_xform_identity(), mm_vec3_make(-1.0f, 0, 0), clip, true,
                               false, 1.0f / 60.0f, &b.pose);
    }
    assert_float_equal(w.orientation_angle, -(float)MM_PI / 2.0f, 0.02f);
    mm_vec3 hips_forward = mm_quat_rotate(b.global[HIPS].rotation, mm_vec3_make(0, 0, 1));
    assert_vec3_near(hips_forward, mm_vec3_make(-1, 0, 0), 0.03f);
    mm_vec3 head_forward = mm_quat_rotate(b.global[HEAD].rotation, mm_vec3_make(0, 0, 1));
    assert_vec3_near(head_forward, mm_vec3_make(0, 0, 1), 1e-4f);
    /* not strafing: it springs back to 0, and then the pose is left as it is */
    for (int k = 0; k < 240; ++k) {
        make_body(&b);
        mm_warping_orientation(&w, &d, &b.rig, mm_xform_identity(), mm_vec3_make(-1.0f, 0, 0), clip, false,
                               false, 1.0f / 60.0f, &b.pose);
    }
    assert_float_equal(w.orientation_angle, 0.0f, 0.0f);
    assert_vec3_near(mm_quat_rotate(b.global[HIPS].rotation, mm_vec3_make(0, 0, 1)), mm_vec3_make(0, 0, 1),
                     0.0f);
}

/* A clip that starts going forward while strafing: the warp's target steps from 0 to 90 degrees
 * in one tick. The angle eases in: its largest second difference per tick is a small share of
 * what a critically damped spring from rest toward the whole step moves on its first tick,
 * step (1 - (1 + y dt) e^(-y dt)) (mm_spring_damping; the spring alone moves exactly that, all of
 * its acceleration at once: 0.098 rad here, eased 0.029); and it still gets there. */
static void test_warping_orientation_eases_in_a_step(void **state)
{
    (void)state;
    mm_character_desc d = defaults();
    body b;
    mm_warping w;
    memset(&w, 0, sizeof w);
    const float dt = 1.0f / 60.0f, step = (float)MM_PI / 2.0f;
    double y = mm_spring_damping(0.6931472f / d.orientation_speed);
    double spring_first = step * (1.0 - (1.0 + y * dt) * exp(-y * dt));
    mm_warping_clip standing = {mm_vec3_make(0, 0, 0.0f), false}, forward = {mm_vec3_make(0, 0, 1.2f), false};
    float a[122] = {0};
    for (int k = 0; k < 122; ++k) {
        make_body(&b);
        /* two ticks on a clip going nowhere (no warp), then one going forward */
        mm_warping_orientation(&w, &d, &b.rig, mm_xform_identity(), mm_vec3_make(-1.0f, 0, 0),
                               k < 2 ? standing : forward, true, false, dt, &b.pose);
        a[k] = w.orientation_angle;
    }
    assert_float_equal(a[0], 0.0f, 0.0f);
    assert_float_equal(a[1], 0.0f, 0.0f);
    double largest = 0.0;
    for (int k = 2; k < 122; ++k) largest = fmax(largest, fabs(a[k] - 2.0f * a[k - 1] + a[k - 2]));
    assert_true(largest > 0.0);
    assert_true(largest <= 0.5 * spring_first);
    assert_float_equal(a[121], -step, 0.02f);
}

/* ---- 7. feet ---- */

/* The contact labels the feet tests give, none foreseen. */
static const mm_feet_contacts LABEL_NONE = {0, {-1.0f, -1.0f}, {-1.0f, -1.0f}},
                              LABEL_LEFT_HEEL = {MM_CONTACT_LEFT_HEEL, {-1.0f, -1.0f}, {-1.0f, -1.0f}},
                              LABEL_LEFT_TOE = {MM_CONTACT_LEFT_TOE, {-1.0f, -1.0f}, {-1.0f, -1.0f}},
                              LABEL_LEFT_HEEL_TOE = {
                                  MM_CONTACT_LEFT_HEEL | MM_CONTACT_LEFT_TOE, {-1.0f, -1.0f}, {-1.0f, -1.0f}};

/* A feet test's settings and feet: the character's defaults with the landing eased over
 * plant_time (0: planted at once; the easing is test_feet_land's, test_character.c) and, with
 * hips_held, the hips never lowered (max_hip_drop 0: the legs' reach is the test's alone); no foot
 * planted yet. */
static mm_character_desc feet_fixture(mm_feet *f, float plant_time, bool hips_held)
{
    mm_character_desc d = defaults();
    d.plant_time = plant_time;
    if (hips_held) d.max_hip_drop = 0.0f;
    memset(f, 0, sizeof *f);
    return d;
}

/* One tick of the feet of b under labels on level ground at 0, held (not a move). */
static void level_tick(mm_feet *f, const mm_character_desc *d, body *b, const mm_feet_contacts *labels,
                       float dt)
{
    mm_feet_update(f, d, &b->rig, labels, &(mm_feet_ground){0.0f, true, NULL}, dt, &b->pose);
}

static void test_feet_lock_holds_and_releases(void **state)
{
    (void)state;
    mm_feet f;
    mm_character_desc d = feet_fixture(&f, 0.0f, false);
    body b;
    float dt = 1.0f / 60.0f;
    /* planted where the ankle is */
    make_body(&b);
    mm_feet_record(&f, &b.rig, &b.pose);
    assert_vec3_near(f.raw_contacts[0], mm_vec3_make(0.1f, 0.06f, 0), 1e-6f);
    assert_vec3_near(f.raw_contacts[3], mm_vec3_make(-0.1f, 0.02f, 0.12f), 1e-6f);
    level_tick(&f, &d, &b, &LABEL_LEFT_HEEL, dt);
    assert_true(f.locked[0] && f.heel_locked[0]);
    assert_false(f.locked[1]);
    mm_vec3 planted = f.heel_lock[0];
    assert_vec3_near(planted, mm_vec3_make(0.1f, 0.06f, 0), 1e-5f);
    /* the body slides 5 cm forward: the locked ankle stays (IK), the free one goes along */
    for (int k = 0; k < 10; ++k) {
        make_body(&b);
        b.positions[HIPS].z = 0.05f;
        mm_rig_forward(&b.rig, 1, &b.pose);
        level_tick(&f, &d, &b, &LABEL_LEFT_HEEL, dt);
    }
    assert_vec3_near(b.global[L_FOOT].translation, planted, 1e-3f);
    assert_vec3_near(b.global[R_FOOT].translation, mm_vec3_make(-0.1f, 0.06f, 0.05f), 1e-3f);
    /* the label off: released where it is held (the ankle keeps its place and velocity on that
     * tick), then the difference fades with foot_halflife (half of it one half-life later) */
    int ticks = (int)lroundf(d.foot_halflife / dt);
    make_body(&b);
    b.positions[HIPS].z = 0.05f;
    mm_rig_forward(&b.rig, 1, &b.pose);
    level_tick(&f, &d, &b, &LABEL_NONE, dt);
    assert_false(f.locked[0]);
    assert_vec3_near(b.global[L_FOOT].translation, planted, 1e-3f);
    for (int k = 0; k < ticks; ++k) {
        make_body(&b);
        b.positions[HIPS].z = 0.05f;
        mm_rig_forward(&b.rig, 1, &b.pose);
        level_tick(&f, &d, &b, &LABEL_NONE, dt);
    }
    assert_false(f.locked[0]);
    assert_float_equal(b.global[L_FOOT].translation.z, 0.05f - 0.025f, 2e-3f);
    /* pulled further than unlock_radius: released, and planted again one spring step (foot_halflife,
     * from rest) from where it was toward the animation: the foot creeps after it */
    memset(&f, 0, sizeof f);
    make_body(&b);
    level_tick(&f, &d, &b, &LABEL_LEFT_HEEL, dt);
    make_body(&b);
    b.positions[ROOT].z = b.positions[HIPS].z = 0.0f;
    b.global[ROOT].translation.z = d.unlock_radius + 0.1f;
    mm_rig_forward(&b.rig, 1, &b.pose);
    level_tick(&f, &d, &b, &LABEL_LEFT_HEEL, dt);
    assert_true(f.heel_locked[0]);
    float pulled = d.unlock_radius + 0.1f, y = (float)mm_spring_damping(d.foot_halflife);
    assert_float_equal(f.heel_lock[0].z, pulled * (1.0f - (1.0f + y * dt) * expf(-y * dt)), 1e-4f);
    /* never below the ground held (the root's height): the ankle at least at its planted height
     * above it (0 on this rig, which learned none), and high enough that its toe, 4 cm below it in
     * this pose, is at most 1 cm (feet.c's TOE_SINK) below its own planted height (0) */
    memset(&f, 0, sizeof f);
    make_body(&b);
    mm_feet_update(&f, &d, &b.rig, &LABEL_LEFT_HEEL, &(mm_feet_ground){0.1f, true, NULL}, dt, &b.pose);
    assert_float_equal(f.lock[0].y, 0.1f + 0.04f - 0.01f, 1e-6f);
    memset(&f, 0, sizeof f);
    make_body(&b);
    mm_feet_update(&f, &d, &b.rig, &LABEL_LEFT_HEEL, &(mm_feet_ground){0.1f, false, NULL}, dt,
                   &b.pose); /* a move: no ground held */
    assert_float_equal(f.lock[0].y, 0.06f, 1e-6f);
}

/* The body with its left knee bent by 2 bend (the thigh forward, the shin back, the foot level) and
 * the hips lowered so that the ankle stays 0.06 m above the ground, with pitch added to the foot;
 * the hips then raised by lift. Within the leg's reach, unlike the straight legs of make_body. */
static void bent_left_leg(body *b, float bend, float pitch, float lift)
{
    make_body(b);
    mm_vec3 x = mm_vec3_make(1, 0, 0);
    b->rotations[L_UPLEG] = mm_quat_from_axis_angle(x, -bend);
    b->rotations[L_LEG] = mm_quat_from_axis_angle(x, 2.0f * bend);
    b->rotations[L_FOOT] = mm_quat_from_axis_angle(x, pitch - bend);
    b->positions[HIPS].y = 0.9f - 0.84f * (1.0f - cosf(bend)) + lift;
    b->rig.planted_ankle[0] = 0.06f, b->rig.planted_toe[0] = 0.02f; /* the data's, standing */
    mm_rig_forward(&b->rig, 1, &b->pose);
}

/* The heel lifts off while the toe holds (a foot rolling onto its toe): the toe stays on its lock
 * as the animated foot pitches about the ankle, before and after the heel's label goes off, and
 * the ankle rises with the roll. */
static void test_feet_roll_onto_the_toe(void **state)
{
    (void)state;
    mm_feet f;
    mm_character_desc d = feet_fixture(&f, 0.0f, true);
    body b;
    float dt = 1.0f / 60.0f;
    bent_left_leg(&b, 0.3f, 0.0f, 0.0f);
    level_tick(&f, &d, &b, &LABEL_LEFT_HEEL_TOE, dt);
    assert_true(f.heel_locked[0] && f.toe_locked[0]);
    mm_vec3 planted = b.global[L_TOE].translation;
    for (int i = 1; i <= 20; ++i) {
        /* the animated foot pitches toe-down about its ankle, 0.02 rad a tick (the heel rising) */
        bent_left_leg(&b, 0.3f, 0.02f * (float)i, 0.0f);
        level_tick(&f, &d, &b, i < 4 ? &LABEL_LEFT_HEEL_TOE : &LABEL_LEFT_TOE, dt);
        assert_vec3_near(b.global[L_TOE].translation, planted, 1e-3f);
    }
    assert_true(f.toe_locked[0] && !f.heel_locked[0]);
    assert_true(b.global[L_FOOT].translation.y > 0.06f + 0.03f);
}

/* Toe pivot (feet.c): the left foot planted on its toe alone, the body then carried on along +Z at
 * 1.2 m/s with the leg as animated (bent 0.5 rad), the toe's label on: once the pelvis's move is
 * spent (from the 16th tick) the ankle's target is out of the leg's reach, and the foot pivots
 * about its toe, heel up, so that the toe stays on its lock (within 1 mm) while the ankle rises
 * (3.8 cm by the 30th tick); before, the straight leg left the whole foot short of its target, the
 * toe lifted off the ground (1.4 cm by then) and dragged after the body. The label then off, the
 * foot lets go from where it was shown (the toe moves 0.4 cm in that tick; dropping the pivot
 * at once moved it 2.8 cm). */
static void test_feet_toe_pivot_out_of_reach(void **state)
{
    (void)state;
    mm_character_desc d = defaults();
    d.plant_time = 0.0f;
    d.max_hip_drop = 0.0f;
    body b;
    mm_feet f;
    memset(&f, 0, sizeof f);
    float dt = 1.0f / 60.0f;
    mm_feet_contacts toe = {MM_CONTACT_LEFT_TOE, {-1.0f, -1.0f}, {-1.0f, -1.0f}},
                     none = {0, {-1.0f, -1.0f}, {-1.0f, -1.0f}};
    mm_vec3 planted = {0, 0, 0}, shown = {0, 0, 0};
    for (int n = 0; n <= 31; ++n) {
        bent_left_leg(&b, 0.5f, 0.0f, 0.0f);
        b.positions[HIPS].z = 1.2f * (float)n * dt;
        mm_rig_forward(&b.rig, 1, &b.pose);
        mm_feet_update(&f, &d, &b.rig, n <= 30 ? &toe : &none, &(mm_feet_ground){0.0f, true, NULL}, dt,
                       &b.pose);
        if (n == 0) planted = b.global[L_TOE].translation;
        if (n <= 30) assert_vec3_near(b.global[L_TOE].translation, planted, 1e-3f);
        if (n == 30) assert_true(b.global[L_FOOT].translation.y > 0.06f + 0.03f); /* heel up */
        if (n == 31) assert_true(mm_vec3_distance(b.global[L_TOE].translation, shown) < 0.01f);
        shown = b.global[L_TOE].translation;
    }
    assert_false(f.toe_locked[0]);
}

/* The heel up before the hips down (feet.c): the toe pivot's body, carried on along +Z at 1.2 m/s
 * over the left foot planted behind it, now with the hips free to come down (max_hip_drop 0.1 m).
 * Planted on its toe alone, the foot's pivot (at most 0.8 rad) brings its ankle within reach for
 * the whole 30 ticks (test_feet_toe_pivot_out_of_reach: the toe held by the pivot alone, the hips
 * never lowered), so the hips stay where they are animated (hip_drop 0) and the toe stays on its
 * lock (within 1 mm). Planted on heel and toe, the ankle held where it was planted, the same body
 * has its hips lowered (more than 2 cm by the 30th tick): the pivot, not the drop, is what spares
 * the hips; before, the drop reached for the unpivoted ankle and came down either way. */
static void test_feet_heel_up_before_hips_down(void **state)
{
    (void)state;
    float dt = 1.0f / 60.0f;
    mm_feet_contacts toe = {MM_CONTACT_LEFT_TOE, {-1.0f, -1.0f}, {-1.0f, -1.0f}};
    for (int heel = 0; heel <= 1; ++heel) {
        mm_feet f;
        mm_character_desc d = feet_fixture(&f, 0.0f, false);
        assert_true(d.max_hip_drop >= 0.1f - 1e-6f);
        body b;
        mm_vec3 planted = {0, 0, 0};
        float most = 0.0f;
        for (int n = 0; n <= 30; ++n) {
            bent_left_leg(&b, 0.5f, 0.0f, 0.0f);
            b.positions[HIPS].z = 1.2f * (float)n * dt;
            mm_rig_forward(&b.rig, 1, &b.pose);
            level_tick(&f, &d, &b, heel ? &LABEL_LEFT_HEEL_TOE : &toe, dt);
            if (n == 0) planted = b.global[L_TOE].translation;
            most = fmaxf(most, f.hip_drop);
            if (!heel) assert_vec3_near(b.global[L_TOE].translation, planted, 1e-3f);
        }
        if (heel)
            assert_true(f.hip_drop > 0.02f);
        else
            assert_float_equal(most, 0.0f, 1e-6f);
    }
}

/* Tick n of the body carried on at 1.2 m/s over its left foot planted on heel and toe (the ground
 * held or not: a move's), the rig's floors as the caller set them. */
static void carry_over_planted_foot(mm_feet *f, const mm_character_desc *d, body *b, int n, float dt,
                                    bool held)
{
    b->positions[HIPS].z = 1.2f * (float)n * dt;
    mm_rig_forward(&b->rig, 1, &b->pose);
    mm_feet_update(f, d, &b->rig, &LABEL_LEFT_HEEL_TOE, &(mm_feet_ground){0.0f, held, NULL}, dt, &b->pose);
}

/* The hips come down no lower than the data's upright locomotion carries them (mm_rig.hip_floor),
 * on held ground (not during a move):
 * the body of test_feet_heel_up_before_hips_down carried on at 1.2 m/s over a foot planted on heel
 * and toe, its animated hips at 0.9 - 0.84 (1 - cos 0.5) = 0.797 m. With no floor the hips come down
 * more than 2 cm; with the floor 1 cm under the animated hips they come down at most that 1 cm (the
 * pelvis never under the floor), and the lock its leg no longer reaches creeps after the animation
 * (the ankle left within REACH_SLACK, 2 cm, of its target) instead of the body sinking. */
static void test_feet_hips_no_lower_than_the_floor(void **state)
{
    (void)state;
    float dt = 1.0f / 60.0f;
    /* floored 2: the same floor during a move (the ground not held): the floor is locomotion's,
     * a move's clip lowers the hips as far as its legs need (a climb reaching for a wall's top) */
    for (int floored = 0; floored <= 2; ++floored) {
        mm_feet f;
        mm_character_desc d = feet_fixture(&f, 0.0f, false);
        body b;
        float most = 0.0f, lowest = INFINITY;
        for (int n = 0; n <= 30; ++n) {
            bent_left_leg(&b, 0.5f, 0.0f, 0.0f);
            b.rig.hip_floor = floored ? 0.9f - 0.84f * (1.0f - cosf(0.5f)) - 0.01f : 0.0f;
            carry_over_planted_foot(&f, &d, &b, n, dt, floored != 2);
            most = fmaxf(most, f.hip_drop);
            lowest = fminf(lowest, b.global[HIPS].translation.y);
            assert_true(f.locked[0]);
            if (floored < 2) assert_true(f.reach_miss[0] < 0.02f + 1e-4f);
        }
        if (floored == 1) {
            assert_true(most <= 0.01f + 1e-6f);
            assert_true(lowest >= b.rig.hip_floor - 1e-5f);
        } else {
            assert_true(most > 0.02f);
            if (floored == 2) assert_true(lowest < b.rig.hip_floor - 0.01f);
        }
    }
}

/* The hips' drop keeps the head above the crouch line (mm_rig.head_floor), on held ground: the body
 * of test_feet_hips_no_lower_than_the_floor (hips animated at 0.797 m, no hip floor), its head
 * 0.15 + 0.2 + 0.3 = 0.65 m above the hips (upright spine), so at 1.447 m. With no head floor the hips
 * come down more than 2 cm; with the line 2 cm under the animated head they come down at most the
 * 2 cm less the 1 cm margin, the head never under the line plus that margin, and the lock the leg no
 * longer reaches creeps after the animation (the ankle within REACH_SLACK, 2 cm, of its target).
 * During a move (the ground not held) the line does not hold the hips. */
static void test_feet_head_above_the_crouch_line(void **state)
{
    (void)state;
    float dt = 1.0f / 60.0f, hips = 0.9f - 0.84f * (1.0f - cosf(0.5f)), line = hips + 0.65f - 0.02f;
    for (int floored = 0; floored <= 2; ++floored) {
        mm_feet f;
        mm_character_desc d = feet_fixture(&f, 0.0f, false);
        body b;
        float most = 0.0f, lowest = INFINITY;
        for (int n = 0; n <= 30; ++n) {
            bent_left_leg(&b, 0.5f, 0.0f, 0.0f);
            b.rig.hip_floor = 0.0f;
            b.rig.head = HEAD;
            b.rig.head_floor = floored ? line : 0.0f;
            assert_float_equal(mm_rig_head_above_pelvis(&b.rig, &b.pose), 0.65f, 1e-5f);
            carry_over_planted_foot(&f, &d, &b, n, dt, floored != 2);
            most = fmaxf(most, f.hip_drop);
            lowest = fminf(lowest, b.global[HIPS].translation.y + 0.65f);
            assert_true(f.locked[0]);
            if (floored < 2) assert_true(f.reach_miss[0] < 0.02f + 1e-4f);
        }
        if (floored == 1) {
            assert_true(most <= 0.01f + 1e-5f);
            assert_true(lowest >= line + 0.01f - 1e-5f);
        } else {
            assert_true(most > 0.02f);
        }
    }
}

/* The head's height above the pelvis follows the spine: the test body's spine (its joint 0.15 m above
 * the hips, the chest 0.2 m above it, the head 0.3 m above that) leaned 0.6 rad at the spine joint
 * puts the head 0.15 + 0.5 cos 0.6 above the hips; the pelvis turned 0.3 rad about the same axis as
 * well, 0.15 cos 0.3 + 0.5 cos 0.9; a rig with no head gives 0. */
static void test_rig_head_above_pelvis(void **state)
{
    (void)state;
    body b;
    make_body(&b);
    b.rig.head = HEAD;
    mm_vec3 x = mm_vec3_make(1, 0, 0);
    b.rotations[SPINE] = mm_quat_from_axis_angle(x, 0.6f);
    mm_rig_forward(&b.rig, 1, &b.pose);
    assert_float_equal(mm_rig_head_above_pelvis(&b.rig, &b.pose), 0.15f + 0.5f * cosf(0.6f), 1e-5f);
    b.rotations[HIPS] = mm_quat_from_axis_angle(x, 0.3f);
    mm_rig_forward(&b.rig, 1, &b.pose);
    assert_float_equal(mm_rig_head_above_pelvis(&b.rig, &b.pose), 0.15f * cosf(0.3f) + 0.5f * cosf(0.9f),
                       1e-5f);
    b.rig.head = -1;
    assert_float_equal(mm_rig_head_above_pelvis(&b.rig, &b.pose), 0.0f, 0.0f);
}

/* Planted on heel and toe with the toe's lock 1 cm further along the foot than the foot reaches (two
 * locks placed and settled apart): the toe is shown on the foot, short of its lock; when the heel
 * lifts, the toe stays where it was shown (within 1 mm on the ground plane) instead of moving onto
 * its lock in that tick, and stays there as the foot rolls about it. */
static void test_feet_heel_lifts_where_shown(void **state)
{
    (void)state;
    mm_feet f;
    mm_character_desc d = feet_fixture(&f, 0.0f, true);
    body b;
    float dt = 1.0f / 60.0f;
    bent_left_leg(&b, 0.3f, 0.0f, 0.0f);
    level_tick(&f, &d, &b, &LABEL_LEFT_HEEL_TOE, dt);
    assert_true(f.heel_locked[0] && f.toe_locked[0]);
    mm_vec3 along = mm_vec3_sub(f.toe_lock[0], f.heel_lock[0]);
    along.y = 0.0f;
    f.toe_lock[0] = mm_vec3_add(f.toe_lock[0], mm_vec3_scale(mm_vec3_normalize(along), 0.01f));
    bent_left_leg(&b, 0.3f, 0.0f, 0.0f);
    level_tick(&f, &d, &b, &LABEL_LEFT_HEEL_TOE, dt);
    mm_vec3 shown = b.global[L_TOE].translation, off = mm_vec3_sub(f.toe_lock[0], shown);
    assert_true(sqrtf(off.x * off.x + off.z * off.z) > 0.008f); /* short of its lock */
    for (int i = 1; i <= 10; ++i) {
        bent_left_leg(&b, 0.3f, 0.02f * (float)i, 0.0f); /* the heel rising */
        level_tick(&f, &d, &b, &LABEL_LEFT_TOE, dt);
        assert_true(f.toe_locked[0] && !f.heel_locked[0]);
        mm_vec3 moved = mm_vec3_sub(b.global[L_TOE].translation, shown);
        assert_true(sqrtf(moved.x * moved.x + moved.z * moved.z) < 1e-3f);
    }
}

/* The horizontal distance (m) between a and b. */
static float ground_distance(mm_vec3 a, mm_vec3 b)
{
    return sqrtf((a.x - b.x) * (a.x - b.x) + (a.z - b.z) * (a.z - b.z));
}

/* The body turning on the spot about a foot planted on heel and toe (its ankle where the animation
 * has it, the animated foot yawing 1.1 rad away from the planted one over 44 ticks, as a body turns
 * over a foot the data pivots): the foot is held, its toe within 1 mm of where it was planted; with
 * the foot turned at most 0.8 rad from its animation, the toe went round the heel past that, 0.12 m
 * from the ankle: 0.12 * 0.3 = 3.6 cm. The knee turns with the held foot, by the foot's turn about
 * the leg (here vertical): the least rotation taking the animated ankle-to-toe vector (0, -0.04,
 * 0.12) yawed by 1.1 rad onto the planted one turns it 0.978 rad about the vertical, so the knee's
 * bend (from the middle of hip and ankle, on the ground plane) ends 1.1 - 0.978 rad from the foot;
 * before, it stayed where the body turned, 1.1 rad off the foot. */
static void test_feet_body_turns_over_a_planted_foot(void **state)
{
    (void)state;
    mm_feet f;
    mm_character_desc d = feet_fixture(&f, 0.0f, true);
    body b;
    float dt = 1.0f / 60.0f;
    bent_left_leg(&b, 0.3f, 0.0f, 0.0f);
    mm_vec3 ankle = b.global[L_FOOT].translation, planted = {0, 0, 0};
    for (int i = 0; i <= 44; ++i) {
        bent_left_leg(&b, 0.3f, 0.0f, 0.0f);
        mm_quat yaw = mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), 0.025f * (float)i);
        b.global[ROOT] = mm_xform_make(yaw, mm_vec3_sub(ankle, mm_quat_rotate(yaw, ankle)));
        mm_rig_forward(&b.rig, 1, &b.pose);
        level_tick(&f, &d, &b, &LABEL_LEFT_HEEL_TOE, dt);
        mm_vec3 toe = b.global[L_TOE].translation;
        if (i == 0) planted = toe;
        assert_true(ground_distance(toe, planted) < 1e-3f);
    }
    mm_vec3 foot = mm_vec3_sub(b.global[L_TOE].translation, b.global[L_FOOT].translation);
    mm_vec3 middle =
        mm_vec3_scale(mm_vec3_add(b.global[L_UPLEG].translation, b.global[L_FOOT].translation), 0.5f);
    mm_vec3 bend = mm_vec3_sub(b.global[L_LEG].translation, middle);
    float off = fabsf(atan2f(foot.x * bend.z - foot.z * bend.x, foot.x * bend.x + foot.z * bend.z));
    assert_float_equal(off, 1.1f - 0.978f, 0.01f);
}

/* A lock that begins while the foot still rolls holds its joint where it was shown (feet.c,
 * foot_as_shown). The animated left foot turns about its ankle at `rate` rad a tick from `pitch`
 * (positive: toe down), under `before` and then, from tick `on`, under `after`; joint (L_TOE or
 * L_FOOT) is followed as shown. Returns how far it moved on the ground plane in the tick before
 * `on` (*rolling: the roll's speed as shown, which the planted joint used to keep for its first
 * labelled tick) and in tick `on` itself; *held: the most it moved from there over 4 ticks more. */
static float plant_while_rolling(float pitch, float rate, int on, const mm_feet_contacts *before,
                                 const mm_feet_contacts *after, int joint, float *rolling, float *held)
{
    mm_feet f;
    mm_character_desc d = feet_fixture(&f, 0.0f, true);
    body b;
    float dt = 1.0f / 60.0f, moved = 0.0f;
    mm_vec3 shown = {0, 0, 0}, planted = {0, 0, 0};
    *held = 0.0f;
    for (int i = 0; i <= on + 4; ++i) {
        bent_left_leg(&b, 0.3f, pitch + rate * (float)i, 0.0f);
        level_tick(&f, &d, &b, i < on ? before : after, dt);
        mm_vec3 at = b.global[joint].translation;
        if (i == on - 1) *rolling = ground_distance(at, shown);
        if (i == on) moved = ground_distance(at, shown), planted = at;
        if (i > on) *held = fmaxf(*held, ground_distance(at, planted));
        shown = at;
    }
    return moved;
}

/* Three ways a lock begins while the foot rolls at 4.2 or 2.4 rad/s (a transition's offsets turning
 * the foot), the joint moving over the ground by 1.3, 2.6 and 3.0 mm in the tick before its label
 * turns on: a toe landing first (the foot pitching toe down), a toe coming down after its heel (the
 * foot flattening, the heel held), a heel coming down under a held toe (the foot rolling back onto
 * it). Before, the joint was planted where the foot had turned it that tick and moved 0.7, 2.0 and
 * 2.9 mm on its first labelled tick. Now at most a tenth of the tick before; the toe planted first
 * stays within 1 mm while the foot goes on turning. */
static void test_feet_lock_begins_where_shown(void **state)
{
    (void)state;
    float rolling = 0.0f, held = 0.0f, moved;
    moved = plant_while_rolling(0.0f, -0.07f, 4, &LABEL_NONE, &LABEL_LEFT_TOE, L_TOE, &rolling, &held);
    assert_true(rolling > 1e-3f);
    assert_true(moved < 0.1f * rolling);
    assert_true(held < 1e-3f);
    moved =
        plant_while_rolling(-0.8f, 0.07f, 4, &LABEL_LEFT_HEEL, &LABEL_LEFT_HEEL_TOE, L_TOE, &rolling, &held);
    assert_true(rolling > 1e-3f);
    assert_true(moved < 0.1f * rolling);
    moved =
        plant_while_rolling(0.5f, -0.04f, 6, &LABEL_LEFT_TOE, &LABEL_LEFT_HEEL_TOE, L_FOOT, &rolling, &held);
    assert_true(rolling > 1e-3f);
    assert_true(moved < 0.1f * rolling);
}

/* A foot planted while still settling (its label on 3 cm above where it comes to rest) follows the
 * animated foot down to the ground instead of hovering at the height it was planted at. */
static void test_feet_lock_comes_down(void **state)
{
    (void)state;
    mm_feet f;
    mm_character_desc d = feet_fixture(&f, 0.0f, true);
    body b;
    float dt = 1.0f / 60.0f;
    for (int i = 0; i <= 10; ++i) {
        bent_left_leg(&b, 0.3f, 0.0f, 0.03f * (1.0f - (float)i / 10.0f));
        float animated = b.global[L_FOOT].translation.y;
        level_tick(&f, &d, &b, &LABEL_LEFT_HEEL, dt);
        assert_true(f.heel_locked[0]);
        assert_float_equal(b.global[L_FOOT].translation.y, animated, 1e-3f);
    }
    assert_float_equal(b.global[L_FOOT].translation.y, 0.06f, 1e-3f);
}

/* A second difference |p2 - 2 p1 + p0| (m). */
static float second_difference(mm_vec3 p0, mm_vec3 p1, mm_vec3 p2)
{
    return mm_vec3_length(mm_vec3_add(mm_vec3_sub(p2, mm_vec3_scale(p1, 2.0f)), p0));
}

/* A lock above its animated foot (planted while an offset held the foot up) comes down to it
 * gradually: with the animated foot still, its height h above it halves every feet.c's
 * LOCK_SETTLE_HALFLIFE (0.1 s), h 2^(-n dt / 0.1) after n ticks, and the ankle's largest second
 * difference is the first tick's, h (1 - 2^(-dt / 0.1)) = 0.11 h, where put down at once it moved h
 * in a tick. */
static void test_feet_lock_settles_gradually(void **state)
{
    (void)state;
    mm_feet f;
    mm_character_desc d = feet_fixture(&f, 0.0f, true);
    body b;
    float dt = 1.0f / 60.0f, h = 0.1f;
    bent_left_leg(&b, 0.3f, 0.0f, 0.0f);
    level_tick(&f, &d, &b, &LABEL_LEFT_HEEL, dt);
    assert_true(f.heel_locked[0]);
    f.heel_lock[0].y += h; /* planted h above the animated ankle */
    mm_vec3 p[3];
    float worst = 0.0f;
    for (int n = 0; n <= 30; ++n) {
        bent_left_leg(&b, 0.3f, 0.0f, 0.0f);
        level_tick(&f, &d, &b, &LABEL_LEFT_HEEL, dt);
        p[2] = f.lock[0]; /* the ankle's target (the leg's bend catches up with it: ease_bend) */
        if (n == 0) p[0] = p[1] = mm_vec3_make(p[2].x, 0.06f + h, p[2].z);
        assert_float_equal(p[2].y, 0.06f + h * exp2f(-(float)(n + 1) * dt / 0.1f), 1e-3f);
        if (n >= 6) assert_float_equal(b.global[L_FOOT].translation.y, p[2].y, 1e-3f);
        worst = fmaxf(worst, second_difference(p[0], p[1], p[2]));
        p[0] = p[1], p[1] = p[2];
    }
    assert_float_equal(worst, h * (1.0f - exp2f(-dt / 0.1f)), 1e-3f);
}

/* A foot let go far behind its animated place with its next contact near (ease_swing, feet.c): the
 * left toe held (its pivot, the pelvis leaning back) for 8 ticks while the body runs on along +Z at
 * 4 m/s, its label then off with the next contact 0.25 s away. Let go, the foot keeps its velocity
 * (at rest) and its offset (0.5 m behind the animated ankle, which moves on evenly: any change of
 * the foot's velocity is the feet stage's own). The offset's spring, with the swing's catch-up
 * (half-life 0.08 s), pulled the ankle's target from rest by a second difference of 6.2 cm in one
 * tick (the shown ankle 4.8 cm); now its velocity changes by at most SWING_ACCELERATION (150 m/s^2)
 * dt a tick, a second difference of 150 dt^2 = 4.2 cm on the ground plane (4.5 allowed: the height
 * is the step's lift's), and the shown ankle follows within its leg's reach. The foot still goes
 * after its animated place (over 0.5 m in the 9 ticks). */
static void test_feet_swing_eases_out_of_a_far_release(void **state)
{
    (void)state;
    mm_character_desc d = defaults();
    d.max_hip_drop = 0.0f;
    body b;
    mm_feet f;
    memset(&f, 0, sizeof f);
    float dt = 1.0f / 60.0f, speed = 4.0f;
    int held = 8, free_ticks = 9;
    mm_vec3 shown[3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}, aimed[3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    mm_vec3 let_go = {0, 0, 0};
    float worst_shown = 0.0f, worst_aimed = 0.0f;
    for (int n = 0; n <= held + free_ticks; ++n) {
        bent_left_leg(&b, 0.5f, 0.0f, 0.0f);
        b.positions[HIPS].z = speed * (float)n * dt;
        mm_rig_forward(&b.rig, 1, &b.pose);
        mm_vec3 animated = b.global[L_FOOT].translation;
        /* the toe's label on, then off with the next contact coming in 0.25 s (beyond the landing's
         * look-ahead throughout: no landing, the catch-up alone) */
        mm_feet_contacts labels = {MM_CONTACT_LEFT_TOE, {-1.0f, -1.0f}, {-1.0f, -1.0f}};
        if (n > held) labels.label = 0, labels.until_contact[0] = 0.25f - (float)(n - held - 1) * dt;
        level_tick(&f, &d, &b, &labels, dt);
        shown[0] = shown[1], shown[1] = shown[2], shown[2] = b.global[L_FOOT].translation;
        aimed[0] = aimed[1], aimed[1] = aimed[2], aimed[2] = f.last_target[0];
        if (n == held) {
            assert_true(f.toe_locked[0]);
            let_go = shown[2];
            assert_true(animated.z - let_go.z > 0.5f); /* far behind its animated place */
        }
        if (n > held) {
            assert_false(f.locked[0]);
            worst_shown = fmaxf(worst_shown, second_difference(shown[0], shown[1], shown[2]));
            worst_aimed = fmaxf(worst_aimed, second_difference(aimed[0], aimed[1], aimed[2]));
        }
    }
    assert_true(worst_aimed < 0.045f); /* 6.2 cm before */
    assert_true(worst_shown < 0.045f); /* 4.8 cm before */
    assert_true(shown[2].z - let_go.z > 0.5f);
}

/* A leg near full extension whose target goes out of its reach and comes back fast, as built-in seed
 * 52's right leg did at 15.7 s (docs/metrics.md, "Pops, eighth pass"): the hip-to-ankle distance asked
 * for, in leg lengths (0.84 m), 0.97 -> 1.11 -> 0.75 over ten ticks, here a planted foot the hips rise
 * above and come down over (the leg's animated shape the same throughout). Near straight the knee
 * moves as the square root of what the leg lacks: the knee's second difference about its hip, the
 * thigh (0.42 m) times the bend's at the hip, was 0.2 rad (8 cm) as the target came back into reach;
 * feet.c's ease_bend bounds the bend's by BEND_ACCELERATION dt^2 (1 + (bend / 0.3)^2), 300 rad/s^2
 * (0.083 rad, 3.5 cm near straight), and the ankle is on its lock again once the bend has caught up. */
static void test_feet_bend_eased_near_full_extension(void **state)
{
    (void)state;
    mm_feet f;
    mm_character_desc d = feet_fixture(&f, 0.0f, true);
    body b;
    float dt = 1.0f / 60.0f, length = 0.84f, shown = 0.84f * cosf(0.05f);
    const float asked[] = {0.974f, 0.974f, 0.974f, 0.987f, 1.034f, 1.083f, 1.105f, 1.074f, 1.000f, 0.903f,
                           0.816f, 0.762f, 0.748f, 0.743f, 0.743f, 0.743f, 0.743f, 0.743f, 0.743f, 0.743f};
    int ticks = (int)(sizeof asked / sizeof asked[0]);
    mm_vec3 rel[3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    float bend[3] = {0, 0, 0}, worst = 0.0f;
    for (int n = 0; n < ticks; ++n) {
        bent_left_leg(&b, 0.05f, 0.0f, asked[n] * length - shown);
        mm_feet_contacts labels = {
            MM_CONTACT_LEFT_HEEL | MM_CONTACT_LEFT_TOE, {-1.0f, -1.0f}, {-1.0f, -1.0f}};
        level_tick(&f, &d, &b, &labels, dt);
        assert_true(f.locked[0]);
        rel[0] = rel[1], rel[1] = rel[2];
        rel[2] = mm_vec3_sub(b.global[L_LEG].translation, b.global[L_UPLEG].translation);
        bend[0] = bend[1], bend[1] = bend[2], bend[2] = f.bend[0];
        if (n < 2) continue;
        worst = fmaxf(worst, second_difference(rel[0], rel[1], rel[2]));
        /* the bend's own second difference within the limit (the animated bend is still: no own change) */
        float most = fmaxf(bend[0], fmaxf(bend[1], bend[2])) / 0.3f;
        assert_true(fabsf(bend[2] - 2.0f * bend[1] + bend[0]) <=
                    300.0f * dt * dt * (1.0f + most * most) + 1e-4f);
    }
    assert_true(worst < 0.055f);           /* 0.064 m without the ease, 0.050 with it */
    assert_true(f.reach_miss[0] < 0.005f); /* caught up: on its lock */
}

/* A foot whose label turns on while it is held up more than feet.c's PLANT_MAX_HEIGHT (4 cm) above
 * where it stands is not planted there: held on the ground plane by the landing (plant_time, two
 * ticks) and not rising (its animation lifted 2 cm more on one tick), it comes down with the
 * animated foot and is planted on the first tick it is within 4 cm (the ankle 0.06 m + 4 cm). */
static void wait_aloft(const mm_scene *scene)
{
    float dt = 1.0f / 60.0f;
    mm_feet f;
    mm_character_desc d = feet_fixture(&f, 2.0f * dt, true);
    const float lift[] = {0.08f, 0.08f, 0.10f, 0.09f, 0.07f, 0.05f, 0.03f, 0.02f, 0.01f};
    body b;
    float last_y = 1.0f, held_z = 0.0f;
    int first = -1;
    for (int n = 0; n < 9 && first < 0; ++n) { /* free on tick 0, the label on from tick 1 */
        bent_left_leg(&b, 0.3f, 0.0f, lift[n]);
        b.positions[HIPS].z = 0.5f * (float)n * dt; /* the body moving on */
        mm_rig_forward(&b.rig, 1, &b.pose);
        mm_feet_update(&f, &d, &b.rig, n == 0 ? &LABEL_NONE : &LABEL_LEFT_HEEL,
                       &(mm_feet_ground){0.0f, true, scene}, dt, &b.pose);
        if (n == 0) continue;
        assert_true(f.lock[0].y <= last_y + 1e-6f); /* not rising */
        if (n == 2) held_z = f.lock[0].z;           /* the landing has run its two ticks */
        if (n > 2) assert_float_equal(f.lock[0].z, held_z, 1e-5f);
        if (f.heel_locked[0]) {
            first = n;
            assert_true(f.heel_lock[0].y < 0.06f + 0.04f);
        } else if (n >= 2 && !scene) {
            assert_true(f.lock[0].y > 0.06f + 0.04f - 1e-5f); /* waiting: aloft */
        }
        last_y = f.lock[0].y;
    }
    assert_true(first > 2);
}

static void test_feet_wait_aloft(void **state)
{
    (void)state;
    wait_aloft(NULL);
}

/* A foot whose toe's label turns on while it is held 8 cm up (aloft: it waits to be planted), the
 * body turning about that ankle 0.03 rad a tick (the animated foot yawing with it): once the
 * landing has run (two ticks), the foot keeps the heading it was shown with, its toe within 0.5 mm
 * on the ground plane over the next 5 ticks. Before, the toe swung round the held ankle as
 * animated, 0.12 m from it: 0.12 * 0.03 = 3.6 mm a tick. */
static void test_feet_toe_aloft_keeps_its_heading(void **state)
{
    (void)state;
    float dt = 1.0f / 60.0f;
    mm_feet f;
    mm_character_desc d = feet_fixture(&f, 2.0f * dt, true);
    body b;
    bent_left_leg(&b, 0.3f, 0.0f, 0.08f);
    mm_vec3 ankle = b.global[L_FOOT].translation, held = {0, 0, 0};
    for (int n = 0; n <= 8; ++n) { /* free on tick 0, the toe's label on from tick 1 */
        bent_left_leg(&b, 0.3f, 0.0f, 0.08f);
        mm_quat yaw = mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), 0.03f * (float)n);
        b.global[ROOT] = mm_xform_make(yaw, mm_vec3_sub(ankle, mm_quat_rotate(yaw, ankle)));
        mm_rig_forward(&b.rig, 1, &b.pose);
        level_tick(&f, &d, &b, n == 0 ? &LABEL_NONE : &LABEL_LEFT_TOE, dt);
        assert_false(f.locked[0]); /* aloft: waiting */
        mm_vec3 toe = b.global[L_TOE].translation;
        if (n == 3) held = toe;
        if (n > 3) assert_true(ground_distance(toe, held) < 5e-4f);
    }
}

/* The same on terrain (a scene whose ground is the plane y = 0): where a foot stands is the ground
 * under it, and a foot labelled while held up is not planted until it is down (going down stairs,
 * a foot labelled over the lower tread while still shown above it was planted in the air and came
 * down over 0.2 s, 11 cm up); while it waits the terrain's landing brings it down
 * (LANDING_FALL_SPEED), so its height then is not the animation's. */
static void test_feet_wait_aloft_on_terrain(void **state)
{
    (void)state;
    static mm_scene flat; /* large: kept off the stack */
    mm_scene_init(&flat, 0.0f);
    wait_aloft(&flat);
}

/* The body at z along +Z (everything moved with its hips and root). */
static void body_at(body *b, float z)
{
    make_body(b);
    b->positions[HIPS].z = z;
    mm_rig_forward(&b->rig, 1, &b->pose);
}

/* The rig's planted heights those of make_body's feet (ankles 0.06 m, toes 0.02 m above the ground):
 * its feet stand on the ground. */
static void on_the_ground(body *b)
{
    for (int k = 0; k < 2; ++k) b->rig.planted_ankle[k] = 0.06f, b->rig.planted_toe[k] = 0.02f;
}

/* Toe down under a raised heel (feet.c): on terrain (a scene whose ground is the plane y = 0), the
 * left foot labelled on heel and toe while animated toe first: the body 8 cm up and the foot
 * pitched 0.6 rad toe down, so that its toe is 1.9 cm above its planted height (not aloft) and its
 * ankle 8 cm above its own. Planted there, both locks stand on the ground and the offset carries the
 * ankle's 8 cm, fading over foot_halflife (the knee bent 0.6 rad: the leg reaches the ground). The
 * toe is shown within 1.5 cm of its planted 2 cm from the first tick (3.3 cm: the foot's length
 * from the raised ankle falls short of a lock 1.9 cm under the animated toe) while the ankle comes
 * down from its 14 cm; before, the foot was held flat above both locks, its toe lifted with the
 * ankle (8.1 cm on the first tick, 3.7 cm after 10). */
static void test_feet_toe_down_under_raised_heel(void **state)
{
    (void)state;
    static mm_scene flat; /* large: kept off the stack */
    mm_scene_init(&flat, 0.0f);
    mm_character_desc d = defaults();
    d.plant_time = 0.0f;
    d.max_hip_drop = 0.0f;
    float dt = 1.0f / 60.0f, raised = 0.08f, pitch = 0.6f;
    mm_feet_contacts both = {MM_CONTACT_LEFT_HEEL | MM_CONTACT_LEFT_TOE, {-1.0f, -1.0f}, {-1.0f, -1.0f}};
    mm_feet f;
    memset(&f, 0, sizeof f);
    body b;
    float last_ankle = 1.0f;
    for (int n = 0; n < 20; ++n) {
        bent_left_leg(&b, 0.6f, pitch, raised); /* the knee bent: the leg can reach the ground */
        if (n == 0) { /* as animated: toe 1.9 cm, ankle 8 cm above their planted heights */
            assert_float_equal(b.global[L_TOE].translation.y, 0.02f + 0.0194f, 1e-3f);
            assert_float_equal(b.global[L_FOOT].translation.y, 0.06f + raised, 1e-6f);
        }
        mm_feet_update(&f, &d, &b.rig, &both, &(mm_feet_ground){0.0f, true, &flat}, dt, &b.pose);
        assert_true(f.heel_locked[0] && f.toe_locked[0]);
        float ankle = b.global[L_FOOT].translation.y, toe = b.global[L_TOE].translation.y;
        /* on (or just over) its lock: the lock is 1.9 cm under the animated toe, which the foot's
         * length reaches from the raised ankle at 3.3 cm, then the toe's soft floor (TOE_SINK) */
        assert_true(toe < 0.02f + 0.015f && toe > 0.02f - 0.0101f);
        assert_true(ankle < last_ankle + 1e-5f);        /* the heel comes down, never up */
        if (n == 0) assert_true(ankle > 0.06f + 0.07f); /* from where it was shown */
        last_ankle = ankle;
    }
    assert_true(last_ankle < 0.06f + 0.025f); /* most of the way down after 1/3 s (2 cm left) */
}

/* A toe planted under a raised ankle (feet.c, the toe's aim from the floored ankle): on terrain (a
 * scene whose ground is the plane y = 0), the left foot animated 3 cm too low (its ankle at 0.03,
 * under its planted 0.06) and pitched 0.24 rad toe up so that its toe is at its planted 2 cm, lands
 * toe first, then on heel and toe, then rolls up onto its toe (pitching 0.03 rad a tick toe down)
 * while the body runs on past it at 1.2 m/s (the knee bent 0.5 rad: the leg reaches). The ankle is
 * held at its floor (0.06 m), 3 cm above where the animation has it: the foot pitches down about it
 * onto the toe's lock. The toe then stands within the foot's own mismatch of its lock: the foot's
 * length, 12.65 cm, against 13.2 cm from the raised ankle to the lock (12.6 cm ahead, 4 cm down),
 * leaves it short by 0.58 cm along a foot pitched 0.31 rad down, 0.18 cm up (0.5 allowed), and by
 * TOE_SINK (1 cm) at most down. Before, the foot was pitched for the ankle where the animation had
 * it and then raised with it: the toe 3 cm above its lock while on its toe, up to 5.6 cm on heel
 * and toe, and 2.2-2.5 cm after the heel let go (LAFAN1's run on the rough field: 2.96 cm). */
static void test_feet_toe_planted_under_a_raised_ankle(void **state)
{
    (void)state;
    static mm_scene flat; /* large: kept off the stack */
    mm_scene_init(&flat, 0.0f);
    mm_character_desc d = defaults();
    d.plant_time = 0.0f;
    d.max_hip_drop = 0.0f;
    float dt = 1.0f / 60.0f, low = -0.03f, toe_up = -0.24f;
    mm_feet_contacts toe = {MM_CONTACT_LEFT_TOE, {-1.0f, -1.0f}, {-1.0f, -1.0f}},
                     both = {MM_CONTACT_LEFT_HEEL | MM_CONTACT_LEFT_TOE, {-1.0f, -1.0f}, {-1.0f, -1.0f}};
    mm_feet f;
    memset(&f, 0, sizeof f);
    body b;
    float highest = 0.0f, lowest = 1.0f;
    for (int n = 0; n < 30; ++n) {
        float pitch = toe_up + (n < 15 ? 0.0f : 0.03f * (float)(n - 14));
        bent_left_leg(&b, 0.5f, pitch, low);
        b.positions[HIPS].z = 1.2f * (float)n * dt;
        mm_rig_forward(&b.rig, 1, &b.pose);
        if (n == 0) { /* as animated: the toe at its planted height, the ankle 3 cm under its own */
            assert_float_equal(b.global[L_TOE].translation.y, 0.02f, 1e-3f);
            assert_float_equal(b.global[L_FOOT].translation.y, 0.06f + low, 1e-6f);
        }
        const mm_feet_contacts *labels = n < 3 || n >= 15 ? &toe : &both;
        mm_feet_update(&f, &d, &b.rig, labels, &(mm_feet_ground){0.0f, true, &flat}, dt, &b.pose);
        assert_true(f.toe_locked[0]);
        float gap = b.global[L_TOE].translation.y - 0.02f;
        highest = fmaxf(highest, gap), lowest = fminf(lowest, gap);
    }
    assert_true(highest < 0.005f); /* 5.6 cm before */
    assert_true(lowest > -0.0101f);
}

/* A foot let go behind its animated place steps there instead of skating over the ground: the left
 * heel planted at P while the body stands, the body then 0.3 m ahead (within unlock_radius: held),
 * the label off with the body still. The ankle's target catches up 0.3 m along +Z as its offset
 * fades and rises meanwhile by STEP_LIFT_SHARE (0.25) of the way left, at most STEP_LIFT_MAX (4
 * cm), through a 0.15 s spring (feet.c): from the ground on the tick it is let go (under 2 mm up),
 * over 2 cm up on its way (the offset fades over foot_halflife, faster than the lift's spring),
 * and back on the animated height once there. A
 * contact coming (its label on within the landing's look-ahead): no lift. Before, the foot stayed
 * at the animated height (6 cm, on the ground) all the way. */
static void test_feet_released_foot_steps(void **state)
{
    (void)state;
    for (int coming = 0; coming < 2; ++coming) {
        mm_feet f;
        mm_character_desc d = feet_fixture(&f, 0.0f, false);
        float dt = 1.0f / 60.0f;
        mm_feet_contacts off = {0, {coming ? 0.05f : -1.0f, -1.0f}, {-1.0f, -1.0f}};
        body b;
        body_at(&b, 0.0f);
        level_tick(&f, &d, &b, &LABEL_LEFT_HEEL, dt);
        mm_vec3 P = f.heel_lock[0];
        body_at(&b, 0.3f);
        level_tick(&f, &d, &b, &LABEL_LEFT_HEEL, dt);
        assert_vec3_near(f.heel_lock[0], P, 1e-6f);
        float highest = 0.0f, first = -1.0f;
        for (int n = 0; n < 120; ++n) {
            body_at(&b, 0.3f);
            level_tick(&f, &d, &b, &off, dt);
            float lift = f.lock[0].y - P.y;
            if (first < 0.0f) first = lift;
            highest = fmaxf(highest, lift);
            assert_true(lift <= 0.04f + 1e-5f && lift <= 0.25f * 0.3f);
        }
        assert_float_equal(f.lock[0].z, P.z + 0.3f, 1e-3f); /* there */
        if (coming) {
            assert_float_equal(highest, 0.0f, 1e-6f);
        } else {
            assert_true(first >= 0.0f && first < 0.002f);
            assert_true(highest > 0.02f); /* 2.77 cm */
            assert_float_equal(f.lock[0].y, P.y, 1e-3f);
        }
    }
}

/* A foot let go far behind its animated place, its contact coming, is planted near the animation's
 * place: the left heel held at P while the body is carried 0.3 m ahead (within unlock_radius), the
 * label then off for 9 ticks (0.15 s) and on again with the body still. With no contact coming
 * (until_contact -1) the offset decays on the spring of foot_halflife from rest: the heel is planted
 * 0.3 (1 + y T) e^(-y T) short of the animated heel (y its damping, T the 9 ticks: the release tick
 * sets the offset after its decay), 15 cm: T is the half-life. With the contact seen coming 0.15 s
 * ahead an offset over SWING_CATCH_UP_FROM (0.2 m) fades faster, wholly from SWING_CATCH_UP_RAMP
 * further (0.3 m), with the half-life of the time left over 3, at least 0.08 s (feet.c): planted
 * 8.2 cm short (under 0.6 of the 15), the foot moving no faster than the spring of 0.08 s takes it
 * from rest (a step of at most 0.3 y' dt e^-1 on the ground plane, y' its damping). */
static void test_feet_swing_catches_up_before_contact(void **state)
{
    (void)state;
    float short_of[2] = {0.0f, 0.0f};
    for (int coming = 0; coming < 2; ++coming) {
        mm_character_desc d = defaults();
        d.plant_time = 0.0f;
        float dt = 1.0f / 60.0f;
        mm_feet_contacts heel = {MM_CONTACT_LEFT_HEEL, {-1.0f, -1.0f}, {-1.0f, -1.0f}};
        mm_feet f;
        memset(&f, 0, sizeof f);
        body b;
        body_at(&b, 0.0f);
        mm_feet_update(&f, &d, &b.rig, &heel, &(mm_feet_ground){0.0f, true, NULL}, dt, &b.pose);
        mm_vec3 P = f.heel_lock[0];
        body_at(&b, 0.3f);
        mm_feet_update(&f, &d, &b.rig, &heel, &(mm_feet_ground){0.0f, true, NULL}, dt, &b.pose);
        assert_vec3_near(f.heel_lock[0], P, 1e-6f);
        float fastest = 0.0f, last_z = P.z;
        for (int n = 0; n < 9; ++n) {
            float left = coming ? 0.15f - (float)n * dt : -1.0f;
            mm_feet_contacts off = {0, {-1.0f, -1.0f}, {left, -1.0f}};
            body_at(&b, 0.3f);
            mm_feet_update(&f, &d, &b.rig, &off, &(mm_feet_ground){0.0f, true, NULL}, dt, &b.pose);
            assert_false(f.locked[0]);
            fastest = fmaxf(fastest, f.lock[0].z - last_z);
            last_z = f.lock[0].z;
        }
        body_at(&b, 0.3f);
        mm_feet_update(&f, &d, &b.rig, &heel, &(mm_feet_ground){0.0f, true, NULL}, dt, &b.pose);
        assert_true(f.heel_locked[0]);
        short_of[coming] = P.z + 0.3f - f.heel_lock[0].z;
        float y = (float)mm_spring_damping(coming ? 0.08f : d.foot_halflife);
        assert_true(fastest <= 0.3f * y * dt * expf(-1.0f) + 1e-4f);
    }
    float y = (float)mm_spring_damping(0.15f), T = 9.0f / 60.0f;
    assert_float_equal(short_of[0], 0.3f * (1.0f + y * T) * expf(-y * T), 2e-3f);
    assert_true(short_of[1] > 0.0f && short_of[1] < 0.6f * short_of[0]);
}

/* A foot let go keeps its velocity: the left heel held at P while the body stands, the body moving
 * at v along +Z from the tick before the label turns off (its ankle at P on that tick). The ankle's
 * target then follows the animation plus an offset that starts at 0 with velocity -v (what the foot
 * had less what it follows) and decays on a critically damped spring: x(t) = -v t e^(-y t), y the
 * damping of foot_halflife, so p(n) = P + v n dt (1 - e^(-y n dt)). Its largest second difference,
 * 2 v dt (e^(-y dt) - e^(-2 y dt)) = 0.37 v dt, is where a jump to the animation's velocity gave v dt.
 * On the ground plane: the foot also rises as it catches up (test_feet_released_foot_steps). */
static void test_feet_release_keeps_velocity(void **state)
{
    (void)state;
    mm_feet f;
    mm_character_desc d = feet_fixture(&f, 0.0f, false);
    float dt = 1.0f / 60.0f, v = 1.0f, y = (float)mm_spring_damping(d.foot_halflife);
    body b;
    for (int k = 0; k < 5; ++k) {
        body_at(&b, 0.0f);
        level_tick(&f, &d, &b, &LABEL_LEFT_HEEL, dt);
    }
    mm_vec3 P = f.heel_lock[0];
    body_at(&b, -v * dt); /* still held, the animation one step behind */
    level_tick(&f, &d, &b, &LABEL_LEFT_HEEL, dt);
    mm_vec3 last[3] = {P, P, P};
    float worst = 0.0f;
    for (int n = 0; n <= 20; ++n) {
        body_at(&b, v * (float)n * dt);
        level_tick(&f, &d, &b, &LABEL_NONE, dt);
        float t = (float)n * dt;
        mm_vec3 expected = mm_vec3_add(P, mm_vec3_make(0, 0, v * t * (1.0f - expf(-y * t))));
        mm_vec3 flat = mm_vec3_make(f.lock[0].x, P.y, f.lock[0].z); /* the step's lift aside */
        assert_vec3_near(flat, expected, 1e-4f);
        last[0] = last[1], last[1] = last[2], last[2] = flat;
        worst = fmaxf(worst, second_difference(last[0], last[1], last[2]));
    }
    assert_false(f.locked[0]);
    float bound = 2.0f * v * dt * (expf(-y * dt) - expf(-2.0f * y * dt));
    assert_float_equal(worst, bound, 2e-4f);
    assert_true(worst < 0.4f * v * dt);
}

/* A lock pulled further than unlock_radius on the tick its label turns off is let go as any other,
 * after that tick's creep (a spring step from rest toward the animation, scaled by how far past the
 * radius it is over feet.c's UNLOCK_RAMP, 5 cm): the ankle keeps its place and its velocity (0,
 * held), and its offset (x0 = P' - a, the animated ankle a moving at v, velocity -v) decays on the
 * spring of foot_halflife: p(t) = a(t) + (x0 + (-v + y x0) t) e^(-y t). Starting it from rest
 * instead would start the foot at v at once. */
static void test_feet_far_release_keeps_velocity(void **state)
{
    (void)state;
    mm_feet f;
    mm_character_desc d = feet_fixture(&f, 0.0f, false);
    d.unlock_radius = 0.095f;
    float dt = 1.0f / 60.0f, v = 1.0f, y = (float)mm_spring_damping(d.foot_halflife), ramp = 0.05f;
    body b;
    body_at(&b, 0.0f);
    level_tick(&f, &d, &b, &LABEL_LEFT_HEEL, dt);
    mm_vec3 P = f.heel_lock[0];
    int n = 0;
    mm_vec3 last[3] = {P, P, P};
    float worst = 0.0f;
    /* held while the body walks off at v; the label goes off on the first tick past unlock_radius */
    for (n = 1; (float)n * v * dt <= d.unlock_radius; ++n) {
        body_at(&b, v * (float)n * dt);
        level_tick(&f, &d, &b, &LABEL_LEFT_HEEL, dt);
        assert_true(f.heel_locked[0]);
        assert_vec3_near(f.heel_lock[0], P, 1e-6f); /* within the radius: no creep */
        last[0] = last[1], last[1] = last[2], last[2] = f.lock[0];
    }
    float gap = v * (float)n * dt, step = 1.0f - (1.0f + y * dt) * expf(-y * dt);
    float crept = fminf((gap - d.unlock_radius) / ramp, 1.0f) * step * gap;
    float x0 = crept - gap;
    for (int i = 0; i <= 20; ++i, ++n) {
        body_at(&b, v * (float)n * dt);
        level_tick(&f, &d, &b, &LABEL_NONE, dt);
        assert_false(f.locked[0]);
        float t = (float)i * dt, x = (x0 + (-v + y * x0) * t) * expf(-y * t);
        mm_vec3 flat = mm_vec3_make(f.lock[0].x, P.y, f.lock[0].z); /* the step's lift aside */
        assert_vec3_near(flat, mm_vec3_add(P, mm_vec3_make(0, 0, v * (float)n * dt + x)), 1e-4f);
        last[0] = last[1], last[1] = last[2], last[2] = flat;
        worst = fmaxf(worst, second_difference(last[0], last[1], last[2]));
    }
    assert_true(worst < 0.6f * v * dt);
}

/* A lock let go while the animated ankle is above it (the body rose 8 cm over the stance, the
 * locked ankle held on the ground by the leg's IK): the foot comes up to the animation on the
 * spring of feet.c's LIFT_HALFLIFE (0.05 s), not foot_halflife's 0.15 s: its height's offset
 * -h decays as -h (1 + y t) e^(-y t) from the tick after the release, and the foot stays over
 * where it was held (x, z) since the animation does not move along the ground. */
static void test_feet_release_lifts_off_as_animated(void **state)
{
    (void)state;
    mm_feet f;
    mm_character_desc d = feet_fixture(&f, 0.0f, true);
    float dt = 1.0f / 60.0f, lift = 0.08f, y = (float)mm_spring_damping(0.05f);
    body b;
    for (int n = 0; n <= 30; ++n) { /* planted, then the body rises by lift while it is held */
        bent_left_leg(&b, 0.6f, 0.0f, lift * (float)n / 30.0f);
        level_tick(&f, &d, &b, &LABEL_LEFT_HEEL, dt);
    }
    for (int n = 0; n < 30; ++n) {
        bent_left_leg(&b, 0.6f, 0.0f, lift);
        level_tick(&f, &d, &b, &LABEL_LEFT_HEEL, dt);
    }
    mm_vec3 held = f.heel_lock[0], animated = b.global[L_FOOT].translation;
    assert_float_equal(held.y, 0.06f, 1e-4f);
    assert_vec3_near(b.global[L_FOOT].translation, held, 1e-3f); /* the IK reaches it */
    bent_left_leg(&b, 0.6f, 0.0f, lift);
    level_tick(&f, &d, &b, &LABEL_NONE, dt);
    assert_false(f.locked[0]);
    animated = mm_vec3_make(held.x, held.y + lift, held.z);
    for (int i = 1; i <= 12; ++i) {
        bent_left_leg(&b, 0.6f, 0.0f, lift);
        level_tick(&f, &d, &b, &LABEL_NONE, dt);
        float t = (float)i * dt, below = -lift * (1.0f + y * t) * expf(-y * t);
        assert_vec3_near(f.lock[0], mm_vec3_add(animated, mm_vec3_make(0, below, 0)), 1e-4f);
    }
    assert_true(animated.y - f.lock[0].y < 0.005f); /* at foot_halflife, still 3.6 cm below */
}

/* A lock the animation pulls past unlock_radius creeps after it continuously: each tick it moves
 * by a spring step from rest toward the animated ankle times min((gap - radius) / UNLOCK_RAMP, 1)
 * (feet.c, 5 cm): nothing at the radius, so two characters whose bodies differ by a rounding
 * error move their locks by as little. */
static void test_feet_lock_creeps_after_the_animation(void **state)
{
    (void)state;
    mm_feet f;
    mm_character_desc d = feet_fixture(&f, 0.0f, false);
    float dt = 1.0f / 60.0f, y = (float)mm_spring_damping(d.foot_halflife), ramp = 0.05f;
    float step = 1.0f - (1.0f + y * dt) * expf(-y * dt);
    float past[4] = {-1e-4f, 1e-4f, 0.02f, 0.1f};
    for (int i = 0; i < 4; ++i) {
        memset(&f, 0, sizeof f);
        body b;
        body_at(&b, 0.0f);
        level_tick(&f, &d, &b, &LABEL_LEFT_HEEL, dt);
        mm_vec3 P = f.heel_lock[0];
        float gap = d.unlock_radius + past[i];
        body_at(&b, gap);
        level_tick(&f, &d, &b, &LABEL_LEFT_HEEL, dt);
        assert_true(f.heel_locked[0]);
        float share = past[i] > 0.0f ? fminf(past[i] / ramp, 1.0f) * step : 0.0f;
        assert_float_equal(f.heel_lock[0].z - P.z, share * gap, 1e-6f);
    }
}

/* A foot held 8 cm above the animated one by its offset (a transition's, or a released lock's) when
 * its label turns on: the lock goes where the animated foot is and the offset carries the height,
 * fading (no drop in a tick; the ankle's target moves by less than 1 cm of second difference), and
 * the foot comes down onto the animated one. */
static void test_feet_plant_above_the_animated_foot(void **state)
{
    (void)state;
    mm_feet f;
    mm_character_desc d = feet_fixture(&f, 0.0f, true);
    float dt = 1.0f / 60.0f;
    body b;
    bent_left_leg(&b, 0.3f, 0.0f, 0.0f);
    level_tick(&f, &d, &b, &LABEL_NONE, dt);
    f.offset[0] = mm_vec3_make(0, 0.08f, 0), f.offset_velocity[0] = mm_vec3_make(0, 0, 0);
    mm_vec3 last[3] = {f.lock[0], f.lock[0], f.lock[0]};
    float worst = 0.0f;
    for (int n = 0; n < 60; ++n) {
        bent_left_leg(&b, 0.3f, 0.0f, 0.0f);
        level_tick(&f, &d, &b, n < 3 ? &LABEL_NONE : &LABEL_LEFT_HEEL, dt);
        last[0] = last[1], last[1] = last[2], last[2] = f.lock[0];
        if (n >= 2) worst = fmaxf(worst, second_difference(last[0], last[1], last[2]));
        if (n == 3) assert_float_equal(f.heel_lock[0].y, 0.06f, 1e-4f);
    }
    assert_true(f.heel_locked[0]);
    assert_true(worst < 0.01f);
    assert_float_equal(b.global[L_FOOT].translation.y, 0.06f, 1e-3f);
}

/* A free foot carried over the ground is kept clear of it for its speed (swing_clear, feet.c): the
 * left foot animated on the ground (its ankle at its planted 6 cm) moving at v with no label. From
 * the second tick its target's speed asks for W = 0.02 s (v - 0.5 m/s), at most 4 cm, followed by a
 * critically damped spring of half-life 0.05 s from rest: c(t) = W (1 - (1 + y t) e^(-y t)); the
 * ankle is held c above where it stands once c is past TOE_SINK (1 cm; eased in below it). At 0.4
 * m/s nothing; at 1.5 m/s 2 cm; at 4 m/s the 4 cm most; with its contact 0.075 s away (half of
 * SWING_CLEAR_LAND) half of 2 cm. Before, such a foot skimmed the ground at its planted height. Then
 * a contact seen 3 ticks ahead (plant_time 2 ticks): none is asked for, and the clearance comes down
 * through its spring from rest, W (1 + y t) e^(-y t), through the tick the foot is planted; handed
 * to the offset there, it fades on from there (foot_halflife): no vertical second difference over
 * the spring's own largest, W (y dt)^2 (taken down with the landing's share, the foot came down 1.4
 * cm in the tick before it was planted), and the foot ends on its lock. */
static void test_feet_swing_clears_the_ground(void **state)
{
    (void)state;
    const float speeds[4] = {0.4f, 1.5f, 4.0f, 1.5f}, wants[4] = {0.0f, 0.02f, 0.04f, 0.01f};
    float dt = 1.0f / 60.0f, y = (float)mm_spring_damping(0.05f);
    for (int c = 0; c < 4; ++c) {
        mm_feet f;
        mm_character_desc d = feet_fixture(&f, 2.0f * dt, false);
        float v = speeds[c], W = wants[c], z = 0.0f;
        mm_feet_contacts free = {0, {-1.0f, -1.0f}, {c == 3 ? 0.075f : -1.0f, -1.0f}};
        body b;
        float ground = 0.0f;
        for (int n = 0; n <= 60; ++n, z += v * dt) {
            body_at(&b, z);
            on_the_ground(&b);
            level_tick(&f, &d, &b, &free, dt);
            if (n == 0) ground = f.lock[0].y;
            float h = f.lock[0].y - ground, t = (float)(n - 1) * dt;
            assert_true(h >= -1e-6f && h <= W + 1e-5f);
            float expected = n >= 2 ? W * (1.0f - (1.0f + y * t) * expf(-y * t)) : 0.0f;
            if (expected >= 0.01f) assert_float_equal(h, expected, 1e-4f);
        }
        assert_float_equal(ground, 0.06f, 1e-5f);
        assert_float_equal(f.lock[0].y - ground, W, 1e-4f);
        if (c != 1) continue;
        float h[64] = {W, W}, worst = 0.0f;
        for (int n = 0; n < 62; ++n, z += v * dt) { /* coming in 3, 2, 1 ticks, then on */
            mm_feet_contacts coming = {0, {(float)(3 - n) * dt, -1.0f}, {(float)(3 - n) * dt, -1.0f}};
            body_at(&b, z);
            on_the_ground(&b);
            level_tick(&f, &d, &b, n < 3 ? &coming : &LABEL_LEFT_HEEL, dt);
            h[n + 2] = f.lock[0].y - ground;
            float t = (float)(n + 1) * dt, expected = W * (1.0f + y * t) * expf(-y * t);
            if (n <= 3 && expected >= 0.01f) assert_float_equal(h[n + 2], expected, 1e-4f);
            worst = fmaxf(worst, fabsf(h[n + 2] - 2.0f * h[n + 1] + h[n]));
            if (n == 3) assert_true(f.heel_locked[0]);
        }
        assert_true(worst <= W * y * dt * y * dt); /* the spring's own largest, at its start */
        assert_float_equal(f.heel_lock[0].y, ground, 1e-6f);
        assert_true(h[63] < 1e-4f); /* down on the lock once the offset has faded */
    }
}

/* a and b the same on the ground plane, to within tolerance */
static void assert_across_near(mm_vec3 a, mm_vec3 b, float tolerance)
{
    assert_float_equal(a.x, b.x, tolerance);
    assert_float_equal(a.z, b.z, tolerance);
}

/* A fast foot (8 m/s on the ground plane: a transition's offsets carrying a swing) whose label comes
 * on without warning lands evenly, its step shrinking by the same amount each tick, at most feet.c's
 * LANDING_DECELERATION (150 m/s^2) times dt^2 (20% more: the offset's spring pulls the foot on as it
 * lags the body), over ceil(v / (150 dt)) ticks instead of plant_time's two, where its step would
 * halve and then stop (second differences of v dt / 2, 6.7 cm). Foreseen, it lands as slowly before
 * its label. */
static void test_feet_fast_landing(void **state)
{
    (void)state;
    float dt = 1.0f / 60.0f, v = 8.0f, deceleration = 150.0f;
    mm_feet f;
    mm_character_desc d = feet_fixture(&f, 2.0f * dt, false);
    body b;
    mm_vec3 p[16];
    int landed_at = -1, ticks = (int)ceilf(v / (deceleration * dt));
    for (int n = 0; n < 16; ++n) { /* free on ticks 0 to 4, the label on from tick 5 */
        body_at(&b, v * (float)n * dt);
        on_the_ground(&b);
        level_tick(&f, &d, &b, n < 5 ? &LABEL_NONE : &LABEL_LEFT_HEEL, dt);
        p[n] = f.lock[0];
        if (f.heel_locked[0] && landed_at < 0) landed_at = n;
        if (n >= 2) assert_true(second_difference(p[n - 2], p[n - 1], p[n]) < 1.2f * deceleration * dt * dt);
    }
    /* planted on the tick its share reaches 1, where the landing's last step left it */
    assert_int_equal(landed_at, 4 + ticks);
    assert_across_near(p[landed_at], p[landed_at - 1], 1e-6f);
    /* and every step of the landing shorter than the one before */
    for (int n = 5; n < landed_at; ++n) assert_true(p[n].z - p[n - 1].z < p[n - 1].z - p[n - 2].z);
    /* foreseen (the label's coming seen up to MM_FEET_LANDING_MAX_TIME ahead), the landing runs
     * before the label: planted on the label's tick, as slowly */
    memset(&f, 0, sizeof f);
    landed_at = -1;
    for (int n = 0; n < 8; ++n) {
        float left = (float)(5 - n) * dt;
        mm_feet_contacts coming = {
            0, {left <= MM_FEET_LANDING_MAX_TIME ? left : -1.0f, -1.0f}, {-1.0f, -1.0f}};
        body_at(&b, v * (float)n * dt);
        on_the_ground(&b);
        level_tick(&f, &d, &b, n < 5 ? &coming : &LABEL_LEFT_HEEL, dt);
        p[n] = f.lock[0];
        if (f.heel_locked[0] && landed_at < 0) landed_at = n;
        if (n >= 2) assert_true(second_difference(p[n - 2], p[n - 1], p[n]) < 1.2f * deceleration * dt * dt);
    }
    assert_int_equal(landed_at, 5);
}

/* A foot held on its toe, pitched toe-up as animated so that its toe floats above its lock (the ankle
 * kept at its planted height), then planted on its heel too: the foot turns down onto the toe's lock
 * over the turn's fading offset (foot_halflife), not in the one tick (the toe's second difference
 * stays under 1 cm), and ends with the toe on its lock (to the toe's soft floor). */
static void test_feet_heel_planted_under_a_held_toe(void **state)
{
    (void)state;
    mm_feet f;
    mm_character_desc d = feet_fixture(&f, 0.0f, true);
    float dt = 1.0f / 60.0f;
    body b;
    mm_vec3 last[3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    float worst = 0.0f, floated = 0.0f;
    for (int n = 0; n < 90; ++n) {
        float pitch = -0.4f * fminf((float)n / 20.0f, 1.0f); /* toe up, over a third of a second */
        bent_left_leg(&b, 0.3f, pitch, 0.0f);
        level_tick(&f, &d, &b, n < 30 ? &LABEL_LEFT_TOE : &LABEL_LEFT_HEEL_TOE, dt);
        if (n == 29) floated = b.global[L_TOE].translation.y - f.toe_lock[0].y;
        last[0] = last[1], last[1] = last[2], last[2] = b.global[L_TOE].translation;
        if (n >= 2) worst = fmaxf(worst, second_difference(last[0], last[1], last[2]));
    }
    assert_true(f.heel_locked[0] && f.toe_locked[0]);
    assert_true(floated > 0.02f); /* what the heel's plant had to bring down */
    assert_true(worst < 0.01f);
    assert_vec3_near(b.global[L_TOE].translation, f.toe_lock[0], 0.01f); /* TOE_SINK's soft floor */
}

/* A contact that comes without warning (the label on where it was not foreseen: a jump onto a frame
 * whose label is on) is waited for over plant_time: with plant_time two ticks, a foot moving at v
 * steps v dt / 2 on the tick its label turns on and is planted, at rest, on the next, where it is:
 * second differences of v dt / 2, where planting at once stopped it dead (v dt). A contact that was
 * foreseen (within plant_time the tick before) has slowed already and is planted on its tick. */
static void test_feet_land_without_warning(void **state)
{
    (void)state;
    float dt = 1.0f / 60.0f, v = 1.2f;
    mm_feet f;
    mm_character_desc d = feet_fixture(&f, 2.0f * dt, false);
    body b;
    mm_vec3 p[16];
    for (int n = 0; n < 8; ++n) { /* free on ticks 0 to 4, the label on from tick 5 */
        body_at(&b, v * (float)n * dt);
        on_the_ground(&b);
        level_tick(&f, &d, &b, n < 5 ? &LABEL_NONE : &LABEL_LEFT_HEEL, dt);
        p[n] = f.lock[0];
        if (n == 5) assert_false(f.locked[0]); /* waited for */
        if (n == 6) assert_true(f.heel_locked[0]);
    }
    assert_float_equal(p[4].z - p[3].z, v * dt, 1e-5f);
    assert_float_equal(p[5].z - p[4].z, 0.5f * v * dt, 1e-5f);
    assert_float_equal(p[6].z - p[5].z, 0.0f, 1e-5f);
    assert_across_near(f.heel_lock[0], p[6], 1e-6f);
    assert_across_near(p[7], p[6], 1e-6f);
    /* on the ground plane; upward, the clearance its speed kept it at (swing_clear in feet.c,
     * SWING_CLEAR_TIME (v - SWING_CLEAR_FROM) = W = 1.4 cm asked for, 5 mm reached through its
     * spring by then) is followed on through the landing (asked for no more) and, planted, carried
     * by the offset: no tick's vertical second difference is more than the clearance spring's own
     * largest, W (y dt)^2 (y its damping: a critically damped spring let go at W from rest),
     * where dropping it in the label's tick reversed the rise at once */
    float W = 0.02f * (v - 0.5f), y = (float)mm_spring_damping(0.05f);
    float h = p[4].y - p[0].y, up[16];
    assert_true(h > 0.0f && h < W);
    for (int n = 2; n < 8; ++n) {
        mm_vec3 a = {p[n - 2].x, 0, p[n - 2].z}, c = {p[n - 1].x, 0, p[n - 1].z}, e = {p[n].x, 0, p[n].z};
        assert_true(second_difference(a, c, e) < 0.5f * v * dt + 1e-5f);
    }
    for (int n = 8; n < 16; ++n) { /* planted: the height it was held at comes down */
        body_at(&b, v * (float)n * dt);
        on_the_ground(&b);
        level_tick(&f, &d, &b, &LABEL_LEFT_HEEL, dt);
        p[n] = f.lock[0];
    }
    for (int n = 0; n < 16; ++n) up[n] = p[n].y - p[0].y;
    for (int n = 2; n < 16; ++n) {
        assert_true(up[n] >= -1e-6f && up[n] <= W);
        assert_true(fabsf(up[n] - 2.0f * up[n - 1] + up[n - 2]) <= W * y * dt * y * dt);
    }
    assert_true(up[15] < 0.5f * h);
    /* foreseen: the tick before the label, its step halves; on the label's tick it is planted */
    memset(&f, 0, sizeof f);
    mm_feet_contacts coming = {0, {dt, -1.0f}, {-1.0f, -1.0f}};
    for (int n = 0; n < 7; ++n) {
        body_at(&b, v * (float)n * dt);
        on_the_ground(&b);
        level_tick(&f, &d, &b, n < 4 ? &LABEL_NONE : n == 4 ? &coming : &LABEL_LEFT_HEEL, dt);
        p[n] = f.lock[0];
    }
    assert_float_equal(p[4].z - p[3].z, 0.5f * v * dt, 1e-5f);
    assert_float_equal(p[5].z - p[4].z, 0.0f, 1e-5f);
    assert_across_near(f.heel_lock[0], p[5], 1e-6f);
}

/* The hips come down through a spring (half-life feet.c's HIP_DROP_HALFLIFE, 0.05 s), not at once:
 * standing with straight legs, the ankles planted where they are asks for a drop of D = 0.84 m -
 * 0.95 x 0.84 m (the reach the IK keeps, SOFT_REACH short of the leg), which the pelvis takes as a
 * critically damped spring from rest does: D (1 - (1 + y t) e^(-y t)). Its largest second
 * difference is on the first tick, D (1 - (1 + y dt) e^(-y dt)) = 0.11 D, where at once it was D. */
static void test_feet_hips_come_down_smoothly(void **state)
{
    (void)state;
    mm_feet f;
    mm_character_desc d = feet_fixture(&f, 0.0f, false);
    float dt = 1.0f / 60.0f, D = 0.84f - 0.95f * 0.84f, y = (float)mm_spring_damping(0.05f);
    mm_feet_contacts both = {MM_CONTACT_LEFT_HEEL | MM_CONTACT_RIGHT_HEEL, {-1.0f, -1.0f}, {-1.0f, -1.0f}};
    body b;
    mm_vec3 p[3] = {{0, 0.9f, 0}, {0, 0.9f, 0}, {0, 0.9f, 0}};
    float worst = 0.0f;
    for (int n = 1; n <= 30; ++n) {
        make_body(&b);
        level_tick(&f, &d, &b, &both, dt);
        float t = (float)n * dt;
        assert_float_equal(f.hip_drop, D * (1.0f - (1.0f + y * t) * expf(-y * t)), 1e-4f);
        p[0] = p[1], p[1] = p[2], p[2] = b.global[HIPS].translation;
        worst = fmaxf(worst, second_difference(p[0], p[1], p[2]));
    }
    assert_float_equal(worst, D * (1.0f - (1.0f + y * dt) * expf(-y * dt)), 1e-4f);
    assert_float_equal(f.hip_drop, D, 1e-3f);
}

/* The body leans back over a planted foot the root goes on from, as far as a third of a leg: the
 * left heel planted at (0.1, 0.06, 0), the hips 0.7 m up (no hip drop) then carried 0.75 m ahead at
 * 1.5 m/s and held there. The leg (0.84 m, softening from R = 0.95 x 0.84 m) needs the pelvis back
 * by 0.75 - sqrt(R^2 - 0.64^2) = 0.27 m to reach; the first-order move (L - R) L / 0.75 = 0.247 m
 * (L = |(0.64, 0.75)|) is within the most (0.35 x 0.84 = 0.294 m): the lock creeps only while
 * the pelvis's spring lags the hips (under 1 cm), and the ankle ends within 5 mm of it. With the
 * pelvis moved at most 0.12 m the lock crept 7.5 cm after the animation and the ankle was left 2 cm
 * short of it (REACH_SLACK). */
static void test_feet_pelvis_leans_back_over_a_planted_foot(void **state)
{
    (void)state;
    mm_feet f;
    mm_character_desc d = feet_fixture(&f, 0.0f, true);
    d.unlock_radius = 2.0f;
    float dt = 1.0f / 60.0f, reach = 0.95f * 0.84f, L = sqrtf(0.64f * 0.64f + 0.75f * 0.75f);
    float move = (L - reach) * L / 0.75f;
    body b;
    make_body(&b);
    on_the_ground(&b);
    level_tick(&f, &d, &b, &LABEL_LEFT_HEEL, dt);
    mm_vec3 planted = f.heel_lock[0];
    for (int n = 1; n <= 120; ++n) {
        make_body(&b);
        on_the_ground(&b);
        b.positions[HIPS] = mm_vec3_make(0.0f, 0.7f, fminf(1.5f * dt * (float)n, 0.75f));
        mm_rig_forward(&b.rig, 1, &b.pose);
        level_tick(&f, &d, &b, &LABEL_LEFT_HEEL, dt);
    }
    assert_float_equal(f.pelvis_shift.z, -move, 0.01f);
    assert_true(mm_vec3_distance(f.heel_lock[0], planted) < 0.01f);
    assert_true(mm_vec3_distance(b.global[L_FOOT].translation, f.heel_lock[0]) < 0.005f);
}

/* A planted foot the hips are carried away from is kept in reach by moving the pelvis toward it on
 * the ground plane (in the pose only): the left heel planted at (0.1, 0.06, 0), then the hips held
 * 0.2 m lower (0.7 m, straight legs of 0.84 m) and moved 0.55 m forward. The leg reaches
 * R = 0.95 x 0.84 m before the IK softens; the hip is L = |(0.64, 0.55)| from the lock, and the
 * pelvis comes back by the first-order move that shortens the leg by L - R: (L - R) L / 0.55 (the
 * ankle then within a millimetre of its lock, where 0.55 - sqrt(R^2 - 0.64^2) = 7.3 cm short without
 * it). Hips 1 m ahead: at most 0.35 leg lengths (feet.c's MAX_PELVIS_SHIFT_LEGS: 0.294 m); with
 * the label off, or the ground not held, back to none. */
static void test_feet_pelvis_shifts_toward_a_planted_foot(void **state)
{
    (void)state;
    mm_feet f;
    mm_character_desc d = feet_fixture(&f, 0.0f, true);
    d.unlock_radius = 2.0f; /* the lock holds */
    float dt = 1.0f / 60.0f, reach = 0.95f * 0.84f, down = 0.7f - 0.06f;
    float L = sqrtf(down * down + 0.55f * 0.55f), move = (L - reach) * L / 0.55f;
    body b;
    make_body(&b);
    on_the_ground(&b);
    level_tick(&f, &d, &b, &LABEL_LEFT_HEEL, dt);
    assert_vec3_near(f.heel_lock[0], mm_vec3_make(0.1f, 0.06f, 0.0f), 1e-5f);
    assert_float_equal(mm_vec3_length(f.pelvis_shift), 0.0f, 1e-6f); /* in reach: no shift */
    mm_vec3 p[3] = {f.pelvis_shift, f.pelvis_shift, f.pelvis_shift};
    float worst = 0.0f;
    for (int n = 0; n < 120; ++n) {
        make_body(&b);
        on_the_ground(&b);
        b.positions[HIPS] = mm_vec3_make(0.0f, 0.7f, 0.55f);
        mm_rig_forward(&b.rig, 1, &b.pose);
        level_tick(&f, &d, &b, &LABEL_LEFT_HEEL, dt);
        p[0] = p[1], p[1] = p[2], p[2] = f.pelvis_shift;
        worst = fmaxf(worst, second_difference(p[0], p[1], p[2]));
    }
    assert_vec3_near(f.pelvis_shift, mm_vec3_make(0.0f, 0.0f, -move), 1e-4f);
    assert_vec3_near(b.global[HIPS].translation, mm_vec3_make(0.0f, 0.7f, 0.55f - move), 1e-4f);
    assert_vec3_near(b.global[L_FOOT].translation, f.heel_lock[0], 1e-3f);
    /* through a critically damped spring (half-life 0.05 s) from rest: no second difference larger
     * than its first step toward where it goes */
    float y = (float)mm_spring_damping(0.05f);
    assert_true(worst > 0.0f && worst <= move * (1.0f - (1.0f + y * dt) * expf(-y * dt)) + 1e-6f);
    /* further than the most it moves: MAX_PELVIS_SHIFT_LEGS toward the lock */
    for (int n = 0; n < 120; ++n) {
        make_body(&b);
        on_the_ground(&b);
        b.positions[HIPS] = mm_vec3_make(0.0f, 0.7f, 1.0f);
        mm_rig_forward(&b.rig, 1, &b.pose);
        level_tick(&f, &d, &b, &LABEL_LEFT_HEEL, dt);
    }
    assert_vec3_near(f.pelvis_shift, mm_vec3_make(0.0f, 0.0f, -0.35f * 0.84f), 1e-4f);
    /* the label off: back to none */
    for (int n = 0; n < 120; ++n) {
        make_body(&b);
        on_the_ground(&b);
        b.positions[HIPS] = mm_vec3_make(0.0f, 0.7f, 0.8f);
        mm_rig_forward(&b.rig, 1, &b.pose);
        level_tick(&f, &d, &b, &LABEL_NONE, dt);
    }
    assert_float_equal(mm_vec3_length(f.pelvis_shift), 0.0f, 1e-4f);
    assert_vec3_near(b.global[HIPS].translation, mm_vec3_make(0.0f, 0.7f, 0.8f), 1e-4f);
    /* planted again, but the ground not held (a move): none */
    for (int n = 0; n < 120; ++n) {
        make_body(&b);
        on_the_ground(&b);
        b.positions[HIPS] = mm_vec3_make(0.0f, 0.7f, 0.8f);
        mm_rig_forward(&b.rig, 1, &b.pose);
        mm_feet_update(&f, &d, &b.rig, &LABEL_LEFT_HEEL, &(mm_feet_ground){0.0f, false, NULL}, dt, &b.pose);
    }
    assert_float_equal(mm_vec3_length(f.pelvis_shift), 0.0f, 1e-4f);
}

/* A lock its leg cannot reach, even with the pelvis moved its most, creeps after the animation
 * however far inside unlock_radius the animated foot is: the left heel planted at (0.1, 0.06, 0),
 * the hips then 0.7 m up and 1 m ahead (0.64 m above the lock, straight legs of 0.84 m). The lock
 * comes forward until the leg leaves its ankle at most feet.c's REACH_SLACK (2 cm) short, and stays
 * planted there (far short of the animated ankle 1 m ahead). */
static void test_feet_unreachable_lock_creeps(void **state)
{
    (void)state;
    mm_feet f;
    mm_character_desc d = feet_fixture(&f, 0.0f, true);
    d.unlock_radius = 2.0f; /* the animation's pull alone would never move it */
    float dt = 1.0f / 60.0f;
    body b;
    make_body(&b);
    on_the_ground(&b);
    level_tick(&f, &d, &b, &LABEL_LEFT_HEEL, dt);
    float z[2] = {0.0f, 0.0f};
    for (int n = 0; n < 600; ++n) {
        make_body(&b);
        on_the_ground(&b);
        b.positions[HIPS] = mm_vec3_make(0.0f, 0.7f, 1.0f);
        mm_rig_forward(&b.rig, 1, &b.pose);
        level_tick(&f, &d, &b, &LABEL_LEFT_HEEL, dt);
        assert_true(f.heel_locked[0]);
        z[n % 2] = f.heel_lock[0].z;
    }
    assert_true(f.reach_miss[0] <= 0.02f + 1e-4f);
    assert_float_equal(z[0], z[1], 1e-6f); /* at rest */
    /* come up to where the straight leg from the hip (the pelvis moved back its most, 0.35 x 0.84
     * = 0.294 m, to 0.706 m ahead) reaches it, give or take the slack: 0.84 to 0.86 m from the hip */
    assert_float_equal(f.pelvis_shift.z, -0.35f * 0.84f, 1e-4f);
    float near = 0.706f - sqrtf(0.84f * 0.84f - 0.64f * 0.64f),
          far = 0.706f - sqrtf(0.86f * 0.86f - 0.64f * 0.64f);
    assert_true(f.heel_lock[0].z >= far - 1e-3f && f.heel_lock[0].z <= near + 1e-3f);
    assert_vec3_near(b.global[L_FOOT].translation, f.lock[0], 0.02f + 1e-4f);
}

/* A free foot pitched toe down is raised by its ankle so that the toe stays at most 1 cm (feet.c's
 * TOE_SINK) below its planted height (0 on this rig), smoothly: with the toe h below the ankle and the
 * ankle at y, it is at y from h on, at h - 1 cm from h - 2 cm down, and on the parabola h - 1 cm +
 * (y - h + 2 cm)^2 / 4 cm between. A target far out of a free leg's reach is brought in to its length
 * and three widths of the IK's softening (1.15 x 0.84 m), not onto the length. */
static void test_feet_toe_floor_and_far_targets(void **state)
{
    (void)state;
    mm_feet f;
    mm_character_desc d = feet_fixture(&f, 0.0f, false);
    d.max_hip_drop = MM_OFF;
    float dt = 1.0f / 60.0f, h = 0.04f, s = 0.01f;
    float heights[] = {0.06f, h, h - 0.005f, h - s, h - 0.015f, h - 2.0f * s, 0.0f};
    for (int i = 0; i < (int)(sizeof heights / sizeof heights[0]); ++i) {
        memset(&f, 0, sizeof f);
        body b;
        for (int tick = 0; tick < 2; ++tick) { /* a ground far below, then at 0 */
            make_body(&b);
            b.positions[HIPS].y = 0.9f - (0.06f - heights[i]); /* the body lowered: ankle at heights[i] */
            mm_rig_forward(&b.rig, 1, &b.pose);
            mm_feet_update(&f, &d, &b.rig, &LABEL_NONE, &(mm_feet_ground){tick ? 0.0f : -1.0f, true, NULL},
                           dt, &b.pose);
        }
        float yy = heights[i], expected = yy;
        if (yy < h - 2.0f * s)
            expected = h - s;
        else if (yy < h)
            expected = h - s + (yy - h + 2.0f * s) * (yy - h + 2.0f * s) / (4.0f * s);
        assert_float_equal(f.lock[0].y, expected, 1e-5f);
    }
    /* far out of reach, free: in to 1.15 of the leg's length from the hip, along the same line */
    memset(&f, 0, sizeof f);
    body b;
    make_body(&b);
    mm_feet_update(&f, &d, &b.rig, &LABEL_NONE, &(mm_feet_ground){-1.0f, false, NULL}, dt, &b.pose);
    f.offset[0] = mm_vec3_make(0, 0, 1.5f);
    f.offset_velocity[0] = mm_vec3_make(0, 0, 0);
    make_body(&b);
    mm_feet_update(&f, &d, &b.rig, &LABEL_NONE, &(mm_feet_ground){-1.0f, false, NULL}, dt, &b.pose);
    /* the offset decayed one step from rest first: 1.5 (1 + y dt) e^(-y dt), its velocity changed by
     * at most feet.c's SWING_ACCELERATION (150 m/s^2) dt, evenly over the tick (the spring's first
     * step asks for a little more here: 2.6 m/s) */
    float y = (float)mm_spring_damping(d.foot_halflife), z = 1.5f * (1.0f + y * dt) * expf(-y * dt);
    z = fmaxf(z, 1.5f - 0.5f * 150.0f * dt * dt);
    mm_vec3 hip = mm_vec3_make(0.1f, 0.9f, 0.0f), along = mm_vec3_make(0.0f, -0.84f, z);
    assert_vec3_near(f.lock[0], mm_vec3_add(hip, mm_vec3_scale(along, 1.15f * 0.84f / mm_vec3_length(along))),
                     1e-4f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rig_finds_legs_pelvis_and_spine),
        cmocka_unit_test(test_rig_deferred_body),
        cmocka_unit_test(test_intent_from_input),
        cmocka_unit_test(test_playback_advance_by_clock_and_rate),
        cmocka_unit_test(test_playback_time_to_contact),
        cmocka_unit_test(test_playback_distance_matching_on_a_cycle),
        cmocka_unit_test(test_playback_rate_after_a_change_of_clip),
        cmocka_unit_test(test_matching_due),
        cmocka_unit_test(test_matching_pose_weighed_back_after_a_jump),
        cmocka_unit_test(test_transition_inertialize_keeps_pose_and_velocity),
        cmocka_unit_test(test_transition_inertialize_keeps_velocity_across_axes),
        cmocka_unit_test(test_transition_legs_fade_with_their_halflife),
        cmocka_unit_test(test_matching_stance_ends_after_its_reach),
        cmocka_unit_test(test_root_motion_pull_and_clamps),
        cmocka_unit_test(test_warping_stride_stretches_the_step),
        cmocka_unit_test(test_warping_orientation_turns_legs_not_chest),
        cmocka_unit_test(test_warping_orientation_eases_in_a_step),
        cmocka_unit_test(test_feet_lock_holds_and_releases),
        cmocka_unit_test(test_feet_release_keeps_velocity),
        cmocka_unit_test(test_feet_released_foot_steps),
        cmocka_unit_test(test_feet_swing_catches_up_before_contact),
        cmocka_unit_test(test_feet_far_release_keeps_velocity),
        cmocka_unit_test(test_feet_release_lifts_off_as_animated),
        cmocka_unit_test(test_feet_lock_creeps_after_the_animation),
        cmocka_unit_test(test_feet_plant_above_the_animated_foot),
        cmocka_unit_test(test_feet_land_without_warning),
        cmocka_unit_test(test_feet_swing_clears_the_ground),
        cmocka_unit_test(test_feet_fast_landing),
        cmocka_unit_test(test_feet_heel_planted_under_a_held_toe),
        cmocka_unit_test(test_feet_hips_come_down_smoothly),
        cmocka_unit_test(test_feet_pelvis_shifts_toward_a_planted_foot),
        cmocka_unit_test(test_feet_pelvis_leans_back_over_a_planted_foot),
        cmocka_unit_test(test_feet_unreachable_lock_creeps),
        cmocka_unit_test(test_feet_toe_floor_and_far_targets),
        cmocka_unit_test(test_feet_roll_onto_the_toe),
        cmocka_unit_test(test_feet_heel_lifts_where_shown),
        cmocka_unit_test(test_feet_lock_comes_down),
        cmocka_unit_test(test_feet_lock_begins_where_shown),
        cmocka_unit_test(test_feet_body_turns_over_a_planted_foot),
        cmocka_unit_test(test_feet_toe_aloft_keeps_its_heading),
        cmocka_unit_test(test_feet_lock_settles_gradually),
        cmocka_unit_test(test_feet_wait_aloft),
        cmocka_unit_test(test_feet_wait_aloft_on_terrain),
        cmocka_unit_test(test_feet_toe_down_under_raised_heel),
        cmocka_unit_test(test_feet_toe_planted_under_a_raised_ankle),
        cmocka_unit_test(test_feet_toe_pivot_out_of_reach),
        cmocka_unit_test(test_feet_heel_up_before_hips_down),
        cmocka_unit_test(test_feet_hips_no_lower_than_the_floor),
        cmocka_unit_test(test_feet_head_above_the_crouch_line),
        cmocka_unit_test(test_rig_head_above_pelvis),
        cmocka_unit_test(test_feet_swing_eases_out_of_a_far_release),
        cmocka_unit_test(test_feet_bend_eased_near_full_extension),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
