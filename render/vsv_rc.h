/* vsv_rc.h — the raycaster: its sampling copies, the frame and rays every
 * sample loop reads, and the sixteen-ray kernels (vsv_raycast.c,
 * vsv_sampling.c, vsv_raycast_simd.c). Private to render/. */
#ifndef VSV_RC_H
#define VSV_RC_H

#include "vsv_geo.h"
#include "vsv_light.h"
#include "vsv_tf_internal.h"

#include <math.h>
#include <stdint.h>

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
/* Whether brick b's sampling copy holds data: one of the eight bricks whose
 * cells it copies has some. */
int vsv_rc_copy_has_data(const vsv_volume *v, int b);
/* A layer's sampling copy as the renderer keeps it across frames. */
typedef struct vsv_rc_copy {
    const vsv_volume *vol;
    uint64_t gen;
    float *store; /* the bricks whose copy holds data, then the shared empty one */
    size_t store_cap;
    float *empty;
    const float **cells; /* per brick */
    int cells_cap;
    float *mm; /* per block (VSV_RC_BLOCK): the smallest and largest
                  value of its cells and the next one along each
                  axis, which its trilinear samples read (NaN left
                  out: a sample touching one is no data) */
    size_t mm_cap;
} vsv_rc_copy;
/* Blocks of VSV_RC_BLOCK^3 cells, for skipping: block (bi, bj, bk) holds
 * the samples whose lower cell (vsv_rc_frame last-clamped) is in it; their
 * count per axis is (last >> VSV_RC_BSHIFT) + 1. */
#define VSV_RC_BSHIFT 2
#define VSV_RC_BLOCK (1 << VSV_RC_BSHIFT)
#define VSV_RC_FINE 0x80 /* vsv_rc_frame.skip: a block shown that has clear cells */
_Static_assert(VSV_RC_BLOCK *VSV_RC_BLOCK *VSV_RC_BLOCK == 64, "vsv_rc_frame.fine: 64 bits a block");
static inline void vsv_rc_block_dims(const vsv_volume *v, int nb[3])
{
    const int n[3] = {v->nx, v->ny, v->nz};
    for (int a = 0; a < 3; a++)
        nb[a] = ((n[a] > 1 ? n[a] - 2 : 0) >> VSV_RC_BSHIFT) + 1;
}
/* The min/max (c->mm) of the blocks of brick b of the copy c. */
void vsv_rc_copy_minmax(const vsv_rc_copy *c, int b);
/* Sets c up to hold v's sampling copy: room for the bricks whose copy holds
 * data and for the shared empty brick, which is filled here (the others by
 * vsv_rc_copy_fill); -1 when out of memory. */
int vsv_rc_copy_prepare(vsv_rc_copy *c, const vsv_volume *v);

/* A visible layer as the raycaster reads it, set up once per frame. */
typedef struct vsv_rc_layer {
    const vsv_volume *vol;
    vsv_rc_cells cells;    /* per brick: its sampling copy */
    const float (*lut)[4]; /* the transfer function's table */
    float lo, inv, off;    /* table position = (value or ln value) * inv + off */
    int log;
    float sigma;                /* extinction per world unit of curve value 1 */
    const float *mm;            /* per block: its samples' min and max (vsv_rc_copy.mm) */
    const unsigned char *clear; /* per block: every sample in it transparent */
    float inv_span;             /* lighting: vsv_light_inv_span of its transfer function */
} vsv_rc_layer;

/* The camera's rays in cell coordinates, a ray's distances counted in
 * steps (vsv_rc_frame st): pixel (px, py) is at screen position
 * sx = px sxk + sx0, sy = py syk + sy0 (vsv_rays_get's). In perspective, its
 * ray leaves o with a step dp = (sx r + (sy u + f)) / sqrt(sx^2 + (sy^2 + 1))
 * (f, r, u: the camera's orthonormal axes, a step long, in cells); in
 * parallel projection it leaves sx r + (sy u + o) with the step f. Both
 * ray set-ups, the one-ray (vsv_rc_ray_setup) and the sixteen-ray one,
 * work it out in single precision with the same operations in the same
 * order, so their rays have the same bits. */
typedef struct vsv_rc_cam {
    float o[3], f[3], r[3], u[3];
    float sx0, sxk, sy0, syk;
    float bmin[3], bmax[3]; /* the scene's box */
    float snear, sfar;      /* the camera's near and far distances */
    int persp;
} vsv_rc_cam;

/* What every ray of a frame reads: the visible layers and their common grid. */
typedef struct vsv_rc_frame {
    const vsv_rc_layer *layer;
    int nlayers;
    const unsigned char *skip; /* per block: 0 where a sample may be seen; d > 0:
                                  every block within d - 1 blocks (on each
                                  axis) is clear in every layer, so a ray leaps
                                  out of that box; VSV_RC_FINE added to the 0
                                  of a block with clear cells (fine). NULL: no
                                  skipping. Four readable bytes past the end
                                  (for gathers). */
    const uint32_t *fine;      /* per block, two words: bit (i & 3) + 4 (j & 3) +
                                  16 (k & 3) of word 2 b + bit / 32 is set where
                                  every sample whose lower cell is (i, j, k) is
                                  transparent in every layer (block b at skip
                                  distance 0); with skip, else NULL */
    int layer_clear;           /* several layers: test each one's clear flags */
    int nbx, nbxy;             /* blocks along x, in an xy plane */
    float hi[3];               /* the largest cell coordinate per axis */
    int last[3];               /* the largest lower corner of a trilinear sample */
    int shift, mask, brick, bx, bxy;
    int ey, ez;         /* the sampling copy's strides: brick + 1, (brick + 1)^2 */
    double st, inv_st;  /* the step in world units, and 1 / st */
    float term;         /* early ray termination: T below this */
    double inv_cell[3]; /* 1 / cell edge (exaggerated in z), world units */
    vsv_light light;    /* lit frames march one ray at a time */
    vsv_rc_cam cam;     /* the camera's rays, in cell coordinates */
} vsv_rc_frame;

/* One ray through the volume: sample n (0 <= n < ns) sits at cell
 * coordinates p + n dp, at world distance (ts + n) st. */
typedef struct vsv_rc_ray {
    float p[3], dp[3], inv_dp[3]; /* inv_dp: 1 / dp, for leaps and the box */
    int ns;
    float ts;
    float nl, wl; /* the last sample: where (in steps from ts) and its step's length (in steps) */
} vsv_rc_ray;

/* The ray of the pixel at screen position (sx, sy) (vsv_rc_cam), ending at
 * s_hit steps (a surface; INFINITY: none): its samples inside the scene's
 * box and the camera's near and far distances, the first half a step in
 * (ns 0 where it has none). The sixteen-ray kernels do the same operations. */
static inline void vsv_rc_ray_setup(const vsv_rc_cam *C, float sx, float sy, float s_hit, vsv_rc_ray *ray)
{
    float o[3], dp[3];
    if (C->persp) {
        const float k = 1 / sqrtf(fmaf(sx, sx, fmaf(sy, sy, 1)));
        for (int a = 0; a < 3; a++) {
            o[a] = C->o[a];
            dp[a] = fmaf(sx, C->r[a], fmaf(sy, C->u[a], C->f[a])) * k;
        }
    } else {
        for (int a = 0; a < 3; a++) {
            o[a] = fmaf(sx, C->r[a], fmaf(sy, C->u[a], C->o[a]));
            dp[a] = C->f[a];
        }
    }
    float lo = -INFINITY, hi = INFINITY;
    int out = 0;
    for (int a = 0; a < 3; a++) { /* the slabs of the box, as vsv_box_hit */
        const float inv = 1 / dp[a], s0 = (C->bmin[a] - o[a]) * inv, s1 = (C->bmax[a] - o[a]) * inv;
        const float near = s0 < s1 ? s0 : s1, far = s0 > s1 ? s0 : s1;
        const int flat = dp[a] == 0; /* parallel to the slab: in it or not */
        out |= flat & (o[a] < C->bmin[a] || o[a] > C->bmax[a]);
        lo = !flat && near > lo ? near : lo;
        hi = !flat && far < hi ? far : hi;
        ray->inv_dp[a] = inv;
    }
    const int hit = !out & (hi >= lo) & (hi > 0);
    lo = lo < C->snear ? C->snear : lo;
    hi = hi > C->sfar ? C->sfar : hi;
    /* a sample in the middle of every whole step from lo, and the last in the
     * middle of the part step left, weighted by its length: opacity grows
     * with the path, not by whole steps (a slab one step thick showed its
     * sample planes as sheets) */
    const float ts = lo + 0.5f, send = hi < s_hit ? hi : s_hit, seg = send - lo;
    ray->ns = hit && seg > 0 ? (int)ceilf(seg < 1e8f ? seg : 1e8f) : 0;
    ray->ts = ts;
    const float wl = seg - (float)(ray->ns - 1);
    ray->wl = wl < 1 ? wl : 1;
    ray->nl = fmaf(0.5f, ray->wl, (float)(ray->ns - 1) - 0.5f);
    for (int a = 0; a < 3; a++) {
        ray->p[a] = fmaf(ts, dp[a], o[a]);
        ray->dp[a] = dp[a];
    }
}

/* Sample n's cell (i, j, k) of ray: the lower corner of its trilinear
 * (clamped into the grid), as both raycaster loops find it. */
static inline void vsv_rc_cell(const vsv_rc_frame *F, const vsv_rc_ray *ray, int n, float c[3], int ci[3])
{
    const float nf = n == ray->ns - 1 ? ray->nl : (float)n;
    for (int a = 0; a < 3; a++) {
        c[a] = fmaf(nf, ray->dp[a], ray->p[a]);
        c[a] = c[a] > 0 ? (c[a] < F->hi[a] ? c[a] : F->hi[a]) : 0;
        ci[a] = (int)c[a];
        ci[a] = ci[a] < F->last[a] ? ci[a] : F->last[a];
    }
}

/* The leap of a ray whose sample n, in cell ci, lies in a box of clear
 * cells: the boxes of 2^shift cells a side within d - 1 boxes of ci's (the
 * blocks at skip distance d: shift VSV_RC_BSHIFT; a clear cell of the fine
 * bits: shift 0, d 1). Returns the next sample to test (n + 1 at least):
 * k, the last sample before the box's far side (the far side along an axis
 * where the clamped cell cannot reach it does not count), or k + 1 where
 * sample k's cell is still in the box (worked out as the loops do: every
 * sample from n to k then is, the cells along a ray being monotonic). */
static inline int vsv_rc_leap(const vsv_rc_frame *F, const vsv_rc_ray *ray, int n, const int ci[3], int d, int shift)
{
    const float *p = ray->p, *dp = ray->dp, *inv_dp = ray->inv_dp;
    float k = (float)ray->ns;
    int lo[3], hi[3];
    for (int a = 0; a < 3; a++) {
        const int b = ci[a] >> shift;
        const int up = (b + d) << shift, down = (b - d + 1) * (1 << shift);
        const int never = dp[a] > 0 ? up > F->last[a] : dp[a] < 0 ? down <= 0 : 1;
        const float ka = ((float)(dp[a] > 0 ? up : down) - p[a]) * inv_dp[a];
        k = !never && ka < k ? ka : k;
        lo[a] = down;
        hi[a] = up;
    }
    int kn = k > (float)n ? (int)k : n; /* (never converts a value out of range) */
    float c[3];
    int ck[3];
    vsv_rc_cell(F, ray, kn, c, ck);
    kn += ck[0] >= lo[0] && ck[0] < hi[0] && ck[1] >= lo[1] && ck[1] < hi[1] && ck[2] >= lo[2] && ck[2] < hi[2];
    return kn > n + 1 ? kn : n + 1;
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

/* VSV_RC_LANES rays at once, the pixels px .. px + 15 of row py (screen
 * position sy) whose bits are set in live: each lane's ray set up as
 * vsv_rc_ray_setup does (s_hit: where it ends on a surface, in steps), then
 * T (transmittance), acc (colour) and depth, which start at 1, 0, INFINITY,
 * composited front to back through every ray's samples, as the one-ray loop
 * does. A lane whose ray has no samples is left as it is. One source, two
 * builds: vsv_raycast16 for AVX2 + FMA, vsv_raycast16_avx512 for AVX-512F;
 * call each only on a CPU that has them. */
#define VSV_RC_LANES 16
typedef void vsv_rc_kernel(const vsv_rc_frame *F, int px, float sy, unsigned live, const float s_hit[VSV_RC_LANES],
                           float T[VSV_RC_LANES], float acc[3][VSV_RC_LANES], float depth[VSV_RC_LANES]);
vsv_rc_kernel vsv_raycast16, vsv_raycast16_avx512;

#endif
