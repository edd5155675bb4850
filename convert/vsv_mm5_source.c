/* vsv_mm5_source.c — MM5 v3 output as a Vesuvius source: the cross-point
 * grid (dot fields averaged to cross points, the last row and column of
 * cross fields dropped), projection metres from the big header, sigma levels
 * turned into heights with MM5's reference-state formula (fixed in time),
 * then either kept (native) or resampled per column onto even heights with
 * cells below the ground empty. INPUT-FORMATS.md §1 has every formula. */
#include "vsv_mm5.h"
#include "vsv_source_internal.h"
#include "vsv_vgrid.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define R_DRY 287.04
#define G0 9.81

typedef struct mm5src {
    vsv_mm5 *m;
    int IX, JX, KX, nx, ny;
    /* pressure levels (REGRID, INTERPB: YXP): KP levels bottom-up, the first
     * the surface; placed by each column's geopotential height H, which
     * changes with time, so the even plan is redone per output time */
    int KP, plev, plan_t;
    int16_t *zidx; /* KP*plane: file level of each above-ground level, bottom-up */
    float *hraw;   /* KP*plane: H of the planned time, cross points */
    int has_sigma;
    float *zn;    /* KX*ny*nx heights of the half-sigma levels, k bottom-up */
    float *pstar; /* ny*nx reference p* (Pa) of the sigma levels, and their */
    float *sigma; /* KX sigma values (file order, k = 1 the top) and PTOP: */
    double ptop;  /* the reference pressure p0 = p* sigma + PTOP */
    vsv_vgrid vg; /* even: the resampling (heights are fixed in time) */
    int even;
    float *raw;     /* scratch: one record */
    float *nat;     /* scratch: native cross volume */
    int *period_of; /* source time → MM5 period */
} mm5src;

static int mm5_probe(const unsigned char *h, size_t n) { return vsv_mm5_probe(h, n); }

/* A cross-point plane (ny*nx) of a YX field of period p: 0, 1 if absent, or
 * a negative error when the record is not one plane of the domain. */
static int cross_plane(vsv_source *s, mm5src *x, int p, const char *name, float *out)
{
    const int fi = vsv_mm5_find(x->m, p, name);
    if (fi < 0)
        return 1;
    const vsv_mm5_field *f = vsv_mm5_field_at(x->m, fi);
    if (strcmp(f->order, "YX") || f->end[0] - f->start[0] + 1 != x->IX || f->end[1] - f->start[1] + 1 != x->JX ||
        f->bytes != (uint64_t)x->IX * x->JX * 4)
        return vsv_source_fail(s, VSV_ECORRUPT,
                               "record %d at byte offset %llu: %s is not a %dx%d YX field (%llu bytes)", f->record,
                               (unsigned long long)f->offset, name, x->IX, x->JX, (unsigned long long)f->bytes);
    if (vsv_mm5_read(x->m, f, x->raw))
        return vsv_source_fail(s, VSV_ETRUNC, VSV_CUT_TEXT);
    const int dot = !strcmp(f->stag, "D");
    for (int j = 0; j < x->ny; j++)
        for (int i = 0; i < x->nx; i++) {
            /* file order (I fastest): raw[J*IX + I]; here I = j (south-north), J = i */
            const float *r = x->raw;
            float v = r[(size_t)i * x->IX + j];
            if (dot)
                v = 0.25f * (v + r[(size_t)i * x->IX + j + 1] + r[(size_t)(i + 1) * x->IX + j] +
                             r[(size_t)(i + 1) * x->IX + j + 1]);
            out[(size_t)j * x->nx + i] = v;
        }
    return 0;
}

/* The time of period p: 0, 1 when it has no date (set-up files), or an error
 * naming the record whose date is not a date. */
static int period_time(vsv_source *s, const vsv_mm5 *m, int p, int64_t *t)
{
    for (int i = 0; i < vsv_mm5_nfields(m); i++) {
        const vsv_mm5_field *f = vsv_mm5_field_at(m, i);
        if (f->period == p) {
            const int rc = vsv_mm5_date(f->date, t);
            if (rc < 0)
                return vsv_source_fail(s, VSV_ECORRUPT, "record %d (%s, output time %d): date \"%s\" is not a date",
                                       f->record, f->name, p, f->date);
            return rc;
        }
    }
    return 1;
}

/* A YXP field of period p as a native cross volume (KP*plane, bottom-up as
 * in the file: level 0 is the surface), after checking its shape. */
static int plev_volume(vsv_source *s, mm5src *x, int p, const char *name, float *nat)
{
    const int idx = vsv_mm5_find(x->m, p, name);
    if (idx < 0)
        return vsv_source_fail(s, VSV_ECORRUPT, "field %s missing from output time %d", name, p);
    const vsv_mm5_field *f = vsv_mm5_field_at(x->m, idx);
    if (strcmp(f->order, "YXP") || f->end[0] - f->start[0] + 1 != x->IX || f->end[1] - f->start[1] + 1 != x->JX ||
        f->bytes != (uint64_t)x->IX * x->JX * (uint64_t)x->KP * 4)
        return vsv_source_fail(s, VSV_ECORRUPT,
                               "record %d at byte offset %llu: %s (output time %d) is %s %dx%d, %llu bytes; "
                               "expected YXP %dx%dx%d",
                               f->record, (unsigned long long)f->offset, f->name, p, f->order,
                               f->end[0] - f->start[0] + 1, f->end[1] - f->start[1] + 1, (unsigned long long)f->bytes,
                               x->IX, x->JX, x->KP);
    if (vsv_mm5_read(x->m, f, x->raw))
        return vsv_source_fail(s, VSV_ETRUNC, VSV_CUT_TEXT);
    const int dot = !strcmp(f->stag, "D");
    const size_t plane = (size_t)x->nx * x->ny, fplane = (size_t)x->IX * x->JX;
    for (int k = 0; k < x->KP; k++) {
        const float *a = x->raw + (size_t)k * fplane;
        float *o = nat + (size_t)k * plane;
        for (int j = 0; j < x->ny; j++)
            for (int i = 0; i < x->nx; i++) {
                const size_t c = (size_t)i * x->IX + j;
                o[(size_t)j * x->nx + i] = dot ? 0.25f * (a[c] + a[c + 1] + a[c + x->IX] + a[c + x->IX + 1]) : a[c];
            }
    }
    return 0;
}

/* The heights of output time t's pressure levels: H into hraw; per column the
 * levels above the ground (level 0, the surface, first) into zidx/zn, the
 * column's top repeated above its last level, so heights never decrease. */
static int plev_heights(vsv_source *s, mm5src *x, int t)
{
    const int p = x->period_of ? x->period_of[t] : 0;
    int rc = plev_volume(s, x, p, "H", x->hraw);
    if (rc)
        return rc;
    const size_t plane = (size_t)x->nx * x->ny;
    for (size_t c = 0; c < plane; c++) {
        int n = 0;
        float top = x->hraw[c];
        for (int k = 0; k < x->KP; k++) {
            const float h = x->hraw[(size_t)k * plane + c];
            if (k == 0 || h > top) {
                x->zidx[(size_t)n * plane + c] = (int16_t)k;
                x->zn[(size_t)n * plane + c] = top = h;
                n++;
            }
        }
        for (int k = n; k < x->KP; k++) {
            x->zidx[(size_t)k * plane + c] = x->zidx[(size_t)(n - 1) * plane + c];
            x->zn[(size_t)k * plane + c] = top;
        }
    }
    x->plan_t = t;
    return 0;
}

/* Native pressure levels: every time's heights in every column, H's, the
 * surface level (0) at the ground; a level H puts under the ground (REGRID
 * extrapolates there) is squeezed 1 cm above the one below, so heights
 * rise, and its cells are empty (plev_read). */
static int plev_native_heights(vsv_source *s, mm5src *x)
{
    const size_t plane = (size_t)x->nx * x->ny;
    float *z = malloc(plane * (size_t)x->KP * sizeof *z);
    if (!z)
        return VSV_ENOMEM;
    int rc = 0;
    for (int t = 0; t < s->ntimes && !rc; t++) {
        if ((rc = plev_heights(s, x, t)))
            break;
        for (size_t c = 0; c < plane; c++)
            for (int k = 0; k < x->KP; k++) {
                const size_t i = (size_t)k * plane + c;
                z[i] = k ? fmaxf(x->hraw[i], z[i - plane] + 0.01f) : x->hraw[c];
            }
        rc = vsv_source_native_heights(s, t, z);
    }
    free(z);
    x->plan_t = -1;
    return rc;
}

static int plev_read(vsv_source *s, mm5src *x, const vsv_field_info *fi, int t, float *out)
{
    const size_t plane = (size_t)x->nx * x->ny;
    int rc;
    if (!x->even) { /* the file's levels; those under the ground empty */
        if ((x->plan_t != t && (rc = plev_heights(s, x, t))) ||
            (rc = plev_volume(s, x, x->period_of[t], fi->name, out)))
            return rc;
        for (int k = 1; k < x->KP; k++)
            for (size_t c = 0; c < plane; c++)
                if (!(x->hraw[(size_t)k * plane + c] > x->hraw[c]))
                    out[(size_t)k * plane + c] = NAN;
        return 0;
    }
    if (x->plan_t != t) {
        if ((rc = plev_heights(s, x, t)))
            return rc;
        if (vsv_vgrid_plan(&x->vg, x->zn, x->KP, plane, s->grid.terrain, s->grid.nz, s->grid.origin[2],
                           s->grid.spacing[2]))
            return VSV_ENOMEM;
    }
    float *nat = x->nat, *col = x->raw; /* raw is free again once nat is built */
    if ((rc = plev_volume(s, x, x->period_of[t], fi->name, nat)))
        return rc;
    for (int k = 0; k < x->KP; k++)
        for (size_t c = 0; c < plane; c++)
            col[(size_t)k * plane + c] = nat[(size_t)x->zidx[(size_t)k * plane + c] * plane + c];
    vsv_vgrid_apply(&x->vg, col, out);
    return 0;
}

static int is_default_name(const char *n)
{
    static const char *const d[] = {"CLW", "RNW", "ICE", "SNOW", "GRAUPEL", "Q", NULL};
    for (int i = 0; d[i]; i++)
        if (!strcmp(n, d[i]))
            return 1;
    return 0;
}

/* MM5's reference state from the big header (-999 where the program that
 * wrote the file did not fill it). */
typedef struct mm5_base {
    double ptop, p00, ts0, a, tiso;
} mm5_base;

/* The domain from the big header and the vertical from the fields: sigma
 * levels (KX) or, without them, pressure levels placed by H (KP); the
 * scratch buffers sized for them. */
static int mm5_domain(vsv_source *s, mm5src *x)
{
    vsv_mm5 *m = x->m;
    x->IX = vsv_mm5_bhi(m, 16, 1);
    x->JX = vsv_mm5_bhi(m, 17, 1);
    if (x->IX < 3 || x->JX < 3 || x->IX > VSV_MAX_DIM || x->JX > VSV_MAX_DIM)
        return vsv_source_fail(s, VSV_ECORRUPT, "big header: domain of %d x %d dot points", x->IX, x->JX);
    x->nx = x->JX - 1;
    x->ny = x->IX - 1;
    /* the vertical: from the first 3-D sigma field, SIGMAH and PSTARCRS */
    x->KX = 0;
    for (int i = 0; i < vsv_mm5_nfields(m); i++) {
        const vsv_mm5_field *f = vsv_mm5_field_at(m, i);
        if (!strcmp(f->order, "YXS")) {
            x->KX = f->end[2] - f->start[2] + 1;
            if (x->KX > VSV_MAX_DIM)
                return vsv_source_fail(s, VSV_ECORRUPT, "record %d: %s has %d sigma levels, more than %d", f->record,
                                       f->name, x->KX, VSV_MAX_DIM);
            break;
        }
    }
    /* no sigma levels: pressure levels placed by H (REGRID, INTERPB) */
    x->plan_t = -1;
    if (!x->KX)
        for (int i = 0; i < vsv_mm5_nfields(m); i++) {
            const vsv_mm5_field *f = vsv_mm5_field_at(m, i);
            if (!strcmp(f->order, "YXP") && !strcmp(f->name, "H")) {
                x->KP = f->end[2] - f->start[2] + 1;
                if (x->KP < 2 || x->KP > 1000 || f->ndim != 3)
                    return vsv_source_fail(s, VSV_ECORRUPT, "record %d: H has %d pressure levels", f->record, x->KP);
                x->plev = 1;
                break;
            }
        }
    const size_t plane = (size_t)x->nx * x->ny;
    const int kmax = x->KX > x->KP ? x->KX : x->KP;
    x->raw = malloc((size_t)x->IX * x->JX * (size_t)(kmax + 2) * sizeof(float));
    x->nat = malloc(plane * (size_t)(kmax + 1) * sizeof(float));
    if (!x->raw || !x->nat)
        return VSV_ENOMEM;
    return 0;
}

/* The grid's plan position, projection, run description and the big
 * header's attributes; the reference state into b. */
static int mm5_header(vsv_source *s, mm5src *x, mm5_base *b)
{
    vsv_mm5 *m = x->m;
    vsv_meta *g = &s->grid;
    g->nx = x->nx;
    g->ny = x->ny;
    /* horizontal position of cross point (0,0), projection metres */
    const double d = vsv_mm5_bhr(m, 1, 1), ds = vsv_mm5_bhr(m, 9, 1);
    const int IXc = vsv_mm5_bhi(m, 5, 1), JXc = vsv_mm5_bhi(m, 6, 1);
    if (!(d > 0) || !(ds > 0))
        return vsv_source_fail(s, VSV_ECORRUPT, "big header: grid distance %g / %g m", d, ds);
    g->origin[0] = (vsv_mm5_bhr(m, 11, 1) - (JXc + 1) / 2.0) * d + ds / 2;
    g->origin[1] = (vsv_mm5_bhr(m, 10, 1) - (IXc + 1) / 2.0) * d + ds / 2;
    g->spacing[0] = g->spacing[1] = ds;
    const int proj = vsv_mm5_bhi(m, 7, 1);
    g->proj.kind = proj == 1 ? VSV_PROJ_LCC : proj == 2 ? VSV_PROJ_PSTEREO : proj == 3 ? VSV_PROJ_MERCATOR : -1;
    if (g->proj.kind < 0)
        return vsv_source_fail(s, VSV_EUNSUPPORTED, "big header: unknown projection %d", proj);
    g->proj.lat0 = vsv_mm5_bhr(m, 2, 1);
    g->proj.lon0 = vsv_mm5_bhr(m, 3, 1);
    g->proj.lat1 = vsv_mm5_bhr(m, 5, 1);
    g->proj.lat2 = vsv_mm5_bhr(m, 6, 1);
    if (g->proj.kind != VSV_PROJ_LCC)
        g->proj.lat2 = g->proj.lat1;
    g->proj.radius = 6370000;
    snprintf(g->model, sizeof g->model, "MM5 v3");
    const int prog = vsv_mm5_bhi(m, 1, 1);
    const char *pname = prog == 1                  ? "TERRAIN"
                        : prog == 2                ? "REGRID"
                        : prog == 5                ? "INTERPF"
                        : prog == 6                ? "LOWBDY"
                        : prog == 7                ? "BDYOUT"
                        : prog == 8                ? "INTERPB"
                        : prog >= 11 && prog <= 16 ? "MM5"
                                                   : "unknown";
    /* the model's start (MM5's own header; the pre-processors' files leave it
     * unset and carry their times in the fields' headers: no clause) */
    char start[48] = "";
    if (vsv_mm5_bhi(m, 5, 11) > 0)
        snprintf(start, sizeof start, ", start %04d-%02d-%02dT%02d:%02d:%02dZ", vsv_mm5_bhi(m, 5, 11),
                 vsv_mm5_bhi(m, 6, 11), vsv_mm5_bhi(m, 7, 11), vsv_mm5_bhi(m, 8, 11), vsv_mm5_bhi(m, 9, 11),
                 vsv_mm5_bhi(m, 10, 11));
    snprintf(g->run, sizeof g->run, "%s output, domain %d, %d x %d dot points, %.4g km grid%s", pname,
             vsv_mm5_bhi(m, 13, 1), x->IX, x->JX, ds / 1000, start);
    char buf[160];
    const double PTOP = vsv_mm5_bhr(m, 2, 2), P00 = vsv_mm5_bhr(m, 2, 5), TS0 = vsv_mm5_bhr(m, 3, 5),
                 A = vsv_mm5_bhr(m, 4, 5), TISO = vsv_mm5_bhr(m, 5, 5);
    *b = (mm5_base){PTOP, P00, TS0, A, TISO};
    snprintf(buf, sizeof buf, "%d", prog);
    vsv_meta_add_attr(g, "MM5 program", buf);
    snprintf(buf, sizeof buf, "%g Pa", PTOP);
    vsv_meta_add_attr(g, "PTOP", buf);
    snprintf(buf, sizeof buf, "P00 %g Pa, TS0 %g K, TLP %g K, TISO %g K", P00, TS0, A, TISO);
    if (P00 > 0) /* -999: not filled by the program that wrote the file */
        vsv_meta_add_attr(g, "base state", buf);
    snprintf(buf, sizeof buf, "%d", vsv_mm5_bhi(m, 3, 13));
    if (vsv_mm5_bhi(m, 3, 13) != -999)
        vsv_meta_add_attr(g, "IMPHYS", buf);
    return 0;
}

/* Terrain and land use (period 0), each dropped when the file has none. */
static int mm5_surface(vsv_source *s, mm5src *x)
{
    vsv_mm5 *m = x->m;
    vsv_meta *g = &s->grid;
    int rc;
    if (vsv_meta_alloc_terrain(g) || vsv_meta_alloc_landuse(g))
        return VSV_ENOMEM;
    if ((rc = cross_plane(s, x, 0, "TERRAIN", g->terrain)) < 0)
        return rc;
    if (rc) {
        free(g->terrain);
        g->terrain = NULL;
    }
    if ((rc = cross_plane(s, x, 0, "LAND USE", g->landuse)) < 0)
        return rc;
    if (rc) {
        free(g->landuse);
        g->landuse = NULL;
    } else {
        /* which category is water: the big header says (bhi(23,1), "... WATER CATEGORY") */
        char what[96], buf[160];
        vsv_mm5_bhic(m, 23, 1, what, sizeof what);
        const int water = vsv_mm5_bhi(m, 23, 1);
        if (strstr(what, "WATER CATEGORY") && water >= 0 && water < 64) {
            snprintf(buf, sizeof buf, "%d", water);
            vsv_meta_add_attr(g, "landuse_water", buf);
        }
    }
    return 0;
}

/* Heights of the half-sigma levels into x->zn when the file has SIGMAH and
 * a reference state (x->has_sigma); the sigma values into sig. */
static int mm5_sigma_heights(vsv_source *s, mm5src *x, const mm5_base *b, float *sig)
{
    vsv_mm5 *m = x->m;
    const vsv_meta *g = &s->grid;
    const double PTOP = b->ptop, P00 = b->p00, TS0 = b->ts0, A = b->a, TISO = b->tiso;
    const size_t plane = (size_t)x->nx * x->ny;
    const int isig = vsv_mm5_find(m, 0, "SIGMAH");
    x->has_sigma = x->KX > 0 && isig >= 0 && P00 > 0 && A > 0 && TS0 > 0 && PTOP > 0;
    if (!x->has_sigma)
        return 0;
    const vsv_mm5_field *fs = vsv_mm5_field_at(m, isig);
    if ((int)(fs->bytes / 4) != x->KX)
        return vsv_source_fail(s, VSV_ECORRUPT, "record %d: SIGMAH has %llu levels, 3-D fields %d", fs->record,
                               (unsigned long long)(fs->bytes / 4), x->KX);
    if (vsv_mm5_read(m, fs, sig))
        return vsv_source_fail(s, VSV_ETRUNC, VSV_CUT_TEXT);
    float *pstar = x->pstar = malloc(plane * sizeof *pstar);
    x->zn = malloc(plane * (size_t)x->KX * sizeof *x->zn);
    x->sigma = malloc((size_t)x->KX * sizeof *x->sigma);
    if (!pstar || !x->zn || !x->sigma)
        return VSV_ENOMEM;
    memcpy(x->sigma, sig, (size_t)x->KX * sizeof *sig);
    x->ptop = PTOP;
    int rc;
    if ((rc = cross_plane(s, x, 0, "PSTARCRS", pstar)) < 0)
        return rc;
    if (rc) {
        if (!g->terrain)
            return vsv_source_fail(s, VSV_ECORRUPT, "neither PSTARCRS nor TERRAIN: heights unknown");
        for (size_t c = 0; c < plane; c++) {
            double ps0 = P00 * exp(-TS0 / A + sqrt((TS0 / A) * (TS0 / A) - 2 * G0 * g->terrain[c] / (A * R_DRY)));
            pstar[c] = (float)(ps0 - PTOP);
        }
    }
    const double ref[4] = {P00, TS0, A, TISO};
    for (int k = 0; k < x->KX; k++)
        for (size_t c = 0; c < plane; c++)
            x->zn[(size_t)k * plane + c] = (float)vsv_mm5_ref_height(pstar[c] * sig[x->KX - 1 - k] + PTOP, ref);
    return 0;
}

/* The vertical axis of a pressure-level file: heights from H at the first
 * time, even when they allow, and the levels described. */
static int mm5_plev_axis(vsv_source *s, mm5src *x)
{
    vsv_mm5 *m = x->m;
    vsv_meta *g = &s->grid;
    const size_t plane = (size_t)x->nx * x->ny;
    int rc;
    char buf[160];
    x->hraw = malloc(plane * (size_t)x->KP * sizeof *x->hraw);
    x->zn = malloc(plane * (size_t)x->KP * sizeof *x->zn);
    x->zidx = malloc(plane * (size_t)x->KP * sizeof *x->zidx);
    if (!x->hraw || !x->zn || !x->zidx)
        return VSV_ENOMEM;
    if (!g->terrain)
        return vsv_source_fail(s, VSV_ECORRUPT, "pressure levels without TERRAIN: the ground is unknown");
    if ((rc = plev_heights(s, x, 0)))
        return rc;
    x->plan_t = -1; /* heights known, no even plan yet */
    const int even = vsv_source_axis(s, x->hraw, x->KP, 100.0);
    if (even < 0)
        return even;
    x->even = even;
    float pl[1000];
    const int ip = vsv_mm5_find(m, 0, "PRESSURE");
    const vsv_mm5_field *fp = ip >= 0 ? vsv_mm5_field_at(m, ip) : NULL;
    if (fp && fp->bytes == (uint64_t)x->KP * 4) {
        if (vsv_mm5_read(m, fp, pl))
            return vsv_source_fail(s, VSV_ETRUNC, VSV_CUT_TEXT);
        snprintf(buf, sizeof buf,
                 "%d pressure levels, %g hPa (surface) to %g hPa, placed by the geopotential "
                 "height H of each column and time",
                 x->KP, pl[0] / 100, pl[x->KP - 1] / 100);
    } else {
        snprintf(buf, sizeof buf, "%d pressure levels placed by the geopotential height H of each column and time",
                 x->KP);
    }
    vsv_meta_add_attr(g, "vertical", buf);
    return 0;
}

/* The vertical axis of a sigma file: even heights with a resampling plan,
 * or the native levels with their heights in every column. */
static int mm5_sigma_axis(vsv_source *s, mm5src *x, const mm5_base *b, const float *sig)
{
    vsv_meta *g = &s->grid;
    const double PTOP = b->ptop, P00 = b->p00, TS0 = b->ts0, A = b->a, TISO = b->tiso;
    const size_t plane = (size_t)x->nx * x->ny;
    const int even = vsv_source_axis(s, x->zn, x->KX, 100.0);
    if (even < 0)
        return even;
    if (!even && g->terrain) {
        /* native levels: their heights in every column, as MM5's formula over the terrain */
        const double mm5[5] = {P00, TS0, A, TISO, PTOP};
        double *sigma = malloc((size_t)x->KX * sizeof *sigma);
        if (!sigma)
            return VSV_ENOMEM;
        for (int k = 0; k < x->KX; k++)
            sigma[k] = sig[x->KX - 1 - k];
        const int hrc = vsv_meta_add_heights(g, INT64_MIN, NULL, mm5, sigma);
        free(sigma);
        if (hrc)
            return hrc == VSV_ENOMEM
                       ? hrc
                       : vsv_source_fail(s, VSV_ECORRUPT, "SIGMAH does not give heights increasing upward");
    }
    if (even && vsv_vgrid_plan(&x->vg, x->zn, x->KX, plane, g->terrain, g->nz, g->origin[2], g->spacing[2]))
        return VSV_ENOMEM;
    x->even = even;
    return 0;
}

/* The field table: those of the first period that has any, each with its
 * levels, role and whether it is a volume; the time tables allocated. */
static int mm5_fields(vsv_source *s, mm5src *x)
{
    vsv_mm5 *m = x->m;
    int p0 = 0;
    while (p0 < vsv_mm5_nperiods(m) && vsv_mm5_find(m, p0, "T") < 0 && vsv_mm5_find(m, p0, "U") < 0 &&
           vsv_mm5_find(m, p0, "TERRAIN") < 0)
        p0++;
    s->fields = calloc((size_t)vsv_mm5_nfields(m) + 1, sizeof *s->fields);
    s->times = calloc((size_t)vsv_mm5_nperiods(m) + 1, sizeof *s->times);
    x->period_of = calloc((size_t)vsv_mm5_nperiods(m) + 1, sizeof *x->period_of);
    if (!s->fields || !s->times || !x->period_of)
        return VSV_ENOMEM;
    for (int i = 0; i < vsv_mm5_nfields(m); i++) {
        const vsv_mm5_field *f = vsv_mm5_field_at(m, i);
        if (f->period != (p0 < vsv_mm5_nperiods(m) ? p0 : 0))
            continue;
        vsv_field_info *fi = &s->fields[s->nfields++];
        snprintf(fi->name, sizeof fi->name, "%s", f->name);
        snprintf(fi->units, sizeof fi->units, "%s", f->units);
        snprintf(fi->description, sizeof fi->description, "%s", f->desc);
        snprintf(fi->ordering, sizeof fi->ordering, "%s%s%s", f->order, f->stag[0] ? " " : "", f->stag);
        const int ext2 = f->end[2] - f->start[2] + 1;
        fi->nlevels = !strcmp(f->order, "YXS")   ? ext2
                      : !strcmp(f->order, "YXW") ? ext2
                      : !strcmp(f->order, "YXP") ? ext2
                                                 : 0;
        fi->is_volume = (x->KX > 0 && ((!strcmp(f->order, "YXS") && ext2 == x->KX) ||
                                       (!strcmp(f->order, "YXW") && ext2 == x->KX + 1))) ||
                        (x->plev && !strcmp(f->order, "YXP") && ext2 == x->KP && f->ndim == 3);
        /* pressure-level files hold no particulates: their fields are the point */
        fi->is_default = fi->is_volume && (is_default_name(f->name) || x->plev);
        if (f->order[0] && (!strcmp(f->order + 1, "SB") || !strcmp(f->order + 1, "WB")))
            fi->nlevels = f->end[1] - f->start[1] + 1; /* (IX or JX, levels, width) */
        if (f->order[0] && !strcmp(f->order + 1, "SB"))
            snprintf(fi->role, sizeof fi->role, "boundary slab, not a volume");
        else if (f->order[0] && !strcmp(f->order + 1, "WB"))
            snprintf(fi->role, sizeof fi->role, "boundary slab (W levels), not a volume");
        else if (!strcmp(f->order, "YX"))
            snprintf(fi->role, sizeof fi->role, "2-D");
        else if (!strcmp(f->order, "S") || !strcmp(f->order, "P"))
            snprintf(fi->role, sizeof fi->role, "1-D levels");
        else if (!strcmp(f->order, "CA"))
            snprintf(fi->role, sizeof fi->role, "table");
    }
    return 0;
}

/* The times: one per dated period, in increasing order. */
static int mm5_times(vsv_source *s, mm5src *x)
{
    vsv_mm5 *m = x->m;
    for (int p = 0; p < vsv_mm5_nperiods(m); p++) {
        int64_t t;
        const int dated = period_time(s, m, p, &t);
        if (dated < 0)
            return dated;
        if (dated)
            continue; /* TERRAIN-like files carry no dates */
        if (s->ntimes && t <= s->times[s->ntimes - 1])
            return vsv_source_fail(s, VSV_ECORRUPT, "output time %d does not follow the one before", p);
        x->period_of[s->ntimes] = p;
        s->times[s->ntimes++] = t;
    }
    return 0;
}

static int mm5_open(vsv_source *s)
{
    mm5src *x = calloc(1, sizeof *x);
    if (!x)
        return VSV_ENOMEM;
    s->priv = x;
    vsv_mm5 *m = NULL;
    int rc = vsv_mm5_open(s->path, &m);
    x->m = m;
    if (rc) {
        vsv_msg(s->err, sizeof s->err, "%s", vsv_mm5_error(m));
        return rc;
    }
    /* everything acquired hangs off x, freed by mm5_close */
    mm5_base b = {0};
    float sig[VSV_MAX_DIM];
    if ((rc = mm5_domain(s, x)) || (rc = mm5_header(s, x, &b)) || (rc = mm5_surface(s, x)) ||
        (rc = mm5_sigma_heights(s, x, &b, sig)))
        return rc;
    /* the vertical axis: levels need heights (sigma files, or H on pressure
     * levels); else the layer index */
    if (x->plev) {
        rc = mm5_plev_axis(s, x);
    } else if (!x->has_sigma) {
        s->grid.nz = x->KX > 0 ? x->KX : 1;
        s->grid.vert_kind = VSV_VERT_INDEX;
    } else {
        rc = mm5_sigma_axis(s, x, &b, sig);
    }
    if (rc || (rc = mm5_fields(s, x)) || (rc = mm5_times(s, x)))
        return rc;
    return x->plev && !x->even ? plev_native_heights(s, x) : 0;
}

/* A sigma-level field at time t as a native cross volume into x->nat,
 * bottom-up. */
static int sigma_native(vsv_source *s, mm5src *x, const vsv_field_info *fi, int t)
{
    const int p = x->period_of[t];
    const int idx = vsv_mm5_find(x->m, p, fi->name);
    if (idx < 0)
        return vsv_source_fail(s, VSV_ECORRUPT, "field %s missing from output time %d", fi->name, p);
    const vsv_mm5_field *f = vsv_mm5_field_at(x->m, idx);
    const int full = !strncmp(fi->ordering, "YXW", 3), dot = !strcmp(f->stag, "D");
    /* the first period's shape is the field's: a later period must match it
     * before any byte is copied (its record may be larger) */
    const int want = x->KX + full;
    if (strcmp(f->order, full ? "YXW" : "YXS") || f->end[0] - f->start[0] + 1 != x->IX ||
        f->end[1] - f->start[1] + 1 != x->JX || f->bytes != (uint64_t)x->IX * x->JX * (uint64_t)want * 4)
        return vsv_source_fail(s, VSV_ECORRUPT,
                               "record %d at byte offset %llu: %s (output time %d) is %s %dx%d, %llu bytes; "
                               "the first output time's is %s %dx%dx%d",
                               f->record, (unsigned long long)f->offset, f->name, p, f->order,
                               f->end[0] - f->start[0] + 1, f->end[1] - f->start[1] + 1, (unsigned long long)f->bytes,
                               full ? "YXW" : "YXS", x->IX, x->JX, want);
    if (vsv_mm5_read(x->m, f, x->raw))
        return vsv_source_fail(s, VSV_ETRUNC, VSV_CUT_TEXT);
    const size_t plane = (size_t)x->nx * x->ny, fplane = (size_t)x->IX * x->JX;
    /* native cross volume, bottom-up: file level kk = KX-1-k (k = 1 is the top) */
    for (int k = 0; k < x->KX; k++) {
        const int kk = x->KX - 1 - k;
        const float *a = x->raw + (size_t)kk * fplane, *b = full ? a + fplane : NULL;
        float *o = x->nat + (size_t)k * plane;
        for (int j = 0; j < x->ny; j++)
            for (int i = 0; i < x->nx; i++) {
                const size_t c = (size_t)i * x->IX + j;
                float v = a[c];
                if (dot)
                    v = 0.25f * (a[c] + a[c + 1] + a[c + x->IX] + a[c + x->IX + 1]);
                if (full)
                    v = 0.5f * (v + b[c]); /* W: mean of the full levels around the half level */
                o[(size_t)j * x->nx + i] = v;
            }
    }
    return 0;
}

/* x->nat onto the grid: as it is (native) or resampled (even). */
static void sigma_out(const mm5src *x, float *out)
{
    if (!x->even)
        memcpy(out, x->nat, (size_t)x->nx * x->ny * (size_t)x->KX * sizeof *out);
    else
        vsv_vgrid_apply(&x->vg, x->nat, out);
}

static int mm5_read(vsv_source *s, int field, int t, float *out)
{
    mm5src *x = s->priv;
    const vsv_field_info *fi = &s->fields[field];
    if (!fi->is_volume && !x->KX && !x->plev)
        return vsv_source_fail(s, VSV_EINVAL, "%s (%s) is not a volume (%s); this file has no 3-D levels", fi->name,
                               fi->ordering, fi->role[0] ? fi->role : "2-D");
    if (!fi->is_volume)
        return vsv_source_fail(s, VSV_EINVAL, "%s (%s) is not a 3-D field on the %d %s levels%s%s", fi->name,
                               fi->ordering, x->plev ? x->KP : x->KX, x->plev ? "pressure" : "sigma",
                               fi->role[0] ? ": " : "", fi->role);
    if (x->plev)
        return plev_read(s, x, fi, t, out);
    const int rc = sigma_native(s, x, fi, t);
    if (!rc)
        sigma_out(x, out);
    return rc;
}

int vsv_mm5_pressure(vsv_source *s, int t, float *out)
{
    mm5src *x = s->priv;
    const int f = vsv_source_find_field(s, "PP");
    if (s->ops != &vsv_mm5_ops || !x->pstar || f < 0 || !s->fields[f].is_volume)
        return vsv_source_fail(s, VSV_ENOTFOUND, "no pressure: it needs sigma levels with a reference state and PP");
    if (t < 0 || t >= s->ntimes)
        return vsv_source_fail(s, VSV_ERANGE, "time %d out of range 0..%d", t, s->ntimes - 1);
    const int rc = sigma_native(s, x, &s->fields[f], t);
    if (rc)
        return rc;
    /* p = p* sigma + PTOP + PP, level k bottom-up (file level KX-1-k) */
    const size_t plane = (size_t)x->nx * x->ny;
    for (int k = 0; k < x->KX; k++) {
        const double sg = x->sigma[x->KX - 1 - k];
        float *o = x->nat + (size_t)k * plane;
        for (size_t c = 0; c < plane; c++)
            o[c] = (float)(x->pstar[c] * sg + x->ptop + o[c]);
    }
    sigma_out(x, out);
    return 0;
}

/* Native heights: sigma levels are fixed in time; pressure levels are where
 * H puts them at time t (below the ground too, as the file has them). */
static int mm5_heights(vsv_source *s, int t, float *out)
{
    mm5src *x = s->priv;
    const size_t plane = (size_t)x->nx * x->ny;
    if (x->plev) {
        int rc = plev_heights(s, x, t);
        if (!rc)
            memcpy(out, x->hraw, plane * (size_t)x->KP * sizeof *out);
        return rc;
    }
    if (!x->has_sigma)
        return vsv_source_fail(s, VSV_EUNSUPPORTED, "no level heights (no SIGMAH and base state)");
    memcpy(out, x->zn, plane * (size_t)x->KX * sizeof *out);
    return 0;
}

static void mm5_close(vsv_source *s)
{
    mm5src *x = s->priv;
    if (!x)
        return;
    vsv_mm5_free(x->m);
    free(x->zn);
    free(x->pstar);
    free(x->sigma);
    free(x->zidx);
    free(x->hraw);
    vsv_vgrid_free(&x->vg);
    free(x->raw);
    free(x->nat);
    free(x->period_of);
    free(x);
}

static char *mm5_summary(vsv_source *s)
{
    const mm5src *x = s->priv;
    return vsv_mm5_summary(s, x->m, x->IX, x->JX);
}

const vsv_source_ops vsv_mm5_ops = {"MM5 v3", mm5_probe, mm5_open, mm5_read, mm5_close, mm5_summary, mm5_heights, NULL};
