/* The built-in clip set and the public API.
 *
 * Every clip is a control plan (see synth_plan.c) or the jump; the nominal speeds, radii and
 * angles written into the metadata are exactly the plan's inputs.
 */
#include <math.h>
#include <string.h>

#include <mm/bvh.h>

#include "synth_internal.h"

static const char *const kind_names[MM_SYNTH_KIND_COUNT] = {
    "idle",          "walk",     "run",      "walk_arc",    "run_arc", "start",    "stop",
    "turn_in_place", "sidestep", "backward", "gait_change", "jump",    "turn_loop"};

const char *mm_synth_kind_name(mm_synth_kind kind)
{
    return (unsigned)kind < MM_SYNTH_KIND_COUNT ? kind_names[kind] : NULL;
}

int mm_synth_contact_ranges(const mm_synth_clip *clip, unsigned flag, int *out_ranges, int max_ranges)
{
    int n = 0, start = -1;
    for (int f = 0; f <= clip->clip.frame_count; ++f) {
        bool on = f < clip->clip.frame_count && (clip->contacts[f] & flag) != 0;
        if (on && start < 0) start = f;
        if (!on && start >= 0) {
            if (out_ranges && n < max_ranges) {
                out_ranges[2 * n] = start;
                out_ranges[2 * n + 1] = f - 1;
            }
            ++n;
            start = -1;
        }
    }
    return n;
}

/* ---- the clip list ---------------------------------------------------------------------- */

typedef struct clip_spec {
    char name[MM_SYNTH_NAME_MAX];
    mm_synth_kind kind;
    synth_plan plan;
    float speed, radius, angle, direction;
    float jump_distance; /* > 0: the jump */
} clip_spec;

#define MAX_SPECS 48

/* Appends value with the given number of decimals (locale-independent, value >= 0). */
static void append_fixed(char *buf, size_t size, float value, int decimals)
{
    long scale = 1;
    for (int i = 0; i < decimals; ++i) scale *= 10;
    long v = lroundf(fabsf(value) * (float)scale);
    char tmp[32];
    int n = 0;
    for (int i = 0; i < decimals; ++i, v /= 10) tmp[n++] = (char)('0' + v % 10);
    if (decimals > 0) tmp[n++] = '.';
    do {
        tmp[n++] = (char)('0' + v % 10);
        v /= 10;
    } while (v > 0 && n < 30);
    size_t len = strlen(buf);
    while (n > 0 && len + 1 < size) buf[len++] = tmp[--n];
    buf[len] = 0;
}

static void spec_name(clip_spec *s, const char *prefix, float value, int decimals, const char *suffix)
{
    s->name[0] = 0;
    strncat(s->name, prefix, sizeof s->name - 1);
    if (decimals >= 0) append_fixed(s->name, sizeof s->name, value, decimals);
    if (suffix) strncat(s->name, suffix, sizeof s->name - strlen(s->name) - 1);
}

static synth_key key(float t, float speed, float curvature, float direction, float turn_rate, float gait,
                     float activity)
{
    synth_key k;
    k.t = t;
    k.speed = speed;
    k.curvature = curvature;
    k.direction = direction;
    k.turn_rate = turn_rate;
    k.gait = gait;
    k.activity = activity;
    return k;
}

static clip_spec *add_spec(clip_spec *specs, int *n, mm_synth_kind kind)
{
    clip_spec *s = &specs[(*n)++];
    memset(s, 0, sizeof *s);
    s->kind = kind;
    return s;
}

static void loop_plan(const synth_ctx *ctx, clip_spec *s, float speed, float curvature, float direction,
                      float gait, float target_duration)
{
    synth_gait g;
    synth_gait_eval(&ctx->body, &ctx->style, speed, gait, 1.0f, 0.0f, direction, &g);
    s->plan.keys[0] = key(0.0f, speed, curvature, direction, 0.0f, gait, 1.0f);
    s->plan.key_count = 1;
    s->plan.loop = true;
    long cycles = lroundf(target_duration * g.freq);
    s->plan.loop_cycles = cycles < 2 ? 2 : (int)cycles;
    s->speed = speed;
    s->direction = direction;
    s->radius = curvature != 0.0f ? 1.0f / curvature : 0.0f;
}

/* A loop of sharp turns while walking or running: turn i (angles[i] rad, > 0 left) is centred
 * at (i + 0.5) * spacing; its turn rate eases up over half seconds and down again (so the heading
 * changes by exactly angles[i]) while the speed dips to dip * speed, as the runtime's velocity
 * spring does when the stick swings (a 90 degree swing passes through 1 / sqrt 2 of the speed).
 * Between turns the path is straight, shorter than the search's 1 s of trajectory, so straight
 * walking keeps its exact loops. */
static void turn_loop_plan(clip_spec *s, float speed, float dip, float gait, const float *angles, int turns,
                           float half, float spacing)
{
    int k = 0;
    for (int i = 0; i < turns; ++i) {
        float c = ((float)i + 0.5f) * spacing;
        s->plan.keys[k++] = key(c - half, speed, 0, 0, 0, gait, 1);
        s->plan.keys[k++] = key(c, dip * speed, 0, 0, angles[i] / half, gait, 1);
        s->plan.keys[k++] = key(c + half, speed, 0, 0, 0, gait, 1);
        s->angle += angles[i];
    }
    s->plan.key_count = k;
    s->plan.loop = true;
    s->plan.period = (float)turns * spacing;
    s->speed = speed;
}

/* Step response of the runtime's critically damped springs (mm/spring.h) from rest: 0 to 1 with
 * half-life h, and its time derivative. */
static float spring_step(float t, float h)
{
    float y = 2.0f * 0.69314718f / h;
    return 1.0f - (1.0f + y * t) * expf(-y * t);
}
static float spring_step_d(float t, float h)
{
    float y = 2.0f * 0.69314718f / h;
    return y * y * t * expf(-y * t);
}

/* A loop of walking about-turns (to the left; mirrored in the config) at speed, the stick swung straight back
 * twice per loop, every spacing seconds. The runtime's velocity spring (half-life vel_h) runs the speed down
 * through 0 and up again the other way while its facing spring (rot_h) turns the body half a circle, faster,
 * so that the body travels sideways for a moment. Four keys per turn: the start, a pair around the reversal
 * (where the travel direction flips at almost no speed, with the facing spring's turn rate there) and the
 * end; the rates are scaled so that each turn is exactly pi. */
static void about_turn_plan(clip_spec *s, float speed, float vel_h, float rot_h, float spacing)
{
    const float pi = SYNTH_PI;
    /* the reversal: the velocity spring half way (1 - (1 + x) e^-x = 1/2 at x = 1.6784) */
    float t0 = 1.6783470f * vel_h / (2.0f * 0.69314718f);
    /* key times in units of t0: few keys, as every key holds the speed still for a moment (a
     * jolt of the lean that follows the acceleration) */
    enum { N = 4 };
    static const float at[N] = {0.0f, 0.92f, 1.08f, 2.6f};
    float rate[N], total = 0.0f;
    for (int i = 0; i < N; ++i) {
        rate[i] = i == 0 || i == N - 1 ? 0.0f : pi * spring_step_d(at[i] * t0, rot_h);
        if (i > 0) total += 0.5f * (rate[i] + rate[i - 1]) * (at[i] - at[i - 1]) * t0;
    }
    int k = 0;
    for (int turn = 0; turn < 2; ++turn) {
        float start = ((float)turn + 0.25f) * spacing, heading = 0.0f;
        for (int i = 0; i < N; ++i) {
            float t = at[i] * t0, r = rate[i] * pi / total;
            if (i > 0) heading += 0.5f * (r + rate[i - 1] * pi / total) * (at[i] - at[i - 1]) * t0;
            float v = i == N - 1 ? -1.0f : 1.0f - 2.0f * spring_step(t, vel_h); /* along the old way */
            float dir = i == N - 1 ? 0.0f : (v >= 0.0f ? 0.0f : pi) - heading;
            s->plan.keys[k++] = key(start + t, fabsf(v) * speed, 0, dir, r, 0, 1);
        }
    }
    s->plan.key_count = k;
    s->plan.loop = true;
    s->plan.period = 2.0f * spacing;
    s->speed = speed;
    s->angle = 2.0f * pi;
}

/* The shared times of a start, a stretch at speed and a stop (seconds). */
#define GO_STOP_STAND_UNTIL 0.6f /* standing still until here */
#define GO_STOP_MOVE_AT     1.1f /* moving off at the start speed */
#define GO_STOP_HOLD_UNTIL  3.6f /* the speed held until here */
#define GO_STOP_DURATION    6.0f

/* What differs between them (seconds, m/s). */
typedef struct go_stop_timing {
    float start_speed;         /* at GO_STOP_MOVE_AT */
    float go_at, speed;        /* up to speed */
    float slow_at, slow_speed; /* slowed after GO_STOP_HOLD_UNTIL */
    float stand_at;            /* standing again */
} go_stop_timing;

/* The plan of a start, a stretch at speed and a stop in one direction (stand, go, hold, slow,
 * stand), the foot lead stepping first. */
static void start_go_stop_plan(clip_spec *s, float direction, const go_stop_timing *g, int lead)
{
    s->plan.keys[0] = key(0.0f, 0, 0, direction, 0, 0, 0);
    s->plan.keys[1] = key(GO_STOP_STAND_UNTIL, 0, 0, direction, 0, 0, 0);
    s->plan.keys[2] = key(GO_STOP_MOVE_AT, g->start_speed, 0, direction, 0, 0, 1);
    s->plan.keys[3] = key(g->go_at, g->speed, 0, direction, 0, 0, 1);
    s->plan.keys[4] = key(GO_STOP_HOLD_UNTIL, g->speed, 0, direction, 0, 0, 1);
    s->plan.keys[5] = key(g->slow_at, g->slow_speed, 0, direction, 0, 0, 1);
    s->plan.keys[6] = key(g->stand_at, 0, 0, direction, 0, 0, 0);
    s->plan.key_count = 7;
    s->plan.duration = GO_STOP_DURATION;
    s->plan.lead = lead;
    s->speed = g->speed;
    s->direction = direction;
}

static int build_specs(const synth_ctx *ctx, clip_spec *specs)
{
    int n = 0;
    const float pi = SYNTH_PI;
    clip_spec *s;

    s = add_spec(specs, &n, MM_SYNTH_IDLE);
    spec_name(s, "idle", 0, -1, NULL);
    s->plan.keys[0] = key(0, 0, 0, 0, 0, 0, 0);
    s->plan.key_count = 1;
    s->plan.loop = true;
    s->plan.duration = 8.0f;

    /* 1.20: the runtime's walk at 0.8 stick (1.5 m/s full) has an exact loop */
    static const float walk_speeds[] = {1.05f, 1.20f, 1.40f, 1.75f};
    for (int i = 0; i < 4; ++i) {
        s = add_spec(specs, &n, MM_SYNTH_WALK);
        spec_name(s, "walk_", walk_speeds[i], 2, NULL);
        loop_plan(ctx, s, walk_speeds[i], 0, 0, 0, 9.0f);
    }
    static const float run_speeds[] = {3.0f, 3.8f, 4.6f};
    for (int i = 0; i < 3; ++i) {
        s = add_spec(specs, &n, MM_SYNTH_RUN);
        spec_name(s, "run_", run_speeds[i], 2, NULL);
        loop_plan(ctx, s, run_speeds[i], 0, 0, 1, 7.0f);
    }
    static const float walk_radii[] = {1.5f, 3.0f}, run_radii[] = {4.0f, 8.0f};
    for (int i = 0; i < 2; ++i)
        for (int side = 0; side < 2; ++side) {
            float sgn = side == 0 ? 1.0f : -1.0f;
            s = add_spec(specs, &n, MM_SYNTH_WALK_ARC);
            spec_name(s, side == 0 ? "walk_arc_left_r" : "walk_arc_right_r", walk_radii[i], 1, NULL);
            loop_plan(ctx, s, 1.4f, sgn / walk_radii[i], 0, 0, 8.0f);
        }
    /* the runtime's full-stick walk (1.5 m/s) circling at 30 degrees a second, so that gentle turns keep an
     * exact arc rather than the ends of the sharp turns below */
    for (int side = 0; side < 2; ++side) {
        s = add_spec(specs, &n, MM_SYNTH_WALK_ARC);
        spec_name(s, side == 0 ? "walk_arc_left_r" : "walk_arc_right_r", 2.8f, 1, NULL);
        loop_plan(ctx, s, 1.5f, (side == 0 ? 1.0f : -1.0f) / 2.8f, 0, 0, 8.0f);
    }
    for (int i = 0; i < 2; ++i)
        for (int side = 0; side < 2; ++side) {
            float sgn = side == 0 ? 1.0f : -1.0f;
            s = add_spec(specs, &n, MM_SYNTH_RUN_ARC);
            spec_name(s, side == 0 ? "run_arc_left_r" : "run_arc_right_r", run_radii[i], 1, NULL);
            loop_plan(ctx, s, 3.5f, sgn / run_radii[i], 0, 1, 7.0f);
        }

    /* Starts and stops. */
    s = add_spec(specs, &n, MM_SYNTH_START);
    spec_name(s, "walk_start", 0, -1, NULL);
    s->plan.keys[0] = key(0.0f, 0, 0, 0, 0, 0, 0);
    s->plan.keys[1] = key(0.8f, 0, 0, 0, 0, 0, 0);
    s->plan.keys[2] = key(1.25f, 0.3f, 0, 0, 0, 0, 1);
    s->plan.keys[3] = key(2.6f, 1.4f, 0, 0, 0, 0, 1);
    s->plan.key_count = 4;
    s->plan.duration = 5.0f;
    s->speed = 1.4f;

    s = add_spec(specs, &n, MM_SYNTH_STOP);
    spec_name(s, "walk_stop", 0, -1, NULL);
    s->plan.keys[0] = key(0.0f, 1.4f, 0, 0, 0, 0, 1);
    s->plan.keys[1] = key(1.5f, 1.4f, 0, 0, 0, 0, 1);
    s->plan.keys[2] = key(2.9f, 0.25f, 0, 0, 0, 0, 1);
    s->plan.keys[3] = key(3.4f, 0, 0, 0, 0, 0, 0);
    s->plan.key_count = 4;
    s->plan.duration = 5.0f;
    s->speed = 1.4f;

    s = add_spec(specs, &n, MM_SYNTH_START);
    spec_name(s, "run_start", 0, -1, NULL);
    s->plan.keys[0] = key(0.0f, 0, 0, 0, 0, 0, 0);
    s->plan.keys[1] = key(0.8f, 0, 0, 0, 0, 0, 0);
    s->plan.keys[2] = key(1.25f, 0.5f, 0, 0, 0, 0.3f, 1);
    s->plan.keys[3] = key(3.0f, 3.8f, 0, 0, 0, 1, 1);
    s->plan.key_count = 4;
    s->plan.duration = 5.5f;
    s->speed = 3.8f;

    s = add_spec(specs, &n, MM_SYNTH_STOP);
    spec_name(s, "run_stop", 0, -1, NULL);
    s->plan.keys[0] = key(0.0f, 3.8f, 0, 0, 0, 1, 1);
    s->plan.keys[1] = key(1.0f, 3.8f, 0, 0, 0, 1, 1);
    s->plan.keys[2] = key(3.0f, 0.5f, 0, 0, 0, 0.1f, 1);
    s->plan.keys[3] = key(3.5f, 0, 0, 0, 0, 0, 0);
    s->plan.key_count = 4;
    s->plan.duration = 5.5f;
    s->speed = 3.8f;

    /* Quick starts and stops: the runtime's velocity spring (half-life 0.25 s walking, 0.4 s
     * running) reaches or leaves full speed in under a second, faster than the ones above. */
    s = add_spec(specs, &n, MM_SYNTH_START);
    spec_name(s, "walk_start_quick", 0, -1, NULL);
    s->plan.keys[0] = key(0.0f, 0, 0, 0, 0, 0, 0);
    s->plan.keys[1] = key(0.8f, 0, 0, 0, 0, 0, 0);
    s->plan.keys[2] = key(1.1f, 0.35f, 0, 0, 0, 0, 1);
    s->plan.keys[3] = key(1.8f, 1.5f, 0, 0, 0, 0, 1);
    s->plan.key_count = 4;
    s->plan.duration = 4.0f;
    s->speed = 1.5f;

    s = add_spec(specs, &n, MM_SYNTH_STOP);
    spec_name(s, "walk_stop_quick", 0, -1, NULL);
    s->plan.keys[0] = key(0.0f, 1.5f, 0, 0, 0, 0, 1);
    s->plan.keys[1] = key(1.2f, 1.5f, 0, 0, 0, 0, 1);
    s->plan.keys[2] = key(1.9f, 0.25f, 0, 0, 0, 0, 1);
    s->plan.keys[3] = key(2.3f, 0, 0, 0, 0, 0, 0);
    s->plan.key_count = 4;
    s->plan.duration = 3.6f;
    s->speed = 1.5f;

    s = add_spec(specs, &n, MM_SYNTH_START);
    spec_name(s, "run_start_quick", 0, -1, NULL);
    s->plan.keys[0] = key(0.0f, 0, 0, 0, 0, 0, 0);
    s->plan.keys[1] = key(0.8f, 0, 0, 0, 0, 0, 0);
    s->plan.keys[2] = key(1.15f, 0.6f, 0, 0, 0, 0.3f, 1);
    s->plan.keys[3] = key(2.3f, 3.8f, 0, 0, 0, 1, 1);
    s->plan.key_count = 4;
    s->plan.duration = 4.5f;
    s->speed = 3.8f;

    s = add_spec(specs, &n, MM_SYNTH_STOP);
    spec_name(s, "run_stop_quick", 0, -1, NULL);
    s->plan.keys[0] = key(0.0f, 3.8f, 0, 0, 0, 1, 1);
    s->plan.keys[1] = key(1.0f, 3.8f, 0, 0, 0, 1, 1);
    s->plan.keys[2] = key(2.2f, 0.4f, 0, 0, 0, 0, 1);
    s->plan.keys[3] = key(2.9f, 0, 0, 0, 0, 0, 0);
    s->plan.key_count = 4;
    s->plan.duration = 4.0f;
    s->speed = 3.8f;

    /* Turns on the spot: the turn rate ramps up in 0.5 s, holds, ramps down in 0.5 s, so the
     * heading changes by rate * (hold + 0.5). */
    static const float turn_angles[] = {90.0f, 180.0f}, turn_rates[] = {1.2f, 1.6f};
    for (int i = 0; i < 2; ++i)
        for (int side = 0; side < 2; ++side) {
            float sgn = side == 0 ? 1.0f : -1.0f;
            float angle = turn_angles[i] * (float)MM_DEG_TO_RAD, rate = turn_rates[i];
            float hold = angle / rate - 0.5f;
            s = add_spec(specs, &n, MM_SYNTH_TURN_IN_PLACE);
            spec_name(s, side == 0 ? "turn_left_" : "turn_right_", turn_angles[i], 0, NULL);
            s->plan.keys[0] = key(0.0f, 0, 0, 0, 0, 0, 0);
            s->plan.keys[1] = key(0.6f, 0, 0, 0, 0, 0, 0);
            s->plan.keys[2] = key(1.0f, 0, 0, 0, 0, 0, 1);
            s->plan.keys[3] = key(1.5f, 0, 0, 0, sgn * rate, 0, 1);
            s->plan.keys[4] = key(1.5f + hold, 0, 0, 0, sgn * rate, 0, 1);
            s->plan.keys[5] = key(2.0f + hold, 0, 0, 0, 0, 0, 1);
            s->plan.keys[6] = key(2.6f + hold, 0, 0, 0, 0, 0, 0);
            s->plan.key_count = 7;
            s->plan.duration = 3.6f + hold;
            s->plan.lead = side == 0 ? SYNTH_LEFT : SYNTH_RIGHT;
            s->angle = sgn * angle;
        }

    /* Sidesteps. */
    for (int side = 0; side < 2; ++side) {
        float dir = side == 0 ? 0.5f * pi : -0.5f * pi;
        s = add_spec(specs, &n, MM_SYNTH_SIDESTEP);
        spec_name(s, side == 0 ? "sidestep_left" : "sidestep_right", 0, -1, NULL);
        const go_stop_timing sidestep = {0.2f, 1.8f, 0.5f, 4.4f, 0.15f, 4.9f};
        start_go_stop_plan(s, dir, &sidestep, side == 0 ? SYNTH_LEFT : SYNTH_RIGHT);
    }

    /* Steps backward from standing and back to standing: the backward walk's start and stop
     * (without them a character standing, asked to walk backward, has no way into the walk). */
    s = add_spec(specs, &n, MM_SYNTH_SIDESTEP);
    spec_name(s, "backstep", 0, -1, NULL);
    const go_stop_timing backstep = {0.3f, 1.9f, 1.0f, 4.5f, 0.2f, 5.0f};
    start_go_stop_plan(s, pi, &backstep, SYNTH_LEFT);

    s = add_spec(specs, &n, MM_SYNTH_BACKWARD);
    spec_name(s, "walk_backward", 0, -1, NULL);
    loop_plan(ctx, s, 1.0f, 0, pi, 0, 8.0f);

    s = add_spec(specs, &n, MM_SYNTH_GAIT_CHANGE);
    spec_name(s, "walk_to_run", 0, -1, NULL);
    s->plan.keys[0] = key(0.0f, 1.6f, 0, 0, 0, 0, 1);
    s->plan.keys[1] = key(1.5f, 1.6f, 0, 0, 0, 0, 1);
    s->plan.keys[2] = key(3.2f, 3.4f, 0, 0, 0, 1, 1);
    s->plan.key_count = 3;
    s->plan.duration = 6.0f;
    s->speed = 3.4f;

    s = add_spec(specs, &n, MM_SYNTH_GAIT_CHANGE);
    spec_name(s, "run_to_walk", 0, -1, NULL);
    s->plan.keys[0] = key(0.0f, 3.4f, 0, 0, 0, 1, 1);
    s->plan.keys[1] = key(1.5f, 3.4f, 0, 0, 0, 1, 1);
    s->plan.keys[2] = key(3.3f, 1.5f, 0, 0, 0, 0, 1);
    s->plan.key_count = 3;
    s->plan.duration = 6.0f;
    s->speed = 3.4f;

    s = add_spec(specs, &n, MM_SYNTH_JUMP);
    spec_name(s, "jump", 0, -1, NULL);
    s->jump_distance = 1.0f;

    /* Sharp turns: the runtime's walk (1.5 m/s, velocity half-life 0.25 s) turns 90 degrees in
     * about 0.8 s, its run (3.8 m/s, 0.4 s) in about 1.4 s. */
    const float quarter = 0.5f * pi;
    static const float zig[2] = {1.0f, -1.0f}, same[4] = {1.0f, 1.0f, 1.0f, 1.0f};
    float angles[4];
    for (int i = 0; i < 4; ++i) angles[i] = zig[i % 2] * quarter;
    s = add_spec(specs, &n, MM_SYNTH_TURN_LOOP);
    spec_name(s, "walk_zigzag", 0, -1, NULL);
    turn_loop_plan(s, 1.5f, 0.71f, 0.0f, angles, 2, 0.5f, 1.5f);
    for (int i = 0; i < 4; ++i) angles[i] = same[i] * quarter;
    s = add_spec(specs, &n, MM_SYNTH_TURN_LOOP);
    spec_name(s, "walk_turns_left", 0, -1, NULL);
    turn_loop_plan(s, 1.5f, 0.71f, 0.0f, angles, 4, 0.5f, 1.6f);
    s = add_spec(specs, &n, MM_SYNTH_TURN_LOOP);
    spec_name(s, "run_turns_left", 0, -1, NULL);
    turn_loop_plan(s, 3.8f, 0.71f, 1.0f, angles, 4, 0.72f, 2.0f);
    s = add_spec(specs, &n, MM_SYNTH_TURN_LOOP);
    spec_name(s, "walk_about_turns", 0, -1, NULL);
    about_turn_plan(s, 1.5f, 0.25f, 0.2f, 1.8f);
    return n;
}

/* ---- generation ------------------------------------------------------------------------- */

void mm_synth_set_free(mm_synth_set *set)
{
    if (!set) return;
    for (int i = 0; i < set->clip_count; ++i) {
        mm_clip_free(&set->clips[i].clip);
        mm_free(&set->allocator, set->clips[i].contacts);
    }
    mm_free(&set->allocator, set->clips);
    memset(set, 0, sizeof *set);
}

mm_result mm_synth_generate(const mm_synth_desc *desc, mm_synth_set *out, mm_error *err)
{
    if (!out) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "synth: no output set");
    memset(out, 0, sizeof *out);
    mm_synth_desc d;
    memset(&d, 0, sizeof d);
    if (desc) d = *desc;
    if (d.fps == 0.0f) d.fps = 60.0f;
    if (!(d.fps >= 10.0f && d.fps <= 240.0f))
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "synth: fps %g is outside 10-240",
                            (double)d.fps);
    if (d.allocator) out->allocator = *d.allocator;

    synth_ctx ctx;
    memset(&ctx, 0, sizeof ctx);
    ctx.fps = d.fps;
    ctx.allocator = d.allocator;
    synth_body_init(&ctx.body);
    synth_style_init(&ctx.style, d.seed);
    mm_result r = mm_synth_skeleton(&ctx.skeleton, d.allocator);
    if (r != MM_OK) return mm_error_set(err, r, 0, 0, "synth: cannot build the skeleton");

    clip_spec specs[MAX_SPECS];
    int count = build_specs(&ctx, specs);
    out->clips = (mm_synth_clip *)mm_alloc_array(d.allocator, (size_t)count, sizeof(mm_synth_clip));
    if (!out->clips) {
        mm_skeleton_free(&ctx.skeleton);
        return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "synth: out of memory");
    }
    for (int i = 0; i < count && r == MM_OK; ++i) {
        const clip_spec *s = &specs[i];
        mm_synth_clip *c = &out->clips[i];
        out->clip_count = i + 1; /* a zeroed clip frees safely */
        if (s->jump_distance > 0.0f)
            r = synth_make_jump(&ctx, s->jump_distance, c);
        else
            r = synth_make_loco(&ctx, &s->plan, c);
        if (r != MM_OK) break;
        memcpy(c->name, s->name, sizeof c->name);
        c->kind = s->kind;
        c->speed = s->speed;
        c->turn_radius = s->radius;
        c->direction = s->direction;
        c->turn_angle = s->angle;
        if (s->plan.loop_cycles > 0 && s->radius != 0.0f)
            c->turn_angle = s->speed / s->radius * (float)c->clip.frame_count / d.fps;
    }
    synth_work_free(&ctx);
    mm_skeleton_free(&ctx.skeleton);
    if (r != MM_OK) {
        mm_synth_set_free(out);
        return mm_error_set(err, r, 0, 0, "synth: generation failed (%s)", mm_result_str(r));
    }
    return MM_OK;
}
