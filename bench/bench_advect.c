/* bench_advect.c — fidelity of time interpolation: hold out one output of a
 * model run, rebuild it from the outputs before and after it with linear
 * interpolation and with advection along the model's winds (vsv_interp,
 * the code vsv-convert runs), and print per species the RMSE and the
 * largest error against the held-out truth, with the advect/linear ratio,
 * plus how far the main cloud objects' centroids land from the truth.
 *
 *   bench_advect FILE HOLD [VARS [SCALE [shift]]]
 *
 * HOLD: the index of the held-out output (1 .. times-2); VARS: comma-
 * separated species (default: the reader's defaults, "" too); SCALE: a
 * factor on the winds, or three (SU,SV,SW) on U, V and W apart (default 1;
 * diagnostics: how fast do the clouds really move compared with the wind,
 * and does a wind with its sign turned do better, as it would if a reader
 * gave a component the wrong sign?). With "shift", also per species and
 * every fifth level: the whole-level shift (whole cells, up to 8) of the
 * earlier output that best matches the later one, beside the mean wind's
 * displacement over the interval at those cells (map factors ignored): how
 * far the pattern moved against how far the air moved. Objects: the species'
 * column totals (sum over levels) above a quarter of the truth's largest
 * column total, 8-connected; for each of the three heaviest truth objects
 * the rebuilt object is the rebuilt component holding most of its mass
 * (thresholded the same way), and the error is the distance between the two
 * mass-weighted centroids in km. */
#include "vsv_convert.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct grab {
    int64_t want;
    int nv, got;
    size_t cells;
    float **out;
} grab;

static int keep(void *ctx, int64_t t, const float *const *f)
{
    grab *g = ctx;
    if (t != g->want)
        return 0;
    for (int v = 0; v < g->nv; v++)
        memcpy(g->out[v], f[v], g->cells * sizeof(float));
    g->got = 1;
    return 0;
}

/* Rebuilds the frame at time th from frames a (ta) and b (tb). */
static int rebuild(int method, const vsv_meta *m, int64_t ta, int64_t tb, int64_t th, float **a, float **b, grab *g)
{
    vsv_interp_opts o = {method, 0};
    vsv_interp *ip = NULL;
    int rc = vsv_interp_open(th - ta, m, &o, keep, g, &ip);
    g->got = 0;
    if (!rc)
        rc = vsv_interp_push(ip, ta, (const float *const *)a);
    if (!rc)
        rc = vsv_interp_push(ip, tb, (const float *const *)b);
    if (rc)
        fprintf(stderr, "bench_advect: %s\n", vsv_interp_error(ip));
    int nb;
    const float *al = rc ? NULL : vsv_interp_scales(ip, &nb);
    if (al) { /* advect: the fitted scales */
        printf("advect's fitted scales of the wind's displacement, per band of levels (bottom up):\n");
        for (int v = 0; v < g->nv; v++) {
            printf("  %-6s", m->vars[v].name);
            for (int k = 0; k < nb; k++)
                printf(" %.3g", al[(size_t)v * nb + k]);
            printf("\n");
        }
        printf("\n");
    }
    vsv_interp_free(ip);
    return rc || !g->got ? -1 : 0;
}

/* Column totals of a species (levels without data count as 0). */
static void columns(const vsv_meta *m, const float *f, double *col)
{
    const size_t plane = (size_t)m->nx * m->ny;
    for (size_t c = 0; c < plane; c++) {
        double s = 0;
        for (int k = 0; k < m->nz; k++) {
            const float v = f[(size_t)k * plane + c];
            s += isfinite(v) ? v : 0;
        }
        col[c] = s;
    }
}

/* 8-connected components of col > thr: label per column (0 none), count. */
static int label(const vsv_meta *m, const double *col, double thr, int *lab, int *stack)
{
    const int nx = m->nx, ny = m->ny;
    const size_t plane = (size_t)nx * ny;
    memset(lab, 0, plane * sizeof *lab);
    int n = 0;
    for (size_t c = 0; c < plane; c++) {
        if (lab[c] || !(col[c] > thr))
            continue;
        int sp = 0;
        lab[c] = ++n;
        stack[sp++] = (int)c;
        while (sp) {
            const int q = stack[--sp], i = q % nx, j = q / nx;
            for (int dj = -1; dj <= 1; dj++)
                for (int di = -1; di <= 1; di++) {
                    const int ii = i + di, jj = j + dj;
                    if (ii < 0 || jj < 0 || ii >= nx || jj >= ny)
                        continue;
                    const size_t r = (size_t)jj * nx + ii;
                    if (!lab[r] && col[r] > thr) {
                        lab[r] = n;
                        stack[sp++] = (int)r;
                    }
                }
        }
    }
    return n;
}

/* Mass-weighted centroid (cells) of component id. */
static double centroid(const vsv_meta *m, const double *col, const int *lab, int id, double *x, double *y)
{
    double s = 0, sx = 0, sy = 0;
    for (int j = 0; j < m->ny; j++)
        for (int i = 0; i < m->nx; i++) {
            const size_t c = (size_t)j * m->nx + i;
            if (lab[c] == id) {
                s += col[c];
                sx += col[c] * i;
                sy += col[c] * j;
            }
        }
    *x = s > 0 ? sx / s : 0;
    *y = s > 0 ? sy / s : 0;
    return s;
}

/* Metres per cell along x and y (degrees on a latitude/longitude grid,
 * near the centre). */
static void cell_km(const vsv_meta *m, double *kx, double *ky)
{
    *kx = m->spacing[0] / 1000, *ky = m->spacing[1] / 1000;
    if (m->proj.kind == VSV_PROJ_LATLON) {
        const double lat = m->origin[1] + m->spacing[1] * m->ny / 2;
        *kx = m->spacing[0] * 111.2 * cos(lat * M_PI / 180);
        *ky = m->spacing[1] * 111.2;
    }
}

/* Mean centroid error (km) over up to 3 heaviest truth objects; -1 if none. */
static double objects(const vsv_meta *m, const float *truth, const float *rec, int *nobj)
{
    const size_t plane = (size_t)m->nx * m->ny;
    double *ct = malloc(plane * sizeof *ct), *cr = malloc(plane * sizeof *cr);
    int *lt = malloc(plane * sizeof *lt), *lr = malloc(plane * sizeof *lr), *stack = malloc(9 * plane * sizeof *stack);
    columns(m, truth, ct);
    columns(m, rec, cr);
    double mx = 0;
    for (size_t c = 0; c < plane; c++)
        mx = ct[c] > mx ? ct[c] : mx;
    double err = -1;
    *nobj = 0;
    if (mx > 0) {
        const double thr = 0.25 * mx;
        const int nt = label(m, ct, thr, lt, stack), nr = label(m, cr, thr, lr, stack);
        double *mass = calloc((size_t)nt + 1, sizeof *mass), *share = calloc((size_t)nr + 1, sizeof *share);
        for (size_t c = 0; c < plane; c++)
            mass[lt[c]] += ct[c];
        double kx, ky, sum = 0;
        cell_km(m, &kx, &ky);
        for (int rank = 0; rank < 3; rank++) {
            int best = 0;
            for (int id = 1; id <= nt; id++)
                if (mass[id] > 0 && (!best || mass[id] > mass[best]))
                    best = id;
            if (!best)
                break;
            mass[best] = -1;
            double xt, yt, xr, yr;
            centroid(m, ct, lt, best, &xt, &yt);
            /* the rebuilt component holding most of the object's cells' mass */
            memset(share, 0, ((size_t)nr + 1) * sizeof *share);
            for (size_t c = 0; c < plane; c++)
                if (lt[c] == best && lr[c])
                    share[lr[c]] += cr[c];
            int pick = 0;
            for (int id = 1; id <= nr; id++)
                if (share[id] > 0 && (!pick || share[id] > share[pick]))
                    pick = id;
            if (!pick) { /* nothing overlaps: the nearest rebuilt object */
                double dbest = INFINITY;
                for (int id = 1; id <= nr; id++) {
                    centroid(m, cr, lr, id, &xr, &yr);
                    const double d = hypot((xr - xt) * kx, (yr - yt) * ky);
                    if (d < dbest)
                        dbest = d, pick = id;
                }
            }
            if (!pick)
                continue; /* the rebuild has no object at all */
            centroid(m, cr, lr, pick, &xr, &yr);
            sum += hypot((xr - xt) * kx, (yr - yt) * ky);
            (*nobj)++;
        }
        if (*nobj)
            err = sum / *nobj;
        free(mass);
        free(share);
    }
    free(ct), free(cr), free(lt), free(lr), free(stack);
    return err;
}

/* RMSE of level k of b against level k of a shifted by (sx, sy) cells, over
 * the overlap (cells without data count as 0). */
static double shifted_rmse(const vsv_meta *m, const float *a, const float *b, int k, int sx, int sy)
{
    const size_t plane = (size_t)m->nx * m->ny;
    double s = 0;
    long n = 0;
    for (int j = sy > 0 ? sy : 0; j < m->ny + (sy < 0 ? sy : 0); j++)
        for (int i = sx > 0 ? sx : 0; i < m->nx + (sx < 0 ? sx : 0); i++) {
            const float va = a[k * plane + (size_t)(j - sy) * m->nx + (i - sx)],
                        vb = b[k * plane + (size_t)j * m->nx + i];
            const double d = (isfinite(vb) ? vb : 0) - (double)(isfinite(va) ? va : 0);
            s += d * d;
            n++;
        }
    return n ? sqrt(s / n) : 0;
}

/* How far the pattern moved against how far the air moved: per species and
 * every fifth level, the whole-cell shift of the earlier output that best
 * matches the later one, and the mean wind's displacement (cells over the
 * interval dt, the mean of both outputs' winds where either has the
 * species). The species come first in a and b, the winds after them. */
static void shifts(const vsv_meta *m, int ns, float **a, float **b, double dt)
{
    const int iu = vsv_meta_find_var(m, VSV_WIND_U), iv = vsv_meta_find_var(m, VSV_WIND_V);
    if (iu < 0 || iv < 0)
        return;
    const size_t plane = (size_t)m->nx * m->ny;
    printf("\n| species | level | best shift x, y (cells) | RMSE shifted / unshifted | mean wind displacement x, y "
           "(cells) |\n|---|---|---|---|---|\n");
    for (int v = 0; v < ns; v++)
        for (int k = 0; k < m->nz; k += 5) {
            double su = 0, sv = 0;
            long n = 0;
            for (size_t c = 0; c < plane; c++) {
                const size_t q = (size_t)k * plane + c;
                const float x = a[v][q], y = b[v][q];
                if (!((isfinite(x) && x > 0) || (isfinite(y) && y > 0)))
                    continue;
                const float u = (a[iu][q] + b[iu][q]) / 2, w = (a[iv][q] + b[iv][q]) / 2;
                if (!isfinite(u) || !isfinite(w))
                    continue;
                su += u, sv += w, n++;
            }
            if (n < 10)
                continue;
            const double r0 = shifted_rmse(m, a[v], b[v], k, 0, 0);
            double best = r0;
            int bx = 0, by = 0;
            for (int sy = -8; sy <= 8; sy++)
                for (int sx = -8; sx <= 8; sx++) {
                    const double r = shifted_rmse(m, a[v], b[v], k, sx, sy);
                    if (r < best)
                        best = r, bx = sx, by = sy;
                }
            printf("| %s | %d | %d, %d | %.2f | %.1f, %.1f |\n", m->vars[v].name, k, bx, by, r0 > 0 ? best / r0 : 1.0,
                   su / n * dt / m->spacing[0], sv / n * dt / m->spacing[1]);
        }
}

int main(int argc, char **argv)
{
    if (argc < 3 || argc > 6) {
        fprintf(stderr, "usage: bench_advect FILE HOLD [VARS [SCALE [shift]]]\n");
        return 2;
    }
    const int h = atoi(argv[2]);
    const char *paths[1] = {argv[1]};
    vsv_run *run = NULL;
    if (vsv_run_open(paths, 1, NULL, argc > 3 && argv[3][0] ? argv[3] : NULL, NULL, &run) ||
        vsv_run_add_winds(run, NULL, NULL)) {
        fprintf(stderr, "bench_advect: %s\n", vsv_run_error(run));
        return 1;
    }
    if (h < 1 || h >= vsv_run_nframes(run) - 1) {
        fprintf(stderr, "bench_advect: HOLD must be 1..%d\n", vsv_run_nframes(run) - 2);
        return 2;
    }
    const vsv_meta *m = vsv_run_meta(run);
    const size_t cells = (size_t)m->nx * m->ny * m->nz;
    const int nv = m->nvars;
    float *buf[6][64];
    for (int f = 0; f < 6; f++)
        for (int v = 0; v < nv; v++)
            if (!(buf[f][v] = malloc(cells * sizeof(float))))
                return 1;
    /* 0: before, 1: truth, 2: after, 3..5: the rebuilds */
    for (int f = 0; f < 3; f++)
        if (vsv_run_read(run, h - 1 + f, buf[f])) {
            fprintf(stderr, "bench_advect: %s\n", vsv_run_error(run));
            return 1;
        }
    double sc[3] = {1, 1, 1};
    const int nsc = argc > 4 ? sscanf(argv[4], "%lf,%lf,%lf", &sc[0], &sc[1], &sc[2]) : 0;
    if (nsc == 1)
        sc[1] = sc[2] = sc[0];
    else if (nsc != 0 && nsc != 3) {
        fprintf(stderr, "bench_advect: SCALE is one factor or three (SU,SV,SW)\n");
        return 2;
    }
    const int scale = sc[0] != 1 || sc[1] != 1 || sc[2] != 1;
    static const char *const wn[3] = {"wind.u", "wind.v", "wind.w"};
    for (int v = 0; v < nv && scale; v++)
        for (int d = 0; d < 3; d++)
            if (!strcmp(m->vars[v].name, wn[d]))
                for (size_t i = 0; i < cells; i++)
                    buf[0][v][i] *= (float)sc[d], buf[2][v][i] *= (float)sc[d];
    const int64_t ta = vsv_run_time(run, h - 1), th = vsv_run_time(run, h), tb = vsv_run_time(run, h + 1);
    int ns = 0;
    while (ns < nv && strncmp(m->vars[ns].name, "wind.", 5))
        ns++;
    char a[40], b[40], c[40];
    vsv_time_format(ta, a, sizeof a);
    vsv_time_format(th, b, sizeof b);
    vsv_time_format(tb, c, sizeof c);
    printf("%s: %d x %d x %d cells; %s rebuilt from %s and %s\n", argv[1], m->nx, m->ny, m->nz, b, a, c);
    printf("winds: %s%s\n\n", vsv_meta_attr(m, VSV_WINDS_ATTR) ? vsv_meta_attr(m, VSV_WINDS_ATTR) : "?",
           scale ? " (scaled)" : "");
    if (scale)
        printf("winds scaled by U %g, V %g, W %g\n\n", sc[0], sc[1], sc[2]);
    /* 3: linear, 4: advect (fitted scales), 5: wind (the air's displacement) */
    static const int method[3] = {VSV_TIME_LINEAR, VSV_TIME_ADVECT, VSV_TIME_WIND};
    for (int q = 0; q < 3; q++) {
        grab g = {th, ns, 0, cells, buf[3 + q]};
        if (rebuild(method[q], m, ta, tb, th, buf[0], buf[2], &g))
            return 1;
    }
    printf("| species | truth max | RMSE linear | RMSE wind | RMSE advect | wind/linear | advect/linear | max err "
           "linear | max err wind | max err advect | objects | centroid err linear / wind / advect (km) |\n");
    printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (int v = 0; v < ns; v++) {
        const float *t = buf[1][v];
        double se[3] = {0}, me[3] = {0}, tmax = 0;
        long n = 0;
        for (size_t i = 0; i < cells; i++) {
            if (!isfinite(t[i]) || !isfinite(buf[3][v][i]) || !isfinite(buf[4][v][i]) || !isfinite(buf[5][v][i]))
                continue;
            for (int q = 0; q < 3; q++) {
                const double e = buf[3 + q][v][i] - (double)t[i];
                se[q] += e * e;
                me[q] = fmax(me[q], fabs(e));
            }
            tmax = fmax(tmax, t[i]);
            n++;
        }
        double r[3];
        char cen[3][32];
        int nobj = 0;
        for (int q = 0; q < 3; q++) {
            r[q] = n ? sqrt(se[q] / n) : 0;
            const double o = objects(m, t, buf[3 + q][v], &nobj);
            snprintf(cen[q], sizeof cen[q], o >= 0 ? "%.1f" : "-", o);
        }
        /* columns: linear, wind, advect */
        const double rl = r[0], rw = r[2], ra = r[1];
        printf("| %s | %.3g | %.3g | %.3g | %.3g | %s%.2f%s | %s%.2f%s | %.3g | %.3g | %.3g | %d | %s / %s / %s |\n",
               m->vars[v].name, tmax, rl, rw, ra, rl > 0 && rw <= 0.7 * rl ? "**" : "", rl > 0 ? rw / rl : 1.0,
               rl > 0 && rw <= 0.7 * rl ? "**" : "", rl > 0 && ra <= 0.7 * rl ? "**" : "", rl > 0 ? ra / rl : 1.0,
               rl > 0 && ra <= 0.7 * rl ? "**" : "", me[0], me[2], me[1], nobj, cen[0], cen[2], cen[1]);
    }
    if (argc > 5 && !strcmp(argv[5], "shift"))
        shifts(m, ns, buf[0], buf[2], (double)(tb - ta));
    for (int f = 0; f < 6; f++)
        for (int v = 0; v < nv; v++)
            free(buf[f][v]);
    vsv_run_free(run);
    return 0;
}
