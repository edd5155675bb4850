/* vsv-convert — model files → .vsv in one process: the same steps and the
 * same bytes as vsv-extract | vsv-interp | vsv-pack. */
#include "vsv_cli.h"
#include "vsv_convert.h"

#include <getopt.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char usage[] =
    "Usage: vsv-convert [OPTIONS] FILE... -o OUT.vsv\n"
    "Convert model output (MM5 v3, GrADS; detected from the content) to a .vsv file.\n"
    "Several files are one run in time order (gaps and overlaps are errors). The\n"
    "result is byte for byte the file of\n"
    "  vsv-extract FILE... | vsv-interp --time-res D | vsv-pack -o OUT.vsv\n"
    "and appears only when the conversion succeeded.\n"
    "\n"
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

typedef struct ctx {
    vsv_writer *w;
    int frames;
} ctx;

static int add(void *p, int64_t time, const float *const *fields)
{
    ctx *c = p;
    c->frames++;
    return vsv_writer_add_step(c->w, time, fields);
}

int main(int argc, char **argv)
{
    vsv_cli_init("vsv-convert");
    static const struct option longopts[] = {{"output", required_argument, 0, 'o'},
                                             {"time-res", required_argument, 0, 'r'},
                                             {"vars", required_argument, 0, 'v'},
                                             {"times", required_argument, 0, 't'},
                                             {"quiet", no_argument, 0, 'q'},
                                             {"help", no_argument, 0, 'h'},
                                             {"version", no_argument, 0, 'V'},
                                             VSV_SOURCE_LONGOPTS,
                                             VSV_CLI_PACK_LONGOPTS,
                                             {0, 0, 0, 0}};
    vsv_cli_pack pack;
    vsv_cli_pack_init(&pack);
    vsv_source_opts so;
    vsv_source_opts_init(&so);
    const char *out = NULL, *vars = NULL, *times = NULL;
    int64_t dt = 0;
    const char *res_text = NULL;
    int c;
    while ((c = getopt_long(argc, argv, "o:r:v:t:qhV", longopts, NULL)) != -1) {
        int h = vsv_source_cli_option(&so, c, optarg);
        if (h < 0)
            vsv_cli_usage_error("bad value '%s' for a vertical-grid option", optarg);
        if (h || vsv_cli_pack_option(&pack, c, optarg))
            continue;
        switch (c) {
        case 'o': out = optarg; break;
        case 'r':
            res_text = optarg;
            if (vsv_cli_duration(optarg, &dt))
                vsv_cli_usage_error("--time-res %s: expected a duration with its unit: 30s, 10m, 1h, 1d", optarg);
            break;
        case 'v': vars = optarg; break;
        case 't': times = optarg; break;
        case 'q': vsv_cli_set_quiet(1); break;
        case 'h':
            fputs(usage, stdout);
            fputs(vsv_cli_pack_help, stdout);
            return 0;
        case 'V': vsv_cli_version();
        default: vsv_cli_usage_error("unknown option");
        }
    }
    if (!out)
        vsv_cli_usage_error("no output file (-o OUT.vsv)");
    if (optind >= argc)
        vsv_cli_usage_error("no input file");
    char tmsg[300];
    if (times && vsv_timesel_parse(times, NULL, 0, 0, &(vsv_timesel){0}, tmsg, sizeof tmsg))
        vsv_cli_usage_error("--times %s: %s", times, tmsg);
    vsv_run *run = NULL;
    if (vsv_run_open((const char *const *)argv + optind, argc - optind, &so, vars, times, &run))
        vsv_cli_die(1, "%s", vsv_run_error(run));
    const vsv_meta *meta = vsv_run_meta(run);
    vsv_cli_pack_resolve(&pack, meta);
    ctx cx = {NULL, 0};
    if (vsv_writer_create(out, meta, &pack.opts, &cx.w))
        vsv_cli_writer_die(cx.w, out);
    const size_t cells = (size_t)meta->nx * meta->ny * meta->nz;
    float **fields = calloc((size_t)meta->nvars, sizeof *fields);
    for (int v = 0; fields && v < meta->nvars; v++)
        if (!(fields[v] = malloc(cells * sizeof(float))))
            vsv_cli_die(1, "out of memory");
    vsv_interp *ip = NULL;
    if (dt && vsv_interp_create(dt, meta->nvars, cells, add, &cx, &ip))
        vsv_cli_die(1, "out of memory");
    const int n = vsv_run_nframes(run);
    for (int i = 0; i < n; i++) {
        if (vsv_run_read(run, i, fields)) {
            vsv_writer_free(cx.w);
            vsv_cli_die(1, "%s", vsv_run_error(run));
        }
        const int64_t t = vsv_run_time(run, i);
        if (ip ? vsv_interp_push(ip, t, (const float *const *)fields) : add(&cx, t, (const float *const *)fields))
            vsv_cli_writer_die(cx.w, out);
        vsv_cli_progress("vsv-convert: reading", i + 1, n);
    }
    if (vsv_interp_dropped(ip) && !vsv_cli_quiet())
        fprintf(stderr, "vsv-convert: note: %d of %d model times lie between the steps every %s from the first "
                "and are not kept themselves\n", vsv_interp_dropped(ip), n, res_text);
    if (vsv_writer_finish(cx.w, vsv_cli_progress, "vsv-convert: encoding"))
        vsv_cli_writer_die(cx.w, out);
    vsv_writer_free(cx.w);
    vsv_interp_free(ip);
    for (int v = 0; v < meta->nvars; v++)
        free(fields[v]);
    free(fields);
    free(pack.opts.vars);
    vsv_run_free(run);
    return 0;
}
