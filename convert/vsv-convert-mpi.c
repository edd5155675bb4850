/* vsv-convert-mpi — vsv-convert across the ranks of an MPI job: the same
 * options, inputs and output bytes. The output steps are cut into whole
 * shares of equal length, one a rank (a step's chunk depends only on its
 * fields and the previous step's, none at a keyframe: a share that starts
 * inside a keyframe group makes the step before it too, as a share makes
 * the input frame before its first step for the interpolation); each rank
 * reads the input frames its steps need, spools its frames locally, and after one reduction of the value ranges
 * (the quantisation needs them over all steps) encodes its chunks. The
 * chunks are written once, at their final offsets, by collective MPI-IO
 * writes into a temporary file beside the output; rank 0 then writes the
 * table of contents and the header, and renames the file into place. A
 * failure on any rank stops every rank (a STOP message between steps, an
 * agreement at the end of each phase): one message names the rank and the
 * file, nothing is left behind, and every rank exits 1. */
#include "vsv_common.h"
#include "vsv_mpi_cli.h"
#include "vsv_vdb.h"

#include <errno.h>
#include <fcntl.h>
#include <libgen.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#define PIECE ((size_t)64 << 20) /* bytes per collective write */

/* clang-format off */ /* (the help text as it prints, a line a line) */
static const char usage[] =
    "Usage: mpirun -np N vsv-convert-mpi [OPTIONS] FILE... -o OUT.vsv\n"
    "vsv-convert on the N ranks of an MPI job: the same options and inputs, and\n"
    "byte for byte the same file. Each rank reads and encodes an equal share of the\n"
    "output steps; the chunks are written once at their\n"
    "final offsets by collective MPI-IO into a temporary file beside OUT, which\n"
    "appears only when every rank succeeded. Frames are spooled in $TMPDIR (or /tmp)\n"
    "of each rank's node; each rank encodes on one thread (run one rank a core).\n"
    "Reads, detected from the content (never the name):\n" VSV_CLI_MODEL_FORMATS VSV_CLI_VDB_FORMAT
    "Writes the .vsv format (vsv(5)).\n"
    "\n";
/* clang-format on */

/* ------------------------------------------------------ the steps' plan */

typedef struct steps {
    int64_t *t;
    int n, cap;
} steps;

static int add_time(void *p, int64_t t, const float *const *fields)
{
    (void)fields;
    steps *s = p;
    if (s->n == s->cap) {
        int cap = s->cap ? 2 * s->cap : 1024;
        int64_t *nt = cap > 0 ? realloc(s->t, (size_t)cap * sizeof *nt) : NULL;
        if (!nt)
            return VSV_ENOMEM;
        s->t = nt;
        s->cap = cap;
    }
    s->t[s->n++] = t;
    return s->n > 10000000 ? VSV_ERANGE : 0;
}

/* The output times of the whole run, from the interpolation itself run
 * over the input times alone (no data read), so they are vsv-convert's;
 * then this rank's share of the steps and the input frames
 * they need. */
static void plan_steps(rank *r, int *dropped)
{
    const int n = vsv_run_nframes(r->run);
    steps s = {0};
    int rc = 0;
    *dropped = 0;
    if (!r->a.dt) {
        for (int i = 0; i < n && !rc; i++)
            rc = add_time(&s, vsv_run_time(r->run, i), NULL);
    } else {
        vsv_interp *ip = NULL;
        rc = vsv_interp_create(r->a.dt, 0, 0, add_time, &s, &ip);
        if (!rc)
            vsv_run_place(r->run, ip);
        for (int i = 0; i < n && !rc; i++)
            rc = vsv_interp_push(ip, vsv_run_time(r->run, i), NULL);
        *dropped = vsv_interp_dropped(ip);
        vsv_interp_free(ip);
    }
    if (rc) {
        free(s.t);
        rank_fail(r, "%s", rc == VSV_ERANGE ? "more than 10000000 output steps" : "out of memory");
        return;
    }
    r->times = s.t;
    r->nsteps = s.n;
    /* an even share of the steps; a share that starts inside a keyframe
     * group also makes the step before it (its first chunk is a delta) */
    const int K = r->a.pack.opts.keyframe > 0 ? r->a.pack.opts.keyframe : 8;
    r->s0 = (int)((long long)r->nsteps * r->me / r->np);
    r->s1 = (int)((long long)r->nsteps * (r->me + 1) / r->np);
    r->lead = r->s0 < r->s1 && r->s0 % K ? 1 : 0;
    r->f0 = 0;
    r->f1 = -1;
    if (r->s0 < r->s1) {
        /* the last input at or before the first step, the first at or after the last */
        int a = 0, b = n - 1;
        while (a + 1 < n && vsv_run_time(r->run, a + 1) <= r->times[r->s0 - r->lead])
            a++;
        while (b > 0 && vsv_run_time(r->run, b - 1) >= r->times[r->s1 - 1])
            b--;
        r->f0 = a;
        r->f1 = b;
    }
    r->step_bytes = r->nsteps ? (double)vsv_run_input_bytes(r->run) / r->nsteps : 0;
}

/* --------------------------------------------------------------- phases */

/* Receives the frames of the rank's input range: keeps those of its steps. */
static int keep(void *p, int64_t t, const float *const *fields)
{
    rank *r = p;
    if (r->stopped)
        return VSV_EAGAIN;
    if (t < r->times[r->s0 - r->lead] || t > r->times[r->s1 - 1])
        return 0;
    const int s = r->s0 - r->lead + r->spooled;
    if (s >= r->s1 || r->times[s] != t) {
        rank_fail(r, "internal error: frame at %lld is not step %d", (long long)t, s);
        return VSV_EINVAL;
    }
    if (s >= r->s0) /* the step before the share is another rank's */
        vsv_pack_stats_add(r->st, r->meta->nvars, r->cells, fields);
    for (int v = 0; v < r->meta->nvars; v++)
        if (vsv_write_full(r->spool_fd, fields[v], r->cells * sizeof(float), -1)) {
            rank_fail(r, "writing the spool file: %s", strerror(errno));
            return VSV_EIO;
        }
    r->spooled++;
    if (s >= r->s0)
        rank_step_done(r, PHASE_READ, s - r->s0 + 1);
    return r->stopped ? VSV_EAGAIN : 0;
}

static void read_phase(rank *r)
{
    r->t_phase = mpi_now();
    const int nv = r->in->nvars;
    r->st = calloc((size_t)r->meta->nvars, sizeof *r->st);
    float **fields = calloc((size_t)nv, sizeof *fields);
    if (!r->st || !fields)
        rank_fail(r, "out of memory");
    for (int v = 0; !r->failed && v < nv; v++)
        if (!(fields[v] = malloc(r->cells * sizeof(float))))
            rank_fail(r, "out of memory");
    if (!r->failed) {
        vsv_pack_stats_init(r->st, r->meta->nvars);
        r->spool_fd = local_temp(r, "spool");
    }
    if (!r->failed && r->s0 < r->s1) {
        int bad, dropped;
        if (vsv_convert_frames(r->run, r->a.dt, r->a.method, r->f0, r->f1, fields, keep, r, NULL, &bad, &dropped) &&
            !r->stopped) {
            if (bad >= 0)
                rank_fail(r, "%s", vsv_run_error(r->run));
            else if (bad == -2)
                rank_fail(r, "out of memory");
        }
        if (!r->failed && !r->stopped && r->spooled != r->s1 - r->s0 + r->lead)
            rank_fail(r, "internal error: %d of steps %d..%d made", r->spooled, r->s0, r->s1 - 1);
    }
    for (int v = 0; fields && v < nv; v++)
        free(fields[v]);
    free(fields);
    r->secs[0] = mpi_now() - r->t_phase;
}

/* The value ranges of every rank's steps, merged on all ranks. */
static void merge_stats(rank *r)
{
    const int nv = r->meta->nvars;
    double *d = malloc(3 * (size_t)nv * sizeof *d);
    uint64_t *u = malloc((size_t)nv * sizeof *u);
    for (int v = 0; v < nv; v++) {
        d[v] = r->st[v].min;
        d[nv + v] = -r->st[v].max;
        d[2 * nv + v] = r->st[v].minpos;
        u[v] = r->st[v].nonfinite;
    }
    MPI_Allreduce(MPI_IN_PLACE, d, 3 * nv, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD);
    MPI_Allreduce(MPI_IN_PLACE, u, nv, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
    for (int v = 0; v < nv; v++)
        r->st[v] = (vsv_pack_stats){d[v], -d[nv + v], d[2 * nv + v], u[v]};
    free(d);
    free(u);
}

static void encode_phase(rank *r, const vsv_pack_plan *plan)
{
    r->t_phase = mpi_now();
    const int nv = r->meta->nvars, n = r->s1 - r->s0;
    r->sizes = calloc((size_t)n + 1, sizeof *r->sizes);
    const float **cur = malloc(2 * ((size_t)nv + 1) * sizeof *cur), **prev = cur ? cur + nv + 1 : NULL;
    vsv_chunk_encoder *e = NULL;
    if (!r->sizes || !cur || vsv_chunk_encoder_create(plan, &e))
        rank_fail(r, "out of memory");
    if (!r->failed)
        r->chunk_fd = local_temp(r, "chunks");
    if (!r->failed && n > 0) {
        r->spool_bytes = (size_t)(n + r->lead) * nv * r->cells * sizeof(float);
        void *map = mmap(NULL, r->spool_bytes, PROT_READ, MAP_PRIVATE, r->spool_fd, 0);
        if (map == MAP_FAILED)
            rank_fail(r, "mapping the spool file: %s", vsv_errno_text(errno));
        else
            r->spool = map;
    }
    for (int i = 0; !r->failed && !r->stopped && i < n; i++) {
        const int k = i + r->lead; /* the step's frame in the spool */
        for (int v = 0; v < nv; v++) {
            cur[v] = r->spool + ((size_t)k * nv + v) * r->cells;
            prev[v] = k ? cur[v] - (size_t)nv * r->cells : NULL;
        }
        const unsigned char *bytes;
        size_t size;
        if (vsv_chunk_encode(e, r->s0 + i, r->times[r->s0 + i], cur, k ? prev : NULL, &bytes, &size)) {
            rank_fail(r, "encoding step %d: %s", r->s0 + i, vsv_chunk_encoder_error(e));
            break;
        }
        if (vsv_write_full(r->chunk_fd, bytes, size, -1)) {
            rank_fail(r, "writing the chunk spool file: %s", strerror(errno));
            break;
        }
        r->sizes[i] = size;
        r->chunk_bytes += size;
        rank_step_done(r, PHASE_ENCODE, i + 1);
    }
    vsv_chunk_encoder_free(e);
    free(cur);
    if (r->spool) {
        munmap(r->spool, r->spool_bytes);
        r->spool = NULL;
    }
    r->secs[1] = mpi_now() - r->t_phase;
}

/* Every rank writes its chunks at their offsets (collective writes of at
 * most PIECE bytes, as many rounds on every rank), then rank 0 the
 * metadata, the table of contents and the header. */
static void write_phase(rank *r, vsv_pack_plan *plan)
{
    r->t_phase = mpi_now();
    const int n = r->s1 - r->s0;
    uint64_t base = 0;
    MPI_Exscan(&r->chunk_bytes, &base, 1, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
    if (!r->me)
        base = 0;
    base += vsv_pack_plan_first_chunk(plan);
    /* rank 0 gathers every chunk's size for the table of contents */
    int *counts = NULL, *displs = NULL;
    uint64_t *all = NULL;
    if (!r->me) {
        counts = calloc((size_t)r->np, sizeof *counts);
        displs = calloc((size_t)r->np, sizeof *displs);
        all = calloc((size_t)r->nsteps + 1, sizeof *all);
    }
    MPI_Gather(&n, 1, MPI_INT, counts, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (!r->me)
        for (int p = 1; p < r->np; p++)
            displs[p] = displs[p - 1] + counts[p - 1];
    MPI_Gatherv(r->sizes, n, MPI_UINT64_T, all, counts, displs, MPI_UINT64_T, 0, MPI_COMM_WORLD);

    MPI_File fh;
    int rc = MPI_File_open(MPI_COMM_WORLD, r->tmp ? r->tmp : "", MPI_MODE_WRONLY, MPI_INFO_NULL, &fh);
    if (rc != MPI_SUCCESS) {
        rank_mpi_fail(r, rc, "opening the temporary output");
        free(counts);
        free(displs);
        free(all);
        return;
    }
    MPI_File_set_errhandler(fh, MPI_ERRORS_RETURN);
    unsigned char *chunks = NULL;
    if (r->chunk_bytes) {
        void *map = mmap(NULL, r->chunk_bytes, PROT_READ, MAP_PRIVATE, r->chunk_fd, 0);
        if (map == MAP_FAILED)
            rank_fail(r, "mapping the chunk spool file: %s", vsv_errno_text(errno));
        else
            chunks = map;
    }
    long long rounds = chunks ? (long long)((r->chunk_bytes + PIECE - 1) / PIECE) : 0;
    MPI_Allreduce(MPI_IN_PLACE, &rounds, 1, MPI_LONG_LONG, MPI_MAX, MPI_COMM_WORLD);
    for (long long i = 0; i < rounds; i++) {
        const uint64_t at = (uint64_t)i * PIECE;
        size_t len = chunks && at < r->chunk_bytes ? (size_t)(r->chunk_bytes - at) : 0;
        if (len > PIECE)
            len = PIECE;
        if (r->failed)
            len = 0; /* still in every round, so no rank waits for it */
        MPI_Status st;
        rc = MPI_File_write_at_all(fh, (MPI_Offset)(base + at), chunks ? chunks + at : NULL, (int)len, MPI_BYTE, &st);
        int got = 0;
        if (rc == MPI_SUCCESS)
            MPI_Get_count(&st, MPI_BYTE, &got);
        if (rc != MPI_SUCCESS)
            rank_mpi_fail(r, rc, "writing the chunks");
        else if ((size_t)got != len)
            rank_fail(r, "%s: writing the chunks: %d of %zu bytes written", r->a.out, got, len);
    }
    if (chunks)
        munmap(chunks, r->chunk_bytes);
    if ((rc = MPI_File_sync(fh)) != MPI_SUCCESS)
        rank_mpi_fail(r, rc, "syncing the chunks");
    if (!r->me && !r->failed) {
        /* the table of contents last, then the header that points to it */
        const size_t tail_bytes = vsv_pack_tail_bytes(r->nsteps);
        unsigned char *tail = malloc(tail_bytes), head[128];
        uint64_t tail_off = 0;
        if (!tail)
            rank_fail(r, "out of memory");
        else if (vsv_pack_plan_finish(plan, r->nsteps, r->times, all, head, tail, &tail_off))
            rank_fail(r, "%s: %s", r->a.out, vsv_pack_plan_error(plan));
        const uint64_t first = vsv_pack_plan_first_chunk(plan);
        MPI_Status st;
        if (!r->failed &&
            ((rc = MPI_File_write_at(fh, 128, vsv_pack_plan_meta_bytes(plan), (int)(first - 128), MPI_BYTE, &st)) ||
             (rc = MPI_File_write_at(fh, (MPI_Offset)tail_off, tail, (int)tail_bytes, MPI_BYTE, &st)) ||
             (rc = MPI_File_write_at(fh, 0, head, 128, MPI_BYTE, &st))))
            rank_mpi_fail(r, rc, "writing the table of contents and the header");
        free(tail);
    }
    if ((rc = MPI_File_sync(fh)) != MPI_SUCCESS)
        rank_mpi_fail(r, rc, "syncing the file");
    if ((rc = MPI_File_close(&fh)) != MPI_SUCCESS)
        rank_mpi_fail(r, rc, "closing the file");
    free(counts);
    free(displs);
    free(all);
    r->secs[2] = mpi_now() - r->t_phase;
}

/* Rank 0 renames the complete file into place. */
static void publish(rank *r)
{
    int ok = 1;
    if (!r->me && vsv_output_publish(r->tmp, r->a.out)) {
        rank_fail(r, "%s: renaming the temporary output into place: %s", r->a.out, strerror(errno));
        ok = 0;
    }
    MPI_Bcast(&ok, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (ok) { /* renamed (a rank that removes the name meanwhile finds none) */
        vsv_output_forget(r->tmp);
        free(r->tmp);
        r->tmp = NULL;
    }
    if (!ok)
        rank_give_up(r, 0);
}

static void print_stats(rank *r, double wall)
{
    double mine[4] = {r->secs[0], r->secs[1], r->secs[2], (double)(r->s1 - r->s0)};
    double *all = r->me ? NULL : malloc(4 * (size_t)r->np * sizeof *all);
    MPI_Gather(mine, 4, MPI_DOUBLE, all, 4, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    uint64_t out = 0;
    MPI_Reduce(&r->chunk_bytes, &out, 1, MPI_UINT64_T, MPI_SUM, 0, MPI_COMM_WORLD);
    if (r->me)
        return;
    printf("rank  steps   read s  encode s  write s\n");
    for (int p = 0; p < r->np; p++)
        printf("%4d  %5.0f  %7.2f  %8.2f  %7.2f\n", p, all[4 * p + 3], all[4 * p], all[4 * p + 1], all[4 * p + 2]);
    printf("%d steps on %d ranks in %.2f s: %.1f MB of model input, %.1f MB of chunks, %.2f steps/s\n", r->nsteps,
           r->np, wall, (double)vsv_run_input_bytes(r->run) / 1e6, (double)out / 1e6, r->nsteps / wall);
    free(all);
}

/* Rank 0 makes the temporary output beside OUT (so the rename is atomic)
 * and tells the others its name. Every rank lists it (vsv_output.c), so
 * SIGINT, SIGTERM or SIGHUP on any rank removes it before the rank dies of
 * the signal (vsv_cli.c): a scheduler's time limit left OUT.tmp.XXXXXX
 * after every interrupted run. */
static void make_output(rank *r)
{
    int len = 0;
    if (!r->me) {
        const size_t n = strlen(r->a.out) + 64;
        char *name = malloc(n);
        const int fd = name ? vsv_output_temp(r->a.out, NULL, name, n) : -1;
        if (fd < 0) {
            rank_fail(r, "%s: cannot create a temporary file beside it: %s", r->a.out, strerror(name ? errno : ENOMEM));
            free(name);
        } else {
            close(fd); /* MPI-IO opens it by name */
            r->tmp = name;
            len = (int)strlen(name) + 1;
        }
    }
    MPI_Bcast(&len, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (r->me && len) {
        r->tmp = malloc((size_t)len); /* every rank opens it; rank 0 removes it */
        if (!r->tmp)
            MPI_Abort(MPI_COMM_WORLD, 1);
    }
    if (len)
        MPI_Bcast(r->tmp, len, MPI_CHAR, 0, MPI_COMM_WORLD);
    if (r->me && len)
        vsv_output_claim(r->tmp);
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    atexit(mpi_finalize_at_exit);
    static rank R;
    rank *r = &R;
    MPI_Comm_rank(MPI_COMM_WORLD, &r->me);
    MPI_Comm_size(MPI_COMM_WORLD, &r->np);
    r->spool_fd = r->chunk_fd = -1;
    r->t_start = mpi_now();
    r->done = calloc((size_t)r->np, sizeof *r->done);
    r->received = calloc((size_t)r->np, sizeof *r->received);
    vsv_cli_init("vsv-convert-mpi");
    vsv_vdb_source_register(); /* .vdb sequences too (interop/), as vsv-convert */
    quiet_others(r->me, 1);
    vsv_convert_args_parse(&r->a, argc, argv, usage, 1);
    vsv_cli_refuse_input(r->a.out, (const char *const *)r->a.inputs, r->a.ninputs);
    vsv_cli_refuse_input(r->a.out, &r->a.so.heights, 1);
    quiet_others(r->me, 0);
    if (r->me)
        vsv_cli_set_quiet(1);

    if (vsv_run_open(r->a.inputs, r->a.ninputs, &r->a.so, r->a.vars, NULL, &r->run))
        rank_fail(r, "%s", vsv_run_error(r->run));
    rank_check(r, -1);
    /* with --interp advect the run reads the winds too; the frames made, and
     * the file, have the species only (vsv_convert_setup, as vsv-convert) */
    quiet_others(r->me, 1);
    vsv_convert_setup(&r->a, r->run, &r->out);
    r->in = vsv_run_meta(r->run);
    r->meta = &r->out;
    r->cells = (size_t)r->meta->nx * r->meta->ny * r->meta->nz;
    vsv_cli_pack_resolve(&r->a.pack, r->meta);
    quiet_others(r->me, 0);
    int dropped = 0;
    plan_steps(r, &dropped);
    make_output(r);
    rank_check(r, -1);
    if (!r->me && dropped && !vsv_cli_quiet())
        fprintf(stderr,
                "vsv-convert-mpi: note: %d of %d model times lie between the steps every %s from the first "
                "and are not kept themselves\n",
                dropped, vsv_run_within(r->run), r->a.res_text);

    read_phase(r);
    rank_check(r, PHASE_READ);
    merge_stats(r);
    vsv_pack_plan *plan = NULL;
    if (vsv_pack_plan_create(r->meta, &r->a.pack.opts, r->st, &plan))
        rank_fail(r, "%s: %s", r->a.out, vsv_pack_plan_error(plan));
    rank_check(r, -1);
    encode_phase(r, plan);
    rank_check(r, PHASE_ENCODE);
    write_phase(r, plan);
    rank_check(r, -1);
    publish(r);
    for (int v = 0; !r->me && v < r->meta->nvars; v++)
        vsv_cli_pack_note(&r->a.pack, r->meta->vars[v].name, v, vsv_pack_plan_quant(plan, v));
    if (r->a.stats)
        print_stats(r, mpi_now() - r->t_start);
    vsv_pack_plan_free(plan);
    if (r->spool_fd >= 0)
        close(r->spool_fd);
    if (r->chunk_fd >= 0)
        close(r->chunk_fd);
    free(r->a.pack.opts.vars);
    free((char *)r->a.vars); /* (vsv_convert_vars's copy) */
    free(r->times);
    free(r->sizes);
    free(r->st);
    free(r->done);
    free(r->received);
    free(r->tmp);
    vsv_meta_clear(&r->out);
    vsv_run_free(r->run);
    return 0;
}
