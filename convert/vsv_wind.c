/* vsv_wind.c — the model's wind as earth-relative components at mass
 * points (vsv_run_store_winds): the rotation from the grid's axes to east
 * and north column by column, and what each model's winds were. */
#include "vsv_convert.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

int vsv_wind_rotation(const vsv_meta *m, const double origin[2], float *rot)
{
    for (int j = 0; j < m->ny; j++)
        for (int i = 0; i < m->nx; i++) {
            double J[2][2] = {{1, 0}, {0, 1}};
            const double x = origin[0] + i * m->spacing[0], y = origin[1] + j * m->spacing[1];
            /* a latitude-longitude grid's axes are east and north everywhere (the poles too) */
            const int rc = m->proj.kind == VSV_PROJ_LATLON ? 0 : vsv_proj_jacobian(&m->proj, x, y, J);
            if (rc)
                return rc;
            const double a = hypot(J[0][0], J[0][1]), b = hypot(J[1][0], J[1][1]);
            if (!(a > 0) || !(b > 0))
                return VSV_ERANGE;
            float *r = rot + 4 * ((size_t)j * m->nx + i);
            /* east = u * r[0] + v * r[1], north = u * r[2] + v * r[3] */
            r[0] = (float)(J[0][0] / a), r[1] = (float)(J[1][0] / b);
            r[2] = (float)(J[0][1] / a), r[3] = (float)(J[1][1] / b);
        }
    return 0;
}

void vsv_wind_rotate(const float *rot, size_t plane, int nz, float *u, float *v)
{
    for (int k = 0; k < nz; k++)
        for (size_t c = 0; c < plane; c++) {
            const float *r = rot + 4 * c;
            const size_t o = (size_t)k * plane + c;
            const double ug = u[o], vg = v[o];
            u[o] = (float)(ug * r[0] + vg * r[1]);
            v[o] = (float)(ug * r[2] + vg * r[3]);
        }
}

void vsv_wind_origin(const vsv_meta *g, const char *format, const char *file, char names[3][16], int n, char *buf,
                     size_t cap)
{
    const char *how;
    if (!strncmp(g->model, "MM5", 3))
        how = "U, V on dot points (the mean of the 4 around a cross point), W on full sigma levels (of the 2 "
              "around a half level)";
    else if (!strncmp(g->model, "WRF", 3))
        how = "U, V on the C grid's faces, W on full eta levels (each the mean of the 2 faces around a mass point)";
    else if (!strncmp(g->model, "CAMx", 4))
        how = "U, V at cell centres, or the mean of the 2 faces around one (a staggered file)";
    else
        how = "at the grid's points as the file holds them";
    const char *pj = g->proj.kind == VSV_PROJ_NONE ? "none: taken as east, north" : vsv_proj_name(g->proj.kind);
    snprintf(buf, cap,
             "%s %s%s%s (%s, grid-relative m/s: %s; rotated to east, north by the projection's (%s) "
             "convergence) of %s",
             names[0], names[1], n > 2 ? " " : "", n > 2 ? names[2] : "", format, how, pj, file);
}
