/* test_annotate.c — what a frame says about itself: text drawn by FreeType
 * covers its box and nothing else; a colour bar's pixels are its transfer
 * function's colours at their values (linear and log); the GSHHG outlines,
 * projected with the real MM5 domain's Lambert grid, pass within a cell of
 * the Lake Michigan shore at Chicago (drawn, in the lake/coast colour) and
 * not through western Kansas; on the GrADS global lat/lon grid they are
 * split at the seam and pass the Cape of Good Hope; on the real MM5 run the
 * GSHHG coast and the model's own land-use coastline lie within a cell of
 * each other (79 % of coast points, 96 % of land-use shore edges), best
 * unshifted; the lines' work on grids of extreme spacing is bounded by the
 * image. */
#include "vsv_annot_internal.h"
#include "vsv_convert.h"
#include "vsv_source_reader.h"
#include "vsv_format.h"
#include "vsv_render.h"
#include "vsv_testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void test_text(void)
{
    vsv_font *f = NULL;
    char err[256];
    const int rc = vsv_font_open(NULL, 16, &f, err, sizeof err);
    if (!CHECK(rc == 0, "a font opens (DejaVu Sans, fonts-dejavu-core)", "%s", err))
        return;
    enum { W = 240, H = 40 };
    float *img = calloc((size_t)W * H * 4, sizeof *img);
    const char *s = "Vesuvius 1995 \xc3\x97";
    const int tw = vsv_text_width(f, s), lh = vsv_font_line(f);
    CHECK(tw > 80 && tw < 200 && lh >= 16 && lh <= 24, "text has a plausible size", "width %d, line %d", tw, lh);
    CHECK(vsv_text_width(f, "WWWW") > vsv_text_width(f, "iiii"), "glyph widths differ (a proportional font)", "");
    const float white[3] = {1, 1, 1};
    vsv_text_draw(f, img, W, H, 10, 8, s, white, 1);
    int in = 0, out = 0, bad = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const float *q = img + 4 * ((size_t)y * W + x);
            if (q[3] <= 0)
                continue;
            bad += fabsf(q[0] - q[3]) > 1e-6f; /* white, premultiplied */
            if (x >= 10 && x < 10 + tw + 2 && y >= 8 && y < 8 + lh)
                in += q[3] > 0.5f;
            else
                out++;
        }
    CHECK(in > 150, "text pixels fill its box", "%d pixels over half covered", in);
    CHECK(out == 0, "no text pixels outside its box", "%d", out);
    CHECK(bad == 0, "text is premultiplied white", "%d pixels", bad);
    /* clipped at the edges, never written outside */
    vsv_text_draw(f, img, W, H, W - 5, H - 5, s, white, 1);
    vsv_text_draw(f, img, W, H, -50, -10, s, white, 1);
    CHECK(1, "text past the image's edges is clipped", "");
    free(img);
    vsv_font_free(f);
    CHECK(vsv_font_open("/nonexistent/font.ttf", 16, &f, err, sizeof err) == VSV_ENOTFOUND && !f &&
              strstr(err, "/nonexistent/font.ttf"),
          "a missing font is VSV_ENOTFOUND naming it", "%s", err);
}

/* The MM5 run's domain (../shared/data/mm5/run1: 32 km Lambert conformal
 * centred on 38N 97W, true at 33 and 50N), its 207 x 142 cross points. */
static void mm5_meta(vsv_meta *m)
{
    vsv_meta_init(m);
    m->nx = 207, m->ny = 142, m->nz = 2;
    m->origin[0] = -3296000, m->origin[1] = -2256000, m->origin[2] = 500;
    m->spacing[0] = m->spacing[1] = 32000, m->spacing[2] = 1000;
    m->proj = (vsv_proj){VSV_PROJ_LCC, 38, -97, 50, 33, 6370000};
    snprintf(m->model, sizeof m->model, "MM5 v3");
}

static void test_colour_bar(void)
{
    vsv_meta m;
    mm5_meta(&m);
    vsv_meta_add_var(&m, "CLW", "kg/kg", "cloud water");
    vsv_meta_add_var(&m, "O3", "ppm", "ozone");
    vsv_tf tf[2];
    char msg[128];
    const int p0 = vsv_tf_parse(&tf[0], "colormap viridis\nrange 0 10\nscale linear\nopacity 0 1\n", msg, sizeof msg);
    const int p1 = vsv_tf_parse(&tf[1], "colormap magma\nrange 1e-6 1e-3\nscale log\nopacity 0 1\n", msg, sizeof msg);
    if (!CHECK(!p0 && !p1 && !vsv_tf_prepare(&tf[0]) && !vsv_tf_prepare(&tf[1]), "transfer functions parse", "%s", msg))
        return;
    const vsv_layer layers[2] = {{NULL, &tf[0], 1, 1}, {NULL, &tf[1], 1, 1}};
    vsv_scene sc = {.meta = &m, .layers = layers, .nlayers = 2, .exaggeration = 20};
    vsv_camera cam;
    vsv_camera_plan(&cam, &sc, 640, 480);
    vsv_font *font = NULL;
    char err[256];
    vsv_font_open(NULL, 13, &font, err, sizeof err);
    const int species[2] = {0, 1};
    const vsv_annot a = {VSV_ANNOT_COLOURBAR, font, 0, "test.vsv", species, NULL, NULL, NULL};
    float *img = calloc((size_t)640 * 480 * 4, sizeof *img);
    CHECK(vsv_annotate(&a, &sc, &cam, img, NULL) == 0, "vsv_annotate draws the colour bars", "");
    for (int l = 0; l < 2; l++) {
        int box[4];
        if (!CHECK(vsv_annotate_bar_box(&a, &sc, &cam, l, box) == 0 && box[1] - box[0] >= 100, "a bar is placed",
                   "layer %d: %d..%d", l, box[0], box[1]))
            continue;
        const int n = box[1] - box[0] + 1;
        double worst = 0;
        for (int k = 1; k < 4; k++) { /* a quarter, half and three quarters along */
            const int c = n * k / 4;
            const double f = (c + 0.5) / n;
            const double v = l == 0 ? 10 * f : 1e-6 * pow(1e3, f);
            float want[4];
            vsv_tf_eval(&tf[l], (float)v, want);
            for (int y = box[2]; y <= box[3]; y++) {
                const float *q = img + 4 * ((size_t)y * 640 + box[0] + c);
                for (int i = 0; i < 3; i++)
                    worst = fmax(worst, fabs(q[i] - want[i]));
                worst = fmax(worst, fabs(q[3] - 1));
            }
        }
        CHECK(worst < 1e-6,
              l == 0 ? "linear colour bar = transfer function at 2.5, 5, 7.5"
                     : "log colour bar = transfer function at 5.6e-6, 3.2e-5, 1.8e-4",
              "worst channel error %g", worst);
        /* the ends differ: the bar spans the colour map */
        const float *lo = img + 4 * ((size_t)box[2] * 640 + box[0]), *hi = img + 4 * ((size_t)box[2] * 640 + box[1]);
        CHECK(fabs(lo[0] - hi[0]) + fabs(lo[1] - hi[1]) + fabs(lo[2] - hi[2]) > 0.3, "a bar runs from lo to hi colours",
              "");
    }
    /* a hidden layer has no bar, and the other keeps one */
    vsv_layer hidden[2] = {layers[0], layers[1]};
    hidden[0].visible = 0;
    sc.layers = hidden;
    int box[4];
    CHECK(vsv_annotate_bar_box(&a, &sc, &cam, 0, box) == VSV_ERANGE && vsv_annotate_bar_box(&a, &sc, &cam, 1, box) == 0,
          "a hidden species has no colour bar", "");
    /* slices coloured by the hidden layer with their own colour map: a bar of their own */
    const vsv_slice slice = {VSV_SLICE_Z, 2000, 0, {{0, 0}}};
    vsv_tf stf = tf[0];
    snprintf(stf.colormap, sizeof stf.colormap, "magma");
    vsv_tf_prepare(&stf);
    sc.slices = &slice, sc.nslices = 1, sc.slice_layer = 0, sc.slice_tf = &stf;
    memset(img, 0, (size_t)640 * 480 * 4 * sizeof *img);
    vsv_annotate(&a, &sc, &cam, img, NULL);
    if (CHECK(vsv_annotate_bar_box(&a, &sc, &cam, 2, box) == 0, "the slices have a colour bar", "")) {
        const int n = box[1] - box[0] + 1, c = n / 2;
        float want[4];
        vsv_tf_eval(&stf, (float)(10 * (c + 0.5) / n), want);
        const float *q = img + 4 * ((size_t)box[2] * 640 + box[0] + c);
        CHECK(fabsf(q[0] - want[0]) + fabsf(q[1] - want[1]) + fabsf(q[2] - want[2]) < 1e-6,
              "the slices' bar = their transfer function at 5", "");
    }
    free(img);
    vsv_font_free(font);
    vsv_meta_clear(&m);
}

/* Coast/lake-coloured pixels (blue as bright as the line: not the orange of
 * a border) within r pixels of screen point (x, y). */
static int shore_near(const float *img, int w, int h, double x, double y, double r)
{
    int n = 0;
    for (int py = (int)(y - r); py <= (int)(y + r); py++)
        for (int px = (int)(x - r); px <= (int)(x + r); px++) {
            if (px < 0 || py < 0 || px >= w || py >= h || hypot(px + 0.5 - x, py + 0.5 - y) > r)
                continue;
            const float *q = img + 4 * ((size_t)py * w + px);
            n += q[3] > 0.3f && q[2] > 0.9f * q[3];
        }
    return n;
}

/* The smallest distance (world metres) from (x, y) to a vertex of the outlines of one kind. */
static double nearest(const vsv_outlines *o, int want, double x, double y)
{
    double best = INFINITY;
    for (int i = 0; i < vsv_outlines_count(o); i++) {
        int kind, n;
        const double *xy = vsv_outlines_line(o, i, &kind, &n);
        for (int k = 0; want == kind && k < n; k++)
            best = fmin(best, hypot(xy[2 * k] - x, xy[2 * k + 1] - y));
    }
    return best;
}

static void test_outlines_mm5(void)
{
    if (access("/usr/share/gmt-gshhg/binned_GSHHS_l.nc", R_OK)) {
        CHECK(0, "GSHHG outlines are installed", "apt-get install gmt-gshhg-low (tools/deps.sh)");
        return;
    }
    vsv_meta m;
    mm5_meta(&m);
    vsv_outlines *o = NULL;
    char msg[512];
    if (!CHECK(vsv_outlines_load(&m, NULL, 'l', &o, msg, sizeof msg) == 0 && vsv_outlines_count(o) > 100,
               "GSHHG coast, lakes and borders load for the MM5 domain", "%s (%d lines)", msg, vsv_outlines_count(o)))
        return;
    /* Chicago's lake front, 41.88N 87.62W: the Lake Michigan shore (a lake,
     * level 2) within a cell (32 km) of it, and the coast (level 1) far */
    double cx, cy;
    vsv_scene_world(&m, 41.88, -87.62, &cx, &cy);
    const double dl = nearest(o, VSV_OUTLINE_LAKE, cx, cy), dc = nearest(o, VSV_OUTLINE_COAST, cx, cy);
    CHECK(dl < 32000, "the Lake Michigan shore passes within a cell of Chicago's lake front", "%.1f km", dl / 1000);
    CHECK(dc > 500000, "the sea coast is far from Chicago", "%.1f km", dc / 1000);
    double sx, sy;
    vsv_scene_world(&m, 32.78, -79.93, &sx, &sy); /* Charleston harbour: the Atlantic coast */
    CHECK(nearest(o, VSV_OUTLINE_COAST, sx, sy) < 32000, "the Atlantic coast passes within a cell of Charleston", "");
    double bx, by;
    vsv_scene_world(&m, 49.0, -105.0, &bx, &by); /* the 49th parallel: the US-Canada border */
    CHECK(nearest(o, VSV_OUTLINE_BORDER, bx, by) < 32000, "the national border passes 49N 105W", "");

    /* drawn: a plan view of the domain, the shore's pixels at Chicago and none in western Kansas */
    const vsv_scene sc = {.meta = &m, .exaggeration = 20};
    vsv_camera cam;
    const int w = 828, h = 568;
    vsv_camera_plan(&cam, &sc, w, h);
    float *img = calloc((size_t)w * h * 4, sizeof *img);
    const vsv_annot a = {VSV_ANNOT_OUTLINES, NULL, 0, NULL, NULL, o, NULL, NULL};
    CHECK(vsv_annotate(&a, &sc, &cam, img, NULL) == 0, "outlines drawn", "");
    vsv_rays R;
    vsv_rays_init(&R, &cam);
    const double cell_px = 32000 / (cam.ortho_height / h);
    double px, py, t;
    const double chicago[3] = {cx, cy, 0};
    vsv_rays_project(&R, chicago, &px, &py, &t);
    const int nc = shore_near(img, w, h, px, py, cell_px);
    CHECK(nc > 0, "the drawn shore passes within a cell of Chicago", "%d pixels within %.1f px of (%.1f, %.1f)", nc,
          cell_px, px, py);
    double kx, ky;
    vsv_scene_world(&m, 38.9, -101.3, &kx, &ky); /* western Kansas: no sea, no big lake */
    const double kansas[3] = {kx, ky, 0};
    vsv_rays_project(&R, kansas, &px, &py, &t);
    CHECK(shore_near(img, w, h, px, py, cell_px) == 0, "no shore drawn in western Kansas", "");
    free(img);
    vsv_outlines_free(o);
    vsv_meta_clear(&m);
}

static void test_outlines_latlon(void)
{
    if (access("/usr/share/gmt-gshhg/binned_GSHHS_c.nc", R_OK))
        return;
    /* the GrADS sample's grid (../shared/data/grads/model.ctl): 72 x 46, 5 x 4 degrees from 0E 90S */
    vsv_meta m;
    vsv_meta_init(&m);
    m.nx = 72, m.ny = 46, m.nz = 7;
    m.origin[0] = 0, m.origin[1] = -90;
    m.spacing[0] = 5, m.spacing[1] = 4, m.spacing[2] = 1000;
    m.proj.kind = VSV_PROJ_LATLON;
    vsv_outlines *o = NULL;
    char msg[512];
    if (!CHECK(vsv_outlines_load(&m, NULL, 'c', &o, msg, sizeof msg) == 0, "outlines load on a global lat/lon grid",
               "%s", msg))
        return;
    double ux, uy, longest = 0, xmin = INFINITY, xmax = -INFINITY;
    vsv_scene_units(&m, &ux, &uy);
    for (int i = 0; i < vsv_outlines_count(o); i++) {
        int kind, n;
        const double *xy = vsv_outlines_line(o, i, &kind, &n);
        for (int k = 0; k < n; k++) {
            xmin = fmin(xmin, xy[2 * k] / ux), xmax = fmax(xmax, xy[2 * k] / ux);
            if (k)
                longest = fmax(longest, fabs(xy[2 * k] - xy[2 * k - 2]) / ux);
        }
    }
    CHECK(longest < 90, "no outline jumps across the grid's seam", "longest step %.1f degrees", longest);
    CHECK(xmin >= -2.5 - 1e-9 && xmax <= 357.5 + 1e-9, "outline longitudes lie on the grid's span (-2.5..357.5)",
          "%.3f..%.3f", xmin, xmax);
    double x, y;
    vsv_scene_world(&m, -34.36, 18.47, &x, &y); /* Cape of Good Hope */
    CHECK(nearest(o, VSV_OUTLINE_COAST, x, y) < 5 * ux, "the coast passes the Cape of Good Hope", "%.2f degrees",
          nearest(o, VSV_OUTLINE_COAST, x, y) / ux);
    vsv_outlines_free(o);
    vsv_meta_clear(&m);
    /* a missing data set is VSV_ENOTFOUND with the package named */
    vsv_meta_init(&m);
    m.nx = m.ny = m.nz = 2;
    m.spacing[0] = m.spacing[1] = m.spacing[2] = 1;
    m.proj.kind = VSV_PROJ_LATLON;
    const int rc = vsv_outlines_load(&m, "/nonexistent", 'l', &o, msg, sizeof msg);
    CHECK(rc == VSV_ENOTFOUND && !o && strstr(msg, "gmt-gshhg-low"),
          "missing GSHHG files: VSV_ENOTFOUND naming the package", "%d %s", rc, msg);
    vsv_meta_clear(&m);
}

/* The real MM5 run (../shared/data/mm5/run1): the GSHHG shore the plan view
 * draws against the model's own land use (water where its category is the
 * one MM5 calls water): the share of shore points (coast and lakes, away
 * from the domain's edge) within one cell of a water/land cell edge. */
static void test_coast_vs_landuse(void)
{
    const char *path = vsv_test_shared("mm5/run1/MMOUT_DOMAIN1");
    if (vsv_test_absent(path, "the MM5 run's coast against its land use"))
        return;
    if (access("/usr/share/gmt-gshhg/binned_GSHHS_l.nc", R_OK)) {
        printf("(no GSHHG: the land-use coastline check is skipped)\n");
        return;
    }
    vsv_source *src = NULL;
    if (!CHECK(vsv_source_open(path, NULL, &src) == 0, "the MM5 run opens", "%s", src ? src->err : ""))
        return;
    const vsv_meta *m = &src->grid;
    const uint64_t water = vsv_meta_water(m);
    if (!CHECK(m->landuse && water, "the MM5 run has a land use with water", "")) {
        vsv_source_free(src);
        return;
    }
    vsv_outlines *o = NULL;
    char msg[512];
    if (!CHECK(vsv_outlines_load(m, NULL, 'l', &o, msg, sizeof msg) == 0, "outlines for the MM5 run", "%s", msg)) {
        vsv_source_free(src);
        return;
    }
    const int nx = m->nx, ny = m->ny;
#define WET(i, j)                                                                                                      \
    ((int)m->landuse[(size_t)(j)*nx + (i)] >= 0 && (int)m->landuse[(size_t)(j)*nx + (i)] < 64 &&                       \
     (water >> (int)m->landuse[(size_t)(j)*nx + (i)] & 1))
    /* the coast's points near a land-use shore edge, as drawn and shifted
     * by half a cell each way: drawn where the model has its coast, the
     * unshifted lines agree best */
    double best_shifted = 0, share0 = 0;
    long all0 = 0;
    for (int shift = 0; shift < 9; shift++) {
        const double du = 0.5 * (shift % 3 - 1), dv = 0.5 * (shift / 3 - 1);
        long near = 0, all = 0;
        for (int li = 0; li < vsv_outlines_count(o); li++) {
            int kind, n;
            const double *xy = vsv_outlines_line(o, li, &kind, &n);
            for (int k = 0; kind == VSV_OUTLINE_COAST && k < n; k++) {
                const double u = (xy[2 * k] - m->origin[0]) / m->spacing[0] + du,
                             v = (xy[2 * k + 1] - m->origin[1]) / m->spacing[1] + dv;
                if (u < 2 || v < 2 || u > nx - 3 || v > ny - 3)
                    continue;
                all++;
                int hit = 0;
                for (int j = (int)v - 2; j <= (int)v + 2 && !hit; j++)
                    for (int i = (int)u - 2; i <= (int)u + 2 && !hit; i++) {
                        /* the edges to the east and north of cell (i, j), at their midpoints */
                        if (i + 1 < nx && WET(i, j) != WET(i + 1, j) && hypot(i + 0.5 - u, j - v) <= 1.0)
                            hit = 1;
                        if (j + 1 < ny && WET(i, j) != WET(i, j + 1) && hypot(i - u, j + 0.5 - v) <= 1.0)
                            hit = 1;
                    }
                near += hit;
            }
        }
        const double share = all ? (double)near / all : 0;
        if (shift == 4)
            share0 = share, all0 = all;
        else
            best_shifted = fmax(best_shifted, share);
    }
    printf(
        "(MM5 run, GSHHG low: %.1f %% of %ld coast points within a cell of a land-use shore edge; shifted half a cell, "
        "at most %.1f %%)\n",
        100 * share0, all0, 100 * best_shifted);
    CHECK(share0 >= 0.75 && all0 > 1000, "most of the coast drawn lies within a cell of the land-use coastline",
          "%.1f %% of %ld points (the rest: islands and inlets finer than 32 km)", 100 * share0, all0);
    CHECK(share0 > best_shifted, "the coast is registered: half a cell off any way agrees less", "%.1f %% vs %.1f %%",
          100 * share0, 100 * best_shifted);
    /* the other way: every water/land cell edge of the land use (away from
     * the edge of the domain) within a cell of a GSHHG shore point; cells of
     * shore points first, so each edge looks at its neighbourhood only */
    int *first = malloc(((size_t)nx * ny + 1) * sizeof *first), *next = NULL;
    size_t npts = 0;
    for (int li = 0; li < vsv_outlines_count(o); li++) {
        int kind, n;
        vsv_outlines_line(o, li, &kind, &n);
        npts += kind == VSV_OUTLINE_COAST || kind == VSV_OUTLINE_LAKE ? (size_t)n : 0;
    }
    double *pu = malloc((npts + 1) * 2 * sizeof *pu);
    next = malloc((npts + 1) * sizeof *next);
    if (first && pu && next) {
        for (size_t c = 0; c < (size_t)nx * ny; c++)
            first[c] = -1;
        size_t np = 0;
        for (int li = 0; li < vsv_outlines_count(o); li++) {
            int kind, n;
            const double *xy = vsv_outlines_line(o, li, &kind, &n);
            for (int k = 0; (kind == VSV_OUTLINE_COAST || kind == VSV_OUTLINE_LAKE) && k < n; k++) {
                const double u = (xy[2 * k] - m->origin[0]) / m->spacing[0],
                             v = (xy[2 * k + 1] - m->origin[1]) / m->spacing[1];
                const int i = (int)lround(u), j = (int)lround(v);
                if (i < 0 || j < 0 || i >= nx || j >= ny)
                    continue;
                pu[2 * np] = u, pu[2 * np + 1] = v;
                next[np] = first[(size_t)j * nx + i];
                first[(size_t)j * nx + i] = (int)np++;
            }
        }
        long edges = 0, near = 0;
        for (int j = 2; j < ny - 3; j++)
            for (int i = 2; i < nx - 3; i++)
                for (int dir = 0; dir < 2; dir++) {
                    const int i1 = i + !dir, j1 = j + dir;
                    if (WET(i, j) == WET(i1, j1))
                        continue;
                    const double eu = i + 0.5 * !dir, ev = j + 0.5 * dir;
                    int hit = 0;
                    for (int jj = j - 2; jj <= j + 2 && !hit; jj++)
                        for (int ii = i - 2; ii <= i + 2 && !hit; ii++)
                            for (int q = first[(size_t)jj * nx + ii]; q >= 0 && !hit; q = next[q])
                                hit = hypot(pu[2 * q] - eu, pu[2 * q + 1] - ev) <= 1.0;
                    edges++;
                    near += hit;
                }
        const double share = edges ? (double)near / edges : 0;
        printf("(MM5 run: %ld of %ld land-use shore edges within a cell of a GSHHG shore point, %.1f %%)\n", near,
               edges, 100 * share);
        CHECK(share >= 0.9 && edges > 500, "the land-use coastline lies within a cell of the drawn shore",
              "%.1f %% of %ld water/land edges", 100 * share, edges);
    }
    free(first), free(next), free(pu);
#undef WET
    vsv_outlines_free(o);
    vsv_source_free(src);
}

static void test_time_line(void)
{
    vsv_meta m;
    vsv_meta_init(&m);
    char buf[160];
    const int64_t t = vsv_time_from_civil(2002, 6, 3, 17, 0, 0);
    vsv_annot_time_line(&m, t, buf, sizeof buf);
    CHECK(!strcmp(buf, "2002-06-03T17:00:00Z"), "the time line: ISO, UTC", "'%s'", buf);
    /* CAMx v6+: the file's hours are 5 behind UTC */
    vsv_meta_add_attr(&m, "time zone", "5 (the file's hours are UTC-5; times here are UTC)");
    vsv_annot_time_line(&m, t, buf, sizeof buf);
    CHECK(!strcmp(buf, "2002-06-03T17:00:00Z   local 2002-06-03T12:00 UTC-5"),
          "the time line: the file's time zone too", "'%s'", buf);
    vsv_meta_clear(&m);
    vsv_meta_init(&m);
    vsv_meta_add_attr(&m, "time zone", "none in a v5 header: hours taken as UTC");
    vsv_annot_time_line(&m, t, buf, sizeof buf);
    CHECK(!strcmp(buf, "2002-06-03T17:00:00Z"), "no local time where the file names no zone", "'%s'", buf);
    vsv_meta_clear(&m);
    /* a frame between the model's hourly outputs says so (issue 32); one on them does not */
    vsv_meta_init(&m);
    vsv_meta_add_attr(&m, VSV_ATTR_OUTPUTS, "every 3600 s from 2002-06-03T00:00:00Z");
    vsv_annot_time_line(&m, t + 1200, buf, sizeof buf);
    CHECK(!strcmp(buf, "2002-06-03T17:20:00Z   interpolated between 17:00 and 18:00"),
          "an interpolated frame names the outputs it lies between", "'%s'", buf);
    vsv_annot_time_line(&m, t, buf, sizeof buf);
    CHECK(!strcmp(buf, "2002-06-03T17:00:00Z"), "a model output is just its time", "'%s'", buf);
    vsv_annot_time_line(&m, vsv_time_from_civil(2002, 6, 3, 23, 30, 0), buf, sizeof buf);
    CHECK(!strcmp(buf, "2002-06-03T23:30:00Z   interpolated between 2002-06-03T23:00 and 2002-06-04T00:00"),
          "across midnight the dates are given", "'%s'", buf);
    vsv_meta_clear(&m);
}

/* A colour bar names its species with its units: the label over the bar,
 * right-aligned to it, is exactly as wide as "CLW (kg/kg)" (and as "CLW"
 * for a variable without units). */
static void test_bar_units(void)
{
    vsv_font *font = NULL;
    char err[256];
    if (vsv_font_open(NULL, 13, &font, err, sizeof err)) {
        CHECK(1, "bar units: skipped (no font)", "%s", err);
        return;
    }
    for (int withunits = 1; withunits >= 0; withunits--) {
        vsv_meta m;
        mm5_meta(&m);
        vsv_meta_add_var(&m, "CLW", withunits ? "kg/kg" : "", "");
        vsv_tf tf;
        char msg[128];
        vsv_tf_parse(&tf, "colormap viridis\nrange 0 10\nscale linear\nopacity 0 1\n", msg, sizeof msg);
        vsv_tf_prepare(&tf);
        const vsv_layer layer = {NULL, &tf, 1, 1};
        vsv_scene sc = {.meta = &m, .layers = &layer, .nlayers = 1, .exaggeration = 20};
        vsv_camera cam;
        vsv_camera_plan(&cam, &sc, 640, 480);
        const int species[1] = {0};
        const vsv_annot a = {VSV_ANNOT_COLOURBAR, font, 0, "test.vsv", species, NULL, NULL, NULL};
        float *img = calloc((size_t)640 * 480 * 4, sizeof *img);
        int box[4];
        if (img && vsv_annotate(&a, &sc, &cam, img, NULL) == 0 && vsv_annotate_bar_box(&a, &sc, &cam, 0, box) == 0) {
            int left = 640, right = -1;
            for (int y = box[2] - vsv_font_line(font); y < box[2]; y++)
                for (int x = 0; x < 640; x++)
                    if (y >= 0 && img[4 * ((size_t)y * 640 + x)] > 0.5f) {
                        left = x < left ? x : left;
                        right = x > right ? x : right;
                    }
            const char *want = withunits ? "CLW (kg/kg)" : "CLW";
            const int tw = vsv_text_width(font, want);
            CHECK(right <= box[1] + 1 && right >= box[1] - 3 && abs((right - left + 1) - tw) <= 3,
                  withunits ? "the bar's label is its species and units: CLW (kg/kg)"
                            : "without units, the label is the name alone",
                  "label pixels %d..%d, bar to %d, want %d wide", left, right, box[1], tw);
        } else {
            CHECK(0, "bar units: annotated", "");
        }
        free(img);
        vsv_meta_clear(&m);
    }
    vsv_font_free(font);
}

/* The boxes vsv_annotate drew, as its placed callback reports them. */
typedef struct boxes {
    int n;
    unsigned part[64];
    int box[64][4];
} boxes;

static void collect(void *ctx, unsigned part, const int box[4])
{
    boxes *b = ctx;
    if (b->n < 64) {
        b->part[b->n] = part;
        memcpy(b->box[b->n++], box, 4 * sizeof(int));
    }
}

static int meet(const int a[4], const int b[4]) { return a[0] <= b[2] && b[0] <= a[2] && a[1] <= b[3] && b[1] <= a[3]; }

/* The layout, checked by the boxes (issue 32): in a plan view framed by
 * vsv_annotate_insets no box of the legend (time block, colour bars, scale)
 * covers the map, there is no exaggeration to state, and no two boxes, the
 * graticule's labels among them, overlap; in the oblique view of the same
 * grid neither do any two. One form of bar title, the name and units. */
static void test_layout(void)
{
    vsv_meta m;
    mm5_meta(&m);
    vsv_meta_add_var(&m, "CLW", "kg/kg", "cloud water mixing ratio");
    vsv_meta_add_var(&m, "SNOW", "kg/kg", "SNOW MIXING RATIO");
    vsv_tf tf[2];
    char msg[128];
    int ok = !vsv_tf_parse(&tf[0], "colormap viridis\nrange 0 1e-3\nopacity 0 1\n", msg, sizeof msg) &&
             !vsv_tf_parse(&tf[1], "colormap magma\nrange 0 2e-4\nopacity 0 1\n", msg, sizeof msg) &&
             !vsv_tf_prepare(&tf[0]) && !vsv_tf_prepare(&tf[1]);
    vsv_font *font = NULL;
    char err[256];
    ok &= vsv_font_open(NULL, 13, &font, err, sizeof err) == 0;
    if (!CHECK(ok, "layout: a scene and a font", "%s %s", msg, err))
        return;
    const vsv_layer layers[2] = {{NULL, &tf[0], 1, 1}, {NULL, &tf[1], 1, 1}};
    vsv_scene sc = {.meta = &m, .layers = layers, .nlayers = 2, .exaggeration = 20};
    const int species[2] = {0, 1};
    const int W = 800, H = 600;
    float *img = calloc((size_t)W * H * 4, sizeof *img);
    for (int view = 0; view < 2; view++) {
        boxes b = {0};
        const vsv_annot a = {VSV_ANNOT_ALL & ~VSV_ANNOT_OUTLINES, font, 0, "test.vsv", species, NULL, collect, &b};
        vsv_camera cam;
        int map[4] = {0, 0, -1, -1};
        if (view == 0) {
            int inset[4];
            vsv_annotate_insets(&a, &sc, W, H, inset);
            vsv_camera_plan_inset(&cam, &sc, W, H, inset);
            /* the domain's pixels in the orthographic view */
            double mn[3], mx[3];
            vsv_scene_bounds(&sc, mn, mx);
            const double per_px = cam.ortho_height / H;
            map[0] = (int)floor((mn[0] - cam.pos[0]) / per_px + W / 2.0);
            map[2] = (int)ceil((mx[0] - cam.pos[0]) / per_px + W / 2.0);
            map[1] = (int)floor(H / 2.0 - (mx[1] - cam.pos[1]) / per_px);
            map[3] = (int)ceil(H / 2.0 - (mn[1] - cam.pos[1]) / per_px);
            CHECK(inset[1] > 30 && inset[2] > 150 && map[1] >= inset[1] - 1 && map[2] <= W - inset[2] + 1 &&
                      map[2] - map[0] > 300,
                  "plan view: the map framed inside the legend's margins", "inset %d %d %d %d, map %d..%d x %d..%d",
                  inset[0], inset[1], inset[2], inset[3], map[0], map[2], map[1], map[3]);
        } else {
            vsv_camera_fit(&cam, &sc, 225, 30, W, H);
        }
        memset(img, 0, (size_t)W * H * 4 * sizeof *img);
        CHECK(vsv_annotate(&a, &sc, &cam, img, NULL) == 0, view ? "oblique: annotated" : "plan: annotated");
        int legend_on_map = 0, overlaps = 0, labels = 0, exag = 0, kinds = 0;
        for (int i = 0; i < b.n; i++) {
            labels += b.part[i] == VSV_ANNOT_GRATICULE;
            exag += b.part[i] == VSV_ANNOT_EXAGGERATION;
            kinds |= (int)b.part[i];
            if (view == 0 && b.part[i] != VSV_ANNOT_GRATICULE && meet(b.box[i], map))
                legend_on_map++;
            for (int j = 0; j < i; j++)
                overlaps += meet(b.box[i], b.box[j]);
        }
        if (view == 0) {
            CHECK(legend_on_map == 0, "plan view: no box of the legend covers the map", "%d do", legend_on_map);
            CHECK(exag == 0, "plan view: no exaggeration stated");
        }
        CHECK((kinds & (VSV_ANNOT_TIME | VSV_ANNOT_COLOURBAR | VSV_ANNOT_SCALEBAR)) ==
                      (VSV_ANNOT_TIME | VSV_ANNOT_COLOURBAR | VSV_ANNOT_SCALEBAR) &&
                  labels >= 4,
              view ? "oblique: time, bars, scale and graticule labels drawn"
                   : "plan: time, bars, scale and graticule labels drawn",
              "%d boxes, %d labels, parts %#x", b.n, labels, kinds);
        CHECK(overlaps == 0,
              view ? "oblique: no two boxes overlap (labels among them)"
                   : "plan: no two boxes overlap (labels among them)",
              "%d pairs", overlaps);
    }
    free(img);
    vsv_font_free(font);
    vsv_meta_clear(&m);
}

/* Species shown together are told apart: two whose default colour maps are
 * the same get two maps; a --tf file's choice stands (issue 32). */
static void test_distinct_maps(void)
{
    vsv_meta m;
    vsv_meta_init(&m);
    m.nx = m.ny = m.nz = 4;
    m.spacing[0] = m.spacing[1] = m.spacing[2] = 1000;
    vsv_meta_add_var(&m, "AAA", "ppm", "");
    vsv_meta_add_var(&m, "BBB", "ppm", "");
    vsv_meta_add_var(&m, "CCC", "ppm", "");
    float v[64];
    for (int i = 0; i < 64; i++)
        v[i] = (float)i;
    const float *fl[3] = {v, v, v};
    const char *path = vsv_test_tmp("maps.vsv"), *tfp = vsv_test_tmp("maps.tf");
    vsv_writer *w = NULL;
    int rc = vsv_writer_create(path, &m, NULL, &w);
    rc = rc ? rc : vsv_writer_add_step(w, 0, fl);
    rc = rc ? rc : vsv_writer_finish(w, NULL, NULL);
    vsv_writer_free(w);
    vsv_file *f = NULL;
    if (!CHECK(rc == 0 && vsv_file_open(path, &f) == 0, "maps: a file of three species"))
        return;
    vsv_tf tf[3];
    char msg[256];
    for (int s = 0; s < 3; s++)
        vsv_tf_for_species(f, s, NULL, &tf[s], msg, sizeof msg);
    CHECK(strcmp(tf[0].colormap, tf[1].colormap) && strcmp(tf[0].colormap, tf[2].colormap) &&
              strcmp(tf[1].colormap, tf[2].colormap),
          "three species of one default colour map get three", "%s %s %s", tf[0].colormap, tf[1].colormap,
          tf[2].colormap);
    FILE *fp = fopen(tfp, "w");
    if (fp) {
        fputs("species AAA\ncolormap rain\nrange 0 63\nopacity 0 1\nspecies BBB\ncolormap rain\nrange 0 63\nopacity 0 "
              "1\n",
              fp);
        fclose(fp);
    }
    rc =
        vsv_tf_for_species(f, 0, tfp, &tf[0], msg, sizeof msg) | vsv_tf_for_species(f, 1, tfp, &tf[1], msg, sizeof msg);
    CHECK(rc == 0 && !strcmp(tf[0].colormap, "rain") && !strcmp(tf[1].colormap, "rain"),
          "a colour map the --tf file chose stands, shared or not", "%s %s (%s)", tf[0].colormap, tf[1].colormap, msg);
    vsv_file_free(f);
    vsv_meta_clear(&m);
}

/* The work of drawing the lines on the ground follows the image, not the
 * grid's spacing (issue 33 item 9): a grid of 1 mm by 1000 km cells once
 * sampled every coast segment 100,000 times (74 s for 160 x 120 pixels).
 * Each frame's work (points set on the terrain, brush steps) is counted:
 * on the real MM5 domain it stays far under the frame's budget, so the
 * budget never cuts a real map short; on extreme grids it stays under a
 * few hundred units a segment of image, and the lines still draw. */
static double ground_work(const vsv_meta *m, const vsv_outlines *o, int view, int w, int h, int *drawn)
{
    const vsv_scene sc = {.meta = m, .exaggeration = 20};
    vsv_camera cam;
    if (view)
        vsv_camera_fit(&cam, &sc, 225, 30, w, h);
    else
        vsv_camera_plan(&cam, &sc, w, h);
    float *img = calloc((size_t)w * h * 4, sizeof *img);
    const vsv_annot a = {VSV_ANNOT_OUTLINES | VSV_ANNOT_GRATICULE, NULL, 0, NULL, NULL, o, NULL, NULL};
    int64_t work = -1;
    if (!img || vsv_annot_ground(&a, &sc, &cam, img, NULL, NULL, &work))
        work = -1;
    *drawn = 0;
    for (size_t p = 0; img && p < (size_t)w * h; p++)
        *drawn += img[4 * p + 3] > 0;
    free(img);
    return (double)work;
}

static void test_ground_work(void)
{
    if (access("/usr/share/gmt-gshhg/binned_GSHHS_l.nc", R_OK))
        return;
    vsv_meta m;
    mm5_meta(&m);
    vsv_outlines *o = NULL;
    char msg[512];
    int drawn;
    if (!CHECK(vsv_outlines_load(&m, NULL, 'l', &o, msg, sizeof msg) == 0, "outlines load for the MM5 domain", "%s",
               msg))
        return;
    for (int view = 0; view < 2; view++) {
        const double work = ground_work(&m, o, view, 828, 568, &drawn);
        const double budget = (double)vsv_annot_ground_budget(828, 568);
        CHECK(work > 0 && work < budget / 4 && drawn > 10000, "MM5 map lines: the frame's work far under its budget",
              "%s view: %.0f units of %.0f, %d pixels drawn", view ? "oblique" : "plan", work, budget, drawn);
    }
    vsv_outlines_free(o);
    vsv_meta_clear(&m);
    /* cells of 1 mm by 1000 km (and milder: 1 m by 10 km), Lambert conformal as MM5's */
    static const double sp[][2] = {{1e-3, 1e6}, {1, 1e4}, {1e6, 1e-3}};
    for (size_t k = 0; k < sizeof sp / sizeof *sp; k++) {
        mm5_meta(&m);
        m.nx = 16, m.ny = 12, m.nz = 4;
        m.origin[0] = m.origin[1] = 0;
        m.spacing[0] = sp[k][0], m.spacing[1] = sp[k][1], m.spacing[2] = 1e-3;
        o = NULL;
        if (!CHECK(vsv_outlines_load(&m, NULL, 'l', &o, msg, sizeof msg) == 0, "outlines load for an extreme grid",
                   "%g x %g m: %s", sp[k][0], sp[k][1], msg))
            continue;
        for (int view = 0; view < 2; view++) {
            const int w = 160, h = 120;
            const double work = ground_work(&m, o, view, w, h, &drawn);
            CHECK(work >= 0 && work <= 200.0 * (w + h) && drawn > 0,
                  "lines on an extreme grid: work bounded by the image, not the spacing",
                  "%g x %g m cells, %s view: %.0f units (at most %d), %d pixels drawn", sp[k][0], sp[k][1],
                  view ? "oblique" : "plan", work, 200 * (w + h), drawn);
        }
        vsv_outlines_free(o);
        vsv_meta_clear(&m);
    }
}

int main(void)
{
    test_layout();
    test_distinct_maps();
    test_bar_units();
    test_time_line();
    test_text();
    test_colour_bar();
    test_outlines_mm5();
    test_outlines_latlon();
    test_coast_vs_landuse();
    test_ground_work();
    return vsv_test_done();
}
