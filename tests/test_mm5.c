/* test_mm5.c — the MM5 v3 reader on the real files in ../shared/data/mm5:
 * the TERRAIN header and the 1 m latitude/longitude match, every field and
 * time of MMOUT, values through the .vsv, heights, interpolation, split runs,
 * and bad input (cut records, wrong kinds, sizes that disagree). */
#include "vsv_convert.h"
#include "vsv_format.h"
#include "vsv_mm5.h"
#include "vsv_testlib.h"

#include <math.h>
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

static void test_terrain(void)
{
    const char *path = vsv_test_shared("mm5/TERRAIN_DOMAIN1");
    vsv_mm5 *m = NULL;
    if (vsv_test_absent(path, "the MM5 TERRAIN file"))
        return;
    if (!CHECK(vsv_mm5_open(path, &m) == 0, "TERRAIN_DOMAIN1 opens", "%s", vsv_mm5_error(m))) {
        vsv_mm5_free(m);
        return;
    }
    CHECK(vsv_mm5_bhi(m, 1, 1) == 1 && vsv_mm5_bhi(m, 16, 1) == 143 && vsv_mm5_bhi(m, 17, 1) == 208,
          "TERRAIN: program 1, 143 x 208 dot points");
    CHECK(vsv_mm5_bhi(m, 7, 1) == 1 && vsv_mm5_bhr(m, 2, 1) == 38 && vsv_mm5_bhr(m, 3, 1) == -97 &&
              vsv_mm5_bhr(m, 5, 1) == 50 && vsv_mm5_bhr(m, 6, 1) == 33 && vsv_mm5_bhr(m, 9, 1) == 32000,
          "TERRAIN: Lambert conformal, centre 38N 97W, true latitudes 50/33, 32 km");
    CHECK(vsv_mm5_nfields(m) == 24 && vsv_mm5_nperiods(m) == 1, "TERRAIN: 24 fields, one period", "%d %d",
          vsv_mm5_nfields(m), vsv_mm5_nperiods(m));
    vsv_source *src = NULL;
    int rc = vsv_source_open(path, NULL, &src);
    if (!CHECK(rc == 0, "TERRAIN opens as a source", "%s", vsv_source_error(src))) {
        vsv_source_free(src);
        vsv_mm5_free(m);
        return;
    }
    const vsv_meta *g = vsv_source_grid(src);
    CHECK(g->nx == 207 && g->ny == 142 && g->proj.kind == VSV_PROJ_LCC, "TERRAIN grid: 207 x 142 cross cells, lcc");
    const int IX = 143, JX = 208;
    float *lat = malloc(IX * JX * 4), *lon = malloc(IX * JX * 4), *ter = malloc(IX * JX * 4);
    vsv_mm5_read(m, vsv_mm5_field_at(m, vsv_mm5_find(m, 0, "LATITCRS")), lat);
    vsv_mm5_read(m, vsv_mm5_field_at(m, vsv_mm5_find(m, 0, "LONGICRS")), lon);
    vsv_mm5_read(m, vsv_mm5_field_at(m, vsv_mm5_find(m, 0, "TERRAIN")), ter);
    /* MM5 computed and stored these in float32: its own values scatter by up
     * to ~2 m around the exact projection (storage rounding alone is ~0.5 m).
     * So: no bias, 1 m for nearly all cells, 2.5 m for every cell. */
    double worst = 0, sx = 0, sy = 0, ss = 0;
    int within1 = 0, cnt = 0;
    for (int J = 0; J < JX - 1; J++)
        for (int I = 0; I < IX - 1; I++) {
            double la, lo, x, y;
            const double gx = g->origin[0] + J * g->spacing[0], gy = g->origin[1] + I * g->spacing[1];
            vsv_proj_inverse(&g->proj, gx, gy, &la, &lo);
            const double e = dist_m(la, lo, lat[J * IX + I], lon[J * IX + I]);
            worst = fmax(worst, e);
            within1 += e <= 1.0;
            cnt++;
            vsv_proj_forward(&g->proj, lat[J * IX + I], lon[J * IX + I], &x, &y);
            sx += x - gx;
            sy += y - gy;
            ss += e * e;
        }
    CHECK(worst < 2.5, "computed lat/lon of every cross cell within 2.5 m of LATITCRS/LONGICRS", "worst %.3f m", worst);
    CHECK(within1 >= cnt * 0.9, "90 % of cross cells within 1 m", "%d of %d", within1, cnt);
    CHECK(fabs(sx / cnt) < 0.25 && fabs(sy / cnt) < 0.25, "no systematic offset (mean under 0.25 m)", "%.3f %.3f",
          sx / cnt, sy / cnt);
    printf("  cross points: worst %.3f m, rms %.3f m, %.1f %% within 1 m, mean offset (%.3f, %.3f) m\n", worst,
           sqrt(ss / cnt), 100.0 * within1 / cnt, sx / cnt, sy / cnt);
    /* dot points too */
    vsv_mm5_read(m, vsv_mm5_field_at(m, vsv_mm5_find(m, 0, "LATITDOT")), lat);
    vsv_mm5_read(m, vsv_mm5_field_at(m, vsv_mm5_find(m, 0, "LONGIDOT")), lon);
    worst = 0;
    for (int J = 0; J < JX; J++)
        for (int I = 0; I < IX; I++) {
            double la, lo;
            vsv_proj_inverse(&g->proj, g->origin[0] - g->spacing[0] / 2 + J * g->spacing[0],
                             g->origin[1] - g->spacing[1] / 2 + I * g->spacing[1], &la, &lo);
            worst = fmax(worst, dist_m(la, lo, lat[J * IX + I], lon[J * IX + I]));
        }
    CHECK(worst < 2.5, "computed lat/lon of every dot point within 2.5 m of LATITDOT/LONGIDOT", "worst %.3f m", worst);
    /* corners of the grid */
    double la, lo;
    vsv_proj_inverse(&g->proj, g->origin[0], g->origin[1], &la, &lo);
    CHECK(fabs(la - 13.624) < 0.01 && fabs(lo + 125.122) < 0.01, "SW corner cell at 13.62N 125.12W", "%f %f", la, lo);
    /* the 1e20 fill of the last row and column is not in the grid */
    int fill_in_file = ter[(JX - 1) * IX + 5] > 1e19 && ter[5 * IX + IX - 1] > 1e19;
    float tmax = 0;
    for (int i = 0; g->terrain && i < g->nx * g->ny; i++)
        tmax = fmaxf(tmax, g->terrain[i]);
    CHECK(fill_in_file && g->terrain && tmax > 1000 && tmax < 5000, "1e20 fill in the last row/column is ignored",
          "terrain max %g", tmax);
    free(lat);
    free(lon);
    free(ter);
    vsv_source_free(src);
    vsv_mm5_free(m);
}

/* every field of every period reads, with finite values; T at 3 h within its documented range */
static void mmout_fields(vsv_mm5 *m, float *buf)
{
    int finite = 1, read = 0;
    for (int i = 0; i < vsv_mm5_nfields(m); i++) {
        const vsv_mm5_field *f = vsv_mm5_field_at(m, i);
        vsv_mm5_read(m, f, buf);
        read++;
        if (!strcmp(f->order, "YXS") || !strcmp(f->order, "YXW"))
            for (size_t k = 0; k < f->bytes / 4; k++)
                finite &= isfinite(buf[k]);
    }
    CHECK(read == 204 && finite, "every field and time reads; 3-D fields finite");
    /* T at 3 h within the documented 208..303 K, CLW max 6.0e-4 */
    const vsv_mm5_field *ft = vsv_mm5_field_at(m, vsv_mm5_find(m, 3, "T"));
    vsv_mm5_read(m, ft, buf);
    float tmin = 1e9, tmax = -1e9;
    for (int k = 0; k < 15; k++)
        for (int J = 0; J < 207; J++)
            for (int I = 0; I < 142; I++) {
                float v = buf[(k * 208 + J) * 143 + I];
                tmin = fminf(tmin, v);
                tmax = fmaxf(tmax, v);
            }
    CHECK(tmin > 205 && tmin < 212 && tmax > 300 && tmax < 306, "T at 3 h spans 208..303 K", "%g..%g", tmin, tmax);
}

/* Samples of the written native .vsv against the MM5 values (U and W moved to the cross points and half
 * levels), each within the species' bound; vol is scratch for one volume. */
static void mmout_native_samples(vsv_mm5 *m, const char *out, float *vol, float *buf)
{
    vsv_file *f = NULL;
    vsv_decoder *d = NULL;
    int ok = vsv_file_open(out, &f) == 0 && vsv_decoder_create(f, &d) == 0;
    uint64_t rs = 99;
    const char *names[] = {"T", "CLW", "SNOW", "U", "W"};
    int within = 1, samples = 0;
    for (int t = 0; ok && t < 4; t++)
        for (int s = 0; s < 5; s++) {
            ok &= vsv_decoder_volume(d, t, s, vol) == 0;
            const vsv_mm5_field *mf = vsv_mm5_field_at(m, vsv_mm5_find(m, t, names[s]));
            vsv_mm5_read(m, mf, buf);
            const double bound = vsv_file_quant(f, s)->max_abs_error;
            for (int n = 0; n < 400; n++) {
                int i = (int)(vsv_test_rand(&rs) % 207), j = (int)(vsv_test_rand(&rs) % 142),
                    k = (int)(vsv_test_rand(&rs) % 15), kk = 14 - k;
                double want;
                if (s == 3) /* U: dot → cross */
                    want = 0.25 * ((double)buf[(kk * 208 + i) * 143 + j] + buf[(kk * 208 + i) * 143 + j + 1] +
                                   buf[(kk * 208 + i + 1) * 143 + j] + buf[(kk * 208 + i + 1) * 143 + j + 1]);
                else if (s == 4) /* W: full levels kk, kk+1 around half level kk */
                    want = 0.5 * ((double)buf[(kk * 208 + i) * 143 + j] + buf[((kk + 1) * 208 + i) * 143 + j]);
                else
                    want = buf[(kk * 208 + i) * 143 + j];
                double got = vol[((size_t)k * 142 + j) * 207 + i];
                within &= fabs(got - want) <= bound + 1e-6 * fabs(want);
                samples++;
            }
        }
    CHECK(ok && within, "sampled .vsv values equal MM5 values within the bound (T, CLW, SNOW, U dot->cross, W)",
          "%d samples", samples);
    vsv_decoder_free(d);
    vsv_file_free(f);
}

/* native conversion: .vsv values equal MM5 values within the bound; 0 if the run does not open */
static int mmout_native(vsv_mm5 *m, const char *path, const vsv_source_opts *so, float *buf)
{
    const char *out = vsv_test_tmp("mmout-native.vsv");
    vsv_run *run = NULL;
    const char *paths[] = {path};
    int rc = vsv_run_open(paths, 1, so, "T,CLW,SNOW,U,W", NULL, &run);
    if (!CHECK(rc == 0, "native run opens", "%s", vsv_run_error(run))) {
        vsv_run_free(run);
        return 0;
    }
    const vsv_meta *meta = vsv_run_meta(run);
    CHECK(meta->nz == 15 && meta->vert_kind == VSV_VERT_NATIVE && meta->levels, "native: 15 levels with heights");
    int mono = 1;
    for (int k = 1; k < 15; k++)
        mono &= meta->levels[k] > meta->levels[k - 1];
    CHECK(mono, "mean level heights increase upward");
    printf("  native mean heights: lowest %.0f m, top %.0f m\n", meta->levels[0], meta->levels[14]);
    const size_t cells = (size_t)meta->nx * meta->ny * meta->nz;
    float *fields[5];
    for (int v = 0; v < 5; v++)
        fields[v] = malloc(cells * 4);
    vsv_writer *w = NULL;
    rc = vsv_writer_create(out, meta, NULL, &w);
    for (int i = 0; !rc && i < vsv_run_nframes(run); i++) {
        rc = vsv_run_read(run, i, fields);
        if (!rc)
            rc = vsv_writer_add_step(w, vsv_run_time(run, i), (const float *const *)fields);
    }
    if (!rc)
        rc = vsv_writer_finish(w, NULL, NULL);
    CHECK(rc == 0, "native .vsv written", "%s %s", vsv_writer_error(w), vsv_run_error(run));
    vsv_writer_free(w);
    mmout_native_samples(m, out, fields[0], buf);
    unlink(out);
    for (int v = 0; v < 5; v++)
        free(fields[v]);
    vsv_run_free(run);
    return 1;
}

/* the even grid: 50 levels to the model top; a column's cells are empty below ground and filled above it */
static void mmout_even(const char *path, vsv_source_opts *so)
{
    vsv_source *src = NULL;
    so->vertical = VSV_VERT_EVEN;
    so->nz = 50;
    const int rc = vsv_source_open(path, so, &src);
    const vsv_meta *g = vsv_source_grid(src);
    CHECK(rc == 0 && g->nz == 50 && g->vert_kind == VSV_VERT_EVEN && g->spacing[2] > 250 && g->spacing[2] < 400,
          "even grid: 50 levels up to the model top");
    /* a column's even cells are empty below ground and filled above it */
    float *vol = malloc((size_t)g->nx * g->ny * g->nz * 4);
    vsv_source_read(src, vsv_source_find_field(src, "T"), 0, vol);
    int below_ok = 1, above_ok = 1;
    for (int j = 0; j < g->ny; j += 7)
        for (int i = 0; i < g->nx; i += 7) {
            const float ground = g->terrain[(size_t)j * g->nx + i];
            for (int k = 0; k < g->nz; k++) {
                const double z = g->origin[2] + k * g->spacing[2];
                const float v = vol[((size_t)k * g->ny + j) * g->nx + i];
                if (z < ground)
                    below_ok &= isnan(v);
                else if (z < 12000)
                    above_ok &= v > 180 && v < 320;
            }
        }
    CHECK(below_ok, "even cells below the terrain are empty (NaN)");
    CHECK(above_ok, "even cells above the terrain hold plausible temperatures");
    free(vol);
    vsv_source_free(src);
}

/* the native heights themselves, from the formula, per column: top near PTOP, lowest tens of metres up */
static void mmout_heights(vsv_mm5 *m, const char *path, vsv_source_opts *so)
{
    const double PTOP = vsv_mm5_bhr(m, 2, 2), P00 = vsv_mm5_bhr(m, 2, 5), TS0 = vsv_mm5_bhr(m, 3, 5),
                 A = vsv_mm5_bhr(m, 4, 5);
    const double lp = log(PTOP / P00);
    const double ztop = -((287.04 * A / (2 * 9.81)) * lp * lp + (287.04 * TS0 / 9.81) * lp);
    so->vertical = VSV_VERT_NATIVE;
    vsv_source *src = NULL;
    vsv_source_open(path, so, &src);
    const vsv_meta *g = vsv_source_grid(src);
    CHECK(g->levels[14] < ztop && g->levels[14] > ztop - 2000, "model top level near the PTOP height",
          "top %.0f m, PTOP at %.0f m", g->levels[14], ztop);
    const double agl = g->levels[0] - 0; /* mean over columns of the lowest level ASL */
    double tsum = 0;
    for (int c = 0; c < g->nx * g->ny; c++)
        tsum += g->terrain[c];
    const double lowest_agl = agl - tsum / (g->nx * g->ny);
    CHECK(lowest_agl > 10 && lowest_agl < 100, "lowest layer tens of metres above the terrain", "%.1f m", lowest_agl);
    printf("  lowest layer %.1f m above ground on average; model top %.0f m (PTOP height %.0f m)\n", lowest_agl,
           g->levels[14], ztop);
    vsv_source_free(src);
}

static void test_mmout(void)
{
    const char *path = vsv_test_shared("mm5/run1/MMOUT_DOMAIN1");
    vsv_mm5 *m = NULL;
    if (vsv_test_absent(path, "the real MM5 run"))
        return;
    if (!CHECK(vsv_mm5_open(path, &m) == 0, "MMOUT_DOMAIN1 opens", "%s", vsv_mm5_error(m))) {
        vsv_mm5_free(m);
        return;
    }
    CHECK(vsv_mm5_nperiods(m) == 4 && vsv_mm5_nfields(m) == 4 * 51, "MMOUT: 4 periods of 51 fields",
          "%d periods %d fields", vsv_mm5_nperiods(m), vsv_mm5_nfields(m));
    float *buf = malloc((size_t)143 * 208 * 16 * 4);
    mmout_fields(m, buf);
    vsv_source_opts so;
    vsv_source_opts_init(&so);
    so.vertical = VSV_VERT_NATIVE;
    if (mmout_native(m, path, &so, buf)) {
        /* heights: per column increasing, lowest level tens of metres above ground, top near PTOP */
        mmout_even(path, &so);
        mmout_heights(m, path, &so);
    }
    free(buf);
    vsv_mm5_free(m);
}

/* Interpolated frames equal the linear blend; originals pass unchanged. */
static float **last_frames;
static int64_t emitted[64];
static int nemitted;
static int collect(void *ctx, int64_t t, const float *const *f)
{
    float *store = ctx;
    emitted[nemitted] = t;
    memcpy(store + (size_t)nemitted * 4, f[0], 4 * sizeof(float));
    nemitted++;
    (void)last_frames;
    return 0;
}

static void test_interp(void)
{
    float store[64 * 4];
    vsv_interp *ip = NULL;
    vsv_interp_create(600, 1, 4, collect, store, &ip);
    float a[4] = {0, 1, NAN, 100}, b[4] = {6, -1, 5, 100.5f};
    const float *fa[1] = {a}, *fb[1] = {b};
    vsv_interp_push(ip, 3600, fa);
    vsv_interp_push(ip, 7200, fb);
    int ok = nemitted == 7 && emitted[0] == 3600 && emitted[6] == 7200 && emitted[1] == 4200;
    ok &= !memcmp(store, a, 12) && store[3] == 100 && !memcmp(store + 24, b, 16);
    for (int n = 1; n < 6; n++) {
        const double w = n / 6.0;
        ok &= store[n * 4 + 0] == (float)(0 + (6.0 - 0) * w) && store[n * 4 + 1] == (float)(1 + (-1.0 - 1) * w) &&
              isnan(store[n * 4 + 2]);
    }
    CHECK(ok, "interpolated frames equal the linear blend; originals pass through exactly", "%d frames", nemitted);
    vsv_interp_free(ip);
    /* a time step that does not divide the interval stays regular: the
     * original at 60 min is between steps and not output */
    nemitted = 0;
    vsv_interp_create(25 * 60, 1, 4, collect, store, &ip);
    vsv_interp_push(ip, 0, fa);
    vsv_interp_push(ip, 3600, fb);
    CHECK(nemitted == 3 && emitted[1] == 1500 && emitted[2] == 3000 && vsv_interp_dropped(ip) == 1,
          "25 min steps: 0, 25, 50 min, the original at 60 min off the grid");
    vsv_interp_free(ip);
}

/* Split runs: the project's MM5 writer cuts the sample into files. */
static int write_periods(const char *in, const char *out, int p0, int p1)
{
    vsv_mm5 *m = NULL;
    if (vsv_mm5_open(in, &m))
        return -1;
    FILE *fp = fopen(out, "wb");
    vsv_mm5_writer w = {fp, 0};
    vsv_mm5_write_flag(&w, 0);
    vsv_mm5_write_bighdr(&w, vsv_mm5_bighdr_bytes(m));
    float *buf = malloc((size_t)40 * 40 * 16 * 4 + 1024);
    for (int p = p0; p <= p1; p++) {
        for (int i = 0; i < vsv_mm5_nfields(m); i++) {
            const vsv_mm5_field *f = vsv_mm5_field_at(m, i);
            if (f->period != p)
                continue;
            vsv_mm5_read(m, f, buf);
            vsv_mm5_write_field(&w, f, buf);
        }
        vsv_mm5_write_flag(&w, 2);
    }
    free(buf);
    vsv_mm5_free(m);
    return fclose(fp);
}

static int convert(const char *const *paths, int n, const char *out, char *err, size_t cap)
{
    vsv_run *run = NULL;
    int rc = vsv_run_open(paths, n, NULL, NULL, NULL, &run);
    if (rc) {
        snprintf(err, cap, "%s", vsv_run_error(run));
        vsv_run_free(run);
        return rc;
    }
    const vsv_meta *meta = vsv_run_meta(run);
    const size_t cells = (size_t)meta->nx * meta->ny * meta->nz;
    float **fields = calloc((size_t)meta->nvars, sizeof *fields);
    for (int v = 0; v < meta->nvars; v++)
        fields[v] = malloc(cells * 4);
    vsv_writer *w = NULL;
    rc = vsv_writer_create(out, meta, NULL, &w);
    for (int i = 0; !rc && i < vsv_run_nframes(run); i++)
        if (!(rc = vsv_run_read(run, i, fields)))
            rc = vsv_writer_add_step(w, vsv_run_time(run, i), (const float *const *)fields);
    if (!rc)
        rc = vsv_writer_finish(w, NULL, NULL);
    vsv_writer_free(w);
    for (int v = 0; v < meta->nvars; v++)
        free(fields[v]);
    free(fields);
    vsv_run_free(run);
    return rc;
}

static void test_split(void)
{
    const char *sample = "samples/mm5/MMOUT_DOMAIN1_CROP";
    const char *a = vsv_test_tmp("MMOUT_DOMAIN1_00"), *b = vsv_test_tmp("MMOUT_DOMAIN1_01");
    const char *c = vsv_test_tmp("MMOUT_DOMAIN1_02");
    write_periods(sample, a, 0, 1);
    write_periods(sample, b, 2, 3);
    char err[1024] = "";
    const char *whole[] = {sample}, *split[] = {b, a}; /* given out of order: sorted by time */
    int rc1 = convert(whole, 1, vsv_test_tmp("whole.vsv"), err, sizeof err);
    int rc2 = convert(split, 2, vsv_test_tmp("split.vsv"), err, sizeof err);
    size_t n1 = 0, n2 = 0;
    unsigned char *d1 = vsv_test_slurp(vsv_test_tmp("whole.vsv"), &n1),
                  *d2 = vsv_test_slurp(vsv_test_tmp("split.vsv"), &n2);
    CHECK(!rc1 && !rc2 && d1 && d2 && n1 == n2 && !memcmp(d1, d2, n1),
          "split files _00 _01 convert to the same bytes as the whole run", "%s", err);
    free(d1);
    free(d2);
    write_periods(sample, c, 1, 3);
    const char *overlap[] = {a, c};
    err[0] = 0;
    CHECK(convert(overlap, 2, vsv_test_tmp("x.vsv"), err, sizeof err) != 0 && strstr(err, "overlap") &&
              strstr(err, "MMOUT_DOMAIN1_00") && strstr(err, "MMOUT_DOMAIN1_02"),
          "overlapping files are an error naming both", "%s", err);
    write_periods(sample, c, 0, 0);
    const char *gap[] = {c, b};
    err[0] = 0;
    CHECK(convert(gap, 2, vsv_test_tmp("x.vsv"), err, sizeof err) != 0 && strstr(err, "gap between") &&
              strstr(err, "MMOUT_DOMAIN1_02") && strstr(err, "MMOUT_DOMAIN1_01"),
          "a gap between files is an error naming both", "%s", err);
    /* little-endian framing reads the same values */
    vsv_mm5 *m = NULL, *le = NULL;
    vsv_mm5_open(sample, &m);
    FILE *fp = fopen(vsv_test_tmp("le.mm5"), "wb");
    vsv_mm5_writer w = {fp, 1};
    vsv_mm5_write_flag(&w, 0);
    vsv_mm5_write_bighdr(&w, vsv_mm5_bighdr_bytes(m));
    float *buf = malloc((size_t)40 * 40 * 16 * 4 + 1024), *buf2 = malloc((size_t)40 * 40 * 16 * 4 + 1024);
    int period = 0;
    for (int i = 0; i < vsv_mm5_nfields(m); i++) {
        const vsv_mm5_field *f = vsv_mm5_field_at(m, i);
        if (f->period != period) {
            vsv_mm5_write_flag(&w, 2);
            period = f->period;
            /* a big header again mid-file, as restarts write it */
            vsv_mm5_write_flag(&w, 0);
            vsv_mm5_write_bighdr(&w, vsv_mm5_bighdr_bytes(m));
        }
        vsv_mm5_read(m, f, buf);
        vsv_mm5_write_field(&w, f, buf);
    }
    vsv_mm5_write_flag(&w, 2);
    fclose(fp);
    int ok = vsv_mm5_open(vsv_test_tmp("le.mm5"), &le) == 0 && vsv_mm5_little_endian(le) &&
             vsv_mm5_nfields(le) == vsv_mm5_nfields(m) && vsv_mm5_nbighdr(le) == 4 && vsv_mm5_bhi(le, 16, 1) == 40 &&
             vsv_mm5_bhr(le, 2, 2) == 10000;
    for (int i = 0; ok && i < vsv_mm5_nfields(m); i++) {
        vsv_mm5_read(m, vsv_mm5_field_at(m, i), buf);
        vsv_mm5_read(le, vsv_mm5_field_at(le, i), buf2);
        ok &= !memcmp(buf, buf2, vsv_mm5_field_at(m, i)->bytes) &&
              !strcmp(vsv_mm5_field_at(le, i)->name, vsv_mm5_field_at(m, i)->name);
    }
    CHECK(ok, "little-endian framing with repeated big headers reads the same fields", "%s",
          le ? vsv_mm5_error(le) : "");
    /* a second big header that differs (BHI(16,1) 41, BHR(2,2) 5000): the
     * first one is in force (vsv_mm5.h), in either byte order; fields after
     * the second say so */
    unsigned char *other = malloc(VSV_MM5_BIGHDR);
    memcpy(other, vsv_mm5_bighdr_bytes(m), VSV_MM5_BIGHDR);
    const unsigned char i41[4] = {0, 0, 0, 41}, r5000[4] = {0x45, 0x9c, 0x40, 0}; /* 5000.0f big-endian */
    memcpy(other + 4 * 15, i41, 4);
    memcpy(other + 4000 + 4 * (20 + 1), r5000, 4);
    const vsv_mm5_field *f0 = vsv_mm5_field_at(m, 0);
    vsv_mm5_read(m, f0, buf);
    for (int order = 0; order < 2; order++) {
        vsv_mm5 *two = NULL;
        fp = fopen(vsv_test_tmp("two.mm5"), "wb");
        w = (vsv_mm5_writer){fp, order};
        vsv_mm5_write_flag(&w, 0);
        vsv_mm5_write_bighdr(&w, vsv_mm5_bighdr_bytes(m));
        vsv_mm5_write_field(&w, f0, buf);
        vsv_mm5_write_flag(&w, 2);
        vsv_mm5_write_flag(&w, 0);
        vsv_mm5_write_bighdr(&w, other);
        vsv_mm5_write_field(&w, f0, buf);
        if (!order)
            vsv_mm5_write_flag(&w, 2); /* the little-endian file ends without it */
        fclose(fp);
        const int rc = vsv_mm5_open(vsv_test_tmp("two.mm5"), &two);
        CHECK(rc == 0 && vsv_mm5_nbighdr(two) == 2 && vsv_mm5_bhi(two, 16, 1) == 40 &&
                  vsv_mm5_bhr(two, 2, 2) == 10000 &&
                  !memcmp(vsv_mm5_bighdr_bytes(two), vsv_mm5_bighdr_bytes(m), VSV_MM5_BIGHDR),
              order ? "little-endian: of two differing big headers the first is in force (BHI(16,1) 40, BHR(2,2) 10000)"
                    : "big-endian: of two differing big headers the first is in force (BHI(16,1) 40, BHR(2,2) 10000)",
              "rc %d, %d headers, BHI(16,1) %d, BHR(2,2) %g: %s", rc, two ? vsv_mm5_nbighdr(two) : -1,
              two ? vsv_mm5_bhi(two, 16, 1) : -1, two ? vsv_mm5_bhr(two, 2, 2) : -1.0, two ? vsv_mm5_error(two) : "");
        CHECK(rc == 0 && vsv_mm5_nfields(two) == 2 && vsv_mm5_nperiods(two) == 2 &&
                  vsv_mm5_field_at(two, 0)->bighdr == 1 && vsv_mm5_field_at(two, 1)->bighdr == 2 &&
                  vsv_mm5_field_at(two, 1)->period == 1,
              order ? "little-endian, no end flag: the field after big header 2 is in period 1 of 2"
                    : "big-endian: the field after big header 2 is in period 1 of 2",
              "%d fields, %d periods", rc ? -1 : vsv_mm5_nfields(two), rc ? -1 : vsv_mm5_nperiods(two));
        vsv_mm5_free(two);
    }
    free(other);
    free(buf);
    free(buf2);
    vsv_mm5_free(le);
    vsv_mm5_free(m);
}

static void test_bad(void)
{
    const char *sample = "samples/mm5/MMOUT_DOMAIN1_CROP";
    size_t n;
    unsigned char *d = vsv_test_slurp(sample, &n);
    if (!CHECK(d != NULL, "sample readable"))
        return;
    /* cut mid-record */
    const char *cut = vsv_test_tmp("cut.mm5");
    vsv_test_write(cut, d, 200000);
    vsv_mm5 *m = NULL;
    int rc = vsv_mm5_open(cut, &m);
    CHECK(rc == VSV_ETRUNC && strstr(vsv_mm5_error(m), "record 5 at byte offset 117792") &&
              strstr(vsv_mm5_error(m), "file ends inside the record"),
          "a file cut mid-record names the record number and byte offset", "%s", vsv_mm5_error(m));
    vsv_mm5_free(m);
    vsv_source *src = NULL;
    rc = vsv_source_open(cut, NULL, &src);
    CHECK(rc != 0 && strstr(vsv_source_error(src), "record 5 at byte offset 117792"), "the source reports it too", "%s",
          vsv_source_error(src));
    vsv_source_free(src);
    /* not MM5 */
    const char *other = vsv_test_tmp("other.bin");
    vsv_test_write(other, "\x89PNG\r\n\x1a\nthis is not MM5 at all", 30);
    m = NULL;
    rc = vsv_mm5_open(other, &m);
    CHECK(rc == VSV_ENOTVSV && strstr(vsv_mm5_error(m), "not an MM5 v3 file"), "a non-MM5 file: 'not an MM5 v3 file'",
          "%s", vsv_mm5_error(m));
    vsv_mm5_free(m);
    /* a sub-header whose extent disagrees with the data record: first field's end[2] 15 → 16 */
    unsigned char *bad = malloc(n);
    memcpy(bad, d, n);
    const size_t sub = 12 + 117600 + 8 + 12 + 4; /* flag, bighdr, flag 1, then the sub-header payload */
    bad[sub + 20 + 8 + 3] = 16;
    const char *badp = vsv_test_tmp("badsize.mm5");
    vsv_test_write(badp, bad, n);
    m = NULL;
    rc = vsv_mm5_open(badp, &m);
    CHECK(rc == VSV_ECORRUPT &&
              strstr(vsv_mm5_error(m), "field U has 96000 bytes of data, its sub-header implies 102400"),
          "a field whose size disagrees with its sub-header is an error", "%s", vsv_mm5_error(m));
    vsv_mm5_free(m);
    /* the big header record's trailing length marker one off */
    memcpy(bad, d, n);
    bad[12 + 4 + 117600 + 3] ^= 1;
    vsv_test_write(badp, bad, n);
    m = NULL;
    rc = vsv_mm5_open(badp, &m);
    CHECK(rc == VSV_ECORRUPT &&
              strstr(vsv_mm5_error(m),
                     "record 2 at byte offset 12: trailing length marker 117601 differs from leading 117600"),
          "a record whose trailing length marker differs from its leading one is an error naming both", "%s",
          vsv_mm5_error(m));
    vsv_mm5_free(m);
    /* every truncation length and many flips: errors or success, never a crash */
    int crashes_avoided = 0;
    for (size_t len = 0; len < 200000; len += 997) {
        m = NULL;
        if (vsv_mm5_open_mem(d, len, "cut", &m) != 0)
            crashes_avoided++;
        vsv_mm5_free(m);
    }
    CHECK(crashes_avoided == 201, "every truncation up to 200 kB is an error", "%d", crashes_avoided);
    free(bad);
    free(d);
}

/* Crafted files (issue 18): the sample rewritten with one field changed by a
 * hook; each case crashed or misread before the shape checks. */
static int craft_case;
static void craft_hook_fn(vsv_mm5_field *f, int *skip)
{
    *skip = 0;
    switch (craft_case) {
    case 1: /* a later period's T with 30 levels, not 15 */
        if (f->period == 1 && !strcmp(f->name, "T"))
            f->end[2] = f->start[2] + 29;
        break;
    case 2: /* a later period's T with a fourth dimension of 3 */
        if (f->period == 1 && !strcmp(f->name, "T"))
            f->end[3] = f->start[3] + 2;
        break;
    case 3: /* TERRAIN (YX) with 40 extra levels */
        if (!strcmp(f->name, "TERRAIN"))
            f->end[2] = f->start[2] + 39;
        break;
    case 4: /* PSTARCRS (YX) with a fourth dimension */
        if (!strcmp(f->name, "PSTARCRS"))
            f->end[3] = f->start[3] + 19;
        break;
    case 5: /* a garbage date in the second period */
        if (f->period == 1)
            snprintf(f->date, sizeof f->date, "1995-13-45_99:00:00.0000");
        break;
    }
}

static int craft(const char *out)
{
    vsv_mm5 *m = NULL;
    if (vsv_mm5_open("samples/mm5/MMOUT_DOMAIN1_CROP", &m))
        return -1;
    FILE *fp = fopen(out, "wb");
    vsv_mm5_writer w = {fp, 0};
    vsv_mm5_write_flag(&w, 0);
    vsv_mm5_write_bighdr(&w, vsv_mm5_bighdr_bytes(m));
    int period = 0;
    for (int i = 0; i < vsv_mm5_nfields(m); i++) {
        vsv_mm5_field f = *vsv_mm5_field_at(m, i);
        if (f.period != period) {
            vsv_mm5_write_flag(&w, 2);
            period = f.period;
        }
        int skip = 0;
        craft_hook_fn(&f, &skip);
        uint64_t count = 1;
        for (int d = 0; d < 4; d++)
            count *= (uint64_t)(f.end[d] - f.start[d] + 1);
        float *buf = calloc(count > f.bytes / 4 ? count : f.bytes / 4, 4);
        vsv_mm5_read(m, vsv_mm5_field_at(m, i), buf);
        vsv_mm5_write_field(&w, &f, buf);
        free(buf);
    }
    vsv_mm5_write_flag(&w, 2);
    vsv_mm5_free(m);
    return fclose(fp);
}

/* A file whose first 3-D field and SIGMAH have n levels on a 1x1 patch. */
static int craft_levels(const char *out, int n)
{
    vsv_mm5 *m = NULL;
    if (vsv_mm5_open("samples/mm5/MMOUT_DOMAIN1_CROP", &m))
        return -1;
    FILE *fp = fopen(out, "wb");
    vsv_mm5_writer w = {fp, 0};
    vsv_mm5_write_flag(&w, 0);
    vsv_mm5_write_bighdr(&w, vsv_mm5_bighdr_bytes(m));
    vsv_mm5_field t = *vsv_mm5_field_at(m, vsv_mm5_find(m, 0, "T"));
    vsv_mm5_field sg = *vsv_mm5_field_at(m, vsv_mm5_find(m, 0, "SIGMAH"));
    t.end[0] = t.start[0];
    t.end[1] = t.start[1];
    t.end[2] = t.start[2] + n - 1;
    sg.end[0] = sg.start[0] + n - 1;
    float *v = calloc((size_t)n, 4);
    for (int k = 0; k < n; k++)
        v[k] = (k + 0.5f) / n;
    vsv_mm5_write_field(&w, &t, v);
    vsv_mm5_write_field(&w, &sg, v);
    vsv_mm5_write_flag(&w, 2);
    free(v);
    vsv_mm5_free(m);
    return fclose(fp);
}

static void test_crafted(void)
{
    static const char *const what[] = {NULL,
                                       "a later period's T with 30 levels",
                                       "a later period's T with 4 dimensions",
                                       "TERRAIN with 40 levels",
                                       "PSTARCRS with a fourth dimension",
                                       "a period with the date 1995-13-45_99"};
    static const char *const want[] = {NULL,
                                       "the first output time's is YXS 40x40x15",
                                       "the first output time's is YXS 40x40x15",
                                       "TERRAIN is not a 40x40 YX field",
                                       "PSTARCRS is not a 40x40 YX field",
                                       "is not a date"};
    float *vol = malloc((size_t)40 * 40 * 64 * 4);
    for (craft_case = 1; craft_case <= 5; craft_case++) {
        char name[32];
        snprintf(name, sizeof name, "craft%d.mm5", craft_case);
        const char *path = vsv_test_tmp(name);
        craft(path);
        vsv_source *src = NULL;
        vsv_source_opts o;
        vsv_source_opts_init(&o);
        o.vertical = VSV_VERT_NATIVE;
        int rc = vsv_source_open(path, &o, &src);
        if (rc == 0) {
            const int fT = vsv_source_find_field(src, "T");
            rc = fT < 0 ? -1 : vsv_source_read(src, fT, 0, vol);
            if (rc == 0)
                rc = vsv_source_read(src, fT, 1, vol);
        }
        char label[160];
        snprintf(label, sizeof label, "crafted MM5, %s: an error naming it, no overflow", what[craft_case]);
        CHECK(rc != 0 && strstr(vsv_source_error(src), want[craft_case]) && strstr(vsv_source_error(src), name), label,
              "rc %d: %s", rc, vsv_source_error(src));
        vsv_source_free(src);
    }
    free(vol);
    const char *deep = vsv_test_tmp("deep.mm5");
    craft_levels(deep, 100000);
    vsv_source *src = NULL;
    int rc = vsv_source_open(deep, NULL, &src);
    CHECK(rc != 0 && strstr(vsv_source_error(src), "100000 sigma levels, more than 16384"),
          "crafted MM5 with KX 100000: an error, no stack overflow", "rc %d: %s", rc, vsv_source_error(src));
    vsv_source_free(src);
}

/* vsv_mm5_date (vsv_mm5.h): a date's seconds; 1 for the all-zero date of
 * set-up files; -1 for a day the month does not have, or other nonsense. */
static void test_dates(void)
{
    int64_t t = 0;
    CHECK(vsv_mm5_date("1995-10-24_03:00:00.0000", &t) == 0 && t == 814492800 + 3 * 3600,
          "MM5 date 1995-10-24_03:00:00.0000 is its UTC seconds", "%lld", (long long)t);
    CHECK(vsv_mm5_date("0000-00-00_00:00:00", &t) == 1, "the all-zero MM5 date is 'no time' (1)");
    CHECK(vsv_mm5_date("1995-04-31_00:00:00", &t) == -1 && vsv_mm5_date("1995-06-31_12:00:00", &t) == -1,
          "April 31 and June 31 are not MM5 dates (-1)");
    CHECK(vsv_mm5_date("1995-10-24_24:00:00", &t) == -1 && vsv_mm5_date("1995-10-24", &t) == -1,
          "hour 24 and a date without its time are not MM5 dates (-1)");
    CHECK(vsv_mm5_date("1995-02-29_00:00:00", &t) == -1 && vsv_mm5_date("1900-02-29_00:00:00", &t) == -1 &&
              vsv_mm5_date("2000-02-29_06:00:00", &t) == 0 && t == 951782400 + 6 * 3600,
          "February 29 only in leap years (1995, 1900: -1; 2000: its seconds)", "%lld", (long long)t);
}

int main(void)
{
    test_terrain();
    test_mmout();
    test_interp();
    test_split();
    test_bad();
    test_crafted();
    test_dates();
    return vsv_test_done();
}
