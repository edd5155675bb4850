/* vsv_raycast_simd.c — the raycaster's march sixteen rays at a time, one ray
 * per lane of two AVX2 registers: raycast_march (vsv_render.c) operation for
 * operation, in the same order, so a pixel does not depend on the rays beside
 * it. A step of one ray is a long chain of dependent operations (coordinates,
 * cells, trilinear, table, opacity); two registers of rays side by side give
 * the core two independent chains to overlap (measured: the step time hardly
 * grows from 8 to 16 rays). Each lane's eight cells and two transfer-function
 * entries are loaded as rows and transposed into lanes (cheaper than gathers
 * here, measured). Built with -mavx2 -mfma; the renderer calls it only when
 * the CPU has both. */
#include "vsv_render_internal.h"

#include <immintrin.h>
#include <limits.h>

#define H 2            /* AVX2 registers per packet */
#define W (8 * H)      /* rays per packet: VSV_RC_LANES */
typedef struct {
    __m256 r[H];
} vf;
typedef struct {
    __m256i r[H];
} vi;

#define EACH for (int h = 0; h < H; h++)
static inline vf fset(float x)
{
    vf o;
    EACH o.r[h] = _mm256_set1_ps(x);
    return o;
}
static inline vi iset(int x)
{
    vi o;
    EACH o.r[h] = _mm256_set1_epi32(x);
    return o;
}
/* name(a, b): op on each register of the pair */
#define BIN(T, name, op)                                                                                               \
    static inline T name(T a, T b)                                                                                     \
    {                                                                                                                  \
        T o;                                                                                                           \
        EACH o.r[h] = op(a.r[h], b.r[h]);                                                                              \
        return o;                                                                                                      \
    }
#define CMP_LT(a, b) _mm256_cmp_ps(a, b, _CMP_LT_OQ)
#define CMP_GT(a, b) _mm256_cmp_ps(a, b, _CMP_GT_OQ)
#define CMP_GE(a, b) _mm256_cmp_ps(a, b, _CMP_GE_OQ)
BIN(vf, add, _mm256_add_ps)
BIN(vf, sub, _mm256_sub_ps)
BIN(vf, mul, _mm256_mul_ps)
BIN(vf, vmin, _mm256_min_ps)
BIN(vf, vmax, _mm256_max_ps)
BIN(vf, fand, _mm256_and_ps)
BIN(vf, fandnot, _mm256_andnot_ps) /* ~a & b */
BIN(vf, lt, CMP_LT)
BIN(vf, gt, CMP_GT)
BIN(vf, ge, CMP_GE)
BIN(vi, iadd, _mm256_add_epi32)
BIN(vi, iand, _mm256_and_si256)
BIN(vi, ior, _mm256_or_si256)
BIN(vi, imin, _mm256_min_epi32)
BIN(vi, imul, _mm256_mullo_epi32)
BIN(vi, ieq, _mm256_cmpeq_epi32)
BIN(vi, igt, _mm256_cmpgt_epi32)
static inline vf blend(vf a, vf b, vf m) /* m ? b : a */
{
    vf o;
    EACH o.r[h] = _mm256_blendv_ps(a.r[h], b.r[h], m.r[h]);
    return o;
}
static inline vf as_f(vi x)
{
    vf o;
    EACH o.r[h] = _mm256_castsi256_ps(x.r[h]);
    return o;
}
static inline vi as_i(vf x)
{
    vi o;
    EACH o.r[h] = _mm256_castps_si256(x.r[h]);
    return o;
}
static inline vf to_f(vi x)
{
    vf o;
    EACH o.r[h] = _mm256_cvtepi32_ps(x.r[h]);
    return o;
}
static inline vi to_i(vf x) /* truncating */
{
    vi o;
    EACH o.r[h] = _mm256_cvttps_epi32(x.r[h]);
    return o;
}
static inline vi srl(vi x, int s)
{
    vi o;
    EACH o.r[h] = _mm256_srl_epi32(x.r[h], _mm_cvtsi32_si128(s));
    return o;
}
static inline vi sll(vi x, int s)
{
    vi o;
    EACH o.r[h] = _mm256_sll_epi32(x.r[h], _mm_cvtsi32_si128(s));
    return o;
}
static inline unsigned bits(vf m)
{
    unsigned b = 0;
    EACH b |= (unsigned)_mm256_movemask_ps(m.r[h]) << (8 * h);
    return b;
}
static inline void istore(int *p, vi x)
{
    EACH _mm256_storeu_si256((__m256i *)(p + 8 * h), x.r[h]);
}
static inline void fstore(float *p, vf x)
{
    EACH _mm256_storeu_ps(p + 8 * h, x.r[h]);
}
static inline vf fload(const float *p)
{
    vf o;
    EACH o.r[h] = _mm256_loadu_ps(p + 8 * h);
    return o;
}
static inline vi iload(const int *p)
{
    vi o;
    EACH o.r[h] = _mm256_loadu_si256((const __m256i *)(p + 8 * h));
    return o;
}
static inline __m256 lerp1(__m256 a, __m256 b, __m256 f) { return _mm256_fmadd_ps(_mm256_sub_ps(b, a), f, a); }
static inline vf fma3(vf a, vf b, vf c) /* a b + c */
{
    vf o;
    EACH o.r[h] = _mm256_fmadd_ps(a.r[h], b.r[h], c.r[h]);
    return o;
}
static inline vf fnma3(vf a, vf b, vf c) /* c - a b */
{
    vf o;
    EACH o.r[h] = _mm256_fnmadd_ps(a.r[h], b.r[h], c.r[h]);
    return o;
}
#define ALL ((1u << W) - 1)

/* r[l] holds eight values of lane l (of 8); afterwards r[k] holds value k of
 * every lane. */
static inline void transpose8(__m256 r[8])
{
    __m256 t[8], u[8];
    for (int i = 0; i < 8; i += 2) {
        t[i] = _mm256_unpacklo_ps(r[i], r[i + 1]);
        t[i + 1] = _mm256_unpackhi_ps(r[i], r[i + 1]);
    }
    for (int i = 0; i < 8; i += 4) {
        u[i] = _mm256_shuffle_ps(t[i], t[i + 2], _MM_SHUFFLE(1, 0, 1, 0));
        u[i + 1] = _mm256_shuffle_ps(t[i], t[i + 2], _MM_SHUFFLE(3, 2, 3, 2));
        u[i + 2] = _mm256_shuffle_ps(t[i + 1], t[i + 3], _MM_SHUFFLE(1, 0, 1, 0));
        u[i + 3] = _mm256_shuffle_ps(t[i + 1], t[i + 3], _MM_SHUFFLE(3, 2, 3, 2));
    }
    for (int i = 0; i < 4; i++) {
        r[i] = _mm256_permute2f128_ps(u[i], u[i + 4], 0x20);
        r[i + 4] = _mm256_permute2f128_ps(u[i], u[i + 4], 0x31);
    }
}

/* Byte flags at idx, as a mask (the array has four readable bytes past its end). */
static inline vf flags(const unsigned char *a, vi idx)
{
    vi o;
    EACH o.r[h] = _mm256_and_si256(_mm256_i32gather_epi32((const int *)a, idx.r[h], 1), _mm256_set1_epi32(0xff));
    return as_f(igt(o, iset(0)));
}

/* Four pairs along x of the cells from q: c000 c100 | c010 c110 | c001 c101 | c011 c111. */
static inline __m256 cell_row(const float *q, int dj, int dk)
{
    const __m128 lo = _mm_loadh_pi(_mm_castsi128_ps(_mm_loadl_epi64((const __m128i *)q)), (const __m64 *)(q + dj));
    const __m128 hi =
        _mm_loadh_pi(_mm_castsi128_ps(_mm_loadl_epi64((const __m128i *)(q + dk))), (const __m64 *)(q + dk + dj));
    return _mm256_set_m128(hi, lo);
}

/* Trilinear samples of layer L in every lane (the caller masks them): each
 * lane's eight cells loaded from the brick's sampling copy (four pairs along
 * x), transposed, interpolated. uni: every lane is in brick bidx[0]. */
static vf sample(const vsv_rc_layer *L, int uni, const int *bidx, const int *off, int ey, int ez, const vf f[3])
{
    vf v;
    const float *one = L->cells[bidx[0]];
    EACH { /* eight lanes at a time: their rows stay in registers */
        __m256 r[8];
        if (uni) /* the most common case */
            for (int l = 0; l < 8; l++)
                r[l] = cell_row(one + off[8 * h + l], ey, ez);
        else
            for (int l = 0; l < 8; l++)
                r[l] = cell_row(L->cells[bidx[8 * h + l]] + off[8 * h + l], ey, ez);
        transpose8(r); /* c000 c100 c010 c110 c001 c101 c011 c111, lane by lane */
        const __m256 fu = f[0].r[h], fv = f[1].r[h], fw = f[2].r[h];
        const __m256 a0 = lerp1(r[0], r[1], fu), a1 = lerp1(r[2], r[3], fu);
        const __m256 a2 = lerp1(r[4], r[5], fu), a3 = lerp1(r[6], r[7], fu);
        const __m256 e0 = lerp1(a0, a1, fv), e1 = lerp1(a2, a3, fv);
        v.r[h] = lerp1(e0, e1, fw);
    }
    return v;
}

void vsv_raycast16(const vsv_rc_frame *F, const vsv_rc_ray ray[W], float T_out[W], float acc_out[3][W],
                   float depth[W])
{
    float p[3][W], dp[3][W];
    int ns[W], nmax = 0;
    double st_d = 0;
    for (int l = 0; l < W; l++) {
        ns[l] = ray[l].ns;
        for (int a = 0; a < 3; a++) {
            p[a][l] = ns[l] ? ray[l].p[a] : 0;
            dp[a][l] = ns[l] ? ray[l].dp[a] : 0;
        }
        if (ns[l] > nmax)
            nmax = ns[l], st_d = ray[l].st;
    }
    if (!nmax || !F->nlayers)
        return;
    vf P[3], DP[3], HI[3];
    vi LAST[3];
    for (int a = 0; a < 3; a++) {
        P[a] = fload(p[a]);
        DP[a] = fload(dp[a]);
        HI[a] = fset(F->hi[a]);
        LAST[a] = iset(F->last[a]);
    }
    const vi NS = iload(ns), M = iset(F->mask), BX = iset(F->bx), BXY = iset(F->bxy), EY = iset(F->ey), EZ = iset(F->ez);
    const int sh = F->shift;
    const vf ST = fset((float)st_d), ONE = fset(1), ZERO = fset(0);
    const vf TERM = fset(1.0f / 512), LUTMAX = fset(VSV_TF_LUT - 1), DEPTH = fset(0.1f);
    const vi LUTI = iset(VSV_TF_LUT - 2);
    const vf UMAX = fset(VSV_OPACITY_UMAX), UK = fset(VSV_OPACITY_N / VSV_OPACITY_UMAX), HALF = fset(0.5f);
    const vf SMALL = fset(VSV_OPACITY_SMALL);
    const vf SERIES[5] = {fset(1.0f / 120), fset(-1.0f / 24), fset(1.0f / 6), fset(-1.0f / 2), ONE};
    vf T = ONE, acc[3] = {ZERO, ZERO, ZERO};
    unsigned deep_set = 0; /* lanes whose depth is set */
    for (int n = 0; n < nmax; n++) {
        const vi N = iset(n);
        const vf act = fand(as_f(igt(NS, N)), ge(T, TERM));
        if (!bits(act))
            break; /* every ray has ended or is opaque */
        const vf NF = to_f(N);
        vf c[3], f[3];
        vi ci[3];
        for (int a = 0; a < 3; a++) {
            c[a] = fma3(NF, DP[a], P[a]);
            c[a] = vmax(vmin(c[a], HI[a]), ZERO);
            ci[a] = imin(to_i(c[a]), LAST[a]);
        }
        const vi bidx = iadd(iadd(srl(ci[0], sh), imul(BX, srl(ci[1], sh))), imul(BXY, srl(ci[2], sh)));
        int bidx_a[W];
        istore(bidx_a, bidx);
        /* every lane in one brick? */
        const int uni = bits(as_f(ieq(bidx, iset(bidx_a[0])))) == ALL;
        vf comp = act;
        if (F->skip) {
            comp = uni ? (F->skip[bidx_a[0]] ? ZERO : act) : fandnot(flags(F->skip, bidx), act);
            if (!bits(comp)) {
                /* every live ray is in a skipped brick: on to the nearest far side */
                int ci_a[3][W], next = INT_MAX;
                for (int a = 0; a < 3; a++)
                    istore(ci_a[a], ci[a]);
                const unsigned live = bits(act);
                for (int l = 0; l < W; l++)
                    if (live >> l & 1) {
                        const int cl[3] = {ci_a[0][l], ci_a[1][l], ci_a[2][l]};
                        const int k = vsv_rc_skip_to(F, &ray[l], cl);
                        next = k < next ? k : next;
                    }
                if (next > n + 1)
                    n = next - 1;
                continue;
            }
        }
        for (int a = 0; a < 3; a++)
            f[a] = sub(c[a], to_f(ci[a]));
        const vi off = iadd(iadd(iand(ci[0], M), imul(iand(ci[1], M), EY)), imul(iand(ci[2], M), EZ));
        int off_a[W];
        istore(off_a, off);
        vf sig = ZERO, col[3] = {ZERO, ZERO, ZERO};
        for (int li = 0; li < F->nlayers; li++) {
            const vsv_rc_layer *L = &F->layer[li];
            vf m = comp;
            if (F->skip) /* transparent around this brick */
                m = uni ? (L->clear[bidx_a[0]] ? ZERO : m) : fandnot(flags(L->clear, bidx), m);
            if (!bits(m))
                continue;
            const vf v = sample(L, uni, bidx_a, off_a, F->ey, F->ez, f);
            const vf valid = fand(m, ge(v, fset(L->lo)));
            const unsigned vb = bits(valid);
            if (!vb)
                continue;
            vf xv = v;
            if (L->log) {
                float t[W];
                fstore(t, v);
                for (int l = 0; l < W; l++)
                    t[l] = vb >> l & 1 ? logf(t[l]) : 0;
                xv = fload(t);
            }
            const vf x = vmin(fma3(xv, fset(L->inv), fset(L->off)), LUTMAX);
            const vi i = imin(to_i(x), LUTI);
            const vf fx = sub(x, to_f(i));
            /* each lane's two table entries (eight floats in a row), transposed */
            int ia[W];
            istore(ia, iand(i, as_i(valid)));
            const __m256 sigma = _mm256_set1_ps(L->sigma);
            EACH { /* eight lanes at a time */
                __m256 e[8]; /* r g b a of entry i, then of entry i + 1 */
                for (int l = 0; l < 8; l++)
                    e[l] = _mm256_loadu_ps(L->lut[ia[8 * h + l]]);
                transpose8(e);
                /* s <= 0 (a hair below the table) and lanes without a value add 0;
                 * products summed by plain additions: two species give the
                 * same bits in either order */
                const __m256 t = fx.r[h], s0 = _mm256_mul_ps(lerp1(e[3], e[7], t), sigma);
                const __m256 s = _mm256_and_ps(_mm256_max_ps(s0, _mm256_setzero_ps()), valid.r[h]);
                sig.r[h] = _mm256_add_ps(sig.r[h], s);
                for (int ch = 0; ch < 3; ch++)
                    col[ch].r[h] = _mm256_add_ps(col[ch].r[h], _mm256_mul_ps(s, lerp1(e[ch], e[ch + 4], t)));
            }
        }
        const vf cm = gt(sig, ZERO); /* only lanes of comp have added anything */
        const unsigned cb = bits(cm);
        if (!cb)
            continue;
        /* the step's opacity as vsv_rc_opacity_per_u: the series, the table, 1/u */
        const vf us = mul(sig, ST);
        vf fo = fset(-1.0f / 720);
        for (int t = 0; t < 5; t++)
            fo = fma3(us, fo, SERIES[t]);
        const vf thick = fand(cm, ge(us, SMALL));
        if (bits(thick)) {
            const vf in = fand(thick, lt(us, UMAX));
            const vi ti = to_i(fand(in, add(mul(us, UK), HALF)));
            vf tab;
            EACH tab.r[h] = _mm256_mask_i32gather_ps(_mm256_setzero_ps(), vsv_opacity_table, ti.r[h], in.r[h], 4);
            fo = blend(fo, tab, in);
            if (bits(in) != bits(thick)) { /* beyond the table: 1/u */
                vf inv;
                EACH inv.r[h] = _mm256_div_ps(ONE.r[h], us.r[h]);
                fo = blend(fo, inv, fandnot(in, thick));
            }
        }
        /* the other lanes have sig = 0, so us = 0, fo = 1, a = 0, col = 0: no change */
        const vf a = mul(us, fo), k = mul(mul(T, fo), ST);
        for (int ch = 0; ch < 3; ch++)
            acc[ch] = fma3(k, col[ch], acc[ch]);
        T = fnma3(T, a, T);
        const unsigned deep = bits(fand(cm, gt(sub(ONE, T), DEPTH))) & ~deep_set;
        for (int l = 0; deep && l < W; l++)
            if (deep >> l & 1 && depth[l] == INFINITY)
                depth[l] = (float)(ray[l].ts + n * ray[l].st);
        deep_set |= deep;
    }
    fstore(T_out, T);
    for (int ch = 0; ch < 3; ch++)
        fstore(acc_out[ch], acc[ch]);
}
