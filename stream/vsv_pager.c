/* vsv_pager.c — the pager's API (vsv_pager.h). One mutex guards the cache (a hash of
 * entries keyed by species, brick and defining step, with use ticks for
 * least-recently-used eviction); decoding happens outside it. An entry is
 * LOADING while one thread decodes it (others wait on `ready`), then READY
 * or FAILED; it counts as pinned while it is decoded. */
#include "vsv_pager_internal.h"

#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/mman.h>
#include <unistd.h>


void vsv_pager_opts_init(vsv_pager_opts *o) { memset(o, 0, sizeof *o); }

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
    if (!p->rows || !p->want || vsv_cache_rehash(p, 2048) || vsv_decoder_create(f, &p->own))
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
        if (pthread_create(&p->tid[i], NULL, vsv_pager_worker, ws)) {
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
    /* volumes still out keep their memory, lose their bricks */
    for (shell *sh = p->shells; sh; sh = sh->next) {
        sh->p = NULL;
        for (int b = 0; b < sh->v.nbricks; b++)
            sh->v.bricks[b] = NULL;
        sh->v.step = sh->v.species = -1;
        sh->v.gen = 0;
    }
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

static void shell_release(vsv_volume *v);
static void unpin(vsv_pager *p, shell *sh);

/* sh is a volume of p's (a shell of p still alive). */
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
    if (!sh->v.bricks || !sh->v.bmin || !sh->v.bmax || !sh->v.bkey || !sh->held) {
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
    if (!is_shell_of(p, v))
        return;
    pthread_mutex_lock(&p->mu);
    unpin(p, (shell *)v);
    vsv_cache_make_room(p, 0, 1);
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
    if (!is_shell_of(p, v)) {
        vsv_pager_set_err(p, "vsv_pager_get: not a volume of this pager (vsv_pager_volume_new)");
        return VSV_EINVAL;
    }
    if (step < 0 || step >= p->info.nsteps || s < 0 || s >= p->info.nspecies)
        return VSV_ERANGE;
    const int nb = p->info.nbricks;
    pthread_mutex_lock(&p->mu);
    unpin(p, sh);
    const int *def = vsv_pager_defs(p, step, s);
    const unsigned char *oct = vsv_file_octree(p->f, step, s, NULL);
    if (!def || !oct) {
        vsv_cache_make_room(p, 0, 1);
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
        v->bkey[b] = vsv_file_brick_key(p->f, s, def[b]);
        v->bricks[b] = NULL;
        if (def[b] < 0)
            continue;
        const int e = vsv_cache_lookup(p, s, b, def[b]);
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
        vsv_cache_make_room(p, 0, 1);
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
            int e = vsv_cache_lookup(p, s, b, def[b]);
            if (e >= 0 && p->ent[e].state == READY) {
                pin(p, sh, b, e);
                need--;
                progressed = 1;
                continue;
            }
            if (e >= 0 && p->ent[e].state == FAILED) {
                vsv_cache_drop(p, e); /* retry once here: the error is reported below */
                e = -1;
            }
            if (e >= 0)
                continue; /* a worker decodes it */
            vsv_cache_make_room(p, p->brick_bytes, 1);
            if ((e = vsv_cache_claim(p, s, b, def[b])) < 0) {
                rc = VSV_ENOMEM;
                break;
            }
            float *out = p->ent[e].data;
            pthread_mutex_unlock(&p->mu);
            char msg[256];
            pthread_mutex_lock(&p->own_mu);
            const double t0 = vsv_pager_now();
            const int ok = !vsv_pager_decode(p, p->own, s, b, def[b], out, msg, sizeof msg);
            const double t1 = vsv_pager_now();
            pthread_mutex_unlock(&p->own_mu);
            pthread_mutex_lock(&p->mu);
            vsv_pager_finish(p, e, ok, t1 - t0);
            if (!ok) {
                vsv_pager_set_err(p, "%s", msg);
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
    vsv_cache_make_room(p, 0, 1);
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
        const int *def = vsv_pager_defs(p, step, s);
        if (!def) {
            ok = 0;
            break;
        }
        for (int b = 0; b < p->info.nbricks && ok; b++) {
            if (def[b] < 0)
                continue;
            const int e = vsv_cache_lookup(p, s, b, def[b]);
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
