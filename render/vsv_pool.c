/* vsv_pool.c — the renderer's persistent thread pool (vsv_pool.h). A frame
 * is a few short jobs in a row, so idle workers spin briefly before they
 * sleep. */
#include "vsv_pool.h"

#include <stddef.h>

static void run_items(vsv_pool *p, int thread)
{
    for (;;) { /* one atomic counter hands out the items (a lock per item cost as much as a warp row) */
        const int item = __atomic_fetch_add(&p->next_item, 1, __ATOMIC_RELAXED);
        if (item >= p->nitems)
            return;
        p->job(p->job_ctx, item, thread);
    }
}

/* A frame runs several short jobs in a row (the ground, compositing, the
 * warp): a thread that has just finished one, or waits for the others to,
 * spins this many pauses (tens of microseconds) before it sleeps, so the next
 * job does not wait for a wake-up (measured: the shear-warp's warp got no help
 * from a second thread without it). */
#define SPIN 4000
#if defined(__x86_64__) || defined(__i386__)
#define PAUSE() __builtin_ia32_pause()
#else
#define PAUSE() ((void)0)
#endif

static void *worker(void *arg)
{
    struct vsv_pool_slot *ws = arg;
    vsv_pool *p = ws->p;
    int seen = 0;
    for (;;) {
        for (int i = 0; i < SPIN && __atomic_load_n(&p->generation, __ATOMIC_ACQUIRE) == seen &&
                        !__atomic_load_n(&p->quit, __ATOMIC_RELAXED);
             i++)
            PAUSE();
        pthread_mutex_lock(&p->mu);
        while (p->generation == seen && !p->quit)
            pthread_cond_wait(&p->go, &p->mu);
        if (p->quit) {
            pthread_mutex_unlock(&p->mu);
            return NULL;
        }
        seen = p->generation;
        pthread_mutex_unlock(&p->mu);
        run_items(p, ws->index);
        pthread_mutex_lock(&p->mu);
        __atomic_add_fetch(&p->finished, 1, __ATOMIC_RELEASE);
        pthread_cond_signal(&p->done);
        pthread_mutex_unlock(&p->mu);
    }
}

void vsv_pool_run(vsv_pool *p, void (*job)(void *, int, int), void *ctx, int n)
{
    pthread_mutex_lock(&p->mu);
    p->job = job;
    p->job_ctx = ctx;
    p->nitems = n;
    p->next_item = 0;
    p->finished = 0;
    __atomic_add_fetch(&p->generation, 1, __ATOMIC_RELEASE);
    pthread_cond_broadcast(&p->go);
    pthread_mutex_unlock(&p->mu);
    run_items(p, 0);
    for (int i = 0; i < SPIN && __atomic_load_n(&p->finished, __ATOMIC_ACQUIRE) < p->nthreads - 1; i++)
        PAUSE();
    pthread_mutex_lock(&p->mu);
    while (p->finished < p->nthreads - 1)
        pthread_cond_wait(&p->done, &p->mu);
    pthread_mutex_unlock(&p->mu);
}

void vsv_pool_start(vsv_pool *p, int n)
{
    p->nthreads = n < 1 ? 1 : n > VSV_POOL_MAX ? VSV_POOL_MAX : n;
    pthread_mutex_init(&p->mu, NULL);
    pthread_cond_init(&p->go, NULL);
    pthread_cond_init(&p->done, NULL);
    for (int i = 1; i < p->nthreads; i++) { /* the caller's thread is worker 0 */
        p->slot[i] = (struct vsv_pool_slot){p, i};
        if (pthread_create(&p->tid[i], NULL, worker, &p->slot[i])) {
            p->nthreads = i;
            break;
        }
    }
    p->running = 1;
}

void vsv_pool_stop(vsv_pool *p)
{
    if (!p->running)
        return;
    pthread_mutex_lock(&p->mu);
    __atomic_store_n(&p->quit, 1, __ATOMIC_RELEASE);
    pthread_cond_broadcast(&p->go);
    pthread_mutex_unlock(&p->mu);
    for (int i = 1; i < p->nthreads; i++)
        pthread_join(p->tid[i], NULL);
    pthread_mutex_destroy(&p->mu);
    pthread_cond_destroy(&p->go);
    pthread_cond_destroy(&p->done);
    p->running = 0;
}
