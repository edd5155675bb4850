/* test_iso_draw.c — isosurfaces drawn in a scene (vsv_scene.isos, issue
 * 35): a ball's surface seen from above covers its disc (area within 2 %),
 * at the depth of its top and in its colour; the raycaster and the
 * shear-warp give the same pixels; a translucent volume in front is
 * composited over it exactly (acc + T colour) and one behind it is hidden. */
#include "vsv_format.h"
#include "vsv_render.h"
#include "vsv_testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { N = 40, B = 16, W = 240, H = 240 };
static const double C = 20, R = 12; /* the ball: centre cell (20, 20, 20), 12 cells */

static double ball(int i, int j, int k) { return R - sqrt((i - C) * (i - C) + (j - C) * (j - C) + (k - C) * (k - C)); }
static double outside(int i, int j, int k) { return -ball(i, j, k); }
static double above(int i, int j, int k) { return (void)i, (void)j, k >= 36 ? 0.5 : 0; }
static double below(int i, int j, int k) { return (void)i, (void)j, k <= 4 ? 0.5 : 0; }

/* An in-memory volume of f, exact brick ranges. */
static vsv_volume *make_volume(double (*f)(int, int, int))
{
    vsv_volume *v = calloc(1, sizeof *v);
    v->nx = v->ny = v->nz = N, v->brick = B, v->shift = 4;
    v->bdim[0] = v->bdim[1] = v->bdim[2] = (N + B - 1) / B;
    v->nbricks = v->bdim[0] * v->bdim[1] * v->bdim[2];
    v->bricks = calloc((size_t)v->nbricks, sizeof *v->bricks);
    v->bmin = calloc((size_t)v->nbricks, sizeof *v->bmin);
    v->bmax = calloc((size_t)v->nbricks, sizeof *v->bmax);
    v->gen = vsv_volume_new_gen();
    for (int b = 0; b < v->nbricks; b++) {
        float *p = v->bricks[b] = calloc(B * B * B, sizeof(float));
        const int i0 = b % v->bdim[0] * B, j0 = b / v->bdim[0] % v->bdim[1] * B, k0 = b / (v->bdim[0] * v->bdim[1]) * B;
        v->bmin[b] = INFINITY, v->bmax[b] = -INFINITY;
        for (int k = 0; k < B; k++)
            for (int j = 0; j < B; j++)
                for (int i = 0; i < B; i++)
                    if (i0 + i < N && j0 + j < N && k0 + k < N) {
                        const float x = p[i + B * (j + B * k)] = (float)f(i0 + i, j0 + j, k0 + k);
                        v->bmin[b] = fminf(v->bmin[b], x), v->bmax[b] = fmaxf(v->bmax[b], x);
                    }
    }
    return v;
}

static void free_volume(vsv_volume *v)
{
    for (int b = 0; b < v->nbricks; b++)
        free(v->bricks[b]);
    free(v->bricks), free(v->bmin), free(v->bmax), free(v);
}

/* Renders sc in a plan view with renderer kind: rgba and depth, new. */
static float *render_plan(const vsv_scene *sc, int kind, float **depth, vsv_camera *cam)
{
    vsv_render_opts o;
    vsv_render_opts_init(&o);
    o.kind = kind;
    o.threads = 2;
    vsv_renderer *r = NULL;
    vsv_camera_plan(cam, sc, W, H);
    float *img = malloc(sizeof(float) * 4 * W * H);
    *depth = malloc(sizeof(float) * W * H);
    if (vsv_renderer_create(&o, &r) || vsv_render(r, sc, cam, img, *depth)) {
        free(img), free(*depth);
        img = NULL, *depth = NULL;
    }
    vsv_renderer_free(r);
    return img;
}

static void test_draw(void)
{
    vsv_meta m;
    vsv_meta_init(&m);
    m.nx = m.ny = m.nz = N;
    m.spacing[0] = m.spacing[1] = m.spacing[2] = 1000;
    m.vert_kind = VSV_VERT_EVEN;
    vsv_volume *vb = make_volume(ball), *va = make_volume(above), *vl = make_volume(below);
    vsv_tf tf;
    char msg[128];
    CHECK(vsv_tf_parse(&tf, "colormap greys\nrange 0.1 1\nopacity 1 1\n", msg, sizeof msg) == 0, "draw: tf");
    /* layer 0 the ball (not drawn as a volume), layer 1 a slab above or below it */
    vsv_layer L[2] = {{vb, &tf, 1, 0}, {va, &tf, 0.01f, 0}};
    const vsv_scene_iso iso = {0, 0, {0.9f, 0.5f, 0.2f}};
    vsv_scene sc = {.meta = &m, .layers = L, .nlayers = 2, .exaggeration = 1, .isos = &iso, .nisos = 1};
    vsv_camera cam;
    float *d_rc = NULL, *d_sw = NULL, *d_v = NULL, *d_vi = NULL, *d_b = NULL;
    float *rc = render_plan(&sc, VSV_RENDER_RAYCAST, &d_rc, &cam),
          *sw = render_plan(&sc, VSV_RENDER_SHEARWARP, &d_sw, &cam);
    if (!CHECK(rc && sw, "draw: rendered"))
        goto done;
    /* the disc: pixels of alpha 1 against pi (R cells)^2 in pixels */
    const double pix = cam.ortho_height / H, want = M_PI * (R * 1000 / pix) * (R * 1000 / pix);
    int disc = 0;
    for (int i = 0; i < W * H; i++)
        disc += rc[4 * i + 3] == 1;
    CHECK(fabs(disc / want - 1) < 0.02, "draw: the ball's disc covered, area within 2 %", "(%d pixels for %.0f)", disc,
          want);
    /* the pixel over the centre: the top's depth, the colour lit head on */
    const int px = (int)floor((C * 1000 - cam.pos[0]) / pix + W / 2.0),
              py = (int)floor(H / 2.0 - (C * 1000 - cam.pos[1]) / pix);
    const size_t at = (size_t)py * W + px, beside = (size_t)(py + 15 * 1000 / pix) * W + px; /* 15 cells south */
    const double top = cam.pos[2] - (C + R) * 1000;
    float lin[3];
    double off = 0;
    for (int k = 0; k < 3; k++) {
        lin[k] = powf(iso.rgb[k], 2.2f);
        off = fmax(off, fabs(rc[4 * at + k] - lin[k]));
    }
    CHECK(fabs(d_rc[at] - top) < 30 && off < 0.02, "draw: the top at its depth, in its colour lit head on",
          "(depth %.1f for %.1f, colour %.3g off)", d_rc[at], top, off);
    CHECK(!memcmp(rc, sw, sizeof(float) * 4 * W * H) && !memcmp(d_rc, d_sw, sizeof(float) * W * H),
          "draw: the shear-warp's pixels are the raycaster's (such frames are raycast)");
    /* a translucent slab above: over the ball, acc + T colour of the slab
     * alone; beside it, the slab alone */
    L[1].visible = 1;
    float *vi = render_plan(&sc, VSV_RENDER_RAYCAST, &d_vi, &cam);
    sc.nisos = 0;
    float *v = render_plan(&sc, VSV_RENDER_RAYCAST, &d_v, &cam);
    double err = 0, side = 0;
    for (int k = 0; k < 3 && vi && v; k++) {
        err = fmax(err, fabs(vi[4 * at + k] - (v[4 * at + k] + (1 - v[4 * at + 3]) * rc[4 * at + k])));
        side = fmax(side, fabs(vi[k] - v[k]));
    }
    CHECK(vi && v && v[4 * at + 3] > 0.1 && v[4 * at + 3] < 0.9 && err < 1e-4 && side == 0 && vi[4 * at + 3] == 1,
          "draw: a translucent volume in front composited over it", "(alpha in front %.3f, %.2g off)",
          v ? v[4 * at + 3] : 0, err);
    /* a slab below: hidden by the ball, whose pixel is as without it */
    L[1].vol = vl;
    sc.nisos = 1;
    float *b = render_plan(&sc, VSV_RENDER_RAYCAST, &d_b, &cam);
    CHECK(b && !memcmp(b + 4 * at, rc + 4 * at, 16) && b[4 * beside + 3] > 0 && rc[4 * beside + 3] == 0,
          "draw: a volume behind hidden by it, drawn beside it");
    /* the same surface of a field that grows outward: its normals point in,
     * the side seen is shaded alike */
    vsv_volume *vo = make_volume(outside);
    L[1].visible = 0;
    vsv_scene_iso iso2 = {0, 0.25f, {0.9f, 0.5f, 0.2f}};
    sc.isos = &iso2;
    float *d_i = NULL, *in = render_plan(&sc, VSV_RENDER_RAYCAST, &d_i, &cam);
    L[0].vol = vo;
    iso2.value = -0.25f;
    float *d_o = NULL, *o = render_plan(&sc, VSV_RENDER_RAYCAST, &d_o, &cam);
    double most = 0;
    for (int i = 0; in && o && i < 4 * W * H; i++)
        most = fmax(most, fabs(in[i] - o[i]));
    CHECK(in && o && most < 1e-3, "draw: both sides of a surface shaded alike", "(%.3g off)", most);
    free(in), free(d_i), free(o), free(d_o);
    free_volume(vo);
    free(vi), free(v), free(b), free(d_vi), free(d_v), free(d_b);
done:
    free(rc), free(sw), free(d_rc), free(d_sw);
    free_volume(vb), free_volume(va), free_volume(vl);
    vsv_meta_clear(&m);
}

/* An eye at the ball's centre looking east (the surface all around it, half
 * of it behind the eye): every pixel meets it, the middle one at the
 * radius. */
static void test_inside(void)
{
    vsv_meta m;
    vsv_meta_init(&m);
    m.nx = m.ny = m.nz = N;
    m.spacing[0] = m.spacing[1] = m.spacing[2] = 1000;
    m.vert_kind = VSV_VERT_EVEN;
    vsv_volume *vb = make_volume(ball);
    vsv_tf tf;
    char msg[128];
    vsv_tf_parse(&tf, "colormap greys\nrange 0.1 1\nopacity 1 1\n", msg, sizeof msg);
    vsv_layer L = {vb, &tf, 1, 0};
    const vsv_scene_iso iso = {0, 0, {0.9f, 0.5f, 0.2f}};
    vsv_scene sc = {.meta = &m, .layers = &L, .nlayers = 1, .exaggeration = 1, .isos = &iso, .nisos = 1};
    vsv_camera cam = {.pos = {C * 1000, C * 1000, C * 1000},
                      .dir = {1, 0, 0},
                      .up = {0, 0, 1},
                      .fov_deg = 60,
                      .znear = 1,
                      .zfar = 1e7,
                      .width = W,
                      .height = H};
    vsv_render_opts o;
    vsv_render_opts_init(&o);
    o.threads = 2;
    vsv_renderer *r = NULL;
    float *img = malloc(sizeof(float) * 4 * W * H), *depth = malloc(sizeof(float) * W * H);
    if (CHECK(vsv_renderer_create(&o, &r) == 0 && vsv_render(r, &sc, &cam, img, depth) == 0, "inside: rendered")) {
        int all = 1;
        for (int i = 0; i < W * H; i++)
            all &= img[4 * i + 3] == 1;
        const float mid = depth[(H / 2) * W + W / 2];
        CHECK(all && fabs(mid - R * 1000) < 100, "inside: the surface all around, at the radius ahead",
              "(every pixel %s, middle at %.0f m)", all ? "covered" : "not covered", mid);
    }
    vsv_renderer_free(r);
    free(img), free(depth);
    free_volume(vb);
    vsv_meta_clear(&m);
}

/* The boxes vsv_annotate draws, as its placed callback reports them. */
typedef struct boxes {
    int n, bars, box[32][4];
} boxes;
static void on_placed(void *ctx, unsigned part, const int box[4])
{
    boxes *b = ctx;
    b->bars += part == VSV_ANNOT_COLOURBAR;
    if (b->n < 32)
        memcpy(b->box[b->n++], box, sizeof b->box[0]);
}

/* The annotation lists each isosurface under the colour bars: a box of
 * its own (none overlapping) with a swatch of its colour. */
static void test_legend(void)
{
    vsv_meta m;
    vsv_meta_init(&m);
    m.nx = m.ny = m.nz = N;
    m.spacing[0] = m.spacing[1] = m.spacing[2] = 1000;
    m.vert_kind = VSV_VERT_EVEN;
    vsv_meta_add_var(&m, "CLW", "kg/kg", "cloud water");
    vsv_volume *vb = make_volume(ball);
    vsv_tf tf;
    char msg[128];
    vsv_tf_parse(&tf, "colormap greys\nrange 0.1 1\nopacity 1 1\n", msg, sizeof msg);
    vsv_layer L = {vb, &tf, 0.02f, 1};
    const vsv_scene_iso iso = {0, 0, {0.9f, 0.5f, 0.2f}};
    vsv_scene sc = {.meta = &m, .layers = &L, .nlayers = 1, .exaggeration = 1, .isos = &iso, .nisos = 1};
    vsv_font *font = NULL;
    vsv_font_open(NULL, 14, &font, msg, sizeof msg); /* without one: the boxes and swatches only */
    const int species[1] = {0};
    boxes b = {0, 0, {{0}}};
    vsv_annot a = {VSV_ANNOT_COLOURBAR, font, 0, "test.vsv", species, NULL, on_placed, &b};
    vsv_camera cam;
    float *d = NULL, *img = render_plan(&sc, VSV_RENDER_RAYCAST, &d, &cam);
    if (CHECK(img && vsv_annotate(&a, &sc, &cam, img, d) == 0, "legend: annotated")) {
        int overlap = 0;
        for (int i = 0; i < b.n; i++)
            for (int j = i + 1; j < b.n; j++)
                overlap += b.box[i][0] <= b.box[j][2] && b.box[j][0] <= b.box[i][2] && b.box[i][1] <= b.box[j][3] &&
                           b.box[j][1] <= b.box[i][3];
        /* the swatch: a row of the last box, near its right end, in the colour */
        const int *q = b.box[b.n - 1], x = q[2] - 12;
        double off = INFINITY;
        for (int y = q[1]; y <= q[3] && y >= 0 && y < H; y++) {
            const float *px = img + 4 * ((size_t)y * W + x);
            double o = 0;
            for (int k = 0; k < 3; k++)
                o = fmax(o, fabs(px[k] - powf(iso.rgb[k], 2.2f)));
            off = fmin(off, o);
        }
        CHECK(b.bars == 2 && overlap == 0 && off < 1e-6, "legend: an entry for the isosurface, in its colour",
              "(%d colour-bar boxes, %d overlapping, swatch %.3g off)", b.bars, overlap, off);
    }
    free(img), free(d);
    vsv_font_free(font);
    free_volume(vb);
    vsv_meta_clear(&m);
}

int main(void)
{
    test_draw();
    test_inside();
    test_legend();
    return vsv_test_done();
}
