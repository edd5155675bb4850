/* vsv_mm5.h — MM5 version 3 files (TERRAIN, REGRID, INTERPF, MM5 output):
 * the record index of one file and its big header, and the writer of the
 * same layout the tests and samples/ use. Layout facts: INPUT-FORMATS.md §1.
 * Private to convert/ and the tests. */
#ifndef VSV_MM5_H
#define VSV_MM5_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#define VSV_MM5_BIGHDR 117600
#define VSV_MM5_SUBHDR 152

/* One field of one output time: plain info. */
typedef struct vsv_mm5_field {
    char name[10]; /* trailing blanks removed; may contain spaces */
    char units[26];
    char desc[47];
    char order[5]; /* "YXS", "YX", "CA", ... */
    char stag[5];  /* "D", "C", "H" or "" */
    char date[25]; /* "YYYY-MM-DD_HH:MM:SS.0000" */
    int ndim, start[4], end[4];
    float xtime;     /* minutes since the model start */
    uint64_t offset; /* file offset of the data payload */
    uint64_t bytes;  /* payload bytes */
    int record;      /* 1-based record number of the data record */
    int period;      /* 0-based output time */
    int bighdr;      /* which big header was in force */
} vsv_mm5_field;

typedef struct vsv_mm5 vsv_mm5;

/* Maps and indexes `path`. Errors name the record number and byte offset.
 * Caller frees with vsv_mm5_free; on error *out may hold a handle whose
 * error says why (free it too). */
int vsv_mm5_open(const char *path, vsv_mm5 **out);
/* The same over a caller buffer that outlives the handle (fuzzing). */
int vsv_mm5_open_mem(const void *data, size_t n, const char *name, vsv_mm5 **out);
/* 1 if these bytes begin like an MM5 v3 file (either byte order). */
int vsv_mm5_probe(const unsigned char *head, size_t n);
void vsv_mm5_free(vsv_mm5 *m);
const char *vsv_mm5_error(const vsv_mm5 *m);
int vsv_mm5_little_endian(const vsv_mm5 *m);

/* Big header entries, 1-based as in MM5's own docs; of the first big header
 * (nbig = how many the file holds). -999 for unused entries. */
int vsv_mm5_bhi(const vsv_mm5 *m, int i, int j);
float vsv_mm5_bhr(const vsv_mm5 *m, int i, int j);
/* The 80-character description of bhi(i,j), blanks trimmed, into buf. */
void vsv_mm5_bhic(const vsv_mm5 *m, int i, int j, char *buf, size_t cap);
int vsv_mm5_nbighdr(const vsv_mm5 *m);

int vsv_mm5_nfields(const vsv_mm5 *m);
const vsv_mm5_field *vsv_mm5_field_at(const vsv_mm5 *m, int i);
int vsv_mm5_nperiods(const vsv_mm5 *m);
/* Index of field `name` in period p, or -1. */
int vsv_mm5_find(const vsv_mm5 *m, int period, const char *name);
/* Number of boundary-slab records (YSB XSB YWB XWB; indexed like any
 * field, never volumes). */
int vsv_mm5_skipped(const vsv_mm5 *m);
/* Reads a field's values as native floats in file order (caller buffer of
 * field->bytes/4 floats). 0, or VSV_ETRUNC when the file shrank while it
 * was read (the values are then not the file's; the caller says so, with
 * VSV_CUT_TEXT). */
int vsv_mm5_read(const vsv_mm5 *m, const vsv_mm5_field *f, float *out);

/* Seconds since 1970 of an MM5 date "YYYY-MM-DD_HH:MM:SS" in *t: 0; 1 for
 * the all-zero date of set-up files (no time); -1 for anything else. */
int vsv_mm5_date(const char *date, int64_t *t);

/* -------------------------------------------------------------- writer */

/* Writes MM5 v3 records (big-endian, or little-endian when le) to fp. */
typedef struct vsv_mm5_writer {
    FILE *fp;
    int le;
} vsv_mm5_writer;

int vsv_mm5_write_flag(vsv_mm5_writer *w, int flag);
int vsv_mm5_write_bighdr(vsv_mm5_writer *w, const unsigned char *hdr117600);
/* Sub-header from f (its ndim/start/end/names), then the data record. */
int vsv_mm5_write_field(vsv_mm5_writer *w, const vsv_mm5_field *f, const float *values);
/* A copy of the first big header (117600 bytes, file byte order: big-endian). */
const unsigned char *vsv_mm5_bighdr_bytes(const vsv_mm5 *m);

#endif
