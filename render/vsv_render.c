/* vsv_render.c — the renderer behind vsv_render.h: a persistent thread pool
 * that hands out 16x16 tiles, the scene geometry (world box, terrain), the
 * cameras, and the raycaster. Each pixel depends only on the scene and its
 * own ray, so the thread count and the tile order cannot change a pixel. */
#include "vsv_render_internal.h"

#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define TILE 16
#define MAX_THREADS 64

struct vsv_renderer {
    vsv_render_opts o;
    int nthreads;
    pthread_t tid[MAX_THREADS];
    pthread_mutex_t mu;
    pthread_cond_t go, done;
    int generation, running, finished, quit;
    /* the job */
    const vsv_scene *sc;
    const vsv_camera *cam;
    float *rgba, *depth;
    vsv_geo g;
    int ntiles, tiles_x;
    /* the current job of the pool: items handed out one at a time */
    void (*job)(void *ctx, int item, int thread);
    void *job_ctx;
    int nitems, next_item;
    struct wslot {
        struct vsv_renderer *r;
        int index;
    } slot[MAX_THREADS];
    /* per-layer skip flags (allocated when the scene grows, not per frame) */
    unsigned char *skip;
    size_t skip_cap;
    /* the visible layers of this frame, as the raycaster reads them */
    vsv_rc_layer *act;
    int act_cap;
    vsv_rc_frame frame;
    /* the sampling copies, one per scene layer (vsv_rc_cells), and those
     * this frame rebuilds */
    struct rc_copy {
        const vsv_volume *vol;
        uint64_t gen;
        float *store; /* the bricks whose copy holds data, then the shared empty one */
        size_t store_cap;
        float *empty;
        const float **cells; /* per brick */
        int cells_cap;
    } *copy, **build;
    int copy_cap, nbuild;
    double copy_seconds; /* the last rebuild of sampling copies */
    int simd;              /* the CPU has AVX2 and FMA (and VSV_SIMD is not 0) */
    vsv_rc_kernel *kernel; /* sixteen rays at once, or NULL: one at a time */
    vsv_sw *sw;           /* shear-warp state, for VSV_RENDER_SHEARWARP */
    vsv_rays rays;        /* the camera's rays, for this frame */
    /* the ground per pixel, for ground_cam and ground_geo */
    vsv_ground *ground;
    size_t ground_cap;
    vsv_camera ground_cam;
    vsv_geo ground_geo;
    int ground_valid;
    vsv_native native;    /* native levels placed at their heights */
};

void vsv_render_opts_init(vsv_render_opts *o)
{
    memset(o, 0, sizeof *o);
    o->kind = VSV_RENDER_RAYCAST;
    o->step_cells = 0.5;
}

/* ------------------------------------------------------------- geometry */

void vsv_scene_geo(const vsv_scene *sc, vsv_geo *g)
{
    const vsv_meta *m = sc->meta;
    g->nx = m->nx;
    g->ny = m->ny;
    g->nz = m->nz;
    g->ox = m->origin[0];
    g->oy = m->origin[1];
    g->dx = m->spacing[0];
    g->dy = m->spacing[1];
    g->idx = 1 / g->dx;
    g->idy = 1 / g->dy;
    /* renderers draw every grid with evenly stacked levels (DESIGN.md §3) */
    if (m->vert_kind == VSV_VERT_EVEN) {
        g->oz = m->origin[2];
        g->dz = m->spacing[2];
    } else if (m->vert_kind == VSV_VERT_NATIVE && m->nheights) {
        /* per-column heights: the even axis the volumes are resampled onto */
        vsv_heights_axis(m, &g->nz, &g->oz, &g->dz);
    } else if (m->vert_kind == VSV_VERT_NATIVE && m->levels && m->nz > 1) {
        g->oz = m->levels[0];
        g->dz = (m->levels[m->nz - 1] - m->levels[0]) / (m->nz - 1);
    } else {
        g->oz = 250;
        g->dz = 500;
    }
    g->E = sc->exaggeration > 0 ? sc->exaggeration : 1;
    g->bmin[0] = g->ox - g->dx / 2;
    g->bmax[0] = g->ox + (g->nx - 0.5) * g->dx;
    g->bmin[1] = g->oy - g->dy / 2;
    g->bmax[1] = g->oy + (g->ny - 0.5) * g->dy;
    g->bmin[2] = (g->oz - g->dz / 2) * g->E;
    g->bmax[2] = (g->oz + (g->nz - 0.5) * g->dz) * g->E;
    g->terrain = sc->show_terrain && (m->vert_kind == VSV_VERT_EVEN || m->vert_kind == VSV_VERT_NATIVE) ? m->terrain : NULL;
    if (g->terrain) {
        /* the box reaches below the lowest ground, so rays meet the sea surface
         * inside it rather than on its face */
        float lowest = 0, highest = 0;
        for (size_t c = 0; c < (size_t)g->nx * g->ny; c++) {
            lowest = g->terrain[c] < lowest ? g->terrain[c] : lowest;
            highest = g->terrain[c] > highest ? g->terrain[c] : highest;
        }
        g->ground_top = highest * g->E;
        const double floor_z = (lowest - 10.0) * g->E;
        if (g->bmin[2] > floor_z)
            g->bmin[2] = floor_z;
    }
}

void vsv_scene_bounds(const vsv_scene *sc, double mn[3], double mx[3])
{
    vsv_geo g;
    vsv_scene_geo(sc, &g);
    memcpy(mn, g.bmin, sizeof g.bmin);
    memcpy(mx, g.bmax, sizeof g.bmax);
}

void vsv_camera_orbit(vsv_camera *cam, const vsv_scene *sc, double az, double el, double dist, int width, int height)
{
    double mn[3], mx[3], c[3];
    vsv_scene_bounds(sc, mn, mx);
    for (int a = 0; a < 3; a++)
        c[a] = 0.5 * (mn[a] + mx[a]);
    c[2] = mn[2] + 0.3 * (mx[2] - mn[2]);
    memset(cam, 0, sizeof *cam);
    cam->fov_deg = 35;
    cam->width = width;
    cam->height = height;
    if (!(dist > 0)) {
        const double r = 0.5 * sqrt((mx[0] - mn[0]) * (mx[0] - mn[0]) + (mx[1] - mn[1]) * (mx[1] - mn[1]) +
                                    (mx[2] - mn[2]) * (mx[2] - mn[2]));
        dist = 1.15 * r / tan(cam->fov_deg * M_PI / 360);
    }
    const double a = az * M_PI / 180, e = el * M_PI / 180;
    /* azimuth clockwise from north (+y); the camera sits at that bearing from the centre */
    const double off[3] = {sin(a) * cos(e), cos(a) * cos(e), sin(e)};
    for (int i = 0; i < 3; i++) {
        cam->pos[i] = c[i] + dist * off[i];
        cam->dir[i] = -off[i];
    }
    cam->up[0] = cam->up[1] = 0;
    cam->up[2] = 1;
    cam->znear = 0;
    cam->zfar = INFINITY;
}

static void normalize(double v[3])
{
    const double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (n > 0) {
        const double k = 1 / n;
        for (int i = 0; i < 3; i++)
            v[i] *= k;
    }
}

static void cross(const double a[3], const double b[3], double o[3])
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

void vsv_rays_init(vsv_rays *R, const vsv_camera *cam)
{
    double *f = R->f, *r = R->r, *u = R->u;
    for (int i = 0; i < 3; i++)
        f[i] = cam->dir[i];
    normalize(f);
    cross(f, cam->up, r);
    if (r[0] == 0 && r[1] == 0 && r[2] == 0) {
        const double alt[3] = {0, 1, 0};
        cross(f, alt, r);
    }
    normalize(r);
    cross(r, f, u);
    const double aspect = (double)cam->width / cam->height;
    for (int i = 0; i < 3; i++)
        R->o[i] = cam->pos[i] + cam->eye_offset * r[i];
    R->persp = cam->fov_deg > 0;
    const double t = R->persp ? tan(cam->fov_deg * M_PI / 360) : cam->ortho_height / 2;
    R->kx = t * aspect;
    R->ky = t;
    R->cx = R->cy = 0;
    if (R->persp && cam->window[0] != cam->window[1] && cam->window[2] != cam->window[3]) {
        R->kx = 0.5 * (cam->window[1] - cam->window[0]);
        R->cx = 0.5 * (cam->window[1] + cam->window[0]);
        R->ky = 0.5 * (cam->window[3] - cam->window[2]);
        R->cy = 0.5 * (cam->window[3] + cam->window[2]);
    }
    R->w = cam->width;
    R->h = cam->height;
    R->x0 = R->y0 = 0, R->x1 = cam->width - 1, R->y1 = cam->height - 1;
}

void vsv_rays_get(const vsv_rays *R, int px, int py, double o[3], double d[3])
{
    const double sx = R->cx + R->kx * (2 * (px + 0.5) / R->w - 1), sy = R->cy + R->ky * (1 - 2 * (py + 0.5) / R->h);
    if (R->persp) {
        for (int i = 0; i < 3; i++) {
            o[i] = R->o[i];
            d[i] = R->f[i] + sx * R->r[i] + sy * R->u[i];
        }
        normalize(d);
    } else {
        for (int i = 0; i < 3; i++) {
            o[i] = R->o[i] + sx * R->r[i] + sy * R->u[i];
            d[i] = R->f[i];
        }
    }
}

/* The pixels whose rays can meet the box [mn, mx]: the bounding rectangle
 * of its corners on the screen (a pixel of margin), or every pixel when a
 * corner is not in front of the eye. */
static void rays_cull(vsv_rays *R, const double mn[3], const double mx[3])
{
    R->x0 = 0, R->x1 = (int)R->w - 1, R->y0 = 0, R->y1 = (int)R->h - 1;
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int c = 0; c < 8; c++) {
        const double p[3] = {c & 1 ? mx[0] : mn[0], c & 2 ? mx[1] : mn[1], c & 4 ? mx[2] : mn[2]};
        double v[3], z = 0, s[2] = {0, 0};
        for (int i = 0; i < 3; i++) {
            v[i] = p[i] - R->o[i];
            z += v[i] * R->f[i];
            s[0] += v[i] * R->r[i];
            s[1] += v[i] * R->u[i];
        }
        if (R->persp) {
            if (!(z > 0))
                return;
            s[0] /= z, s[1] /= z;
        }
        /* the inverse of vsv_rays_get's screen position */
        const double px = ((s[0] - R->cx) / R->kx + 1) * R->w / 2 - 0.5, py = (1 - (s[1] - R->cy) / R->ky) * R->h / 2 - 0.5;
        lo[0] = fmin(lo[0], px), hi[0] = fmax(hi[0], px);
        lo[1] = fmin(lo[1], py), hi[1] = fmax(hi[1], py);
    }
    if (!(hi[0] >= lo[0] && hi[1] >= lo[1]))
        return;
    R->x0 = lo[0] - 1 > 0 ? (int)(lo[0] - 1) : 0;
    R->y0 = lo[1] - 1 > 0 ? (int)(lo[1] - 1) : 0;
    R->x1 = hi[0] + 1 < R->w - 1 ? (int)ceil(hi[0] + 1) : (int)R->w - 1;
    R->y1 = hi[1] + 1 < R->h - 1 ? (int)ceil(hi[1] + 1) : (int)R->h - 1;
}

/* Whether the ray of pixel (px, py) may meet the scene's box. */
static inline int rays_may_hit(const vsv_rays *R, int px, int py)
{
    return px >= R->x0 && px <= R->x1 && py >= R->y0 && py <= R->y1;
}

void vsv_pixel_ray(const vsv_camera *cam, int px, int py, double o[3], double d[3])
{
    vsv_rays R;
    vsv_rays_init(&R, cam);
    vsv_rays_get(&R, px, py, o, d);
}

/* Terrain height (exaggerated world z) at world (x, y): bilinear at cell centres. */
double vsv_geo_terrain(const vsv_geo *g, double x, double y)
{
    double u = (x - g->ox) * g->idx, v = (y - g->oy) * g->idy;
    u = u < 0 ? 0 : u > g->nx - 1 ? g->nx - 1 : u;
    v = v < 0 ? 0 : v > g->ny - 1 ? g->ny - 1 : v;
    int i = (int)u, j = (int)v;
    if (i > g->nx - 2)
        i = g->nx > 1 ? g->nx - 2 : 0;
    if (j > g->ny - 2)
        j = g->ny > 1 ? g->ny - 2 : 0;
    const double fu = u - i, fv = v - j;
    const int i1 = g->nx > 1 ? i + 1 : i, j1 = g->ny > 1 ? j + 1 : j;
    const float *t = g->terrain;
    const double a = t[(size_t)j * g->nx + i], b = t[(size_t)j * g->nx + i1], c = t[(size_t)j1 * g->nx + i],
                 dd = t[(size_t)j1 * g->nx + i1];
    return ((a * (1 - fu) + b * fu) * (1 - fv) + (c * (1 - fu) + dd * fu) * fv) * g->E;
}

void vsv_geo_terrain_colour(const vsv_geo *g, double x, double y, float rgb[3])
{
    const double h = vsv_geo_terrain(g, x, y) / g->E;
    const double ex = g->dx, ey = g->dy;
    const double gx = (vsv_geo_terrain(g, x + ex, y) - vsv_geo_terrain(g, x - ex, y)) / (2 * ex);
    const double gy = (vsv_geo_terrain(g, x, y + ey) - vsv_geo_terrain(g, x, y - ey)) / (2 * ey);
    double n[3] = {-gx, -gy, 1}, l[3] = {-0.5, -0.4, 0.75};
    normalize(n);
    normalize(l);
    const double lam = 0.35 + 0.65 * fmax(0, n[0] * l[0] + n[1] * l[1] + n[2] * l[2]);
    double c[3];
    if (h <= 0.5) {
        c[0] = 0.12, c[1] = 0.22, c[2] = 0.42; /* sea */
    } else {
        const double t = fmin(h / 3000.0, 1.0), s = fmax(0, fmin((h - 3000) / 2000.0, 1.0));
        c[0] = 0.22 + 0.33 * t + 0.35 * s;
        c[1] = 0.42 + 0.03 * t + 0.45 * s;
        c[2] = 0.22 + 0.13 * t + 0.55 * s;
    }
    for (int i = 0; i < 3; i++)
        rgb[i] = (float)(c[i] * lam);
}

/* The first s in [0, L] where q2 s^2 + q1 s + q0 falls to 0 (q0 > 0: the
 * ray above the ground at s = 0); INFINITY if none. */
static double first_root(double q2, double q1, double q0, double L)
{
    if (fabs(q2) * L <= 1e-12 * (fabs(q1) + q0 / L)) { /* linear */
        const double s = q1 < 0 ? -q0 / q1 : INFINITY;
        return s <= L ? s : INFINITY;
    }
    const double disc = q1 * q1 - 4 * q2 * q0;
    if (disc < 0)
        return INFINITY;
    const double qq = -0.5 * (q1 + copysign(sqrt(disc), q1));
    double r1 = qq / q2, r2 = qq != 0 ? q0 / qq : INFINITY;
    if (r1 > r2) {
        const double x = r1;
        r1 = r2, r2 = x;
    }
    return r1 >= 0 && r1 <= L ? r1 : r2 >= 0 && r2 <= L ? r2 : INFINITY;
}

double vsv_geo_terrain_hit(const vsv_geo *g, const double o[3], const double d[3], double t0, double t1)
{
    /* only where the ray is below the highest ground can it meet it */
    if (d[2] < 0) {
        const double tt = (g->ground_top - o[2]) / d[2];
        if (tt > t0)
            t0 = tt;
    } else if (d[2] > 0) {
        const double tt = (g->ground_top - o[2]) / d[2];
        if (tt < t1)
            t1 = tt;
    } else if (o[2] > g->ground_top) {
        return INFINITY;
    }
    if (!(t0 <= t1))
        return INFINITY;
    /* The ground is one bilinear patch per square of four cell centres (patch
     * i spans u in [i, i+1]); beyond the outer centres it is flat (patches -1
     * and n-1). Walk the patches the ray crosses; in each whose highest corner
     * the ray comes down to, solve the ray against the patch: a quadratic. */
    const int nx = g->nx, ny = g->ny;
    const double uo = (o[0] - g->ox) * g->idx, du = d[0] * g->idx;
    const double vo = (o[1] - g->oy) * g->idy, dv = d[1] * g->idy;
    const double u = uo + t0 * du, v = vo + t0 * dv;
    int i = u < 0 ? -1 : u >= nx - 1 ? nx - 1 : (int)u, j = v < 0 ? -1 : v >= ny - 1 ? ny - 1 : (int)v;
    const float *h = g->terrain;
    const double iu = 1 / du, iv = 1 / dv; /* infinite along an axis the ray does not move on */
    for (double t = t0;;) {
        const double tu = du > 0 && i < nx - 1 ? (i + 1 - uo) * iu : du < 0 && i > -1 ? (i - uo) * iu : INFINITY;
        const double tv = dv > 0 && j < ny - 1 ? (j + 1 - vo) * iv : dv < 0 && j > -1 ? (j - vo) * iv : INFINITY;
        double te = tu < tv ? tu : tv;
        te = te < t1 ? te : t1;
        const int i0 = i < 0 ? 0 : i, i1 = i + 1 < nx ? i + 1 : nx - 1, j0 = j < 0 ? 0 : j, j1 = j + 1 < ny ? j + 1 : ny - 1;
        const double h00 = h[(size_t)j0 * nx + i0] * g->E, h10 = h[(size_t)j0 * nx + i1] * g->E;
        const double h01 = h[(size_t)j1 * nx + i0] * g->E, h11 = h[(size_t)j1 * nx + i1] * g->E;
        const double za = o[2] + t * d[2], zb = o[2] + te * d[2];
        const double top0 = h00 > h10 ? h00 : h10, top1 = h01 > h11 ? h01 : h11;
        if ((za < zb ? za : zb) <= (top0 > top1 ? top0 : top1)) {
            /* local coordinates along the ray from t: fu = fua + fu1 s (flat beyond the centres) */
            const int inu = i >= 0 && i < nx - 1, inv = j >= 0 && j < ny - 1;
            const double fua = inu ? uo + t * du - i : 0, fu1 = inu ? du : 0;
            const double fva = inv ? vo + t * dv - j : 0, fv1 = inv ? dv : 0;
            const double b = h10 - h00, c = h01 - h00, e = h11 - h10 - h01 + h00;
            const double q0 = za - (h00 + b * fua + c * fva + e * fua * fva);
            if (q0 <= 0)
                return t; /* below the ground already: where it starts, or on this patch's edge */
            const double q1 = d[2] - (b * fu1 + c * fv1 + e * (fua * fv1 + fu1 * fva)), q2 = -e * fu1 * fv1;
            const double sh = first_root(q2, q1, q0, te - t);
            if (sh < INFINITY)
                return t + sh;
        }
        if (te >= t1)
            return INFINITY;
        if (tu <= tv)
            i += du > 0 ? 1 : -1;
        if (tv <= tu)
            j += dv > 0 ? 1 : -1;
        t = te;
    }
}

float vsv_opacity_table[VSV_OPACITY_N + 1];

static void opacity_fill(void)
{
    vsv_opacity_table[0] = 1;
    for (int i = 1; i <= VSV_OPACITY_N; i++) {
        const double u = i * (double)VSV_OPACITY_UMAX / VSV_OPACITY_N;
        vsv_opacity_table[i] = (float)(-expm1(-u) / u);
    }
}

void vsv_opacity_init(void)
{
    static pthread_once_t once = PTHREAD_ONCE_INIT;
    pthread_once(&once, opacity_fill);
}

/* Whether brick b's sampling copy holds data: one of the eight bricks
 * whose cells it copies has some. */
static int copy_has_data(const vsv_volume *v, int b)
{
    const int bx = v->bdim[0], by = v->bdim[1], bz = v->bdim[2];
    const int bi = b % bx, bj = b / bx % by, bk = b / (bx * by);
    for (int n = 0; n < 8; n++) {
        const int i = bi + (n & 1), j = bj + (n >> 1 & 1), k = bk + (n >> 2);
        if (i < bx && j < by && k < bz && v->bricks[i + bx * (j + by * k)])
            return 1;
    }
    return 0;
}

/* Sets c up to hold v's sampling copy (vsv_rc_cells): room for the bricks
 * whose copy holds data and for the shared empty brick, which is filled
 * here; copy_brick fills the others. */
static int copy_prepare(struct rc_copy *c, const vsv_volume *v)
{
    const size_t n3 = (size_t)(v->brick + 1) * (v->brick + 1) * (v->brick + 1);
    if (v->nbricks > c->cells_cap) {
        const float **p = realloc(c->cells, (size_t)v->nbricks * sizeof *p);
        if (!p)
            return -1;
        c->cells = p;
        c->cells_cap = v->nbricks;
    }
    size_t own = 0;
    for (int b = 0; b < v->nbricks; b++)
        own += (size_t)copy_has_data(v, b);
    if ((own + 1) * n3 > c->store_cap) {
        float *p = realloc(c->store, (own + 1) * n3 * sizeof *p);
        if (!p)
            return -1;
        c->store = p;
        c->store_cap = (own + 1) * n3;
    }
    c->empty = c->store + own * n3;
    for (size_t i = 0; i < n3; i++)
        c->empty[i] = v->empty_value;
    own = 0;
    for (int b = 0; b < v->nbricks; b++)
        c->cells[b] = copy_has_data(v, b) ? c->store + own++ * n3 : c->empty;
    c->vol = v;
    c->gen = v->gen;
    return 0;
}

void vsv_rc_copy_fill(const vsv_volume *v, int b, float *dst)
{
    const int B = v->brick, e = B + 1, s = v->shift, m = B - 1, bx = v->bdim[0], by = v->bdim[1];
    const int i0 = b % bx * B, j0 = b / bx % by * B, k0 = b / (bx * by) * B;
    for (int k = 0; k < e; k++) {
        const int gk = k0 + k < v->nz ? k0 + k : v->nz - 1;
        for (int j = 0; j < e; j++) {
            const int gj = j0 + j < v->ny ? j0 + j : v->ny - 1;
            float *row = dst + ((size_t)k * e + j) * e;
            if (i0 + B < v->nx) { /* the brick's row and the next cell inside the grid */
                const float *src = v->bricks[b % bx + bx * ((gj >> s) + by * (gk >> s))];
                if (src)
                    memcpy(row, src + ((gj & m) << s) + ((gk & m) << (2 * s)), (size_t)B * sizeof *row);
                else
                    for (int i = 0; i < B; i++)
                        row[i] = v->empty_value;
                row[B] = vsv_volume_at(v, i0 + B, gj, gk);
            } else {
                for (int i = 0; i < e; i++)
                    row[i] = vsv_volume_at(v, i0 + i < v->nx ? i0 + i : v->nx - 1, gj, gk);
            }
        }
    }
}

/* Brick item % nbricks of the copy item / nbricks being rebuilt. */
static void copy_brick(void *ctx, int item, int thread)
{
    const vsv_renderer *r = ctx;
    (void)thread;
    const struct rc_copy *c = r->build[item / r->build[0]->vol->nbricks];
    const int b = item % c->vol->nbricks;
    if (c->cells[b] != c->empty)
        vsv_rc_copy_fill(c->vol, b, (float *)c->cells[b]);
}

/* The raycaster's frame: its visible layers, and empty-space skipping: a
 * brick is skipped when, for every visible layer, the values of the brick and
 * of every brick around it (a trilinear sample reaches one cell across, and
 * blends values between those ranges) map to zero opacity. Computed per frame
 * from the octree's level 0. */
static int prepare_frame(vsv_renderer *r, const vsv_scene *sc)
{
    int nb = 0;
    const vsv_volume *v0 = NULL;
    for (int l = 0; l < sc->nlayers; l++)
        if (sc->layers[l].vol) {
            nb = sc->layers[l].vol->nbricks > nb ? sc->layers[l].vol->nbricks : nb;
            v0 = sc->layers[l].vol;
        }
    /* layout: [all layers clear][layer 0 clear][layer 1 clear]...[4 bytes] */
    const size_t need = (size_t)nb * ((size_t)sc->nlayers + 1) + 4;
    if (need > r->skip_cap) {
        unsigned char *p = realloc(r->skip, need);
        if (!p)
            return VSV_ENOMEM;
        r->skip = p;
        r->skip_cap = need;
    }
    if (sc->nlayers > r->act_cap) {
        vsv_rc_layer *p = realloc(r->act, (size_t)sc->nlayers * sizeof *p);
        if (!p)
            return VSV_ENOMEM;
        r->act = p;
        r->act_cap = sc->nlayers;
    }
    if (sc->nlayers > r->copy_cap) {
        struct rc_copy *c = realloc(r->copy, (size_t)sc->nlayers * sizeof *c);
        struct rc_copy **b = c ? realloc(r->build, (size_t)sc->nlayers * sizeof *b) : NULL;
        if (c)
            r->copy = c;
        if (!b)
            return VSV_ENOMEM;
        r->build = b;
        memset(c + r->copy_cap, 0, (size_t)(sc->nlayers - r->copy_cap) * sizeof *c);
        r->copy_cap = sc->nlayers;
    }
    r->nbuild = 0;
    vsv_rc_frame *F = &r->frame;
    memset(F, 0, sizeof *F);
    F->layer = r->act;
    if (!nb)
        return 0;
    memset(r->skip, 1, need);
    const vsv_geo *g = &r->g;
    const int bx = v0->bdim[0], by = v0->bdim[1], bz = v0->bdim[2];
    for (int l = 0; l < sc->nlayers; l++) {
        const vsv_layer *L = &sc->layers[l];
        unsigned char *clear = r->skip + (size_t)nb * (l + 1);
        if (!L->visible || !(L->opacity > 0) || !L->vol)
            continue;
        struct rc_copy *cp = &r->copy[l];
        if (cp->vol != L->vol || cp->gen != L->vol->gen || !cp->gen) {
            if (copy_prepare(cp, L->vol))
                return VSV_ENOMEM;
            r->build[r->nbuild++] = cp;
        }
        r->act[F->nlayers++] = (vsv_rc_layer){
            .vol = L->vol,
            .cells = cp->cells,
            .lut = (const float(*)[4])L->tf->lut,
            .lo = (float)L->tf->lo,
            .inv = (float)L->tf->inv,
            .off = (float)(-L->tf->base * L->tf->inv),
            .log = L->tf->scale == VSV_SCALE_LOG,
            .sigma = (float)(L->opacity * VSV_SIGMA_PER_CELL / fmin(g->dx, g->dy)),
            .clear = clear,
        };
        for (int k = 0; k < bz; k++)
            for (int j = 0; j < by; j++)
                for (int i = 0; i < bx; i++) {
                    const int b = i + bx * (j + by * k);
                    float lo = INFINITY, hi = -INFINITY;
                    for (int dk = -1; dk <= 1; dk++)
                        for (int dj = -1; dj <= 1; dj++)
                            for (int di = -1; di <= 1; di++) {
                                const int a = i + di, c = j + dj, e = k + dk;
                                if (a < 0 || c < 0 || e < 0 || a >= bx || c >= by || e >= bz)
                                    continue;
                                const int n = a + bx * (c + by * e);
                                /* a NaN minimum (no-data cells beside data) says nothing
                                 * about the smallest real value: assume the lowest */
                                const float bmn = L->vol->bmin[n] == L->vol->bmin[n] ? L->vol->bmin[n] : -INFINITY;
                                if (bmn < lo)
                                    lo = bmn;
                                if (L->vol->bmax[n] > hi)
                                    hi = L->vol->bmax[n];
                            }
                    if (vsv_tf_max_opacity(L->tf, (float)lo, (float)hi) > 0)
                        clear[b] = r->skip[b] = 0;
                }
    }
    if (!F->nlayers)
        return 0;
    const vsv_volume *V = r->act[0].vol;
    const int n[3] = {V->nx, V->ny, V->nz};
    for (int a = 0; a < 3; a++) {
        F->hi[a] = (float)(n[a] - 1);
        F->last[a] = n[a] > 1 ? n[a] - 2 : 0;
    }
    /* a fixed step in world units: a fraction of the smallest cell edge */
    F->st = r->o.step_cells * fmin(fmin(g->dx, g->dy), g->dz * g->E);
    F->inv_st = 1 / F->st;
    F->inv_cell[0] = 1 / g->dx;
    F->inv_cell[1] = 1 / g->dy;
    F->inv_cell[2] = 1 / (g->dz * g->E);
    /* nothing to skip (a dense species): no tests per sample */
    int any = 0;
    for (int l = -1; l < F->nlayers; l++)
        for (int b = 0; b < nb && !any; b++)
            any = (l < 0 ? r->skip : r->act[l].clear)[b];
    F->skip = r->o.no_skip || !any ? NULL : r->skip;
    F->shift = V->shift;
    F->mask = V->brick - 1;
    F->brick = V->brick;
    F->bx = V->bdim[0];
    F->bxy = V->bdim[0] * V->bdim[1];
    F->ey = V->brick + 1;
    F->ez = F->ey * F->ey;
    return 0;
}

/* One ray through the volume, front to back: trilinear samples classified
 * per layer, extinction and extinction-weighted colour summed over layers,
 * composited with the opacity of the step; early ray termination, skipping.
 * vsv_raycast16 does the same operations in the same order, sixteen rays wide. */
static void raycast_march(const vsv_rc_frame *F, const vsv_rc_ray *ray, float *pT, float acc[3], float *depth)
{
    const int sh = F->shift, m = F->mask, ey = F->ey, ez = F->ez;
    const float st = (float)ray->st;
    float T = 1;
    for (int n = 0; n < ray->ns; n++) {
        float c[3];
        int ci[3];
        for (int a = 0; a < 3; a++) {
            c[a] = fmaf((float)n, ray->dp[a], ray->p[a]);
            c[a] = c[a] > 0 ? (c[a] < F->hi[a] ? c[a] : F->hi[a]) : 0;
            ci[a] = (int)c[a];
            ci[a] = ci[a] < F->last[a] ? ci[a] : F->last[a];
        }
        const int bidx = (ci[0] >> sh) + F->bx * (ci[1] >> sh) + F->bxy * (ci[2] >> sh);
        if (F->skip && F->skip[bidx]) {
            const int next = vsv_rc_skip_to(F, ray, ci);
            if (next > n + 1)
                n = next - 1;
            continue;
        }
        const float fu = c[0] - ci[0], fv = c[1] - ci[1], fw = c[2] - ci[2];
        const int off = (ci[0] & m) + (ci[1] & m) * ey + (ci[2] & m) * ez;
        float sig = 0, col[3] = {0, 0, 0};
        for (int l = 0; l < F->nlayers; l++) {
            const vsv_rc_layer *L = &F->layer[l];
            if (F->skip && L->clear[bidx])
                continue; /* transparent around this brick: adds nothing */
            float cell[8];
            const float *q = L->cells[bidx] + off;
            for (int i = 0; i < 8; i++)
                cell[i] = q[(i & 1) + (i & 2 ? ey : 0) + (i & 4 ? ez : 0)];
            const float v = vsv_rc_trilinear(cell, fu, fv, fw);
            if (!(v >= L->lo)) /* below the range, or no data (NaN) */
                continue;
            float x = fmaf(L->log ? logf(v) : v, L->inv, L->off);
            x = x < VSV_TF_LUT - 1 ? x : VSV_TF_LUT - 1;
            int i = (int)x;
            i = i < VSV_TF_LUT - 2 ? i : VSV_TF_LUT - 2;
            const float f = x - i;
            const float *lo = L->lut[i], *hi = lo + 4;
            const float s = vsv_rc_lerp(lo[3], hi[3], f) * L->sigma;
            if (s > 0) {
                sig += s;
                for (int ch = 0; ch < 3; ch++)
                    col[ch] += s * vsv_rc_lerp(lo[ch], hi[ch], f);
            }
        }
        if (sig > 0) {
            const float us = sig * st;
            const float f = vsv_rc_opacity_per_u(us);
            const float a = us * f, k = T * f * st; /* T a / sig */
            for (int ch = 0; ch < 3; ch++)
                acc[ch] = fmaf(k, col[ch], acc[ch]);
            T = fmaf(-T, a, T);
            if (*depth == INFINITY && 1 - T > 0.1f)
                *depth = (float)(ray->ts + n * ray->st);
            if (T < 1.0f / 512)
                break; /* early ray termination */
        }
    }
    *pT = T;
}

/* The rays of pixels px .. px + SPAN - 1 of row py and their stretches
 * [t0, t1] inside the scene's box and the camera's near and far distances
 * (hit 0 where a ray has none, or its pixel is past the image's width w):
 * vsv_rays_get's arithmetic and vsv_box_hit, lane by lane without branches
 * so that the compiler works on several rays at once. */
enum { SPAN = VSV_RC_LANES };
typedef struct spans {
    double o[3][SPAN], d[3][SPAN], t0[SPAN], t1[SPAN];
    int hit[SPAN];
} spans;

static void pixel_spans(const vsv_renderer *r, int px, int py, int w, spans *S)
{
    const vsv_rays *R = &r->rays;
    if (py < R->y0 || py > R->y1 || px + SPAN <= R->x0 || px > R->x1) {
        memset(S, 0, sizeof *S); /* all sixteen outside the scene's rectangle on screen: no hits */
        return;
    }
    const double sy = R->cy + R->ky * (1 - 2 * (py + 0.5) / R->h);
    double sx[SPAN];
    for (int i = 0; i < SPAN; i++)
        sx[i] = R->cx + R->kx * (2 * (px + i + 0.5) / R->w - 1);
    if (R->persp) {
        for (int i = 0; i < SPAN; i++) {
            double d[3];
            for (int a = 0; a < 3; a++)
                d[a] = R->f[a] + sx[i] * R->r[a] + sy * R->u[a];
            const double n = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), k = 1 / n;
            for (int a = 0; a < 3; a++) {
                S->o[a][i] = R->o[a];
                S->d[a][i] = n > 0 ? d[a] * k : d[a];
            }
        }
    } else {
        for (int i = 0; i < SPAN; i++)
            for (int a = 0; a < 3; a++) {
                S->o[a][i] = R->o[a] + sx[i] * R->r[a] + sy * R->u[a];
                S->d[a][i] = R->f[a];
            }
    }
    const double *mn = r->g.bmin, *mx = r->g.bmax;
    const double znear = r->cam->znear > 0 ? r->cam->znear : 0, zfar = r->cam->zfar > 0 ? r->cam->zfar : INFINITY;
    for (int i = 0; i < SPAN; i++) { /* py is inside the rectangle (above) */
        const double o[3] = {S->o[0][i], S->o[1][i], S->o[2][i]}, d[3] = {S->d[0][i], S->d[1][i], S->d[2][i]};
        double lo, hi;
        const int box = vsv_box_hit(o, d, mn, mx, &lo, &hi);
        S->hit[i] = (px + i >= R->x0) & (px + i <= R->x1) & (px + i < w) & box;
        S->t0[i] = lo < znear ? znear : lo;
        S->t1[i] = hi > zfar ? zfar : hi;
    }
}

/* The rays of pixels px .. px + SPAN - 1 of row py: their samples through
 * the volume (none when a ray misses, or its pixel is past the image), and
 * where they meet the ground (t_hit; INFINITY when they do not). */
static void raycast_setup(const vsv_renderer *r, int px, int py, vsv_rc_ray ray[SPAN], double t_hit[SPAN])
{
    const vsv_geo *g = &r->g;
    spans S;
    pixel_spans(r, px, py, r->cam->width, &S);
    const double st = r->frame.st, org[3] = {g->ox, g->oy, g->oz * g->E};
    for (int i = 0; i < SPAN; i++) {
        t_hit[i] = S.hit[i] && g->terrain ? r->ground[(size_t)py * r->cam->width + px + i].t : INFINITY;
        const double ts = S.t0[i] + 0.5 * st, tend = S.t1[i] < t_hit[i] ? S.t1[i] : t_hit[i];
        ray[i].ns = S.hit[i] && r->frame.nlayers && tend > ts ? (int)ceil((tend - ts) * r->frame.inv_st) : 0;
        ray[i].ts = ts;
        ray[i].st = st;
        for (int a = 0; a < 3; a++) {
            ray[i].p[a] = (float)((S.o[a][i] + ts * S.d[a][i] - org[a]) * r->frame.inv_cell[a]);
            ray[i].dp[a] = (float)(st * S.d[a][i] * r->frame.inv_cell[a]);
        }
    }
}

/* A pixel from its ray's compositing: the ground behind what is left. */
static void raycast_finish(const vsv_renderer *r, int px, int py, double t_hit, float T, const float acc[3],
                           float depth)
{
    const size_t at = (size_t)py * r->cam->width + px;
    float out[4] = {acc[0], acc[1], acc[2], 1 - T};
    if (t_hit < INFINITY && T >= 1.0f / 512) {
        const vsv_ground *gp = &r->ground[at];
        for (int c = 0; c < 3; c++)
            out[c] += T * gp->rgb[c];
        out[3] = 1;
        if (depth == INFINITY)
            depth = (float)t_hit;
    }
    if (r->rgba)
        memcpy(r->rgba + 4 * at, out, sizeof out);
    if (r->depth)
        r->depth[at] = depth;
}

/* One image row of the ground cache. */
static void ground_row(void *ctx, int py, int thread)
{
    vsv_renderer *r = ctx;
    const vsv_geo *g = &r->g;
    const vsv_camera *cam = r->cam;
    (void)thread;
    for (int px0 = 0; px0 < cam->width; px0 += SPAN) {
        spans S;
        pixel_spans(r, px0, py, cam->width, &S);
        for (int i = 0; i < SPAN && px0 + i < cam->width; i++) {
            vsv_ground *gp = &r->ground[(size_t)py * cam->width + px0 + i];
            gp->t = INFINITY;
            if (!S.hit[i])
                continue;
            const double o[3] = {S.o[0][i], S.o[1][i], S.o[2][i]}, d[3] = {S.d[0][i], S.d[1][i], S.d[2][i]};
            const double t = vsv_geo_terrain_hit(g, o, d, S.t0[i], S.t1[i]);
            if (t < INFINITY) {
                gp->t = (float)t;
                vsv_geo_terrain_colour(g, o[0] + t * d[0], o[1] + t * d[1], gp->rgb);
            }
        }
    }
}

/* --------------------------------------------------------------- threads */

/* One 16x16 tile of the raycaster: a row of the tile at a time, sixteen rays
 * at once where the CPU has AVX2 (in one AVX-512 register where it has that;
 * VSV_SIMD=0 in the environment: one ray at a time, VSV_SIMD=avx2: never
 * AVX-512), else one ray at a time. */
static void raycast_tile(void *ctx, int tile, int thread)
{
    enum { N = VSV_RC_LANES };
    vsv_renderer *r = ctx;
    const vsv_camera *cam = r->cam;
    (void)thread;
    const int tx = tile % r->tiles_x, ty = tile / r->tiles_x;
    const int x1 = (tx + 1) * TILE < cam->width ? (tx + 1) * TILE : cam->width;
    for (int py = ty * TILE; py < (ty + 1) * TILE && py < cam->height; py++)
        for (int px = tx * TILE; px < x1; px += N) {
            vsv_rc_ray ray[N];
            double t_hit[N];
            float T[N], acc[3][N], depth[N];
            const int n = x1 - px < N ? x1 - px : N;
            raycast_setup(r, px, py, ray, t_hit);
            for (int i = 0; i < N; i++) {
                if (i >= n) /* the next tile's */
                    ray[i].ns = 0;
                T[i] = 1;
                acc[0][i] = acc[1][i] = acc[2][i] = 0;
                depth[i] = INFINITY;
            }
            if (r->kernel) {
                r->kernel(&r->frame, ray, T, acc, depth);
            } else {
                for (int i = 0; i < n; i++) {
                    float a[3] = {0, 0, 0};
                    raycast_march(&r->frame, &ray[i], &T[i], a, &depth[i]);
                    for (int c = 0; c < 3; c++)
                        acc[c][i] = a[c];
                }
            }
            for (int i = 0; i < n; i++) {
                const float a[3] = {acc[0][i], acc[1][i], acc[2][i]};
                raycast_finish(r, px + i, py, t_hit[i], T[i], a, depth[i]);
            }
        }
}

static void run_items(vsv_renderer *r, int thread)
{
    for (;;) { /* one atomic counter hands out the items (a lock per item cost as much as a warp row) */
        const int item = __atomic_fetch_add(&r->next_item, 1, __ATOMIC_RELAXED);
        if (item >= r->nitems)
            return;
        r->job(r->job_ctx, item, thread);
    }
}

/* A frame runs several short jobs in a row (the ground, compositing, the
 * warp): a thread that has just finished one, or waits for the others to,
 * spins this many pauses (tens of microseconds) before it sleeps, so the next
 * job does not wait for a wake-up (measured: the shear-warp's warp got no help
 * from a second thread without it). */
#define SPIN 4000
#if defined(__x86_64__) || defined(__i386__)
#define PAUSE() __builtin_ia32_pause()
#else
#define PAUSE() ((void)0)
#endif

static void *worker(void *arg)
{
    struct wslot *ws = arg;
    vsv_renderer *r = ws->r;
    int seen = 0;
    for (;;) {
        for (int i = 0; i < SPIN && __atomic_load_n(&r->generation, __ATOMIC_ACQUIRE) == seen &&
                        !__atomic_load_n(&r->quit, __ATOMIC_RELAXED);
             i++)
            PAUSE();
        pthread_mutex_lock(&r->mu);
        while (r->generation == seen && !r->quit)
            pthread_cond_wait(&r->go, &r->mu);
        if (r->quit) {
            pthread_mutex_unlock(&r->mu);
            return NULL;
        }
        seen = r->generation;
        pthread_mutex_unlock(&r->mu);
        run_items(r, ws->index);
        pthread_mutex_lock(&r->mu);
        __atomic_add_fetch(&r->finished, 1, __ATOMIC_RELEASE);
        pthread_cond_signal(&r->done);
        pthread_mutex_unlock(&r->mu);
    }
}

/* Runs job(ctx, item, thread) for items 0..n-1 on every thread; returns when done. */
static void pool_run(vsv_renderer *r, void (*job)(void *, int, int), void *ctx, int n)
{
    pthread_mutex_lock(&r->mu);
    r->job = job;
    r->job_ctx = ctx;
    r->nitems = n;
    r->next_item = 0;
    r->finished = 0;
    __atomic_add_fetch(&r->generation, 1, __ATOMIC_RELEASE);
    pthread_cond_broadcast(&r->go);
    pthread_mutex_unlock(&r->mu);
    run_items(r, 0);
    for (int i = 0; i < SPIN && __atomic_load_n(&r->finished, __ATOMIC_ACQUIRE) < r->nthreads - 1; i++)
        PAUSE();
    pthread_mutex_lock(&r->mu);
    while (r->finished < r->nthreads - 1)
        pthread_cond_wait(&r->done, &r->mu);
    pthread_mutex_unlock(&r->mu);
}

int vsv_renderer_create(const vsv_render_opts *o, vsv_renderer **out)
{
    vsv_renderer *r = *out = calloc(1, sizeof *r);
    if (!r)
        return VSV_ENOMEM;
    vsv_opacity_init();
    if (o)
        r->o = *o;
    else
        vsv_render_opts_init(&r->o);
    if (r->o.kind != VSV_RENDER_RAYCAST && r->o.kind != VSV_RENDER_SHEARWARP)
        return VSV_EUNSUPPORTED;
    const char *simd = getenv("VSV_SIMD");
    __builtin_cpu_init();
    r->simd = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") && !(simd && !strcmp(simd, "0"));
    r->kernel = NULL;
    if (r->simd)
        r->kernel = __builtin_cpu_supports("avx512f") && !(simd && !strcmp(simd, "avx2")) ? vsv_raycast16_avx512
                                                                                          : vsv_raycast16;
    if (r->o.kind == VSV_RENDER_SHEARWARP &&
        !(r->sw = vsv_sw_create(MAX_THREADS, r->simd && __builtin_cpu_supports("f16c"))))
        return VSV_ENOMEM;
    if (!(r->o.step_cells > 0))
        r->o.step_cells = 0.5;
    int n = r->o.threads > 0 ? r->o.threads : vsv_ncpus();
    r->nthreads = n > MAX_THREADS ? MAX_THREADS : n;
    pthread_mutex_init(&r->mu, NULL);
    pthread_cond_init(&r->go, NULL);
    pthread_cond_init(&r->done, NULL);
    for (int i = 1; i < r->nthreads; i++) { /* the caller's thread is worker 0 */
        r->slot[i] = (struct wslot){r, i};
        if (pthread_create(&r->tid[i], NULL, worker, &r->slot[i])) {
            r->nthreads = i;
            break;
        }
    }
    r->running = 1;
    return 0;
}

void vsv_renderer_free(vsv_renderer *r)
{
    if (!r)
        return;
    if (r->running) {
        pthread_mutex_lock(&r->mu);
        __atomic_store_n(&r->quit, 1, __ATOMIC_RELEASE);
        pthread_cond_broadcast(&r->go);
        pthread_mutex_unlock(&r->mu);
        for (int i = 1; i < r->nthreads; i++)
            pthread_join(r->tid[i], NULL);
        pthread_mutex_destroy(&r->mu);
        pthread_cond_destroy(&r->go);
        pthread_cond_destroy(&r->done);
    }
    free(r->skip);
    free(r->act);
    for (int l = 0; l < r->copy_cap; l++) {
        free(r->copy[l].store);
        free(r->copy[l].cells);
    }
    free(r->copy);
    free(r->build);
    free(r->ground);
    vsv_sw_free(r->sw);
    vsv_native_free(&r->native);
    free(r);
}

int vsv_render(vsv_renderer *r, const vsv_scene *sc, const vsv_camera *cam, float *rgba, float *depth)
{
    if (cam->width < 1 || cam->height < 1 || !sc->meta)
        return VSV_EINVAL;
    int nrc = vsv_native_scene(&r->native, sc, &sc);
    if (nrc)
        return nrc;
    for (int l = 0; l < sc->nlayers; l++) {
        const vsv_volume *v = sc->layers[l].vol;
        if (v && (v->nx != sc->meta->nx || v->ny != sc->meta->ny || v->nz != sc->meta->nz))
            return VSV_EINVAL;
    }
    vsv_scene_geo(sc, &r->g);
    r->cam = cam;
    vsv_rays_init(&r->rays, cam);
    rays_cull(&r->rays, r->g.bmin, r->g.bmax);
    if (r->g.terrain) { /* the ground: again only when the view or the geometry changed */
        const size_t n = (size_t)cam->width * cam->height;
        if (n > r->ground_cap) {
            vsv_ground *ng = realloc(r->ground, n * sizeof *ng);
            if (!ng)
                return VSV_ENOMEM;
            r->ground = ng;
            r->ground_cap = n;
            r->ground_valid = 0;
        }
        if (!r->ground_valid || memcmp(&r->ground_cam, cam, sizeof *cam) || memcmp(&r->ground_geo, &r->g, sizeof r->g)) {
            pool_run(r, ground_row, r, cam->height);
            r->ground_cam = *cam;
            r->ground_geo = r->g;
            r->ground_valid = 1;
        }
    }
    if (r->o.kind == VSV_RENDER_SHEARWARP) {
        int rows = 0, classify = 0;
        int rc = vsv_sw_begin(r->sw, sc, &r->g, cam, rgba, depth, r->ground, &rows, &classify);
        if (!rc && classify) {
            struct timespec t0, t1;
            clock_gettime(CLOCK_MONOTONIC, &t0);
            pool_run(r, vsv_sw_classify_slice, r->sw, classify);
            clock_gettime(CLOCK_MONOTONIC, &t1);
            vsv_sw_classified(r->sw, (t1.tv_sec - t0.tv_sec) + (t1.tv_nsec - t0.tv_nsec) * 1e-9);
        }
        if (!rc) {
            pool_run(r, vsv_sw_composite_row, r->sw, rows);
            pool_run(r, vsv_sw_warp_rows, r->sw, vsv_sw_warp_jobs(cam->height));
            return 0;
        }
        if (rc != VSV_EUNSUPPORTED)
            return rc;
        /* an eye among the slices has no shear-warp factorisation: raycast this frame */
    }
    int rc = prepare_frame(r, sc);
    if (rc)
        return rc;
    if (r->nbuild) {
        struct timespec t0, t1;
        clock_gettime(CLOCK_MONOTONIC, &t0);
        pool_run(r, copy_brick, r, r->nbuild * r->build[0]->vol->nbricks);
        clock_gettime(CLOCK_MONOTONIC, &t1);
        r->copy_seconds = (t1.tv_sec - t0.tv_sec) + (t1.tv_nsec - t0.tv_nsec) * 1e-9;
    }
    r->sc = sc;
    r->rgba = rgba;
    r->depth = depth;
    r->tiles_x = (cam->width + TILE - 1) / TILE;
    r->ntiles = r->tiles_x * ((cam->height + TILE - 1) / TILE);
    pool_run(r, raycast_tile, r, r->ntiles);
    return 0;
}

double vsv_renderer_rebuild_seconds(const vsv_renderer *r)
{
    return r->o.kind == VSV_RENDER_SHEARWARP ? vsv_sw_build_seconds(r->sw) : r->copy_seconds;
}
