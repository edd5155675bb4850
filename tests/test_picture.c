/* test_picture.c — what the picture shows (issue 20): the ground's water
 * from the model's own land use in a plan view; lat/lon grids on the
 * sphere; every model's water field; the hydrometeors' colours; the views
 * and their framing; the bytes of a float image (the gamma). */
#include "vsv_convert.h"
#include "vsv_format.h"
#include "vsv_render.h"
#include "vsv_testlib.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* The pixel (row 0 at the top) of world (x, y) in a plan view. */
static void plan_pixel(const vsv_camera *cam, double x, double y, int *px, int *py)
{
    const double wh = cam->ortho_height, ww = wh * cam->width / cam->height;
    *px = (int)floor((x - cam->pos[0]) / ww * cam->width + cam->width / 2.0);
    *py = (int)floor(cam->height / 2.0 - (y - cam->pos[1]) / wh * cam->height);
}

static int is_blue(const float *p) { return p[2] > p[1] * 1.3f && p[2] > p[0] * 1.8f; }

/* A plan view of the MM5 run's ground: every cell the model calls water
 * whose neighbours are water too (lakes inland: the ground above 100 m) is
 * drawn as water, and every land cell amid land is land. */
static void test_lakes(void)
{
    const char *path = vsv_test_shared("mm5/run1/MMOUT_DOMAIN1");
    vsv_source *src = NULL;
    if (vsv_test_absent(path, "lakes of the MM5 run"))
        return;
    if (!CHECK(vsv_source_open(path, NULL, &src) == 0, "the MM5 run opens")) {
        vsv_source_free(src);
        return;
    }
    const vsv_meta *m = vsv_source_grid(src);
    vsv_scene sc = {.meta = m, .layers = NULL, .nlayers = 0, .exaggeration = 20, .show_terrain = 1};
    enum { PW = 1200, PH = 900 };
    vsv_camera cam;
    vsv_camera_plan(&cam, &sc, PW, PH);
    vsv_render_opts o;
    vsv_render_opts_init(&o);
    vsv_renderer *r = NULL;
    float *rgba = malloc((size_t)PW * PH * 4 * sizeof *rgba);
    CHECK(m->landuse && vsv_meta_water(m) == (1u << 16), "the MM5 run's land use: category 16 is water");
    if (!rgba || vsv_renderer_create(&o, &r) || vsv_render(r, &sc, &cam, rgba, NULL)) {
        CHECK(0, "lakes: plan view renders");
    } else {
        int lakes = 0, lakes_blue = 0, land = 0, land_blue = 0;
        for (int j = 1; j < m->ny - 1; j++)
            for (int i = 1; i < m->nx - 1; i++) {
                int wet = 0;
                for (int dj = -1; dj <= 1; dj++)
                    for (int di = -1; di <= 1; di++)
                        wet += m->landuse[(size_t)(j + dj) * m->nx + i + di] == 16;
                const size_t c = (size_t)j * m->nx + i;
                int px, py;
                plan_pixel(&cam, m->origin[0] + i * m->spacing[0], m->origin[1] + j * m->spacing[1], &px, &py);
                const int blue = is_blue(rgba + 4 * ((size_t)py * PW + px));
                if (wet == 9 && m->terrain[c] > 100)
                    lakes++, lakes_blue += blue;
                else if (wet == 0)
                    land++, land_blue += blue;
            }
        CHECK(lakes > 30 && lakes_blue == lakes, "plan view: inland water (Great Lakes) drawn as water",
              "%d of %d lake cells", lakes_blue, lakes);
        CHECK(land > 1000 && land_blue == 0, "plan view: land drawn as land", "%d of %d land cells blue", land_blue,
              land);
    }
    vsv_renderer_free(r);
    free(rgba);
    vsv_source_free(src);
}

/* A latitude/longitude grid (GrADS model.ctl: 72 x 46 cells of 5 x 4
 * degrees, the whole globe) is drawn in metres on the sphere: the world box
 * is the globe's circumference wide and half of it tall, and a plan view
 * of its Q fills the frame's width. */
static void test_latlon(void)
{
    const char *path = vsv_test_shared("grads/model.ctl");
    vsv_source *src = NULL;
    if (vsv_source_open(path, NULL, &src)) {
        CHECK(1, "latlon: skipped (no ../shared GrADS sample)");
        vsv_source_free(src);
        return;
    }
    const vsv_meta *m = vsv_source_grid(src);
    vsv_scene sc = {.meta = m, .layers = NULL, .nlayers = 0, .exaggeration = 20, .show_terrain = 0};
    double mn[3], mx[3];
    vsv_scene_bounds(&sc, mn, mx);
    const double circ = 2 * M_PI * 6370000.0;
    CHECK(m->proj.kind == VSV_PROJ_LATLON && fabs((mx[0] - mn[0]) - circ) < 0.01 * circ &&
              fabs((mx[1] - mn[1]) - circ * 184 / 360) < 0.01 * circ,
          "latlon: the grid is drawn in metres on the sphere", "box %.0f x %.0f m", mx[0] - mn[0], mx[1] - mn[1]);
    double lat, lon, x, y;
    CHECK(vsv_scene_world(m, 44, 100, &x, &y) == 0 && vsv_scene_latlon(m, x, y, &lat, &lon) == 0 &&
              fabs(lat - 44) < 1e-9 && fabs(lon - 100) < 1e-9 && fabs(y - 44 * circ / 360) < 1,
          "latlon: world metres and latitude/longitude both ways", "%g %g (y %g)", lat, lon, y);
    vsv_source_free(src);
}

/* Every model's own water: WRF's LU_INDEX with ISWATER/ISLAKE, CAMx's
 * land-use file among its met companions (dominant of 11 categories, 7 is
 * water). */
static void test_water_sources(void)
{
    vsv_source *src = NULL;
    if (vsv_source_open(vsv_test_shared("wrf/wrf_d01_allvars_cropped.nc"), NULL, &src)) {
        CHECK(1, "WRF land use: skipped (no ../shared)");
    } else {
        const vsv_meta *m = vsv_source_grid(src);
        CHECK(m->landuse && vsv_meta_water(m) == ((1ull << 16) | (1ull << 28)),
              "WRF: LU_INDEX with water 16 and lake 28");
    }
    vsv_source_free(src);
    src = NULL;
    vsv_source_opts o;
    vsv_source_opts_init(&o);
    char dir[1100];
    snprintf(dir, sizeof dir, "%s", vsv_test_tmp("camxmet"));
    mkdir(dir, 0755);
    char lu[1200];
    snprintf(lu, sizeof lu, "%s/test.landuse", dir);
    size_t n = 0;
    unsigned char *d = vsv_test_slurp(vsv_test_shared("camx/test.landuse"), &n);
    if (!d || vsv_test_write(lu, d, n)) {
        CHECK(1, "CAMx land use: skipped (no ../shared)");
        free(d);
        return;
    }
    free(d);
    o.met = dir;
    o.proj.kind = VSV_PROJ_LCC;
    o.proj.lat0 = 40, o.proj.lon0 = -97, o.proj.lat1 = 33, o.proj.lat2 = 45;
    const int rc = vsv_source_open(vsv_test_shared("camx/test.uamiv"), &o, &src);
    const vsv_meta *m = rc ? NULL : vsv_source_grid(src);
    int cats = 0;
    for (int c = 0; m && m->landuse && c < m->nx * m->ny; c++)
        cats |= m->landuse[c] >= 1 && m->landuse[c] <= 11 ? 1 : 2;
    CHECK(m && m->landuse && cats == 1 && vsv_meta_water(m) == (1ull << 7),
          "CAMx: the land-use file's dominant category, 7 water", "%s", rc ? vsv_source_error(src) : "");
    vsv_source_free(src);
    unlink(lu);
    rmdir(dir);
}

/* The default colours of the hydrometeors differ: cloud water, rain, ice,
 * snow and graupel at the top of their ranges are at least 0.2 apart (RGB,
 * 0..1) from each other. */
static void test_colours(void)
{
    static const char *const names[] = {"CLW", "RNW", "ICE", "SNOW", "GRAUPEL"};
    float rgb[5][4];
    for (int i = 0; i < 5; i++) {
        vsv_quant q = {.bits = 16, .lo = 0, .hi = 1e-3};
        char text[512], msg[128];
        vsv_tf tf;
        vsv_tf_default(names[i], &q, text, sizeof text);
        vsv_tf_parse(&tf, text, msg, sizeof msg);
        vsv_tf_prepare(&tf);
        vsv_tf_eval(&tf, 0.9e-3f, rgb[i]);
    }
    double least = 1e9;
    for (int i = 0; i < 5; i++)
        for (int j = 0; j < i; j++) {
            const double d =
                sqrt(pow(rgb[i][0] - rgb[j][0], 2) + pow(rgb[i][1] - rgb[j][1], 2) + pow(rgb[i][2] - rgb[j][2], 2));
            least = d < least ? d : least;
        }
    CHECK(least >= 0.2, "hydrometeors' default colours are distinct", "closest pair %.3f apart", least);
}

/* The views scientists use (vsv_view_preset, vsv-render --view, vsv-play's
 * view action) on the bundled MM5 sample's ground: each from where it says
 * (plan: straight down, north up; south and west: from that side, low;
 * oblique: from the south-west, above), and the domain filling the image:
 * its box's corners spanning at least 85 % of its width or height (92 %
 * for plan, south and west), none outside, and
 * the ground's pixels spanning at least 80 % of its width or height,
 * centred (the orbit camera of before, vsv_camera_orbit at distance 0,
 * left 36-44 % of the width empty). */
static void test_views(void)
{
    vsv_source *src = NULL;
    if (!CHECK(vsv_source_open("samples/mm5/MMOUT_DOMAIN1_CROP", NULL, &src) == 0, "views: the sample opens", "")) {
        vsv_source_free(src);
        return;
    }
    const vsv_meta *m = vsv_source_grid(src);
    vsv_scene sc = {.meta = m, .layers = NULL, .nlayers = 0, .exaggeration = 0, .show_terrain = 1};
    sc.exaggeration = vsv_scene_default_exaggeration(&sc);
    double mn[3], mx[3];
    vsv_scene_bounds(&sc, mn, mx);
    const double cx = 0.5 * (mn[0] + mx[0]), cy = 0.5 * (mn[1] + mx[1]), cz = 0.5 * (mn[2] + mx[2]);
    enum { W = 320, H = 240 };
    vsv_render_opts o;
    vsv_render_opts_init(&o);
    vsv_renderer *r = NULL;
    float *rgba = malloc((size_t)W * H * 4 * sizeof *rgba);
    if (!rgba || vsv_renderer_create(&o, &r)) {
        CHECK(0, "views: a renderer", "");
        free(rgba);
        vsv_source_free(src);
        return;
    }
    static const char *const names[] = {"plan", "south", "west", "oblique"};
    for (int v = 0; v < 4; v++) {
        double az = -1, el = -1;
        const int plan = vsv_view_preset(names[v], &az, &el);
        vsv_camera cam;
        if (plan)
            vsv_camera_plan(&cam, &sc, W, H);
        else
            vsv_camera_fit(&cam, &sc, az, el, W, H);
        const double dx = cam.pos[0] - cx, dy = cam.pos[1] - cy, dz = cam.pos[2] - cz;
        int where = 0;
        switch (v) {
        case 0: where = plan == 1 && cam.ortho_height > 0 && cam.dir[2] < 0 && cam.up[1] > 0 && !cam.up[0]; break;
        case 1:
            where = !plan && dy < 0 && fabs(dx) < 1e-6 * fabs(dy) && dz > 0 && dz < fabs(dy) * tan(10 * M_PI / 180);
            break;
        case 2:
            where = !plan && dx < 0 && fabs(dy) < 1e-6 * fabs(dx) && dz > 0 && dz < fabs(dx) * tan(10 * M_PI / 180);
            break;
        case 3: where = !plan && dx < 0 && dy < 0 && fabs(dx - dy) < 1e-6 * fabs(dx) && dz > 0.4 * hypot(dx, dy); break;
        }
        CHECK(where, "a view from where it says", "%s: eye %.0f, %.0f, %.0f from the centre", names[v], dx, dy, dz);
        if (vsv_render(r, &sc, &cam, rgba, NULL)) {
            CHECK(0, "views: renders", "%s", names[v]);
            continue;
        }
        int x0 = W, x1 = -1, y0 = H, y1 = -1;
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++)
                if (rgba[4 * ((size_t)y * W + x) + 3] > 0.5f) {
                    x0 = x < x0 ? x : x0, x1 = x > x1 ? x : x1;
                    y0 = y < y0 ? y : y0, y1 = y > y1 ? y : y1;
                }
        const double fw = (x1 - x0 + 1.0) / W, fh = (y1 - y0 + 1.0) / H;
        const double offx = fabs((x0 + x1 + 1) / 2.0 - W / 2.0) / W, offy = fabs((y0 + y1 + 1) / 2.0 - H / 2.0) / H;
        CHECK(x1 >= 0 && (fw >= 0.8 || fh >= 0.8) && (fw >= 0.8 ? offx : offy) < 0.05,
              "the ground fills most of the image", "%s: it spans %.0f %% x %.0f %% of it", names[v], 100 * fw,
              100 * fh);
        /* the box's eight corners (the volume above the ground): inside the
         * image, and spanning at least 85 % of its width or height */
        double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
        double f[3] = {cam.dir[0], cam.dir[1], cam.dir[2]}, rr[3], u[3];
        const double fl = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
        for (int i = 0; i < 3; i++)
            f[i] /= fl;
        rr[0] = f[1] * cam.up[2] - f[2] * cam.up[1], rr[1] = f[2] * cam.up[0] - f[0] * cam.up[2],
        rr[2] = f[0] * cam.up[1] - f[1] * cam.up[0];
        const double rl = sqrt(rr[0] * rr[0] + rr[1] * rr[1] + rr[2] * rr[2]);
        for (int i = 0; i < 3; i++)
            rr[i] /= rl;
        u[0] = rr[1] * f[2] - rr[2] * f[1], u[1] = rr[2] * f[0] - rr[0] * f[2], u[2] = rr[0] * f[1] - rr[1] * f[0];
        const double ky = plan ? cam.ortho_height / 2 : tan(cam.fov_deg * M_PI / 360), kx = ky * W / H;
        for (int k = 0; k < 8; k++) {
            const double q[3] = {k & 1 ? mx[0] : mn[0], k & 2 ? mx[1] : mn[1], k & 4 ? mx[2] : mn[2]};
            const double d[3] = {q[0] - cam.pos[0], q[1] - cam.pos[1], q[2] - cam.pos[2]};
            const double z = plan ? 1 : d[0] * f[0] + d[1] * f[1] + d[2] * f[2];
            const double sx = (d[0] * rr[0] + d[1] * rr[1] + d[2] * rr[2]) / z / kx;
            const double sy = (d[0] * u[0] + d[1] * u[1] + d[2] * u[2]) / z / ky;
            lo[0] = fmin(lo[0], sx), hi[0] = fmax(hi[0], sx), lo[1] = fmin(lo[1], sy), hi[1] = fmax(hi[1], sy);
        }
        const int inside = lo[0] >= -1.001 && hi[0] <= 1.001 && lo[1] >= -1.001 && hi[1] <= 1.001;
        const int fills = (lo[0] <= -0.85 && hi[0] >= 0.85) || (lo[1] <= -0.85 && hi[1] >= 0.85);
        CHECK(inside && fills, "the domain's box fills the image", "%s: corners from %.2f, %.2f to %.2f, %.2f (-1..1)",
              names[v], lo[0], lo[1], hi[0], hi[1]);
    }
    double az, el;
    CHECK(vsv_view_preset("sideways", &az, &el) == -1 && vsv_view_preset(NULL, &az, &el) == -1,
          "an unknown view is refused", "");
    vsv_renderer_free(r);
    free(rgba);
    vsv_source_free(src);
}

/* vsv_image_rgb8's bytes are lrintf(255 v^(1/2.2)) of the value over the
 * background, clamped to [0, 1]: every 61st float in [0, 1] (and every float
 * of the darkest values, where the bytes change fastest), each channel. */
static void test_gamma(void)
{
    enum { N = 1 << 16 };
    float *px = malloc(N * 4 * sizeof *px);
    unsigned char *rgb = malloc(N * 3);
    const float bg[3] = {0, 0.25f, 1};
    long bad = 0, tried = 0;
    for (uint32_t base = 0; base < 0x3f800000u + 2 * 61 * N; base += 61 * N) {
        for (uint32_t i = 0; i < N; i++) {
            const uint32_t b = base + 61 * i;
            float v;
            memcpy(&v, &b, sizeof v);
            px[4 * i] = v, px[4 * i + 1] = v - 0.25f, px[4 * i + 2] = -v, px[4 * i + 3] = 1;
        }
        vsv_image_rgb8(px, N, 1, bg, rgb);
        for (uint32_t i = 0; i < N; i++)
            for (int c = 0; c < 3; c++) {
                const float v = px[4 * i + c] + (1 - px[4 * i + 3]) * bg[c];
                const unsigned char want = v <= 0 ? 0 : v >= 1 ? 255 : (unsigned char)lrintf(powf(v, 1 / 2.2f) * 255);
                bad += rgb[3 * i + c] != want;
                tried++;
            }
    }
    for (uint32_t b = 0x3a000000u; b < 0x3a000000u + N; b++) { /* around 4.9e-4: bytes 8-9 */
        float v;
        memcpy(&v, &b, sizeof v);
        const float one[4] = {v, 0, 0, 1};
        vsv_image_rgb8(one, 1, 1, (const float[3]){0, 0, 0}, rgb);
        bad += rgb[0] != (unsigned char)lrintf(powf(v, 1 / 2.2f) * 255);
        tried++;
    }
    CHECK(!bad, "the image's bytes are the gamma formula's exactly", "(%ld of %ld differ)", bad, tried);
    free(px);
    free(rgb);
}

int main(void)
{
    test_gamma();
    test_views();
    test_colours();
    test_water_sources();
    test_lakes();
    test_latlon();
    return vsv_test_done();
}
