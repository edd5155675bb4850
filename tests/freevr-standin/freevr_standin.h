/* freevr_standin.h — the test stand-in for FreeVR: the calls the FreeVR back end
 * uses (declared in viewer/freevr/freevr.h, installed as this stand-in's
 * freevr.h), written by the project from ../shared/docs/FREEVR.md and what
 * FreeVR's own documentation says of its configuration; no FreeVR code. It
 * is NOT FreeVR: it exists so that `make test` can run vsv-play-freevr under
 * Xvfb and look at what each wall shows. Built by `make test`, never
 * installed. It behaves the way FREEVR.md says FreeVR behaves wherever that
 * decides what a wall shows, and fails the way FreeVR 0.6f was seen to fail
 * (FREEVR.md, "Behaviour seen on FreeVR 0.6f itself"). Each behaviour, and
 * where it comes from:
 *
 *  - real-world units are feet (the CAVE a 10-foot cube, the floor y = 0)
 *    (FREEVR.md, "Units and clipping");
 *  - configuration in FreeVR's syntax (FREEVR.md, "Configuration syntax"):
 *    FreeVR's default first, the one-window simulator with Escape, the
 *    mouse buttons and the simulated head and wand (FreeVR's User's Guide:
 *    its start-up report reads "Default Config String" before any file),
 *    then $FREEVR_HOME/.freevrrc, $HOME/.freevrrc, ./.freevrrc, the FREEVR
 *    variable and every command-line argument (none removed; a warning for
 *    each one not understood) (FREEVR.md, "Arguments"); a definition given
 *    again replaces the earlier one;
 *  - a named system that is not defined (`usesystem "cave4";` and no
 *    `system "cave4"`) prints
 *      FreeVR config: could not find system "cave4", using default (with boring input)
 *    and runs one simulator window whose input maps nothing: Escape does
 *    nothing, vrFrame never returns 0 from input, and only a signal ends it
 *    (FREEVR.md, "A named system that is not defined");
 *  - where the head starts: every 6-sensor starts at its tracker's origin,
 *    so the head (6-sensor 0) is at the real-world origin (0, 0, 0), on the
 *    floor, looking along -z, unless the input device it is an input of
 *    moves that origin (FREEVR.md, "Where the head starts"). Syntax: in an
 *    inputdevice, `input "head" = "6sensor(sim6[0])";` (FreeVR's usage
 *    notes for its xwindows device give input "<name>" =
 *    "6sensor(sim6[<number>])") and `t2rw_translate = 0, 5.5, 0;` (feet;
 *    FreeVR's configuration keywords list t2rw_translate among the input
 *    device options). 6-sensors are numbered in the order their inputs are
 *    listed over the system's input processes' devices: the first is the
 *    head, the second the wand. The wand (6-sensor 1) starts likewise at
 *    its own device's t2rw_translate, by default the real-world origin too,
 *    pointing along -z. vrPointGetRWFrom6sensor, vrMatrixGet6sensorValues
 *    and vrVectorGetRWFrom6sensorDir return these poses; fixed walls are
 *    drawn with their frustum for the head (FREEVR.md, "Units and
 *    clipping"); the simulator window keeps its own viewpoint;
 *  - signals: vrConfigure sets SIGINT ignored, so Ctrl-C does nothing to
 *    any process unless the application installs a handler after vrStart;
 *    SIGTERM or SIGHUP to the main process alone ends it and orphans the
 *    render and input processes, which go on drawing (nothing sets the
 *    quit flag any more), and the semaphore set stays (FREEVR.md,
 *    "Signals");
 *  - a render process that dies (killed, crashed, or one that cannot open
 *    its display): the others go on, and vrExit, which waits for every
 *    forked process to say it has finished, never returns (FREEVR.md, "A
 *    render process that dies"); an input process likewise;
 *  - stereo: `visrenmode = "anaglyphic";` or `"dualvp";` on a window, or on
 *    its system for all its windows (the window's wins), "mono" (the
 *    default), "left" or "right" (one eye) (FreeVR's usage notes for its
 *    visual rendering windows: visrenMode = { "default", "mono", "right",
 *    "left", "dualvp", "dualfb", "anaglyphic", "checkerboard", "vibrate" },
 *    and its configuration keywords list VisrenMode among the system
 *    options); dualfb, checkerboard and vibrate are not simulated (mono,
 *    with "FreeVR stand-in: visrenmode "dualfb" is not simulated: mono").
 *    Both stereo modes call the display callback once per eye with that
 *    eye's frustum (FREEVR.md, "Stereo"), the left eye first; the eyes are
 *    the head moved half the user's iod left and right along the head's
 *    right vector (`user "NAME" = { iod = 0.2; }`, a user option among
 *    FreeVR's configuration keywords; 0.2 feet when none is given: FreeVR's
 *    own default is not in the documentation read), so content in front of
 *    the screen has negative parallax. dualvp sets each eye's glViewport
 *    and glScissor (GL_SCISSOR_TEST on) to its half of the window, the left
 *    eye's the left half, so each eye's clear wipes only its half; anaglyphic
 *    draws both eyes into the whole window through glColorMask, the left eye
 *    red, the right green and blue. VRFUNC_DISPLAY_FRAME is still called
 *    once per window per frame, before the eyes (with the mono eye's
 *    matrices); vrRenderInfo's eye is 0 for the left (or only) eye, 1 for
 *    the right;
 *  - vrConfigure creates one SysV semaphore set of 250 semaphores; vrExit
 *    removes it (a process that exits without vrExit leaves it) (FREEVR.md,
 *    "Semaphores");
 *  - one shared arena of exactly the size the first vrShmemInit asked for
 *    (16 MiB by default), from which the stand-in takes its own state too:
 *    445,000 bytes at vrConfigure and, in each render process, its share of
 *    the per-window state measured with FreeVR (525 KB in all with one
 *    window, 765 KB with four, 1,049,736 bytes with eight); when it is full
 *    it prints "Not enough room to amalloc", and a render process that
 *    cannot get its state waits forever (so vrExit never returns)
 *    (FREEVR.md, "The shared arena");
 *  - vrStart forks one render process per visren process, each opening its
 *    own GLX windows and contexts (named "FreeVR(pid): NAME window"), and one
 *    input process polling the X server every usecmin microseconds (16,667:
 *    60 Hz); Escape is 2switch 0, and vrFrame returns 0 once it is pressed
 *    (FREEVR.md, "Processes", "Input timing", "Input");
 *  - before each eye's display callback it loads glFrustum(near 0.1, far
 *    1000) for that wall from its rw2w_coords corners and the eye, and the
 *    modelview (the wall's axes times a translation by minus the eye); it
 *    never clears the colour or depth buffer (FREEVR.md, "Display
 *    callbacks", "Clearing is the application's job").
 * Simplifications, all outside what a wall shows: the head and the wand
 * never move (no tracker is read and no key moves them); the simulator
 * window looks from (0, 7, 12) at (0, 4, -3) and draws the head (a brown
 * cube) and a foot of the wand; an xwindows device's 2switches are numbered
 * in the order its inputs are listed; locks are exclusive.
 *
 * Test aids (not FreeVR):
 *  - FREEVR_STANDIN_DUMP=DIR: every frame of every window is written, as
 *    glReadPixels sees the back buffer just before the swap (after both
 *    eyes), to DIR/NAME.ppm (a "# frame N" comment counts the frames);
 *  - FREEVR_STANDIN_HEAD="x,y,z" (feet) puts the head there, and
 *    FREEVR_STANDIN_WAND="x,y,z[,yaw,pitch]" the wand, turned yaw degrees
 *    about +y from pointing along -z (positive: to the left), then pitched
 *    up by pitch degrees; both override the configuration. A value that is
 *    not that is ignored with "FreeVR stand-in: NAME='VALUE' is not ...".
 *
 * This header is what the stand-in's files share: freevr_config.c (the
 * configuration language), freevr_shmem.c (the shared arena, semaphores and
 * locks), freevr_process.c (vrConfigure, vrStart, vrExit: the processes and
 * signals), freevr_render.c (callbacks, windows, eyes, projection, stereo,
 * drawing) and freevr_input.c (switches, valuators, sensors, travel).
 * standin_selftest.c is a small FreeVR program that exercises it alone
 * (README-checks.txt). */
#ifndef FREEVR_STANDIN_H
#define FREEVR_STANDIN_H

#include <freevr.h>

#include <stddef.h>

/* what FreeVR loads into OpenGL before each eye's display callback (the
 * header leaves vrRenderInfo opaque: the back end reads the GL matrices) */
typedef struct vrPerspective {
    struct {
        struct {
            double left, right, bottom, top;
        } n;
        double near_clip, far_clip;
    } frustum;
    double eye[3];       /* the eye in real-world feet */
    vrMatrix rw2w_xform; /* real world -> the wall's frame */
} vrPerspective;

struct vrRenderInfo {
    vrPerspective *persp;
    const char *window; /* the window's name */
    int eye;            /* 0: the left (or only) eye, 1: the right eye */
};

#define NEAR_CLIP 0.1
#define FAR_CLIP 1000.0
#define NSEMS 250
#define BASE_STATE 445000ul
#define MAXWIN 32
#define MAXPROC 40
#define NAMELEN 64
#define NSW 16
#define NVAL 8
/* the eye separation (feet) when no `user` sets `iod`: FreeVR's own
 * default is not in the documentation the stand-in was written from */
#define FVS_DEFAULT_IOD 0.2

/* a window's visrenmode (FreeVR's names) */
enum {
    FVS_VISREN_DEFAULT, /* as the system says; mono if it says nothing */
    FVS_VISREN_MONO,
    FVS_VISREN_LEFT,  /* mono, seen by the left eye */
    FVS_VISREN_RIGHT, /* mono, seen by the right eye */
    FVS_VISREN_DUALVP,
    FVS_VISREN_ANAGLYPHIC
};

/* ---------------------------------------------------------- configuration */

typedef struct {
    char name[NAMELEN];
    int simulator;  /* mount = "simulator" (else fixed) */
    int w, h, x, y; /* geometry */
    double c[9];    /* rw2w_coords: lower-left, lower-right, upper-left */
    int visren;     /* visrenmode: FVS_VISREN_* */
} win_def;

typedef struct {
    char name[NAMELEN];
    int type; /* 'v' visren, 'i' input, 0 other */
    int nobj;
    char obj[MAXWIN][NAMELEN];
    long usecmin;
} proc_def;

typedef struct {
    char name[NAMELEN];
    int nprocs;
    char procs[MAXPROC][NAMELEN];
    int visren; /* visrenmode: FVS_VISREN_* */
} sys_def;

typedef struct {
    char name[NAMELEN];
    int xwindows, nin;
    struct {
        int button; /* 1..3: a mouse button, else a key */
        unsigned long keysym;
    } in[NSW];
    int nsensor;    /* its 6sensor inputs */
    double t2rw[3]; /* t2rw_translate: where its tracker's origin is, feet */
} dev_def;

typedef struct {
    char use[NAMELEN];
    win_def win[MAXWIN * 2];
    int nwin;
    proc_def proc[MAXPROC];
    int nproc;
    sys_def sys[8];
    int nsys;
    dev_def dev[8];
    int ndev;
    double iod; /* a user's iod: the eye separation, feet */
} config;

/* The configuration in use (freevr_config.c). */
extern config fvs_cfg;
/* Reads FreeVR's configuration in its order (its default, the one-window
 * simulator; $FREEVR_HOME/.freevrrc, $HOME/.freevrrc, ./.freevrrc,
 * $FREEVR, every argument) into fvs_cfg; when the system `usesystem` names
 * is not defined, FreeVR's message and the simulator with boring input. */
void fvs_config_load(int *argc, char **argv);
/* The definitions named so in fvs_cfg (borrowed), or NULL. */
const proc_def *fvs_find_proc(const char *name);
const win_def *fvs_find_win(const char *name);
const dev_def *fvs_find_dev(const char *name);
/* The system `usesystem` names, or NULL. */
const sys_def *fvs_used_system(void);
/* The windows of the used system's visren processes ('v'), or the 2switches
 * of its input processes' xwindows devices ('i'). */
int fvs_config_count(int type);
/* The visrenmode a window renders in (FVS_VISREN_MONO, _LEFT, _RIGHT,
 * _DUALVP or _ANAGLYPHIC): its own, else its system's, else mono. */
int fvs_config_visren(const win_def *w);
/* Where FreeVR's 6-sensor n (0 the head, 1 the wand) starts: the origin
 * of the tracker of the device whose n-th 6sensor input it is (the used
 * system's input processes' devices in order), moved by that device's
 * t2rw_translate; 1 if it is configured, else 0 and the real-world
 * origin. */
int fvs_config_sensor(int n, double pos[3]);

/* ------------------------------------------------------------- the arena */

/* FreeVR's own state at the start of the arena's first allocation */
typedef struct {
    volatile int quit, started;
    volatile int sw[NSW];
    volatile float val[NVAL];
    double sensor[2][16]; /* the head's and the wand's pose, real world */
    double start;
    int nextlock;
    double travel[16];
    volatile int done[MAXPROC + 1]; /* set by each forked process as it ends well */
} base_state;

/* FreeVR's state at the start of the arena (freevr_shmem.c); NULL before
 * vrConfigure and after vrExit. */
extern base_state *fvs_base;
/* Each render process's share of FreeVR's per-window state, in bytes. */
extern size_t fvs_per_window;
/* Maps the arena, creates the semaphore set and takes the base state from
 * the arena for a system of `windows` windows; exits the process when the
 * arena or the semaphores cannot be had. */
void fvs_shmem_create(int windows);
/* Removes the semaphore set and unmaps the arena. */
void fvs_shmem_destroy(void);
/* FreeVR's allocator over the shared arena: zeroed bytes, or NULL (with
 * FreeVR's message) when the arena is full. */
void *fvs_amalloc(size_t n);

/* -------------------------------------------------------------- sensors */

/* Sets the head's and the wand's poses in fvs_base from the configuration
 * (fvs_config_sensor, looking along -z), then from the test aid's
 * FREEVR_STANDIN_HEAD and FREEVR_STANDIN_WAND. */
void fvs_sensors_init(void);

/* ------------------------------------------------------------ processes */

/* Seconds on the monotonic clock. */
double fvs_now(void);
/* The bodies of the processes vrStart forks; neither returns. */
void fvs_render_process(const proc_def *p);
void fvs_input_process(const proc_def *p);
/* Which of the forked processes this is (vrStart's order), -1 in the main
 * process. */
extern int fvs_slot;
/* Tells vrExit that this forked process has finished; a process that ends
 * any other way (killed, crashed, _exit on an error) leaves vrExit waiting
 * for ever, as FreeVR does. */
void fvs_process_done(void);

#endif
