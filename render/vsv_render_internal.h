/* vsv_render_internal.h — what the renderers share: the scene's world
 * geometry, the terrain, camera rays, and the shear-warp entry points.
 * Private to render/. */
#ifndef VSV_RENDER_INTERNAL_H
#define VSV_RENDER_INTERNAL_H

#include "vsv_format_internal.h"
#include "vsv_render.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

/* extinction of opacity 1 over one horizontal cell: alpha 0.95 */
#define VSV_SIGMA_PER_CELL 3.0

/* Opacity of a sample: 1 - e^-u = u f(u) with f(u) = (1 - e^-u)/u: below
 * VSV_OPACITY_SMALL (the thin samples of most species) by the first six
 * terms of its series (off by under 5e-8), up to VSV_OPACITY_UMAX read from
 * a table at the nearest entry (off by at most 1.2e-4), 1/u beyond (off by
 * e^-12 = 6e-6): no exponential per sample. */
#define VSV_OPACITY_N 16384
#define VSV_OPACITY_UMAX 12.0f
#define VSV_OPACITY_SMALL 0.25f
extern float vsv_opacity_table[VSV_OPACITY_N + 1];
void vsv_opacity_init(void); /* fills the table once (thread-safe) */
static inline float vsv_opacity_series(float u)
{
    return 1.0f + u * (-1.0f / 2 + u * (1.0f / 6 + u * (-1.0f / 24 + u * (1.0f / 120 + u * (-1.0f / 720)))));
}
static inline float vsv_opacity_per_u(float u)
{
    return u < VSV_OPACITY_SMALL ? vsv_opacity_series(u)
           : u < VSV_OPACITY_UMAX ? vsv_opacity_table[(int)(u * (VSV_OPACITY_N / VSV_OPACITY_UMAX) + 0.5f)]
                                  : 1 / u;
}
/* The raycaster's: the series by fused multiply-adds (one rounding each,
 * as the sixteen-ray loop's FMA instructions: both loops give the same bits). */
static inline float vsv_rc_opacity_per_u(float u)
{
    if (!(u < VSV_OPACITY_SMALL))
        return vsv_opacity_per_u(u);
    float f = -1.0f / 720;
    f = fmaf(u, f, 1.0f / 120);
    f = fmaf(u, f, -1.0f / 24);
    f = fmaf(u, f, 1.0f / 6);
    f = fmaf(u, f, -1.0f / 2);
    return fmaf(u, f, 1.0f);
}

/* Colour and opacity-curve value of one data value, inline (vsv_tf_eval). */
static inline void vsv_tf_lookup(const vsv_tf *tf, float v, float rgba[4])
{
    if (!(v >= tf->lo)) { /* below the range, or no data (NaN) */
        rgba[0] = rgba[1] = rgba[2] = rgba[3] = 0;
        return;
    }
    double x = ((tf->scale == VSV_SCALE_LOG ? log(v) : (double)v) - tf->base) * tf->inv;
    if (x > VSV_TF_LUT - 1)
        x = VSV_TF_LUT - 1;
    /* linear interpolation in the table */
    int i = (int)x;
    if (i >= VSV_TF_LUT - 1)
        i = VSV_TF_LUT - 2;
    const float f = (float)(x - i);
    const float *a = tf->lut[i], *b = tf->lut[i + 1];
    for (int c = 0; c < 4; c++)
        rgba[c] = a[c] + (b[c] - a[c]) * f;
}

/* Largest opacity of a transfer function over the values [lo, hi] (a bound:
 * 0 means every value in there is transparent). */
float vsv_tf_max_opacity(const vsv_tf *tf, float lo, float hi);

/* World geometry of a scene: cell centres at (ox + i dx, oy + j dy, (oz + k dz) E). */
typedef struct vsv_geo {
    double ox, oy, oz, dx, dy, dz, E;
    double idx, idy; /* 1 / dx, 1 / dy */
    double bmin[3], bmax[3];
    int nx, ny, nz;
    const float *terrain;
    double ground_top; /* the highest ground, exaggerated (with a terrain) */
} vsv_geo;

void vsv_scene_geo(const vsv_scene *sc, vsv_geo *g);

/* Native levels at their heights (vsv_native.c): for a scene whose file has
 * per-column heights, *out is the same scene over the volumes resampled
 * onto the even axis of vsv_heights_axis (valid until the next call);
 * otherwise *out is in. */
typedef struct vsv_native {
    const vsv_meta *m;
    vsv_resampler **rs; /* per layer */
    vsv_layer *layers;
    int cap;
    vsv_scene sc;
} vsv_native;
int vsv_native_scene(vsv_native *n, const vsv_scene *in, const vsv_scene **out);
void vsv_native_free(vsv_native *n);
/* Exaggerated terrain height at world (x, y), bilinear between cell centres. */
double vsv_geo_terrain(const vsv_geo *g, double x, double y);
/* Ground colour at (x, y): by height, shaded by slope. */
void vsv_geo_terrain_colour(const vsv_geo *g, double x, double y, float rgb[3]);
/* Slab intersection of a ray with a box: [t0, t1]; 0 if missed. Without
 * branches: the renderer runs it over several rays at once. */
static inline int vsv_box_hit(const double o[3], const double d[3], const double mn[3], const double mx[3], double *t0,
                              double *t1)
{
    double lo = -INFINITY, hi = INFINITY;
    int out = 0;
    for (int a = 0; a < 3; a++) {
        const double inv = 1 / d[a], ta = (mn[a] - o[a]) * inv, tb = (mx[a] - o[a]) * inv;
        const double near = ta > tb ? tb : ta, far = ta > tb ? ta : tb;
        const int flat = d[a] == 0; /* parallel to the slab: in it or not */
        out |= flat & (o[a] < mn[a] || o[a] > mx[a]);
        lo = !flat && near > lo ? near : lo;
        hi = !flat && far < hi ? far : hi;
    }
    *t0 = lo;
    *t1 = hi;
    return !out & (hi >= lo) & (hi > 0);
}
/* Distance along the ray (o, d) where it first meets the ground (the
 * bilinear height field through the cell centres, flat beyond them) between
 * t0 and t1: exact, patch by patch; INFINITY if never. */
double vsv_geo_terrain_hit(const vsv_geo *g, const double o[3], const double d[3], double t0, double t1);
/* A camera's rays: the basis worked out once per frame. */
typedef struct vsv_rays {
    double o[3], f[3], r[3], u[3], kx, ky, cx, cy, w, h;
    int persp;
    int x0, x1, y0, y1; /* the pixels whose rays may meet the scene (the renderer's) */
} vsv_rays;
void vsv_rays_init(vsv_rays *R, const vsv_camera *cam);
/* Ray origin and unit direction of pixel (px, py). */
void vsv_rays_get(const vsv_rays *R, int px, int py, double o[3], double d[3]);
/* The same, for one pixel (works out the basis each call). */
void vsv_pixel_ray(const vsv_camera *cam, int px, int py, double o[3], double d[3]);

/* Where each pixel's ray meets the ground (t, INFINITY when it does not) and
 * the ground's colour there: worked out once per camera and scene geometry
 * (the renderer keeps it while only the time step or the species change). */
typedef struct vsv_ground {
    float t;
    float rgb[3];
} vsv_ground;

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

/* ------------------------------------------------------------ raycaster */

/* The raycaster's sampling copy of a layer's volume: every brick with one
 * more cell along each axis (the first cells of the bricks after it; past
 * the grid, its last cell again), so that the eight cells of any trilinear
 * sample lie in one brick of the copy: (brick + 1)^3 floats, cell (i, j, k)
 * of the brick at i + e j + e^2 k with e = brick + 1 (vsv_rc_frame ey, ez).
 * Bricks whose copy holds nothing but the empty value share one. Built
 * brick by brick on the renderer's threads when the volume's generation
 * (vsv_volume.gen: a load) differs from the copy's, kept across frames. */
typedef const float *const *vsv_rc_cells;
/* Fills brick b's sampling copy into dst ((brick + 1)^3 floats). */
void vsv_rc_copy_fill(const vsv_volume *v, int b, float *dst);

/* A visible layer as the raycaster reads it, set up once per frame. */
typedef struct vsv_rc_layer {
    const vsv_volume *vol;
    vsv_rc_cells cells;         /* per brick: its sampling copy */
    const float (*lut)[4];      /* the transfer function's table */
    float lo, inv, off;         /* table position = (value or ln value) * inv + off */
    int log;
    float sigma;                /* extinction per world unit of curve value 1 */
    const unsigned char *clear; /* per brick: transparent around it (skipping) */
} vsv_rc_layer;

/* What every ray of a frame reads: the visible layers and their common grid. */
typedef struct vsv_rc_frame {
    const vsv_rc_layer *layer;
    int nlayers;
    const unsigned char *skip; /* per brick: every layer clear; NULL: no skipping.
                                  Four readable bytes past the end (for gathers). */
    float hi[3];               /* the largest cell coordinate per axis */
    int last[3];               /* the largest lower corner of a trilinear sample */
    int shift, mask, brick, bx, bxy;
    int ey, ez;                /* the sampling copy's strides: brick + 1, (brick + 1)^2 */
    double st, inv_st;         /* the step in world units, and 1 / st */
    double inv_cell[3];        /* 1 / cell edge (exaggerated in z), world units */
} vsv_rc_frame;

/* One ray through the volume: sample n (0 <= n < ns) sits at world distance
 * ts + n st, at cell coordinates p + n dp. */
typedef struct vsv_rc_ray {
    float p[3], dp[3];
    int ns;
    double ts, st;
} vsv_rc_ray;

/* The first sample of a ray at or past the far side of the brick of cell ci
 * (one before it at most: the caller tests that sample again), for skipping. */
static inline int vsv_rc_skip_to(const vsv_rc_frame *F, const vsv_rc_ray *ray, const int ci[3])
{
    int next = ray->ns;
    for (int a = 0; a < 3; a++) {
        if (ray->dp[a] == 0)
            continue;
        const int b = ci[a] >> F->shift;
        const float edge = (float)(ray->dp[a] > 0 ? b + 1 : b) * F->brick;
        const float k = (edge - ray->p[a]) / ray->dp[a];
        const int kn = k < (float)ray->ns ? (int)k : ray->ns;
        next = kn < next ? kn : next;
    }
    return next;
}

/* Trilinear interpolation of the eight cells around a sample, in the order
 * c000 c100 c010 c110 c001 c101 c011 c111 (c100: one along x; the order of
 * operations both raycaster loops keep). */
static inline float vsv_rc_lerp(float a, float b, float f) { return fmaf(b - a, f, a); }
static inline float vsv_rc_trilinear(const float c[8], float fu, float fv, float fw)
{
    const float a0 = vsv_rc_lerp(c[0], c[1], fu), a1 = vsv_rc_lerp(c[2], c[3], fu);
    const float a2 = vsv_rc_lerp(c[4], c[5], fu), a3 = vsv_rc_lerp(c[6], c[7], fu);
    return vsv_rc_lerp(vsv_rc_lerp(a0, a1, fv), vsv_rc_lerp(a2, a3, fv), fw);
}

/* VSV_RC_LANES rays at once: T (transmittance), acc (colour) and depth, which
 * start at 1, 0, INFINITY, are composited front to back through every ray's
 * samples, as the one-ray loop does. A ray with ns 0 is left as it is. One
 * source, two builds: vsv_raycast16 for AVX2 + FMA, vsv_raycast16_avx512 for
 * AVX-512F; call each only on a CPU that has them. */
#define VSV_RC_LANES 16
typedef void vsv_rc_kernel(const vsv_rc_frame *F, const vsv_rc_ray ray[VSV_RC_LANES], float T[VSV_RC_LANES],
                           float acc[3][VSV_RC_LANES], float depth[VSV_RC_LANES]);
vsv_rc_kernel vsv_raycast16, vsv_raycast16_avx512;

#endif
