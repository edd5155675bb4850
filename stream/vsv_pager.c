/* vsv_pager.c — the pager's API (vsv_pager.h). One mutex guards the cache (a hash of
 * entries keyed by species, brick and defining step, with use ticks for
 * least-recently-used eviction); decoding happens outside it. An entry is
 * LOADING while one thread decodes it (others wait on `ready`), then READY
 * or FAILED; it counts as pinned while it is decoded. */
#include "vsv_pager_internal.h"

#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/mman.h>
#include <unistd.h>

void vsv_pager_opts_init(vsv_pager_opts *o) { memset(o, 0, sizeof *o); }

static void job_free(job *j)
{
    free(j->step);
    free(j->ent);
    free(j->out);
    free(j->ck_step);
    free(j->ck_ent);
    free(j->ck_buf);
}

/* Frees what open allocated (the workers stopped). */
static void release(vsv_pager *p)
{
    for (int i = 0; p->dec && i < p->nthreads; i++)
        vsv_decoder_free(p->dec[i]);
    for (int i = 0; p->scratch && i < p->nthreads; i++)
        free(p->scratch[i]);
    for (int i = 0; p->jobs && i < p->nthreads; i++)
        job_free(&p->jobs[i]);
    vsv_decoder_free(p->own);
    free(p->own_scratch);
    vsv_slab_free_all(p);
    if (p->rows)
        free(p->rows[0].def);
    free(p->rows);
    for (int t = 0; p->cmsg && t < p->info.nsteps; t++)
        free(p->cmsg[t]);
    free(p->cmsg);
    free(p->cst);
    free(p->tracks);
    free(p->want);
    free(p->next);
    free(p->ent);
    free(p->bucket);
    free(p->dec);
    free(p->scratch);
    free(p->jobs);
    free(p->tid);
    pthread_mutex_destroy(&p->mu);
    pthread_mutex_destroy(&p->own_mu);
    pthread_cond_destroy(&p->ready);
    pthread_cond_destroy(&p->work);
    free(p);
}

static int job_alloc(vsv_pager *p, job *j)
{
    j->step = malloc((size_t)p->job_cap * sizeof *j->step);
    j->ent = malloc((size_t)p->job_cap * sizeof *j->ent);
    j->out = malloc((size_t)p->job_cap * sizeof *j->out);
    j->ck_step = malloc((size_t)p->job_cap * sizeof *j->ck_step);
    j->ck_ent = malloc((size_t)p->job_cap * sizeof *j->ck_ent);
    j->ck_buf = malloc((size_t)p->job_cap * sizeof *j->ck_buf);
    return j->step && j->ent && j->out && j->ck_step && j->ck_ent && j->ck_buf ? 0 : VSV_ENOMEM;
}

int vsv_pager_open(vsv_file *f, const vsv_pager_opts *o, vsv_pager **out)
{
    vsv_pager_opts def;
    if (!o) {
        vsv_pager_opts_init(&def);
        o = &def;
    }
    *out = NULL;
    vsv_pager *p = calloc(1, sizeof *p);
    if (!p)
        return VSV_ENOMEM;
    p->f = f;
    vsv_file_info_get(f, &p->info);
    p->meta = vsv_file_meta(f);
    const size_t cells = (size_t)p->info.brick * p->info.brick * p->info.brick;
    const int ns = p->info.nspecies, nb = p->info.nbricks;
    p->brick_bytes = cells * sizeof(float);
    p->codes_bytes = cells * sizeof(uint16_t);
    p->slab_bytes = (size_t)2 << 20; /* bricks are at most 64^3 floats: 1 MB */
    p->pool[0].size = p->brick_bytes;
    p->pool[1].size = p->codes_bytes;
    p->slab_alloc = o->slab_alloc;
    p->slab_ctx = o->slab_ctx;
    p->budget = o->budget;
    if (!p->budget) {
        const long pages = sysconf(_SC_PHYS_PAGES), psz = sysconf(_SC_PAGESIZE);
        p->budget = pages > 0 && psz > 0 ? (size_t)pages * (size_t)psz / 4 : (size_t)1 << 30;
    }
    p->ahead = o->ahead > 0 ? o->ahead : VSV_PAGER_AHEAD;
    p->incremental = !o->from_keyframe;
    p->job_cap = p->ahead + 2;
    p->dir = 1;
    p->freelist = -1;
    p->missing = -1;
    p->focus = -1;
    for (int l = 0; l < 4; l++)
        vsv_lru_init(&p->lru[l]);
    vsv_lru_init(&p->tlru);
    pthread_mutex_init(&p->mu, NULL);
    pthread_mutex_init(&p->own_mu, NULL);
    pthread_cond_init(&p->ready, NULL);
    pthread_cond_init(&p->work, NULL);
    /* rows of defining steps: enough that the window's never collide */
    p->nrows = 4;
    while (p->nrows < 2 * (p->ahead + 2) * ns)
        p->nrows *= 2;
    p->rows = calloc((size_t)p->nrows, sizeof *p->rows);
    int *defs = p->rows ? malloc((size_t)p->nrows * nb * sizeof *defs) : NULL;
    p->tracks = calloc((size_t)ns * nb, sizeof *p->tracks);
    p->want = calloc((size_t)ns, 1);
    p->next = calloc((size_t)p->ahead + 1, sizeof *p->next);
    p->own_scratch = malloc(p->codes_bytes);
    p->cst = calloc((size_t)p->info.nsteps, sizeof *p->cst);
    p->cmsg = calloc((size_t)p->info.nsteps, sizeof *p->cmsg);
    if (!defs || !p->tracks || !p->want || !p->next || !p->own_scratch || !p->cst || !p->cmsg ||
        vsv_cache_rehash(p, 2048) || vsv_decoder_create(f, &p->own)) {
        if (p->rows)
            p->rows[0].def = defs;
        release(p);
        return VSV_ENOMEM;
    }
    for (int r = 0; r < p->nrows; r++)
        p->rows[r] = (defrow){-1, 0, defs + (size_t)r * nb};
    for (int i = 0; i < ns * nb; i++)
        p->tracks[i] = (track){{-1, -1}, NULL, -1, 0, 0};
    memset(p->want, 1, (size_t)ns);
    int n = o->threads < 0 ? 0 : o->threads > 0 ? o->threads : vsv_ncpus() - 1;
    if (o->threads == 0 && n < 1)
        n = 1;
    p->dec = calloc((size_t)(n ? n : 1), sizeof *p->dec);
    p->scratch = calloc((size_t)(n ? n : 1), sizeof *p->scratch);
    p->jobs = calloc((size_t)(n ? n : 1), sizeof *p->jobs);
    p->tid = calloc((size_t)(n ? n : 1), sizeof *p->tid);
    if (!p->dec || !p->scratch || !p->jobs || !p->tid) {
        release(p);
        return VSV_ENOMEM;
    }
    /* the fixed tables count against the budget as well */
    p->fixed = sizeof *p + (size_t)p->nrows * (sizeof *p->rows + (size_t)nb * sizeof(int)) +
               (size_t)ns * nb * sizeof *p->tracks + p->nbucket * sizeof(int) +
               (size_t)p->info.nsteps * (sizeof *p->cst + sizeof *p->cmsg) +
               (size_t)(n + 1) * (p->codes_bytes + (size_t)p->job_cap * (4 * sizeof(int) + 2 * sizeof(void *)));
    p->bytes = p->peak = p->fixed;
    for (int i = 0; i < n; i++) { /* as many workers as start */
        wslot *ws = malloc(sizeof *ws);
        int ok = ws && !vsv_decoder_create(f, &p->dec[i]) && (p->scratch[i] = malloc(p->codes_bytes)) &&
                 !job_alloc(p, &p->jobs[i]);
        if (ok) {
            *ws = (wslot){p, i};
            ok = !pthread_create(&p->tid[i], NULL, vsv_pager_worker, ws);
        }
        if (!ok) {
            free(ws);
            vsv_decoder_free(p->dec[i]);
            free(p->scratch[i]);
            job_free(&p->jobs[i]);
            p->dec[i] = NULL, p->scratch[i] = NULL, p->jobs[i] = (job){0};
            break;
        }
        p->nthreads++;
    }
    *out = p;
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
    /* volumes still out keep their memory, lose their bricks */
    for (shell *sh = p->shells; sh; sh = sh->next) {
        sh->p = NULL;
        for (int b = 0; b < sh->v.nbricks; b++)
            sh->v.bricks[b] = NULL;
        sh->v.step = sh->v.species = -1;
        sh->v.gen = 0;
    }
    release(p);
}

const char *vsv_pager_error(const vsv_pager *cp)
{
    static _Thread_local char copy[sizeof cp->err];
    vsv_pager *p = (vsv_pager *)cp;
    pthread_mutex_lock(&p->mu);
    memcpy(copy, p->err, sizeof copy);
    pthread_mutex_unlock(&p->mu);
    return copy;
}

void vsv_pager_playhead(vsv_pager *p, int step, int dir, const int *next, int n, const unsigned char *species)
{
    pthread_mutex_lock(&p->mu);
    const int ns = p->info.nsteps, head = step < 0 ? 0 : step >= ns ? ns - 1 : step;
    dir = dir > 0 ? 1 : dir < 0 ? -1 : 0;
    int same = head == p->head && dir == p->dir;
    int k = 0; /* the listed steps that exist, else the ones after head */
    for (int i = 0; k <= p->ahead && (next ? i < n : 1); i++) {
        const int t = next ? next[i] : head + (dir ? dir : 1) * (i + 1);
        if (!next && (t < 0 || t >= ns || (dir == 0 && i > 0)))
            break;
        if (t < 0 || t >= ns)
            continue;
        same &= k < p->nnext && p->next[k] == t;
        p->next[k++] = t;
    }
    same &= k == p->nnext;
    p->nnext = k;
    for (int s = 0; s < p->info.nspecies; s++) {
        const unsigned char w = species ? species[s] != 0 : 1;
        same &= p->want[s] == w;
        p->want[s] = w;
    }
    p->head = head;
    p->dir = dir;
    if (!same) {
        p->gen++;
        pthread_cond_broadcast(&p->work);
    }
    pthread_mutex_unlock(&p->mu);
}

static void shell_release(vsv_volume *v);
static void unpin(vsv_pager *p, shell *sh);

/* v is a volume of p's (a shell of p still alive). */
static int is_shell_of(const vsv_pager *p, const vsv_volume *v)
{
    return v && v->release_ == shell_release && ((const shell *)v)->p == p;
}

vsv_volume *vsv_pager_volume_new(vsv_pager *p)
{
    shell *sh = calloc(1, sizeof *sh);
    const int nb = p->info.nbricks;
    if (!sh)
        return NULL;
    sh->v.release_ = shell_release;
    sh->v.bricks = calloc((size_t)nb, sizeof *sh->v.bricks);
    sh->v.bmin = calloc((size_t)nb, sizeof(float));
    sh->v.bmax = calloc((size_t)nb, sizeof(float));
    sh->v.bkey = calloc((size_t)nb, sizeof *sh->v.bkey);
    sh->held = malloc((size_t)nb * sizeof *sh->held);
    sh->def = malloc((size_t)nb * sizeof *sh->def);
    if (!sh->v.bricks || !sh->v.bmin || !sh->v.bmax || !sh->v.bkey || !sh->held || !sh->def || job_alloc(p, &sh->job)) {
        shell_release(&sh->v);
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
    pthread_mutex_lock(&p->mu);
    sh->p = p;
    sh->next = p->shells;
    if (p->shells)
        p->shells->prev = sh;
    p->shells = sh;
    pthread_mutex_unlock(&p->mu);
    return &sh->v;
}

/* vsv_volume_free of a pager volume: unpins its bricks and leaves the
 * pager's list; after vsv_pager_free (sh->p NULL) only the memory is left. */
static void shell_release(vsv_volume *v)
{
    shell *sh = (shell *)v;
    vsv_pager *p = sh->p;
    if (p) {
        pthread_mutex_lock(&p->mu);
        if (v->step >= 0) {
            unpin(p, sh);
            vsv_cache_make_room(p, 0, 1);
            p->gen++;
            pthread_cond_broadcast(&p->work);
        }
        if (sh->prev)
            sh->prev->next = sh->next;
        else
            p->shells = sh->next;
        if (sh->next)
            sh->next->prev = sh->prev;
        pthread_mutex_unlock(&p->mu);
    }
    free(v->bricks);
    free(v->bmin);
    free(v->bmax);
    free(v->bkey);
    free(sh->held);
    free(sh->def);
    job_free(&sh->job);
    free(sh);
}

/* Unpins what sh holds (under the lock). */
static void unpin(vsv_pager *p, shell *sh)
{
    for (int b = 0; b < p->info.nbricks; b++)
        if (sh->held[b] >= 0) {
            vsv_cache_unpin(p, sh->held[b]);
            sh->held[b] = -1;
        }
    sh->v.step = sh->v.species = -1;
    sh->v.gen = 0;
}

void vsv_pager_put(vsv_pager *p, vsv_volume *v)
{
    if (!is_shell_of(p, v))
        return;
    pthread_mutex_lock(&p->mu);
    unpin(p, (shell *)v);
    vsv_cache_make_room(p, 0, 1);
    p->gen++; /* room may have appeared: the workers look again */
    pthread_cond_broadcast(&p->work);
    pthread_mutex_unlock(&p->mu);
}

static void hold(vsv_pager *p, shell *sh, int b, int e)
{
    vsv_cache_pin(p, e);
    vsv_cache_touch(p, e);
    sh->held[b] = e;
    sh->v.bricks[b] = p->ent[e].data;
}

/* Whether brick b of species s waits for its track (a job is using it). */
static int track_busy(const vsv_pager *p, int s, int b)
{
    return p->incremental && p->tracks[(size_t)s * p->info.nbricks + b].busy;
}

/* Decodes on this thread what is missing of (step, s) and nobody is
 * decoding, fetching what that needs, and waits for the rest (under the
 * lock, which it drops while fetching, decoding and waiting). A brick that
 * failed is tried once more here. 0 or the error (folded, error set). */
static int fill(vsv_pager *p, shell *sh, int need)
{
    vsv_volume *v = &sh->v;
    const int s = v->species, nb = p->info.nbricks;
    const int *def = sh->def;
    job *j = &sh->job;
    while (need) {
        int progressed = 0;
        for (int b = 0; b < nb; b++) {
            if (def[b] < 0 || sh->held[b] >= 0)
                continue;
            int e = vsv_cache_lookup(p, s, b, def[b]);
            if (e >= 0 && p->ent[e].state == READY) {
                hold(p, sh, b, e);
                need--;
                progressed = 1;
                continue;
            }
            if (e >= 0 && (p->ent[e].state == FAILED || p->ent[e].state == STALLED)) {
                vsv_cache_drop(p, e); /* retry once here: the error is reported below */
                e = -1;
            }
            if (e >= 0 || track_busy(p, s, b))
                continue; /* another thread decodes it, or carries its track forward */
            vsv_cache_make_room(p, p->brick_bytes, 1);
            int rc = vsv_pager_job_make(p, j, s, b, def[b]);
            if (rc == VSV_EAGAIN) { /* a chunk index to fetch first */
                vsv_pager_wait_chunk(p);
                progressed = 1;
                break;
            }
            if (rc)
                return vsv_pager_fold(rc);
            pthread_mutex_unlock(&p->mu);
            char msg[512];
            pthread_mutex_lock(&p->own_mu);
            const double t0 = vsv_pager_now();
            rc = vsv_pager_job_run(p, p->own, j, p->own_scratch, msg, sizeof msg);
            const double t1 = vsv_pager_now();
            pthread_mutex_unlock(&p->own_mu);
            pthread_mutex_lock(&p->mu);
            vsv_pager_job_finish(p, j, rc, t1 - t0, 1, msg);
            if (rc) {
                vsv_pager_set_err(p, "%s", msg);
                return vsv_pager_fold(rc);
            }
            e = j->ent[j->n - 1]; /* pinned for us */
            sh->held[b] = e;
            v->bricks[b] = p->ent[e].data;
            vsv_cache_make_room(p, 0, 1); /* the job's other outputs were released */
            need--;
            progressed = 1;
        }
        if (need && !progressed)
            pthread_cond_wait(&p->ready, &p->mu);
    }
    return 0;
}

/* A get without wait that meets brick entry e failed (under the lock): a
 * damaged one stays so, its code and message; one a transfer left is
 * VSV_EIO with its message, or once it may be tried again, dropped and the
 * workers told (VSV_EAGAIN). */
static int failed_get(vsv_pager *p, int e)
{
    entry *E = &p->ent[e];
    if (E->state == STALLED && vsv_pager_due(p)) {
        vsv_cache_drop(p, e);
        p->gen++; /* the window scanned again: its bricks left so are made again */
        pthread_cond_broadcast(&p->work);
        vsv_pager_set_err(p, "fetched again: %s", p->ioerr);
        return VSV_EAGAIN;
    }
    vsv_pager_set_err(p, "%s", (const char *)E->data);
    return vsv_pager_fold(E->why);
}

int vsv_pager_get(vsv_pager *p, int step, int s, int wait, vsv_volume *v)
{
    shell *sh = (shell *)v;
    if (!is_shell_of(p, v)) {
        pthread_mutex_lock(&p->mu);
        vsv_pager_set_err(p, "vsv_pager_get: not a volume of this pager (vsv_pager_volume_new)");
        pthread_mutex_unlock(&p->mu);
        return VSV_EINVAL;
    }
    if (step < 0 || step >= p->info.nsteps || s < 0 || s >= p->info.nspecies)
        return VSV_ERANGE;
    const int nb = p->info.nbricks;
    pthread_mutex_lock(&p->mu);
    unpin(p, sh);
    vsv_cache_make_room(p, 0, 1);
    int rc = 0;
    const int *def;
    for (;;) { /* (waiting: the chunk indexes it needs fetched here, or by others) */
        vsv_sched_mark_window(p);
        if ((def = vsv_pager_defs(p, step, s, &rc)) || rc != VSV_EAGAIN || !wait)
            break;
        vsv_pager_wait_chunk(p);
    }
    const unsigned char *oct = def ? vsv_file_octree(p->f, step, s, NULL) : NULL;
    if (!def || !oct) {
        pthread_mutex_unlock(&p->mu);
        return def ? VSV_ECORRUPT : vsv_pager_fold(rc);
    }
    memcpy(sh->def, def, (size_t)nb * sizeof *def); /* the row cache may reuse the slot */
    const vsv_quant *q = vsv_file_quant(p->f, s);
    v->empty_value = vsv_quant_value(q, 0);
    v->species = s;
    int need = 0, failed = -1; /* a brick that failed: damaged first, else a transfer */
    for (int b = 0; b < nb; b++) {
        unsigned mn, mx;
        vsv_octree_node(oct, (size_t)b, &mn, &mx);
        v->bmin[b] = vsv_quant_value(q, mn);
        v->bmax[b] = vsv_quant_value(q, mx);
        v->bkey[b] = vsv_file_brick_key(p->f, s, sh->def[b]);
        v->bricks[b] = NULL;
        if (sh->def[b] < 0)
            continue;
        const int e = vsv_cache_lookup(p, s, b, sh->def[b]);
        if (e >= 0 && p->ent[e].state == READY) {
            p->st.hits++;
            hold(p, sh, b, e);
        } else {
            p->st.misses++;
            need++;
            if (e >= 0 && (p->ent[e].state == FAILED || (p->ent[e].state == STALLED && failed < 0)))
                failed = e;
        }
    }
    if (need && !wait) { /* not all there: nothing stays pinned */
        p->st.stalls++;
        unpin(p, sh);
        rc = failed >= 0 ? failed_get(p, failed) : VSV_EAGAIN;
        vsv_cache_make_room(p, 0, 1);
        pthread_mutex_unlock(&p->mu);
        return rc;
    }
    if (need) {
        p->st.stalls++;
        rc = fill(p, sh, need);
    }
    if (rc) {
        unpin(p, sh);
    } else {
        v->step = step;
        v->species = s;
        v->time = vsv_file_time(p->f, step);
        v->gen = vsv_volume_new_gen();
    }
    vsv_cache_make_room(p, 0, 1);
    pthread_mutex_unlock(&p->mu);
    return rc;
}

/* vsv_pager_ready under the lock. */
static int ready_locked(vsv_pager *p, int step, const unsigned char *species)
{
    int ok = 1;
    for (int s = 0; s < p->info.nspecies && ok == 1; s++) {
        if (species && !species[s])
            continue;
        int rc = 0;
        const int *def = vsv_pager_defs(p, step, s, &rc);
        if (!def)
            return rc == VSV_EAGAIN ? 0 : -1; /* not fetched yet; or failed its checks, or its fetch */
        for (int b = 0; b < p->info.nbricks && ok == 1; b++) {
            if (def[b] < 0)
                continue;
            const int e = vsv_cache_lookup(p, s, b, def[b]);
            ok = e < 0 || p->ent[e].state == LOADING ? 0 : p->ent[e].state == READY ? 1 : -1;
        }
    }
    return ok;
}

int vsv_pager_ready(vsv_pager *p, int step, const unsigned char *species)
{
    return vsv_pager_wait_ready(p, step, species, 0);
}

int vsv_pager_wait_ready(vsv_pager *p, int step, const unsigned char *species, double seconds)
{
    if (step < 0 || step >= p->info.nsteps)
        return 0;
    pthread_mutex_lock(&p->mu);
    int ok = ready_locked(p, step, species);
    if (ok == 0 && seconds > 0) { /* each brick a worker finishes wakes the wait (p->ready) */
        struct timespec until;
        clock_gettime(CLOCK_REALTIME, &until); /* (the condition's clock) */
        const double s = fmin(seconds, 10.0);
        const long ns = until.tv_nsec + (long)((s - floor(s)) * 1e9);
        until.tv_sec += (time_t)floor(s) + ns / 1000000000L;
        until.tv_nsec = ns % 1000000000L;
        int rc = 0;
        while (ok == 0 && rc == 0) {
            rc = pthread_cond_timedwait(&p->ready, &p->mu, &until);
            ok = ready_locked(p, step, species);
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
    st->track_bytes = p->track_bytes;
    st->fixed_bytes = p->fixed;
    pthread_mutex_unlock(&p->mu);
}

void vsv_pager_stall(vsv_pager *p)
{
    pthread_mutex_lock(&p->mu);
    p->st.stalls++;
    pthread_mutex_unlock(&p->mu);
}
