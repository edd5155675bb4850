/* vsv_gl_context.c — a headless OpenGL context through EGL (vsv_gl.h):
 * Mesa's surfaceless platform where it is offered (no X, no device
 * needed), else the first EGL device (a GPU's driver on a server), else
 * the default display; OpenGL 3.3 core (with no config where the display
 * allows it, else the first OpenGL config), current with no surface (the
 * raycaster draws into its own framebuffer). libepoxy loads libEGL only
 * here, when asked. */
#include "vsv_gl.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct vsv_gl_context {
    EGLDisplay dpy;
    EGLContext ctx;
};

static int has_ext(const char *list, const char *ext)
{
    const size_t n = strlen(ext);
    for (const char *p = list; p && (p = strstr(p, ext)); p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || !p[n]))
            return 1;
    return 0;
}

/* A display that can run without a window system, initialised. */
static EGLDisplay open_display(char *why, size_t cap)
{
    const char *client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    EGLDisplay d = EGL_NO_DISPLAY;
    EGLint maj, min;
    if (has_ext(client, "EGL_MESA_platform_surfaceless")) {
        d = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
        if (d != EGL_NO_DISPLAY && eglInitialize(d, &maj, &min))
            return d;
    }
    if (has_ext(client, "EGL_EXT_device_enumeration") && has_ext(client, "EGL_EXT_platform_device")) {
        EGLDeviceEXT dev[8];
        EGLint n = 0;
        if (eglQueryDevicesEXT(8, dev, &n))
            for (EGLint i = 0; i < n; i++) {
                d = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, dev[i], NULL);
                if (d != EGL_NO_DISPLAY && eglInitialize(d, &maj, &min))
                    return d;
            }
    }
    d = eglGetDisplay(EGL_DEFAULT_DISPLAY);
    if (d != EGL_NO_DISPLAY && eglInitialize(d, &maj, &min))
        return d;
    snprintf(why, cap, "no EGL display (surfaceless, device or default): EGL error 0x%x", (unsigned)eglGetError());
    return EGL_NO_DISPLAY;
}

int vsv_gl_context_create(vsv_gl_context **out, char *err, size_t cap)
{
    *out = NULL;
    if (!epoxy_has_egl()) {
        snprintf(err, cap, "no EGL library (libEGL.so.1: apt-get install libegl1 libegl-mesa0)");
        return VSV_EUNSUPPORTED;
    }
    vsv_gl_context *c = calloc(1, sizeof *c);
    if (!c) {
        snprintf(err, cap, "out of memory");
        return VSV_ENOMEM;
    }
    c->dpy = open_display(err, cap);
    if (c->dpy == EGL_NO_DISPLAY) {
        free(c);
        return VSV_EUNSUPPORTED;
    }
    const char *ext = eglQueryString(c->dpy, EGL_EXTENSIONS);
    if (!has_ext(ext, "EGL_KHR_surfaceless_context") || !eglBindAPI(EGL_OPENGL_API)) {
        snprintf(err, cap, "the EGL display (%s) has no surfaceless OpenGL contexts",
                 eglQueryString(c->dpy, EGL_VENDOR) ? eglQueryString(c->dpy, EGL_VENDOR) : "?");
        vsv_gl_context_free(c);
        return VSV_EUNSUPPORTED;
    }
    const EGLint core[] = {
        EGL_CONTEXT_MAJOR_VERSION,           3,       EGL_CONTEXT_MINOR_VERSION, 3, EGL_CONTEXT_OPENGL_PROFILE_MASK,
        EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    const EGLConfig none = (EGLConfig)0; /* (EGL_KHR_no_config_context, which Mesa has) */
    c->ctx = eglCreateContext(c->dpy, none, EGL_NO_CONTEXT, core);
    if (c->ctx == EGL_NO_CONTEXT) {
        EGLint n = 0;
        EGLConfig cfg;
        const EGLint want[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
        if (eglChooseConfig(c->dpy, want, &cfg, 1, &n) && n > 0)
            c->ctx = eglCreateContext(c->dpy, cfg, EGL_NO_CONTEXT, core);
    }
    if (c->ctx == EGL_NO_CONTEXT || !eglMakeCurrent(c->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, c->ctx)) {
        snprintf(err, cap, "no OpenGL 3.3 core context from EGL (%s): EGL error 0x%x",
                 eglQueryString(c->dpy, EGL_VENDOR) ? eglQueryString(c->dpy, EGL_VENDOR) : "?",
                 (unsigned)eglGetError());
        vsv_gl_context_free(c);
        return VSV_EUNSUPPORTED;
    }
    *out = c;
    return 0;
}

void vsv_gl_context_free(vsv_gl_context *c)
{
    if (!c)
        return;
    if (c->dpy != EGL_NO_DISPLAY) {
        eglMakeCurrent(c->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        if (c->ctx != EGL_NO_CONTEXT)
            eglDestroyContext(c->dpy, c->ctx);
        /* the display stays initialised: EGL has one per platform and
         * device in a process, and terminating it unloads the driver under
         * any other context of the process (the process's end frees it) */
    }
    free(c);
}
