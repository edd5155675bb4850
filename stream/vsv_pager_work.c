/* vsv_pager_work.c — the pager's decoding: the defining step of each
 * brick, one brick decoded outside the lock, and the worker threads. */
#include "vsv_pager_internal.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void vsv_pager_set_err(vsv_pager *p, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(p->err, sizeof p->err, fmt, ap);
    va_end(ap);
}

/* The defining step of every brick of (step, s) (under the lock); NULL on a
 * damaged chunk (error set). */
const int *vsv_pager_defs(vsv_pager *p, int step, int s)
{
    defrow *r = &p->rows[(size_t)step * p->info.nspecies + s];
    if (r->def)
        return r->def;
    const int nb = p->info.nbricks;
    int *d = malloc((size_t)nb * sizeof *d);
    const unsigned char *oct = vsv_file_octree(p->f, step, s, NULL);
    if (!d || !oct) {
        free(d);
        vsv_pager_set_err(p, "%s", oct ? "out of memory" : vsv_file_error(p->f));
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
            vsv_pager_set_err(p, "%s", vsv_file_error(p->f));
            return NULL;
        }
        d[b] = mx == 0 || k == VSV_BRICK_EMPTY ? -1 : t;
    }
    return r->def = d;
}

/* Decodes a brick into out with decoder d (outside the lock); 0, or -1
 * with the error text in msg. */
int vsv_pager_decode(vsv_pager *p, vsv_decoder *d, int s, int b, int step, float *out, char *msg, size_t cap)
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
void vsv_pager_finish(vsv_pager *p, int e, int ok, double secs)
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


void *vsv_pager_worker(void *arg)
{
    wslot *ws = arg;
    vsv_pager *p = ws->p;
    vsv_decoder *d = p->dec[ws->index];
    free(ws);
    char msg[256];
    pthread_mutex_lock(&p->mu);
    while (!p->quit) {
        int s, b, step;
        const int e = vsv_sched_next(p, &s, &b, &step);
        if (e < 0) {
            const int gen = p->gen;
            while (!p->quit && gen == p->gen)
                pthread_cond_wait(&p->work, &p->mu);
            continue;
        }
        float *out = p->ent[e].data;
        pthread_mutex_unlock(&p->mu);
        const double t0 = vsv_pager_now();
        const int ok = !vsv_pager_decode(p, d, s, b, step, out, msg, sizeof msg);
        const double t1 = vsv_pager_now();
        pthread_mutex_lock(&p->mu);
        if (!ok)
            vsv_pager_set_err(p, "%s", msg);
        vsv_pager_finish(p, e, ok, t1 - t0);
        p->ent[e].pins = 0;
        p->pinned -= p->brick_bytes;
        vsv_cache_make_room(p, 0, 1);
    }
    pthread_mutex_unlock(&p->mu);
    return NULL;
}
