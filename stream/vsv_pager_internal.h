/* vsv_pager_internal.h — the pager's state and the parts of it each file
 * of stream/ works on: the cache of decoded bricks (vsv_cache.c: the hash
 * of entries and the least-recently-used lists), the buffers (vsv_slab.c),
 * the prefetch scheduler (vsv_sched.c), decoding (vsv_pager_work.c) and the
 * API (vsv_pager.c). Every function here runs under p->mu unless it says
 * otherwise. Private to stream/.
 *
 * Lock discipline (what ThreadSanitizer checks): p->mu guards every field
 * below except the ones set at open and never changed (f, info, meta, sizes,
 * budget, ahead, incremental, the worker arrays) and own_mu's decoder and
 * scratch. Decoding runs outside p->mu on buffers the decoding thread owns
 * by claim: the LOADING entries of its job and the busy track (nothing else
 * touches them until the job is finished under p->mu). own_mu is only ever
 * taken without p->mu held. A thread waits (on `ready`) only for LOADING
 * entries, busy tracks and chunk indexes being fetched, and a job never
 * waits: no cycle.
 *
 * Transfers (a byte source: a file on a web server) never happen under
 * p->mu, so no call waits for a stalled server behind the lock: the code
 * under it reads chunk indexes only through vsv_pager_chunk, which lets
 * through those the reader holds (vsv_file_chunk_resident) and names a
 * missing one in p->missing instead of fetching it; a worker, or a caller
 * that waits, fetches it with the lock dropped (vsv_pager_fetch_missing).
 * Payloads are fetched by jobs, outside the lock already. */
#ifndef VSV_PAGER_INTERNAL_H
#define VSV_PAGER_INTERNAL_H

#include "vsv_pager.h"

#include <pthread.h>
#include <stddef.h>
#include <stdint.h>
#include <time.h>

/* an entry: being decoded; decoded; damaged (stays so: its code in `why`,
 * its message in `data`); a transfer failed (the same, retried once
 * p->retry_at has passed) */
enum { LOADING, READY, FAILED, STALLED };
/* a step's chunk index, for the lock's code (p->cst): not fetched; being
 * fetched (outside the lock); there; its fetch failed (retried once
 * p->retry_at has passed); a negative VSV_E* code: damaged */
enum { C_UNKNOWN, C_LOADING, C_RESIDENT, C_STALLED };
/* seconds before what a failed transfer left is tried again */
#define VSV_PAGER_RETRY 1.0
/* the least-recently-used lists an entry can be on: unpinned READY or
 * FAILED bricks outside / inside the prefetch window, and checkpoints
 * (pinned and LOADING entries are on none: eviction never sees them) */
enum { L_NONE, L_OUT, L_IN, L_CK };

/* Intrusive list links (indices into the entry or track array; -1 ends). */
typedef struct vsv_link {
    int prev, next;
} vsv_link;
typedef struct vsv_lru {
    int head, tail; /* head: least recently used */
} vsv_lru;

typedef struct entry {
    vsv_link ln;    /* first: the LRU links */
    int s, b, step; /* key: the step whose payload defines this brick state */
    int state, pins;
    int listed;     /* on an LRU list: [L_CK] for a checkpoint, else [L_IN] when mark is the pager's, else [L_OUT] */
    int mark;       /* == the pager's window mark: needed ahead of the playhead */
    void *data;     /* the brick's floats, or a checkpoint's codes */
    int next;       /* hash chain, or free list */
    int lo, halves; /* a checkpoint: the state in its second half (-1 none); halves not yet used (bits 1, 2) */
    int why;        /* FAILED, STALLED: the error code */
} entry;

/* A checkpoint is an entry keyed (s + nspecies, b, step) holding the
 * brick's codes at that defining step and, in the second half of its brick
 * buffer, at the defining step before it (`lo`): pool 0 only, as a pool of
 * its own would keep its memory after the checkpoints are gone, beyond the
 * budget; a backward walk
 * from a keyframe saves the states it passes on the way to the group's top
 * step, so reaching them later costs a copy, not a payload undone. They
 * count as decoder state (track_bytes) and are evicted before tracks.
 *
 * Per-(species, brick) decoder state: the brick's codes at `step`, so the
 * next step costs one delta. Busy while a job decodes with it; idle tracks
 * holding codes are on the track LRU list (evictable). */
typedef struct track {
    vsv_link ln;     /* first: the LRU links */
    uint16_t *codes; /* brick^3 codes, or NULL (none held) */
    int step;        /* the step codes hold; -1 none */
    int busy, listed;
} track;

/* The defining step of every brick of (step, species), in a direct-mapped
 * cache of rows allocated at open (counted as fixed bytes): -1 = no memory
 * needed (empty). */
typedef struct defrow {
    int step, s; /* which row the slot holds; step -1 none */
    int *def;
} defrow;

/* One decode: brick b of species s from the state `from` on through the
 * outputs' defining steps (ascending), each into a claimed LOADING entry. */
typedef struct job {
    int s, b, n;
    int *step, *ent;            /* n outputs (capacity p->job_cap): defining steps, entries */
    float **out;                /* the entries' buffers */
    int track;                  /* the busy track used, or -1 (scratch codes) */
    uint16_t *codes;            /* the track's codes, or NULL */
    int from;                   /* first step to apply; rev: the step the track's codes hold */
    int rev;                    /* 1: undo deltas from `from` down (outputs served highest first) */
    int copy;                   /* a READY checkpoint (pinned) whose codes start the job, or -1 */
    int copy_half;              /* which half of it */
    const uint16_t *copy_codes; /* that half (read outside the lock: p->ent may move) */
    int nck;                    /* states the walk saves in checkpoints (ascending steps; LOADING) */
    int *ck_step, *ck_ent;      /* each state's step and checkpoint entry (two states an entry) */
    uint16_t **ck_buf;          /* where each state goes */
    int fresh;                  /* 1: from is an absolute (or empty) state: start clean */
    int payloads;               /* payloads the job decodes */
} job;

struct shell;

struct vsv_pager {
    /* set at open, then read-only */
    vsv_file *f;
    vsv_file_info info;
    const vsv_meta *meta;
    size_t brick_bytes, codes_bytes, budget, fixed;
    int ahead, incremental, job_cap;
    /* under mu */
    pthread_mutex_t mu;
    pthread_cond_t ready, work;
    entry *ent;
    int nent, capent, freelist;
    int *bucket;
    unsigned nbucket;
    vsv_lru lru[4]; /* indexed by L_*: [L_OUT], [L_IN], [L_CK] */
    track *tracks;  /* nspecies * nbricks */
    vsv_lru tlru;
    size_t bytes, pinned, peak, track_bytes;
    defrow *rows;
    int nrows; /* a power of two */
    /* the playhead */
    int head, dir, gen;
    int *next, nnext; /* the steps the next frames show (capacity ahead + 1) */
    unsigned char *want;
    size_t step_bytes; /* the largest step seen (all wanted species) */
    int depth;
    int mark, marked_gen;       /* entries of the prefetch window carry mark */
    int scan_d, scan_s, scan_b; /* where the last prefetch scan stopped (this mark) */
    int focus, focus_dir;       /* the step being decoded ahead: finished before moving on */
    int quit, idle, kick;       /* workers waiting; bumped when a track is released */
    struct shell *shells;       /* volumes handed out and not freed yet */
    vsv_pager_stats st;
    char err[512];
    /* transfers: per step its chunk index's C_* state (and a damaged one's
     * message), the step whose index a thread should fetch (-1 none), when
     * what a failed transfer left is tried again, that failure's message */
    signed char *cst;
    char **cmsg;
    int missing;
    double retry_at;
    char ioerr[512];
    /* the workers: each owns dec[i], scratch[i] and jobs[i] */
    pthread_t *tid;
    int nthreads;
    vsv_decoder **dec;
    uint16_t **scratch;
    job *jobs;
    /* for callers' demand decodes: under own_mu */
    pthread_mutex_t own_mu;
    vsv_decoder *own;
    uint16_t *own_scratch;
    /* buffers: brick floats (pool 0) and track codes (pool 1) carved from
     * 2 MB slabs (huge pages where the kernel gives them: far fewer page
     * faults) and recycled through free lists */
    struct vsv_pool {
        size_t size; /* bytes a buffer */
        void **slabs;
        int nslabs, capslabs;
        size_t slab_used;
        void *freebuf;
    } pool[2];
    size_t slab_bytes;
    void *(*slab_alloc)(void *ctx, size_t bytes); /* pool 0's slabs: the caller's (vsv_pager_opts) */
    void *slab_ctx;
};

typedef struct shell {
    vsv_volume v;              /* first: callers see a vsv_volume */
    vsv_pager *p;              /* NULL once the pager is freed (the shell outlives it) */
    int *held;                 /* entry index per brick, -1 none */
    int *def;                  /* the defining steps being filled (a copy of the row) */
    job job;                   /* the caller's demand decodes */
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

/* intrusive lists (vsv_cache.c): base is the entry or track array, whose
 * elements start with their vsv_link */
void vsv_lru_init(vsv_lru *l);
void vsv_lru_push(vsv_lru *l, void *base, size_t stride, int i);
void vsv_lru_unlink(vsv_lru *l, void *base, size_t stride, int i);
/* the cache (vsv_cache.c) */
int vsv_cache_lookup(const vsv_pager *p, int s, int b, int step);
int vsv_cache_rehash(vsv_pager *p, unsigned n);
int vsv_cache_claim(vsv_pager *p, int s, int b, int step);
void vsv_cache_drop(vsv_pager *p, int e);
/* An entry's use: to the tail of its list (after a pin is dropped, a
 * decode finished, a window mark changed). */
void vsv_cache_touch(vsv_pager *p, int e);
void vsv_cache_pin(vsv_pager *p, int e);
void vsv_cache_unpin(vsv_pager *p, int e);
/* The window's entries: everything marked before moves to the outside list. */
void vsv_cache_new_window(vsv_pager *p);
/* Marks e as needed by the current window. */
void vsv_cache_mark(vsv_pager *p, int e);
int vsv_cache_make_room(vsv_pager *p, size_t extra, int window);
/* Room for a checkpoint: evicts only bricks outside the window. */
int vsv_cache_room_ck(vsv_pager *p);
/* Whether entry e is a checkpoint (codes), and its buffer's bytes. */
static inline int vsv_cache_is_ck(const vsv_pager *p, int e) { return p->ent[e].s >= p->info.nspecies; }
static inline size_t vsv_cache_size(const vsv_pager *p, int e)
{
    (void)e;
    return p->brick_bytes;
}
/* buffers (vsv_slab.c) */
void *vsv_slab_get(vsv_pager *p, int pool);
void vsv_slab_put(vsv_pager *p, int pool, void *b);
void vsv_slab_free_all(vsv_pager *p);
/* the prefetch scheduler (vsv_sched.c) */
int vsv_sched_ahead(const vsv_pager *p, int d);
void vsv_sched_mark_window(vsv_pager *p);
/* The next job: 1 with j made, 0 none, or the error of one that could not
 * be made (its outputs failed, or released: VSV_EAGAIN, VSV_ENOMEM). */
int vsv_sched_next(vsv_pager *p, job *j);
/* transfers (vsv_pager_io.c) */
/* What a failure's code says of the data: 1 damaged (stays so), 0 not (a
 * transfer that failed, a chunk index not fetched yet, out of memory). */
static inline int vsv_pager_damage(int rc) { return rc && rc != VSV_EIO && rc != VSV_EAGAIN && rc != VSV_ENOMEM; }
/* The code vsv_pager_get returns for rc: a damage other than a truncation
 * is VSV_ECORRUPT; VSV_ETRUNC, VSV_EIO, VSV_EAGAIN, VSV_ENOMEM stay. */
static inline int vsv_pager_fold(int rc) { return !vsv_pager_damage(rc) || rc == VSV_ETRUNC ? rc : VSV_ECORRUPT; }
/* 0 when step t's chunk index can be read without a transfer; else (error
 * set) VSV_EAGAIN (not fetched yet: p->missing names it, or a thread
 * fetches it now), VSV_EIO (its fetch failed; tried again after
 * p->retry_at) or its damage code. */
int vsv_pager_chunk(vsv_pager *p, int t);
/* vsv_file_brick_kind through vsv_pager_chunk: the kind, or an error (set). */
int vsv_pager_kind(vsv_pager *p, int t, int s, int b);
/* Fetches the chunk index p->missing names with the lock dropped: 1 if
 * there was one, else 0. */
int vsv_pager_fetch_missing(vsv_pager *p);
/* A caller that waits (vsv_pager_get with wait): a missing chunk index
 * fetched, else the wait for the one being fetched. */
void vsv_pager_wait_chunk(vsv_pager *p);
/* A transfer failed (msg says how): what it left is tried again after
 * VSV_PAGER_RETRY seconds. */
void vsv_pager_stalled(vsv_pager *p, const char *msg);
/* Whether what a failed transfer left may be tried again now. */
int vsv_pager_due(const vsv_pager *p);
/* decoding (vsv_pager_work.c) */
void vsv_pager_set_err(vsv_pager *p, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* The defining steps of (step, s), or NULL with *rc (may be NULL) the
 * error (vsv_pager_chunk's, or the chunk's damage). */
const int *vsv_pager_defs(vsv_pager *p, int step, int s, int *rc);
int vsv_pager_job_make(vsv_pager *p, job *j, int s, int b, int step);
int vsv_pager_job_prewalk(vsv_pager *p, job *j);
int vsv_pager_job_run(vsv_pager *p, vsv_decoder *d, job *j, uint16_t *scratch, char *msg, size_t cap);
void vsv_pager_job_finish(vsv_pager *p, job *j, int rc, double secs, int keep_last, const char *msg);
void *vsv_pager_worker(void *arg); /* a wslot, which it frees */

#endif
