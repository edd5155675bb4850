/* bench_size.c — the .vsv's size against the field's honest lossy peers at
 * the same error bound, per species and in total (issue 36): netCDF-4
 * with CF int16 packing (scale_factor = 2 x the bound the .vsv states,
 * add_offset the middle of the range, deflate 4 + shuffle: what modellers
 * store), netCDF-4 float32 of the values the .vsv decodes to (rounded to the
 * bound, deflate 4 + shuffle), ZFP fixed-accuracy at tolerance = bound,
 * and ZFP calibrated: its tolerance raised (ZFP uses only its power of two)
 * while the largest error it makes stays within the bound.
 *
 * Every peer is fed the same floats as the .vsv (the model's own levels,
 * every time of the file); the terrain and land use a .vsv carries are
 * left out (the peers' files hold the species only).
 * Usage: bench_size SHARED_DIR PLUME_DIR WORK_DIR */
#include "bench_data.h"

#include <math.h>
#include <netcdf.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <zfp.h>

static long long fsize(const char *p)
{
    struct stat st;
    return stat(p, &st) ? -1 : (long long)st.st_size;
}

/* One species' (or the total's) figures; errors as multiples of the bound. */
typedef struct row {
    double bound;
    long long vsv, f32, i16;
    double e_vsv, e_i16;
    size_t zfp, zcal;
    double e_zfp, e_zcal, zcal_tol;
} row;

/* The species [v0, v1) of d as a .vsv as written by default (format 4);
 * its size, or -1. With q set, every value it decodes to, and the bounds. */
static long long write_vsv(const bench_data *d, int v0, int v1, const char *path, float *q, double *bound,
                           vsv_file_counts *counts)
{
    int rc = bench_data_write(d, v0, v1, 2, path);
    vsv_file *vf = NULL;
    vsv_decoder *dec = NULL;
    if (!rc && q && !(rc = vsv_file_open(path, &vf)) && !(rc = vsv_decoder_create(vf, &dec)))
        for (int v = v0; v < v1 && !rc; v++) {
            bound[v] = vsv_file_quant(vf, v - v0)->max_abs_error;
            for (int t = 0; t < d->nt && !rc; t++)
                rc = vsv_decoder_volume(dec, t, v - v0, q + ((size_t)t * d->nv + v) * bench_cells(d));
        }
    if (!rc && q)
        vsv_file_count(vf, counts);
    vsv_decoder_free(dec);
    vsv_file_free(vf);
    return rc ? -1 : fsize(path);
}

/* CF packing of species v: short = round((x - offset) / scale), NaN the
 * fill value -32768; scale = 2 x bound unless the range needs more than
 * 65534 steps (then the error exceeds the bound, and *err says so). */
static void cf_pack(const bench_data *d, int v, double bound, double *scale, double *offset)
{
    double lo = INFINITY, hi = -INFINITY;
    for (int t = 0; t < d->nt; t++) {
        const float *x = bench_field(d, t, v);
        for (size_t i = 0; i < bench_cells(d); i++)
            if (isfinite(x[i]))
                lo = fmin(lo, x[i]), hi = fmax(hi, x[i]);
    }
    if (!(hi >= lo))
        lo = hi = 0;
    *scale = fmax(2 * bound, (hi - lo) / 65534);
    if (!(*scale > 0))
        *scale = 1;
    *offset = (lo + hi) / 2;
}

/* netCDF-4 of species [v0, v1): float32 of q, or (q NULL) CF int16 packed
 * from the originals (*err: the largest packing error / bound). */
static long long write_nc(const bench_data *d, int v0, int v1, const float *q, const double *bound, const char *path,
                          double *err)
{
    int nc, dim[4];
    if (nc_create(path, NC_NETCDF4 | NC_CLOBBER, &nc))
        return -1;
    nc_def_dim(nc, "time", (size_t)d->nt, &dim[0]);
    nc_def_dim(nc, "z", (size_t)d->meta.nz, &dim[1]);
    nc_def_dim(nc, "y", (size_t)d->meta.ny, &dim[2]);
    nc_def_dim(nc, "x", (size_t)d->meta.nx, &dim[3]);
    double scale[64], offset[64];
    for (int v = v0; v < v1; v++) {
        int var;
        nc_def_var(nc, d->meta.vars[v].name, q ? NC_FLOAT : NC_SHORT, 4, dim, &var);
        nc_def_var_deflate(nc, var, 1, 1, 4);
        if (!q) {
            cf_pack(d, v, bound[v], &scale[v], &offset[v]);
            const short fill = -32768;
            nc_def_var_fill(nc, var, 0, &fill);
            nc_put_att_double(nc, var, "scale_factor", NC_FLOAT, 1, &scale[v]);
            nc_put_att_double(nc, var, "add_offset", NC_FLOAT, 1, &offset[v]);
        }
    }
    nc_enddef(nc);
    const size_t n = bench_cells(d);
    short *s = q ? NULL : malloc(n * sizeof *s);
    for (int v = v0; v < v1; v++)
        for (int t = 0; t < d->nt; t++) {
            const size_t start[4] = {(size_t)t, 0, 0, 0},
                         count[4] = {1, (size_t)d->meta.nz, (size_t)d->meta.ny, (size_t)d->meta.nx};
            if (q) {
                nc_put_vara_float(nc, v - v0, start, count, q + ((size_t)t * d->nv + v) * n);
                continue;
            }
            /* the reader's view: float32 attributes, as written */
            const float sc = (float)scale[v], of = (float)offset[v];
            const float *x = bench_field(d, t, v);
            for (size_t i = 0; i < n; i++) {
                if (!isfinite(x[i])) {
                    s[i] = -32768;
                    continue;
                }
                const double k = fmax(-32767, fmin(32767, nearbyint((x[i] - of) / sc)));
                s[i] = (short)k;
                if (bound[v] > 0)
                    *err = fmax(*err, fabs(k * sc + of - x[i]) / bound[v]);
            }
            nc_put_vara_short(nc, v - v0, start, count, s);
        }
    free(s);
    nc_close(nc);
    return fsize(path);
}

/* ZFP fixed-accuracy at tol of every step of species v: the bytes, and the
 * largest error (non-finite cells given as 0 and not counted) in *err. */
static size_t zfp_bytes(const bench_data *d, int v, double tol, double *err)
{
    const size_t n = bench_cells(d);
    float *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b);
    zfp_field *f = zfp_field_3d(a, zfp_type_float, (size_t)d->meta.nx, (size_t)d->meta.ny, (size_t)d->meta.nz);
    zfp_stream *z = zfp_stream_open(NULL);
    zfp_stream_set_accuracy(z, tol);
    const size_t cap = zfp_stream_maximum_size(z, f);
    void *buf = malloc(cap);
    bitstream *bs = stream_open(buf, cap);
    zfp_stream_set_bit_stream(z, bs);
    size_t total = 0;
    *err = 0;
    for (int t = 0; t < d->nt; t++) {
        const float *in = bench_field(d, t, v);
        for (size_t i = 0; i < n; i++)
            a[i] = isfinite(in[i]) ? in[i] : 0;
        zfp_field_set_pointer(f, a);
        zfp_stream_rewind(z);
        total += zfp_compress(z, f);
        zfp_stream_rewind(z);
        zfp_field_set_pointer(f, b);
        zfp_decompress(z, f);
        for (size_t i = 0; i < n; i++)
            if (isfinite(in[i]))
                *err = fmax(*err, fabs((double)b[i] - in[i]));
    }
    zfp_field_free(f);
    zfp_stream_close(z);
    stream_close(bs);
    free(buf);
    free(a);
    free(b);
    return total;
}

/* ZFP at the bound, then calibrated: ZFP keeps bit planes down to the power
 * of two at or under its tolerance, so each candidate is one power of two
 * more, kept while the largest error stays within the bound. */
static void zfp_row(const bench_data *d, int v, double bound, row *r)
{
    const double b = bound > 0 ? bound : 1e-30;
    double e;
    r->zfp = zfp_bytes(d, v, b, &e);
    r->e_zfp = fmax(r->e_zfp, e / b);
    int ex;
    frexp(b, &ex);
    double tol = ldexp(1, ex - 1), best_tol = b;
    size_t best = r->zfp;
    double best_e = e;
    for (int k = 1; k <= 24; k++) {
        const size_t z = zfp_bytes(d, v, ldexp(tol, k), &e);
        if (e > b)
            break;
        if (z <= best)
            best = z, best_e = e, best_tol = ldexp(tol, k);
    }
    r->zcal = best;
    r->e_zcal = fmax(r->e_zcal, best_e / b);
    r->zcal_tol = best_tol / b;
}

/* One table row; the total's bound and calibrated tolerance are per
 * species, so it prints none. */
static void print_row(const char *name, const row *r, int total)
{
    char bound[32] = "-", tol[32] = "per species";
    if (!total) {
        snprintf(bound, sizeof bound, "%.3g", r->bound);
        snprintf(tol, sizeof tol, "x%.3g", r->zcal_tol);
    }
    printf("| %s | %s | %lld | %lld | %lld (%.2f) | %zu (%.2f) | %zu (%s: %.2f) | **%.3f** | **%.3f** | %.3f |\n", name,
           bound, r->vsv, r->f32, r->i16, r->e_i16, r->zfp, r->e_zfp, r->zcal, tol, r->e_zcal, (double)r->vsv / r->i16,
           (double)r->vsv / r->zcal, (double)r->vsv / r->f32);
}

/* What the summary keeps of a data set: its totals' ratios, and its
 * species' ratios to CF int16 (the goals). */
enum { MAX_SETS = 8, MAX_SPECIES = 64 };
typedef struct summary {
    const char *name[MAX_SETS];
    double i16[MAX_SETS], zcal[MAX_SETS];
    int real[MAX_SETS], n;
    char sname[MAX_SPECIES][32]; /* species of real files */
    const char *sptr[MAX_SPECIES], *sset[MAX_SPECIES];
    double s16[MAX_SPECIES];
    int ns;
} summary;

static int run(const bench_data *d, const char *work, int real, summary *sum)
{
    char vp[1024], np[1024];
    snprintf(vp, sizeof vp, "%s/s.vsv", work);
    snprintf(np, sizeof np, "%s/s.nc", work);
    const size_t n = bench_cells(d);
    float *q = malloc((size_t)d->nt * d->nv * n * sizeof *q);
    double bound[64] = {0};
    row tot = {0};
    vsv_file_counts counts = {0};
    if (!q || (tot.vsv = write_vsv(d, 0, d->nv, vp, q, bound, &counts)) < 0)
        return -1;
    printf("\n%s: %dx%dx%d, %d steps\n\n", d->name, d->meta.nx, d->meta.ny, d->meta.nz, d->nt);
    printf("| species | bound | .vsv | netCDF-4 f32 rounded | netCDF-4 CF int16 (err/bound) | ZFP tol=bound "
           "(err/bound) | ZFP calibrated (tol/bound: err/bound) | .vsv / CF int16 | .vsv / ZFP cal. | .vsv / f32 |\n"
           "|---|---|---|---|---|---|---|---|---|---|\n");
    for (int v = 0; v < d->nv; v++) {
        row r = {.bound = bound[v]};
        r.vsv = write_vsv(d, v, v + 1, vp, NULL, NULL, NULL);
        r.f32 = write_nc(d, v, v + 1, q, bound, np, NULL);
        r.i16 = write_nc(d, v, v + 1, NULL, bound, np, &r.e_i16);
        zfp_row(d, v, bound[v], &r);
        print_row(d->meta.vars[v].name, &r, 0);
        if (real && sum->ns < MAX_SPECIES) {
            snprintf(sum->sname[sum->ns], sizeof sum->sname[0], "%s", d->meta.vars[v].name);
            sum->sptr[sum->ns] = sum->sname[sum->ns];
            sum->sset[sum->ns] = d->name;
            sum->s16[sum->ns++] = (double)r.vsv / r.i16;
        }
        tot.e_i16 = fmax(tot.e_i16, r.e_i16);
        tot.e_zfp = fmax(tot.e_zfp, r.e_zfp);
        tot.e_zcal = fmax(tot.e_zcal, r.e_zcal);
        tot.zfp += r.zfp;
        tot.zcal += r.zcal;
        fflush(stdout);
    }
    tot.f32 = write_nc(d, 0, d->nv, q, bound, np, NULL);
    double e = 0;
    tot.i16 = write_nc(d, 0, d->nv, NULL, bound, np, &e);
    print_row("**all**", &tot, 1);
    if (sum->n < MAX_SETS) {
        sum->name[sum->n] = d->name;
        sum->i16[sum->n] = (double)tot.vsv / tot.i16;
        sum->zcal[sum->n] = (double)tot.vsv / tot.zcal;
        sum->real[sum->n++] = real;
    }
    printf("\nThe .vsv of all species: %llu bytes of brick payloads (%.1f %%) in %llu stored bricks, the rest chunk "
           "indexes (octree and brick entries), metadata and table of contents.\n",
           (unsigned long long)counts.payload_bytes, 100.0 * counts.payload_bytes / tot.vsv,
           (unsigned long long)counts.stored_bricks);
    free(q);
    remove(vp);
    remove(np);
    return 0;
}

/* One line: the worst and best of the real files' ratios x[] (n of them,
 * named name[], of the files in set[] when set is given) beside the goal,
 * and those above it. */
static void worst_best(const char *what, const char *const *name, const char *const *set, const double *x,
                       const int *real, int n, double goal)
{
    int lo = -1, hi = -1, above = 0;
    for (int i = 0; i < n; i++)
        if (real[i]) {
            hi = hi < 0 || x[i] > x[hi] ? i : hi;
            lo = lo < 0 || x[i] < x[lo] ? i : lo;
            above += x[i] > goal;
        }
    if (lo < 0)
        return;
    printf("- %s: worst %.3f× (%s%s%s), best %.3f× (%s%s%s); ", what, x[hi], name[hi], set ? ", " : "",
           set ? set[hi] : "", x[lo], name[lo], set ? ", " : "", set ? set[lo] : "");
    if (!above) {
        printf("<= %.2f× on every one: met\n", goal);
        return;
    }
    printf("above %.2f× (not met) on %d of them:", goal, above);
    for (int i = 0, k = 0; i < n; i++)
        if (real[i] && x[i] > goal)
            printf("%s %s%s%s %.3f×", k++ ? "," : "", name[i], set ? " of " : "", set ? set[i] : "", x[i]);
    printf("\n");
}

int main(int argc, char **argv)
{
    if (argc < 4) {
        fprintf(stderr, "usage: bench_size SHARED_DIR PLUME_DIR WORK_DIR\n");
        return 2;
    }
    static const char *const files[][2] = {
        {"MM5 run (MMOUT_DOMAIN1)", "data/mm5/run1/MMOUT_DOMAIN1"},
        {"WRF Katrina (moving nest)", "data/wrf/katrina_ci_test_file.nc"},
        {"WRF wrf_cropped", "data/wrf/wrf_cropped.nc"},
        {"WRF d01 allvars cropped", "data/wrf/wrf_d01_allvars_cropped.nc"},
    };
    printf("Sizes in bytes; bound: the largest error the .vsv states for the species (its max_abs_error),\n"
           "every peer held to it; (err/bound): the largest error each actually made. ZFP calibrated: its\n"
           "tolerance as a multiple of the bound. Ratios under 1: the .vsv is smaller. The .vsv: as written\n"
           "by default (format 4: Lorenzo residuals, Rice-coded or zstd per brick, whichever is smaller).\n");
    int rc = 0;
    summary sum = {0};
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", argv[1], files[i][1]);
        bench_data d;
        if (fsize(path) < 0) {
            printf("\n%s: %s absent, skipped\n", files[i][0], path);
            continue;
        }
        rc |= bench_data_source(&d, files[i][0], path, NULL, 0) || run(&d, argv[3], 1, &sum);
        bench_data_free(&d);
    }
    static const char *const plume[] = {"plume_t0.f32", "plume_t1.f32"}, *haze[] = {"plume_haze.f32"};
    bench_data d;
    rc |= bench_data_plume(&d, "gen-plume plume (sparse)", argv[2], plume, 2) || run(&d, argv[3], 0, &sum);
    bench_data_free(&d);
    rc |= bench_data_plume(&d, "gen-plume haze (dense)", argv[2], haze, 1) || run(&d, argv[3], 0, &sum);
    bench_data_free(&d);
    /* the goals, on the real files (the synthetic ones beside) */
    printf("\nWorst beside best, the .vsv over its peer (real model output; issue 36's goals: in total <= 0.35× CF "
           "int16\nnetCDF-4 and <= 0.5× calibrated ZFP on each real file, no species above 0.6× CF int16):\n\n");
    int ones[MAX_SPECIES];
    for (int i = 0; i < MAX_SPECIES; i++)
        ones[i] = 1;
    worst_best("in total × CF int16 netCDF-4", sum.name, NULL, sum.i16, sum.real, sum.n, 0.35);
    worst_best("in total × calibrated ZFP", sum.name, NULL, sum.zcal, sum.real, sum.n, 0.5);
    worst_best("per species × CF int16 netCDF-4", sum.sptr, sum.sset, sum.s16, ones, sum.ns, 0.6);
    for (int i = 0; i < sum.n; i++)
        if (!sum.real[i])
            printf("- %s (synthetic, not part of the goals): in total %.3f× CF int16, %.3f× calibrated ZFP\n",
                   sum.name[i], sum.i16[i], sum.zcal[i]);
    return rc != 0;
}
