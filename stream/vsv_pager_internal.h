/* vsv_pager_internal.h — the pager's state and the parts of it each file
 * of stream/ works on: the cache of decoded bricks (vsv_cache.c: the hash
 * of entries and least-recently-used eviction), the brick buffers
 * (vsv_slab.c), the prefetch scheduler (vsv_sched.c), the decoding workers
 * (vsv_pager_work.c) and the API (vsv_pager.c). Every function here runs
 * under p->mu unless it says otherwise. Private to stream/. */
#ifndef VSV_PAGER_INTERNAL_H
#define VSV_PAGER_INTERNAL_H

#include "vsv_pager.h"

#include <pthread.h>
#include <stddef.h>
#include <stdint.h>
#include <time.h>

enum { LOADING, READY, FAILED };

typedef struct entry {
    int s, b, step; /* key: the step whose payload defines this brick state */
    int state, pins;
    int mark;       /* == the pager's window mark: needed ahead of the playhead */
    float *data;
    uint64_t tick;
    int next; /* hash chain, or free list */
} entry;

/* defining steps of every brick of (step, species): -1 = no memory needed */
typedef struct defrow {
    int *def;
} defrow;

struct shell;

struct vsv_pager {
    struct shell *shells; /* volumes handed out and not freed yet */
    vsv_file *f;
    vsv_file_info info;
    const vsv_meta *meta;
    size_t brick_bytes, budget;
    int ahead;
    pthread_mutex_t mu;
    pthread_cond_t ready, work;
    entry *ent;
    int nent, capent, freelist;
    int *bucket;
    unsigned nbucket;
    uint64_t tick;
    size_t bytes, pinned, peak;
    defrow *rows; /* nsteps * nspecies, filled on first use */
    /* the playhead */
    int head, dir, stride, loop, gen;
    unsigned char *want;
    size_t step_bytes; /* the largest step seen (all wanted species) */
    int depth;
    int mark, marked_gen; /* entries of the prefetch window carry mark */
    int scan_d, scan_s, scan_b; /* where the last prefetch scan stopped (this mark) */
    int focus, focus_dir;       /* the step being decoded ahead: finished before moving on */
    /* workers */
    pthread_t *tid;
    int nthreads, quit;
    vsv_decoder **dec; /* one per worker */
    vsv_decoder *own;  /* for callers' demand decodes (under own_mu) */
    pthread_mutex_t own_mu;
    vsv_pager_stats st;
    char err[512];
    /* brick buffers: carved from 2 MB slabs (huge pages where the kernel
     * gives them: far fewer page faults) and recycled through a free list */
    void **slabs;
    int nslabs, capslabs;
    size_t slab_bytes, slab_used;
    void *freebuf;
};

typedef struct shell {
    vsv_volume v; /* first: callers see a vsv_volume */
    vsv_pager *p; /* NULL once the pager is freed (the shell outlives it) */
    int *held; /* entry index per brick, -1 none */
    struct shell *prev, *next; /* the pager's live shells (under p->mu) */
} shell;

typedef struct wslot {
    vsv_pager *p;
    int index;
} wslot;

static inline double vsv_pager_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* Whether species s is among those the playhead wants. */
static inline int vsv_sched_wanted(const vsv_pager *p, int s) { return !p->want || p->want[s]; }

/* the cache (vsv_cache.c) */
int vsv_cache_lookup(const vsv_pager *p, int s, int b, int step);
void vsv_cache_unlink(vsv_pager *p, int e);
int vsv_cache_rehash(vsv_pager *p, unsigned n);
int vsv_cache_insert(vsv_pager *p, int s, int b, int step);
int vsv_cache_claim(vsv_pager *p, int s, int b, int step);
void vsv_cache_drop(vsv_pager *p, int e);
int vsv_cache_make_room(vsv_pager *p, size_t extra, int window);
/* brick buffers (vsv_slab.c) */
float *vsv_slab_get(vsv_pager *p);
void vsv_slab_put(vsv_pager *p, float *b);
/* the prefetch scheduler (vsv_sched.c) */
int vsv_sched_ahead(const vsv_pager *p, int d);
int vsv_sched_mark_window(vsv_pager *p);
int vsv_sched_next(vsv_pager *p, int *s_out, int *b_out, int *step_out);
/* decoding (vsv_pager_work.c) */
void vsv_pager_set_err(vsv_pager *p, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
const int *vsv_pager_defs(vsv_pager *p, int step, int s);
int vsv_pager_decode(vsv_pager *p, vsv_decoder *d, int s, int b, int step, float *out, char *msg, size_t cap);
void vsv_pager_finish(vsv_pager *p, int e, int ok, double secs);
void *vsv_pager_worker(void *arg); /* a wslot, which it frees */

#endif
