/* test_skip.c — the raycaster's empty-space skipping: the skip distances of
 * its blocks (transfer-function aware), the same pixels with and without
 * skipping on a sparse plume (gen-plume's, when ../shared has it; else one
 * made here), on single cells scattered in empty space (and the fine bits
 * that mark the clear cells of the blocks shown) and on real MM5 fields, in
 * the one-ray and sixteen-ray loops, and a uniform slab in empty space whose
 * transmittance is the closed form exp(-tau). */
#include "vsv_format.h"
#include "vsv_render.h"
#include "vsv_renderer.h"
#include "vsv_testlib.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

enum { W = 160, H = 120 };

/* A one-species, one-step .vsv of v (nx*ny*nz floats, x fastest). */
static int write_vol(const char *path, const float *v, int nx, int ny, int nz, double dx, double dz)
{
    vsv_meta m;
    vsv_meta_init(&m);
    m.nx = nx;
    m.ny = ny;
    m.nz = nz;
    m.spacing[0] = m.spacing[1] = dx;
    m.spacing[2] = dz;
    m.origin[2] = dz / 2;
    m.vert_kind = VSV_VERT_EVEN;
    vsv_meta_add_var(&m, "X", "1", "test field");
    vsv_pack_opts o;
    vsv_pack_opts_init(&o);
    vsv_writer *w = NULL;
    const float *f[1] = {v};
    int rc = vsv_writer_create(path, &m, &o, &w);
    if (!rc)
        rc = vsv_writer_add_step(w, 0, f);
    if (!rc)
        rc = vsv_writer_finish(w, NULL, NULL);
    vsv_writer_free(w);
    vsv_meta_clear(&m);
    return rc;
}

typedef struct one {
    char path[1024]; /* a file make_one wrote: removed by close_one */
    vsv_file *f;
    vsv_decoder *d;
    vsv_volume *v;
    vsv_tf tf;
} one;

static int open_one(one *o, const char *path, int step, const char *species, const char *tftext)
{
    memset(o, 0, sizeof *o);
    if (vsv_file_open(path, &o->f) || vsv_decoder_create(o->f, &o->d) || vsv_volume_create(o->f, &o->v))
        return -1;
    const int s = species ? vsv_meta_find_var(vsv_file_meta(o->f), species) : 0;
    char text[512], msg[128];
    if (s < 0 || vsv_volume_load(o->v, o->d, step, s))
        return -1;
    if (!tftext) {
        vsv_tf_default(vsv_file_meta(o->f)->vars[s].name, vsv_file_quant(o->f, s), text, sizeof text);
        tftext = text;
    }
    return vsv_tf_parse(&o->tf, tftext, msg, sizeof msg) ? -1 : 0;
}

/* Writes v (freed here) as a .vsv in the scratch folder under name and
 * opens it into o with transfer function tf (NULL: the default). 0 or -1. */
static int make_one(one *o, const char *name, float *v, int nx, int ny, int nz, double dx, double dz, const char *tf)
{
    const char *path = vsv_test_tmp(name);
    const int rc = write_vol(path, v, nx, ny, nz, dx, dz) == 0 && open_one(o, path, 0, NULL, tf) == 0 ? 0 : -1;
    snprintf(o->path, sizeof o->path, "%s", path);
    free(v);
    return rc;
}

static void close_one(one *o)
{
    vsv_volume_free(o->v);
    vsv_decoder_free(o->d);
    vsv_file_free(o->f);
    if (o->path[0])
        unlink(o->path);
}

/* Renders o at view az (perspective, or plan when az < 0) with opacity op. */
static float *draw(one *o, double az, float op, int noskip, const char *simd, vsv_renderer **keep)
{
    vsv_layer layer = {o->v, &o->tf, op, 1};
    vsv_scene sc = {.meta = vsv_file_meta(o->f), .layers = &layer, .nlayers = 1, .exaggeration = 1};
    sc.exaggeration = az < 0 ? 1 : vsv_scene_default_exaggeration(&sc);
    vsv_camera cam;
    if (az < 0)
        vsv_camera_plan(&cam, &sc, W, H);
    else
        vsv_camera_orbit(&cam, &sc, az, 30, 0, W, H);
    if (simd)
        setenv("VSV_SIMD", simd, 1);
    vsv_render_opts ro;
    vsv_render_opts_init(&ro);
    ro.threads = 2;
    ro.no_skip = noskip;
    vsv_renderer *r = NULL;
    float *img = malloc(sizeof(float) * W * H * 4);
    if (vsv_renderer_create(&ro, &r) || vsv_render(r, &sc, &cam, img, NULL)) {
        free(img);
        img = NULL;
    }
    unsetenv("VSV_SIMD");
    if (keep)
        *keep = r;
    else
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

static double coverage(const float *a)
{
    int n = 0;
    for (int i = 0; i < W * H; i++)
        n += a[4 * i + 3] > 0.01f;
    return (double)n / (W * H);
}

/* With and without skipping, in each loop, from three views: the same bits. */
static void same_pixels(const char *label, one *o, float op)
{
    static const char *const loops[3] = {NULL, "avx2", "0"};
    static const char *const names[3] = {"the default loop", "the AVX2 sixteen-ray loop", "the one-ray loop"};
    double worst = 0, cover = 0;
    int bad = 0;
    for (int view = 0; view < 3; view++)
        for (int l = 0; l < 3; l++) {
            float *a = draw(o, 225 + 120 * view, op, 0, loops[l], NULL),
                  *b = draw(o, 225 + 120 * view, op, 1, loops[l], NULL);
            if (!a || !b) {
                bad = 1;
            } else {
                worst = fmax(worst, max_diff(a, b));
                cover = fmax(cover, coverage(a));
                if (worst > 0)
                    printf("  %s: %s differs at view %d\n", label, names[l], view);
            }
            free(a);
            free(b);
        }
    char name[256];
    snprintf(name, sizeof name, "%s: skipping gives the same pixels as none (3 views, 3 loops)", label);
    CHECK(!bad && worst == 0 && cover > 0.003, name, "max diff %g, coverage %.2f", worst, cover);
}

/* A slab of value 1 in levels 16..23 of 40, 0 elsewhere, opacity curve
 * linear from 0 to 0.8: seen straight down, the ray's optical depth is
 * 3 op / dx * dz * 0.8 * 8 (the slab's 7 cells between centres, plus half a
 * cell's worth in each linear ramp to the empty level beside it), and
 * sampling at half a level (the midpoint rule on each linear stretch) is
 * exact. Blocks above and below the slab are clear at known distances. */
static void slab(void)
{
    const int nx = 24, ny = 20, nz = 40, k0 = 16, k1 = 23;
    const double dx = 30000, dz = 500;
    float *v = calloc((size_t)nx * ny * nz, sizeof *v);
    for (int k = k0; k <= k1; k++)
        for (size_t c = 0; c < (size_t)nx * ny; c++)
            v[(size_t)k * nx * ny + c] = 1;
    one o;
    const int ok = make_one(&o, "skip-slab.vsv", v, nx, ny, nz, dx, dz,
                            "colormap greys\nrange 0 1\nscale linear\nopacity 0 0.8\n") == 0;
    if (!CHECK(ok, "a slab in empty space is written and read"))
        return;
    const float op = 5;
    const double tau = 3 * op / dx * dz * 0.8 * (k1 - k0 + 1), want = 1 - exp(-tau);
    vsv_renderer *r = NULL;
    float *a = draw(&o, -1, op, 0, NULL, &r), *b = draw(&o, -1, op, 1, NULL, NULL);
    double worst = 0;
    for (int p = 0; a && b && p < W * H; p++)
        if (a[4 * p + 3] > 0 || b[4 * p + 3] > 0) /* the pixels that see the slab */
            worst = fmax(worst, fmax(fabs(a[4 * p + 3] - want), fabs(b[4 * p + 3] - want)));
    CHECK(a && b && a[4 * (W * H / 2 + W / 2) + 3] > 0 && worst < 2e-4,
          "a uniform slab seen straight down: opacity 1 - exp(-tau), with and without skipping",
          "want %.6f, worst error %.2g", want, worst);
    CHECK(a && b && max_diff(a, b) == 0, "the slab: skipping changes no pixel");
    /* levels 12..23 are the samples that read the slab (blocks 3, 4, 5: a
     * sample in level 15 reads level 16); every other block is clear, at its
     * distance in blocks from those */
    const unsigned char *d = r ? r->frame.skip : NULL;
    const int nbz = ((nz - 2) >> VSV_RC_BSHIFT) + 1, at = r ? r->frame.nbxy : 0;
    int right = d != NULL && nbz == 10;
    for (int bk = 0; right && bk < nbz; bk++) {
        const int want_d = bk < 3 ? 3 - bk : bk > 5 ? bk - 5 : 0;
        right = (d[bk * at] & ~VSV_RC_FINE) == want_d && (d[bk * at + at - 1] & ~VSV_RC_FINE) == want_d;
        if (!right)
            printf("  block level %d: distance %d, want %d\n", bk, d[bk * at] & ~VSV_RC_FINE, want_d);
    }
    CHECK(right, "the slab: blocks are clear at their distances from the slab (3 2 1 0 0 0 1 2 3 4)");
    vsv_renderer_free(r);
    free(a);
    free(b);
    /* the same slab under a transfer function that shows 0 too: nothing is clear */
    vsv_tf shown;
    char msg[128];
    vsv_tf_parse(&shown, "colormap greys\nrange -1 1\nscale linear\nopacity 0 0.8\n", msg, sizeof msg);
    o.tf = shown;
    float *c = draw(&o, -1, op, 0, NULL, &r);
    CHECK(c && r && r->frame.skip == NULL,
          "a transfer function that shows 0: no block is clear (skipping follows the table)");
    vsv_renderer_free(r);
    free(c);
    close_one(&o);
}

/* Single cells of value 1 scattered in empty space (some on the grid's
 * faces and in its last cells), under a table that shows every value above
 * 0: the fine bits of each block at skip distance 0 mark exactly the cells
 * none of whose trilinear samples reads a speck (the cells i - 1 and i of a
 * speck at i, on each axis), the blocks where at least half the cells are
 * such are flagged (VSV_RC_FINE), and the pixels are the same with and without
 * skipping. Thin layers (exaggerated) and single cells make rays leap out of
 * clear cells every few samples. */
static void specks(void)
{
    enum { NS = 40 };
    const int nx = 37, ny = 30, nz = 26;
    float *v = calloc((size_t)nx * ny * nz, sizeof *v);
    int at[NS][3];
    uint64_t seed = 11;
    for (int s = 0; s < NS; s++) {
        for (int a = 0; a < 3; a++) {
            const int n = a == 0 ? nx : a == 1 ? ny : nz;
            at[s][a] = (int)(vsv_test_rand(&seed) % (uint64_t)n);
        }
        if (s < 4) /* on the faces: the last column, the first row and level, the top */
            at[s][s < 3 ? s : 2] = s == 0 ? nx - 1 : s == 3 ? nz - 1 : 0;
        v[((size_t)at[s][2] * ny + at[s][1]) * nx + at[s][0]] = 1;
    }
    one o;
    const int ok = make_one(&o, "skip-specks.vsv", v, nx, ny, nz, 20000, 400,
                            "colormap magma\nrange 0 1\nscale linear\nopacity 0 1\n") == 0;
    if (!CHECK(ok, "scattered single cells are written and read"))
        return;
    vsv_renderer *r = NULL;
    float *img = draw(&o, 200, 3, 0, NULL, &r);
    const vsv_rc_frame *F = r ? &r->frame : NULL;
    int wrong = 0, shown = 0, checked = 0;
    if (F && F->skip && F->fine) {
        const int n[3] = {nx, ny, nz}, nb[3] = {F->nbx, F->nbxy / F->nbx, ((nz - 2) >> VSV_RC_BSHIFT) + 1};
        for (int bk = 0; bk < nb[2]; bk++)
            for (int bj = 0; bj < nb[1]; bj++)
                for (int bi = 0; bi < nb[0]; bi++) {
                    const size_t b = (size_t)bi + (size_t)nb[0] * (bj + (size_t)nb[1] * bk);
                    if (F->skip[b] & ~VSV_RC_FINE)
                        continue;
                    shown++;
                    /* flagged where it has clear cells */
                    wrong += (F->skip[b] == VSV_RC_FINE) !=
                             (__builtin_popcount(F->fine[2 * b]) + __builtin_popcount(F->fine[2 * b + 1]) >= 32);
                    for (int c = 0; c < 64; c++) {
                        const int g[3] = {bi * 4 + c % 4, bj * 4 + c / 4 % 4, bk * 4 + c / 16};
                        if (g[0] > n[0] - 2 || g[1] > n[1] - 2 || g[2] > n[2] - 2)
                            continue; /* no sample has this lower cell */
                        int seen = 0;
                        for (int s = 0; s < NS; s++)
                            seen |= g[0] >= at[s][0] - 1 && g[0] <= at[s][0] && g[1] >= at[s][1] - 1 &&
                                    g[1] <= at[s][1] && g[2] >= at[s][2] - 1 && g[2] <= at[s][2];
                        const int bit = F->fine[2 * b + c / 32] >> (c % 32) & 1;
                        wrong += bit == seen; /* clear where a speck is read, or not where none is */
                        checked++;
                    }
                }
    }
    CHECK(shown > 0 && checked > 0 && wrong == 0,
          "single cells: the fine bits mark exactly the clear cells of the blocks shown",
          "%d of %d cells wrong in %d blocks", wrong, checked, shown);
    vsv_renderer_free(r);
    free(img);
    same_pixels("single cells", &o, 3);
    close_one(&o);
}

/* gen-plume's sparse plume when ../shared has the generator, else a plume
 * of the same kind made here (sheared Gaussians with noise, cut at 0.2 %). */
static void plume(void)
{
    const int nx = 256, ny = 256, nz = 64;
    const size_t n = (size_t)nx * ny * nz;
    float *v = malloc(n * sizeof *v);
    char dir[1024], cmd[4096], f32[1100];
    const char *shared = getenv("SHARED") ? getenv("SHARED") : "../shared";
    snprintf(dir, sizeof dir, "%s", vsv_test_tmp("plume"));
    snprintf(f32, sizeof f32, "%s/plume_t0.f32", dir);
    snprintf(cmd, sizeof cmd,
             "test -f %s/tools/gen-plume/gen_volume.c && mkdir -p %s && cc -O2 -o %s/gen "
             "%s/tools/gen-plume/gen_volume.c -lm "
             "&& %s/gen %s > /dev/null",
             shared, dir, dir, shared, dir, dir);
    FILE *fp = system(cmd) == 0 ? fopen(f32, "rb") : NULL;
    const int gen = fp && fread(v, sizeof *v, n, fp) == n;
    if (fp)
        fclose(fp);
    if (!gen) {
        uint64_t seed = 7;
        float mx = 0;
        for (int k = 0; k < nz; k++)
            for (int j = 0; j < ny; j++)
                for (int i = 0; i < nx; i++) {
                    double s = 0;
                    for (int p = 0; p < 4; p++) {
                        const double cx = 50 + 50 * p + 0.6 * (k - 10), cy = 60 + 45 * p, cz = 8 + 5 * p;
                        const double e =
                            ((i - cx) * (i - cx) / 400 + (j - cy) * (j - cy) / 100 + (k - cz) * (k - cz) / 16);
                        s += e < 30 ? exp(-0.5 * e) : 0;
                    }
                    const double noise = (double)(vsv_test_rand(&seed) >> 11) / 9007199254740992.0;
                    const float x = (float)(s * (0.8 + 0.4 * noise));
                    v[((size_t)k * ny + j) * nx + i] = x;
                    mx = x > mx ? x : mx;
                }
        for (size_t c = 0; c < n; c++)
            v[c] = v[c] < 2e-3f * mx ? 0 : v[c];
    }
    one o;
    const int ok = make_one(&o, "skip-plume.vsv", v, nx, ny, nz, 1000, 100, NULL) == 0;
    char name[128];
    snprintf(name, sizeof name, "the plume (%s) is written and read", gen ? "gen-plume's" : "made here");
    if (!CHECK(ok, name))
        return;
    same_pixels(gen ? "gen-plume plume" : "plume", &o, 1);
    close_one(&o);
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    if (system(cmd) != 0)
        printf("  (could not remove %s)\n", dir);
}

/* Real MM5 fields at 3 h: cloud water (sparse), snow, vapour (dense). */
static void mm5(void)
{
    const char *path = vsv_test_tmp("skip-mm5.vsv");
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "%s/vsv-convert -q --times 3:3 %s -o %s 2>/dev/null", getenv("B") ? getenv("B") : "build",
             vsv_test_shared("mm5/run1/MMOUT_DOMAIN1"), path);
    if (system(cmd) != 0) {
        snprintf(cmd, sizeof cmd, "%s/vsv-convert -q samples/mm5/MMOUT_DOMAIN1_CROP -o %s",
                 getenv("B") ? getenv("B") : "build", path);
        printf("  (no ../shared MM5 run: the bundled crop)\n");
        if (!CHECK(system(cmd) == 0, "the MM5 sample converts"))
            return;
    }
    const char *species[3] = {"CLW", "SNOW", "Q"};
    for (int s = 0; s < 3; s++) {
        one o;
        vsv_file_info info;
        char label[64];
        snprintf(label, sizeof label, "MM5 %s", species[s]);
        if (!CHECK(vsv_file_open(path, &o.f) == 0, "the MM5 volume opens"))
            return;
        vsv_file_info_get(o.f, &info);
        const int step = info.nsteps - 1;
        vsv_file_free(o.f);
        if (!CHECK(open_one(&o, path, step, species[s], NULL) == 0, "an MM5 species loads"))
            return;
        same_pixels(label, &o, 1);
        close_one(&o);
    }
    unlink(path);
}

/* A volume one layer thick, of one value: seen from elevation e, the ray
 * through the middle of the picture crosses the layer along its thickness
 * over sin(e), so its optical depth -ln(T) times sin(e) is the same from
 * every elevation (Beer-Lambert). With whole steps only (the last, partial
 * one counted whole) it varied by up to a third: the layer's sample planes
 * showed as sheets (the CAMx test problem, 5x4x1). */
static void thin(void)
{
    const int nx = 24, ny = 20, nz = 1;
    float *v = malloc(sizeof(float) * nx * ny * nz);
    for (int i = 0; i < nx * ny * nz; i++)
        v[i] = 1;
    one o;
    const int ok = make_one(&o, "skip-thin.vsv", v, nx, ny, nz, 30000, 500,
                            "colormap greys\nrange 0 1\nscale linear\nopacity 0.05 0.05\n") == 0;
    if (!CHECK(ok, "a layer one cell thick is written and read"))
        return;
    static const double els[] = {35, 42, 50, 58, 67, 80};
    double lo = INFINITY, hi = 0, got[6] = {0};
    int bad = 0;
    for (int i = 0; i < 6; i++) {
        vsv_layer layer = {o.v, &o.tf, 1, 1};
        vsv_scene sc = {.meta = vsv_file_meta(o.f), .layers = &layer, .nlayers = 1, .exaggeration = 1};
        sc.exaggeration = vsv_scene_default_exaggeration(&sc);
        vsv_camera cam;
        vsv_camera_orbit(&cam, &sc, 200, els[i], 0, W + 1, H + 1); /* odd: a pixel at the middle */
        vsv_render_opts ro;
        vsv_render_opts_init(&ro);
        ro.kind = VSV_RENDER_RAYCAST;
        vsv_renderer *r = NULL;
        float *img = malloc(sizeof(float) * (W + 1) * (H + 1) * 4);
        if (!img || vsv_renderer_create(&ro, &r) || vsv_render(r, &sc, &cam, img, NULL)) {
            bad = 1;
        } else {
            const float a = img[4 * ((H / 2) * (W + 1) + W / 2) + 3];
            got[i] = -log(1 - (double)a) * sin(els[i] * M_PI / 180);
            lo = fmin(lo, got[i]);
            hi = fmax(hi, got[i]);
        }
        vsv_renderer_free(r);
        free(img);
    }
    CHECK(!bad && lo > 0.05 && hi / lo < 1.02,
          "a layer one cell thick: optical depth times sin(elevation) the same from 35 to 80 degrees",
          "(%.4f %.4f %.4f %.4f %.4f %.4f; spread %.1f %%)", got[0], got[1], got[2], got[3], got[4], got[5],
          100 * (hi / lo - 1));
    close_one(&o);
}

int main(void)
{
    thin();
    slab();
    specks();
    plume();
    mm5();
    return vsv_test_done();
}
