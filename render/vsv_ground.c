/* vsv_ground.c — the terrain: exaggerated height and colour at a world
 * point, and where a ray first meets the ground. */
#include "vsv_geo.h"

#include <math.h>

/* Terrain height (exaggerated world z) at world (x, y): bilinear at cell centres. */
double vsv_geo_terrain(const vsv_geo *g, double x, double y)
{
    double u = (x - g->ox) * g->idx, v = (y - g->oy) * g->idy;
    u = u < 0 ? 0 : u > g->nx - 1 ? g->nx - 1 : u;
    v = v < 0 ? 0 : v > g->ny - 1 ? g->ny - 1 : v;
    int i = (int)u, j = (int)v;
    if (i > g->nx - 2)
        i = g->nx > 1 ? g->nx - 2 : 0;
    if (j > g->ny - 2)
        j = g->ny > 1 ? g->ny - 2 : 0;
    const double fu = u - i, fv = v - j;
    const int i1 = g->nx > 1 ? i + 1 : i, j1 = g->ny > 1 ? j + 1 : j;
    const float *t = g->terrain;
    const double a = t[(size_t)j * g->nx + i], b = t[(size_t)j * g->nx + i1], c = t[(size_t)j1 * g->nx + i],
                 dd = t[(size_t)j1 * g->nx + i1];
    return ((a * (1 - fu) + b * fu) * (1 - fv) + (c * (1 - fu) + dd * fu) * fv) * g->E;
}

static int vsv_geo_is_water(const vsv_geo *g, size_t c)
{
    const float lu = g->landuse[c];
    return lu >= 0 && lu < 64 && (g->water >> (int)lu & 1) && lu == (float)(int)lu;
}

void vsv_geo_terrain_colour(const vsv_geo *g, double x, double y, float rgb[3])
{
    const double h = vsv_geo_terrain(g, x, y) / g->E;
    const double ex = g->dx, ey = g->dy;
    const double gx = (vsv_geo_terrain(g, x + ex, y) - vsv_geo_terrain(g, x - ex, y)) / (2 * ex);
    const double gy = (vsv_geo_terrain(g, x, y + ey) - vsv_geo_terrain(g, x, y - ey)) / (2 * ey);
    double n[3] = {-gx, -gy, 1}, l[3] = {-0.5, -0.4, 0.75};
    vsv_normalize(n);
    vsv_normalize(l);
    const double lam = 0.35 + 0.65 * fmax(0, n[0] * l[0] + n[1] * l[1] + n[2] * l[2]);
    double c[3];
    int water = h <= 0.5;
    if (g->landuse) {
        /* the model's own water: the land-use categories it calls water,
         * bilinear between cell centres, water where that is at least half */
        double u = (x - g->ox) * g->idx, v = (y - g->oy) * g->idy;
        u = u < 0 ? 0 : u > g->nx - 1 ? g->nx - 1 : u;
        v = v < 0 ? 0 : v > g->ny - 1 ? g->ny - 1 : v;
        const int i = (int)u < g->nx - 1 ? (int)u : (g->nx > 1 ? g->nx - 2 : 0);
        const int j = (int)v < g->ny - 1 ? (int)v : (g->ny > 1 ? g->ny - 2 : 0);
        const int i1 = g->nx > 1 ? i + 1 : i, j1 = g->ny > 1 ? j + 1 : j;
        const double fu = u - i, fv = v - j;
#define WET(ii, jj) (vsv_geo_is_water(g, (size_t)(jj)*g->nx + (ii)) ? 1.0 : 0.0)
        const double w =
            (WET(i, j) * (1 - fu) + WET(i1, j) * fu) * (1 - fv) + (WET(i, j1) * (1 - fu) + WET(i1, j1) * fu) * fv;
#undef WET
        water = w >= 0.5;
    }
    if (water) {
        c[0] = 0.12, c[1] = 0.22, c[2] = 0.42; /* sea and lakes */
    } else {
        const double t = fmin(h / 3000.0, 1.0), s = fmax(0, fmin((h - 3000) / 2000.0, 1.0));
        c[0] = 0.22 + 0.33 * t + 0.35 * s;
        c[1] = 0.42 + 0.03 * t + 0.45 * s;
        c[2] = 0.22 + 0.13 * t + 0.55 * s;
    }
    for (int i = 0; i < 3; i++)
        rgb[i] = (float)(c[i] * lam);
}

/* The first s in [0, L] where q2 s^2 + q1 s + q0 falls to 0 (q0 > 0: the
 * ray above the ground at s = 0); INFINITY if none. */
static double first_root(double q2, double q1, double q0, double L)
{
    if (fabs(q2) * L <= 1e-12 * (fabs(q1) + q0 / L)) { /* linear */
        const double s = q1 < 0 ? -q0 / q1 : INFINITY;
        return s <= L ? s : INFINITY;
    }
    const double disc = q1 * q1 - 4 * q2 * q0;
    if (disc < 0)
        return INFINITY;
    const double qq = -0.5 * (q1 + copysign(sqrt(disc), q1));
    double r1 = qq / q2, r2 = qq != 0 ? q0 / qq : INFINITY;
    if (r1 > r2) {
        const double x = r1;
        r1 = r2, r2 = x;
    }
    return r1 >= 0 && r1 <= L ? r1 : r2 >= 0 && r2 <= L ? r2 : INFINITY;
}

double vsv_geo_terrain_hit(const vsv_geo *g, const double o[3], const double d[3], double t0, double t1)
{
    /* only where the ray is below the highest ground can it meet it */
    if (d[2] < 0) {
        const double tt = (g->ground_top - o[2]) / d[2];
        if (tt > t0)
            t0 = tt;
    } else if (d[2] > 0) {
        const double tt = (g->ground_top - o[2]) / d[2];
        if (tt < t1)
            t1 = tt;
    } else if (o[2] > g->ground_top) {
        return INFINITY;
    }
    if (!(t0 <= t1))
        return INFINITY;
    /* The ground is one bilinear patch per square of four cell centres (patch
     * i spans u in [i, i+1]); beyond the outer centres it is flat (patches -1
     * and n-1). Walk the patches the ray crosses; in each whose highest corner
     * the ray comes down to, solve the ray against the patch: a quadratic. */
    const int nx = g->nx, ny = g->ny;
    const double uo = (o[0] - g->ox) * g->idx, du = d[0] * g->idx;
    const double vo = (o[1] - g->oy) * g->idy, dv = d[1] * g->idy;
    const double u = uo + t0 * du, v = vo + t0 * dv;
    if (!(isfinite(u) && isfinite(v) && isfinite(t1))) /* a ray beyond numbers (an exaggeration of 1e308) */
        return INFINITY;
    int i = u < 0 ? -1 : u >= nx - 1 ? nx - 1 : (int)u, j = v < 0 ? -1 : v >= ny - 1 ? ny - 1 : (int)v;
    const float *h = g->terrain;
    const double iu = 1 / du, iv = 1 / dv; /* infinite along an axis the ray does not move on */
    for (double t = t0;;) {
        const double tu = du > 0 && i < nx - 1 ? (i + 1 - uo) * iu : du < 0 && i > -1 ? (i - uo) * iu : INFINITY;
        const double tv = dv > 0 && j < ny - 1 ? (j + 1 - vo) * iv : dv < 0 && j > -1 ? (j - vo) * iv : INFINITY;
        double te = tu < tv ? tu : tv;
        te = te < t1 ? te : t1;
        const int i0 = i < 0 ? 0 : i, i1 = i + 1 < nx ? i + 1 : nx - 1, j0 = j < 0 ? 0 : j,
                  j1 = j + 1 < ny ? j + 1 : ny - 1;
        const double h00 = h[(size_t)j0 * nx + i0] * g->E, h10 = h[(size_t)j0 * nx + i1] * g->E;
        const double h01 = h[(size_t)j1 * nx + i0] * g->E, h11 = h[(size_t)j1 * nx + i1] * g->E;
        const double za = o[2] + t * d[2], zb = o[2] + te * d[2];
        const double top0 = h00 > h10 ? h00 : h10, top1 = h01 > h11 ? h01 : h11;
        if ((za < zb ? za : zb) <= (top0 > top1 ? top0 : top1)) {
            /* local coordinates along the ray from t: fu = fua + fu1 s (flat beyond the centres) */
            const int inu = i >= 0 && i < nx - 1, inv = j >= 0 && j < ny - 1;
            const double fua = inu ? uo + t * du - i : 0, fu1 = inu ? du : 0;
            const double fva = inv ? vo + t * dv - j : 0, fv1 = inv ? dv : 0;
            const double b = h10 - h00, c = h01 - h00, e = h11 - h10 - h01 + h00;
            const double q0 = za - (h00 + b * fua + c * fva + e * fua * fva);
            if (q0 <= 0)
                return t; /* below the ground already: where it starts, or on this patch's edge */
            const double q1 = d[2] - (b * fu1 + c * fv1 + e * (fua * fv1 + fu1 * fva)), q2 = -e * fu1 * fv1;
            const double sh = first_root(q2, q1, q0, te - t);
            if (sh < INFINITY)
                return t + sh;
        }
        if (te >= t1)
            return INFINITY;
        if (tu <= tv)
            i += du > 0 ? 1 : -1;
        if (tv <= tu)
            j += dv > 0 ? 1 : -1;
        t = te;
    }
}
