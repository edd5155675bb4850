/* bench_plot.c — what vsv-plot's plots cost (issue 35, item 6): each plot
 * kind read from a .vsv (vsv_plot_create: locating, decoding the bricks it
 * touches, the section's heights) and drawn and written as SVG, PNG and PDF
 * (vsv_plot_write: cairo, the file through a temporary, fsync, rename).
 * Usage:
 *   bench_plot HOURLY.vsv SERIES.vsv OUTDIR [ROUNDS]
 * the section and the profile from HOURLY's last step, the series over
 * every step of SERIES (the same run at a finer time step); the places are
 * the real MM5 run's (bench_plot.sh). Prints the median of ROUNDS (default
 * 5) of thread CPU time and wall time for each, and each file's size. */
#include "vsv_plot_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

enum { MAXR = 64 };

static double clk(clockid_t id)
{
    struct timespec ts;
    clock_gettime(id, &ts);
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

/* One plot kind: read it rounds times, then draw and write each format rounds times. */
static int run(vsv_file *f, const vsv_plot_opts *o, const char *name, const char *what, const char *dir, int rounds)
{
    double cpu[MAXR], wall[MAXR];
    vsv_plot *p = NULL;
    char msg[512];
    for (int r = 0; r < rounds; r++) {
        vsv_plot_free(p);
        const double c0 = clk(CLOCK_THREAD_CPUTIME_ID), w0 = clk(CLOCK_MONOTONIC);
        if (vsv_plot_create(f, o, &p, msg, sizeof msg)) {
            fprintf(stderr, "bench_plot: %s: %s\n", name, msg);
            return -1;
        }
        cpu[r] = clk(CLOCK_THREAD_CPUTIME_ID) - c0, wall[r] = clk(CLOCK_MONOTONIC) - w0;
    }
    printf("%-8s %s\n", name, what);
    if (o->kind == VSV_PLOT_SECTION)
        printf("         %.0f km, %d samples x %d levels; ", p->length, p->ns, p->nz);
    else
        printf("         %d rows x %d species; ", p->nrows, o->nspecies);
    printf("%dx%d\n", o->size[0], o->size[1]);
    printf("  read   CPU %7.2f ms  wall %7.2f ms\n", 1e3 * median(cpu, rounds), 1e3 * median(wall, rounds));
    static const char *ext[] = {"svg", "png", "pdf"};
    for (int e = 0; e < 3; e++) {
        char path[1024];
        snprintf(path, sizeof path, "%s/%s.%s", dir, name, ext[e]);
        for (int r = 0; r < rounds; r++) {
            const double c0 = clk(CLOCK_THREAD_CPUTIME_ID), w0 = clk(CLOCK_MONOTONIC);
            if (vsv_plot_write(p, path, msg, sizeof msg)) {
                fprintf(stderr, "bench_plot: %s\n", msg);
                vsv_plot_free(p);
                return -1;
            }
            cpu[r] = clk(CLOCK_THREAD_CPUTIME_ID) - c0, wall[r] = clk(CLOCK_MONOTONIC) - w0;
        }
        struct stat st;
        const double kb = stat(path, &st) ? NAN : st.st_size / 1024.0;
        printf("  %s    CPU %7.2f ms  wall %7.2f ms  %7.1f kB\n", ext[e], 1e3 * median(cpu, rounds),
               1e3 * median(wall, rounds), kb);
    }
    vsv_plot_free(p);
    return 0;
}

static int open_file(const char *path, vsv_file **f, int *last)
{
    if (vsv_file_open(path, f)) {
        fprintf(stderr, "bench_plot: %s\n", *f ? vsv_file_error(*f) : path);
        return -1;
    }
    vsv_file_info info;
    vsv_file_info_get(*f, &info);
    *last = info.nsteps - 1;
    return 0;
}

/* The species named in list (comma-separated) into o. */
static int species(const vsv_file *f, const char *list, vsv_plot_opts *o)
{
    char buf[256];
    snprintf(buf, sizeof buf, "%s", list);
    o->nspecies = 0;
    for (char *save = NULL, *s = strtok_r(buf, ",", &save); s; s = strtok_r(NULL, ",", &save)) {
        const int v = vsv_meta_find_var(vsv_file_meta(f), s);
        if (v < 0 || o->nspecies == VSV_PLOT_MAXSPECIES) {
            fprintf(stderr, "bench_plot: no species %s\n", s);
            return -1;
        }
        o->species[o->nspecies++] = v;
    }
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 4) {
        fprintf(stderr, "usage: bench_plot HOURLY.vsv SERIES.vsv OUTDIR [ROUNDS]\n");
        return 2;
    }
    const int rounds = argc > 4 && atoi(argv[4]) > 0 ? (atoi(argv[4]) < MAXR ? atoi(argv[4]) : MAXR) : 5;
    vsv_file *hf = NULL, *sf = NULL;
    int hlast, slast, rc = 1;
    if (open_file(argv[1], &hf, &hlast) || open_file(argv[2], &sf, &slast))
        goto done;
    printf("median of %d rounds; one thread (the plots do not use more)\n", rounds);
    vsv_plot_opts o;
    /* a section across the domain through the snow band, the lowest 10 km */
    vsv_plot_opts_init(&o);
    o.kind = VSV_PLOT_SECTION;
    o.lat[0] = 45.2, o.lon[0] = -123.4, o.lat[1] = 41.5, o.lon[1] = -58.0;
    o.step0 = o.step1 = hlast;
    o.top = 10000;
    o.source = argv[1];
    if (species(hf, "SNOW", &o) ||
        run(hf, &o, "section", "SNOW from 45.2N 123.4W to 41.5N 58.0W, last step", argv[3], rounds))
        goto done;
    /* a time series where the snow is heaviest, every step */
    vsv_plot_opts_init(&o);
    o.kind = VSV_PLOT_SERIES;
    o.lat[0] = 48.54, o.lon[0] = -87.38, o.at_height = 3800;
    o.step0 = 0, o.step1 = slast;
    o.source = argv[2];
    if (species(sf, "CLW,SNOW", &o) ||
        run(sf, &o, "series", "CLW, SNOW at 48.54N 87.38W, 3800 m, every step", argv[3], rounds))
        goto done;
    /* the column there */
    vsv_plot_opts_init(&o);
    o.kind = VSV_PLOT_PROFILE;
    o.lat[0] = 48.54, o.lon[0] = -87.38;
    o.step0 = o.step1 = hlast;
    o.source = argv[1];
    if (species(hf, "Q,CLW,SNOW", &o) ||
        run(hf, &o, "profile", "Q, CLW, SNOW at 48.54N 87.38W, last step", argv[3], rounds))
        goto done;
    rc = 0;
done:
    vsv_file_free(hf);
    vsv_file_free(sf);
    return rc;
}
