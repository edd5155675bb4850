/* bench_gl.c — the GPU raycaster against the CPU raycaster (issue #31):
 *
 *   bench_gl FILE.vsv SPECIES WxH FRAMES
 *
 * opens FILE's last step with SPECIES (comma-separated; "-": the default
 * ones), makes a headless OpenGL context (EGL), and renders FRAMES frames
 * of WxH with each renderer at the same cameras (an orbit, 2 degrees a
 * frame: every frame renders anew, the ground included, for both), the
 * renderers interleaved frame by frame. Prints per renderer the frames a
 * second (wall) and the process's CPU milliseconds a frame, the ratio, the
 * PSNR of the first frames (over the pixels either covers: the pictures
 * must match for the timing to count) and the OpenGL device: on Mesa's
 * llvmpipe the "GPU" is this machine's CPU. */
#include "vsv_gl.h"
#include "vsv_player.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now(clockid_t c)
{
    struct timespec ts;
    clock_gettime(c, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

static double psnr(const unsigned char *a, const unsigned char *b, int n, const float bg[3])
{
    unsigned char bg8[3];
    for (int c = 0; c < 3; c++)
        bg8[c] = (unsigned char)lrint(255 * pow(bg[c], 1 / 2.2));
    double se = 0;
    long cnt = 0;
    for (int i = 0; i < n; i++) {
        int cov = 0;
        for (int c = 0; c < 3; c++)
            cov |= abs(a[3 * i + c] - bg8[c]) > 8 || abs(b[3 * i + c] - bg8[c]) > 8;
        if (!cov)
            continue;
        cnt++;
        for (int c = 0; c < 3; c++)
            se += (double)(a[3 * i + c] - b[3 * i + c]) * (a[3 * i + c] - b[3 * i + c]);
    }
    return !cnt ? 0 : se == 0 ? 99 : 10 * log10(255.0 * 255 * 3 * cnt / se);
}

int main(int argc, char **argv)
{
    int w, h;
    if (argc != 5 || sscanf(argv[3], "%dx%d", &w, &h) != 2 || w < 1 || h < 1 || atoi(argv[4]) < 1) {
        fprintf(stderr, "usage: bench_gl FILE.vsv SPECIES|- WxH FRAMES\n");
        return 2;
    }
    const int frames = atoi(argv[4]);
    char err[1024];
    vsv_gl_context *ctx = NULL;
    if (vsv_gl_context_create(&ctx, err, sizeof err)) {
        fprintf(stderr, "bench_gl: %s\n", err);
        return 1;
    }
    static int said;
    if (!said++) { /* the device, once */
        vsv_gl *g = NULL;
        if (!vsv_gl_create(NULL, &g, err, sizeof err))
            printf("OpenGL device: %s%s\n", vsv_gl_device(g),
                   vsv_gl_context_software() ? " (a software rasteriser: the CPU)" : "");
        vsv_gl_free(g);
    }
    vsv_player *p[2] = {NULL, NULL};
    for (int k = 0; k < 2; k++) {
        vsv_player_opts o;
        vsv_player_opts_init(&o);
        o.path = argv[1];
        o.species = strcmp(argv[2], "-") ? argv[2] : NULL;
        o.renderer = k ? VSV_RENDER_GL : VSV_RENDER_RAYCAST;
        o.cache_bytes = (size_t)1 << 30;
        if (vsv_player_open(&o, &p[k], err, sizeof err)) {
            fprintf(stderr, "bench_gl: %s\n", err);
            return 1;
        }
        vsv_player_do(p[k], "end", err, sizeof err);
        vsv_player_update(p[k], 0, 1);
    }
    unsigned char *first[2] = {malloc((size_t)w * h * 3), malloc((size_t)w * h * 3)};
    double wall[2] = {0, 0}, cpu[2] = {0, 0};
    for (int f = 0; f < frames + 1; f++) /* frame 0: warm-up (shaders, bricks, copies), not timed */
        for (int k = 0; k < 2; k++) {
            char act[64];
            snprintf(act, sizeof act, "camera %g 30", 225.0 + 2 * f);
            vsv_player_do(p[k], act, err, sizeof err);
            vsv_camera cam;
            vsv_player_camera(p[k], w, h, &cam);
            const double t0 = now(CLOCK_MONOTONIC), c0 = now(CLOCK_PROCESS_CPUTIME_ID);
            const unsigned char *img = vsv_player_image(p[k], &cam, err, sizeof err);
            const double t1 = now(CLOCK_MONOTONIC), c1 = now(CLOCK_PROCESS_CPUTIME_ID);
            if (!img) {
                fprintf(stderr, "bench_gl: %s\n", err);
                return 1;
            }
            if (f == 0)
                memcpy(first[k], img, (size_t)w * h * 3);
            else
                wall[k] += t1 - t0, cpu[k] += c1 - c0;
        }
    const double db = psnr(first[0], first[1], w * h, vsv_player_background(p[0]));
    printf("%-28s %4dx%-4d  CPU raycast %6.2f frames/s %8.1f ms CPU   GPU raycast %6.2f frames/s %8.1f ms CPU   "
           "GPU/CPU %5.2fx   %.1f dB\n",
           argv[1], w, h, frames / wall[0], 1000 * cpu[0] / frames, frames / wall[1], 1000 * cpu[1] / frames,
           wall[0] / wall[1], db);
    vsv_player_free(p[0]);
    vsv_player_free(p[1]);
    free(first[0]);
    free(first[1]);
    vsv_gl_context_free(ctx);
    return 0;
}
