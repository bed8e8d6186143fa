/* The standing jump forward: stand, crouch (countermovement, arms back), push (heels rise, arms
 * swing forward), flight (ballistic pelvis, feet tucked), landing (toes first, heels down,
 * absorption), rise, stand.
 *
 * The pelvis is C1 everywhere: Hermite segments join the ballistic flight with its exact
 * take-off and landing velocities. In flight the feet move relative to the pelvis on a Hermite
 * arc that matches their take-off and landing velocities. The take-off and landing heights are
 * solved so the legs are within reach, with margin.
 */
#include <math.h>
#include <string.h>

#include "synth_internal.h"

/* Timeline, s. */
#define J_CROUCH   0.8f  /* start of the countermovement */
#define J_PUSH     1.45f /* deepest crouch, start of the push */
#define J_PUSH_T   0.30f /* push duration */
#define J_HEEL_T   0.18f /* heel rise before take-off */
#define J_ROLL_T   0.12f /* heels coming down after landing */
#define J_ABSORB_T 0.30f
#define J_SETTLE_T 0.5f /* horizontal deceleration after landing */
#define J_RISE_T   0.8f
#define J_REST_T   0.8f

typedef struct jump_plan {
    float t_to, t_ld, t_end;
    float y_stand, y_crouch, y_to, y_ld, y_absorb;
    float z_crouch, z_to, z_ld, z_end;
    float vy, vz, vy_ld;
    float beta_to, beta_ld;
    mm_vec3 plant0[2], plant1[2];
    float yaw[2];
} jump_plan;

/* Smoothly interpolated keys (time, value) for the upper body. */
static float keyed(const float (*k)[2], int n, float t)
{
    if (t <= k[0][0]) return k[0][1];
    for (int i = 0; i + 1 < n; ++i)
        if (t < k[i + 1][0])
            return synth_lerpf(k[i][1], k[i + 1][1], synth_smoother((t - k[i][0]) / (k[i + 1][0] - k[i][0])));
    return k[n - 1][1];
}

static float ballistic_time(float y0, float vy, float y1)
{
    /* y0 + vy t - g t^2 / 2 = y1, the later root. */
    float d = vy * vy + 2.0f * SYNTH_GRAVITY * (y0 - y1);
    return (vy + sqrtf(d > 0.0f ? d : 0.0f)) / SYNTH_GRAVITY;
}

static void plan_jump(const synth_ctx *ctx, float distance, jump_plan *j)
{
    const synth_body *b = &ctx->body;
    const float deg = (float)MM_DEG_TO_RAD;
    memset(j, 0, sizeof *j);
    for (int side = 0; side < 2; ++side) {
        float s = synth_side_sign(side);
        j->yaw[side] = s * ctx->style.toe_out;
        j->plant0[side] = mm_vec3_make(s * ctx->style.stand_width, b->ankle_height, 0.0f);
        j->plant1[side] = mm_vec3_make(s * ctx->style.stand_width, b->ankle_height, distance);
    }
    j->y_stand = b->stand_height;
    j->y_crouch = b->stand_height - 0.24f;
    j->y_absorb = b->stand_height - 0.20f;
    j->z_crouch = -0.06f;
    j->z_to = 0.16f;
    j->z_end = distance;
    j->vy = 2.3f;
    j->beta_to = -38.0f * deg;
    j->beta_ld = -14.0f * deg;
    j->t_to = J_PUSH + J_PUSH_T;
    mm_quat upright = mm_quat_identity();

    /* Take-off height: the legs nearly straight with the heels up. */
    mm_vec3 pel = mm_vec3_make(0.0f, 0.0f, j->z_to);
    float y = 10.0f;
    for (int side = 0; side < 2; ++side) {
        mm_vec3 a = synth_foot_pivot(b, j->plant0[side], j->yaw[side], j->beta_to);
        float lim = synth_pelvis_reach(b, side, pel, upright, a);
        if (lim < y) y = lim;
    }
    j->y_to = y - 0.05f;

    /* Horizontal speed and landing height depend on each other: a few fixed-point rounds. */
    j->y_ld = j->y_to - 0.08f;
    for (int it = 0; it < 4; ++it) {
        float tf = ballistic_time(j->y_to, j->vy, j->y_ld);
        j->vz = (j->z_end - j->z_to) / (tf + 0.45f * J_SETTLE_T);
        j->z_ld = j->z_end - 0.45f * j->vz * J_SETTLE_T;
        pel = mm_vec3_make(0.0f, 0.0f, j->z_ld);
        y = 10.0f;
        for (int side = 0; side < 2; ++side) {
            mm_vec3 a = synth_foot_pivot(b, j->plant1[side], j->yaw[side], j->beta_ld);
            float lim = synth_pelvis_reach(b, side, pel, upright, a);
            if (lim < y) y = lim;
        }
        j->y_ld = y - 0.05f;
    }
    float tf = ballistic_time(j->y_to, j->vy, j->y_ld);
    j->t_ld = j->t_to + tf;
    j->vy_ld = j->vy - SYNTH_GRAVITY * tf;
    j->t_end = j->t_ld + J_ABSORB_T + J_RISE_T + J_REST_T;
}

static void pelvis_path(const jump_plan *j, float t, float *y, float *z)
{
    if (t < J_CROUCH) {
        *y = j->y_stand;
        *z = 0.0f;
    } else if (t < J_PUSH) {
        float s = (t - J_CROUCH) / (J_PUSH - J_CROUCH);
        *y = synth_hermite(j->y_stand, 0, j->y_crouch, 0, s);
        *z = synth_hermite(0.0f, 0, j->z_crouch, 0, s);
    } else if (t < j->t_to) {
        float s = (t - J_PUSH) / J_PUSH_T;
        *y = synth_hermite(j->y_crouch, 0, j->y_to, j->vy * J_PUSH_T, s);
        *z = synth_hermite(j->z_crouch, 0, j->z_to, j->vz * J_PUSH_T, s);
    } else if (t < j->t_ld) {
        float u = t - j->t_to;
        *y = j->y_to + j->vy * u - 0.5f * SYNTH_GRAVITY * u * u;
        *z = j->z_to + j->vz * u;
    } else {
        float u = t - j->t_ld;
        float sy = synth_clampf(u / J_ABSORB_T, 0.0f, 1.0f);
        float sz = synth_clampf(u / J_SETTLE_T, 0.0f, 1.0f);
        if (u < J_ABSORB_T)
            *y = synth_hermite(j->y_ld, j->vy_ld * J_ABSORB_T, j->y_absorb, 0, sy);
        else
            *y = synth_hermite(j->y_absorb, 0, j->y_stand, 0,
                               synth_clampf((u - J_ABSORB_T) / J_RISE_T, 0.0f, 1.0f));
        *z = synth_hermite(j->z_ld, j->vz * J_SETTLE_T, j->z_end, 0, sz);
    }
}

static void pelvis_velocity(const jump_plan *j, float t, float *vy, float *vz)
{
    /* Only needed at take-off and landing, where it is known exactly. */
    if (t <= j->t_to) {
        *vy = j->vy;
        *vz = j->vz;
    } else {
        *vy = j->vy_ld;
        *vz = j->vz;
    }
}

/* A planted foot: heel rise before take-off, heels down after landing. */
static void stance_foot(const synth_body *b, const jump_plan *j, int side, float t, synth_foot *f)
{
    bool landed = t >= j->t_ld;
    mm_vec3 plant = landed ? j->plant1[side] : j->plant0[side];
    float beta = 0.0f;
    if (!landed) {
        float q = synth_clampf((t - (j->t_to - J_HEEL_T)) / J_HEEL_T, 0.0f, 1.0f);
        beta = j->beta_to * q * q;
    } else {
        float q = synth_clampf(1.0f - (t - j->t_ld) / J_ROLL_T, 0.0f, 1.0f);
        beta = j->beta_ld * q * q;
    }
    f->ankle = synth_foot_pivot(b, plant, j->yaw[side], beta);
    f->yaw = j->yaw[side];
    f->pitch = beta;
    f->toe_angle = beta < 0.0f ? beta : 0.0f;
    f->heel = beta >= 0.0f;
    f->toe = beta <= 0.0f;
}

static void flight_foot(const synth_body *b, const jump_plan *j, int side, float t, mm_vec3 pelvis,
                        synth_foot *f)
{
    float tf = j->t_ld - j->t_to;
    float s = (t - j->t_to) / tf;
    float rate0 = 2.0f * j->beta_to / J_HEEL_T;  /* d(beta)/dt at take-off */
    float rate1 = -2.0f * j->beta_ld / J_ROLL_T; /* d(beta)/dt at landing */
    mm_vec3 a0 = synth_foot_pivot(b, j->plant0[side], j->yaw[side], j->beta_to);
    mm_vec3 a1 = synth_foot_pivot(b, j->plant1[side], j->yaw[side], j->beta_ld);
    mm_vec3 va0 = mm_vec3_scale(synth_foot_pivot_d(b, j->yaw[side], j->beta_to), rate0);
    mm_vec3 va1 = mm_vec3_scale(synth_foot_pivot_d(b, j->yaw[side], j->beta_ld), rate1);
    float y0, z0, y1, z1, vy0, vz0, vy1, vz1;
    pelvis_path(j, j->t_to, &y0, &z0);
    pelvis_path(j, j->t_ld, &y1, &z1);
    pelvis_velocity(j, j->t_to, &vy0, &vz0);
    pelvis_velocity(j, j->t_ld, &vy1, &vz1);
    mm_vec3 r0 = mm_vec3_sub(a0, mm_vec3_make(0.0f, y0, z0)),
            r1 = mm_vec3_sub(a1, mm_vec3_make(0.0f, y1, z1));
    mm_vec3 m0 = mm_vec3_scale(mm_vec3_sub(va0, mm_vec3_make(0.0f, vy0, vz0)), tf);
    mm_vec3 m1 = mm_vec3_scale(mm_vec3_sub(va1, mm_vec3_make(0.0f, vy1, vz1)), tf);
    mm_vec3 rel = synth_vec3_hermite(r0, m0, r1, m1, s);
    float bump = 16.0f * s * s * (1.0f - s) * (1.0f - s);
    rel.y += 0.22f * bump;
    rel.z += 0.05f * bump;
    f->ankle = mm_vec3_add(pelvis, rel);
    f->yaw = j->yaw[side];
    f->pitch = synth_hermite(j->beta_to, rate0 * tf, j->beta_ld, rate1 * tf, s) + 0.35f * bump;
    f->toe_angle = synth_hermite(j->beta_to, rate0 * tf, j->beta_ld, rate1 * tf, s);
    f->heel = false;
    f->toe = false;
}

mm_result synth_make_jump(synth_ctx *ctx, float distance, mm_synth_clip *out)
{
    const synth_body *b = &ctx->body;
    const synth_style *st = &ctx->style;
    const float deg = (float)MM_DEG_TO_RAD;
    jump_plan j;
    plan_jump(ctx, distance, &j);
    int frames = (int)lroundf(j.t_end * ctx->fps) + 1;
    mm_result r = synth_clip_alloc(ctx, frames, out);
    if (r != MM_OK) return r;
    out->loop = false;

    const float t_absorb = j.t_ld + J_ABSORB_T, t_rise = t_absorb + J_RISE_T;
    const float trunk_keys[][2] = {{J_CROUCH, 3 * deg},      {J_PUSH, 34 * deg}, {j.t_to, 12 * deg},
                                   {j.t_to + 0.2f, 6 * deg}, {j.t_ld, 18 * deg}, {t_absorb, 30 * deg},
                                   {t_rise, 3 * deg}};
    const float arm_keys[][2] = {{J_CROUCH, -3 * deg},      {J_PUSH - 0.12f, -40 * deg},
                                 {j.t_to + 0.1f, 65 * deg}, {j.t_to + 0.3f, 55 * deg},
                                 {j.t_ld, 35 * deg},        {t_absorb, 30 * deg},
                                 {t_rise, -3 * deg}};
    const float elbow_keys[][2] = {{J_CROUCH, st->elbow}, {J_PUSH, 20 * deg},   {j.t_to, 35 * deg},
                                   {j.t_ld, 45 * deg},    {t_absorb, 40 * deg}, {t_rise, st->elbow}};
    const int nk = 7;

    for (int f = 0; f < frames; ++f) {
        float t = (float)f / ctx->fps;
        synth_pose p;
        memset(&p, 0, sizeof p);
        float y, z;
        pelvis_path(&j, t, &y, &z);
        float trunk = keyed(trunk_keys, nk, t);
        float breath = sinf(SYNTH_TAU * t / 4.0f + st->idle_phase[2]);
        float calm = 1.0f - synth_smooth((t - J_CROUCH + 0.3f) / 0.3f) + synth_smooth((t - t_rise) / 0.5f);
        p.pelvis = mm_vec3_make(0.0f, y, z);
        p.pelvis_rot = synth_yaw_pitch_roll(0.0f, 0.5f * trunk + 3.0f * deg, 0.0f);
        bool flight = t > j.t_to && t < j.t_ld;
        for (int side = 0; side < 2; ++side) {
            if (flight)
                flight_foot(b, &j, side, t, p.pelvis, &p.foot[side]);
            else
                stance_foot(b, &j, side, t, &p.foot[side]);
        }
        if (!flight) {
            /* Never let a planted foot out of reach. */
            for (int side = 0; side < 2; ++side)
                p.pelvis.y = synth_smin(
                    p.pelvis.y, synth_pelvis_reach(b, side, p.pelvis, p.pelvis_rot, p.foot[side].ankle),
                    0.01f);
        }
        p.facing = 0.0f;
        p.chest = synth_yaw_pitch_roll(0.0f, trunk, 0.0f);
        p.breath = breath * calm;
        p.head_yaw = 0.0f;
        p.head_pitch = st->head_pitch + 0.4f * trunk;
        p.head_roll = 0.0f;
        float arm = keyed(arm_keys, nk, t), elbow = keyed(elbow_keys, 6, t);
        for (int side = 0; side < 2; ++side) {
            p.arm_swing[side] = arm;
            p.arm_abduct[side] = 8.0f * deg + 0.15f * fabsf(arm);
            p.elbow[side] = elbow;
            p.clavicle[side] = 1.5f * deg * p.breath + 0.1f * synth_clampf(arm, 0.0f, 1.0f);
            p.wrist[side] = 8.0f * deg;
        }
        synth_pose_to_locals(b, &p, mm_clip_rotations(&out->clip, f), mm_clip_positions(&out->clip, f));
        uint8_t bits = 0;
        if (p.foot[0].heel) bits |= MM_SYNTH_LEFT_HEEL;
        if (p.foot[0].toe) bits |= MM_SYNTH_LEFT_TOE;
        if (p.foot[1].heel) bits |= MM_SYNTH_RIGHT_HEEL;
        if (p.foot[1].toe) bits |= MM_SYNTH_RIGHT_TOE;
        out->contacts[f] = bits;
    }
    out->speed_in = 0.0f;
    out->speed_out = 0.0f;
    return MM_OK;
}
