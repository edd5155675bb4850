/* vsv_shearwarp.c — Lacroute's shear-warp factorisation, for parallel and
 * perspective projection (slices sheared, or scaled about the eye). The species rule is applied per voxel (classification: summed
 * extinction and extinction-weighted colour),
 * the classified volume is run-length encoded along each axis (transparent /
 * non-transparent runs per voxel scanline), slices perpendicular to the
 * principal viewing axis are sheared and composited front to back into an
 * intermediate image with bilinear interpolation inside each slice, skipping
 * transparent voxel runs and pixels that are already opaque, and one 2-D
 * affine warp resamples the intermediate image into the final one. The
 * ground is the raycaster's height field, met by each final pixel's ray and
 * composited behind the volume (cells below the ground hold no data). */
#include "vsv_render_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define OPAQUE 0.998f

/* Classified voxel: extinction per unit of ray length in voxel steps is not
 * known until the view is; store sigma per world metre and sigma * colour. */
typedef struct cvox {
    float s, r, g, b;
} cvox;

struct vsv_sw {
    cvox *cls;            /* nx*ny*nz classified voxels */
    size_t cls_cap;
    uint64_t key;         /* what the classification was built from */
    int n[3];
    /* run lengths per axis: for axis c, scanlines (k along c, ib along b) hold
     * alternating transparent / opaque-ish run lengths along a, starting with
     * a transparent run; starts[] indexes them */
    uint16_t *runs[3];
    size_t runs_len[3], runs_cap[3];
    uint32_t *starts[3];
    size_t starts_cap[3];
    /* intermediate image and opaque-pixel links */
    float *img;           /* w*h*4: premultiplied rgb, alpha */
    int *link;            /* w*h: next pixel of the row that is not opaque */
    size_t img_cap, link_cap;
    unsigned char **mask; /* per thread: a voxel scanline's non-transparent footprint */
    size_t mask_cap;
    int max_threads;
    /* the current view (set by begin) */
    const vsv_geo *g;
    const vsv_camera *cam;
    float *out, *depth;
    int c, a, b, na, nb, nc, w, h, front, dk;
    double sa, sb, ta, tb, delta, dv[3];
    /* perspective: the eye in voxel coordinates, the reference slice (the one
     * nearest the eye, scale 1) and the world size of a voxel along a, b, c */
    int persp, kref;
    double eye[3], wsz[3];
    double build_seconds;
};

static uint64_t mix(uint64_t h, uint64_t v)
{
    h ^= v + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    return h;
}

/* A key of everything the classification depends on. */
static uint64_t scene_key(const vsv_scene *sc)
{
    uint64_t h = 1469598103934665603ull;
    for (int l = 0; l < sc->nlayers; l++) {
        const vsv_layer *L = &sc->layers[l];
        h = mix(h, (uint64_t)(uintptr_t)L->vol);
        h = mix(h, L->vol ? (uint64_t)(L->vol->step * 131 + L->vol->species) : 0);
        h = mix(h, (uint64_t)L->visible);
        uint32_t u;
        memcpy(&u, &L->opacity, 4);
        h = mix(h, u);
        h = mix(h, L->tf ? vsv_crc32c(0, L->tf, sizeof *L->tf) : 0);
    }
    uint64_t e;
    memcpy(&e, &sc->exaggeration, 8);
    return mix(mix(h, e), (uint64_t)sc->show_terrain);
}

static int grow(void **p, size_t *cap, size_t need, size_t elem)
{
    if (need <= *cap)
        return 0;
    void *q = realloc(*p, need * elem);
    if (!q)
        return -1;
    *p = q;
    *cap = need;
    return 0;
}

/* Classification and the three run-length encodings. */
static int classify(vsv_sw *sw, const vsv_scene *sc, const vsv_geo *g)
{
    const int nx = g->nx, ny = g->ny, nz = g->nz;
    const size_t n = (size_t)nx * ny * nz;
    if (grow((void **)&sw->cls, &sw->cls_cap, n, sizeof *sw->cls))
        return VSV_ENOMEM;
    sw->n[0] = nx;
    sw->n[1] = ny;
    sw->n[2] = nz;
    const double sigma_unit = VSV_SIGMA_PER_CELL / fmin(g->dx, g->dy);
    for (int k = 0; k < nz; k++)
        for (int j = 0; j < ny; j++)
            for (int i = 0; i < nx; i++) {
                /* sums in double: exact for a few float terms, so the species
                 * order cannot change a bit */
                double cs = 0, cr = 0, cg = 0, cb = 0;
                for (int l = 0; l < sc->nlayers; l++) {
                    const vsv_layer *L = &sc->layers[l];
                    if (!L->visible || !(L->opacity > 0) || !L->vol)
                        continue;
                    float rgba[4];
                    vsv_tf_eval(L->tf, vsv_volume_at(L->vol, i, j, k), rgba);
                    const float s = (float)(rgba[3] * L->opacity * sigma_unit);
                    if (s > 0) {
                        cs += s;
                        cr += (double)s * rgba[0];
                        cg += (double)s * rgba[1];
                        cb += (double)s * rgba[2];
                    }
                }
                const cvox c = {(float)cs, (float)cr, (float)cg, (float)cb};
                sw->cls[((size_t)k * ny + j) * nx + i] = c;
            }
    /* run lengths along axis a for every scanline of every slice, per principal axis c */
    for (int c = 0; c < 3; c++) {
        const int a = (c + 1) % 3, b = (c + 2) % 3;
        const int na = sw->n[a], nb = sw->n[b], nc = sw->n[c];
        if (grow((void **)&sw->starts[c], &sw->starts_cap[c], (size_t)nc * nb + 1, sizeof(uint32_t)))
            return VSV_ENOMEM;
        size_t len = 0;
        for (int k = 0; k < nc; k++)
            for (int ib = 0; ib < nb; ib++) {
                sw->starts[c][(size_t)k * nb + ib] = (uint32_t)len;
                int ia = 0, want_opaque = 0;
                while (ia < na) {
                    int run = 0;
                    while (ia < na && run < 65535) {
                        int idx[3];
                        idx[a] = ia, idx[b] = ib, idx[c] = k;
                        const int op = sw->cls[((size_t)idx[2] * ny + idx[1]) * nx + idx[0]].s > 0;
                        if (op != want_opaque)
                            break;
                        run++;
                        ia++;
                    }
                    if (grow((void **)&sw->runs[c], &sw->runs_cap[c], len + 2, sizeof(uint16_t)))
                        return VSV_ENOMEM;
                    sw->runs[c][len++] = (uint16_t)run;
                    want_opaque = !want_opaque;
                }
                if (grow((void **)&sw->runs[c], &sw->runs_cap[c], len + 1, sizeof(uint16_t)))
                    return VSV_ENOMEM;
                sw->runs[c][len++] = 0; /* terminator */
            }
        sw->starts[c][(size_t)nc * nb] = (uint32_t)len;
        sw->runs_len[c] = len;
    }
    return 0;
}

/* Marks in `mask` (length na + 1) the voxels of scanline (k, ib) that are not
 * transparent, dilated by one for bilinear footprints. */
static void scan_mask(const vsv_sw *sw, int c, int k, int ib, unsigned char *mask)
{
    const int a = (c + 1) % 3, b = (c + 2) % 3, na = sw->n[a], nb = sw->n[b];
    if (ib < 0 || ib >= nb)
        return;
    const uint16_t *r = sw->runs[c] + sw->starts[c][(size_t)k * nb + ib];
    int ia = 0, opaque = 0;
    for (; ia < na; r++) { /* the runs of a scanline add up to na */
        const int run = *r;
        if (opaque && run) {
            const int from = ia > 0 ? ia - 1 : 0, to = ia + run < na ? ia + run : na - 1;
            memset(mask + from, 1, (size_t)(to - from + 1));
        }
        ia += run;
        opaque = !opaque;
    }
}

int vsv_sw_begin(vsv_sw *sw, const vsv_scene *sc, const vsv_geo *g, const vsv_camera *cam, float *out, float *depth,
                 int *rows)
{
    const uint64_t key = scene_key(sc);
    int rc;
    if (key != sw->key || !sw->cls || sw->n[0] != g->nx || sw->n[1] != g->ny || sw->n[2] != g->nz) {
        struct timespec t0, t1;
        clock_gettime(CLOCK_MONOTONIC, &t0);
        if ((rc = classify(sw, sc, g)))
            return rc;
        clock_gettime(CLOCK_MONOTONIC, &t1);
        sw->build_seconds = (t1.tv_sec - t0.tv_sec) + (t1.tv_nsec - t0.tv_nsec) * 1e-9;
        sw->key = key;
    }
    /* the view in voxel index space */
    double d[3] = {cam->dir[0], cam->dir[1], cam->dir[2]};
    const double dl = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int i = 0; i < 3; i++)
        d[i] /= dl;
    sw->dv[0] = d[0] / g->dx;
    sw->dv[1] = d[1] / g->dy;
    sw->dv[2] = d[2] / (g->dz * g->E);
    int c = 0;
    for (int i = 1; i < 3; i++)
        if (fabs(sw->dv[i]) > fabs(sw->dv[c]))
            c = i;
    sw->c = c;
    sw->a = (c + 1) % 3;
    sw->b = (c + 2) % 3;
    sw->na = sw->n[sw->a];
    sw->nb = sw->n[sw->b];
    sw->nc = sw->n[c];
    sw->sa = -sw->dv[sw->a] / sw->dv[c];
    sw->sb = -sw->dv[sw->b] / sw->dv[c];
    sw->ta = -fmin(0, sw->sa * (sw->nc - 1));
    sw->tb = -fmin(0, sw->sb * (sw->nc - 1));
    sw->w = sw->na + (int)ceil(fabs(sw->sa) * (sw->nc - 1)) + 2;
    sw->h = sw->nb + (int)ceil(fabs(sw->sb) * (sw->nc - 1)) + 2;
    sw->delta = 1 / fabs(sw->dv[c]); /* world metres between slices along a ray */
    sw->front = sw->dv[c] > 0 ? 0 : sw->nc - 1;
    sw->dk = sw->dv[c] > 0 ? 1 : -1;
    sw->persp = cam->fov_deg > 0;
    if (sw->persp) {
        /* Lacroute's perspective factorisation: slice k seen from the eye E
         * lands on the reference slice scaled by s_k = (kref - E_c)/(k - E_c)
         * about E; the eye must lie outside the slab of slices. */
        double o[3], rd[3];
        vsv_pixel_ray(cam, 0, 0, o, rd);
        sw->eye[0] = (o[0] - g->ox) / g->dx;
        sw->eye[1] = (o[1] - g->oy) / g->dy;
        sw->eye[2] = (o[2] / g->E - g->oz) / g->dz;
        const double sizes[3] = {g->dx, g->dy, g->dz * g->E};
        for (int i = 0; i < 3; i++)
            sw->wsz[i] = sizes[(i == 0 ? sw->a : i == 1 ? sw->b : c)];
        const double ec = sw->eye[c];
        if (ec > -0.5 && ec < sw->nc - 0.5)
            return VSV_EUNSUPPORTED; /* the eye among the slices: the caller raycasts */
        sw->kref = ec < 0 ? 0 : sw->nc - 1;
        sw->front = sw->kref;
        sw->dk = ec < 0 ? 1 : -1;
        /* the intermediate image bounds: the reference slice at scale 1 and the
         * farthest slice, both around the eye */
        const int kfar = sw->kref == 0 ? sw->nc - 1 : 0;
        const double sfar = (sw->kref - ec) / (kfar - ec);
        const double ea = sw->eye[sw->a == 0 ? 0 : sw->a], eb = sw->eye[sw->b];
        double lo_a = fmin(-1.0, ea + (-1 - ea) * sfar), hi_a = fmax((double)sw->na, ea + (sw->na - ea) * sfar);
        double lo_b = fmin(-1.0, eb + (-1 - eb) * sfar), hi_b = fmax((double)sw->nb, eb + (sw->nb - eb) * sfar);
        sw->ta = -lo_a;
        sw->tb = -lo_b;
        sw->w = (int)ceil(hi_a - lo_a) + 2;
        sw->h = (int)ceil(hi_b - lo_b) + 2;
    }
    /* buffers grow with the view and are reused: no allocation per frame */
    const size_t wh = (size_t)sw->w * sw->h;
    if (grow((void **)&sw->img, &sw->img_cap, wh * 4, sizeof(float)) ||
        grow((void **)&sw->link, &sw->link_cap, wh, sizeof(int)))
        return VSV_ENOMEM;
    if ((size_t)sw->na + 2 > sw->mask_cap) {
        for (int t = 0; t < sw->max_threads; t++) {
            unsigned char *m = realloc(sw->mask[t], (size_t)sw->na + 2);
            if (!m)
                return VSV_ENOMEM;
            sw->mask[t] = m;
        }
        sw->mask_cap = (size_t)sw->na + 2;
    }
    memset(sw->img, 0, wh * 4 * sizeof(float));
    for (size_t i = 0; i < wh; i++)
        sw->link[i] = (int)(i % (size_t)sw->w);
    sw->g = g;
    sw->cam = cam;
    sw->out = out;
    sw->depth = depth;
    *rows = sw->h;
    return 0;
}

/* Intermediate row y through every slice, front to back. */
/* Opaque-pixel skipping: the first pixel at or after x of this row that is
 * not yet opaque (w when none), following the links and shortening the one
 * at x to point there. */
static int open_pixel(int *lk, int x, int w)
{
    int xx = x;
    while (xx < w && lk[xx] != xx)
        xx = lk[xx];
    if (xx != x)
        lk[x] = xx;
    return xx;
}

/* One intermediate pixel: the bilinear blend of four classified voxels of
 * slice k at voxel coordinates (pa, pb), composited over what is there. */
static void composite(vsv_sw *sw, float *px, int *lk, int x, int k, double pa, double pb, double delta)
{
    const int a = sw->a, b = sw->b, c = sw->c, na = sw->na, nb = sw->nb, nx = sw->n[0], ny = sw->n[1];
    const int ia = (int)floor(pa), ib = (int)floor(pb);
    const float fu = (float)(pa - ia), fv = (float)(pb - ib);
    float acc[4] = {0, 0, 0, 0};
    for (int q = 0; q < 4; q++) {
        const int ja = ia + (q & 1), jb = ib + (q >> 1);
        if (ja < 0 || ja >= na || jb < 0 || jb >= nb)
            continue;
        const float wq = ((q & 1) ? fu : 1 - fu) * ((q >> 1) ? fv : 1 - fv);
        int idx[3];
        idx[a] = ja, idx[b] = jb, idx[c] = k;
        const cvox *v = &sw->cls[((size_t)idx[2] * ny + idx[1]) * nx + idx[0]];
        acc[0] += wq * v->s;
        acc[1] += wq * v->r;
        acc[2] += wq * v->g;
        acc[3] += wq * v->b;
    }
    if (!(acc[0] > 0))
        return;
    const float T = 1 - px[3];
    const float al = (float)(1 - exp(-acc[0] * delta));
    px[0] += T * al * acc[1] / acc[0];
    px[1] += T * al * acc[2] / acc[0];
    px[2] += T * al * acc[3] / acc[0];
    px[3] += T * al;
    if (px[3] >= OPAQUE)
        lk[x] = x + 1;
}

/* Perspective: slice k is the reference slice scaled by s_k about the eye. */
static void composite_row_persp(vsv_sw *sw, int y, int thread)
{
    const int c = sw->c, na = sw->na, nb = sw->nb;
    unsigned char *m0 = sw->mask[thread];
    float *row = sw->img + (size_t)y * sw->w * 4;
    int *lk = sw->link + (size_t)y * sw->w;
    const double ea = sw->eye[sw->a], eb = sw->eye[sw->b], ec = sw->eye[c];
    const double yb = y - sw->tb; /* the row on the reference slice, voxel units */
    for (int s = 0; s < sw->nc; s++) {
        const int k = sw->front + s * sw->dk;
        const double sk = (sw->kref - ec) / (k - ec);
        const double pb = eb + (yb - eb) / sk;
        if (pb < -1 || pb > nb)
            continue;
        const int ib = (int)floor(pb);
        memset(m0, 0, (size_t)na + 1);
        scan_mask(sw, c, k, ib, m0);
        scan_mask(sw, c, k, ib + 1, m0);
        /* the pixels whose voxel coordinate pa lies in [-1, na] */
        const int x0 = (int)ceil(sw->ta + ea + (-1 - ea) * sk), x1 = (int)floor(sw->ta + ea + (na - ea) * sk);
        for (int x = x0 < 0 ? 0 : x0; x <= x1 && x < sw->w; x++) {
            const int open = open_pixel(lk, x, sw->w);
            if (open != x) { /* opaque pixels: skip them */
                x = open - 1;
                continue;
            }
            const double pa = ea + (x - sw->ta - ea) / sk;
            const int ia = (int)floor(pa);
            const int i0 = ia < 0 ? 0 : ia > na - 1 ? na - 1 : ia, i1 = ia + 1 > na - 1 ? na - 1 : ia + 1 < 0 ? 0 : ia + 1;
            if (!m0[i0] && !m0[i1])
                continue;
            /* world length of this ray per slice */
            const double ua = (x - sw->ta - ea) / (sw->kref - ec), ub = (yb - eb) / (sw->kref - ec);
            const double delta = sqrt(ua * ua * sw->wsz[0] * sw->wsz[0] + ub * ub * sw->wsz[1] * sw->wsz[1] +
                                      sw->wsz[2] * sw->wsz[2]);
            composite(sw, row + 4 * x, lk, x, k, pa, pb, delta);
        }
    }
}

void vsv_sw_composite_row(void *p, int y, int thread)
{
    vsv_sw *sw = p;
    if (sw->persp) {
        composite_row_persp(sw, y, thread);
        return;
    }
    const int c = sw->c, na = sw->na, nb = sw->nb;
    unsigned char *m0 = sw->mask[thread];
    float *row = sw->img + (size_t)y * sw->w * 4;
    int *lk = sw->link + (size_t)y * sw->w;
    for (int s = 0; s < sw->nc; s++) {
        const int k = sw->front + s * sw->dk;
        const double fa = sw->sa * k + sw->ta, fb = sw->sb * k + sw->tb;
        /* intermediate pixel (x, y) samples voxel coordinates (x - fa, y - fb):
         * the slice is only sheared, so the fractions are the same everywhere */
        const int oa = (int)floor(fa), ob = (int)floor(fb);
        if (y < ob || y > ob + nb)
            continue;
        const int ib0 = y - ob - 1, ib1 = y - ob; /* the two voxel rows under this row */
        memset(m0, 0, (size_t)na + 1);
        scan_mask(sw, c, k, ib0, m0);
        scan_mask(sw, c, k, ib1, m0);
        for (int x = oa; x <= oa + na; x++) {
            const int open = open_pixel(lk, x, sw->w);
            if (open != x) { /* opaque pixels: skip them */
                x = open - 1;
                continue;
            }
            const int ia0 = x - oa - 1, ia1 = x - oa;
            const int mi0 = ia0 < 0 ? 0 : ia0, mi1 = ia1 >= na ? na - 1 : ia1;
            if (!m0[mi0] && !m0[mi1])
                continue; /* transparent voxels around: nothing to add */
            composite(sw, row + 4 * x, lk, x, k, x - fa, y - fb, sw->delta);
        }
    }
}

/* Where the ray of final pixel (px, py) crosses the slice plane k = 0, in
 * intermediate-image coordinates. */
static void warp_point(const vsv_sw *sw, double px, double py, double *x, double *y)
{
    const vsv_geo *g = sw->g;
    double o[3], rd[3];
    vsv_pixel_ray(sw->cam, (int)px, (int)py, o, rd);
    const double q[3] = {(o[0] - g->ox) / g->dx, (o[1] - g->oy) / g->dy, (o[2] / g->E - g->oz) / g->dz};
    if (sw->persp) { /* this ray's crossing with the reference slice */
        const double dv[3] = {rd[0] / g->dx, rd[1] / g->dy, rd[2] / (g->dz * g->E)};
        const double t = (sw->kref - q[sw->c]) / dv[sw->c];
        *x = q[sw->a] + t * dv[sw->a] + sw->ta;
        *y = q[sw->b] + t * dv[sw->b] + sw->tb;
        return;
    }
    const double t = -q[sw->c] / sw->dv[sw->c];
    *x = q[sw->a] + t * sw->dv[sw->a] + sw->ta;
    *y = q[sw->b] + t * sw->dv[sw->b] + sw->tb;
}

/* Final row py: the warp is affine (parallel rays), so the intermediate
 * point moves by a constant step per pixel; bilinear there; the ground
 * behind. */
void vsv_sw_warp_row(void *p, int py, int thread)
{
    vsv_sw *sw = p;
    const vsv_geo *g = sw->g;
    const vsv_camera *cam = sw->cam;
    const int w = sw->w, h = sw->h;
    (void)thread;
    double x0w, y0w, x1w, y1w;
    warp_point(sw, 0, py, &x0w, &y0w);
    warp_point(sw, 1, py, &x1w, &y1w);
    const double ddx = x1w - x0w, ddy = y1w - y0w;
    const double st = 0.5 * fmin(fmin(g->dx, g->dy), g->dz * g->E);
    for (int px = 0; px < cam->width; px++) {
        double x = x0w + px * ddx, y = y0w + px * ddy;
        if (sw->persp) /* projective: each ray on its own */
            warp_point(sw, px, py, &x, &y);
        float *dst = sw->out + 4 * ((size_t)py * cam->width + px);
        dst[0] = dst[1] = dst[2] = dst[3] = 0;
        if (sw->depth)
            sw->depth[(size_t)py * cam->width + px] = INFINITY;
        const int xi = (int)floor(x), yi = (int)floor(y);
        const float fx = (float)(x - xi), fy = (float)(y - yi);
        for (int k = 0; k < 4; k++) {
            const int xx = xi + (k & 1), yy = yi + (k >> 1);
            if (xx < 0 || yy < 0 || xx >= w || yy >= h)
                continue;
            const float wq = ((k & 1) ? fx : 1 - fx) * ((k >> 1) ? fy : 1 - fy);
            const float *sp = sw->img + 4 * ((size_t)yy * w + xx);
            for (int ch = 0; ch < 4; ch++)
                dst[ch] += wq * sp[ch];
        }
        if (g->terrain) {
            double o[3], rd[3], t0b, t1b, t_hit = INFINITY;
            vsv_pixel_ray(cam, px, py, o, rd);
            if (vsv_box_hit(o, rd, g->bmin, g->bmax, &t0b, &t1b))
                t_hit = vsv_geo_terrain_hit(g, o, rd, fmax(t0b, 0), t1b, st);
            if (t_hit < INFINITY) {
                float rgb[3];
                vsv_geo_terrain_colour(g, o[0] + t_hit * rd[0], o[1] + t_hit * rd[1], rgb);
                for (int ch = 0; ch < 3; ch++)
                    dst[ch] += (1 - dst[3]) * rgb[ch];
                dst[3] = 1;
                if (sw->depth)
                    sw->depth[(size_t)py * cam->width + px] = (float)t_hit;
            }
        }
    }
}

vsv_sw *vsv_sw_create(int max_threads)
{
    vsv_sw *sw = calloc(1, sizeof *sw);
    if (sw && !(sw->mask = calloc((size_t)max_threads, sizeof *sw->mask))) {
        free(sw);
        return NULL;
    }
    if (sw)
        sw->max_threads = max_threads;
    return sw;
}

void vsv_sw_free(vsv_sw *sw)
{
    if (!sw)
        return;
    free(sw->cls);
    for (int c = 0; c < 3; c++) {
        free(sw->runs[c]);
        free(sw->starts[c]);
    }
    free(sw->img);
    free(sw->link);
    for (int t = 0; sw->mask && t < sw->max_threads; t++)
        free(sw->mask[t]);
    free(sw->mask);
    free(sw);
}

double vsv_sw_build_seconds(const vsv_sw *sw) { return sw->build_seconds; }
