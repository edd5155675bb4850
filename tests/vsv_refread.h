/* vsv_refread.h — a deliberately simple reference reader of .vsv files,
 * written from format/SPEC.md alone (it shares no code with format/), used
 * by the tests to cross-check the fast reader. Slow on purpose: it decodes
 * every step from 0 in order. */
#ifndef VSV_REFREAD_H
#define VSV_REFREAD_H

#include <stddef.h>
#include <stdint.h>

typedef struct ref_species {
    char name[64];
    unsigned bits, scale, missing;
    double lo, hi, threshold, max_abs_error;
} ref_species;

typedef struct ref_file {
    const unsigned char *d;
    size_t n;
    unsigned nx, ny, nz, brick, keyframe, codec, nsteps, nspecies;
    unsigned major; /* 1; 2: brick kinds 4 and 5 allowed; 4: 6 and 7 too */
    ref_species *sp;
    uint64_t toc;
} ref_file;

/* 0 on success; else -1 with a reason in err. data must outlive rf. */
int ref_open(ref_file *rf, const unsigned char *data, size_t n, char *err, size_t cap);
/* Codes (nx*ny*nz) and values of species s at step t; 0 or -1. */
int ref_decode(const ref_file *rf, unsigned t, unsigned s, uint16_t *codes, float *values, char *err, size_t cap);
int64_t ref_time(const ref_file *rf, unsigned t);
void ref_close(ref_file *rf);
uint32_t ref_crc32c(const unsigned char *p, size_t n);

#endif
