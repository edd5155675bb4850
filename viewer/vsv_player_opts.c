/* vsv_player_opts.c — the player's options and the command-line options
 * vsv-play and vsv-play-freevr share (--colormap, --log, --range, --iso,
 * the wind's), taken alike in both and checked against the file when it
 * is opened; the wind's lines of the step shown and the trajectories
 * seeded while playing. */
#include "vsv_player_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void vsv_player_opts_init(vsv_player_opts *o)
{
    memset(o, 0, sizeof *o);
    o->renderer = VSV_RENDER_SHEARWARP;
    o->terrain = 1;
    o->sun_az = 315;
    o->sun_el = 45;
    o->slice_range[0] = o->slice_range[1] = NAN;
}

int vsv_player_iso_option(vsv_player_opts *o, const char *arg, char *msg, size_t cap)
{
    if (o->nisos >= VSV_SCENE_ISO_MAX) {
        snprintf(msg, cap, "--iso %s: at most %d isosurfaces", arg, VSV_SCENE_ISO_MAX);
        return VSV_EINVAL;
    }
    o->isos[o->nisos++] = arg;
    return 0;
}

int vsv_player_open_isos(vsv_player *p, const vsv_player_opts *o, char *err, size_t cap)
{
    for (int i = 0; i < o->nisos && i < VSV_SCENE_ISO_MAX; i++) {
        vsv_iso_spec sp;
        if (vsv_iso_parse(p->m, o->isos[i], &sp, err, cap))
            return VSV_EINVAL;
        char why[600];
        const int rc = vsv_iso_in_range(p->f, o->isos[i], &sp, why, sizeof why);
        if (rc) {
            snprintf(err, cap, "%s: %s", o->path, why);
            return rc;
        }
        p->isos[p->nisos++] = (vsv_scene_iso){sp.species, sp.value, {sp.rgb[0], sp.rgb[1], sp.rgb[2]}};
    }
    return 0;
}

int vsv_player_tf_option(vsv_player_opts *o, const char *opt, const char *arg, char *msg, size_t cap)
{
    if (o->ntf_changes >= VSV_PLAYER_MAX_TF_CHANGES) {
        snprintf(msg, cap, "--%s: at most %d colour and scale changes", opt, VSV_PLAYER_MAX_TF_CHANGES);
        return VSV_EINVAL;
    }
    const int rc = vsv_tf_change_parse(opt, arg, &o->tf_changes[o->ntf_changes], msg, cap);
    o->ntf_changes += !rc;
    return rc;
}

int vsv_player_option(vsv_player_opts *o, const char *opt, const char *arg, char *msg, size_t cap)
{
    if (!strcmp(opt, "iso"))
        return vsv_player_iso_option(o, arg, msg, cap);
    if (!strcmp(opt, "colormap") || !strcmp(opt, "log") || !strcmp(opt, "range"))
        return vsv_player_tf_option(o, opt, arg, msg, cap);
    return vsv_flow_opt(&o->flow, opt, arg, msg, cap);
}

int vsv_player_open_flow(vsv_player *p, const vsv_player_opts *o, char *err, size_t cap)
{
    p->flow_opts = o->flow;
    p->lines_key[0] = p->lines_key[1] = -2;
    if (!vsv_flow_any(&o->flow))
        return 0;
    char why[512];
    if (vsv_flow_open(p->f, &o->flow, &p->flow, why, sizeof why)) {
        snprintf(err, cap, "%s: %s", p->path, why);
        return -1;
    }
    p->wind_on = 1;
    return 0;
}

void vsv_player_wind_lines(vsv_player *p)
{
    const int key[2] = {p->shown, p->wind_on};
    if (!p->flow || p->shown < 0 || !memcmp(key, p->lines_key, sizeof key))
        return;
    memcpy(p->lines_key, key, sizeof key);
    char why[512];
    const int rc = vsv_flow_frame(p->flow, p->shown, 1, 1, &p->lines, &p->nlines, why, sizeof why);
    if (rc && rc != VSV_ERANGE)
        p->nlines = 0; /* (a read error: the step shows without its wind; a plane
                          with no air at its height just shows no arrows) */
    p->dirty = 1;
}

int vsv_player_add_trajectory(vsv_player *p, const char *lat, const char *lon, const char *height, char *err,
                              size_t cap)
{
    char *e1 = NULL, *e2 = NULL, *e3 = NULL;
    const double la = lat ? strtod(lat, &e1) : NAN, lo = lon ? strtod(lon, &e2) : NAN,
                 h = height ? strtod(height, &e3) : NAN;
    double seed[3] = {0, 0, h};
    if (!isfinite(la) || !isfinite(lo) || !isfinite(h) || *e1 || *e2 || (*e3 && strcmp(e3, "m"))) {
        snprintf(err, cap, "trajectory: LAT LON HEIGHT (degrees, metres)");
        return -1;
    }
    if (vsv_proj_forward(&p->m->proj, la, lo, &seed[0], &seed[1])) {
        snprintf(err, cap, "trajectory: %s %s: not in the grid's projection", lat, lon);
        return -1;
    }
    return vsv_player_add_seed(p, seed, err, cap);
}

int vsv_player_add_seed(vsv_player *p, const double seed[3], char *err, size_t cap)
{
    return vsv_player_seed_step(p, seed, p->clock.step, err, cap); /* (the step shown, or being sought) */
}

int vsv_player_seed_world(vsv_player *p, const double world[3], char *err, size_t cap)
{
    double ux, uy;
    vsv_scene_units(p->m, &ux, &uy);
    const double seed[3] = {world[0] / ux, world[1] / uy, world[2] / (p->exaggeration > 0 ? p->exaggeration : 1)};
    return vsv_player_add_seed(p, seed, err, cap);
}

int vsv_player_seed_step(vsv_player *p, const double seed[3], int step, char *err, size_t cap)
{
    char why[512];
    if (p->nseeds >= VSV_PLAYER_MAX_SEEDS) {
        snprintf(err, cap, "trajectory: at most %d seeded while playing", VSV_PLAYER_MAX_SEEDS);
        return -1;
    }
    if (!p->flow && vsv_flow_open(p->f, &p->flow_opts, &p->flow, why, sizeof why)) {
        vsv_flow_free(p->flow);
        p->flow = NULL;
        snprintf(err, cap, "trajectory: %s", why);
        return -1;
    }
    if (vsv_flow_add(p->flow, seed, step, why, sizeof why)) {
        snprintf(err, cap, "trajectory: %s", why);
        return -1;
    }
    const double rec[4] = {seed[0], seed[1], seed[2], step};
    memcpy(p->seeds[p->nseeds++], rec, sizeof rec);
    p->wind_on = 1;
    p->lines_key[0] = -2; /* made again */
    p->dirty = 1;
    return 0;
}
