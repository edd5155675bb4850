/* vsv_source_reader.h — what a reader of another file format implements to
 * be a source (vsv_convert.h) beside the built-in model readers: its
 * operations, the source it fills in, and its registration. The interop
 * library's OpenVDB reader is one (interop/vsv_vdbsrc.c). */
#ifndef VSV_SOURCE_READER_H
#define VSV_SOURCE_READER_H

#include "vsv_convert.h"

#ifdef __cplusplus
extern "C" {
#endif

VSV_API_BEGIN

typedef struct vsv_source_ops {
    const char *name;
    /* 1 if the first n bytes look like this format */
    int (*probe)(const unsigned char *head, size_t n);
    int (*open)(vsv_source *s);
    int (*read)(vsv_source *s, int field, int t, float *out);
    void (*close)(vsv_source *s);
    char *(*summary)(vsv_source *s); /* may be NULL */
    /* --vertical native only: the levels' heights at time t per column
     * (nx*ny*nz, m above sea level); may be NULL (no per-column heights) */
    int (*heights)(vsv_source *s, int t, float *out);
    /* the file field comes from, when it is not s->path (a companion);
     * may be NULL (every field is in s->path) */
    const char *(*field_path)(const vsv_source *s, int field);
} vsv_source_ops;

struct vsv_source {
    const vsv_source_ops *ops;
    char path[1024];
    char err[512];
    vsv_meta grid;
    vsv_field_info *fields;
    int nfields;
    int64_t *times;
    int ntimes;
    vsv_source_opts opts;
    void *priv;
};

/* Sets s->err to "path: message" and returns rc. */
int vsv_source_fail(vsv_source *s, int rc, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

/* Adds a reader that vsv_source_open tries after the built-in ones (ops is
 * borrowed, valid for the life of the program; at most 8). Call before
 * opening sources, from one thread. 0, VSV_EINVAL when full. */
int vsv_source_register(const vsv_source_ops *ops);

VSV_API_END

#ifdef __cplusplus
}
#endif

#endif
