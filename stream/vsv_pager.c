/* vsv_pager.c — see vsv_pager.h. One mutex guards the cache (a hash of
 * entries keyed by species, brick and defining step, with use ticks for
 * least-recently-used eviction); decoding happens outside it. An entry is
 * LOADING while one thread decodes it (others wait on `ready`), then READY
 * or FAILED; it counts as pinned while it is decoded. */
#include "vsv_pager.h"

#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/mman.h>
#include <unistd.h>

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

struct vsv_pager {
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
    vsv_pager *p;
    int *held; /* entry index per brick, -1 none */
} shell;

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

void vsv_pager_opts_init(vsv_pager_opts *o) { memset(o, 0, sizeof *o); }

static unsigned hash3(int s, int b, int step)
{
    uint64_t h = (uint64_t)(unsigned)s * 0x9E3779B97F4A7C15ull ^ (uint64_t)(unsigned)b * 0xC2B2AE3D27D4EB4Full ^
                 (uint64_t)(unsigned)step * 0x165667B19E3779F9ull;
    return (unsigned)(h ^ (h >> 29));
}

static int lookup(const vsv_pager *p, int s, int b, int step)
{
    for (int e = p->bucket[hash3(s, b, step) & (p->nbucket - 1)]; e >= 0; e = p->ent[e].next)
        if (p->ent[e].s == s && p->ent[e].b == b && p->ent[e].step == step)
            return e;
    return -1;
}

static void unlink_entry(vsv_pager *p, int e)
{
    int *at = &p->bucket[hash3(p->ent[e].s, p->ent[e].b, p->ent[e].step) & (p->nbucket - 1)];
    while (*at != e)
        at = &p->ent[*at].next;
    *at = p->ent[e].next;
}

static int rehash(vsv_pager *p, unsigned n)
{
    int *nb = malloc(n * sizeof *nb);
    if (!nb)
        return VSV_ENOMEM;
    for (unsigned i = 0; i < n; i++)
        nb[i] = -1;
    free(p->bucket);
    p->bucket = nb;
    p->nbucket = n;
    for (int e = 0; e < p->nent; e++)
        if (p->ent[e].state >= 0) { /* live entries (state -1: free) */
            const unsigned h = hash3(p->ent[e].s, p->ent[e].b, p->ent[e].step) & (n - 1);
            p->ent[e].next = p->bucket[h];
            p->bucket[h] = e;
        }
    return 0;
}

/* A brick buffer (under the lock); NULL when out of memory. */
static float *buf_get(vsv_pager *p)
{
    if (p->freebuf) {
        void *b = p->freebuf;
        memcpy(&p->freebuf, b, sizeof(void *));
        return b;
    }
    if (!p->nslabs || p->slab_used + p->brick_bytes > p->slab_bytes) {
        if (p->nslabs == p->capslabs) {
            const int cap = p->capslabs ? 2 * p->capslabs : 64;
            void **ns = realloc(p->slabs, (size_t)cap * sizeof *ns);
            if (!ns)
                return NULL;
            p->slabs = ns;
            p->capslabs = cap;
        }
        void *m = NULL;
        if (posix_memalign(&m, (size_t)2 << 20, p->slab_bytes))
            return NULL;
        madvise(m, p->slab_bytes, MADV_HUGEPAGE);
        p->slabs[p->nslabs++] = m;
        p->slab_used = 0;
    }
    float *b = (float *)((char *)p->slabs[p->nslabs - 1] + p->slab_used);
    p->slab_used += p->brick_bytes;
    return b;
}

static void buf_put(vsv_pager *p, float *b)
{
    if (!b)
        return;
    memcpy(b, &p->freebuf, sizeof(void *));
    p->freebuf = b;
}

/* A new LOADING entry with its buffer (under the lock); -1 when out of memory. */
static int insert(vsv_pager *p, int s, int b, int step)
{
    float *buf = buf_get(p);
    if (!buf)
        return -1;
    int e = p->freelist;
    if (e >= 0) {
        p->freelist = p->ent[e].next;
    } else {
        if (p->nent == p->capent) {
            const int cap = p->capent ? 2 * p->capent : 1024;
            entry *ne = realloc(p->ent, (size_t)cap * sizeof *ne);
            if (!ne) {
                buf_put(p, buf);
                return -1;
            }
            p->ent = ne;
            p->capent = cap;
        }
        e = p->nent++;
        if ((unsigned)p->nent * 2 > p->nbucket) {
            p->ent[e].state = -1;
            if (rehash(p, p->nbucket * 2)) {
                buf_put(p, buf);
                return -1;
            }
        }
    }
    entry *E = &p->ent[e];
    *E = (entry){s, b, step, LOADING, 0, p->mark, buf, ++p->tick, 0};
    const unsigned h = hash3(s, b, step) & (p->nbucket - 1);
    E->next = p->bucket[h];
    p->bucket[h] = e;
    p->bytes += p->brick_bytes;
    if (p->bytes > p->peak)
        p->peak = p->bytes;
    return e;
}

/* A brick this thread will decode (under the lock): a new entry, pinned
 * while it is decoded so nothing evicts it; -1 when out of memory. */
static int claim(vsv_pager *p, int s, int b, int step)
{
    const int e = insert(p, s, b, step);
    if (e >= 0) {
        p->ent[e].pins = 1;
        p->pinned += p->brick_bytes;
    }
    return e;
}

static void drop(vsv_pager *p, int e)
{
    unlink_entry(p, e);
    buf_put(p, p->ent[e].data);
    p->ent[e].data = NULL;
    p->ent[e].state = -1;
    p->ent[e].next = p->freelist;
    p->freelist = e;
    p->bytes -= p->brick_bytes;
}

static int tick_cmp(const void *a, const void *b)
{
    const uint64_t x = ((const uint64_t *)a)[0], y = ((const uint64_t *)b)[0];
    return x < y ? -1 : x > y;
}

/* Evicts unpinned READY (and FAILED) entries until `extra` more bytes fit in
 * the budget: those outside the prefetch window first, least recently used
 * first; inside the window only when `window` is set. Returns whether they
 * fit. */
static int make_room(vsv_pager *p, size_t extra, int window)
{
    if (p->bytes + extra <= p->budget)
        return 1;
    size_t n = 0;
    for (int e = 0; e < p->nent; e++)
        if ((p->ent[e].state == READY || p->ent[e].state == FAILED) && !p->ent[e].pins)
            n++;
    uint64_t *c = malloc((n ? n : 1) * 2 * sizeof *c);
    if (!c)
        return 0;
    n = 0;
    for (int e = 0; e < p->nent; e++) {
        const entry *E = &p->ent[e];
        if ((E->state == READY || E->state == FAILED) && !E->pins && (window || E->mark != p->mark)) {
            c[2 * n] = (E->mark == p->mark ? 1ull << 62 : 0) | E->tick;
            c[2 * n + 1] = (uint64_t)e;
            n++;
        }
    }
    qsort(c, n, 2 * sizeof *c, tick_cmp);
    for (size_t i = 0; i < n && p->bytes + extra > p->budget; i++) {
        drop(p, (int)c[2 * i + 1]);
        p->st.evictions++;
        p->scan_d = p->scan_s = p->scan_b = 0; /* what was there may be gone */
    }
    free(c);
    return p->bytes + extra <= p->budget;
}

static void set_err(vsv_pager *p, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(p->err, sizeof p->err, fmt, ap);
    va_end(ap);
}

/* The defining step of every brick of (step, s) (under the lock); NULL on a
 * damaged chunk (error set). */
static const int *defs(vsv_pager *p, int step, int s)
{
    defrow *r = &p->rows[(size_t)step * p->info.nspecies + s];
    if (r->def)
        return r->def;
    const int nb = p->info.nbricks;
    int *d = malloc((size_t)nb * sizeof *d);
    const unsigned char *oct = vsv_file_octree(p->f, step, s, NULL);
    if (!d || !oct) {
        free(d);
        set_err(p, "%s", oct ? "out of memory" : vsv_file_error(p->f));
        return NULL;
    }
    for (int b = 0; b < nb; b++) {
        unsigned mn, mx;
        vsv_octree_node(oct, (size_t)b, &mn, &mx);
        int t = step, k;
        while ((k = vsv_file_brick_kind(p->f, t, s, b)) == VSV_BRICK_UNCHANGED && t > 0)
            t--;
        if (k < 0) {
            free(d);
            set_err(p, "%s", vsv_file_error(p->f));
            return NULL;
        }
        d[b] = mx == 0 || k == VSV_BRICK_EMPTY ? -1 : t;
    }
    return r->def = d;
}

/* Decodes a brick into out with decoder d (outside the lock); 0, or -1
 * with the error text in msg. */
static int decode(vsv_pager *p, vsv_decoder *d, int s, int b, int step, float *out, char *msg, size_t cap)
{
    const int n = p->info.brick;
    if (vsv_decoder_brick(d, step, s, b, out)) {
        snprintf(msg, cap, "%s", vsv_decoder_error(d));
        return -1;
    }
    int org[3], ext[3];
    vsv_file_brick_box(p->f, b, org, ext);
    if (ext[0] < n || ext[1] < n || ext[2] < n) { /* outside the grid: the empty value */
        const float ev = vsv_quant_value(vsv_file_quant(p->f, s), 0);
        for (int k = 0; k < n; k++)
            for (int j = 0; j < n; j++)
                for (int i = 0; i < n; i++)
                    if (i >= ext[0] || j >= ext[1] || k >= ext[2])
                        out[((size_t)k * n + j) * n + i] = ev;
    }
    return 0;
}

/* Marks e decoded, or failed (under the lock). */
static void finish(vsv_pager *p, int e, int ok, double secs)
{
    entry *E = &p->ent[e];
    E->state = ok ? READY : FAILED;
    E->tick = ++p->tick;
    if (ok) {
        p->st.bricks_decoded++;
        p->st.bytes_decoded += p->brick_bytes;
    }
    p->st.decode_seconds += secs;
    pthread_cond_broadcast(&p->ready);
}

/* ------------------------------------------------------------ prefetch */

static int wanted(const vsv_pager *p, int s) { return !p->want || p->want[s]; }

/* The step d frames ahead of the playhead, or -1 past an end. */
static int ahead_step(const vsv_pager *p, int d)
{
    const int n = p->info.nsteps;
    long t = p->head + (long)d * p->stride * (p->dir ? p->dir : 1);
    if (p->dir == 0 && d > 1)
        return -1; /* paused: the step on screen and its neighbours */
    if (p->dir == 0 && d == 1)
        t = p->head + 1;
    if (t < 0 || t >= n) {
        if (!p->loop)
            return -1;
        t = ((t % n) + n) % n;
    }
    return (int)t;
}

/* Marks every cached brick the prefetch window needs (under the lock, once
 * per playhead change) and sizes the window: as many steps as fit beside the
 * current one. 0 on a damaged chunk. */
static int mark_window(vsv_pager *p)
{
    if (p->marked_gen == p->gen)
        return 1;
    p->marked_gen = p->gen;
    p->mark++;
    p->scan_d = p->scan_s = p->scan_b = 0;
    size_t unit = 0;
    for (int s = 0; s < p->info.nspecies; s++) {
        const int *def = wanted(p, s) ? defs(p, p->head, s) : NULL;
        for (int b = 0; def && b < p->info.nbricks; b++)
            unit += def[b] >= 0 ? p->brick_bytes : 0;
    }
    if (unit > p->step_bytes)
        p->step_bytes = unit;
    const long fit = (long)(p->budget / (p->step_bytes ? p->step_bytes : p->brick_bytes)) - 2;
    int depth = (int)(fit < 0 ? 0 : fit > p->ahead ? p->ahead : fit);
    if (p->dir == 0 && depth > 1)
        depth = 1;
    p->depth = depth;
    for (int d = 0; d <= depth; d++) {
        const int t = ahead_step(p, d);
        if (t < 0)
            break;
        for (int s = 0; s < p->info.nspecies; s++) {
            const int *def = wanted(p, s) ? defs(p, t, s) : NULL;
            if (wanted(p, s) && !def)
                return 0;
            for (int b = 0; def && b < p->info.nbricks; b++) {
                const int e = def[b] >= 0 ? lookup(p, s, b, def[b]) : -1;
                if (e >= 0)
                    p->ent[e].mark = p->mark;
            }
        }
    }
    return 1;
}

/* The next brick to decode ahead (under the lock): claims it (LOADING) and
 * returns the entry, or -1 when there is nothing to do within the budget. */
static int next_job(vsv_pager *p, int *s_out, int *b_out, int *step_out)
{
    if (!mark_window(p))
        return -1;
    /* finish the step under way first, even if the playhead has moved past
     * it: when decoding cannot keep up, complete steps are what the player
     * can show (the newest complete one), half-decoded ones are not */
    if (p->focus >= 0 && p->focus_dir == p->dir && p->depth > 0) {
        for (int s = 0; s < p->info.nspecies; s++) {
            const int *def = wanted(p, s) ? defs(p, p->focus, s) : NULL;
            for (int b = 0; def && b < p->info.nbricks; b++) {
                if (def[b] < 0 || lookup(p, s, b, def[b]) >= 0)
                    continue;
                if (!make_room(p, p->brick_bytes, 0))
                    goto scan;
                const int ne = claim(p, s, b, def[b]);
                if (ne >= 0)
                    *s_out = s, *b_out = b, *step_out = def[b];
                return ne;
            }
        }
        p->focus = -1; /* complete */
    }
scan:
    /* resume where the last scan of this window stopped: what lies before
     * it was decoded or claimed (an eviction changes the window's mark) */
    for (int d = p->scan_d; d <= p->depth; d++) {
        const int t = ahead_step(p, d);
        if (t < 0)
            break;
        for (int s = d == p->scan_d ? p->scan_s : 0; s < p->info.nspecies; s++) {
            if (!wanted(p, s))
                continue;
            const int *def = defs(p, t, s);
            if (!def)
                return -1;
            for (int b = d == p->scan_d && s == p->scan_s ? p->scan_b : 0; b < p->info.nbricks; b++) {
                if (def[b] < 0 || lookup(p, s, b, def[b]) >= 0)
                    continue;
                p->scan_d = d, p->scan_s = s, p->scan_b = b;
                if (!make_room(p, p->brick_bytes, 0))
                    return -1;
                p->focus = t;
                p->focus_dir = p->dir;
                const int ne = claim(p, s, b, def[b]);
                if (ne >= 0)
                    *s_out = s, *b_out = b, *step_out = def[b];
                return ne;
            }
        }
    }
    p->scan_d = p->depth + 1;
    return -1;
}

typedef struct wslot {
    vsv_pager *p;
    int index;
} wslot;

static void *worker(void *arg)
{
    wslot *ws = arg;
    vsv_pager *p = ws->p;
    vsv_decoder *d = p->dec[ws->index];
    free(ws);
    char msg[256];
    pthread_mutex_lock(&p->mu);
    while (!p->quit) {
        int s, b, step;
        const int e = next_job(p, &s, &b, &step);
        if (e < 0) {
            const int gen = p->gen;
            while (!p->quit && gen == p->gen)
                pthread_cond_wait(&p->work, &p->mu);
            continue;
        }
        float *out = p->ent[e].data;
        pthread_mutex_unlock(&p->mu);
        const double t0 = now();
        const int ok = !decode(p, d, s, b, step, out, msg, sizeof msg);
        const double t1 = now();
        pthread_mutex_lock(&p->mu);
        if (!ok)
            set_err(p, "%s", msg);
        finish(p, e, ok, t1 - t0);
        p->ent[e].pins = 0;
        p->pinned -= p->brick_bytes;
        make_room(p, 0, 1);
    }
    pthread_mutex_unlock(&p->mu);
    return NULL;
}

/* ------------------------------------------------------------------ API */

int vsv_pager_open(vsv_file *f, const vsv_pager_opts *o, vsv_pager **out)
{
    vsv_pager_opts def;
    if (!o) {
        vsv_pager_opts_init(&def);
        o = &def;
    }
    vsv_pager *p = *out = calloc(1, sizeof *p);
    if (!p)
        return VSV_ENOMEM;
    p->f = f;
    vsv_file_info_get(f, &p->info);
    p->meta = vsv_file_meta(f);
    p->brick_bytes = (size_t)p->info.brick * p->info.brick * p->info.brick * sizeof(float);
    p->slab_bytes = p->brick_bytes > ((size_t)2 << 20) ? p->brick_bytes : ((size_t)2 << 20) / p->brick_bytes * p->brick_bytes;
    p->budget = o->budget;
    if (!p->budget) {
        const long pages = sysconf(_SC_PHYS_PAGES), psz = sysconf(_SC_PAGESIZE);
        p->budget = pages > 0 && psz > 0 ? (size_t)pages * (size_t)psz / 4 : (size_t)1 << 30;
    }
    p->ahead = o->ahead > 0 ? o->ahead : 16;
    p->stride = 1;
    p->dir = 1;
    p->freelist = -1;
    p->focus = -1;
    pthread_mutex_init(&p->mu, NULL);
    pthread_mutex_init(&p->own_mu, NULL);
    pthread_cond_init(&p->ready, NULL);
    pthread_cond_init(&p->work, NULL);
    p->rows = calloc((size_t)p->info.nsteps * p->info.nspecies, sizeof *p->rows);
    p->want = calloc((size_t)p->info.nspecies, 1);
    if (!p->rows || !p->want || rehash(p, 2048) || vsv_decoder_create(f, &p->own))
        return VSV_ENOMEM;
    memset(p->want, 1, (size_t)p->info.nspecies);
    int n = o->threads < 0 ? 0 : o->threads > 0 ? o->threads : vsv_ncpus() - 1;
    if (o->threads == 0 && n < 1)
        n = 1;
    p->dec = calloc((size_t)(n ? n : 1), sizeof *p->dec);
    p->tid = calloc((size_t)(n ? n : 1), sizeof *p->tid);
    if (!p->dec || !p->tid)
        return VSV_ENOMEM;
    for (int i = 0; i < n; i++) {
        wslot *ws = malloc(sizeof *ws);
        if (!ws || vsv_decoder_create(f, &p->dec[i])) {
            free(ws);
            return VSV_ENOMEM;
        }
        *ws = (wslot){p, i};
        if (pthread_create(&p->tid[i], NULL, worker, ws)) {
            free(ws);
            vsv_decoder_free(p->dec[i]);
            p->dec[i] = NULL;
            break;
        }
        p->nthreads++;
    }
    return 0;
}

void vsv_pager_free(vsv_pager *p)
{
    if (!p)
        return;
    pthread_mutex_lock(&p->mu);
    p->quit = 1;
    pthread_cond_broadcast(&p->work);
    pthread_mutex_unlock(&p->mu);
    for (int i = 0; i < p->nthreads; i++)
        pthread_join(p->tid[i], NULL);
    for (int i = 0; p->dec && i < p->nthreads; i++)
        vsv_decoder_free(p->dec[i]);
    vsv_decoder_free(p->own);
    for (int i = 0; i < p->nslabs; i++)
        free(p->slabs[i]);
    free(p->slabs);
    if (p->rows)
        for (size_t i = 0; i < (size_t)p->info.nsteps * p->info.nspecies; i++)
            free(p->rows[i].def);
    free(p->rows);
    free(p->want);
    free(p->ent);
    free(p->bucket);
    free(p->dec);
    free(p->tid);
    pthread_mutex_destroy(&p->mu);
    pthread_mutex_destroy(&p->own_mu);
    pthread_cond_destroy(&p->ready);
    pthread_cond_destroy(&p->work);
    free(p);
}

const char *vsv_pager_error(const vsv_pager *p) { return p->err; }

void vsv_pager_playhead(vsv_pager *p, int step, int dir, int stride, int loop, const unsigned char *species)
{
    pthread_mutex_lock(&p->mu);
    p->head = step < 0 ? 0 : step >= p->info.nsteps ? p->info.nsteps - 1 : step;
    p->dir = dir > 0 ? 1 : dir < 0 ? -1 : 0;
    p->stride = stride > 0 ? stride : 1;
    p->loop = loop;
    for (int s = 0; s < p->info.nspecies; s++)
        p->want[s] = species ? species[s] != 0 : 1;
    p->gen++;
    pthread_cond_broadcast(&p->work);
    pthread_mutex_unlock(&p->mu);
}

vsv_volume *vsv_pager_volume_new(vsv_pager *p)
{
    shell *sh = calloc(1, sizeof *sh);
    const int nb = p->info.nbricks;
    if (!sh)
        return NULL;
    sh->p = p;
    sh->v.bricks = calloc((size_t)nb, sizeof *sh->v.bricks);
    sh->v.bmin = calloc((size_t)nb, sizeof(float));
    sh->v.bmax = calloc((size_t)nb, sizeof(float));
    sh->held = malloc((size_t)nb * sizeof *sh->held);
    if (!sh->v.bricks || !sh->v.bmin || !sh->v.bmax || !sh->held) {
        vsv_pager_volume_free(&sh->v);
        return NULL;
    }
    for (int b = 0; b < nb; b++)
        sh->held[b] = -1;
    const vsv_meta *m = p->meta;
    sh->v.nx = m->nx;
    sh->v.ny = m->ny;
    sh->v.nz = m->nz;
    sh->v.brick = p->info.brick;
    for (int a = 0; a < 3; a++)
        sh->v.bdim[a] = p->info.bricks[a];
    sh->v.nbricks = nb;
    while ((1 << sh->v.shift) < sh->v.brick)
        sh->v.shift++;
    sh->v.step = sh->v.species = -1;
    return &sh->v;
}

void vsv_pager_volume_free(vsv_volume *v)
{
    if (!v)
        return;
    shell *sh = (shell *)v;
    if (v->step >= 0)
        vsv_pager_put(sh->p, v);
    free(v->bricks);
    free(v->bmin);
    free(v->bmax);
    free(sh->held);
    free(sh);
}

/* Unpins what sh holds (under the lock). */
static void unpin(vsv_pager *p, shell *sh)
{
    for (int b = 0; b < p->info.nbricks; b++)
        if (sh->held[b] >= 0) {
            entry *E = &p->ent[sh->held[b]];
            if (!--E->pins)
                p->pinned -= p->brick_bytes;
            sh->held[b] = -1;
        }
    sh->v.step = sh->v.species = -1;
    sh->v.gen = 0;
}

void vsv_pager_put(vsv_pager *p, vsv_volume *v)
{
    pthread_mutex_lock(&p->mu);
    unpin(p, (shell *)v);
    make_room(p, 0, 1);
    p->gen++; /* room may have appeared: the workers look again */
    pthread_cond_broadcast(&p->work);
    pthread_mutex_unlock(&p->mu);
}

static void pin(vsv_pager *p, shell *sh, int b, int e)
{
    entry *E = &p->ent[e];
    if (!E->pins++)
        p->pinned += p->brick_bytes;
    E->tick = ++p->tick;
    sh->held[b] = e;
    sh->v.bricks[b] = E->data;
}

int vsv_pager_get(vsv_pager *p, int step, int s, int wait, vsv_volume *v)
{
    shell *sh = (shell *)v;
    if (step < 0 || step >= p->info.nsteps || s < 0 || s >= p->info.nspecies)
        return VSV_ERANGE;
    const int nb = p->info.nbricks;
    pthread_mutex_lock(&p->mu);
    unpin(p, sh);
    const int *def = defs(p, step, s);
    const unsigned char *oct = vsv_file_octree(p->f, step, s, NULL);
    if (!def || !oct) {
        make_room(p, 0, 1);
        pthread_mutex_unlock(&p->mu);
        return VSV_ECORRUPT;
    }
    const vsv_quant *q = vsv_file_quant(p->f, s);
    v->empty_value = vsv_quant_value(q, 0);
    size_t need = 0;
    int rc = 0;
    for (int b = 0; b < nb; b++) {
        unsigned mn, mx;
        vsv_octree_node(oct, (size_t)b, &mn, &mx);
        v->bmin[b] = vsv_quant_value(q, mn);
        v->bmax[b] = vsv_quant_value(q, mx);
        v->bricks[b] = NULL;
        if (def[b] < 0)
            continue;
        const int e = lookup(p, s, b, def[b]);
        if (e >= 0 && p->ent[e].state == READY) {
            p->st.hits++;
            pin(p, sh, b, e);
        } else {
            p->st.misses++;
            need++;
        }
    }
    if (need && !wait) { /* not all there: nothing stays pinned */
        p->st.stalls++;
        unpin(p, sh);
        make_room(p, 0, 1);
        pthread_mutex_unlock(&p->mu);
        return VSV_EAGAIN;
    }
    if (need)
        p->st.stalls++;
    /* what is missing: decode here what nobody is decoding, wait for the rest */
    while (need && !rc) {
        int progressed = 0;
        for (int b = 0; b < nb && !rc; b++) {
            if (def[b] < 0 || sh->held[b] >= 0)
                continue;
            int e = lookup(p, s, b, def[b]);
            if (e >= 0 && p->ent[e].state == READY) {
                pin(p, sh, b, e);
                need--;
                progressed = 1;
                continue;
            }
            if (e >= 0 && p->ent[e].state == FAILED) {
                drop(p, e); /* retry once here: the error is reported below */
                e = -1;
            }
            if (e >= 0)
                continue; /* a worker decodes it */
            make_room(p, p->brick_bytes, 1);
            if ((e = claim(p, s, b, def[b])) < 0) {
                rc = VSV_ENOMEM;
                break;
            }
            float *out = p->ent[e].data;
            pthread_mutex_unlock(&p->mu);
            char msg[256];
            pthread_mutex_lock(&p->own_mu);
            const double t0 = now();
            const int ok = !decode(p, p->own, s, b, def[b], out, msg, sizeof msg);
            const double t1 = now();
            pthread_mutex_unlock(&p->own_mu);
            pthread_mutex_lock(&p->mu);
            finish(p, e, ok, t1 - t0);
            if (!ok) {
                set_err(p, "%s", msg);
                p->ent[e].pins = 0;
                p->pinned -= p->brick_bytes;
                rc = VSV_ECORRUPT;
                break;
            }
            sh->held[b] = e; /* already pinned */
            v->bricks[b] = p->ent[e].data;
            need--;
            progressed = 1;
        }
        if (need && !rc && !progressed)
            pthread_cond_wait(&p->ready, &p->mu);
    }
    if (rc) {
        unpin(p, sh);
    } else {
        v->step = step;
        v->species = s;
        v->time = vsv_file_time(p->f, step);
        v->gen = vsv_volume_new_gen();
    }
    make_room(p, 0, 1);
    pthread_mutex_unlock(&p->mu);
    return rc;
}

int vsv_pager_ready(vsv_pager *p, int step, const unsigned char *species)
{
    if (step < 0 || step >= p->info.nsteps)
        return 0;
    pthread_mutex_lock(&p->mu);
    int ok = 1;
    for (int s = 0; s < p->info.nspecies && ok; s++) {
        if (species && !species[s])
            continue;
        const int *def = defs(p, step, s);
        if (!def) {
            ok = 0;
            break;
        }
        for (int b = 0; b < p->info.nbricks && ok; b++) {
            if (def[b] < 0)
                continue;
            const int e = lookup(p, s, b, def[b]);
            ok = e >= 0 && p->ent[e].state == READY;
        }
    }
    pthread_mutex_unlock(&p->mu);
    return ok;
}

void vsv_pager_stats_get(vsv_pager *p, vsv_pager_stats *st)
{
    pthread_mutex_lock(&p->mu);
    *st = p->st;
    st->prefetch_depth = p->depth;
    st->budget = p->budget;
    st->bytes = p->bytes;
    st->pinned_bytes = p->pinned;
    st->peak_bytes = p->peak;
    pthread_mutex_unlock(&p->mu);
}

void vsv_pager_stall(vsv_pager *p)
{
    pthread_mutex_lock(&p->mu);
    p->st.stalls++;
    pthread_mutex_unlock(&p->mu);
}
