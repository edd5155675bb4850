/* vsv_http.c — the HTTP byte source (vsv_http.h): a HEAD request learns the
 * file's length and validators; each range the reader needs is fetched in
 * whole blocks (VSV_HTTP_BLOCK), the missing blocks of the range and of the
 * hint after it in as few requests as possible (runs of missing blocks, with
 * small held gaps fetched again rather than split), into a buffer that is
 * checked (HTTP 206, the Content-Range asked for, the length and ETag the
 * file had when opened, every byte there) before any byte reaches the
 * reader. One transfer at a time per file (a mutex); held blocks are read
 * without it. */
#include "vsv_http_internal.h"

#include <curl/curl.h>
#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <time.h>

/* the most one request fetches beyond what was asked (the hint), and a held
 * gap short enough to fetch again inside one request */
#define AHEAD_MAX (8u << 20)
#define GAP_MAX 4
/* the most blocks one request fetches (16 MiB): a larger range, as
 * vsv-info --check asks for a whole chunk, takes several */
#define RUN_MAX 1024

typedef struct http_src {
    vsv_byte_source pub; /* first: the reader's view */
    char url[2048];
    CURL *curl;
    pthread_mutex_t lock;
    vsv_http_ident id;
    vsv_http_cache cache;
    int retries;
    double time_limit;
    long stall;       /* seconds without a byte: a stalled transfer */
    int stop;         /* (atomic) interrupted: every transfer ends, no more start */
    char failed[512]; /* once the file changed: every later need fails so */
    int down;         /* the last range outlasted its retries: the next gets one attempt */
} http_src;

typedef struct reply {
    long status;
    uint64_t cr_first, cr_last, cr_total; /* Content-Range; cr_total UINT64_MAX: "*" */
    int has_cr;
    char etag[256], lastmod[128];
    int ranges_none;
    unsigned char *buf;
    size_t want, got;
    int overflow, refused; /* more bytes than asked; a body that is not a 206 */
    char encoding[64];     /* a Content-Encoding other than identity: the body is not the file's bytes */
    CURL *curl;
    const int *stop; /* the source's interruption flag */
} reply;

static pthread_once_t curl_once = PTHREAD_ONCE_INIT;
static CURLcode curl_init_rc;
static void curl_init(void) { curl_init_rc = curl_global_init(CURL_GLOBAL_DEFAULT); }

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + t.tv_nsec * 1e-9;
}

static void copy_value(char *dst, size_t cap, const char *v, size_t n)
{
    while (n && (*v == ' ' || *v == '\t'))
        v++, n--;
    while (n && (v[n - 1] == '\r' || v[n - 1] == '\n' || v[n - 1] == ' '))
        n--;
    if (n >= cap)
        n = cap - 1;
    memcpy(dst, v, n);
    dst[n] = 0;
}

static size_t on_header(char *line, size_t size, size_t nitems, void *ctx)
{
    reply *r = ctx;
    const size_t n = size * nitems;
    if (n >= 5 && !strncmp(line, "HTTP/", 5)) { /* a new response (a redirect, a 100) */
        r->has_cr = 0;
        r->etag[0] = r->lastmod[0] = 0;
        r->ranges_none = 0;
        r->encoding[0] = 0;
        return n;
    }
    const char *colon = memchr(line, ':', n);
    if (!colon)
        return n;
    const size_t klen = (size_t)(colon - line), vlen = n - klen - 1;
    char v[300];
    copy_value(v, sizeof v, colon + 1, vlen);
    if (klen == 4 && !strncasecmp(line, "etag", 4)) {
        snprintf(r->etag, sizeof r->etag, "%s", v);
    } else if (klen == 13 && !strncasecmp(line, "last-modified", 13)) {
        snprintf(r->lastmod, sizeof r->lastmod, "%s", v);
    } else if (klen == 16 && !strncasecmp(line, "content-encoding", 16)) {
        if (v[0] && strcasecmp(v, "identity"))
            snprintf(r->encoding, sizeof r->encoding, "%s", v);
    } else if (klen == 13 && !strncasecmp(line, "accept-ranges", 13)) {
        r->ranges_none = !strcasecmp(v, "none");
    } else if (klen == 13 && !strncasecmp(line, "content-range", 13)) {
        unsigned long long a, b, t;
        char star;
        if (sscanf(v, "bytes %llu-%llu/%llu", &a, &b, &t) == 3) {
            r->has_cr = 1, r->cr_first = a, r->cr_last = b, r->cr_total = t;
        } else if (sscanf(v, "bytes %llu-%llu/%c", &a, &b, &star) == 3 && star == '*') {
            r->has_cr = 1, r->cr_first = a, r->cr_last = b, r->cr_total = UINT64_MAX;
        }
    }
    return n;
}

static size_t on_body(char *p, size_t size, size_t nitems, void *ctx)
{
    reply *r = ctx;
    const size_t n = size * nitems;
    long status = 0;
    curl_easy_getinfo(r->curl, CURLINFO_RESPONSE_CODE, &status);
    if (status != 206 || r->encoding[0]) { /* a whole file, an error page, encoded bytes: not read */
        r->refused = 1;
        return 0;
    }
    if (n > r->want - r->got) {
        r->overflow = 1;
        return 0;
    }
    memcpy(r->buf + r->got, p, n);
    r->got += n;
    return n;
}

/* libcurl's progress callback, called about once a second even while no
 * byte comes: an interruption ends the transfer. */
static int on_progress(void *ctx, curl_off_t dltotal, curl_off_t dlnow, curl_off_t ultotal, curl_off_t ulnow)
{
    (void)dltotal, (void)dlnow, (void)ultotal, (void)ulnow;
    return __atomic_load_n(((const reply *)ctx)->stop, __ATOMIC_ACQUIRE) != 0;
}

/* Why a transfer that libcurl timed out failed: the server stalled (no
 * byte for h->stall seconds), or the range's time ran out. */
static void timed_out(const http_src *h, const reply *r, double took, char *why, size_t cap)
{
    if (took + 0.5 < (double)h->stall) /* (the stall clock had not run out) */
        snprintf(why, cap, "no complete answer within the %.0f s a range may take (%zu of %zu bytes came)",
                 h->time_limit, r->got, r->want);
    else if (!r->status)
        snprintf(why, cap, "the server stalled: no answer for %ld s", h->stall);
    else if (!r->got)
        snprintf(why, cap, "the server stalled: headers, then no data for %ld s", h->stall);
    else
        snprintf(why, cap, "the server stalled: no data for %ld s after %zu of %zu bytes", h->stall, r->got, r->want);
}

/* One attempt. 0, or -1 with why set and *transient saying whether another
 * attempt may succeed; *changed when the file is no longer the one opened. */
static int transfer(http_src *h, int head, uint64_t a, uint64_t n, unsigned char *buf, double deadline, reply *r,
                    int *transient, int *changed, char *why, size_t cap)
{
    CURL *c = h->curl;
    memset(r, 0, sizeof *r);
    r->buf = buf;
    r->want = (size_t)n;
    r->curl = c;
    r->stop = &h->stop;
    *transient = 0;
    *changed = 0;
    curl_easy_reset(c);
    char range[64];
    snprintf(range, sizeof range, "%" PRIu64 "-%" PRIu64, a, a + n - 1);
    curl_easy_setopt(c, CURLOPT_URL, h->url);
    curl_easy_setopt(c, CURLOPT_NOSIGNAL, 1L);
    curl_easy_setopt(c, CURLOPT_FOLLOWLOCATION, 1L);
    curl_easy_setopt(c, CURLOPT_MAXREDIRS, 5L);
    curl_easy_setopt(c, CURLOPT_USERAGENT, "vesuvius/" VSV_VERSION_STRING);
    curl_easy_setopt(c, CURLOPT_HEADERFUNCTION, on_header);
    curl_easy_setopt(c, CURLOPT_HEADERDATA, r);
    curl_easy_setopt(c, CURLOPT_WRITEFUNCTION, on_body);
    curl_easy_setopt(c, CURLOPT_WRITEDATA, r);
    /* a stalled transfer (under 1 byte/s for h->stall s) is a transient
     * failure; an interruption ends one at the next progress call */
    curl_easy_setopt(c, CURLOPT_LOW_SPEED_LIMIT, 1L);
    curl_easy_setopt(c, CURLOPT_LOW_SPEED_TIME, h->stall);
    curl_easy_setopt(c, CURLOPT_CONNECTTIMEOUT_MS, 30000L);
    curl_easy_setopt(c, CURLOPT_NOPROGRESS, 0L);
    curl_easy_setopt(c, CURLOPT_XFERINFOFUNCTION, on_progress);
    curl_easy_setopt(c, CURLOPT_XFERINFODATA, r);
    const double t0 = now(), left = deadline - t0;
    curl_easy_setopt(c, CURLOPT_TIMEOUT_MS, (long)(left > 0.001 ? left * 1000 : 1));
    const char *ca = getenv("CURL_CA_BUNDLE");
    if (ca && *ca)
        curl_easy_setopt(c, CURLOPT_CAINFO, ca);
    /* no compression: the bytes are the file's bytes */
    curl_easy_setopt(c, CURLOPT_ACCEPT_ENCODING, NULL);
    if (head)
        curl_easy_setopt(c, CURLOPT_NOBODY, 1L);
    else
        curl_easy_setopt(c, CURLOPT_RANGE, range);
    const CURLcode rc = curl_easy_perform(c);
    curl_easy_getinfo(c, CURLINFO_RESPONSE_CODE, &r->status);
    if (rc == CURLE_ABORTED_BY_CALLBACK) {
        snprintf(why, cap, "interrupted (the program is closing)");
        return -1;
    }
    if (rc == CURLE_OPERATION_TIMEDOUT) {
        *transient = 1;
        timed_out(h, r, now() - t0, why, cap);
        return -1;
    }
    if (rc != CURLE_OK && !(rc == CURLE_WRITE_ERROR && (r->refused || r->overflow))) {
        switch (rc) {
        case CURLE_COULDNT_CONNECT:
        case CURLE_PARTIAL_FILE:
        case CURLE_RECV_ERROR:
        case CURLE_SEND_ERROR:
        case CURLE_GOT_NOTHING:
        case CURLE_OPERATION_TIMEDOUT:
        case CURLE_HTTP2:
        case CURLE_HTTP2_STREAM:
        case CURLE_SSL_CONNECT_ERROR: *transient = 1; break;
        default: break;
        }
        snprintf(why, cap, "%s%s",
                 rc == CURLE_PARTIAL_FILE  ? "truncated response (the connection closed early)"
                 : rc == CURLE_GOT_NOTHING ? "connection dropped (no response)"
                                           : curl_easy_strerror(rc),
                 rc == CURLE_PEER_FAILED_VERIFICATION ? " (a certificate not signed by an authority the system "
                                                        "trusts: CURL_CA_BUNDLE=FILE.pem names one to trust)"
                                                      : "");
        return -1;
    }
    const long st = r->status;
    if (r->encoding[0] && (st == 200 || st == 206)) {
        /* none was asked for (no Accept-Encoding): a server or proxy that
         * compresses anyway sends other bytes than the range's, every time
         * (it read as a truncated reply, retried six times) */
        snprintf(why, cap,
                 "the server sent the %s %s-encoded (Content-Encoding: %s) instead of its bytes as they are; remote "
                 ".vsv files are read by range, unencoded",
                 head ? "file" : "range", r->encoding, r->encoding);
        return -1;
    }
    if (st == 408 || st == 429 || (st >= 500 && st <= 599)) {
        *transient = 1;
        snprintf(why, cap, "HTTP %ld from the server", st);
        return -1;
    }
    const int etag_moved = h->id.etag[0] && r->etag[0] && strcmp(h->id.etag, r->etag);
    const int lm_moved = !h->id.etag[0] && h->id.lastmod[0] && r->lastmod[0] && strcmp(h->id.lastmod, r->lastmod);
    if (head) {
        if (st != 200) {
            snprintf(why, cap, "HTTP %ld%s", st, st == 404 ? " (not found)" : st == 403 ? " (forbidden)" : "");
            return -1;
        }
        return 0;
    }
    if (st == 416 || ((st == 200 || st == 206) && (etag_moved || lm_moved))) {
        *changed = 1;
        if (etag_moved)
            snprintf(why, cap, "the file changed on the server while it was read (ETag %s became %s)", h->id.etag,
                     r->etag);
        else if (lm_moved)
            snprintf(why, cap, "the file changed on the server while it was read (Last-Modified %s became %s)",
                     h->id.lastmod, r->lastmod);
        else
            snprintf(why, cap, "the file changed on the server while it was read (HTTP 416: it is shorter now)");
        return -1;
    }
    if (st == 200) {
        snprintf(why, cap,
                 "the server ignores range requests (HTTP 200, the whole file, for a range); "
                 "remote .vsv files are read by range");
        return -1;
    }
    if (st != 206) {
        snprintf(why, cap, "HTTP %ld%s", st, st == 404 ? " (not found)" : st == 403 ? " (forbidden)" : "");
        return -1;
    }
    if (!r->has_cr || r->cr_first != a || r->cr_last != a + n - 1) {
        snprintf(why, cap, "the server answered with another range (Content-Range %s%llu-%llu)",
                 r->has_cr ? "" : "missing, ", (unsigned long long)r->cr_first, (unsigned long long)r->cr_last);
        return -1;
    }
    if (r->cr_total != UINT64_MAX && r->cr_total != h->id.size) {
        *changed = 1;
        snprintf(why, cap, "the file changed on the server while it was read (%llu bytes, was %llu)",
                 (unsigned long long)r->cr_total, (unsigned long long)h->id.size);
        return -1;
    }
    if (r->overflow || r->got != r->want) {
        *transient = 1;
        snprintf(why, cap, "%s: %zu of %zu bytes",
                 r->overflow ? "response longer than the range" : "truncated response", r->got, r->want);
        return -1;
    }
    return 0;
}

/* Sleeps t seconds, or less when interrupted: 1 then. */
static int pause_for(const http_src *h, double t)
{
    const double end = now() + t;
    for (double left = t; left > 0 && !__atomic_load_n(&h->stop, __ATOMIC_ACQUIRE); left = end - now()) {
        const double d = left < 0.1 ? left : 0.1;
        struct timespec ts = {0, (long)(d * 1e9)};
        while (nanosleep(&ts, &ts) && errno == EINTR) {
        }
    }
    return __atomic_load_n(&h->stop, __ATOMIC_ACQUIRE) != 0;
}

/* A transfer with retries: back-off from 0.25 s doubling to 4 s, at most
 * h->retries more attempts, within h->time_limit seconds. Once a range has
 * failed after all its attempts (the server went away), the next ones get
 * one attempt each until one succeeds: a player goes on past the steps it
 * cannot fetch instead of waiting out the back-off for every brick. */
static int fetch(http_src *h, int head, uint64_t a, uint64_t n, unsigned char *buf, reply *r, char *msg, size_t cap)
{
    if (h->failed[0]) {
        snprintf(msg, cap, "%s", h->failed);
        return VSV_EIO;
    }
    if (__atomic_load_n(&h->stop, __ATOMIC_ACQUIRE)) {
        snprintf(msg, cap, "%s: interrupted (the program is closing)", h->url);
        return VSV_EIO;
    }
    const double deadline = now() + h->time_limit;
    double delay = 0.25;
    char why[400];
    const int retries = h->down ? 0 : h->retries;
    for (int attempt = 0;; attempt++) {
        int transient, changed;
        if (!transfer(h, head, a, n, buf, deadline, r, &transient, &changed, why, sizeof why)) {
            h->down = 0;
            return 0;
        }
        const int stopped = __atomic_load_n(&h->stop, __ATOMIC_ACQUIRE) != 0;
        if (!transient || stopped || attempt >= retries || now() + delay >= deadline) {
            char where[96] = "";
            if (!head)
                snprintf(where, sizeof where, " (bytes %" PRIu64 "-%" PRIu64 ")", a, a + n - 1);
            char tries[112] = "";
            if (attempt)
                snprintf(tries, sizeof tries, ", after %d attempts", attempt + 1);
            else if (h->down)
                snprintf(tries, sizeof tries, " (one attempt: the range before it failed after all of its attempts)");
            h->down = transient && !changed;
            snprintf(msg, cap, "%s: %s%s%s", h->url, why, where, tries);
            if (changed) {
                h->cache.stale = 1;
                snprintf(h->failed, sizeof h->failed, "%s", msg);
            }
            return changed || transient || stopped ? VSV_EIO : VSV_EUNSUPPORTED;
        }
        if (pause_for(h, delay))
            transient = 0; /* (the next attempt is refused at once) */
        delay = delay * 2 > 4 ? 4 : delay * 2;
    }
}

static int held(const http_src *h, size_t b) { return __atomic_load_n(&h->cache.have[b], __ATOMIC_ACQUIRE); }

/* Fetches blocks [b0, b1] into the cache; with all, held ones too. */
static int fetch_blocks(http_src *h, size_t b0, size_t b1, int all, char *msg, size_t cap)
{
    const uint64_t a = (uint64_t)b0 * VSV_HTTP_BLOCK;
    uint64_t e = (uint64_t)(b1 + 1) * VSV_HTTP_BLOCK;
    if (e > h->id.size)
        e = h->id.size;
    unsigned char *buf = malloc((size_t)(e - a));
    if (!buf) {
        snprintf(msg, cap, "%s: out of memory", h->url);
        return VSV_ENOMEM;
    }
    reply r;
    int rc = fetch(h, 0, a, e - a, buf, &r, msg, cap);
    for (size_t b = b0; !rc && b <= b1; b++) {
        if (!all && held(h, b))
            continue; /* never written over while it may be read */
        const uint64_t o = (uint64_t)b * VSV_HTTP_BLOCK;
        const size_t len = (size_t)((o + VSV_HTTP_BLOCK < e ? o + VSV_HTTP_BLOCK : e) - o);
        char why[300];
        if ((rc = vsv_http_cache_put(&h->cache, o, buf + (o - a), len, why, sizeof why))) {
            snprintf(msg, cap, "%s: %s", h->url, why);
            break;
        }
        __atomic_store_n(&h->cache.have[b], 1, __ATOMIC_RELEASE);
        vsv_http_cache_mark(&h->cache, b);
    }
    free(buf);
    return rc;
}

static int check_range(http_src *h, uint64_t off, uint64_t n, char *msg, size_t cap)
{
    if (off > h->id.size || n > h->id.size - off) {
        snprintf(msg, cap, "%s: bytes %llu-%llu past the end of the file (%llu bytes)", h->url, (unsigned long long)off,
                 (unsigned long long)(off + n - 1), (unsigned long long)h->id.size);
        return VSV_ETRUNC;
    }
    return 0;
}

static int src_need(vsv_byte_source *s, uint64_t off, uint64_t n, uint64_t ahead, char *msg, size_t cap)
{
    http_src *h = (http_src *)s;
    int rc = check_range(h, off, n, msg, cap);
    if (rc || !n)
        return rc;
    const size_t b0 = (size_t)(off / VSV_HTTP_BLOCK), b1 = (size_t)((off + n - 1) / VSV_HTTP_BLOCK);
    size_t b = b0;
    while (b <= b1 && held(h, b))
        b++;
    if (b > b1)
        return 0; /* all there: no lock */
    pthread_mutex_lock(&h->lock);
    if (ahead > AHEAD_MAX)
        ahead = AHEAD_MAX;
    const uint64_t end = off + n + ahead < h->id.size ? off + n + ahead : h->id.size;
    const size_t last = (size_t)((end - 1) / VSV_HTTP_BLOCK);
    /* runs of missing blocks from b: those of [b0, b1] all, those of the hint
     * while they continue the run; short held gaps joined */
    while (!rc && b <= b1) {
        if (held(h, b)) {
            b++;
            continue;
        }
        size_t r1 = b, gap = 0;
        for (size_t k = b + 1; k <= last && k - b < RUN_MAX; k++) {
            if (!held(h, k)) {
                r1 = k;
                gap = 0;
            } else if (++gap > GAP_MAX || k > b1) {
                break;
            }
        }
        rc = fetch_blocks(h, b, r1, 0, msg, cap);
        b = r1 + 1;
    }
    pthread_mutex_unlock(&h->lock);
    return rc;
}

static int src_refetch(vsv_byte_source *s, uint64_t off, uint64_t n, char *msg, size_t cap)
{
    http_src *h = (http_src *)s;
    int rc = check_range(h, off, n, msg, cap);
    if (rc || !n)
        return rc ? rc : VSV_EINVAL;
    pthread_mutex_lock(&h->lock);
    rc = fetch_blocks(h, (size_t)(off / VSV_HTTP_BLOCK), (size_t)((off + n - 1) / VSV_HTTP_BLOCK), 1, msg, cap);
    pthread_mutex_unlock(&h->lock);
    return rc;
}

static void src_interrupt(vsv_byte_source *s) { __atomic_store_n(&((http_src *)s)->stop, 1, __ATOMIC_RELEASE); }

static void src_close(vsv_byte_source *s)
{
    http_src *h = (http_src *)s;
    vsv_http_cache_close(&h->cache, &h->id);
    if (h->curl)
        curl_easy_cleanup(h->curl);
    pthread_mutex_destroy(&h->lock);
    free(h);
}

void vsv_http_opts_init(vsv_http_opts *o)
{
    memset(o, 0, sizeof *o);
    o->retries = -1;
}

int vsv_is_url(const char *name)
{
    return name && (!strncasecmp(name, "http://", 7) || !strncasecmp(name, "https://", 8));
}

static const char *default_dir(char *buf, size_t cap)
{
    const char *d = getenv("VSV_CACHE_DIR");
    if (d && *d)
        return d;
    if ((d = getenv("XDG_CACHE_HOME")) && *d == '/') {
        snprintf(buf, cap, "%s/vesuvius", d);
        return buf;
    }
    if ((d = getenv("HOME")) && *d == '/') {
        snprintf(buf, cap, "%s/.cache/vesuvius", d);
        return buf;
    }
    return NULL;
}

/* A source that only fails: the handle it opens carries the message, as
 * vsv_file_open leaves one. */
typedef struct failed_src {
    vsv_byte_source pub;
    int rc;
    char msg[700];
} failed_src;

static int failed_need(vsv_byte_source *s, uint64_t off, uint64_t n, uint64_t ahead, char *msg, size_t cap)
{
    (void)off, (void)n, (void)ahead;
    snprintf(msg, cap, "%s", ((failed_src *)s)->msg);
    return ((failed_src *)s)->rc;
}

static void failed_close(vsv_byte_source *s) { free(s); }

static int failed_handle(const char *url, int rc, const char *msg, vsv_file **out)
{
    static const unsigned char none[1];
    failed_src *fs = calloc(1, sizeof *fs);
    if (!fs)
        return VSV_ENOMEM;
    fs->rc = rc;
    snprintf(fs->msg, sizeof fs->msg, "%s", msg);
    fs->pub.base = none;
    fs->pub.size = 1;
    fs->pub.need = failed_need;
    fs->pub.close = failed_close;
    vsv_file_open_source(&fs->pub, url, out);
    return rc;
}

/* An entry of the cache used again holds this file only if its first block
 * is the server's now (vsv_http_cache_confirm): fetched on every such open.
 * 0, or the fetch's error with msg set. */
static int confirm_cache(http_src *h, char *msg, size_t cap)
{
    if (!h->cache.reused)
        return 0;
    const size_t n = h->id.size < VSV_HTTP_BLOCK ? (size_t)h->id.size : VSV_HTTP_BLOCK;
    unsigned char *first = malloc(n);
    if (!first) {
        snprintf(msg, cap, "%s: out of memory", h->url);
        return VSV_ENOMEM;
    }
    reply r;
    char why[400];
    int rc = fetch(h, 0, 0, n, first, &r, msg, cap);
    if (!rc && (rc = vsv_http_cache_confirm(&h->cache, h->url, &h->id, first, n, why, sizeof why)))
        snprintf(msg, cap, "%s: %s", h->url, why);
    free(first);
    return rc;
}

/* The source for url, its cache opened; *reused: blocks came from the cache. */
static int src_open(const char *url, const vsv_http_opts *o, http_src **out, vsv_file **fout, size_t *reused)
{
    char msg[700];
    http_src *h = calloc(1, sizeof *h);
    *out = h;
    if (!h)
        return VSV_ENOMEM;
    pthread_mutex_init(&h->lock, NULL);
    h->cache.fd = h->cache.meta_fd = -1;
    snprintf(h->url, sizeof h->url, "%s", url);
    h->retries = o->retries < 0 ? 5 : o->retries;
    h->time_limit = o->time_limit > 0 ? o->time_limit : 120;
    double stall = o->stall;
    const char *st = getenv("VSV_HTTP_STALL");
    if (!(stall > 0) && st && *st)
        stall = strtod(st, NULL);
    h->stall = !(stall > 0) ? 30 : stall > 86400 ? 86400 : (long)ceil(stall);
    pthread_once(&curl_once, curl_init);
    if (curl_init_rc != CURLE_OK || !(h->curl = curl_easy_init())) {
        snprintf(msg, sizeof msg, "%s: cannot start libcurl", url);
        goto fail_nomem;
    }
    reply r;
    int rc = fetch(h, 1, 0, 0, NULL, &r, msg, sizeof msg);
    if (rc)
        goto fail;
    curl_off_t len = -1;
    curl_easy_getinfo(h->curl, CURLINFO_CONTENT_LENGTH_DOWNLOAD_T, &len);
    if (len < 0) {
        snprintf(msg, sizeof msg, "%s: the server does not say the file's length (no Content-Length)", url);
        rc = VSV_EUNSUPPORTED;
        goto fail;
    }
    if (r.ranges_none) {
        snprintf(msg, sizeof msg,
                 "%s: the server does not support range requests (Accept-Ranges: none); "
                 "remote .vsv files are read by range",
                 url);
        rc = VSV_EUNSUPPORTED;
        goto fail;
    }
    if (len == 0) {
        snprintf(msg, sizeof msg, "%s: not a .vsv file (empty)", url);
        rc = VSV_ENOTVSV;
        goto fail;
    }
    h->id.size = (uint64_t)len;
    snprintf(h->id.etag, sizeof h->id.etag, "%s", r.etag);
    snprintf(h->id.lastmod, sizeof h->id.lastmod, "%s", r.lastmod);
    char dbuf[4096];
    const char *dir = o->cache_dir ? o->cache_dir : default_dir(dbuf, sizeof dbuf);
    uint64_t max = o->cache_max;
    const char *m = getenv("VSV_CACHE_MAX");
    if (!max && m && *m)
        max = strtoull(m, NULL, 10);
    if (!max)
        max = 4ull << 30;
    char why[400];
    if ((rc = vsv_http_cache_open(&h->cache, dir, max, url, &h->id, why, sizeof why))) {
        snprintf(msg, sizeof msg, "%s: %s", url, why);
        goto fail;
    }
    if ((rc = confirm_cache(h, msg, sizeof msg)))
        goto fail;
    *reused = h->cache.reused;
    h->pub.base = h->cache.map;
    h->pub.size = h->id.size;
    h->pub.need = src_need;
    h->pub.refetch = src_refetch;
    h->pub.close = src_close;
    h->pub.interrupt = src_interrupt;
    return 0;
fail_nomem:
    rc = VSV_ENOMEM;
fail:
    src_close(&h->pub);
    *out = NULL;
    return failed_handle(url, rc ? rc : VSV_EIO, msg, fout);
}

int vsv_file_open_url(const char *url, const vsv_http_opts *opts, vsv_file **out)
{
    vsv_http_opts def;
    if (!opts) {
        vsv_http_opts_init(&def);
        opts = &def;
    }
    *out = NULL;
    for (int pass = 0;; pass++) {
        http_src *h = NULL;
        size_t reused = 0;
        int rc = src_open(url, opts, &h, out, &reused);
        if (rc)
            return rc;
        rc = vsv_file_open_source(&h->pub, url, out);
        /* a damaged cache: once more without it (the fetched bytes are
         * checked as the file's own are) */
        if ((rc == VSV_ECORRUPT || rc == VSV_ENOTVSV || rc == VSV_ETRUNC || rc == VSV_EVERSION) && reused && !pass) {
            h->cache.stale = 1;
            vsv_file_free(*out);
            *out = NULL;
            continue;
        }
        return rc;
    }
}

int vsv_file_open_any(const char *name, const vsv_http_opts *o, vsv_file **out)
{
    return vsv_is_url(name) ? vsv_file_open_url(name, o, out) : vsv_file_open(name, out);
}
