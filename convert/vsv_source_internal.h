/* vsv_source_internal.h — what the built-in model readers share beyond
 * vsv_source_reader.h. Private to convert/. */
#ifndef VSV_SOURCE_INTERNAL_H
#define VSV_SOURCE_INTERNAL_H

#include "vsv_common.h"
#include "vsv_source_reader.h"

#include <stdint.h>
#include <stdio.h>

/* Sets the grid's vertical axis from native heights zn (kx levels of the
 * grid's plane, increasing upward): --vertical native keeps the levels with
 * their mean heights (returns 0); else even heights up to --ztop or the
 * highest top-level height rounded up to round_to metres (returns 1). */
int vsv_source_axis(vsv_source *s, const float *zn, int kx, double round_to);

/* --vertical native: records the heights zn (the grid's nz levels of its
 * plane, increasing upward, m above sea level) in force from time t on,
 * unless they are within half a metre of the last ones recorded. 0 or error. */
int vsv_source_native_heights(vsv_source *s, int t, const float *zn);

/* CAMx land use (vsv_camxlu.c): 1 if the first n bytes start like a
 * land-use file; reading one into s->grid's land use (0 or error). */
int vsv_camx_is_landuse(const unsigned char *head, size_t n);
int vsv_camx_landuse(vsv_source *s, const char *path);

/* MM5 sigma files (vsv_mm5_source.c): the full pressure at time t, Pa, on
 * the source's grid like a field: p* sigma + PTOP + PP, p* = PSTARCRS (or
 * from the terrain) of the reference state. VSV_ENOTFOUND in a file without
 * sigma levels, a reference state or PP, or not MM5. */
int vsv_mm5_pressure(vsv_source *s, int t, float *out);
/* The summary of MM5 file m, open as s (IX x JX dot points), for vsv-info
 * (vsv_mm5_summary.c): a string (caller frees with free()), or NULL. */
struct vsv_mm5;
char *vsv_mm5_summary(const vsv_source *s, const struct vsv_mm5 *m, int IX, int JX);

extern const vsv_source_ops vsv_grads_ops;
extern const vsv_source_ops vsv_mm5_ops;
extern const vsv_source_ops vsv_netcdf_ops;
extern const vsv_source_ops vsv_camx_ops;
extern const vsv_source_ops vsv_ioapi_ops;
/* Reads time t of netCDF variable var (named name in errors) whose last n
 * dimensions are shape[0..n-1], after at most one leading (time) dimension:
 * prod(shape) floats into out (caller buffer of that many). Nothing is read
 * unless the variable has exactly that shape; the error names the variable
 * and both shapes. */
int vsv_nc_read(vsv_source *s, int nc, int var, const char *name, int t, const size_t *shape, int n, float *out);
/* The netCDF files the readers hold (vsv_nc_file.c): vsv_nc_open opens
 * s->path with libnetcdf into *nc (0, or an error in s) and remembers its
 * size; vsv_nc_cut(nc) is 1 when the file is shorter now than then (libnetcdf
 * reads past the end as zeros: values read since are not the file's);
 * vsv_nc_close closes it. */
int vsv_nc_open(vsv_source *s, int *nc);
int vsv_nc_cut(int nc);
void vsv_nc_close(int nc);
/* CF netCDF (convert/vsv_cf.c): 1 if the open file nc says Conventions
 * "CF-…"; the open of such a file (detected by vsv_netcdf_ops). */
extern const vsv_source_ops vsv_cf_ops;
int vsv_cf_detect(int nc);
int vsv_cf_open(vsv_source *s, int nc);
/* Opens and reads the netCDF-4/HDF5 file s->path in a child process that may
 * run limit_s seconds: 0 when it read cleanly, else an error in s saying
 * whether the library failed (and where), crashed or ran out of time. */
int vsv_nc_guard(vsv_source *s, int limit_s);
#define VSV_NC_GUARD_LIMIT 600
/* The header of the classic netCDF file (CDF-1, -2, -5) open as fp at its
 * start, size bytes long (vsv_nc_header.c): 0 when every list, name and
 * attribute value it declares lies inside the file; -1 with what and where
 * in msg otherwise; 1 when fp is not a classic netCDF file. */
int vsv_nc_classic_check(FILE *fp, uint64_t size, char *msg, size_t cap);
/* The netCDF-4/HDF5 file open as fp, size bytes long (vsv_nc_hdf5.c): -1
 * with both lengths in msg when it is shorter than its superblock's
 * end-of-file address says; 0 when not (or the superblock is not one this
 * knows); 1 when fp is not an HDF5 file. */
int vsv_nc_hdf5_check(FILE *fp, uint64_t size, char *msg, size_t cap);
/* Opens an IOAPI netCDF file already open as nc (detected by vsv_netcdf_ops). */
int vsv_ioapi_open(vsv_source *s, int nc);

#endif
