/* vsv_buf.c — the growable byte buffer the writer and the readers of model
 * files build records in, little-endian. */
#include "vsv_common.h"

#include <assert.h>
#include <stdlib.h>
#include <string.h>

int vsv_buf_reserve(vsv_buf *b, size_t extra)
{
    assert(b->len <= b->cap); /* what is held fits what is allocated */
    if (b->len + extra <= b->cap)
        return 0;
    size_t cap = b->cap ? b->cap : 4096;
    while (cap < b->len + extra)
        cap *= 2;
    unsigned char *p = realloc(b->p, cap);
    if (!p)
        return VSV_ENOMEM;
    b->p = p;
    b->cap = cap;
    return 0;
}

int vsv_buf_put(vsv_buf *b, const void *data, size_t n)
{
    if (vsv_buf_reserve(b, n))
        return VSV_ENOMEM;
    if (n)
        memcpy(b->p + b->len, data, n);
    b->len += n;
    return 0;
}

int vsv_buf_zeros(vsv_buf *b, size_t n)
{
    if (vsv_buf_reserve(b, n))
        return VSV_ENOMEM;
    memset(b->p + b->len, 0, n);
    b->len += n;
    return 0;
}

int vsv_buf_u32(vsv_buf *b, uint32_t v)
{
    unsigned char t[4];
    vsv_wr32(t, v);
    return vsv_buf_put(b, t, 4);
}

int vsv_buf_u64(vsv_buf *b, uint64_t v)
{
    unsigned char t[8];
    vsv_wr64(t, v);
    return vsv_buf_put(b, t, 8);
}

int vsv_buf_f64(vsv_buf *b, double v)
{
    unsigned char t[8];
    vsv_wrf64(t, v);
    return vsv_buf_put(b, t, 8);
}

int vsv_buf_str(vsv_buf *b, const char *s)
{
    size_t n = strlen(s);
    if (vsv_buf_u32(b, (uint32_t)n))
        return VSV_ENOMEM;
    return vsv_buf_put(b, s, n);
}

void vsv_buf_free(vsv_buf *b)
{
    free(b->p);
    b->p = NULL;
    b->len = b->cap = 0;
}
