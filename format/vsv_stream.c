/* vsv_stream.c — the field stream (SPEC.md part 2): the plain framed format
 * the Unix tools pipe between each other. Header with metadata records, then
 * one frame of dense float32 fields per time, then an end marker. */
#include "vsv_format_internal.h"

#include <errno.h>
#include <stdlib.h>

#define VSV_STREAM_MAJOR 1 /* the field stream's own version (SPEC.md §13) */

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "the field stream code assumes a little-endian host (floats are copied as is)"
#endif

struct vsv_stream_reader {
    FILE *fp;
    char name[256];
    vsv_meta meta;
    uint64_t frames, offset;
    int64_t last_time;
    int ended;
    char err[512];
};

struct vsv_stream_writer {
    FILE *fp;
    vsv_meta meta;
    uint64_t frames;
    int64_t last_time;
};

static int rd_exact(vsv_stream_reader *r, void *dst, size_t n, const char *what)
{
    size_t got = fread(dst, 1, n, r->fp);
    r->offset += got;
    if (got == n)
        return 0;
    if (ferror(r->fp)) {
        vsv_msg(r->err, sizeof r->err, "%s: read error in %s at byte %llu: %s", r->name, what,
                (unsigned long long)r->offset, strerror(errno));
        return VSV_EIO;
    }
    vsv_msg(r->err, sizeof r->err, "%s: field stream truncated in %s at byte %llu", r->name, what,
            (unsigned long long)r->offset);
    return VSV_ETRUNC;
}

int vsv_stream_reader_open(FILE *fp, const char *name, vsv_stream_reader **out)
{
    *out = NULL;
    vsv_stream_reader *r = calloc(1, sizeof *r);
    if (!r)
        return VSV_ENOMEM;
    *out = r;
    r->fp = fp;
    snprintf(r->name, sizeof r->name, "%s", name ? name : "(stdin)");
    vsv_meta_init(&r->meta);
    unsigned char h[16];
    int rc = rd_exact(r, h, 16, "header");
    if (rc == VSV_ETRUNC && r->offset < 8) {
        vsv_msg(r->err, sizeof r->err, "%s: not a field stream (empty or too short)", r->name);
        return VSV_ENOTVSV;
    }
    if (rc)
        return rc;
    if (memcmp(h, VSV_STREAM_MAGIC, 8)) {
        vsv_msg(r->err, sizeof r->err, "%s: not a field stream (bad magic at byte 0)", r->name);
        return VSV_ENOTVSV;
    }
    if (vsv_rd16(h + 8) != VSV_STREAM_MAJOR) {
        vsv_msg(r->err, sizeof r->err, "%s: field stream version %u not supported", r->name, vsv_rd16(h + 8));
        return VSV_EVERSION;
    }
    uint32_t n = vsv_rd32(h + 12);
    if (n > (64u << 20) + (uint32_t)VSV_MAX_DIM * VSV_MAX_DIM * 8u) {
        vsv_msg(r->err, sizeof r->err, "%s: field stream header of %u bytes is implausible", r->name, n);
        return VSV_ECORRUPT;
    }
    /* the buffer grows with the bytes that actually arrive: a damaged
     * length in a short stream costs no more memory than the stream holds */
    size_t cap = n < (1u << 20) ? n : (1u << 20), got = 0;
    unsigned char *buf = malloc(cap ? cap : 1);
    if (!buf)
        return VSV_ENOMEM;
    while (got < n) {
        if (got == cap) {
            cap = n - cap < cap ? n : 2 * cap;
            unsigned char *b = realloc(buf, cap);
            if (!b) {
                free(buf);
                return VSV_ENOMEM;
            }
            buf = b;
        }
        if ((rc = rd_exact(r, buf + got, cap - got, "header"))) {
            free(buf);
            return rc;
        }
        got = cap;
    }
    char msg[256];
    rc = vsv_meta_decode(buf, n, &r->meta, NULL, msg, sizeof msg);
    free(buf);
    if (rc) {
        vsv_msg(r->err, sizeof r->err, "%s: field stream header: %s", r->name, msg);
        return rc;
    }
    r->last_time = INT64_MIN;
    return 0;
}

const vsv_meta *vsv_stream_reader_meta(const vsv_stream_reader *r) { return &r->meta; }
const char *vsv_stream_reader_error(const vsv_stream_reader *r) { return r ? r->err : "out of memory"; }

int vsv_stream_reader_next(vsv_stream_reader *r, int64_t *time, float *const *fields)
{
    if (r->ended)
        return 0;
    unsigned char h[16];
    int rc = rd_exact(r, h, 16, "frame header");
    if (rc)
        return rc;
    if (!memcmp(h, "END!", 4)) {
        if (vsv_rd32(h + 4) != 0 || vsv_rd64(h + 8) != r->frames) {
            vsv_msg(r->err, sizeof r->err, "%s: end marker counts %llu frames, stream had %llu", r->name,
                    (unsigned long long)vsv_rd64(h + 8), (unsigned long long)r->frames);
            return VSV_ECORRUPT;
        }
        r->ended = 1;
        /* a stream ends at its marker: bytes after it are a second stream
         * (two commands' output joined) or damage, never dropped unsaid */
        if (getc(r->fp) != EOF) {
            vsv_msg(r->err, sizeof r->err,
                    "%s: bytes after the end marker at byte %llu (two streams joined? one vsv-extract reads "
                    "several files)",
                    r->name, (unsigned long long)r->offset);
            return VSV_ECORRUPT;
        }
        if (ferror(r->fp)) {
            vsv_msg(r->err, sizeof r->err, "%s: read error after the end marker at byte %llu: %s", r->name,
                    (unsigned long long)r->offset, strerror(errno));
            return VSV_EIO;
        }
        return 0;
    }
    if (memcmp(h, "FRAM", 4) || vsv_rd32(h + 4) != 0) {
        vsv_msg(r->err, sizeof r->err, "%s: bad frame marker at byte %llu (frame %llu)", r->name,
                (unsigned long long)(r->offset - 16), (unsigned long long)r->frames);
        return VSV_ECORRUPT;
    }
    int64_t t = (int64_t)vsv_rd64(h + 8);
    if (!VSV_TIME_OK(t)) {
        vsv_msg(r->err, sizeof r->err, "%s: frame %llu: time %lld is outside the years 1..9999", r->name,
                (unsigned long long)r->frames, (long long)t);
        return VSV_ECORRUPT;
    }
    if (r->frames && t <= r->last_time) {
        vsv_msg(r->err, sizeof r->err, "%s: frame %llu time does not increase", r->name, (unsigned long long)r->frames);
        return VSV_ECORRUPT;
    }
    const size_t cells = (size_t)r->meta.nx * (size_t)r->meta.ny * (size_t)r->meta.nz;
    for (int v = 0; v < r->meta.nvars; v++)
        if ((rc = rd_exact(r, fields[v], cells * 4, "frame data")))
            return rc;
    r->last_time = t;
    *time = t;
    r->frames++;
    return 1;
}

void vsv_stream_reader_free(vsv_stream_reader *r)
{
    if (!r)
        return;
    vsv_meta_clear(&r->meta);
    free(r);
}

int vsv_stream_writer_open(FILE *fp, const vsv_meta *meta, vsv_stream_writer **out)
{
    *out = NULL;
    char msg[256];
    if (vsv_meta_validate(meta, msg, sizeof msg))
        return VSV_EINVAL;
    vsv_stream_writer *w = calloc(1, sizeof *w);
    if (!w)
        return VSV_ENOMEM;
    w->fp = fp;
    vsv_meta_init(&w->meta);
    vsv_buf b = {0};
    int rc = vsv_meta_copy(&w->meta, meta);
    if (!rc)
        rc = vsv_buf_put(&b, VSV_STREAM_MAGIC, 8);
    if (!rc)
        rc = vsv_buf_zeros(&b, 8);
    if (!rc)
        rc = vsv_meta_encode(meta, NULL, 0, &b); /* streams keep heights raw (stream 1.x) */
    if (!rc) {
        vsv_wr16(b.p + 8, VSV_STREAM_MAJOR);
        vsv_wr16(b.p + 10, meta->nmoves     ? 2
                           : meta->nheights ? 1
                                            : 0); /* the lowest minor that has what the stream uses */
        vsv_wr32(b.p + 12, (uint32_t)(b.len - 16));
        if (fwrite(b.p, 1, b.len, fp) != b.len)
            rc = VSV_EIO;
    }
    vsv_buf_free(&b);
    if (rc) {
        vsv_stream_writer_free(w);
        return rc;
    }
    *out = w;
    return 0;
}

int vsv_stream_writer_frame(vsv_stream_writer *w, int64_t time, const float *const *fields)
{
    if ((w->frames && time <= w->last_time) || !VSV_TIME_OK(time))
        return VSV_EINVAL;
    unsigned char h[16];
    memcpy(h, "FRAM", 4);
    vsv_wr32(h + 4, 0);
    vsv_wr64(h + 8, (uint64_t)time);
    if (fwrite(h, 1, 16, w->fp) != 16)
        return VSV_EIO;
    const size_t cells = (size_t)w->meta.nx * (size_t)w->meta.ny * (size_t)w->meta.nz;
    for (int v = 0; v < w->meta.nvars; v++)
        if (fwrite(fields[v], 4, cells, w->fp) != cells)
            return VSV_EIO;
    w->frames++;
    w->last_time = time;
    return 0;
}

int vsv_stream_writer_end(vsv_stream_writer *w)
{
    unsigned char h[16];
    memcpy(h, "END!", 4);
    vsv_wr32(h + 4, 0);
    vsv_wr64(h + 8, w->frames);
    if (fwrite(h, 1, 16, w->fp) != 16 || fflush(w->fp))
        return VSV_EIO;
    return 0;
}

void vsv_stream_writer_free(vsv_stream_writer *w)
{
    if (!w)
        return;
    vsv_meta_clear(&w->meta);
    free(w);
}
