/* vsv_sw_table.c — the shear-warp's tables, in vectors: a layer's
 * classification at every position of its table (vsv_sw_table), and
 * values to their positions (vsv_sw_positions), the classification of a
 * brick when one layer is shown. */
#include "vsv_sw.h"

#include <stdint.h>
#include <string.h>

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_THREAD__)
#define SW_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define SW_CLONES
#endif

typedef float sw_v8f __attribute__((vector_size(32)));
typedef int32_t sw_v8i __attribute__((vector_size(32)));
typedef uint32_t sw_v8u __attribute__((vector_size(32)));

/* *h = vsv_half of eight floats *f */
static inline void half8(const sw_v8f *f, sw_v8u *h)
{
    sw_v8u u;
    memcpy(&u, f, sizeof u);
    const sw_v8u big = (sw_v8u)(u >= 0x477FE000u), small = (sw_v8u)(u < 0x38800000u);
    *h = (((u - 0x38000000u + 0x1000u) >> 13 & ~big) | (0x7BFFu & big)) & ~small;
}

/* (Each function built for AVX2 too, the one the CPU can run picked at
 * load.) */
SW_CLONES
void vsv_sw_table(const vsv_tf *tf, float o, uint64_t *t)
{
    t[0] = 0;
    for (int x = 0; x < VSV_TF_LUT - 1; x++) /* entries 1 + 16 x + k, k = 0 .. 15, in two vectors */
        for (int half = 0; half < 2; half++) {
            const float *a = tf->lut[x], *b = tf->lut[x + 1];
            sw_v8f f, c[4];
            for (int k = 0; k < 8; k++)
                f[k] = (float)(8 * half + k) / VSV_SW_SUB;
            for (int ch = 0; ch < 4; ch++)
                c[ch] = a[ch] + (b[ch] - a[ch]) * f;
            const sw_v8f s = c[3] * o, sr = s * c[0], sg = s * c[1], sb = s * c[2]; /* in units of sigma_unit / scale */
            const sw_v8u on = (sw_v8u)(s > 0);
            sw_v8u r, g, bl, e;
            half8(&sr, &r), half8(&sg, &g), half8(&sb, &bl), half8(&s, &e);
            /* entry k: red | green << 16 (rg[k]) | blue << 32 | extinction << 48 (be[k]) */
            const sw_v8u rg = (r | g << 16) & on, be = (bl | e << 16) & on;
            const sw_v8u lo = __builtin_shuffle(rg, be, (sw_v8u){0, 8, 1, 9, 2, 10, 3, 11});
            const sw_v8u hi = __builtin_shuffle(rg, be, (sw_v8u){4, 12, 5, 13, 6, 14, 7, 15});
            uint64_t *const out = t + 1 + VSV_SW_SUB * x + 8 * half;
            memcpy(out, &lo, sizeof lo);
            memcpy(out + 4, &hi, sizeof hi);
        }
    const float *a = tf->lut[VSV_TF_LUT - 1], s = a[3] * o; /* the last: the table's end */
    t[VSV_SW_NTAB - 1] = s > 0 ? (uint64_t)vsv_half(s * a[0]) | (uint64_t)vsv_half(s * a[1]) << 16 |
                                     (uint64_t)vsv_half(s * a[2]) << 32 | (uint64_t)vsv_half(s) << 48
                               : 0;
}

SW_CLONES
void vsv_sw_positions(const float *v, const float *x, int n, float lo, float base, float inv, uint16_t *out,
                      vsv_sw_h8 *mn, vsv_sw_h8 *mx)
{
    const sw_v8f zero = {0}, top = zero + (VSV_TF_LUT - 1);
    for (int i = 0; i < n; i += 8, out += 512, mn++, mx++) {
        vsv_sw_h8 h;
        if (n - i >= 8) {
            sw_v8f xv, vv;
            memcpy(&xv, x + i, sizeof xv);
            memcpy(&vv, v + i, sizeof vv);
            sw_v8f p = (xv - base) * inv;
            p = (sw_v8f)((sw_v8i)p & (p > zero));
            const sw_v8i in = p < top;
            p = (sw_v8f)(((sw_v8i)p & in) | ((sw_v8i)top & ~in));
            h = __builtin_convertvector((__builtin_convertvector(p * VSV_SW_SUB + 0.5f, sw_v8i) + 1) & (vv >= lo),
                                        vsv_sw_h8);
            memcpy(out, &h, sizeof h);
        } else { /* the last few; the other lanes repeat the first */
            uint16_t e[8];
            for (int k = 0; k < 8; k++)
                e[k] = vsv_sw_position(v[i + (i + k < n ? k : 0)], x[i + (i + k < n ? k : 0)], lo, base, inv);
            memcpy(out, e, (size_t)(n - i) * sizeof *e);
            memcpy(&h, e, sizeof h);
        }
        const vsv_sw_h8 below = (vsv_sw_h8)(h < *mn), above = (vsv_sw_h8)(h > *mx);
        *mn = (h & below) | (*mn & ~below);
        *mx = (h & above) | (*mx & ~above);
    }
}
