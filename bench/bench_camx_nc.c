/* bench_camx_nc.c — the netCDF equivalent of a UAM-IV file for the size
 * comparison: one float variable per species (TSTEP, LAY, ROW, COL), classic
 * 64-bit-offset format, written from the UAM-IV reader's values. Usage:
 *   bench_camx_nc IN.avrg OUT.nc */
#include "vsv_uamiv.h"

#include <netcdf.h>
#include <stdio.h>
#include <stdlib.h>

int main(int argc, char **argv)
{
    if (argc != 3)
        return 2;
    vsv_uamiv *u = NULL;
    if (vsv_uamiv_open(argv[1], &u)) {
        fprintf(stderr, "%s\n", vsv_uamiv_error(u));
        return 1;
    }
    const vsv_uamiv_header *h = vsv_uamiv_header_get(u);
    int nc, d[4], *v = calloc((size_t)h->nspec, sizeof *v);
    nc_create(argv[2], NC_CLOBBER | NC_64BIT_OFFSET, &nc);
    nc_def_dim(nc, "TSTEP", (size_t)h->nhours, &d[0]);
    nc_def_dim(nc, "LAY", (size_t)h->nz, &d[1]);
    nc_def_dim(nc, "ROW", (size_t)h->ny, &d[2]);
    nc_def_dim(nc, "COL", (size_t)h->nx, &d[3]);
    for (int s = 0; s < h->nspec; s++)
        nc_def_var(nc, h->species[s], NC_FLOAT, 4, d, &v[s]);
    nc_enddef(nc);
    float *plane = malloc((size_t)h->nx * h->ny * sizeof *plane);
    for (int t = 0; t < h->nhours; t++)
        for (int s = 0; s < h->nspec; s++)
            for (int k = 0; k < h->nz; k++) {
                vsv_uamiv_read(u, t, s, k, plane);
                size_t st[4] = {(size_t)t, (size_t)k, 0, 0}, ct[4] = {1, 1, (size_t)h->ny, (size_t)h->nx};
                nc_put_vara_float(nc, v[s], st, ct, plane);
            }
    free(plane);
    free(v);
    vsv_uamiv_free(u);
    return nc_close(nc) ? 1 : 0;
}
