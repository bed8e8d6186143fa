/* pool.h (private) - a fixed pool of threads that run one job together.
 *
 * mm__pool_run(pool, fn, ctx) runs fn(ctx, i, n) on n threads (the caller is thread 0) and
 * returns when all are done. Threads are made at creation; running a job allocates nothing.
 * Calls from several threads are serialised. */
#ifndef MM_SEARCH_POOL_H
#define MM_SEARCH_POOL_H

#include <mm/alloc.h>

typedef struct mm_searcher_pool mm_searcher_pool;
typedef void (*mm__pool_fn)(void *ctx, int worker, int workers);

/* NULL on failure (or for threads < 2: no pool is needed). */
mm_searcher_pool *mm__pool_create(int threads, const mm_allocator *allocator);
void mm__pool_run(mm_searcher_pool *pool, mm__pool_fn fn, void *ctx);
int mm__pool_size(const mm_searcher_pool *pool);
void mm__pool_destroy(mm_searcher_pool *pool);

#endif
