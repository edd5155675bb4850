/* vsv_encode.c — the writer's work in pieces that need not run in one
 * process: value statistics, the pack plan (quantisation, default transfer
 * functions, metadata bytes), the chunk of one step, and the file's header
 * and tail. vsv_writer.c assembles a file from them on one machine;
 * vsv-convert-mpi does the same across ranks, so both write the same bytes. */
#include "vsv_format_internal.h"
#include "vsv_layout.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <zstd.h>
#include <zstd_errors.h>

struct vsv_pack_plan {
    vsv_meta meta;      /* with every species' transfer function */
    vsv_pack_opts opts; /* opts.vars NULL: the copies are in quant */
    vsv_quant *quant;
    vsv_layout lay;
    size_t cells;
    vsv_buf head;     /* metadata records + padding: bytes [128, first_chunk) */
    size_t meta_size; /* the records without the padding */
    char err[512];
};

struct vsv_chunk_encoder {
    const vsv_pack_plan *p;
    uint16_t *cur, *prev;
    unsigned char *raw, *z, *raw3, *z3; /* a payload; the 3-D kind's */
    unsigned char *ctx;                 /* the Rice coding's scratch: 3 bytes a cell */
    size_t zcap;
    uint16_t *nodes;
    ZSTD_CCtx *cctx;
    vsv_buf out;
    char err[256];
};

/* ------------------------------------------------------------ statistics */

void vsv_pack_stats_init(vsv_pack_stats *st, int nvars)
{
    for (int v = 0; v < nvars; v++)
        st[v] = (vsv_pack_stats){INFINITY, -INFINITY, INFINITY, 0};
}

void vsv_pack_stats_add(vsv_pack_stats *st, int nvars, size_t cells, const float *const *fields)
{
    for (int v = 0; v < nvars; v++) {
        const float *f = fields[v];
        vsv_pack_stats s = st[v];
        for (size_t i = 0; i < cells; i++) {
            const float x = f[i];
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
        st[v] = s;
    }
}

void vsv_pack_stats_merge(vsv_pack_stats *into, const vsv_pack_stats *from, int nvars)
{
    for (int v = 0; v < nvars; v++) {
        vsv_pack_stats *a = &into[v];
        const vsv_pack_stats *b = &from[v];
        a->min = fmin(a->min, b->min);
        a->max = fmax(a->max, b->max);
        a->minpos = fmin(a->minpos, b->minpos);
        a->nonfinite += b->nonfinite;
    }
}

/* ------------------------------------------------------------------ plan */

int vsv_pack_opts_check(const vsv_pack_opts *o, const vsv_meta *meta, char *err, size_t cap)
{
    if (o->brick != 8 && o->brick != 16 && o->brick != 32 && o->brick != 64) {
        vsv_msg(err, cap, "brick size %d: must be 8, 16, 32 or 64", o->brick);
        return VSV_EINVAL;
    }
    if (o->keyframe < 1 || o->keyframe > 65535) {
        vsv_msg(err, cap, "keyframe interval %d: must be 1..65535", o->keyframe);
        return VSV_EINVAL;
    }
    if (o->codec != VSV_CODEC_NONE && o->codec != VSV_CODEC_ZSTD) {
        vsv_msg(err, cap, "unknown codec %d", o->codec);
        return VSV_EINVAL;
    }
    if (o->predict < 0 || o->predict > 2) {
        vsv_msg(err, cap, "predict %d: must be 0 (format 1), 1 (format 2 or 3) or 2 (format 4)", o->predict);
        return VSV_EINVAL;
    }
    if (o->codec == VSV_CODEC_ZSTD && (o->level < 1 || o->level > ZSTD_maxCLevel())) {
        vsv_msg(err, cap, "zstd level %d: must be 1..%d", o->level, ZSTD_maxCLevel());
        return VSV_EINVAL;
    }
    for (int v = 0; o->vars && v < meta->nvars; v++)
        if (o->vars[v].bits != 8 && o->vars[v].bits != 16) {
            vsv_msg(err, cap, "%s: %d bits: must be 8 or 16", meta->vars[v].name, o->vars[v].bits);
            return VSV_EINVAL;
        }
    vsv_layout lay;
    if (vsv_layout_init(&lay, meta->nx, meta->ny, meta->nz, o->brick)) {
        vsv_msg(err, cap, "grid too large for the octree");
        return VSV_EINVAL;
    }
    /* a file the reader would reject is never written: the chunk header
     * stores the index size in 32 bits (SPEC.md §5, §12) */
    const uint64_t index_bytes = (uint64_t)meta->nvars * lay.species_index_bytes;
    if (index_bytes > UINT32_MAX) {
        vsv_msg(err, cap,
                "a chunk index of %llu bytes (%d species of %d bricks of %d cells) exceeds the format's 4 GiB limit: "
                "use larger bricks, fewer species or a smaller grid",
                (unsigned long long)index_bytes, meta->nvars, lay.nbricks, o->brick);
        return VSV_EINVAL;
    }
    return 0;
}

const char *vsv_pack_plan_error(const vsv_pack_plan *p) { return p ? p->err : "out of memory"; }
const vsv_quant *vsv_pack_plan_quant(const vsv_pack_plan *p, int s) { return &p->quant[s]; }
uint64_t vsv_pack_plan_first_chunk(const vsv_pack_plan *p) { return VSV_HEADER_SIZE + p->head.len; }
const unsigned char *vsv_pack_plan_meta_bytes(const vsv_pack_plan *p) { return p->head.p; }

int vsv_pack_plan_create(const vsv_meta *meta, const vsv_pack_opts *opts, const vsv_pack_stats *stats,
                         vsv_pack_plan **out)
{
    vsv_pack_plan *p = *out = calloc(1, sizeof *p);
    if (!p)
        return VSV_ENOMEM;
    vsv_meta_init(&p->meta);
    if (vsv_meta_validate(meta, p->err, sizeof p->err))
        return VSV_EINVAL;
    if (opts)
        p->opts = *opts;
    else
        vsv_pack_opts_init(&p->opts);
    int rc = vsv_pack_opts_check(&p->opts, meta, p->err, sizeof p->err);
    if (rc)
        return rc;
    if ((rc = vsv_meta_copy(&p->meta, meta)))
        return rc;
    const int ns = meta->nvars;
    p->quant = calloc((size_t)ns, sizeof *p->quant);
    if (!p->quant)
        return VSV_ENOMEM;
    /* no data the grid can place: below the ground of even heights over a
     * terrain (SPEC.md §4) */
    const int placed = meta->vert_kind == VSV_VERT_EVEN && meta->terrain && !vsv_meta_above_ground(meta);
    for (int s = 0; s < ns; s++) {
        vsv_pack_var dflt;
        vsv_pack_var_init(&dflt);
        const vsv_pack_stats *st = &stats[s];
        vsv_quant_plan(&p->quant[s], p->opts.vars ? &p->opts.vars[s] : &dflt, st->min, st->max,
                       st->minpos < INFINITY ? st->minpos : 0, st->nonfinite > 0 ? (placed ? 1 : 2) : 0);
    }
    p->opts.vars = NULL;
    vsv_layout_init(&p->lay, meta->nx, meta->ny, meta->nz, p->opts.brick);
    p->cells = (size_t)meta->nx * (size_t)meta->ny * (size_t)meta->nz;
    /* every species carries a default transfer function */
    if (!p->meta.tf && !(p->meta.tf = calloc((size_t)ns + 1, sizeof(char *))))
        return VSV_ENOMEM;
    for (int s = 0; s < ns; s++)
        if (!p->meta.tf[s]) {
            char tf[512];
            vsv_tf_default(p->meta.vars[s].name, &p->quant[s], tf, sizeof tf);
            if (!(p->meta.tf[s] = strdup(tf)))
                return VSV_ENOMEM;
        }
    /* planes and heights coded (format 3) unless a 1.x file was asked for */
    if (vsv_meta_encode(&p->meta, p->quant, p->opts.predict, &p->head))
        return VSV_ENOMEM;
    p->meta_size = p->head.len;
    const uint64_t end = VSV_HEADER_SIZE + p->head.len;
    if (vsv_buf_zeros(&p->head, (size_t)(vsv_align_up(end, VSV_ALIGN) - end)))
        return VSV_ENOMEM;
    return 0;
}

void vsv_pack_plan_free(vsv_pack_plan *p)
{
    if (!p)
        return;
    vsv_meta_clear(&p->meta);
    free(p->quant);
    vsv_buf_free(&p->head);
    free(p);
}

size_t vsv_pack_tail_bytes(int nsteps) { return (size_t)nsteps * VSV_TOC_ENTRY_SIZE + VSV_TRAILER_SIZE; }

int vsv_pack_plan_finish(vsv_pack_plan *p, int nsteps, const int64_t *times, const uint64_t *sizes,
                         unsigned char *header, unsigned char *tail, uint64_t *tail_offset)
{
    if (nsteps < 1 || nsteps > VSV_MAX_STEPS) {
        vsv_msg(p->err, sizeof p->err, "%d time steps: must be 1..%d", nsteps, VSV_MAX_STEPS);
        return VSV_EINVAL;
    }
    uint64_t off = vsv_pack_plan_first_chunk(p);
    for (int t = 0; t < nsteps; t++) {
        if (!VSV_TIME_OK(times[t]) || (t && times[t] <= times[t - 1])) {
            vsv_msg(p->err, sizeof p->err, "step %d: time %lld does not increase", t, (long long)times[t]);
            return VSV_EINVAL;
        }
        if (sizes[t] % VSV_ALIGN || sizes[t] < VSV_CHUNK_HEADER_SIZE) {
            vsv_msg(p->err, sizeof p->err, "step %d: chunk of %llu bytes is not a chunk", t,
                    (unsigned long long)sizes[t]);
            return VSV_EINVAL;
        }
        unsigned char *e = tail + (size_t)t * VSV_TOC_ENTRY_SIZE;
        vsv_wr64(e, off);
        vsv_wr64(e + 8, sizes[t]);
        vsv_wr64(e + 16, (uint64_t)times[t]);
        off += sizes[t];
    }
    const uint64_t toc_off = off, toc_size = (uint64_t)nsteps * VSV_TOC_ENTRY_SIZE;
    const uint32_t toc_crc = vsv_crc32c(0, tail, toc_size);
    const uint64_t file_size = toc_off + toc_size + VSV_TRAILER_SIZE;
    unsigned char *tr = tail + toc_size;
    memset(tr, 0, VSV_TRAILER_SIZE);
    memcpy(tr, VSV_END_MAGIC, 8);
    vsv_wr64(tr + 8, toc_off);
    vsv_wr64(tr + 16, file_size);
    vsv_wr32(tr + 24, toc_crc);
    vsv_wr32(tr + 28, vsv_crc32c(0, tr, 28));
    unsigned char *h = header;
    memset(h, 0, VSV_HEADER_SIZE);
    memcpy(h, VSV_MAGIC, 8);
    /* the lowest major and minor that have what the file may use */
    /* what vsv_meta_encode coded: planes and stored heights (format 3) */
    int coded = p->meta.terrain || p->meta.landuse;
    for (int i = 0; i < p->meta.nheights; i++)
        coded |= p->meta.heights[i].form == VSV_HEIGHTS_STORED;
    coded = coded && p->opts.predict;
    const int major = p->opts.predict >= 2 ? 4 : coded ? 3 : p->opts.predict || p->meta.nmoves ? 2 : 1;
    vsv_wr16(h + 8, (uint16_t)major);
    /* 3.1: a vector (an attribute "vector:NAME"; older readers see only species) */
    int vector = 0;
    for (int a = 0; a < p->meta.nattrs; a++)
        vector |= !strncmp(p->meta.attr_keys[a], VSV_VECTOR_ATTR, strlen(VSV_VECTOR_ATTR));
    vsv_wr16(h + 10, major == 4 ? 0 : major == 3 ? vector : major == 2 ? p->meta.nmoves > 0 : p->meta.nheights > 0);
    vsv_wr32(h + 12, VSV_HEADER_SIZE);
    vsv_wr64(h + 16, file_size);
    vsv_wr64(h + 24, VSV_HEADER_SIZE);
    vsv_wr64(h + 32, p->meta_size);
    vsv_wr32(h + 40, vsv_crc32c(0, p->head.p, p->meta_size));
    vsv_wr32(h + 44, (uint32_t)nsteps);
    vsv_wr64(h + 48, toc_off);
    vsv_wr64(h + 56, toc_size);
    vsv_wr32(h + 64, toc_crc);
    vsv_wr32(h + 68, (uint32_t)p->meta.nvars);
    vsv_wr32(h + 72, (uint32_t)p->meta.nx);
    vsv_wr32(h + 76, (uint32_t)p->meta.ny);
    vsv_wr32(h + 80, (uint32_t)p->meta.nz);
    vsv_wr32(h + 84, (uint32_t)p->opts.brick);
    vsv_wr32(h + 88, (uint32_t)p->opts.keyframe);
    vsv_wr32(h + 92, (uint32_t)p->opts.codec);
    vsv_wr32(h + 124, vsv_crc32c(0, h, 124));
    *tail_offset = toc_off;
    return 0;
}

/* --------------------------------------------------------------- chunks */

const char *vsv_chunk_encoder_error(const vsv_chunk_encoder *e) { return e ? e->err : "out of memory"; }

int vsv_chunk_encoder_create(const vsv_pack_plan *p, vsv_chunk_encoder **out)
{
    vsv_chunk_encoder *e = *out = calloc(1, sizeof *e);
    if (!e)
        return VSV_ENOMEM;
    const vsv_layout *L = &p->lay;
    const size_t n = (size_t)L->brick * L->brick * L->brick;
    e->p = p;
    e->cur = calloc(n, 2);
    e->prev = calloc(n, 2);
    e->raw = malloc(2 * n);
    e->zcap = ZSTD_compressBound(2 * n);
    e->z = malloc(e->zcap);
    e->raw3 = malloc(2 * n);
    e->z3 = malloc(e->zcap);
    e->ctx = malloc(3 * n);
    e->nodes = calloc(2 * L->nnodes, 2);
    e->cctx = ZSTD_createCCtx();
    return e->cur && e->prev && e->raw && e->z && e->raw3 && e->z3 && e->ctx && e->nodes && e->cctx ? 0 : VSV_ENOMEM;
}

void vsv_chunk_encoder_free(vsv_chunk_encoder *e)
{
    if (!e)
        return;
    free(e->cur);
    free(e->prev);
    free(e->raw);
    free(e->z);
    free(e->raw3);
    free(e->z3);
    free(e->ctx);
    free(e->nodes);
    ZSTD_freeCCtx(e->cctx);
    vsv_buf_free(&e->out);
    free(e);
}

/* Codes of brick b of field f (cells outside the grid are 0), and the
 * min/max over the cells inside the grid. */
static void gather(const vsv_pack_plan *p, const vsv_quant *q, const float *f, int b, uint16_t *codes, unsigned *mn,
                   unsigned *mx)
{
    const int B = p->lay.brick;
    int org[3], ext[3];
    vsv_layout_box(&p->lay, b, org, ext);
    if (ext[0] < B || ext[1] < B || ext[2] < B)
        memset(codes, 0, (size_t)B * B * B * sizeof *codes);
    unsigned lo = 0xffff, hi = 0;
    for (int k = 0; k < ext[2]; k++)
        for (int j = 0; j < ext[1]; j++) {
            const float *src = f + ((size_t)(org[2] + k) * p->meta.ny + (size_t)(org[1] + j)) * p->meta.nx + org[0];
            vsv_quant_row(q, src, (size_t)ext[0], codes + ((size_t)k * B + j) * B, &lo, &hi);
        }
    *mn = lo;
    *mx = hi;
}

/* A failed compression: out of memory said as such (zstd's text for it is
 * "Allocation error : not enough memory"), anything else as zstd says it. */
static int zstd_failed(vsv_chunk_encoder *e, size_t code)
{
    if (ZSTD_getErrorCode(code) == ZSTD_error_memory_allocation) {
        vsv_msg(e->err, sizeof e->err, "out of memory (zstd)");
        return VSV_ENOMEM;
    }
    vsv_msg(e->err, sizeof e->err, "zstd: %s", ZSTD_getErrorName(code));
    return VSV_ECODEC;
}

int vsv_chunk_encode(vsv_chunk_encoder *e, int t, int64_t time, const float *const *fields, const float *const *prev,
                     const unsigned char **bytes, size_t *size)
{
    const vsv_pack_plan *p = e->p;
    const vsv_layout *L = &p->lay;
    const int ns = p->meta.nvars;
    const size_t n = (size_t)L->brick * L->brick * L->brick;
    const int key = t % p->opts.keyframe == 0;
    *bytes = NULL;
    *size = 0;
    if (t < 0 || (!key && !prev)) {
        vsv_msg(e->err, sizeof e->err, "step %d: %s", t,
                t < 0 ? "negative step" : "a delta step needs the step before");
        return VSV_EINVAL;
    }
    vsv_buf *o = &e->out;
    o->len = 0;
    const size_t index_bytes = (size_t)ns * L->species_index_bytes;
    if (vsv_buf_zeros(o, (size_t)vsv_align_up(VSV_CHUNK_HEADER_SIZE + index_bytes, VSV_ALIGN)))
        return VSV_ENOMEM;
    for (int s = 0; s < ns; s++) {
        const vsv_quant *q = &p->quant[s];
        const float *fc = fields[s], *fp = key ? NULL : prev[s];
        const size_t oct_at = VSV_CHUNK_HEADER_SIZE + (size_t)s * L->species_index_bytes;
        const size_t tab_at = oct_at + L->octree_bytes;
        for (int b = 0; b < L->nbricks; b++) {
            unsigned mn, mx, pmn = 0, pmx = 0;
            gather(p, q, fc, b, e->cur, &mn, &mx);
            int kind;
            if (key) {
                kind = mx == 0 ? VSV_BRICK_EMPTY : VSV_BRICK_ABS;
            } else {
                gather(p, q, fp, b, e->prev, &pmn, &pmx);
                if (!memcmp(e->cur, e->prev, n * sizeof *e->cur))
                    kind = VSV_BRICK_UNCHANGED;
                else if (mx == 0)
                    kind = VSV_BRICK_EMPTY;
                else if (pmx == 0)
                    kind = VSV_BRICK_ABS;
                else
                    kind = VSV_BRICK_DELTA;
            }
            e->nodes[2 * b] = (uint16_t)mn;
            e->nodes[2 * b + 1] = (uint16_t)mx;
            unsigned char *ent = o->p + tab_at + (size_t)b * VSV_BRICK_ENTRY_SIZE;
            ent[0] = (unsigned char)kind;
            if (kind != VSV_BRICK_ABS && kind != VSV_BRICK_DELTA)
                continue;
            int org[3], ext[3];
            vsv_layout_box(L, b, org, ext);
            const size_t raw = vsv_brick_raw_bytes(q->bits, ext);
            vsv_brick_forward(q->bits, kind, e->cur, e->prev, L->brick, ext, e->raw);
            const unsigned char *payload = e->raw;
            size_t psize = raw;
            if (p->opts.codec == VSV_CODEC_ZSTD) {
                psize = ZSTD_compressCCtx(e->cctx, e->z, e->zcap, e->raw, raw, p->opts.level);
                if (ZSTD_isError(psize))
                    return zstd_failed(e, psize);
                payload = e->z;
                if (p->opts.predict) { /* the 3-D kind where its payload is smaller */
                    const int k3 = kind == VSV_BRICK_ABS ? VSV_BRICK_ABS3 : VSV_BRICK_DELTA3;
                    vsv_brick_forward(q->bits, k3, e->cur, e->prev, L->brick, ext, e->raw3);
                    const size_t s3 = ZSTD_compressCCtx(e->cctx, e->z3, e->zcap, e->raw3, raw, p->opts.level);
                    if (ZSTD_isError(s3))
                        return zstd_failed(e, s3);
                    if (s3 < psize) {
                        kind = k3;
                        psize = s3;
                        payload = e->z3;
                    }
                    if (p->opts.predict >= 2) { /* the same residuals Rice-coded (format 4) */
                        unsigned char *zr = payload == e->z ? e->z3 : e->z;
                        const size_t sr = vsv_rice_encode(q->bits, ext, e->raw3, e->ctx, zr, psize - 1);
                        if (sr) {
                            kind = k3 + 2;
                            psize = sr;
                            payload = zr;
                        }
                    }
                }
            }
            const size_t at = o->len;
            if (vsv_buf_put(o, payload, psize) || vsv_buf_zeros(o, (size_t)(vsv_align_up(o->len, VSV_ALIGN) - o->len)))
                return VSV_ENOMEM;
            ent = o->p + tab_at + (size_t)b * VSV_BRICK_ENTRY_SIZE;
            ent[0] = (unsigned char)kind;
            vsv_wr32(ent + 4, vsv_crc32c(0, o->p + at, psize));
            vsv_wr64(ent + 8, at);
            vsv_wr32(ent + 16, (uint32_t)psize);
        }
        vsv_layout_reduce(L, e->nodes);
        for (size_t i = 0; i < L->nnodes; i++) {
            vsv_wr16(o->p + oct_at + 4 * i, e->nodes[2 * i]);
            vsv_wr16(o->p + oct_at + 4 * i + 2, e->nodes[2 * i + 1]);
        }
    }
    unsigned char *h = o->p;
    memcpy(h, "VCHK", 4);
    vsv_wr32(h + 4, (uint32_t)t);
    vsv_wr64(h + 8, (uint64_t)time);
    vsv_wr32(h + 16, (uint32_t)index_bytes);
    vsv_wr32(h + 20, (uint32_t)ns);
    uint32_t crc = vsv_crc32c(0, h, 28);
    crc = vsv_crc32c(crc, h + VSV_CHUNK_HEADER_SIZE, index_bytes);
    vsv_wr32(h + 28, crc);
    *bytes = o->p;
    *size = o->len;
    return 0;
}
