/* vsv_cache.c — the pager's cache: entries keyed by species, brick and
 * defining step in a hash with chains, with use ticks for least-recently-used
 * eviction under the byte budget. */
#include "vsv_pager_internal.h"

#include <stdlib.h>
#include <string.h>

static unsigned hash3(int s, int b, int step)
{
    uint64_t h = (uint64_t)(unsigned)s * 0x9E3779B97F4A7C15ull ^ (uint64_t)(unsigned)b * 0xC2B2AE3D27D4EB4Full ^
                 (uint64_t)(unsigned)step * 0x165667B19E3779F9ull;
    return (unsigned)(h ^ (h >> 29));
}

int vsv_cache_lookup(const vsv_pager *p, int s, int b, int step)
{
    for (int e = p->bucket[hash3(s, b, step) & (p->nbucket - 1)]; e >= 0; e = p->ent[e].next)
        if (p->ent[e].s == s && p->ent[e].b == b && p->ent[e].step == step)
            return e;
    return -1;
}

void vsv_cache_unlink(vsv_pager *p, int e)
{
    int *at = &p->bucket[hash3(p->ent[e].s, p->ent[e].b, p->ent[e].step) & (p->nbucket - 1)];
    while (*at != e)
        at = &p->ent[*at].next;
    *at = p->ent[e].next;
}

int vsv_cache_rehash(vsv_pager *p, unsigned n)
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


/* A new LOADING entry with its buffer (under the lock); -1 when out of memory. */
int vsv_cache_insert(vsv_pager *p, int s, int b, int step)
{
    float *buf = vsv_slab_get(p);
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
                vsv_slab_put(p, buf);
                return -1;
            }
            p->ent = ne;
            p->capent = cap;
        }
        e = p->nent++;
        if ((unsigned)p->nent * 2 > p->nbucket) {
            p->ent[e].state = -1;
            if (vsv_cache_rehash(p, p->nbucket * 2)) {
                vsv_slab_put(p, buf);
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
int vsv_cache_claim(vsv_pager *p, int s, int b, int step)
{
    const int e = vsv_cache_insert(p, s, b, step);
    if (e >= 0) {
        p->ent[e].pins = 1;
        p->pinned += p->brick_bytes;
    }
    return e;
}

void vsv_cache_drop(vsv_pager *p, int e)
{
    vsv_cache_unlink(p, e);
    vsv_slab_put(p, p->ent[e].data);
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
int vsv_cache_make_room(vsv_pager *p, size_t extra, int window)
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
        vsv_cache_drop(p, (int)c[2 * i + 1]);
        p->st.evictions++;
        p->scan_d = p->scan_s = p->scan_b = 0; /* what was there may be gone */
    }
    free(c);
    return p->bytes + extra <= p->budget;
}
