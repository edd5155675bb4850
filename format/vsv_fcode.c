/* vsv_fcode.c — float arrays coded losslessly for metadata (SPEC.md §4,
 * HGTS form 2): heights of neighbouring levels share their sign, exponent
 * and high mantissa bits, so each value's bits minus those of the value
 * `stride` places before (the level below) leave small integers; their four
 * byte planes one after another put the near-constant high bytes together
 * for zstd. 2.25x on the Katrina file's heights, where raw floats through
 * zstd give 1.6x. */
#include "vsv_format_internal.h"

#include <stdlib.h>
#include <zstd.h>
#include <zstd_errors.h>

#define FCODE_LEVEL 9

int vsv_floats_code(const float *v, size_t n, size_t stride, vsv_buf *b)
{
    unsigned char *planes = malloc(4 * n + 1);
    if (!planes)
        return VSV_ENOMEM;
    for (size_t i = 0; i < n; i++) {
        uint32_t u, w = 0;
        memcpy(&u, &v[i], 4);
        if (i >= stride)
            memcpy(&w, &v[i - stride], 4);
        u -= w;
        for (int k = 0; k < 4; k++)
            planes[(size_t)k * n + i] = (unsigned char)(u >> (8 * k));
    }
    const size_t bound = ZSTD_compressBound(4 * n);
    int rc = vsv_buf_reserve(b, bound);
    if (!rc) {
        const size_t got = ZSTD_compress(b->p + b->len, bound, planes, 4 * n, FCODE_LEVEL);
        if (ZSTD_isError(got))
            rc = ZSTD_getErrorCode(got) == ZSTD_error_memory_allocation ? VSV_ENOMEM : VSV_EIO;
        else
            b->len += got;
    }
    free(planes);
    return rc;
}

int vsv_floats_decode(const unsigned char *p, size_t len, size_t n, size_t stride, float *out)
{
    /* exactly one frame of exactly 4n bytes: a record is never read past */
    if (ZSTD_getFrameContentSize(p, len) != 4 * (unsigned long long)n || ZSTD_findFrameCompressedSize(p, len) != len)
        return VSV_ECORRUPT;
    unsigned char *planes = malloc(4 * n + 1);
    if (!planes)
        return VSV_ENOMEM;
    const size_t got = ZSTD_decompress(planes, 4 * n, p, len);
    /* (zstd's own context may not be had under a memory limit: no damage) */
    int rc = ZSTD_isError(got) && ZSTD_getErrorCode(got) == ZSTD_error_memory_allocation ? VSV_ENOMEM
             : ZSTD_isError(got) || got != 4 * n                                         ? VSV_ECORRUPT
                                                                                         : 0;
    for (size_t i = 0; i < n && !rc; i++) {
        uint32_t u = 0, w = 0;
        for (int k = 0; k < 4; k++)
            u |= (uint32_t)planes[(size_t)k * n + i] << (8 * k);
        if (i >= stride)
            memcpy(&w, &out[i - stride], 4);
        u += w;
        memcpy(&out[i], &u, 4);
    }
    free(planes);
    return rc;
}

int vsv_plane_code(const float *v, size_t n, vsv_buf *b)
{
    /* along x: neighbouring cells of terrain and land use share high bits */
    return vsv_floats_code(v, n, 1, b);
}

int vsv_plane_decode(const unsigned char *p, size_t len, size_t n, float *out)
{
    return vsv_floats_decode(p, len, n, 1, out);
}
