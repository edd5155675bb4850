/* vsv_convert_cli.h — vsv-convert's command line and its read loop, shared
 * by vsv-convert and vsv-convert-mpi so that both take the same options and
 * make the same frames. Program code: linked into those tools, never into a
 * library (it prints and exits). */
#ifndef VSV_CONVERT_CLI_H
#define VSV_CONVERT_CLI_H

#include "vsv_cli.h"
#include "vsv_convert.h"

enum { VSV_CLI_MAX_DERIVE = 32 };

/* The help of --derive, shared by vsv-convert, vsv-convert-mpi and
 * vsv-extract. */
#define VSV_CLI_DERIVE_HELP                                                                                            \
    "      --derive SPEC    add a variable computed at every model time from the\n"                                    \
    "                       file's 3-D fields (read whether or not in --vars):\n"                                      \
    "                       NAME=EXPR[:UNITS] with + - * / ^ ( ) numbers, field\n"                                     \
    "                       names (\"QUOTED\" when odd), pressure (Pa), sqrt exp log\n"                                \
    "                       abs min max; or a built-in: condensate, wind_speed,\n"                                     \
    "                       theta, rh (formulas in the man page and the file);\n"                                      \
    "                       repeatable\n"

/* What the command line asked for: plain info over argv's strings, but
 * vars (--vars less the derived names: vsv_convert_vars's copy, which the
 * program frees with free()). */
typedef struct vsv_convert_args {
    const char *out, *vars, *times;
    int64_t dt;                /* --time-res in seconds, 0 for none */
    const char *res_text;      /* --time-res as given */
    vsv_cli_pack pack;         /* packing options (opts.vars set by resolve) */
    vsv_source_opts so;        /* vertical grid, CAMx, OpenVDB options */
    const char *const *inputs; /* the model files, borrowed from argv */
    int ninputs;
    int stats;         /* --stats (vsv-convert-mpi only) */
    int method;        /* --interp: VSV_TIME_LINEAR, VSV_TIME_ADVECT or VSV_TIME_WIND */
    const char *winds; /* --winds FILE, or NULL */
    int no_winds;      /* --no-winds: the wind is not stored */
    /* --derive SPEC, in order (vsv_run_add_derived) */
    const char *derive[VSV_CLI_MAX_DERIVE];
    int nderive;
} vsv_convert_args;

/* The formats the conversion tools read, for their --help (vsv-extract,
 * vsv-convert, vsv-convert-mpi; vsv-info describes all but OpenVDB). */
#define VSV_CLI_MODEL_FORMATS                                                                                          \
    "  MM5 v3 (MMOUT, REGRID/INTERPB, INTERPF; TERRAIN, BDYOUT and LOWBDY hold no\n"                                   \
    "  volumes: listed, never converted), WRF netCDF (wrfout), CAMx UAM-IV (AVERAGE,\n"                                \
    "  INSTANT, AIRQUALITY, EMISSIONS), IOAPI netCDF (CMAQ CONC/ACONC, CAMx netCDF),\n"                                \
    "  CF netCDF (e.g. from vsv-export --netcdf), GrADS .ctl + data"
#define VSV_CLI_VDB_FORMAT ",\n  and OpenVDB .vdb sequences (one file per step, float grids).\n"

/* The option list of --help, shared by both tools. */
extern const char vsv_convert_options_help[];

/* Parses argv as vsv-convert does. `head` is the tool's usage text before
 * the option list; with `mpi`, --stats is an option too. Prints the help
 * (exit 0), the version (exit 0) or a usage error (exit 2) itself. */
void vsv_convert_args_parse(vsv_convert_args *a, int argc, char **argv, const char *head, int mpi);

/* --vars LIST less the names its --derive SPECs give (NAME=... or a
 * built-in's own name): a derived variable is always written, and naming
 * it in --vars too asks for nothing more. A copy (caller frees with
 * free()); NULL when vars is NULL (exits 1 when out of memory; 2 when a
 * name in vars is empty, or vars is "" without a derived variable). */
char *vsv_convert_vars(const char *vars, const char *const *derive, int nderive);
/* Adds each --derive of a to the run (exits 1 with the reason). */
void vsv_convert_derive(const vsv_convert_args *a, vsv_run *run);

/* After vsv_run_open (with times NULL): adds --derive (vsv_convert_derive), selects --times (among the output
 * steps with --time-res: vsv_run_select; a note on stderr when a single
 * time fell between steps), stores the wind unless --no-winds
 * (vsv_run_store_winds: where the input, or --winds FILE, has one), with
 * --interp advect adds the auxiliary winds to the run
 * (exits 1 naming what is wrong with either); fills out (uninitialised) with the
 * metadata of the frames vsv_convert_frames emits: the run's without the
 * auxiliary winds. Caller clears out with vsv_meta_clear. */
void vsv_convert_setup(const vsv_convert_args *a, vsv_run *run, vsv_meta *out);

/* How many steps the conversion writes: the run's frames, or (with
 * --time-res) about its span every dt. */
double vsv_convert_steps(const vsv_convert_args *a, const vsv_run *run);

/* Exits 1 before any reading when the steps the conversion writes (the
 * run's frames, or its span every dt) cannot be spooled beside a->out: the
 * writer keeps every step's floats in a temporary there until it encodes
 * (out: the metadata vsv_convert_setup gave). */
void vsv_convert_check_space(const vsv_convert_args *a, const vsv_run *run, const vsv_meta *out);

/* Feeds input frames first..last of the run through the time
 * interpolation (when dt > 0, its grid starting at the run's first time;
 * method: --interp's, the winds in the run with a method other than linear:
 * vsv_convert_setup) to
 * emit; fields: nvars caller buffers of nx*ny*nz floats. Progress goes to
 * label (NULL: none); *dropped (may be NULL) receives the count of input
 * frames between grid times (vsv_interp_dropped). Returns 0; or a negative code with *bad_frame the
 * input frame that did not read (vsv_run_error says why), -1 when emit
 * failed, -2 when memory ran out. */
int vsv_convert_frames(vsv_run *run, int64_t dt, int method, int first, int last, float **fields, vsv_frame_fn emit,
                       void *ctx, const char *label, int *bad_frame, int *dropped);

#endif
