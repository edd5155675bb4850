/* vsv_player_internal.h — the player's state, shared by vsv_player.c (the
 * file, pager and pictures), vsv_player_do.c (the actions) and
 * vsv_player_state.c (the status lines, accessors and the state a
 * multi-process back end copies). */
#ifndef VSV_PLAYER_INTERNAL_H
#define VSV_PLAYER_INTERNAL_H

#include "vsv_player.h"

struct vsv_player {
    vsv_file *f;
    const vsv_meta *m;
    vsv_meta *placed; /* m at each placement of a moving grid (GRID's first) */
    char path[1024];
    int ns;
    vsv_pager *pager;
    vsv_clock clock;
    int64_t *times;
    vsv_tf *tf;
    vsv_volume **cur;    /* per species: the volume shown (step -1: none) */
    vsv_volume **alt;    /* nowait: per species, the next step's, swapped in when all are there */
    int nowait;          /* never waits for the pager: a URL (the main thread never waits for a server) */
    int waiting;         /* the step not shown yet for want of its bricks (being fetched, decoded), or -1 */
    int stall_step;      /* the step whose transfer failed last (tried again), or -1 once one shows */
    int stall_news;      /* that step, not yet taken by vsv_player_stalled, or -1 */
    char stall[1024];    /* why (the pager's message) */
    vsv_layer *layers;   /* per species */
    unsigned char *want; /* per species: visible */
    int selected;
    int shown;     /* the step on screen; -1 before the first */
    int target;    /* the step meant to be on screen (the clock's, at the stride) */
    int stride;    /* playing fast: every stride-th step shown (vsv_clock_stride) */
    double frame;  /* wall seconds between updates (smoothed); 0 before the second */
    int idle;      /* the last frame drew nothing new (vsv_player_image) */
    double waited; /* wall seconds the last update waited for its step */
    char **bad;    /* per step: why it cannot be decoded, or NULL */
    int news;      /* a step found damaged and not yet taken, or -1 */
    double exaggeration;
    int terrain;
    /* camera: an orbit about the scene centre (dist 0: the box filling the
     * view), or a plan view zoomed by plan_zoom; moved by pan (world metres) */
    double az, el, dist, pan[3], plan_zoom;
    int plan;
    /* lighting and slices */
    int light, slices_on, nslices, slice_var;
    double sun_az, sun_el;
    vsv_slice slices[8];
    vsv_tf slice_tf;
    double slice_fixed[2];                 /* --slice-range, or NaN: each step's own */
    int slice_key[4];                      /* what slice_tf's range was taken for (shown,
                                              slices_on, nslices, slice_var) */
    vsv_scene_iso isos[VSV_SCENE_ISO_MAX]; /* --iso: layer = the species */
    int nisos;
    /* the wind (vsv_flow.h): its options, the flow made from them, whether
     * it shows, and the lines of the step shown (for lines_key) */
    vsv_flow_opts flow_opts;
    vsv_flow *flow;
    int wind_on, nlines, lines_key[2];
    int nseeds; /* the paths seeded while playing: where and when (the state's) */
    double seeds[VSV_PLAYER_MAX_SEEDS][4];
    const vsv_scene_line *lines;
    unsigned char *need; /* per species: pinned (drawn, the slices' or an isosurface's species) */
    uint64_t *gens;      /* per species: the gen of the volume shown (external) */
    /* rendering */
    vsv_render_opts ro; /* ro.kind: the renderer in use (VSV_RENDER_GL: gl) */
    vsv_renderer *r;    /* the CPU renderer (the last CPU kind used) */
    vsv_gl *gl;         /* the GPU raycaster, once asked for */
    int gl_ok;          /* it could be made */
    int no_renderer;    /* never draws: the renderer is only named */
    int gl_by_caller;   /* gl: the caller's raycasters draw (vsv_player_draw) */
    size_t gpu_budget;
    float *rgba, *depth;
    unsigned char *rgb;
    /* the annotated copy of the frame (vsv_player_annotated) */
    float *argba;
    unsigned char *argb;
    int *sidx; /* per layer: its species (the identity) */
    int iw, ih;
    size_t icap; /* pixels the image buffers hold */
    vsv_camera last_cam;
    int dirty;
    float bg[3];
    /* back-end state */
    int quit, help;
    char err[1024];
    char shot[1024];
    int shot_pending;
};

/* Makes kind the renderer in use: the CPU's (started anew), or the GPU's
 * (made once, in the GL context current now). 0, or -1 with why. */
int vsv_player_use_renderer(vsv_player *p, int kind, char *why, size_t cap);

/* The isosurfaces of o (--iso), parsed against p's file into p->isos:
 * 0, VSV_EINVAL with the reason in err, or VSV_ERANGE (a value the file
 * never reaches; "FILE: --iso ...: no surface: ...") (vsv_player_opts.c). */
int vsv_player_open_isos(vsv_player *p, const vsv_player_opts *o, char *err, size_t cap);
/* The trajectories and wind arrows of o, integrated through p's file
 * (vsv_flow_open): 0, or -1 with "FILE: why" in err ("no wind stored"). */
int vsv_player_open_flow(vsv_player *p, const vsv_player_opts *o, char *err, size_t cap);
/* A path from projected seed (x, y, height) leaving at step, recorded in
 * p->seeds: 0, or -1 with the reason in err. */
int vsv_player_seed_step(vsv_player *p, const double seed[3], int step, char *err, size_t cap);
/* p->lines made for the step shown when it or wind_on changed. */
void vsv_player_wind_lines(vsv_player *p);

#endif
