/* vsv_derive.h — the derived variables of a run (vsv_run_add_derived):
 * their specs compiled against a source's fields, the inputs they read and
 * their evaluation per frame. Private to convert/. */
#ifndef VSV_DERIVE_H
#define VSV_DERIVE_H

#include "vsv_convert.h"

typedef struct vsv_derive vsv_derive;

/* An empty set; caller frees with vsv_derive_free. NULL when out of memory. */
vsv_derive *vsv_derive_create(void);
void vsv_derive_free(vsv_derive *d);

/* Adds the variable of spec (NAME=EXPR[:UNITS] or a built-in's name) over
 * the fields of s; its name must be none of s's fields nor of m's
 * variables. 0, or VSV_EINVAL / VSV_ENOTFOUND / VSV_ENOMEM with the reason
 * in msg (caller buffer of cap bytes). */
int vsv_derive_add(vsv_derive *d, const vsv_source *s, const vsv_meta *m, const char *spec, char *msg, size_t cap);
int vsv_derive_count(const vsv_derive *d);
/* Variable i's name, units and description (borrowed until free). */
const vsv_var *vsv_derive_var(const vsv_derive *d, int i);
/* Variable i's whole formula and where its inputs come from (borrowed). */
const char *vsv_derive_formula(const vsv_derive *d, int i);
/* The first input the set reads that s lacks, or NULL (borrowed). */
const char *vsv_derive_missing(const vsv_derive *d, const vsv_source *s);
/* Reads the inputs of time t of s and computes every variable into out[i]
 * (caller buffers of the grid's nx*ny*nz floats). 0 or the read's error
 * with s's message in msg. */
int vsv_derive_frame(vsv_derive *d, vsv_source *s, int t, float *const *out, char *msg, size_t cap);

#endif
