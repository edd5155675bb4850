/* vsv_sw.h — the shear-warp renderer in phases the pool runs, and its
 * row kernels (vsv_shearwarp.c, vsv_sw_row.c). Private to render/. */
#ifndef VSV_SW_H
#define VSV_SW_H

#include "vsv_geo.h"
#include "vsv_light.h"
#include "vsv_tf_internal.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#ifdef __SSE2__
#include <emmintrin.h>
#endif

/* Shear-warp in phases so the pool can run all but begin. begin sets up the
 * view (*rows = the compositing jobs: intermediate rows, or bands of
 * VSV_SW_BAND of them for parallel rays; VSV_EUNSUPPORTED when the eye is
 * among the slices) and, when the principal axis's classified copy is not
 * current for this scene, *bricks = the bricks to classify (once for all
 * axes) and *classify = the slices to copy them into (all of them the
 * first time, then those of slabs where a brick changed): the caller runs
 * vsv_sw_classify_brick for the first items, then vsv_sw_classify_slice
 * for the second, then vsv_sw_classified. Then every
 * compositing job (they are independent), then every job of final rows
 * warped (vsv_sw_warp_jobs). thread indexes per-thread scratch (< the
 * create argument). */
typedef struct vsv_sw vsv_sw;
vsv_sw *vsv_sw_create(int max_threads, int simd);
void vsv_sw_free(vsv_sw *sw);
int vsv_sw_begin(vsv_sw *sw, const vsv_scene *sc, const vsv_geo *g, const vsv_camera *cam, float *rgba,
                 unsigned char *rgba8, float *depth, const vsv_ground *ground, int *rows, int *bricks, int *classify);
void vsv_sw_classify_brick(void *sw, int j, int thread);
void vsv_sw_classify_slice(void *sw, int j, int thread);
void vsv_sw_classified(vsv_sw *sw, double seconds);
void vsv_sw_composite_row(void *sw, int y, int thread);
#define VSV_SW_WARP_ROWS 32 /* final rows a warp job */
static inline int vsv_sw_warp_jobs(int height) { return (height + VSV_SW_WARP_ROWS - 1) / VSV_SW_WARP_ROWS; }
void vsv_sw_warp_rows(void *sw, int job, int thread);
double vsv_sw_build_seconds(const vsv_sw *sw);
int vsv_sw_build_bricks(const vsv_sw *sw); /* bricks the last build classified */

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
    const uint16_t *vox;  /* the classified copy (above) */
    const vsv_sw_fp *fps; /* its footprints */
    const uint16_t *ivl;
    size_t plane; /* VSV_SW_PLANE(na) */
    int na, nb, nc, w, front, dk;
    double sa, sb, ta, tb;
    float delta; /* ray between slices, in the extinction's units */
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
void vsv_sw_par_warp(const float *img, size_t W, int w, int h, double x0, double y0, double dx, double dy, int p0,
                     int p1, float *out);
void vsv_sw_par_warp_avx2(const float *img, size_t W, int w, int h, double x0, double y0, double dx, double dy, int p0,
                          int p1, float *out);

/* a layer's classification table: entry 0 transparent (below the range,
 * no data), then VSV_SW_SUB entries per step of the transfer function's */
#define VSV_SW_SUB 16
/* slices a classification job copies into (B is a multiple) */
#define VSV_SW_GROUP 8
#define VSV_SW_NTAB ((VSV_TF_LUT - 1) * VSV_SW_SUB + 2)
/* A layer's table t for transfer function tf at opacity o (times the
 * copy's scale): entry 1 + i the species rule at position i / VSV_SW_SUB
 * of tf's table (linear between its entries), the four half floats packed
 * in 64 bits (the copy's plane order), 0 where the extinction is not above
 * 0 (vsv_sw_classify.c) */
void vsv_sw_table(const vsv_tf *tf, float o, uint64_t *t);
/* The entry of a layer's table for value v at x (v itself on a linear
 * scale, its logarithm on a log scale) of a transfer function of range
 * lo, base (float)tf->base, inv (float)tf->inv: 1 + round(x' VSV_SW_SUB), x'
 * its position in the transfer function's table (within 1/32 of a step
 * of the exact lookup); 0 below the range or without data (NaN). */
static inline uint16_t vsv_sw_position(float v, float x, float lo, float base, float inv)
{
    float p = (x - base) * inv;
    p = p > 0 ? p : 0; /* NaN too (selected away below): converted in range */
    p = p < VSV_TF_LUT - 1 ? p : VSV_TF_LUT - 1;
    return (uint16_t)(v >= lo ? 1 + (int)(p * VSV_SW_SUB + 0.5f) : 0);
}
typedef uint16_t vsv_sw_h8 __attribute__((vector_size(16)));
/* vsv_sw_position for a row of n values v (at x), eight a vector: the
 * entries of the i-th eight to out + 512 i (a row of 8^3-cell blocks of a
 * classified brick), lane by lane the smallest and largest so far into
 * mn[i], mx[i] (vsv_sw_table.c) */
void vsv_sw_positions(const float *v, const float *x, int n, float lo, float base, float inv, uint16_t *out,
                      vsv_sw_h8 *mn, vsv_sw_h8 *mx);

/* The renderer's state (vsv_shearwarp.c: the frame; vsv_sw_classify.c: the
 * classification). */
struct vsv_sw {
    /* per principal axis c (a = c+1, b = c+2 mod 3): the classified copy
     * and its footprints (vsv_sw.h) */
    uint16_t *vox[3];
    size_t vox_cap[3];
    vsv_sw_fp *fps[3];
    uint16_t *ivl[3];
    size_t fps_cap[3], ivl_cap[3];
    uint64_t key; /* what the classification was built from */
    int n[3];
    int valid[3];        /* the copy for this axis is current */
    const vsv_scene *sc; /* during classification */
    /* per layer and brick: every value transparent; then per brick: to be
     * classified in this build */
    unsigned char *clear;
    size_t clear_cap;
    /* per axis: the brick keys (per layer and brick) its copy was built
     * from; the scene's now */
    uint64_t *keys[3], *cur;
    size_t keys_cap[3], nkeys[3], cur_cap;
    int nbk, shift, bdim[3]; /* the brick layout */
    int *jobs, njobs, full;  /* the slices to copy bricks into; all of them */
    /* per axis: the layout its copy was last built in (na, nb, nc, the
     * brick shift; wipe: 1 another now, the copy cleared whole, or 2 the
     * copy new zeros: either way it holds nothing), and per
     * brick and block of 8^3 cells (bnz's order), 1 when the copy may hold
     * a cell of it that is not 0 (what a build clears where the block has
     * nothing to see now; the rest of the copy is 0 already) */
    int layout[3][4], wipe;
    unsigned char *held[3];
    size_t held_cap[3];
    size_t jobs_cap;
    /* the classified bricks (per brick B^3 cells of four half floats, in
     * the volume's order) shared by the three axes, the keys they were
     * classified from (valid: cvalid), the bricks to classify */
    uint64_t *cls, *ckeys;
    size_t cls_cap, ckeys_cap, cnkeys, cjobs_cap;
    int cvalid, *cjobs, ncjobs;
    unsigned char *cok; /* per brick: classified under this scene */
    size_t cok_cap;
    /* per brick, per block of 8^3 cells of its classified copy (micro()'s
     * order): 1 when a cell inside the grid is not transparent */
    unsigned char *bnz;
    size_t bnz_cap;
    uint64_t *ltab; /* per layer, VSV_SW_NTAB classified positions */
    size_t ltab_cap;
    /* one visible layer, no lighting: the classified bricks as entries of
     * its table (2 bytes a cell at micro()'s place; cls unused), read
     * through the table as they are copied into an axis's slices; solo is
     * that layer, -1 otherwise; nzc[i], how many of its first i entries
     * are not transparent */
    uint16_t *pos;
    size_t pos_cap;
    uint32_t nzc[VSV_SW_NTAB + 1];
    int solo;
    /* per thread: sums of four channels over a brick's row */
    double **cacc;
    size_t cacc_cap;
    int nclassified, built_bricks; /* bricks classified in this build, the last */
    double sigma_unit;
    vsv_light light; /* the classification's lighting */
    float scale;     /* the classified copy holds extinction in units of sigma_unit, times scale */
    /* intermediate image (img_stride floats a row), an empty border of one
     * pixel left and top, two right and bottom, and its opaque-pixel links
     * (w + 1 per row, perspective) */
    float *img;
    int *link;
    int *boxes; /* parallel rays: each band's box of pixels with alpha > 0 */
    size_t img_cap, link_cap, boxes_cap;
    /* per thread: a parallel band's group links, or a slice's scanline runs
     * while classifying; a parallel band's planes, or perspective deltas */
    int **scratch;
    float **dscratch;
    size_t scratch_cap, dscratch_cap;
    int max_threads, simd;
    /* the current view (set by begin) */
    const vsv_geo *g;
    const vsv_camera *cam;
    vsv_rays rays;
    float *out, *depth;
    unsigned char *out8; /* or the picture in bytes, row by row (vsv_render_rgba8) */
    const vsv_ground *ground;
    int c, a, b, na, nb, nc, w, h, front, dk;
    double sa, sb, ta, tb, delta, dv[3];
    /* perspective: the eye in voxel coordinates, the reference slice (the one
     * nearest the eye, scale 1) and the world size of a voxel along a, b, c */
    int persp, kref;
    double eye[3], wsz[3];
    double build_seconds;
};

/* n premultiplied float channels to bytes: round(255 v), v clamped to [0, 1]
 * (NaN as 0, halves up); vsv_render_rgba8's rule. */
static inline void vsv_sw_bytes(const float *f, size_t n, unsigned char *o)
{
    size_t i = 0;
#ifdef __SSE2__
    const __m128 k = _mm_set1_ps(255), h = _mm_set1_ps(0.5f), z = _mm_setzero_ps(), one = _mm_set1_ps(1);
    for (; i + 16 <= n; i += 16) { /* sixteen at a time; max, then min, take NaN to 0 */
        __m128i q[4];
        for (int j = 0; j < 4; j++) {
            const __m128 v = _mm_min_ps(_mm_max_ps(_mm_loadu_ps(f + i + 4 * j), z), one);
            q[j] = _mm_cvttps_epi32(_mm_add_ps(_mm_mul_ps(v, k), h));
        }
        _mm_storeu_si128((__m128i *)(o + i),
                         _mm_packus_epi16(_mm_packs_epi32(q[0], q[1]), _mm_packs_epi32(q[2], q[3])));
    }
#endif
    for (; i < n; i++) {
        const float v = f[i] > 0 ? (f[i] < 1 ? f[i] : 1) : 0;
        o[i] = (unsigned char)(v * 255 + 0.5f);
    }
}

/* Grows *p (of *cap elements of elem bytes) to need: 0, or -1 out of memory. */
static inline int vsv_sw_grow(void **p, size_t *cap, size_t need, size_t elem)
{
    if (need <= *cap)
        return 0;
    void *q = realloc(*p, need * elem);
    if (!q)
        return -1;
    *p = q;
    *cap = need;
    return 0;
}
/* The axes of a slice of principal axis c */
static inline int vsv_sw_axis_a(int c) { return (c + 1) % 3; }
static inline int vsv_sw_axis_b(int c) { return (c + 2) % 3; }
/* Checks the classification against the scene for principal axis c and
 * plans the work (vsv_sw_classify.c): 0 or VSV_ENOMEM. */
int vsv_sw_classification_for(vsv_sw *sw, const vsv_scene *sc, int c);

#endif
