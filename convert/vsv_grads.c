/* vsv_grads.c — GrADS gridded binary data described by a .ctl file (the
 * GrADS sample model output bundled for the demo): DSET, OPTIONS
 * little_endian/big_endian, UNDEF, XDEF/YDEF LINEAR (lat/lon), ZDEF
 * LEVELS/LINEAR, TDEF LINEAR, VARS. Data layout: per time, per variable,
 * per level, nx*ny float32 with x fastest. */
#include "vsv_source_internal.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

typedef struct grads {
    char dset[1024];
    int big_endian;
    double undef;
    int nx, ny, nz;
    long long *var_offset; /* bytes into a time block */
    long long time_bytes;
    FILE *fp;
} grads;

static int grads_probe(const unsigned char *h, size_t n)
{
    size_t i = 0;
    while (i < n && isspace(h[i]))
        i++;
    static const char *keys[] = {"dset", "DSET", "*"};
    for (int k = 0; k < 3; k++)
        if (n - i >= strlen(keys[k]) && !memcmp(h + i, keys[k], strlen(keys[k])))
            return k < 2 || memmem(h, n, "DSET", 4) || memmem(h, n, "dset", 4);
    return 0;
}

/* "hh[:mm]Zddmmmyyyy" or "ddmmmyyyy" → seconds. */
static int parse_gtime(const char *s, int64_t *t)
{
    static const char *mon[] = {"jan", "feb", "mar", "apr", "may", "jun", "jul", "aug", "sep", "oct", "nov", "dec"};
    int hh = 0, mm = 0, dd = 1, yyyy, n = 0;
    const char *z = strpbrk(s, "zZ");
    if (z) {
        if (sscanf(s, "%d:%d", &hh, &mm) < 1)
            return -1;
        s = z + 1;
    }
    char m3[4] = {0};
    if (isdigit((unsigned char)s[0])) {
        if (sscanf(s, "%d%n", &dd, &n) != 1)
            return -1;
        s += n;
    }
    if (strlen(s) < 7)
        return -1;
    memcpy(m3, s, 3);
    int month = 0;
    for (int i = 0; i < 12; i++)
        if (!strcasecmp(m3, mon[i]))
            month = i + 1;
    if (!month || sscanf(s + 3, "%d", &yyyy) != 1)
        return -1;
    if (hh < 0 || hh > 23 || mm < 0 || mm > 59 || dd < 1 || dd > 31 || yyyy < 1 || yyyy > 9999)
        return -1; /* an hour of 22222222 (found by fuzz_grads) is no time */
    *t = vsv_time_from_civil(yyyy, month, dd, hh, mm, 0);
    return 0;
}

static int64_t add_months(int64_t t, long months)
{
    char buf[40];
    vsv_time_format(t, buf, sizeof buf);
    int y, m, d, hh, mi, ss;
    sscanf(buf, "%d-%d-%dT%d:%d:%d", &y, &m, &d, &hh, &mi, &ss);
    long total = (long)y * 12 + (m - 1) + months;
    return vsv_time_from_civil((int)(total / 12), (int)(total % 12) + 1, d, hh, mi, ss);
}

/* A date, in the standard calendar's seconds, as the same date of the
 * noleap calendar (29 February, which it has not, as the 28th). */
static int64_t to_noleap(int64_t t)
{
    char buf[40];
    vsv_time_format(t, buf, sizeof buf);
    int y, m, d, hh, mi, ss;
    sscanf(buf, "%d-%d-%dT%d:%d:%d", &y, &m, &d, &hh, &mi, &ss);
    return vsv_cal_from_civil(VSV_CAL_NOLEAP, y, m, m == 2 && d == 29 ? 28 : d, hh, mi, ss);
}

/* What the descriptor says beyond the handle: axes, times, levels, title. */
typedef struct grads_ctl {
    int lineno, in_vars, nvars;
    double xs, dx, ys, dy;
    int64_t t0, dt;
    long dmonths;
    int nt, cal365, have_x, have_y, have_z, have_t;
    double *levels; /* owned: freed by grads_open */
    char title[256];
} grads_ctl;

/* One record of the VARS list: name, level count, units code, description. */
static int grads_var_record(vsv_source *s, const grads_ctl *c, const char *key, char *rest)
{
    vsv_field_info *f = &s->fields[s->nfields];
    int lev, units_code, k = 0;
    if (s->nfields >= c->nvars || sscanf(rest, "%d %d%n", &lev, &units_code, &k) != 2 || lev < 0 || lev > 100000)
        return vsv_source_fail(s, VSV_ECORRUPT, "line %d: bad variable record", c->lineno);
    memset(f, 0, sizeof *f);
    snprintf(f->name, sizeof f->name, "%s", key);
    char *desc = rest + k;
    while (isspace((unsigned char)*desc))
        desc++;
    desc[strcspn(desc, "\r\n")] = 0;
    snprintf(f->description, sizeof f->description, "%s", desc);
    f->nlevels = lev;
    f->is_volume = 1;
    f->is_default = lev > 0;
    s->nfields++;
    return 0;
}

/* OPTIONS: every keyword honoured or refused by name. */
static int grads_options(vsv_source *s, grads *g, grads_ctl *c, char *rest)
{
    char *save = NULL;
    for (char *o = strtok_r(rest, " \t\r\n", &save); o; o = strtok_r(NULL, " \t\r\n", &save)) {
        if (!strcasecmp(o, "big_endian"))
            g->big_endian = 1;
        else if (!strcasecmp(o, "little_endian"))
            g->big_endian = 0;
        else if (!strcasecmp(o, "byteswapped"))
            g->big_endian = 1; /* the other order than this (little-endian) machine's */
        else if (!strcasecmp(o, "365_day_calendar"))
            c->cal365 = 1;
        else {
            const int known = !strcasecmp(o, "template") || !strcasecmp(o, "sequential") || !strcasecmp(o, "yrev") ||
                              !strcasecmp(o, "zrev") || !strcasecmp(o, "pascals") || !strcasecmp(o, "cray_32bit_ieee");
            return vsv_source_fail(s, VSV_EUNSUPPORTED,
                                   "line %d: OPTIONS %s %s (little_endian, big_endian, byteswapped and "
                                   "365_day_calendar are)",
                                   c->lineno, o, known ? "is not supported" : "is unknown");
        }
    }
    return 0;
}

/* XDEF or YDEF n LINEAR start step. */
static int grads_xydef(vsv_source *s, grads *g, grads_ctl *c, const char *key, const char *rest)
{
    int cnt;
    char kind[16];
    double a, b;
    if (sscanf(rest, "%d %15s %lf %lf", &cnt, kind, &a, &b) != 4 || strcasecmp(kind, "linear") || cnt < 1)
        return vsv_source_fail(s, VSV_EUNSUPPORTED, "line %d: only %s n LINEAR start step is supported", c->lineno,
                               key);
    if (cnt > VSV_MAX_DIM)
        return vsv_source_fail(s, VSV_ECORRUPT, "line %d: %s %d: more than %d cells", c->lineno, key, cnt, VSV_MAX_DIM);
    if (tolower((unsigned char)key[0]) == 'x')
        g->nx = cnt, c->xs = a, c->dx = b, c->have_x = 1;
    else
        g->ny = cnt, c->ys = a, c->dy = b, c->have_y = 1;
    return 0;
}

/* ZDEF n LINEAR start step, or ZDEF n LEVELS with the values running on
 * over the following lines (read into line, a buffer of cap bytes). */
static int grads_zdef(vsv_source *s, grads *g, grads_ctl *c, char *rest, char *line, int cap, FILE *fp)
{
    int cnt, k = 0;
    char kind[16];
    if (sscanf(rest, "%d %15s%n", &cnt, kind, &k) != 2 || cnt < 1 || cnt > VSV_MAX_DIM)
        return vsv_source_fail(s, VSV_ECORRUPT, "line %d: bad ZDEF", c->lineno);
    g->nz = cnt;
    free(c->levels);
    c->levels = calloc((size_t)cnt, sizeof *c->levels);
    if (!c->levels)
        return VSV_ENOMEM;
    char *q = rest + k;
    if (!strcasecmp(kind, "linear")) {
        double a, b;
        if (sscanf(q, "%lf %lf", &a, &b) != 2)
            return vsv_source_fail(s, VSV_ECORRUPT, "line %d: bad ZDEF LINEAR", c->lineno);
        for (int i = 0; i < cnt; i++)
            c->levels[i] = a + i * b;
    } else {
        int got = 0;
        while (got < cnt) {
            char *end;
            double v = strtod(q, &end);
            if (end == q) {
                if (!fgets(line, cap, fp))
                    break;
                c->lineno++;
                q = line;
                continue;
            }
            c->levels[got++] = v;
            q = end;
        }
        if (got < cnt)
            return vsv_source_fail(s, VSV_ECORRUPT, "line %d: ZDEF lists %d of %d levels", c->lineno, got, cnt);
    }
    c->have_z = 1;
    return 0;
}

/* TDEF n LINEAR start increment (mn, hr, dy, mo or yr). */
static int grads_tdef(vsv_source *s, grads_ctl *c, const char *rest)
{
    char kind[16], start[32], inc[16];
    if (sscanf(rest, "%d %15s %31s %15s", &c->nt, kind, start, inc) != 4 || strcasecmp(kind, "linear") || c->nt < 1 ||
        c->nt > VSV_MAX_STEPS || parse_gtime(start, &c->t0))
        return vsv_source_fail(s, VSV_EUNSUPPORTED, "line %d: only TDEF n LINEAR time increment is supported",
                               c->lineno);
    char *u;
    long v = strtol(inc, &u, 10);
    /* at most a million units: every step's time stays far inside int64 */
    if (v <= 0 || v > 1000000)
        return vsv_source_fail(s, VSV_ECORRUPT, "line %d: bad time increment %s", c->lineno, inc);
    if (!strcasecmp(u, "mn"))
        c->dt = v * 60;
    else if (!strcasecmp(u, "hr"))
        c->dt = v * 3600;
    else if (!strcasecmp(u, "dy"))
        c->dt = v * 86400;
    else if (!strcasecmp(u, "mo"))
        c->dmonths = v;
    else if (!strcasecmp(u, "yr"))
        c->dmonths = 12 * v;
    else
        return vsv_source_fail(s, VSV_ECORRUPT, "line %d: bad time increment %s", c->lineno, inc);
    c->have_t = 1;
    return 0;
}

/* VARS n: the field table, filled by the records that follow. */
static int grads_vars(vsv_source *s, grads_ctl *c, const char *rest)
{
    if (sscanf(rest, "%d", &c->nvars) != 1 || c->nvars < 1 || c->nvars > VSV_MAX_VARS)
        return vsv_source_fail(s, VSV_ECORRUPT, "line %d: bad VARS count", c->lineno);
    if (s->fields) /* a second list (found by fuzz_grads: the first leaked) */
        return vsv_source_fail(s, VSV_ECORRUPT, "line %d: a second VARS", c->lineno);
    s->fields = calloc((size_t)c->nvars, sizeof *s->fields);
    if (!s->fields)
        return VSV_ENOMEM;
    c->in_vars = 1;
    return 0;
}

/* Reads the whole .ctl descriptor into g, s->fields and c; checks it is complete. */
static int grads_read_ctl(vsv_source *s, grads *g, grads_ctl *c, FILE *fp)
{
    char line[1024];
    int rc = 0;
    while (fgets(line, sizeof line, fp)) {
        c->lineno++;
        char *p = line;
        while (isspace((unsigned char)*p))
            p++;
        if (!*p || *p == '*')
            continue;
        char key[32] = "";
        int n = 0;
        sscanf(p, "%31s%n", key, &n);
        char *rest = p + n;
        if (c->in_vars) {
            if (!strcasecmp(key, "endvars")) {
                c->in_vars = 0;
                continue;
            }
            if ((rc = grads_var_record(s, c, key, rest)))
                return rc;
            continue;
        }
        if (!strcasecmp(key, "dset")) {
            char d[900];
            if (sscanf(rest, "%899s", d) != 1)
                continue;
            if (d[0] == '^') {
                const char *slash = strrchr(s->path, '/');
                int dir = slash ? (int)(slash - s->path + 1) : 0;
                snprintf(g->dset, sizeof g->dset, "%.*s%s", dir, s->path, d + 1);
            } else {
                snprintf(g->dset, sizeof g->dset, "%s", d);
            }
        } else if (!strcasecmp(key, "options")) {
            rc = grads_options(s, g, c, rest);
        } else if (!strcasecmp(key, "undef")) {
            g->undef = strtod(rest, NULL);
        } else if (!strcasecmp(key, "title")) {
            snprintf(c->title, sizeof c->title, "%s", rest + strspn(rest, " \t"));
            c->title[strcspn(c->title, "\r\n")] = 0;
        } else if (!strcasecmp(key, "xdef") || !strcasecmp(key, "ydef")) {
            rc = grads_xydef(s, g, c, key, rest);
        } else if (!strcasecmp(key, "zdef")) {
            rc = grads_zdef(s, g, c, rest, line, (int)sizeof line, fp);
        } else if (!strcasecmp(key, "tdef")) {
            rc = grads_tdef(s, c, rest);
        } else if (!strcasecmp(key, "vars")) {
            rc = grads_vars(s, c, rest);
        }
        if (rc)
            return rc;
    }
    if (!g->dset[0] || !c->have_x || !c->have_y || !c->have_z || !c->have_t || !s->nfields)
        return vsv_source_fail(s, VSV_ECORRUPT, "not a complete GrADS descriptor (DSET, XDEF, YDEF, ZDEF, TDEF, VARS)");
    return 0;
}

/* Lays the variables out in a time block, checks the data file's size
 * against nt blocks, and opens it (g->fp, closed by grads_close). */
static int grads_layout(vsv_source *s, grads *g, int nt)
{
    g->var_offset = calloc((size_t)s->nfields, sizeof *g->var_offset);
    if (!g->var_offset)
        return VSV_ENOMEM;
    /* sizes in 64 bits, each product checked: dimensions up to 16384 and a
     * thousand variables still fit, a crafted descriptor cannot wrap them */
    if ((uint64_t)g->nx * g->ny * g->nz > VSV_MAX_CELLS)
        return vsv_source_fail(s, VSV_ECORRUPT, "grid %d x %d x %d: more than %llu cells", g->nx, g->ny, g->nz,
                               (unsigned long long)VSV_MAX_CELLS);
    const long long plane = (long long)g->nx * g->ny * 4;
    for (int i = 0; i < s->nfields; i++) {
        if (s->fields[i].nlevels > g->nz)
            return vsv_source_fail(s, VSV_ECORRUPT, "variable %s has %d levels, ZDEF %d", s->fields[i].name,
                                   s->fields[i].nlevels, g->nz);
        g->var_offset[i] = g->time_bytes;
        g->time_bytes += plane * (s->fields[i].nlevels ? s->fields[i].nlevels : 1);
    }
    long long total;
    if (__builtin_mul_overflow(g->time_bytes, (long long)nt, &total))
        return vsv_source_fail(s, VSV_ECORRUPT, "the descriptor implies more than 2^63 bytes (%d steps of %lld)", nt,
                               g->time_bytes);
    struct stat st;
    if (stat(g->dset, &st))
        return vsv_source_fail(s, VSV_EIO, "data file %s: %s", g->dset, strerror(errno));
    if ((long long)st.st_size != total)
        return vsv_source_fail(s, VSV_ECORRUPT, "data file %s has %lld bytes, the descriptor implies %lld", g->dset,
                               (long long)st.st_size, total);
    char why[160];
    if (!(g->fp = vsv_input_fopen(g->dset, "rb", why, sizeof why)))
        return vsv_source_fail(s, VSV_EIO, "data file %s: %s", g->dset, why);
    return 0;
}

/* Fills the source's times and grid from the descriptor. */
static int grads_fill(vsv_source *s, const grads *g, const grads_ctl *c)
{
    const int nt = c->nt, cal365 = c->cal365;
    const int64_t t0 = c->t0, dt = c->dt;
    const long dmonths = c->dmonths;
    const double *levels = c->levels;
    /* a run of at most 10 000 years: the calendar arithmetic stays exact */
    if ((long long)dmonths * (nt - 1) > 120000 || (long long)dt * (nt - 1) > 10000LL * 366 * 86400)
        return vsv_source_fail(s, VSV_ECORRUPT, "TDEF: %d steps span more than 10000 years", nt);
    s->ntimes = nt;
    s->times = malloc((size_t)nt * sizeof *s->times);
    if (!s->times)
        return VSV_ENOMEM;
    for (int t = 0; t < nt; t++)
        s->times[t] = dmonths  ? (cal365 ? to_noleap(add_months(t0, dmonths * t)) : add_months(t0, dmonths * t))
                      : cal365 ? to_noleap(t0) + dt * t
                               : t0 + dt * t;
    if (cal365) /* the model's clock: counted in its own calendar (VSV_ATTR_CALENDAR) */
        vsv_meta_add_attr(&s->grid, VSV_ATTR_CALENDAR, vsv_calendar_name(VSV_CAL_NOLEAP));
    vsv_meta *m = &s->grid;
    m->nx = g->nx;
    m->ny = g->ny;
    m->nz = g->nz;
    m->origin[0] = c->xs;
    m->origin[1] = c->ys;
    m->spacing[0] = c->dx;
    m->spacing[1] = c->dy;
    m->proj.kind = VSV_PROJ_LATLON;
    int rc = vsv_meta_alloc_levels(m);
    if (rc)
        return rc;
    memcpy(m->levels, levels, (size_t)g->nz * sizeof *levels);
    /* GrADS does not say what ZDEF measures: decreasing values up to ~1100 are
     * pressure levels (hPa), otherwise plain level coordinates. */
    int pressure = g->nz == 1 || (levels[0] <= 1100 && levels[0] > 0);
    for (int k = 1; k < g->nz; k++)
        pressure = pressure && levels[k] < levels[k - 1] && levels[k] > 0;
    m->vert_kind = VSV_VERT_COORD;
    snprintf(m->vert_units, sizeof m->vert_units, "%s", pressure ? "hPa" : "level");
    m->origin[2] = 0;
    m->spacing[2] = 1;
    snprintf(m->model, sizeof m->model, "GrADS");
    snprintf(m->run, sizeof m->run, "%s", c->title);
    return 0;
}

static int grads_open(vsv_source *s)
{
    grads *g = calloc(1, sizeof *g);
    if (!g)
        return VSV_ENOMEM;
    s->priv = g;
    char why[160];
    FILE *fp = vsv_input_fopen(s->path, "r", why, sizeof why);
    if (!fp)
        return vsv_source_fail(s, VSV_EIO, "%s", why);
    grads_ctl c = {.dx = 1, .dy = 1};
    int rc = grads_read_ctl(s, g, &c, fp);
    if (rc)
        goto done;
    if ((rc = grads_layout(s, g, c.nt)))
        goto done;
    rc = grads_fill(s, g, &c);
done:
    free(c.levels);
    fclose(fp);
    return rc;
}

static int grads_read(vsv_source *s, int field, int t, float *out)
{
    grads *g = s->priv;
    const vsv_field_info *f = &s->fields[field];
    const size_t plane = (size_t)g->nx * g->ny;
    const int nl = f->nlevels ? f->nlevels : 1;
    if (fseeko(g->fp, (off_t)(g->time_bytes * t + g->var_offset[field]), SEEK_SET) ||
        fread(out, 4, plane * nl, g->fp) != plane * nl)
        return vsv_source_fail(s, VSV_EIO, "reading %s at time %d: %s", f->name, t,
                               ferror(g->fp) ? strerror(errno) : "file ends early");
    const double tol = fabs(g->undef) * 1e-6;
    for (size_t i = 0; i < plane * nl; i++) {
        unsigned char *b = (unsigned char *)&out[i];
        uint32_t u =
            g->big_endian ? ((uint32_t)b[0] << 24 | (uint32_t)b[1] << 16 | (uint32_t)b[2] << 8 | b[3]) : vsv_rd32(b);
        float v;
        memcpy(&v, &u, 4);
        if (g->undef != 0 && fabs(v - g->undef) <= tol)
            v = NAN;
        out[i] = v;
    }
    for (size_t i = plane * nl; i < plane * g->nz; i++)
        out[i] = NAN;
    return 0;
}

static void grads_close(vsv_source *s)
{
    grads *g = s->priv;
    if (!g)
        return;
    if (g->fp)
        fclose(g->fp);
    free(g->var_offset);
    free(g);
}

const vsv_source_ops vsv_grads_ops = {"GrADS", grads_probe, grads_open, grads_read, grads_close, NULL, NULL, NULL};
