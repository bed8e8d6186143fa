#include "search/pool.h"

#include <pthread.h>
#include <string.h>

#define MAX_THREADS 64

typedef struct worker_arg {
    struct mm_searcher_pool *pool;
    int index;
} worker_arg;

struct mm_searcher_pool {
    int n;       /* threads including the caller */
    int started; /* worker threads running */
    pthread_t threads[MAX_THREADS];
    worker_arg args[MAX_THREADS];
    pthread_mutex_t lock, call;
    pthread_cond_t start, done;
    unsigned long generation;
    int pending, stop;
    mm__pool_fn fn;
    void *ctx;
    mm_allocator allocator;
};

static void *worker(void *p)
{
    const worker_arg *arg = (const worker_arg *)p;
    mm_searcher_pool *pool = arg->pool;
    unsigned long seen = 0;
    pthread_mutex_lock(&pool->lock);
    for (;;) {
        while (pool->generation == seen && !pool->stop) pthread_cond_wait(&pool->start, &pool->lock);
        if (pool->stop) break;
        seen = pool->generation;
        mm__pool_fn fn = pool->fn;
        void *ctx = pool->ctx;
        pthread_mutex_unlock(&pool->lock);
        fn(ctx, arg->index, pool->n);
        pthread_mutex_lock(&pool->lock);
        if (--pool->pending == 0) pthread_cond_signal(&pool->done);
    }
    pthread_mutex_unlock(&pool->lock);
    return NULL;
}

mm_searcher_pool *mm__pool_create(int threads, const mm_allocator *allocator)
{
    if (threads < 2) return NULL;
    if (threads > MAX_THREADS) threads = MAX_THREADS;
    mm_searcher_pool *pool = (mm_searcher_pool *)mm_alloc_array(allocator, 1, sizeof *pool);
    if (!pool) return NULL;
    if (allocator) pool->allocator = *allocator;
    pool->n = threads;
    pthread_mutex_init(&pool->lock, NULL);
    pthread_mutex_init(&pool->call, NULL);
    pthread_cond_init(&pool->start, NULL);
    pthread_cond_init(&pool->done, NULL);
    for (int i = 1; i < threads; ++i) {
        pool->args[i].pool = pool;
        pool->args[i].index = i;
        if (pthread_create(&pool->threads[i], NULL, worker, &pool->args[i]) != 0) {
            pool->n = i; /* run with the threads that did start */
            break;
        }
        pool->started = i;
    }
    if (pool->n < 2) {
        mm__pool_destroy(pool);
        return NULL;
    }
    return pool;
}

int mm__pool_size(const mm_searcher_pool *pool) { return pool ? pool->n : 1; }

void mm__pool_run(mm_searcher_pool *pool, mm__pool_fn fn, void *ctx)
{
    if (!pool) {
        fn(ctx, 0, 1);
        return;
    }
    pthread_mutex_lock(&pool->call);
    pthread_mutex_lock(&pool->lock);
    pool->fn = fn;
    pool->ctx = ctx;
    pool->pending = pool->n - 1;
    ++pool->generation;
    pthread_cond_broadcast(&pool->start);
    pthread_mutex_unlock(&pool->lock);
    fn(ctx, 0, pool->n);
    pthread_mutex_lock(&pool->lock);
    while (pool->pending > 0) pthread_cond_wait(&pool->done, &pool->lock);
    pthread_mutex_unlock(&pool->lock);
    pthread_mutex_unlock(&pool->call);
}

void mm__pool_destroy(mm_searcher_pool *pool)
{
    if (!pool) return;
    pthread_mutex_lock(&pool->lock);
    pool->stop = 1;
    pthread_cond_broadcast(&pool->start);
    pthread_mutex_unlock(&pool->lock);
    for (int i = 1; i <= pool->started; ++i) pthread_join(pool->threads[i], NULL);
    pthread_mutex_destroy(&pool->lock);
    pthread_mutex_destroy(&pool->call);
    pthread_cond_destroy(&pool->start);
    pthread_cond_destroy(&pool->done);
    mm_allocator a = pool->allocator;
    mm_free(&a, pool);
}
