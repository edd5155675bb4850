/* test_format_damage.c — the .vsv format library against damage: the
 * writer's atomic output (nothing at the path until finish, no
 * temporaries left), refused grids, every flipped byte and every
 * truncation of a small file, wrong kinds of file, the golden file and
 * its damaged copies with their exact messages, and a file cut short
 * while it is open. */
#include "vsv_format.h"
#include "vsv_synth.h"
#include "vsv_testlib.h"

#include <dirent.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

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
    CHECK(vsv_writer_add_step(w, 10, (const float *const *)f) == VSV_EINVAL, "non-increasing time rejected", "%s",
          vsv_writer_error(w));
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
          "a grid whose chunk index exceeds 32 bits is refused at create", "%s",
          w ? vsv_writer_error(w) : "(no handle)");
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
    bad[8] = VSV_FORMAT_MAJOR + 1; /* 1 to VSV_FORMAT_MAJOR are read */
    f = NULL;
    rc = vsv_file_open_mem(bad, n, "v5.vsv", &f);
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
    CHECK(count >= 32, "damaged golden files present", "%d", count);
    free(g);
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
              pass ? "decoding a file cut while open: VSV_ETRUNC, named"
                   : "checking a file cut while open: VSV_ETRUNC, named",
              "rc %d: %s", rc, msg);
        free(vol);
        vsv_decoder_free(d);
        vsv_file_free(f);
        if (!CHECK(synth_write(&sy, path, &o, err, sizeof err) == 0, "write it again", "%s", err))
            return;
    }
}

/* The same cut after every chunk index was verified: the table of contents
 * now lies past the end, and reading it gave zeros, so a verified chunk
 * "was" at byte 0 and its brick entries came from the header (SIGSEGV in
 * vsv-render, vsv-export; issue 33). The table is the one read at open, a
 * brick's kind past the cut is an error, and every decode afterwards gives
 * the values decoded before the cut or VSV_ETRUNC, never others. */
static void test_truncated_after_verify(void)
{
    synth sy = {40, 30, 10, 12, 0, 0};
    const char *path = vsv_test_tmp("cut2.vsv");
    vsv_pack_opts o;
    vsv_pack_opts_init(&o);
    o.brick = 8;
    char err[512] = "";
    if (!CHECK(synth_write(&sy, path, &o, err, sizeof err) == 0, "write a file to cut", "%s", err))
        return;
    struct stat st;
    stat(path, &st);
    vsv_file *f = NULL;
    vsv_decoder *d = NULL;
    const size_t nv = (size_t)sy.nx * sy.ny * sy.nz;
    float *vol = malloc(nv * sizeof *vol), *all = malloc(nv * 3 * sy.nsteps * sizeof *all);
    int rc = vol && all ? vsv_file_open(path, &f) : VSV_ENOMEM;
    if (!rc)
        rc = vsv_decoder_create(f, &d);
    for (int t = 0; t < sy.nsteps && !rc; t++)
        for (int s = 0; s < 3 && !rc; s++)
            rc = vsv_decoder_volume(d, t, s, all + nv * (size_t)(3 * t + s));
    if (!CHECK(rc == 0, "open and decode every step", "%s", f ? vsv_file_error(f) : "out of memory"))
        goto done;
    const int last = sy.nsteps - 1;
    const int64_t when = vsv_file_time(f, last);
    if (!CHECK(truncate(path, st.st_size / 3) == 0, "cut it to a third after every chunk was verified"))
        goto done;
    rc = vsv_file_brick_kind(f, last, 1, 0);
    CHECK(rc == VSV_ETRUNC && strstr(vsv_file_error(f), "cut2.vsv: truncated while reading"),
          "a brick's kind in a verified chunk past the cut: VSV_ETRUNC, named", "rc %d: %s", rc, vsv_file_error(f));
    int cut = 0, wrong = 0;
    for (int t = last; t >= 0; t--)
        for (int s = 0; s < 3; s++) {
            rc = vsv_decoder_volume(d, t, s, vol);
            if (rc == VSV_ETRUNC && strstr(vsv_decoder_error(d), "cut2.vsv: truncated while reading"))
                cut++;
            else if (rc || memcmp(vol, all + nv * (size_t)(3 * t + s), nv * sizeof *vol))
                wrong += !CHECK(0, "decoding after the cut: the values from before it, or VSV_ETRUNC",
                                "step %d species %d: rc %d: %s", t, s, rc, vsv_decoder_error(d));
        }
    CHECK(cut > 0 && !wrong, "decoding every step after the cut: VSV_ETRUNC past it, named; never other values",
          "%d truncated, %d wrong", cut, wrong);
    CHECK(vsv_file_time(f, last) == when, "step times are still the file's (not zeros)", "%lld",
          (long long)vsv_file_time(f, last));
done:
    free(vol);
    free(all);
    vsv_decoder_free(d);
    vsv_file_free(f);
}

/* Cuts inside a page (issue 33's gap): the bytes between the new end and
 * the end of its page read as zeros without a signal, and a zeroed brick
 * entry is a valid EMPTY one, so a decode could return zeros as values.
 * Cut at many offsets over the file's second half, after every chunk was
 * verified: every decode afterwards gives the values from before the cut
 * or VSV_ETRUNC, never others. */
static void test_truncated_in_page_tail(void)
{
    synth sy = {24, 20, 8, 6, 0, 0};
    const char *orig = vsv_test_tmp("tail0.vsv"), *path = vsv_test_tmp("tail.vsv");
    vsv_pack_opts o;
    vsv_pack_opts_init(&o);
    o.brick = 8;
    char err[512] = "";
    if (!CHECK(synth_write(&sy, orig, &o, err, sizeof err) == 0, "write a file to cut in a page", "%s", err))
        return;
    size_t size = 0;
    unsigned char *bytes = vsv_test_slurp(orig, &size);
    const size_t nv = (size_t)sy.nx * sy.ny * sy.nz;
    float *vol = malloc(nv * sizeof *vol), *all = malloc(nv * 3 * sy.nsteps * sizeof *all);
    int cuts = 0, seen = 0, wrong = 0;
    for (size_t at = size / 2 + 1; bytes && vol && all && at < size; at += 61) {
        vsv_file *f = NULL;
        vsv_decoder *d = NULL;
        int rc = vsv_test_write(path, bytes, size) ? VSV_EIO : vsv_file_open(path, &f);
        if (!rc)
            rc = vsv_decoder_create(f, &d);
        for (int t = 0; t < sy.nsteps && !rc; t++)
            for (int s = 0; s < 3 && !rc; s++)
                rc = vsv_decoder_volume(d, t, s, all + nv * (size_t)(3 * t + s));
        if (!rc && truncate(path, (off_t)at) == 0) {
            cuts++;
            for (int t = sy.nsteps - 1; t >= 0; t--)
                for (int s = 0; s < 3; s++) {
                    rc = vsv_decoder_volume(d, t, s, vol);
                    if (rc == VSV_ETRUNC && strstr(vsv_decoder_error(d), "tail.vsv: truncated while reading"))
                        seen++;
                    else if (rc || memcmp(vol, all + nv * (size_t)(3 * t + s), nv * sizeof *vol))
                        wrong++;
                }
        }
        vsv_decoder_free(d);
        vsv_file_free(f);
    }
    CHECK(cuts > 100 && seen > 0 && !wrong,
          "cut inside a page after verifying: the values from before the cut or VSV_ETRUNC, never zeros",
          "%d cuts, %d truncated, %d wrong", cuts, seen, wrong);
    free(bytes);
    free(vol);
    free(all);
}

int main(void)
{
    test_atomic();
    test_damage();
    test_golden();
    test_truncated_while_reading();
    test_truncated_after_verify();
    test_truncated_in_page_tail();
    return vsv_test_done();
}
