/* vsv_http.h — .vsv files on a web server (libvesuvius-http, over libcurl):
 * the reader's byte source (vsv_format.h) as HTTP range requests. Opening
 * fetches the header, metadata, table of contents and end marker; then only
 * the chunk indexes and payloads the reader asks for, adjacent ranges in one
 * request. Transient failures (a dropped connection, a truncated response,
 * HTTP 5xx) are retried with back-off, bounded in attempts and wall-clock
 * time. Fetched bytes are kept in an on-disk cache (one sparse file per URL
 * and a record of the ranges it holds) that is used again only while the
 * server's ETag, or its length and Last-Modified, still match; each
 * structure's CRC is checked as for a local file, and a mismatch on cached
 * bytes fetches them again. A transfer that gets no byte for opts.stall
 * seconds fails as stalled ("URL: the server stalled: headers, then no data
 * for 30 s (bytes A-B)"), a transient failure; vsv_file_interrupt ends one
 * under way within a second or so. A server that ignores Range, a file that
 * changes on the server while it is read (its ETag or length), or a failure
 * that outlasts the retries is an error, "URL: what, where"; data never
 * reaches the reader unverified. The core library (vsv_format.h) never needs
 * libcurl: programs that read URLs link this library too. */
#ifndef VSV_HTTP_H
#define VSV_HTTP_H

#include "vsv_format.h"

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vsv_http_opts {
    /* NULL: $VSV_CACHE_DIR, else $XDG_CACHE_HOME/vesuvius, else
     * $HOME/.cache/vesuvius; "off" (or ""): no disk cache, memory only */
    const char *cache_dir;
    /* the cache's bound in bytes, least recently used files removed first
     * (0: $VSV_CACHE_MAX bytes, else 4 GiB) */
    uint64_t cache_max;
    /* attempts after the first on a transient failure (-1: 5) */
    int retries;
    /* seconds one range may take, its retries included (0: 120) */
    double time_limit;
    /* seconds a transfer may go without a byte (a server that sent its
     * headers and then nothing) before it fails as stalled, a transient
     * failure retried as a dropped connection is (0: $VSV_HTTP_STALL
     * seconds, else 30; whole seconds, at least 1) */
    double stall;
} vsv_http_opts;

void vsv_http_opts_init(vsv_http_opts *o);
/* 1 if name is an http:// or https:// URL. */
int vsv_is_url(const char *name);
/* Opens the .vsv at url (o may be NULL: the defaults). As vsv_file_open:
 * on failure *out may hold a handle whose error says why. HTTPS is verified
 * against the system's certificates, or the file $CURL_CA_BUNDLE names. */
int vsv_file_open_url(const char *url, const vsv_http_opts *o, vsv_file **out);
/* vsv_file_open_url for a URL, vsv_file_open for a path. */
int vsv_file_open_any(const char *name, const vsv_http_opts *o, vsv_file **out);
/* Makes the cache directory dir (and its parents) as opening a URL would,
 * and checks this process can write there: 0, or -1 with the reason in why
 * ("not a directory", "cannot make PARENT: ..."). "off" and "" are 0. */
int vsv_http_cache_dir_make(const char *dir, char *why, size_t cap);

#ifdef __cplusplus
}
#endif

#endif
