/* vsv_ioapi.c — Models-3 I/O API netCDF: CMAQ CONC/ACONC and CAMx netCDF
 * output. TFLAG times, GDTYP projections (1 lat/lon, 2 Lambert conformal,
 * 5 UTM, 6 polar stereographic, 7 equatorial Mercator, 8 transverse Mercator,
 * 9 Albers; 3, 4 and 10 — rotated/oblique or without a GeographicLib
 * class — refused by name),
 * heights from CAMx's `z` (layer tops above ground), else from VGTYP/VGLVLS
 * (metres, or sigma-P through the standard atmosphere, stated in the
 * metadata), else the layer index; lifted onto `topo` where there is one,
 * else marked as above the ground (VSV_ATTR_DATUM). INPUT-FORMATS.md §2.2
 * and §3. */
#include "vsv_source_internal.h"
#include "vsv_vgrid.h"

#include <math.h>
#include <netcdf.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

typedef struct ioapi {
    int nc;
    int nx, ny, nk;
    int *varid;
    int zvar; /* CAMx `z`, or -1 */
    float *zm, *nat, *tmp;
    vsv_vgrid vg;
    int vg_t, even, static_heights;
} ioapi;

static double gatt(int nc, const char *name, double dflt)
{
    double v;
    return nc_get_att_double(nc, NC_GLOBAL, name, &v) == NC_NOERR ? v : dflt;
}

/* Standard atmosphere (ICAO, troposphere): height of pressure p (Pa). */
static double std_height(double p) { return 44330.8 * (1 - pow(p / 101325.0, 0.190263)); }

/* Heights above the ground onto the terrain (topo) where the file has one:
 * above sea level, as the format keeps them and the terrain is drawn. */
static void lift(const vsv_source *s, ioapi *a)
{
    const float *ter = s->grid.terrain;
    const size_t plane = (size_t)a->nx * a->ny;
    for (int k = 0; ter && k < a->nk; k++)
        for (size_t c = 0; c < plane; c++)
            a->zm[(size_t)k * plane + c] += ter[c];
}

/* Layer-middle heights of time t from `z` (layer tops above the ground),
 * lifted onto the terrain. */
static int z_heights(vsv_source *s, ioapi *a, int t)
{
    const size_t plane = (size_t)a->nx * a->ny;
    const size_t shape[3] = {(size_t)a->nk, (size_t)a->ny, (size_t)a->nx};
    int rc = vsv_nc_read(s, a->nc, a->zvar, "z", t, shape, 3, a->tmp);
    if (rc)
        return rc;
    for (int k = 0; k < a->nk; k++)
        for (size_t c = 0; c < plane; c++)
            a->zm[(size_t)k * plane + c] =
                0.5f * ((k ? a->tmp[(size_t)(k - 1) * plane + c] : 0.0f) + a->tmp[(size_t)k * plane + c]);
    lift(s, a);
    return 0;
}

/* The grid's size from NCOLS, NROWS and NLAYS, and the scratch sized for it. */
static int ioapi_dims(vsv_source *s, ioapi *a)
{
    const int nc = a->nc;
    a->nx = (int)gatt(nc, "NCOLS", 0);
    a->ny = (int)gatt(nc, "NROWS", 0);
    a->nk = (int)gatt(nc, "NLAYS", 1);
    if (a->nx < 1 || a->ny < 1 || a->nk < 1 || a->nx > VSV_MAX_DIM || a->ny > VSV_MAX_DIM || a->nk > 1000)
        return vsv_source_fail(s, VSV_ECORRUPT, "IOAPI globals NCOLS %d, NROWS %d, NLAYS %d out of range", a->nx, a->ny,
                               a->nk);
    const size_t plane = (size_t)a->nx * a->ny;
    a->zm = malloc(plane * (size_t)a->nk * sizeof *a->zm);
    a->nat = malloc(plane * (size_t)a->nk * sizeof *a->nat);
    a->tmp = malloc(plane * (size_t)a->nk * sizeof *a->tmp);
    if (!a->zm || !a->nat || !a->tmp)
        return VSV_ENOMEM;
    return 0;
}

/* The times from TFLAG of the first variable: YYYYDDD, HHMMSS; increasing. */
static int ioapi_times(vsv_source *s, int nc, int tflag)
{
    int td[3], tnd;
    size_t nt = 0, nv = 0, two = 0;
    if (nc_inq_varndims(nc, tflag, &tnd) || tnd != 3 || nc_inq_vardimid(nc, tflag, td) ||
        nc_inq_dimlen(nc, td[0], &nt) || nc_inq_dimlen(nc, td[1], &nv) || nc_inq_dimlen(nc, td[2], &two) || two != 2 ||
        nv < 1)
        return vsv_source_fail(s, VSV_ECORRUPT, "TFLAG is not (TSTEP, VAR, DATE-TIME=2)");
    /* TFLAG's values lie in the file: a damaged header's time-step count
     * (4294967295, found by fuzz_netcdf) is not allocated */
    struct stat fst;
    if (!stat(s->path, &fst) && nt > (uint64_t)fst.st_size / (nv * 2 * sizeof(int)))
        return vsv_source_fail(s, VSV_ECORRUPT,
                               "TFLAG declares %zu time steps of %zu variables, more than the file "
                               "(%lld bytes) holds",
                               nt, nv, (long long)fst.st_size);
    s->times = calloc(nt + 1, sizeof *s->times);
    if (!s->times)
        return VSV_ENOMEM;
    for (size_t t = 0; t < nt; t++) {
        int dt[2];
        size_t st[3] = {t, 0, 0}, ct[3] = {1, 1, 2};
        if (nc_get_vara_int(nc, tflag, st, ct, dt))
            return vsv_source_fail(s, VSV_ECORRUPT, "cannot read TFLAG[%zu]", t);
        const int y = dt[0] / 1000, doy = dt[0] % 1000, hh = dt[1] / 10000, mm = dt[1] / 100 % 100, ss = dt[1] % 100;
        if (y < 1 || doy < 1 || doy > 366 || hh > 23 || mm > 59 || ss > 60)
            return vsv_source_fail(s, VSV_ECORRUPT, "TFLAG[%zu] = %d, %06d is not a date and time", t, dt[0], dt[1]);
        s->times[t] = vsv_time_from_civil(y, 1, 1, hh, mm, ss) + (int64_t)(doy - 1) * 86400;
        if (t && s->times[t] <= s->times[t - 1])
            return vsv_source_fail(s, VSV_ECORRUPT, "TFLAG[%zu] does not follow TFLAG[%zu]", t, t - 1);
    }
    s->ntimes = (int)nt;
    return 0;
}

/* FILEDESC as one line into out: IOAPI writes it as 60 lines of 80
 * characters padded with blanks (4800 in all), each non-blank line
 * trimmed and joined by "; " up to the first that does not fit; text of
 * another length is one line, trimmed. Control bytes and non-ASCII are
 * blanks. */
static void file_description(int nc, char *out, size_t cap)
{
    size_t len, n = 0;
    out[0] = 0;
    char *fd = NULL;
    if (nc_inq_attlen(nc, NC_GLOBAL, "FILEDESC", &len) != NC_NOERR || len > ((size_t)1 << 20) ||
        !(fd = malloc(len + 1)) || nc_get_att_text(nc, NC_GLOBAL, "FILEDESC", fd) != NC_NOERR) {
        free(fd);
        return;
    }
    fd[len] = 0;
    const size_t width = len % 80 ? len : 80; /* a line */
    for (size_t at = 0; at < len; at += width) {
        size_t a = at, b = at + width < len ? at + width : len;
        for (size_t i = a; i < b; i++)
            fd[i] = fd[i] > 0x20 && fd[i] < 0x7f ? fd[i] : ' ';
        while (a < b && fd[a] == ' ')
            a++;
        while (b > a && fd[b - 1] == ' ')
            b--;
        if (b == a)
            continue;
        if (n + 2 + (b - a) >= cap) { /* the first line cut to fit; no later one */
            if (!n)
                snprintf(out, cap, "%.*s", (int)(b - a), fd + a);
            break;
        }
        n += (size_t)snprintf(out + n, cap - n, "%s%.*s", n ? "; " : "", (int)(b - a), fd + a);
    }
    free(fd);
}

/* The grid and its projection (GDTYP), its plan position, and the model
 * and run it describes. */
static int ioapi_grid(vsv_source *s, const ioapi *a)
{
    const int nc = a->nc;
    vsv_meta *g = &s->grid;
    g->nx = a->nx;
    g->ny = a->ny;
    const int gdtyp = (int)gatt(nc, "GDTYP", -1);
    const double alp = gatt(nc, "P_ALP", 0), bet = gatt(nc, "P_BET", 0), gam = gatt(nc, "P_GAM", 0);
    const double xcent = gatt(nc, "XCENT", gam), ycent = gatt(nc, "YCENT", 0);
    const double xcell = gatt(nc, "XCELL", 0), ycell = gatt(nc, "YCELL", 0);
    g->proj.radius = 6370000;
    switch (gdtyp) {
    case 1: g->proj.kind = VSV_PROJ_LATLON; break;
    case 2: g->proj = (vsv_proj){VSV_PROJ_LCC, ycent, gam, alp, bet, 6370000}; break;
    case 6:
        g->proj =
            (vsv_proj){VSV_PROJ_PSTEREO, ycent, gam, alp >= 0 ? bet : -fabs(bet), alp >= 0 ? bet : -fabs(bet), 6370000};
        break;
    case 7: g->proj = (vsv_proj){VSV_PROJ_MERCATOR, ycent, gam, alp, alp, 6370000}; break;
    case 5: /* UTM: P_ALP is the zone; coordinates carry a 500 km false easting */
        if (!(alp >= 1 && alp <= 60))
            return vsv_source_fail(s, VSV_ECORRUPT, "GDTYP 5 (UTM) with zone %g", alp);
        g->proj = (vsv_proj){VSV_PROJ_TMERC, 0, 6 * alp - 183, 0.9996, 0.9996, 6370000};
        break;
    case 8: g->proj = (vsv_proj){VSV_PROJ_TMERC, alp, gam, bet > 0 ? bet : 1, bet > 0 ? bet : 1, 6370000}; break;
    case 9: g->proj = (vsv_proj){VSV_PROJ_ALBERS, ycent, gam, alp, bet, 6370000}; break;
    default: {
        static const char *names[] = {"?",
                                      "lat/lon",
                                      "Lambert conformal",
                                      "general Mercator",
                                      "general stereographic",
                                      "UTM",
                                      "polar stereographic",
                                      "equatorial Mercator",
                                      "transverse Mercator",
                                      "Albers equal-area",
                                      "Lambert azimuthal equal-area"};
        return vsv_source_fail(s, VSV_EUNSUPPORTED, "GDTYP %d (%s) is not supported (1, 2, 5, 6, 7, 8 and 9 are)",
                               gdtyp, gdtyp >= 1 && gdtyp <= 10 ? names[gdtyp] : "unknown");
    }
    }
    if (!(xcell > 0) || !(ycell > 0))
        return vsv_source_fail(s, VSV_ECORRUPT, "XCELL %g, YCELL %g", xcell, ycell);
    /* XORIG/YORIG are relative to (XCENT, YCENT); our origin is (lat0 = YCENT, lon0 = P_GAM) */
    double ox = 0, oy = 0;
    if (gdtyp == 5)
        ox = -500000; /* UTM false easting; the origin is (equator, central meridian) */
    else if (g->proj.kind != VSV_PROJ_LATLON && vsv_proj_forward(&g->proj, ycent, xcent, &ox, &oy))
        return vsv_source_fail(s, VSV_ECORRUPT, "projection centre (%g, %g) outside the projection", ycent, xcent);
    g->origin[0] = gatt(nc, "XORIG", 0) + xcell / 2 + ox;
    g->origin[1] = gatt(nc, "YORIG", 0) + ycell / 2 + oy;
    g->spacing[0] = xcell;
    g->spacing[1] = ycell;
    const int camx = nc_inq_attlen(nc, NC_GLOBAL, "CAMx_NAME", &(size_t){0}) == NC_NOERR ||
                     nc_inq_attlen(nc, NC_GLOBAL, "CPROJ", &(size_t){0}) == NC_NOERR;
    snprintf(g->model, sizeof g->model, "%s", camx ? "CAMx (IOAPI netCDF)" : "CMAQ (IOAPI netCDF)");
    file_description(nc, g->run, sizeof g->run);
    char buf[64];
    snprintf(buf, sizeof buf, "%d", gdtyp);
    vsv_meta_add_attr(g, "GDTYP", buf);
    return 0;
}

/* The layer heights into a->zm: from CAMx's z (varying in time), else from
 * VGTYP/VGLVLS (fixed); *have_heights says whether either was there. */
static int ioapi_heights(vsv_source *s, ioapi *a, int *have_heights)
{
    const int nc = a->nc;
    vsv_meta *g = &s->grid;
    const size_t plane = (size_t)a->nx * a->ny;
    const int vgtyp = (int)gatt(nc, "VGTYP", -1);
    double *vgl = calloc((size_t)a->nk + 1, sizeof *vgl);
    size_t vgn = 0;
    const int have_vgl = vgl && nc_inq_attlen(nc, NC_GLOBAL, "VGLVLS", &vgn) == NC_NOERR && vgn == (size_t)a->nk + 1 &&
                         nc_get_att_double(nc, NC_GLOBAL, "VGLVLS", vgl) == NC_NOERR;
    int rc = 0;
    *have_heights = 0;
    if (nc_inq_varid(nc, "z", &a->zvar) == NC_NOERR) {
        if ((rc = z_heights(s, a, 0)))
            goto fail;
        *have_heights = 1;
        vsv_meta_add_attr(g, "heights",
                          g->terrain ? "CAMx z: layer tops above ground, varying in time, on topo"
                                     : "CAMx z: layer tops above ground, varying in time");
    } else if (have_vgl && (vgtyp == 6 || vgtyp == 2 || vgtyp == 7)) {
        const double vgtop = gatt(nc, "VGTOP", 5000);
        for (int k = 0; k < a->nk; k++) {
            double z;
            if (vgtyp == 6) {
                z = 0.5 * (vgl[k] + vgl[k + 1]);
            } else {
                const double sig = 0.5 * (vgl[k] + vgl[k + 1]);
                z = std_height(vgtop + sig * (101325.0 - vgtop));
            }
            for (size_t c = 0; c < plane; c++)
                a->zm[(size_t)k * plane + c] = (float)z;
        }
        lift(s, a);
        a->zvar = -1;
        a->static_heights = 1;
        *have_heights = 1;
        vsv_meta_add_attr(g, "heights",
                          vgtyp == 6 ? "VGLVLS in metres above ground"
                                     : "sigma-P levels through the ICAO standard atmosphere (approximate)");
    }
fail:
    free(vgl);
    return rc;
}

/* The species: float (TSTEP, LAY, ROW, COL) variables, units and
 * descriptions without their trailing blanks. */
static int ioapi_fields(vsv_source *s, ioapi *a)
{
    const int nc = a->nc;
    int nvars;
    nc_inq_nvars(nc, &nvars);
    s->fields = calloc((size_t)nvars + 1, sizeof *s->fields);
    a->varid = calloc((size_t)nvars + 1, sizeof *a->varid);
    if (!s->fields || !a->varid)
        return VSV_ENOMEM;
    for (int v = 0; v < nvars; v++) {
        char name[NC_MAX_NAME + 1];
        int nd, dims[NC_MAX_VAR_DIMS];
        nc_type type;
        size_t len[4];
        if (nc_inq_var(nc, v, name, &type, &nd, dims, NULL) || nd != 4 || type != NC_FLOAT || v == a->zvar ||
            strlen(name) >= sizeof s->fields[0].name)
            continue;
        for (int d = 0; d < 4; d++)
            nc_inq_dimlen(nc, dims[d], &len[d]);
        if (len[1] != (size_t)a->nk || len[2] != (size_t)a->ny || len[3] != (size_t)a->nx)
            continue;
        vsv_field_info *f = &s->fields[s->nfields];
        snprintf(f->name, sizeof f->name, "%s", name);
        size_t al;
        char txt[200] = "";
        if (nc_inq_attlen(nc, v, "units", &al) == NC_NOERR && al < sizeof txt) {
            nc_get_att_text(nc, v, "units", txt);
            txt[al] = 0;
            for (int e = (int)strlen(txt) - 1; e >= 0 && txt[e] == ' '; e--)
                txt[e] = 0;
            snprintf(f->units, sizeof f->units, "%s", txt);
        }
        memset(txt, 0, sizeof txt);
        if (nc_inq_attlen(nc, v, "var_desc", &al) == NC_NOERR && al < sizeof txt) {
            nc_get_att_text(nc, v, "var_desc", txt);
            for (int e = (int)strlen(txt) - 1; e >= 0 && txt[e] == ' '; e--)
                txt[e] = 0;
            snprintf(f->description, sizeof f->description, "%s", txt);
        }
        snprintf(f->ordering, sizeof f->ordering, "IOAPI");
        f->nlevels = a->nk;
        f->is_volume = f->is_default = 1;
        a->varid[s->nfields++] = v;
    }
    return 0;
}

int vsv_ioapi_open(vsv_source *s, int nc)
{
    ioapi *a = calloc(1, sizeof *a);
    if (!a) {
        vsv_nc_close(nc);
        return VSV_ENOMEM;
    }
    s->priv = a;
    a->nc = nc;
    a->zvar = -1;
    a->vg_t = -1;
    /* everything acquired hangs off a and s, freed by ioapi_close */
    int tflag, rc;
    if (nc_inq_varid(nc, "TFLAG", &tflag))
        return vsv_source_fail(s, VSV_ECORRUPT, "IOAPI file without TFLAG");
    if ((rc = ioapi_dims(s, a)) || (rc = ioapi_times(s, nc, tflag)) || (rc = ioapi_grid(s, a)))
        return rc;
    /* terrain */
    vsv_meta *g = &s->grid;
    int topo;
    if (nc_inq_varid(nc, "topo", &topo) == NC_NOERR) {
        if (vsv_meta_alloc_terrain(g))
            return VSV_ENOMEM;
        const size_t pshape[2] = {(size_t)a->ny, (size_t)a->nx};
        if ((rc = vsv_nc_read(s, nc, topo, "topo", 0, pshape, 2, g->terrain)))
            return rc;
    }
    /* heights */
    int have_heights;
    if ((rc = ioapi_heights(s, a, &have_heights)))
        return rc;
    if (!have_heights) {
        g->nz = a->nk;
        g->vert_kind = VSV_VERT_INDEX;
    } else {
        if (!g->terrain && vsv_meta_add_attr(g, VSV_ATTR_DATUM, "ground") < 0)
            return VSV_ENOMEM;
        const int even = vsv_source_axis(s, a->zm, a->nk, 10.0);
        if (even < 0)
            return even;
        a->even = even;
    }
    return ioapi_fields(s, a);
}

static int ioapi_read(vsv_source *s, int field, int t, float *out)
{
    ioapi *a = s->priv;
    const size_t plane = (size_t)a->nx * a->ny;
    const size_t shape[3] = {(size_t)a->nk, (size_t)a->ny, (size_t)a->nx};
    int rc = vsv_nc_read(s, a->nc, a->varid[field], s->fields[field].name, t, shape, 3, a->even ? a->nat : out);
    if (rc)
        return rc;
    if (!a->even)
        return 0;
    if (a->vg_t != t && !(a->static_heights && a->vg_t >= 0)) {
        if (a->zvar >= 0 && (rc = z_heights(s, a, t)))
            return rc;
        if (vsv_vgrid_plan(&a->vg, a->zm, a->nk, plane, NULL, s->grid.nz, s->grid.origin[2], s->grid.spacing[2]))
            return VSV_ENOMEM;
        a->vg_t = t;
    }
    vsv_vgrid_apply(&a->vg, a->nat, out);
    return 0;
}

static void ioapi_close(vsv_source *s)
{
    ioapi *a = s->priv;
    if (!a)
        return;
    vsv_nc_close(a->nc);
    free(a->varid);
    free(a->zm);
    free(a->nat);
    free(a->tmp);
    vsv_vgrid_free(&a->vg);
    free(a);
}

static char *ioapi_summary(vsv_source *s)
{
    vsv_buf b = {0};
    char line[600];
    const vsv_meta *g = &s->grid;
    const ioapi *a = s->priv;
    char out[120] = "";
    if (g->vert_kind == VSV_VERT_EVEN)
        snprintf(out, sizeof out, "; converted onto %d even levels of %.4g m (--vertical native keeps the layers)",
                 g->nz, g->spacing[2]);
    snprintf(line, sizeof line,
             "%s: %s\n  grid        %d x %d columns, %d layers (%s)%s\n  projection  %s (GDTYP %s)\n  times       %d\n"
             "  species     %d:",
             g->model, g->run, g->nx, g->ny, a->nk,
             vsv_meta_attr(g, "heights") ? vsv_meta_attr(g, "heights") : "layer index", out,
             vsv_proj_name(g->proj.kind), vsv_meta_attr(g, "GDTYP"), s->ntimes, s->nfields);
    vsv_buf_put(&b, line, strlen(line));
    for (int i = 0; i < s->nfields; i++) {
        snprintf(line, sizeof line, " %s", s->fields[i].name);
        vsv_buf_put(&b, line, strlen(line));
    }
    vsv_buf_put(&b, "\n", 2);
    return (char *)b.p;
}

const vsv_source_ops vsv_ioapi_ops = {"IOAPI", NULL, NULL, ioapi_read, ioapi_close, ioapi_summary, NULL, NULL};
