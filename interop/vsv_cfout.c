/* vsv_cfout.c — a .vsv out as one CF-1.8 netCDF-4 file (layout in
 * vsv_cf.h): the grid mapping from the file's projection, 2-D lat/lon from
 * the library's own cell positions, the decoded values of each step. */
#include "vsv_cf_internal.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <netcdf.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Records the first failure as "path: what: netCDF's reason". */
typedef struct cfw {
    int nc, rc;
    const char *path;
    char *err;
    size_t cap;
} cfw;

static int nc_ok(cfw *w, int status, const char *what)
{
    const int e = errno; /* a failed write's cause, which HDF5 reports only as "HDF error" */
    if (status != NC_NOERR && !w->rc) {
        /* netCDF-4 returns EACCES for any failed H5Fcreate: on a full disk
         * that read "cannot create: Permission denied"; errno has the cause */
        const int io =
            (status == NC_EHDFERR || status == EACCES) && (e == ENOSPC || e == EFBIG || e == EDQUOT || e == EIO);
        if (io && status == EACCES)
            snprintf(w->err, w->cap, "%s: %s: %s", w->path, what, strerror(e));
        else
            snprintf(w->err, w->cap, "%s: %s: %s%s%s", w->path, what, nc_strerror(status), io ? ": " : "",
                     io ? strerror(e) : "");
        w->rc = VSV_EIO;
    }
    return status == NC_NOERR;
}

static void att_text(cfw *w, int var, const char *name, const char *text)
{
    nc_ok(w, nc_put_att_text(w->nc, var, name, strlen(text), text), name);
}

static void att_double(cfw *w, int var, const char *name, int n, const double *v)
{
    nc_ok(w, nc_put_att_double(w->nc, var, name, NC_DOUBLE, (size_t)n, v), name);
}

static void att_one(cfw *w, int var, const char *name, double v) { att_double(w, var, name, 1, &v); }

/* The grid_mapping attributes of p on variable var (CF 1.8 appendix F). The
 * false easting/northing are this file's coordinates of the projection's
 * natural origin, so x/y stay the .vsv's own projected coordinates. */
static void grid_mapping(cfw *w, int var, const vsv_proj *p)
{
    const double R = p->radius > 0 ? p->radius : 6370000.0;
    double olat = p->lat0, fe = 0, fn = 0;
    const double sp[2] = {p->lat1, p->lat2};
    const int nsp = fabs(p->lat1 - p->lat2) < 1e-12 ? 1 : 2;
    switch (p->kind) {
    case VSV_PROJ_LATLON: att_text(w, var, "grid_mapping_name", "latitude_longitude"); break;
    case VSV_PROJ_LCC:
        att_text(w, var, "grid_mapping_name", "lambert_conformal_conic");
        att_double(w, var, "standard_parallel", nsp, sp);
        att_one(w, var, "longitude_of_central_meridian", p->lon0);
        att_one(w, var, "latitude_of_projection_origin", p->lat0);
        break;
    case VSV_PROJ_PSTEREO: {
        const double lts = p->lat1 != 0 ? p->lat1 : (p->lat0 >= 0 ? 90 : -90);
        olat = (p->lat1 != 0 ? p->lat1 : p->lat0) >= 0 ? 90 : -90;
        att_text(w, var, "grid_mapping_name", "polar_stereographic");
        att_one(w, var, "straight_vertical_longitude_from_pole", p->lon0);
        att_one(w, var, "latitude_of_projection_origin", olat);
        att_one(w, var, "standard_parallel", lts);
        break;
    }
    case VSV_PROJ_MERCATOR:
        olat = 0;
        att_text(w, var, "grid_mapping_name", "mercator");
        att_one(w, var, "longitude_of_projection_origin", p->lon0);
        att_one(w, var, "standard_parallel", p->lat1);
        break;
    case VSV_PROJ_TMERC:
        att_text(w, var, "grid_mapping_name", "transverse_mercator");
        att_one(w, var, "scale_factor_at_central_meridian", p->lat1 > 0 ? p->lat1 : 1.0);
        att_one(w, var, "longitude_of_central_meridian", p->lon0);
        att_one(w, var, "latitude_of_projection_origin", p->lat0);
        break;
    case VSV_PROJ_ALBERS:
        att_text(w, var, "grid_mapping_name", "albers_conical_equal_area");
        att_double(w, var, "standard_parallel", nsp, sp);
        att_one(w, var, "longitude_of_central_meridian", p->lon0);
        att_one(w, var, "latitude_of_projection_origin", p->lat0);
        break;
    default: return;
    }
    att_one(w, var, "earth_radius", R);
    if (p->kind != VSV_PROJ_LATLON) {
        if (vsv_proj_forward(p, olat, p->lon0, &fe, &fn))
            fe = fn = 0;
        att_one(w, var, "false_easting", fe);
        att_one(w, var, "false_northing", fn);
    }
    char params[256];
    snprintf(params, sizeof params, "%s lat0=%.10g lon0=%.10g lat1=%.10g lat2=%.10g radius=%.10g",
             vsv_proj_name(p->kind), p->lat0, p->lon0, p->lat1, p->lat2, R);
    att_text(w, var, "vsv_projection", params);
}

/* A netCDF name from free text: letters, digits and underscores. */
static void nc_name(const char *in, char *out, size_t cap)
{
    size_t n = 0;
    for (; *in && n + 1 < cap; in++)
        out[n++] =
            (char)((*in >= 'a' && *in <= 'z') || (*in >= 'A' && *in <= 'Z') || (*in >= '0' && *in <= '9') ? *in : '_');
    out[n] = 0;
}

/* The time axis's attributes: seconds since step a's time, in the file's calendar. */
static void def_time(cfw *w, int vt, vsv_file *f, int a)
{
    const vsv_meta *m = vsv_file_meta(f);
    char since[64], units[96];
    const int cal = vsv_meta_calendar(m);
    vsv_cal_format(cal, vsv_file_time(f, a), since, sizeof since);
    since[10] = ' '; /* "YYYY-MM-DD HH:MM:SS", the UDUNITS form */
    since[19] = 0;
    snprintf(units, sizeof units, "seconds since %s", since);
    att_text(w, vt, "standard_name", "time");
    att_text(w, vt, "long_name", "time");
    att_text(w, vt, "units", units);
    att_text(w, vt, "calendar", vsv_calendar_name(cal));
    att_text(w, vt, "axis", "T");
}

/* The vertical axis's attributes: CF's altitude counts from sea level, its height from the ground. */
static void def_z(cfw *w, int vz, const vsv_meta *m, const char *zname, const char *datum)
{
    char text[512];
    switch (m->vert_kind) {
    case VSV_VERT_EVEN:
    case VSV_VERT_NATIVE:
        att_text(w, vz, "standard_name", zname);
        snprintf(text, sizeof text, "%sheight above %s%s", m->vert_kind == VSV_VERT_EVEN ? "" : "mean ", datum,
                 m->vert_kind == VSV_VERT_EVEN ? "" : " of the model level");
        att_text(w, vz, "long_name", text);
        att_text(w, vz, "units", "m");
        att_text(w, vz, "positive", "up");
        break;
    case VSV_VERT_COORD:
        att_text(w, vz, "long_name", "model level coordinate");
        att_text(w, vz, "units", m->vert_units);
        if (!strcmp(m->vert_units, "hPa") || !strcmp(m->vert_units, "Pa")) {
            att_text(w, vz, "standard_name", "air_pressure");
            att_text(w, vz, "positive", "down");
        }
        break;
    default:
        att_text(w, vz, "standard_name", "model_level_number");
        att_text(w, vz, "long_name", "layer index");
        att_text(w, vz, "units", "1");
        att_text(w, vz, "positive", "up");
    }
    att_text(w, vz, "axis", "Z");
}

/* The horizontal axes' attributes: longitude and latitude, or projection metres. */
static void def_xy(cfw *w, int vx, int vy, int latlon)
{
    if (latlon) {
        att_text(w, vx, "standard_name", "longitude");
        att_text(w, vx, "units", "degrees_east");
        att_text(w, vy, "standard_name", "latitude");
        att_text(w, vy, "units", "degrees_north");
    } else {
        att_text(w, vx, "standard_name", "projection_x_coordinate");
        att_text(w, vx, "long_name", "x coordinate of projection (cell centre)");
        att_text(w, vx, "units", "m");
        att_text(w, vy, "standard_name", "projection_y_coordinate");
        att_text(w, vy, "long_name", "y coordinate of projection (cell centre)");
        att_text(w, vy, "units", "m");
    }
    att_text(w, vx, "axis", "X");
    att_text(w, vy, "axis", "Y");
}

/* One 4-D variable for each species selected, its ids into vid; the number whose unit was spelt anew. */
static int def_species(cfw *w, vsv_file *f, const int *sel, int n, int *vid, const int d4[4], const char *coords)
{
    const vsv_meta *m = vsv_file_meta(f);
    const size_t nx = (size_t)m->nx, ny = (size_t)m->ny, nz = (size_t)m->nz;
    const int has_proj = m->proj.kind != VSV_PROJ_NONE;
    int respelt = 0; /* variables whose unit was spelt anew */
    for (int l = 0; l < n && !w->rc; l++) {
        const vsv_var *v = &m->vars[sel[l]];
        const vsv_quant *q = vsv_file_quant(f, sel[l]);
        char name[NC_MAX_NAME + 1];
        nc_name(v->name, name, sizeof name);
        if (!nc_ok(w, nc_def_var(w->nc, name, NC_FLOAT, 4, d4, &vid[l]), v->name))
            break;
        const size_t chunk[4] = {1, nz, ny, nx};
        nc_ok(w, nc_def_var_chunking(w->nc, vid[l], NC_CHUNKED, chunk), "chunking");
        nc_ok(w, nc_def_var_deflate(w->nc, vid[l], 1, 1, 4), "deflate");
        { /* no data (the species' own, or below the ground) is NaN */
            const float nan = NAN;
            nc_ok(w, nc_def_var_fill(w->nc, vid[l], 0, &nan), "_FillValue");
        }
        att_text(w, vid[l], "long_name", v->description[0] ? v->description : v->name);
        /* no units given: none written (an empty one reads as dimensionless) */
        const char *vunits = vsv_cf_units(v->units), *comment;
        if (vunits[0])
            att_text(w, vid[l], "units", vunits);
        if (strcmp(vunits, v->units)) {
            att_text(w, vid[l], "vsv_units_original", v->units);
            respelt++;
        }
        const char *sn = vsv_cf_standard_name(m->model, v->name, v->units, &comment);
        if (sn)
            att_text(w, vid[l], "standard_name", sn);
        if (comment)
            att_text(w, vid[l], "comment", comment);
        if (coords)
            att_text(w, vid[l], "coordinates", coords);
        if (has_proj)
            att_text(w, vid[l], "grid_mapping", "crs");
        att_one(w, vid[l], "vsv_max_abs_error", q->max_abs_error);
        char qs[128];
        snprintf(qs, sizeof qs, "%d-bit %s over [%.9g, %.9g]%s", q->bits, q->scale == VSV_SCALE_LOG ? "log" : "linear",
                 q->lo, q->hi, q->missing ? ", no-data cells NaN" : "");
        att_text(w, vid[l], "vsv_quantisation", qs);
        if (strcmp(name, v->name))
            att_text(w, vid[l], "vsv_name", v->name);
    }
    return respelt;
}

/* The global attributes: CF's, the model's and the file's own. */
static void def_globals(cfw *w, const vsv_meta *m, const char *history, int respelt)
{
    char text[512];
    att_text(w, NC_GLOBAL, "Conventions", "CF-1.8");
    snprintf(text, sizeof text, "%s%s%s", m->model[0] ? m->model : "Vesuvius", m->run[0] ? ": " : "", m->run);
    att_text(w, NC_GLOBAL, "title", text);
    snprintf(
        text, sizeof text,
        "%s, through a Vesuvius .vsv file (values as decoded: within each variable's vsv_max_abs_error of the model's)",
        m->model[0] ? m->model : "unknown model");
    att_text(w, NC_GLOBAL, "source", text);
    if (history || respelt) {
        char hist[1800];
        snprintf(hist, sizeof hist, "%s%s%s", history ? history : "", history && respelt ? "\n" : "",
                 respelt ? "units in the model's spelling written as UDUNITS spells them (ppmV as ppm, "
                           "micrograms/m**3 as ug m-3); each such variable keeps the model's in vsv_units_original"
                         : "");
        att_text(w, NC_GLOBAL, "history", hist);
    }
    att_text(w, NC_GLOBAL, "vsv_model", m->model);
    att_text(w, NC_GLOBAL, "vsv_run", m->run);
    for (int i = 0; i < m->nattrs; i++) {
        char key[NC_MAX_NAME + 1];
        char raw[80];
        snprintf(raw, sizeof raw, "vsv_attr_%s", m->attr_keys[i]);
        nc_name(raw, key, sizeof key);
        att_text(w, NC_GLOBAL, key, m->attr_values[i]);
    }
}

/* The 1-D coordinates' values: seconds from step a, the levels' heights, y and x; buf holds the longest. */
static void put_axes(cfw *w, vsv_file *f, const vsv_meta *m, int a, size_t nt, double *buf, int vt, int vz, int vy,
                     int vx)
{
    const size_t nx = (size_t)m->nx, ny = (size_t)m->ny, nz = (size_t)m->nz;
    int64_t *tv = (int64_t *)buf;
    for (size_t t = 0; t < nt; t++)
        tv[t] = vsv_file_time(f, a + (int)t) - vsv_file_time(f, a);
    nc_ok(w, nc_put_var_longlong(w->nc, vt, (const long long *)tv), "time");
    for (size_t k = 0; k < nz; k++)
        buf[k] = vsv_meta_cell_height(m, 0, 0, (int)k);
    nc_ok(w, nc_put_var_double(w->nc, vz, buf), "z");
    for (size_t i = 0; i < nx; i++)
        buf[i] = m->origin[0] + (double)i * m->spacing[0];
    nc_ok(w, nc_put_var_double(w->nc, vx, buf), "x");
    for (size_t j = 0; j < ny; j++)
        buf[j] = m->origin[1] + (double)j * m->spacing[1];
    nc_ok(w, nc_put_var_double(w->nc, vy, buf), "y");
}

/* One file, one place: steps a..b of a moving nest at one placement (its x
 * and y differ between placements); 0, or VSV_EUNSUPPORTED with err set. */
static int one_place(vsv_file *f, int a, int b, const char *path, char *err, size_t cap)
{
    const vsv_meta *fm = vsv_file_meta(f);
    const vsv_move *ma = vsv_meta_move_at(fm, vsv_file_time(f, a));
    for (int t = a + 1; t <= b; t++)
        if (vsv_meta_move_at(fm, vsv_file_time(f, t)) != ma) {
            char iso[40];
            vsv_cal_format(vsv_meta_calendar(fm), vsv_file_time(f, t), iso, sizeof iso);
            snprintf(err, cap,
                     "%s: the grid moves at %s (step %d; a moving nest): a netCDF file holds one placement, "
                     "so export the steps before it and from it apart (--times)",
                     path, iso, t);
            return VSV_EUNSUPPORTED;
        }
    return 0;
}

int vsv_cf_write_here(const char *target, const char *path, vsv_file *f, const int *sel, int n, int a, int b,
                      const char *history, void (*progress)(void *ctx, int done, int total), void *ctx, char *err,
                      size_t cap)
{
    const vsv_meta *fm = vsv_file_meta(f);
    vsv_file_info info;
    vsv_file_info_get(f, &info);
    cfw w = {-1, 0, path, err, cap};
    if (n < 1 || a < 0 || b >= info.nsteps || a > b) {
        snprintf(err, cap, "%s: nothing selected (steps %d..%d of 0..%d, %d species)", path, a, b, info.nsteps - 1, n);
        return VSV_EINVAL;
    }
    if (one_place(f, a, b, path, err, cap))
        return VSV_EUNSUPPORTED;
    const vsv_meta placed = vsv_meta_placed(fm, vsv_file_time(f, a)), *m = &placed;
    const size_t nx = (size_t)m->nx, ny = (size_t)m->ny, nz = (size_t)m->nz, nt = (size_t)(b - a + 1);
    float *vol = malloc(nx * ny * nz * sizeof *vol);
    size_t nbuf = 2 * nx * ny; /* lat and lon; also the time, z, y, x axes */
    nbuf = nbuf > nt ? nbuf : nt;
    nbuf = nbuf > nz ? nbuf : nz;
    double *buf = malloc(nbuf * sizeof *buf);
    int *vid = calloc((size_t)n, sizeof *vid);
    vsv_decoder *d = NULL;
    if (!vol || !buf || !vid || vsv_decoder_create(f, &d)) {
        snprintf(err, cap, "%s: out of memory", path);
        w.rc = VSV_ENOMEM;
        goto fail;
    }
    if (!nc_ok(&w, nc_create(target, NC_CLOBBER | NC_NETCDF4, &w.nc), "cannot create"))
        goto fail;
    int dt, dz, dy, dx;
    nc_ok(&w, nc_def_dim(w.nc, "time", nt, &dt), "time");
    nc_ok(&w, nc_def_dim(w.nc, "z", nz, &dz), "z");
    nc_ok(&w, nc_def_dim(w.nc, "y", ny, &dy), "y");
    nc_ok(&w, nc_def_dim(w.nc, "x", nx, &dx), "x");
    const int has_proj = m->proj.kind != VSV_PROJ_NONE, latlon = m->proj.kind == VSV_PROJ_LATLON;
    int vt, vz, vy, vx, vlat = -1, vlon = -1, vcrs = -1, vter = -1;
    const int d2[2] = {dy, dx}, d4[4] = {dt, dz, dy, dx};
    nc_ok(&w, nc_def_var(w.nc, "time", NC_INT64, 1, &dt, &vt), "time");
    nc_ok(&w, nc_def_var(w.nc, "z", NC_DOUBLE, 1, &dz, &vz), "z");
    nc_ok(&w, nc_def_var(w.nc, "y", NC_DOUBLE, 1, &dy, &vy), "y");
    nc_ok(&w, nc_def_var(w.nc, "x", NC_DOUBLE, 1, &dx, &vx), "x");
    def_time(&w, vt, f, a);
    /* vertical: CF's altitude counts from sea level, its height from the ground */
    const int agl = vsv_meta_above_ground(m);
    const char *zname = agl ? "height" : "altitude", *datum = agl ? "the ground" : "sea level";
    char text[512];
    def_z(&w, vz, m, zname, datum);
    def_xy(&w, vx, vy, latlon);
    if (has_proj) {
        nc_ok(&w, nc_def_var(w.nc, "crs", NC_INT, 0, NULL, &vcrs), "crs");
        grid_mapping(&w, vcrs, &m->proj);
        if (!latlon) {
            nc_ok(&w, nc_def_var(w.nc, "lat", NC_DOUBLE, 2, d2, &vlat), "lat");
            nc_ok(&w, nc_def_var(w.nc, "lon", NC_DOUBLE, 2, d2, &vlon), "lon");
            att_text(&w, vlat, "standard_name", "latitude");
            att_text(&w, vlat, "long_name", "latitude of the cell centre");
            att_text(&w, vlat, "units", "degrees_north");
            att_text(&w, vlon, "standard_name", "longitude");
            att_text(&w, vlon, "long_name", "longitude of the cell centre");
            att_text(&w, vlon, "units", "degrees_east");
        }
    }
    /* per-column heights of native levels (moving in time): a 4-D auxiliary coordinate */
    int vh = -1;
    const int colh = m->vert_kind == VSV_VERT_NATIVE && m->nheights > 0;
    if (colh) {
        nc_ok(&w, nc_def_var(w.nc, "height", NC_FLOAT, 4, d4, &vh), "height");
        const size_t chunk[4] = {1, nz, ny, nx};
        nc_ok(&w, nc_def_var_chunking(w.nc, vh, NC_CHUNKED, chunk), "chunking");
        nc_ok(&w, nc_def_var_deflate(w.nc, vh, 1, 1, 4), "deflate");
        att_text(&w, vh, "standard_name", zname);
        snprintf(text, sizeof text, "height above %s of the cell centre (the model level in this column)", datum);
        att_text(&w, vh, "long_name", text);
        att_text(&w, vh, "units", "m");
        att_text(&w, vh, "positive", "up");
        if (has_proj && !latlon)
            att_text(&w, vh, "coordinates", "lat lon");
        if (has_proj)
            att_text(&w, vh, "grid_mapping", "crs");
    }
    const char *coords = has_proj && !latlon ? (colh ? "lat lon height" : "lat lon") : (colh ? "height" : NULL);
    if (m->terrain) {
        nc_ok(&w, nc_def_var(w.nc, "terrain", NC_FLOAT, 2, d2, &vter), "terrain");
        att_text(&w, vter, "standard_name", "surface_altitude");
        att_text(&w, vter, "long_name", "terrain height");
        att_text(&w, vter, "units", "m");
        if (has_proj && !latlon) /* (not height: a coordinate has no dimension its variable lacks) */
            att_text(&w, vter, "coordinates", "lat lon");
        if (has_proj)
            att_text(&w, vter, "grid_mapping", "crs");
    }
    const int respelt = def_species(&w, f, sel, n, vid, d4, coords);
    def_globals(&w, m, history, respelt);
    if (w.rc || !nc_ok(&w, nc_enddef(w.nc), "defining the variables"))
        goto fail;
    /* coordinates */
    put_axes(&w, f, m, a, nt, buf, vt, vz, vy, vx);
    if (vlat >= 0) {
        double *lat = buf, *lon = buf + nx * ny;
        for (size_t j = 0; j < ny; j++)
            for (size_t i = 0; i < nx; i++)
                if (vsv_meta_cell_latlon(m, (double)i, (double)j, &lat[j * nx + i], &lon[j * nx + i]))
                    lat[j * nx + i] = lon[j * nx + i] = NAN;
        nc_ok(&w, nc_put_var_double(w.nc, vlat, lat), "lat");
        nc_ok(&w, nc_put_var_double(w.nc, vlon, lon), "lon");
    }
    if (vter >= 0)
        nc_ok(&w, nc_put_var_float(w.nc, vter, m->terrain), "terrain");
    if (vcrs >= 0) {
        const int zero = 0;
        nc_ok(&w, nc_put_var_int(w.nc, vcrs, &zero), "crs");
    }
    /* the values, step by step */
    for (int t = a; t <= b && !w.rc; t++) {
        for (int l = 0; l < n && !w.rc; l++) {
            int rc = vsv_decoder_volume(d, t, sel[l], vol);
            if (rc) {
                snprintf(err, cap, "%s", vsv_decoder_error(d));
                w.rc = rc;
                break;
            }
            const size_t start[4] = {(size_t)(t - a), 0, 0, 0}, count[4] = {1, nz, ny, nx};
            nc_ok(&w, nc_put_vara_float(w.nc, vid[l], start, count, vol), m->vars[sel[l]].name);
        }
        if (vh >= 0) {
            const size_t start[4] = {(size_t)(t - a), 0, 0, 0}, count[4] = {1, nz, ny, nx};
            nc_ok(&w, nc_put_vara_float(w.nc, vh, start, count, vsv_meta_heights_at(m, vsv_file_time(f, t))), "height");
        }
        if (progress)
            progress(ctx, t - a + 1, (int)nt);
    }
    if (w.rc)
        goto fail;
    const int crc = nc_close(w.nc);
    w.nc = -1;
    nc_ok(&w, crc, "writing");
fail:
    /* (an open file is left as it is: libnetcdf's close after a failed
     * HDF5 write crashes, and this process ends without exit handlers) */
    free(vol);
    free(buf);
    free(vid);
    vsv_decoder_free(d);
    return w.rc;
}
