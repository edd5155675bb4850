/* vsv-play — play a .vsv file in a desktop window (GLFW + OpenGL): the
 * rendered image on a billboard at the volume's position, keys and mouse
 * for time, species and camera, and --script for playback without a
 * person. */
#include "vsv_cli.h"
#include "vsv_gl.h"
#include "vsv_overlay.h"
#include "vsv_player.h"

#include <GLFW/glfw3.h>
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

/* clang-format off */ /* (the help text as it prints, a line a line) */
static const char usage[] =
    "Usage: vsv-play FILE.vsv|URL [OPTIONS]\n"
    "Play a .vsv file in a window: play, pause, step, rewind and fast-forward through\n"
    "time, show, hide and fade each species, orbit, pan and zoom. Press h in the\n"
    "window for the keys.\n"
    "Reads .vsv files (vsv(5)), transfer-function files (--tf) and timed scripts\n"
    "(--script); writes PNG screenshots (p, or the script's screenshot FILE.png): the\n"
    "picture without the status lines, annotated as vsv-render's frames are.\n"
    "\n"
    "  -s, --species LIST      NAME[:OPACITY],... visible at start (default: all but\n"
    "                          water vapour and the wind's components)\n"
    "      --tf FILE           transfer functions (as vsv-render)\n"
    "  -r, --renderer NAME     auto (default: gl where OpenGL 3.3 runs on a GPU, else\n"
    "                          shearwarp), shearwarp (fast on a CPU), raycast\n"
    "                          (detail) or gl (the raycaster on the GPU); m switches\n"
    "      --gpu-mb N          the GPU raycaster's brick memory (default 512)\n"
    "      --cache-mb N        decoded-brick cache budget (default: a quarter of RAM)\n"
    "      --threads N         render threads (default: all cores)\n"
    "      --size WxH          window size (default 960x600; 16x16 to 16384x16384)\n"
    "      --render-scale F    render at F times the window size (default 1)\n"
    "  -x, --exaggerate N      vertical exaggeration (default: as vsv-render)\n"
    "      --rate SECONDS      model seconds per wall second at x1 (default: 4 steps/s)\n"
    "      --loop on|off|bounce  at the ends (default off: stop)\n"
    "      --play              start playing\n"
    "      --no-terrain        do not draw the ground\n"
    "      --view NAME         start in a view: plan, south, west or oblique (default)\n"
    "      --light[=AZ,EL]     start lit: gradient shading, sun at AZ,EL (default\n"
    "                          315,45); g switches it\n"
    "      --slice SPEC        a section, as vsv-render: z=HEIGHT, lat=DEG, lon=DEG\n"
    "                          or line=LAT1,LON1:LAT2,LON2 (repeatable); c switches\n"
    VSV_PLAYER_TF_HELP
    VSV_PLAYER_ISO_HELP
    VSV_PLAYER_FLOW_HELP
    "      --slice-species NAME, --slice-colormap NAME, --slice-range LO:HI\n"
    "                          as vsv-render (the slices coloured over the range\n"
    "                          of what they show in the step shown, or LO:HI)\n"
    "  screenshots:\n"
    "      --no-annotate       the bare picture: no time, colour bars, scale,\n"
    "                          graticule or outlines\n"
    "      --annotate PARTS    only these: time,bars,exaggeration,scale,graticule,\n"
    "                          outlines (default: all, as vsv-render)\n"
    "      --script FILE       timed actions, one per line: SECONDS ACTION [ARGS]\n"
    "                          (see vsv-play(1)); quit exits 0\n"
    "  -q, --quiet             no messages\n"
    VSV_CLI_CACHE_DIR_HELP
    "  -h, --help              this help\n"
    "  -V, --version           print versions\n";
/* clang-format on */

typedef struct script_line {
    double at;
    int line;
    char action[1024];
} script_line;

static script_line *load_script(const char *path, int *n)
{
    FILE *fp = vsv_cli_open_input(path, "r", 0);
    script_line *v = NULL;
    int cap = 0, ln = 0;
    char buf[1200];
    *n = 0;
    while (fgets(buf, sizeof buf, fp)) {
        ln++;
        char *s = buf + strspn(buf, " \t");
        if (*s == '#' || *s == '\n' || !*s)
            continue;
        char *end;
        const double at = strtod(s, &end);
        if (end == s || !(at >= 0) || (*end != ' ' && *end != '\t'))
            vsv_cli_die(1, "%s: line %d: expected SECONDS ACTION [ARGS]", path, ln);
        end += strspn(end, " \t");
        end[strcspn(end, "\r\n")] = 0;
        if (*n == cap) {
            cap = cap ? 2 * cap : 16;
            v = realloc(v, (size_t)cap * sizeof *v);
            if (!v)
                vsv_cli_die(1, "out of memory");
        }
        if (*n && at < v[*n - 1].at)
            vsv_cli_die(1, "%s: line %d: times must not go backwards", path, ln);
        v[*n].at = at;
        v[*n].line = ln;
        snprintf(v[*n].action, sizeof v[*n].action, "%s", end);
        (*n)++;
    }
    fclose(fp);
    return v;
}

typedef struct app {
    vsv_player *p;
    GLFWwindow *win;
    double mx, my;
    int drag; /* 1 orbit, 2 pan */
    int shots;
    long frames, late, stalled; /* drawn while playing; of them, behind the clock's step; still the last one's */
    long waits;                 /* frames that waited for their step's bricks */
    double waited;              /* the longest wait, seconds */
    int last_shown, last_clock;
} app;

static void run(app *a, const char *action)
{
    char err[512];
    if (vsv_player_do(a->p, action, err, sizeof err) && !vsv_cli_quiet())
        fprintf(stderr, "vsv-play: %s\n", err);
}

static void on_key(GLFWwindow *w, int key, int scancode, int act, int mods)
{
    app *a = glfwGetWindowUserPointer(w);
    (void)scancode;
    if (act == GLFW_RELEASE)
        return;
    char buf[64];
    switch (key) {
    case GLFW_KEY_SPACE: run(a, "toggle-play"); break;
    case GLFW_KEY_RIGHT: run(a, "step +1"); break;
    case GLFW_KEY_LEFT: run(a, "step -1"); break;
    case GLFW_KEY_F: run(a, "forward"); break;
    case GLFW_KEY_R: run(a, "rewind"); break;
    case GLFW_KEY_EQUAL:
    case GLFW_KEY_KP_ADD: run(a, "faster"); break;
    case GLFW_KEY_MINUS:
    case GLFW_KEY_KP_SUBTRACT: run(a, "slower"); break;
    case GLFW_KEY_L: run(a, "loop"); break;
    case GLFW_KEY_HOME: run(a, "start"); break;
    case GLFW_KEY_END: run(a, "end"); break;
    case GLFW_KEY_TAB: run(a, mods & GLFW_MOD_SHIFT ? "select -1" : "select +1"); break;
    case GLFW_KEY_V: run(a, "toggle"); break;
    case GLFW_KEY_UP: run(a, "opacity - +0.1"); break;
    case GLFW_KEY_DOWN: run(a, "opacity - -0.1"); break;
    case GLFW_KEY_M: run(a, "renderer switch"); break;
    case GLFW_KEY_F2: run(a, "view plan"); break;
    case GLFW_KEY_F3: run(a, "view south"); break;
    case GLFW_KEY_F4: run(a, "view west"); break;
    case GLFW_KEY_F5: run(a, "view oblique"); break;
    case GLFW_KEY_G: run(a, "light"); break;
    case GLFW_KEY_C: run(a, "slices"); break;
    case GLFW_KEY_W: run(a, "wind"); break;
    case GLFW_KEY_P:
        snprintf(buf, sizeof buf, "screenshot vsv-play-%04d.png", a->shots++);
        run(a, buf);
        break;
    case GLFW_KEY_H:
    case GLFW_KEY_F1: run(a, "help"); break;
    case GLFW_KEY_Q:
    case GLFW_KEY_ESCAPE: run(a, "quit"); break;
    default:
        if (key >= GLFW_KEY_1 && key <= GLFW_KEY_9) {
            snprintf(buf, sizeof buf, "select #%d", key - GLFW_KEY_1);
            run(a, buf);
        }
    }
}

static void on_button(GLFWwindow *w, int button, int act, int mods)
{
    app *a = glfwGetWindowUserPointer(w);
    glfwGetCursorPos(w, &a->mx, &a->my);
    a->drag = act != GLFW_PRESS ? 0 : button == GLFW_MOUSE_BUTTON_RIGHT || (mods & GLFW_MOD_SHIFT) ? 2 : 1;
}

static void on_move(GLFWwindow *w, double x, double y)
{
    app *a = glfwGetWindowUserPointer(w);
    if (!a->drag)
        return;
    int ww, wh;
    glfwGetWindowSize(w, &ww, &wh);
    char buf[96];
    if (a->drag == 1)
        snprintf(buf, sizeof buf, "orbit %g %g", -(x - a->mx) * 0.3, (y - a->my) * 0.3);
    else
        snprintf(buf, sizeof buf, "pan %g %g", (x - a->mx) / ww, -(y - a->my) / wh);
    run(a, buf);
    a->mx = x, a->my = y;
}

static void on_scroll(GLFWwindow *w, double dx, double dy)
{
    app *a = glfwGetWindowUserPointer(w);
    (void)dx;
    char buf[64];
    snprintf(buf, sizeof buf, "zoom %g", pow(1.1, dy));
    run(a, buf);
}

/* The window's picture (the back buffer just drawn) to PNG. */
static void screenshot(const char *path, int w, int h)
{
    unsigned char *px = malloc((size_t)w * h * 3), *flip = malloc((size_t)w * h * 3);
    char err[512];
    if (!px || !flip)
        vsv_cli_die(1, "out of memory");
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, w, h, GL_RGB, GL_UNSIGNED_BYTE, px);
    for (int y = 0; y < h; y++) /* GL rows go up */
        memcpy(flip + (size_t)y * w * 3, px + (size_t)(h - 1 - y) * w * 3, (size_t)w * 3);
    if (vsv_png_write(path, flip, w, h, err, sizeof err))
        vsv_cli_die(1, "%s", err);
    if (!vsv_cli_quiet())
        fprintf(stderr, "vsv-play: wrote %s (%dx%d)\n", path, w, h);
    free(px);
    free(flip);
}

/* The rendered picture on its billboard over the background. */
static void draw_picture(const vsv_player *p, const vsv_camera *cam, const double mn[3], const double mx[3],
                         const unsigned char *img)
{
    const float *bg = vsv_player_background(p);
    glClearColor(bg[0], bg[1], bg[2], 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    vsv_billboard_draw(cam, vsv_billboard_depth(cam, mn, mx), img, cam->width, cam->height, 1);
}

static void glfw_error(int code, const char *what)
{
    (void)code;
    if (!vsv_cli_quiet())
        fprintf(stderr, "vsv-play: GLFW: %s\n", what);
}

/* The command line as parsed: the player's options and the window's own. */
typedef struct play_args {
    vsv_player_opts po;
    int width, height;
    int want; /* the renderer asked for: -1 auto */
    double scale;
    const char *script, *view;
    unsigned parts;
} play_args;

/* The command line into *o (usage errors exit 2); 1 when --help was printed. */
static int parse_args(int argc, char **argv, play_args *o)
{
    /* clang-format off */ /* (a table, laid out by hand) */
    enum {
        O_TF = 1000, O_CACHE, O_THREADS, O_SIZE, O_SCALE, O_RATE, O_LOOP, O_PLAY, O_NOTERRAIN, O_SCRIPT,
        O_VIEW, O_LIGHT, O_SLICE, O_SLICESP, O_SLICECM, O_NOANNOT, O_ANNOT, O_GPUMB, O_SLICERANGE,
        O_FLOW
    };
    static const struct option longopts[] = {
        {"species", required_argument, 0, 's'},    {"tf", required_argument, 0, O_TF},
        {"renderer", required_argument, 0, 'r'},   {"cache-mb", required_argument, 0, O_CACHE},
        {"gpu-mb", required_argument, 0, O_GPUMB},
        {"threads", required_argument, 0, O_THREADS}, {"size", required_argument, 0, O_SIZE},
        {"render-scale", required_argument, 0, O_SCALE}, {"exaggerate", required_argument, 0, 'x'},
        {"rate", required_argument, 0, O_RATE},    {"loop", required_argument, 0, O_LOOP},
        {"play", no_argument, 0, O_PLAY},          {"no-terrain", no_argument, 0, O_NOTERRAIN},
        {"script", required_argument, 0, O_SCRIPT}, {"quiet", no_argument, 0, 'q'},
        {"help", no_argument, 0, 'h'}, {"cache-dir", required_argument, 0, VSV_CLI_CACHE_DIR},             {"version", no_argument, 0, 'V'},
        {"view", required_argument, 0, O_VIEW},    {"light", optional_argument, 0, O_LIGHT},
        {"slice", required_argument, 0, O_SLICE},  {"slice-species", required_argument, 0, O_SLICESP},
        {"slice-colormap", required_argument, 0, O_SLICECM},
        {"slice-range", required_argument, 0, O_SLICERANGE},
        {"no-annotate", no_argument, 0, O_NOANNOT}, {"annotate", required_argument, 0, O_ANNOT},
        {"colormap", required_argument, 0, O_FLOW}, {"log", required_argument, 0, O_FLOW},
        {"range", required_argument, 0, O_FLOW},  {"iso", required_argument, 0, O_FLOW},
        VSV_PLAYER_FLOW_LONGOPTS(O_FLOW),          {0, 0, 0, 0}};
    /* clang-format on */
    vsv_player_opts po;
    vsv_player_opts_init(&po);
    int width = 960, height = 600, c;
    int want = -1; /* the renderer asked for: -1 auto */
    double scale = 1;
    const char *script = NULL, *view = NULL;
    unsigned parts = VSV_ANNOT_ALL;
    int li = 0;
    argv[0] = (char *)vsv_cli_tool(); /* getopt's messages name the tool as ours do */
    while ((c = getopt_long(argc, argv, "s:r:x:qhV", longopts, &li)) != -1) {
        long v;
        double d;
        switch (c) {
        case 's': po.species = optarg; break;
        case O_TF: po.tfpath = optarg; break;
        case O_FLOW: { /* --colormap, --log, --range, --iso, the wind: vsv_player_option */
            char msg[512];
            if (vsv_player_option(&po, longopts[li].name, optarg, msg, sizeof msg))
                vsv_cli_usage_error("%s", msg);
            break;
        }
        case 'r':
            if (!strcmp(optarg, "raycast"))
                want = VSV_RENDER_RAYCAST;
            else if (!strcmp(optarg, "shearwarp"))
                want = VSV_RENDER_SHEARWARP;
            else if (!strcmp(optarg, "gl"))
                want = VSV_RENDER_GL;
            else if (!strcmp(optarg, "auto"))
                want = -1;
            else
                vsv_cli_usage_error("--renderer: auto, shearwarp, raycast or gl, not '%s'", optarg);
            break;
        case O_GPUMB:
            if (vsv_cli_int(optarg, 16, 1 << 20, &v))
                vsv_cli_usage_error("--gpu-mb %s: a whole number of megabytes, 16 to %d", optarg, 1 << 20);
            po.gpu_budget = (size_t)v << 20;
            break;
        case O_CACHE:
            if (vsv_cli_int(optarg, 1, 1 << 30, &v))
                vsv_cli_usage_error("--cache-mb %s: a whole number of megabytes, 1 to %d", optarg, 1 << 30);
            po.cache_bytes = (size_t)v << 20;
            break;
        case O_THREADS:
            if (vsv_cli_int(optarg, 1, 64, &v))
                vsv_cli_usage_error("--threads: 1..64");
            po.threads = (int)v;
            break;
        case O_SIZE: vsv_cli_size(optarg, (const int[2]){16, 16}, (const int[2]){16384, 16384}, &width, &height); break;
        case O_SCALE:
            if (vsv_cli_double(optarg, &scale) || !(scale >= 0.05 && scale <= 4))
                vsv_cli_usage_error("--render-scale: 0.05..4");
            break;
        case 'x':
            if (vsv_cli_double(optarg, &d) || !(d > 0) || d > VSV_MAX_EXAGGERATION)
                vsv_cli_usage_error("--exaggerate %s: a number above 0 and at most %d", optarg, VSV_MAX_EXAGGERATION);
            po.exaggerate = d;
            break;
        case O_RATE:
            if (vsv_cli_double(optarg, &d) || !(d > 0))
                vsv_cli_usage_error("--rate: model seconds per wall second, > 0");
            po.rate = d;
            break;
        case O_LOOP:
            po.loop = !strcmp(optarg, "on") ? VSV_CLOCK_LOOP : !strcmp(optarg, "bounce") ? VSV_CLOCK_BOUNCE : 0;
            if (!po.loop && strcmp(optarg, "off"))
                vsv_cli_usage_error("--loop: on, off or bounce");
            break;
        case O_PLAY: po.play = 1; break;
        case O_NOTERRAIN: po.terrain = 0; break;
        case O_SCRIPT: script = optarg; break;
        case O_VIEW: {
            double az, el;
            if (vsv_view_preset(optarg, &az, &el) < 0)
                vsv_cli_usage_error("--view %s: plan, south, west or oblique", optarg);
            view = optarg;
            break;
        }
        case O_LIGHT:
            po.light = 1;
            if (optarg && vsv_sun_parse(optarg, &po.sun_az, &po.sun_el))
                vsv_cli_usage_error("--light=%s: expected AZ,EL in degrees with -90 <= EL <= 90", optarg);
            break;
        case O_SLICE:
            if (po.nslices >= 8)
                vsv_cli_usage_error("--slice %s: at most 8 slices", optarg);
            po.slices[po.nslices++] = optarg;
            break;
        case O_SLICESP: po.slice_species = optarg; break;
        case O_SLICECM: po.slice_colormap = optarg; break;
        case O_SLICERANGE: {
            int used = 0;
            if (sscanf(optarg, "%lf:%lf%n", &po.slice_range[0], &po.slice_range[1], &used) != 2 || optarg[used] ||
                !(po.slice_range[0] < po.slice_range[1]) || !isfinite(po.slice_range[0]) ||
                !isfinite(po.slice_range[1]))
                vsv_cli_usage_error("--slice-range %s: expected LO:HI with LO < HI", optarg);
            break;
        }
        case O_NOANNOT: parts = 0; break;
        case O_ANNOT: {
            char msg[300];
            if (vsv_annot_parse(optarg, &parts, msg, sizeof msg))
                vsv_cli_usage_error("%s", msg);
            break;
        }
        case 'q': vsv_cli_set_quiet(1); break;
        case VSV_CLI_CACHE_DIR: vsv_cli_cache_dir(optarg); break;
        case 'h': fputs(usage, stdout); return 1;
        case 'V': vsv_cli_version();
        default: vsv_cli_getopt_failed();
        }
    }
    if (optind != argc - 1)
        vsv_cli_usage_error(optind < argc ? "one file at a time" : "no input file");
    po.path = argv[optind];
    po.http = &vsv_cli_http;
    *o = (play_args){po, width, height, want, scale, script, view, parts};
    return 0;
}

/* The player opened, the script's lines tried first on the clock and state alone; dies on errors. */
static vsv_player *open_player(const play_args *o, const script_line *lines, int nscript)
{
    vsv_player *p = NULL;
    char err[1024];
    vsv_player_opts co = o->po;
    co.clock_only = 1;
    int orc = lines ? vsv_player_open(&co, &p, err, sizeof err) : 0;
    for (int i = 0; !orc && i < nscript; i++)
        if (vsv_player_do(p, lines[i].action, err, sizeof err))
            vsv_cli_die(1, "%s: line %d: %s", o->script, lines[i].line, err);
    vsv_player_free(p);
    p = NULL;
    if (!orc)
        orc = vsv_player_open(&o->po, &p, err, sizeof err);
    if (orc == VSV_EINVAL)
        vsv_cli_usage_error("%s", err);
    if (orc)
        vsv_cli_die(1, "%s", err);
    if (o->view) {
        char act[64];
        snprintf(act, sizeof act, "view %s", o->view);
        vsv_player_do(p, act, err, sizeof err);
    }
    return p;
}

/* The script's first quit (its index), or -1 when it has none. */
static int quit_line(const script_line *lines, int n)
{
    for (int i = 0; i < n; i++)
        if (!strncmp(lines[i].action, "quit", 4) && (!lines[i].action[4] || strchr(" \t", lines[i].action[4])))
            return i;
    return -1;
}

typedef struct opening {
    const play_args *o;
    const script_line *lines;
    int nscript, done;
    vsv_player *p;
    pthread_mutex_t mu;
    pthread_cond_t cv;
} opening;

static void *open_job(void *arg)
{
    opening *g = arg;
    vsv_player *p = open_player(g->o, g->lines, g->nscript);
    pthread_mutex_lock(&g->mu);
    g->p = p, g->done = 1;
    pthread_cond_signal(&g->cv);
    pthread_mutex_unlock(&g->mu);
    return NULL;
}

/* open_player, on a thread of its own when the script quits: a file that is
 * still opening when the quit comes due, counted from `start` (a server that
 * stalls before the first byte of the file), ends the run there, said, exit
 * 1 (_exit: the thread is still inside the transfer; nothing is written
 * yet). */
static vsv_player *open_watched(const play_args *o, const script_line *lines, int nscript, struct timespec start)
{
    const int q = quit_line(lines, nscript);
    opening g = {o, lines, nscript, 0, NULL, PTHREAD_MUTEX_INITIALIZER, PTHREAD_COND_INITIALIZER};
    pthread_condattr_t ca;
    pthread_t th;
    if (q < 0 || pthread_condattr_init(&ca))
        return open_player(o, lines, nscript);
    pthread_condattr_setclock(&ca, CLOCK_MONOTONIC);
    const int ok = !pthread_cond_init(&g.cv, &ca);
    pthread_condattr_destroy(&ca);
    if (!ok || pthread_create(&th, NULL, open_job, &g))
        return open_player(o, lines, nscript);
    const double quit = lines[q].at;
    struct timespec due = start;
    due.tv_sec += (time_t)quit;
    due.tv_nsec += (long)((quit - floor(quit)) * 1e9);
    if (due.tv_nsec >= 1000000000L)
        due.tv_sec++, due.tv_nsec -= 1000000000L;
    pthread_mutex_lock(&g.mu);
    while (!g.done && pthread_cond_timedwait(&g.cv, &g.mu, &due) != ETIMEDOUT)
        ;
    const int done = g.done;
    pthread_mutex_unlock(&g.mu);
    if (!done) {
        fprintf(stderr, "vsv-play: %s: still opening when the script quit at %g s (line %d): nothing shown\n",
                o->po.path, quit, lines[q].line);
        fflush(stderr);
        _exit(1);
    }
    pthread_join(th, NULL);
    return g.p;
}

/* The renderer, once the window's OpenGL context is current: auto takes the GPU raycaster where OpenGL 3.3 runs
 * on a GPU. */
static void choose_renderer(vsv_player *p, int want)
{
    char err[1024];
    if (want == -1 && vsv_gl_context_software()) {
        if (!vsv_cli_quiet())
            fprintf(stderr,
                    "vsv-play: renderer: shear-warp (OpenGL here is %s, a software rasteriser: the CPU "
                    "renderers are faster; --renderer gl to use it anyway)\n",
                    (const char *)glGetString(GL_RENDERER));
    } else if (want == VSV_RENDER_GL || want == -1) {
        if (vsv_player_do(p, "renderer gl", err, sizeof err)) { /* err: "renderer gl: why" */
            if (want == VSV_RENDER_GL)
                vsv_cli_usage_error("--renderer gl: %s", err + strlen("renderer gl: "));
            if (!vsv_cli_quiet())
                fprintf(stderr, "vsv-play: renderer: shear-warp (the GPU raycaster cannot run: %s)\n",
                        err + strlen("renderer gl: "));
        }
    } else if (want != VSV_RENDER_SHEARWARP) {
        vsv_player_do(p, "renderer raycast", err, sizeof err);
    }
}

/* The font and outlines for annotated screenshots, kept between frames. */
typedef struct annot_cache {
    vsv_font *font;
    vsv_outlines *outlines;
    int font_h; /* the height they were loaded for */
} annot_cache;

/* The picture annotated (the font sized for it, the outlines loaded at the first screenshot), without the status
 * lines, drawn and written to path. */
static void annotated_screenshot(vsv_player *p, unsigned parts, annot_cache *ac, const vsv_camera *cam,
                                 const double mn[3], const double mx[3], const char *path, int fw, int fh)
{
    char err[1024];
    const int rw = cam->width, rh = cam->height;
    if (parts && ac->font_h != rh) { /* the first, or at a new size */
        char note[1200];
        vsv_font_free(ac->font);
        vsv_outlines_free(ac->outlines);
        if (vsv_annot_load(vsv_player_meta(p), parts, rw, rh, mx[0] - mn[0], !ac->font_h && !vsv_cli_quiet(), &ac->font,
                           &ac->outlines, note, sizeof note))
            vsv_cli_die(1, "%s", note);
        if (!ac->font_h)
            vsv_cli_notes(note);
        ac->font_h = rh;
    }
    const unsigned char *ann = vsv_player_annotated(p, parts, ac->font, ac->outlines, err, sizeof err);
    if (!ann)
        vsv_cli_die(1, "%s", err);
    draw_picture(p, cam, mn, mx, ann);
    screenshot(path, fw, fh);
}

/* The script's actions that are due, up to a screenshot: it takes the
 * picture of everything before it, nothing after. While one waits for its
 * step (a URL's, on its way), the due actions wait too, but a quit among
 * them runs at its time. */
static void run_due(vsv_player *p, const play_args *o, const script_line *lines, int nscript, int *next, double elapsed,
                    int shot_waits)
{
    char err[1024];
    for (int i = *next; shot_waits && i < nscript && lines[i].at <= elapsed; i++)
        if (!strncmp(lines[i].action, "quit", 4) && !lines[i].action[4 + strspn(lines[i].action + 4, " \t\r\n")]) {
            vsv_player_do(p, "quit", err, sizeof err);
            return;
        }
    while (!shot_waits && *next < nscript && lines[*next].at <= elapsed) {
        if (vsv_player_do(p, lines[*next].action, err, sizeof err))
            vsv_cli_die(1, "%s: line %d: %s", o->script, lines[*next].line, err);
        ++*next;
        if (vsv_player_quit(p) || !strncmp(lines[*next - 1].action, "screenshot", 10))
            break;
    }
}

/* Says once on stderr a step newly found damaged (1 then), or one whose
 * transfer failed (a URL's: tried again). */
static int say_news(vsv_player *p, const play_args *o)
{
    const char *why, *how;
    char when[64];
    const int bad = vsv_player_damage(p, &why), stalled = vsv_player_stalled(p, &how);
    if (bad >= 0) { /* once per step; the status line keeps saying it */
        vsv_cal_format(vsv_meta_calendar(vsv_player_meta(p)), vsv_player_clock(p)->times[bad], when, sizeof when);
        fprintf(stderr, "vsv-play: %s: step %d (%s) is damaged, not drawn; playing on: %s\n", o->po.path, bad, when,
                why);
    }
    if (stalled >= 0 && !vsv_cli_quiet()) {
        vsv_cal_format(vsv_meta_calendar(vsv_player_meta(p)), vsv_player_clock(p)->times[stalled], when, sizeof when);
        fprintf(stderr, "vsv-play: %s: step %d (%s) not loaded yet, trying again: %s\n", o->po.path, stalled, when,
                how);
    }
    return bad >= 0;
}

/* The frame loop until the window closes or the player quits; the number of damaged steps met; *unshot: a
 * screenshot still waiting for its step then (said on stderr). */
static int play_loop(app *a, const play_args *o, const script_line *lines, int nscript, vsv_overlay *ov,
                     annot_cache *ac, int *unshot)
{
    vsv_player *p = a->p;
    char err[1024];
    const double t0 = glfwGetTime();
    double last = t0;
    int next = 0, ndamaged = 0, shot_waits = 0;
    char shot_path[1024];
    while (!glfwWindowShouldClose(a->win) && !vsv_player_quit(p)) {
        const double now = glfwGetTime();
        run_due(p, o, lines, nscript, &next, now - t0, shot_waits);
        if (vsv_player_quit(p))
            break;
        const char *shot = shot_waits ? NULL : vsv_player_take_screenshot(p);
        if (shot) {
            snprintf(shot_path, sizeof shot_path, "%s", shot);
            shot_waits = 1;
        }
        if (vsv_player_update(p, now - last, shot_waits))
            vsv_cli_die(1, "%s", vsv_player_error(p));
        ndamaged += say_news(p, o);
        last = now;
        if (vsv_player_clock(p)->playing) { /* late: not the clock's step; stalled: still the last frame's */
            const int shown = vsv_player_shown_step(p), clk = vsv_player_target_step(p);
            a->frames++;
            a->late += shown != clk;
            a->waits += vsv_player_waited(p) > 0;
            a->waited = fmax(a->waited, vsv_player_waited(p));
            a->stalled += shown != clk && shown == a->last_shown && clk != a->last_clock;
            a->last_shown = shown, a->last_clock = clk;
        }
        int fw, fh;
        glfwGetFramebufferSize(a->win, &fw, &fh);
        if (fw < 1 || fh < 1) {
            glfwWaitEventsTimeout(0.1);
            continue;
        }
        vsv_camera cam;
        const int rw = (int)fmax(16, lrint(fw * o->scale)), rh = (int)fmax(16, lrint(fh * o->scale));
        vsv_player_camera(p, rw, rh, &cam);
        const unsigned char *img = vsv_player_image(p, &cam, err, sizeof err);
        if (!img)
            vsv_cli_die(1, "%s", err);
        glViewport(0, 0, fw, fh);
        double mn[3], mx[3];
        vsv_player_bounds(p, mn, mx);
        /* the picture of the clock's step, once all of it is there */
        if (shot_waits && vsv_player_shown_step(p) == vsv_player_clock(p)->step && vsv_player_waiting(p, NULL) < 0) {
            annotated_screenshot(p, o->parts, ac, &cam, mn, mx, shot_path, fw, fh);
            shot_waits = 0;
        }
        draw_picture(p, &cam, mn, mx, img);
        char status[2048];
        vsv_player_status(p, status, sizeof status);
        vsv_overlay_text(ov, fw, fh, 8, -8, status);
        if (vsv_player_help_shown(p))
            vsv_overlay_text(ov, fw, fh, 8, 8, vsv_player_help_text());
        glfwSwapBuffers(a->win);
        /* nothing moves on screen while paused: sleep until input or a due action */
        if (vsv_player_clock(p)->playing)
            glfwPollEvents();
        else
            glfwWaitEventsTimeout(next < nscript ? fmax(0, fmin(0.1, lines[next].at - (glfwGetTime() - t0))) : 0.1);
    }
    if (shot_waits) {
        const char *why = NULL;
        const int t = vsv_player_waiting(p, &why);
        fprintf(stderr, "vsv-play: %s: screenshot %s not taken: step %d not loaded when the run ended%s%s\n",
                o->po.path, shot_path, t >= 0 ? t : vsv_player_clock(p)->step, why ? ": " : "", why ? why : "");
    }
    *unshot = shot_waits;
    return ndamaged;
}

int main(int argc, char **argv)
{
    struct timespec start;
    clock_gettime(CLOCK_MONOTONIC, &start);
    vsv_cli_init("vsv-play");
    play_args o;
    if (parse_args(argc, argv, &o))
        return 0;
    int nscript = 0;
    script_line *lines = o.script ? load_script(o.script, &nscript) : NULL;
    vsv_player *p = open_watched(&o, lines, nscript, start);
    char err[1024];
    glfwSetErrorCallback(glfw_error);
    if (!glfwInit())
        vsv_cli_die(1, "cannot open a window: no display (set DISPLAY, or run under xvfb-run)");
    glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
    char title[1100];
    snprintf(title, sizeof title, "vsv-play: %s", o.po.path);
    app a = {.p = p, .last_shown = -1, .last_clock = -1};
    if (!(a.win = glfwCreateWindow(o.width, o.height, title, NULL, NULL)))
        vsv_cli_die(1, "cannot open a window (OpenGL not available)");
    glfwMakeContextCurrent(a.win);
    glfwSwapInterval(1);
    glfwSetWindowUserPointer(a.win, &a);
    choose_renderer(p, o.want);
    glfwSetKeyCallback(a.win, on_key);
    glfwSetMouseButtonCallback(a.win, on_button);
    glfwSetCursorPosCallback(a.win, on_move);
    glfwSetScrollCallback(a.win, on_scroll);
    vsv_overlay *ov = vsv_overlay_create(15, err, sizeof err);
    if (!ov)
        vsv_cli_die(1, "%s", err);
    annot_cache ac = {NULL, NULL, 0};
    int rc = 0, unshot = 0;
    const int ndamaged = play_loop(&a, &o, lines, nscript, ov, &ac, &unshot);
    if (!vsv_cli_quiet()) {
        vsv_pager_stats st;
        vsv_player_pager_stats(p, &st);
        fprintf(stderr,
                "vsv-play: %llu bricks decoded (%.1f MB, %.2f s) from %llu payloads, %llu hits, %llu misses, %llu "
                "stalls, cache peak %.1f MiB of %.0f MiB\n",
                (unsigned long long)st.bricks_decoded, st.bytes_decoded / 1e6, st.decode_seconds,
                (unsigned long long)st.payloads_decoded, (unsigned long long)st.hits, (unsigned long long)st.misses,
                (unsigned long long)st.stalls, st.peak_bytes / 1048576.0, st.budget / 1048576.0);
        if (a.frames)
            fprintf(stderr,
                    "vsv-play: %ld frames drawn while playing: %ld late (the clock's step not decoded in time, an "
                    "earlier one shown), %ld of them stalled (the last frame's step again); %ld waited for their "
                    "step, at most %.0f ms\n",
                    a.frames, a.late, a.stalled, a.waits, 1e3 * a.waited);
        if (st.transfer_failures)
            fprintf(stderr, "vsv-play: %s: %llu transfers failed (each tried again)\n", o.po.path,
                    (unsigned long long)st.transfer_failures);
    }
    if (ndamaged) { /* played past them, but the run did not show all of the file */
        fprintf(stderr, "vsv-play: %s: %d step%s damaged, not drawn\n", o.po.path, ndamaged, ndamaged > 1 ? "s" : "");
        rc = 1;
    }
    if (unshot) /* (said above) */
        rc = 1;
    vsv_overlay_free(ov);
    vsv_font_free(ac.font);
    vsv_outlines_free(ac.outlines);
    vsv_player_free(p); /* (its GPU raycaster in the window's context) */
    glfwDestroyWindow(a.win);
    glfwTerminate();
    free(lines);
    return rc;
}
