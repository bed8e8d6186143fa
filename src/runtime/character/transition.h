/* Stage 4, transition: the animated pose played at the playhead, and jumps hidden by
 * inertialization (offsets decaying through springs) or by the crossfade mixer. */
#ifndef MM_RUNTIME_TRANSITION_H
#define MM_RUNTIME_TRANSITION_H

#include <stdint.h>

#include <mm/character.h>
#include <mm/mixer.h>

#include "matching.h"
#include "playback.h"

typedef struct mm_transition {
    mm_transition_mode mode;
    /* the animated pose (database plus inertialization) of this tick and the last, before warping
     * and foot IK: transitions are taken on it, so that IK does not leak into the offsets */
    mm_quat *rotations, *previous_rotations;
    mm_vec3 *positions, *previous_positions;
    /* inertialization: per joint, offsets and their velocities (rotation vectors, rad and rad/s) */
    mm_vec3 *rotation_offset, *rotation_offset_velocity;
    mm_vec3 *position_offset, *position_offset_velocity;
    /* per joint, 1 for the legs' joints (each hip and what hangs from it), whose offsets decay with
     * the legs' half-life (mm_transition_decay); NULL: every joint with the body's */
    unsigned char *legs;
    /* the root motion's offsets (velocity in the character's frame, m/s; yaw rate, rad/s) */
    mm_vec3 root_velocity_offset, root_velocity_offset_rate;
    float root_yaw_rate_offset, root_yaw_rate_offset_rate;
    /* the play rate the animated pose was last played at (a change of rate is taken up by the
     * offsets: mm_transition_pose) */
    float played_rate;
    /* crossfade: the mixer (its slot 0 is the playhead), the slots' poses ([MM_MIXER_SLOTS *
     * joint_count]; rotations one pose more, the blend's reference), the frames whose transitions
     * are never cancelled ("Jump", "Uncancellable") and the winners the mixer cancelled */
    mm_mixer mixer;
    mm_quat *slot_rotations;
    mm_vec3 *slot_positions;
    /* two database frames' local transforms as read (mm_database_local_pose), [2 * joint_count] */
    mm_quat *frame_rotations;
    mm_vec3 *frame_positions;
    uint64_t uncancellable_tags;
    int cancelled;
    int transitions;
} mm_transition;

/* The root motion played this tick: velocity in the character's frame (m/s), yaw rate (rad/s). */
typedef struct mm_root_played {
    mm_vec3 velocity;
    float yaw_rate;
} mm_root_played;

/* Two consecutive frames of a clip: where a jump lands, between them. */
typedef struct mm_frame_pair {
    const mm_quat *rotations0, *rotations1; /* [joint_count] local */
    const mm_vec3 *positions0, *positions1;
} mm_frame_pair;

/* Starts on the playhead p: the pose there, no offsets. The arrays are the caller's. */
void mm_transition_init(mm_transition *tr, const mm_database *db, mm_transition_mode mode,
                        const mm_playback *p);

/* Crossfade mode: the older slots play on dt at p's play rate; slot 0 follows the playhead. */
void mm_transition_advance(mm_transition *tr, const mm_database *db, const mm_playback *p, float dt);

/* Jumps the playhead p as asked (jump->frame >= 0). Inertialization keeps the animated pose where
 * it is and moving as it moves: the difference becomes offsets that decay, and the root motion
 * played (current) continues into the new frame's. Crossfade starts a transition of
 * crossfade_time s in the mixer, unless it cancels it. */
void mm_transition_jump(mm_transition *tr, const mm_database *db, const mm_jump *jump, float crossfade_time,
                        mm_root_played current, mm_playback *p, float dt);

/* The rate of a rotation offset x (a rotation vector; turn = exp(x)) that gives the output the
 * angular velocity w_out while the clip turns at w_new (mm_transition_inertialize, and a change of
 * play rate); mm__rotation_offset_rates: count of them, the same bits, four at a time where the
 * machine has the lanes for it. */
mm_vec3 mm__rotation_offset_rate(mm_vec3 x, mm_quat turn, mm_vec3 w_out, mm_vec3 w_new);
void mm__rotation_offset_rates(const mm_vec3 *x, const mm_quat *turn, const mm_vec3 *w_out,
                               const mm_vec3 *w_new, int count, mm_vec3 *out);

/* Inertialization's offsets for a jump into `to` at fraction (the new clip plays on at frame_rate
 * frames per second; 0 at its last frame), taken one tick (dt) back against the animated pose and
 * its velocity (tr->rotations, tr->positions and their previous values): the output keeps its
 * position and velocity across the jump. Joint 0 (the root) is left out. */
void mm_transition_inertialize(mm_transition *tr, int joint_count, const mm_frame_pair *to, float fraction,
                               float frame_rate, float dt);
/* The offsets' velocities changed so that the output keeps its velocity while the clip's, at the
 * frames `at` (frame_rate frames per second at rate 1), goes from rate_before to rate_now times it. */
void mm_transition_hold_velocity(mm_transition *tr, int joint_count, const mm_frame_pair *at,
                                 float frame_rate, float rate_before, float rate_now);
/* The root motion's offsets for a jump: what played (current) continues into `to`'s. */
void mm_transition_inertialize_root(mm_transition *tr, mm_root_played current, mm_root_played to);

/* Marks the legs' joints (tr->legs): each of hips[0] and hips[1] (-1: none) and the joints that
 * hang from them in skeleton (parents before children). */
void mm_transition_mark_legs(mm_transition *tr, const mm_joint *skeleton, int joint_count, const int hips[2]);

/* The offsets decayed over dt, by halflife, the legs' (tr->legs) by legs_halflife, and added to
 * the animated pose (tr->rotations, tr->positions, as played); the root motion played with its
 * decayed offset. */
void mm_transition_decay(mm_transition *tr, int joint_count, float halflife, float legs_halflife, float dt);
mm_root_played mm_transition_decay_root(mm_transition *tr, mm_root_played played, float halflife, float dt);

/* The animated pose of this tick at the playhead (the last one kept as previous) with the offsets
 * decayed over dt, by halflife, the legs' and the root motion's by legs_halflife (what carries
 * the planted feet: docs/runtime.md, "The legs' half-life"); *root: the root motion played with
 * its offset. */
void mm_transition_pose(mm_transition *tr, const mm_database *db, const mm_playback *p, float halflife,
                        float legs_halflife, float dt, mm_root_played *root);

#endif
