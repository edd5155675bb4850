/* vsv_query.c — asking a .vsv for numbers: where a latitude/longitude/height
 * falls in the grid, where a cell is, and the decoded value at a cell or
 * between cells (nearest or trilinear), through a small cache of decoded
 * bricks so a time series or a column decodes each brick once per step. */
#include "vsv_format_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

void vsv_meta_cell_xy(const vsv_meta *m, double i, double j, double *x, double *y)
{
    *x = m->origin[0] + i * m->spacing[0];
    *y = m->origin[1] + j * m->spacing[1];
}

int vsv_meta_cell_latlon(const vsv_meta *m, double i, double j, double *lat, double *lon)
{
    if (m->proj.kind == VSV_PROJ_NONE)
        return VSV_EUNSUPPORTED;
    double x, y;
    vsv_meta_cell_xy(m, i, j, &x, &y);
    return vsv_proj_inverse(&m->proj, x, y, lat, lon);
}

double vsv_meta_cell_height(const vsv_meta *m, int i, int j, int k)
{
    (void)i;
    (void)j;
    switch (m->vert_kind) {
    case VSV_VERT_EVEN: return m->origin[2] + k * m->spacing[2];
    case VSV_VERT_NATIVE:
    case VSV_VERT_COORD: return m->levels ? m->levels[k] : k;
    default: return k;
    }
}

double vsv_meta_cell_height_at(const vsv_meta *m, int64_t time, int i, int j, int k)
{
    const float *z = m->vert_kind == VSV_VERT_NATIVE ? vsv_meta_heights_at(m, time) : NULL;
    return z ? z[((size_t)k * m->ny + j) * m->nx + i] : vsv_meta_cell_height(m, i, j, k);
}

const char *vsv_meta_height_units(const vsv_meta *m)
{
    switch (m->vert_kind) {
    case VSV_VERT_EVEN:
    case VSV_VERT_NATIVE: return "m";
    case VSV_VERT_COORD: return m->vert_units;
    default: return "";
    }
}

/* The lowest level of column (i, j) whose centre is at or above the ground.
 * Native model levels follow the terrain: their lowest is above the ground
 * everywhere, whatever its mean height over the grid. */
static int lowest_above_ground(const vsv_meta *m, int i, int j)
{
    if (!m->terrain || m->vert_kind != VSV_VERT_EVEN)
        return 0;
    const double ground = m->terrain[(size_t)j * m->nx + i];
    for (int k = 0; k < m->nz; k++)
        if (vsv_meta_cell_height(m, i, j, k) >= ground)
            return k;
    return m->nz - 1;
}

/* Fractional level of height h in column (i, j): piecewise linear between
 * the levels' centres, half a level beyond the first and last. Levels may
 * increase (heights) or decrease (pressure). */
int vsv_meta_level_of(const vsv_meta *m, int64_t time, int i, int j, double h, double *kf, double range[2])
{
    const int nz = m->nz;
    const double z0 = vsv_meta_cell_height_at(m, time, i, j, 0), z1 = vsv_meta_cell_height_at(m, time, i, j, nz - 1);
    const double g0 = nz > 1 ? vsv_meta_cell_height_at(m, time, i, j, 1) - z0 : (m->spacing[2] > 0 ? m->spacing[2] : 1);
    const double g1 = nz > 1 ? z1 - vsv_meta_cell_height_at(m, time, i, j, nz - 2) : g0;
    double a = z0 - g0 / 2, b = z1 + g1 / 2;
    range[0] = fmin(a, b);
    range[1] = fmax(a, b);
    if (!(h >= range[0] && h <= range[1]))
        return VSV_ERANGE;
    if ((h - z0) * (g0 >= 0 ? 1 : -1) <= 0) {
        *kf = (h - z0) / g0;
        return 0;
    }
    for (int k = 0; k + 1 < nz; k++) {
        const double lo = vsv_meta_cell_height_at(m, time, i, j, k), hi = vsv_meta_cell_height_at(m, time, i, j, k + 1);
        if ((h - lo) * (hi - lo) >= 0 && (h - hi) * (hi - lo) <= 0) {
            *kf = k + (hi != lo ? (h - lo) / (hi - lo) : 0);
            return 0;
        }
    }
    *kf = nz - 1 + (h - z1) / g1;
    return 0;
}

/* The extremes of latitude and longitude along the grid's outer edge. */
static void edge_range(const vsv_meta *m, double *la0, double *la1, double *lo0, double *lo1)
{
    *la0 = *lo0 = INFINITY;
    *la1 = *lo1 = -INFINITY;
    const double ex = m->nx - 0.5, ey = m->ny - 0.5;
    for (int side = 0; side < 4; side++) {
        const int n = side < 2 ? m->nx : m->ny;
        for (int c = 0; c <= n; c++) {
            const double t = c - 0.5;
            const double i = side < 2 ? t : side == 2 ? -0.5 : ex, j = side < 2 ? (side ? ey : -0.5) : t;
            double la, lo;
            if (vsv_meta_cell_latlon(m, i, j, &la, &lo))
                continue;
            *la0 = fmin(*la0, la);
            *la1 = fmax(*la1, la);
            *lo0 = fmin(*lo0, lo);
            *lo1 = fmax(*lo1, lo);
        }
    }
}

static void fill_centre(const vsv_meta *m, int64_t time, vsv_point *p)
{
    for (int a = 0; a < 3; a++) {
        const int n = a == 0 ? m->nx : a == 1 ? m->ny : m->nz;
        long c = lround(p->pos[a]);
        if (a == 0 && vsv_meta_periodic_x(m))
            c = (c % n + n) % n; /* (the half cell past the last is the first's) */
        p->cell[a] = (int)(c < 0 ? 0 : c >= n ? n - 1 : c);
    }
    if (vsv_meta_cell_latlon(m, p->cell[0], p->cell[1], &p->lat, &p->lon))
        p->lat = p->lon = NAN;
    p->height = vsv_meta_cell_height_at(m, time, p->cell[0], p->cell[1], p->cell[2]);
}

int vsv_point_locate(const vsv_meta *m, double lat, double lon, double height, vsv_point *p, char *msg, size_t cap)
{
    return vsv_point_locate_at(m, INT64_MIN, lat, lon, height, p, msg, cap);
}

int vsv_point_locate_at(const vsv_meta *grid, int64_t time, double lat, double lon, double height, vsv_point *p,
                        char *msg, size_t cap)
{
    const vsv_meta placed = vsv_meta_placed(grid, time), *m = &placed; /* a moving grid where it is then */
    if (m->proj.kind == VSV_PROJ_NONE) {
        vsv_msg(msg, cap, "the grid has no map projection: no latitude/longitude is known");
        return VSV_EUNSUPPORTED;
    }
    double x = NAN, y = NAN;
    int rc = vsv_proj_forward(&m->proj, lat, lon, &x, &y);
    const double ex = m->nx - 0.5, ey = m->ny - 0.5;
    double fi = (x - m->origin[0]) / m->spacing[0], fj = (y - m->origin[1]) / m->spacing[1];
    if (!rc && m->proj.kind == VSV_PROJ_LATLON) /* the same meridian a turn away */
        for (int w = -1; w <= 1 && !(fi >= -0.5 && fi <= ex); w += 2)
            fi = (x + 360.0 * w - m->origin[0]) / m->spacing[0];
    if (rc || !(fi >= -0.5 && fi <= ex && fj >= -0.5 && fj <= ey)) {
        double la0, la1, lo0, lo1, c[4][2];
        edge_range(m, &la0, &la1, &lo0, &lo1);
        /* on a map projection the edges are no parallels and meridians: a
         * point inside the box of the span may lie outside, so the corners
         * (cell centres) are named too */
        for (int k = 0; k < 4; k++)
            if (vsv_meta_cell_latlon(m, k & 1 ? m->nx - 1 : 0, k & 2 ? m->ny - 1 : 0, &c[k][0], &c[k][1]))
                c[k][0] = c[k][1] = NAN;
        if (m->proj.kind == VSV_PROJ_LATLON)
            vsv_msg(msg, cap,
                    "%.5g,%.5g is outside the grid (%d x %d cells spanning latitude %.3f..%.3f, longitude %.3f..%.3f)",
                    lat, lon, m->nx, m->ny, la0, la1, lo0, lo1);
        else
            vsv_msg(msg, cap,
                    "%.5g,%.5g is outside the grid (%d x %d cells spanning latitude %.3f..%.3f, longitude %.3f..%.3f; "
                    "the %s grid's edges are not parallels or meridians; corner cells SW %.3f,%.3f SE %.3f,%.3f NW "
                    "%.3f,%.3f "
                    "NE %.3f,%.3f)",
                    lat, lon, m->nx, m->ny, la0, la1, lo0, lo1, vsv_proj_name(m->proj.kind), c[0][0], c[0][1], c[1][0],
                    c[1][1], c[2][0], c[2][1], c[3][0], c[3][1]);
        return VSV_ERANGE;
    }
    /* where the point is, -0.5..n-0.5 (the edge cells' outer halves
     * included: the samplers clamp); its column the nearest centre's */
    p->pos[0] = fi;
    p->pos[1] = fj;
    const int ci = vsv_meta_periodic_x(m) ? (int)((lround(fi) + m->nx) % m->nx)
                                          : (int)fmin(fmax(lround(fi), 0), m->nx - 1),
              cj = (int)fmin(fmax(lround(fj), 0), m->ny - 1);
    if (isnan(height)) {
        p->pos[2] = lowest_above_ground(m, ci, cj);
    } else {
        double kf, r[2];
        if (vsv_meta_level_of(m, time, ci, cj, height, &kf, r)) {
            const char *u = vsv_meta_height_units(m);
            vsv_msg(msg, cap, "height %g%s%s is outside the grid's levels (%g..%g%s%s at this column)", height,
                    *u ? " " : "", u, r[0], r[1], *u ? " " : "", u);
            return VSV_ERANGE;
        }
        p->pos[2] = kf;
    }
    fill_centre(m, time, p);
    return 0;
}

int vsv_point_cell(const vsv_meta *m, int i, int j, int k, vsv_point *p, char *msg, size_t cap)
{
    if (i < 0 || i >= m->nx || j < 0 || j >= m->ny || k >= m->nz) {
        char at[48];
        if (k < 0)
            snprintf(at, sizeof at, "%d,%d", i, j);
        else
            snprintf(at, sizeof at, "%d,%d,%d", i, j, k);
        vsv_msg(msg, cap, "cell %s is outside the grid (i 0..%d, j 0..%d, k 0..%d)", at, m->nx - 1, m->ny - 1,
                m->nz - 1);
        return VSV_ERANGE;
    }
    p->pos[0] = i;
    p->pos[1] = j;
    p->pos[2] = k < 0 ? lowest_above_ground(m, i, j) : k;
    fill_centre(m, INT64_MIN, p);
    return 0;
}

/* ------------------------------------------------------------ values */

#define QUERY_SLOTS 8

struct vsv_query {
    vsv_file *f;
    vsv_decoder *d;
    int brick, shift, bdim[3], nx, ny, nz;
    int periodic;            /* x goes round the globe (vsv_meta_periodic_x) */
    int key[QUERY_SLOTS][3]; /* step, species, brick; step -1 = empty */
    float *slot[QUERY_SLOTS];
    int next; /* the slot to reuse next (round robin) */
    char err[512];
};

int vsv_query_create(vsv_file *f, vsv_query **out)
{
    vsv_query *q = *out = calloc(1, sizeof *q);
    if (!q)
        return VSV_ENOMEM;
    vsv_file_info info;
    vsv_file_info_get(f, &info);
    const vsv_meta *m = vsv_file_meta(f);
    q->f = f;
    q->brick = info.brick;
    while ((1 << q->shift) < q->brick)
        q->shift++;
    for (int a = 0; a < 3; a++)
        q->bdim[a] = info.bricks[a];
    q->nx = m->nx;
    q->ny = m->ny;
    q->nz = m->nz;
    q->periodic = vsv_meta_periodic_x(m);
    const size_t n = (size_t)q->brick * q->brick * q->brick;
    int rc = vsv_decoder_create(f, &q->d);
    for (int s = 0; s < QUERY_SLOTS && !rc; s++) {
        q->key[s][0] = -1;
        if (!(q->slot[s] = malloc(n * sizeof(float))))
            rc = VSV_ENOMEM;
    }
    if (rc) {
        vsv_msg(q->err, sizeof q->err, "%s", vsv_strerror(rc));
        return rc;
    }
    return 0;
}

void vsv_query_free(vsv_query *q)
{
    if (!q)
        return;
    for (int s = 0; s < QUERY_SLOTS; s++)
        free(q->slot[s]);
    vsv_decoder_free(q->d);
    free(q);
}

const char *vsv_query_error(const vsv_query *q) { return q ? q->err : "out of memory"; }

int vsv_query_cell(vsv_query *q, int step, int s, int i, int j, int k, float *v)
{
    vsv_file_info info;
    vsv_file_info_get(q->f, &info);
    if (step < 0 || step >= info.nsteps || s < 0 || s >= info.nspecies || i < 0 || i >= q->nx || j < 0 || j >= q->ny ||
        k < 0 || k >= q->nz) {
        vsv_msg(q->err, sizeof q->err, "step %d, species %d, cell %d,%d,%d out of range", step, s, i, j, k);
        return VSV_ERANGE;
    }
    const int sh = q->shift, msk = q->brick - 1;
    const int b = (i >> sh) + q->bdim[0] * ((j >> sh) + q->bdim[1] * (k >> sh));
    int slot = -1;
    for (int c = 0; c < QUERY_SLOTS && slot < 0; c++)
        if (q->key[c][0] == step && q->key[c][1] == s && q->key[c][2] == b)
            slot = c;
    if (slot < 0) {
        slot = q->next;
        q->next = (q->next + 1) % QUERY_SLOTS;
        q->key[slot][0] = -1;
        int rc = vsv_decoder_brick(q->d, step, s, b, q->slot[slot]);
        if (rc) {
            vsv_msg(q->err, sizeof q->err, "%s", vsv_decoder_error(q->d));
            return rc;
        }
        q->key[slot][0] = step;
        q->key[slot][1] = s;
        q->key[slot][2] = b;
    }
    *v = q->slot[slot][(i & msk) + ((size_t)(j & msk) << sh) + ((size_t)(k & msk) << (2 * sh))];
    return 0;
}

int vsv_query_sample(vsv_query *q, int step, int s, const double pos[3], int interp, float *v)
{
    const int n[3] = {q->nx, q->ny, q->nz};
    /* round the globe, x is taken modulo nx into [0, nx): the last cell's
     * neighbour is the first (a value that is not finite: cell 0) */
    double x = pos[0];
    if (q->periodic) {
        x = fmod(pos[0], n[0]);
        x = x < 0 ? x + n[0] : x;
        x = x >= 0 && x < n[0] ? x : 0;
    }
    if (interp == VSV_INTERP_NEAREST) {
        int c[3];
        for (int a = 0; a < 3; a++) {
            long r = lround(a ? pos[a] : x);
            if (a == 0 && q->periodic)
                r %= n[0];
            c[a] = (int)(r < 0 ? 0 : r >= n[a] ? n[a] - 1 : r);
        }
        return vsv_query_cell(q, step, s, c[0], c[1], c[2], v);
    }
    /* trilinear: the cells around pos, clamped to the grid (but round the
     * globe), weights in double */
    int lo[3], hi[3];
    double w[3];
    for (int a = 0; a < 3; a++) {
        const int wrap = a == 0 && q->periodic;
        const double p = wrap ? x : fmin(fmax(pos[a], 0), n[a] - 1);
        lo[a] = (int)floor(p);
        hi[a] = wrap ? (lo[a] + 1) % n[a] : lo[a] + 1 < n[a] ? lo[a] + 1 : lo[a];
        w[a] = p - lo[a];
    }
    /* the cells without data (under the ground, or none in the file) are
     * left out and the others' weights taken as the whole; no data when
     * the nearest cell (the corner of weight 1/2 or more on every axis, as
     * lround rounds) has none */
    const int nearest = (w[0] >= 0.5) | (w[1] >= 0.5) << 1 | (w[2] >= 0.5) << 2;
    double sum = 0, wsum = 0;
    for (int c = 0; c < 8; c++) {
        const double wx = c & 1 ? w[0] : 1 - w[0], wy = c & 2 ? w[1] : 1 - w[1], wz = c & 4 ? w[2] : 1 - w[2];
        const double wt = wx * wy * wz;
        if (wt == 0)
            continue;
        float cv;
        int rc = vsv_query_cell(q, step, s, c & 1 ? hi[0] : lo[0], c & 2 ? hi[1] : lo[1], c & 4 ? hi[2] : lo[2], &cv);
        if (rc)
            return rc;
        if (cv != cv) {
            if (c == nearest)
                return *v = NAN, 0;
            continue;
        }
        sum += wt * cv;
        wsum += wt;
    }
    *v = (float)(sum / wsum);
    return 0;
}
