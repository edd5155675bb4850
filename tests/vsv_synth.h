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
/* Time of step t. */
int64_t synth_time(int t);

#endif
