/* vsv_cache.c — the pager's cache: entries keyed by species, brick and
 * defining step in a hash with chains, and intrusive least-recently-used
 * lists (the links live in the entries and tracks), so eviction under the
 * byte budget takes list heads: no allocation, scan or sort under the lock. */
#include "vsv_pager_internal.h"

#include <assert.h>
#include <stdlib.h>
#include <string.h>

static vsv_link *link_at(void *base, size_t stride, int i) { return (vsv_link *)((char *)base + (size_t)i * stride); }

void vsv_lru_init(vsv_lru *l) { l->head = l->tail = -1; }

void vsv_lru_push(vsv_lru *l, void *base, size_t stride, int i)
{
    vsv_link *n = link_at(base, stride, i);
    n->next = -1;
    n->prev = l->tail;
    if (l->tail >= 0)
        link_at(base, stride, l->tail)->next = i;
    else
        l->head = i;
    l->tail = i;
}

void vsv_lru_unlink(vsv_lru *l, void *base, size_t stride, int i)
{
    vsv_link *n = link_at(base, stride, i);
    if (n->prev >= 0)
        link_at(base, stride, n->prev)->next = n->next;
    else
        l->head = n->next;
    if (n->next >= 0)
        link_at(base, stride, n->next)->prev = n->prev;
    else
        l->tail = n->prev;
    n->prev = n->next = -1;
}

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

static void hash_unlink(vsv_pager *p, int e)
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

/* The list an unpinned entry belongs on: checkpoints, or bricks inside
 * the window or outside. */
static vsv_lru *list_of(vsv_pager *p, const entry *E)
{
    return &p->lru[E->s >= p->info.nspecies ? L_CK : E->mark == p->mark ? L_IN : L_OUT];
}

/* A brick (or with s >= nspecies a checkpoint) this thread will decode
 * (under the lock): a new LOADING entry with its buffer, pinned while it is
 * decoded so nothing evicts it; -1 when out of memory. */
int vsv_cache_claim(vsv_pager *p, int s, int b, int step)
{
    const int ck = s >= p->info.nspecies;
    const size_t size = p->brick_bytes;
    void *buf = vsv_slab_get(p, 0);
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
                vsv_slab_put(p, 0, buf);
                return -1;
            }
            p->ent = ne;
            p->capent = cap;
        }
        e = p->nent++;
        if ((unsigned)p->nent * 2 > p->nbucket) {
            p->ent[e].state = -1;
            if (vsv_cache_rehash(p, p->nbucket * 2)) {
                p->ent[e].next = p->freelist;
                p->freelist = e;
                vsv_slab_put(p, 0, buf);
                return -1;
            }
        }
    }
    entry *E = &p->ent[e];
    *E = (entry){{-1, -1}, s, b, step, LOADING, 1, 0, ck ? -1 : p->mark, buf, 0, -1, 0, 0};
    const unsigned h = hash3(s, b, step) & (p->nbucket - 1);
    E->next = p->bucket[h];
    p->bucket[h] = e;
    p->bytes += size;
    p->pinned += size;
    if (ck)
        p->track_bytes += size;
    if (p->bytes > p->peak)
        p->peak = p->bytes;
    return e;
}

void vsv_cache_drop(vsv_pager *p, int e)
{
    entry *E = &p->ent[e];
    const int ck = vsv_cache_is_ck(p, e);
    const size_t size = vsv_cache_size(p, e);
    assert(E->state != -1 && p->bytes >= size && (!E->pins || p->pinned >= size)); /* a live entry, counted */
    if (E->listed)
        vsv_lru_unlink(list_of(p, E), p->ent, sizeof *p->ent, e);
    if (E->pins)
        p->pinned -= size;
    hash_unlink(p, e);
    vsv_slab_put(p, 0, E->data);
    E->data = NULL;
    E->state = -1;
    E->listed = 0;
    E->pins = 0;
    E->next = p->freelist;
    p->freelist = e;
    p->bytes -= size;
    if (ck)
        p->track_bytes -= size;
}

void vsv_cache_touch(vsv_pager *p, int e)
{
    entry *E = &p->ent[e];
    if (!E->listed)
        return;
    vsv_lru *l = list_of(p, E);
    vsv_lru_unlink(l, p->ent, sizeof *p->ent, e);
    vsv_lru_push(l, p->ent, sizeof *p->ent, e);
}

void vsv_cache_pin(vsv_pager *p, int e)
{
    entry *E = &p->ent[e];
    assert(E->state != -1); /* never a free entry */
    if (E->pins++)
        return;
    p->pinned += vsv_cache_size(p, e);
    if (E->listed) {
        vsv_lru_unlink(list_of(p, E), p->ent, sizeof *p->ent, e);
        E->listed = 0;
    }
}

void vsv_cache_unpin(vsv_pager *p, int e)
{
    entry *E = &p->ent[e];
    assert(E->pins > 0); /* every unpin follows its pin */
    if (--E->pins)
        return;
    p->pinned -= vsv_cache_size(p, e);
    if (E->state != LOADING) { /* READY, FAILED, STALLED: evictable */
        vsv_lru_push(list_of(p, E), p->ent, sizeof *p->ent, e);
        E->listed = 1;
    }
}

/* Called before p->mark changes: the old window's entries join the outside
 * list (behind its own, as more recently used), in one splice. */
void vsv_cache_new_window(vsv_pager *p)
{
    vsv_lru *in = &p->lru[L_IN], *out = &p->lru[L_OUT];
    if (in->head < 0)
        return;
    if (out->tail >= 0) {
        p->ent[out->tail].ln.next = in->head;
        p->ent[in->head].ln.prev = out->tail;
        out->tail = in->tail;
    } else {
        *out = *in;
    }
    vsv_lru_init(in);
}

/* Marks e as needed by the current window: to the inside list. */
void vsv_cache_mark(vsv_pager *p, int e)
{
    entry *E = &p->ent[e];
    if (E->mark == p->mark)
        return;
    if (E->listed) {
        vsv_lru_unlink(&p->lru[L_OUT], p->ent, sizeof *p->ent, e);
        E->mark = p->mark;
        vsv_lru_push(&p->lru[L_IN], p->ent, sizeof *p->ent, e);
    }
    E->mark = p->mark;
}

static void evict_track(vsv_pager *p)
{
    const int i = p->tlru.head;
    track *T = &p->tracks[i];
    vsv_lru_unlink(&p->tlru, p->tracks, sizeof *p->tracks, i);
    T->listed = 0;
    vsv_slab_put(p, 1, T->codes);
    T->codes = NULL;
    T->step = -1;
    p->bytes -= p->codes_bytes;
    p->track_bytes -= p->codes_bytes;
}

/* Evicts until `extra` more bytes fit in the budget, taking list heads:
 * unpinned bricks outside the prefetch window (least recently used first),
 * then checkpoints, then idle decoder tracks, then (only when `window` is
 * set) unpinned bricks inside the window. Returns whether they fit. */
int vsv_cache_make_room(vsv_pager *p, size_t extra, int window)
{
    while (p->bytes + extra > p->budget) {
        if (p->lru[L_OUT].head >= 0) {
            vsv_cache_drop(p, p->lru[L_OUT].head);
            p->st.evictions++;
        } else if (p->lru[L_CK].head >= 0) {
            vsv_cache_drop(p, p->lru[L_CK].head);
        } else if (p->tlru.head >= 0) {
            evict_track(p);
        } else if (window && p->lru[L_IN].head >= 0) {
            vsv_cache_drop(p, p->lru[L_IN].head);
            p->st.evictions++;
        } else {
            return 0;
        }
        p->scan_d = p->scan_s = p->scan_b = 0; /* what was there may be gone */
    }
    return 1;
}

int vsv_cache_room_ck(vsv_pager *p)
{
    while (p->bytes + p->brick_bytes > p->budget && p->lru[L_OUT].head >= 0) {
        vsv_cache_drop(p, p->lru[L_OUT].head);
        p->st.evictions++;
        p->scan_d = p->scan_s = p->scan_b = 0;
    }
    return p->bytes + p->brick_bytes <= p->budget;
}
