/* Locomotion and idle clips: the planned track -> a pose per frame.
 *
 * Pelvis: on the root trajectory, swaying toward the stance foot, rotating so the swing leg's hip
 * comes forward, dropping on the swing side, rising and falling twice a cycle (highest at
 * mid-stance when walking, lowest when running), leaning with speed, acceleration and into
 * turns, and lowered smoothly wherever a foot would otherwise be out of reach. The chest
 * counter-rotates, the arms swing opposite the legs, the head keeps the gaze level and looks into
 * turns. Standing adds breathing, slow weight shifts and glances, all periodic in 8 s.
 */
#include <math.h>
#include <string.h>

#include "synth_internal.h"

#define SYNTH_IDLE_PERIOD 8.0f /* s: every idle motion repeats in this time (the idle loop) */
#define SYNTH_PELVIS_SMIN 0.04f

mm_result synth_clip_alloc(synth_ctx *ctx, int frame_count, mm_synth_clip *out)
{
    mm_result r = mm_clip_init(&out->clip, &ctx->skeleton, frame_count, ctx->fps, ctx->allocator);
    if (r != MM_OK) return r;
    out->contacts = (uint8_t *)mm_alloc_array(ctx->allocator, (size_t)frame_count, 1);
    if (!out->contacts) {
        mm_clip_free(&out->clip);
        return MM_ERR_OUT_OF_MEMORY;
    }
    return MM_OK;
}

static uint8_t contact_bits(const synth_foot *f)
{
    uint8_t bits = 0;
    if (f[SYNTH_LEFT].heel) bits |= MM_SYNTH_LEFT_HEEL;
    if (f[SYNTH_LEFT].toe) bits |= MM_SYNTH_LEFT_TOE;
    if (f[SYNTH_RIGHT].heel) bits |= MM_SYNTH_RIGHT_HEEL;
    if (f[SYNTH_RIGHT].toe) bits |= MM_SYNTH_RIGHT_TOE;
    return bits;
}

/* Standing motions at time t, weighted by w (1 standing, 0 moving). */
typedef struct idle_motion {
    float shift;  /* lateral weight shift of the pelvis, m (> 0 left) */
    float sway;   /* fore-aft sway, m */
    float breath; /* -1..1 */
    float look;   /* head yaw, rad */
    float nod;    /* head pitch, rad */
} idle_motion;

static void idle_at(const synth_style *st, float t, float w, idle_motion *m)
{
    const float f = SYNTH_TAU / SYNTH_IDLE_PERIOD;
    const float deg = (float)MM_DEG_TO_RAD;
    m->shift = w * 0.022f * st->idle_amp[0] * sinf(f * t + st->idle_phase[0]);
    m->sway = w * 0.008f * st->idle_amp[1] * sinf(3.0f * f * t + st->idle_phase[1]);
    m->breath = w * sinf(2.0f * f * t + st->idle_phase[2]);
    m->look = w * deg *
              (7.0f * st->idle_amp[2] * sinf(f * t + st->idle_phase[3]) +
               2.5f * sinf(3.0f * f * t + st->idle_phase[2]));
    m->nod = w * deg * 2.0f * st->idle_amp[3] * sinf(2.0f * f * t + st->idle_phase[1]);
}

/* Highest pelvis height with both feet within reach. */
static float reach_limit(const synth_body *b, const synth_pose *p)
{
    float y = 1e9f;
    for (int side = 0; side < 2; ++side) {
        float lim =
            synth_pelvis_reach(b, side, p->pelvis, p->pelvis_rot, p->foot[side].ankle) - p->foot[side].margin;
        if (lim < y) y = lim;
    }
    return y;
}

/* A smooth curve below lim: out[i] <= lim[j] whenever |i - j| <= r (a running minimum of radius
 * r, then two box filters of radius r / 2). wrap: the frames form a loop. */
static void lower_envelope(const float *lim, float *a, float *out, int n, int r, bool wrap)
{
    for (int i = 0; i < n; ++i) {
        float m = lim[i];
        for (int d = -r; d <= r; ++d) {
            int j = i + d;
            if (wrap)
                j = ((j % n) + n) % n;
            else
                j = j < 0 ? 0 : j >= n ? n - 1 : j;
            if (lim[j] < m) m = lim[j];
        }
        a[i] = m;
    }
    int h = r / 2 > 0 ? r / 2 : 1;
    for (int pass = 0; pass < 2; ++pass) {
        const float *src = pass == 0 ? a : out;
        float *dst = pass == 0 ? out : a;
        for (int i = 0; i < n; ++i) {
            float sum = 0.0f;
            for (int d = -h; d <= h; ++d) {
                int j = i + d;
                if (wrap)
                    j = ((j % n) + n) % n;
                else
                    j = j < 0 ? 0 : j >= n ? n - 1 : j;
                sum += src[j];
            }
            dst[i] = sum / (float)(2 * h + 1);
        }
    }
    for (int i = 0; i < n; ++i) out[i] = a[i];
}

static void loco_pose(const synth_ctx *ctx, const synth_track *tr, int frame, synth_pose *p)
{
    const synth_body *b = &ctx->body;
    const synth_style *st = &ctx->style;
    const float deg = (float)MM_DEG_TO_RAD;
    const synth_sample *s = &tr->s[tr->zero + frame * tr->substeps];
    float t = (float)frame / ctx->fps;
    synth_key k;
    float accel;
    synth_plan_values(tr->plan, t, &k, &accel);
    synth_gait g;
    synth_gait_eval(b, st, k.speed, k.gait, k.activity, k.turn_rate, k.direction, &g);
    float a = synth_clampf(k.activity, 0.0f, 1.0f);
    idle_motion idle;
    idle_at(st, t, 1.0f - a, &idle);

    double phi = s->phi;
    float heading = (float)s->heading;
    mm_vec3 root = mm_vec3_make((float)s->x, 0.0f, (float)s->z);
    float o_left = tr->foot_offset[SYNTH_LEFT];
    float sag = cosf(k.direction); /* how much of the stride is along the body's forward axis */

    /* Phase angles: c1 peaks at the left foot's mid-stance, c2 at both mid-stances. */
    float mid_left = (float)(phi - (double)o_left) - 0.5f * g.duty;
    float c1 = cosf(SYNTH_TAU * mid_left), c2 = cosf(2.0f * SYNTH_TAU * mid_left);
    float cyc = (float)(phi - (double)o_left); /* 0 at left touchdown */
    float step = cosf(SYNTH_TAU * cyc);        /* +1 left leg forward, -1 right leg forward */

    for (int side = 0; side < 2; ++side) synth_track_foot(b, tr, side, phi, &p->foot[side]);

    /* Pelvis. */
    float lean_turn = synth_turn_lean(k.speed, k.curvature);
    float yaw_osc = -g.yaw * step * sag;
    float list = g.list * c1 + 2.5f * deg * idle.shift / 0.022f;
    float accel_lean = synth_clampf(0.035f * accel, -0.15f, 0.15f);
    float trunk = g.lean + accel_lean;
    p->pelvis_rot = synth_yaw_pitch_roll(heading + yaw_osc, 0.4f * trunk + 3.0f * deg, list - lean_turn);
    float lateral = g.sway * c1 + idle.shift;
    mm_vec3 offset = mm_quat_rotate(synth_rot_y(heading), mm_vec3_make(lateral, 0.0f, idle.sway));
    p->pelvis = mm_vec3_add(root, offset);
    p->pelvis.y = g.pelvis_height + g.bob * c2; /* desired; lowered later where feet need it */
    p->facing = heading;

    /* Chest: counter-rotates against the pelvis, leans with the trunk and into turns, and stays
     * nearly level sideways. */
    p->chest =
        synth_yaw_pitch_roll(heading + yaw_osc * (1.0f - g.counter), trunk, -0.9f * lean_turn + 0.15f * list);
    p->breath = idle.breath;

    /* Head: level gaze, looking a little into turns. */
    float look = synth_clampf(0.3f * k.speed * k.curvature + 0.15f * k.turn_rate, -0.5f, 0.5f);
    p->head_yaw = heading + look + idle.look;
    p->head_pitch = st->head_pitch + idle.nod + 0.3f * trunk;
    p->head_roll = -0.4f * lean_turn;

    /* Arms: opposite the legs, with a slight lag; elbows flex more when the arm is forward. */
    float arm = cosf(SYNTH_TAU * (cyc - 0.04f)) * sag;
    for (int side = 0; side < 2; ++side) {
        float sgn = side == SYNTH_LEFT ? -1.0f : 1.0f;
        float swing = sgn * g.arm_swing * arm; /* left arm forward when the right leg is */
        float fwd = 0.5f + 0.5f * sgn * arm;   /* 1 when this arm is furthest forward */
        p->arm_swing[side] = g.arm_carry + swing - 0.3f * idle.sway / 0.008f * deg;
        p->arm_abduct[side] = g.arm_abduct + 2.0f * deg * synth_side_sign(side) * idle.shift / 0.022f;
        p->elbow[side] = g.elbow + g.elbow_swing * fwd;
        p->clavicle[side] = 1.5f * deg * idle.breath + 2.0f * deg * k.gait;
        p->wrist[side] = 8.0f * deg;
    }
}

mm_result synth_make_loco(synth_ctx *ctx, const synth_plan *plan, mm_synth_clip *out)
{
    synth_track tr;
    mm_result r = synth_track_build(ctx, plan, &tr);
    if (r != MM_OK) return r;
    int n = tr.frames;
    size_t pose_bytes = (size_t)n * sizeof(synth_pose);
    synth_pose *poses = (synth_pose *)synth_work_get(ctx, 1, pose_bytes + 3 * (size_t)n * sizeof(float));
    if (!poses) return MM_ERR_OUT_OF_MEMORY;
    float *limit = (float *)(poses + n), *tmp = limit + n, *env = tmp + n;
    r = synth_clip_alloc(ctx, n, out);
    if (r != MM_OK) return r;
    out->loop = plan->loop;

    /* Pass 1: everything but the pelvis height, which must stay under a smooth envelope of every
     * frame's reach limit (so planted feet are always reachable and the pelvis never snaps). */
    for (int f = 0; f < n; ++f) {
        loco_pose(ctx, &tr, f, &poses[f]);
        limit[f] = reach_limit(&ctx->body, &poses[f]);
    }
    int radius = (int)lroundf(0.06f * ctx->fps);
    lower_envelope(limit, tmp, env, n, radius < 2 ? 2 : radius, plan->loop);

    for (int f = 0; f < n; ++f) {
        synth_pose *p = &poses[f];
        p->pelvis.y = synth_smin(p->pelvis.y, env[f], 0.02f);
        synth_pose_to_locals(&ctx->body, p, mm_clip_rotations(&out->clip, f),
                             mm_clip_positions(&out->clip, f));
        out->contacts[f] = contact_bits(p->foot);
    }
    synth_key k;
    synth_plan_values(plan, 0.0f, &k, NULL);
    out->speed_in = k.speed;
    synth_plan_values(plan, (float)(n - 1) / ctx->fps, &k, NULL);
    out->speed_out = k.speed;
    return MM_OK;
}
