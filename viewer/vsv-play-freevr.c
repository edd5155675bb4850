/* vsv-play-freevr — vsv-play on an immersive display through FreeVR (a CAVE,
 * a single wall, or FreeVR's desktop simulator). Built only when FREEVR_DIR
 * names a FreeVR install (make FREEVR_DIR=...); `make test` compiles it with
 * -fsyntax-only against viewer/freevr/freevr.h so it keeps building.
 *
 * FreeVR forks one render process per window, so the brick cache cannot be
 * shared: each render process opens the file and runs its own pager and
 * renderer (the budget is split between them), while the input process runs
 * the clock and the species settings and publishes them, under a lock, in
 * shared memory. Each eye of each wall is rendered with that eye's
 * off-axis frustum and drawn on a billboard at the volume's depth.
 *
 * Wand: button 1 play/pause, button 2 next species, button 3 show/hide it;
 * joystick right/left fast-forward/rewind, up/down its opacity. */
#include "vsv_cli.h"
#include "vsv_overlay.h"
#include "vsv_player.h"

#include <GL/gl.h>
#include <freevr.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* the volume in the display: 8 feet wide, its centre 4 feet up, 3 feet in
 * front of the floor's centre */
static const double AT[3] = {0, 4, -3}, SIZE = 8;

typedef struct shared {
    vrLock lock;
    vsv_player_state st;
    int windows; /* render processes started (for the cache split) */
} shared;

static shared *S;
static vsv_player_opts OPTS;
static size_t BUDGET;
/* per render process (after the fork) */
static vsv_player *R;
static vsv_overlay *OV;

static void display_init(void)
{
    char err[1024];
    vrLockWriteSet(S->lock);
    S->windows++;
    vrLockWriteRelease(S->lock);
    vsv_player_opts o = OPTS;
    o.cache_bytes = BUDGET / 4; /* up to four windows share the budget */
    if (vsv_player_open(&o, &R, err, sizeof err))
        vsv_cli_die(1, "%s", err);
    if (!(OV = vsv_overlay_create(18, err, sizeof err)))
        vsv_cli_die(1, "%s", err);
}

static void display(vrRenderInfo *ri)
{
    char err[1024];
    (void)ri;
    vsv_player_state st;
    vrLockReadSet(S->lock);
    st = S->st;
    vrLockReadRelease(S->lock);
    if (vsv_player_state_apply(R, &st, err, sizeof err) || vsv_player_update(R, 0, 1))
        vsv_cli_die(1, "%s", err[0] ? err : vsv_player_error(R));
    double P[16], MV[16];
    GLint vp[4];
    glGetDoublev(GL_PROJECTION_MATRIX, P);
    glGetDoublev(GL_MODELVIEW_MATRIX, MV);
    glGetIntegerv(GL_VIEWPORT, vp);
    if (vp[2] < 1 || vp[3] < 1)
        return;
    vsv_camera cam;
    vsv_player_camera_from_gl(R, AT, SIZE, P, MV, vp[2], vp[3], &cam);
    const unsigned char *img = vsv_player_image(R, &cam, err, sizeof err);
    if (!img)
        vsv_cli_die(1, "%s", err);
    double mn[3], mx[3];
    vsv_player_bounds(R, mn, mx);
    vsv_billboard_draw(&cam, mn, mx, img, vp[2], vp[3], 0);
    char status[2048];
    vsv_player_status(R, status, sizeof status);
    vsv_overlay_text(OV, vp[2], vp[3], 8, -8, status);
}

int main(int argc, char **argv)
{
    vsv_cli_init("vsv-play-freevr");
    vsv_player_opts_init(&OPTS);
    int c;
    static const struct option longopts[] = {{"species", required_argument, 0, 's'},
                                             {"renderer", required_argument, 0, 'r'},
                                             {"cache-mb", required_argument, 0, 'C'},
                                             {"loop", no_argument, 0, 'l'},
                                             {"play", no_argument, 0, 'p'},
                                             {"help", no_argument, 0, 'h'},
                                             {0, 0, 0, 0}};
    BUDGET = (size_t)1 << 30;
    /* FreeVR takes its own arguments first */
    vrShmemInit((size_t)1 << 20);
    vrConfigure(&argc, argv, NULL);
    while ((c = getopt_long(argc, argv, "s:r:h", longopts, NULL)) != -1) {
        long v;
        switch (c) {
        case 's': OPTS.species = optarg; break;
        case 'r': OPTS.renderer = strcmp(optarg, "raycast") ? VSV_RENDER_SHEARWARP : VSV_RENDER_RAYCAST; break;
        case 'C':
            if (vsv_cli_int(optarg, 16, 1 << 30, &v))
                vsv_cli_usage_error("--cache-mb: a number of megabytes >= 16");
            BUDGET = (size_t)v << 20;
            break;
        case 'l': OPTS.loop = VSV_CLOCK_LOOP; break;
        case 'p': OPTS.play = 1; break;
        case 'h':
            puts("Usage: vsv-play-freevr FILE.vsv [--species LIST] [--renderer raycast|shearwarp]\n"
                 "       [--cache-mb N] [--loop] [--play]   (FreeVR options before them)");
            return 0;
        default: vsv_cli_usage_error("see --help");
        }
    }
    if (optind != argc - 1)
        vsv_cli_usage_error("one .vsv file");
    OPTS.path = argv[optind];
    /* the input process: clock and settings only */
    vsv_player_opts io = OPTS;
    io.clock_only = 1;
    vsv_player *in = NULL;
    char err[1024];
    if (vsv_player_open(&io, &in, err, sizeof err))
        vsv_cli_die(1, "%s", err);
    S = vrShmemAlloc0(sizeof *S);
    if (!S)
        vsv_cli_die(1, "FreeVR shared memory: out of space");
    S->lock = vrLockCreate();
    vsv_player_state_get(in, &S->st);
    vrInputSet2switchDescription(1, "play / pause");
    vrInputSet2switchDescription(2, "next species");
    vrInputSet2switchDescription(3, "show / hide the species");
    vrCallbackSet(VRFUNC_DISPLAY_INIT, "vsv_display_init", display_init, 0);
    vrCallbackSet(VRFUNC_DISPLAY, "vsv_display", display, 0);
    vrStart();
    double last = vrCurrentSimTime();
    int stick = 0; /* joystick x: -1, 0, +1 (edges trigger) */
    while (vrFrame()) {
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
    }
    vrExit();
    vsv_player_free(in);
    return 0;
}
