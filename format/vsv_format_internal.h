/* vsv_format_internal.h — byte helpers, on-disk constants and the metadata
 * record codec shared by the .vsv file and the field stream. Private. */
#ifndef VSV_FORMAT_INTERNAL_H
#define VSV_FORMAT_INTERNAL_H

#include "vsv_format.h"

#include <stdarg.h>
#include <string.h>

/* Little-endian memcpy helpers: never cast structs onto bytes. */
static inline uint16_t vsv_rd16(const unsigned char *p) { return (uint16_t)(p[0] | (p[1] << 8)); }
static inline uint32_t vsv_rd32(const unsigned char *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}
static inline uint64_t vsv_rd64(const unsigned char *p)
{
    return (uint64_t)vsv_rd32(p) | ((uint64_t)vsv_rd32(p + 4) << 32);
}
static inline double vsv_rdf64(const unsigned char *p)
{
    uint64_t u = vsv_rd64(p);
    double d;
    memcpy(&d, &u, 8);
    return d;
}
static inline float vsv_rdf32(const unsigned char *p)
{
    uint32_t u = vsv_rd32(p);
    float f;
    memcpy(&f, &u, 4);
    return f;
}
static inline void vsv_wr16(unsigned char *p, uint16_t v) { p[0] = (unsigned char)v; p[1] = (unsigned char)(v >> 8); }
static inline void vsv_wr32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)v; p[1] = (unsigned char)(v >> 8);
    p[2] = (unsigned char)(v >> 16); p[3] = (unsigned char)(v >> 24);
}
static inline void vsv_wr64(unsigned char *p, uint64_t v) { vsv_wr32(p, (uint32_t)v); vsv_wr32(p + 4, (uint32_t)(v >> 32)); }
static inline void vsv_wrf64(unsigned char *p, double d)
{
    uint64_t u;
    memcpy(&u, &d, 8);
    vsv_wr64(p, u);
}
static inline void vsv_wrf32(unsigned char *p, float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    vsv_wr32(p, u);
}

/* On-disk layout constants (SPEC.md). */
#define VSV_MAGIC "\x89VSV\r\n\x1a\n"
#define VSV_STREAM_MAGIC "\x89VSF\r\n\x1a\n"
#define VSV_END_MAGIC "\x89VSVEND\n"
#define VSV_HEADER_SIZE 128
#define VSV_TRAILER_SIZE 32
#define VSV_CHUNK_HEADER_SIZE 32
#define VSV_BRICK_ENTRY_SIZE 24
#define VSV_TOC_ENTRY_SIZE 24
#define VSV_ALIGN 64
#define VSV_MAX_DIM 16384
#define VSV_MAX_CELLS ((uint64_t)1 << 34)
#define VSV_MAX_VARS 1024
#define VSV_MAX_STEPS 10000000
#define VSV_MAX_STRING 4096
#define VSV_MAX_META ((uint64_t)1 << 32)

static inline uint64_t vsv_align_up(uint64_t v, uint64_t a) { return (v + a - 1) / a * a; }

/* A growable byte buffer. */
typedef struct vsv_buf {
    unsigned char *p;
    size_t len, cap;
} vsv_buf;

int vsv_buf_reserve(vsv_buf *b, size_t extra);
int vsv_buf_put(vsv_buf *b, const void *data, size_t n);
int vsv_buf_zeros(vsv_buf *b, size_t n);
int vsv_buf_u32(vsv_buf *b, uint32_t v);
int vsv_buf_u64(vsv_buf *b, uint64_t v);
int vsv_buf_f64(vsv_buf *b, double v);
int vsv_buf_str(vsv_buf *b, const char *s);
void vsv_buf_free(vsv_buf *b);

/* Metadata records. `with_quant` adds QUAN records (the .vsv, not the stream). */
int vsv_meta_encode(const vsv_meta *m, const vsv_quant *quant, vsv_buf *out);
/* The HGTS records (vsv_heights.c): free, deep copy, one record's payload. */
void vsv_heights_clear_all(vsv_meta *m);
int vsv_heights_copy_all(vsv_meta *dst, const vsv_meta *src);
int vsv_heights_encode(const vsv_meta *m, const vsv_heights *h, vsv_buf *b);
int vsv_heights_decode(vsv_meta *m, const unsigned char *p, size_t len, char *msg, size_t cap);
/* Parses records from [p, p+n). quant (nvars entries, may be NULL) is filled
 * from QUAN records; *nquant counts them. msg receives a reason on error. */
int vsv_meta_decode(const unsigned char *p, size_t n, vsv_meta *m, vsv_quant **quant,
                    char *msg, size_t cap);

/* printf into a fixed message buffer. */
void vsv_msg(char *buf, size_t cap, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
/* "path: " followed by the formatted message: the shape of every error a
 * reader keeps for its file. */
void vsv_vmsg_path(char *buf, size_t cap, const char *path, const char *fmt, va_list ap)
    __attribute__((format(printf, 4, 0)));

/* Quantisation shared by writer and reader (SPEC.md "Quantisation"). */
unsigned vsv_quant_code(const vsv_quant *q, float v);
/* The same over n values; widens [*mn, *mx] to the codes' extremes. */
void vsv_quant_row(const vsv_quant *q, const float *src, size_t n, uint16_t *dst, unsigned *mn, unsigned *mx);
/* All 2^bits decoded values, bit-identical to vsv_quant_value. */
void vsv_quant_table(const vsv_quant *q, float *out);
/* Fills q from per-species options and the observed finite range. */
/* missing: the data had non-finite (no-data) values. */
void vsv_quant_plan(vsv_quant *q, const vsv_pack_var *opt, double dmin, double dmax, double minpos, int missing);

/* Checks packing options against a grid; fills err (cap bytes) on error. */
int vsv_pack_opts_check(const vsv_pack_opts *o, const vsv_meta *meta, char *err, size_t cap);

/* Brick payload transform (SPEC.md §7) of the ext[0] x ext[1] x ext[2] cells
 * inside the grid of a B^3 brick array of `bits`-bit codes. */
size_t vsv_brick_raw_bytes(int bits, const int ext[3]);
void vsv_brick_forward(int bits, int kind, const uint16_t *cur, const uint16_t *prev, int B, const int ext[3],
                       unsigned char *out);
/* Inverse in place: ABS overwrites the cells inside the grid, DELTA adds to them. */
void vsv_brick_inverse(int bits, int kind, const unsigned char *in, int B, const int ext[3], uint16_t *state);

#endif
