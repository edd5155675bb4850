/* vsv_raycast.c — the raycaster: the frame's visible layers and empty-space
 * skipping, the one-ray sample loop, the rays of a row of pixels, the
 * ground cache, and the tiles the pool hands out. Each pixel depends only on
 * the scene and its own ray, so the thread count and the tile order cannot
 * change a pixel. */
#include "vsv_renderer.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The camera's rays in cell coordinates, counted in steps (vsv_rc_cam),
 * from this frame's rays (r->rays), geometry and step. */
static void rc_cam(vsv_renderer *r)
{
    const vsv_rays *R = &r->rays;
    const vsv_geo *g = &r->g;
    vsv_rc_frame *F = &r->frame;
    vsv_rc_cam *C = &F->cam;
    const double org[3] = {g->ox, g->oy, g->oz * g->E};
    for (int a = 0; a < 3; a++) {
        const double per_step = F->st * F->inv_cell[a]; /* cells a world step along axis a */
        C->o[a] = (float)((R->o[a] - org[a]) * F->inv_cell[a]);
        C->f[a] = (float)(R->f[a] * per_step);
        /* perspective: the direction per unit of sx, sy; parallel: the origin */
        C->r[a] = (float)(R->r[a] * (R->persp ? per_step : F->inv_cell[a]));
        C->u[a] = (float)(R->u[a] * (R->persp ? per_step : F->inv_cell[a]));
        C->bmin[a] = (float)((g->bmin[a] - org[a]) * F->inv_cell[a]);
        C->bmax[a] = (float)((g->bmax[a] - org[a]) * F->inv_cell[a]);
    }
    /* vsv_rays_get: sx = cx + kx (2 (px + 1/2) / w - 1), sy = cy + ky (1 - 2 (py + 1/2) / h) */
    C->sxk = (float)(2 * R->kx / R->w);
    C->sx0 = (float)(R->cx + R->kx * (1 / R->w - 1));
    C->syk = (float)(-2 * R->ky / R->h);
    C->sy0 = (float)(R->cy + R->ky * (1 - 1 / R->h));
    C->snear = (float)(r->cam->znear > 0 ? r->cam->znear * F->inv_st : 0);
    C->sfar = r->cam->zfar > 0 ? (float)(r->cam->zfar * F->inv_st) : INFINITY;
    C->persp = R->persp;
}

/* The raycaster's frame: its visible layers, their sampling copies to
 * rebuild (r->build), the grid and the step. vsv_rc_prepare_skip follows
 * once the copies are built. */
int vsv_rc_prepare_frame(vsv_renderer *r, const vsv_scene *sc, int copies)
{
    if (sc->nlayers > r->act_cap) {
        vsv_rc_layer *p = realloc(r->act, (size_t)sc->nlayers * sizeof *p);
        if (!p)
            return VSV_ENOMEM;
        r->act = p;
        r->act_cap = sc->nlayers;
    }
    if (sc->nlayers > r->copy_cap) {
        vsv_rc_copy *c = realloc(r->copy, (size_t)sc->nlayers * sizeof *c);
        vsv_rc_copy **b = c ? realloc(r->build, (size_t)sc->nlayers * sizeof *b) : NULL;
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
    const vsv_geo *g = &r->g;
    for (int l = 0; l < sc->nlayers; l++) {
        const vsv_layer *L = &sc->layers[l];
        if (!L->visible || !(L->opacity > 0) || !L->vol || !L->vol->nbricks)
            continue;
        vsv_rc_copy *cp = &r->copy[l];
        if (copies && (cp->vol != L->vol || cp->gen != L->vol->gen || !cp->gen)) {
            if (vsv_rc_copy_prepare(cp, L->vol))
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
            .mm = cp->mm,
            .inv_span = vsv_light_inv_span(L->tf),
        };
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
    F->term = (float)r->o.term;
    F->inv_cell[0] = 1 / g->dx;
    F->inv_cell[1] = 1 / g->dy;
    F->inv_cell[2] = 1 / (g->dz * g->E);
    rc_cam(r);
    vsv_light_init(&F->light, sc, g);
    F->shift = V->shift;
    F->mask = V->brick - 1;
    F->brick = V->brick;
    F->bx = V->bdim[0];
    F->bxy = V->bdim[0] * V->bdim[1];
    F->ey = V->brick + 1;
    F->ez = F->ey * F->ey;
    return 0;
}

/* Per entry i of layer L's table, how many entries before it have some
 * opacity (VSV_TF_LUT + 1 counts): layer_clear in constant time. */
void vsv_rc_alpha_counts(const vsv_rc_layer *L, int *cnt)
{
    cnt[0] = 0;
    for (int i = 0; i < VSV_TF_LUT; i++)
        cnt[i + 1] = cnt[i] + (L->lut[i][3] > 0);
}

/* Whether layer L gives zero opacity to every sample value in [lo, hi]: the
 * table entries its lookup may read for them (the sampler's own arithmetic,
 * monotonic in the value) are all transparent (cnt: alpha_counts). */
int vsv_rc_layer_clear(const vsv_rc_layer *L, const int *cnt, float lo, float hi)
{
    if (!(hi >= L->lo))
        return 1; /* below the range, or no value but no data */
    lo = lo > L->lo ? lo : L->lo;
    float x0 = fmaf(L->log ? logf(lo) : lo, L->inv, L->off), x1 = fmaf(L->log ? logf(hi) : hi, L->inv, L->off);
    x0 = x0 < VSV_TF_LUT - 1 ? x0 : VSV_TF_LUT - 1;
    x1 = x1 < VSV_TF_LUT - 1 ? x1 : VSV_TF_LUT - 1;
    /* a value at x reads entries floor(x) and floor(x) + 1, the second with
     * weight x - floor(x): exactly 0 at an entry */
    int i0 = (int)x0, i1 = (int)ceilf(x1);
    i0 = i0 < 0 ? 0 : i0 < VSV_TF_LUT - 2 ? i0 : VSV_TF_LUT - 2;
    i1 = i1 < VSV_TF_LUT - 1 ? i1 : VSV_TF_LUT - 1;
    return i1 < i0 || cnt[i1 + 1] == cnt[i0];
}

/* A key of what the skip distances depend on: the layers' volumes and
 * generations, their tables and lookups (FNV-1a). */
static uint64_t skip_key(const vsv_renderer *r)
{
    uint64_t h = 1469598103934665603ULL;
#define MIX(p, n)                                                                                                      \
    for (size_t i_ = 0; i_ < (n); i_++)                                                                                \
        h = (h ^ ((const unsigned char *)(p))[i_]) * 1099511628211ULL;
    const vsv_rc_frame *F = &r->frame;
    MIX(&F->nlayers, sizeof F->nlayers);
    for (int l = 0; l < F->nlayers; l++) {
        const vsv_rc_layer *L = &F->layer[l];
        MIX(&L->vol, sizeof L->vol);
        MIX(&L->vol->gen, sizeof L->vol->gen);
        MIX(&L->mm, sizeof L->mm);
        MIX(&L->lo, 4 * sizeof(float));
        MIX(&L->log, sizeof L->log);
        for (int i = 0; i < VSV_TF_LUT; i++)
            MIX(&L->lut[i][3], sizeof(float));
    }
#undef MIX
    return h;
}

/* dst = src widened by one block along axis a (0/1 flags, nb blocks per axis) */
static void dilate(const unsigned char *src, unsigned char *dst, const int nb[3], int a)
{
    const size_t stride = a == 0 ? 1 : a == 1 ? (size_t)nb[0] : (size_t)nb[0] * nb[1];
    size_t b = 0;
    for (int k = 0; k < nb[2]; k++)
        for (int j = 0; j < nb[1]; j++)
            for (int i = 0; i < nb[0]; i++, b++) {
                const int c = a == 0 ? i : a == 1 ? j : k;
                unsigned char v = src[b];
                if (c > 0)
                    v |= src[b - stride];
                if (c < nb[a] - 1)
                    v |= src[b + stride];
                dst[b] = v;
            }
}

/* NaN-blind minimum and maximum: a NaN a is replaced, a NaN b left out */
static inline float min_nan(float a, float b) { return b < a || a != a ? b : a; }
static inline float max_nan(float a, float b) { return b > a || a != a ? b : a; }

/* The fine skipping bits (vsv_rc_frame.fine) of the blocks in block layer
 * bk: per cell (i, j, k) of a block some layer shows, whether every sample
 * whose lower cell it is (its trilinear reads cells i .. i + 1, j .. j + 1,
 * k .. k + 1, NaN left out: a sample touching one is no data) is
 * transparent in every layer (the value range of its eight cells and
 * layer_clear). The cells past the grid's last lower cell get 0. */
static void fine_layer(void *ctx, int bk, int thread)
{
    vsv_renderer *r = ctx;
    const vsv_rc_frame *F = &r->frame;
    const int *nb = r->fine_nb;
    const int e = F->ey, ez = F->ez, sh = F->shift, m = F->mask;
    (void)thread;
    for (int bj = 0; bj < nb[1]; bj++)
        for (int bi = 0; bi < nb[0]; bi++) {
            const size_t b = (size_t)bi + (size_t)nb[0] * (bj + (size_t)nb[1] * bk);
            uint64_t bits = ~(uint64_t)0;
            const int o[3] = {bi * VSV_RC_BLOCK, bj * VSV_RC_BLOCK, bk * VSV_RC_BLOCK};
            const int brick = (o[0] >> sh) + F->bx * (o[1] >> sh) + F->bxy * (o[2] >> sh);
            const int off = (o[0] & m) + (o[1] & m) * e + (o[2] & m) * ez;
            for (int l = 0; l < F->nlayers && bits; l++) {
                const vsv_rc_layer *L = &F->layer[l];
                if (L->clear[b])
                    continue;
                const int *cnt = r->alpha_cnt + (size_t)l * (VSV_TF_LUT + 1);
                const float *q = L->cells[brick] + off;
                /* min and max over pairs along x, then y, then z */
                float lo[VSV_RC_BLOCK + 1][VSV_RC_BLOCK + 1][VSV_RC_BLOCK],
                    hi[VSV_RC_BLOCK + 1][VSV_RC_BLOCK + 1][VSV_RC_BLOCK];
                for (int k = 0; k <= VSV_RC_BLOCK; k++)
                    for (int j = 0; j <= VSV_RC_BLOCK; j++) {
                        const float *row = q + j * e + k * ez;
                        for (int i = 0; i < VSV_RC_BLOCK; i++) {
                            lo[k][j][i] = min_nan(row[i], row[i + 1]);
                            hi[k][j][i] = max_nan(row[i], row[i + 1]);
                        }
                    }
                for (int k = 0; k <= VSV_RC_BLOCK; k++)
                    for (int j = 0; j < VSV_RC_BLOCK; j++)
                        for (int i = 0; i < VSV_RC_BLOCK; i++) {
                            lo[k][j][i] = min_nan(lo[k][j][i], lo[k][j + 1][i]);
                            hi[k][j][i] = max_nan(hi[k][j][i], hi[k][j + 1][i]);
                        }
                uint64_t lb = 0;
                for (int k = 0; k < VSV_RC_BLOCK; k++)
                    for (int j = 0; j < VSV_RC_BLOCK; j++)
                        for (int i = 0; i < VSV_RC_BLOCK; i++) {
                            const int in = o[0] + i <= F->last[0] && o[1] + j <= F->last[1] && o[2] + k <= F->last[2];
                            const float a = min_nan(lo[k][j][i], lo[k + 1][j][i]);
                            const float z = max_nan(hi[k][j][i], hi[k + 1][j][i]);
                            if (in && vsv_rc_layer_clear(L, cnt, a, z))
                                lb |= (uint64_t)1 << (i + VSV_RC_BLOCK * (j + VSV_RC_BLOCK * k));
                        }
                bits &= lb;
            }
            r->fine[2 * b] = (uint32_t)bits;
            r->fine[2 * b + 1] = (uint32_t)(bits >> 32);
        }
}

enum { SKIP_FAR = 15 }; /* skip distances stop here (a leap of up to 60 cells either way) */

/* Empty-space skipping for the frame, once its sampling copies are built:
 * per block of VSV_RC_BLOCK^3 cells and layer, whether every sample in it
 * is transparent (from the copy's block min/max and the layer's table:
 * transfer-function aware), and per block its distance in blocks (on the
 * worst axis, up to SKIP_FAR + 1) to the nearest block some layer may show:
 * a ray in a block at distance d leaps out of the box of blocks within
 * d - 1 (vsv_rc_leap), sample by sample decided for each ray. Kept while the
 * volumes and transfer functions stay the same. */
int vsv_rc_prepare_skip(vsv_renderer *r)
{
    vsv_rc_frame *F = &r->frame;
    if (!F->nlayers || r->o.no_skip)
        return 0;
    int nb[3];
    vsv_rc_block_dims(F->layer[0].vol, nb);
    const size_t nblk = (size_t)nb[0] * nb[1] * nb[2];
    /* layout: [distance][three scratch planes][layer 0 clear][layer 1 clear]...[4 bytes] */
    const size_t need = nblk * (4 + (size_t)F->nlayers) + 4;
    if (need > r->skip_cap) {
        unsigned char *p = realloc(r->skip, need);
        if (!p)
            return VSV_ENOMEM;
        r->skip = p;
        r->skip_cap = need;
        r->skip_key = 0;
    }
    unsigned char *dist = r->skip, *occ = dist + nblk, *t = occ + nblk, *u = t + nblk;
    for (int l = 0; l < F->nlayers; l++)
        r->act[l].clear = u + nblk * (size_t)(l + 1);
    F->nbx = nb[0];
    F->nbxy = nb[0] * nb[1];
    F->layer_clear = F->nlayers > 1;
    const uint64_t key = skip_key(r);
    if (key == r->skip_key) {
        F->skip = r->skip_any ? dist : NULL;
        F->fine = r->skip_any ? r->fine : NULL;
        return 0;
    }
    if ((size_t)F->nlayers * (VSV_TF_LUT + 1) > r->alpha_cap) {
        int *c = realloc(r->alpha_cnt, (size_t)F->nlayers * (VSV_TF_LUT + 1) * sizeof *c);
        if (!c)
            return VSV_ENOMEM;
        r->alpha_cnt = c;
        r->alpha_cap = (size_t)F->nlayers * (VSV_TF_LUT + 1);
    }
    if (2 * nblk > r->fine_cap) {
        uint32_t *f = realloc(r->fine, 2 * nblk * sizeof *f);
        if (!f)
            return VSV_ENOMEM;
        r->fine = f;
        r->fine_cap = 2 * nblk;
    }
    memset(occ, 0, nblk);
    for (int l = 0; l < F->nlayers; l++) {
        const vsv_rc_layer *L = &F->layer[l];
        int *cnt = r->alpha_cnt + (size_t)l * (VSV_TF_LUT + 1);
        vsv_rc_alpha_counts(L, cnt);
        unsigned char *clear = (unsigned char *)L->clear;
        for (size_t b = 0; b < nblk; b++) {
            clear[b] = (unsigned char)vsv_rc_layer_clear(L, cnt, L->mm[2 * b], L->mm[2 * b + 1]);
            occ[b] |= !clear[b];
        }
    }
    /* the clear samples of the blocks some layer shows, a layer of blocks an item */
    r->fine_nb[0] = nb[0], r->fine_nb[1] = nb[1], r->fine_nb[2] = nb[2];
    vsv_pool_run(&r->pool, fine_layer, r, nb[2]);
    int any = 0;
    for (size_t b = 0; b < nblk; b++) {
        dist[b] = occ[b] ? 0 : SKIP_FAR + 1;
        any |= !occ[b];
    }
    /* distances by dilation: the blocks within d of a shown one, d = 1, 2 ...
     * (a step of the L-infinity dilation: along x, then y, then z) */
    for (int d = 1; any && d <= SKIP_FAR; d++) {
        dilate(occ, t, nb, 0);
        dilate(t, u, nb, 1);
        dilate(u, t, nb, 2);
        int grew = 0;
        for (size_t b = 0; b < nblk; b++) {
            occ[b] = t[b];
            if (t[b] && dist[b] > d) {
                dist[b] = (unsigned char)d;
                grew = 1;
            }
        }
        if (!grew)
            break;
    }
    /* the blocks shown whose cells are at least half clear: rays test their
     * cells (with fewer, as in dense fields, leaping rays part from their
     * neighbours and their steps no longer share a brick: measured slower) */
    for (size_t b = 0; b < nblk; b++)
        dist[b] |= !dist[b] && __builtin_popcount(r->fine[2 * b]) + __builtin_popcount(r->fine[2 * b + 1]) >= 32
                       ? VSV_RC_FINE
                       : 0;
    r->skip_key = key;
    r->skip_any = any;
    F->skip = any ? dist : NULL;
    F->fine = any ? r->fine : NULL;
    return 0;
}

/* Layer L's trilinear value at cell coordinates p, clamped into the grid. */
static float rc_value(const vsv_rc_frame *F, const vsv_rc_layer *L, const float p[3])
{
    int ci[3];
    float f[3];
    for (int a = 0; a < 3; a++) {
        const float c = p[a] > 0 ? (p[a] < F->hi[a] ? p[a] : F->hi[a]) : 0;
        ci[a] = (int)c;
        ci[a] = ci[a] < F->last[a] ? ci[a] : F->last[a];
        f[a] = c - ci[a];
    }
    const int sh = F->shift, m = F->mask;
    const int bidx = (ci[0] >> sh) + F->bx * (ci[1] >> sh) + F->bxy * (ci[2] >> sh);
    const float *q = L->cells[bidx] + (ci[0] & m) + (ci[1] & m) * F->ey + (ci[2] & m) * F->ez;
    float cell[8];
    for (int i = 0; i < 8; i++)
        cell[i] = q[(i & 1) + (i & 2 ? F->ey : 0) + (i & 4 ? F->ez : 0)];
    return vsv_rc_trilinear(cell, f[0], f[1], f[2]);
}

/* The lighting factor of layer L's value v at cell coordinates c: central
 * differences one cell either way (a neighbour without data counts as v). */
static float rc_shade(const vsv_rc_frame *F, const vsv_rc_layer *L, const float c[3], float v)
{
    float d[3];
    for (int a = 0; a < 3; a++) {
        float p[3] = {c[0], c[1], c[2]};
        p[a] = c[a] + 1;
        float hi = rc_value(F, L, p);
        p[a] = c[a] - 1;
        float lo = rc_value(F, L, p);
        hi = hi == hi ? hi : v;
        lo = lo == lo ? lo : v;
        d[a] = 0.5f * (hi - lo);
    }
    return vsv_light_shade(&F->light, v, d, L->log, L->inv_span);
}

/* One ray through the volume, front to back: trilinear samples classified
 * per layer, extinction and extinction-weighted colour summed over layers,
 * composited with the opacity of the step; early ray termination, skipping.
 * vsv_raycast16 does the same operations in the same order, sixteen rays wide. */
static void raycast_march(const vsv_rc_frame *F, const vsv_rc_ray *ray, float *pT, float acc[3], float *depth)
{
    const int sh = F->shift, m = F->mask, ey = F->ey, ez = F->ez;
    const float st = (float)F->st;
    float T = 1;
    for (int n = 0; n < ray->ns; n++) {
        float c[3];
        int ci[3];
        vsv_rc_cell(F, ray, n, c, ci);
        size_t blk = 0;
        if (F->skip) {
            blk = (size_t)(ci[0] >> VSV_RC_BSHIFT) + (size_t)F->nbx * (ci[1] >> VSV_RC_BSHIFT) +
                  (size_t)F->nbxy * (ci[2] >> VSV_RC_BSHIFT);
            if (F->skip[blk] & ~VSV_RC_FINE) { /* clear around: leap */
                n = vsv_rc_leap(F, ray, n, ci, F->skip[blk], VSV_RC_BSHIFT) - 1;
                continue;
            }
            const int cell = (ci[0] & (VSV_RC_BLOCK - 1)) + VSV_RC_BLOCK * (ci[1] & (VSV_RC_BLOCK - 1)) +
                             VSV_RC_BLOCK * VSV_RC_BLOCK * (ci[2] & (VSV_RC_BLOCK - 1));
            if (F->skip[blk] == VSV_RC_FINE &&
                F->fine[2 * blk + (cell >> 5)] >> (cell & 31) & 1) { /* a clear cell: out of it */
                n = vsv_rc_leap(F, ray, n, ci, 1, 0) - 1;
                continue;
            }
        }
        const int bidx = (ci[0] >> sh) + F->bx * (ci[1] >> sh) + F->bxy * (ci[2] >> sh);
        const float fu = c[0] - ci[0], fv = c[1] - ci[1], fw = c[2] - ci[2];
        const int off = (ci[0] & m) + (ci[1] & m) * ey + (ci[2] & m) * ez;
        float sig = 0, col[3] = {0, 0, 0};
        for (int l = 0; l < F->nlayers; l++) {
            const vsv_rc_layer *L = &F->layer[l];
            if (F->skip && F->layer_clear && L->clear[blk])
                continue; /* transparent in this block: adds nothing */
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
                const float k = F->light.on ? s * rc_shade(F, L, c, v) : s;
                for (int ch = 0; ch < 3; ch++)
                    col[ch] += k * vsv_rc_lerp(lo[ch], hi[ch], f);
            }
        }
        if (sig > 0) {
            const float stn = n == ray->ns - 1 ? st * ray->wl : st; /* the last: its part step */
            const float us = sig * stn;
            const float f = vsv_rc_opacity_per_u(us);
            const float a = us * f, k = T * f * stn; /* T a / sig */
            for (int ch = 0; ch < 3; ch++)
                acc[ch] = fmaf(k, col[ch], acc[ch]);
            T = fmaf(-T, a, T);
            if (*depth == INFINITY && 1 - T > 0.1f)
                *depth = (float)(F->st * ((double)ray->ts + n));
            if (T < F->term)
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

/* A pixel from its ray's compositing: the ground behind what is left. */
static void raycast_finish(const vsv_renderer *r, int px, int py, double t_hit, float T, const float acc[3],
                           float depth)
{
    const size_t at = (size_t)py * r->cam->width + px;
    float out[4] = {acc[0], acc[1], acc[2], 1 - T};
    if (t_hit < INFINITY && T >= r->frame.term) {
        const vsv_ground *gp = &r->surf_read[at];
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
void vsv_rc_ground_row(void *ctx, int py, int thread)
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

/* One 16x16 tile of the raycaster: a row of the tile at a time, sixteen rays
 * at once where the CPU has AVX2 (in one AVX-512 register where it has that;
 * VSV_SIMD=0 in the environment: one ray at a time, VSV_SIMD=avx2: never
 * AVX-512), else one ray at a time. */
void vsv_rc_tile(void *ctx, int tile, int thread)
{
    enum { N = VSV_RC_LANES };
    vsv_renderer *r = ctx;
    const vsv_camera *cam = r->cam;
    const vsv_rays *R = &r->rays;
    const vsv_rc_frame *F = &r->frame;
    const vsv_rc_cam *C = &F->cam;
    (void)thread;
    const int tx = tile % r->tiles_x, ty = tile / r->tiles_x;
    const int x1 = (tx + 1) * VSV_RC_TILE < cam->width ? (tx + 1) * VSV_RC_TILE : cam->width;
    for (int py = ty * VSV_RC_TILE; py < (ty + 1) * VSV_RC_TILE && py < cam->height; py++)
        for (int px = tx * VSV_RC_TILE; px < x1; px += N) {
            const int n = x1 - px < N ? x1 - px : N;
            /* where each ray ends on a surface (the ground, slices) */
            const vsv_ground *surf = r->surf_read ? r->surf_read + (size_t)py * cam->width + px : NULL;
            /* the lanes whose pixels are in the image, this tile and the
             * scene's rectangle on screen (vsv_rays_cull) */
            unsigned live = 0;
            for (int i = 0; i < n && F->nlayers && py >= R->y0 && py <= R->y1; i++)
                live |= (unsigned)(px + i >= R->x0 && px + i <= R->x1) << i;
            float s_hit[N], T[N], acc[3][N], depth[N];
            for (int i = 0; i < N; i++) {
                T[i] = 1;
                acc[0][i] = acc[1][i] = acc[2][i] = 0;
                depth[i] = INFINITY;
            }
            if (live) {
                for (int i = 0; i < N; i++)
                    s_hit[i] = surf && i < n ? (float)(surf[i].t * F->inv_st) : INFINITY;
                const float sy = fmaf((float)py, C->syk, C->sy0);
                if (r->kernel && !F->light.on) {
                    r->kernel(F, px, sy, live, s_hit, T, acc, depth);
                } else {
                    for (int i = 0; i < n; i++) {
                        if (!(live >> i & 1))
                            continue;
                        vsv_rc_ray ray;
                        vsv_rc_ray_setup(C, fmaf((float)(px + i), C->sxk, C->sx0), sy, s_hit[i], &ray);
                        float a[3] = {0, 0, 0};
                        raycast_march(F, &ray, &T[i], a, &depth[i]);
                        for (int c = 0; c < 3; c++)
                            acc[c][i] = a[c];
                    }
                }
            }
            for (int i = 0; i < n; i++) {
                const float a[3] = {acc[0][i], acc[1][i], acc[2][i]};
                raycast_finish(r, px + i, py, surf ? surf[i].t : INFINITY, T[i], a, depth[i]);
            }
        }
}
