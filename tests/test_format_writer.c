/* test_format_writer.c — the writer's other ways to the same bytes:
 * writing in parts (vsv-convert-mpi's ranks) and the planned writer
 * (vsv_writer_expect, no spool), each byte for byte the plain writer's. */
#include "vsv_format_internal.h"
#include "vsv_refread.h"
#include "vsv_synth.h"
#include "vsv_testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

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
    CHECK(want && nref == file.len && !memcmp(want, file.p, nref),
          "parts: assembled file is the writer's, byte for byte", "%zu vs %zu bytes", file.len, nref);
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

/* vsv_writer_expect: told the statistics in advance, the writer encodes as
 * the steps come (no spool) and writes the same bytes; a promise the steps
 * break fails at finish and leaves nothing. */
static void test_planned(void)
{
    const synth sy = {70, 50, 20, 30, 10, 20};
    const char *a = vsv_test_tmp("spooled.vsv"), *b = vsv_test_tmp("planned.vsv"), *c = vsv_test_tmp("lied.vsv");
    for (int threads = 1; threads <= 3; threads += 2) {
        vsv_pack_opts o;
        vsv_pack_opts_init(&o);
        o.brick = 16;
        o.keyframe = 4;
        o.threads = threads;
        char err[512] = "";
        int rc = synth_write(&sy, a, &o, err, sizeof err);
        rc |= synth_write_planned(&sy, b, &o, 0, err, sizeof err);
        size_t na = 0, nb = 0;
        unsigned char *da = vsv_test_slurp(a, &na), *db = vsv_test_slurp(b, &nb);
        CHECK(rc == 0 && da && db && na == nb && !memcmp(da, db, na),
              threads == 1 ? "planned writer, 1 thread: byte for byte the spooled file"
                           : "planned writer, 3 threads: byte for byte the spooled file",
              "%s (%zu vs %zu bytes)", err, na, nb);
        free(da);
        free(db);
    }
    char err[512] = "";
    int rc = synth_write_planned(&sy, c, NULL, 1, err, sizeof err);
    CHECK(rc == VSV_EINVAL && strstr(err, "do not have the statistics promised") && access(c, F_OK) != 0,
          "a broken promise fails at finish and leaves no file", "rc %d: %s", rc, err);
}

int main(void)
{
    test_parts();
    test_planned();
    return vsv_test_done();
}
