/* vsv_synth.c — see vsv_synth.h. */
#include "vsv_synth.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int64_t synth_time(int t) { return 1000000000LL + 600LL * t; }

float synth_value(const synth *sy, int s, int t, int i, int j, int k)
{
    if (s == 2 && t >= sy->frozen_from && t <= sy->frozen_to)
        t = sy->frozen_from;
    const double x = (double)i / sy->nx, y = (double)j / sy->ny, z = (double)k / sy->nz;
    if (s == 0) {
        /* two plumes drifting east and north; exactly 0 far from them */
        double v = 0;
        for (int p = 0; p < 2; p++) {
            double cx = fmod(0.2 + 0.004 * t * (p ? 1 : 1.5), 1.0), cy = 0.3 + 0.4 * p + 0.002 * t, cz = 0.4 + 0.1 * p;
            double r2 = ((x - cx) * (x - cx) + (y - cy) * (y - cy)) / 0.01 + (z - cz) * (z - cz) / 0.04;
            if (r2 < 4)
                v += 6e-4 * exp(-r2) * (1 + 0.2 * sin(0.3 * t + p));
        }
        return v < 1e-7 ? 0.0f : (float)v;
    }
    if (s == 1)
        return (float)(290 - 60 * z + 5 * sin(6.283 * x + 0.05 * t) * cos(3.1 * y));
    /* species 2: positive everywhere, five decades */
    return (float)(1e-6 * pow(10.0, 5 * (0.5 + 0.5 * sin(4 * x + 3 * y + 0.1 * t) * cos(2 * z))));
}

void synth_meta(const synth *sy, vsv_meta *m)
{
    m->nx = sy->nx;
    m->ny = sy->ny;
    m->nz = sy->nz;
    m->origin[0] = -1000e3;
    m->origin[1] = -800e3;
    m->origin[2] = 50;
    m->spacing[0] = m->spacing[1] = 30e3;
    m->spacing[2] = 500;
    m->vert_kind = VSV_VERT_EVEN;
    m->proj = (vsv_proj){VSV_PROJ_LCC, 38, -97, 30, 60, 6370000};
    snprintf(m->model, sizeof m->model, "synthetic");
    snprintf(m->run, sizeof m->run, "moving plumes for the tests");
    vsv_meta_add_attr(m, "PTOP", "10000 Pa");
    vsv_meta_add_var(m, "CLW", "kg/kg", "cloud water mixing ratio");
    vsv_meta_add_var(m, "T", "K", "temperature");
    vsv_meta_add_var(m, "O3", "ppm", "ozone");
    vsv_meta_alloc_terrain(m);
    for (int j = 0; j < sy->ny; j++)
        for (int i = 0; i < sy->nx; i++)
            /* a slope of 0..40 m, under the lowest level's centre (50 m):
             * every cell holds data (none is below the ground, SPEC.md) */
            m->terrain[(size_t)j * sy->nx + i] = (float)(40.0 * (i + j) / (sy->nx + sy->ny));
}

/* The three species at step t into f. */
static void synth_fill(const synth *sy, int t, float *const *f)
{
    for (int s = 0; s < 3; s++)
        for (int k = 0; k < sy->nz; k++)
            for (int j = 0; j < sy->ny; j++)
                for (int i = 0; i < sy->nx; i++)
                    f[s][((size_t)k * sy->ny + j) * sy->nx + i] = synth_value(sy, s, t, i, j, k);
}

static int write_series(const synth *sy, const char *path, const vsv_pack_opts *opts, int planned, char *err,
                        size_t cap)
{
    vsv_meta m;
    vsv_meta_init(&m);
    synth_meta(sy, &m);
    vsv_writer *w = NULL;
    const size_t cells = (size_t)sy->nx * sy->ny * sy->nz;
    float *f[3] = {malloc(cells * 4), malloc(cells * 4), malloc(cells * 4)};
    int rc = vsv_writer_create(path, &m, opts, &w);
    if (!rc && planned) { /* a first pass for the statistics (a wrong one when planned is 2) */
        vsv_pack_stats st[3];
        vsv_pack_stats_init(st, 3);
        for (int t = 0; t < sy->nsteps; t++) {
            synth_fill(sy, t, f);
            vsv_pack_stats_add(st, 3, cells, (const float *const *)f);
        }
        if (planned == 2)
            st[1].max += 1;
        rc = vsv_writer_expect(w, st);
    }
    for (int t = 0; !rc && t < sy->nsteps; t++) {
        synth_fill(sy, t, f);
        rc = vsv_writer_add_step(w, synth_time(t), (const float *const *)f);
    }
    if (!rc)
        rc = vsv_writer_finish(w, NULL, NULL);
    if (rc)
        snprintf(err, cap, "%s", vsv_writer_error(w));
    vsv_writer_free(w);
    vsv_meta_clear(&m);
    for (int s = 0; s < 3; s++)
        free(f[s]);
    return rc;
}

int synth_write(const synth *sy, const char *path, const vsv_pack_opts *opts, char *err, size_t cap)
{
    return write_series(sy, path, opts, 0, err, cap);
}

int synth_write_planned(const synth *sy, const char *path, const vsv_pack_opts *opts, int lie, char *err, size_t cap)
{
    return write_series(sy, path, opts, lie ? 2 : 1, err, cap);
}

void synth_wind_uniform(synth_wind *w, float east, float north, float up)
{
    *w = (synth_wind){.nx = 40,
                      .ny = 30,
                      .nz = 10,
                      .nsteps = 4,
                      .dxy = 2000,
                      .dz = 1000,
                      .x0 = -40000,
                      .y0 = -30000,
                      .z0 = 500,
                      .lat1 = 40,
                      .lat2 = 40,
                      .t0 = 946684800,
                      .wind = {east, north, up},
                      .vector = 1,
                      .scalar = "CLW",
                      .units = "kg/kg"};
}

int synth_wind_write(const char *path, const synth_wind *sw, char *err, size_t cap)
{
    vsv_meta m;
    vsv_meta_init(&m);
    m.nx = sw->nx, m.ny = sw->ny, m.nz = sw->nz;
    m.spacing[0] = m.spacing[1] = sw->dxy, m.spacing[2] = sw->dz;
    m.origin[0] = sw->x0, m.origin[1] = sw->y0, m.origin[2] = sw->z0;
    m.vert_kind = VSV_VERT_EVEN;
    if (!sw->flat)
        m.proj = (vsv_proj){VSV_PROJ_LCC, 40, -100, sw->lat1, sw->lat2, 0};
    snprintf(m.model, sizeof m.model, "test");
    int nf = 0;
    if (sw->scalar)
        vsv_meta_add_var(&m, sw->scalar, sw->units, "zeros"), nf++;
    if (sw->vector >= 0) {
        vsv_meta_add_var(&m, VSV_WIND_EAST, "m s-1", "eastward wind");
        vsv_meta_add_var(&m, VSV_WIND_NORTH, "m s-1", "northward wind");
        vsv_meta_add_var(&m, VSV_WIND_UP, "m s-1", "upward wind");
        nf += 3;
    }
    if (sw->vector > 0)
        vsv_meta_add_attr(&m, VSV_VECTOR_ATTR VSV_WIND, VSV_WIND_EAST " " VSV_WIND_NORTH " " VSV_WIND_UP);
    const size_t cells = (size_t)m.nx * m.ny * m.nz;
    float *f[4] = {NULL, NULL, NULL, NULL};
    int rc = 0;
    for (int s = 0; s < nf && !rc; s++) {
        const float v = s < nf - 3 || sw->vector < 0 ? 0 : sw->wind[s - (nf - 3)];
        if (!(f[s] = malloc(cells * sizeof(float))))
            rc = VSV_ENOMEM;
        for (size_t c = 0; f[s] && c < cells; c++)
            f[s][c] = v;
    }
    vsv_writer *wr = NULL;
    if (!rc)
        rc = vsv_writer_create(path, &m, NULL, &wr);
    for (int t = 0; !rc && t < sw->nsteps; t++)
        rc = vsv_writer_add_step(wr, sw->t0 + 3600 * t, (const float *const *)f);
    if (!rc)
        rc = vsv_writer_finish(wr, NULL, NULL);
    if (rc)
        snprintf(err, cap, "%s: %s", path, wr ? vsv_writer_error(wr) : vsv_strerror(rc));
    vsv_writer_free(wr);
    vsv_meta_clear(&m);
    for (int s = 0; s < 4; s++)
        free(f[s]);
    return rc;
}
