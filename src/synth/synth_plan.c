/* Gait planning: control plan -> root trajectory and gait phase -> footsteps.
 *
 * 1. The plan's keys (speed, curvature, travel direction, turn rate, walk/run blend, activity)
 *    are interpolated with a C2 ease and integrated at a fine fixed rate (a whole number of
 *    samples per output frame) into the root trajectory: heading' = speed * curvature +
 *    turn_rate, position' = speed * (direction of heading + travel direction).
 * 2. The gait phase (in cycles) advances at activity * cadence. Each foot touches down at a fixed
 *    phase in every cycle (left at 0, right at 0.5, or the other way round) and lifts off a duty
 *    factor later. Standing is a phase where both feet are in stance; a clip that ends standing
 *    has its phase scaled (or offset) so that it comes to rest in the middle of a double support.
 * 3. Every stance gets a plant: where the trajectory will be when the stance is plant_ref through
 *    (the ankle passes under the hip there), offset sideways by the step width plus a quarter of
 *    the lateral stride (so sidesteps never cross the feet) and outward by the turn lean. A stance
 *    that contains a standing period is planted at the standing position instead.
 * 4. Between stances a swing arc (cubic Hermite matching the rocker velocities at liftoff and
 *    touchdown, plus a clearance bump) carries the foot; yaw, foot angle and toe bend are
 *    interpolated the same way, so the foot's motion is C1 everywhere.
 */
#include <math.h>
#include <string.h>

#include "synth_internal.h"

#define SYNTH_SIM_HZ  480.0f /* the trajectory is integrated at least this finely */
#define SYNTH_PREROLL 2.5f   /* s simulated before and after the clip (stances crossing its ends) */

void synth_plan_values(const synth_plan *p, float t, synth_key *out, float *accel)
{
    const synth_key *k = p->keys;
    int n = p->key_count;
    if (accel) *accel = 0.0f;
    if (p->period > 0.0f) t -= floorf(t / p->period) * p->period;
    if (t <= k[0].t || n == 1) {
        *out = k[0];
        out->t = t;
        return;
    }
    if (t >= k[n - 1].t) {
        *out = k[n - 1];
        out->t = t;
        return;
    }
    int i = 0;
    while (i + 1 < n - 1 && t >= k[i + 1].t) ++i;
    const synth_key *a = &k[i], *b = &k[i + 1];
    float span = b->t - a->t;
    float x = (t - a->t) / span;
    float e = synth_smoother(x);
    out->t = t;
    out->speed = synth_lerpf(a->speed, b->speed, e);
    out->curvature = synth_lerpf(a->curvature, b->curvature, e);
    out->direction = synth_lerpf(a->direction, b->direction, e);
    out->turn_rate = synth_lerpf(a->turn_rate, b->turn_rate, e);
    out->gait = synth_lerpf(a->gait, b->gait, e);
    out->activity = synth_lerpf(a->activity, b->activity, e);
    if (accel) *accel = (b->speed - a->speed) * 30.0f * x * x * (1.0f - x) * (1.0f - x) / span;
}

float synth_turn_lean(float speed, float curvature)
{
    /* People lean a little less than the full centripetal angle. */
    return 0.8f * atanf(speed * speed * curvature / SYNTH_GRAVITY);
}

void *synth_work_get(synth_ctx *ctx, int slot, size_t bytes)
{
    synth_work *w = &ctx->work;
    if (w->capacity[slot] >= bytes) return w->mem[slot];
    mm_free(ctx->allocator, w->mem[slot]);
    w->capacity[slot] = 0;
    w->mem[slot] = mm_alloc(ctx->allocator, bytes);
    if (w->mem[slot]) w->capacity[slot] = bytes;
    return w->mem[slot];
}

void synth_work_free(synth_ctx *ctx)
{
    for (int i = 0; i < SYNTH_WORK_SLOTS; ++i) {
        mm_free(ctx->allocator, ctx->work.mem[i]);
        ctx->work.mem[i] = NULL;
        ctx->work.capacity[i] = 0;
    }
}

/* Time of the first sample whose phase reaches phi (linear between samples), clamped to the
 * simulated range. */
static float time_of_phase(const synth_track *tr, double phi)
{
    const synth_sample *s = tr->s;
    if (phi <= s[0].phi) return tr->t0;
    if (phi > s[tr->count - 1].phi) return tr->t0 + (float)(tr->count - 1) * tr->dt;
    int lo = 0, hi = tr->count - 1; /* s[lo].phi < phi <= s[hi].phi */
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (s[mid].phi < phi)
            lo = mid;
        else
            hi = mid;
    }
    double f = (phi - s[lo].phi) / (s[hi].phi - s[lo].phi);
    return tr->t0 + ((float)lo + (float)f) * tr->dt;
}

/* Trajectory position and heading at time t (linear between samples). */
static void track_at(const synth_track *tr, float t, mm_vec3 *pos, float *heading)
{
    float x = (t - tr->t0) / tr->dt;
    int i = (int)floorf(x);
    if (i < 0) i = 0;
    if (i > tr->count - 2) i = tr->count - 2;
    double f = synth_clampf(x - (float)i, 0.0f, 1.0f);
    const synth_sample *a = &tr->s[i], *b = &tr->s[i + 1];
    *pos = mm_vec3_make((float)(a->x + (b->x - a->x) * f), 0.0f, (float)(a->z + (b->z - a->z) * f));
    *heading = (float)(a->heading + (b->heading - a->heading) * f);
}

static void gait_at(const synth_ctx *ctx, const synth_key *k, synth_gait *g)
{
    synth_gait_eval(&ctx->body, &ctx->style, k->speed, k->gait, k->activity, k->turn_rate, k->direction, g);
}

/* The plant of a stance in which the character stands still at time t. */
static void rest_plant(const synth_ctx *ctx, const synth_track *tr, int side, float t, synth_stance *st)
{
    mm_vec3 pos;
    float heading;
    track_at(tr, t, &pos, &heading);
    float s = synth_side_sign(side);
    mm_vec3 lateral =
        mm_quat_rotate(synth_rot_y(heading), mm_vec3_make(s * ctx->style.stand_width, 0.0f, 0.0f));
    st->plant = mm_vec3_add(pos, lateral);
    st->plant.y = ctx->body.ankle_height;
    st->yaw = heading + s * ctx->style.toe_out;
}

/* Keeps a standing phase inside the flat part of a stance (and drops rockers it leaves no room
 * for). */
static void clamp_rest(synth_stance *st, double phi_rest)
{
    float u = (float)((phi_rest - st->phi_td) / (st->phi_lo - st->phi_td));
    if (st->u1 > u - 0.03f) st->u1 = u - 0.03f;
    if (st->u1 < 0.03f) {
        st->u1 = 0.0f;
        st->beta_td = 0.0f;
    }
    if (st->u2 < u + 0.03f) st->u2 = u + 0.03f;
    if (st->u2 > 0.97f) {
        st->u2 = 1.0f;
        st->beta_lo = 0.0f;
    }
}

static void plan_stance(const synth_ctx *ctx, const synth_track *tr, int side, double phi_td,
                        synth_stance *st)
{
    const synth_plan *plan = tr->plan;
    memset(st, 0, sizeof *st);
    synth_key k_td, k_lo, k_ref;
    synth_gait g_td, g_lo, g_ref;
    float t_td = time_of_phase(tr, phi_td);
    synth_plan_values(plan, t_td, &k_td, NULL);
    gait_at(ctx, &k_td, &g_td);
    st->phi_td = phi_td;
    st->phi_lo = phi_td + g_td.duty;
    float t_lo = time_of_phase(tr, st->phi_lo);
    synth_plan_values(plan, t_lo, &k_lo, NULL);
    gait_at(ctx, &k_lo, &g_lo);

    /* Rockers: heel first and toe last when walking forwards, the reverse backwards, flat
     * sideways and on the spot. */
    st->beta_td = g_td.heel_strike * synth_roll_scale(k_td.speed) * cosf(k_td.direction);
    st->beta_lo = -g_lo.toe_off * synth_roll_scale(k_lo.speed) * cosf(k_lo.direction);
    st->u1 = g_td.roll_in;
    st->u2 = 1.0f - g_lo.roll_out;
    st->swing_height = g_lo.swing_height;
    st->swing_peak = g_lo.swing_peak;

    bool rest = false;
    if (tr->rest_start && phi_td <= tr->phi_rest_start && tr->phi_rest_start <= st->phi_lo) {
        rest_plant(ctx, tr, side, 0.0f, st);
        clamp_rest(st, tr->phi_rest_start);
        rest = true;
    }
    if (tr->rest_end && phi_td <= tr->phi_rest_end && tr->phi_rest_end <= st->phi_lo) {
        float t_end = (float)(tr->frames - 1) * (float)tr->substeps * tr->dt;
        if (!rest) rest_plant(ctx, tr, side, t_end, st);
        clamp_rest(st, tr->phi_rest_end);
        rest = true;
    }
    if (rest) return;

    /* Plant where the hip will be plant_ref through the stance (mirrored when walking backwards). */
    float ref = 0.5f + (g_td.plant_ref - 0.5f) * cosf(k_td.direction);
    float t_ref = time_of_phase(tr, phi_td + ref * g_td.duty);
    synth_plan_values(plan, t_ref, &k_ref, NULL);
    gait_at(ctx, &k_ref, &g_ref);
    mm_vec3 pos;
    float heading;
    track_at(tr, t_ref, &pos, &heading);
    float s = synth_side_sign(side);
    float width = synth_lerpf(ctx->style.stand_width, g_ref.width, synth_clampf(k_ref.activity, 0.0f, 1.0f));
    float lateral_stride = fabsf(k_ref.speed * sinf(k_ref.direction)) / g_ref.freq;
    float lean = synth_turn_lean(k_ref.speed, k_ref.curvature);
    float lean_shift = (g_ref.pelvis_height - ctx->body.ankle_height) * tanf(lean);
    float lateral = s * (width + 0.25f * lateral_stride) - lean_shift;
    st->plant = mm_vec3_add(pos, mm_quat_rotate(synth_rot_y(heading), mm_vec3_make(lateral, 0.0f, 0.0f)));
    st->plant.y = ctx->body.ankle_height;
    st->yaw = heading + s * ctx->style.toe_out;
}

mm_result synth_track_build(synth_ctx *ctx, const synth_plan *plan, synth_track *tr)
{
    memset(tr, 0, sizeof *tr);
    tr->plan = plan;
    const float fps = ctx->fps;
    synth_key k0;
    synth_gait g0;
    synth_plan_values(plan, 0.0f, &k0, NULL);
    gait_at(ctx, &k0, &g0);

    /* Output length. A gait loop holds a whole number of cycles in a whole number of frames. */
    float duration = plan->duration;
    if (plan->loop_cycles > 0) duration = (float)plan->loop_cycles / (k0.activity * g0.freq);
    if (plan->period > 0.0f) duration = plan->period;
    int frames = (int)lroundf(duration * fps);
    if (!plan->loop) frames += 1;
    if (frames < 2) frames = 2;
    tr->frames = frames;
    tr->substeps = (int)ceilf(SYNTH_SIM_HZ / fps);
    tr->dt = 1.0f / (fps * (float)tr->substeps);
    int pre = (int)ceilf(SYNTH_PREROLL / tr->dt);
    int span = (plan->loop ? frames : frames - 1) * tr->substeps; /* samples from t = 0 to the end */
    tr->zero = pre;
    tr->count = pre + span + pre + 1;
    tr->t0 = -(float)pre * tr->dt;

    /* Memory: samples, then the stances of both feet. */
    size_t stance_cap = 8 + (size_t)(3.0f * (float)tr->count * tr->dt * 2.5f);
    size_t bytes = (size_t)tr->count * sizeof(synth_sample) + 2 * stance_cap * sizeof(synth_stance);
    tr->s = (synth_sample *)synth_work_get(ctx, 0, bytes);
    if (!tr->s) return MM_ERR_OUT_OF_MEMORY;
    tr->stance[0] = (synth_stance *)(tr->s + tr->count);
    tr->stance[1] = tr->stance[0] + stance_cap;

    /* Integrate the trajectory and the raw phase (midpoint rule). */
    double x = 0.0, z = 0.0, heading = 0.0, raw = 0.0;
    for (int i = 0; i < tr->count; ++i) {
        synth_sample *s = &tr->s[i];
        s->x = x;
        s->z = z;
        s->heading = heading;
        s->phi = raw;
        if (i + 1 == tr->count) break;
        synth_key k;
        synth_gait g;
        synth_plan_values(plan, tr->t0 + ((float)i + 0.5f) * tr->dt, &k, NULL);
        gait_at(ctx, &k, &g);
        double turn = (double)k.speed * k.curvature + k.turn_rate;
        double mid = heading + 0.5 * turn * tr->dt + k.direction;
        x += (double)k.speed * tr->dt * sin(mid);
        z += (double)k.speed * tr->dt * cos(mid);
        heading += turn * tr->dt;
        raw += (double)synth_clampf(k.activity, 0.0f, 1.0f) * g.freq * tr->dt;
    }
    /* Put the root at the origin facing +Z at t = 0. */
    const synth_sample origin = tr->s[tr->zero];
    double c = cos(-origin.heading), sn = sin(-origin.heading);
    for (int i = 0; i < tr->count; ++i) {
        synth_sample *s = &tr->s[i];
        double dx = s->x - origin.x, dz = s->z - origin.z;
        s->x = c * dx + sn * dz;
        s->z = -sn * dx + c * dz;
        s->heading -= origin.heading;
    }

    /* Phase: offset and scale. */
    const synth_key *klast = &plan->keys[plan->key_count - 1];
    tr->rest_start = plan->keys[0].activity <= 0.0f;
    tr->rest_end = klast->activity <= 0.0f && !plan->loop;
    int lead = plan->lead == SYNTH_RIGHT ? SYNTH_RIGHT : SYNTH_LEFT;
    tr->foot_offset[lead] = 0.0f;
    tr->foot_offset[1 - lead] = 0.5f;
    synth_gait grest;
    synth_gait_eval(&ctx->body, &ctx->style, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, &grest);
    /* Double supports start at every touchdown (multiples of 0.5) and last duty - 0.5. */
    double window_mid = 0.5 * (grest.duty - 0.5);
    double i0 = tr->s[tr->zero].phi, i1 = tr->s[tr->zero + span].phi, total = i1 - i0;
    double phi0 = 0.0, scale = 1.0;
    if (plan->loop_cycles > 0) {
        scale = total > 0.0 ? (double)plan->loop_cycles / total : 1.0;
    } else if (plan->period > 0.0f) {
        /* a whole number of cycles per period (the cadence changes by a few per cent) */
        double cycles = floor(total + 0.5);
        scale = total > 0.0 ? (cycles < 1.0 ? 1.0 : cycles) / total : 1.0;
    } else if (tr->rest_start) {
        phi0 = 0.5 + window_mid; /* the lead foot's stance is the one that ends first */
        if (tr->rest_end && total > 1e-6) {
            double n = floor((total - window_mid) / 0.5 + 0.5);
            if (n < 1.0) n = 1.0;
            scale = (n * 0.5) / total;
        }
    } else if (tr->rest_end) {
        double n = ceil((total - window_mid) / 0.5);
        phi0 = n * 0.5 + window_mid - total;
    }
    for (int i = 0; i < tr->count; ++i) tr->s[i].phi = phi0 + scale * (tr->s[i].phi - i0);
    tr->phi_rest_start = tr->s[tr->zero].phi;
    tr->phi_rest_end = tr->s[tr->zero + span].phi;

    /* Footsteps. */
    double phi_min = tr->s[0].phi, phi_max = tr->s[tr->count - 1].phi;
    for (int side = 0; side < 2; ++side) {
        double off = tr->foot_offset[side];
        int k_first = (int)floor(phi_min - off) - 1, k_last = (int)ceil(phi_max - off) + 1;
        int n = 0;
        for (int k = k_first; k <= k_last; ++k) {
            if ((size_t)n >= stance_cap) return MM_ERR_LIMIT;
            plan_stance(ctx, tr, side, off + k, &tr->stance[side][n++]);
        }
        tr->stance_count[side] = n;
    }
    return MM_OK;
}

/* ---- evaluating a foot ------------------------------------------------------------------ */

/* Rocker profile on q in [0, 1]: starts flat (zero slope), ends with slope ROCKER_END_SLOPE. */
#define ROCKER_END_SLOPE 0.8f
static float rocker(float q)
{
    const float w = 1.0f - 0.5f * ROCKER_END_SLOPE; /* blend of smoothstep (end slope 0) and q^2 (2) */
    return w * q * q * (3.0f - 2.0f * q) + (1.0f - w) * q * q;
}

static float stance_beta(const synth_stance *st, float u)
{
    if (u < st->u1) return st->beta_td * rocker(1.0f - u / st->u1);
    if (u > st->u2) return st->beta_lo * rocker((u - st->u2) / (1.0f - st->u2));
    return 0.0f;
}

/* d(beta)/d(phase) at liftoff and touchdown. */
static float beta_rate_lo(const synth_stance *st)
{
    if (st->u2 >= 1.0f) return 0.0f;
    return ROCKER_END_SLOPE * st->beta_lo / ((1.0f - st->u2) * (float)(st->phi_lo - st->phi_td));
}
static float beta_rate_td(const synth_stance *st)
{
    if (st->u1 <= 0.0f) return 0.0f;
    return -ROCKER_END_SLOPE * st->beta_td / (st->u1 * (float)(st->phi_lo - st->phi_td));
}

/* Reach margins near liftoff and touchdown: the knee is already flexing when the toe leaves
 * the ground and not quite straight when the heel lands (no snap through full extension). */
#define SYNTH_MARGIN_LO 0.02f
#define SYNTH_MARGIN_TD 0.008f

static float stance_margin(const synth_stance *st, float u)
{
    float m = 0.0f;
    if (u < st->u1 && st->beta_td != 0.0f) {
        float q = 1.0f - u / st->u1;
        m += SYNTH_MARGIN_TD * q * q;
    }
    if (u > st->u2 && st->beta_lo != 0.0f) {
        float q = (u - st->u2) / (1.0f - st->u2);
        m += SYNTH_MARGIN_LO * q * q;
    }
    return m;
}

static float swing_bump(float s, float peak)
{
    /* s^2 (1-s)^b peaks at 2 / (2 + b); normalised to 1 there. */
    float b = 2.0f * (1.0f - peak) / peak;
    float norm = peak * peak * powf(1.0f - peak, b);
    return s * s * powf(1.0f - s, b) / norm;
}

void synth_track_foot(const synth_body *b, const synth_track *tr, int side, double phi, synth_foot *out)
{
    const synth_stance *st = tr->stance[side];
    int n = tr->stance_count[side];
    int lo = 0, hi = n - 1; /* last stance with phi_td <= phi */
    if (phi < st[0].phi_td) hi = 0;
    while (lo < hi) {
        int mid = (lo + hi + 1) / 2;
        if (st[mid].phi_td <= phi)
            lo = mid;
        else
            hi = mid - 1;
    }
    const synth_stance *a = &st[lo];
    if (phi <= a->phi_lo || lo == n - 1) {
        float u = synth_clampf((float)((phi - a->phi_td) / (a->phi_lo - a->phi_td)), 0.0f, 1.0f);
        float beta = stance_beta(a, u);
        out->ankle = synth_foot_pivot(b, a->plant, a->yaw, beta);
        out->yaw = a->yaw;
        out->pitch = beta;
        out->toe_angle = beta < 0.0f ? beta : 0.0f;
        out->heel = beta >= 0.0f;
        out->toe = beta <= 0.0f;
        out->margin = stance_margin(a, u);
        return;
    }
    const synth_stance *c = &st[lo + 1];
    float span = (float)(c->phi_td - a->phi_lo);
    float s = synth_clampf((float)((phi - a->phi_lo) / span), 0.0f, 1.0f);
    float b0 = a->beta_lo, b1 = c->beta_td;
    float r0 = beta_rate_lo(a) * span, r1 = beta_rate_td(c) * span;
    mm_vec3 p0 = synth_foot_pivot(b, a->plant, a->yaw, b0);
    mm_vec3 p1 = synth_foot_pivot(b, c->plant, c->yaw, b1);
    mm_vec3 v0 = mm_vec3_scale(synth_foot_pivot_d(b, a->yaw, b0), r0);
    mm_vec3 v1 = mm_vec3_scale(synth_foot_pivot_d(b, c->yaw, b1), r1);
    out->ankle = synth_vec3_hermite5(p0, v0, p1, v1, s);
    out->ankle.y += a->swing_height * swing_bump(s, a->swing_peak);
    float yaw1 = a->yaw + synth_wrap_angle(c->yaw - a->yaw);
    out->yaw = synth_hermite(a->yaw, 0.0f, yaw1, 0.0f, s);
    /* Angles: an eased blend from liftoff to touchdown, plus terms that carry the rocker
     * rates a little way into the swing and decay (the foot keeps rolling just after toe-off
     * and is still rolling at heel strike), so the rotation is C1 without overshooting. */
    float carry0 = s * (1.0f - s) * (1.0f - s) * (1.0f - s), carry1 = -(1.0f - s) * s * s * s;
    out->pitch = synth_hermite(b0, 0.0f, b1, 0.0f, s) + r0 * carry0 + r1 * carry1;
    float t0 = b0 < 0.0f ? b0 : 0.0f, t1 = b1 < 0.0f ? b1 : 0.0f;
    out->toe_angle = synth_hermite(t0, 0.0f, t1, 0.0f, s) + (b0 < 0.0f ? r0 : 0.0f) * carry0 +
                     (b1 < 0.0f ? r1 : 0.0f) * carry1;
    out->heel = false;
    out->toe = false;
    float m0 = a->beta_lo != 0.0f ? SYNTH_MARGIN_LO : 0.0f, m1 = c->beta_td != 0.0f ? SYNTH_MARGIN_TD : 0.0f;
    out->margin = synth_hermite(m0, 0.0f, m1, 0.0f, s);
}
