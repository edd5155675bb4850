/* vsv_vdb_internal.h — what interop/ keeps to itself: the body of the
 * private helper program vsv-vdb-reader (interop/vsv-vdb-reader.c), which
 * reads .vdb files for vsv_vdb_scan and vsv_vdb_read in a process of its
 * own (vsv_vdb.cc). */
#ifndef VSV_VDB_INTERNAL_H
#define VSV_VDB_INTERNAL_H

#include "vsv_vdb.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The helper: `vsv-vdb-reader scan|read MEMORY` with the shared memory as
 * descriptor 3 and, for read, its requests on stdin and replies on stdout.
 * The exit status. */
int vsv_vdb_helper_main(int argc, char **argv);

#ifdef __cplusplus
}

/* The OpenVDB calls themselves, in the calling process (vsv_vdb.cc); only
 * the helper makes them. */
struct vsv_vdb_grid_status {
    int rc;
    char err[252];
};
/* vsv_vdb_scan's work: 0, or -1 with err. */
int vsv_vdb_scan_here(const char *const *paths, int n, vsv_vdb_info *info, char *err, size_t cap);
/* `count` grids (names) of one file onto info's lattice: out holds them one
 * after the other, st one status per grid. 0 when the file opened (each grid
 * then has its own status), else -1 with the reason in st[0]. */
int vsv_vdb_read_here(const char *path, const vsv_vdb_info *info, const char (*names)[64], int count, float *out,
                      vsv_vdb_grid_status *st);
#endif

#endif
