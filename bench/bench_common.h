/* What the benchmarks share: a monotonic clock, an ordering of doubles for qsort and random numbers
 * (the same sequence in every run). */
#ifndef MM_BENCH_COMMON_H
#define MM_BENCH_COMMON_H

#include <math.h>
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

#endif
