/* vsv_run.c — several model files as one run: sorted by first time, checked
 * for matching grids, overlaps and gaps; variables and times selected once.
 * The single extraction path behind vsv-extract and vsv-convert. */
#include "vsv_common.h"
#include "vsv_convert.h"
#include "vsv_derive.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

struct vsv_run {
    vsv_source **src;
    int nsrc;
    vsv_meta meta;
    int *sel; /* field index per selected variable */
    int nsel;
    int *fsrc, *ft; /* per frame: source and its local time index */
    int64_t *ftime;
    int nframes;
    uint64_t bytes;
    char **path;       /* per source, in time order */
    int ncomp;         /* wind components found (0, 2 or 3; wind_source) */
    int store;         /* stored earth-relative components (0 or ncomp) */
    int nwind;         /* auxiliary wind variables appended to meta (0 or ncomp) */
    char wname[3][16]; /* their fields' names in the model files */
    float *rot;        /* stored: per column, the rotation (vsv_wind_rotation) */
    double rot_at[2];  /* ... for the grid placed there */
    vsv_source *wsrc;  /* a companion wind file, or NULL for the run's own */
    int *wt;           /* companion: its time index per frame */
    vsv_derive *der;   /* derived variables, after the selected ones, or NULL */
    int nder;
    char err[1024];
    char note[400]; /* a --times of one time between steps: which was taken */
    int64_t origin; /* the first time before any selection: the grid's t0 */
    int64_t win[2]; /* the selected output steps' times (vsv_run_select) */
};

const char *vsv_run_error(const vsv_run *r) { return r ? r->err : "out of memory"; }
const char *vsv_run_note(const vsv_run *r) { return r->note; }
const vsv_meta *vsv_run_meta(const vsv_run *r) { return &r->meta; }
int vsv_run_nframes(const vsv_run *r) { return r->nframes; }
int64_t vsv_run_time(const vsv_run *r, int i) { return r->ftime[i]; }
uint64_t vsv_run_input_bytes(const vsv_run *r) { return r->bytes; }
int vsv_run_within(const vsv_run *r)
{
    int n = 0;
    for (int i = 0; i < r->nframes; i++)
        n += r->ftime[i] >= r->win[0] && r->ftime[i] <= r->win[1];
    return n;
}

void vsv_run_place(const vsv_run *r, vsv_interp *ip)
{
    vsv_interp_set_origin(ip, r->origin);
    vsv_interp_set_window(ip, r->win[0], r->win[1]);
}
void vsv_run_window(const vsv_run *r, int64_t *first, int64_t *last) { *first = r->win[0], *last = r->win[1]; }

static int fail(vsv_run *r, int rc, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static int fail(vsv_run *r, int rc, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(r->err, sizeof r->err, fmt, ap);
    va_end(ap);
    return rc;
}

/* The inputs in order make one run: the same grid and calendar, no overlap, and (where a file has two outputs)
 * no gap; 0 or VSV_EINVAL, the reason in r->err. */
static int check_sources(vsv_run *r, const char **names)
{
    const vsv_meta *g0 = vsv_source_grid(r->src[0]);
    int64_t dt = 0;
    for (int i = 0; i < r->nsrc && !dt; i++)
        if (vsv_source_ntimes(r->src[i]) > 1 &&
            __builtin_sub_overflow(vsv_source_time(r->src[i], 1), vsv_source_time(r->src[i], 0), &dt))
            dt = 0; /* (times anywhere in int64: differences checked) */
    for (int i = 1; i < r->nsrc; i++) {
        const vsv_meta *g = vsv_source_grid(r->src[i]);
        /* a WRF nest whose files stand in different places moves (run_moves) */
        const int moves = !strcmp(g->model, "WRF") && !strcmp(g0->model, "WRF");
        if (g->nx != g0->nx || g->ny != g0->ny || g->nz != g0->nz || g->proj.kind != g0->proj.kind ||
            (!moves && (g->origin[0] != g0->origin[0] || g->origin[1] != g0->origin[1])) ||
            fabs(g->spacing[0] - g0->spacing[0]) > 1e-6 * g0->spacing[0] ||
            fabs(g->spacing[1] - g0->spacing[1]) > 1e-6 * g0->spacing[1] || !g->terrain != !g0->terrain) {
            return fail(r, VSV_EINVAL, "%s and %s: different grids (%dx%dx%d vs %dx%dx%d or another position)",
                        names[0], names[i], g0->nx, g0->ny, g0->nz, g->nx, g->ny, g->nz);
        }
        const int64_t end = vsv_source_time(r->src[i - 1], vsv_source_ntimes(r->src[i - 1]) - 1);
        const int64_t start = vsv_source_time(r->src[i], 0);
        char a[40], b[40];
        if (vsv_meta_calendar(g) != vsv_meta_calendar(g0)) {
            return fail(r, VSV_EINVAL, "%s and %s: different calendars (%s, %s)", names[0], names[i],
                        vsv_calendar_name(vsv_meta_calendar(g0)), vsv_calendar_name(vsv_meta_calendar(g)));
        }
        vsv_cal_format(vsv_meta_calendar(g), end, a, sizeof a);
        vsv_cal_format(vsv_meta_calendar(g), start, b, sizeof b);
        if (start <= end) {
            return fail(r, VSV_EINVAL, "%s (ends %s) and %s (starts %s) overlap in time", names[i - 1], a, names[i], b);
        }
        int64_t gap;
        if (dt && (__builtin_sub_overflow(start, end, &gap) || gap != dt)) {
            return fail(r, VSV_EINVAL, "gap between %s (ends %s) and %s (starts %s): the run steps every %lld s",
                        names[i - 1], a, names[i], b, (long long)dt);
        }
    }
    return 0;
}

/* A placement of r's grid from time t on, where it differs from the one in
 * force then: the next file of a moving nest, or a move inside one. */
static int place(vsv_run *r, int64_t t, const double o[2], const float *terrain)
{
    vsv_meta *m = &r->meta;
    const vsv_move *now = vsv_meta_move_at(m, t);
    const double *at = now ? now->origin : m->origin;
    if (fabs(o[0] - at[0]) < 0.01 * m->spacing[0] && fabs(o[1] - at[1]) < 0.01 * m->spacing[1])
        return 0;
    const int rc = vsv_meta_add_move(m, t, o, terrain);
    return rc == VSV_EINVAL ? fail(r, rc, "the grid's placements are out of time order") : rc;
}

/* The placements of a moving nest over all the inputs (SPEC.md "MOVE"). */
static int run_moves(vsv_run *r)
{
    int rc = 0;
    for (int i = 1; i < r->nsrc && !rc; i++) {
        const vsv_meta *g = vsv_source_grid(r->src[i]);
        rc = place(r, vsv_source_time(r->src[i], 0), g->origin, g->terrain);
        for (int k = 0; k < g->nmoves && !rc; k++)
            rc = place(r, g->moves[k].time, g->moves[k].origin, g->moves[k].terrain);
    }
    return rc;
}

/* The per-column heights of native levels over all the inputs: each file's
 * records from its first time on, where they differ from those in force
 * (WRF's levels move with the air, and with a moving nest's ground). */
static int run_heights(vsv_run *r)
{
    vsv_meta *m = &r->meta;
    const size_t n = (size_t)m->nx * m->ny * m->nz;
    for (int i = 1; i < r->nsrc && m->nheights; i++) {
        const vsv_meta *g = vsv_source_grid(r->src[i]);
        for (int k = 0; k < g->nheights; k++) {
            const vsv_heights *h = &g->heights[k], *last = &m->heights[m->nheights - 1];
            const int64_t t = k ? h->time : vsv_source_time(r->src[i], 0);
            if (h->form != VSV_HEIGHTS_STORED || last->form != VSV_HEIGHTS_STORED)
                continue; /* MM5's formula: fixed in time */
            size_t c = 0;
            while (c < n && fabsf(h->z[c] - last->z[c]) <= 0.5f)
                c++;
            if (c == n)
                continue;
            const int rc = vsv_meta_add_heights(m, t, h->z, NULL, NULL);
            if (rc)
                return rc == VSV_EINVAL ? fail(r, rc, "the inputs' level heights are out of time order") : rc;
        }
    }
    return 0;
}

/* The variables: those of vars (NAME,...; NULL: the format's defaults), each in every input, added to r->meta; 0,
 * VSV_EINVAL, VSV_ENOTFOUND or VSV_ENOMEM, the reason in r->err. */
static int select_vars(vsv_run *r, const char *vars, const char **names)
{
    int rc = 0;
    const vsv_source *s0 = r->src[0];
    const int nf = vsv_source_nfields(s0);
    r->sel = calloc((size_t)nf + 1, sizeof *r->sel);
    if (!r->sel)
        return VSV_ENOMEM;
    if (vars) {
        char *copy = strdup(vars), *save = NULL;
        if (!copy)
            return VSV_ENOMEM;
        for (char *name = strtok_r(copy, ",", &save); name && !rc; name = strtok_r(NULL, ",", &save)) {
            const int i = vsv_source_find_field(s0, name);
            if (i < 0 || !vsv_source_field(s0, i)->is_volume) {
                size_t n = (size_t)snprintf(r->err, sizeof r->err, "%s: %s '%s'; available:", names[0],
                                            i < 0 ? "no variable" : "not a 3-D variable", name);
                /* comma-separated, as --vars takes them (a name may hold a
                 * space: MM5's RAD TEND) */
                for (int k = 0, first = 1; k < nf && n < sizeof r->err; k++)
                    if (vsv_source_field(s0, k)->is_volume) {
                        n += (size_t)snprintf(r->err + n, sizeof r->err - n, "%s %s", first ? "" : ",",
                                              vsv_source_field(s0, k)->name);
                        first = 0;
                    }
                rc = VSV_ENOTFOUND;
                break;
            }
            for (int k = 0; k < r->nsel; k++)
                if (r->sel[k] == i)
                    rc = fail(r, VSV_EINVAL, "variable %s named twice", name);
            if (!rc && r->nsel < nf)
                r->sel[r->nsel++] = i;
        }
        free(copy);
        if (rc)
            return rc;
    } else {
        for (int i = 0; i < nf; i++)
            if (vsv_source_field(s0, i)->is_default)
                r->sel[r->nsel++] = i;
        int nvol = 0;
        for (int i = 0; i < nf; i++)
            nvol += vsv_source_field(s0, i)->is_volume;
        if (!nvol) {
            return fail(r, VSV_EINVAL,
                        "%s: no field of this %s file is a volume on the 3-D grid (%s); "
                        "vsv-extract --list shows what it holds",
                        names[0], vsv_source_format(s0),
                        nf && vsv_source_field(s0, 0)->role[0] ? vsv_source_field(s0, 0)->role : "2-D fields only");
        }
        if (!r->nsel) {
            return fail(r, VSV_EINVAL, "%s: none of the default variables is present; choose with --vars", names[0]);
        }
    }
    for (int v = 0; v < r->nsel; v++) {
        const vsv_field_info *f = vsv_source_field(s0, r->sel[v]);
        for (int i = 1; i < r->nsrc; i++)
            if (vsv_source_find_field(r->src[i], f->name) < 0) {
                return fail(r, VSV_EINVAL, "%s has no variable %s (it is in %s)", names[i], f->name, names[0]);
            }
        vsv_meta_add_var(&r->meta, f->name, f->units, f->description);
    }
    return 0;
}

int vsv_run_open(const char *const *paths, int npaths, const vsv_source_opts *opts, const char *vars, const char *times,
                 vsv_run **out)
{
    vsv_run *r = *out = calloc(1, sizeof *r);
    if (!r)
        return VSV_ENOMEM;
    vsv_meta_init(&r->meta);
    if (npaths < 1)
        return fail(r, VSV_EINVAL, "no input files");
    r->src = calloc((size_t)npaths, sizeof *r->src);
    const char **names = calloc((size_t)npaths, sizeof *names);
    if (!r->src || !names) {
        free(names);
        return fail(r, VSV_ENOMEM, "%s: out of memory", paths[0]);
    }
    int rc = 0;
    for (int i = 0; i < npaths; i++) {
        vsv_source *s = NULL;
        vsv_source_opts o;
        if (opts)
            o = *opts;
        else
            vsv_source_opts_init(&o);
        o.seq = paths, o.nseq = npaths, o.seq_index = i;
        rc = vsv_source_open(paths[i], &o, &s);
        if (rc) {
            fail(r, rc, "%s", vsv_source_error(s));
            vsv_source_free(s);
            goto done;
        }
        if (vsv_source_ntimes(s) < 1) {
            rc = fail(r, VSV_EINVAL, "%s: no output times (a %s file without time-varying fields)", paths[i],
                      vsv_source_format(s));
            vsv_source_free(s);
            goto done;
        }
        /* insertion by first time */
        int at = r->nsrc;
        while (at > 0 && vsv_source_time(r->src[at - 1], 0) > vsv_source_time(s, 0)) {
            r->src[at] = r->src[at - 1];
            names[at] = names[at - 1];
            at--;
        }
        r->src[at] = s;
        names[at] = paths[i];
        r->nsrc++;
        struct stat st;
        if (!stat(paths[i], &st))
            r->bytes += (uint64_t)st.st_size;
    }
    const vsv_meta *g0 = vsv_source_grid(r->src[0]);
    if ((rc = check_sources(r, names)))
        goto done;
    if ((rc = vsv_meta_copy(&r->meta, g0)) || (rc = run_moves(r)) || (rc = run_heights(r)))
        goto done;
    if (!(r->path = calloc((size_t)r->nsrc, sizeof *r->path))) {
        rc = VSV_ENOMEM;
        goto done;
    }
    for (int i = 0; i < r->nsrc; i++)
        if (!(r->path[i] = strdup(names[i]))) {
            rc = VSV_ENOMEM;
            goto done;
        }
    /* variables */
    if ((rc = select_vars(r, vars, names)))
        goto done;
    /* frames */
    int total = 0;
    for (int i = 0; i < r->nsrc; i++)
        total += vsv_source_ntimes(r->src[i]);
    r->fsrc = malloc((size_t)total * sizeof *r->fsrc);
    r->ft = malloc((size_t)total * sizeof *r->ft);
    r->ftime = malloc((size_t)total * sizeof *r->ftime);
    if (!r->fsrc || !r->ft || !r->ftime) {
        rc = VSV_ENOMEM;
        goto done;
    }
    for (int i = 0, k = 0; i < r->nsrc; i++)
        for (int t = 0; t < vsv_source_ntimes(r->src[i]); t++, k++) {
            r->fsrc[k] = i;
            r->ft[k] = t;
            r->ftime[k] = vsv_source_time(r->src[i], t);
        }
    r->nframes = total;
    r->origin = total ? r->ftime[0] : 0;
    /* outputs every so often: said in the file, so a frame interpolated
     * between them (--time-res) can say so */
    int regular = total >= 2;
    for (int k = 2; regular && k < total; k++)
        regular = r->ftime[k] - r->ftime[k - 1] == r->ftime[1] - r->ftime[0];
    if (regular) {
        char iso[40], text[96];
        vsv_cal_format(vsv_meta_calendar(&r->meta), r->ftime[0], iso, sizeof iso);
        snprintf(text, sizeof text, "every %lld s from %s", (long long)(r->ftime[1] - r->ftime[0]), iso);
        if (vsv_meta_add_attr(&r->meta, VSV_ATTR_OUTPUTS, text) < 0) {
            rc = VSV_ENOMEM;
            goto done;
        }
    }
    r->win[0] = INT64_MIN, r->win[1] = INT64_MAX;
    if (times)
        rc = vsv_run_select(r, times, 0);
done:
    free(names);
    if (rc && !r->err[0]) /* a step that gave only the code (out of memory) */
        fail(r, rc, "%s: %s opening the run", paths[0], vsv_strerror(rc));
    return rc;
}

/* Keeps frames a..b of the run. */
static void cut(vsv_run *r, int a, int b)
{
    const size_t n = (size_t)(b - a + 1);
    memmove(r->fsrc, r->fsrc + a, n * sizeof *r->fsrc);
    memmove(r->ft, r->ft + a, n * sizeof *r->ft);
    memmove(r->ftime, r->ftime + a, n * sizeof *r->ftime);
    if (r->wt)
        memmove(r->wt, r->wt + a, n * sizeof *r->wt);
    r->nframes = b - a + 1;
}

int vsv_run_select(vsv_run *r, const char *times, int64_t dt)
{
    const char *name = r->path[0];
    char msg[400];
    vsv_timesel sel;
    int rc;
    const int cal = vsv_meta_calendar(&r->meta);
    r->note[0] = 0;
    if (!dt) {
        if ((rc = vsv_timesel_parse(times, r->ftime, r->nframes, VSV_TIMESEL_CAL(cal), &sel, msg, sizeof msg)))
            return fail(r, rc, "%s: --times %s: %s", name, times, msg);
        r->win[0] = r->ftime[sel.first], r->win[1] = r->ftime[sel.last];
        if (!sel.exact) {
            char when[40];
            vsv_cal_format(cal, r->ftime[sel.first], when, sizeof when);
            snprintf(r->note, sizeof r->note, "--times %s: no step at that time; the nearest is step %d, %s", times,
                     sel.first, when);
        }
        cut(r, sel.first, sel.last);
        return 0;
    }
    /* the output steps origin + k*dt up to the last time: the selection
     * picks among them, and the model frames kept are those around them */
    if (dt < 0 || !r->nframes)
        return fail(r, VSV_EINVAL, "%s: --times %s: no steps", name, times);
    const int64_t span = (r->ftime[r->nframes - 1] - r->origin) / dt;
    if (span >= VSV_RUN_MAX_STEPS)
        return fail(r, VSV_ERANGE, "%s: more than %d output steps", name, VSV_RUN_MAX_STEPS);
    const int n = (int)span + 1;
    int64_t *grid = malloc((size_t)(n + 1) * sizeof *grid);
    if (!grid)
        return fail(r, VSV_ENOMEM, "out of memory");
    for (int k = 0; k < n; k++)
        grid[k] = r->origin + k * dt;
    rc = vsv_timesel_parse(times, grid, n, VSV_TIMESEL_CAL(cal), &sel, msg, sizeof msg);
    if (rc == VSV_ERANGE && r->ftime[r->nframes - 1] > grid[n - 1]) {
        /* a range ending after the last output step but within the run (its
         * last time off the grid: 03:00 every 2h from 00:00) ends at that
         * step; a mark one second past the run stands after it, so an
         * index past the steps, a later time or a start there still fail */
        vsv_timesel s2;
        grid[n] = r->ftime[r->nframes - 1] + 1;
        if (!vsv_timesel_parse(times, grid, n + 1, VSV_TIMESEL_CAL(cal), &s2, NULL, 0) && s2.range && s2.last < n)
            sel = s2, rc = 0;
    }
    if (!rc) {
        r->win[0] = grid[sel.first], r->win[1] = grid[sel.last];
        if (!sel.exact) {
            char when[40];
            vsv_cal_format(cal, grid[sel.first], when, sizeof when);
            snprintf(r->note, sizeof r->note, "--times %s: no output step at that time; the nearest is step %d, %s",
                     times, sel.first, when);
        }
    }
    free(grid);
    if (rc) {
        char every[32];
        vsv_duration_format(dt, every, sizeof every);
        return fail(r, rc, "%s: --times %s (among the output steps every %s): %s", name, times, every, msg);
    }
    int a = 0, b = r->nframes - 1;
    while (a + 1 < r->nframes && r->ftime[a + 1] <= r->win[0])
        a++;
    while (b > 0 && r->ftime[b - 1] >= r->win[1])
        b--;
    cut(r, a, b);
    return 0;
}

/* Frame i's winds into w: the stored components earth-relative, then the
 * auxiliary ones grid-relative. */
static int read_winds(vsv_run *r, int i, float *const *w)
{
    vsv_source *ws = r->wsrc ? r->wsrc : r->src[r->fsrc[i]];
    const size_t plane = (size_t)r->meta.nx * r->meta.ny, cells = plane * (size_t)r->meta.nz;
    for (int d = 0; d < r->ncomp; d++) {
        const int f = vsv_source_find_field(ws, r->wname[d]);
        if (f < 0)
            return fail(r, VSV_ENOTFOUND, "%s: no wind %s", r->path[r->fsrc[i]], r->wname[d]);
        int rc = vsv_source_read(ws, f, r->wsrc ? r->wt[i] : r->ft[i], w[d]);
        if (rc)
            return fail(r, rc, "%s", vsv_source_error(ws));
        if (r->store && r->nwind)
            memcpy(w[r->store + d], w[d], cells * sizeof(float));
    }
    if (!r->store)
        return 0;
    const vsv_move *mv = vsv_meta_move_at(&r->meta, r->ftime[i]);
    const double *o = mv ? mv->origin : r->meta.origin;
    if (!r->rot || o[0] != r->rot_at[0] || o[1] != r->rot_at[1]) {
        if (!r->rot && !(r->rot = malloc(plane * 4 * sizeof *r->rot)))
            return fail(r, VSV_ENOMEM, "out of memory");
        int rc = vsv_wind_rotation(&r->meta, o, r->rot);
        if (rc) {
            free(r->rot), r->rot = NULL;
            return fail(r, rc,
                        "%s: the winds cannot be rotated to east and north: the grid reaches beyond its %s "
                        "projection",
                        r->path[0], vsv_proj_name(r->meta.proj.kind));
        }
        r->rot_at[0] = o[0], r->rot_at[1] = o[1];
    }
    vsv_wind_rotate(r->rot, plane, r->meta.nz, w[0], w[1]);
    return 0;
}

int vsv_run_read(vsv_run *r, int i, float *const *fields)
{
    if (i < 0 || i >= r->nframes)
        return fail(r, VSV_ERANGE, "frame %d out of range", i);
    vsv_source *s = r->src[r->fsrc[i]];
    const vsv_source *s0 = r->src[0];
    for (int v = 0; v < r->nsel; v++) {
        const int f = s == s0 ? r->sel[v] : vsv_source_find_field(s, vsv_source_field(s0, r->sel[v])->name);
        int rc = vsv_source_read(s, f, r->ft[i], fields[v]);
        if (rc)
            return fail(r, rc, "%s", vsv_source_error(s));
    }
    int rc = r->nder ? vsv_derive_frame(r->der, s, r->ft[i], fields + r->nsel, r->err, sizeof r->err) : 0;
    if (rc)
        return rc;
    return r->store || r->nwind ? read_winds(r, i, fields + r->nsel + r->nder) : 0;
}

int vsv_run_add_derived(vsv_run *r, const char *spec)
{
    if (r->ncomp)
        return fail(r, VSV_EINVAL, "--derive %s: derived variables come before the winds", spec);
    if (!r->der && !(r->der = vsv_derive_create()))
        return fail(r, VSV_ENOMEM, "out of memory");
    int rc = vsv_derive_add(r->der, r->src[0], &r->meta, spec, r->err, sizeof r->err);
    if (rc)
        return rc;
    for (int i = 1; i < r->nsrc; i++) {
        const char *lack = vsv_derive_missing(r->der, r->src[i]);
        if (lack)
            return fail(r, VSV_ENOTFOUND, "--derive %s: %s has no %s (it is in %s)", spec, r->path[i], lack,
                        r->path[0]);
    }
    const int k = vsv_derive_count(r->der) - 1;
    const vsv_var *v = vsv_derive_var(r->der, k);
    char key[80];
    snprintf(key, sizeof key, "derived %s", v->name);
    if (vsv_meta_add_var(&r->meta, v->name, v->units, v->description) < 0 ||
        vsv_meta_add_attr(&r->meta, key, vsv_derive_formula(r->der, k)) < 0)
        return fail(r, VSV_ENOMEM, "out of memory");
    r->nder++;
    return 0;
}

/* The wind components a source offers: U and V (or UWIND and VWIND, as
 * MCIP names them) on its 3-D grid, and W (WWIND) when it has one. Returns
 * how many (0 when U or V is missing) and their names. */
static int find_winds(const vsv_source *s, char names[3][16])
{
    static const char *const sets[][3] = {{"U", "V", "W"}, {"UWIND", "VWIND", "WWIND"}};
    for (size_t k = 0; k < sizeof sets / sizeof *sets; k++) {
        int n = 0;
        for (int d = 0; d < 3; d++) {
            const int f = vsv_source_find_field(s, sets[k][d]);
            if (f < 0 || !vsv_source_field(s, f)->is_volume)
                break;
            snprintf(names[d], sizeof names[d], "%s", sets[k][d]);
            n++;
        }
        if (n >= 2)
            return n;
    }
    return 0;
}

/* Finds the winds once (r->ncomp components, their names, and where:
 * companion or the run's own files); 0, or VSV_ENOTFOUND when there are
 * none (with quiet, 1 and no message). */
static int wind_source(vsv_run *r, const char *companion, const vsv_source_opts *opts, int quiet)
{
    if (r->ncomp)
        return 0;
    int n;
    if (companion) {
        vsv_source_opts o;
        if (opts)
            o = *opts;
        else
            vsv_source_opts_init(&o);
        o.seq = &companion, o.nseq = 1, o.seq_index = 0;
        int rc = vsv_source_open(companion, &o, &r->wsrc);
        if (rc)
            return fail(r, rc, "--winds: %s", vsv_source_error(r->wsrc));
        const vsv_meta *g = vsv_source_grid(r->wsrc);
        if (g->nx != r->meta.nx || g->ny != r->meta.ny || g->nz != r->meta.nz || g->origin[0] != r->meta.origin[0] ||
            g->origin[1] != r->meta.origin[1] || g->spacing[0] != r->meta.spacing[0] ||
            g->spacing[1] != r->meta.spacing[1])
            return fail(r, VSV_EINVAL, "--winds %s: its grid (%d x %d x %d) is not the grid of %s (%d x %d x %d)",
                        companion, g->nx, g->ny, g->nz, r->path[0], r->meta.nx, r->meta.ny, r->meta.nz);
        if (!(n = find_winds(r->wsrc, r->wname)))
            return fail(r, VSV_ENOTFOUND, "--winds %s: no wind in it (3-D fields U and V, or UWIND and VWIND)",
                        companion);
        if (!(r->wt = malloc((size_t)r->nframes * sizeof *r->wt)))
            return VSV_ENOMEM;
        for (int i = 0, t = 0; i < r->nframes; i++) {
            while (t < vsv_source_ntimes(r->wsrc) && vsv_source_time(r->wsrc, t) < r->ftime[i])
                t++;
            if (t >= vsv_source_ntimes(r->wsrc) || vsv_source_time(r->wsrc, t) != r->ftime[i]) {
                char when[40];
                vsv_cal_format(vsv_meta_calendar(&r->meta), r->ftime[i], when, sizeof when);
                return fail(r, VSV_ENOTFOUND, "--winds %s: no winds at %s (frame %d of the run)", companion, when, i);
            }
            r->wt[i] = t;
        }
    } else {
        if (!(n = find_winds(r->src[0], r->wname)))
            return quiet ? 1
                         : fail(r, VSV_ENOTFOUND,
                                "%s: advection needs winds, and this %s file has no 3-D U and V (nor UWIND and "
                                "VWIND); name a file with them: --winds FILE",
                                r->path[0], vsv_source_format(r->src[0]));
        for (int i = 1; i < r->nsrc; i++)
            for (int d = 0; d < n; d++)
                if (vsv_source_find_field(r->src[i], r->wname[d]) < 0)
                    return fail(r, VSV_ENOTFOUND, "%s has no wind %s (it is in %s)", r->path[i], r->wname[d],
                                r->path[0]);
    }
    r->ncomp = n;
    return 0;
}

/* The name of the file the winds come from (--winds, or the file of the
 * run's first source holding the first component: a CAMx met companion),
 * without its directory. */
static const char *wind_file(const vsv_run *r, const char *companion)
{
    const char *from = companion ? companion
                                 : vsv_source_field_path(r->src[0], vsv_source_find_field(r->src[0], r->wname[0])),
               *base = strrchr(from, '/');
    return base ? base + 1 : from;
}

int vsv_run_store_winds(vsv_run *r, const char *companion, const vsv_source_opts *opts)
{
    if (r->store)
        return 0;
    if (r->nwind)
        return fail(r, VSV_EINVAL, "the stored winds come before the auxiliary ones");
    int rc = wind_source(r, companion, opts, 1);
    if (rc)
        return rc;
    static const char *const vname[3] = {VSV_WIND_EAST, VSV_WIND_NORTH, VSV_WIND_UP};
    static const char *const what[3] = {"eastward wind", "northward wind", "upward wind"};
    char list[64] = "";
    for (int d = 0; d < r->ncomp; d++) {
        char desc[160];
        snprintf(desc, sizeof desc, "%s (earth-relative, at mass points; from %s)", what[d], r->wname[d]);
        if (vsv_meta_find_var(&r->meta, vname[d]) >= 0)
            return fail(r, VSV_EINVAL, "the winds: the run already has a variable %s", vname[d]);
        if (vsv_meta_add_var(&r->meta, vname[d], "m s-1", desc) < 0)
            return fail(r, VSV_ENOMEM, "out of memory");
        snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", d ? " " : "", vname[d]);
    }
    char buf[512];
    vsv_wind_origin(&r->meta, vsv_source_format(r->wsrc ? r->wsrc : r->src[0]), wind_file(r, companion), r->wname,
                    r->ncomp, buf, sizeof buf);
    if (vsv_meta_add_attr(&r->meta, VSV_VECTOR_ATTR VSV_WIND, list) < 0 ||
        vsv_meta_add_attr(&r->meta, VSV_WIND_SOURCE_ATTR, buf) < 0)
        return fail(r, VSV_ENOMEM, "out of memory");
    r->store = r->ncomp;
    return 0;
}

int vsv_run_add_winds(vsv_run *r, const char *companion, const vsv_source_opts *opts)
{
    if (r->nwind)
        return 0;
    int rc = wind_source(r, companion, opts, 0);
    if (rc)
        return rc;
    const int n = r->ncomp;
    static const char *const vname[3] = {VSV_WIND_U, VSV_WIND_V, VSV_WIND_W};
    static const char *const what[3] = {"wind along the grid's x axis", "wind along the grid's y axis",
                                        "vertical wind"};
    for (int d = 0; d < n; d++) {
        char desc[128];
        snprintf(desc, sizeof desc, "%s (%s), auxiliary: used by --interp advect", what[d], r->wname[d]);
        const int v = vsv_meta_add_var(&r->meta, vname[d], "m s-1", desc);
        if (v < 0)
            return v;
    }
    char buf[256];
    snprintf(buf, sizeof buf, "%s %s%s%s of %s (%s; grid-relative, m/s)", r->wname[0], r->wname[1], n > 2 ? " " : "",
             n > 2 ? r->wname[2] : "", wind_file(r, companion), vsv_source_format(r->wsrc ? r->wsrc : r->src[0]));
    rc = vsv_meta_add_attr(&r->meta, VSV_WINDS_ATTR, buf);
    if (rc < 0)
        return rc;
    r->nwind = n;
    return 0;
}

void vsv_run_free(vsv_run *r)
{
    if (!r)
        return;
    for (int i = 0; i < r->nsrc; i++)
        vsv_source_free(r->src[i]);
    free(r->src);
    free(r->sel);
    free(r->fsrc);
    free(r->ft);
    free(r->ftime);
    free(r->wt);
    free(r->rot);
    vsv_source_free(r->wsrc);
    vsv_derive_free(r->der);
    for (int i = 0; r->path && i < r->nsrc; i++)
        free(r->path[i]);
    free(r->path);
    vsv_meta_clear(&r->meta);
    free(r);
}
