/* test_rice.c — format 4's Rice-coded brick kinds (SPEC.md §7 "Rice
 * coding"): the payload coder round trip over boxes of every shape and
 * residuals of every size, its refusals (a stream cut, a byte too many,
 * bits after the last code, a parameter or a value out of range, random
 * bytes), and files: the default writer's header says 4.0, noisy smooth
 * fields take ABS3R and DELTA3R, every value equals the format-3 file's and
 * the reference reader's (written from SPEC.md alone), and a payload
 * changed under a valid checksum is an error, not a wrong picture. */
#include "vsv_format_internal.h"
#include "vsv_layout.h"
#include "vsv_refread.h"
#include "vsv_testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

enum { MAXN = 64 * 64 * 64 };

/* A box's zigzagged residuals as planes: mostly small, a share of large
 * ones (escapes) and of the largest, per the mix. */
static void fill(int bits, size_t n, int mix, uint64_t *st, unsigned char *planes)
{
    const unsigned mask = bits == 8 ? 0xffu : 0xffffu;
    for (size_t m = 0; m < n; m++) {
        const unsigned r = (unsigned)vsv_test_rand(st);
        unsigned z = mix == 0 ? 0 : mix == 1 ? r % 5 : mix == 2 ? r % 3000 : r;
        if (mix == 3 && r % 7 == 0)
            z = mask;
        z &= mask;
        planes[m] = (unsigned char)z;
        if (bits == 16)
            planes[n + m] = (unsigned char)(z >> 8);
    }
}

/* A payload's padded copy, as the decoder reads it, decoded; its
 * residuals (a value a cell) as planes (-2: a value past 8 bits given). */
static int decode(int bits, const int ext[3], const unsigned char *p, size_t size, unsigned char *planes)
{
    static unsigned char pad[3 * 2 * MAXN + 4096];
    static uint16_t z[MAXN];
    if (size > sizeof pad - VSV_RICE_PAD)
        return -1;
    memcpy(pad, p, size);
    memset(pad + size, 0xA5, VSV_RICE_PAD); /* whatever follows a payload: never part of it */
    const size_t n = (size_t)ext[0] * ext[1] * ext[2];
    for (size_t m = 0; m < n; m++)
        z[m] = 0x5A5A;
    const int rc = vsv_rice_decode(bits, ext, pad, size, z);
    for (size_t m = 0; m < n && rc == 0; m++) {
        if (bits == 8 && z[m] > 0xff)
            return -2;
        planes[m] = (unsigned char)z[m];
        if (bits == 16)
            planes[n + m] = (unsigned char)(z[m] >> 8);
    }
    return rc;
}

static void test_coder(void)
{
    static unsigned char in[2 * MAXN], out[2 * MAXN], pay[3 * 2 * MAXN + 64];
    static uint16_t ctx[3 * MAXN / 2]; /* the encoder's scratch */
    const int shapes[][3] = {{1, 1, 1}, {2, 1, 1}, {5, 3, 2}, {31, 7, 3}, {32, 32, 15}, {33, 2, 2}, {64, 64, 64}};
    uint64_t st = 11;
    int same = 1, fits = 1, tried = 0;
    size_t worst = 0;
    for (int bits = 8; bits <= 16; bits += 8)
        for (size_t s = 0; s < sizeof shapes / sizeof *shapes; s++)
            for (int mix = 0; mix < 4; mix++) {
                const int *ext = shapes[s];
                const size_t n = (size_t)ext[0] * ext[1] * ext[2];
                fill(bits, n, mix, &st, in);
                const size_t size = vsv_rice_encode(bits, ext, in, ctx, pay, sizeof pay);
                fits &= size > 0 && size <= vsv_rice_max(bits, n);
                worst = size > worst ? size : worst;
                memset(out, 0x5A, sizeof out);
                same &= size > 0 && decode(bits, ext, pay, size, out) == 0 && !memcmp(in, out, bits == 8 ? n : 2 * n);
                tried++;
            }
    CHECK(same, "Rice payloads decode to their residuals: 8 and 16 bits, 7 box shapes, 4 mixes", "(%d tried)", tried);
    CHECK(fits, "every payload within vsv_rice_max", "(largest %zu bytes)", worst);

    /* a cap too small: 0, nothing written past it */
    const int ext[3] = {32, 32, 15};
    const size_t n = 32 * 32 * 15;
    fill(16, n, 2, &st, in);
    const size_t size = vsv_rice_encode(16, ext, in, ctx, pay, sizeof pay);
    memset(pay + size / 2, 0xEE, 16);
    CHECK(vsv_rice_encode(16, ext, in, ctx, pay, size / 2) == 0 && pay[size / 2] == 0xEE,
          "an encoder whose output would pass its cap gives 0 and stays within it");
    vsv_rice_encode(16, ext, in, ctx, pay, sizeof pay);
    CHECK(decode(16, ext, pay, size, out) == 0, "the payload again decodes");
    CHECK(decode(16, ext, pay, size - 1, out) == -1, "a payload cut by a byte is refused");
    pay[size] = 0;
    CHECK(decode(16, ext, pay, size + 1, out) == -1, "a payload with a byte too many is refused");
    unsigned char keep = pay[5];
    pay[5] = 17; /* a parameter above 16 bits */
    CHECK(decode(16, ext, pay, size, out) == -1, "a Rice parameter larger than the bits is refused");
    pay[5] = keep;
    const uint32_t l0 = vsv_rd32(pay + VSV_RICE_CONTEXTS);
    vsv_wr32(pay + VSV_RICE_CONTEXTS, (uint32_t)size);
    CHECK(decode(16, ext, pay, size, out) == -1, "a stream length past the payload is refused");
    vsv_wr32(pay + VSV_RICE_CONTEXTS, l0);
    CHECK(decode(16, ext, pay, VSV_RICE_CONTEXTS + 5, out) == -1, "a payload shorter than its head is refused");

    /* bits after the last code: a one in the last byte's unused bits */
    const int one[3] = {1, 1, 1};
    in[0] = 0; /* one zero: a code of one bit (Rice parameter 0), seven zero bits after it */
    const size_t s1 = vsv_rice_encode(8, one, in, ctx, pay, sizeof pay);
    CHECK(s1 == VSV_RICE_CONTEXTS + 12 + 1 && decode(8, one, pay, s1, out) == 0 && out[0] == 0,
          "one cell: a head and one byte", "(%zu bytes)", s1);
    pay[s1 - 1] |= 0x80;
    CHECK(decode(8, one, pay, s1, out) == -1, "a one after the last code is refused");
    /* a value above 8 bits: quotient 1 with a parameter of 8 */
    memset(pay, 0, VSV_RICE_CONTEXTS);
    pay[0] = 8;
    pay[s1 - 1] = 0x02; /* 0 then 1: quotient 1, then 8 zero bits would follow: cut */
    CHECK(decode(8, one, pay, s1, out) == -1, "a code running past its stream is refused");

    /* random bytes: never a crash, and refused or decoded within range */
    int calm = 1;
    for (int k = 0; k < 4000; k++) {
        const int e[3] = {1 + (int)(vsv_test_rand(&st) % 40), 1 + (int)(vsv_test_rand(&st) % 9),
                          1 + (int)(vsv_test_rand(&st) % 5)};
        const int bits = k & 1 ? 16 : 8;
        const size_t len = (size_t)(vsv_test_rand(&st) % 600);
        for (size_t b = 0; b < len; b++)
            pay[b] = (unsigned char)vsv_test_rand(&st);
        if (len > VSV_RICE_CONTEXTS)
            for (int c = 0; c < VSV_RICE_CONTEXTS; c++)
                pay[c] %= (unsigned char)(bits + 1);
        const int rc = decode(bits, e, pay, len, out);
        calm &= rc == 0 || rc == -1;
    }
    CHECK(calm, "4000 payloads of random bytes: each refused or decoded, none crashed");
}

/* A smooth field with noise of a few codes, drifting: what the Rice kinds are for. */
static float noisy(int i, int j, int k, int t, uint64_t *st)
{
    return (float)(100 + 3 * sin(0.2 * i + 0.1 * t) + 2 * cos(0.15 * j) + 0.5 * k +
                   1e-3 * (double)(vsv_test_rand(st) % 1000));
}

static int write_file(const char *path, const vsv_meta *m, int predict, float *const *v, int nt, int ns, size_t n)
{
    vsv_pack_opts o;
    vsv_pack_opts_init(&o);
    if (predict >= 0)
        o.predict = predict;
    o.brick = 16;
    o.keyframe = 3;
    o.threads = 1;
    vsv_writer *w = NULL;
    int rc = vsv_writer_create(path, m, &o, &w);
    for (int t = 0; t < nt && !rc; t++) {
        const float *f[4];
        for (int s = 0; s < ns; s++)
            f[s] = v[t] + (size_t)s * n;
        rc = vsv_writer_add_step(w, 3600 * t, f);
    }
    if (!rc)
        rc = vsv_writer_finish(w, NULL, NULL);
    vsv_writer_free(w);
    return rc;
}

/* Every step and species of f4 against f3 and the reference reader. */
static void compare(vsv_file *f4, vsv_file *f3, const unsigned char *d4, size_t n4, int nt, int ns, size_t n)
{
    vsv_decoder *x4 = NULL, *x3 = NULL;
    float *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b), *rv = malloc(n * sizeof *rv);
    uint16_t *codes = malloc(n * sizeof *codes);
    ref_file rf;
    char err[256] = "";
    int ok = a && b && rv && codes && !vsv_decoder_create(f4, &x4) && !vsv_decoder_create(f3, &x3);
    int refok = ok && ref_open(&rf, d4, n4, err, sizeof err) == 0, same = ok, back = ok;
    for (int t = 0; t < nt && same; t++)
        for (int s = 0; s < ns && same; s++) {
            same = !vsv_decoder_volume(x4, t, s, a) && !vsv_decoder_volume(x3, t, s, b) && !memcmp(a, b, n * sizeof *a);
            if (refok)
                refok = ref_decode(&rf, (unsigned)t, (unsigned)s, codes, rv, err, sizeof err) == 0 &&
                        !memcmp(a, rv, n * sizeof *a);
        }
    /* backwards, brick by brick: a delta undone (the pager's way) */
    uint16_t c4[16 * 16 * 16], c3[16 * 16 * 16];
    for (int b4 = 0; b4 < 8 && back; b4++) {
        back = !vsv_decoder_brick_codes(x4, nt - 1, 0, b4, c4);
        for (int t = nt - 1; t > 0 && back; t--) {
            const int abs = vsv_brick_absolute(vsv_file_brick_kind(f4, t, 0, b4)); /* a keyframe: decoded afresh */
            back =
                !(abs ? vsv_decoder_brick_codes(x4, t - 1, 0, b4, c4) : vsv_decoder_brick_retreat(x4, t, 0, b4, c4)) &&
                !vsv_decoder_brick_codes(x3, t - 1, 0, b4, c3) && !memcmp(c4, c3, sizeof c4);
        }
    }
    CHECK(same, "format 4 decodes to format 3's values bit for bit, every step and species");
    CHECK(refok, "the reference reader decodes the format-4 file to the same values", "%s", err);
    CHECK(back, "stepping back through Rice-coded deltas gives the earlier steps' codes");
    if (refok)
        ref_close(&rf);
    vsv_decoder_free(x4);
    vsv_decoder_free(x3);
    free(a);
    free(b);
    free(rv);
    free(codes);
}

static void test_file(void)
{
    enum { NX = 40, NY = 30, NZ = 20, NT = 5, NS = 2 };
    const size_t n = (size_t)NX * NY * NZ;
    vsv_meta m;
    vsv_meta_init(&m);
    m.nx = NX, m.ny = NY, m.nz = NZ;
    m.spacing[0] = m.spacing[1] = m.spacing[2] = 1000;
    vsv_meta_add_var(&m, "noisy", "1", "smooth with noise");
    vsv_meta_add_var(&m, "sparse", "1", "mostly zero");
    float *v[NT];
    uint64_t st = 5;
    for (int t = 0; t < NT; t++) {
        v[t] = malloc(NS * n * sizeof *v[t]);
        for (size_t c = 0; c < n; c++) {
            const int i = (int)(c % NX), j = (int)(c / NX % NY), k = (int)(c / NX / NY);
            v[t][c] = noisy(i, j, k, t, &st);
            v[t][n + c] = i > 30 && j > 20 ? (float)(i + j + t) : 0.0f;
        }
    }
    const char *p4 = vsv_test_tmp("rice4.vsv"), *p3 = vsv_test_tmp("rice3.vsv");
    CHECK(!write_file(p4, &m, -1, v, NT, NS, n) && !write_file(p3, &m, 1, v, NT, NS, n),
          "a series written by default and with predict 1");
    size_t n4 = 0, n3 = 0;
    unsigned char *d4 = vsv_test_slurp(p4, &n4), *d3 = vsv_test_slurp(p3, &n3);
    CHECK(d4 && d3 && d4[8] == 4 && d4[9] == 0 && d4[10] == 0 && d3[8] == 2, "their headers say 4.0 and 2.0");
    vsv_file *f4 = NULL, *f3 = NULL;
    int ok = d4 && d3 && !vsv_file_open_mem(d4, n4, "rice4.vsv", &f4) && !vsv_file_open_mem(d3, n3, "rice3.vsv", &f3);
    CHECK(ok && vsv_file_check(f4, NULL, NULL) == 0, "the format-4 file checks", "%s", ok ? vsv_file_error(f4) : "");
    int kinds[8] = {0};
    for (int t = 0; t < NT && ok; t++)
        for (int s = 0; s < NS; s++)
            for (int b = 0; b < 3 * 2 * 2; b++) {
                const int k = vsv_file_brick_kind(f4, t, s, b);
                if (k >= 0 && k < 8)
                    kinds[k]++;
            }
    CHECK(kinds[VSV_BRICK_ABS3R] > 0 && kinds[VSV_BRICK_DELTA3R] > 0 && kinds[VSV_BRICK_EMPTY] > 0,
          "the noisy field takes ABS3R and DELTA3R, the sparse one keeps EMPTY bricks",
          "(ABS %d DELTA %d ABS3 %d DELTA3 %d ABS3R %d DELTA3R %d EMPTY %d)", kinds[2], kinds[3], kinds[4], kinds[5],
          kinds[6], kinds[7], kinds[0]);
    CHECK(n4 < n3, "the format-4 file is smaller", "%zu vs %zu bytes", n4, n3);
    if (ok)
        compare(f4, f3, d4, n4, NT, NS, n);

    /* a Rice payload changed under a valid checksum: an error naming it */
    vsv_file_free(f4);
    f4 = NULL;
    int hit = 0;
    for (int b = 0; b < 12 && ok && !hit; b++) {
        vsv_file *g = NULL;
        vsv_file_open_mem(d4, n4, "rice4.vsv", &g);
        if (vsv_file_brick_kind(g, 1, 0, b) != VSV_BRICK_DELTA3R) {
            vsv_file_free(g);
            continue;
        }
        /* chunk 1's entry of brick b: find its payload through the table (SPEC.md §5) */
        const uint64_t c1 = vsv_rd64(d4 + vsv_rd64(d4 + 48) + 24);
        vsv_layout L;
        vsv_layout_init(&L, NX, NY, NZ, 16);
        unsigned char *e = d4 + c1 + VSV_CHUNK_HEADER_SIZE + L.octree_bytes + (size_t)b * VSV_BRICK_ENTRY_SIZE;
        unsigned char *p = d4 + c1 + vsv_rd64(e + 8);
        const uint32_t size = vsv_rd32(e + 16);
        vsv_wr32(p + VSV_RICE_CONTEXTS, vsv_rd32(p + VSV_RICE_CONTEXTS) + 1); /* stream 0 a byte longer */
        vsv_wr32(e + 4, vsv_crc32c(0, p, size));
        uint32_t crc = vsv_crc32c(0, d4 + c1, 28); /* the chunk index's checksum again */
        crc = vsv_crc32c(crc, d4 + c1 + VSV_CHUNK_HEADER_SIZE, (size_t)NS * L.species_index_bytes);
        vsv_wr32(d4 + c1 + 28, crc);
        vsv_file_free(g);
        vsv_file_open_mem(d4, n4, "rice4.vsv", &g);
        vsv_decoder *x = NULL;
        float *a = malloc(n * sizeof *a);
        const int rc = vsv_decoder_create(g, &x) ? -1 : vsv_decoder_volume(x, 1, 0, a);
        CHECK(rc == VSV_ECODEC && strstr(vsv_decoder_error(x), "payload does not decode"),
              "a Rice payload changed under a valid checksum: VSV_ECODEC, the brick named", "rc %d: %s", rc,
              x ? vsv_decoder_error(x) : "");
        free(a);
        vsv_decoder_free(x);
        vsv_file_free(g);
        hit = 1;
    }
    CHECK(hit, "a DELTA3R brick at step 1 to damage");
    vsv_file_free(f3);
    free(d4);
    free(d3);
    unlink(p4);
    unlink(p3);
    for (int t = 0; t < NT; t++)
        free(v[t]);
    vsv_meta_clear(&m);
}

int main(void)
{
    test_coder();
    test_file();
    return vsv_test_done();
}
