/* vsv-extract — model file → field stream on stdout (select variables and
 * times), or --list what a file holds. */
#include "vsv_cli.h"
#include "vsv_convert.h"

#include <errno.h>
#include <getopt.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char usage[] =
    "Usage: vsv-extract [OPTIONS] FILE\n"
    "Read a model file (format detected from its content; this version reads\n"
    "GrADS .ctl/.dat) and write the selected fields as a field stream on stdout,\n"
    "for vsv-interp or vsv-pack.\n"
    "\n"
    "  -v, --vars LIST      comma-separated variable names (default: the 3-D fields)\n"
    "  -t, --times A:B      steps A..B inclusive, as indices (0-based) or ISO times;\n"
    "                       either end may be empty\n"
    "  -l, --list           list the fields (levels, units, description) and times\n"
    "  -h, --help           this help\n"
    "  -V, --version        print versions\n";

static int parse_end(const vsv_source *src, const char *s, int dflt, int is_end)
{
    if (!*s)
        return dflt;
    long v;
    if (!vsv_cli_int(s, 0, 10000000, &v))
        return (int)v;
    int64_t t;
    if (vsv_time_parse(s, &t))
        vsv_cli_usage_error("--times: '%s' is neither a step index nor an ISO time", s);
    int n = vsv_source_ntimes(src);
    if (is_end) {
        for (int i = n - 1; i >= 0; i--)
            if (vsv_source_time(src, i) <= t)
                return i;
        return -1;
    }
    for (int i = 0; i < n; i++)
        if (vsv_source_time(src, i) >= t)
            return i;
    return n;
}

int main(int argc, char **argv)
{
    vsv_cli_init("vsv-extract");
    static const struct option longopts[] = {{"vars", required_argument, 0, 'v'}, {"times", required_argument, 0, 't'},
                                             {"list", no_argument, 0, 'l'},       {"help", no_argument, 0, 'h'},
                                             {"version", no_argument, 0, 'V'},    {0, 0, 0, 0}};
    const char *vars = NULL, *times = NULL;
    int list = 0, c;
    while ((c = getopt_long(argc, argv, "v:t:lhV", longopts, NULL)) != -1) {
        switch (c) {
        case 'v': vars = optarg; break;
        case 't': times = optarg; break;
        case 'l': list = 1; break;
        case 'h': fputs(usage, stdout); return 0;
        case 'V': vsv_cli_version();
        default: vsv_cli_usage_error("unknown option");
        }
    }
    if (argc - optind != 1)
        vsv_cli_usage_error(optind >= argc ? "no input file" : "one input file (several files: issue #3)");
    const char *path = argv[optind];
    vsv_source *src = NULL;
    if (vsv_source_open(path, &src))
        vsv_cli_die(1, "%s", vsv_source_error(src));
    const vsv_meta *grid = vsv_source_grid(src);
    const int nf = vsv_source_nfields(src), nt = vsv_source_ntimes(src);
    char buf[64];
    if (list) {
        printf("%s: %s, %d x %d x %d, %d times\n", path, vsv_source_format(src), grid->nx, grid->ny, grid->nz, nt);
        printf("  %-10s %6s %-12s %s\n", "field", "levels", "units", "description");
        for (int i = 0; i < nf; i++) {
            const vsv_field_info *f = vsv_source_field(src, i);
            printf("  %-10s %6d %-12s %s%s\n", f->name, f->nlevels, f->units, f->description,
                   f->is_default ? "" : "  (not extracted by default)");
        }
        printf("  times:");
        for (int t = 0; t < nt; t++) {
            vsv_time_format(vsv_source_time(src, t), buf, sizeof buf);
            printf(" %s", buf);
        }
        printf("\n");
        vsv_source_free(src);
        return 0;
    }
    int *sel = calloc((size_t)nf, sizeof *sel), nsel = 0;
    if (!sel)
        vsv_cli_die(1, "out of memory");
    if (vars) {
        char *copy = strdup(vars), *save = NULL;
        for (char *name = strtok_r(copy, ",", &save); name; name = strtok_r(NULL, ",", &save)) {
            int i = vsv_source_find_field(src, name);
            if (i < 0) {
                fprintf(stderr, "vsv-extract: %s: no variable '%s'; available:", path, name);
                for (int k = 0; k < nf; k++)
                    fprintf(stderr, " %s", vsv_source_field(src, k)->name);
                fputc('\n', stderr);
                return 1;
            }
            sel[nsel++] = i;
        }
        free(copy);
    } else {
        for (int i = 0; i < nf; i++)
            if (vsv_source_field(src, i)->is_default)
                sel[nsel++] = i;
    }
    if (!nsel)
        vsv_cli_die(1, "%s: no variables selected", path);
    int a = 0, b = nt - 1;
    if (times) {
        const char *colon = strchr(times, ':');
        if (!colon)
            vsv_cli_usage_error("--times %s: expected A:B", times);
        char first[64];
        snprintf(first, sizeof first, "%.*s", (int)(colon - times), times);
        a = parse_end(src, first, 0, 0);
        b = parse_end(src, colon + 1, nt - 1, 1);
        if (a < 0 || b >= nt || a > b)
            vsv_cli_die(1, "%s: --times %s selects no step of 0..%d", path, times, nt - 1);
    }
    if (isatty(1))
        vsv_cli_usage_error("refusing to write a binary field stream to a terminal; pipe it into vsv-pack");
    vsv_meta meta;
    vsv_meta_init(&meta);
    if (vsv_meta_copy(&meta, grid))
        vsv_cli_die(1, "out of memory");
    for (int i = 0; i < nsel; i++) {
        const vsv_field_info *f = vsv_source_field(src, sel[i]);
        vsv_meta_add_var(&meta, f->name, f->units, f->description);
    }
    vsv_stream_writer *w = NULL;
    if (vsv_stream_writer_open(stdout, &meta, &w))
        vsv_cli_die(1, "writing the stream header: %s", strerror(errno));
    const size_t cells = (size_t)grid->nx * grid->ny * grid->nz;
    float **fields = calloc((size_t)nsel, sizeof *fields);
    for (int i = 0; fields && i < nsel; i++)
        if (!(fields[i] = malloc(cells * sizeof(float))))
            vsv_cli_die(1, "out of memory");
    for (int t = a; t <= b; t++) {
        for (int i = 0; i < nsel; i++)
            if (vsv_source_read(src, sel[i], t, fields[i]))
                vsv_cli_die(1, "%s", vsv_source_error(src));
        if (vsv_stream_writer_frame(w, vsv_source_time(src, t), (const float *const *)fields))
            vsv_cli_die(1, "writing to stdout: %s", strerror(errno));
        vsv_cli_progress("vsv-extract", t - a + 1, b - a + 1);
    }
    if (vsv_stream_writer_end(w))
        vsv_cli_die(1, "writing to stdout: %s", strerror(errno));
    vsv_stream_writer_free(w);
    for (int i = 0; i < nsel; i++)
        free(fields[i]);
    free(fields);
    free(sel);
    vsv_meta_clear(&meta);
    vsv_source_free(src);
    return 0;
}
