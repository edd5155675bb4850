/* vsv_source_internal.h — what a model reader implements. Private. */
#ifndef VSV_SOURCE_INTERNAL_H
#define VSV_SOURCE_INTERNAL_H

#include "vsv_convert.h"
#include "vsv_format_internal.h"

typedef struct vsv_source_ops {
    const char *name;
    /* 1 if the first n bytes look like this format */
    int (*probe)(const unsigned char *head, size_t n);
    int (*open)(vsv_source *s);
    int (*read)(vsv_source *s, int field, int t, float *out);
    void (*close)(vsv_source *s);
    char *(*summary)(vsv_source *s); /* may be NULL */
    /* --vertical native only: the levels' heights at time t per column
     * (nx*ny*nz, m above sea level); may be NULL (no per-column heights) */
    int (*heights)(vsv_source *s, int t, float *out);
} vsv_source_ops;

struct vsv_source {
    const vsv_source_ops *ops;
    char path[1024];
    char err[512];
    vsv_meta grid;
    vsv_field_info *fields;
    int nfields;
    int64_t *times;
    int ntimes;
    vsv_source_opts opts;
    void *priv;
};

/* Sets s->err to "path: message" and returns rc. */
int vsv_source_fail(vsv_source *s, int rc, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

/* Sets the grid's vertical axis from native heights zn (kx levels of the
 * grid's plane, increasing upward): --vertical native keeps the levels with
 * their mean heights (returns 0); else even heights up to --ztop or the
 * highest top-level height rounded up to round_to metres (returns 1). */
int vsv_source_axis(vsv_source *s, const float *zn, int kx, double round_to);

/* --vertical native: records the heights zn (the grid's nz levels of its
 * plane, increasing upward, m above sea level) in force from time t on,
 * unless they are within half a metre of the last ones recorded. 0 or error. */
int vsv_source_native_heights(vsv_source *s, int t, const float *zn);

extern const vsv_source_ops vsv_grads_ops;
extern const vsv_source_ops vsv_mm5_ops;
extern const vsv_source_ops vsv_netcdf_ops;
extern const vsv_source_ops vsv_camx_ops;
extern const vsv_source_ops vsv_ioapi_ops;
extern const vsv_source_ops vsv_vdb_ops;
/* Reads time t of netCDF variable var (named name in errors) whose last n
 * dimensions are shape[0..n-1], after at most one leading (time) dimension:
 * prod(shape) floats into out (caller buffer of that many). Nothing is read
 * unless the variable has exactly that shape; the error names the variable
 * and both shapes. */
int vsv_nc_read(vsv_source *s, int nc, int var, const char *name, int t, const size_t *shape, int n, float *out);
/* CF netCDF (convert/vsv_cf.c): 1 if the open file nc says Conventions
 * "CF-…"; the open of such a file (detected by vsv_netcdf_ops). */
extern const vsv_source_ops vsv_cf_ops;
int vsv_cf_detect(int nc);
int vsv_cf_open(vsv_source *s, int nc);
/* Opens an IOAPI netCDF file already open as nc (detected by vsv_netcdf_ops). */
int vsv_ioapi_open(vsv_source *s, int nc);

#endif
