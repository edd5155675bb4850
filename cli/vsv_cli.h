/* vsv_cli.h — what the command-line tools share: the progress bar,
 * option-value parsers, the pack options and the CLI error conventions of
 * DESIGN.md §2 (usage errors exit 2, data errors exit 1 as "tool: file:
 * what, where"), and the JSON builder (vsv_json.h). A static library of the
 * programs (cli/): no library links it; these functions print and exit. */
#ifndef VSV_CLI_H
#define VSV_CLI_H

#include "vsv_format.h"
#include "vsv_http.h"
#include "vsv_json.h"

#include <stdio.h>

/* ---------------------------------------------------------- the tools */

/* Set once by main: the tool name used in messages. */
void vsv_cli_init(const char *tool);
/* on: SIGINT/SIGTERM/SIGHUP wait (a sequence's files are being renamed
 * into place: all of them appear, or none); off: one that came is acted on
 * now (the finished outputs stay, the tool dies of it). */
void vsv_cli_hold_signals(int on);
const char *vsv_cli_tool(void);
/* "tool: message" on stderr, then exit(code). */
void vsv_cli_die(int code, const char *fmt, ...) __attribute__((format(printf, 2, 3), noreturn));
/* Standard output flushed: when any of what went to it was not written
 * (a full disk, a closed pipe), "tool: standard output: why" and exit(1). */
void vsv_cli_stdout_done(void);
/* "tool: message\nTry 'tool --help'." and exit(2). */
void vsv_cli_usage_error(const char *fmt, ...) __attribute__((format(printf, 1, 2), noreturn));
/* After getopt_long has said what was wrong (an unknown option, a missing
 * argument): "Try 'tool --help'." and exit(2). */
void vsv_cli_getopt_failed(void) __attribute__((noreturn));
/* Refuses (exit 2, before anything is written) an output that is one of the
 * inputs: the same path, a hard link or a symlink to it (same device and
 * inode); NULL inputs are skipped. A missing output is never an input. Also
 * refuses an output that exists and is not a regular file (a directory,
 * /dev/null): writing it would replace it. An output name that is another
 * user's in a sticky folder (/tmp; a symlink's own owner, dangling or
 * not), which the final rename could not replace, exits 1. */
void vsv_cli_refuse_input(const char *out, const char *const *inputs, int n);
/* Refuses (exit 2) an output name whose extension is another kind's than
 * the option writes (x.nc for a .vsv, x.vsv for netCDF: a file others
 * would take for what it is not); exts: the extensions it writes, space
 * separated (".nc .nc4"); writes: what, for the message ("netCDF-4
 * (.nc)"). A name with no extension known here is the user's choice. */
void vsv_cli_output_kind(const char *opt, const char *name, const char *exts, const char *writes);
/* Opens an input the tool reads as text or a stream, checked: a regular
 * file, and with pipes != 0 also a FIFO (a field stream's writer on the other
 * end); a directory, device or socket exits 1 with "tool: path: what". */
FILE *vsv_cli_open_input(const char *path, const char *mode, int pipes);
/* Frees the writer (removing its temporaries), then exits 1 with
 * "tool: OUT: the writer's message". */
void vsv_cli_writer_die(vsv_writer *w, const char *out) __attribute__((noreturn));
/* Prints "tool (Vesuvius X) format A.B" and exits 0. */
void vsv_cli_version(void) __attribute__((noreturn));

/* The tools that read a .vsv read http(s):// URLs too (vsv_http.h): they
 * open with vsv_file_open_any(path, &vsv_cli_http, &f), and their
 * --cache-dir option (id VSV_CLI_CACHE_DIR) goes through vsv_cli_cache_dir. */
extern vsv_http_opts vsv_cli_http;
/* --cache-dir DIR: makes DIR (and its parents) unless it is "off", and
 * exits 1 naming it when it is not a directory this process can write
 * (the cache would silently keep nothing); sets vsv_cli_http.cache_dir. */
void vsv_cli_cache_dir(const char *dir);
enum { VSV_CLI_CACHE_DIR = 1900 };
#define VSV_CLI_CACHE_DIR_HELP                                                                                         \
    "      --cache-dir DIR     where parts of files read from http(s):// URLs are kept\n"                              \
    "                          (default $VSV_CACHE_DIR, else $XDG_CACHE_HOME/vesuvius, else\n"                         \
    "                          ~/.cache/vesuvius; \"off\": none)\n"

/* Progress on stderr: a bar when stderr is a terminal, nothing otherwise.
 * ctx is a const char* label. Matches the writer's progress callback. */
void vsv_cli_progress(void *label, int done, int total);
int vsv_cli_quiet(void);
void vsv_cli_set_quiet(int q);
/* Each line of text (a library's notes, '\n' separated; "" for none) on
 * stderr as "tool: note: LINE". */
void vsv_cli_notes(const char *text);

/* An output name that numbers frames: "%d" or "%0Nd" (a width of 1..9)
 * once, and "%%" for a percent sign; no other '%' (the name is never a
 * printf format: "%s" or "%n" in it is refused). 1 when pattern holds a
 * number, 0 when it holds none, -1 when it is none of these. */
int vsv_cli_pattern(const char *pattern);
/* Frame n's name from such a pattern (or one without a number: itself, its
 * "%%" as "%") into out; 0, or -1 when it does not fit in cap or is no
 * such pattern. */
int vsv_cli_pattern_name(const char *pattern, long n, char *out, size_t cap);
/* --size WxH (arg) into *w, *h, each within [min, max] of its axis;
 * exits 2 ("--size ARG: expected WxH, MINWxMINH to MAXWxMAXH") otherwise. */
void vsv_cli_size(const char *arg, const int min[2], const int max[2], int *w, int *h);
/* Parses an integer in [lo, hi]; 0 or -1. */
int vsv_cli_int(const char *s, long lo, long hi, long *out);
/* Parses a double; 0 or -1. */
int vsv_cli_double(const char *s, double *out);
/* The value of option opt as a duration (vsv_duration_parse) into *out;
 * exits 2 saying why it is not one (zero, negative, no unit ...). */
void vsv_cli_duration(const char *opt, const char *s, int64_t *out);

/* Packing options as the tools take them (--brick, --keyframe, --bits,
 * --scale, --threshold, --range, --codec, --threads), shared by vsv-pack and
 * vsv-convert. Per-species options accept "VALUE" (every species) or
 * "NAME=VALUE,NAME=VALUE" lists. */
typedef struct vsv_cli_pack {
    vsv_pack_opts opts;
    const char *bits, *scale, *threshold, *range, *decades;
} vsv_cli_pack;

/* Long options of the pack family, for getopt_long tables (ids >= 1000). */
extern const char vsv_cli_pack_help[];
void vsv_cli_pack_init(vsv_cli_pack *p);
/* Handles option `id` (see VSV_CLI_PACK_*), exits 2 on a bad value; returns 1
 * if the id was a pack option. */
int vsv_cli_pack_option(vsv_cli_pack *p, int id, const char *arg);
/* Builds opts.vars for the variables of meta (caller frees opts.vars with
 * free()); exits 2 naming an unknown species. */
void vsv_cli_pack_resolve(vsv_cli_pack *p, const vsv_meta *meta);
/* Unless quiet, notes on standard error about species v as written (q: its
 * quantisation, data_min/data_max the values seen): no finite value at all
 * (every cell no data: an expression that fits no value, say), or values
 * beyond its --range (stored as the top, and, linear, as the bottom). */
void vsv_cli_pack_note(const vsv_cli_pack *p, const char *name, int v, const vsv_quant *q);
/* The same for every species of the file just written at path. */
void vsv_cli_pack_note_file(const vsv_cli_pack *p, const char *path);

enum {
    VSV_CLI_PACK_BRICK = 1000,
    VSV_CLI_PACK_KEYFRAME,
    VSV_CLI_PACK_BITS,
    VSV_CLI_PACK_SCALE,
    VSV_CLI_PACK_THRESHOLD,
    VSV_CLI_PACK_RANGE,
    VSV_CLI_PACK_DECADES,
    VSV_CLI_PACK_CODEC,
    VSV_CLI_PACK_FORMAT,
    VSV_CLI_PACK_THREADS
};
#define VSV_CLI_PACK_LONGOPTS                                                                                          \
    {"brick", required_argument, 0, VSV_CLI_PACK_BRICK}, {"keyframe", required_argument, 0, VSV_CLI_PACK_KEYFRAME},    \
        {"bits", required_argument, 0, VSV_CLI_PACK_BITS}, {"scale", required_argument, 0, VSV_CLI_PACK_SCALE},        \
        {"threshold", required_argument, 0, VSV_CLI_PACK_THRESHOLD},                                                   \
        {"range", required_argument, 0, VSV_CLI_PACK_RANGE},                                                           \
        {"log-decades", required_argument, 0, VSV_CLI_PACK_DECADES},                                                   \
        {"codec", required_argument, 0, VSV_CLI_PACK_CODEC}, {"format", required_argument, 0, VSV_CLI_PACK_FORMAT},    \
    {                                                                                                                  \
        "threads", required_argument, 0, VSV_CLI_PACK_THREADS                                                          \
    }

/* The species --species LIST names (comma-separated; NULL: every species)
 * as indices into sel (caller array of m->nvars ints); returns how many.
 * Exits 2 naming a species the file (path) lacks or one named twice. */
int vsv_cli_species(const vsv_meta *m, const char *list, const char *path, int *sel);

/* Resolves SPEC of option opt (e.g. "--times") by the one time grammar
 * (vsv_timesel_parse) against n times of path: exits 2 on a malformed SPEC,
 * 1 on one out of range ("tool: path: opt SPEC: why (the valid range)");
 * says on stderr which step a time between steps picked. */
void vsv_cli_timesel(const char *path, const char *opt, const char *spec, const int64_t *times, int n, int flags,
                     int *a, int *b);
/* The steps --time T or --times A:B select in f (opened from path); with
 * neither, every step when all, else the last. */
void vsv_cli_steps(const vsv_file *f, const char *path, const char *time, const char *times, int all, int *a, int *b);

#endif
