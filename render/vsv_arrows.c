/* vsv_arrows.c — wind arrows on a horizontal plane (vsv_wind_arrows): the
 * wind species' east and north components sampled at a height in every
 * k-th column, turned onto the grid's axes, as lines a renderer draws
 * with arrowheads (vsv_scene_line). */
#include "vsv_render.h"

#include <math.h>

/* Height of level k's centre in column (i, j): the per-column heights, else
 * the renderers' even axis (as isosurfaces place it). */
static double level_z(const vsv_meta *m, const float *hts, double oz, double dz, int i, int j, int k)
{
    return hts ? hts[((size_t)k * m->ny + j) * m->nx + i] : oz + k * dz;
}

/* The value of v at height z in column (i, j) (linear between the levels
 * around it); NaN where z is outside the column's levels. */
static double column_at(const vsv_meta *m, const vsv_volume *v, const float *hts, double oz, double dz, int i, int j,
                        double z)
{
    for (int k = 0; k + 1 < m->nz; k++) {
        const double z0 = level_z(m, hts, oz, dz, i, j, k), z1 = level_z(m, hts, oz, dz, i, j, k + 1);
        if (z >= z0 && z <= z1 && z1 > z0) {
            const double f = (z - z0) / (z1 - z0);
            return (1 - f) * vsv_volume_at(v, i, j, k) + f * vsv_volume_at(v, i, j, k + 1);
        }
    }
    return m->nz == 1 && z == level_z(m, hts, oz, dz, i, j, 0) ? vsv_volume_at(v, i, j, 0) : NAN;
}

int vsv_wind_arrows(const vsv_meta *m, const vsv_volume *east, const vsv_volume *north, double z, int every,
                    double seconds, double *xyz, int cap, int *n, double *fastest)
{
    *n = 0;
    *fastest = 0;
    if (!east || !north || every < 1 || !isfinite(z) || !(seconds > 0) || cap < 0 || east->nx != m->nx ||
        east->ny != m->ny || east->nz != m->nz || north->nx != m->nx || north->ny != m->ny || north->nz != m->nz)
        return VSV_EINVAL;
    const float *hts = m->vert_kind == VSV_VERT_NATIVE ? vsv_meta_heights_at(m, east->time) : NULL;
    double oz = 250, dz = 500, ux, uy;
    if (m->vert_kind == VSV_VERT_EVEN)
        oz = m->origin[2], dz = m->spacing[2];
    else if (m->vert_kind == VSV_VERT_NATIVE && m->levels && m->nz > 1)
        oz = m->levels[0], dz = (m->levels[m->nz - 1] - m->levels[0]) / (m->nz - 1);
    vsv_scene_units(m, &ux, &uy);
    for (int j = 0; j < m->ny; j += every)
        for (int i = 0; i < m->nx && *n < cap; i += every) {
            if (m->terrain && !vsv_meta_above_ground(m) && z < m->terrain[(size_t)j * m->nx + i])
                continue; /* under the ground */
            const double e = column_at(m, east, hts, oz, dz, i, j, z), no = column_at(m, north, hts, oz, dz, i, j, z);
            if (!isfinite(e) || !isfinite(no))
                continue;
            const double px = m->origin[0] + i * m->spacing[0], py = m->origin[1] + j * m->spacing[1];
            double J[2][2];
            if (vsv_proj_jacobian(&m->proj, px, py, J))
                continue;
            /* (e, no) = gx J[0] + gy J[1]: the move along the grid's axes */
            const double det = J[0][0] * J[1][1] - J[1][0] * J[0][1];
            if (!(fabs(det) > 0))
                continue;
            const double gx = (e * J[1][1] - no * J[1][0]) / det, gy = (no * J[0][0] - e * J[0][1]) / det;
            double *a = xyz + 6 * (*n)++;
            a[0] = px * ux, a[1] = py * uy, a[2] = z;
            a[3] = a[0] + gx * seconds * ux, a[4] = a[1] + gy * seconds * uy, a[5] = z;
            *fastest = fmax(*fastest, hypot(e, no));
        }
    return 0;
}
