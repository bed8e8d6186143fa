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
 * turns each slot into a pose and mixes them with mm_pose_blend (mm/pose.h).
 *
 * Functions: mm_mixer_init mm_mixer_start mm_mixer_advance mm_mixer_play mm_mixer_weight_sum
 */
#ifndef MM_MIXER_H
#define MM_MIXER_H

#include <stdbool.h>

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

#ifdef __cplusplus
}
#endif

#endif /* MM_MIXER_H */
