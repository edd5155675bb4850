/* fuzz_argv_rt.c — see fuzz_argv.h. A tool ends by exit() (vsv_cli_die,
 * usage errors, --help) and leaves to the process's end what it holds; in
 * one process over millions of inputs that would be descriptors, mappings
 * (the map guard's 512 slots), threads and memory. The link wraps the calls
 * involved (-Wl,--wrap=NAME, the Makefile's ARGV_WRAP): exit longjmps back
 * here while a tool runs; atexit is recorded and run at the tool's end;
 * fopen, the open calls of files, model runs and sources, the renderer and
 * the temporaries are tracked, so what the tool left is closed, freed,
 * joined and unlisted after it. Child processes (ffmpeg, the netCDF and
 * OpenVDB helpers) and the GPU context are refused: posix_spawn fails with
 * ENOSYS, vsv_gl_context_create with a message, and each tool takes its
 * error path. Only the harness thread's exit comes back. */
#include "fuzz_argv.h"
#include "vsv_convert.h"
#include "vsv_format.h"
#include "vsv_gl.h"
#include "vsv_http.h"
#include "vsv_render.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <setjmp.h>
#include <signal.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static jmp_buf back;
static volatile int in_tool;
static int exit_code;
static pthread_t harness;
static FILE *quiet_err;
static int null_fd = -1, verbose;

/* --------------------------------------------------------- tracked things */

enum { KINDS = 6, SLOTS = 256 };
enum { K_FILE, K_RUN, K_SOURCE, K_VSV, K_RENDERER, K_TEMP };
static void *held[KINDS][SLOTS];
static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;

static void hold(int kind, void *p)
{
    if (!p || !in_tool)
        return;
    pthread_mutex_lock(&lock);
    int at = -1;
    for (int i = 0; i < SLOTS; i++) {
        if (held[kind][i] == p)
            at = -2, i = SLOTS;
        else if (at == -1 && !held[kind][i])
            at = i;
    }
    if (at >= 0)
        held[kind][at] = p; /* full: left, as a process would leave it */
    pthread_mutex_unlock(&lock);
}

static void release(int kind, const void *p)
{
    pthread_mutex_lock(&lock);
    for (int i = 0; p && i < SLOTS; i++)
        if (held[kind][i] == p)
            held[kind][i] = NULL;
    pthread_mutex_unlock(&lock);
}

/* Takes one tracked pointer of kind out of the table (NULL when none). */
static void *take(int kind)
{
    for (int i = 0; i < SLOTS; i++)
        if (held[kind][i]) {
            void *p = held[kind][i];
            held[kind][i] = NULL;
            return p;
        }
    return NULL;
}

/* ---------------------------------------------------------- the wrappers */

_Noreturn void __real_exit(int code);
_Noreturn void __wrap_exit(int code);
int __real_atexit(void (*fn)(void));
int __wrap_atexit(void (*fn)(void));
FILE *__real_fopen(const char *path, const char *mode);
FILE *__wrap_fopen(const char *path, const char *mode);
FILE *__real_fdopen(int fd, const char *mode);
FILE *__wrap_fdopen(int fd, const char *mode);
int __real_fclose(FILE *fp);
int __wrap_fclose(FILE *fp);
int __wrap_posix_spawn(pid_t *pid, const char *path, const posix_spawn_file_actions_t *fa, const posix_spawnattr_t *at,
                       char *const argv[], char *const envp[]);
int __wrap_posix_spawnp(pid_t *pid, const char *file, const posix_spawn_file_actions_t *fa, const posix_spawnattr_t *at,
                        char *const argv[], char *const envp[]);
int __real_vsv_file_open_any(const char *name, const vsv_http_opts *o, vsv_file **out);
int __wrap_vsv_file_open_any(const char *name, const vsv_http_opts *o, vsv_file **out);
void __real_vsv_file_free(vsv_file *f);
void __wrap_vsv_file_free(vsv_file *f);
int __real_vsv_run_open(const char *const *paths, int npaths, const vsv_source_opts *opts, const char *vars,
                        const char *times, vsv_run **out);
int __wrap_vsv_run_open(const char *const *paths, int npaths, const vsv_source_opts *opts, const char *vars,
                        const char *times, vsv_run **out);
void __real_vsv_run_free(vsv_run *r);
void __wrap_vsv_run_free(vsv_run *r);
int __real_vsv_source_open(const char *path, const vsv_source_opts *opts, vsv_source **out);
int __wrap_vsv_source_open(const char *path, const vsv_source_opts *opts, vsv_source **out);
void __real_vsv_source_free(vsv_source *s);
void __wrap_vsv_source_free(vsv_source *s);
int __real_vsv_renderer_create(const vsv_render_opts *o, vsv_renderer **out);
int __wrap_vsv_renderer_create(const vsv_render_opts *o, vsv_renderer **out);
void __real_vsv_renderer_free(vsv_renderer *r);
void __wrap_vsv_renderer_free(vsv_renderer *r);
int __wrap_vsv_gl_context_create(vsv_gl_context **out, char *err, size_t cap);
int __real_vsv_output_temp(const char *path, const char *suffix, char *tmp, size_t cap);
int __wrap_vsv_output_temp(const char *path, const char *suffix, char *tmp, size_t cap);

void __wrap_exit(int code)
{
    if (in_tool && pthread_equal(pthread_self(), harness)) {
        exit_code = code;
        longjmp(back, 1);
    }
    __real_exit(code);
}

static void (*at_exits[16])(void);
static int n_at_exits;

int __wrap_atexit(void (*fn)(void))
{
    if (!in_tool)
        return __real_atexit(fn);
    for (int i = 0; i < n_at_exits; i++)
        if (at_exits[i] == fn)
            return 0;
    if (n_at_exits >= 16)
        return -1;
    at_exits[n_at_exits++] = fn;
    return 0;
}

FILE *__wrap_fopen(const char *path, const char *mode)
{
    FILE *fp = __real_fopen(path, mode);
    hold(K_FILE, fp);
    return fp;
}

FILE *__wrap_fdopen(int fd, const char *mode)
{
    FILE *fp = __real_fdopen(fd, mode);
    hold(K_FILE, fp);
    return fp;
}

int __wrap_fclose(FILE *fp)
{
    release(K_FILE, fp);
    return __real_fclose(fp);
}

int __wrap_posix_spawn(pid_t *pid, const char *path, const posix_spawn_file_actions_t *fa, const posix_spawnattr_t *at,
                       char *const argv[], char *const envp[])
{
    (void)pid, (void)path, (void)fa, (void)at, (void)argv, (void)envp;
    return ENOSYS;
}

int __wrap_posix_spawnp(pid_t *pid, const char *file, const posix_spawn_file_actions_t *fa, const posix_spawnattr_t *at,
                        char *const argv[], char *const envp[])
{
    (void)pid, (void)file, (void)fa, (void)at, (void)argv, (void)envp;
    return ENOSYS;
}

int __wrap_vsv_file_open_any(const char *name, const vsv_http_opts *o, vsv_file **out)
{
    *out = NULL; /* a failure may leave it as it was */
    const int rc = __real_vsv_file_open_any(name, o, out);
    hold(K_VSV, *out);
    return rc;
}

void __wrap_vsv_file_free(vsv_file *f)
{
    release(K_VSV, f);
    __real_vsv_file_free(f);
}

int __wrap_vsv_run_open(const char *const *paths, int npaths, const vsv_source_opts *opts, const char *vars,
                        const char *times, vsv_run **out)
{
    *out = NULL; /* a failure may leave it as it was */
    const int rc = __real_vsv_run_open(paths, npaths, opts, vars, times, out);
    hold(K_RUN, *out);
    return rc;
}

void __wrap_vsv_run_free(vsv_run *r)
{
    release(K_RUN, r);
    __real_vsv_run_free(r);
}

int __wrap_vsv_source_open(const char *path, const vsv_source_opts *opts, vsv_source **out)
{
    *out = NULL; /* a failure may leave it as it was */
    const int rc = __real_vsv_source_open(path, opts, out);
    hold(K_SOURCE, *out);
    return rc;
}

void __wrap_vsv_source_free(vsv_source *s)
{
    release(K_SOURCE, s);
    __real_vsv_source_free(s);
}

int __wrap_vsv_renderer_create(const vsv_render_opts *o, vsv_renderer **out)
{
    *out = NULL; /* a failure may leave it as it was */
    const int rc = __real_vsv_renderer_create(o, out);
    hold(K_RENDERER, *out);
    return rc;
}

void __wrap_vsv_renderer_free(vsv_renderer *r)
{
    release(K_RENDERER, r);
    __real_vsv_renderer_free(r);
}

/* EGL may find a GPU or a software one; neither is a tool's argument
 * handling, and a driver's threads would outlive the tool */
int __wrap_vsv_gl_context_create(vsv_gl_context **out, char *err, size_t cap)
{
    *out = NULL;
    snprintf(err, cap, "no GPU context in the argv fuzz harness");
    return VSV_EUNSUPPORTED;
}

int __wrap_vsv_output_temp(const char *path, const char *suffix, char *tmp, size_t cap)
{
    const int fd = __real_vsv_output_temp(path, suffix, tmp, cap);
    if (fd >= 0 && in_tool)
        hold(K_TEMP, strdup(tmp));
    return fd;
}

/* -------------------------------------------------------------- the call */

static const int sigs[] = {SIGINT, SIGTERM, SIGHUP, SIGPIPE};
enum { NSIGS = sizeof sigs / sizeof *sigs };

void fuzz_argv_rt_init(void)
{
    harness = pthread_self();
    const char *v = getenv("VSV_FUZZ_VERBOSE");
    verbose = v && *v && *v != '0';
    null_fd = open("/dev/null", O_RDWR | O_CLOEXEC);
    quiet_err = fdopen(dup(null_fd), "w");
    if (null_fd < 0 || !quiet_err)
        abort();
}

/* The descriptors open now (a bit a descriptor below 1024). */
static void open_fds(unsigned char *set)
{
    memset(set, 0, 128);
    DIR *dp = opendir("/proc/self/fd");
    const int own = dp ? dirfd(dp) : -1;
    struct dirent *e;
    while (dp && (e = readdir(dp))) {
        const int fd = atoi(e->d_name);
        if (e->d_name[0] != '.' && fd != own && fd < 1024)
            set[fd / 8] |= (unsigned char)(1u << fd % 8);
    }
    if (dp)
        closedir(dp);
}

/* What a process's end would have done to what the tool left. */
static void tidy(const unsigned char *fds_before)
{
    void *p;
    while ((p = take(K_RENDERER)))
        __wrap_vsv_renderer_free(p);
    while ((p = take(K_RUN)))
        __wrap_vsv_run_free(p);
    while ((p = take(K_SOURCE)))
        __wrap_vsv_source_free(p);
    while ((p = take(K_VSV)))
        __wrap_vsv_file_free(p);
    while ((p = take(K_FILE)))
        (void)__real_fclose(p);
    while ((p = take(K_TEMP))) {
        vsv_output_forget(p);
        free(p);
    }
    unsigned char now[128];
    open_fds(now);
    for (int fd = 3; fd < 1024; fd++)
        if (now[fd / 8] >> fd % 8 & 1 && !(fds_before[fd / 8] >> fd % 8 & 1))
            close(fd);
}

int fuzz_argv_call(int (*main_fn)(int, char **), int argc, char **argv)
{
    struct sigaction old[NSIGS];
    sigset_t mask;
    for (int i = 0; i < NSIGS; i++)
        sigaction(sigs[i], NULL, &old[i]);
    sigprocmask(SIG_SETMASK, NULL, &mask);
    unsigned char fds[128];
    open_fds(fds);
    /* the tools' output: standard output and error to /dev/null (the
     * sanitizers and libFuzzer write to descriptor 2 itself, which stays) */
    fflush(stdout);
    const int out_fd = dup(1), in_fd = dup(0);
    dup2(null_fd, 0); /* no tool waits on a terminal: standard input is empty */
    FILE *err = stderr;
    if (!verbose) {
        dup2(null_fd, 1);
        stderr = quiet_err;
    }
    volatile int rc;
    n_at_exits = 0;
    in_tool = 1;
    if (setjmp(back) == 0)
        rc = main_fn(argc, argv);
    else
        rc = exit_code;
    in_tool = 0;
    for (int i = n_at_exits - 1; i >= 0; i--)
        at_exits[i]();
    fflush(stdout);
    fflush(stderr);
    stderr = err;
    dup2(out_fd, 1);
    dup2(in_fd, 0);
    close(out_fd);
    close(in_fd);
    tidy(fds);
    for (int i = 0; i < NSIGS; i++)
        sigaction(sigs[i], &old[i], NULL);
    sigprocmask(SIG_SETMASK, &mask, NULL);
    return rc;
}
