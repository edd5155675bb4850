/* vsv_advect.c — see vsv_advect.h. The scheme, and why:
 *
 * Trajectories run in the grid's index space, so sampling is plain
 * trilinear. Winds are turned once into cells per second: u and v are
 * along the grid's axes (MM5, WRF and CAMx winds are grid-relative), and a
 * metre on the earth is m/dx cells of the map, m the projection's scale
 * factor at the column (computed from the projection: it is MM5's MAPFACCR,
 * WRF's MAPFAC_M); w is divided by the local level spacing.
 *
 * Integration: explicit midpoint (RK2) with the wind interpolated linearly
 * in time between the two outputs, sub-stepped per trajectory so that a
 * step moves at most one cell along any axis at the wind where it starts.
 * Second order at two wind samples a step (Euler's first-order error would
 * bend every curved path outward by about half a cell an hour at jet
 * speeds); the one-cell limit keeps the midpoint inside the cells whose
 * winds the trilinear sample sees, and costs nothing in calm air, where
 * a trajectory takes one step. Trajectories start from every second
 * column and row only, the cells between interpolated (vsv_advect_traj.c).
 * A uniform wind is followed exactly (up to rounding), a calm cell does
 * not move at all, so advection in a calm reproduces linear interpolation
 * bit for bit.
 *
 * Values: trilinear from the 8 cells around the end point, cells without
 * data (NaN, below ground) left out and the weights renormalised, the
 * result clamped to the range of those cells — no new maxima, no
 * negative concentrations. Not mass-conserving (nor is linear
 * interpolation); the original outputs are never touched. A trajectory
 * that leaves the grid sideways met air nobody knows: that end takes the
 * cell's own value, as linear interpolation would.
 *
 * How far: clouds and moisture patterns travel more slowly than the air
 * blowing through them (they form downwind and decay upwind; the MM5 run's
 * vapour follows about 0.8 of the air's displacement, bench/RESULTS.md). So
 * each species, in each band of levels, moves by alpha times its
 * trajectories' displacements, alpha fitted per interval as radar
 * hydrology's advection correction fits its motion: of 0, 1/8, ..., 5/4 the
 * one under which the earlier output carried to the later time matches the
 * later output, and the later carried back the earlier, best (least
 * squares over every third column each way; per-row sums added in row
 * order, so threads do not change the result). alpha 0 is linear
 * interpolation's arithmetic; in a frame alpha is linear in height between
 * the bands' centres. A fixed scale (1: the air's displacement, --interp
 * wind) skips the fit.
 *
 * Zeros: most of a hydrometeor's grid is +0 (86-93 % of the cells of the
 * MM5 run's CLW, RNW, ICE and SNOW), so once per interval a bit mask per
 * species and end marks the cells whose 8-cell sample block is all +0, and
 * such samples are answered +0 without reading them — the same bits as
 * sampling (see carried); a quarter of advect's CPU time on the MM5 run.
 * Per row the first and last column not +0 are noted too, so that a row
 * whose samples stay within REACH rows and levels answers those that fall
 * outside its neighbours' columns without finding their cell (zero_reach;
 * the fit skips such cells whole): a fifth of what remained.
 *
 * Threads: rows of the output frame are handed out through an atomic
 * counter to threads started per frame; nothing is allocated per cell. */
#include "vsv_advect_internal.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* Earth distance (m) between two points on a sphere of radius r. */
static double great_circle(double lat1, double lon1, double lat2, double lon2, double r)
{
    const double d = M_PI / 180;
    const double a = sin((lat2 - lat1) * d / 2), b = sin((lon2 - lon1) * d / 2);
    const double h = a * a + cos(lat1 * d) * cos(lat2 * d) * b * b;
    return 2 * r * asin(sqrt(h < 1 ? h : 1));
}

/* Cells per metre along x and y at the centre of column (i, j): a short
 * step of the map measured on the earth. Without a projection the map units
 * are metres. */
static void column_scale(const vsv_meta *g, int i, int j, float *sx, float *sy)
{
    const double x = g->origin[0] + i * g->spacing[0], y = g->origin[1] + j * g->spacing[1];
    double mx = 1, my = 1; /* map units per metre on the earth */
    if (g->proj.kind != VSV_PROJ_NONE) {
        const double r = g->proj.radius > 0 ? g->proj.radius : 6370000;
        const double hx = g->spacing[0] * 0.01, hy = g->spacing[1] * 0.01;
        double la, lo, la2, lo2, la3, lo3;
        if (!vsv_proj_inverse(&g->proj, x, y, &la, &lo) && !vsv_proj_inverse(&g->proj, x + hx, y, &la2, &lo2) &&
            !vsv_proj_inverse(&g->proj, x, y + hy, &la3, &lo3)) {
            const double dx = great_circle(la, lo, la2, lo2, r), dy = great_circle(la, lo, la3, lo3, r);
            if (dx > 0 && dy > 0) {
                mx = hx / dx;
                my = hy / dy;
            }
        }
    }
    *sx = (float)(mx / g->spacing[0]);
    *sy = (float)(my / g->spacing[1]);
}

int vsv_advect_create(const vsv_meta *g, int threads, vsv_advect **out)
{
    vsv_advect *a = *out = calloc(1, sizeof *a);
    if (!a)
        return VSV_ENOMEM;
    a->nx = g->nx;
    a->ny = g->ny;
    a->nz = g->nz;
    a->nvars = g->nvars > 0 ? g->nvars : 1;
    a->threads = threads > 0 ? threads : vsv_ncpus();
    if (a->threads > MAXTHREADS)
        a->threads = MAXTHREADS;
    a->plane = (size_t)g->nx * g->ny;
    a->cells = a->plane * g->nz;
    a->stride[0] = g->nx > 1 ? 1 : 0;
    a->stride[1] = g->ny > 1 ? (size_t)g->nx : 0;
    a->stride[2] = g->nz > 1 ? a->plane : 0;
    a->zrow = ((size_t)g->nx + 63) / 64;
    a->zplane = a->zrow * g->ny * g->nz;
    a->cx = (g->nx - 1 + COARSE - 1) / COARSE + 1;
    a->cy = (g->ny - 1 + COARSE - 1) / COARSE + 1;
    const size_t ncoarse = (size_t)a->cx * a->cy * g->nz;
    /* the fit's bands: about an eighth of the levels each (at least 2) */
    a->band = (g->nz + 7) / 8 > 2 ? (g->nz + 7) / 8 : 2;
    a->nband = (g->nz + a->band - 1) / a->band;
    const size_t nfit = (size_t)a->nvars * a->nband;
    a->sx = malloc(a->plane * sizeof *a->sx);
    a->sy = malloc(a->plane * sizeof *a->sy);
    a->sz = calloc((size_t)g->nz, sizeof *a->sz);
    a->wind = calloc(a->cells * 8, sizeof *a->wind);
    a->alpha = calloc(nfit, sizeof *a->alpha);
    a->fitrows = (g->ny + FIT_STRIDE - 1) / FIT_STRIDE * g->nz;
    a->acc = malloc((size_t)a->fitrows * a->nvars * NCAND * sizeof *a->acc);
    a->scratch = malloc((size_t)a->threads * (size_t)g->nx * 6 * sizeof *a->scratch);
    a->sums = malloc(nfit * NCAND * sizeof *a->sums);
    a->coarse = malloc(ncoarse * 6 * sizeof *a->coarse);
    a->cflag = malloc(ncoarse);
    if (!a->sx || !a->sy || !a->sz || !a->wind || !a->alpha || !a->acc || !a->sums || !a->scratch || !a->coarse ||
        !a->cflag)
        return VSV_ENOMEM;
    for (int j = 0; j < g->ny; j++)
        for (int i = 0; i < g->nx; i++)
            column_scale(g, i, j, &a->sx[(size_t)j * g->nx + i], &a->sy[(size_t)j * g->nx + i]);
    /* vertical: even heights have one spacing; native levels the local one
     * (centred differences of the levels' mean heights); a layer index or a
     * pressure axis gives no length, so no vertical motion */
    if (g->vert_kind == VSV_VERT_EVEN) {
        for (int k = 0; k < g->nz; k++)
            a->sz[k] = (float)(1 / g->spacing[2]);
        a->vertical = g->nz > 1;
    } else if (g->vert_kind == VSV_VERT_NATIVE && g->levels && g->nz > 1) {
        for (int k = 0; k < g->nz; k++) {
            const int lo = k > 0 ? k - 1 : 0, hi = k < g->nz - 1 ? k + 1 : g->nz - 1;
            const double dz = (g->levels[hi] - g->levels[lo]) / (hi - lo);
            a->sz[k] = dz > 0 ? (float)(1 / dz) : 0;
        }
        a->vertical = 1;
    }
    return 0;
}

int vsv_advect_has_vertical(const vsv_advect *a) { return a->vertical; }

static float calm(float v) { return isfinite(v) ? v : 0.0f; }

void vsv_advect_winds(vsv_advect *a, const float *u0, const float *v0, const float *w0, const float *u1,
                      const float *v1, const float *w1)
{
    a->span = 1; /* cells per second until a frame gives the interval */
    for (size_t c = 0; c < a->cells; c++) {
        const size_t col = c % a->plane;
        const float sx = a->sx[col], sy = a->sy[col], sz = a->sz[c / a->plane];
        float *o = a->wind + c * 8;
        o[0] = calm(u0[c]) * sx;
        o[1] = calm(v0[c]) * sy;
        o[2] = w0 ? calm(w0[c]) * sz : 0;
        o[4] = calm(u1[c]) * sx;
        o[5] = calm(v1[c]) * sy;
        o[6] = w1 ? calm(w1[c]) * sz : 0;
    }
}

/* Trilinear value of f at the corners, clamped to the range of the 8
 * cells; when some hold no data (NaN) they are left out and the weights of
 * the others renormalised; own when none has data. */
static inline float sample(const float *f, const size_t off[8], const f8 *wt, float own)
{
    const f8 v = {f[off[0]], f[off[1]], f[off[2]], f[off[3]], f[off[4]], f[off[5]], f[off[6]], f[off[7]]};
    const f8 p = v * *wt;
    const float sum = ((p[0] + p[1]) + (p[2] + p[3])) + ((p[4] + p[5]) + (p[6] + p[7]));
    float lo, hi, r;
    if (sum == sum) { /* every corner has data: the common case, without branches */
        lo = hi = v[0];
        for (int c = 1; c < 8; c++) {
            lo = v[c] < lo ? v[c] : lo;
            hi = v[c] > hi ? v[c] : hi;
        }
        r = sum;
    } else {
        float s = 0, w = 0;
        lo = INFINITY, hi = -INFINITY;
        for (int c = 0; c < 8; c++)
            if (v[c] == v[c]) {
                s += (*wt)[c] * v[c];
                w += (*wt)[c];
                lo = v[c] < lo ? v[c] : lo;
                hi = v[c] > hi ? v[c] : hi;
            }
        if (!(w > 0))
            return own;
        r = w == 1 ? s : s / w;
    }
    return r < lo ? lo : r > hi ? hi : r;
}

/* The winds in cells per interval of t1 - t0 seconds. */
static void set_span(vsv_advect *a, int64_t t0, int64_t t1)
{
    if (a->span != (double)(t1 - t0)) {
        const float r = (float)((double)(t1 - t0) / (a->span > 0 ? a->span : 1));
        for (size_t i = 0; i < a->cells * 8; i++)
            a->wind[i] *= r;
        a->span = (double)(t1 - t0);
    }
}

/* Species v's end value at cell (i, j, k) displaced by alpha * d: f
 * sampled trilinearly there and limited (sample), own where none has data.
 * zero: f's zero mask. Where the 8 cells are all +0 (most of the grid for
 * a hydrometeor) the answer is +0 without reading them: sample would sum
 * eight +0 times weights >= 0 to +0 and clamp it to [+0, +0], so the
 * shortcut gives the same bits. */
static inline float carried(const vsv_advect *a, const float *f, const uint64_t *zero, int i, int j, int k, float alpha,
                            const float d[3], float own)
{
    const float p[3] = {(float)i + alpha * d[0], (float)j + alpha * d[1], (float)k + alpha * d[2]};
    float fx, fy, fz;
    const int ci = axis(p[0], a->nx, &fx), cj = axis(p[1], a->ny, &fy), ck = axis(p[2], a->nz, &fz);
    if (zero[((size_t)ck * a->ny + cj) * a->zrow + ((unsigned)ci >> 6)] >> (ci & 63) & 1)
        return 0.0f;
    size_t off[8];
    f8 wt;
    corners_at(a, ci, cj, ck, fx, fy, fz, off, &wt);
    return sample(f, off, &wt, own);
}

/* Bits of a float (+0 is all zero bits). */
static inline uint32_t bits(float x)
{
    uint32_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}

/* Level k lies between band r and r + 1 of the m bands of n levels, weight
 * *f on r + 1 (band centres at (r + 0.5) * n - 0.5; the scale is linear
 * between them, so it has no step at a band's edge). */
static inline int band_of(int c, int n, int m, float *f)
{
    const float u = ((float)c + 0.5f) / (float)n - 0.5f;
    if (m < 2 || u <= 0) {
        *f = 0;
        return 0;
    }
    if (u >= m - 1) {
        *f = 0;
        return m - 1;
    }
    const int r = (int)u;
    *f = u - (float)r;
    return r;
}

enum { JOB_FRAME, JOB_FIT, JOB_MASK, JOB_COARSE };

typedef struct job {
    vsv_advect *a;
    double s, w;  /* the frame's interval time, its linear weight */
    int ns, kind; /* JOB_FRAME, JOB_FIT (rows FIT_STRIDE apart), JOB_MASK, JOB_COARSE */
    float *const *out;
    atomic_int next; /* next row (j + k*ny) to do */
    atomic_int tid;  /* next worker's scratch */
} job;

/* The scales of level k for every species, into al (ns): the fitted ones,
 * linear between band centres, or the one given scale. Returns 1 if any is
 * non-zero. */
static int level_scales(const vsv_advect *a, int ns, int k, float *al)
{
    float f;
    const int b = band_of(k, a->band, a->nband, &f), b1 = b + (f > 0);
    int any = 0;
    for (int v = 0; v < ns; v++) {
        const float *t = a->alpha + (size_t)v * a->nband;
        al[v] = a->scale > 0 ? a->scale : t[b] + f * (t[b1] - t[b]);
        any |= al[v] > 0;
    }
    return any;
}

/* Rows within REACH of a row, levels within REACH of its level: if no
 * sample of the row moves further across them, its 8 cells lie among them.
 * NEVER: a column bound no sample passes (a scale above 1 may carry a
 * sample past the grid's edge, where it is clamped onto the edge cells). */
enum { REACH = 2, NEVER = 1 << 28 };

/* For the row (j, k) of species-end e (2 * v + e) at scale al with the
 * row's largest displacements m (y and z): the columns *lo, *hi such that
 * a sample at x < *lo - 1 or x >= *hi + 1 reads +0 cells only; -NEVER and
 * NEVER when the samples reach further than REACH rows or levels. The edge
 * cells of an axis take the samples beyond them, hence lo >= 2 and
 * hi <= nx - 3 (else NEVER). */
static void zero_reach(const vsv_advect *a, int e, int j, int k, float al, const float m[2], int *lo, int *hi)
{
    *lo = -NEVER, *hi = NEVER;
    if (!(al * m[0] < REACH && al * m[1] < REACH))
        return;
    int l = a->nx + 2, h = -3;
    for (int kk = k - REACH; kk <= k + REACH; kk++)
        for (int jj = j - REACH; jj <= j + REACH; jj++)
            if (kk >= 0 && kk < a->nz && jj >= 0 && jj < a->ny) {
                const int *x = a->ext + ((size_t)e * a->ny * a->nz + (size_t)kk * a->ny + jj) * 2;
                l = x[0] < l ? x[0] : l;
                h = x[1] > h ? x[1] : h;
            }
    *lo = l >= 2 ? l : -NEVER;
    *hi = h <= a->nx - 3 ? h : NEVER;
}

/* One row of a frame: every cell's two displacements (once, for all
 * species), then species by species (a pass reads a few rows of one field
 * at a time) each end sampled at the species' scale of them, the scale of
 * the row's level. A species at scale 0 gets linear interpolation's very
 * arithmetic. sc: the thread's scratch. */
static void do_row(const job *jb, int row, float *sc)
{
    const vsv_advect *a = jb->a;
    const int j = row % a->ny, k = row / a->ny;
    const float s = (float)jb->s;
    const size_t c0 = (size_t)k * a->plane + (size_t)j * a->nx;
    float *d = sc, al[MAXVARS];
    float m[2][2] = {{0, 0}, {0, 0}}; /* the row's largest |y| and |z| displacements, back and on */
    if (level_scales(a, jb->ns, k, al))
        for (int i = 0; i < a->nx; i++) {
            /* only where some moving species has data at both ends (not
             * below the ground) */
            int need = 0;
            for (int v = 0; v < jb->ns && !need; v++)
                need = al[v] > 0 && a->f0[v][c0 + i] == a->f0[v][c0 + i] && a->f1[v][c0 + i] == a->f1[v][c0 + i];
            if (!need)
                continue;
            float *di = d + 6 * i;
            vsv_advect_cell(a, i, j, k, s, di);
            for (int e = 0; e < 2; e++)
                for (int c = 0; c < 2; c++)
                    m[e][c] = fabsf(di[3 * e + 1 + c]) > m[e][c] ? fabsf(di[3 * e + 1 + c]) : m[e][c];
        }
    for (int v = 0; v < jb->ns; v++) {
        const float *f0 = a->f0[v], *f1 = a->f1[v];
        const uint64_t *z0 = a->zero + 2 * (size_t)v * a->zplane, *z1 = z0 + a->zplane;
        float *out = jb->out[v] + c0;
        /* columns whose samples read only +0 cells: +0 without a look (the
         * zero mask's answer, found without computing the sample's cell) */
        int lo0 = -NEVER, hi0 = NEVER, lo1 = -NEVER, hi1 = NEVER;
        if (al[v] > 0) {
            zero_reach(a, 2 * v, j, k, al[v], m[0], &lo0, &hi0);
            zero_reach(a, 2 * v + 1, j, k, al[v], m[1], &lo1, &hi1);
        }
        for (int i = 0; i < a->nx; i++) {
            const float a0 = f0[c0 + i], a1 = f1[c0 + i];
            float r = NAN;
            if (a0 == a0 && a1 == a1) {
                float A = a0, B = a1;
                if (al[v] > 0) {
                    const float x0 = (float)i + al[v] * d[6 * i], x1 = (float)i + al[v] * d[6 * i + 3];
                    A = x0 < lo0 - 1 || x0 >= hi0 + 1 ? 0.0f : carried(a, f0, z0, i, j, k, al[v], d + 6 * i, a0);
                    B = x1 < lo1 - 1 || x1 >= hi1 + 1 ? 0.0f : carried(a, f1, z1, i, j, k, al[v], d + 6 * i + 3, a1);
                }
                r = (float)(A + ((double)B - A) * jb->w);
            }
            out[i] = r;
        }
    }
}

/* One row of the fit: at every FIT_STRIDE-th cell the displacements over
 * the whole interval of the air there at its end (db) and at its start
 * (df); for each candidate scale and species the squared differences
 * between the start's field carried to the end and the end's field, and
 * between the end's carried back and the start's, summed into the row's
 * slot of acc. */
static void fit_row(const job *jb, int row, float *sc)
{
    const vsv_advect *a = jb->a;
    const int nj = (a->ny + FIT_STRIDE - 1) / FIT_STRIDE;
    const int j = row % nj * FIT_STRIDE, k = row / nj;
    const size_t c0 = (size_t)k * a->plane + (size_t)j * a->nx;
    const float top = (NCAND - 1) * CAND_STEP;
    double *acc = a->acc + (size_t)row * a->nvars * NCAND;
    memset(acc, 0, (size_t)jb->ns * NCAND * sizeof *acc);
    float m[2][2] = {{0, 0}, {0, 0}}; /* the row's largest |y| and |z| displacements */
    for (int i = 0; i < a->nx; i += FIT_STRIDE) {
        float unused[3], *d = sc + 6 * i;
        vsv_advect_trace(a, i, j, k, 1, d, unused);
        vsv_advect_trace(a, i, j, k, 0, unused, d + 3);
        for (int e = 0; e < 2; e++)
            for (int c = 0; c < 2; c++)
                m[e][c] = fabsf(d[3 * e + 1 + c]) > m[e][c] ? fabsf(d[3 * e + 1 + c]) : m[e][c];
    }
    for (int v = 0; v < jb->ns; v++) {
        const float *f0 = a->f0[v], *f1 = a->f1[v];
        const uint64_t *z0 = a->zero + 2 * (size_t)v * a->zplane, *z1 = z0 + a->zplane;
        double *o = acc + (size_t)v * NCAND;
        /* a cell +0 at both ends whose samples at every scale read +0 cells
         * only adds 0 to every sum: skipped (as in do_row) */
        int lo0, hi0, lo1, hi1;
        zero_reach(a, 2 * v, j, k, top, m[0], &lo0, &hi0);
        zero_reach(a, 2 * v + 1, j, k, top, m[1], &lo1, &hi1);
        for (int i = 0; i < a->nx; i += FIT_STRIDE) {
            const float *db = sc + 6 * i, *df = db + 3;
            const float a0 = f0[c0 + i], a1 = f1[c0 + i];
            if (!(a0 == a0 && a1 == a1))
                continue;
            if (!bits(a0) && !bits(a1)) {
                const float b0 = (float)i + top * db[0], b1 = (float)i + top * df[0];
                const float l0 = b0 < i ? b0 : (float)i, h0 = b0 > i ? b0 : (float)i;
                const float l1 = b1 < i ? b1 : (float)i, h1 = b1 > i ? b1 : (float)i;
                if ((h0 < lo0 - 1 || l0 >= hi0 + 1) && (h1 < lo1 - 1 || l1 >= hi1 + 1))
                    continue;
            }
            for (int c = 0; c < NCAND; c++) {
                const float al = c * CAND_STEP;
                const double A = c ? carried(a, f0, z0, i, j, k, al, db, a0) : a0;
                const double B = c ? carried(a, f1, z1, i, j, k, al, df, a1) : a1;
                o[c] += (A - a1) * (A - a1) + (B - a0) * (B - a0);
            }
        }
    }
}

/* Row (j, k) of the zero masks of every species and end: a cell's bit is
 * set when the cells (i..i+1, j..j+1, k..k+1) — the same cell for an
 * axis of one — are all +0; never at the last cell of an axis, which is
 * no sample's base (axis). */
static void mask_row(const job *jb, int row)
{
    const vsv_advect *a = jb->a;
    const int j = row % a->ny, k = row / a->ny;
    const size_t c0 = (size_t)k * a->plane + (size_t)j * a->nx;
    const size_t sx = a->stride[0], sy = a->stride[1], sz = a->stride[2];
    const int last = (a->ny > 1 && j == a->ny - 1) || (a->nz > 1 && k == a->nz - 1);
    const int ni = a->nx > 1 ? a->nx - 1 : 1;
    for (int e = 0; e < 2 * jb->ns; e++) {
        const float *f = (e & 1 ? a->f1 : a->f0)[e / 2] + c0;
        uint64_t *z = a->zero + (size_t)e * a->zplane + (size_t)row * a->zrow;
        int *x = a->ext + ((size_t)e * a->ny * a->nz + row) * 2;
        x[0] = a->nx + 2, x[1] = -3;
        for (int i = 0; i < a->nx; i++)
            if (bits(f[i])) {
                x[0] = x[0] < i ? x[0] : i;
                x[1] = i;
            }
        memset(z, 0, a->zrow * sizeof *z);
        if (last)
            continue;
        /* or of each column's 4 cells (i; j, j+1; k, k+1), then of two columns */
        uint32_t prev = bits(f[0]) | bits(f[sy]) | bits(f[sz]) | bits(f[sy + sz]);
        for (int i = 0; i < ni; i++) {
            const size_t c = (size_t)i + sx;
            const uint32_t col = bits(f[c]) | bits(f[c + sy]) | bits(f[c + sz]) | bits(f[c + sy + sz]);
            if (!(prev | col))
                z[i >> 6] |= (uint64_t)1 << (i & 63);
            prev = col;
        }
    }
}

static void *worker(void *p)
{
    job *jb = p;
    const vsv_advect *a = jb->a;
    if (jb->kind == JOB_COARSE) {
        float al[MAXVARS];
        for (int r; (r = atomic_fetch_add(&jb->next, 1)) < a->cy * a->nz;)
            if (level_scales(a, jb->ns, r / a->cy, al))
                vsv_advect_coarse_row(a, r, (float)jb->s, jb->ns, al);
        return NULL;
    }
    if (jb->kind == JOB_MASK) {
        for (int r; (r = atomic_fetch_add(&jb->next, 1)) < a->ny * a->nz;)
            mask_row(jb, r);
        return NULL;
    }
    float *sc = a->scratch + (size_t)atomic_fetch_add(&jb->tid, 1) * a->nx * 6;
    if (jb->kind == JOB_FIT) {
        for (int r; (r = atomic_fetch_add(&jb->next, 1)) < a->fitrows;)
            fit_row(jb, r, sc);
        return NULL;
    }
    for (int r; (r = atomic_fetch_add(&jb->next, 1)) < a->ny * a->nz;)
        do_row(jb, r, sc);
    return NULL;
}

/* Runs jb on the caller's thread and up to threads - 1 more. */
static void run_job(job *jb)
{
    atomic_init(&jb->next, 0);
    atomic_init(&jb->tid, 0);
    pthread_t th[MAXTHREADS];
    int n = 0;
    while (n < jb->a->threads - 1 && !pthread_create(&th[n], NULL, worker, jb))
        n++;
    worker(jb);
    for (int i = 0; i < n; i++)
        pthread_join(th[i], NULL);
}

/* The candidate of least mismatch in sums e (NCAND), the smaller scale on
 * a tie; -1 when e says nothing (no difference at all at scale 0). */
static int best(const double *e)
{
    if (!(e[0] > 0))
        return -1;
    int b = 0;
    for (int c = 1; c < NCAND; c++)
        if (e[c] < e[b])
            b = c;
    return b;
}

void vsv_advect_set_scale(vsv_advect *a, float scale) { a->scale = scale > 0 ? scale : 0; }

int vsv_advect_outputs(vsv_advect *a, int ns, const float *const *f0, const float *const *f1)
{
    if (ns > a->nvars)
        ns = a->nvars;
    a->ns = ns;
    a->f0 = f0;
    a->f1 = f1;
    const size_t need = 2 * (size_t)ns * a->zplane;
    if (need > a->zcap) {
        uint64_t *z = realloc(a->zero, need * sizeof *z);
        int *x = z ? realloc(a->ext, 4 * (size_t)ns * a->ny * a->nz * sizeof *x) : NULL;
        if (z)
            a->zero = z;
        if (!x) {
            a->ns = 0;
            return VSV_ENOMEM;
        }
        a->ext = x;
        a->zcap = need;
    }
    job jb = {a, 0, 0, ns, JOB_MASK, NULL, 0, 0};
    run_job(&jb);
    return 0;
}

int vsv_advect_fit(vsv_advect *a, int64_t t0, int64_t t1)
{
    if (a->scale > 0)
        return 0;
    const int ns = a->ns;
    set_span(a, t0, t1);
    job jb = {a, 0, 0, ns, JOB_FIT, NULL, 0, 0};
    run_job(&jb);
    /* per species and band, the rows' sums in row order */
    double *sum = a->sums;
    memset(sum, 0, (size_t)ns * a->nband * NCAND * sizeof *sum);
    const int nj = a->fitrows / a->nz;
    for (int r = 0; r < a->fitrows; r++)
        for (int v = 0; v < ns; v++)
            for (int c = 0; c < NCAND; c++)
                sum[((size_t)v * a->nband + (size_t)(r / nj / a->band)) * NCAND + c] +=
                    a->acc[((size_t)r * a->nvars + v) * NCAND + c];
    /* a band's own choice where it has something to compare; elsewhere the
     * species' over the whole grid, else 0 (linear) */
    for (int v = 0; v < ns; v++) {
        double all[NCAND] = {0};
        for (int b = 0; b < a->nband; b++)
            for (int c = 0; c < NCAND; c++)
                all[c] += sum[((size_t)v * a->nband + b) * NCAND + c];
        const int ball = best(all);
        for (int b = 0; b < a->nband; b++) {
            const int bb = best(sum + ((size_t)v * a->nband + b) * NCAND);
            a->alpha[(size_t)v * a->nband + b] = (float)(bb >= 0 ? bb : ball >= 0 ? ball : 0) * CAND_STEP;
        }
    }
    return 0;
}

const float *vsv_advect_scales(const vsv_advect *a, int *nband)
{
    *nband = a->nband;
    return a->alpha;
}

int vsv_advect_frame(vsv_advect *a, int64_t t0, int64_t t1, int64_t t, float *const *out)
{
    set_span(a, t0, t1);
    job jb = {a, 0, 0, a->ns, JOB_COARSE, out, 0, 0};
    jb.w = (double)(t - t0) / (double)(t1 - t0); /* exactly as linear interpolation weighs */
    jb.s = jb.w;
    run_job(&jb); /* the coarse grid's trajectories, then the cells */
    jb.kind = JOB_FRAME;
    run_job(&jb);
    return 0;
}

void vsv_advect_free(vsv_advect *a)
{
    if (!a)
        return;
    free(a->sx);
    free(a->sy);
    free(a->sz);
    free(a->wind);
    free(a->alpha);
    free(a->acc);
    free(a->sums);
    free(a->scratch);
    free(a->zero);
    free(a->ext);
    free(a->coarse);
    free(a->cflag);
    free(a);
}
