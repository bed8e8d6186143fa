/* mm/recorder.h - the last N ticks of a character, kept to look at and to go back to.
 *
 * A recorder is a ring buffer in memory the caller gives (mm_recorder_bytes says how much); it
 * allocates nothing, at init or per tick. After each mm_character_update, mm_recorder_record keeps
 * what the tick did: the input, the simulated trajectory (past and future, world), the query, the
 * search's best candidates with every cost term when a search ran, whether the playhead jumped,
 * the feet's contact labels and locks, the output pose, and the character's whole state (a byte
 * copy, mm_character_snapshot_save). mm_recorder_restore puts the character back to a recorded
 * tick: given the inputs that followed, it runs on bit for bit as it ran (tests/test_recorder.c).
 * When the buffer is full the oldest tick gives way.
 *
 *   size_t bytes = mm_recorder_bytes(&c, 600, 5);
 *   void *memory = malloc(bytes);
 *   mm_recorder rec;
 *   mm_recorder_init(&rec, memory, bytes, &c, 600, 5, &err);   // asks c for its top 5 candidates
 *   each tick: mm_character_update(&c, &in, dt); mm_recorder_record(&rec, &c, &in, dt);
 *   const mm_recorded_tick *t = mm_recorder_tick(&rec, i);     // i in [0, mm_recorder_count)
 *   mm_recorder_restore(&rec, i, &c, &err);                    // back to the end of tick i
 *
 * Indices run from 0 (the oldest tick kept) to mm_recorder_count - 1 (the newest); a tick's
 * number counts the ticks recorded since init (mm_recorder_tick's `number`).
 *
 * Functions: mm_recorder_bytes mm_recorder_init mm_recorder_clear mm_recorder_record
 *            mm_recorder_count mm_recorder_oldest mm_recorder_newest mm_recorder_index
 *            mm_recorder_tick mm_recorder_restore mm_recorder_truncate
 */
#ifndef MM_RECORDER_H
#define MM_RECORDER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "character.h"
#include "database.h"
#include "input.h"
#include "math.h"
#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

#define MM_RECORDER_MAX_CANDIDATES 64 /* top_k at most */

/* What a recorder kept of one tick (the end of it: after mm_character_update). The arrays point
 * into the recorder's memory and stay valid until that tick gives way or the recorder is cleared. */
typedef struct mm_recorded_tick {
    int64_t number; /* ticks recorded before this one since init (or mm_recorder_clear) */
    double time;    /* s: the sum of the dt recorded, this tick's included */
    float dt;       /* s */
    mm_input input; /* the input the tick ran with (neutral when none was given) */

    /* playback after the tick: the frame playing, its clip, how far toward the next frame, and
     * the character on the ground (joint 0) */
    int frame, clip;
    double frame_fraction;
    mm_xform root;

    /* the simulated trajectory at the database's trajectory times (s, past < 0 < future; the
     * future predicted with the input held): world positions on the ground and facings */
    int traj_count;
    float traj_times[MM_MAX_TRAJ_SAMPLES];
    mm_vec3 traj_positions[MM_MAX_TRAJ_SAMPLES];
    mm_quat traj_facings[MM_MAX_TRAJ_SAMPLES];

    /* the search: whether one ran this tick; the query it weighed (the last search's when none
     * ran; [dims] normalised features, db->dims_padded floats stored); its best candidates
     * (mm_character_candidates: winner first, then by cost); whether the playhead jumped
     * (a transition started) */
    bool searched;
    bool transition;
    int dims;
    const float *query;
    int candidate_count;
    const mm_candidate *candidates;

    /* the feet (0 left, 1 right): the contact labels of the frame playing (heel, toe), whether
     * each ankle is held and where */
    bool heel_contact[2], toe_contact[2];
    bool foot_locked[2];
    mm_vec3 foot_lock[2];

    /* the character's counters after the tick (mm_character.searches, .transitions) */
    int searches, transitions;

    /* the output pose: world transforms, [joint_count] */
    int joint_count;
    const mm_xform *global;
} mm_recorded_tick;

typedef struct mm_recorder {
    const mm_database *db;               /* of the character recorded */
    int capacity;                        /* ticks kept */
    int top_k;                           /* candidates kept per search */
    int count;                           /* ticks held, <= capacity */
    int head;                            /* slot of the oldest tick */
    int64_t recorded;                    /* ticks recorded since init */
    double time;                         /* s: the sum of the dt recorded */
    int last_searches, last_transitions; /* the character's counters at the last record */
    int traj_count;                      /* the database's trajectory times */
    float traj_times[MM_MAX_TRAJ_SAMPLES];
    size_t snapshot_bytes; /* mm_character_snapshot_bytes of the character */
    /* in the caller's memory: per slot, the tick, its query, candidates, pose and state */
    mm_recorded_tick *ticks;
    float *queries;
    mm_candidate *candidates;
    mm_xform *poses;
    unsigned char *snapshots;
} mm_recorder;

/* Bytes of memory a recorder of `ticks` ticks and top_k candidates per search needs for
 * character c (0 when ticks < 1, top_k < 0 or c has no state). */
size_t mm_recorder_bytes(const mm_character *c, int ticks, int top_k);

/* Lays the recorder out in memory (bytes at least mm_recorder_bytes(c, ticks, top_k); any
 * alignment) and asks c for its top top_k candidates at every search (mm_character_set_candidates,
 * which allocates there, once). MM_ERR_INVALID_ARGUMENT for too little memory, a bad count or no
 * character; MM_ERR_OUT_OF_MEMORY when c cannot keep top_k candidates. */
mm_result mm_recorder_init(mm_recorder *rec, void *memory, size_t bytes, mm_character *c, int ticks,
                           int top_k, mm_error *err);

/* Forgets every tick kept (the numbering starts again at 0). */
void mm_recorder_clear(mm_recorder *rec);

/* Keeps the tick c has just run (after mm_character_update(c, in, dt); in may be NULL). c must be
 * the character the recorder was made for (its database). No allocation. */
void mm_recorder_record(mm_recorder *rec, const mm_character *c, const mm_input *in, float dt);

/* Ticks held; the numbers of the oldest and the newest (-1 when empty). */
int mm_recorder_count(const mm_recorder *rec);
int64_t mm_recorder_oldest(const mm_recorder *rec);
int64_t mm_recorder_newest(const mm_recorder *rec);
/* The index of the tick numbered `number`, -1 when it is not held. */
int mm_recorder_index(const mm_recorder *rec, int64_t number);

/* Tick `index` (0: the oldest held), NULL out of range. */
const mm_recorded_tick *mm_recorder_tick(const mm_recorder *rec, int index);

/* Puts c back to the end of tick `index` (mm_character_snapshot_load): every field and all its
 * state as they were, so that updating it with the inputs that followed repeats the run bit for
 * bit. c is the character recorded or one made the same way (same database, same desc). The
 * ticks kept are not changed (recording on after a restore keeps the newer ticks: clear them with
 * mm_recorder_truncate). MM_ERR_INVALID_ARGUMENT out of range or for another character's layout. */
mm_result mm_recorder_restore(const mm_recorder *rec, int index, mm_character *c, mm_error *err);

/* Forgets the ticks after `index` (so that recording on after a restore continues from there). */
void mm_recorder_truncate(mm_recorder *rec, int index);

#ifdef __cplusplus
}
#endif

#endif /* MM_RECORDER_H */
