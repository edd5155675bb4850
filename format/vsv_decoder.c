/* vsv_decoder.c — decoding a brick: the keyframe and the deltas after it
 * applied to quantised codes (exact, no drift), then the codes to values. */
#include "vsv_reader_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Per column, the levels whose centre lies below the ground: on even
 * heights over a terrain, z0 + k*dz < terrain (the converter's rule,
 * vsv_vgrid_plan). NULL when no column has any (or without a terrain:
 * native levels follow the ground; heights above the ground start at it). */
static uint16_t *under_ground(const vsv_meta *m, const float *terrain, int *rc)
{
    *rc = 0;
    if (m->vert_kind != VSV_VERT_EVEN || !terrain || vsv_meta_above_ground(m))
        return NULL;
    const size_t plane = (size_t)m->nx * m->ny;
    uint16_t *u = malloc(plane * sizeof *u);
    if (!u) {
        *rc = VSV_ENOMEM;
        return NULL;
    }
    int any = 0;
    for (size_t c = 0; c < plane; c++) {
        int k = 0;
        while (k < m->nz && m->origin[2] + k * m->spacing[2] < (double)terrain[c])
            k++;
        u[c] = (uint16_t)k;
        any |= k;
    }
    if (!any) {
        free(u);
        return NULL;
    }
    return u;
}

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
    d->scratch = malloc(2 * n);
    d->zres = f->major >= 4 ? malloc(2 * n) : NULL;
    d->rice = f->major >= 4 ? calloc(1, vsv_rice_max(16, n) + VSV_RICE_PAD) : NULL;
    d->state = calloc((size_t)f->meta.nvars, sizeof *d->state);
    d->state_step = calloc((size_t)f->meta.nvars, sizeof *d->state_step);
    /* one mask per placement of a moving grid: GRID's, then each MOVE's */
    int urc = 0;
    d->under = calloc((size_t)f->meta.nmoves + 1, sizeof *d->under);
    for (int i = 0; d->under && !urc && i <= f->meta.nmoves; i++)
        d->under[i] = under_ground(&f->meta, i ? f->meta.moves[i - 1].terrain : f->meta.terrain, &urc);
    if (urc || !d->under || !d->dctx || !d->raw || !d->codes || !d->scratch ||
        (f->major >= 4 && (!d->rice || !d->zres)) || !d->state || !d->state_step) {
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
    for (int i = 0; d->under && i <= d->f->meta.nmoves; i++)
        free(d->under[i]);
    free(d->under);
    free(d->raw);
    free(d->codes);
    free(d->scratch);
    free(d->zres);
    free(d->rice);
    if (d->state)
        for (int s = 0; s < d->f->meta.nvars; s++)
            free(d->state[s]);
    free(d->state);
    free(d->state_step);
    free(d);
}

const char *vsv_decoder_error(const vsv_decoder *d) { return d ? d->err : "out of memory"; }

static int apply(vsv_decoder *d, const unsigned char *c, int t, int s, int b, const unsigned char *be, uint16_t *codes,
                 int back);

/* Applies the brick entry `be` of chunk c (step t) to codes (back: undoes
 * it, a delta's entry only); a mapping cut by a truncation meanwhile (zeros
 * read) is an error, whatever they decoded to. Zeros are a valid EMPTY
 * entry, so after one the file's size is looked at. */
static int apply_checked(vsv_decoder *d, const unsigned char *c, int t, int s, int b, const unsigned char *be,
                         uint16_t *codes, int back)
{
    const int rc = apply(d, c, t, s, b, be, codes, back);
    return vsv_file_cut_look(d->f, rc, rc || be[0] == VSV_BRICK_EMPTY, d->err, sizeof d->err);
}

int vsv_decoder_apply(vsv_decoder *d, const unsigned char *c, int t, int s, int b, const unsigned char *be,
                      uint16_t *codes)
{
    return apply_checked(d, c, t, s, b, be, codes, 0);
}

static int apply(vsv_decoder *d, const unsigned char *c, int t, int s, int b, const unsigned char *be, uint16_t *codes,
                 int back)
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
    /* checked again where it is used: the entry was verified with its
     * chunk, but the mapping may have changed since (a file cut or
     * rewritten while it is read); the chunk's extent is the table's copy */
    const uint64_t csize = vsv_rd64(f->toc + (size_t)t * VSV_TOC_ENTRY_SIZE + 8);
    if (kind > vsv_file_last_kind(f) || off > csize || size > csize - off || !size ||
        (f->codec != VSV_CODEC_ZSTD && kind < VSV_BRICK_ABS3R && size != raw)) {
        vsv_msg(d->err, sizeof d->err, "%s: chunk %d, species %d, brick %d: brick entry changed after it was checked",
                f->name, t, s, b);
        return VSV_ECORRUPT;
    }
    const unsigned char *p = c + off;
    if (f->src) { /* fetch the payload, and the species' payloads after it */
        const uint64_t at = (uint64_t)(p - f->data),
                       end = __atomic_load_n(&f->span_end[(size_t)t * f->meta.nvars + s], __ATOMIC_RELAXED);
        const int rc = vsv_file_need(f, at, size, end > at + size ? end - at - size : 0, d->err, sizeof d->err);
        if (rc)
            return rc;
    }
    uint32_t crc = vsv_crc32c(0, p, size);
    if (crc != vsv_rd32(be + 4) && vsv_file_refetch(f, (uint64_t)(p - f->data), size))
        crc = vsv_crc32c(0, p, size); /* a damaged cache, fetched again */
    if (crc != vsv_rd32(be + 4)) {
        vsv_msg(d->err, sizeof d->err, "%s: chunk %d, species %d, brick %d (offset %llu): payload checksum mismatch",
                f->name, t, s, b, (unsigned long long)(p - f->data));
        return VSV_ECORRUPT;
    }
    const unsigned char *src = p;
    if (kind >= VSV_BRICK_ABS3R) { /* read from a padded copy (vsv_rice_decode reads past the end) */
        const int fits = size <= vsv_rice_max(bits, (size_t)ext[0] * ext[1] * ext[2]);
        if (fits) {
            memcpy(d->rice, p, size);
            memset(d->rice + size, 0, VSV_RICE_PAD);
        }
        if (!fits || vsv_rice_decode(bits, ext, d->rice, size, d->zres)) {
            vsv_msg(d->err, sizeof d->err, "%s: chunk %d, species %d, brick %d (offset %llu): payload does not decode",
                    f->name, t, s, b, (unsigned long long)(p - f->data));
            return VSV_ECODEC;
        }
        vsv_brick_inverse_z(bits, vsv_brick_predictor(kind), d->zres, f->lay.brick, ext, codes, d->scratch, back);
        return 0;
    } else if (f->codec == VSV_CODEC_ZSTD) {
        size_t got = ZSTD_decompressDCtx(d->dctx, d->raw, raw, p, size);
        if (ZSTD_isError(got) || got != raw) {
            vsv_msg(d->err, sizeof d->err,
                    "%s: chunk %d, species %d, brick %d (offset %llu): payload does not decode (%s)", f->name, t, s, b,
                    (unsigned long long)(p - f->data), ZSTD_isError(got) ? ZSTD_getErrorName(got) : "wrong size");
            return VSV_ECODEC;
        }
        src = d->raw;
    }
    vsv_brick_inverse(bits, vsv_brick_predictor(kind), src, f->lay.brick, ext, codes, d->scratch, back);
    return 0;
}

/* The chunk index of step and the entry of brick b of species s in it,
 * the arguments checked; 0 or an error code with the reason in d->err. */
static int locate(vsv_decoder *d, int step, int s, int b, const unsigned char **c, const unsigned char **be)
{
    vsv_file *f = d->f;
    int rc = vsv_file_check_args(f, step, s, b, d->err, sizeof d->err);
    if (rc)
        return rc;
    if (!(*c = vsv_file_chunk_index(f, step, d->err, sizeof d->err)))
        return vsv_file_chunk_rc(f, d->err, sizeof d->err);
    *be = vsv_file_brick_entry(f, *c, s, b);
    return 0;
}

int vsv_decoder_brick_advance(vsv_decoder *d, int step, int s, int b, uint16_t *codes)
{
    const unsigned char *c = NULL, *be = NULL;
    const int rc = locate(d, step, s, b, &c, &be);
    return rc ? rc : vsv_decoder_apply(d, c, step, s, b, be, codes);
}

int vsv_decoder_brick_retreat(vsv_decoder *d, int step, int s, int b, uint16_t *codes)
{
    const unsigned char *c = NULL, *be = NULL;
    const int rc = locate(d, step, s, b, &c, &be);
    if (rc)
        return rc;
    if (vsv_brick_absolute(be[0])) {
        vsv_msg(d->err, sizeof d->err, "%s: chunk %d, species %d, brick %d: an absolute state cannot be undone",
                d->f->name, step, s, b);
        return VSV_EINVAL;
    }
    return apply_checked(d, c, step, s, b, be, codes, 1);
}

/* vsv_decoder_brick_codes, the cells outside the grid zeroed when outside
 * is set, else left as they are (a whole volume's decode never reads them:
 * neither zeroed nor, for the first time, touched). */
static int brick_codes(vsv_decoder *d, int step, int s, int b, uint16_t *codes, int outside)
{
    vsv_file *f = d->f;
    int rc = vsv_file_check_args(f, step, s, b, d->err, sizeof d->err);
    if (rc)
        return rc;
    int org[3], ext[3];
    vsv_layout_box(&f->lay, b, org, ext);
    if (outside && (ext[0] < f->lay.brick || ext[1] < f->lay.brick || ext[2] < f->lay.brick))
        memset(codes, 0, (size_t)f->lay.brick * f->lay.brick * f->lay.brick * sizeof *codes);
    /* walk back to the brick's last absolute state (never past a keyframe) */
    int t0 = step;
    for (;;) {
        const unsigned char *c = vsv_file_chunk_index(f, t0, d->err, sizeof d->err);
        if (!c)
            return vsv_file_chunk_rc(f, d->err, sizeof d->err);
        const int kind = vsv_file_brick_entry(f, c, s, b)[0];
        if (vsv_brick_absolute(kind))
            break;
        /* keyframes hold only absolute kinds (checked), so t0 stays >= 0,
         * unless the mapping changed since */
        if (t0-- == 0) {
            vsv_msg(d->err, sizeof d->err,
                    "%s: chunk 0, species %d, brick %d: brick entry changed after it was checked", f->name, s, b);
            return vsv_file_cut(f, VSV_ECORRUPT, d->err, sizeof d->err);
        }
    }
    for (int t = t0; t <= step; t++) {
        const unsigned char *c = vsv_file_chunk_index(f, t, d->err, sizeof d->err);
        if (!c)
            return vsv_file_chunk_rc(f, d->err, sizeof d->err);
        if ((rc = vsv_decoder_apply(d, c, t, s, b, vsv_file_brick_entry(f, c, s, b), codes)))
            return rc;
    }
    return 0;
}

int vsv_decoder_brick_codes(vsv_decoder *d, int step, int s, int b, uint16_t *codes)
{
    return brick_codes(d, step, s, b, codes, 1);
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

/* Linear 16-bit codes to values by the rule of SPEC.md §6 itself, in double
 * as vsv_quant_value does (so bit-identical to the table), with f = 1 when
 * code 0 means no data: a loop the compiler vectorises (the table lookup it
 * replaces, 256 kB, one load a voxel, was a third of a full decode). rows
 * rows of n codes, cs apart, to rows of n values, os apart. */
VSV_CLONES("avx2")
static void dequant_linear16(double lo, double step, int f, const uint16_t *codes, size_t n, int rows, size_t cs,
                             float *out, size_t os)
{
    const float nan = NAN;
    uint32_t qnan;
    memcpy(&qnan, &nan, sizeof qnan);
    for (int r = 0; r < rows; r++, codes += cs, out += os) {
        if (f) {
            for (size_t i = 0; i < n; i++) { /* select without a branch */
                const int c = codes[i];
                const float v = (float)(lo + (double)(c - 1) * step);
                uint32_t u;
                memcpy(&u, &v, sizeof u);
                const uint32_t none = 0u - (uint32_t)(c == 0);
                u = (u & ~none) | (qnan & none);
                memcpy(&out[i], &u, sizeof u);
            }
        } else {
            for (size_t i = 0; i < n; i++)
                out[i] = (float)(lo + (double)codes[i] * step);
        }
    }
}

/* vsv_file_dequantise of rows rows of n codes, cs apart, to rows os apart. */
static void dequantise_rows(vsv_file *f, int s, const uint16_t *codes, size_t n, int rows, size_t cs, float *out,
                            size_t os)
{
    const vsv_quant *q = &f->quant[s];
    if (q->scale == VSV_SCALE_LINEAR && q->bits == 16) {
        const int m = q->missing ? 1 : 0; /* step = vsv_quant_value's */
        dequant_linear16(q->lo, (q->hi - q->lo) / (65535.0 - m), m, codes, n, rows, cs, out, os);
        return;
    }
    const float *l = lut_of(f, s);
    for (int r = 0; r < rows; r++, codes += cs, out += os) {
        if (l) {
            for (size_t i = 0; i < n; i++)
                out[i] = l[codes[i]];
        } else {
            for (size_t i = 0; i < n; i++)
                out[i] = vsv_quant_value(q, codes[i]);
        }
    }
}

void vsv_file_dequantise(const vsv_file *f, int s, const uint16_t *codes, size_t n, float *out)
{
    dequantise_rows((vsv_file *)f, s, codes, n, 1, 0, out, 0);
}

/* n copies of v at out. */
static void fill(float *out, size_t n, float v)
{
    for (size_t i = 0; i < n; i++)
        out[i] = v;
}

void vsv_file_dequantise_brick(const vsv_file *cf, int s, int b, const uint16_t *codes, float *out)
{
    vsv_file *f = (vsv_file *)cf;
    const size_t B = (size_t)f->lay.brick;
    int org[3], ext[3];
    vsv_layout_box(&f->lay, b, org, ext);
    const float ev = vsv_quant_value(&f->quant[s], 0);
    for (int k = 0; k < (int)B; k++) { /* inside the grid a plane's rows a call; the rest filled */
        float *const plane = out + (size_t)k * B * B;
        if (k >= ext[2]) {
            fill(plane, B * B, ev);
            continue;
        }
        dequantise_rows(f, s, codes + (size_t)k * B * B, (size_t)ext[0], ext[1], B, plane, B);
        for (int j = 0; j < ext[1] && ext[0] < (int)B; j++)
            fill(plane + j * B + ext[0], B - (size_t)ext[0], ev);
        fill(plane + (size_t)ext[1] * B, (B - (size_t)ext[1]) * B, ev);
    }
}

/* The mask of the placement in force at step (NULL: nothing below ground). */
static const uint16_t *step_under(const vsv_decoder *d, int step)
{
    const vsv_meta *m = &d->f->meta;
    const int64_t t = vsv_file_time(d->f, step);
    int i = 0;
    while (i < m->nmoves && m->moves[i].time <= t)
        i++;
    return d->under[i];
}

int vsv_decoder_brick(vsv_decoder *d, int step, int s, int b, float *out)
{
    int rc = vsv_decoder_brick_codes(d, step, s, b, d->codes);
    if (rc)
        return rc;
    const vsv_layout *L = &d->f->lay;
    const int n = L->brick;
    vsv_file_dequantise_brick(d->f, s, b, d->codes, out);
    const uint16_t *under = step_under(d, step);
    if (under) { /* below the ground: no data, whatever the species */
        int org[3], ext[3];
        vsv_layout_box(L, b, org, ext);
        for (int j = 0; j < ext[1]; j++)
            for (int i = 0; i < ext[0]; i++) {
                const int top = under[(size_t)(org[1] + j) * d->f->meta.nx + org[0] + i] - org[2];
                for (int k = 0; k < top && k < ext[2]; k++)
                    out[((size_t)k * n + j) * n + i] = NAN;
            }
    }
    return 0;
}

/* The decoder keeps the codes of the last step it decoded per species, so a
 * forward sequential read costs one delta per brick and step. */
int vsv_decoder_volume(vsv_decoder *d, int step, int s, float *out)
{
    vsv_file *f = d->f;
    int rc = vsv_file_check_args(f, step, s, 0, d->err, sizeof d->err);
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
            rc = brick_codes(d, step, s, b, codes, 0);
        }
        if (rc)
            return rc;
        int org[3], ext[3];
        vsv_layout_box(L, b, org, ext);
        for (int k = 0; k < ext[2]; k++) /* a plane of the brick a call */
            dequantise_rows(f, s, codes + (size_t)k * L->brick * L->brick, (size_t)ext[0], ext[1], (size_t)L->brick,
                            out + ((size_t)(org[2] + k) * f->meta.ny + (size_t)org[1]) * f->meta.nx + org[0],
                            (size_t)f->meta.nx);
    }
    d->state_step[s] = step;
    const uint16_t *under = step_under(d, step);
    if (under) { /* below the ground: no data, whatever the species */
        const size_t plane = (size_t)f->meta.nx * f->meta.ny;
        for (size_t c = 0; c < plane; c++)
            for (int k = 0; k < under[c]; k++)
                out[(size_t)k * plane + c] = NAN;
    }
    return 0;
}
