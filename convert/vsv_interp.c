/* vsv_interp.c — frames in time (vsv-interp and vsv-convert --time-res):
 * keeps the previous frame, emits the times between it and the next one,
 * linear or along the winds (vsv_advect.c), and passes the originals
 * through untouched. Wind variables are consumed, never emitted. Allocates
 * at creation only. */
#include "vsv_advect.h"
#include "vsv_convert.h"
#include "vsv_common.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

struct vsv_interp {
    int64_t dt, t0, prev_t;
    int64_t win[2]; /* the steps emitted: win[0] <= t <= win[1] */
    int nf, nout, have, method, dropped, origin_set;
    int wind[3]; /* input index of wind.u, wind.v, wind.w (-1 absent) */
    int *keep;   /* nout input indices of the emitted fields */
    size_t cells;
    float **prev, **tmp;
    const float **in0, **in1, **outp; /* nout pointers: scratch for each frame */
    vsv_advect *adv;
    /* a moving nest: its placements (origin per time, GRID's first), and
       the next frame moved into the last one's place (cells of nx*ny*nz) */
    int nx, ny, nplace;
    double dx, dy;
    int64_t *ptime;
    double (*porig)[2];
    float **moved;
    vsv_frame_fn emit;
    void *ctx;
    char err[256];
};

int vsv_interp_method(const char *name)
{
    return !strcmp(name, "linear")   ? VSV_TIME_LINEAR
           : !strcmp(name, "advect") ? VSV_TIME_ADVECT
           : !strcmp(name, "wind")   ? VSV_TIME_WIND
                                     : -1;
}

const char *vsv_interp_error(const vsv_interp *ip) { return ip ? ip->err : "out of memory"; }

static int is_wind(const char *name)
{
    return !strcmp(name, VSV_WIND_U) || !strcmp(name, VSV_WIND_V) || !strcmp(name, VSV_WIND_W);
}

/* The common set-up: nfields inputs of which keep[0..nout) are emitted. */
static int setup(vsv_interp *ip, int64_t dt, int nfields, size_t cells, vsv_frame_fn emit, void *ctx)
{
    if (dt <= 0 || nfields < 0) {
        vsv_msg(ip->err, sizeof ip->err, "a time step of %lld s and %d fields", (long long)dt, nfields);
        return VSV_EINVAL;
    }
    ip->dt = dt;
    ip->win[0] = INT64_MIN, ip->win[1] = INT64_MAX;
    ip->nf = nfields;
    ip->cells = cells;
    ip->emit = emit;
    ip->ctx = ctx;
    ip->prev = calloc((size_t)nfields + 1, sizeof *ip->prev);
    ip->tmp = calloc((size_t)nfields + 1, sizeof *ip->tmp);
    ip->in0 = calloc((size_t)nfields + 1, sizeof *ip->in0);
    ip->in1 = calloc((size_t)nfields + 1, sizeof *ip->in1);
    ip->outp = calloc((size_t)nfields + 1, sizeof *ip->outp);
    if (!ip->prev || !ip->tmp || !ip->in0 || !ip->in1 || !ip->outp)
        return VSV_ENOMEM;
    for (int v = 0; v < nfields; v++)
        if (!(ip->prev[v] = malloc(cells * sizeof(float))) || !(ip->tmp[v] = malloc(cells * sizeof(float))))
            return VSV_ENOMEM;
    return 0;
}

/* The placements of a moving grid (none: it stays put). */
static int placements(vsv_interp *ip, const vsv_meta *m)
{
    ip->nx = m->nx, ip->ny = m->ny, ip->dx = m->spacing[0], ip->dy = m->spacing[1];
    if (!m->nmoves)
        return 0;
    ip->nplace = m->nmoves + 1;
    ip->ptime = malloc((size_t)ip->nplace * sizeof *ip->ptime);
    ip->porig = malloc((size_t)ip->nplace * sizeof *ip->porig);
    ip->moved = calloc((size_t)ip->nf + 1, sizeof *ip->moved);
    if (!ip->ptime || !ip->porig || !ip->moved)
        return VSV_ENOMEM;
    ip->ptime[0] = INT64_MIN;
    memcpy(ip->porig[0], m->origin, sizeof ip->porig[0]);
    for (int i = 0; i < m->nmoves; i++) {
        ip->ptime[i + 1] = m->moves[i].time;
        memcpy(ip->porig[i + 1], m->moves[i].origin, sizeof ip->porig[0]);
    }
    for (int v = 0; v < ip->nf; v++)
        if (!(ip->moved[v] = malloc(ip->cells * sizeof(float))))
            return VSV_ENOMEM;
    return 0;
}

/* The origin of the placement in force at t. */
static const double *origin_at(const vsv_interp *ip, int64_t t)
{
    int i = 0;
    while (i + 1 < ip->nplace && ip->ptime[i + 1] <= t)
        i++;
    return ip->porig[i];
}

/* Frames between two placements of a moving nest are interpolated where the
 * air is, not where the cells are: the next frame's fields moved by whole
 * cells into the last frame's place (a cell it does not cover keeps the last
 * frame's value). *next: the fields to interpolate toward (fields itself
 * where the grid did not move); 0, or VSV_EUNSUPPORTED with ip->err set. */
static int moved_fields(vsv_interp *ip, int64_t time, const float *const *fields, const float *const **next)
{
    *next = fields;
    if (!ip->nplace || !fields)
        return 0;
    const double *a = origin_at(ip, ip->prev_t), *b = origin_at(ip, time);
    const double fx = (a[0] - b[0]) / ip->dx, fy = (a[1] - b[1]) / ip->dy;
    const long sx = lround(fx), sy = lround(fy);
    if (!sx && !sy)
        return 0;
    if (fabs(fx - (double)sx) > 0.01 || fabs(fy - (double)sy) > 0.01) {
        vsv_msg(ip->err, sizeof ip->err, "the grid moves by %.3f x %.3f cells: frames between are not interpolated", fx,
                fy);
        return VSV_EUNSUPPORTED;
    }
    const size_t plane = (size_t)ip->nx * ip->ny, nz = ip->cells / plane;
    for (int v = 0; v < ip->nf; v++)
        for (size_t k = 0; k < nz; k++)
            for (long j = 0; j < ip->ny; j++)
                for (long i = 0; i < ip->nx; i++) {
                    const size_t c = k * plane + (size_t)j * ip->nx + (size_t)i;
                    const long i1 = i + sx, j1 = j + sy;
                    const int in = i1 >= 0 && i1 < ip->nx && j1 >= 0 && j1 < ip->ny;
                    ip->moved[v][c] = in ? fields[v][k * plane + (size_t)j1 * ip->nx + (size_t)i1] : ip->prev[v][c];
                }
    *next = (const float *const *)ip->moved;
    return 0;
}

int vsv_interp_create(int64_t dt, int nfields, size_t cells, vsv_frame_fn emit, void *ctx, vsv_interp **out)
{
    vsv_interp *ip = *out = calloc(1, sizeof *ip);
    if (!ip)
        return VSV_ENOMEM;
    ip->wind[0] = ip->wind[1] = ip->wind[2] = -1;
    ip->keep = malloc((size_t)(nfields > 0 ? nfields : 1) * sizeof *ip->keep);
    if (!ip->keep)
        return VSV_ENOMEM;
    for (int v = 0; v < nfields; v++) /* nfields 0: the times only */
        ip->keep[v] = v;
    ip->nout = nfields;
    return setup(ip, dt, nfields, cells, emit, ctx);
}

int vsv_interp_open(int64_t dt, const vsv_meta *m, const vsv_interp_opts *o, vsv_frame_fn emit, void *ctx,
                    vsv_interp **out)
{
    vsv_interp *ip = *out = calloc(1, sizeof *ip);
    if (!ip)
        return VSV_ENOMEM;
    ip->method = o ? o->method : VSV_TIME_LINEAR;
    ip->keep = malloc((size_t)(m->nvars > 0 ? m->nvars : 1) * sizeof *ip->keep);
    if (!ip->keep)
        return VSV_ENOMEM;
    ip->wind[0] = vsv_meta_find_var(m, VSV_WIND_U);
    ip->wind[1] = vsv_meta_find_var(m, VSV_WIND_V);
    ip->wind[2] = vsv_meta_find_var(m, VSV_WIND_W);
    for (int d = 0; d < 3; d++)
        if (ip->wind[d] < 0)
            ip->wind[d] = -1;
    for (int v = 0; v < m->nvars; v++)
        if (!is_wind(m->vars[v].name))
            ip->keep[ip->nout++] = v;
    if (!ip->nout) {
        vsv_msg(ip->err, sizeof ip->err, "no fields to interpolate besides the winds");
        return VSV_EINVAL;
    }
    const size_t cells = (size_t)m->nx * m->ny * m->nz;
    int rc = setup(ip, dt, m->nvars, cells, emit, ctx);
    if (!rc)
        rc = placements(ip, m);
    if (rc || ip->method == VSV_TIME_LINEAR)
        return rc;
    if (ip->wind[0] < 0 || ip->wind[1] < 0) {
        vsv_msg(ip->err, sizeof ip->err,
                "--interp %s needs the winds, and the input has no %s%s%s (horizontal wind along the grid's "
                "x and y axes)",
                ip->method == VSV_TIME_WIND ? "wind" : "advect", ip->wind[0] < 0 ? VSV_WIND_U : "",
                ip->wind[0] < 0 && ip->wind[1] < 0 ? " and no " : "", ip->wind[1] < 0 ? VSV_WIND_V : "");
        return VSV_ENOTFOUND;
    }
    if ((rc = vsv_advect_create(m, o->threads, &ip->adv)))
        return rc;
    vsv_advect_set_scale(ip->adv, ip->method == VSV_TIME_WIND ? 1.0f : 0.0f);
    return 0;
}

int vsv_interp_meta(const vsv_interp *ip, const vsv_meta *m, vsv_meta *dst)
{
    int rc = vsv_meta_copy(dst, m);
    if (rc)
        return rc;
    /* drop the wind variables (their transfer functions too) */
    int n = 0;
    for (int v = 0; v < dst->nvars; v++) {
        if (is_wind(dst->vars[v].name)) {
            if (dst->tf)
                free(dst->tf[v]);
            continue;
        }
        dst->vars[n] = dst->vars[v];
        if (dst->tf)
            dst->tf[n] = dst->tf[v];
        n++;
    }
    dst->nvars = n;
    /* and the attribute that described them */
    const char *winds = vsv_meta_attr(m, VSV_WINDS_ATTR);
    int a = 0;
    for (int i = 0; i < dst->nattrs; i++) {
        if (!strcmp(dst->attr_keys[i], VSV_WINDS_ATTR))
            continue;
        if (a != i) {
            memcpy(dst->attr_keys[a], dst->attr_keys[i], sizeof dst->attr_keys[a]);
            memcpy(dst->attr_values[a], dst->attr_values[i], sizeof dst->attr_values[a]);
        }
        a++;
    }
    dst->nattrs = a;
    if (ip->method != VSV_TIME_LINEAR) {
        char buf[256];
        snprintf(buf, sizeof buf, "%s: semi-Lagrangian along %s%s%s", ip->method == VSV_TIME_WIND ? "wind" : "advect",
                 winds ? winds : "the input's winds",
                 ip->wind[2] < 0 || !vsv_advect_has_vertical(ip->adv) ? " (horizontal only)" : "",
                 ip->method == VSV_TIME_WIND
                     ? ""
                     : ", displacements scaled per species and band of levels as fitted to the outputs");
        rc = vsv_meta_add_attr(dst, "time interpolation", buf);
    }
    return rc;
}

int vsv_interp_push(vsv_interp *ip, int64_t time, const float *const *fields)
{
    int rc;
    const float *const *next = fields; /* what the frames between lead to */
    if (ip->have && time > ip->prev_t && (rc = moved_fields(ip, time, fields, &next)))
        return rc;
    if (ip->have) {
        if (time <= ip->prev_t)
            return VSV_EINVAL;
        for (int v = 0; v < ip->nout; v++) {
            ip->in0[v] = ip->prev[ip->keep[v]];
            ip->in1[v] = next[ip->keep[v]];
            ip->outp[v] = ip->tmp[v];
        }
        /* grid times strictly between the previous frame and this one */
        int winds_set = 0;
        int64_t k = (ip->prev_t - ip->t0) / ip->dt + 1;
        int64_t t = ip->t0 + k * ip->dt;
        if (t < ip->win[0]) /* skip to the window */
            t += (ip->win[0] - t) / ip->dt * ip->dt;
        for (; t < time && t <= ip->win[1]; t += ip->dt) {
            if (t < ip->win[0])
                continue;
            if (ip->method != VSV_TIME_LINEAR) {
                if (!winds_set) {
                    const int *w = ip->wind;
                    vsv_advect_winds(ip->adv, ip->prev[w[0]], ip->prev[w[1]], w[2] >= 0 ? ip->prev[w[2]] : NULL,
                                     next[w[0]], next[w[1]], w[2] >= 0 ? next[w[2]] : NULL);
                    if ((rc = vsv_advect_outputs(ip->adv, ip->nout, ip->in0, ip->in1))) {
                        vsv_msg(ip->err, sizeof ip->err, "out of memory");
                        return rc;
                    }
                    vsv_advect_fit(ip->adv, ip->prev_t, time);
                    winds_set = 1;
                }
                vsv_advect_frame(ip->adv, ip->prev_t, time, t, ip->tmp);
            } else {
                const double w = (double)(t - ip->prev_t) / (double)(time - ip->prev_t);
                for (int v = 0; v < ip->nout; v++) {
                    const float *a = ip->in0[v], *b = ip->in1[v];
                    float *o = ip->tmp[v];
                    for (size_t i = 0; i < ip->cells; i++)
                        o[i] = (float)(a[i] + ((double)b[i] - a[i]) * w);
                }
            }
            if ((rc = ip->emit(ip->ctx, t, ip->outp)))
                return rc;
        }
    } else if (!ip->origin_set) {
        ip->t0 = time;
    }
    /* an input frame on the grid passes through unchanged; one between grid
     * times only feeds the interpolation (every step stays dt apart) */
    if (time < ip->win[0] || time > ip->win[1]) {
        /* only bounds the interpolation into the window */
    } else if ((time - ip->t0) % ip->dt == 0) {
        for (int v = 0; v < ip->nout; v++)
            ip->outp[v] = fields[ip->keep[v]];
        if ((rc = ip->emit(ip->ctx, time, ip->outp)))
            return rc;
    } else {
        ip->dropped++;
    }
    for (int v = 0; v < ip->nf; v++)
        memcpy(ip->prev[v], fields[v], ip->cells * sizeof(float));
    ip->prev_t = time;
    ip->have = 1;
    return 0;
}

const float *vsv_interp_scales(const vsv_interp *ip, int *nband)
{
    return ip && ip->adv && ip->method == VSV_TIME_ADVECT ? vsv_advect_scales(ip->adv, nband) : NULL;
}

int vsv_interp_dropped(const vsv_interp *ip) { return ip ? ip->dropped : 0; }

void vsv_interp_set_origin(vsv_interp *ip, int64_t t0)
{
    ip->t0 = t0;
    ip->origin_set = 1;
}

void vsv_interp_set_window(vsv_interp *ip, int64_t first, int64_t last)
{
    ip->win[0] = first;
    ip->win[1] = last;
}

void vsv_interp_free(vsv_interp *ip)
{
    if (!ip)
        return;
    for (int v = 0; v < ip->nf; v++) {
        if (ip->prev)
            free(ip->prev[v]);
        if (ip->tmp)
            free(ip->tmp[v]);
    }
    for (int v = 0; ip->moved && v < ip->nf; v++)
        free(ip->moved[v]);
    free(ip->moved);
    free(ip->ptime);
    free(ip->porig);
    free(ip->prev);
    free(ip->tmp);
    free(ip->in0);
    free(ip->in1);
    free(ip->outp);
    free(ip->keep);
    vsv_advect_free(ip->adv);
    free(ip);
}
