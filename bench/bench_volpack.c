/* bench_volpack.c — the shear-warp renderer beside VolPack, Lacroute's own
 * shear-warp (Debian libvolpack1-dev), on the same 8-bit volume (one species
 * of a .vsv quantised to 0..255 over its range), the same linear opacity
 * ramp, parallel projection, 512x512, orbiting 8 views. VolPack is
 * single-threaded; Vesuvius runs with 1 and 2 threads. The three render
 * the orbit in turn, 16 rounds, so a change in the machine's load falls on
 * all alike. Classification is outside the timing on both sides (and
 * reported). Usage:
 *   bench_volpack FILE.vsv SPECIES [STEP] */
#include "vsv_render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <volpack.h>

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

enum { SIZE = 512, FRAMES = 8, REPEAT = 16 }; /* 8 views, each timed 16 times */

int main(int argc, char **argv)
{
    vsv_file *f = NULL;
    vsv_decoder *d = NULL;
    if (argc < 3 || vsv_file_open(argv[1], &f) || vsv_decoder_create(f, &d)) {
        fprintf(stderr, "usage: bench_volpack FILE.vsv SPECIES [STEP]\n");
        return 2;
    }
    const vsv_meta *m = vsv_file_meta(f);
    vsv_file_info info;
    vsv_file_info_get(f, &info);
    const int s = vsv_meta_find_var(m, argv[2]), step = argc > 3 ? atoi(argv[3]) : info.nsteps - 1;
    vsv_volume *vol = NULL;
    if (s < 0 || vsv_volume_create(f, &vol) || vsv_volume_load(vol, d, step, s))
        return 1;
    const vsv_quant *q = vsv_file_quant(f, s);
    const double lo = q->lo, hi = q->hi > q->lo ? q->hi : q->lo + 1;
    const int nx = m->nx, ny = m->ny, nz = m->nz;
    /* the 8-bit volume both renderers see */
    unsigned char *dens = malloc((size_t)nx * ny * nz);
    for (int k = 0; k < nz; k++)
        for (int j = 0; j < ny; j++)
            for (int i = 0; i < nx; i++) {
                const float v = vsv_volume_at(vol, i, j, k);
                const double t = v == v ? (v - lo) / (hi - lo) : 0;
                dens[((size_t)k * ny + j) * nx + i] = (unsigned char)lrint(255 * fmin(1, fmax(0, t)));
            }
    /* ------------------------------------------------------------ VolPack */
    vpContext *vpc = vpCreateContext();
    vpSetVolumeSize(vpc, nx, ny, nz);
    /* voxel = {uint16 shade index, uint8 density, pad}: VolPack wants the
     * shading field first and two bytes wide */
    unsigned char *vox = calloc((size_t)nx * ny * nz, 4);
    for (size_t i = 0; i < (size_t)nx * ny * nz; i++) {
        const uint16_t si = dens[i];
        memcpy(vox + 4 * i, &si, 2);
        vox[4 * i + 2] = dens[i];
    }
    vpSetVoxelSize(vpc, 4, 2, 1, 1);
    vpSetVoxelField(vpc, 0, 2, 0, 255);
    vpSetVoxelField(vpc, 1, 1, 2, 255);
    vpSetRawVoxels(vpc, vox, (int)((size_t)nx * ny * nz * 4), 4, 4 * nx, 4 * nx * ny);
    float ramp[256], shade[256];
    for (int i = 0; i < 256; i++) {
        ramp[i] = i / 255.0f;   /* the opacity ramp */
        shade[i] = 0.4f + 0.6f * i / 255.0f;
    }
    vpSetClassifierTable(vpc, 0, 1, ramp, sizeof ramp);
    if (vpSetLookupShader(vpc, 1, 1, 0, shade, sizeof shade, 0, NULL, 0) != VP_OK)
        fprintf(stderr, "VolPack shader: %s\n", vpGetErrorString(vpGetError(vpc)));
    vpSetd(vpc, VP_MIN_VOXEL_OPACITY, 1.0 / 255);
    vpSetd(vpc, VP_MAX_RAY_OPACITY, 0.998);
    double t0 = now();
    if (vpClassifyVolume(vpc) != VP_OK) {
        fprintf(stderr, "VolPack: %s\n", vpGetErrorString(vpGetError(vpc)));
        return 1;
    }
    const double vp_classify = now() - t0;
    unsigned char *image = malloc(SIZE * SIZE * 2);
    vpSetImage(vpc, image, SIZE, SIZE, SIZE * 2, VP_LUMINANCEA);
    vpCurrentMatrix(vpc, VP_PROJECT);
    vpIdentityMatrix(vpc);
    vpWindow(vpc, VP_PARALLEL, -0.75, 0.75, -0.75, 0.75, -0.75, 0.75);
    vpCurrentMatrix(vpc, VP_MODEL);
    /* the model tilted 60 degrees (the eye 30 degrees up), then each frame
     * turned about the volume's own vertical axis: an orbit, as on our side */
    vpSeti(vpc, VP_CONCAT_MODE, VP_CONCAT_LEFT);
    vpRotate(vpc, VP_X_AXIS, -60.0);
    vpSeti(vpc, VP_CONCAT_MODE, VP_CONCAT_RIGHT);
    vpRenderClassifiedVolume(vpc); /* warm-up */
    /* ------------------------------------------------------------ Vesuvius */
    vsv_tf tf;
    char text[256], msg[128];
    /* values that quantise to 0 in the 8-bit volume are below the range, so
     * transparent on both sides (VolPack skips voxels of opacity 0) */
    size_t nonzero = 0;
    for (size_t i = 0; i < (size_t)nx * ny * nz; i++)
        nonzero += dens[i] > 0;
    snprintf(text, sizeof text, "colormap greys\nrange %.9g %.9g\nopacity 0 1\n", lo + (hi - lo) * 0.5 / 255, hi);
    if (vsv_tf_parse(&tf, text, msg, sizeof msg))
        return 1;
    vsv_layer layer = {vol, &tf, 1, 1};
    vsv_meta iso = *m; /* isotropic cells, as VolPack sees them */
    iso.spacing[0] = iso.spacing[1] = iso.spacing[2] = 1000;
    iso.vert_kind = VSV_VERT_EVEN;
    iso.levels = NULL;
    iso.terrain = NULL;
    vsv_scene sc = {.meta = &iso, .layers = &layer, .nlayers = 1, .exaggeration = 1, .show_terrain = 0};
    double mn[3], mx[3];
    vsv_scene_bounds(&sc, mn, mx);
    vsv_camera cams[FRAMES];
    for (int k = 0; k < FRAMES; k++) {
        vsv_camera_orbit(&cams[k], &sc, 225 + 45 * k, 30, 0, SIZE, SIZE);
        cams[k].fov_deg = 0;
        cams[k].ortho_height = 1.5 * fmax(fmax(mx[0] - mn[0], mx[1] - mn[1]), mx[2] - mn[2]);
    }
    float *img = malloc(sizeof(float) * 4 * SIZE * SIZE);
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
    /* the three orbit in turn, 16 rounds (so the machine's changing load
     * falls on all three alike; within an orbit each renders frame after
     * frame, as in an animation) */
    double sum[3] = {0, 0, 0};
    for (int rep = 0; rep < REPEAT; rep++) {
        double t = now();
        for (int k = 0; k < FRAMES; k++) {
            vpRotate(vpc, VP_Z_AXIS, 45.0);
            if (vpRenderClassifiedVolume(vpc) != VP_OK) {
                fprintf(stderr, "VolPack: %s\n", vpGetErrorString(vpGetError(vpc)));
                return 1;
            }
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
           "orbiting views, %d orbits each, the three renderers in turn\n\n",
           argv[1], argv[2], step, nx, ny, nz, 100.0 * nonzero / ((double)nx * ny * nz), SIZE, SIZE, FRAMES, REPEAT);
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
    free(vox);
    free(dens);
    vsv_volume_free(vol);
    vsv_decoder_free(d);
    vsv_file_free(f);
    return 0;
}
