/* vsv_player.c — see vsv_player.h. */
#include "vsv_player_internal.h"

#include "vsv_gl.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <time.h>

/* The grid as it lies at the step shown: a moving nest's placement then
 * (p->placed holds one view per placement). */
static const vsv_meta *shown_meta(const vsv_player *p)
{
    const int64_t t = p->shown >= 0 ? p->times[p->shown] : p->times[0];
    int i = 0;
    while (i < p->m->nmoves && p->m->moves[i].time <= t)
        i++;
    return &p->placed[i];
}

static vsv_scene scene(const vsv_player *p)
{
    vsv_scene sc = {.meta = shown_meta(p),
                    .layers = p->layers,
                    .nlayers = p->ns,
                    .exaggeration = p->exaggeration,
                    .show_terrain = p->terrain};
    if (p->light)
        vsv_scene_sun(&sc, p->sun_az, p->sun_el);
    if (p->slices_on && p->nslices) {
        sc.slices = p->slices;
        sc.nslices = p->nslices;
        sc.slice_layer = p->slice_var;
        sc.slice_tf = &p->slice_tf;
    }
    sc.isos = p->isos;
    sc.nisos = p->nisos;
    sc.lines = p->lines;
    sc.nlines = p->wind_on ? p->nlines : 0;
    return sc;
}

/* The slices' colours over the range of what they show in the step shown
 * (vsv_slice_range, as vsv-render colours them), taken again only when the
 * step or the slices change; a fixed --slice-range stays. */
static void colour_slices(vsv_player *p)
{
    const int key[4] = {p->shown, p->slices_on, p->nslices, p->slice_var};
    if (!p->slices_on || !p->nslices || isfinite(p->slice_fixed[0]) || !memcmp(key, p->slice_key, sizeof key))
        return;
    memcpy(p->slice_key, key, sizeof key);
    /* the scene drawn (its ground too: what lies below it is not shown) */
    const vsv_scene sc = scene(p);
    double lo, hi;
    if (p->slice_var < 0 || !p->layers[p->slice_var].vol || vsv_slice_range(&sc, &lo, &hi))
        return;
    if (p->slice_tf.scale == VSV_SCALE_LOG)
        lo = lo > 0 ? lo : hi * 1e-6;
    if (!(hi > lo))
        hi = lo + (lo ? fabs(lo) * 1e-6 : 1e-30);
    vsv_tf t = p->slice_tf;
    t.lo = lo, t.hi = hi;
    if (!vsv_tf_prepare(&t)) {
        p->slice_tf = t;
        p->dirty = 1;
    }
}

/* The species to pin: those drawn, and the slices' while they show. */
static const unsigned char *needed(vsv_player *p)
{
    for (int s = 0; s < p->ns; s++)
        p->need[s] = p->want[s] || (p->slices_on && p->nslices && s == p->slice_var);
    for (int i = 0; i < p->nisos; i++)
        p->need[p->isos[i].layer] = 1;
    return p->need;
}

int vsv_player_use_renderer(vsv_player *p, int kind, char *why, size_t cap)
{
    if (p->no_renderer || (kind == VSV_RENDER_GL && p->gl_by_caller)) { /* (only named: others draw) */
    } else if (kind == VSV_RENDER_GL) {
        if (!p->gl) {
            vsv_gl_opts go;
            vsv_gl_opts_init(&go);
            go.threads = p->ro.threads;
            if (p->gpu_budget)
                go.budget = p->gpu_budget;
            if (vsv_gl_create(&go, &p->gl, why, cap))
                return -1;
            p->gl_ok = 1;
        }
    } else {
        vsv_renderer *r = NULL;
        vsv_render_opts ro = p->ro;
        ro.kind = kind;
        if (vsv_renderer_create(&ro, &r)) {
            snprintf(why, cap, "cannot start it");
            vsv_renderer_free(r);
            return -1;
        }
        vsv_renderer_free(p->r);
        p->r = r;
    }
    p->ro.kind = kind;
    p->dirty = 1;
    return 0;
}

/* Each species' transfer function, volume and layer, shown as --species says: 0 or -1 / VSV_EINVAL, the reason in
 * err. */
static int open_species(vsv_player *p, const vsv_player_opts *o, char *err, size_t cap)
{
    float *opac = malloc((size_t)p->ns * sizeof *opac);
    int rc = 0;
    if (!opac) {
        snprintf(err, cap, "out of memory");
        return -1;
    }
    for (int s = 0; s < p->ns; s++) /* -1: hidden (v shows it) */
        opac[s] = !o->species && vsv_meta_default_shown(p->m, s) ? 1 : -1;
    if (o->species && (rc = vsv_species_parse(p->m, o->species, o->path, opac, err, cap)))
        goto fail;
    for (int i = 0; i < o->ntf_changes; i++)
        if (vsv_meta_find_var(p->m, o->tf_changes[i].species) < 0) {
            snprintf(err, cap, "--%s: %s has no species '%s'",
                     !strncmp(o->tf_changes[i].line, "scale", 5)   ? "log"
                     : !strncmp(o->tf_changes[i].line, "range", 5) ? "range"
                                                                   : "colormap",
                     o->path, o->tf_changes[i].species);
            rc = VSV_EINVAL;
            goto fail;
        }
    for (int s = 0; s < p->ns; s++) {
        char msg[512];
        rc = vsv_tf_for_species(p->f, s, o->tfpath, &p->tf[s], msg, sizeof msg);
        for (int i = 0; !rc && i < o->ntf_changes; i++)
            if (!strcmp(o->tf_changes[i].species, p->m->vars[s].name) &&
                vsv_tf_change_apply(&p->tf[s], &o->tf_changes[i], msg, sizeof msg)) {
                snprintf(err, cap, "%s", msg);
                rc = VSV_EINVAL;
                goto fail;
            }
        if (rc) {
            snprintf(err, cap, rc == VSV_EIO ? "%s" : "%s: %s",
                     rc == VSV_EIO ? msg
                     : o->tfpath   ? o->tfpath
                                   : o->path,
                     msg);
            rc = -1;
            goto fail;
        }
        if (!(p->cur[s] = vsv_pager_volume_new(p->pager)) ||
            (p->nowait && !(p->alt[s] = vsv_pager_volume_new(p->pager)))) {
            snprintf(err, cap, "out of memory");
            rc = -1;
            goto fail;
        }
        p->want[s] = opac[s] >= 0;
        p->layers[s] = (vsv_layer){NULL, &p->tf[s], opac[s] >= 0 ? opac[s] : 1, p->want[s]};
    }
fail:
    free(opac);
    return rc;
}

/* The slices: parsed against the grid, coloured by a species' range: 0 or VSV_EINVAL, the reason in err. */
static int open_slices(vsv_player *p, const vsv_player_opts *o, char *err, size_t cap)
{
    p->slice_var = -1;
    for (int s = 0; s < p->ns && p->slice_var < 0; s++)
        p->slice_var = p->want[s] ? s : -1;
    if (o->slice_species && (p->slice_var = vsv_meta_find_var(p->m, o->slice_species)) < 0) {
        snprintf(err, cap, "--slice-species: %s has no species '%s'", o->path, o->slice_species);
        return VSV_EINVAL;
    }
    if (p->slice_var < 0)
        p->slice_var = 0;
    for (int i = 0; i < o->nslices && i < 8; i++) {
        char msg[512];
        if (vsv_slice_parse(p->m, o->slices[i], &p->slices[i], msg, sizeof msg)) {
            snprintf(err, cap, "--%s in %s", msg, o->path); /* as vsv-render says it */
            return VSV_EINVAL;
        }
        p->nslices++;
    }
    p->slices_on = p->nslices > 0;
    if (p->ns) {
        p->slice_tf = p->tf[p->slice_var];
        snprintf(p->slice_tf.colormap, sizeof p->slice_tf.colormap, "%s",
                 o->slice_colormap ? o->slice_colormap : "viridis");
        p->slice_fixed[0] = o->slice_range[0], p->slice_fixed[1] = o->slice_range[1];
        p->slice_key[0] = -2; /* none taken yet */
        if (isfinite(p->slice_fixed[0]))
            p->slice_tf.lo = p->slice_fixed[0], p->slice_tf.hi = p->slice_fixed[1];
        if (vsv_tf_prepare(&p->slice_tf)) {
            snprintf(err, cap, "--slice-colormap %s: not a colour map name",
                     o->slice_colormap ? o->slice_colormap : "");
            return VSV_EINVAL;
        }
    }
    return 0;
}

int vsv_player_open(const vsv_player_opts *o, vsv_player **out, char *err, size_t cap)
{
    int rc = -1;
    vsv_player *p = *out = calloc(1, sizeof *p);
    if (!p) {
        snprintf(err, cap, "out of memory");
        return -1;
    }
    snprintf(p->path, sizeof p->path, "%s", o->path);
    p->shown = p->target = -1;
    p->stride = 1;
    p->bg[0] = 0.02f, p->bg[1] = 0.03f, p->bg[2] = 0.06f;
    if (vsv_file_open_any(o->path, o->http, &p->f)) {
        snprintf(err, cap, "%s", p->f ? vsv_file_error(p->f) : "cannot open");
        if (!p->f || !strstr(err, o->path)) {
            char tmp[600];
            snprintf(tmp, sizeof tmp, "%s: %s", o->path, err[0] ? err : "cannot open");
            snprintf(err, cap, "%s", tmp);
        }
        goto fail;
    }
    p->m = vsv_file_meta(p->f);
    if (!(p->placed = malloc(((size_t)p->m->nmoves + 1) * sizeof *p->placed))) {
        snprintf(err, cap, "out of memory");
        goto fail;
    }
    for (int i = 0; i <= p->m->nmoves; i++)
        p->placed[i] = vsv_meta_placed(p->m, i ? p->m->moves[i - 1].time : INT64_MIN);
    vsv_file_info info;
    vsv_file_info_get(p->f, &info);
    p->ns = p->m->nvars;
    p->times = malloc((size_t)info.nsteps * sizeof *p->times);
    p->tf = calloc((size_t)p->ns, sizeof *p->tf);
    p->cur = calloc((size_t)p->ns, sizeof *p->cur);
    p->alt = calloc((size_t)p->ns, sizeof *p->alt);
    p->layers = calloc((size_t)p->ns, sizeof *p->layers);
    p->want = calloc((size_t)p->ns, 1);
    p->need = calloc((size_t)p->ns, 1);
    p->bad = calloc((size_t)info.nsteps, sizeof *p->bad);
    p->gens = calloc((size_t)(p->ns ? p->ns : 1), sizeof *p->gens);
    p->news = p->waiting = p->stall_step = p->stall_news = -1;
    if (!p->times || !p->tf || !p->cur || !p->alt || !p->layers || !p->want || !p->need || !p->bad || !p->gens) {
        snprintf(err, cap, "out of memory");
        goto fail;
    }
    for (int t = 0; t < info.nsteps; t++)
        p->times[t] = vsv_file_time(p->f, t);
    vsv_pager_opts po;
    vsv_pager_opts_init(&po);
    po.budget = o->clock_only || o->external ? (size_t)1 << 20 : o->cache_bytes;
    po.threads = o->clock_only || o->external ? -1 : 0;
    po.slab_alloc = o->slab_alloc;
    po.slab_ctx = o->slab_ctx;
    /* a URL: what is shown comes from the workers, never a wait on the
     * server on this thread (vsv-play froze behind a stalled one) */
    p->nowait = vsv_is_url(o->path) && po.threads >= 0;
    if (vsv_pager_open(p->f, &po, &p->pager)) {
        snprintf(err, cap, "cannot start the pager: out of memory");
        goto fail;
    }
    if ((rc = open_species(p, o, err, cap)) || (rc = open_slices(p, o, err, cap)) ||
        (rc = vsv_player_open_isos(p, o, err, cap)) || (rc = vsv_player_open_flow(p, o, err, cap)))
        goto fail;
    p->light = o->light;
    p->sun_az = o->sun_az;
    p->sun_el = o->sun_el;
    p->terrain = o->terrain;
    vsv_scene sc = scene(p);
    p->exaggeration = o->exaggerate > 0 ? o->exaggerate : vsv_scene_default_exaggeration(&sc);
    vsv_clock_init(&p->clock, p->times, info.nsteps, o->rate);
    p->clock.ends = o->loop;
    if (o->play)
        vsv_clock_play(&p->clock);
    p->az = 225;
    p->el = 30;
    vsv_render_opts_init(&p->ro);
    p->ro.threads = o->clock_only ? 1 : o->threads;
    p->gpu_budget = o->gpu_budget;
    p->no_renderer = o->no_renderer || o->clock_only;
    p->gl_by_caller = o->gl_by_caller;
    p->ro.kind = VSV_RENDER_SHEARWARP;
    if (vsv_renderer_create(&p->ro, &p->r)) {
        snprintf(err, cap, "cannot start the renderer");
        rc = -1;
        goto fail;
    }
    if (o->renderer != VSV_RENDER_SHEARWARP) {
        char why[1024];
        if (vsv_player_use_renderer(p, o->renderer, why, sizeof why)) {
            snprintf(err, cap, "%s", why);
            rc = o->renderer == VSV_RENDER_GL ? VSV_EUNSUPPORTED : -1;
            goto fail;
        }
    }
    p->dirty = 1;
    return 0;
fail:
    vsv_player_free(p);
    *out = NULL;
    return rc;
}

void vsv_player_free(vsv_player *p)
{
    if (!p)
        return;
    for (int s = 0; p->cur && s < p->ns; s++)
        vsv_volume_free(p->cur[s]);
    for (int s = 0; p->alt && s < p->ns; s++)
        vsv_volume_free(p->alt[s]);
    vsv_flow_free(p->flow);
    vsv_file_interrupt(p->f); /* a worker waiting on a stalled server: at once */
    vsv_pager_free(p->pager);
    vsv_renderer_free(p->r);
    vsv_gl_free(p->gl);
    vsv_file_free(p->f);
    for (int t = 0; p->bad && t < p->clock.nsteps; t++)
        free(p->bad[t]);
    free(p->bad);
    free(p->times);
    free(p->placed);
    free(p->tf);
    free(p->cur);
    free(p->alt);
    free(p->layers);
    free(p->want);
    free(p->need);
    free(p->gens);
    free(p->rgba);
    free(p->depth);
    free(p->rgb);
    free(p->argba);
    free(p->argb);
    free(p->sidx);
    free(p);
}

/* ---------------------------------------------------------------- paging */

/* Shows step t: every visible species pinned from the pager (waiting for
 * what is not decoded yet, so all species always show the same step);
 * hidden ones released. 0 or -1. */
static int show(vsv_player *p, int t, int wait)
{
    needed(p);
    for (int s = 0; s < p->ns; s++) {
        if (!p->need[s]) {
            if (p->cur[s]->step >= 0)
                vsv_pager_put(p->pager, p->cur[s]);
            p->layers[s].vol = NULL;
            continue;
        }
        if (p->cur[s]->step == t)
            continue;
        const int rc = vsv_pager_get(p->pager, t, s, wait, p->cur[s]);
        if (rc) {
            p->layers[s].vol = NULL;
            return rc;
        }
        p->layers[s].vol = p->cur[s];
    }
    if (t != p->shown)
        p->dirty = 1;
    p->shown = t;
    return 0;
}

/* Shows step t without waiting (nowait: a URL): every needed species got
 * into its spare volume, then all swapped in at once, so they always show
 * the same step; else what is shown stays, but hidden species are
 * released. 0, or the first get's error (VSV_EAGAIN: not decoded yet). */
static int show_nowait(vsv_player *p, int t)
{
    needed(p);
    int rc = 0;
    for (int s = 0; s < p->ns && !rc; s++)
        if (p->need[s] && p->cur[s]->step != t)
            rc = vsv_pager_get(p->pager, t, s, 0, p->alt[s]);
    for (int s = 0; s < p->ns; s++) {
        if (p->alt[s]->step >= 0 && rc) /* (nothing of a step half there) */
            vsv_pager_put(p->pager, p->alt[s]);
        if (!p->need[s]) {
            if (p->cur[s]->step >= 0)
                vsv_pager_put(p->pager, p->cur[s]);
            p->dirty |= p->layers[s].vol != NULL;
            p->layers[s].vol = NULL;
        } else if (!rc && p->alt[s]->step == t) {
            vsv_volume *was = p->cur[s];
            p->cur[s] = p->alt[s];
            p->alt[s] = was;
            if (was->step >= 0)
                vsv_pager_put(p->pager, was);
            p->layers[s].vol = p->cur[s];
        }
    }
    if (rc)
        return rc;
    if (t != p->shown)
        p->dirty = 1;
    p->shown = t;
    return 0;
}

const char *vsv_player_error(const vsv_player *p) { return p->err; }

/* Step t is damaged: shown as nothing (no species drawn, the step's time
 * and its damage in the status), never as the picture before it. */
static void show_blank(vsv_player *p, int t)
{
    for (int s = 0; s < p->ns; s++) {
        if (p->cur[s]->step >= 0)
            vsv_pager_put(p->pager, p->cur[s]);
        p->layers[s].vol = NULL;
    }
    if (t != p->shown)
        p->dirty = 1;
    p->shown = t;
}

static int show_checked(vsv_player *p, int t)
{
    if (p->bad[t]) {
        show_blank(p, t);
        p->waiting = -1;
        return 0;
    }
    const int rc = p->nowait ? show_nowait(p, t) : show(p, t, 1);
    if (!rc) {
        p->waiting = p->stall_step = -1;
        return 0;
    }
    snprintf(p->err, sizeof p->err, "%s", vsv_pager_error(p->pager));
    if (rc == VSV_EAGAIN || rc == VSV_EIO) {
        /* not there yet, or a transfer for it failed (not damage: tried
         * again on a later frame); what is shown stays (nowait) */
        if (!p->nowait)
            show_blank(p, t);
        p->waiting = t;
        if (rc == VSV_EIO) {
            snprintf(p->stall, sizeof p->stall, "%s", p->err);
            if (p->stall_step != t)
                p->stall_news = t;
            p->stall_step = t;
        }
        return 0;
    }
    if (rc != VSV_ECORRUPT && rc != VSV_ETRUNC)
        return -1;
    /* a damaged step: reported once (vsv_player_damage), playback goes on */
    if (!(p->bad[t] = strdup(p->err[0] ? p->err : "damaged")))
        return -1;
    p->news = t;
    show_blank(p, t);
    return 0;
}

int vsv_player_damage(vsv_player *p, const char **why)
{
    const int t = p->news;
    p->news = -1;
    if (why)
        *why = t >= 0 ? p->bad[t] : NULL;
    return t;
}

int vsv_player_waiting(const vsv_player *p, const char **why)
{
    if (why)
        *why = p->waiting >= 0 && p->stall_step == p->waiting && p->stall[0] ? p->stall : NULL;
    return p->waiting;
}

int vsv_player_stalled(vsv_player *p, const char **why)
{
    const int t = p->stall_news;
    p->stall_news = -1;
    if (why)
        *why = t >= 0 ? p->stall : NULL;
    return t;
}

vsv_pager *vsv_player_pager(vsv_player *p) { return p->pager; }

const vsv_volume *vsv_player_volume(const vsv_player *p, int s)
{
    return s >= 0 && s < p->ns && p->shown >= 0 ? p->layers[s].vol : NULL;
}

const char *vsv_player_shown_damage(const vsv_player *p) { return p->shown >= 0 ? p->bad[p->shown] : NULL; }

void vsv_player_show(vsv_player *p, int step, const vsv_volume *const *vols, const char *damage)
{
    if (step < 0 || step >= p->clock.nsteps)
        return;
    for (int s = 0; s < p->ns; s++) {
        const vsv_volume *v = vols ? vols[s] : NULL;
        if (p->layers[s].vol != v || (v && v->gen != p->gens[s]))
            p->dirty = 1;
        p->layers[s].vol = v;
        p->gens[s] = v ? v->gen : 0;
    }
    const int was = p->bad[step] != NULL;
    if (damage && !was)
        p->bad[step] = strdup(damage);
    else if (!damage && was) {
        free(p->bad[step]);
        p->bad[step] = NULL;
    }
    if (was != (damage != NULL) || step != p->shown)
        p->dirty = 1;
    p->shown = step;
}

int vsv_player_update(vsv_player *p, double dt, int exact)
{
    vsv_clock *c = &p->clock;
    vsv_clock_tick(c, dt);
    /* the time between frames that draw, smoothed: when the next pictures
     * come (a frame that found nothing new to draw takes a few ms and says
     * nothing of the next one's time) */
    if (dt > 0 && !p->idle)
        p->frame = p->frame > 0 ? 0.75 * p->frame + 0.25 * fmin(dt, 0.25) : fmin(dt, 0.25);
    p->idle = 0;
    p->waited = 0;
    /* a frame spanning several steps shows every stride-th: the steps decoded
     * ahead for the next frames are then the ones they show */
    p->stride = vsv_clock_stride(c, p->frame, p->stride);
    const int target = p->target = vsv_clock_stride_step(c, c->step, p->stride);
    const int dir = !c->playing ? 0 : c->speed > 0 ? 1 : -1;
    const unsigned char *need = needed(p);
    int next[VSV_PAGER_AHEAD + 1];
    const int nn = vsv_clock_ahead_stride(c, p->frame > 0 ? p->frame : 1.0 / 30, p->stride, next, VSV_PAGER_AHEAD + 1);
    vsv_pager_playhead(p->pager, target, dir, next, nn, need);
    vsv_pager_stats st;
    vsv_pager_stats_get(p->pager, &st);
    /* st.prefetch_depth 0: a step does not fit the budget beside the one
     * shown, nothing is decoded ahead, so decode on demand */
    if (exact || !c->playing || p->shown < 0 || target == p->shown || st.prefetch_depth == 0 || p->bad[target] ||
        vsv_pager_ready(p->pager, target, need)) /* (-1, failed: decoded here to say why) */
        return show_checked(p, target);
    /* not decoded yet, the workers on it (the playhead): a quarter of a
     * frame's wait for it, a frame a little later rather than the picture
     * of the frame before again (not for a URL: a transfer may stall) */
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    const int got = !p->nowait && vsv_pager_wait_ready(p->pager, target, need, 0.25 * p->frame);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    p->waited = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    if (got)
        return show_checked(p, target);
    /* playing and the clock's step is not decoded yet: the newest decoded
     * step on the way there, else the one shown stays */
    vsv_pager_stall(p->pager);
    const int n = c->nsteps;
    for (int t = target, i = 0; i < n; i++) {
        t = ((t - dir) % n + n) % n;
        if (t == p->shown)
            break;
        if (vsv_pager_ready(p->pager, t, need) == 1)
            return show_checked(p, t);
    }
    return show_checked(p, p->shown); /* the step shown, with any species just switched on */
}

/* ---------------------------------------------------------------- camera */

void vsv_player_camera(const vsv_player *p, int w, int h, vsv_camera *cam)
{
    vsv_scene sc = scene(p);
    sc.meta = p->m; /* framed on every place a moving nest stands (vsv_scene_bounds) */
    if (p->plan) {
        vsv_camera_plan(cam, &sc, w, h);
        cam->ortho_height /= p->plan_zoom > 0 ? p->plan_zoom : 1;
    } else if (p->dist > 0) {
        vsv_camera_orbit(cam, &sc, p->az, p->el, p->dist, w, h);
    } else {
        vsv_camera_fit(cam, &sc, p->az, p->el, w, h);
    }
    for (int i = 0; i < 3; i++)
        cam->pos[i] += p->pan[i];
}

void vsv_player_scene(vsv_player *p, vsv_scene *sc)
{
    colour_slices(p);
    vsv_player_wind_lines(p);
    *sc = scene(p);
}

void vsv_player_bounds(const vsv_player *p, double mn[3], double mx[3])
{
    vsv_scene sc = scene(p);
    sc.meta = p->m; /* every place a moving nest stands: the room holds still */
    vsv_scene_bounds(&sc, mn, mx);
}

const float *vsv_player_background(const vsv_player *p) { return p->bg; }

void vsv_player_invalidate(vsv_player *p) { p->dirty = 1; }

const unsigned char *vsv_player_image(vsv_player *p, const vsv_camera *cam, char *err, size_t cap)
{
    const int w = cam->width, h = cam->height;
    if (w != p->iw || h != p->ih) {
        /* the buffers only grow: windows of other sizes drawn in turn (a
         * render process with several) allocate nothing per frame */
        const size_t n = (size_t)w * h;
        if (n > p->icap) {
            free(p->rgba);
            free(p->depth);
            free(p->rgb);
            free(p->argba);
            free(p->argb);
            p->argba = NULL, p->argb = NULL;
            p->rgba = malloc(n * 4 * sizeof(float));
            p->depth = malloc(n * sizeof(float));
            p->rgb = malloc(n * 3);
            if (!p->rgba || !p->depth || !p->rgb) {
                p->iw = p->ih = 0;
                p->icap = 0;
                snprintf(err, cap, "out of memory");
                return NULL;
            }
            p->icap = n;
        }
        p->iw = w, p->ih = h;
        p->dirty = 1;
    }
    colour_slices(p);
    vsv_player_wind_lines(p);
    if (!p->dirty && !memcmp(cam, &p->last_cam, sizeof *cam)) {
        p->idle = 1; /* (a frame that drew nothing: not counted in p->frame) */
        return p->rgb;
    }
    vsv_scene sc = scene(p);
    if (p->ro.kind == VSV_RENDER_GL && p->gl) {
        if (vsv_gl_render(p->gl, &sc, cam, p->rgba, p->depth)) {
            snprintf(err, cap, "render failed: %s", vsv_gl_error(p->gl));
            return NULL;
        }
    } else {
        const int rc = vsv_render(p->r, &sc, cam, p->rgba, p->depth);
        if (rc) {
            snprintf(err, cap, "render failed: %s", vsv_strerror(rc));
            return NULL;
        }
    }
    vsv_image_rgb8(p->rgba, w, h, p->bg, p->rgb);
    p->last_cam = *cam;
    p->dirty = 0;
    return p->rgb;
}

int vsv_player_draw(vsv_player *p, vsv_gl *gl, const vsv_camera *cam, const int viewport[4], char *err, size_t cap)
{
    if (p->ro.kind != VSV_RENDER_GL || !gl)
        return VSV_EUNSUPPORTED;
    colour_slices(p);
    vsv_player_wind_lines(p);
    vsv_scene sc = scene(p);
    const int rc = vsv_gl_draw(gl, &sc, cam, viewport, p->bg);
    if (rc)
        snprintf(err, cap, "the GPU raycaster: %s", vsv_gl_error(gl));
    return rc;
}

int vsv_player_renderer(const vsv_player *p) { return p->ro.kind; }

const unsigned char *vsv_player_annotated(vsv_player *p, unsigned parts, vsv_font *font, const vsv_outlines *outlines,
                                          char *err, size_t cap)
{
    if (!p->iw || !p->rgb || p->shown < 0) {
        snprintf(err, cap, "no frame drawn yet");
        return NULL;
    }
    const size_t n = (size_t)p->iw * p->ih;
    if (!p->argba) /* (as large as the image buffers: their sizes come and go) */
        p->argba = malloc(p->icap * 4 * sizeof(float));
    if (!p->argb)
        p->argb = malloc(p->icap * 3);
    if (!p->sidx && (p->sidx = malloc((size_t)(p->ns ? p->ns : 1) * sizeof *p->sidx)))
        for (int s = 0; s < p->ns; s++)
            p->sidx[s] = s;
    if (!p->argba || !p->argb || !p->sidx) {
        snprintf(err, cap, "out of memory");
        return NULL;
    }
    memcpy(p->argba, p->rgba, n * 4 * sizeof(float));
    const char *base = strrchr(p->path, '/') ? strrchr(p->path, '/') + 1 : p->path;
    char source[1200]; /* a damaged step is said on the picture too */
    snprintf(source, sizeof source, "%s%s", base, p->bad[p->shown] ? " - step DAMAGED, not drawn" : "");
    const vsv_annot a = {parts, font, p->times[p->shown], source, p->sidx, outlines, NULL, NULL};
    vsv_scene sc = scene(p);
    if (parts && vsv_annotate(&a, &sc, &p->last_cam, p->argba, p->depth)) {
        snprintf(err, cap, "out of memory");
        return NULL;
    }
    vsv_image_rgb8(p->argba, p->iw, p->ih, p->bg, p->argb);
    return p->argb;
}
