/* mm/mixer.h - the crossfade mixer of seed 000 (动画播放与过渡): five slots, each a playing source
 * with a weight, blended into one pose. The character controller's alternative to
 * inertialization (mm_character_desc.transition_mode, docs/transitions.md).
 *
 * A slot plays a source: a database frame and how far toward the next (or any id the caller maps
 * to a pose, with the fraction left at 0). Slot 0 holds the newest source. The weights of the
 * slots in use always sum to 1 (to float rounding).
 *
 * Starting a transition to a new source over T seconds (mm_mixer_start):
 *   - slots whose weight is 0 (other than slot 0) are dropped first: they show nothing;
 *   - when all MM_MIXER_SLOTS slots are in use, the oldest (the last slot) is to be evicted. If it
 *     still holds more than cancel_weight (MM_MIXER_CANCEL_WEIGHT, 0.2, unless changed in the
 *     struct), the transition is cancelled: nothing changes but the `cancelled` count, and
 *     mm_mixer_start returns false. A weight exactly at the threshold is evicted. A source marked
 *     uncancellable (the seed's jumps) evicts it whatever its weight. The evicted weight goes to
 *     the other slots in proportion to their own (they are renormalised to sum 1);
 *   - the older slots shift down by one and the new source takes slot 0 with weight 0. Each older
 *     slot remembers the weight it has now, its share.
 * Advancing by dt (mm_mixer_advance): s = elapsed / T (clamped to 1); an older slot's weight is its
 * share times (1 - s), slot 0's is 1 minus the others' sum. So every weight moves linearly over
 * the transition time, the older slots keep their proportions to one another, and at s = 1 they
 * all reach 0 and are freed, leaving slot 0 alone at weight 1. A transition started before the
 * last one ended takes the weights where they are as the new shares. T <= 0 (or not finite): the
 * new source takes weight 1 at once and the others are freed.
 *
 * The mixer allocates nothing, is a plain struct (copy it to keep a state) and is deterministic.
 * Playheads advance with mm_mixer_play on a next-frame table (mm_database.frame_next); the caller
 * turns each slot into a pose and mixes them with mm_pose_blend.
 *
 * Functions: mm_mixer_init mm_mixer_start mm_mixer_advance mm_mixer_play mm_mixer_weight_sum
 *            mm_pose_blend mm_pose_to_model mm_pose_to_local
 */
#ifndef MM_MIXER_H
#define MM_MIXER_H

#include <stdbool.h>

#include "math.h"
#include "skeleton.h"

#ifdef __cplusplus
extern "C" {
#endif

#define MM_MIXER_SLOTS 5
/* A transition is cancelled when the slot it would evict holds more than this weight. 0.2: a
 * fifth of the pose vanishing in one tick is a visible pop (the slot's whole weight goes at once);
 * below it the renormalised blend hides it. */
#define MM_MIXER_CANCEL_WEIGHT 0.2f

typedef struct mm_mixer_slot {
    int source;     /* database frame (or the caller's id) */
    float fraction; /* [0, 1): toward the next frame */
    float weight;   /* now */
    float share;    /* the weight it had when the current transition started */
} mm_mixer_slot;

typedef struct mm_mixer {
    mm_mixer_slot slots[MM_MIXER_SLOTS]; /* [0, count): slot 0 the newest */
    int count;
    float duration, elapsed; /* s: of the current transition and how far into it */
    float cancel_weight;     /* MM_MIXER_CANCEL_WEIGHT */
    int started, cancelled;  /* transitions started and cancelled since init */
} mm_mixer;

/* One slot playing source (at fraction) with weight 1; cancel_weight MM_MIXER_CANCEL_WEIGHT. */
void mm_mixer_init(mm_mixer *m, int source, float fraction);

/* Starts a transition to source over time seconds (see above). Returns false when it is cancelled
 * (the mixer is unchanged but for m->cancelled), true when it started. */
bool mm_mixer_start(mm_mixer *m, int source, float fraction, float time, bool uncancellable);

/* Moves the weights dt seconds on (dt <= 0 or not finite: nothing); frees older slots at 0. */
void mm_mixer_advance(mm_mixer *m, float dt);

/* Advances every slot's playhead by frames (>= 0) along next (next[f]: the frame after f, < 0 at
 * the end of its clip; frame_count entries). A playhead at the end of its clip stays on its last
 * frame with fraction 0. Returns a bit mask: bit i set when slot i is at the end of its clip. A
 * source outside [0, frame_count) does not move. */
unsigned mm_mixer_play(mm_mixer *m, const int *next, int frame_count, float frames);

/* The sum of the weights in use (1 to float rounding). */
float mm_mixer_weight_sum(const mm_mixer *m);

/* Blends pose_count poses of joint_count joints into out: rotations by the normalised weighted
 * sum of the quaternions, each first put in the hemisphere of a reference (q and -q are the same
 * rotation, and the sum must not cancel them); positions linearly. The reference is
 * reference[joint] when given, else the heaviest pose's (the first of equals). A caller blending
 * every tick passes the last tick's output: quaternions far apart (a half turn: dot near 0) then
 * keep their signs and the result moves continuously, where a fixed reference flips one of them
 * as it passes orthogonal to it (for two poses the heaviest gives the same result as either).
 * Weights are normalised by their sum; negative or non-finite weights count as 0; with no
 * positive weight (or pose_count < 2) out is pose 0. A joint whose weighted sum cancels takes the
 * heaviest pose's rotation. out may alias pose 0 (not the reference). */
void mm_pose_blend(const mm_quat *const *rotations, const mm_vec3 *const *positions, const float *weights,
                   int pose_count, int joint_count, const mm_quat *reference, mm_quat *out_rotations,
                   mm_vec3 *out_positions);

/* Local rotations to model space (each joint's rotation in the frame of joint 0: its parents' and
 * its own composed, joint 0 counted as the identity and left as it is) and back, in place; parents
 * from joints[j].parent (< j). The character blends in model space: two poses whose local
 * rotations differ by half a turn about a bone that the child undoes (LAFAN1's mirrored clips
 * have such flips; the joints land in the same places) blend in local space into a pose unlike
 * either, in model space into one between them. */
void mm_pose_to_model(const mm_joint *joints, int joint_count, mm_quat *rotations);
void mm_pose_to_local(const mm_joint *joints, int joint_count, mm_quat *rotations);

#ifdef __cplusplus
}
#endif

#endif /* MM_MIXER_H */
