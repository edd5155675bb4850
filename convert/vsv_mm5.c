/* vsv_mm5.c — indexes an MM5 v3 file: Fortran sequential records
 * [u32 n][n bytes][u32 n] (big-endian, or little-endian when the first
 * marker says so), the flag grammar  file := (flag0 bighdr)? period*,
 * period := (flag1 subhdr data)* flag2, with a big header accepted anywhere.
 * Every length is checked against the file before use. */
#include "vsv_mm5.h"
#include "vsv_f77.h"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

struct vsv_mm5 {
    const unsigned char *d;
    size_t n;
    vsv_mapped map; /* a file's mapping (open), or none (open_mem) */
    int le;
    char path[1024];
    char err[512];
    unsigned char big[VSV_MM5_BIGHDR]; /* first big header, normalised to big-endian */
    int nbig;
    vsv_mm5_field *f;
    int nf, cap;
    int nperiods;
    int skipped;
};

static uint32_t u32(const vsv_mm5 *m, const unsigned char *p) { return vsv_f77_u32(m->le, p); }
static uint32_t be32(const unsigned char *p) { return vsv_f77_u32(0, p); }

const char *vsv_mm5_error(const vsv_mm5 *m) { return m ? m->err : "out of memory"; }
int vsv_mm5_little_endian(const vsv_mm5 *m) { return m->le; }
int vsv_mm5_nbighdr(const vsv_mm5 *m) { return m->nbig; }
int vsv_mm5_nfields(const vsv_mm5 *m) { return m->nf; }
const vsv_mm5_field *vsv_mm5_field_at(const vsv_mm5 *m, int i) { return &m->f[i]; }
int vsv_mm5_nperiods(const vsv_mm5 *m) { return m->nperiods; }
int vsv_mm5_skipped(const vsv_mm5 *m) { return m->skipped; }
const unsigned char *vsv_mm5_bighdr_bytes(const vsv_mm5 *m) { return m->big; }

int vsv_mm5_bhi(const vsv_mm5 *m, int i, int j)
{
    if (i < 1 || i > 50 || j < 1 || j > 20)
        return -999;
    return (int32_t)be32(m->big + 4 * ((j - 1) * 50 + (i - 1)));
}

float vsv_mm5_bhr(const vsv_mm5 *m, int i, int j)
{
    if (i < 1 || i > 20 || j < 1 || j > 20)
        return -999;
    uint32_t u = be32(m->big + 4000 + 4 * ((j - 1) * 20 + (i - 1)));
    float f;
    memcpy(&f, &u, 4);
    return f;
}

static void trimmed(char *dst, size_t cap, const unsigned char *src, size_t n)
{
    while (n && (src[n - 1] == ' ' || src[n - 1] == 0))
        n--;
    if (n >= cap)
        n = cap - 1;
    for (size_t i = 0; i < n; i++)
        dst[i] = src[i] >= 32 && src[i] < 127 ? (char)src[i] : '?';
    dst[n] = 0;
}

void vsv_mm5_bhic(const vsv_mm5 *m, int i, int j, char *buf, size_t cap)
{
    if (i < 1 || i > 50 || j < 1 || j > 20) {
        buf[0] = 0;
        return;
    }
    trimmed(buf, cap, m->big + 5600 + 80 * ((j - 1) * 50 + (i - 1)), 80);
}

int vsv_mm5_probe(const unsigned char *h, size_t n)
{
    static const unsigned char be[16] = {0, 0, 0, 4, 0, 0, 0, 0, 0, 0, 0, 4, 0, 1, 0xCB, 0x60};
    static const unsigned char le[16] = {4, 0, 0, 0, 0, 0, 0, 0, 4, 0, 0, 0, 0x60, 0xCB, 1, 0};
    if (n < 16)
        return 0;
    if (!memcmp(h, be, 16) || !memcmp(h, le, 16))
        return 1;
    /* a file may also start directly with a period (flag 1, sub-header) */
    static const unsigned char be1[12] = {0, 0, 0, 4, 0, 0, 0, 1, 0, 0, 0, 4};
    static const unsigned char le1[12] = {4, 0, 0, 0, 1, 0, 0, 0, 4, 0, 0, 0};
    return !memcmp(h, be1, 12) || !memcmp(h, le1, 12);
}

int vsv_mm5_date(const char *date, int64_t *t)
{
    int y, mo, d, h, mi, s;
    if (sscanf(date, "%4d-%2d-%2d_%2d:%2d:%2d", &y, &mo, &d, &h, &mi, &s) != 6)
        return -1;
    if (y == 0 && mo == 0 && d == 0)
        return 1; /* "0000-00-00_00:00:00": no date (TERRAIN and other set-up files) */
    static const int mdays[12] = {31, 29, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
    const int leap = y % 4 == 0 && (y % 100 != 0 || y % 400 == 0);
    if (y < 1 || mo < 1 || mo > 12 || d < 1 || d > mdays[mo - 1] || (mo == 2 && d == 29 && !leap) || h < 0 || h > 23 ||
        mi < 0 || mi > 59 || s < 0 || s > 60)
        return -1;
    *t = vsv_time_from_civil(y, mo, d, h, mi, s);
    return 0;
}

static int fail(vsv_mm5 *m, int rc, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static int fail(vsv_mm5 *m, int rc, const char *fmt, ...)
{
    if (vsv_input_cut(&m->map, 1)) { /* zeros read past a new end: not the file's damage */
        vsv_msg(m->err, sizeof m->err, "%s: %s", m->path, VSV_CUT_TEXT);
        return VSV_ETRUNC;
    }
    va_list ap;
    va_start(ap, fmt);
    vsv_vmsg_path(m->err, sizeof m->err, m->path, fmt, ap);
    va_end(ap);
    return rc;
}

/* The record at *at; advances *at. Errors name the record and offset. */
static int record(vsv_mm5 *m, size_t *at, int recno, const unsigned char **payload, uint32_t *len)
{
    char msg[300];
    const int rc = vsv_f77_record(m->d, m->n, m->le, at, recno, payload, len, msg, sizeof msg);
    return rc ? fail(m, rc, "%s", msg) : 0;
}

static int add_field(vsv_mm5 *m, const vsv_mm5_field *f)
{
    if (m->nf == m->cap) {
        int cap = m->cap ? 2 * m->cap : 256;
        vsv_mm5_field *nf = realloc(m->f, (size_t)cap * sizeof *nf);
        if (!nf)
            return VSV_ENOMEM;
        m->f = nf;
        m->cap = cap;
    }
    m->f[m->nf++] = *f;
    return 0;
}

static int is_slab(const char *order)
{
    return !strcmp(order, "YSB") || !strcmp(order, "XSB") || !strcmp(order, "YWB") || !strcmp(order, "XWB");
}

static int index_file(vsv_mm5 *m)
{
    size_t at = 0;
    int recno = 0, period = 0, in_period = 0;
    const unsigned char *p;
    uint32_t len;
    int rc;
    while (at < m->n) {
        recno++;
        const size_t flag_at = at;
        if ((rc = record(m, &at, recno, &p, &len)))
            return rc;
        if (len != 4)
            return fail(m, VSV_ECORRUPT, "record %d at byte offset %zu: expected a 4-byte flag record, found %u bytes",
                        recno, flag_at, len);
        const int32_t flag = (int32_t)u32(m, p);
        if (flag == 0) {
            recno++;
            const size_t h_at = at;
            if ((rc = record(m, &at, recno, &p, &len)))
                return rc;
            if (len != VSV_MM5_BIGHDR)
                return fail(m, VSV_ECORRUPT, "record %d at byte offset %zu: big header has %u bytes, expected %d",
                            recno, h_at, len, VSV_MM5_BIGHDR);
            if (m->nbig == 0) {
                /* normalise the numeric part to big-endian */
                memcpy(m->big, p, VSV_MM5_BIGHDR);
                if (m->le)
                    for (int w = 0; w < 5600 / 4; w++) {
                        unsigned char *q = m->big + 4 * w;
                        unsigned char t0 = q[0], t1 = q[1];
                        q[0] = q[3];
                        q[1] = q[2];
                        q[2] = t1;
                        q[3] = t0;
                    }
            } else if (u32(m, p + 4036) != be32(m->big + 4036) || u32(m, p + 4040) != be32(m->big + 4040))
                /* bhr(10,1), bhr(11,1): where the nest lies in the coarse domain */
                return fail(m, VSV_EUNSUPPORTED,
                            "record %d at byte offset %zu: a big header that moves the nest (a moving MM5 nest: "
                            "its placement in time is not read, so it is refused)",
                            recno, h_at);
            m->nbig++;
        } else if (flag == 1) {
            recno++;
            const size_t s_at = at;
            if ((rc = record(m, &at, recno, &p, &len)))
                return rc;
            if (len != VSV_MM5_SUBHDR)
                return fail(m, VSV_ECORRUPT, "record %d at byte offset %zu: sub-header has %u bytes, expected %d",
                            recno, s_at, len, VSV_MM5_SUBHDR);
            vsv_mm5_field f;
            memset(&f, 0, sizeof f);
            f.ndim = (int)u32(m, p);
            uint64_t count = 1;
            for (int d = 0; d < 4; d++) {
                f.start[d] = (int32_t)u32(m, p + 4 + 4 * d);
                f.end[d] = (int32_t)u32(m, p + 20 + 4 * d);
                const int64_t ext = (int64_t)f.end[d] - f.start[d] + 1;
                if (ext < 1 || ext > 100000)
                    return fail(m, VSV_ECORRUPT, "record %d at byte offset %zu: dimension %d extent %lld out of range",
                                recno, s_at, d + 1, (long long)ext);
                count *= (uint64_t)ext;
            }
            uint32_t xt = u32(m, p + 36);
            memcpy(&f.xtime, &xt, 4);
            trimmed(f.stag, sizeof f.stag, p + 40, 4);
            trimmed(f.order, sizeof f.order, p + 44, 4);
            trimmed(f.date, sizeof f.date, p + 48, 24);
            trimmed(f.name, sizeof f.name, p + 72, 9);
            trimmed(f.units, sizeof f.units, p + 81, 25);
            trimmed(f.desc, sizeof f.desc, p + 106, 46);
            if (f.ndim < 1 || f.ndim > 4)
                return fail(m, VSV_ECORRUPT, "record %d at byte offset %zu: field %s has %d dimensions", recno, s_at,
                            f.name, f.ndim);
            recno++;
            const size_t d_at = at;
            if ((rc = record(m, &at, recno, &p, &len)))
                return rc;
            if ((uint64_t)len != count * 4)
                return fail(m, VSV_ECORRUPT,
                            "record %d at byte offset %zu: field %s has %u bytes of data, its sub-header implies %llu",
                            recno, d_at, f.name, len, (unsigned long long)(count * 4));
            f.offset = (uint64_t)(p - m->d);
            f.bytes = len;
            f.record = recno;
            f.period = period;
            f.bighdr = m->nbig;
            if (is_slab(f.order))
                m->skipped++; /* listed, never a volume */
            if ((rc = add_field(m, &f)))
                return rc;
            in_period = 1;
        } else if (flag == 2) {
            if (in_period)
                period++;
            in_period = 0;
        } else {
            return fail(m, VSV_ECORRUPT, "record %d at byte offset %zu: unknown flag %d (expected 0, 1 or 2)", recno,
                        flag_at, flag);
        }
    }
    if (in_period)
        period++; /* a last period without its end flag: keep it */
    m->nperiods = period;
    if (!m->nbig)
        return fail(m, VSV_ECORRUPT, "no big header (flag 0 record) in the file");
    return 0;
}

int vsv_mm5_open(const char *path, vsv_mm5 **out)
{
    vsv_mm5 *m = *out = calloc(1, sizeof *m);
    if (!m)
        return VSV_ENOMEM;
    snprintf(m->path, sizeof m->path, "%s", path);
    char why[160];
    const int rc = vsv_input_map(path, 16, &m->map, why, sizeof why);
    m->d = m->map.data;
    m->n = m->map.n;
    if (rc < 0)
        return fail(m, VSV_EIO, "%s", why);
    if (rc > 0)
        return fail(m, VSV_ENOTVSV, "not an MM5 v3 file (%zu bytes)", m->n);
    if (!vsv_mm5_probe(m->d, m->n))
        return fail(m, VSV_ENOTVSV, "not an MM5 v3 file (no flag record and big header at byte 0)");
    m->le = m->d[0] == 4;
    const int irc = index_file(m);
    return irc || !vsv_input_cut(&m->map, 1) ? irc : fail(m, VSV_ETRUNC, VSV_CUT_TEXT);
}

int vsv_mm5_open_mem(const void *data, size_t n, const char *name, vsv_mm5 **out)
{
    vsv_mm5 *m = *out = calloc(1, sizeof *m);
    if (!m)
        return VSV_ENOMEM;
    snprintf(m->path, sizeof m->path, "%s", name);
    m->map = (vsv_mapped){NULL, 0, -1, -1};
    m->d = data;
    m->n = n;
    if (!vsv_mm5_probe(m->d, m->n))
        return fail(m, VSV_ENOTVSV, "not an MM5 v3 file (no flag record and big header at byte 0)");
    m->le = m->d[0] == 4;
    return index_file(m);
}

void vsv_mm5_free(vsv_mm5 *m)
{
    if (!m)
        return;
    vsv_input_unmap(&m->map);
    free(m->f);
    free(m);
}

int vsv_mm5_find(const vsv_mm5 *m, int period, const char *name)
{
    for (int i = 0; i < m->nf; i++)
        if (m->f[i].period == period && !strcmp(m->f[i].name, name))
            return i;
    return -1;
}

int vsv_mm5_read(const vsv_mm5 *m, const vsv_mm5_field *f, float *out)
{
    const unsigned char *p = m->d + f->offset;
    const size_t n = f->bytes / 4;
    for (size_t i = 0; i < n; i++) {
        uint32_t u = u32(m, p + 4 * i);
        memcpy(&out[i], &u, 4);
    }
    /* the values are the file's only if it did not shrink meanwhile */
    return vsv_input_cut(&m->map, 1) ? VSV_ETRUNC : 0;
}

/* ------------------------------------------------------------------ writer */

static int put32(vsv_mm5_writer *w, uint32_t v)
{
    unsigned char b[4];
    if (w->le)
        vsv_wr32(b, v);
    else
        b[0] = (unsigned char)(v >> 24), b[1] = (unsigned char)(v >> 16), b[2] = (unsigned char)(v >> 8),
        b[3] = (unsigned char)v;
    return fwrite(b, 1, 4, w->fp) == 4 ? 0 : VSV_EIO;
}

static int put_record(vsv_mm5_writer *w, const unsigned char *p, uint32_t n)
{
    if (put32(w, n) || fwrite(p, 1, n, w->fp) != n || put32(w, n))
        return VSV_EIO;
    return 0;
}

int vsv_mm5_write_flag(vsv_mm5_writer *w, int flag)
{
    return put32(w, 4) || put32(w, (uint32_t)flag) || put32(w, 4) ? VSV_EIO : 0;
}

int vsv_mm5_write_bighdr(vsv_mm5_writer *w, const unsigned char *hdr)
{
    unsigned char *b = malloc(VSV_MM5_BIGHDR);
    if (!b)
        return VSV_ENOMEM;
    memcpy(b, hdr, VSV_MM5_BIGHDR);
    if (w->le)
        for (int i = 0; i < 5600 / 4; i++)
            vsv_wr32(b + 4 * i, be32(hdr + 4 * i));
    int rc = put_record(w, b, VSV_MM5_BIGHDR);
    free(b);
    return rc;
}

static void pad(unsigned char *dst, const char *s, size_t n)
{
    memset(dst, ' ', n);
    memcpy(dst, s, strlen(s) < n ? strlen(s) : n);
}

int vsv_mm5_write_field(vsv_mm5_writer *w, const vsv_mm5_field *f, const float *values)
{
    unsigned char h[VSV_MM5_SUBHDR];
    uint32_t words[10];
    words[0] = (uint32_t)f->ndim;
    for (int d = 0; d < 4; d++) {
        words[1 + d] = (uint32_t)f->start[d];
        words[5 + d] = (uint32_t)f->end[d];
    }
    memcpy(&words[9], &f->xtime, 4);
    for (int i = 0; i < 10; i++) {
        if (w->le)
            vsv_wr32(h + 4 * i, words[i]);
        else
            h[4 * i] = (unsigned char)(words[i] >> 24), h[4 * i + 1] = (unsigned char)(words[i] >> 16),
                  h[4 * i + 2] = (unsigned char)(words[i] >> 8), h[4 * i + 3] = (unsigned char)words[i];
    }
    pad(h + 40, f->stag, 4);
    pad(h + 44, f->order, 4);
    pad(h + 48, f->date, 24);
    pad(h + 72, f->name, 9);
    pad(h + 81, f->units, 25);
    pad(h + 106, f->desc, 46);
    uint64_t count = 1;
    for (int d = 0; d < 4; d++)
        count *= (uint64_t)(f->end[d] - f->start[d] + 1);
    if (vsv_mm5_write_flag(w, 1) || put_record(w, h, VSV_MM5_SUBHDR) || put32(w, (uint32_t)(count * 4)))
        return VSV_EIO;
    for (uint64_t i = 0; i < count; i++) {
        uint32_t u;
        memcpy(&u, &values[i], 4);
        if (put32(w, u))
            return VSV_EIO;
    }
    return put32(w, (uint32_t)(count * 4));
}
