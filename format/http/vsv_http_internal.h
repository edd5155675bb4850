/* vsv_http_internal.h — the HTTP byte source's parts: the source and its
 * transfers (vsv_http.c) and the on-disk cache (vsv_http_cache.c). Private
 * to format/http/. */
#ifndef VSV_HTTP_INTERNAL_H
#define VSV_HTTP_INTERNAL_H

#include "vsv_http.h"

#include <pthread.h>
#include <stddef.h>
#include <stdint.h>

/* the unit of fetching and caching */
#define VSV_HTTP_BLOCK 16384u

/* What the server says of the file: its length and validators. */
typedef struct vsv_http_ident {
    uint64_t size;
    char etag[256];
    char lastmod[128];
} vsv_http_ident;

/* An entry of the cache: the file's bytes (a sparse file, or memory when
 * there is no cache) mapped at `map`, and per block whether it is there. */
typedef struct vsv_http_cache {
    unsigned char *map;
    size_t nblocks;
    unsigned char *have; /* per block: 1 resident (atomic) */
    int fd;              /* the data file (locked), or -1: memory only */
    int meta_fd;         /* its record, a byte per block written as it arrives */
    size_t head_len;     /* where the record's bytes per block start */
    char data_path[4096], meta_path[4096];
    char dir[4096];
    uint64_t max;
    size_t reused; /* blocks found in the cache at open */
    int stale;
} vsv_http_cache;

/* Opens the entry for url in dir (NULL or "off": memory only), used again
 * when id matches what it recorded, else started empty; an entry another
 * process holds, or a directory that cannot be written, falls back to
 * memory. 0, or VSV_ENOMEM / VSV_EIO with msg set. */
int vsv_http_cache_open(vsv_http_cache *c, const char *dir, uint64_t max, const char *url, const vsv_http_ident *id,
                        char *msg, size_t cap);
/* Confirms an entry used again (c->reused) against p, the server's bytes
 * [0, n) now (its first block: the .vsv header with its CRC, and what
 * follows): the same length and validators do not prove the same file (a
 * server without ETag, a file replaced in place and its date kept). The
 * entry's copy is read from its data file (not the mapping); a different
 * copy, or none, empties the entry, and p is then its first block held.
 * 0, or VSV_EIO with msg set. */
int vsv_http_cache_confirm(vsv_http_cache *c, const char *url, const vsv_http_ident *id, const unsigned char *p,
                           size_t n, char *msg, size_t cap);
/* Puts n fetched bytes at off (into the data file, or memory); the caller
 * then marks their blocks held. 0, or VSV_EIO with msg set (a full disk). */
int vsv_http_cache_put(vsv_http_cache *c, uint64_t off, const unsigned char *p, size_t n, char *msg, size_t cap);
/* Marks block b held in the record (c->have is the caller's). */
void vsv_http_cache_mark(vsv_http_cache *c, size_t b);
/* Drops a stale entry, keeps the directory under its bound, unmaps. A
 * program that exits without it loses nothing: the record is kept as the
 * blocks arrive. */
void vsv_http_cache_close(vsv_http_cache *c, const vsv_http_ident *id);

#endif
