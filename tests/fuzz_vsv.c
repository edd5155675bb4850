/* fuzz_vsv.c — fuzz target for the .vsv reader: open any bytes and, when
 * they open, check and decode everything. Its mutator is structure-aware:
 * it changes one field of the header, a metadata record, the table of
 * contents, the end marker, a chunk header, an octree node, a brick entry
 * or a payload (or lets libFuzzer change raw bytes), then recomputes every
 * CRC the file's own (possibly changed) layout points at (SPEC.md §3-§9),
 * so that the input reaches the structure checks behind the checksums.
 * One mutation in sixteen keeps the stale CRCs. Built for libFuzzer by
 * `make fuzz`; fuzz_main.c runs it as a regression test in `make test`. */
#include "vsv_format.h"
#include "vsv_layout.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
size_t LLVMFuzzerCustomMutator(uint8_t *data, size_t size, size_t max, unsigned seed);
size_t LLVMFuzzerMutate(uint8_t *data, size_t size, size_t max);
int fuzz_report(char *msg, size_t cap);
const char *const fuzz_default_dirs[4] = {"tests/golden", "tests/golden/bad", "tests/corpus/vsv", NULL};
const char fuzz_label[] = ".vsv reader";
const long fuzz_mutations = 1500;

/* outcomes of the inputs run (fuzz_report) */
static long n_runs, n_crc, n_struct, n_opened, n_checked;

static void classify(int rc, const vsv_file *f)
{
    n_runs++;
    if (rc == 0)
        return;
    const char *e = f ? vsv_file_error(f) : "";
    if (strstr(e, "checksum"))
        n_crc++;
    else
        n_struct++;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    vsv_file *f = NULL;
    int rc = vsv_file_open_mem(data, size, "fuzz", &f);
    if (rc == 0) {
        n_opened++;
        const vsv_meta *m = vsv_file_meta(f);
        vsv_file_info info;
        vsv_file_info_get(f, &info);
        vsv_file_counts cnt; /* every chunk index verified */
        vsv_file_count(f, &cnt);
        const size_t cells = (size_t)m->nx * m->ny * m->nz;
        if (cells <= ((size_t)1 << 20) && (size_t)info.nsteps * info.nspecies <= 4096) {
            rc = vsv_file_check(f, NULL, NULL);
            if (rc == 0)
                n_checked++;
            float *vol = malloc(cells * sizeof *vol);
            vsv_decoder *d = NULL;
            if (vol && vsv_decoder_create(f, &d) == 0)
                for (int t = 0; t < info.nsteps; t++)
                    for (int s = 0; s < info.nspecies; s++)
                        (void)vsv_decoder_volume(d, t, s, vol);
            vsv_decoder_free(d);
            free(vol);
        }
    }
    classify(rc, f);
    vsv_file_free(f);
    return 0;
}

int fuzz_report(char *msg, size_t cap)
{
    /* Raw byte changes are caught by a CRC almost every time; with the
     * CRCs recomputed most inputs must be judged by the structure checks. */
    snprintf(msg, cap, "%ld inputs: %ld stopped at a checksum, %ld by a structure check, %ld opened, %ld checked clean",
             n_runs, n_crc, n_struct, n_opened, n_checked);
    return n_runs > 0 && n_struct * 2 > n_runs && n_crc * 5 < n_runs && n_opened > 0 ? 0 : -1;
}

/* ------------------------------------------------------------ the mutator */

static uint64_t rd(const uint8_t *p, int w)
{
    uint64_t v = 0;
    for (int i = w - 1; i >= 0; i--)
        v = v << 8 | p[i];
    return v;
}

static void wr(uint8_t *p, int w, uint64_t v)
{
    for (int i = 0; i < w; i++, v >>= 8)
        p[i] = (uint8_t)v;
}

static uint64_t rnd(uint64_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 7;
    *s ^= *s << 17;
    return *s;
}

/* inside [0, n): off + len without wrapping */
static int inside(uint64_t off, uint64_t len, size_t n) { return off <= n && len <= n - off; }

/* The file's regions as its own header and tables describe them. */
typedef struct view {
    uint64_t meta_off, meta_size, toc_off;
    uint32_t nsteps, nspecies;
    vsv_layout lay;
    int have_lay;
} view;

static int view_of(const uint8_t *d, size_t n, view *v)
{
    if (n < 160 || memcmp(d, "\x89VSV\r\n\x1a\n", 8))
        return -1;
    v->meta_off = rd(d + 24, 8);
    v->meta_size = rd(d + 32, 8);
    v->nsteps = (uint32_t)rd(d + 44, 4);
    v->toc_off = rd(d + 48, 8);
    v->nspecies = (uint32_t)rd(d + 68, 4);
    const uint32_t nx = (uint32_t)rd(d + 72, 4), ny = (uint32_t)rd(d + 76, 4), nz = (uint32_t)rd(d + 80, 4);
    const uint32_t b = (uint32_t)rd(d + 84, 4);
    v->have_lay = nx && ny && nz && nx <= 65536 && ny <= 65536 && nz <= 65536 &&
                  (b == 8 || b == 16 || b == 32 || b == 64) &&
                  (uint64_t)((nx + b - 1) / b) * ((ny + b - 1) / b) * ((nz + b - 1) / b) < ((uint64_t)1 << 24) &&
                  vsv_layout_init(&v->lay, (int)nx, (int)ny, (int)nz, (int)b) == 0;
    return 0;
}

/* Recomputes every CRC that the layout reaches, innermost first. */
static void fix_crcs(uint8_t *d, size_t n)
{
    view v;
    if (view_of(d, n, &v))
        return;
    if (inside(v.meta_off, v.meta_size, n))
        wr(d + 40, 4, vsv_crc32c(0, d + v.meta_off, v.meta_size));
    const uint64_t toc_bytes = (uint64_t)v.nsteps * 24;
    for (uint32_t t = 0; t < v.nsteps && inside(v.toc_off, (uint64_t)(t + 1) * 24, n); t++) {
        const uint64_t c = rd(d + v.toc_off + 24 * (uint64_t)t, 8);
        if (!inside(c, 32, n))
            continue;
        const uint64_t ib = rd(d + c + 16, 4);
        if (!inside(c + 32, ib, n))
            continue;
        if (v.have_lay) {
            const uint64_t S = v.lay.species_index_bytes;
            for (uint32_t s = 0; s < v.nspecies && (uint64_t)(s + 1) * S <= ib; s++) {
                const uint8_t *tab = d + c + 32 + s * S + v.lay.octree_bytes;
                for (int b = 0; b < v.lay.nbricks; b++) {
                    uint8_t *e = (uint8_t *)tab + 24 * (size_t)b;
                    if (e[0] != 2 && e[0] != 3)
                        continue;
                    const uint64_t po = rd(e + 8, 8), ps = rd(e + 16, 4);
                    if (po <= n && inside(c + po, ps, n) && c + po >= c)
                        wr(e + 4, 4, vsv_crc32c(0, d + c + po, ps));
                }
            }
        }
        wr(d + c + 28, 4, vsv_crc32c(vsv_crc32c(0, d + c, 28), d + c + 32, ib));
    }
    if (inside(v.toc_off, toc_bytes, n)) {
        const uint32_t tc = vsv_crc32c(0, d + v.toc_off, toc_bytes);
        wr(d + 64, 4, tc);
        wr(d + n - 8, 4, tc);
    }
    wr(d + n - 4, 4, vsv_crc32c(0, d + n - 32, 28));
    wr(d + 124, 4, vsv_crc32c(0, d, 124));
}

/* A new value for a field of w bytes that held old. */
static uint64_t new_value(uint64_t *s, uint64_t old, int w, size_t n)
{
    static const uint64_t special[] = {0,
                                       1,
                                       2,
                                       3,
                                       7,
                                       8,
                                       24,
                                       31,
                                       32,
                                       63,
                                       64,
                                       65,
                                       127,
                                       128,
                                       255,
                                       256,
                                       4095,
                                       4096,
                                       65535,
                                       65536,
                                       0x7fffffff,
                                       0x80000000,
                                       0xffffffff,
                                       0x7fffffffffffffff,
                                       0x8000000000000000,
                                       UINT64_MAX};
    switch (rnd(s) % 6) {
    case 0: return special[rnd(s) % (sizeof special / sizeof *special)];
    case 1: return old + 1 + rnd(s) % 8;
    case 2: return old - 1 - rnd(s) % 8;
    case 3: return old ^ (uint64_t)1 << (rnd(s) % (8 * (unsigned)w));
    case 4: return old + (rnd(s) % 2 ? 64 : -(uint64_t)64) * (1 + rnd(s) % 4);
    default: return rnd(s) % 3 ? rnd(s) % (n + 64) : rnd(s); /* an offset inside the file, or anything */
    }
}

/* One field of the file: its offset and width (0: none found). */
static int pick_field(const uint8_t *d, size_t n, uint64_t *s, uint64_t *at)
{
    view v;
    if (view_of(d, n, &v))
        return 0;
    switch (rnd(s) % 8) {
    case 0: { /* header */
        static const uint8_t off[] = {8, 10, 12, 16, 24, 32, 44, 48, 56, 68, 72, 76, 80, 84, 88, 92, 96, 100};
        static const uint8_t wid[] = {2, 2, 4, 8, 8, 8, 4, 8, 8, 4, 4, 4, 4, 4, 4, 4, 4, 4};
        const int i = (int)(rnd(s) % sizeof off);
        *at = off[i];
        return wid[i];
    }
    case 1:
    case 2: { /* a metadata record: its tag, length or a word of its payload */
        if (!inside(v.meta_off, v.meta_size, n))
            return 0;
        uint64_t recs[256], nrec = 0;
        for (uint64_t o = v.meta_off; o + 8 <= v.meta_off + v.meta_size && nrec < 256;) {
            recs[nrec++] = o;
            const uint64_t len = rd(d + o + 4, 4);
            o += 8 + (len + 7) / 8 * 8;
        }
        if (!nrec)
            return 0;
        const uint64_t r = recs[rnd(s) % nrec], len = rd(d + r + 4, 4);
        const unsigned what = (unsigned)(rnd(s) % 4);
        if (what == 0 || !inside(r + 8, len, n) || len < 4) {
            *at = r + 4 * (what & 1);
            return 4;
        }
        *at = r + 8 + rnd(s) % (len - 3);
        return len >= 8 && rnd(s) % 2 && *at + 8 <= r + 8 + len ? 8 : 4;
    }
    case 3: /* the table of contents */
        if (!v.nsteps || !inside(v.toc_off, (uint64_t)v.nsteps * 24, n))
            return 0;
        *at = v.toc_off + 24 * (rnd(s) % v.nsteps) + 8 * (rnd(s) % 3);
        return 8;
    case 4: /* the end marker */ *at = n - 32 + 8 * (1 + rnd(s) % 2); return 8;
    default: { /* a chunk: its header, an octree node, a brick entry or a payload byte */
        if (!v.nsteps || !inside(v.toc_off, (uint64_t)v.nsteps * 24, n))
            return 0;
        const uint64_t c = rd(d + v.toc_off + 24 * (rnd(s) % v.nsteps), 8);
        if (!inside(c, 32, n))
            return 0;
        const unsigned what = (unsigned)(rnd(s) % 4);
        if (what == 0 || !v.have_lay || !v.nspecies) {
            static const uint8_t off[] = {0, 4, 8, 16, 20, 24};
            static const uint8_t wid[] = {4, 4, 8, 4, 4, 4};
            const int i = (int)(rnd(s) % sizeof off);
            *at = c + off[i];
            return wid[i];
        }
        const uint64_t sp = c + 32 + (rnd(s) % v.nspecies) * v.lay.species_index_bytes;
        if (what == 1) {
            *at = sp + 4 * (rnd(s) % v.lay.nnodes) + 2 * (rnd(s) % 2);
            return inside(*at, 2, n) ? 2 : 0;
        }
        const uint64_t e = sp + v.lay.octree_bytes + 24 * (rnd(s) % (uint64_t)v.lay.nbricks);
        if (!inside(e, 24, n))
            return 0;
        if (what == 2) {
            static const uint8_t off[] = {0, 1, 8, 16, 20};
            static const uint8_t wid[] = {1, 1, 8, 4, 4};
            const int i = (int)(rnd(s) % sizeof off);
            *at = e + off[i];
            return wid[i];
        }
        const uint64_t po = rd(d + e + 8, 8), ps = rd(d + e + 16, 4);
        if ((d[e] != 2 && d[e] != 3) || !ps || po > n || !inside(c + po, ps, n))
            return 0;
        *at = c + po + rnd(s) % ps;
        return 1;
    }
    }
}

size_t LLVMFuzzerCustomMutator(uint8_t *data, size_t size, size_t max, unsigned seed)
{
    uint64_t s = seed * 0x9E3779B97F4A7C15ull | 1;
    int changed = 0;
    if (rnd(&s) % 4) {
        for (int tries = 0; tries < 8 && !changed; tries++) {
            uint64_t at;
            const int w = pick_field(data, size, &s, &at);
            if (w && inside(at, (uint64_t)w, size)) {
                const uint64_t old = rd(data + at, w), v = new_value(&s, old, w, size);
                wr(data + at, w, v);
                changed = rd(data + at, w) != old;
            }
        }
    }
    if (!changed)
        size = LLVMFuzzerMutate(data, size, max);
    if (rnd(&s) % 16)
        fix_crcs(data, size);
    return size;
}
