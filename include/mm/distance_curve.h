/* mm/distance_curve.h - distance curves: how far a clip's root has travelled, and how far it is
 * from its next stop or pivot, frame by frame (seed 003).
 *
 * A clip's distance curves are made offline from its root path (mm/distance_curve_build.h, in the
 * mm_build library; the database build makes one per clip and stores it in the .mmdb,
 * mm/database.h): the travelled
 * path length per frame (monotonic over the whole clip), and per segment the signed distance to
 * the segment's stop or pivot point (negative before it, 0 at it, positive after it). A stop or
 * pivot is where the root speed is lowest below a threshold; clips with several stops are split
 * into segments; loops keep growing across the wrap. The read-only queries below take a curve and
 * nothing else; distance matching (mm/distance_matching.h) moves a playhead with them.
 *
 *   mm_distance_curve c;
 *   mm_database_distance_curve(&db, clip, &c);           a view into the database
 *   float left = -mm_distance_signed(&c, t);             m to the stop ahead (no allocation)
 *
 * Units: metres, seconds; distances are measured on the ground plane (x, z), Y up. The queries
 * are free of allocation and give finite results for any input (NaN times, invalid curves).
 *
 * Functions: mm_distance_curve_validate mm_distance_duration mm_distance_travelled mm_distance_segment_at
 * mm_distance_signed mm_distance_time_after mm_distance_clip_speed
 */
#ifndef MM_DISTANCE_CURVE_H
#define MM_DISTANCE_CURVE_H

#include <stdint.h>

#include "alloc.h"
#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

#define MM_DISTANCE_STOP_SPEED_DEFAULT 0.1f /* m/s: below this the root counts as stopping */

typedef enum mm_distance_kind {
    MM_DISTANCE_NONE = 0,  /* no stop in the segment: distance from its first frame */
    MM_DISTANCE_STOP = 1,  /* the root comes to rest (or nearly) and goes on the same way, or not */
    MM_DISTANCE_PIVOT = 2, /* the root slows to its lowest speed and leaves the other way (> 90 deg) */
} mm_distance_kind;

/* One segment: consecutive frames (a loop's segment may run past the last frame into the first)
 * measured against one stop or pivot. All fields are 4 bytes wide, for storing as they are. */
typedef struct mm_distance_segment {
    int32_t first_frame;    /* 0-based */
    int32_t frame_count;    /* >= 1; frames first_frame .. first_frame + frame_count - 1 (mod n in loops) */
    int32_t marker_frame;   /* the stop or pivot frame; first_frame for MM_DISTANCE_NONE */
    int32_t kind;           /* mm_distance_kind */
    float marker_travelled; /* travelled path (m) at the marker, counted in the segment's unwrapped
                             * frames: frames past a loop's wrap add the path length once */
} mm_distance_segment;

/* A clip's distance curves: flat float arrays plus a segment table (ready to be stored in a file).
 * A curve made by mm_distance_curve_build (mm/distance_curve_build.h) owns one block; to read one stored
 * elsewhere, fill the fields yourself with block NULL (and check it with mm_distance_curve_validate). */
typedef struct mm_distance_curve {
    int32_t frame_count; /* >= 2 */
    int32_t loop;        /* 1: the frame after the last is the first */
    float fps;           /* frames per second, > 0 */
    float path_length;   /* m: the whole root path on the ground; a loop's includes the wrap step */
    int32_t segment_count;
    const float *travelled;              /* [frame_count] m from frame 0 along the path, non-decreasing */
    const float *distance;               /* [frame_count] m, signed distance to the segment's marker */
    const mm_distance_segment *segments; /* [segment_count], in frame order, covering every frame once */
    void *block;                         /* owned allocation, or NULL for a view */
    mm_allocator allocator;
} mm_distance_curve;

/* ---- queries (no allocation) ------------------------------------------------------------ */

/* Checks a curve (for example one read from a file): sizes, finite and monotonic values,
 * segments covering every frame once with their marker inside. */
mm_result mm_distance_curve_validate(const mm_distance_curve *c, mm_error *err);

/* Seconds of clip time: (frame_count - 1) / fps for one-shots, frame_count / fps for loops. */
float mm_distance_duration(const mm_distance_curve *c);
/* Path travelled (m) from time 0 to time t, linear between frames. One-shots clamp t to
 * [0, duration]; loops take any t and keep growing: travelled(t + k duration) = travelled(t) +
 * k path_length. 0 for a non-finite t or an invalid curve. */
float mm_distance_travelled(const mm_distance_curve *c, float t);
/* The segment holding clip time t (wrapped or clamped into the clip); 0 when t is not finite. */
int mm_distance_segment_at(const mm_distance_curve *c, float t);
/* Signed distance (m) to the marker of the segment holding time t; continuous within a segment. */
float mm_distance_signed(const mm_distance_curve *c, float t);

/* Seed 003's GetTimeAfterDistanceTraveled: from time, steps frame by frame (the curve is linear
 * between frames, so the fraction of the last step is exact) until the clip's root has travelled
 * distance (m, >= 0). Steps where the root does not move are passed through. Loops wrap (the
 * result is unwrapped: >= time, whole loops skipped at once); one-shots stop at the last frame.
 * Returns time itself for a bad argument; at most FLT_MAX. */
float mm_distance_time_after(const mm_distance_curve *c, float time, float distance);

/* The clip's average root speed: path_length / duration (m/s); 0 for an invalid curve. */
float mm_distance_clip_speed(const mm_distance_curve *c);

#ifdef __cplusplus
}
#endif

#endif /* MM_DISTANCE_CURVE_H */
