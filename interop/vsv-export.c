/* vsv-export — a .vsv file out to other tools: one OpenVDB file per time
 * step, one FloatGrid per species (Blender, Houdini and the OpenVDB tools
 * read them), one CF-1.8 netCDF-4 file (xarray, ncview, CDO, NCL), or an
 * isosurface of one step as PLY or glTF 2.0 (MeshLab, Blender, three.js). */
#include "vsv_cf.h"
#include "vsv_cli.h"
#include "vsv_render.h"
#include "vsv_vdb.h"

#include <sys/stat.h>

#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <errno.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

/* clang-format off */ /* (the help text as it prints, a line a line) */
static const char usage[] =
    "Usage: vsv-export FILE.vsv|URL (--vdb OUT_%04d.vdb | --netcdf OUT.nc) [--times A:B] [--species LIST]\n"
    "       vsv-export FILE.vsv|URL --iso SPECIES:VALUE[:COLOUR] (--ply OUT.ply | --gltf OUT.gltf) [--time T]\n"
    "Write each selected time step as an OpenVDB file: one FloatGrid per species,\n"
    "named after it, in world units (projected metres, height above sea level;\n"
    "the grid's origin and spacing are the transform), only non-empty cells\n"
    "active, with units, model time (ISO 8601), source model and projection as\n"
    "metadata. %04d (or %d, %0Nd with N 1-9) numbers the files from 0; a name\n"
    "without one takes a single step.\n"
    "--netcdf writes every selected step into one CF-1.8 netCDF-4 file: the\n"
    "projection as a grid_mapping, 2-D lat/lon, heights, time in seconds since the\n"
    "first step, units, long_name and the quantisation bound (vsv_max_abs_error)\n"
    "per variable, chunked by step and deflated; vsv-extract reads it back.\n"
    "--iso writes the surface where SPECIES equals VALUE at one step (--time; the\n"
    "last by default) as triangles with normals, at the model's own heights: PLY\n"
    "(binary; x east, y north, z up) or glTF 2.0 (one .gltf, buffer embedded; +Y\n"
    "up, +Z south), metres in the file's projected frame, coloured COLOUR.\n"
    "Reads .vsv files (vsv(5)); writes OpenVDB (.vdb) and CF netCDF-4 (.nc).\n"
    "\n"
    "      --vdb OUT           the OpenVDB files to write\n"
    "      --netcdf OUT.nc     the netCDF file to write\n"
    "      --iso S:V[:COLOUR]  the isosurface of species S at value V (COLOUR: white\n"
    "                          grey red orange yellow green cyan blue purple #RRGGBB)\n"
    "      --ply OUT.ply       write it as binary PLY\n"
    "      --gltf OUT.gltf     write it as glTF 2.0\n"
    "  -t, --time T            one step: an index or an ISO time, the nearest step\n"
    "                          (said on stderr when not exact; default: all steps)\n"
    "      --times A:B         steps A..B (indices or ISO times, which may hold colons;\n"
    "                          either end may be empty; outside the file is an error)\n"
    "  -s, --species LIST      NAME,... (default: every species; --vdb: but the\n"
    "                          wind's components, written only when named)\n"
    "  -q, --quiet             no progress\n"
    VSV_CLI_CACHE_DIR_HELP
    "  -h, --help              this help\n"
    "  -V, --version           print versions\n";
/* clang-format on */

/* --netcdf: the selected species and steps into one CF netCDF file. */
static int export_netcdf(int argc, char **argv, vsv_file *f, const char *path, const char *ncout, int *sel, int n,
                         int a, int b)
{
    vsv_cli_refuse_input(ncout, (const char *const *)&path, 1);
    char history[1024] = "vsv-export", err[4300];
    for (int i = 1; i < argc; i++)
        snprintf(history + strlen(history), sizeof history - strlen(history), " %s", argv[i]);
    if (vsv_cf_write(ncout, path, f, sel, n, a, b, history, vsv_cli_progress, (void *)"vsv-export", err, sizeof err))
        vsv_cli_die(1, "%s", err);
    if (!vsv_cli_quiet() && !isatty(2))
        fprintf(stderr, "vsv-export: %s: %d step%s, %d species\n", ncout, b - a + 1, b > a ? "s" : "", n);
    free(sel);
    vsv_file_free(f);
    return 0;
}

/* --iso S:V with --ply or --gltf: the surface at one step, at the model's
 * own heights, written all or nothing. iso: the three options' arguments;
 * other: whether an option of the other outputs was given. */
static int export_iso(int argc, char **argv, const char *const iso[3], int other, const char *time)
{
    if (!iso[0])
        vsv_cli_usage_error("--ply and --gltf write an isosurface: give --iso SPECIES:VALUE");
    if (!iso[1] == !iso[2])
        vsv_cli_usage_error(iso[1] ? "--ply and --gltf exclude each other"
                                   : "--iso needs --ply OUT.ply or --gltf OUT.gltf");
    if (other)
        vsv_cli_usage_error("--iso takes one step (--time) and none of --vdb, --netcdf, --times, --species");
    if (optind != argc - 1)
        vsv_cli_usage_error(optind < argc ? "one .vsv file" : "no input file");
    const char *path = argv[optind], *dst = iso[1] ? iso[1] : iso[2];
    vsv_cli_refuse_input(dst, (const char *const *)&path, 1);
    vsv_file *f = NULL;
    if (vsv_file_open_any(path, &vsv_cli_http, &f))
        vsv_cli_die(1, "%s", f ? vsv_file_error(f) : path);
    const vsv_meta *m = vsv_file_meta(f);
    char msg[4400];
    vsv_iso_spec spec;
    if (vsv_iso_parse(m, iso[0], &spec, msg, sizeof msg))
        vsv_cli_usage_error("%s", msg);
    int a, b;
    vsv_cli_steps(f, path, time, NULL, 0, &a, &b);
    vsv_volume *v = NULL;
    vsv_decoder *d = NULL;
    vsv_iso *s = NULL;
    if (vsv_decoder_create(f, &d) || vsv_volume_create(f, &v) || vsv_iso_create(0, &s))
        vsv_cli_die(1, "out of memory");
    if (vsv_volume_load(v, d, a, spec.species))
        vsv_cli_die(1, "%s", vsv_decoder_error(d));
    const vsv_meta placed = vsv_meta_placed(m, v->time); /* a moving nest where it is then */
    if (vsv_iso_extract(s, &placed, v, spec.value))
        vsv_cli_die(1, "out of memory");
    vsv_iso_info in;
    vsv_iso_get_info(s, &in);
    const vsv_var *var = &m->vars[spec.species];
    char when[64], title[256];
    vsv_time_format(v->time, when, sizeof when);
    snprintf(title, sizeof title, "%s = %g %s at %s", var->name, (double)spec.value, var->units, when);
    if (!in.ntris)
        vsv_cli_die(1, "%s: no surface: %s (the values of step %d lie on one side)", path, title, a);
    if (vsv_iso_write(s, dst, iso[1] ? VSV_ISO_PLY : VSV_ISO_GLTF, spec.rgb, title, msg, sizeof msg))
        vsv_cli_die(1, "%s", msg);
    if (!vsv_cli_quiet() && !isatty(2))
        fprintf(stderr, "vsv-export: %s: %zu triangles, %s (%.3f s)\n", dst, in.ntris, title, in.seconds);
    vsv_iso_free(s);
    vsv_volume_free(v);
    vsv_decoder_free(d);
    vsv_file_free(f);
    return 0;
}

/* A .vdb is drawn as a volume (Blender, Houdini): of the n species in sel,
 * the wind's components are written only when named; the others' count. */
static int drop_vectors(const vsv_meta *m, const char *path, int *sel, int n)
{
    int kept = 0;
    for (int l = 0; l < n; l++)
        if (!vsv_meta_var_in_vector(m, sel[l]))
            sel[kept++] = sel[l];
    if (!kept)
        vsv_cli_die(1, "%s: its species are the wind's components, which --vdb writes only when named (--species)",
                    path);
    return kept;
}

/* Each output named as the kind of file its option writes (misuse
 * otherwise: vsv_cli_output_kind). */
static void output_kinds(const char *vdb, const char *nc, const char *const iso[3])
{
    const char *const name[4] = {vdb, nc, iso[1], iso[2]}, *const opt[4] = {"--vdb", "--netcdf", "--ply", "--gltf"},
                      *const ext[4] = {".vdb", ".nc .nc4", ".ply", ".gltf"},
                      *const what[4] = {"OpenVDB (.vdb)", "netCDF-4 (.nc)", "PLY (.ply)", "glTF 2.0 (.gltf)"};
    for (int i = 0; i < 4; i++)
        if (name[i])
            vsv_cli_output_kind(opt[i], name[i], ext[i], what[i]);
}

int main(int argc, char **argv)
{
    vsv_cli_init("vsv-export");
    /* clang-format off */ /* (a table, laid out by hand) */
    enum { O_VDB = 1000, O_TIMES, O_NETCDF, O_ISO, O_PLY, O_GLTF };
    static const struct option longopts[] = {{"vdb", required_argument, 0, O_VDB},   {"netcdf", required_argument, 0, O_NETCDF},
                                             {"iso", required_argument, 0, O_ISO},   {"ply", required_argument, 0, O_PLY},
                                             {"gltf", required_argument, 0, O_GLTF}, {"time", required_argument, 0, 't'},
                                             {"times", required_argument, 0, O_TIMES}, {"species", required_argument, 0, 's'},
                                             {"quiet", no_argument, 0, 'q'},          {"help", no_argument, 0, 'h'}, {"cache-dir", required_argument, 0, VSV_CLI_CACHE_DIR},
                                             {"version", no_argument, 0, 'V'},        {0, 0, 0, 0}};
    /* clang-format on */
    const char *out = NULL, *ncout = NULL, *time = NULL, *times = NULL, *species = NULL, *iso[3] = {NULL, NULL, NULL};
    int c;
    argv[0] = (char *)vsv_cli_tool(); /* getopt's messages name the tool as ours do */
    while ((c = getopt_long(argc, argv, "t:s:qhV", longopts, NULL)) != -1) {
        switch (c) {
        case O_VDB: out = optarg; break;
        case O_NETCDF: ncout = optarg; break;
        case O_ISO: iso[0] = optarg; break;
        case O_PLY: iso[1] = optarg; break;
        case O_GLTF: iso[2] = optarg; break;
        case 't': time = optarg; break;
        case O_TIMES: times = optarg; break;
        case 's': species = optarg; break;
        case 'q': vsv_cli_set_quiet(1); break;
        case VSV_CLI_CACHE_DIR: vsv_cli_cache_dir(optarg); break;
        case 'h': fputs(usage, stdout); return 0;
        case 'V': vsv_cli_version();
        default: vsv_cli_getopt_failed();
        }
    }
    output_kinds(out, ncout, iso);
    if (iso[0] || iso[1] || iso[2])
        return export_iso(argc, argv, iso, out || ncout || times || species, time);
    if (!out == !ncout)
        vsv_cli_usage_error(out ? "--vdb and --netcdf exclude each other"
                                : "no output (--vdb OUT_%%04d.vdb or --netcdf OUT.nc)");
    if (optind != argc - 1)
        vsv_cli_usage_error(optind < argc ? "one .vsv file" : "no input file");
    if (time && times)
        vsv_cli_usage_error("--time and --times exclude each other");
    const char *path = argv[optind];
    const int sequence = out ? vsv_cli_pattern(out) : 0;
    if (sequence < 0)
        vsv_cli_usage_error("--vdb %s: a '%%' in the name must be %%d or %%0Nd (the step number, once) or %%%% (a "
                            "percent sign)",
                            out);
    vsv_file *f = NULL;
    if (vsv_file_open_any(path, &vsv_cli_http, &f))
        vsv_cli_die(1, "%s", f ? vsv_file_error(f) : path);
    const vsv_meta *m = vsv_file_meta(f);
    vsv_file_info info;
    vsv_file_info_get(f, &info);
    int a, b;
    vsv_cli_steps(f, path, time, times, 1, &a, &b);
    if (a < 0 || b >= info.nsteps || a > b)
        vsv_cli_die(1, "%s: no step selected (the file has steps 0..%d)", path, info.nsteps - 1);
    if (out && !sequence && a != b)
        vsv_cli_usage_error("several steps need %%04d in the output name (or --time T)");
    /* species */
    int *sel = calloc((size_t)m->nvars, sizeof *sel);
    if (!sel)
        vsv_cli_die(1, "out of memory");
    int n = vsv_cli_species(m, species, path, sel);
    if (ncout)
        return export_netcdf(argc, argv, f, path, ncout, sel, n, a, b);
    if (!species)
        n = drop_vectors(m, path, sel, n);
    vsv_volume **vols = calloc((size_t)n, sizeof *vols);
    vsv_decoder *d = NULL;
    if (!vols || vsv_decoder_create(f, &d))
        vsv_cli_die(1, "out of memory");
    for (int l = 0; l < n; l++)
        if (vsv_volume_create(f, &vols[l]))
            vsv_cli_die(1, "out of memory");
    /* native levels with per-column heights: placed at their heights, on an
     * even axis (as the renderers draw them) */
    vsv_resampler **rs = calloc((size_t)n, sizeof *rs);
    const vsv_volume **out_vols = calloc((size_t)n, sizeof *out_vols);
    const vsv_meta *out_meta = m;
    if (!rs || !out_vols)
        vsv_cli_die(1, "out of memory");
    for (int l = 0; l < n && m->vert_kind == VSV_VERT_NATIVE && m->nheights; l++) {
        if (vsv_resampler_create(m, &rs[l]))
            vsv_cli_die(1, "out of memory");
        out_meta = vsv_resampler_meta(rs[l]);
    }
    for (int t = a; t <= b; t++) { /* every name, before any is written */
        char name[4096];
        if (vsv_cli_pattern_name(out, t - a, name, sizeof name))
            vsv_cli_usage_error("--vdb %s: the name is too long", out);
        vsv_cli_refuse_input(name, (const char *const *)&path, 1);
    }
    char *staged = calloc((size_t)(b - a + 1), 4200); /* the files' temporary names */
    if (!staged)
        vsv_cli_die(1, "out of memory");
    for (int t = a; t <= b; t++) {
        for (int l = 0; l < n; l++) {
            if (vsv_volume_load(vols[l], d, t, sel[l]))
                vsv_cli_die(1, "%s", vsv_decoder_error(d));
            out_vols[l] = vols[l];
            if (rs[l] && vsv_resampler_run(rs[l], vols[l], &out_vols[l]))
                vsv_cli_die(1, "out of memory");
        }
        char name[4096], err[4300];
        vsv_cli_pattern_name(out, t - a, name, sizeof name); /* (each fitted above) */
        /* each file complete under a listed temporary name; all are renamed
         * into place only when every step is written (all or nothing) */
        char *tmp = staged + (size_t)(t - a) * 4200;
        const int fd = vsv_output_temp(name, NULL, tmp, 4200);
        if (fd < 0)
            vsv_cli_die(1, "%s: cannot create: %s", name, strerror(errno));
        close(fd);
        const vsv_meta placed = vsv_meta_placed(out_meta, vsv_file_time(f, t)); /* a moving nest where it is then */
        if (vsv_vdb_write(tmp, &placed, vsv_file_time(f, t), out_vols, n, err, sizeof err)) {
            const size_t k = strlen(tmp);
            vsv_cli_die(1, "%s%s", name, !strncmp(err, tmp, k) ? err + k : err);
        }
        vsv_cli_progress("vsv-export", t - a + 1, b - a + 1);
    }
    vsv_cli_hold_signals(1); /* all renamed, or none: a signal waits for it */
    for (int t = a; t <= b; t++) {
        char name[4096];
        vsv_cli_pattern_name(out, t - a, name, sizeof name); /* (each fitted above) */
        if (vsv_output_publish(staged + (size_t)(t - a) * 4200, name))
            vsv_cli_die(1, "%s: cannot rename into place: %s", name, strerror(errno));
    }
    vsv_cli_hold_signals(0);
    free(staged);
    if (!vsv_cli_quiet() && !isatty(2))
        fprintf(stderr, "vsv-export: %d file%s, %d species each\n", b - a + 1, b > a ? "s" : "", n);
    for (int l = 0; l < n; l++) {
        vsv_volume_free(vols[l]);
        vsv_resampler_free(rs[l]);
    }
    free(vols);
    free(rs);
    free(out_vols);
    free(sel);
    vsv_decoder_free(d);
    vsv_file_free(f);
    return 0;
}
