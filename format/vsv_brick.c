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

/* Residuals of the brick's cells inside the grid (ext[0] x ext[1] x ext[2] of
 * the B^3 array), in storage order: ABS predicts each code from the previous
 * one, DELTA from the same cell one step earlier; both in wrapping bits-wide
 * arithmetic, then zigzag, then (16 bit) all low bytes before all high bytes
 * so the mostly-zero high bytes compress to almost nothing. (A 3-D Lorenzo
 * predictor was measured on the real series in ../shared/data: within ±3 %
 * of this size, and slower to decode.) */
void vsv_brick_forward(int bits, int kind, const uint16_t *cur, const uint16_t *prev, int B, const int ext[3],
                       unsigned char *out)
{
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

void vsv_brick_inverse(int bits, int kind, const unsigned char *in, int B, const int ext[3], uint16_t *state)
{
    const size_t n = (size_t)ext[0] * ext[1] * ext[2];
    const unsigned char *lo = in, *hi = in + n;
    if (kind == VSV_BRICK_DELTA) {
        for (int k = 0; k < ext[2]; k++)
            for (int j = 0; j < ext[1]; j++) {
                uint16_t *row = state + ((size_t)k * B + j) * B;
                if (bits == 8) {
                    for (int i = 0; i < ext[0]; i++) {
                        const unsigned z = lo[i];
                        row[i] = (uint16_t)((row[i] + ((z >> 1) ^ (0u - (z & 1)))) & 0xffu);
                    }
                } else {
                    for (int i = 0; i < ext[0]; i++) {
                        const uint16_t z = (uint16_t)(lo[i] | (hi[i] << 8));
                        row[i] = (uint16_t)(row[i] + (uint16_t)((z >> 1) ^ (uint16_t)(0u - (z & 1))));
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
