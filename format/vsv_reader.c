/* vsv_reader.c — the memory-mapped .vsv reader. Open validates only the
 * fixed-size header, the metadata, the table of contents and the end marker,
 * so its cost does not grow with the amount of brick data; chunk indexes and
 * brick payloads are verified (CRC-32C) when first touched. */
#include "vsv_format_internal.h"
#include "vsv_layout.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zstd.h>

struct vsv_file {
    const unsigned char *data;
    size_t size;
    int mapped;
    char name[256];
    char err[512];
    vsv_meta meta;
    vsv_quant *quant;
    vsv_layout lay;
    int nsteps, keyframe, codec;
    const unsigned char *toc;
    uint64_t meta_end, toc_off;
    signed char *chunk_ok; /* per step: 0 unchecked, 1 index verified */
    float **lut;           /* per species: 2^bits values, built on first use */
    pthread_mutex_t lock;
    int counted;
    uint64_t stored, nonempty, payload;
};

struct vsv_decoder {
    vsv_file *f;
    ZSTD_DCtx *dctx;
    unsigned char *raw;
    uint16_t *codes;
    uint16_t **state; /* per species: codes of all bricks at state_step */
    int *state_step;
    char err[512];
};

const char *vsv_file_error(const vsv_file *f) { return f ? f->err : "out of memory"; }
const vsv_meta *vsv_file_meta(const vsv_file *f) { return &f->meta; }
int64_t vsv_file_time(const vsv_file *f, int step)
{
    return (int64_t)vsv_rd64(f->toc + (size_t)step * VSV_TOC_ENTRY_SIZE + 16);
}
const vsv_quant *vsv_file_quant(const vsv_file *f, int s) { return &f->quant[s]; }

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

static int bad(vsv_file *f, int rc, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static int bad(vsv_file *f, int rc, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsv_vmsg_path(f->err, sizeof f->err, f->name, fmt, ap);
    va_end(ap);
    return rc;
}

static int all_zero(const unsigned char *p, size_t n, size_t *first)
{
    for (size_t i = 0; i < n; i++)
        if (p[i]) {
            *first = i;
            return 0;
        }
    return 1;
}

static int parse(vsv_file *f)
{
    const unsigned char *d = f->data;
    const size_t n = f->size;
    if (n < 8 || memcmp(d, VSV_MAGIC, 8))
        return bad(f, VSV_ENOTVSV, "not a .vsv file (no .vsv magic at byte 0)");
    if (n < VSV_HEADER_SIZE)
        return bad(f, VSV_ETRUNC, "truncated: %zu bytes, shorter than the %d-byte header", n, VSV_HEADER_SIZE);
    if (vsv_rd16(d + 8) != VSV_FORMAT_MAJOR)
        return bad(f, VSV_EVERSION, "format version %u.%u is not readable by this version (%d.x)", vsv_rd16(d + 8),
                   vsv_rd16(d + 10), VSV_FORMAT_MAJOR);
    if (vsv_crc32c(0, d, 124) != vsv_rd32(d + 124))
        return bad(f, VSV_ECORRUPT, "header checksum mismatch (bytes 0-127)");
    size_t z;
    if (vsv_rd32(d + 12) != VSV_HEADER_SIZE || vsv_rd32(d + 96) != 0 || !all_zero(d + 100, 24, &z))
        return bad(f, VSV_ECORRUPT, "header has unknown size or non-zero reserved fields");
    const uint64_t fsize = vsv_rd64(d + 16);
    if (fsize > n)
        return bad(f, VSV_ETRUNC, "truncated: file has %zu bytes, header says %llu", n, (unsigned long long)fsize);
    if (fsize < n)
        return bad(f, VSV_ECORRUPT, "%llu unexpected bytes after the end marker (file %zu bytes, header says %llu)",
                   (unsigned long long)(n - fsize), n, (unsigned long long)fsize);
    const uint64_t meta_off = vsv_rd64(d + 24), meta_size = vsv_rd64(d + 32);
    const uint64_t toc_off = vsv_rd64(d + 48), toc_size = vsv_rd64(d + 56);
    const uint32_t nsteps = vsv_rd32(d + 44), nspec = vsv_rd32(d + 68);
    if (n < VSV_HEADER_SIZE + VSV_TRAILER_SIZE)
        return bad(f, VSV_ETRUNC, "truncated: no room for the end marker");
    const unsigned char *tr = d + n - VSV_TRAILER_SIZE;
    if (memcmp(tr, VSV_END_MAGIC, 8) || vsv_crc32c(0, tr, 28) != vsv_rd32(tr + 28))
        return bad(f, VSV_ECORRUPT, "end marker damaged at offset %zu", n - VSV_TRAILER_SIZE);
    if (vsv_rd64(tr + 8) != toc_off || vsv_rd64(tr + 16) != fsize || vsv_rd32(tr + 24) != vsv_rd32(d + 64))
        return bad(f, VSV_ECORRUPT, "end marker disagrees with the header");
    if (meta_off != VSV_HEADER_SIZE || meta_size > n || meta_size > VSV_MAX_META ||
        meta_off + meta_size > n - VSV_TRAILER_SIZE)
        return bad(f, VSV_ECORRUPT, "metadata section (offset %llu, %llu bytes) outside the file",
                   (unsigned long long)meta_off, (unsigned long long)meta_size);
    if (vsv_crc32c(0, d + meta_off, meta_size) != vsv_rd32(d + 40))
        return bad(f, VSV_ECORRUPT, "metadata checksum mismatch (offset %llu, %llu bytes)",
                   (unsigned long long)meta_off, (unsigned long long)meta_size);
    if (nsteps < 1 || nsteps > VSV_MAX_STEPS || toc_size != (uint64_t)nsteps * VSV_TOC_ENTRY_SIZE ||
        toc_off % 8 || toc_off > n || toc_off + toc_size != n - VSV_TRAILER_SIZE)
        return bad(f, VSV_ECORRUPT, "table of contents (offset %llu, %u steps) does not fit the file",
                   (unsigned long long)toc_off, nsteps);
    if (vsv_crc32c(0, d + toc_off, toc_size) != vsv_rd32(d + 64))
        return bad(f, VSV_ECORRUPT, "table of contents checksum mismatch (offset %llu)", (unsigned long long)toc_off);
    char msg[300];
    int rc = vsv_meta_decode(d + meta_off, meta_size, &f->meta, &f->quant, msg, sizeof msg);
    if (rc)
        return bad(f, rc == VSV_ENOMEM ? rc : VSV_ECORRUPT, "metadata: %s", msg);
    const uint32_t brick = vsv_rd32(d + 84), key = vsv_rd32(d + 88), codec = vsv_rd32(d + 92);
    if (nspec != (uint32_t)f->meta.nvars || vsv_rd32(d + 72) != (uint32_t)f->meta.nx ||
        vsv_rd32(d + 76) != (uint32_t)f->meta.ny || vsv_rd32(d + 80) != (uint32_t)f->meta.nz)
        return bad(f, VSV_ECORRUPT, "header dimensions disagree with the metadata");
    if ((brick != 8 && brick != 16 && brick != 32 && brick != 64) || key < 1 || key > 65535 ||
        (codec != VSV_CODEC_NONE && codec != VSV_CODEC_ZSTD))
        return bad(f, VSV_ECORRUPT, "header: brick %u, keyframe %u or codec %u invalid", brick, key, codec);
    if (vsv_layout_init(&f->lay, f->meta.nx, f->meta.ny, f->meta.nz, (int)brick))
        return bad(f, VSV_ECORRUPT, "grid too large for the octree");
    f->nsteps = (int)nsteps;
    f->keyframe = (int)key;
    f->codec = (int)codec;
    f->toc = d + toc_off;
    f->toc_off = toc_off;
    f->meta_end = meta_off + meta_size;
    const uint64_t index_bytes = (uint64_t)nspec * f->lay.species_index_bytes;
    uint64_t expect = vsv_align_up(f->meta_end, VSV_ALIGN);
    int64_t last_time = 0;
    for (uint32_t t = 0; t < nsteps; t++) {
        const unsigned char *e = f->toc + (size_t)t * VSV_TOC_ENTRY_SIZE;
        const uint64_t off = vsv_rd64(e), size = vsv_rd64(e + 8);
        const int64_t time = (int64_t)vsv_rd64(e + 16);
        if (off != expect || size % VSV_ALIGN || size < VSV_CHUNK_HEADER_SIZE + index_bytes || size > toc_off - off)
            return bad(f, VSV_ECORRUPT, "table of contents entry %u: chunk at %llu (%llu bytes) out of place", t,
                       (unsigned long long)off, (unsigned long long)size);
        if (t && time <= last_time)
            return bad(f, VSV_ECORRUPT, "table of contents entry %u: time does not increase", t);
        last_time = time;
        expect = off + size;
    }
    if (expect != toc_off)
        return bad(f, VSV_ECORRUPT, "%llu unaccounted bytes before the table of contents",
                   (unsigned long long)(toc_off - expect));
    f->chunk_ok = calloc(nsteps, 1);
    f->lut = calloc(nspec, sizeof *f->lut);
    if (!f->chunk_ok || !f->lut)
        return bad(f, VSV_ENOMEM, "out of memory");
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

int vsv_file_open(const char *path, vsv_file **out)
{
    vsv_file *f = *out = file_new(path);
    if (!f)
        return VSV_ENOMEM;
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return bad(f, VSV_EIO, "cannot open: %s", strerror(errno));
    struct stat st;
    if (fstat(fd, &st) || !S_ISREG(st.st_mode)) {
        close(fd);
        return bad(f, VSV_EIO, "not a regular file");
    }
    f->size = (size_t)st.st_size;
    if (f->size == 0) {
        close(fd);
        return bad(f, VSV_ENOTVSV, "not a .vsv file (empty)");
    }
    void *p = mmap(NULL, f->size, PROT_READ, MAP_SHARED, fd, 0);
    close(fd);
    if (p == MAP_FAILED)
        return bad(f, VSV_EIO, "cannot map: %s", strerror(errno));
    f->data = p;
    f->mapped = 1;
    return parse(f);
}

void vsv_file_free(vsv_file *f)
{
    if (!f)
        return;
    if (f->mapped)
        munmap((void *)f->data, f->size);
    if (f->lut)
        for (int s = 0; s < f->meta.nvars; s++)
            free(f->lut[s]);
    free(f->lut);
    free(f->chunk_ok);
    free(f->quant);
    vsv_meta_clear(&f->meta);
    pthread_mutex_destroy(&f->lock);
    free(f);
}

/* --------------------------------------------------------------- chunks */

/* Verified index of chunk t (header included), or NULL with f->err / msg set. */
static const unsigned char *chunk_index(vsv_file *f, int t, char *msg, size_t cap)
{
    const unsigned char *e = f->toc + (size_t)t * VSV_TOC_ENTRY_SIZE;
    const unsigned char *c = f->data + vsv_rd64(e);
    if (__atomic_load_n(&f->chunk_ok[t], __ATOMIC_ACQUIRE))
        return c;
    const size_t index_bytes = (size_t)f->meta.nvars * f->lay.species_index_bytes;
    if (memcmp(c, "VCHK", 4) || vsv_rd32(c + 4) != (uint32_t)t || vsv_rd64(c + 8) != vsv_rd64(e + 16) ||
        vsv_rd32(c + 16) != index_bytes || vsv_rd32(c + 20) != (uint32_t)f->meta.nvars || vsv_rd32(c + 24) != 0) {
        vsv_msg(msg, cap, "%s: chunk %d (offset %llu): bad chunk header", f->name, t,
                (unsigned long long)vsv_rd64(e));
        return NULL;
    }
    uint32_t crc = vsv_crc32c(0, c, 28);
    crc = vsv_crc32c(crc, c + VSV_CHUNK_HEADER_SIZE, index_bytes);
    if (crc != vsv_rd32(c + 28)) {
        vsv_msg(msg, cap, "%s: chunk %d (offset %llu): index checksum mismatch", f->name, t,
                (unsigned long long)vsv_rd64(e));
        return NULL;
    }
    /* structural rules of the brick tables, once per chunk */
    const uint64_t csize = vsv_rd64(e + 8);
    uint64_t expect = vsv_align_up(VSV_CHUNK_HEADER_SIZE + index_bytes, VSV_ALIGN);
    const int key = t % f->keyframe == 0;
    for (int s = 0; s < f->meta.nvars; s++) {
        const unsigned char *tab = c + VSV_CHUNK_HEADER_SIZE + (size_t)s * f->lay.species_index_bytes + f->lay.octree_bytes;
        for (int b = 0; b < f->lay.nbricks; b++) {
            int org[3], ext[3];
            vsv_layout_box(&f->lay, b, org, ext);
            const size_t raw = vsv_brick_raw_bytes(f->quant[s].bits, ext);
            const unsigned char *be = tab + (size_t)b * VSV_BRICK_ENTRY_SIZE;
            const int kind = be[0];
            const uint64_t off = vsv_rd64(be + 8);
            const uint32_t size = vsv_rd32(be + 16);
            int ok = kind <= VSV_BRICK_DELTA && !be[1] && !be[2] && !be[3] && !vsv_rd32(be + 20) &&
                     !(key && (kind == VSV_BRICK_UNCHANGED || kind == VSV_BRICK_DELTA));
            if (kind == VSV_BRICK_ABS || kind == VSV_BRICK_DELTA) {
                ok = ok && off == expect && size > 0 && size <= csize - off &&
                     (f->codec == VSV_CODEC_ZSTD || size == raw);
                expect = vsv_align_up(off + size, VSV_ALIGN);
            } else {
                ok = ok && !off && !size && !vsv_rd32(be + 4);
            }
            if (!ok) {
                vsv_msg(msg, cap, "%s: chunk %d, species %d, brick %d (offset %llu): invalid brick entry", f->name,
                        t, s, b, (unsigned long long)(be - f->data));
                return NULL;
            }
        }
    }
    if (expect != csize) {
        vsv_msg(msg, cap, "%s: chunk %d (offset %llu): payloads end at %llu of %llu bytes", f->name, t,
                (unsigned long long)vsv_rd64(e), (unsigned long long)expect, (unsigned long long)csize);
        return NULL;
    }
    __atomic_store_n(&f->chunk_ok[t], 1, __ATOMIC_RELEASE);
    return c;
}

static const unsigned char *brick_entry(const vsv_file *f, const unsigned char *c, int s, int b)
{
    return c + VSV_CHUNK_HEADER_SIZE + (size_t)s * f->lay.species_index_bytes + f->lay.octree_bytes +
           (size_t)b * VSV_BRICK_ENTRY_SIZE;
}

static int check_args(vsv_file *f, int step, int s, int b, char *msg, size_t cap)
{
    if (step < 0 || step >= f->nsteps || s < 0 || s >= f->meta.nvars || b < 0 || b >= f->lay.nbricks) {
        vsv_msg(msg, cap, "%s: step %d, species %d, brick %d out of range", f->name, step, s, b);
        return VSV_ERANGE;
    }
    return 0;
}

int vsv_file_brick_kind(vsv_file *f, int step, int s, int b)
{
    int rc = check_args(f, step, s, b, f->err, sizeof f->err);
    if (rc)
        return rc;
    const unsigned char *c = chunk_index(f, step, f->err, sizeof f->err);
    return c ? brick_entry(f, c, s, b)[0] : VSV_ECORRUPT;
}

const unsigned char *vsv_file_octree(vsv_file *f, int step, int s, int *dims)
{
    if (check_args(f, step, s, 0, f->err, sizeof f->err))
        return NULL;
    const unsigned char *c = chunk_index(f, step, f->err, sizeof f->err);
    if (!c)
        return NULL;
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
static void count_bricks(vsv_file *f)
{
    pthread_mutex_lock(&f->lock);
    if (!f->counted) {
        char msg[256];
        for (int t = 0; t < f->nsteps; t++) {
            const unsigned char *c = chunk_index(f, t, msg, sizeof msg);
            if (!c)
                continue;
            for (int s = 0; s < f->meta.nvars; s++) {
                const unsigned char *oct = c + VSV_CHUNK_HEADER_SIZE + (size_t)s * f->lay.species_index_bytes;
                for (int b = 0; b < f->lay.nbricks; b++) {
                    const unsigned char *be = brick_entry(f, c, s, b);
                    if (be[0] == VSV_BRICK_ABS || be[0] == VSV_BRICK_DELTA) {
                        f->stored++;
                        f->payload += vsv_rd32(be + 16);
                    }
                    if (vsv_rd16(oct + 4 * (size_t)b + 2) > 0)
                        f->nonempty++;
                }
            }
        }
        f->counted = 1;
    }
    pthread_mutex_unlock(&f->lock);
}

void vsv_file_info_get(const vsv_file *cf, vsv_file_info *info)
{
    vsv_file *f = (vsv_file *)cf;
    count_bricks(f);
    memset(info, 0, sizeof *info);
    info->major = vsv_rd16(f->data + 8);
    info->minor = vsv_rd16(f->data + 10);
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
    info->stored_bricks = f->stored;
    info->nonempty_bricks = f->nonempty;
    info->payload_bytes = f->payload;
}

/* ------------------------------------------------------------- decoding */

int vsv_decoder_create(vsv_file *f, vsv_decoder **out)
{
    vsv_decoder *d = *out = calloc(1, sizeof *d);
    if (!d)
        return VSV_ENOMEM;
    d->f = f;
    const size_t n = (size_t)f->lay.brick * f->lay.brick * f->lay.brick;
    d->dctx = ZSTD_createDCtx();
    d->raw = malloc(2 * n);
    d->codes = malloc(2 * n);
    d->state = calloc((size_t)f->meta.nvars, sizeof *d->state);
    d->state_step = calloc((size_t)f->meta.nvars, sizeof *d->state_step);
    if (!d->dctx || !d->raw || !d->codes || !d->state || !d->state_step) {
        vsv_decoder_free(d);
        *out = NULL;
        return VSV_ENOMEM;
    }
    return 0;
}

void vsv_decoder_free(vsv_decoder *d)
{
    if (!d)
        return;
    ZSTD_freeDCtx(d->dctx);
    free(d->raw);
    free(d->codes);
    if (d->state)
        for (int s = 0; s < d->f->meta.nvars; s++)
            free(d->state[s]);
    free(d->state);
    free(d->state_step);
    free(d);
}

const char *vsv_decoder_error(const vsv_decoder *d) { return d ? d->err : "out of memory"; }

/* Applies the brick entry `be` of chunk c (step t) to codes. */
static int apply(vsv_decoder *d, const unsigned char *c, int t, int s, int b, const unsigned char *be, uint16_t *codes)
{
    vsv_file *f = d->f;
    const size_t n = (size_t)f->lay.brick * f->lay.brick * f->lay.brick;
    const int kind = be[0];
    if (kind == VSV_BRICK_UNCHANGED)
        return 0;
    if (kind == VSV_BRICK_EMPTY) {
        memset(codes, 0, n * sizeof *codes);
        return 0;
    }
    const int bits = f->quant[s].bits;
    int org[3], ext[3];
    vsv_layout_box(&f->lay, b, org, ext);
    const size_t raw = vsv_brick_raw_bytes(bits, ext);
    const uint64_t off = vsv_rd64(be + 8);
    const uint32_t size = vsv_rd32(be + 16);
    const unsigned char *p = c + off;
    if (vsv_crc32c(0, p, size) != vsv_rd32(be + 4)) {
        vsv_msg(d->err, sizeof d->err, "%s: chunk %d, species %d, brick %d (offset %llu): payload checksum mismatch",
                f->name, t, s, b, (unsigned long long)(p - f->data));
        return VSV_ECORRUPT;
    }
    const unsigned char *src = p;
    if (f->codec == VSV_CODEC_ZSTD) {
        size_t got = ZSTD_decompressDCtx(d->dctx, d->raw, raw, p, size);
        if (ZSTD_isError(got) || got != raw) {
            vsv_msg(d->err, sizeof d->err, "%s: chunk %d, species %d, brick %d (offset %llu): payload does not decode (%s)",
                    f->name, t, s, b, (unsigned long long)(p - f->data),
                    ZSTD_isError(got) ? ZSTD_getErrorName(got) : "wrong size");
            return VSV_ECODEC;
        }
        src = d->raw;
    }
    vsv_brick_inverse(bits, kind, src, f->lay.brick, ext, codes);
    return 0;
}

int vsv_decoder_brick_advance(vsv_decoder *d, int step, int s, int b, uint16_t *codes)
{
    vsv_file *f = d->f;
    int rc = check_args(f, step, s, b, d->err, sizeof d->err);
    if (rc)
        return rc;
    const unsigned char *c = chunk_index(f, step, d->err, sizeof d->err);
    if (!c)
        return VSV_ECORRUPT;
    return apply(d, c, step, s, b, brick_entry(f, c, s, b), codes);
}

int vsv_decoder_brick_codes(vsv_decoder *d, int step, int s, int b, uint16_t *codes)
{
    vsv_file *f = d->f;
    int rc = check_args(f, step, s, b, d->err, sizeof d->err);
    if (rc)
        return rc;
    int org[3], ext[3];
    vsv_layout_box(&f->lay, b, org, ext);
    if (ext[0] < f->lay.brick || ext[1] < f->lay.brick || ext[2] < f->lay.brick)
        memset(codes, 0, (size_t)f->lay.brick * f->lay.brick * f->lay.brick * sizeof *codes);
    /* walk back to the brick's last absolute state (never past a keyframe) */
    int t0 = step;
    for (;;) {
        const unsigned char *c = chunk_index(f, t0, d->err, sizeof d->err);
        if (!c)
            return VSV_ECORRUPT;
        const int kind = brick_entry(f, c, s, b)[0];
        if (kind == VSV_BRICK_EMPTY || kind == VSV_BRICK_ABS)
            break;
        t0--; /* keyframes hold only absolute kinds (checked), so t0 stays >= 0 */
    }
    for (int t = t0; t <= step; t++) {
        const unsigned char *c = chunk_index(f, t, d->err, sizeof d->err);
        if (!c)
            return VSV_ECORRUPT;
        if ((rc = apply(d, c, t, s, b, brick_entry(f, c, s, b), codes)))
            return rc;
    }
    return 0;
}

static const float *lut_of(vsv_file *f, int s)
{
    float *l = __atomic_load_n(&f->lut[s], __ATOMIC_ACQUIRE);
    if (l)
        return l;
    pthread_mutex_lock(&f->lock);
    l = f->lut[s];
    if (!l) {
        const unsigned n = f->quant[s].bits == 8 ? 256u : 65536u;
        l = malloc(n * sizeof *l);
        if (l) {
            vsv_quant_table(&f->quant[s], l);
            __atomic_store_n(&f->lut[s], l, __ATOMIC_RELEASE);
        }
    }
    pthread_mutex_unlock(&f->lock);
    return l;
}

void vsv_file_dequantise(const vsv_file *cf, int s, const uint16_t *codes, size_t n, float *out)
{
    vsv_file *f = (vsv_file *)cf;
    const vsv_quant *q = &f->quant[s];
    if (q->scale == VSV_SCALE_LINEAR && q->bits == 16 && !q->missing) {
        const double lo = q->lo, step = (q->hi - q->lo) / 65535.0; /* = vsv_quant_value */
        for (size_t i = 0; i < n; i++)
            out[i] = (float)(lo + codes[i] * step);
        return;
    }
    const float *l = lut_of(f, s);
    if (l) {
        for (size_t i = 0; i < n; i++)
            out[i] = l[codes[i]];
    } else {
        for (size_t i = 0; i < n; i++)
            out[i] = vsv_quant_value(q, codes[i]);
    }
}

int vsv_decoder_brick(vsv_decoder *d, int step, int s, int b, float *out)
{
    int rc = vsv_decoder_brick_codes(d, step, s, b, d->codes);
    if (!rc)
        vsv_file_dequantise(d->f, s, d->codes, (size_t)d->f->lay.brick * d->f->lay.brick * d->f->lay.brick, out);
    return rc;
}

/* The decoder keeps the codes of the last step it decoded per species, so a
 * forward sequential read costs one delta per brick and step. */
int vsv_decoder_volume(vsv_decoder *d, int step, int s, float *out)
{
    vsv_file *f = d->f;
    int rc = check_args(f, step, s, 0, d->err, sizeof d->err);
    if (rc)
        return rc;
    const vsv_layout *L = &f->lay;
    const size_t n = (size_t)L->brick * L->brick * L->brick;
    if (!d->state[s]) {
        d->state[s] = malloc((size_t)L->nbricks * n * sizeof(uint16_t));
        if (!d->state[s])
            return VSV_ENOMEM;
        d->state_step[s] = -1;
    }
    const int prev = d->state_step[s];
    const int seq = prev >= 0 && prev < step && step - prev <= f->keyframe;
    d->state_step[s] = -1;
    for (int b = 0; b < L->nbricks; b++) {
        uint16_t *codes = d->state[s] + (size_t)b * n;
        if (seq) {
            for (int t = prev + 1; t <= step && !rc; t++)
                rc = vsv_decoder_brick_advance(d, t, s, b, codes);
        } else if (prev != step) {
            rc = vsv_decoder_brick_codes(d, step, s, b, codes);
        }
        if (rc)
            return rc;
        int org[3], ext[3];
        vsv_layout_box(L, b, org, ext);
        for (int k = 0; k < ext[2]; k++)
            for (int j = 0; j < ext[1]; j++)
                vsv_file_dequantise(f, s, codes + ((size_t)k * L->brick + j) * L->brick, (size_t)ext[0],
                                    out + ((size_t)(org[2] + k) * f->meta.ny + (size_t)(org[1] + j)) * f->meta.nx + org[0]);
    }
    d->state_step[s] = step;
    return 0;
}

/* ---------------------------------------------------------------- check */

int vsv_file_check(vsv_file *f, void (*progress)(void *, int, int), void *ctx)
{
    size_t z;
    const uint64_t first = vsv_align_up(f->meta_end, VSV_ALIGN);
    if (!all_zero(f->data + f->meta_end, (size_t)(first - f->meta_end), &z))
        return bad(f, VSV_ECORRUPT, "non-zero padding after the metadata at offset %llu",
                   (unsigned long long)(f->meta_end + z));
    vsv_decoder *d = NULL;
    int rc = vsv_decoder_create(f, &d);
    if (rc)
        return bad(f, rc, "out of memory");
    const vsv_layout *L = &f->lay;
    const size_t n = (size_t)L->brick * L->brick * L->brick;
    uint16_t *state = calloc((size_t)f->meta.nvars * L->nbricks * n, sizeof *state);
    if (!state) {
        vsv_decoder_free(d);
        return bad(f, VSV_ENOMEM, "out of memory");
    }
    for (int t = 0; t < f->nsteps && !rc; t++) {
        const unsigned char *te = f->toc + (size_t)t * VSV_TOC_ENTRY_SIZE;
        const uint64_t coff = vsv_rd64(te), csize = vsv_rd64(te + 8);
        const unsigned char *c = chunk_index(f, t, f->err, sizeof f->err);
        if (!c) {
            rc = VSV_ECORRUPT;
            break;
        }
        /* padding after the index, and between and after payloads */
        const size_t index_end = VSV_CHUNK_HEADER_SIZE + (size_t)f->meta.nvars * L->species_index_bytes;
        uint64_t pos = index_end;
        for (int s = 0; s < f->meta.nvars && !rc; s++) {
            const unsigned char *oct = c + VSV_CHUNK_HEADER_SIZE + (size_t)s * L->species_index_bytes;
            for (int b = 0; b < L->nbricks && !rc; b++) {
                const unsigned char *be = brick_entry(f, c, s, b);
                uint16_t *codes = state + ((size_t)s * L->nbricks + b) * n;
                if (be[0] == VSV_BRICK_ABS || be[0] == VSV_BRICK_DELTA) {
                    const uint64_t off = vsv_rd64(be + 8);
                    if (!all_zero(c + pos, (size_t)(off - pos), &z)) {
                        rc = bad(f, VSV_ECORRUPT, "chunk %d: non-zero padding at offset %llu", t,
                                 (unsigned long long)(coff + pos + z));
                        break;
                    }
                    pos = off + vsv_rd32(be + 16);
                }
                if ((rc = apply(d, c, t, s, b, be, codes))) {
                    vsv_msg(f->err, sizeof f->err, "%s", d->err);
                    break;
                }
                /* octree level 0 must match the decoded codes */
                int org[3], ext[3];
                vsv_layout_box(L, b, org, ext);
                unsigned mn = 0xffff, mx = 0, stray = 0;
                for (int k = 0; k < L->brick; k++)
                    for (int j = 0; j < L->brick; j++)
                        for (int i = 0; i < L->brick; i++) {
                            unsigned v = codes[((size_t)k * L->brick + j) * L->brick + i];
                            if (i >= ext[0] || j >= ext[1] || k >= ext[2]) {
                                stray |= v;
                                continue;
                            }
                            mn = v < mn ? v : mn;
                            mx = v > mx ? v : mx;
                        }
                unsigned omn, omx;
                vsv_octree_node(oct, (size_t)b, &omn, &omx);
                if (stray || omn != mn || omx != mx || (f->quant[s].bits == 8 && mx > 255))
                    rc = bad(f, VSV_ECORRUPT, "chunk %d, species %d, brick %d: decoded codes disagree with the octree", t,
                             s, b);
            }
            if (!rc) {
                /* upper octree levels must reduce level 0 */
                uint16_t *nodes = malloc(L->nnodes * 4);
                if (!nodes) {
                    rc = bad(f, VSV_ENOMEM, "out of memory");
                    break;
                }
                for (int b = 0; b < L->nbricks; b++) {
                    unsigned a0, a1;
                    vsv_octree_node(oct, (size_t)b, &a0, &a1);
                    nodes[2 * b] = (uint16_t)a0;
                    nodes[2 * b + 1] = (uint16_t)a1;
                }
                vsv_layout_reduce(L, nodes);
                for (size_t i = L->lstart[1]; L->levels > 1 && i < L->nnodes; i++) {
                    unsigned a0, a1;
                    vsv_octree_node(oct, i, &a0, &a1);
                    if (a0 != nodes[2 * i] || a1 != nodes[2 * i + 1]) {
                        rc = bad(f, VSV_ECORRUPT, "chunk %d, species %d: octree node %zu disagrees with its children",
                                 t, s, i);
                        break;
                    }
                }
                free(nodes);
            }
        }
        if (!rc && !all_zero(c + pos, (size_t)(csize - pos), &z))
            rc = bad(f, VSV_ECORRUPT, "chunk %d: non-zero padding at offset %llu", t, (unsigned long long)(coff + pos + z));
        if (progress)
            progress(ctx, t + 1, f->nsteps);
    }
    free(state);
    vsv_decoder_free(d);
    return rc;
}

/* --------------------------------------------------------------- volumes */

typedef struct volume_impl {
    vsv_volume pub;
    uint16_t *codes;  /* nbricks * B^3: the decoded codes, kept for deltas */
    float *store;     /* nbricks * B^3 floats */
} volume_impl;

uint64_t vsv_volume_new_gen(void)
{
    static uint64_t gens;
    return __atomic_add_fetch(&gens, 1, __ATOMIC_RELAXED);
}

int vsv_volume_create(const vsv_file *f, vsv_volume **out)
{
    *out = NULL;
    volume_impl *v = calloc(1, sizeof *v);
    if (!v)
        return VSV_ENOMEM;
    const vsv_layout *L = &f->lay;
    const size_t n = (size_t)L->brick * L->brick * L->brick;
    v->pub.nx = f->meta.nx;
    v->pub.ny = f->meta.ny;
    v->pub.nz = f->meta.nz;
    v->pub.brick = L->brick;
    while ((1 << v->pub.shift) < L->brick)
        v->pub.shift++;
    for (int a = 0; a < 3; a++)
        v->pub.bdim[a] = L->bdim[a];
    v->pub.nbricks = L->nbricks;
    v->pub.step = v->pub.species = -1;
    v->pub.bricks = calloc((size_t)L->nbricks, sizeof *v->pub.bricks);
    v->pub.bmin = calloc((size_t)L->nbricks, sizeof(float));
    v->pub.bmax = calloc((size_t)L->nbricks, sizeof(float));
    v->codes = calloc((size_t)L->nbricks * n, sizeof *v->codes);
    v->store = malloc((size_t)L->nbricks * n * sizeof *v->store);
    if (!v->pub.bricks || !v->pub.bmin || !v->pub.bmax || !v->codes || !v->store) {
        vsv_volume_free(&v->pub);
        return VSV_ENOMEM;
    }
    *out = &v->pub;
    return 0;
}

void vsv_volume_free(vsv_volume *pv)
{
    if (!pv)
        return;
    volume_impl *v = (volume_impl *)pv;
    free(v->pub.bricks);
    free(v->pub.bmin);
    free(v->pub.bmax);
    free(v->codes);
    free(v->store);
    free(v);
}

int vsv_volume_load(vsv_volume *pv, vsv_decoder *d, int step, int s)
{
    volume_impl *v = (volume_impl *)pv;
    vsv_file *f = d->f;
    int rc = check_args(f, step, s, 0, d->err, sizeof d->err);
    if (rc)
        return rc;
    const vsv_layout *L = &f->lay;
    const size_t n = (size_t)L->brick * L->brick * L->brick;
    const int seq = pv->species == s && pv->step >= 0 && pv->step < step && step - pv->step <= f->keyframe;
    const int prev = pv->step;
    pv->step = pv->species = -1;
    pv->gen = 0;
    const unsigned char *oct = vsv_file_octree(f, step, s, NULL);
    if (!oct) {
        vsv_msg(d->err, sizeof d->err, "%s", f->err);
        return VSV_ECORRUPT;
    }
    const vsv_quant *q = &f->quant[s];
    pv->empty_value = vsv_quant_value(q, 0);
    for (int b = 0; b < L->nbricks; b++) {
        uint16_t *codes = v->codes + (size_t)b * n;
        if (seq) {
            for (int t = prev + 1; t <= step && !rc; t++)
                rc = vsv_decoder_brick_advance(d, t, s, b, codes);
        } else {
            rc = vsv_decoder_brick_codes(d, step, s, b, codes);
        }
        if (rc)
            return rc;
        unsigned mn, mx;
        vsv_octree_node(oct, (size_t)b, &mn, &mx);
        pv->bmin[b] = vsv_quant_value(q, mn);
        pv->bmax[b] = vsv_quant_value(q, mx);
        if (mx == 0) {
            pv->bricks[b] = NULL;
            continue;
        }
        float *dst = v->store + (size_t)b * n;
        vsv_file_dequantise(f, s, codes, n, dst);
        /* cells outside the grid read as the empty value */
        int org[3], ext[3];
        vsv_layout_box(L, b, org, ext);
        if (ext[0] < L->brick || ext[1] < L->brick || ext[2] < L->brick)
            for (int k = 0; k < L->brick; k++)
                for (int j = 0; j < L->brick; j++)
                    for (int i = 0; i < L->brick; i++)
                        if (i >= ext[0] || j >= ext[1] || k >= ext[2])
                            dst[((size_t)k * L->brick + j) * L->brick + i] = pv->empty_value;
        pv->bricks[b] = dst;
    }
    pv->step = step;
    pv->species = s;
    pv->time = vsv_file_time(f, step);
    pv->gen = vsv_volume_new_gen();
    return 0;
}
