/* test_light.c — lighting and slices (issue 20) against analytic volumes:
 * a lit cone-shaped sphere is brighter on the side facing the light by the
 * shading rule's amount in both renderers, a uniform slab is unchanged by
 * lighting; a linear field's slices show the linear colour ramp, and a
 * horizontal slice of native levels with per-column heights shows the
 * value at its height; a curtain's range on grids of extreme spacing takes
 * a column per cell crossed. */
#include "vsv_format.h"
#include "vsv_geo.h"
#include "vsv_render.h"
#include "vsv_renderer.h"
#include "vsv_testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { N = 40, B = 16, W = 200, H = 200 };

/* An in-memory volume of nx x ny x nz cells of f(i, j, k). */
static vsv_volume *make_volume(int nx, int ny, int nz, double (*f)(int, int, int))
{
    vsv_volume *v = calloc(1, sizeof *v);
    v->nx = nx, v->ny = ny, v->nz = nz, v->brick = B, v->shift = 4;
    v->bdim[0] = (nx + B - 1) / B, v->bdim[1] = (ny + B - 1) / B, v->bdim[2] = (nz + B - 1) / B;
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
                for (int i = 0; i < B; i++) {
                    const int gi = i0 + i, gj = j0 + j, gk = k0 + k;
                    const float x = f && gi < nx && gj < ny && gk < nz ? (float)f(gi, gj, gk) : 0;
                    p[i + B * (j + B * k)] = x;
                    if (gi < nx && gj < ny && gk < nz) {
                        v->bmin[b] = fminf(v->bmin[b], x);
                        v->bmax[b] = fmaxf(v->bmax[b], x);
                    }
                }
    }
    return v;
}

static void free_volume(vsv_volume *v)
{
    for (int b = 0; v && b < v->nbricks; b++)
        free(v->bricks[b]);
    if (v) {
        free(v->bricks);
        free(v->bmin);
        free(v->bmax);
    }
    free(v);
}

static void grid(vsv_meta *m, int nx, int ny, int nz, double dz)
{
    vsv_meta_init(m);
    m->nx = nx, m->ny = ny, m->nz = nz;
    m->spacing[0] = m->spacing[1] = 1000;
    m->spacing[2] = dz;
    m->origin[2] = dz / 2;
    m->vert_kind = VSV_VERT_EVEN;
}

static double cone(int i, int j, int k)
{
    const double c = (N - 1) / 2.0, R = 12;
    return 1 - sqrt((i - c) * (i - c) + (j - c) * (j - c) + (k - c) * (k - c)) / R;
}
static double uniform(int i, int j, int k) { return (void)i, (void)j, (void)k, 0.5; }
static double comb(int i, int j, int k) { return (void)j, (void)k, i % 3 ? 0 : 0.5; }

/* Renders sc from straight above (orthographic, the domain filling the
 * image) with renderer kind; a new image. */
static float *render_plan(const vsv_scene *sc, int kind)
{
    vsv_render_opts o;
    vsv_render_opts_init(&o);
    o.kind = kind;
    o.threads = 2;
    vsv_renderer *r = NULL;
    vsv_camera cam;
    vsv_camera_plan(&cam, sc, W, H);
    float *img = malloc(sizeof(float) * 4 * W * H);
    if (vsv_renderer_create(&o, &r) || vsv_render(r, sc, &cam, img, NULL)) {
        free(img);
        img = NULL;
    }
    vsv_renderer_free(r);
    return img;
}

static double psnr(const float *a, const float *b)
{
    double se = 0;
    for (int i = 0; i < 4 * W * H; i++) {
        const double d = fmin(1, a[i]) - fmin(1, b[i]);
        se += d * d;
    }
    return se > 0 ? 10 * log10(4.0 * W * H / se) : INFINITY;
}

/* The luminance (mean of rgb) of the pixel over grid cell (i, j) in a plan view. */
static double lum_at(const float *img, const vsv_scene *sc, double i, double j)
{
    vsv_camera cam;
    vsv_camera_plan(&cam, sc, W, H);
    const double x = sc->meta->origin[0] + i * sc->meta->spacing[0], y = sc->meta->origin[1] + j * sc->meta->spacing[1];
    const double wh = cam.ortho_height, ww = wh * W / H;
    const int px = (int)floor((x - cam.pos[0]) / ww * W + W / 2.0),
              py = (int)floor(H / 2.0 - (y - cam.pos[1]) / wh * H);
    const float *p = img + 4 * ((size_t)py * W + px);
    return (p[0] + p[1] + p[2]) / 3;
}

/* A ball of density 1 - r/R (R = 12 cells), nearly opaque from its edge,
 * lit from the east and seen from above: over the cell half a radius east
 * of the centre the surface's normal makes 60 degrees with the light (n.L =
 * 1/2), half a radius west 120 degrees (n.L < 0): the lit image over the
 * unlit one is AMBIENT + DIFFUSE / 2 there, AMBIENT here, in both
 * renderers; a uniform slab is the same lit and unlit. */
static void test_lit_sphere(void)
{
    vsv_meta m;
    grid(&m, N, N, N, 1000);
    vsv_volume *v = make_volume(N, N, N, cone), *u = make_volume(N, N, N, uniform);
    vsv_tf tf;
    char msg[128];
    CHECK(vsv_tf_parse(&tf, "colormap greys\nrange 0.02 1\nopacity 1 1\n", msg, sizeof msg) == 0, "light: tf");
    vsv_layer L = {v, &tf, 30, 1};
    vsv_scene sc = {.meta = &m, .layers = &L, .nlayers = 1, .exaggeration = 1, .show_terrain = 0};
    const double c = (N - 1) / 2.0;
    const double east = VSV_LIGHT_AMBIENT + VSV_LIGHT_DIFFUSE * 0.5, west = VSV_LIGHT_AMBIENT;
    float *img[2][2] = {{NULL, NULL}, {NULL, NULL}}; /* [renderer][lit] */
    for (int kind = 0; kind < 2; kind++) {
        const char *name = kind ? "shear-warp" : "raycaster";
        sc.light = 0;
        img[kind][0] = render_plan(&sc, kind);
        sc.light = 1;
        sc.light_dir[0] = 1, sc.light_dir[1] = 0, sc.light_dir[2] = 0;
        img[kind][1] = render_plan(&sc, kind);
        if (!CHECK(img[kind][0] && img[kind][1], "light: renders"))
            continue;
        const double re = lum_at(img[kind][1], &sc, c + 6, c) / lum_at(img[kind][0], &sc, c + 6, c);
        const double rw = lum_at(img[kind][1], &sc, c - 6, c) / lum_at(img[kind][0], &sc, c - 6, c);
        char what[160];
        snprintf(what, sizeof what, "light (%s): the side facing the light %.3f of unlit, the far side %.3f", name,
                 east, west);
        CHECK(fabs(re - east) < 0.04 && fabs(rw - west) < 0.04, what, "east %.4f west %.4f", re, rw);
        /* north and south of the centre the normal is across the light: n.L = 0 */
        const double rn = lum_at(img[kind][1], &sc, c, c + 6) / lum_at(img[kind][0], &sc, c, c + 6);
        CHECK(fabs(rn - west) < 0.06, "light: across the light only the ambient part", "%s north %.4f", name, rn);
    }
    if (img[0][1] && img[1][1]) {
        const double lit = psnr(img[0][1], img[1][1]), unlit = psnr(img[0][0], img[1][0]);
        printf("light: raycaster against shear-warp, PSNR lit %.1f dB, unlit %.1f dB\n", lit, unlit);
        CHECK(lit > 25 && lit > unlit - 1, "light: raycaster and shear-warp agree on the lit ball as well as unlit",
              "PSNR lit %.1f dB (unlit %.1f dB)", lit, unlit);
    }
    for (int k = 0; k < 2; k++)
        for (int l = 0; l < 2; l++)
            free(img[k][l]);
    /* a uniform slab: no gradient, so lighting changes nothing at all */
    L.vol = u;
    L.opacity = 0.05f;
    for (int kind = 0; kind < 2; kind++) {
        sc.light = 0;
        float *a = render_plan(&sc, kind);
        sc.light = 1;
        float *b = render_plan(&sc, kind);
        double d = a && b ? 0 : INFINITY, alpha = 0;
        for (int i = 0; a && b && i < 4 * W * H; i++) {
            d = fmax(d, fabs(a[i] - b[i]));
            alpha = fmax(alpha, a[i]);
        }
        CHECK(d < 1e-6 && alpha > 0.5, "light: a uniform slab's colour and transmittance unchanged by lighting",
              "%s: max difference %g (alpha %g)", kind ? "shear-warp" : "raycaster", d, alpha);
        free(a);
        free(b);
    }
    free_volume(v);
    free_volume(u);
}

/* A linear field 0.2 + 0.6 i / (N - 1) + 0.1 k / (N - 1): a horizontal
 * slice seen from above and a vertical one (along j = const) seen from the
 * south show, pixel by pixel, the colour map's colour of the field's value
 * where the pixel's ray meets the slice; nothing else is drawn. */
static void test_slice_linear(void)
{
    vsv_meta m;
    grid(&m, N, N, N, 500);
    vsv_volume *v = make_volume(N, N, N, NULL);
    for (int b = 0; b < v->nbricks; b++) { /* the field, filled here (make_volume's f is per cell) */
        const int i0 = b % v->bdim[0] * B, k0 = b / (v->bdim[0] * v->bdim[1]) * B;
        for (int k = 0; k < B; k++)
            for (int j = 0; j < B; j++)
                for (int i = 0; i < B; i++)
                    v->bricks[b][i + B * (j + B * k)] =
                        (float)(0.2 + 0.6 * (i0 + i) / (N - 1) + 0.1 * (k0 + k) / (N - 1));
    }
    vsv_tf tf;
    char msg[128];
    CHECK(vsv_tf_parse(&tf, "colormap viridis\nrange 0 1\nopacity 0 1\n", msg, sizeof msg) == 0, "slice: tf");
    vsv_layer L = {v, &tf, 1, 0}; /* hidden: only the slice shows */
    vsv_slice s[2];
    CHECK(vsv_slice_parse(&m, "z=10000m", &s[0], msg, sizeof msg) == 0 && s[0].kind == VSV_SLICE_Z && s[0].z == 10000,
          "slice: z=10000m parsed", "%s", msg);
    vsv_scene sc = {.meta = &m,
                    .layers = &L,
                    .nlayers = 1,
                    .exaggeration = 1,
                    .show_terrain = 0,
                    .slices = s,
                    .nslices = 1,
                    .slice_layer = 0};
    for (int view = 0; view < 2; view++) {
        vsv_camera cam;
        if (view == 0) {
            vsv_camera_plan(&cam, &sc, W, H);
        } else {
            s[0].kind = VSV_SLICE_CURTAIN; /* along y = 15 km, across the grid */
            s[0].npts = 2;
            s[0].xy[0][0] = -5000, s[0].xy[0][1] = 15000, s[0].xy[1][0] = 45000, s[0].xy[1][1] = 15000;
            vsv_camera_fit(&cam, &sc, 180, 10, W, H);
        }
        /* the slices' own range: the values they show (issue 32) */
        double rlo, rhi;
        const double kz = (10000 - 250) / 500.0;
        const double want_lo = view ? 0.2 : 0.2 + 0.1 * kz / (N - 1), want_hi = view ? 0.9 : 0.8 + 0.1 * kz / (N - 1);
        CHECK(vsv_slice_range(&sc, &rlo, &rhi) == 0 && fabs(rlo - want_lo) < 1e-5 && fabs(rhi - want_hi) < 1e-5,
              view ? "slice range: a curtain's values, every level (0.2 .. 0.9)"
                   : "slice range: a horizontal slice's values at its height (0.24 .. 0.84)",
              "%g .. %g, wanted %g .. %g", rlo, rhi, want_lo, want_hi);
        vsv_render_opts o;
        vsv_render_opts_init(&o);
        o.kind = view ? VSV_RENDER_SHEARWARP : VSV_RENDER_RAYCAST; /* sliced frames are raycast either way */
        vsv_renderer *r = NULL;
        float *img = malloc(sizeof(float) * 4 * W * H);
        if (!CHECK(!vsv_renderer_create(&o, &r) && !vsv_render(r, &sc, &cam, img, NULL), "slice: renders")) {
            vsv_renderer_free(r);
            free(img);
            continue;
        }
        vsv_geo g;
        vsv_scene_geo(&sc, &g);
        int on = 0, bad = 0, off_bad = 0;
        double worst = 0;
        for (int py = 0; py < H; py++)
            for (int px = 0; px < W; px++) {
                double o3[3], d[3], t0, t1;
                vsv_pixel_ray(&cam, px, py, o3, d);
                const float *p = img + 4 * ((size_t)py * W + px);
                double t = INFINITY;
                if (vsv_box_hit(o3, d, g.bmin, g.bmax, &t0, &t1)) {
                    if (view == 0) {
                        t = (10000 - o3[2]) / d[2];
                    } else {
                        t = (15000 - o3[1]) / d[1];
                        const double x = o3[0] + t * d[0];
                        if (x < g.bmin[0] || x > g.bmax[0])
                            t = INFINITY;
                    }
                    if (!(t >= t0 && t <= t1))
                        t = INFINITY;
                }
                if (t == INFINITY) {
                    off_bad += p[3] != 0;
                    continue;
                }
                /* away from the slice's edges (a pixel there may be half off) */
                const double x = o3[0] + t * d[0], z = o3[2] + t * d[2];
                const double ci = x / 1000, ck = (z - 250) / 500;
                if (ci < 1 || ci > N - 2 || ck < 1 || ck > N - 2)
                    continue;
                const double want = 0.2 + 0.6 * ci / (N - 1) + 0.1 * ck / (N - 1);
                float rgba[4];
                vsv_tf_eval(&tf, (float)want, rgba);
                double e = 0;
                for (int ch = 0; ch < 3; ch++)
                    e = fmax(e, fabs(p[ch] - rgba[ch]));
                on++;
                bad += e > 1.0 / 255 || p[3] != 1;
                worst = fmax(worst, e);
            }
        char what[160];
        snprintf(what, sizeof what, "slice: a linear field's %s slice shows the colour ramp of its values",
                 view ? "vertical" : "horizontal");
        CHECK(on > 2000 && bad == 0, what, "%d of %d pixels off (worst %.4f)", bad, on, worst);
        CHECK(off_bad == 0, "slice: nothing drawn off the slice", "%d pixels", off_bad);
        vsv_renderer_free(r);
        free(img);
    }
    /* bad slices: clear reasons */
    CHECK(vsv_slice_parse(&m, "z=90000", &s[0], msg, sizeof msg) == VSV_EINVAL &&
              strstr(msg, "outside the grid's heights"),
          "slice: a height above the grid is refused", "%s", msg);
    CHECK(vsv_slice_parse(&m, "height=3", &s[0], msg, sizeof msg) == VSV_EINVAL && strstr(msg, "expected z=HEIGHT"),
          "slice: an unknown kind is refused", "%s", msg);
    CHECK(vsv_slice_parse(&m, "z=12x", &s[0], msg, sizeof msg) == VSV_EINVAL, "slice: a malformed height is refused",
          "%s", msg);
    free_volume(v);
}

/* Native levels with per-column heights (the ground rising from 0 to 1950 m
 * west to east, levels 250 m apart above it), holding their own height: a
 * slice at 3000 m shows 3000's colour wherever the ground is below it, seen
 * from above. */
static void test_slice_heights(void)
{
    enum { NZ = 20 };
    vsv_meta m;
    grid(&m, N, N, NZ, 250);
    m.vert_kind = VSV_VERT_NATIVE;
    vsv_meta_alloc_levels(&m);
    vsv_meta_alloc_terrain(&m);
    float *z = malloc(sizeof(float) * N * N * NZ);
    for (int k = 0; k < NZ; k++)
        for (int j = 0; j < N; j++)
            for (int i = 0; i < N; i++) {
                m.terrain[j * N + i] = (float)(50.0 * i);
                z[(size_t)k * N * N + j * N + i] = (float)(50.0 * i + 125 + 250 * k);
            }
    for (int k = 0; k < NZ; k++)
        m.levels[k] = 125 + 975 + 250 * k;
    if (!CHECK(vsv_meta_add_heights(&m, 0, z, NULL, NULL) == 0, "slice: per-column heights")) {
        free(z);
        vsv_meta_clear(&m);
        return;
    }
    vsv_volume *v = make_volume(N, N, NZ, NULL);
    for (int b = 0; b < v->nbricks; b++) {
        const int i0 = b % v->bdim[0] * B, j0 = b / v->bdim[0] % v->bdim[1] * B, k0 = b / (v->bdim[0] * v->bdim[1]) * B;
        for (int k = 0; k < B; k++)
            for (int j = 0; j < B; j++)
                for (int i = 0; i < B; i++)
                    if (i0 + i < N && j0 + j < N && k0 + k < NZ)
                        v->bricks[b][i + B * (j + B * k)] = z[(size_t)(k0 + k) * N * N + (j0 + j) * N + i0 + i];
        v->bmin[b] = 0, v->bmax[b] = 10000;
    }
    vsv_tf tf;
    char msg[128];
    vsv_tf_parse(&tf, "colormap viridis\nrange 0 6000\nopacity 0 1\n", msg, sizeof msg);
    vsv_layer L = {v, &tf, 1, 0};
    vsv_slice s;
    const int prc = vsv_slice_parse(&m, "z=3000", &s, msg, sizeof msg);
    vsv_scene sc = {.meta = &m,
                    .layers = &L,
                    .nlayers = 1,
                    .exaggeration = 1,
                    .show_terrain = 1,
                    .slices = &s,
                    .nslices = 1,
                    .slice_layer = 0};
    float *img = prc ? NULL : render_plan(&sc, VSV_RENDER_RAYCAST);
    float want[4];
    vsv_tf_eval(&tf, 3000, want);
    int on = 0, bad = 0;
    double worst = 0;
    for (int j = 2; img && j < N - 2; j += 3)
        for (int i = 2; i < N - 2; i++) { /* ground (50 i) and lowest level (50 i + 125) below 3000 m */
            vsv_camera cam;
            vsv_camera_plan(&cam, &sc, W, H);
            const double wh = cam.ortho_height, ww = wh * W / H;
            const int px = (int)floor((i * 1000.0 - cam.pos[0]) / ww * W + W / 2.0);
            const int py = (int)floor(H / 2.0 - (j * 1000.0 - cam.pos[1]) / wh * H);
            const float *p = img + 4 * ((size_t)py * W + px);
            double e = 0;
            for (int ch = 0; ch < 3; ch++)
                e = fmax(e, fabs(p[ch] - want[ch]));
            on++;
            bad += e > 1.0 / 255;
            worst = fmax(worst, e);
        }
    CHECK(img && on > 100 && bad == 0, "slice: z=3000 on native levels with per-column heights shows 3000 m's value",
          "%d of %d columns off (worst %.4f)%s", bad, on, worst, prc ? msg : "");
    free(img);
    free(z);
    free_volume(v);
    vsv_meta_clear(&m);
}

/* A uniform slab (value 0.5 everywhere, 10 levels of 1 km) seen at 30
 * degrees from straight down, orthographic, a transfer function of range
 * 0.2 .. 1 with opacity 0 .. 1 (0.375 at 0.5): where a pixel's ray enters
 * the top and leaves the bottom, away from the sides, the pixel is the
 * closed form of emission and absorption, alpha = 1 - exp(-sigma L) with
 * sigma = opacity * 0.375 * 3 / dx per metre and L the ray's length in the
 * box (11.5 km, 15.4 raycaster steps of 750 m: the part step counts by its
 * length), and rgb = the colour map's colour at 0.5 times alpha. A thick
 * slab stops its rays at the first sample whose transmittance falls below
 * the renderer's 1/512: steps of 250 m, 0.2 optical depth each, stop after
 * 32 (alpha 1 - exp(-6.4)), not at the bottom (1 - exp(-9.24)). On a
 * log scale of range 0.01 .. 100 the opacity at 0.5 is ln 50 / ln 10^4. */
static void test_slab_closed_form(void)
{
    enum { NZ = 10 };
    vsv_meta m;
    grid(&m, N, N, NZ, 1000);
    vsv_volume *u = make_volume(N, N, NZ, uniform);
    vsv_tf tf, tflog;
    char msg[128];
    CHECK(vsv_tf_parse(&tf, "colormap viridis\nrange 0.2 1\nopacity 0 1\n", msg, sizeof msg) == 0 &&
              vsv_tf_parse(&tflog, "colormap viridis\nscale log\nrange 0.01 100\nopacity 0 1\n", msg, sizeof msg) == 0,
          "slab: tf", "%s", msg);
    vsv_layer L = {u, &tf, 0.08f, 1};
    vsv_scene sc = {.meta = &m, .layers = &L, .nlayers = 1, .exaggeration = 1, .show_terrain = 0};
    vsv_geo g;
    vsv_scene_geo(&sc, &g);
    const double th = 30 * M_PI / 180, D = 100000;
    vsv_camera cam;
    memset(&cam, 0, sizeof cam);
    cam.dir[1] = sin(th), cam.dir[2] = -cos(th);
    cam.up[1] = cos(th), cam.up[2] = sin(th);
    for (int a = 0; a < 3; a++)
        cam.pos[a] = 0.5 * (g.bmin[a] + g.bmax[a]) - D * cam.dir[a];
    cam.ortho_height = 60000;
    cam.width = W, cam.height = H;
    static const struct {
        int kind, log;
        float opacity;
        double step, tol;
        const char *name;
    } runs[] = {
        {VSV_RENDER_RAYCAST, 0, 0.08f, 0.75, 1e-5,
         "slab: the raycaster's pixels are 1 - exp(-sigma L) of the colour at 0.5, "
         "L the ray's length in the box (a part step by its length)"},
        {VSV_RENDER_SHEARWARP, 0, 0.08f, 0.5, 5e-4,
         "slab: shear-warp's pixels are 1 - exp(-sigma L) of the colour at 0.5, "
         "L the slices' spacing along the oblique ray"},
        {VSV_RENDER_RAYCAST, 0, 0.8f / 3 / 0.375f, 0.25, 1e-5,
         "slab: a thick slab's rays stop at the first sample "
         "below 1/512 transmittance: alpha 1 - exp(-6.4)"},
        {VSV_RENDER_RAYCAST, 1, 0.08f, 0.75, 1e-5,
         "slab: the raycaster on a log scale 0.01 .. 100: opacity "
         "ln 50 / ln 10^4 at 0.5"},
        {VSV_RENDER_SHEARWARP, 1, 0.08f, 0.5, 5e-4,
         "slab: shear-warp on a log scale 0.01 .. 100: opacity "
         "ln 50 / ln 10^4 at 0.5"},
    };
    for (int run = 0; run < 5; run++) {
        vsv_render_opts o;
        vsv_render_opts_init(&o);
        o.kind = runs[run].kind;
        o.threads = 2;
        o.step_cells = runs[run].step;
        L.opacity = runs[run].opacity;
        L.tf = runs[run].log ? &tflog : &tf;
        float want_rgb[4];
        vsv_tf_eval(L.tf, 0.5f, want_rgb);
        vsv_renderer *r = NULL;
        float *img = malloc(sizeof(float) * 4 * W * H);
        if (!CHECK(!vsv_renderer_create(&o, &r) && !vsv_render(r, &sc, &cam, img, NULL), "slab: renders")) {
            vsv_renderer_free(r);
            free(img);
            continue;
        }
        const double op = runs[run].log ? log(50) / log(1e4) : 0.375;
        const double sigma = L.opacity * op * 3 / 1000, st = runs[run].step * 1000;
        int on = 0, bad = 0;
        double worst = 0, first = -1;
        for (int py = 0; py < H; py++)
            for (int px = 0; px < W; px++) {
                double o3[3], d[3], t0, t1;
                vsv_pixel_ray(&cam, px, py, o3, d);
                if (!vsv_box_hit(o3, d, g.bmin, g.bmax, &t0, &t1))
                    continue;
                int inner = fabs(o3[2] + t0 * d[2] - g.bmax[2]) < 1e-6 && fabs(o3[2] + t1 * d[2] - g.bmin[2]) < 1e-6;
                for (int a = 0; a < 2; a++)
                    for (int e = 0; e < 2; e++) {
                        const double x = o3[a] + (e ? t1 : t0) * d[a];
                        inner &= x > g.bmin[a] + 2000 && x < g.bmax[a] - 2000;
                    }
                if (!inner)
                    continue;
                double alpha = -expm1(-sigma * (t1 - t0));
                if (run == 2) { /* the first whole step whose transmittance is below 1/512 */
                    int k = 1;
                    while (exp(-sigma * st * k) >= 1.0 / 512)
                        k++;
                    alpha = -expm1(-sigma * st * k);
                }
                const float *p = img + 4 * ((size_t)py * W + px);
                double e = fabs(p[3] - alpha);
                for (int ch = 0; ch < 3; ch++)
                    e = fmax(e, fabs(p[ch] - want_rgb[ch] * alpha));
                on++;
                bad += e > runs[run].tol;
                if (e > worst)
                    worst = e, first = p[3] - alpha;
            }
        CHECK(on > 1000 && bad == 0, runs[run].name, "%d of %d pixels off (worst %.3g, alpha off by %.3g)", bad, on,
              worst, first);
        vsv_renderer_free(r);
        free(img);
    }
    free_volume(u);
}

/* A curtain's range on grids of extreme spacing (issue 33 item 9): the
 * values are taken per cell the curtain crosses, not per metre of the
 * smallest cell (a 1 mm by 1000 km grid took 10^10 values and hung
 * vsv-render --slice lon=); the part of the curtain off the grid costs
 * nothing. */
static double ramp_x(int i, int j, int k) { return (void)j, (void)k, i / 15.0; }

/* Columns one cell wide, two cells apart (every third x), 0.5 all the way
 * down 10 levels, seen from straight above by shear-warp: a pixel's ray
 * meets at most a column's extinction (the slices' samples interpolate
 * between a column and the empty cells beside it), so no pixel is more
 * opaque than over the uniform slab of 0.5 seen the same way. Each such
 * scanline's footprint is a run of short intervals, several in a group of
 * eight pixels: a group composited once per interval broke the bound. */
static void test_comb(void)
{
    vsv_meta m;
    grid(&m, N, N, 10, 1000);
    vsv_volume *cv = make_volume(N, N, 10, comb), *uv = make_volume(N, N, 10, uniform);
    vsv_tf tf;
    char msg[128];
    CHECK(vsv_tf_parse(&tf, "colormap viridis\nrange 0.2 1\nopacity 0 1\n", msg, sizeof msg) == 0, "comb: tf", "%s",
          msg);
    vsv_layer L = {cv, &tf, 0.1f, 1};
    vsv_scene sc = {.meta = &m, .layers = &L, .nlayers = 1, .exaggeration = 1, .show_terrain = 0};
    float *a = render_plan(&sc, VSV_RENDER_SHEARWARP);
    L.vol = uv;
    float *b = render_plan(&sc, VSV_RENDER_SHEARWARP);
    double amax = 0, bmax = 0;
    int shown = 0;
    for (int i = 0; a && b && i < W * H; i++) {
        amax = fmax(amax, a[4 * i + 3]);
        bmax = fmax(bmax, b[4 * i + 3]);
        shown += a[4 * i + 3] > 0.1f;
    }
    CHECK(a && b && bmax > 0.6 && amax <= bmax + 1e-4 && shown > W * H / 10,
          "comb: shear-warp composites each pixel once a slice where footprints lie closer than a group",
          "(comb's largest alpha %.4f, the slab's %.4f, %d pixels)", amax, bmax, shown);
    free(a);
    free(b);
    free_volume(cv);
    free_volume(uv);
}

static void test_slice_extreme(void)
{
    static const double sp[][2] = {{1, 1e4}, {1e-3, 1e6}, {1e6, 1e-3}};
    for (size_t c = 0; c < sizeof sp / sizeof *sp; c++) {
        vsv_meta m;
        grid(&m, 16, 12, 4, 1e-3);
        m.spacing[0] = sp[c][0], m.spacing[1] = sp[c][1];
        vsv_volume *v = make_volume(16, 12, 4, ramp_x);
        vsv_tf tf;
        char msg[128];
        vsv_tf_parse(&tf, "colormap viridis\nrange 0 1\nopacity 0 1\n", msg, sizeof msg);
        vsv_layer L = {v, &tf, 1, 0};
        vsv_slice s = {.kind = VSV_SLICE_CURTAIN, .npts = 2};
        /* corner to corner, and as far again beyond each */
        s.xy[0][0] = -16.5 * sp[c][0], s.xy[0][1] = -12.5 * sp[c][1];
        s.xy[1][0] = 31.5 * sp[c][0], s.xy[1][1] = 23.5 * sp[c][1];
        const vsv_scene sc = {
            .meta = &m, .layers = &L, .nlayers = 1, .exaggeration = 1, .slices = &s, .nslices = 1, .slice_layer = 0};
        double lo, hi;
        int64_t work = -1;
        const int rc = vsv_slice_range_work(&sc, &lo, &hi, &work);
        CHECK(rc == 0 && lo == 0 && fabs(hi - 1) < 1e-6 && work > 0 && work <= (16 + 12 + 2) * 4,
              "slice range on an extreme grid: the curtain's values, a column per cell crossed",
              "%g x %g m cells: rc %d, %g .. %g from %lld values (at most %d)", sp[c][0], sp[c][1], rc, lo, hi,
              (long long)work, (16 + 12 + 2) * 4);
        free_volume(v);
        vsv_meta_clear(&m);
    }
}

int main(void)
{
    test_lit_sphere();
    test_slab_closed_form();
    test_comb();
    test_slice_linear();
    test_slice_heights();
    test_slice_extreme();
    return vsv_test_done();
}
