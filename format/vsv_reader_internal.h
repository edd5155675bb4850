/* vsv_reader_internal.h — the reader's handles and what its files share:
 * opening and chunk indexes (vsv_reader.c), decoding (vsv_decoder.c), the
 * full check (vsv_check.c) and decoded volumes (vsv_volume.c). Private to
 * format/. */
#ifndef VSV_READER_INTERNAL_H
#define VSV_READER_INTERNAL_H

#include "vsv_format_internal.h"
#include "vsv_layout.h"

#include <pthread.h>
#include <zstd.h>

struct vsv_file {
    const unsigned char *data;
    size_t size;
    vsv_mapped map; /* a local file's mapping, or a byte source's guard alone */
    char name[256];
    char err[512];
    vsv_meta meta;
    vsv_quant *quant;
    vsv_layout lay;
    int nsteps, keyframe, codec;
    int major, minor;   /* major 2: the 3-D brick kinds may appear, 4: the Rice-coded ones */
    unsigned char *toc; /* a copy of the table of contents, checked at open:
                         * never read from the mapping again (a file cut
                         * meanwhile would read zeros: every chunk at 0) */
    uint64_t meta_end, toc_off;
    signed char *chunk_ok; /* per step: 0 unchecked, 1 index verified */
    float **lut;           /* per species: 2^bits values, built on first use */
    pthread_mutex_t lock;
    int counted, damaged;
    uint64_t stored, rice, nonempty, payload;
    uint64_t uid;         /* unique in the process: brick keys (vsv_file_brick_key) */
    vsv_byte_source *src; /* NULL: a mapped local file, every byte resident */
    uint64_t *span_end;   /* with src: per (step, species), where its payloads end */
};

struct vsv_decoder {
    vsv_file *f;
    ZSTD_DCtx *dctx;
    unsigned char *raw;
    uint16_t *codes;
    uint16_t *scratch;   /* a brick: DELTA3's differences */
    unsigned char *rice; /* format 4: a Rice-coded payload's padded copy */
    uint16_t *zres;      /* and its residuals, a value a cell */
    uint16_t **state;    /* per species: codes of all bricks at state_step */
    int *state_step;
    uint16_t **under; /* per placement (GRID's, then each MOVE's), per column: how
                         many levels lie below the ground (NULL: none) */
    char err[512];
};

/* The last brick kind a file of f's major may hold. */
static inline int vsv_file_last_kind(const vsv_file *f)
{
    return f->major >= 4 ? VSV_BRICK_DELTA3R : f->major >= 2 ? VSV_BRICK_DELTA3 : VSV_BRICK_DELTA;
}

/* Makes bytes [off, off + n) of f resident (a byte source; nothing to do for
 * a mapped file), fetching up to `ahead` more if that is cheap; 0 or a VSV_E*
 * code with msg set. */
static inline int vsv_file_need(vsv_file *f, uint64_t off, uint64_t n, uint64_t ahead, char *msg, size_t cap)
{
    return f->src ? f->src->need(f->src, off, n, ahead, msg, cap) : 0;
}
/* A byte source's fresh copy of a range whose checksum failed: 1 if one was
 * fetched (check again), else 0. */
static inline int vsv_file_refetch(vsv_file *f, uint64_t off, uint64_t n)
{
    char why[256];
    return f->src && f->src->refetch && !f->src->refetch(f->src, off, n, why, sizeof why);
}

/* Sets f->err to "name: message" and returns rc. */
int vsv_file_fail(vsv_file *f, int rc, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
/* 1 if the n bytes at p are all zero, else 0 with the first non-zero at *first. */
int vsv_all_zero(const unsigned char *p, size_t n, size_t *first);
/* Verified index of chunk t (header included), or NULL with f->err / msg set. */
const unsigned char *vsv_file_chunk_index(vsv_file *f, int t, char *msg, size_t cap);
/* The code for this thread's last failed vsv_file_chunk_index: VSV_ETRUNC
 * (the mapping was cut; msg says so), a byte source's code, else
 * VSV_ECORRUPT. */
int vsv_file_chunk_rc(const vsv_file *f, char *msg, size_t cap);
/* The entry of brick b of species s in chunk index c. */
const unsigned char *vsv_file_brick_entry(const vsv_file *f, const unsigned char *c, int s, int b);
/* VSV_ERANGE with msg set when (step, s, b) is outside the file. */
int vsv_file_check_args(vsv_file *f, int step, int s, int b, char *msg, size_t cap);
/* What rc becomes when f's file may have shrunk while it was read: with
 * msg set to "name: truncated while reading ...", VSV_ETRUNC when the guard
 * saw an access past its end (whatever rc), or when rc is an error and the
 * file is shorter now (a system call, on failure paths only); else rc. */
int vsv_file_cut(const vsv_file *f, int rc, char *msg, size_t cap);
/* vsv_file_cut, looking at the file's size (a system call) when look is set
 * whatever rc is: after reading an EMPTY brick entry, which is all zeros, as
 * the rest of a page past a new end of the file reads without a signal. */
int vsv_file_cut_look(const vsv_file *f, int rc, int look, char *msg, size_t cap);
/* Applies the brick entry be of chunk c (step t) to codes. */
int vsv_decoder_apply(vsv_decoder *d, const unsigned char *c, int t, int s, int b, const unsigned char *be,
                      uint16_t *codes);

#endif
