/* mm/crowd.h - many characters sharing one database, ticked together on the game's threads.
 *
 * A crowd owns `count` characters (mm/character.h), each, in a scene, with its move layer
 * (mm/moves.h; on flat ground without one it would only call mm_character_update, and none is
 * made), all searching one read-only searcher: each character moves as mm simulate and mm/run.h
 * move one. mm_crowd_update ticks every character once; the work, each character's tick with its
 * search, goes through a parallel-for:
 *  - the game's (desc.parallel_for): the engine's job system is handed [0, count) and a function
 *    to run over ranges of it; it may split the range as it likes, run the pieces on any threads
 *    in any order, and returns when every piece has returned;
 *  - or, without one, mm's own pool of desc.threads threads (the search's pool, made at init; the
 *    calling thread is one of them). threads 0 or 1: the calling thread alone (no thread is ever
 *    made unless asked for).
 * A character's tick reads only its own state, its input and the shared read-only database,
 * searcher and scene, so the result is the same bits however the work is split or ordered, and
 * on any number of threads. mm_crowd_update allocates nothing.
 *
 *   mm_crowd crowd;
 *   mm_crowd_desc d = {.count = 500, .threads = 2};      // or .parallel_for = engine_for, .user = jobs
 *   mm_crowd_init(&crowd, &db, NULL, &d, &err);           // NULL: the crowd makes its searcher
 *   place them: mm_character_set_root(&crowd.characters[i], ...), teleport their simulations
 *   each tick: inputs[i] = ...; mm_crowd_update(&crowd, inputs, dt); read crowd.characters[i].global
 *   mm_crowd_free(&crowd);
 *
 * Between ticks the game may call any mm_character_* or mm_moves_* function on a character of the
 * crowd (on one thread at a time); not during mm_crowd_update.
 *
 * Functions: mm_crowd_init mm_crowd_update mm_crowd_free
 */
#ifndef MM_CROWD_H
#define MM_CROWD_H

#include "alloc.h"
#include "character.h"
#include "database.h"
#include "input.h"
#include "moves.h"
#include "result.h"
#include "scene.h"
#include "search.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The work of a tick over items [begin, end) (characters), with the crowd's context. */
typedef void (*mm_crowd_work)(void *work_context, int begin, int end);

/* A parallel-for: must call work(work_context, begin, end) over ranges that cover [0, count)
 * exactly once, in any order, on any threads (the calling one included), and return only when
 * all have returned. user is mm_crowd_desc.user. */
typedef void (*mm_crowd_parallel_for)(void *user, int count, mm_crowd_work work, void *work_context);

/* mm's pool hands out characters this many at a time (a small batch: the searches make the
 * characters' ticks uneven, so threads take the next batch as they finish). */
#define MM_CROWD_BATCH 8

typedef struct mm_crowd_desc {
    int count;                          /* characters (>= 0) */
    const mm_character_desc *character; /* every character's tuning; NULL: the database's
                                           (mm_character_desc_from_database) */
    const mm_moves_desc *moves;         /* NULL: mm_moves_desc_from_database */
    const mm_scene *scene;              /* the move layer's scene; NULL: flat ground */
    mm_crowd_parallel_for parallel_for; /* the game's; NULL: mm's pool */
    void *user;                         /* passed to parallel_for */
    int threads;                        /* mm's pool without parallel_for: 0 or 1 the calling
                                           thread alone, at most MM_SEARCH_MAX_THREADS */
    const mm_allocator *allocator;      /* NULL: malloc */
    bool spread_searches;               /* each character's search schedule shifted by a phase of its
                                           own (mm_character_set_search_phase, spread evenly by its
                                           index), so that every tick has about the same searches;
                                           false: all search on the same ticks, each character as
                                           mm simulate moves one */
} mm_crowd_desc;

typedef struct mm_crowd_state mm_crowd_state; /* private */

typedef struct mm_crowd {
    const mm_database *db;
    const mm_searcher *searcher; /* the one given, or the crowd's own */
    int count;
    mm_character *characters; /* [count] */
    mm_moves *moves;          /* [count]: each character's move layer; NULL without a scene (the
                                 layer would only call mm_character_update) */
    mm_crowd_state *state;
} mm_crowd;

/* Makes count characters (each as mm_character_init: at the origin facing +Z) and their move
 * layers, and mm's pool when asked for. searcher: one of db made with one thread (a crowd searches
 * from many threads at once; a searcher with a pool would serialise them), or NULL for the crowd
 * to make its own. The database, searcher and scene must outlive the crowd.
 * MM_ERR_INVALID_ARGUMENT: no crowd or db, a negative count, threads out of range, a searcher of
 * another database or with threads; MM_ERR_OUT_OF_MEMORY. On failure nothing is left allocated. */
mm_result mm_crowd_init(mm_crowd *crowd, const mm_database *db, const mm_searcher *searcher,
                        const mm_crowd_desc *desc, mm_error *err);

/* One tick of dt seconds for every character: inputs[i] is character i's (inputs NULL: no input,
 * every character stands). Each character runs mm_moves_update (which runs mm_character_update).
 * Allocates nothing. */
void mm_crowd_update(mm_crowd *crowd, const mm_input *inputs, float dt);

void mm_crowd_free(mm_crowd *crowd);

#ifdef __cplusplus
}
#endif

#endif /* MM_CROWD_H */
