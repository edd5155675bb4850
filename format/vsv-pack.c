/* vsv-pack — field stream on stdin (or a file) → .vsv file. */
#include "vsv_cli.h"

#include <errno.h>
#include <getopt.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* clang-format off */ /* (the help text as it prints, a line a line) */
static const char usage[] =
    "Usage: vsv-pack [OPTIONS] -o OUT.vsv [STREAM]\n"
    "Pack a field stream (from vsv-extract or vsv-interp; stdin by default) into a\n"
    "chunked, bricked, delta-encoded .vsv file. OUT.vsv appears only when packing\n"
    "succeeded.\n"
    "Reads a field stream (vsv(5)); writes the .vsv format (vsv(5)).\n"
    "\n"
    "  -o, --output FILE    the .vsv to write (required)\n"
    "  -q, --quiet          no progress bar\n"
    "  -h, --help           this help\n"
    "  -V, --version        print versions\n"
    "\n";
/* clang-format on */

int main(int argc, char **argv)
{
    vsv_cli_init("vsv-pack");
    /* clang-format off */ /* (a table, laid out by hand) */
    static const struct option longopts[] = {{"output", required_argument, 0, 'o'},
                                             {"quiet", no_argument, 0, 'q'},
                                             {"help", no_argument, 0, 'h'},
                                             {"version", no_argument, 0, 'V'},
                                             VSV_CLI_PACK_LONGOPTS,
                                             {0, 0, 0, 0}};
    /* clang-format on */
    vsv_cli_pack pack;
    vsv_cli_pack_init(&pack);
    const char *out = NULL;
    int c;
    argv[0] = (char *)vsv_cli_tool(); /* getopt's messages name the tool as ours do */
    while ((c = getopt_long(argc, argv, "o:qhV", longopts, NULL)) != -1) {
        if (vsv_cli_pack_option(&pack, c, optarg))
            continue;
        switch (c) {
        case 'o': out = optarg; break;
        case 'q': vsv_cli_set_quiet(1); break;
        case 'h':
            fputs(usage, stdout);
            fputs(vsv_cli_pack_help, stdout);
            return 0;
        case 'V': vsv_cli_version();
        default: vsv_cli_getopt_failed();
        }
    }
    if (!out)
        vsv_cli_usage_error("no output file (-o OUT.vsv)");
    vsv_cli_output_kind("-o", out, ".vsv", "a .vsv file");
    if (argc - optind > 1)
        vsv_cli_usage_error("one input stream at most");
    const char *in_name = optind < argc ? argv[optind] : "(stdin)";
    FILE *in = stdin;
    if (optind < argc && strcmp(argv[optind], "-"))
        vsv_cli_refuse_input(out, (const char *const *)&argv[optind], 1);
    if (optind < argc && strcmp(argv[optind], "-"))
        in = vsv_cli_open_input(argv[optind], "rb", 1);

    vsv_stream_reader *r = NULL;
    int rc = vsv_stream_reader_open(in, in_name, &r);
    if (rc)
        vsv_cli_die(1, "%s", vsv_stream_reader_error(r));
    const vsv_meta *meta = vsv_stream_reader_meta(r);
    vsv_cli_pack_resolve(&pack, meta);
    vsv_writer *w = NULL;
    if ((rc = vsv_writer_create(out, meta, &pack.opts, &w)))
        vsv_cli_writer_die(w, out);
    const size_t cells = (size_t)meta->nx * meta->ny * meta->nz;
    float **fields = calloc((size_t)meta->nvars, sizeof *fields);
    for (int v = 0; fields && v < meta->nvars; v++)
        if (!(fields[v] = malloc(cells * sizeof(float))))
            vsv_cli_die(1, "out of memory for a %zu-cell frame", cells);
    if (!fields)
        vsv_cli_die(1, "out of memory");
    int64_t t;
    int n = 0;
    while ((rc = vsv_stream_reader_next(r, &t, fields)) == 1) {
        if ((rc = vsv_writer_add_step(w, t, (const float *const *)fields)))
            vsv_cli_writer_die(w, out);
        n++;
        if (!vsv_cli_quiet() && isatty(2))
            fprintf(stderr, "\rvsv-pack: read %d steps", n);
    }
    if (!vsv_cli_quiet() && isatty(2) && n)
        fputc('\n', stderr);
    if (rc < 0) {
        vsv_writer_free(w);
        vsv_cli_die(1, "%s", vsv_stream_reader_error(r));
    }
    if ((rc = vsv_writer_finish(w, vsv_cli_progress, "vsv-pack: encoding")))
        vsv_cli_writer_die(w, out);
    vsv_writer_free(w);
    vsv_cli_pack_note_file(&pack, out);
    for (int v = 0; v < meta->nvars; v++)
        free(fields[v]);
    vsv_stream_reader_free(r);
    free(fields);
    free(pack.opts.vars);
    if (in != stdin)
        fclose(in);
    return 0;
}
