/* vsv_convert.h — model readers behind one "source" interface (grid,
 * projection, times, fields), as DESIGN.md §1 draws them. The format of a
 * file is detected from its content, never from its name. */
#ifndef VSV_CONVERT_H
#define VSV_CONVERT_H

#include "vsv_format.h"

#ifdef __cplusplus
extern "C" {
#endif

VSV_API_BEGIN

/* -------------------------------------------------------------- sources */

typedef struct vsv_source vsv_source;

/* One field a source offers: plain info. */
typedef struct vsv_field_info {
    char name[64];
    char units[64];
    char description[128];
    char ordering[16]; /* the model's own layout name, e.g. "YXS", or "" */
    int nlevels;       /* 0 for a 2-D field */
    int is_volume;     /* can be extracted onto the 3-D grid */
    int is_default;    /* extracted when no --vars is given */
    char role[48];     /* what a field that is not a volume is, e.g.
                        * "boundary slab", or "" (2-D or not on the grid) */
} vsv_field_info;

/* How a source builds its grid: plain info. */
typedef struct vsv_source_opts {
    int vertical;        /* VSV_VERT_NATIVE (default) or VSV_VERT_EVEN */
    int vertical_set;    /* given by --vertical (else --nz or --ztop mean even) */
    int nz;              /* even: number of levels (0: 40) */
    double ztop;         /* even: top of the grid, m above sea level (0: the model top) */
    const char *heights; /* CAMx: the height/pressure companion file, or NULL */
    const char *met;     /* CAMx: a folder of met companions (found by content), or NULL */
    vsv_proj proj;       /* a projection for files without one (CAMx 5); kind NONE = not given */
    unsigned proj_set;   /* which of --lat0 --lon0 --lat1 --lat2 were given (bits 0..3) */
    /* sequences of one-step files without times of their own (OpenVDB):
     * time of file i = time_start + i * time_step when time_step > 0
     * (time_start INT64_MIN: not given) */
    int64_t time_step, time_start;
    /* the whole sequence this file belongs to and its place in it (set by
     * vsv_run; a lone file is a sequence of one) */
    const char *const *seq;
    int nseq, seq_index;
} vsv_source_opts;

void vsv_source_opts_init(vsv_source_opts *o);

/* Opens a model file, detecting its format from its content. opts may be
 * NULL for defaults. Caller frees with vsv_source_free; on failure *out may
 * hold a handle whose error says why (free it too). */
int vsv_source_open(const char *path, const vsv_source_opts *opts, vsv_source **out);
/* A human description of the file's own header (e.g. MM5's big header and
 * field list); caller frees with free(). NULL if the format has none. */
char *vsv_source_summary(vsv_source *s);
void vsv_source_free(vsv_source *s);
const char *vsv_source_error(const vsv_source *s);
/* Short format name, e.g. "GrADS". */
const char *vsv_source_format(const vsv_source *s);
/* Grid, projection, levels, terrain and source description, with no
 * variables (borrowed, valid until free). */
const vsv_meta *vsv_source_grid(const vsv_source *s);
int vsv_source_nfields(const vsv_source *s);
/* Field i (NULL outside 0..nfields-1), borrowed. */
const vsv_field_info *vsv_source_field(const vsv_source *s, int i);
int vsv_source_find_field(const vsv_source *s, const char *name);
/* The path of the file field i is read from: the source's own, or a
 * companion's (CAMx --met); borrowed, valid until free. */
const char *vsv_source_field_path(const vsv_source *s, int i);
int vsv_source_ntimes(const vsv_source *s);
/* The time of step t (0 outside 0..ntimes-1). */
int64_t vsv_source_time(const vsv_source *s, int t);
/* With --vertical native (opts.vertical VSV_VERT_NATIVE): the height (m
 * above sea level) of every cell's level at time t, per column, into out
 * (nx*ny*nz floats, x fastest), for models whose levels move in time (WRF
 * eta, MM5 pressure levels by H, CAMx layers by the ZP file) or vary by
 * column (MM5 sigma). The .vsv itself records each level's mean height;
 * this is the data a per-column, per-time height axis needs.
 * VSV_EUNSUPPORTED on even grids and formats without such heights. */
int vsv_source_heights(vsv_source *s, int t, float *out);
/* Reads field i at time t into out (nx*ny*nz floats of the grid, x fastest;
 * levels a field lacks and missing values are NaN). */
int vsv_source_read(vsv_source *s, int field, int t, float *out);

/* Command-line options of the vertical grid (--vertical even|native, --nz,
 * --ztop), shared by vsv-extract and vsv-convert. */
enum {
    VSV_SOURCE_OPT_VERTICAL = 2000,
    VSV_SOURCE_OPT_NZ,
    VSV_SOURCE_OPT_ZTOP,
    VSV_SOURCE_OPT_HEIGHTS,
    VSV_SOURCE_OPT_PROJ,
    VSV_SOURCE_OPT_LAT0,
    VSV_SOURCE_OPT_LON0,
    VSV_SOURCE_OPT_LAT1,
    VSV_SOURCE_OPT_LAT2,
    VSV_SOURCE_OPT_TIME_STEP,
    VSV_SOURCE_OPT_TIME_START,
    VSV_SOURCE_OPT_MET
};
#define VSV_SOURCE_LONGOPTS                                                                                            \
    {"vertical", required_argument, 0, VSV_SOURCE_OPT_VERTICAL}, {"nz", required_argument, 0, VSV_SOURCE_OPT_NZ},      \
        {"ztop", required_argument, 0, VSV_SOURCE_OPT_ZTOP},                                                           \
        {"heights", required_argument, 0, VSV_SOURCE_OPT_HEIGHTS},                                                     \
        {"proj", required_argument, 0, VSV_SOURCE_OPT_PROJ}, {"lat0", required_argument, 0, VSV_SOURCE_OPT_LAT0},      \
        {"lon0", required_argument, 0, VSV_SOURCE_OPT_LON0}, {"lat1", required_argument, 0, VSV_SOURCE_OPT_LAT1},      \
        {"lat2", required_argument, 0, VSV_SOURCE_OPT_LAT2},                                                           \
        {"time-step", required_argument, 0, VSV_SOURCE_OPT_TIME_STEP},                                                 \
        {"time-start", required_argument, 0, VSV_SOURCE_OPT_TIME_START},                                               \
    {                                                                                                                  \
        "met", required_argument, 0, VSV_SOURCE_OPT_MET                                                                \
    }
#define VSV_SOURCE_HELP                                                                                                \
    "Vertical grid:\n"                                                                                                 \
    "  --vertical native|even  the model's own levels (default: every value as the\n"                                  \
    "                       model wrote it) or even heights above sea level (linear\n"                                 \
    "                       in height between levels: peaks between two even levels\n"                                 \
    "                       are lost; cells below the ground are empty)\n"                                             \
    "  --nz N               even: number of levels (default 40; implies even)\n"                                       \
    "  --ztop METRES        even: top of the grid (default: the model top; implies even)\n"                            \
    "CAMx:\n"                                                                                                          \
    "  --heights ZPFILE     layer heights from the height/pressure file (without it the\n"                             \
    "                       vertical axis is the layer index)\n"                                                       \
    "  --met DIR            the met input files in DIR, found by their content: the\n"                                 \
    "                       height/pressure file as the vertical coordinate, wind as U\n"                              \
    "                       and V, TEMP, HUMIDITY, KV, cloud/rain (CWC RWC ...), PRESS;\n"                             \
    "                       each checked against the file's grid, layers and hours\n"                                  \
    "  --proj NAME --lat0 D --lon0 D --lat1 D --lat2 D  the projection of a CAMx 5\n"                                  \
    "                       file (its header has none): lcc, pstereo, mercator,\n"                                     \
    "                       tmerc, albers or latlon\n"                                                                 \
    "OpenVDB sequences (one .vdb per step, given in time order):\n"                                                    \
    "  --time-step DURATION the spacing of the steps (e.g. 10m, 1h) of files without\n"                                \
    "                       \"time\" metadata (files from vsv-export have it; a file\n"                                \
    "                       with its own time and --time-step is an error)\n"                                          \
    "  --time-start ISO     the time of the first file (required with --time-step)\n"
/* 1 if id was one of these options, 0 if not, -1 for a bad value. */
int vsv_source_cli_option(vsv_source_opts *o, int id, const char *arg);
/* Why arg is a bad value for option id ("--proj utm: expected latlon, lcc,
 * ..."), into msg (caller buffer of cap bytes). */
void vsv_source_cli_why(int id, const char *arg, char *msg, size_t cap);
/* Checks the options together once all are given (a projection with the
 * parameters it needs, --time-step with --time-start); 0, or VSV_EINVAL with
 * the reason in msg (caller buffer of cap bytes). */
int vsv_source_opts_check(const vsv_source_opts *o, char *msg, size_t cap);

/* ------------------------------------------------------------ a run */

/* Several model files forming one run in time order (the extraction both
 * vsv-extract and vsv-convert do): same grid and fields in every file,
 * files sorted by their first time, no overlaps, no gaps. */
typedef struct vsv_run vsv_run;

/* vars: comma-separated names or NULL for the default fields; times: "A:B"
 * (indices or ISO times, either end may be empty) or NULL. Caller frees with
 * vsv_run_free; on failure *out may hold a handle whose error says why. */
int vsv_run_open(const char *const *paths, int npaths, const vsv_source_opts *opts, const char *vars, const char *times,
                 vsv_run **out);
void vsv_run_free(vsv_run *r);
const char *vsv_run_error(const vsv_run *r);
/* "" or a note the caller should show: which step a --times of one time
 * between steps took (borrowed until free). */
const char *vsv_run_note(const vsv_run *r);
/* Grid and selected variables; borrowed until free. */
const vsv_meta *vsv_run_meta(const vsv_run *r);
int vsv_run_nframes(const vsv_run *r);
int64_t vsv_run_time(const vsv_run *r, int i);
/* Selects times (the grammar of vsv_timesel_parse) once more, on the run
 * as opened: with dt 0 among the model frames; with dt > 0 among the
 * output steps origin + k*dt (vsv-convert --time-res: what --times means
 * there), keeping the model frames that bound them (the last at or before
 * the first step, the first at or after the last). Before
 * vsv_run_add_winds. VSV_ERANGE / VSV_EINVAL with the reason (naming the
 * valid steps), more than VSV_RUN_MAX_STEPS output steps VSV_ERANGE. */
int vsv_run_select(vsv_run *r, const char *times, int64_t dt);
enum { VSV_RUN_MAX_STEPS = 10000000 };
/* The times of the first and last selected steps (INT64_MIN, INT64_MAX
 * when nothing was selected). */
void vsv_run_window(const vsv_run *r, int64_t *first, int64_t *last);
/* How many of the run's frames lie in that window (the others only bound
 * the interpolation into it). */
int vsv_run_within(const vsv_run *r);
/* Reads frame i: fields[v] are caller buffers of nx*ny*nz floats. */
int vsv_run_read(vsv_run *r, int i, float *const *fields);
/* Stores the model's wind (vsv-convert's default): appends the species
 * wind_east, wind_north and, where the model has a vertical wind, wind_up
 * (VSV_WIND_EAST ..., m s-1, earth-relative at mass points: the source's
 * destaggered U and V rotated column by column with vsv_wind_rotation, W as
 * it is), the attribute "vector:wind" naming them and VSV_WIND_SOURCE_ATTR
 * saying what the model's winds were. From companion or the run's own files
 * as vsv_run_add_winds; after the derived variables, before the auxiliary
 * winds. 1, with no message, when the run's files have no wind (no U and V
 * nor UWIND and VWIND in the first); errors with the reason. */
int vsv_run_store_winds(vsv_run *r, const char *companion, const vsv_source_opts *opts);
/* The rotation of a grid-relative wind to east and north in each column of
 * m placed with cell (0, 0) at projected origin: rot[4 c .. 4 c + 3] for
 * column c (i fastest) such that east = u rot[0] + v rot[1] and north =
 * u rot[2] + v rot[3] (from vsv_proj_jacobian). 0, or its error. */
int vsv_wind_rotation(const vsv_meta *m, const double origin[2], float *rot);
/* u and v (nz planes of plane cells) rotated in place with rot. */
void vsv_wind_rotate(const float *rot, size_t plane, int nz, float *u, float *v);
/* The text of VSV_WIND_SOURCE_ATTR: the n components' field names, the
 * file and its format, and how the model (g->model) places its winds. */
void vsv_wind_origin(const vsv_meta *g, const char *format, const char *file, char names[3][16], int n, char *buf,
                     size_t cap);
/* Appends the winds as the variables wind.u, wind.v (and wind.w when there
 * is a vertical wind) and the attribute "winds" saying whence (see
 * VSV_WIND_U): from companion (a model file on the same grid, with U and V,
 * or UWIND and VWIND, at every time of the run; opened with opts) or, when
 * NULL, from the run's own files. VSV_ENOTFOUND naming what is missing. */
int vsv_run_add_winds(vsv_run *r, const char *companion, const vsv_source_opts *opts);
/* Bytes of model input the run covers (for throughput figures). */
uint64_t vsv_run_input_bytes(const vsv_run *r);

/* Appends the derived variable of spec (vsv-convert --derive; the grammar
 * and the built-ins are in vsv_derive.c and vsv-convert(1)): NAME=EXPR or
 * NAME=EXPR:UNITS, an expression over the run's 3-D fields, numbers and
 * `pressure`; or the name of a built-in (condensate, wind_speed, theta, rh).
 * Computed at every frame from the fields as read (on the run's grid, before
 * any time interpolation), whether or not they are selected themselves. Its
 * description holds the formula, and the attribute "derived NAME" the whole
 * formula with where its inputs come from. Before vsv_run_add_winds.
 * VSV_EINVAL (a bad expression, saying at which character of spec; a name
 * taken), VSV_ENOTFOUND (an unknown name listing the file's fields; a
 * built-in's missing inputs, named), the reason in vsv_run_error. */
int vsv_run_add_derived(vsv_run *r, const char *spec);

/* --------------------------------------------------------- expressions */

/* An arithmetic expression over named float inputs, compiled once and
 * evaluated over arrays (the engine of vsv_run_add_derived). Grammar:
 *   expr  := term (('+' | '-') term)*
 *   term  := unary (('*' | '/') unary)*
 *   unary := ('-' | '+') unary | power
 *   power := value ('^' unary)?          right-associative, above unary minus
 *   value := NUMBER | NAME | "QUOTED NAME" | FUNC '(' expr (',' expr)* ')'
 *          | '(' expr ')'
 * NUMBER: digits, fraction, exponent (1, 2.5, .5, 6.112e2). FUNC: sqrt exp
 * log abs (one argument), min max (two or more). Blanks are ignored. */
typedef struct vsv_expr vsv_expr;
enum { VSV_EXPR_MAX_OPS = 256, VSV_EXPR_MAX_DEPTH = 32 };

/* Compiles text against the nnames input names (borrowed for the call).
 * Caller frees *out with vsv_expr_free. VSV_EINVAL with msg (caller buffer
 * of cap bytes) saying what was wrong and *pos the 1-based character of text
 * where (an unknown name: where it starts; msg has no position in it);
 * VSV_ENOMEM. */
int vsv_expr_compile(const char *text, const char *const *names, int nnames, vsv_expr **out, char *msg, size_t cap,
                     int *pos);
/* 1 if the expression reads input i. */
int vsv_expr_uses(const vsv_expr *e, int input);
/* out[c] = the expression at cell c, c < n, in double precision, from
 * inputs[i][c] (arrays of n floats for the inputs it uses; the others may
 * be NULL). A NaN input gives NaN (min and max too); a result that is not a
 * finite float (division by zero, log of 0, sqrt of a negative, overflow)
 * is NaN, the empty value of a .vsv. No allocation. */
void vsv_expr_eval(const vsv_expr *e, const float *const *inputs, size_t n, float *out);
void vsv_expr_free(vsv_expr *e);

/* ------------------------------------------------------- interpolation */

/* Linear interpolation in time between consecutive frames onto the regular
 * times t0 + k*dt (t0 = the first frame's time), every output step exactly
 * dt apart. An input frame at a grid time passes through unchanged; one
 * between grid times is not output itself (it only bounds the interpolation
 * of the grid times around it; vsv_interp_dropped counts them), so a dt
 * coarser than the input's and a multiple of it keeps every k-th frame.
 * The last output is the last grid time at or before the last input. An
 * interpolated value is
 *   (float)(a + (b - a) * w),  w = (t - ta) / (tb - ta)  (in double),
 * NaN where a or b is NaN. With VSV_TIME_WIND, a and b are instead the
 * earlier frame carried forward to t and the later one carried back to t
 * along the winds (semi-Lagrangian trajectories, see vsv_advect.c); with
 * VSV_TIME_ADVECT along the winds' displacements scaled per species and
 * band of levels by the factor (0 .. 1.25) that best carries the one output
 * onto the other (fitted per interval; 0 is linear interpolation). */
typedef struct vsv_interp vsv_interp;
typedef int (*vsv_frame_fn)(void *ctx, int64_t time, const float *const *fields);

/* Methods of time interpolation (vsv_interp_opts.method). */
enum { VSV_TIME_LINEAR = 0, VSV_TIME_ADVECT = 1, VSV_TIME_WIND = 2 };

/* Auxiliary wind fields: variables of these names travel with the species
 * (vsv_run_add_winds puts them last; the attribute VSV_WINDS_ATTR says where
 * they came from), m/s, u and v along the grid's x and y axes, w upward.
 * vsv_interp uses them and never emits them. */
#define VSV_WIND_U "wind.u"
#define VSV_WIND_V "wind.v"
#define VSV_WIND_W "wind.w"
#define VSV_WINDS_ATTR "winds"

/* How to interpolate: plain info. */
typedef struct vsv_interp_opts {
    int method;  /* VSV_TIME_LINEAR (default), VSV_TIME_ADVECT or VSV_TIME_WIND */
    int threads; /* advect: threads a frame uses, 0 = one per online CPU */
} vsv_interp_opts;

/* "linear" / "advect" / "wind" to a method; -1 if none. */
int vsv_interp_method(const char *name);

/* nfields fields of cells floats each; emit receives every output frame.
 * With nfields 0 only the times are emitted (the output times of a run,
 * found without reading it). */
int vsv_interp_create(int64_t dt, int nfields, size_t cells, vsv_frame_fn emit, void *ctx, vsv_interp **out);
/* Sets t0 to the first frame of the whole run, when the frames pushed are
 * a later part of it (call before the first push): the part then gets
 * exactly the frames the whole run gives at its times. */
void vsv_interp_set_origin(vsv_interp *ip, int64_t t0);
/* Emits only the steps at first <= t <= last; frames outside still bound
 * the interpolation (and are not counted as dropped). */
void vsv_interp_set_window(vsv_interp *ip, int64_t first, int64_t last);
/* Places an interpolation on the run's output steps: its origin the run's
 * first time before any selection, its window the selected steps. */
void vsv_run_place(const vsv_run *r, vsv_interp *ip);
/* Frames of the variables of meta (borrowed for the call); the wind
 * variables among them are consumed, emit receives the others in order
 * (vsv_interp_meta describes them). opts NULL = linear. Caller frees with
 * vsv_interp_free; on failure *out may hold a handle whose vsv_interp_error
 * says why (advect without wind.u and wind.v: VSV_ENOTFOUND). */
int vsv_interp_open(int64_t dt, const vsv_meta *meta, const vsv_interp_opts *opts, vsv_frame_fn emit, void *ctx,
                    vsv_interp **out);
const char *vsv_interp_error(const vsv_interp *ip);
/* The metadata of the emitted frames: meta without the wind variables and
 * their attribute; advect records itself in the attribute
 * "time interpolation". dst must be initialised. */
int vsv_interp_meta(const vsv_interp *ip, const vsv_meta *meta, vsv_meta *dst);
/* Feeds the next input frame (times strictly increase); returns emit's
 * first non-zero result, or 0. */
int vsv_interp_push(vsv_interp *ip, int64_t time, const float *const *fields);
/* advect: the scales fitted for the last interval, per species v (of those
 * emitted) and band b of levels (bottom up) at [v * nband + b]; NULL for
 * the other methods. */
const float *vsv_interp_scales(const vsv_interp *ip, int *nband);
/* Input frames so far that fell between grid times (not output). */
int vsv_interp_dropped(const vsv_interp *ip);
void vsv_interp_free(vsv_interp *ip);

VSV_API_END

#ifdef __cplusplus
}
#endif

#endif
