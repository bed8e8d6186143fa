/* mm/posture.h - what kind of pose a body holds: upright, crouched, bent over, lying, or a
 * calibration pose (arms straight out), the arms spread wide, a hand or a knee raised, judged from world
 * joint positions (the mm_build library).
 *
 * The database build uses it to keep poses out of ordinary locomotion (docs/database.md,
 * "Postures"): calibration, lying, arms-spread, hand-raised and knee-raised frames are removed from
 * locomotion and idle clips, crouched
 * and bent-over ones are tagged with the crouch gait. mm simulate uses it to measure the posture
 * of what it played (docs/metrics.md). Both judge against the same reference: the head's height
 * in an upright pose of the same body, so that any skeleton and unit works.
 *
 *   mm_posture_reference ref = {mm_posture_reference_height(head_heights, n)};
 *   mm_posture p = mm_posture_classify(world, &joints, ground_y, &ref);
 *
 * A calibration pose is also the A pose: upright, both arms straight and 15-60 degrees down from the
 * shoulders, out to the sides, held still (a pose, not a swing of the arms). Being still needs
 * frames, so A poses are found over a sequence (mm_posture_find_a_poses) on the arms' joints
 * (mm_posture_find_arms), not by mm_posture_classify.
 *
 * Functions: mm_posture_name mm_posture_reference_height mm_posture_stature mm_posture_classify
 *            mm_posture_arms_out mm_posture_remove_flicker mm_posture_remove_flicker_each
 *            mm_posture_find_arms mm_posture_find_legs mm_posture_thigh_sine mm_posture_a_pose_shape
 *            mm_posture_find_a_poses
 */
#ifndef MM_POSTURE_H
#define MM_POSTURE_H

#include <stdbool.h>
#include <stdint.h>

#include "math.h"
#include "skeleton.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum mm_posture {
    MM_POSTURE_UPRIGHT = 0,
    MM_POSTURE_CROUCHED,    /* the head low: knees bent or a stoop */
    MM_POSTURE_BENT,        /* the trunk leaning far from vertical (bent over at the waist) */
    MM_POSTURE_LYING,       /* the head near the ground */
    MM_POSTURE_CALIBRATION, /* upright with both arms straight out (a T pose) */
    MM_POSTURE_ARMS_SPREAD, /* the hands wide apart otherwise: a gesture, not a walk */
    MM_POSTURE_HAND_RAISED, /* a hand at the shoulders or above: reaching, waving, a hand to the head */
    MM_POSTURE_KNEE_RAISED, /* upright with a thigh near level: a high-knee or skipping step, a kick */
    MM_POSTURE_COUNT
} mm_posture;

/* Thresholds, as fractions of the reference (the upright head height) or angles. Measured on the
 * LAFAN1 takes (docs/database.md, "Postures"): upright walking and running carry the head at
 * 0.92-1.0 of the reference, the stooped walk at 0.77-0.87; the hips-to-head line leans 2-30
 * degrees in upright motion and 40-65 in the stoop; a T pose holds the hands 0.8 of the stature
 * apart at 0.9 of the head's height, walking at most 0.6. */
#define MM_POSTURE_CROUCHED_HEIGHT   0.88f /* head below this x reference: crouched */
#define MM_POSTURE_LYING_HEIGHT      0.5f  /* head below this x reference: lying */
#define MM_POSTURE_BENT_DEGREES      40.0f /* hips-to-head line farther from vertical: bent over */
#define MM_POSTURE_HEAD_TO_STATURE   0.92f /* the head joint's height as a fraction of the stature */
#define MM_POSTURE_ARMS_OUT          0.6f  /* hands farther apart than this x stature: arms out */
#define MM_POSTURE_CALIBRATION_ARMS  0.75f /* a calibration pose: hands farther apart than this x stature */
#define MM_POSTURE_CALIBRATION_HANDS 0.75f /* and both above this x reference */
/* Running pumps the hands up to 0.80-0.86 of the reference for a frame or two (LAFAN1, p99 of
 * frames above 2 m/s, the head then at about 0.97); a hand waved overhead or put to the head is
 * at 0.9-1.2 for a second. Judged against the head, not the ground, so that a body up a step whose
 * ground is not yet known does not raise its hands. */
#define MM_POSTURE_HAND_RAISED_BELOW_HEAD 0.1f /* a hand less than this x reference under the head */
/* A knee raised: the sine of a thigh's elevation (its top to the knee) above this, a thigh within
 * 0.2 of level. A stylised high-knee step lifts the thigh to level or above; running swings it
 * forward to 15-30 degrees below level at most (docs/database.md, "A knee raised"). Judged on the
 * thigh's own direction, so that any size of body works. */
#define MM_POSTURE_KNEE_RAISED_SINE   -0.2f
#define MM_POSTURE_REFERENCE_QUANTILE 0.9f  /* the reference: this quantile of the head's heights */
#define MM_POSTURE_MIN_SECONDS        0.25f /* shorter runs of a posture are flicker */
/* The A pose. A calibration A pose holds the arms 30-50 degrees below the shoulders; walking swings
 * them 70-90 degrees down, standing hangs them at 80-90, a T pose holds them within 15 of level. */
#define MM_POSTURE_A_POSE_MIN_DEGREES 15.0f /* each arm at least this far below level */
#define MM_POSTURE_A_POSE_MAX_DEGREES 60.0f /* and at most this far */
#define MM_POSTURE_A_POSE_STRAIGHT                                                                           \
    0.95f /* shoulder to hand over upper arm + forearm: a straight arm                                       \
               (the elbow bent 35 degrees at most) */
#define MM_POSTURE_A_POSE_SIDEWAYS                                                                           \
    0.7f /* cosine from the arm's level part to the shoulders' line, outward                                 \
          */
#define MM_POSTURE_A_POSE_STILL_SPEED  0.15f /* m/s: both hands slower than this (over +-0.1 s) are still */
#define MM_POSTURE_A_POSE_HOLD_SECONDS 0.5f  /* held at least this long */
#define MM_POSTURE_LEG_BONE_MIN                                                                              \
    0.15f /* m: likewise the shin and the thigh: the knee is the first ancestor of the foot this far         \
             from it at rest, the thigh's top the first this far from the knee */
#define MM_POSTURE_ARM_BONE_MIN                                                                              \
    0.15f /* m: a bone of the arm (forearm, upper arm) spans at least this                                   \
             at rest; shorter links (twist joints) are part of one */

/* The joints the judgement reads (indices into the world positions; -1: the skeleton has none).
 * hips and head are needed; without the hands a pose is never a calibration pose, without a leg's
 * knee and thigh never a knee raised on that leg. knee[0], thigh[0] are the left leg's, [1] the
 * right's: the thigh is the joint the thigh starts from (the leg's hip joint), mm_posture_find_legs
 * finds both from the feet. */
typedef struct mm_posture_joints {
    int hips, head, left_hand, right_hand;
    int knee[2], thigh[2];
} mm_posture_joints;

typedef struct mm_posture_reference {
    float head_height; /* m above the ground: the head's height when upright, > 0 */
} mm_posture_reference;

/* "upright", "crouched", "bent", "lying", "calibration", "arms_spread", "hand_raised", "knee_raised";
 * NULL if out of range. */
const char *mm_posture_name(mm_posture p);

/* The reference head height from the head's heights above the ground over many frames of a body's
 * motion: their MM_POSTURE_REFERENCE_QUANTILE quantile (a body upright for at least a tenth of the
 * time gives its upright height). Reorders heights. 0 when n < 1. */
float mm_posture_reference_height(float *heights, int n);

/* The stature the reference implies: head_height / MM_POSTURE_HEAD_TO_STATURE. */
float mm_posture_stature(const mm_posture_reference *ref);

/* The posture of one pose: world joint positions (metres, +Y up) over ground at height ground_y.
 * Calibration wins over the others, then lying, arms spread, hand raised, bent, crouched, knee raised
 * (a crouch bends the knees and a thigh may come level: the crouch it is). Upright when a needed
 * joint is missing, a position is not finite, or the reference is not positive. */
mm_posture mm_posture_classify(const mm_vec3 *world, const mm_posture_joints *joints, float ground_y,
                               const mm_posture_reference *ref);

/* Both hands farther apart than MM_POSTURE_ARMS_OUT x the stature (false without hands). */
bool mm_posture_arms_out(const mm_vec3 *world, const mm_posture_joints *joints,
                         const mm_posture_reference *ref);

/* The joints of the arms, [0] left and [1] right: the hand, the elbow and the shoulder (where the
 * upper arm starts); -1 when not found. */
typedef struct mm_posture_arms {
    int hand[2], elbow[2], shoulder[2];
} mm_posture_arms;

/* Walks up from each hand (skeleton in metres): the elbow is the first ancestor at least
 * MM_POSTURE_ARM_BONE_MIN from the hand at rest, the shoulder the first at least that far from the
 * elbow. False (and -1s) when a hand is missing or its chain is too short. */
bool mm_posture_find_arms(const mm_skeleton *s, int left_hand, int right_hand, mm_posture_arms *out);

/* Fills joints->knee and joints->thigh from the feet (skeleton in metres): walking up from each
 * foot, the knee is the first ancestor at least MM_POSTURE_LEG_BONE_MIN from the foot at rest, the
 * thigh the first at least that far from the knee. -1s for a leg whose foot is missing or whose
 * chain is too short. Returns the legs found (0-2). */
int mm_posture_find_legs(const mm_skeleton *s, int left_foot, int right_foot, mm_posture_joints *joints);

/* The sine of the thigh's elevation (from its top to the knee) of leg side (0 left, 1 right); NAN
 * without the joints. */
float mm_posture_thigh_sine(const mm_vec3 *world, const mm_posture_joints *joints, int side);

/* One pose in the shape of an A pose (stillness aside): upright (the head at least
 * MM_POSTURE_CROUCHED_HEIGHT x the reference, the trunk within MM_POSTURE_BENT_DEGREES of vertical),
 * each arm straight, MM_POSTURE_A_POSE_MIN_DEGREES to MM_POSTURE_A_POSE_MAX_DEGREES below level and
 * out to its side. False when a joint is missing or not finite. */
bool mm_posture_a_pose_shape(const mm_vec3 *world, const mm_posture_arms *arms,
                             const mm_posture_joints *joints, float ground_y,
                             const mm_posture_reference *ref);

/* The A poses of a sequence: world[f * stride + j] the world positions of frame f (n frames at
 * fps), ground_y[f] its ground. out[f] is 1 where the pose is in the shape of an A pose with both hands still
 * (MM_POSTURE_A_POSE_STILL_SPEED) for at least MM_POSTURE_A_POSE_HOLD_SECONDS, else 0. Returns the
 * frames found. */
int mm_posture_find_a_poses(const mm_vec3 *world, int n, int stride, float fps, const mm_posture_arms *arms,
                            const mm_posture_joints *joints, const float *ground_y,
                            const mm_posture_reference *ref, uint8_t *out);

/* Runs of one posture shorter than min_frames take the posture of the run before them (the run
 * after, at the start): a pose that dips under a threshold for a few frames is not a crouch. A
 * spell of postures other than upright at least min_frames long (for the shortest run of any
 * posture in it) is one spell: its short runs first take their neighbours' postures within it
 * (a crouch that leans past the bent threshold for a few frames stays out of upright whole). */
void mm_posture_remove_flicker(uint8_t *postures, int n, int min_frames);

/* The same with a minimum for each posture: runs of posture p shorter than min_frames[p] are
 * flicker (a minimum of 1 or less keeps every run of p, however brief). */
void mm_posture_remove_flicker_each(uint8_t *postures, int n, const int min_frames[MM_POSTURE_COUNT]);

#ifdef __cplusplus
}
#endif

#endif /* MM_POSTURE_H */
