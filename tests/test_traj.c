/* test_traj.c — trajectories (vsv_traj.h) through winds written with known
 * integrals: a uniform wind is a straight line of its speed times the time
 * (and on a Lambert grid an east wind keeps to its parallel), a solid-body
 * rotation a circle that closes, a wind that changes between steps the
 * integral of its linear blend; backward then forward returns to the seed;
 * the path stops at the edge, the ground, the top and the end of the
 * file's times with the right end; bad seeds are VSV_EINVAL; the seeding
 * helpers. */
#include "vsv_flow.h"
#include "vsv_format.h"
#include "vsv_testlib.h"
#include "vsv_traj.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The wind of a test: east, north, up at projected (x, y), height z, step s. */
typedef void (*wind_fn)(int s, double x, double y, double z, float out[3]);

/* A grid of nx x ny x nz cells of dx metres (heights: 50 m + 100 m a level),
 * projection none, origin at (0, 0). */
static void grid(vsv_meta *m, int nx, int ny, int nz, double dx)
{
    vsv_meta_init(m);
    m->nx = nx, m->ny = ny, m->nz = nz;
    m->spacing[0] = m->spacing[1] = dx, m->spacing[2] = 100;
    m->origin[2] = 50;
    m->vert_kind = VSV_VERT_EVEN;
    snprintf(m->model, sizeof m->model, "test");
}

/* Writes m with the wind fn at nsteps times (times[]) and opens it. */
static vsv_file *wind_file(const char *name, vsv_meta *m, int nsteps, const int64_t *times, wind_fn fn)
{
    vsv_meta_add_var(m, VSV_WIND_EAST, "m s-1", "eastward wind");
    vsv_meta_add_var(m, VSV_WIND_NORTH, "m s-1", "northward wind");
    vsv_meta_add_var(m, VSV_WIND_UP, "m s-1", "upward wind");
    vsv_meta_add_attr(m, VSV_VECTOR_ATTR VSV_WIND, VSV_WIND_EAST " " VSV_WIND_NORTH " " VSV_WIND_UP);
    const size_t cells = (size_t)m->nx * m->ny * m->nz;
    float *v[3];
    for (int c = 0; c < 3; c++)
        v[c] = malloc(cells * sizeof(float));
    const char *path = vsv_test_tmp(name);
    vsv_writer *w = NULL;
    vsv_file *f = NULL;
    int rc = vsv_writer_create(path, m, NULL, &w);
    for (int s = 0; s < nsteps && !rc; s++) {
        const vsv_meta pm = vsv_meta_placed(m, times[s]); /* a moving grid where it is then */
        for (int k = 0; k < m->nz; k++)
            for (int j = 0; j < m->ny; j++)
                for (int i = 0; i < m->nx; i++) {
                    float o[3];
                    fn(s, pm.origin[0] + i * m->spacing[0], pm.origin[1] + j * m->spacing[1],
                       vsv_meta_cell_height_at(&pm, times[s], i, j, k), o);
                    for (int c = 0; c < 3; c++)
                        v[c][((size_t)k * m->ny + j) * m->nx + i] = o[c];
                }
        const float *fields[3] = {v[0], v[1], v[2]};
        rc = vsv_writer_add_step(w, times[s], fields);
    }
    if (!rc)
        rc = vsv_writer_finish(w, NULL, NULL);
    if (!rc)
        vsv_file_open(path, &f);
    vsv_writer_free(w);
    for (int c = 0; c < 3; c++)
        free(v[c]);
    vsv_meta_clear(m);
    return f;
}

static void uniform(int s, double x, double y, double z, float o[3])
{
    (void)s, (void)x, (void)y, (void)z;
    o[0] = 10, o[1] = 5, o[2] = 0.01f;
}

static void east10(int s, double x, double y, double z, float o[3])
{
    (void)s, (void)x, (void)y, (void)z;
    o[0] = 10, o[1] = 0, o[2] = 0;
}

static void east100(int s, double x, double y, double z, float o[3])
{
    (void)s, (void)x, (void)y, (void)z;
    o[0] = 100, o[1] = 0, o[2] = 0;
}

/* 10 m/s east at the first step, 20 at the second */
static void ramp(int s, double x, double y, double z, float o[3])
{
    (void)x, (void)y, (void)z;
    o[0] = s ? 20 : 10, o[1] = 0, o[2] = 0;
}

#define OMEGA (2 * M_PI / 36000.0) /* a turn in 10 h */
#define XC 50000.0

static void rotation(int s, double x, double y, double z, float o[3])
{
    (void)s, (void)z;
    o[0] = (float)(-OMEGA * (y - XC)), o[1] = (float)(OMEGA * (x - XC)), o[2] = 0;
}

static void down(int s, double x, double y, double z, float o[3])
{
    (void)s, (void)x, (void)y, (void)z;
    o[0] = 0, o[1] = 0, o[2] = -1;
}

static void up(int s, double x, double y, double z, float o[3])
{
    (void)s, (void)x, (void)y, (void)z;
    o[0] = 0, o[1] = 0, o[2] = 1;
}

/* east = z / 100 m/s: a shear in height */
static void shear(int s, double x, double y, double z, float o[3])
{
    (void)s, (void)x, (void)y;
    o[0] = (float)(z / 100), o[1] = 0, o[2] = 1;
}

/* east = 5 + x / 10000 m/s in the projection's x, wherever the grid is */
static void stretch(int s, double x, double y, double z, float o[3])
{
    (void)s, (void)y, (void)z;
    o[0] = (float)(5 + x / 10000), o[1] = 0, o[2] = 0;
}

static int run(vsv_traj *t, double x, double y, double z, double from, double to, double every, vsv_traj_path *p)
{
    const double seed[3] = {x, y, z};
    return vsv_traj_run(t, seed, from, to, every, p);
}

static void test_uniform(void)
{
    vsv_meta m;
    grid(&m, 40, 40, 10, 1000);
    const int64_t times[2] = {0, 7200};
    vsv_file *f = wind_file("uniform.vsv", &m, 2, times, uniform);
    vsv_traj *t = NULL;
    vsv_traj_path p = {0};
    if (!CHECK(f && vsv_traj_create(f, &t) == 0, "uniform wind: the file opens with its wind"))
        goto done;
    const double T = 3000, len = T * sqrt(10 * 10 + 5 * 5 + 0.01 * 0.01);
    int rc = run(t, 5000, 5000, 300, 0, T, 0, &p);
    const vsv_traj_point *e = &p.pts[p.n - 1];
    const double d = sqrt(pow(e->x - 5000, 2) + pow(e->y - 5000, 2) + pow(e->z - 300, 2));
    double off = 0; /* the farthest point from the line through the seed along (10, 5, 0.01) */
    for (int i = 0; i < p.n; i++) {
        const double r[3] = {p.pts[i].x - 5000, p.pts[i].y - 5000, p.pts[i].z - 300};
        const double s = (r[0] * 10 + r[1] * 5 + r[2] * 0.01) / sqrt(125.0001);
        off = fmax(off, sqrt(fmax(r[0] * r[0] + r[1] * r[1] + r[2] * r[2] - s * s, 0)));
    }
    CHECK(rc == 0 && p.end == VSV_TRAJ_END_TIME && e->t == T, "uniform wind: the path reaches the time asked",
          "rc %d end %d t %g", rc, p.end, e->t);
    CHECK(fabs(d - len) <= 1e-6 * len, "uniform wind: a path of |v| * duration (1e-6)", "%.9g m, expected %.9g m", d,
          len);
    CHECK(off <= 1e-6 * len, "uniform wind: a straight line (1e-6 of its length)", "%.3g m off the line", off);
    CHECK(p.n > 2 && p.pts[1].t - p.pts[0].t == 50,
          "step rule: Courant 0.5 on the cell (0.5 / (10 m/s / 1000 m) = 50 s)", "first step %g s",
          p.n > 1 ? p.pts[1].t - p.pts[0].t : -1);
    CHECK(e->east == 10 && e->north == 5 && fabsf(e->up - 0.01f) < 1e-4f, "uniform wind: the wind at the point",
          "%g %g %g", e->east, e->north, e->up);
    printf("  uniform wind: %.9g m in %g s (%d points), %.3g m off the line\n", d, T, p.n, off);
    /* a point every 10 minutes, at those times exactly */
    rc = run(t, 5000, 5000, 300, 0, 3000, 600, &p);
    CHECK(rc == 0 && p.n == 6 && p.pts[3].t == 1800 && fabs(p.pts[3].x - (5000 + 18000)) < 1e-6,
          "every 600 s: 6 points at those times", "%d points", p.n);
    /* the edge: x = (40 - 0.5) * 1000 reached after 3450 s */
    rc = run(t, 5000, 5000, 300, 0, 7200, 0, &p);
    e = &p.pts[p.n - 1];
    CHECK(rc == 0 && p.end == VSV_TRAJ_END_EDGE && fabs(e->x - 39500) < 1e-3 && fabs(e->t - 3450) < 1e-3,
          "uniform wind: the path ends at the grid's east edge (END_EDGE)", "end %d at x %.6f, t %.6f", p.end, e->x,
          e->t);
    /* the file's times run out: END_DATA at its last time */
    rc = run(t, 1000, 1000, 300, 6500, 9000, 0, &p);
    CHECK(rc == 0 && p.end == VSV_TRAJ_END_DATA && p.pts[p.n - 1].t == 7200,
          "a path past the file's last time ends there (END_DATA)", "end %d at t %g", p.end, p.pts[p.n - 1].t);
    /* bad seeds */
    CHECK(run(t, -2000, 5000, 300, 0, 100, 0, &p) == VSV_EINVAL && p.n == 0, "a seed outside the grid: VSV_EINVAL");
    CHECK(run(t, 5000, 5000, 2000, 0, 100, 0, &p) == VSV_EINVAL, "a seed above the top: VSV_EINVAL");
    CHECK(run(t, 5000, 5000, 300, -10, 100, 0, &p) == VSV_EINVAL, "a start before the file's times: VSV_EINVAL", "%s",
          vsv_traj_error(t));
    CHECK(run(t, NAN, 5000, 300, 0, 100, 0, &p) == VSV_EINVAL, "a seed not a number: VSV_EINVAL");
    CHECK(run(t, 5000, 5000, 300, 0, 100, -1, &p) == VSV_EINVAL, "a negative interval: VSV_EINVAL");
done:
    vsv_traj_path_clear(&p);
    vsv_traj_free(t);
    vsv_file_free(f);
}

/* Great-circle distance on the models' sphere. */
static double dist_m(double lat1, double lon1, double lat2, double lon2)
{
    const double r = M_PI / 180, R = 6370000;
    double dlat = (lat2 - lat1) * r, dlon = (lon2 - lon1) * r;
    double a = sin(dlat / 2) * sin(dlat / 2) + cos(lat1 * r) * cos(lat2 * r) * sin(dlon / 2) * sin(dlon / 2);
    return 2 * R * asin(sqrt(a));
}

static void test_lcc(void)
{
    vsv_meta m;
    grid(&m, 60, 60, 5, 4000);
    m.proj = (vsv_proj){VSV_PROJ_LCC, 40, -100, 30, 60, 0};
    m.origin[0] = m.origin[1] = -118000;
    const int64_t times[2] = {0, 21600};
    vsv_file *f = wind_file("lcc.vsv", &m, 2, times, east10);
    vsv_traj *t = NULL;
    vsv_traj_path p = {0};
    if (!CHECK(f && vsv_traj_create(f, &t) == 0, "Lambert grid: the file opens with its wind"))
        goto done;
    const double T = 10800;
    int rc = run(t, -60000, 30000, 250, 0, T, 0, &p);
    double along = 0;
    for (int i = 1; i < p.n; i++)
        along += dist_m(p.pts[i - 1].lat, p.pts[i - 1].lon, p.pts[i].lat, p.pts[i].lon);
    const vsv_traj_point *a = &p.pts[0], *e = &p.pts[p.n - 1];
    const double parallel = 6370000 * cos(a->lat * M_PI / 180) * (e->lon - a->lon) * M_PI / 180;
    CHECK(rc == 0 && p.end == VSV_TRAJ_END_TIME, "Lambert grid: the path runs its 3 h", "rc %d end %d", rc, p.end);
    CHECK(fabs(along - 108000) <= 1e-4 * 108000, "Lambert grid: 10 m/s east for 3 h travels 108 km (1e-4)", "%.3f m",
          along);
    CHECK(fabs(e->lat - a->lat) < 1e-4 && fabs(parallel - 108000) <= 1e-4 * 108000,
          "Lambert grid: an east wind keeps to its parallel (1e-4 degree) for 108 km along it",
          "latitude %.7f -> %.7f, %.3f m along the parallel", a->lat, e->lat, parallel);
    printf("  Lambert grid: %.3f m travelled, latitude drift %.2g degree\n", along, e->lat - a->lat);
    /* seeds along a line between two points, and on a slice */
    double s[15];
    const double la[3] = {a->lat, a->lon, 100}, lb[3] = {e->lat, e->lon, 500};
    rc = vsv_traj_seed_line(vsv_file_meta(f), la, lb, 5, s);
    CHECK(rc == 0 && fabs(s[0] + 60000) < 1e-3 && fabs(s[1] - 30000) < 1e-3 && fabs(s[12] - e->x) < 1e-3 &&
              fabs(s[6] - (s[0] + s[12]) / 2) < 1e-6 && s[8] == 300,
          "seeds along a line: its ends projected, evenly spaced, heights linear", "rc %d %g %g", rc, s[0], s[1]);
    CHECK(vsv_traj_seed_line(vsv_file_meta(f), la, lb, 0, s) == VSV_EINVAL, "seeds along a line: n 0 refused");
    CHECK(vsv_traj_seed_plane(vsv_file_meta(f), 0, 250, 10, NULL, 0) == 36 &&
              vsv_traj_seed_plane(vsv_file_meta(f), 0, 250, 10, s, 5) == 36 && s[0] == -98000 && s[3] == -58000,
          "seeds on a slice: every 10th column from the 5th (36), at most cap written");
    CHECK(vsv_traj_seed_plane(vsv_file_meta(f), 0, 9000, 10, NULL, 0) == 0, "seeds on a slice above the top: none");
done:
    vsv_traj_path_clear(&p);
    vsv_traj_free(t);
    vsv_file_free(f);
}

static void test_rotation(void)
{
    vsv_meta m;
    grid(&m, 101, 101, 3, 1000);
    const int64_t times[2] = {0, 36000};
    vsv_file *f = wind_file("rotation.vsv", &m, 2, times, rotation);
    vsv_traj *t = NULL;
    vsv_traj_path p = {0}, q = {0};
    if (!CHECK(f && vsv_traj_create(f, &t) == 0, "solid-body rotation: the file opens with its wind"))
        goto done;
    const double R = 30000;
    int rc = run(t, XC + R, XC, 150, 0, 36000, 0, &p);
    double worst = 0;
    for (int i = 0; i < p.n; i++)
        worst = fmax(worst, fabs(hypot(p.pts[i].x - XC, p.pts[i].y - XC) - R));
    const vsv_traj_point *e = &p.pts[p.n - 1];
    const double closing = hypot(e->x - (XC + R), e->y - XC);
    CHECK(rc == 0 && p.end == VSV_TRAJ_END_TIME, "solid-body rotation: the path runs a period");
    CHECK(closing < 1e-4 * R, "solid-body rotation: a circle that closes after a period (1e-4 of the radius)",
          "closing error %.3f m of %g m", closing, R);
    CHECK(worst < 1e-4 * R, "solid-body rotation: the radius kept within 1e-4", "%.3f m", worst);
    printf("  solid-body rotation, radius %g m, one period (%d steps): closing error %.3f m (%.2g of the radius), "
           "radius within %.3f m\n",
           R, p.n - 1, closing, closing / R, worst);
    /* backward half a period, then forward again: back at the seed */
    rc = run(t, XC, XC + 20000, 150, 18000, 0, 0, &p);
    e = &p.pts[p.n - 1];
    CHECK(rc == 0 && p.end == VSV_TRAJ_END_TIME && e->t == 0 && fabs(e->x - XC) < 1 && fabs(e->y - (XC - 20000)) < 1,
          "backward half a turn: the opposite point", "at %g: %.3f %.3f", e->t, e->x, e->y);
    rc = run(t, e->x, e->y, e->z, 0, 18000, 0, &q);
    e = &q.pts[q.n - 1];
    const double back = hypot(e->x - XC, e->y - (XC + 20000));
    CHECK(rc == 0 && back < 0.01, "backward then forward returns to the seed (1 cm)", "%.4f m", back);
done:
    vsv_traj_path_clear(&p);
    vsv_traj_path_clear(&q);
    vsv_traj_free(t);
    vsv_file_free(f);
}

static void test_time_varying(void)
{
    vsv_meta m;
    grid(&m, 80, 10, 3, 1000);
    const int64_t times[2] = {0, 3600};
    vsv_file *f = wind_file("ramp.vsv", &m, 2, times, ramp);
    vsv_traj *t = NULL;
    vsv_traj_path p = {0};
    if (!CHECK(f && vsv_traj_create(f, &t) == 0, "a wind that changes: the file opens"))
        goto done;
    /* u(t) = 10 + 10 t / 3600: x(t) = x0 + 10 t + 5 t^2 / 3600 */
    int rc = run(t, 2000, 5000, 150, 0, 3600, 1800, &p);
    CHECK(rc == 0 && p.n == 3 && fabs(p.pts[1].x - 24500) < 1e-6 * 24500 && fabs(p.pts[2].x - 56000) < 1e-6 * 56000,
          "a wind linear in time between steps: its integral (24500 m at 30 min, 56000 m at 1 h)", "%.6f %.6f",
          p.n > 2 ? p.pts[1].x : 0, p.n > 2 ? p.pts[2].x : 0);
    CHECK(p.n == 3 && p.pts[1].east == 15, "the wind halfway between the steps is their mean", "%g",
          p.n > 1 ? p.pts[1].east : 0);
    /* streamlines: the wind frozen at one moment, whatever the clock says */
    CHECK(vsv_traj_freeze(t, 0) == 0 && run(t, 2000, 5000, 150, 0, 3600, 0, &p) == 0 && p.n > 1 &&
              fabs(p.pts[p.n - 1].x - 38000) < 1e-6 * 38000 && p.pts[p.n - 1].t == 3600,
          "a streamline of the wind at 0 s: 10 m/s for the hour (38000 m)", "%.6f", p.n ? p.pts[p.n - 1].x : 0);
    CHECK(vsv_traj_freeze(t, 3600) == 0 && run(t, 2000, 5000, 150, 10000, 13000, 0, &p) == 0 &&
              p.end == VSV_TRAJ_END_TIME && fabs(p.pts[p.n - 1].x - 62000) < 1e-6 * 62000,
          "a streamline of the wind at 3600 s: 20 m/s for 3000 s of travel (62000 m), the clock past the file's "
          "times",
          "%.6f end %d", p.n ? p.pts[p.n - 1].x : 0, p.end);
    CHECK(vsv_traj_freeze(t, 3601) == VSV_EINVAL, "a streamline's time outside the file's is refused", "");
    CHECK(vsv_traj_freeze(t, NAN) == 0 && run(t, 2000, 5000, 150, 0, 3600, 0, &p) == 0 &&
              fabs(p.pts[p.n - 1].x - 56000) < 1e-6 * 56000,
          "unfrozen: the wind changes in time again (56000 m)", "%.6f", p.n ? p.pts[p.n - 1].x : 0);
done:
    vsv_traj_path_clear(&p);
    vsv_traj_free(t);
    vsv_file_free(f);
}

/* Round the globe: a 10-degree longitude-latitude grid whose 36 columns
 * span 360 degrees, 100 m/s east everywhere; a streamline from 350 east on
 * the equator for one and a half turns keeps going (it ended at the grid's
 * east edge) and its longitudes stay within a turn of the grid's west edge
 * (-5: they grew to 890). */
static void test_globe(void)
{
    vsv_meta m;
    grid(&m, 36, 9, 2, 10);
    m.proj.kind = VSV_PROJ_LATLON;
    m.origin[1] = -40;
    const int64_t times[2] = {0, 3600};
    vsv_file *f = wind_file("globe.vsv", &m, 2, times, east100);
    vsv_traj *t = NULL;
    vsv_traj_path p = {0};
    if (!CHECK(f && vsv_traj_create(f, &t) == 0 && vsv_traj_freeze(t, 0) == 0, "a global grid: the file opens"))
        goto done;
    const double turn = 2 * M_PI * 6370000 / 100; /* seconds a turn at 100 m/s */
    int rc = run(t, 350, 0, 150, 0, 1.5 * turn, 0, &p);
    const vsv_traj_point *e = &p.pts[p.n - 1];
    int within = 1;
    for (int i = 0; i < p.n; i++)
        within &= p.pts[i].x >= -5 && p.pts[i].x < 355 && p.pts[i].lon == p.pts[i].x;
    CHECK(rc == 0 && p.end == VSV_TRAJ_END_TIME && fabs(e->x - 170) < 1e-6 && fabs(e->y) < 1e-9,
          "round the globe: 1.5 turns east from 350 end at 170 east, on the equator", "rc %d, end %d at x %.9g, y %g",
          rc, p.end, e->x, e->y);
    CHECK(within, "... every point's longitude within [-5, 355), the grid's west edge and a turn");
    /* drawn (vsv-render --trajectory): a line to the map's east edge, then
     * one on from its west edge (it was one line running off the map) */
    vsv_flow_opts o = {0};
    o.traj[o.ntraj++] = "0,350,150";
    o.steady = 1;
    o.dur = (int64_t)(0.5 * turn);
    vsv_flow *fl = NULL;
    const vsv_scene_line *lines = NULL;
    char msg[256] = "";
    int n = 0;
    rc = vsv_flow_open(f, &o, &fl, msg, sizeof msg);
    if (!rc)
        rc = vsv_flow_frame(fl, 0, 1, 0, &lines, &n, msg, sizeof msg);
    int split = rc == 0 && n == 2 && lines[0].npts > 1 && lines[1].npts > 1;
    for (int l = 0; split && l < 2; l++)
        for (int i = 1; i < lines[l].npts; i++)
            split &= lines[l].xyz[3 * i] > lines[l].xyz[3 * i - 3];
    CHECK(split && lines[0].xyz[3 * (lines[0].npts - 1)] > lines[1].xyz[0],
          "... drawn as two lines, east to the map's edge, then on from its west edge", "rc %d (%s), %d lines", rc, msg,
          n);
    vsv_flow_free(fl);
done:
    vsv_traj_path_clear(&p);
    vsv_traj_free(t);
    vsv_file_free(f);
}

static void test_ground_top(void)
{
    vsv_meta m;
    grid(&m, 10, 10, 10, 1000);
    vsv_meta_alloc_terrain(&m);
    for (int c = 0; c < 100; c++)
        m.terrain[c] = 200;
    const int64_t times[2] = {0, 3600};
    vsv_file *f = wind_file("down.vsv", &m, 2, times, down), *g = NULL;
    vsv_traj *t = NULL, *u = NULL;
    vsv_traj_path p = {0};
    if (!CHECK(f && vsv_traj_create(f, &t) == 0, "the ground: the file opens"))
        goto done;
    int rc = run(t, 5000, 5000, 600, 0, 3600, 0, &p);
    const vsv_traj_point *e = &p.pts[p.n - 1];
    CHECK(rc == 0 && p.end == VSV_TRAJ_END_GROUND && fabs(e->z - 200) < 1e-3 && fabs(e->t - 400) < 1e-3,
          "a sinking path ends on the ground (END_GROUND) where it meets it", "end %d at z %.6f, t %.6f", p.end, e->z,
          e->t);
    CHECK(run(t, 5000, 5000, 150, 0, 100, 0, &p) == VSV_EINVAL, "a seed below the ground: VSV_EINVAL", "%s",
          vsv_traj_error(t));
    grid(&m, 10, 10, 10, 1000);
    g = wind_file("up.vsv", &m, 2, times, up);
    if (!CHECK(g && vsv_traj_create(g, &u) == 0, "the top: the file opens"))
        goto done;
    rc = run(u, 5000, 5000, 600, 0, 3600, 0, &p);
    e = &p.pts[p.n - 1];
    CHECK(rc == 0 && p.end == VSV_TRAJ_END_TOP && fabs(e->z - 1000) < 1e-3 && fabs(e->t - 400) < 1e-3,
          "a rising path ends at the top (END_TOP)", "end %d at z %.6f, t %.6f", p.end, e->z, e->t);
done:
    vsv_traj_path_clear(&p);
    vsv_traj_free(t);
    vsv_traj_free(u);
    vsv_file_free(f);
    vsv_file_free(g);
}

/* A wind of two components (a model without W): the air keeps its height. */
static void test_horizontal(void)
{
    vsv_meta m;
    grid(&m, 20, 10, 3, 1000);
    vsv_meta_add_var(&m, VSV_WIND_EAST, "m s-1", "eastward wind");
    vsv_meta_add_var(&m, VSV_WIND_NORTH, "m s-1", "northward wind");
    vsv_meta_add_attr(&m, VSV_VECTOR_ATTR VSV_WIND, VSV_WIND_EAST " " VSV_WIND_NORTH);
    static float e[600], n[600];
    for (int c = 0; c < 600; c++)
        e[c] = 5, n[c] = 2;
    const float *fields[2] = {e, n};
    vsv_writer *w = NULL;
    vsv_file *f = NULL;
    vsv_traj *t = NULL;
    vsv_traj_path p = {0};
    const char *path = vsv_test_tmp("horizontal.vsv");
    if (!vsv_writer_create(path, &m, NULL, &w) && !vsv_writer_add_step(w, 0, fields) &&
        !vsv_writer_add_step(w, 3600, fields) && !vsv_writer_finish(w, NULL, NULL))
        vsv_file_open(path, &f);
    vsv_writer_free(w);
    vsv_meta_clear(&m);
    if (!CHECK(f && vsv_traj_create(f, &t) == 0, "a wind without its upward component: a handle", ""))
        goto done;
    const int rc = run(t, 2000, 2000, 150, 0, 1000, 0, &p);
    const vsv_traj_point *q = p.n ? &p.pts[p.n - 1] : NULL;
    CHECK(rc == 0 && q && fabs(q->x - 7000) < 1e-6 && fabs(q->y - 4000) < 1e-6 && q->z == 150 && q->up == 0,
          "a wind without its upward component: 5 and 2 m/s for 1000 s at its height, up 0", "%.6f %.6f %.6f",
          q ? q->x : 0, q ? q->y : 0, q ? q->z : 0);
done:
    vsv_traj_path_clear(&p);
    vsv_traj_free(t);
    vsv_file_free(f);
}

static void test_no_wind(void)
{
    vsv_meta m;
    grid(&m, 4, 4, 2, 1000);
    vsv_meta_add_var(&m, "O3", "ppb", "ozone");
    float z[32] = {0};
    const float *fields[1] = {z};
    vsv_writer *w = NULL;
    vsv_file *f = NULL;
    const char *path = vsv_test_tmp("nowind.vsv");
    if (!vsv_writer_create(path, &m, NULL, &w) && !vsv_writer_add_step(w, 0, fields) &&
        !vsv_writer_finish(w, NULL, NULL))
        vsv_file_open(path, &f);
    vsv_writer_free(w);
    vsv_meta_clear(&m);
    vsv_traj *t = NULL;
    CHECK(f && vsv_traj_create(f, &t) == VSV_ENOTFOUND && strstr(vsv_traj_error(t), "no wind"),
          "a file without wind: VSV_ENOTFOUND, \"no wind\"");
    vsv_traj_free(t);
    vsv_file_free(f);
}

/* Native levels whose heights differ by column (100 + 200 k + 10 i m) in a
 * wind that grows with height: at a fixed height the wind is the same in
 * every column only when each is sampled at its own heights; pressure
 * levels keep the air's level whatever the upward wind. */
static void test_levels(void)
{
    vsv_meta m;
    grid(&m, 40, 6, 14, 1000);
    m.vert_kind = VSV_VERT_NATIVE;
    vsv_meta_alloc_levels(&m);
    float *z = malloc((size_t)40 * 6 * 14 * sizeof *z);
    for (int k = 0; k < 14; k++) {
        m.levels[k] = 100 + 200 * k + 195;
        for (int c = 0; c < 240; c++)
            z[(size_t)k * 240 + c] = (float)(100 + 200 * k + 10 * (c % 40));
    }
    vsv_meta_add_heights(&m, 0, z, NULL, NULL);
    free(z);
    const int64_t times[2] = {0, 3600};
    vsv_file *f = wind_file("native.vsv", &m, 2, times, shear), *g = NULL;
    vsv_traj *t = NULL, *u = NULL;
    vsv_traj_path p = {0};
    if (!CHECK(f && vsv_traj_create(f, &t) == 0, "native levels: the file opens"))
        goto done;
    /* rising 1 m/s from 300 m: east = z / 100, x(t) = x0 + 3 t + t^2 / 200 */
    int rc = run(t, 2000, 2500, 300, 0, 1800, 0, &p);
    const vsv_traj_point *e = &p.pts[p.n - 1];
    const double x = 2000 + 3 * 1800.0 + 1800.0 * 1800 / 200;
    CHECK(rc == 0 && p.end == VSV_TRAJ_END_TIME && fabs(e->z - 2100) < 1e-3 && fabs(e->x - x) < 0.5,
          "native levels: the wind at the columns' own heights (x and z as integrated, 0.5 m)",
          "end %d, x %.3f (expected %.3f), z %.3f", p.end, e->x, x, e->z);
    vsv_meta m2;
    grid(&m2, 40, 40, 4, 1000);
    m2.vert_kind = VSV_VERT_COORD;
    snprintf(m2.vert_units, sizeof m2.vert_units, "hPa");
    vsv_meta_alloc_levels(&m2);
    for (int k = 0; k < 4; k++)
        m2.levels[k] = 1000 - 100 * k;
    g = wind_file("pressure.vsv", &m2, 2, times, uniform); /* up 0.01 m/s: not used */
    if (!CHECK(g && vsv_traj_create(g, &u) == 0, "pressure levels: the file opens"))
        goto done;
    rc = run(u, 2000, 2500, 850, 0, 1800, 0, &p);
    e = &p.pts[p.n - 1];
    CHECK(rc == 0 && e->z == 850 && fabs(e->x - 20000) < 1e-6 && fabs(e->y - 11500) < 1e-6 && e->up != 0,
          "pressure levels: the air keeps its level (the upward wind printed, not used)", "z %g, x %.6f, y %.6f", e->z,
          e->x, e->y);
    CHECK(run(u, 2000, 2500, 500, 0, 1800, 0, &p) == VSV_EINVAL, "pressure levels: a seed off the levels: VSV_EINVAL");
done:
    vsv_traj_path_clear(&p);
    vsv_traj_free(t);
    vsv_traj_free(u);
    vsv_file_free(f);
    vsv_file_free(g);
}

/* A grid that moves 5 cells east at 30 min, in a wind tied to the ground
 * (east = 5 + x / 10000): dx/dt = 5 + x / 1e4, x(t) = (x0 + 5e4) e^(t/1e4) - 5e4. */
static void test_moving(void)
{
    vsv_meta m;
    grid(&m, 40, 6, 3, 1000);
    const double o1[2] = {5000, 0};
    vsv_meta_add_move(&m, 1800, o1, NULL);
    const int64_t times[3] = {0, 1800, 3600};
    vsv_file *f = wind_file("moving.vsv", &m, 3, times, stretch);
    vsv_traj *t = NULL;
    vsv_traj_path p = {0};
    if (!CHECK(f && vsv_traj_create(f, &t) == 0, "a moving grid: the file opens"))
        goto done;
    int rc = run(t, 6000, 2500, 150, 0, 3600, 0, &p);
    const vsv_traj_point *e = &p.pts[p.n - 1];
    const double x = 56000 * exp(0.36) - 50000;
    CHECK(rc == 0 && p.end == VSV_TRAJ_END_TIME && fabs(e->x - x) < 0.5,
          "a moving grid: the wind of each step where the grid is then (0.5 m)", "end %d, x %.3f (expected %.3f)",
          p.end, e->x, x);
done:
    vsv_traj_path_clear(&p);
    vsv_traj_free(t);
    vsv_file_free(f);
}

int main(void)
{
    test_uniform();
    test_lcc();
    test_rotation();
    test_time_varying();
    test_globe();
    test_ground_top();
    test_no_wind();
    test_horizontal();
    test_levels();
    test_moving();
    return vsv_test_done();
}
