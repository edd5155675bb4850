/* bench_classify.c — the shear-warp's classification and its frame rate
 * while playing, beside VolPack (Debian libvolpack1-dev) on the same
 * volumes in the same run: the real MM5 run's Q (dense), CLW and SNOW
 * (sparse), the real WRF file's QCLOUD (PLUME_DIR/wrf.vsv, when there:
 * bench_classify.sh converts it), gen-plume's plume and haze
 * (../shared/tools/gen-plume).
 *
 * Both sides draw the same picture: the same 8-bit volume, opacity matched
 * per unit length, views and termination (vp_match.h, as bench_volpack);
 * each volume's row ends with the PSNR between the two pictures of each
 * view (the lowest; a comparison counts at 35 dB or more).
 *
 * Classification: VolPack's vpClassifyVolume (it builds its run-length
 * encoded copy for all three axes) against ours for all three axes, first
 * time (every brick). Playing: the steps in turn, each frame a new step at
 * a fixed view, 4 views: VolPack classifies the new step and renders
 * (vpClassifyVolume + vpRenderClassifiedVolume; its other path for
 * changing data, vpRenderRawVolume, is timed too and the faster taken);
 * ours renders the new step's volume (as 8-bit RGBA, VolPack's image:
 * vsv_render_rgba8), re-classifying only bricks whose
 * values changed (decoded volumes held ready, as the player's pager holds
 * them: decoding is outside both timings). One thread on both sides. Times
 * are the thread's CPU time (the machine is shared; wall time moves with
 * other load), interleaved: each round times VolPack then us; medians and
 * ranges over rounds. Usage:
 *   bench_classify MM5.vsv PLUME_DIR [ROUNDS [ONLY]]  (ONLY: volumes whose name has it) */
#include "bench_stats.h"
#include "vp_match.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

enum { SIZE = VP_SIZE, VIEWS = 4 };

static double cpu(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* A volume's ratios to VolPack (classification, playing) and whether the
 * pictures matched, for the summary. */
typedef struct ratios {
    double cls, play;
    int matched;
} ratios;

static ratios run(vp_series *S, int rounds)
{
    unsigned char *image = malloc(SIZE * SIZE * 4);
    vpContext *vpc = vp_setup(S, image);
    vsv_layer layer;
    vsv_scene sc;
    vp_scene(S, &layer, &sc);
    vsv_camera cams[VIEWS];
    for (int k = 0; k < VIEWS; k++)
        vp_camera(&sc, k, &cams[k]);
    unsigned char *img = malloc(4 * SIZE * SIZE); /* ours as VolPack's: 8-bit RGBA */
    vsv_render_opts o;
    vsv_render_opts_init(&o);
    o.kind = VSV_RENDER_SHEARWARP;
    o.threads = 1;
    /* principal axes: views whose copies differ (the orbit meets x and y;
     * a view from above meets z) */
    vsv_camera axes[3];
    vsv_camera_orbit(&axes[0], &sc, 180, 10, 0, SIZE, SIZE);
    vsv_camera_orbit(&axes[1], &sc, 270, 10, 0, SIZE, SIZE);
    vsv_camera_orbit(&axes[2], &sc, 180, 85, 0, SIZE, SIZE);
    for (int i = 0; i < 3; i++) {
        axes[i].fov_deg = 0;
        axes[i].ortho_height = cams[0].ortho_height;
    }
    /* the pictures first: each view of step 0 on both sides, PSNR between
     * them (the comparison counts at 35 dB or more) */
    double pmin = INFINITY;
    {
        vsv_renderer *pr = NULL;
        if (vsv_renderer_create(&o, &pr))
            exit(1);
        vp_step(vpc, S, 0);
        vp_check(vpc, vpClassifyVolume(vpc));
        for (int v = 0; v < VIEWS; v++) {
            vp_view(vpc, v);
            vp_check(vpc, vpRenderClassifiedVolume(vpc));
            vsv_render_rgba8(pr, &sc, &cams[v], img, NULL);
            pmin = fmin(pmin, vp_psnr8(image, img));
        }
        vsv_renderer_free(pr);
    }
    double *vc = malloc(sizeof(double) * rounds), *oc = malloc(sizeof(double) * rounds);
    double *vp = malloc(sizeof(double) * rounds), *vr = malloc(sizeof(double) * rounds);
    double *op = malloc(sizeof(double) * rounds);
    long bricks = 0, frames = 0;
    double cold = 0;
    vsv_renderer *rr = NULL;
    if (vsv_renderer_create(&o, &rr))
        exit(1);
    /* one uncounted round first: caches, page faults, VolPack's tables */
    for (int r = -1; r < rounds; r++) {
        /* classification, every brick, all three axes */
        vp_step(vpc, S, 0);
        double t = cpu();
        vp_check(vpc, vpClassifyVolume(vpc));
        const double tv = cpu() - t;
        /* a new opacity (by one part in 2^22, alternately) makes every
         * brick classify again, on buffers already allocated (the first,
         * uncounted round allocates them: cold) */
        layer.vol = S->vol[0];
        layer.opacity = r & 1 ? 1.0f : 1.0f - 0x1p-22f;
        /* our classification's CPU time: a view's first frame less its second */
        double to = 0;
        for (int i = 0; i < 3; i++) {
            t = cpu();
            vsv_render_rgba8(rr, &sc, &axes[i], img, NULL);
            to += cpu() - t;
            t = cpu();
            vsv_render_rgba8(rr, &sc, &axes[i], img, NULL);
            to -= cpu() - t;
        }
        /* playing: each view, the steps in turn, twice round */
        double tp = 0, tr = 0, tq = 0;
        for (int v = 0; v < VIEWS; v++) {
            vp_view(vpc, v);
            for (int i = 0; i < 2 * S->nsteps; i++) {
                const int st = (i + 1) % S->nsteps;
                vp_step(vpc, S, st);
                t = cpu();
                vp_check(vpc, vpClassifyVolume(vpc));
                vp_check(vpc, vpRenderClassifiedVolume(vpc));
                tp += cpu() - t;
                t = cpu();
                vp_check(vpc, vpRenderRawVolume(vpc));
                tr += cpu() - t;
                layer.vol = S->vol[st];
                t = cpu();
                vsv_render_rgba8(rr, &sc, &cams[v], img, NULL);
                tq += cpu() - t;
                if (r >= 0) {
                    bricks += vsv_renderer_rebuild_bricks(rr);
                    frames++;
                }
            }
        }
        if (r < 0) {
            cold = to;
            continue;
        }
        vc[r] = tv, oc[r] = to;
        const int nf = VIEWS * 2 * S->nsteps;
        vp[r] = tp / nf, vr[r] = tr / nf, op[r] = tq / nf;
    }
    vsv_renderer_free(rr);
    double c0[3], c1[3], p0[3], p1[3], p2[3];
    bench_stats(vc, rounds, c0);
    bench_stats(oc, rounds, c1);
    bench_stats(vp, rounds, p0);
    bench_stats(vr, rounds, p1);
    bench_stats(op, rounds, p2);
    const vsv_meta *m = &S->iso;
    size_t vis = 0;
    for (size_t i = 0; i < (size_t)m->nx * m->ny * m->nz; i++)
        vis += S->vox[0][4 * i + 2] > 0;
    const double *vbest = p1[0] < p0[0] ? p1 : p0;
    printf("| %s | %dx%dx%d, %d steps, %.0f%% of voxels above 0 | %.1f (%.1f–%.1f) | %.1f (%.1f–%.1f); cold %.0f | "
           "**%.2f** | "
           "%.1f (%.1f–%.1f) / %.1f (%.1f–%.1f) | %.1f (%.1f–%.1f) | %.0f %% | **%.2f** (%.2f–%.2f) | %.1f%s |\n",
           S->name, m->nx, m->ny, m->nz, S->nsteps, 100.0 * vis / ((double)m->nx * m->ny * m->nz), 1e3 * c0[0],
           1e3 * c0[1], 1e3 * c0[2], 1e3 * c1[0], 1e3 * c1[1], 1e3 * c1[2], 1e3 * cold, c0[0] / c1[0], 1e3 * p0[0],
           1e3 * p0[1], 1e3 * p0[2], 1e3 * p1[0], 1e3 * p1[1], 1e3 * p1[2], 1e3 * p2[0], 1e3 * p2[1], 1e3 * p2[2],
           100.0 * bricks / ((double)frames * S->vol[0]->nbricks), vbest[0] / p2[0], vbest[1] / p2[2], vbest[2] / p2[1],
           pmin, pmin >= 35 ? "" : " (NOT matched: no comparison)");
    fflush(stdout);
    free(vc), free(oc), free(vp), free(vr), free(op);
    free(img);
    vpDestroyContext(vpc);
    free(image);
    return (ratios){c0[0] / c1[0], vbest[0] / p2[0], pmin >= 35};
}

/* One line of the summary: the worst and best of n ratios (those of
 * matched pictures) beside the goal, and the volumes below it. */
static void summary(const char *what, const double *x, const char *const *names, const int *matched, int n)
{
    int lo = -1, hi = -1;
    for (int i = 0; i < n; i++)
        if (matched[i]) {
            lo = lo < 0 || x[i] < x[lo] ? i : lo;
            hi = hi < 0 || x[i] > x[hi] ? i : hi;
        }
    if (lo < 0)
        return;
    printf("%s: worst %.2f× (%s), best %.2f× (%s); ", what, x[lo], names[lo], x[hi], names[hi]);
    int below = 0;
    for (int i = 0; i < n; i++)
        if (matched[i] && x[i] < 1.5)
            printf("%s%s %.2f×", below++ ? ", " : "the 1.5× goal not met on ", names[i], x[i]);
    printf("%s\n", below ? "" : "the 1.5× goal met on every volume");
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: bench_classify MM5.vsv PLUME_DIR [ROUNDS]\n");
        return 2;
    }
    const int rounds = argc > 3 ? atoi(argv[3]) : 5;
    char plume[1024], haze[1024];
    snprintf(plume, sizeof plume, "%s/plume.vsv", argv[2]);
    snprintf(haze, sizeof haze, "%s/haze.vsv", argv[2]);
    char wrf[1024];
    snprintf(wrf, sizeof wrf, "%s/wrf.vsv", argv[2]);
    const char *pn[] = {"plume_t0.f32", "plume_t1.f32"}, *hn[] = {"plume_haze.f32", "plume_t1.f32"};
    if (vp_write_plume(argv[2], plume, pn, 2) || vp_write_plume(argv[2], haze, hn, 2))
        return 1;
    printf("Classification: every brick, all three axes (VolPack: vpClassifyVolume; ours: the three principal axes'\n"
           "copies). Playing: each frame a new step (the series' steps in turn at each of %d views); VolPack\n"
           "classifies and renders (vpClassifyVolume + vpRenderClassifiedVolume, or vpRenderRawVolume: the faster\n"
           "is compared), ours re-classifies the bricks that changed and renders. One thread, CPU ms, median\n"
           "(range) over %d rounds, %dx%d image, 8-bit RGBA on both sides (ours: vsv_render_rgba8).\n\n",
           VIEWS, rounds, SIZE, SIZE);
    printf("| volume | grid | VolPack classify ms | ours ms (cold: first time, buffers allocated) | × | VolPack "
           "playing ms/frame: classify+render / raw | "
           "ours ms/frame | bricks re-classified | × VolPack's frame rate | PSNR dB, lowest of the views |\n"
           "|---|---|---|---|---|---|---|---|---|---|\n");
    struct {
        const char *name, *path, *species;
        int first, n;
    } sets[] = {{"MM5 Q", argv[1], "Q", 1, 3},
                {"MM5 CLW", argv[1], "CLW", 1, 3},
                {"MM5 SNOW", argv[1], "SNOW", 1, 3},
                {"WRF Katrina QCLOUD", wrf, "QCLOUD", 1, 3},
                {"gen-plume plume", plume, "plume", 0, 2},
                {"gen-plume haze", haze, "plume", 0, 2}};
    enum { NSETS = sizeof sets / sizeof sets[0] };
    double cls[NSETS], play[NSETS];
    const char *names[NSETS];
    int matched[NSETS], n = 0;
    for (size_t i = 0; i < NSETS; i++) {
        if ((argc > 4 && !strstr(sets[i].name, argv[4])) || (sets[i].path == wrf && access(wrf, R_OK)))
            continue;
        vp_series S;
        if (vp_series_open(&S, sets[i].name, sets[i].path, sets[i].species, sets[i].first, sets[i].n))
            return 1;
        const ratios r = run(&S, rounds);
        cls[n] = r.cls, play[n] = r.play, matched[n] = r.matched, names[n++] = sets[i].name;
        vp_series_free(&S);
    }
    printf("\nWorst beside best, × VolPack (one thread's CPU; volumes whose pictures matched):\n");
    summary("classification", cls, names, matched, n);
    summary("playing", play, names, matched, n);
    return 0;
}
