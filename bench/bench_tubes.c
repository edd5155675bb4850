/* bench_tubes.c — lines drawn as lit tubes (vsv_scene.lines, issue 35):
 * frame times with N paths against none. Usage:
 *   bench_tubes [ROUNDS]
 * The scene: a 100 x 100 x 40 grid of 1 km cells (no volume, no terrain),
 * paths of 200 points each wandering through it (a fixed pseudo-random
 * walk, 1 km a step: trajectories of 200 recorded points), radius 1/300 of
 * the domain, arrowheads; frames 512 x 384 on 2 threads, the oblique view,
 * raycast. Prints medians for 0, 10, 100 and 400 paths. */
#include "bench_stats.h"
#include "vsv_render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

enum { W = 512, H = 384, NP = 200, MAXL = 400, MAXR = 32 };

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

int main(int argc, char **argv)
{
    const int R = argc > 1 ? (atoi(argv[1]) < 1 ? 1 : atoi(argv[1]) > MAXR ? MAXR : atoi(argv[1])) : 5;
    vsv_meta m;
    vsv_meta_init(&m);
    m.nx = m.ny = 100, m.nz = 40;
    m.spacing[0] = m.spacing[1] = m.spacing[2] = 1000;
    m.vert_kind = VSV_VERT_EVEN;
    double *xyz = malloc(sizeof(double) * 3 * NP * MAXL);
    vsv_scene_line *L = malloc(sizeof *L * MAXL);
    uint64_t s = 88172645463325252ull;
    for (int l = 0; l < MAXL; l++) {
        double p[3] = {10000 + (s % 80000), 10000 + (s / 80000 % 80000), 3000 + (s / 6400000000ull % 30000)};
        double dir = (double)(s % 628) / 100;
        for (int i = 0; i < NP; i++) {
            s ^= s << 13, s ^= s >> 7, s ^= s << 17;
            dir += ((double)(s % 1000) / 1000 - 0.5) * 0.3;
            p[0] += 1000 * cos(dir), p[1] += 1000 * sin(dir), p[2] += ((double)(s % 200) - 100);
            memcpy(xyz + 3 * ((size_t)l * NP + i), p, sizeof p);
        }
        L[l] = (vsv_scene_line){xyz + 3 * (size_t)l * NP, NP, 100000.0 / 300, 1, {0.95f, 0.85f, 0.2f}};
    }
    vsv_scene sc = {.meta = &m, .exaggeration = 1, .lines = L};
    vsv_scene_sun(&sc, 315, 45);
    vsv_camera cam;
    vsv_camera_fit(&cam, &sc, 225, 30, W, H);
    vsv_render_opts o;
    vsv_render_opts_init(&o);
    o.threads = 2;
    vsv_renderer *r = NULL;
    float *img = malloc(sizeof(float) * 4 * W * H);
    if (vsv_renderer_create(&o, &r) || !img || !xyz || !L) {
        fprintf(stderr, "bench_tubes: cannot start the renderer\n");
        return 1;
    }
    printf("scene: 100 x 100 x 40 km, no volume; paths of %d points, radius %.0f m, arrowheads; %dx%d, 2 threads, "
           "raycast, %d rounds (medians)\n",
           NP, L[0].radius, W, H, R);
    const int counts[] = {0, 10, 100, 400};
    double base = 0;
    for (int c = 0; c < 4; c++) {
        sc.nlines = counts[c];
        double t[MAXR];
        for (int k = 0; k < R; k++) {
            const double t0 = now();
            if (vsv_render(r, &sc, &cam, img, NULL))
                return 1;
            t[k] = now() - t0;
        }
        double st[3];
        bench_stats(t, R, st);
        const double med = st[0];
        if (!c)
            base = med;
        printf("%4d paths (%7d triangles): %7.1f ms a frame, %+7.1f ms for the tubes\n", counts[c],
               counts[c] * ((NP - 1) * 2 * VSV_TUBE_SIDES + 3 * VSV_TUBE_SIDES), med * 1e3, (med - base) * 1e3);
    }
    vsv_renderer_free(r);
    free(img), free(xyz), free(L);
    vsv_meta_clear(&m);
    return 0;
}
