/* vsv_wrf.c — netCDF model output: detection (WRF by MAP_PROJ and Times,
 * IOAPI by its grid globals) and the WRF (wrfout) reader: U, V, W, PH
 * destaggered to mass points, heights from (PH+PHB)/g (mass levels halfway
 * between w-levels, varying in time), MAP_PROJ 1/2/3/6, Times, terrain from
 * HGT (or the lowest w-level). INPUT-FORMATS.md §4. */
#include "vsv_source_internal.h"
#include "vsv_vgrid.h"

#include <math.h>
#include <netcdf.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define G0 9.81

typedef struct wrf {
    int nc;
    int nx, ny, nk; /* mass points */
    int *varid;     /* per field */
    int *stag;      /* per field: 0 none, 1 x, 2 y, 3 z */
    float *zw;      /* scratch: (nk+1)*plane w-level heights */
    float *zm;      /* scratch: nk*plane mass-level heights */
    float *raw, *nat;
    int vgrid_t; /* time the vgrid was planned for, -1 none */
    vsv_vgrid vg;
    int even;
    double ztop;
} wrf;

static int nc_probe(const unsigned char *h, size_t n)
{
    return n >= 8 && (!memcmp(h, "CDF\x01", 4) || !memcmp(h, "CDF\x02", 4) || !memcmp(h, "CDF\x05", 4) ||
                      !memcmp(h, "\x89HDF\r\n\x1a\n", 8));
}

static int has_att(int nc, const char *name)
{
    size_t len;
    return nc_inq_attlen(nc, NC_GLOBAL, name, &len) == NC_NOERR;
}

static double att_double(int nc, const char *name, double dflt)
{
    double v;
    return nc_get_att_double(nc, NC_GLOBAL, name, &v) == NC_NOERR ? v : dflt;
}

static int dim_len(int nc, const char *name, size_t *len)
{
    int id;
    return nc_inq_dimid(nc, name, &id) == NC_NOERR && nc_inq_dimlen(nc, id, len) == NC_NOERR ? 0 : -1;
}

int vsv_nc_read(vsv_source *s, int nc, int var, const char *name, int t, const size_t *shape, int n, float *out)
{
    int nd = 0, dims[NC_MAX_VAR_DIMS];
    size_t start[5] = {0}, count[5], len[5] = {0};
    char have[96] = "", want[96] = "";
    for (int d = 0; d < n; d++)
        snprintf(want + strlen(want), sizeof want - strlen(want), "%s%zu", d ? " x " : "", shape[d]);
    if (nc_inq_varndims(nc, var, &nd) || nd < 0 || nd > NC_MAX_VAR_DIMS || nc_inq_vardimid(nc, var, dims))
        return vsv_source_fail(s, VSV_ECORRUPT, "variable %s: its dimensions cannot be read", name);
    for (int d = 0; d < nd; d++) {
        size_t l = 0;
        nc_inq_dimlen(nc, dims[d], &l);
        if (d < 5)
            len[d] = l;
        snprintf(have + strlen(have), sizeof have - strlen(have), "%s%zu", d ? " x " : "", l);
    }
    if (nd < n || nd > n + 1)
        return vsv_source_fail(s, VSV_ECORRUPT, "variable %s is %s, expected [time x] %s", name, nd ? have : "a scalar",
                               want);
    const int lead = nd - n;
    int ok = !lead || (t >= 0 && (size_t)t < len[0]);
    for (int d = 0; d < n; d++)
        ok &= len[lead + d] == shape[d];
    if (!ok)
        return vsv_source_fail(s, VSV_ECORRUPT, "variable %s is %s, expected [time x] %s%s", name, have, want,
                               lead ? "" : " (no time dimension)");
    if (lead) {
        start[0] = (size_t)t;
        count[0] = 1;
    }
    for (int d = 0; d < n; d++)
        count[lead + d] = shape[d];
    const int rc = nc_get_vara_float(nc, var, start, count, out);
    if (vsv_nc_cut(nc)) /* read as zeros, or failed, past the new end */
        return vsv_source_fail(s, VSV_ETRUNC, "reading variable %s at time %d: %s", name, t, VSV_CUT_TEXT);
    if (rc)
        return vsv_source_fail(s, VSV_ECORRUPT, "reading variable %s at time %d: %s", name, t, nc_strerror(rc));
    return 0;
}

/* Heights of the w-levels at time t: (PH+PHB)/g; 0 or error. */
static int w_heights(vsv_source *s, wrf *w, int t)
{
    const size_t plane = (size_t)w->nx * w->ny;
    int ph, phb;
    if (nc_inq_varid(w->nc, "PH", &ph) || nc_inq_varid(w->nc, "PHB", &phb))
        return vsv_source_fail(s, VSV_ECORRUPT, "WRF file without PH and PHB: heights unknown");
    const size_t shape[3] = {(size_t)w->nk + 1, (size_t)w->ny, (size_t)w->nx};
    int rc;
    if ((rc = vsv_nc_read(s, w->nc, ph, "PH", t, shape, 3, w->zw)) ||
        (rc = vsv_nc_read(s, w->nc, phb, "PHB", t, shape, 3, w->raw)))
        return rc;
    for (size_t i = 0; i < plane * (size_t)(w->nk + 1); i++)
        w->zw[i] = (float)((w->zw[i] + w->raw[i]) / G0);
    for (int k = 0; k < w->nk; k++)
        for (size_t c = 0; c < plane; c++)
            w->zm[(size_t)k * plane + c] = 0.5f * (w->zw[(size_t)k * plane + c] + w->zw[(size_t)(k + 1) * plane + c]);
    return 0;
}

static int is_default_wrf(const char *n)
{
    /* the hydrometeors, and water vapour as MM5's default has Q */
    static const char *const d[] = {"QVAPOR", "QCLOUD", "QRAIN", "QICE", "QSNOW", "QGRAUP", NULL};
    for (int i = 0; d[i]; i++)
        if (!strcmp(n, d[i]))
            return 1;
    return 0;
}

static int wrf_open(vsv_source *s, int nc);

static int netcdf_open(vsv_source *s)
{
    int nc, rc;
    /* netCDF-4 (HDF5): a damaged file can crash the library, so a child
     * reads it first (vsv_nc_guard.c) */
    unsigned char head[8] = {0};
    char msg[512];
    FILE *fp = fopen(s->path, "rb");
    const size_t got = fp ? fread(head, 1, sizeof head, fp) : 0;
    /* classic netCDF: libnetcdf believes the header's counts, so they are
     * checked against the file first (vsv_nc_header.c) */
    int bad = 0;
    struct stat st;
    if (fp && !fstat(fileno(fp), &st) && !fseeko(fp, 0, SEEK_SET))
        bad = vsv_nc_classic_check(fp, (uint64_t)st.st_size, msg, sizeof msg) < 0 ||
              vsv_nc_hdf5_check(fp, (uint64_t)st.st_size, msg, sizeof msg) < 0;
    if (fp)
        fclose(fp);
    if (bad)
        return vsv_source_fail(s, VSV_ECORRUPT, "%s", msg);
    if (got == 8 && !memcmp(head, "\x89HDF\r\n\x1a\n", 8) && (rc = vsv_nc_guard(s, VSV_NC_GUARD_LIMIT)))
        return rc;
    if ((rc = vsv_nc_open(s, &nc)))
        return rc;
    int tv;
    if (has_att(nc, "MAP_PROJ") && nc_inq_varid(nc, "Times", &tv) == NC_NOERR)
        return wrf_open(s, nc);
    if (has_att(nc, "XORIG") && has_att(nc, "YORIG") && has_att(nc, "XCELL") && has_att(nc, "YCELL") &&
        has_att(nc, "NCOLS") && has_att(nc, "NROWS")) {
        s->ops = &vsv_ioapi_ops;
        return vsv_ioapi_open(s, nc);
    }
    if (vsv_cf_detect(nc)) {
        s->ops = &vsv_cf_ops;
        return vsv_cf_open(s, nc);
    }
    vsv_nc_close(nc);
    return vsv_source_fail(s, VSV_ENOTVSV,
                           "a netCDF file that is none of WRF output (MAP_PROJ, Times), IOAPI/CMAQ, CAMx netCDF or "
                           "CF-convention netCDF (Conventions \"CF-...\")");
}

/* The mass-point dimensions and time count (nt), and the scratch sized for them. */
static int wrf_dims(vsv_source *s, wrf *w, size_t *nt)
{
    size_t nx, ny, nk;
    if (dim_len(w->nc, "west_east", &nx) || dim_len(w->nc, "south_north", &ny) || dim_len(w->nc, "bottom_top", &nk) ||
        dim_len(w->nc, "Time", nt) || nx < 2 || ny < 2 || nk < 1 || nx > VSV_MAX_DIM || ny > VSV_MAX_DIM)
        return vsv_source_fail(s, VSV_ECORRUPT, "WRF file without west_east, south_north, bottom_top and Time");
    w->nx = (int)nx;
    w->ny = (int)ny;
    w->nk = (int)nk;
    const size_t plane = nx * ny;
    w->zw = malloc(plane * (nk + 1) * sizeof(float));
    w->zm = malloc(plane * nk * sizeof(float));
    w->raw = malloc((nx + 1) * (ny + 1) * (nk + 1) * sizeof(float));
    w->nat = malloc(plane * nk * sizeof(float));
    if (!w->zw || !w->zm || !w->raw || !w->nat)
        return VSV_ENOMEM;
    return 0;
}

/* The nt times from Times (YYYY-MM-DD_HH:MM:SS each), increasing. */
static int wrf_times(vsv_source *s, int nc, size_t nt)
{
    int tv;
    nc_inq_varid(nc, "Times", &tv);
    size_t slen = 0;
    int tdims[NC_MAX_VAR_DIMS], tnd = 0;
    size_t tlen = 0;
    if (nc_inq_varndims(nc, tv, &tnd) || tnd != 2 || nc_inq_vardimid(nc, tv, tdims) ||
        nc_inq_dimlen(nc, tdims[1], &slen) || slen < 19 || slen > 64 || nc_inq_dimlen(nc, tdims[0], &tlen) ||
        tlen != nt)
        return vsv_source_fail(s, VSV_ECORRUPT, "Times is not a (Time, 19-character) variable");
    char *tbuf = calloc(nt * slen + 1, 1);
    s->times = calloc(nt + 1, sizeof *s->times);
    int rc = VSV_ENOMEM;
    if (!tbuf || !s->times)
        goto fail;
    if (nt && nc_get_var_text(nc, tv, tbuf)) {
        rc = vsv_source_fail(s, VSV_ECORRUPT, "cannot read Times");
        goto fail;
    }
    for (size_t t = 0; t < nt; t++) {
        char one[65];
        memcpy(one, tbuf + t * slen, slen);
        one[slen] = 0;
        int y, mo, d, h, mi, se;
        if (sscanf(one, "%4d-%2d-%2d_%2d:%2d:%2d", &y, &mo, &d, &h, &mi, &se) != 6) {
            rc = vsv_source_fail(s, VSV_ECORRUPT, "Times[%zu] = '%s' is not YYYY-MM-DD_HH:MM:SS", t, one);
            goto fail;
        }
        s->times[t] = vsv_time_from_civil(y, mo, d, h, mi, se);
        if (t && s->times[t] <= s->times[t - 1]) {
            rc = vsv_source_fail(s, VSV_ECORRUPT, "Times[%zu] does not follow Times[%zu]", t, t - 1);
            goto fail;
        }
    }
    s->ntimes = (int)nt;
    rc = 0;
fail:
    free(tbuf);
    return rc;
}

/* The projection from MAP_PROJ (1, 2, 3 or 6) and its globals; MAP_PROJ into mp. */
static int wrf_projection(vsv_source *s, int nc, int *mp_out)
{
    vsv_meta *g = &s->grid;
    const int mp = *mp_out = (int)att_double(nc, "MAP_PROJ", -1);
    const double lat1 = att_double(nc, "TRUELAT1", 0), lat2 = att_double(nc, "TRUELAT2", lat1),
                 slon = att_double(nc, "STAND_LON", att_double(nc, "CEN_LON", 0)),
                 clat = att_double(nc, "MOAD_CEN_LAT", att_double(nc, "CEN_LAT", 0));
    g->proj.radius = 6370000;
    g->proj.lon0 = slon;
    g->proj.lat0 = clat;
    g->proj.lat1 = lat1;
    g->proj.lat2 = lat2;
    if (mp == 1)
        g->proj.kind = VSV_PROJ_LCC;
    else if (mp == 2)
        g->proj.kind = VSV_PROJ_PSTEREO;
    else if (mp == 3) {
        g->proj.kind = VSV_PROJ_MERCATOR;
        g->proj.lat2 = lat1;
        g->proj.lat0 = 0;
    } else if (mp == 6) {
        /* a cylindrical equidistant grid; with its pole moved (POLE_LAT not
         * 90) the grid's own latitudes are not the Earth's */
        const double plat = att_double(nc, "POLE_LAT", 90), plon = att_double(nc, "POLE_LON", 0);
        if (fabs(plat - 90) > 1e-6)
            return vsv_source_fail(s, VSV_EUNSUPPORTED,
                                   "MAP_PROJ 6 with POLE_LAT %g, POLE_LON %g: a rotated-pole lat/lon grid is not "
                                   "supported (only POLE_LAT 90)",
                                   plat, plon);
        g->proj.kind = VSV_PROJ_LATLON;
    } else
        return vsv_source_fail(s, VSV_EUNSUPPORTED, "MAP_PROJ %d is not supported (1, 2, 3 and 6 are)", mp);
    return 0;
}

/* Where the grid lies at time t: XLAT/XLONG placed in the projection, the
 * origin that fits every cell best (WRF rounded each to float32, about a
 * metre, so one cell alone places the grid that far off; the mean over all
 * cells of (projected cell - its offset) does not). The spacing is DX, DY
 * (*dx, *dy as given when positive, else from the corners: lat/lon grids),
 * checked by the far corner landing where they put it. */
static int wrf_place(vsv_source *s, const wrf *w, int t, int mp, double *dx, double *dy, double o[2])
{
    const int nc = w->nc;
    const size_t nx = (size_t)w->nx, ny = (size_t)w->ny, plane = nx * ny;
    const vsv_meta *g = &s->grid;
    int vlat, vlon;
    if (nc_inq_varid(nc, "XLAT", &vlat) || nc_inq_varid(nc, "XLONG", &vlon))
        return vsv_source_fail(s, VSV_ECORRUPT, "WRF file without XLAT/XLONG: its position is unknown");
    float *la = malloc(plane * sizeof *la), *lo = malloc(plane * sizeof *lo);
    const size_t pshape[2] = {ny, nx};
    int rc = VSV_ENOMEM;
    if (!la || !lo)
        goto fail;
    if ((rc = vsv_nc_read(s, nc, vlat, "XLAT", t, pshape, 2, la)) ||
        (rc = vsv_nc_read(s, nc, vlon, "XLONG", t, pshape, 2, lo)))
        goto fail;
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    if (vsv_proj_forward(&g->proj, la[0], lo[0], &x0, &y0) ||
        vsv_proj_forward(&g->proj, la[plane - 1], lo[plane - 1], &x1, &y1)) {
        rc = vsv_source_fail(s, VSV_ECORRUPT, "cannot place XLAT/XLONG at time %d in the projection", t);
        goto fail;
    }
    if (!(*dx > 0) || !(*dy > 0)) {
        *dx = (x1 - x0) / (double)(nx - 1);
        *dy = (y1 - y0) / (double)(ny - 1);
    }
    if (mp != 6) {
        double sx = 0, sy = 0;
        size_t used = 0;
        for (size_t c = 0; c < plane; c++) {
            double x, y;
            if (vsv_proj_forward(&g->proj, la[c], lo[c], &x, &y))
                continue;
            sx += x - (double)(c % nx) * *dx;
            sy += y - (double)(c / nx) * *dy;
            used++;
        }
        if (used == plane) {
            x1 += sx / (double)used - x0;
            y1 += sy / (double)used - y0;
            x0 = sx / (double)used;
            y0 = sy / (double)used;
        }
    }
    o[0] = x0;
    o[1] = y0;
    if (mp != 6 && (fabs(x1 - (x0 + *dx * (double)(nx - 1))) > 0.02 * *dx * (double)nx ||
                    fabs(y1 - (y0 + *dy * (double)(ny - 1))) > 0.02 * *dy * (double)ny))
        rc = vsv_source_fail(s, VSV_ECORRUPT, "XLAT/XLONG at time %d do not match MAP_PROJ %d with DX %g, DY %g", t, mp,
                             *dx, *dy);
    else
        rc = 0;
fail:
    free(la);
    free(lo);
    return rc;
}

/* The grid's origin and spacing: its place at the first time. */
static int wrf_position(vsv_source *s, const wrf *w, int mp)
{
    vsv_meta *g = &s->grid;
    const int nc = w->nc;
    double dx = mp == 6 ? 0 : att_double(nc, "DX", 0), dy = mp == 6 ? 0 : att_double(nc, "DY", 0), o[2];
    const int rc = wrf_place(s, w, 0, mp, &dx, &dy, o);
    if (rc)
        return rc;
    g->origin[0] = o[0];
    g->origin[1] = o[1];
    g->spacing[0] = dx;
    g->spacing[1] = dy;
    return 0;
}

/* A moving nest (XLAT/XLONG that change in time): each time it stands
 * somewhere new, its placement and the ground under it (SPEC.md "MOVE").
 * WRF moves a nest by whole cells of its parent; a place that is not a
 * whole number of the nest's own cells away is refused (every reader
 * shifts frames by whole cells between placements). */
static int wrf_moves(vsv_source *s, wrf *w, int mp)
{
    vsv_meta *g = &s->grid;
    const size_t plane = (size_t)w->nx * w->ny;
    const size_t pshape[2] = {(size_t)w->ny, (size_t)w->nx};
    double last[2] = {g->origin[0], g->origin[1]};
    float *hgt = NULL;
    int hv = -1, rc = 0;
    if (nc_inq_varid(w->nc, "HGT", &hv) != NC_NOERR)
        hv = -1;
    for (int t = 1; t < s->ntimes && !rc; t++) {
        double dx = g->spacing[0], dy = g->spacing[1], o[2];
        if ((rc = wrf_place(s, w, t, mp, &dx, &dy, o)))
            break;
        const double fx = (o[0] - last[0]) / dx, fy = (o[1] - last[1]) / dy;
        if (fabs(fx) < 0.01 && fabs(fy) < 0.01)
            continue; /* the same place (float32 noise in XLAT/XLONG) */
        if (fabs(fx - round(fx)) > 0.01 || fabs(fy - round(fy)) > 0.01) {
            rc = vsv_source_fail(s, VSV_EUNSUPPORTED,
                                 "the grid moves by %.3f x %.3f cells at time %d: a moving nest moves by whole cells",
                                 fx, fy, t);
            break;
        }
        last[0] += round(fx) * dx; /* whole cells: no drift from float32 noise */
        last[1] += round(fy) * dy;
        if (g->terrain && !hgt && !(hgt = malloc(plane * sizeof *hgt + 1))) {
            rc = VSV_ENOMEM;
            break;
        }
        if (g->terrain && hv >= 0)
            rc = vsv_nc_read(s, w->nc, hv, "HGT", t, pshape, 2, hgt);
        else if (g->terrain && !(rc = w_heights(s, w, t)))
            memcpy(hgt, w->zw, plane * sizeof *hgt);
        if (!rc && (rc = vsv_meta_add_move(g, s->times[t], last, hgt)) == VSV_EINVAL)
            rc = vsv_source_fail(s, VSV_ECORRUPT, "HGT at time %d is not finite", t);
    }
    free(hgt);
    return rc;
}

/* The model, run title and the globals worth keeping as attributes. */
static void wrf_describe(vsv_source *s, const wrf *w, int mp)
{
    const int nc = w->nc;
    vsv_meta *g = &s->grid;
    snprintf(g->model, sizeof g->model, "WRF");
    char title[200] = "";
    size_t tl;
    if (nc_inq_attlen(nc, NC_GLOBAL, "TITLE", &tl) == NC_NOERR && tl < sizeof title)
        nc_get_att_text(nc, NC_GLOBAL, "TITLE", title);
    char *tt = title;
    while (*tt == ' ')
        tt++;
    snprintf(g->run, sizeof g->run, "%s, %zu x %zu x %zu mass points", tt, (size_t)w->nx, (size_t)w->ny, (size_t)w->nk);
    char buf[64];
    snprintf(buf, sizeof buf, "%d", mp);
    vsv_meta_add_attr(g, "MAP_PROJ", buf);
    snprintf(buf, sizeof buf, "%d", (int)att_double(nc, "MP_PHYSICS", -1));
    vsv_meta_add_attr(g, "MP_PHYSICS", buf);
}

/* Terrain (HGT, else the lowest w-level) and land use with its water categories. */
static int wrf_surface(vsv_source *s, wrf *w)
{
    const int nc = w->nc;
    const size_t plane = (size_t)w->nx * w->ny;
    const size_t pshape[2] = {(size_t)w->ny, (size_t)w->nx};
    vsv_meta *g = &s->grid;
    int rc;
    /* terrain: HGT, else the lowest w-level */
    if (vsv_meta_alloc_terrain(g))
        return VSV_ENOMEM;
    int hv;
    if (nc_inq_varid(nc, "HGT", &hv) == NC_NOERR) {
        if ((rc = vsv_nc_read(s, nc, hv, "HGT", 0, pshape, 2, g->terrain)))
            return rc;
    } else {
        if ((rc = w_heights(s, w, 0)))
            return rc;
        memcpy(g->terrain, w->zw, plane * sizeof(float));
    }
    /* land use, and which categories are water: LU_INDEX with the file's
     * ISWATER (and ISLAKE), else LANDMASK (0 water), else XLAND (2 water) */
    static const char *const lu_names[] = {"LU_INDEX", "LANDMASK", "XLAND"};
    for (int i = 0; i < 3; i++) {
        int lv;
        char water[32] = "";
        const int isw = (int)att_double(nc, "ISWATER", -1), isl = (int)att_double(nc, "ISLAKE", -1);
        if (i == 0 && isw >= 0 && isw < 64)
            snprintf(water, sizeof water, isl >= 0 && isl < 64 ? "%d,%d" : "%d", isw, isl);
        else if (i > 0)
            snprintf(water, sizeof water, "%d", i == 1 ? 0 : 2);
        if (!water[0] || nc_inq_varid(nc, lu_names[i], &lv) != NC_NOERR)
            continue;
        if (vsv_meta_alloc_landuse(g))
            return VSV_ENOMEM;
        if ((rc = vsv_nc_read(s, nc, lv, lu_names[i], 0, pshape, 2, g->landuse)))
            return rc;
        vsv_meta_add_attr(g, "landuse_water", water);
        vsv_meta_add_attr(g, "landuse", lu_names[i]);
        break;
    }
    return 0;
}

/* The vertical: even heights, or the native levels' heights at every time. */
static int wrf_vertical(vsv_source *s, wrf *w)
{
    int rc;
    if ((rc = w_heights(s, w, 0)))
        return rc;
    const int even = vsv_source_axis(s, w->zm, w->nk, 100.0); /* no invented levels above the file's top */
    if (even < 0)
        return even;
    w->even = even;
    /* native: the levels' heights in every column, at every time they move */
    for (int t = 0; !even && t < s->ntimes; t++)
        if ((rc = w_heights(s, w, t)) || (rc = vsv_source_native_heights(s, t, w->zm)))
            return rc;
    return 0;
}

/* The fields: the 4-D float variables on (Time, bottom_top[_stag],
 * south_north[_stag], west_east[_stag]), each with its staggering. */
static int wrf_fields(vsv_source *s, wrf *w)
{
    const int nc = w->nc;
    int nvars;
    nc_inq_nvars(nc, &nvars);
    s->fields = calloc((size_t)nvars + 1, sizeof *s->fields);
    w->varid = calloc((size_t)nvars + 1, sizeof *w->varid);
    w->stag = calloc((size_t)nvars + 1, sizeof *w->stag);
    if (!s->fields || !w->varid || !w->stag)
        return VSV_ENOMEM;
    for (int v = 0; v < nvars; v++) {
        char name[NC_MAX_NAME + 1], dn[4][NC_MAX_NAME + 1];
        int dims[NC_MAX_VAR_DIMS];
        nc_type type;
        int nd;
        if (nc_inq_var(nc, v, name, &type, &nd, dims, NULL) || nd != 4 || (type != NC_FLOAT && type != NC_DOUBLE) ||
            strlen(name) >= sizeof s->fields[0].name)
            continue;
        for (int d = 0; d < 4; d++)
            nc_inq_dimname(nc, dims[d], dn[d]);
        int stag = 0;
        if (strcmp(dn[0], "Time"))
            continue;
        if (!strcmp(dn[1], "bottom_top_stag"))
            stag = 3;
        else if (strcmp(dn[1], "bottom_top"))
            continue;
        if (!strcmp(dn[2], "south_north_stag"))
            stag = stag ? -1 : 2;
        else if (strcmp(dn[2], "south_north"))
            continue;
        if (!strcmp(dn[3], "west_east_stag"))
            stag = stag ? -1 : 1;
        else if (strcmp(dn[3], "west_east"))
            continue;
        if (stag < 0)
            continue;
        vsv_field_info *f = &s->fields[s->nfields];
        snprintf(f->name, sizeof f->name, "%s", name);
        size_t al;
        if (nc_inq_attlen(nc, v, "units", &al) == NC_NOERR && al < sizeof f->units)
            nc_get_att_text(nc, v, "units", f->units);
        if (nc_inq_attlen(nc, v, "description", &al) == NC_NOERR && al < sizeof f->description)
            nc_get_att_text(nc, v, "description", f->description);
        static const char *const sn[] = {"mass", "X stag", "Y stag", "Z stag"};
        snprintf(f->ordering, sizeof f->ordering, "%s", sn[stag]);
        f->nlevels = stag == 3 ? w->nk + 1 : w->nk;
        f->is_volume = 1;
        f->is_default = is_default_wrf(name);
        w->varid[s->nfields] = v;
        w->stag[s->nfields] = stag;
        s->nfields++;
    }
    return 0;
}

static int wrf_open(vsv_source *s, int nc)
{
    wrf *w = calloc(1, sizeof *w);
    if (!w) {
        vsv_nc_close(nc);
        return VSV_ENOMEM;
    }
    s->priv = w;
    w->nc = nc;
    w->vgrid_t = -1;
    /* everything acquired hangs off w and s, freed by wrf_close */
    size_t nt;
    int mp, rc;
    if ((rc = wrf_dims(s, w, &nt)) || (rc = wrf_times(s, nc, nt)))
        return rc;
    /* projection and position: the first cell's lat/lon placed in the projection */
    s->grid.nx = w->nx;
    s->grid.ny = w->ny;
    if ((rc = wrf_projection(s, nc, &mp)) || (rc = wrf_position(s, w, mp)))
        return rc;
    wrf_describe(s, w, mp);
    if ((rc = wrf_surface(s, w)) || (rc = wrf_moves(s, w, mp)) || (rc = wrf_vertical(s, w)))
        return rc;
    return wrf_fields(s, w);
}

static int wrf_read(vsv_source *s, int field, int t, float *out)
{
    wrf *w = s->priv;
    const int nx = w->nx, ny = w->ny, nk = w->nk, stag = w->stag[field];
    const size_t plane = (size_t)nx * ny;
    const size_t shape[3] = {(size_t)nk + (stag == 3), (size_t)ny + (stag == 2), (size_t)nx + (stag == 1)};
    int rc = vsv_nc_read(s, w->nc, w->varid[field], s->fields[field].name, t, shape, 3, w->raw);
    if (rc)
        return rc;
    /* destagger onto mass points: the mean of the two faces around each cell */
    for (int k = 0; k < nk; k++)
        for (int j = 0; j < ny; j++)
            for (int i = 0; i < nx; i++) {
                const size_t o = ((size_t)k * ny + j) * nx + i;
                float v;
                if (stag == 1) {
                    const float *r = w->raw + ((size_t)k * ny + j) * (nx + 1) + i;
                    v = 0.5f * (r[0] + r[1]);
                } else if (stag == 2) {
                    const float *r = w->raw + ((size_t)k * (ny + 1) + j) * nx + i;
                    v = 0.5f * (r[0] + r[nx]);
                } else if (stag == 3) {
                    v = 0.5f * (w->raw[o] + w->raw[o + plane]);
                } else {
                    v = w->raw[o];
                }
                w->nat[o] = v;
            }
    if (!w->even) {
        memcpy(out, w->nat, plane * (size_t)nk * sizeof *out);
        return 0;
    }
    /* heights move with time in WRF: plan the resampling for this time */
    if (w->vgrid_t != t) {
        if ((rc = w_heights(s, w, t)))
            return rc;
        const vsv_meta g = vsv_meta_placed(&s->grid, s->times[t]); /* the ground under a moving nest then */
        if (vsv_vgrid_plan(&w->vg, w->zm, nk, plane, g.terrain, g.nz, g.origin[2], g.spacing[2]))
            return VSV_ENOMEM;
        w->vgrid_t = t;
    }
    vsv_vgrid_apply(&w->vg, w->nat, out);
    return 0;
}

static int wrf_heights(vsv_source *s, int t, float *out)
{
    wrf *w = s->priv;
    int rc = w_heights(s, w, t);
    if (!rc)
        memcpy(out, w->zm, (size_t)w->nx * w->ny * (size_t)w->nk * sizeof *out);
    return rc;
}

static void wrf_close(vsv_source *s)
{
    wrf *w = s->priv;
    if (!w)
        return;
    vsv_nc_close(w->nc);
    free(w->varid);
    free(w->stag);
    free(w->zw);
    free(w->zm);
    free(w->raw);
    free(w->nat);
    vsv_vgrid_free(&w->vg);
    free(w);
}

static char *wrf_summary(vsv_source *s)
{
    vsv_buf b = {0};
    char line[512];
    const vsv_meta *g = &s->grid;
    snprintf(line, sizeof line,
             "WRF output: %s\n  projection  %s (MAP_PROJ %s), lat0 %g, lon0 %g, true lat %g/%g\n  grid        %d x %d, "
             "%g x %g m\n  times       %d\n  fields      %d 3-D\n",
             g->run, vsv_proj_name(g->proj.kind), vsv_meta_attr(g, "MAP_PROJ"), g->proj.lat0, g->proj.lon0,
             g->proj.lat1, g->proj.lat2, g->nx, g->ny, g->spacing[0], g->spacing[1], s->ntimes, s->nfields);
    vsv_buf_put(&b, line, strlen(line));
    for (int i = 0; i < s->nfields; i++) {
        snprintf(line, sizeof line, "    %-10s %-7s %3d %-12s %s\n", s->fields[i].name, s->fields[i].ordering,
                 s->fields[i].nlevels, s->fields[i].units, s->fields[i].description);
        vsv_buf_put(&b, line, strlen(line));
    }
    vsv_buf_put(&b, "", 1);
    return (char *)b.p;
}

/* WRF's read/close/summary; the open of every netCDF file starts here. */
const vsv_source_ops vsv_netcdf_ops = {"WRF",     nc_probe,    netcdf_open, wrf_read,
                                       wrf_close, wrf_summary, wrf_heights, NULL};
