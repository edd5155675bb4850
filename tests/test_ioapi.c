/* test_ioapi.c — the IOAPI netCDF reader (CMAQ CONC/ACONC, CAMx netCDF) on
 * files written here through libnetcdf: TFLAG times, species and units,
 * heights from `z` or from sigma-P levels, each supported GDTYP's projected
 * coordinates checked against closed-form spherical formulas, classic and
 * netCDF-4 files, unsupported projections named. */
#include "vsv_convert.h"
#include "vsv_format.h"
#include "vsv_testlib.h"

#include <math.h>
#include <netcdf.h>
#include <stdlib.h>
#include <string.h>

#define R_E 6370000.0
#define D2R (M_PI / 180)

typedef struct spec {
    int gdtyp;
    double alp, bet, gam, xcent, ycent, xorig, yorig, cell;
    int camx, nc4, vgtyp;
} spec;

enum { NX = 30, NY = 20, NZ = 5, NT = 3 };

static float value(int v, int t, int k, int j, int i)
{
    return (float)((v + 1) * 0.01 * (1 + 0.1 * k) + 0.001 * i + 0.0001 * j + t * 0.5);
}

/* 1: topo written as ROW x COL x LAY, five times the grid's plane (crafted) */
static int big_topo;

static int write_ioapi(const char *path, const spec *sp)
{
    int nc, d[6], tflag, vars[2], z = -1, topo = -1;
    int rc = nc_create(path, NC_CLOBBER | (sp->nc4 ? NC_NETCDF4 : 0), &nc);
    if (rc)
        return rc;
    nc_def_dim(nc, "TSTEP", NC_UNLIMITED, &d[0]);
    nc_def_dim(nc, "DATE-TIME", 2, &d[1]);
    nc_def_dim(nc, "LAY", NZ, &d[2]);
    nc_def_dim(nc, "VAR", 2, &d[3]);
    nc_def_dim(nc, "ROW", NY, &d[4]);
    nc_def_dim(nc, "COL", NX, &d[5]);
    int tdims[3] = {d[0], d[3], d[1]}, vdims[4] = {d[0], d[2], d[4], d[5]}, pdims[2] = {d[4], d[5]};
    nc_def_var(nc, "TFLAG", NC_INT, 3, tdims, &tflag);
    const char *names[2] = {"O3", "PM25"}, *units[2] = {"ppmV            ", "micrograms/m**3 "};
    for (int v = 0; v < 2; v++) {
        nc_def_var(nc, names[v], NC_FLOAT, 4, vdims, &vars[v]);
        nc_put_att_text(nc, vars[v], "units", 16, units[v]);
        nc_put_att_text(nc, vars[v], "var_desc", 10, v ? "fine PM   " : "ozone     ");
    }
    if (sp->camx) {
        nc_def_var(nc, "z", NC_FLOAT, 4, vdims, &z);
        int bdims[3] = {d[4], d[5], d[2]};
        nc_def_var(nc, "topo", NC_FLOAT, big_topo ? 3 : 2, big_topo ? bdims : pdims, &topo);
        nc_put_att_text(nc, NC_GLOBAL, "CAMx_NAME", 7, "AVERAGE");
    }
    int ncols = NX, nrows = NY, nlays = NZ, gd = sp->gdtyp, sdate = 2016182, stime = 0, tstep = 10000,
        vgtyp = sp->vgtyp;
    nc_put_att_int(nc, NC_GLOBAL, "NCOLS", NC_INT, 1, &ncols);
    nc_put_att_int(nc, NC_GLOBAL, "NROWS", NC_INT, 1, &nrows);
    nc_put_att_int(nc, NC_GLOBAL, "NLAYS", NC_INT, 1, &nlays);
    nc_put_att_int(nc, NC_GLOBAL, "GDTYP", NC_INT, 1, &gd);
    nc_put_att_int(nc, NC_GLOBAL, "SDATE", NC_INT, 1, &sdate);
    nc_put_att_int(nc, NC_GLOBAL, "STIME", NC_INT, 1, &stime);
    nc_put_att_int(nc, NC_GLOBAL, "TSTEP", NC_INT, 1, &tstep);
    nc_put_att_int(nc, NC_GLOBAL, "VGTYP", NC_INT, 1, &vgtyp);
    const double dv[] = {sp->alp, sp->bet, sp->gam, sp->xcent, sp->ycent, sp->xorig, sp->yorig, sp->cell, sp->cell};
    const char *dn[] = {"P_ALP", "P_BET", "P_GAM", "XCENT", "YCENT", "XORIG", "YORIG", "XCELL", "YCELL"};
    for (int i = 0; i < 9; i++)
        nc_put_att_double(nc, NC_GLOBAL, dn[i], NC_DOUBLE, 1, &dv[i]);
    const float vgtop = 5000, vgl[NZ + 1] = {1.0f, 0.995f, 0.985f, 0.96f, 0.9f, 0.8f};
    nc_put_att_float(nc, NC_GLOBAL, "VGTOP", NC_FLOAT, 1, &vgtop);
    nc_put_att_float(nc, NC_GLOBAL, "VGLVLS", NC_FLOAT, NZ + 1, vgl);
    char desc[60 * 80 + 1]; /* as IOAPI writes it: 60 lines of 80 characters, blank-padded */
    snprintf(desc, sizeof desc, "%-80s%-80s%-4640s", "Vesuvius IOAPI test", "  second line", "");
    nc_put_att_text(nc, NC_GLOBAL, "FILEDESC", 4800, desc);
    nc_enddef(nc);
    float *buf = malloc(sizeof(float) * NX * NY * NZ);
    for (int t = 0; t < NT; t++) {
        int tf[2][2] = {{sdate, t * 10000}, {sdate, t * 10000}};
        size_t ts[3] = {(size_t)t, 0, 0}, tc[3] = {1, 2, 2};
        nc_put_vara_int(nc, tflag, ts, tc, &tf[0][0]);
        size_t st[4] = {(size_t)t, 0, 0, 0}, ct[4] = {1, NZ, NY, NX};
        for (int v = 0; v < 2; v++) {
            for (int k = 0; k < NZ; k++)
                for (int j = 0; j < NY; j++)
                    for (int i = 0; i < NX; i++)
                        buf[(k * NY + j) * NX + i] = value(v, t, k, j, i);
            nc_put_vara_float(nc, vars[v], st, ct, buf);
        }
        if (z >= 0) {
            for (int k = 0; k < NZ; k++)
                for (int p = 0; p < NX * NY; p++)
                    buf[k * NX * NY + p] = (float)(40.0 * (k + 1) * (k + 1) + t);
            nc_put_vara_float(nc, z, st, ct, buf);
        }
    }
    if (topo >= 0) {
        for (int p = 0; p < NX * NY * (big_topo ? NZ : 1); p++)
            buf[p] = (float)(100 + p % NX);
        nc_put_var_float(nc, topo, buf);
    }
    free(buf);
    return nc_close(nc);
}

/* Closed-form spherical projections: (x, y) of (lat, lon) relative to (lat0, lon0). */
static void lcc(double p1, double p2, double lat0, double lon0, double lat, double lon, double *x, double *y)
{
    p1 *= D2R, p2 *= D2R;
    double n =
        fabs(p1 - p2) < 1e-12 ? sin(p1) : log(cos(p1) / cos(p2)) / log(tan(M_PI / 4 + p2 / 2) / tan(M_PI / 4 + p1 / 2));
    double F = cos(p1) * pow(tan(M_PI / 4 + p1 / 2), n) / n;
    double r = R_E * F / pow(tan(M_PI / 4 + lat * D2R / 2), n), r0 = R_E * F / pow(tan(M_PI / 4 + lat0 * D2R / 2), n);
    *x = r * sin(n * (lon - lon0) * D2R);
    *y = r0 - r * cos(n * (lon - lon0) * D2R);
}
static void ps(double pc, double lat0, double lon0, double lat, double lon, double *x, double *y)
{
    double k0 = (1 + sin(pc * D2R)) / 2;
    double r = 2 * R_E * k0 * tan(M_PI / 4 - lat * D2R / 2), r0 = 2 * R_E * k0 * tan(M_PI / 4 - lat0 * D2R / 2);
    *x = r * sin((lon - lon0) * D2R);
    *y = -r * cos((lon - lon0) * D2R) + r0;
}
static void merc(double pc, double lat0, double lon0, double lat, double lon, double *x, double *y)
{
    double k = cos(pc * D2R);
    *x = R_E * k * (lon - lon0) * D2R;
    *y = R_E * k * (log(tan(M_PI / 4 + lat * D2R / 2)) - log(tan(M_PI / 4 + lat0 * D2R / 2)));
}

/* spherical transverse Mercator with scale k0, origin (lat0, lon0) */
static void tm(double k0, double lat0, double lon0, double lat, double lon, double *x, double *y)
{
    const double B = cos(lat * D2R) * sin((lon - lon0) * D2R);
    *x = 0.5 * R_E * k0 * log((1 + B) / (1 - B));
    *y = R_E * k0 * (atan2(tan(lat * D2R), cos((lon - lon0) * D2R)) - lat0 * D2R);
}
/* spherical Albers with standard parallels p1, p2 */
static void albers(double p1, double p2, double lat0, double lon0, double lat, double lon, double *x, double *y)
{
    const double n = (sin(p1 * D2R) + sin(p2 * D2R)) / 2, C = cos(p1 * D2R) * cos(p1 * D2R) + 2 * n * sin(p1 * D2R);
    const double r = R_E * sqrt(C - 2 * n * sin(lat * D2R)) / n, r0 = R_E * sqrt(C - 2 * n * sin(lat0 * D2R)) / n;
    *x = r * sin(n * (lon - lon0) * D2R);
    *y = r0 - r * cos(n * (lon - lon0) * D2R);
}

static void check(const char *label, const spec *sp)
{
    char name[256], path[64];
    snprintf(path, sizeof path, "ioapi-%d-%d.nc", sp->gdtyp, sp->camx);
    const char *p = vsv_test_tmp(path);
    int rc = write_ioapi(p, sp);
    snprintf(name, sizeof name, "%s: written", label);
    if (!CHECK(rc == 0, name, "%s", nc_strerror(rc)))
        return;
    vsv_source_opts so;
    vsv_source_opts_init(&so);
    so.vertical = VSV_VERT_NATIVE;
    vsv_source *src = NULL;
    rc = vsv_source_open(p, &so, &src);
    snprintf(name, sizeof name, "%s: opens as IOAPI", label);
    if (!CHECK(rc == 0 && !strcmp(vsv_source_format(src), "IOAPI"), name, "%s", vsv_source_error(src))) {
        vsv_source_free(src);
        return;
    }
    const vsv_meta *g = vsv_source_grid(src);
    snprintf(name, sizeof name, "%s: TFLAG times 2016-06-30 00, 01, 02 UTC", label);
    CHECK(vsv_source_ntimes(src) == NT && vsv_source_time(src, 0) == vsv_time_from_civil(2016, 6, 30, 0, 0, 0) &&
              vsv_source_time(src, 2) == vsv_time_from_civil(2016, 6, 30, 2, 0, 0),
          name);
    snprintf(name, sizeof name, "%s: FILEDESC's 60 lines of 80 as one, trimmed", label);
    CHECK(!strcmp(g->run, "Vesuvius IOAPI test; second line"), name, "'%s'", g->run);
    const vsv_field_info *o3 = vsv_source_field(src, vsv_source_find_field(src, "O3"));
    const vsv_field_info *pm = vsv_source_field(src, vsv_source_find_field(src, "PM25"));
    snprintf(name, sizeof name, "%s: species O3 (ppmV), PM25 (micrograms/m**3)", label);
    CHECK(vsv_source_nfields(src) == 2 && !strcmp(o3->units, "ppmV") && !strcmp(pm->units, "micrograms/m**3") &&
              !strcmp(o3->description, "ozone"),
          name, "%d fields, '%s' '%s'", vsv_source_nfields(src), o3->units, pm->units);
    float *vol = malloc(sizeof(float) * NX * NY * NZ);
    int same = 1;
    for (int t = 0; t < NT; t++)
        for (int v = 0; v < 2; v++) {
            same &= vsv_source_read(src, v, t, vol) == 0;
            for (int k = 0; k < NZ; k++)
                for (int j = 0; j < NY; j++)
                    for (int i = 0; i < NX; i++)
                        same &= vol[(k * NY + j) * NX + i] == value(v, t, k, j, i);
        }
    snprintf(name, sizeof name, "%s: every value read back", label);
    CHECK(same, name);
    free(vol);
    /* heights */
    if (sp->camx) {
        double ter = 0;
        for (int c = 0; g->terrain && c < NX * NY; c++)
            ter += g->terrain[c] / (double)(NX * NY);
        snprintf(name, sizeof name, "%s: heights from z (layer middles) lifted onto the terrain from topo", label);
        CHECK(g->vert_kind == VSV_VERT_NATIVE && fabs(g->levels[0] - 20 - ter) < 1e-3 &&
                  fabs(g->levels[1] - 100 - ter) < 1e-3 && g->terrain && g->terrain[3] == 103 &&
                  !vsv_meta_above_ground(g),
              name, "%g %g over %g", g->levels ? g->levels[0] : -1, g->levels ? g->levels[1] : -1, ter);
    } else {
        int mono = g->vert_kind == VSV_VERT_NATIVE;
        for (int k = 1; mono && k < NZ; k++)
            mono &= g->levels[k] > g->levels[k - 1];
        snprintf(name, sizeof name, "%s: sigma-P heights through the standard atmosphere, increasing (%.0f..%.0f m)",
                 label, g->levels ? g->levels[0] : -1, g->levels ? g->levels[NZ - 1] : -1);
        CHECK(mono && g->levels[0] > 10 && g->levels[0] < 60 && vsv_meta_attr(g, "heights"), name);
        snprintf(name, sizeof name, "%s: without terrain, the heights are marked as above the ground", label);
        CHECK(vsv_meta_above_ground(g), name);
    }
    /* projected coordinates: every cell's lat/lon, back through the closed form, lands on XORIG + (i+1/2) XCELL */
    double worst = 0;
    for (int j = 0; j < NY; j += 3)
        for (int i = 0; i < NX; i += 3) {
            double lat, lon, x = 0, y = 0;
            vsv_proj_inverse(&g->proj, g->origin[0] + i * g->spacing[0], g->origin[1] + j * g->spacing[1], &lat, &lon);
            if (sp->gdtyp == 2)
                lcc(sp->alp, sp->bet, sp->ycent, sp->gam, lat, lon, &x, &y);
            else if (sp->gdtyp == 6)
                ps(sp->bet, sp->ycent, sp->gam, lat, lon, &x, &y);
            else if (sp->gdtyp == 7)
                merc(sp->alp, sp->ycent, sp->gam, lat, lon, &x, &y);
            else if (sp->gdtyp == 5) {
                tm(0.9996, 0, 6 * sp->alp - 183, lat, lon, &x, &y);
                x += 500000;
            } else if (sp->gdtyp == 8)
                tm(sp->bet, sp->alp, sp->gam, lat, lon, &x, &y);
            else if (sp->gdtyp == 9)
                albers(sp->alp, sp->bet, sp->ycent, sp->gam, lat, lon, &x, &y);
            else
                x = lon, y = lat;
            const double wx = sp->xorig + (i + 0.5) * sp->cell, wy = sp->yorig + (j + 0.5) * sp->cell;
            worst = fmax(worst, hypot(x - wx, y - wy));
        }
    snprintf(name, sizeof name, "%s: projected coordinates agree with the closed-form projection", label);
    CHECK(worst < (sp->gdtyp == 1 ? 1e-9 : 1e-3), name, "worst %g", worst);
    vsv_source_free(src);
}

/* A topo variable larger than the grid (issue 18: read whole into an nx*ny
 * buffer, a heap overflow) is an error naming it and both shapes. */
static void test_big_topo(void)
{
    spec camx = {2, 30, 60, -100, -100, 40, -792000, -1656000, 36000, 1, 1, 6};
    const char *path = vsv_test_tmp("bigtopo.nc");
    big_topo = 1;
    write_ioapi(path, &camx);
    big_topo = 0;
    vsv_source *src = NULL;
    const int rc = vsv_source_open(path, NULL, &src);
    CHECK(rc == VSV_ECORRUPT &&
              strstr(vsv_source_error(src), "bigtopo.nc: variable topo is 20 x 30 x 5, expected [time x] 20 x 30"),
          "IOAPI topo larger than the grid: an error naming the variable and shapes", "rc %d: %s", rc,
          vsv_source_error(src));
    vsv_source_free(src);
}

int main(void)
{
    test_big_topo();
    spec cmaq = {2, 33, 45, -97, -97, 40, -2556000, -1728000, 12000, 0, 0, 7};
    check("CMAQ CONC, GDTYP 2 Lambert, classic", &cmaq);
    spec camx = {2, 30, 60, -100, -100, 40, -792000, -1656000, 36000, 1, 1, 6};
    check("CAMx netCDF, GDTYP 2 Lambert, netCDF-4, z and topo", &camx);
    spec pst = {6, 1, 60, -98, -98, 90, -3000000, -4000000, 20000, 0, 1, 7};
    check("GDTYP 6 polar stereographic", &pst);
    spec mer = {7, 20, 0, -60, -60, 0, -1000000, 1000000, 15000, 0, 0, 7};
    check("GDTYP 7 equatorial Mercator", &mer);
    spec ll = {1, 0, 0, 0, 0, 0, -120, 20, 0.5, 0, 0, 7};
    check("GDTYP 1 lat/lon", &ll);
    spec utm = {5, 17, 0, 0, 0, 0, 300000, 4000000, 4000, 0, 0, 7};
    check("GDTYP 5 UTM zone 17", &utm);
    spec trm = {8, 35, 0.9999, -90, -90, 35, -200000, -150000, 10000, 0, 0, 7};
    check("GDTYP 8 transverse Mercator", &trm);
    spec alb = {9, 29.5, 45.5, -96, -96, 23, -2400000, 200000, 12000, 0, 0, 7};
    check("GDTYP 9 Albers equal-area", &alb);
    /* an unsupported GDTYP is named */
    spec laea = {10, 45, 0, 10, 10, 52, -100000, -100000, 5000, 0, 0, 7};
    const char *p = vsv_test_tmp("laea.nc");
    write_ioapi(p, &laea);
    vsv_source *src = NULL;
    int rc = vsv_source_open(p, NULL, &src);
    CHECK(rc == VSV_EUNSUPPORTED &&
              strstr(vsv_source_error(src), "GDTYP 10 (Lambert azimuthal equal-area) is not supported"),
          "GDTYP 10 (Lambert azimuthal) is refused by name", "%s", vsv_source_error(src));
    vsv_source_free(src);
    return vsv_test_done();
}
