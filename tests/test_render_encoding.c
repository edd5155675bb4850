/* test_render_encoding.c — the render layer's values in and out: the
 * transfer-function text (parse, format, refusals with their line, the
 * fuzzer's infinite ranges), the shear-warp's half floats, table and warp,
 * and EXR frames read back with OpenEXR's own C API. */
#include "vsv_render.h"
#include "vsv_sw.h"
#include "vsv_testlib.h"

#include <math.h>
#include <openexr.h>
#include <stdio.h>
#include <string.h>

/* The shear-warp's half floats: exact at the ends of the range, rounded to
 * nearest, within half a unit in the last place everywhere. */
static void test_half(void)
{
    CHECK(vsv_half(0) == 0 && vsv_half(1) == 0x3C00 && vsv_half(0.5f) == 0x3800 && vsv_half(65504) == 0x7BFF &&
              vsv_half(1e9f) == 0x7BFF && vsv_half(0x1p-14f) == 0x0400 && vsv_half(0x1p-15f) == 0 &&
              vsv_half(1 + 0x1p-11f + 0x1p-20f) == 0x3C01 && vsv_half(1 + 0x1p-11f - 0x1p-20f) == 0x3C00 &&
              vsv_half_float(0) == 0 && vsv_half_float(0x0400) == 0x1p-14f && vsv_half_float(0x7BFF) == 65504,
          "half floats: exact values, rounding to nearest, nothing below 2^-14");
    double worst = 0;
    for (float f = 0x1p-14f; f < 65000; f *= 1.0007f) {
        const float back = vsv_half_float(vsv_half(f));
        worst = fmax(worst, fabs(back - (double)f) / (f * 0x1p-11)); /* half an ulp: 2^-11 relative */
    }
    CHECK(worst <= 1.0001, "half floats: every value within half a unit in the last place", "worst %g", worst);
}

/* The shear-warp's classification table: every entry the species rule at
 * its position, worked out here one at a time, bit for bit; over colour
 * maps, opacity ramps and opacities that reach the half floats' top
 * (65504) and fall below their smallest normal (2^-14, then 0). */
static void test_sw_table(void)
{
    static const char *const text[] = {"colormap clouds\nrange 0 1\nopacity 0 0.1 0.5 1\n",
                                       "colormap magma\nrange 0 1\nopacity 1 0 0 0.3 0.7\n",
                                       "colormap greys\nrange 0 1\nopacity 0.02 0.02\n"};
    static const float ops[] = {1, 1e-3f, 3e-5f, 300, 1e5f};
    static uint64_t t[VSV_SW_NTAB];
    long bad = 0, nonzero = 0, top = 0;
    for (size_t n = 0; n < sizeof text / sizeof *text; n++) {
        vsv_tf tf;
        char msg[128];
        if (!CHECK(vsv_tf_parse(&tf, text[n], msg, sizeof msg) == 0, "table: transfer function parses", "%s", msg))
            return;
        for (size_t j = 0; j < sizeof ops / sizeof *ops; j++) {
            vsv_sw_table(&tf, ops[j], t);
            bad += t[0] != 0;
            for (int i = 0; i < VSV_SW_NTAB - 1; i++) {
                const int x = i / VSV_SW_SUB < VSV_TF_LUT - 1 ? i / VSV_SW_SUB : VSV_TF_LUT - 2;
                const float f = (float)(i - x * VSV_SW_SUB) / VSV_SW_SUB;
                float c[4];
                for (int ch = 0; ch < 4; ch++)
                    c[ch] = tf.lut[x][ch] + (tf.lut[x + 1][ch] - tf.lut[x][ch]) * f;
                const float s = c[3] * ops[j];
                const uint64_t want = s > 0 ? (uint64_t)vsv_half(s * c[0]) | (uint64_t)vsv_half(s * c[1]) << 16 |
                                                  (uint64_t)vsv_half(s * c[2]) << 32 | (uint64_t)vsv_half(s) << 48
                                            : 0;
                bad += t[1 + i] != want;
                nonzero += want != 0;
                top += want >> 48 == 0x7BFF;
            }
        }
    }
    CHECK(bad == 0 && nonzero > 10000 && top > 1000, "the shear-warp's table: every entry the rule at its position",
          "%ld wrong, %ld not 0, %ld at the top", bad, nonzero, top);
}

static void test_tf(void)
{
    vsv_tf tf;
    char msg[128] = "", text[512];
    int rc = vsv_tf_parse(&tf, "kind cloud\ncolormap clouds\nrange 0 0.0006\nscale linear\nopacity 0 0.1 0.5 1\n", msg,
                          sizeof msg);
    CHECK(rc == 0 && !strcmp(tf.colormap, "clouds") && tf.hi == 0.0006 && tf.nopacity == 4, "transfer function parses",
          "%s", msg);
    vsv_tf_format(&tf, text, sizeof text);
    vsv_tf back;
    CHECK(vsv_tf_parse(&back, text, msg, sizeof msg) == 0 && back.hi == tf.hi && back.nopacity == 4 &&
              back.opacity[2] == tf.opacity[2],
          "format then parse gives the same transfer function");
    float rgba[4];
    vsv_tf_eval(&tf, 0.0006f, rgba);
    CHECK(fabsf(rgba[3] - 1) < 1e-6 && rgba[0] > 0.99f, "the top of the range is opaque white for clouds");
    vsv_tf_eval(&tf, NAN, rgba);
    CHECK(rgba[3] == 0, "no data is transparent");
    rc = vsv_tf_parse(&tf, "colormap rainbow\n", msg, sizeof msg);
    CHECK(rc != 0 && strstr(msg, "line 1: unknown colour map"), "an unknown colour map is named with its line", "%s",
          msg);
    rc = vsv_tf_parse(&tf, "range 1 2\nscale log\nopacity 0 2\n", msg, sizeof msg);
    CHECK(rc != 0 && strstr(msg, "line 3"), "opacity outside [0, 1] is refused", "%s", msg);
    /* found by fuzzing (tests/corpus/text/crash-tf-infinite-range): an
     * infinite end made the table position NaN, converted to int */
    rc = vsv_tf_parse(&tf, "colormap magma\nrange 1e-9 1e8400\nscale log\nopacity 0 1\n", msg, sizeof msg);
    CHECK(rc != 0 && strstr(msg, "line 2: range needs finite"), "an infinite range end is refused", "%s", msg);
    rc = vsv_tf_parse(&tf, "colormap magma\nrange -1e308 1e308\nopacity 0 1\n", msg, sizeof msg);
    CHECK(rc != 0 && strstr(msg, "line 2"), "a range whose width overflows is refused", "%s", msg);
    tf.lo = 0, tf.hi = 1, tf.scale = VSV_SCALE_LINEAR, tf.nopacity = 2, tf.opacity[0] = 0, tf.opacity[1] = 1;
    snprintf(tf.colormap, sizeof tf.colormap, "magma");
    vsv_tf_prepare(&tf);
    tf.inv = 0; /* as a range of infinite width made it */
    vsv_tf_eval(&tf, INFINITY, rgba);
    CHECK(rgba[3] == 1, "an infinite value reads as the top of the range");
}

static void test_exr(void)
{
    enum { EW = 37, EH = 23 };
    float rgba[EW * EH * 4], depth[EW * EH];
    for (int i = 0; i < EW * EH; i++) {
        for (int c = 0; c < 4; c++)
            rgba[4 * i + c] = (float)(c + 1) / 8;
        depth[i] = i == 5 ? INFINITY : 1000.0f + i;
    }
    const char *p = vsv_test_tmp("frame.exr");
    char err[256] = "";
    int rc = vsv_exr_write(p, rgba, depth, EW, EH, err, sizeof err);
    CHECK(rc == 0, "an EXR frame is written", "%s", err);
    exr_context_t ctx = NULL;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    int ok = exr_start_read(&ctx, p, &init) == EXR_ERR_SUCCESS;
    const exr_attr_chlist_t *cl = NULL;
    ok = ok && exr_get_channels(ctx, 0, &cl) == EXR_ERR_SUCCESS && cl && cl->num_channels == 5;
    /* channels are stored sorted by name: A B G R Z */
    static const char *want[5] = {"A", "B", "G", "R", "Z"};
    for (int c = 0; ok && c < 5; c++)
        ok &= !strcmp(cl->entries[c].name.str, want[c]) &&
              cl->entries[c].pixel_type == (c < 4 ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT);
    exr_attr_box2i_t dw;
    ok = ok && exr_get_data_window(ctx, 0, &dw) == EXR_ERR_SUCCESS && dw.max.x == EW - 1 && dw.max.y == EH - 1;
    /* decode the first chunk's Z and A */
    exr_chunk_info_t ci;
    exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
    float z[EW * 16], a[EW * 16];
    ok = ok && exr_read_scanline_chunk_info(ctx, 0, 0, &ci) == EXR_ERR_SUCCESS &&
         exr_decoding_initialize(ctx, 0, &ci, &dec) == EXR_ERR_SUCCESS;
    for (int c = 0; ok && c < dec.channel_count; c++) {
        exr_coding_channel_info_t *ch = &dec.channels[c];
        ch->user_data_type = EXR_PIXEL_FLOAT;
        ch->user_bytes_per_element = 4;
        ch->user_pixel_stride = 4;
        ch->user_line_stride = 4 * EW;
        ch->decode_to_ptr = !strcmp(ch->channel_name, "Z")   ? (uint8_t *)z
                            : !strcmp(ch->channel_name, "A") ? (uint8_t *)a
                                                             : NULL;
    }
    ok = ok && exr_decoding_choose_default_routines(ctx, 0, &dec) == EXR_ERR_SUCCESS &&
         exr_decoding_run(ctx, 0, &dec) == EXR_ERR_SUCCESS;
    ok = ok && z[0] == 1000.0f && z[7] == 1007.0f && isinf(z[5]) && a[3] == 0.5f;
    exr_decoding_destroy(ctx, &dec);
    exr_finish(&ctx);
    CHECK(ok, "the EXR reads back with R G B A half and Z float, values intact");
}

/* The shear-warp's warp for parallel rays: each pixel the bilinear blend
 * of the intermediate image at its point, clamped into the empty border,
 * against the blend worked out here in double; random pixels (a blend
 * that confused the two fractions or the taps would miss), rows crossing
 * the border and running past it, both builds (AVX2 where the CPU has it). */
static void test_sw_warp(void)
{
    enum { w = 37, h = 23, W = w + 3, N = 120 };
    static float img[4 * W * (h + 3)], out[4 * N];
    unsigned r = 12345;
    for (int y = 1; y <= h; y++)
        for (int x = 1; x <= w; x++)
            for (int ch = 0; ch < 4; ch++) {
                r = r * 1103515245u + 12345u;
                img[4 * (y * W + x) + ch] = (float)(r >> 8) * 0x1p-24f;
            }
    static const double rows[][4] = {
        {-3, 17.3, 0.37, -0.11}, {2.5, -2, 0.05, 0.29}, {40, 30, -0.41, -0.26}, {1.25, 7.75, 0.5, 0}};
    const int simd = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") && __builtin_cpu_supports("f16c");
    for (int build = 0; build < 1 + simd; build++) {
        double worst = 0;
        for (size_t k = 0; k < sizeof rows / sizeof *rows; k++) {
            const double *q = rows[k];
            (build ? vsv_sw_par_warp_avx2 : vsv_sw_par_warp)(img, W, w, h, q[0], q[1], q[2], q[3], 3, N - 5, out);
            for (int px = 3; px <= N - 5; px++) {
                double x = q[0] + px * q[2], y = q[1] + px * q[3];
                x = !(x > 0) ? 0 : x < w + 1 ? x : w + 1;
                y = !(y > 0) ? 0 : y < h + 1 ? y : h + 1;
                const int xi = (int)x, yi = (int)y;
                const double fx = x - xi, fy = y - yi;
                for (int ch = 0; ch < 4; ch++) {
                    const float *t = img + 4 * (yi * W + xi) + ch;
                    const double want =
                        (1 - fy) * ((1 - fx) * t[0] + fx * t[4]) + fy * ((1 - fx) * t[4 * W] + fx * t[4 * W + 4]);
                    worst = fmax(worst, fabs(out[4 * px + ch] - want));
                }
            }
        }
        CHECK(worst < 1e-5,
              build ? "the shear-warp's warp (AVX2): every pixel the bilinear blend at its point, clamped"
                    : "the shear-warp's warp: every pixel the bilinear blend at its point, clamped",
              "off by %g", worst);
    }
}

int main(void)
{
    test_exr();
    test_half();
    test_sw_table();
    test_sw_warp();
    test_tf();
    return vsv_test_done();
}
