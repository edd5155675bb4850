/* vsv_vgrid.h — resampling model columns onto even heights (DESIGN.md §3):
 * per cell of the even grid, the native level below it and a weight; cells
 * below the ground or above the column's top level hold no data (NaN), cells
 * between the ground and the lowest level take the lowest level's value.
 * Shared by the MM5, WRF and CAMx readers and by the resampler that places
 * native levels at their heights (vsv_heights.c). Private to the library. */
#ifndef VSV_VGRID_H
#define VSV_VGRID_H

#include <stddef.h>
#include <stdint.h>

typedef struct vsv_vgrid {
    int nz, kx;
    size_t plane;
    double z0, dz; /* centre of even level 0, spacing (m) */
    int16_t *lev;  /* nz*plane: native level below, -1 = no data */
    float *wt;     /* nz*plane: weight of the level above */
} vsv_vgrid;

/* Plans the mapping for native heights zn (kx*plane, level-major, increasing
 * upward, same datum as ground and z0) and ground heights (plane, or NULL for
 * none). Reuses the arrays of a previous plan of the same size. 0 or -1. */
int vsv_vgrid_plan(vsv_vgrid *g, const float *zn, int kx, size_t plane, const float *ground, int nz, double z0,
                   double dz);
/* out (nz*plane) from the native volume nat (kx*plane). */
void vsv_vgrid_apply(const vsv_vgrid *g, const float *nat, float *out);
void vsv_vgrid_free(vsv_vgrid *g);

#endif
