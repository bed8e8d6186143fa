/* distance_curve_private.h (private) - the double-precision readers of a distance curve that
 * the queries (src/db/distance_curve.c) and distance matching (src/runtime/distance_matching.c)
 * share, and the size limit the builder and the validator share. Times are seconds of clip time,
 * distances metres (mm/distance_curve.h).
 */
#ifndef MM_DB_DISTANCE_CURVE_PRIVATE_H
#define MM_DB_DISTANCE_CURVE_PRIVATE_H

#include <mm/distance_curve.h>

#define MM__DISTANCE_MAX_FRAMES (1 << 28)

/* The quick check every query makes: sizes, fps, arrays present, a finite path length. */
int mm__distance_usable(const mm_distance_curve *c);
/* Seconds of clip time (mm_distance_duration in double; c usable). */
double mm__distance_duration(const mm_distance_curve *c);
/* A finite time into the clip: [0, duration) for loops, [0, duration] for one-shots. */
double mm__distance_into_clip(const mm_distance_curve *c, double t);
/* mm_distance_time_after in double: from time t (into the clip for one-shots, any for loops) until
 * the root has travelled dist; unwrapped for loops. */
double mm__distance_time_after(const mm_distance_curve *c, double t, double dist);

#endif /* MM_DB_DISTANCE_CURVE_PRIVATE_H */
