/* vsv_sw_classify.c — the shear-warp's classification. The species rule
 * (summed extinction and extinction-weighted colour) is applied once per
 * brick, for all three axes, from a table per species (the rule at 16
 * positions per step of the transfer function's table: one lookup a
 * voxel), skipping bricks every species leaves transparent (from the
 * octree's brick ranges). The classified bricks are copied into the copy
 * of the principal viewing axis (vsv_sw.h), with, for every pair of
 * adjacent scanlines, the intervals where a sample between them can meet a
 * non-transparent voxel (the union of both scanlines' non-transparent runs,
 * each widened by the one voxel a bilinear footprint reaches). It runs on
 * the renderer's thread pool, a brick, then eight slices, a job. While
 * playing, a new step re-classifies and copies only the bricks whose values
 * changed: every brick of a volume carries a key (vsv_volume.bkey: the
 * file, species and the step that last changed it, known from the file's
 * delta kinds), and each axis's copy remembers the keys it was built from. */
#include "vsv_sw.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static uint64_t mix(uint64_t h, uint64_t v)
{
    h ^= v + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    return h;
}

/* A key of everything the classification depends on but the volumes'
 * values (those are keyed brick by brick: brick_key). */
static uint64_t scene_key(const vsv_scene *sc)
{
    uint64_t h = 1469598103934665603ull;
    h = mix(h, (uint64_t)sc->nlayers);
    for (int l = 0; l < sc->nlayers; l++) {
        const vsv_layer *L = &sc->layers[l];
        h = mix(h, L->vol ? (uint64_t)L->vol->nbricks << 8 | (uint64_t)L->vol->shift : 0);
        h = mix(h, (uint64_t)L->visible);
        uint32_t u;
        memcpy(&u, &L->opacity, 4);
        h = mix(h, u);
        h = mix(h, L->tf ? vsv_crc32c(0, L->tf, sizeof *L->tf) : 0);
    }
    uint64_t e;
    h = mix(h, (uint64_t)sc->light);
    for (int a = 0; a < 3 && sc->light; a++) {
        memcpy(&e, &sc->light_dir[a], 8);
        h = mix(h, e);
    }
    memcpy(&e, &sc->exaggeration, 8);
    return mix(mix(h, e), (uint64_t)sc->show_terrain);
}

/* What brick b of v holds: its key when the loader gave one (equal keys,
 * equal values), else the load's gen (every brick changes with a load). */
static uint64_t brick_key(const vsv_volume *v, int b) { return !v ? 0 : v->bkey && v->gen ? v->bkey[b] : v->gen; }

/* Grows *p (of *cap half floats) to need as new zeros: 1, or 0 when it
 * holds need already (unchanged), -1 out of memory. */
static int grow_zeros(uint16_t **p, size_t *cap, size_t need)
{
    if (need <= *cap)
        return 0;
    free(*p);
    *p = calloc(need, sizeof **p);
    *cap = *p ? need : 0;
    return *p ? 1 : -1;
}

/* Per layer, the classification of VSV_SW_SUB positions per step of its
 * transfer function's table (sw->ltab), and whether one layer alone is
 * shown without lighting (sw->solo, sw->nzc): 0 or VSV_ENOMEM. */
static int layer_tables(vsv_sw *sw, const vsv_scene *sc)
{
    if (vsv_sw_grow((void **)&sw->ltab, &sw->ltab_cap, (size_t)sc->nlayers * VSV_SW_NTAB, sizeof *sw->ltab))
        return VSV_ENOMEM;
    int seen = 0;
    sw->solo = -1;
    for (int l = 0; l < sc->nlayers; l++) {
        const vsv_layer *L = &sc->layers[l];
        uint64_t *t = sw->ltab + (size_t)l * VSV_SW_NTAB;
        if (L->tf)
            vsv_sw_table(L->tf, L->opacity * sw->scale, t);
        else
            memset(t, 0, VSV_SW_NTAB * sizeof *t);
        if (L->visible && L->opacity > 0 && L->vol && L->tf && seen++ == 0)
            sw->solo = l;
    }
    if (seen != 1 || sc->light)
        sw->solo = -1;
    for (int i = 0; sw->solo >= 0 && i < VSV_SW_NTAB; i++)
        sw->nzc[i + 1] = sw->nzc[i] + (sw->ltab[(size_t)sw->solo * VSV_SW_NTAB + i] != 0);
    return 0;
}

/* Checks the classification against the scene (invalidating every axis's
 * copy and the classified bricks when anything but the volumes' values
 * changed; begin has checked the grid's size), sizes the copy for axis c
 * and decides what to do: the bricks to classify (sw->cjobs: not
 * transparent in every layer, needed by this axis, and not classified from
 * the same values already), then the slices to copy them into (sw->jobs:
 * every slice when the axis's copy is not valid, else those of slabs where
 * a brick changed since it was built; none when nothing changed). */
int vsv_sw_classification_for(vsv_sw *sw, const vsv_scene *sc, int c)
{
    const uint64_t key = scene_key(sc);
    if (key != sw->key) {
        sw->valid[0] = sw->valid[1] = sw->valid[2] = 0;
        sw->cvalid = 0;
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
        if (layer_tables(sw, sc))
            return VSV_ENOMEM;
    }
    const size_t na = sw->n[vsv_sw_axis_a(c)], nb = sw->n[vsv_sw_axis_b(c)], nc = sw->n[c];
    /* a copy made larger is allocated anew, zeros (pages the build never
     * writes are never touched) */
    const int fresh = sw->valid[c] ? 0 : grow_zeros(&sw->vox[c], &sw->vox_cap[c], nc * (nb + 2) * 4 * VSV_SW_PLANE(na));
    if (fresh < 0 || (!sw->valid[c] &&
                      (vsv_sw_grow((void **)&sw->fps[c], &sw->fps_cap[c], nc * (nb + 1), sizeof(vsv_sw_fp)) ||
                       vsv_sw_grow((void **)&sw->ivl[c], &sw->ivl_cap[c], nc * (nb + 1) * (na + 4), sizeof(uint16_t)))))
        return VSV_ENOMEM;
    sw->sc = sc;
    /* the brick layout (every layer's volume has the first one's, or is
     * left out as transparent); no volume: one brick, transparent */
    const vsv_volume *v0 = NULL;
    for (int l = 0; l < sc->nlayers && !v0; l++)
        v0 = sc->layers[l].vol;
    sw->nbk = v0 ? v0->nbricks : 1;
    sw->shift = v0 ? v0->shift : 15;
    for (int i = 0; i < 3; i++)
        sw->bdim[i] = v0 ? v0->bdim[i] : 1;
    const size_t nbk = (size_t)sw->nbk, nkeys = (size_t)sc->nlayers * nbk, B3 = v0 ? (size_t)1 << (3 * sw->shift) : 1;
    if (vsv_sw_grow((void **)&sw->clear, &sw->clear_cap, nbk * (sc->nlayers + 3), 1) ||
        vsv_sw_grow((void **)&sw->cur, &sw->cur_cap, nkeys + 1, sizeof *sw->cur) ||
        vsv_sw_grow((void **)&sw->ckeys, &sw->ckeys_cap, nkeys + 1, sizeof *sw->ckeys) ||
        vsv_sw_grow((void **)&sw->jobs, &sw->jobs_cap, nc, sizeof *sw->jobs) ||
        vsv_sw_grow((void **)&sw->cjobs, &sw->cjobs_cap, nbk, sizeof *sw->cjobs) ||
        (sw->solo < 0 ? vsv_sw_grow((void **)&sw->cls, &sw->cls_cap, nbk * B3, sizeof *sw->cls)
                      : vsv_sw_grow((void **)&sw->pos, &sw->pos_cap, nbk * B3, sizeof *sw->pos)) ||
        vsv_sw_grow((void **)&sw->bnz, &sw->bnz_cap, nbk * (B3 >> 9 ? B3 >> 9 : 1), 1))
        return VSV_ENOMEM;
    if (sw->cnkeys != nkeys || !sw->cvalid) {
        if (vsv_sw_grow((void **)&sw->cok, &sw->cok_cap, nbk, 1))
            return VSV_ENOMEM;
        memset(sw->cok, 0, nbk); /* no brick classified under this scene */
    }
    /* bricks a layer leaves transparent need no transfer-function lookups */
    for (int l = 0; l < sc->nlayers; l++) {
        const vsv_layer *L = &sc->layers[l];
        const int ok = v0 && L->vol && (size_t)L->vol->nbricks == nbk && L->vol->shift == v0->shift && L->visible &&
                       L->opacity > 0;
        for (size_t b = 0; b < nbk; b++) {
            const float lo = ok && L->vol->bmin[b] == L->vol->bmin[b] ? L->vol->bmin[b] : -INFINITY;
            sw->clear[l * nbk + b] = !ok || !(vsv_tf_max_opacity(L->tf, lo, L->vol->bmax[b]) > 0);
            sw->cur[l * nbk + b] = ok ? brick_key(L->vol, (int)b) : 0;
        }
    }
    /* after the layers, per brick: 1 when the axis's copy needs it again;
     * then 1 when every layer leaves it transparent */
    unsigned char *dirty = sw->clear + nbk * sc->nlayers, *zero = dirty + nbk, *stale = zero + nbk;
    const int full = !sw->valid[c] || sw->nkeys[c] != nkeys;
    int any = 0;
    sw->nclassified = sw->ncjobs = sw->njobs = 0;
    for (size_t b = 0; b < nbk; b++) {
        dirty[b] = (unsigned char)full;
        zero[b] = 1;
        stale[b] = !sw->cok[b];
        for (int l = 0; l < sc->nlayers; l++) {
            if (!dirty[b] && sw->cur[l * nbk + b] != sw->keys[c][l * nbk + b])
                dirty[b] = 1;
            if (sw->cur[l * nbk + b] != sw->ckeys[l * nbk + b])
                stale[b] = 1;
            zero[b] &= sw->clear[l * nbk + b];
        }
    }
    if (sw->light.on) /* shading reads one cell into the neighbours: a change reaches them */
        for (int pass = 0; pass < 2; pass++) {
            unsigned char *f = pass ? stale : dirty;
            for (size_t b = 0; b < nbk; b++)
                if (f[b] & 1)
                    for (int a = 0; a < 3; a++) {
                        const size_t st = a == 0 ? 1 : a == 1 ? (size_t)sw->bdim[0] : (size_t)sw->bdim[0] * sw->bdim[1];
                        const int i = (int)(b / st % (size_t)sw->bdim[a]);
                        if (i > 0)
                            f[b - st] |= 2;
                        if (i + 1 < sw->bdim[a])
                            f[b + st] |= 2;
                    }
            for (size_t b = 0; b < nbk; b++)
                f[b] = f[b] != 0;
        }
    for (size_t b = 0; b < nbk; b++) {
        any |= dirty[b];
        if (dirty[b] && !zero[b] && stale[b]) {
            sw->cjobs[sw->ncjobs++] = (int)b;
            sw->cok[b] = 1;
            for (int l = 0; l < sc->nlayers; l++) /* classified below, from these values */
                sw->ckeys[l * nbk + b] = sw->cur[l * nbk + b];
        }
        sw->nclassified += dirty[b];
    }
    sw->cvalid = 1;
    sw->cnkeys = nkeys;
    sw->full = full;
    /* a copy built in another layout (or never), or of no volume (one
     * brick, transparent, no blocks): cleared whole, holding nothing (a
     * new one is zeros already) */
    const int layout[4] = {(int)na, (int)nb, (int)nc, sw->shift};
    const size_t nheld = nbk * (B3 >> 9 ? B3 >> 9 : 1);
    sw->wipe = fresh ? 2 : full && (!v0 || memcmp(layout, sw->layout[c], sizeof layout));
    if (sw->wipe) {
        if (vsv_sw_grow((void **)&sw->held[c], &sw->held_cap[c], nheld, 1))
            return VSV_ENOMEM;
        memset(sw->held[c], 0, nheld);
        memcpy(sw->layout[c], layout, sizeof layout);
    }
    if (!any)
        return 0;
    /* the slabs of B slices (bricks with the same index along c) holding a
     * brick to copy */
    const int B = 1 << sw->shift, stride[3] = {1, sw->bdim[0], sw->bdim[0] * sw->bdim[1]};
    for (int bc = 0; bc < sw->bdim[c]; bc++) {
        int hit = full;
        for (int bb = 0; bb < sw->bdim[vsv_sw_axis_b(c)] && !hit; bb++)
            for (int ba = 0; ba < sw->bdim[vsv_sw_axis_a(c)] && !hit; ba++)
                hit = dirty[bc * stride[c] + bb * stride[vsv_sw_axis_b(c)] + ba * stride[vsv_sw_axis_a(c)]];
        for (int k = bc * B; hit && k < (bc + 1) * B && k < (int)nc; k += VSV_SW_GROUP)
            sw->jobs[sw->njobs++] = k;
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

static void slice_footprints(vsv_sw *sw, int k, int thread);

/* One cell's classification from one layer's table t (a value v at
 * transfer-function position x reads entry 1 + round(x VSV_SW_SUB): within
 * 1/32 of a table step of the exact lookup, and no arithmetic per cell
 * beyond the position). */
static inline uint64_t classify_one(const vsv_tf *tf, const uint64_t *t, float v)
{
    if (!(v >= tf->lo)) /* below the range, or no data (NaN) */
        return 0;
    return t[vsv_sw_position(v, tf->scale == VSV_SCALE_LOG ? logf(v) : v, tf->lo, (float)tf->base, (float)tf->inv)];
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

/* Where cell (x, y, z) of a brick of 2^sh cells a side is in its
 * classified copy: in blocks of 8^3 cells (4 KB; x fastest, then y, then
 * z, inside and between them), so a slice of any of the three axes reads
 * whole cache lines from blocks that fit the first-level cache. */
static inline size_t micro(int x, int y, int z, int sh)
{
    const int nm = sh - 3; /* log2 of the blocks a side */
    return ((((size_t)(z >> 3) << (2 * nm)) + ((size_t)(y >> 3) << nm) + (size_t)(x >> 3)) << 9) +
           ((size_t)(z & 7) << 6) + ((size_t)(y & 7) << 3) + (size_t)(x & 7);
}

/* The flags of brick bno's blocks of 8^3 cells (sw->bnz): which hold a
 * cell inside the grid (ex x ey x ez) that is not transparent. */
static void block_flags(vsv_sw *sw, int bno, const uint64_t *out, int ex, int ey, int ez)
{
    const int sh = sw->shift, nm = sh - 3;
    unsigned char *f = sw->bnz + ((size_t)bno << (3 * nm));
    for (int z = 0; z < ez; z += 8)
        for (int y = 0; y < ey; y += 8)
            for (int x = 0; x < ex; x += 8) {
                const uint64_t *blk = out + micro(x, y, z, sh);
                const int nx = ex - x < 8 ? ex - x : 8, ny = ey - y < 8 ? ey - y : 8, nz = ez - z < 8 ? ez - z : 8;
                uint64_t any = 0;
                for (int k = 0; k < nz; k++)
                    for (int jj = 0; jj < ny; jj++)
                        for (int i = 0; i < nx; i++)
                            any |= blk[(k << 6) + (jj << 3) + i];
                f[((size_t)(z >> 3) << (2 * nm)) + ((size_t)(y >> 3) << nm) + (size_t)(x >> 3)] = any != 0;
            }
}

/* Brick bno of the solo layer (ex x ey x ez cells inside the grid) as its
 * table's entries (sw->pos, micro()'s order) and its blocks' flags: a
 * block is marked when the entries from its smallest to its largest hold
 * one not transparent (exactly when it holds one value, as most blocks of a
 * sparse field do; else it may be marked with nothing to see, which costs
 * a scan, never a voxel). */
static void classify_positions(vsv_sw *sw, int bno, int ex, int ey, int ez, int thread)
{
    const vsv_layer *L = &sw->sc->layers[sw->solo];
    const vsv_tf *tf = L->tf;
    const int sh = sw->shift, B = 1 << sh, nm = sh - 3, nblk = 1 << (3 * nm);
    const float *src = L->vol->bricks[bno], e = L->vol->empty_value;
    const float flo = tf->lo, base = (float)tf->base, inv = (float)tf->inv;
    const int lg = tf->scale == VSV_SCALE_LOG;
    uint16_t *const out = sw->pos + ((size_t)bno << (3 * sh));
    vsv_sw_h8 lo[512], hi[512];                 /* per block, lane by lane */
    float *const x = (float *)sw->cacc[thread]; /* B values: a row's logarithms, or the empty row */
    for (int i = 0; i < nblk; i++)
        lo[i] = (vsv_sw_h8){0} + UINT16_MAX, hi[i] = (vsv_sw_h8){0};
    if (!src)
        for (int i = 0; i < B; i++)
            x[B + i] = e, x[i] = lg ? logf(e) : e;
    for (int k = 0; k < ez; k++)
        for (int jj = 0; jj < ey; jj++) {
            const float *v = src ? src + ((size_t)k << (2 * sh)) + ((size_t)jj << sh) : x + B;
            if (src && lg)
                for (int i = 0; i < ex; i++)
                    x[i] = logf(v[i]);
            const size_t bk = ((size_t)(k >> 3) << (2 * nm)) + ((size_t)(jj >> 3) << nm);
            vsv_sw_positions(v, lg || !src ? x : v, ex, flo, base, inv, out + micro(0, jj, k, sh), lo + bk, hi + bk);
        }
    unsigned char *const f = sw->bnz + ((size_t)bno << (3 * nm));
    for (int i = 0; i < nblk; i++) {
        uint16_t a = UINT16_MAX, z = 0;
        for (int k = 0; k < 8; k++) {
            a = lo[i][k] < a ? lo[i][k] : a;
            z = hi[i][k] > z ? hi[i][k] : z;
        }
        f[i] = a <= z && sw->nzc[z + 1] > sw->nzc[a];
    }
}

/* Job j: brick sw->cjobs[j] classified once for every axis: the species
 * rule summed over the layers that are not clear in it, per cell four half
 * floats (extinction-weighted red, green, blue, then extinction) at
 * micro(). Only cells inside the grid (the others are never read). */
void vsv_sw_classify_brick(void *p, int j, int thread)
{
    vsv_sw *sw = p;
    const vsv_scene *sc = sw->sc;
    const int bno = sw->cjobs[j], sh = sw->shift, B = 1 << sh;
    const size_t nbk = (size_t)sw->nbk;
    uint64_t *const out = sw->cls + ((size_t)bno << (3 * sh));
    /* the brick's cells inside the grid: ex x ey x ez */
    const int bi = bno % sw->bdim[0], bj = bno / sw->bdim[0] % sw->bdim[1], bk = bno / sw->bdim[0] / sw->bdim[1];
    const int ex = sw->n[0] - (bi << sh) < B ? sw->n[0] - (bi << sh) : B;
    const int ey = sw->n[1] - (bj << sh) < B ? sw->n[1] - (bj << sh) : B;
    const int ez = sw->n[2] - (bk << sh) < B ? sw->n[2] - (bk << sh) : B;
    if (sw->solo >= 0) {
        classify_positions(sw, bno, ex, ey, ez, thread);
        return;
    }
    int nl = 0, last = -1;
    for (int l = 0; l < sc->nlayers; l++)
        if (!sw->clear[l * nbk + bno])
            nl++, last = l;
    if (nl == 1 && !sw->light.on) {
        /* one layer: its table (the empty value, most cells of a sparse
         * field, looked up once) */
        const vsv_layer *L = &sc->layers[last];
        const float *src = L->vol->bricks[bno], e = L->vol->empty_value;
        const uint64_t *t = sw->ltab + (size_t)last * VSV_SW_NTAB, ce = classify_one(L->tf, t, e);
        const int nm = sh - 3;
        unsigned char *const f = sw->bnz + ((size_t)bno << (3 * nm));
        memset(f, 0, (size_t)1 << (3 * nm));
        for (int k = 0; k < ez; k++)
            for (int jj = 0; jj < ey; jj++) {
                const size_t r = ((size_t)k << (2 * sh)) + ((size_t)jj << sh);
                uint64_t *const o = out + micro(0, jj, k, sh);
                unsigned char *const fr = f + ((size_t)(k >> 3) << (2 * nm)) + ((size_t)(jj >> 3) << nm);
                for (int i0 = 0; i0 < ex; i0 += 8) { /* a block's row, then its flag */
                    const int i1 = ex - i0 < 8 ? ex : i0 + 8;
                    uint64_t any = 0;
                    for (int i = i0; i < i1; i++) {
                        const float v = src ? src[r + i] : e;
                        const uint64_t x = v == e ? ce : classify_one(L->tf, t, v);
                        o[(i >> 3 << 9) + (i & 7)] = x;
                        any |= x;
                    }
                    fr[i0 >> 3] |= any != 0;
                }
            }
        return;
    }
    /* sums in double: exact for a few float terms, so the species order
     * cannot change a bit; a row at a time; with lighting, each colour
     * scaled by its shading */
    double *acc = sw->cacc[thread];
    for (int k = 0; k < ez; k++)
        for (int jj = 0; jj < ey; jj++) {
            const size_t r = ((size_t)k << (2 * sh)) + ((size_t)jj << sh);
            memset(acc, 0, 4 * (size_t)ex * sizeof *acc);
            for (int l = 0; l < sc->nlayers; l++) {
                if (sw->clear[l * nbk + bno])
                    continue;
                const vsv_layer *L = &sc->layers[l];
                const float *src = L->vol->bricks[bno], o = L->opacity * sw->scale, e = L->vol->empty_value;
                for (int i = 0; i < ex; i++) {
                    float rgba[4];
                    const float val = src ? src[r + i] : e;
                    vsv_tf_lookup(L->tf, val, rgba);
                    const float s = rgba[3] * o;
                    if (s > 0) {
                        acc[4 * i + 3] += s;
                        const int idx[3] = {(bi << sh) + i, (bj << sh) + jj, (bk << sh) + k};
                        const double ks = sw->light.on ? (double)s * sw_shade(sw, L, idx, val) : s;
                        acc[4 * i + 0] += ks * rgba[0];
                        acc[4 * i + 1] += ks * rgba[1];
                        acc[4 * i + 2] += ks * rgba[2];
                    }
                }
            }
            uint64_t *const o = out + micro(0, jj, k, sh);
            for (int i = 0; i < ex; i++)
                o[(i >> 3 << 9) + (i & 7)] =
                    (uint64_t)vsv_half((float)acc[4 * i]) | (uint64_t)vsv_half((float)acc[4 * i + 1]) << 16 |
                    (uint64_t)vsv_half((float)acc[4 * i + 2]) << 32 | (uint64_t)vsv_half((float)acc[4 * i + 3]) << 48;
        }
    block_flags(sw, bno, out, ex, ey, ez);
}

/* The first n <= 8 cells of a scanline (its four planes P apart) from
 * their classifications: eight by a transpose of 16-bit lanes. */
static inline void put8(uint16_t *row, size_t P, int n, const uint64_t v[8])
{
#ifdef __SSE2__
    if (n == 8) {
        __m128i x[4], y[4];
        for (int i = 0; i < 4; i++) /* red, green, blue, extinction of cells 2i, 2i + 1 */
            x[i] = _mm_set_epi64x((long long)v[2 * i + 1], (long long)v[2 * i]);
        for (int i = 0; i < 2; i++) { /* r0 r2 g0 g2 b0 b2 e0 e2, r1 r3 g1 g3 ... (and 4-7) */
            y[2 * i] = _mm_unpacklo_epi16(x[2 * i], x[2 * i + 1]);
            y[2 * i + 1] = _mm_unpackhi_epi16(x[2 * i], x[2 * i + 1]);
        }
        for (int i = 0; i < 2; i++) { /* r0-r3 g0-g3, b0-b3 e0-e3 (and 4-7) */
            x[2 * i] = _mm_unpacklo_epi16(y[2 * i], y[2 * i + 1]);
            x[2 * i + 1] = _mm_unpackhi_epi16(y[2 * i], y[2 * i + 1]);
        }
        _mm_storeu_si128((__m128i *)row, _mm_unpacklo_epi64(x[0], x[2]));
        _mm_storeu_si128((__m128i *)(row + P), _mm_unpackhi_epi64(x[0], x[2]));
        _mm_storeu_si128((__m128i *)(row + 2 * P), _mm_unpacklo_epi64(x[1], x[3]));
        _mm_storeu_si128((__m128i *)(row + 3 * P), _mm_unpackhi_epi64(x[1], x[3]));
        return;
    }
#endif
    for (int i = 0; i < n; i++) {
        row[i] = (uint16_t)v[i];
        row[P + i] = (uint16_t)(v[i] >> 16);
        row[2 * P + i] = (uint16_t)(v[i] >> 32);
        row[3 * P + i] = (uint16_t)(v[i] >> 48);
    }
}

/* Job j: slices sw->jobs[j] .. + VSV_SW_GROUP - 1 of the current axis
 * (those that exist): the classified bricks they need again copied in (a
 * brick every layer leaves transparent zeroed; when the copy is built
 * anew, the whole slice zeroed first: the empty scanlines and padding too),
 * then the footprints of their scanline pairs. A brick's square of a slice
 * is copied through a small tile read in the brick's memory order, the
 * group's slices one after the other: for two of the three axes a slice's
 * cells are strided in the brick (a scanline along z steps 8 KB a cell),
 * and the next slices use the rest of each cache line read. */
void vsv_sw_classify_slice(void *p, int j, int thread)
{
    vsv_sw *sw = p;
    const vsv_scene *sc = sw->sc;
    const int c = sw->c, a = vsv_sw_axis_a(c), b = vsv_sw_axis_b(c), na = sw->n[a], nb = sw->n[b];
    const int k0 = sw->jobs[j], k1 = k0 + VSV_SW_GROUP < sw->n[c] ? k0 + VSV_SW_GROUP : sw->n[c];
    const size_t P = VSV_SW_PLANE(na), scan = 4 * P, nbk = (size_t)sw->nbk;
    if (sw->wipe == 1)
        memset(sw->vox[c] + (size_t)k0 * (nb + 2) * scan, 0, (size_t)(k1 - k0) * (nb + 2) * scan * sizeof(uint16_t));
    const unsigned char *dirty = sw->clear + nbk * sc->nlayers, *zero = dirty + nbk;
    const int sh = sw->shift, B = 1 << sh, m = B - 1, stride[3] = {1, sw->bdim[0], sw->bdim[0] * sw->bdim[1]};
    /* a cell's step in a block along a, b, c; blocks' along a and b */
    const int st[3] = {1, 8, 64}, nm = sh - 3;
    const size_t ba[3] = {512, (size_t)512 << nm, (size_t)512 << (2 * nm)};
    const int kn = k1 - k0;
    const uint64_t *const lt = sw->solo >= 0 ? sw->ltab + (size_t)sw->solo * VSV_SW_NTAB : NULL;
    for (int ib0 = 0; ib0 < nb; ib0 += B) {
        const int nbt = nb - ib0 < B ? nb - ib0 : B;
        for (int ia0 = 0; ia0 < na; ia0 += B) {
            const int nat = na - ia0 < B ? na - ia0 : B;
            const int bno = (ia0 >> sh) * stride[a] + (ib0 >> sh) * stride[b] + (k0 >> sh) * stride[c];
            if (!dirty[bno] || (zero[bno] && sw->wipe))
                continue;
            uint16_t *const base = sw->vox[c] + ((size_t)k0 * (nb + 2) + ib0 + 1) * scan + VSV_SW_PAD + ia0;
            const size_t kstep = (size_t)(nb + 2) * scan;
            /* the group's layer of blocks, block by block: a block with no
             * cell to see (all of a brick every layer leaves transparent)
             * cleared where the copy held something, else left as it is */
            const size_t cb = ((size_t)bno << (3 * sh)) + ((size_t)((k0 & m) >> 3) * ba[c]);
            const size_t fo = ((size_t)bno << (3 * nm)) + ((size_t)((k0 & m) >> 3) * (ba[c] >> 9));
            const unsigned char *const fb = zero[bno] ? NULL : sw->bnz + fo;
            unsigned char *const held = sw->held[c] + fo;
            for (int mb = 0; mb < nbt; mb += 8)
                for (int ma = 0; ma < nat; ma += 8) {
                    const size_t bo = (size_t)(mb >> 3) * ba[b] + (size_t)(ma >> 3) * ba[a];
                    const size_t blk = cb + bo;
                    const int ea = nat - ma < 8 ? nat - ma : 8, eb = nbt - mb < 8 ? nbt - mb : 8;
                    if (!fb || !fb[bo >> 9]) {
                        if (held[bo >> 9])
                            for (int kk = 0; kk < kn; kk++)
                                for (int jb = 0; jb < eb; jb++)
                                    for (int ch = 0; ch < 4; ch++)
                                        memset(base + kk * kstep + (size_t)(mb + jb) * scan + ch * P + ma, 0,
                                               (size_t)ea * sizeof *base);
                        held[bo >> 9] = 0;
                        continue;
                    }
                    for (int kk = 0; kk < kn; kk++)
                        for (int jb = 0; jb < eb; jb++) {
                            uint16_t *const row = base + kk * kstep + (size_t)(mb + jb) * scan + ma;
                            const size_t t = blk + (size_t)kk * st[c] + (size_t)jb * st[b];
                            uint64_t v[8];
                            for (int ja = 0; ja < 8; ja++)
                                v[ja] = ja >= ea ? 0
                                        : lt     ? lt[sw->pos[t + (size_t)ja * st[a]]]
                                                 : sw->cls[t + (size_t)ja * st[a]];
                            put8(row, P, ea, v);
                        }
                    held[bo >> 9] = 1;
                }
        }
    }
    for (int k = k0; k < k1; k++)
        slice_footprints(sw, k, thread);
}

/* Bit i set when cell i of the eight from e is not transparent (its
 * extinction, a half float >= 0, above 0). */
static inline unsigned seen8(const uint16_t *e)
{
#ifdef __SSE2__
    const __m128i z = _mm_cmpeq_epi16(_mm_loadu_si128((const __m128i *)e), _mm_setzero_si128());
    return ~(unsigned)_mm_movemask_epi8(_mm_packs_epi16(z, z)) & 0xffu;
#else
    unsigned m = 0;
    for (int i = 0; i < 8; i++)
        m |= (unsigned)(e[i] > 0) << i;
    return m;
#endif
}

/* The footprints of slice k's scanline pairs from its classified copy. */
static void slice_footprints(vsv_sw *sw, int k, int thread)
{
    const int c = sw->c, a = vsv_sw_axis_a(c), b = vsv_sw_axis_b(c), na = sw->n[a], nb = sw->n[b];
    const size_t P = VSV_SW_PLANE(na), scan = 4 * P, nbk = (size_t)sw->nbk;
    const unsigned char *zero = sw->clear + nbk * (sw->sc->nlayers + 1);
    const int sh = sw->shift, B = 1 << sh, m = B - 1, nm = sh - 3,
              stride[3] = {1, sw->bdim[0], sw->bdim[0] * sw->bdim[1]};
    const size_t bs[3] = {512, (size_t)512 << nm, (size_t)512 << (2 * nm)}; /* a block's step along x, y, z */
    const uint16_t *slice = sw->vox[c] + (size_t)k * (nb + 2) * scan;
    vsv_sw_fp *fps = sw->fps[c] + (size_t)k * (nb + 1);
    uint16_t *const ivl = sw->ivl[c] + (size_t)k * (nb + 1) * (na + 4);
    /* the runs of every scanline (searched only where a brick is not
     * transparent in every layer), this one's and the previous one's */
    uint32_t at = 0;
    uint16_t *runs[2] = {(uint16_t *)sw->scratch[thread], (uint16_t *)sw->scratch[thread] + na + 4};
    runs[1][0] = 0;
    for (int ib = 0; ib < nb; ib++) {
        const uint16_t *ext = slice + (size_t)(ib + 1) * scan + 3 * P + VSV_SW_PAD;
        uint16_t *iv = runs[ib & 1];
        int cnt = 0, open = 0;
        for (int ia0 = 0; ia0 < na; ia0 += B) {
            const int bno = (ia0 >> sh) * stride[a] + (ib >> sh) * stride[b] + (k >> sh) * stride[c];
            const int end = na - ia0 < B ? na : ia0 + B;
            if (zero[bno]) {
                if (open) {
                    iv[1 + cnt++] = (uint16_t)ia0;
                    open = 0;
                }
                continue;
            }
            /* eight cells at a time: a block with no cell to see is a gap */
            const unsigned char *fb = sw->bnz + ((size_t)bno << (3 * nm)) + (size_t)((ib & m) >> 3) * (bs[b] >> 9) +
                                      (size_t)((k & m) >> 3) * (bs[c] >> 9);
            for (int s0 = ia0; s0 < end; s0 += 8) {
                const int n = end - s0 < 8 ? end - s0 : 8;
                if (!fb[(size_t)((s0 & m) >> 3) * (bs[a] >> 9)]) {
                    if (open) {
                        iv[1 + cnt++] = (uint16_t)s0;
                        open = 0;
                    }
                    continue;
                }
                /* a run starts or ends at each cell unlike the one before
                 * (the eight read past the row's end are its padding) */
                const unsigned in = (1u << n) - 1, seen = seen8(ext + s0) & in;
                for (unsigned t = (seen ^ (seen << 1 | (unsigned)open)) & in; t; t &= t - 1)
                    iv[1 + cnt++] = (uint16_t)(s0 + __builtin_ctz(t));
                open = (int)(seen >> (n - 1) & 1);
            }
        }
        if (open)
            iv[1 + cnt++] = (uint16_t)na;
        iv[0] = (uint16_t)(cnt / 2);
        const uint16_t *prev = runs[(ib + 1) & 1];
        fps[ib] = (vsv_sw_fp){at, prev[0] || cnt ? (uint32_t)merge_footprints(prev, iv, ivl + at)
                                                 : 0}; /* pair (ib - 1, ib) */
        at += 2 * fps[ib].n;
    }
    fps[nb] = (vsv_sw_fp){at, (uint32_t)merge_footprints(runs[(nb + 1) & 1], NULL, ivl + at)}; /* pair (nb - 1, nb) */
}

void vsv_sw_classified(vsv_sw *sw, double seconds)
{
    const size_t n = (size_t)sw->sc->nlayers * sw->nbk;
    if (vsv_sw_grow((void **)&sw->keys[sw->c], &sw->keys_cap[sw->c], n + 1, sizeof(uint64_t))) {
        sw->valid[sw->c] = 0; /* no room to remember what it was built from: built again next time */
    } else {
        memcpy(sw->keys[sw->c], sw->cur, n * sizeof(uint64_t));
        sw->nkeys[sw->c] = n;
        sw->valid[sw->c] = 1;
    }
    sw->build_seconds = seconds;
    sw->built_bricks = sw->nclassified;
    sw->sc = NULL;
}
