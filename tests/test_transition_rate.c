/* The transition stage across a change of play rate (src/runtime/character/transition.c,
 * mm_transition_hold_velocity): the clip's velocity changes by the change of rate, the offsets take
 * it up, and the output keeps its velocity, the difference fading on the offsets' spring. Truth:
 * the motion played on at the old rate, and the spring's closed form (mm/spring.h). */
#include <math.h>

#include "test_util.h"

#include <mm/spring.h>

#include "runtime/character/transition.h"

enum { N = 2 };

/* s: the clip's frame interval, the tick; rad/s and m/s: joint 1's motion in the clip */
static const float interval = 1.0f / 30.0f, dt = 1.0f / 60.0f, turn_rate = 6.0f, speed = 1.5f;

/* joint 1 of the clip at clip time s: turning about +Y from `tilt` about +X (from the parent's
 * side), moving along +X */
static mm_quat clip_rotation(float s, float tilt)
{
    mm_quat swing = mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), 0.2f + turn_rate * s);
    return mm_quat_mul(mm_quat_from_axis_angle(mm_vec3_make(1, 0, 0), tilt), swing);
}

typedef struct run {
    mm_quat rot[N], prev[N], r0[N], r1[N];
    mm_vec3 pos[N], prev_pos[N], p0[N], p1[N];
    mm_vec3 ro[N], rov[N], po[N], pov[N];
    mm_transition tr;
    float clip_time; /* s into the clip */
} run;

static void run_init(run *r)
{
    memset(r, 0, sizeof *r);
    mm_transition *tr = &r->tr;
    tr->rotations = r->rot, tr->previous_rotations = r->prev, tr->positions = r->pos,
    tr->previous_positions = r->prev_pos;
    tr->rotation_offset = r->ro, tr->rotation_offset_velocity = r->rov, tr->position_offset = r->po,
    tr->position_offset_velocity = r->pov;
    for (int j = 0; j < N; ++j) r->rot[j] = r->prev[j] = r->r0[j] = r->r1[j] = mm_quat_identity();
}

/* One tick played at `rate` (rate_before the last tick's): the playhead moves on, the change of
 * rate is held (hold) at the frames around the playhead, the offsets decay over dt (half-life h)
 * onto the clip's pose. Returns joint 1's output. */
static mm_xform tick(run *r, float rate, float rate_before, bool hold, float h)
{
    r->clip_time += rate * dt;
    r->r0[1] = clip_rotation(r->clip_time, 0.0f), r->r1[1] = clip_rotation(r->clip_time + interval, 0.0f);
    r->p0[1] = mm_vec3_make(speed * r->clip_time, 0, 0);
    r->p1[1] = mm_vec3_make(speed * (r->clip_time + interval), 0, 0);
    mm_frame_pair at = {r->r0, r->r1, r->p0, r->p1};
    if (hold) mm_transition_hold_velocity(&r->tr, N, &at, 1.0f / interval, rate_before, rate);
    r->rot[1] = r->r0[1], r->pos[1] = r->p0[1];
    mm_transition_decay(&r->tr, N, h, h, dt);
    return mm_xform_make(r->rot[1], r->pos[1]);
}

static float angle_about_y(mm_quat q) { return 2.0f * atan2f(q.y, q.w); }

/* Rate 1 for three ticks, then 1.25: the second difference of the output's turn and place on the
 * tick of the change is the spring's (the offset starting at rest with velocity -(r1 - r0) v:
 * (r1 - r0) v dt (1 - e^(-y dt))) instead of the whole (r1 - r0) v dt. */
static void test_rate_change_keeps_velocity(void **state)
{
    (void)state;
    const float h = 0.2f, r0 = 1.0f, r1 = 1.25f;
    float y = (float)mm_spring_damping(h);
    for (int hold = 0; hold < 2; ++hold) {
        run r;
        run_init(&r);
        float angle[5], x[5];
        for (int k = 0; k < 5; ++k) {
            float rate = k < 3 ? r0 : r1, before = k < 4 ? r0 : r1;
            mm_xform out = tick(&r, rate, k == 0 ? rate : before, hold != 0, h);
            angle[k] = angle_about_y(out.rotation), x[k] = out.translation.x;
        }
        /* the change is on tick 3 */
        float turn_jump = angle[3] - 2.0f * angle[2] + angle[1], move_jump = x[3] - 2.0f * x[2] + x[1];
        float whole = (r1 - r0) * dt;
        if (hold) {
            float share = 1.0f - expf(-y * dt);
            assert_near(turn_jump, whole * turn_rate * share, 2e-5f);
            assert_near(move_jump, whole * speed * share, 1e-6f);
            assert_true(fabsf(turn_jump) < 0.15f * whole * turn_rate);
        } else { /* without: the clip's velocity changes at once */
            assert_near(turn_jump, whole * turn_rate, 2e-5f);
            assert_near(move_jump, whole * speed, 1e-6f);
        }
    }
}

/* The same under an offset that does not commute with the swing (0.8 rad about +X, a long
 * half-life so that it stays): one tick after the rate goes 1 -> 1.5 the output is where the old
 * motion, the tilted swing at rate 1, would be to second order; the offset's rate is taken through
 * the exponential map's Jacobian (a plain difference of rates would miss by the tilt's turn of it). */
static void test_rate_change_under_a_tilted_offset(void **state)
{
    (void)state;
    const float h = 10.0f, tilt = 0.8f;
    run r;
    run_init(&r);
    r.ro[1] = mm_vec3_make(tilt, 0, 0); /* the output is the tilted swing */
    tick(&r, 1.0f, 1.0f, true, h);
    float played = r.clip_time;
    mm_xform out = tick(&r, 1.5f, 1.0f, true, h);
    mm_quat old_motion = clip_rotation(played + dt, tilt);
    assert_true(mm_quat_angle_between(out.rotation, old_motion) < 2e-3f);
    /* not held: off by the change of rate's turn, 0.5 w dt (0.05 rad) */
    run bare;
    run_init(&bare);
    bare.ro[1] = mm_vec3_make(tilt, 0, 0);
    tick(&bare, 1.0f, 1.0f, false, h);
    out = tick(&bare, 1.5f, 1.0f, false, h);
    assert_true(mm_quat_angle_between(out.rotation, old_motion) > 0.04f);
}

/* No change of rate: nothing held (the offsets' velocities stay as they are). */
static void test_same_rate_holds_nothing(void **state)
{
    (void)state;
    run r;
    run_init(&r);
    r.rov[1] = mm_vec3_make(0.1f, 0.2f, 0.3f), r.pov[1] = mm_vec3_make(-0.5f, 0, 0);
    r.r0[1] = clip_rotation(0.0f, 0.0f), r.r1[1] = clip_rotation(interval, 0.0f);
    mm_frame_pair at = {r.r0, r.r1, r.p0, r.p1};
    mm_transition_hold_velocity(&r.tr, N, &at, 1.0f / interval, 1.1f, 1.1f);
    assert_true(r.rov[1].x == 0.1f && r.rov[1].y == 0.2f && r.rov[1].z == 0.3f);
    assert_true(r.pov[1].x == -0.5f);
}

/* The offsets' rates four joints at a time (mm__rotation_offset_rates): the bits of
 * mm__rotation_offset_rate each, for offsets from none through tiny (the series of c) to past pi,
 * velocities in and out of every size, zero and NaN among them, every count's remainder. */
static void test_offset_rates_packed(void **state)
{
    (void)state;
    enum { JOINTS = 23 };
    mm_vec3 x[JOINTS], w_out[JOINTS], w_new[JOINTS], many[JOINTS];
    mm_quat turn[JOINTS];
    unsigned seed = 7;
    for (int n = 0; n < 300; ++n) {
        for (int j = 0; j < JOINTS; ++j) {
            float v[9];
            for (int k = 0; k < 9; ++k) {
                seed = seed * 1664525u + 1013904223u;
                v[k] = ((float)(seed >> 8) / 16777216.0f - 0.5f) * 2.0f;
            }
            float size = powf(10.0f, -6.0f + 6.5f * fabsf(v[0])); /* 1e-6 to about 3 rad */
            x[j] = mm_vec3_scale(mm_vec3_normalize(mm_vec3_make(v[1], v[2], v[0] + 0.1f)), size);
            w_out[j] = mm_vec3_scale(mm_vec3_make(v[3], v[4], v[5]), 10.0f * fabsf(v[8]));
            w_new[j] = mm_vec3_make(v[6] * 20.0f, v[7], v[8]);
            turn[j] = mm_quat_exp(x[j]);
        }
        x[n % JOINTS] = mm_vec3_make(0.0f, -0.0f, 0.0f);
        turn[n % JOINTS] = mm_quat_identity();
        if (n % 7 == 2) w_new[3] = mm_vec3_make(NAN, 0.0f, 0.0f);
        if (n % 7 == 4) x[6] = mm_vec3_make(0.0f, INFINITY, 0.0f);
        int count = JOINTS - n % 4;
        mm__rotation_offset_rates(x, turn, w_out, w_new, count, many);
        for (int j = 0; j < count; ++j) {
            mm_vec3 one = mm__rotation_offset_rate(x[j], turn[j], w_out[j], w_new[j]);
            assert_memory_equal(&many[j], &one, sizeof one);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rate_change_keeps_velocity),
        cmocka_unit_test(test_rate_change_under_a_tilted_offset),
        cmocka_unit_test(test_same_rate_holds_nothing),
        cmocka_unit_test(test_offset_rates_packed),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
