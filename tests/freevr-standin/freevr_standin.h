/* freevr_standin.h — the test stand-in for FreeVR: the calls the FreeVR back end
 * uses (declared in viewer/freevr/freevr.h, installed as this stand-in's
 * freevr.h), written by the project from ../shared/docs/FREEVR.md alone. It
 * is NOT FreeVR: it exists so that `make test` can run vsv-play-freevr under
 * Xvfb and look at what each wall shows. Built by `make test`, never
 * installed. It behaves the way that page says FreeVR behaves wherever that
 * decides what a wall shows:
 *
 *  - real-world units are feet (the CAVE a 10-foot cube, the floor y = 0);
 *  - configuration in FreeVR's syntax from $FREEVR_HOME/.freevrrc,
 *    $HOME/.freevrrc, ./.freevrrc, the FREEVR variable, then every
 *    command-line argument (none removed; a warning for each one not
 *    understood), read after FreeVR's default, the one-window simulator; a
 *    `usesystem` naming a system that is not defined: FreeVR's message and
 *    the simulator with boring input (Escape does nothing);
 *  - vrConfigure creates one SysV semaphore set of 250 semaphores; vrExit
 *    removes it (a process that exits without vrExit leaves it);
 *  - vrConfigure sets SIGINT ignored (the processes vrStart forks inherit
 *    it); SIGTERM or SIGHUP to the main process alone ends it and orphans
 *    the render and input processes, which go on drawing; vrExit waits for
 *    every forked process to say it has finished, so one that died keeps
 *    it waiting for ever;
 *  - one shared arena of exactly the size the first vrShmemInit asked for
 *    (16 MiB by default), from which the stand-in takes its own state too:
 *    445,000 bytes at vrConfigure and, in each render process, its share of
 *    the per-window state measured with FreeVR (525 KB in all with one
 *    window, 765 KB with four, 1,049,736 bytes with eight); when it is full
 *    it prints "Not enough room to amalloc", and a render process that
 *    cannot get its state waits forever (so vrExit never returns);
 *  - vrStart forks one render process per visren process, each opening its
 *    own GLX windows and contexts (named "FreeVR(pid): NAME window"), and one
 *    input process polling the X server every usecmin microseconds (16,667:
 *    60 Hz); Escape is 2switch 0, and vrFrame returns 0 once it is pressed;
 *  - the head (6-sensor 0) and the wand (6-sensor 1) start at the origin
 *    of their input device's tracker, moved by its t2rw_translate: the
 *    real-world origin, on the floor, when none is given;
 *  - stereo: `visrenmode = "anaglyphic";` or `"dualvp";` on a window or
 *    its system calls the display callback once per eye, each eye half a
 *    user's iod (0.2 feet unless set) left or right of the head; dualvp
 *    gives each eye its half of the window (viewport and scissor),
 *    anaglyphic the whole window through its colour mask (left red, right
 *    green and blue);
 *  - before each eye's display callback it loads glFrustum(near 0.1, far
 *    1000) for that wall from its rw2w_coords corners and the head, and the
 *    modelview (the wall's axes times a translation by minus the eye); it
 *    never clears the colour or depth buffer.
 * Simplifications, all outside what a wall shows: the head and the wand
 * never move; the simulator window looks from (0, 7, 12) at
 * (0, 4, -3); an xwindows device's 2switches are numbered in the order its
 * inputs are listed; locks are exclusive.
 *
 * Test aid (not FreeVR): with FREEVR_STANDIN_DUMP=DIR every frame of every
 * window is written, as glReadPixels sees the back buffer just before the
 * swap, to DIR/NAME.ppm (a "# frame N" comment counts the frames);
 * FREEVR_STANDIN_HEAD="x,y,z" and FREEVR_STANDIN_WAND="x,y,z[,yaw,pitch]"
 * (feet; degrees about +y from -z, positive to the left, then up) put the
 * head and the wand there whatever the configuration says.
 *
 * This header is what the stand-in's files share: freevr_config.c (the
 * configuration language), freevr_shmem.c (the shared arena, semaphores and
 * locks), freevr_process.c (vrConfigure, vrStart, vrExit: the processes),
 * freevr_render.c (callbacks, windows, projection, drawing) and
 * freevr_input.c (switches, valuators, sensors, travel). */
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
        int button;         /* 1..3: a mouse button, else a key */
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
