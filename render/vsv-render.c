/* vsv-render — headless frames of a .vsv file to PNG. */
#include "vsv_cli.h"
#include "vsv_flow.h"
#include "vsv_gl.h"
#include "vsv_movie_cli.h"
#include "vsv_render.h"

#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

/* clang-format off */ /* (the help text as it prints, a line a line) */
static const char usage[] =
    "Usage: vsv-render FILE.vsv|URL -o OUT.png|OUT.exr [OPTIONS]\n"
    "       vsv-render FILE.vsv|URL --movie OUT.mp4 [--fps N] [OPTIONS]\n"
    "Render the species of a .vsv file over its terrain to PNG images, or to OpenEXR\n"
    "(RGBA half, premultiplied, plus a float Z depth channel), by raycasting.\n"
    "With %04d (or %d, %0Nd with N 1-9) in OUT, every selected step is rendered,\n"
    "numbered from 0.\n"
    "Reads .vsv files (vsv(5)) and transfer-function files (--tf); writes PNG,\n"
    "OpenEXR (.exr) and, through ffmpeg, movies (--movie: MP4/H.264, or H.264 in\n"
    "the container the extension names: .m4v, .mov, .mkv, .avi, .flv or .ts).\n"
    "\n"
    "  -o, --output FILE       the image; %04d for a sequence\n"
    "  -t, --time T            one step: an index or an ISO time, the nearest step\n"
    "                          (said on stderr when not exact; default: the last)\n"
    "      --times A:B         steps A..B (indices or ISO times, which may hold colons:\n"
    "                          1995-10-24T01:00Z:1995-10-24T02:00Z; either end may be\n"
    "                          empty; outside the file's steps is an error)\n"
    "  -s, --species LIST      NAME[:OPACITY],... (default: every species but water\n"
    "                          vapour Q/QVAPOR and the wind's components, opacity 1)\n"
    "      --tf FILE           transfer functions: 'species NAME' blocks of\n"
    "                          colormap / range / scale / opacity lines\n"
    "  -c, --camera AZ,EL[,DIST] azimuth clockwise from north, elevation (degrees),\n"
    "                          distance in world metres (default 225,30: from the\n"
    "                          south-west, 30 degrees up, the domain filling the image)\n"
    "      --range SPECIES:LO:HI  the values the species' colours span (its transfer\n"
    "                          function's range; also SPECIES=LO:HI), so files share\n"
    "                          a scale\n"
    "      --colormap SPECIES:NAME  its colour map: viridis, magma, cividis, inferno,\n"
    "                          plasma (perceptually uniform, matplotlib's), clouds,\n"
    "                          rain, ice, snow, graupel, greys\n"
    "      --log SPECIES       its colours on a log scale (over its range; a range\n"
    "                          from 0 starts 4 decades below its top)\n"
    "                          (these three repeat, per species, in the order given)\n"
    "      --view NAME         plan (a map: orthographic, north up), south, west\n"
    "                          (from 8 degrees up) or oblique (225,30)\n"
    "      --look-at EX,EY,EZ,TX,TY,TZ  eye and target in metres (projection x, y;\n"
    "                          height above sea level), instead of --camera\n"
    "      --stereo            a side-by-side pair, left eye on the left (twice as wide)\n"
    "      --size WxH          image size (default 800x600; at most 16384x16384)\n"
    "  -x, --exaggerate N      vertical exaggeration (default: a domain 1/5 as tall as wide)\n"
    "      --background R,G,B  0..1 (default 0.02,0.03,0.06)\n"
    "      --no-terrain        do not draw the ground\n"
    "      --light[=AZ,EL]     shade the clouds by their gradient, lit by a sun at\n"
    "                          azimuth AZ, elevation EL degrees (default 315,45: from\n"
    "                          the north-west, as hill shading is)\n"
    "      --no-light          no shading (the default)\n"
    "      --slice SPEC        an opaque section in a species' colours: z=HEIGHT\n"
    "                          (metres above sea level), lat=DEG, lon=DEG, or\n"
    "                          line=LAT1,LON1:LAT2,LON2 (a vertical section between\n"
    "                          two points); repeatable (8 at most)\n"
    "      --slice-species NAME  the species the slices show (default: the first\n"
    "                          drawn); drawn as a slice only when not in --species\n"
    "      --slice-colormap NAME  the slices' colour map (default viridis; see --tf\n"
    "                          for the names) over the range of the values the\n"
    "                          slices show in each frame (said on their bar)\n"
    "      --slice-range LO:HI   that range fixed instead (the same for every frame)\n"
    "      --iso S:V[:COLOUR]  an opaque, lit isosurface where species S equals V, at\n"
    "                          the model's own heights (COLOUR: white grey red orange\n"
    "                          yellow green cyan blue purple #RRGGBB; default white);\n"
    "                          repeatable (8 at most); such frames are raycast\n"
    "      --trajectory LAT,LON,HEIGHT[:COLOUR]  the path of the air from there\n"
    "                          (HEIGHT in metres as the file's heights), drawn up to\n"
    "                          each frame's time as a lit tube with an arrowhead;\n"
    "                          repeatable (64 at most)\n"
    "      --seed-line LAT,LON,H:LAT,LON,H:N[:COLOUR]  N paths along a line\n"
    "      --seed-slice HEIGHT:EVERY[:COLOUR]  a path from every EVERY-th column\n"
    "      --traj-from T       the air leaves at step or time T (default: the first)\n"
    "      --traj-for DURATION  followed so long (1h30m; default: to the last step)\n"
    "      --streamlines       the paths are streamlines of each frame's wind held\n"
    "                          still, drawn whole (--traj-for of travel, default 1h)\n"
    "      --barbs HEIGHT[:EVERY]  wind arrows on a horizontal plane from every\n"
    "                          EVERY-th column (default: about 24 across); an arrow\n"
    "                          of 20 m/s spans EVERY columns\n"
    "      --tube-radius M     the tubes' radius in metres (default: 1/300 of the\n"
    "                          domain's larger side; arrows 0.6 of it)\n"
    "                          (these need the wind in the file; frames are raycast)\n"
    "  -r, --renderer NAME     raycast (default), shearwarp (faster; frames whose eye\n"
    "                          is inside the volume are raycast) or gl (the raycaster\n"
    "                          on the GPU, OpenGL 3.3 through EGL: no display needed)\n"
    "      --gpu-mb N          the GPU raycaster's brick memory (default 512)\n"
    "      --threads N         render threads (default: all cores)\n"
    "      --movie OUT.mp4     a movie of the selected steps (default: all) through ffmpeg\n"
    "                          (H.264; the container follows the extension), -o optional\n"
    "      --fps N             movie frames per second (default 12)\n"
    "      --no-annotate       the bare image: no time, colour bars, scale, graticule\n"
    "                          or outlines\n"
    "      --annotate PARTS    only these: time,bars,exaggeration,scale,graticule,\n"
    "                          outlines (default: all; outlines need gmt-gshhg-low)\n"
    "  -q, --quiet             no progress\n"
    VSV_CLI_CACHE_DIR_HELP
    "  -h, --help              this help\n"
    "  -V, --version           print versions\n";
/* clang-format on */

static int write_png(const char *path, const float *rgba, int w, int h, const float bg[3], char *err, size_t cap)
{
    unsigned char *rgb = malloc((size_t)w * h * 3);
    if (!rgb) {
        snprintf(err, cap, "%s: out of memory", path);
        return -1;
    }
    vsv_image_rgb8(rgba, w, h, bg, rgb);
    const int rc = vsv_png_write(path, rgb, w, h, err, cap);
    free(rgb);
    return rc;
}

/* clang-format off */ /* (a table, laid out by hand) */
enum { O_TIMES = 1000, O_TF, O_SIZE, O_BG, O_NOTERRAIN, O_THREADS, O_LOOKAT, O_STEREO, O_MOVIE, O_FPS, O_VIEW, O_RANGE, O_COLORMAP, O_LOG, O_LIGHT, O_NOLIGHT, O_SLICE, O_SLICESP, O_SLICECM, O_NOANNOT, O_ANNOT, O_GPUMB, O_SLICERANGE, O_ISO, O_TRAJ, O_SEEDLINE, O_SEEDSLICE, O_TRAJFROM, O_TRAJFOR, O_BARBS, O_TUBER, O_STREAM };
/* "R,G,B", each from 0 to 1, nothing after; 0 or -1. */
static int parse_rgb(const char *s, float rgb[3])
{
    for (int i = 0; i < 3; i++) {
        char *end;
        errno = 0;
        const double v = strtod(s, &end);
        if (errno || end == s || !(v >= 0 && v <= 1) || *end != (i < 2 ? ',' : '\0'))
            return -1;
        rgb[i] = (float)v;
        s = end + 1;
    }
    return 0;
}

static const struct option longopts[] = {
    {"output", required_argument, 0, 'o'},     {"time", required_argument, 0, 't'},
    {"times", required_argument, 0, O_TIMES},  {"species", required_argument, 0, 's'},
    {"tf", required_argument, 0, O_TF},        {"camera", required_argument, 0, 'c'},
    {"size", required_argument, 0, O_SIZE},    {"exaggerate", required_argument, 0, 'x'},
    {"background", required_argument, 0, O_BG}, {"no-terrain", no_argument, 0, O_NOTERRAIN},
    {"renderer", required_argument, 0, 'r'},   {"threads", required_argument, 0, O_THREADS},
    {"look-at", required_argument, 0, O_LOOKAT}, {"stereo", no_argument, 0, O_STEREO},
    {"movie", required_argument, 0, O_MOVIE},  {"fps", required_argument, 0, O_FPS},
    {"quiet", no_argument, 0, 'q'},            {"help", no_argument, 0, 'h'}, {"cache-dir", required_argument, 0, VSV_CLI_CACHE_DIR},
    {"view", required_argument, 0, O_VIEW},    {"range", required_argument, 0, O_RANGE},
    {"colormap", required_argument, 0, O_COLORMAP}, {"log", required_argument, 0, O_LOG},
    {"light", optional_argument, 0, O_LIGHT},  {"no-light", no_argument, 0, O_NOLIGHT},
    {"slice", required_argument, 0, O_SLICE},  {"slice-species", required_argument, 0, O_SLICESP},
    {"slice-colormap", required_argument, 0, O_SLICECM}, {"gpu-mb", required_argument, 0, O_GPUMB},
    {"slice-range", required_argument, 0, O_SLICERANGE}, {"iso", required_argument, 0, O_ISO},
    {"no-annotate", no_argument, 0, O_NOANNOT}, {"annotate", required_argument, 0, O_ANNOT},
    {"trajectory", required_argument, 0, O_TRAJ}, {"seed-line", required_argument, 0, O_SEEDLINE},
    {"seed-slice", required_argument, 0, O_SEEDSLICE}, {"traj-from", required_argument, 0, O_TRAJFROM},
    {"traj-for", required_argument, 0, O_TRAJFOR}, {"barbs", required_argument, 0, O_BARBS},
    {"tube-radius", required_argument, 0, O_TUBER}, {"streamlines", no_argument, 0, O_STREAM},
    {"version", no_argument, 0, 'V'},          {0, 0, 0, 0}};
/* clang-format on */

/* The command line, parsed and checked (main). */
typedef struct render_args {
    const char *out, *time, *times, *species, *tfpath, *movie_out, *path;
    int fps, width, height, terrain, lookat, stereo, plan, nchanges, nslice_specs, light, sequence;
    size_t gpu_mb;
    double az, el, dist, exag, sun_az, sun_el, la[6], slice_range[2]; /* --slice-range, else each frame's own */
    float bg[3];
    const char *slice_specs[8], *slice_species, *slice_cmap;
    const char *iso_specs[VSV_SCENE_ISO_MAX]; /* --iso, parsed against the file in make_layers */
    int niso;
    vsv_tf_change changes[64]; /* --colormap, --log, --range */
    vsv_flow_opts flow;        /* --trajectory, --barbs, ... */
    unsigned parts;
    vsv_render_opts ro;
} render_args;

/* One run: the file, its steps, layers, scene and camera, and what draws them (main). */
typedef struct render_run {
    vsv_file *f;
    const vsv_meta *m;
    vsv_meta placed; /* m at the frame's time (vsv_meta_placed: shallow) */
    int a, b, nl, slice_layer, ow, exr;
    vsv_layer *layers;
    vsv_tf *tfs, slice_tf;
    vsv_volume **vols;
    int *sidx;
    float *opac; /* per species: its layer's opacity, -1 when not drawn */
    vsv_slice slices[8];
    vsv_scene_iso isos[VSV_SCENE_ISO_MAX];
    vsv_scene sc;
    vsv_camera cam;
    double sep, mn[3], mx[3];
    vsv_movie mv;
    unsigned char *rgb8;
    vsv_font *font;
    vsv_outlines *outlines;
    vsv_annot annot;
    vsv_renderer *r;
    vsv_gl_context *glc;
    vsv_gl *gl;
    vsv_flow *flow;                   /* trajectories and wind arrows, or NULL */
    float *rgba, *depth, *img, *zimg; /* a frame's buffers (here: reachable at an exit on an error) */
} render_run;

/* Reads the options into ra (set to the defaults by main); 1 after --help. */
static int parse_args(int argc, char **argv, render_args *ra)
{
    int c;
    argv[0] = (char *)vsv_cli_tool(); /* getopt's messages name the tool as ours do */
    while ((c = getopt_long(argc, argv, "o:t:s:c:x:r:qhV", longopts, NULL)) != -1) {
        long v;
        switch (c) {
        case 'o': ra->out = optarg; break;
        case 't': ra->time = optarg; break;
        case O_TIMES: ra->times = optarg; break;
        case 's': ra->species = optarg; break;
        case O_TF: ra->tfpath = optarg; break;
        case 'c': {
            int n = sscanf(optarg, "%lf,%lf,%lf", &ra->az, &ra->el, &ra->dist);
            if (n < 2 || !(ra->el > -90 && ra->el < 90) || ra->dist < 0)
                vsv_cli_usage_error("--camera %s: expected AZ,EL[,DIST] with -90 < EL < 90", optarg);
            ra->plan = 0;
            break;
        }
        case O_RANGE:
        case O_COLORMAP:
        case O_LOG: {
            char msg[512];
            const char *opt = c == O_RANGE ? "range" : c == O_LOG ? "log" : "colormap";
            if (ra->nchanges >= 64)
                vsv_cli_usage_error("--%s: at most 64 colour and scale changes", opt);
            if (vsv_tf_change_parse(opt, optarg, &ra->changes[ra->nchanges++], msg, sizeof msg))
                vsv_cli_usage_error("%s", msg);
            break;
        }
        case O_VIEW:
            if ((ra->plan = vsv_view_preset(optarg, &ra->az, &ra->el)) < 0)
                vsv_cli_usage_error("--view %s: plan, south, west or oblique", optarg);
            ra->dist = 0;
            break;
        case O_SIZE:
            vsv_cli_size(optarg, (const int[2]){1, 1}, (const int[2]){16384, 16384}, &ra->width, &ra->height);
            break;
        case 'x':
            if (vsv_cli_double(optarg, &ra->exag) || !(ra->exag > 0) || ra->exag > VSV_MAX_EXAGGERATION)
                vsv_cli_usage_error("--exaggerate %s: a number above 0 and at most %d", optarg, VSV_MAX_EXAGGERATION);
            break;
        case O_BG:
            if (parse_rgb(optarg, ra->bg))
                vsv_cli_usage_error("--background %s: expected R,G,B, each from 0 to 1", optarg);
            break;
        case O_NOTERRAIN: ra->terrain = 0; break;
        case O_LIGHT:
            ra->light = 1;
            if (optarg && vsv_sun_parse(optarg, &ra->sun_az, &ra->sun_el))
                vsv_cli_usage_error("--light=%s: expected AZ,EL in degrees with -90 <= EL <= 90", optarg);
            break;
        case O_NOLIGHT: ra->light = 0; break;
        case O_SLICE:
            if (ra->nslice_specs >= 8)
                vsv_cli_usage_error("--slice %s: at most 8 slices", optarg);
            ra->slice_specs[ra->nslice_specs++] = optarg;
            break;
        case O_SLICESP: ra->slice_species = optarg; break;
        case O_ISO:
            if (ra->niso >= VSV_SCENE_ISO_MAX)
                vsv_cli_usage_error("--iso %s: at most %d isosurfaces", optarg, VSV_SCENE_ISO_MAX);
            ra->iso_specs[ra->niso++] = optarg;
            break;
        case O_SLICECM: {
            int known = 0;
            for (const char *const *cm = vsv_tf_colormaps(); *cm; cm++)
                known |= !strcmp(*cm, optarg);
            if (!known)
                vsv_cli_usage_error("--slice-colormap %s: not a colour map name", optarg);
            ra->slice_cmap = optarg;
            break;
        }
        case O_SLICERANGE: {
            int used = 0;
            if (sscanf(optarg, "%lf:%lf%n", &ra->slice_range[0], &ra->slice_range[1], &used) != 2 || optarg[used] ||
                !(ra->slice_range[0] < ra->slice_range[1]) || !isfinite(ra->slice_range[0]) ||
                !isfinite(ra->slice_range[1]))
                vsv_cli_usage_error("--slice-range %s: expected LO:HI with LO < HI", optarg);
            break;
        }
        case O_NOANNOT: ra->parts = 0; break;
        case O_ANNOT: {
            char msg[300];
            if (vsv_annot_parse(optarg, &ra->parts, msg, sizeof msg))
                vsv_cli_usage_error("%s", msg);
            break;
        }
        case O_LOOKAT:
            if (sscanf(optarg, "%lf,%lf,%lf,%lf,%lf,%lf", &ra->la[0], &ra->la[1], &ra->la[2], &ra->la[3], &ra->la[4],
                       &ra->la[5]) != 6 ||
                (ra->la[0] == ra->la[3] && ra->la[1] == ra->la[4] && ra->la[2] == ra->la[5]))
                vsv_cli_usage_error("--look-at %s: expected EX,EY,EZ,TX,TY,TZ with distinct eye and target", optarg);
            ra->lookat = 1;
            break;
        case O_STEREO: ra->stereo = 1; break;
        case O_MOVIE: ra->movie_out = optarg; break;
        case O_FPS:
            if (vsv_cli_int(optarg, 1, 240, &v))
                vsv_cli_usage_error("--fps %s: 1..240", optarg);
            ra->fps = (int)v;
            break;
        case 'r':
            if (!strcmp(optarg, "raycast"))
                ra->ro.kind = VSV_RENDER_RAYCAST;
            else if (!strcmp(optarg, "shearwarp"))
                ra->ro.kind = VSV_RENDER_SHEARWARP;
            else if (!strcmp(optarg, "gl"))
                ra->ro.kind = VSV_RENDER_GL;
            else
                vsv_cli_usage_error("--renderer %s: raycast, shearwarp or gl", optarg);
            break;
        case O_GPUMB:
            if (vsv_cli_int(optarg, 16, 1 << 20, &v))
                vsv_cli_usage_error("--gpu-mb %s: a whole number of megabytes, 16 to %d", optarg, 1 << 20);
            ra->gpu_mb = (size_t)v;
            break;
        case O_THREADS:
            if (vsv_cli_int(optarg, 1, 64, &v))
                vsv_cli_usage_error("--threads %s: 1..64", optarg);
            ra->ro.threads = (int)v;
            break;
        case 'q': vsv_cli_set_quiet(1); break;
        case VSV_CLI_CACHE_DIR: vsv_cli_cache_dir(optarg); break;
        case 'h': fputs(usage, stdout); return 1;
        case 'V': vsv_cli_version();
        case O_TRAJ:
        case O_SEEDLINE:
        case O_SEEDSLICE:
        case O_TRAJFROM:
        case O_TRAJFOR:
        case O_BARBS:
        case O_TUBER:
        case O_STREAM: {
            char msg[512];
            for (int i = 0; longopts[i].name; i++)
                if (longopts[i].val == c && vsv_flow_opt(&ra->flow, longopts[i].name, optarg, msg, sizeof msg))
                    vsv_cli_usage_error("%s", msg);
            break;
        }
        default: vsv_cli_getopt_failed();
        }
    }
    return 0;
}

/* The options that go together, the output names and the one input (ra->path, ra->sequence). */
static void check_args(int argc, char **argv, render_args *ra)
{
    if (!ra->out && !ra->movie_out)
        vsv_cli_usage_error("no output image (-o OUT.png) or movie (--movie OUT.mp4)");
    if (optind != argc - 1)
        vsv_cli_usage_error("one .vsv file");
    if (ra->time && ra->times)
        vsv_cli_usage_error("--time and --times exclude each other");
    if (ra->out) { /* the format is the extension's: never PNG bytes in a .jpg */
        const char *dot = strrchr(ra->out, '.'), *slash = strrchr(ra->out, '/');
        if (!dot || (slash && dot < slash) || (strcasecmp(dot, ".png") && strcasecmp(dot, ".exr")))
            vsv_cli_usage_error("-o %s: the image format comes from the extension: .png or .exr", ra->out);
    }
    ra->sequence = ra->out ? vsv_cli_pattern(ra->out) : 0;
    if (ra->sequence < 0)
        vsv_cli_usage_error("-o %s: a '%%' in the name must be %%d or %%0Nd (the frame number, once) or %%%% (a "
                            "percent sign)",
                            ra->out);
    ra->path = argv[optind];
    const char *const ins[2] = {ra->path, ra->tfpath};
    if (ra->out && !ra->sequence)
        vsv_cli_refuse_input(ra->out, ins, 2);
    vsv_cli_refuse_input(ra->movie_out, ins, 2);
}

/* Opens the file and selects its steps, run->a..run->b; no frame's name may be an input. */
static void open_steps(const render_args *ra, render_run *run)
{
    const char *path = ra->path, *out = ra->out;
    const char *const ins[2] = {path, ra->tfpath};
    if (vsv_file_open_any(path, &vsv_cli_http, &run->f))
        vsv_cli_die(1, "%s", vsv_file_error(run->f));
    run->m = vsv_file_meta(run->f);
    vsv_file_info info;
    vsv_file_info_get(run->f, &info);
    vsv_cli_steps(run->f, path, ra->time, ra->times, ra->sequence || ra->movie_out, &run->a, &run->b);
    const int a = run->a, b = run->b;
    if (a < 0 || b >= info.nsteps || a > b)
        vsv_cli_die(1, "%s: no step selected (the file has steps 0..%d)", path, info.nsteps - 1);
    if (out && !ra->sequence && a != b)
        vsv_cli_usage_error("several steps need %%04d in the output name");
    for (int t = a; ra->sequence && t <= b; t++) { /* every name, before any is written */
        char name[4096];
        if (vsv_cli_pattern_name(out, t - a, name, sizeof name))
            vsv_cli_usage_error("-o %s: the name is too long", out);
        vsv_cli_refuse_input(name, ins, 2);
    }
}

/* The layers: the species asked for (all by default) with their opacities and transfer functions, and the slices'. */
static void make_layers(const render_args *ra, render_run *run)
{
    const vsv_meta *m = run->m;
    const char *path = ra->path, *species = ra->species, *tfpath = ra->tfpath;
    vsv_layer *layers = run->layers = calloc((size_t)m->nvars, sizeof *layers);
    vsv_tf *tfs = run->tfs = calloc((size_t)m->nvars, sizeof *tfs);
    vsv_volume **vols = run->vols = calloc((size_t)m->nvars, sizeof *vols);
    int *sidx = run->sidx = calloc((size_t)m->nvars, sizeof *sidx);
    float *opac = run->opac = calloc((size_t)m->nvars, sizeof *opac);
    if (!layers || !tfs || !vols || !sidx || !opac)
        vsv_cli_die(1, "out of memory");
    for (int s = 0; s < m->nvars; s++) /* -1: not drawn */
        opac[s] = !species && vsv_meta_default_shown(m, s) ? 1 : -1;
    for (int i = 0; i < ra->nchanges; i++)
        if (vsv_meta_find_var(m, ra->changes[i].species) < 0)
            vsv_cli_usage_error("--%.*s: %s has no species '%s'", (int)strcspn(ra->changes[i].line, " "),
                                !strncmp(ra->changes[i].line, "scale", 5) ? "log" : ra->changes[i].line, path,
                                ra->changes[i].species);
    char why[512];
    const int src = species ? vsv_species_parse(m, species, path, opac, why, sizeof why) : 0;
    if (src == VSV_ENOMEM)
        vsv_cli_die(1, "%s", why);
    if (src)
        vsv_cli_usage_error("%s", why);
    int slice_var = -1;
    const char *slice_species = ra->slice_species;
    if (ra->nslice_specs) { /* the slices' species: named, or the first drawn */
        for (int s = 0; s < m->nvars && slice_var < 0 && !slice_species; s++)
            slice_var = opac[s] >= 0 ? s : -1;
        if (slice_species && (slice_var = vsv_meta_find_var(m, slice_species)) < 0)
            vsv_cli_usage_error("--slice-species: %s has no species '%s'", path, slice_species);
        if (slice_var < 0)
            vsv_cli_usage_error("--slice: no species to colour the slices (--slice-species NAME)");
    }
    vsv_iso_spec iso[VSV_SCENE_ISO_MAX];
    for (int i = 0; i < ra->niso; i++) { /* their species are loaded, drawn or not */
        char msg[1024];
        if (vsv_iso_parse(m, ra->iso_specs[i], &iso[i], msg, sizeof msg))
            vsv_cli_usage_error("%s", msg);
        if (vsv_iso_in_range(run->f, ra->iso_specs[i], &iso[i], msg, sizeof msg))
            vsv_cli_die(1, "%s: %s", path, msg);
    }
    int nl = 0, slice_layer = 0;
    for (int s = 0; s < m->nvars; s++) {
        int iso_var = 0;
        for (int i = 0; i < ra->niso; i++)
            if (iso[i].species == s) {
                run->isos[i] = (vsv_scene_iso){nl, iso[i].value, {iso[i].rgb[0], iso[i].rgb[1], iso[i].rgb[2]}};
                iso_var = 1;
            }
        if (opac[s] < 0 && s != slice_var && !iso_var)
            continue;
        char msg[512];
        const int trc = vsv_tf_for_species(run->f, s, tfpath, &tfs[nl], msg, sizeof msg);
        if (trc == VSV_EIO)
            vsv_cli_die(1, "%s", msg);
        if (trc)
            vsv_cli_die(1, "%s: %s", tfpath ? tfpath : path, msg);
        for (int i = 0; i < ra->nchanges; i++) /* --colormap, --log, --range: in the order given */
            if (!strcmp(ra->changes[i].species, m->vars[s].name) &&
                vsv_tf_change_apply(&tfs[nl], &ra->changes[i], msg, sizeof msg))
                vsv_cli_usage_error("%s", msg);
        if (vsv_volume_create(run->f, &vols[nl]))
            vsv_cli_die(1, "out of memory");
        layers[nl] = (vsv_layer){vols[nl], &tfs[nl], opac[s] >= 0 ? opac[s] : 0, opac[s] >= 0};
        if (s == slice_var)
            slice_layer = nl;
        sidx[nl++] = s;
    }
    run->nl = nl;
    run->slice_layer = slice_layer;
}

/* The slices, the scene and the camera (with the stereo eyes' separation, run->sep). */
static void make_scene(const render_args *ra, render_run *run)
{
    const int nslice_specs = ra->nslice_specs, width = ra->width, height = ra->height;
    for (int i = 0; i < nslice_specs; i++) {
        char msg[512];
        if (vsv_slice_parse(run->m, ra->slice_specs[i], &run->slices[i], msg, sizeof msg))
            vsv_cli_usage_error("--%s in %s", msg, ra->path);
    }
    vsv_tf *slice_tf = &run->slice_tf;
    *slice_tf = run->tfs[run->slice_layer]; /* the species' range and scale, the slices' colour map */
    snprintf(slice_tf->colormap, sizeof slice_tf->colormap, "%s", ra->slice_cmap);
    if (isfinite(ra->slice_range[0]))
        slice_tf->lo = ra->slice_range[0], slice_tf->hi = ra->slice_range[1];
    if (nslice_specs && vsv_tf_prepare(slice_tf))
        vsv_cli_die(1, "%s: the slices' colours cannot be made", ra->path);
    vsv_scene *sc = &run->sc;
    *sc = (vsv_scene){.meta = run->m,
                      .layers = run->layers,
                      .nlayers = run->nl,
                      .exaggeration = ra->exag,
                      .show_terrain = ra->terrain,
                      .slices = run->slices,
                      .nslices = nslice_specs,
                      .slice_layer = run->slice_layer,
                      .slice_tf = slice_tf,
                      .isos = run->isos,
                      .nisos = ra->niso};
    if (ra->light)
        vsv_scene_sun(sc, ra->sun_az, ra->sun_el);
    if (!(ra->exag > 0))
        sc->exaggeration = vsv_scene_default_exaggeration(sc);
    vsv_camera *cam = &run->cam;
    if (ra->plan)
        vsv_camera_plan(cam, sc, width, height);
    else if (ra->dist > 0)
        vsv_camera_orbit(cam, sc, ra->az, ra->el, ra->dist, width, height);
    else
        vsv_camera_fit(cam, sc, ra->az, ra->el, width, height);
    if (ra->lookat) {
        for (int i = 0; i < 3; i++) {
            const double e = i == 2 ? sc->exaggeration : 1;
            cam->pos[i] = ra->la[i] * e;
            cam->dir[i] = (ra->la[3 + i] - ra->la[i]) * e;
        }
    }
    /* stereo: two eyes a thirtieth of the viewing distance apart */
    double target[3] = {0, 0, 0};
    vsv_scene_bounds(sc, run->mn, run->mx);
    for (int i = 0; i < 3; i++)
        target[i] = 0.5 * (run->mn[i] + run->mx[i]) - cam->pos[i];
    run->sep = sqrt(target[0] * target[0] + target[1] * target[1] + target[2] * target[2]) / 30;
    char msg[1024];
    if (vsv_flow_any(&ra->flow) && vsv_flow_open(run->f, &ra->flow, &run->flow, msg, sizeof msg))
        vsv_cli_die(1, "%s: %s", ra->path, msg);
}

/* Starts the movie, loads the annotation's font and outlines and starts the renderer. */
static void start_drawing(const render_args *ra, render_run *run)
{
    const char *out = ra->out, *movie_out = ra->movie_out;
    const int width = ra->width, height = ra->height, ow = run->ow = ra->stereo ? 2 * width : width;
    run->exr = out && strlen(out) > 4 && !strcasecmp(out + strlen(out) - 4, ".exr");
    run->rgb8 = movie_out ? malloc((size_t)ow * height * 3) : NULL;
    if (movie_out) {
        if (!run->rgb8)
            vsv_cli_die(1, "out of memory");
        signal(SIGPIPE, SIG_IGN); /* a dying ffmpeg is an error, not a signal */
        vsv_movie_open(&run->mv, movie_out, ow, height, ra->fps);
    }
    /* annotation: the font and, for a map, the outlines (a note, not an
     * error, where a package is missing) */
    if (ra->parts) {
        char note[1200];
        if (vsv_annot_load(run->m, ra->parts, width, height, run->mx[0] - run->mn[0], !vsv_cli_quiet(), &run->font,
                           &run->outlines, note, sizeof note))
            vsv_cli_die(1, "%s", note);
        vsv_cli_notes(note);
    }
    const char *base = strrchr(ra->path, '/') ? strrchr(ra->path, '/') + 1 : ra->path;
    run->annot = (vsv_annot){ra->parts, run->font, 0, base, run->sidx, run->outlines, NULL, NULL};
    if (ra->plan && ra->parts && !ra->lookat) { /* the map framed inside the legend's margins */
        int inset[4];
        vsv_annotate_insets(&run->annot, &run->sc, width, height, inset);
        vsv_camera_plan_inset(&run->cam, &run->sc, width, height, inset);
    }
    if (ra->ro.kind == VSV_RENDER_GL) { /* asked for: no context is misuse of this machine, exit 2 */
        char why[1024];
        vsv_gl_opts go;
        vsv_gl_opts_init(&go);
        go.threads = ra->ro.threads;
        if (ra->gpu_mb)
            go.budget = ra->gpu_mb << 20;
        if (vsv_gl_context_create(&run->glc, why, sizeof why) || vsv_gl_create(&go, &run->gl, why, sizeof why))
            vsv_cli_usage_error("--renderer gl: %s", why);
    } else if (vsv_renderer_create(&ra->ro, &run->r)) {
        vsv_cli_die(1, "cannot start the renderer");
    }
}

/* Renders every selected step, each frame to a listed temporary name (staged, 4200 bytes a frame) and the movie. */
static void render_frames(const render_args *ra, render_run *run, char *staged)
{
    const char *out = ra->out, *path = ra->path;
    const int width = ra->width, height = ra->height, ow = run->ow, stereo = ra->stereo, a = run->a;
    vsv_tf *slice_tf = &run->slice_tf;
    vsv_gl *const gl = run->gl;
    vsv_decoder *d = NULL;
    float *rgba = run->rgba = malloc((size_t)width * height * 4 * sizeof(float));
    float *depth = run->depth = malloc((size_t)width * height * sizeof(float));
    float *img = run->img = malloc((size_t)ow * height * 4 * sizeof(float));
    float *zimg = run->zimg = malloc((size_t)ow * height * sizeof(float));
    if (vsv_decoder_create(run->f, &d) || !rgba || !depth || !img || !zimg)
        vsv_cli_die(1, "out of memory");
    for (int t = a; t <= run->b; t++) {
        run->placed = vsv_meta_placed(run->m, vsv_file_time(run->f, t)); /* a moving nest where it is then */
        run->sc.meta = &run->placed;
        for (int l = 0; l < run->nl; l++)
            if (vsv_volume_load(run->vols[l], d, t, run->sidx[l]))
                vsv_cli_die(1, "%s", vsv_decoder_error(d));
        char msg[1024];
        if (run->flow && vsv_flow_frame(run->flow, t, 1, 1, &run->sc.lines, &run->sc.nlines, msg, sizeof msg))
            vsv_cli_die(1, "%s: step %d: %s", path, t, msg);
        double slo, shi; /* the slices' own range in this frame */
        if (ra->nslice_specs && !isfinite(ra->slice_range[0]) && !vsv_slice_range(&run->sc, &slo, &shi)) {
            if (slice_tf->scale == VSV_SCALE_LOG)
                slo = slo > 0 ? slo : shi * 1e-6;
            if (!(shi > slo))
                shi = slo + (slo ? fabs(slo) * 1e-6 : 1e-30);
            slice_tf->lo = slo, slice_tf->hi = shi;
            if (vsv_tf_prepare(slice_tf))
                vsv_cli_die(1, "%s: the slices' colours cannot be made", path);
        }
        for (int eye = 0; eye < (stereo ? 2 : 1); eye++) {
            run->cam.eye_offset = stereo ? (eye ? run->sep / 2 : -run->sep / 2) : 0;
            int rc = gl ? vsv_gl_render(gl, &run->sc, &run->cam, rgba, depth)
                        : vsv_render(run->r, &run->sc, &run->cam, rgba, depth);
            if (rc) /* (out of memory, mostly: the renderers fail of nothing else) */
                vsv_cli_die(1, "%s: rendering step %d: %s", path, t, gl ? vsv_gl_error(gl) : vsv_strerror(rc));
            vsv_annot an = run->annot;
            an.time = vsv_file_time(run->f, t);
            if (ra->parts && (rc = vsv_annotate(&an, &run->sc, &run->cam, rgba, depth)))
                vsv_cli_die(1, "%s: annotating step %d: %s", path, t, vsv_strerror(rc));
            for (int y = 0; y < height; y++) {
                memcpy(img + 4 * ((size_t)y * ow + (size_t)eye * width), rgba + 4 * (size_t)y * width,
                       4 * sizeof(float) * (size_t)width);
                memcpy(zimg + (size_t)y * ow + (size_t)eye * width, depth + (size_t)y * width,
                       sizeof(float) * (size_t)width);
            }
        }
        char name[4096], err[4200];
        if (out && vsv_cli_pattern_name(out, t - a, name, sizeof name))
            vsv_cli_die(1, "-o %s: the name is too long", out);
        if (out) {
            /* each frame complete under a listed temporary name; all are
             * renamed into place only when the whole run has succeeded */
            char *tmp = staged + (size_t)(t - a) * 4200;
            const int fd = vsv_output_temp(name, NULL, tmp, 4200);
            if (fd < 0)
                vsv_cli_die(1, "%s: cannot create: %s", name, strerror(errno));
            close(fd);
            if (run->exr ? vsv_exr_write(tmp, img, zimg, ow, height, err, sizeof err)
                         : write_png(tmp, img, ow, height, ra->bg, err, sizeof err)) {
                const size_t n = strlen(tmp);
                vsv_cli_die(1, "%s%s", name, !strncmp(err, tmp, n) ? err + n : err);
            }
        }
        if (ra->movie_out) {
            vsv_image_rgb8(img, ow, height, ra->bg, run->rgb8);
            vsv_movie_frame(&run->mv, run->rgb8, ow, height);
        }
        vsv_cli_progress("vsv-render", t - a + 1, run->b - a + 1);
    }
    free(rgba);
    free(depth);
    free(img);
    free(zimg);
    vsv_decoder_free(d);
}

/* Everything written: into place (a sequence appears all at once, a signal waits for it). */
static void publish_outputs(const render_args *ra, render_run *run, const char *staged)
{
    const char *out = ra->out, *movie_out = ra->movie_out;
    if (movie_out)
        vsv_movie_close(&run->mv);
    vsv_cli_hold_signals(1);
    for (int t = run->a; out && t <= run->b; t++) {
        char name[4096];
        if (vsv_cli_pattern_name(out, t - run->a, name, sizeof name))
            vsv_cli_die(1, "-o %s: the name is too long", out);
        if (vsv_output_publish(staged + (size_t)(t - run->a) * 4200, name))
            vsv_cli_die(1, "%s: cannot rename into place: %s", name, strerror(errno));
    }
    if (movie_out && vsv_output_publish(run->mv.tmp, movie_out))
        vsv_cli_die(1, "%s: cannot rename into place: %s", movie_out, strerror(errno));
    vsv_cli_hold_signals(0);
}

int main(int argc, char **argv)
{
    vsv_cli_init("vsv-render");
    render_args ra = {.fps = 12,
                      .az = 225,
                      .el = 30,
                      .bg = {0.02f, 0.03f, 0.06f},
                      .width = 800,
                      .height = 600,
                      .terrain = 1,
                      .slice_cmap = "viridis",
                      .slice_range = {NAN, NAN},
                      .sun_az = 315,
                      .sun_el = 45,
                      .parts = VSV_ANNOT_ALL};
    vsv_render_opts_init(&ra.ro);
    if (parse_args(argc, argv, &ra))
        return 0;
    check_args(argc, argv, &ra);
    render_run run = {0};
    open_steps(&ra, &run);
    make_layers(&ra, &run);
    make_scene(&ra, &run);
    start_drawing(&ra, &run);
    char *staged = ra.out ? calloc((size_t)(run.b - run.a + 1), 4200) : NULL; /* the frames' temporary names */
    if (ra.out && !staged)
        vsv_cli_die(1, "out of memory");
    render_frames(&ra, &run, staged);
    publish_outputs(&ra, &run, staged);
    free(staged);
    free(run.rgb8);
    if (!vsv_cli_quiet() && !isatty(2))
        fprintf(stderr, "vsv-render: %d frame%s, %dx%d, exaggeration %g%s%s\n", run.b - run.a + 1,
                run.b > run.a ? "s" : "", ra.width, ra.height, run.sc.exaggeration, ra.movie_out ? ", movie " : "",
                ra.movie_out ? ra.movie_out : "");
    vsv_flow_free(run.flow);
    vsv_renderer_free(run.r);
    vsv_gl_free(run.gl);
    vsv_gl_context_free(run.glc);
    vsv_font_free(run.font);
    vsv_outlines_free(run.outlines);
    for (int l = 0; l < run.nl; l++)
        vsv_volume_free(run.vols[l]);
    free(run.vols);
    free(run.tfs);
    free(run.layers);
    free(run.sidx);
    free(run.opac);
    vsv_file_free(run.f);
    return 0;
}
