/* vsv_panel.c — see vsv_panel.h. Legacy OpenGL (1.1 + non-power-of-two
 * textures), which FreeVR's contexts provide. */
#include "vsv_panel.h"

#include <GL/gl.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define REF_PX 24 /* the font size the panel is measured at */
#define MIN_PX 6
#define MAX_PX 64

struct vsv_panel {
    vsv_font *font;
    int px;        /* the font's size */
    vsv_font *ref; /* REF_PX, for measuring */
    GLuint tex;
    uint64_t key; /* what the texture shows */
    int tw, th;
    float *rgba;
    unsigned char *rgba8;
    size_t cap;
};

vsv_panel *vsv_panel_create(void) { return calloc(1, sizeof(vsv_panel)); }

void vsv_panel_free(vsv_panel *pn)
{
    if (!pn)
        return;
    if (pn->tex)
        glDeleteTextures(1, &pn->tex);
    vsv_font_free(pn->font);
    vsv_font_free(pn->ref);
    free(pn->rgba);
    free(pn->rgba8);
    free(pn);
}

static uint64_t fnv(uint64_t h, const void *p, size_t n)
{
    const unsigned char *b = p;
    for (size_t i = 0; i < n; i++)
        h = (h ^ b[i]) * 1099511628211ull;
    return h;
}

/* What the legend shows, as a key. */
static uint64_t content_key(const vsv_annot *a, const vsv_scene *sc, const char *lines, int px)
{
    uint64_t h = fnv(1469598103934665603ull, &px, sizeof px);
    h = fnv(h, &a->time, sizeof a->time);
    h = fnv(h, lines ? lines : "", lines ? strlen(lines) : 0);
    for (int l = 0; l < sc->nlayers; l++) {
        const vsv_layer *L = &sc->layers[l];
        const int on = L->visible && L->opacity > 0;
        h = fnv(h, &on, sizeof on);
        h = fnv(h, &L->tf, sizeof L->tf);
    }
    return fnv(h, &sc->nslices, sizeof sc->nslices);
}

int vsv_panel_measure(vsv_panel *pn, const vsv_annot *a, const vsv_scene *sc, const char *lines, double lh, double *w,
                      double *h, char *err, size_t cap)
{
    if (!pn->ref && vsv_font_open(NULL, REF_PX, &pn->ref, err, cap))
        return -1;
    vsv_annot m = *a;
    m.font = pn->ref;
    int pw, ph;
    vsv_legend_size(&m, sc, lines, &pw, &ph);
    const double line = vsv_font_line(pn->ref);
    *w = pw / line * lh;
    *h = ph / line * lh;
    return 0;
}

/* Window pixel coordinates of room point p; 0 when it is behind the eye. */
static int project(const double P[16], const double MV[16], const int vp[4], const double p[3], double out[2])
{
    double e[4], c[4];
    for (int i = 0; i < 4; i++)
        e[i] = MV[i] * p[0] + MV[4 + i] * p[1] + MV[8 + i] * p[2] + MV[12 + i];
    for (int i = 0; i < 4; i++)
        c[i] = P[i] * e[0] + P[4 + i] * e[1] + P[8 + i] * e[2] + P[12 + i] * e[3];
    if (!(c[3] > 1e-9))
        return 0;
    out[0] = vp[0] + (c[0] / c[3] + 1) * 0.5 * vp[2];
    out[1] = vp[1] + (c[1] / c[3] + 1) * 0.5 * vp[3];
    return 1;
}

/* The legend at font size px into the texture; 0 or -1. */
static int rasterise(vsv_panel *pn, const vsv_annot *a, const vsv_scene *sc, const char *lines, int px)
{
    if (pn->px != px || !pn->font) {
        char err[256];
        vsv_font_free(pn->font);
        pn->font = NULL;
        if (vsv_font_open(NULL, px, &pn->font, err, sizeof err))
            return -1;
        pn->px = px;
    }
    vsv_annot m = *a;
    m.font = pn->font;
    int w, h;
    vsv_legend_size(&m, sc, lines, &w, &h);
    const size_t n = (size_t)w * h;
    if (n > pn->cap) {
        float *f = realloc(pn->rgba, n * 4 * sizeof *f);
        if (f)
            pn->rgba = f;
        unsigned char *b = realloc(pn->rgba8, n * 4);
        if (b)
            pn->rgba8 = b;
        if (!f || !b)
            return -1;
        pn->cap = n;
    }
    vsv_legend_draw(&m, sc, lines, pn->rgba, w, h);
    for (size_t i = 0; i < n; i++) { /* premultiplied linear -> straight sRGB-ish, as frames are written */
        const float *q = pn->rgba + 4 * i;
        const float al = q[3] > 1 ? 1 : q[3] < 0 ? 0 : q[3];
        for (int c = 0; c < 3; c++) {
            const float v = al > 0 ? q[c] / al : 0;
            pn->rgba8[4 * i + c] = (unsigned char)(255 * powf(v > 1 ? 1 : v < 0 ? 0 : v, 1 / 2.2f) + 0.5f);
        }
        pn->rgba8[4 * i + 3] = (unsigned char)(255 * al + 0.5f);
    }
    if (!pn->tex)
        glGenTextures(1, &pn->tex);
    glBindTexture(GL_TEXTURE_2D, pn->tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, pn->rgba8);
    pn->tw = w, pn->th = h;
    return 0;
}

double vsv_panel_draw(vsv_panel *pn, const vsv_annot *a, const vsv_scene *sc, const char *lines, const double at[3],
                      const double right[3], const double down[3], double lh, const double P[16], const double MV[16],
                      const int vp[4])
{
    char err[256];
    double W, H;
    if (!(lh > 0) || vsv_panel_measure(pn, a, sc, lines, lh, &W, &H, err, sizeof err))
        return 0;
    double q[4][3]; /* top-left, top-right, bottom-right, bottom-left */
    for (int i = 0; i < 3; i++) {
        q[0][i] = at[i];
        q[1][i] = at[i] + W * right[i];
        q[2][i] = at[i] + W * right[i] + H * down[i];
        q[3][i] = at[i] + H * down[i];
    }
    /* the size of a line in this view: at the panel's centre, down its side */
    const double mid[3] = {0.5 * (q[0][0] + q[2][0]), 0.5 * (q[0][1] + q[2][1]), 0.5 * (q[0][2] + q[2][2])};
    const double below[3] = {mid[0] + lh * down[0], mid[1] + lh * down[1], mid[2] + lh * down[2]};
    double a2[2], b2[2];
    if (!project(P, MV, vp, mid, a2) || !project(P, MV, vp, below, b2))
        return 0;
    const double line_px = hypot(a2[0] - b2[0], a2[1] - b2[1]);
    const int seen = a2[0] >= vp[0] && a2[0] < vp[0] + vp[2] && a2[1] >= vp[1] && a2[1] < vp[1] + vp[3];
    int px = (int)lround(REF_PX * line_px / vsv_font_line(pn->ref));
    px = px < MIN_PX ? MIN_PX : px > MAX_PX ? MAX_PX : px;
    if (pn->px && abs(px - pn->px) <= 1) /* (the two eyes, a head moving: no flicker of sizes) */
        px = pn->px;
    const uint64_t key = content_key(a, sc, lines, px);
    if ((key != pn->key || !pn->tex) && !rasterise(pn, a, sc, lines, px))
        pn->key = key;
    if (!pn->tex)
        return 0;
    glBindTexture(GL_TEXTURE_2D, pn->tex);
    glEnable(GL_TEXTURE_2D);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glColor4f(1, 1, 1, 1);
    glBegin(GL_QUADS); /* texture row 0 is the top */
    glTexCoord2f(0, 0), glVertex3dv(q[0]);
    glTexCoord2f(1, 0), glVertex3dv(q[1]);
    glTexCoord2f(1, 1), glVertex3dv(q[2]);
    glTexCoord2f(0, 1), glVertex3dv(q[3]);
    glEnd();
    glDisable(GL_BLEND);
    glDisable(GL_TEXTURE_2D);
    return seen ? line_px / lh : 0;
}
