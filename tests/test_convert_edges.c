/* test_convert_edges.c — the edges of conversion on the real files in
 * ../shared/data: WRF's default fields (QVAPOR), a rotated-pole MAP_PROJ 6
 * refused by name, native level heights that move in time (WRF eta, MM5
 * pressure levels by H) through vsv_source_heights. */
#include "vsv_convert.h"
#include "vsv_format.h"
#include "vsv_testlib.h"

#include <math.h>
#include <netcdf.h>
#include <stdlib.h>
#include <string.h>

static void test_wrf_default(void)
{
    vsv_source *s = NULL;
    int rc = vsv_source_open(vsv_test_shared("wrf/wrf_cropped.nc"), NULL, &s);
    const int f = rc ? -1 : vsv_source_find_field(s, "QVAPOR");
    CHECK(f >= 0 && vsv_source_field(s, f)->is_default,
          "WRF: QVAPOR is a default field (wrf_cropped.nc has no hydrometeors)", "(%s)", vsv_source_error(s));
    vsv_source_free(s);
    vsv_run *r = NULL;
    const char *paths[] = {vsv_test_shared("wrf/wrf_cropped.nc")};
    rc = vsv_run_open(paths, 1, NULL, NULL, NULL, &r);
    CHECK(rc == 0 && vsv_run_meta(r)->nvars == 1 && !strcmp(vsv_run_meta(r)->vars[0].name, "QVAPOR"),
          "wrf_cropped.nc converts by default (QVAPOR)", "(%s)", vsv_run_error(r));
    vsv_run_free(r);
}

static void test_rotated_pole(void)
{
    /* a copy of a real wrfout told it is a rotated-pole lat/lon grid */
    size_t n;
    unsigned char *d = vsv_test_slurp(vsv_test_shared("wrf/wrf_cropped.nc"), &n);
    const char *path = vsv_test_tmp("rotated.nc");
    int nc, ok = d && !vsv_test_write(path, d, n) && !nc_open(path, NC_WRITE, &nc);
    free(d);
    if (ok) {
        const int six = 6;
        const float plat = 30, plon = 180;
        nc_redef(nc);
        ok = !nc_put_att_int(nc, NC_GLOBAL, "MAP_PROJ", NC_INT, 1, &six) &&
             !nc_put_att_float(nc, NC_GLOBAL, "POLE_LAT", NC_FLOAT, 1, &plat) &&
             !nc_put_att_float(nc, NC_GLOBAL, "POLE_LON", NC_FLOAT, 1, &plon);
        ok &= !nc_close(nc);
    }
    CHECK(ok, "a rotated-pole copy of wrf_cropped.nc is written");
    vsv_source *s = NULL;
    const int rc = vsv_source_open(path, NULL, &s);
    CHECK(rc == VSV_EUNSUPPORTED && strstr(vsv_source_error(s), "MAP_PROJ 6 with POLE_LAT 30, POLE_LON 180") &&
              strstr(vsv_source_error(s), "rotated-pole"),
          "MAP_PROJ 6 with a moved pole is refused by name", "rc %d (%s)", rc, vsv_source_error(s));
    vsv_source_free(s);
    remove(path);
}

/* (PH + PHB) / g at w-level k of time t, cell (i, j), read here directly. */
static double wrf_zw(int nc, int t, int k, int j, int i)
{
    int a, b;
    float ph, phb;
    size_t at[4] = {(size_t)t, (size_t)k, (size_t)j, (size_t)i};
    if (nc_inq_varid(nc, "PH", &a) || nc_inq_varid(nc, "PHB", &b) || nc_get_var1_float(nc, a, at, &ph) ||
        nc_get_var1_float(nc, b, at, &phb))
        return NAN;
    return (ph + phb) / 9.81;
}

static void test_native_heights(void)
{
    const char *path = vsv_test_shared("wrf/wrf_cropped.nc");
    vsv_source_opts o;
    vsv_source_opts_init(&o);
    o.vertical = VSV_VERT_NATIVE;
    vsv_source *s = NULL;
    int rc = vsv_source_open(path, &o, &s);
    const vsv_meta *g = vsv_source_grid(s);
    const size_t plane = rc ? 0 : (size_t)g->nx * g->ny, cells = plane * (size_t)(rc ? 0 : g->nz);
    float *z0 = malloc((cells + 1) * sizeof *z0), *z3 = malloc((cells + 1) * sizeof *z3);
    rc = rc ? rc : vsv_source_heights(s, 0, z0);
    rc = rc ? rc : vsv_source_heights(s, 3, z3);
    CHECK(rc == 0, "WRF native: heights of every column at times 0 and 3", "(%s)", vsv_source_error(s));
    int nc;
    if (!rc && !nc_open(path, NC_NOWRITE, &nc)) {
        double worst = 0, moved = 0;
        const int cols[][2] = {{0, 0}, {5, 20}, {25, 25}, {13, 7}};
        for (size_t q = 0; q < 4; q++)
            for (int k = 0; k < g->nz; k += 3) {
                const int i = cols[q][0], j = cols[q][1];
                const size_t at = (size_t)k * plane + (size_t)j * g->nx + i;
                for (int t = 0; t < 4; t += 3) {
                    const double want = 0.5 * (wrf_zw(nc, t, k, j, i) + wrf_zw(nc, t, k + 1, j, i));
                    worst = fmax(worst, fabs((t ? z3 : z0)[at] - want));
                }
                moved = fmax(moved, fabs(z3[at] - z0[at]));
            }
        nc_close(nc);
        CHECK(worst < 0.01 && moved > 1, "WRF native heights are (PH+PHB)/g of their time, and move in time",
              "worst %.4f m, moved up to %.1f m", worst, moved);
    }
    vsv_source_free(s);
    free(z0);
    free(z3);
    /* even grids have no native heights to give */
    vsv_source_opts even;
    vsv_source_opts_init(&even);
    even.vertical = VSV_VERT_EVEN;
    rc = vsv_source_open(path, &even, &s);
    float one[1];
    CHECK(!rc && vsv_source_heights(s, 0, one) == VSV_EUNSUPPORTED, "even grid: vsv_source_heights is unsupported");
    vsv_source_free(s);
    s = NULL;
    /* MM5 REGRID: pressure levels where H puts them, per time */
    const char *regrid = vsv_test_shared("mm5/run1/REGRID_DOMAIN1");
    rc = vsv_test_absent(regrid, "MM5 REGRID heights") ? -1 : vsv_source_open(regrid, &o, &s);
    if (!rc) {
        g = vsv_source_grid(s);
        const size_t pl = (size_t)g->nx * g->ny, nc3 = pl * (size_t)g->nz;
        float *a = malloc(nc3 * sizeof *a), *b = malloc(nc3 * sizeof *b), *h = malloc(nc3 * sizeof *h);
        rc = vsv_source_heights(s, 0, a) || vsv_source_heights(s, 1, b) ||
             vsv_source_read(s, vsv_source_find_field(s, "H"), 1, h);
        /* (the file's two periods are the same analysis: constant boundaries,
         * so only the columns can differ here) */
        double diff = 0, lo = INFINITY, hi = -INFINITY;
        for (size_t c = 0; !rc && c < nc3; c++)
            diff = fmax(diff, fabs(b[c] - h[c]));
        for (size_t c = 0; !rc && c < pl; c++) {
            lo = fmin(lo, a[5 * pl + c]);
            hi = fmax(hi, a[5 * pl + c]);
        }
        CHECK(!rc && diff == 0 && hi - lo > 100 && g->nz == 23,
              "REGRID native: level heights are H of each time and column", "rc %d, |z-H| %g, 900 hPa %g..%g m", rc,
              diff, lo, hi);
        free(a);
        free(b);
        free(h);
    }
    vsv_source_free(s);
}

static void test_zstd_level(void)
{
    vsv_meta m;
    vsv_meta_init(&m);
    m.nx = m.ny = m.nz = 8;
    vsv_meta_add_var(&m, "X", "1", "test");
    vsv_pack_opts o;
    vsv_pack_opts_init(&o);
    o.level = 40;
    vsv_writer *w = NULL;
    const char *out = vsv_test_tmp("level.vsv");
    const int rc = vsv_writer_create(out, &m, &o, &w);
    CHECK(rc == VSV_EINVAL && strstr(vsv_writer_error(w), "zstd level 40: must be 1.."),
          "an invalid zstd level is refused by name (was silently 3)", "rc %d (%s)", rc, vsv_writer_error(w));
    vsv_writer_free(w);
    vsv_meta_clear(&m);
}

/* A CF file whose coordinates are in kilometres and whose time counts
 * hours: x, y and z become metres (x 0, 1, 2, 3 km: origin 0, spacing
 * 1000 m; z 0.5, 1.5 km: origin 500 m, spacing 1000 m), 1.5 hours since
 * 2001-01-01 06:00 is 07:30, and packed values are unpacked. */
static void test_cf_units(void)
{
    const char *path = vsv_test_tmp("km.nc");
    int nc, d[4], v[5], ok = !nc_create(path, NC_CLOBBER, &nc);
    static const char *const dn[4] = {"time", "z", "y", "x"};
    static const size_t len[4] = {1, 2, 3, 4};
    for (int i = 0; ok && i < 4; i++)
        ok = !nc_def_dim(nc, dn[i], len[i], &d[i]) && !nc_def_var(nc, dn[i], NC_DOUBLE, 1, &d[i], &v[i]);
    ok = ok && !nc_def_var(nc, "O3", NC_SHORT, 4, d, &v[4]);
    static const char *const att[][3] = {{"time", "units", "hours since 2001-01-01 06:00:00"},
                                         {"z", "units", "km"},
                                         {"z", "positive", "up"},
                                         {"z", "standard_name", "altitude"},
                                         {"y", "units", "km"},
                                         {"y", "standard_name", "projection_y_coordinate"},
                                         {"x", "units", "km"},
                                         {"x", "standard_name", "projection_x_coordinate"},
                                         {"O3", "units", "ppm"}};
    for (size_t i = 0; ok && i < sizeof att / sizeof *att; i++) {
        int id;
        ok = !nc_inq_varid(nc, att[i][0], &id) && !nc_put_att_text(nc, id, att[i][1], strlen(att[i][2]), att[i][2]);
    }
    const double sf = 0.5, ao = 10;
    ok = ok && !nc_put_att_text(nc, NC_GLOBAL, "Conventions", 6, "CF-1.8") &&
         !nc_put_att_double(nc, v[4], "scale_factor", NC_DOUBLE, 1, &sf) &&
         !nc_put_att_double(nc, v[4], "add_offset", NC_DOUBLE, 1, &ao) && !nc_enddef(nc);
    const double tv[1] = {1.5}, zv[2] = {0.5, 1.5}, yv[3] = {0, 1, 2}, xv[4] = {0, 1, 2, 3};
    short o3[24];
    for (int i = 0; i < 24; i++)
        o3[i] = (short)(2 * i);
    ok = ok && !nc_put_var_double(nc, v[0], tv) && !nc_put_var_double(nc, v[1], zv) &&
         !nc_put_var_double(nc, v[2], yv) && !nc_put_var_double(nc, v[3], xv) && !nc_put_var_short(nc, v[4], o3);
    ok &= !nc_close(nc);
    CHECK(ok, "a CF file in km and hours is written");
    vsv_source *s = NULL;
    const int rc = vsv_source_open(path, NULL, &s);
    const vsv_meta *g = rc ? NULL : vsv_source_grid(s);
    const int64_t t0 = 978307200 + 27000; /* 2001-01-01T07:30:00Z in Unix seconds */
    CHECK(g && g->spacing[0] == 1000 && g->spacing[1] == 1000 && g->origin[0] == 0 && g->origin[2] == 500 &&
              g->spacing[2] == 1000 && g->vert_kind == VSV_VERT_EVEN && vsv_source_ntimes(s) == 1 &&
              vsv_source_time(s, 0) == t0,
          "CF: km coordinates become metres (spacing 1000, z origin 500), 1.5 hours since 06:00 is 07:30",
          "rc %d (%s): dx %g dy %g x0 %g z0 %g dz %g, time %lld", rc, vsv_source_error(s), g ? g->spacing[0] : 0,
          g ? g->spacing[1] : 0, g ? g->origin[0] : 0, g ? g->origin[2] : 0, g ? g->spacing[2] : 0,
          g ? (long long)vsv_source_time(s, 0) : 0);
    float out[24];
    const int f = g ? vsv_source_find_field(s, "O3") : -1;
    int same = f >= 0 && !vsv_source_read(s, f, 0, out);
    for (int i = 0; same && i < 24; i++)
        same = out[i] == (float)(10 + i);
    CHECK(same, "CF: packed values are unpacked (short 2 i times 0.5 plus 10)", "O3 %d", f);
    vsv_source_free(s);
    remove(path);
}

int main(void)
{
    test_cf_units();
    test_zstd_level();
    test_wrf_default();
    test_rotated_pole();
    test_native_heights();
    return vsv_test_done();
}
