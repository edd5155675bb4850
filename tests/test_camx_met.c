/* test_camx_met.c — a CAMx average file with the real met companions in
 * ../shared/data/camx (5 x 4 cells, 3 layers, 2 hours): the average file is
 * written by the project's own UAM-IV writer to match them (no real
 * multi-layer CAMx output exists), read with --met DIR and --heights; the
 * real 1-layer test.uamiv reads their lowest layer, a 4-layer file is
 * refused naming both files; a v6
 * header's time zone turns every time into UTC. */
#include "vsv_convert.h"
#include "vsv_format.h"
#include "vsv_testlib.h"
#include "vsv_uamiv.h"

#include "vsv_source_internal.h"

#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static void values(void *ctx, int hour, int spec, int layer, float *plane)
{
    (void)ctx;
    for (int i = 0; i < 20; i++)
        plane[i] = (float)(1e-3 * (1 + spec) + 1e-4 * layer + 1e-5 * hour + 1e-6 * i);
}

/* A 5 x 4 x nz AVERAGE file of nh hours from 2002-06-03 00:00 (local). */
static const char *write_avrg(const char *name, int nz, int nh, int v6, int zone)
{
    vsv_uamiv_header h;
    memset(&h, 0, sizeof h);
    snprintf(h.name, sizeof h.name, "AVERAGE");
    snprintf(h.note, sizeof h.note, "Vesuvius test: beside the real met samples");
    char sp[2][11] = {"O3", "NO2"};
    h.species = sp;
    h.nspec = 2;
    h.nseg_or_tz = v6 ? zone : 1;
    h.bdate = h.edate = 2154;
    h.bhour = 0;
    h.ehour = (float)nh;
    h.xorg = 0;
    h.yorg = 0;
    h.dx = h.dy = 4000;
    h.nx = 5;
    h.ny = 4;
    h.nz = nz;
    h.nhours = nh;
    if (v6) {
        h.iproj = 2, h.plon = -97, h.plat = 40, h.tlat1 = 33, h.tlat2 = 45;
    }
    h.rec3[0] = h.rec3[1] = 1, h.rec3[2] = 5, h.rec3[3] = 4;
    int dates[20];
    float hours[20];
    for (int t = 0; t < nh; t++) {
        dates[2 * t] = dates[2 * t + 1] = 2154;
        hours[2 * t] = (float)t;
        hours[2 * t + 1] = (float)t + 1;
    }
    const char *path = vsv_test_tmp(name);
    return vsv_uamiv_write(path, &h, 0, dates, hours, values, NULL) ? NULL : path;
}

/* Field f of a real companion: layer k, hour t, cell c, read here directly
 * from its big-endian records (rec: record index; skip: bytes before the plane). */
static float raw(const char *rel, int rec, int skip, int c)
{
    size_t n;
    unsigned char *d = vsv_test_slurp(vsv_test_shared(rel), &n);
    size_t at = 0;
    float v = NAN;
    for (int r = 0; d && at + 8 <= n; r++) {
        const uint32_t len = (uint32_t)d[at] << 24 | d[at + 1] << 16 | d[at + 2] << 8 | d[at + 3];
        if (r == rec) {
            const unsigned char *p = d + at + 4 + skip + 4 * c;
            const uint32_t u = (uint32_t)p[0] << 24 | p[1] << 16 | p[2] << 8 | p[3];
            memcpy(&v, &u, 4);
            break;
        }
        at += 8 + len;
    }
    free(d);
    return v;
}

static void test_met_dir(void)
{
    const char *avrg = write_avrg("met.avrg", 3, 2, 0, 0);
    vsv_source_opts o;
    vsv_source_opts_init(&o);
    o.met = vsv_test_shared("camx");
    o.vertical = VSV_VERT_NATIVE;
    vsv_source *s = NULL;
    int rc = vsv_source_open(avrg, &o, &s);
    CHECK(rc == 0, "an average file with --met ../shared/data/camx opens", "(%s)", vsv_source_error(s));
    if (rc) {
        vsv_source_free(s);
        return;
    }
    /* the cloud/rain sample holds 5 fields per layer (INPUT-FORMATS.md says 4):
     * cloud, rain, snow, graupel water and the optical depth */
    const char *want[] = {"O3", "NO2", "CWC", "RWC", "SWC", "GWC", "COD", "PRESS", "HUMIDITY", "TEMP", "KV", "U", "V"};
    int ok = vsv_source_nfields(s) == 13;
    for (int i = 0; i < 13 && ok; i++)
        ok &=
            vsv_source_find_field(s, want[i]) >= 0 && vsv_source_field(s, vsv_source_find_field(s, want[i]))->is_volume;
    CHECK(ok, "companions found by content: cloud/rain, height/pressure, humidity, temperature, Kv, wind", "%d fields",
          vsv_source_nfields(s));
    const vsv_meta *g = vsv_source_grid(s);
    /* layer-middle heights from the real ZP file: layer 0 is half its top */
    const float top0 = raw("camx/test.height_pressure", 0, 8, 0);
    CHECK(g->vert_kind == VSV_VERT_NATIVE && g->nz == 3 && g->levels && g->levels[0] > 10 && g->levels[0] < 20 &&
              fabsf(top0 - 33.87f) < 0.01f && vsv_meta_attr(g, "heights"),
          "real layer heights from test.height_pressure", "levels %g (top0 %g)", g->levels ? g->levels[0] : 0, top0);
    CHECK(vsv_meta_above_ground(g), "CAMx heights from ZP (no terrain) are marked as above the ground");
    float vol[60];
    /* U of hour 1, layer 2, cell 7: wind record 8 (time) + 1 + 2*2 */
    rc = vsv_source_read(s, vsv_source_find_field(s, "U"), 1, vol);
    const float u = raw("camx/test.wind", 8 + 1 + 4, 0, 7);
    CHECK(rc == 0 && vol[2 * 20 + 7] == u && isfinite(u), "U (hour 1, layer 2) is the wind file's", "%g vs %g",
          vol[2 * 20 + 7], u);
    rc = vsv_source_read(s, vsv_source_find_field(s, "TEMP"), 0, vol);
    const float tk = raw("camx/test.temperature", 1 + 1, 8, 3); /* after Tsurf */
    CHECK(rc == 0 && vol[20 + 3] == tk && tk > 250 && tk < 320, "TEMP (hour 0, layer 1) skips the surface record",
          "%g vs %g", vol[23], tk);
    rc = vsv_source_read(s, vsv_source_find_field(s, "COD"), 1, vol);
    const float rw = raw("camx/test.cloud_rain", 1 + 16 + 1 + 0 * 5 + 4, 0, 1);
    CHECK(rc == 0 && vol[1] == rw && rw > 2, "COD (hour 1, layer 0) is the cloud/rain file's fifth field", "%g vs %g",
          vol[1], rw);
    CHECK(vsv_source_time(s, 1) == vsv_time_from_civil(2002, 6, 3, 1, 0, 0), "v5 hours stay as written");
    vsv_source_free(s);
    /* the same through a run, on even heights: U and V by name */
    vsv_source_opts_init(&o);
    o.met = vsv_test_shared("camx");
    o.vertical = VSV_VERT_EVEN;
    vsv_run *r = NULL;
    const char *paths[] = {avrg};
    rc = vsv_run_open(paths, 1, &o, "O3,U,V", NULL, &r);
    CHECK(rc == 0 && vsv_run_meta(r)->nvars == 3 && vsv_run_meta(r)->vert_kind == VSV_VERT_EVEN,
          "O3 with U and V on even heights found by --met", "(%s)", vsv_run_error(r));
    vsv_run_free(r);
}

static void test_mismatch(void)
{
    vsv_source_opts o;
    vsv_source_opts_init(&o);
    vsv_source *s = NULL;
    /* the real 1-layer, 1-hour average beside 3-layer companions: CAMx
     * writes the surface layer alone unless asked for 3-D output, so the
     * companions' lowest layer is read (it was refused) */
    const char *real = vsv_test_shared("camx/test.uamiv");
    o.met = vsv_test_shared("camx");
    int rc = vsv_source_open(real, &o, &s);
    CHECK(rc == 0, "--met with 3-layer companions for the real 1-layer average opens", "(%s)", vsv_source_error(s));
    if (!rc) {
        const vsv_meta *g = vsv_source_grid(s);
        const float top0 = raw("camx/test.height_pressure", 0, 8, 0);
        CHECK(g->nz == 1 && g->levels && fabs(g->levels[0] - top0 / 2) < 1, "... on the companions' lowest layer",
              "nz %d, level %g, top %g", g->nz, g->levels ? g->levels[0] : 0, top0);
        float vol[20];
        const char *name[] = {"TEMP", "PRESS", "U", "V", "CWC", "KV"};
        const char *file[] = {"temperature", "height_pressure", "wind", "wind", "cloud_rain", "vertical_diffusivity"};
        const int rec[] = {1, 1, 1, 2, 2, 0}, skip[] = {8, 8, 0, 0, 0, 8};
        for (int i = 0; i < 6; i++) {
            char rel[64];
            snprintf(rel, sizeof rel, "camx/test.%s", file[i]);
            const float want = raw(rel, rec[i], skip[i], 7);
            const int f = vsv_source_find_field(s, name[i]);
            rc = f < 0 ? -1 : vsv_source_read(s, f, 0, vol);
            CHECK(rc == 0 && vol[7] == want && isfinite(want), "... its layer 1 of each companion",
                  "%s: rc %d, %g vs %g in %s", name[i], rc, vol[7], want, rel);
        }
    }
    vsv_source_free(s);
    /* an average file of more layers than the companions is refused */
    const char *four = write_avrg("four.avrg", 4, 2, 0, 0);
    o.met = NULL;
    o.heights = vsv_test_shared("camx/test.height_pressure");
    rc = vsv_source_open(four, &o, &s);
    CHECK(rc == VSV_EINVAL && strstr(vsv_source_error(s), "test.height_pressure") &&
              strstr(vsv_source_error(s), "four.avrg") && strstr(vsv_source_error(s), "fewer layers"),
          "--heights with 3 layers for a 4-layer file is refused naming both", "(%s)", vsv_source_error(s));
    vsv_source_free(s);
    o.heights = NULL;
    o.met = vsv_test_shared("camx");
    rc = vsv_source_open(four, &o, &s);
    CHECK(rc == VSV_EINVAL && strstr(vsv_source_error(s), "four.avrg") && strstr(vsv_source_error(s), "companion"),
          "--met with 3-layer companions for a 4-layer file is refused naming both", "(%s)", vsv_source_error(s));
    vsv_source_free(s);
    /* right layers, wrong hours: 3 hours against 2 */
    const char *three = write_avrg("three.avrg", 3, 4, 0, 0);
    o.met = NULL;
    o.heights = vsv_test_shared("camx/test.height_pressure");
    rc = vsv_source_open(three, &o, &s);
    CHECK(rc == VSV_EINVAL && strstr(vsv_source_error(s), "test.height_pressure has 2 hours, this file 4"),
          "a height/pressure file of other hours is refused", "(%s)", vsv_source_error(s));
    vsv_source_free(s);
    /* the ZP file given where a wind file is: --heights wants height/pressure */
    o.heights = vsv_test_shared("camx/test.wind");
    rc = vsv_source_open(write_avrg("met2.avrg", 3, 2, 0, 0), &o, &s);
    CHECK(rc == VSV_EINVAL && strstr(vsv_source_error(s), "a wind file, not a height/pressure file"),
          "--heights given a wind file is refused by kind", "(%s)", vsv_source_error(s));
    vsv_source_free(s);
}

static void test_zone(void)
{
    const char *v6 = write_avrg("zone6.avrg", 3, 2, 1, 6);
    vsv_source *s = NULL;
    int rc = vsv_source_open(v6, NULL, &s);
    CHECK(rc == 0 && vsv_source_time(s, 0) == vsv_time_from_civil(2002, 6, 3, 6, 0, 0) &&
              vsv_source_time(s, 1) == vsv_time_from_civil(2002, 6, 3, 7, 0, 0),
          "v6 header with time zone 6: local 00:00 is 06:00 UTC", "(%s) %lld", vsv_source_error(s),
          rc ? 0LL : (long long)vsv_source_time(s, 0));
    const char *z = rc ? NULL : vsv_meta_attr(vsv_source_grid(s), "time zone");
    CHECK(z && strstr(z, "6 (the file's hours are UTC-6"), "the zone is recorded", "%s", z ? z : "(none)");
    vsv_source_free(s);
    /* and with companions: their stamps are local like the file's */
    vsv_source_opts o;
    vsv_source_opts_init(&o);
    o.met = vsv_test_shared("camx");
    rc = vsv_source_open(v6, &o, &s);
    CHECK(rc == 0 && vsv_source_time(s, 1) == vsv_time_from_civil(2002, 6, 3, 7, 0, 0),
          "v6 zone 6 with its companions: hours matched locally, times UTC", "(%s)", vsv_source_error(s));
    vsv_source_free(s);
    const char *bad = write_avrg("zone99.avrg", 3, 2, 1, 99);
    rc = vsv_source_open(bad, NULL, &s);
    CHECK(rc == VSV_ECORRUPT && strstr(vsv_source_error(s), "time zone 99"), "a time zone of 99 hours is refused",
          "(%s)", vsv_source_error(s));
    vsv_source_free(s);
}

static int count_frames(void *ctx, int64_t t, const float *const *f)
{
    (void)t, (void)f;
    ++*(int *)ctx;
    return 0;
}

/* --interp advect with CAMx: the wind companion's U and V are the winds
 * (no vertical wind in CAMx: horizontal motion only). */
static void test_advect_winds(void)
{
    const char *avrg = write_avrg("adv.avrg", 3, 2, 0, 0);
    const char *paths[1] = {avrg};
    vsv_source_opts o;
    vsv_source_opts_init(&o);
    o.met = vsv_test_shared("camx");
    o.vertical = VSV_VERT_NATIVE;
    vsv_run *r = NULL;
    int rc = vsv_run_open(paths, 1, &o, "O3,NO2", NULL, &r);
    if (!rc)
        rc = vsv_run_add_winds(r, NULL, &o);
    const vsv_meta *m = rc ? NULL : vsv_run_meta(r);
    CHECK(m && m->nvars == 4 && !strcmp(m->vars[2].name, VSV_WIND_U) && !strcmp(m->vars[3].name, VSV_WIND_V) &&
              strstr(vsv_meta_attr(m, VSV_WINDS_ATTR), "U V of test.wind (CAMx"),
          "advect: CAMx winds from the real wind companion (U, V; no W)", "(%s)", rc ? vsv_run_error(r) : "");
    if (m) {
        float *f[2][4];
        for (int t = 0; t < 2; t++)
            for (int v = 0; v < 4; v++)
                f[t][v] = malloc(60 * sizeof(float));
        int frames = 0, ok = !vsv_run_read(r, 0, f[0]) && !vsv_run_read(r, 1, f[1]);
        const float u = raw("camx/test.wind", 8 + 1 + 4, 0, 7); /* hour 1, layer 2, cell 7 */
        ok &= f[1][2][2 * 20 + 7] == u;
        vsv_interp_opts io = {VSV_TIME_ADVECT, 1};
        vsv_interp *ip = NULL;
        vsv_meta out;
        vsv_meta_init(&out);
        ok &= !vsv_interp_open(600, m, &io, count_frames, &frames, &ip) && !vsv_interp_meta(ip, m, &out) &&
              !vsv_interp_push(ip, vsv_run_time(r, 0), (const float *const *)f[0]) &&
              !vsv_interp_push(ip, vsv_run_time(r, 1), (const float *const *)f[1]);
        CHECK(ok && frames == 7 && out.nvars == 2 &&
                  strstr(vsv_meta_attr(&out, "time interpolation"), "horizontal only"),
              "advect: CAMx O3, NO2 every 10 minutes along the wind file's U V", "%d frames", frames);
        vsv_interp_free(ip);
        vsv_meta_clear(&out);
        for (int t = 0; t < 2; t++)
            for (int v = 0; v < 4; v++)
                free(f[t][v]);
    }
    vsv_run_free(r);
}

/* The stored winds of a CAMx run with --met: the wind companion's U and V,
 * and the attribute saying where they came from names it (it named the
 * average file). */
static void test_stored_winds(void)
{
    const char *avrg = write_avrg("store.avrg", 3, 2, 0, 0);
    const char *paths[1] = {avrg};
    vsv_source_opts o;
    vsv_source_opts_init(&o);
    o.met = vsv_test_shared("camx");
    vsv_run *r = NULL;
    int rc = vsv_run_open(paths, 1, &o, "O3", NULL, &r);
    if (!rc)
        rc = vsv_run_store_winds(r, NULL, &o);
    const vsv_meta *m = rc ? NULL : vsv_run_meta(r);
    const char *from = m ? vsv_meta_attr(m, VSV_WIND_SOURCE_ATTR) : NULL;
    CHECK(from && strstr(from, "U V (CAMx UAM-IV") && strstr(from, ") of test.wind") && !strstr(from, "store.avrg"),
          "stored CAMx winds: their source names the wind file", "(%s)", from ? from : vsv_run_error(r));
    vsv_run_free(r);
}

/* A FIFO where the land-use file is read: refused at open, naming it (a
 * plain fopen blocked on it for good: the alarm ends that as a failure). */
static void test_landuse_fifo(void)
{
    char dir[] = "/tmp/vsv-test-camxlu.XXXXXX", fifo[64];
    if (!mkdtemp(dir)) {
        CHECK(0, "a temporary folder");
        return;
    }
    snprintf(fifo, sizeof fifo, "%s/lu.fifo", dir);
    CHECK(!mkfifo(fifo, 0600), "a FIFO");
    vsv_source *s = calloc(1, sizeof *s);
    snprintf(s->path, sizeof s->path, "avrg.uamiv");
    s->grid.nx = 5;
    s->grid.ny = 4;
    alarm(60);
    const int rc = vsv_camx_landuse(s, fifo);
    alarm(0);
    CHECK(rc == VSV_EIO, "a land-use FIFO is refused", "(rc %d)", rc);
    CHECK(strstr(s->err, fifo) && strstr(s->err, "a FIFO, not a regular file: refused"),
          "naming the FIFO and what it is", "(%s)", s->err);
    free(s);
    unlink(fifo);
    rmdir(dir);
}

/* --derive on CAMx met (vsv_run_add_derived): theta and rh from TEMP,
 * HUMIDITY (ppm) and PRESS (mb) at every cell, against the formulas of
 * vsv-convert(1) computed here; condensate refused naming what it looks for. */
static void test_derive_met(void)
{
    const char *avrg = write_avrg("derive.avrg", 3, 2, 0, 0);
    vsv_source_opts o;
    vsv_source_opts_init(&o);
    o.met = vsv_test_shared("camx");
    vsv_run *r = NULL;
    const char *paths[] = {avrg};
    int rc = vsv_run_open(paths, 1, &o, "TEMP,HUMIDITY,PRESS", NULL, &r);
    if (!rc)
        rc = vsv_run_add_derived(r, "theta");
    if (!rc)
        rc = vsv_run_add_derived(r, "rh");
    if (!CHECK(rc == 0 && vsv_run_meta(r)->nvars == 5, "CAMx --met: --derive theta and rh", "(%s)", vsv_run_error(r))) {
        vsv_run_free(r);
        return;
    }
    CHECK(vsv_run_add_derived(r, "condensate") == VSV_ENOTFOUND &&
              strstr(vsv_run_error(r), "no hydrometeor mixing ratio"),
          "CAMx: condensate refused naming the mixing ratios it looks for", "(%s)", vsv_run_error(r));
    const vsv_meta *m = vsv_run_meta(r);
    const size_t n = (size_t)m->nx * m->ny * m->nz;
    float *f[5];
    for (int v = 0; v < 5; v++)
        f[v] = malloc(n * sizeof(float));
    double worst[2] = {0, 0};
    for (int t = 0; t < vsv_run_nframes(r) && f[4]; t++) {
        rc |= vsv_run_read(r, t, f);
        for (size_t c = 0; c < n && !rc; c++) {
            const double T = f[0][c], h = f[1][c], p = f[2][c] * 100.0;
            const double th = T * pow(100000 / p, 0.2857);
            const double rh = 100 * (h * 1e-6 * p) / (611.2 * exp(17.67 * (T - 273.15) / (T - 29.65)));
            /* NaN compares false: counted as a difference of 1 */
            worst[0] = fmax(worst[0], fabs(f[3][c] - th) / th < 1e-6 ? fabs(f[3][c] - th) / th : 1);
            worst[1] = fmax(worst[1], fabs(f[4][c] - rh) / rh < 1e-6 ? fabs(f[4][c] - rh) / rh : 1);
        }
    }
    CHECK(rc == 0 && worst[0] < 1e-6 && worst[1] < 1e-6 && f[0][0] > 200,
          "CAMx: theta = TEMP*(100000/(PRESS*100))^0.2857, rh from HUMIDITY ppm, every cell of both hours",
          "(rc %d, relative differences %g %g)", rc, worst[0], worst[1]);
    for (int v = 0; v < 5; v++)
        free(f[v]);
    vsv_run_free(r);
}

int main(void)
{
    test_landuse_fifo();
    test_met_dir();
    test_advect_winds();
    test_stored_winds();
    test_mismatch();
    test_zone();
    test_derive_met();
    return vsv_test_done();
}
