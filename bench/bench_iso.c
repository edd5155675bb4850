/* bench_iso.c — isosurfaces (vsv_iso_*, issue 35): extraction and drawing
 * times on a real file. Usage:
 *   bench_iso FILE.vsv SPECIES VALUE [ROUNDS]
 * Per round: every step extracted afresh (a new extractor each step: every
 * straddling brick done) and in order by one extractor (bricks whose
 * neighbourhood did not change kept), wall time on 2 threads; then frames
 * (512x384, 2 threads, terrain on, the oblique view) of the last step:
 * the species as a volume, the isosurface alone (the first frame after a
 * step, extracting, and a second, only drawing), and both. Prints medians. */
#include "vsv_render.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

enum { W = 512, H = 384, MAXSTEPS = 64, MAXR = 32 };

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

static int cmp(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}
static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* One frame of sc; wall seconds, or -1. */
static double frame(vsv_renderer *r, const vsv_scene *sc, const vsv_camera *cam, float *img)
{
    const double t0 = now();
    return vsv_render(r, sc, cam, img, NULL) ? -1 : now() - t0;
}

int main(int argc, char **argv)
{
    if (argc < 4) {
        fprintf(stderr, "usage: bench_iso FILE.vsv SPECIES VALUE [ROUNDS]\n");
        return 2;
    }
    const int R = argc > 4 ? (atoi(argv[4]) < 1 ? 1 : atoi(argv[4]) > MAXR ? MAXR : atoi(argv[4])) : 5;
    const float value = strtof(argv[3], NULL);
    vsv_file *f = NULL;
    vsv_decoder *d = NULL;
    if (vsv_file_open(argv[1], &f) || vsv_decoder_create(f, &d)) {
        fprintf(stderr, "bench_iso: %s\n", f ? vsv_file_error(f) : argv[1]);
        return 1;
    }
    const vsv_meta *m = vsv_file_meta(f);
    const int s = vsv_meta_find_var(m, argv[2]);
    vsv_file_info info;
    vsv_file_info_get(f, &info);
    const int n = info.nsteps < MAXSTEPS ? info.nsteps : MAXSTEPS;
    vsv_volume *v = NULL;
    vsv_iso *kept = NULL;
    if (s < 0 || vsv_volume_create(f, &v) || vsv_iso_create(2, &kept)) {
        fprintf(stderr, "bench_iso: %s: no species %s\n", argv[1], argv[2]);
        return 1;
    }
    printf("%s: %dx%dx%d cells, bricks of %d (%d), %d steps; %s = %g\n", argv[1], m->nx, m->ny, m->nz, v->brick,
           v->nbricks, n, argv[2], (double)value);
    static double fresh[MAXSTEPS][MAXR], inorder[MAXSTEPS][MAXR];
    vsv_iso_info fi[MAXSTEPS], ki[MAXSTEPS];
    for (int r = 0; r < R; r++)
        for (int t = 0; t < n; t++) {
            vsv_iso *s1 = NULL;
            if (vsv_volume_load(v, d, t, s) || vsv_iso_create(2, &s1))
                return 1;
            const vsv_meta placed = vsv_meta_placed(m, v->time);
            if (vsv_iso_extract(s1, &placed, v, value) || vsv_iso_extract(kept, &placed, v, value))
                return 1;
            vsv_iso_get_info(s1, &fi[t]);
            vsv_iso_get_info(kept, &ki[t]);
            fresh[t][r] = fi[t].seconds, inorder[t][r] = ki[t].seconds;
            vsv_iso_free(s1);
        }
    printf("extraction, wall, 2 threads, median of %d rounds:\n", R);
    for (int t = 0; t < n; t++)
        printf("  step %2d: %8zu triangles, %4d of %d bricks visited; afresh %7.2f ms; in order %7.2f ms (%d kept)\n",
               t, fi[t].ntris, fi[t].visited, fi[t].nbricks, 1e3 * median(fresh[t], R), 1e3 * median(inorder[t], R),
               ki[t].reused);
    /* frames of the last step */
    vsv_tf tf;
    char text[512], msg[128];
    vsv_tf_default(m->vars[s].name, vsv_file_quant(f, s), text, sizeof text);
    if (vsv_tf_parse(&tf, text, msg, sizeof msg))
        return 1;
    vsv_layer L = {v, &tf, 1, 1};
    const vsv_scene_iso iso = {0, value, {0.92f, 0.92f, 0.92f}};
    vsv_scene sc = {.meta = m, .layers = &L, .nlayers = 1, .show_terrain = 1};
    sc.exaggeration = vsv_scene_default_exaggeration(&sc);
    vsv_camera cam;
    vsv_camera_fit(&cam, &sc, 225, 30, W, H);
    vsv_render_opts o;
    vsv_render_opts_init(&o);
    o.threads = 2;
    vsv_renderer *rr = NULL;
    float *img = malloc(sizeof(float) * 4 * W * H);
    if (!img || vsv_renderer_create(&o, &rr))
        return 1;
    double fv[MAXR], fi1[MAXR], fi2[MAXR], fb[MAXR];
    for (int r = 0; r < R; r++) {
        vsv_renderer *r2 = NULL;
        if (vsv_renderer_create(&o, &r2))
            return 1;
        sc.nisos = 0, L.visible = 1;
        frame(rr, &sc, &cam, img); /* the sampling copies, outside the timing */
        fv[r] = frame(rr, &sc, &cam, img);
        sc.isos = &iso, sc.nisos = 1, L.visible = 0;
        fi1[r] = frame(r2, &sc, &cam, img); /* a renderer's first: extraction and drawing */
        fi2[r] = frame(r2, &sc, &cam, img);
        L.visible = 1;
        frame(r2, &sc, &cam, img);
        fb[r] = frame(r2, &sc, &cam, img);
        vsv_renderer_free(r2);
    }
    printf("frames %dx%d of the last step, raycast, wall, 2 threads, median of %d:\n", W, H, R);
    printf("  volume only %7.1f ms; isosurface only: first %7.1f ms, again %7.1f ms; both %7.1f ms\n",
           1e3 * median(fv, R), 1e3 * median(fi1, R), 1e3 * median(fi2, R), 1e3 * median(fb, R));
    vsv_renderer_free(rr);
    vsv_iso_free(kept);
    vsv_volume_free(v);
    vsv_decoder_free(d);
    vsv_file_free(f);
    free(img);
    return 0;
}
