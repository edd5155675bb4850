/* vsv_cf.c — CF-convention netCDF (Conventions "CF-…"): the 4-D variables on
 * (time, z, y, x) dimensions with 1-D coordinate variables, times from
 * "<unit> since <date>", the grid_mapping (lambert_conformal_conic,
 * polar_stereographic, mercator, transverse_mercator,
 * albers_conical_equal_area, latitude_longitude, on a sphere) turned back
 * into the .vsv projection, heights from an altitude/height z (even spacing
 * kept as even, else native levels), pressure or index levels, terrain from
 * a surface_altitude variable; _FillValue/missing_value → no data,
 * scale_factor/add_offset applied. What vsv-export --netcdf writes reads back
 * exactly; files of other CF writers read when they fit this shape. */
#include "vsv_source_internal.h"

#include <math.h>
#include <netcdf.h>
#include <stdlib.h>
#include <string.h>

typedef struct cf {
    int nc;
    int *varid;
    int flip_y; /* y decreases in the file: rows are reversed */
    float *tmp;
} cf;

/* Text attribute of var into buf ("" if absent). */
static void att_str(int nc, int var, const char *name, char *buf, size_t cap)
{
    size_t len = 0;
    buf[0] = 0;
    if (nc_inq_attlen(nc, var, name, &len) || len >= cap)
        return;
    nc_type type;
    if (nc_inq_atttype(nc, var, name, &type) || type != NC_CHAR)
        return;
    if (nc_get_att_text(nc, var, name, buf) == NC_NOERR)
        buf[len] = 0;
}

/* Numeric attribute values (up to cap); how many, 0 if absent. */
static int att_num(int nc, int var, const char *name, double *v, int cap)
{
    size_t len = 0;
    nc_type type;
    if (nc_inq_attlen(nc, var, name, &len) || nc_inq_atttype(nc, var, name, &type) || type == NC_CHAR ||
        type == NC_STRING || len < 1 || len > (size_t)cap)
        return 0;
    return nc_get_att_double(nc, var, name, v) == NC_NOERR ? (int)len : 0;
}

int vsv_cf_detect(int nc)
{
    char conv[128];
    att_str(nc, NC_GLOBAL, "Conventions", conv, sizeof conv);
    return strstr(conv, "CF-") != NULL;
}

/* The coordinate variable of dimension dim (a variable of the same name on
 * that one dimension), or -1. */
static int coord_var(int nc, int dim)
{
    char name[NC_MAX_NAME + 1];
    int v, nd, d;
    if (nc_inq_dimname(nc, dim, name) || nc_inq_varid(nc, name, &v) || nc_inq_varndims(nc, v, &nd) || nd != 1 ||
        nc_inq_vardimid(nc, v, &d) || d != dim)
        return -1;
    return v;
}

/* Values of 1-D variable v (n of them) as doubles; caller frees. */
static double *coord_values(int nc, int v, size_t n)
{
    double *a = malloc((n ? n : 1) * sizeof *a);
    if (a && nc_get_var_double(nc, v, a)) {
        free(a);
        return NULL;
    }
    return a;
}

/* "seconds since 1995-10-24 00:00:00" → seconds per unit and the epoch (a
 * date of calendar cal). */
static int time_units(const char *u, int cal, double *scale, int64_t *epoch)
{
    char unit[32], date[80] = "";
    if (sscanf(u, "%31s since %79[^\n]", unit, date) != 2)
        return -1;
    static const struct {
        const char *name;
        double s;
    } units[] = {{"seconds", 1}, {"second", 1}, {"secs", 1},     {"s", 1},        {"minutes", 60},
                 {"minute", 60}, {"mins", 60},  {"min", 60},     {"hours", 3600}, {"hour", 3600},
                 {"hrs", 3600},  {"h", 3600},   {"days", 86400}, {"day", 86400},  {"d", 86400}};
    *scale = 0;
    for (size_t i = 0; i < sizeof units / sizeof *units; i++)
        if (!strcmp(unit, units[i].name))
            *scale = units[i].s;
    if (!*scale)
        return -1;
    /* "1995-10-24 00:00:00", "1995-10-24T00:00:00Z", "1995-10-24 00:00:00 UTC", "1995-10-24" */
    char *tz = strstr(date, " UTC");
    if (tz)
        *tz = 0;
    size_t l = strlen(date);
    while (l && date[l - 1] == ' ')
        date[--l] = 0;
    if (l > 19 && date[19] == '.') /* "…:00.0": fractional seconds of the epoch dropped */
        date[19] = 0;
    return vsv_cal_parse(cal, date, epoch) ? -1 : 0;
}

/* The .vsv projection of grid_mapping variable gm; fe/fn its false
 * easting/northing. */
static int cf_projection(vsv_source *s, int nc, int gm, vsv_proj *p, double *fe, double *fn)
{
    char name[64];
    att_str(nc, gm, "grid_mapping_name", name, sizeof name);
    double v[2] = {0, 0}, r = 0;
    memset(p, 0, sizeof *p);
    *fe = *fn = 0;
    att_num(nc, gm, "false_easting", fe, 1);
    att_num(nc, gm, "false_northing", fn, 1);
    if (!att_num(nc, gm, "earth_radius", &r, 1))
        att_num(nc, gm, "semi_major_axis", &r, 1);
    p->radius = r > 0 ? r : 6370000;
    double inv = 0;
    if (att_num(nc, gm, "inverse_flattening", &inv, 1) && inv != 0)
        return vsv_source_fail(s, VSV_EUNSUPPORTED,
                               "grid_mapping %s: an ellipsoid (inverse_flattening %g); only a sphere is supported",
                               name, inv);
    if (!strcmp(name, "latitude_longitude")) {
        p->kind = VSV_PROJ_LATLON;
    } else if (!strcmp(name, "lambert_conformal_conic") || !strcmp(name, "albers_conical_equal_area")) {
        p->kind = name[0] == 'l' ? VSV_PROJ_LCC : VSV_PROJ_ALBERS;
        const int n = att_num(nc, gm, "standard_parallel", v, 2);
        if (!n)
            return vsv_source_fail(s, VSV_ECORRUPT, "grid_mapping %s without standard_parallel", name);
        p->lat1 = v[0];
        p->lat2 = n == 2 ? v[1] : v[0];
        att_num(nc, gm, "longitude_of_central_meridian", &p->lon0, 1);
        att_num(nc, gm, "latitude_of_projection_origin", &p->lat0, 1);
    } else if (!strcmp(name, "polar_stereographic")) {
        p->kind = VSV_PROJ_PSTEREO;
        if (!att_num(nc, gm, "straight_vertical_longitude_from_pole", &p->lon0, 1))
            att_num(nc, gm, "longitude_of_projection_origin", &p->lon0, 1);
        att_num(nc, gm, "latitude_of_projection_origin", &p->lat0, 1);
        double k0 = 0;
        if (att_num(nc, gm, "standard_parallel", v, 1))
            p->lat1 = v[0];
        else if (att_num(nc, gm, "scale_factor_at_projection_origin", &k0, 1) && k0 > 0 && k0 <= 1)
            p->lat1 = copysign(asin(2 * k0 - 1) * 180 / M_PI, p->lat0 >= 0 ? 1 : -1);
        else
            p->lat1 = p->lat0 >= 0 ? 90 : -90;
        p->lat2 = p->lat1;
    } else if (!strcmp(name, "mercator")) {
        p->kind = VSV_PROJ_MERCATOR;
        att_num(nc, gm, "longitude_of_projection_origin", &p->lon0, 1);
        double k0 = 0;
        if (att_num(nc, gm, "standard_parallel", v, 1))
            p->lat1 = v[0];
        else if (att_num(nc, gm, "scale_factor_at_projection_origin", &k0, 1) && k0 > 0 && k0 <= 1)
            p->lat1 = acos(k0) * 180 / M_PI;
        p->lat2 = p->lat1;
    } else if (!strcmp(name, "transverse_mercator")) {
        p->kind = VSV_PROJ_TMERC;
        att_num(nc, gm, "longitude_of_central_meridian", &p->lon0, 1);
        att_num(nc, gm, "latitude_of_projection_origin", &p->lat0, 1);
        double k0 = 1;
        att_num(nc, gm, "scale_factor_at_central_meridian", &k0, 1);
        p->lat1 = p->lat2 = k0;
    } else {
        return vsv_source_fail(s, VSV_EUNSUPPORTED,
                               "grid_mapping_name '%s' is not supported (lambert_conformal_conic, polar_stereographic, "
                               "mercator, transverse_mercator, albers_conical_equal_area, latitude_longitude are)",
                               name);
    }
    return 0;
}

/* Spacing of coordinate values a[0..n-1] if even (1e-6 relative), else 0. */
static double even_step(const double *a, size_t n)
{
    if (n < 2)
        return 0;
    const double d = (a[n - 1] - a[0]) / (double)(n - 1);
    for (size_t i = 1; i < n; i++)
        if (fabs(a[i] - a[i - 1] - d) > 1e-6 * fabs(d) + 1e-9)
            return 0;
    return d;
}

static double unit_scale(const char *u)
{
    return !strcmp(u, "km") ? 1000
           : !strcmp(u, "m") || !strcmp(u, "metre") || !strcmp(u, "meter") || !strcmp(u, "metres") ||
                   !strcmp(u, "meters")
               ? 1
               : 0;
}

/* The four axes of the data: (time, z, y, x) dimensions, their lengths and
 * coordinate variables. */
typedef struct cf_axes {
    int dims[4];
    size_t len[4];
    int cv[4];
} cf_axes;

/* The axes from the first 4-D numeric variable that is not a coordinate;
 * the grid's size from them. */
static int cf_find_axes(vsv_source *s, int nc, int nvars, cf_axes *ax)
{
    /* the dimensions of the first 4-D numeric variable that is not a coordinate */
    int *dims = ax->dims, nd;
    size_t *len = ax->len;
    dims[0] = dims[1] = dims[2] = dims[3] = -1;
    for (int v = 0; v < nvars && dims[0] < 0; v++) {
        nc_type type;
        int dd[NC_MAX_VAR_DIMS];
        if (nc_inq_var(nc, v, NULL, &type, &nd, dd, NULL) || nd != 4 || type == NC_CHAR || type == NC_STRING)
            continue;
        int ok = 1;
        for (int d = 0; d < 4; d++)
            ok &= coord_var(nc, dd[d]) >= 0;
        if (ok)
            memcpy(dims, dd, sizeof ax->dims);
    }
    if (dims[0] < 0)
        return vsv_source_fail(s, VSV_ENOTVSV,
                               "a CF netCDF file without a (time, z, y, x) variable with coordinate variables");
    for (int d = 0; d < 4; d++) {
        nc_inq_dimlen(nc, dims[d], &len[d]);
        ax->cv[d] = coord_var(nc, dims[d]);
    }
    if (len[1] < 1 || len[2] < 1 || len[3] < 1 || len[1] > VSV_MAX_DIM || len[2] > VSV_MAX_DIM || len[3] > VSV_MAX_DIM)
        return vsv_source_fail(s, VSV_ECORRUPT, "grid of %zu x %zu x %zu cells out of range", len[3], len[2], len[1]);
    vsv_meta *g = &s->grid;
    g->nx = (int)len[3];
    g->ny = (int)len[2];
    g->nz = (int)len[1];
    return 0;
}

/* The times from the time coordinate, in its calendar and units; increasing. */
static int cf_times(vsv_source *s, int nc, const cf_axes *ax)
{
    vsv_meta *g = &s->grid;
    const int *cv = ax->cv;
    const size_t *len = ax->len;
    char u[256], dn[NC_MAX_NAME + 1];
    nc_inq_dimname(nc, ax->dims[0], dn);
    att_str(nc, cv[0], "units", u, sizeof u);
    double tscale;
    int64_t epoch;
    char cal[64];
    att_str(nc, cv[0], "calendar", cal, sizeof cal);
    /* the model's calendar: its dates and intervals kept (VSV_ATTR_CALENDAR) */
    const int calendar = cal[0] ? vsv_calendar_named(cal) : VSV_CAL_STANDARD;
    if (calendar < 0)
        return vsv_source_fail(s, VSV_EUNSUPPORTED,
                               "variable %s: calendar '%s' (standard, gregorian, proleptic_gregorian, noleap, 365_day, "
                               "all_leap, 366_day or 360_day)",
                               dn, cal);
    if (calendar != VSV_CAL_STANDARD && vsv_meta_add_attr(g, VSV_ATTR_CALENDAR, vsv_calendar_name(calendar)) < 0)
        return VSV_ENOMEM;
    if (time_units(u, calendar, &tscale, &epoch))
        return vsv_source_fail(s, VSV_ECORRUPT, "variable %s: units '%s' are not '<unit> since <date>'", dn, u);
    double *tv = coord_values(nc, cv[0], len[0]);
    s->times = calloc(len[0] + 1, sizeof *s->times);
    int rc = VSV_ENOMEM;
    if (!tv || !s->times)
        goto fail;
    for (size_t t = 0; t < len[0]; t++) {
        s->times[t] = epoch + (int64_t)llround(tv[t] * tscale);
        if (t && s->times[t] <= s->times[t - 1]) {
            rc = vsv_source_fail(s, VSV_ECORRUPT, "variable %s: times do not increase at index %zu", dn, t);
            goto fail;
        }
    }
    s->ntimes = (int)len[0];
    rc = 0;
fail:
    free(tv);
    return rc;
}

/* The grid mapping variable (gm, -1 for none), from the first data variable
 * that names one. */
static int cf_find_mapping(vsv_source *s, int nc, int nvars, int *gm)
{
    *gm = -1;
    for (int v = 0; v < nvars && *gm < 0; v++) {
        char gname[NC_MAX_NAME + 1];
        att_str(nc, v, "grid_mapping", gname, sizeof gname);
        if (gname[0] && nc_inq_varid(nc, gname, gm))
            return vsv_source_fail(s, VSV_ECORRUPT, "grid_mapping '%s' names no variable", gname);
    }
    return 0;
}

/* The plan: origin and spacing from the x and y coordinates (m, km or
 * degrees, evenly spaced), less the false easting and northing. */
static int cf_plan(vsv_source *s, cf *c, const cf_axes *ax, int gm, double fe, double fn)
{
    const int nc = c->nc;
    const int *cv = ax->cv;
    const size_t *len = ax->len;
    vsv_meta *g = &s->grid;
    double *xs = coord_values(nc, cv[3], len[3]), *ys = coord_values(nc, cv[2], len[2]);
    int rc = VSV_ENOMEM;
    if (!xs || !ys)
        goto fail;
    char ux[64], uy[64];
    att_str(nc, cv[3], "units", ux, sizeof ux);
    att_str(nc, cv[2], "units", uy, sizeof uy);
    const int deg = g->proj.kind == VSV_PROJ_LATLON || (gm < 0 && !strncmp(ux, "degree", 6));
    if (gm < 0 && deg) {
        g->proj.kind = VSV_PROJ_LATLON;
        g->proj.radius = 6370000;
    }
    const double sx = deg ? 1 : unit_scale(ux), sy = deg ? 1 : unit_scale(uy);
    double dx = even_step(xs, len[3]) * sx, dy = even_step(ys, len[2]) * sy;
    if (len[3] == 1)
        dx = 1;
    if (len[2] == 1)
        dy = 1;
    const double x0 = xs[0] * sx - fe, y0 = ys[len[2] - 1] * sy - fn, y0f = ys[0] * sy - fn;
    if (!sx || !sy) {
        rc = vsv_source_fail(s, VSV_EUNSUPPORTED, "x/y coordinate units '%s'/'%s' (m, km or degrees)", ux, uy);
        goto fail;
    }
    if (!dx || !dy) {
        rc = vsv_source_fail(s, VSV_EUNSUPPORTED,
                             "the x or y coordinate is not evenly spaced (a regular grid is needed)");
        goto fail;
    }
    c->flip_y = dy < 0;
    g->origin[0] = x0;
    g->origin[1] = c->flip_y ? y0 : y0f;
    g->spacing[0] = dx;
    g->spacing[1] = fabs(dy);
    rc = dx < 0 ? vsv_source_fail(s, VSV_EUNSUPPORTED, "x decreases (east to west): not supported") : 0;
fail:
    free(xs);
    free(ys);
    return rc;
}

/* The vertical from the z coordinate: even or native heights (above the
 * ground when its standard_name is height: *above_ground), other
 * coordinates with their units, or the level index. */
static int cf_vertical(vsv_source *s, int nc, const cf_axes *ax, int *above_ground)
{
    const int *cv = ax->cv;
    const size_t *len = ax->len;
    vsv_meta *g = &s->grid;
    double *zs = coord_values(nc, cv[1], len[1]);
    if (!zs)
        return VSV_ENOMEM;
    int rc = 0;
    char uz[64], zstd[64], pos[16];
    att_str(nc, cv[1], "units", uz, sizeof uz);
    att_str(nc, cv[1], "standard_name", zstd, sizeof zstd);
    att_str(nc, cv[1], "positive", pos, sizeof pos);
    const double sz = unit_scale(uz);
    if (sz && strcmp(pos, "down") && strcmp(zstd, "model_level_number")) {
        const double dz = even_step(zs, len[1]);
        for (size_t k = 1; k < len[1]; k++)
            if (!(zs[k] > zs[k - 1])) {
                rc = vsv_source_fail(s, VSV_EUNSUPPORTED, "heights do not increase upward");
                goto fail;
            }
        if (dz > 0 || len[1] == 1) {
            g->vert_kind = VSV_VERT_EVEN;
            g->origin[2] = zs[0] * sz;
            g->spacing[2] = len[1] > 1 ? dz * sz : 1;
        } else {
            g->vert_kind = VSV_VERT_NATIVE;
            if (vsv_meta_alloc_levels(g)) {
                rc = VSV_ENOMEM;
                goto fail;
            }
            for (size_t k = 0; k < len[1]; k++)
                g->levels[k] = zs[k] * sz;
        }
        snprintf(g->vert_units, sizeof g->vert_units, "m");
        if (!strcmp(zstd, "height")) /* CF: above the ground */
            *above_ground = 1;
    } else if (uz[0] && strcmp(uz, "1") && strcmp(zstd, "model_level_number")) {
        g->vert_kind = VSV_VERT_COORD;
        snprintf(g->vert_units, sizeof g->vert_units, "%s", uz);
        if (vsv_meta_alloc_levels(g)) {
            rc = VSV_ENOMEM;
            goto fail;
        }
        memcpy(g->levels, zs, len[1] * sizeof(double));
    } else {
        g->vert_kind = VSV_VERT_INDEX;
    }
fail:
    free(zs);
    return rc;
}

/* The source description: model, run and the run metadata of the globals. */
static int cf_describe(vsv_source *s, int nc, int above_ground)
{
    vsv_meta *g = &s->grid;
    char text[256];
    att_str(nc, NC_GLOBAL, "vsv_model", text, sizeof text);
    if (!text[0])
        att_str(nc, NC_GLOBAL, "source", text, 64);
    snprintf(g->model, sizeof g->model, "%s", text[0] ? text : "CF netCDF");
    att_str(nc, NC_GLOBAL, "vsv_run", text, sizeof text);
    if (!text[0])
        att_str(nc, NC_GLOBAL, "title", text, sizeof text);
    snprintf(g->run, sizeof g->run, "%s", text);
    /* run metadata vsv-export stored as vsv_attr_KEY (spaces and colons in
     * keys became _): the vectors' and the wind source's keys restored, so
     * that the wind is the wind again (vsv_vector.h) */
    int natts = 0;
    nc_inq_natts(nc, &natts);
    for (int i = 0; i < natts; i++) {
        char an[NC_MAX_NAME + 1], val[256], key[NC_MAX_NAME + 8];
        if (nc_inq_attname(nc, NC_GLOBAL, i, an) || strncmp(an, "vsv_attr_", 9) || !an[9])
            continue;
        att_str(nc, NC_GLOBAL, an, val, sizeof val);
        if (!strncmp(an + 9, "vector_", 7) && an[16])
            snprintf(key, sizeof key, "%s%s", VSV_VECTOR_ATTR, an + 16);
        else
            snprintf(key, sizeof key, "%s", !strcmp(an + 9, "wind_source") ? VSV_WIND_SOURCE_ATTR : an + 9);
        if (val[0] && !vsv_meta_attr(g, key) && vsv_meta_add_attr(g, key, val) < 0) /* (the reader's own first) */
            return VSV_ENOMEM;
    }
    if (above_ground && !vsv_meta_attr(g, VSV_ATTR_DATUM) && vsv_meta_add_attr(g, VSV_ATTR_DATUM, "ground") < 0)
        return VSV_ENOMEM;
    return 0;
}

/* The terrain from variable v (standard_name surface_altitude), its rows
 * reversed when y is stored north to south. */
static int cf_terrain(vsv_source *s, const cf *c, const cf_axes *ax, int v, const char *name)
{
    const size_t *len = ax->len;
    vsv_meta *g = &s->grid;
    int rc;
    if (vsv_meta_alloc_terrain(g))
        return VSV_ENOMEM;
    const size_t shape[2] = {len[2], len[3]};
    if ((rc = vsv_nc_read(s, c->nc, v, name, 0, shape, 2, g->terrain)))
        return rc;
    if (c->flip_y)
        for (size_t j = 0; j < len[2] / 2; j++)
            for (size_t i = 0; i < len[3]; i++) {
                float *a = &g->terrain[j * len[3] + i], *b = &g->terrain[(len[2] - 1 - j) * len[3] + i];
                const float t = *a;
                *a = *b;
                *b = t;
            }
    return 0;
}

/* The fields: numeric variables on exactly the four axes; terrain and the
 * per-column heights of native levels taken on the way. */
static int cf_fields(vsv_source *s, cf *c, const cf_axes *ax, int nvars)
{
    const int nc = c->nc;
    const size_t *len = ax->len;
    vsv_meta *g = &s->grid;
    int rc, nd;
    const size_t plane = len[2] * len[3];
    c->tmp = malloc(plane * len[1] * sizeof *c->tmp);
    s->fields = calloc((size_t)nvars + 1, sizeof *s->fields);
    c->varid = calloc((size_t)nvars + 1, sizeof *c->varid);
    if (!c->tmp || !s->fields || !c->varid)
        return VSV_ENOMEM;
    for (int v = 0; v < nvars; v++) {
        char name[NC_MAX_NAME + 1];
        nc_type type;
        int dd[NC_MAX_VAR_DIMS];
        if (nc_inq_var(nc, v, name, &type, &nd, dd, NULL) || type == NC_CHAR || type == NC_STRING)
            continue;
        char sn[64];
        att_str(nc, v, "standard_name", sn, sizeof sn);
        if (nd == 2 && dd[0] == ax->dims[2] && dd[1] == ax->dims[3] && !strcmp(sn, "surface_altitude") && !g->terrain) {
            if ((rc = cf_terrain(s, c, ax, v, name)))
                return rc;
            continue;
        }
        if (nd != 4 || memcmp(dd, ax->dims, sizeof ax->dims) || strlen(name) >= sizeof s->fields[0].name)
            continue;
        if (!strcmp(sn, "altitude") || !strcmp(sn, "height")) { /* per-column heights of native levels, by time */
            if (g->vert_kind == VSV_VERT_NATIVE)
                for (size_t t = 0; t < len[0]; t++) {
                    const size_t shape[3] = {len[1], len[2], len[3]};
                    if ((rc = vsv_nc_read(s, nc, v, name, (int)t, shape, 3, c->tmp)))
                        return rc;
                    if (c->flip_y)
                        return vsv_source_fail(s, VSV_EUNSUPPORTED, "per-column heights with y stored north to south");
                    if ((rc = vsv_source_native_heights(s, (int)t, c->tmp)))
                        return rc;
                }
            continue;
        }
        vsv_field_info *f = &s->fields[s->nfields];
        att_str(nc, v, "vsv_name", f->name, sizeof f->name);
        if (!f->name[0])
            snprintf(f->name, sizeof f->name, "%s", name);
        att_str(nc, v, "units", f->units, sizeof f->units);
        att_str(nc, v, "long_name", f->description, sizeof f->description);
        snprintf(f->ordering, sizeof f->ordering, "CF");
        f->nlevels = (int)len[1];
        f->is_volume = 1;
        f->is_default = 1;
        c->varid[s->nfields++] = v;
    }
    if (!s->nfields)
        return vsv_source_fail(s, VSV_ENOTVSV, "a CF netCDF file without readable 4-D variables");
    return 0;
}

static int cf_open(vsv_source *s, int nc)
{
    cf *c = calloc(1, sizeof *c);
    if (!c) {
        vsv_nc_close(nc);
        return VSV_ENOMEM;
    }
    s->priv = c;
    c->nc = nc;
    /* everything acquired hangs off c and s, freed by cf_close */
    int nvars;
    nc_inq_nvars(nc, &nvars);
    cf_axes ax;
    int gm, rc, above_ground = 0;
    double fe = 0, fn = 0;
    if ((rc = cf_find_axes(s, nc, nvars, &ax)) || (rc = cf_times(s, nc, &ax)) ||
        (rc = cf_find_mapping(s, nc, nvars, &gm)))
        return rc;
    if (gm >= 0 && (rc = cf_projection(s, nc, gm, &s->grid.proj, &fe, &fn)))
        return rc;
    if ((rc = cf_plan(s, c, &ax, gm, fe, fn)) || (rc = cf_vertical(s, nc, &ax, &above_ground)) ||
        (rc = cf_describe(s, nc, above_ground)))
        return rc;
    return cf_fields(s, c, &ax, nvars);
}

static int cf_read(vsv_source *s, int field, int t, float *out)
{
    cf *c = s->priv;
    const vsv_meta *g = &s->grid;
    const size_t nx = (size_t)g->nx, ny = (size_t)g->ny, nz = (size_t)g->nz;
    const size_t shape[3] = {nz, ny, nx};
    const int v = c->varid[field];
    int rc = vsv_nc_read(s, c->nc, v, s->fields[field].name, t, shape, 3, c->flip_y ? c->tmp : out);
    if (rc)
        return rc;
    if (c->flip_y)
        for (size_t k = 0; k < nz; k++)
            for (size_t j = 0; j < ny; j++)
                memcpy(out + (k * ny + j) * nx, c->tmp + (k * ny + (ny - 1 - j)) * nx, nx * sizeof *out);
    /* fill values → no data; packing */
    double fill[1], miss[1], scale = 1, offset = 0;
    const int hf = att_num(c->nc, v, "_FillValue", fill, 1), hm = att_num(c->nc, v, "missing_value", miss, 1);
    att_num(c->nc, v, "scale_factor", &scale, 1);
    att_num(c->nc, v, "add_offset", &offset, 1);
    const float ff = hf ? (float)fill[0] : NAN, fm = hm ? (float)miss[0] : NAN;
    if (!hf && !hm && scale == 1 && offset == 0)
        return 0;
    for (size_t i = 0, n = nx * ny * nz; i < n; i++) {
        float x = out[i];
        if ((hf && x == ff) || (hm && x == fm))
            x = NAN;
        else if (scale != 1 || offset != 0)
            x = (float)(x * scale + offset);
        out[i] = x;
    }
    return 0;
}

static void cf_close(vsv_source *s)
{
    cf *c = s->priv;
    if (!c)
        return;
    vsv_nc_close(c->nc);
    free(c->varid);
    free(c->tmp);
    free(c);
}

static char *cf_summary(vsv_source *s)
{
    vsv_buf b = {0};
    char line[512];
    const vsv_meta *g = &s->grid;
    snprintf(line, sizeof line,
             "CF netCDF: %s%s%s\n  projection  %s, lat0 %g, lon0 %g, lat1 %g, lat2 %g\n  grid        %d x %d x %d, %g "
             "x %g\n  times       %d\n  fields      %d 4-D\n",
             g->model, g->run[0] ? ": " : "", g->run, vsv_proj_name(g->proj.kind), g->proj.lat0, g->proj.lon0,
             g->proj.lat1, g->proj.lat2, g->nx, g->ny, g->nz, g->spacing[0], g->spacing[1], s->ntimes, s->nfields);
    vsv_buf_put(&b, line, strlen(line));
    for (int i = 0; i < s->nfields; i++) {
        snprintf(line, sizeof line, "    %-10s %-12s %s\n", s->fields[i].name, s->fields[i].units,
                 s->fields[i].description);
        vsv_buf_put(&b, line, strlen(line));
    }
    vsv_buf_put(&b, "", 1);
    return (char *)b.p;
}

const vsv_source_ops vsv_cf_ops = {"CF netCDF", NULL, NULL, cf_read, cf_close, cf_summary, NULL, NULL};

int vsv_cf_open(vsv_source *s, int nc) { return cf_open(s, nc); }
