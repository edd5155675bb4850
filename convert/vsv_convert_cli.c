/* vsv_convert_cli.c — see vsv_convert_cli.h. */
#include "vsv_convert_cli.h"

#include <getopt.h>
#include <stdlib.h>
#include <string.h>

const char vsv_convert_options_help[] =
    "  -o, --output FILE    the .vsv to write (required)\n"
    "  -r, --time-res D     regular frames every D (30s, 10m, 1h, 1d; a unit is\n"
    "                       required) from the first time, interpolated linearly;\n"
    "                       model times on that grid pass through unchanged, those\n"
    "                       between its steps are not kept (a D coarser than the\n"
    "                       model's keeps every k-th output)\n"
    "  -v, --vars LIST      variables (default: CLW RNW ICE SNOW GRAUPEL Q present)\n"
    "  -t, --times A:B      steps A..B: indices or ISO times (which may hold colons);\n"
    "                       either end may be empty; one index or time: that step\n"
    "  -q, --quiet          no progress bar\n"
    "  -h, --help           this help\n"
    "  -V, --version        print versions\n" VSV_SOURCE_HELP;

enum { OPT_STATS = 3000 };

void vsv_convert_args_parse(vsv_convert_args *a, int argc, char **argv, const char *head, int mpi)
{
    static const struct option longopts[] = {{"output", required_argument, 0, 'o'},
                                             {"time-res", required_argument, 0, 'r'},
                                             {"vars", required_argument, 0, 'v'},
                                             {"times", required_argument, 0, 't'},
                                             {"quiet", no_argument, 0, 'q'},
                                             {"help", no_argument, 0, 'h'},
                                             {"version", no_argument, 0, 'V'},
                                             {"stats", no_argument, 0, OPT_STATS},
                                             VSV_SOURCE_LONGOPTS,
                                             VSV_CLI_PACK_LONGOPTS,
                                             {0, 0, 0, 0}};
    memset(a, 0, sizeof *a);
    vsv_cli_pack_init(&a->pack);
    vsv_source_opts_init(&a->so);
    int c;
    while ((c = getopt_long(argc, argv, "o:r:v:t:qhV", longopts, NULL)) != -1) {
        int h = vsv_source_cli_option(&a->so, c, optarg);
        if (h < 0)
            vsv_cli_usage_error("bad value '%s' for a vertical-grid option", optarg);
        if (h || vsv_cli_pack_option(&a->pack, c, optarg))
            continue;
        switch (c) {
        case 'o': a->out = optarg; break;
        case 'r':
            a->res_text = optarg;
            if (vsv_cli_duration(optarg, &a->dt))
                vsv_cli_usage_error("--time-res %s: expected a duration with its unit: 30s, 10m, 1h, 1d", optarg);
            break;
        case 'v': a->vars = optarg; break;
        case 't': a->times = optarg; break;
        case 'q': vsv_cli_set_quiet(1); break;
        case OPT_STATS:
            if (!mpi)
                vsv_cli_usage_error("unknown option '--stats'");
            a->stats = 1;
            break;
        case 'h':
            fputs(head, stdout);
            fputs(vsv_convert_options_help, stdout);
            if (mpi)
                fputs("MPI:\n  --stats              each rank's read, encode and write seconds at the end\n", stdout);
            fputs(vsv_cli_pack_help, stdout);
            exit(0);
        case 'V': vsv_cli_version();
        default: vsv_cli_usage_error("unknown option");
        }
    }
    if (!a->out)
        vsv_cli_usage_error("no output file (-o OUT.vsv)");
    if (optind >= argc)
        vsv_cli_usage_error("no input file");
    char tmsg[300];
    if (a->times && vsv_timesel_parse(a->times, NULL, 0, 0, &(vsv_timesel){0}, tmsg, sizeof tmsg))
        vsv_cli_usage_error("--times %s: %s", a->times, tmsg);
    a->inputs = (const char *const *)argv + optind;
    a->ninputs = argc - optind;
}

int vsv_convert_frames(vsv_run *run, int64_t dt, int first, int last, float **fields, vsv_frame_fn emit, void *ctx,
                       const char *label, int *bad_frame, int *dropped)
{
    const vsv_meta *meta = vsv_run_meta(run);
    const size_t cells = (size_t)meta->nx * meta->ny * meta->nz;
    vsv_interp *ip = NULL;
    int rc = 0;
    *bad_frame = -1;
    if (dt && (rc = vsv_interp_create(dt, meta->nvars, cells, emit, ctx, &ip))) {
        *bad_frame = -2;
        goto done;
    }
    if (ip)
        vsv_interp_set_origin(ip, vsv_run_time(run, 0));
    for (int i = first; i <= last; i++) {
        if ((rc = vsv_run_read(run, i, fields))) {
            *bad_frame = i;
            break;
        }
        const int64_t t = vsv_run_time(run, i);
        if ((rc = ip ? vsv_interp_push(ip, t, (const float *const *)fields) : emit(ctx, t, (const float *const *)fields)))
            break;
        if (label)
            vsv_cli_progress((void *)label, i - first + 1, last - first + 1);
    }
done:
    if (dropped)
        *dropped = vsv_interp_dropped(ip);
    vsv_interp_free(ip);
    return rc;
}
