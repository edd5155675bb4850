/* vsv_slab.c — the pager's brick buffers: carved from 2 MB slabs (huge
 * pages where the kernel gives them: far fewer page faults) and recycled
 * through a free list. */
#include "vsv_pager_internal.h"

#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

/* A brick buffer (under the lock); NULL when out of memory. */
float *vsv_slab_get(vsv_pager *p)
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

void vsv_slab_put(vsv_pager *p, float *b)
{
    if (!b)
        return;
    memcpy(b, &p->freebuf, sizeof(void *));
    p->freebuf = b;
}
