/* fuzz_argv.c — fuzz target over the tools' argument vectors (issue #33):
 * each tool's main, compiled a second time as vsv_fuzz_main_<tool> (the
 * Makefile's -Dmain=), runs in this process on an argv made from the input,
 * in a scratch folder holding small fixtures (a .vsv, MM5, WRF, CAMx, CMAQ
 * files, a transfer function, a field stream). exit() inside a tool comes
 * back here (fuzz_argv_rt.c, the link's --wrap=exit), then the cleanup the
 * tool's atexit handler would run, and the state tools keep is reset.
 * Input: a first byte choosing the tool, then the arguments, NUL-separated
 * (at most 32). What is filtered out, and why: tests/FUZZING.md. Built for
 * libFuzzer by `make fuzz`; also runs as a regression test over
 * tests/corpus/argv (fuzz_main.c). */
#include "fuzz_argv.h"
#include "fuzz_source.h"
#include "vsv_cli.h"
#include "vsv_format.h"
#include "vsv_time.h"

#include <dirent.h>
#include <fcntl.h>
#include <getopt.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
/* LeakSanitizer off in this program alone: a tool that exits keeps what it
 * allocated (a process's end frees it), and an exit that comes back here
 * leaks that by design; fuzz_argv_rt.c frees what the tools hold open
 * (files, runs, sources, renderers), so the memory stays bounded. */
const char *__asan_default_options(void);
const char *__asan_default_options(void) { return "detect_leaks=0"; }
int LLVMFuzzerInitialize(int *argc, char ***argv);
const char *const fuzz_default_dirs[4] = {"tests/corpus/argv", NULL, NULL, NULL};
const char fuzz_label[] = "tools' argument vectors (in process)";
/* each tool run costs milliseconds (a render, a conversion): few mutations */
const long fuzz_mutations = 50;

int vsv_fuzz_main_vsv_info(int argc, char **argv);
int vsv_fuzz_main_vsv_query(int argc, char **argv);
int vsv_fuzz_main_vsv_render(int argc, char **argv);
int vsv_fuzz_main_vsv_plot(int argc, char **argv);
int vsv_fuzz_main_vsv_export(int argc, char **argv);
int vsv_fuzz_main_vsv_convert(int argc, char **argv);
int vsv_fuzz_main_vsv_extract(int argc, char **argv);
int vsv_fuzz_main_vsv_interp(int argc, char **argv);
int vsv_fuzz_main_vsv_pack(int argc, char **argv);

/* The input's first byte modulo the count picks the tool; this order is
 * tests/corpus/argv/make-seeds.py's too. */
static const struct {
    const char *name;
    int (*main)(int, char **);
} tools[] = {{"vsv-info", vsv_fuzz_main_vsv_info},       {"vsv-query", vsv_fuzz_main_vsv_query},
             {"vsv-render", vsv_fuzz_main_vsv_render},   {"vsv-plot", vsv_fuzz_main_vsv_plot},
             {"vsv-export", vsv_fuzz_main_vsv_export},   {"vsv-convert", vsv_fuzz_main_vsv_convert},
             {"vsv-extract", vsv_fuzz_main_vsv_extract}, {"vsv-interp", vsv_fuzz_main_vsv_interp},
             {"vsv-pack", vsv_fuzz_main_vsv_pack}};
enum { NTOOLS = sizeof tools / sizeof *tools, MAX_ARGS = 32 };

/* The fixtures: short names the arguments can hit (the dictionary has
 * them), copied from the tree once; b.vsv is converted from the MM5 sample
 * at start by the tool itself. */
static struct fixture {
    const char *name, *src;
    unsigned char *data;
    size_t size;
    struct stat st;
} fixtures[] = {{"a.vsv", "tests/golden/small.vsv", NULL, 0, {0}},
                {"m.mm5", "tests/corpus/mm5/tiny.mm5", NULL, 0, {0}},
                {"w.nc", "tests/corpus/netcdf/wrf-crop.nc", NULL, 0, {0}},
                {"c.uamiv", "tests/data/camx/test.uamiv", NULL, 0, {0}},
                {"q.nc", "tests/corpus/netcdf/ioapi-cmaq.nc", NULL, 0, {0}},
                {"t.tf", "share/transfer-functions.tf", NULL, 0, {0}},
                {"s.vsvs", "tests/corpus/stream/camx-uamiv.vsvs", NULL, 0, {0}},
                {"b.vsv", NULL, NULL, 0, {0}}};
enum { NFIX = sizeof fixtures / sizeof *fixtures };

static int top_fd = -1, scratch_fd = -1;
static vsv_http_opts http0;

static void die(const char *what, const char *name)
{
    fprintf(stderr, "fuzz_argv: %s %s\n", what, name);
    abort();
}

static void put_fixture(struct fixture *f)
{
    (void)unlinkat(scratch_fd, f->name, 0);
    const int fd = openat(scratch_fd, f->name, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0 || write(fd, f->data, f->size) != (ssize_t)f->size || close(fd) ||
        fstatat(scratch_fd, f->name, &f->st, 0))
        die("cannot write the fixture", f->name);
}

/* The whole of path (relative to the top of the tree), or abort. */
static unsigned char *slurp(int dir, const char *path, size_t *n)
{
    const int fd = openat(dir, path, O_RDONLY | O_CLOEXEC);
    struct stat st;
    if (fd < 0 || fstat(fd, &st))
        die("cannot read", path);
    unsigned char *d = malloc((size_t)st.st_size + 1);
    if (!d || read(fd, d, (size_t)st.st_size) != st.st_size)
        die("cannot read", path);
    close(fd);
    *n = (size_t)st.st_size;
    return d;
}

/* Removes what is under the open directory dir except the fixtures
 * (top: the scratch folder itself), depth first. */
static void sweep(int dir, int top)
{
    DIR *dp = fdopendir(dup(dir));
    if (!dp)
        return;
    rewinddir(dp);
    struct dirent *e;
    while ((e = readdir(dp))) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
            continue;
        int keep = 0;
        for (int i = 0; top && i < NFIX && !keep; i++)
            keep = !strcmp(e->d_name, fixtures[i].name);
        if (keep)
            continue;
        if (unlinkat(dir, e->d_name, 0) == 0)
            continue;
        const int sub = openat(dir, e->d_name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
        if (sub >= 0) {
            (void)fchmod(sub, 0700);
            sweep(sub, 0);
            close(sub);
        }
        (void)unlinkat(dir, e->d_name, AT_REMOVEDIR);
    }
    closedir(dp);
}

/* Every fixture as it was (a tool may have renamed its output over one, or
 * removed it), and nothing else in the folder. */
static void restore(void)
{
    sweep(scratch_fd, 1);
    for (int i = 0; i < NFIX; i++) {
        struct fixture *f = &fixtures[i];
        struct stat st;
        if (!f->data) /* b.vsv while it is being made */
            continue;
        if (fstatat(scratch_fd, f->name, &st, AT_SYMLINK_NOFOLLOW) || st.st_ino != f->st.st_ino ||
            st.st_size != f->st.st_size || st.st_mtim.tv_sec != f->st.st_mtim.tv_sec ||
            st.st_mtim.tv_nsec != f->st.st_mtim.tv_nsec || st.st_mode != f->st.st_mode)
            put_fixture(f);
    }
}

/* Runs tool t on argv (argv[0] its name) in the scratch folder; the exit
 * status (fuzz_argv_rt.c does the rest). */
static int run(int t, int argc, char **argv)
{
    if (fchdir(scratch_fd))
        die("cannot enter", fuzz_dir());
    optind = 0; /* a full reset of GNU getopt, its scan position too */
    opterr = 1;
    vsv_cli_set_quiet(0);
    vsv_cli_http = http0;
    const int rc = fuzz_argv_call(tools[t].main, argc, argv);
    vsv_cli_hold_signals(0);
    if (fchdir(top_fd))
        die("cannot return to", "the top of the tree");
    restore();
    return rc;
}

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc, (void)argv;
    if (top_fd >= 0)
        return 0;
    http0 = vsv_cli_http;
    top_fd = open(".", O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    scratch_fd = open(fuzz_dir(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (top_fd < 0 || scratch_fd < 0)
        die("cannot open", fuzz_dir());
    fuzz_argv_rt_init();
    for (int i = 0; i < NFIX; i++)
        if (fixtures[i].src) {
            fixtures[i].data = slurp(top_fd, fixtures[i].src, &fixtures[i].size);
            put_fixture(&fixtures[i]);
        }
    /* b.vsv: the MM5 sample converted by vsv-convert in this process, the
     * way the tools make their files (once; kept as bytes like the others) */
    char *conv[] = {"vsv-convert", "-q", "--keyframe", "2", "m.mm5", "-o", "b.vsv", NULL};
    struct fixture *b = &fixtures[NFIX - 1];
    if (run(5, 7, conv) != 0 || !(b->data = slurp(scratch_fd, "b.vsv", &b->size)))
        die("cannot convert", "m.mm5 to b.vsv");
    put_fixture(b);
    return 0;
}

/* ------------------------------------------------------------ the filter */

/* The longest time a fixture spans (seconds): MM5 3 h, WRF 3 h, CMAQ 2 h,
 * a.vsv 40 min; a --time-res finer than this over 400 steps is a big
 * honest request. */
enum { SPAN = 6 * 3600, MAX_FRAMES = 400 };
/* The raycaster under ASan and UBSan (-O1) costs about 17 µs a pixel here,
 * about 8 times that with --light: vsv-render's default 800x600 took 8.6 s,
 * with --light 55 s, beside libFuzzer's 10 s limit. A render may cost at
 * most this many pixels x 8 with light x 2 for stereo x 5 for a sequence
 * (a.vsv's steps), about 2.5 s. */
enum { RENDER_PIXELS = 150000, PLOT_PIXELS = 1024 * 1024 };

/* The largest WxH among the values of argv (a --size, however spelled),
 * else def. */
static long largest_size(int argc, char **argv, long def)
{
    long most = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *eq = strchr(a, '=');
        /* the value alone: after '=', or after a short option letter */
        const char *v[3] = {a, eq ? eq + 1 : a, a[0] == '-' && a[1] && a[1] != '-' ? a + 2 : a};
        for (int k = 0; k < 3; k++) {
            long w, h;
            char x;
            if (sscanf(v[k], "%ld%c%ld", &w, &x, &h) == 3 && x == 'x' && w > 0 && h > 0 && w <= 16384 && h <= 16384 &&
                w * h > most)
                most = w * h;
        }
    }
    return most ? most : def;
}

static int has(int argc, char **argv, const char *prefix)
{
    for (int i = 1; i < argc; i++)
        if (!strncmp(argv[i], prefix, strlen(prefix)))
            return 1;
    return 0;
}

/* 1 when argv asks for legitimately big work (tests/FUZZING.md): a render
 * above RENDER_PIXELS, a plot above 1024², frames finer than SPAN /
 * MAX_FRAMES; or leaves the scratch folder: any '/' (absolute and parent
 * paths, URLs). */
static int too_big(int t, int argc, char **argv)
{
    const char *name = tools[t].name;
    for (int i = 1; i < argc; i++)
        if (strchr(argv[i], '/'))
            return 1;
    if (!strcmp(name, "vsv-render")) {
        int sequence = 0;
        for (int i = 1; i < argc; i++)
            sequence |= strchr(argv[i], '%') != NULL;
        const double cost = (double)largest_size(argc, argv, 800 * 600) * (has(argc, argv, "--st") ? 2 : 1) *
                            (has(argc, argv, "--li") ? 8 : 1) * (sequence ? 5 : 1);
        return cost > RENDER_PIXELS;
    }
    if (!strcmp(name, "vsv-plot"))
        return largest_size(argc, argv, 800 * 600) > PLOT_PIXELS;
    if (strcmp(name, "vsv-convert") && strcmp(name, "vsv-interp"))
        return 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *eq = strchr(a, '=');
        const char *v[3] = {a, eq ? eq + 1 : a, a[0] == '-' && a[1] && a[1] != '-' ? a + 2 : a};
        for (int k = 0; k < 3; k++) {
            int64_t dt;
            if (!vsv_duration_parse(v[k], &dt) && dt > 0 && dt < (int64_t)SPAN / MAX_FRAMES)
                return 1;
        }
    }
    return 0;
}

static long n_skipped, n_exit[4]; /* 0, 1, 2, other */

int fuzz_report(char *msg, size_t cap);
int fuzz_report(char *msg, size_t cap)
{
    snprintf(msg, cap, "%ld skipped; exit 0: %ld, 1: %ld, 2: %ld, other: %ld", n_skipped, n_exit[0], n_exit[1],
             n_exit[2], n_exit[3]);
    /* the seeds are command lines that work: some inputs must get through */
    return n_exit[0] > 0 && n_exit[1] > 0 && n_exit[2] > 0 && !n_exit[3] ? 0 : -1;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1 || size > 4096)
        return 0;
    LLVMFuzzerInitialize(NULL, NULL);
    const int t = data[0] % NTOOLS;
    /* the arguments: NUL-separated, a last one without its NUL too */
    char *buf = malloc(size);
    if (!buf)
        return 0;
    memcpy(buf, data + 1, size - 1);
    buf[size - 1] = 0;
    char *argv[MAX_ARGS + 2];
    int argc = 0;
    argv[argc++] = (char *)tools[t].name;
    for (size_t at = 0; at < size - 1 && argc <= MAX_ARGS; at += strlen(buf + at) + 1)
        argv[argc++] = buf + at;
    argv[argc] = NULL;
    if (too_big(t, argc, argv)) {
        n_skipped++;
    } else {
        const int rc = run(t, argc, argv);
        n_exit[rc >= 0 && rc <= 2 ? rc : 3]++;
        /* the tools' contract (their man pages): 0, 1 for a failure, 2 for
         * a misuse; anything else is a finding */
        if (rc < 0 || rc > 2) {
            fprintf(stderr, "fuzz_argv: %s exited %d\n", tools[t].name, rc);
            abort();
        }
    }
    free(buf);
    return 0;
}
