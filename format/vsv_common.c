/* vsv_common.c — pieces every part of the format library shares: error
 * texts, the byte buffer, CRC-32C, civil time, metadata ownership and the
 * quantisation and brick-transform rules of SPEC.md. */
#include "vsv_format_internal.h"

#include <float.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <strings.h>
#include <unistd.h>

const char *vsv_strerror(int code)
{
    switch (code) {
    case VSV_OK: return "success";
    case VSV_EIO: return "I/O error";
    case VSV_ENOMEM: return "out of memory";
    case VSV_ENOTVSV: return "not a .vsv file";
    case VSV_EVERSION: return "unsupported format version";
    case VSV_ECORRUPT: return "corrupt data";
    case VSV_ETRUNC: return "truncated";
    case VSV_EINVAL: return "invalid argument";
    case VSV_ERANGE: return "index out of range";
    case VSV_ECODEC: return "payload does not decode";
    case VSV_ENOTFOUND: return "not found";
    case VSV_EUNSUPPORTED: return "not supported";
    case VSV_EAGAIN: return "not ready yet";
    default: return "unknown error";
    }
}

void vsv_msg(char *buf, size_t cap, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, cap, fmt, ap);
    va_end(ap);
}

void vsv_vmsg_path(char *buf, size_t cap, const char *path, const char *fmt, va_list ap)
{
    char m[512];
    vsnprintf(m, sizeof m, fmt, ap);
    snprintf(buf, cap, "%s: %s", path, m);
}

int vsv_ncpus(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : (int)n;
}

/* ------------------------------------------------------------------ buffer */

int vsv_buf_reserve(vsv_buf *b, size_t extra)
{
    if (b->len + extra <= b->cap)
        return 0;
    size_t cap = b->cap ? b->cap : 4096;
    while (cap < b->len + extra)
        cap *= 2;
    unsigned char *p = realloc(b->p, cap);
    if (!p)
        return VSV_ENOMEM;
    b->p = p;
    b->cap = cap;
    return 0;
}

int vsv_buf_put(vsv_buf *b, const void *data, size_t n)
{
    if (vsv_buf_reserve(b, n))
        return VSV_ENOMEM;
    if (n)
        memcpy(b->p + b->len, data, n);
    b->len += n;
    return 0;
}

int vsv_buf_zeros(vsv_buf *b, size_t n)
{
    if (vsv_buf_reserve(b, n))
        return VSV_ENOMEM;
    memset(b->p + b->len, 0, n);
    b->len += n;
    return 0;
}

int vsv_buf_u32(vsv_buf *b, uint32_t v)
{
    unsigned char t[4];
    vsv_wr32(t, v);
    return vsv_buf_put(b, t, 4);
}

int vsv_buf_u64(vsv_buf *b, uint64_t v)
{
    unsigned char t[8];
    vsv_wr64(t, v);
    return vsv_buf_put(b, t, 8);
}

int vsv_buf_f64(vsv_buf *b, double v)
{
    unsigned char t[8];
    vsv_wrf64(t, v);
    return vsv_buf_put(b, t, 8);
}

int vsv_buf_str(vsv_buf *b, const char *s)
{
    size_t n = strlen(s);
    if (vsv_buf_u32(b, (uint32_t)n))
        return VSV_ENOMEM;
    return vsv_buf_put(b, s, n);
}

void vsv_buf_free(vsv_buf *b)
{
    free(b->p);
    b->p = NULL;
    b->len = b->cap = 0;
}

/* ---------------------------------------------------------------- CRC-32C */

/* Slicing-by-8 tables, built once; the SSE4.2 instruction when the CPU has
 * it (the same polynomial, so both give identical values). */
static uint32_t crc_table[8][256];
static int crc_have_hw;

static void crc_init(void)
{
    for (unsigned i = 0; i < 256; i++) {
        uint32_t c = i;
        for (int k = 0; k < 8; k++)
            c = (c >> 1) ^ (0x82F63B78u & (0u - (c & 1)));
        crc_table[0][i] = c;
    }
    for (unsigned i = 0; i < 256; i++)
        for (int t = 1; t < 8; t++)
            crc_table[t][i] = (crc_table[t - 1][i] >> 8) ^ crc_table[0][crc_table[t - 1][i] & 0xff];
#if defined(__x86_64__)
    __builtin_cpu_init();
    crc_have_hw = __builtin_cpu_supports("sse4.2") ? 1 : 0;
#else
    crc_have_hw = 0;
#endif
}

#if defined(__x86_64__)
__attribute__((target("sse4.2"))) static uint32_t crc_hw(uint32_t c, const unsigned char *p, size_t n)
{
    uint64_t c64 = c;
    while (n >= 8) {
        uint64_t w;
        memcpy(&w, p, 8);
        c64 = __builtin_ia32_crc32di(c64, w);
        p += 8;
        n -= 8;
    }
    c = (uint32_t)c64;
    while (n--)
        c = __builtin_ia32_crc32qi(c, *p++);
    return c;
}
#endif

uint32_t vsv_crc32c(uint32_t crc, const void *buf, size_t len)
{
    static pthread_once_t once = PTHREAD_ONCE_INIT;
    pthread_once(&once, crc_init);
    const unsigned char *p = buf;
    uint32_t c = ~crc;
#if defined(__x86_64__)
    if (crc_have_hw)
        return ~crc_hw(c, p, len);
#endif
    while (len >= 8) {
        uint32_t lo = vsv_rd32(p) ^ c, hi = vsv_rd32(p + 4);
        c = crc_table[7][lo & 0xff] ^ crc_table[6][(lo >> 8) & 0xff] ^ crc_table[5][(lo >> 16) & 0xff] ^
            crc_table[4][lo >> 24] ^ crc_table[3][hi & 0xff] ^ crc_table[2][(hi >> 8) & 0xff] ^
            crc_table[1][(hi >> 16) & 0xff] ^ crc_table[0][hi >> 24];
        p += 8;
        len -= 8;
    }
    while (len--)
        c = (c >> 8) ^ crc_table[0][(c ^ *p++) & 0xff];
    return ~c;
}

/* ------------------------------------------------------------------- time */

int64_t vsv_time_from_civil(int y, int m, int d, int hh, int mm, int ss)
{
    /* Days from civil (H. Hinnant's algorithm), exact for any Gregorian date. */
    y -= m <= 2;
    const int64_t era = (y >= 0 ? y : y - 399) / 400;
    const int64_t yoe = y - era * 400;
    const int64_t doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
    const int64_t doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    const int64_t days = era * 146097 + doe - 719468;
    return days * 86400 + hh * 3600 + mm * 60 + ss;
}

void vsv_time_format(int64_t t, char *buf, size_t cap)
{
    int64_t days = t >= 0 ? t / 86400 : -((-t + 86399) / 86400);
    int64_t sec = t - days * 86400;
    int64_t z = days + 719468;
    const int64_t era = (z >= 0 ? z : z - 146096) / 146097;
    const int64_t doe = z - era * 146097;
    const int64_t yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
    int64_t y = yoe + era * 400;
    const int64_t doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    const int64_t mp = (5 * doy + 2) / 153;
    const int64_t d = doy - (153 * mp + 2) / 5 + 1;
    const int64_t m = mp + (mp < 10 ? 3 : -9);
    y += m <= 2;
    snprintf(buf, cap, "%04lld-%02lld-%02lldT%02lld:%02lld:%02lldZ", (long long)y, (long long)m,
             (long long)d, (long long)(sec / 3600), (long long)(sec / 60 % 60), (long long)(sec % 60));
}

int vsv_time_parse(const char *s, int64_t *t)
{
    int y, mo, d, h = 0, mi = 0, se = 0, n = 0;
    if (sscanf(s, "%d-%d-%d%n", &y, &mo, &d, &n) != 3)
        return VSV_EINVAL;
    const char *p = s + n;
    if (*p == 'T' || *p == ' ' || *p == '_') {
        int k = 0;
        if (sscanf(p + 1, "%d%n", &h, &k) != 1)
            return VSV_EINVAL;
        p += 1 + k;
        if (*p == ':') {
            if (sscanf(p + 1, "%d%n", &mi, &k) != 1)
                return VSV_EINVAL;
            p += 1 + k;
            if (*p == ':') {
                if (sscanf(p + 1, "%d%n", &se, &k) != 1)
                    return VSV_EINVAL;
                p += 1 + k;
            }
        }
    }
    if (*p == 'Z')
        p++;
    if (*p || mo < 1 || mo > 12 || d < 1 || d > 31 || h < 0 || h > 24 || mi < 0 || mi > 59 || se < 0 ||
        se > 60)
        return VSV_EINVAL;
    *t = vsv_time_from_civil(y, mo, d, h, mi, se);
    return 0;
}

/* --------------------------------------------------------------- metadata */

void vsv_meta_init(vsv_meta *m)
{
    memset(m, 0, sizeof *m);
    m->spacing[0] = m->spacing[1] = m->spacing[2] = 1;
    m->proj.kind = VSV_PROJ_NONE;
}

void vsv_meta_clear(vsv_meta *m)
{
    if (!m)
        return;
    free(m->levels);
    free(m->attr_keys);
    free(m->attr_values);
    if (m->tf)
        for (int i = 0; i < m->nvars; i++)
            free(m->tf[i]);
    free(m->tf);
    free(m->vars);
    free(m->terrain);
    free(m->landuse);
    vsv_heights_clear_all(m);
    vsv_meta_init(m);
}

static int dup_array(void **dst, const void *src, size_t bytes)
{
    *dst = NULL;
    if (!src)
        return 0;
    *dst = malloc(bytes ? bytes : 1);
    if (!*dst)
        return VSV_ENOMEM;
    memcpy(*dst, src, bytes);
    return 0;
}

int vsv_meta_copy(vsv_meta *dst, const vsv_meta *src)
{
    vsv_meta_clear(dst);
    *dst = *src;
    dst->levels = NULL;
    dst->attr_keys = NULL;
    dst->attr_values = NULL;
    dst->vars = NULL;
    dst->tf = NULL;
    dst->terrain = dst->landuse = NULL;
    dst->heights = NULL;
    dst->nheights = 0;
    size_t plane = (size_t)src->nx * (size_t)src->ny * sizeof(float);
    if (dup_array((void **)&dst->levels, src->levels, (size_t)src->nz * sizeof(double)) ||
        dup_array((void **)&dst->attr_keys, src->attr_keys, (size_t)src->nattrs * 64) ||
        dup_array((void **)&dst->attr_values, src->attr_values, (size_t)src->nattrs * 256) ||
        dup_array((void **)&dst->vars, src->vars, (size_t)src->nvars * sizeof(vsv_var)) ||
        dup_array((void **)&dst->terrain, src->terrain, plane) ||
        dup_array((void **)&dst->landuse, src->landuse, plane) || vsv_heights_copy_all(dst, src))
        goto fail;
    if (src->tf) {
        dst->tf = calloc((size_t)src->nvars + 1, sizeof(char *));
        if (!dst->tf)
            goto fail;
        for (int i = 0; i < src->nvars; i++)
            if (src->tf[i] && !(dst->tf[i] = strdup(src->tf[i])))
                goto fail;
    }
    return 0;
fail:
    vsv_meta_clear(dst);
    return VSV_ENOMEM;
}

static void copy_str(char *dst, size_t cap, const char *src)
{
    snprintf(dst, cap, "%s", src ? src : "");
}

int vsv_meta_add_var(vsv_meta *m, const char *name, const char *units, const char *desc)
{
    if (m->nvars >= VSV_MAX_VARS)
        return VSV_EINVAL;
    vsv_var *v = realloc(m->vars, ((size_t)m->nvars + 1) * sizeof *v);
    if (!v)
        return VSV_ENOMEM;
    m->vars = v;
    if (m->tf) {
        char **tf = realloc(m->tf, ((size_t)m->nvars + 2) * sizeof *tf);
        if (!tf)
            return VSV_ENOMEM;
        m->tf = tf;
        m->tf[m->nvars] = NULL;
    }
    vsv_var *nv = &m->vars[m->nvars];
    memset(nv, 0, sizeof *nv);
    copy_str(nv->name, sizeof nv->name, name);
    copy_str(nv->units, sizeof nv->units, units);
    copy_str(nv->description, sizeof nv->description, desc);
    return m->nvars++;
}

int vsv_meta_add_attr(vsv_meta *m, const char *key, const char *value)
{
    char(*k)[64] = realloc(m->attr_keys, ((size_t)m->nattrs + 1) * 64);
    if (!k)
        return VSV_ENOMEM;
    m->attr_keys = k;
    char(*v)[256] = realloc(m->attr_values, ((size_t)m->nattrs + 1) * 256);
    if (!v)
        return VSV_ENOMEM;
    m->attr_values = v;
    memset(k[m->nattrs], 0, 64);
    memset(v[m->nattrs], 0, 256);
    copy_str(k[m->nattrs], 64, key);
    copy_str(v[m->nattrs], 256, value);
    m->nattrs++;
    return 0;
}

const char *vsv_meta_attr(const vsv_meta *m, const char *key)
{
    for (int i = 0; i < m->nattrs; i++)
        if (!strcmp(m->attr_keys[i], key))
            return m->attr_values[i];
    return NULL;
}

int vsv_meta_alloc_levels(vsv_meta *m)
{
    free(m->levels);
    m->levels = calloc((size_t)m->nz ? (size_t)m->nz : 1, sizeof(double));
    return m->levels ? 0 : VSV_ENOMEM;
}

int vsv_meta_alloc_terrain(vsv_meta *m)
{
    free(m->terrain);
    m->terrain = calloc((size_t)m->nx * (size_t)m->ny + 1, sizeof(float));
    return m->terrain ? 0 : VSV_ENOMEM;
}

int vsv_meta_alloc_landuse(vsv_meta *m)
{
    free(m->landuse);
    m->landuse = calloc((size_t)m->nx * (size_t)m->ny + 1, sizeof(float));
    return m->landuse ? 0 : VSV_ENOMEM;
}

int vsv_meta_find_var(const vsv_meta *m, const char *name)
{
    for (int i = 0; i < m->nvars; i++)
        if (!strcmp(m->vars[i].name, name))
            return i;
    return VSV_ENOTFOUND;
}

int vsv_meta_validate(const vsv_meta *m, char *msg, size_t cap)
{
    if (m->nx < 1 || m->ny < 1 || m->nz < 1 || m->nx > VSV_MAX_DIM || m->ny > VSV_MAX_DIM ||
        m->nz > VSV_MAX_DIM) {
        vsv_msg(msg, cap, "grid %dx%dx%d outside 1..%d", m->nx, m->ny, m->nz, VSV_MAX_DIM);
        return VSV_EINVAL;
    }
    if ((uint64_t)m->nx * (uint64_t)m->ny * (uint64_t)m->nz > VSV_MAX_CELLS) {
        vsv_msg(msg, cap, "grid has too many cells");
        return VSV_EINVAL;
    }
    if (m->nvars < 1 || m->nvars > VSV_MAX_VARS) {
        vsv_msg(msg, cap, "%d variables (need 1..%d)", m->nvars, VSV_MAX_VARS);
        return VSV_EINVAL;
    }
    for (int i = 0; i < 3; i++)
        if (!isfinite(m->origin[i]) || !isfinite(m->spacing[i]) || !(m->spacing[i] > 0)) {
            vsv_msg(msg, cap, "origin/spacing along axis %d is not finite and positive", i);
            return VSV_EINVAL;
        }
    if (m->vert_kind < 0 || m->vert_kind > VSV_VERT_COORD) {
        vsv_msg(msg, cap, "unknown vertical kind %d", m->vert_kind);
        return VSV_EINVAL;
    }
    if (m->vert_kind != VSV_VERT_EVEN && m->vert_kind != VSV_VERT_INDEX && !m->levels) {
        vsv_msg(msg, cap, "vertical kind %d needs levels", m->vert_kind);
        return VSV_EINVAL;
    }
    if (m->proj.kind < 0 || m->proj.kind >= VSV_PROJ_COUNT) {
        vsv_msg(msg, cap, "unknown projection %d", m->proj.kind);
        return VSV_EINVAL;
    }
    for (int i = 0; i < m->nvars; i++) {
        if (!m->vars[i].name[0]) {
            vsv_msg(msg, cap, "variable %d has no name", i);
            return VSV_EINVAL;
        }
        for (int j = 0; j < i; j++)
            if (!strcmp(m->vars[i].name, m->vars[j].name)) {
                vsv_msg(msg, cap, "variable name %s appears twice", m->vars[i].name);
                return VSV_EINVAL;
            }
    }
    return 0;
}

/* ------------------------------------------------------------ quantisation */

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
        q->lo = fixed ? opt->lo : (dmin <= dmax ? dmin : 0);
        /* round-off below zero in a non-negative field (WRF's hydrometeors
         * carry -1e-14 and the like): keep 0 as the floor so zeros stay empty */
        if (!fixed && dmin < 0 && dmax > 0 && -dmin < 1e-6 * dmax)
            q->lo = 0;
        q->hi = fixed ? opt->hi : (dmin <= dmax ? dmax : 0);
        q->threshold = isnan(opt->threshold) ? -INFINITY : opt->threshold;
        /* no-data cells of a field whose smallest value is 0 (a concentration)
         * share code 0 with the zeros: both mean "nothing here" */
        q->missing = missing != 0 && q->lo != 0;
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

/* ---------------------------------------------------------- brick payload */

size_t vsv_brick_raw_bytes(int bits, const int ext[3])
{
    const size_t n = (size_t)ext[0] * ext[1] * ext[2];
    return bits == 8 ? n : 2 * n;
}

/* Residuals of the brick's cells inside the grid (ext[0] x ext[1] x ext[2] of
 * the B^3 array), in storage order: ABS predicts each code from the previous
 * one, DELTA from the same cell one step earlier; both in wrapping bits-wide
 * arithmetic, then zigzag, then (16 bit) all low bytes before all high bytes
 * so the mostly-zero high bytes compress to almost nothing. (A 3-D Lorenzo
 * predictor was measured on the real series in ../shared/data: within ±3 %
 * of this size, and slower to decode.) */
void vsv_brick_forward(int bits, int kind, const uint16_t *cur, const uint16_t *prev, int B, const int ext[3],
                       unsigned char *out)
{
    const size_t n = (size_t)ext[0] * ext[1] * ext[2];
    const unsigned mask = bits == 8 ? 0xffu : 0xffffu, sh = (unsigned)bits - 1;
    unsigned last = 0;
    size_t m = 0;
    for (int k = 0; k < ext[2]; k++)
        for (int j = 0; j < ext[1]; j++) {
            const size_t row = ((size_t)k * B + j) * B;
            for (int i = 0; i < ext[0]; i++, m++) {
                const unsigned c = cur[row + i];
                const unsigned p = kind == VSV_BRICK_DELTA ? prev[row + i] : last;
                const unsigned r = (c - p) & mask;
                const unsigned z = ((r << 1) ^ (0u - (r >> sh))) & mask;
                out[m] = (unsigned char)z;
                if (bits == 16)
                    out[n + m] = (unsigned char)(z >> 8);
                last = c;
            }
        }
}

void vsv_brick_inverse(int bits, int kind, const unsigned char *in, int B, const int ext[3], uint16_t *state)
{
    const size_t n = (size_t)ext[0] * ext[1] * ext[2];
    const unsigned char *lo = in, *hi = in + n;
    if (kind == VSV_BRICK_DELTA) {
        for (int k = 0; k < ext[2]; k++)
            for (int j = 0; j < ext[1]; j++) {
                uint16_t *row = state + ((size_t)k * B + j) * B;
                if (bits == 8) {
                    for (int i = 0; i < ext[0]; i++) {
                        const unsigned z = lo[i];
                        row[i] = (uint16_t)((row[i] + ((z >> 1) ^ (0u - (z & 1)))) & 0xffu);
                    }
                } else {
                    for (int i = 0; i < ext[0]; i++) {
                        const uint16_t z = (uint16_t)(lo[i] | (hi[i] << 8));
                        row[i] = (uint16_t)(row[i] + (uint16_t)((z >> 1) ^ (uint16_t)(0u - (z & 1))));
                    }
                    hi += ext[0];
                }
                lo += ext[0];
            }
        return;
    }
    unsigned acc = 0;
    const unsigned mask = bits == 8 ? 0xffu : 0xffffu;
    for (int k = 0; k < ext[2]; k++)
        for (int j = 0; j < ext[1]; j++) {
            uint16_t *row = state + ((size_t)k * B + j) * B;
            for (int i = 0; i < ext[0]; i++) {
                const unsigned z = bits == 8 ? lo[i] : (unsigned)(lo[i] | (hi[i] << 8));
                acc = (acc + ((z >> 1) ^ (0u - (z & 1)))) & mask;
                row[i] = (uint16_t)acc;
            }
            lo += ext[0];
            if (bits == 16)
                hi += ext[0];
        }
}

/* ------------------------------------------------------ transfer functions */

static int name_is(const char *name, const char *const *list)
{
    for (; *list; list++)
        if (!strcasecmp(name, *list) || (strlen(*list) > 2 && !strncasecmp(name, *list, strlen(*list))))
            return 1;
    return 0;
}

void vsv_tf_default(const char *name, const vsv_quant *q, char *buf, size_t cap)
{
    static const char *const cloud[] = {"CLW", "QCLOUD", "QC", "CLOUD", NULL};
    static const char *const rain[] = {"RNW", "QRAIN", "QR", "RAIN", NULL};
    static const char *const ice[] = {"ICE", "QICE", "QI", "GRAUPEL", "QGRAUP", "QG", "NCI", NULL};
    static const char *const snow[] = {"SNOW", "QSNOW", "QS", NULL};
    static const char *const ozone[] = {"O3", "OZONE", NULL};
    static const char *const nox[] = {"NO", "NO2", "NOX", "NOY", NULL};
    static const char *const pm[] = {"PM25", "PM2.5", "PM10", "PM", "PSO4", "PNO3", "PNH4", "POA", "PEC", "SOA", "ASO4",
                                     "ANO3", "ANH4", "AEC", "AORG", NULL};
    static const char *const smoke[] = {"SMOKE", "BC", "OC", "CO", NULL};
    static const char *const vapour[] = {"Q", "QVAPOR", "QV", "H2O", NULL};
    const char *map = "viridis", *kind = "other", *opacity = "0 0.05 0.2 0.45 0.8";
    if (name_is(name, cloud))
        map = "clouds", kind = "cloud";
    else if (name_is(name, rain))
        map = "rain", kind = "rain";
    else if (name_is(name, ice))
        map = "ice", kind = "ice";
    else if (name_is(name, snow))
        map = "snow", kind = "snow";
    else if (name_is(name, ozone))
        map = "viridis", kind = "ozone";
    else if (name_is(name, nox))
        map = "magma", kind = "nox";
    else if (name_is(name, pm))
        map = "cividis", kind = "pm";
    else if (name_is(name, smoke))
        map = "greys", kind = "smoke";
    else if (name_is(name, vapour)) /* everywhere in the air: a faint veil */
        map = "cividis", kind = "vapour", opacity = "0 0.005 0.01 0.02 0.04";
    /* values at the floor are transparent; opacity rises with concentration */
    snprintf(buf, cap, "kind %s\ncolormap %s\nrange %.9g %.9g\nscale %s\nopacity %s\n", kind, map, q->lo,
             q->hi > q->lo ? q->hi : q->lo + 1, q->scale == VSV_SCALE_LOG ? "log" : "linear", opacity);
}
