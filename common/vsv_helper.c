/* vsv_helper.c — starting the private helper programs that read untrusted
 * files with libraries that can crash on them (libhdf5, OpenVDB). A helper
 * is exec'd, never a fork of the caller: the caller may have threads
 * (log4cplus, loaded with OpenVDB, starts four at load), and a forked copy of
 * a threaded process may hang on a lock another thread held (it did, under
 * AddressSanitizer). posix_spawn runs no code of ours between fork and exec.
 * Helpers are found as git finds its libexec programs: $VSV_HELPER_DIR, then
 * next to the library or program holding this code (a build tree keeps them
 * beside the tools and shared libraries), then the install's
 * $(libdir)/vesuvius/. */
#include "vsv_common.h"

#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <link.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

extern char **environ;

#ifndef VSV_HELPER_DIR
#define VSV_HELPER_DIR "/usr/local/lib/vesuvius"
#endif

static int try_dir(const char *dir, size_t dlen, const char *sub, const char *name, char *out, size_t cap)
{
    const int n = snprintf(out, cap, "%.*s%s/%s", (int)dlen, dir, sub, name);
    return n > 0 && (size_t)n < cap && access(out, X_OK) == 0;
}

int vsv_helper_path(const char *name, char *out, size_t cap)
{
    const char *env = getenv("VSV_HELPER_DIR");
    if (env && *env)
        return try_dir(env, strlen(env), "", name, out, cap) ? 0 : -1;
    /* the object holding this code: a shared library, or the program itself
     * (whose name dladdr gives as argv[0]: /proc/self/exe instead) */
    char self[4096] = "";
    Dl_info dl;
    struct link_map *lm = NULL;
    if (dladdr1((void *)vsv_helper_path, &dl, (void **)&lm, RTLD_DL_LINKMAP) && lm && lm->l_name && lm->l_name[0])
        snprintf(self, sizeof self, "%s", lm->l_name);
    else {
        const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
        self[n > 0 ? n : 0] = 0;
    }
    const char *slash = strrchr(self, '/');
    if (slash) {
        const size_t dlen = (size_t)(slash - self);
        /* the build tree (tools and libraries; tests and benchmarks one
         * folder down), an install's lib/ (the shared library) and bin/ */
        static const char *const subs[] = {"", "/..", "/vesuvius", "/../lib/vesuvius"};
        for (size_t i = 0; i < sizeof subs / sizeof *subs; i++)
            if (try_dir(self, dlen, subs[i], name, out, cap))
                return 0;
    }
    return try_dir(VSV_HELPER_DIR, strlen(VSV_HELPER_DIR), "", name, out, cap) ? 0 : -1;
}

pid_t vsv_helper_spawn(const char *name, char *const argv[], int in, int out, int extra, char *why, size_t cap)
{
    char path[4200];
    if (vsv_helper_path(name, path, sizeof path)) {
        snprintf(why, cap,
                 "cannot find the helper program %s (looked next to the program and in %s; "
                 "VSV_HELPER_DIR overrides)",
                 name, VSV_HELPER_DIR);
        errno = ENOENT;
        return -1;
    }
    /* the descriptors to hand over, first moved above 2 so that placing one
     * at 0, 1 or 3 cannot overwrite another before it is placed */
    const int want[3] = {in, out, extra};
    int fd[3] = {-1, -1, -1};
    pid_t pid = -1;
    posix_spawn_file_actions_t fa;
    posix_spawnattr_t at;
    if (posix_spawn_file_actions_init(&fa)) {
        snprintf(why, cap, "cannot start %s: out of memory", name);
        return -1;
    }
    if (posix_spawnattr_init(&at)) {
        posix_spawn_file_actions_destroy(&fa);
        snprintf(why, cap, "cannot start %s: out of memory", name);
        return -1;
    }
    int rc = 0;
    /* (F_DUPFD says EINVAL, not EMFILE, when the descriptor limit is at or
     * under the lowest number asked for: out of descriptors all the same) */
    for (int k = 0; k < 3 && !rc; k++)
        if (want[k] >= 0 && (fd[k] = fcntl(want[k], F_DUPFD_CLOEXEC, 10)) < 0)
            rc = errno == EINVAL ? EMFILE : errno;
    static const int slot[3] = {0, 1, 3};
    for (int k = 0; k < 3 && !rc; k++)
        rc = fd[k] >= 0 ? posix_spawn_file_actions_adddup2(&fa, fd[k], slot[k])
             : k < 2    ? posix_spawn_file_actions_addopen(&fa, slot[k], "/dev/null", O_RDWR, 0)
                        : 0;
    /* the library's own complaints stay out of the caller's stderr */
    if (!rc)
        rc = posix_spawn_file_actions_addopen(&fa, 2, "/dev/null", O_WRONLY, 0);
    /* signals the caller ignores or blocks stay ignored or blocked across
     * exec: a helper starts with the defaults */
    sigset_t none, all;
    sigemptyset(&none);
    sigfillset(&all);
    sigdelset(&all, SIGKILL);
    sigdelset(&all, SIGSTOP);
    if (!rc)
        rc = posix_spawnattr_setsigmask(&at, &none);
    if (!rc)
        rc = posix_spawnattr_setsigdefault(&at, &all);
    if (!rc)
        rc = posix_spawnattr_setflags(&at, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
    if (!rc)
        rc = posix_spawn(&pid, path, &fa, &at, argv, environ);
    if (rc) {
        snprintf(why, cap, "cannot start %s: %s", path, strerror(rc));
        pid = -1;
    }
    for (int k = 0; k < 3; k++)
        if (fd[k] >= 0)
            close(fd[k]);
    posix_spawnattr_destroy(&at);
    posix_spawn_file_actions_destroy(&fa);
    return pid;
}

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

int vsv_helper_poll(int fd, double limit_s)
{
    const double end = now_s() + limit_s;
    for (;;) {
        const double left = end - now_s();
        if (left <= 0)
            return 0;
        struct pollfd p = {.fd = fd, .events = POLLIN};
        const int r = poll(&p, 1, left > 1e6 ? 1000000000 : (int)(left * 1000) + 1);
        if (r > 0)
            return 1;
        if (r < 0 && errno != EINTR)
            return -1;
    }
}

int vsv_helper_reap(pid_t pid, double limit_s, int *status)
{
    const double end = now_s() + limit_s;
    int timed_out = 0;
    for (;;) {
        const pid_t r = waitpid(pid, status, WNOHANG);
        if (r == pid)
            return timed_out;
        if (r < 0 && errno != EINTR) {
            *status = 0;
            return timed_out;
        }
        if (!timed_out && now_s() > end) {
            kill(pid, SIGKILL);
            timed_out = 1;
            while (waitpid(pid, status, 0) < 0 && errno == EINTR) {
            }
            return timed_out;
        }
        nanosleep(&(struct timespec){0, 2000000}, NULL);
    }
}

int vsv_helper_run(const char *name, char *const argv[], int extra, double limit_s, char *out, size_t cap, int *status,
                   char *why, size_t wcap)
{
    int p[2];
    if (pipe2(p, O_CLOEXEC)) {
        snprintf(why, wcap, "cannot start %s: pipe: %s", name, strerror(errno));
        return -1;
    }
    const pid_t pid = vsv_helper_spawn(name, argv, -1, p[1], extra, why, wcap);
    close(p[1]);
    if (pid < 0) {
        close(p[0]);
        return -1;
    }
    /* its report, until it closes its end (exits) or the time is up */
    const double end = now_s() + limit_s;
    size_t got = 0;
    int timed_out = 0;
    for (;;) {
        const int r = vsv_helper_poll(p[0], end - now_s());
        if (r == 0) {
            timed_out = 1;
            break;
        }
        if (r < 0)
            break;
        char tmp[512];
        const ssize_t n = read(p[0], tmp, sizeof tmp);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            break;
        const size_t take = cap && got < cap - 1 ? ((size_t)n < cap - 1 - got ? (size_t)n : cap - 1 - got) : 0;
        memcpy(out + got, tmp, take);
        got += take;
    }
    close(p[0]);
    if (cap)
        out[got] = 0;
    if (timed_out) {
        kill(pid, SIGKILL);
        while (waitpid(pid, status, 0) < 0 && errno == EINTR) {
        }
        return 1;
    }
    return vsv_helper_reap(pid, end - now_s() + 5, status);
}
