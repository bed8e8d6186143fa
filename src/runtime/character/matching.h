/* Stage 3, search: when to search, the query, and the frame to go to. */
#ifndef MM_RUNTIME_MATCHING_H
#define MM_RUNTIME_MATCHING_H

#include <stdbool.h>
#include <stdint.h>

#include <mm/character.h>
#include <mm/search.h>

#include "intent.h"
#include "playback.h"

typedef struct mm_matching {
    float since_search;                /* s */
    float last_direction;              /* rad: desired direction at the last search */
    bool idle;                         /* asking for idle */
    bool has_idle;                     /* the database has idle clips */
    uint64_t gait_tags[MM_GAIT_COUNT]; /* tags named after each gait ("Walk", "Run", ...) */
    float *query;                      /* [dims_padded] */
    int searches;
    float last_search_us;
    mm_search_result last_result;
    mm_search_params last_params; /* what the last search weighed with */
} mm_matching;

/* A jump of the playhead asked for: to frame at fraction (-1: none); uncancellable: the crossfade
 * mixer may not drop it. */
typedef struct mm_jump {
    int frame;
    double fraction;
    bool uncancellable;
} mm_jump;

/* The tags and the idle clips of db; idle, searching on the first tick. */
void mm_matching_init(mm_matching *m, const mm_database *db, float *query);

/* One tick: updates idle (from the intent, the simulation t and root_speed, the speed of the root
 * motion played last tick), and searches when it is time (search_interval), the desired direction
 * turned sharply, idle changed, or the clip ended (ended) — never while a move plays (move_playing).
 * The query is the pose of the frame playing and t's future in the frame of root. *jump: where to
 * go (frame -1 when playback goes on where it is). */
void mm_matching_update(mm_matching *m, const mm_character_desc *d, const mm_database *db,
                        const mm_searcher *searcher, const mm_trajectory *t, const mm_input *in,
                        const mm_intent *intent, mm_xform root, float root_speed, const mm_playback *p,
                        bool ended, bool move_playing, float dt, mm_jump *jump);

#endif
