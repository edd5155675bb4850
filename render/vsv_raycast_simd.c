/* vsv_raycast_simd.c — the raycaster's march sixteen rays at a time, one ray
 * per lane: raycast_march (vsv_render.c) operation for operation, in the same
 * order, so a pixel does not depend on the rays beside it. A step of one ray is
 * a long chain of dependent operations (coordinates, cells, trilinear, table,
 * opacity); sixteen rays side by side give the core independent chains to
 * overlap (measured: the step time hardly grows from 8 to 16 rays). Each
 * lane's eight cells and two transfer-function entries are loaded as rows and
 * transposed into lanes (cheaper than gathers here, measured).
 *
 * One source, two builds, over a small layer of vector types and operations
 * (vf floats, vi integers, vm lane masks): this file with -mavx2 -mfma is
 * vsv_raycast16 (the rays in two AVX2 registers, masks as all-ones lanes);
 * vsv_raycast_avx512.c includes it with VSV_RC_AVX512 for
 * vsv_raycast16_avx512 (one AVX-512 register, masks in mask registers, 32
 * registers: no spills; 5-8 % faster on the Zen 4 this was measured on).
 * The renderer calls each only when the CPU has what it was built for. */
#include "vsv_rc.h"

#include <immintrin.h>
#include <limits.h>

/* Each build lifts its intrinsics into the layer's operations with the same
 * macros: TRI (three float operands), BIN (two), UN (one), SPLAT (a scalar
 * to every lane), LOAD (sixteen values from memory); V(op) names the build's
 * intrinsic. The operations both builds spell alike are listed once, after
 * the two. */
#if VSV_RC_AVX512
/* AVX-512F: the sixteen rays in one register, comparisons into mask registers */
#define VSV_RC_KERNEL vsv_raycast16_avx512
typedef __m512 vf;
typedef __m512i vi;
typedef __mmask16 vm;
#define V(op) _mm512_##op
#define BIN(To, Ti, name, op)                                                                                          \
    static inline To name(Ti a, Ti b) { return op(a, b); }
#define UN(To, Ti, name, op)                                                                                           \
    static inline To name(Ti a) { return op(a); }
#define TRI(name, op)                                                                                                  \
    static inline vf name(vf a, vf b, vf c) { return op(a, b, c); }
#define SPLAT UN
#define LOAD(To, Ts, name, op)                                                                                         \
    static inline To name(const Ts *p) { return op(p); }
#define CMP_LT(a, b) _mm512_cmp_ps_mask(a, b, _CMP_LT_OQ)
#define CMP_GT(a, b) _mm512_cmp_ps_mask(a, b, _CMP_GT_OQ)
#define CMP_GE(a, b) _mm512_cmp_ps_mask(a, b, _CMP_GE_OQ)
#define CMP_EQ(a, b) _mm512_cmp_ps_mask(a, b, _CMP_EQ_OQ)
#define CEIL(a) _mm512_roundscale_ps(a, _MM_FROUND_TO_POS_INF | _MM_FROUND_NO_EXC)
#define IGT _mm512_cmpgt_epi32_mask
#define IEQ _mm512_cmpeq_epi32_mask
#define IAND _mm512_and_si512
#define ILOAD _mm512_loadu_si512
#else
/* AVX2: the sixteen rays in two registers, comparisons as all-ones lanes */
#define VSV_RC_KERNEL vsv_raycast16
#define H 2 /* AVX2 registers per packet */
typedef struct {
    __m256 r[H];
} vf;
typedef struct {
    __m256i r[H];
} vi;
typedef vf vm;
#define V(op) _mm256_##op
#define EACH for (int h = 0; h < H; h++)
#define BIN(To, Ti, name, op)                                                                                          \
    static inline To name(Ti a, Ti b)                                                                                  \
    {                                                                                                                  \
        To o;                                                                                                          \
        EACH o.r[h] = op(a.r[h], b.r[h]);                                                                              \
        return o;                                                                                                      \
    }
#define UN(To, Ti, name, op)                                                                                           \
    static inline To name(Ti a)                                                                                        \
    {                                                                                                                  \
        To o;                                                                                                          \
        EACH o.r[h] = op(a.r[h]);                                                                                      \
        return o;                                                                                                      \
    }
#define TRI(name, op)                                                                                                  \
    static inline vf name(vf a, vf b, vf c)                                                                            \
    {                                                                                                                  \
        vf o;                                                                                                          \
        EACH o.r[h] = op(a.r[h], b.r[h], c.r[h]);                                                                      \
        return o;                                                                                                      \
    }
#define SPLAT(To, Ts, name, op)                                                                                        \
    static inline To name(Ts x)                                                                                        \
    {                                                                                                                  \
        To o;                                                                                                          \
        EACH o.r[h] = op(x);                                                                                           \
        return o;                                                                                                      \
    }
#define LOAD(To, Ts, name, op)                                                                                         \
    static inline To name(const Ts *p)                                                                                 \
    {                                                                                                                  \
        To o;                                                                                                          \
        EACH o.r[h] = op(p + 8 * h);                                                                                   \
        return o;                                                                                                      \
    }
#define CMP_LT(a, b) _mm256_cmp_ps(a, b, _CMP_LT_OQ)
#define CMP_GT(a, b) _mm256_cmp_ps(a, b, _CMP_GT_OQ)
#define CMP_GE(a, b) _mm256_cmp_ps(a, b, _CMP_GE_OQ)
#define CMP_EQ(a, b) _mm256_cmp_ps(a, b, _CMP_EQ_OQ)
#define CEIL _mm256_ceil_ps
#define IGT(a, b) _mm256_castsi256_ps(_mm256_cmpgt_epi32(a, b))
#define IEQ(a, b) _mm256_castsi256_ps(_mm256_cmpeq_epi32(a, b))
#define IAND _mm256_and_si256
#define ILOAD(p) _mm256_loadu_si256((const __m256i *)(p))
#endif
BIN(vf, vf, add, V(add_ps))
BIN(vf, vf, sub, V(sub_ps))
BIN(vf, vf, mul, V(mul_ps))
BIN(vf, vf, vdiv, V(div_ps))
BIN(vf, vf, vmin, V(min_ps))
BIN(vf, vf, vmax, V(max_ps))
BIN(vm, vf, lt, CMP_LT)
BIN(vm, vf, gt, CMP_GT)
BIN(vm, vf, ge, CMP_GE)
BIN(vm, vf, eq, CMP_EQ)
BIN(vi, vi, iadd, V(add_epi32))
BIN(vi, vi, iand, IAND)
BIN(vi, vi, imin, V(min_epi32))
BIN(vi, vi, imax, V(max_epi32))
BIN(vi, vi, isub, V(sub_epi32))
BIN(vi, vi, imul, V(mullo_epi32))
BIN(vi, vi, srlv, V(srlv_epi32)) /* lane by lane */
BIN(vm, vi, igt, IGT)
BIN(vm, vi, ieq, IEQ)
TRI(fma3, V(fmadd_ps))   /* a b + c */
TRI(fnma3, V(fnmadd_ps)) /* c - a b */
UN(vf, vi, to_f, V(cvtepi32_ps))
UN(vi, vf, to_i, V(cvttps_epi32)) /* truncating */
UN(vf, vf, vsqrt, V(sqrt_ps))
UN(vf, vf, vceil, CEIL)
SPLAT(vf, float, fset, V(set1_ps))
SPLAT(vi, int, iset, V(set1_epi32))
LOAD(vf, float, fload, V(loadu_ps))
LOAD(vi, int, iload, ILOAD)
#if VSV_RC_AVX512
static inline vm mand(vm a, vm b) { return a & b; }
static inline vm mandnot(vm a, vm b) { return (vm)(~a & b); } /* ~a & b */
static inline vm mor(vm a, vm b) { return a | b; }
static inline vm lanes(unsigned b) { return (vm)b; } /* the lanes whose bits are set */
static const vm MNONE = 0;
static inline unsigned bits(vm m) { return m; }
static inline vf keep(vm m, vf x) { return _mm512_maskz_mov_ps(m, x); } /* m ? x : 0 */
static inline vi ikeep(vm m, vi x) { return _mm512_maskz_mov_epi32(m, x); }
static inline vf sel(vf a, vf b, vm m) { return _mm512_mask_blend_ps(m, a, b); } /* m ? b : a */
static inline vi srl(vi x, int s) { return _mm512_srl_epi32(x, _mm_cvtsi32_si128(s)); }
static inline vi sll(vi x, int s) { return _mm512_sll_epi32(x, _mm_cvtsi32_si128(s)); }
/* words[idx] where m, else 0 */
static inline vi igather(const uint32_t *words, vi idx, vm m)
{
    return _mm512_mask_i32gather_epi32(_mm512_setzero_si512(), m, idx, (const int *)words, 4);
}
static inline void istore(void *p, vi x) { _mm512_storeu_si512(p, x); }
static inline void fstore(float *p, vf x) { _mm512_storeu_ps(p, x); }
/* table[idx] where m, else 0 */
static inline vf mgather(const float *table, vi idx, vm m)
{
    return _mm512_mask_i32gather_ps(_mm512_setzero_ps(), m, idx, table, 4);
}
/* byte flags at idx, as a mask (the array has four readable bytes past its end) */
static inline vm flags(const unsigned char *a, vi idx)
{
    return _mm512_test_epi32_mask(_mm512_i32gather_epi32(idx, (const int *)a, 1), _mm512_set1_epi32(0xff));
}
/* byte values at idx (the array has three readable bytes past its end) */
static inline vi bytes(const unsigned char *a, vi idx)
{
    return _mm512_and_si512(_mm512_i32gather_epi32(idx, (const int *)a, 1), _mm512_set1_epi32(0xff));
}
static inline vi isel(vi a, vi b, vm m) { return _mm512_mask_blend_epi32(m, a, b); } /* m ? b : a */
static inline int lane0(vi x) { return _mm_cvtsi128_si32(_mm512_castsi512_si128(x)); }
/* the eight lanes 8h.. as an AVX2 register, and back */
static inline __m256 half(vf x, int h)
{
    return h ? _mm256_castpd_ps(_mm512_extractf64x4_pd(_mm512_castps_pd(x), 1)) : _mm512_castps512_ps256(x);
}
static inline vf join(__m256 lo, __m256 hi)
{
    return _mm512_castpd_ps(_mm512_insertf64x4(_mm512_castps_pd(_mm512_castps256_ps512(lo)), _mm256_castps_pd(hi), 1));
}
#else
BIN(vf, vf, mand, _mm256_and_ps)
BIN(vf, vf, mandnot, _mm256_andnot_ps) /* ~a & b */
BIN(vf, vf, mor, _mm256_or_ps)
BIN(vf, vf, keep, _mm256_and_ps) /* keep(m, x): m ? x : 0 */
static const vm MNONE;
static inline unsigned bits(vm m)
{
    unsigned b = 0;
    EACH b |= (unsigned)_mm256_movemask_ps(m.r[h]) << (8 * h);
    return b;
}
static inline vi ikeep(vm m, vi x)
{
    vi o;
    EACH o.r[h] = _mm256_and_si256(x.r[h], _mm256_castps_si256(m.r[h]));
    return o;
}
static inline vf sel(vf a, vf b, vm m) /* m ? b : a */
{
    vf o;
    EACH o.r[h] = _mm256_blendv_ps(a.r[h], b.r[h], m.r[h]);
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
static inline vi igather(const uint32_t *words, vi idx, vm m) /* words[idx] where m, else 0 */
{
    vi o;
    EACH o.r[h] = _mm256_mask_i32gather_epi32(_mm256_setzero_si256(), (const int *)words, idx.r[h],
                                              _mm256_castps_si256(m.r[h]), 4);
    return o;
}
static inline void istore(void *p, vi x) { EACH _mm256_storeu_si256((__m256i *)p + h, x.r[h]); }
static inline void fstore(float *p, vf x) { EACH _mm256_storeu_ps(p + 8 * h, x.r[h]); }
static inline vf mgather(const float *table, vi idx, vm m) /* table[idx] where m, else 0 */
{
    vf o;
    EACH o.r[h] = _mm256_mask_i32gather_ps(_mm256_setzero_ps(), table, idx.r[h], m.r[h], 4);
    return o;
}
/* byte flags at idx, as a mask (the array has four readable bytes past its end) */
static inline vm flags(const unsigned char *a, vi idx)
{
    vi o;
    EACH o.r[h] = _mm256_and_si256(_mm256_i32gather_epi32((const int *)a, idx.r[h], 1), _mm256_set1_epi32(0xff));
    return igt(o, iset(0));
}
/* byte values at idx (the array has three readable bytes past its end) */
static inline vi bytes(const unsigned char *a, vi idx)
{
    vi o;
    EACH o.r[h] = _mm256_and_si256(_mm256_i32gather_epi32((const int *)a, idx.r[h], 1), _mm256_set1_epi32(0xff));
    return o;
}
static inline int lane0(vi x) { return _mm_cvtsi128_si32(_mm256_castsi256_si128(x.r[0])); }
static inline vm lanes(unsigned b) /* the lanes whose bits are set */
{
    vm o;
    EACH o.r[h] = _mm256_castsi256_ps(_mm256_cmpgt_epi32(
        _mm256_and_si256(_mm256_set1_epi32((int)(b >> 8 * h)), _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128)),
        _mm256_setzero_si256()));
    return o;
}
static inline vi isel(vi a, vi b, vm m) /* m ? b : a */
{
    vi o;
    EACH o.r[h] =
        _mm256_castps_si256(_mm256_blendv_ps(_mm256_castsi256_ps(a.r[h]), _mm256_castsi256_ps(b.r[h]), m.r[h]));
    return o;
}
static inline __m256 half(vf x, int h) { return x.r[h]; }
static inline vf join(__m256 lo, __m256 hi) { return (vf){{lo, hi}}; }
#endif
#define W 16 /* rays per packet: VSV_RC_LANES */
static const int IOTA[W] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
#define ALL ((1u << W) - 1)
static inline __m256 lerp1(__m256 a, __m256 b, __m256 f) { return _mm256_fmadd_ps(_mm256_sub_ps(b, a), f, a); }

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
static vf sample(const vsv_rc_layer *L, int uni, const unsigned *bidx, const unsigned *off, int ey, int ez,
                 const vf f[3])
{
    __m256 v[2];
    const float *one = L->cells[bidx[0]];
    for (int h = 0; h < 2; h++) { /* eight lanes at a time: their rows stay in registers */
        __m256 r[8];
        if (uni) /* the most common case */
            for (int l = 0; l < 8; l++)
                r[l] = cell_row(one + off[8 * h + l], ey, ez);
        else
            for (int l = 0; l < 8; l++)
                r[l] = cell_row(L->cells[bidx[8 * h + l]] + off[8 * h + l], ey, ez);
        transpose8(r); /* c000 c100 c010 c110 c001 c101 c011 c111, lane by lane */
        const __m256 fu = half(f[0], h), fv = half(f[1], h), fw = half(f[2], h);
        const __m256 a0 = lerp1(r[0], r[1], fu), a1 = lerp1(r[2], r[3], fu);
        const __m256 a2 = lerp1(r[4], r[5], fu), a3 = lerp1(r[6], r[7], fu);
        const __m256 e0 = lerp1(a0, a1, fv), e1 = lerp1(a2, a3, fv);
        v[h] = lerp1(e0, e1, fw);
    }
    return join(v[0], v[1]);
}

/* The next sample of the rays in leap (vsv_rc_leap, lane by lane): out of
 * the box of blocks within d - 1 of their block for the lanes in empty,
 * out of their (clear) cell for the others; kept out of the kernel's loop,
 * whose registers it would crowd. */
static __attribute__((noinline)) vi leap_to(const vsv_rc_frame *F, const vf P[3], const vf DP[3], const vf IDP[3],
                                            vi NS, vf NL, vi N, const vi ci[3], vi d, vm empty, vm leap)
{
    const vi ONEI = iset(1), ZEROI = iset(0);
    const vf ZERO = fset(0);
    const vi dd = isel(ONEI, d, empty), size = isel(ONEI, iset(VSV_RC_BLOCK), empty);
    vf k = to_f(NS);
    vi up[3], down[3];
    for (int a = 0; a < 3; a++) {
        const vi b = isel(ci[a], srl(ci[a], VSV_RC_BSHIFT), empty), last = iset(F->last[a]);
        up[a] = imul(iadd(b, dd), size);
        down[a] = imul(iadd(isub(b, dd), ONEI), size);
        const vm pos = gt(DP[a], ZERO), neg = lt(DP[a], ZERO);
        const vf ka = mul(sub(to_f(isel(down[a], up[a], pos)), P[a]), IDP[a]);
        k = sel(k, ka, mand(mandnot(igt(up[a], last), pos), lt(ka, k)));
        k = sel(k, ka, mand(mand(neg, igt(down[a], ZEROI)), lt(ka, k)));
    }
    vi kn = imax(to_i(k), N);
    const vf KF = sel(to_f(kn), NL, ieq(kn, isub(NS, ONEI))); /* the last sample where it is */
    vm inbox = leap;
    for (int a = 0; a < 3; a++) { /* sample kn's cell, as the kernel finds it */
        const vi ck = imin(to_i(vmax(vmin(fma3(KF, DP[a], P[a]), fset(F->hi[a])), ZERO)), iset(F->last[a]));
        inbox = mand(inbox, mandnot(igt(down[a], ck), igt(up[a], ck)));
    }
    kn = iadd(kn, ikeep(inbox, ONEI));
    return isel(N, imax(kn, iadd(N, ONEI)), leap);
}

/* The layers' classification at one sample of each lane of comp: the summed
 * extinction (sig) and colour weighted by it (col), as the scalar march. */
static inline __attribute__((always_inline)) void classify(const vsv_rc_frame *F, vm comp, int ublk, vi blk, int uni,
                                                           const unsigned *bidx_a, const unsigned *off_a, const vf f[3],
                                                           vf *sig, vf col[3])
{
    const vf LUTMAX = fset(VSV_TF_LUT - 1), ZERO = fset(0);
    const vi LUTI = iset(VSV_TF_LUT - 2);
    *sig = ZERO;
    for (int ch = 0; ch < 3; ch++)
        col[ch] = ZERO;
    for (int li = 0; li < F->nlayers; li++) {
        const vsv_rc_layer *L = &F->layer[li];
        vm m = comp;
        if (F->skip && F->layer_clear) /* transparent in this block */
            m = ublk ? (L->clear[lane0(blk)] ? MNONE : m) : mandnot(flags(L->clear, blk), m);
        if (!bits(m))
            continue;
        const vf v = sample(L, uni, bidx_a, off_a, F->ey, F->ez, f);
        const vm valid = mand(m, ge(v, fset(L->lo)));
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
        unsigned ia[W];
        istore(ia, ikeep(valid, i));
        __m256 la[2], lc[3][2];
        for (int h = 0; h < 2; h++) { /* eight lanes at a time */
            __m256 e[8];              /* r g b a of entry i, then of entry i + 1 */
            for (int l = 0; l < 8; l++)
                e[l] = _mm256_loadu_ps(L->lut[ia[8 * h + l]]);
            transpose8(e);
            const __m256 t = half(fx, h);
            la[h] = lerp1(e[3], e[7], t);
            for (int ch = 0; ch < 3; ch++)
                lc[ch][h] = lerp1(e[ch], e[ch + 4], t);
        }
        /* s <= 0 (a hair below the table) and lanes without a value add 0;
         * products summed by plain additions: two species give the same
         * bits in either order */
        const vf s = keep(valid, vmax(mul(join(la[0], la[1]), fset(L->sigma)), ZERO));
        *sig = add(*sig, s);
        for (int ch = 0; ch < 3; ch++)
            col[ch] = add(col[ch], mul(s, join(lc[ch][0], lc[ch][1])));
    }
}

/* The step's opacity for the lanes of cm (as vsv_rc_opacity_per_u: the
 * series, the table, 1/u), composited front to back into T and acc; the
 * depth of each lane where it first passes 0.1 opacity. */
static inline __attribute__((always_inline)) void composite(const vsv_rc_frame *F, vm cm, vm lastm, vf sig,
                                                            const vf col[3], vf WL, vi N, const float *ts, vf *T,
                                                            vf acc[3], unsigned *deep_set, float depth[W])
{
    const vf ONE = fset(1), ST = fset((float)F->st), DEPTH = fset(0.1f);
    const vf UMAX = fset(VSV_OPACITY_UMAX), UK = fset(VSV_OPACITY_N / VSV_OPACITY_UMAX), HALF = fset(0.5f);
    const vf SMALL = fset(VSV_OPACITY_SMALL);
    const vf SERIES[5] = {fset(1.0f / 120), fset(-1.0f / 24), fset(1.0f / 6), fset(-1.0f / 2), ONE};
    /* the step's opacity as vsv_rc_opacity_per_u: the series, the table, 1/u */
    const vf STN = sel(ST, mul(ST, WL), lastm);
    const vf us = mul(sig, STN);
    vf fo = fset(-1.0f / 720);
    for (int t = 0; t < 5; t++)
        fo = fma3(us, fo, SERIES[t]);
    const vm thick = mand(cm, ge(us, SMALL));
    if (bits(thick)) {
        const vm in = mand(thick, lt(us, UMAX));
        const vi ti = to_i(keep(in, add(mul(us, UK), HALF)));
        fo = sel(fo, mgather(vsv_opacity_table, ti, in), in);
        if (bits(in) != bits(thick)) { /* beyond the table: 1/u */
            fo = sel(fo, vdiv(ONE, us), mandnot(in, thick));
        }
    }
    /* the other lanes have sig = 0, so us = 0, fo = 1, a = 0, col = 0: no change */
    const vf a = mul(us, fo), k = mul(mul(*T, fo), STN);
    for (int ch = 0; ch < 3; ch++)
        acc[ch] = fma3(k, col[ch], acc[ch]);
    *T = fnma3(*T, a, *T);
    const unsigned deep = bits(mand(cm, gt(sub(ONE, *T), DEPTH))) & ~*deep_set;
    if (deep) {
        int n_a[W];
        istore(n_a, N);
        for (int l = 0; l < W; l++)
            if (deep >> l & 1 && depth[l] == INFINITY)
                depth[l] = (float)(F->st * ((double)ts[l] + n_a[l]));
    }
    *deep_set |= deep;
}

void VSV_RC_KERNEL(const vsv_rc_frame *F, int px, float sy, unsigned live, const float s_hit[W], float T_out[W],
                   float acc_out[3][W], float depth[W])
{
    if (!F->nlayers)
        return;
    const vsv_rc_cam *C = &F->cam;
    const vf ONE = fset(1), ZERO = fset(0);
    const vi ZEROI = iset(0);
    /* the rays, as vsv_rc_ray_setup: the same operations in the same order */
    const vf SX = fma3(to_f(iadd(iset(px), iload(IOTA))), fset(C->sxk), fset(C->sx0)), SY = fset(sy);
    vf O[3], DP[3], IDP[3], P[3];
    if (C->persp) {
        const vf k = vdiv(ONE, vsqrt(fma3(SX, SX, fma3(SY, SY, ONE))));
        for (int a = 0; a < 3; a++) {
            O[a] = fset(C->o[a]);
            DP[a] = mul(fma3(SX, fset(C->r[a]), fma3(SY, fset(C->u[a]), fset(C->f[a]))), k);
        }
    } else {
        for (int a = 0; a < 3; a++) {
            O[a] = fma3(SX, fset(C->r[a]), fma3(SY, fset(C->u[a]), fset(C->o[a])));
            DP[a] = fset(C->f[a]);
        }
    }
    vf lo = fset(-INFINITY), hi = fset(INFINITY);
    vm out = MNONE;
    for (int a = 0; a < 3; a++) {
        const vf bmin = fset(C->bmin[a]), bmax = fset(C->bmax[a]);
        IDP[a] = vdiv(ONE, DP[a]);
        const vf s0 = mul(sub(bmin, O[a]), IDP[a]), s1 = mul(sub(bmax, O[a]), IDP[a]);
        const vf near = vmin(s0, s1), far = vmax(s0, s1);
        const vm flat = eq(DP[a], ZERO);
        out = mor(out, mand(flat, mor(lt(O[a], bmin), gt(O[a], bmax))));
        lo = sel(lo, near, mandnot(flat, gt(near, lo)));
        hi = sel(hi, far, mandnot(flat, lt(far, hi)));
    }
    const vm hit = mandnot(out, mand(ge(hi, lo), gt(hi, ZERO)));
    lo = sel(lo, fset(C->snear), lt(lo, fset(C->snear)));
    hi = sel(hi, fset(C->sfar), gt(hi, fset(C->sfar)));
    const vf TS = add(lo, fset(0.5f)), seg = sub(vmin(hi, fload(s_hit)), lo);
    const vm has = mand(mand(hit, gt(seg, ZERO)), lanes(live));
    if (!bits(has))
        return;
    const vi NS = ikeep(has, to_i(vceil(vmin(seg, fset(1e8f))))), NS1 = isub(NS, iset(1));
    const vf WL = vmin(sub(seg, to_f(NS1)), fset(1)); /* the last sample's part step, and where it is */
    const vf NL = fma3(fset(0.5f), WL, sub(to_f(NS1), fset(0.5f)));
    float ts[W];
    fstore(ts, TS);
    for (int a = 0; a < 3; a++) { /* lanes without samples at 0: every index they make is in range */
        P[a] = keep(has, fma3(TS, DP[a], O[a]));
        DP[a] = keep(has, DP[a]);
        IDP[a] = keep(has, IDP[a]);
    }
    vf HI[3];
    vi LAST[3];
    for (int a = 0; a < 3; a++) {
        HI[a] = fset(F->hi[a]);
        LAST[a] = iset(F->last[a]);
    }
    const vi M = iset(F->mask), BX = iset(F->bx), BXY = iset(F->bxy), EY = iset(F->ey), EZ = iset(F->ez);
    const vi NBX = iset(F->nbx), NBXY = iset(F->nbxy), ONEI = iset(1);
    const vi B3 = iset(VSV_RC_BLOCK - 1), B31 = iset(31);
    const int sh = F->shift;
    const vf TERM = fset(F->term);
    vf T = ONE, acc[3] = {ZERO, ZERO, ZERO};
    vi N = ZEROI;          /* each ray's sample: rays leap on their own */
    unsigned deep_set = 0; /* lanes whose depth is set */
    for (;;) {
        const vm act = mand(igt(NS, N), ge(T, TERM));
        if (!bits(act))
            break; /* every ray has ended or is opaque */
        const vm lastm = ieq(N, NS1);
        const vf NF = sel(to_f(N), NL, lastm);
        vf c[3], f[3];
        vi ci[3];
        for (int a = 0; a < 3; a++) {
            c[a] = fma3(NF, DP[a], P[a]);
            c[a] = vmax(vmin(c[a], HI[a]), ZERO);
            ci[a] = imin(to_i(c[a]), LAST[a]);
        }
        vi blk = ZEROI;
        int ublk = 0;
        vm comp = act, leap = MNONE;
        if (F->skip) {
            blk = iadd(iadd(srl(ci[0], VSV_RC_BSHIFT), imul(NBX, srl(ci[1], VSV_RC_BSHIFT))),
                       imul(NBXY, srl(ci[2], VSV_RC_BSHIFT)));
            const unsigned b0 = (unsigned)lane0(blk); /* in a register: no store and reload */
            ublk = bits(ieq(blk, iset((int)b0))) == ALL;
            const unsigned d0 = ublk ? F->skip[b0] : 0;
            if (!ublk || d0) { /* else (dense fields): no ray leaps */
                /* the distances, and the blocks shown that have clear cells (VSV_RC_FINE) */
                const vi d = ublk ? iset((int)d0) : bytes(F->skip, blk), dist = iand(d, iset(VSV_RC_FINE - 1));
                const vm empty = mand(act, igt(dist, ZEROI)), fine = mand(act, igt(d, iset(VSV_RC_FINE - 1)));
                leap = empty;
                if (bits(fine)) { /* the clear cells among them (their fine bits) */
                    const vi cell = iadd(iadd(iand(ci[0], B3), sll(iand(ci[1], B3), VSV_RC_BSHIFT)),
                                         sll(iand(ci[2], B3), 2 * VSV_RC_BSHIFT));
                    const vi word = !ublk ? igather(F->fine, iadd(iadd(blk, blk), srl(cell, 5)), fine)
                                          : ikeep(act, isel(iset((int)F->fine[2 * b0]), iset((int)F->fine[2 * b0 + 1]),
                                                            igt(cell, B31)));
                    leap = mor(leap, igt(iand(srlv(word, iand(cell, B31)), ONEI), ZEROI));
                }
                if (bits(leap)) {
                    N = leap_to(F, P, DP, IDP, NS, NL, N, ci, dist, empty, leap);
                    comp = mandnot(leap, act);
                    if (!bits(comp))
                        continue;
                }
            }
        }
        const vi bidx = iadd(iadd(srl(ci[0], sh), imul(BX, srl(ci[1], sh))), imul(BXY, srl(ci[2], sh)));
        unsigned bidx_a[W]; /* indices unsigned: a 32-bit load is its own zero extension */
        istore(bidx_a, bidx);
        /* every lane in one brick? */
        const int uni = bits(ieq(bidx, iset((int)bidx_a[0]))) == ALL;
        for (int a = 0; a < 3; a++)
            f[a] = sub(c[a], to_f(ci[a]));
        const vi off = iadd(iadd(iand(ci[0], M), imul(iand(ci[1], M), EY)), imul(iand(ci[2], M), EZ));
        unsigned off_a[W];
        istore(off_a, off);
        vf sig, col[3];
        classify(F, comp, ublk, blk, uni, bidx_a, off_a, f, &sig, col);
        const vm cm = gt(sig, ZERO); /* only lanes of comp have added anything */
        if (bits(cm))
            composite(F, cm, lastm, sig, col, WL, N, ts, &T, acc, &deep_set, depth);
        N = isel(iadd(N, ONEI), N, leap); /* the leaping rays have moved on */
    }
    fstore(T_out, T);
    for (int ch = 0; ch < 3; ch++)
        fstore(acc_out[ch], acc[ch]);
}
