/* bench_soak: 16 characters on random input for one simulated hour (LAFAN1 via $MM_DATA_DIR, or
 * the built-in set). Every so often a tick gets hostile input: NaN or huge stick values, dt of 0,
 * negative, or a whole second. Reports the largest distance between the simulated trajectory and
 * the character's root, ticks whose pose holds a NaN (must be 0) and heap allocations after
 * start-up (must be 0: malloc is wrapped at link time, so every call from mm's libraries is counted).
 * usage: bench_soak [SECONDS] [CHARACTERS]   (defaults 3600 and 16). Exit 1 on a NaN or an
 * allocation; never fails on speed. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <mm/character.h>
#include <mm/input.h>

#include "../tests/test_databases.h"

#include "bench_common.h"

/* ---- allocation counting (-Wl,--wrap=malloc,...) ---------------------------------------------- */

static long allocations;
void *__real_malloc(size_t size);
void *__real_calloc(size_t count, size_t size);
void *__real_realloc(void *p, size_t size);
void *__wrap_malloc(size_t size);
void *__wrap_calloc(size_t count, size_t size);
void *__wrap_realloc(void *p, size_t size);
void *__wrap_malloc(size_t size)
{
    ++allocations;
    return __real_malloc(size);
}
void *__wrap_calloc(size_t count, size_t size)
{
    ++allocations;
    return __real_calloc(count, size);
}
void *__wrap_realloc(void *p, size_t size)
{
    ++allocations;
    return __real_realloc(p, size);
}

/* ---- the soak --------------------------------------------------------------------------------- */

static uint64_t next_random(uint64_t *state) /* xorshift64* */
{
    *state ^= *state >> 12;
    *state ^= *state << 25;
    *state ^= *state >> 27;
    return *state * 2685821657736338717ull;
}

static int pose_has_nan(const mm_character *c)
{
    for (int j = 0; j < c->db->joint_count; ++j) {
        const mm_xform *x = &c->global[j];
        float sum = x->translation.x + x->translation.y + x->translation.z + x->rotation.x + x->rotation.y +
                    x->rotation.z + x->rotation.w;
        if (!isfinite(sum)) return 1;
    }
    return 0;
}

/* One tick in 500 is hostile; returns the dt to use and may spoil the input. */
static float hostile(uint64_t *rng, mm_input *in, float dt)
{
    if (next_random(rng) % 500 != 0) return dt;
    switch (next_random(rng) % 6) {
    case 0:
        in->stick[0] = NAN;
        return dt;
    case 1:
        in->stick[1] = 1e30f;
        return dt;
    case 2:
        in->stick[0] = -INFINITY;
        return dt;
    case 3:
        return 0.0f;
    case 4:
        return -dt;
    default:
        return 1.0f;
    }
}

int main(int argc, char **argv)
{
    double seconds = argc > 1 ? atof(argv[1]) : 3600.0;
    int n = argc > 2 ? atoi(argv[2]) : 16;
    if (!(seconds > 0.0)) seconds = 3600.0;
    if (n < 1) n = 1;
    mm_database db;
    int lafan = 0;
    if (test_build_real_database(&db, &lafan) != 0) return 1;
    mm_searcher s;
    if (mm_searcher_init(&s, &db, NULL, NULL) != MM_OK) return 1;
    mm_character *c = calloc((size_t)n, sizeof(mm_character));
    mm_input_script *scripts = calloc((size_t)n, sizeof(mm_input_script));
    if (!c || !scripts) return 1;
    for (int i = 0; i < n; ++i) {
        mm_input_random_desc rd = {(float)seconds, 0, 0, 0, 0, NULL};
        if (mm_input_script_random(&scripts[i], (uint64_t)i + 1, &rd) != MM_OK) return 1;
        if (mm_character_init(&c[i], &db, &s, NULL, NULL) != MM_OK) return 1;
    }
    printf("database: %s, %d frames; %d characters for %.0f simulated seconds\n",
           lafan ? "LAFAN1" : "built-in set", db.frame_count, n, seconds);

    const float dt = 1.0f / 60.0f;
    long ticks = (long)(seconds * 60.0), nan_ticks = 0, hostile_ticks = 0;
    double max_drift = 0.0, sum_drift = 0.0;
    uint64_t rng = 0x9e3779b97f4a7c15ull;
    long allocations_at_start = allocations;
    double start = now();
    for (long t = 0; t < ticks; ++t)
        for (int i = 0; i < n; ++i) {
            mm_input in;
            mm_input_script_sample(&scripts[i], (float)((double)t / 60.0), &in);
            float step = hostile(&rng, &in, dt);
            hostile_ticks +=
                step != dt || !isfinite(in.stick[0]) || !isfinite(in.stick[1]) || in.stick[1] > 1e29f;
            mm_character_update(&c[i], &in, step);
            nan_ticks += pose_has_nan(&c[i]);
            mm_vec3 a = c[i].trajectory->position, b = c[i].root.translation;
            double drift = hypot((double)a.x - b.x, (double)a.z - b.z);
            sum_drift += drift;
            if (drift > max_drift || !isfinite(drift)) max_drift = drift;
        }
    double elapsed = now() - start;
    long allocated = allocations - allocations_at_start;
    int searches = 0, transitions = 0;
    for (int i = 0; i < n; ++i) searches += c[i].searches, transitions += c[i].transitions;

    printf("%ld ticks x %d characters in %.1f s (%.2f us per character tick); %ld hostile ticks\n", ticks, n,
           elapsed, 1e6 * elapsed / ((double)ticks * n), hostile_ticks);
    printf("searches %d, transitions %d\n", searches, transitions);
    printf("simulation to character: max %.3f m, mean %.3f m\n", max_drift, sum_drift / ((double)ticks * n));
    printf("ticks with a NaN pose: %ld (must be 0)\n", nan_ticks);
    printf("allocations: %ld at start-up, %ld after (must be 0)\n", allocations_at_start, allocated);

    for (int i = 0; i < n; ++i) {
        mm_character_free(&c[i]);
        mm_input_script_free(&scripts[i]);
    }
    free(c);
    free(scripts);
    mm_searcher_free(&s);
    mm_database_free(&db);
    return nan_ticks == 0 && allocated == 0 ? 0 : 1;
}
