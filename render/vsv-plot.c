/* vsv-plot — plots of a .vsv file with axes, as NCL and GrADS draw them: a
 * vertical cross-section along a line, a time series at a point, a profile;
 * PNG, SVG or PDF. The reading and drawing live in the library (vsv_plot_*,
 * render/vsv_plot*.c). */
#include "vsv_cli.h"
#include "vsv_render.h"

#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* clang-format off */ /* (the help text as it prints, a line a line) */
static const char usage[] =
    "Usage: vsv-plot FILE.vsv|URL -o OUT.svg|OUT.png|OUT.pdf\n"
    "                (--section LAT1,LON1:LAT2,LON2 | --series LAT,LON[,HEIGHT] | --profile LAT,LON)\n"
    "                [--species LIST] [--time T | --times A:B] [OPTIONS]\n"
    "Draw a plot of a .vsv file with axes, tick labels, a colour bar or a legend, and\n"
    "a title and subtitle that name the species, units, time and place: a vertical\n"
    "cross-section along a line (distance against height, one species in colour), a\n"
    "time series at a point (one line per species), or a profile (height against\n"
    "value, one line per species). The values are the file's decoded values at the\n"
    "nearest cells, as vsv-query prints them (--csv writes them).\n"
    "Reads .vsv files (vsv(5)); writes PNG, SVG or PDF (the output's extension), and CSV.\n"
    "\n"
    "      --section LAT1,LON1:LAT2,LON2  a cross-section along the straight line\n"
    "                          between two points in the grid's projection, sampled\n"
    "                          every half cell, each column's levels at their heights\n"
    "                          (the ground and no data grey)\n"
    "      --series LAT,LON[,H]  a time series at a point: H in metres above sea level\n"
    "                          (the grid's level unit when its levels are not heights);\n"
    "                          without H the lowest level above the ground\n"
    "      --profile LAT,LON   a profile: every level of the column at the point\n"
    "  -o, --output FILE       the plot: .png, .svg or .pdf\n"
    "  -s, --species LIST      NAME,... (a section: one; lines: up to 8; default: the\n"
    "                          species shown by default: not water vapour Q/QVAPOR,\n"
    "                          nor the wind's components)\n"
    "  -t, --time T            the step of a section or profile, or a series of one\n"
    "                          step: an index or an ISO time (default: the last)\n"
    "      --times A:B         a series' steps (indices or ISO times; default: all)\n"
    "      --size WxH          pixels (PDF: points; default 800x600; 200x150 to 8192x8192)\n"
    "      --colormap NAME     the section's colours (default viridis): viridis, magma,\n"
    "                          cividis, inferno, plasma, clouds, rain, ice, snow,\n"
    "                          graupel, greys; for lines, their colours spread over it\n"
    "                          (default: tab10)\n"
    "      --log               the values on a log scale (a section's colours, the\n"
    "                          value axis of lines; by default down to 4 decades below\n"
    "                          the largest value)\n"
    "      --range LO:HI       the values' range (the colour bar's ends, or the value\n"
    "                          axis; default: the least and greatest value drawn)\n"
    "      --top HEIGHT        the height axis' top (metres above sea level, as H;\n"
    "                          default: the model's top)\n"
    "      --title TEXT        the title (default: the species and the time, or place)\n"
    "      --csv FILE          also the values drawn as CSV (vsv-query --csv's columns;\n"
    "                          a section's with the distance along the line); - for\n"
    "                          standard output\n"
    VSV_CLI_CACHE_DIR_HELP
    "  -h, --help              this help\n"
    "  -V, --version           print versions\n";
/* clang-format on */

/* The command line, parsed and checked (main). */
typedef struct plot_args {
    const char *path, *out, *csv, *section, *series, *profile, *species, *time, *times, *range, *top, *size;
    vsv_plot_opts o;
} plot_args;

/* "A,B[,C]" into up to 3 finite doubles; how many, or -1. */
static int numbers(const char *s, double *v, int max)
{
    int n = 0;
    for (const char *p = s;;) {
        char *end;
        if (n == max)
            return -1;
        errno = 0;
        v[n] = strtod(p, &end);
        if (end == p || !isfinite(v[n]) || errno)
            return -1;
        n++;
        if (!*end)
            return n;
        if (*end != ',')
            return -1;
        p = end + 1;
    }
}

static void parse_args(int argc, char **argv, plot_args *a)
{
    /* clang-format off */ /* (a table, laid out by hand) */
    enum { O_SECTION = 1000, O_SERIES, O_PROFILE, O_TIMES, O_SIZE, O_COLORMAP, O_LOG, O_RANGE, O_TOP, O_TITLE, O_CSV };
    static const struct option longopts[] = {
        {"section", required_argument, 0, O_SECTION}, {"series", required_argument, 0, O_SERIES},
        {"profile", required_argument, 0, O_PROFILE}, {"output", required_argument, 0, 'o'},
        {"species", required_argument, 0, 's'},      {"time", required_argument, 0, 't'},
        {"times", required_argument, 0, O_TIMES},    {"size", required_argument, 0, O_SIZE},
        {"colormap", required_argument, 0, O_COLORMAP}, {"log", no_argument, 0, O_LOG},
        {"range", required_argument, 0, O_RANGE},    {"top", required_argument, 0, O_TOP},
        {"title", required_argument, 0, O_TITLE},    {"csv", required_argument, 0, O_CSV},
        {"cache-dir", required_argument, 0, VSV_CLI_CACHE_DIR},
        {"help", no_argument, 0, 'h'},               {"version", no_argument, 0, 'V'}, {0, 0, 0, 0}};
    /* clang-format on */
    int c;
    argv[0] = (char *)vsv_cli_tool(); /* getopt's messages name the tool as ours do */
    while ((c = getopt_long(argc, argv, "o:s:t:hV", longopts, NULL)) != -1) {
        switch (c) {
        case O_SECTION: a->section = optarg; break;
        case O_SERIES: a->series = optarg; break;
        case O_PROFILE: a->profile = optarg; break;
        case 'o': a->out = optarg; break;
        case 's': a->species = optarg; break;
        case 't': a->time = optarg; break;
        case O_TIMES: a->times = optarg; break;
        case O_SIZE: a->size = optarg; break;
        case O_COLORMAP: snprintf(a->o.colormap, sizeof a->o.colormap, "%s", optarg); break;
        case O_LOG: a->o.log = 1; break;
        case O_RANGE: a->range = optarg; break;
        case O_TOP: a->top = optarg; break;
        case O_TITLE: a->o.title = optarg; break;
        case O_CSV: a->csv = optarg; break;
        case VSV_CLI_CACHE_DIR: vsv_cli_cache_dir(optarg); break;
        case 'h': fputs(usage, stdout); exit(0);
        case 'V': vsv_cli_version();
        default: vsv_cli_getopt_failed();
        }
    }
    if (optind != argc - 1)
        vsv_cli_usage_error(optind < argc ? "one .vsv file" : "no input file");
    a->path = argv[optind];
}

/* The options that need no file: exits 2 on any that is wrong. */
static void check_args(plot_args *a)
{
    vsv_plot_opts *o = &a->o;
    if (!!a->section + !!a->series + !!a->profile != 1)
        vsv_cli_usage_error("give one of --section, --series or --profile");
    if (!a->out)
        vsv_cli_usage_error("no output (-o FILE.svg, FILE.png or FILE.pdf)");
    if (vsv_plot_format(a->out) < 0)
        vsv_cli_usage_error("-o %s: the format comes from the extension: .png, .svg or .pdf", a->out);
    if (a->time && a->times)
        vsv_cli_usage_error("--time and --times exclude each other");
    if (a->times && !a->series)
        vsv_cli_usage_error("--times: a %s is drawn at one time (--time T)", a->section ? "section" : "profile");
    double v[4];
    const char *colon = a->section ? strchr(a->section, ':') : NULL;
    if (a->section) {
        char first[128];
        snprintf(first, sizeof first, "%.*s", colon ? (int)(colon - a->section) : 0, a->section);
        if (!colon || numbers(first, v, 2) != 2 || numbers(colon + 1, v + 2, 2) != 2 || fabs(v[0]) > 90 ||
            fabs(v[2]) > 90)
            vsv_cli_usage_error("--section %s: expected LAT1,LON1:LAT2,LON2 (degrees)", a->section);
        if (v[0] == v[2] && v[1] == v[3])
            vsv_cli_usage_error("--section %s: the two ends are the same point", a->section);
        o->kind = VSV_PLOT_SECTION;
        o->lat[0] = v[0], o->lon[0] = v[1], o->lat[1] = v[2], o->lon[1] = v[3];
    } else {
        const char *arg = a->series ? a->series : a->profile;
        const int n = numbers(arg, v, a->series ? 3 : 2);
        if (n < 2 || fabs(v[0]) > 90 || fabs(v[1]) > 360)
            vsv_cli_usage_error("--%s %s: expected LAT,LON%s (degrees%s)", a->series ? "series" : "profile", arg,
                                a->series ? "[,HEIGHT]" : "", a->series ? "; metres" : "");
        o->kind = a->series ? VSV_PLOT_SERIES : VSV_PLOT_PROFILE;
        o->lat[0] = v[0], o->lon[0] = v[1];
        o->at_height = n == 3 ? v[2] : NAN;
    }
    if (a->size)
        vsv_cli_size(a->size, (const int[2]){200, 150}, (const int[2]){8192, 8192}, &o->size[0], &o->size[1]);
    int used = 0;
    if (a->range && (sscanf(a->range, "%lf:%lf%n", &o->lo, &o->hi, &used) != 2 || a->range[used] || !(o->lo < o->hi) ||
                     !isfinite(o->hi - o->lo)))
        vsv_cli_usage_error("--range %s: expected LO:HI with LO < HI", a->range);
    if (a->range && o->log && !(o->lo > 0))
        vsv_cli_usage_error("--range %s with --log: a log scale needs LO > 0", a->range);
    if (a->top && a->series)
        vsv_cli_usage_error("--top: a series has no height axis");
    if (a->top && (vsv_cli_double(a->top, &o->top) || !(o->top > 0)))
        vsv_cli_usage_error("--top %s: expected a height above 0", a->top);
    int known = !o->colormap[0];
    char names[256] = "";
    for (const char *const *c = vsv_tf_colormaps(); *c; c++) {
        known |= !strcmp(*c, o->colormap);
        snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", *c, c[1] ? ", " : "");
    }
    if (!known)
        vsv_cli_usage_error("--colormap %s: no colour map '%s' (%s)", o->colormap, o->colormap, names);
    if (a->csv && !strcmp(a->csv, a->out))
        vsv_cli_usage_error("--csv %s: the plot's own name", a->csv);
    const char *in[1] = {a->path};
    vsv_cli_refuse_input(a->out, in, 1);
    if (a->csv && strcmp(a->csv, "-"))
        vsv_cli_refuse_input(a->csv, in, 1);
}

/* The species: --species, or those shown by default (a section: the first). */
static void species(const vsv_meta *m, plot_args *a)
{
    vsv_plot_opts *o = &a->o;
    int *sel = calloc((size_t)m->nvars, sizeof *sel);
    if (!sel)
        vsv_cli_die(1, "out of memory");
    int n = 0;
    if (a->species) {
        n = vsv_cli_species(m, a->species, a->path, sel);
    } else {
        for (int s = 0; s < m->nvars; s++)
            if (vsv_meta_default_shown(m, s))
                sel[n++] = s;
    }
    const int max = o->kind == VSV_PLOT_SECTION ? 1 : VSV_PLOT_MAXSPECIES;
    if (a->species && n > max)
        vsv_cli_usage_error("--species %s: a %s draws %s", a->species, o->kind == VSV_PLOT_SECTION ? "section" : "plot",
                            o->kind == VSV_PLOT_SECTION ? "one species" : "at most 8 species");
    o->nspecies = n < max ? n : max;
    memcpy(o->species, sel, (size_t)o->nspecies * sizeof *sel);
    free(sel);
}

/* The values as CSV on standard output. */
static void print_csv(const vsv_plot *p)
{
    if (vsv_plot_csv(p, stdout)) {
        vsv_cli_stdout_done(); /* dies saying why, when the output failed */
        vsv_cli_die(1, "standard output: not all of it written");
    }
}

/* The values as CSV into a temporary file beside path, written whole and
 * synced, its name into tmp: published once the plot is. */
static void stage_csv(const vsv_plot *p, const char *path, char *tmp, size_t cap)
{
    const int fd = vsv_output_temp(path, NULL, tmp, cap);
    FILE *fp = fd >= 0 ? fdopen(fd, "w") : NULL;
    if (!fp) {
        const int e = errno;
        if (fd >= 0)
            close(fd), vsv_output_discard(tmp);
        vsv_cli_die(1, "%s: cannot create: %s", path, strerror(e));
    }
    int bad = vsv_plot_csv(p, fp) || fsync(fileno(fp));
    const int e = errno;
    if (fclose(fp) || bad) {
        const int e2 = bad ? e : errno;
        vsv_output_discard(tmp);
        vsv_cli_die(1, "%s: cannot write: %s", path, strerror(e2));
    }
}

int main(int argc, char **argv)
{
    vsv_cli_init("vsv-plot");
    plot_args a = {0};
    vsv_plot_opts_init(&a.o);
    parse_args(argc, argv, &a);
    check_args(&a);
    vsv_file *f = NULL;
    if (vsv_file_open_any(a.path, &vsv_cli_http, &f))
        vsv_cli_die(1, "%s", f ? vsv_file_error(f) : a.path);
    const vsv_meta *m = vsv_file_meta(f);
    species(m, &a);
    if (!a.o.nspecies)
        vsv_cli_die(1, "%s: no species to plot", a.path);
    vsv_cli_steps(f, a.path, a.time, a.times, a.series != NULL, &a.o.step0, &a.o.step1);
    a.o.source = a.path;
    vsv_plot *p = NULL;
    char msg[1024];
    const char *what = a.section ? "--section" : a.series ? "--series" : "--profile";
    const char *arg = a.section ? a.section : a.series ? a.series : a.profile;
    int rc = vsv_plot_create(f, &a.o, &p, msg, sizeof msg);
    if (rc)
        vsv_cli_die(rc == VSV_EINVAL ? 2 : 1, "%s: %s %s: %s%s", a.path, what, arg, msg,
                    rc == VSV_EUNSUPPORTED ? " (vsv-convert --proj gives a CAMx 5 grid its projection)" : "");
    /* both outputs or neither: the CSV staged first, published after the plot */
    char tmp[4200] = "";
    const int to_file = a.csv && strcmp(a.csv, "-");
    if (to_file)
        stage_csv(p, a.csv, tmp, sizeof tmp);
    if ((rc = vsv_plot_write(p, a.out, msg, sizeof msg))) {
        if (to_file)
            vsv_output_discard(tmp);
        vsv_cli_die(1, "%s", msg);
    }
    if (to_file && vsv_output_publish(tmp, a.csv)) {
        const int e = errno;
        vsv_output_discard(tmp);
        vsv_cli_die(1, "%s: cannot write: %s (the plot %s is written)", a.csv, strerror(e), a.out);
    }
    if (a.csv && !to_file)
        print_csv(p);
    vsv_plot_free(p);
    vsv_file_free(f);
    return 0;
}
