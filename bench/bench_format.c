/* bench_format.c — file size and full-decode speed of .vsv against the
 * peers on the same data in one run: raw float32, zstd -3 of the raw floats,
 * netCDF-4 deflate level 4 (nccopy -d4). Datasets: the real GrADS sample and
 * NCL contour.cdf series, and a synthetic cloud-like series (moving plumes,
 * sparse) at a realistic size. Prints a Markdown table. Usage:
 *   bench_format SHARED_DIR WORK_DIR */
#include "vsv_convert.h"
#include "vsv_format.h"

#include <math.h>
#include <netcdf.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <zstd.h>

typedef struct dataset {
    const char *name;
    vsv_meta meta;
    int nt;
    float *data; /* nt * nvars * cells, step-major */
} dataset;

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

static long long fsize(const char *p)
{
    struct stat st;
    return stat(p, &st) ? -1 : (long long)st.st_size;
}

static size_t cells(const dataset *d) { return (size_t)d->meta.nx * d->meta.ny * d->meta.nz; }
static size_t total(const dataset *d) { return cells(d) * d->meta.nvars * d->nt; }

static int load_source(dataset *d, const char *path, const char *const *vars, int nv)
{
    vsv_source *s = NULL;
    if (vsv_source_open(path, NULL, &s)) {
        fprintf(stderr, "%s\n", vsv_source_error(s));
        vsv_source_free(s);
        return -1;
    }
    vsv_meta_init(&d->meta);
    vsv_meta_copy(&d->meta, vsv_source_grid(s));
    d->nt = vsv_source_ntimes(s);
    for (int v = 0; v < nv; v++) {
        const vsv_field_info *f = vsv_source_field(s, vsv_source_find_field(s, vars[v]));
        vsv_meta_add_var(&d->meta, f->name, f->units, f->description);
    }
    d->data = malloc(total(d) * 4);
    for (int t = 0; t < d->nt; t++)
        for (int v = 0; v < nv; v++)
            vsv_source_read(s, vsv_source_find_field(s, vars[v]), t, d->data + ((size_t)t * nv + v) * cells(d));
    vsv_source_free(s);
    return 0;
}

static int load_nc(dataset *d, const char *path)
{
    int nc, id[2];
    if (nc_open(path, NC_NOWRITE, &nc))
        return -1;
    vsv_meta_init(&d->meta);
    d->meta.nx = 36;
    d->meta.ny = 33;
    d->meta.nz = 10;
    d->nt = 7;
    d->meta.vert_kind = VSV_VERT_INDEX;
    vsv_meta_add_var(&d->meta, "T", "K", "temperature");
    vsv_meta_add_var(&d->meta, "Z", "m", "geopotential height");
    nc_inq_varid(nc, "T", &id[0]);
    nc_inq_varid(nc, "Z", &id[1]);
    d->data = malloc(total(d) * 4);
    float *tmp = malloc(total(d) / 2 * 4);
    for (int v = 0; v < 2; v++) {
        nc_get_var_float(nc, id[v], tmp);
        for (int t = 0; t < 7; t++)
            memcpy(d->data + ((size_t)t * 2 + v) * cells(d), tmp + (size_t)t * cells(d), cells(d) * 4);
    }
    free(tmp);
    nc_close(nc);
    return 0;
}

/* Cloud-like: a few plumes drifting and growing over a 10-minute series. */
static void make_synth(dataset *d, int nx, int ny, int nz, int nt)
{
    vsv_meta_init(&d->meta);
    d->meta.nx = nx;
    d->meta.ny = ny;
    d->meta.nz = nz;
    d->nt = nt;
    d->meta.spacing[0] = d->meta.spacing[1] = 4000;
    d->meta.spacing[2] = 250;
    vsv_meta_add_var(&d->meta, "CLW", "kg/kg", "cloud water");
    vsv_meta_add_var(&d->meta, "RNW", "kg/kg", "rain water");
    d->data = malloc(total(d) * 4);
    for (int t = 0; t < nt; t++)
        for (int v = 0; v < 2; v++) {
            float *f = d->data + ((size_t)t * 2 + v) * cells(d);
            for (int k = 0; k < nz; k++)
                for (int j = 0; j < ny; j++)
                    for (int i = 0; i < nx; i++) {
                        double x = (double)i / nx, y = (double)j / ny, z = (double)k / nz, val = 0;
                        for (int p = 0; p < 6; p++) {
                            double cx = 0.1 + 0.15 * p + 0.002 * t, cy = 0.2 + 0.1 * (p % 4) + 0.001 * t;
                            double cz = v ? 0.15 : 0.35 + 0.05 * (p % 3), rr = 0.004 + 0.0001 * t;
                            double r2 = ((x - cx) * (x - cx) + (y - cy) * (y - cy)) / rr + (z - cz) * (z - cz) / 0.02;
                            if (r2 < 5)
                                val += 1e-3 * exp(-r2) * (0.8 + 0.2 * sin(0.2 * t + p + 7 * x));
                        }
                        f[((size_t)k * ny + j) * nx + i] = val < 1e-6 ? 0.0f : (float)val;
                    }
        }
}

static void run(dataset *d, const char *work)
{
    char raw[1024], zst[1024], nc3[1024], nc4[1024], vsv[1024], cmd[4096];
    snprintf(raw, sizeof raw, "%s/%s.f32", work, d->name);
    snprintf(zst, sizeof zst, "%s/%s.f32.zst", work, d->name);
    snprintf(nc3, sizeof nc3, "%s/%s.nc", work, d->name);
    snprintf(nc4, sizeof nc4, "%s/%s.d4.nc", work, d->name);
    snprintf(vsv, sizeof vsv, "%s/%s.vsv", work, d->name);
    const size_t n = total(d), c = cells(d);
    const int nv = d->meta.nvars;
    FILE *fp = fopen(raw, "wb");
    fwrite(d->data, 4, n, fp);
    fclose(fp);
    /* zstd -3 (the CLI), decode timed with libzstd in this process */
    snprintf(cmd, sizeof cmd, "zstd -3 -q -f '%s' -o '%s'", raw, zst);
    if (system(cmd))
        fprintf(stderr, "zstd failed\n");
    long long zsize = fsize(zst);
    double zrate = 0;
    {
        FILE *zf = fopen(zst, "rb");
        unsigned char *zb = malloc((size_t)zsize);
        if (fread(zb, 1, (size_t)zsize, zf) != (size_t)zsize)
            zsize = -1;
        fclose(zf);
        float *out = malloc(n * 4);
        memset(out, 0, n * 4);              /* no page faults inside the timing */
        for (int rep = 0; rep < 4; rep++) { /* best of 4, like .vsv below */
            double t0 = now();
            size_t got = ZSTD_decompress(out, n * 4, zb, (size_t)zsize);
            double dt = now() - t0;
            if (!ZSTD_isError(got) && n / dt / 1e6 > zrate)
                zrate = n / dt / 1e6;
        }
        free(out);
        free(zb);
    }
    /* netCDF classic → nccopy -d4 → timed read of every variable */
    int ncid, dims[4], ids[64];
    nc_create(nc3, NC_CLOBBER | NC_64BIT_OFFSET, &ncid);
    nc_def_dim(ncid, "time", (size_t)d->nt, &dims[0]);
    nc_def_dim(ncid, "z", (size_t)d->meta.nz, &dims[1]);
    nc_def_dim(ncid, "y", (size_t)d->meta.ny, &dims[2]);
    nc_def_dim(ncid, "x", (size_t)d->meta.nx, &dims[3]);
    for (int v = 0; v < nv; v++)
        nc_def_var(ncid, d->meta.vars[v].name, NC_FLOAT, 4, dims, &ids[v]);
    nc_enddef(ncid);
    for (int v = 0; v < nv; v++)
        for (int t = 0; t < d->nt; t++) {
            size_t start[4] = {(size_t)t, 0, 0, 0},
                   count[4] = {1, (size_t)d->meta.nz, (size_t)d->meta.ny, (size_t)d->meta.nx};
            nc_put_vara_float(ncid, ids[v], start, count, d->data + ((size_t)t * nv + v) * c);
        }
    nc_close(ncid);
    snprintf(cmd, sizeof cmd, "nccopy -d4 '%s' '%s'", nc3, nc4);
    if (system(cmd))
        fprintf(stderr, "nccopy failed\n");
    long long nsize = fsize(nc4);
    double nrate = 0;
    {
        float *out = malloc(n / nv * 4);
        memset(out, 0, n / nv * 4);
        for (int rep = 0; rep < 4; rep++) {
            double t0 = now();
            nc_open(nc4, NC_NOWRITE, &ncid);
            for (int v = 0; v < nv; v++) {
                int id;
                nc_inq_varid(ncid, d->meta.vars[v].name, &id);
                nc_get_var_float(ncid, id, out);
            }
            nc_close(ncid);
            double r = n / (now() - t0) / 1e6;
            nrate = r > nrate ? r : nrate;
        }
        free(out);
    }
    /* .vsv at 16 and 8 bits: size, and full sequential decode on one core */
    for (int bits = 16; bits >= 8; bits -= 8) {
        vsv_pack_opts o;
        vsv_pack_opts_init(&o);
        vsv_pack_var *pv = calloc((size_t)nv, sizeof *pv);
        for (int v = 0; v < nv; v++) {
            vsv_pack_var_init(&pv[v]);
            pv[v].bits = bits;
        }
        o.vars = pv;
        vsv_writer *w = NULL;
        double t0 = now();
        vsv_writer_create(vsv, &d->meta, &o, &w);
        const float **fields = calloc((size_t)nv, sizeof *fields);
        for (int t = 0; t < d->nt; t++) {
            for (int v = 0; v < nv; v++)
                fields[v] = d->data + ((size_t)t * nv + v) * c;
            vsv_writer_add_step(w, 1000 * (int64_t)t, fields);
        }
        if (vsv_writer_finish(w, NULL, NULL))
            fprintf(stderr, "%s\n", vsv_writer_error(w));
        double enc = now() - t0;
        vsv_writer_free(w);
        free(fields);
        free(pv);
        vsv_file *f = NULL;
        vsv_file_open(vsv, &f);
        vsv_decoder *dec = NULL;
        vsv_decoder_create(f, &dec);
        float *vol = malloc(c * 4);
        double best = 1e9;
        double maxerr = 0;
        memset(vol, 0, c * 4);
        for (int rep = 0; rep < 4; rep++) { /* best of 4; the first also warms the decoder */
            t0 = now();
            for (int v = 0; v < nv; v++)
                for (int t = 0; t < d->nt; t++)
                    vsv_decoder_volume(dec, t, v, vol);
            double dt = now() - t0;
            best = dt < best ? dt : best;
        }
        for (int v = 0; v < nv; v++)
            maxerr = fmax(maxerr, vsv_file_quant(f, v)->max_abs_error);
        long long vsize = fsize(vsv);
        if (bits == 16)
            printf("| %s | %d×%d×%d ×%d var ×%d steps | %.2f | %.2f (%.0f) | %.2f (%.0f) |", d->name, d->meta.nx,
                   d->meta.ny, d->meta.nz, nv, d->nt, n * 4 / 1e6, zsize / 1e6, zrate, nsize / 1e6, nrate);
        printf(" %.3f (%.0f; %.2f× nc4) |", vsize / 1e6, n / best / 1e6, (double)vsize / nsize);
        if (bits == 8)
            printf(" %.0f |\n", n / enc / 1e6);
        free(vol);
        vsv_decoder_free(dec);
        vsv_file_free(f);
    }
    fflush(stdout);
    remove(raw);
    remove(zst);
    remove(nc3);
    remove(nc4);
    remove(vsv);
}

int main(int argc, char **argv)
{
    const char *shared = argc > 1 ? argv[1] : "../shared";
    const char *work = argc > 2 ? argv[2] : "/tmp";
    char path[1024];
    printf("Sizes in MB; in parentheses, full-decode speed in M voxels/s on one core\n"
           "(best of 4 runs; zstd: libzstd in process; netCDF-4: nc_get_var of every variable; .vsv: every\n"
           "step and species decoded in order to float32; \"x nc4\": the .vsv's size over netCDF-4's).\n\n");
    printf("| data | shape | raw f32 | zstd -3 | netCDF-4 -d4 | .vsv 16-bit | .vsv 8-bit | .vsv encode M voxels/s (2 "
           "threads) |\n");
    printf("|---|---|---|---|---|---|---|---|\n");
    dataset d;
    snprintf(path, sizeof path, "%s/data/grads/model.ctl", shared);
    const char *gv[] = {"U", "V", "Z", "T", "Q"};
    d.name = "grads-model";
    if (!load_source(&d, path, gv, 5)) {
        run(&d, work);
        free(d.data);
        vsv_meta_clear(&d.meta);
    }
    snprintf(path, sizeof path, "%s/data/ncl/contour.cdf", shared);
    d.name = "ncl-contour";
    if (!load_nc(&d, path)) {
        run(&d, work);
        free(d.data);
        vsv_meta_clear(&d.meta);
    }
    d.name = "synthetic-clouds";
    make_synth(&d, 208, 143, 40, 48);
    run(&d, work);
    free(d.data);
    vsv_meta_clear(&d.meta);
    return 0;
}
