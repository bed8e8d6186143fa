/* Walls stop the character (mm_character_set_scene, mm/trajectory.h's collision) on the built-in
 * motion set: walking or running into a wall too high for any move, at 0 to 80 degrees from its
 * normal, no joint of the body goes more than 5 cm into it; walking diagonally into it, the root
 * slides along it; the predicted future stops at the wall before the character reaches it; a
 * scene whose walls are never touched predicts what the closed form does; and the capsule's
 * push-out (mm_scene_collide_capsule) against hand-computed cases. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <mm/character.h>
#include <mm/moves.h>
#include <mm/prediction.h>
#include <mm/scene.h>
#include <mm/trajectory.h>

#include "test_databases.h"
#include "test_util.h"

/* m: the deepest a joint of the body may go into a wall */
#define MAX_PENETRATION 0.05f
/* the wall: a slab this high (above any move: mm_moves_desc.high_max_height is 2.6 m), its near
 * face at z = WALL_Z, long enough to slide along for the whole run */
#define WALL_HEIGHT    3.5f
#define WALL_Z         3.0f
#define WALL_THICKNESS 0.4f
#define WALL_LENGTH    60.0f
#define TICK           (1.0f / 60.0f)
/* m: the simulation's capsule, the default (mm_trajectory_desc.collider_radius) */
#define CAPSULE_RADIUS 0.3f

static mm_database synth_db;
static mm_searcher synth_searcher;
static mm_scene wall;

static int setup(void **state)
{
    (void)state;
    if (test_build_synth_database(&synth_db) != 0) return -1;
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_scene_init(&wall, 0.0f);
    if (mm_scene_add_box(&wall, mm_vec3_make(0.0f, 0.0f, WALL_Z + 0.5f * WALL_THICKNESS),
                         mm_vec3_make(WALL_LENGTH, WALL_HEIGHT, WALL_THICKNESS), 0.0f) != MM_OK)
        return -1;
    return mm_searcher_init(&synth_searcher, &synth_db, NULL, &err) == MM_OK ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    mm_searcher_free(&synth_searcher);
    mm_database_free(&synth_db);
    return 0;
}

/* What a run toward the wall did. */
typedef struct wall_run {
    float penetration;    /* m: the deepest any joint of the body (not joint 0) went into the wall */
    float root_max_z;     /* m: the root's farthest toward the wall */
    float slide;          /* m the root moved along the wall (x) over the last second */
    float predicted_stop; /* m: the farthest z of the predicted future while the simulation was
                             still a metre or more from the wall */
    bool idle;            /* asking for idle frames at the end */
} wall_run;

/* A character walking (or running) from the origin at `degrees` from the wall's normal (+Z) for
 * `seconds`, in the scene when with_scene; with_moves: through the move layer (as mm simulate
 * runs it), whose own collider leaves this wall, higher than any move, to the character. */
static void run_at_wall_with(float degrees, mm_gait gait, float seconds, int with_scene, int with_moves,
                             wall_run *out)
{
    memset(out, 0, sizeof *out);
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_character_desc desc;
    assert_int_equal(mm_character_desc_from_database(&desc, &synth_db, &err), MM_OK);
    mm_character c;
    assert_int_equal(mm_character_init(&c, &synth_db, &synth_searcher, &desc, &err), MM_OK);
    if (with_scene) mm_character_set_scene(&c, &wall);
    static mm_moves moves;
    mm_moves_desc md;
    mm_moves_desc_from_database(&md, &synth_db);
    assert_int_equal(mm_moves_init(&moves, &synth_db, with_moves ? &wall : NULL, &md, &err), MM_OK);
    if (with_moves) assert_true(moves.enabled);
    float a = degrees * MM_PI / 180.0f;
    mm_input in;
    memset(&in, 0, sizeof in);
    in.stick[0] = sinf(a);
    in.stick[1] = cosf(a);
    in.gait = gait;
    int ticks = (int)lroundf(seconds / TICK), last_second = ticks - (int)lroundf(1.0f / TICK);
    float x_before = 0.0f;
    out->root_max_z = -INFINITY;
    out->predicted_stop = -INFINITY;
    float times[3] = {0.33f, 0.67f, 1.0f};
    for (int k = 0; k < ticks; ++k) {
        mm_moves_update(&moves, &c, &in, TICK);
        if (with_moves) assert_int_equal(moves.kind, MM_MOVE_NONE);
        int n = synth_db.joint_count;
        float depth = 0.0f;
        for (int j = 1; j < n; ++j) {
            mm_vec3 p = c.global[j].translation;
            depth = fmaxf(depth, mm_moves_penetration(&wall, &p, 1));
        }
        out->penetration = fmaxf(out->penetration, depth);
        out->root_max_z = fmaxf(out->root_max_z, c.root.translation.z);
        if (k == last_second) x_before = c.root.translation.x;
        if (c.trajectory->position.z < WALL_Z - 1.0f) {
            mm_vec3 p[3];
            mm_quat q[3];
            mm_trajectory_sample(c.trajectory, &in, times, 3, p, q);
            for (int i = 0; i < 3; ++i) out->predicted_stop = fmaxf(out->predicted_stop, p[i].z);
        }
    }
    out->slide = c.root.translation.x - x_before;
    out->idle = c.idle;
    mm_character_free(&c);
}

static void run_at_wall(float degrees, mm_gait gait, float seconds, int with_scene, wall_run *out)
{
    run_at_wall_with(degrees, gait, seconds, with_scene, 0, out);
}

/* The capsule against boxes, by hand: a circle of 0.3 m about (0.1, 0) touching the face x = 0.2
 * of a box (centre 0.5, 1 wide): pushed to x = -0.1 along -X; inside a box, out through the
 * nearer side; turned by 90 degrees, the same in the box's frame; a corner of two boxes, out of
 * both; too low or too high a box, nothing; within the skin, touched but not pushed. */
static void test_capsule(void **state)
{
    (void)state;
    mm_scene s;
    mm_scene_init(&s, 0.0f);
    assert_int_equal(
        mm_scene_add_box(&s, mm_vec3_make(0.7f, 0.0f, 0.0f), mm_vec3_make(1.0f, 2.0f, 4.0f), 0.0f), MM_OK);
    mm_vec3 p = mm_vec3_make(0.1f, 0.0f, 0.0f), n[4];
    assert_int_equal(mm_scene_collide_capsule(&s, 0.3f, 0.0f, 0.3f, 1.8f, &p, n, 4), 1);
    assert_float_equal(p.x, -0.1f, 1e-6f);
    assert_float_equal(p.z, 0.0f, 1e-6f);
    assert_float_equal(n[0].x, -1.0f, 1e-6f);
    assert_float_equal(n[0].z, 0.0f, 1e-6f);
    /* resting there: touched within a skin, not moved; clear without one */
    mm_vec3 q = p;
    assert_int_equal(mm_scene_collide_capsule(&s, 0.3f, 0.01f, 0.3f, 1.8f, &q, n, 4), 1);
    assert_true(q.x == p.x && q.z == p.z);
    assert_int_equal(mm_scene_collide_capsule(&s, 0.3f, 0.0f, 0.3f, 1.8f, &q, n, 4), 0);
    /* inside, nearer the +z side (z 1.7 of half-depth 2): out to z = 2.3 */
    p = mm_vec3_make(0.7f, 0.0f, 1.7f);
    assert_int_equal(mm_scene_collide_capsule(&s, 0.3f, 0.0f, 0.3f, 1.8f, &p, n, 4), 1);
    assert_float_equal(p.z, 2.3f, 1e-5f);
    assert_float_equal(p.x, 0.7f, 1e-6f);
    /* a box lower than the span (a step) or above it (walked under): no contact */
    p = mm_vec3_make(0.1f, 0.0f, 0.0f);
    assert_int_equal(mm_scene_collide_capsule(&s, 0.3f, 0.0f, 2.0f, 3.0f, &p, n, 4), 0);
    assert_int_equal(mm_scene_collide_capsule(&s, 0.3f, 0.0f, -2.0f, 0.0f, &p, n, 4), 0);
    /* the box turned by 90 degrees about its bottom centre (0.7, 0, 0): its 1 m side along world z */
    s.boxes[0].yaw = 0.5f * MM_PI;
    p = mm_vec3_make(0.7f, 0.0f, -0.45f); /* 0.05 m from the face z = -0.5 */
    assert_int_equal(mm_scene_collide_capsule(&s, 0.3f, 0.0f, 0.3f, 1.8f, &p, n, 4), 1);
    assert_float_equal(p.z, -0.8f, 1e-5f);
    assert_float_equal(n[0].z, -1.0f, 1e-5f);
    /* a corner: a second box meeting the first; the capsule comes out of both */
    s.boxes[0].yaw = 0.0f;
    assert_int_equal(
        mm_scene_add_box(&s, mm_vec3_make(0.0f, 0.0f, 2.5f), mm_vec3_make(4.0f, 2.0f, 1.0f), 0.0f), MM_OK);
    p = mm_vec3_make(0.1f, 0.0f, 1.9f);
    assert_int_equal(mm_scene_collide_capsule(&s, 0.3f, 0.0f, 0.3f, 1.8f, &p, n, 4), 2);
    assert_float_equal(p.x, -0.1f, 1e-5f);
    assert_float_equal(p.z, 1.7f, 1e-5f);
    /* bad input: nothing */
    p = mm_vec3_make(NAN, 0.0f, 0.0f);
    assert_int_equal(mm_scene_collide_capsule(&s, 0.3f, 0.0f, 0.3f, 1.8f, &p, n, 4), 0);
    assert_int_equal(mm_scene_collide_capsule(NULL, 0.3f, 0.0f, 0.3f, 1.8f, &p, n, 4), 0);
}

/* A scene whose wall is never reached: the stepped simulation and its prediction agree with the
 * closed form (within float rounding of the steps), its past too; in a scene without boxes the
 * trajectory is the closed form to the bit (the same as one without a scene). */
static void test_untouched_scene(void **state)
{
    (void)state;
    mm_scene far;
    mm_scene_init(&far, 0.0f);
    assert_int_equal(
        mm_scene_add_box(&far, mm_vec3_make(0.0f, 0.0f, 500.0f), mm_vec3_make(1.0f, 3.0f, 1.0f), 0.0f),
        MM_OK);
    mm_trajectory plain, stepped, unset;
    assert_int_equal(mm_trajectory_init(&plain, NULL, NULL), MM_OK);
    assert_int_equal(mm_trajectory_init(&stepped, NULL, NULL), MM_OK);
    assert_int_equal(mm_trajectory_init(&unset, NULL, NULL), MM_OK);
    mm_trajectory_set_scene(&stepped, &far, -1.0f);
    mm_scene open; /* no boxes: nothing to collide with */
    mm_scene_init(&open, 0.0f);
    mm_trajectory_set_scene(&unset, &open, -1.0f);
    mm_input in;
    memset(&in, 0, sizeof in);
    float times[5] = {-0.5f, -0.2f, 0.33f, 0.67f, 1.0f};
    for (int k = 0; k < 240; ++k) {
        float a = 0.02f * (float)k;
        in.stick[0] = 0.8f * sinf(a), in.stick[1] = 0.8f * cosf(a);
        in.gait = k < 120 ? MM_GAIT_WALK : MM_GAIT_RUN;
        float dt = k % 3 == 0 ? 1.0f / 30.0f : 1.0f / 60.0f;
        mm_trajectory_update(&plain, &in, dt);
        mm_trajectory_update(&stepped, &in, dt);
        mm_trajectory_update(&unset, &in, dt);
        mm_vec3 p0[5], p1[5], p2[5];
        mm_quat q0[5], q1[5], q2[5];
        mm_trajectory_sample(&plain, &in, times, 5, p0, q0);
        mm_trajectory_sample(&stepped, &in, times, 5, p1, q1);
        mm_trajectory_sample(&unset, &in, times, 5, p2, q2);
        for (int i = 0; i < 5; ++i) {
            assert_memory_equal(&p0[i], &p2[i], sizeof p0[i]);
            assert_memory_equal(&q0[i], &q2[i], sizeof q0[i]);
            assert_float_equal(p0[i].x, p1[i].x, 1e-4f);
            assert_float_equal(p0[i].z, p1[i].z, 1e-4f);
            assert_float_equal(mm_quat_dot(q0[i], q1[i]), 1.0f, 1e-5f);
        }
        assert_int_equal(stepped.contact_count, 0);
    }
    /* mm_trajectory_predict: the closed form without a scene, stepped with it; the same place */
    mm_vec3 v;
    mm_quat f;
    mm_trajectory_desired(&plain, &in, &v, &f);
    mm_vec3 a, b;
    float path_a, path_b;
    assert_int_equal(mm_trajectory_predict(&plain, v, f, MM_GAIT_RUN, 0.8f, &a, NULL, &path_a), 0);
    assert_int_equal(mm_trajectory_predict(&stepped, v, f, MM_GAIT_RUN, 0.8f, &b, NULL, &path_b), 0);
    assert_float_equal(a.x, b.x, 1e-4f);
    assert_float_equal(a.z, b.z, 1e-4f);
    assert_true(path_a > 0.5f && path_b >= path_a - 1e-4f);
    mm_trajectory_free(&plain);
    mm_trajectory_free(&stepped);
    mm_trajectory_free(&unset);
}

/* The stop prediction (mm_distance_predict_trajectory) in a scene: running at +Z, a wall half
 * way along the closed form's stop ends it at the wall (a capsule's radius before its face); a
 * wall beyond it changes nothing, to the bit. */
static void test_stop_at_wall(void **state)
{
    (void)state;
    mm_trajectory t;
    assert_int_equal(mm_trajectory_init(&t, NULL, NULL), MM_OK);
    mm_input in;
    memset(&in, 0, sizeof in);
    in.stick[1] = 1.0f;
    in.gait = MM_GAIT_RUN;
    for (int k = 0; k < 60; ++k) mm_trajectory_update(&t, &in, TICK);
    mm_distance_prediction open, walled;
    assert_int_equal(mm_distance_predict_trajectory(&t, &in, 0.0f, &open, NULL), MM_OK);
    assert_true(open.found && open.offset.z > 0.2f);
    float reach = open.offset.z;
    for (int far = 0; far < 2; ++far) {
        float face = t.position.z + CAPSULE_RADIUS + (far ? 2.0f : 0.5f) * reach;
        mm_scene s;
        mm_scene_init(&s, 0.0f);
        assert_int_equal(mm_scene_add_box(&s, mm_vec3_make(0.0f, 0.0f, face + 0.5f),
                                          mm_vec3_make(10.0f, 3.0f, 1.0f), 0.0f),
                         MM_OK);
        mm_trajectory_set_scene(&t, &s, -1.0f);
        assert_int_equal(mm_distance_predict_trajectory(&t, &in, 0.0f, &walled, NULL), MM_OK);
        assert_true(walled.found);
        if (far) {
            assert_memory_equal(&walled, &open, sizeof open);
        } else {
            assert_float_equal(walled.offset.z, face - CAPSULE_RADIUS - t.position.z, 1e-3f);
            assert_float_equal(walled.offset.x, 0.0f, 1e-4f);
            assert_float_equal(walled.distance, 0.5f * reach, 2e-3f);
        }
        mm_trajectory_set_scene(&t, NULL, -1.0f);
    }
    mm_trajectory_free(&t);
}

/* Into the wall at 0..80 degrees, walking and running: never more than 5 cm into it, and the
 * root kept out by about the capsule's radius. */
static void test_no_joint_in_wall(void **state)
{
    (void)state;
    const mm_gait gaits[2] = {MM_GAIT_WALK, MM_GAIT_RUN};
    for (int g = 0; g < 2; ++g)
        for (int deg = 0; deg <= 80; deg += 10) {
            wall_run r;
            /* long enough to reach the wall and push along it for 3 s more */
            float toward = (g ? 4.0f : 1.5f) * cosf((float)deg * MM_PI / 180.0f);
            int moves = deg % 20 == 10; /* every other angle through the move layer */
            run_at_wall_with((float)deg, gaits[g], fmaxf(6.0f, WALL_Z / toward + 3.0f), 1, moves, &r);
            assert_true(r.root_max_z >= WALL_Z - CAPSULE_RADIUS - 0.01f); /* it got there */
            print_message(
                "%s%s %2d deg: penetration %.1f cm, root max z %.3f, slide %.2f m/s, predicted %.2f\n",
                g ? "run " : "walk", moves ? " (moves)" : "", deg, 100.0f * r.penetration, r.root_max_z,
                r.slide, r.predicted_stop);
            assert_true(r.penetration <= MAX_PENETRATION);
            /* the root stays a capsule's radius from the wall */
            assert_true(r.root_max_z <= WALL_Z - CAPSULE_RADIUS + 1e-3f);
            /* the simulation a metre away saw the wall ahead (a second ahead: 1.5 m walking, 4
             * running), and its predicted future stopped there, not past it */
            if (deg <= 60) {
                assert_true(r.predicted_stop >= WALL_Z - CAPSULE_RADIUS - 0.01f);
                assert_true(r.predicted_stop <= WALL_Z - CAPSULE_RADIUS + 1e-3f);
            }
        }
}

/* Diagonally into the wall the root keeps moving along it, at about the part of the speed asked
 * for that lies along the wall (the gait's forward speed times the sine of the angle); head on it
 * stops, and asks for idle. */
static void test_slide(void **state)
{
    (void)state;
    const float walk = 1.5f, run = 4.0f; /* m/s: the default forward speeds (mm/trajectory.h) */
    for (int deg = 20; deg <= 80; deg += 20) {
        float a = (float)deg * MM_PI / 180.0f;
        wall_run r;
        run_at_wall((float)deg, MM_GAIT_WALK, 6.0f, 1, &r);
        assert_float_equal(r.slide, walk * sinf(a), 0.15f * walk * sinf(a));
        run_at_wall((float)deg, MM_GAIT_RUN, 6.0f, 1, &r);
        assert_float_equal(r.slide, run * sinf(a), 0.15f * run * sinf(a));
    }
    wall_run r;
    run_at_wall(0.0f, MM_GAIT_WALK, 6.0f, 1, &r);
    assert_float_equal(r.slide, 0.0f, 0.01f);
    assert_true(r.idle);
    /* without the scene the character walks through where the wall would be */
    run_at_wall(0.0f, MM_GAIT_WALK, 6.0f, 0, &r);
    assert_true(r.root_max_z > WALL_Z + 2.0f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_capsule),      cmocka_unit_test(test_untouched_scene),
        cmocka_unit_test(test_stop_at_wall), cmocka_unit_test(test_no_joint_in_wall),
        cmocka_unit_test(test_slide),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
