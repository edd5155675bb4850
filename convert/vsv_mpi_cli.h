/* vsv_mpi_cli.h — what vsv-convert-mpi's ranks share besides the work: a
 * rank's state, failing (the first failure on any rank stops every rank:
 * a STOP message between steps, an agreement at the end of each phase),
 * rank 0's progress display, and small local-file helpers. Program code
 * (it prints and exits), built only with MPI; never part of a library. */
#ifndef VSV_MPI_CLI_H
#define VSV_MPI_CLI_H

#include "vsv_convert_cli.h"

#include <mpi.h>

enum { TAG_PROGRESS = 1, TAG_STOP = 2 };
/* the phases that report progress; other agreements pass -1 */
enum { PHASE_READ = 0, PHASE_ENCODE = 1 };

/* One rank's state. */
typedef struct rank {
    int me, np;
    vsv_convert_args a;
    vsv_run *run;
    const vsv_meta *in;   /* the run's variables (with advect, the winds too) */
    vsv_meta out;         /* those of the frames made: the file's */
    const vsv_meta *meta; /* = &out */
    size_t cells;
    int nsteps;     /* output steps of the whole run */
    int64_t *times; /* their times */
    int s0, s1;     /* this rank's steps [s0, s1) */
    int lead;       /* 1: step s0-1 is made too (s0 is not a keyframe) */
    int f0, f1;     /* the input frames they need [f0, f1] */
    /* reading: frames of [s0, s1) spooled to a local temporary file */
    int spool_fd, spooled;
    float *spool;
    size_t spool_bytes;
    vsv_pack_stats *st;
    /* encoding: chunks spooled to a second local file */
    int chunk_fd;
    uint64_t *sizes, chunk_bytes;
    unsigned char *chunks;
    /* failure: this rank's message, and whether another rank said STOP */
    char err[1536];
    int failed, stopped, stops_in;
    /* progress: rank 0's view of every rank */
    int sent, *done, *received;
    double t_start, t_phase, secs[3]; /* read, encode, write seconds */
    double last_line;
    double step_bytes; /* input bytes per output step (for MB/s) */
    char *tmp;         /* the temporary output (rank 0 made it; every rank lists it) */
} rank;

/* Seconds of a monotonic clock. */
double mpi_now(void);
/* Records this rank's failure (the first one only) and tells every other
 * rank to stop at its next step. */
void rank_fail(rank *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Between steps: notices STOP (r->stopped); rank 0 takes in progress. */
void rank_poll(rank *r, int phase);
/* Step n of this rank's share is done in phase (progress to rank 0). */
void rank_step_done(rank *r, int phase, int n);
/* The end of a phase on every rank: returns the lowest failed rank or -1;
 * no message is left under way. */
int rank_agree(rank *r, int phase);
/* The first failed rank prints its message, rank 0 removes the temporary
 * output, every rank exits 1. */
_Noreturn void rank_give_up(rank *r, int first);
/* rank_agree, then rank_give_up if any rank failed. */
void rank_check(rank *r, int phase);
/* atexit: MPI_Finalize if not yet (exits from the shared option parser). */
void mpi_finalize_at_exit(void);
/* Silences stdout and stderr on ranks other than 0 (on), or restores them. */
void quiet_others(int me, int on);
/* An unlinked temporary file in $TMPDIR (or /tmp) for `what`; -1 (and
 * rank_fail) on error. */
int local_temp(rank *r, const char *what);
/* rank_fail with an MPI error's text: "OUT: what: MPI's message". */
void rank_mpi_fail(rank *r, int code, const char *what);

#endif
