/* vsv_vdb.h — OpenVDB in and out, through a thin C++ shim over libopenvdb
 * (interop/vsv_vdb.cc); everything else stays C.
 *
 * Out: one .vdb per time step, one FloatGrid per species named after it, in
 * world units: index (i, j, k) sits at (x0 + i dx, y0 + j dy, z0 + k dz) —
 * projected metres and height above sea level, not exaggerated — through a
 * scale-and-translate transform. Only cells holding something are active
 * (EMPTY bricks, code-0 cells and no-data cells stay inactive; the background
 * is 0). Metadata: per grid "units", "description"; per file "time" (ISO
 * 8601), "source_model", "run", "projection" (name and parameters),
 * "vertical" (even or native levels). Written under a temporary name and
 * renamed.
 *
 * In: a sequence of .vdb files (one time step each) read as one grid: the
 * union of every file's active bounding box at their shared voxel size,
 * float grids by name (a grid missing from a file reads as 0). */
#ifndef VSV_VDB_H
#define VSV_VDB_H

#include "vsv_format.h"

#ifdef __cplusplus
extern "C" {
#endif

VSV_API_BEGIN

/* Writes species[0..n-1] (decoded volumes of m's grid at model time t) to
 * path. 0, or -1 with the reason in err. */
int vsv_vdb_write(const char *path, const vsv_meta *m, int64_t t, const vsv_volume *const *vols, int n, char *err,
                  size_t cap);

/* 1 if the bytes start like an OpenVDB file. */
int vsv_vdb_probe(const unsigned char *head, size_t n);

/* What a sequence of .vdb files holds. */
typedef struct vsv_vdb_info {
    int nx, ny, nz;
    int64_t imin[3];  /* index of cell (0, 0, 0) */
    double origin[3]; /* world position of cell (0, 0, 0) */
    double voxel[3];  /* voxel size */
    int ngrids;
    char (*names)[64]; /* float grids, in the first file's order */
    char (*units)[64];
    int64_t *times; /* per file: "time" metadata, or INT64_MIN */
    char model[64];
    char projection[256]; /* "projection" metadata of the first file, or "" */
} vsv_vdb_info;

/* Scans paths[0..n-1] (metadata only where the files carry their bounding
 * boxes). 0, or -1 with the reason in err ("FILE: what"). */
int vsv_vdb_scan(const char *const *paths, int n, vsv_vdb_info *info, char *err, size_t cap);
void vsv_vdb_info_free(vsv_vdb_info *info);
/* Reads grid `name` of path onto info's grid (nx*ny*nz floats, x fastest;
 * inactive cells hold the grid's background). 0, or -1 with err. */
int vsv_vdb_read(const char *path, const char *name, const vsv_vdb_info *info, float *out, char *err, size_t cap);

/* Makes .vdb sequences a source that vsv_source_open (convert/vsv_convert.h)
 * reads: each file one time step, every float grid a field. Call once before
 * opening sources, from one thread; 0 or VSV_EINVAL. */
int vsv_vdb_source_register(void);

VSV_API_END

#ifdef __cplusplus
}
#endif

#endif
