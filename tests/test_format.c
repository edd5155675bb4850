/* test_format.c — unit and round-trip tests of the .vsv format library on
 * synthetic series: exactness of deltas, random access, empty bricks,
 * quantisation bounds, cross-check with the reference reader, damage and
 * truncation at every byte, golden files. */
#include "vsv_format_internal.h"
#include "vsv_refread.h"
#include "vsv_synth.h"
#include "vsv_testlib.h"

#include <dirent.h>
#include <sys/stat.h>
#include <unistd.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void test_basics(void)
{
    CHECK(vsv_crc32c(0, "123456789", 9) == 0xE3069283u, "crc32c known vector");
    uint64_t st = 7;
    unsigned char buf[1000];
    for (size_t i = 0; i < sizeof buf; i++)
        buf[i] = (unsigned char)vsv_test_rand(&st);
    int same = 1;
    for (size_t n = 0; n < sizeof buf; n += 37)
        same &= vsv_crc32c(0, buf, n) == ref_crc32c(buf, n);
    CHECK(same, "crc32c equals the bitwise reference at many lengths");
    CHECK(vsv_crc32c(vsv_crc32c(0, buf, 300), buf + 300, 700) == vsv_crc32c(0, buf, 1000), "crc32c continues");

    char t[40];
    CHECK(vsv_time_from_civil(1970, 1, 1, 0, 0, 0) == 0, "epoch is 0");
    CHECK(vsv_time_from_civil(2000, 3, 1, 0, 0, 0) == 951868800, "2000-03-01 seconds");
    vsv_time_format(-1, t, sizeof t);
    CHECK(!strcmp(t, "1969-12-31T23:59:59Z"), "negative time formats", "got %s", t);
    vsv_time_format(814492800 + 3 * 3600, t, sizeof t);
    CHECK(!strcmp(t, "1995-10-24T03:00:00Z"), "MM5 run time formats", "got %s", t);
    int64_t p = 0;
    CHECK(!vsv_time_parse("1995-10-24T03:00:00Z", &p) && p == 814492800 + 3 * 3600, "ISO time parses");
    CHECK(!vsv_time_parse("1995-10-24_03:00", &p) && p == 814492800 + 3 * 3600, "MM5-style time parses");
    CHECK(vsv_time_parse("1995-13-24", &p) == VSV_EINVAL, "bad month rejected");
}

static void test_quant(void)
{
    vsv_pack_var o;
    vsv_pack_var_init(&o);
    vsv_quant q;
    vsv_quant_plan(&q, &o, 200, 300, 200, 0);
    int ok = 1;
    for (double v = 200; v <= 300; v += 0.0137) {
        unsigned c = vsv_quant_code(&q, (float)v);
        ok &= fabs(vsv_quant_value(&q, c) - (float)v) <= q.max_abs_error;
    }
    CHECK(ok && q.max_abs_error < 100.0 / 65535, "linear 16-bit error within bound", "bound %g", q.max_abs_error);
    CHECK(vsv_quant_code(&q, NAN) == 0 && vsv_quant_code(&q, INFINITY) == 0, "non-finite values are code 0");
    vsv_quant_plan(&q, &o, 200, 300, 200, 1);
    ok = q.missing && vsv_quant_code(&q, 200) == 1 && vsv_quant_code(&q, 300) == 65535 && isnan(vsv_quant_value(&q, 0));
    for (double v = 200; v <= 300; v += 0.0137)
        ok &= fabs(vsv_quant_value(&q, vsv_quant_code(&q, (float)v)) - (float)v) <= q.max_abs_error;
    CHECK(ok, "linear with no-data cells: code 0 decodes to NaN, values within bound");
    o.scale = VSV_SCALE_LOG;
    o.bits = 8;
    vsv_quant_plan(&q, &o, 0, 1e-3, 1e-9, 0);
    CHECK(fabs(q.lo - 1e-6) < 1e-18 && q.hi == 1e-3, "log 8-bit spans 3 decades by default", "lo %g", q.lo);
    ok = 1;
    for (double v = 1e-9; v <= 1e-3; v *= 1.07) {
        unsigned c = vsv_quant_code(&q, (float)v);
        ok &= fabs(vsv_quant_value(&q, c) - (float)v) <= q.max_abs_error;
        ok &= v < q.lo ? c == 0 : c >= 1;
    }
    CHECK(ok, "log 8-bit error within bound, below floor is empty", "bound %g", q.max_abs_error);
    CHECK(vsv_quant_code(&q, 0) == 0 && vsv_quant_value(&q, 0) == 0, "log code 0 is zero");
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
    CHECK(within, "no drift: every value of 120 steps within the stated bound",
          "worst %g %g %g, bounds %g %g %g", worst[0], worst[1], worst[2], vsv_file_quant(f, 0)->max_abs_error,
          vsv_file_quant(f, 1)->max_abs_error, vsv_file_quant(f, 2)->max_abs_error);
    printf("  worst errors: CLW %.3g (bound %.3g), T %.3g (bound %.3g), O3 %.3g (bound %.3g)\n", worst[0],
           vsv_file_quant(f, 0)->max_abs_error, worst[1], vsv_file_quant(f, 1)->max_abs_error, worst[2],
           vsv_file_quant(f, 2)->max_abs_error);

    /* random access with fresh decoders equals the sequential decode */
    uint64_t rs = 42;
    int same = 1;
    for (int n = 0; n < 60; n++) {
        int t = (int)(vsv_test_rand(&rs) % 120), s = (int)(vsv_test_rand(&rs) % 3);
        vsv_decoder *d2 = NULL;
        vsv_decoder_create(f, &d2);
        same &= vsv_decoder_volume(d2, t, s, vol) == 0 && vsv_crc32c(0, vol, cells * 4) == crcs[t][s];
        vsv_decoder_free(d2);
    }
    /* and backwards with one decoder */
    for (int t = 119; t >= 0; t -= 7)
        same &= vsv_decoder_volume(d, t, 1, vol) == 0 && vsv_crc32c(0, vol, cells * 4) == crcs[t][1];
    CHECK(same, "random access and backward decode equal sequential decode bit for bit");

    /* one brick equals its part of the volume */
    float *brick = malloc(16 * 16 * 16 * 4);
    int bok = 1;
    for (int n = 0; n < 40; n++) {
        int t = (int)(vsv_test_rand(&rs) % 120), s = (int)(vsv_test_rand(&rs) % 3),
            b = (int)(vsv_test_rand(&rs) % (unsigned)info.nbricks);
        int org[3], ext[3];
        vsv_file_brick_box(f, b, org, ext);
        bok &= vsv_decoder_brick(d, t, s, b, brick) == 0 && vsv_decoder_volume(d, t, s, vol) == 0;
        for (int k = 0; k < ext[2]; k++)
            for (int j = 0; j < ext[1]; j++)
                for (int i = 0; i < ext[0]; i++)
                    bok &= brick[(k * 16 + j) * 16 + i] ==
                           vol[((size_t)(org[2] + k) * 50 + org[1] + j) * 70 + org[0] + i];
    }
    CHECK(bok, "single-brick decode equals the volume");

    /* empty bricks cost nothing; the octree says which */
    int kinds_ok = 1, empty_seen = 0, unchanged_frozen = 1;
    for (int t = 0; t < 120; t++) {
        int dims[3 * 16];
        const unsigned char *oct = vsv_file_octree(f, t, 0, dims);
        for (int b = 0; b < info.nbricks; b++) {
            unsigned mn, mx;
            vsv_octree_node(oct, (size_t)b, &mn, &mx);
            int kind = vsv_file_brick_kind(f, t, 0, b);
            if (mx == 0) {
                empty_seen++;
                kinds_ok &= kind == VSV_BRICK_EMPTY || kind == VSV_BRICK_UNCHANGED;
            }
            if (t > 40 && t <= 60 && t % 8)
                unchanged_frozen &= vsv_file_brick_kind(f, t, 2, b) == VSV_BRICK_UNCHANGED;
        }
    }
    CHECK(empty_seen > 0 && kinds_ok, "empty bricks are stored as EMPTY/UNCHANGED", "%d empty", empty_seen);
    vsv_file_counts cnt;
    vsv_file_count(f, &cnt);
    CHECK(cnt.stored_bricks < (uint64_t)info.nbricks * 3 * 120, "fewer payloads than bricks",
          "%llu stored", (unsigned long long)cnt.stored_bricks);
    CHECK(unchanged_frozen, "unchanged steps store no payload");

    /* the octree root bounds the volume */
    int dims[3 * 16];
    const unsigned char *oct = vsv_file_octree(f, 77, 1, dims);
    unsigned rmn, rmx;
    vsv_octree_node(oct, vsv_file_octree_level_start(f, info.octree_levels - 1), &rmn, &rmx);
    vsv_decoder_volume(d, 77, 1, vol);
    float vmn = INFINITY, vmx = -INFINITY;
    for (size_t i = 0; i < cells; i++) {
        vmn = vol[i] < vmn ? vol[i] : vmn;
        vmx = vol[i] > vmx ? vol[i] : vmx;
    }
    CHECK(vsv_quant_value(vsv_file_quant(f, 1), rmn) == vmn && vsv_quant_value(vsv_file_quant(f, 1), rmx) == vmx,
          "octree root min/max equal the volume's");

    /* reference reader agrees exactly */
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
    CHECK(info.file_bytes * 4 < cells * 4 * 3 * 120, "file is under a quarter of raw float32",
          "%llu bytes", (unsigned long long)info.file_bytes);
    free(data);
    free(brick);
    free(vol);
    vsv_decoder_free(d);
    vsv_file_free(f);

    /* the thread count does not change a byte */
    const char *p1 = vsv_test_tmp("series-t1.vsv");
    o.threads = 1;
    synth_write(&sy, p1, &o, err, sizeof err);
    size_t n1, n2;
    unsigned char *a1 = vsv_test_slurp(p1, &n1), *a2 = vsv_test_slurp(path, &n2);
    CHECK(a1 && a2 && n1 == n2 && !memcmp(a1, a2, n1), "1 and 2 encoder threads write identical files");
    free(a1);
    free(a2);
    unlink(p1);
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
        snprintf(label, sizeof label, "variant brick %d, %d bits, %s, K=%d, codec %s round trips within bound",
                 o.brick, pv[0].bits, pv[0].scale ? "log" : "linear", o.keyframe, o.codec ? "zstd" : "none");
        CHECK(ok, label, "%s %s", err, f ? vsv_file_error(f) : "");
        free(vol);
        vsv_decoder_free(d);
        vsv_file_free(f);
        unlink(path);
    }
}

static int dir_has_temp(const char *dir)
{
    DIR *dp = opendir(dir);
    int found = 0;
    struct dirent *e;
    while (dp && (e = readdir(dp)))
        found |= strstr(e->d_name, ".tmp.") || strstr(e->d_name, ".spool.");
    if (dp)
        closedir(dp);
    return found;
}

static void test_atomic(void)
{
    synth sy = {10, 10, 4, 3, 9, 9};
    vsv_meta m;
    vsv_meta_init(&m);
    synth_meta(&sy, &m);
    const char *path = vsv_test_tmp("atomic.vsv");
    unlink(path);
    vsv_writer *w = NULL;
    float *f[3];
    for (int s = 0; s < 3; s++)
        f[s] = calloc(400, 4);
    int rc = vsv_writer_create(path, &m, NULL, &w);
    rc |= vsv_writer_add_step(w, 10, (const float *const *)f);
    CHECK(rc == 0 && access(path, F_OK) != 0, "nothing at the output path before finish");
    CHECK(vsv_writer_add_step(w, 10, (const float *const *)f) == VSV_EINVAL, "non-increasing time rejected",
          "%s", vsv_writer_error(w));
    vsv_writer_free(w);
    char dir[1024];
    snprintf(dir, sizeof dir, "%s", path);
    *strrchr(dir, '/') = 0;
    CHECK(access(path, F_OK) != 0 && !dir_has_temp(dir), "abandoned writer leaves no file and no temporaries");
    vsv_pack_opts o;
    vsv_pack_opts_init(&o);
    o.brick = 12;
    CHECK(vsv_writer_create(path, &m, &o, &w) == VSV_EINVAL && strstr(vsv_writer_error(w), "brick size 12"),
          "bad brick size rejected with a message");
    vsv_writer_free(w);
    w = NULL;
    /* a grid whose chunk index does not fit the 32-bit index size: refused
     * at create (issue 18: it was written, and the reader rejected it) */
    vsv_meta big;
    vsv_meta_init(&big);
    big.nx = 16384, big.ny = 8192, big.nz = 128;
    big.spacing[0] = big.spacing[1] = big.spacing[2] = 1;
    for (int s = 0; s < 5; s++) {
        char nm[8];
        snprintf(nm, sizeof nm, "S%d", s);
        vsv_meta_add_var(&big, nm, "1", "");
    }
    vsv_pack_opts_init(&o);
    o.brick = 8;
    rc = vsv_writer_create(path, &big, &o, &w);
    CHECK(rc == VSV_EINVAL &&
              strstr(vsv_writer_error(w), "a chunk index of 4793521520 bytes (5 species of 33554432 bricks of 8 cells) "
                                          "exceeds the format's 4 GiB limit"),
          "a grid whose chunk index exceeds 32 bits is refused at create", "%s", w ? vsv_writer_error(w) : "(no handle)");
    vsv_writer_free(w);
    vsv_meta_clear(&big);
    w = NULL;
    CHECK(vsv_writer_create("/nonexistent-dir/x.vsv", &m, NULL, &w) == VSV_EIO, "unwritable directory is an I/O error",
          "%s", vsv_writer_error(w));
    vsv_writer_free(w);
    for (int s = 0; s < 3; s++)
        free(f[s]);
    vsv_meta_clear(&m);
}

/* The small file of the damage tests and the golden file. */
static const synth small = {12, 10, 5, 5, 2, 3};

static void small_opts(vsv_pack_opts *o, vsv_pack_var *pv)
{
    vsv_pack_opts_init(o);
    o->brick = 8;
    o->keyframe = 3;
    o->threads = 1;
    o->predict = 0; /* format 1.0: tests/golden/small.vsv */
    for (int s = 0; s < 3; s++)
        vsv_pack_var_init(&pv[s]);
    pv[0].bits = 8;
    pv[2].scale = VSV_SCALE_LOG;
    pv[2].bits = 8; /* keeps the per-flip decode table small: 16k flips */
    o->vars = pv;
}

/* Every value of every (step, species) of an in-memory file, or -1. */
static int decode_all(vsv_file *f, float *out)
{
    vsv_decoder *d = NULL;
    if (vsv_decoder_create(f, &d))
        return -1;
    const size_t cells = (size_t)small.nx * small.ny * small.nz;
    int rc = 0;
    for (int t = 0; t < small.nsteps && !rc; t++)
        for (int s = 0; s < 3 && !rc; s++)
            rc = vsv_decoder_volume(d, t, s, out + ((size_t)t * 3 + s) * cells);
    vsv_decoder_free(d);
    return rc;
}

static void test_damage(void)
{
    const char *path = vsv_test_tmp("small.vsv");
    vsv_pack_opts o;
    vsv_pack_var pv[3];
    small_opts(&o, pv);
    char err[512];
    if (!CHECK(synth_write(&small, path, &o, err, sizeof err) == 0, "write the small file", "%s", err))
        return;
    size_t n;
    unsigned char *good = vsv_test_slurp(path, &n);
    unsigned char *bad = malloc(n);
    const size_t total = (size_t)small.nx * small.ny * small.nz * 3 * small.nsteps;
    float *ref = malloc(total * 4), *got = malloc(total * 4);
    vsv_file *f = NULL;
    int ok = vsv_file_open_mem(good, n, "small.vsv", &f) == 0 && decode_all(f, ref) == 0 &&
             vsv_file_check(f, NULL, NULL) == 0;
    vsv_file_free(f);
    CHECK(ok, "the undamaged small file checks clean");
    printf("  small file: %zu bytes\n", n);
    /* flip every byte: check must fail; decoding must fail or give the truth */
    size_t undetected = 0, wrong = 0, first_undetected = 0;
    for (size_t i = 0; i < n; i++) {
        memcpy(bad, good, n);
        bad[i] ^= (unsigned char)(1u << (i % 8));
        f = NULL;
        int rc = vsv_file_open_mem(bad, n, "flip.vsv", &f);
        if (!rc) {
            int drc = decode_all(f, got);
            if (!drc && memcmp(got, ref, total * 4))
                wrong++;
            if (vsv_file_check(f, NULL, NULL) == 0) {
                if (!undetected)
                    first_undetected = i;
                undetected++;
            }
        }
        vsv_file_free(f);
    }
    CHECK(undetected == 0, "every flipped byte is reported by open or check", "%zu undetected, first at %zu",
          undetected, first_undetected);
    CHECK(wrong == 0, "no flipped byte yields a wrong value", "%zu wrong", wrong);
    /* truncation at every length */
    size_t accepted = 0;
    for (size_t len = 0; len < n; len++) {
        f = NULL;
        if (vsv_file_open_mem(good, len, "cut.vsv", &f) == 0)
            accepted++;
        vsv_file_free(f);
    }
    CHECK(accepted == 0, "truncation at every offset is an error", "%zu accepted", accepted);
    f = NULL;
    int rc = vsv_file_open_mem(good, n - 100, "cut.vsv", &f);
    CHECK(rc == VSV_ETRUNC && strstr(vsv_file_error(f), "truncated"), "truncation names itself", "%s",
          vsv_file_error(f));
    vsv_file_free(f);
    /* wrong kinds of file */
    const char *texts[] = {"", "hello world, this is not a vsv file at all\n", "\x89PNG\r\n\x1a\n0000000000000000"};
    for (int k = 0; k < 3; k++) {
        f = NULL;
        rc = vsv_file_open_mem(texts[k], strlen(texts[k]), "other", &f);
        CHECK(rc == VSV_ENOTVSV && strstr(vsv_file_error(f), "not a .vsv file"), "wrong-kind file is 'not a .vsv file'",
              "rc %d: %s", rc, vsv_file_error(f));
        vsv_file_free(f);
    }
    memcpy(bad, good, n);
    bad[8] = 3; /* 1 and 2 are read */
    f = NULL;
    rc = vsv_file_open_mem(bad, n, "v2.vsv", &f);
    CHECK(rc == VSV_EVERSION, "a future major version is refused", "%s", vsv_file_error(f));
    vsv_file_free(f);
    free(good);
    free(bad);
    free(ref);
    free(got);
}

/* Golden files: the writer reproduces the committed file byte for byte, and
 * each damaged golden file fails with its recorded message. */
static void test_golden(void)
{
    const char *dir = getenv("GOLDEN") ? getenv("GOLDEN") : "tests/golden";
    char gpath[1024];
    snprintf(gpath, sizeof gpath, "%s/small.vsv", dir);
    const char *fresh = vsv_test_tmp("golden-fresh.vsv");
    vsv_pack_opts o;
    vsv_pack_var pv[3];
    small_opts(&o, pv);
    char err[512];
    synth_write(&small, fresh, &o, err, sizeof err);
    size_t ng, nf;
    unsigned char *g = vsv_test_slurp(gpath, &ng), *fr = vsv_test_slurp(fresh, &nf);
    if (!g && getenv("VSV_REGEN_GOLDEN")) {
        vsv_test_write(gpath, fr, nf);
        g = vsv_test_slurp(gpath, &ng);
    }
    CHECK(g && fr && ng == nf && !memcmp(g, fr, ng), "writer reproduces tests/golden/small.vsv byte for byte");
    vsv_file *f = NULL;
    CHECK(g && vsv_file_open_mem(g, ng, "small.vsv", &f) == 0 && vsv_file_check(f, NULL, NULL) == 0,
          "golden file opens and checks");
    vsv_file_free(f);
    free(fr);
    unlink(fresh);
    /* damaged goldens: "name<TAB>the exact message" lines */
    char lpath[1024];
    snprintf(lpath, sizeof lpath, "%s/bad/EXPECTED", dir);
    FILE *lf = fopen(lpath, "r");
    char line[512];
    int count = 0;
    while (lf && fgets(line, sizeof line, lf)) {
        line[strcspn(line, "\n")] = 0;
        char *tab = strchr(line, '\t');
        if (!tab || line[0] == '#')
            continue;
        *tab = 0;
        char bpath[1024];
        snprintf(bpath, sizeof bpath, "%s/bad/%s", dir, line);
        f = NULL;
        int rc = vsv_file_open(bpath, &f);
        if (!rc)
            rc = vsv_file_check(f, NULL, NULL);
        char label[1100];
        snprintf(label, sizeof label, "damaged golden %s: %s", line, tab + 1);
        char want[1600];
        snprintf(want, sizeof want, "%s: %s", bpath, tab + 1);
        CHECK(rc != 0 && !strcmp(vsv_file_error(f), want), label, "got: %s", vsv_file_error(f));
        vsv_file_free(f);
        count++;
    }
    if (lf)
        fclose(lf);
    CHECK(count >= 26, "damaged golden files present", "%d", count);
    free(g);
}

/* Writing in parts (what vsv-convert-mpi's ranks do): statistics gathered in
 * three pieces and merged, chunks encoded by three encoders each over whole
 * keyframe groups, the file put together from the plan's metadata, the
 * chunks and the tail: byte for byte the writer's file. */
static void test_parts(void)
{
    const synth sy = {45, 37, 19, 13, 3, 6};
    const char *ref = vsv_test_tmp("parts-ref.vsv");
    vsv_pack_opts o;
    vsv_pack_opts_init(&o);
    o.brick = 16;
    o.keyframe = 4;
    char err[512];
    CHECK(!synth_write(&sy, ref, &o, err, sizeof err), "parts: reference file written", "%s", err);
    vsv_meta m;
    vsv_meta_init(&m);
    synth_meta(&sy, &m);
    const size_t cells = (size_t)sy.nx * sy.ny * sy.nz;
    float *f = malloc((size_t)sy.nsteps * 3 * cells * sizeof *f);
    for (int t = 0; t < sy.nsteps; t++)
        for (int s = 0; s < 3; s++)
            for (int k = 0; k < sy.nz; k++)
                for (int j = 0; j < sy.ny; j++)
                    for (int i = 0; i < sy.nx; i++)
                        f[((size_t)t * 3 + s) * cells + ((size_t)k * sy.ny + j) * sy.nx + i] =
                            synth_value(&sy, s, t, i, j, k);
    /* three "ranks": steps [0,4) [4,12) [12,13), whole keyframe groups */
    const int from[4] = {0, 4, 12, 13};
    vsv_pack_stats all[3], part[3];
    vsv_pack_stats_init(all, 3);
    for (int r = 0; r < 3; r++) {
        vsv_pack_stats_init(part, 3);
        for (int t = from[r]; t < from[r + 1]; t++) {
            const float *fl[3] = {f + (size_t)t * 3 * cells, f + ((size_t)t * 3 + 1) * cells,
                                  f + ((size_t)t * 3 + 2) * cells};
            vsv_pack_stats_add(part, 3, cells, fl);
        }
        vsv_pack_stats_merge(all, part, 3);
    }
    vsv_pack_plan *plan = NULL;
    int rc = vsv_pack_plan_create(&m, &o, all, &plan);
    CHECK(!rc, "parts: plan created", "%s", vsv_pack_plan_error(plan));
    vsv_buf file = {0};
    uint64_t sizes[13];
    int64_t times[13];
    const uint64_t first = vsv_pack_plan_first_chunk(plan);
    vsv_buf_zeros(&file, VSV_HEADER_SIZE);
    vsv_buf_put(&file, vsv_pack_plan_meta_bytes(plan), first - VSV_HEADER_SIZE);
    for (int r = 0; !rc && r < 3; r++) {
        vsv_chunk_encoder *e = NULL;
        rc = vsv_chunk_encoder_create(plan, &e);
        for (int t = from[r]; !rc && t < from[r + 1]; t++) {
            const float *cur[3], *prev[3];
            for (int s = 0; s < 3; s++) {
                cur[s] = f + ((size_t)t * 3 + s) * cells;
                prev[s] = t ? f + ((size_t)(t - 1) * 3 + s) * cells : NULL;
            }
            const unsigned char *bytes;
            size_t n;
            /* a group's first step is a keyframe: it needs no step before */
            rc = vsv_chunk_encode(e, t, synth_time(t), cur, t == from[r] ? NULL : prev, &bytes, &n);
            if (!rc) {
                sizes[t] = n;
                times[t] = synth_time(t);
                vsv_buf_put(&file, bytes, n);
            }
        }
        if (rc)
            CHECK(0, "parts: chunks encoded", "%s", vsv_chunk_encoder_error(e));
        vsv_chunk_encoder_free(e);
    }
    unsigned char *tail = malloc(vsv_pack_tail_bytes(13));
    uint64_t tail_off = 0;
    if (!rc)
        rc = vsv_pack_plan_finish(plan, 13, times, sizes, file.p, tail, &tail_off);
    CHECK(!rc && tail_off == file.len, "parts: tail starts where the last chunk ends", "%llu vs %zu",
          (unsigned long long)tail_off, file.len);
    vsv_buf_put(&file, tail, vsv_pack_tail_bytes(13));
    size_t nref = 0;
    unsigned char *want = vsv_test_slurp(ref, &nref);
    CHECK(want && nref == file.len && !memcmp(want, file.p, nref), "parts: assembled file is the writer's, byte for byte",
          "%zu vs %zu bytes", file.len, nref);
    /* misuse is reported, not encoded */
    vsv_chunk_encoder *e = NULL;
    const unsigned char *bytes;
    size_t n;
    const float *cur[3] = {f, f + cells, f + 2 * cells};
    CHECK(!vsv_chunk_encoder_create(plan, &e) && vsv_chunk_encode(e, 5, 0, cur, NULL, &bytes, &n) == VSV_EINVAL &&
              strstr(vsv_chunk_encoder_error(e), "step before"),
          "parts: a delta step without the step before is refused", "%s", vsv_chunk_encoder_error(e));
    vsv_chunk_encoder_free(e);
    times[7] = times[6];
    CHECK(vsv_pack_plan_finish(plan, 13, times, sizes, file.p, tail, &tail_off) == VSV_EINVAL &&
              strstr(vsv_pack_plan_error(plan), "step 7"),
          "parts: times that do not increase are refused", "%s", vsv_pack_plan_error(plan));
    free(want);
    free(tail);
    vsv_buf_free(&file);
    vsv_pack_plan_free(plan);
    vsv_meta_clear(&m);
    free(f);
}

/* Per-column heights (SPEC.md HGTS, format 1.1): both forms round-trip, the
 * file says 1.1 (and a file without them still 1.0), the reference reader
 * (which knows nothing of HGTS) still reads it, bad heights are refused, and
 * the resampler puts a field equal to each cell's height at the even cell's
 * own height. */
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
    CHECK(m.nheights == 1 && fabsf(m.heights[0].z[0] - m.heights[0].z[NX - 1] + 1100.0f) < 80, "MM5 levels follow the terrain",
          "%g %g", m.heights[0].z[0], m.heights[0].z[NX - 1]);
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
    int same = r && r->nheights == 2 && r->heights[0].form == VSV_HEIGHTS_MM5 && r->heights[1].form == VSV_HEIGHTS_STORED &&
               r->heights[0].time == INT64_MIN && r->heights[1].time == 3600;
    for (size_t i = 0; same && i < n; i++)
        same = r->heights[0].z[i] == m.heights[0].z[i] && r->heights[1].z[i] == m.heights[1].z[i];
    CHECK(same, "both records come back exactly");
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
    int ok = d2 && d1 && !vsv_file_open_mem(d2, n2, "predict2.vsv", &f2) && !vsv_file_open_mem(d1, n1, "predict1.vsv", &f1) &&
             !vsv_decoder_create(f2, &x2) && !vsv_decoder_create(f1, &x1);
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

/* A file cut short after it was opened (another program truncating it):
 * reads past its new end are "truncated while reading" errors, not SIGBUS
 * (vsv_mapguard.c). */
static void test_truncated_while_reading(void)
{
    synth sy = {40, 30, 10, 12, 0, 0};
    const char *path = vsv_test_tmp("cut.vsv");
    vsv_pack_opts o;
    vsv_pack_opts_init(&o);
    o.brick = 8;
    o.codec = VSV_CODEC_NONE;
    char err[512] = "";
    if (!CHECK(synth_write(&sy, path, &o, err, sizeof err) == 0, "write a file to cut", "%s", err))
        return;
    struct stat st;
    stat(path, &st);
    for (int pass = 0; pass < 2; pass++) {
        vsv_file *f = NULL;
        if (!CHECK(vsv_file_open(path, &f) == 0, "open it", "%s", vsv_file_error(f))) {
            vsv_file_free(f);
            return;
        }
        if (!CHECK(truncate(path, st.st_size / 3) == 0, "cut it to a third after opening"))
            return;
        int rc = 0;
        const char *msg = "";
        vsv_decoder *d = NULL;
        float *vol = malloc((size_t)sy.nx * sy.ny * sy.nz * sizeof *vol);
        if (pass == 0) {
            rc = vsv_file_check(f, NULL, NULL);
            msg = vsv_file_error(f);
        } else if (vsv_decoder_create(f, &d) == 0 && vol) {
            for (int t = 0; t < sy.nsteps && !rc; t++)
                rc = vsv_decoder_volume(d, t, 0, vol);
            msg = vsv_decoder_error(d);
        }
        CHECK(rc == VSV_ETRUNC && strstr(msg, "cut.vsv: truncated while reading"),
              pass ? "decoding a file cut while open: VSV_ETRUNC, named" : "checking a file cut while open: VSV_ETRUNC, named",
              "rc %d: %s", rc, msg);
        free(vol);
        vsv_decoder_free(d);
        vsv_file_free(f);
        if (!CHECK(synth_write(&sy, path, &o, err, sizeof err) == 0, "write it again", "%s", err))
            return;
    }
}

/* vsv_file_dequantise gives, for every code, the very bits of
 * vsv_quant_value (the rule of SPEC.md §6): linear 16-bit with code 0 as no
 * data (NaN), linear 16-bit without, and 8-bit (its table). */
static void test_dequantise(void)
{
    vsv_meta m;
    vsv_meta_init(&m);
    m.nx = 4, m.ny = 2, m.nz = 1;
    m.spacing[0] = m.spacing[1] = m.spacing[2] = 1;
    vsv_meta_add_var(&m, "gaps", "K", "");
    vsv_meta_add_var(&m, "full", "K", "");
    vsv_meta_add_var(&m, "byte", "K", "");
    vsv_pack_opts o;
    vsv_pack_var pv[3];
    vsv_pack_opts_init(&o);
    o.threads = 1;
    for (int s = 0; s < 3; s++)
        vsv_pack_var_init(&pv[s]);
    pv[2].bits = 8;
    o.vars = pv;
    const float gaps[8] = {201.5f, NAN, 250, 299.25f, 233, 201, 278.125f, 300};
    const float full[8] = {-3.75f, 0.5f, 1e3f, 17, 18, 19, 20, 21}, byte[8] = {1, 2, 3, 4, 5, 6, 7, 8.5f};
    const float *fields[3] = {gaps, full, byte};
    const char *path = vsv_test_tmp("dequant.vsv");
    vsv_writer *w = NULL;
    int rc = vsv_writer_create(path, &m, &o, &w);
    rc = rc ? rc : vsv_writer_add_step(w, 0, fields);
    rc = rc ? rc : vsv_writer_finish(w, NULL, NULL);
    vsv_writer_free(w);
    vsv_meta_clear(&m);
    vsv_file *f = NULL;
    CHECK(!rc && !vsv_file_open(path, &f), "dequantise test file written");
    if (!f)
        return;
    uint16_t *codes = malloc(65536 * sizeof *codes);
    float *got = malloc(65536 * sizeof *got), *want = malloc(65536 * sizeof *want);
    for (unsigned c = 0; c < 65536; c++)
        codes[c] = (uint16_t)c;
    for (int s = 0; s < 3; s++) {
        const vsv_quant *q = vsv_file_quant(f, s);
        const unsigned n = q->bits == 8 ? 256 : 65536;
        for (unsigned c = 0; c < n; c++)
            want[c] = vsv_quant_value(q, c);
        /* odd starts and lengths: the vector loops' edges */
        vsv_file_dequantise(f, s, codes, 3, got);
        vsv_file_dequantise(f, s, codes + 3, n - 3, got + 3);
        unsigned bad = n;
        for (unsigned c = n; c-- > 0;)
            if (memcmp(&got[c], &want[c], sizeof got[c]))
                bad = c;
        CHECK(bad == n && (s != 0 || (q->missing && isnan(got[0]))), "dequantise matches the rule bit for bit",
              "species %d (missing %d, bits %d): code %u gives %.9g, not %.9g", s, q->missing, q->bits, bad,
              bad < n ? got[bad] : 0, bad < n ? want[bad] : 0);
    }
    free(codes);
    free(got);
    free(want);
    vsv_file_free(f);
    unlink(path);
}

int main(void)
{
    test_basics();
    test_quant();
    test_dequantise();
    test_series();
    test_variants();
    test_atomic();
    test_damage();
    test_golden();
    test_parts();
    test_heights();
    test_predict();
    test_truncated_while_reading();
    return vsv_test_done();
}
