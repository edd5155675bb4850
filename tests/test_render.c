/* test_render.c — the raycaster: the compositing rule (species order,
 * hiding, opacity 0), determinism across thread counts, empty-space skipping
 * within 1/255, agreement with a reference render (small step, no skipping)
 * at PSNR >= 40 dB on synthetic and real MM5 data. Transfer-function text,
 * half floats and EXR frames: test_render_encoding.c. */
#include "vsv_format.h"
#include "vsv_render.h"
#include "vsv_rc.h"
#include "vsv_sw.h"
#include "vsv_synth.h"
#include "vsv_testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

enum { W = 160, H = 120 };

typedef struct world {
    vsv_file *f;
    vsv_decoder *d;
    vsv_volume *vol[8];
    vsv_tf tf[8];
    int n;
} world;

static int load(world *w, const char *path, int step)
{
    memset(w, 0, sizeof *w);
    if (vsv_file_open(path, &w->f) || vsv_decoder_create(w->f, &w->d))
        return -1;
    const vsv_meta *m = vsv_file_meta(w->f);
    w->n = m->nvars < 8 ? m->nvars : 8;
    for (int s = 0; s < w->n; s++) {
        char text[512], msg[128];
        vsv_tf_default(m->vars[s].name, vsv_file_quant(w->f, s), text, sizeof text);
        if (vsv_tf_parse(&w->tf[s], text, msg, sizeof msg) || vsv_volume_create(w->f, &w->vol[s]) ||
            vsv_volume_load(w->vol[s], w->d, step, s))
            return -1;
    }
    return 0;
}

static void unload(world *w)
{
    for (int s = 0; s < w->n; s++)
        vsv_volume_free(w->vol[s]);
    vsv_decoder_free(w->d);
    vsv_file_free(w->f);
}

/* Renders layers (species indices, opacities) into a new image. */
static int g_kind = VSV_RENDER_RAYCAST, g_ortho = 0;

static float *render(world *w, const int *idx, const float *op, int n, int threads, double step, int noskip,
                     float *depth)
{
    vsv_layer layers[8];
    for (int i = 0; i < n; i++)
        layers[i] = (vsv_layer){w->vol[idx[i]], &w->tf[idx[i]], op[i], op[i] >= 0};
    vsv_scene sc = {.meta = vsv_file_meta(w->f), .layers = layers, .nlayers = n, .exaggeration = 0, .show_terrain = 1};
    double mn[3], mx[3];
    sc.exaggeration = 1;
    vsv_scene_bounds(&sc, mn, mx);
    sc.exaggeration = fmax(1, round(0.2 * fmax(mx[0] - mn[0], mx[1] - mn[1]) / (mx[2] - fmin(0, mn[2]))));
    vsv_camera cam;
    vsv_camera_orbit(&cam, &sc, 225, 30, 0, W, H);
    if (g_ortho) {
        vsv_scene_bounds(&sc, mn, mx);
        cam.fov_deg = 0;
        cam.ortho_height = 0.75 * sqrt((mx[0] - mn[0]) * (mx[0] - mn[0]) + (mx[1] - mn[1]) * (mx[1] - mn[1]) +
                                       (mx[2] - mn[2]) * (mx[2] - mn[2]));
    }
    vsv_render_opts o;
    vsv_render_opts_init(&o);
    o.kind = step < 0 ? VSV_RENDER_RAYCAST : g_kind;
    if (step < 0)
        step = -step;
    o.threads = threads;
    o.step_cells = step;
    o.no_skip = noskip;
    vsv_renderer *r = NULL;
    float *img = malloc(sizeof(float) * W * H * 4);
    if (vsv_renderer_create(&o, &r) || vsv_render(r, &sc, &cam, img, depth)) {
        free(img);
        img = NULL;
    }
    vsv_renderer_free(r);
    return img;
}

static double max_diff(const float *a, const float *b)
{
    double m = 0;
    for (int i = 0; i < W * H * 4; i++)
        m = fmax(m, fabs((double)a[i] - b[i]));
    return m;
}

static double psnr(const float *a, const float *ref)
{
    double se = 0;
    for (int i = 0; i < W * H * 4; i++) {
        const double d = fmin(1, fmax(0, a[i])) - fmin(1, fmax(0, ref[i]));
        se += d * d;
    }
    const double mse = se / (W * H * 4);
    return mse > 0 ? 10 * log10(1 / mse) : 999;
}

static double coverage(const float *a)
{
    int n = 0;
    for (int i = 0; i < W * H; i++)
        n += a[4 * i + 3] > 0.01f;
    return (double)n / (W * H);
}

/* which sixteen-ray build the renderer picks here */
static const char *simd_name(void)
{
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512f") ? "AVX-512" : "AVX2";
}

static void rules(const char *label, world *w)
{
    char name[256];
    const int ab[2] = {0, 2}, ba[2] = {2, 0}, a1[1] = {0};
    const float one2[2] = {1, 1}, hide2[2] = {1, -1}, zero2[2] = {1, 0}, one1[1] = {1};
    float *x = render(w, ab, one2, 2, 2, 0.5, 0, NULL), *y = render(w, ba, one2, 2, 2, 0.5, 0, NULL);
    snprintf(name, sizeof name, "%s: swapping species order gives identical pixels", label);
    CHECK(x && y && max_diff(x, y) == 0, name, "%g", x && y ? max_diff(x, y) : -1);
    float *h = render(w, ab, hide2, 2, 2, 0.5, 0, NULL), *rm = render(w, a1, one1, 1, 2, 0.5, 0, NULL);
    float *z = render(w, ab, zero2, 2, 2, 0.5, 0, NULL);
    snprintf(name, sizeof name, "%s: hiding a species equals removing it", label);
    CHECK(h && rm && !memcmp(h, rm, sizeof(float) * W * H * 4), name);
    snprintf(name, sizeof name, "%s: opacity 0 equals hidden", label);
    CHECK(z && rm && !memcmp(z, rm, sizeof(float) * W * H * 4), name);
    snprintf(name, sizeof name, "%s: hiding a species changes the picture", label);
    CHECK(x && h && max_diff(x, h) > 0.01, name);
    float *t1 = render(w, ab, one2, 2, 1, 0.5, 0, NULL);
    snprintf(name, sizeof name, "%s: 1 and 2 threads give identical pixels", label);
    CHECK(t1 && x && !memcmp(t1, x, sizeof(float) * W * H * 4), name);
    setenv("VSV_SIMD", "0", 1); /* the one-ray loop, on any CPU */
    float *one = render(w, ab, one2, 2, 2, 0.5, 0, NULL);
    setenv("VSV_SIMD", "avx2", 1); /* the AVX2 build of the sixteen-ray loop, on a CPU with AVX-512 too */
    float *avx2 = render(w, ab, one2, 2, 2, 0.5, 0, NULL);
    unsetenv("VSV_SIMD");
    snprintf(name, sizeof name, "%s: the sixteen-ray (%s) and one-ray loops give identical pixels", label, simd_name());
    CHECK(one && x && max_diff(one, x) == 0, name, "max diff %g", one && x ? max_diff(one, x) : -1);
    snprintf(name, sizeof name, "%s: the sixteen-ray loop's AVX2 build gives the same pixels too", label);
    CHECK(avx2 && x && max_diff(avx2, x) == 0, name, "max diff %g", avx2 && x ? max_diff(avx2, x) : -1);
    free(one);
    free(avx2);
    float *ns = render(w, ab, one2, 2, 2, 0.5, 1, NULL);
    snprintf(name, sizeof name, "%s: empty-space skipping changes no pixel by more than 1/255", label);
    CHECK(ns && x && max_diff(ns, x) <= 1.0 / 255, name, "max diff %g", ns && x ? max_diff(ns, x) : -1);
    float *ref = render(w, ab, one2, 2, 2, -0.125, 1, NULL);
    const double p = ref && x ? psnr(x, ref) : 0;
    snprintf(name, sizeof name, "%s: raycast vs reference (step 1/8 cell, no skipping) PSNR >= 40 dB", label);
    CHECK(p >= 40, name, "%.1f dB", p);
    printf("  %s: coverage %.0f %%, PSNR vs reference %.1f dB\n", label, 100 * (x ? coverage(x) : 0), p);
    free(x);
    free(y);
    free(h);
    free(rm);
    free(z);
    free(t1);
    free(ns);
    free(ref);
}

/* Shear-warp at a parallel view: the species rule, and agreement with the
 * reference raycaster (step 1/8 cell, no skipping) at PSNR >= 30 dB. */
static void sw_rules_proj(const char *label, world *w, const int *ab, int nab, int ortho)
{
    char name[256];
    g_ortho = ortho;
    g_kind = VSV_RENDER_SHEARWARP;
    int ba[8];
    float ones[8], hide[8];
    for (int i = 0; i < nab; i++) {
        ba[i] = ab[nab - 1 - i];
        ones[i] = 1;
        hide[i] = i == 0 ? -1 : 1;
    }
    float *x = render(w, ab, ones, nab, 2, 0.5, 0, NULL), *y = render(w, ba, ones, nab, 2, 0.5, 0, NULL);
    snprintf(name, sizeof name, "%s shear-warp: swapping species order gives identical pixels", label);
    CHECK(x && y && max_diff(x, y) == 0, name, "%g", x && y ? max_diff(x, y) : -1);
    float *h = render(w, ab, hide, nab, 2, 0.5, 0, NULL), *rm = render(w, ab + 1, ones, nab - 1, 2, 0.5, 0, NULL);
    hide[0] = 0;
    float *z = render(w, ab, hide, nab, 2, 0.5, 0, NULL);
    snprintf(name, sizeof name, "%s shear-warp: hiding a species equals removing it, opacity 0 equals hidden", label);
    CHECK(h && rm && z && max_diff(h, rm) == 0 && max_diff(z, rm) == 0, name);
    float *one = render(w, ab, ones, nab, 1, 0.5, 0, NULL);
    snprintf(name, sizeof name, "%s shear-warp: 1 and 2 threads give identical pixels", label);
    CHECK(one && x && max_diff(one, x) == 0, name);
    free(one);
    if (ortho) { /* the eight-pixel rows built for any x86-64 against the AVX2 build: they differ by rounding only */
        setenv("VSV_SIMD", "0", 1);
        float *generic = render(w, ab, ones, nab, 2, 0.5, 0, NULL);
        unsetenv("VSV_SIMD");
        const double d = generic && x ? max_diff(generic, x) : -1;
        snprintf(name, sizeof name, "%s shear-warp: the AVX2 and the generic rows agree within 1e-5", label);
        CHECK(d >= 0 && d <= 1e-5, name, "max diff %g", d);
        free(generic);
    }
    float *ref = render(w, ab, ones, nab, 2, -0.125, 1, NULL);
    const double p = x && ref ? psnr(x, ref) : 0;
    snprintf(name, sizeof name, "%s shear-warp vs reference raycast PSNR >= 30 dB", label);
    CHECK(p >= 30, name, "%.1f dB", p);
    printf("  %s: shear-warp PSNR vs reference %.1f dB\n", label, p);
    free(x);
    free(y);
    free(h);
    free(rm);
    free(z);
    free(ref);
    g_ortho = 0;
    g_kind = VSV_RENDER_RAYCAST;
}

static void sw_rules(const char *label, world *w, const int *ab, int nab)
{
    char name[256];
    snprintf(name, sizeof name, "%s (parallel)", label);
    sw_rules_proj(name, w, ab, nab, 1);
    snprintf(name, sizeof name, "%s (perspective)", label);
    sw_rules_proj(name, w, ab, nab, 0);
}

/* An eye among the slices has no shear-warp factorisation: the frame is
 * raycast instead, pixel for pixel. */
static void test_eye_inside(world *w)
{
    const vsv_meta *m = vsv_file_meta(w->f);
    vsv_layer layer = {w->vol[0], &w->tf[0], 1, 1};
    vsv_scene sc = {.meta = m, .layers = &layer, .nlayers = 1, .exaggeration = 1, .show_terrain = 1};
    double mn[3], mx[3];
    vsv_scene_bounds(&sc, mn, mx);
    vsv_camera cam;
    vsv_camera_orbit(&cam, &sc, 225, 0.5, 0, W, H);
    for (int i = 0; i < 3; i++)
        cam.pos[i] = 0.5 * (mn[i] + mx[i]); /* in the middle of the volume */
    cam.pos[2] = mn[2] + 0.3 * (mx[2] - mn[2]);
    float *a = malloc(sizeof(float) * W * H * 4), *b = malloc(sizeof(float) * W * H * 4);
    vsv_render_opts o;
    vsv_render_opts_init(&o);
    vsv_renderer *r1 = NULL, *r2 = NULL;
    vsv_renderer_create(&o, &r1);
    o.kind = VSV_RENDER_SHEARWARP;
    vsv_renderer_create(&o, &r2);
    const int rc1 = vsv_render(r1, &sc, &cam, a, NULL), rc2 = vsv_render(r2, &sc, &cam, b, NULL);
    CHECK(!rc1 && !rc2 && max_diff(a, b) == 0, "shear-warp with the eye among the slices falls back to raycasting",
          "%d %d %g", rc1, rc2, max_diff(a, b));
    vsv_renderer_free(r1);
    vsv_renderer_free(r2);
    free(a);
    free(b);
}

/* The sixteen-ray loop against the one-ray loop where they differ most: a
 * log-scale transfer function (a logarithm per lane), an image whose width is
 * not a multiple of sixteen (part-filled packets), depth. */
static void test_simd_paths(world *w)
{
    enum { SW = 101, SH = 67 };
    const vsv_quant *q = vsv_file_quant(w->f, 0);
    char text[256], msg[128];
    snprintf(text, sizeof text, "colormap magma\nrange %.9g %.9g\nscale log\nopacity 0 0.3 1\n",
             (q->hi > 0 ? q->hi : 1) * 1e-4, q->hi > 0 ? q->hi : 1);
    vsv_tf tf;
    if (!CHECK(vsv_tf_parse(&tf, text, msg, sizeof msg) == 0, "a log-scale transfer function parses", "%s", msg))
        return;
    const vsv_layer layers[2] = {{w->vol[0], &tf, 1, 1}, {w->vol[1], &w->tf[1], 0.7f, 1}};
    vsv_scene sc = {.meta = vsv_file_meta(w->f), .layers = layers, .nlayers = 2, .exaggeration = 1, .show_terrain = 1};
    sc.exaggeration = vsv_scene_default_exaggeration(&sc);
    vsv_camera cam;
    vsv_camera_orbit(&cam, &sc, 200, 25, 0, SW, SH);
    float *img[3], *dep[3];
    for (int k = 0; k < 3; k++) { /* the default kernel, the one-ray loop, the AVX2 build */
        if (k)
            setenv("VSV_SIMD", k == 1 ? "0" : "avx2", 1);
        vsv_render_opts o;
        vsv_render_opts_init(&o);
        o.threads = 2;
        vsv_renderer *r = NULL;
        img[k] = malloc(sizeof(float) * 4 * SW * SH);
        dep[k] = malloc(sizeof(float) * SW * SH);
        if (vsv_renderer_create(&o, &r) || vsv_render(r, &sc, &cam, img[k], dep[k]))
            memset(img[k], 0, sizeof(float) * 4 * SW * SH);
        vsv_renderer_free(r);
        unsetenv("VSV_SIMD");
    }
    int shown = 0;
    for (int i = 0; i < SW * SH; i++)
        shown += img[0][4 * i + 3] > 0.05f;
    CHECK(shown > 200 && !memcmp(img[0], img[1], sizeof(float) * 4 * SW * SH) &&
              !memcmp(dep[0], dep[1], sizeof(float) * SW * SH) &&
              !memcmp(img[0], img[2], sizeof(float) * 4 * SW * SH) && !memcmp(dep[0], dep[2], sizeof(float) * SW * SH),
          "log scale, 101x67 image: the sixteen-ray loop (both builds) and the one-ray loop give identical pixels "
          "and depths",
          "%d pixels shown", shown);
    for (int k = 0; k < 3; k++) {
        free(img[k]);
        free(dep[k]);
    }
}

/* vsv_render_rgba8: the bytes of vsv_render's floats, round(255 v) clamped,
 * from the shear-warp (parallel rays and perspective, with and without the
 * terrain, which it writes row by row) and the raycaster, on an image whose
 * width is no multiple of sixteen. */
static void test_rgba8(world *w)
{
    enum { SW = 101, SH = 67 };
    const vsv_layer layers[2] = {{w->vol[0], &w->tf[0], 1, 1}, {w->vol[1], &w->tf[1], 0.7f, 1}};
    float *f = malloc(sizeof(float) * 4 * SW * SH), *d0 = malloc(sizeof(float) * SW * SH),
          *d1 = malloc(sizeof(float) * SW * SH);
    unsigned char *b = malloc(4 * SW * SH), *want = malloc(4 * SW * SH);
    int cases = 0, same = 0, mid = 0;
    for (int kind = 0; kind < 2; kind++)
        for (int view = 0; view < 4; view++) {
            vsv_scene sc = {.meta = vsv_file_meta(w->f), .layers = layers, .nlayers = 2, .exaggeration = 1};
            sc.show_terrain = view & 1;
            vsv_camera cam;
            vsv_camera_orbit(&cam, &sc, 200 + 40 * view, 25, 0, SW, SH);
            if (view >= 2) { /* parallel rays */
                cam.fov_deg = 0;
                cam.ortho_height = 0.8 * fabs(cam.pos[2]) + 1;
            }
            vsv_render_opts o;
            vsv_render_opts_init(&o);
            o.kind = kind ? VSV_RENDER_SHEARWARP : VSV_RENDER_RAYCAST;
            o.threads = 2;
            vsv_renderer *r = NULL;
            if (vsv_renderer_create(&o, &r) || vsv_render(r, &sc, &cam, f, d0) ||
                vsv_render_rgba8(r, &sc, &cam, b, d1)) {
                vsv_renderer_free(r);
                continue;
            }
            for (int i = 0; i < 4 * SW * SH; i++) {
                const float v = f[i] > 0 ? (f[i] < 1 ? f[i] : 1) : 0;
                want[i] = (unsigned char)(v * 255 + 0.5f);
                mid += want[i] > 0 && want[i] < 255;
            }
            cases++;
            same += !memcmp(b, want, 4 * SW * SH) && !memcmp(d0, d1, sizeof(float) * SW * SH);
            if (view == 0 && kind)
                CHECK(vsv_render_rgba8(r, &sc, &cam, NULL, NULL) == VSV_EINVAL, "vsv_render_rgba8 without an image",
                      "is VSV_EINVAL");
            vsv_renderer_free(r);
        }
    CHECK(cases == 8 && same == 8 && mid > 1000,
          "8-bit RGBA: vsv_render's floats as bytes, round(255 v), from the shear-warp and the raycaster, "
          "perspective and parallel, with and without the terrain",
          "(%d of %d the same; %d channels strictly between 0 and 255)", same, cases, mid);
    free(f), free(d0), free(d1), free(b), free(want);
}

/* The raycaster's sampling copy: every brick with one more cell along each
 * axis holds the cells of the grid (past its end, the last cell again); a
 * volume loaded with another step is sampled anew by the same renderer. */
static void test_sampling_copy(world *w)
{
    const vsv_volume *v = w->vol[0];
    const int e = v->brick + 1;
    float *copy = malloc(sizeof(float) * e * e * e);
    long bad = 0, cells = 0;
    for (int b = 0; copy && b < v->nbricks; b++) {
        vsv_rc_copy_fill(v, b, copy);
        const int i0 = b % v->bdim[0] * v->brick, j0 = b / v->bdim[0] % v->bdim[1] * v->brick;
        const int k0 = b / (v->bdim[0] * v->bdim[1]) * v->brick;
        for (int k = 0; k < e; k++)
            for (int j = 0; j < e; j++)
                for (int i = 0; i < e; i++, cells++) {
                    const int gi = i0 + i < v->nx ? i0 + i : v->nx - 1, gj = j0 + j < v->ny ? j0 + j : v->ny - 1;
                    const int gk = k0 + k < v->nz ? k0 + k : v->nz - 1;
                    const float want = vsv_volume_at(v, gi, gj, gk), got = copy[(k * e + j) * e + i];
                    bad += !(got == want || (got != got && want != want));
                }
    }
    CHECK(copy && bad == 0 && cells > 10000,
          "the raycaster's sampling copy holds the grid's cells, the last again past it", "%ld of %ld differ", bad,
          cells);
    free(copy);
    /* the same renderer after the volume is loaded with another step */
    vsv_layer L = {w->vol[0], &w->tf[0], 1, 1};
    vsv_scene sc = {.meta = vsv_file_meta(w->f), .layers = &L, .nlayers = 1, .exaggeration = 1, .show_terrain = 0};
    vsv_camera cam;
    vsv_camera_orbit(&cam, &sc, 225, 30, 0, W, H);
    vsv_render_opts o;
    vsv_render_opts_init(&o);
    vsv_renderer *r = NULL, *fresh = NULL;
    float *a = malloc(sizeof(float) * 4 * W * H), *b = malloc(sizeof(float) * 4 * W * H);
    float *c = malloc(sizeof(float) * 4 * W * H);
    int ok = !vsv_renderer_create(&o, &r) && !vsv_renderer_create(&o, &fresh) && a && b && c &&
             !vsv_render(r, &sc, &cam, a, NULL) && !vsv_volume_load(w->vol[0], w->d, 1, 0) &&
             !vsv_render(r, &sc, &cam, b, NULL) && !vsv_render(fresh, &sc, &cam, c, NULL);
    CHECK(ok && max_diff(a, b) > 0.01 && max_diff(b, c) == 0,
          "a volume loaded with another step: the renderer samples the new step", "%g %g", ok ? max_diff(a, b) : -1,
          ok ? max_diff(b, c) : -1);
    vsv_volume_load(w->vol[0], w->d, 2, 0);
    vsv_renderer_free(r);
    vsv_renderer_free(fresh);
    free(a);
    free(b);
    free(c);
}

static void test_synthetic(void)
{
    synth sy = {64, 48, 20, 3, 9, 9};
    const char *path = vsv_test_tmp("render.vsv");
    char err[256];
    vsv_pack_opts o;
    vsv_pack_opts_init(&o);
    o.brick = 16;
    if (!CHECK(synth_write(&sy, path, &o, err, sizeof err) == 0, "synthetic file for rendering", "%s", err))
        return;
    world w;
    if (!CHECK(load(&w, path, 2) == 0, "synthetic volumes load"))
        return;
    rules("synthetic", &w);
    test_sampling_copy(&w);
    test_simd_paths(&w);
    test_rgba8(&w);
    const int sw3[3] = {0, 1, 2};
    sw_rules("synthetic", &w, sw3, 3);
    test_eye_inside(&w);
    /* a plume-only render is not empty, and its depth is finite where it shows */
    const int a1[1] = {0};
    const float one1[1] = {1};
    float *depth = malloc(sizeof(float) * W * H);
    float *img = render(&w, a1, one1, 1, 2, 0.5, 0, depth);
    int finite = 0, shown = 0;
    for (int i = 0; img && i < W * H; i++) {
        shown += img[4 * i + 3] > 0.2f;
        finite += img[4 * i + 3] > 0.2f && isfinite(depth[i]);
    }
    CHECK(shown > 100 && finite == shown, "depth is finite wherever the picture is opaque", "%d %d", shown, finite);
    free(img);
    free(depth);
    unload(&w);
    unlink(path);
}

/* The whole real MMOUT (Q with no-data cells under the Rockies): skipping
 * must not change the picture. */
/* Where rays meet the real terrain: the exact patch-by-patch intersection
 * against a march at a sixteenth of a cell: the point found lies on the
 * ground (or is where the ray enters the box below it), the march finds the
 * ray below the ground nowhere before it, and nowhere at all on rays that
 * miss. Four views, one of them 8 degrees up (long grazing rays). */
static void test_ground(world *w)
{
    const vsv_layer none[1] = {{w->vol[0], &w->tf[0], 0, 0}};
    vsv_scene sc = {.meta = vsv_file_meta(w->f), .layers = none, .nlayers = 1, .exaggeration = 1, .show_terrain = 1};
    sc.exaggeration = vsv_scene_default_exaggeration(&sc);
    vsv_geo g;
    vsv_scene_geo(&sc, &g);
    int hits = 0, rays = 0, bad = 0;
    for (int view = 0; view < 4; view++) {
        vsv_camera cam;
        vsv_camera_orbit(&cam, &sc, 225 + 90 * view, view == 3 ? 8 : 30, 0, W, H);
        for (int py = 0; py < H; py += 3)
            for (int px = 0; px < W; px += 3) {
                double o[3], d[3], t0, t1;
                vsv_pixel_ray(&cam, px, py, o, d);
                if (!vsv_box_hit(o, d, g.bmin, g.bmax, &t0, &t1))
                    continue;
                t0 = fmax(t0, 0);
                rays++;
                const double t = vsv_geo_terrain_hit(&g, o, d, t0, t1);
                const double hs = sqrt(d[0] * d[0] + d[1] * d[1]), st = hs > 0 ? fmin(g.dx, g.dy) / 16 / hs : 1e3;
                const double end = t < INFINITY ? t - 1e-6 * (t + 1) : t1;
                for (double s = t0; s < end; s += st) /* above the ground all the way to the hit */
                    if (o[2] + s * d[2] < vsv_geo_terrain(&g, o[0] + s * d[0], o[1] + s * d[1])) {
                        bad++;
                        break;
                    }
                if (t < INFINITY) {
                    hits++;
                    const double f = o[2] + t * d[2] - vsv_geo_terrain(&g, o[0] + t * d[0], o[1] + t * d[1]);
                    /* on the ground, or where the ray enters the box already below it */
                    bad += !(fabs(f) <= 1e-6 * (g.ground_top + 1) || (t == t0 && f <= 0));
                }
            }
    }
    CHECK(rays > 1000 && hits > 500 && bad == 0,
          "real MMOUT terrain: every ray meets the ground where a fine march says, exactly on it",
          "%d rays, %d hits, %d wrong", rays, hits, bad);
    /* an exaggeration beyond numbers (vsv-render -x 1e308 overflowed the heap
     * here, issue 33): a whole frame renders, nothing out of bounds */
    sc.exaggeration = 1e308;
    vsv_camera cam;
    vsv_camera_fit(&cam, &sc, 225, 30, 64, 48);
    vsv_render_opts o;
    vsv_render_opts_init(&o);
    vsv_renderer *r = NULL;
    float *img = malloc(sizeof(float) * 4 * 64 * 48);
    CHECK(img && vsv_renderer_create(&o, &r) == 0 && vsv_render(r, &sc, &cam, img, NULL) >= 0,
          "an exaggeration of 1e308: the frame renders without a fault");
    vsv_renderer_free(r);
    free(img);
}

/* The shear-warp while playing: one renderer shown steps in turn (forward,
 * back to the start, a jump), two views with different principal axes each
 * step, classifies again only the bricks whose values changed (the volumes'
 * brick keys), and every picture equals, bit for bit, a new renderer's
 * (every brick classified) of the same step and view. */
static void test_sw_playing(const char *label, world *w, int nsteps, int first, int light)
{
    const vsv_meta *m = vsv_file_meta(w->f);
    vsv_layer layers[16];
    int nl = 0;
    for (int i = first; i < w->n; i++) /* (the wind's components are not drawn) */
        if (!vsv_meta_var_in_vector(m, i))
            layers[nl++] = (vsv_layer){w->vol[i], &w->tf[i], 1, 1};
    vsv_scene sc;
    memset(&sc, 0, sizeof sc);
    sc.meta = m;
    sc.layers = layers;
    sc.nlayers = nl;
    sc.exaggeration = 4;
    if (light) /* shading reads across brick faces: a change reaches the neighbours */
        vsv_scene_sun(&sc, 135, 40);
    double mn[3], mx[3];
    vsv_scene_bounds(&sc, mn, mx);
    vsv_camera cam[2];
    vsv_camera_orbit(&cam[0], &sc, 225, 30, 0, W, H);
    vsv_camera_orbit(&cam[1], &sc, 200, 80, 0, W, H);
    for (int v = 0; v < 2; v++) {
        cam[v].fov_deg = 0;
        cam[v].ortho_height = 0.75 * (mx[0] - mn[0]);
    }
    vsv_render_opts o;
    vsv_render_opts_init(&o);
    o.kind = VSV_RENDER_SHEARWARP;
    o.threads = 2;
    vsv_renderer *r = NULL;
    float *a = malloc(sizeof(float) * 4 * W * H), *b = malloc(sizeof(float) * 4 * W * H);
    int ok = !vsv_renderer_create(&o, &r) && a && b, same = 1, fewest = INT32_MAX, most = 0, frames = 0;
    const int order[] = {1, 2, 3, 0, 1, 3, 2};
    int nb = w->vol[0]->nbricks, enz; /* bricks of the grid drawn: native levels on their even axis */
    double ez0, edz;
    if (!vsv_heights_axis(m, &enz, &ez0, &edz))
        nb = w->vol[0]->bdim[0] * w->vol[0]->bdim[1] * ((enz + w->vol[0]->brick - 1) / w->vol[0]->brick);
    double diff = 0;
    for (size_t i = 0; ok && i < sizeof order / sizeof order[0]; i++) {
        const int t = order[i] % nsteps;
        for (int s = 0; s < w->n && ok; s++)
            ok = !vsv_volume_load(w->vol[s], w->d, t, s);
        for (int v = 0; v < 2 && ok; v++) {
            vsv_renderer *fresh = NULL;
            ok = !vsv_render(r, &sc, &cam[v], a, NULL) && !vsv_renderer_create(&o, &fresh) &&
                 !vsv_render(fresh, &sc, &cam[v], b, NULL);
            if (ok && i > 0) { /* the first frame of each axis classifies every brick */
                const int n = vsv_renderer_rebuild_bricks(r);
                fewest = n < fewest ? n : fewest;
                most = n > most ? n : most;
                frames++;
            }
            if (ok && max_diff(a, b) > diff)
                diff = max_diff(a, b);
            same &= ok && max_diff(a, b) == 0;
            vsv_renderer_free(fresh);
        }
    }
    char name[200];
    snprintf(name, sizeof name, "%s: shear-warp playing steps, each picture equals a full classification's", label);
    CHECK(ok && same, name, "largest difference %g", diff);
    snprintf(name, sizeof name, "%s: shear-warp playing re-classifies only changed bricks", label);
    /* (Q, species 0, changes everywhere: checked for the pictures only) */
    CHECK(ok && frames > 0 && most > 0 && (first == 0 || fewest < nb), name, "%d..%d of %d bricks", fewest, most, nb);
    printf("  %s: bricks classified again per frame while playing %d..%d of %d\n", label, fewest, most, nb);
    vsv_renderer_free(r);
    free(a);
    free(b);
}

static void test_mmout_playing(void)
{
    const char *path = vsv_test_tmp("render-mmout-play.vsv");
    char cmd[2048];
    if (vsv_test_absent(vsv_test_shared("mm5/run1/MMOUT_DOMAIN1"), "playing the real MMOUT"))
        return;
    snprintf(cmd, sizeof cmd, "%s/vsv-convert -q --vertical even %s -o %s", getenv("B") ? getenv("B") : "build",
             vsv_test_shared("mm5/run1/MMOUT_DOMAIN1"), path);
    if (!CHECK(system(cmd) == 0, "the real MMOUT converts, four periods"))
        return;
    world w;
    if (CHECK(load(&w, path, 0) == 0, "MMOUT volumes load (4 periods)")) {
        test_sw_playing("real MMOUT, all species", &w, 4, 0, 0);
        test_sw_playing("real MMOUT, hydrometeors", &w, 4, 1, 0);
        test_sw_playing("real MMOUT, hydrometeors, lit", &w, 4, 1, 1);
        unload(&w);
    }
    unlink(path);
}

static void test_mmout(void)
{
    const char *path = vsv_test_tmp("render-mmout.vsv");
    char cmd[2048];
    if (vsv_test_absent(vsv_test_shared("mm5/run1/MMOUT_DOMAIN1"), "rendering the real MMOUT"))
        return;
    snprintf(cmd, sizeof cmd, "%s/vsv-convert -q --times 3:3 %s -o %s", getenv("B") ? getenv("B") : "build",
             vsv_test_shared("mm5/run1/MMOUT_DOMAIN1"), path);
    if (!CHECK(system(cmd) == 0, "the real MMOUT converts for rendering"))
        return;
    world w;
    if (!CHECK(load(&w, path, 0) == 0, "MMOUT volumes load"))
        return;
    const int all5[5] = {0, 1, 2, 3, 4};
    const float ones5[5] = {1, 1, 1, 1, 1};
    float *sk = render(&w, all5, ones5, 5, 2, 0.5, 0, NULL), *nsk = render(&w, all5, ones5, 5, 2, 0.5, 1, NULL);
    CHECK(sk && nsk && max_diff(sk, nsk) <= 1.0 / 255, "real MMOUT, all species: skipping within 1/255", "%g",
          sk && nsk ? max_diff(sk, nsk) : -1);
    CHECK(sk && coverage(sk) > 0.1, "a render of the whole MMOUT domain is not empty", "%.2f", sk ? coverage(sk) : 0);
    test_ground(&w);
    free(sk);
    free(nsk);
    unload(&w);
    unlink(path);
}

static void test_mm5(void)
{
    const char *path = vsv_test_tmp("render-mm5.vsv");
    /* convert the bundled sample with the library, as vsv-convert does */
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "%s/vsv-convert -q --vertical even samples/mm5/MMOUT_DOMAIN1_CROP -o %s",
             getenv("B") ? getenv("B") : "build", path);
    if (!CHECK(system(cmd) == 0, "the MM5 sample converts for rendering"))
        return;
    world w;
    if (!CHECK(load(&w, path, 3) == 0, "MM5 volumes load (3 h)"))
        return;
    /* species 1 is CLW: show CLW and SNOW against the terrain */
    const int clw_snow[2] = {1, 4}, snow[1] = {4};
    const float one2[2] = {1, 1}, one1[1] = {1};
    float *a = render(&w, clw_snow, one2, 2, 2, 0.5, 0, NULL), *b = render(&w, snow, one1, 1, 2, 0.5, 0, NULL);
    CHECK(a && coverage(a) > 0.05, "a render of real MM5 data is not empty", "coverage %.2f", a ? coverage(a) : 0);
    CHECK(a && b && max_diff(a, b) > 0.05, "hiding cloud water changes the MM5 render");
    free(a);
    free(b);
    /* all five species, Q with no-data cells below the ground among them */
    const int all5[5] = {0, 1, 2, 3, 4};
    const float ones5[5] = {1, 1, 1, 1, 1};
    float *sk = render(&w, all5, ones5, 5, 2, 0.5, 0, NULL), *nsk = render(&w, all5, ones5, 5, 2, 0.5, 1, NULL);
    CHECK(sk && nsk && max_diff(sk, nsk) <= 1.0 / 255, "MM5 all species with no-data cells: skipping within 1/255",
          "%g", sk && nsk ? max_diff(sk, nsk) : -1);
    free(sk);
    free(nsk);
    world *pw = &w;
    /* the rules on real data: CLW (1) and ICE (3) in the places of 0 and 2 */
    vsv_volume *v0 = pw->vol[0], *v2 = pw->vol[2];
    vsv_tf t0 = pw->tf[0], t2 = pw->tf[2];
    pw->vol[0] = pw->vol[1];
    pw->tf[0] = pw->tf[1];
    pw->vol[2] = pw->vol[3];
    pw->tf[2] = pw->tf[3];
    rules("MM5 CLW+ICE", pw);
    const int sw5[5] = {0, 1, 2, 3, 4};
    sw_rules("MM5 all species", pw, sw5, 5);
    pw->vol[0] = v0;
    pw->vol[2] = v2;
    pw->tf[0] = t0;
    pw->tf[2] = t2;
    test_sw_playing("MM5 sample, all species", pw, 4, 0, 0);
    test_sw_playing("MM5 sample, hydrometeors", pw, 4, 1, 0);
    unload(&w);
    unlink(path);
    /* the model's own levels (the default), resampled as they are drawn:
       only the bricks over a changed column of native bricks again */
    snprintf(cmd, sizeof cmd, "%s/vsv-convert -q samples/mm5/MMOUT_DOMAIN1_CROP -o %s",
             getenv("B") ? getenv("B") : "build", path);
    if (!CHECK(system(cmd) == 0 && load(&w, path, 3) == 0, "the MM5 sample on its own levels loads"))
        return;
    test_sw_playing("MM5 sample, native levels, hydrometeors", &w, 4, 1, 0);
    unload(&w);
    unlink(path);
}

int main(void)
{
    test_synthetic();
    test_mm5();
    test_mmout();
    test_mmout_playing();
    return vsv_test_done();
}
