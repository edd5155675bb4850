/* vsv_outlines.c — coast, lake and border lines for the map under a grid,
 * from the GSHHG binned netCDF files of Debian's gmt-gshhg-low
 * (binned_GSHHS_R.nc: shorelines by level, 1 land/sea, 2 lake, 3 island in a
 * lake, 4 pond; binned_border_R.nc: 1 national, 2 state or province, 3
 * maritime), read by the helper program vsv-gshhg (render/vsv-gshhg.c: the
 * files' layout is described there; libhdf5 runs in it, not here) and
 * projected with the grid's own projection. */
#include "vsv_annot_internal.h"

#include "vsv_common.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#define VSV_GSHHG_DIR "/usr/share/gmt-gshhg"

typedef struct line {
    int kind, first, n; /* VSV_OUTLINE_*, its points */
} line;

struct vsv_outlines {
    line *lines;
    int nlines, cap;
    double *xy; /* world x, y pairs */
    size_t npts, ptcap;
    char res;
};

/* The lat/lon box a grid covers: its boundary cells inverse-projected
 * (longitudes unwrapped around the centre's), widened by a margin, the
 * whole circle of longitude when a pole is inside. */
int vsv_grid_latlon_box(const vsv_meta *m, double box[4])
{
    double *s = &box[0], *n = &box[1], *w = &box[2], *e = &box[3];
    double clat, clon;
    const double cx = m->origin[0] + 0.5 * (m->nx - 1) * m->spacing[0];
    const double cy = m->origin[1] + 0.5 * (m->ny - 1) * m->spacing[1];
    if (vsv_proj_inverse(&m->proj, cx, cy, &clat, &clon))
        return VSV_EUNSUPPORTED;
    *s = *w = INFINITY;
    *n = *e = -INFINITY;
    const int per = 64;
    for (int side = 0; side < 4; side++)
        for (int k = 0; k <= per; k++) {
            const double f = (double)k / per - 0.5;
            const double u = side < 2 ? f : side == 2 ? -0.5 : 0.5, v = side < 2 ? (side ? 0.5 : -0.5) : f;
            const double x = cx + u * (m->nx) * m->spacing[0], y = cy + v * (m->ny) * m->spacing[1];
            double lat, lon;
            if (vsv_proj_inverse(&m->proj, x, y, &lat, &lon))
                continue;
            lon = clon + remainder(lon - clon, 360);
            *s = fmin(*s, lat), *n = fmax(*n, lat), *w = fmin(*w, lon), *e = fmax(*e, lon);
        }
    if (!(*s <= *n))
        return VSV_EUNSUPPORTED;
    const double pad = 1;
    *s -= pad, *n += pad, *w -= pad, *e += pad;
    for (int pole = -1; pole <= 1; pole += 2) { /* a pole inside the grid */
        double x, y;
        if (vsv_proj_forward(&m->proj, 90.0 * pole, clon, &x, &y) == 0 && fabs(x - cx) < 0.5 * m->nx * m->spacing[0] &&
            fabs(y - cy) < 0.5 * m->ny * m->spacing[1]) {
            *w = clon - 180, *e = clon + 180;
            if (pole < 0)
                *s = -90;
            else
                *n = 90;
        }
    }
    if (*e - *w > 360)
        *w = clon - 180, *e = clon + 180;
    *s = fmax(*s, -90), *n = fmin(*n, 90);
    return 0;
}

static int add_point(vsv_outlines *o, double x, double y)
{
    if (o->npts == o->ptcap) {
        const size_t nc = o->ptcap ? 2 * o->ptcap : 4096;
        double *p = realloc(o->xy, nc * 2 * sizeof *p);
        if (!p)
            return VSV_ENOMEM;
        o->xy = p;
        o->ptcap = nc;
    }
    o->xy[2 * o->npts] = x;
    o->xy[2 * o->npts + 1] = y;
    o->npts++;
    return 0;
}

static int end_line(vsv_outlines *o, int kind, size_t first)
{
    if (o->npts - first < 2) {
        o->npts = first;
        return 0;
    }
    if (o->nlines == o->cap) {
        const int nc = o->cap ? 2 * o->cap : 256;
        line *l = realloc(o->lines, (size_t)nc * sizeof *l);
        if (!l)
            return VSV_ENOMEM;
        o->lines = l;
        o->cap = nc;
    }
    o->lines[o->nlines++] = (line){kind, (int)first, (int)(o->npts - first)};
    return 0;
}

/* The grid's x of longitude lon: for a latitude/longitude grid the copy of
 * lon (lon + k 360) inside its span, else the projection's. */
static int project(const vsv_meta *m, double lat, double lon, double x0, double *x, double *y)
{
    if (m->proj.kind == VSV_PROJ_LATLON)
        lon = x0 + fmod(fmod(lon - x0, 360) + 360, 360);
    return vsv_scene_world(m, lat, lon, x, y);
}

/* Reads exactly n bytes of fd by the deadline (CLOCK_MONOTONIC seconds):
 * 0, or -1 (the helper closed its end early, or took too long). */
static int take(int fd, void *p, size_t n, double deadline)
{
    char *c = p;
    while (n) {
        struct timespec ts;
        clock_gettime(CLOCK_MONOTONIC, &ts);
        const double left = deadline - (ts.tv_sec + ts.tv_nsec * 1e-9);
        if (left <= 0 || vsv_helper_poll(fd, left) != 1)
            return -1;
        const ssize_t r = read(fd, c, n);
        if (r < 0 && errno == EINTR)
            continue;
        if (r <= 0)
            return -1;
        c += r, n -= (size_t)r;
    }
    return 0;
}

/* Adds one segment's points (lat/lon from its bin's corner and offsets),
 * projected, split where the projection fails or a latitude/longitude
 * grid's seam cuts it. */
static int add_segment(vsv_outlines *o, const vsv_meta *m, int kind, int n, const double corner[3],
                       const unsigned short *dx, const unsigned short *dy)
{
    const double x0 = m->origin[0] - 0.5 * m->spacing[0]; /* a latitude/longitude grid's west edge */
    double ux, uy;
    vsv_scene_units(m, &ux, &uy);
    const double half_turn = m->proj.kind == VSV_PROJ_LATLON ? 180 * ux : INFINITY;
    size_t start = o->npts;
    int rc = 0;
    for (int p = 0; p < n && !rc; p++) {
        const double lon = corner[0] + dx[p] * corner[2], lat = corner[1] + dy[p] * corner[2];
        double x, y;
        const int ok = !project(m, lat, lon, x0, &x, &y) && isfinite(x) && isfinite(y);
        /* a latitude/longitude grid's seam: the line leaves on one side and
         * comes back on the other */
        if (!ok || (o->npts > start && fabs(x - o->xy[2 * o->npts - 2]) > half_turn)) {
            rc = end_line(o, kind, start);
            start = o->npts;
        }
        if (ok && !rc)
            rc = add_point(o, x, y);
    }
    return rc ? rc : end_line(o, kind, start);
}

/* The records the helper vsv-gshhg writes on fd (its header says how),
 * added to o. 0, VSV_ECORRUPT (its error, said in msg), VSV_ENOMEM, or
 * VSV_EIO when the stream breaks off (the caller reports how it ended). */
static int take_records(vsv_outlines *o, const vsv_meta *m, int fd, double deadline, char *msg, size_t cap)
{
    unsigned short *d = NULL;
    size_t dcap = 0;
    int rc = 0;
    for (;;) {
        int32_t head[2];
        double corner[3];
        if (take(fd, head, sizeof head, deadline)) {
            rc = VSV_EIO;
            break;
        }
        if (head[0] == 0 && head[1] == -1) /* the end */
            break;
        if (head[0] == -1) { /* its error, saying where */
            char why[600] = "";
            const size_t n = head[1] > 0 && (size_t)head[1] < sizeof why ? (size_t)head[1] : 0;
            rc = n && !take(fd, why, n, deadline) ? VSV_ECORRUPT : VSV_EIO;
            snprintf(msg, cap, "%s", why);
            break;
        }
        if (head[0] < VSV_OUTLINE_COAST || head[0] > VSV_OUTLINE_STATE || head[1] < 0 || head[1] > 10000000 ||
            take(fd, corner, sizeof corner, deadline)) {
            rc = VSV_EIO;
            break;
        }
        if ((size_t)head[1] * 2 > dcap) {
            unsigned short *g = realloc(d, (size_t)head[1] * 2 * sizeof *d + 2);
            if (!g) {
                rc = VSV_ENOMEM;
                snprintf(msg, cap, "out of memory");
                break;
            }
            d = g, dcap = (size_t)head[1] * 2;
        }
        if (take(fd, d, (size_t)head[1] * 2 * sizeof *d, deadline)) {
            rc = VSV_EIO;
            break;
        }
        if ((rc = add_segment(o, m, head[0], head[1], corner, d, d + head[1]))) {
            snprintf(msg, cap, "out of memory");
            break;
        }
    }
    free(d);
    return rc;
}

/* Reads one binned file (border = 0: shorelines, 1: borders) in the helper
 * vsv-gshhg and adds the segments of the bins that meet [s, n] x [w, e]: a
 * libhdf5 that fails under it (a damaged file, an address-space limit) ends
 * the helper, said here, never the program drawing the map. */
static int read_binned(vsv_outlines *o, const vsv_meta *m, const char *path, int border, const double box[4], char *msg,
                       size_t cap)
{
    enum { LIMIT_S = 60 };
    char arg[6][32], why[300] = "";
    snprintf(arg[0], sizeof arg[0], "%d", border);
    for (int i = 0; i < 4; i++)
        snprintf(arg[1 + i], sizeof arg[1 + i], "%.17g", box[i]);
    snprintf(arg[5], sizeof arg[5], "%d", LIMIT_S);
    char *argv[] = {"vsv-gshhg", (char *)path, arg[0], arg[1], arg[2], arg[3], arg[4], arg[5], NULL};
    int fds[2], st = 0;
    if (pipe2(fds, O_CLOEXEC)) {
        snprintf(msg, cap, "%s: cannot read it: %s", path, strerror(errno));
        return VSV_EIO;
    }
    const pid_t pid = vsv_helper_spawn("vsv-gshhg", argv, -1, fds[1], -1, why, sizeof why);
    close(fds[1]);
    if (pid < 0) {
        close(fds[0]);
        snprintf(msg, cap, "%s: cannot read it: %s", path, why);
        return VSV_EIO;
    }
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    int rc = take_records(o, m, fds[0], ts.tv_sec + ts.tv_nsec * 1e-9 + LIMIT_S + 5, msg, cap);
    close(fds[0]);
    const int late = vsv_helper_reap(pid, rc ? 5 : LIMIT_S + 5, &st);
    if (rc != VSV_EIO)
        return rc;
    if (late || (WIFSIGNALED(st) && WTERMSIG(st) == SIGALRM))
        snprintf(msg, cap, "%s: reading it took more than %d s: stopped", path, LIMIT_S);
    else if (WIFSIGNALED(st))
        snprintf(msg, cap, "%s: the netCDF/HDF5 library crashed reading it (%s; out of memory?)", path,
                 strsignal(WTERMSIG(st)));
    else if (WIFEXITED(st) && WEXITSTATUS(st) == 127)
        snprintf(msg, cap, "%s: its reader (vsv-gshhg) could not start (out of memory?)", path);
    else
        snprintf(msg, cap, "%s: its reader (vsv-gshhg) ended early (exit status %d)", path,
                 WIFEXITED(st) ? WEXITSTATUS(st) : -1);
    return VSV_ECORRUPT;
}

int vsv_outlines_load(const vsv_meta *grid, const char *dir, char res, vsv_outlines **out, char *msg, size_t cap)
{
    const vsv_meta span = vsv_meta_span(grid), *m = &span; /* a moving nest: every place it stands */
    *out = NULL;
    if (!dir || !*dir)
        dir = getenv("VSV_GSHHG");
    if (!dir || !*dir)
        dir = VSV_GSHHG_DIR;
    if (res != 'c' && res != 'l' && res != 'i') {
        snprintf(msg, cap, "GSHHG resolution '%c': c, l or i", res);
        return VSV_EINVAL;
    }
    double box[4];
    if (m->proj.kind == VSV_PROJ_NONE || vsv_grid_latlon_box(m, box)) {
        snprintf(msg, cap, "the grid has no map projection: no coastlines");
        return VSV_EUNSUPPORTED;
    }
    char shore[4096], border[4096];
    snprintf(shore, sizeof shore, "%s/binned_GSHHS_%c.nc", dir, res);
    snprintf(border, sizeof border, "%s/binned_border_%c.nc", dir, res);
    if (access(shore, R_OK)) {
        snprintf(msg, cap, "%s: not found: no coast or border outlines (apt-get install gmt-gshhg-low)", shore);
        return VSV_ENOTFOUND;
    }
    vsv_outlines *o = calloc(1, sizeof *o);
    if (!o) {
        snprintf(msg, cap, "out of memory");
        return VSV_ENOMEM;
    }
    o->res = res;
    int rc = read_binned(o, m, shore, 0, box, msg, cap);
    if (!rc && !access(border, R_OK))
        rc = read_binned(o, m, border, 1, box, msg, cap);
    if (rc) {
        vsv_outlines_free(o);
        return rc;
    }
    *out = o;
    return 0;
}

char vsv_outlines_resolution(double km)
{
    /* GSHHG's resolutions keep features of about 25 (c), 5 (l) and 1 km (i) */
    return km > 12 ? 'c' : km > 2.5 ? 'l' : 'i';
}

void vsv_outlines_free(vsv_outlines *o)
{
    if (!o)
        return;
    free(o->lines);
    free(o->xy);
    free(o);
}

int vsv_outlines_count(const vsv_outlines *o) { return o ? o->nlines : 0; }

const double *vsv_outlines_line(const vsv_outlines *o, int i, int *kind, int *n)
{
    if (!o || i < 0 || i >= o->nlines)
        return NULL;
    *kind = o->lines[i].kind;
    *n = o->lines[i].n;
    return o->xy + 2 * (size_t)o->lines[i].first;
}
