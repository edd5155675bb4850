/* vsv_player_state.c — the player's status lines and help text, its
 * accessors, and the state a multi-process back end copies from the
 * process that reads the input (vsv_player.h). */
#include "vsv_player_internal.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

void vsv_player_status(const vsv_player *p, char *buf, size_t cap)
{
    const vsv_clock *c = &p->clock;
    char when[64] = "-";
    const int step = p->shown >= 0 ? p->shown : c->step;
    if (c->nsteps)
        vsv_cal_format(vsv_meta_calendar(p->m), p->times[step], when, sizeof when);
    static const char *ends[] = {"", "  loop", "  bounce"};
    size_t n = (size_t)snprintf(buf, cap, "%s  step %d [0-%d]  %s %sx%g%s  %s%s%s%s%s\n", when, step, c->nsteps - 1,
                                c->playing ? "PLAY" : "PAUSE", c->speed < 0 ? "-" : "", fabs(c->speed), ends[c->ends],
                                p->ro.kind == VSV_RENDER_RAYCAST ? "raycast"
                                : p->ro.kind == VSV_RENDER_GL    ? "GPU raycast"
                                                                 : "shear-warp",
                                p->plan ? "  plan" : "", p->light ? "  lit" : "",
                                p->slices_on && p->nslices ? "  slices of " : "",
                                p->slices_on && p->nslices ? p->m->vars[p->slice_var].name : "");
    for (int s = 0; s < p->ns && n < cap; s++) {
        const int sel = s == p->selected;
        if (p->want[s])
            n += (size_t)snprintf(buf + n, cap - n, "%s%s%s %.1f%s", s ? " " : "", sel ? "[" : "", p->m->vars[s].name,
                                  p->layers[s].opacity, sel ? "]" : "");
        else
            n += (size_t)snprintf(buf + n, cap - n, "%s%s%s off%s", s ? " " : "", sel ? "[" : "", p->m->vars[s].name,
                                  sel ? "]" : "");
    }
    if (p->shown >= 0 && p->bad[p->shown] && n < cap)
        n += (size_t)snprintf(buf + n, cap - n, "\nstep %d DAMAGED, not drawn: %s", p->shown, p->bad[p->shown]);
    const char *why = NULL;
    if (vsv_player_waiting(p, &why) >= 0 && n < cap) /* (a URL's step on its way) */
        snprintf(buf + n, cap - n, why ? "\nstep %d not loaded yet, trying again: %s" : "\nstep %d loading", p->waiting,
                 why);
}

const char *vsv_player_help_text(void)
{
    return "space      play / pause\n"
           "right/left step forward / back (pauses)\n"
           "f / r      fast-forward / rewind: x2, x4 ... x64\n"
           "+ / -      speed up / slow down\n"
           "l          loop: off, on, bounce\n"
           "home / end jump to the start / the end\n"
           "tab / 1-9  select a species\n"
           "v          show / hide the selected species\n"
           "up / down  its opacity up / down\n"
           "m          switch renderer (shear-warp / raycast / GPU raycast)\n"
           "F2 F3 F4 F5 view: plan (map) / from the south / west / oblique\n"
           "g          lighting on / off\n"
           "c          slices on / off (given with --slice)\n"
           "w          the wind on / off (--trajectory, --barbs)\n"
           "p          screenshot (vsv-play-NNNN.png)\n"
           "h          this help\n"
           "q / esc    quit\n"
           "mouse      left drag: orbit; right drag: pan; wheel: zoom\n";
}

int vsv_player_quit(const vsv_player *p) { return p->quit; }
int vsv_player_help_shown(const vsv_player *p) { return p->help; }

const char *vsv_player_take_screenshot(vsv_player *p)
{
    if (!p->shot_pending)
        return NULL;
    p->shot_pending = 0;
    return p->shot;
}

const vsv_clock *vsv_player_clock(const vsv_player *p) { return &p->clock; }
const vsv_meta *vsv_player_meta(const vsv_player *p) { return p->m; }
int vsv_player_shown_step(const vsv_player *p) { return p->shown; }
int vsv_player_target_step(const vsv_player *p) { return p->target; }
double vsv_player_waited(const vsv_player *p) { return p->waited; }
int64_t vsv_player_step_time(const vsv_player *p, int t) { return t >= 0 && t < p->clock.nsteps ? p->times[t] : 0; }
void vsv_player_pager_stats(const vsv_player *p, vsv_pager_stats *st) { vsv_pager_stats_get(p->pager, st); }

void vsv_player_state_get(const vsv_player *p, vsv_player_state *st)
{
    memset(st, 0, sizeof *st);
    st->model = p->clock.model;
    st->speed = p->clock.speed;
    st->step = p->clock.step;
    st->playing = p->clock.playing;
    st->ends = p->clock.ends;
    st->renderer = p->ro.kind;
    st->selected = p->selected;
    st->help = p->help;
    st->light = p->light;
    st->slices = p->slices_on;
    st->wind = p->wind_on;
    st->nseeds = p->nseeds;
    memcpy(st->seeds, p->seeds, sizeof st->seeds);
    for (int s = 0; s < p->ns && s < VSV_PLAYER_MAX_SPECIES; s++) {
        st->visible[s] = p->want[s];
        st->opacity[s] = p->layers[s].opacity;
    }
}

int vsv_player_state_apply(vsv_player *p, const vsv_player_state *st, char *err, size_t cap)
{
    for (int s = 0; s < p->ns && s < VSV_PLAYER_MAX_SPECIES; s++) {
        if (p->want[s] != st->visible[s] || p->layers[s].opacity != st->opacity[s])
            p->dirty = 1;
        p->want[s] = p->layers[s].visible = st->visible[s];
        p->layers[s].opacity = st->opacity[s];
    }
    p->clock.model = st->model;
    p->clock.speed = st->speed;
    p->clock.step = st->step < 0 ? 0 : st->step >= p->clock.nsteps ? p->clock.nsteps - 1 : st->step;
    p->clock.playing = st->playing;
    p->clock.ends = st->ends;
    p->selected = st->selected >= 0 && st->selected < p->ns ? st->selected : 0;
    p->help = st->help;
    if (p->light != st->light || p->slices_on != st->slices)
        p->dirty = 1;
    p->light = st->light;
    p->slices_on = st->slices;
    if (p->wind_on != st->wind)
        p->wind_on = st->wind, p->lines_key[0] = -2;
    for (int i = p->nseeds; i < st->nseeds && i < VSV_PLAYER_MAX_SEEDS; i++) /* the seeds new to p */
        if (vsv_player_seed_step(p, st->seeds[i], (int)st->seeds[i][3], err, cap))
            return -1;
    if (st->renderer >= 0 && st->renderer != p->ro.kind) /* (-1: each display chose) */
        return vsv_player_do(p,
                             st->renderer == VSV_RENDER_RAYCAST ? "renderer raycast"
                             : st->renderer == VSV_RENDER_GL    ? "renderer gl"
                                                                : "renderer shearwarp",
                             err, cap);
    return 0;
}

void vsv_player_tick(vsv_player *p, double dt) { vsv_clock_tick(&p->clock, dt); }
