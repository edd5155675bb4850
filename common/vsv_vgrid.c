/* vsv_vgrid.c — see vsv_vgrid.h. */
#include "vsv_vgrid.h"

#include <math.h>
#include <stdlib.h>

int vsv_vgrid_plan(vsv_vgrid *g, const float *zn, int kx, size_t plane, const float *ground, int nz, double z0,
                   double dz)
{
    if (!g->lev || g->nz != nz || g->plane != plane) {
        free(g->lev);
        free(g->wt);
        g->lev = malloc((size_t)nz * plane * sizeof *g->lev);
        g->wt = malloc((size_t)nz * plane * sizeof *g->wt);
        if (!g->lev || !g->wt)
            return -1;
    }
    g->nz = nz;
    g->kx = kx;
    g->plane = plane;
    g->z0 = z0;
    g->dz = dz;
    for (size_t c = 0; c < plane; c++) {
        const double floor_z = ground ? ground[c] : -INFINITY;
        const double top = zn[(size_t)(kx - 1) * plane + c];
        int k0 = 0;
        for (int k = 0; k < nz; k++) {
            const double z = z0 + k * dz;
            const size_t at = (size_t)k * plane + c;
            int16_t lv = -1;
            float w = 0;
            if (z >= floor_z && z <= top) {
                if (z <= zn[c] || kx == 1) {
                    lv = 0;
                } else {
                    while (k0 + 1 < kx - 1 && zn[(size_t)(k0 + 1) * plane + c] < z)
                        k0++;
                    const double za = zn[(size_t)k0 * plane + c], zb = zn[(size_t)(k0 + 1) * plane + c];
                    lv = (int16_t)k0;
                    w = zb > za ? (float)((z - za) / (zb - za)) : 0;
                }
            }
            g->lev[at] = lv;
            g->wt[at] = w;
        }
    }
    return 0;
}

void vsv_vgrid_apply(const vsv_vgrid *g, const float *nat, float *out)
{
    const size_t plane = g->plane;
    for (int k = 0; k < g->nz; k++)
        for (size_t c = 0; c < plane; c++) {
            const size_t at = (size_t)k * plane + c;
            const int lv = g->lev[at];
            if (lv < 0) {
                out[at] = NAN;
            } else {
                const float lo = nat[(size_t)lv * plane + c], w = g->wt[at];
                out[at] = w == 0 ? lo : lo + (nat[(size_t)(lv + 1) * plane + c] - lo) * w;
            }
        }
}

void vsv_vgrid_free(vsv_vgrid *g)
{
    free(g->lev);
    free(g->wt);
    g->lev = NULL;
    g->wt = NULL;
}
