/* vsv_flow.h — the wind drawn in a scene as the tools' options ask for it
 * (vsv-render, vsv-play): trajectories (--trajectory, --seed-line,
 * --seed-slice, --traj-from, --traj-for), the path of the air up to each
 * frame's time, and wind arrows on horizontal planes (--barbs), as the
 * scene's lines (vsv_scene_line). Part of the public interface of
 * libvesuvius-render (include after vsv_render.h). */
#ifndef VSV_FLOW_H
#define VSV_FLOW_H

#include "vsv_render.h"

#ifdef __cplusplus
extern "C" {
#endif

VSV_API_BEGIN

/* A colour: white grey red orange yellow green cyan blue purple, or
 * #RRGGBB (0..1 out, gamma-encoded as given). 0 or -1. */
int vsv_colour_parse(const char *s, float rgb[3]);

/* The options as given (each checked for its syntax by vsv_flow_opt,
 * against the file by vsv_flow_open): plain info, borrowed strings. */
#define VSV_FLOW_MAX 64
typedef struct vsv_flow_opts {
    const char *traj[VSV_FLOW_MAX]; /* --trajectory LAT,LON,HEIGHT[:COLOUR] */
    int ntraj;
    const char *line[8]; /* --seed-line LAT,LON,H:LAT,LON,H:N[:COLOUR] */
    int nline;
    const char *slice[8]; /* --seed-slice HEIGHT:EVERY[:COLOUR] */
    int nslice;
    const char *barbs[8]; /* --barbs HEIGHT[:EVERY] */
    int nbarbs;
    const char *from; /* --traj-from T (a step or a time; default the first step) */
    int64_t dur;      /* --traj-for DURATION (seconds; 0: to the last step) */
    double radius;    /* --tube-radius METRES (0: the default) */
    int steady;       /* --streamlines: each frame's paths are streamlines of its wind */
} vsv_flow_opts;

/* Takes option opt (without its dashes: "trajectory", "seed-line", "streamlines" (arg unused),
 * "seed-slice", "barbs", "traj-from", "traj-for", "tube-radius") and its
 * argument into o. 0, or VSV_EINVAL with "--opt ARG: why" in msg. */
int vsv_flow_opt(vsv_flow_opts *o, const char *opt, const char *arg, char *msg, size_t cap);
/* 1 when o asks for anything drawn. */
int vsv_flow_any(const vsv_flow_opts *o);

typedef struct vsv_flow vsv_flow;
/* Reads o against f (borrowed; it must outlive the flow) and integrates
 * the trajectories (vsv_traj_run, from --traj-from for --traj-for, a point
 * recorded every VSV_FLOW_EVERY seconds). VSV_ENOTFOUND ("no wind stored")
 * when f has no wind, VSV_EINVAL ("--opt ARG: why": a seed outside the
 * grid or under the ground, a time outside the file's), VSV_ENOMEM or a
 * read error, with the reason in msg. *out is set even on failure: free
 * it with vsv_flow_free either way. */
#define VSV_FLOW_EVERY 300
int vsv_flow_open(vsv_file *f, const vsv_flow_opts *o, vsv_flow **out, char *msg, size_t cap);
/* With --streamlines the paths are instead streamlines of each frame's
 * wind, held still (vsv_traj_freeze), from every seed for --traj-for of
 * travel (default VSV_FLOW_STREAM seconds), drawn whole; --traj-from is
 * unused. They are integrated when a frame of another step is asked for
 * (the first at open, to check the seeds). */
#define VSV_FLOW_STREAM 3600
void vsv_flow_free(vsv_flow *fl);
/* The lines of step `step` (time vsv_file_time): each trajectory from its
 * seed up to that time (the point at that time interpolated between the
 * two around it), an arrowhead at its head, none before its start; with
 * `barbs`, the wind arrows of each --barbs plane at that step (the wind
 * decoded with the flow's own decoder). *lines (borrowed until the next
 * call or free) and *n. Tubes are `radius` world metres (--tube-radius,
 * else 1/300 of the domain's larger side), arrows 0.6 of that. 0, a read
 * error with the reason in msg, or VSV_ERANGE when a --barbs plane has no
 * arrow there (no air at its height: msg says which; the rest is drawn and
 * *n counts it). */
int vsv_flow_frame(vsv_flow *fl, int step, int trajectories, int barbs, const vsv_scene_line **lines, int *n, char *msg,
                   size_t cap);
/* One more trajectory: the air at projected (x, y) and height z (as
 * vsv_traj_run's seed) leaving at step `step`, followed for --traj-for (or
 * to the last step), drawn in the next colour of the palette. 0, or
 * VSV_EINVAL (the seed outside the grid or under the ground) or an error
 * of vsv_traj, with the reason in msg. */
int vsv_flow_add(vsv_flow *fl, const double seed[3], int step, char *msg, size_t cap);

/* The wind arrows' scale: an arrow VSV_FLOW_BARB m/s long spans the
 * spacing between arrows. */
#define VSV_FLOW_BARB 20
/* The number of trajectories (seeds that started), for messages. */
int vsv_flow_paths(const vsv_flow *fl);

VSV_API_END

#ifdef __cplusplus
}
#endif
#endif
