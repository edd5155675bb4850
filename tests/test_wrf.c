/* test_wrf.c — the WRF reader on the three real wrfout files in
 * ../shared/data/wrf: positions against XLAT/XLONG, values against a direct
 * netCDF read after destaggering, heights, the Katrina file's cut-off top,
 * and netCDF files that are not WRF. */
#include "vsv_convert.h"
#include "vsv_format.h"
#include "vsv_testlib.h"

#include <math.h>
#include <netcdf.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static double dist_m(double lat1, double lon1, double lat2, double lon2)
{
    const double r = M_PI / 180, R = 6370000;
    double dlat = (lat2 - lat1) * r, dlon = (lon2 - lon1) * r;
    double a = sin(dlat / 2) * sin(dlat / 2) + cos(lat1 * r) * cos(lat2 * r) * sin(dlon / 2) * sin(dlon / 2);
    return 2 * R * asin(sqrt(a));
}

/* A 4-D variable at time t, as stored. */
static float *get(int nc, const char *name, int t, size_t *dims)
{
    int id, dimids[4];
    if (nc_inq_varid(nc, name, &id) || nc_inq_vardimid(nc, id, dimids))
        return NULL;
    for (int d = 1; d < 4; d++)
        nc_inq_dimlen(nc, dimids[d], &dims[d - 1]);
    size_t start[4] = {(size_t)t, 0, 0, 0}, count[4] = {1, dims[0], dims[1], dims[2]};
    float *v = malloc(dims[0] * dims[1] * dims[2] * sizeof *v);
    if (v && nc_get_vara_float(nc, id, start, count, v)) {
        free(v);
        return NULL;
    }
    return v;
}

static void check_file(const char *rel, int nx, int ny, int nk, int proj)
{
    const char *path = vsv_test_shared(rel);
    char name[256];
    vsv_source_opts so;
    vsv_source_opts_init(&so);
    so.vertical = VSV_VERT_NATIVE;
    vsv_source *src = NULL;
    int rc = vsv_source_open(path, &so, &src);
    snprintf(name, sizeof name, "%s opens as WRF", rel);
    if (!CHECK(rc == 0 && !strcmp(vsv_source_format(src), "WRF"), name, "%s", vsv_source_error(src))) {
        vsv_source_free(src);
        return;
    }
    const vsv_meta *g = vsv_source_grid(src);
    snprintf(name, sizeof name, "%s: %d x %d x %d, 4 times, projection %d", rel, nx, ny, nk, proj);
    CHECK(g->nx == nx && g->ny == ny && g->nz == nk && vsv_source_ntimes(src) == 4 && g->proj.kind == proj, name,
          "%dx%dx%d t%d p%d", g->nx, g->ny, g->nz, vsv_source_ntimes(src), g->proj.kind);
    int nc;
    nc_open(path, NC_NOWRITE, &nc);
    /* every cell's position against XLAT/XLONG */
    size_t d2[3];
    int id, nd;
    nc_inq_varid(nc, "XLAT", &id);
    nc_inq_varndims(nc, id, &nd);
    float *la = malloc((size_t)nx * ny * 4), *lo = malloc((size_t)nx * ny * 4);
    size_t st[3] = {0, 0, 0}, ct[3] = {1, (size_t)ny, (size_t)nx};
    nc_get_vara_float(nc, id, nd == 3 ? st : st + 1, nd == 3 ? ct : ct + 1, la);
    nc_inq_varid(nc, "XLONG", &id);
    nc_get_vara_float(nc, id, nd == 3 ? st : st + 1, nd == 3 ? ct : ct + 1, lo);
    double worst = 0;
    for (int j = 0; j < ny; j++)
        for (int i = 0; i < nx; i++) {
            double plat, plon;
            vsv_proj_inverse(&g->proj, g->origin[0] + i * g->spacing[0], g->origin[1] + j * g->spacing[1], &plat,
                             &plon);
            worst = fmax(worst, dist_m(plat, plon, la[j * nx + i], lo[j * nx + i]));
        }
    snprintf(name, sizeof name, "%s: every cell within 10 m of XLAT/XLONG", rel);
    CHECK(worst < 10, name, "worst %.1f m", worst);
    printf("  %s: worst position difference %.2f m\n", rel, worst);
    free(la);
    free(lo);
    /* heights: levels increase */
    int mono = 1;
    for (int k = 1; k < nk; k++)
        mono &= g->levels[k] > g->levels[k - 1];
    snprintf(name, sizeof name, "%s: mass-level heights increase (%.0f .. %.0f m)", rel, g->levels[0],
             g->levels[nk - 1]);
    CHECK(mono && g->levels[0] > 0, name);
    /* values equal a direct read after destaggering */
    const char *vars[] = {"U", "V", "W", "QCLOUD", "T"};
    float *vol = malloc((size_t)nx * ny * nk * 4);
    for (int v = 0; v < 5; v++) {
        const int fi = vsv_source_find_field(src, vars[v]);
        if (fi < 0)
            continue;
        int same = 1;
        for (int t = 0; t < 4; t += 3) {
            size_t dims[3];
            float *raw = get(nc, vars[v], t, dims);
            same &= raw && vsv_source_read(src, fi, t, vol) == 0;
            for (int k = 0; same && k < nk; k++)
                for (int j = 0; j < ny; j++)
                    for (int i = 0; i < nx; i++) {
                        float want;
                        if (v == 0)
                            want = 0.5f * (raw[((size_t)k * ny + j) * (nx + 1) + i] +
                                           raw[((size_t)k * ny + j) * (nx + 1) + i + 1]);
                        else if (v == 1)
                            want = 0.5f * (raw[((size_t)k * (ny + 1) + j) * nx + i] +
                                           raw[((size_t)k * (ny + 1) + j + 1) * nx + i]);
                        else if (v == 2)
                            want =
                                0.5f * (raw[((size_t)k * ny + j) * nx + i] + raw[((size_t)(k + 1) * ny + j) * nx + i]);
                        else
                            want = raw[((size_t)k * ny + j) * nx + i];
                        same &= vol[((size_t)k * ny + j) * nx + i] == want;
                    }
            free(raw);
        }
        snprintf(name, sizeof name, "%s: %s equals a direct netCDF read%s", rel, vars[v],
                 v < 3 ? " after destaggering" : "");
        CHECK(same, name);
    }
    free(vol);
    (void)d2;
    nc_close(nc);
    vsv_source_free(src);
}

static void test_katrina_top(void)
{
    const char *path = vsv_test_shared("wrf/katrina_ci_test_file.nc");
    vsv_source *src = NULL;
    vsv_source_opts so;
    vsv_source_opts_init(&so);
    int rc = vsv_source_open(path, &so, &src);
    if (!CHECK(rc == 0, "Katrina opens on even heights", "%s", vsv_source_error(src))) {
        vsv_source_free(src);
        return;
    }
    const vsv_meta *g = vsv_source_grid(src);
    const double top = g->origin[2] + (g->nz - 0.5) * g->spacing[2];
    /* the file keeps 14 of the run's 29 levels: the grid stops near the 14th (~5.6 km), not at 20 km */
    CHECK(top < 7000, "Katrina: the even grid ends at the file's top level, no invented levels", "top %.0f m", top);
    float *vol = malloc((size_t)g->nx * g->ny * g->nz * 4);
    vsv_source_read(src, vsv_source_find_field(src, "QCLOUD"), 0, vol);
    int nan_top = 0, data_low = 0;
    for (int c = 0; c < g->nx * g->ny; c++) {
        nan_top += isnan(vol[(size_t)(g->nz - 1) * g->nx * g->ny + c]);
        data_low += !isnan(vol[(size_t)1 * g->nx * g->ny + c]);
    }
    CHECK(data_low == g->nx * g->ny, "Katrina: low levels hold data everywhere (over the sea)");
    printf("  Katrina: even top %.0f m, %d of %d top cells above their column's data (empty)\n", top, nan_top,
           g->nx * g->ny);
    free(vol);
    vsv_source_free(src);
}

static void test_not_wrf(void)
{
    vsv_source *src = NULL;
    int rc = vsv_source_open(vsv_test_shared("ncl/contour.cdf"), NULL, &src);
    CHECK(rc != 0 && strstr(vsv_source_error(src), "netCDF file that is none of WRF"),
          "a netCDF file that is none of these is a clear error", "%s", vsv_source_error(src));
    vsv_source_free(src);
    /* an IOAPI file missing TFLAG */
    const char *p = vsv_test_tmp("notflag.nc");
    int nc, dim, var;
    nc_create(p, NC_CLOBBER, &nc);
    float v = 0;
    int n = 4;
    nc_put_att_float(nc, NC_GLOBAL, "XORIG", NC_FLOAT, 1, &v);
    nc_put_att_float(nc, NC_GLOBAL, "YORIG", NC_FLOAT, 1, &v);
    nc_put_att_float(nc, NC_GLOBAL, "XCELL", NC_FLOAT, 1, &v);
    nc_put_att_float(nc, NC_GLOBAL, "YCELL", NC_FLOAT, 1, &v);
    nc_put_att_int(nc, NC_GLOBAL, "NCOLS", NC_INT, 1, &n);
    nc_put_att_int(nc, NC_GLOBAL, "NROWS", NC_INT, 1, &n);
    nc_def_dim(nc, "COL", 4, &dim);
    nc_def_var(nc, "O3", NC_FLOAT, 1, &dim, &var);
    nc_close(nc);
    src = NULL;
    rc = vsv_source_open(p, NULL, &src);
    CHECK(rc != 0 && strstr(vsv_source_error(src), "IOAPI file without TFLAG"), "an IOAPI file missing TFLAG is named",
          "%s", vsv_source_error(src));
    vsv_source_free(src);
    /* a truncated netCDF file */
    size_t len;
    unsigned char *d = vsv_test_slurp(vsv_test_shared("wrf/wrf_cropped.nc"), &len);
    const char *cut = vsv_test_tmp("cut.nc");
    if (d)
        vsv_test_write(cut, d, len / 2);
    free(d);
    src = NULL;
    rc = vsv_source_open(cut, NULL, &src);
    int rrc = rc;
    if (!rc) {
        float *vol = malloc((size_t)26 * 26 * 40 * 4);
        for (int t = 0; t < vsv_source_ntimes(src) && !rrc; t++)
            rrc = vsv_source_read(src, vsv_source_find_field(src, "QVAPOR"), t, vol);
        free(vol);
    }
    CHECK(rrc != 0, "a truncated netCDF file is an error, not a crash", "%s", vsv_source_error(src));
    vsv_source_free(src);
}

/* 1: HGT written 4-D (Time, bottom_top, south_north, west_east) (crafted) */
static int hgt4;

/* A small synthetic wrfout: Lambert 20 km, 12x10x6, times t0.. every 3 h. */
static void write_wrf(const char *path, int t0, int nt)
{
    int nc, dT, dS, dz, dzs, dy, dx, vt, vlat, vlon, vph, vphb, vq, vh;
    nc_create(path, NC_CLOBBER | NC_NETCDF4, &nc);
    nc_def_dim(nc, "Time", NC_UNLIMITED, &dT);
    nc_def_dim(nc, "DateStrLen", 19, &dS);
    nc_def_dim(nc, "bottom_top", 6, &dz);
    nc_def_dim(nc, "bottom_top_stag", 7, &dzs);
    nc_def_dim(nc, "south_north", 10, &dy);
    nc_def_dim(nc, "west_east", 12, &dx);
    int td[2] = {dT, dS}, d3[3] = {dT, dy, dx}, d4[4] = {dT, dz, dy, dx}, d4s[4] = {dT, dzs, dy, dx};
    nc_def_var(nc, "Times", NC_CHAR, 2, td, &vt);
    nc_def_var(nc, "XLAT", NC_FLOAT, 3, d3, &vlat);
    nc_def_var(nc, "XLONG", NC_FLOAT, 3, d3, &vlon);
    nc_def_var(nc, "HGT", NC_FLOAT, hgt4 ? 4 : 3, hgt4 ? d4 : d3, &vh);
    nc_def_var(nc, "PH", NC_FLOAT, 4, d4s, &vph);
    nc_def_var(nc, "PHB", NC_FLOAT, 4, d4s, &vphb);
    nc_def_var(nc, "QCLOUD", NC_FLOAT, 4, d4, &vq);
    int mp = 1;
    float t1 = 30, t2 = 60, sl = -98, cl = 38, dxv = 20000;
    nc_put_att_int(nc, NC_GLOBAL, "MAP_PROJ", NC_INT, 1, &mp);
    nc_put_att_float(nc, NC_GLOBAL, "TRUELAT1", NC_FLOAT, 1, &t1);
    nc_put_att_float(nc, NC_GLOBAL, "TRUELAT2", NC_FLOAT, 1, &t2);
    nc_put_att_float(nc, NC_GLOBAL, "STAND_LON", NC_FLOAT, 1, &sl);
    nc_put_att_float(nc, NC_GLOBAL, "MOAD_CEN_LAT", NC_FLOAT, 1, &cl);
    nc_put_att_float(nc, NC_GLOBAL, "DX", NC_FLOAT, 1, &dxv);
    nc_put_att_float(nc, NC_GLOBAL, "DY", NC_FLOAT, 1, &dxv);
    nc_enddef(nc);
    vsv_proj p = {VSV_PROJ_LCC, 38, -98, 30, 60, 6370000};
    float lat[120], lon[120], hgt[120], ph[7 * 120], phb[7 * 120], q[6 * 120];
    for (int j = 0; j < 10; j++)
        for (int i = 0; i < 12; i++) {
            double la, lo;
            vsv_proj_inverse(&p, -200000.0 + i * 20000, -100000.0 + j * 20000, &la, &lo);
            lat[j * 12 + i] = (float)la;
            lon[j * 12 + i] = (float)lo;
            hgt[j * 12 + i] = (float)(100 + 10 * i);
        }
    for (int t = 0; t < nt; t++) {
        char ts[20];
        const int h = 3 * (t0 + t);
        snprintf(ts, sizeof ts, "2020-01-%02d_%02d:00:00", 1 + h / 24, h % 24);
        size_t s2[2] = {(size_t)t, 0}, c2[2] = {1, 19}, s3[3] = {(size_t)t, 0, 0}, c3[3] = {1, 10, 12};
        size_t s4[4] = {(size_t)t, 0, 0, 0}, c4s[4] = {1, 7, 10, 12}, c4[4] = {1, 6, 10, 12};
        nc_put_vara_text(nc, vt, s2, c2, ts);
        nc_put_vara_float(nc, vlat, s3, c3, lat);
        nc_put_vara_float(nc, vlon, s3, c3, lon);
        if (hgt4) {
            float h4[6 * 120];
            for (int c = 0; c < 6 * 120; c++)
                h4[c] = hgt[c % 120];
            nc_put_vara_float(nc, vh, (size_t[4]){(size_t)t, 0, 0, 0}, (size_t[4]){1, 6, 10, 12}, h4);
        } else
            nc_put_vara_float(nc, vh, s3, c3, hgt);
        for (int k = 0; k < 7; k++)
            for (int c = 0; c < 120; c++) {
                phb[k * 120 + c] = (float)(9.81 * (hgt[c] + 1000.0 * k * k / 2));
                ph[k * 120 + c] = (float)(9.81 * 5 * (t0 + t));
            }
        for (int k = 0; k < 6; k++)
            for (int c = 0; c < 120; c++)
                q[k * 120 + c] = (float)(1e-4 * (k == 2) * (1 + c % 7) * (1 + t0 + t));
        nc_put_vara_float(nc, vph, s4, c4s, ph);
        nc_put_vara_float(nc, vphb, s4, c4s, phb);
        nc_put_vara_float(nc, vq, s4, c4, q);
    }
    nc_close(nc);
}

static void test_run(void)
{
    const char *a = vsv_test_tmp("wrfout_d01_a"), *b = vsv_test_tmp("wrfout_d01_b"),
               *all = vsv_test_tmp("wrfout_d01_all");
    write_wrf(a, 0, 2);
    write_wrf(b, 2, 2);
    write_wrf(all, 0, 4);
    const char *two[] = {b, a}, *one[] = {all};
    vsv_run *r2 = NULL, *r1 = NULL;
    int rc2 = vsv_run_open(two, 2, NULL, NULL, NULL, &r2), rc1 = vsv_run_open(one, 1, NULL, NULL, NULL, &r1);
    int ok = !rc1 && !rc2 && vsv_run_nframes(r2) == 4 && vsv_run_nframes(r1) == 4;
    const vsv_meta *m = ok ? vsv_run_meta(r2) : NULL;
    const size_t cells = m ? (size_t)m->nx * m->ny * m->nz : 0;
    float *f1 = malloc(cells * 4 + 4), *f2 = malloc(cells * 4 + 4);
    for (int i = 0; ok && i < 4; i++) {
        ok &= vsv_run_time(r1, i) == vsv_run_time(r2, i) && vsv_run_read(r1, i, &f1) == 0 &&
              vsv_run_read(r2, i, &f2) == 0;
        ok &= !memcmp(f1, f2, cells * 4);
    }
    CHECK(ok && !strcmp(m->vars[0].name, "QCLOUD"),
          "two wrfout files given out of order are one run equal to the whole", "%s %s", vsv_run_error(r1),
          vsv_run_error(r2));
    /* heights move with PH in time: the even grid follows them */
    free(f1);
    free(f2);
    vsv_run_free(r1);
    vsv_run_free(r2);
    const char *twice[] = {a, a};
    vsv_run *r3 = NULL;
    int rc = vsv_run_open(twice, 2, NULL, NULL, NULL, &r3);
    CHECK(rc != 0 && strstr(vsv_run_error(r3), "overlap"), "the same wrfout twice overlaps", "%s", vsv_run_error(r3));
    vsv_run_free(r3);
}

/* A 4-D HGT (issue 18: 3-element start/count passed for 4 dimensions, read
 * past their end) is an error naming the variable and its shape. */
static void test_hgt4(void)
{
    const char *path = vsv_test_tmp("hgt4.nc");
    hgt4 = 1;
    write_wrf(path, 0, 1);
    hgt4 = 0;
    vsv_source *src = NULL;
    const int rc = vsv_source_open(path, NULL, &src);
    CHECK(rc == VSV_ECORRUPT &&
              strstr(vsv_source_error(src), "hgt4.nc: variable HGT is 1 x 6 x 10 x 12, expected [time x] 10 x 12"),
          "WRF with a 4-D HGT: an error naming the variable and shapes", "rc %d: %s", rc, vsv_source_error(src));
    vsv_source_free(src);
}

int main(void)
{
    test_hgt4();
    test_run();
    check_file("wrf/wrf_cropped.nc", 26, 26, 12, VSV_PROJ_LCC);
    check_file("wrf/wrf_d01_allvars_cropped.nc", 10, 8, 27, VSV_PROJ_LCC);
    check_file("wrf/katrina_ci_test_file.nc", 48, 48, 14, VSV_PROJ_MERCATOR);
    test_katrina_top();
    test_not_wrf();
    return vsv_test_done();
}
