/* vsv-play-freevr — vsv-play on an immersive display through FreeVR (a CAVE,
 * a single wall, or FreeVR's desktop simulator). Built with
 * `make FREEVR_DIR=DIR freevr` against a FreeVR install; `make test` builds
 * it against the project's stand-in (tests/freevr-standin/) and checks its
 * syntax against viewer/freevr/freevr.h.
 *
 * FreeVR forks one render process per `visren` process of its
 * configuration. This main process reads the wand, runs the clock, decodes
 * every step once with the one pager, into shared memory the render
 * processes map (vsv_room.h), and publishes ticks: a step with its volumes
 * and the play state, the scene's placement, the wand and the panel. Every
 * window draws every tick, and the next tick waits until every window has
 * shown the current one, so all walls show the same model time and a slow
 * wall slows the room (vsv_freevr_draw.c draws them).
 *
 * Arguments: those starting with '-' are ours, one other is the file, and
 * any containing one of ; = " { } is FreeVR configuration, handed to
 * vrConfigure untouched. Everything that can fail on our side (options, the
 * file, species, a system the configuration does not define) is checked
 * before vrConfigure creates FreeVR's semaphores. After vrStart, SIGINT
 * (which FreeVR ignores), SIGTERM and SIGHUP end the run through vrExit;
 * a render process that dies ends it without vrExit (which would wait for
 * it forever): its siblings are ended and FreeVR's IPC objects removed. */
#include "vsv_cli.h"
#include "vsv_common.h"
#include "vsv_freevr_app.h"
#include "vsv_freevr_conf.h"
#include "vsv_panel.h"
#include "vsv_place.h"
#include "vsv_procs.h"
#include "vsv_wand.h"

#include <errno.h>
#include <fcntl.h>
#include <freevr.h>
#include <getopt.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

/* clang-format off */ /* (the help text as it prints, a line a line) */
static const char usage[] =
    "Usage: vsv-play-freevr FILE.vsv|URL [OPTIONS] [FREEVR-CONFIGURATION...]\n"
    "Play a .vsv file in a CAVE, on a wall or in FreeVR's simulator: every wall\n"
    "shows the same model time; the wand moves you through the scene.\n"
    "Reads .vsv files (vsv(5)), transfer-function files (--tf) and FreeVR's\n"
    "configuration (.freevrrc, $FREEVR, or strings given here); writes only --trace.\n"
    "\n"
    "  -s, --species LIST      NAME[:OPACITY],... visible at start (default: all\n"
    "                          but water vapour and the wind's components)\n"
    "      --tf FILE           transfer functions (as vsv-render)\n"
    VSV_PLAYER_TF_HELP
    VSV_PLAYER_ISO_HELP
    VSV_PLAYER_FLOW_HELP
    "  -r, --renderer NAME     auto (default: gl where OpenGL 3.3 runs on a GPU, else\n"
    "                          shearwarp), shearwarp, raycast, or gl: the raycaster on\n"
    "                          the GPU, each eye of each wall in its own frustum\n"
    "      --gpu-mb N          the GPU raycaster's brick memory a render process\n"
    "                          (default 512)\n"
    "      --place table|room  the domain on a table at waist height, sized to the\n"
    "                          room (default), or the room inside the clouds: its\n"
    "                          floor the ground, its ceiling the model's top\n"
    "      --cache-mb N        decoded-brick budget, one copy for every wall\n"
    "                          (default 1024)\n"
    "      --threads N         render threads per render process (default: all cores)\n"
    "      --render-scale F    render at F times each window's size (default 1)\n"
    "  -x, --exaggerate N      vertical exaggeration (default: as vsv-render)\n"
    "      --rate SECONDS      model seconds per wall second at x1 (default: 4 steps/s)\n"
    "      --loop[=on|off|bounce]  at the ends (--loop alone: on; default off)\n"
    "      --play              start playing\n"
    "      --no-terrain        do not draw the ground\n"
    "      --no-panel          no information panel on the front wall\n"
    "      --fps               the frame rate on the panel\n"
    "      --no-wand           do not draw the wand's pointer\n"
    "      --trace FILE        a line per window per frame: window frame tick step\n"
    "                          time seconds cpu pid (written when the run ends)\n"
    VSV_CLI_CACHE_DIR_HELP
    "  -h, --help              this help\n"
    "  -V, --version           print versions\n"
    "\n"
    "The wand (FreeVR's 2switches 1-3 and the joystick; the simulator: mouse\n"
    "buttons, and the pointer while space is held):\n";
/* clang-format on */

static const char usage_tail[] = "\n"
                                 "FreeVR reads its configuration from $FREEVR_HOME/.freevrrc, ~/.freevrrc,\n"
                                 "./.freevrrc and the FREEVR variable (none: its simulator). An argument that\n"
                                 "contains any of ; = \" { } is FreeVR configuration and goes to FreeVR as it is,\n"
                                 "e.g. 'usesystem \"cave\";'. See vsv-play-freevr(1).\n";

vsv_fv_app vsv_fv;

/* ----------------------------------------------------------- life cycle */

static volatile sig_atomic_t got_signal;
static vsv_ipc fv_ipc; /* the IPC objects FreeVR made */
static pid_t kids[64]; /* FreeVR's processes, as vrStart left them */
static volatile sig_atomic_t nkids;
static volatile sig_atomic_t end_status;

static void on_signal(int sig) { got_signal = sig; }

/* vrExit did not return: FreeVR's processes are killed and its IPC objects
 * removed here (async-signal-safe calls only). */
static void on_watchdog(int sig)
{
    (void)sig;
    static const char msg[] = "vsv-play-freevr: FreeVR did not end in time: its processes were killed\n";
    for (int i = 0; i < nkids; i++)
        kill(kids[i], SIGKILL);
    vsv_ipc_remove(&fv_ipc);
    vsv_output_cleanup();
    if (write(2, msg, sizeof msg - 1) < 0)
        _exit(1);
    _exit(end_status ? end_status : 1);
}

/* vrExit, which waits for FreeVR's processes to finish the frame they
 * draw, under a watchdog: 3 s after a signal (the run must end now), 20 s
 * otherwise (a frame of the GPU raycaster on a software rasteriser can take
 * seconds). */
static void freevr_exit(int status, int urgent)
{
    end_status = status;
    signal(SIGALRM, on_watchdog);
    alarm(urgent ? 3 : 20);
    vrExit();
    alarm(0);
    vsv_ipc_remove(&fv_ipc); /* (what FreeVR left; normally nothing) */
}

/* The trace: a temporary beside FILE, renamed into place at the end. */
static char trace_path[4096], trace_tmp[4200];

static void trace_open(const char *path)
{
    vsv_cli_refuse_input(path, NULL, 0);
    snprintf(trace_path, sizeof trace_path, "%s", path);
    const int fd = vsv_output_temp(path, NULL, trace_tmp, sizeof trace_tmp);
    if (fd < 0)
        vsv_cli_die(1, "%s: cannot create: %s", path, strerror(errno));
    /* the render processes append whole lines; this process alone ends it
     * (their signal handlers must not remove it) */
    vsv_output_forget(trace_tmp);
    fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_APPEND);
    static const char head[] = "# vsv-play-freevr trace: one line per window per frame\n"
                               "# window frame tick step time seconds cpu pid\n";
    if (write(fd, head, sizeof head - 1) != (ssize_t)(sizeof head - 1))
        vsv_cli_die(1, "%s: cannot write: %s", path, strerror(errno));
    vsv_fv.trace_fd = fd;
}

static void trace_close(void)
{
    if (vsv_fv.trace_fd < 0)
        return;
    if (vsv_output_seal(vsv_fv.trace_fd) || rename(trace_tmp, trace_path)) {
        fprintf(stderr, "%s: %s: cannot write the trace: %s\n", vsv_cli_tool(), trace_path, strerror(errno));
        unlink(trace_tmp);
    }
    vsv_fv.trace_fd = -1;
}

/* ------------------------------------------------------ configuration */

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

/* The layout FreeVR will start, read from what FreeVR reads. */
static void read_layout(char **fv, int nfv, vsv_freevr_layout *lay)
{
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
    vsv_freevr_layout_count(texts, nt, lay);
    free(texts);
    for (int i = 0; i < 3; i++)
        free(owned[i]);
}

/* ------------------------------------------------------------ main loop */

typedef struct run {
    vsv_player *dec; /* clock, actions, the one pager */
    vsv_freevr_layout lay;
    int kind; /* VSV_PLACE_* */
    double base[16], nav[16];
    vsv_wand wand;
    vsv_fv_tick last; /* published last */
    int last_step;
    const char *last_damage;
    int fps;             /* --fps */
    int panel;           /* draw the panel */
    vsv_panel *measure;  /* the panel's size (no GL) */
    double panel_at;     /* when it was sized last (monotonic seconds) */
    double lh, where[9]; /* its line height, corner and directions then */
} run;

static void place_base(run *r)
{
    double mn[3], mx[3];
    vsv_player_bounds(r->dec, mn, mx);
    vsv_place_base(r->kind, r->lay.room_lo, r->lay.room_hi, mn, mx, r->base);
}

/* The panel's line height (feet): 11 pixels on the windows that see it
 * (their lowest pixels a foot, as they report it), 0.2 feet at least, the
 * panel narrower than 0.9 of the room and lower than 0.8 of it; with its
 * top-left corner, right and down directions, on the front wall's upper
 * left. Sized for the longest lines it can show, so it keeps its size. */
static void panel_place(run *r, vsv_fv_tick *t)
{
    const double now = vsv_room_clock();
    if (now - r->panel_at < 0.5) { /* (sizing it takes FreeType: twice a second is enough) */
        t->lh = r->lh;
        memcpy(t->panel, r->where, sizeof r->where);
        return;
    }
    r->panel_at = now;
    vsv_room_window w[64];
    const int n = vsv_room_windows(vsv_fv.room, w, 64);
    double dens = 0;
    for (int i = 0; i < n && i < 64; i++)
        if (w[i].report > 0 && (dens == 0 || w[i].report < dens))
            dens = w[i].report;
    if (dens == 0 && r->lay.px_per_ft > 0)
        dens = r->lay.px_per_ft;
    double lh = dens > 0 ? fmax(0.2, 11 / dens) : 0.35;
    const double *lo = r->lay.room_lo, *hi = r->lay.room_hi, width = hi[0] - lo[0], height = hi[1] - lo[1];
    vsv_scene sc;
    vsv_player_scene(r->dec, &sc);
    static int sp[4 * VSV_PLAYER_MAX_SPECIES]; /* (as many as the file may have: main checks) */
    for (int s = 0; s < 4 * VSV_PLAYER_MAX_SPECIES; s++)
        sp[s] = s;
    const vsv_annot a = {VSV_ANNOT_TIME | VSV_ANNOT_COLOURBAR, NULL, 0, NULL, sp, NULL, NULL, NULL};
    char err[256], lines[512];
    vsv_fv_panel_lines(NULL, vsv_player_meta(r->dec), vsv_player_clock(r->dec)->nsteps, 0, 0, r->fps, lines,
                       sizeof lines);
    double pw, ph;
    if (!r->panel || vsv_panel_measure(r->measure, &a, &sc, lines, lh, &pw, &ph, err, sizeof err)) {
        t->lh = r->lh = 0;
        return;
    }
    if (pw > 0.9 * width)
        lh *= 0.9 * width / pw, ph *= 0.9 * width / pw;
    if (ph > 0.8 * height)
        lh *= 0.8 * height / ph;
    t->lh = r->lh = lh;
    const double m = 0.05 * width;
    const double at[9] = {lo[0] + m, hi[1] - m, lo[2] + 0.02, 1, 0, 0, 0, -1, 0};
    memcpy(t->panel, at, sizeof at);
    memcpy(r->where, at, sizeof at);
}

/* Reads the wand, moves the scene, runs the actions. */
static void input(run *r, double dt)
{
    vsv_wand_in in;
    memset(&in, 0, sizeof in);
    for (int i = 1; i < VSV_WAND_SWITCHES; i++)
        in.sw[i] = vrGet2switchValue(i);
    in.jx = vrGetValuatorValue(0);
    in.jy = vrGetValuatorValue(1);
    in.dt = dt;
    vsv_wand_out o;
    vsv_wand_update(&r->wand, &in, &o);
    char err[1024];
    for (int i = 0; i < o.nact; i++)
        vsv_player_do(r->dec, o.act[i], err, sizeof err); /* (the wand's actions are all valid) */
    vrPoint wp, hp;
    vrVector wd;
    vrPointGetRWFrom6sensor(&wp, 1);
    vrVectorGetRWFrom6sensorDir(&wd, 1, VRDIR_FORE);
    vrPointGetRWFrom6sensor(&hp, 0);
    const double len = sqrt(wd.v[0] * wd.v[0] + wd.v[1] * wd.v[1] + wd.v[2] * wd.v[2]);
    for (int i = 0; i < 3; i++) {
        r->last.wand[i] = wp.v[i];
        r->last.wdir[i] = len > 0 ? wd.v[i] / len : i == 2 ? -1 : 0;
        r->last.tip[i] = r->last.wand[i] + r->last.wdir[i]; /* a foot along it */
    }
    double M[16], inv[16], w[3]; /* a trajectory from the wand's tip, where it is in the world */
    vsv_mat4_mul(r->nav, r->base, M);
    if (o.seed && vsv_mat4_invert(M, inv) && (vsv_mat4_point(inv, r->last.tip, w), 1) &&
        vsv_player_seed_world(r->dec, w, err, sizeof err))
        fprintf(stderr, "vsv-play-freevr: %s\n", err);
    if (o.reset)
        vsv_nav_identity(r->nav);
    if (o.place) {
        r->kind = r->kind == VSV_PLACE_TABLE ? VSV_PLACE_ROOM : VSV_PLACE_TABLE;
        place_base(r);
        vsv_nav_identity(r->nav);
    }
    if (o.travel != 0) {
        const double d[3] = {o.travel * r->last.wdir[0], o.travel * r->last.wdir[1], o.travel * r->last.wdir[2]};
        vsv_nav_travel(r->nav, d);
    }
    if (o.turn != 0)
        vsv_nav_turn(r->nav, hp.v, o.turn);
    if (o.scale != 1)
        vsv_nav_scale(r->nav, r->last.tip, o.scale);
}

/* A process of the run that is gone (a render process, with its window's
 * name, or FreeVR's input process): who and how it ended into why; 1 when
 * there is one. */
static int dead_process(char *why, size_t cap)
{
    vsv_room_window w[64];
    const int n = vsv_room_windows(vsv_fv.room, w, 64);
    for (int k = 0; k < nkids; k++) {
        if (vsv_proc_alive(kids[k]))
            continue;
        char how[128];
        if (vsv_proc_ended(kids[k], how, sizeof how))
            snprintf(how, sizeof how, "ended");
        const char *name = NULL;
        for (int i = 0; i < n && i < 64 && !name; i++)
            name = w[i].pid == kids[k] ? w[i].name : NULL;
        if (name)
            snprintf(why, cap, "the render process of the %s window (pid %d) %s: the run is ended", name, (int)kids[k],
                     how);
        else
            snprintf(why, cap, "FreeVR's process %d (it drew no window yet, or read the input) %s: the run is ended",
                     (int)kids[k], how);
        return 1;
    }
    return 0;
}

/* Publishes a tick when something changed and every window has shown the
 * last one. 0, or -1 with the reason in err. */
static int publish(run *r, char *err, size_t cap)
{
    vsv_fv_tick t;
    memcpy(&t, &r->last, sizeof t); /* (padding included: the tick is compared whole) */
    vsv_player_state_get(r->dec, &t.st);
    t.nsteps = vsv_player_clock(r->dec)->nsteps;
    vsv_mat4_mul(r->nav, r->base, t.place);
    if (r->fps) {
        vsv_room_window w[64];
        const int n = vsv_room_windows(vsv_fv.room, w, 64);
        t.fps = n ? 1e9 : 0;
        for (int i = 0; i < n && i < 64; i++)
            t.fps = fmin(t.fps, w[i].rate);
        t.fps = round(t.fps * 10) / 10;
    } else {
        t.fps = -1;
    }
    const int step = vsv_player_shown_step(r->dec);
    const char *damage = vsv_player_shown_damage(r->dec);
    if (step < 0)
        return 0;
    /* the clock's own time moves every frame while playing: what the
     * walls show is the step, not it */
    t.st.model = 0;
    panel_place(r, &t);
    if (vsv_room_tick(vsv_fv.room) && step == r->last_step && damage == r->last_damage &&
        !memcmp(&t, &r->last, sizeof t))
        return 0;
    const vsv_meta *m = vsv_player_meta(r->dec);
    static const vsv_volume *vols[4 * VSV_PLAYER_MAX_SPECIES];
    for (int s = 0; s < m->nvars; s++)
        vols[s] = vsv_player_volume(r->dec, s);
    const int rc = vsv_room_publish(vsv_fv.room, vsv_player_pager(r->dec), step, vsv_player_step_time(r->dec, step),
                                    damage, vols, &t, NULL, err, cap);
    if (rc == VSV_EAGAIN) /* a window has not shown the tick before yet */
        return 0;
    if (rc) {
        if (rc == VSV_ENOMEM && vsv_room_arena_used(vsv_fv.room) + ((size_t)4 << 20) > vsv_room_arena_size(vsv_fv.room))
            snprintf(err, cap, "the walls' shared brick memory (%zu MB, from --cache-mb) is full",
                     vsv_room_arena_size(vsv_fv.room) >> 20);
        return -1;
    }
    memcpy(&r->last, &t, sizeof t);
    r->last_step = step;
    r->last_damage = damage;
    return 0;
}

/* clang-format off */
enum { O_TF = 1000, O_CACHE, O_THREADS, O_SCALE, O_RATE, O_LOOP, O_PLAY, O_NOTERRAIN,
       O_PLACE, O_TRACE, O_NOPANEL, O_FPS, O_NOWAND, O_GPUMB, O_FLOW };
/* clang-format on */

/* What the command line says beyond the player's options: ours apart from FreeVR's strings. */
typedef struct freevr_args {
    vsv_player_opts opts;
    size_t budget; /* --cache-mb */
    const char *trace_file;
    char **ours, **fv; /* argv split: ours (options and the file), FreeVR's */
    int nfv;
} freevr_args;

/* The command line into *a, *r and vsv_fv (usage errors exit 2); 1 when --help was printed. */
static int parse_args(int argc, char **argv, freevr_args *a, run *r)
{
    vsv_player_opts_init(&a->opts);
    a->opts.renderer = -1; /* auto: each render process chooses (vsv_freevr_draw.c) */
    a->trace_file = NULL;
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
    /* clang-format off */ /* (a table, laid out by hand) */
    static const struct option longopts[] = {
        {"species", required_argument, 0, 's'},       {"tf", required_argument, 0, O_TF},
        {"renderer", required_argument, 0, 'r'},      {"cache-mb", required_argument, 0, O_CACHE},
        {"threads", required_argument, 0, O_THREADS}, {"render-scale", required_argument, 0, O_SCALE},
        {"exaggerate", required_argument, 0, 'x'},    {"rate", required_argument, 0, O_RATE},
        {"loop", optional_argument, 0, O_LOOP},       {"play", no_argument, 0, O_PLAY},
        {"no-terrain", no_argument, 0, O_NOTERRAIN},  {"place", required_argument, 0, O_PLACE},
        {"trace", required_argument, 0, O_TRACE},     {"no-panel", no_argument, 0, O_NOPANEL},
        {"fps", no_argument, 0, O_FPS},               {"no-wand", no_argument, 0, O_NOWAND},
        {"gpu-mb", required_argument, 0, O_GPUMB},      {"colormap", required_argument, 0, O_FLOW},
        {"log", required_argument, 0, O_FLOW},          {"range", required_argument, 0, O_FLOW}, {"iso", required_argument, 0, O_FLOW},
        {"help", no_argument, 0, 'h'},                {"cache-dir", required_argument, 0, VSV_CLI_CACHE_DIR},
        VSV_PLAYER_FLOW_LONGOPTS(O_FLOW), {"version", no_argument, 0, 'V'}, {0, 0, 0, 0}};
    /* clang-format on */
    a->budget = (size_t)1 << 30;
    int c, li = 0;
    ours[0] = (char *)vsv_cli_tool(); /* getopt's messages name the tool as ours do */
    while ((c = getopt_long(nours, ours, "s:r:x:hV", longopts, &li)) != -1) {
        long v;
        double d;
        switch (c) {
        case 's': a->opts.species = optarg; break;
        case O_TF: a->opts.tfpath = optarg; break;
        case O_FLOW: { /* --colormap, --log, --range, --iso, the wind: vsv_player_option */
            char msg[512];
            if (vsv_player_option(&a->opts, longopts[li].name, optarg, msg, sizeof msg))
                vsv_cli_usage_error("%s", msg);
            break;
        }
        case 'r':
            if (!strcmp(optarg, "raycast"))
                a->opts.renderer = VSV_RENDER_RAYCAST;
            else if (!strcmp(optarg, "shearwarp"))
                a->opts.renderer = VSV_RENDER_SHEARWARP;
            else if (!strcmp(optarg, "gl"))
                a->opts.renderer = VSV_RENDER_GL;
            else if (!strcmp(optarg, "auto"))
                a->opts.renderer = -1;
            else
                vsv_cli_usage_error("--renderer: auto, shearwarp, raycast or gl, not '%s'", optarg);
            break;
        case O_GPUMB:
            if (vsv_cli_int(optarg, 16, 1 << 20, &v))
                vsv_cli_usage_error("--gpu-mb %s: a whole number of megabytes, 16 to %d", optarg, 1 << 20);
            a->opts.gpu_budget = (size_t)v << 20;
            break;
        case O_CACHE:
            if (vsv_cli_int(optarg, 16, 1 << 30, &v))
                vsv_cli_usage_error("--cache-mb %s: a whole number of megabytes, 16 to %d", optarg, 1 << 30);
            a->budget = (size_t)v << 20;
            break;
        case O_THREADS:
            if (vsv_cli_int(optarg, 1, 64, &v))
                vsv_cli_usage_error("--threads: 1..64");
            a->opts.threads = (int)v;
            break;
        case O_SCALE:
            if (vsv_cli_double(optarg, &vsv_fv.scale) || !(vsv_fv.scale >= 0.05 && vsv_fv.scale <= 4))
                vsv_cli_usage_error("--render-scale: 0.05..4");
            break;
        case 'x':
            if (vsv_cli_double(optarg, &d) || !(d > 0))
                vsv_cli_usage_error("--exaggerate: a number > 0");
            a->opts.exaggerate = d;
            break;
        case O_RATE:
            if (vsv_cli_double(optarg, &d) || !(d > 0))
                vsv_cli_usage_error("--rate: model seconds per wall second, > 0");
            a->opts.rate = d;
            break;
        case O_LOOP:
            a->opts.loop = !optarg || !strcmp(optarg, "on") ? VSV_CLOCK_LOOP
                           : !strcmp(optarg, "bounce")      ? VSV_CLOCK_BOUNCE
                                                            : VSV_CLOCK_STOP;
            if (optarg && !a->opts.loop && strcmp(optarg, "off"))
                vsv_cli_usage_error("--loop: on, off or bounce");
            break;
        case O_PLAY: a->opts.play = 1; break;
        case O_NOTERRAIN: a->opts.terrain = 0; break;
        case O_PLACE:
            if (!strcmp(optarg, "table"))
                r->kind = VSV_PLACE_TABLE;
            else if (!strcmp(optarg, "room"))
                r->kind = VSV_PLACE_ROOM;
            else
                vsv_cli_usage_error("--place: table or room, not '%s'", optarg);
            break;
        case O_TRACE: a->trace_file = optarg; break;
        case O_NOPANEL: r->panel = 0; break;
        case O_FPS: r->fps = 1; break;
        case O_NOWAND: vsv_fv.wand = 0; break;
        case VSV_CLI_CACHE_DIR: vsv_cli_cache_dir(optarg); break;
        case 'h':
            fputs(usage, stdout);
            fputs(vsv_wand_help(), stdout);
            fputs(usage_tail, stdout);
            free(ours);
            free(fv);
            return 1;
        case 'V': vsv_cli_version();
        default: vsv_cli_getopt_failed();
        }
    }
    if (optind != nours - 1)
        vsv_cli_usage_error(optind < nours ? "one file at a time (FreeVR configuration strings contain ; = \" { or })"
                                           : "no input file");
    a->opts.path = ours[optind];
    a->opts.http = &vsv_cli_http;
    a->ours = ours;
    a->fv = fv;
    a->nfv = nfv;
    return 0;
}

/* The file and the species checked, the FreeVR layout read and the room (one decoded copy for every wall)
 * created, all before FreeVR starts anything; dies on errors. */
static void open_room(freevr_args *a, run *r)
{
    vsv_player_opts io = a->opts;
    io.clock_only = 1;
    vsv_player *in = NULL;
    char err[1024];
    const int orc = vsv_player_open(&io, &in, err, sizeof err);
    if (orc == VSV_EINVAL) /* an option the file cannot have: misuse, as in vsv-play */
        vsv_cli_usage_error("%s", err);
    if (orc)
        vsv_cli_die(1, "%s", err);
    read_layout(a->fv, a->nfv, &r->lay);
    if (r->lay.missing[0])
        vsv_cli_usage_error("FreeVR configuration: usesystem \"%s\", but no system \"%s\" is defined in "
                            "$FREEVR_HOME/.freevrrc, ~/.freevrrc, ./.freevrrc, $FREEVR or the arguments (FreeVR "
                            "would open its simulator with no input: Escape would not end it); define it, or "
                            "leave usesystem out for the simulator",
                            r->lay.missing, r->lay.missing);
    /* one decoded copy for every wall: the room, mapped before the fork */
    vsv_volume *shape = vsv_pager_volume_new(vsv_player_pager(in));
    if (!shape)
        vsv_cli_die(1, "out of memory");
    /* the arena: the budget, with room for what stays pinned beyond it (the
     * two published ticks and the step being shown: three whole steps at
     * most) and the pager's slabs' rounding */
    const size_t step_bytes = (size_t)vsv_player_meta(in)->nvars * (size_t)shape->nbricks * (size_t)shape->brick *
                              (size_t)shape->brick * (size_t)shape->brick * sizeof(float);
    const vsv_room_opts ro = {a->budget + 3 * step_bytes + ((size_t)64 << 20), vsv_player_meta(in)->nvars,
                              shape->nbricks, r->lay.windows, sizeof(vsv_fv_tick)};
    vsv_volume_free(shape);
    if (ro.nspecies > VSV_PLAYER_MAX_SPECIES * 4)
        vsv_cli_die(1, "%s: %d species: vsv-play-freevr draws at most %d", a->opts.path, ro.nspecies,
                    VSV_PLAYER_MAX_SPECIES * 4);
    if (vsv_room_create(&ro, &vsv_fv.room, err, sizeof err))
        vsv_cli_die(1, "%s", err);
    if (a->trace_file)
        trace_open(a->trace_file);
    vsv_fv.opts = a->opts;
    vsv_fv.opts.external = 1;
    vsv_fv.t0 = vsv_room_clock();
    vsv_player_free(in);
    if (!(r->measure = vsv_panel_create()))
        vsv_cli_die(1, "out of memory");
}

/* FreeVR: its arena (its own per-window state), its processes, and this process's signal handlers. */
static void start_freevr(run *r, char **fv, int nfv)
{
    vsv_ipc before, after;
    vsv_ipc_list(&before);
    vrShmemInit(vsv_freevr_arena_bytes(&r->lay, 0));
    fv[nfv] = NULL;
    vrConfigure(&nfv, fv, NULL);
    vsv_ipc_list(&after);
    vsv_ipc_new(&before, &after, &fv_ipc);
    /* from here on every exit ends FreeVR's processes */
    vrInputSet2switchDescription(1, "play / pause; held: joystick scales");
    vrInputSet2switchDescription(2, "next species; held: joystick opacity");
    vrInputSet2switchDescription(3, "show / hide; held: joystick steps, speed");
    vrCallbackSet(VRFUNC_DISPLAY_INIT, "vsv_display_init", vsv_fv_display_init, 0);
    vrCallbackSet(VRFUNC_DISPLAY_FRAME, "vsv_display_frame", vsv_fv_display_frame, 0);
    vrCallbackSet(VRFUNC_DISPLAY, "vsv_display", vsv_fv_display_eye, 0);
    vrCallbackSet(VRFUNC_DISPLAY_EXIT, "vsv_display_exit", vsv_fv_display_exit, 0);
    vsv_ipc_list(&before);
    vrStart();
    vsv_ipc_list(&after);
    nkids = vsv_proc_children(kids, 64); /* FreeVR's render and input processes */
    vsv_ipc new_ipc;
    vsv_ipc_new(&before, &after, &new_ipc);
    for (int i = 0; i < new_ipc.nsem && fv_ipc.nsem < 256; i++)
        fv_ipc.sem[fv_ipc.nsem++] = new_ipc.sem[i];
    for (int i = 0; i < new_ipc.nshm && fv_ipc.nshm < 256; i++)
        fv_ipc.shm[fv_ipc.nshm++] = new_ipc.shm[i];
    /* FreeVR ignores SIGINT; this process ends the run on it */
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    sigaction(SIGHUP, &sa, NULL);
}

int main(int argc, char **argv)
{
    vsv_cli_init("vsv-play-freevr");
    memset(&vsv_fv, 0, sizeof vsv_fv);
    vsv_fv.scale = 1;
    vsv_fv.trace_fd = -1;
    vsv_fv.wand = 1;
    run r;
    memset(&r, 0, sizeof r);
    r.panel = 1;
    r.last_step = -1;
    freevr_args a;
    if (parse_args(argc, argv, &a, &r))
        return 0;
    open_room(&a, &r);
    start_freevr(&r, a.fv, a.nfv);
    /* the decoding player: its threads start after FreeVR's forks */
    vsv_player_opts dopts = a.opts;
    dopts.cache_bytes = a.budget;
    dopts.threads = 1;
    dopts.no_renderer = 1; /* (the render processes draw) */
    dopts.slab_alloc = vsv_room_slab;
    dopts.slab_ctx = vsv_fv.room;
    int status = 0, dead = 0;
    char msg[1200] = "";
    if (vsv_player_open(&dopts, &r.dec, msg, sizeof msg)) {
        status = 1;
    } else {
        vsv_nav_identity(r.nav);
        place_base(&r);
        const double depth = r.lay.room_hi[2] - r.lay.room_lo[2];
        vsv_wand_init(&r.wand, depth / 2.5);
    }
    double last = vrCurrentSimTime(), checked = 0, start = vsv_room_clock();
    int started = 0;
    while (!status && vrFrame()) {
        if (got_signal)
            break;
        if ((status = vsv_room_failed(vsv_fv.room, msg, sizeof msg)))
            break;
        const double now = vrCurrentSimTime(), wall = vsv_room_clock();
        if (wall - checked > 0.2) { /* a render process that died: FreeVR would wait for it forever */
            checked = wall;
            if (dead_process(msg, sizeof msg)) {
                status = 1, dead = 1;
                break;
            }
        }
        /* the clock starts once every window has joined (or after 20 s) */
        if (!started) {
            vsv_room_window w[64];
            started = vsv_room_windows(vsv_fv.room, w, 64) >= r.lay.windows || wall - start > 20;
        }
        const double dt = started ? now - last : 0;
        input(&r, now - last);
        last = now;
        if (vsv_player_update(r.dec, dt, 0) || publish(&r, msg, sizeof msg)) {
            if (!msg[0])
                snprintf(msg, sizeof msg, "%s", vsv_player_error(r.dec));
            status = 1;
            break;
        }
        const char *why;
        if (vsv_player_damage(r.dec, &why) >= 0)
            fprintf(stderr, "%s: %s\n", vsv_cli_tool(), why);
        /* the input arrives at FreeVR's poll rate (about 60 Hz): no need to
         * spin, the render processes want the cores */
        nanosleep(&(struct timespec){0, 5000000}, NULL);
    }
    const int sig = got_signal;
    if (dead) {
        /* vrExit would wait for the dead process: end FreeVR's others */
        vsv_proc_end(kids, nkids, 1.0);
        vsv_ipc_remove(&fv_ipc);
    } else {
        freevr_exit(sig ? 128 + sig : status, sig != 0);
    }
    trace_close();
    vsv_room_unpin(vsv_fv.room);
    vsv_player_free(r.dec);
    vsv_panel_free(r.measure);
    vsv_room_free(vsv_fv.room);
    free(a.ours);
    free(a.fv);
    if (sig) {
        signal(sig, SIG_DFL);
        raise(sig);
    }
    if (status)
        vsv_cli_die(status, "%s", msg);
    return 0;
}
