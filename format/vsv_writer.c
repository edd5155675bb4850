/* vsv_writer.c — the streaming .vsv writer. Steps are spooled as raw floats
 * to an unlinked temporary file (quantisation needs each species' range over
 * all steps before the first brick is coded); finish() then quantises and
 * encodes every step in parallel — a step's bricks depend only on the
 * quantised codes of that step and the one before, both recomputable from
 * the spool — and writes the chunks in time order to a temporary name that
 * is renamed into place only when everything succeeded. */
#include "vsv_format_internal.h"
#include "vsv_layout.h"

#include <errno.h>
#include <fcntl.h>
#include <libgen.h>
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zstd.h>

typedef struct stats {
    double min, max, minpos;
    uint64_t nonfinite;
} stats;

typedef struct scratch {
    uint16_t *cur, *prev;
    unsigned char *raw, *z;
    size_t zcap;
    uint16_t *nodes;
    ZSTD_CCtx *cctx;
    vsv_buf out;
    int rc;
    char err[256];
} scratch;

struct vsv_writer {
    char *path, *tmp;
    int spool_fd, out_fd;
    vsv_meta meta;
    vsv_pack_opts opts;
    vsv_pack_var *vars;
    vsv_quant *quant;
    vsv_layout lay;
    size_t cells;
    int64_t *times;
    int nsteps, cap_steps, finished;
    stats *st;
    const float *spool;
    size_t spool_bytes;
    char err[512];
};

void vsv_pack_var_init(vsv_pack_var *v)
{
    memset(v, 0, sizeof *v);
    v->bits = 16;
    v->scale = VSV_SCALE_LINEAR;
    v->threshold = NAN;
}

void vsv_pack_opts_init(vsv_pack_opts *o)
{
    memset(o, 0, sizeof *o);
    o->brick = 32;
    o->keyframe = 8;
    o->codec = VSV_CODEC_ZSTD;
    o->level = 3;
}

const char *vsv_writer_error(const vsv_writer *w) { return w ? w->err : "out of memory"; }

static int fail_errno(vsv_writer *w, const char *what)
{
    vsv_msg(w->err, sizeof w->err, "%s: %s", what, strerror(errno));
    return VSV_EIO;
}

/* A temporary file in the directory of `path` (so rename is atomic). */
static int make_temp(const char *path, const char *suffix, char **name_out)
{
    size_t n = strlen(path) + strlen(suffix) + 16;
    char *name = malloc(n);
    if (!name)
        return -1;
    snprintf(name, n, "%s%sXXXXXX", path, suffix);
    int fd = mkstemp(name);
    if (fd < 0) {
        free(name);
        return -1;
    }
    *name_out = name;
    return fd;
}

int vsv_writer_create(const char *path, const vsv_meta *meta, const vsv_pack_opts *opts, vsv_writer **out)
{
    *out = NULL;
    vsv_writer *w = calloc(1, sizeof *w);
    if (!w)
        return VSV_ENOMEM;
    *out = w;
    w->spool_fd = w->out_fd = -1;
    vsv_meta_init(&w->meta);
    w->path = strdup(path);
    if (!w->path)
        return VSV_ENOMEM;
    if (vsv_meta_validate(meta, w->err, sizeof w->err))
        return VSV_EINVAL;
    if (opts)
        w->opts = *opts;
    else
        vsv_pack_opts_init(&w->opts);
    const vsv_pack_opts *o = &w->opts;
    if (o->brick != 8 && o->brick != 16 && o->brick != 32 && o->brick != 64) {
        vsv_msg(w->err, sizeof w->err, "brick size %d: must be 8, 16, 32 or 64", o->brick);
        return VSV_EINVAL;
    }
    if (o->keyframe < 1 || o->keyframe > 65535) {
        vsv_msg(w->err, sizeof w->err, "keyframe interval %d: must be 1..65535", o->keyframe);
        return VSV_EINVAL;
    }
    if (o->codec != VSV_CODEC_NONE && o->codec != VSV_CODEC_ZSTD) {
        vsv_msg(w->err, sizeof w->err, "unknown codec %d", o->codec);
        return VSV_EINVAL;
    }
    if (o->level < 1 || o->level > ZSTD_maxCLevel())
        w->opts.level = 3;
    int rc = vsv_meta_copy(&w->meta, meta);
    if (rc)
        return rc;
    const int nv = meta->nvars;
    w->vars = calloc((size_t)nv, sizeof *w->vars);
    w->st = calloc((size_t)nv, sizeof *w->st);
    w->quant = calloc((size_t)nv, sizeof *w->quant);
    if (!w->vars || !w->st || !w->quant)
        return VSV_ENOMEM;
    for (int v = 0; v < nv; v++) {
        if (o->vars)
            w->vars[v] = o->vars[v];
        else
            vsv_pack_var_init(&w->vars[v]);
        if (w->vars[v].bits != 8 && w->vars[v].bits != 16) {
            vsv_msg(w->err, sizeof w->err, "%s: %d bits: must be 8 or 16", meta->vars[v].name, w->vars[v].bits);
            return VSV_EINVAL;
        }
        w->st[v].min = INFINITY;
        w->st[v].max = -INFINITY;
        w->st[v].minpos = INFINITY;
    }
    w->opts.vars = NULL;
    if (vsv_layout_init(&w->lay, meta->nx, meta->ny, meta->nz, o->brick)) {
        vsv_msg(w->err, sizeof w->err, "grid too large for the octree");
        return VSV_EINVAL;
    }
    w->cells = (size_t)meta->nx * (size_t)meta->ny * (size_t)meta->nz;
    char *spool_name = NULL;
    w->spool_fd = make_temp(path, ".spool.", &spool_name);
    if (w->spool_fd < 0)
        return fail_errno(w, "cannot create a temporary file beside it");
    unlink(spool_name);
    free(spool_name);
    return 0;
}

static int write_all(int fd, const void *p, size_t n)
{
    const unsigned char *c = p;
    while (n) {
        ssize_t k = write(fd, c, n > (1u << 30) ? (1u << 30) : n);
        if (k < 0) {
            if (errno == EINTR)
                continue;
            return -1;
        }
        c += k;
        n -= (size_t)k;
    }
    return 0;
}

int vsv_writer_add_step(vsv_writer *w, int64_t time, const float *const *fields)
{
    if (w->finished || w->spool_fd < 0)
        return VSV_EINVAL;
    if (w->nsteps && time <= w->times[w->nsteps - 1]) {
        vsv_msg(w->err, sizeof w->err, "step %d: time %lld does not increase", w->nsteps, (long long)time);
        return VSV_EINVAL;
    }
    if (w->nsteps >= VSV_MAX_STEPS) {
        vsv_msg(w->err, sizeof w->err, "more than %d steps", VSV_MAX_STEPS);
        return VSV_EINVAL;
    }
    if (w->nsteps == w->cap_steps) {
        int cap = w->cap_steps ? 2 * w->cap_steps : 64;
        int64_t *t = realloc(w->times, (size_t)cap * sizeof *t);
        if (!t)
            return VSV_ENOMEM;
        w->times = t;
        w->cap_steps = cap;
    }
    for (int v = 0; v < w->meta.nvars; v++) {
        const float *f = fields[v];
        stats s = w->st[v];
        for (size_t i = 0; i < w->cells; i++) {
            float x = f[i];
            if (!isfinite(x)) {
                s.nonfinite++;
                continue;
            }
            if (x < s.min)
                s.min = x;
            if (x > s.max)
                s.max = x;
            if (x > 0 && x < s.minpos)
                s.minpos = x;
        }
        w->st[v] = s;
        if (write_all(w->spool_fd, f, w->cells * 4))
            return fail_errno(w, "writing the spool file");
    }
    w->times[w->nsteps++] = time;
    return 0;
}

/* ---------------------------------------------------------------- encoding */

static const float *spool_field(const vsv_writer *w, int t, int v)
{
    return w->spool + ((size_t)t * (size_t)w->meta.nvars + (size_t)v) * w->cells;
}

/* Codes of brick b of field f (cells outside the grid are 0); returns the
 * largest code, and the min/max over the cells inside the grid. */
static void gather(const vsv_writer *w, const vsv_quant *q, const float *f, int b, uint16_t *codes,
                   unsigned *mn, unsigned *mx)
{
    const int B = w->lay.brick;
    int org[3], ext[3];
    vsv_layout_box(&w->lay, b, org, ext);
    if (ext[0] < B || ext[1] < B || ext[2] < B)
        memset(codes, 0, (size_t)B * B * B * sizeof *codes);
    unsigned lo = 0xffff, hi = 0;
    for (int k = 0; k < ext[2]; k++)
        for (int j = 0; j < ext[1]; j++) {
            const float *src = f + ((size_t)(org[2] + k) * w->meta.ny + (size_t)(org[1] + j)) * w->meta.nx + org[0];
            vsv_quant_row(q, src, (size_t)ext[0], codes + ((size_t)k * B + j) * B, &lo, &hi);
        }
    *mn = lo;
    *mx = hi;
}

static int encode_chunk(const vsv_writer *w, scratch *sc, int t)
{
    const vsv_layout *L = &w->lay;
    const int ns = w->meta.nvars;
    const size_t n = (size_t)L->brick * L->brick * L->brick;
    const int key = t % w->opts.keyframe == 0;
    vsv_buf *o = &sc->out;
    o->len = 0;
    const size_t index_bytes = (size_t)ns * L->species_index_bytes;
    if (vsv_buf_zeros(o, (size_t)vsv_align_up(VSV_CHUNK_HEADER_SIZE + index_bytes, VSV_ALIGN)))
        return VSV_ENOMEM;
    for (int s = 0; s < ns; s++) {
        const vsv_quant *q = &w->quant[s];
        const float *fc = spool_field(w, t, s), *fp = t ? spool_field(w, t - 1, s) : NULL;
        const size_t oct_at = VSV_CHUNK_HEADER_SIZE + (size_t)s * L->species_index_bytes;
        const size_t tab_at = oct_at + L->octree_bytes;
        for (int b = 0; b < L->nbricks; b++) {
            unsigned mn, mx, pmn = 0, pmx = 0;
            gather(w, q, fc, b, sc->cur, &mn, &mx);
            int kind;
            if (key) {
                kind = mx == 0 ? VSV_BRICK_EMPTY : VSV_BRICK_ABS;
            } else {
                gather(w, q, fp, b, sc->prev, &pmn, &pmx);
                if (!memcmp(sc->cur, sc->prev, n * sizeof *sc->cur))
                    kind = VSV_BRICK_UNCHANGED;
                else if (mx == 0)
                    kind = VSV_BRICK_EMPTY;
                else if (pmx == 0)
                    kind = VSV_BRICK_ABS;
                else
                    kind = VSV_BRICK_DELTA;
            }
            sc->nodes[2 * b] = (uint16_t)mn;
            sc->nodes[2 * b + 1] = (uint16_t)mx;
            unsigned char *e = o->p + tab_at + (size_t)b * VSV_BRICK_ENTRY_SIZE;
            e[0] = (unsigned char)kind;
            if (kind != VSV_BRICK_ABS && kind != VSV_BRICK_DELTA)
                continue;
            int org[3], ext[3];
            vsv_layout_box(L, b, org, ext);
            const size_t raw = vsv_brick_raw_bytes(q->bits, ext);
            vsv_brick_forward(q->bits, kind, sc->cur, sc->prev, L->brick, ext, sc->raw);
            const unsigned char *payload = sc->raw;
            size_t size = raw;
            if (w->opts.codec == VSV_CODEC_ZSTD) {
                size = ZSTD_compressCCtx(sc->cctx, sc->z, sc->zcap, sc->raw, raw, w->opts.level);
                if (ZSTD_isError(size)) {
                    vsv_msg(sc->err, sizeof sc->err, "zstd: %s", ZSTD_getErrorName(size));
                    return VSV_ECODEC;
                }
                payload = sc->z;
            }
            const size_t at = o->len;
            if (vsv_buf_put(o, payload, size) ||
                vsv_buf_zeros(o, (size_t)(vsv_align_up(o->len, VSV_ALIGN) - o->len)))
                return VSV_ENOMEM;
            e = o->p + tab_at + (size_t)b * VSV_BRICK_ENTRY_SIZE;
            vsv_wr32(e + 4, vsv_crc32c(0, o->p + at, size));
            vsv_wr64(e + 8, at);
            vsv_wr32(e + 16, (uint32_t)size);
        }
        vsv_layout_reduce(L, sc->nodes);
        for (size_t i = 0; i < L->nnodes; i++) {
            vsv_wr16(o->p + oct_at + 4 * i, sc->nodes[2 * i]);
            vsv_wr16(o->p + oct_at + 4 * i + 2, sc->nodes[2 * i + 1]);
        }
    }
    unsigned char *h = o->p;
    memcpy(h, "VCHK", 4);
    vsv_wr32(h + 4, (uint32_t)t);
    vsv_wr64(h + 8, (uint64_t)w->times[t]);
    vsv_wr32(h + 16, (uint32_t)index_bytes);
    vsv_wr32(h + 20, (uint32_t)ns);
    uint32_t crc = vsv_crc32c(0, h, 28);
    crc = vsv_crc32c(crc, h + VSV_CHUNK_HEADER_SIZE, index_bytes);
    vsv_wr32(h + 28, crc);
    return 0;
}

typedef struct job {
    const vsv_writer *w;
    scratch *sc;
    int t;
} job;

static void *job_run(void *arg)
{
    job *j = arg;
    j->sc->rc = encode_chunk(j->w, j->sc, j->t);
    return NULL;
}

static void scratch_free(scratch *sc)
{
    free(sc->cur);
    free(sc->prev);
    free(sc->raw);
    free(sc->z);
    free(sc->nodes);
    ZSTD_freeCCtx(sc->cctx);
    vsv_buf_free(&sc->out);
}

static int scratch_init(scratch *sc, const vsv_layout *L)
{
    memset(sc, 0, sizeof *sc);
    const size_t n = (size_t)L->brick * L->brick * L->brick;
    sc->cur = calloc(n, 2);
    sc->prev = calloc(n, 2);
    sc->raw = malloc(2 * n);
    sc->zcap = ZSTD_compressBound(2 * n);
    sc->z = malloc(sc->zcap);
    sc->nodes = calloc(2 * L->nnodes, 2);
    sc->cctx = ZSTD_createCCtx();
    return sc->cur && sc->prev && sc->raw && sc->z && sc->nodes && sc->cctx ? 0 : VSV_ENOMEM;
}

static int write_at(int fd, const void *p, size_t n, uint64_t off)
{
    const unsigned char *c = p;
    while (n) {
        ssize_t k = pwrite(fd, c, n, (off_t)off);
        if (k < 0) {
            if (errno == EINTR)
                continue;
            return -1;
        }
        c += k;
        n -= (size_t)k;
        off += (uint64_t)k;
    }
    return 0;
}

static int finish_body(vsv_writer *w, void (*progress)(void *, int, int), void *ctx)
{
    const int ns = w->meta.nvars;
    int rc = 0;
    if (w->nsteps < 1) {
        vsv_msg(w->err, sizeof w->err, "no time steps to write");
        return VSV_EINVAL;
    }
    for (int s = 0; s < ns; s++) {
        const stats *st = &w->st[s];
        vsv_quant_plan(&w->quant[s], &w->vars[s], st->min, st->max, st->minpos < INFINITY ? st->minpos : 0,
                       st->nonfinite > 0);
    }
    w->spool_bytes = (size_t)w->nsteps * (size_t)ns * w->cells * 4;
    void *map = mmap(NULL, w->spool_bytes, PROT_READ, MAP_PRIVATE, w->spool_fd, 0);
    if (map == MAP_FAILED)
        return fail_errno(w, "mapping the spool file");
    w->spool = map;
    madvise(map, w->spool_bytes, MADV_SEQUENTIAL);

    w->out_fd = make_temp(w->path, ".tmp.", &w->tmp);
    if (w->out_fd < 0)
        return fail_errno(w, "cannot create the temporary output");
    mode_t um = umask(0);
    umask(um);
    fchmod(w->out_fd, 0666 & ~um);

    /* every species carries a default transfer function */
    if (!w->meta.tf && !(w->meta.tf = calloc((size_t)ns + 1, sizeof(char *))))
        return VSV_ENOMEM;
    for (int s = 0; s < ns; s++)
        if (!w->meta.tf[s]) {
            char tf[512];
            vsv_tf_default(w->meta.vars[s].name, &w->quant[s], tf, sizeof tf);
            if (!(w->meta.tf[s] = strdup(tf)))
                return VSV_ENOMEM;
        }
    vsv_buf meta = {0};
    if (vsv_meta_encode(&w->meta, w->quant, &meta)) {
        vsv_buf_free(&meta);
        return VSV_ENOMEM;
    }
    const uint64_t meta_off = VSV_HEADER_SIZE;
    const uint32_t meta_crc = vsv_crc32c(0, meta.p, meta.len);
    const uint64_t meta_size = meta.len;
    uint64_t off = vsv_align_up(meta_off + meta_size, VSV_ALIGN);
    if (vsv_buf_zeros(&meta, (size_t)(off - meta_off - meta_size)) || write_at(w->out_fd, meta.p, meta.len, meta_off)) {
        vsv_buf_free(&meta);
        return fail_errno(w, "writing metadata");
    }
    vsv_buf_free(&meta);

    int nth = w->opts.threads > 0 ? w->opts.threads : vsv_ncpus();
    if (nth > w->nsteps)
        nth = w->nsteps;
    if (nth > 64)
        nth = 64;
    scratch *sc = calloc((size_t)nth, sizeof *sc);
    unsigned char *toc = calloc((size_t)w->nsteps, VSV_TOC_ENTRY_SIZE);
    if (!sc || !toc) {
        free(sc);
        free(toc);
        return VSV_ENOMEM;
    }
    for (int i = 0; i < nth; i++)
        if (scratch_init(&sc[i], &w->lay))
            rc = VSV_ENOMEM;
    for (int t0 = 0; !rc && t0 < w->nsteps; t0 += nth) {
        const int cnt = w->nsteps - t0 < nth ? w->nsteps - t0 : nth;
        job jobs[64];
        pthread_t tid[64];
        int started[64] = {0};
        for (int i = 0; i < cnt; i++) {
            jobs[i] = (job){w, &sc[i], t0 + i};
            if (i > 0 && pthread_create(&tid[i], NULL, job_run, &jobs[i]) == 0)
                started[i] = 1;
        }
        job_run(&jobs[0]);
        for (int i = 1; i < cnt; i++) {
            if (started[i])
                pthread_join(tid[i], NULL);
            else
                job_run(&jobs[i]);
        }
        for (int i = 0; i < cnt && !rc; i++) {
            if (sc[i].rc) {
                rc = sc[i].rc;
                vsv_msg(w->err, sizeof w->err, "encoding step %d: %s", t0 + i,
                        sc[i].err[0] ? sc[i].err : vsv_strerror(rc));
                break;
            }
            unsigned char *e = toc + (size_t)(t0 + i) * VSV_TOC_ENTRY_SIZE;
            vsv_wr64(e, off);
            vsv_wr64(e + 8, sc[i].out.len);
            vsv_wr64(e + 16, (uint64_t)w->times[t0 + i]);
            if (write_at(w->out_fd, sc[i].out.p, sc[i].out.len, off))
                rc = fail_errno(w, "writing a chunk");
            off += sc[i].out.len;
        }
        if (progress && !rc)
            progress(ctx, t0 + cnt, w->nsteps);
    }
    for (int i = 0; i < nth; i++)
        scratch_free(&sc[i]);
    free(sc);
    if (rc) {
        free(toc);
        return rc;
    }
    const uint64_t toc_off = off, toc_size = (uint64_t)w->nsteps * VSV_TOC_ENTRY_SIZE;
    const uint32_t toc_crc = vsv_crc32c(0, toc, toc_size);
    const uint64_t file_size = toc_off + toc_size + VSV_TRAILER_SIZE;
    int wr = write_at(w->out_fd, toc, toc_size, toc_off);
    free(toc);
    if (wr)
        return fail_errno(w, "writing the table of contents");
    unsigned char tr[VSV_TRAILER_SIZE] = {0};
    memcpy(tr, VSV_END_MAGIC, 8);
    vsv_wr64(tr + 8, toc_off);
    vsv_wr64(tr + 16, file_size);
    vsv_wr32(tr + 24, toc_crc);
    vsv_wr32(tr + 28, vsv_crc32c(0, tr, 28));
    unsigned char h[VSV_HEADER_SIZE] = {0};
    memcpy(h, VSV_MAGIC, 8);
    vsv_wr16(h + 8, VSV_FORMAT_MAJOR);
    vsv_wr16(h + 10, VSV_FORMAT_MINOR);
    vsv_wr32(h + 12, VSV_HEADER_SIZE);
    vsv_wr64(h + 16, file_size);
    vsv_wr64(h + 24, meta_off);
    vsv_wr64(h + 32, meta_size);
    vsv_wr32(h + 40, meta_crc);
    vsv_wr32(h + 44, (uint32_t)w->nsteps);
    vsv_wr64(h + 48, toc_off);
    vsv_wr64(h + 56, toc_size);
    vsv_wr32(h + 64, toc_crc);
    vsv_wr32(h + 68, (uint32_t)ns);
    vsv_wr32(h + 72, (uint32_t)w->meta.nx);
    vsv_wr32(h + 76, (uint32_t)w->meta.ny);
    vsv_wr32(h + 80, (uint32_t)w->meta.nz);
    vsv_wr32(h + 84, (uint32_t)w->opts.brick);
    vsv_wr32(h + 88, (uint32_t)w->opts.keyframe);
    vsv_wr32(h + 92, (uint32_t)w->opts.codec);
    vsv_wr32(h + 124, vsv_crc32c(0, h, 124));
    if (write_at(w->out_fd, tr, sizeof tr, toc_off + toc_size) || write_at(w->out_fd, h, sizeof h, 0))
        return fail_errno(w, "writing the header");
    if (fsync(w->out_fd))
        return fail_errno(w, "fsync");
    if (close(w->out_fd)) {
        w->out_fd = -1;
        return fail_errno(w, "close");
    }
    w->out_fd = -1;
    if (rename(w->tmp, w->path))
        return fail_errno(w, "renaming the temporary output into place");
    free(w->tmp);
    w->tmp = NULL;
    char *dir = strdup(w->path);
    if (dir) {
        int dfd = open(dirname(dir), O_RDONLY | O_DIRECTORY);
        if (dfd >= 0) {
            fsync(dfd);
            close(dfd);
        }
        free(dir);
    }
    return 0;
}

int vsv_writer_finish(vsv_writer *w, void (*progress)(void *, int, int), void *ctx)
{
    if (w->finished)
        return VSV_EINVAL;
    w->finished = 1;
    int rc = finish_body(w, progress, ctx);
    if (w->spool) {
        munmap((void *)w->spool, w->spool_bytes);
        w->spool = NULL;
    }
    return rc;
}

void vsv_writer_free(vsv_writer *w)
{
    if (!w)
        return;
    if (w->spool)
        munmap((void *)w->spool, w->spool_bytes);
    if (w->spool_fd >= 0)
        close(w->spool_fd);
    if (w->out_fd >= 0)
        close(w->out_fd);
    if (w->tmp) {
        unlink(w->tmp);
        free(w->tmp);
    }
    vsv_meta_clear(&w->meta);
    free(w->path);
    free(w->vars);
    free(w->quant);
    free(w->st);
    free(w->times);
    free(w);
}
