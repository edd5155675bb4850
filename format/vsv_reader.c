/* vsv_reader.c — the memory-mapped .vsv reader. Open validates only the
 * fixed-size header, the metadata, the table of contents and the end marker,
 * so its cost does not grow with the amount of brick data; chunk indexes and
 * brick payloads are verified (CRC-32C) when first touched. */
#include "vsv_reader_internal.h"

#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

const char *vsv_file_error(const vsv_file *f) { return f ? f->err : "out of memory"; }
const vsv_meta *vsv_file_meta(const vsv_file *f) { return &f->meta; }
int64_t vsv_file_time(const vsv_file *f, int step)
{
    if (step < 0 || step >= f->nsteps)
        return 0;
    return (int64_t)vsv_rd64(f->toc + (size_t)step * VSV_TOC_ENTRY_SIZE + 16);
}
const vsv_quant *vsv_file_quant(const vsv_file *f, int s) { return s >= 0 && s < f->meta.nvars ? &f->quant[s] : NULL; }

int vsv_file_find_time(const vsv_file *f, int64_t time)
{
    int lo = 0, hi = f->nsteps - 1;
    while (lo <= hi) {
        int mid = lo + (hi - lo) / 2;
        int64_t t = vsv_file_time(f, mid);
        if (t == time)
            return mid;
        if (t < time)
            lo = mid + 1;
        else
            hi = mid - 1;
    }
    return VSV_ENOTFOUND;
}

void vsv_file_brick_box(const vsv_file *f, int b, int org[3], int ext[3]) { vsv_layout_box(&f->lay, b, org, ext); }

int vsv_file_fail(vsv_file *f, int rc, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsv_vmsg_path(f->err, sizeof f->err, f->name, fmt, ap);
    va_end(ap);
    return rc;
}

int vsv_all_zero(const unsigned char *p, size_t n, size_t *first)
{
    for (size_t i = 0; i < n; i++)
        if (p[i]) {
            *first = i;
            return 0;
        }
    return 1;
}

int vsv_head_is_vsv(const void *head, size_t n) { return n >= 8 && !memcmp(head, VSV_MAGIC, 8); }

static int parse(vsv_file *f)
{
    const unsigned char *d = f->data;
    const size_t n = f->size;
    /* a byte source fetches the header and what follows it in one request */
    int rc = vsv_file_need(f, 0, n < VSV_HEADER_SIZE ? n : VSV_HEADER_SIZE, 65536, f->err, sizeof f->err);
    if (rc)
        return rc;
    if (!vsv_head_is_vsv(d, n))
        return vsv_file_fail(f, VSV_ENOTVSV, "not a .vsv file (no .vsv magic at byte 0)");
    if (n < VSV_HEADER_SIZE)
        return vsv_file_fail(f, VSV_ETRUNC, "truncated: %zu bytes, shorter than the %d-byte header", n,
                             VSV_HEADER_SIZE);
    if (vsv_rd16(d + 8) < 1 || vsv_rd16(d + 8) > VSV_FORMAT_MAJOR)
        return vsv_file_fail(f, VSV_EVERSION, "format version %u.%u is not readable by this version (1.x to %d.x)",
                             vsv_rd16(d + 8), vsv_rd16(d + 10), VSV_FORMAT_MAJOR);
    f->major = vsv_rd16(d + 8);
    f->minor = vsv_rd16(d + 10);
    if (vsv_crc32c(0, d, 124) != vsv_rd32(d + 124))
        return vsv_file_fail(f, VSV_ECORRUPT, "header checksum mismatch (bytes 0-127)");
    size_t z;
    if (vsv_rd32(d + 12) != VSV_HEADER_SIZE || vsv_rd32(d + 96) != 0 || !vsv_all_zero(d + 100, 24, &z))
        return vsv_file_fail(f, VSV_ECORRUPT, "header has unknown size or non-zero reserved fields");
    const uint64_t fsize = vsv_rd64(d + 16);
    if (fsize > n)
        return vsv_file_fail(f, VSV_ETRUNC, "truncated: file has %zu bytes, header says %llu", n,
                             (unsigned long long)fsize);
    if (fsize < n)
        return vsv_file_fail(f, VSV_ECORRUPT,
                             "%llu unexpected bytes after the end marker (file %zu bytes, header says %llu)",
                             (unsigned long long)(n - fsize), n, (unsigned long long)fsize);
    const uint64_t meta_off = vsv_rd64(d + 24), meta_size = vsv_rd64(d + 32);
    const uint64_t toc_off = vsv_rd64(d + 48), toc_size = vsv_rd64(d + 56);
    const uint32_t nsteps = vsv_rd32(d + 44), nspec = vsv_rd32(d + 68);
    if (n < VSV_HEADER_SIZE + VSV_TRAILER_SIZE)
        return vsv_file_fail(f, VSV_ETRUNC, "truncated: no room for the end marker");
    /* the table of contents and the end marker after it, in one piece where
     * the header places them so (checked below) */
    const int toc_fits = nsteps <= VSV_MAX_STEPS && toc_size == (uint64_t)nsteps * VSV_TOC_ENTRY_SIZE &&
                         toc_off <= n - VSV_TRAILER_SIZE && toc_size == n - VSV_TRAILER_SIZE - toc_off;
    if ((rc = toc_fits ? vsv_file_need(f, toc_off, toc_size + VSV_TRAILER_SIZE, 0, f->err, sizeof f->err)
                       : vsv_file_need(f, n - VSV_TRAILER_SIZE, VSV_TRAILER_SIZE, 0, f->err, sizeof f->err)))
        return rc;
    const unsigned char *tr = d + n - VSV_TRAILER_SIZE;
    if (memcmp(tr, VSV_END_MAGIC, 8) || vsv_crc32c(0, tr, 28) != vsv_rd32(tr + 28))
        return vsv_file_fail(f, VSV_ECORRUPT, "end marker damaged at offset %zu", n - VSV_TRAILER_SIZE);
    if (vsv_rd64(tr + 8) != toc_off || vsv_rd64(tr + 16) != fsize || vsv_rd32(tr + 24) != vsv_rd32(d + 64))
        return vsv_file_fail(f, VSV_ECORRUPT, "end marker disagrees with the header");
    /* The layout rule (SPEC.md §2): header, metadata, padding, chunks, table
     * of contents and end marker follow one another in that order, each inside
     * the file, none overlapping the next; checked here before any of them is
     * read, with no sum that can wrap. */
    if (meta_off != VSV_HEADER_SIZE || meta_size > n || meta_size > VSV_MAX_META || meta_size % 8 ||
        meta_off + meta_size > n - VSV_TRAILER_SIZE)
        return vsv_file_fail(f, VSV_ECORRUPT,
                             "metadata section (offset %llu, %llu bytes) outside the file or not a multiple of 8",
                             (unsigned long long)meta_off, (unsigned long long)meta_size);
    if ((rc = vsv_file_need(f, meta_off, meta_size, 0, f->err, sizeof f->err)))
        return rc;
    if (vsv_crc32c(0, d + meta_off, meta_size) != vsv_rd32(d + 40))
        return vsv_file_fail(f, VSV_ECORRUPT, "metadata checksum mismatch (offset %llu, %llu bytes)",
                             (unsigned long long)meta_off, (unsigned long long)meta_size);
    if (nsteps < 1 || nsteps > VSV_MAX_STEPS || toc_size != (uint64_t)nsteps * VSV_TOC_ENTRY_SIZE || toc_off % 8 ||
        toc_off > n || toc_size > n || toc_off + toc_size != n - VSV_TRAILER_SIZE)
        return vsv_file_fail(f, VSV_ECORRUPT, "table of contents (offset %llu, %u steps) does not fit the file",
                             (unsigned long long)toc_off, nsteps);
    if (toc_off < vsv_align_up(meta_off + meta_size, VSV_ALIGN))
        return vsv_file_fail(
            f, VSV_ECORRUPT,
            "table of contents (offset %llu) overlaps the metadata and its padding (offsets 128 to %llu)",
            (unsigned long long)toc_off, (unsigned long long)vsv_align_up(meta_off + meta_size, VSV_ALIGN));
    /* checked and used as one copy: what was checked is what is used */
    if (!(f->toc = malloc(toc_size)))
        return vsv_file_fail(f, VSV_ENOMEM, "out of memory");
    memcpy(f->toc, d + toc_off, toc_size);
    if (vsv_crc32c(0, f->toc, toc_size) != vsv_rd32(d + 64))
        return vsv_file_fail(f, VSV_ECORRUPT, "table of contents checksum mismatch (offset %llu)",
                             (unsigned long long)toc_off);
    char msg[300];
    rc = vsv_meta_decode(d + meta_off, meta_size, &f->meta, &f->quant, msg, sizeof msg);
    if (rc)
        return vsv_file_fail(f, rc == VSV_ENOMEM ? rc : VSV_ECORRUPT, "metadata: %s", msg);
    const uint32_t brick = vsv_rd32(d + 84), key = vsv_rd32(d + 88), codec = vsv_rd32(d + 92);
    if (nspec != (uint32_t)f->meta.nvars || vsv_rd32(d + 72) != (uint32_t)f->meta.nx ||
        vsv_rd32(d + 76) != (uint32_t)f->meta.ny || vsv_rd32(d + 80) != (uint32_t)f->meta.nz)
        return vsv_file_fail(f, VSV_ECORRUPT, "header dimensions disagree with the metadata");
    if ((brick != 8 && brick != 16 && brick != 32 && brick != 64) || key < 1 || key > 65535 ||
        (codec != VSV_CODEC_NONE && codec != VSV_CODEC_ZSTD))
        return vsv_file_fail(f, VSV_ECORRUPT, "header: brick %u, keyframe %u or codec %u invalid", brick, key, codec);
    if (vsv_layout_init(&f->lay, f->meta.nx, f->meta.ny, f->meta.nz, (int)brick))
        return vsv_file_fail(f, VSV_ECORRUPT, "grid too large for the octree");
    f->nsteps = (int)nsteps;
    f->keyframe = (int)key;
    f->codec = (int)codec;
    f->toc_off = toc_off;
    f->meta_end = meta_off + meta_size;
    const uint64_t index_bytes = (uint64_t)nspec * f->lay.species_index_bytes;
    if (index_bytes > UINT32_MAX)
        return vsv_file_fail(f, VSV_ECORRUPT,
                             "a chunk index of %llu bytes (%u species of %d bricks) exceeds the 32-bit limit",
                             (unsigned long long)index_bytes, nspec, f->lay.nbricks);
    uint64_t expect = vsv_align_up(f->meta_end, VSV_ALIGN); /* <= toc_off, checked above */
    int64_t last_time = 0;
    for (uint32_t t = 0; t < nsteps; t++) {
        const unsigned char *e = f->toc + (size_t)t * VSV_TOC_ENTRY_SIZE;
        const uint64_t off = vsv_rd64(e), size = vsv_rd64(e + 8);
        const int64_t time = (int64_t)vsv_rd64(e + 16);
        /* off == expect <= toc_off, so toc_off - off cannot wrap */
        if (off != expect || size % VSV_ALIGN || size < VSV_CHUNK_HEADER_SIZE + index_bytes || size > toc_off - off)
            return vsv_file_fail(f, VSV_ECORRUPT, "table of contents entry %u: chunk at %llu (%llu bytes) out of place",
                                 t, (unsigned long long)off, (unsigned long long)size);
        if (!VSV_TIME_OK(time))
            return vsv_file_fail(f, VSV_ECORRUPT, "table of contents entry %u: time %lld is outside the years 1..9999",
                                 t, (long long)time);
        if (t && time <= last_time)
            return vsv_file_fail(f, VSV_ECORRUPT, "table of contents entry %u: time does not increase", t);
        last_time = time;
        expect = off + size;
    }
    if (expect != toc_off)
        return vsv_file_fail(f, VSV_ECORRUPT, "%llu unaccounted bytes before the table of contents",
                             (unsigned long long)(toc_off - expect));
    f->chunk_ok = calloc(nsteps, 1);
    f->lut = calloc(nspec, sizeof *f->lut);
    if (f->src && !(f->span_end = calloc((size_t)nsteps * nspec, sizeof *f->span_end)))
        return vsv_file_fail(f, VSV_ENOMEM, "out of memory");
    if (!f->chunk_ok || !f->lut)
        return vsv_file_fail(f, VSV_ENOMEM, "out of memory");
    return 0;
}

static vsv_file *file_new(const char *name)
{
    vsv_file *f = calloc(1, sizeof *f);
    if (!f)
        return NULL;
    snprintf(f->name, sizeof f->name, "%s", name ? name : "(memory)");
    vsv_meta_init(&f->meta);
    pthread_mutex_init(&f->lock, NULL);
    f->uid = vsv_volume_new_gen();
    f->map.fd = f->map.guard = -1;
    return f;
}

int vsv_file_open_mem(const void *data, size_t size, const char *name, vsv_file **out)
{
    vsv_file *f = *out = file_new(name);
    if (!f)
        return VSV_ENOMEM;
    f->data = data;
    f->size = size;
    return parse(f);
}

int vsv_file_open_source(vsv_byte_source *src, const char *name, vsv_file **out)
{
    vsv_file *f = *out = file_new(name);
    if (!f) {
        src->close(src);
        return VSV_ENOMEM;
    }
    f->src = src;
    f->data = src->base;
    f->size = (size_t)src->size;
    if ((uint64_t)f->size != src->size)
        return vsv_file_fail(f, VSV_EUNSUPPORTED, "%llu bytes: too large for this machine's address space",
                             (unsigned long long)src->size);
    /* a source's bytes may be a mapped file too (the HTTP cache's): a
     * truncation of it is then an error here, not a SIGBUS */
    f->map.guard = vsv_mapguard_add(f->data, f->size);
    return vsv_file_cut(f, parse(f), f->err, sizeof f->err);
}

int vsv_file_open(const char *path, vsv_file **out)
{
    vsv_file *f = *out = file_new(path);
    if (!f)
        return VSV_ENOMEM;
    char why[160];
    const int rc = vsv_input_map(path, 1, &f->map, why, sizeof why);
    if (rc < 0 && strstr(path, "://") && access(path, F_OK)) /* ftp://, s3:// ... */
        return vsv_file_fail(f, VSV_EIO, "no such file; of URLs, only http:// and https:// ones are read");
    if (rc < 0)
        return vsv_file_fail(f, VSV_EIO, "%s", why);
    if (rc > 0)
        return vsv_file_fail(f, VSV_ENOTVSV, "not a .vsv file (empty)");
    f->data = f->map.data;
    f->size = f->map.n;
    return vsv_file_cut(f, parse(f), f->err, sizeof f->err);
}

int vsv_file_cut(const vsv_file *f, int rc, char *msg, size_t cap)
{
    return vsv_file_cut_look(f, rc, rc != 0, msg, cap);
}

int vsv_file_cut_look(const vsv_file *f, int rc, int look, char *msg, size_t cap)
{
    if (!vsv_input_cut(&f->map, look))
        return rc;
    vsv_msg(msg, cap, "%s: %s", f->name, f->src ? "truncated while reading (its cached copy shrank)" : VSV_CUT_TEXT);
    return VSV_ETRUNC;
}

int vsv_file_chunk_resident(const vsv_file *f, int step)
{
    return step >= 0 && step < f->nsteps &&
           (!f->src || (f->chunk_ok && __atomic_load_n(&f->chunk_ok[step], __ATOMIC_ACQUIRE) == 1));
}

int vsv_file_chunk_fetch(vsv_file *f, int step, char *msg, size_t cap)
{
    const int rc = vsv_file_check_args(f, step, 0, 0, msg, cap);
    if (rc)
        return rc;
    return vsv_file_chunk_index(f, step, msg, cap) ? 0 : vsv_file_chunk_rc(f, msg, cap);
}

void vsv_file_interrupt(vsv_file *f)
{
    if (f && f->src && f->src->interrupt)
        f->src->interrupt(f->src);
}

void vsv_file_free(vsv_file *f)
{
    if (!f)
        return;
    vsv_input_unmap(&f->map);
    if (f->src)
        f->src->close(f->src);
    free(f->span_end);
    if (f->lut)
        for (int s = 0; s < f->meta.nvars; s++)
            free(f->lut[s]);
    free(f->lut);
    free(f->chunk_ok);
    free(f->toc);
    free(f->quant);
    vsv_meta_clear(&f->meta);
    pthread_mutex_destroy(&f->lock);
    free(f);
}

/* --------------------------------------------------------------- chunks */

static const unsigned char *chunk_index(vsv_file *f, int t, char *msg, size_t cap);

/* Why this thread's last vsv_file_chunk_index failed: a byte source's code,
 * or 0 (the index itself). */
static __thread int chunk_rc;

int vsv_file_chunk_rc(const vsv_file *f, char *msg, size_t cap)
{
    return vsv_file_cut(f, chunk_rc ? chunk_rc : VSV_ECORRUPT, msg, cap);
}

/* Verified index of chunk t (header included), or NULL with f->err / msg set:
 * the zeros a truncation leaves (vsv_mapguard.c) fail its checks, and the
 * message then says why. */
const unsigned char *vsv_file_chunk_index(vsv_file *f, int t, char *msg, size_t cap)
{
    chunk_rc = 0;
    const unsigned char *c = vsv_file_cut(f, 0, msg, cap) ? NULL : chunk_index(f, t, msg, cap);
    if (!c)
        vsv_file_cut(f, VSV_ECORRUPT, msg, cap);
    return c;
}

/* 0 if chunk t's header and index are sound, 1 for a bad header, 2 for a
 * checksum mismatch. */
static int index_bad(const vsv_file *f, const unsigned char *c, int t, const unsigned char *e, size_t index_bytes)
{
    if (memcmp(c, "VCHK", 4) || vsv_rd32(c + 4) != (uint32_t)t || vsv_rd64(c + 8) != vsv_rd64(e + 16) ||
        vsv_rd32(c + 16) != index_bytes || vsv_rd32(c + 20) != (uint32_t)f->meta.nvars || vsv_rd32(c + 24) != 0)
        return 1;
    uint32_t crc = vsv_crc32c(0, c, 28);
    crc = vsv_crc32c(crc, c + VSV_CHUNK_HEADER_SIZE, index_bytes);
    return crc != vsv_rd32(c + 28) ? 2 : 0;
}

static const unsigned char *chunk_index(vsv_file *f, int t, char *msg, size_t cap)
{
    const unsigned char *e = f->toc + (size_t)t * VSV_TOC_ENTRY_SIZE;
    const unsigned char *c = f->data + vsv_rd64(e);
    if (__atomic_load_n(&f->chunk_ok[t], __ATOMIC_ACQUIRE))
        return c;
    const size_t index_bytes = (size_t)f->meta.nvars * f->lay.species_index_bytes;
    if ((chunk_rc = vsv_file_need(f, vsv_rd64(e), VSV_CHUNK_HEADER_SIZE + index_bytes, 0, msg, cap)))
        return NULL;
    int bad = index_bad(f, c, t, e, index_bytes);
    if (bad && vsv_file_refetch(f, vsv_rd64(e), VSV_CHUNK_HEADER_SIZE + index_bytes))
        bad = index_bad(f, c, t, e, index_bytes); /* a damaged cache, fetched again */
    if (bad) {
        vsv_msg(msg, cap, "%s: chunk %d (offset %llu): %s", f->name, t, (unsigned long long)vsv_rd64(e),
                bad == 1 ? "bad chunk header" : "index checksum mismatch");
        return NULL;
    }
    /* structural rules of the brick tables, once per chunk */
    const uint64_t csize = vsv_rd64(e + 8);
    uint64_t expect = vsv_align_up(VSV_CHUNK_HEADER_SIZE + index_bytes, VSV_ALIGN);
    const int key = t % f->keyframe == 0;
    for (int s = 0; s < f->meta.nvars; s++) {
        const unsigned char *tab =
            c + VSV_CHUNK_HEADER_SIZE + (size_t)s * f->lay.species_index_bytes + f->lay.octree_bytes;
        for (int b = 0; b < f->lay.nbricks; b++) {
            int org[3], ext[3];
            vsv_layout_box(&f->lay, b, org, ext);
            const size_t raw = vsv_brick_raw_bytes(f->quant[s].bits, ext);
            const unsigned char *be = tab + (size_t)b * VSV_BRICK_ENTRY_SIZE;
            const int kind = be[0];
            const uint64_t off = vsv_rd64(be + 8);
            const uint32_t size = vsv_rd32(be + 16);
            /* the 3-D kinds from format 2, the Rice-coded from 4; a keyframe holds absolute kinds */
            int ok = kind <= vsv_file_last_kind(f) && !be[1] && !be[2] && !be[3] && !vsv_rd32(be + 20) &&
                     !(key && !vsv_brick_absolute(kind));
            if (vsv_brick_stored(kind)) {
                ok = ok && off == expect && size > 0 && size <= csize - off &&
                     (f->codec == VSV_CODEC_ZSTD || kind >= VSV_BRICK_ABS3R || size == raw);
                expect = vsv_align_up(off + size, VSV_ALIGN);
            } else {
                ok = ok && !off && !size && !vsv_rd32(be + 4);
            }
            if (!ok) {
                vsv_msg(msg, cap, "%s: chunk %d, species %d, brick %d (offset %llu): invalid brick entry", f->name, t,
                        s, b, (unsigned long long)(be - f->data));
                return NULL;
            }
        }
        if (f->span_end)
            __atomic_store_n(&f->span_end[(size_t)t * f->meta.nvars + s], vsv_rd64(e) + expect, __ATOMIC_RELAXED);
    }
    if (expect != csize) {
        vsv_msg(msg, cap, "%s: chunk %d (offset %llu): payloads end at %llu of %llu bytes", f->name, t,
                (unsigned long long)vsv_rd64(e), (unsigned long long)expect, (unsigned long long)csize);
        return NULL;
    }
    __atomic_store_n(&f->chunk_ok[t], 1, __ATOMIC_RELEASE);
    return c;
}

const unsigned char *vsv_file_brick_entry(const vsv_file *f, const unsigned char *c, int s, int b)
{
    return c + VSV_CHUNK_HEADER_SIZE + (size_t)s * f->lay.species_index_bytes + f->lay.octree_bytes +
           (size_t)b * VSV_BRICK_ENTRY_SIZE;
}

int vsv_file_check_args(vsv_file *f, int step, int s, int b, char *msg, size_t cap)
{
    if (step < 0 || step >= f->nsteps || s < 0 || s >= f->meta.nvars || b < 0 || b >= f->lay.nbricks) {
        vsv_msg(msg, cap, "%s: step %d, species %d, brick %d out of range", f->name, step, s, b);
        return VSV_ERANGE;
    }
    return 0;
}

/* A failure of a call threads may make on one handle at once: its message
 * into f->err under the handle's lock (vsv_file_error reads it after). */
static void shared_fail(vsv_file *f, const char *msg)
{
    pthread_mutex_lock(&f->lock);
    snprintf(f->err, sizeof f->err, "%s", msg);
    pthread_mutex_unlock(&f->lock);
}

int vsv_file_brick_kind(vsv_file *f, int step, int s, int b)
{
    char msg[sizeof f->err];
    int rc = vsv_file_check_args(f, step, s, b, msg, sizeof msg);
    if (rc) {
        shared_fail(f, msg);
        return rc;
    }
    const unsigned char *c = vsv_file_chunk_index(f, step, msg, sizeof msg);
    if (c) { /* read from the mapping: a cut meanwhile made it a zero */
        const int kind = vsv_file_brick_entry(f, c, s, b)[0];
        if (!(rc = vsv_file_cut_look(f, 0, kind == VSV_BRICK_EMPTY, msg, sizeof msg)))
            return kind;
    } else {
        rc = vsv_file_chunk_rc(f, msg, sizeof msg);
    }
    shared_fail(f, msg);
    return rc;
}

const unsigned char *vsv_file_octree(vsv_file *f, int step, int s, int *dims)
{
    char msg[sizeof f->err];
    const unsigned char *c =
        vsv_file_check_args(f, step, s, 0, msg, sizeof msg) ? NULL : vsv_file_chunk_index(f, step, msg, sizeof msg);
    if (!c) {
        shared_fail(f, msg);
        return NULL;
    }
    if (dims)
        for (int L = 0; L < f->lay.levels; L++)
            for (int a = 0; a < 3; a++)
                dims[3 * L + a] = f->lay.ldim[L][a];
    return c + VSV_CHUNK_HEADER_SIZE + (size_t)s * f->lay.species_index_bytes;
}

void vsv_octree_node(const unsigned char *nodes, size_t n, unsigned *min, unsigned *max)
{
    *min = vsv_rd16(nodes + 4 * n);
    *max = vsv_rd16(nodes + 4 * n + 2);
}

size_t vsv_file_octree_level_start(const vsv_file *f, int level)
{
    return level >= 0 && level <= f->lay.levels ? f->lay.lstart[level] : 0;
}

/* Counts stored / non-empty bricks and payload bytes: one pass over the chunk
 * indexes, done once, for vsv-info. */
void vsv_file_count(vsv_file *f, vsv_file_counts *out)
{
    pthread_mutex_lock(&f->lock);
    if (!f->counted) {
        char msg[512];
        for (int t = 0; t < f->nsteps; t++) {
            const unsigned char *c = vsv_file_chunk_index(f, t, msg, sizeof msg);
            if (!c) { /* counted and reported, never silently fewer bricks */
                if (!f->damaged++)
                    snprintf(f->err, sizeof f->err, "%s", msg);
                continue;
            }
            for (int s = 0; s < f->meta.nvars; s++) {
                const unsigned char *oct = c + VSV_CHUNK_HEADER_SIZE + (size_t)s * f->lay.species_index_bytes;
                for (int b = 0; b < f->lay.nbricks; b++) {
                    const unsigned char *be = vsv_file_brick_entry(f, c, s, b);
                    if (vsv_brick_stored(be[0])) {
                        f->stored++;
                        f->rice += be[0] >= VSV_BRICK_ABS3R;
                        f->payload += vsv_rd32(be + 16);
                    }
                    if (vsv_rd16(oct + 4 * (size_t)b + 2) > 0)
                        f->nonempty++;
                }
            }
        }
        /* zeros read past a new end would have counted as empty bricks */
        if (vsv_file_cut_look(f, 0, 1, f->err, sizeof f->err))
            f->damaged++;
        f->counted = 1;
    }
    out->stored_bricks = f->stored;
    out->rice_bricks = f->rice;
    out->nonempty_bricks = f->nonempty;
    out->payload_bytes = f->payload;
    out->damaged_chunks = f->damaged;
    pthread_mutex_unlock(&f->lock);
}

void vsv_file_info_get(const vsv_file *f, vsv_file_info *info)
{
    memset(info, 0, sizeof *info);
    info->major = f->major;
    info->minor = f->minor;
    info->nsteps = f->nsteps;
    info->nspecies = f->meta.nvars;
    info->brick = f->lay.brick;
    for (int a = 0; a < 3; a++)
        info->bricks[a] = f->lay.bdim[a];
    info->nbricks = f->lay.nbricks;
    info->keyframe = f->keyframe;
    info->codec = f->codec;
    info->octree_levels = f->lay.levels;
    info->file_bytes = f->size;
}
