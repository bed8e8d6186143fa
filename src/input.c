#include <mm/input.h>

#include <math.h>
#include <string.h>

/* the most keys a script may hold: far more than hours of input, under any int overflow */
#define MAX_SCRIPT_KEYS (1 << 24)
/* the largest squared stick length accepted: the unit circle, with room for a float's rounding in JSON */
#define MAX_STICK_LENGTH_SQ 1.0002f
/* how far from 1 a facing's length may be: rounding of a unit direction written in JSON */
#define FACING_LENGTH_TOLERANCE 1e-3f

/* The random scripts (mm_input_script_random). */
/* s: the longest script (about 11 days): a larger one is a unit mistake */
#define MAX_RANDOM_SECONDS 1e6f
/* s: the shortest hold of a key: the exponential holds start there */
#define MIN_HOLD 0.1
/* keys per second at most: 1 / MIN_HOLD */
#define MAX_KEYS_PER_SECOND 10.0f
/* keys beyond seconds x MAX_KEYS_PER_SECOND: the key at 0 and the rounding down */
#define KEYS_SLACK 2
/* the chance a key that moves holds the stick part way (a walk slower than the gait's) */
#define PARTIAL_STICK_CHANCE 0.25
/* such a stick's length: uniform from this to 1 (0.3 + 0.7) */
#define PARTIAL_STICK_MIN   0.3
#define PARTIAL_STICK_RANGE 0.7

mm_result mm_input_script_init(mm_input_script *s, int key_count, const mm_allocator *allocator)
{
    if (!s) return MM_ERR_INVALID_ARGUMENT;
    memset(s, 0, sizeof *s);
    if (allocator) s->allocator = *allocator;
    if (key_count < 0 || key_count > MAX_SCRIPT_KEYS) return MM_ERR_LIMIT;
    if (key_count == 0) return MM_OK;
    s->keys = (mm_input_key *)mm_alloc_array(&s->allocator, (size_t)key_count, sizeof(mm_input_key));
    if (!s->keys) return MM_ERR_OUT_OF_MEMORY;
    s->key_count = key_count;
    return MM_OK;
}

void mm_input_script_free(mm_input_script *s)
{
    if (!s) return;
    mm_allocator a = s->allocator;
    mm_free(&a, s->keys);
    memset(s, 0, sizeof *s);
}

mm_result mm_input_script_validate(const mm_input_script *s, mm_error *err)
{
    if (!s || (s->key_count > 0 && !s->keys))
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no script");
    for (int i = 0; i < s->key_count; ++i) {
        const mm_input_key *k = &s->keys[i];
        if (!isfinite(k->t) || k->t < 0.0f)
            return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "keys[%d].t: %g is not a time >= 0", i, k->t);
        if (i > 0 && !(k->t > s->keys[i - 1].t))
            return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "keys[%d].t: %g does not come after %g", i,
                                k->t, s->keys[i - 1].t);
        const float *st = k->input.stick;
        if (!isfinite(st[0]) || !isfinite(st[1]) || st[0] * st[0] + st[1] * st[1] > MAX_STICK_LENGTH_SQ)
            return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0,
                                "keys[%d].stick: [%g, %g] is not within the unit circle", i, st[0], st[1]);
        if ((int)k->input.gait < 0 || k->input.gait >= MM_GAIT_COUNT)
            return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "keys[%d].gait: unknown gait", i);
        if (k->input.has_facing) {
            const float *f = k->input.facing;
            float len = isfinite(f[0]) && isfinite(f[1]) ? sqrtf(f[0] * f[0] + f[1] * f[1]) : 0.0f;
            if (!(fabsf(len - 1.0f) < FACING_LENGTH_TOLERANCE))
                return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0,
                                    "keys[%d].facing: [%g, %g] is not a unit direction", i, f[0], f[1]);
        }
    }
    return MM_OK;
}

/* The last key with k.t <= t (-1: none, or t NaN). */
static int last_key(const mm_input_script *s, float t)
{
    if (!s || s->key_count == 0 || !(t >= s->keys[0].t)) return -1;
    int lo = 0, hi = s->key_count - 1;
    while (lo < hi) {
        int mid = (lo + hi + 1) / 2;
        if (s->keys[mid].t <= t)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

void mm_input_script_sample(const mm_input_script *s, float t, mm_input *out)
{
    memset(out, 0, sizeof *out);
    out->gait = MM_GAIT_WALK;
    int k = last_key(s, t); /* before the first key, or NaN: neutral */
    if (k >= 0) *out = s->keys[k].input;
}

void mm_input_script_sample_tick(const mm_input_script *s, float t, float dt, mm_input *out)
{
    mm_input_script_sample(s, t, out);
    out->jump = false;
    if (!isfinite(dt) || !(dt >= 0.0f)) return;
    float from = t - dt;
    /* the keys in (from, t]; a first tick (from < 0) takes a key at time 0 too */
    for (int k = last_key(s, t); k >= 0 && !out->jump; --k) {
        if (s->keys[k].t <= from && !(from < 0.0f && s->keys[k].t <= 0.0f)) break;
        out->jump = s->keys[k].input.jump;
    }
}

/* A small seeded generator (xorshift64*): the same seed, the same script, everywhere. */
static double next_uniform(uint64_t *state)
{
    uint64_t x = *state;
    x ^= x >> 12;
    x ^= x << 25;
    x ^= x >> 27;
    *state = x;
    return (double)((x * 0x2545F4914F6CDD1DULL) >> 11) * (1.0 / 9007199254740992.0);
}

mm_result mm_input_script_random(mm_input_script *s, uint64_t seed, const mm_input_random_desc *desc)
{
    mm_input_random_desc d;
    memset(&d, 0, sizeof d);
    if (desc) d = *desc;
    float seconds = d.seconds > 0.0f ? d.seconds : 60.0f;
    float hold = d.mean_hold > 0.0f ? d.mean_hold : 1.5f;
    float run = d.run_chance == 0.0f ? 0.3f : (d.run_chance < 0.0f ? 0.0f : d.run_chance);
    float strafe = d.strafe_chance == 0.0f ? 0.1f : (d.strafe_chance < 0.0f ? 0.0f : d.strafe_chance);
    float idle = d.idle_chance == 0.0f ? 0.15f : (d.idle_chance < 0.0f ? 0.0f : d.idle_chance);
    if (!isfinite(seconds) || seconds > MAX_RANDOM_SECONDS || !isfinite(hold)) return MM_ERR_OUT_OF_RANGE;
    uint64_t state = seed * 0x9E3779B97F4A7C15ULL + 0x632BE59BD9B4E019ULL;
    if (!state) state = 1;
    /* keys at least MIN_HOLD apart */
    int capacity = (int)(seconds * MAX_KEYS_PER_SECOND) + KEYS_SLACK;
    mm_result r = mm_input_script_init(s, capacity, d.allocator);
    if (r != MM_OK) return r;
    int n = 0;
    double t = 0.0;
    while (t < seconds && n < capacity) {
        mm_input_key *k = &s->keys[n++];
        k->t = (float)t;
        double angle = 2.0 * MM_PI * next_uniform(&state),
               magnitude = next_uniform(&state) < idle ? 0.0 : 1.0;
        if (magnitude > 0.0 && next_uniform(&state) < PARTIAL_STICK_CHANCE)
            magnitude = PARTIAL_STICK_MIN + PARTIAL_STICK_RANGE * next_uniform(&state);
        k->input.stick[0] = (float)(magnitude * sin(angle));
        k->input.stick[1] = (float)(magnitude * cos(angle));
        k->input.gait = next_uniform(&state) < run ? MM_GAIT_RUN : MM_GAIT_WALK;
        k->input.strafe = next_uniform(&state) < strafe;
        if (k->input.strafe) {
            double f = 2.0 * MM_PI * next_uniform(&state);
            k->input.has_facing = true;
            k->input.facing[0] = (float)sin(f);
            k->input.facing[1] = (float)cos(f);
        }
        /* exponential holds, at least MIN_HOLD */
        t += MIN_HOLD + (hold - MIN_HOLD) * -log(1.0 - next_uniform(&state) * 0.999999);
    }
    s->key_count = n;
    return MM_OK;
}

mm_gait mm_input_gait(const mm_input *in)
{
    return in && (int)in->gait >= 0 && in->gait < MM_GAIT_COUNT ? in->gait : MM_GAIT_WALK;
}
