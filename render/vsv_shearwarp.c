/* vsv_shearwarp.c — Lacroute's shear-warp factorisation, for parallel and
 * perspective projection (slices sheared, or scaled about the eye).
 *
 * Classification (vsv_sw_classify.c) applies the species rule per voxel
 * (summed extinction and extinction-weighted colour) into a copy of the
 * volume for the principal viewing axis, built when a view first needs that
 * axis (one copy per axis at most): its scanlines contiguous, each as four
 * planes (red, green, blue, extinction) with empty voxels around them (so
 * the bilinear footprint never needs a bounds test), and, for every pair of
 * adjacent scanlines, the intervals where a sample between them can meet a
 * non-transparent voxel (the run-length part). Layout in vsv_sw.h.
 *
 * A frame composites slices perpendicular to the principal viewing axis front
 * to back into an intermediate image, one intermediate row per job: the
 * footprints of the scanline pair under the row say which pixels can receive
 * anything, pixels already opaque are skipped through per-row links, samples
 * are bilinear inside the slice. For parallel rays a row is eight pixels a
 * step (vsv_sw_row.c: every pixel of the row has the same bilinear weights);
 * for perspective one pixel a step, opacity from the table of (1 - e^-u)/u.
 * One 2-D warp (affine for parallel rays, projective for perspective)
 * resamples the intermediate image into the final one. The ground is the
 * raycaster's height field, met by each final pixel's ray and composited
 * behind the volume (cells below the ground hold no data).
 *
 * Memory: 8 bytes per voxel (and 16 voxels of padding per scanline) for a
 * classified copy and 2 bytes per voxel for its footprints, about 11 bytes
 * per voxel for one viewing axis, 33 when views have used all three; and
 * 8 bytes per cell of the bricks for the classified bricks. */
#include "vsv_sw.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define OPAQUE 0.998f

/* an intermediate pixel: premultiplied rgb, alpha */
typedef float v4 __attribute__((vector_size(16)));

/* pixels in a row of the intermediate image: border, w pixels, two of border */
static size_t img_stride(const vsv_sw *sw) { return (size_t)sw->w + 3; }

int vsv_sw_begin(vsv_sw *sw, const vsv_scene *sc, const vsv_geo *g, const vsv_camera *cam, float *out,
                 unsigned char *out8, float *depth, const vsv_ground *ground, int *rows, int *bricks, int *classify)
{
    sw->ground = ground;
    if (sw->n[0] != g->nx || sw->n[1] != g->ny || sw->n[2] != g->nz) {
        sw->valid[0] = sw->valid[1] = sw->valid[2] = 0;
        sw->n[0] = g->nx;
        sw->n[1] = g->ny;
        sw->n[2] = g->nz;
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
    sw->a = vsv_sw_axis_a(c);
    sw->b = vsv_sw_axis_b(c);
    sw->na = sw->n[sw->a];
    sw->nb = sw->n[sw->b];
    sw->nc = sw->n[c];
    sw->sa = -sw->dv[sw->a] / sw->dv[c];
    sw->sb = -sw->dv[sw->b] / sw->dv[c];
    sw->ta = -fmin(0, sw->sa * (sw->nc - 1)) + 1;
    sw->tb = -fmin(0, sw->sb * (sw->nc - 1)) + 1;
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
        sw->wsz[0] = sizes[sw->a];
        sw->wsz[1] = sizes[sw->b];
        sw->wsz[2] = sizes[c];
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
        const double ea = sw->eye[sw->a], eb = sw->eye[sw->b];
        double lo_a = fmin(-1.0, ea + (-1 - ea) * sfar), hi_a = fmax((double)sw->na, ea + (sw->na - ea) * sfar);
        double lo_b = fmin(-1.0, eb + (-1 - eb) * sfar), hi_b = fmax((double)sw->nb, eb + (sw->nb - eb) * sfar);
        sw->ta = -lo_a;
        sw->tb = -lo_b;
        sw->w = (int)ceil(hi_a - lo_a) + 2;
        sw->h = (int)ceil(hi_b - lo_b) + 2;
    }
    /* buffers grow with the view and are reused: no allocation per frame */
    const size_t W = img_stride(sw);
    if (vsv_sw_grow((void **)&sw->img, &sw->img_cap, W * (sw->h + 3) * 4, sizeof(float)) ||
        vsv_sw_grow((void **)&sw->link, &sw->link_cap, ((size_t)sw->w + 1) * sw->h, sizeof(int)) ||
        vsv_sw_grow((void **)&sw->boxes, &sw->boxes_cap, 4 * ((size_t)sw->h / VSV_SW_BAND + 1), sizeof(int)))
        return VSV_ENOMEM;
    /* per thread: two scanlines' runs (uint16) or a band's group links; a
     * band's planes or a row's perspective deltas; a final row's floats
     * (bytes out) */
    const size_t ng = vsv_sw_par_groups(sw->w), nl = VSV_SW_BAND * (ng + 1);
    const size_t ni = (size_t)sw->na + 4 > nl ? (size_t)sw->na + 4 : nl;
    size_t nf = VSV_SW_BAND * 4 * ng * VSV_SW_LANES;
    nf = out8 && 4 * (size_t)cam->width > nf ? 4 * (size_t)cam->width : nf;
    for (int t = 0; t < sw->max_threads; t++) {
        size_t ci = sw->scratch_cap, cf = sw->dscratch_cap;
        if (vsv_sw_grow((void **)&sw->scratch[t], &ci, ni, sizeof(int)) ||
            vsv_sw_grow((void **)&sw->dscratch[t], &cf, nf, sizeof(float)))
            return VSV_ENOMEM;
    }
    if (ni > sw->scratch_cap)
        sw->scratch_cap = ni;
    if (nf > sw->dscratch_cap)
        sw->dscratch_cap = nf;
    /* the border rows; each composited row clears itself */
    memset(sw->img, 0, W * 4 * sizeof(float));
    memset(sw->img + W * (sw->h + 1) * 4, 0, 2 * W * 4 * sizeof(float));
    sw->g = g;
    sw->sigma_unit = VSV_SIGMA_PER_CELL / fmin(g->dx, g->dy);
    vsv_light_init(&sw->light, sc, g);
    sw->cam = cam;
    vsv_rays_init(&sw->rays, cam);
    sw->out = out;
    sw->out8 = out8;
    sw->depth = depth;
    *rows = sw->persp ? sw->h : (sw->h + VSV_SW_BAND - 1) / VSV_SW_BAND;
    int rc = vsv_sw_classification_for(sw, sc, c);
    if (rc)
        return rc;
    const size_t B = (size_t)1 << sw->shift;
    for (int t = 0; t < sw->max_threads; t++) {
        size_t ca = sw->cacc_cap;
        if (vsv_sw_grow((void **)&sw->cacc[t], &ca, 4 * B, sizeof(double)))
            return VSV_ENOMEM;
    }
    if (4 * B > sw->cacc_cap)
        sw->cacc_cap = 4 * B;
    *bricks = sw->ncjobs;
    *classify = sw->njobs;
    return 0;
}

/* Opaque-pixel skipping: the first pixel at or after x of this row that is
 * not yet opaque (w when none), following the links and shortening the one
 * at x to point there. */
static int open_pixel(int *lk, int x)
{
    int xx = x;
    while (lk[xx] != xx)
        xx = lk[xx];
    if (xx != x)
        lk[x] = xx;
    return xx;
}

/* The bilinear blend (weights w) of plane ch of voxels t0[0], t0[1],
 * t1[0], t1[1]. */
static inline float blend(const uint16_t *t0, const uint16_t *t1, size_t ch, const v4 w)
{
    return w[0] * vsv_half_float(t0[ch]) + w[1] * vsv_half_float(t0[ch + 1]) + w[2] * vsv_half_float(t1[ch]) +
           w[3] * vsv_half_float(t1[ch + 1]);
}

/* One pixel: the blend of voxels t0[0], t0[1], t1[0], t1[1] (each four
 * planes P apart) composited over px with d units of ray per slice; opaque
 * pixels are linked past. */
static inline __attribute__((always_inline)) void sample(v4 *px, int *lk, int x, const uint16_t *t0, const uint16_t *t1,
                                                         size_t P, const v4 w, float d)
{
    const float S = blend(t0, t1, 3 * P, w);
    if (!(S > 0))
        return;
    const v4 acc = {blend(t0, t1, 0, w), blend(t0, t1, P, w), blend(t0, t1, 2 * P, w), S};
    const float f = vsv_opacity_per_u(S * d);
    *px += ((1 - (*px)[3]) * d * f) * acc; /* transmittance x alpha / S */
    if ((*px)[3] >= OPAQUE)
        lk[x] = x + 1;
}

static v4 weights(float fu, float fv) { return (v4){(1 - fu) * (1 - fv), fu * (1 - fv), (1 - fu) * fv, fu * fv}; }

/* Intermediate row y (perspective), or band y of VSV_SW_BAND rows (parallel
 * rays: vsv_sw_row.c), through every slice, front to back. For perspective,
 * slice k samples the voxel coordinates pa = pa0 + x / s_k, pb along the
 * row, one pixel a step. */
void vsv_sw_composite_row(void *p, int y, int thread)
{
    vsv_sw *sw = p;
    const int c = sw->c, na = sw->na, nb = sw->nb, w = sw->w;
    const size_t W = img_stride(sw);
    if (!sw->persp) {
        const vsv_sw_par par = {
            sw->vox[c], sw->fps[c], sw->ivl[c], VSV_SW_PLANE(na), na,
            nb,         sw->nc,     w,          sw->front,        sw->dk,
            sw->sa,     sw->sb,     sw->ta,     sw->tb,           (float)(sw->delta * sw->sigma_unit / sw->scale)};
        const int y0 = y * VSV_SW_BAND, n = sw->h - y0 < VSV_SW_BAND ? sw->h - y0 : VSV_SW_BAND;
        float *const row = sw->img + ((size_t)y0 + 1) * W * 4;
        for (int j = 0; j < n; j++) { /* the border pixels */
            memset(row + j * W * 4, 0, 4 * sizeof(float));
            memset(row + (j * W + w + 1) * 4, 0, 2 * 4 * sizeof(float));
        }
        (sw->simd ? vsv_sw_par_rows_avx2 : vsv_sw_par_rows)(&par, y0, n, sw->dscratch[thread], sw->scratch[thread],
                                                            row + 4, W * 4, sw->boxes + 4 * y);
        return;
    }
    float *row = sw->img + ((size_t)y + 1) * W * 4;
    memset(row, 0, W * 4 * sizeof(float));
    v4 *const img = (v4 *)row + 1; /* pixel 0 */
    int *lk = sw->link + (size_t)y * (w + 1);
    for (int x = 0; x <= w; x++)
        lk[x] = x;
    float *dl = sw->dscratch[thread];
    const double ea = sw->eye[sw->a], eb = sw->eye[sw->b], ec = sw->eye[c];
    /* each pixel's ray per slice, in the extinction's units */
    const double ub = (y - sw->tb - eb) / (sw->kref - ec);
    const double kb = ub * ub * sw->wsz[1] * sw->wsz[1] + sw->wsz[2] * sw->wsz[2];
    for (int x = 0; x < w; x++) {
        const double ua = (x - sw->ta - ea) / (sw->kref - ec);
        dl[x] = (float)(sqrt(ua * ua * sw->wsz[0] * sw->wsz[0] + kb) * sw->sigma_unit / sw->scale);
    }
    const size_t P = VSV_SW_PLANE(na), scan = 4 * P, slice = (size_t)(nb + 2) * scan;
    for (int s = 0; s < sw->nc; s++) {
        const int k = sw->front + s * sw->dk;
        const double sk = (sw->kref - ec) / (k - ec);
        const double dpa = 1 / sk, pa0 = ea - (sw->ta + ea) / sk, pb = eb + (y - sw->tb - eb) / sk;
        if (!(pb >= -1) || !(pb < nb))
            continue;
        const int ib = (int)(pb + 1) - 1;
        const float fv = (float)(pb - ib);
        const vsv_sw_fp fp = sw->fps[c][(size_t)k * (nb + 1) + ib + 1];
        const uint16_t *iv = sw->ivl[c] + (size_t)k * (nb + 1) * (na + 4) + fp.at;
        /* voxel ia of scanline ib at r0 + ia, of ib + 1 at r1 + ia */
        const uint16_t *r0 = sw->vox[c] + k * slice + (size_t)(ib + 1) * scan + VSV_SW_PAD, *r1 = r0 + scan;
        for (uint32_t q = 0; q < fp.n; q++) {
            /* pixels whose pa lies in [lo - 1, hi) */
            int x = (int)ceil((iv[2 * q] - 1 - pa0) / dpa), xe = (int)ceil((iv[2 * q + 1] - pa0) / dpa) - 1;
            if (x < 0)
                x = 0;
            if (xe > w - 1)
                xe = w - 1;
            for (; x <= xe; x++) {
                x = open_pixel(lk, x);
                if (x > xe)
                    break;
                const float pa = (float)(pa0 + x * dpa);
                const int ip = (int)(pa + 1) - 1; /* pa >= -1 */
                sample(img + x, lk, x, r0 + ip, r1 + ip, P, weights(pa - ip, fv), dl[x]);
            }
        }
    }
}

/* Ray of final pixel px on row py: o(px) = o0 + px o1, direction along
 * d0 + px d1 (not unit length), in voxel index coordinates. */
static void row_rays(const vsv_sw *sw, int py, double o0[3], double o1[3], double d0[3], double d1[3])
{
    const vsv_geo *g = sw->g;
    double oa[3], ra[3], ob[3], rb[3];
    vsv_rays_get(&sw->rays, 0, py, oa, ra);
    vsv_rays_get(&sw->rays, 1, py, ob, rb);
    if (sw->persp) { /* unit directions: undo the normalisation through the forward component */
        double f[3] = {sw->cam->dir[0], sw->cam->dir[1], sw->cam->dir[2]};
        const double fl = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
        const double na = fl / (ra[0] * f[0] + ra[1] * f[1] + ra[2] * f[2]);
        const double nb = fl / (rb[0] * f[0] + rb[1] * f[1] + rb[2] * f[2]);
        for (int i = 0; i < 3; i++) {
            ra[i] *= na;
            rb[i] *= nb;
        }
    }
    const double sc[3] = {g->dx, g->dy, g->dz * g->E};
    const double qa[3] = {(oa[0] - g->ox) / g->dx, (oa[1] - g->oy) / g->dy, (oa[2] / g->E - g->oz) / g->dz};
    const double qb[3] = {(ob[0] - g->ox) / g->dx, (ob[1] - g->oy) / g->dy, (ob[2] / g->E - g->oz) / g->dz};
    for (int i = 0; i < 3; i++) {
        o0[i] = qa[i];
        o1[i] = qb[i] - qa[i];
        d0[i] = ra[i] / sc[i];
        d1[i] = (rb[i] - ra[i]) / sc[i];
    }
}

/* The pixels [*p0, *p1] of a final row of width pixels (parallel rays)
 * whose point (x0 + px dx, y0 + px dy) can meet a band's box of pixels with
 * alpha > 0, [bx0, bx1] x [by0, by1]: a point (x, y) reads pixels floor(x),
 * floor(x) + 1, so when bx0 - 1 <= x < bx1 + 1 and likewise y (a pixel more
 * each side, for rounding); the hull over the bands the row's points pass,
 * empty (p1 < p0) when none. Per band, not over their union: a row across a
 * sparse field meets the boxes of few bands, and those only in part. */
static void par_span(const vsv_sw *sw, double x0, double y0, double dx, double dy, int width, int *p0, int *p1)
{
    /* the bands the row's y can reach (NaN: all of them) */
    const int last = (sw->h + VSV_SW_BAND - 1) / VSV_SW_BAND - 1;
    const double ya = y0, yb = y0 + (width - 1) * dy, ymin = ya < yb ? ya : yb, ymax = ya < yb ? yb : ya;
    const double f0 = floor((ymin - 2) / VSV_SW_BAND), f1 = floor((ymax + 2) / VSV_SW_BAND);
    const int i0 = f0 > 0 ? (f0 < last ? (int)f0 : last) : 0, i1 = f1 < last ? (f1 >= 0 ? (int)f1 : -1) : last;
    const double v0[2] = {x0, y0}, dv[2] = {dx, dy}, inv[2] = {dx != 0 ? 1 / dx : 0, dy != 0 ? 1 / dy : 0};
    int lo = width, hi = -1;
    for (int i = i0; i <= i1; i++) {
        const int *bb = sw->boxes + 4 * i;
        if (bb[0] > bb[1])
            continue;
        double e_lo = 0, e_hi = width - 1;
        const double lim0[2] = {bb[0] - 1.0, bb[2] - 1.0}, lim1[2] = {bb[1] + 1.0, bb[3] + 1.0};
        for (int k = 0; k < 2; k++) {
            if (dv[k] == 0) {
                if (!(v0[k] >= lim0[k] && v0[k] < lim1[k]))
                    e_hi = -1;
                continue;
            }
            const double e0 = (lim0[k] - v0[k]) * inv[k], e1 = (lim1[k] - v0[k]) * inv[k];
            const double el = (e0 < e1 ? e0 : e1) - 1, eh = (e0 < e1 ? e1 : e0) + 1;
            e_lo = el > e_lo ? el : e_lo;
            e_hi = eh < e_hi ? eh : e_hi;
        }
        if (!(e_lo <= e_hi))
            continue;
        const int l = (int)floor(e_lo), h = (int)ceil(e_hi);
        lo = l < lo ? l : lo;
        hi = h > hi ? h : hi;
    }
    *p0 = lo, *p1 = hi;
}

/* Final row py: each pixel's ray meets the reference plane (k = kref for
 * perspective, 0 for parallel rays) at an intermediate-image point; bilinear
 * there, the point clamped into the image's empty border (no test per
 * pixel); the ground behind. */
static void warp_row(vsv_sw *sw, int py, int thread)
{
    const vsv_geo *g = sw->g;
    const vsv_camera *cam = sw->cam;
    const int w = sw->w, h = sw->h, a = sw->a, b = sw->b, c = sw->c;
    const size_t W = img_stride(sw);
    double o0[3], o1[3], d0[3], d1[3];
    row_rays(sw, py, o0, o1, d0, d1);
    const double kp = sw->persp ? sw->kref : 0;
    /* bytes out: the row's floats in the thread's scratch (in its cache),
     * then bytes; cleared pixels straight to bytes */
    unsigned char *const out8 = sw->out8 ? sw->out8 + 4 * (size_t)py * cam->width : NULL;
    float *const out = out8 ? sw->dscratch[thread] : sw->out + 4 * (size_t)py * cam->width;
    float *dep = sw->depth ? sw->depth + (size_t)py * cam->width : NULL;
    if (dep)
        for (int px = 0; px < cam->width; px++)
            dep[px] = INFINITY;
    /* the pixels whose point can fall where the image is not empty: all of
     * them for perspective, for parallel rays those whose point (it moves
     * linearly) meets a band's box of pixels with alpha > 0 (the others are
     * cleared) */
    int p0 = 0, p1 = cam->width - 1;
    double x0 = 0, y0 = 0, ddx = 0, ddy = 0;
    if (!sw->persp) {
        const double t = (kp - o0[c]) / d0[c];
        x0 = o0[a] + t * d0[a] + sw->ta, y0 = o0[b] + t * d0[b] + sw->tb;
        const double tx = (kp - o0[c] - o1[c]) / d0[c];
        ddx = o0[a] + o1[a] + tx * d0[a] + sw->ta - x0, ddy = o0[b] + o1[b] + tx * d0[b] + sw->tb - y0;
        par_span(sw, x0, y0, ddx, ddy, cam->width, &p0, &p1);
        p0 -= p0 % VSV_SW_LANES; /* groups of eight from a multiple of eight: a pixel's point never depends on p0 */
    }
    if (p1 < p0)
        p0 = cam->width, p1 = cam->width - 1;
    if (out8 && !g->terrain) {
        memset(out8, 0, 4 * (size_t)p0);
        memset(out8 + 4 * (p1 + 1), 0, 4 * (size_t)(cam->width - 1 - p1));
    } else {
        memset(out, 0, sizeof(float) * 4 * p0);
        memset(out + 4 * (p1 + 1), 0, sizeof(float) * 4 * (cam->width - 1 - p1));
    }
    if (!sw->persp) /* eight pixels a step (vsv_sw_row.c) */
        (sw->simd ? vsv_sw_par_warp_avx2 : vsv_sw_par_warp)(sw->img, W, w, h, x0 + 1, y0 + 1, ddx, ddy, p0, p1, out);
    /* perspective: border coordinates (pixel i at i + 1) clamped into [0, w +
     * 1] x [0, h + 1], so a point outside the image reads only border pixels
     * (NaN too) */
    const float xmax = (float)w + 1, ymax = (float)h + 1;
    for (int px = 0; px < cam->width && sw->persp; px++) {
        const double qa = o0[a], qb = o0[b], qc = o0[c]; /* the eye */
        const double va = d0[a] + px * d1[a], vb = d0[b] + px * d1[b], vc = d0[c] + px * d1[c];
        const double t = (kp - qc) / vc;
        const double x = qa + t * va + sw->ta, y = qb + t * vb + sw->tb;
        float fx = (float)(x + 1), fy = (float)(y + 1);
        fx = !(fx > 0) ? 0 : fx < xmax ? fx : xmax;
        fy = !(fy > 0) ? 0 : fy < ymax ? fy : ymax;
        const int xi = (int)fx, yi = (int)fy;
        fx -= xi, fy -= yi;
        const v4 *s0 = (const v4 *)(sw->img + 4 * ((size_t)yi * W + xi)), *s1 = s0 + W;
        *(v4 *)(out + 4 * px) = (1 - fy) * ((1 - fx) * s0[0] + fx * s0[1]) + fy * ((1 - fx) * s1[0] + fx * s1[1]);
    }
    const vsv_ground *gr = g->terrain ? sw->ground + (size_t)py * cam->width : NULL;
    for (int px = 0; gr && px < cam->width; px++) {
        if (!(gr[px].t < INFINITY))
            continue;
        float *dst = out + 4 * px;
        for (int ch = 0; ch < 3; ch++)
            dst[ch] += (1 - dst[3]) * gr[px].rgb[ch];
        dst[3] = 1;
        if (dep)
            dep[px] = gr[px].t;
    }
    if (out8 && gr)
        vsv_sw_bytes(out, 4 * (size_t)cam->width, out8);
    else if (out8 && p1 >= p0) /* (the others cleared above) */
        vsv_sw_bytes(out + 4 * p0, 4 * (size_t)(p1 - p0 + 1), out8 + 4 * p0);
}

/* Final rows job * VSV_SW_WARP_ROWS onwards: a thread's rows adjacent, so
 * the intermediate pixels one row reads are in its cache for the next. */
void vsv_sw_warp_rows(void *p, int job, int thread)
{
    vsv_sw *sw = p;
    for (int py = job * VSV_SW_WARP_ROWS; py < (job + 1) * VSV_SW_WARP_ROWS && py < sw->cam->height; py++)
        warp_row(sw, py, thread);
}

vsv_sw *vsv_sw_create(int max_threads, int simd)
{
    vsv_sw *sw = calloc(1, sizeof *sw);
    if (!sw)
        return NULL;
    sw->scratch = calloc((size_t)max_threads, sizeof *sw->scratch);
    sw->dscratch = calloc((size_t)max_threads, sizeof *sw->dscratch);
    sw->cacc = calloc((size_t)max_threads, sizeof *sw->cacc);
    if (!sw->scratch || !sw->dscratch || !sw->cacc) {
        vsv_sw_free(sw);
        return NULL;
    }
    sw->max_threads = max_threads; /* the opacity table: vsv_renderer_create */
    sw->simd = simd;
    sw->solo = -1;
    return sw;
}

void vsv_sw_free(vsv_sw *sw)
{
    if (!sw)
        return;
    for (int c = 0; c < 3; c++) {
        free(sw->vox[c]);
        free(sw->fps[c]);
        free(sw->ivl[c]);
        free(sw->held[c]);
    }
    free(sw->img);
    free(sw->link);
    free(sw->boxes);
    free(sw->clear);
    free(sw->cur);
    free(sw->jobs);
    for (int c = 0; c < 3; c++)
        free(sw->keys[c]);
    for (int t = 0; t < sw->max_threads; t++) {
        if (sw->scratch)
            free(sw->scratch[t]);
        if (sw->dscratch)
            free(sw->dscratch[t]);
        if (sw->cacc)
            free(sw->cacc[t]);
    }
    free(sw->cacc);
    free(sw->cls);
    free(sw->pos);
    free(sw->ckeys);
    free(sw->cok);
    free(sw->bnz);
    free(sw->ltab);
    free(sw->cjobs);
    free(sw->scratch);
    free(sw->dscratch);
    free(sw);
}

double vsv_sw_build_seconds(const vsv_sw *sw) { return sw->build_seconds; }
int vsv_sw_build_bricks(const vsv_sw *sw) { return sw->built_bricks; }
