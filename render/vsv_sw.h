/* vsv_sw.h — the shear-warp renderer in phases the pool runs, and its
 * row kernels (vsv_shearwarp.c, vsv_sw_row.c). Private to render/. */
#ifndef VSV_SW_H
#define VSV_SW_H

#include "vsv_geo.h"
#include "vsv_tf_internal.h"

#include <stdint.h>
#include <string.h>

/* Shear-warp in phases so the pool can run all but begin. begin sets up the
 * view (*rows = the compositing jobs: intermediate rows, or bands of
 * VSV_SW_BAND of them for parallel rays; VSV_EUNSUPPORTED when the eye is
 * among the slices) and, when the principal axis's classified copy is not
 * current for this scene, *classify = its slice count: the caller runs
 * vsv_sw_classify_slice for those items, then vsv_sw_classified. Then every
 * compositing job (they are independent), then every job of final rows
 * warped (vsv_sw_warp_jobs). thread indexes per-thread scratch (< the
 * create argument). */
typedef struct vsv_sw vsv_sw;
vsv_sw *vsv_sw_create(int max_threads, int simd);
void vsv_sw_free(vsv_sw *sw);
int vsv_sw_begin(vsv_sw *sw, const vsv_scene *sc, const vsv_geo *g, const vsv_camera *cam, float *rgba, float *depth,
                 const vsv_ground *ground, int *rows, int *classify);
void vsv_sw_classify_slice(void *sw, int k, int thread);
void vsv_sw_classified(vsv_sw *sw, double seconds);
void vsv_sw_composite_row(void *sw, int y, int thread);
#define VSV_SW_WARP_ROWS 32 /* final rows a warp job */
static inline int vsv_sw_warp_jobs(int height) { return (height + VSV_SW_WARP_ROWS - 1) / VSV_SW_WARP_ROWS; }
void vsv_sw_warp_rows(void *sw, int job, int thread);
double vsv_sw_build_seconds(const vsv_sw *sw);

/* The classified copy for a principal axis c (a = c+1, b = c+2 mod 3), in
 * the order a frame reads it: slice k holds scanlines ib = -1 .. nb (the
 * first and last empty), each scanline four planes (extinction-weighted red,
 * green, blue, then extinction, the extinction in units of
 * VSV_SIGMA_PER_CELL over the smaller horizontal cell size, times a power
 * of two that brings the largest possible to 2^14) of VSV_SW_PLANE(na) half
 * floats (IEEE binary16, vsv_half: normal or 0), voxel ia at
 * VSV_SW_PAD + ia, the padding empty. Beside it, for every pair of adjacent
 * scanlines (ib, ib + 1), ib = -1 .. nb - 1, where a sample between them can
 * meet a non-transparent voxel: n sorted half-open intervals [lo, hi) of
 * voxel indices (a sample at pa touches it when floor(pa) lies in [lo - 1,
 * hi - 1]), its footprint. Slice k's footprints are packed together from
 * ivl + k (nb + 1)(na + 4) (uint16 pairs lo, hi), pair ib's found through
 * the entry (nb + 1) k + ib + 1 of fps: a frame reads only a few kilobytes
 * of them a slice. */
typedef struct vsv_sw_fp {
    uint32_t at, n; /* from the slice's first, n intervals */
} vsv_sw_fp;
#define VSV_SW_LANES 8
/* Half floats for values >= 0, normal or 0 only: rounded to nearest (up at
 * ties), below 2^-14 to 0, 65504 at most. Integer work on the bits, float
 * arithmetic on normal numbers only (a subnormal operand or result costs a
 * microcode assist of a hundred cycles or more on x86), so every CPU gives
 * the same bits. */
static inline uint16_t vsv_half(float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    if (u >= 0x477FE000u) /* 65504 and above (or NaN, which never comes) */
        return 0x7BFF;
    if (u < 0x38800000u) /* below 2^-14 */
        return 0;
    return (uint16_t)((u - 0x38000000u + 0x1000u) >> 13); /* the exponent rebased by -112 */
}
static inline float vsv_half_float(uint16_t h)
{
    const uint32_t u = (uint32_t)h << 13; /* 0 or normal */
    float f;
    memcpy(&f, &u, 4);
    return f * 0x1p112f;
}
#define VSV_SW_PAD VSV_SW_LANES
#define VSV_SW_PLANE(na) ((((size_t)(na) + 2 * VSV_SW_PAD) + VSV_SW_LANES - 1) / VSV_SW_LANES * VSV_SW_LANES)

/* Intermediate rows for parallel rays: slice k samples voxel position
 * pa = x - (sa k + ta) at pixel x, pb = y - (sb k + tb), with the same
 * bilinear weights all along the row, VSV_SW_LANES pixels a step. */
typedef struct vsv_sw_par {
    const uint16_t *vox; /* the classified copy (above) */
    const vsv_sw_fp *fps; /* its footprints */
    const uint16_t *ivl;
    size_t plane;        /* VSV_SW_PLANE(na) */
    int na, nb, nc, w, front, dk;
    double sa, sb, ta, tb;
    float delta;         /* ray between slices, in the extinction's units */
} vsv_sw_par;
/* Composites rows y0 .. y0 + n - 1 front to back, row y0 + j into img +
 * j stride (w pixels of premultiplied rgb, alpha), the smallest box holding
 * every pixel with alpha > 0 into box (x0, x1, y0, y1, inclusive; x0 > x1
 * when none); acc (n times 4 planes of
 * vsv_sw_par_groups(w) * VSV_SW_LANES floats) and link (n times
 * vsv_sw_par_groups(w) + 1 ints) are the caller's scratch. The same source
 * built twice: for any x86-64 and for AVX2 + FMA. */
#define VSV_SW_BAND 8 /* rows a call */
static inline int vsv_sw_par_groups(int w) { return (w + VSV_SW_LANES - 1) / VSV_SW_LANES; }
void vsv_sw_par_rows(const vsv_sw_par *p, int y0, int n, float *acc, int *link, float *img, size_t stride, int box[4]);
void vsv_sw_par_rows_avx2(const vsv_sw_par *p, int y0, int n, float *acc, int *link, float *img, size_t stride,
                          int box[4]);
/* Final pixels p0 .. p1 of a row for parallel rays: pixel px is the
 * bilinear blend of the intermediate image (stride W pixels of four floats,
 * w x h inside an empty border of one pixel left and top, two right and
 * bottom) at border coordinates (x0 + px dx, y0 + px dy), clamped into the
 * border. Built the same two ways. */
void vsv_sw_par_warp(const float *img, size_t W, int w, int h, double x0, double y0, double dx, double dy, int p0, int p1,
                     float *out);
void vsv_sw_par_warp_avx2(const float *img, size_t W, int w, int h, double x0, double y0, double dx, double dy, int p0,
                          int p1, float *out);

#endif
