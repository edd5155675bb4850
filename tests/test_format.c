/* test_format.c — round trips of the .vsv format library on synthetic
 * series: exactness of deltas, random access, empty bricks, quantisation
 * bounds, other brick sizes and codecs, cross-checks with the reference
 * reader, per-column heights and format 2's predicted bricks. Writing in
 * parts and the planned writer: test_format_writer.c. Damage, golden files
 * and truncation: test_format_damage.c;
 * CRC, calendar and quantisation rules: test_format_primitives.c. */
#include "vsv_format_internal.h"
#include "vsv_refread.h"
#include "vsv_synth.h"
#include "vsv_testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* random access with fresh decoders, and backwards with one decoder, equal the sequential decode */
static void series_random_access(vsv_file *f, vsv_decoder *d, float *vol, size_t cells, uint32_t (*crcs)[3],
                                 uint64_t *rs)
{
    int same = 1;
    for (int n = 0; n < 60; n++) {
        int t = (int)(vsv_test_rand(rs) % 120), s = (int)(vsv_test_rand(rs) % 3);
        vsv_decoder *d2 = NULL;
        vsv_decoder_create(f, &d2);
        same &= vsv_decoder_volume(d2, t, s, vol) == 0 && vsv_crc32c(0, vol, cells * 4) == crcs[t][s];
        vsv_decoder_free(d2);
    }
    /* and backwards with one decoder */
    for (int t = 119; t >= 0; t -= 7)
        same &= vsv_decoder_volume(d, t, 1, vol) == 0 && vsv_crc32c(0, vol, cells * 4) == crcs[t][1];
    CHECK(same, "random access and backward decode equal sequential decode bit for bit");
}

/* one brick equals its part of the volume */
static void series_single_bricks(vsv_file *f, vsv_decoder *d, const vsv_file_info *info, float *vol, uint64_t *rs)
{
    float *brick = malloc(16 * 16 * 16 * 4);
    int bok = 1;
    for (int n = 0; n < 40; n++) {
        int t = (int)(vsv_test_rand(rs) % 120), s = (int)(vsv_test_rand(rs) % 3),
            b = (int)(vsv_test_rand(rs) % (unsigned)info->nbricks);
        int org[3], ext[3];
        vsv_file_brick_box(f, b, org, ext);
        bok &= vsv_decoder_brick(d, t, s, b, brick) == 0 && vsv_decoder_volume(d, t, s, vol) == 0;
        for (int k = 0; k < ext[2]; k++)
            for (int j = 0; j < ext[1]; j++)
                for (int i = 0; i < ext[0]; i++)
                    bok &=
                        brick[(k * 16 + j) * 16 + i] == vol[((size_t)(org[2] + k) * 50 + org[1] + j) * 70 + org[0] + i];
    }
    CHECK(bok, "single-brick decode equals the volume");
    free(brick);
}

/* empty bricks cost nothing; the octree says which */
static void series_brick_kinds(vsv_file *f, const vsv_file_info *info)
{
    int kinds_ok = 1, empty_seen = 0, unchanged_frozen = 1, appear_seen = 0, appear_abs = 1;
    for (int t = 0; t < 120; t++) {
        int dims[3 * 16];
        const unsigned char *oct = vsv_file_octree(f, t, 0, dims);
        const unsigned char *before = t ? vsv_file_octree(f, t - 1, 0, dims) : NULL;
        for (int b = 0; b < info->nbricks; b++) {
            unsigned mn, mx, pmn, pmx;
            vsv_octree_node(oct, (size_t)b, &mn, &mx);
            int kind = vsv_file_brick_kind(f, t, 0, b);
            if (mx == 0) {
                empty_seen++;
                kinds_ok &= kind == VSV_BRICK_EMPTY || kind == VSV_BRICK_UNCHANGED;
            }
            if (before && mx > 0) { /* a plume entering an empty brick: a DELTA against zeros costs more */
                vsv_octree_node(before, (size_t)b, &pmn, &pmx);
                if (pmx == 0) {
                    appear_seen++;
                    appear_abs &= kind == VSV_BRICK_ABS || kind == VSV_BRICK_ABS3;
                }
            }
            if (t > 40 && t <= 60 && t % 8)
                unchanged_frozen &= vsv_file_brick_kind(f, t, 2, b) == VSV_BRICK_UNCHANGED;
        }
    }
    CHECK(empty_seen > 0 && kinds_ok, "empty bricks are stored as EMPTY/UNCHANGED", "%d empty", empty_seen);
    CHECK(appear_seen > 0 && appear_abs, "a brick empty the step before is stored ABS/ABS3, not as a DELTA",
          "%d such bricks", appear_seen);
    vsv_file_counts cnt;
    vsv_file_count(f, &cnt);
    CHECK(cnt.stored_bricks < (uint64_t)info->nbricks * 3 * 120, "fewer payloads than bricks", "%llu stored",
          (unsigned long long)cnt.stored_bricks);
    CHECK(unchanged_frozen, "unchanged steps store no payload");
}

/* the octree root bounds the volume */
static void series_octree_root(vsv_file *f, vsv_decoder *d, const vsv_file_info *info, float *vol, size_t cells)
{
    int dims[3 * 16];
    const unsigned char *oct = vsv_file_octree(f, 77, 1, dims);
    unsigned rmn, rmx;
    vsv_octree_node(oct, vsv_file_octree_level_start(f, info->octree_levels - 1), &rmn, &rmx);
    vsv_decoder_volume(d, 77, 1, vol);
    float vmn = INFINITY, vmx = -INFINITY;
    for (size_t i = 0; i < cells; i++) {
        vmn = vol[i] < vmn ? vol[i] : vmn;
        vmx = vol[i] > vmx ? vol[i] : vmx;
    }
    CHECK(vsv_quant_value(vsv_file_quant(f, 1), rmn) == vmn && vsv_quant_value(vsv_file_quant(f, 1), rmx) == vmx,
          "octree root min/max equal the volume's");
}

/* reference reader agrees exactly */
static void series_reference(const char *path, vsv_file *f, size_t cells, uint32_t (*crcs)[3])
{
    size_t n = 0;
    unsigned char *data = vsv_test_slurp(path, &n);
    ref_file rf;
    char rerr[200] = "";
    int refok = data && ref_open(&rf, data, n, rerr, sizeof rerr) == 0;
    if (refok) {
        uint16_t *rc16 = malloc(cells * 2);
        float *rv = malloc(cells * 4);
        const int ts[] = {0, 7, 8, 9, 45, 63, 119};
        for (size_t a = 0; a < sizeof ts / sizeof *ts && refok; a++)
            for (int s = 0; s < 3 && refok; s++) {
                refok &= ref_decode(&rf, (unsigned)ts[a], (unsigned)s, rc16, rv, rerr, sizeof rerr) == 0;
                refok &= vsv_crc32c(0, rv, cells * 4) == crcs[ts[a]][s];
                refok &= ref_time(&rf, (unsigned)ts[a]) == vsv_file_time(f, ts[a]);
            }
        free(rc16);
        free(rv);
        ref_close(&rf);
    }
    CHECK(refok, "reference reader decodes identical values", "%s", rerr);
    free(data);
}

/* the thread count does not change a byte */
static void series_threads(const synth *sy, vsv_pack_opts *o, const char *path, char *err, size_t errsz)
{
    const char *p1 = vsv_test_tmp("series-t1.vsv");
    o->threads = 1;
    synth_write(sy, p1, o, err, errsz);
    size_t n1, n2;
    unsigned char *a1 = vsv_test_slurp(p1, &n1), *a2 = vsv_test_slurp(path, &n2);
    CHECK(a1 && a2 && n1 == n2 && !memcmp(a1, a2, n1), "1 and 2 encoder threads write identical files");
    free(a1);
    free(a2);
    unlink(p1);
}

/* Decodes every (step, species) sequentially; checks the bound against the
 * synthetic truth and remembers a CRC of each volume. */
static void test_series(void)
{
    synth sy = {70, 50, 20, 120, 40, 60};
    const char *path = vsv_test_tmp("series.vsv");
    vsv_pack_opts o;
    vsv_pack_opts_init(&o);
    o.brick = 16;
    o.keyframe = 8;
    vsv_pack_var pv[3];
    for (int s = 0; s < 3; s++)
        vsv_pack_var_init(&pv[s]);
    pv[2].scale = VSV_SCALE_LOG;
    o.vars = pv;
    char err[512] = "";
    int rc = synth_write(&sy, path, &o, err, sizeof err);
    if (!CHECK(rc == 0, "write a 120-step, 3-species series", "%s", err))
        return;
    vsv_file *f = NULL;
    rc = vsv_file_open(path, &f);
    if (!CHECK(rc == 0, "open the series", "%s", vsv_file_error(f))) {
        vsv_file_free(f);
        return;
    }
    vsv_file_info info;
    vsv_file_info_get(f, &info);
    CHECK(info.nsteps == 120 && info.nspecies == 3 && info.nbricks == 5 * 4 * 2, "series shape");
    CHECK(!vsv_file_quant(f, 3) && !vsv_file_quant(f, -1) && vsv_file_quant(f, 2) && !vsv_file_time(f, -1) &&
              !vsv_file_time(f, 120) && vsv_file_time(f, 119) > vsv_file_time(f, 0),
          "accessors answer NULL / 0 outside the file's species and steps");
    const size_t cells = (size_t)70 * 50 * 20;
    float *vol = malloc(cells * 4);
    uint32_t crcs[120][3];
    vsv_decoder *d = NULL;
    vsv_decoder_create(f, &d);
    double worst[3] = {0, 0, 0};
    int within = 1, decoded = 1;
    for (int t = 0; t < 120; t++)
        for (int s = 0; s < 3; s++) {
            if (vsv_decoder_volume(d, t, s, vol)) {
                decoded = 0;
                continue;
            }
            crcs[t][s] = vsv_crc32c(0, vol, cells * 4);
            const vsv_quant *q = vsv_file_quant(f, s);
            for (int k = 0; k < 20; k++)
                for (int j = 0; j < 50; j++)
                    for (int i = 0; i < 70; i++) {
                        double e = fabs(vol[((size_t)k * 50 + j) * 70 + i] - synth_value(&sy, s, t, i, j, k));
                        worst[s] = e > worst[s] ? e : worst[s];
                        within &= e <= q->max_abs_error;
                    }
        }
    CHECK(decoded, "every step decodes sequentially", "%s", vsv_decoder_error(d));
    CHECK(within, "no drift: every value of 120 steps within the stated bound", "worst %g %g %g, bounds %g %g %g",
          worst[0], worst[1], worst[2], vsv_file_quant(f, 0)->max_abs_error, vsv_file_quant(f, 1)->max_abs_error,
          vsv_file_quant(f, 2)->max_abs_error);
    printf("  worst errors: CLW %.3g (bound %.3g), T %.3g (bound %.3g), O3 %.3g (bound %.3g)\n", worst[0],
           vsv_file_quant(f, 0)->max_abs_error, worst[1], vsv_file_quant(f, 1)->max_abs_error, worst[2],
           vsv_file_quant(f, 2)->max_abs_error);

    uint64_t rs = 42;
    series_random_access(f, d, vol, cells, crcs, &rs);
    series_single_bricks(f, d, &info, vol, &rs);
    series_brick_kinds(f, &info);
    series_octree_root(f, d, &info, vol, cells);
    series_reference(path, f, cells, crcs);
    CHECK(info.file_bytes * 4 < cells * 4 * 3 * 120, "file is under a quarter of raw float32", "%llu bytes",
          (unsigned long long)info.file_bytes);
    free(vol);
    vsv_decoder_free(d);
    vsv_file_free(f);

    series_threads(&sy, &o, path, err, sizeof err);
    unlink(path);
}

/* Other brick sizes, 8 bits, log scale, codec none. */
static void test_variants(void)
{
    synth sy = {37, 29, 11, 10, 3, 5};
    const int bricks[] = {8, 32, 64};
    for (int v = 0; v < 6; v++) {
        vsv_pack_opts o;
        vsv_pack_opts_init(&o);
        vsv_pack_var pv[3];
        for (int s = 0; s < 3; s++) {
            vsv_pack_var_init(&pv[s]);
            pv[s].bits = v & 1 ? 8 : 16;
            pv[s].scale = v >= 2 && s != 1 ? VSV_SCALE_LOG : VSV_SCALE_LINEAR;
        }
        o.vars = pv;
        o.brick = bricks[v % 3];
        o.keyframe = 1 + v;
        o.codec = v == 4 ? VSV_CODEC_NONE : VSV_CODEC_ZSTD;
        char name[64], err[512] = "";
        snprintf(name, sizeof name, "variant%d.vsv", v);
        const char *path = vsv_test_tmp(name);
        int ok = synth_write(&sy, path, &o, err, sizeof err) == 0;
        vsv_file *f = NULL;
        ok = ok && vsv_file_open(path, &f) == 0 && vsv_file_check(f, NULL, NULL) == 0;
        vsv_decoder *d = NULL;
        float *vol = malloc((size_t)37 * 29 * 11 * 4);
        ok = ok && vsv_decoder_create(f, &d) == 0;
        for (int t = 9; ok && t >= 0; t -= 3)
            for (int s = 0; s < 3 && ok; s++) {
                ok &= vsv_decoder_volume(d, t, s, vol) == 0;
                const vsv_quant *q = vsv_file_quant(f, s);
                for (int k = 0; k < 11; k++)
                    for (int j = 0; j < 29; j++)
                        for (int i = 0; i < 37; i++)
                            ok &= fabs(vol[((size_t)k * 29 + j) * 37 + i] - synth_value(&sy, s, t, i, j, k)) <=
                                  q->max_abs_error;
            }
        char label[128];
        snprintf(label, sizeof label, "variant brick %d, %d bits, %s, K=%d, codec %s round trips within bound", o.brick,
                 pv[0].bits, pv[0].scale ? "log" : "linear", o.keyframe, o.codec ? "zstd" : "none");
        CHECK(ok, label, "%s %s", err, f ? vsv_file_error(f) : "");
        free(vol);
        vsv_decoder_free(d);
        vsv_file_free(f);
        unlink(path);
    }
}

/* Per-column heights (SPEC.md HGTS, format 1.1): both forms round-trip, the
 * file says 1.1 (and a file without them still 1.0), the reference reader
 * (which knows nothing of HGTS) still reads it, bad heights are refused, and
 * the resampler puts a field equal to each cell's height at the even cell's
 * own height. */
/* Format 3.0: the same heights written with the 3-D kinds (predict 1; the
 * default writer's format 4 codes them alike) are HGTS form 2, coded
 * losslessly: the header says 3.0, the records come
 * back bit for bit, the reference reader still reads the file (it skips
 * HGTS), and the coded file is smaller than the 1.1 one of raw heights. */
static void heights_coded(const vsv_meta *m, float *const *v, int nt, size_t raw_size)
{
    const size_t n = (size_t)m->nx * m->ny * m->nz;
    vsv_pack_opts o;
    vsv_pack_opts_init(&o);
    o.brick = 8;
    o.threads = 1;
    o.predict = 1;
    const char *path = vsv_test_tmp("heights3.vsv");
    vsv_writer *w = NULL;
    int rc = vsv_writer_create(path, m, &o, &w);
    for (int t = 0; t < nt && !rc; t++)
        rc = vsv_writer_add_step(w, t * 3600, (const float *const *)&v[t]);
    if (!rc)
        rc = vsv_writer_finish(w, NULL, NULL);
    vsv_writer_free(w);
    size_t sz = 0;
    unsigned char *d = rc ? NULL : vsv_test_slurp(path, &sz);
    CHECK(d && sz > 16 && d[8] == 3 && d[9] == 0 && d[10] == 0 && d[11] == 0,
          "written with the 3-D kinds, a file with stored heights says format 3.0", "rc %d", rc);
    CHECK(d && sz + 4 * n / 2 < raw_size, "its coded heights take under half their raw bytes",
          "%zu bytes against 1.1's %zu", sz, raw_size);
    ref_file rf;
    char err[256];
    uint16_t *codes = malloc(n * sizeof *codes);
    float *vals = malloc(n * sizeof *vals);
    CHECK(d && codes && vals && ref_open(&rf, d, sz, err, sizeof err) == 0 &&
              ref_decode(&rf, 2, 0, codes, vals, err, sizeof err) == 0 && fabsf(vals[n - 1] - v[2][n - 1]) < 1,
          "the reference reader reads a 3.0 file", "%s", err);
    if (d)
        ref_close(&rf);
    vsv_file *f = NULL;
    CHECK(vsv_file_open(path, &f) == 0, "a 3.0 file reads back", "%s", f ? vsv_file_error(f) : "");
    const vsv_meta *r = f ? vsv_file_meta(f) : NULL;
    int same = r && r->nheights == m->nheights;
    for (int h = 0; same && h < m->nheights; h++)
        same = r->heights[h].form == m->heights[h].form && r->heights[h].time == m->heights[h].time &&
               !memcmp(r->heights[h].z, m->heights[h].z, n * sizeof *r->heights[h].z);
    CHECK(same, "its heights come back bit for bit (the MM5 formula's and the coded ones)");
    vsv_file_free(f);
    free(d);
    free(codes);
    free(vals);
}

static void test_heights(void)
{
    enum { NX = 12, NY = 10, NZ = 6, NT = 3 };
    const size_t plane = NX * NY, n = plane * NZ;
    vsv_meta m;
    vsv_meta_init(&m);
    m.nx = NX, m.ny = NY, m.nz = NZ;
    m.vert_kind = VSV_VERT_NATIVE;
    m.spacing[0] = m.spacing[1] = 1000;
    vsv_meta_alloc_levels(&m);
    vsv_meta_alloc_terrain(&m);
    for (size_t c = 0; c < plane; c++)
        m.terrain[c] = (float)(100.0 * (double)(c % NX)); /* a slope, 0..1100 m */
    const double mm5[5] = {100000, 290, 50, 0, 10000};
    const double sigma[NZ] = {0.99, 0.95, 0.85, 0.6, 0.3, 0.05};
    CHECK(vsv_meta_add_heights(&m, INT64_MIN, NULL, mm5, sigma) == 0, "MM5 heights from the formula");
    /* a lowest level ~80 m above the ground whatever the ground */
    CHECK(m.nheights == 1 && fabsf(m.heights[0].z[0] - m.heights[0].z[NX - 1] + 1100.0f) < 80,
          "MM5 levels follow the terrain", "%g %g", m.heights[0].z[0], m.heights[0].z[NX - 1]);
    for (int k = 0; k < NZ; k++)
        m.levels[k] = m.heights[0].z[(size_t)k * plane];
    float *z = malloc(n * sizeof *z);
    for (size_t i = 0; i < n; i++)
        z[i] = m.heights[0].z[i] + 50.0f;
    CHECK(vsv_meta_add_heights(&m, 3600, z, NULL, NULL) == 0, "stored heights from the second step on");
    CHECK(vsv_meta_add_heights(&m, 3600, z, NULL, NULL) == VSV_EINVAL, "heights out of time order refused");
    z[plane] = z[0] - 1; /* level 1 below level 0 */
    CHECK(vsv_meta_add_heights(&m, 7200, z, NULL, NULL) == VSV_EINVAL, "heights not increasing upward refused");
    z[plane] = m.heights[0].z[plane] + 50.0f;
    vsv_meta_add_var(&m, "HGT", "m", "the height of the cell");
    /* the field is the height of its own cell */
    float *v[NT];
    for (int t = 0; t < NT; t++) {
        v[t] = malloc(n * sizeof *v[t]);
        const float *h = vsv_meta_heights_at(&m, t * 3600);
        for (size_t i = 0; i < n; i++)
            v[t][i] = h[i];
    }
    CHECK(vsv_meta_heights_at(&m, -5) == m.heights[0].z && vsv_meta_heights_at(&m, 7200) == m.heights[1].z,
          "the heights in force at a time");
    vsv_pack_opts o;
    vsv_pack_var pv;
    vsv_pack_opts_init(&o);
    vsv_pack_var_init(&pv);
    o.brick = 8;
    o.threads = 1;
    o.predict = 0; /* the minors of format 1 */
    o.vars = &pv;
    const char *path = vsv_test_tmp("heights.vsv");
    vsv_writer *w = NULL;
    int rc = vsv_writer_create(path, &m, &o, &w);
    for (int t = 0; t < NT && !rc; t++)
        rc = vsv_writer_add_step(w, t * 3600, (const float *const *)&v[t]);
    if (!rc)
        rc = vsv_writer_finish(w, NULL, NULL);
    vsv_writer_free(w);
    CHECK(rc == 0, "a file with heights is written");
    size_t sz = 0;
    unsigned char *d = vsv_test_slurp(path, &sz);
    CHECK(d && sz > 16 && d[10] == 1 && d[11] == 0, "its header says format 1.1");
    ref_file rf;
    char err[256];
    uint16_t *codes = malloc(n * sizeof *codes);
    float *vals = malloc(n * sizeof *vals);
    CHECK(d && ref_open(&rf, d, sz, err, sizeof err) == 0 && ref_decode(&rf, 2, 0, codes, vals, err, sizeof err) == 0 &&
              fabsf(vals[n - 1] - v[2][n - 1]) < 1,
          "the reference reader reads a 1.1 file", "%s", err);
    if (d)
        ref_close(&rf);
    vsv_file *f = NULL;
    CHECK(vsv_file_open(path, &f) == 0, "it reads back", "%s", f ? vsv_file_error(f) : "");
    const vsv_meta *r = f ? vsv_file_meta(f) : NULL;
    int same = r && r->nheights == 2 && r->heights[0].form == VSV_HEIGHTS_MM5 &&
               r->heights[1].form == VSV_HEIGHTS_STORED && r->heights[0].time == INT64_MIN &&
               r->heights[1].time == 3600;
    for (size_t i = 0; same && i < n; i++)
        same = r->heights[0].z[i] == m.heights[0].z[i] && r->heights[1].z[i] == m.heights[1].z[i];
    CHECK(same, "both records come back exactly");
    heights_coded(&m, v, NT, sz);
    /* the resampler: value = height, so each even cell holds its own height */
    vsv_resampler *rs = NULL;
    vsv_volume *vol = NULL;
    vsv_decoder *dec = NULL;
    const vsv_volume *e = NULL;
    double worst = 0;
    int inside = 0;
    if (r && vsv_resampler_create(r, &rs) == 0 && vsv_volume_create(f, &vol) == 0 && vsv_decoder_create(f, &dec) == 0 &&
        vsv_volume_load(vol, dec, 1, 0) == 0 && vsv_resampler_run(rs, vol, &e) == 0) {
        const vsv_meta *em = vsv_resampler_meta(rs);
        const float *h = vsv_meta_heights_at(r, vol->time);
        for (int k = 0; k < e->nz; k++)
            for (int j = 0; j < NY; j++)
                for (int i = 0; i < NX; i++) {
                    const size_t c = (size_t)j * NX + i;
                    const double zc = em->origin[2] + k * em->spacing[2];
                    if (zc < h[c] || zc > h[(size_t)(NZ - 1) * plane + c])
                        continue;
                    inside++;
                    const double err1 = fabs(vsv_volume_at(e, i, j, k) - zc);
                    worst = err1 > worst ? err1 : worst;
                }
        CHECK(em->vert_kind == VSV_VERT_EVEN && em->nz == 40 && e->nz == 40, "the even axis: 40 levels", "%d", em->nz);
    }
    CHECK(inside > 1000 && worst < 1.0, "resampled: every cell between the levels holds its own height",
          "%d cells, worst %g m", inside, worst);
    vsv_resampler_free(rs);
    vsv_volume_free(vol);
    vsv_decoder_free(dec);
    vsv_file_free(f);
    /* a file without heights stays 1.0 */
    vsv_meta plain;
    vsv_meta_init(&plain);
    vsv_meta_copy(&plain, &m);
    vsv_heights_clear_all(&plain);
    plain.vert_kind = VSV_VERT_EVEN;
    w = NULL;
    rc = vsv_writer_create(path, &plain, &o, &w);
    if (!rc)
        rc = vsv_writer_add_step(w, 0, (const float *const *)&v[0]);
    if (!rc)
        rc = vsv_writer_finish(w, NULL, NULL);
    vsv_writer_free(w);
    free(d);
    d = vsv_test_slurp(path, &sz);
    CHECK(rc == 0 && d && d[10] == 0, "a file without heights stays format 1.0");
    vsv_meta_clear(&plain);
    free(d);
    free(codes);
    free(vals);
    free(z);
    for (int t = 0; t < NT; t++)
        free(v[t]);
    vsv_meta_clear(&m);
}

/* Format 2's 3-D brick kinds (SPEC.md §7): the same series written as 2.0
 * (the default) and 1.x decodes to the same codes bit for bit (the coding
 * is lossless on them), the reference reader agrees, values are within the
 * stated bound and no-data cells stay no-data; a smooth field takes the
 * 3-D kinds and the file is smaller. Edge cases: a constant field, an
 * all-zero one, edge bricks cut by the grid, and a grid at the largest
 * edge the format allows. */
static void test_predict(void)
{
    enum { NX = 40, NY = 36, NZ = 20, NT = 4, NS = 4 };
    const size_t n = (size_t)NX * NY * NZ;
    vsv_meta m;
    vsv_meta_init(&m);
    m.nx = NX, m.ny = NY, m.nz = NZ;
    m.spacing[0] = m.spacing[1] = m.spacing[2] = 1000;
    vsv_meta_add_var(&m, "ramp", "1", "smooth, drifting");
    vsv_meta_add_var(&m, "const", "1", "constant");
    vsv_meta_add_var(&m, "zero", "1", "all zero");
    vsv_meta_add_var(&m, "blob", "1", "a moving blob with no-data cells");
    float *v = malloc((size_t)NT * NS * n * sizeof *v);
    for (int t = 0; t < NT; t++)
        for (size_t c = 0; c < n; c++) {
            const int i = (int)(c % NX), j = (int)(c / NX % NY), k = (int)(c / NX / NY);
            float *f = v + (size_t)t * NS * n;
            f[c] = (float)(0.3 * i + 0.7 * j + 1.1 * k + 0.01 * i * j + 0.5 * t);
            f[n + c] = 5.0f;
            f[2 * n + c] = 0.0f;
            const double r2 = (i - 15.0 - 3 * t) * (i - 15.0 - 3 * t) + (j - 18.0) * (j - 18.0) + (k - 8.0) * (k - 8.0);
            f[3 * n + c] = k == 0 && i < 6 ? NAN : (float)(-2 + 10 * exp(-r2 / 40));
        }
    const char *p2 = vsv_test_tmp("predict2.vsv"), *p1 = vsv_test_tmp("predict1.vsv");
    int rc = 0;
    for (int pass = 0; pass < 2 && !rc; pass++) {
        vsv_pack_opts o;
        vsv_pack_opts_init(&o);
        o.brick = 16;
        o.keyframe = 3;
        o.threads = 1;
        o.predict = pass == 0;
        vsv_writer *w = NULL;
        rc = vsv_writer_create(pass == 0 ? p2 : p1, &m, &o, &w);
        for (int t = 0; t < NT && !rc; t++) {
            const float *fl[NS];
            for (int s = 0; s < NS; s++)
                fl[s] = v + ((size_t)t * NS + s) * n;
            rc = vsv_writer_add_step(w, 3600 * t, fl);
        }
        if (!rc)
            rc = vsv_writer_finish(w, NULL, NULL);
        vsv_writer_free(w);
    }
    CHECK(rc == 0, "a series written as format 2 and as format 1");
    size_t n2 = 0, n1 = 0;
    unsigned char *d2 = vsv_test_slurp(p2, &n2), *d1 = vsv_test_slurp(p1, &n1);
    CHECK(d2 && d1 && d2[8] == 2 && d2[10] == 0 && d1[8] == 1, "their headers say 2.0 and 1.0");
    vsv_file *f2 = NULL, *f1 = NULL;
    vsv_decoder *x2 = NULL, *x1 = NULL;
    int ok = d2 && d1 && !vsv_file_open_mem(d2, n2, "predict2.vsv", &f2) &&
             !vsv_file_open_mem(d1, n1, "predict1.vsv", &f1) && !vsv_decoder_create(f2, &x2) &&
             !vsv_decoder_create(f1, &x1);
    CHECK(ok && vsv_file_check(f2, NULL, NULL) == 0, "the format-2 file checks", "%s", ok ? vsv_file_error(f2) : "");
    int kinds[6] = {0};
    for (int t = 0; t < NT && ok; t++)
        for (int s = 0; s < NS; s++)
            for (int b = 0; b < 3 * 3 * 2; b++) {
                const int k = vsv_file_brick_kind(f2, t, s, b);
                if (k >= 0 && k < 6)
                    kinds[k]++;
            }
    CHECK(kinds[VSV_BRICK_ABS3] > 0 && kinds[VSV_BRICK_DELTA3] > 0, "the smooth fields take the 3-D kinds",
          "(ABS %d, DELTA %d, ABS3 %d, DELTA3 %d)", kinds[2], kinds[3], kinds[4], kinds[5]);
    CHECK(n2 < n1, "the format-2 file is smaller", "%zu vs %zu bytes", n2, n1);
    float *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b), *rv = malloc(n * sizeof *rv);
    uint16_t *codes = malloc(n * sizeof *codes);
    ref_file rf;
    char err[256] = "";
    int same = ok, refok = ok && ref_open(&rf, d2, n2, err, sizeof err) == 0, within = ok, nodata = ok;
    double worst = 0;
    for (int t = 0; t < NT && same; t++)
        for (int s = 0; s < NS && same; s++) {
            same = !vsv_decoder_volume(x2, t, s, a) && !vsv_decoder_volume(x1, t, s, b) && !memcmp(a, b, n * sizeof *a);
            if (refok)
                refok = ref_decode(&rf, (unsigned)t, (unsigned)s, codes, rv, err, sizeof err) == 0 &&
                        !memcmp(a, rv, n * sizeof *a);
            const double bound = vsv_file_quant(f2, s)->max_abs_error;
            const float *in = v + ((size_t)t * NS + s) * n;
            for (size_t c = 0; c < n; c++) {
                if (in[c] != in[c]) {
                    nodata &= a[c] != a[c];
                    continue;
                }
                const double e = fabs((double)a[c] - in[c]);
                worst = e > worst ? e : worst;
                within &= e <= bound;
            }
        }
    CHECK(same, "format 2 decodes to format 1's values bit for bit, every step and species");
    CHECK(refok, "the reference reader decodes the format-2 file to the same values", "%s", err);
    CHECK(within, "decoded values within the stated bound", "(worst %g)", worst);
    CHECK(nodata, "no-data cells (NaN in) read as no data");
    if (refok)
        ref_close(&rf);
    vsv_decoder_free(x2);
    vsv_decoder_free(x1);
    vsv_file_free(f2);
    vsv_file_free(f1);
    free(d2);
    free(d1);
    unlink(p2);
    unlink(p1);
    free(a);
    free(b);
    free(rv);
    free(codes);
    free(v);
    vsv_meta_clear(&m);

    /* the largest edge the format allows (16384 cells along x) */
    vsv_meta_init(&m);
    m.nx = 16384, m.ny = 2, m.nz = 1;
    m.spacing[0] = m.spacing[1] = m.spacing[2] = 1;
    vsv_meta_add_var(&m, "x", "1", "a ramp along x");
    const size_t nl = (size_t)m.nx * m.ny;
    float *l = malloc(nl * sizeof *l), *back = malloc(nl * sizeof *back);
    for (size_t c = 0; c < nl; c++)
        l[c] = (float)(c % 16384) * 0.25f + (float)(c / 16384);
    vsv_pack_opts o;
    vsv_pack_opts_init(&o);
    o.brick = 64;
    vsv_writer *w = NULL;
    const char *pl = vsv_test_tmp("predict-long.vsv");
    rc = vsv_writer_create(pl, &m, &o, &w);
    const float *lf[1] = {l};
    if (!rc)
        rc = vsv_writer_add_step(w, 0, lf);
    if (!rc)
        rc = vsv_writer_finish(w, NULL, NULL);
    vsv_writer_free(w);
    vsv_file *fl = NULL;
    vsv_decoder *xl = NULL;
    ok = !rc && !vsv_file_open(pl, &fl) && !vsv_decoder_create(fl, &xl) && !vsv_decoder_volume(xl, 0, 0, back);
    double lw = 0;
    for (size_t c = 0; ok && c < nl; c++)
        lw = fmax(lw, fabs((double)back[c] - l[c]));
    CHECK(ok && lw <= vsv_file_quant(fl, 0)->max_abs_error, "a 16384-cell edge round-trips within the bound (format 2)",
          "(worst %g)", lw);
    vsv_decoder_free(xl);
    vsv_file_free(fl);
    unlink(pl);
    free(l);
    free(back);
    vsv_meta_clear(&m);
}

/* Below the ground no species has data (SPEC.md "No data below the
 * ground"): on even heights over a terrain, the value readers give NaN in
 * every cell whose centre lies below it, for a concentration (0 its
 * smallest value: code 0 is zero and no data alike) as for a field whose
 * no-data has a code of its own; the codes themselves are the writer's. */
static void test_below_ground(void)
{
    enum { NX = 20, NY = 10, NZ = 8 };
    const size_t n = (size_t)NX * NY * NZ;
    vsv_meta m;
    vsv_meta_init(&m);
    m.nx = NX, m.ny = NY, m.nz = NZ;
    m.spacing[0] = m.spacing[1] = 1000, m.spacing[2] = 250;
    m.origin[2] = 125; /* centres 125, 375, ... 1875 m */
    vsv_meta_add_var(&m, "CLW", "kg/kg", "0 at its least");
    vsv_meta_add_var(&m, "T", "K", "no zero");
    vsv_meta_alloc_terrain(&m);
    for (int c = 0; c < NX * NY; c++)
        m.terrain[c] = (float)(100 * (c % NX)); /* 0 .. 1900 m */
    float *clw = malloc(n * sizeof *clw), *tk = malloc(n * sizeof *tk), *out = malloc(n * sizeof *out);
    for (size_t c = 0; c < n; c++) {
        clw[c] = c % 7 ? 0.0f : 1e-4f; /* values below the ground too, as a careless writer gives */
        tk[c] = 280.0f - (float)(c / (NX * NY));
    }
    const char *path = vsv_test_tmp("below.vsv");
    vsv_writer *w = NULL;
    const float *fl[2] = {clw, tk};
    int rc = vsv_writer_create(path, &m, NULL, &w);
    if (!rc)
        rc = vsv_writer_add_step(w, 0, fl);
    if (!rc)
        rc = vsv_writer_finish(w, NULL, NULL);
    vsv_writer_free(w);
    vsv_file *f = NULL;
    vsv_decoder *d = NULL;
    CHECK(rc == 0 && vsv_file_open(path, &f) == 0 && vsv_decoder_create(f, &d) == 0, "a file over a terrain");
    int vol_ok = 1, under = 0, above_ok = 1;
    for (int s = 0; s < 2 && d; s++) {
        vol_ok &= vsv_decoder_volume(d, 0, s, out) == 0;
        for (size_t c = 0; c < n; c++) {
            const int i = (int)(c % NX), k = (int)(c / (NX * NY));
            if (125.0 + 250.0 * k < 100.0 * i) {
                under += s == 0;
                vol_ok &= isnan(out[c]);
            } else {
                above_ok &= fabsf(out[c] - (s ? tk : clw)[c]) <= vsv_file_quant(f, s)->max_abs_error;
            }
        }
    }
    CHECK(vol_ok && under == 760, "every species reads NaN in the cells below the ground", "%d cells", under);
    CHECK(above_ok, "and its values above it");
    float *brick = malloc(32 * 32 * 32 * sizeof *brick);
    int brick_ok = d && vsv_decoder_brick(d, 0, 0, 0, brick) == 0;
    for (int k = 0; k < NZ && brick_ok; k++)
        for (int i = 0; i < NX; i++)
            brick_ok &= !!isnan(brick[((size_t)k * 32 + 3) * 32 + i]) == (125.0 + 250.0 * k < 100.0 * i);
    CHECK(brick_ok, "a brick decodes the same no data");
    free(brick);
    vsv_decoder_free(d);
    vsv_file_free(f);
    vsv_meta_clear(&m);
    free(clw);
    free(tk);
    free(out);
}

int main(void)
{
    test_series();
    test_variants();
    test_heights();
    test_predict();
    test_below_ground();
    return vsv_test_done();
}
