/* vsv-play-freevr — vsv-play on an immersive display through FreeVR (a CAVE,
 * a single wall, or FreeVR's desktop simulator). Built with
 * `make FREEVR_DIR=DIR freevr` against a FreeVR install; `make test` builds
 * it against the project's stand-in (tests/freevr-standin/) and checks its
 * syntax against viewer/freevr/freevr.h.
 *
 * FreeVR forks one render process per `visren` process of its configuration,
 * so a brick cache cannot be shared: each render process opens the file and
 * runs its own pager and renderer (the budget split between them), while the
 * main process reads the wand, runs the clock and publishes the play state,
 * under a lock, in FreeVR's shared arena. Each eye of each wall is rendered
 * with the frustum FreeVR loaded for it and drawn on a billboard inside that
 * frustum's near/far range, in FreeVR's units (feet).
 *
 * Arguments: those starting with '-' are ours, one other is the file, and
 * any containing one of ; = " { } is FreeVR configuration, handed to
 * vrConfigure untouched. Everything that can fail on our side (options, the
 * file, species) is checked before vrConfigure creates FreeVR's semaphores;
 * after it, every exit goes through vrExit. */
#include "vsv_cli.h"
#include "vsv_common.h"
#include "vsv_freevr_conf.h"
#include "vsv_overlay.h"
#include "vsv_player.h"

#include <GL/gl.h>
#include <errno.h>
#include <freevr.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

static const char usage[] =
    "Usage: vsv-play-freevr FILE.vsv|URL [OPTIONS] [FREEVR-CONFIGURATION...]\n"
    "Play a .vsv file in a CAVE, on a wall or in FreeVR's simulator. The volume\n"
    "stands 8 feet wide, its centre 4 feet up and 3 feet in front of the floor's\n"
    "centre. Wand: button 1 play/pause, 2 next species, 3 show/hide it; joystick\n"
    "right/left fast-forward/rewind, up/down its opacity; switch 0 (Escape in the\n"
    "simulator) quits.\n"
    "Reads .vsv files (vsv(5)), transfer-function files (--tf) and FreeVR's\n"
    "configuration (.freevrrc, $FREEVR, or strings given here); writes nothing.\n"
    "\n"
    "  -s, --species LIST      NAME[:OPACITY],... visible at start (default: all)\n"
    "      --tf FILE           transfer functions (as vsv-render)\n"
    "  -r, --renderer NAME     shearwarp (default) or raycast\n"
    "      --cache-mb N        decoded-brick budget, split between the render\n"
    "                          processes (default 1024)\n"
    "      --threads N         render threads per render process (default: all cores)\n"
    "      --render-scale F    render at F times each window's size (default 1)\n"
    "  -x, --exaggerate N      vertical exaggeration (default: as vsv-render)\n"
    "      --rate SECONDS      model seconds per wall second at x1 (default: 4 steps/s)\n"
    "      --loop[=on|off|bounce]  at the ends (--loop alone: on; default off)\n"
    "      --play              start playing\n"
    "      --no-terrain        do not draw the ground\n"
    VSV_CLI_CACHE_DIR_HELP
    "  -h, --help              this help\n"
    "  -V, --version           print versions\n"
    "\n"
    "FreeVR reads its configuration from $FREEVR_HOME/.freevrrc, ~/.freevrrc,\n"
    "./.freevrrc and the FREEVR variable (none: its simulator). An argument that\n"
    "contains any of ; = \" { } is FreeVR configuration and goes to FreeVR as it is,\n"
    "e.g. 'usesystem \"cave\";'. See vsv-play-freevr(1).\n";

/* the volume in the display: 8 feet wide, its centre 4 feet up, 3 feet in
 * front of the floor's centre (FreeVR's real-world frame: feet, y up, the
 * front wall at -z) */
static const double AT[3] = {0, 4, -3}, SIZE = 8;

/* what the render processes read, in FreeVR's shared arena */
typedef struct shared {
    vrLock lock;
    vsv_player_state st;
    int failed;     /* a render process could not go on: msg says why */
    char msg[1024];
} shared;

static shared *S;
static vsv_player_opts OPTS;
static size_t PER_PROCESS; /* each render process's cache budget */
static double SCALE = 1;
/* per render process (after the fork) */
static vsv_player *R;
static vsv_overlay *OV;

/* Reports a render process's error to the main process, which quits
 * through vrExit (a render process must not exit by itself: FreeVR would
 * wait for it and keep its semaphores). */
static void fail(const char *msg)
{
    vrLockWriteSet(S->lock);
    if (!S->failed) {
        S->failed = 1;
        snprintf(S->msg, sizeof S->msg, "%s", msg);
    }
    vrLockWriteRelease(S->lock);
}

/* Once per window; a render process that drives several windows keeps one
 * player (one cache) for them all. */
static int WINDOWS;

static void display_init(void)
{
    char err[1024];
    if (WINDOWS++)
        return;
    vsv_player_opts o = OPTS;
    o.cache_bytes = PER_PROCESS;
    if (vsv_player_open(&o, &R, err, sizeof err)) {
        vsv_player_free(R);
        R = NULL;
        fail(err);
        return;
    }
    if (!(OV = vsv_overlay_create(18, err, sizeof err)))
        fprintf(stderr, "%s: no status text: %s\n", vsv_cli_tool(), err);
}

static void display_exit(void)
{
    if (--WINDOWS > 0)
        return;
    vsv_overlay_free(OV);
    vsv_player_free(R);
    OV = NULL;
    R = NULL;
}

/* The depth (positive, in the projection's units) at which the billboard
 * lies: the volume's centre as this eye sees it, kept inside the near and
 * far planes of the projection P that FreeVR loaded. */
static double billboard_depth(const double P[16], const double MV[16])
{
    const double z = MV[2] * AT[0] + MV[6] * AT[1] + MV[10] * AT[2] + MV[14];
    double d = -z, n = 0.1, f = 1000;
    if (P[11] == -1 && P[10] != 1 && P[10] != -1) { /* glFrustum */
        n = P[14] / (P[10] - 1);
        f = P[14] / (P[10] + 1);
    }
    if (!(n > 0 && f > n))
        n = 0.1, f = 1000;
    if (!(d > n * 1.5))
        d = n * 1.5;
    if (d > f * 0.5)
        d = f * 0.5;
    return d;
}

static void display(vrRenderInfo *ri)
{
    (void)ri;
    const float *bg = R ? vsv_player_background(R) : NULL;
    /* FreeVR does not clear: old frames and stale depth would show */
    glClearColor(bg ? bg[0] : 0, bg ? bg[1] : 0, bg ? bg[2] : 0, 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    if (!R)
        return;
    char err[1024] = "";
    vsv_player_state st;
    vrLockReadSet(S->lock);
    st = S->st;
    const int failed = S->failed;
    vrLockReadRelease(S->lock);
    if (failed)
        return;
    if (vsv_player_state_apply(R, &st, err, sizeof err) || vsv_player_update(R, 0, 1)) {
        fail(err[0] ? err : vsv_player_error(R));
        return;
    }
    double P[16], MV[16];
    GLint vp[4];
    glGetDoublev(GL_PROJECTION_MATRIX, P);
    glGetDoublev(GL_MODELVIEW_MATRIX, MV);
    glGetIntegerv(GL_VIEWPORT, vp);
    if (vp[2] < 1 || vp[3] < 1)
        return;
    int w = (int)(vp[2] * SCALE + 0.5), h = (int)(vp[3] * SCALE + 0.5);
    w = w < 16 ? 16 : w, h = h < 16 ? 16 : h;
    vsv_camera cam;
    vsv_player_camera_from_gl(R, AT, SIZE, P, MV, w, h, &cam);
    const unsigned char *img = vsv_player_image(R, &cam, err, sizeof err);
    if (!img) {
        fail(err);
        return;
    }
    vsv_billboard_draw(&cam, billboard_depth(P, MV), img, w, h, 0);
    if (OV) {
        char status[2048];
        vsv_player_status(R, status, sizeof status);
        vsv_overlay_text(OV, vp[2], vp[3], 8, 8, status); /* at the top: the volume stands low */
    }
}

/* FreeVR's configuration strings among the arguments. */
static int is_freevr_arg(const char *a) { return a[0] != '-' && strpbrk(a, ";=\"{}") != NULL; }

/* A configuration file's text, or NULL when there is none; one that is
 * there but not a readable regular file (a FIFO would block) is an error. */
static char *slurp(const char *dir, const char *name)
{
    if (!dir || !dir[0])
        return NULL;
    char path[4096], why[256];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    struct stat st;
    if (stat(path, &st) && errno == ENOENT)
        return NULL;
    FILE *fp = vsv_input_fopen(path, "r", why, sizeof why);
    if (!fp)
        vsv_cli_die(1, "%s: %s", path, why);
    size_t cap = 1 << 16, n = 0, got;
    char *buf = malloc(cap + 1);
    while (buf && (got = fread(buf + n, 1, cap - n, fp)) > 0) {
        n += got;
        if (n == cap) {
            char *more = realloc(buf, 2 * cap + 1);
            if (!more) {
                free(buf);
                buf = NULL;
                break;
            }
            buf = more, cap *= 2;
        }
    }
    fclose(fp);
    if (buf)
        buf[n] = 0;
    return buf;
}

enum { O_TF = 1000, O_CACHE, O_THREADS, O_SCALE, O_RATE, O_LOOP, O_PLAY, O_NOTERRAIN };

int main(int argc, char **argv)
{
    vsv_cli_init("vsv-play-freevr");
    vsv_player_opts_init(&OPTS);
    /* ours (options and the file) apart from FreeVR's configuration strings */
    char **ours = calloc((size_t)argc + 1, sizeof *ours), **fv = calloc((size_t)argc + 1, sizeof *fv);
    if (!ours || !fv)
        vsv_cli_die(1, "out of memory");
    int nours = 0, nfv = 0;
    ours[nours++] = fv[nfv++] = argv[0];
    for (int i = 1; i < argc; i++) {
        if (is_freevr_arg(argv[i]))
            fv[nfv++] = argv[i];
        else
            ours[nours++] = argv[i];
    }
    static const struct option longopts[] = {
        {"species", required_argument, 0, 's'},       {"tf", required_argument, 0, O_TF},
        {"renderer", required_argument, 0, 'r'},      {"cache-mb", required_argument, 0, O_CACHE},
        {"threads", required_argument, 0, O_THREADS}, {"render-scale", required_argument, 0, O_SCALE},
        {"exaggerate", required_argument, 0, 'x'},    {"rate", required_argument, 0, O_RATE},
        {"loop", optional_argument, 0, O_LOOP},       {"play", no_argument, 0, O_PLAY},
        {"no-terrain", no_argument, 0, O_NOTERRAIN},  {"help", no_argument, 0, 'h'}, {"cache-dir", required_argument, 0, VSV_CLI_CACHE_DIR},
        {"version", no_argument, 0, 'V'},             {0, 0, 0, 0}};
    size_t budget = (size_t)1 << 30;
    int c;
    while ((c = getopt_long(nours, ours, "s:r:x:hV", longopts, NULL)) != -1) {
        long v;
        double d;
        switch (c) {
        case 's': OPTS.species = optarg; break;
        case O_TF: OPTS.tfpath = optarg; break;
        case 'r':
            if (!strcmp(optarg, "raycast"))
                OPTS.renderer = VSV_RENDER_RAYCAST;
            else if (!strcmp(optarg, "shearwarp"))
                OPTS.renderer = VSV_RENDER_SHEARWARP;
            else
                vsv_cli_usage_error("--renderer: raycast or shearwarp, not '%s'", optarg);
            break;
        case O_CACHE:
            if (vsv_cli_int(optarg, 16, 1 << 30, &v))
                vsv_cli_usage_error("--cache-mb %s: a whole number of megabytes, 16 to %d", optarg, 1 << 30);
            budget = (size_t)v << 20;
            break;
        case O_THREADS:
            if (vsv_cli_int(optarg, 1, 64, &v))
                vsv_cli_usage_error("--threads: 1..64");
            OPTS.threads = (int)v;
            break;
        case O_SCALE:
            if (vsv_cli_double(optarg, &SCALE) || !(SCALE >= 0.05 && SCALE <= 4))
                vsv_cli_usage_error("--render-scale: 0.05..4");
            break;
        case 'x':
            if (vsv_cli_double(optarg, &d) || !(d > 0))
                vsv_cli_usage_error("--exaggerate: a number > 0");
            OPTS.exaggerate = d;
            break;
        case O_RATE:
            if (vsv_cli_double(optarg, &d) || !(d > 0))
                vsv_cli_usage_error("--rate: model seconds per wall second, > 0");
            OPTS.rate = d;
            break;
        case O_LOOP:
            OPTS.loop = !optarg || !strcmp(optarg, "on") ? VSV_CLOCK_LOOP
                        : !strcmp(optarg, "bounce")      ? VSV_CLOCK_BOUNCE
                                                         : VSV_CLOCK_STOP;
            if (optarg && !OPTS.loop && strcmp(optarg, "off"))
                vsv_cli_usage_error("--loop: on, off or bounce");
            break;
        case O_PLAY: OPTS.play = 1; break;
        case O_NOTERRAIN: OPTS.terrain = 0; break;
        case VSV_CLI_CACHE_DIR: vsv_cli_cache_dir(optarg); break;
        case 'h':
            fputs(usage, stdout);
            free(ours);
            free(fv);
            return 0;
        case 'V': vsv_cli_version();
        default: vsv_cli_usage_error("see --help");
        }
    }
    if (optind != nours - 1)
        vsv_cli_usage_error(optind < nours ? "one file at a time (FreeVR configuration strings contain ; = \" { or })"
                                           : "no input file");
    OPTS.path = ours[optind];
    OPTS.http = &vsv_cli_http;
    /* the main process's player: clock and settings only; opening it checks
     * the file and the species before FreeVR starts anything */
    vsv_player_opts io = OPTS;
    io.clock_only = 1;
    vsv_player *in = NULL;
    char err[1024];
    const int orc = vsv_player_open(&io, &in, err, sizeof err);
    if (orc == VSV_EINVAL) /* an option the file cannot have: misuse, as in vsv-play */
        vsv_cli_usage_error("%s", err);
    if (orc)
        vsv_cli_die(1, "%s", err);
    /* the layout FreeVR will start, read from what FreeVR reads */
    char *owned[3] = {slurp(getenv("FREEVR_HOME"), ".freevrrc"), slurp(getenv("HOME"), ".freevrrc"),
                      slurp(".", ".freevrrc")};
    const char **texts = calloc((size_t)nfv + 4, sizeof *texts);
    if (!texts)
        vsv_cli_die(1, "out of memory");
    int nt = 0;
    for (int i = 0; i < 3; i++)
        texts[nt++] = owned[i];
    texts[nt++] = getenv("FREEVR");
    for (int i = 1; i < nfv; i++)
        texts[nt++] = fv[i];
    vsv_freevr_layout lay;
    vsv_freevr_layout_count(texts, nt, &lay);
    free(texts);
    for (int i = 0; i < 3; i++)
        free(owned[i]);
    PER_PROCESS = budget / (size_t)lay.visren;
    vrShmemInit(vsv_freevr_arena_bytes(&lay, sizeof(shared)));
    fv[nfv] = NULL;
    vrConfigure(&nfv, fv, NULL);
    /* from here on every exit goes through vrExit */
    int status = 0;
    S = vrShmemAlloc0(sizeof *S);
    if (!S) {
        vrExit();
        vsv_cli_die(1, "FreeVR's shared memory is full (%lu bytes for %d windows)",
                    vsv_freevr_arena_bytes(&lay, sizeof(shared)), lay.windows);
    }
    S->lock = vrLockCreate();
    vsv_player_state_get(in, &S->st);
    vrInputSet2switchDescription(1, "play / pause");
    vrInputSet2switchDescription(2, "next species");
    vrInputSet2switchDescription(3, "show / hide the species");
    vrCallbackSet(VRFUNC_DISPLAY_INIT, "vsv_display_init", display_init, 0);
    vrCallbackSet(VRFUNC_DISPLAY, "vsv_display", display, 0);
    vrCallbackSet(VRFUNC_DISPLAY_EXIT, "vsv_display_exit", display_exit, 0);
    vrStart();
    double last = vrCurrentSimTime();
    int stick = 0; /* joystick x: -1, 0, +1 (edges trigger) */
    while (vrFrame()) {
        vrLockReadSet(S->lock);
        const int failed = S->failed;
        vrLockReadRelease(S->lock);
        if (failed) {
            status = 1;
            break;
        }
        const double now = vrCurrentSimTime();
        if (vrGet2switchDelta(1) > 0)
            vsv_player_do(in, "toggle-play", err, sizeof err);
        if (vrGet2switchDelta(2) > 0)
            vsv_player_do(in, "select +1", err, sizeof err);
        if (vrGet2switchDelta(3) > 0)
            vsv_player_do(in, "toggle", err, sizeof err);
        const float jx = vrGetValuatorValue(0), jy = vrGetValuatorValue(1);
        const int sx = jx > 0.8f ? 1 : jx < -0.8f ? -1 : 0;
        if (sx && sx != stick)
            vsv_player_do(in, sx > 0 ? "forward" : "rewind", err, sizeof err);
        stick = sx;
        if (jy > 0.2f || jy < -0.2f) {
            char act[64];
            snprintf(act, sizeof act, "opacity - %+.3f", 0.5 * jy * (now - last));
            vsv_player_do(in, act, err, sizeof err);
        }
        vsv_player_tick(in, now - last);
        last = now;
        vsv_player_state st;
        vsv_player_state_get(in, &st);
        vrLockWriteSet(S->lock);
        S->st = st;
        vrLockWriteRelease(S->lock);
        /* the input arrives at FreeVR's poll rate (about 60 Hz): no need to
         * spin, the render processes want the cores */
        nanosleep(&(struct timespec){0, 5000000}, NULL);
    }
    char msg[sizeof S->msg];
    snprintf(msg, sizeof msg, "%s", S->msg);
    vrExit();
    vsv_player_free(in);
    free(ours);
    free(fv);
    if (status)
        vsv_cli_die(1, "%s", msg);
    return 0;
}
