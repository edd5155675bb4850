/* vsv_brick.c — a brick's payload before compression (SPEC.md): packed
 * codes, as a keyframe or as a delta against the previous step. */
#include "vsv_format_internal.h"

#include <stdlib.h>
#include <string.h>

size_t vsv_brick_raw_bytes(int bits, const int ext[3])
{
    const size_t n = (size_t)ext[0] * ext[1] * ext[2];
    return bits == 8 ? n : 2 * n;
}

/* The value the 3-D (Lorenzo) kinds code at cell (i, j, k): the code (ABS3)
 * or its change from the step before (DELTA3), wrapping; 0 outside the box. */
static unsigned field(const uint16_t *cur, const uint16_t *prev, int B, int i, int j, int k)
{
    if (i < 0 || j < 0 || k < 0)
        return 0;
    const size_t at = ((size_t)k * B + j) * B + (size_t)i;
    return prev ? (unsigned)cur[at] - prev[at] : cur[at];
}

/* The 3-D kinds: each value predicted from its seven neighbours already
 * coded (the corner of the cube below it: x + y + z - xy - xz - yz + xyz,
 * the Lorenzo predictor, exact on any trilinear field). */
static void forward3(int bits, const uint16_t *cur, const uint16_t *prev, int B, const int ext[3], unsigned char *out)
{
    const size_t n = (size_t)ext[0] * ext[1] * ext[2];
    const unsigned mask = bits == 8 ? 0xffu : 0xffffu, sh = (unsigned)bits - 1;
    size_t m = 0;
    for (int k = 0; k < ext[2]; k++)
        for (int j = 0; j < ext[1]; j++)
            for (int i = 0; i < ext[0]; i++, m++) {
#define F(a, b, c) field(cur, prev, B, a, b, c)
                const unsigned p = F(i - 1, j, k) + F(i, j - 1, k) + F(i, j, k - 1) - F(i - 1, j - 1, k) -
                                   F(i - 1, j, k - 1) - F(i, j - 1, k - 1) + F(i - 1, j - 1, k - 1);
                const unsigned r = (F(i, j, k) - p) & mask;
#undef F
                const unsigned z = ((r << 1) ^ (0u - (r >> sh))) & mask;
                out[m] = (unsigned char)z;
                if (bits == 16)
                    out[n + m] = (unsigned char)(z >> 8);
            }
}

/* Residuals of the brick's cells inside the grid (ext[0] x ext[1] x ext[2] of
 * the B^3 array), in storage order: ABS predicts each code from the previous
 * one, DELTA from the same cell one step earlier, ABS3 and DELTA3 the code or
 * its change from the seven neighbours before it; all in wrapping bits-wide
 * arithmetic, then zigzag, then (16 bit) all low bytes before all high bytes
 * so the mostly-zero high bytes compress to almost nothing. */
void vsv_brick_forward(int bits, int kind, const uint16_t *cur, const uint16_t *prev, int B, const int ext[3],
                       unsigned char *out)
{
    if (kind == VSV_BRICK_ABS3 || kind == VSV_BRICK_DELTA3) {
        forward3(bits, cur, kind == VSV_BRICK_DELTA3 ? prev : NULL, B, ext, out);
        return;
    }
    const size_t n = (size_t)ext[0] * ext[1] * ext[2];
    const unsigned mask = bits == 8 ? 0xffu : 0xffffu, sh = (unsigned)bits - 1;
    unsigned last = 0;
    size_t m = 0;
    for (int k = 0; k < ext[2]; k++)
        for (int j = 0; j < ext[1]; j++) {
            const size_t row = ((size_t)k * B + j) * B;
            for (int i = 0; i < ext[0]; i++, m++) {
                const unsigned c = cur[row + i];
                const unsigned p = kind == VSV_BRICK_DELTA ? prev[row + i] : last;
                const unsigned r = (c - p) & mask;
                const unsigned z = ((r << 1) ^ (0u - (r >> sh))) & mask;
                out[m] = (unsigned char)z;
                if (bits == 16)
                    out[n + m] = (unsigned char)(z >> 8);
                last = c;
            }
        }
}

/* The 3-D kinds decoded row by row: with T = up + back - up-back (the rows
 * at j - 1, k - 1 and both, zero outside the box), the value is x[i] =
 * r[i] + x[i - 1] + T[i] - T[i - 1]: T and the differences a row at a time
 * (vectorised), then one running sum. In uint16 arithmetic (mod 2^16; 8-bit
 * values are masked as each row is done, which leaves every later sum right
 * mod 2^8). The residuals come from the planes in (z16 NULL) or from z16, a
 * value a cell. The values land in out (a B^3 array); ABS3 decodes into the
 * state itself, DELTA3 into scratch (the rebuilt differences are the next
 * rows' neighbours), each row added to the state while it is in cache. */
static inline __attribute__((always_inline)) void inverse3(int bits, const unsigned char *in, const uint16_t *z16,
                                                           int B, const int ext[3], uint16_t *out, uint16_t *add,
                                                           int undo)
{
    const size_t n = (size_t)ext[0] * ext[1] * ext[2];
    const unsigned char *lo = in, *hi = in + n;
    const int ex = ext[0];
    const uint16_t mask = bits == 8 ? 0xffu : 0xffffu;
    uint16_t zero[64], t[65], d[64];
    memset(zero, 0, sizeof zero);
    for (int k = 0; k < ext[2]; k++)
        for (int j = 0; j < ext[1]; j++) {
            const size_t at = ((size_t)k * B + j) * B;
            uint16_t *row = out + at;
            const uint16_t *up = j ? row - B : zero, *back = k ? row - (size_t)B * B : zero;
            const uint16_t *ub = j && k ? row - B - (size_t)B * B : zero;
            t[0] = 0;
            for (int i = 0; i < ex; i++)
                t[i + 1] = (uint16_t)(up[i] + back[i] - ub[i]);
            if (z16) {
                for (int i = 0; i < ex; i++) {
                    const unsigned z = z16[i];
                    d[i] = (uint16_t)(((z >> 1) ^ (0u - (z & 1))) + t[i + 1] - t[i]);
                }
                z16 += ex;
            } else if (bits == 8) {
                for (int i = 0; i < ex; i++) {
                    const unsigned z = lo[i];
                    d[i] = (uint16_t)(((z >> 1) ^ (0u - (z & 1))) + t[i + 1] - t[i]);
                }
            } else {
                for (int i = 0; i < ex; i++) {
                    const unsigned z = (unsigned)lo[i] | (unsigned)hi[i] << 8;
                    d[i] = (uint16_t)(((z >> 1) ^ (0u - (z & 1))) + t[i + 1] - t[i]);
                }
                hi += ex;
            }
            lo += ex;
            uint16_t x = 0;
            for (int i = 0; i < ex; i++)
                d[i] = x = (uint16_t)(x + d[i]);
            for (int i = 0; i < ex; i++)
                row[i] = d[i] & mask;
            if (add) {
                uint16_t *st = add + at;
                if (undo)
                    for (int i = 0; i < ex; i++)
                        st[i] = (uint16_t)((st[i] - d[i]) & mask);
                else
                    for (int i = 0; i < ex; i++)
                        st[i] = (uint16_t)((st[i] + d[i]) & mask);
            }
        }
}

VSV_CLONES("avx2")
void vsv_brick_inverse_z(int bits, int kind, const uint16_t *z, int B, const int ext[3], uint16_t *state,
                         uint16_t *scratch, int undo)
{
    if (kind == VSV_BRICK_ABS3)
        inverse3(bits, NULL, z, B, ext, state, NULL, 0);
    else
        inverse3(bits, NULL, z, B, ext, scratch, state, undo);
}

VSV_CLONES("avx2")
void vsv_brick_inverse(int bits, int kind, const unsigned char *in, int B, const int ext[3], uint16_t *state,
                       uint16_t *scratch, int undo)
{
    if (kind == VSV_BRICK_ABS3 || kind == VSV_BRICK_DELTA3) {
        if (kind == VSV_BRICK_ABS3)
            inverse3(bits, in, NULL, B, ext, state, NULL, 0);
        else
            inverse3(bits, in, NULL, B, ext, scratch, state, undo);
        return;
    }
    const size_t n = (size_t)ext[0] * ext[1] * ext[2];
    const unsigned char *lo = in, *hi = in + n;
    if (kind == VSV_BRICK_DELTA) {            /* undo: the residuals subtracted (wrapping) */
        const unsigned neg = undo ? ~0u : 0u; /* (r ^ neg) - neg: -r when undoing */
        for (int k = 0; k < ext[2]; k++)
            for (int j = 0; j < ext[1]; j++) {
                uint16_t *row = state + ((size_t)k * B + j) * B;
                if (bits == 8) {
                    for (int i = 0; i < ext[0]; i++) {
                        const unsigned z = lo[i], r = (z >> 1) ^ (0u - (z & 1));
                        row[i] = (uint16_t)((row[i] + ((r ^ neg) - neg)) & 0xffu);
                    }
                } else {
                    for (int i = 0; i < ext[0]; i++) {
                        const uint16_t z = (uint16_t)(lo[i] | (hi[i] << 8));
                        const uint16_t r = (uint16_t)((z >> 1) ^ (uint16_t)(0u - (z & 1)));
                        row[i] = (uint16_t)(row[i] + (uint16_t)((r ^ neg) - neg));
                    }
                    hi += ext[0];
                }
                lo += ext[0];
            }
        return;
    }
    unsigned acc = 0;
    const unsigned mask = bits == 8 ? 0xffu : 0xffffu;
    for (int k = 0; k < ext[2]; k++)
        for (int j = 0; j < ext[1]; j++) {
            uint16_t *row = state + ((size_t)k * B + j) * B;
            for (int i = 0; i < ext[0]; i++) {
                const unsigned z = bits == 8 ? lo[i] : (unsigned)(lo[i] | (hi[i] << 8));
                acc = (acc + ((z >> 1) ^ (0u - (z & 1)))) & mask;
                row[i] = (uint16_t)acc;
            }
            lo += ext[0];
            if (bits == 16)
                hi += ext[0];
        }
}
