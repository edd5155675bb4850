/* vsv_advect_internal.h — the state of vsv_advect and the index
 * arithmetic its two files share: vsv_advect.c (set-up, the fit, frames,
 * threads) and vsv_advect_traj.c (trajectories). Private to convert/. */
#ifndef VSV_ADVECT_INTERNAL_H
#define VSV_ADVECT_INTERNAL_H

#include "vsv_advect.h"

#include <stdint.h>
#include <string.h>

/* Eight floats as one value: GCC's and Clang's vector extension, two SSE
 * registers (or one AVX register) per operation. */
typedef float f8 __attribute__((vector_size(32)));

/* The fit's candidate scales: 0, 1/8, ..., 10/8 of the wind's displacement. */
enum { NCAND = 11, FIT_STRIDE = 3, MAXTHREADS = 64, MAXVARS = 256 };
#define CAND_STEP 0.125f

struct vsv_advect {
    int nx, ny, nz, threads, vertical, nvars;
    size_t plane, cells;
    size_t stride[3]; /* index step per axis (0 for an axis of one cell) */
    float *sx, *sy;   /* per column: cells per metre along x, y */
    float *sz;        /* per level: cells per metre upward (0: no vertical motion) */
    float *wind;      /* per cell 8 floats: u v w 0 at the start, u v w 0 at the end,
                       * in cells per span seconds */
    double span;
    float scale;                        /* > 0: every species moves with the wind times this; 0: fitted */
    int band, nband;                    /* the fit's bands: of band levels, nband of them */
    float *alpha;                       /* the fitted scales: nvars * nband (band fastest) */
    int fitrows;                        /* rows the fit visits: every FIT_STRIDE-th of each level */
    double *acc;                        /* per fit row: nvars * NCAND squared mismatches (summed in
                                         * row order afterwards, so the fit does not depend on
                                         * which thread did which row) */
    double *sums;                       /* nvars * nband * NCAND: the bands' sums */
    float *scratch;                     /* per thread: one row of displacements, 6 floats a cell */
    int ns;                             /* species of the interval's outputs */
    const float *const *f0, *const *f1; /* its outputs (borrowed: vsv_advect_outputs) */
    size_t zrow;                        /* words of a row of a zero mask */
    size_t zplane;                      /* words of a zero mask: ny * nz rows */
    size_t zcap;                        /* words allocated in zero */
    uint64_t *zero;                     /* per species v and end e, the mask at (2 * v + e) * zplane:
                                         * bit i of row (j, k) set when the 8 cells a sample based at
                                         * cell (i, j, k) reads are all +0 (see carried) */
    int *ext;                           /* per species v and end e, per row r (j + k * ny): the first and
                                         * last column not +0, at ext[((2 * v + e) * ny * nz + r) * 2]
                                         * (first > last for a row all +0) */
    int cx, cy;                         /* the coarse trajectory grid: columns and rows (vsv_advect_traj.c) */
    float *coarse;                      /* its displacements, 6 floats a point (back, then on),
                                         * cx * cy * nz points */
    unsigned char *cflag;               /* per coarse point: C_LEFT_* or C_NONE (not computed) */
};

/* The coarse trajectory grid's step: every COARSE-th column and row. */
enum { COARSE = 2 };

/* Why a coarse point's displacements may not be interpolated: a
 * trajectory left the grid sideways, or the point has no data. */
enum { C_LEFT_BACK = 1, C_LEFT_ON = 2, C_NONE = 4 };

/* Index of the lower cell and the weight of the upper one along an axis of
 * n cells, for position p clamped to [0, n-1]. */
static inline int axis(float p, int n, float *f)
{
    /* without branches (a trajectory's samples wander unpredictably):
     * q is p clamped, NaN to 0; at the top the lower cell is n - 2, f 1 */
    const float top = (float)(n - 1);
    const float q = p > 0 ? (p < top ? p : top) : 0;
    int i = (int)q;
    i -= i == n - 1 && n > 1;
    *f = q - (float)i;
    return i;
}

/* The 8 cells from cell (i, j, k) (axis's lower cells) and their
 * trilinear weights at fractions fx, fy, fz. */
static inline void corners_at(const vsv_advect *a, int i, int j, int k, float fx, float fy, float fz, size_t off[8],
                              f8 *wt)
{
    const size_t base = (size_t)k * a->plane + (size_t)j * a->nx + (size_t)i;
    const size_t sx = a->stride[0], sy = a->stride[1], sz = a->stride[2];
    const float gx = 1 - fx, gy = 1 - fy, gz = 1 - fz;
    off[0] = base, off[1] = base + sx, off[2] = base + sy, off[3] = base + sy + sx;
    for (int c = 0; c < 4; c++)
        off[c + 4] = off[c] + sz;
    const f8 w = {gx * gy * gz, fx * gy * gz, gx * fy * gz, fx * fy * gz,
                  gx * gy * fz, fx * gy * fz, gx * fy * fz, fx * fy * fz};
    *wt = w;
}

/* The 8 cells around point p and their trilinear weights. */
static inline void corners(const vsv_advect *a, const float p[3], size_t off[8], f8 *wt)
{
    float fx, fy, fz;
    const int i = axis(p[0], a->nx, &fx), j = axis(p[1], a->ny, &fy), k = axis(p[2], a->nz, &fz);
    corners_at(a, i, j, k, fx, fy, fz, off, wt);
}

/* The displacements of the air at cell (i, j, k) at interval time s,
 * traced from that cell: db to where it was at the start, df to where it
 * will be at the end (cells; 0 for an end whose trajectory left the grid
 * sideways). Returns 0, or which left: C_LEFT_BACK, C_LEFT_ON or both. */
int vsv_advect_trace(const vsv_advect *a, int i, int j, int k, float s, float db[3], float df[3]);
/* Row r (cj + k * cy) of the coarse trajectory grid at interval time s:
 * every point traced where some species of al (ns scales of level k) > 0
 * has data at both ends, C_NONE elsewhere. */
void vsv_advect_coarse_row(const vsv_advect *a, int r, float s, int ns, const float *al);
/* Cell (i, j, k)'s displacements at interval time s, 6 floats into d (db,
 * then df): bilinear between the 4 coarse points around it when they were
 * all traced without leaving the grid, else traced from the cell. */
void vsv_advect_cell(const vsv_advect *a, int i, int j, int k, float s, float d[6]);

#endif
