/* mm/take_spans.h - the frame spans of a take for a database config (the mm_build library): which
 * frames hold poses that are not motion and are left out, which stand still (idle) and which move
 * (locomotion). mm config init (mm/config_init.h) and mm bvh spans both split takes with it
 * (docs/database.md, "Spans of a take").
 *
 * Each frame gets a kind: its posture (mm/posture.h) against the take's own upright head height
 * over the ground under it (MM_SPAN_GROUND_SECONDS), short runs merged (mm_posture_remove_flicker); an A pose
 * held still (mm_posture_find_a_poses) is MM_SPAN_A_POSE; in a stretch of low frames (crouched, bent, lying)
 * the crouched and bent frames within MM_SPAN_TRANSITION_SECONDS of a lying frame are MM_SPAN_GETTING_UP
 * (lying down, getting up), and those within it of a frame with the hips below MM_SPAN_DOWN_HIPS x their
 * upright height MM_SPAN_DOWN (kneeling, sitting, picking something up). Calibration poses (T and A), lying,
 * getting up and going down are left out, widened by pad seconds on each side; in the rest, the
 * root bone's ground projection slower than idle_speed for idle_min seconds is idle, the others
 * locomotion (crouched, bent and arms-spread frames stay: the database build tags or cuts them).
 *
 * Functions: mm_take_spans_desc_defaults mm_take_spans_find mm_take_spans_free mm_span_kind_name
 *            mm_span_left_out
 */
#ifndef MM_TAKE_SPANS_H
#define MM_TAKE_SPANS_H

#include <stdbool.h>
#include <stdint.h>

#include "clip.h"
#include "config.h"
#include "posture.h"
#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Kinds of frame beyond the postures (mm_posture values are kinds too). */
#define MM_SPAN_A_POSE     MM_POSTURE_COUNT       /* an A pose held still: a calibration pose */
#define MM_SPAN_GETTING_UP (MM_POSTURE_COUNT + 1) /* the way into or out of lying */
#define MM_SPAN_DOWN       (MM_POSTURE_COUNT + 2) /* going down to the ground and back */
#define MM_SPAN_KIND_COUNT (MM_POSTURE_COUNT + 3)

/* A crouched or bent stretch whose hips come lower than this x their upright height goes down to
 * the ground (kneeling, squatting, sitting, picking something up): not a way of walking. */
#define MM_SPAN_DOWN_HIPS 0.65f
/* Lying down, getting up and going down to the ground and back take at most this long (s): the
 * crouched or bent frames farther from a lying frame or from the hips' lowest are another motion. */
#define MM_SPAN_TRANSITION_SECONDS 2.0f

/* s: the ground under a frame is the lowest joint within this of it when above the take's floor
 * (a ground that follows obstacles and steps up, not jumps: LAFAN1's leave the floor for 0.5-0.6 s) */
#define MM_SPAN_GROUND_SECONDS 0.4f

/* The joints the spans are judged on (indices; -1: none). hips, root_bone and head are needed;
 * without both hands no calibration pose is looked for. */
typedef struct mm_take_joints {
    int hips, root_bone, head, left_hand, right_hand;
} mm_take_joints;

typedef struct mm_take_spans_desc {
    float pad;        /* s left out before and after a left-out frame; default 1 */
    float idle_speed; /* m/s: the root slower than this (over +-0.1 s) stands still; default 0.15 */
    float idle_min;   /* s: ... for at least this long; default 1 */
    float low_hips;   /* m: > 0 also leaves out frames whose hips are lower (deprecated); default 0: off */
} mm_take_spans_desc;

void mm_take_spans_desc_defaults(mm_take_spans_desc *desc);

/* Half-open frame ranges, each of 2 frames or more. */
typedef struct mm_take_spans {
    int frame_count;
    uint8_t *kinds;            /* [frame_count]: an mm_posture or MM_SPAN_A_POSE, _GETTING_UP, _DOWN */
    float upright_head_height; /* m above the ground: the reference the postures are judged against */
    bool arms_found;           /* the hands' elbows and shoulders were found: A poses looked for */
    int excluded_count, idle_count, locomotion_count;
    mm_config_range *excluded, *idle, *locomotion; /* malloc'd */
} mm_take_spans;

/* The spans of a clip in metres, +Y up. desc NULL: the defaults. Errors: MM_ERR_INVALID_ARGUMENT
 * (a needed joint out of range, no frame rate), MM_ERR_OUT_OF_MEMORY; out is then empty. */
mm_result mm_take_spans_find(const mm_clip *clip, const mm_take_joints *joints,
                             const mm_take_spans_desc *desc, mm_take_spans *out);
void mm_take_spans_free(mm_take_spans *spans);

/* "upright" ... (mm_posture_name), "a_pose", "getting_up", "down"; NULL if out of range. */
const char *mm_span_kind_name(int kind);

/* Frames of this kind are left out of idle and locomotion: calibration (T and A poses), lying,
 * getting up, down. */
bool mm_span_left_out(int kind);

#ifdef __cplusplus
}
#endif

#endif /* MM_TAKE_SPANS_H */
