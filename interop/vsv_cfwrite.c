/* vsv_cfwrite.c — vsv_cf_write: the netCDF export run in the private helper
 * vsv-nc-writer, both ends. libhdf5 does not survive a failed write: on a
 * full disk it crashed in H5Fflush's error path and in libnetcdf's close
 * after it, taking the tool with it. Here the tool creates and lists the
 * temporary (its signal handler removes it), hands it to the helper as
 * descriptor 3 (the helper writes through /proc/self/fd/3, so it never
 * creates a file by name: after the tool is gone nothing can appear), reads
 * its progress lines, and seals and renames the file only when the helper
 * exits 0. A helper that crashes, fails or stops reporting is an error
 * naming the output, and the temporary is removed. */
#include "vsv_cf_internal.h"
#include "vsv_common.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

/* The longest the helper may go without reporting (one step written). */
#define STALL_S 900

int vsv_cf_write(const char *path, const char *src, vsv_file *f, const int *sel, int n, int a, int b,
                 const char *history, void (*progress)(void *ctx, int done, int total), void *ctx, char *err,
                 size_t cap)
{
    vsv_file_info info;
    vsv_file_info_get(f, &info);
    if (n < 1 || a < 0 || b >= info.nsteps || a > b) {
        snprintf(err, cap, "%s: nothing selected (steps %d..%d of 0..%d, %d species)", path, a, b, info.nsteps - 1, n);
        return VSV_EINVAL;
    }
    char tmp[4200];
    const int fd = vsv_output_temp(path, NULL, tmp, sizeof tmp);
    if (fd < 0) {
        snprintf(err, cap, "%s: cannot create a temporary file beside it: %s", path, strerror(errno));
        return VSV_EIO;
    }
    if (strstr(src, "://")) {
        /* a remote .vsv (vsv_file_open_any): the helper cannot open it again,
         * so this process writes (a library crash on a failed write is then
         * not contained) */
        char target[64];
        snprintf(target, sizeof target, "/proc/self/fd/%d", fd);
        const int rc = vsv_cf_write_here(target, path, f, sel, n, a, b, history, progress, ctx, err, cap);
        if (rc) {
            close(fd);
            vsv_output_discard(tmp);
            return rc;
        }
        if (vsv_output_commit(fd, tmp, path)) {
            snprintf(err, cap, "%s: cannot write the finished file to disk: %s", path, strerror(errno));
            return VSV_EIO;
        }
        return 0;
    }
    char *list = malloc((size_t)n * 12 + 1), pid[24], sa[16], sb[16];
    int p[2] = {-1, -1};
    if (!list) {
        snprintf(err, cap, "%s: out of memory", path);
        close(fd);
        vsv_output_discard(tmp);
        return VSV_ENOMEM;
    }
    list[0] = 0;
    for (int l = 0; l < n; l++)
        sprintf(list + strlen(list), l ? ",%d" : "%d", sel[l]);
    snprintf(pid, sizeof pid, "%ld", (long)getpid());
    snprintf(sa, sizeof sa, "%d", a);
    snprintf(sb, sizeof sb, "%d", b);
    char *argv[] = {
        "vsv-nc-writer", pid, (char *)src, (char *)path, sa, sb, list, (char *)(history ? history : ""), NULL};
    char why[600] = "", msg[4300] = "";
    pid_t child = -1;
    if (pipe2(p, O_CLOEXEC))
        snprintf(why, sizeof why, "cannot start vsv-nc-writer: pipe: %s", strerror(errno));
    else
        child = vsv_helper_spawn("vsv-nc-writer", argv, -1, p[1], fd, why, sizeof why);
    if (p[1] >= 0)
        close(p[1]);
    free(list);
    int status = 0, stalled = 0;
    if (child > 0) {
        /* lines "P done total" and at most one "E message", until it exits */
        char line[4400];
        size_t got = 0;
        for (;;) {
            const int r = vsv_helper_poll(p[0], STALL_S);
            if (r == 0)
                stalled = 1;
            if (r <= 0)
                break;
            const ssize_t k = read(p[0], line + got, sizeof line - 1 - got);
            if (k < 0 && errno == EINTR)
                continue;
            if (k <= 0)
                break;
            got += (size_t)k;
            line[got] = 0;
            char *nl;
            while ((nl = strchr(line, '\n'))) {
                *nl = 0;
                int done, total;
                if (line[0] == 'P' && sscanf(line + 1, "%d %d", &done, &total) == 2) {
                    if (progress)
                        progress(ctx, done, total);
                } else if (line[0] == 'E')
                    snprintf(msg, sizeof msg, "%s", line + 2);
                got -= (size_t)(nl + 1 - line);
                memmove(line, nl + 1, got + 1);
            }
            if (got == sizeof line - 1)
                got = 0; /* an overlong line: not ours */
        }
        if (stalled)
            kill(child, SIGKILL);
        vsv_helper_reap(child, 30, &status);
    }
    close(p[0]);
    int rc = 0;
    if (child <= 0) {
        snprintf(err, cap, "%s: %s", path, why);
        rc = VSV_EIO;
    } else if (stalled) {
        snprintf(err, cap, "%s: the netCDF writer made no progress for %d s: stopped", path, STALL_S);
        rc = VSV_EIO;
    } else if (WIFSIGNALED(status)) {
        snprintf(err, cap, "%s: the netCDF library crashed writing it (signal %d)", path, WTERMSIG(status));
        rc = VSV_EIO;
    } else if (!WIFEXITED(status) || WEXITSTATUS(status)) {
        if (msg[0])
            snprintf(err, cap, "%s", msg);
        else
            snprintf(err, cap, "%s: the netCDF writer failed (exit %d)", path,
                     WIFEXITED(status) ? WEXITSTATUS(status) : -1);
        rc = WIFEXITED(status) && WEXITSTATUS(status) == 3 ? VSV_ECORRUPT : VSV_EIO;
    }
    if (rc) {
        close(fd);
        vsv_output_discard(tmp);
        return rc;
    }
    if (vsv_output_commit(fd, tmp, path)) {
        snprintf(err, cap, "%s: cannot write the finished file to disk: %s", path, strerror(errno));
        return VSV_EIO;
    }
    return 0;
}

/* ------------------------------------------------------------- the helper */

static void report(void *ctx, int done, int total)
{
    (void)ctx;
    char line[64];
    const int k = snprintf(line, sizeof line, "P %d %d\n", done, total);
    if (write(1, line, (size_t)k) < 0) { /* the tool is gone */
    }
}

int vsv_cf_helper_main(int argc, char **argv)
{
    if (argc != 8)
        return 2;
    /* gone with the tool, even in the middle of a step; a file size limit
     * is a failed write (EFBIG, reported), as in the tool, not a signal */
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    signal(SIGXFSZ, SIG_IGN);
    if (getppid() != (pid_t)atol(argv[1]))
        return 1;
    const char *src = argv[2], *path = argv[3];
    const int a = atoi(argv[4]), b = atoi(argv[5]);
    int n = 1;
    for (const char *c = argv[6]; *c; c++)
        n += *c == ',';
    int *sel = calloc((size_t)n, sizeof *sel);
    char err[4300] = "";
    vsv_file *f = NULL;
    int rc;
    if (!sel) {
        snprintf(err, sizeof err, "%s: out of memory", path);
        rc = VSV_ENOMEM;
    } else if ((rc = vsv_file_open(src, &f))) {
        snprintf(err, sizeof err, "%s", f ? vsv_file_error(f) : src);
    } else {
        char *s = argv[6];
        for (int l = 0; l < n; l++)
            sel[l] = (int)strtol(s, &s, 10), s += *s == ',';
        rc = vsv_cf_write_here("/proc/self/fd/3", path, f, sel, n, a, b, argv[7][0] ? argv[7] : NULL, report, NULL, err,
                               sizeof err);
    }
    if (rc) {
        char *line = malloc(strlen(err) + 4);
        if (line) {
            const int k = sprintf(line, "E %s\n", err);
            if (write(1, line, (size_t)k) < 0) {
            }
            free(line);
        }
        return rc == VSV_ECORRUPT || rc == VSV_ETRUNC ? 3 : 1;
    }
    /* (f and sel are left to the process's end: no exit handlers run) */
    return 0;
}
