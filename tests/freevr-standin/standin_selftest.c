/* standin_selftest.c — a small FreeVR program that exercises the project's
 * FreeVR stand-in alone, without Vesuvius, for the checks by hand in
 * README-checks.txt. Built by `make build/tests/freevr-standin/selftest`,
 * never by `make test`.
 *
 *   selftest sensors [FREEVR-CONFIGURATION...]
 *       prints where the head and the wand are (vrPointGetRWFrom6sensor)
 *       and where the wand points (vrVectorGetRWFrom6sensorDir), then exits
 *       through vrExit without starting anything;
 *   selftest run SECONDS [FREEVR-CONFIGURATION...]
 *       runs FreeVR (vrStart, vrFrame) until Escape or SECONDS (0: for
 *       ever), then calls vrExit and says when it returns. On each window's
 *       first frame (SELFTEST_FRAMES frames: more) every display callback
 *       prints what it found: the eye, the frustum FreeVR loaded, where the
 *       eye is, the viewport, the scissor test and the colour mask, and
 *       where a point 2 feet in front of the head and one 8 feet in front
 *       land (normalised x). Each eye clears its part of the window: the
 *       left eye to white, the right to grey (128), so a frame dump
 *       (FREEVR_STANDIN_DUMP) shows which eye wrote where.
 *
 * Only the first argument is the selftest's (the second too for run); the
 * rest go to vrConfigure as FreeVR configuration strings. */
#include "freevr_standin.h" /* to read ri->eye and ri->window, which FreeVR keeps opaque */

#include <GL/gl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static int FRAMES = 1; /* frames of each window whose callbacks print */

/* per render process: how many frames each of its windows has begun */
static struct {
    const char *name;
    int frames;
} g_win[MAXWIN];
static int g_nwin;

static int *frames_of(const char *name)
{
    for (int i = 0; i < g_nwin; i++)
        if (g_win[i].name == name)
            return &g_win[i].frames;
    if (g_nwin == MAXWIN)
        return &g_win[0].frames;
    g_win[g_nwin].name = name;
    return &g_win[g_nwin++].frames;
}

static void display_frame(vrRenderInfo *ri)
{
    const int n = ++*frames_of(ri->window);
    if (n <= FRAMES)
        printf("pid %d window %s frame %d: VRFUNC_DISPLAY_FRAME\n", (int)getpid(), ri->window, n);
}

/* where a real-world point lands in the loaded projection: normalised x */
static double ndc_x(const double P[16], const double M[16], const double p[3])
{
    double e[4], c[4];
    for (int i = 0; i < 4; i++)
        e[i] = M[i] * p[0] + M[4 + i] * p[1] + M[8 + i] * p[2] + M[12 + i];
    for (int i = 0; i < 4; i++)
        c[i] = P[i] * e[0] + P[4 + i] * e[1] + P[8 + i] * e[2] + P[12 + i] * e[3];
    return c[0] / c[3];
}

static void display(vrRenderInfo *ri)
{
    /* FreeVR does not clear: each eye clears what it may */
    const float grey = ri->eye ? 0.5f : 1.0f;
    glClearColor(grey, grey, grey, 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    const int n = *frames_of(ri->window);
    if (n > FRAMES)
        return;
    double P[16], M[16];
    GLint vp[4], sc[4];
    GLboolean mask[4];
    glGetDoublev(GL_PROJECTION_MATRIX, P);
    glGetDoublev(GL_MODELVIEW_MATRIX, M);
    glGetIntegerv(GL_VIEWPORT, vp);
    glGetIntegerv(GL_SCISSOR_BOX, sc);
    glGetBooleanv(GL_COLOR_WRITEMASK, mask);
    /* glFrustum's planes back from the matrix, at the near plane */
    const double near = P[14] / (P[10] - 1), l = near * (P[8] - 1) / P[0], r = near * (P[8] + 1) / P[0];
    const double b = near * (P[9] - 1) / P[5], t = near * (P[9] + 1) / P[5];
    /* the eye: minus the rotation's transpose times the translation */
    double eye[3];
    for (int i = 0; i < 3; i++)
        eye[i] = -(M[i * 4 + 0] * M[12] + M[i * 4 + 1] * M[13] + M[i * 4 + 2] * M[14]);
    vrPoint h;
    vrPointGetRWFrom6sensor(&h, 0);
    const double near2[3] = {h.v[0], h.v[1], h.v[2] - 2}, far8[3] = {h.v[0], h.v[1], h.v[2] - 8};
    printf("pid %d window %s frame %d: VRFUNC_DISPLAY eye %d (%s) frustum l %.4f r %.4f b %.4f t %.4f near %.2f;"
           " eye at (%.3f, %.3f, %.3f); viewport %d %d %d %d; scissor %s %d %d %d %d; colour mask %d%d%d%d;"
           " x of 2 ft ahead %.4f, of 8 ft ahead %.4f\n",
           (int)getpid(), ri->window, n, ri->eye, ri->eye ? "right" : "left/mono", l, r, b, t, near, eye[0], eye[1],
           eye[2], vp[0], vp[1], vp[2], vp[3], glIsEnabled(GL_SCISSOR_TEST) ? "on" : "off", sc[0], sc[1], sc[2], sc[3],
           mask[0], mask[1], mask[2], mask[3], ndc_x(P, M, near2), ndc_x(P, M, far8));
}

static void print_sensors(void)
{
    const char *names[2] = {"head", "wand"};
    for (int n = 0; n < 2; n++) {
        vrPoint p;
        vrVector fore, right;
        vrPointGetRWFrom6sensor(&p, n);
        vrVectorGetRWFrom6sensorDir(&fore, n, VRDIR_FORE);
        vrVectorGetRWFrom6sensorDir(&right, n, VRDIR_RIGHT);
        printf("sensor %d (%s) at (%.3f, %.3f, %.3f), fore (%.3f, %.3f, %.3f), right (%.3f, %.3f, %.3f)\n", n, names[n],
               p.v[0], p.v[1], p.v[2], fore.v[0], fore.v[1], fore.v[2], right.v[0], right.v[1], right.v[2]);
    }
}

int main(int argc, char **argv)
{
    if (argc < 2 || (strcmp(argv[1], "sensors") && (strcmp(argv[1], "run") || argc < 3))) {
        fprintf(stderr, "usage: %s sensors|run SECONDS [FREEVR-CONFIGURATION...]\n", argv[0]);
        return 2;
    }
    const int run = !strcmp(argv[1], "run");
    const double seconds = run ? atof(argv[2]) : 0;
    if (getenv("SELFTEST_FRAMES"))
        FRAMES = atoi(getenv("SELFTEST_FRAMES"));
    setvbuf(stdout, NULL, _IOLBF, 0); /* several processes write here */
    /* FreeVR's arguments: argv[0] and what follows the selftest's own */
    const int skip = run ? 2 : 1;
    int fargc = argc - skip;
    char **fargv = argv + skip;
    fargv[0] = argv[0];
    vrConfigure(&fargc, fargv, NULL);
    struct sigaction now;
    sigaction(SIGINT, NULL, &now);
    printf("main pid %d: SIGINT after vrConfigure: %s\n", (int)getpid(),
           now.sa_handler == SIG_IGN ? "ignored" : "default or handled");
    print_sensors();
    if (!run) {
        vrExit();
        printf("vrExit returned\n");
        return 0;
    }
    vrCallbackSet(VRFUNC_DISPLAY_FRAME, "selftest_frame", display_frame, 0);
    vrCallbackSet(VRFUNC_DISPLAY, "selftest_display", display, 0);
    vrStart();
    const double t0 = vrCurrentSimTime();
    while (vrFrame() && (seconds <= 0 || vrCurrentSimTime() - t0 < seconds))
        nanosleep(&(struct timespec){0, 10000000}, NULL);
    printf("main pid %d: calling vrExit\n", (int)getpid());
    vrExit();
    printf("main pid %d: vrExit returned\n", (int)getpid());
    return 0;
}
