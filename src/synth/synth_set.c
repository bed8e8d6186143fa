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
    "idle", "walk",          "run",      "walk_arc", "run_arc",     "start",
    "stop", "turn_in_place", "sidestep", "backward", "gait_change", "jump"};

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

#define MAX_SPECS 40

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

    static const float walk_speeds[] = {1.05f, 1.40f, 1.75f};
    for (int i = 0; i < 3; ++i) {
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
        s->plan.keys[0] = key(0.0f, 0, 0, dir, 0, 0, 0);
        s->plan.keys[1] = key(0.6f, 0, 0, dir, 0, 0, 0);
        s->plan.keys[2] = key(1.1f, 0.2f, 0, dir, 0, 0, 1);
        s->plan.keys[3] = key(1.8f, 0.5f, 0, dir, 0, 0, 1);
        s->plan.keys[4] = key(3.6f, 0.5f, 0, dir, 0, 0, 1);
        s->plan.keys[5] = key(4.4f, 0.15f, 0, dir, 0, 0, 1);
        s->plan.keys[6] = key(4.9f, 0, 0, dir, 0, 0, 0);
        s->plan.key_count = 7;
        s->plan.duration = 6.0f;
        s->plan.lead = side == 0 ? SYNTH_LEFT : SYNTH_RIGHT;
        s->speed = 0.5f;
        s->direction = dir;
    }

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
