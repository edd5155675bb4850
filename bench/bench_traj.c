/* bench_traj.c — trajectories on the real MM5 run: the run's U and V (grid-
 * relative; the source averages dot points to cross points) turned earth-
 * relative with the projection's Jacobian (vsv_proj_jacobian) and W (the
 * mean of the full levels around each half level), written as the vector
 * species wind on the run's own levels; then the paths seeded on a slice
 * (every `every`-th column at a height, vsv_traj_seed_plane) integrated over
 * the run's three hours, timed: a fresh handle (its bricks decoded as
 * touched) and again on the same handle (decoded bricks kept).
 *   bench_traj MMOUT_DOMAIN1 OUT.vsv [EVERY [HEIGHT]] */
#include "vsv_convert.h"
#include "vsv_format.h"
#include "vsv_traj.h"

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

/* The run's wind into a .vsv at out: 0 or 1 (with a message). */
static int write_wind(const char *mm5, const char *out)
{
    vsv_source_opts o;
    vsv_source_opts_init(&o);
    vsv_source *src = NULL;
    vsv_writer *w = NULL;
    vsv_meta m;
    vsv_meta_init(&m);
    float *v[3] = {NULL, NULL, NULL};
    int rc = vsv_source_open(mm5, &o, &src);
    const int iu = rc ? -1 : vsv_source_find_field(src, "U"), iv = rc ? -1 : vsv_source_find_field(src, "V"),
              iw = rc ? -1 : vsv_source_find_field(src, "W");
    if (rc || iu < 0 || iv < 0 || iw < 0) {
        fprintf(stderr, "bench_traj: %s: %s\n", mm5, src ? vsv_source_error(src) : "no U, V, W");
        vsv_source_free(src);
        return 1;
    }
    vsv_meta_copy(&m, vsv_source_grid(src));
    vsv_meta_add_var(&m, VSV_WIND_EAST, "m s-1", "eastward wind");
    vsv_meta_add_var(&m, VSV_WIND_NORTH, "m s-1", "northward wind");
    vsv_meta_add_var(&m, VSV_WIND_UP, "m s-1", "upward wind");
    vsv_meta_add_attr(&m, VSV_VECTOR_ATTR VSV_WIND, VSV_WIND_EAST " " VSV_WIND_NORTH " " VSV_WIND_UP);
    const size_t plane = (size_t)m.nx * m.ny, cells = plane * m.nz;
    for (int c = 0; c < 3; c++)
        v[c] = malloc(cells * sizeof(float));
    double(*jac)[2][2] = malloc(plane * sizeof *jac);
    for (int j = 0; j < m.ny; j++)
        for (int i = 0; i < m.nx; i++) {
            double x, y;
            vsv_meta_cell_xy(&m, i, j, &x, &y);
            vsv_proj_jacobian(&m.proj, x, y, jac[(size_t)j * m.nx + i]);
        }
    rc = vsv_writer_create(out, &m, NULL, &w);
    for (int t = 0; !rc && t < vsv_source_ntimes(src); t++) {
        rc = vsv_source_read(src, iu, t, v[0]);
        if (!rc)
            rc = vsv_source_read(src, iv, t, v[1]);
        if (!rc)
            rc = vsv_source_read(src, iw, t, v[2]);
        for (size_t c = 0; !rc && c < cells; c++) { /* grid-relative (ug, vg) to earth's (east, north) */
            const double(*J)[2] = jac[c % plane];
            const double n0 = hypot(J[0][0], J[0][1]), n1 = hypot(J[1][0], J[1][1]), ug = v[0][c], vg = v[1][c];
            v[0][c] = (float)(ug * J[0][0] / n0 + vg * J[1][0] / n1);
            v[1][c] = (float)(ug * J[0][1] / n0 + vg * J[1][1] / n1);
        }
        const float *fields[3] = {v[0], v[1], v[2]};
        if (!rc)
            rc = vsv_writer_add_step(w, vsv_source_time(src, t), fields);
    }
    if (!rc)
        rc = vsv_writer_finish(w, NULL, NULL);
    if (rc)
        fprintf(stderr, "bench_traj: %s\n", w ? vsv_writer_error(w) : vsv_source_error(src));
    vsv_writer_free(w);
    vsv_source_free(src);
    vsv_meta_clear(&m);
    free(jac);
    for (int c = 0; c < 3; c++)
        free(v[c]);
    return rc ? 1 : 0;
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: bench_traj MMOUT_DOMAIN1 OUT.vsv [EVERY [HEIGHT]]\n");
        return 2;
    }
    const int every = argc > 3 ? atoi(argv[3]) : 8;
    const double height = argc > 4 ? atof(argv[4]) : 1500;
    double t0 = now();
    if (write_wind(argv[1], argv[2]))
        return 1;
    const double t_write = now() - t0;
    vsv_file *f = NULL;
    vsv_traj *tr = NULL;
    if (vsv_file_open(argv[2], &f) || vsv_traj_create(f, &tr)) {
        fprintf(stderr, "bench_traj: %s: %s\n", argv[2], f ? vsv_traj_error(tr) : "does not open");
        return 1;
    }
    const vsv_meta *m = vsv_file_meta(f);
    vsv_file_info info;
    vsv_file_info_get(f, &info);
    const double from = (double)vsv_file_time(f, 0), to = (double)vsv_file_time(f, info.nsteps - 1);
    const int n = vsv_traj_seed_plane(m, (int64_t)from, height, every, NULL, 0);
    double *seeds = malloc((size_t)(n > 0 ? n : 1) * 3 * sizeof *seeds);
    vsv_traj_seed_plane(m, (int64_t)from, height, every, seeds, n);
    long points = 0, ends[5] = {0};
    double dist = 0, t_run[2];
    vsv_traj_path p = {0};
    for (int round = 0; round < 2; round++) {
        t0 = now();
        for (int s = 0; s < n; s++) {
            if (vsv_traj_run(tr, seeds + 3 * s, from, to, 0, &p)) {
                fprintf(stderr, "bench_traj: %s\n", vsv_traj_error(tr));
                return 1;
            }
            if (round)
                continue;
            points += p.n;
            ends[p.end]++;
            dist += hypot(p.pts[p.n - 1].x - p.pts[0].x, p.pts[p.n - 1].y - p.pts[0].y);
        }
        t_run[round] = now() - t0;
    }
    printf("bench_traj: %s: %d x %d x %d cells, %d steps; wind written in %.2f s (%llu bytes)\n", argv[1], m->nx, m->ny,
           m->nz, info.nsteps, t_write, (unsigned long long)info.file_bytes);
    printf("  %d paths from every %d-th column at %g m over %g h: %.1f RK4 steps a path, %.0f km apart at the end "
           "(mean); ends: time %ld, edge %ld, ground %ld, top %ld\n",
           n, every, height, (to - from) / 3600, n ? (double)(points - n) / n : 0, n ? dist / n / 1000 : 0, ends[0],
           ends[1], ends[2], ends[3]);
    printf("  integration: %.3f ms a path on a fresh handle (bricks decoded as touched), %.3f ms with them kept; "
           "%.2f us a step\n",
           n ? 1e3 * t_run[0] / n : 0, n ? 1e3 * t_run[1] / n : 0,
           points > n ? 1e6 * t_run[1] / (double)(points - n) : 0);
    vsv_traj_path_clear(&p);
    free(seeds);
    vsv_traj_free(tr);
    vsv_file_free(f);
    return 0;
}
