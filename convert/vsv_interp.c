/* vsv_interp.c — linear interpolation of frames in time (vsv-interp and
 * vsv-convert --time-res). Keeps one previous frame; allocates at creation
 * only. */
#include "vsv_convert.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct vsv_interp {
    int64_t dt, t0, prev_t;
    int nf, have, dropped, origin_set;
    size_t cells;
    float **prev, **tmp;
    vsv_frame_fn emit;
    void *ctx;
};

int vsv_interp_create(int64_t dt, int nfields, size_t cells, vsv_frame_fn emit, void *ctx, vsv_interp **out)
{
    vsv_interp *ip = *out = calloc(1, sizeof *ip);
    if (!ip || dt <= 0)
        return ip ? VSV_EINVAL : VSV_ENOMEM;
    ip->dt = dt;
    ip->nf = nfields;
    ip->cells = cells;
    ip->emit = emit;
    ip->ctx = ctx;
    ip->prev = calloc((size_t)nfields + 1, sizeof *ip->prev);
    ip->tmp = calloc((size_t)nfields + 1, sizeof *ip->tmp);
    if (!ip->prev || !ip->tmp)
        return VSV_ENOMEM;
    for (int v = 0; v < nfields; v++)
        if (!(ip->prev[v] = malloc(cells * sizeof(float))) || !(ip->tmp[v] = malloc(cells * sizeof(float))))
            return VSV_ENOMEM;
    return 0;
}

int vsv_interp_push(vsv_interp *ip, int64_t time, const float *const *fields)
{
    int rc;
    if (ip->have) {
        if (time <= ip->prev_t)
            return VSV_EINVAL;
        /* grid times strictly between the previous frame and this one */
        int64_t k = (ip->prev_t - ip->t0) / ip->dt + 1;
        for (int64_t t = ip->t0 + k * ip->dt; t < time; t += ip->dt) {
            const double w = (double)(t - ip->prev_t) / (double)(time - ip->prev_t);
            for (int v = 0; v < ip->nf; v++) {
                const float *a = ip->prev[v], *b = fields[v];
                float *o = ip->tmp[v];
                for (size_t i = 0; i < ip->cells; i++)
                    o[i] = (float)(a[i] + ((double)b[i] - a[i]) * w);
            }
            if ((rc = ip->emit(ip->ctx, t, (const float *const *)ip->tmp)))
                return rc;
        }
    } else if (!ip->origin_set) {
        ip->t0 = time;
    }
    /* an input frame on the grid passes through unchanged; one between grid
     * times only feeds the interpolation (every step stays dt apart) */
    if ((time - ip->t0) % ip->dt == 0) {
        if ((rc = ip->emit(ip->ctx, time, fields)))
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

int vsv_interp_dropped(const vsv_interp *ip) { return ip ? ip->dropped : 0; }

void vsv_interp_set_origin(vsv_interp *ip, int64_t t0)
{
    ip->t0 = t0;
    ip->origin_set = 1;
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
    free(ip->prev);
    free(ip->tmp);
    free(ip);
}
