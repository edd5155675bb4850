/* vsv_cf.h — a .vsv out as one CF-1.8 netCDF-4 file (interop/vsv_cfout.c),
 * which xarray, ncview, Panoply, CDO and NCL read, and which vsv-extract
 * reads back (convert/vsv_cf.c).
 *
 * Layout: dimensions time, z, y, x; coordinate variables time ("seconds
 * since" the first step, int64), z (heights in metres with standard_name
 * altitude, or height where the file's heights count from the ground
 * (vsv_meta_above_ground), or the level coordinate), y and x (projected metres, or degrees
 * for lat/lon grids); 2-D auxiliary coordinates lat(y, x), lon(y, x); a
 * scalar `crs` grid_mapping variable (lambert_conformal_conic,
 * polar_stereographic, mercator, transverse_mercator,
 * albers_conical_equal_area or latitude_longitude, on a sphere:
 * earth_radius; false easting/northing place the file's own origin);
 * terrain(y, x) as surface_altitude; one float variable per species on
 * (time, z, y, x) with units, long_name, coordinates "lat lon",
 * grid_mapping "crs", the quantisation bound as `vsv_max_abs_error`,
 * units as UDUNITS spells them and standard names where the species is a
 * CF quantity (vsv_cf_names.c), and _FillValue NaN (no data: the
 * species' own, and every cell below the ground). Native model levels
 * with per-column heights (SPEC.md "HGTS") add height(time, z, y, x), the
 * altitude of every cell at every step, named in each species'
 * coordinates (z then holds the levels' mean heights). Each variable is
 * chunked by step (1, nz, ny, nx), shuffled and deflated. */
#ifndef VSV_CF_H
#define VSV_CF_H

#include "vsv_format.h"

#ifdef __cplusplus
extern "C" {
#endif

VSV_API_BEGIN

/* Writes steps a..b of species sel[0..n-1] of f, opened from the file src,
 * to path: under a temporary name beside it, renamed into place only when
 * complete (path is never half-written, and an input is never replaced:
 * path must not be src). The netCDF library runs in the private helper
 * program vsv-nc-writer (found as vsv-nc-check is), which opens src again:
 * a library crash (libhdf5 on a full disk) is an error, not the caller's
 * end. history is stored as the global "history" (may be NULL). progress
 * (may be NULL) gets (done, total) steps. 0, or a negative VSV_E* code with
 * the reason in err (cap bytes). */
int vsv_cf_write(const char *path, const char *src, vsv_file *f, const int *sel, int n, int a, int b,
                 const char *history, void (*progress)(void *ctx, int done, int total), void *ctx, char *err,
                 size_t cap);

VSV_API_END

#ifdef __cplusplus
}
#endif

#endif
