/* vsv_tf_internal.h — transfer functions and sample opacity as both
 * renderers evaluate them, inline. Private to render/. */
#ifndef VSV_TF_INTERNAL_H
#define VSV_TF_INTERNAL_H

#include "vsv_render.h"

#include <math.h>

/* extinction of opacity 1 over one horizontal cell: alpha 0.95 */
#define VSV_SIGMA_PER_CELL 3.0

/* Opacity of a sample: 1 - e^-u = u f(u) with f(u) = (1 - e^-u)/u: below
 * VSV_OPACITY_SMALL (the thin samples of most species) by the first six
 * terms of its series (off by under 5e-8), up to VSV_OPACITY_UMAX read from
 * a table at the nearest entry (off by at most 1.2e-4), 1/u beyond (off by
 * e^-12 = 6e-6): no exponential per sample. */
#define VSV_OPACITY_N 16384
#define VSV_OPACITY_UMAX 12.0f
#define VSV_OPACITY_SMALL 0.25f
extern float vsv_opacity_table[VSV_OPACITY_N + 1];
void vsv_opacity_init(void); /* fills the table once (thread-safe) */
static inline float vsv_opacity_series(float u)
{
    return 1.0f + u * (-1.0f / 2 + u * (1.0f / 6 + u * (-1.0f / 24 + u * (1.0f / 120 + u * (-1.0f / 720)))));
}
static inline float vsv_opacity_per_u(float u)
{
    return u < VSV_OPACITY_SMALL  ? vsv_opacity_series(u)
           : u < VSV_OPACITY_UMAX ? vsv_opacity_table[(int)(u * (VSV_OPACITY_N / VSV_OPACITY_UMAX) + 0.5f)]
                                  : 1 / u;
}
/* The raycaster's: the series by fused multiply-adds (one rounding each,
 * as the sixteen-ray loop's FMA instructions: both loops give the same bits). */
static inline float vsv_rc_opacity_per_u(float u)
{
    if (!(u < VSV_OPACITY_SMALL))
        return vsv_opacity_per_u(u);
    float f = -1.0f / 720;
    f = fmaf(u, f, 1.0f / 120);
    f = fmaf(u, f, -1.0f / 24);
    f = fmaf(u, f, 1.0f / 6);
    f = fmaf(u, f, -1.0f / 2);
    return fmaf(u, f, 1.0f);
}

/* Colour and opacity-curve value of one data value, inline (vsv_tf_eval). */
static inline void vsv_tf_lookup(const vsv_tf *tf, float v, float rgba[4])
{
    if (!(v >= tf->lo)) { /* below the range, or no data (NaN) */
        rgba[0] = rgba[1] = rgba[2] = rgba[3] = 0;
        return;
    }
    double x = ((tf->scale == VSV_SCALE_LOG ? log(v) : (double)v) - tf->base) * tf->inv;
    if (!(x <= VSV_TF_LUT - 1)) /* above the range, or NaN (an infinite value) */
        x = VSV_TF_LUT - 1;
    /* linear interpolation in the table */
    int i = (int)x;
    if (i >= VSV_TF_LUT - 1)
        i = VSV_TF_LUT - 2;
    const float f = (float)(x - i);
    const float *a = tf->lut[i], *b = tf->lut[i + 1];
    for (int c = 0; c < 4; c++)
        rgba[c] = a[c] + (b[c] - a[c]) * f;
}

/* Largest opacity of a transfer function over the values [lo, hi] (a bound:
 * 0 means every value in there is transparent). */
float vsv_tf_max_opacity(const vsv_tf *tf, float lo, float hi);

#endif
