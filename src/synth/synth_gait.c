/* The gait model: cadence, duty factor, rockers, swing and body amplitudes as functions of speed,
 * blended between a walk and a run.
 *
 * Figures follow the gait literature for adults: walking cadence 105-120 steps/min for 1.0-1.8 m/s
 * with 60-63% stance, heel strike at about 20 degrees of foot angle, heel-off at ~55% of stance,
 * pelvic rotation +-4-6 degrees and obliquity +-4 degrees, vertical excursion of a few cm with the
 * pelvis highest at mid-stance; running cadence 165-180 steps/min with 35-42% stance, a flight
 * phase, the pelvis lowest at mid-stance, elbows near 90 degrees.
 */
#include <math.h>

#include "synth_internal.h"

float synth_roll_scale(float speed) { return synth_smooth(speed / 0.9f); }

static void walk_params(const synth_body *b, const synth_style *st, float v, synth_gait *g)
{
    const float deg = (float)MM_DEG_TO_RAD;
    v = synth_clampf(v, 0.0f, 2.4f);
    float steps = (1.45f + 0.30f * v) * st->cadence;
    g->freq = 0.5f * steps;
    g->duty = 0.66f - 0.035f * v;
    g->width = st->step_width;
    g->heel_strike = (10.0f + 7.0f * v) * deg;
    g->toe_off = (32.0f + 15.0f * v) * deg;
    g->roll_in = 0.15f;
    g->roll_out = 0.5f;
    g->swing_height = 0.035f + 0.025f * v;
    g->swing_peak = 0.45f;
    g->plant_ref = 0.37f;
    g->pelvis_height = b->ankle_height + synth_leg_length_at(b, 12.0f * deg) + 0.05f;
    g->bob = 0.012f * st->bob;
    g->sway = (0.032f - 0.008f * v) * st->sway;
    g->yaw = (2.5f + 2.0f * v) * deg * st->pelvis_rot;
    g->list = (2.5f + 1.5f * v) * deg * st->pelvis_rot;
    g->lean = (1.5f + 2.0f * v) * deg * st->lean;
    g->counter = 1.35f;
    g->arm_swing = (5.0f + 10.0f * v) * deg * st->arm_swing;
    g->arm_carry = -2.0f * deg;
    g->arm_abduct = 7.0f * deg;
    g->elbow = st->elbow + 4.0f * v * deg;
    g->elbow_swing = (4.0f + 6.0f * v) * deg;
}

static void run_params(const synth_body *b, const synth_style *st, float v, synth_gait *g)
{
    const float deg = (float)MM_DEG_TO_RAD;
    v = synth_clampf(v, 1.5f, 6.0f);
    float steps = (2.6f + 0.10f * v) * st->cadence;
    g->freq = 0.5f * steps;
    g->duty = 0.34f - 0.0375f * (v - 3.0f);
    g->width = 0.6f * st->step_width;
    g->heel_strike = 7.0f * deg;
    g->toe_off = (45.0f + 3.0f * v) * deg;
    g->roll_in = 0.2f;
    g->roll_out = 0.6f;
    g->swing_height = 0.10f + 0.05f * v;
    g->swing_peak = 0.36f;
    g->plant_ref = 0.3f;
    g->pelvis_height = b->ankle_height + synth_leg_length_at(b, 25.0f * deg) + 0.05f;
    g->bob = -0.03f * st->bob;
    g->sway = 0.012f * st->sway;
    g->yaw = (5.0f + 1.0f * v) * deg * st->pelvis_rot;
    g->list = 4.0f * deg * st->pelvis_rot;
    g->lean = (5.0f + 1.5f * (v - 3.0f)) * deg * st->lean;
    g->counter = 1.5f;
    g->arm_swing = (30.0f + 4.0f * (v - 3.0f)) * deg * st->arm_swing;
    g->arm_carry = -4.0f * deg;
    g->arm_abduct = 10.0f * deg;
    g->elbow = (82.0f + 2.0f * (v - 3.0f)) * deg;
    g->elbow_swing = 14.0f * deg;
}

void synth_gait_eval(const synth_body *b, const synth_style *st, float speed, float gait, float activity,
                     float turn_rate, float direction, synth_gait *out)
{
    synth_gait w, r;
    gait = synth_clampf(gait, 0.0f, 1.0f);
    walk_params(b, st, speed, &w);
    if (gait > 0.0f) {
        run_params(b, st, speed, &r);
#define SYNTH_BLEND(f) w.f = synth_lerpf(w.f, r.f, gait)
        SYNTH_BLEND(freq);
        SYNTH_BLEND(duty);
        SYNTH_BLEND(width);
        SYNTH_BLEND(heel_strike);
        SYNTH_BLEND(toe_off);
        SYNTH_BLEND(roll_in);
        SYNTH_BLEND(roll_out);
        SYNTH_BLEND(swing_height);
        SYNTH_BLEND(swing_peak);
        SYNTH_BLEND(plant_ref);
        SYNTH_BLEND(pelvis_height);
        SYNTH_BLEND(bob);
        SYNTH_BLEND(sway);
        SYNTH_BLEND(yaw);
        SYNTH_BLEND(list);
        SYNTH_BLEND(lean);
        SYNTH_BLEND(counter);
        SYNTH_BLEND(arm_swing);
        SYNTH_BLEND(arm_carry);
        SYNTH_BLEND(arm_abduct);
        SYNTH_BLEND(elbow);
        SYNTH_BLEND(elbow_swing);
#undef SYNTH_BLEND
    }
    /* Stepping on the spot while turning: a little quicker. */
    w.freq += 0.12f * fabsf(turn_rate);
    /* Sideways: quicker, shorter steps (the feet must not cross, so every step spans the
     * stance width plus the lateral stride). */
    w.freq *= 1.0f + 0.35f * fabsf(sinf(direction));
    /* Amplitudes of the gait grow with the activity; standing has none. */
    float a = synth_clampf(activity, 0.0f, 1.0f);
    w.bob *= a;
    w.sway *= a;
    w.yaw *= a;
    w.list *= a;
    w.arm_swing *= a;
    w.elbow_swing *= a;
    *out = w;
}
