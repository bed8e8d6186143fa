/* test_distance_paths.h - root paths whose distance is known in closed form (a constant-speed
 * line, a spring coming to rest, a loop that stops, two stops), sampled into positions, and the
 * distance curve builder run on them with its validator; shared by the tests of the distance curves
 * and of distance matching. */
#ifndef MM_TEST_DISTANCE_PATHS_H
#define MM_TEST_DISTANCE_PATHS_H

#include <math.h>
#include <string.h>

#include <mm/distance_curve.h>
#include <mm/distance_curve_build.h>
#include <mm/spring.h>

#include "test_util.h"

#define MAX_CLIP 1024

/* A root path s(t) along the ground direction (dx, dz), sampled at fps, as 3D positions. */
typedef double (*path_fn)(double t);

static inline int sample_path(path_fn s, double dx, double dz, double fps, int frames, float *xyz)
{
    for (int i = 0; i < frames; ++i) {
        double v = s(i / fps);
        xyz[3 * i + 0] = (float)(dx * v);
        xyz[3 * i + 1] = 0.93f; /* a height, ignored */
        xyz[3 * i + 2] = (float)(dz * v);
    }
    return frames;
}

static inline mm_distance_curve build(const float *pos, int components, int frames, float fps, int loop)
{
    mm_distance_desc d;
    memset(&d, 0, sizeof d);
    d.positions = pos;
    d.components = components;
    d.frame_count = frames;
    d.fps = fps;
    d.loop = loop;
    mm_distance_curve c;
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_result r = mm_distance_curve_build(&c, &d, &err);
    if (r != MM_OK) print_error("build: %s\n", err.message);
    assert_int_equal(r, MM_OK);
    assert_int_equal(mm_distance_curve_validate(&c, &err), MM_OK);
    return c;
}

static inline double line(double t) { return 1.2 * t; }

/* Walks 1 s at 1.5 m/s, then the velocity decays with the project's spring (half-life 0.2 s):
 * x = 1.5 + v0 (1 - (1 + y t) e^(-y t)) / y + v0 t e^(-y t) ... in closed form below. */
static inline double spring_y(void) { return mm_spring_damping(0.2f); }
static inline double spring_stop(double t)
{
    if (t <= 1.0) return 1.5 * t;
    double y = spring_y(), u = t - 1.0, e = exp(-y * u);
    /* v(u) = v0 (1 + y u) e^(-y u); x(u) = v0 (2 - (2 + y u) e^(-y u)) / y */
    return 1.5 + 1.5 * (2.0 - (2.0 + y * u) * e) / y;
}

/* A loop that comes to rest `stops` times per cycle, once exactly at the wrap:
 * v(t) = 0.7 (1 - cos(2 pi stops t / T)), s(t) = 0.7 (t - T / (2 pi stops) sin(2 pi stops t / T)). */
static double loop_T = 4.0;
static int loop_stops = 1;
static inline double stopping_loop(double t)
{
    double w = 2.0 * MM_PI * loop_stops / loop_T;
    return 0.7 * (t - sin(w * t) / w);
}

/* 1.4 m/s, brake at 1.4 m/s^2 to rest at t = 2, stand, speed up again from t = 3, brake to
 * rest at t = 6, stand to the end (7 s). */
static inline double two_stops(double t)
{
    if (t <= 1.0) return 1.4 * t;
    if (t <= 2.0) return 1.4 + 1.4 * (t - 1.0) - 0.7 * (t - 1.0) * (t - 1.0);
    if (t <= 3.0) return 2.1;
    if (t <= 4.0) return 2.1 + 0.7 * (t - 3.0) * (t - 3.0);
    if (t <= 5.0) return 2.8 + 1.4 * (t - 4.0);
    if (t <= 6.0) return 4.2 + 1.4 * (t - 5.0) - 0.7 * (t - 5.0) * (t - 5.0);
    return 4.9;
}

/* A loop of n frames once round a circle of radius r on the ground: (x, z) pairs into pos; frame n
 * would be frame 0 again. */
static inline void circle_loop(float *pos, int n, double r)
{
    for (int i = 0; i < n; ++i) {
        double a = 2.0 * MM_PI * i / n;
        pos[2 * i] = (float)(r * cos(a));
        pos[2 * i + 1] = (float)(r * sin(a));
    }
}

/* The stopping loop (stopping_loop) along -X, on and on (a loop whose root does not come back), at
 * z = 0.25: n frames at fps into pos as (x, z) pairs. */
static inline void stopping_loop_path(float *pos, int n, float fps)
{
    for (int i = 0; i < n; ++i) {
        pos[2 * i] = (float)-stopping_loop(i / fps);
        pos[2 * i + 1] = 0.25f;
    }
}

#endif /* MM_TEST_DISTANCE_PATHS_H */
