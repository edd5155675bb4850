/* vsv_freevr_draw.c — the FreeVR back end's render processes: each window
 * joins the room (vsv_room.h), takes one tick at the start of each of its
 * frames (every eye of that frame draws it), and each eye renders the
 * scene with the frustum FreeVR loaded for it, keeps the picture while
 * neither the eye nor what it shows changed, and draws it on a billboard,
 * then the wand's pointer and the panel, in FreeVR's room (feet).
 *
 * A render process decodes nothing: the volumes are the room's, decoded
 * once by the main process. Its player holds the file's metadata, the
 * transfer functions and the renderer. */
#include "vsv_freevr_app.h"
#include "vsv_gl.h"
#include "vsv_overlay.h"
#include "vsv_panel.h"
#include "vsv_place.h"

#include <GL/gl.h>
#include <GL/glx.h>
#include <X11/Xlib.h>
#include <freevr.h>
#include <math.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define MAXWIN 32

/* a window of this render process */
typedef struct fvwin {
    GLXDrawable drawable; /* which window the current context draws */
    int room;             /* its record in the room; -1 when it could not join */
    char name[64];
    int have; /* a tick is taken for this frame */
    unsigned long long frames;
    int64_t tick, time;
    double when; /* when the tick was taken */
    int step, eye;
    const char *damage;
    const vsv_volume *const *vols; /* its volumes per species (the room's) */
    uint64_t content;              /* what the tick's picture depends on, but the eye */
    vsv_fv_tick tk;
    vsv_panel *panel;
    vsv_gl *gl;    /* the GPU raycaster of this window's context */
    GLuint tex[2]; /* each eye's picture, and what it shows */
    uint64_t key[2];
    vsv_camera cam[2];
} fvwin;

static fvwin wins[MAXWIN];
static int nwins, opened;
static vsv_player *player; /* one per render process, for all its windows */
static vsv_annot legend;   /* the panel's legend: time and species map */
static int *species_map;

static void fail(const char *msg) { vsv_room_fail(vsv_fv.room, 1, msg); }
static uint64_t content_key(const struct fvwin *w, const vsv_volume *const *vols);

/* The window whose context is current. */
static fvwin *current(void)
{
    const GLXDrawable d = glXGetCurrentDrawable();
    for (int i = 0; i < nwins; i++)
        if (wins[i].drawable == d)
            return &wins[i];
    return NULL;
}

/* Its FreeVR name: windows are titled "FreeVR(pid): NAME window". */
static void window_name(GLXDrawable d, int index, char *out, size_t cap)
{
    snprintf(out, cap, "window%d", index);
    Display *dpy = glXGetCurrentDisplay();
    char *title = NULL;
    if (!dpy || !XFetchName(dpy, (Window)d, &title) || !title)
        return;
    const char *p = strstr(title, "): ");
    if (p) {
        p += 3;
        size_t n = strlen(p);
        if (n > 7 && !strcmp(p + n - 7, " window"))
            n -= 7;
        if (n > 0)
            snprintf(out, cap, "%.*s", (int)n, p);
    }
    XFree(title);
}

void vsv_fv_display_init(void)
{
    char err[1024];
    if (nwins == MAXWIN) {
        fail("more than 32 windows in one render process");
        return;
    }
    fvwin *w = &wins[nwins];
    memset(w, 0, sizeof *w);
    w->drawable = glXGetCurrentDrawable();
    window_name(w->drawable, nwins, w->name, sizeof w->name);
    nwins++;
    w->room = vsv_room_join(vsv_fv.room, w->name);
    if (w->room < 0) {
        snprintf(err, sizeof err, "the %s window: more windows than the configuration counted", w->name);
        fail(err);
    }
    w->panel = vsv_panel_create();
    vsv_gl_opts go;
    vsv_gl_opts_init(&go);
    go.threads = vsv_fv.opts.threads;
    if (vsv_fv.opts.gpu_budget)
        go.budget = vsv_fv.opts.gpu_budget;
    if (!opened++) {
        /* the renderer: the GPU raycaster where asked for (or, by default,
         * where OpenGL 3.3 runs on a GPU: a raycaster made in this context
         * says whether it can), else the CPU's */
        vsv_player_opts o = vsv_fv.opts;
        const int want = o.renderer;
        if (want == VSV_RENDER_GL || (want < 0 && !vsv_gl_context_software())) {
            if (!vsv_gl_create(&go, &w->gl, err, sizeof err)) {
                o.renderer = VSV_RENDER_GL;
            } else if (want == VSV_RENDER_GL) {
                char msg[1100];
                snprintf(msg, sizeof msg, "--renderer gl: %s", err);
                vsv_room_fail(vsv_fv.room, 2, msg);
                return;
            } else {
                if (w->room == 0)
                    fprintf(stderr, "vsv-play-freevr: renderer: shear-warp (the GPU raycaster cannot run: %s)\n", err);
                o.renderer = VSV_RENDER_SHEARWARP;
            }
        } else if (want < 0) {
            if (w->room == 0)
                fprintf(stderr,
                        "vsv-play-freevr: renderer: shear-warp (OpenGL here is %s, a software rasteriser: "
                        "the CPU renderers are faster; --renderer gl to use it anyway)\n",
                        (const char *)glGetString(GL_RENDERER));
            o.renderer = VSV_RENDER_SHEARWARP;
        }
        o.gl_by_caller = 1; /* (each window draws with its own) */
        if (vsv_player_open(&o, &player, err, sizeof err)) {
            vsv_player_free(player);
            player = NULL;
            fail(err);
            return;
        }
        const vsv_meta *m = vsv_player_meta(player);
        species_map = calloc((size_t)(m->nvars ? m->nvars : 1), sizeof *species_map);
        for (int s = 0; species_map && s < m->nvars; s++)
            species_map[s] = s;
        legend = (vsv_annot){VSV_ANNOT_TIME | VSV_ANNOT_COLOURBAR, NULL, 0, NULL, species_map, NULL, NULL, NULL};
    } else if (player && vsv_player_renderer(player) == VSV_RENDER_GL && vsv_gl_create(&go, &w->gl, err, sizeof err)) {
        char msg[1100]; /* (this context's own raycaster) */
        snprintf(msg, sizeof msg, "the %s window: --renderer gl: %s", w->name, err);
        vsv_room_fail(vsv_fv.room, 2, msg);
    }
}

void vsv_fv_display_exit(void)
{
    fvwin *w = current();
    if (w) {
        vsv_panel_free(w->panel);
        vsv_gl_free(w->gl);
        w->panel = NULL, w->gl = NULL;
        glDeleteTextures(2, w->tex);
    }
    if (--opened > 0)
        return;
    vsv_player_free(player);
    player = NULL;
    free(species_map);
    species_map = NULL;
}

/* --trace: one line for this window's frame, appended whole (O_APPEND: the
 * lines of all render processes interleave, never mix). */
static void trace(const fvwin *w)
{
    if (vsv_fv.trace_fd < 0)
        return;
    struct timespec cpu;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &cpu);
    char when[40], line[256];
    vsv_cal_format(vsv_meta_calendar(vsv_player_meta(player)), w->time, when, sizeof when);
    const int n = snprintf(line, sizeof line, "%s %llu %lld %d %s %.4f %.4f %d\n", w->name,
                           (unsigned long long)w->frames, (long long)w->tick, w->step, when, w->when - vsv_fv.t0,
                           (double)cpu.tv_sec + cpu.tv_nsec * 1e-9, (int)getpid());
    if (n > 0 && write(vsv_fv.trace_fd, line, (size_t)n) != n)
        return; /* a trace that cannot be written is not the display's failure */
}

void vsv_fv_display_frame(void *ri)
{
    (void)ri;
    fvwin *w = current();
    if (!w || !player || w->room < 0)
        return;
    w->eye = 0;
    vsv_room_view v;
    if (vsv_room_frame(vsv_fv.room, w->room, &v)) {
        w->have = 0;
        return;
    }
    w->have = 1;
    w->frames++;
    w->tick = v.tick, w->step = v.step, w->damage = v.damage, w->time = v.time, w->when = v.when;
    memcpy(&w->tk, v.user, sizeof w->tk);
    w->vols = v.vols;
    w->content = content_key(w, v.vols);
    trace(w);
}

/* ------------------------------------------------------------------ eyes */

static uint64_t fnv(uint64_t h, const void *p, size_t n)
{
    const unsigned char *b = p;
    for (size_t i = 0; i < n; i++)
        h = (h ^ b[i]) * 1099511628211ull;
    return h;
}

/* What the picture of this tick depends on besides the eye: the volumes
 * (their loads), the species' settings, the placement, the step and its
 * damage. Ticks that change only the wand or the panel keep it. */
static uint64_t content_key(const fvwin *w, const vsv_volume *const *vols)
{
    const vsv_fv_tick *t = &w->tk;
    const int ns = vsv_player_meta(player)->nvars;
    uint64_t h = fnv(1469598103934665603ull, &w->step, sizeof w->step);
    for (int s = 0; s < ns; s++) {
        const uint64_t g = vols && vols[s] ? vols[s]->gen : 0;
        h = fnv(h, &g, sizeof g);
    }
    h = fnv(h, t->st.visible, sizeof t->st.visible);
    h = fnv(h, t->st.opacity, sizeof t->st.opacity);
    h = fnv(h, &t->st.renderer, sizeof t->st.renderer);
    h = fnv(h, &t->st.light, sizeof t->st.light);
    h = fnv(h, &t->st.slices, sizeof t->st.slices);
    h = fnv(h, t->place, sizeof t->place);
    const int bad = w->damage != NULL;
    return fnv(h, &bad, sizeof bad);
}

/* The depth (positive, in the projection's units) at which the billboard
 * lies: the scene's centre as this eye sees it, kept inside the near and
 * far planes of the projection P that FreeVR loaded. Any depth between
 * them gives the same picture. */
static double billboard_depth(const double P[16], const double MV[16], const double centre[3])
{
    const double z = MV[2] * centre[0] + MV[6] * centre[1] + MV[10] * centre[2] + MV[14];
    double d = -z, n = 0.1, f = 1000;
    if (P[11] == -1 && P[10] != 1 && P[10] != -1) { /* glFrustum */
        n = P[14] / (P[10] - 1);
        f = P[14] / (P[10] + 1);
    }
    if (!(n > 0 && f > n))
        n = 0.1, f = 1000;
    if (!(d > n * 1.5))
        d = n * 1.5;
    if (d > f * 0.5)
        d = f * 0.5;
    return d;
}

/* The wand's pointer in the room: a foot-long stick to its tip (what the
 * scene scales about), a cross at the tip, and a faint ray beyond. */
static void draw_wand(const vsv_fv_tick *t)
{
    const double *a = t->wand, *d = t->wdir, *tip = t->tip, s = 0.08;
    glDisable(GL_TEXTURE_2D);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glLineWidth(2);
    glBegin(GL_LINES);
    glColor4f(1, 0.85f, 0.2f, 1);
    glVertex3dv(a), glVertex3dv(tip);
    glColor4f(1, 1, 1, 1);
    for (int ax = 0; ax < 3; ax++) {
        double p[3], q[3];
        memcpy(p, tip, sizeof p);
        memcpy(q, tip, sizeof q);
        p[ax] -= s, q[ax] += s;
        glVertex3dv(p), glVertex3dv(q);
    }
    glColor4f(1, 0.85f, 0.2f, 0.35f);
    glVertex3dv(tip);
    glVertex3d(tip[0] + 30 * d[0], tip[1] + 30 * d[1], tip[2] + 30 * d[2]);
    glEnd();
    glLineWidth(1);
    glDisable(GL_BLEND);
}

void vsv_fv_panel_lines(const vsv_fv_tick *t, const vsv_meta *m, int nsteps, int step, int damaged, int fps, char *buf,
                        size_t cap)
{
    static const char *ends[] = {"", "  loop", "  bounce"};
    if (!t) { /* the widest they get: the longest species name, the most digits */
        size_t longest = 1;
        for (int s = 0; s < m->nvars; s++)
            longest = strlen(m->vars[s].name) > longest ? strlen(m->vars[s].name) : longest;
        char name[64], num[32];
        snprintf(name, sizeof name, "%.*s", (int)(longest < 60 ? longest : 60),
                 "WWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWW");
        snprintf(num, sizeof num, "%d", nsteps > 0 ? nsteps - 1 : 0);
        for (char *c = num; *c; c++)
            *c = '0';
        snprintf(buf, cap, "step %s of %s  playing\nx64 back  bounce\nselected %s  hidden  0.00%s", num, num, name,
                 fps ? "\n000.0 frames a second" : "");
        return;
    }
    const int sel = t->st.selected >= 0 && t->st.selected < m->nvars ? t->st.selected : 0;
    size_t n = (size_t)snprintf(buf, cap, "step %d of %d  %s\nx%g%s%s", step, nsteps - 1,
                                t->st.playing ? "playing" : "paused", fabs(t->st.speed), t->st.speed < 0 ? " back" : "",
                                ends[t->st.ends >= 0 && t->st.ends < 3 ? t->st.ends : 0]);
    if (m->nvars && n < cap) {
        const int on = sel < VSV_PLAYER_MAX_SPECIES ? t->st.visible[sel] : 1;
        n += (size_t)snprintf(buf + n, cap - n, "\nselected %s  %s  %.2f", m->vars[sel].name, on ? "shown" : "hidden",
                              sel < VSV_PLAYER_MAX_SPECIES ? t->st.opacity[sel] : 1.0);
    }
    if (fps && t->fps >= 0 && n < cap)
        n += (size_t)snprintf(buf + n, cap - n, "\n%.1f frames a second", t->fps);
    if (damaged && n < cap)
        snprintf(buf + n, cap - n, "\nstep %d DAMAGED", step);
}

/* After the picture: the wand's pointer and the panel, in the room. */
static void overlays(fvwin *w, int eye, const double P[16], const double MV[16], const GLint vp[4])
{
    if (vsv_fv.wand)
        draw_wand(&w->tk);
    if (w->tk.lh > 0 && w->panel) {
        char lines[512];
        vsv_fv_panel_lines(&w->tk, vsv_player_meta(player), w->tk.nsteps, w->step, w->damage != NULL, w->tk.fps >= 0,
                           lines, sizeof lines);
        legend.time = w->time;
        vsv_scene sc;
        vsv_player_scene(player, &sc);
        const double density = vsv_panel_draw(w->panel, &legend, &sc, lines, w->tk.panel, w->tk.panel + 3,
                                              w->tk.panel + 6, w->tk.lh, P, MV, vp);
        if (eye == 0)
            vsv_room_report(vsv_fv.room, w->room, density);
    }
}

void vsv_fv_display_eye(void *ri)
{
    (void)ri;
    fvwin *w = current();
    const float *bg = player ? vsv_player_background(player) : NULL;
    /* FreeVR does not clear: old frames and stale depth would show */
    glClearColor(bg ? bg[0] : 0, bg ? bg[1] : 0, bg ? bg[2] : 0, 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    if (!w || !w->have || !player)
        return;
    const int eye = w->eye < 2 ? w->eye : 1;
    w->eye++;
    /* this window's tick into the player, which every window of this
     * process shares (cheap when it holds it already) */
    char err[1024] = "";
    if (vsv_player_state_apply(player, &w->tk.st, err, sizeof err)) {
        fail(err);
        return;
    }
    vsv_player_show(player, w->step, w->vols, w->damage);
    double P[16], MV[16];
    GLint vp[4];
    glGetDoublev(GL_PROJECTION_MATRIX, P);
    glGetDoublev(GL_MODELVIEW_MATRIX, MV);
    glGetIntegerv(GL_VIEWPORT, vp);
    if (vp[2] < 1 || vp[3] < 1)
        return;
    vsv_camera cam;
    if (vsv_player_renderer(player) == VSV_RENDER_GL) { /* the GPU raycaster: this eye's frustum, no billboard */
        vsv_player_camera_from_gl(w->tk.place, P, MV, vp[2], vp[3], &cam);
        if (vsv_player_draw(player, w->gl, &cam, vp, err, sizeof err)) {
            fail(err);
            return;
        }
        glViewport(vp[0], vp[1], vp[2], vp[3]);
        glMatrixMode(GL_PROJECTION); /* (what FreeVR loaded, for the wand and the panel) */
        glLoadMatrixd(P);
        glMatrixMode(GL_MODELVIEW);
        glLoadMatrixd(MV);
        overlays(w, eye, P, MV, vp);
        return;
    }
    int iw = (int)(vp[2] * vsv_fv.scale + 0.5), ih = (int)(vp[3] * vsv_fv.scale + 0.5);
    iw = iw < 16 ? 16 : iw, ih = ih < 16 ? 16 : ih;
    vsv_player_camera_from_gl(w->tk.place, P, MV, iw, ih, &cam);
    if (!w->tex[eye] || w->key[eye] != w->content || memcmp(&cam, &w->cam[eye], sizeof cam)) {
        const unsigned char *img = vsv_player_image(player, &cam, err, sizeof err);
        if (!img) {
            fail(err);
            return;
        }
        vsv_billboard_upload(&w->tex[eye], img, iw, ih);
        w->key[eye] = w->content;
        w->cam[eye] = cam;
    }
    double mn[3], mx[3], c[3];
    vsv_player_bounds(player, mn, mx);
    for (int i = 0; i < 3; i++)
        c[i] = 0.5 * (mn[i] + mx[i]);
    vsv_mat4_point(w->tk.place, c, c);
    vsv_billboard_quad(&cam, billboard_depth(P, MV, c), w->tex[eye], 0);
    overlays(w, eye, P, MV, vp);
}
