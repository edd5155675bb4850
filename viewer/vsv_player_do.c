/* vsv_player_do.c — the player's action language (vsv_player_do): the
 * words a key, a script or the wand sends, and what each one changes. */
#include "vsv_player_internal.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

static int find_species(const vsv_player *p, const char *name)
{
    for (int s = 0; s < p->ns; s++)
        if (!strcasecmp(p->m->vars[s].name, name))
            return s;
    return -1;
}

static int num(const char *s, double *v)
{
    char *end;
    if (!s)
        return -1;
    *v = strtod(s, &end);
    return end == s || *end || !isfinite(*v) ? -1 : 0; /* inf, nan: not numbers here */
}

/* Fails the action (-1) with the message unless cond holds. */
#define NEED(cond, ...)                                                                                                \
    do {                                                                                                               \
        if (!(cond)) {                                                                                                 \
            snprintf(err, cap, __VA_ARGS__);                                                                           \
            return -1;                                                                                                 \
        }                                                                                                              \
    } while (0)

/* The clock's actions: play, pause, step, seek, speed, loop and the like; 1 when verb is none of them. */
static int do_clock(vsv_player *p, const char *verb, const char *a1, char *err, size_t cap)
{
    vsv_clock *c = &p->clock;
    double v;
    if (!strcmp(verb, "play"))
        vsv_clock_play(c);
    else if (!strcmp(verb, "pause"))
        vsv_clock_pause(c);
    else if (!strcmp(verb, "toggle-play"))
        vsv_clock_toggle(c);
    else if (!strcmp(verb, "step")) {
        v = 1;
        NEED(!a1 || (!num(a1, &v) && fabs(v) <= 1e9), "step: '%s' is not a number of steps", a1);
        vsv_clock_step(c, (int)v);
    } else if (!strcmp(verb, "seek")) {
        NEED(a1, "seek: needs an ISO time or a step index");
        vsv_timesel sel;
        char why[300];
        NEED(!vsv_timesel_parse(a1, p->times, c->nsteps, VSV_TIMESEL_ONE | VSV_TIMESEL_CAL(vsv_meta_calendar(p->m)),
                                &sel, why, sizeof why),
             "seek %s: %s", a1, why);
        vsv_clock_seek_step(c, sel.first);
    } else if (!strcmp(verb, "speed")) {
        NEED(!num(a1, &v) && v != 0, "speed: needs a non-zero number (negative plays backwards)");
        vsv_clock_set_speed(c, v);
    } else if (!strcmp(verb, "faster") || !strcmp(verb, "slower")) {
        vsv_clock_set_speed(c, !strcmp(verb, "faster") ? c->speed * 2 : c->speed / 2);
    } else if (!strcmp(verb, "forward") || !strcmp(verb, "rewind")) {
        vsv_clock_faster(c, !strcmp(verb, "forward") ? 1 : -1);
    } else if (!strcmp(verb, "loop")) {
        if (!a1)
            c->ends = (c->ends + 1) % 3;
        else if (!strcmp(a1, "on"))
            c->ends = VSV_CLOCK_LOOP;
        else if (!strcmp(a1, "off"))
            c->ends = VSV_CLOCK_STOP;
        else if (!strcmp(a1, "bounce"))
            c->ends = VSV_CLOCK_BOUNCE;
        else
            NEED(0, "loop: on, off or bounce");
    } else if (!strcmp(verb, "start")) {
        vsv_clock_seek_step(c, 0);
    } else if (!strcmp(verb, "end")) {
        vsv_clock_seek_step(c, c->nsteps - 1);
    } else {
        return 1;
    }
    return 0;
}

/* The species' actions: show, hide, opacity and select; 1 when verb is none of them. */
static int do_species(vsv_player *p, const char *verb, const char *a1, const char *a2, char *err, size_t cap)
{
    double v;
    if (!strcmp(verb, "toggle") || !strcmp(verb, "show") || !strcmp(verb, "hide")) {
        const int s = a1 ? find_species(p, a1) : p->selected;
        NEED(s >= 0, "%s: no species '%s' (the file has %d)", verb, a1 ? a1 : "", p->ns);
        p->want[s] = !strcmp(verb, "toggle") ? !p->want[s] : !strcmp(verb, "show");
        p->layers[s].visible = p->want[s];
        p->dirty = 1;
    } else if (!strcmp(verb, "opacity")) {
        const int s = a1 && !strcmp(a1, "-") ? p->selected : a1 ? find_species(p, a1) : -1;
        NEED(s >= 0, "opacity: no species '%s'", a1 ? a1 : "");
        const int rel = a2 && (a2[0] == '+' || a2[0] == '-');
        NEED(!num(a2, &v) && (rel || v >= 0), "opacity: needs a value >= 0 (or +D / -D to change it)");
        v = rel ? p->layers[s].opacity + v : v;
        p->layers[s].opacity = (float)(v < 0 ? 0 : round(v * 1000) / 1000);
        p->dirty = 1;
    } else if (!strcmp(verb, "select")) {
        NEED(a1, "select: +1, -1 or a species name");
        if (!strcmp(a1, "+1") || !strcmp(a1, "-1"))
            p->selected = (p->selected + (a1[0] == '+' ? 1 : p->ns - 1)) % p->ns;
        else if (a1[0] == '#' && !num(a1 + 1, &v)) {
            NEED(v >= 0 && v < p->ns, "select: no species number %s", a1 + 1);
            p->selected = (int)v;
        } else {
            const int s = find_species(p, a1);
            NEED(s >= 0, "select: no species '%s'", a1);
            p->selected = s;
        }
    } else {
        return 1;
    }
    return 0;
}

/* The camera's actions: camera, view, orbit, zoom and pan; 1 when verb is none of them. */
static int do_camera(vsv_player *p, const char *verb, const char *a1, const char *a2, const char *a3, char *err,
                     size_t cap)
{
    double v, v2, v3;
    if (!strcmp(verb, "camera")) {
        NEED(!num(a1, &v) && !num(a2, &v2) && (!a3 || !num(a3, &v3)), "camera: needs AZ EL [DIST]");
        p->az = v, p->el = fmax(-89.9, fmin(89.9, v2)), p->dist = a3 ? fmax(0, v3) : 0;
        p->plan = 0;
        memset(p->pan, 0, sizeof p->pan);
    } else if (!strcmp(verb, "view")) {
        /* vsv-render's --view presets */
        double az, el;
        const int plan = vsv_view_preset(a1, &az, &el);
        NEED(plan >= 0, "view: plan, south, west or oblique");
        p->plan = plan;
        p->plan_zoom = 1;
        p->az = az, p->el = el, p->dist = 0;
        memset(p->pan, 0, sizeof p->pan);
    } else if (!strcmp(verb, "orbit")) {
        NEED(!num(a1, &v) && !num(a2, &v2), "orbit: needs DAZ DEL");
        if (p->plan) /* out of the map view: from straight above */
            p->plan = 0, p->az = 0, p->el = 89.9;
        p->az = fmod(p->az + v + 360, 360), p->el = fmax(-89.9, fmin(89.9, p->el + v2));
    } else if (!strcmp(verb, "zoom")) {
        NEED(!num(a1, &v) && v > 0, "zoom: needs a factor > 0");
        if (p->plan) {
            p->plan_zoom *= v;
        } else if (!(p->dist > 0)) {
            vsv_camera cam;
            vsv_player_camera(p, 100, 100, &cam);
            double mn[3], mx[3];
            vsv_player_bounds(p, mn, mx);
            double d2 = 0;
            for (int i = 0; i < 3; i++)
                d2 += pow(0.5 * (mn[i] + mx[i]) + p->pan[i] - cam.pos[i], 2);
            p->dist = sqrt(d2);
        }
        if (!p->plan)
            p->dist /= v;
    } else if (!strcmp(verb, "pan")) {
        NEED(!num(a1, &v) && !num(a2, &v2), "pan: needs DX DY (fractions of the view)");
        vsv_camera cam;
        vsv_player_camera(p, 100, 100, &cam);
        double f[3] = {cam.dir[0], cam.dir[1], cam.dir[2]}, r[3], u[3];
        const double fl = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
        for (int i = 0; i < 3; i++)
            f[i] /= fl;
        r[0] = f[1] * cam.up[2] - f[2] * cam.up[1], r[1] = f[2] * cam.up[0] - f[0] * cam.up[2],
        r[2] = f[0] * cam.up[1] - f[1] * cam.up[0];
        const double rl = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
        for (int i = 0; i < 3; i++)
            r[i] /= rl > 0 ? rl : 1;
        u[0] = r[1] * f[2] - r[2] * f[1], u[1] = r[2] * f[0] - r[0] * f[2], u[2] = r[0] * f[1] - r[1] * f[0];
        double mn[3], mx[3];
        vsv_player_bounds(p, mn, mx);
        const double span = fmax(mx[0] - mn[0], mx[1] - mn[1]);
        for (int i = 0; i < 3; i++)
            p->pan[i] -= (v * r[i] + v2 * u[i]) * span;
    } else {
        return 1;
    }
    return 0;
}

/* The rest of action after its verb, as one file name: blanks at its ends
 * dropped, then one pair of double quotes around it; into out. 0, or -1
 * when there is none or it does not fit. */
static int rest_as_name(const char *action, char *out, size_t cap)
{
    const char *s = action + strspn(action, " \t\r\n");
    s += strcspn(s, " \t\r\n");
    s += strspn(s, " \t\r\n");
    size_t n = strlen(s);
    while (n && strchr(" \t\r\n", s[n - 1]))
        n--;
    if (n >= 2 && s[0] == '"' && s[n - 1] == '"')
        s++, n -= 2;
    if (!n || n >= cap)
        return -1;
    memcpy(out, s, n);
    out[n] = 0;
    return 0;
}

int vsv_player_do(vsv_player *p, const char *action, char *err, size_t cap)
{
    char buf[1100], *save = NULL;
    snprintf(buf, sizeof buf, "%s", action);
    char *verb = strtok_r(buf, " \t\r\n", &save);
    char *a1 = strtok_r(NULL, " \t\r\n", &save), *a2 = strtok_r(NULL, " \t\r\n", &save);
    char *a3 = strtok_r(NULL, " \t\r\n", &save);
    err[0] = 0;
    if (!verb)
        return 0;
    int rc = do_clock(p, verb, a1, err, cap);
    if (rc == 1)
        rc = do_species(p, verb, a1, a2, err, cap);
    if (rc == 1)
        rc = do_camera(p, verb, a1, a2, a3, err, cap);
    if (rc != 1)
        return rc;
    if (!strcmp(verb, "light") || !strcmp(verb, "slices") || !strcmp(verb, "wind")) {
        int *on = !strcmp(verb, "light") ? &p->light : !strcmp(verb, "wind") ? &p->wind_on : &p->slices_on;
        NEED(!a1 || !strcmp(a1, "on") || !strcmp(a1, "off"), "%s: on or off (nothing: switch)", verb);
        NEED(on != &p->slices_on || p->nslices, "slices: none given (vsv-play --slice SPEC)");
        NEED(on != &p->wind_on || p->flow, "wind: none given (vsv-play --trajectory, --barbs, ...)");
        *on = a1 ? !strcmp(a1, "on") : !*on;
        p->dirty = 1;
    } else if (!strcmp(verb, "trajectory")) {
        return vsv_player_add_trajectory(p, a1, a2, a3, err, cap);
    } else if (!strcmp(verb, "renderer")) {
        int kind = p->ro.kind;
        if (a1 && !strcmp(a1, "raycast"))
            kind = VSV_RENDER_RAYCAST;
        else if (a1 && !strcmp(a1, "shearwarp"))
            kind = VSV_RENDER_SHEARWARP;
        else if (a1 && !strcmp(a1, "gl"))
            kind = VSV_RENDER_GL;
        else if (a1 && !strcmp(a1, "switch")) /* shear-warp, raycast, the GPU's where it runs */
            kind = kind == VSV_RENDER_SHEARWARP             ? VSV_RENDER_RAYCAST
                   : kind == VSV_RENDER_RAYCAST && p->gl_ok ? VSV_RENDER_GL
                                                            : VSV_RENDER_SHEARWARP;
        else
            NEED(0, "renderer: raycast, shearwarp, gl or switch");
        if (kind != p->ro.kind) {
            char why[1024];
            NEED(!vsv_player_use_renderer(p, kind, why, sizeof why), "renderer %s: %s",
                 kind == VSV_RENDER_GL ? "gl" : "", why);
        }
    } else if (!strcmp(verb, "help")) {
        p->help = !p->help;
    } else if (!strcmp(verb, "screenshot")) {
        NEED(a1, "screenshot: needs a FILE.png");
        NEED(!rest_as_name(action, p->shot, sizeof p->shot), "screenshot: a name of at most %zu bytes",
             sizeof p->shot - 1);
        p->shot_pending = 1; /* (the whole rest of the line: a name may hold blanks) */
    } else if (!strcmp(verb, "quit")) {
        p->quit = 1;
    } else {
        NEED(0, "unknown action '%s'", verb);
    }
    return 0;
}
#undef NEED

/* ---------------------------------------------------------------- status */
