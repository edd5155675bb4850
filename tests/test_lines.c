/* test_lines.c — lines drawn in a scene (vsv_scene.lines, issue 35): a
 * tube seen side-on covers a band two radii wide, lit brighter on the
 * light's side; its arrowhead is wider and ends at the last point; a tube
 * above the ground or an isosurface hides it and one below is hidden
 * (depth compositing with the other surfaces); the shear-warp hands
 * such frames to the raycaster; wind arrows on a slice point along the
 * wind. */
#include "vsv_format.h"
#include "vsv_render.h"
#include "vsv_testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { N = 40, W = 200, H = 200 };

static void grid(vsv_meta *m)
{
    vsv_meta_init(m);
    m->nx = m->ny = m->nz = N;
    m->spacing[0] = m->spacing[1] = m->spacing[2] = 1000;
    m->vert_kind = VSV_VERT_EVEN;
}

/* Renders sc from cam with renderer kind: rgba and depth, new (NULL on
 * failure). */
static float *render(const vsv_scene *sc, const vsv_camera *cam, int kind, float **depth)
{
    vsv_render_opts o;
    vsv_render_opts_init(&o);
    o.kind = kind;
    o.threads = 2;
    vsv_renderer *r = NULL;
    float *img = malloc(sizeof(float) * 4 * W * H);
    *depth = malloc(sizeof(float) * W * H);
    if (vsv_renderer_create(&o, &r) || vsv_render(r, sc, cam, img, *depth)) {
        free(img), free(*depth);
        img = NULL, *depth = NULL;
    }
    vsv_renderer_free(r);
    return img;
}

/* An orthographic camera from the south, 40 km high (200 m a pixel),
 * centred on (20 km, -, 20 km). */
static void side_camera(vsv_camera *cam)
{
    memset(cam, 0, sizeof *cam);
    cam->pos[0] = 20000, cam->pos[1] = -100000, cam->pos[2] = 20000;
    cam->dir[1] = 1, cam->up[2] = 1;
    cam->ortho_height = 40000;
    cam->zfar = 1e9;
    cam->width = W, cam->height = H;
}

/* Rows of column px whose pixel is opaque: count, first, last. */
static int band(const float *img, int px, int *y0, int *y1)
{
    int n = 0;
    *y0 = H, *y1 = -1;
    for (int y = 0; y < H; y++)
        if (img[4 * ((size_t)y * W + px) + 3] == 1) {
            n++;
            *y0 = y < *y0 ? y : *y0, *y1 = y;
        }
    return n;
}

static void test_tube(void)
{
    vsv_meta m;
    grid(&m);
    /* along x at y = 20 km, z = 20 km, radius 1 km: 10 pixels across */
    const double pts[] = {5000, 20000, 20000, 15000, 20000, 20000, 30000, 20000, 20000};
    vsv_scene_line L = {pts, 3, 1000, 0, {0.8f, 0.8f, 0.8f}};
    vsv_scene sc = {.meta = &m, .exaggeration = 1, .lines = &L, .nlines = 1};
    vsv_scene_sun(&sc, 180, 90); /* the sun overhead */
    vsv_camera cam;
    side_camera(&cam);
    float *d_rc = NULL, *d_sw = NULL, *rc = render(&sc, &cam, VSV_RENDER_RAYCAST, &d_rc),
          *sw = render(&sc, &cam, VSV_RENDER_SHEARWARP, &d_sw);
    if (!CHECK(rc && sw, "tube: rendered"))
        goto done;
    const double pix = cam.ortho_height / H;
    int y0, y1, worst = 0;
    for (int px = 40; px <= 140; px += 10) { /* x 12 .. 32 km: 10 .. 30 km along it */
        const int n = band(rc, px, &y0, &y1);
        worst = abs(n - (int)lround(2 * L.radius / pix)) > abs(worst) ? n - (int)lround(2 * L.radius / pix) : worst;
    }
    CHECK(abs(worst) <= 1, "tube: a band two radii wide seen side-on, within a pixel", "(%+d pixels off 10)", worst);
    band(rc, 100, &y0, &y1);
    const float top = rc[4 * ((size_t)(y0 + 1) * W + 100)], bottom = rc[4 * ((size_t)(y1 - 1) * W + 100)];
    CHECK(top > 1.5f * bottom && bottom > 0, "tube: lit, brighter on the sun's side", "(top %.3f, bottom %.3f)", top,
          bottom);
    const double mid = d_rc[(size_t)((y0 + y1) / 2) * W + 100], want = 100000 + 20000 - 1000;
    CHECK(fabs(mid - want) < 80, "tube: its near side at its depth (an octagon's: within 80 m)", "(%.0f for %.0f)", mid,
          want);
    /* pixel px's centre at x = 20 km + (px + 0.5 - W / 2) 200 m: the ends at 24.5 and 149.5 */
    const int past = band(rc, 152, &y0, &y1) + band(rc, 22, &y0, &y1);
    CHECK(past == 0 && band(rc, 27, &y0, &y1) > 0 && band(rc, 147, &y0, &y1) > 0,
          "tube: from its first point to its last, no further");
    CHECK(!memcmp(rc, sw, sizeof(float) * 4 * W * H) && !memcmp(d_rc, d_sw, sizeof(float) * W * H),
          "tube: the shear-warp's pixels are the raycaster's (such frames are raycast)");
    /* with an arrowhead: 2.5 radii wide at its base, 6 long, its tip at the last point */
    L.arrow = 1;
    free(d_sw), free(sw);
    sw = render(&sc, &cam, VSV_RENDER_RAYCAST, &d_sw);
    const int tipx = (int)lround((30000 - 20000) / pix + W / 2.0 - 0.5);
    const int base = sw ? band(sw, tipx - (int)(6 * L.radius / pix) + 1, &y0, &y1) : 0,
              shaft = sw ? band(sw, 80, &y0, &y1) : 0, beyond = sw ? band(sw, tipx + 2, &y0, &y1) : 1;
    CHECK(base >= 2 * 2.5 * L.radius / pix - 3 && shaft == 10 && beyond == 0,
          "tube: an arrowhead 2.5 radii wide at its base, its tip at the last point",
          "(base %d pixels, shaft %d, past the tip %d)", base, shaft, beyond);
done:
    free(rc), free(sw), free(d_rc), free(d_sw);
    vsv_meta_clear(&m);
}

/* The ground at 5 km: a tube above it hides it, one below it is hidden. */
static void test_depth(void)
{
    vsv_meta m;
    grid(&m);
    m.terrain = malloc(sizeof(float) * N * N);
    for (int c = 0; c < N * N; c++)
        m.terrain[c] = 5000;
    double pts[] = {5000, 20000, 8000, 35000, 20000, 8000};
    vsv_scene_line L = {pts, 2, 1000, 1, {1, 0, 0}};
    vsv_scene sc = {.meta = &m, .exaggeration = 1, .show_terrain = 1, .lines = &L};
    vsv_camera cam;
    vsv_camera_plan(&cam, &sc, W, H);
    float *d0, *d1, *d2, *bare = render(&sc, &cam, VSV_RENDER_RAYCAST, &d0);
    sc.nlines = 1;
    float *over = render(&sc, &cam, VSV_RENDER_RAYCAST, &d1);
    pts[2] = pts[5] = 2000;
    float *under = render(&sc, &cam, VSV_RENDER_RAYCAST, &d2);
    if (CHECK(bare && over && under, "depth: rendered")) {
        const double pix = cam.ortho_height / H;
        const int px = (int)floor((20000 - cam.pos[0]) / pix + W / 2.0),
                  py = (int)floor(H / 2.0 - (20000 - cam.pos[1]) / pix);
        const size_t at = (size_t)py * W + px;
        CHECK(over[4 * at] > 0.9f && over[4 * at + 1] < 0.05f && fabs(d1[at] - (cam.pos[2] - 9000)) < 30 &&
                  fabs(d0[at] - (cam.pos[2] - 5000)) < 30,
              "depth: a tube above the ground hides it", "(red %.2f green %.2f at depth %.0f, ground at %.0f)",
              over[4 * at], over[4 * at + 1], d1[at], d0[at]);
        CHECK(!memcmp(under, bare, sizeof(float) * 4 * W * H) && !memcmp(d2, d0, sizeof(float) * W * H),
              "depth: a tube under the ground hidden by it");
    }
    free(bare), free(over), free(under), free(d0), free(d1), free(d2);
    vsv_meta_clear(&m);
}

/* An isosurface: the plane z = 20 km (a field equal to its level's index
 * in km, at 20); a tube above it hides it, one below it is hidden. */
static void test_iso(void)
{
    vsv_meta m;
    grid(&m);
    vsv_volume v = {0};
    v.nx = v.ny = v.nz = N, v.brick = 64, v.shift = 6, v.bdim[0] = v.bdim[1] = v.bdim[2] = 1, v.nbricks = 1;
    float *p = calloc(64 * 64 * 64, sizeof(float)), *bricks[1] = {p}, bmin = 0, bmax = N - 1;
    for (int k = 0; k < N; k++)
        for (int j = 0; j < N; j++)
            for (int i = 0; i < N; i++)
                p[i + 64 * (j + 64 * k)] = (float)k;
    v.bricks = bricks, v.bmin = &bmin, v.bmax = &bmax, v.gen = vsv_volume_new_gen();
    vsv_tf tf;
    char msg[128];
    vsv_tf_parse(&tf, "colormap greys\nrange 0 40\nopacity 0 0\n", msg, sizeof msg);
    vsv_layer layer = {&v, &tf, 0, 0};
    const vsv_scene_iso iso = {0, 20, {0, 0, 1}};
    double pts[] = {5000, 20000, 25000, 35000, 20000, 25000};
    vsv_scene_line L = {pts, 2, 1000, 0, {1, 0, 0}};
    vsv_scene sc = {
        .meta = &m, .layers = &layer, .nlayers = 1, .exaggeration = 1, .isos = &iso, .nisos = 1, .lines = &L};
    vsv_camera cam;
    vsv_camera_plan(&cam, &sc, W, H);
    float *d0, *d1, *d2, *bare = render(&sc, &cam, VSV_RENDER_RAYCAST, &d0);
    sc.nlines = 1;
    float *over = render(&sc, &cam, VSV_RENDER_RAYCAST, &d1);
    pts[2] = pts[5] = 15000;
    float *under = render(&sc, &cam, VSV_RENDER_RAYCAST, &d2);
    if (CHECK(bare && over && under, "iso: rendered")) {
        const double pix = cam.ortho_height / H;
        const int px = (int)floor((20000 - cam.pos[0]) / pix + W / 2.0),
                  py = (int)floor(H / 2.0 - (20000 - cam.pos[1]) / pix);
        const size_t at = (size_t)py * W + px;
        CHECK(bare[4 * at + 2] > 0.5f && over[4 * at] > 0.9f && over[4 * at + 2] < 0.05f &&
                  fabs(d1[at] - (cam.pos[2] - 26000)) < 30,
              "iso: a tube above an isosurface hides it", "(blue %.2f bare; red %.2f blue %.2f over it, depth %.0f)",
              bare[4 * at + 2], over[4 * at], over[4 * at + 2], d1[at]);
        CHECK(!memcmp(under, bare, sizeof(float) * 4 * W * H) && !memcmp(d2, d0, sizeof(float) * W * H),
              "iso: a tube under it hidden by it");
    }
    free(bare), free(over), free(under), free(d0), free(d1), free(d2), free(p);
    vsv_meta_clear(&m);
}

/* A uniform wind from the west (10 m/s east, 5 north) on an even grid: its
 * arrows on a slice, every 4th column, point east-north-east, 10 * 60 m
 * east and 5 * 60 north of their tails; drawn due east, each head is east
 * of its tail in a plan view. */
static void test_arrows(void)
{
    vsv_meta m;
    grid(&m);
    vsv_volume ve = {0}, vn = {0};
    float *e = malloc(sizeof(float) * N * N * N), *n = malloc(sizeof(float) * N * N * N);
    float *be[27], *bn[27];
    for (int i = 0; i < N * N * N; i++)
        e[i] = 10, n[i] = 5;
    /* one brick of 64 over the whole grid */
    ve.nx = vn.nx = ve.ny = vn.ny = ve.nz = vn.nz = N;
    ve.brick = vn.brick = 64, ve.shift = vn.shift = 6;
    ve.bdim[0] = ve.bdim[1] = ve.bdim[2] = vn.bdim[0] = vn.bdim[1] = vn.bdim[2] = 1;
    ve.nbricks = vn.nbricks = 1;
    float *pe = calloc(64 * 64 * 64, sizeof(float)), *pn = calloc(64 * 64 * 64, sizeof(float));
    for (int k = 0; k < N; k++)
        for (int j = 0; j < N; j++)
            for (int i = 0; i < N; i++)
                pe[i + 64 * (j + 64 * k)] = e[0], pn[i + 64 * (j + 64 * k)] = n[0];
    be[0] = pe, bn[0] = pn;
    ve.bricks = be, vn.bricks = bn;
    double xyz[6 * 100], fastest = 0;
    int na = 0;
    const int rc = vsv_wind_arrows(&m, &ve, &vn, 10500, 4, 60, xyz, 100, &na, &fastest);
    double off = 0;
    for (int a = 0; a < na; a++)
        off = fmax(off, fabs(xyz[6 * a + 3] - xyz[6 * a] - 600) + fabs(xyz[6 * a + 4] - xyz[6 * a + 1] - 300) +
                            fabs(xyz[6 * a + 5] - 10500) + fabs(xyz[6 * a + 2] - 10500));
    CHECK(rc == 0 && na == 100 && off < 1e-6 && fabs(fastest - sqrt(125)) < 1e-4,
          "arrows: every 4th column, along the wind, as far as it goes in the time", "(%d arrows, %.3g off, %.3f m/s)",
          na, off, fastest);
    /* drawn: in each arrow's row of pixels, the wide head lies east of the tail */
    vsv_scene_line lines[100];
    for (int a = 0; a < na; a++) {
        lines[a] = (vsv_scene_line){xyz + 6 * a, 2, 100, 1, {1, 1, 0}};
        xyz[6 * a + 3] = xyz[6 * a] + 3000, xyz[6 * a + 4] = xyz[6 * a + 1]; /* due east, 3 km */
    }
    vsv_scene sc = {.meta = &m, .exaggeration = 1, .lines = lines, .nlines = na};
    vsv_camera cam; /* looking down on 16 km around (20 km, 20 km): 80 m a pixel */
    memset(&cam, 0, sizeof cam);
    cam.pos[0] = cam.pos[1] = 20000, cam.pos[2] = 100000;
    cam.dir[2] = -1, cam.up[1] = 1;
    cam.ortho_height = 16000, cam.zfar = 1e9, cam.width = W, cam.height = H;
    float *d = NULL, *img = render(&sc, &cam, VSV_RENDER_RAYCAST, &d);
    int east = 0, tested = 0;
    const double pix = cam.ortho_height / H;
    for (int a = 0; img && a < na; a++) {
        const double tx = (xyz[6 * a] - cam.pos[0]) / pix + W / 2.0 - 0.5,
                     ty = H / 2.0 - 0.5 - (xyz[6 * a + 1] - cam.pos[1]) / pix;
        if (tx < 2 || tx + 3000 / pix + 2 >= W || ty < 4 || ty + 4 >= H)
            continue;
        /* the widest column of the arrow (its head's base, 2.4 km along):
         * nearer the tip than the tail */
        int widest = 0, wx = 0;
        for (int x = (int)tx; x <= (int)(tx + 3000 / pix); x++) {
            int w = 0;
            for (int y = (int)ty - 3; y <= (int)ty + 3; y++)
                w += img[4 * ((size_t)y * W + x) + 3] == 1;
            if (w > widest)
                widest = w, wx = x;
        }
        tested++;
        east += wx > tx + 1500 / pix;
    }
    CHECK(tested == 9 && east == tested, "arrows: each head east of its tail in plan view", "(%d of %d)", east, tested);
    free(img), free(d), free(e), free(n), free(pe), free(pn);
    vsv_meta_clear(&m);
}

int main(void)
{
    test_tube();
    test_depth();
    test_iso();
    test_arrows();
    return vsv_test_done();
}
