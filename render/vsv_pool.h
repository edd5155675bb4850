/* vsv_pool.h — the renderer's persistent thread pool: a job is a function
 * over items 0..n-1 handed out one at a time by an atomic counter; the
 * caller's thread works as worker 0. Private to render/. */
#ifndef VSV_POOL_H
#define VSV_POOL_H

#include <pthread.h>

#define VSV_POOL_MAX 64 /* threads at most */

typedef struct vsv_pool {
    int nthreads;
    pthread_t tid[VSV_POOL_MAX];
    pthread_mutex_t mu;
    pthread_cond_t go, done;
    int generation, running, finished, quit;
    /* the current job: items handed out one at a time */
    void (*job)(void *ctx, int item, int thread);
    void *job_ctx;
    int nitems, next_item;
    struct vsv_pool_slot {
        struct vsv_pool *p;
        int index;
    } slot[VSV_POOL_MAX];
} vsv_pool;

/* Starts n - 1 threads (n clamped to [1, VSV_POOL_MAX]; fewer when a thread
 * cannot be created) into p, which the caller holds zeroed. */
void vsv_pool_start(vsv_pool *p, int n);
/* Runs job(ctx, item, thread) for items 0..n-1 on every thread (thread <
 * p->nthreads); returns when every item is done. */
void vsv_pool_run(vsv_pool *p, void (*job)(void *, int, int), void *ctx, int n);
/* Stops and joins the threads; a pool never started is left alone. */
void vsv_pool_stop(vsv_pool *p);

#endif
