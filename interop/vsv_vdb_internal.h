/* vsv_vdb_internal.h — what interop/ keeps to itself: the private helper
 * program vsv-vdb-reader (interop/vsv-vdb-reader.c), the one process that
 * loads OpenVDB: it reads .vdb files for vsv_vdb_scan and vsv_vdb_read and
 * writes them for vsv_vdb_write (the callers' side: vsv_vdb_isolate.cc; the
 * helper's: vsv_vdb_helper.cc; the OpenVDB calls: vsv_vdb.cc), so that no
 * tool links libopenvdb and its logging library (which aborts before main
 * under a small address-space limit) and a damaged file that crashes it
 * kills the helper, not the tool. They talk through shared memory laid out
 * as below. */
#ifndef VSV_VDB_INTERNAL_H
#define VSV_VDB_INTERNAL_H

#include "vsv_vdb.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The helper: `vsv-vdb-reader scan|read|write MEMORY` with the shared
 * memory as descriptor 3 and, for read, its requests on stdin and replies
 * on stdout. The exit status. */
int vsv_vdb_helper_main(int argc, char **argv);

#ifdef __cplusplus
}

#include <cstdint>
#include <cstring>
#include <sys/stat.h>

/* The OpenVDB calls themselves (vsv_vdb.cc); only the helper makes them. */
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

namespace vsv_vdb_shm
{

/* The head of every exchange: scan's results (then MAXG names and units,
 * the files' times and their paths), read's status. */
struct head {
    int rc, nx, ny, nz, ngrids, nfiles;
    int64_t imin[3];
    double origin[3], voxel[3];
    char model[64], projection[256], err[1024];
};

/* The request the reader finds after the head before a byte on its socket;
 * the `count` grid names follow it, then their statuses, then the floats. */
struct read_request {
    char path[4096];
    int first, count, nx, ny, nz;
    int64_t imin[3];
};

enum { MAXG = 1024 };

/* Where the parts of a read request lie. */
struct read_layout {
    read_request *rq = nullptr;
    char (*names)[64] = nullptr;
    vsv_vdb_grid_status *st = nullptr;
    float *data = nullptr;
};

inline size_t read_head_bytes(int count)
{
    return sizeof(head) + sizeof(read_request) + (size_t)count * (64 + sizeof(vsv_vdb_grid_status));
}

inline read_layout read_parts(void *m, int count)
{
    read_layout l;
    char *p = static_cast<char *>(m) + sizeof(head);
    l.rq = reinterpret_cast<read_request *>(p);
    p += sizeof(read_request);
    l.names = reinterpret_cast<char(*)[64]>(p);
    p += (size_t)count * 64;
    l.st = reinterpret_cast<vsv_vdb_grid_status *>(p);
    l.data = reinterpret_cast<float *>(static_cast<char *>(m) + read_head_bytes(count));
    return l;
}

/* A write request, sent on the helper's stdin: this, then `ngrids` grid
 * records, then their values, nx * ny * nz floats each (x fastest; NaN: an
 * inactive cell), in a stream, so that no file size or address-space limit
 * on shared memory stands between the tool and the helper. The helper
 * writes the file `path` (which the caller made and listed; the helper
 * never creates a file) and answers with a write_reply on its stdout (err:
 * "cannot write: ...", "OpenVDB: ...", without the path). */
struct write_request {
    char path[4200];
    int nx, ny, nz, ngrids;
    double origin[3], spacing[3]; /* world position of cell (0, 0, 0), cell size */
    char time[64], model[64], run[256], projection[256], vertical[64];
};
struct write_grid {
    char name[64], units[64], description[128];
};
struct write_reply {
    int rc;
    char err[1024];
};

/* Seconds a helper may spend on `input` bytes: 20, plus one per 4 MB
 * (OpenVDB reads ~100 MB/s). */
inline unsigned time_limit(uint64_t input) { return 20u + (unsigned)(input / (4u << 20)); }

/* Total size of the files (what a helper reads). */
inline uint64_t input_bytes(const char *const *paths, int n)
{
    uint64_t t = 0;
    for (int i = 0; i < n; i++) {
        struct stat st;
        if (stat(paths[i], &st) == 0)
            t += (uint64_t)st.st_size;
    }
    return t;
}

} // namespace vsv_vdb_shm

/* Writes a .vdb from a write request (the helper's side of vsv_vdb_write):
 * 0, or -1 with the reason in err (cap bytes). */
int vsv_vdb_write_here(const vsv_vdb_shm::write_request *rq, const vsv_vdb_shm::write_grid *grids, const float *values,
                       char *err, size_t cap);
#endif

#endif
