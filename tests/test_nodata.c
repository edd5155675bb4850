/* test_nodata.c — no data in a species whose smallest value is 0 (a
 * concentration, a height from 0): where the grid cannot place it, code 0
 * must mean no data (SPEC.md §6), else the cells read as 0. The rest of
 * the format's round trips: test_format.c. */
#include "vsv_format_internal.h"
#include "vsv_testlib.h"

#include <math.h>
#include <stdlib.h>

/* Writes one step of species "conc" (values v, n cells) on grid m; its
 * file open in *f and decoded into out. 0 or an error code. */
static int one_step(vsv_meta *m, const char *name, const float *v, vsv_file **f, float *out)
{
    const char *path = vsv_test_tmp(name);
    vsv_writer *w = NULL;
    const float *fl[1] = {v};
    int rc = vsv_writer_create(path, m, NULL, &w);
    if (!rc)
        rc = vsv_writer_add_step(w, 0, fl);
    if (!rc)
        rc = vsv_writer_finish(w, NULL, NULL);
    vsv_writer_free(w);
    vsv_decoder *d = NULL;
    if (!rc && !(rc = vsv_file_open(path, f)) && !(rc = vsv_decoder_create(*f, &d)))
        rc = vsv_decoder_volume(d, 0, 0, out);
    vsv_decoder_free(d);
    return rc;
}

/* No data in a species whose smallest value is 0 (a concentration): where
 * the grid cannot place it (no terrain, or not below it) code 0 must mean
 * no data, or the cells read as 0 (a CF fill value, REGRID's levels under
 * the ground read 0); below the ground of even heights over a terrain
 * zeros and no data share code 0, so zero bricks stay empty. */
static void test_no_data_zero_floor(void)
{
    enum { NX = 12, NY = 10, NZ = 6 };
    const size_t n = (size_t)NX * NY * NZ;
    vsv_meta m;
    vsv_meta_init(&m);
    m.nx = NX, m.ny = NY, m.nz = NZ;
    m.spacing[0] = m.spacing[1] = 1000, m.spacing[2] = 250;
    m.origin[2] = 125;
    vsv_meta_add_var(&m, "conc", "ppb", "0 at its least");
    float *v = malloc(n * sizeof *v), *out = malloc(n * sizeof *out);
    for (size_t c = 0; c < n; c++)
        v[c] = c % 5 == 1 ? NAN : (float)(c % 3);
    vsv_file *f = NULL;
    int rc = one_step(&m, "nodata0.vsv", v, &f, out), ok = !rc;
    for (size_t c = 0; c < n && ok; c++)
        ok &= c % 5 == 1 ? isnan(out[c]) : fabsf(out[c] - v[c]) <= vsv_file_quant(f, 0)->max_abs_error;
    CHECK(ok, "no terrain: no-data cells of a 0-floored species read NaN, zeros 0", "rc %d", rc);
    vsv_file_free(f);
    f = NULL;
    /* over a terrain, no data below the ground only: code 0 shared */
    vsv_meta_alloc_terrain(&m);
    for (int c = 0; c < NX * NY; c++)
        m.terrain[c] = (float)(100 * (c % NX)); /* 0 .. 1100 m */
    for (size_t c = 0; c < n; c++) {
        const int i = (int)(c % NX), k = (int)(c / (NX * NY));
        v[c] = 125.0 + 250.0 * k < 100.0 * i ? NAN : (float)(c % 3);
    }
    rc = one_step(&m, "nodata1.vsv", v, &f, out);
    ok = !rc && !vsv_file_quant(f, 0)->missing;
    for (size_t c = 0; c < n && ok; c++)
        ok &= isnan(v[c]) ? isnan(out[c]) : fabsf(out[c] - v[c]) <= vsv_file_quant(f, 0)->max_abs_error;
    CHECK(ok, "over a terrain, no data below the ground alone: code 0 shared, those cells NaN", "rc %d", rc);
    vsv_file_free(f);
    vsv_meta_clear(&m);
    free(v);
    free(out);
}

int main(void)
{
    test_no_data_zero_floor();
    return vsv_test_done();
}
