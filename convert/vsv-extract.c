/* vsv-extract — model file(s) → field stream on stdout (select variables,
 * times, vertical grid), or --list what a file holds. */
#include "vsv_cli.h"
#include "vsv_convert.h"
#include "vsv_convert_cli.h"
#include "vsv_vdb.h"

#include <errno.h>
#include <getopt.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* clang-format off */ /* (the help text as it prints, a line a line) */
static const char usage[] =
    "Usage: vsv-extract [OPTIONS] FILE...\n"
    "Read model output and write the selected 3-D fields as a field stream (the\n"
    "binary frames of vsv(5)) on stdout, for vsv-interp or vsv-pack. Several files\n"
    "are one run in time order. Reads, detected from the content (never the name):\n"
    VSV_CLI_MODEL_FORMATS VSV_CLI_VDB_FORMAT
    "\n"
    "  -v, --vars LIST      comma-separated variable names (default: the particulate\n"
    "                       and moisture fields present: CLW RNW ICE SNOW GRAUPEL Q;\n"
    "                       for GrADS every 3-D field)\n"
    "  -t, --times A:B      steps A..B inclusive, as 0-based indices or ISO times\n"
    "                       (which may hold colons: 1995-10-24T01:00Z:1995-10-24T02:00Z);\n"
    "                       either end may be empty; outside the file is an error\n"
    "  -w, --add-winds      also the model's winds U V (W) as the auxiliary fields\n"
    "                       wind.u wind.v (wind.w), for vsv-interp --interp advect\n"
    "                       (which uses them and drops them)\n"
    "      --winds FILE     the same, the winds taken from FILE (a model file on the\n"
    "                       same grid with U and V at every time), stored from it too\n"
    "      --no-winds       do not store the wind (by default, where the input has\n"
    "                       U and V: wind_east wind_north (wind_up), as vsv-convert)\n"
    VSV_CLI_DERIVE_HELP
    "  -l, --list           list each file's fields (ordering, units, description)\n"
    "                       and times, and exit\n"
    "  -h, --help           this help\n"
    "  -V, --version        print versions\n" VSV_SOURCE_HELP;
/* clang-format on */

static int emit(void *ctx, int64_t time, const float *const *fields)
{
    return vsv_stream_writer_frame(ctx, time, fields);
}

int main(int argc, char **argv)
{
    vsv_cli_init("vsv-extract");
    vsv_vdb_source_register(); /* .vdb sequences too (interop/) */
    /* clang-format off */ /* (a table, laid out by hand) */
    static const struct option longopts[] = {{"vars", required_argument, 0, 'v'},
                                             {"times", required_argument, 0, 't'},
                                             {"list", no_argument, 0, 'l'},
                                             {"add-winds", no_argument, 0, 'w'},
                                             {"winds", required_argument, 0, 'W'},
                                             {"no-winds", no_argument, 0, 'N'},
                                             {"derive", required_argument, 0, 'D'},
                                             {"help", no_argument, 0, 'h'},
                                             {"version", no_argument, 0, 'V'},
                                             VSV_SOURCE_LONGOPTS,
                                             {0, 0, 0, 0}};
    /* clang-format on */
    const char *vars = NULL, *times = NULL, *winds = NULL;
    const char *derive[VSV_CLI_MAX_DERIVE];
    int nderive = 0;
    int list = 0, c, add_winds = 0, no_winds = 0;
    vsv_source_opts so;
    vsv_source_opts_init(&so);
    argv[0] = (char *)vsv_cli_tool(); /* getopt's messages name the tool as ours do */
    while ((c = getopt_long(argc, argv, "v:t:lwhV", longopts, NULL)) != -1) {
        int h = vsv_source_cli_option(&so, c, optarg);
        if (h < 0) {
            char why[256];
            vsv_source_cli_why(c, optarg, why, sizeof why);
            vsv_cli_usage_error("%s", why);
        }
        if (h)
            continue;
        switch (c) {
        case 'v': vars = optarg; break;
        case 't': times = optarg; break;
        case 'l': list = 1; break;
        case 'w': add_winds = 1; break;
        case 'W': winds = optarg, add_winds = 1; break;
        case 'N': no_winds = 1; break;
        case 'D':
            if (nderive >= VSV_CLI_MAX_DERIVE)
                vsv_cli_usage_error("more than %d --derive", VSV_CLI_MAX_DERIVE);
            derive[nderive++] = optarg;
            break;
        case 'h': fputs(usage, stdout); return 0;
        case 'V': vsv_cli_version();
        default: vsv_cli_getopt_failed();
        }
    }
    if (optind >= argc)
        vsv_cli_usage_error("no input file");
    char tmsg[300];
    char smsg[200];
    if (vsv_source_opts_check(&so, smsg, sizeof smsg))
        vsv_cli_usage_error("%s", smsg);
    if (times && vsv_timesel_parse(times, NULL, 0, 0, &(vsv_timesel){0}, tmsg, sizeof tmsg))
        vsv_cli_usage_error("--times %s: %s", times, tmsg);
    if (list) {
        int status = 0;
        for (int a = optind; a < argc; a++) {
            vsv_source *src = NULL;
            if (vsv_source_open(argv[a], &so, &src)) {
                fprintf(stderr, "vsv-extract: %s\n", vsv_source_error(src));
                vsv_source_free(src);
                status = 1;
                continue;
            }
            const vsv_meta *g = vsv_source_grid(src);
            int layers = 0; /* the model's own (of its default fields first), which the even grid resamples */
            for (int pass = 0; pass < 2 && !layers; pass++)
                for (int i = 0; i < vsv_source_nfields(src); i++) {
                    const vsv_field_info *f = vsv_source_field(src, i);
                    if (f->is_volume && (pass || f->is_default) && f->nlevels > layers)
                        layers = f->nlevels;
                }
            if (g->vert_kind == VSV_VERT_EVEN && layers && layers != g->nz)
                printf("%s: %s, grid %d x %d, %d model layers (resampled onto %d even levels), %d times\n", argv[a],
                       vsv_source_format(src), g->nx, g->ny, layers, g->nz, vsv_source_ntimes(src));
            else
                printf("%s: %s, grid %d x %d x %d, %d times\n", argv[a], vsv_source_format(src), g->nx, g->ny, g->nz,
                       vsv_source_ntimes(src));
            printf("  %-10s %-8s %6s %-16s %s\n", "field", "order", "levels", "units", "description");
            for (int i = 0; i < vsv_source_nfields(src); i++) {
                const vsv_field_info *f = vsv_source_field(src, i);
                char note[80];
                snprintf(note, sizeof note, "  (%s)", f->role[0] ? f->role : "2-D or not on the grid");
                printf("  %-10s %-8s %6d %-16s %s%s\n", f->name, f->ordering, f->nlevels, f->units, f->description,
                       f->is_default  ? "  [default]"
                       : f->is_volume ? ""
                                      : note);
            }
            printf("  times:");
            for (int t = 0; t < vsv_source_ntimes(src); t++) {
                char buf[40];
                vsv_cal_format(vsv_meta_calendar(g), vsv_source_time(src, t), buf, sizeof buf);
                printf(" %s", buf);
            }
            printf("\n");
            vsv_source_free(src);
        }
        vsv_cli_stdout_done();
        return status;
    }
    vsv_run *run = NULL;
    char *picked = vsv_convert_vars(vars, derive, nderive);
    const int orc = vsv_run_open((const char *const *)argv + optind, argc - optind, &so, picked, times, &run);
    free(picked);
    if (orc)
        vsv_cli_die(1, "%s", vsv_run_error(run));
    if (*vsv_run_note(run))
        fprintf(stderr, "vsv-extract: %s\n", vsv_run_note(run));
    for (int i = 0; i < nderive; i++) /* before the winds: they stay last */
        if (vsv_run_add_derived(run, derive[i]))
            vsv_cli_die(1, "%s", vsv_run_error(run));
    if (!no_winds && vsv_run_store_winds(run, winds, &so) < 0)
        vsv_cli_die(1, "%s", vsv_run_error(run));
    if (add_winds && vsv_run_add_winds(run, winds, &so))
        vsv_cli_die(1, "%s", vsv_run_error(run));
    if (isatty(1))
        vsv_cli_usage_error("refusing to write a binary field stream to a terminal; pipe it into vsv-pack");
    const vsv_meta *meta = vsv_run_meta(run);
    vsv_stream_writer *w = NULL;
    if (vsv_stream_writer_open(stdout, meta, &w))
        vsv_cli_die(1, "writing the stream header: %s", strerror(errno));
    const size_t cells = (size_t)meta->nx * meta->ny * meta->nz;
    float **fields = calloc((size_t)meta->nvars, sizeof *fields);
    for (int v = 0; fields && v < meta->nvars; v++)
        if (!(fields[v] = malloc(cells * sizeof(float))))
            vsv_cli_die(1, "out of memory");
    const int n = vsv_run_nframes(run);
    for (int i = 0; i < n; i++) {
        if (vsv_run_read(run, i, fields))
            vsv_cli_die(1, "%s", vsv_run_error(run));
        if (emit(w, vsv_run_time(run, i), (const float *const *)fields))
            vsv_cli_die(1, "writing to stdout: %s", strerror(errno));
        vsv_cli_progress("vsv-extract", i + 1, n);
    }
    if (vsv_stream_writer_end(w))
        vsv_cli_die(1, "writing to stdout: %s", strerror(errno));
    vsv_stream_writer_free(w);
    for (int v = 0; v < meta->nvars; v++)
        free(fields[v]);
    free(fields);
    vsv_run_free(run);
    return 0;
}
