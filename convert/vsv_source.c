/* vsv_source.c — the source interface: detection by content and dispatch
 * to the readers. */
#include "vsv_source_internal.h"
#include "vsv_uamiv.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

const char *vsv_source_error(const vsv_source *s) { return s ? s->err : "out of memory"; }
const char *vsv_source_format(const vsv_source *s) { return s->ops->name; }
const vsv_meta *vsv_source_grid(const vsv_source *s) { return &s->grid; }
int vsv_source_nfields(const vsv_source *s) { return s->nfields; }
const vsv_field_info *vsv_source_field(const vsv_source *s, int i)
{
    return i >= 0 && i < s->nfields ? &s->fields[i] : NULL;
}
int vsv_source_ntimes(const vsv_source *s) { return s->ntimes; }
int64_t vsv_source_time(const vsv_source *s, int t) { return t >= 0 && t < s->ntimes ? s->times[t] : 0; }

const char *vsv_source_field_path(const vsv_source *s, int i)
{
    return s->ops->field_path ? s->ops->field_path(s, i) : s->path;
}

int vsv_source_find_field(const vsv_source *s, const char *name)
{
    for (int i = 0; i < s->nfields; i++)
        if (!strcmp(s->fields[i].name, name))
            return i;
    return VSV_ENOTFOUND;
}

int vsv_source_read(vsv_source *s, int field, int t, float *out)
{
    if (field < 0 || field >= s->nfields || t < 0 || t >= s->ntimes) {
        vsv_msg(s->err, sizeof s->err, "%s: field %d, time %d out of range", s->path, field, t);
        return VSV_ERANGE;
    }
    s->err[0] = 0;
    const int rc = s->ops->read(s, field, t, out);
    if (rc && !s->err[0]) /* a reader that gave only the code (out of memory) */
        vsv_source_fail(s, rc, "%s reading %s at step %d", vsv_strerror(rc), s->fields[field].name, t);
    return rc;
}

int vsv_source_heights(vsv_source *s, int t, float *out)
{
    if (t < 0 || t >= s->ntimes)
        return vsv_source_fail(s, VSV_ERANGE, "time %d out of range 0..%d", t, s->ntimes - 1);
    if (s->grid.vert_kind != VSV_VERT_NATIVE || !s->ops->heights)
        return vsv_source_fail(s, VSV_EUNSUPPORTED, "no per-column heights of native levels (%s grid, %s)",
                               s->grid.vert_kind == VSV_VERT_NATIVE ? "native" : "not a native", s->ops->name);
    s->err[0] = 0;
    const int rc = s->ops->heights(s, t, out);
    if (rc && !s->err[0])
        vsv_source_fail(s, rc, "%s reading the heights at step %d", vsv_strerror(rc), t);
    return rc;
}

int vsv_source_fail(vsv_source *s, int rc, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsv_vmsg_path(s->err, sizeof s->err, s->path, fmt, ap);
    va_end(ap);
    return rc;
}

static const vsv_source_ops *readers[16] = {&vsv_mm5_ops, &vsv_camx_ops, &vsv_netcdf_ops, &vsv_grads_ops};
enum { BUILTIN = 4 };
static int nreaders = BUILTIN;

int vsv_source_register(const vsv_source_ops *ops)
{
    if (!ops || !ops->probe || !ops->open || nreaders >= BUILTIN + 8)
        return VSV_EINVAL;
    for (int i = 0; i < nreaders; i++)
        if (readers[i] == ops)
            return 0;
    readers[nreaders++] = ops;
    return 0;
}

void vsv_source_opts_init(vsv_source_opts *o)
{
    memset(o, 0, sizeof *o);
    o->vertical = VSV_VERT_NATIVE; /* the model's own levels: no peak resampled away */
    o->time_start = INT64_MIN;     /* not given: no invented start */
}

char *vsv_source_summary(vsv_source *s) { return s->ops && s->ops->summary ? s->ops->summary(s) : NULL; }

int vsv_source_open(const char *path, const vsv_source_opts *opts, vsv_source **out)
{
    vsv_source *s = *out = calloc(1, sizeof *s);
    if (!s)
        return VSV_ENOMEM;
    if (opts)
        s->opts = *opts;
    else
        vsv_source_opts_init(&s->opts);
    snprintf(s->path, sizeof s->path, "%s", path);
    vsv_meta_init(&s->grid);
    char why[160];
    FILE *fp = vsv_input_fopen(path, "rb", why, sizeof why);
    if (!fp)
        return vsv_source_fail(s, VSV_EIO, "%s", why);
    unsigned char head[512];
    size_t n = fread(head, 1, sizeof head, fp);
    fclose(fp);
    for (int i = 0; i < nreaders; i++)
        if (readers[i]->probe(head, n)) {
            s->ops = readers[i];
            const int camx = readers[i] == &vsv_camx_ops, vdb = !strcmp(readers[i]->name, "OpenVDB"); /* interop's */
            if (!camx && (s->opts.heights || s->opts.met || s->opts.proj.kind != VSV_PROJ_NONE))
                return vsv_source_fail(s, VSV_EINVAL, "--%s is for CAMx files; this is a %s file",
                                       s->opts.heights ? "heights"
                                       : s->opts.met   ? "met"
                                                       : "proj",
                                       readers[i]->name);
            if (!vdb && s->opts.time_step > 0)
                return vsv_source_fail(s, VSV_EINVAL, "--time-step is for OpenVDB sequences; this is a %s file",
                                       readers[i]->name);
            const int rc = readers[i]->open(s);
            if (rc && !s->err[0]) /* a reader that gave only the code (out of memory) */
                vsv_source_fail(s, rc, "%s opening it (%s)", vsv_strerror(rc), readers[i]->name);
            char bad[200];
            if (!rc && vsv_meta_check_proj(&s->grid, bad, sizeof bad)) /* a header's map that places nothing */
                return vsv_source_fail(s, VSV_ECORRUPT, "%s", bad);
            return rc;
        }
    if (vsv_head_is_vsv(head, n))
        return vsv_source_fail(s, VSV_ENOTVSV,
                               "a .vsv file already, not model output (vsv-info, vsv-query and vsv-play read it)");
    int beside;
    const char *camx = vsv_camx_input_kind(head, n, &beside);
    if (camx)
        return vsv_source_fail(s, VSV_ENOTVSV, "%s%s", camx,
                               beside ? ", with no grid of its own: read beside a CAMx average file (--met DIR)" : "");
    char more[256] = "";
    for (int i = BUILTIN; i < nreaders; i++)
        snprintf(more + strlen(more), sizeof more - strlen(more), ", %s", readers[i]->name);
    return vsv_source_fail(
        s, VSV_ENOTVSV,
        "not an MM5 v3 file, nor another format Vesuvius reads (CAMx UAM-IV, WRF, IOAPI or CF netCDF, "
        "GrADS .ctl%s)",
        more);
}

void vsv_source_free(vsv_source *s)
{
    if (!s)
        return;
    if (s->ops && s->ops->close)
        s->ops->close(s);
    vsv_meta_clear(&s->grid);
    free(s->fields);
    free(s->times);
    free(s);
}

int vsv_source_cli_option(vsv_source_opts *o, int id, const char *arg)
{
    char *end;
    switch (id) {
    case VSV_SOURCE_OPT_VERTICAL:
        if (!strcmp(arg, "even"))
            o->vertical = VSV_VERT_EVEN;
        else if (!strcmp(arg, "native"))
            o->vertical = VSV_VERT_NATIVE;
        else
            return -1;
        o->vertical_set = 1;
        return 1;
    case VSV_SOURCE_OPT_NZ: {
        long v = strtol(arg, &end, 10);
        if (*end || v < 1 || v > 4096)
            return -1;
        o->nz = (int)v;
        if (!o->vertical_set) /* the even grid's shape: the even grid */
            o->vertical = VSV_VERT_EVEN;
        return 1;
    }
    case VSV_SOURCE_OPT_ZTOP: {
        double v = strtod(arg, &end);
        if (*end || !(v > 0 && v < 1e6))
            return -1;
        o->ztop = v;
        if (!o->vertical_set)
            o->vertical = VSV_VERT_EVEN;
        return 1;
    }
    case VSV_SOURCE_OPT_HEIGHTS: o->heights = arg; return 1;
    case VSV_SOURCE_OPT_MET: o->met = arg; return 1;
    case VSV_SOURCE_OPT_TIME_STEP: return vsv_duration_parse(arg, &o->time_step) ? -1 : 1;
    case VSV_SOURCE_OPT_TIME_START: return vsv_time_parse(arg, &o->time_start) ? -1 : 1;
    case VSV_SOURCE_OPT_PROJ:
        for (int k = VSV_PROJ_LATLON; k < VSV_PROJ_COUNT; k++)
            if (!strcmp(arg, vsv_proj_name(k))) {
                o->proj.kind = k;
                if (!o->proj.radius)
                    o->proj.radius = 6370000;
                return 1;
            }
        return -1;
    case VSV_SOURCE_OPT_LAT0:
    case VSV_SOURCE_OPT_LON0:
    case VSV_SOURCE_OPT_LAT1:
    case VSV_SOURCE_OPT_LAT2: {
        double v = strtod(arg, &end);
        const double lim = id == VSV_SOURCE_OPT_LON0 ? 360 : 90;
        if (*end || !(v >= -lim && v <= lim))
            return -1;
        double *dst[] = {&o->proj.lat0, &o->proj.lon0, &o->proj.lat1, &o->proj.lat2};
        *dst[id - VSV_SOURCE_OPT_LAT0] = v;
        o->proj_set |= 1u << (id - VSV_SOURCE_OPT_LAT0);
        return 1;
    }
    default: return 0;
    }
}

void vsv_source_cli_why(int id, const char *arg, char *msg, size_t cap)
{
    static const char *const names[] = {"vertical", "nz",   "ztop", "heights",   "proj",       "lat0",
                                        "lon0",     "lat1", "lat2", "time-step", "time-start", "met"};
    const int k = id - VSV_SOURCE_OPT_VERTICAL;
    const char *why = "a bad value";
    char projs[128] = "";
    switch (id) {
    case VSV_SOURCE_OPT_VERTICAL: why = "expected native or even"; break;
    case VSV_SOURCE_OPT_NZ: why = "expected a whole number of levels from 1 to 4096"; break;
    case VSV_SOURCE_OPT_ZTOP: why = "expected metres above 0 and below 1000000"; break;
    case VSV_SOURCE_OPT_LON0: why = "expected degrees from -360 to 360"; break;
    case VSV_SOURCE_OPT_LAT0:
    case VSV_SOURCE_OPT_LAT1:
    case VSV_SOURCE_OPT_LAT2: why = "expected a latitude, degrees from -90 to 90"; break;
    case VSV_SOURCE_OPT_TIME_STEP: why = vsv_duration_why(arg); break;
    case VSV_SOURCE_OPT_TIME_START: why = "expected an ISO 8601 time, e.g. 2005-08-28T00:00:00Z"; break;
    case VSV_SOURCE_OPT_PROJ: {
        size_t n = (size_t)snprintf(projs, sizeof projs, "expected");
        for (int p = VSV_PROJ_LATLON; p < VSV_PROJ_COUNT && n < sizeof projs; p++)
            n += (size_t)snprintf(projs + n, sizeof projs - n, "%s %s", p == VSV_PROJ_LATLON ? "" : ",",
                                  vsv_proj_name(p));
        why = projs;
        break;
    }
    default: break;
    }
    if (k >= 0 && k < (int)(sizeof names / sizeof names[0]))
        snprintf(msg, cap, "--%s %s: %s", names[k], arg ? arg : "", why);
    else
        snprintf(msg, cap, "%s: %s", arg ? arg : "", why);
}

int vsv_source_opts_check(const vsv_source_opts *o, char *msg, size_t cap)
{
    static const char *const pn[] = {"--lat0", "--lon0", "--lat1", "--lat2"};
    if (o->proj.kind == VSV_PROJ_NONE) {
        for (int i = 0; i < 4; i++)
            if (o->proj_set & (1u << i)) {
                vsv_msg(msg, cap, "%s without --proj", pn[i]);
                return VSV_EINVAL;
            }
    } else {
        /* what each projection needs: lcc lat0 lon0 lat1 (lat2 = lat1 when
         * absent: tangent); pstereo lat0 (the pole's side) lon0 lat1;
         * mercator lon0 lat1; tmerc lon0 lat1 (k0); albers all four */
        unsigned need = 0;
        switch (o->proj.kind) {
        case VSV_PROJ_LCC: need = 7; break;
        case VSV_PROJ_PSTEREO: need = 7; break;
        case VSV_PROJ_MERCATOR: need = 6; break;
        case VSV_PROJ_TMERC: need = 6; break;
        case VSV_PROJ_ALBERS: need = 15; break;
        default: need = 0; break;
        }
        if ((o->proj_set & need) != need) {
            char list[64] = "";
            for (int i = 0; i < 4; i++)
                if (need & ~o->proj_set & (1u << i))
                    snprintf(list + strlen(list), sizeof list - strlen(list), " %s", pn[i]);
            vsv_msg(msg, cap, "--proj %s needs%s (no default puts a grid on the map)", vsv_proj_name(o->proj.kind),
                    list);
            return VSV_EINVAL;
        }
        if (o->proj.kind == VSV_PROJ_LATLON && o->proj_set) {
            vsv_msg(msg, cap, "--proj latlon takes no --lat0/--lon0/--lat1/--lat2");
            return VSV_EINVAL;
        }
    }
    if (o->vertical == VSV_VERT_NATIVE && (o->nz > 0 || o->ztop > 0)) {
        vsv_msg(msg, cap, "--nz and --ztop shape the even grid: not with --vertical native");
        return VSV_EINVAL;
    }
    if (o->time_step > 0 && o->time_start == INT64_MIN) {
        vsv_msg(msg, cap, "--time-step needs --time-start (the time of the first file)");
        return VSV_EINVAL;
    }
    if (!(o->time_step > 0) && o->time_start != INT64_MIN) {
        vsv_msg(msg, cap, "--time-start without --time-step");
        return VSV_EINVAL;
    }
    return 0;
}

int vsv_source_axis(vsv_source *s, const float *zn, int kx, double round_to)
{
    vsv_meta *g = &s->grid;
    const size_t plane = (size_t)g->nx * g->ny;
    if (s->opts.vertical == VSV_VERT_NATIVE) {
        g->nz = kx;
        g->vert_kind = VSV_VERT_NATIVE;
        snprintf(g->vert_units, sizeof g->vert_units, "m");
        if (vsv_meta_alloc_levels(g))
            return VSV_ENOMEM;
        for (int k = 0; k < kx; k++) {
            double sum = 0;
            for (size_t c = 0; c < plane; c++)
                sum += zn[(size_t)k * plane + c];
            g->levels[k] = sum / (double)plane;
        }
        return 0;
    }
    double ztop = s->opts.ztop;
    if (!(ztop > 0)) {
        float top = 0;
        for (size_t c = 0; c < plane; c++)
            top = fmaxf(top, zn[(size_t)(kx - 1) * plane + c]);
        ztop = ceil(top / round_to) * round_to;
    }
    g->nz = s->opts.nz > 0 ? s->opts.nz : 40;
    g->vert_kind = VSV_VERT_EVEN;
    g->spacing[2] = ztop / g->nz;
    g->origin[2] = g->spacing[2] / 2;
    char how[160];
    snprintf(how, sizeof how,
             "from the model's %d levels onto %d even heights of %.4g m, linear in height (extremes between two "
             "even levels are lost)",
             kx, g->nz, g->spacing[2]);
    return vsv_meta_add_attr(g, VSV_ATTR_RESAMPLED, how) < 0 ? VSV_ENOMEM : 1;
}

int vsv_source_native_heights(vsv_source *s, int t, const float *zn)
{
    vsv_meta *g = &s->grid;
    const size_t n = (size_t)g->nx * g->ny * g->nz;
    if (g->nheights) {
        const float *last = g->heights[g->nheights - 1].z;
        size_t i = 0;
        while (i < n && fabsf(zn[i] - last[i]) <= 0.5f)
            i++;
        if (i == n)
            return 0;
    }
    const int rc = vsv_meta_add_heights(g, t ? s->times[t] : INT64_MIN, zn, NULL, NULL);
    if (rc == VSV_EINVAL)
        return vsv_source_fail(s, VSV_ECORRUPT, "the model levels' heights at time %d are not increasing upward", t);
    return rc;
}
