/* test_stream.c — the brick pager and the playback clock. */
#include "vsv_clock.h"
#include "vsv_pager.h"
#include "vsv_synth.h"
#include "vsv_testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static synth SY = {40, 30, 12, 60, 20, 35};
static float **REF; /* [step * 3 + s] whole volumes decoded directly */

static int write_series(const char *path)
{
    vsv_pack_opts o;
    vsv_pack_opts_init(&o);
    o.brick = 8;
    o.keyframe = 6;
    char err[512] = "";
    const int rc = synth_write(&SY, path, &o, err, sizeof err);
    CHECK(rc == 0, "write a 60-step, 3-species series (brick 8, keyframe 6)", "%s", err);
    return rc;
}

/* v equals the direct decode of (v->step, v->species) at every cell. */
static int same_as_direct(const vsv_volume *v, int step, int s)
{
    if (v->step != step || v->species != s)
        return 0;
    const float *ref = REF[step * 3 + s];
    for (int k = 0; k < v->nz; k++)
        for (int j = 0; j < v->ny; j++)
            for (int i = 0; i < v->nx; i++) {
                const float a = vsv_volume_at(v, i, j, k), b = ref[((size_t)k * v->ny + j) * v->nx + i];
                if (memcmp(&a, &b, sizeof a))
                    return 0;
            }
    return 1;
}

/* Tells p the playhead at step, playing dir (0 paused) `stride` steps a
 * frame (wrapping at the ends when loop): the 17 steps the next frames show. */
static void playhead(vsv_pager *p, int step, int dir, int stride, int loop, const unsigned char *want)
{
    enum { N = 60 };
    int next[VSV_PAGER_AHEAD + 1], n = 0;
    for (int d = 1; dir && n <= VSV_PAGER_AHEAD; d++) {
        int t = step + d * stride * dir;
        if (!loop && (t < 0 || t >= N))
            break;
        next[n++] = ((t % N) + N) % N;
    }
    vsv_pager_playhead(p, step, dir, dir ? next : NULL, n, want);
}

/* A random walk of seeks, direction and speed changes with gets checked
 * against direct decodes; the budget bound checked after every operation. */
static void random_walk(vsv_file *f, size_t budget, int threads, const char *label)
{
    vsv_pager_opts o;
    vsv_pager_opts_init(&o);
    o.budget = budget;
    o.threads = threads;
    vsv_pager *p = NULL;
    char name[160];
    if (!CHECK(vsv_pager_open(f, &o, &p) == 0, "pager opens", "(%s)", label))
        return;
    vsv_volume *v[2] = {vsv_pager_volume_new(p), vsv_pager_volume_new(p)};
    uint64_t rng = 12345 + budget + (uint64_t)threads;
    int bad = 0, over = 0, gets = 0, tries = 0, tried_ok = 0;
    unsigned char want[3] = {1, 1, 1};
    for (int op = 0; op < 300 && !bad; op++) {
        const uint64_t r = vsv_test_rand(&rng);
        const int step = (int)(r % 60), s = (int)((r >> 8) % 3), h = (int)((r >> 16) & 1);
        switch ((r >> 20) % 5) {
        case 0: { /* playhead: any direction, stride, loop, species */
            want[(r >> 24) % 3] = (r >> 27) & 1;
            playhead(p, step, (int)((r >> 28) % 3) - 1, 1 + (int)((r >> 30) % 8), (int)((r >> 33) & 1), want);
            break;
        }
        case 1: /* a non-blocking get: EAGAIN or the right volume */
            tries++;
            {
                const int rc = vsv_pager_get(p, step, s, 0, v[h]);
                if (rc == 0)
                    tried_ok++, bad |= !same_as_direct(v[h], step, s);
                else
                    bad |= rc != VSV_EAGAIN || v[h]->step != -1;
            }
            break;
        case 2: /* let the workers run a little */ usleep(200); break;
        default: /* a blocking get: always the right volume */
            gets++;
            if (vsv_pager_get(p, step, s, 1, v[h]) || !same_as_direct(v[h], step, s))
                bad = 1;
            /* the other held volume is still intact */
            if (v[!h]->step >= 0 && !same_as_direct(v[!h], v[!h]->step, v[!h]->species))
                bad = 1;
        }
        vsv_pager_stats st;
        vsv_pager_stats_get(p, &st);
        /* (a budget below the pager's fixed tables: those and the pinned) */
        if (st.bytes > (st.budget > st.fixed_bytes ? st.budget : st.fixed_bytes) + st.pinned_bytes)
            over = 1;
    }
    snprintf(name, sizeof name, "%s: every volume equals the direct decode under random seeks", label);
    CHECK(!bad, name, "(%d blocking gets, %d tries of which %d ready) %s", gets, tries, tried_ok, vsv_pager_error(p));
    snprintf(name, sizeof name, "%s: the budget is never exceeded by more than the pinned bricks", label);
    CHECK(!over, name, " ");
    vsv_volume_free(v[0]);
    vsv_volume_free(v[1]);
    vsv_pager_stats st;
    vsv_pager_stats_get(p, &st);
    snprintf(name, sizeof name, "%s: statistics add up", label);
    /* nothing held: only bricks a worker is decoding right now stay pinned */
    CHECK(st.hits + st.misses > 0 && st.bricks_decoded > 0 &&
              /* a worker's job: up to ahead + 2 bricks (a keyframe group
               * backward) and its decoder state, half a brick */
              st.pinned_bytes <= (size_t)(threads > 0 ? threads : 0) * (18 * 2 + 1) * 8 * 8 * 8 * sizeof(uint16_t) &&
              st.bytes_decoded == st.bricks_decoded * 8 * 8 * 8 * sizeof(float),
          name, "(hits %llu misses %llu decoded %llu stalls %llu evictions %llu)", (unsigned long long)st.hits,
          (unsigned long long)st.misses, (unsigned long long)st.bricks_decoded, (unsigned long long)st.stalls,
          (unsigned long long)st.evictions);
    vsv_pager_free(p);
}

static void test_volume_owner(vsv_file *f);
static void test_pager_bounds(vsv_file *f);

static void test_pager(const char *path)
{
    vsv_file *f = NULL;
    if (!CHECK(vsv_file_open(path, &f) == 0, "open the series", "%s", f ? vsv_file_error(f) : ""))
        return;
    vsv_decoder *d = NULL;
    vsv_decoder_create(f, &d);
    REF = calloc(60 * 3, sizeof *REF);
    for (int t = 0; t < 60; t++)
        for (int s = 0; s < 3; s++) {
            REF[t * 3 + s] = malloc(sizeof(float) * 40 * 30 * 12);
            vsv_decoder_volume(d, t, s, REF[t * 3 + s]);
        }
    vsv_decoder_free(d);
    const size_t brick = 8 * 8 * 8 * sizeof(float);
    random_walk(f, 64 << 20, 2, "64 MB budget, 2 workers");
    random_walk(f, 20 * brick, 1, "budget of 20 bricks (under one step), 1 worker");
    random_walk(f, 1, 2, "budget of 1 byte, 2 workers");
    random_walk(f, 200 * brick, -1, "no workers");

    /* prefetch: decoded ahead in the direction of play, backwards too */
    vsv_pager_opts o;
    vsv_pager_opts_init(&o);
    o.budget = 64 << 20;
    o.threads = 1;
    vsv_pager *p = NULL;
    vsv_pager_open(f, &o, &p);
    CHECK(vsv_pager_wait_ready(p, 45, NULL, 0.05) == 0 && vsv_pager_wait_ready(p, -1, NULL, 1) == 0 &&
              vsv_pager_wait_ready(p, 60, NULL, 1) == 0,
          "a wait for a step nobody decodes ends not ready; steps outside the file are never ready", " ");
    playhead(p, 30, -1, 2, 0, NULL);
    CHECK(vsv_pager_wait_ready(p, 30, NULL, 10) == 1, "a wait for the playhead's step ends when the workers decoded it",
          " ");
    int ready = 0;
    for (int i = 0; i < 5000 && !ready; i++) {
        ready = vsv_pager_ready(p, 30, NULL) && vsv_pager_ready(p, 28, NULL) && vsv_pager_ready(p, 20, NULL);
        if (!ready)
            usleep(1000);
    }
    CHECK(ready, "playing backwards at stride 2, steps 30, 28 ... 20 are decoded ahead", " ");
    CHECK(!vsv_pager_ready(p, 31, NULL) && !vsv_pager_ready(p, 29, NULL), "steps off the stride are not decoded", " ");
    vsv_pager_stats st;
    vsv_pager_stats_get(p, &st);
    CHECK(st.prefetch_depth == 16, "prefetch depth is the 16-step default with room", "(%d)", st.prefetch_depth);
    vsv_volume *v = vsv_pager_volume_new(p), *w = vsv_pager_volume_new(p);
    vsv_pager_stats_get(p, &st);
    const uint64_t hits0 = st.hits;
    CHECK(vsv_pager_get(p, 24, 0, 0, v) == 0 && same_as_direct(v, 24, 0), "a prefetched step is there without waiting",
          " ");
    vsv_pager_stats_get(p, &st);
    CHECK(st.hits > hits0 && st.misses == 0, "and counts as hits", "(hits %llu misses %llu)",
          (unsigned long long)st.hits, (unsigned long long)st.misses);
    /* species 2 is frozen over steps 20..35: after the keyframe at 30 its
     * bricks are shared, not copied */
    vsv_pager_get(p, 31, 2, 1, v);
    vsv_pager_get(p, 35, 2, 1, w);
    int shared = 1, any = 0;
    for (int b = 0; b < v->nbricks; b++) {
        shared &= v->bricks[b] == w->bricks[b];
        any |= v->bricks[b] != NULL;
    }
    CHECK(shared && any, "an unchanged brick is one cache entry for every step that shares it", " ");
    vsv_volume_free(v);
    vsv_volume_free(w);
    vsv_pager_free(p);

    /* a budget smaller than one step: playback still gets every step */
    o.budget = 4 * brick;
    vsv_pager_open(f, &o, &p);
    v = vsv_pager_volume_new(p);
    int ok = 1;
    for (int t = 0; t < 60 && ok; t++) {
        vsv_pager_playhead(p, t, 1, NULL, 0, NULL);
        for (int s = 0; s < 3 && ok; s++)
            ok = vsv_pager_get(p, t, s, 1, v) == 0 && same_as_direct(v, t, s);
    }
    vsv_pager_stats_get(p, &st);
    CHECK(ok && st.prefetch_depth == 0 && st.evictions > 0,
          "a 4-brick budget plays every step correctly (prefetch off, evicting)", "(depth %d, evictions %llu)",
          st.prefetch_depth, (unsigned long long)st.evictions);
    /* brick keys (what a renderer re-derives only for bricks that changed):
     * the pager's volumes carry the loader's, and a step changes some */
    vsv_decoder *dec = NULL;
    vsv_volume *ref = NULL;
    ok = !vsv_decoder_create(f, &dec) && !vsv_volume_create(f, &ref);
    const int nb = ok ? ref->nbricks : 0;
    uint64_t *before = calloc((size_t)nb * 3 + 1, sizeof *before);
    long changed = 0, kept = 0;
    for (int t = 0; t < 60 && ok; t++) {
        vsv_pager_playhead(p, t, 1, NULL, 0, NULL);
        for (int s = 0; s < 3 && ok; s++) {
            ok = vsv_pager_get(p, t, s, 1, v) == 0 && vsv_volume_load(ref, dec, t, s) == 0 && v->bkey && ref->bkey &&
                 !memcmp(v->bkey, ref->bkey, (size_t)nb * sizeof *v->bkey);
            for (int b = 0; b < nb && ok && t > 0; b++) {
                changed += v->bkey[b] != before[s * nb + b];
                kept += v->bkey[b] == before[s * nb + b];
            }
            if (ok)
                memcpy(before + (size_t)s * nb, v->bkey, (size_t)nb * sizeof *before);
        }
    }
    CHECK(ok && changed > 0 && kept > 0, "the pager's volumes carry the loader's brick keys; a step changes some",
          "(%ld changed, %ld kept)", changed, kept);
    free(before);
    vsv_volume_free(ref);
    vsv_decoder_free(dec);
    vsv_volume_free(v);
    vsv_pager_free(p);
    test_volume_owner(f);
    test_pager_bounds(f);
    for (int i = 0; i < 180; i++)
        free(REF[i]);
    free(REF);
    vsv_file_free(f);
}

/* One owner rule: vsv_volume_free releases any volume the library made, the
 * way its maker needs (a pager volume unpins its bricks; before or after its
 * pager); each maker fills only its own volumes. */
static void test_volume_owner(vsv_file *f)
{
    vsv_pager_opts o;
    vsv_pager_opts_init(&o);
    o.budget = 64 << 20;
    o.threads = -1;
    vsv_pager *p = NULL, *q = NULL;
    vsv_decoder *d = NULL;
    vsv_volume *r = NULL;
    if (!CHECK(vsv_pager_open(f, &o, &p) == 0 && vsv_pager_open(f, &o, &q) == 0 && vsv_decoder_create(f, &d) == 0 &&
                   vsv_volume_create(f, &r) == 0,
               "two pagers, a decoder and a reader volume", " "))
        return;
    vsv_volume *v = vsv_pager_volume_new(p), *w = vsv_pager_volume_new(p);
    vsv_pager_stats st;
    CHECK(vsv_pager_get(p, 5, 0, 1, v) == 0 && same_as_direct(v, 5, 0), "a pager volume holds step 5", " ");
    vsv_pager_stats_get(p, &st);
    const size_t pinned = st.pinned_bytes;
    vsv_volume_free(v);
    vsv_pager_stats_get(p, &st);
    CHECK(pinned > 0 && st.pinned_bytes == 0, "vsv_volume_free on a pager volume unpins its bricks",
          "(pinned %zu, then %zu bytes)", pinned, st.pinned_bytes);
    CHECK(vsv_pager_get(p, 6, 1, 1, w) == 0 && same_as_direct(w, 6, 1), "and the pager works on", " ");
    CHECK(vsv_volume_load(w, d, 3, 0) == VSV_EINVAL &&
              strstr(vsv_decoder_error(d), "not a volume of vsv_volume_create"),
          "vsv_volume_load refuses a pager volume", "(%s)", vsv_decoder_error(d));
    CHECK(same_as_direct(w, 6, 1), "which still holds what it held", " ");
    CHECK(vsv_pager_get(p, 3, 0, 1, r) == VSV_EINVAL && strstr(vsv_pager_error(p), "not a volume of this pager"),
          "vsv_pager_get refuses a reader volume", "(%s)", vsv_pager_error(p));
    CHECK(vsv_pager_get(q, 3, 0, 1, w) == VSV_EINVAL, "and another pager's volume", " ");
    vsv_pager_put(q, w);
    CHECK(same_as_direct(w, 6, 1), "which another pager's put leaves alone", " ");
    CHECK(vsv_volume_load(r, d, 3, 0) == 0 && same_as_direct(r, 3, 0), "the reader volume loads step 3", " ");
    vsv_pager_free(p);
    int none = w->step == -1;
    for (int b = 0; b < w->nbricks; b++)
        none &= w->bricks[b] == NULL;
    CHECK(none, "a volume still out when its pager is freed holds no bricks", " ");
    vsv_volume_free(w); /* after its pager: only its own memory */
    vsv_volume_free(r);
    vsv_volume mine;
    memset(&mine, 0, sizeof mine);
    vsv_volume_free(&mine); /* caller-built: left alone */
    vsv_volume_free(NULL);
    vsv_pager_free(q);
    vsv_decoder_free(d);
}

/* What the pager holds around its gets, exactly (no workers): a put gives
 * the bytes of a step larger than the budget back to it; a get that cannot
 * be served at once leaves nothing pinned; the prefetch window is the
 * budget in steps less two (playing backward, less K - 2 checkpoints of
 * half a step first). */
static void test_pager_bounds(vsv_file *f)
{
    const size_t brick = 8 * 8 * 8 * sizeof(float);
    vsv_file_info in;
    vsv_file_info_get(f, &in);
    const size_t unit = (size_t)in.nbricks * brick; /* a step of species 1 (dense: every brick) */
    unsigned char one[3] = {0, 1, 0};
    vsv_pager_opts o;
    vsv_pager_opts_init(&o);
    o.threads = -1;
    vsv_pager *p = NULL;
    vsv_pager_stats st;
    if (!CHECK(vsv_pager_open(f, &o, &p) == 0, "a pager opens (its fixed bytes)", " "))
        return;
    vsv_pager_stats_get(p, &st);
    vsv_pager_free(p);
    o.budget = st.fixed_bytes + 4 * brick;
    vsv_pager_open(f, &o, &p);
    vsv_volume *v = vsv_pager_volume_new(p);
    vsv_pager_playhead(p, 5, 1, NULL, 0, one);
    const int got = vsv_pager_get(p, 5, 1, 1, v) == 0 && same_as_direct(v, 5, 1);
    vsv_pager_stats_get(p, &st);
    const size_t held = st.bytes;
    vsv_pager_put(p, v);
    vsv_pager_stats_get(p, &st);
    CHECK(got && held > st.budget && st.pinned_bytes == 0 && st.bytes <= st.budget,
          "a step larger than the budget, put back: the bytes held back within the budget",
          "(%zu bytes held with the step, %zu after the put, budget %zu, %zu pinned)", held, st.bytes, st.budget,
          st.pinned_bytes);
    /* some of step 5's bricks are still cached, not all: not ready */
    const int rc = vsv_pager_get(p, 5, 1, 0, v);
    vsv_pager_stats_get(p, &st);
    CHECK(rc == VSV_EAGAIN && v->step == -1 && st.pinned_bytes == 0 && st.hits > 0,
          "a get that cannot be served at once (some bricks cached): VSV_EAGAIN, nothing left pinned",
          "(rc %d, step %d, %zu bytes pinned, %llu hits)", rc, v->step, st.pinned_bytes, (unsigned long long)st.hits);
    vsv_volume_free(v);
    vsv_pager_free(p);
    /* a budget of 6 steps and a half: 4 ahead forward; backward the
     * checkpoints of K - 2 = 4 half steps first, 2 ahead */
    o.budget = 6 * unit + unit / 2;
    int depth[2] = {-1, -1};
    for (int back = 0; back < 2; back++) {
        if (vsv_pager_open(f, &o, &p))
            break;
        v = vsv_pager_volume_new(p);
        vsv_pager_playhead(p, 30, back ? -1 : 1, NULL, 0, one);
        if (vsv_pager_get(p, 30, 1, 1, v) == 0) {
            vsv_pager_stats_get(p, &st);
            depth[back] = st.prefetch_depth;
        }
        vsv_volume_free(v);
        vsv_pager_free(p);
    }
    CHECK(depth[0] == 4, "a budget of 6.5 steps: 4 steps decoded ahead (the budget in steps less two)", "(%d)",
          depth[0]);
    CHECK(depth[1] == 2, "playing backward: 2 steps ahead (4 checkpoints of half a step set aside first)", "(%d)",
          depth[1]);
}

/* A damaged payload: a clear error from the get, no crash, no hang. */
static void test_pager_corrupt(const char *path)
{
    size_t size = 0;
    unsigned char *data = vsv_test_slurp(path, &size);
    vsv_file *f = NULL;
    if (!data || vsv_file_open_mem(data, size, "series.vsv", &f)) {
        CHECK(0, "open the series in memory", " ");
        free(data);
        return;
    }
    vsv_file_info info;
    vsv_file_info_get(f, &info);
    /* damage step 7's first payload (SPEC.md §5: the chunk's offset from the
     * table of contents, payloads from align(32 + index_bytes, 64) on) */
    vsv_file_free(f);
    f = NULL;
    const unsigned char *toc = data + size - 32 - 24 * (size_t)info.nsteps;
    uint64_t chunk = 0;
    uint32_t index_bytes = 0;
    memcpy(&chunk, toc + 24 * 7, 8); /* little-endian hosts only, as the library */
    memcpy(&index_bytes, data + chunk + 16, 4);
    const size_t at = (size_t)chunk + (32 + index_bytes + 63) / 64 * 64 + 2;
    data[at] ^= 0x5a;
    data[at + 1] ^= 0xa5;
    vsv_file_open_mem(data, size, "series.vsv", &f);
    vsv_pager_opts o;
    vsv_pager_opts_init(&o);
    o.threads = 2;
    o.budget = 8 << 20;
    vsv_pager *p = NULL;
    int failed = 0, crashed = 0;
    if (f && vsv_pager_open(f, &o, &p) == 0) {
        vsv_pager_playhead(p, 0, 1, NULL, 0, NULL);
        vsv_volume *v = vsv_pager_volume_new(p);
        for (int t = 0; t < 60; t++)
            for (int s = 0; s < 3; s++) {
                const int rc = vsv_pager_get(p, t, s, 1, v);
                if (rc) {
                    failed++;
                    if (rc != VSV_ECORRUPT || !strstr(vsv_pager_error(p), "series.vsv"))
                        crashed++;
                }
            }
        vsv_volume_free(v);
        vsv_pager_free(p);
    }
    CHECK(failed > 0 && !crashed, "a damaged brick is a named error from the pager, other steps still play",
          "(%d failed gets)", failed);
    vsv_file_free(f);
    free(data);
}

static void test_clock(void)
{
    int64_t times[10];
    for (int i = 0; i < 10; i++)
        times[i] = 1000000 + 3600 * i;
    vsv_clock c;
    vsv_clock_init(&c, times, 10, 0);
    CHECK(c.step == 0 && !c.playing && c.speed == 1 && c.rate == 4 * 3600,
          "a new clock is paused at the first step, x1, four steps a second", "(rate %g)", c.rate);
    CHECK(vsv_clock_tick(&c, 1) == 0, "paused: wall time does not move it", " ");
    {
        /* irregular steps: the median interval (an hour), not the shortest */
        const int64_t odd[5] = {0, 60, 3660, 7260, 10860};
        vsv_clock o;
        vsv_clock_init(&o, odd, 5, 0);
        CHECK(o.rate == 4 * 3600, "the default rate is the median step interval per quarter second (one short step)",
              "(rate %g)", o.rate);
    }
    vsv_clock_play(&c);
    CHECK(vsv_clock_tick(&c, 0.25) == 1 && vsv_clock_tick(&c, 0.125) == 1 && vsv_clock_tick(&c, 0.125) == 2,
          "x1: one step per quarter second, the step at or before model time", "(step %d)", c.step);
    vsv_clock_set_speed(&c, 4);
    CHECK(vsv_clock_tick(&c, 0.25) == 6, "x4: four steps per quarter second", "(step %d)", c.step);
    vsv_clock_tick(&c, 10);
    CHECK(c.step == 9 && !c.playing, "at the end without loop it stops", "(step %d)", c.step);
    vsv_clock_play(&c);
    CHECK(c.step == 0 && c.playing, "play at the end starts over", "(step %d)", c.step);
    c.ends = VSV_CLOCK_LOOP;
    vsv_clock_seek_step(&c, 8);
    vsv_clock_set_speed(&c, 1);
    vsv_clock_tick(&c, 0.375);
    CHECK(c.step == 9 && c.playing, "loop: the last step is shown before the wrap", "(step %d)", c.step);
    vsv_clock_tick(&c, 0.25);
    CHECK(c.step == 0 && c.playing, "loop: past the end wraps to the start", "(step %d)", c.step);
    /* four laps in ticks of 0.1 s (2.5 ticks a step): every step, the last
     * included, is on screen about as long as every other, both ways */
    for (int dir = 1; dir >= -1; dir -= 2) {
        int seen[10] = {0}, lo = 1000, hi = 0;
        vsv_clock_set_speed(&c, dir);
        for (int i = 0; i < 100; i++)
            seen[vsv_clock_tick(&c, 0.1)]++;
        for (int k = 0; k < 10; k++)
            lo = seen[k] < lo ? seen[k] : lo, hi = seen[k] > hi ? seen[k] : hi;
        CHECK(lo >= 8 && hi <= 12,
              dir > 0 ? "loop forward: every step is shown, the last as long as the others"
                      : "loop backward: every step is shown, the first as long as the others",
              "(ticks per step: first %d, last %d, fewest %d, most %d)", seen[0], seen[9], lo, hi);
    }
    vsv_clock_set_speed(&c, 1);
    c.ends = VSV_CLOCK_BOUNCE;
    vsv_clock_seek_step(&c, 8);
    vsv_clock_tick(&c, 0.5);
    CHECK(c.step == 8 && c.speed == -1 && c.playing, "bounce: turns round at the end", "(step %d speed %g)", c.step,
          c.speed);
    vsv_clock_tick(&c, 0.25);
    CHECK(c.step == 7, "and plays backwards", "(step %d)", c.step);
    vsv_clock_seek_step(&c, 1);
    vsv_clock_tick(&c, 0.5); /* two steps' time backward from step 1: an hour before the start */
    CHECK(c.step == 1 && c.speed == 1 && c.playing && c.model == (double)times[1],
          "bounce: turns round at the start (an hour past it: step 1, forward)", "(step %d speed %g, model %+g s)",
          c.step, c.speed, c.model - (double)times[0]);
    c.ends = VSV_CLOCK_STOP;
    vsv_clock_pause(&c);
    vsv_clock_seek_step(&c, 0);
    vsv_clock_set_speed(&c, -1);
    vsv_clock_play(&c);
    CHECK(c.step == 9 && c.playing && c.speed == -1, "play backward at the start starts over from the end", "(step %d)",
          c.step);
    vsv_clock_seek_step(&c, 7);
    vsv_clock_step(&c, 3);
    CHECK(c.step == 9 && !c.playing, "step +3 pauses and clamps at the end", "(step %d)", c.step);
    vsv_clock_step(&c, -4);
    CHECK(c.step == 5 && c.model == (double)times[5], "step -4 goes back four steps", "(step %d)", c.step);
    vsv_clock_step(&c, -40);
    CHECK(c.step == 0, "step before the start clamps", "(step %d)", c.step);
    c.ends = VSV_CLOCK_LOOP;
    vsv_clock_step(&c, -1);
    CHECK(c.step == 9, "with loop on, step -1 from the start wraps to the end", "(step %d)", c.step);
    c.ends = VSV_CLOCK_STOP;
    vsv_clock_seek_time(&c, times[3] + 1800);
    CHECK(c.step == 3, "seek to a time between steps shows the step before", "(step %d)", c.step);
    vsv_clock_seek_time(&c, 0);
    CHECK(c.step == 0, "seek before the first time clamps", "(step %d)", c.step);
    vsv_clock_seek_step(&c, 4);
    vsv_clock_faster(&c, 1);
    CHECK(c.playing && c.speed == 2, "fast-forward from pause plays at x2", "(speed %g)", c.speed);
    for (int i = 0; i < 8; i++)
        vsv_clock_faster(&c, 1);
    CHECK(c.speed == 64, "fast-forward doubles up to x64", "(speed %g)", c.speed);
    vsv_clock_faster(&c, -1);
    CHECK(c.speed == -2 && c.playing, "rewind while going forward plays backwards at x2", "(speed %g)", c.speed);
    vsv_clock_faster(&c, -1);
    CHECK(c.speed == -4, "rewind again: x4 backwards", "(speed %g)", c.speed);
    vsv_clock_seek_step(&c, 6);
    vsv_clock_set_speed(&c, -1);
    vsv_clock_tick(&c, 0.125);
    CHECK(c.step == 6 && c.model < (double)times[6], "backwards, the step at or after model time is shown", "(step %d)",
          c.step);
    vsv_clock_tick(&c, 0.125);
    CHECK(c.step == 5, "and the previous step once it is reached", "(step %d)", c.step);
    vsv_clock_set_speed(&c, 0);
    CHECK(c.speed == -1, "speed 0 is refused", "(speed %g)", c.speed);
    vsv_clock_set_speed(&c, 1000);
    CHECK(c.speed == 64, "speed is clamped to x64", "(speed %g)", c.speed);
    vsv_clock_pause(&c);
    const double m = c.model;
    vsv_clock_tick(&c, 3);
    CHECK(c.model == m && !c.playing, "pause holds model time", " ");
    vsv_clock_seek_step(&c, 0);
    vsv_clock_set_speed(&c, -1);
    vsv_clock_play(&c);
    const int from = c.step;
    CHECK(from == 9 && c.playing && vsv_clock_tick(&c, 0.25) == 8,
          "play backwards at the start starts over from the last step (9, then 8)", "(step %d, then %d)", from, c.step);
}

/* Whether steps[0 .. n-1] are want[] (m of them). */
static int list_is(const int *steps, int n, const int *want, int m)
{
    if (n != m)
        return 0;
    for (int i = 0; i < n; i++)
        if (steps[i] != want[i])
            return 0;
    return 1;
}

static void test_clock_ahead(void)
{
    int64_t times[10];
    for (int i = 0; i < 10; i++)
        times[i] = 3600 * i;
    vsv_clock c;
    vsv_clock_init(&c, times, 10, 0); /* four steps a second at x1 */
    int s[20], n;
    const double frame = 3.0 / 64; /* x8: 1.5 steps a frame, exactly */
    n = vsv_clock_ahead(&c, frame, s, 20);
    CHECK(list_is(s, n, (int[]){1}, 1), "paused: the step ahead is the next one", "(%d: %d)", n, s[0]);
    vsv_clock_set_speed(&c, 8);
    vsv_clock_play(&c);
    n = vsv_clock_ahead(&c, frame, s, 20);
    CHECK(list_is(s, n, (int[]){1, 3, 4, 6, 7, 9}, 6),
          "1.5 steps a frame: the steps the frames show, the ones jumped over left out, to the end", "(%d: %d %d %d)",
          n, s[0], s[1], s[2]);
    CHECK(vsv_clock_ahead(&c, frame, s, 3) == 3 && s[2] == 4, "no more than asked", " ");
    vsv_clock_seek_step(&c, 9);
    vsv_clock_set_speed(&c, -8);
    vsv_clock_play(&c);
    n = vsv_clock_ahead(&c, frame, s, 20);
    CHECK(list_is(s, n, (int[]){8, 6, 5, 3, 2, 0}, 6), "backward: the step at or after each frame's time",
          "(%d: %d %d %d)", n, s[0], s[1], s[2]);
    c.ends = VSV_CLOCK_LOOP;
    vsv_clock_seek_step(&c, 7);
    vsv_clock_set_speed(&c, 8);
    vsv_clock_play(&c);
    n = vsv_clock_ahead(&c, frame, s, 4);
    CHECK(list_is(s, n, (int[]){8, 0, 1, 3}, 4), "looping: through the wrap as the clock goes", "(%d: %d %d %d %d)", n,
          s[0], s[1], s[2], s[3]);
    n = vsv_clock_ahead(&c, frame, s, 20);
    CHECK(n == 9 && s[8] != 7, "a lap lists each other step once", "(%d)", n);
    vsv_clock_set_speed(&c, 1.0 / 64);
    n = vsv_clock_ahead(&c, 1.0 / 32, s, 3);
    CHECK(list_is(s, n, (int[]){8, 9}, 2), "x1/64 (512 frames a step): the steps of the next 1024 frames",
          "(%d: %d %d)", n, s[0], s[1]);
    c.ends = VSV_CLOCK_STOP;
    vsv_clock_seek_step(&c, 9);
    CHECK(vsv_clock_ahead(&c, frame, s, 20) == 0, "paused at the last step without loop: nothing ahead", " ");
    /* against the clock ticked frame by frame: any ends, speed, frame and
     * place, uneven step times */
    int64_t uneven[7] = {0, 600, 900, 3600, 3700, 7200, 9000};
    uint64_t rng = 99;
    int agree = 0, tries = 0;
    for (int r = 0; r < 1000 && tries < 300; r++) {
        vsv_clock k;
        vsv_clock_init(&k, uneven, 7, 0);
        k.ends = (int)(vsv_test_rand(&rng) % 3);
        vsv_clock_seek_step(&k, (int)(vsv_test_rand(&rng) % 7));
        const double x = ldexp(1, (int)(vsv_test_rand(&rng) % 13) - 6) * (vsv_test_rand(&rng) & 1 ? -1 : 1);
        const double fr = (double)(1 + vsv_test_rand(&rng) % 100) / 997;
        vsv_clock_set_speed(&k, x);
        vsv_clock_play(&k);
        vsv_clock_tick(&k, (double)(vsv_test_rand(&rng) % 1000) / 3001);
        if (!k.playing) /* stopped at an end */
            continue;
        tries++;
        int want[8], m = 0;
        vsv_clock b = k;
        for (int f = 0; f < VSV_CLOCK_HORIZON && m < 8 && b.playing; f++) {
            vsv_clock_tick(&b, fr);
            int seen = b.step == k.step;
            for (int i = 0; i < m && !seen; i++)
                seen = want[i] == b.step;
            if (!seen)
                want[m++] = b.step;
        }
        n = vsv_clock_ahead(&k, fr, s, 8);
        agree += list_is(s, n, want, m);
    }
    CHECK(agree == tries, "the steps ahead are those of the clock ticked frame by frame (300 random plays)",
          "(%d of %d agree)", agree, tries);
}

/* Playing so fast that a frame spans several steps: the stride, with its
 * hysteresis, and the steps shown at it; then a run of frames whose times
 * vary by +-25 %: each frame's step is one the frame before listed ahead. */
static void test_clock_stride(void)
{
    int64_t times[40];
    for (int i = 0; i < 40; i++)
        times[i] = 300 * i;
    vsv_clock c;
    vsv_clock_init(&c, times, 40, 1200); /* four steps a second at x1 */
    vsv_clock_set_speed(&c, 8);          /* 32 steps a second */
    CHECK(vsv_clock_stride(&c, 0.08, 1) == 1, "paused: stride 1");
    vsv_clock_play(&c);
    const int k1 = vsv_clock_stride(&c, 1.5 / 32, 1), k2 = vsv_clock_stride(&c, 2.5 / 32, 1),
              k3 = vsv_clock_stride(&c, 2.3 / 32, 1), k4 = vsv_clock_stride(&c, 3.5 / 32, 2),
              k5 = vsv_clock_stride(&c, 3.8 / 32, 2), k6 = vsv_clock_stride(&c, 1.9 / 32, 2),
              k7 = vsv_clock_stride(&c, 9.5 / 32, 1), k8 = vsv_clock_stride(&c, 3.5 / 32, 5),
              k9 = vsv_clock_stride(&c, 2.1 / 32, 2);
    CHECK(k1 == 1 && k2 == 2 && k3 == 1 && k4 == 2 && k5 == 3 && k6 == 1 && k7 == 7 && k8 == 2 && k9 == 2,
          "stride: 1.5 steps a frame 1; 2.5 from 1: 2; 2.3 from 1 stays 1; 3.5 from 2 stays 2; 3.8: 3; 1.9: 1; "
          "9.5 from 1: 7; 3.5 from 5: 2; 2.1 from 2 stays 2",
          "(%d %d %d %d %d %d %d %d %d)", k1, k2, k3, k4, k5, k6, k7, k8, k9);
    const int f7 = vsv_clock_stride_step(&c, 7, 3);
    vsv_clock_set_speed(&c, -8);
    const int b7 = vsv_clock_stride_step(&c, 7, 3), b38 = vsv_clock_stride_step(&c, 38, 4);
    CHECK(f7 == 6 && b7 == 9 && b38 == 39, "stride steps: forward 7 -> 6, backward 7 -> 9, 38 -> 39 (the last)",
          "(%d %d %d)", f7, b7, b38);
    /* frames of 50 to 130 ms at x8, looping both ways: 1.6 to 4.2 steps a
     * frame; the steps listed ahead hold every frame's step, whatever its
     * time, and the stride stays put */
    for (int dir = 1; dir >= -1; dir -= 2) {
        vsv_clock_seek_step(&c, dir > 0 ? 0 : 39);
        vsv_clock_set_speed(&c, 8 * dir);
        c.ends = VSV_CLOCK_LOOP;
        vsv_clock_play(&c);
        uint64_t rng = 5;
        int k = 1, missed = 0, changes = 0, shown = -1, ahead[VSV_PAGER_AHEAD + 1], na = 0;
        double smooth = 0.09;
        for (int f = 0; f < 400; f++) {
            const double dt = 0.05 + 0.08 * (double)(vsv_test_rand(&rng) % 1000) / 1000;
            vsv_clock_tick(&c, dt);
            smooth = 0.75 * smooth + 0.25 * dt;
            const int was = k;
            k = vsv_clock_stride(&c, smooth, k);
            changes += f >= 8 && k != was;
            const int t = vsv_clock_stride_step(&c, c.step, k);
            int in = t == shown || k != was;
            for (int i = 0; i < na && !in; i++)
                in = ahead[i] == t;
            missed += !in && f >= 2;
            shown = t;
            na = vsv_clock_ahead_stride(&c, smooth, k, ahead, VSV_PAGER_AHEAD + 1);
        }
        CHECK(k == 2 && missed == 0 && changes <= 4,
              "x8 at 50-130 ms a frame: stride 2; every frame's step listed ahead the frame before; the stride "
              "changed at most 4 times in 400 frames",
              "(direction %d: stride %d, %d frames' steps not listed, %d changes)", dir, k, missed, changes);
    }
}

int main(void)
{
    test_clock_stride();
    const char *path = vsv_test_tmp("stream-series.vsv");
    if (write_series(path) == 0) {
        test_pager(path);
        test_pager_corrupt(path);
    }
    test_clock();
    test_clock_ahead();
    return vsv_test_done();
}
