/* vsv_traj.c — trajectories through a .vsv's wind (vsv_traj.h): the air
 * moved in the grid's projected x, y and in height by classic RK4.
 *
 * The wind: the vector species "wind" (vsv_vector.h), earth-relative m/s
 * (a wind stored without its upward component moves the air level),
 * turned into projected units a second by the inverse of the projection's
 * local Jacobian (vsv_proj_jacobian) at the point; the upward wind moves
 * the height in metres. On levels that are not heights (a layer index,
 * pressure levels) there is no metre axis: the upward wind is reported but
 * not used, and the air keeps its level. In space the wind is trilinear
 * between cell centres: bilinear across the four columns around the point,
 * each sampled linearly between its own levels at the point's height (the
 * columns' own heights where native levels have them, vsv_meta_level_of);
 * cells with no data (below the ground) drop out of the blend and the rest
 * are renormalised. In time it is linear between the two steps around t.
 * A moving grid is placed per step (vsv_meta_placed).
 *
 * The step rule: dt = 0.5 / max(|vx| / dx, |vy| / dy, |w| / dz) from the
 * wind at the step's start (Courant number 0.5 on the horizontal cells and
 * the local layer), at least 1 s, and never past the next file step (the
 * wind's time derivative jumps there), the next recorded point or the end.
 * Where a stage or the step's end leaves the grid (its sides, the ground,
 * the top, the wind's data), the step is halved until a straight step with
 * the starting wind would leave too; then the crossing along that straight
 * step is found by bisection and the path ends there. */
#include "vsv_format_internal.h"
#include "vsv_traj.h"

#include <math.h>
#include <stdlib.h>

#define TRAJ_COURANT 0.5
#define TRAJ_MIN_DT 1.0
/* Decoded wind kept per handle: as many steps as fit (at least the two a
 * moment needs), so paths run one after another over the same hours decode
 * each brick once. */
#define TRAJ_CACHE_BYTES ((size_t)256 << 20)

/* The decoded bricks of one step, decoded when first touched. */
typedef struct traj_slot {
    int step;           /* -1: none */
    unsigned gen;       /* bricks decoded for this step carry it */
    unsigned long used; /* when it was last used (the least recently used is reused) */
    float **brick[3];   /* per component, nbricks buffers (allocated on first use) */
    unsigned *stamp[3]; /* the gen each brick was decoded at */
} traj_slot;

struct vsv_traj {
    vsv_file *f;
    const vsv_meta *m;
    vsv_decoder *d;
    int idx[3], nsteps, brick, shift, bdim[3], nbricks;
    int vertical;  /* 1: levels are heights (metres), the upward wind moves them */
    double frozen; /* the time of the frozen wind (streamlines), or NAN */
    double *times;
    traj_slot *slot;
    int nslots;
    unsigned long tick;
    char err[512];
};

/* The wind at a point and time: where it moves the point, and how fast. */
typedef struct traj_eval {
    double vel[3];  /* projected units a second in x, y; the height's unit a second */
    float wind[3];  /* east, north, up, m/s */
    double cell[3]; /* the local cell: dx, dy (projected units), dz (height unit) */
} traj_eval;

int vsv_traj_create(vsv_file *f, vsv_traj **out)
{
    vsv_traj *t = *out = calloc(1, sizeof *t);
    if (!t)
        return VSV_ENOMEM;
    const vsv_meta *m = t->m = vsv_file_meta(f);
    t->f = f;
    t->frozen = NAN;
    if (vsv_meta_vector(m, VSV_WIND, t->idx)) {
        vsv_msg(t->err, sizeof t->err, "no wind stored (the vector species \"%s\")", VSV_WIND);
        return VSV_ENOTFOUND;
    }
    vsv_file_info info;
    vsv_file_info_get(f, &info);
    t->nsteps = info.nsteps;
    t->brick = info.brick;
    while ((1 << t->shift) < t->brick)
        t->shift++;
    for (int a = 0; a < 3; a++)
        t->bdim[a] = info.bricks[a];
    t->nbricks = info.nbricks;
    t->vertical = m->vert_kind == VSV_VERT_EVEN || m->vert_kind == VSV_VERT_NATIVE;
    int rc = (t->times = malloc((size_t)(t->nsteps > 0 ? t->nsteps : 1) * sizeof *t->times)) ? 0 : VSV_ENOMEM;
    for (int s = 0; !rc && s < t->nsteps; s++)
        t->times[s] = (double)vsv_file_time(f, s);
    const size_t volume = (size_t)3 * t->nbricks * t->brick * t->brick * t->brick * sizeof(float);
    const size_t fit = TRAJ_CACHE_BYTES / (volume ? volume : 1);
    t->nslots = fit < 2 ? 2 : fit > (size_t)t->nsteps ? (t->nsteps > 2 ? t->nsteps : 2) : (int)fit;
    if (!rc && !(t->slot = calloc((size_t)t->nslots, sizeof *t->slot)))
        rc = VSV_ENOMEM;
    for (int s = 0; s < t->nslots && !rc; s++) {
        t->slot[s].step = -1;
        for (int c = 0; c < 3 && !rc; c++)
            if (!(t->slot[s].brick[c] = calloc((size_t)t->nbricks, sizeof(float *))) ||
                !(t->slot[s].stamp[c] = calloc((size_t)t->nbricks, sizeof(unsigned))))
                rc = VSV_ENOMEM;
    }
    if (!rc)
        rc = vsv_decoder_create(f, &t->d);
    if (rc)
        vsv_msg(t->err, sizeof t->err, "%s", vsv_strerror(rc));
    return rc;
}

void vsv_traj_free(vsv_traj *t)
{
    if (!t)
        return;
    for (int s = 0; t->slot && s < t->nslots; s++)
        for (int c = 0; c < 3; c++) {
            for (int b = 0; t->slot[s].brick[c] && b < t->nbricks; b++)
                free(t->slot[s].brick[c][b]);
            free(t->slot[s].brick[c]);
            free(t->slot[s].stamp[c]);
        }
    vsv_decoder_free(t->d);
    free(t->slot);
    free(t->times);
    free(t);
}

const char *vsv_traj_error(const vsv_traj *t) { return t ? t->err : "out of memory"; }

void vsv_traj_path_clear(vsv_traj_path *p)
{
    if (!p)
        return;
    free(p->pts);
    p->pts = NULL;
    p->n = 0;
    p->end = VSV_TRAJ_END_TIME;
}

/* The slot holding step's bricks (the least recently used is reused). */
static traj_slot *slot_for(vsv_traj *t, int step)
{
    int s = 0;
    for (int i = 0; i < t->nslots; i++) {
        if (t->slot[i].step == step) {
            s = i;
            break;
        }
        if (t->slot[i].used < t->slot[s].used)
            s = i;
    }
    traj_slot *sl = &t->slot[s];
    if (sl->step != step) {
        sl->step = step;
        sl->gen++;
    }
    sl->used = ++t->tick;
    return sl;
}

/* The decoded value of component c at cell (i, j, k) of sl's step. */
static int cell_value(vsv_traj *t, traj_slot *sl, int c, int i, int j, int k, float *v)
{
    if (t->idx[c] < 0) { /* a wind without its upward component: none */
        *v = 0;
        return 0;
    }
    const int sh = t->shift, msk = t->brick - 1;
    const int b = (i >> sh) + t->bdim[0] * ((j >> sh) + t->bdim[1] * (k >> sh));
    if (sl->stamp[c][b] != sl->gen) {
        const size_t n = (size_t)t->brick * t->brick * t->brick;
        if (!sl->brick[c][b] && !(sl->brick[c][b] = malloc(n * sizeof(float)))) {
            vsv_msg(t->err, sizeof t->err, "%s", vsv_strerror(VSV_ENOMEM));
            return VSV_ENOMEM;
        }
        int rc = vsv_decoder_brick(t->d, sl->step, t->idx[c], b, sl->brick[c][b]);
        if (rc) {
            vsv_msg(t->err, sizeof t->err, "%s", vsv_decoder_error(t->d));
            return rc;
        }
        sl->stamp[c][b] = sl->gen;
    }
    *v = sl->brick[c][b][(i & msk) + ((size_t)(j & msk) << sh) + ((size_t)(k & msk) << (2 * sh))];
    return 0;
}

/* Fractional column (fi, fj) of projected (x, y) on grid m (placed); 0, or
 * VSV_TRAJ_END_EDGE outside its cells. A longitude a turn away counts; on a
 * grid round the globe any number of turns, fi in [0, nx). */
static int column_of(const vsv_meta *m, double x, double y, double *fi, double *fj)
{
    *fi = (x - m->origin[0]) / m->spacing[0];
    *fj = (y - m->origin[1]) / m->spacing[1];
    if (vsv_meta_periodic_x(m) && isfinite(*fi)) {
        *fi = fmod(*fi, m->nx);
        *fi = *fi < 0 ? *fi + m->nx : *fi;
        *fi = *fi < m->nx ? *fi : 0;
        return *fj >= -0.5 && *fj <= m->ny - 0.5 ? 0 : VSV_TRAJ_END_EDGE;
    }
    for (int w = -1; m->proj.kind == VSV_PROJ_LATLON && w <= 1 && !(*fi >= -0.5 && *fi <= m->nx - 0.5); w += 2)
        *fi = (x + 360.0 * w - m->origin[0]) / m->spacing[0];
    return *fi >= -0.5 && *fi <= m->nx - 0.5 && *fj >= -0.5 && *fj <= m->ny - 0.5 ? 0 : VSV_TRAJ_END_EDGE;
}

/* The columns around fractional column fi of m: i0, i1 and the weight of
 * i1; clamped to the grid's edges, or round the globe (fi in [0, nx)). */
static void columns_around(const vsv_meta *m, double fi, int *i0, int *i1, double *w)
{
    const int wrap = vsv_meta_periodic_x(m);
    const double p = wrap ? fi : fmin(fmax(fi, 0), m->nx - 1);
    *i0 = (int)p;
    *i1 = wrap ? (*i0 + 1) % m->nx : *i0 + 1 < m->nx ? *i0 + 1 : *i0;
    *w = p - *i0;
}

/* The ground under (fi, fj) of placed grid m, bilinear in its terrain, or
 * -INFINITY where the grid's bottom is its ground (no terrain, heights
 * above the ground: 0, or levels that are not heights). */
static double ground_at(const vsv_meta *m, int vertical, double fi, double fj)
{
    if (!vertical)
        return -INFINITY;
    if (vsv_meta_above_ground(m))
        return 0;
    if (!m->terrain)
        return -INFINITY;
    const double q = fmin(fmax(fj, 0), m->ny - 1);
    int i0, i1;
    double a;
    columns_around(m, fi, &i0, &i1, &a);
    const int j0 = (int)q, j1 = j0 + 1 < m->ny ? j0 + 1 : j0;
    const double b = q - j0;
    const float *g = m->terrain;
    return (1 - b) * ((1 - a) * g[(size_t)j0 * m->nx + i0] + a * g[(size_t)j0 * m->nx + i1]) +
           b * ((1 - a) * g[(size_t)j1 * m->nx + i0] + a * g[(size_t)j1 * m->nx + i1]);
}

/* The wind of one step at projected (x, y) and height z: e[3] east, north,
 * up; dz the local layer. 0, a VSV_TRAJ_END_* code > 0 where the point is
 * not in the grid then, or a read error < 0. */
static int wind_of_step(vsv_traj *t, int step, const double pos[3], double e[3], double *dz)
{
    const int64_t when = (int64_t)t->times[step];
    const vsv_meta pm = vsv_meta_placed(t->m, when), *m = &pm;
    double fi, fj;
    if (column_of(m, pos[0], pos[1], &fi, &fj))
        return VSV_TRAJ_END_EDGE;
    const double ground = ground_at(m, t->vertical, fi, fj);
    if (pos[2] < ground)
        return VSV_TRAJ_END_GROUND;
    const double q = fmin(fmax(fj, 0), m->ny - 1);
    int ci[2];
    double wi;
    columns_around(m, fi, &ci[0], &ci[1], &wi);
    const int j0 = (int)q, cj[2] = {j0, j0 + 1 < m->ny ? j0 + 1 : j0};
    const double wj = q - j0;
    traj_slot *sl = slot_for(t, step);
    double sum[3] = {0, 0, 0}, wsum = 0, best = -1;
    for (int c = 0; c < 4; c++) {
        const int i = ci[c & 1], j = cj[c >> 1];
        const double wc = (c & 1 ? wi : 1 - wi) * (c >> 1 ? wj : 1 - wj);
        double kf = 0, range[2];
        const int out = vsv_meta_level_of(m, when, i, j, pos[2], &kf, range) != 0;
        if (out) /* beyond the column's end nearer the point (heights rise, pressures fall) */
            kf = fabs(pos[2] - vsv_meta_cell_height_at(m, when, i, j, 0)) <
                         fabs(pos[2] - vsv_meta_cell_height_at(m, when, i, j, m->nz - 1))
                     ? 0
                     : m->nz - 1;
        if (wc > best) { /* the nearest column decides leaving through the top or bottom, and the layer */
            best = wc;
            if (out && !t->vertical)
                return VSV_TRAJ_END_DATA; /* (a seed off the levels: the level never changes) */
            if (out && pos[2] > range[1])
                return VSV_TRAJ_END_TOP;
            if (out && ground == -INFINITY)
                return VSV_TRAJ_END_GROUND;
            const int kn = (int)fmin(fmax(lround(kf), 0), m->nz - 1), k2 = kn + 1 < m->nz ? kn + 1 : kn - 1;
            *dz = m->nz > 1
                      ? fabs(vsv_meta_cell_height_at(m, when, i, j, k2) - vsv_meta_cell_height_at(m, when, i, j, kn))
                      : fabs(m->spacing[2]);
        }
        if (wc == 0)
            continue;
        kf = fmin(fmax(kf, 0), m->nz - 1);
        const int k0 = (int)kf, k1 = k0 + 1 < m->nz ? k0 + 1 : k0;
        const double wk = kf - k0;
        for (int l = 0; l < 2; l++) {
            const double w = wc * (l ? wk : 1 - wk);
            float v[3];
            if (w == 0)
                continue;
            for (int a = 0; a < 3; a++) {
                int rc = cell_value(t, sl, a, i, j, l ? k1 : k0, &v[a]);
                if (rc)
                    return rc;
            }
            if (isnan(v[0]) || isnan(v[1]) || isnan(v[2]))
                continue; /* no data (below the ground): the others carry the blend */
            for (int a = 0; a < 3; a++)
                sum[a] += w * v[a];
            wsum += w;
        }
    }
    if (!(wsum > 1e-9))
        return VSV_TRAJ_END_DATA;
    for (int a = 0; a < 3; a++)
        e[a] = sum[a] / wsum;
    return 0;
}

/* The step before time `when`'s interval and the weight of the one after:
 * t->times[s] <= when <= t->times[s + 1]. */
static int bracket(const vsv_traj *t, double when, double *w)
{
    int lo = 0, hi = t->nsteps - 1;
    if (hi == 0) {
        *w = 0;
        return 0;
    }
    while (hi - lo > 1) {
        const int mid = (lo + hi) / 2;
        if (t->times[mid] <= when)
            lo = mid;
        else
            hi = mid;
    }
    *w = (when - t->times[lo]) / (t->times[hi] - t->times[lo]);
    return lo;
}

/* The wind at pos and time `when` into ev: 0, a VSV_TRAJ_END_* code > 0, or
 * a read error < 0. */
static int wind_at(vsv_traj *t, double when, const double pos[3], traj_eval *ev)
{
    if (!isnan(t->frozen))
        when = t->frozen;
    if (!(when >= t->times[0] && when <= t->times[t->nsteps - 1]))
        return VSV_TRAJ_END_DATA;
    if (!(isfinite(pos[0]) && isfinite(pos[1]) && isfinite(pos[2])))
        return VSV_TRAJ_END_EDGE;
    double w, e[3] = {0, 0, 0}, dz = 1;
    const int s = bracket(t, when, &w);
    for (int l = 0; l < 2; l++) {
        const double wl = l ? w : 1 - w;
        double el[3], dzl = 1;
        if (wl == 0)
            continue;
        int rc = wind_of_step(t, s + l, pos, el, &dzl);
        if (rc)
            return rc;
        for (int a = 0; a < 3; a++)
            e[a] += wl * el[a];
        dz = dzl;
    }
    double j[2][2];
    if (vsv_proj_jacobian(&t->m->proj, pos[0], pos[1], j))
        return VSV_TRAJ_END_EDGE;
    const double det = j[0][0] * j[1][1] - j[1][0] * j[0][1];
    if (!(fabs(det) > 0))
        return VSV_TRAJ_END_EDGE;
    /* (east, north) = vx j[0] + vy j[1]: solved for (vx, vy) */
    ev->vel[0] = (j[1][1] * e[0] - j[1][0] * e[1]) / det;
    ev->vel[1] = (-j[0][1] * e[0] + j[0][0] * e[1]) / det;
    ev->vel[2] = t->vertical ? e[2] : 0;
    for (int a = 0; a < 3; a++)
        ev->wind[a] = (float)e[a];
    ev->cell[0] = fabs(t->m->spacing[0]);
    ev->cell[1] = fabs(t->m->spacing[1]);
    ev->cell[2] = dz > 0 ? dz : 1;
    return 0;
}

/* Appends a point (the path grows by doubling; *cap its room). */
static int push(vsv_traj *t, vsv_traj_path *p, int *cap, double when, const double pos[3], const traj_eval *ev)
{
    if (p->n == *cap) {
        const int nc = *cap ? 2 * *cap : 64;
        vsv_traj_point *np = nc > *cap ? realloc(p->pts, (size_t)nc * sizeof *np) : NULL;
        if (!np) {
            vsv_msg(t->err, sizeof t->err, "%s", vsv_strerror(VSV_ENOMEM));
            return VSV_ENOMEM;
        }
        p->pts = np;
        *cap = nc;
    }
    vsv_traj_point *q = &p->pts[p->n++];
    q->t = when;
    q->x = pos[0];
    if (vsv_meta_periodic_x(t->m)) { /* round the globe: from the grid's west edge, within one turn */
        const double west = t->m->origin[0] - t->m->spacing[0] / 2;
        q->x = west + fmod(pos[0] - west, 360.0);
        q->x = q->x < west ? q->x + 360 : q->x;
    }
    q->y = pos[1];
    q->z = pos[2];
    if (t->m->proj.kind == VSV_PROJ_NONE || vsv_proj_inverse(&t->m->proj, q->x, pos[1], &q->lat, &q->lon))
        q->lat = q->lon = NAN;
    q->east = ev->wind[0];
    q->north = ev->wind[1];
    q->up = ev->wind[2];
    return 0;
}

/* One RK4 step of dt (negative: backward) from pos at `when`, k1 the wind
 * there: the new position and its wind into np and ev1. 0, a
 * VSV_TRAJ_END_* code > 0 where a stage or the end is not in the grid, or
 * a read error < 0. */
static int rk4(vsv_traj *t, double when, const double pos[3], const traj_eval *k1, double dt, double np[3],
               traj_eval *ev1)
{
    traj_eval k2, k3, k4;
    double p[3];
    int rc;
    for (int a = 0; a < 3; a++)
        p[a] = pos[a] + dt / 2 * k1->vel[a];
    if ((rc = wind_at(t, when + dt / 2, p, &k2)))
        return rc;
    for (int a = 0; a < 3; a++)
        p[a] = pos[a] + dt / 2 * k2.vel[a];
    if ((rc = wind_at(t, when + dt / 2, p, &k3)))
        return rc;
    for (int a = 0; a < 3; a++)
        p[a] = pos[a] + dt * k3.vel[a];
    if ((rc = wind_at(t, when + dt, p, &k4)))
        return rc;
    for (int a = 0; a < 3; a++)
        np[a] = pos[a] + dt / 6 * (k1->vel[a] + 2 * k2.vel[a] + 2 * k3.vel[a] + k4.vel[a]);
    return wind_at(t, when + dt, np, ev1);
}

/* Where a straight step of dt with the wind k1 at pos leaves the grid: the
 * last point inside (bisection to a millionth of dt) into *tau, np and
 * ev1, and how it leaves; 0 when the straight step stays inside (a stage
 * of RK4 strayed: the caller shortens the step), a read error < 0. */
static int leave(vsv_traj *t, double when, const double pos[3], const traj_eval *k1, double dt, double *tau,
                 double np[3], traj_eval *ev1)
{
    double p[3], lo = 0, hi = dt;
    traj_eval ev;
    for (int a = 0; a < 3; a++)
        p[a] = pos[a] + dt * k1->vel[a];
    int code = wind_at(t, when + dt, p, &ev);
    if (code <= 0)
        return code;
    *ev1 = *k1;
    for (int a = 0; a < 3; a++)
        np[a] = pos[a];
    for (int it = 0; it < 20 * 3; it++) { /* 2^-60 of dt */
        const double mid = (lo + hi) / 2;
        for (int a = 0; a < 3; a++)
            p[a] = pos[a] + mid * k1->vel[a];
        const int c = wind_at(t, when + mid, p, &ev);
        if (c < 0)
            return c;
        if (c) {
            hi = mid;
            code = c;
            continue;
        }
        lo = mid;
        *ev1 = ev;
        for (int a = 0; a < 3; a++)
            np[a] = p[a];
    }
    *tau = lo;
    return code;
}

/* The file's next time after `when` going dir (+1, -1), or NAN at its end. */
static double next_time(const vsv_traj *t, double when, int dir)
{
    if (!isnan(t->frozen)) /* a streamline: no step ends its wind */
        return dir * INFINITY;
    double w;
    const int s = bracket(t, when, &w);
    if (dir > 0) {
        for (int k = s; k < t->nsteps; k++)
            if (t->times[k] > when)
                return t->times[k];
        return NAN;
    }
    for (int k = s + 1 < t->nsteps ? s + 1 : s; k >= 0; k--)
        if (t->times[k] < when)
            return t->times[k];
    return NAN;
}

/* The seed, checked: 0, or VSV_EINVAL saying why it cannot start there. */
static int check_seed(vsv_traj *t, const double seed[3], double from, double to, double every, traj_eval *ev)
{
    char when[40];
    if (!(isfinite(seed[0]) && isfinite(seed[1]) && isfinite(seed[2]) && isfinite(from) && !isnan(to) && every >= 0 &&
          isfinite(every))) {
        vsv_msg(t->err, sizeof t->err, "a seed, time or interval that is not a finite number");
        return VSV_EINVAL;
    }
    const int cal = vsv_meta_calendar(t->m);
    if (isnan(t->frozen) && !(t->nsteps > 0 && from >= t->times[0] && from <= t->times[t->nsteps - 1])) {
        char a[40], b[40];
        vsv_cal_format(cal, (int64_t)floor(from), when, sizeof when);
        vsv_cal_format(cal, t->nsteps ? vsv_file_time(t->f, 0) : 0, a, sizeof a);
        vsv_cal_format(cal, t->nsteps ? vsv_file_time(t->f, t->nsteps - 1) : 0, b, sizeof b);
        vsv_msg(t->err, sizeof t->err, "start %s is outside the file's times (%s to %s)", when, a, b);
        return VSV_EINVAL;
    }
    const int rc = wind_at(t, from, seed, ev);
    if (rc <= 0)
        return rc;
    static const char *const why[] = {"", "outside the grid", "below the ground", "above the grid's top",
                                      "where the wind has no data (or off the levels)"};
    vsv_cal_format(cal, (int64_t)floor(from), when, sizeof when);
    vsv_msg(t->err, sizeof t->err, "seed x %.9g, y %.9g, height %.9g is %s at %s", seed[0], seed[1], seed[2], why[rc],
            when);
    return VSV_EINVAL;
}

int vsv_traj_run(vsv_traj *t, const double seed[3], double from, double to, double every, vsv_traj_path *out)
{
    vsv_traj_path_clear(out);
    traj_eval ev, ev1;
    int rc = check_seed(t, seed, from, to, every, &ev), cap = 0, last_in = 1;
    if (rc || (rc = push(t, out, &cap, from, seed, &ev)))
        return rc;
    const int dir = to >= from ? 1 : -1;
    double when = from, pos[3] = {seed[0], seed[1], seed[2]}, np[3];
    double next_rec = every > 0 ? from + dir * every : NAN;
    out->end = VSV_TRAJ_END_TIME;
    while (when != to && out->end == VSV_TRAJ_END_TIME) {
        const double bound = next_time(t, when, dir);
        if (isnan(bound)) { /* the file's times ran out before `to` */
            out->end = VSV_TRAJ_END_DATA;
            break;
        }
        double rate = 0;
        for (int a = 0; a < 3; a++)
            rate = fmax(rate, fabs(ev.vel[a]) / ev.cell[a]);
        double dt = fmax(rate > 0 ? TRAJ_COURANT / rate : INFINITY, TRAJ_MIN_DT), land = NAN;
        const double stops[3] = {to, bound, next_rec};
        for (int s = 0; s < 3; s++)
            if (!isnan(stops[s]) && dir * (stops[s] - when) > 0 && dir * (stops[s] - when) <= dt)
                dt = dir * (stops[s] - when), land = stops[s];
        for (;;) {
            rc = rk4(t, when, pos, &ev, dir * dt, np, &ev1);
            if (rc <= 0)
                break;
            double tau = 0;
            const int code = leave(t, when, pos, &ev, dir * dt, &tau, np, &ev1);
            if (code < 0)
                return code;
            if (code > 0 || dt < 1e-3) { /* it leaves: the path ends at the crossing */
                out->end = code > 0 ? code : rc;
                land = when + (code > 0 ? tau : 0);
                if (code == 0)
                    np[0] = pos[0], np[1] = pos[1], np[2] = pos[2], ev1 = ev;
                rc = 0;
                break;
            }
            dt /= 2; /* a stage strayed where the path does not: a shorter step */
            land = NAN;
        }
        if (rc < 0)
            return rc;
        when = isnan(land) ? when + dir * dt : land;
        for (int a = 0; a < 3; a++)
            pos[a] = np[a];
        ev = ev1;
        last_in = 0;
        if (every == 0 || when == next_rec || when == to || out->end != VSV_TRAJ_END_TIME) {
            if ((rc = push(t, out, &cap, when, pos, &ev)))
                return rc;
            last_in = 1;
        }
        if (when == next_rec)
            next_rec += dir * every;
    }
    if (!last_in && (rc = push(t, out, &cap, when, pos, &ev)))
        return rc;
    return 0;
}

int vsv_traj_freeze(vsv_traj *t, double at)
{
    if (isnan(at) || (t->nsteps > 0 && at >= t->times[0] && at <= t->times[t->nsteps - 1])) {
        t->frozen = at;
        return 0;
    }
    vsv_msg(t->err, sizeof t->err, "a streamline's time outside the file's times");
    return VSV_EINVAL;
}

int vsv_traj_seed_line(const vsv_meta *m, const double a[3], const double b[3], int n, double *seeds)
{
    if (n < 1 ||
        !(isfinite(a[0]) && isfinite(a[1]) && isfinite(a[2]) && isfinite(b[0]) && isfinite(b[1]) && isfinite(b[2])))
        return VSV_EINVAL;
    if (m->proj.kind == VSV_PROJ_NONE)
        return VSV_EUNSUPPORTED;
    double pa[2], pb[2];
    int rc = vsv_proj_forward(&m->proj, a[0], a[1], &pa[0], &pa[1]);
    if (!rc)
        rc = vsv_proj_forward(&m->proj, b[0], b[1], &pb[0], &pb[1]);
    if (rc)
        return rc;
    if (m->proj.kind == VSV_PROJ_LATLON) /* the shorter way round */
        pb[0] = pa[0] + remainder(pb[0] - pa[0], 360.0);
    for (int i = 0; i < n; i++) {
        const double f = n > 1 ? (double)i / (n - 1) : 0;
        seeds[3 * i] = pa[0] + f * (pb[0] - pa[0]);
        seeds[3 * i + 1] = pa[1] + f * (pb[1] - pa[1]);
        seeds[3 * i + 2] = a[2] + f * (b[2] - a[2]);
    }
    return 0;
}

int vsv_traj_seed_plane(const vsv_meta *grid, int64_t time, double z, int every, double *seeds, int cap)
{
    if (every < 1 || !isfinite(z))
        return VSV_EINVAL;
    const vsv_meta pm = vsv_meta_placed(grid, time), *m = &pm;
    const int vertical = m->vert_kind == VSV_VERT_EVEN || m->vert_kind == VSV_VERT_NATIVE;
    int n = 0;
    for (int j = every / 2; j < m->ny; j += every)
        for (int i = every / 2; i < m->nx; i += every) {
            double kf, range[2];
            if (z < ground_at(m, vertical, i, j) || vsv_meta_level_of(m, time, i, j, z, &kf, range))
                continue;
            if (n < cap) {
                vsv_meta_cell_xy(m, i, j, &seeds[3 * n], &seeds[3 * n + 1]);
                seeds[3 * n + 2] = z;
            }
            n++;
        }
    return n;
}
