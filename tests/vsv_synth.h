/* vsv_synth.h — deterministic synthetic time series for the tests: moving
 * plumes (sparse, like cloud water), a smooth dense field (like temperature)
 * and a field spanning decades (like ozone), written through the library. */
#ifndef VSV_SYNTH_H
#define VSV_SYNTH_H

#include "vsv_format.h"

typedef struct synth {
    int nx, ny, nz, nsteps;
    int frozen_from, frozen_to; /* species 2 is constant over these steps */
} synth;

/* Value of species s at cell (i,j,k), step t. */
float synth_value(const synth *sy, int s, int t, int i, int j, int k);
/* Fills meta (initialised by the caller) with the grid and 3 species. */
void synth_meta(const synth *sy, vsv_meta *m);
/* Writes the series to path with opts (vars may be NULL); 0 or error. */
int synth_write(const synth *sy, const char *path, const vsv_pack_opts *opts, char *err, size_t cap);
/* The same, with the statistics given to the writer in advance from a
 * first pass (vsv_writer_expect), false ones when lie is set. */
int synth_write_planned(const synth *sy, const char *path, const vsv_pack_opts *opts, int lie, char *err, size_t cap);
/* A file of one wind everywhere (tests of trajectories and of the wind
 * drawn): an even grid (Lambert conformal centred on 40 N 100 W, true at
 * lat1 and lat2; flat: projection none), cells of dxy metres from
 * projected (x0, y0), levels dz apart from z0, hourly steps from t0, a
 * species of zeros first (scalar, with its units; NULL: none), then the
 * three wind species (east, north, up = wind; vector 1: the vector species
 * wind, 0: the species without the attribute, -1: no wind species). */
typedef struct synth_wind {
    int nx, ny, nz, nsteps;
    double dxy, dz, x0, y0, z0, lat1, lat2;
    int flat;
    int64_t t0;
    float wind[3];
    int vector;
    const char *scalar, *units;
} synth_wind;
/* The one the wind's drawing tests use: 40 x 30 x 10 cells of 2 km, levels
 * every 1 km from 500 m, true at 40 N (so a metre east along it is a
 * projected metre; cell (20, 15) is at 40 N 100 W, projected (0, 0)), four
 * steps from 2000-01-01T00Z, CLW (zeros) and the vector wind. */
void synth_wind_uniform(synth_wind *w, float east, float north, float up);
/* Writes it to path: 0 or an error (err says why). */
int synth_wind_write(const char *path, const synth_wind *w, char *err, size_t cap);
/* Time of step t. */
int64_t synth_time(int t);

#endif
