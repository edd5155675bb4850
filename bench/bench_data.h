/* bench_data.h — the benchmarks' data sets held in memory: a model file's
 * fields read through the converter's source (the species a conversion
 * takes by default, or named ones) or one of gen-plume's raw volumes. */
#ifndef BENCH_DATA_H
#define BENCH_DATA_H

#include "vsv_convert.h"
#include "vsv_format.h"

#include <stddef.h>

typedef struct bench_data {
    const char *name;
    vsv_meta meta; /* the grid and the species, no terrain or land use */
    int nt, nv;
    float *data; /* nt * nv * cells, step-major */
} bench_data;

static inline size_t bench_cells(const bench_data *d) { return (size_t)d->meta.nx * d->meta.ny * d->meta.nz; }
static inline float *bench_field(const bench_data *d, int t, int v)
{
    return d->data + ((size_t)t * d->nv + v) * bench_cells(d);
}

/* Reads path (vsv_source_open's defaults: native levels) into d: vars[0..nv)
 * or, with vars NULL, every field the source extracts by default. The
 * terrain, land use, per-column heights and placements a .vsv also carries
 * are dropped: the peers' files hold the species only. 0, or -1 with the
 * reason printed. Free with bench_data_free. */
int bench_data_source(bench_data *d, const char *name, const char *path, const char *const *vars, int nv);
/* Reads gen-plume's 256x256x64 floats: the files dir/names[0..nt). */
int bench_data_plume(bench_data *d, const char *name, const char *dir, const char *const *names, int nt);
/* Writes the species [v0, v1) of d as a .vsv at path, step t at t hours
 * (predict: format 2's predictive kinds, else 1.x). 0, or non-zero with
 * the reason printed. */
int bench_data_write(const bench_data *d, int v0, int v1, int predict, const char *path);
void bench_data_free(bench_data *d);

#endif
