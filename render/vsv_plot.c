/* vsv_plot.c — what a plot shows, read from a .vsv (vsv_render.h, "plots"):
 * the samples of a section along its line with their levels' heights, the
 * rows of a time series or a profile located and sampled as vsv-query does
 * it, the range of the values, the axes' and titles' words, and the numbers
 * as CSV. Drawing is vsv_plot_draw.c's. */
#include "vsv_plot_internal.h"
#include "vsv_common.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

void vsv_plot_opts_init(vsv_plot_opts *o)
{
    memset(o, 0, sizeof *o);
    o->lat[0] = o->lat[1] = o->lon[0] = o->lon[1] = NAN;
    o->at_height = o->lo = o->hi = o->top = NAN;
    o->size[0] = 800;
    o->size[1] = 600;
}

int vsv_plot_format(const char *path)
{
    const char *dot = path ? strrchr(path, '.') : NULL;
    if (!dot || strchr(dot, '/'))
        return -1;
    return !strcasecmp(dot, ".png")   ? VSV_PLOT_PNG
           : !strcasecmp(dot, ".svg") ? VSV_PLOT_SVG
           : !strcasecmp(dot, ".pdf") ? VSV_PLOT_PDF
                                      : -1;
}

/* "45.00N 125.00W" */
static void place(double lat, double lon, char *buf, size_t cap)
{
    lon = remainder(lon, 360);
    snprintf(buf, cap, "%.2f%c %.2f%c", fabs(lat), lat < 0 ? 'S' : 'N', fabs(lon), lon < 0 ? 'W' : 'E');
}

/* Great-circle distance in km between two points on a sphere of radius r (m). */
static double arc_km(double la0, double lo0, double la1, double lo1, double r)
{
    const double d2r = M_PI / 180, a = la0 * d2r, c = la1 * d2r, dl = (lo1 - lo0) * d2r;
    const double s = sin((c - a) / 2), t = sin(dl / 2);
    const double h = s * s + cos(a) * cos(c) * t * t;
    return 2 * r / 1000 * asin(sqrt(fmin(1, h)));
}

/* The words: species names and units, the value axis, the height axis and column. */
static void words(vsv_plot *p, const vsv_meta *m)
{
    int same = 1;
    for (int l = 0; l < p->o.nspecies; l++) {
        const vsv_var *v = &m->vars[p->o.species[l]];
        vsv_plot_clean(v->name, p->names[l], sizeof p->names[l]);
        vsv_plot_clean(v->units, p->units[l], sizeof p->units[l]);
        same &= !strcmp(p->units[l], p->units[0]);
    }
    /* "Q, CLW (kg/kg)" where the units agree, else "Q (kg/kg), T (K)"; "log" in the last parentheses */
    char *a = p->vaxis;
    const size_t cap = sizeof p->vaxis;
    a[0] = 0;
    for (int l = 0; l < p->o.nspecies; l++) {
        const int last = l == p->o.nspecies - 1;
        const char *u = p->units[l], *lg = last && p->o.log ? "log" : "";
        if (!same || last)
            snprintf(a + strlen(a), cap - strlen(a), "%s%s%s%s%s%s%s", l ? ", " : "", p->names[l],
                     *u || *lg ? " (" : "", u, *u && *lg ? ", " : "", lg, *u || *lg ? ")" : "");
        else
            snprintf(a + strlen(a), cap - strlen(a), "%s%s", l ? ", " : "", p->names[l]);
    }
    p->same_units = same;
    const char *hu = vsv_meta_height_units(m);
    const int heights = m->vert_kind == VSV_VERT_EVEN || m->vert_kind == VSV_VERT_NATIVE;
    snprintf(p->hname, sizeof p->hname, *hu ? "%s (%s)" : "%s%s", heights ? "height" : "level", hu);
    p->metres = heights;
    p->yscale = 1;
    if (heights) {
        p->yscale = fabs(p->ytop - p->ybot) >= 2000 ? 1e-3 : 1;
        snprintf(p->yaxis, sizeof p->yaxis, "height%s (%s)", vsv_meta_above_ground(m) ? " above ground" : "",
                 p->yscale < 1 ? "km" : "m");
    } else {
        char u[40];
        vsv_plot_clean(hu, u, sizeof u);
        snprintf(p->yaxis, sizeof p->yaxis, *u ? "level (%s)" : "level%s", u);
    }
}

/* The levels' interfaces of column (i, j) at time t into z (nz + 1), from
 * the centres: midpoints, half a level beyond the ends; a native column
 * starts at its ground. */
static void interfaces(const vsv_meta *m, int64_t t, int i, int j, double ground, double *z)
{
    const int nz = m->nz;
    double prev = vsv_meta_cell_height_at(m, t, i, j, 0), c = prev;
    const double g0 = nz > 1 ? vsv_meta_cell_height_at(m, t, i, j, 1) - prev : (m->spacing[2] > 0 ? m->spacing[2] : 1);
    z[0] = prev - g0 / 2;
    for (int k = 1; k < nz; k++) {
        c = vsv_meta_cell_height_at(m, t, i, j, k);
        z[k] = 0.5 * (prev + c);
        z[nz] = c + 0.5 * (c - prev);
        prev = c;
    }
    if (nz == 1)
        z[1] = c + g0 / 2;
    if (m->vert_kind == VSV_VERT_NATIVE && isfinite(ground) && ground < vsv_meta_cell_height_at(m, t, i, j, 0))
        z[0] = ground;
}

/* Reads the section: samples every half cell along the line, the nearest
 * column's levels, values and interfaces; the height axis. */
static int section_read(vsv_plot *p, vsv_file *f, vsv_query *q, const vsv_point ends[2], char *msg, size_t cap)
{
    const vsv_meta *m = vsv_file_meta(f);
    const int64_t t = vsv_file_time(f, p->o.step0);
    const vsv_meta pm = vsv_meta_placed(m, t);
    const double di = ends[1].pos[0] - ends[0].pos[0], dj = ends[1].pos[1] - ends[0].pos[1];
    const double cells = hypot(di, dj), r = m->proj.radius > 0 ? m->proj.radius : 6370000;
    const int ns = p->ns = cells * 2 + 1 < 4096 ? (int)ceil(cells * 2) + 1 : 4096, nz = p->nz = m->nz;
    p->nrows = ns * nz;
    p->rows = calloc((size_t)p->nrows, sizeof *p->rows);
    p->ground = malloc((size_t)ns * sizeof *p->ground);
    p->iface = malloc((size_t)ns * (nz + 1) * sizeof *p->iface);
    if (!p->rows || !p->ground || !p->iface) {
        vsv_msg(msg, cap, "out of memory");
        return VSV_ENOMEM;
    }
    double plat = NAN, plon = NAN, d = 0;
    for (int s = 0; s < ns; s++) {
        const double fr = ns > 1 ? (double)s / (ns - 1) : 0;
        const double fi = ends[0].pos[0] + fr * di, fj = ends[0].pos[1] + fr * dj;
        const int i = (int)fmin(fmax(lround(fi), 0), m->nx - 1), j = (int)fmin(fmax(lround(fj), 0), m->ny - 1);
        double lat, lon, clat, clon;
        if (vsv_meta_cell_latlon(&pm, fi, fj, &lat, &lon) || vsv_meta_cell_latlon(&pm, i, j, &clat, &clon)) {
            vsv_msg(msg, cap, "the grid has no latitude and longitude");
            return VSV_EUNSUPPORTED;
        }
        if (s)
            d += arc_km(plat, plon, lat, lon, r);
        plat = lat, plon = lon;
        p->ground[s] = pm.terrain ? pm.terrain[(size_t)j * m->nx + i] : NAN;
        interfaces(m, t, i, j, p->ground[s], p->iface + (size_t)s * (nz + 1));
        for (int k = 0; k < nz; k++) {
            plot_row *row = &p->rows[(size_t)s * nz + k];
            row->time = t;
            row->cell[0] = i, row->cell[1] = j, row->cell[2] = k;
            row->lat = clat, row->lon = clon, row->dist = d;
            row->h = vsv_meta_cell_height_at(m, t, i, j, k);
            if (vsv_query_cell(q, p->o.step0, p->o.species[0], i, j, k, &row->v[0])) {
                vsv_msg(msg, cap, "%s", vsv_query_error(q));
                return VSV_EIO;
            }
        }
    }
    p->length = d;
    /* the height axis: from sea level (or the lowest interface or ground
       below it) to the highest top, or --top; along k for other levels */
    p->up = nz < 2 || p->iface[nz] >= p->iface[0] ? 1 : -1;
    p->ybot = p->ytop = p->iface[0];
    for (int s = 0; s < ns; s++) {
        const double *z = p->iface + (size_t)s * (nz + 1);
        p->ybot = p->up > 0 ? fmin(p->ybot, z[0]) : fmax(p->ybot, z[0]);
        p->ytop = p->up > 0 ? fmax(p->ytop, z[nz]) : fmin(p->ytop, z[nz]);
        if (isfinite(p->ground[s]))
            p->ybot = fmin(p->ybot, p->ground[s]);
    }
    if (m->vert_kind == VSV_VERT_EVEN || m->vert_kind == VSV_VERT_NATIVE)
        p->ybot = fmin(p->ybot, 0);
    return 0;
}

/* Locates the point as vsv-query does at the first step (a moving nest:
 * the first step that has it). */
static int locate(vsv_plot *p, vsv_file *f, double height, vsv_point *pt, char *msg, size_t cap)
{
    const vsv_meta *m = vsv_file_meta(f);
    int rc = vsv_point_locate_at(m, vsv_file_time(f, p->o.step0), p->o.lat[0], p->o.lon[0], height, pt, msg, cap);
    for (int t = p->o.step0 + 1; rc == VSV_ERANGE && m->nmoves && t <= p->o.step1; t++)
        if (!vsv_point_locate_at(m, vsv_file_time(f, t), p->o.lat[0], p->o.lon[0], height, pt, NULL, 0))
            rc = 0;
    return rc;
}

/* Reads a series (one row a step) or a profile (one row a level), as
 * vsv-query --at and --profile print them. */
static int column_read(vsv_plot *p, vsv_file *f, vsv_query *q, char *msg, size_t cap)
{
    const vsv_meta *m = vsv_file_meta(f);
    const int series = p->o.kind == VSV_PLOT_SERIES;
    const double height = series ? p->o.at_height : NAN;
    vsv_point pt;
    int rc = locate(p, f, height, &pt, msg, cap);
    if (rc)
        return rc;
    const int nt = series ? p->o.step1 - p->o.step0 + 1 : 1, nk = series ? 1 : m->nz;
    p->nrows = nt * nk;
    if (!(p->rows = calloc((size_t)p->nrows, sizeof *p->rows))) {
        vsv_msg(msg, cap, "out of memory");
        return VSV_ENOMEM;
    }
    plot_row *row = p->rows;
    for (int t = p->o.step0; t < p->o.step0 + nt; t++) {
        const int64_t time = vsv_file_time(f, t);
        int outside = 0;
        if ((series && !isnan(height) && m->nheights > 1) || m->nmoves) {
            rc = vsv_point_locate_at(m, time, p->o.lat[0], p->o.lon[0], height, &pt, msg, cap);
            outside = rc == VSV_ERANGE && m->nmoves; /* the nest has left the point: no data then */
            if (rc && !outside)
                return rc;
        }
        for (int k = series ? -1 : 0; k < (series ? 0 : m->nz); k++, row++) {
            double pos[3] = {pt.pos[0], pt.pos[1], pt.pos[2]};
            int *cell = row->cell;
            memcpy(cell, pt.cell, sizeof pt.cell);
            if (k >= 0)
                pos[2] = cell[2] = k;
            row->time = time;
            row->lat = pt.lat, row->lon = pt.lon;
            row->h = outside ? NAN : vsv_meta_cell_height_at(m, time, cell[0], cell[1], cell[2]);
            if (outside)
                cell[0] = cell[1] = cell[2] = -1;
            for (int l = 0; l < p->o.nspecies; l++) {
                row->v[l] = NAN;
                if (!outside && vsv_query_sample(q, t, p->o.species[l], pos, VSV_INTERP_NEAREST, &row->v[l])) {
                    vsv_msg(msg, cap, "%s", vsv_query_error(q));
                    return VSV_EIO;
                }
            }
        }
    }
    /* a profile's height axis: its levels' span, from sea level; its ground */
    if (!series) {
        const vsv_meta pm = vsv_meta_placed(m, p->rows[0].time);
        if (!(p->ground = malloc(sizeof *p->ground))) {
            vsv_msg(msg, cap, "out of memory");
            return VSV_ENOMEM;
        }
        p->ground[0] = pm.terrain ? pm.terrain[(size_t)pt.cell[1] * m->nx + pt.cell[0]] : NAN;
        const plot_row *r0 = &p->rows[0], *r1 = &p->rows[p->nrows - 1];
        p->up = r1->h >= r0->h ? 1 : -1;
        const double g = p->nrows > 1 ? (r1->h - p->rows[p->nrows - 2].h) / 2 : 1;
        p->ybot = m->vert_kind == VSV_VERT_EVEN || m->vert_kind == VSV_VERT_NATIVE ? fmin(0, r0->h) : r0->h;
        p->ytop = r1->h + g;
    }
    return 0;
}

/* Whether height h shows on the height axis. */
static int shown(const vsv_plot *p, double h)
{
    return p->o.kind == VSV_PLOT_SERIES || ((h - p->ybot) * p->up >= 0 && (p->ytop - h) * p->up >= 0);
}

/* The values' range: the options', else the least and greatest drawn (on
 * a log scale the positive ones, at most four decades below the top). */
static int value_range(vsv_plot *p, const vsv_file *f, char *msg, size_t cap)
{
    double lo = INFINITY, hi = -INFINITY;
    for (int r = 0; r < p->nrows; r++)
        for (int l = 0; l < p->o.nspecies; l++) {
            const double v = p->rows[r].v[l];
            if (isfinite(v) && (!p->o.log || v > 0) && shown(p, p->rows[r].h))
                lo = fmin(lo, v), hi = fmax(hi, v);
        }
    if (p->o.log && !isfinite(p->o.lo) && !(hi > 0)) {
        vsv_msg(msg, cap, "no value above 0 to put on a log scale");
        return VSV_ERANGE;
    }
    if (!(lo <= hi)) { /* nothing but no data: an empty panel, its scale made up */
        vsv_msg(msg, cap, "nothing to plot: every value in view is no data (below the ground or outside the levels)");
        return VSV_ERANGE;
    }
    if (p->o.log) {
        lo = fmax(lo, hi * 1e-4);
        if (!(hi > lo))
            lo = hi / 10;
    } else if (!(hi > lo)) {
        /* one value everywhere in view (no cloud yet: CLW 0): the species'
         * range over the file, so the bar says where that value stands (a
         * made-up 0 to 1 read as up to 1 kg/kg); ten per cent either way
         * when the file holds that one value only */
        double flo = lo, fhi = hi;
        for (int l = 0; l < p->o.nspecies; l++) {
            const vsv_quant *qt = vsv_file_quant(f, p->o.species[l]);
            if (qt && isfinite(qt->lo) && isfinite(qt->hi))
                flo = fmin(flo, qt->lo), fhi = fmax(fhi, qt->hi);
        }
        if (fhi > flo) {
            lo = flo, hi = fhi;
        } else {
            const double d = lo != 0 ? fabs(lo) * 0.1 : 1;
            lo = lo != 0 ? lo - d : lo, hi += d;
        }
    }
    p->lo = isfinite(p->o.lo) ? p->o.lo : lo;
    p->hi = isfinite(p->o.hi) ? p->o.hi : hi;
    p->vlo = p->lo, p->vhi = p->hi;
    if (!isfinite(p->o.lo) && p->o.kind != VSV_PLOT_SECTION) { /* a value axis from tick to tick */
        if (p->o.log) {
            p->vlo = pow(10, floor(log10(p->lo) + 1e-9)), p->vhi = pow(10, ceil(log10(p->hi) - 1e-9));
        } else {
            const double st = vsv_plot_nice_step(p->lo, p->hi, 6);
            p->vlo = floor(p->lo / st + 1e-9) * st, p->vhi = ceil(p->hi / st - 1e-9) * st;
        }
    }
    return 0;
}

/* The title (the option's, or the species with the time or place) and the subtitle. */
static void titles(vsv_plot *p, vsv_file *f, const char *title)
{
    const vsv_meta *m = vsv_file_meta(f);
    char names[600] = "", t0[32], t1[32], a[64], b[64], model[80];
    for (int l = 0; l < p->o.nspecies; l++)
        snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", l ? ", " : "", p->names[l]);
    vsv_cal_format(p->cal, vsv_file_time(f, p->o.step0), t0, sizeof t0);
    vsv_cal_format(p->cal, vsv_file_time(f, p->o.step1), t1, sizeof t1);
    place(p->o.lat[0], p->o.lon[0], a, sizeof a);
    vsv_plot_clean(m->model, model, sizeof model);
    const char *src = p->source[0] ? p->source : "";
    char *T = p->title, *S = p->subtitle;
    const size_t tc = sizeof p->title, sc = sizeof p->subtitle;
    if (p->o.kind == VSV_PLOT_SECTION) {
        char desc[160];
        place(p->o.lat[1], p->o.lon[1], b, sizeof b);
        vsv_plot_clean(m->vars[p->o.species[0]].description, desc, sizeof desc);
        snprintf(T, tc, "%s at %s", names, t0);
        snprintf(S, sc, "%s%s%s to %s (%.0f km), %s%s%s", desc, *desc ? ", " : "", a, b, p->length, model,
                 *src ? ", " : "", src);
    } else {
        char h[64] = "lowest level";
        const char *hu = vsv_meta_height_units(m);
        if (!isnan(p->o.at_height))
            snprintf(h, sizeof h, "%g%s%s", p->o.at_height, *hu ? " " : "", hu);
        const plot_row *r = &p->rows[0];
        if (p->o.kind == VSV_PLOT_SERIES) {
            snprintf(T, tc, "%s at %s, %s", names, a, h);
            snprintf(S, sc, "%s to %s, cell %d,%d,%d, %s%s%s", t0, t1, r->cell[0], r->cell[1], r->cell[2], model,
                     *src ? ", " : "", src);
        } else {
            place(r->lat, r->lon, b, sizeof b);
            snprintf(T, tc, "%s at %s, %s", names, a, t0);
            snprintf(S, sc, "column %d,%d at %s, %s%s%s", r->cell[0], r->cell[1], b, model, *src ? ", " : "", src);
        }
    }
    if (title && title[0])
        vsv_plot_clean(title, T, tc);
}

/* The options against the file. */
static int check_opts(const vsv_plot_opts *o, const vsv_meta *m, int nsteps, char *msg, size_t cap)
{
    int bad = o->kind < VSV_PLOT_SECTION || o->kind > VSV_PLOT_PROFILE || o->nspecies < 1 ||
              o->nspecies > VSV_PLOT_MAXSPECIES || (o->kind == VSV_PLOT_SECTION && o->nspecies != 1);
    for (int l = 0; l < o->nspecies && !bad; l++)
        bad = o->species[l] < 0 || o->species[l] >= m->nvars;
    if (bad) {
        vsv_msg(msg, cap, "a plot takes 1 to %d species (a section: 1) of the file's", VSV_PLOT_MAXSPECIES);
        return VSV_EINVAL;
    }
    if (o->step0 < 0 || o->step1 < o->step0 || o->step1 >= nsteps) {
        vsv_msg(msg, cap, "steps %d..%d: the file has 0..%d", o->step0, o->step1, nsteps - 1);
        return VSV_ERANGE;
    }
    if (o->size[0] < 200 || o->size[1] < 150 || o->size[0] > 8192 || o->size[1] > 8192) {
        vsv_msg(msg, cap, "a plot is 200x150 to 8192x8192 pixels");
        return VSV_EINVAL;
    }
    if ((isfinite(o->lo) || isfinite(o->hi)) && !(o->lo < o->hi && isfinite(o->hi - o->lo))) {
        vsv_msg(msg, cap, "a range needs LO < HI");
        return VSV_EINVAL;
    }
    if (o->log && isfinite(o->lo) && !(o->lo > 0)) {
        vsv_msg(msg, cap, "a log scale needs LO > 0");
        return VSV_EINVAL;
    }
    int known = !o->colormap[0];
    for (const char *const *c = vsv_tf_colormaps(); *c && !known; c++)
        known = !strcmp(*c, o->colormap);
    if (!known) {
        vsv_msg(msg, cap, "no colour map '%s'", o->colormap);
        return VSV_EINVAL;
    }
    if (o->kind == VSV_PLOT_SECTION && fabs(o->lat[0] - o->lat[1]) < 1e-9 && fabs(o->lon[0] - o->lon[1]) < 1e-9) {
        vsv_msg(msg, cap, "the two ends are the same point");
        return VSV_EINVAL;
    }
    return 0;
}

int vsv_plot_create(vsv_file *f, const vsv_plot_opts *o, vsv_plot **out, char *msg, size_t cap)
{
    *out = NULL;
    const vsv_meta *m = vsv_file_meta(f);
    vsv_file_info info;
    vsv_file_info_get(f, &info);
    int rc = check_opts(o, m, info.nsteps, msg, cap);
    if (rc)
        return rc;
    vsv_plot *p = calloc(1, sizeof *p);
    vsv_query *q = NULL;
    if (!p) {
        vsv_msg(msg, cap, "out of memory");
        return VSV_ENOMEM;
    }
    p->o = *o;
    p->o.title = p->o.source = NULL;
    if (o->kind != VSV_PLOT_SERIES)
        p->o.step1 = o->step0;
    if (o->source) {
        const char *slash = strrchr(o->source, '/');
        vsv_plot_clean(slash && slash[1] ? slash + 1 : o->source, p->source, sizeof p->source);
    }
    p->cal = vsv_meta_calendar(m);
    if ((rc = vsv_query_create(f, &q))) {
        vsv_msg(msg, cap, "%s", q ? vsv_query_error(q) : vsv_strerror(rc));
        goto fail;
    }
    if (o->kind == VSV_PLOT_SECTION) {
        vsv_point ends[2];
        const int64_t t = vsv_file_time(f, o->step0);
        for (int e = 0; e < 2 && !rc; e++)
            rc = vsv_point_locate_at(m, t, o->lat[e], o->lon[e], NAN, &ends[e], msg, cap);
        if (rc || (rc = section_read(p, f, q, ends, msg, cap)))
            goto fail;
    } else if ((rc = column_read(p, f, q, msg, cap))) {
        goto fail;
    }
    if (isfinite(o->top) && p->o.kind != VSV_PLOT_SERIES) {
        if (!((o->top - p->ybot) * p->up > 0)) {
            vsv_msg(msg, cap, "--top %g: not above the axis' bottom (%g)", o->top, p->ybot);
            rc = VSV_EINVAL;
            goto fail;
        }
        p->ytop = o->top;
    }
    words(p, m);
    if ((rc = value_range(p, f, msg, cap)))
        goto fail;
    titles(p, f, o->title);
    vsv_query_free(q);
    *out = p;
    return 0;
fail:
    vsv_query_free(q);
    vsv_plot_free(p);
    return rc;
}

void vsv_plot_free(vsv_plot *p)
{
    if (!p)
        return;
    free(p->rows);
    free(p->ground);
    free(p->iface);
    free(p);
}

void vsv_plot_range(const vsv_plot *p, double *lo, double *hi)
{
    *lo = p->o.kind == VSV_PLOT_SECTION ? p->lo : p->vlo;
    *hi = p->o.kind == VSV_PLOT_SECTION ? p->hi : p->vhi;
}

int vsv_plot_csv(const vsv_plot *p, FILE *fp)
{
    const int sec = p->o.kind == VSV_PLOT_SECTION;
    fprintf(fp, "time,%si,j,k,lat,lon,", sec ? "distance (km)," : "");
    vsv_csv_field(fp, p->hname);
    for (int l = 0; l < p->o.nspecies; l++) {
        char col[300];
        snprintf(col, sizeof col, *p->units[l] ? "%s (%s)" : "%s%s", p->names[l], p->units[l]);
        fputc(',', fp);
        vsv_csv_field(fp, col);
    }
    fputc('\n', fp);
    for (int r = 0; r < p->nrows; r++) {
        const plot_row *w = &p->rows[r];
        char iso[32];
        vsv_cal_format(p->cal, w->time, iso, sizeof iso);
        fprintf(fp, "%s,", iso);
        if (sec)
            fprintf(fp, "%.3f,", w->dist);
        fprintf(fp, "%d,%d,%d,%.6f,%.6f,%.9g", w->cell[0], w->cell[1], w->cell[2], w->lat, w->lon, w->h);
        for (int l = 0; l < p->o.nspecies; l++)
            if (isnan(w->v[l]))
                fputs(",NaN", fp);
            else
                fprintf(fp, ",%.9g", w->v[l]);
        fputc('\n', fp);
    }
    return fflush(fp) || ferror(fp) ? VSV_EIO : 0;
}
