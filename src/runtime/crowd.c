/* Many characters ticked together through a parallel-for: the game's, or mm's pool (mm/crowd.h). */
#include <mm/crowd.h>

#include <math.h>
#include <stdatomic.h>
#include <string.h>

#include "search/pool.h"

/* bytes: a cache line */
#define CACHE_LINE 64

struct mm_crowd_state {
    mm_searcher own_searcher; /* when the crowd was given none */
    bool owns_searcher;
    mm_searcher_pool *pool; /* mm's threads (NULL: the calling thread alone, or the game's) */
    mm_crowd_parallel_for parallel_for;
    void *user;
    /* this tick's work, read by every thread */
    const mm_input *inputs;
    float dt;
    /* mm's pool: the first character no thread has taken yet, alone on its cache line (each thread
     * writes it per batch; the fields above are read per batch by every thread) */
    char before_next[CACHE_LINE];
    atomic_int next;
    char after_next[CACHE_LINE];
    mm_allocator allocator;
};

/* The search phase of character i with spread searches: the fractional parts of i times the golden
 * ratio, which fill [0, 1) evenly for any number of characters and any search interval. */
#define PHASE_STEP 0.6180339887498949

static float search_phase(int i)
{
    float phase = (float)fmod((double)i * PHASE_STEP, 1.0);
    return phase < 1.0f ? phase : 0.0f;
}

/* No input: the stick at rest, walking (what a character stands still on). */
static const mm_input NO_INPUT;

/* The tick of characters [begin, end): each alone with its input (the only thing any of them writes
 * is its own character and move layer). */
static void tick_range(void *context, int begin, int end)
{
    mm_crowd *crowd = (mm_crowd *)context;
    const mm_crowd_state *s = crowd->state;
    if (begin < 0) begin = 0;
    if (end > crowd->count) end = crowd->count;
    for (int i = begin; i < end; ++i) {
        const mm_input *in = s->inputs ? &s->inputs[i] : &NO_INPUT;
        if (crowd->moves)
            mm_moves_update(&crowd->moves[i], &crowd->characters[i], in, s->dt);
        else
            mm_character_update(&crowd->characters[i], in, s->dt);
    }
}

/* A thread of mm's pool: batches of MM_CROWD_BATCH characters, taken in turn until none is left. */
static void pool_worker(void *context, int worker, int workers)
{
    (void)worker, (void)workers;
    mm_crowd *crowd = (mm_crowd *)context;
    for (;;) {
        int begin = atomic_fetch_add(&crowd->state->next, MM_CROWD_BATCH);
        if (begin >= crowd->count) return;
        tick_range(crowd, begin, begin + MM_CROWD_BATCH);
    }
}

void mm_crowd_free(mm_crowd *crowd)
{
    if (!crowd) return;
    mm_crowd_state *s = crowd->state;
    if (crowd->characters)
        for (int i = 0; i < crowd->count; ++i) mm_character_free(&crowd->characters[i]);
    if (s) {
        mm__pool_destroy(s->pool);
        if (s->owns_searcher) mm_searcher_free(&s->own_searcher);
        mm_allocator a = s->allocator;
        mm_free(&a, crowd->characters);
        mm_free(&a, crowd->moves);
        mm_free(&a, s);
    }
    memset(crowd, 0, sizeof *crowd);
}

mm_result mm_crowd_init(mm_crowd *crowd, const mm_database *db, const mm_searcher *searcher,
                        const mm_crowd_desc *desc, mm_error *err)
{
    if (!crowd) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "mm_crowd_init: no crowd");
    memset(crowd, 0, sizeof *crowd);
    mm_crowd_desc zero;
    memset(&zero, 0, sizeof zero);
    const mm_crowd_desc *d = desc ? desc : &zero;
    if (!db) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "mm_crowd_init: no database");
    if (d->count < 0)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "mm_crowd_init: count %d is negative",
                            d->count);
    if (d->threads < 0 || d->threads > MM_SEARCH_MAX_THREADS)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "mm_crowd_init: threads %d is not in 0..%d",
                            d->threads, MM_SEARCH_MAX_THREADS);
    if (searcher && searcher->db != db)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                            "mm_crowd_init: the searcher is not of this database");
    if (searcher && searcher->threads > 1)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                            "mm_crowd_init: the searcher has %d threads: a crowd's characters search from "
                            "many threads at once and need a searcher of one",
                            searcher->threads);

    mm_allocator allocator;
    memset(&allocator, 0, sizeof allocator);
    if (d->allocator) allocator = *d->allocator;
    mm_crowd_state *s = (mm_crowd_state *)mm_alloc_array(&allocator, 1, sizeof *s);
    if (!s) return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "mm_crowd_init: out of memory");
    s->allocator = allocator;
    s->parallel_for = d->parallel_for;
    s->user = d->user;
    crowd->state = s;
    crowd->db = db;
    mm_result r = MM_OK;
    if (!searcher) {
        mm_searcher_desc sd;
        memset(&sd, 0, sizeof sd);
        sd.allocator = d->allocator;
        r = mm_searcher_init(&s->own_searcher, db, &sd, err);
        if (r != MM_OK) goto fail;
        s->owns_searcher = true;
        searcher = &s->own_searcher;
    }
    crowd->searcher = searcher;

    mm_character_desc cd;
    if (d->character)
        cd = *d->character;
    else if ((r = mm_character_desc_from_database(&cd, db, err)) != MM_OK)
        goto fail;
    if (!cd.allocator) cd.allocator = d->allocator;
    mm_moves_desc md;
    if (d->moves)
        md = *d->moves;
    else
        mm_moves_desc_from_database(&md, db);

    if (d->count > 0) {
        crowd->characters =
            (mm_character *)mm_alloc_array(&allocator, (size_t)d->count, sizeof *crowd->characters);
        /* without a scene the move layer would only call mm_character_update: none is made */
        if (d->scene)
            crowd->moves = (mm_moves *)mm_alloc_array(&allocator, (size_t)d->count, sizeof *crowd->moves);
        if (!crowd->characters || (d->scene && !crowd->moves)) {
            r = mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0,
                             "mm_crowd_init: out of memory for %d characters", d->count);
            goto fail;
        }
    }
    for (int i = 0; i < d->count; ++i) {
        r = mm_character_init(&crowd->characters[i], db, searcher, &cd, err);
        if (r != MM_OK) goto fail;
        crowd->count = i + 1; /* what mm_crowd_free frees */
        if (d->spread_searches) mm_character_set_search_phase(&crowd->characters[i], search_phase(i));
        if (crowd->moves && (r = mm_moves_init(&crowd->moves[i], db, d->scene, &md, err)) != MM_OK) goto fail;
    }
    crowd->count = d->count;
    if (!d->parallel_for && d->threads > 1) {
        s->pool = mm__pool_create(d->threads, d->allocator);
        if (!s->pool) {
            r = mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "mm_crowd_init: cannot start %d threads",
                             d->threads);
            goto fail;
        }
    }
    return MM_OK;
fail:
    mm_crowd_free(crowd);
    return r;
}

void mm_crowd_update(mm_crowd *crowd, const mm_input *inputs, float dt)
{
    if (!crowd || !crowd->state || crowd->count == 0) return;
    mm_crowd_state *s = crowd->state;
    s->inputs = inputs;
    s->dt = dt;
    if (s->parallel_for) {
        s->parallel_for(s->user, crowd->count, tick_range, crowd);
    } else if (s->pool) {
        atomic_store(&s->next, 0);
        mm__pool_run(s->pool, pool_worker, crowd);
    } else {
        tick_range(crowd, 0, crowd->count);
    }
}
