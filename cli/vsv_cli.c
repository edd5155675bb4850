/* vsv_cli.c — shared support for the command-line tools (see vsv_cli.h). */
#include "vsv_cli.h"
#include "vsv_common.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* no call into the HTTP library here (vsv_cli_http.c holds those): a tool
 * that reads no URL links none */
/* ----------------------------------------------------------------- tools */

static const char *tool_name = "vsv";
static int quiet;

/* SIGINT, SIGTERM, SIGHUP: every temporary output removed (vsv_output.c),
 * then the signal re-raised with its default action, so the caller sees the
 * tool die of it (as zstd's programs do). */
static volatile sig_atomic_t holding, held;

static void on_stop(int sig)
{
    if (holding) { /* a sequence is being renamed into place: after it */
        held = sig;
        return;
    }
    vsv_output_cleanup();
    signal(sig, SIG_DFL);
    raise(sig);
}

void vsv_cli_hold_signals(int on)
{
    holding = on;
    if (!on && held)
        on_stop(held);
}

static void at_exit(void) { vsv_output_cleanup(); }

void vsv_cli_init(const char *tool)
{
    tool_name = tool;
    static const int sigs[] = {SIGINT, SIGTERM, SIGHUP};
    for (size_t i = 0; i < sizeof sigs / sizeof *sigs; i++) {
        struct sigaction sa, old;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = on_stop;
        sigemptyset(&sa.sa_mask);
        for (size_t k = 0; k < sizeof sigs / sizeof *sigs; k++)
            sigaddset(&sa.sa_mask, sigs[k]);
        /* a signal the caller ignores (nohup, a shell's background job)
         * stays ignored */
        if (sigaction(sigs[i], NULL, &old) == 0 && old.sa_handler != SIG_IGN)
            sigaction(sigs[i], &sa, NULL);
    }
    /* an error exit (vsv_cli_die) leaves no temporary either */
    atexit(at_exit);
}
const char *vsv_cli_tool(void) { return tool_name; }
int vsv_cli_quiet(void) { return quiet; }
void vsv_cli_set_quiet(int q) { quiet = q; }

void vsv_cli_notes(const char *text)
{
    for (const char *p = text; p && *p;) {
        const size_t n = strcspn(p, "\n");
        fprintf(stderr, "%s: note: %.*s\n", vsv_cli_tool(), (int)n, p);
        p += n + (p[n] == '\n');
    }
}

void vsv_cli_die(int code, const char *fmt, ...)
{
    va_list ap;
    fflush(stdout);
    fprintf(stderr, "%s: ", tool_name);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
    exit(code);
}

void vsv_cli_stdout_done(void)
{
    const int before = ferror(stdout) ? errno : 0; /* a write that failed already: its reason */
    errno = 0;
    if (fflush(stdout) == 0 && !ferror(stdout))
        return;
    const int e = errno ? errno : before;
    vsv_cli_die(1, "standard output: %s", e ? strerror(e) : "not all of it written");
}

void vsv_cli_usage_error(const char *fmt, ...)
{
    va_list ap;
    fprintf(stderr, "%s: ", tool_name);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fprintf(stderr, "\nTry '%s --help'.\n", tool_name);
    exit(2);
}

void vsv_cli_getopt_failed(void)
{
    fprintf(stderr, "Try '%s --help'.\n", tool_name);
    exit(2);
}

void vsv_cli_output_kind(const char *opt, const char *name, const char *exts, const char *writes)
{
    static const struct {
        const char *ext, *kind;
    } kinds[] = {{".vsv", "a Vesuvius file"},     {".vdb", "an OpenVDB file"}, {".nc", "a netCDF file"},
                 {".nc4", "a netCDF file"},       {".ply", "a PLY mesh"},      {".gltf", "a glTF scene"},
                 {".glb", "a binary glTF scene"}, {".png", "a PNG image"},     {".exr", "an OpenEXR image"},
                 {".svg", "an SVG image"},        {".pdf", "a PDF document"},  {".csv", "a CSV table"},
                 {".npy", "a numpy array"},       {".mp4", "an MP4 movie"}};
    const char *base = strrchr(name, '/'), *dot = strrchr(base ? base : name, '.');
    for (size_t i = 0; dot && i < sizeof kinds / sizeof *kinds; i++) {
        if (strcasecmp(dot, kinds[i].ext))
            continue;
        const size_t n = strlen(kinds[i].ext);
        for (const char *e = exts; (e = strstr(e, kinds[i].ext)); e += n)
            if (!e[n] || e[n] == ' ')
                return; /* one of its own */
        vsv_cli_usage_error("%s %s: the name of %s (%s); %s writes %s", opt, name, kinds[i].kind, kinds[i].ext, opt,
                            writes);
    }
}

FILE *vsv_cli_open_input(const char *path, const char *mode, int pipes)
{
    char why[256];
    FILE *fp = pipes ? vsv_input_fopen_stream(path, why, sizeof why) : vsv_input_fopen(path, mode, why, sizeof why);
    if (!fp)
        vsv_cli_die(1, "%s: %s", path, why);
    return fp;
}

/* In a sticky folder (/tmp) only the owner of a name (a symlink's own,
 * dangling or not) or of the folder may replace it: the rename at the end
 * would fail after all the work (and after vsv-plot had published its plot
 * beside the CSV), so such an output exits 1 before. */
static void refuse_sticky(const char *out)
{
    struct stat sl, sd;
    const uid_t me = geteuid();
    if (!me || lstat(out, &sl) || sl.st_uid == me)
        return;
    char dir[4200];
    snprintf(dir, sizeof dir, "%s", out);
    char *slash = strrchr(dir, '/');
    if (slash)
        slash[slash == dir] = 0;
    if (!stat(slash ? dir : ".", &sd) && (sd.st_mode & S_ISVTX) && sd.st_uid != me) {
        fprintf(stderr, "%s: %s: another user's file in a sticky folder (as /tmp): it cannot be replaced\n", tool_name,
                out);
        exit(1);
    }
}

void vsv_cli_refuse_input(const char *out, const char *const *inputs, int n)
{
    struct stat so, si;
    if (!out)
        return;
    refuse_sticky(out);
    if (stat(out, &so))
        return;
    if (!S_ISREG(so.st_mode)) { /* the output would replace it */
        fprintf(stderr, "%s: output %s is %s, not a regular file: refusing to replace it\n", tool_name, out,
                vsv_file_kind(so.st_mode));
        exit(2);
    }
    for (int i = 0; i < n; i++)
        if (inputs[i] && !stat(inputs[i], &si) && si.st_dev == so.st_dev && si.st_ino == so.st_ino) {
            fprintf(stderr, "%s: output %s is the input %s (the same file%s): refusing to overwrite it\n", tool_name,
                    out, inputs[i], strcmp(out, inputs[i]) ? ", through a link" : "");
            exit(2);
        }
}

void vsv_cli_writer_die(vsv_writer *w, const char *out)
{
    char msg[600];
    snprintf(msg, sizeof msg, "%s", vsv_writer_error(w));
    vsv_writer_free(w);
    vsv_cli_die(1, "%s: %s", out, msg);
}

void vsv_cli_version(void)
{
    printf("%s (Vesuvius %s) format %d.%d\n", tool_name, VSV_VERSION_STRING, VSV_FORMAT_MAJOR, VSV_FORMAT_MINOR);
    exit(0);
}

void vsv_cli_progress(void *label, int done, int total)
{
    if (quiet || !isatty(2) || total <= 0)
        return;
    const int width = 40, fill = (int)((long long)done * width / total);
    fprintf(stderr, "\r%s [%.*s%*s] %d/%d", label ? (const char *)label : "", fill,
            "########################################", width - fill, "", done, total);
    if (done >= total)
        fputc('\n', stderr);
    fflush(stderr);
}

int vsv_cli_int(const char *s, long lo, long hi, long *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || end == s || *end || v < lo || v > hi)
        return -1;
    *out = v;
    return 0;
}

/* Walks pattern: 0 with the count of numbers it holds, or -1 when it is no
 * pattern; with out, writes frame n's name (-2 when it does not fit). */
static int pattern_walk(const char *pattern, long n, char *out, size_t cap, int *numbers)
{
    size_t k = 0;
    *numbers = 0;
    for (const char *p = pattern; *p; p++) {
        char piece[32];
        size_t len = 1;
        piece[0] = *p, piece[1] = 0;
        if (*p == '%') {
            if (p[1] == '%') {
                p++;
            } else {
                const char *q = p + 1;
                const int zero = *q == '0';
                q += zero;
                int width = 0;
                while (*q >= '0' && *q <= '9' && width < 100)
                    width = width * 10 + (*q++ - '0');
                if (*q != 'd' || width > 9 || zero != (width > 0) || ++*numbers > 1) /* %d, %0Nd */
                    return -1;
                snprintf(piece, sizeof piece, "%0*ld", width, n);
                len = strlen(piece);
                p = q;
            }
        }
        if (out && k + len >= cap)
            return -2;
        if (out)
            memcpy(out + k, piece, len);
        k += len;
    }
    if (out)
        out[k] = 0;
    return 0;
}

int vsv_cli_pattern(const char *pattern)
{
    int numbers;
    return pattern_walk(pattern, 0, NULL, 0, &numbers) ? -1 : numbers;
}

int vsv_cli_pattern_name(const char *pattern, long n, char *out, size_t cap)
{
    int numbers;
    return pattern_walk(pattern, n, out, cap, &numbers) ? -1 : 0;
}

void vsv_cli_size(const char *arg, const int min[2], const int max[2], int *w, int *h)
{
    int used = 0;
    if (sscanf(arg, "%dx%d%n", w, h, &used) != 2 || arg[used] || *w < min[0] || *h < min[1] || *w > max[0] ||
        *h > max[1])
        vsv_cli_usage_error("--size %s: expected WxH, %dx%d to %dx%d", arg, min[0], min[1], max[0], max[1]);
}

int vsv_cli_double(const char *s, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (errno || end == s || *end || !isfinite(v))
        return -1;
    *out = v;
    return 0;
}

void vsv_cli_duration(const char *opt, const char *s, int64_t *out)
{
    if (vsv_duration_parse(s, out))
        vsv_cli_usage_error("%s %s: %s", opt, s, vsv_duration_why(s));
}

/* ------------------------------------------------------- pack options */

const char vsv_cli_pack_help[] = "Packing:\n"
                                 "  --brick N            brick edge in cells: 8, 16, 32 or 64 (default 32)\n"
                                 "  --keyframe K         a keyframe every K steps, deltas between (default 8)\n"
                                 "  --bits B|LIST        8 or 16 bits per value (default 16); LIST is NAME=B,...\n"
                                 "  --scale S|LIST       linear or log quantisation (default linear)\n"
                                 "  --threshold V|LIST   values below V are stored as empty\n"
                                 "  --range LO:HI|LIST   fixed quantisation range (default: the data's range)\n"
                                 "  --log-decades D|LIST log scale spans at most D decades below the maximum\n"
                                 "                       (default 3 for 8 bits, 6 for 16 bits)\n"
                                 "  --codec C[:LEVEL]    zstd (default, level 3) or none\n"
                                 "  --format N           the newest format version to write: 4 (default; dense\n"
                                 "                       bricks Rice-coded where smaller), 3 (for readers before\n"
                                 "                       format 4) or 1 (no 3-D prediction)\n"
                                 "  --threads N          encoder threads (default: all cores)\n";

void vsv_cli_pack_init(vsv_cli_pack *p)
{
    memset(p, 0, sizeof *p);
    vsv_pack_opts_init(&p->opts);
}

int vsv_cli_pack_option(vsv_cli_pack *p, int id, const char *arg)
{
    long v;
    switch (id) {
    case VSV_CLI_PACK_BRICK:
        if (vsv_cli_int(arg, 8, 64, &v) || (v != 8 && v != 16 && v != 32 && v != 64))
            vsv_cli_usage_error("--brick %s: must be 8, 16, 32 or 64", arg);
        p->opts.brick = (int)v;
        return 1;
    case VSV_CLI_PACK_KEYFRAME:
        if (vsv_cli_int(arg, 1, 65535, &v))
            vsv_cli_usage_error("--keyframe %s: must be an integer 1..65535", arg);
        p->opts.keyframe = (int)v;
        return 1;
    case VSV_CLI_PACK_THREADS:
        if (vsv_cli_int(arg, 1, 64, &v))
            vsv_cli_usage_error("--threads %s: must be an integer 1..64", arg);
        p->opts.threads = (int)v;
        return 1;
    case VSV_CLI_PACK_CODEC: {
        const char *colon = strchr(arg, ':');
        size_t n = colon ? (size_t)(colon - arg) : strlen(arg);
        if (n == 4 && !strncmp(arg, "zstd", 4))
            p->opts.codec = VSV_CODEC_ZSTD;
        else if (n == 4 && !strncmp(arg, "none", 4))
            p->opts.codec = VSV_CODEC_NONE;
        else
            vsv_cli_usage_error("--codec %s: must be zstd[:LEVEL] or none", arg);
        if (colon) {
            if (p->opts.codec != VSV_CODEC_ZSTD || vsv_cli_int(colon + 1, 1, 19, &v))
                vsv_cli_usage_error("--codec %s: level must be 1..19", arg);
            p->opts.level = (int)v;
        }
        return 1;
    }
    case VSV_CLI_PACK_FORMAT:
        if (vsv_cli_int(arg, 1, 4, &v) || v == 2)
            vsv_cli_usage_error("--format %s: must be 4, 3 or 1", arg);
        p->opts.predict = v == 4 ? 2 : v == 3 ? 1 : 0;
        return 1;
    case VSV_CLI_PACK_BITS: p->bits = arg; return 1;
    case VSV_CLI_PACK_SCALE: p->scale = arg; return 1;
    case VSV_CLI_PACK_THRESHOLD: p->threshold = arg; return 1;
    case VSV_CLI_PACK_RANGE: p->range = arg; return 1;
    case VSV_CLI_PACK_DECADES: p->decades = arg; return 1;
    default: return 0;
    }
}

/* Applies one VALUE to species v of the option named opt. */
static void pack_apply(vsv_pack_var *pv, const char *opt, const char *val)
{
    long l;
    double d, lo, hi;
    if (!strcmp(opt, "bits")) {
        if (vsv_cli_int(val, 8, 16, &l) || (l != 8 && l != 16))
            vsv_cli_usage_error("--bits %s: must be 8 or 16", val);
        pv->bits = (int)l;
    } else if (!strcmp(opt, "scale")) {
        if (!strcmp(val, "linear"))
            pv->scale = VSV_SCALE_LINEAR;
        else if (!strcmp(val, "log"))
            pv->scale = VSV_SCALE_LOG;
        else
            vsv_cli_usage_error("--scale %s: must be linear or log", val);
    } else if (!strcmp(opt, "threshold")) {
        if (vsv_cli_double(val, &d))
            vsv_cli_usage_error("--threshold %s: not a number", val);
        pv->threshold = d;
    } else if (!strcmp(opt, "log-decades")) {
        if (vsv_cli_double(val, &d) || !(d > 0 && d <= 30))
            vsv_cli_usage_error("--log-decades %s: must be a number in (0, 30]", val);
        pv->log_decades = d;
    } else {
        char buf[128];
        snprintf(buf, sizeof buf, "%s", val);
        char *colon = strchr(buf, ':');
        if (!colon)
            vsv_cli_usage_error("--range %s: must be LO:HI", val);
        *colon = 0;
        if (vsv_cli_double(buf, &lo) || vsv_cli_double(colon + 1, &hi) || !(lo < hi))
            vsv_cli_usage_error("--range %s: must be LO:HI with LO < HI", val);
        pv->lo = lo;
        pv->hi = hi;
    }
}

static void pack_list(vsv_pack_var *vars, const vsv_meta *m, const char *opt, const char *arg)
{
    if (!arg)
        return;
    if (!strchr(arg, '=')) {
        for (int v = 0; v < m->nvars; v++)
            pack_apply(&vars[v], opt, arg);
        return;
    }
    char *copy = strdup(arg), *save = NULL;
    if (!copy)
        vsv_cli_die(1, "out of memory");
    for (char *item = strtok_r(copy, ",", &save); item; item = strtok_r(NULL, ",", &save)) {
        char *eq = strchr(item, '=');
        if (!eq)
            vsv_cli_usage_error("--%s %s: expected NAME=VALUE items", opt, arg);
        *eq = 0;
        int v = vsv_meta_find_var(m, item);
        if (v < 0)
            vsv_cli_usage_error("--%s: no species named '%s'", opt, item);
        pack_apply(&vars[v], opt, eq + 1);
    }
    free(copy);
}

void vsv_cli_pack_resolve(vsv_cli_pack *p, const vsv_meta *meta)
{
    vsv_pack_var *vars = calloc((size_t)meta->nvars, sizeof *vars);
    if (!vars)
        vsv_cli_die(1, "out of memory");
    for (int v = 0; v < meta->nvars; v++)
        vsv_pack_var_init(&vars[v]);
    pack_list(vars, meta, "bits", p->bits);
    pack_list(vars, meta, "scale", p->scale);
    pack_list(vars, meta, "threshold", p->threshold);
    pack_list(vars, meta, "range", p->range);
    pack_list(vars, meta, "log-decades", p->decades);
    p->opts.vars = vars;
}

void vsv_cli_pack_note(const vsv_cli_pack *p, const char *name, int v, const vsv_quant *q)
{
    if (vsv_cli_quiet() || !q)
        return;
    if (!(q->data_min <= q->data_max)) {
        fprintf(stderr, "%s: note: %s: no finite value at any step: every cell is no data\n", tool_name, name);
        return;
    }
    if (!p->opts.vars || !(p->opts.vars[v].lo < p->opts.vars[v].hi))
        return;
    if (q->data_max > q->hi)
        fprintf(stderr, "%s: note: %s: values up to %.6g lie above --range's top, %.6g, and are stored as it\n",
                tool_name, name, q->data_max, q->hi);
    if (q->scale == VSV_SCALE_LINEAR && q->data_min < q->lo)
        fprintf(stderr, "%s: note: %s: values down to %.6g lie below --range's bottom, %.6g, and are stored as it\n",
                tool_name, name, q->data_min, q->lo);
}

void vsv_cli_pack_note_file(const vsv_cli_pack *p, const char *path)
{
    if (vsv_cli_quiet())
        return;
    vsv_file *f = NULL;
    if (!vsv_file_open(path, &f)) {
        const vsv_meta *m = vsv_file_meta(f);
        for (int v = 0; v < m->nvars; v++)
            vsv_cli_pack_note(p, m->vars[v].name, v, vsv_file_quant(f, v));
    }
    vsv_file_free(f);
}

int vsv_cli_species(const vsv_meta *m, const char *list, const char *path, int *sel)
{
    int n = 0;
    if (!list) {
        for (int s = 0; s < m->nvars; s++)
            sel[n++] = s;
        return n;
    }
    char *copy = strdup(list);
    if (!copy)
        vsv_cli_die(1, "out of memory");
    for (char *it = copy, *next; it; it = next) {
        next = strchr(it, ',');
        if (next)
            *next++ = 0;
        if (!*it)
            vsv_cli_usage_error("--species %s: an empty species name", list);
        const int s = vsv_meta_find_var(m, it);
        if (s < 0)
            vsv_cli_usage_error("--species: %s has no species '%s'", path, it);
        for (int l = 0; l < n; l++)
            if (sel[l] == s)
                vsv_cli_usage_error("--species: '%s' named twice", it);
        sel[n++] = s;
    }
    free(copy);
    if (!n)
        vsv_cli_usage_error("--species: no species named");
    return n;
}

void vsv_cli_timesel(const char *path, const char *opt, const char *spec, const int64_t *times, int n, int flags,
                     int *a, int *b)
{
    vsv_timesel sel;
    char msg[400];
    const int rc = vsv_timesel_parse(spec, times, n, flags, &sel, msg, sizeof msg);
    if (rc == VSV_EINVAL)
        vsv_cli_usage_error("%s %s: %s", opt, spec, msg);
    if (rc)
        vsv_cli_die(1, "%s: %s %s: %s", path, opt, spec, msg);
    if (!sel.exact) {
        char when[40];
        vsv_cal_format(flags >> 4 & 3, times[sel.first], when, sizeof when);
        fprintf(stderr, "%s: %s %s: no step at that time; the nearest is step %d, %s\n", tool_name, opt, spec,
                sel.first, when);
    }
    *a = sel.first;
    *b = sel.last;
}

void vsv_cli_steps(const vsv_file *f, const char *path, const char *time, const char *times, int all, int *a, int *b)
{
    vsv_file_info info;
    vsv_file_info_get(f, &info);
    *a = *b = info.nsteps - 1;
    if (!time && !times) {
        if (all)
            *a = 0;
        return;
    }
    int64_t *t = malloc((size_t)info.nsteps * sizeof *t);
    if (!t)
        vsv_cli_die(1, "out of memory");
    for (int i = 0; i < info.nsteps; i++)
        t[i] = vsv_file_time(f, i);
    const int cal = VSV_TIMESEL_CAL(vsv_meta_calendar(vsv_file_meta(f)));
    if (time)
        vsv_cli_timesel(path, "--time", time, t, info.nsteps, VSV_TIMESEL_ONE | cal, a, b);
    else
        vsv_cli_timesel(path, "--times", times, t, info.nsteps, cal, a, b);
    free(t);
}
