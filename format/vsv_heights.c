/* vsv_heights.c — per-column heights of native levels (SPEC.md "HGTS"):
 * the records in a vsv_meta, MM5's reference-state formula, the even axis
 * renderers place native levels on, and the resampler that does it. */
#include "vsv_format_internal.h"
#include "vsv_vgrid.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define R_DRY 287.04
#define G0 9.81

double vsv_mm5_ref_height(double p, const double mm5[4])
{
    const double P00 = mm5[0], TS0 = mm5[1], A = mm5[2], TISO = mm5[3];
    const double l = log(p / P00);
    double z = -((R_DRY * A / (2 * G0)) * l * l + (R_DRY * TS0 / G0) * l);
    if (TISO > 0) {
        const double piso = P00 * exp((TISO - TS0) / A);
        if (p < piso) {
            const double li = log(piso / P00);
            const double ziso = -((R_DRY * A / (2 * G0)) * li * li + (R_DRY * TS0 / G0) * li);
            z = ziso - (R_DRY * TISO / G0) * log(p / piso);
        }
    }
    return z;
}

/* Heights of MM5's half-sigma levels over the terrain: p*(terrain) from the
 * reference surface pressure, p = p*·sigma + PTOP, z = reference height. */
static void mm5_heights(const vsv_meta *m, const double mm5[5], const double *sigma, float *z)
{
    const size_t plane = (size_t)m->nx * m->ny;
    const double P00 = mm5[0], TS0 = mm5[1], A = mm5[2], PTOP = mm5[4];
    for (size_t c = 0; c < plane; c++) {
        const double ps0 = P00 * exp(-TS0 / A + sqrt((TS0 / A) * (TS0 / A) - 2 * G0 * m->terrain[c] / (A * R_DRY)));
        for (int k = 0; k < m->nz; k++)
            z[(size_t)k * plane + c] = (float)vsv_mm5_ref_height((ps0 - PTOP) * sigma[k] + PTOP, mm5);
    }
}

static void heights_free(vsv_heights *h)
{
    free(h->sigma);
    free(h->z);
}

void vsv_heights_clear_all(vsv_meta *m)
{
    for (int i = 0; i < m->nheights; i++)
        heights_free(&m->heights[i]);
    free(m->heights);
    m->heights = NULL;
    m->nheights = 0;
}

int vsv_heights_copy_all(vsv_meta *dst, const vsv_meta *src)
{
    dst->heights = NULL;
    dst->nheights = 0;
    for (int i = 0; i < src->nheights; i++) {
        const vsv_heights *h = &src->heights[i];
        const int rc =
            vsv_meta_add_heights(dst, h->time, h->form == VSV_HEIGHTS_STORED ? h->z : NULL, h->mm5, h->sigma);
        if (rc)
            return rc;
    }
    return 0;
}

int vsv_meta_add_heights(vsv_meta *m, int64_t time, const float *z, const double mm5[5], const double *sigma)
{
    const size_t plane = (size_t)m->nx * m->ny, n = plane * (size_t)m->nz;
    if (m->nheights && time <= m->heights[m->nheights - 1].time)
        return VSV_EINVAL;
    if (!z && (!mm5 || !sigma || !m->terrain || !(mm5[0] > 0) || !(mm5[1] > 0) || !(mm5[2] > 0) || !(mm5[3] >= 0) ||
               !(mm5[4] > 0) || !(mm5[4] < mm5[0])))
        return VSV_EINVAL;
    vsv_heights h = {.time = time, .form = z ? VSV_HEIGHTS_STORED : VSV_HEIGHTS_MM5};
    h.z = malloc(n * sizeof *h.z + 1);
    if (!z) {
        memcpy(h.mm5, mm5, sizeof h.mm5);
        h.sigma = malloc((size_t)m->nz * sizeof *h.sigma);
        if (h.sigma)
            memcpy(h.sigma, sigma, (size_t)m->nz * sizeof *h.sigma);
    }
    vsv_heights *nh = realloc(m->heights, ((size_t)m->nheights + 1) * sizeof *nh);
    if (nh)
        m->heights = nh;
    if (!h.z || (!z && !h.sigma) || !nh) {
        heights_free(&h);
        return VSV_ENOMEM;
    }
    if (z)
        memcpy(h.z, z, n * sizeof *h.z);
    else
        mm5_heights(m, mm5, sigma, h.z);
    /* finite and strictly increasing upward in every column */
    for (size_t c = 0; c < plane; c++)
        for (int k = 0; k < m->nz; k++) {
            const float v = h.z[(size_t)k * plane + c];
            if (!isfinite(v) || (k && !(v > h.z[(size_t)(k - 1) * plane + c]))) {
                heights_free(&h);
                return VSV_EINVAL;
            }
        }
    m->heights[m->nheights++] = h;
    return 0;
}

const float *vsv_meta_heights_at(const vsv_meta *m, int64_t time)
{
    if (!m->nheights)
        return NULL;
    int i = 0;
    while (i + 1 < m->nheights && m->heights[i + 1].time <= time)
        i++;
    return m->heights[i].z;
}

int vsv_heights_axis(const vsv_meta *m, int *nz, double *z0, double *dz)
{
    if (!m->nheights || m->vert_kind != VSV_VERT_NATIVE)
        return VSV_EINVAL;
    const size_t plane = (size_t)m->nx * m->ny;
    float top = 0;
    for (int i = 0; i < m->nheights; i++) {
        const float *z = m->heights[i].z + (size_t)(m->nz - 1) * plane;
        for (size_t c = 0; c < plane; c++)
            top = z[c] > top ? z[c] : top;
    }
    /* from sea level to the highest top level rounded up to 100 m, in three
     * times as many levels as the file has (at least 40, at most 512) */
    const double ztop = ceil(top / 100.0) * 100.0 + (top <= 0 ? 100 : 0);
    int n = 3 * m->nz;
    n = n < 40 ? 40 : n > 512 ? 512 : n;
    *nz = n;
    *dz = ztop / n;
    *z0 = *dz / 2;
    return 0;
}

/* ----------------------------------------------------------- the record */

int vsv_heights_encode(const vsv_meta *m, const vsv_heights *h, int coded, vsv_buf *b)
{
    const size_t n = (size_t)m->nx * m->ny * m->nz;
    coded = coded && h->form == VSV_HEIGHTS_STORED;
    int rc = vsv_buf_u32(b, coded ? VSV_HEIGHTS_CODED : (uint32_t)h->form);
    if (!rc)
        rc = vsv_buf_u32(b, 0);
    if (!rc)
        rc = vsv_buf_u64(b, (uint64_t)h->time);
    if (rc)
        return rc;
    if (h->form == VSV_HEIGHTS_MM5) {
        for (int i = 0; i < 5 && !rc; i++)
            rc = vsv_buf_f64(b, h->mm5[i]);
        for (int k = 0; k < m->nz && !rc; k++)
            rc = vsv_buf_f64(b, h->sigma[k]);
        return rc;
    }
    if (coded) /* each height against the one below it */
        return vsv_floats_code(h->z, n, (size_t)m->nx * m->ny, b);
    if ((rc = vsv_buf_reserve(b, n * 4)))
        return rc;
    for (size_t i = 0; i < n; i++)
        vsv_wrf32(b->p + b->len + 4 * i, h->z[i]);
    b->len += n * 4;
    return 0;
}

int vsv_heights_decode(vsv_meta *m, const unsigned char *p, size_t len, char *msg, size_t cap)
{
    const size_t n = (size_t)m->nx * m->ny * m->nz;
    if (m->vert_kind != VSV_VERT_NATIVE || len < 16) {
        vsv_msg(msg, cap, "HGTS record on a grid without native levels, or short");
        return VSV_ECORRUPT;
    }
    const uint32_t form = vsv_rd32(p), zero = vsv_rd32(p + 4);
    const int64_t time = (int64_t)vsv_rd64(p + 8);
    int rc;
    if ((form == VSV_HEIGHTS_STORED && zero == 0 && len == 16 + 4 * n) ||
        (form == VSV_HEIGHTS_CODED && zero == 0 && len > 16)) {
        float *z = malloc(n * sizeof *z + 1);
        if (!z)
            return VSV_ENOMEM;
        rc = 0;
        if (form == VSV_HEIGHTS_CODED)
            rc = vsv_floats_decode(p + 16, len - 16, n, (size_t)m->nx * m->ny, z);
        else
            for (size_t i = 0; i < n; i++)
                z[i] = vsv_rdf32(p + 16 + 4 * i);
        if (rc == VSV_ECORRUPT) {
            free(z);
            vsv_msg(msg, cap, "HGTS record %d: its coded heights do not decode to %dx%dx%d values", m->nheights, m->nx,
                    m->ny, m->nz);
            return rc;
        }
        if (!rc)
            rc = vsv_meta_add_heights(m, time, z, NULL, NULL);
        free(z);
    } else if (form == VSV_HEIGHTS_MM5 && zero == 0 && len == 16 + 40 + 8 * (size_t)m->nz) {
        double mm5[5], *sigma = malloc((size_t)m->nz * sizeof *sigma);
        if (!sigma)
            return VSV_ENOMEM;
        for (int i = 0; i < 5; i++)
            mm5[i] = vsv_rdf64(p + 16 + 8 * i);
        for (int k = 0; k < m->nz; k++)
            sigma[k] = vsv_rdf64(p + 56 + 8 * k);
        rc = m->terrain ? vsv_meta_add_heights(m, time, NULL, mm5, sigma) : VSV_EINVAL;
        free(sigma);
    } else {
        vsv_msg(msg, cap, "HGTS record: form %u, %zu bytes for a %dx%dx%d grid", form, len, m->nx, m->ny, m->nz);
        return VSV_ECORRUPT;
    }
    if (rc == VSV_EINVAL) {
        vsv_msg(msg, cap,
                "HGTS record %d: heights not finite and increasing upward, out of time order, or an MM5 "
                "formula without terrain or with bad constants",
                m->nheights);
        return VSV_ECORRUPT;
    }
    return rc;
}

/* ----------------------------------------------------------- resampling */

typedef struct rs_volume {
    vsv_volume pub;
    float *store;
} rs_volume;

struct vsv_resampler {
    const vsv_meta *m;
    vsv_meta even; /* shallow: m's arrays */
    rs_volume out;
    const float *planned; /* the heights the plan was made for */
    vsv_vgrid vg;         /* per even cell: native level below, weight */
    uint64_t done_gen;
};

int vsv_resampler_create(const vsv_meta *m, vsv_resampler **out)
{
    *out = NULL;
    int nz;
    double z0, dz;
    if (vsv_heights_axis(m, &nz, &z0, &dz))
        return VSV_EINVAL;
    vsv_resampler *r = calloc(1, sizeof *r);
    if (!r)
        return VSV_ENOMEM;
    r->m = m;
    r->even = *m;
    r->even.vert_kind = VSV_VERT_EVEN;
    r->even.nz = nz;
    r->even.origin[2] = z0;
    r->even.spacing[2] = dz;
    r->even.levels = NULL;
    r->even.nheights = 0;
    r->even.heights = NULL;
    *out = r;
    return 0;
}

void vsv_resampler_free(vsv_resampler *r)
{
    if (!r)
        return;
    vsv_vgrid_free(&r->vg);
    free(r->out.pub.bricks);
    free(r->out.pub.bmin);
    free(r->out.pub.bmax);
    free(r->out.pub.bkey);
    free(r->out.store);
    free(r);
}

const vsv_meta *vsv_resampler_meta(const vsv_resampler *r) { return &r->even; }

static uint64_t mix64(uint64_t x)
{
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ull;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

/* The keys of the resampled bricks (vsv_volume.bkey): a brick's values
 * follow from its column of native bricks and the heights in force, so the
 * same native keys under the same heights give the same key, and a player
 * classifies again only the bricks whose column changed. Without native
 * keys, none (renderers then go by the volume's gen). */
static void resampled_keys(vsv_resampler *r, const vsv_volume *nat, const float *zn)
{
    vsv_volume *e = &r->out.pub;
    if (!nat->bkey) {
        free(e->bkey);
        e->bkey = NULL;
        return;
    }
    if (!e->bkey && !(e->bkey = calloc((size_t)(unsigned)e->nbricks + 1, sizeof *e->bkey)))
        return; /* (no keys: renderers go by gen) */
    for (int ob = 0; ob < e->nbricks; ob++) {
        const int bi = ob % e->bdim[0], bj = ob / e->bdim[0] % e->bdim[1];
        uint64_t h = mix64((uint64_t)(uintptr_t)zn ^ 0x7265736d706c6564ull) ^ (uint64_t)ob;
        for (int nk = 0; nk < nat->bdim[2]; nk++)
            h = mix64(h ^ nat->bkey[bi + nat->bdim[0] * (bj + nat->bdim[1] * nk)]);
        e->bkey[ob] = h | 1; /* never 0 */
    }
}

int vsv_resampler_run(vsv_resampler *r, const vsv_volume *nat, const vsv_volume **out)
{
    const vsv_meta *m = r->m;
    if (nat->nx != m->nx || nat->ny != m->ny || nat->nz != m->nz || nat->step < 0)
        return VSV_EINVAL;
    vsv_volume *e = &r->out.pub;
    *out = e;
    if (r->done_gen == nat->gen && nat->gen)
        return 0;
    const int B = nat->brick, nz = r->even.nz;
    const size_t n = (size_t)B * B * B, plane = (size_t)m->nx * m->ny;
    if (!e->bricks) {
        e->nx = m->nx;
        e->ny = m->ny;
        e->nz = nz;
        e->brick = B;
        e->shift = nat->shift;
        e->bdim[0] = nat->bdim[0];
        e->bdim[1] = nat->bdim[1];
        e->bdim[2] = (nz + B - 1) / B;
        e->nbricks = e->bdim[0] * e->bdim[1] * e->bdim[2];
        e->bricks = calloc((size_t)e->nbricks, sizeof *e->bricks);
        e->bmin = calloc((size_t)e->nbricks, sizeof *e->bmin);
        e->bmax = calloc((size_t)e->nbricks, sizeof *e->bmax);
        r->out.store = malloc((size_t)e->nbricks * n * sizeof *r->out.store);
        if (!e->bricks || !e->bmin || !e->bmax || !r->out.store)
            return VSV_ENOMEM;
    }
    const float *zn = vsv_meta_heights_at(m, nat->time);
    if (zn != r->planned) {
        if (vsv_vgrid_plan(&r->vg, zn, m->nz, plane, m->terrain, nz, r->even.origin[2], r->even.spacing[2]))
            return VSV_ENOMEM;
        r->planned = zn;
    }
    const float empty = nat->empty_value;
    e->empty_value = empty;
    e->step = nat->step;
    e->species = nat->species;
    e->time = nat->time;
    for (int b = 0; b < e->nbricks; b++) {
        e->bricks[b] = r->out.store + (size_t)b * n;
        e->bmin[b] = INFINITY;
        e->bmax[b] = -INFINITY;
    }
    const int empty_is_nan = isnan(empty);
    /* brick by brick of the output; one whose column of native bricks holds
     * only the empty value (most of a cloud species) is empty without a
     * look at its cells. Inside a brick level by level, row by row. */
    for (int ob = 0; ob < e->nbricks; ob++) {
        const int bi = ob % e->bdim[0], bj = ob / e->bdim[0] % e->bdim[1], bk = ob / (e->bdim[0] * e->bdim[1]);
        int any = 0;
        for (int nk = 0; nk < nat->bdim[2] && !any; nk++)
            any = nat->bricks[bi + nat->bdim[0] * (bj + nat->bdim[1] * nk)] != NULL;
        if (!any) {
            e->bmin[ob] = 1, e->bmax[ob] = 0; /* empty: cleared below */
            continue;
        }
        float *dst = e->bricks[ob];
        float mn = INFINITY, mx = -INFINITY;
        const int i0 = bi * B, j0 = bj * B, k0 = bk * B;
        const int i1 = i0 + B < m->nx ? i0 + B : m->nx, j1 = j0 + B < m->ny ? j0 + B : m->ny;
        for (int k = k0; k < k0 + B; k++)
            for (int j = j0; j < j1; j++) {
                float *o = dst + ((size_t)(k - k0) << (2 * e->shift)) + ((size_t)(j - j0) << e->shift);
                if (k >= nz) {
                    for (int i = i0; i < i1; i++)
                        o[i - i0] = empty;
                    continue;
                }
                const size_t row = (size_t)k * plane + (size_t)j * m->nx;
                for (int i = i0; i < i1; i++) {
                    float v = empty;
                    const int lv = r->vg.lev[row + i];
                    if (lv >= 0) {
                        const float lo = vsv_volume_at(nat, i, j, lv), w = r->vg.wt[row + i];
                        v = w == 0 ? lo : lo + (vsv_volume_at(nat, i, j, lv + 1) - lo) * w;
                        if (isnan(v) && !empty_is_nan)
                            v = empty;
                    }
                    o[i - i0] = v;
                    if (!isnan(v)) {
                        mn = v < mn ? v : mn;
                        mx = v > mx ? v : mx;
                    }
                }
            }
        e->bmin[ob] = mn;
        e->bmax[ob] = mx;
    }
    /* cells outside the grid along x and y, and bricks holding only the
     * empty value */
    for (int b = 0; b < e->nbricks; b++) {
        const int bi = b % e->bdim[0], bj = (b / e->bdim[0]) % e->bdim[1];
        const int ex = m->nx - bi * B < B ? m->nx - bi * B : B, ey = m->ny - bj * B < B ? m->ny - bj * B : B;
        float *dst = e->bricks[b];
        if (e->bmin[b] > e->bmax[b]) { /* nothing but the empty value, or skipped above */
            e->bricks[b] = NULL;
            e->bmin[b] = e->bmax[b] = empty;
            continue;
        }
        if (ex < B || ey < B)
            for (size_t q = 0; q < n; q++)
                if ((int)(q & (size_t)(B - 1)) >= ex || (int)((q >> e->shift) & (size_t)(B - 1)) >= ey)
                    dst[q] = empty;
        const int all_empty = e->bmin[b] > e->bmax[b] || (e->bmin[b] == empty && e->bmax[b] == empty);
        if (all_empty) {
            e->bricks[b] = NULL;
            e->bmin[b] = e->bmax[b] = empty;
        } else if (!empty_is_nan) {
            /* the empty value counts in the range where the brick holds it */
            if (empty < e->bmin[b])
                e->bmin[b] = empty;
            if (empty > e->bmax[b])
                e->bmax[b] = empty;
        }
    }
    resampled_keys(r, nat, zn);
    e->gen = vsv_volume_new_gen();
    r->done_gen = nat->gen;
    return 0;
}
