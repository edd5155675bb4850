/* vsv_common.h — the private helpers the libraries of Vesuvius share, as
 * zstd's lib/common/ (never exported, never installed; compiled once into
 * common/libvsv-common.a, see ARCHITECTURE.md): little-endian byte helpers,
 * a growable byte buffer (vsv_buf.c), "path: message" texts (vsv_msg.c) and
 * the sane limits every reader checks sizes against. Every library folder
 * may include it. */
#ifndef VSV_COMMON_H
#define VSV_COMMON_H

#include "vsv_format.h"

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <sys/types.h>

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
static inline void vsv_wr16(unsigned char *p, uint16_t v)
{
    p[0] = (unsigned char)v;
    p[1] = (unsigned char)(v >> 8);
}
static inline void vsv_wr32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)v;
    p[1] = (unsigned char)(v >> 8);
    p[2] = (unsigned char)(v >> 16);
    p[3] = (unsigned char)(v >> 24);
}
static inline void vsv_wr64(unsigned char *p, uint64_t v)
{
    vsv_wr32(p, (uint32_t)v);
    vsv_wr32(p + 4, (uint32_t)(v >> 32));
}
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

#define VSV_MAX_DIM 16384
#define VSV_MAX_CELLS ((uint64_t)1 << 34)
#define VSV_MAX_VARS 1024
#define VSV_MAX_STEPS 10000000
#define VSV_MAX_STRING 4096
#define VSV_MAX_META ((uint64_t)1 << 32)

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

/* errno's text for a message, as the tools say it: "out of memory" for
 * ENOMEM (whose strerror is "Cannot allocate memory"), else strerror(e). */
const char *vsv_errno_text(int e);
/* printf into a fixed message buffer. */
void vsv_msg(char *buf, size_t cap, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

/* Writes s to fp as one CSV field (RFC 4180: quoted when it holds a comma,
 * a double quote or a line break; vsv_csv.c). */
void vsv_csv_field(FILE *fp, const char *s);
/* "path: " followed by the formatted message: the shape of every error a
 * reader keeps for its file. */
void vsv_vmsg_path(char *buf, size_t cap, const char *path, const char *fmt, va_list ap)
    __attribute__((format(printf, 4, 0)));

/* What a file of mode m (st_mode) is when not a regular file: "a FIFO",
 * "a directory", "a character device" ... */
const char *vsv_file_kind(unsigned m);
/* Opens an input file read-only, refusing (without blocking) anything but a
 * regular file: a FIFO, device, socket or directory. The descriptor, or -1
 * with the reason in why (e.g. "a FIFO, not a regular file: refused"). */
int vsv_input_open(const char *path, char *why, size_t cap);
/* The same as a stdio stream (mode "r" or "rb"); NULL with why set. */
FILE *vsv_input_fopen(const char *path, const char *mode, char *why, size_t cap);
/* Opens an input stream (a field stream: read once, front to back): a
 * regular file or a pipe (FIFO, /dev/fd/N of a shell's process
 * substitution), whose open waits for its writer; a directory, device or
 * socket is refused. NULL with the reason in why. */
FILE *vsv_input_fopen_stream(const char *path, char *why, size_t cap);
/* Mappings guarded against a file that shrinks while it is read
 * (vsv_mapguard.c): add returns a slot (or -1: unguarded, a truncation then
 * kills as before); cut says whether an access past the file's new end has
 * happened since (it read zeros, not the file); remove before munmap. */
int vsv_mapguard_add(const void *p, size_t n);
int vsv_mapguard_cut(int slot);
void vsv_mapguard_remove(int slot);
/* What every reader says of an input cut while it reads it. */
#define VSV_CUT_TEXT "truncated while reading (the file shrank after it was opened)"

/* A whole input file mapped read-only, guarded (vsv_mapguard.c), its
 * descriptor kept to learn its size again. */
typedef struct vsv_mapped {
    const unsigned char *data; /* NULL: nothing mapped */
    size_t n;
    int fd;    /* -1: none */
    int guard; /* the vsv_mapguard slot, or -1 */
} vsv_mapped;
/* Maps an input file (opened as vsv_input_open): 0 with m set (caller frees
 * with vsv_input_unmap); 1, nothing mapped, when it is shorter than
 * min_bytes or empty (m->n its size: the caller says what it is not); -1
 * with the reason in why. m is always safe to unmap. */
int vsv_input_map(const char *path, size_t min_bytes, vsv_mapped *m, char *why, size_t cap);
/* 1 when the file under m has shrunk since it was mapped, so what was read
 * from it since may be zeros, not its bytes: the guard saw an access past
 * its new end, or, with look set, fstat says it is shorter (the rest of the
 * last page past a new end reads zeros without a signal; a system call, for
 * failure paths and once per large read). 0 otherwise. */
int vsv_input_cut(const vsv_mapped *m, int look);
/* Unguards, unmaps and closes what m holds (a guard alone: a byte source's
 * range, registered by its reader). */
void vsv_input_unmap(vsv_mapped *m);

/* Writes all n bytes of p to fd (vsv_fdio.c): at offset off with pwrite(2),
 * or where the descriptor stands with write(2) when off < 0; short writes
 * and EINTR are continued. 0, or -1 with errno. */
int vsv_write_full(int fd, const void *p, size_t n, int64_t off);

/* Private helper programs (vsv_helper.c): reading untrusted files with a
 * library that can crash on them happens in an exec'd helper, never in a
 * fork of a process that may have threads. */
/* The helper's path into out (caller buffer of cap bytes): $VSV_HELPER_DIR,
 * else next to this library or program (build tree, install), else the
 * compiled-in $(libdir)/vesuvius. 0, or -1 when it is nowhere. */
int vsv_helper_path(const char *name, char *out, size_t cap);
/* Starts helper `name` with argv (argv[0] included, NULL-terminated), its
 * stdin and stdout on in and out (-1: /dev/null), `extra` as its fd 3 (-1:
 * none), stderr on /dev/null, default signal dispositions. The caller's
 * descriptors stay its own. The pid, or -1 with the reason in why. */
pid_t vsv_helper_spawn(const char *name, char *const argv[], int in, int out, int extra, char *why, size_t cap);
/* Waits up to limit_s seconds for fd to become readable: 1, 0 on time out,
 * -1 on error. */
int vsv_helper_poll(int fd, double limit_s);
/* Waits for pid at most limit_s seconds of wall clock, then kills it
 * (SIGKILL) and waits. Its wait status in *status; 1 when it was killed for
 * time, else 0. */
int vsv_helper_reap(pid_t pid, double limit_s, int *status);
/* Runs a helper to completion with at most limit_s seconds of wall clock:
 * what it writes to stdout (up to cap - 1 bytes, NUL-terminated) in out,
 * its wait status in *status. 0; 1 when killed for time; -1 when it could
 * not be started (the reason in why, wcap bytes). */
int vsv_helper_run(const char *name, char *const argv[], int extra, double limit_s, char *out, size_t cap, int *status,
                   char *why, size_t wcap);

#endif
