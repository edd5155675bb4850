/* vsv_advect_traj.c — the trajectories of vsv_advect (see vsv_advect.c
 * for the scheme): midpoint steps of at most a cell through the winds
 * interpolated in space and time, and the coarse grid they are traced on.
 *
 * Coarse grid: a frame traces trajectories from every second column of
 * every second row (and the last of each) on every level, a quarter of the
 * cells, and the cells between take the bilinear mean of the 4 around
 * them. Tracing was the largest part of advect's time once the zero masks
 * had cut sampling (30 %, perf on the MM5 run); this cuts the whole by a
 * fifth. The winds of a model vary over tens of kilometres, so the
 * displacement field varies little between neighbouring points (a uniform
 * wind's, or one sheared with height only, is reproduced exactly). Where a
 * coarse point's trajectory left the grid or the point has no data (below
 * the ground), the cells around it are traced themselves, so edges and
 * terrain are as before; the coarse points are their own cells' exact
 * displacements. The cost, measured (bench/RESULTS.md): rebuilding the MM5
 * run's held-out 02:00, vapour's RMSE 2.49e-05 -> 2.53e-05 (0.87 -> 0.88 of
 * linear's), the hydrometeors' within 0.3 %. */
#include "vsv_advect_internal.h"

#include <math.h>

/* The wind at point p and interval time s (0 at the start, 1 at the end),
 * in cells per interval (the stored winds are already in those units). A
 * cell's 8 floats hold both ends, so the trilinear sum is 8 vector
 * multiply-adds. */
static inline void wind_at(const vsv_advect *a, const float p[3], float s, float k[3])
{
    size_t off[8];
    f8 wt, acc = {0};
    corners(a, p, off, &wt);
    for (int c = 0; c < 8; c++) {
        f8 w;
        memcpy(&w, a->wind + off[c] * 8, sizeof w);
        acc += wt[c] * w;
    }
    for (int d = 0; d < 3; d++)
        k[d] = acc[d] + s * (acc[d + 4] - acc[d]);
}

static inline float fmax3abs(const float k[3])
{
    const float x = fabsf(k[0]), y = fabsf(k[1]), z = fabsf(k[2]);
    const float m = x > y ? x : y;
    return m > z ? m : z;
}

/* Moves p along the wind from interval time s over dur (> 0) of the
 * interval, forward (dir 1) or back (dir -1); k1 is the wind at p and s.
 * Returns 0, or 1 when the trajectory left the grid sideways (the air came
 * from, or goes to, outside it: nothing there is known), and 1 too when it
 * would cross more cells than 16 times across the grid within the interval
 * or meets a wind that is not finite: the row of a latitude-longitude grid
 * at a pole, whose cells have no width, makes any wind there infinite or
 * near it in cells, and its steps of at most a cell would never end. */
static int trajectory(const vsv_advect *a, float p[3], const float k1_in[3], float s, float dur, float dir)
{
    const float hi[3] = {(float)(a->nx - 1), (float)(a->ny - 1), (float)(a->nz - 1)};
    const int most = 16 * (a->nx + a->ny + a->nz);
    float k1[3] = {k1_in[0], k1_in[1], k1_in[2]};
    for (int steps = 0; dur > 0; steps++) {
        float k2[3], m[3];
        if (steps)
            wind_at(a, p, s, k1);
        const float vm = fmax3abs(k1);
        if (steps == most || !(vm < INFINITY))
            return 1;
        const float h = vm * dur > 1 ? 1 / vm : dur; /* at most one cell a step */
        for (int d = 0; d < 3; d++)
            m[d] = p[d] + dir * k1[d] * (h / 2);
        wind_at(a, m, s + dir * h / 2, k2);
        for (int d = 0; d < 3; d++) {
            const float q = p[d] + dir * k2[d] * h;
            if (d < 2 && (q < 0 || q > hi[d]) && hi[d] > 0)
                return 1;
            p[d] = q < 0 ? 0 : q > hi[d] ? hi[d] : q;
        }
        s += dir * h;
        dur = h < dur ? dur - h : 0;
    }
    return 0;
}

/* The displacements of the air at cell (i, j, k) at interval time s: db to
 * where it was at the start, df to where it will be at the end (cells; 0
 * for an end whose trajectory left the grid sideways). See the header. */
int vsv_advect_trace(const vsv_advect *a, int i, int j, int k, float s, float db[3], float df[3])
{
    const size_t c = (size_t)k * a->plane + (size_t)j * a->nx + i;
    /* both trajectories start from the cell's centre, where the wind is the
     * cell's own (no trilinear sum) */
    const float *w = a->wind + c * 8;
    const float k1[3] = {w[0] + s * (w[4] - w[0]), w[1] + s * (w[5] - w[1]), w[2] + s * (w[6] - w[2])};
    const float x[3] = {(float)i, (float)j, (float)k};
    float pb[3] = {x[0], x[1], x[2]}, pf[3] = {x[0], x[1], x[2]};
    int left = 0;
    if (s > 0 && trajectory(a, pb, k1, s, s, -1))
        memcpy(pb, x, sizeof pb), left |= C_LEFT_BACK;
    if (s < 1 && trajectory(a, pf, k1, s, 1 - s, 1))
        memcpy(pf, x, sizeof pf), left |= C_LEFT_ON;
    for (int d = 0; d < 3; d++)
        db[d] = pb[d] - x[d], df[d] = pf[d] - x[d];
    return left;
}

/* Coarse index of cell i along an axis of n cells (points at 0, COARSE,
 * 2 * COARSE, ... and n - 1): the point at or below it, and the weight f of the next. */
static inline int coarse_axis(int i, int n, float *f)
{
    const int c = i / COARSE, x0 = COARSE * c;
    if (x0 == i) {
        *f = 0;
        return c;
    }
    const int x1 = x0 + COARSE < n - 1 ? x0 + COARSE : n - 1;
    *f = (float)(i - x0) / (float)(x1 - x0);
    return c;
}

void vsv_advect_coarse_row(const vsv_advect *a, int r, float s, int ns, const float *al)
{
    const int cj = r % a->cy, k = r / a->cy;
    const int j = COARSE * cj < a->ny - 1 ? COARSE * cj : a->ny - 1;
    const size_t c0 = (size_t)k * a->plane + (size_t)j * a->nx;
    float *d = a->coarse + (size_t)r * a->cx * 6;
    unsigned char *fl = a->cflag + (size_t)r * a->cx;
    for (int ci = 0; ci < a->cx; ci++) {
        const int i = COARSE * ci < a->nx - 1 ? COARSE * ci : a->nx - 1;
        /* only where some moving species has data at both ends (not below
         * the ground) */
        int need = 0;
        for (int v = 0; v < ns && !need; v++)
            need = al[v] > 0 && a->f0[v][c0 + i] == a->f0[v][c0 + i] && a->f1[v][c0 + i] == a->f1[v][c0 + i];
        fl[ci] = need ? (unsigned char)vsv_advect_trace(a, i, j, k, s, d + 6 * ci, d + 6 * ci + 3) : C_NONE;
    }
}

void vsv_advect_cell(const vsv_advect *a, int i, int j, int k, float s, float d[6])
{
    float fx, fy;
    const int ci = coarse_axis(i, a->nx, &fx), cj = coarse_axis(j, a->ny, &fy);
    const int ci1 = ci + (fx > 0), cj1 = cj + (fy > 0);
    const size_t r0 = ((size_t)k * a->cy + cj) * a->cx, r1 = ((size_t)k * a->cy + cj1) * a->cx;
    if (a->cflag[r0 + ci] | a->cflag[r0 + ci1] | a->cflag[r1 + ci] | a->cflag[r1 + ci1]) {
        vsv_advect_trace(a, i, j, k, s, d, d + 3);
        return;
    }
    const float *p00 = a->coarse + (r0 + ci) * 6, *p10 = a->coarse + (r0 + ci1) * 6;
    const float *p01 = a->coarse + (r1 + ci) * 6, *p11 = a->coarse + (r1 + ci1) * 6;
    for (int c = 0; c < 6; c++) {
        const float lo = p00[c] + fx * (p10[c] - p00[c]), hi = p01[c] + fx * (p11[c] - p01[c]);
        d[c] = lo + fy * (hi - lo);
    }
}
