/* test_camx.c — the CAMx UAM-IV reader: the real test.uamiv (header, 21
 * species, known NO2 values, boundary zeros), a UAM-IV writer that reproduces
 * it byte for byte, then larger multi-layer, multi-hour files (v5 and v6
 * headers, both byte orders) with a matching height/pressure file, and bad
 * sizes. */
#include "vsv_convert.h"
#include "vsv_format.h"
#include "vsv_testlib.h"
#include "vsv_uamiv.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* ------------------------------------------- writers (ZP here, UAM-IV in the library) */

typedef struct w {
    FILE *fp;
    int le;
} w_t;

static void w32(w_t *w, uint32_t v)
{
    unsigned char b[4];
    if (w->le)
        b[0] = (unsigned char)v, b[1] = (unsigned char)(v >> 8), b[2] = (unsigned char)(v >> 16),
        b[3] = (unsigned char)(v >> 24);
    else
        b[0] = (unsigned char)(v >> 24), b[1] = (unsigned char)(v >> 16), b[2] = (unsigned char)(v >> 8),
        b[3] = (unsigned char)v;
    fwrite(b, 1, 4, w->fp);
}
static void wf(w_t *w, float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    w32(w, u);
}
typedef float (*value_fn)(int hour, int spec, int layer, int i, int j);

/* Adapters from the tests' value sources to the library writer. */
typedef struct src_ctx {
    value_fn fn;
    vsv_uamiv *from;
    int nx, ny;
} src_ctx;

static void fill(void *p, int hour, int spec, int layer, float *plane)
{
    src_ctx *c = p;
    if (c->from) {
        vsv_uamiv_read(c->from, hour, spec, layer, plane);
        return;
    }
    for (int j = 0; j < c->ny; j++)
        for (int i = 0; i < c->nx; i++)
            plane[j * c->nx + i] = c->fn(hour, spec, layer, i, j);
}

static void write_uamiv(const char *path, const vsv_uamiv_header *h, int le, const int *dates, const float *hours,
                        value_fn val, vsv_uamiv *copy_from)
{
    src_ctx c = {val, copy_from, h->nx, h->ny};
    vsv_uamiv_write(path, h, le, dates, hours, fill, &c);
}

/* ZP: per hour and layer, height (layer top, m above ground) then pressure */
/* Stamped like CAMx: hour t at the average's begin time (HHMM, YYJJJ). */
static void write_zp(const char *path, int nx, int ny, int nz, int nh, int le, const int *dates, const float *hours)
{
    w_t w = {fopen(path, "wb"), le};
    for (int t = 0; t < nh; t++)
        for (int k = 0; k < nz; k++)
            for (int what = 0; what < 2; what++) {
                const uint32_t n = (uint32_t)(8 + 4 * nx * ny);
                w32(&w, n);
                const float h = hours[2 * t];
                wf(&w, floorf(h) * 100 + roundf((h - floorf(h)) * 60));
                w32(&w, (uint32_t)dates[2 * t]);
                for (int j = 0; j < ny; j++)
                    for (int i = 0; i < nx; i++)
                        wf(&w, what ? 1000.0f - 50 * k : (float)(50.0 * (k + 1) * (k + 1) + i + j + t));
                w32(&w, n);
            }
    fclose(w.fp);
}

static float synth(int hour, int spec, int layer, int i, int j)
{
    if (i == 0 || j == 0)
        return 0; /* boundary cells of a master grid */
    return (float)((spec + 1) * 1e-3 * (1 + 0.1 * layer) * (1 + sin(0.3 * i + 0.2 * j + 0.5 * hour)));
}

static void test_real(void)
{
    const char *path = vsv_test_shared("camx/test.uamiv");
    vsv_uamiv *u = NULL;
    if (!CHECK(vsv_uamiv_open(path, &u) == 0, "test.uamiv opens", "%s", vsv_uamiv_error(u))) {
        vsv_uamiv_free(u);
        return;
    }
    const vsv_uamiv_header *h = vsv_uamiv_header_get(u);
    CHECK(!strcmp(h->name, "AVERAGE") && h->nspec == 21 && h->nx == 5 && h->ny == 4 && h->nz == 1 && h->nhours == 1 &&
              h->xorg == -792000 && h->yorg == -1656000 && h->dx == 36000 && !h->v6 && !h->little_endian,
          "test.uamiv header: AVERAGE, 21 species, 5x4x1, 1 hour, 36 km, CAMx 5, big-endian");
    CHECK(!strcmp(h->note, "CAMx 5.40 Test Problem -- Mech6 CF CB05 v5.40.midwest.36.12."), "note read", "'%s'",
          h->note);
    const char *names[21] = {"NO",  "NO2",  "O3",   "SO2",  "H2O2", "HNO3", "NH3",  "PNO3", "PSO4", "PNH4", "POA",
                             "PEC", "FPRM", "CPRM", "CCRS", "FCRS", "SOA1", "SOA2", "SOA3", "SOA4", "SOA5"};
    int same = 1;
    for (int s = 0; s < 21; s++)
        same &= !strcmp(h->species[s], names[s]);
    CHECK(same, "the 21 species names");
    CHECK(vsv_uamiv_time(h->bdate, h->bhour) == vsv_time_from_civil(2002, 6, 3, 0, 0, 0),
          "YYJJJ 02154 0.0 h = 2002-06-03 00Z");
    float no2[20];
    vsv_uamiv_read(u, 0, 1, 0, no2);
    const float want[4] = {1.24175494e-04f, 2.79196858e-04f, 1.01672206e-03f, 4.36782313e-04f};
    int known = 1, zeros = 1;
    for (int i = 1; i < 5; i++)
        known &= no2[1 * 5 + i] == want[i - 1];
    for (int i = 0; i < 5; i++)
        zeros &= no2[i] == 0;
    for (int j = 0; j < 4; j++)
        zeros &= no2[j * 5] == 0;
    CHECK(known, "NO2 row 2, x = 2..5 equal the known values", "%g %g %g %g", no2[6], no2[7], no2[8], no2[9]);
    CHECK(zeros, "row 1 and column 1 are 0 (boundary)");
    /* the writer reproduces the file byte for byte from what the reader read */
    int dates[2];
    float hours[2];
    vsv_uamiv_hour(u, 0, &dates[0], &hours[0], &dates[1], &hours[1]);
    const char *copy = vsv_test_tmp("copy.uamiv");
    write_uamiv(copy, h, 0, dates, hours, NULL, u);
    size_t n1, n2;
    unsigned char *a = vsv_test_slurp(path, &n1), *b = vsv_test_slurp(copy, &n2);
    CHECK(a && b && n1 == n2 && !memcmp(a, b, n1), "a UAM-IV writer reproduces test.uamiv byte for byte", "%zu vs %zu",
          n1, n2);
    free(a);
    free(b);
    /* through the source: units per species kind, values */
    vsv_source *src = NULL;
    vsv_source_open(path, NULL, &src);
    const vsv_field_info *fo3 = vsv_source_field(src, vsv_source_find_field(src, "O3"));
    const vsv_field_info *fpso4 = vsv_source_field(src, vsv_source_find_field(src, "PSO4"));
    CHECK(!strcmp(fo3->units, "ppm") && !strcmp(fpso4->units, "ug/m3"), "units: ppm for gases, ug/m3 for aerosols");
    CHECK(vsv_source_grid(src)->vert_kind == VSV_VERT_INDEX && vsv_source_grid(src)->proj.kind == VSV_PROJ_NONE,
          "without heights and projection: layer index, no projection");
    int nt = vsv_source_ntimes(src);
    CHECK(!vsv_source_field(src, vsv_source_find_field(src, "NOPE")) &&
              !vsv_source_field(src, vsv_source_nfields(src)) && !vsv_source_time(src, nt) &&
              !vsv_source_time(src, -1) && vsv_source_time(src, nt - 1) > 0,
          "a field or time outside the source is NULL / 0");
    vsv_source_free(src);
    vsv_uamiv_free(u);
}

/* The header of test file `variant`: v6 (bit 0) with a zone and a projection, 40x30x6 cells, 25 hours, the
 * three species named in sp (borrowed by h). */
static void written_header(vsv_uamiv_header *h, int variant, char (*sp)[11])
{
    const int v6 = variant & 1;
    memset(h, 0, sizeof *h);
    snprintf(h->name, sizeof h->name, "AVERAGE");
    snprintf(h->note, sizeof h->note, "Vesuvius test file %d", variant);
    h->nseg_or_tz = v6 ? 5 : 1;
    h->nspec = 3;
    h->species = sp;
    h->bdate = 2154;
    h->edate = 2155;
    h->bhour = 0;
    h->ehour = 1.5f;
    h->xorg = -900000;
    h->yorg = -600000;
    h->dx = h->dy = 12000;
    h->nx = 40;
    h->ny = 30;
    h->nz = 6;
    h->nhours = 25;
    if (v6) {
        h->iproj = 2;
        h->plon = -97;
        h->plat = 40;
        h->tlat1 = 33;
        h->tlat2 = 45;
    }
    h->rec3[0] = h->rec3[1] = 1;
    h->rec3[2] = h->nx;
    h->rec3[3] = h->ny;
}

/* even heights from the ZP file through a .vsv */
static void written_even_vsv(const char *path, vsv_source_opts *so)
{
    const char *out = vsv_test_tmp("camx.vsv");
    so->vertical = VSV_VERT_EVEN;
    so->nz = 20;
    vsv_run *run = NULL;
    const char *paths[] = {path};
    int rc = vsv_run_open(paths, 1, so, "O3", NULL, &run);
    if (!rc) {
        const vsv_meta *m = vsv_run_meta(run);
        float *f[1] = {malloc((size_t)40 * 30 * 20 * 4)};
        vsv_writer *wr = NULL;
        rc = vsv_writer_create(out, m, NULL, &wr);
        for (int i = 0; !rc && i < vsv_run_nframes(run); i++)
            if (!(rc = vsv_run_read(run, i, f)))
                rc = vsv_writer_add_step(wr, vsv_run_time(run, i), (const float *const *)f);
        if (!rc)
            rc = vsv_writer_finish(wr, NULL, NULL);
        vsv_writer_free(wr);
        free(f[0]);
    }
    vsv_file *vf = NULL;
    CHECK(rc == 0 && vsv_file_open(out, &vf) == 0 && vsv_file_check(vf, NULL, NULL) == 0,
          "CAMx on even heights packs into a checked .vsv", "%s", vsv_run_error(run));
    vsv_file_free(vf);
    vsv_run_free(run);
}

/* One written file (v5 or v6 by bit 0 of variant, little-endian by bit 1) with its ZP file: opens with heights,
 * times, projection and every value as written; the last variant also packs into a .vsv. */
static void written_variant(int variant)
{
    const int v6 = variant & 1, le = variant >> 1;
    vsv_uamiv_header h;
    char sp[3][11] = {"O3", "NO2", "PSO4"};
    written_header(&h, variant, sp);
    int dates[50];
    float hours[50];
    for (int t = 0; t < 25; t++) {
        dates[2 * t] = t < 24 ? 2154 : 2155;
        hours[2 * t] = (float)(t % 24) + (t == 3 ? 0.5f : 0); /* a half hour: 03:30 */
        dates[2 * t + 1] = dates[2 * t];
        hours[2 * t + 1] = hours[2 * t] + 1;
    }
    char label[200];
    const char *path = vsv_test_tmp(le ? "big-le.avrg" : "big-be.avrg"), *zp = vsv_test_tmp("big.zp");
    write_uamiv(path, &h, le, dates, hours, synth, NULL);
    write_zp(zp, h.nx, h.ny, h.nz, 25, le, dates, hours);
    vsv_source_opts so;
    vsv_source_opts_init(&so);
    so.heights = zp;
    so.vertical = VSV_VERT_NATIVE;
    vsv_source *src = NULL;
    int rc = vsv_source_open(path, &so, &src);
    snprintf(label, sizeof label, "v%s %s-endian 40x30x6, 25 hours, 3 species: opens with heights", v6 ? "6" : "5",
             le ? "little" : "big");
    if (!CHECK(rc == 0, label, "%s", vsv_source_error(src))) {
        vsv_source_free(src);
        return;
    }
    const vsv_meta *g = vsv_source_grid(src);
    const int64_t zone = v6 ? 5 * 3600 : 0; /* v6: hours in zone 5, times UTC */
    int ok = vsv_source_ntimes(src) == 25 && g->nz == 6 && g->vert_kind == VSV_VERT_NATIVE &&
             vsv_source_time(src, 3) == vsv_time_from_civil(2002, 6, 3, 3, 30, 0) + zone &&
             vsv_source_time(src, 24) == vsv_time_from_civil(2002, 6, 4, 0, 0, 0) + zone &&
             g->proj.kind == (v6 ? VSV_PROJ_LCC : VSV_PROJ_NONE) && g->origin[0] == -894000;
    /* mean layer-middle height of layer 2: tops 50*k^2 + i + j */
    double mean_top1 = 50 * 4 + (39 + 29) / 2.0, mean_top0 = 50 * 1 + (39 + 29) / 2.0;
    ok &= fabs(g->levels[1] - 0.5 * (mean_top0 + mean_top1)) < 1e-3;
    snprintf(label, sizeof label, "v%s %s-endian: times (decimal hours exact), projection %s, heights from ZP",
             v6 ? "6" : "5", le ? "little" : "big", v6 ? "from the header" : "none");
    CHECK(ok, label, "t3 %lld proj %d lev %g", (long long)vsv_source_time(src, 3), g->proj.kind, g->levels[1]);
    float *vol = malloc((size_t)40 * 30 * 6 * 4);
    int same = 1;
    for (int t = 0; t < 25; t += 6)
        for (int s = 0; s < 3; s++) {
            same &= vsv_source_read(src, s, t, vol) == 0;
            for (int k = 0; k < 6; k++)
                for (int j = 0; j < 30; j++)
                    for (int i = 0; i < 40; i++)
                        same &= vol[(k * 30 + j) * 40 + i] == synth(t, s, k, i, j);
        }
    snprintf(label, sizeof label, "v%s %s-endian: every value read back exactly", v6 ? "6" : "5",
             le ? "little" : "big");
    CHECK(same, label);
    free(vol);
    vsv_source_free(src);
    if (variant == 3)
        written_even_vsv(path, &so);
}

/* Damaged copies of the big-endian written file: a size that is not whole hours, a wrong record length, and
 * truncation at many lengths are errors that say what is wrong. */
static void written_damage(void)
{
    /* a size that does not divide into hours names expected and actual sizes */
    const char *path = vsv_test_tmp("big-be.avrg");
    size_t n;
    unsigned char *d = vsv_test_slurp(path, &n);
    const char *cut = vsv_test_tmp("cut.avrg");
    vsv_test_write(cut, d, n - 100);
    vsv_uamiv *u = NULL;
    int rc = vsv_uamiv_open(cut, &u);
    char want[200];
    snprintf(want, sizeof want, "file size %zu does not divide into hours", n - 100);
    CHECK(rc == VSV_ECORRUPT && strstr(vsv_uamiv_error(u), want) && strstr(vsv_uamiv_error(u), "expected"),
          "a size that does not divide evenly names the sizes", "%s", vsv_uamiv_error(u));
    vsv_uamiv_free(u);
    /* a data record of the wrong length */
    unsigned char *bad = malloc(n);
    memcpy(bad, d, n);
    const size_t first_data = 312 + 68 + 24 + (40 * 3 + 8) + 24; /* after the header and hour 0's time record */
    bad[first_data + 3] ^= 4;
    const char *badp = vsv_test_tmp("badrec.avrg");
    vsv_test_write(badp, bad, n);
    u = NULL;
    rc = vsv_uamiv_open(badp, &u);
    float plane[1200];
    if (!rc)
        rc = vsv_uamiv_read(u, 0, 0, 0, plane);
    CHECK(rc != 0 && strstr(vsv_uamiv_error(u), "record 6 at byte offset"), "a wrong record length names the record",
          "%s", vsv_uamiv_error(u));
    vsv_uamiv_free(u);
    /* truncation at many lengths: errors, never a crash */
    int errors = 0, tries = 0;
    for (size_t len = 0; len < n; len += 1237, tries++) {
        u = NULL;
        errors += vsv_uamiv_open_mem(d, len, "cut", &u) != 0;
        vsv_uamiv_free(u);
    }
    CHECK(errors == tries, "every truncation is an error", "%d of %d", errors, tries);
    free(bad);
    free(d);
}

static void test_written(void)
{
    for (int variant = 0; variant < 4; variant++)
        written_variant(variant);
    written_damage();
}

int main(void)
{
    test_real();
    test_written();
    return vsv_test_done();
}
