/* mm/distance_curve_build.h - making distance curves from a clip's root path (offline; the
 * mm_build library). The curves and their queries are in mm/distance_curve.h.
 *
 *   mm_distance_curve c;
 *   mm_distance_desc d = {0};
 *   d.positions = root_xz; d.components = 2; d.frame_count = n; d.fps = 30; d.loop = 0;
 *   mm_distance_curve_build(&c, &d, &err);               allocates once
 *   mm_distance_curve_free(&c);
 *
 * Functions: mm_distance_curve_build mm_distance_curve_free
 */
#ifndef MM_DISTANCE_CURVE_BUILD_H
#define MM_DISTANCE_CURVE_BUILD_H

#include "alloc.h"
#include "distance_curve.h"
#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Defaults: stop_speed 0.1 m/s; loop_step interpolated from the steps around the wrap. */
typedef struct mm_distance_desc {
    const float *positions; /* root positions, frame_count rows of `components` floats */
    int components;         /* 2: (x, z) per frame; 3: (x, y, z) per frame (y ignored) */
    int frame_count;        /* >= 2 */
    float fps;              /* > 0 */
    int loop;               /* nonzero: a loop clip */
    float stop_speed;       /* m/s; 0: MM_DISTANCE_STOP_SPEED_DEFAULT */
    float loop_step;        /* m: path from the last frame to the first when a loop wraps; 0: the
                             * cubic through the two steps before and the two after the wrap */
    const mm_allocator *allocator;
} mm_distance_desc;

/* Builds the curves (allocates one block; offline). Stops: each run of frames whose speed (mean
 * of the two adjacent ground steps, times fps) is below stop_speed marks the first frame of the
 * run whose speed is within a quarter of stop_speed of the run's lowest, moved on while the speed
 * keeps falling (the earliest moment at rest, or the bottom of a pivot). A run at the start of a
 * one-shot clip is not a stop (the clip starts from rest: its distance counts from the start). A
 * segment ends with the run after its marker (where the root speeds up again); the last one runs
 * to the end of the clip. err (may be NULL) says which frame or field is wrong.
 * MM_ERR_INVALID_ARGUMENT for bad sizes or parameters, MM_ERR_BAD_NUMBER for a non-finite
 * position, MM_ERR_OUT_OF_MEMORY. On failure c is zeroed. */
mm_result mm_distance_curve_build(mm_distance_curve *c, const mm_distance_desc *desc, mm_error *err);
void mm_distance_curve_free(mm_distance_curve *c);

#ifdef __cplusplus
}
#endif

#endif /* MM_DISTANCE_CURVE_BUILD_H */
