/* test_realdata.c — round trips of the real 3-D time series in ../shared/data
 * through the writer and both readers: NCL's contour.cdf (T, Z), the CCM
 * vinth2p.nc T, and the GrADS sample model output through vsv_source. */
#include "vsv_convert.h"
#include "vsv_format.h"
#include "vsv_refread.h"
#include "vsv_testlib.h"

#include <math.h>
#include <netcdf.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

typedef struct series {
    vsv_meta meta;
    int nt;
    int64_t *times;
    float **data; /* [var] → nt*cells */
} series;

static size_t cells_of(const vsv_meta *m) { return (size_t)m->nx * m->ny * m->nz; }

/* Reads 4-D float variables (time, level, lat, lon) of a netCDF file. */
static int read_nc(const char *path, const char *const *vars, int nvars, series *s)
{
    int nc, rc = nc_open(path, NC_NOWRITE, &nc);
    if (rc)
        return rc;
    vsv_meta_init(&s->meta);
    s->data = calloc((size_t)nvars, sizeof *s->data);
    for (int v = 0; v < nvars; v++) {
        int id, dims[4], nd;
        size_t len[4];
        if ((rc = nc_inq_varid(nc, vars[v], &id)) || (rc = nc_inq_varndims(nc, id, &nd)) || nd != 4 ||
            (rc = nc_inq_vardimid(nc, id, dims)))
            return rc ? rc : -1;
        for (int d = 0; d < 4; d++)
            nc_inq_dimlen(nc, dims[d], &len[d]);
        s->nt = (int)len[0];
        s->meta.nz = (int)len[1];
        s->meta.ny = (int)len[2];
        s->meta.nx = (int)len[3];
        char units[64] = "", lname[128] = "";
        nc_get_att_text(nc, id, "units", units);
        nc_get_att_text(nc, id, "long_name", lname);
        float fill = NAN;
        nc_get_att_float(nc, id, "_FillValue", &fill);
        vsv_meta_add_var(&s->meta, vars[v], units, lname);
        const size_t n = (size_t)s->nt * cells_of(&s->meta);
        s->data[v] = malloc(n * sizeof(float));
        if ((rc = nc_get_var_float(nc, id, s->data[v])))
            return rc;
        for (size_t i = 0; i < n; i++)
            if (s->data[v][i] == fill)
                s->data[v][i] = NAN;
    }
    nc_close(nc);
    s->meta.proj.kind = VSV_PROJ_LATLON;
    s->meta.spacing[0] = s->meta.spacing[1] = 1;
    s->meta.vert_kind = VSV_VERT_INDEX;
    s->times = malloc((size_t)s->nt * sizeof *s->times);
    for (int t = 0; t < s->nt; t++)
        s->times[t] = 3600LL * 12 * t;
    return 0;
}

static void series_free(series *s)
{
    for (int v = 0; v < s->meta.nvars; v++)
        free(s->data[v]);
    free(s->data);
    free(s->times);
    vsv_meta_clear(&s->meta);
}

/* Packs, reopens, checks every finite value within the bound; cross-checks
 * the last step with the reference reader. */
static void round_trip(const char *label, series *s, int bits)
{
    const char *path = vsv_test_tmp("real.vsv");
    vsv_pack_opts o;
    vsv_pack_opts_init(&o);
    vsv_pack_var *pv = calloc((size_t)s->meta.nvars, sizeof *pv);
    for (int v = 0; v < s->meta.nvars; v++) {
        vsv_pack_var_init(&pv[v]);
        pv[v].bits = bits;
    }
    o.vars = pv;
    const size_t cells = cells_of(&s->meta);
    vsv_writer *w = NULL;
    int rc = vsv_writer_create(path, &s->meta, &o, &w);
    const float **fields = calloc((size_t)s->meta.nvars, sizeof *fields);
    for (int t = 0; !rc && t < s->nt; t++) {
        for (int v = 0; v < s->meta.nvars; v++)
            fields[v] = s->data[v] + (size_t)t * cells;
        rc = vsv_writer_add_step(w, s->times[t], fields);
    }
    if (!rc)
        rc = vsv_writer_finish(w, NULL, NULL);
    char name[256];
    snprintf(name, sizeof name, "%s %d-bit: packs", label, bits);
    CHECK(rc == 0, name, "%s", vsv_writer_error(w));
    vsv_writer_free(w);
    free(fields);
    free(pv);
    vsv_file *f = NULL;
    snprintf(name, sizeof name, "%s %d-bit: opens and checks", label, bits);
    if (!CHECK(vsv_file_open(path, &f) == 0 && vsv_file_check(f, NULL, NULL) == 0, name, "%s", vsv_file_error(f))) {
        vsv_file_free(f);
        return;
    }
    vsv_decoder *d = NULL;
    vsv_decoder_create(f, &d);
    float *vol = malloc(cells * 4);
    int ok = 1;
    double worst = 0, bound = 0;
    for (int v = 0; v < s->meta.nvars; v++) {
        const vsv_quant *q = vsv_file_quant(f, v);
        bound = fmax(bound, q->max_abs_error);
        for (int t = 0; t < s->nt; t++) {
            ok &= vsv_decoder_volume(d, t, v, vol) == 0;
            const float *orig = s->data[v] + (size_t)t * cells;
            for (size_t i = 0; i < cells; i++) {
                if (!isfinite(orig[i]))
                    continue;
                double e = fabs(vol[i] - orig[i]);
                worst = fmax(worst, e / q->max_abs_error);
                ok &= e <= q->max_abs_error;
            }
        }
    }
    snprintf(name, sizeof name, "%s %d-bit: every value within the stated bound", label, bits);
    CHECK(ok, name, "worst error %.3f of bound", worst);
    vsv_file_info info;
    vsv_file_info_get(f, &info);
    printf("  %s %d-bit: %llu bytes of %zu raw (ratio %.2f), worst error %.2f of bound\n", label, bits,
           (unsigned long long)info.file_bytes, cells * 4 * s->meta.nvars * s->nt,
           (double)(cells * 4 * s->meta.nvars * s->nt) / (double)info.file_bytes, worst);
    /* reference reader on the last step of the last variable */
    size_t n;
    unsigned char *data = vsv_test_slurp(path, &n);
    ref_file rf;
    char err[200] = "";
    uint16_t *codes = malloc(cells * 2);
    float *rv = malloc(cells * 4);
    const int lv = s->meta.nvars - 1, lt = s->nt - 1;
    int same = data && ref_open(&rf, data, n, err, sizeof err) == 0 &&
               ref_decode(&rf, (unsigned)lt, (unsigned)lv, codes, rv, err, sizeof err) == 0 &&
               vsv_decoder_volume(d, lt, lv, vol) == 0 && !memcmp(vol, rv, cells * 4);
    if (data)
        ref_close(&rf);
    snprintf(name, sizeof name, "%s %d-bit: reference reader agrees", label, bits);
    CHECK(same, name, "%s", err);
    free(codes);
    free(rv);
    free(data);
    free(vol);
    vsv_decoder_free(d);
    vsv_file_free(f);
    unlink(path);
}

static void test_netcdf(void)
{
    series s;
    const char *tz[] = {"T", "Z"};
    int rc = read_nc(vsv_test_shared("ncl/contour.cdf"), tz, 2, &s);
    if (CHECK(rc == 0 && s.nt == 7 && s.meta.nz == 10 && s.meta.ny == 33 && s.meta.nx == 36, "contour.cdf T, Z read",
              "%s", nc_strerror(rc))) {
        round_trip("contour.cdf T,Z", &s, 16);
        round_trip("contour.cdf T,Z", &s, 8);
    }
    series_free(&s);
    const char *t[] = {"T"};
    rc = read_nc(vsv_test_shared("ncl/vinth2p.nc"), t, 1, &s);
    if (CHECK(rc == 0 && s.nt == 2 && s.meta.nz == 18 && s.meta.nx == 128, "vinth2p.nc T read", "%s", nc_strerror(rc)))
        round_trip("vinth2p.nc T", &s, 16);
    series_free(&s);
}

static void test_grads(void)
{
    vsv_source *src = NULL;
    int rc = vsv_source_open(vsv_test_shared("grads/model.ctl"), NULL, &src);
    if (!CHECK(rc == 0, "GrADS model.ctl opens", "%s", vsv_source_error(src))) {
        vsv_source_free(src);
        return;
    }
    const vsv_meta *g = vsv_source_grid(src);
    CHECK(g->nx == 72 && g->ny == 46 && g->nz == 7 && vsv_source_ntimes(src) == 5 && vsv_source_nfields(src) == 8,
          "GrADS grid 72x46x7, 5 times, 8 fields");
    char buf[40];
    vsv_time_format(vsv_source_time(src, 1), buf, sizeof buf);
    CHECK(!strcmp(buf, "1987-01-03T00:00:00Z"), "GrADS TDEF 02JAN1987 1DY", "%s", buf);
    CHECK(g->levels && g->levels[0] == 1000 && g->levels[6] == 100 && !strcmp(g->vert_units, "hPa"),
          "GrADS pressure levels");
    /* T at (i=10, j=20, k=3), time 2: read the raw bytes directly */
    const int iT = vsv_source_find_field(src, "T");
    float *vol = malloc((size_t)72 * 46 * 7 * 4);
    vsv_source_read(src, iT, 2, vol);
    FILE *fp = fopen(vsv_test_shared("grads/model.dat"), "rb");
    const long plane = 72 * 46 * 4, per_time = plane * 36;
    /* PS 1, U 7, V 7, Z 7 planes precede T */
    float raw = 0;
    if (fp) {
        fseek(fp, per_time * 2 + plane * (1 + 7 + 7 + 7 + 3) + (20 * 72 + 10) * 4, SEEK_SET);
        if (fread(&raw, 4, 1, fp) != 1)
            raw = -1;
        fclose(fp);
    }
    CHECK(vol[(3 * 46 + 20) * 72 + 10] == raw && raw > 150 && raw < 320, "GrADS T value equals the raw file",
          "%g vs %g", vol[(3 * 46 + 20) * 72 + 10], raw);
    const int iQ = vsv_source_find_field(src, "Q");
    vsv_source_read(src, iQ, 0, vol);
    CHECK(isnan(vol[(size_t)6 * 46 * 72]) && !isnan(vol[(size_t)4 * 46 * 72 + 5]), "Q above its 5 levels is NaN");
    series s;
    vsv_meta_init(&s.meta);
    vsv_meta_copy(&s.meta, g);
    s.nt = 5;
    s.times = malloc(5 * sizeof *s.times);
    s.data = calloc(5, sizeof *s.data);
    const char *names[] = {"U", "V", "Z", "T", "Q"};
    for (int v = 0; v < 5; v++) {
        int fi = vsv_source_find_field(src, names[v]);
        const vsv_field_info *fin = vsv_source_field(src, fi);
        vsv_meta_add_var(&s.meta, fin->name, fin->units, fin->description);
        s.data[v] = malloc((size_t)5 * 72 * 46 * 7 * 4);
        for (int t = 0; t < 5; t++)
            vsv_source_read(src, fi, t, s.data[v] + (size_t)t * 72 * 46 * 7);
    }
    for (int t = 0; t < 5; t++)
        s.times[t] = vsv_source_time(src, t);
    round_trip("GrADS model.dat", &s, 16);
    series_free(&s);
    free(vol);
    vsv_source_free(src);
}

int main(void)
{
    test_netcdf();
    test_grads();
    return vsv_test_done();
}
