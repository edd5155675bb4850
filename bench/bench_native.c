/* bench_native.c — the cost of drawing native levels at their heights
 * (resample on load, vsv_resampler) against a file converted with even
 * heights, on the same model output. Usage:
 *   bench_native EVEN.vsv NATIVE.vsv [ROUNDS]
 * Per round, interleaved (even, native, even, native ...) so a busy machine
 * slows both alike: every species of every step loaded (decoded), the
 * native file's volumes resampled onto the even axis (thread CPU time:
 * both run on the calling thread), and one raycast
 * frame (512x384, 2 threads, terrain off, from the south) of the last step
 * from each file. Prints the median of the rounds and the ratios. */
#include "vsv_render.h"

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

enum { MAXS = 16, W = 512, H = 384 };

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}
/* CPU seconds of this thread: loading and resampling run on it alone, so a
 * machine busy with other work does not inflate them */
static double cpu(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

typedef struct side {
    vsv_file *f;
    vsv_decoder *d;
    const vsv_meta *m;
    int ns, nsteps;
    vsv_volume *v[MAXS];
    vsv_resampler *rs[MAXS];
    vsv_tf tf[MAXS];
    vsv_layer L[MAXS];
    vsv_renderer *r;
} side;

static int side_open(side *s, const char *path)
{
    if (vsv_file_open(path, &s->f) || vsv_decoder_create(s->f, &s->d)) {
        fprintf(stderr, "bench_native: %s\n", s->f ? vsv_file_error(s->f) : path);
        return -1;
    }
    s->m = vsv_file_meta(s->f);
    vsv_file_info info;
    vsv_file_info_get(s->f, &info);
    s->nsteps = info.nsteps;
    s->ns = s->m->nvars < MAXS ? s->m->nvars : MAXS;
    vsv_render_opts o;
    vsv_render_opts_init(&o);
    o.threads = 2;
    if (vsv_renderer_create(&o, &s->r))
        return -1;
    for (int i = 0; i < s->ns; i++) {
        char text[512], msg[128];
        vsv_tf_default(s->m->vars[i].name, vsv_file_quant(s->f, i), text, sizeof text);
        if (vsv_tf_parse(&s->tf[i], text, msg, sizeof msg) || vsv_volume_create(s->f, &s->v[i]))
            return -1;
        if (s->m->nheights && vsv_resampler_create(s->m, &s->rs[i]))
            return -1;
        s->L[i] = (vsv_layer){s->v[i], &s->tf[i], 1, 1};
    }
    return 0;
}

/* Loads every species of every step: seconds decoding into *dec, resampling into *res. */
static int side_load(side *s, double *dec, double *res)
{
    *dec = *res = 0;
    for (int t = 0; t < s->nsteps; t++)
        for (int i = 0; i < s->ns; i++) {
            double t0 = cpu();
            if (vsv_volume_load(s->v[i], s->d, t, i))
                return -1;
            double t1 = cpu();
            const vsv_volume *out;
            if (s->rs[i] && vsv_resampler_run(s->rs[i], s->v[i], &out))
                return -1;
            *dec += t1 - t0;
            *res += cpu() - t1;
        }
    return 0;
}

/* One raycast frame of the loaded (last) step; seconds. */
static double side_frame(side *s, float *img)
{
    vsv_scene sc = {.meta = s->m, .layers = s->L, .nlayers = s->ns, .exaggeration = 60, .show_terrain = 0};
    vsv_camera cam;
    vsv_camera_fit(&cam, &sc, 180, 5, W, H);
    vsv_render(s->r, &sc, &cam, img, NULL); /* the resampled copy for this load, outside the timing */
    const double t0 = now();
    if (vsv_render(s->r, &sc, &cam, img, NULL))
        return -1;
    return now() - t0;
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

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: bench_native EVEN.vsv NATIVE.vsv [ROUNDS]\n");
        return 2;
    }
    const int rounds = argc > 3 ? atoi(argv[3]) : 5;
    side s[2] = {{0}, {0}};
    if (side_open(&s[0], argv[1]) || side_open(&s[1], argv[2]))
        return 1;
    if (!s[1].m->nheights) {
        fprintf(stderr, "bench_native: %s has no per-column heights (vsv-convert --vertical native)\n", argv[2]);
        return 1;
    }
    float *img = malloc(sizeof(float) * 4 * W * H);
    double dec[2][64], res[2][64], fr[2][64];
    const int R = rounds < 1 ? 1 : rounds > 64 ? 64 : rounds;
    for (int r = 0; r < R; r++)
        for (int k = 0; k < 2; k++) {
            if (side_load(&s[k], &dec[k][r], &res[k][r]))
                return 1;
            fr[k][r] = side_frame(&s[k], img);
        }
    const double de = median(dec[0], R), dn = median(dec[1], R), rn = median(res[1], R);
    const double fe = median(fr[0], R), fn = median(fr[1], R);
    const int loads = s[1].nsteps * s[1].ns;
    printf("even   %s: %dx%dx%d cells, %d steps x %d species\n", argv[1], s[0].m->nx, s[0].m->ny, s[0].m->nz,
           s[0].nsteps, s[0].ns);
    printf("native %s: %dx%dx%d cells (%d per-column height records), resampled to the even axis\n", argv[2],
           s[1].m->nx, s[1].m->ny, s[1].m->nz, s[1].m->nheights);
    printf("median of %d interleaved rounds (2 threads for the frames):\n", R);
    printf("  load, per volume (CPU):  even %7.2f ms   native %7.2f ms decode + %7.2f ms resample = %7.2f ms (x%.2f)\n",
           1e3 * de / loads, 1e3 * dn / loads, 1e3 * rn / loads, 1e3 * (dn + rn) / loads, (dn + rn) / de);
    printf("  raycast frame %dx%d (wall): even %7.1f ms   native %7.1f ms (x%.2f)\n", W, H, 1e3 * fe, 1e3 * fn,
           fn / fe);
    printf("  a new step (load every species + one frame): even %.1f ms, native %.1f ms (x%.2f)\n",
           1e3 * (de / s[0].nsteps + fe), 1e3 * ((dn + rn) / s[1].nsteps + fn),
           ((dn + rn) / s[1].nsteps + fn) / (de / s[0].nsteps + fe));
    free(img);
    for (int k = 0; k < 2; k++) {
        for (int i = 0; i < s[k].ns; i++) {
            vsv_volume_free(s[k].v[i]);
            vsv_resampler_free(s[k].rs[i]);
        }
        vsv_renderer_free(s[k].r);
        vsv_decoder_free(s[k].d);
        vsv_file_free(s[k].f);
    }
    return 0;
}
