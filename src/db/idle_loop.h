/* idle_loop.h (private) - idle clips made to loop (config idle_loop.make; docs/database.md, "Idle
 * that loops").
 *
 * An idle clip ends: a character standing still plays it to its end, where the search may not land
 * (its end margin), and jumps back into the same still stretch again and again. The build gives
 * each idle clip that has a still stretch a loop clip: the frames [begin, end) of that stretch
 * whose frame `end` (where the loop's last frame would go on) matches frame `begin` best, pose
 * against pose (joint positions and velocities in the character frame), with `end` as near the
 * stretch's end as the match allows. Its last MM__IDLE_LOOP_BLEND_SECONDS carry a correction that
 * grows from nothing to the seam's difference (a cubic in time: position and velocity), so that
 * the frame after the last is the first, continuous in pose and in velocity (C1). The loop is an
 * idle clip of its own (loop 1: playback wraps; the search has no end margin in it) named
 * "<clip>" MM_IDLE_LOOP_SUFFIX, mirrored when its clip is. */
#ifndef MM_DB_IDLE_LOOP_H
#define MM_DB_IDLE_LOOP_H

#include <mm/clip.h>
#include <mm/database_build.h>

/* m/s: a frame is still when the simulation bone moves slower than this on the ground... */
#define MM__IDLE_LOOP_STILL_ROOT_SPEED 0.1f
/* m/s: ...and the joints' mean speed relative to it is below this */
#define MM__IDLE_LOOP_STILL_JOINT_SPEED 0.25f
/* s: the shortest loop (a shorter one repeats visibly) */
#define MM__IDLE_LOOP_MIN_SECONDS 1.0f
/* s: the loop's end is sought within this of its still stretch's end */
#define MM__IDLE_LOOP_END_WINDOW 0.5f
/* s: a m/s of joint velocity difference counts as this many m of position difference */
#define MM__IDLE_LOOP_VELOCITY_WEIGHT 0.1f
/* m: no loop when the best seam's pose distance (RMS over joints) is above this */
#define MM__IDLE_LOOP_MAX_ERROR 0.05f
/* s: the seam's correction is spread over this much of the loop's end (at most half the loop) */
#define MM__IDLE_LOOP_BLEND_SECONDS 0.3f

/* A loop found in a clip. */
typedef struct mm__idle_loop {
    int found;                  /* 0: no still stretch long enough, or none matched */
    int begin, end;             /* the loop: frames [begin, end); frame end's pose met begin's */
    int still_begin, still_end; /* the still stretch it was found in: frames [still_begin, still_end) */
    float error;                /* m: the seam's pose distance before the correction */
} mm__idle_loop;

/* Finds the loop of a database clip (joint 0 the simulation bone, frames at clip->fps): its last
 * still stretch at least MM__IDLE_LOOP_MIN_SECONDS long and, in it, the seam of least pose
 * distance. MM_ERR_OUT_OF_MEMORY only; none found is out->found 0. */
mm_result mm__idle_loop_find(const mm_clip *clip, mm__idle_loop *out);

/* The loop clip of loop (found in src): frames [begin, end) with the seam's correction over its
 * end. */
mm_result mm__idle_loop_make(const mm_clip *src, const mm__idle_loop *loop, mm_clip *out,
                             const mm_allocator *a);

#endif
