/* bench_play.c — streamed playback through the pager: time to the first
 * frame, steps per second decoded under a 64 MB and a 1 GB budget, stalls
 * while a 30 frames/s display plays forward and backward at x1 and x8, and
 * anonymous resident memory against the budget. Usage:
 *   bench_play FILE.vsv                 measure
 *   bench_play --compare FILE.vsv MB..  steps/s forward and backward, the pager
 *                                       decoding every brick from its keyframe
 *                                       (the earlier path) against incremental
 *                                       decoding, interleaved, with the ratio
 *   bench_play --make OUT.vsv STEPS     write a synthetic file: 256x256x48, 4 noisy
 *                                       species, 16-bit, ~21 MB a step on disk
 *   bench_play --plume OUT.vsv STEPS PLUME_T0.f32
 *                                       a series from gen-plume's plume (256x256x64
 *                                       float32): advected 0.6, 0.3, 0.05 voxels a
 *                                       step with fresh 5 % white noise, as gen-plume
 *                                       makes its t1 */
#include "vsv_clock.h"
#include "vsv_pager.h"
#include "vsv_render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* kB of resident memory of one kind from /proc/self/status: "RssAnon:"
 * (what the process allocates: the decoded cache lives there) or
 * "RssFile:" (file-backed: the mapped .vsv, page cache the kernel can drop
 * and read again; what `top` and /usr/bin/time add to RSS) */
static long rss_kb(const char *key)
{
    FILE *fp = fopen("/proc/self/status", "r");
    char line[256];
    long kb = -1;
    const size_t n = strlen(key);
    while (fp && fgets(line, sizeof line, fp))
        if (!strncmp(line, key, n))
            kb = atol(line + n);
    if (fp)
        fclose(fp);
    return kb;
}
static long rss_anon_kb(void) { return rss_kb("RssAnon:"); }

static uint64_t mix64(uint64_t x)
{
    x ^= x >> 33;
    x *= 0xff51afd7ed558ccdull;
    x ^= x >> 33;
    x *= 0xc4ceb9fe1a85ec53ull;
    return x ^ (x >> 33);
}

static int make_synthetic(const char *path, int steps)
{
    const int nx = 256, ny = 256, nz = 48, ns = 4;
    vsv_meta m;
    vsv_meta_init(&m);
    m.nx = nx, m.ny = ny, m.nz = nz;
    m.spacing[0] = m.spacing[1] = 4000;
    m.spacing[2] = 300;
    m.origin[2] = 150;
    m.vert_kind = VSV_VERT_EVEN;
    const char *names[4] = {"CLW", "QRAIN", "O3", "PM25"};
    for (int s = 0; s < ns; s++)
        vsv_meta_add_var(&m, names[s], "1", "synthetic, noisy");
    vsv_pack_opts o;
    vsv_pack_opts_init(&o);
    vsv_writer *w = NULL;
    if (vsv_writer_create(path, &m, &o, &w)) {
        fprintf(stderr, "bench_play: %s\n", w ? vsv_writer_error(w) : "cannot write");
        return 1;
    }
    const size_t cells = (size_t)nx * ny * nz;
    float *f[4];
    for (int s = 0; s < ns; s++)
        f[s] = malloc(cells * sizeof(float));
    for (int t = 0; t < steps; t++) {
        for (int s = 0; s < ns; s++)
            for (size_t c = 0; c < cells; c++) {
                const int i = (int)(c % nx), j = (int)(c / nx % ny), k = (int)(c / ((size_t)nx * ny));
                const double smooth = 0.5 + 0.4 * sin(0.02 * i + 0.1 * t + s) * cos(0.03 * j) * exp(-0.05 * k);
                const double noise = (double)(mix64(c * 131 + (uint64_t)t * 7919 + (uint64_t)s) >> 40) / (1 << 24);
                f[s][c] = (float)(smooth + 0.02 * noise);
            }
        if (vsv_writer_add_step(w, 1000000000LL + 300LL * t, (const float *const *)f)) {
            fprintf(stderr, "bench_play: %s\n", vsv_writer_error(w));
            return 1;
        }
    }
    const int rc = vsv_writer_finish(w, NULL, NULL);
    if (rc)
        fprintf(stderr, "bench_play: %s\n", vsv_writer_error(w));
    vsv_writer_free(w);
    for (int s = 0; s < ns; s++)
        free(f[s]);
    vsv_meta_clear(&m);
    return rc != 0;
}

/* gen-plume's lattice noise in [-1, 1) (its hash3 and lat) */
static float plume_noise(int x, int y, int z, uint32_t seed)
{
    uint32_t h = seed * 0x9E3779B1u ^ (uint32_t)x * 0x85EBCA77u ^ (uint32_t)y * 0xC2B2AE3Du ^ (uint32_t)z * 0x27D4EB2Fu;
    h ^= h >> 15;
    h *= 0x2C1B3C6Du;
    h ^= h >> 12;
    h *= 0x297A2D39u;
    h ^= h >> 15;
    return (float)(h >> 8) * (1.0f / 8388608.0f) - 1.0f;
}

static int make_plume(const char *path, int steps, const char *t0_path)
{
    enum { NX = 256, NY = 256, NZ = 64 };
    const size_t cells = (size_t)NX * NY * NZ;
    float *t0 = malloc(cells * sizeof *t0), *f = malloc(cells * sizeof *f);
    FILE *fp = fopen(t0_path, "rb");
    if (!t0 || !f || !fp || fread(t0, sizeof *t0, cells, fp) != cells) {
        fprintf(stderr, "bench_play: %s: cannot read %zu floats\n", t0_path, cells);
        if (fp)
            fclose(fp);
        return 1;
    }
    fclose(fp);
    float vmax = 0;
    for (size_t c = 0; c < cells; c++)
        vmax = t0[c] > vmax ? t0[c] : vmax;
    vsv_meta m;
    vsv_meta_init(&m);
    m.nx = NX, m.ny = NY, m.nz = NZ;
    m.spacing[0] = m.spacing[1] = 1000;
    m.spacing[2] = 100;
    m.origin[2] = 50;
    m.vert_kind = VSV_VERT_EVEN;
    vsv_meta_add_var(&m, "PLUME", "1", "gen-plume's plume, advected, fresh noise every step");
    vsv_pack_opts o;
    vsv_pack_opts_init(&o);
    vsv_writer *w = NULL;
    if (vsv_writer_create(path, &m, &o, &w)) {
        fprintf(stderr, "bench_play: %s\n", w ? vsv_writer_error(w) : "cannot write");
        return 1;
    }
    int rc = 0;
    for (int t = 0; t < steps && !rc; t++) {
        const float ax = 0.6f * t, ay = 0.3f * t, az = 0.05f * t;
        for (int k = 0; k < NZ; k++)
            for (int j = 0; j < NY; j++)
                for (int i = 0; i < NX; i++) {
                    /* trilinear sample of t0 at the Lagrangian point */
                    const float X = i - ax, Y = j - ay, Z = k - az;
                    const int x0 = (int)floorf(X), y0 = (int)floorf(Y), z0 = (int)floorf(Z);
                    const float fx = X - x0, fy = Y - y0, fz = Z - z0;
                    float v = 0;
                    for (int c = 0; c < 8; c++) {
                        const int xi = x0 + (c & 1), yi = y0 + (c >> 1 & 1), zi = z0 + (c >> 2);
                        if (xi < 0 || yi < 0 || zi < 0 || xi >= NX || yi >= NY || zi >= NZ)
                            continue;
                        const float wgt = (c & 1 ? fx : 1 - fx) * (c >> 1 & 1 ? fy : 1 - fy) * (c >> 2 ? fz : 1 - fz);
                        v += wgt * t0[((size_t)zi * NY + yi) * NX + xi];
                    }
                    v *= 1.0f + 0.05f * plume_noise(i, j, k, 1000u + (uint32_t)t);
                    f[((size_t)k * NY + j) * NX + i] = v < 2e-3f * vmax ? 0 : v;
                }
        const float *fields[1] = {f};
        if (vsv_writer_add_step(w, 1000000000LL + 300LL * t, fields)) {
            fprintf(stderr, "bench_play: %s\n", vsv_writer_error(w));
            rc = 1;
        }
    }
    if (!rc && vsv_writer_finish(w, NULL, NULL)) {
        fprintf(stderr, "bench_play: %s\n", vsv_writer_error(w));
        rc = 1;
    }
    vsv_writer_free(w);
    vsv_meta_clear(&m);
    free(t0);
    free(f);
    return rc;
}

/* Steps per second playing every step of every species in one direction
 * as fast as the pager delivers them (a new pager: nothing cached), and
 * the payloads it decoded. */
static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* cpu: the process's CPU seconds a step (all threads), which the machine's
 * load does not inflate as it does wall time */
static double pass_rate(vsv_file *f, size_t budget, int from_keyframe, int dir, uint64_t *payloads, double *cpu)
{
    vsv_file_info info;
    vsv_file_info_get(f, &info);
    vsv_pager_opts po;
    vsv_pager_opts_init(&po);
    po.budget = budget;
    po.from_keyframe = from_keyframe;
    vsv_pager *p = NULL;
    if (vsv_pager_open(f, &po, &p))
        return 0;
    vsv_volume **v = calloc((size_t)info.nspecies, sizeof *v);
    for (int s = 0; s < info.nspecies; s++)
        v[s] = vsv_pager_volume_new(p);
    const double t0 = now(), c0 = cpu_now();
    for (int i = 0; i < info.nsteps; i++) {
        const int t = dir > 0 ? i : info.nsteps - 1 - i;
        vsv_pager_playhead(p, t, dir, NULL, 0, NULL);
        for (int s = 0; s < info.nspecies; s++)
            if (vsv_pager_get(p, t, s, 1, v[s]))
                fprintf(stderr, "bench_play: %s\n", vsv_pager_error(p));
    }
    const double rate = info.nsteps / (now() - t0);
    *cpu = (cpu_now() - c0) / info.nsteps;
    vsv_pager_stats st;
    vsv_pager_stats_get(p, &st);
    *payloads = st.payloads_decoded;
    for (int s = 0; s < info.nspecies; s++)
        vsv_volume_free(v[s]);
    free(v);
    vsv_pager_free(p);
    return rate;
}

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* The earlier path (every brick from its keyframe) against incremental
 * decoding, forward and backward, under each budget: 3 interleaved passes
 * of each, medians. */
static int compare(const char *path, int nb, char **mb)
{
    vsv_file *f = NULL;
    if (vsv_file_open(path, &f)) {
        fprintf(stderr, "bench_play: %s\n", f ? vsv_file_error(f) : path);
        vsv_file_free(f);
        return 1;
    }
    vsv_file_info info;
    vsv_file_info_get(f, &info);
    const vsv_meta *m = vsv_file_meta(f);
    printf("file: %s, %.2f GB, %d steps x %d species of %dx%dx%d, keyframe every %d (%.0f MB of floats a step)\n\n",
           path, info.file_bytes / 1e9, info.nsteps, info.nspecies, m->nx, m->ny, m->nz, info.keyframe,
           (double)m->nx * m->ny * m->nz * 4 * info.nspecies / 1e6);
    printf(
        "| budget | direction | from keyframe: steps/s | incremental: steps/s | ratio | payloads decoded (keyframe / "
        "incremental) |\n|---|---|---|---|---|---|\n");
    double fwd_back[64][2], cpu_fb[64][2]; /* incremental medians, forward and backward, per budget */
    if (nb > 64)
        nb = 64;
    for (int i = 0; i < nb; i++) {
        const size_t budget = (size_t)atol(mb[i]) << 20;
        for (int dir = 1; dir >= -1; dir -= 2) {
            double old[3], inc[3], oc[3], ic[3];
            uint64_t po = 0, pn = 0;
            for (int r = 0; r < 3; r++) {
                old[r] = pass_rate(f, budget, 1, dir, &po, &oc[r]);
                inc[r] = pass_rate(f, budget, 0, dir, &pn, &ic[r]);
            }
            qsort(old, 3, sizeof *old, cmp_double);
            qsort(inc, 3, sizeof *inc, cmp_double);
            qsort(ic, 3, sizeof *ic, cmp_double);
            cpu_fb[i][dir < 0] = ic[1];
            printf("| %s MB | %s | %.1f (%.1f-%.1f) | %.1f (%.1f-%.1f) | **%.2f** | %llu / %llu |\n", mb[i],
                   dir > 0 ? "forward" : "backward", old[1], old[0], old[2], inc[1], inc[0], inc[2], inc[1] / old[1],
                   (unsigned long long)po, (unsigned long long)pn);
            fflush(stdout);
            fwd_back[i][dir < 0] = inc[1];
        }
    }
    printf(
        "\n| budget | incremental forward steps/s | backward steps/s | forward / backward (target <= 1.5) | CPU ms a "
        "step forward | backward | backward / forward |\n|---|---|---|---|---|---|---|\n");
    for (int i = 0; i < nb; i++)
        printf("| %s MB | %.1f | %.1f | **%.2f** | %.2f | %.2f | **%.2f** |\n", mb[i], fwd_back[i][0], fwd_back[i][1],
               fwd_back[i][0] / fwd_back[i][1], 1e3 * cpu_fb[i][0], 1e3 * cpu_fb[i][1], cpu_fb[i][1] / cpu_fb[i][0]);
    vsv_file_free(f);
    return 0;
}

/* A 30 frames/s display playing for `frames` frames at speed x: stalls
 * (after the first frame, which waits for its step from a cold start) and
 * steps shown. */
static void play(vsv_pager *p, vsv_volume **v, int ns, const int64_t *times, int nsteps, double x, int frames,
                 uint64_t *stalls, int *shown_steps, long *peak_kb)
{
    vsv_clock c;
    vsv_clock_init(&c, times, nsteps, 0);
    c.ends = VSV_CLOCK_LOOP;
    vsv_clock_seek_step(&c, x > 0 ? 0 : nsteps - 1);
    vsv_clock_set_speed(&c, x);
    vsv_clock_play(&c);
    vsv_pager_stats st0, st1;
    vsv_pager_stats_get(p, &st0);
    int shown = -1, changes = 0;
    const double frame = 1.0 / 30;
    double t_next = now();
    for (int f = 0; f < frames; f++) {
        vsv_clock_tick(&c, f ? frame : 0);
        const int target = c.step;
        int next[VSV_PAGER_AHEAD + 1];
        const int nn = vsv_clock_ahead(&c, frame, next, VSV_PAGER_AHEAD + 1);
        vsv_pager_playhead(p, target, x > 0 ? 1 : -1, next, nn, NULL);
        if (target != shown) {
            /* as vsv-play: the clock's step when decoded, else the newest
             * decoded step on the way there, else the one shown stays */
            vsv_pager_stats ps;
            vsv_pager_stats_get(p, &ps);
            int pick = shown < 0 || ps.prefetch_depth == 0 ? target : -1; /* nothing ahead: on demand */
            if (pick < 0 && vsv_pager_ready(p, target, NULL))
                pick = target;
            if (pick < 0) {
                vsv_pager_stall(p);
                const int dir = x > 0 ? 1 : -1;
                for (int t = target, i = 0; i < nsteps; i++) {
                    t = ((t - dir) % nsteps + nsteps) % nsteps;
                    if (t == shown)
                        break;
                    if (vsv_pager_ready(p, t, NULL)) {
                        pick = t;
                        break;
                    }
                }
            }
            if (pick >= 0) {
                for (int s = 0; s < ns; s++)
                    vsv_pager_get(p, pick, s, 1, v[s]);
                shown = pick;
                changes++;
            }
        }
        if (f == 0) /* the first frame waits for its step (the time to the first frame, measured apart): not a stall */
            vsv_pager_stats_get(p, &st0);
        const long kb = rss_anon_kb();
        if (kb > *peak_kb)
            *peak_kb = kb;
        t_next += frame;
        const double wait = t_next - now();
        if (wait > 0)
            usleep((useconds_t)(wait * 1e6));
    }
    vsv_pager_stats_get(p, &st1);
    *stalls = st1.stalls - st0.stalls;
    *shown_steps = changes;
}

int main(int argc, char **argv)
{
    if (argc == 4 && !strcmp(argv[1], "--make"))
        return make_synthetic(argv[2], atoi(argv[3]));
    if (argc == 5 && !strcmp(argv[1], "--plume"))
        return make_plume(argv[2], atoi(argv[3]), argv[4]);
    if (argc >= 4 && !strcmp(argv[1], "--compare"))
        return compare(argv[2], argc - 3, argv + 3);
    if (argc != 2) {
        fprintf(stderr,
                "usage: bench_play FILE.vsv | --compare FILE.vsv MB... | --make OUT.vsv STEPS | --plume OUT.vsv "
                "STEPS PLUME_T0.f32\n");
        return 2;
    }
    const long base_kb = rss_anon_kb();
    /* time to the first frame: open, start the pager, every species of step 0 */
    double t0 = now();
    vsv_file *f = NULL;
    if (vsv_file_open(argv[1], &f)) {
        fprintf(stderr, "bench_play: %s\n", f ? vsv_file_error(f) : argv[1]);
        return 1;
    }
    vsv_file_info info;
    vsv_file_info_get(f, &info);
    const vsv_meta *m = vsv_file_meta(f);
    vsv_pager_opts po;
    vsv_pager_opts_init(&po);
    po.budget = (size_t)1 << 30;
    vsv_pager *p = NULL;
    vsv_pager_open(f, &po, &p);
    vsv_volume **v = calloc((size_t)info.nspecies, sizeof *v);
    for (int s = 0; s < info.nspecies; s++) {
        v[s] = vsv_pager_volume_new(p);
        vsv_pager_get(p, 0, s, 1, v[s]);
    }
    const double first = now() - t0;
    /* ... and its first picture: shear-warp, 512x512, all species */
    vsv_render_opts ro;
    vsv_render_opts_init(&ro);
    ro.kind = VSV_RENDER_SHEARWARP;
    vsv_renderer *r = NULL;
    vsv_renderer_create(&ro, &r);
    vsv_tf *tf = calloc((size_t)info.nspecies, sizeof *tf);
    vsv_layer *layers = calloc((size_t)info.nspecies, sizeof *layers);
    char msg[512];
    for (int s = 0; s < info.nspecies; s++) {
        vsv_tf_for_species(f, s, NULL, &tf[s], msg, sizeof msg);
        layers[s] = (vsv_layer){v[s], &tf[s], 1, 1};
    }
    vsv_scene sc = {.meta = m, .layers = layers, .nlayers = info.nspecies, .exaggeration = 0, .show_terrain = 1};
    sc.exaggeration = vsv_scene_default_exaggeration(&sc);
    vsv_camera cam;
    vsv_camera_orbit(&cam, &sc, 225, 30, 0, 512, 512);
    float *img = malloc(512 * 512 * 4 * sizeof(float));
    vsv_render(r, &sc, &cam, img, NULL);
    const double first_picture = now() - t0;
    vsv_renderer_free(r);
    free(img);
    free(layers);
    free(tf);
    for (int s = 0; s < info.nspecies; s++)
        vsv_pager_put(p, v[s]);
    vsv_pager_free(p);
    const double raw_mb = (double)m->nx * m->ny * m->nz * 4 * info.nspecies / 1e6;
    const double step_mb = raw_mb * 1e6 / 1048576.0;
    printf("file: %s, %.2f GB, %d steps x %d species of %dx%dx%d (%.0f MB of floats per step)\n\n", argv[1],
           info.file_bytes / 1e9, info.nsteps, info.nspecies, m->nx, m->ny, m->nz, raw_mb);
    printf("- time to the first frame: %.0f ms decoded (open, pager, every species of step 0), %.0f ms to the "
           "first 512x512 shear-warp picture\n\n",
           1000 * first, 1000 * first_picture);
    int64_t *times = malloc((size_t)info.nsteps * sizeof *times);
    for (int t = 0; t < info.nsteps; t++)
        times[t] = vsv_file_time(f, t);
    printf("| budget | steps/s, first pass (all species) | steps/s, second pass | play x1 fwd: stalls / steps shown | "
           "x8 fwd | x1 back | x8 back | peak anonymous RSS above start (pager's own peak; one step of floats) | "
           "peak file-backed RSS (the mapped file: page cache) |\n|---|---|---|---|---|---|---|---|---|\n");
    const size_t budgets[2] = {(size_t)64 << 20, (size_t)1 << 30};
    for (int bi = getenv("BENCH_ONLY_1G") ? 1 : 0; bi < 2; bi++) {
        po.budget = budgets[bi];
        if (getenv("BENCH_THREADS"))
            po.threads = atoi(getenv("BENCH_THREADS"));
        vsv_pager_open(f, &po, &p);
        for (int s = 0; s < info.nspecies; s++)
            v[s] = vsv_pager_volume_new(p);
        long peak = 0, peak_file = 0;
        /* decode throughput: every step in order, as fast as it goes */
        const int n = info.nsteps < 40 ? info.nsteps : 40;
        t0 = now();
        for (int t = 0; t < n; t++) {
            vsv_pager_playhead(p, t, 1, NULL, 0, NULL);
            for (int s = 0; s < info.nspecies; s++)
                vsv_pager_get(p, t, s, 1, v[s]);
            const long kb = rss_anon_kb(), fkb = rss_kb("RssFile:");
            peak = kb > peak ? kb : peak;
            peak_file = fkb > peak_file ? fkb : peak_file;
        }
        const double sps = n / (now() - t0);
        /* again: what the cache still holds comes without decoding */
        t0 = now();
        for (int t = 0; t < n; t++) {
            vsv_pager_playhead(p, t, 1, NULL, 0, NULL);
            for (int s = 0; s < info.nspecies; s++)
                vsv_pager_get(p, t, s, 1, v[s]);
        }
        const double sps2 = n / (now() - t0);
        printf("| %zu MB | %.1f | %.1f |", budgets[bi] >> 20, sps, sps2);
        const double speeds[4] = {1, 8, -1, -8};
        for (int k = 0; k < 4; k++) {
            uint64_t stalls;
            int shown;
            play(p, v, info.nspecies, times, info.nsteps, speeds[k], 120, &stalls, &shown, &peak);
            printf(" %llu / %d |", (unsigned long long)stalls, shown);
        }
        vsv_pager_stats st;
        vsv_pager_stats_get(p, &st);
        printf(" %.0f MB (cache peak %.0f MB, a step pinned %.0f MB) | %.0f MB |\n", (peak - base_kb) / 1024.0,
               st.peak_bytes / 1048576.0, step_mb, peak_file / 1024.0);
        for (int s = 0; s < info.nspecies; s++)
            vsv_volume_free(v[s]);
        vsv_pager_free(p);
    }
    free(times);
    free(v);
    vsv_file_free(f);
    return 0;
}
