/* vsv_writer.c — the streaming .vsv writer. Steps are spooled as raw floats
 * to an unlinked temporary file (quantisation needs each species' range over
 * all steps before the first brick is coded); finish() then plans the file
 * and encodes every step in parallel (vsv_encode.c: a step's chunk depends
 * only on the fields of that step and the one before, both in the spool),
 * and writes the chunks in time order to a temporary name that is renamed
 * into place only when everything succeeded. When the caller knows the
 * steps' statistics in advance (vsv_writer_expect), the plan is made at
 * once and the steps are encoded as they come, from a ring of a few in
 * memory, with no spool: the same bytes. */
#include "vsv_format_internal.h"

#include <errno.h>
#include <fcntl.h>
#include <libgen.h>
#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdlib.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

struct vsv_writer {
    char *path, *tmp;
    int spool_fd, out_fd;
    vsv_meta meta;
    vsv_pack_opts opts;
    vsv_pack_var *vars;
    size_t cells;
    int64_t *times;
    int nsteps, cap_steps, finished;
    vsv_pack_stats *st;
    const float *spool;
    size_t spool_bytes;
    /* vsv_writer_expect: the plan made up front, the statistics promised,
     * the encoders, a ring of the last nring steps, the chunks' sizes and
     * where the next goes; encoded: steps whose chunks are written */
    vsv_pack_plan *plan;
    vsv_pack_stats *promised;
    vsv_chunk_encoder *enc[64];
    int nenc, nring, encoded;
    float *ring;
    uint64_t *sizes, off;
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
    o->predict = 2;
}

const char *vsv_writer_error(const vsv_writer *w) { return w ? w->err : "out of memory"; }

static int fail_errno(vsv_writer *w, const char *what)
{
    vsv_msg(w->err, sizeof w->err, "%s: %s", what, vsv_errno_text(errno));
    return VSV_EIO;
}

/* A failure's message where the step that failed left none (an allocation
 * that failed says nothing): the code's text and what was being done. */
static int said(vsv_writer *w, int rc, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static int said(vsv_writer *w, int rc, const char *fmt, ...)
{
    if (rc && !w->err[0]) {
        char doing[200];
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(doing, sizeof doing, fmt, ap);
        va_end(ap);
        vsv_msg(w->err, sizeof w->err, "%s %s", vsv_strerror(rc), doing);
    }
    return rc;
}

static int create_body(vsv_writer *w, const char *path, const vsv_meta *meta, const vsv_pack_opts *opts)
{
    w->path = strdup(path);
    if (!w->path)
        return VSV_ENOMEM;
    if (vsv_meta_validate(meta, w->err, sizeof w->err))
        return VSV_EINVAL;
    if (opts)
        w->opts = *opts;
    else
        vsv_pack_opts_init(&w->opts);
    if (vsv_pack_opts_check(&w->opts, meta, w->err, sizeof w->err))
        return VSV_EINVAL;
    int rc = vsv_meta_copy(&w->meta, meta);
    if (rc)
        return rc;
    const int nv = meta->nvars;
    w->vars = calloc((size_t)nv, sizeof *w->vars);
    w->st = calloc((size_t)nv, sizeof *w->st);
    if (!w->vars || !w->st)
        return VSV_ENOMEM;
    for (int v = 0; v < nv; v++)
        if (opts && opts->vars)
            w->vars[v] = opts->vars[v];
        else
            vsv_pack_var_init(&w->vars[v]);
    w->opts.vars = w->vars;
    vsv_pack_stats_init(w->st, nv);
    w->cells = (size_t)meta->nx * (size_t)meta->ny * (size_t)meta->nz;
    /* the spool: a listed temporary unlinked at once (a signal in between
     * leaves nothing) */
    char tmp[4200];
    w->spool_fd = vsv_output_temp(path, ".spool", tmp, sizeof tmp);
    if (w->spool_fd < 0)
        return fail_errno(w, "cannot create a temporary file beside it");
    vsv_output_discard(tmp);
    return 0;
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
    return said(w, create_body(w, path, meta, opts), "setting the writer up");
}

static int encode_steps(vsv_writer *w, int t0, int t1, void (*progress)(void *, int, int), void *ctx);

static int add_step_body(vsv_writer *w, int64_t time, const float *const *fields)
{
    if (w->finished || (w->spool_fd < 0 && !w->ring))
        return VSV_EINVAL;
    if (!VSV_TIME_OK(time)) {
        vsv_msg(w->err, sizeof w->err, "step %d: time %lld is outside the years 1..9999", w->nsteps, (long long)time);
        return VSV_EINVAL;
    }
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
        if (w->ring) {
            uint64_t *sz = realloc(w->sizes, (size_t)cap * sizeof *sz);
            if (!sz)
                return VSV_ENOMEM;
            w->sizes = sz;
        }
    }
    vsv_pack_stats_add(w->st, w->meta.nvars, w->cells, fields);
    if (w->ring) { /* into the ring; a full batch is encoded at once */
        float *slot = w->ring + (size_t)(w->nsteps % w->nring) * (size_t)w->meta.nvars * w->cells;
        for (int v = 0; v < w->meta.nvars; v++)
            memcpy(slot + (size_t)v * w->cells, fields[v], w->cells * sizeof(float));
        w->times[w->nsteps++] = time;
        if (w->nsteps - w->encoded == w->nring - 1)
            return encode_steps(w, w->encoded, w->nsteps, NULL, NULL);
        return 0;
    }
    for (int v = 0; v < w->meta.nvars; v++)
        if (vsv_write_full(w->spool_fd, fields[v], w->cells * 4, -1))
            return fail_errno(w, "writing the spool file");
    w->times[w->nsteps++] = time;
    return 0;
}

/* ---------------------------------------------------------------- encoding */

/* One thread's job: the chunk of step t from the spool. */
typedef struct job {
    const vsv_writer *w;
    vsv_chunk_encoder *enc;
    int t, rc;
    const unsigned char *bytes;
    size_t size;
} job;

/* The fields of step t: in the spool, or in the ring. */
static void spool_fields(const vsv_writer *w, int t, const float **f)
{
    const float *base = w->ring ? w->ring + (size_t)(t % w->nring) * (size_t)w->meta.nvars * w->cells
                                : w->spool + (size_t)t * (size_t)w->meta.nvars * w->cells;
    for (int v = 0; v < w->meta.nvars; v++)
        f[v] = base + (size_t)v * w->cells;
}

static void *job_run(void *arg)
{
    job *j = arg;
    const int nv = j->w->meta.nvars;
    const float **cur = malloc(2 * (size_t)nv * sizeof *cur);
    if (!cur) {
        j->rc = VSV_ENOMEM;
        return NULL;
    }
    const float **prev = cur + nv;
    spool_fields(j->w, j->t, cur);
    if (j->t)
        spool_fields(j->w, j->t - 1, prev);
    j->rc = vsv_chunk_encode(j->enc, j->t, j->w->times[j->t], cur, j->t ? prev : NULL, &j->bytes, &j->size);
    free(cur);
    return NULL;
}

/* The encoders over the plan, one a thread (made once). */
static int encoders(vsv_writer *w, const vsv_pack_plan *plan)
{
    if (w->nenc)
        return 0;
    int nth = w->opts.threads > 0 ? w->opts.threads : vsv_ncpus();
    nth = nth < 1 ? 1 : nth > 64 ? 64 : nth;
    for (int i = 0; i < nth; i++) {
        int rc = vsv_chunk_encoder_create(plan, &w->enc[i]);
        if (rc)
            return rc;
        w->nenc++;
    }
    return 0;
}

/* Encodes steps t0..t1-1 in parallel batches and writes their chunks in
 * order at w->off. */
static int encode_steps(vsv_writer *w, int t0, int t1, void (*progress)(void *, int, int), void *ctx)
{
    int rc = 0;
    const int nth = w->nenc;
    for (int b0 = t0; !rc && b0 < t1; b0 += nth) {
        const int cnt = t1 - b0 < nth ? t1 - b0 : nth;
        job jobs[64];
        pthread_t tid[64];
        int started[64] = {0};
        for (int i = 0; i < cnt; i++) {
            jobs[i] = (job){w, w->enc[i], b0 + i, 0, NULL, 0};
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
            if (jobs[i].rc) {
                rc = jobs[i].rc;
                vsv_msg(w->err, sizeof w->err, "encoding step %d: %s", b0 + i,
                        rc == VSV_ENOMEM ? vsv_strerror(rc) : vsv_chunk_encoder_error(w->enc[i]));
                break;
            }
            w->sizes[b0 + i] = jobs[i].size;
            if (vsv_write_full(w->out_fd, jobs[i].bytes, jobs[i].size, (int64_t)w->off))
                rc = fail_errno(w, "writing a chunk");
            w->off += jobs[i].size;
        }
        if (!rc)
            w->encoded = b0 + cnt;
        if (progress && !rc)
            progress(ctx, b0 + cnt, t1);
    }
    return rc;
}

/* The temporary output beside the path, with the plan's metadata written. */
static int start_output(vsv_writer *w, const vsv_pack_plan *plan)
{
    char tmp[4200];
    w->out_fd = vsv_output_temp(w->path, NULL, tmp, sizeof tmp);
    if (w->out_fd < 0 || !(w->tmp = strdup(tmp))) {
        if (w->out_fd >= 0) {
            close(w->out_fd);
            w->out_fd = -1;
            vsv_output_discard(tmp);
        }
        return fail_errno(w, "cannot create the temporary output");
    }
    const uint64_t meta_off = VSV_HEADER_SIZE;
    w->off = vsv_pack_plan_first_chunk(plan);
    if (vsv_write_full(w->out_fd, vsv_pack_plan_meta_bytes(plan), w->off - meta_off, (int64_t)meta_off))
        return fail_errno(w, "writing metadata");
    return 0;
}

int vsv_writer_add_step(vsv_writer *w, int64_t time, const float *const *fields)
{
    return said(w, add_step_body(w, time, fields), "adding step %d", w->nsteps);
}

static int expect_body(vsv_writer *w, const vsv_pack_stats *stats)
{
    if (w->finished || w->nsteps || w->plan || w->spool_fd < 0)
        return VSV_EINVAL;
    const int nv = w->meta.nvars;
    int rc = vsv_pack_plan_create(&w->meta, &w->opts, stats, &w->plan);
    if (rc) {
        vsv_msg(w->err, sizeof w->err, "%s", rc == VSV_ENOMEM ? vsv_strerror(rc) : vsv_pack_plan_error(w->plan));
        vsv_pack_plan_free(w->plan);
        w->plan = NULL;
        return rc;
    }
    if ((rc = encoders(w, w->plan)))
        return rc;
    /* a batch of as many steps as encoders, and the one before it */
    w->nring = w->nenc + 1;
    w->promised = malloc((size_t)nv * sizeof *w->promised);
    w->ring = malloc((size_t)w->nring * (size_t)nv * w->cells * sizeof(float));
    w->sizes = malloc((size_t)(w->cap_steps > 0 ? w->cap_steps : 1) * sizeof *w->sizes);
    if (!w->promised || !w->ring || !w->sizes)
        return VSV_ENOMEM;
    memcpy(w->promised, stats, (size_t)nv * sizeof *stats);
    close(w->spool_fd);
    w->spool_fd = -1;
    return start_output(w, w->plan);
}

int vsv_writer_expect(vsv_writer *w, const vsv_pack_stats *stats)
{
    return said(w, expect_body(w, stats), "planning the encoding");
}

/* 1 when the statistics of the steps added are the ones promised. */
static int kept_promise(const vsv_writer *w)
{
    for (int v = 0; v < w->meta.nvars; v++) {
        const vsv_pack_stats *a = &w->st[v], *b = &w->promised[v];
        if (a->min != b->min || a->max != b->max || a->minpos != b->minpos || (a->nonfinite > 0) != (b->nonfinite > 0))
            return 0;
    }
    return 1;
}

static int finish_body(vsv_writer *w, void (*progress)(void *, int, int), void *ctx)
{
    if (w->nsteps < 1) {
        vsv_msg(w->err, sizeof w->err, "no time steps to write");
        return VSV_EINVAL;
    }
    int rc = 0;
    const size_t tail_bytes = vsv_pack_tail_bytes(w->nsteps);
    unsigned char *tail = malloc(tail_bytes), head[VSV_HEADER_SIZE];
    if (!tail)
        return VSV_ENOMEM;
    if (w->ring) { /* planned: the steps left in the ring */
        if (!kept_promise(w)) {
            vsv_msg(w->err, sizeof w->err, "the steps added do not have the statistics promised for them");
            rc = VSV_EINVAL;
            goto done;
        }
        if ((rc = encode_steps(w, w->encoded, w->nsteps, NULL, NULL)))
            goto done;
        if (progress)
            progress(ctx, w->nsteps, w->nsteps);
    } else {
        if ((rc = vsv_pack_plan_create(&w->meta, &w->opts, w->st, &w->plan))) {
            vsv_msg(w->err, sizeof w->err, "%s", rc == VSV_ENOMEM ? vsv_strerror(rc) : vsv_pack_plan_error(w->plan));
            goto done;
        }
        w->sizes = calloc((size_t)w->nsteps, sizeof *w->sizes);
        if (!w->sizes) {
            rc = VSV_ENOMEM;
            goto done;
        }
        w->spool_bytes = (size_t)w->nsteps * (size_t)w->meta.nvars * w->cells * 4;
        void *map = mmap(NULL, w->spool_bytes, PROT_READ, MAP_PRIVATE, w->spool_fd, 0);
        if (map == MAP_FAILED) {
            rc = fail_errno(w, "mapping the spool file");
            goto done;
        }
        w->spool = map;
        madvise(map, w->spool_bytes, MADV_SEQUENTIAL);
        if ((rc = start_output(w, w->plan)) || (rc = encoders(w, w->plan)) ||
            (rc = encode_steps(w, 0, w->nsteps, progress, ctx)))
            goto done;
    }
    uint64_t tail_off;
    if ((rc = vsv_pack_plan_finish(w->plan, w->nsteps, w->times, w->sizes, head, tail, &tail_off))) {
        vsv_msg(w->err, sizeof w->err, "%s", vsv_pack_plan_error(w->plan));
        goto done;
    }
    if (vsv_write_full(w->out_fd, tail, tail_bytes, (int64_t)tail_off)) {
        rc = fail_errno(w, "writing the table of contents");
        goto done;
    }
    if (vsv_write_full(w->out_fd, head, sizeof head, 0)) {
        rc = fail_errno(w, "writing the header");
        goto done;
    }
    /* synced and closed (a full disk shows here at the latest), renamed,
     * the directory synced */
    const int fd = w->out_fd;
    w->out_fd = -1;
    if (vsv_output_seal(fd)) {
        rc = fail_errno(w, "writing the output (fsync, close)");
        goto done;
    }
    if (vsv_output_publish(w->tmp, w->path)) {
        rc = fail_errno(w, "renaming the temporary output into place");
        goto done;
    }
    free(w->tmp);
    w->tmp = NULL;
done:
    free(tail);
    return rc;
}

int vsv_writer_finish(vsv_writer *w, void (*progress)(void *, int, int), void *ctx)
{
    if (w->finished)
        return VSV_EINVAL;
    w->finished = 1;
    int rc = said(w, finish_body(w, progress, ctx), "encoding the %d steps", w->nsteps);
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
        vsv_output_discard(w->tmp);
        free(w->tmp);
    }
    for (int i = 0; i < w->nenc; i++)
        vsv_chunk_encoder_free(w->enc[i]);
    vsv_pack_plan_free(w->plan);
    free(w->promised);
    free(w->ring);
    free(w->sizes);
    vsv_meta_clear(&w->meta);
    free(w->path);
    free(w->vars);
    free(w->st);
    free(w->times);
    free(w);
}
