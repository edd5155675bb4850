/* test_resample.c — native levels resampled to even heights on load
 * (vsv_resampler, issue #20): the even cells do not depend on how the
 * native volume is bricked. */
#include "vsv_format.h"
#include "vsv_testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* The resampler's even cells do not depend on the brick size: native
 * levels 0-19 lie in three bricks of 8 (the level above a cell's in the
 * brick above, at 7 and 15) and in two of 16; every cell the same float. */
static float resampled_at(int brick, const vsv_meta *m, const float *v, int want_i, int want_j, float *out, int *nz)
{
    vsv_pack_opts o;
    vsv_pack_opts_init(&o);
    o.brick = brick;
    o.threads = 1;
    const char *path = vsv_test_tmp(brick == 8 ? "rs8.vsv" : "rs16.vsv");
    vsv_writer *w = NULL;
    int rc = vsv_writer_create(path, m, &o, &w);
    if (!rc)
        rc = vsv_writer_add_step(w, 0, &v);
    if (!rc)
        rc = vsv_writer_finish(w, NULL, NULL);
    vsv_writer_free(w);
    vsv_file *f = NULL;
    vsv_resampler *rs = NULL;
    vsv_volume *vol = NULL;
    vsv_decoder *dec = NULL;
    const vsv_volume *e = NULL;
    float sum = 0;
    if (!rc && !vsv_file_open(path, &f) && !vsv_resampler_create(vsv_file_meta(f), &rs) &&
        !vsv_volume_create(f, &vol) && !vsv_decoder_create(f, &dec) && !vsv_volume_load(vol, dec, 0, 0) &&
        !vsv_resampler_run(rs, vol, &e)) {
        *nz = e->nz;
        for (int k = 0; k < e->nz; k++) {
            out[k] = vsv_volume_at(e, want_i, want_j, k);
            for (int j = 0; j < m->ny; j++)
                for (int i = 0; i < m->nx; i++)
                    sum += vsv_volume_at(e, i, j, k) * (float)((i + 3 * j + 7 * k) % 5);
        }
    }
    vsv_resampler_free(rs);
    vsv_volume_free(vol);
    vsv_decoder_free(dec);
    vsv_file_free(f);
    unlink(path);
    return sum;
}

static void test_resample_bricks(void)
{
    enum { NX = 20, NY = 18, NZ = 20 };
    const size_t plane = NX * NY;
    vsv_meta m;
    vsv_meta_init(&m);
    m.nx = NX, m.ny = NY, m.nz = NZ;
    m.vert_kind = VSV_VERT_NATIVE;
    m.spacing[0] = m.spacing[1] = 1000;
    vsv_meta_alloc_levels(&m);
    vsv_meta_alloc_terrain(&m);
    for (size_t c = 0; c < plane; c++)
        m.terrain[c] = (float)(60.0 * (double)(c % NX));
    const double mm5[5] = {100000, 290, 50, 0, 10000};
    double sigma[NZ];
    for (int k = 0; k < NZ; k++)
        sigma[k] = 0.995 - 0.049 * k;
    vsv_meta_add_heights(&m, INT64_MIN, NULL, mm5, sigma);
    for (int k = 0; k < NZ; k++)
        m.levels[k] = m.heights[0].z[(size_t)k * plane];
    vsv_meta_add_var(&m, "T", "K", "smooth");
    float *v = malloc(plane * NZ * sizeof *v), a[64], b[64];
    for (size_t c = 0; c < plane * NZ; c++)
        v[c] = (float)(290 - 0.0065 * m.heights[0].z[c] + sin(0.3 * (double)(c % NX)));
    int na = 0, nb = 0;
    const float sa = resampled_at(8, &m, v, 13, 9, a, &na), sb = resampled_at(16, &m, v, 13, 9, b, &nb);
    CHECK(na > 0 && na == nb && sa == sb && !memcmp(a, b, (size_t)na * sizeof *a),
          "resampled: the same even cells from bricks of 8 (levels across bricks) and of 16", "(%d/%d levels, %g %g)",
          na, nb, sa, sb);
    free(v);
    vsv_meta_clear(&m);
}

int main(void)
{
    test_resample_bricks();
    return vsv_test_done();
}
