/* fuzz_source.h — what the fuzz targets of file-based model readers share:
 * a private scratch folder for the input (the netCDF and GrADS libraries
 * read files by name), and a bounded read of everything a source offers. */
#ifndef FUZZ_SOURCE_H
#define FUZZ_SOURCE_H

#include "vsv_convert.h"

#include <stddef.h>
#include <stdint.h>

/* The scratch folder, made once per process under $VSV_FUZZ_TMP, else
 * /dev/shm, else $TMPDIR (removed at exit). */
const char *fuzz_dir(void);
/* Writes n bytes to fuzz_dir()/name; returns the path (static buffer) or NULL. */
const char *fuzz_put(const char *name, const void *data, size_t n);
/* Opens path as a source (opts may be NULL) and, when it opens and its grid
 * is at most 2^20 cells, reads every field at every time (at most 8 times)
 * and the heights. -1 when it does not open, else the reads that failed. */
int fuzz_source_read_all(const char *path, const vsv_source_opts *opts);

#endif
