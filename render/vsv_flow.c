/* vsv_flow.c — trajectories and wind arrows as the tools' options ask for
 * them (vsv_flow.h): the options read, the paths integrated once through
 * the file's wind (vsv_traj), and each frame's lines: every path up to
 * the frame's time, growing frame by frame (as Vis5D draws them), and the
 * arrows of the wind at that step. */
#include "vsv_flow.h"

#include "vsv_format.h"
#include "vsv_traj.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The trajectories' colours, one per option given, in turn. */
static const char *const palette[] = {"yellow", "cyan", "orange", "purple", "green", "red", "blue", "white"};

typedef struct flow_path {
    vsv_traj_path p;
    float rgb[3];
} flow_path;

/* A seed added by vsv_flow_add (streamlines: traced again every step). */
typedef struct flow_seed {
    double s[3];
    float rgb[3];
} flow_seed;

struct vsv_flow {
    vsv_file *f;
    const vsv_meta *m;
    vsv_flow_opts o;
    int wind[3];
    double ux, uy, radius;
    flow_path *paths;
    int npaths, pcap;
    /* the frame's lines and their points (grown, kept) */
    vsv_scene_line *lines;
    int lcap;
    double *xyz;
    size_t xcap;
    size_t *off; /* per line, its first coordinate in xyz */
    /* the wind arrows: the flow's own decoder and volumes */
    vsv_decoder *d;
    vsv_volume *ve, *vn;
    int barb_step; /* the step ve and vn hold, or -1 */
    /* streamlines: the handle frozen at each step's time, the step the
     * paths are of (-1: none), and the seeds vsv_flow_add gave */
    vsv_traj *tr;
    int sl_step;
    flow_seed *extra;
    int nextra;
};

/* Parses "LAT,LON,HEIGHT" (HEIGHT with an optional trailing m) at s into p;
 * *end just after it. 0 or -1. */
static int parse_point(const char *s, double p[3], const char **end)
{
    char *e = NULL;
    for (int k = 0; k < 3; k++) {
        p[k] = strtod(s, &e);
        if (e == s || !isfinite(p[k]))
            return -1;
        if (k < 2 && *e != ',')
            return -1;
        s = k < 2 ? e + 1 : e;
    }
    if (*e == 'm')
        e++;
    *end = e;
    return fabs(p[0]) <= 90 && fabs(p[1]) <= 360 ? 0 : -1;
}

/* An optional ":COLOUR" at s (end of the argument): 0 or -1. */
static int parse_colour(const char *s, float rgb[3], int *given)
{
    *given = 0;
    if (!*s)
        return 0;
    *given = 1;
    return *s == ':' && !vsv_colour_parse(s + 1, rgb) ? 0 : -1;
}

/* "HEIGHT:EVERY[...]" at s: the height (metres, trailing m allowed), the
 * spacing (a positive integer; optional when need_every is 0), *end after
 * them. 0 or -1. */
static int parse_plane(const char *s, int need_every, double *z, int *every, const char **end)
{
    char *e = NULL;
    *z = strtod(s, &e);
    if (e == s || !isfinite(*z))
        return -1;
    if (*e == 'm')
        e++;
    if (*e != ':') {
        *end = e;
        return need_every ? -1 : 0;
    }
    const char *q = e + 1;
    const long k = strtol(q, &e, 10);
    if (e == q || k < 1 || k > 100000)
        return -1;
    *every = (int)k;
    *end = e;
    return 0;
}

/* Checks one option's argument (the syntax: what vsv_flow_open reads). */
static int check(const char *opt, const char *arg)
{
    double p[3], q[3], z;
    float rgb[3];
    int every = 0, given;
    const char *e = arg;
    char *x = NULL;
    if (!strcmp(opt, "trajectory"))
        return parse_point(arg, p, &e) || parse_colour(e, rgb, &given);
    if (!strcmp(opt, "seed-line")) {
        if (parse_point(arg, p, &e) || *e != ':' || parse_point(e + 1, q, &e) || *e != ':')
            return -1;
        const long n = strtol(e + 1, &x, 10);
        return x == e + 1 || n < 2 || n > 10000 || parse_colour(x, rgb, &given);
    }
    if (!strcmp(opt, "seed-slice"))
        return parse_plane(arg, 1, &z, &every, &e) || parse_colour(e, rgb, &given);
    if (!strcmp(opt, "barbs"))
        return parse_plane(arg, 0, &z, &every, &e) || *e;
    return -1;
}

int vsv_flow_opt(vsv_flow_opts *o, const char *opt, const char *arg, char *msg, size_t cap)
{
    const char *why = NULL;
    int64_t d = 0;
    if (!strcmp(opt, "streamlines")) {
        o->steady = 1;
        return 0;
    }
    if (!strcmp(opt, "traj-from")) {
        vsv_timesel sel;
        char w[256];
        if (vsv_timesel_parse(arg, NULL, 0, VSV_TIMESEL_ONE, &sel, w, sizeof w)) {
            snprintf(msg, cap, "--traj-from %s: %s", arg, w);
            return VSV_EINVAL;
        }
        o->from = arg;
        return 0;
    } else if (!strcmp(opt, "traj-for")) {
        if (vsv_duration_parse(arg, &d))
            why = vsv_duration_why(arg);
        else
            o->dur = d;
    } else if (!strcmp(opt, "tube-radius")) {
        char *e = NULL;
        o->radius = strtod(arg, &e);
        if (e == arg || *e || !(o->radius > 0) || !isfinite(o->radius))
            why = "a radius in metres, more than 0";
    } else if (check(opt, arg)) {
        why = !strcmp(opt, "trajectory")   ? "expected LAT,LON,HEIGHT[:COLOUR] (degrees, metres)"
              : !strcmp(opt, "seed-line")  ? "expected LAT,LON,HEIGHT:LAT,LON,HEIGHT:N[:COLOUR] (N from 2)"
              : !strcmp(opt, "seed-slice") ? "expected HEIGHT:EVERY[:COLOUR] (metres, columns)"
                                           : "expected HEIGHT[:EVERY] (metres, columns)";
    } else {
        const char **slot = NULL;
        int *n = NULL, max = 8;
        if (!strcmp(opt, "trajectory"))
            slot = o->traj, n = &o->ntraj, max = VSV_FLOW_MAX;
        else if (!strcmp(opt, "seed-line"))
            slot = o->line, n = &o->nline;
        else if (!strcmp(opt, "seed-slice"))
            slot = o->slice, n = &o->nslice;
        else
            slot = o->barbs, n = &o->nbarbs;
        if (*n >= max) {
            snprintf(msg, cap, "--%s %s: at most %d", opt, arg, max);
            return VSV_EINVAL;
        }
        slot[(*n)++] = arg;
    }
    if (why) {
        snprintf(msg, cap, "--%s %s: %s", opt, arg, why);
        return VSV_EINVAL;
    }
    return 0;
}

int vsv_flow_any(const vsv_flow_opts *o) { return o->ntraj || o->nline || o->nslice || o->nbarbs; }

void vsv_flow_free(vsv_flow *fl)
{
    if (!fl)
        return;
    for (int i = 0; i < fl->npaths; i++)
        vsv_traj_path_clear(&fl->paths[i].p);
    free(fl->paths);
    free(fl->lines);
    free(fl->xyz);
    free(fl->off);
    vsv_volume_free(fl->ve);
    vsv_volume_free(fl->vn);
    vsv_decoder_free(fl->d);
    vsv_traj_free(fl->tr);
    free(fl->extra);
    free(fl);
}

int vsv_flow_paths(const vsv_flow *fl) { return fl->npaths; }

/* The path of the air at projected (x, y), height z, from `from` to `to`,
 * added in colour rgb. 0; VSV_EINVAL (the seed outside the grid or under
 * the ground) with strict set, else skipped; or an error of vsv_traj_run. */
static int add_path(vsv_flow *fl, vsv_traj *tr, const double seed[3], double from, double to, const float rgb[3],
                    int strict)
{
    if (fl->npaths == fl->pcap) {
        const int cap = fl->pcap ? 2 * fl->pcap : 16;
        flow_path *p = realloc(fl->paths, (size_t)cap * sizeof *p);
        if (!p)
            return VSV_ENOMEM;
        fl->paths = p, fl->pcap = cap;
    }
    flow_path *P = &fl->paths[fl->npaths];
    memset(P, 0, sizeof *P);
    const int rc = vsv_traj_run(tr, seed, from, to, VSV_FLOW_EVERY, &P->p);
    if (rc) {
        vsv_traj_path_clear(&P->p);
        return rc == VSV_EINVAL && !strict ? 0 : rc;
    }
    memcpy(P->rgb, rgb, sizeof P->rgb);
    fl->npaths++;
    return 0;
}

/* Every seed of fl's options integrated from `from` to `to`. */
static int seed_all(vsv_flow *fl, vsv_traj *tr, double from, double to, char *msg, size_t cap)
{
    const vsv_meta *m = fl->m;
    const vsv_flow_opts *o = &fl->o;
    int col = 0, given, rc = 0;
    for (int i = 0; i < o->ntraj + o->nline + o->nslice && !rc; i++) {
        float rgb[3];
        vsv_colour_parse(palette[col++ % 8], rgb);
        double p[3], q[3], s[3];
        const char *e = "";
        char *x = NULL;
        if (i < o->ntraj) { /* one seed */
            parse_point(o->traj[i], p, &e);
            parse_colour(e, rgb, &given);
            if (vsv_proj_forward(&m->proj, p[0], p[1], &s[0], &s[1])) {
                snprintf(msg, cap, "--trajectory %s: not in the grid's projection", o->traj[i]);
                return VSV_EINVAL;
            }
            s[2] = p[2];
            if ((rc = add_path(fl, tr, s, from, to, rgb, 1)) == VSV_EINVAL)
                snprintf(msg, cap, "--trajectory %s: outside the grid, under the ground or outside its times",
                         o->traj[i]);
        } else { /* n seeds along a line, or one every k-th column (vsv_traj_seed_*) */
            const int line = i < o->ntraj + o->nline;
            const char *a = line ? o->line[i - o->ntraj] : o->slice[i - o->ntraj - o->nline];
            double z;
            int every = 1;
            long n = 0;
            if (line) {
                parse_point(a, p, &e);
                parse_point(e + 1, q, &e);
                n = strtol(e + 1, &x, 10);
                e = x;
            } else {
                parse_plane(a, 1, &z, &every, &e);
                n = vsv_traj_seed_plane(m, (int64_t)from, z, every, NULL, 0);
            }
            parse_colour(e, rgb, &given);
            double *seeds = n > 0 ? malloc((size_t)n * 3 * sizeof *seeds) : NULL;
            if (n > 0 && !seeds)
                return VSV_ENOMEM;
            const int got = !line ? vsv_traj_seed_plane(m, (int64_t)from, z, every, seeds, (int)n)
                            : vsv_traj_seed_line(m, p, q, (int)n, seeds) ? -1
                                                                         : (int)n;
            if (got < 0) {
                free(seeds);
                snprintf(msg, cap, "--seed-line %s: not in the grid's projection", a);
                return VSV_EINVAL;
            }
            for (int k = 0; k < got && !rc; k++)
                rc = add_path(fl, tr, seeds + 3 * k, from, to, rgb, 0);
            free(seeds);
        }
    }
    if (rc && rc != VSV_EINVAL)
        snprintf(msg, cap, "%s", vsv_traj_error(tr));
    return rc;
}

/* Streamlines of step's wind from every seed (once per step). */
static int streamlines(vsv_flow *fl, int step, char *msg, size_t cap)
{
    if (step == fl->sl_step)
        return 0;
    for (int i = 0; i < fl->npaths; i++)
        vsv_traj_path_clear(&fl->paths[i].p);
    fl->npaths = 0, fl->sl_step = -1;
    const double T = (double)vsv_file_time(fl->f, step);
    const double to = T + (double)(fl->o.dur > 0 ? fl->o.dur : VSV_FLOW_STREAM);
    int rc = fl->tr ? 0 : vsv_traj_create(fl->f, &fl->tr);
    if (!rc)
        rc = vsv_traj_freeze(fl->tr, T);
    if (!rc)
        rc = seed_all(fl, fl->tr, T, to, msg, cap);
    for (int k = 0; k < fl->nextra && !rc; k++)
        rc = add_path(fl, fl->tr, fl->extra[k].s, T, to, fl->extra[k].rgb, 0);
    if (rc && !msg[0])
        snprintf(msg, cap, "%s", fl->tr ? vsv_traj_error(fl->tr) : vsv_strerror(rc));
    fl->sl_step = rc ? -1 : step;
    return rc;
}

/* vsv_flow_add with --streamlines: the seed kept, traced from the next
 * frame on (here once, to check it). */
static int add_steady(vsv_flow *fl, const double seed[3], int step, char *msg, size_t cap)
{
    flow_seed *e = realloc(fl->extra, (size_t)(fl->nextra + 1) * sizeof *e);
    if (!e) {
        snprintf(msg, cap, "out of memory");
        return VSV_ENOMEM;
    }
    fl->extra = e;
    flow_seed *k = &e[fl->nextra];
    memcpy(k->s, seed, sizeof k->s);
    vsv_colour_parse(palette[(fl->o.ntraj + fl->o.nline + fl->o.nslice + fl->nextra) % 8], k->rgb);
    int rc = fl->tr ? 0 : vsv_traj_create(fl->f, &fl->tr);
    const double T = (double)vsv_file_time(fl->f, step);
    if (!rc && !(rc = vsv_traj_freeze(fl->tr, T)))
        rc = add_path(fl, fl->tr, seed, T, T + 1, k->rgb, 1);
    if (rc) {
        snprintf(msg, cap, "%s", rc == VSV_EINVAL ? "outside the grid or under the ground" : vsv_strerror(rc));
        return rc;
    }
    fl->nextra++;
    fl->sl_step = -1; /* traced again, whole, with the others */
    return 0;
}

int vsv_flow_add(vsv_flow *fl, const double seed[3], int step, char *msg, size_t cap)
{
    vsv_file_info info;
    vsv_file_info_get(fl->f, &info);
    if (step < 0 || step >= info.nsteps) {
        snprintf(msg, cap, "no step %d", step);
        return VSV_EINVAL;
    }
    if (fl->o.steady)
        return add_steady(fl, seed, step, msg, cap);
    const double from = (double)vsv_file_time(fl->f, step), last = (double)vsv_file_time(fl->f, info.nsteps - 1);
    const double to = fl->o.dur > 0 && from + (double)fl->o.dur < last ? from + (double)fl->o.dur : last;
    float rgb[3];
    vsv_colour_parse(palette[fl->npaths % 8], rgb);
    vsv_traj *tr = NULL;
    int rc = vsv_traj_create(fl->f, &tr);
    if (!rc && !(to > from))
        rc = VSV_EINVAL;
    if (!rc)
        rc = add_path(fl, tr, seed, from, to, rgb, 1);
    if (rc)
        snprintf(msg, cap, "%s",
                 rc == VSV_EINVAL ? "outside the grid, under the ground or at the last step"
                 : tr             ? vsv_traj_error(tr)
                                  : vsv_strerror(rc));
    vsv_traj_free(tr);
    return rc;
}

int vsv_flow_open(vsv_file *f, const vsv_flow_opts *o, vsv_flow **out, char *msg, size_t cap)
{
    vsv_flow *fl = *out = calloc(1, sizeof *fl);
    if (!fl) {
        snprintf(msg, cap, "out of memory");
        return VSV_ENOMEM;
    }
    fl->f = f, fl->m = vsv_file_meta(f), fl->o = *o, fl->barb_step = -1, fl->sl_step = -1;
    const vsv_meta *m = fl->m;
    if (vsv_meta_vector(m, VSV_WIND, fl->wind)) {
        snprintf(msg, cap, "no wind stored");
        return VSV_ENOTFOUND;
    }
    vsv_scene_units(m, &fl->ux, &fl->uy);
    const double wx = m->nx * m->spacing[0] * fl->ux, wy = m->ny * m->spacing[1] * fl->uy;
    fl->radius = o->radius > 0 ? o->radius : fmax(wx, wy) / 300;
    if (fl->radius > fmax(wx, wy) / 10) { /* (tubes that bury the domain show nothing of it) */
        snprintf(msg, cap, "--tube-radius %g: more than a tenth of the domain's larger side (%.0f m)", fl->radius,
                 fmax(wx, wy));
        return VSV_EINVAL;
    }
    if (!o->ntraj && !o->nline && !o->nslice)
        return 0;
    msg[0] = 0;
    if (o->steady) /* the first step's, to check the seeds */
        return streamlines(fl, 0, msg, cap);
    vsv_file_info info;
    vsv_file_info_get(f, &info);
    int64_t *times = malloc((size_t)info.nsteps * sizeof *times);
    if (!times) {
        snprintf(msg, cap, "out of memory");
        return VSV_ENOMEM;
    }
    for (int t = 0; t < info.nsteps; t++)
        times[t] = vsv_file_time(f, t);
    int first = 0, rc = 0;
    if (o->from) {
        vsv_timesel sel;
        char why[512];
        rc = vsv_timesel_parse(o->from, times, info.nsteps, VSV_TIMESEL_ONE | VSV_TIMESEL_CAL(vsv_meta_calendar(m)),
                               &sel, why, sizeof why);
        if (rc)
            snprintf(msg, cap, "--traj-from %s", why);
        first = sel.first;
    }
    const double from = (double)times[first], last = (double)times[info.nsteps - 1];
    const double to = o->dur > 0 && from + (double)o->dur < last ? from + (double)o->dur : last;
    free(times);
    if (rc)
        return VSV_EINVAL;
    vsv_traj *tr = NULL;
    if ((rc = vsv_traj_create(f, &tr))) {
        snprintf(msg, cap, "%s", rc == VSV_ENOTFOUND ? "no wind stored" : vsv_strerror(rc));
        return rc;
    }
    rc = to > from ? seed_all(fl, tr, from, to, msg, cap) : 0;
    vsv_traj_free(tr);
    return rc;
}

/* Room for n more lines of k more points. */
static int room(vsv_flow *fl, int nl, size_t nx, int n, size_t k)
{
    if (nl + n > fl->lcap) {
        const int c = 2 * (nl + n);
        vsv_scene_line *l = realloc(fl->lines, (size_t)c * sizeof *l);
        if (l)
            fl->lines = l;
        size_t *o = l ? realloc(fl->off, (size_t)c * sizeof *o) : NULL;
        if (!o)
            return VSV_ENOMEM;
        fl->off = o, fl->lcap = c;
    }
    if (nx + 3 * k > fl->xcap) {
        const size_t c = 2 * (nx + 3 * k);
        double *x = realloc(fl->xyz, c * sizeof *x);
        if (!x)
            return VSV_ENOMEM;
        fl->xyz = x, fl->xcap = c;
    }
    return 0;
}

/* Ends the line of k points at x (none for fewer than two). */
static void end_line(vsv_flow *fl, const flow_path *P, int *nl, size_t *nx, int k)
{
    if (k < 2)
        return;
    fl->off[*nl] = *nx;
    fl->lines[(*nl)++] = (vsv_scene_line){NULL, k, fl->radius, 1, {P->rgb[0], P->rgb[1], P->rgb[2]}};
    *nx += 3 * (size_t)k;
}

/* Path P up to time T as a line (none before it starts or when it has one
 * point by then); on a grid round the globe, a line a lap, broken where the
 * path crosses the map's edge (the points' longitudes are within one turn). */
static int path_line(vsv_flow *fl, const flow_path *P, double T, int *nl, size_t *nx)
{
    const vsv_traj_path *p = &P->p;
    if (p->n < 2 || p->pts[0].t > T)
        return 0;
    if (room(fl, *nl, *nx, p->n, (size_t)p->n + 2))
        return VSV_ENOMEM;
    const int wrap = vsv_meta_periodic_x(fl->m);
    int k = 0;
    for (int i = 0; i < p->n; i++) {
        const vsv_traj_point *a = &p->pts[i];
        const vsv_traj_point *b = i ? &p->pts[i - 1] : a;
        const int at = a->t <= T;
        if (wrap && i && fabs(a->x - b->x) > 180) { /* the map's edge: this lap's line ends */
            end_line(fl, P, nl, nx, k);
            k = 0;
        }
        double *x = fl->xyz + *nx + 3 * (size_t)k;
        if (at) {
            x[0] = a->x * fl->ux, x[1] = a->y * fl->uy, x[2] = a->z;
        } else { /* the point at T, between b and a (on b's side of the edge) */
            const double f = (T - b->t) / (a->t - b->t), dx = wrap ? remainder(a->x - b->x, 360) : a->x - b->x;
            x[0] = (b->x + f * dx) * fl->ux, x[1] = (b->y + f * (a->y - b->y)) * fl->uy;
            x[2] = b->z + f * (a->z - b->z);
            if (k == 0) { /* (it starts a line after the edge: b first) */
                x[3] = x[0], x[4] = x[1], x[5] = x[2];
                x[0] = b->x * fl->ux, x[1] = b->y * fl->uy, x[2] = b->z;
                k++;
            }
        }
        k++;
        if (!at)
            break;
    }
    end_line(fl, P, nl, nx, k);
    return 0;
}

/* The wind arrows of every --barbs plane at step; VSV_ERANGE (msg says
 * which) when a plane has none, the others drawn. */
static int barb_lines(vsv_flow *fl, int step, int *nl, size_t *nx, char *msg, size_t cap)
{
    const vsv_meta *m = fl->m;
    if (!fl->d &&
        (vsv_decoder_create(fl->f, &fl->d) || vsv_volume_create(fl->f, &fl->ve) || vsv_volume_create(fl->f, &fl->vn))) {
        snprintf(msg, cap, "out of memory");
        return VSV_ENOMEM;
    }
    if (step != fl->barb_step &&
        (vsv_volume_load(fl->ve, fl->d, step, fl->wind[0]) || vsv_volume_load(fl->vn, fl->d, step, fl->wind[1]))) {
        fl->barb_step = -1;
        snprintf(msg, cap, "%s", vsv_decoder_error(fl->d));
        return VSV_EIO;
    }
    fl->barb_step = step;
    const vsv_meta placed = vsv_meta_placed(m, vsv_file_time(fl->f, step));
    const float white[3] = {0.92f, 0.92f, 0.92f};
    int empty = 0;
    for (int b = 0; b < fl->o.nbarbs; b++) {
        double z;
        int every = 0, na = 0;
        const char *e = "";
        parse_plane(fl->o.barbs[b], 0, &z, &every, &e);
        if (!every) /* about 24 arrows across the larger side */
            every = (m->nx > m->ny ? m->nx : m->ny) / 24 > 1 ? (m->nx > m->ny ? m->nx : m->ny) / 24 : 1;
        const int most = ((m->nx + every - 1) / every) * ((m->ny + every - 1) / every);
        if (room(fl, *nl, *nx, most, 2 * (size_t)most))
            return VSV_ENOMEM;
        /* VSV_FLOW_BARB m/s spans the arrows' spacing */
        const double spacing = every * fmax(m->spacing[0] * fl->ux, m->spacing[1] * fl->uy);
        double top;
        if (vsv_wind_arrows(&placed, fl->ve, fl->vn, z, every, spacing / VSV_FLOW_BARB, fl->xyz + *nx, most, &na,
                            &top)) {
            snprintf(msg, cap, "--barbs %s: the wind cannot be drawn there", fl->o.barbs[b]);
            return VSV_EINVAL;
        }
        if (!na && !empty) /* (the other planes still drawn) */
            snprintf(msg, cap,
                     "--barbs %s: no column drawn has air at that height (above the grid's top or under the ground)",
                     fl->o.barbs[b]);
        empty |= !na;
        for (int a = 0; a < na; a++) {
            fl->off[*nl] = *nx + 6 * (size_t)a;
            fl->lines[(*nl)++] = (vsv_scene_line){NULL, 2, fl->radius * 0.6, 1, {white[0], white[1], white[2]}};
        }
        *nx += 6 * (size_t)na;
    }
    return empty ? VSV_ERANGE : 0;
}

int vsv_flow_frame(vsv_flow *fl, int step, int trajectories, int barbs, const vsv_scene_line **lines, int *n, char *msg,
                   size_t cap)
{
    int nl = 0, rc = 0;
    size_t nx = 0;
    msg[0] = 0;
    if (trajectories && fl->o.steady) /* drawn whole */
        rc = streamlines(fl, step, msg, cap);
    const double T = fl->o.steady ? INFINITY : (double)vsv_file_time(fl->f, step);
    for (int i = 0; trajectories && i < fl->npaths && !rc; i++)
        if ((rc = path_line(fl, &fl->paths[i], T, &nl, &nx)))
            snprintf(msg, cap, "out of memory");
    if (!rc && barbs && fl->o.nbarbs)
        rc = barb_lines(fl, step, &nl, &nx, msg, cap);
    for (int i = 0; i < nl; i++) /* the points are in place: the lines' pointers */
        fl->lines[i].xyz = fl->xyz + fl->off[i];
    *lines = fl->lines;
    *n = rc && rc != VSV_ERANGE ? 0 : nl;
    return rc;
}
