/* test_pager_play.c — incremental decoding in the pager: the format's
 * brick advance, payloads decoded playing forward and backward (counted
 * exactly), bricks equal to from-keyframe decodes on the real MM5 run, the
 * budget's bound, and an open that reads no more than the header, metadata
 * and table of contents (pages of the mapping touched, from
 * /proc/self/pagemap). */
#include "vsv_convert.h"
#include "vsv_pager.h"
#include "vsv_synth.h"
#include "vsv_testlib.h"

#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

static synth SY = {40, 30, 12, 60, 20, 35};
#ifdef __SANITIZE_THREAD__
/* under ThreadSanitizer (code ~10x slower) the real run's first species
 * takes the pager's threads through the same paths */
enum { MM5_SPECIES = 1 };
#else
enum { MM5_SPECIES = 1 << 20 };
#endif
enum { K = 6 };

/* The series at 16 bits, or (bits 8) every species at 8 bits. */
static int write_series_bits(const char *path, int nsteps, int bits)
{
    synth sy = SY;
    sy.nsteps = nsteps;
    vsv_pack_opts o;
    vsv_pack_opts_init(&o);
    o.brick = 8;
    o.keyframe = K;
    vsv_pack_var pv[3];
    for (int s = 0; s < 3; s++) {
        vsv_pack_var_init(&pv[s]);
        pv[s].bits = bits;
    }
    o.vars = pv;
    char err[512] = "";
    const int rc = synth_write(&sy, path, &o, err, sizeof err);
    if (rc)
        CHECK(0, "write a synthetic series", "%s", err);
    return rc;
}

static int write_series(const char *path, int nsteps) { return write_series_bits(path, nsteps, 16); }

/* Advancing a brick's codes step by step from zeros gives, at every step,
 * the codes decoded from the brick's keyframe. */
static void test_advance(vsv_file *f, const char *label)
{
    vsv_file_info in;
    vsv_file_info_get(f, &in);
    vsv_decoder *d = NULL;
    vsv_decoder_create(f, &d);
    const size_t n = (size_t)in.brick * in.brick * in.brick;
    uint16_t *state = malloc(n * sizeof *state), *ref = malloc(n * sizeof *ref);
    int bad = 0, checked = 0, deltas = 0;
    for (int s = 0; s < in.nspecies; s++)
        for (int b = 0; b < in.nbricks; b++) {
            memset(state, 0, n * sizeof *state);
            for (int t = 0; t < in.nsteps && !bad; t++) {
                const int kind = vsv_file_brick_kind(f, t, s, b);
                deltas += vsv_brick_delta(kind);
                if (vsv_decoder_brick_advance(d, t, s, b, state) || vsv_decoder_brick_codes(d, t, s, b, ref) ||
                    memcmp(state, ref, n * sizeof *ref))
                    bad = 1 + t;
                checked++;
            }
        }
    char name[200];
    snprintf(name, sizeof name, "%s: vsv_decoder_brick_advance from step 0 on equals the keyframe decode at every step",
             label);
    CHECK(!bad && deltas > 0, name, "(%d bricks x steps, %d deltas, first bad step %d)", checked, deltas, bad - 1);
    CHECK(vsv_decoder_brick_advance(d, in.nsteps, 0, 0, state) == VSV_ERANGE, "advance past the last step: VSV_ERANGE",
          " ");
    /* undoing: from every step's codes, retreat gives the previous step's */
    int kinds[8] = {0};
    bad = checked = 0;
    for (int s = 0; s < in.nspecies; s++)
        for (int b = 0; b < in.nbricks; b++)
            for (int t = in.nsteps - 1; t > 0 && !bad; t--) {
                const int kind = vsv_file_brick_kind(f, t, s, b);
                vsv_decoder_brick_codes(d, t, s, b, state);
                vsv_decoder_brick_codes(d, t - 1, s, b, ref);
                const int rc = vsv_decoder_brick_retreat(d, t, s, b, state);
                if (vsv_brick_absolute(kind)) {
                    bad = rc != VSV_EINVAL ? 1 + t : 0;
                    continue;
                }
                kinds[kind]++;
                if (rc || memcmp(state, ref, n * sizeof *ref))
                    bad = 1 + t;
                checked++;
            }
    snprintf(name, sizeof name,
             "%s: vsv_decoder_brick_retreat undoes a step exactly (DELTA, DELTA3/3R, UNCHANGED); an absolute state: "
             "VSV_EINVAL",
             label);
    CHECK(!bad && kinds[VSV_BRICK_DELTA] > 0 && kinds[VSV_BRICK_DELTA3] + kinds[VSV_BRICK_DELTA3R] > 0 &&
              kinds[VSV_BRICK_UNCHANGED] > 0,
          name, "(%d undone: %d DELTA, %d DELTA3, %d DELTA3R, %d UNCHANGED; first bad step %d)", checked,
          kinds[VSV_BRICK_DELTA], kinds[VSV_BRICK_DELTA3], kinds[VSV_BRICK_DELTA3R], kinds[VSV_BRICK_UNCHANGED],
          bad - 1);
    free(state);
    free(ref);
    vsv_decoder_free(d);
}

/* Payloads (ABS or DELTA) of species s over steps [a, b]. */
static uint64_t payloads(vsv_file *f, int s, int a, int b, int nbricks)
{
    uint64_t n = 0;
    for (int t = a; t <= b; t++)
        for (int k = 0; k < nbricks; k++) {
            const int kind = vsv_file_brick_kind(f, t, s, k);
            n += kind >= VSV_BRICK_ABS; /* a payload: ABS, DELTA and the 3-D kinds */
        }
    return n;
}

/* Plays species s of f through a pager (no workers: every decode is
 * counted on this thread), forward then backward over all steps; returns
 * the payloads decoded each way and checks each volume brick by brick
 * against the decoder's from-keyframe decode. */
static int play(vsv_file *f, int s, size_t budget, int from_keyframe, int threads, uint64_t *fwd, uint64_t *back,
                size_t *peak_over, char *why, size_t cap)
{
    vsv_file_info in;
    vsv_file_info_get(f, &in);
    vsv_pager_opts o;
    vsv_pager_opts_init(&o);
    o.budget = budget;
    o.threads = threads;
    o.from_keyframe = from_keyframe;
    vsv_decoder *d = NULL;
    vsv_decoder_create(f, &d);
    const size_t n = (size_t)in.brick * in.brick * in.brick;
    float *ref = malloc(n * sizeof *ref);
    uint16_t *codes = malloc(n * sizeof *codes);
    unsigned char *want = calloc((size_t)in.nspecies, 1);
    want[s] = 1;
    int bad = 0;
    *peak_over = 0;
    vsv_pager_stats st;
    for (int pass = 0; pass < 2 && !bad; pass++) { /* a new pager each way: nothing cached */
        vsv_pager *p = NULL;
        if (vsv_pager_open(f, &o, &p)) {
            snprintf(why, cap, "pager does not open");
            bad = 1;
            break;
        }
        vsv_volume *v = vsv_pager_volume_new(p);
        vsv_pager_stats_get(p, &st);
        const uint64_t p0 = st.payloads_decoded;
        for (int i = 0; i < in.nsteps && !bad; i++) {
            const int t = pass ? in.nsteps - 1 - i : i;
            vsv_pager_playhead(p, t, pass ? -1 : 1, NULL, 0, want);
            if (vsv_pager_get(p, t, s, 1, v)) {
                snprintf(why, cap, "get %d: %s", t, vsv_pager_error(p));
                bad = 1;
                break;
            }
            for (int b = 0; b < in.nbricks && !bad; b++) {
                /* the codes' values (the pager's, for the renderers: the
                 * ground hides what is below it; the value readers' NaN there
                 * is vsv_decoder_brick's) */
                vsv_decoder_brick_codes(d, t, s, b, codes);
                vsv_file_dequantise(f, s, codes, n, ref);
                int diff = 0;
                if (v->bricks[b]) /* a NULL brick is all the empty value */
                    diff = memcmp(v->bricks[b], ref, n * sizeof *ref) != 0;
                else
                    for (size_t c = 0; c < n; c++)
                        diff |= memcmp(&ref[c], &v->empty_value, sizeof(float)) != 0;
                if (diff) {
                    snprintf(why, cap, "step %d species %d brick %d differs from the keyframe decode", t, s, b);
                    bad = 1;
                }
            }
            vsv_pager_stats_get(p, &st);
            if (st.bytes > st.budget + st.pinned_bytes && st.budget >= st.fixed_bytes) {
                snprintf(why, cap, "step %d: %zu bytes held, budget %zu + pinned %zu", t, st.bytes, st.budget,
                         st.pinned_bytes);
                bad = 1;
            }
        }
        vsv_pager_stats_get(p, &st);
        *(pass ? back : fwd) = st.payloads_decoded - p0;
        if (st.peak_bytes > budget + *peak_over)
            *peak_over = st.peak_bytes - budget;
        vsv_volume_free(v);
        vsv_pager_free(p);
    }
    free(want);
    free(ref);
    free(codes);
    vsv_decoder_free(d);
    return bad;
}

static void test_counts(const char *path)
{
    vsv_file *f = NULL;
    if (!CHECK(vsv_file_open(path, &f) == 0, "open the 60-step series", "%s", vsv_file_error(f))) {
        vsv_file_free(f);
        return;
    }
    test_advance(f, "16 bits");
    vsv_file_info in;
    vsv_file_info_get(f, &in);
    const int nb = in.nbricks, ns = in.nsteps;
    /* species 1 (smooth, dense) changes every brick at every step */
    int dense = 1;
    for (int t = 0; t < ns; t++)
        for (int b = 0; b < nb; b++) {
            const int kind = vsv_file_brick_kind(f, t, 1, b);
            dense &= t % K ? vsv_brick_delta(kind) : vsv_brick_absolute(kind) && kind != VSV_BRICK_EMPTY;
        }
    CHECK(dense, "species 1 of the series: every brick a delta at every step off the keyframes", " ");
    const uint64_t all = payloads(f, 1, 0, ns - 1, nb);
    uint64_t key = 0;
    for (int t = 0; t < ns; t++)
        key += (uint64_t)nb * (t % K + 1);
    char why[300] = "";
    uint64_t fwd = 0, back = 0, kf = 0, kb = 0;
    size_t over = 0;
    const size_t brick = 8 * 8 * 8 * sizeof(float);
    int bad = play(f, 1, 64 << 20, 0, -1, &fwd, &back, &over, why, sizeof why);
    CHECK(!bad, "incremental: every brick forward and backward equals the keyframe decode", "%s", why);
    CHECK(fwd == all, "forward play of 60 steps decodes exactly one payload per changed brick and step",
          "(%llu payloads, %llu changed bricks)", (unsigned long long)fwd, (unsigned long long)all);
    CHECK(back == all, "backward play decodes each keyframe group once (every payload once)",
          "(%llu payloads, %llu in the file)", (unsigned long long)back, (unsigned long long)all);
    bad = play(f, 1, 64 << 20, 1, -1, &kf, &kb, &over, why, sizeof why);
    CHECK(!bad && kf == key && kb == key, "from_keyframe: every brick walks back to its keyframe, both ways",
          "(forward %llu, backward %llu, expected %llu) %s", (unsigned long long)kf, (unsigned long long)kb,
          (unsigned long long)key, why);
    /* a budget of 3 steps (the window is then a step: a group is decoded
     * in parts, never beyond the budget) */
    const size_t small = 3 * (size_t)nb * brick + 64 * 1024;
    bad = play(f, 1, small, 0, -1, &fwd, &back, &over, why, sizeof why);
    /* backward, a group's top step is reached by one walk from its
     * keyframe (K payloads a brick) and every step below it by undoing one
     * delta (a payload a brick): at most (2K - 1) a brick for each group,
     * where decoding each window of a step or two from the keyframe costs
     * more */
    const uint64_t undo = (uint64_t)(2 * K - 1) * nb * (ns / K);
    CHECK(
        !bad && fwd == all && back <= undo,
        "under a 3-step budget: forward one payload a changed brick; backward one walk a group, then a payload a step",
        "(forward %llu of %llu, backward %llu, at most %llu) %s", (unsigned long long)fwd, (unsigned long long)all,
        (unsigned long long)back, (unsigned long long)undo, why);
    /* the walk keeps the states it passes as checkpoints (codes, half a
     * step's floats each) while they fit: with room for about three, the
     * steps below a group's top cost a copy, not a payload */
    CHECK(!bad && 2 * back <= 3 * fwd,
          "under a 3-step budget backward decodes at most 1.5x forward's payloads (checkpoints)",
          "(forward %llu, backward %llu)", (unsigned long long)fwd, (unsigned long long)back);
    /* a budget of a step and its decoder state (no window): each step
     * backward is a get of its own */
    const size_t tiny = (size_t)nb * brick * 3 / 2 + 64 * 1024;
    size_t over2 = 0;
    bad = play(f, 1, tiny, 0, -1, &fwd, &back, &over2, why, sizeof why);
    CHECK(!bad && fwd == all && back <= undo, "under a one-step budget: the same bound backward, every brick exact",
          "(forward %llu of %llu, backward %llu, at most %llu) %s", (unsigned long long)fwd, (unsigned long long)all,
          (unsigned long long)back, (unsigned long long)undo, why);
    /* the peak: the budget plus what a caller holds (one species of a step)
     * and the brick being decoded with its state */
    CHECK(over <= (size_t)(nb + 1) * brick + brick / 2, "the pager's peak stays within the budget plus the pinned step",
          "(%zu bytes over)", over);
    bad = play(f, 1, small, 0, 2, &fwd, &back, &over, why, sizeof why);
    CHECK(!bad, "with 2 workers under the same budget: every brick equals the keyframe decode", "%s", why);
    vsv_file_free(f);
}

/* The series at 8 bits (deltas wrap modulo 2^8): undoing a step gives
 * the previous step's codes, and the pager playing backward (undoing
 * deltas from the track's state) gives every brick as the keyframe decode,
 * as forward. */
static void test_bits8(void)
{
    const char *path = vsv_test_tmp("play-series-8.vsv");
    vsv_file *f = NULL;
    if (write_series_bits(path, 2 * K + 2, 8) ||
        !CHECK(vsv_file_open(path, &f) == 0, "open the 8-bit series", "%s", vsv_file_error(f))) {
        vsv_file_free(f);
        return;
    }
    int bits8 = 1;
    for (int s = 0; s < 3; s++)
        bits8 &= vsv_file_quant(f, s)->bits == 8;
    CHECK(bits8, "the series is written at 8 bits", " ");
    test_advance(f, "8 bits");
    vsv_file_info in;
    vsv_file_info_get(f, &in);
    char why[300] = "";
    uint64_t fwd = 0, back = 0;
    size_t over = 0;
    int bad = 0;
    for (int s = 0; s < in.nspecies && !bad; s++)
        bad = play(f, s, 64 << 20, 0, -1, &fwd, &back, &over, why, sizeof why);
    CHECK(!bad, "8 bits: every brick forward and backward equals the keyframe decode", "%s", why);
    /* under a one-step budget backward undoes deltas from the track */
    const size_t tiny = (size_t)in.nbricks * 8 * 8 * 8 * sizeof(float) * 3 / 2 + 64 * 1024;
    for (int s = 0; s < in.nspecies && !bad; s++)
        bad = play(f, s, tiny, 0, -1, &fwd, &back, &over, why, sizeof why);
    CHECK(!bad, "8 bits under a one-step budget: every brick backward equals the keyframe decode", "%s", why);
    vsv_file_free(f);
}

/* A grid of one brick, played through a pager (no workers) whose budget
 * holds its fixed tables, one brick and its decoder state: no brick is
 * pinned but the one being decoded (the volume's previous brick is
 * released first), so making room for it must count it: the bytes held
 * never exceed the budget, not even for a moment (the peak), forward or
 * backward. */
static void test_budget_exact(void)
{
    synth sy = {8, 8, 8, 2 * K + 3, 0, 0};
    vsv_pack_opts po;
    vsv_pack_opts_init(&po);
    po.brick = 8;
    po.keyframe = K;
    char err[512] = "";
    const char *path = vsv_test_tmp("one-brick.vsv");
    vsv_file *f = NULL;
    if (!CHECK(synth_write(&sy, path, &po, err, sizeof err) == 0 && vsv_file_open(path, &f) == 0,
               "write and open a one-brick series", "%s %s", err, f ? vsv_file_error(f) : "")) {
        vsv_file_free(f);
        return;
    }
    vsv_file_info in;
    vsv_file_info_get(f, &in);
    const int s = 1; /* smooth, dense: a brick at every step, a delta off the keyframes */
    const size_t brick = 8 * 8 * 8 * sizeof(float), codes = 8 * 8 * 8 * sizeof(uint16_t);
    vsv_pager_opts o;
    vsv_pager_opts_init(&o);
    o.threads = -1;
    vsv_pager *p = NULL;
    vsv_pager_stats st;
    if (vsv_pager_open(f, &o, &p)) {
        CHECK(0, "a pager opens over the one-brick series", " ");
        vsv_file_free(f);
        return;
    }
    vsv_pager_stats_get(p, &st);
    vsv_pager_free(p);
    o.budget = st.fixed_bytes + brick + codes;
    vsv_decoder *d = NULL;
    vsv_decoder_create(f, &d);
    float ref[8 * 8 * 8];
    uint16_t c[8 * 8 * 8];
    unsigned char want[3] = {0, 1, 0};
    int bad = 0, gets = 0;
    size_t worst = 0;
    for (int pass = 0; pass < 2 && !bad; pass++) {
        if (vsv_pager_open(f, &o, &p)) {
            bad = 1;
            break;
        }
        vsv_volume *v = vsv_pager_volume_new(p);
        for (int i = 0; i < in.nsteps && !bad; i++) {
            const int t = pass ? in.nsteps - 1 - i : i;
            vsv_pager_playhead(p, t, pass ? -1 : 1, NULL, 0, want);
            if (vsv_pager_get(p, t, s, 1, v) || !v->bricks[0]) {
                bad = 1;
                break;
            }
            vsv_decoder_brick_codes(d, t, s, 0, c);
            vsv_file_dequantise(f, s, c, 8 * 8 * 8, ref);
            bad |= memcmp(v->bricks[0], ref, sizeof ref) != 0;
            vsv_pager_stats_get(p, &st);
            worst = st.peak_bytes > worst ? st.peak_bytes : worst;
            gets++;
        }
        vsv_volume_free(v);
        vsv_pager_free(p);
    }
    CHECK(!bad && gets == 2 * in.nsteps && in.nbricks == 1,
          "one-brick series under a budget of one brick: every get exact", "(%d gets of %d, %d bricks)", gets,
          2 * in.nsteps, in.nbricks);
    CHECK(worst <= o.budget,
          "one-brick series: the peak never exceeds the budget (making room counts the incoming brick)",
          "(peak %zu bytes, budget %zu: %zu over)", worst, o.budget, worst > o.budget ? worst - o.budget : 0);
    vsv_decoder_free(d);
    vsv_file_free(f);
}

/* The real MM5 run at 10-minute steps (linear in time, 19 steps): the
 * pager's bricks forward and backward equal the keyframe decode for every
 * species, with fewer payloads than from keyframes. */
static int emit(void *ctx, int64_t time, const float *const *fields) { return vsv_writer_add_step(ctx, time, fields); }

static void test_mm5(void)
{
    const char *in = vsv_test_shared("mm5/run1/MMOUT_DOMAIN1"), *out = vsv_test_tmp("mm5-10m.vsv");
    vsv_run *run = NULL;
    if (vsv_test_absent(in, "playing the real MM5 run at 10-minute steps"))
        return;
    int rc = vsv_run_open(&in, 1, NULL, "Q,CLW,RNW,ICE,SNOW", NULL, &run);
    if (!CHECK(rc == 0, "the real MM5 run opens", "%s", vsv_run_error(run))) {
        vsv_run_free(run);
        return;
    }
    const vsv_meta *meta = vsv_run_meta(run);
    const size_t cells = (size_t)meta->nx * meta->ny * meta->nz;
    float **fields = calloc((size_t)meta->nvars, sizeof *fields);
    for (int v = 0; v < meta->nvars; v++)
        fields[v] = malloc(cells * sizeof(float));
    vsv_writer *w = NULL;
    vsv_interp *ip = NULL;
    rc = vsv_writer_create(out, meta, NULL, &w);
    if (!rc)
        rc = vsv_interp_open(600, meta, NULL, emit, w, &ip);
    for (int i = 0; !rc && i < vsv_run_nframes(run); i++)
        if (!(rc = vsv_run_read(run, i, fields)))
            rc = vsv_interp_push(ip, vsv_run_time(run, i), (const float *const *)fields);
    if (!rc)
        rc = vsv_writer_finish(w, NULL, NULL);
    CHECK(rc == 0, "the MM5 run written at 10-minute steps", "%s", w ? vsv_writer_error(w) : "");
    vsv_interp_free(ip);
    vsv_writer_free(w);
    for (int v = 0; v < meta->nvars; v++)
        free(fields[v]);
    free(fields);
    vsv_run_free(run);
    vsv_file *f = NULL;
    if (rc || vsv_file_open(out, &f)) {
        vsv_file_free(f);
        return;
    }
    vsv_file_info info;
    vsv_file_info_get(f, &info);
    int bad = 0;
    uint64_t fwd = 0, back = 0, kf = 0, kb = 0, sf = 0, sb = 0, skf = 0, skb = 0;
    size_t over = 0;
    char why[300] = "";
    for (int s = 0; s < info.nspecies && s < MM5_SPECIES && !bad; s++) {
        bad = play(f, s, 64 << 20, 0, 1, &fwd, &back, &over, why, sizeof why);
        bad = bad || play(f, s, 64 << 20, 1, -1, &kf, &kb, &over, why, sizeof why);
        sf += fwd, sb += back, skf += kf, skb += kb;
    }
    CHECK(!bad && info.nsteps == 19,
          "real MM5 (19 steps, 5 species): every brick forward and backward equals the keyframe decode", "%s", why);
    /* with one worker the counts include what it decoded ahead; with none
     * (below) they are exact */
    bad = 0;
    uint64_t ef = 0, eb = 0;
    for (int s = 0; s < info.nspecies && s < MM5_SPECIES && !bad; s++) {
        bad = play(f, s, 64 << 20, 0, -1, &fwd, &back, &over, why, sizeof why);
        ef += fwd, eb += back;
    }
    CHECK(!bad && ef < skf && eb < skb, "real MM5: fewer payloads decoded than from keyframes, both ways",
          "(forward %llu against %llu, backward %llu against %llu) %s", (unsigned long long)ef, (unsigned long long)skf,
          (unsigned long long)eb, (unsigned long long)skb, why);
    (void)sf, (void)sb;
    vsv_file_free(f);
}

/* Pages of [a, a + n) mapped in this process (present in its page table). */
static long present_pages(const void *a, size_t n)
{
    const long ps = sysconf(_SC_PAGESIZE);
    const int fd = open("/proc/self/pagemap", O_RDONLY);
    if (fd < 0)
        return -1;
    long count = 0;
    const uintptr_t first = (uintptr_t)a / (uintptr_t)ps, last = ((uintptr_t)a + n - 1) / (uintptr_t)ps;
    for (uintptr_t pg = first; pg <= last; pg++) {
        uint64_t e = 0;
        if (pread(fd, &e, sizeof e, (off_t)(pg * sizeof e)) != (ssize_t)sizeof e) {
            count = -1;
            break;
        }
        count += (long)(e >> 63);
    }
    close(fd);
    return count;
}

/* Opens path through a mapping of ours (vsv_file_open_mem), gets its info
 * and starts a pager: the pages of the mapping touched, all and (*mid)
 * those more than 128 kB from either end (the chunks: the header and
 * metadata lie before, the table of contents after; the kernel maps up to
 * 64 kB around a page read). */
static long pages_touched(const char *path, size_t *size, long *mid)
{
    const int fd = open(path, O_RDONLY);
    if (fd < 0)
        return -1;
    *size = (size_t)lseek(fd, 0, SEEK_END);
    void *m = mmap(NULL, *size, PROT_READ, MAP_SHARED, fd, 0);
    close(fd);
    if (m == MAP_FAILED)
        return -1;
    madvise(m, *size, MADV_RANDOM); /* no read-around: a page is touched or not */
    vsv_file *f = NULL;
    long n = -1;
    if (vsv_file_open_mem(m, *size, path, &f) == 0) {
        vsv_file_info info;
        vsv_file_info_get(f, &info);
        vsv_pager *p = NULL;
        vsv_pager_opts o;
        vsv_pager_opts_init(&o);
        o.threads = -1;
        if (vsv_pager_open(f, &o, &p) == 0) {
            n = present_pages(m, *size);
            *mid = *size > (512 << 10) ? present_pages((char *)m + (128 << 10), *size - (256 << 10)) : -1;
        }
        vsv_pager_free(p);
    }
    vsv_file_free(f);
    munmap(m, *size);
    return n;
}

static void test_open(void)
{
    const char *a = vsv_test_tmp("open-6.vsv"), *b = vsv_test_tmp("open-60.vsv");
    if (write_series(a, 6) || write_series(b, 60))
        return;
    size_t na = 0, nb = 0;
    long ma = 0, mb = 0;
    const long pa = pages_touched(a, &na, &ma), pb = pages_touched(b, &nb, &mb);
    CHECK(pa > 0 && nb > 8 * na && mb == 0,
          "opening (file, info, pager) touches no chunk: header, metadata, table of contents only",
          "(6 steps: %ld pages of %zu bytes; 60 steps: %ld pages of %zu bytes, %ld of them among the chunks)", pa, na,
          pb, nb, mb);
}

int main(void)
{
    const char *path = vsv_test_tmp("play-series.vsv");
    if (write_series(path, 60) == 0)
        test_counts(path);
    test_bits8();
    test_budget_exact();
    test_open();
    test_mm5();
    return vsv_test_done();
}
