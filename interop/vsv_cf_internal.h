/* vsv_cf_internal.h — what interop/ keeps to itself of the netCDF export:
 * the writing proper, which runs in the private helper program
 * vsv-nc-writer (interop/vsv-nc-writer.c) so that libhdf5 crashing on a
 * failed write (a full disk: it did, in H5Fflush and in libnetcdf's close
 * after it) kills that process, not the tool (vsv_cfwrite.c). */
#ifndef VSV_CF_INTERNAL_H
#define VSV_CF_INTERNAL_H

#include "vsv_cf.h"

/* Writes the netCDF file (vsv_cf_write's layout and arguments) to target,
 * created or truncated by name; messages name path. On failure the file is
 * left open inside libnetcdf: the process must then end without exit
 * handlers (_exit). 0 or a negative VSV_E* code with err set. */
int vsv_cf_write_here(const char *target, const char *path, vsv_file *f, const int *sel, int n, int a, int b,
                      const char *history, void (*progress)(void *ctx, int done, int total), void *ctx, char *err,
                      size_t cap);

/* The helper: `vsv-nc-writer PARENT-PID SRC.vsv NAME A B SEL,... [HISTORY]`
 * writes to descriptor 3, its progress and error on stdout. The exit
 * status. */
int vsv_cf_helper_main(int argc, char **argv);

#endif
