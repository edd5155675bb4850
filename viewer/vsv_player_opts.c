/* vsv_player_opts.c — the player's options and the command-line options
 * vsv-play and vsv-play-freevr share (--colormap, --log, --range, --iso),
 * taken alike in both and checked against the file when it is opened. */
#include "vsv_player_internal.h"

#include <math.h>
#include <stdio.h>
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
