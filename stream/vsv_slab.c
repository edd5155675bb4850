/* vsv_slab.c — the pager's buffers, in two pools (decoded brick floats;
 * decoder-track codes): carved from 2 MB slabs (huge pages where the kernel
 * gives them: far fewer page faults), or for the bricks from the caller's
 * allocator (vsv_pager_opts.slab_alloc: memory other processes map), and
 * recycled through a free list. A
 * pool never holds more than the most bytes the pager held at once, which
 * the budget bounds (stats.peak_bytes). */
#include "vsv_pager_internal.h"

#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

/* A buffer of pool i (under the lock); NULL when out of memory. */
void *vsv_slab_get(vsv_pager *p, int i)
{
    struct vsv_pool *P = &p->pool[i];
    if (P->freebuf) {
        void *b = P->freebuf;
        memcpy(&P->freebuf, b, sizeof(void *));
        return b;
    }
    if (!P->nslabs || P->slab_used + P->size > p->slab_bytes) {
        if (P->nslabs == P->capslabs) {
            const int cap = P->capslabs ? 2 * P->capslabs : 64;
            void **ns = realloc(P->slabs, (size_t)cap * sizeof *ns);
            if (!ns)
                return NULL;
            P->slabs = ns;
            P->capslabs = cap;
        }
        void *m = NULL;
        if (i == 0 && p->slab_alloc) { /* the caller's memory, kept by the caller */
            if (!(m = p->slab_alloc(p->slab_ctx, p->slab_bytes)))
                return NULL;
        } else {
            if (posix_memalign(&m, (size_t)2 << 20, p->slab_bytes))
                return NULL;
            madvise(m, p->slab_bytes, MADV_HUGEPAGE);
        }
        P->slabs[P->nslabs++] = m;
        P->slab_used = 0;
    }
    void *b = (char *)P->slabs[P->nslabs - 1] + P->slab_used;
    P->slab_used += P->size;
    return b;
}

void vsv_slab_put(vsv_pager *p, int i, void *b)
{
    if (!b)
        return;
    memcpy(b, &p->pool[i].freebuf, sizeof(void *));
    p->pool[i].freebuf = b;
}

void vsv_slab_free_all(vsv_pager *p)
{
    for (int i = 0; i < 2; i++) {
        for (int k = 0; k < p->pool[i].nslabs && !(i == 0 && p->slab_alloc); k++)
            free(p->pool[i].slabs[k]);
        free(p->pool[i].slabs);
    }
}
