/* bench_volpack.c — the shear-warp renderer beside VolPack, Lacroute's own
 * shear-warp (Debian libvolpack1-dev), drawing the same picture: the same
 * 8-bit volume, opacity matched per unit length, the same grey, views,
 * image size and ray termination (vp_match.h). Each view's two images are
 * compared (PSNR over luminance and alpha; a comparison counts only at 35 dB
 * or more, and the table says whether every view got there). VolPack is
 * single-threaded; Vesuvius runs with 1 and 2 threads. The three render the
 * 8 views in turn, 16 rounds, so a change in the machine's load falls on
 * all alike (wall time). Classification is outside the timing on both
 * sides (and reported). Usage:
 *   bench_volpack FILE.vsv SPECIES [STEP] */
#include "vp_match.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

enum { FRAMES = 8, REPEAT = 16 }; /* 8 views, each timed 16 times */

int main(int argc, char **argv)
{
    vp_series S;
    if (argc < 3) {
        fprintf(stderr, "usage: bench_volpack FILE.vsv SPECIES [STEP]\n");
        return 2;
    }
    int step = argc > 3 ? atoi(argv[3]) : 0;
    if (vp_series_open(&S, argv[2], argv[1], argv[2], step, 1))
        return 1;
    const vsv_meta *m = &S.iso;
    const size_t nv = (size_t)m->nx * m->ny * m->nz;
    size_t nonzero = 0;
    for (size_t i = 0; i < nv; i++)
        nonzero += S.vox[0][4 * i + 2] > 0;
    /* ------------------------------------------------------------ VolPack */
    unsigned char *image = malloc(VP_SIZE * VP_SIZE * 2);
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
    /* the pictures: each view on both sides */
    double pmin = INFINITY, psum = 0;
    for (int k = 0; k < FRAMES; k++) {
        vp_view(vpc, k);
        vp_check(vpc, vpRenderClassifiedVolume(vpc));
        vsv_render(r[0], &sc, &cams[k], img, NULL);
        const double p = vp_psnr(image, img);
        pmin = fmin(pmin, p);
        psum += fmin(p, 99);
    }
    /* the three render the views in turn, 16 rounds (so the machine's
     * changing load falls on all three alike; within a round each renders
     * view after view, as in an animation) */
    double sum[3] = {0, 0, 0};
    for (int rep = 0; rep < REPEAT; rep++) {
        double t = now();
        for (int k = 0; k < FRAMES; k++) {
            vp_view(vpc, k);
            vp_check(vpc, vpRenderClassifiedVolume(vpc));
        }
        sum[0] += now() - t;
        for (int i = 0; i < 2; i++) {
            t = now();
            for (int k = 0; k < FRAMES; k++)
                vsv_render(r[i], &sc, &cams[k], img, NULL);
            sum[1 + i] += now() - t;
        }
    }
    printf("volume: %s %s step %d, %dx%dx%d 8-bit (%.0f%% of voxels above 0); image %dx%d, parallel projection, %d "
           "views, %d rounds, the three renderers in turn; the pictures: PSNR %.1f dB the lowest of the views, "
           "%.1f dB their mean (%s)\n\n",
           argv[1], argv[2], step, m->nx, m->ny, m->nz, 100.0 * nonzero / (double)nv, VP_SIZE, VP_SIZE, FRAMES, REPEAT,
           pmin, psum / FRAMES, pmin >= 35 ? "matched: the comparison counts" : "NOT matched: below 35 dB, no comparison");
    printf("| renderer | threads | ms/frame | frames/s | × VolPack's frame rate | classification ms (all axes) |\n"
           "|---|---|---|---|---|---|\n");
    const double vp_frame = sum[0] / (FRAMES * REPEAT);
    printf("| VolPack vpRenderClassifiedVolume | 1 | %.2f | %.1f | 1 | %.0f |\n", 1000 * vp_frame, 1 / vp_frame,
           1000 * vp_classify);
    for (int i = 0; i < 2; i++) {
        const double fr = sum[1 + i] / (FRAMES * REPEAT);
        printf("| Vesuvius shear-warp | %d | %.2f | %.1f | %.2f | %.0f |\n", i + 1, 1000 * fr, 1 / fr, vp_frame / fr,
               1000 * cls[i]);
        vsv_renderer_free(r[i]);
    }
    free(img);
    vpDestroyContext(vpc);
    free(image);
    vp_series_free(&S);
    return 0;
}
