/* test_render_sw.c — the shear-warp's classification kept from frame to
 * frame on the bundled MM5 sample: one visible species (classified as
 * entries of its table) draws the same bytes as the same species beside a
 * second one that is transparent everywhere (classified cell by cell), and
 * one renderer taken through new steps, fades, ranges and scales draws,
 * every frame, what a new renderer draws. */
#include "vsv_render.h"
#include "vsv_testlib.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

enum { W = 160, H = 120, STEPS = 4 };

typedef struct sample {
    vsv_file *f;
    vsv_decoder *d;
    vsv_volume *vol[STEPS];
    int nsteps;
} sample;

/* Species NAME of the converted sample, every step decoded: 0 or -1. */
static int sample_load(sample *s, const char *path, const char *name)
{
    memset(s, 0, sizeof *s);
    if (vsv_file_open(path, &s->f) || vsv_decoder_create(s->f, &s->d))
        return -1;
    const vsv_meta *m = vsv_file_meta(s->f);
    int sp = -1;
    for (int i = 0; i < m->nvars; i++)
        if (!strcmp(m->vars[i].name, name))
            sp = i;
    vsv_file_info info;
    vsv_file_info_get(s->f, &info);
    s->nsteps = info.nsteps < STEPS ? info.nsteps : STEPS;
    for (int t = 0; t < s->nsteps; t++)
        if (sp < 0 || vsv_volume_create(s->f, &s->vol[t]) || vsv_volume_load(s->vol[t], s->d, t, sp))
            return -1;
    return 0;
}

/* The bundled MM5 sample converted with vsv-convert's opts to path, then
 * species NAME loaded: 0 or -1. */
static int sample_open(sample *s, const char *opts, const char *path, const char *name)
{
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "%s/vsv-convert -q %s samples/mm5/MMOUT_DOMAIN1_CROP -o %s",
             getenv("B") ? getenv("B") : "build", opts, path);
    return system(cmd) == 0 ? sample_load(s, path, name) : (memset(s, 0, sizeof *s), -1);
}

static void sample_free(sample *s)
{
    for (int t = 0; t < STEPS; t++)
        vsv_volume_free(s->vol[t]);
    vsv_decoder_free(s->d);
    vsv_file_free(s->f);
}

static int tf(vsv_tf *t, const char *text)
{
    char msg[200];
    if (vsv_tf_parse(t, text, msg, sizeof msg)) {
        fprintf(stderr, "tf: %s\n", msg);
        return -1;
    }
    return 0;
}

/* One frame of the sequence below: its step, view, transfer function and
 * opacity. */
typedef struct frame {
    int step, view, tf;
    float opacity;
} frame;

static int differ(const unsigned char *a, const unsigned char *b) { return memcmp(a, b, 4 * W * H) != 0; }

static int visible(const unsigned char *a)
{
    int n = 0;
    for (int i = 0; i < W * H; i++)
        n += a[4 * i + 3] > 0;
    return n;
}

/* The shear-warp on two threads */
static vsv_render_opts sw_opts(void)
{
    vsv_render_opts o;
    vsv_render_opts_init(&o);
    o.kind = VSV_RENDER_SHEARWARP;
    o.threads = 2;
    return o;
}

/* Draws sc through r into a and through a new renderer into b: 0 or -1. */
static int with_new(vsv_renderer *r, const vsv_scene *sc, const vsv_camera *cam, unsigned char *a, unsigned char *b)
{
    const vsv_render_opts o = sw_opts();
    vsv_renderer *fresh = NULL;
    const int ok = !vsv_render_rgba8(r, sc, cam, a, NULL) && !vsv_renderer_create(&o, &fresh) &&
                   !vsv_render_rgba8(fresh, sc, cam, b, NULL);
    vsv_renderer_free(fresh);
    return ok ? 0 : -1;
}

static void test_sequence(const char *species, int mode)
{
    const char *path = vsv_test_tmp("render-sw.vsv");
    char name[200];
    sample s;
    if (!CHECK(sample_open(&s, "--vertical even", path, species) == 0, "the MM5 sample converts and loads", "%s",
               species))
        return;
    /* the species' values span 0 .. hi: a wide range, one of its top
     * third (most bricks transparent), the wide one on a log scale; a
     * second layer's whose range is above every value */
    float hi = 0;
    for (int t = 0; t < s.nsteps; t++)
        for (int b = 0; b < s.vol[t]->nbricks; b++)
            hi = s.vol[t]->bmax[b] > hi ? s.vol[t]->bmax[b] : hi;
    vsv_tf tfs[5];
    char text[5][300];
    snprintf(text[0], sizeof text[0], "colormap clouds\nrange 0 %.9g\nopacity 0 0.2 0.5 0.9\n", hi);
    snprintf(text[1], sizeof text[1], "colormap viridis\nrange %.9g %.9g\nopacity 0 0.6 1\n", hi * 0.35, hi);
    snprintf(text[2], sizeof text[2], "colormap rain\nrange %.9g %.9g\nscale log\nopacity 0 0.3 0.9\n", hi * 1e-4, hi);
    snprintf(text[3], sizeof text[3], "colormap greys\nrange %.9g %.9g\nopacity 1 1\n", hi * 4, hi * 8);
    snprintf(text[4], sizeof text[4], "colormap greys\nrange 0 %.9g\nopacity 0.05 0.05\n", hi); /* a veil */
    for (int i = 0; i < 5; i++)
        if (!CHECK(tf(&tfs[i], text[i]) == 0, "transfer functions parse", "%d", i))
            return;
    vsv_layer layers[2] = {{s.vol[0], &tfs[0], 1, 1}, {s.vol[0], &tfs[3], 1, 1}};
    vsv_scene sc;
    memset(&sc, 0, sizeof sc);
    sc.meta = vsv_file_meta(s.f);
    sc.layers = layers;
    sc.nlayers = mode ? 2 : 1; /* mode 1: beside a layer transparent everywhere */
    sc.exaggeration = 4;
    double mn[3], mx[3];
    vsv_scene_bounds(&sc, mn, mx);
    vsv_camera cam[3];
    vsv_camera_orbit(&cam[0], &sc, 225, 30, 0, W, H);
    vsv_camera_orbit(&cam[1], &sc, 300, 20, 0, W, H);
    vsv_camera_orbit(&cam[2], &sc, 200, 80, 0, W, H);
    for (int v = 0; v < 3; v++) {
        cam[v].fov_deg = v == 1 ? 30 : 0; /* one in perspective */
        cam[v].ortho_height = 0.75 * (mx[0] - mn[0]);
    }
    /* (step 0 holds no cloud: every brick of it transparent) */
    const frame seq[] = {{1, 0, 0, 1}, {2, 0, 0, 1},    {2, 2, 0, 1}, {2, 2, 0, 0.4f}, {2, 2, 1, 0.4f},
                         {3, 2, 1, 1}, {3, 0, 1, 1},    {3, 0, 0, 1}, {1, 1, 2, 1},    {0, 1, 2, 0.7f},
                         {3, 2, 2, 1}, {2, 2, 0, 0.7f}, {1, 0, 0, 1}, {2, 0, 4, 1},    {2, 2, 0, 1}};
    const vsv_render_opts o = sw_opts();
    vsv_renderer *r = NULL, *fresh = NULL;
    unsigned char *a = malloc(4 * W * H), *b = malloc(4 * W * H);
    int ok = a && b && !vsv_renderer_create(&o, &r), bad = -1, seen = 0;
    for (size_t i = 0; ok && i < sizeof seq / sizeof seq[0]; i++) {
        const frame *fr = &seq[i];
        layers[0].vol = layers[1].vol = s.vol[fr->step % s.nsteps];
        layers[0].tf = &tfs[fr->tf];
        layers[0].opacity = fr->opacity;
        ok = !with_new(r, &sc, &cam[fr->view], a, b);
        seen += visible(a) > 0;
        if (ok && bad < 0 && differ(a, b))
            bad = (int)i;
        if (mode == 0 && ok) { /* the same frame through the per-cell classification */
            sc.nlayers = 2;
            ok = !vsv_renderer_create(&o, &fresh) && !vsv_render_rgba8(fresh, &sc, &cam[fr->view], b, NULL);
            sc.nlayers = 1;
            vsv_renderer_free(fresh);
            fresh = NULL;
            snprintf(name, sizeof name, "%s alone: frame %zu the same bytes as beside a transparent layer", species, i);
            CHECK(ok && !differ(a, b), name);
        }
    }
    /* 24 even levels next: another grid, the copies laid out anew */
    sample n;
    snprintf(name, sizeof name, "%s.native", path);
    if (ok && CHECK(sample_open(&n, "--nz 24", name, species) == 0, "the sample on 24 levels loads")) {
        layers[0].tf = &tfs[0];
        layers[0].vol = layers[1].vol = n.vol[1];
        sc.meta = vsv_file_meta(n.f);
        for (int v = 0; v < 3 && ok; v += 2) {
            ok = !with_new(r, &sc, &cam[v], a, b);
            if (ok && bad < 0 && differ(a, b))
                bad = 100 + v;
        }
        sample_free(&n);
        unlink(name);
    }
    snprintf(name, sizeof name,
             "%s%s: one renderer through steps, views, fades, ranges and scales draws a new one's bytes", species,
             mode ? " beside a transparent layer" : " alone");
    CHECK(ok && bad < 0, name, "first different frame %d", bad);
    snprintf(name, sizeof name, "%s%s: the frames show something", species, mode ? " (two layers)" : "");
    CHECK(ok && seen >= 12, name, "%d of %zu", seen, sizeof seq / sizeof seq[0]);
    vsv_renderer_free(r);
    free(a);
    free(b);
    sample_free(&s);
    unlink(path);
}

/* A scene whose layer has no volume (a step the player could not decode)
 * as a new renderer's first frame, then the volume: nothing drawn, then a
 * new renderer's bytes (a copy allocated as zeros for a grid without
 * bricks was read as if it had them: a crash). */
static void test_no_volume(void)
{
    const char *path = vsv_test_tmp("render-sw-none.vsv");
    sample s;
    vsv_tf t;
    if (!CHECK(sample_open(&s, "--vertical even", path, "CLW") == 0 &&
                   tf(&t, "colormap clouds\nrange 0 0.0005\nopacity 0 0.5 1\n") == 0,
               "no volume: the sample loads"))
        return;
    vsv_layer layer = {NULL, &t, 1, 1};
    vsv_scene sc;
    memset(&sc, 0, sizeof sc);
    sc.meta = vsv_file_meta(s.f);
    sc.layers = &layer;
    sc.nlayers = 1;
    sc.exaggeration = 4;
    vsv_camera cam;
    vsv_camera_orbit(&cam, &sc, 200, 80, 0, W, H);
    cam.fov_deg = 0;
    cam.ortho_height = 2e5;
    const vsv_render_opts o = sw_opts();
    vsv_renderer *r = NULL;
    unsigned char *a = malloc(4 * W * H), *b = malloc(4 * W * H);
    int ok = a && b && !vsv_renderer_create(&o, &r) && !vsv_render_rgba8(r, &sc, &cam, a, NULL);
    CHECK(ok && visible(a) == 0, "no volume: a new renderer's first frame draws nothing", "%d", ok ? visible(a) : -1);
    layer.vol = s.vol[2];
    ok = ok && !with_new(r, &sc, &cam, a, b);
    CHECK(ok && !differ(a, b) && visible(a) > 0, "no volume, then the volume: a new renderer's bytes");
    vsv_renderer_free(r);
    free(a);
    free(b);
    sample_free(&s);
    unlink(path);
}

int main(void)
{
    test_no_volume();
    test_sequence("CLW", 0);
    test_sequence("CLW", 1);
    test_sequence("SNOW", 0);
    test_sequence("Q", 0);
    return vsv_test_done();
}
