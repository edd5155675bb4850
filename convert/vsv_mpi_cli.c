/* vsv_mpi_cli.c — see vsv_mpi_cli.h. */
#include "vsv_mpi_cli.h"

#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

double mpi_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void rank_fail(rank *r, const char *fmt, ...)
{
    if (r->failed)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(r->err, sizeof r->err, fmt, ap);
    va_end(ap);
    r->failed = 1;
    /* tell every other rank to stop at its next step */
    for (int p = 0; p < r->np; p++)
        if (p != r->me) {
            MPI_Request q;
            MPI_Isend(&r->me, 1, MPI_INT, p, TAG_STOP, MPI_COMM_WORLD, &q);
            MPI_Request_free(&q);
        }
}

/* ------------------------------------------------------------ progress */

static void show(rank *r, int phase, int final)
{
    if (r->me || phase < 0 || vsv_cli_quiet())
        return;
    int done = 0;
    for (int p = 0; p < r->np; p++)
        done += r->done[p];
    const double el = mpi_now() - r->t_phase, t = mpi_now();
    const int tty = isatty(2);
    /* a bar on a terminal; a line every 30 s in a batch job's log */
    if (!tty && !final && t - r->last_line < 30)
        return;
    if (!tty && final && t - r->t_start < 30)
        return;
    r->last_line = t;
    /* MB/s of model input converted (the run's bytes per output step) */
    const double mb = (double)done * r->step_bytes;
    char rate[64] = "", eta[32] = "";
    if (el > 0 && done > 0) {
        snprintf(rate, sizeof rate, ", %.1f MB/s", mb / el / 1e6);
        const double left = el / done * (r->nsteps - done);
        snprintf(eta, sizeof eta, ", %d:%02d left", (int)left / 60, (int)left % 60);
    }
    const char *what = phase == PHASE_READ ? "reading" : "encoding";
    if (tty) {
        const int width = 30, fill = r->nsteps ? (int)((long long)done * width / r->nsteps) : width;
        fprintf(stderr, "\rvsv-convert-mpi: %-8s [%.*s%*s] %d/%d steps%s%s   ", what, fill,
                "##############################", width - fill, "", done, r->nsteps, rate, final ? "" : eta);
        if (final)
            fputc('\n', stderr);
    } else {
        fprintf(stderr, "vsv-convert-mpi: %s %d/%d steps%s%s\n", what, done, r->nsteps, rate, final ? "" : eta);
    }
    fflush(stderr);
}

/* Rank 0 takes in the progress messages waiting; every rank notices STOP. */
void rank_poll(rank *r, int phase)
{
    int flag;
    MPI_Status st;
    for (;;) {
        MPI_Iprobe(MPI_ANY_SOURCE, TAG_STOP, MPI_COMM_WORLD, &flag, &st);
        if (!flag)
            break;
        int who;
        MPI_Recv(&who, 1, MPI_INT, st.MPI_SOURCE, TAG_STOP, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        r->stopped = 1;
        r->stops_in++;
    }
    if (r->me)
        return;
    int any = 0;
    for (;;) {
        MPI_Iprobe(MPI_ANY_SOURCE, TAG_PROGRESS, MPI_COMM_WORLD, &flag, &st);
        if (!flag)
            break;
        int n;
        MPI_Recv(&n, 1, MPI_INT, st.MPI_SOURCE, TAG_PROGRESS, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        r->done[st.MPI_SOURCE] = n;
        r->received[st.MPI_SOURCE]++;
        any = 1;
    }
    if (any)
        show(r, phase, 0);
}

/* A step of this rank is done: tell rank 0 (its own count it keeps). */
void rank_step_done(rank *r, int phase, int n)
{
    if (r->me) {
        MPI_Request q;
        static int counts[2][4096]; /* send buffers stay valid until the message went */
        int *slot = &counts[phase][r->sent % 4096];
        *slot = n;
        MPI_Isend(slot, 1, MPI_INT, 0, TAG_PROGRESS, MPI_COMM_WORLD, &q);
        MPI_Request_free(&q);
        r->sent++;
    } else {
        r->done[0] = n;
        show(r, phase, 0);
    }
    rank_poll(r, phase);
}

/* The end of a phase: every rank says whether it failed and how many
 * progress messages it sent; rank 0 keeps taking them in while it waits, and
 * every message still under way is received before anyone goes on (none
 * is left behind). Returns the lowest rank that failed, or -1. */
int rank_agree(rank *r, int phase)
{
    int mine[2] = {r->failed, r->sent}, *all = malloc(2 * (size_t)r->np * sizeof *all);
    MPI_Request q;
    MPI_Iallgather(mine, 2, MPI_INT, all, 2, MPI_INT, MPI_COMM_WORLD, &q);
    for (;;) {
        int flag;
        MPI_Test(&q, &flag, MPI_STATUS_IGNORE);
        if (flag)
            break;
        rank_poll(r, phase);
        usleep(1000);
    }
    int first = -1;
    for (int p = r->np - 1; p >= 0; p--)
        if (all[2 * p])
            first = p;
    /* the rest of the progress messages, and one STOP from each failed rank */
    if (!r->me)
        for (int p = 1; p < r->np; p++)
            while (r->received[p] < all[2 * p + 1]) {
                MPI_Recv(&r->done[p], 1, MPI_INT, p, TAG_PROGRESS, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
                r->received[p]++;
            }
    int stops = 0;
    for (int p = 0; p < r->np; p++)
        stops += p != r->me && all[2 * p];
    while (r->stops_in < stops) {
        int who;
        MPI_Recv(&who, 1, MPI_INT, MPI_ANY_SOURCE, TAG_STOP, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        r->stops_in++;
    }
    free(all);
    if (first < 0)
        show(r, phase, 1);
    for (int p = 0; p < r->np; p++)
        r->done[p] = 0;
    return first;
}

/* ------------------------------------------------------------- helpers */

/* Exits 1 on every rank after a failure the agreement found: the first
 * failed rank says what went wrong, rank 0 removes the temporary output. */
_Noreturn void rank_give_up(rank *r, int first)
{
    if (r->me == first) {
        fflush(stdout);
        fprintf(stderr, "vsv-convert-mpi: rank %d: %s\n", first, r->err);
    }
    if (!r->me && r->tmp)
        vsv_output_discard(r->tmp);
    exit(1); /* (the other ranks' listing of it: at exit, vsv_cli.c) */
}

void rank_check(rank *r, int phase)
{
    const int first = rank_agree(r, phase);
    if (first >= 0)
        rank_give_up(r, first);
}

void mpi_finalize_at_exit(void)
{
    int done = 0;
    MPI_Finalized(&done);
    if (!done)
        MPI_Finalize();
}

/* Ranks other than 0 keep quiet while the command line is read: every rank
 * parses it (and exits alike on --help or a usage error), one speaks. */
void quiet_others(int me, int on)
{
    static int saved[2] = {-1, -1};
    if (!me)
        return;
    fflush(stdout);
    fflush(stderr);
    for (int fd = 1; fd <= 2; fd++)
        if (on) {
            saved[fd - 1] = dup(fd);
            int nul = open("/dev/null", O_WRONLY);
            if (nul >= 0) {
                dup2(nul, fd);
                close(nul);
            }
        } else if (saved[fd - 1] >= 0) {
            dup2(saved[fd - 1], fd);
            close(saved[fd - 1]);
        }
}

/* An unlinked temporary file in $TMPDIR (node-local on most clusters). */
int local_temp(rank *r, const char *what)
{
    const char *dir = getenv("TMPDIR");
    if (!dir || !*dir)
        dir = "/tmp";
    char name[4096], tmp[4200];
    snprintf(name, sizeof name, "%s/vsv-convert-mpi.%s", dir, what);
    /* a listed temporary unlinked at once: a signal in between leaves nothing */
    const int fd = vsv_output_temp(name, NULL, tmp, sizeof tmp);
    if (fd < 0)
        rank_fail(r, "%s: cannot create a %s file: %s", dir, what, strerror(errno));
    else
        vsv_output_discard(tmp);
    return fd;
}

void rank_mpi_fail(rank *r, int code, const char *what)
{
    char msg[MPI_MAX_ERROR_STRING];
    int len = 0;
    MPI_Error_string(code, msg, &len);
    rank_fail(r, "%s: %s: %s", r->a.out, what, msg);
}