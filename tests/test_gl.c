/* test_gl.c — the GPU raycaster (render/gl/) in a headless EGL context
 * (Mesa's llvmpipe here): its frames against the CPU raycaster's at the same
 * camera and settings (PSNR over the pixels either covers, >= 35 dB) on the
 * bundled MM5 sample (even and native heights, lit, with slices, a map
 * view), the real MM5 run (Q, CLW and SNOW, even and native heights), the
 * WRF Katrina file and gen-plume's plume and haze; on a time series, that
 * only the bricks whose values changed are uploaded (counted against the
 * volumes' keys) and that the atlas stays within the budget; a budget too
 * small for one frame is an error that says so; depth against the CPU's. */
#include "vsv_gl.h"
#include "vsv_player.h"
#include "vsv_testlib.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *B(void) { return getenv("B") ? getenv("B") : "build"; }

/* PSNR (dB) of two 8-bit RGB images over the pixels either covers (differs
 * from the background by more than 8 of 255 in a channel), as
 * tests/imgcmp.py; *cover: the share of pixels covered. */
static double psnr(const unsigned char *a, const unsigned char *b, int n, const float bg[3], double *cover)
{
    unsigned char bg8[3];
    for (int c = 0; c < 3; c++)
        bg8[c] = (unsigned char)lrint(255 * pow(bg[c], 1 / 2.2));
    double se = 0;
    long cnt = 0;
    for (int i = 0; i < n; i++) {
        int ca = 0, cb = 0;
        for (int c = 0; c < 3; c++) {
            ca |= abs(a[3 * i + c] - bg8[c]) > 8;
            cb |= abs(b[3 * i + c] - bg8[c]) > 8;
        }
        if (!ca && !cb)
            continue;
        cnt++;
        for (int c = 0; c < 3; c++)
            se += (double)(a[3 * i + c] - b[3 * i + c]) * (a[3 * i + c] - b[3 * i + c]);
    }
    *cover = (double)cnt / n;
    if (!cnt)
        return 0;
    return se == 0 ? 99 : 10 * log10(255.0 * 255 * 3 * cnt / se);
}

/* One file, one view: the CPU raycaster's frame and the GPU raycaster's,
 * through the player (the same scene and camera), then the actions given. */
static void compare(const char *what, const char *path, const char *species, const char *const *actions, int w, int h,
                    const char *slice)
{
    vsv_player_opts o;
    vsv_player_opts_init(&o);
    o.path = path;
    o.species = species;
    if (slice) {
        o.slices[0] = slice;
        o.nslices = 1;
    }
    o.renderer = VSV_RENDER_RAYCAST;
    o.cache_bytes = (size_t)256 << 20;
    vsv_player *p = NULL;
    char err[1024], name[512];
    snprintf(name, sizeof name, "%s: opens", what);
    if (!CHECK(!vsv_player_open(&o, &p, err, sizeof err), name, "(%s)", err)) {
        vsv_player_free(p);
        return;
    }
    for (int i = 0; actions && actions[i]; i++)
        vsv_player_do(p, actions[i], err, sizeof err);
    vsv_player_do(p, "end", err, sizeof err); /* the last step: clouds */
    vsv_player_update(p, 0, 1);
    vsv_camera cam;
    vsv_player_camera(p, w, h, &cam);
    unsigned char *cpu = malloc((size_t)w * h * 3), *gpu = malloc((size_t)w * h * 3);
    const unsigned char *img = vsv_player_image(p, &cam, err, sizeof err);
    if (img)
        memcpy(cpu, img, (size_t)w * h * 3);
    const int sw = vsv_player_do(p, "renderer gl", err, sizeof err);
    snprintf(name, sizeof name, "%s: the GPU raycaster starts", what);
    if (CHECK(img && !sw, name, "(%s)", err)) {
        img = vsv_player_image(p, &cam, err, sizeof err);
        snprintf(name, sizeof name, "%s: the GPU raycaster renders", what);
        if (CHECK(img != NULL, name, "(%s)", err)) {
            memcpy(gpu, img, (size_t)w * h * 3);
            double cover;
            const double db = psnr(cpu, gpu, w * h, vsv_player_background(p), &cover);
            snprintf(name, sizeof name, "%s: the GPU's frame is the CPU raycaster's (PSNR >= 35 dB)", what);
            CHECK(db >= 35 && cover > 0.01, name, "(%.1f dB over %.1f %% of the pixels)", db, 100 * cover);
            printf("  (%s: %.1f dB, %.1f %% covered, %dx%d)\n", what, db, 100 * cover, w, h);
        }
    }
    free(cpu);
    free(gpu);
    vsv_player_free(p);
}

static int convert(const char *args, const char *out)
{
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "%s/vsv-convert -q %s -o %s", B(), args, out);
    return system(cmd) == 0;
}

/* A one-step .vsv of gen-plume's 256 x 256 x 64 float field at f32 (1 km
 * cells, 100 m layers): 0 when it cannot be made. */
static int write_plume(const char *f32, const char *out, const char *name)
{
    enum { NX = 256, NY = 256, NZ = 64 };
    const size_t cells = (size_t)NX * NY * NZ;
    float *v = malloc(cells * sizeof *v);
    FILE *fp = fopen(f32, "rb");
    const int got = v && fp && fread(v, sizeof *v, cells, fp) == cells;
    if (fp)
        fclose(fp);
    if (!got) {
        free(v);
        return 0;
    }
    vsv_meta m;
    vsv_meta_init(&m);
    m.nx = NX, m.ny = NY, m.nz = NZ;
    m.spacing[0] = m.spacing[1] = 1000;
    m.spacing[2] = 100;
    m.origin[2] = 50;
    m.vert_kind = VSV_VERT_EVEN;
    vsv_meta_add_var(&m, name, "1", "gen-plume");
    vsv_pack_opts po;
    vsv_pack_opts_init(&po);
    vsv_writer *w = NULL;
    const float *fields[1] = {v};
    const int ok = !vsv_writer_create(out, &m, &po, &w) && !vsv_writer_add_step(w, 1000000000, fields) &&
                   !vsv_writer_finish(w, NULL, NULL);
    vsv_writer_free(w);
    vsv_meta_clear(&m);
    free(v);
    return ok;
}

/* Depth: the GPU's against the CPU's where both have one. */
static void test_depth(const char *path)
{
    vsv_player_opts o;
    vsv_player_opts_init(&o);
    o.path = path;
    vsv_player *p = NULL;
    char err[512];
    if (vsv_player_open(&o, &p, err, sizeof err))
        return;
    vsv_player_do(p, "end", err, sizeof err);
    vsv_player_update(p, 0, 1);
    vsv_camera cam;
    vsv_player_camera(p, 160, 120, &cam);
    vsv_scene sc;
    vsv_player_scene(p, &sc);
    vsv_render_opts ro;
    vsv_render_opts_init(&ro);
    vsv_renderer *r = NULL;
    vsv_gl *g = NULL;
    float *d0 = malloc(160 * 120 * sizeof(float)), *d1 = malloc(160 * 120 * sizeof(float));
    if (!vsv_renderer_create(&ro, &r) && !vsv_gl_create(NULL, &g, err, sizeof err) &&
        !vsv_render(r, &sc, &cam, NULL, d0) && !vsv_gl_render(g, &sc, &cam, NULL, d1)) {
        int both = 0, agree = 0, inf = 0;
        for (int i = 0; i < 160 * 120; i++) {
            if (isinf(d0[i]) || isinf(d1[i])) {
                inf += isinf(d0[i]) && isinf(d1[i]);
                continue;
            }
            both++;
            agree += fabs(d0[i] - d1[i]) <= 1e-3 * d0[i] + 1;
        }
        CHECK(both > 500 && agree >= both * 99 / 100 && inf > 0,
              "the depth image: the CPU's distance (within 0.1 %) where both see something", "(%d of %d; %d none)",
              agree, both, inf);
    } else {
        CHECK(0, "the depth image", "(%s)", err);
    }
    free(d0);
    free(d1);
    vsv_gl_free(g);
    vsv_renderer_free(r);
    vsv_player_free(p);
}

/* Uploads over a time series: step after step, exactly the bricks whose
 * sampling copies hold other values (a brick's key, or a key of a brick
 * after it, changed) are uploaded; the atlas within the budget. */
static void test_uploads(const char *path)
{
    vsv_file *f = NULL;
    if (!CHECK(!vsv_file_open(path, &f), "the 5-minute series opens", " "))
        return;
    const vsv_meta *m = vsv_file_meta(f);
    vsv_file_info info;
    vsv_file_info_get(f, &info);
    vsv_pager *pg = NULL;
    vsv_pager_open(f, NULL, &pg);
    const int s = vsv_meta_find_var(m, "CLW");
    vsv_volume *v = vsv_pager_volume_new(pg);
    vsv_tf tf;
    char err[512];
    vsv_tf_for_species(f, s, NULL, &tf, err, sizeof err);
    vsv_layer L = {v, &tf, 1, 1};
    vsv_scene sc = {.meta = m, .layers = &L, .nlayers = 1, .exaggeration = 20, .show_terrain = 1};
    vsv_camera cam;
    vsv_camera_fit(&cam, &sc, 225, 30, 96, 72);
    vsv_gl_opts go;
    vsv_gl_opts_init(&go);
    go.budget = (size_t)24 << 20;
    vsv_gl *g = NULL;
    if (!CHECK(!vsv_gl_create(&go, &g, err, sizeof err), "a GPU raycaster with a 24 MB budget", "(%s)", err))
        return;
    uint64_t *prev = calloc((size_t)v->nbricks, sizeof *prev);
    const int steps = info.nsteps < 20 ? info.nsteps : 20;
    int ok = 1, fits = 1, changed_total = 0, up_total = 0;
    for (int t = 0; t < steps; t++) {
        vsv_pager_get(pg, t, s, 1, v);
        /* the expected uploads: non-empty copies whose keys changed */
        int want = 0;
        const int bx = v->bdim[0], by = v->bdim[1], bz = v->bdim[2];
        for (int b = 0; b < v->nbricks; b++) {
            uint64_t k = 1469598103934665603ull;
            const int i = b % bx, j = b / bx % by, kk = b / (bx * by);
            for (int n = 0; n < 8; n++) {
                const int ii = i + (n & 1), jj = j + (n >> 1 & 1), k2 = kk + (n >> 2);
                k = (k ^ (ii < bx && jj < by && k2 < bz ? v->bkey[ii + bx * (jj + by * k2)] : 7)) * 1099511628211ull;
            }
            if (!vsv_march_brick_empty(v, b) && k != prev[b])
                want++;
            prev[b] = vsv_march_brick_empty(v, b) ? 0 : k;
        }
        const int rc = vsv_gl_render(g, &sc, &cam, NULL, NULL);
        vsv_gl_stats st;
        vsv_gl_stats_get(g, &st);
        ok &= !rc && (int)st.last_uploads == want;
        fits &= st.atlas_bytes <= go.budget;
        changed_total += want;
        up_total += (int)st.last_uploads;
        if (!ok) {
            printf("  step %d: %llu uploads, %d bricks changed (rc %d %s)\n", t, (unsigned long long)st.last_uploads,
                   want, rc, vsv_gl_error(g));
            break;
        }
    }
    CHECK(ok && changed_total > 0, "stepping through 20 steps uploads exactly the bricks that changed",
          "(%d uploads, %d changed)", up_total, changed_total);
    vsv_gl_stats st;
    vsv_gl_stats_get(g, &st);
    CHECK(fits && st.uploads < (uint64_t)steps * (uint64_t)v->nbricks, "the atlas stays within the budget",
          "(%zu of %zu bytes; %llu uploads in all)", st.atlas_bytes, st.budget, (unsigned long long)st.uploads);
    /* a budget below one frame's bricks: an error that says so */
    vsv_gl_free(g);
    go.budget = (size_t)200 << 10; /* one slot */
    g = NULL;
    vsv_gl_create(&go, &g, err, sizeof err);
    const int rc = g ? vsv_gl_render(g, &sc, &cam, NULL, NULL) : 0;
    CHECK(g && rc == VSV_ENOMEM && strstr(vsv_gl_error(g), "the budget is 0.2 MB"),
          "a frame that does not fit the budget is an error that says so", "(%d: %s)", rc, g ? vsv_gl_error(g) : "");
    vsv_gl_free(g);
    free(prev);
    vsv_volume_free(v);
    vsv_pager_free(pg);
    vsv_file_free(f);
}

int main(void)
{
    vsv_gl_context *ctx = NULL;
    char err[1024];
    if (!CHECK(!vsv_gl_context_create(&ctx, err, sizeof err), "a headless OpenGL 3.3 context (EGL)", "(%s)", err))
        return vsv_test_done();
    const char *crop = vsv_test_tmp("gl-crop.vsv"), *cropn = vsv_test_tmp("gl-crop-native.vsv");
    const char *crop5 = vsv_test_tmp("gl-crop-5m.vsv");
    if (!CHECK(convert("samples/mm5/MMOUT_DOMAIN1_CROP", crop) &&
                   convert("--vertical native samples/mm5/MMOUT_DOMAIN1_CROP", cropn) &&
                   convert("--time-res 5m samples/mm5/MMOUT_DOMAIN1_CROP", crop5),
               "convert the bundled MM5 sample (even, native, 5-minute steps)", " "))
        return vsv_test_done();
    const char *lit[] = {"light on", NULL}, *plan[] = {"view plan", NULL};
    compare("MM5 sample", crop, NULL, NULL, 160, 120, NULL);
    compare("MM5 sample, lit", crop, NULL, lit, 160, 120, NULL);
    compare("MM5 sample, native heights", cropn, NULL, NULL, 160, 120, NULL);
    compare("MM5 sample, map view", crop, "Q,CLW", plan, 160, 120, NULL);
    compare("MM5 sample, a slice at 1500 m", crop, NULL, NULL, 160, 120, "z=1500");
    compare("MM5 sample, lit, a vertical section", crop, NULL, lit, 160, 120, "line=45,-125:52,-118");
    /* the real runs, when ../shared is beside the checkout */
    const char *mm5 = vsv_test_shared("mm5/run1/MMOUT_DOMAIN1");
    const char *run = vsv_test_tmp("gl-mm5.vsv"), *runn = vsv_test_tmp("gl-mm5-native.vsv");
    if (!vsv_test_absent(mm5, "the real MM5 run on the GPU")) {
        char args[2048];
        snprintf(args, sizeof args, "--times 3 %s", mm5);
        const int a = convert(args, run);
        snprintf(args, sizeof args, "--times 3 --vertical native %s", mm5);
        const int b = convert(args, runn);
        if (CHECK(a && b, "convert the real MM5 run (its last output; even and native heights)", " ")) {
            compare("the real MM5 run, Q CLW SNOW", run, "Q,CLW,SNOW", NULL, 192, 144, NULL);
            compare("the real MM5 run, Q CLW SNOW, native heights", runn, "Q,CLW,SNOW", NULL, 192, 144, NULL);
            compare("the real MM5 run, lit, a slice of Q at 3000 m", run, "CLW,SNOW", lit, 192, 144, "z=3000");
        }
    }
    const char *kat = vsv_test_shared("wrf/katrina_ci_test_file.nc");
    const char *katv = vsv_test_tmp("gl-katrina.vsv");
    if (!vsv_test_absent(kat, "WRF Katrina on the GPU")) {
        if (CHECK(convert(kat, katv), "convert the WRF Katrina file", " "))
            compare("WRF Katrina", katv, NULL, NULL, 160, 160, NULL);
    }
    /* gen-plume's plume and haze, built from ../shared/tools */
    char dir[1024], cmd[4096], f32[1100];
    snprintf(dir, sizeof dir, "%s", vsv_test_tmp("gl-plume"));
    snprintf(cmd, sizeof cmd,
             "test -f %s && mkdir -p %s && cc -O2 -o %s/gen %s -lm 2>/dev/null && %s/gen %s > /dev/null",
             vsv_test_shared("../tools/gen-plume/gen_volume.c"), dir, dir,
             vsv_test_shared("../tools/gen-plume/gen_volume.c"), dir, dir);
    if (!vsv_test_absent(vsv_test_shared("../tools/gen-plume/gen_volume.c"), "gen-plume's plume and haze on the GPU") &&
        CHECK(system(cmd) == 0, "gen-plume builds and writes its volumes", " ")) {
        const char *plume = vsv_test_tmp("gl-plume.vsv"), *haze = vsv_test_tmp("gl-haze.vsv");
        snprintf(f32, sizeof f32, "%s/plume_t0.f32", dir);
        const int a = write_plume(f32, plume, "PLUME");
        snprintf(f32, sizeof f32, "%s/plume_haze.f32", dir);
        const int b = write_plume(f32, haze, "HAZE");
        if (CHECK(a && b, "gen-plume's plume and haze as .vsv files", " ")) {
            compare("gen-plume's plume", plume, NULL, NULL, 160, 120, NULL);
            compare("gen-plume's haze", haze, NULL, NULL, 160, 120, NULL);
            compare("gen-plume's plume, lit", plume, NULL, lit, 160, 120, NULL);
        }
    }
    test_depth(crop);
    test_uploads(crop5);
    vsv_gl_context_free(ctx);
    return vsv_test_done();
}
