/* vsv-convert — model files → .vsv in one process: the same steps and the
 * same bytes as vsv-extract | vsv-interp | vsv-pack. */
#include "vsv_convert_cli.h"
#include "vsv_vdb.h"

#include <stdlib.h>

/* clang-format off */ /* (the help text as it prints, a line a line) */
static const char usage[] =
    "Usage: vsv-convert [OPTIONS] FILE... -o OUT.vsv\n"
    "Convert model output to a .vsv file. Several files are one run in time order\n"
    "(gaps and overlaps are errors). The result is byte for byte the file of\n"
    "  vsv-extract FILE... | vsv-interp --time-res D | vsv-pack -o OUT.vsv\n"
    "and appears only when the conversion succeeded.\n"
    "Reads, detected from the content (never the name):\n" VSV_CLI_MODEL_FORMATS VSV_CLI_VDB_FORMAT
    "Writes the .vsv format (vsv(5)).\n"
    "\n";
/* clang-format on */

static int add(void *w, int64_t time, const float *const *fields) { return vsv_writer_add_step(w, time, fields); }

/* The first pass of a fine --time-res: the statistics of the frames only. */
typedef struct tally {
    vsv_pack_stats *st;
    int nvars;
    size_t cells;
} tally;

static int count(void *p, int64_t time, const float *const *fields)
{
    (void)time;
    tally *t = p;
    vsv_pack_stats_add(t->st, t->nvars, t->cells, fields);
    return 0;
}

int main(int argc, char **argv)
{
    vsv_cli_init("vsv-convert");
    vsv_vdb_source_register(); /* .vdb sequences too (interop/) */
    vsv_convert_args a;
    vsv_convert_args_parse(&a, argc, argv, usage, 0);
    vsv_cli_refuse_input(a.out, (const char *const *)a.inputs, a.ninputs);
    vsv_cli_refuse_input(a.out, &a.so.heights, 1);
    vsv_run *run = NULL;
    if (vsv_run_open(a.inputs, a.ninputs, &a.so, a.vars, NULL, &run))
        vsv_cli_die(1, "%s", vsv_run_error(run));
    /* with advect the run reads the winds too; the file gets only what the
     * interpolation emits */
    vsv_meta out;
    vsv_convert_setup(&a, run, &out);
    const vsv_meta *meta = vsv_run_meta(run);
    vsv_cli_pack_resolve(&a.pack, &out);
    const int n = vsv_run_nframes(run);
    /* frames finer than the model's: two passes (the interpolation run once
     * for the value ranges, once more to encode as it goes), no spool */
    const int planned = vsv_convert_steps(&a, run) > n;
    if (!planned)
        vsv_convert_check_space(&a, run, &out);
    vsv_writer *w = NULL;
    if (vsv_writer_create(a.out, &out, &a.pack.opts, &w))
        vsv_cli_writer_die(w, a.out);
    const size_t cells = (size_t)meta->nx * meta->ny * meta->nz;
    float **fields = calloc((size_t)meta->nvars, sizeof *fields);
    for (int v = 0; fields && v < meta->nvars; v++)
        if (!(fields[v] = malloc(cells * sizeof(float))))
            fields = NULL;
    if (!fields)
        vsv_cli_die(1, "%s: out of memory (%.1f MB for a step's %d fields)", a.inputs[0],
                    (double)meta->nvars * cells * 4 / 1048576, meta->nvars);
    int bad, dropped;
    if (planned) {
        vsv_pack_stats *st = calloc((size_t)out.nvars, sizeof *st);
        if (!st)
            vsv_cli_die(1, "out of memory");
        vsv_pack_stats_init(st, out.nvars);
        tally t = {st, out.nvars, cells};
        if (vsv_convert_frames(run, a.dt, a.method, 0, n - 1, fields, count, &t, "vsv-convert: ranges (1 of 2)", &bad,
                               NULL)) {
            vsv_writer_free(w);
            vsv_cli_die(1, "%s", bad >= 0 ? vsv_run_error(run) : "out of memory");
        }
        if (vsv_writer_expect(w, st))
            vsv_cli_writer_die(w, a.out);
        free(st);
    }
    if (vsv_convert_frames(run, a.dt, a.method, 0, n - 1, fields, add, w,
                           planned ? "vsv-convert: encoding (2 of 2)" : "vsv-convert: reading", &bad, &dropped)) {
        if (bad == -1)
            vsv_cli_writer_die(w, a.out);
        vsv_writer_free(w);
        vsv_cli_die(1, "%s", bad >= 0 ? vsv_run_error(run) : "out of memory");
    }
    if (dropped && !vsv_cli_quiet())
        fprintf(stderr,
                "vsv-convert: note: %d of %d model times lie between the steps every %s from the first "
                "and are not kept themselves\n",
                dropped, vsv_run_within(run), a.res_text);
    if (vsv_writer_finish(w, vsv_cli_progress, "vsv-convert: encoding"))
        vsv_cli_writer_die(w, a.out);
    vsv_writer_free(w);
    vsv_cli_pack_note_file(&a.pack, a.out);
    vsv_meta_clear(&out);
    for (int v = 0; v < meta->nvars; v++)
        free(fields[v]);
    free(fields);
    free(a.pack.opts.vars);
    free((char *)a.vars); /* (vsv_convert_vars's copy) */
    vsv_run_free(run);
    return 0;
}
