/* mm/synth.h - built-in motion: a procedural locomotion set with exactly known ground truth.
 *
 * Someone who clones mm has no motion capture, and tests need motion whose truth is known exactly
 * (speeds, contact frames, turn radii). This module synthesizes a set of clips of one humanoid
 * (22 joints with LAFAN1 names, about 1.75 m tall) the way procedural animation is done well:
 *
 *   - a control plan per clip (speed, path curvature, travel direction, turn rate, walk/run blend,
 *     activity) integrated into a root trajectory, with smooth (C2) changes;
 *   - a gait phase advancing with the cadence; footsteps are planned from the trajectory: each
 *     stance has a fixed plant, a heel rocker (the heel = Foot joint is the pivot) and a toe rocker
 *     (the toe = Toe joint is the pivot), swing arcs join the stances with matched velocities;
 *   - pelvis height, sway, list and rotation follow the phase; the pelvis is lowered smoothly where a
 *     planted foot would be out of reach; two-bone IK places the legs with the knee bending forward;
 *   - the upper body counter-rotates, the arms swing opposite the legs, the head stabilises the gaze.
 *
 * Guarantees (asserted in tests/test_synth.c with mm_clip_fk): a foot contact flag is on only while
 * that joint is exactly planted (horizontal speed below 1 cm/s), knees bend forward and never
 * straighten fully, speeds and turn radii are the nominal ones, loops close, the set is
 * deterministic for a seed. See docs/synth.md.
 *
 *   mm_synth_desc desc = {0};          // seed 0 and 60 fps by default
 *   mm_synth_set set;
 *   if (mm_synth_generate(&desc, &set, &err) != MM_OK) { report err; }
 *   for (int i = 0; i < set.clip_count; ++i) use(set.clips[i].name, &set.clips[i].clip);
 *   mm_synth_set_free(&set);
 *
 * Units: metres, seconds, radians; Y up, the character faces +Z at the start of every clip and
 * stands at the origin (the root's ground projection).
 *
 * Functions: mm_synth_skeleton mm_synth_generate mm_synth_set_free mm_synth_kind_name
 *            mm_synth_contact_ranges
 */
#ifndef MM_SYNTH_H
#define MM_SYNTH_H

#include <stdbool.h>
#include <stdint.h>

#include "alloc.h"
#include "clip.h"
#include "result.h"
#include "skeleton.h"

#ifdef __cplusplus
extern "C" {
#endif

/* What a clip shows. */
typedef enum mm_synth_kind {
    MM_SYNTH_IDLE,          /* standing: breathing, weight shifts (loop) */
    MM_SYNTH_WALK,          /* straight walk cycle (loop) */
    MM_SYNTH_RUN,           /* straight run cycle (loop) */
    MM_SYNTH_WALK_ARC,      /* walk on a constant-curvature path (loop) */
    MM_SYNTH_RUN_ARC,       /* run on a constant-curvature path (loop) */
    MM_SYNTH_START,         /* idle, then accelerate to a walk or run */
    MM_SYNTH_STOP,          /* walk or run, then decelerate to idle */
    MM_SYNTH_TURN_IN_PLACE, /* idle, turn on the spot by turn_angle, idle */
    MM_SYNTH_SIDESTEP,      /* idle, step sideways (direction +-pi/2), idle */
    MM_SYNTH_BACKWARD,      /* walking backwards (loop) */
    MM_SYNTH_GAIT_CHANGE,   /* walk to run or run to walk */
    MM_SYNTH_JUMP,          /* standing jump forward: crouch, take-off, flight, landing */
    MM_SYNTH_TURN_LOOP,     /* walk or run with sharp turns at intervals (loop); turn_angle per loop */
    MM_SYNTH_KIND_COUNT
} mm_synth_kind;

/* "idle", "walk", "run", "walk_arc", "run_arc", "start", "stop", "turn_in_place", "sidestep",
 * "backward", "gait_change", "jump"; NULL for an invalid value. */
const char *mm_synth_kind_name(mm_synth_kind kind);

/* Bits of mm_synth_clip.contacts[frame]: the foot joint (heel) or toe joint is planted. */
enum mm_synth_contact {
    MM_SYNTH_LEFT_HEEL = 1u << 0,  /* LeftFoot joint planted */
    MM_SYNTH_LEFT_TOE = 1u << 1,   /* LeftToe joint planted */
    MM_SYNTH_RIGHT_HEEL = 1u << 2, /* RightFoot joint planted */
    MM_SYNTH_RIGHT_TOE = 1u << 3   /* RightToe joint planted */
};

#define MM_SYNTH_JOINT_COUNT 22
#define MM_SYNTH_NAME_MAX    48

/* One clip with its ground truth. Nominal values are the plan's inputs, not measurements. */
typedef struct mm_synth_clip {
    char name[MM_SYNTH_NAME_MAX]; /* unique, usable as a file stem: "walk_1.40", "run_arc_left_r4.0" */
    mm_synth_kind kind;
    bool loop;         /* the last frame continues into the first (root-relative) */
    float speed;       /* m/s: the steady speed of the clip's main part (0 for idle and turns) */
    float speed_in;    /* m/s: speed at the first frame */
    float speed_out;   /* m/s: speed at the last frame */
    float turn_radius; /* m of the root path, positive turning left, negative right; 0 straight */
    float turn_angle;  /* rad: planned heading change over the clip, positive left */
    float direction;   /* rad: travel direction relative to facing (0 forward, +pi/2 left, pi back) */
    mm_clip clip;      /* joint_count = MM_SYNTH_JOINT_COUNT, fps = desc fps */
    uint8_t *contacts; /* [clip.frame_count] mm_synth_contact bits; owned */
} mm_synth_clip;

typedef struct mm_synth_set {
    int clip_count;
    mm_synth_clip *clips; /* [clip_count], owned */
    mm_allocator allocator;
} mm_synth_set;

/* Defaults (zero): seed 0, fps 60, malloc. The same seed gives the same clips bit for bit; the
 * seed varies style (arm swing, cadence, step width, idle timing) within plausible ranges, never
 * the nominal speeds, radii or angles. */
typedef struct mm_synth_desc {
    uint64_t seed;
    float fps;                     /* output frame rate, 0: 60; accepted range 10-240 */
    const mm_allocator *allocator; /* NULL: malloc */
} mm_synth_desc;

/* The standard skeleton (22 joints, metres, rest pose: T-pose facing +Z, feet flat on y = 0 when
 * the root is at its offset): Hips, LeftUpLeg, LeftLeg, LeftFoot, LeftToe, RightUpLeg, RightLeg,
 * RightFoot, RightToe, Spine, Spine1, Spine2, Neck, Head, LeftShoulder, LeftArm, LeftForeArm,
 * LeftHand, RightShoulder, RightArm, RightForeArm, RightHand. out must not be initialised. */
mm_result mm_synth_skeleton(mm_skeleton *out, const mm_allocator *allocator);

/* Generates the whole set into out (not initialised; free with mm_synth_set_free). desc may be
 * NULL. Returns MM_ERR_INVALID_ARGUMENT (fps out of range) or MM_ERR_OUT_OF_MEMORY, filling err. */
mm_result mm_synth_generate(const mm_synth_desc *desc, mm_synth_set *out, mm_error *err);
void mm_synth_set_free(mm_synth_set *set);

/* Contact ranges of one flag: writes up to max_ranges inclusive [first, last] frame pairs of the
 * runs where (contacts[f] & flag) != 0 into out_ranges (2 ints each) and returns the number of
 * runs (which may exceed max_ranges; out_ranges may then be NULL to count). */
int mm_synth_contact_ranges(const mm_synth_clip *clip, unsigned flag, int *out_ranges, int max_ranges);

#ifdef __cplusplus
}
#endif

#endif /* MM_SYNTH_H */
