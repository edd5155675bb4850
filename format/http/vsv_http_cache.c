/* vsv_http_cache.c — the on-disk cache of remote .vsv files. One entry per
 * URL, named by a hash of it: KEY.data, a sparse file of the remote file's
 * length holding the fetched blocks at their offsets (mapped shared, so
 * bytes copied into the mapping land in it), and KEY.meta, a text record
 * (URL, length, ETag, Last-Modified, block size) followed by one byte per
 * block saying whether it is held, written as each block arrives (after the
 * block itself, so a program that exits or dies at any point leaves a record
 * that claims no block it lacks). The entry is used again only when the
 * record matches what the server says now (its ETag, or its length and
 * Last-Modified when it gives no ETag; a server that gives neither gets no
 * reuse) and its first block is the server's now (fetched on every open:
 * two files of one length and date never mix). The data file is locked (flock) while a process uses it: a second
 * process reading the same URL meanwhile works from memory. The directory is
 * kept under its bound by removing the least recently used entries (by the
 * record's time, touched on every use). */
#include "vsv_http_internal.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

static uint64_t fnv1a(const char *s)
{
    uint64_t h = 1469598103934665603ull;
    for (; *s; s++)
        h = (h ^ (unsigned char)*s) * 1099511628211ull;
    return h;
}

/* mkdir -p with mode 0700: 0, or -1 with errno and the folder that could
 * not be made in failed (cap bytes). */
static int mkdirs(const char *dir, char *failed, size_t cap)
{
    char p[4096];
    snprintf(p, sizeof p, "%s", dir);
    for (char *s = p + 1;; s++)
        if (*s == '/' || !*s) {
            const char c = *s;
            *s = 0;
            if (mkdir(p, 0700) && errno != EEXIST) {
                snprintf(failed, cap, "%s", p);
                return -1;
            }
            if (!c)
                return 0;
            *s = c;
        }
}

/* A cache folder only this user can write: a directory (not a link to
 * one) it owns, with no write permission for its group or others (in one
 * others can write, a planted link or file would make this process
 * overwrite what the planter chose). 0, or -1 with why. */
static int own_dir(const char *dir, char *why, size_t cap)
{
    struct stat st;
    if (lstat(dir, &st) || !S_ISDIR(st.st_mode)) {
        snprintf(why, cap, "not a directory%s", !lstat(dir, &st) && S_ISLNK(st.st_mode) ? " (a symbolic link)" : "");
        return -1;
    }
    if (st.st_uid != geteuid() || (st.st_mode & (S_IWGRP | S_IWOTH))) {
        snprintf(why, cap, "refused: a cache folder must be yours and writable by you alone (owner %u, mode %03o)",
                 (unsigned)st.st_uid, (unsigned)(st.st_mode & 0777));
        return -1;
    }
    return 0;
}

int vsv_http_cache_dir_make(const char *dir, char *why, size_t cap)
{
    char failed[4096];
    if (!dir[0] || !strcmp(dir, "off"))
        return 0;
    if (strlen(dir) >= sizeof failed) {
        snprintf(why, cap, "the path is too long");
        return -1;
    }
    if (mkdirs(dir, failed, sizeof failed)) {
        snprintf(why, cap, "cannot make %s: %s", failed, strerror(errno));
        return -1;
    }
    if (own_dir(dir, why, cap))
        return -1;
    if (access(dir, W_OK | X_OK)) {
        snprintf(why, cap, "cannot write there: %s", strerror(errno));
        return -1;
    }
    return 0;
}

static void record_head(char *buf, size_t cap, const char *url, const vsv_http_ident *id)
{
    snprintf(buf, cap, "vesuvius-cache 1\nurl %s\nsize %llu\netag %s\nlast-modified %s\nblock %u\nheld\n", url,
             (unsigned long long)id->size, id->etag, id->lastmod, VSV_HTTP_BLOCK);
}

/* Loads the held blocks when the record matches url and id; else 0. */
static size_t load_record(vsv_http_cache *c, const char *url, const vsv_http_ident *id)
{
    if (!id->etag[0] && !id->lastmod[0])
        return 0; /* nothing to validate it by */
    const int rfd = open(c->meta_path, O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
    FILE *fp = rfd >= 0 ? fdopen(rfd, "rb") : NULL;
    if (!fp) {
        if (rfd >= 0)
            close(rfd);
        return 0;
    }
    char want[4096 + 1024], got[sizeof want];
    record_head(want, sizeof want, url, id);
    const size_t n = strlen(want);
    size_t held = 0;
    if (fread(got, 1, n, fp) == n && !memcmp(got, want, n) && fread(c->have, 1, c->nblocks, fp) == c->nblocks &&
        fgetc(fp) == EOF) {
        for (size_t i = 0; i < c->nblocks; i++) {
            c->have[i] = c->have[i] == 1;
            held += c->have[i];
        }
    } else {
        memset(c->have, 0, c->nblocks);
    }
    fclose(fp);
    return held;
}

/* A record of no block held (written whole, then renamed into place); its
 * descriptor, or -1. */
static int new_record(vsv_http_cache *c, const char *url, const vsv_http_ident *id)
{
    char tmp[4096 + 16], head[4096 + 1024];
    snprintf(tmp, sizeof tmp, "%s.tmp", c->meta_path);
    record_head(head, sizeof head, url, id);
    c->head_len = strlen(head);
    unlink(tmp); /* one a crash left, or a link someone planted: never followed */
    const int fd = open(tmp, O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
    if (fd < 0)
        return -1;
    if (write(fd, head, c->head_len) != (ssize_t)c->head_len || ftruncate(fd, (off_t)(c->head_len + c->nblocks)) ||
        rename(tmp, c->meta_path)) {
        close(fd);
        unlink(tmp);
        return -1;
    }
    return fd;
}

static void evict(vsv_http_cache *c, int spare);

static int memory_only(vsv_http_cache *c, uint64_t size, char *msg, size_t cap)
{
    if (c->fd >= 0)
        close(c->fd);
    if (c->meta_fd >= 0)
        close(c->meta_fd);
    c->fd = c->meta_fd = -1;
    c->map = mmap(NULL, size, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
    if (c->map == MAP_FAILED) {
        c->map = NULL;
        snprintf(msg, cap, "no memory for a %llu-byte file", (unsigned long long)size);
        return VSV_ENOMEM;
    }
    return 0;
}

int vsv_http_cache_open(vsv_http_cache *c, const char *dir, uint64_t max, const char *url, const vsv_http_ident *id,
                        char *msg, size_t cap)
{
    memset(c, 0, sizeof *c);
    c->fd = c->meta_fd = -1;
    c->max = max;
    c->nblocks = (size_t)((id->size + VSV_HTTP_BLOCK - 1) / VSV_HTTP_BLOCK);
    c->have = calloc(c->nblocks ? c->nblocks : 1, 1);
    if (!c->have) {
        snprintf(msg, cap, "out of memory");
        return VSV_ENOMEM;
    }
    char failed[4096];
    if (!dir || !dir[0] || !strcmp(dir, "off") || strlen(dir) >= sizeof failed || mkdirs(dir, failed, sizeof failed))
        return memory_only(c, id->size, msg, cap);
    char why[300];
    if (own_dir(dir, why, sizeof why)) {
        snprintf(msg, cap, "cache folder %s: %s", dir, why);
        return VSV_EINVAL;
    }
    snprintf(c->dir, sizeof c->dir, "%s", dir);
    const unsigned long long key = (unsigned long long)fnv1a(url);
    snprintf(c->data_path, sizeof c->data_path, "%s/%016llx.data", dir, key);
    snprintf(c->meta_path, sizeof c->meta_path, "%s/%016llx.meta", dir, key);
    c->fd = open(c->data_path, O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0600);
    struct stat st;
    if (c->fd >= 0 && (fstat(c->fd, &st) || !S_ISREG(st.st_mode) || st.st_uid != geteuid() || st.st_nlink != 1)) {
        close(c->fd); /* not a plain file of ours alone: left as it is */
        c->fd = -1;
    }
    if (c->fd < 0 || flock(c->fd, LOCK_EX | LOCK_NB))
        return memory_only(c, id->size, msg, cap); /* unwritable, or in use by another process */
    c->reused = fstat(c->fd, &st) == 0 && (uint64_t)st.st_size == id->size ? load_record(c, url, id) : 0;
    if (c->reused) {
        c->meta_fd = open(c->meta_path, O_RDWR | O_NOFOLLOW | O_CLOEXEC);
        utimensat(AT_FDCWD, c->meta_path, NULL, AT_SYMLINK_NOFOLLOW); /* used now */
        char head[4096 + 1024];
        record_head(head, sizeof head, url, id);
        c->head_len = strlen(head);
    } else { /* start empty: no record, no bytes, then an empty record */
        unlink(c->meta_path);
        if (ftruncate(c->fd, 0) || ftruncate(c->fd, (off_t)id->size) || (c->meta_fd = new_record(c, url, id)) < 0)
            return memory_only(c, id->size, msg, cap);
    }
    evict(c, 1);
    c->map = mmap(NULL, id->size, PROT_READ | PROT_WRITE, MAP_SHARED, c->fd, 0);
    if (c->map == MAP_FAILED) {
        c->map = NULL;
        memset(c->have, 0, c->nblocks);
        c->reused = 0;
        return memory_only(c, id->size, msg, cap);
    }
    return 0;
}

int vsv_http_cache_confirm(vsv_http_cache *c, const char *url, const vsv_http_ident *id, const unsigned char *p,
                           size_t n, char *msg, size_t cap)
{
    if (!c->reused || c->fd < 0)
        return 0;
    unsigned char *mine = malloc(n ? n : 1);
    const int same = mine && c->have[0] && pread(c->fd, mine, n, 0) == (ssize_t)n && !memcmp(mine, p, n);
    free(mine);
    if (same)
        return 0;
    /* another file under the same validators: nothing of the entry is its */
    memset(c->have, 0, c->nblocks);
    c->reused = 0;
    if (c->meta_fd >= 0)
        close(c->meta_fd);
    c->meta_fd = -1;
    unlink(c->meta_path);
    if (ftruncate(c->fd, 0) || ftruncate(c->fd, (off_t)id->size)) {
        snprintf(msg, cap, "cannot empty the cache %s: %s (--cache-dir off reads without one)", c->data_path,
                 strerror(errno));
        return VSV_EIO;
    }
    c->meta_fd = new_record(c, url, id); /* none: the entry is not used again */
    const int rc = vsv_http_cache_put(c, 0, p, n, msg, cap);
    if (!rc) {
        __atomic_store_n(&c->have[0], 1, __ATOMIC_RELEASE);
        vsv_http_cache_mark(c, 0);
    }
    return rc;
}

void vsv_http_cache_mark(vsv_http_cache *c, size_t b)
{
    static const unsigned char one = 1;
    if (c->meta_fd >= 0 && pwrite(c->meta_fd, &one, 1, (off_t)(c->head_len + b)) != 1) {
        close(c->meta_fd); /* the record stops growing: what it says is still true */
        c->meta_fd = -1;
    }
}

/* Removes least recently used entries (by their record's time) until the
 * directory's data files fit c->max; entries in use elsewhere are kept, and
 * with spare, c's own. */
static void evict(vsv_http_cache *c, int spare)
{
    DIR *d = opendir(c->dir);
    if (!d)
        return;
    struct ent {
        char name[64];
        uint64_t bytes;
        struct timespec used;
    } *e = NULL;
    size_t n = 0, capn = 0;
    uint64_t total = 0;
    for (struct dirent *de; (de = readdir(d));) {
        const size_t len = strlen(de->d_name);
        if (len != 21 || strcmp(de->d_name + 16, ".data"))
            continue;
        char p[4096 + 64];
        struct stat st, sm;
        snprintf(p, sizeof p, "%s/%s", c->dir, de->d_name);
        if (stat(p, &st))
            continue;
        snprintf(p, sizeof p, "%s/%.16s.meta", c->dir, de->d_name);
        if (stat(p, &sm))
            sm.st_mtim = st.st_mtim;
        if (n == capn) {
            struct ent *g = realloc(e, (capn = capn ? 2 * capn : 16) * sizeof *e);
            if (!g)
                break;
            e = g;
        }
        snprintf(e[n].name, sizeof e[n].name, "%.16s", de->d_name);
        e[n].bytes = (uint64_t)st.st_blocks * 512;
        e[n].used = sm.st_mtim;
        total += e[n++].bytes;
    }
    closedir(d);
    while (total > c->max && n) {
        size_t old = 0;
        for (size_t i = 1; i < n; i++)
            if (e[i].used.tv_sec < e[old].used.tv_sec ||
                (e[i].used.tv_sec == e[old].used.tv_sec && e[i].used.tv_nsec < e[old].used.tv_nsec))
                old = i;
        char p[4096 + 64];
        snprintf(p, sizeof p, "%s/%s.data", c->dir, e[old].name);
        const int fd = open(p, O_RDWR | O_NOFOLLOW | O_CLOEXEC);
        const int own = !strcmp(p, c->data_path);
        if (fd >= 0 && !(own && spare) && (own || !flock(fd, LOCK_EX | LOCK_NB))) {
            snprintf(p, sizeof p, "%s/%s.meta", c->dir, e[old].name);
            unlink(p);
            snprintf(p, sizeof p, "%s/%s.data", c->dir, e[old].name);
            unlink(p);
            total -= e[old].bytes;
        }
        if (fd >= 0)
            close(fd);
        e[old] = e[--n];
    }
    free(e);
}

int vsv_http_cache_put(vsv_http_cache *c, uint64_t off, const unsigned char *p, size_t n, char *msg, size_t cap)
{
    if (c->fd < 0) {
        memcpy(c->map + off, p, n);
        return 0;
    }
    /* written, not copied into the shared mapping: a full disk is then an
     * error here, not a SIGBUS there */
    while (n) {
        const ssize_t w = pwrite(c->fd, p, n, (off_t)off);
        if (w <= 0) {
            snprintf(msg, cap, "cannot write the cache %s: %s (--cache-dir off reads without one)", c->data_path,
                     w < 0 ? strerror(errno) : "short write");
            return VSV_EIO;
        }
        p += w, off += (uint64_t)w, n -= (size_t)w;
    }
    return 0;
}

void vsv_http_cache_close(vsv_http_cache *c, const vsv_http_ident *id)
{
    if (c->map)
        munmap(c->map, id->size);
    if (c->fd >= 0) {
        if (c->stale) {
            unlink(c->meta_path);
            unlink(c->data_path);
        } else {
            evict(c, 0);
        }
        close(c->fd);
    }
    if (c->meta_fd >= 0)
        close(c->meta_fd);
    free(c->have);
    memset(c, 0, sizeof *c);
    c->fd = c->meta_fd = -1;
}
