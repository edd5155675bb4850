/* bench_render.c — raycaster frames per second on a .vsv: every species of
 * one step, the default camera orbiting 8 azimuths, at the given sizes, with
 * 1 and all threads. Decoding is outside the timing. Usage:
 *   bench_render FILE.vsv [STEP [SPECIES]]
 * With SPECIES (a name) only that species is drawn, and its decoded volume
 * is written to FILE.vsv.raw (float32, x fastest) with a line of geometry on
 * stdout, so bench_vtk.py can render the same volume with VTK.
 * Each time is the fastest of PASSES passes over the frames (bench_vtk.py
 * does the same), so a pass slowed by the rest of the machine does not count.
 * VSV_BENCH_NO_TERRAIN=1 leaves the ground out (VTK draws none);
 * VSV_BENCH_SW_ONLY=1 times the shear-warp alone; VSV_SIMD=0 makes the
 * raycaster march one ray at a time. */
#include "vsv_render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

enum { PASSES = 3 };

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

int main(int argc, char **argv)
{
    vsv_file *f = NULL;
    vsv_decoder *d = NULL;
    if (argc < 2 || vsv_file_open(argv[1], &f) || vsv_decoder_create(f, &d)) {
        fprintf(stderr, "bench_render: %s\n", f ? vsv_file_error(f) : "usage: bench_render FILE.vsv [STEP]");
        return 1;
    }
    const vsv_meta *m = vsv_file_meta(f);
    vsv_file_info info;
    vsv_file_info_get(f, &info);
    const int step = argc > 2 ? atoi(argv[2]) : info.nsteps - 1;
    vsv_layer *L = calloc((size_t)m->nvars, sizeof *L);
    vsv_tf *tf = calloc((size_t)m->nvars, sizeof *tf);
    for (int s = 0; s < m->nvars; s++) {
        char text[512], msg[128];
        vsv_volume *v = NULL;
        vsv_tf_default(m->vars[s].name, vsv_file_quant(f, s), text, sizeof text);
        if (vsv_tf_parse(&tf[s], text, msg, sizeof msg) || vsv_volume_create(f, &v) || vsv_volume_load(v, d, step, s))
            return 1;
        L[s] = (vsv_layer){v, &tf[s], 1, 1};
    }
    int nl = m->nvars;
    if (argc > 3) {
        const int s = vsv_meta_find_var(m, argv[3]);
        if (s < 0)
            return 1;
        L[0] = L[s];
        nl = 1;
    }
    vsv_scene sc = {
        .meta = m, .layers = L, .nlayers = nl, .exaggeration = 1, .show_terrain = !getenv("VSV_BENCH_NO_TERRAIN")};
    double mn[3], mx[3];
    vsv_scene_bounds(&sc, mn, mx);
    sc.exaggeration = fmax(1, round(0.2 * fmax(mx[0] - mn[0], mx[1] - mn[1]) / (mx[2] - fmin(0, mn[2]))));
    if (argc > 3) {
        /* the volume and the camera for the VTK side */
        char raw[4096];
        snprintf(raw, sizeof raw, "%s.raw", argv[1]);
        FILE *fp = fopen(raw, "wb");
        for (int k = 0; k < m->nz; k++)
            for (int j = 0; j < m->ny; j++)
                for (int i = 0; i < m->nx; i++) {
                    float v = vsv_volume_at(L[0].vol, i, j, k);
                    v = v == v ? v : 0;
                    fwrite(&v, 4, 1, fp);
                }
        fclose(fp);
        vsv_camera cam;
        vsv_camera_orbit(&cam, &sc, 225, 30, 0, 512, 512);
        printf("geometry %d %d %d %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g\n", m->nx, m->ny, m->nz,
               m->origin[0], m->origin[1], m->origin[2] * sc.exaggeration, m->spacing[0], m->spacing[1],
               m->spacing[2] * sc.exaggeration, cam.pos[0], cam.pos[1], cam.pos[2], L[0].tf->lo, L[0].tf->hi,
               (double)L[0].tf->opacity[L[0].tf->nopacity - 1]);
    }
    printf("| renderer | image | threads | frames/s | ms/frame |\n|---|---|---|---|---|\n");
    const int sizes[2] = {512, 1024};
    for (int kind = getenv("VSV_BENCH_SW_ONLY") ? 1 : 0; kind < 2; kind++)
        for (int si = 0; si < 2; si++)
            for (int th = 1; th <= 2; th++) {
                vsv_render_opts o;
                vsv_render_opts_init(&o);
                o.threads = th;
                o.kind = kind ? VSV_RENDER_SHEARWARP : VSV_RENDER_RAYCAST;
                vsv_renderer *r = NULL;
                vsv_renderer_create(&o, &r);
                const int n = sizes[si];
                float *img = malloc(sizeof(float) * 4 * (size_t)n * n);
                vsv_camera cam;
                vsv_camera_orbit(&cam, &sc, 225, 30, 0, n, n);
                vsv_render(r, &sc, &cam, img, NULL); /* warm-up (and the shear-warp's classification) */
                const double rebuild = vsv_renderer_rebuild_seconds(r);
                const int frames = si ? 4 : 8;
                double dt = INFINITY;
                for (int pass = 0; pass < PASSES; pass++) {
                    const double t0 = now();
                    for (int k = 0; k < frames; k++) {
                        vsv_camera keep = cam;
                        vsv_camera_orbit(&cam, &sc, 225 + 45 * k, 30, 0, n, n);
                        cam.fov_deg = keep.fov_deg;
                        cam.ortho_height = keep.ortho_height;
                        vsv_render(r, &sc, &cam, img, NULL);
                    }
                    dt = fmin(dt, (now() - t0) / frames);
                }
                printf("| %s | %dx%d | %d | %.2f | %.0f |\n", kind ? "shear-warp" : "raycast", n, n, th, 1 / dt,
                       1000 * dt);
                if (si == 0)
                    printf("| (%s) | | %d | | %.1f |\n",
                           kind ? "shear-warp classification, one viewing axis" : "raycast sampling copy", th,
                           1000 * rebuild);
                fflush(stdout);
                free(img);
                vsv_renderer_free(r);
            }
    /* playback: the same view while the time step changes (what vsv-play
     * does while playing): every frame a new step, so the shear-warp
     * reclassifies; the ground is kept */
    if (argc <= 3 && info.nsteps > 1) {
        vsv_layer *L2 = calloc((size_t)m->nvars, sizeof *L2);
        for (int s = 0; s < m->nvars; s++) {
            vsv_volume *v = NULL;
            if (vsv_volume_create(f, &v) || vsv_volume_load(v, d, step > 0 ? step - 1 : 1, s))
                return 1;
            L2[s] = (vsv_layer){v, &tf[s], 1, 1};
        }
        vsv_scene sc2 = sc;
        sc2.layers = L2;
        printf("\nplayback (the view fixed, a new time step every frame), 512x512:\n\n"
               "| renderer | threads | frames/s | ms/frame |\n|---|---|---|---|\n");
        for (int kind = 0; kind < 2; kind++)
            for (int th = 1; th <= 2; th++) {
                vsv_render_opts o;
                vsv_render_opts_init(&o);
                o.threads = th;
                o.kind = kind ? VSV_RENDER_SHEARWARP : VSV_RENDER_RAYCAST;
                vsv_renderer *r = NULL;
                vsv_renderer_create(&o, &r);
                float *img = malloc(sizeof(float) * 4 * 512 * 512);
                vsv_camera cam;
                vsv_camera_orbit(&cam, &sc, 225, 30, 0, 512, 512);
                vsv_render(r, &sc, &cam, img, NULL);
                const int frames = kind ? 16 : 4;
                double dt = INFINITY;
                for (int pass = 0; pass < PASSES; pass++) {
                    const double t0 = now();
                    for (int k = 0; k < frames; k++)
                        vsv_render(r, k % 2 ? &sc : &sc2, &cam, img, NULL);
                    dt = fmin(dt, (now() - t0) / frames);
                }
                printf("| %s | %d | %.2f | %.0f |\n", kind ? "shear-warp" : "raycast", th, 1 / dt, 1000 * dt);
                fflush(stdout);
                free(img);
                vsv_renderer_free(r);
            }
    }
    return 0;
}
