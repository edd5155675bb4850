/* vsv_nc_guard.c — netCDF-4 files are HDF5 files, and libhdf5 can crash on
 * a damaged one (a one-bit flip can kill nc_open; ncdump dies too). Before a
 * reader opens such a file, a child process opens it and reads every
 * variable; the parent only learns whether that worked, failed (with the
 * library's error and the variable), crashed, or ran past a time limit. A
 * crash is then an error naming the file, never the death of the tool. The
 * library is deterministic, so bytes the child read whole the parent reads
 * the same way. */
#include "vsv_source_internal.h"

#include <errno.h>
#include <fcntl.h>
#include <netcdf.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

/* A slab larger than this is not read by the check (its metadata still is). */
#define SLAB_MAX ((size_t)256 << 20)

/* In the child: opens path and reads every variable slab by slab along its
 * first dimension. 0, or an error in msg saying where. */
static int read_all(const char *path, char *msg, size_t cap)
{
    int nc, rc = nc_open(path, NC_NOWRITE, &nc);
    if (rc) {
        snprintf(msg, cap, "netCDF: %s (opening it)", nc_strerror(rc));
        return 1;
    }
    int nvars = 0;
    if ((rc = nc_inq_nvars(nc, &nvars))) {
        snprintf(msg, cap, "netCDF: %s (listing its variables)", nc_strerror(rc));
        return 1;
    }
    for (int v = 0; v < nvars; v++) {
        char name[NC_MAX_NAME + 1] = "?";
        int nd = 0, dims[NC_MAX_VAR_DIMS];
        nc_type type;
        size_t esize = 0;
        if ((rc = nc_inq_var(nc, v, name, &type, &nd, dims, NULL)) || (rc = nc_inq_type(nc, type, NULL, &esize))) {
            snprintf(msg, cap, "netCDF: %s (variable %d %s)", nc_strerror(rc), v, name);
            return 1;
        }
        if (type > NC_MAX_ATOMIC_TYPE || type == NC_STRING || nd > 32)
            continue; /* user-defined and string types: metadata only */
        size_t len[32], start[32] = {0}, count[32], slab = esize;
        for (int d = 0; d < nd; d++) {
            if ((rc = nc_inq_dimlen(nc, dims[d], &len[d]))) {
                snprintf(msg, cap, "netCDF: %s (variable %s, dimension %d)", nc_strerror(rc), name, d);
                return 1;
            }
            count[d] = d ? len[d] : 1;
            if (d)
                slab = len[d] && slab > SLAB_MAX / len[d] ? SLAB_MAX + 1 : slab * len[d];
        }
        const size_t nslabs = nd ? len[0] : 1;
        if (slab > SLAB_MAX || slab == 0)
            continue;
        void *buf = malloc(slab);
        if (!buf) {
            snprintf(msg, cap, "out of memory (variable %s)", name);
            return 1;
        }
        for (size_t i = 0; i < nslabs; i++) {
            start[0] = i;
            rc = nd ? nc_get_vara(nc, v, start, count, buf) : nc_get_var(nc, v, buf);
            if (rc) {
                snprintf(msg, cap, "netCDF: %s (variable %s, record %zu)", nc_strerror(rc), name, i);
                free(buf);
                return 1;
            }
        }
        free(buf);
    }
    nc_close(nc);
    return 0;
}

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

int vsv_nc_guard(vsv_source *s, int limit_s)
{
#ifdef __SANITIZE_ADDRESS__
    /* GCC 12's AddressSanitizer allocator is not fork-safe: a child forked
     * while another thread allocates (log4cplus, loaded with OpenVDB, starts
     * four threads at load) can wait for ever on its lock. The sanitizer
     * build reads in process; the child check is tested in the plain build. */
    (void)s;
    (void)limit_s;
    return 0;
#endif
    int fd[2];
    if (pipe2(fd, O_CLOEXEC))
        return vsv_source_fail(s, VSV_EIO, "cannot check the netCDF-4/HDF5 file: pipe: %s", strerror(errno));
    const pid_t pid = fork();
    if (pid < 0) {
        close(fd[0]);
        close(fd[1]);
        return vsv_source_fail(s, VSV_EIO, "cannot check the netCDF-4/HDF5 file: fork: %s", strerror(errno));
    }
    if (pid == 0) {
        close(fd[0]);
        /* a crash must end the child by its signal, whatever handlers the
         * program (or a sanitizer) installed */
        static const int sigs[] = {SIGSEGV, SIGBUS, SIGABRT, SIGFPE, SIGILL, SIGALRM};
        for (size_t i = 0; i < sizeof sigs / sizeof *sigs; i++)
            signal(sigs[i], SIG_DFL);
        /* the library's own complaints (HDF5's error stack, glibc's abort
         * text) stay out of the tool's stderr: the parent reports */
        const int dn = open("/dev/null", O_WRONLY | O_CLOEXEC);
        if (dn >= 0) {
            dup2(dn, 2);
            close(dn);
        }
        alarm((unsigned)limit_s);
        char msg[400] = "";
        const int bad = read_all(s->path, msg, sizeof msg);
        if (bad) {
            ssize_t w = write(fd[1], msg, strlen(msg));
            (void)w;
        }
        _exit(bad);
    }
    close(fd[1]);
    int st = 0, timed_out = 0;
    const double deadline = now_s() + limit_s + 5;
    for (;;) {
        const pid_t r = waitpid(pid, &st, WNOHANG);
        if (r == pid || (r < 0 && errno != EINTR))
            break;
        if (now_s() > deadline) {
            kill(pid, SIGKILL);
            while (waitpid(pid, &st, 0) < 0 && errno == EINTR) {
            }
            timed_out = 1;
            break;
        }
        nanosleep(&(struct timespec){0, 5000000}, NULL);
    }
    char msg[400] = "";
    ssize_t n = read(fd[0], msg, sizeof msg - 1);
    close(fd[0]);
    msg[n > 0 ? n : 0] = 0;
    if (timed_out || (WIFSIGNALED(st) && WTERMSIG(st) == SIGALRM))
        return vsv_source_fail(s, VSV_ECORRUPT, "reading it as netCDF-4/HDF5 took more than %d s: stopped", limit_s);
    if (WIFSIGNALED(st))
        return vsv_source_fail(s, VSV_ECORRUPT, "damaged netCDF-4/HDF5 file: the HDF5 library crashed reading it (%s)",
                               strsignal(WTERMSIG(st)));
    if (!WIFEXITED(st) || WEXITSTATUS(st))
        return vsv_source_fail(s, VSV_ECORRUPT, "%s", msg[0] ? msg : "netCDF-4/HDF5 check failed");
    return 0;
}
