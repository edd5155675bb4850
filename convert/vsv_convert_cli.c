/* vsv_convert_cli.c — see vsv_convert_cli.h. */
#include "vsv_convert_cli.h"

#include <getopt.h>
#include <libgen.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/statvfs.h>

const char vsv_convert_options_help[] =
    "  -o, --output FILE    the .vsv to write (required)\n"
    "  -r, --time-res D     regular frames every D (30s, 10m, 1h30m, 1d or ISO 8601\n"
    "                       PT1H30M; a unit is required) from the first time,\n"
    "                       interpolated linearly;\n"
    "                       model times on that grid pass through unchanged, those\n"
    "                       between its steps are not kept (a D coarser than the\n"
    "                       model's keeps every k-th output)\n"
    "  -i, --interp M       how: linear (default); advect (carried along the model's\n"
    "                       own winds U V W, each species as far as fits its two\n"
    "                       outputs); wind (carried as far as the air moves); see\n"
    "                       vsv-interp(1)\n"
    "      --winds FILE     the winds from FILE (a model file on the same grid with U\n"
    "                       and V at every time) instead of the input: stored, and\n"
    "                       for advect and wind\n"
    "      --no-winds       do not store the wind (by default, where the input has\n"
    "                       U and V, the species wind_east wind_north (wind_up from\n"
    "                       W), m/s, earth-relative at mass points: vsv(5) Vectors)\n"
    "  -v, --vars LIST      variables (default: CLW RNW ICE SNOW GRAUPEL Q present)\n"
    "  -t, --times A:B      steps A..B: indices or ISO times (which may hold colons);\n"
    "                       either end may be empty; one index or time: that step.\n"
    "                       With --time-res, the output steps (00:45..00:55 with\n"
    "                       10m picks the 00:50 frame)\n" VSV_CLI_DERIVE_HELP "  -q, --quiet          no progress bar\n"
    "  -h, --help           this help\n"
    "  -V, --version        print versions\n" VSV_SOURCE_HELP;

enum { OPT_STATS = 3000, OPT_WINDS, OPT_NO_WINDS, OPT_DERIVE };

void vsv_convert_args_parse(vsv_convert_args *a, int argc, char **argv, const char *head, int mpi)
{
    /* clang-format off */ /* (a table, laid out by hand) */
    static const struct option longopts[] = {{"output", required_argument, 0, 'o'},
                                             {"time-res", required_argument, 0, 'r'},
                                             {"interp", required_argument, 0, 'i'},
                                             {"winds", required_argument, 0, OPT_WINDS},
                                             {"no-winds", no_argument, 0, OPT_NO_WINDS},
                                             {"derive", required_argument, 0, OPT_DERIVE},
                                             {"vars", required_argument, 0, 'v'},
                                             {"times", required_argument, 0, 't'},
                                             {"quiet", no_argument, 0, 'q'},
                                             {"help", no_argument, 0, 'h'},
                                             {"version", no_argument, 0, 'V'},
                                             {"stats", no_argument, 0, OPT_STATS},
                                             VSV_SOURCE_LONGOPTS,
                                             VSV_CLI_PACK_LONGOPTS,
                                             {0, 0, 0, 0}};
    /* clang-format on */
    memset(a, 0, sizeof *a);
    vsv_cli_pack_init(&a->pack);
    vsv_source_opts_init(&a->so);
    int c;
    argv[0] = (char *)vsv_cli_tool(); /* getopt's messages name the tool as ours do */
    while ((c = getopt_long(argc, argv, "o:r:i:v:t:qhV", longopts, NULL)) != -1) {
        int h = vsv_source_cli_option(&a->so, c, optarg);
        if (h < 0) {
            char why[256];
            vsv_source_cli_why(c, optarg, why, sizeof why);
            vsv_cli_usage_error("%s", why);
        }
        if (h || vsv_cli_pack_option(&a->pack, c, optarg))
            continue;
        switch (c) {
        case 'o': a->out = optarg; break;
        case 'r':
            a->res_text = optarg;
            vsv_cli_duration("--time-res", optarg, &a->dt);
            break;
        case 'i':
            if ((a->method = vsv_interp_method(optarg)) < 0)
                vsv_cli_usage_error("--interp %s: expected linear, advect or wind", optarg);
            break;
        case OPT_WINDS: a->winds = optarg; break;
        case OPT_NO_WINDS: a->no_winds = 1; break;
        case OPT_DERIVE:
            if (a->nderive >= VSV_CLI_MAX_DERIVE)
                vsv_cli_usage_error("more than %d --derive", VSV_CLI_MAX_DERIVE);
            a->derive[a->nderive++] = optarg;
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
        default: vsv_cli_getopt_failed();
        }
    }
    if (!a->out)
        vsv_cli_usage_error("no output file (-o OUT.vsv)");
    vsv_cli_output_kind("-o", a->out, ".vsv", "a .vsv file");
    if (optind >= argc)
        vsv_cli_usage_error("no input file");
    char tmsg[300];
    char smsg[200];
    if (vsv_source_opts_check(&a->so, smsg, sizeof smsg))
        vsv_cli_usage_error("%s", smsg);
    if (a->times && vsv_timesel_parse(a->times, NULL, 0, 0, &(vsv_timesel){0}, tmsg, sizeof tmsg))
        vsv_cli_usage_error("--times %s: %s", a->times, tmsg);
    if (a->method != VSV_TIME_LINEAR && !a->dt)
        vsv_cli_usage_error("--interp %s needs --time-res", a->method == VSV_TIME_WIND ? "wind" : "advect");
    if (a->winds && a->no_winds && a->method == VSV_TIME_LINEAR)
        vsv_cli_usage_error("--winds with --no-winds: the winds are for --interp advect or wind only");
    a->inputs = (const char *const *)argv + optind;
    a->ninputs = argc - optind;
    a->vars = vsv_convert_vars(a->vars, a->derive, a->nderive); /* (lives as long as the program) */
}

char *vsv_convert_vars(const char *vars, const char *const *derive, int nderive)
{
    if (!vars)
        return NULL;
    if (!*vars && !nderive) /* "" asks for the derived variables alone */
        vsv_cli_usage_error("--vars '': no variable (with --derive: the derived ones alone)");
    char *out = malloc(strlen(vars) + 1);
    if (!out)
        vsv_cli_die(1, "out of memory");
    size_t n = 0;
    int first = 1;
    for (const char *t = vars; *vars; t++) {
        const size_t len = strcspn(t, ",");
        if (!len) /* ",", "CLW,": a list made wrong */
            vsv_cli_usage_error("--vars '%s': an empty name", vars);
        int derived = 0;
        for (int i = 0; i < nderive && !derived; i++)
            derived = len && strcspn(derive[i], "=") == len && !strncmp(derive[i], t, len);
        if (!derived) {
            if (!first)
                out[n++] = ',';
            memcpy(out + n, t, len);
            n += len, first = 0;
        }
        t += len;
        if (!*t)
            break;
    }
    out[n] = 0;
    return out;
}

void vsv_convert_derive(const vsv_convert_args *a, vsv_run *run)
{
    for (int i = 0; i < a->nderive; i++)
        if (vsv_run_add_derived(run, a->derive[i]))
            vsv_cli_die(1, "%s", vsv_run_error(run));
}

void vsv_convert_setup(const vsv_convert_args *a, vsv_run *run, vsv_meta *out)
{
    vsv_meta_init(out);
    vsv_convert_derive(a, run);
    if (a->times && vsv_run_select(run, a->times, a->dt))
        vsv_cli_die(1, "%s", vsv_run_error(run));
    if (*vsv_run_note(run))
        fprintf(stderr, "%s: %s\n", vsv_cli_tool(), vsv_run_note(run));
    int rc = a->no_winds ? 0 : vsv_run_store_winds(run, a->winds, &a->so);
    if (rc < 0)
        vsv_cli_die(1, "%s", vsv_run_error(run));
    if (a->method != VSV_TIME_LINEAR && vsv_run_add_winds(run, a->winds, &a->so))
        vsv_cli_die(1, "%s", vsv_run_error(run));
    const vsv_meta *m = vsv_run_meta(run);
    if (!a->dt) {
        if (vsv_meta_copy(out, m))
            vsv_cli_die(1, "out of memory");
        return;
    }
    const vsv_interp_opts io = {a->method, 0};
    vsv_interp *ip = NULL;
    if (vsv_interp_open(a->dt, m, &io, NULL, NULL, &ip))
        vsv_cli_die(1, "%s", vsv_interp_error(ip));
    if (vsv_interp_meta(ip, m, out))
        vsv_cli_die(1, "out of memory");
    vsv_interp_free(ip);
}

double vsv_convert_steps(const vsv_convert_args *a, const vsv_run *run)
{
    const int n = vsv_run_nframes(run);
    if (n < 1 || a->dt <= 0)
        return n;
    int64_t first, last;
    vsv_run_window(run, &first, &last);
    if (first < vsv_run_time(run, 0))
        first = vsv_run_time(run, 0);
    if (last > vsv_run_time(run, n - 1))
        last = vsv_run_time(run, n - 1);
    return (double)((last - first) / a->dt) + 1;
}

void vsv_convert_check_space(const vsv_convert_args *a, const vsv_run *run, const vsv_meta *out)
{
    if (vsv_run_nframes(run) < 1)
        return;
    const double steps = vsv_convert_steps(a, run);
    const double step_bytes = (double)out->nx * out->ny * out->nz * out->nvars * sizeof(float);
    char dir[4200];
    snprintf(dir, sizeof dir, "%s", a->out);
    struct statvfs fs;
    if (statvfs(dirname(dir), &fs))
        return; /* the writer says what is wrong with the place */
    const double avail = (double)fs.f_bavail * (double)fs.f_frsize;
    if (steps * step_bytes > avail) {
        const double need = steps * step_bytes, unit = need >= 1e9 ? 1e9 : 1e6;
        const char *u = unit == 1e9 ? "GB" : "MB";
        vsv_cli_die(1,
                    "%s: %.0f steps of %.1f MB are kept beside it until they are encoded: %.1f %s, and its file "
                    "system has %.1f %s free (fewer --vars or --times, or another place)",
                    a->out, steps, step_bytes / 1e6, need / unit, u, avail / unit, u);
    }
}

int vsv_convert_frames(vsv_run *run, int64_t dt, int method, int first, int last, float **fields, vsv_frame_fn emit,
                       void *ctx, const char *label, int *bad_frame, int *dropped)
{
    const vsv_meta *meta = vsv_run_meta(run);
    vsv_interp *ip = NULL;
    int rc = 0;
    *bad_frame = -1;
    const vsv_interp_opts io = {method, 0};
    if (dt && (rc = vsv_interp_open(dt, meta, &io, emit, ctx, &ip))) {
        *bad_frame = -2;
        goto done;
    }
    if (ip)
        vsv_run_place(run, ip);
    for (int i = first; i <= last; i++) {
        if ((rc = vsv_run_read(run, i, fields))) {
            *bad_frame = i;
            break;
        }
        const int64_t t = vsv_run_time(run, i);
        if ((rc = ip ? vsv_interp_push(ip, t, (const float *const *)fields)
                     : emit(ctx, t, (const float *const *)fields)))
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
