/* vsv_format_internal.h — on-disk constants, the metadata record codec,
 * quantisation and the brick transform shared by the .vsv file and the field
 * stream. Private to format/ and stream/ (the core library). */
#ifndef VSV_FORMAT_INTERNAL_H
#define VSV_FORMAT_INTERNAL_H

#include "vsv_common.h"
#include "vsv_format.h"

#include <string.h>

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

static inline uint64_t vsv_align_up(uint64_t v, uint64_t a) { return (v + a - 1) / a * a; }

/* Metadata records. quant (a .vsv, not the stream) adds QUAN records;
 * coded writes stored heights as HGTS form 2 (format 3, vsv_fcode.c). */
int vsv_meta_encode(const vsv_meta *m, const vsv_quant *quant, int coded, vsv_buf *out);
/* Lossless float coding (vsv_fcode.c): n values, each as its bits minus
 * those stride places before, byte planes, one zstd frame appended to b. */
int vsv_floats_code(const float *v, size_t n, size_t stride, vsv_buf *b);
/* Decodes that frame (exactly len bytes) into out[n]; VSV_ECORRUPT unless
 * it is one frame of exactly n values. */
int vsv_floats_decode(const unsigned char *p, size_t len, size_t n, size_t stride, float *out);
/* A plane of nx*ny floats (TERZ, LUSZ, a coded MOVE's terrain) coded and
 * decoded the same way, each value against the one before it in x. */
int vsv_plane_code(const float *v, size_t n, vsv_buf *b);
int vsv_plane_decode(const unsigned char *p, size_t len, size_t n, float *out);
/* The on-disk form of stored heights coded by vsv_floats_code. */
enum { VSV_HEIGHTS_CODED = 2 };
/* The HGTS records (vsv_heights.c): free, deep copy, one record's payload. */
void vsv_heights_clear_all(vsv_meta *m);
int vsv_heights_copy_all(vsv_meta *dst, const vsv_meta *src);
int vsv_heights_encode(const vsv_meta *m, const vsv_heights *h, int coded, vsv_buf *b);
int vsv_heights_decode(vsv_meta *m, const unsigned char *p, size_t len, char *msg, size_t cap);
/* The MOVE records (vsv_moves.c): the same four. */
void vsv_moves_clear_all(vsv_meta *m);
int vsv_moves_copy_all(vsv_meta *dst, const vsv_meta *src);
int vsv_moves_encode(const vsv_meta *m, const vsv_move *v, int coded, vsv_buf *b);
int vsv_moves_decode(vsv_meta *m, const unsigned char *p, size_t len, char *msg, size_t cap);
/* Parses records from [p, p+n). quant (nvars entries, may be NULL) is filled
 * from QUAN records; *nquant counts them. msg receives a reason on error. */
int vsv_meta_decode(const unsigned char *p, size_t n, vsv_meta *m, vsv_quant **quant, char *msg, size_t cap);

/* Quantisation shared by writer and reader (SPEC.md "Quantisation"). */
unsigned vsv_quant_code(const vsv_quant *q, float v);
/* The same over n values; widens [*mn, *mx] to the codes' extremes. */
void vsv_quant_row(const vsv_quant *q, const float *src, size_t n, uint16_t *dst, unsigned *mn, unsigned *mx);
/* All 2^bits decoded values, bit-identical to vsv_quant_value. */
void vsv_quant_table(const vsv_quant *q, float *out);
/* Fills q from per-species options and the observed finite range.
 * missing: 0, the data had no non-finite (no-data) values; 1, it had, and
 * the grid says where they may be (even heights over a terrain: cells
 * below the ground read as no data whatever their code); 2, it had, and
 * the codes alone must say so. */
void vsv_quant_plan(vsv_quant *q, const vsv_pack_var *opt, double dmin, double dmax, double minpos, int missing);

/* Fractional level *kf of height h in column (i, j) of m at `time`
 * (vsv_meta_cell_height_at): piecewise linear between the levels' centres,
 * half a level beyond the first and last; range the column's extent (lowest
 * and highest face). 0, or VSV_ERANGE when h lies outside it (vsv_query.c;
 * the trajectories use it too). */
int vsv_meta_level_of(const vsv_meta *m, int64_t time, int i, int j, double h, double *kf, double range[2]);

/* Checks packing options against a grid; fills err (cap bytes) on error. */
int vsv_pack_opts_check(const vsv_pack_opts *o, const vsv_meta *meta, char *err, size_t cap);

/* Brick payload transform (SPEC.md §7) of the ext[0] x ext[1] x ext[2] cells
 * inside the grid of a B^3 brick array of `bits`-bit codes. */
size_t vsv_brick_raw_bytes(int bits, const int ext[3]);
/* A function built twice, for the named target and the default, the one
 * the CPU can run picked at load. Not under ThreadSanitizer: the ifunc
 * resolver runs while the dynamic linker relocates the program, before
 * libtsan is set up, and GCC instruments it (every program crashed at load). */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_THREAD__)
#define VSV_CLONES(target) __attribute__((target_clones(target, "default")))
#else
#define VSV_CLONES(target)
#endif

/* Kinds with a payload. */
static inline int vsv_brick_stored(int kind) { return kind >= VSV_BRICK_ABS && kind <= VSV_BRICK_DELTA3R; }
/* The predictor of a kind: ABS3R and DELTA3R code ABS3's and DELTA3's residuals. */
static inline int vsv_brick_predictor(int kind) { return kind >= VSV_BRICK_ABS3R ? kind - 2 : kind; }
void vsv_brick_forward(int bits, int kind, const uint16_t *cur, const uint16_t *prev, int B, const int ext[3],
                       unsigned char *out);
/* Inverse in place: ABS and ABS3 overwrite the cells inside the grid, DELTA
 * and DELTA3 add to them (DELTA3 through scratch, a B^3 array); with undo
 * set, DELTA and DELTA3 subtract instead (the state of the step before:
 * the residuals wrap modulo 2^bits, so the step is exactly undone). */
void vsv_brick_inverse(int bits, int kind, const unsigned char *in, int B, const int ext[3], uint16_t *state,
                       uint16_t *scratch, int undo);
/* The same for ABS3 and DELTA3 from residuals a value a cell (z, as
 * vsv_rice_decode gives them) rather than planes. */
void vsv_brick_inverse_z(int bits, int kind, const uint16_t *z, int B, const int ext[3], uint16_t *state,
                         uint16_t *scratch, int undo);

/* The Rice-coded kinds' payload (SPEC.md §7 "Rice coding") of the residual
 * planes of vsv_brick_forward (n cells, lo then hi bytes for 16 bits):
 * encode returns its size, or 0 when it would not fit in cap bytes; decode
 * gives the residuals a value a cell (z, n of them), 0 or -1 when the
 * payload breaks a rule of §7. Encode works in the caller's scratch (3n
 * bytes, aligned as malloc's: the residuals a value a cell, then every
 * cell's context). Decode reads up to VSV_RICE_PAD bytes past the payload
 * (the caller's copy, padded); a valid payload is at most vsv_rice_max
 * bytes. */
enum { VSV_RICE_CONTEXTS = 20, VSV_RICE_STREAMS = 4, VSV_RICE_PAD = 256 };
static inline size_t vsv_rice_max(int bits, size_t n)
{
    return VSV_RICE_CONTEXTS + 4 * (VSV_RICE_STREAMS - 1) + n * (8 + (size_t)bits) / 8 + VSV_RICE_STREAMS;
}
size_t vsv_rice_encode(int bits, const int ext[3], const unsigned char *planes, void *scratch, unsigned char *out,
                       size_t cap);
int vsv_rice_decode(int bits, const int ext[3], const unsigned char *in, size_t size, uint16_t *z);

#endif
