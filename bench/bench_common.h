/* What the benchmarks share: a monotonic clock, an ordering of doubles for qsort, random numbers
 * (the same sequence in every run) and a sweep that makes caches cold. */
#ifndef MM_BENCH_COMMON_H
#define MM_BENCH_COMMON_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <time.h>

#include <mm/math.h>

/* Seconds on the monotonic clock. */
static inline double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* qsort's comparison of two doubles, ascending. */
static inline int compare(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Uniform in [0, 1): xorshift64 from a fixed seed, one sequence per program. */
static inline double uniform(void)
{
    static uint64_t rng = 0x9E3779B97F4A7C15ull;
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (double)(rng >> 11) / 9007199254740992.0;
}

/* Standard normal, by Box-Muller from two uniforms. */
static inline double normal(void)
{
    double u = uniform() + 1e-12, v = uniform();
    return sqrt(-2.0 * log(u)) * cos(2.0 * MM_PI * v);
}

/* bytes a cold-cache sweep goes over: more than the last-level cache of the machines we run on */
#define BENCH_COLD_SWEEP_BYTES (48u << 20)
#define BENCH_CACHE_LINE       64

/* Reads and writes every cache line of buffer (BENCH_COLD_SWEEP_BYTES): what a game's frame does to
 * the caches between two searches. */
static inline void bench_cold_sweep(unsigned char *buffer)
{
    for (size_t i = 0; i < BENCH_COLD_SWEEP_BYTES; i += BENCH_CACHE_LINE)
        buffer[i] = (unsigned char)(buffer[i] + 1);
}

#endif
