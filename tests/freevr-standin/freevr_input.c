/* freevr_input.c — the FreeVR stand-in's input and tracking: the input
 * process polling the X server for its xwindows devices' keys and buttons
 * (2switches) and the pointer (valuators while space is held), the main
 * process's per-frame copy of them, the simulated head and wand sensors
 * (where the configuration, or the test aid, puts them), and the user's
 * travel matrix. */
#include "freevr_standin.h"

#include <GL/gl.h>
#include <X11/Xlib.h>
#include <X11/keysym.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

/* --------------------------------------------------------- input process */

void fvs_input_process(const proc_def *p)
{
    Display *dpy = XOpenDisplay(NULL);
    if (!dpy) {
        fprintf(stderr, "FreeVR: input: cannot open the display\n");
        fvs_base->quit = 1;
        _exit(1);
    }
    const dev_def *devs[MAXWIN];
    int nd = 0;
    for (int k = 0; k < p->nobj; k++) {
        const dev_def *d = fvs_find_dev(p->obj[k]);
        if (d && d->xwindows && nd < MAXWIN)
            devs[nd++] = d;
    }
    const KeyCode space = XKeysymToKeycode(dpy, XK_space);
    const long usec = p->usecmin > 0 ? p->usecmin : 16667;
    while (!fvs_base->quit) {
        char keys[32];
        Window root, child;
        int rx, ry, wx, wy;
        unsigned int mask = 0;
        XQueryKeymap(dpy, keys);
        XQueryPointer(dpy, DefaultRootWindow(dpy), &root, &child, &rx, &ry, &wx, &wy, &mask);
        int sw = 0;
        for (int k = 0; k < nd; k++)
            for (int i = 0; i < devs[k]->nin && sw < NSW; i++, sw++) {
                int on;
                if (devs[k]->in[i].button)
                    on = !!(mask & (Button1Mask << (devs[k]->in[i].button - 1)));
                else {
                    const KeyCode kc = XKeysymToKeycode(dpy, devs[k]->in[i].keysym);
                    on = kc && (keys[kc / 8] >> (kc % 8) & 1);
                }
                fvs_base->sw[sw] = on;
            }
        if (space && (keys[space / 8] >> (space % 8) & 1)) { /* the pointer is the joystick while space is held */
            const int W = DisplayWidth(dpy, DefaultScreen(dpy)), H = DisplayHeight(dpy, DefaultScreen(dpy));
            fvs_base->val[0] = (float)(2.0 * rx / W - 1);
            fvs_base->val[1] = (float)(1 - 2.0 * ry / H);
        } else {
            fvs_base->val[0] = fvs_base->val[1] = 0;
        }
        nanosleep(&(struct timespec){usec / 1000000, (usec % 1000000) * 1000}, NULL);
    }
    XCloseDisplay(dpy);
    fvs_process_done();
    _exit(0);
}

/* --------------------------------------------------------- main process */

static int g_cur[NSW], g_prev[NSW];
static float g_vcur[NVAL], g_vprev[NVAL];
static int g_quit_seen;

int vrFrame(void)
{
    if (!fvs_base)
        return 0;
    memcpy(g_prev, g_cur, sizeof g_cur);
    memcpy(g_vprev, g_vcur, sizeof g_vcur);
    for (int i = 0; i < NSW; i++)
        g_cur[i] = fvs_base->sw[i];
    for (int i = 0; i < NVAL; i++)
        g_vcur[i] = fvs_base->val[i];
    if (g_cur[0] || fvs_base->quit)
        g_quit_seen = 1;
    return !g_quit_seen;
}

int vrGet2switchValue(int n) { return n >= 0 && n < NSW ? g_cur[n] : 0; }
int vrGet2switchDelta(int n) { return n >= 0 && n < NSW ? g_cur[n] - g_prev[n] : 0; }
float vrGetValuatorValue(int n) { return n >= 0 && n < NVAL ? g_vcur[n] : 0; }
float vrGetValuatorDelta(int n) { return n >= 0 && n < NVAL ? g_vcur[n] - g_vprev[n] : 0; }

/* ---------------------------------------------------------------- sensors */

/* A pose (OpenGL column order): at pos, turned yaw degrees about +y from
 * looking along -z (positive: to the left), then pitched up by pitch. */
static void pose(double m[16], const double pos[3], double yaw, double pitch)
{
    const double a = yaw * M_PI / 180, p = pitch * M_PI / 180;
    const double ca = cos(a), sa = sin(a), cp = cos(p), sp = sin(p);
    const double cols[16] = {ca,      0,      -sa,     0, /* right */
                             sa * sp, cp,     ca * sp, 0, /* up */
                             sa * cp, -sp,    ca * cp, 0, /* back */
                             pos[0],  pos[1], pos[2],  1};
    memcpy(m, cols, sizeof cols);
}

/* "x,y,z[,yaw,pitch]" from a test-aid variable: how many numbers (at
 * least min, at most max), or 0 when it is not that. */
static int numbers(const char *name, int min, int max, double *out)
{
    const char *s = getenv(name);
    int n = 0;
    if (!s || !*s)
        return 0;
    for (const char *p = s;;) {
        char *end;
        const double v = strtod(p, &end);
        if (end == p || n == max || !isfinite(v))
            break;
        out[n++] = v;
        while (*end == ' ')
            end++;
        if (!*end && n >= min)
            return n;
        if (*end != ',')
            break;
        p = end + 1;
    }
    fprintf(stderr, "FreeVR stand-in: %s='%s' is not x,y,z%s (feet%s): ignored\n", name, s,
            max > 3 ? "[,yaw,pitch]" : "", max > 3 ? ", degrees" : "");
    return 0;
}

void fvs_sensors_init(void)
{
    double pos[3], v[5] = {0, 0, 0, 0, 0};
    /* the head and the wand where the configuration starts them, looking
     * along -z (FREEVR.md, "Where the head starts") */
    for (int n = 0; n < 2; n++) {
        fvs_config_sensor(n, pos);
        pose(fvs_base->sensor[n], pos, 0, 0);
    }
    /* test aid (not FreeVR): FREEVR_STANDIN_HEAD=x,y,z and
     * FREEVR_STANDIN_WAND=x,y,z[,yaw,pitch] override the configuration */
    if (numbers("FREEVR_STANDIN_HEAD", 3, 3, v))
        pose(fvs_base->sensor[0], v, 0, 0);
    v[3] = v[4] = 0;
    if (numbers("FREEVR_STANDIN_WAND", 3, 5, v))
        pose(fvs_base->sensor[1], v, v[3], v[4]);
}

/* FreeVR's 6-sensors 0 (the head) and 1 (the wand); any other stays at the
 * real-world origin, looking along -z. */
static const double *sensor(int n)
{
    static const double none[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    return fvs_base && (n == 0 || n == 1) ? fvs_base->sensor[n] : none;
}

vrMatrix *vrMatrixGet6sensorValues(vrMatrix *m, int n)
{
    memcpy(m->v, sensor(n), sizeof m->v);
    return m;
}

vrPoint *vrPointGetRWFrom6sensor(vrPoint *p, int n)
{
    memcpy(p->v, sensor(n) + 12, sizeof p->v);
    return p;
}

vrVector *vrVectorGetRWFrom6sensorDir(vrVector *v, int n, vrDirection d)
{
    /* the pose's columns: 0 right, 1 up, 2 back */
    static const struct {
        int col;
        double sign;
    } dirs[6] = {{2, -1}, {2, 1}, {0, -1}, {0, 1}, {1, 1}, {1, -1}};
    const double *m = sensor(n);
    const int k = (int)d >= 0 && d <= VRDIR_DOWN ? (int)d : 0;
    for (int i = 0; i < 3; i++)
        v->v[i] = dirs[k].sign * m[dirs[k].col * 4 + i];
    return v;
}

int vrInputSet2switchDescription(int n, char *text)
{
    (void)text;
    if (fvs_base && !fvs_base->started && n >= fvs_config_count('i'))
        fprintf(stderr, "FreeVR: Creating dummy 2switch[%d]\n", n);
    return n;
}

/* ---------------------------------------------------------------- travel */

void vrRenderTransformUserTravel(vrRenderInfo *ri)
{
    (void)ri;
    if (fvs_base)
        glMultMatrixd(fvs_base->travel);
}
void vrUserTravelLockSet(int user) { (void)user; }
void vrUserTravelLockRelease(int user) { (void)user; }
void vrUserTravelReset(int user)
{
    (void)user;
    for (int i = 0; fvs_base && i < 16; i++)
        fvs_base->travel[i] = i % 5 == 0;
}
void vrUserTravelTranslate3d(int user, double x, double y, double z)
{
    (void)user;
    if (fvs_base) {
        double *t = fvs_base->travel;
        for (int i = 0; i < 3; i++)
            t[12 + i] += t[i] * x + t[4 + i] * y + t[8 + i] * z;
    }
}
void vrUserTravelRotateId(int user, int axis, double degrees)
{
    (void)user;
    if (!fvs_base || axis != VR_Y)
        return;
    const double c = cos(degrees * M_PI / 180), s = sin(degrees * M_PI / 180);
    double *t = fvs_base->travel, o[8];
    for (int i = 0; i < 4; i++) /* t = t * Ry */
        o[i] = t[i] * c - t[8 + i] * s, o[4 + i] = t[i] * s + t[8 + i] * c;
    for (int i = 0; i < 4; i++)
        t[i] = o[i], t[8 + i] = o[4 + i];
}
