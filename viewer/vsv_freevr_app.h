/* vsv_freevr_app.h — what the FreeVR back end's two halves share: the main
 * process (vsv-play-freevr.c: options, the wand, the clock, publishing
 * ticks, the life cycle) and its render processes (vsv_freevr_draw.c: one
 * frame per window, each eye's picture, the wand and the panel). Private to
 * the back end; no FreeVR types in it. */
#ifndef VSV_FREEVR_APP_H
#define VSV_FREEVR_APP_H

#include "vsv_player.h"
#include "vsv_room.h"

#include <stdio.h>

/* The back end's data in every tick (vsv_room: plain data). */
typedef struct vsv_fv_tick {
    vsv_player_state st;
    double place[16]; /* world metres -> room (feet), navigation included */
    double wand[3];   /* the wand in the room (feet) */
    double wdir[3];   /* where it points (unit) */
    double tip[3];    /* its tip: what the scene scales about */
    double lh;        /* the panel's line height (feet); 0: no panel */
    double panel[9];  /* its top-left corner, right and down directions */
    double fps;       /* the slowest window's frames a second; < 0: not shown */
    int nsteps;
} vsv_fv_tick;

/* Set by the main process before vrStart, read by the render processes
 * (copied at the fork). */
typedef struct vsv_fv_app {
    vsv_player_opts opts; /* the render processes' player (external) */
    vsv_room *room;
    double scale; /* --render-scale */
    int trace_fd; /* --trace: lines appended here; -1 none */
    double t0;    /* vsv_room_clock() at the start */
    int wand;     /* draw the wand's pointer */
} vsv_fv_app;

extern vsv_fv_app vsv_fv;

/* The render processes' callbacks (vsv_freevr_draw.c), set before vrStart:
 * once per window (its GL context current), once per window per frame
 * before its eyes, once per eye, once per window at the end. ri is
 * FreeVR's vrRenderInfo, unused: the GL state says everything. */
void vsv_fv_display_init(void);
void vsv_fv_display_frame(void *ri);
void vsv_fv_display_eye(void *ri);
void vsv_fv_display_exit(void);

/* The panel's lines under the time (the step of nsteps, play state, speed,
 * ends, the selected species, the frame rate with fps, a damaged step) of
 * tick t showing step of m; t NULL: the widest they can be (the panel is
 * sized for them, so it keeps its size). */
void vsv_fv_panel_lines(const vsv_fv_tick *t, const vsv_meta *m, int nsteps, int step, int damaged, int fps, char *buf,
                        size_t cap);

#endif
