/* bench_volpack.c — the shear-warp renderer beside VolPack, Lacroute's own
 * shear-warp (Debian libvolpack1-dev), drawing the same picture: the same
 * 8-bit volume, opacity matched per unit length, the same colours (VolPack
 * in 3-channel colour mode, a colour map whose channels differ), views,
 * image size and ray termination (vp_match.h). Each view's two images are
 * compared (PSNR over red, green, blue and alpha; a comparison counts only at 35 dB
 * or more, and the table says whether every view got there). VolPack is
 * single-threaded; Vesuvius runs with 1 and 2 threads, writing float RGBA
 * (vsv_render) and 8-bit RGBA as VolPack does (vsv_render_rgba8). All
 * render the 8 views in turn, 16 rounds, so a change in the machine's load
 * falls on all alike: wall time and the calling thread's CPU time per
 * round, medians and ranges, and the ratios worked out round by round. Classification is
 * outside the timing on both sides (and reported). Usage:
 *   bench_volpack FILE.vsv SPECIES [STEP]
 *   bench_volpack --box FILE.vsv   (writes the closed-form box of
 *                                   vp_write_box to FILE.vsv and uses it)
 *   bench_volpack --plume DIR | --haze DIR   (gen-plume's plume_t0 or
 *                                   plume_haze in DIR, written as a .vsv there)
 * With VP_DUMP=PREFIX in the environment each view's two pictures are
 * written side by side to PREFIXk.png, with their mean red and
 * alpha printed. */
#include "bench_stats.h"
#include "vp_match.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double cpu(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

enum { FRAMES = 8, REPEAT = 16 }; /* 8 views, each timed 16 times */
enum { NOURS = 4 };               /* ours: 1 and 2 threads, floats and bytes */

/* VolPack, then ours in its four set-ups (threads 1, 2; float RGBA, 8-bit
 * RGBA), the views in turn, REPEAT rounds; ours in an order that turns
 * round by round (the one after VolPack finds the caches full of
 * VolPack's). Per round each one's wall and CPU seconds a frame. */
static void time_rounds(vpContext *vpc, vsv_renderer *const r[2], const vsv_scene *sc, const vsv_camera *cams,
                        float *img, unsigned char *b8, double wall[1 + NOURS][REPEAT], double cput[1 + NOURS][REPEAT])
{
    for (int rep = 0; rep < REPEAT; rep++) {
        double t = now(), c = cpu();
        for (int k = 0; k < FRAMES; k++) {
            vp_view(vpc, k);
            vp_check(vpc, vpRenderClassifiedVolume(vpc));
        }
        wall[0][rep] = (now() - t) / FRAMES, cput[0][rep] = (cpu() - c) / FRAMES;
        for (int j = 0; j < NOURS; j++) {
            const int i = (j + rep) % NOURS;
            t = now(), c = cpu();
            for (int k = 0; k < FRAMES; k++)
                if (i < 2)
                    vsv_render(r[i], sc, &cams[k], img, NULL);
                else
                    vsv_render_rgba8(r[i - 2], sc, &cams[k], b8, NULL);
            wall[1 + i][rep] = (now() - t) / FRAMES, cput[1 + i][rep] = (cpu() - c) / FRAMES;
        }
    }
}

/* The table: VolPack's row, then ours in its four set-ups (a ratio only
 * where the pictures match: counts; CPU time only for one thread, whose
 * caller's thread does all its work). */
static void print_rows(double wall[1 + NOURS][REPEAT], double cput[1 + NOURS][REPEAT], int counts, const double cls[2],
                       double vp_classify)
{
    printf("Median (range) over the rounds; × is VolPack's time over ours, worked out in each round. Ours writes "
           "float RGBA (vsv_render, 16 bytes a pixel) or 8-bit RGBA as VolPack does (vsv_render_rgba8).\n\n"
           "| renderer | threads | wall ms/frame | × VolPack's frame rate (wall) | CPU ms/frame | × VolPack (CPU, one "
           "thread) | classification ms (all axes, wall) |\n"
           "|---|---|---|---|---|---|---|\n");
    double w[3], cc[3];
    bench_stats(wall[0], REPEAT, w);
    bench_stats(cput[0], REPEAT, cc);
    printf(
        "| VolPack vpRenderClassifiedVolume, 8-bit RGBA | 1 | %.2f (%.2f–%.2f) | 1 | %.2f (%.2f–%.2f) | 1 | %.0f |\n",
        1e3 * w[0], 1e3 * w[1], 1e3 * w[2], 1e3 * cc[0], 1e3 * cc[1], 1e3 * cc[2], 1e3 * vp_classify);
    for (int i = 0; i < NOURS; i++) {
        const int th = i % 2 + 1;
        double rw[REPEAT], rc[REPEAT], x[3], y[3];
        for (int rep = 0; rep < REPEAT; rep++)
            rw[rep] = wall[0][rep] / wall[1 + i][rep], rc[rep] = cput[0][rep] / cput[1 + i][rep];
        bench_stats(wall[1 + i], REPEAT, w);
        bench_stats(cput[1 + i], REPEAT, cc);
        bench_stats(rw, REPEAT, x);
        bench_stats(rc, REPEAT, y);
        printf("| Vesuvius shear-warp, %s | %d | %.2f (%.2f–%.2f) | ", i < 2 ? "float RGBA" : "8-bit RGBA", th,
               1e3 * w[0], 1e3 * w[1], 1e3 * w[2]);
        if (counts)
            printf("**%.2f** (%.2f–%.2f) | ", x[0], x[1], x[2]);
        else
            printf("— (below 35 dB) | ");
        if (th == 1 && counts)
            printf("%.2f (%.2f–%.2f) | **%.2f** (%.2f–%.2f) | %.0f |\n", 1e3 * cc[0], 1e3 * cc[1], 1e3 * cc[2], y[0],
                   y[1], y[2], 1e3 * cls[th - 1]);
        else if (th == 1)
            printf("%.2f (%.2f–%.2f) | — (below 35 dB) | %.0f |\n", 1e3 * cc[0], 1e3 * cc[1], 1e3 * cc[2],
                   1e3 * cls[th - 1]);
        else
            printf("— | — | %.0f |\n", 1e3 * cls[th - 1]);
    }
}

int main(int argc, char **argv)
{
    vp_series S;
    if (argc < 3) {
        fprintf(stderr, "usage: bench_volpack FILE.vsv SPECIES [STEP] | --box FILE.vsv | --plume DIR | --haze DIR\n");
        return 2;
    }
    int step = argc > 3 ? atoi(argv[3]) : 0;
    char path[1024];
    if (!strcmp(argv[1], "--box")) {
        /* the closed-form case: argv[2] names the file to write */
        if (vp_write_box(argv[2]))
            return 1;
        argv[1] = argv[2];
        argv[2] = "box";
        step = 0;
    } else if (!strcmp(argv[1], "--plume") || !strcmp(argv[1], "--haze")) {
        /* gen-plume's volume in the folder argv[2], written as a .vsv there */
        const int haze = !strcmp(argv[1], "--haze");
        const char *names[1] = {haze ? "plume_haze.f32" : "plume_t0.f32"};
        snprintf(path, sizeof path, "%s/%s.vsv", argv[2], haze ? "haze" : "plume");
        if (vp_write_plume(argv[2], path, names, 1))
            return 1;
        argv[1] = path;
        argv[2] = "plume";
        step = 0;
    }
    if (vp_series_open(&S, argv[2], argv[1], argv[2], step, 1))
        return 1;
    const vsv_meta *m = &S.iso;
    const size_t nv = (size_t)m->nx * m->ny * m->nz;
    size_t nonzero = 0;
    for (size_t i = 0; i < nv; i++)
        nonzero += S.vox[0][4 * i + 2] > 0;
    /* ------------------------------------------------------------ VolPack */
    unsigned char *image = malloc(VP_SIZE * VP_SIZE * 4);
    vpContext *vpc = vp_setup(&S, image);
    double t0 = now();
    vp_check(vpc, vpClassifyVolume(vpc));
    const double vp_classify = now() - t0;
    /* ------------------------------------------------------------ Vesuvius */
    vsv_layer layer;
    vsv_scene sc;
    vp_scene(&S, &layer, &sc);
    vsv_camera cams[FRAMES];
    for (int k = 0; k < FRAMES; k++)
        vp_camera(&sc, k, &cams[k]);
    float *img = malloc(sizeof(float) * 4 * VP_SIZE * VP_SIZE);
    unsigned char *b8 = malloc(4 * VP_SIZE * VP_SIZE);
    vsv_renderer *r[2] = {NULL, NULL};
    double cls[2] = {0, 0};
    for (int th = 1; th <= 2; th++) {
        vsv_render_opts o;
        vsv_render_opts_init(&o);
        o.kind = VSV_RENDER_SHEARWARP;
        o.threads = th;
        if (vsv_renderer_create(&o, &r[th - 1]))
            return 1;
        /* warm-up: every view once, so each principal axis is classified
         * (VolPack classifies all three up front) */
        for (int k = 0; k < FRAMES; k++) {
            const double before = vsv_renderer_rebuild_seconds(r[th - 1]);
            vsv_render(r[th - 1], &sc, &cams[k], img, NULL);
            if (vsv_renderer_rebuild_seconds(r[th - 1]) != before)
                cls[th - 1] += vsv_renderer_rebuild_seconds(r[th - 1]);
        }
    }
    /* the pictures: each view on both sides (ours as floats and as bytes) */
    double pmin = INFINITY, psum = 0, pmin8 = INFINITY;
    for (int k = 0; k < FRAMES; k++) {
        vp_view(vpc, k);
        vp_check(vpc, vpRenderClassifiedVolume(vpc));
        vsv_render_rgba8(r[0], &sc, &cams[k], b8, NULL);
        pmin8 = fmin(pmin8, vp_psnr8(image, b8));
        vsv_render(r[0], &sc, &cams[k], img, NULL);
        const double p = vp_psnr(image, img);
        if (getenv("VP_DUMP")) {
            char png[1024];
            snprintf(png, sizeof png, "%s%d.png", getenv("VP_DUMP"), k);
            vp_dump(png, image, img);
            double ml[2] = {0, 0}, ma[2] = {0, 0};
            for (int i = 0; i < VP_SIZE * VP_SIZE; i++) {
                ml[0] += image[4 * i], ma[0] += image[4 * i + 3];
                ml[1] += 255 * img[4 * i], ma[1] += 255 * img[4 * i + 3];
            }
            printf("view %d: PSNR %.1f dB; mean red %.2f / %.2f, alpha %.2f / %.2f\n", k, p,
                   ml[0] / (VP_SIZE * VP_SIZE), ml[1] / (VP_SIZE * VP_SIZE), ma[0] / (VP_SIZE * VP_SIZE),
                   ma[1] / (VP_SIZE * VP_SIZE));
        }
        pmin = fmin(pmin, p);
        psum += fmin(p, 99);
    }
    /* the three render the views in turn, 16 rounds (so the machine's
     * changing load falls on all three alike; within a round each renders
     * view after view, as in an animation): per round each one's wall time
     * and the calling thread's CPU time (all of VolPack's work and of our one
     * thread's, whose renderer works on the caller's thread; for two threads
     * only the caller's share, so no CPU figure is given: wall time) */
    double wall[1 + NOURS][REPEAT], cput[1 + NOURS][REPEAT];
    time_rounds(vpc, r, &sc, cams, img, b8, wall, cput);
    const int counts = pmin >= 35 && pmin8 >= 35; /* a ratio only where the pictures match in every view */
    printf("volume: %s %s step %d, %dx%dx%d 8-bit (%.0f%% of voxels above 0); image %dx%d, parallel projection, %d "
           "views, %d rounds, VolPack and ours in turn; the pictures: PSNR %.1f dB the lowest of the views, "
           "%.1f dB their mean (ours as 8-bit RGBA: %.1f dB the lowest) (%s)\n\n",
           argv[1], argv[2], step, m->nx, m->ny, m->nz, 100.0 * nonzero / (double)nv, VP_SIZE, VP_SIZE, FRAMES, REPEAT,
           pmin, psum / FRAMES, pmin8,
           counts ? "matched: the comparison counts" : "NOT matched: below 35 dB, no comparison");
    print_rows(wall, cput, counts, cls, vp_classify);
    for (int i = 0; i < 2; i++)
        vsv_renderer_free(r[i]);
    free(b8);
    free(img);
    vpDestroyContext(vpc);
    free(image);
    vp_series_free(&S);
    return 0;
}
