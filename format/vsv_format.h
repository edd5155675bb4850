/* vsv_format.h — the public interface of the .vsv file format library:
 * metadata, the field stream the Unix tools pipe, the streaming writer and the
 * memory-mapped reader. The bytes are specified in format/SPEC.md. */
#ifndef VSV_FORMAT_H
#define VSV_FORMAT_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* The exported API: what the public headers declare between VSV_API_BEGIN
 * and VSV_API_END. Each shared library exports exactly the vsv_ names of its
 * public headers (a version script made from them; tests/cli_layout.sh
 * checks it); the macros keep those declarations visible in a build with
 * -fvisibility=hidden. */
#define VSV_API_BEGIN _Pragma("GCC visibility push(default)")
#define VSV_API_END _Pragma("GCC visibility pop")

#include "vsv_time.h"

#ifdef __cplusplus
extern "C" {
#endif

VSV_API_BEGIN

#define VSV_VERSION_STRING "0.1.0"
/* The newest format read and written: 3.x (coded heights) only in files that
 * store heights, 2.x otherwise; 1.x is read, and written on request. 3.1: a
 * vector species (the wind, vsv_vector.h). */
#define VSV_FORMAT_MAJOR 4
#define VSV_FORMAT_MINOR 0

/* Error codes: fallible calls return 0 or one of these. Values never change. */
enum {
    VSV_OK = 0,
    VSV_EIO = -1,           /* operating-system I/O error */
    VSV_ENOMEM = -2,        /* out of memory */
    VSV_ENOTVSV = -3,       /* not a .vsv file / not a field stream (wrong magic) */
    VSV_EVERSION = -4,      /* a major version this library does not read */
    VSV_ECORRUPT = -5,      /* checksum mismatch or inconsistent structure */
    VSV_ETRUNC = -6,        /* file or stream ends early */
    VSV_EINVAL = -7,        /* invalid argument or option */
    VSV_ERANGE = -8,        /* index (time step, species, brick) out of range */
    VSV_ECODEC = -9,        /* compressed payload does not decode */
    VSV_ENOTFOUND = -10,    /* named item does not exist */
    VSV_EUNSUPPORTED = -11, /* valid but not supported by this build */
    VSV_EAGAIN = -12        /* not ready yet (try again later) */
};

/* A short fixed text for an error code; borrowed, static. */
const char *vsv_strerror(int code);

/* ---------------------------------------------------------------- metadata */

/* Vertical axis kinds (SPEC.md "GRID"). */
enum {
    VSV_VERT_EVEN = 0,   /* even heights: z = origin[2] + k * spacing[2], metres ASL */
    VSV_VERT_NATIVE = 1, /* model levels; levels[k] = mean height of level k (m ASL) */
    VSV_VERT_INDEX = 2,  /* layer index only: the vertical axis is not a height */
    VSV_VERT_COORD = 3   /* levels[k] in vert_units (e.g. hPa for pressure levels) */
};

/* Map projections (SPEC.md "PROJ"). Projected x/y are metres; for LATLON they
 * are degrees of longitude / latitude. */
enum {
    VSV_PROJ_NONE = 0,
    VSV_PROJ_LATLON = 1,
    VSV_PROJ_LCC = 2,      /* Lambert conformal conic, true latitudes lat1, lat2 */
    VSV_PROJ_PSTEREO = 3,  /* polar stereographic, true at lat1, pole by sign of lat0 */
    VSV_PROJ_MERCATOR = 4, /* Mercator, true at lat1 */
    VSV_PROJ_TMERC = 5,    /* transverse Mercator, central meridian lon0, scale lat1 (k0) */
    VSV_PROJ_ALBERS = 6,   /* Albers equal-area conic, standard parallels lat1, lat2 */
    VSV_PROJ_COUNT = 7
};

enum { VSV_SCALE_LINEAR = 0, VSV_SCALE_LOG = 1 };

/* Projection parameters: plain info. x = y = 0 at (lat0, lon0); projected
 * coordinates are metres on a sphere of radius `radius` (0 = 6370000 m). */
typedef struct vsv_proj {
    int kind;
    double lat0, lon0, lat1, lat2, radius;
} vsv_proj;

/* One variable (species): plain info. Strings are NUL-terminated. */
typedef struct vsv_var {
    char name[64];
    char units[64];
    char description[128];
} vsv_var;

/* Quantisation of one species inside a .vsv (SPEC.md §6): plain info.
 * Code 0 is "nothing here": it decodes to `lo` (linear), to NaN (linear with
 * `missing`, when the data had no-data cells) or to 0 (log). */
typedef struct vsv_quant {
    int bits;                  /* 8 or 16 */
    int scale;                 /* VSV_SCALE_* */
    int missing;               /* linear only: code 0 means no data (decodes to NaN) */
    double lo, hi;             /* the range the codes span */
    double threshold;          /* values below it were stored as code 0 */
    double max_abs_error;      /* bound on |decoded - original| for finite inputs */
    double data_min, data_max; /* finite values seen by the writer */
} vsv_quant;

/* The height of every native level in every column from one time on
 * (SPEC.md "HGTS"): plain info a vsv_meta owns. */
enum { VSV_HEIGHTS_STORED = 0, VSV_HEIGHTS_MM5 = 1 };
typedef struct vsv_heights {
    int64_t time;  /* valid for steps at or after this time (the first record
                      also before it) */
    int form;      /* VSV_HEIGHTS_*: stored, or MM5's reference-state formula */
    double mm5[5]; /* MM5: P00 (Pa), TS0 (K), TLP (K), TISO (K, 0 none), PTOP (Pa) */
    double *sigma; /* MM5: nz half-sigma values, bottom level first */
    float *z;      /* nx*ny*nz heights, m above sea level, x fastest, then y,
                      then level (for MM5 derived from the terrain) */
} vsv_heights;

/* Where a moving grid (a WRF moving nest) lies from one time on (SPEC.md
 * "MOVE"): plain info a vsv_meta owns. Steps before the first use GRID's
 * origin and TERR. */
typedef struct vsv_move {
    int64_t time;     /* in force for steps at or after this time */
    double origin[2]; /* projected x, y of the centre of column (0, 0) */
    float *terrain;   /* nx*ny ground under the grid there (m ASL), or NULL
                         when the file has no terrain */
} vsv_move;

/* Everything about a data set except its values: plain info that owns its
 * arrays. Initialise with vsv_meta_init, release with vsv_meta_clear. */
typedef struct vsv_meta {
    int nx, ny, nz;
    double origin[3];  /* centre of cell (0,0,0): projected x, y; height z */
    double spacing[3]; /* cell size in x, y (projected units) and z (metres) */
    int vert_kind;     /* VSV_VERT_* */
    char vert_units[32];
    double *levels; /* nz values, or NULL for VSV_VERT_EVEN */
    vsv_proj proj;
    char model[64]; /* source model, e.g. "MM5 v3" */
    char run[256];  /* run description */
    int nattrs;
    char (*attr_keys)[64];
    char (*attr_values)[256];
    int nvars;
    vsv_var *vars;
    char **tf;            /* nvars default transfer functions (text) or NULL entries */
    float *terrain;       /* nx*ny terrain height (m ASL), x fastest, or NULL */
    float *landuse;       /* nx*ny land-use category, or NULL */
    int nheights;         /* VSV_VERT_NATIVE: per-column level heights, in time */
    vsv_heights *heights; /* order (0 = none: levels[] only) */
    int nmoves;           /* a grid that moves: its placements in time order */
    vsv_move *moves;      /* (0 = none: it stays at origin over terrain) */
} vsv_meta;

void vsv_meta_init(vsv_meta *m);
/* Frees the arrays the struct owns and re-initialises it. Accepts NULL. */
void vsv_meta_clear(vsv_meta *m);
/* Deep copy; dst must be initialised (it is cleared first). */
int vsv_meta_copy(vsv_meta *dst, const vsv_meta *src);
/* Append one variable; returns its index or a negative error. */
int vsv_meta_add_var(vsv_meta *m, const char *name, const char *units, const char *desc);
int vsv_meta_add_attr(vsv_meta *m, const char *key, const char *value);
/* Borrowed value of an attribute, or NULL. */
const char *vsv_meta_attr(const vsv_meta *m, const char *key);
/* The attribute saying what the heights count from: "ground" where they are
 * metres above the ground with no terrain under them (CAMx and CMAQ files
 * without one); absent, or "sea level", for the format's metres above sea
 * level. */
#define VSV_ATTR_DATUM "vertical_datum"
/* 1 when m's heights are above the ground (VSV_ATTR_DATUM), else 0. */
int vsv_meta_above_ground(const vsv_meta *m);
/* 1 when m's columns go round the globe (longitude and latitude whose nx
 * cells span 360 degrees: the last cell beside the first), else 0. */
int vsv_meta_periodic_x(const vsv_meta *m);
/* The attribute that says when the model wrote its outputs, where they
 * came every so often: "every 3600 s from 1995-10-24T00:00:00Z". A step
 * off that grid was interpolated (vsv-convert --time-res). */
#define VSV_ATTR_OUTPUTS "model_outputs"
/* The attribute that says the values were resampled from the model's own
 * levels onto even heights (vsv-convert --vertical even): what from, and
 * how. Statistics of such a file are the resampled values', not the model's. */
#define VSV_ATTR_RESAMPLED "resampled"
/* Its first time and interval: 1, or 0 when m has no such attribute. */
int vsv_meta_outputs(const vsv_meta *m, int64_t *first, int64_t *every);
/* CF's words for a species (format/vsv_cf_names.c; the netCDF export and
 * Python's to_xarray): the UDUNITS spelling of a model's unit ("ppmV" →
 * "ppm", "micrograms/m**3" → "ug m-3"), units itself when it needs none
 * (static or borrowed); and the CF standard name of species `name` of a
 * file whose model is `model` with `units`, or NULL when it has none (or
 * the unit does not fit it), *comment then NULL or what the variable's
 * comment must say of the match. */
const char *vsv_cf_units(const char *units);
const char *vsv_cf_standard_name(const char *model, const char *name, const char *units, const char **comment);
/* Allocate levels / terrain / landuse arrays (zeroed). */
int vsv_meta_alloc_levels(vsv_meta *m);
int vsv_meta_alloc_terrain(vsv_meta *m);
int vsv_meta_alloc_landuse(vsv_meta *m);
/* Adds per-column heights of the native levels valid from `time` on (times
 * strictly increase from record to record): z is nx*ny*nz heights (m above
 * sea level, copied), or NULL with mm5 (P00, TS0, TLP, TISO, PTOP) and sigma
 * (nz half-sigma values, bottom first) for MM5's formula over the terrain
 * (which must be set). 0, VSV_EINVAL (not increasing upward, not finite,
 * no terrain) or VSV_ENOMEM. */
int vsv_meta_add_heights(vsv_meta *m, int64_t time, const float *z, const double mm5[5], const double *sigma);
/* Adds a placement of a moving grid from `time` on (after every earlier
 * one): origin (projected x, y of column (0, 0)) and the nx*ny terrain
 * under it (copied; given exactly when m has a terrain). 0, VSV_EINVAL or
 * VSV_ENOMEM. */
int vsv_meta_add_move(vsv_meta *m, int64_t time, const double origin[2], const float *terrain);
/* The placement in force at `time` (borrowed from m), or NULL: GRID's. */
const vsv_move *vsv_meta_move_at(const vsv_meta *m, int64_t time);
/* m as it lies at `time`: origin and terrain of the placement in force, no
 * moves. A shallow copy whose arrays are m's (valid while m is; never
 * clear it): what a reader locates, draws and masks one step with. */
vsv_meta vsv_meta_placed(const vsv_meta *m, int64_t time);
/* m grown to cover every placement of a moving grid (origin the lowest, nx
 * and ny reaching the farthest; no terrain, land use, heights or moves):
 * what a view is framed on. m itself where it does not move. Shallow, as
 * vsv_meta_placed's. */
vsv_meta vsv_meta_span(const vsv_meta *m);
/* The heights (nx*ny*nz) in force at `time`, or NULL when the file has none. */
const float *vsv_meta_heights_at(const vsv_meta *m, int64_t time);
/* MM5's reference-state height (m above sea level) of pressure p (Pa) for
 * mm5 = P00, TS0, TLP, TISO. */
double vsv_mm5_ref_height(double p, const double mm5[4]);
/* The even vertical axis on which renderers and exporters place a file's
 * per-column native levels: nz levels centred at z0 + k*dz (m above sea
 * level). 0, or VSV_EINVAL when the file has no per-column heights. */
int vsv_heights_axis(const vsv_meta *m, int *nz, double *z0, double *dz);

/* The land-use categories (0..63) that are water, as a bit mask (bit c set:
 * category c is water), from the `landuse_water` attribute ("16", "0",
 * "17,21": the categories the model's land-use scheme calls water or lake);
 * 0 when the file has no land use or does not say. */
uint64_t vsv_meta_water(const vsv_meta *m);

/* Index of a variable by name, or VSV_ENOTFOUND. */
int vsv_meta_find_var(const vsv_meta *m, const char *name);
/* Checks dimensions and values for sanity; fills msg (cap bytes) on error. */
int vsv_meta_validate(const vsv_meta *m, char *msg, size_t cap);
/* The part of it for the projection: its parameters in their ranges and
 * every corner of the grid (its outer cells' centres) a latitude and
 * longitude; 0, or VSV_EINVAL saying which is not. */
int vsv_meta_check_proj(const vsv_meta *m, char *msg, size_t cap);

/* Projection names ("none", "latlon", "lcc", "pstereo", "mercator", "tmerc", "albers"). */
const char *vsv_proj_name(int kind);
/* Latitude/longitude (degrees) of projected point (x, y) of a grid's
 * projection (a thin shim over GeographicLib, on the sphere the models
 * assume); 0, or VSV_EINVAL / VSV_EUNSUPPORTED. */
int vsv_proj_inverse(const vsv_proj *p, double x, double y, double *lat, double *lon);
/* Projected point of (lat, lon). */
int vsv_proj_forward(const vsv_proj *p, double lat, double lon, double *x, double *y);

/* ----------------------------------------------------------------- times */

/* Times, calendars, durations and the time grammar: vsv_time.h (included above). */
/* The calendar of a file's metadata: VSV_CAL_STANDARD without the
 * attribute (or with one this does not name). */
int vsv_meta_calendar(const vsv_meta *m);

/* ---------------------------------------------------------- field stream */

/* The field stream (SPEC.md part 2): a header with the metadata, then frames
 * of dense float32 fields (all variables of one time), then an end marker. */
typedef struct vsv_stream_reader vsv_stream_reader;
typedef struct vsv_stream_writer vsv_stream_writer;

/* Reads the header from fp (borrowed, must stay open). `name` is used in
 * messages. Caller frees with vsv_stream_reader_free. */
int vsv_stream_reader_open(FILE *fp, const char *name, vsv_stream_reader **out);
/* Borrowed, valid until the reader is freed. */
const vsv_meta *vsv_stream_reader_meta(const vsv_stream_reader *r);
/* Reads the next frame into fields (nvars pointers to nx*ny*nz floats each,
 * caller buffers). 1 with a frame, 0 at the end marker, < 0 on error (bytes after the marker too). */
int vsv_stream_reader_next(vsv_stream_reader *r, int64_t *time, float *const *fields);
/* Message for the last error ("where" included); borrowed. */
const char *vsv_stream_reader_error(const vsv_stream_reader *r);
void vsv_stream_reader_free(vsv_stream_reader *r);

/* Writes the header to fp (borrowed). Caller frees with vsv_stream_writer_free. */
int vsv_stream_writer_open(FILE *fp, const vsv_meta *meta, vsv_stream_writer **out);
int vsv_stream_writer_frame(vsv_stream_writer *w, int64_t time, const float *const *fields);
/* Writes the end marker and flushes. */
int vsv_stream_writer_end(vsv_stream_writer *w);
void vsv_stream_writer_free(vsv_stream_writer *w);

/* ------------------------------------------------------------------ writer */

enum { VSV_CODEC_NONE = 0, VSV_CODEC_ZSTD = 1 };

/* Per-species packing choices: plain info. */
typedef struct vsv_pack_var {
    int bits;           /* 8 or 16 (default 16) */
    int scale;          /* VSV_SCALE_LINEAR (default) or VSV_SCALE_LOG */
    double threshold;   /* values below are empty; default 0 = none */
    double lo, hi;      /* fixed range when lo < hi; else from the data */
    double log_decades; /* log scale: range spans at most this many decades (0 = default) */
} vsv_pack_var;

typedef struct vsv_pack_opts {
    int brick;          /* brick edge in cells: 8, 16, 32 or 64 (default 32) */
    int keyframe;       /* keyframe interval K >= 1 (default 8) */
    int codec;          /* VSV_CODEC_* (default zstd) */
    int level;          /* zstd level (default 3) */
    int predict;        /* 2 (default): bricks may use the 3-D kinds, Rice-coded
                           too, where smaller (format 4); 1: format 2 or 3; 0: 1.x */
    int threads;        /* encoder threads; 0 = all cores */
    vsv_pack_var *vars; /* nvars entries or NULL for defaults; borrowed during create */
} vsv_pack_opts;

void vsv_pack_opts_init(vsv_pack_opts *o);
void vsv_pack_var_init(vsv_pack_var *v);

typedef struct vsv_writer vsv_writer;

/* Starts a .vsv at `path`. Nothing appears at `path` until vsv_writer_finish
 * succeeds: steps are spooled to a temporary file beside it. Caller frees
 * with vsv_writer_free (which removes temporaries if not finished). */
int vsv_writer_create(const char *path, const vsv_meta *meta, const vsv_pack_opts *opts, vsv_writer **out);
/* Adds one time step: fields[v] holds nx*ny*nz floats of variable v, x
 * fastest then y then z (borrowed for the call). Times strictly increase.
 * Non-finite values are stored as empty (code 0). */
int vsv_writer_add_step(vsv_writer *w, int64_t time, const float *const *fields);
/* Quantises, encodes, writes, fsyncs and renames into place. An optional
 * progress callback gets (done, total) steps. */
int vsv_writer_finish(vsv_writer *w, void (*progress)(void *ctx, int done, int total), void *ctx);
const char *vsv_writer_error(const vsv_writer *w);
void vsv_writer_free(vsv_writer *w);

/* --------------------------------------------------------- writing in parts */

/* The writer's work as pieces that need not run in one process (vsv-convert-mpi
 * runs them on many): the value statistics of every step, merged, fix the
 * quantisation (a pack plan); the chunk of step t depends only on the fields
 * of steps t and t-1 (only t's at a keyframe, t mod K = 0), so keyframe groups
 * encode independently; the header and the tail (table of contents and end
 * marker) depend only on the plan and the chunks' sizes and times. A file put
 * together from them, chunks in step order from vsv_pack_plan_first_chunk(),
 * is byte for byte the file vsv_writer writes from the same steps. */

/* Statistics of one species' values over the steps seen: plain info. */
typedef struct vsv_pack_stats {
    double min, max;    /* finite extremes (+inf / -inf before any) */
    double minpos;      /* smallest positive finite value (+inf before any) */
    uint64_t nonfinite; /* count of non-finite values */
} vsv_pack_stats;

/* nvars entries to "nothing seen". */
void vsv_pack_stats_init(vsv_pack_stats *st, int nvars);
/* Adds one step: fields[v] holds `cells` floats of variable v. */
void vsv_pack_stats_add(vsv_pack_stats *st, int nvars, size_t cells, const float *const *fields);
/* into[v] becomes the statistics of both sets of steps. */
void vsv_pack_stats_merge(vsv_pack_stats *into, const vsv_pack_stats *from, int nvars);
/* A writer told in advance what the steps to come hold: stats (nvars
 * entries) over exactly the steps that will be added, from a first pass
 * over them. Call before the first step. The writer then plans at once and
 * encodes the steps as they arrive, a few at a time (as many as its
 * threads, with the one before), with no spool: the file is byte for byte
 * the one it writes without this call. vsv_writer_finish fails (VSV_EINVAL)
 * when the steps added did not have those statistics. */
int vsv_writer_expect(vsv_writer *w, const vsv_pack_stats *stats);

typedef struct vsv_pack_plan vsv_pack_plan;

/* Plans a file of meta's variables from the statistics of all its steps
 * (stats: nvars entries), with the writer's options (opts may be NULL; its
 * vars are borrowed during the call). Caller frees with vsv_pack_plan_free;
 * on failure *out may hold a handle whose error says why (free it too). */
int vsv_pack_plan_create(const vsv_meta *meta, const vsv_pack_opts *opts, const vsv_pack_stats *stats,
                         vsv_pack_plan **out);
const char *vsv_pack_plan_error(const vsv_pack_plan *p);
void vsv_pack_plan_free(vsv_pack_plan *p);
/* Borrowed quantisation of species s. */
const vsv_quant *vsv_pack_plan_quant(const vsv_pack_plan *p, int s);
/* Offset of the first chunk: the header (128 bytes), the metadata, padding. */
uint64_t vsv_pack_plan_first_chunk(const vsv_pack_plan *p);
/* The bytes at [128, first_chunk): metadata records and zero padding;
 * borrowed, valid until the plan is freed. */
const unsigned char *vsv_pack_plan_meta_bytes(const vsv_pack_plan *p);
/* Bytes of the tail (table of contents + end marker) of nsteps steps. */
size_t vsv_pack_tail_bytes(int nsteps);
/* The header (caller buffer of 128 bytes, written at offset 0) and the tail
 * (caller buffer of vsv_pack_tail_bytes(nsteps), written at *tail_offset,
 * the end of the last chunk) of a file whose chunk t has sizes[t] bytes and
 * times[t] (strictly increasing). */
int vsv_pack_plan_finish(vsv_pack_plan *p, int nsteps, const int64_t *times, const uint64_t *sizes,
                         unsigned char *header, unsigned char *tail, uint64_t *tail_offset);

/* A chunk encoder: per-thread scratch over a shared plan (which must outlive
 * it). Caller frees with vsv_chunk_encoder_free. */
typedef struct vsv_chunk_encoder vsv_chunk_encoder;
int vsv_chunk_encoder_create(const vsv_pack_plan *p, vsv_chunk_encoder **out);
/* Encodes the chunk of step t at `time`: fields[v] and prev[v] hold the
 * cells of variable v at steps t and t-1 (prev is unused, and may be NULL,
 * at a keyframe). *bytes (borrowed, valid until the next call or free) and
 * *size (a multiple of 64) receive the chunk. */
int vsv_chunk_encode(vsv_chunk_encoder *e, int t, int64_t time, const float *const *fields, const float *const *prev,
                     const unsigned char **bytes, size_t *size);
const char *vsv_chunk_encoder_error(const vsv_chunk_encoder *e);
void vsv_chunk_encoder_free(vsv_chunk_encoder *e);

/* ------------------------------------------------------------------ reader */

typedef struct vsv_file vsv_file;

/* Brick kinds in a chunk's brick table (SPEC.md "Brick entry"); ABS3 and
 * DELTA3 from format 2, ABS3R and DELTA3R (the same residuals Rice-coded)
 * from format 4. Absolute kinds need no earlier step; delta kinds change it. */
enum { VSV_BRICK_EMPTY, VSV_BRICK_UNCHANGED, VSV_BRICK_ABS, VSV_BRICK_DELTA, VSV_BRICK_ABS3, VSV_BRICK_DELTA3 };
enum { VSV_BRICK_ABS3R = 6, VSV_BRICK_DELTA3R = 7 };
static inline int vsv_brick_absolute(int kind) { return kind >= 0 && !(kind & 1); }
static inline int vsv_brick_delta(int kind) { return kind > VSV_BRICK_UNCHANGED && (kind & 1); }

/* Facts about an open file: plain info filled by vsv_file_info. */
typedef struct vsv_file_info {
    int major, minor;
    int nsteps, nspecies;
    int brick;     /* brick edge */
    int bricks[3]; /* bricks along x, y, z */
    int nbricks;   /* bricks per (step, species) */
    int keyframe;
    int codec;
    int octree_levels; /* level 0 = bricks, last = one root node */
    uint64_t file_bytes;
} vsv_file_info;

/* Brick counts over the whole file: plain info filled by vsv_file_count. */
typedef struct vsv_file_counts {
    uint64_t stored_bricks;   /* bricks with a payload (ABS or DELTA) */
    uint64_t rice_bricks;     /* of them, Rice-coded (ABS3R, DELTA3R: format 4) */
    uint64_t nonempty_bricks; /* bricks whose state is not all code 0 */
    uint64_t payload_bytes;
    int damaged_chunks; /* chunks whose index failed its checks (not
                         * counted above); vsv_file_error names the first */
} vsv_file_counts;

/* 1 when the n bytes at head begin as a .vsv file does (its magic), else
 * 0: for tools that read other formats to say what a .vsv given them is. */
int vsv_head_is_vsv(const void *head, size_t n);
/* Maps `path` and validates header, metadata, table of contents and end
 * marker (cost independent of the amount of brick data). Caller frees with
 * vsv_file_free. On failure *out may hold a handle whose error says why
 * (free it too), or NULL. */
int vsv_file_open(const char *path, vsv_file **out);
/* The same over a caller buffer that must outlive the handle (fuzzing, tests). */
int vsv_file_open_mem(const void *data, size_t size, const char *name, vsv_file **out);
/* A byte source: a .vsv whose bytes are somewhere other than a local file
 * (a web server: vsv_http.h). `base` is `size` bytes of address space that
 * hold the file's bytes at their offsets wherever `need` has made them
 * resident; the reader calls `need` before it reads a range (the header, the
 * metadata, the table of contents and end marker, a chunk index, a payload),
 * from any thread. `need` makes [off, off + n) resident and may fetch up to
 * `ahead` bytes after it too (a hint: the rest of the same structure); it
 * returns 0 or a VSV_E* code with "name: what, where" in msg. `refetch`
 * (may be NULL) replaces a resident range whose checksum failed by a fresh
 * copy (a damaged cache), returning 0 if it fetched one. `close` releases the
 * source. `interrupt` (may be NULL; any thread) ends the transfers under way
 * soon (a second or so) and fails every later `need` at once: a program
 * closing while a server stalls. A transfer that fails (a dropped
 * connection, a stalled server, an interruption) is VSV_EIO; damaged bytes
 * are the reader's to find. A local file needs none of this. */
typedef struct vsv_byte_source {
    const unsigned char *base;
    uint64_t size;
    int (*need)(struct vsv_byte_source *src, uint64_t off, uint64_t n, uint64_t ahead, char *msg, size_t cap);
    int (*refetch)(struct vsv_byte_source *src, uint64_t off, uint64_t n, char *msg, size_t cap);
    void (*close)(struct vsv_byte_source *src);
    void (*interrupt)(struct vsv_byte_source *src);
} vsv_byte_source;
/* Opens the .vsv that src holds, as vsv_file_open does a mapped file; the
 * handle owns src (closed by vsv_file_free, and on failure). */
int vsv_file_open_source(vsv_byte_source *src, const char *name, vsv_file **out);
/* 1 when step's chunk index is there without a transfer (a local file, or
 * fetched and verified): reading it (vsv_file_brick_kind, vsv_file_octree)
 * calls no `need`. No I/O: the pager asks it under its lock. */
int vsv_file_chunk_resident(const vsv_file *f, int step);
/* Fetches and verifies step's chunk index: 0, or VSV_EIO (the transfer
 * failed), VSV_ECORRUPT / VSV_ETRUNC (damaged) with "name: what, where" in
 * msg (caller buffer of cap bytes). May wait on a server. */
int vsv_file_chunk_fetch(vsv_file *f, int step, char *msg, size_t cap);
/* Ends f's transfers (its source's `interrupt`; nothing for a local file)
 * before freeing it while a thread waits on a stalled server. */
void vsv_file_interrupt(vsv_file *f);
void vsv_file_free(vsv_file *f);
const char *vsv_file_error(const vsv_file *f);
/* Borrowed, valid until vsv_file_free. */
const vsv_meta *vsv_file_meta(const vsv_file *f);
/* The header's facts (no chunk is read: cost independent of the steps). */
void vsv_file_info_get(const vsv_file *f, vsv_file_info *info);
/* Reads every chunk index (once; verified on the way) and counts bricks:
 * a summary for vsv-info, whose cost grows with the number of steps. */
void vsv_file_count(vsv_file *f, vsv_file_counts *c);
/* The time of step (0 for a step outside 0..nsteps-1). */
int64_t vsv_file_time(const vsv_file *f, int step);
/* Borrowed quantisation of species s (NULL for one outside 0..nvars-1). */
const vsv_quant *vsv_file_quant(const vsv_file *f, int s);
/* Step index with exactly this time, or VSV_ENOTFOUND. */
int vsv_file_find_time(const vsv_file *f, int64_t time);

/* The default transfer function text (SPEC.md §14) for a species, chosen by
 * its name (cloud, rain, ice, snow, ozone, NOx, PM, smoke; others viridis)
 * over its quantisation range; writes into buf (cap bytes). The writer
 * stores it for every species that has none. */
void vsv_tf_default(const char *name, const vsv_quant *q, char *buf, size_t cap);
/* Whether species s is drawn when the user names none (vsv-render, the
 * player): every species but water vapour (Q, QVAPOR, QV, H2O: a haze over
 * everything), unless vapour is all the file holds besides vectors, and but
 * the components of a vector (the wind: a speed is no cloud), ever. */
int vsv_meta_default_shown(const vsv_meta *m, int s);

/* Decoded value of a code under a quantisation. */
float vsv_quant_value(const vsv_quant *q, unsigned code);

/* Brick geometry: first cell and extent (clipped to the grid) of brick b. */
void vsv_file_brick_box(const vsv_file *f, int b, int org[3], int ext[3]);

/* Octree of (step, species): node n of level L has min/max codes
 * nodes[2n], nodes[2n+1]; levels are stored one after another, level 0 (one
 * node per brick, same order as bricks) first. Node (i,j,k) of level L covers
 * bricks [i*2^L, (i+1)*2^L) etc. dims receives the node counts per level
 * (caller array of 3*octree_levels ints, may be NULL). Returns a borrowed
 * pointer into the mapping (little-endian u16 pairs, read with
 * vsv_octree_node) or NULL if the chunk index is damaged (see error). */
const unsigned char *vsv_file_octree(vsv_file *f, int step, int s, int *dims);
void vsv_octree_node(const unsigned char *nodes, size_t n, unsigned *min, unsigned *max);
/* Index of the first node of level L within the octree array. */
size_t vsv_file_octree_level_start(const vsv_file *f, int level);

/* Kind of brick b at (step, species), or a negative error. */
int vsv_file_brick_kind(vsv_file *f, int step, int s, int b);

/* Verifies every checksum, padding byte and payload; decodes everything.
 * Returns 0 or an error whose message names chunk, species, brick, offset. */
int vsv_file_check(vsv_file *f, void (*progress)(void *ctx, int done, int total), void *ctx);

/* A decoder: per-thread scratch for decoding. One per thread; the file
 * handle may be shared. Caller frees with vsv_decoder_free. */
typedef struct vsv_decoder vsv_decoder;
int vsv_decoder_create(vsv_file *f, vsv_decoder **out);
void vsv_decoder_free(vsv_decoder *d);
const char *vsv_decoder_error(const vsv_decoder *d);

/* Codes of brick b at (step, s): brick^3 values, x fastest, cells outside
 * the grid are 0. Caller buffer. Walks back to the brick's last absolute
 * state (at most K-1 deltas). */
int vsv_decoder_brick_codes(vsv_decoder *d, int step, int s, int b, uint16_t *codes);
/* Advances codes of brick b from step-1 to step in place (pager use). */
int vsv_decoder_brick_advance(vsv_decoder *d, int step, int s, int b, uint16_t *codes);
/* Takes codes of brick b from step back to step-1 in place, undoing step's
 * delta (one payload; UNCHANGED leaves them): exact, as deltas wrap modulo
 * 2^bits (pager use, playing backward). VSV_EINVAL when step's entry is an
 * absolute state (EMPTY, ABS, ABS3: step-1 is not derivable from it). */
int vsv_decoder_brick_retreat(vsv_decoder *d, int step, int s, int b, uint16_t *codes);
/* Floats of brick b at (step, s): brick^3 values (caller buffer). */
int vsv_decoder_brick(vsv_decoder *d, int step, int s, int b, float *out);
/* The whole volume (nx*ny*nz floats, x fastest; caller buffer). Both give
 * NaN, no data, for every species in the cells below the ground (even
 * heights over a terrain: a centre below it; SPEC.md "No data"). */
int vsv_decoder_volume(vsv_decoder *d, int step, int s, float *out);
/* Dequantise n codes of species s into floats; or the brick^3 codes of
 * brick b, the cells outside the grid the empty value (code 0's) whatever
 * their codes. */
void vsv_file_dequantise(const vsv_file *f, int s, const uint16_t *codes, size_t n, float *out);
void vsv_file_dequantise_brick(const vsv_file *f, int s, int b, const uint16_t *codes, float *out);

/* ------------------------------------------------------- decoded volumes */

/* One species at one step, decoded brick by brick: what renderers consume.
 *
 * One owner rule for every vsv_volume, whoever hands it out:
 *  - owned: from vsv_volume_create (bricks in storage the volume owns) or
 *    vsv_pager_volume_new (bricks pinned in the pager's cache). Caller frees
 *    with vsv_volume_free, which releases it the way its maker needs (a
 *    pager volume unpins its bricks first; freeing it after its pager is
 *    allowed). Only its maker fills it: vsv_volume_load takes only volumes
 *    of vsv_volume_create, vsv_pager_get only volumes of that pager
 *    (VSV_EINVAL otherwise).
 *  - borrowed: vsv_resampler_run's output; vsv_volume_free leaves it alone.
 * A volume a caller builds itself (tests, bindings) has release_ NULL and
 * is the caller's to manage.
 *
 * Plain info over storage its maker manages. bricks[b] is NULL
 * for a brick whose cells all hold `empty_value` (an EMPTY brick); otherwise
 * brick^3 floats, x fastest, cells outside the grid hold empty_value. bmin and
 * bmax are the brick's value range (from the octree, exact). */
typedef struct vsv_volume {
    int nx, ny, nz, brick, bdim[3], nbricks;
    int shift;         /* log2(brick) */
    int step, species; /* what is loaded; -1 when nothing */
    uint64_t gen;      /* new on every load, unique in the process: what
                          a renderer keys the copies it derives on (a
                          volume freed and another allocated at the same
                          address may hold the same step and species) */
    float empty_value; /* value of code 0 (0, lo, or NaN for no data) */
    int64_t time;      /* time of `step` */
    float **bricks;
    float *bmin, *bmax;
    uint64_t *bkey; /* per brick, or NULL: a key of the brick's
                       values (equal non-zero keys, equal values, in
                       any volume of the process: vsv_file_brick_key),
                       so a renderer redoes only bricks that changed */
    /* private to the volume's maker: how vsv_volume_free gives it back
       (NULL: borrowed or caller-built; vsv_volume_free leaves it alone) */
    void (*release_)(struct vsv_volume *v);
} vsv_volume;

/* Allocates storage for one species of f (all at once: no allocation per
 * frame). Caller frees with vsv_volume_free. */
int vsv_volume_create(const vsv_file *f, vsv_volume **out);
/* Frees any owned volume (vsv_volume_create's or vsv_pager_volume_new's);
 * NULL and borrowed volumes are left alone. */
void vsv_volume_free(vsv_volume *v);
/* Decodes (step, s) into v (a volume of vsv_volume_create, else VSV_EINVAL)
 * through decoder d; the next step of the same species: a delta a brick. */
int vsv_volume_load(vsv_volume *v, vsv_decoder *d, int step, int s);
/* A new vsv_volume.gen (1, 2, ...: unique in the process), for fillers. */
uint64_t vsv_volume_new_gen(void);
/* The key of a brick of species s of f whose codes were last set at step
 * def (its last entry other than UNCHANGED; -1 for an EMPTY brick): every
 * brick with the same key holds the same values, for as long as f is open
 * (keys of different open files differ). Never 0. */
uint64_t vsv_file_brick_key(const vsv_file *f, int s, int def);
/* Native levels placed at their heights: a volume of a file with per-column
 * heights resampled, column by column and linearly in height, onto the even
 * axis of vsv_heights_axis (cells below the ground or above the top level
 * hold the empty value). One resampler per species; it owns its output. */
typedef struct vsv_resampler vsv_resampler;
/* m: the file's metadata (borrowed, must outlive the resampler). */
int vsv_resampler_create(const vsv_meta *m, vsv_resampler **out);
void vsv_resampler_free(vsv_resampler *r);
/* The metadata of the even grid: m with vert_kind even, the axis's nz,
 * origin and spacing, no levels and no heights (borrowed; its arrays are
 * m's: never clear it). */
const vsv_meta *vsv_resampler_meta(const vsv_resampler *r);
/* Resamples nat (a volume of m, with its time) unless it is the one done
 * last (same gen); *out is the even volume (borrowed, valid until the next
 * call). 0 or VSV_EINVAL/VSV_ENOMEM. */
int vsv_resampler_run(vsv_resampler *r, const vsv_volume *nat, const vsv_volume **out);

/* The value at cell (i, j, k) (inside the grid). */
static inline float vsv_volume_at(const vsv_volume *v, int i, int j, int k)
{
    const int s = v->shift, m = v->brick - 1;
    const float *b = v->bricks[(i >> s) + v->bdim[0] * ((j >> s) + v->bdim[1] * (k >> s))];
    return b ? b[(i & m) + ((j & m) << s) + ((k & m) << (2 * s))] : v->empty_value;
}

/* ---------------------------------------------------------------- queries */

/* Where cells are. Cell (i, j, k) is the cell's centre; fractional indices
 * name points between centres (the grid covers -0.5 .. n-0.5 along each axis). */

/* Projected (x, y) of (fractional) column (i, j). */
void vsv_meta_cell_xy(const vsv_meta *m, double i, double j, double *x, double *y);
/* Latitude/longitude (degrees) of (fractional) column (i, j); VSV_EUNSUPPORTED
 * when the grid has no projection. */
int vsv_meta_cell_latlon(const vsv_meta *m, double i, double j, double *lat, double *lon);
/* Height of the centre of cell (i, j, k): metres above sea level (even and
 * native levels; for native levels the level's mean height), the level
 * coordinate in vert_units (VSV_VERT_COORD) or the index k (VSV_VERT_INDEX). */
double vsv_meta_cell_height(const vsv_meta *m, int i, int j, int k);
/* The same at `time`: a file's per-column heights of native levels
 * (SPEC.md "HGTS", moving in time) where it has them, else as above. */
double vsv_meta_cell_height_at(const vsv_meta *m, int64_t time, int i, int j, int k);
/* The unit of vsv_meta_cell_height: "m", vert_units, or "" for an index. */
const char *vsv_meta_height_units(const vsv_meta *m);

/* A point of a grid: plain info filled by vsv_point_locate / vsv_point_cell. */
typedef struct vsv_point {
    double pos[3];           /* fractional cell coordinates, -0.5..n-0.5 */
    int cell[3];             /* the nearest cell */
    double lat, lon, height; /* the nearest cell's centre (height as
                                vsv_meta_cell_height; lat/lon NaN without
                                a projection) */
} vsv_point;

/* The point at (lat, lon) and `height` (units of vsv_meta_cell_height); a
 * NaN height means the lowest level above the ground (on even heights the
 * lowest whose centre is at or above the column's terrain; level 0 on
 * native model levels, which follow the terrain, and without terrain). VSV_ERANGE, with msg naming the grid's valid
 * range, when the point lies outside the grid; VSV_EUNSUPPORTED without a projection. */
int vsv_point_locate(const vsv_meta *m, double lat, double lon, double height, vsv_point *p, char *msg, size_t cap);
/* The same with the heights in force at `time` (vsv_meta_cell_height_at):
 * on native levels with per-column heights a height's level moves in time. */
int vsv_point_locate_at(const vsv_meta *m, int64_t time, double lat, double lon, double height, vsv_point *p, char *msg,
                        size_t cap);
/* The point at cell (i, j, k); k < 0 means the lowest level above the
 * ground. VSV_ERANGE (msg names the range) outside the grid. */
int vsv_point_cell(const vsv_meta *m, int i, int j, int k, vsv_point *p, char *msg, size_t cap);

/* Values at points: a brick cache over a decoder. One per thread. Caller
 * frees with vsv_query_free. */
typedef struct vsv_query vsv_query;
int vsv_query_create(vsv_file *f, vsv_query **out);
void vsv_query_free(vsv_query *q);
const char *vsv_query_error(const vsv_query *q);
/* The decoded value of species s at step and cell (i, j, k) (exactly what
 * vsv_decoder_volume gives for that cell). */
int vsv_query_cell(vsv_query *q, int step, int s, int i, int j, int k, float *v);
/* The value at fractional cell coordinates pos: VSV_INTERP_NEAREST takes the
 * nearest cell; VSV_INTERP_LINEAR blends the eight around pos trilinearly
 * (clamped to the edge cells, but x round a global longitude-latitude grid;
 * cells without data, NaN, left out and the others' weights scaled to sum
 * to 1; NaN when the nearest cell is). */
enum { VSV_INTERP_NEAREST = 0, VSV_INTERP_LINEAR = 1 };
int vsv_query_sample(vsv_query *q, int step, int s, const double pos[3], int interp, float *v);

/* ---------------------------------------------------------------- helpers */

/* CRC-32C (Castagnoli) of buf, continuing from crc (start with 0). */
uint32_t vsv_crc32c(uint32_t crc, const void *buf, size_t len);

/* Number of online CPUs (>= 1). */
int vsv_ncpus(void);

VSV_API_END

#ifdef __cplusplus
}
#endif
/* Vector species and the projection's local geometry. */
#include "vsv_vector.h"
/* Outputs written all or nothing. */
#include "vsv_output.h"
#endif
