/* vsv_sw_row.c — the shear-warp's compositing for parallel rays, eight
 * pixels of an intermediate row a step.
 *
 * For parallel rays every pixel of a row samples a slice at the same
 * fractions between voxels, so eight adjacent pixels read eight adjacent
 * voxels of each of the two scanlines under the row, in each of the four
 * planes (red, green, blue, extinction): unaligned vector loads, no gather.
 * The row accumulates in four planes of its own; groups of eight pixels that
 * are all opaque are linked past; the footprints of each scanline pair say
 * which groups can receive anything. Opacity 1 - e^-u comes from a
 * polynomial for 2^x (the one-pixel loops read a table; a table here would
 * need a gather per group, slower than the polynomial).
 *
 * Written with GCC's vector extensions only and built twice: as is (for any
 * x86-64, two SSE registers a vector) and by vsv_sw_row_avx2.c for AVX2 and
 * FMA (one register), which vsv_shearwarp.c picks when the CPU has them. */
#include "vsv_sw.h"

#include <stddef.h>
#include <limits.h>
#include <string.h>
#ifdef __AVX2__
#include <immintrin.h>
#endif

#ifndef VSV_SW_PAR_ROWS
#define VSV_SW_PAR_ROWS vsv_sw_par_rows
#define VSV_SW_PAR_WARP vsv_sw_par_warp
#endif

#define OPAQUE 0.998f

typedef float vf __attribute__((vector_size(4 * VSV_SW_LANES)));
typedef int vi __attribute__((vector_size(4 * VSV_SW_LANES)));
typedef float vfu __attribute__((vector_size(4 * VSV_SW_LANES), aligned(4))); /* unaligned */
typedef uint16_t vhu __attribute__((vector_size(2 * VSV_SW_LANES), aligned(2)));
typedef float v4 __attribute__((vector_size(16)));

static inline vf load(const float *p) { return *(const vfu *)p; }

static inline void store(float *p, vf v) { *(vfu *)p = v; }
static inline vf splat(float x) { return (vf){} + x; }
static inline vf pick(vi m, vf a, vf b) { return (vf)(((vi)a & m) | ((vi)b & ~m)); } /* m ? a : b */
/* half floats, normal or 0 (vsv_half_float, lanewise; one instruction with
 * F16C) */
static inline vf load_half(const uint16_t *p)
{
#if defined __F16C__ && VSV_SW_LANES == 8
    return (vf)_mm256_cvtph_ps(_mm_loadu_si128((const __m128i *)p));
#else
    return (vf)(__builtin_convertvector(*(const vhu *)p, vi) << 13) * splat(0x1p112f);
#endif
}

/* e^-u for u >= 0 (relative error under 2e-7; 0 beyond u = 87): 2^x with
 * x = -u log2(e) = n + f, n an integer, |f| <= 1/2, 2^f by its Taylor
 * polynomial to degree 6, 2^n added to the exponent bits. */
static inline vf exp_neg(vf u)
{
    vf x = u * splat(-1.44269504f);
    x = pick(x > splat(-125), x, splat(-125));
    const vf n = (x + splat(12582912.0f)) - splat(12582912.0f); /* round to nearest */
    const vf f = x - n;
    vf p = splat(1.5403530e-4f);
    p = p * f + splat(1.3333558e-3f);
    p = p * f + splat(9.6181291e-3f);
    p = p * f + splat(5.5504109e-2f);
    p = p * f + splat(2.4022651e-1f);
    p = p * f + splat(6.9314718e-1f);
    p = p * f + splat(1.0f);
    const vf r = (vf)((vi)p + (__builtin_convertvector(n, vi) << 23));
    return pick(u < splat(87), r, splat(0));
}

/* every lane of a comparison's mask true */
static inline int all_lanes(vi m)
{
#if defined __AVX__ && VSV_SW_LANES == 8
    return _mm256_movemask_ps((__m256)m) == 0xff;
#endif
    int all = -1;
    for (int i = 0; i < VSV_SW_LANES; i++)
        all &= m[i];
    return all != 0;
}

/* the first group at or after g not linked past as opaque */
static inline int open_group(int *link, int g)
{
    int h = g;
    while (link[h] != h)
        h = link[h];
    if (h != g)
        link[g] = h;
    return h;
}

/* One row (accumulating in acc, its links in link) through one slice:
 * iv the nfp footprint intervals of the scanline pair under the row, r0 and
 * r1 the pair (pixel x's left taps at r0 + x), w00 .. w11 the bilinear
 * weights. */
static inline void row_slice(const vsv_sw_par *p, const uint16_t *iv, int nfp, const uint16_t *r0, const uint16_t *r1,
                             int ip0, vf w00, vf w01, vf w10, vf w11, float *acc, int *link)
{
    const int span = vsv_sw_par_groups(p->w) * VSV_SW_LANES;
    float *const ar = acc, *const ag = acc + span, *const ab = acc + 2 * span, *const aa = acc + 3 * span;
    const size_t P = p->plane;
    const vf d = splat(p->delta);
    /* the intervals are sorted, but two can share a group: each group
     * once, from the first after the last one composited */
    for (int q = 0, next = 0; q < nfp; q++) {
        int x0 = iv[2 * q] - ip0, x1 = iv[2 * q + 1] - ip0;
        if (x0 < 0)
            x0 = 0;
        if (x1 > p->w - 1)
            x1 = p->w - 1;
        const int ge = x1 / VSV_SW_LANES, g0 = x0 / VSV_SW_LANES > next ? x0 / VSV_SW_LANES : next;
        if (x0 > x1 || g0 > ge)
            continue;
        next = ge + 1;
        for (int g = open_group(link, g0); g <= ge; g = open_group(link, g + 1)) {
            const int x = g * VSV_SW_LANES;
            const uint16_t *t0 = r0 + x, *t1 = r1 + x;
            vf c[4];
            for (int ch = 0; ch < 4; ch++, t0 += P, t1 += P)
                c[ch] = w00 * load_half(t0) + w01 * load_half(t0 + 1) + w10 * load_half(t1) + w11 * load_half(t1 + 1);
            /* transmittance x (1 - e^-(S d)) / S, S the extinction (0
             * where nothing is: then so are the colours) */
            const vf S = c[3];
            const vf a = load(aa + x);
            const vf kk = (splat(1) - a) * ((splat(1) - exp_neg(S * d)) / pick(S > splat(1e-30f), S, splat(1e-30f)));
            store(ar + x, load(ar + x) + kk * c[0]);
            store(ag + x, load(ag + x) + kk * c[1]);
            store(ab + x, load(ab + x) + kk * c[2]);
            const vf a2 = a + kk * S;
            store(aa + x, a2);
            if (all_lanes(a2 >= splat(OPAQUE)))
                link[g] = g + 1;
        }
    }
}

/* The bytes [*pa, *pe) of slice k's scanlines ib0 .. ib0 + n (clipped), which
 * rows y0 .. y0 + n - 1 will read; none when their footprints are all
 * empty. */
static inline void band_bytes(const vsv_sw_par *p, int k, int ib0, int n, const char **pa, const char **pe)
{
    const int lo = ib0 < -1 ? -1 : ib0, hi = ib0 + n > p->nb ? p->nb : ib0 + n;
    const vsv_sw_fp *fps = p->fps + (size_t)k * (p->nb + 1);
    int any = 0;
    for (int ib = lo; ib < hi; ib++)
        any |= fps[ib + 1].n != 0;
    *pa = *pe = NULL;
    if (!any)
        return;
    const size_t scan = 4 * p->plane;
    *pa = (const char *)(p->vox + ((size_t)k * (p->nb + 2) + lo + 1) * scan);
    *pe = (const char *)(p->vox + ((size_t)k * (p->nb + 2) + hi + 2) * scan);
}
void VSV_SW_PAR_ROWS(const vsv_sw_par *p, int y0, int n, float *acc, int *link, float *img, size_t stride, int box[4])
{
    const int ng = vsv_sw_par_groups(p->w), span = ng * VSV_SW_LANES;
    memset(acc, 0, sizeof(float) * 4 * span * n);
    for (int g = 0; g < (ng + 1) * n; g++)
        link[g] = g % (ng + 1);
    /* slice by slice, the band's rows in turn: the band's scanlines of a
     * slice are adjacent and read from memory once. Row y0 + j of slice k
     * lies between scanlines ib0 + j and ib0 + j + 1, all at fraction fv. */
    const size_t scan = 4 * p->plane, ivn = (size_t)(p->nb + 1) * (p->na + 4);
    for (int s = 0; s < p->nc; s++) {
        const int k = p->front + s * p->dk;
        const double pb0 = y0 - (p->sb * k + p->tb);
        const int ib0 = (int)floor(pb0);
        const int j0 = -1 - ib0 > 0 ? -1 - ib0 : 0, j1 = p->nb - 1 - ib0 < n - 1 ? p->nb - 1 - ib0 : n - 1;
        /* the next slice's voxels under the band, on their way to the cache:
         * a share before each row (all at once, they measured slower) */
        const char *pa = NULL, *pe = NULL;
        const int kn = k + p->dk;
        if (s + 1 < p->nc)
            band_bytes(p, kn, (int)floor(y0 - (p->sb * kn + p->tb)), n, &pa, &pe);
        const ptrdiff_t share = j1 >= j0 ? ((pe - pa) / 64 / (j1 - j0 + 2) + 1) * 64 : pe - pa;
        if (j0 > j1) {
            for (; pa < pe; pa += 64)
                __builtin_prefetch(pa);
            continue;
        }
        const double pa1 = 1 - (p->sa * k + p->ta);
        const int ip0 = (int)floor(pa1);
        const float fu = (float)(pa1 - ip0), fv = (float)(pb0 - ib0);
        const vf w00 = splat((1 - fu) * (1 - fv)), w01 = splat(fu * (1 - fv)), w10 = splat((1 - fu) * fv),
                 w11 = splat(fu * fv);
        const vsv_sw_fp *fps = p->fps + (size_t)k * (p->nb + 1) + ib0 + 1;
        const uint16_t *iv = p->ivl + k * ivn;
        const uint16_t *r = p->vox + ((size_t)k * (p->nb + 2) + ib0 + 1) * scan + VSV_SW_PAD + ip0 - 1;
        for (int j = j0; j <= j1; j++) {
            for (const char *ce = pe - pa > share ? pa + share : pe; pa < ce; pa += 64)
                __builtin_prefetch(pa);
            if (fps[j].n)
                row_slice(p, iv + fps[j].at, (int)fps[j].n, r + j * scan, r + (j + 1) * scan, ip0, w00, w01, w10, w11,
                          acc + (size_t)4 * span * j, link + (ng + 1) * j);
        }
        for (; pa < pe; pa += 64)
            __builtin_prefetch(pa);
    }
    box[0] = box[2] = INT_MAX, box[1] = box[3] = -1;
    for (int j = 0; j < n; j++) {
        const float *a = acc + (size_t)4 * span * j;
        float *out = img + stride * j;
        int x0 = p->w, x1 = -1, x = 0;
        for (; x + VSV_SW_LANES <= p->w; x += VSV_SW_LANES) { /* four planes to pixels, eight at a time */
            const vf r = load(a + x), g = load(a + span + x), b = load(a + 2 * span + x), al = load(a + 3 * span + x);
            const vf rg0 = __builtin_shufflevector(r, g, 0, 8, 1, 9, 2, 10, 3, 11);
            const vf rg1 = __builtin_shufflevector(r, g, 4, 12, 5, 13, 6, 14, 7, 15);
            const vf ba0 = __builtin_shufflevector(b, al, 0, 8, 1, 9, 2, 10, 3, 11);
            const vf ba1 = __builtin_shufflevector(b, al, 4, 12, 5, 13, 6, 14, 7, 15);
            store(out + 4 * x, __builtin_shufflevector(rg0, ba0, 0, 1, 8, 9, 2, 3, 10, 11));
            store(out + 4 * x + 8, __builtin_shufflevector(rg0, ba0, 4, 5, 12, 13, 6, 7, 14, 15));
            store(out + 4 * x + 16, __builtin_shufflevector(rg1, ba1, 0, 1, 8, 9, 2, 3, 10, 11));
            store(out + 4 * x + 24, __builtin_shufflevector(rg1, ba1, 4, 5, 12, 13, 6, 7, 14, 15));
        }
        for (; x < p->w; x++) {
            out[4 * x] = a[x];
            out[4 * x + 1] = a[span + x];
            out[4 * x + 2] = a[2 * span + x];
            out[4 * x + 3] = a[3 * span + x];
        }
        for (x = 0; x < p->w; x += VSV_SW_LANES) /* where alpha > 0, eight at a time */
            if (!all_lanes(load(a + 3 * span + x) <= splat(0)))
                for (int i = x; i < x + VSV_SW_LANES && i < p->w; i++)
                    if (a[3 * span + i] > 0) {
                        x0 = i < x0 ? i : x0;
                        x1 = i;
                    }
        if (x1 >= 0) {
            box[0] = x0 < box[0] ? x0 : box[0];
            box[1] = x1 > box[1] ? x1 : box[1];
            box[2] = y0 + j < box[2] ? y0 + j : box[2];
            box[3] = y0 + j;
        }
    }
}

void VSV_SW_PAR_WARP(const float *img, size_t W, int w, int h, double x0, double y0, double dx, double dy, int p0,
                     int p1, float *out)
{
    const vf xmax = splat((float)w + 1), ymax = splat((float)h + 1), zero = splat(0);
    vf lane;
    for (int i = 0; i < VSV_SW_LANES; i++)
        lane[i] = (float)i;
    for (int px = p0; px <= p1; px += VSV_SW_LANES) {
        /* eight pixels' points, clamped (NaN too) into [0, w + 1] x [0, h + 1] */
        vf x = splat((float)(x0 + px * dx)) + lane * (float)dx, y = splat((float)(y0 + px * dy)) + lane * (float)dy;
        x = pick(x > zero, x, zero);
        x = pick(x < xmax, x, xmax);
        y = pick(y > zero, y, zero);
        y = pick(y < ymax, y, ymax);
        const vi xi = __builtin_convertvector(x, vi), yi = __builtin_convertvector(y, vi);
        const vf fx = x - __builtin_convertvector(xi, vf), fy = y - __builtin_convertvector(yi, vf);
        /* then each pixel's four taps, one vector of four channels each */
        const vi off = (yi * (int)W + xi) * 4;
        const vf w00 = (1 - fx) * (1 - fy), w01 = fx * (1 - fy), w10 = (1 - fx) * fy, w11 = fx * fy;
        const int n = p1 - px + 1 < VSV_SW_LANES ? p1 - px + 1 : VSV_SW_LANES;
        for (int i = 0; i < n; i++) {
            const v4 *s0 = (const v4 *)(img + off[i]), *s1 = s0 + W;
            *(v4 *)(out + 4 * (px + i)) = s0[0] * w00[i] + s0[1] * w01[i] + s1[0] * w10[i] + s1[1] * w11[i];
        }
    }
}
