/* test_picture.c — what the picture shows (issue 20): the ground's water
 * from the model's own land use in a plan view; (more below as the parts
 * land). */
#include "vsv_convert.h"
#include "vsv_format.h"
#include "vsv_render.h"
#include "vsv_testlib.h"

#include <math.h>
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
    if (!path || vsv_source_open(path, NULL, &src)) {
        CHECK(1, "lakes: skipped (no ../shared MM5 run)");
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
        CHECK(land > 1000 && land_blue == 0, "plan view: land drawn as land", "%d of %d land cells blue", land_blue, land);
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
        CHECK(m->landuse && vsv_meta_water(m) == ((1ull << 16) | (1ull << 28)), "WRF: LU_INDEX with water 16 and lake 28");
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
    CHECK(m && m->landuse && cats == 1 && vsv_meta_water(m) == (1ull << 7), "CAMx: the land-use file's dominant category, 7 water",
          "%s", rc ? vsv_source_error(src) : "");
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
            const double d = sqrt(pow(rgb[i][0] - rgb[j][0], 2) + pow(rgb[i][1] - rgb[j][1], 2) + pow(rgb[i][2] - rgb[j][2], 2));
            least = d < least ? d : least;
        }
    CHECK(least >= 0.2, "hydrometeors' default colours are distinct", "closest pair %.3f apart", least);
}

int main(void)
{
    test_colours();
    test_water_sources();
    test_lakes();
    test_latlon();
    return vsv_test_done();
}
