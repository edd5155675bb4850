/* vsv-interp — field stream → field stream at a finer time step. */
#include "vsv_cli.h"
#include "vsv_convert.h"

#include <errno.h>
#include <getopt.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* clang-format off */ /* (the help text as it prints, a line a line) */
static const char usage[] =
    "Usage: vsv-interp --time-res DURATION [--interp linear|advect|wind] [STREAM]\n"
    "Read a field stream (stdin by default) and write it with frames every DURATION\n"
    "(30s, 10m, 1h30m, 1d or ISO 8601 PT1H30M: a unit is required), at the first\n"
    "frame's time + k*DURATION:\n"
    "values are linear in time between consecutive model outputs. Input frames on\n"
    "that grid pass through unchanged; those between its steps are not written\n"
    "(said on stderr), so every output step is exactly DURATION apart and a\n"
    "DURATION coarser than the input's keeps every k-th frame.\n"
    "Reads and writes the field stream (vsv(5)): from vsv-extract, for vsv-pack.\n"
    "\n"
    "  -r, --time-res D     the output time step (required)\n"
    "  -i, --interp M       linear (default): a blend of the two outputs around each\n"
    "                       frame; advect: the earlier output carried forward and the\n"
    "                       later one carried back along the winds, then blended the\n"
    "                       same way, so what moves moves instead of cross-fading;\n"
    "                       each species in each region of the grid is carried as far\n"
    "                       as best maps one output onto the other (0 to 1.25 times\n"
    "                       the air's displacement, fitted per interval; 0 is linear);\n"
    "                       wind: carried exactly as far as the air moves. On real\n"
    "                       runs: vsv-interp(1), ACCURACY. Needs the winds in the\n"
    "                       stream: vsv-extract --add-winds\n"
    "  -j, --threads N      advect, wind: threads (default: all cores)\n"
    "  -h, --help           this help\n"
    "  -V, --version        print versions\n";
/* clang-format on */

/* emit's context: the writer, opened once the emitted variables are known */
typedef struct out {
    vsv_stream_writer *w;
} out;

static int emit(void *ctx, int64_t time, const float *const *fields)
{
    return vsv_stream_writer_frame(((out *)ctx)->w, time, fields);
}

int main(int argc, char **argv)
{
    vsv_cli_init("vsv-interp");
    /* clang-format off */ /* (a table, laid out by hand) */
    static const struct option longopts[] = {{"time-res", required_argument, 0, 'r'},
                                             {"interp", required_argument, 0, 'i'},
                                             {"threads", required_argument, 0, 'j'},
                                             {"help", no_argument, 0, 'h'},
                                             {"version", no_argument, 0, 'V'},
                                             {0, 0, 0, 0}};
    /* clang-format on */
    int64_t dt = 0;
    const char *res_text = "";
    int c;
    vsv_interp_opts io = {VSV_TIME_LINEAR, 0};
    long nth;
    argv[0] = (char *)vsv_cli_tool(); /* getopt's messages name the tool as ours do */
    while ((c = getopt_long(argc, argv, "r:i:j:hV", longopts, NULL)) != -1) {
        switch (c) {
        case 'i':
            if ((io.method = vsv_interp_method(optarg)) < 0)
                vsv_cli_usage_error("--interp %s: expected linear, advect or wind", optarg);
            break;
        case 'j':
            if (vsv_cli_int(optarg, 1, 64, &nth))
                vsv_cli_usage_error("--threads %s: must be an integer 1..64", optarg);
            io.threads = (int)nth;
            break;
        case 'r':
            res_text = optarg;
            vsv_cli_duration("--time-res", optarg, &dt);
            break;
        case 'h': fputs(usage, stdout); return 0;
        case 'V': vsv_cli_version();
        default: vsv_cli_getopt_failed();
        }
    }
    if (!dt)
        vsv_cli_usage_error("--time-res is required");
    if (argc - optind > 1)
        vsv_cli_usage_error("one input stream at most");
    const char *name = optind < argc ? argv[optind] : "(stdin)";
    FILE *in = stdin;
    if (optind < argc)
        in = vsv_cli_open_input(argv[optind], "rb", 1);
    if (isatty(1))
        vsv_cli_usage_error("refusing to write a binary field stream to a terminal; pipe it into vsv-pack");
    vsv_stream_reader *r = NULL;
    if (vsv_stream_reader_open(in, name, &r))
        vsv_cli_die(1, "%s", vsv_stream_reader_error(r));
    const vsv_meta *m = vsv_stream_reader_meta(r);
    const size_t cells = (size_t)m->nx * m->ny * m->nz;
    out o = {NULL};
    vsv_interp *ip = NULL;
    /* the stream out carries the species; the winds (if any) stay here */
    vsv_meta om;
    vsv_meta_init(&om);
    int orc = vsv_interp_open(dt, m, &io, emit, &o, &ip);
    if (orc == VSV_ENOTFOUND)
        vsv_cli_die(1, "%s: %s; extract them with vsv-extract --add-winds", name, vsv_interp_error(ip));
    if (orc)
        vsv_cli_die(1, "%s: %s", name, vsv_interp_error(ip));
    if (vsv_interp_meta(ip, m, &om) || vsv_stream_writer_open(stdout, &om, &o.w))
        vsv_cli_die(1, "cannot start: %s", strerror(errno));
    float **fields = calloc((size_t)m->nvars, sizeof *fields);
    for (int v = 0; fields && v < m->nvars; v++)
        if (!(fields[v] = malloc(cells * sizeof(float))))
            vsv_cli_die(1, "out of memory");
    int64_t t;
    int rc;
    while ((rc = vsv_stream_reader_next(r, &t, fields)) == 1)
        if (vsv_interp_push(ip, t, (const float *const *)fields))
            vsv_cli_die(1, "writing to stdout: %s", strerror(errno));
    if (rc < 0)
        vsv_cli_die(1, "%s", vsv_stream_reader_error(r));
    if (vsv_interp_dropped(ip))
        fprintf(stderr, "vsv-interp: note: %d input frame%s between the steps every %s from the first, not kept\n",
                vsv_interp_dropped(ip), vsv_interp_dropped(ip) == 1 ? " lies" : "s lie", res_text);
    if (vsv_stream_writer_end(o.w))
        vsv_cli_die(1, "writing to stdout: %s", strerror(errno));
    vsv_interp_free(ip);
    vsv_stream_writer_free(o.w);
    vsv_meta_clear(&om);
    for (int v = 0; v < m->nvars; v++)
        free(fields[v]);
    free(fields);
    vsv_stream_reader_free(r);
    return 0;
}
