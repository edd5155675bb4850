/* freevr_render.c — the FreeVR stand-in's render processes: the display
 * callbacks the application registers, one GLX window and context per
 * window object, each eye's off-axis frustum from the wall's corners and
 * the head, the stereo modes (each eye in its half of the window, or
 * through its colour mask), the simulator's own drawing, and the test
 * aid's frame dumps. */
#include "freevr_standin.h"

#include <GL/gl.h>
#include <GL/glx.h>
#include <X11/Xlib.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define NEAR_CLIP 0.1
#define FAR_CLIP 1000.0

/* ------------------------------------------------------------- callbacks */

struct vrCallback {
    void (*fn)(void);
    int argc;
    void *args[4];
};

static vrCallback g_cb[VRFUNC_DISPLAY_EXIT + 1];

static void call0(const vrCallback *cb)
{
    void *const *a = cb->args;
    switch (cb->argc) {
    case 0: ((void (*)(void))cb->fn)(); break;
    case 1: ((void (*)(void *))cb->fn)(a[0]); break;
    case 2: ((void (*)(void *, void *))cb->fn)(a[0], a[1]); break;
    case 3: ((void (*)(void *, void *, void *))cb->fn)(a[0], a[1], a[2]); break;
    default: ((void (*)(void *, void *, void *, void *))cb->fn)(a[0], a[1], a[2], a[3]); break;
    }
}

static void call_ri(const vrCallback *cb, vrRenderInfo *ri)
{
    void *const *a = cb->args;
    switch (cb->argc) {
    case 0: ((void (*)(vrRenderInfo *))cb->fn)(ri); break;
    case 1: ((void (*)(vrRenderInfo *, void *))cb->fn)(ri, a[0]); break;
    case 2: ((void (*)(vrRenderInfo *, void *, void *))cb->fn)(ri, a[0], a[1]); break;
    case 3: ((void (*)(vrRenderInfo *, void *, void *, void *))cb->fn)(ri, a[0], a[1], a[2]); break;
    default: ((void (*)(vrRenderInfo *, void *, void *, void *, void *))cb->fn)(ri, a[0], a[1], a[2], a[3]); break;
    }
}

/* FreeVR's callback functions are unprototyped (void (*)()) */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wstrict-prototypes"
static void store(vrCallback *cb, void (*fn)(), int argc, va_list ap)
{
    cb->fn = (void (*)(void))fn;
    cb->argc = argc < 0 ? 0 : argc > 4 ? 4 : argc;
    for (int i = 0; i < cb->argc; i++)
        cb->args[i] = va_arg(ap, void *);
}

void vrCallbackSet(vrFuncType type, char *name, void (*fn)(), int argc, ...)
{
    (void)name;
    va_list ap;
    va_start(ap, argc);
    if ((int)type >= 0 && type <= VRFUNC_DISPLAY_EXIT)
        store(&g_cb[type], fn, argc, ap);
    va_end(ap);
}

vrCallback *vrCallbackCreate(void (*fn)(), int argc, ...)
{
    vrCallback *cb = calloc(1, sizeof *cb);
    va_list ap;
    va_start(ap, argc);
    if (cb)
        store(cb, fn, argc, ap);
    va_end(ap);
    return cb;
}
#pragma GCC diagnostic pop

void vrFunctionSetCallback(vrFuncType type, vrCallback *cb)
{
    if (cb && (int)type >= 0 && type <= VRFUNC_DISPLAY_EXIT)
        g_cb[type] = *cb;
}

/* ------------------------------------------------------------ projection */

static void sub3(const double *a, const double *b, double *o)
{
    o[0] = a[0] - b[0], o[1] = a[1] - b[1], o[2] = a[2] - b[2];
}
static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static void cross3(const double *a, const double *b, double *o)
{
    o[0] = a[1] * b[2] - a[2] * b[1], o[1] = a[2] * b[0] - a[0] * b[2], o[2] = a[0] * b[1] - a[1] * b[0];
}
static void norm3(double *a)
{
    const double l = sqrt(dot3(a, a));
    if (l > 0)
        a[0] /= l, a[1] /= l, a[2] /= l;
}

/* How far an eye sits along the head's right vector (feet): half the
 * user's iod to the left (eye 0) or to the right (eye 1) in stereo and in
 * the one-eyed left and right modes, none in mono. */
static double eye_shift(int mode, int eye)
{
    if (mode == FVS_VISREN_MONO)
        return 0;
    return (eye ? 0.5 : -0.5) * fvs_cfg.iod;
}

/* The eye's frustum and the real world -> wall rotation for a window, the
 * eye `shift` feet right of the viewpoint: fixed walls from their corners
 * and the head (an off-axis frustum on the wall's plane, the eyes along
 * the head's right vector); the simulator from its own viewpoint (60
 * degrees high, the eyes along its right vector). */
static void perspective(const win_def *w, int width, int height, double shift, vrPerspective *p)
{
    double r[3], u[3], n[3], e[3];
    if (w->simulator) {
        const double from[3] = {0, 7, 12}, at[3] = {0, 4, -3}, up[3] = {0, 1, 0};
        sub3(from, at, n);
        const double dist = sqrt(dot3(n, n));
        norm3(n);
        cross3(up, n, r);
        norm3(r);
        cross3(n, r, u);
        for (int i = 0; i < 3; i++)
            e[i] = from[i] + shift * r[i];
        const double t = NEAR_CLIP * tan(30 * M_PI / 180), a = (double)width / (height > 0 ? height : 1);
        /* the eyes converge on `at`: its plane is the screen's */
        const double off = shift * NEAR_CLIP / dist;
        p->frustum.n.left = -t * a - off, p->frustum.n.right = t * a - off;
        p->frustum.n.bottom = -t, p->frustum.n.top = t;
    } else {
        const double *ll = w->c, *lr = w->c + 3, *ul = w->c + 6, *head = fvs_base->sensor[0];
        double va[3], vb[3], vc[3];
        for (int i = 0; i < 3; i++)
            e[i] = head[12 + i] + shift * head[i]; /* column 0: the head's right */
        sub3(lr, ll, r);
        norm3(r);
        sub3(ul, ll, u);
        norm3(u);
        cross3(r, u, n); /* towards the viewer */
        norm3(n);
        sub3(ll, e, va);
        sub3(lr, e, vb);
        sub3(ul, e, vc);
        double d = -dot3(va, n);
        if (!(fabs(d) > 1e-6))
            d = 1e-6;
        p->frustum.n.left = dot3(r, va) * NEAR_CLIP / d;
        p->frustum.n.right = dot3(r, vb) * NEAR_CLIP / d;
        p->frustum.n.bottom = dot3(u, va) * NEAR_CLIP / d;
        p->frustum.n.top = dot3(u, vc) * NEAR_CLIP / d;
    }
    p->frustum.near_clip = NEAR_CLIP;
    p->frustum.far_clip = FAR_CLIP;
    memcpy(p->eye, e, sizeof p->eye);
    double *m = p->rw2w_xform.v;
    memset(m, 0, sizeof p->rw2w_xform.v);
    for (int i = 0; i < 3; i++)
        m[i * 4 + 0] = r[i], m[i * 4 + 1] = u[i], m[i * 4 + 2] = n[i];
    m[15] = 1;
}

static void load_matrices(const vrPerspective *p)
{
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glFrustum(p->frustum.n.left, p->frustum.n.right, p->frustum.n.bottom, p->frustum.n.top, p->frustum.near_clip,
              p->frustum.far_clip);
    glMatrixMode(GL_MODELVIEW);
    glLoadMatrixd(p->rw2w_xform.v);
    glTranslated(-p->eye[0], -p->eye[1], -p->eye[2]);
}

/* The simulator's own drawing: the CAVE's outline, the head (a brown cube)
 * and the wand. */
static void draw_simulator(void)
{
    glDisable(GL_TEXTURE_2D);
    glEnable(GL_DEPTH_TEST);
    glColor3f(0.6f, 0.6f, 0.6f);
    glBegin(GL_LINES);
    for (int i = 0; i < 4; i++) {
        const double x0 = i & 1 ? 5 : -5, z0 = i & 2 ? 5 : -5;
        glVertex3d(x0, 0, z0), glVertex3d(x0, 10, z0);
        glVertex3d(x0, 0, z0), glVertex3d(i & 1 ? -5 : 5, 0, z0);
        glVertex3d(x0, 10, z0), glVertex3d(i & 1 ? -5 : 5, 10, z0);
        glVertex3d(x0, 0, z0), glVertex3d(x0, 0, -z0);
        glVertex3d(x0, 10, z0), glVertex3d(x0, 10, -z0);
    }
    glEnd();
    const double *h = fvs_base->sensor[0] + 12, *wand = fvs_base->sensor[1], s = 0.25;
    glColor3f(0.55f, 0.35f, 0.15f);
    glBegin(GL_QUADS);
    for (int f = 0; f < 6; f++) {
        const int ax = f / 2, a1 = (ax + 1) % 3, a2 = (ax + 2) % 3;
        const double sg = f % 2 ? s : -s;
        const double q[4][2] = {{-s, -s}, {s, -s}, {s, s}, {-s, s}};
        for (int k = 0; k < 4; k++) {
            double v[3];
            v[ax] = h[ax] + sg, v[a1] = h[a1] + q[k][0], v[a2] = h[a2] + q[k][1];
            glVertex3dv(v);
        }
    }
    glEnd();
    glColor3f(0.8f, 0.8f, 0.2f); /* a foot along the wand's fore (-z of its pose) */
    glBegin(GL_LINES);
    glVertex3dv(wand + 12);
    glVertex3d(wand[12] - wand[8], wand[13] - wand[9], wand[14] - wand[10]);
    glEnd();
}

/* ------------------------------------------------------- render process */

typedef struct {
    const win_def *def;
    Window xw;
    GLXContext ctx;
    unsigned long frames;
} render_win;

/* the dumps' pixels: grown with the largest window, not made per frame */
static unsigned char *g_px;
static size_t g_pxcap;

static void dump(const render_win *w, int width, int height)
{
    const char *dir = getenv("FREEVR_STANDIN_DUMP");
    if (!dir || !*dir || width < 1 || height < 1)
        return;
    const size_t need = (size_t)width * height * 3;
    if (need > g_pxcap) {
        unsigned char *more = realloc(g_px, need);
        if (!more)
            return;
        g_px = more, g_pxcap = need;
    }
    unsigned char *px = g_px;
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, px);
    char path[4096], tmp[4200];
    snprintf(path, sizeof path, "%s/%s.ppm", dir, w->def->name);
    snprintf(tmp, sizeof tmp, "%s.tmp.%d", path, (int)getpid());
    FILE *fp = fopen(tmp, "wb");
    if (fp) {
        fprintf(fp, "P6\n# frame %lu\n%d %d\n255\n", w->frames, width, height);
        for (int y = height - 1; y >= 0; y--) /* top row first */
            fwrite(px + (size_t)y * width * 3, 1, (size_t)width * 3, fp);
        if (fclose(fp) == 0)
            rename(tmp, path);
        else
            remove(tmp);
    }
}

static int x_error(Display *d, XErrorEvent *e)
{
    char msg[256];
    XGetErrorText(d, e->error_code, msg, sizeof msg);
    fprintf(stderr, "FreeVR: X error: %s\n", msg);
    return 0;
}

void fvs_render_process(const proc_def *p)
{
    render_win wins[MAXWIN];
    int n = 0;
    Display *dpy = XOpenDisplay(NULL);
    if (!dpy) {
        fprintf(stderr, "FreeVR: cannot open the display '%s'\n", getenv("DISPLAY") ? getenv("DISPLAY") : "");
        fvs_base->quit = 1;
        _exit(1);
    }
    XSetErrorHandler(x_error);
    int attrs[] = {GLX_RGBA, GLX_DOUBLEBUFFER, GLX_RED_SIZE, 1,   GLX_GREEN_SIZE, 1, GLX_BLUE_SIZE,
                   1,        GLX_DEPTH_SIZE,   16,           None};
    XVisualInfo *vi = glXChooseVisual(dpy, DefaultScreen(dpy), attrs);
    if (!vi) {
        fprintf(stderr, "FreeVR: no double-buffered RGBA visual with depth\n");
        fvs_base->quit = 1;
        _exit(1);
    }
    for (int k = 0; k < p->nobj && n < MAXWIN; k++) {
        const win_def *d = fvs_find_win(p->obj[k]);
        if (!d) {
            fprintf(stderr, "FreeVR: process '%s': no window '%s'\n", p->name, p->obj[k]);
            continue;
        }
        /* FreeVR's own state for this window, from the shared arena */
        if (!fvs_amalloc(fvs_per_window)) {
            fprintf(stderr, "FreeVR: render process %d (%s window) waits for memory\n", (int)getpid(), d->name);
            for (;;)
                pause();
        }
        render_win *w = &wins[n++];
        memset(w, 0, sizeof *w);
        w->def = d;
        XSetWindowAttributes swa;
        memset(&swa, 0, sizeof swa);
        swa.colormap = XCreateColormap(dpy, RootWindow(dpy, vi->screen), vi->visual, AllocNone);
        swa.event_mask = ExposureMask | StructureNotifyMask;
        w->xw = XCreateWindow(dpy, RootWindow(dpy, vi->screen), d->x, d->y, (unsigned)d->w, (unsigned)d->h, 0,
                              vi->depth, InputOutput, vi->visual, CWColormap | CWEventMask, &swa);
        char title[256];
        snprintf(title, sizeof title, "FreeVR(%d): %s window", (int)getpid(), d->name);
        XStoreName(dpy, w->xw, title);
        XMapWindow(dpy, w->xw);
        w->ctx = glXCreateContext(dpy, vi, NULL, True);
        if (!w->ctx || !glXMakeCurrent(dpy, w->xw, w->ctx)) {
            fprintf(stderr, "FreeVR: cannot create a GLX context for the %s window\n", d->name);
            fvs_base->quit = 1;
            _exit(1);
        }
        if (g_cb[VRFUNC_DISPLAY_INIT].fn)
            call0(&g_cb[VRFUNC_DISPLAY_INIT]);
    }
    XSync(dpy, False);
    while (!fvs_base->quit) {
        const double t0 = fvs_now();
        while (XPending(dpy)) {
            XEvent ev;
            XNextEvent(dpy, &ev);
        }
        for (int k = 0; k < n && !fvs_base->quit; k++) {
            render_win *w = &wins[k];
            XWindowAttributes wa;
            XGetWindowAttributes(dpy, w->xw, &wa);
            glXMakeCurrent(dpy, w->xw, w->ctx);
            glViewport(0, 0, wa.width, wa.height);
            const int mode = fvs_config_visren(w->def);
            const int stereo = mode == FVS_VISREN_DUALVP || mode == FVS_VISREN_ANAGLYPHIC;
            const int first = stereo ? 0 : mode == FVS_VISREN_RIGHT, last = stereo ? 1 : first;
            vrPerspective persp;
            vrRenderInfo ri = {&persp, w->def->name, first};
            if (g_cb[VRFUNC_DISPLAY_FRAME].fn) { /* once a window, before the eyes */
                perspective(w->def, wa.width, wa.height, stereo ? 0 : eye_shift(mode, first), &persp);
                load_matrices(&persp);
                call_ri(&g_cb[VRFUNC_DISPLAY_FRAME], &ri);
            }
            /* once per eye (FREEVR.md, "Stereo"): in dualvp each eye's
             * viewport and scissor are its half of the window (the left
             * eye's the left half), so its clear wipes only that half; in
             * anaglyphic both eyes fill the window, the left through red
             * and the right through green and blue */
            for (int eye = first; eye <= last; eye++) {
                int vx = 0, vw = wa.width;
                if (mode == FVS_VISREN_DUALVP) {
                    vx = eye ? wa.width / 2 : 0;
                    vw = eye ? wa.width - wa.width / 2 : wa.width / 2;
                    glViewport(vx, 0, vw, wa.height);
                    glScissor(vx, 0, vw, wa.height);
                    glEnable(GL_SCISSOR_TEST);
                } else if (mode == FVS_VISREN_ANAGLYPHIC)
                    glColorMask(eye == 0, eye == 1, eye == 1, GL_TRUE);
                perspective(w->def, vw, wa.height, eye_shift(mode, eye), &persp);
                ri.eye = eye;
                load_matrices(&persp); /* no clearing: the application's job */
                if (g_cb[VRFUNC_DISPLAY].fn)
                    call_ri(&g_cb[VRFUNC_DISPLAY], &ri);
                if (w->def->simulator) {
                    load_matrices(&persp);
                    draw_simulator();
                }
            }
            glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
            glDisable(GL_SCISSOR_TEST);
            glViewport(0, 0, wa.width, wa.height);
            w->frames++;
            dump(w, wa.width, wa.height);
            glXSwapBuffers(dpy, w->xw);
        }
        const double left = 1.0 / 60 - (fvs_now() - t0); /* at most 60 frames a second */
        if (left > 0)
            nanosleep(&(struct timespec){0, (long)(left * 1e9)}, NULL);
    }
    for (int k = 0; k < n; k++) {
        glXMakeCurrent(dpy, wins[k].xw, wins[k].ctx);
        if (g_cb[VRFUNC_DISPLAY_EXIT].fn)
            call0(&g_cb[VRFUNC_DISPLAY_EXIT]);
        glXMakeCurrent(dpy, None, NULL);
        glXDestroyContext(dpy, wins[k].ctx);
        XDestroyWindow(dpy, wins[k].xw);
    }
    XCloseDisplay(dpy);
    fvs_process_done();
    _exit(0);
}
