/* vsv_shearwarp.c — Lacroute's shear-warp factorisation, for parallel and
 * perspective projection (slices sheared, or scaled about the eye).
 *
 * Classification applies the species rule per voxel (summed extinction and
 * extinction-weighted colour) into a copy of the volume for the principal
 * viewing axis, built when a view first needs that axis (one copy per axis
 * at most): its scanlines contiguous, each as four planes (red, green, blue,
 * extinction) with empty voxels around them (so the bilinear footprint never
 * needs a bounds test), and, for every pair of adjacent scanlines, the
 * intervals where a sample between them can meet a non-transparent voxel
 * (the run-length part: the union of both scanlines' non-transparent runs,
 * each widened by the one voxel a bilinear footprint reaches). Layout in
 * vsv_sw.h. It runs on the renderer's thread pool, one slice per
 * job.
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
 * Memory: 16 bytes per voxel (and 16 voxels of padding per scanline) for a
 * classified copy and 2 bytes per voxel for its footprints: about 19 bytes
 * per voxel for one viewing axis, 57 when views have used all three. */
#include "vsv_light.h"
#include "vsv_sw.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define OPAQUE 0.998f

/* an intermediate pixel: premultiplied rgb, alpha */
typedef float v4 __attribute__((vector_size(16)));

struct vsv_sw {
    /* per principal axis c (a = c+1, b = c+2 mod 3): the classified copy
     * and its footprints (vsv_sw.h) */
    uint16_t *vox[3];
    size_t vox_cap[3];
    vsv_sw_fp *fps[3];
    uint16_t *ivl[3];
    size_t fps_cap[3], ivl_cap[3];
    uint64_t key; /* what the classification was built from */
    int n[3];
    int valid[3]; /* the copy for this axis is current */
    const vsv_scene *sc; /* during classification */
    unsigned char *clear; /* per layer and brick: every value transparent */
    size_t clear_cap;
    double sigma_unit;
    vsv_light light; /* the classification's lighting */
    float scale; /* the classified copy holds extinction in units of sigma_unit, times scale */
    /* intermediate image (img_stride floats a row), an empty border of one
     * pixel left and top, two right and bottom, and its opaque-pixel links
     * (w + 1 per row, perspective) */
    float *img;
    int *link;
    int *boxes; /* parallel rays: each band's box of pixels with alpha > 0 */
    size_t img_cap, link_cap, boxes_cap;
    /* per thread: a parallel band's group links, or a slice's scanline runs
     * while classifying; a parallel band's planes, or perspective deltas */
    int **scratch;
    float **dscratch;
    size_t scratch_cap, dscratch_cap;
    int max_threads, simd;
    /* the current view (set by begin) */
    const vsv_geo *g;
    const vsv_camera *cam;
    vsv_rays rays;
    float *out, *depth;
    const vsv_ground *ground;
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
        h = mix(h, L->vol ? L->vol->gen : 0);
        h = mix(h, (uint64_t)L->visible);
        uint32_t u;
        memcpy(&u, &L->opacity, 4);
        h = mix(h, u);
        h = mix(h, L->tf ? vsv_crc32c(0, L->tf, sizeof *L->tf) : 0);
    }
    uint64_t e;
    memcpy(&e, &sc->exaggeration, 8);
    h = mix(h, (uint64_t)sc->light);
    for (int a = 0; a < 3 && sc->light; a++) {
        memcpy(&e, &sc->light_dir[a], 8);
        h = mix(h, e);
    }
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

static int axis_a(int c) { return (c + 1) % 3; }
/* pixels in a row of the intermediate image: border, w pixels, two of border */
static size_t img_stride(const vsv_sw *sw) { return (size_t)sw->w + 3; }
static int axis_b(int c) { return (c + 2) % 3; }

/* Checks the classification against the scene (invalidating every axis's
 * copy when anything it depends on changed; begin has checked the grid's
 * size) and sizes the copy for axis c. */
static int classification_for(vsv_sw *sw, const vsv_scene *sc, int c)
{
    const uint64_t key = scene_key(sc);
    if (key != sw->key) {
        sw->valid[0] = sw->valid[1] = sw->valid[2] = 0;
        sw->key = key;
        /* the largest extinction a voxel can have, scaled to 2^14 at most: the
         * half floats keep 2^-28 of it and up, and need no subnormal */
        double smax = 0;
        for (int l = 0; l < sc->nlayers; l++) {
            const vsv_layer *L = &sc->layers[l];
            if (L->visible && L->opacity > 0 && L->vol)
                smax += L->opacity * vsv_tf_max_opacity(L->tf, -INFINITY, INFINITY);
        }
        int e = 0;
        if (smax > 0)
            frexp(smax, &e);
        sw->scale = ldexpf(1, 14 - (e < -40 ? -40 : e > 40 ? 40 : e));
    }
    if (sw->valid[c])
        return 0;
    const size_t na = sw->n[axis_a(c)], nb = sw->n[axis_b(c)], nc = sw->n[c];
    if (grow((void **)&sw->vox[c], &sw->vox_cap[c], nc * (nb + 2) * 4 * VSV_SW_PLANE(na), sizeof(uint16_t)) ||
        grow((void **)&sw->fps[c], &sw->fps_cap[c], nc * (nb + 1), sizeof(vsv_sw_fp)) ||
        grow((void **)&sw->ivl[c], &sw->ivl_cap[c], nc * (nb + 1) * (na + 4), sizeof(uint16_t)))
        return VSV_ENOMEM;
    sw->sc = sc;
    /* bricks a layer leaves transparent need no transfer-function lookups */
    const vsv_volume *v0 = NULL;
    for (int l = 0; l < sc->nlayers && !v0; l++)
        v0 = sc->layers[l].vol;
    const size_t nbk = v0 ? (size_t)v0->nbricks : 0;
    if (grow((void **)&sw->clear, &sw->clear_cap, (size_t)sc->nlayers * nbk + 1, 1))
        return VSV_ENOMEM;
    for (int l = 0; l < sc->nlayers; l++) {
        const vsv_layer *L = &sc->layers[l];
        for (size_t b = 0; b < nbk; b++) {
            const float lo = L->vol && L->vol->bmin[b] == L->vol->bmin[b] ? L->vol->bmin[b] : -INFINITY;
            sw->clear[l * nbk + b] = !L->vol || (size_t)L->vol->nbricks != nbk ||
                                    !(vsv_tf_max_opacity(L->tf, lo, L->vol->bmax[b]) > 0);
        }
    }
    return 0;
}

/* The footprint of two scanlines' runs (n, then n intervals [lo, hi) of
 * non-transparent voxels; NULL: none): a sample at pa touches a voxel of
 * [lo, hi) when floor(pa) lies in [lo - 1, hi - 1], so runs one voxel or
 * less apart merge. Writes the sorted, merged intervals to out (lo, hi
 * pairs), returns their count. */
static int merge_footprints(const uint16_t *A, const uint16_t *B, uint16_t *out)
{
    int na = A ? A[0] : 0, nb = B ? B[0] : 0, i = 0, j = 0, n = 0;
    while (i < na || j < nb) {
        int lo, hi;
        if (j >= nb || (i < na && A[1 + 2 * i] <= B[1 + 2 * j])) {
            lo = A[1 + 2 * i], hi = A[2 + 2 * i];
            i++;
        } else {
            lo = B[1 + 2 * j], hi = B[2 + 2 * j];
            j++;
        }
        if (n && lo <= out[2 * n - 1] + 1) {
            if (hi > out[2 * n - 1])
                out[2 * n - 1] = (uint16_t)hi;
        } else {
            out[2 * n] = (uint16_t)lo;
            out[2 * n + 1] = (uint16_t)hi;
            n++;
        }
    }
    return n;
}

/* The lighting factor of layer L's value v at cell idx: central
 * differences one cell either way, clamped into the grid (a neighbour
 * without data counts as v), as the raycaster's. */
static float sw_shade(const vsv_sw *sw, const vsv_layer *L, const int idx[3], float v)
{
    const vsv_volume *V = L->vol;
    const int n[3] = {V->nx, V->ny, V->nz};
    float d[3];
    for (int a = 0; a < 3; a++) {
        int p[3] = {idx[0], idx[1], idx[2]};
        p[a] = idx[a] + 1 < n[a] ? idx[a] + 1 : n[a] - 1;
        float hi = vsv_volume_at(V, p[0], p[1], p[2]);
        p[a] = idx[a] > 0 ? idx[a] - 1 : 0;
        float lo = vsv_volume_at(V, p[0], p[1], p[2]);
        hi = hi == hi ? hi : v;
        lo = lo == lo ? lo : v;
        d[a] = 0.5f * (hi - lo);
    }
    return vsv_light_shade(&sw->light, v, d, L->tf->scale == VSV_SCALE_LOG, vsv_light_inv_span(L->tf));
}

/* Slice k of the current axis: classified voxels (the empty scanlines and
 * padding too) and the footprints of its scanline pairs. */
void vsv_sw_classify_slice(void *p, int k, int thread)
{
    vsv_sw *sw = p;
    const vsv_scene *sc = sw->sc;
    const int c = sw->c, a = axis_a(c), b = axis_b(c), na = sw->n[a], nb = sw->n[b];
    const size_t P = VSV_SW_PLANE(na), scan = 4 * P;
    uint16_t *slice = sw->vox[c] + (size_t)k * (nb + 2) * scan;
    memset(slice, 0, scan * sizeof *slice);                   /* scanline -1 */
    memset(slice + (nb + 1) * scan, 0, scan * sizeof *slice); /* scanline nb */
    vsv_sw_fp *fps = sw->fps[c] + (size_t)k * (nb + 1);
    uint16_t *const ivl = sw->ivl[c] + (size_t)k * (nb + 1) * (na + 4);
    uint32_t at = 0;
    /* this scanline's runs and the previous one's */
    uint16_t *runs[2] = {(uint16_t *)sw->scratch[thread], (uint16_t *)sw->scratch[thread] + na + 4};
    runs[1][0] = 0;
    for (int ib = 0; ib < nb; ib++) {
        uint16_t *const row = slice + (size_t)(ib + 1) * scan;
        memset(row, 0, scan * sizeof *row);
        uint16_t *iv = runs[ib & 1];
        int cnt = 0, open = 0;
        for (int ia = 0; ia < na; ia++) {
            int idx[3];
            idx[a] = ia, idx[b] = ib, idx[c] = k;
            /* sums in double: exact for a few float terms, so the species
             * order cannot change a bit */
            double cs = 0, cr = 0, cg = 0, cb = 0;
            for (int l = 0; l < sc->nlayers; l++) {
                const vsv_layer *L = &sc->layers[l];
                if (!L->visible || !(L->opacity > 0) || !L->vol)
                    continue;
                const int sh = L->vol->shift;
                const size_t brick =
                    (size_t)(idx[0] >> sh) + L->vol->bdim[0] * ((idx[1] >> sh) + (size_t)L->vol->bdim[1] * (idx[2] >> sh));
                if (sw->clear[l * (size_t)L->vol->nbricks + brick])
                    continue;
                float rgba[4];
                const float val = vsv_volume_at(L->vol, idx[0], idx[1], idx[2]);
                vsv_tf_eval(L->tf, val, rgba);
                const float s = rgba[3] * L->opacity * sw->scale; /* in units of sigma_unit / scale */
                if (s > 0) {
                    cs += s;
                    const double ks = sw->light.on ? (double)s * sw_shade(sw, L, idx, val) : s;
                    cr += ks * rgba[0];
                    cg += ks * rgba[1];
                    cb += ks * rgba[2];
                }
            }
            uint16_t *const v = row + VSV_SW_PAD + ia;
            v[0] = vsv_half((float)cr), v[P] = vsv_half((float)cg), v[2 * P] = vsv_half((float)cb);
            v[3 * P] = vsv_half((float)cs);
            if ((v[3 * P] > 0) != open) { /* a run opens or closes here */
                iv[1 + cnt] = (uint16_t)ia;
                cnt++;
                open = !open;
            }
        }
        if (open)
            iv[1 + cnt++] = (uint16_t)na;
        iv[0] = (uint16_t)(cnt / 2);
        fps[ib] = (vsv_sw_fp){at, (uint32_t)merge_footprints(runs[(ib + 1) & 1], iv, ivl + at)}; /* pair (ib - 1, ib) */
        at += 2 * fps[ib].n;
    }
    fps[nb] = (vsv_sw_fp){at, (uint32_t)merge_footprints(runs[(nb + 1) & 1], NULL, ivl + at)}; /* pair (nb - 1, nb) */
}

void vsv_sw_classified(vsv_sw *sw, double seconds)
{
    sw->valid[sw->c] = 1;
    sw->build_seconds = seconds;
    sw->sc = NULL;
}

int vsv_sw_begin(vsv_sw *sw, const vsv_scene *sc, const vsv_geo *g, const vsv_camera *cam, float *out, float *depth,
                 const vsv_ground *ground, int *rows, int *classify)
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
    sw->a = axis_a(c);
    sw->b = axis_b(c);
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
    if (grow((void **)&sw->img, &sw->img_cap, W * (sw->h + 3) * 4, sizeof(float)) ||
        grow((void **)&sw->link, &sw->link_cap, ((size_t)sw->w + 1) * sw->h, sizeof(int)) ||
        grow((void **)&sw->boxes, &sw->boxes_cap, 4 * ((size_t)sw->h / VSV_SW_BAND + 1), sizeof(int)))
        return VSV_ENOMEM;
    /* per thread: two scanlines' runs (uint16) or a band's group links; a
     * band's planes or a row's perspective deltas */
    const size_t ng = vsv_sw_par_groups(sw->w), nl = VSV_SW_BAND * (ng + 1);
    const size_t ni = (size_t)sw->na + 4 > nl ? (size_t)sw->na + 4 : nl, nf = VSV_SW_BAND * 4 * ng * VSV_SW_LANES;
    for (int t = 0; t < sw->max_threads; t++) {
        size_t ci = sw->scratch_cap, cf = sw->dscratch_cap;
        if (grow((void **)&sw->scratch[t], &ci, ni, sizeof(int)) || grow((void **)&sw->dscratch[t], &cf, nf, sizeof(float)))
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
    sw->depth = depth;
    *rows = sw->persp ? sw->h : (sw->h + VSV_SW_BAND - 1) / VSV_SW_BAND;
    int rc = classification_for(sw, sc, c);
    if (rc)
        return rc;
    *classify = sw->valid[c] ? 0 : sw->nc;
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
static inline __attribute__((always_inline)) void sample(v4 *px, int *lk, int x, const uint16_t *t0,
                                                         const uint16_t *t1, size_t P, const v4 w, float d)
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
        const vsv_sw_par par = {sw->vox[c], sw->fps[c], sw->ivl[c], VSV_SW_PLANE(na), na, nb, sw->nc, w, sw->front, sw->dk,
                                sw->sa, sw->sb, sw->ta, sw->tb, (float)(sw->delta * sw->sigma_unit / sw->scale)};
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

/* Final row py: each pixel's ray meets the reference plane (k = kref for
 * perspective, 0 for parallel rays) at an intermediate-image point; bilinear
 * there, the point clamped into the image's empty border (no test per
 * pixel); the ground behind. */
static void warp_row(vsv_sw *sw, int py)
{
    const vsv_geo *g = sw->g;
    const vsv_camera *cam = sw->cam;
    const int w = sw->w, h = sw->h, a = sw->a, b = sw->b, c = sw->c;
    const size_t W = img_stride(sw);
    double o0[3], o1[3], d0[3], d1[3];
    row_rays(sw, py, o0, o1, d0, d1);
    const double kp = sw->persp ? sw->kref : 0;
    float *const out = sw->out + 4 * (size_t)py * cam->width;
    float *dep = sw->depth ? sw->depth + (size_t)py * cam->width : NULL;
    if (dep)
        for (int px = 0; px < cam->width; px++)
            dep[px] = INFINITY;
    /* the pixels whose point can fall where the image is not empty: all of
     * them for perspective, an interval for parallel rays (the point moves
     * linearly; the others are cleared): a point (x, y) reads pixels floor(x),
     * floor(x) + 1, so it can meet the box of pixels with alpha > 0, [bx0,
     * bx1] x [by0, by1], when bx0 - 1 <= x < bx1 + 1 and likewise y */
    int p0 = 0, p1 = cam->width - 1;
    double x0 = 0, y0 = 0, ddx = 0, ddy = 0;
    if (!sw->persp) {
        int box[4] = {INT_MAX, -1, INT_MAX, -1};
        for (int i = 0; i < (h + VSV_SW_BAND - 1) / VSV_SW_BAND; i++) {
            const int *bb = sw->boxes + 4 * i;
            box[0] = bb[0] < box[0] ? bb[0] : box[0];
            box[1] = bb[1] > box[1] ? bb[1] : box[1];
            box[2] = bb[2] < box[2] ? bb[2] : box[2];
            box[3] = bb[3] > box[3] ? bb[3] : box[3];
        }
        const double t = (kp - o0[c]) / d0[c];
        x0 = o0[a] + t * d0[a] + sw->ta, y0 = o0[b] + t * d0[b] + sw->tb;
        const double tx = (kp - o0[c] - o1[c]) / d0[c];
        ddx = o0[a] + o1[a] + tx * d0[a] + sw->ta - x0, ddy = o0[b] + o1[b] + tx * d0[b] + sw->tb - y0;
        double lo = 0, hi = box[0] <= box[1] ? cam->width - 1 : -1;
        const double v0[2] = {x0, y0}, dv[2] = {ddx, ddy};
        const double lim0[2] = {box[0] - 1.0, box[2] - 1.0}, lim1[2] = {box[1] + 1.0, box[3] + 1.0};
        for (int i = 0; i < 2; i++) {
            if (dv[i] == 0) {
                if (v0[i] < lim0[i] || v0[i] >= lim1[i])
                    hi = -1;
                continue;
            }
            const double e0 = (lim0[i] - v0[i]) / dv[i], e1 = (lim1[i] - v0[i]) / dv[i];
            lo = fmax(lo, fmin(e0, e1) - 1);
            hi = fmin(hi, fmax(e0, e1) + 1);
        }
        p0 = (int)fmax(0, floor(lo));
        p1 = (int)fmin(cam->width - 1, ceil(hi));
    }
    if (p1 < p0)
        p0 = cam->width, p1 = cam->width - 1;
    memset(out, 0, sizeof(float) * 4 * p0);
    memset(out + 4 * (p1 + 1), 0, sizeof(float) * 4 * (cam->width - 1 - p1));
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
    if (!g->terrain)
        return;
    const vsv_ground *gr = sw->ground + (size_t)py * cam->width;
    for (int px = 0; px < cam->width; px++) {
        if (!(gr[px].t < INFINITY))
            continue;
        float *dst = out + 4 * px;
        for (int ch = 0; ch < 3; ch++)
            dst[ch] += (1 - dst[3]) * gr[px].rgb[ch];
        dst[3] = 1;
        if (dep)
            dep[px] = gr[px].t;
    }
}

/* Final rows job * VSV_SW_WARP_ROWS onwards: a thread's rows adjacent, so
 * the intermediate pixels one row reads are in its cache for the next. */
void vsv_sw_warp_rows(void *p, int job, int thread)
{
    vsv_sw *sw = p;
    (void)thread;
    for (int py = job * VSV_SW_WARP_ROWS; py < (job + 1) * VSV_SW_WARP_ROWS && py < sw->cam->height; py++)
        warp_row(sw, py);
}

vsv_sw *vsv_sw_create(int max_threads, int simd)
{
    vsv_sw *sw = calloc(1, sizeof *sw);
    if (!sw)
        return NULL;
    sw->scratch = calloc((size_t)max_threads, sizeof *sw->scratch);
    sw->dscratch = calloc((size_t)max_threads, sizeof *sw->dscratch);
    if (!sw->scratch || !sw->dscratch) {
        vsv_sw_free(sw);
        return NULL;
    }
    sw->max_threads = max_threads; /* the opacity table: vsv_renderer_create */
    sw->simd = simd;
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
    }
    free(sw->img);
    free(sw->link);
    free(sw->boxes);
    free(sw->clear);
    for (int t = 0; t < sw->max_threads; t++) {
        if (sw->scratch)
            free(sw->scratch[t]);
        if (sw->dscratch)
            free(sw->dscratch[t]);
    }
    free(sw->scratch);
    free(sw->dscratch);
    free(sw);
}

double vsv_sw_build_seconds(const vsv_sw *sw) { return sw->build_seconds; }
