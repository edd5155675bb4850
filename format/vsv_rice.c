/* vsv_rice.c — the payload of the Rice-coded 3-D kinds (SPEC.md §7 "Rice
 * coding"): the zigzagged residuals of ABS3 or DELTA3, each coded with a
 * Golomb-Rice parameter chosen per context, the context being how large the
 * residuals already coded beside it were (the row before and the plane
 * before, so a row's contexts are known before any of its cells is
 * decoded). */
#include "vsv_format_internal.h"

#include <string.h>

enum { ESCAPE = 8 }; /* a quotient this large stores the value itself: a code is at most 24 bits */

/* The bit length of t (t < 2^24) through a float's exponent. */
static inline unsigned char bit_length(int32_t t)
{
    const float f = (float)t;
    int32_t e;
    memcpy(&e, &f, sizeof e);
    e = (e >> 23) - 126;
    return (unsigned char)(e > 0 ? e : 0);
}

/* The contexts of row (j, k) of the box of residuals z (a value a cell):
 * the bit length of z(i-1, j-1) + 2 z(i, j-1) + z(i+1, j-1) + 2 z(i, j,
 * k-1), 0 outside; the row's ends apart, so the middle is one loop of loads
 * and adds (vectorised). */
static inline __attribute__((always_inline)) void row_contexts(const uint16_t *z, const int ext[3], int j, int k,
                                                               unsigned char *q)
{
    static const uint16_t none[64];
    const int ex = ext[0];
    const size_t m0 = ((size_t)k * ext[1] + j) * ex;
    const uint16_t *u = j ? z + m0 - ex : none, *b = k ? z + m0 - (size_t)ex * ext[1] : none;
    if (ex == 1) {
        q[0] = bit_length(2 * u[0] + 2 * b[0]);
        return;
    }
    q[0] = bit_length(2 * u[0] + u[1] + 2 * b[0]);
    for (int i = 1; i < ex - 1; i++)
        q[i] = bit_length(u[i - 1] + 2 * u[i] + u[i + 1] + 2 * b[i]);
    q[ex - 1] = bit_length(u[ex - 2] + 2 * u[ex - 1] + 2 * b[ex - 1]);
}

static unsigned code_bits(int bits, unsigned z, unsigned k)
{
    const unsigned u = z >> k;
    return u < ESCAPE ? u + 1 + k : ESCAPE + (unsigned)bits;
}

typedef struct {
    unsigned char *p, *end;
    uint64_t acc;
    int n; /* bits in acc */
} writer;

/* Appends the low `count` bits of v (count <= 32), least significant first;
 * 0, or -1 when the output would pass its end. */
static int put(writer *w, uint64_t v, int count)
{
    w->acc |= v << w->n;
    w->n += count;
    while (w->n >= 8) {
        if (w->p == w->end)
            return -1;
        *w->p++ = (unsigned char)w->acc;
        w->acc >>= 8;
        w->n -= 8;
    }
    return 0;
}

/* Every cell's context into ctx (n bytes), and each context's parameter into
 * kk: the one of the fewest bits over its cells. */
static void choose(int bits, const int ext[3], const uint16_t *z, unsigned char *ctx, unsigned char *kk)
{
    uint64_t cost[VSV_RICE_CONTEXTS][17];
    memset(cost, 0, sizeof cost);
    for (int k = 0; k < ext[2]; k++)
        for (int j = 0; j < ext[1]; j++) {
            const size_t m0 = ((size_t)k * ext[1] + j) * ext[0];
            unsigned char *q = ctx + m0;
            row_contexts(z, ext, j, k, q);
            for (int i = 0; i < ext[0]; i++)
                for (int r = 0; r <= bits; r++)
                    cost[q[i]][r] += code_bits(bits, z[m0 + i], (unsigned)r);
        }
    for (int c = 0; c < VSV_RICE_CONTEXTS; c++) {
        int best = 0;
        for (int r = 1; r <= bits; r++)
            if (cost[c][r] < cost[c][best])
                best = r;
        kk[c] = (unsigned char)best;
    }
}

/* Stream s of the payload (the cells i of every row with i mod 4 = s) at
 * w, which ends where the output does; 0, or -1 when it does not fit. */
static int put_stream(int bits, const int ext[3], const uint16_t *zs, const unsigned char *ctx, const unsigned char *kk,
                      int s, writer *w)
{
    for (int k = 0; k < ext[2]; k++)
        for (int j = 0; j < ext[1]; j++) {
            const size_t m0 = ((size_t)k * ext[1] + j) * ext[0];
            for (int i = s; i < ext[0]; i += VSV_RICE_STREAMS) {
                const unsigned z = zs[m0 + i], r = kk[ctx[m0 + i]], u = z >> r;
                const int bad = u < ESCAPE ? put(w, 1u << u, (int)u + 1) || put(w, z & ((1u << r) - 1), (int)r)
                                           : put(w, 0, ESCAPE) || put(w, z, bits);
                if (bad)
                    return -1;
            }
        }
    return w->n ? put(w, 0, 8 - w->n) : 0;
}

size_t vsv_rice_encode(int bits, const int ext[3], const unsigned char *planes, void *scratch, unsigned char *out,
                       size_t cap)
{
    const size_t head = VSV_RICE_CONTEXTS + 4 * (VSV_RICE_STREAMS - 1);
    if (cap < head)
        return 0;
    const size_t n = (size_t)ext[0] * ext[1] * ext[2];
    uint16_t *const z = scratch; /* the residuals a value a cell, as the decoder has them */
    unsigned char *const ctx = (unsigned char *)(z + n);
    for (size_t m = 0; m < n; m++)
        z[m] = (uint16_t)(bits == 8 ? planes[m] : planes[m] | planes[n + m] << 8);
    choose(bits, ext, z, ctx, out);
    writer w = {out + head, out + cap, 0, 0};
    for (int s = 0; s < VSV_RICE_STREAMS; s++) {
        unsigned char *start = w.p;
        if (put_stream(bits, ext, z, ctx, out, s, &w))
            return 0;
        if (s < VSV_RICE_STREAMS - 1)
            vsv_wr32(out + VSV_RICE_CONTEXTS + 4 * s, (uint32_t)(w.p - start));
    }
    return (size_t)(w.p - out);
}

/* Whether stream t (bytes [at[t], at[t + 1]) of s) ended where it should:
 * read up to its last byte, the bits after its last code zero. */
static int stream_done(const unsigned char *s, const size_t at[VSV_RICE_STREAMS + 1], int t, uint64_t pos)
{
    if (pos > 8 * (uint64_t)at[t + 1] || (pos + 7) / 8 != at[t + 1])
        return 0;
    return !(pos & 7) || !(s[pos >> 3] >> (pos & 7));
}

/* The next code of stream s at bit *pos (Rice parameter k), *pos moved past
 * it. Each stream's position is all its state: four of them side by side
 * are four chains of a load, a count and two shifts. */
static inline __attribute__((always_inline)) uint64_t take(int bits, const unsigned char *s, uint64_t *pos, unsigned k)
{
    const uint64_t b = vsv_rd64(s + (*pos >> 3)) >> (*pos & 7); /* 57 bits; a code has at most 24 */
    const unsigned u = (unsigned)__builtin_ctzll(b | 1ull << 63);
    uint64_t z;
    unsigned used;
    if (u < ESCAPE) {
        z = (uint64_t)u << k | ((b >> (u + 1)) & ((1u << k) - 1));
        used = u + 1 + k;
    } else {
        z = (b >> ESCAPE) & (bits == 8 ? 0xffu : 0xffffu);
        used = ESCAPE + (unsigned)bits;
    }
    *pos += used;
    return z;
}

static inline __attribute__((always_inline)) int decode(int bits, const int ext[3], const unsigned char *in,
                                                        const size_t at[VSV_RICE_STREAMS + 1], uint16_t *z)
{
    const uint64_t mask = bits == 8 ? 0xffu : 0xffffu;
    const unsigned char *s = in + VSV_RICE_CONTEXTS + 4 * (VSV_RICE_STREAMS - 1);
    uint64_t p0 = 8 * (uint64_t)at[0], p1 = 8 * (uint64_t)at[1], p2 = 8 * (uint64_t)at[2], p3 = 8 * (uint64_t)at[3];
    unsigned char q[64];
    const int ex = ext[0], ey = ext[1], ez = ext[2];
    uint64_t seen = 0;
    for (int k = 0; k < ez; k++)
        for (int j = 0; j < ey; j++) {
            row_contexts(z, ext, j, k, q);
            for (int i = 0; i < ex; i++) /* each cell's parameter */
                q[i] = in[q[i]];
            uint16_t *const r = z + ((size_t)k * ey + j) * ex;
            int i = 0;
            for (; i + VSV_RICE_STREAMS <= ex; i += VSV_RICE_STREAMS) {
                const uint64_t z0 = take(bits, s, &p0, q[i]), z1 = take(bits, s, &p1, q[i + 1]);
                const uint64_t z2 = take(bits, s, &p2, q[i + 2]), z3 = take(bits, s, &p3, q[i + 3]);
                seen |= z0 | z1 | z2 | z3;
                r[i] = (uint16_t)z0, r[i + 1] = (uint16_t)z1, r[i + 2] = (uint16_t)z2, r[i + 3] = (uint16_t)z3;
            }
            for (; i < ex; i++) { /* a row's last cells, fewer than four */
                uint64_t *pos = i % 4 == 0 ? &p0 : i % 4 == 1 ? &p1 : &p2;
                const uint64_t v = take(bits, s, pos, q[i]);
                seen |= v;
                r[i] = (uint16_t)v;
            }
            /* a valid stream's reads end within 8 bytes of its end; a row
             * reads at most 3 bytes a code past that (VSV_RICE_PAD) */
            if (p0 > 8 * (uint64_t)at[1] + 64 || p1 > 8 * (uint64_t)at[2] + 64 || p2 > 8 * (uint64_t)at[3] + 64 ||
                p3 > 8 * (uint64_t)at[4] + 64)
                return -1;
        }
    const int ok = !(seen & ~mask) && stream_done(s, at, 0, p0) && stream_done(s, at, 1, p1) &&
                   stream_done(s, at, 2, p2) && stream_done(s, at, 3, p3);
    return ok ? 0 : -1;
}

/* BMI2's shifts where the CPU has them (picked at run time): the chain from
 * one code to the next of a stream is a count and two shifts. */
VSV_CLONES("arch=x86-64-v3")
int vsv_rice_decode(int bits, const int ext[3], const unsigned char *in, size_t size, uint16_t *z)
{
    const size_t head = VSV_RICE_CONTEXTS + 4 * (VSV_RICE_STREAMS - 1);
    if (size < head)
        return -1;
    for (int c = 0; c < VSV_RICE_CONTEXTS; c++)
        if (in[c] > bits)
            return -1;
    size_t at[VSV_RICE_STREAMS + 1] = {0}; /* where each stream starts, from the first's start */
    for (int t = 0; t < VSV_RICE_STREAMS - 1; t++) {
        at[t + 1] = at[t] + vsv_rd32(in + VSV_RICE_CONTEXTS + 4 * t);
        if (at[t + 1] > size - head)
            return -1;
    }
    at[VSV_RICE_STREAMS] = size - head;
    return bits == 8 ? decode(8, ext, in, at, z) : decode(16, ext, in, at, z);
}
