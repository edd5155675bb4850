/* vsv_slice.c — slices through the volume (vsv_render.h): parsing a slice
 * against a grid, the sun of lit scenes, and where each pixel's ray first
 * meets a slice and the colour there, merged with the ground per frame. */
#include "vsv_renderer.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void vsv_scene_sun(vsv_scene *sc, double az, double el)
{
    const double a = az * M_PI / 180, e = el * M_PI / 180;
    sc->light = 1;
    sc->light_dir[0] = sin(a) * cos(e);
    sc->light_dir[1] = cos(a) * cos(e);
    sc->light_dir[2] = sin(e);
}

int vsv_sun_parse(const char *spec, double *az, double *el)
{
    double a, e;
    int used = 0;
    if (!spec || sscanf(spec, "%lf,%lf%n", &a, &e, &used) != 2 || spec[used] || !isfinite(a) || !(e >= -90 && e <= 90))
        return VSV_EINVAL;
    *az = a, *el = e;
    return 0;
}

/* A number, then the end of s or one of the characters in stop; *end past it. */
static int number(const char *s, const char *stop, double *v, const char **end)
{
    char *e;
    while (isspace((unsigned char)*s))
        s++;
    *v = strtod(s, &e);
    if (e == s || !isfinite(*v) || (*e && !strchr(stop, *e)))
        return -1;
    *end = e;
    return 0;
}

/* The latitudes and longitudes of the grid's edge (longitudes unwrapped
 * around the centre's). */
static void grid_extent(const vsv_meta *m, const vsv_geo *g, double ext[4])
{
    double clat, clon;
    ext[0] = ext[2] = INFINITY, ext[1] = ext[3] = -INFINITY;
    if (vsv_scene_latlon(m, 0.5 * (g->bmin[0] + g->bmax[0]), 0.5 * (g->bmin[1] + g->bmax[1]), &clat, &clon))
        return;
    for (int e = 0; e < 4; e++)
        for (int i = 0; i <= 64; i++) {
            const double f = i / 64.0;
            const double x = e < 2 ? g->bmin[0] + f * (g->bmax[0] - g->bmin[0]) : e == 2 ? g->bmin[0] : g->bmax[0];
            const double y = e >= 2 ? g->bmin[1] + f * (g->bmax[1] - g->bmin[1]) : e == 0 ? g->bmin[1] : g->bmax[1];
            double lat, lon;
            if (vsv_scene_latlon(m, x, y, &lat, &lon))
                continue;
            lon += 360 * round((clon - lon) / 360);
            ext[0] = fmin(ext[0], lat), ext[1] = fmax(ext[1], lat);
            ext[2] = fmin(ext[2], lon), ext[3] = fmax(ext[3], lon);
        }
}

int vsv_slice_parse(const vsv_meta *m, const char *spec, vsv_slice *s, char *msg, size_t cap)
{
    memset(s, 0, sizeof *s);
    const vsv_scene sc = {.meta = m, .exaggeration = 1};
    vsv_geo g;
    vsv_scene_geo(&sc, &g);
    const char *eq = strchr(spec, '='), *end;
    const size_t kl = eq ? (size_t)(eq - spec) : 0;
    double a, b, c, d;
    if (eq && kl == 1 && spec[0] == 'z') {
        if (number(eq + 1, "m", &a, &end) || (*end == 'm' && end[1])) {
            snprintf(msg, cap, "slice %s: expected z=HEIGHT in metres", spec);
            return VSV_EINVAL;
        }
        const double lo = g.oz - g.dz / 2, hi = g.oz + (g.nz - 0.5) * g.dz;
        if (!(a >= lo && a <= hi)) {
            snprintf(msg, cap, "slice %s: outside the grid's heights (%.0f to %.0f m)", spec, lo, hi);
            return VSV_EINVAL;
        }
        s->kind = VSV_SLICE_Z;
        s->z = a;
        return 0;
    }
    const int lat = eq && kl == 3 && !strncmp(spec, "lat", 3), lon = eq && kl == 3 && !strncmp(spec, "lon", 3);
    const int line = eq && kl == 4 && !strncmp(spec, "line", 4);
    if (!lat && !lon && !line) {
        snprintf(msg, cap, "slice %s: expected z=HEIGHT, lat=DEG, lon=DEG or line=LAT1,LON1:LAT2,LON2", spec);
        return VSV_EINVAL;
    }
    double pts[VSV_SLICE_MAXPTS][2];
    int n = 0;
    if (line) {
        if (number(eq + 1, ",", &a, &end) || !*end || number(end + 1, ":", &b, &end) || !*end ||
            number(end + 1, ",", &c, &end) || !*end || number(end + 1, "", &d, &end) || fabs(a) > 90 || fabs(c) > 90) {
            snprintf(msg, cap, "slice %s: expected line=LAT1,LON1:LAT2,LON2 (degrees)", spec);
            return VSV_EINVAL;
        }
        pts[0][0] = a, pts[0][1] = b, pts[1][0] = c, pts[1][1] = d;
        n = 2;
    } else {
        if (number(eq + 1, "", &a, &end) || (lat && fabs(a) > 90)) {
            snprintf(msg, cap, "slice %s: expected %s=DEGREES", spec, lat ? "lat" : "lon");
            return VSV_EINVAL;
        }
        double ext[4];
        grid_extent(m, &g, ext);
        if (!(ext[0] <= ext[1])) {
            snprintf(msg, cap, "slice %s: the grid has no latitude and longitude", spec);
            return VSV_EINVAL;
        }
        if (lon)
            a += 360 * round((0.5 * (ext[2] + ext[3]) - a) / 360);
        const double lo = lat ? ext[2] : ext[0], hi = lat ? ext[3] : ext[1];
        const double want_lo = lat ? ext[0] : ext[2], want_hi = lat ? ext[1] : ext[3];
        if (!(a >= want_lo && a <= want_hi)) {
            snprintf(msg, cap, "slice %s: outside the grid (%s %.2f to %.2f)", spec, lat ? "latitudes" : "longitudes",
                     want_lo, want_hi);
            return VSV_EINVAL;
        }
        n = VSV_SLICE_MAXPTS;
        for (int i = 0; i < n; i++) {
            const double o = lo + (hi - lo) * i / (n - 1);
            pts[i][0] = lat ? a : o;
            pts[i][1] = lat ? o : a;
        }
    }
    int inside = 0;
    for (int i = 0; i < n; i++) {
        if (vsv_scene_world(m, pts[i][0], pts[i][1], &s->xy[i][0], &s->xy[i][1])) {
            snprintf(msg, cap, "slice %s: %g,%g cannot be placed on the grid's projection", spec, pts[i][0], pts[i][1]);
            return VSV_EINVAL;
        }
    }
    if (line && !(hypot((s->xy[1][0] - s->xy[0][0]) * g.idx, (s->xy[1][1] - s->xy[0][1]) * g.idy) >= 0.5)) {
        snprintf(msg, cap, "slice %s: the line is shorter than half a cell (a section needs two distinct ends)", spec);
        return VSV_EINVAL;
    }
    for (int i = 0; i + 1 < n && !inside; i++) { /* exactly: a grid 1 mm wide is crossed too */
        double f0, f1;
        inside = vsv_segment_clip(s->xy[i], s->xy[i + 1], g.bmin, g.bmax, &f0, &f1);
    }
    if (!inside) {
        snprintf(msg, cap, "slice %s: does not cross the grid", spec);
        return VSV_EINVAL;
    }
    s->kind = VSV_SLICE_CURTAIN;
    s->npts = n;
    return 0;
}

/* Layer v's value at world point p (trilinear between cell centres, clamped
 * into the grid); NaN where there is no data. */
static float value_at(const vsv_geo *g, const vsv_volume *v, const double p[3])
{
    const double c[3] = {(p[0] - g->ox) * g->idx, (p[1] - g->oy) * g->idy, (p[2] / g->E - g->oz) / g->dz};
    const int n[3] = {v->nx, v->ny, v->nz};
    int i0[3], i1[3];
    double f[3];
    for (int a = 0; a < 3; a++) {
        const double x = c[a] < 0 ? 0 : c[a] > n[a] - 1 ? n[a] - 1 : c[a];
        i0[a] = (int)x;
        i1[a] = i0[a] + 1 < n[a] ? i0[a] + 1 : i0[a];
        f[a] = x - i0[a];
    }
    double s = 0;
    for (int q = 0; q < 8; q++) {
        const double w = (q & 1 ? f[0] : 1 - f[0]) * (q & 2 ? f[1] : 1 - f[1]) * (q & 4 ? f[2] : 1 - f[2]);
        if (w == 0)
            continue;
        const float x = vsv_volume_at(v, q & 1 ? i1[0] : i0[0], q & 2 ? i1[1] : i0[1], q & 4 ? i1[2] : i0[2]);
        s += w * x;
    }
    return (float)s;
}

static void extend(float v, double *lo, double *hi)
{
    if (isfinite(v)) {
        *lo = v < *lo ? v : *lo;
        *hi = v > *hi ? v : *hi;
    }
}

int vsv_slice_range_work(const vsv_scene *in, double *lo, double *hi, int64_t *work)
{
    vsv_native nat = {0};
    const vsv_scene *sc;
    int rc = vsv_native_scene(&nat, in, &sc);
    if (rc)
        return rc;
    vsv_geo g;
    vsv_scene_geo(sc, &g);
    const vsv_volume *v =
        sc->slice_layer >= 0 && sc->slice_layer < sc->nlayers ? sc->layers[sc->slice_layer].vol : NULL;
    int64_t n_at = 0;
    *lo = INFINITY, *hi = -INFINITY;
    for (int i = 0; v && i < sc->nslices; i++) {
        const vsv_slice *s = &sc->slices[i];
        if (s->kind == VSV_SLICE_Z) {
            for (int y = 0; y < g.ny; y++)
                for (int x = 0; x < g.nx; x++) {
                    const double p[3] = {g.ox + x * g.dx, g.oy + y * g.dy, s->z * g.E};
                    if (!g.terrain || p[2] >= vsv_geo_terrain(&g, p[0], p[1]))
                        extend(value_at(&g, v, p), lo, hi), n_at++;
                }
            continue;
        }
        /* each edge's part on the grid, a point per cell it crosses along
         * either axis: in cells, not metres, so that cells of 1 mm by
         * 1000 km cost what 16 x 12 cells do */
        for (int e = 0; e + 1 < s->npts; e++) {
            double f0, f1;
            if (!vsv_segment_clip(s->xy[e], s->xy[e + 1], g.bmin, g.bmax, &f0, &f1))
                continue;
            const double ex = s->xy[e + 1][0] - s->xy[e][0], ey = s->xy[e + 1][1] - s->xy[e][1];
            const double x0 = s->xy[e][0] + f0 * ex, y0 = s->xy[e][1] + f0 * ey, span = f1 - f0;
            const double cells = fmax(fabs(span * ex) * g.idx, fabs(span * ey) * g.idy);
            const int n = (int)fmin(ceil(cells), g.nx + g.ny) + 1;
            for (int q = 0; q <= n; q++)
                for (int k = 0; k < g.nz; k++) {
                    const double f = span * q / n;
                    const double p[3] = {x0 + ex * f, y0 + ey * f, (g.oz + k * g.dz) * g.E};
                    if (!g.terrain || p[2] >= vsv_geo_terrain(&g, p[0], p[1]))
                        extend(value_at(&g, v, p), lo, hi), n_at++;
                }
        }
    }
    vsv_native_free(&nat);
    if (work)
        *work = n_at;
    return *lo <= *hi ? 0 : VSV_ERANGE;
}

int vsv_slice_range(const vsv_scene *sc, double *lo, double *hi) { return vsv_slice_range_work(sc, lo, hi, NULL); }

/* The distance along ray (o, d) to slice s between t0 and t1, or INFINITY;
 * the nearest crossing for a curtain. */
static double slice_hit(const vsv_geo *g, const vsv_slice *s, const double o[3], const double d[3], double t0,
                        double t1)
{
    if (s->kind == VSV_SLICE_Z) {
        if (d[2] == 0)
            return INFINITY;
        const double t = (s->z * g->E - o[2]) / d[2];
        return t >= t0 && t <= t1 ? t : INFINITY;
    }
    double best = INFINITY;
    for (int i = 0; i + 1 < s->npts; i++) {
        /* o + t d = p0 + u (p1 - p0) in x, y */
        const double ex = s->xy[i + 1][0] - s->xy[i][0], ey = s->xy[i + 1][1] - s->xy[i][1];
        const double den = d[0] * ey - d[1] * ex;
        if (den == 0)
            continue;
        const double qx = s->xy[i][0] - o[0], qy = s->xy[i][1] - o[1];
        const double t = (qx * ey - qy * ex) / den, u = (qx * d[1] - qy * d[0]) / den;
        if (u >= 0 && u <= 1 && t >= t0 && t <= t1 && t < best)
            best = t;
    }
    return best;
}

/* One image row of the frame's surfaces: the ground, and in front of it
 * the nearest slice point with data above the ground, in the slice layer's
 * colours (values clamped into its range). */
void vsv_rc_slice_row(void *ctx, int py, int thread)
{
    vsv_renderer *r = ctx;
    const vsv_geo *g = &r->g;
    const vsv_camera *cam = r->cam;
    const vsv_scene *sc = r->sc;
    const vsv_layer *L = &sc->layers[sc->slice_layer];
    const vsv_tf *tf = sc->slice_tf ? sc->slice_tf : L->tf;
    (void)thread;
    for (int px = 0; px < cam->width; px++) {
        const size_t at = (size_t)py * cam->width + px;
        vsv_ground *out = &r->surf[at];
        if (g->terrain)
            *out = r->ground[at];
        else
            out->t = INFINITY;
        double o[3], d[3], t0, t1;
        vsv_rays_get(&r->rays, px, py, o, d);
        if (!vsv_box_hit(o, d, g->bmin, g->bmax, &t0, &t1))
            continue;
        t0 = t0 > cam->znear ? t0 : cam->znear > 0 ? cam->znear : 0;
        if (t1 > out->t)
            t1 = out->t;
        for (int s = 0; s < sc->nslices; s++) {
            double t = slice_hit(g, &sc->slices[s], o, d, t0, t1);
            if (!(t < t1))
                continue;
            const double p[3] = {o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]};
            if (g->terrain && p[2] < vsv_geo_terrain(g, p[0], p[1]))
                continue;
            float v = value_at(g, L->vol, p), rgba[4];
            if (v != v)
                continue;
            v = v < tf->lo ? (float)tf->lo : v > tf->hi ? (float)tf->hi : v;
            vsv_tf_eval(tf, v, rgba);
            out->t = (float)t;
            memcpy(out->rgb, rgba, sizeof out->rgb);
            t1 = t;
        }
    }
}
