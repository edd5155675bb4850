/* vsv_advect.h — interpolation in time along the model's winds
 * (--interp advect): a frame between two outputs is the blend of the earlier
 * output carried forward and the later one carried back along
 * semi-Lagrangian trajectories through the 3-D wind. Private to convert/;
 * vsv_interp drives it. */
#ifndef VSV_ADVECT_H
#define VSV_ADVECT_H

#include "vsv_format.h"

typedef struct vsv_advect vsv_advect;

/* For the grid of `grid` (nx, ny, nz, origin, spacing, projection, vertical
 * axis; borrowed for the call only). threads: workers a frame uses, 0 = one
 * per online CPU. Caller frees with vsv_advect_free. 0 or VSV_ENOMEM. */
int vsv_advect_create(const vsv_meta *grid, int threads, vsv_advect **out);
/* 1 if the vertical axis gives vertical motion a length (even heights or
 * native levels with heights); 0 when W is ignored (layer index, pressure). */
int vsv_advect_has_vertical(const vsv_advect *a);
/* The winds at the two ends of the interval: u0, v0 (and w0, or NULL for no
 * vertical motion) at its start, u1, v1, w1 at its end; m/s, u and v along
 * the grid's x and y axes, w upward. NaN (below ground) counts as calm. */
void vsv_advect_winds(vsv_advect *a, const float *u0, const float *v0, const float *w0, const float *u1,
                      const float *v1, const float *w1);
/* The interval's two outputs: ns fields f0[s] at its start, f1[s] at its
 * end, nx*ny*nz floats each (borrowed: they and their contents must stay
 * until the next call or vsv_advect_free). Notes where each is all zero
 * (samples there are skipped). 0 or VSV_ENOMEM. */
int vsv_advect_outputs(vsv_advect *a, int ns, const float *const *f0, const float *const *f1);
/* out[s] (caller buffers of nx*ny*nz floats) for the ns fields of the
 * outputs last given, at time t of
 * [t0, t1]: (float)(A + (B - A) * w), w = (t - t0) / (t1 - t0) in double,
 * A = f0[s] at the point whose trajectory reaches the cell at t, B = f1[s] at
 * the point the trajectory reaches at t1 (the displacements to those points,
 * traced from every second column and row and interpolated between, times
 * the species' scale: see vsv_advect_set_scale), each sampled trilinearly from the 8
 * cells around it (cells without data skipped) and clamped to their range.
 * NaN where f0 or f1 is NaN at the cell itself (as linear interpolation).
 * Uses the winds last given. Threads that cannot start leave their share
 * to the caller's thread. Returns 0. */
int vsv_advect_frame(vsv_advect *a, int64_t t0, int64_t t1, int64_t t, float *const *out);
/* scale > 0: every species moves with the wind times scale (1: as the air
 * moves); 0 (the default): with the scales vsv_advect_fit found. */
void vsv_advect_set_scale(vsv_advect *a, float scale);
/* With scale 0: fits the scales of the interval [t0, t1] from its two
 * outputs (vsv_advect_outputs) and the winds last given: per species and band of levels (an
 * eighth of the grid's, at least 2) the one of 0, 1/8, ..., 5/4 under
 * which the earlier output carried to t1 matches the later one and the
 * later carried back to t0 the earlier one best (least squares, every
 * third column each way). Returns 0. */
int vsv_advect_fit(vsv_advect *a, int64_t t0, int64_t t1);
/* The scales last fitted: species v, band b at [v * nband + b]. */
const float *vsv_advect_scales(const vsv_advect *a, int *nband);
void vsv_advect_free(vsv_advect *a);

#endif
