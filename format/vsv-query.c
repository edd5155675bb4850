/* vsv-query — numbers out of a .vsv: the values of species at a point
 * (latitude/longitude[/height] or a cell) or down a column, at one time, a
 * range of times or all, as an aligned table, CSV or JSON. The locating and
 * sampling live in the library (vsv_point_*, vsv_query_*). */
#include "vsv_cli.h"
#include "vsv_common.h"
#include "vsv_traj.h"

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* clang-format off */ /* (the help text as it prints, a line a line) */
static const char usage[] =
    "Usage: vsv-query FILE.vsv|URL (--at LAT,LON[,HEIGHT] | --cell I,J[,K] | --profile LAT,LON)\n"
    "                 [--species LIST] [--time T | --times A:B] [--interp] [--csv | --json]\n"
    "       vsv-query FILE.vsv|URL --trajectory LAT,LON,HEIGHT ... [--from T]\n"
    "                 [--to T | --for DURATION] [--back] [--streamline] [--every DURATION]\n"
    "                 [--csv | --json]\n"
    "Print the decoded values of species at a point of the grid: one row per time\n"
    "(every step unless --time/--times), or one row per level and time with\n"
    "--profile. Each row names the cell (i, j, k), its centre's latitude,\n"
    "longitude and height, and each species' value with its units.\n"
    "Reads .vsv files (vsv(5)); writes a text table, CSV (--csv) or JSON (--json).\n"
    "\n"
    "      --at LAT,LON[,H]    a point: degrees north, degrees east, and a height in\n"
    "                          metres above sea level (the grid's level unit when\n"
    "                          its levels are not heights); without H the lowest\n"
    "                          level above the ground\n"
    "      --cell I,J[,K]      a cell by index (0-based, x east, y north, z up);\n"
    "                          without K the lowest level above the ground\n"
    "      --profile LAT,LON   every level of the column at the point\n"
    "  -s, --species LIST      NAME,... (default: every species)\n"
    "  -t, --time T            one step: an index or an ISO time (the nearest step)\n"
    "      --times A:B         steps A..B (indices or ISO times; either end may be empty)\n"
    "      --interp            trilinear between the eight cells around the point\n"
    "                          (default: the nearest cell's value, exactly as decoded)\n"
    "      --trajectory LAT,LON,HEIGHT  the path of the air there at --from through\n"
    "                          the stored wind (RK4; repeat for several paths): a\n"
    "                          row a point, time, lat, lon, height, projected x, y\n"
    "                          and the wind east, north, up (m/s)\n"
    "      --from T            its start: a step index or an ISO time, between steps\n"
    "                          too (default: the first step; with --back the last)\n"
    "      --to T              its end (earlier than --from: backward in time)\n"
    "      --for DURATION      its length (\"6h\", \"90m\"; default: to the file's end)\n"
    "      --back              backward in time from --from (where the air came from)\n"
    "      --streamline        a streamline: the path through the wind of --from held\n"
    "                          still (times then count the travel at that wind)\n"
    "      --every DURATION    a point every DURATION of model time (default: every\n"
    "                          step of the scheme) and at the end\n"
    "      --csv               comma-separated values, a header row first\n"
    "      --json              one JSON document\n"
    VSV_CLI_CACHE_DIR_HELP
    "  -h, --help              this help\n"
    "  -V, --version           print versions\n"
    "Values are the file's decoded values (within each species' stated quantisation\n"
    "bound of the model's); no data is NaN (null in JSON). Times are ISO 8601 UTC.\n"
    "A path ends early where it leaves the grid (its side, the ground, the top) or\n"
    "the file's times end (a note on stderr says which).\n";
/* clang-format on */

enum { FMT_TABLE, FMT_CSV, FMT_JSON };

/* "A,B[,C]" into up to 3 doubles; returns how many, or -1. */
static int parse_list(const char *s, double *v)
{
    int n = 0;
    const char *p = s;
    while (n < 3) {
        char *end;
        v[n] = strtod(p, &end);
        if (end == p || !isfinite(v[n]))
            return -1;
        n++;
        if (*end == 0)
            return n;
        if (*end != ',')
            return -1;
        p = end + 1;
    }
    return -1;
}

static void print_value(FILE *fp, float v, int fmt)
{
    if (isnan(v))
        fputs(fmt == FMT_CSV ? "NaN" : "nan", fp);
    else
        fprintf(fp, fmt == FMT_TABLE ? "%.6g" : "%.9g", v);
}

/* The command line, parsed and checked (main). */
#define MAX_TRAJ 64

typedef struct query_args {
    const char *at, *cellarg, *profile, *species, *time, *times, *path;
    const char *traj[MAX_TRAJ], *from, *to, *dur, *every; /* --trajectory and its times */
    int ntraj, back, steady;
    int interp, fmt, nargs;
    double arg[3]; /* --at, --cell or --profile's numbers, nargs of them */
} query_args;

/* One query: the file, its steps, the species (sel, n of them), the point and the JSON document being built (main). */
typedef struct query_run {
    vsv_file *f;
    const vsv_meta *m;
    int a, b, n, k0, k1;
    int *sel, *width; /* the species' variables, and their table columns' widths */
    vsv_point pt;
    vsv_query *q;
    const char *hu;
    char hname[48];
    vsv_json *root, *rows;
} query_run;

/* Reads the options into qa (set to the defaults by main); 1 after --help. */
static int parse_args(int argc, char **argv, query_args *qa)
{
    /* clang-format off */ /* (a table, laid out by hand) */
    enum { O_AT = 1000, O_CELL, O_PROFILE, O_TIMES, O_INTERP, O_CSV, O_JSON, O_TRAJ, O_FROM, O_TO, O_FOR, O_EVERY, O_BACK, O_STEADY };
    static const struct option longopts[] = {
        {"at", required_argument, 0, O_AT},       {"cell", required_argument, 0, O_CELL},
        {"profile", required_argument, 0, O_PROFILE}, {"species", required_argument, 0, 's'},
        {"time", required_argument, 0, 't'},      {"times", required_argument, 0, O_TIMES},
        {"interp", no_argument, 0, O_INTERP},     {"csv", no_argument, 0, O_CSV},
        {"json", no_argument, 0, O_JSON},         {"help", no_argument, 0, 'h'}, {"cache-dir", required_argument, 0, VSV_CLI_CACHE_DIR},
        {"trajectory", required_argument, 0, O_TRAJ}, {"from", required_argument, 0, O_FROM},
        {"to", required_argument, 0, O_TO},       {"for", required_argument, 0, O_FOR},
        {"every", required_argument, 0, O_EVERY}, {"back", no_argument, 0, O_BACK},
        {"streamline", no_argument, 0, O_STEADY}, {"version", no_argument, 0, 'V'}, {0, 0, 0, 0}};
    /* clang-format on */
    int c;
    argv[0] = (char *)vsv_cli_tool(); /* getopt's messages name the tool as ours do */
    while ((c = getopt_long(argc, argv, "s:t:hV", longopts, NULL)) != -1) {
        switch (c) {
        case O_AT: qa->at = optarg; break;
        case O_CELL: qa->cellarg = optarg; break;
        case O_PROFILE: qa->profile = optarg; break;
        case 's': qa->species = optarg; break;
        case 't': qa->time = optarg; break;
        case O_TIMES: qa->times = optarg; break;
        case O_INTERP: qa->interp = VSV_INTERP_LINEAR; break;
        case O_CSV:
        case O_JSON:
            if (qa->fmt != FMT_TABLE && qa->fmt != (c == O_CSV ? FMT_CSV : FMT_JSON))
                vsv_cli_usage_error("--csv and --json: one output format at a time");
            qa->fmt = c == O_CSV ? FMT_CSV : FMT_JSON;
            break;
        case O_TRAJ:
            if (qa->ntraj == MAX_TRAJ)
                vsv_cli_usage_error("at most %d --trajectory options", MAX_TRAJ);
            qa->traj[qa->ntraj++] = optarg;
            break;
        case O_FROM: qa->from = optarg; break;
        case O_TO: qa->to = optarg; break;
        case O_FOR: qa->dur = optarg; break;
        case O_EVERY: qa->every = optarg; break;
        case O_BACK: qa->back = 1; break;
        case O_STEADY: qa->steady = 1; break;
        case VSV_CLI_CACHE_DIR: vsv_cli_cache_dir(optarg); break;
        case 'h': fputs(usage, stdout); return 1;
        case 'V': vsv_cli_version();
        default: vsv_cli_getopt_failed();
        }
    }
    return 0;
}

/* ------------------------------------------------------------ trajectories */

/* --trajectory's options, checked (check_args): the seeds' numbers are
 * parsed again where they are used. */
static void check_traj_args(int argc, char **argv, query_args *qa)
{
    if (qa->at || qa->cellarg || qa->profile)
        vsv_cli_usage_error("--trajectory excludes --at, --cell and --profile");
    if (qa->species || qa->time || qa->times || qa->interp)
        vsv_cli_usage_error("--trajectory prints the wind: no --species, --time, --times or --interp");
    if (qa->to && qa->dur)
        vsv_cli_usage_error("--to and --for exclude each other");
    if (qa->to && qa->back)
        vsv_cli_usage_error("--back goes with --for (--to earlier than --from goes backward itself)");
    for (int i = 0; i < qa->ntraj; i++) {
        double v[3];
        if (parse_list(qa->traj[i], v) != 3)
            vsv_cli_usage_error("--trajectory %s: expected LAT,LON,HEIGHT", qa->traj[i]);
        if (fabs(v[0]) > 90 || fabs(v[1]) > 360)
            vsv_cli_usage_error("--trajectory %s: latitude must be within -90..90 and longitude within -360..360",
                                qa->traj[i]);
    }
    if (optind != argc - 1)
        vsv_cli_usage_error(optind < argc ? "one .vsv file" : "no input file");
    qa->path = argv[optind];
}

/* The time of --from or --to's SPEC in f: a step index that step's time, an
 * ISO time itself (between steps too); exits 2 on a malformed SPEC, 1 on
 * one outside the file's times. */
static double when_of(vsv_file *f, const char *path, const char *opt, const char *spec)
{
    vsv_file_info info;
    vsv_file_info_get(f, &info);
    int64_t *t = malloc((size_t)info.nsteps * sizeof *t);
    if (!t)
        vsv_cli_die(1, "out of memory");
    for (int i = 0; i < info.nsteps; i++)
        t[i] = vsv_file_time(f, i);
    const int cal = vsv_meta_calendar(vsv_file_meta(f));
    vsv_timesel sel;
    char msg[400];
    const int rc =
        vsv_timesel_parse(spec, t, info.nsteps, VSV_TIMESEL_ONE | VSV_TIMESEL_CAL(cal), &sel, msg, sizeof msg);
    if (rc == VSV_EINVAL)
        vsv_cli_usage_error("%s %s: %s", opt, spec, msg);
    if (rc)
        vsv_cli_die(1, "%s: %s %s: %s", path, opt, spec, msg);
    int64_t w = t[sel.first];
    if (spec[strspn(spec, "0123456789")] && vsv_cal_parse(cal, spec, &w))
        vsv_cli_usage_error("%s %s: not a time", opt, spec);
    free(t);
    return (double)w;
}

/* ISO 8601 of a fractional time: whole seconds, or milliseconds where the
 * time has a fraction (a path's end between the scheme's steps). */
static void format_when(int cal, double t, char *buf, size_t cap)
{
    const double s = floor(t);
    const long ms = lround((t - s) * 1000);
    vsv_cal_format(cal, (int64_t)s + (ms == 1000), buf, cap);
    const size_t n = strlen(buf);
    if (ms % 1000 && n > 1 && buf[n - 1] == 'Z')
        snprintf(buf + n - 1, cap - (n - 1), ".%03ldZ", ms);
}

static const char *const end_names[] = {"time", "edge", "ground", "top", "data"};
static const char *const end_words[] = {"", "left the grid sideways", "met the ground", "left through the top",
                                        "ran out of the file's times"};

/* One path's rows: CSV or table lines, or a JSON object pushed onto arr. */
static void print_path(const query_args *qa, int cal, int which, const vsv_traj_path *p, vsv_json *arr, int has_up)
{
    vsv_json *pts = qa->fmt == FMT_JSON ? vsv_json_array() : NULL;
    for (int i = 0; i < p->n; i++) {
        const vsv_traj_point *q = &p->pts[i];
        char iso[48];
        format_when(cal, q->t, iso, sizeof iso);
        if (qa->fmt == FMT_JSON) {
            vsv_json *o = vsv_json_object();
            vsv_json_set(o, "time", vsv_json_string(iso));
            vsv_json_set(o, "lat", isnan(q->lat) ? vsv_json_null() : vsv_json_number(q->lat));
            vsv_json_set(o, "lon", isnan(q->lon) ? vsv_json_null() : vsv_json_number(q->lon));
            vsv_json_set(o, "height", vsv_json_number(q->z));
            vsv_json_set(o, "x", vsv_json_number(q->x));
            vsv_json_set(o, "y", vsv_json_number(q->y));
            vsv_json_set(o, "east", vsv_json_number(q->east));
            vsv_json_set(o, "north", vsv_json_number(q->north));
            vsv_json_set(o, "up", has_up ? vsv_json_number(q->up) : vsv_json_null());
            vsv_json_push(pts, o);
        } else if (qa->fmt == FMT_CSV) {
            if (qa->ntraj > 1)
                printf("%d,", which + 1);
            printf("%s,%.6f,%.6f,%.9g,%.9g,%.9g,%.9g,%.9g,", iso, q->lat, q->lon, q->z, q->x, q->y, q->east, q->north);
            has_up ? printf("%.9g\n", q->up) : puts("NaN");
        } else {
            if (qa->ntraj > 1)
                printf("%4d ", which + 1);
            printf("%-24s %10.4f %11.4f %10.2f %12.1f %12.1f %8.3f %8.3f ", iso, q->lat, q->lon, q->z, q->x, q->y,
                   q->east, q->north);
            has_up ? printf("%8.4f\n", q->up) : printf("%8s\n", "NaN");
        }
    }
    if (pts) {
        vsv_json *o = vsv_json_object();
        vsv_json_set(o, "seed", vsv_json_string(qa->traj[which]));
        vsv_json_set(o, "end", vsv_json_string(end_names[p->end]));
        vsv_json_set(o, "points", pts);
        vsv_json_push(arr, o);
    }
}

/* --trajectory: each seed's path through the wind, printed. */
static int run_trajectories(const query_args *qa)
{
    const char *path = qa->path;
    vsv_file *f = NULL;
    vsv_traj *tr = NULL;
    if (vsv_file_open_any(path, &vsv_cli_http, &f))
        vsv_cli_die(1, "%s", f ? vsv_file_error(f) : path);
    const vsv_meta *m = vsv_file_meta(f);
    const int rc0 = vsv_traj_create(f, &tr);
    if (rc0 == VSV_ENOTFOUND)
        vsv_cli_die(
            1, "%s: no wind stored (convert from a file with U and V, without --no-winds, or with --winds FILE)", path);
    if (rc0)
        vsv_cli_die(1, "%s: %s", path, vsv_traj_error(tr));
    if (m->proj.kind == VSV_PROJ_NONE)
        vsv_cli_die(1, "%s: the grid has no map projection: no latitude/longitude is known", path);
    vsv_file_info info;
    vsv_file_info_get(f, &info);
    const double first = (double)vsv_file_time(f, 0), last = (double)vsv_file_time(f, info.nsteps - 1);
    const double from = qa->from ? when_of(f, path, "--from", qa->from) : qa->back ? last : first;
    double to = qa->to ? when_of(f, path, "--to", qa->to) : qa->back ? first : last, every = 0;
    if (qa->dur) {
        int64_t d;
        vsv_cli_duration("--for", qa->dur, &d);
        to = from + (qa->back ? -1.0 : 1.0) * (double)d;
    }
    if (qa->every) {
        int64_t d;
        vsv_cli_duration("--every", qa->every, &d);
        every = (double)d;
    }
    if (qa->steady && vsv_traj_freeze(tr, from))
        vsv_cli_die(1, "%s: --streamline: %s", path, vsv_traj_error(tr));
    /* every path before any row: a seed that fails leaves no output */
    vsv_traj_path *paths = calloc((size_t)qa->ntraj, sizeof *paths);
    if (!paths)
        vsv_cli_die(1, "%s: out of memory", path);
    for (int i = 0; i < qa->ntraj; i++) {
        double v[3], seed[3];
        parse_list(qa->traj[i], v);
        int rc = vsv_proj_forward(&m->proj, v[0], v[1], &seed[0], &seed[1]);
        seed[2] = v[2];
        if (rc || (rc = vsv_traj_run(tr, seed, from, to, every, &paths[i])))
            vsv_cli_die(1, "%s: --trajectory %s: %s", path, qa->traj[i],
                        rc == VSV_EINVAL ? vsv_traj_error(tr) : vsv_strerror(rc));
    }
    const int cal = vsv_meta_calendar(m);
    vsv_json *root = NULL, *arr = NULL;
    if (qa->fmt == FMT_JSON) {
        root = vsv_json_object();
        vsv_json_set(root, "file", vsv_json_string(path));
        vsv_json_set(root, "height_units", vsv_json_string(vsv_meta_height_units(m)));
        arr = vsv_json_array();
    } else if (qa->fmt == FMT_CSV) {
        printf("%stime,lat,lon,height,x,y,east,north,up\n", qa->ntraj > 1 ? "path," : "");
    } else {
        printf("%s%-24s %10s %11s %10s %12s %12s %8s %8s %8s\n", qa->ntraj > 1 ? "path " : "", "time", "lat", "lon",
               "height", "x", "y", "east", "north", "up");
    }
    /* a wind with no vertical component has no "up" (null, NaN): 0 would
     * claim a measured calm */
    int wind[3];
    const int has_up = !vsv_meta_vector(m, VSV_WIND, wind) && wind[2] >= 0;
    for (int i = 0; i < qa->ntraj; i++) {
        const vsv_traj_path *p = &paths[i];
        print_path(qa, cal, i, p, arr, has_up);
        if (p->end != VSV_TRAJ_END_TIME) {
            char iso[48];
            format_when(cal, p->pts[p->n - 1].t, iso, sizeof iso);
            fprintf(stderr, "vsv-query: %s: trajectory %s %s at %s\n", path, qa->traj[i], end_words[p->end], iso);
        }
        vsv_traj_path_clear(&paths[i]);
    }
    free(paths);
    if (root) {
        vsv_json_set(root, "trajectories", arr);
        vsv_json_print(stdout, root, 1);
        vsv_json_free(root);
    }
    vsv_cli_stdout_done();
    vsv_traj_free(tr);
    vsv_file_free(f);
    return 0;
}

/* One point, one input, and the point's numbers into qa->arg (qa->path too). */
static void check_args(int argc, char **argv, query_args *qa)
{
    const char *at = qa->at, *cellarg = qa->cellarg, *profile = qa->profile;
    double *arg = qa->arg;
    if (qa->ntraj) {
        check_traj_args(argc, argv, qa);
        return;
    }
    if (qa->from || qa->to || qa->dur || qa->every || qa->back || qa->steady)
        vsv_cli_usage_error("--from, --to, --for, --every, --back and --streamline go with --trajectory");
    if (!!at + !!cellarg + !!profile != 1)
        vsv_cli_usage_error("give one of --at LAT,LON[,HEIGHT], --cell I,J[,K] or --profile LAT,LON");
    if (optind != argc - 1)
        vsv_cli_usage_error(optind < argc ? "one .vsv file" : "no input file");
    if (qa->time && qa->times)
        vsv_cli_usage_error("--time and --times exclude each other");
    const int nargs = qa->nargs = parse_list(at ? at : cellarg ? cellarg : profile, arg);
    if (at && nargs < 2)
        vsv_cli_usage_error("--at %s: expected LAT,LON or LAT,LON,HEIGHT", at);
    if (profile && nargs != 2)
        vsv_cli_usage_error("--profile %s: expected LAT,LON", profile);
    if (cellarg &&
        (nargs < 2 || arg[0] != floor(arg[0]) || arg[1] != floor(arg[1]) || (nargs == 3 && arg[2] != floor(arg[2]))))
        vsv_cli_usage_error("--cell %s: expected I,J or I,J,K (whole numbers)", cellarg);
    for (int i = 0; cellarg && i < nargs; i++) /* an int each, before it is one */
        if (arg[i] < 0 || arg[i] > 1e9)
            vsv_cli_usage_error("--cell %s: indices are whole numbers from 0", cellarg);
    if (at && (fabs(arg[0]) > 90 || fabs(arg[1]) > 360))
        vsv_cli_usage_error("--at %s: latitude must be within -90..90 and longitude within -360..360", at);
    qa->path = argv[optind];
}

/* Opens the file; the steps, the species, the point (run->pt) and the column's levels (run->k0..k1). */
static void open_query(const query_args *qa, query_run *run)
{
    const char *path = qa->path;
    const double *arg = qa->arg;
    if (vsv_file_open_any(path, &vsv_cli_http, &run->f))
        vsv_cli_die(1, "%s", run->f ? vsv_file_error(run->f) : path);
    const vsv_meta *m = run->m = vsv_file_meta(run->f);
    vsv_file_info info;
    vsv_file_info_get(run->f, &info);

    /* the steps (the one time grammar: a time outside the run exits 1 naming it) */
    vsv_cli_steps(run->f, path, qa->time, qa->times, 1, &run->a, &run->b);

    /* the species */
    run->sel = calloc((size_t)m->nvars, sizeof *run->sel);
    if (!run->sel)
        vsv_cli_die(1, "out of memory");
    run->n = vsv_cli_species(m, qa->species, path, run->sel);

    /* the point */
    char msg[512];
    int rc = qa->cellarg ? vsv_point_cell(m, (int)arg[0], (int)arg[1], qa->nargs == 3 ? (int)arg[2] : -1, &run->pt, msg,
                                          sizeof msg)
                         : vsv_point_locate_at(m, vsv_file_time(run->f, run->a), arg[0], arg[1], qa->at ? arg[2] : NAN,
                                               &run->pt, msg, sizeof msg);
    /* a moving nest may reach the point only later: its first step there */
    for (int t = run->a + 1; rc == VSV_ERANGE && m->nmoves && !qa->cellarg && t <= run->b; t++)
        if (!vsv_point_locate_at(m, vsv_file_time(run->f, t), arg[0], arg[1], qa->at ? arg[2] : NAN, &run->pt, NULL, 0))
            rc = 0;
    if (rc)
        vsv_cli_die(1, "%s: %s%s", path, msg, rc == VSV_EUNSUPPORTED ? " (give a cell: --cell I,J[,K])" : "");
    run->k0 = qa->profile ? 0 : -1;
    run->k1 = qa->profile ? m->nz - 1 : -1;

    if (vsv_query_create(run->f, &run->q))
        vsv_cli_die(1, "%s: %s", path, vsv_query_error(run->q));
    run->hu = vsv_meta_height_units(m);
    if (m->vert_kind == VSV_VERT_EVEN || m->vert_kind == VSV_VERT_NATIVE)
        snprintf(run->hname, sizeof run->hname, "height");
    else
        snprintf(run->hname, sizeof run->hname, "level");
}

/* The output's head: the JSON document up to its rows (run->root, run->rows), or the table's or CSV's header row. */
static void print_head(const query_args *qa, query_run *run)
{
    const vsv_meta *m = run->m;
    const double *arg = qa->arg;
    const int n = run->n, fmt = qa->fmt, *sel = run->sel;
    int *width = run->width = calloc((size_t)n, sizeof *width);
    if (!width)
        vsv_cli_die(1, "out of memory");
    if (fmt == FMT_JSON) {
        vsv_json *root = run->root = vsv_json_object();
        vsv_json_set(root, "file", vsv_json_string(qa->path));
        vsv_json *pj = vsv_json_object();
        if (!qa->cellarg) {
            vsv_json_set(pj, "lat", vsv_json_number(arg[0]));
            vsv_json_set(pj, "lon", vsv_json_number(arg[1]));
            if (qa->at && !isnan(arg[2]))
                vsv_json_set(pj, "height", vsv_json_number(arg[2]));
        }
        vsv_json *pos = vsv_json_array();
        for (int d = 0; d < 3; d++)
            vsv_json_push(pos, vsv_json_number(run->pt.pos[d]));
        vsv_json_set(pj, "position", pos);
        vsv_json_set(root, "point", pj);
        vsv_json_set(root, "interp", vsv_json_string(qa->interp ? "trilinear" : "nearest"));
        vsv_json_set(root, "height_units", vsv_json_string(run->hu));
        vsv_json *sp = vsv_json_array();
        for (int l = 0; l < n; l++) {
            vsv_json *o = vsv_json_object();
            vsv_json_set(o, "name", vsv_json_string(m->vars[sel[l]].name));
            vsv_json_set(o, "units", vsv_json_string(m->vars[sel[l]].units));
            vsv_json_set(o, "max_abs_error", vsv_json_number(vsv_file_quant(run->f, sel[l])->max_abs_error));
            vsv_json_push(sp, o);
        }
        vsv_json_set(root, "species", sp);
        run->rows = vsv_json_array();
    } else {
        /* the header row */
        char hcol[64];
        snprintf(hcol, sizeof hcol, *run->hu ? "%s (%s)" : "%s%s", run->hname, run->hu);
        if (fmt == FMT_CSV) {
            fputs("time,i,j,k,lat,lon,", stdout);
            vsv_csv_field(stdout, hcol);
        } else
            printf("%-20s %5s %5s %4s %10s %11s %12s", "time", "i", "j", "k", "lat", "lon", hcol);
        for (int l = 0; l < n; l++) {
            char name[160];
            const vsv_var *v = &m->vars[sel[l]];
            snprintf(name, sizeof name, *v->units ? "%s (%s)" : "%s%s", v->name, v->units);
            width[l] = (int)strlen(name) > 13 ? (int)strlen(name) : 13;
            if (fmt == FMT_CSV) {
                putchar(',');
                vsv_csv_field(stdout, name);
            } else
                printf(" %*s", width[l], name);
        }
        putchar('\n');
    }
}

/* One row a step and level: a JSON object pushed onto run->rows, or a line of the table or CSV. */
static void print_rows(const query_args *qa, query_run *run)
{
    const vsv_meta *m = run->m;
    const double *arg = qa->arg;
    const int n = run->n, fmt = qa->fmt, *sel = run->sel, *width = run->width;
    vsv_file *f = run->f;
    vsv_point *pt = &run->pt;
    char msg[512];
    for (int t = run->a; t <= run->b; t++) {
        char iso[32];
        int outside = 0;
        vsv_cal_format(vsv_meta_calendar(vsv_file_meta(f)), vsv_file_time(f, t), iso, sizeof iso);
        /* per-column heights of native levels move in time: a height's level too;
           a moving nest moves its cells under the point (and a cell's place) */
        if (m->nmoves && qa->cellarg) {
            const vsv_meta pm = vsv_meta_placed(m, vsv_file_time(f, t));
            if (vsv_meta_cell_latlon(&pm, pt->cell[0], pt->cell[1], &pt->lat, &pt->lon))
                pt->lat = pt->lon = NAN;
        } else if ((qa->at && !isnan(arg[2]) && m->nheights > 1) || (m->nmoves && !qa->cellarg)) {
            const int lrc =
                vsv_point_locate_at(m, vsv_file_time(f, t), arg[0], arg[1], qa->at ? arg[2] : NAN, pt, msg, sizeof msg);
            outside = lrc == VSV_ERANGE && m->nmoves; /* the nest has left the point: no data then */
            if (lrc && !outside)
                vsv_cli_die(1, "%s: at %s: %s", qa->path, iso, msg);
        }
        for (int k = run->k0; k <= run->k1; k++) {
            double pos[3] = {pt->pos[0], pt->pos[1], pt->pos[2]};
            int cell[3] = {pt->cell[0], pt->cell[1], pt->cell[2]};
            if (k >= 0)
                pos[2] = cell[2] = k;
            const double h = outside ? NAN : vsv_meta_cell_height_at(m, vsv_file_time(f, t), cell[0], cell[1], cell[2]);
            if (outside)
                cell[0] = cell[1] = cell[2] = -1;
            vsv_json *row = NULL, *vals = NULL;
            if (fmt == FMT_JSON) {
                row = vsv_json_object();
                vsv_json_set(row, "time", vsv_json_string(iso));
                vsv_json_set(row, "i", vsv_json_int(cell[0]));
                vsv_json_set(row, "j", vsv_json_int(cell[1]));
                vsv_json_set(row, "k", vsv_json_int(cell[2]));
                vsv_json_set(row, "lat", isnan(pt->lat) ? vsv_json_null() : vsv_json_number(pt->lat));
                vsv_json_set(row, "lon", isnan(pt->lon) ? vsv_json_null() : vsv_json_number(pt->lon));
                vsv_json_set(row, run->hname, vsv_json_number(h));
                vals = vsv_json_object();
            } else if (fmt == FMT_CSV) {
                printf("%s,%d,%d,%d,%.6f,%.6f,%.9g", iso, cell[0], cell[1], cell[2], pt->lat, pt->lon, h);
            } else {
                printf("%-20s %5d %5d %4d %10.4f %11.4f %12.6g", iso, cell[0], cell[1], cell[2], pt->lat, pt->lon, h);
            }
            for (int l = 0; l < n; l++) {
                float v = NAN;
                if (!outside && vsv_query_sample(run->q, t, sel[l], pos, qa->interp, &v))
                    vsv_cli_die(1, "%s", vsv_query_error(run->q));
                if (fmt == FMT_JSON) {
                    vsv_json_set(vals, m->vars[sel[l]].name, isnan(v) ? vsv_json_null() : vsv_json_number(v));
                } else if (fmt == FMT_CSV) {
                    putchar(',');
                    print_value(stdout, v, fmt);
                } else {
                    char cellv[64];
                    if (isnan(v))
                        snprintf(cellv, sizeof cellv, "nan");
                    else
                        snprintf(cellv, sizeof cellv, "%.6g", v);
                    printf(" %*s", width[l], cellv);
                }
            }
            if (fmt == FMT_JSON) {
                vsv_json_set(row, "values", vals);
                vsv_json_push(run->rows, row);
            } else {
                putchar('\n');
            }
        }
    }
}

int main(int argc, char **argv)
{
    vsv_cli_init("vsv-query");
    query_args qa = {.interp = VSV_INTERP_NEAREST, .fmt = FMT_TABLE, .arg = {NAN, NAN, NAN}};
    if (parse_args(argc, argv, &qa))
        return 0;
    check_args(argc, argv, &qa);
    if (qa.ntraj)
        return run_trajectories(&qa);
    query_run run = {0};
    open_query(&qa, &run);
    print_head(&qa, &run);
    print_rows(&qa, &run);
    if (qa.fmt == FMT_JSON) {
        vsv_json_set(run.root, "rows", run.rows);
        vsv_json_print(stdout, run.root, 1);
        vsv_json_free(run.root);
    }
    vsv_cli_stdout_done();
    free(run.width);
    free(run.sel);
    vsv_query_free(run.q);
    vsv_file_free(run.f);
    return 0;
}
