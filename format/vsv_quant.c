/* vsv_quant.c — quantisation per species (SPEC.md): the plan from a data
 * range, codes from values and values from codes. */
#include "vsv_format_internal.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static unsigned code_max(int bits) { return bits == 8 ? 255u : 65535u; }

void vsv_quant_plan(vsv_quant *q, const vsv_pack_var *opt, double dmin, double dmax, double minpos, int missing)
{
    memset(q, 0, sizeof *q);
    q->bits = opt->bits == 8 ? 8 : 16;
    q->scale = opt->scale == VSV_SCALE_LOG ? VSV_SCALE_LOG : VSV_SCALE_LINEAR;
    q->data_min = dmin;
    q->data_max = dmax;
    const double M = code_max(q->bits);
    const int fixed = opt->lo < opt->hi;
    double err;
    if (q->scale == VSV_SCALE_LINEAR) {
        const int none = !(dmin <= dmax); /* no finite value: every cell is no data */
        q->lo = fixed ? opt->lo : (!none ? dmin : 1);
        /* round-off below zero in a non-negative field (WRF's hydrometeors
         * carry -1e-14 and the like): keep 0 as the floor so zeros stay empty */
        if (!fixed && dmin < 0 && dmax > 0 && -dmin < 1e-6 * dmax)
            q->lo = 0;
        q->hi = fixed ? opt->hi : (!none ? dmax : 2);
        q->threshold = isnan(opt->threshold) ? -INFINITY : opt->threshold;
        /* no-data cells of a field whose smallest value is 0 (a concentration)
         * share code 0 with the zeros where the grid tells them apart (below
         * the ground): both mean "nothing here"; elsewhere code 0 is no data */
        q->missing = missing == 2 || (missing != 0 && (q->lo != 0 || none));
        const double step = (q->hi - q->lo) / (q->missing ? M - 1 : M);
        err = step / 2;
        if (q->threshold > q->lo && dmin < q->threshold && !q->missing)
            err = fmax(err, q->threshold - q->lo);
        if (dmin < q->lo)
            err = fmax(err, q->lo - dmin);
    } else {
        double dec = opt->log_decades > 0 ? opt->log_decades : (q->bits == 8 ? 3 : 6);
        q->hi = fixed ? opt->hi : (dmax > 0 ? dmax : 1);
        q->lo = fixed ? opt->lo : fmax(minpos > 0 ? minpos : q->hi, q->hi * pow(10, -dec));
        if (!(q->lo > 0))
            q->lo = q->hi > 0 ? q->hi * pow(10, -dec) : 1e-30;
        if (!(q->hi >= q->lo))
            q->hi = q->lo;
        q->threshold = isnan(opt->threshold) ? q->lo : fmax(opt->threshold, q->lo);
        const double d = (log(q->hi) - log(q->lo)) / (M - 1);
        err = q->hi * (exp(d / 2) - 1);
        if (dmin < q->threshold)
            err = fmax(err, q->threshold);
        if (dmin < 0)
            err = fmax(err, -dmin);
    }
    if (dmax > q->hi)
        err = fmax(err, dmax - q->hi);
    /* float32 rounding of the decoded value */
    err += fmax(fabs(q->lo), fabs(q->hi)) * ldexp(1.0, -23);
    q->max_abs_error = err;
}

/* The encode rule of SPEC.md §6 over a row, with its constants hoisted:
 * the writer's hot loop. Returns codes and their min/max. */
void vsv_quant_row(const vsv_quant *q, const float *src, size_t n, uint16_t *dst, unsigned *mn, unsigned *mx)
{
    const double M = code_max(q->bits);
    const double thr = q->threshold;
    unsigned lo = *mn, hi = *mx;
    if (q->scale == VSV_SCALE_LINEAR) {
        const unsigned first = q->missing ? 1 : 0;
        const int flat = !(q->hi > q->lo);
        const double base = q->lo, inv = flat ? 0 : (M - first) / (q->hi - q->lo), top = M;
        for (size_t i = 0; i < n; i++) {
            const float v = src[i];
            unsigned c;
            if (!(fabsf(v) <= FLT_MAX) || !(v >= thr)) {
                c = 0;
            } else if (flat) {
                c = first;
            } else {
                double x = first + floor((v - base) * inv + 0.5);
                c = x < first ? first : x > top ? (unsigned)top : (unsigned)x;
            }
            dst[i] = (uint16_t)c;
            lo = c < lo ? c : lo;
            hi = c > hi ? c : hi;
        }
    } else {
        const int flat = !(q->hi > q->lo);
        const double lnlo = log(q->lo), inv = flat ? 0 : (M - 1) / (log(q->hi) - lnlo);
        for (size_t i = 0; i < n; i++) {
            const float v = src[i];
            unsigned c;
            if (!(fabsf(v) <= FLT_MAX) || !(v >= thr) || !(v > 0)) {
                c = 0;
            } else if (flat) {
                c = 1;
            } else {
                double x = 1 + floor((log(v) - lnlo) * inv + 0.5);
                c = x < 1 ? 1 : x > M ? (unsigned)M : (unsigned)x;
            }
            dst[i] = (uint16_t)c;
            lo = c < lo ? c : lo;
            hi = c > hi ? c : hi;
        }
    }
    *mn = lo;
    *mx = hi;
}

unsigned vsv_quant_code(const vsv_quant *q, float v)
{
    uint16_t c;
    unsigned mn = 0xffff, mx = 0;
    vsv_quant_row(q, &v, 1, &c, &mn, &mx);
    return c;
}

/* The decode rule of SPEC.md §6, shared by single values and tables so both
 * give bit-identical floats. */
static inline float quant_value(const vsv_quant *q, double step_or_d, double lnlo, unsigned code)
{
    if (q->scale == VSV_SCALE_LINEAR) {
        if (q->missing)
            return code ? (float)(q->lo + (code - 1) * step_or_d) : NAN;
        return (float)(q->lo + code * step_or_d);
    }
    if (code == 0)
        return 0.0f;
    return (float)exp(lnlo + (code - 1) * step_or_d);
}

static double quant_step(const vsv_quant *q)
{
    const double M = code_max(q->bits);
    if (q->scale == VSV_SCALE_LINEAR)
        return (q->hi - q->lo) / (q->missing ? M - 1 : M);
    return (log(q->hi) - log(q->lo)) / (M - 1);
}

float vsv_quant_value(const vsv_quant *q, unsigned code)
{
    return quant_value(q, quant_step(q), q->scale == VSV_SCALE_LOG ? log(q->lo) : 0, code);
}

void vsv_quant_table(const vsv_quant *q, float *out)
{
    const double step = quant_step(q), lnlo = q->scale == VSV_SCALE_LOG ? log(q->lo) : 0;
    const unsigned n = code_max(q->bits) + 1;
    for (unsigned c = 0; c < n; c++)
        out[c] = quant_value(q, step, lnlo, c);
}
