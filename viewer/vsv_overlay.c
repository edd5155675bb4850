/* vsv_overlay.c — see vsv_overlay.h. Legacy OpenGL (1.1 + non-power-of-two
 * textures), which every Mesa driver and FreeVR's contexts provide. */
#include "vsv_overlay.h"

#include <fontconfig/fontconfig.h>
#include <ft2build.h>
#include FT_FREETYPE_H
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct vsv_overlay {
    FT_Library lib;
    FT_Face face;
    int px, ascent, line;
    unsigned char *buf; /* RGBA8 text image */
    size_t cap;
    GLuint tex;
};

vsv_overlay *vsv_overlay_create(int px, char *err, size_t cap)
{
    vsv_overlay *o = calloc(1, sizeof *o);
    if (!o) {
        snprintf(err, cap, "out of memory");
        return NULL;
    }
    o->px = px;
    char path[1024] = "";
    if (FcInit()) {
        FcPattern *pat = FcNameParse((const FcChar8 *)"monospace");
        FcConfigSubstitute(NULL, pat, FcMatchPattern);
        FcDefaultSubstitute(pat);
        FcResult res;
        FcPattern *match = FcFontMatch(NULL, pat, &res);
        FcChar8 *file = NULL;
        if (match && FcPatternGetString(match, FC_FILE, 0, &file) == FcResultMatch)
            snprintf(path, sizeof path, "%s", (const char *)file);
        if (match)
            FcPatternDestroy(match);
        FcPatternDestroy(pat);
    }
    if (!path[0] || FT_Init_FreeType(&o->lib) || FT_New_Face(o->lib, path, 0, &o->face) ||
        FT_Set_Pixel_Sizes(o->face, 0, (FT_UInt)px)) {
        snprintf(err, cap, "no usable monospace font%s%s (install fonts-dejavu-core)", path[0] ? ": " : "", path);
        vsv_overlay_free(o);
        return NULL;
    }
    o->ascent = (int)(o->face->size->metrics.ascender >> 6);
    o->line = (int)(o->face->size->metrics.height >> 6);
    return o;
}

void vsv_overlay_free(vsv_overlay *o)
{
    if (!o)
        return;
    if (o->face)
        FT_Done_Face(o->face);
    if (o->lib)
        FT_Done_FreeType(o->lib);
    free(o->buf);
    free(o);
}

/* Text extent in pixels. */
static void measure(vsv_overlay *o, const char *text, int *w, int *h)
{
    int x = 0, lines = 1;
    *w = 0;
    for (const char *c = text; *c; c++) {
        if (*c == '\n') {
            lines += c[1] != 0;
            x = 0;
            continue;
        }
        if (!FT_Load_Char(o->face, (unsigned char)*c, FT_LOAD_DEFAULT))
            x += (int)(o->face->glyph->advance.x >> 6);
        if (x > *w)
            *w = x;
    }
    *h = lines * o->line;
}

void vsv_overlay_text(vsv_overlay *o, int win_w, int win_h, int x0, int y0, const char *text)
{
    const int pad = 4;
    int tw, th;
    measure(o, text, &tw, &th);
    const int w = tw + 2 * pad, h = th + 2 * pad;
    if (y0 < 0) /* from the bottom */
        y0 = win_h + y0 - h;
    if ((size_t)w * h * 4 > o->cap) {
        unsigned char *nb = realloc(o->buf, (size_t)w * h * 4);
        if (!nb)
            return;
        o->buf = nb;
        o->cap = (size_t)w * h * 4;
    }
    for (size_t i = 0; i < (size_t)w * h; i++) { /* the box: dark, translucent */
        unsigned char *q = o->buf + 4 * i;
        q[0] = q[1] = q[2] = 0;
        q[3] = 150;
    }
    int pen_x = pad, base = pad + o->ascent;
    for (const char *c = text; *c; c++) {
        if (*c == '\n') {
            pen_x = pad;
            base += o->line;
            continue;
        }
        if (FT_Load_Char(o->face, (unsigned char)*c, FT_LOAD_RENDER))
            continue;
        const FT_GlyphSlot g = o->face->glyph;
        for (unsigned r = 0; r < g->bitmap.rows; r++)
            for (unsigned col = 0; col < g->bitmap.width; col++) {
                const int px = pen_x + g->bitmap_left + (int)col, py = base - g->bitmap_top + (int)r;
                if (px < 0 || py < 0 || px >= w || py >= h)
                    continue;
                const unsigned a = g->bitmap.buffer[r * (unsigned)g->bitmap.pitch + col];
                unsigned char *q = o->buf + 4 * ((size_t)py * w + px);
                /* white text over the box */
                q[0] = q[1] = q[2] = (unsigned char)(255 * a / 255);
                q[3] = (unsigned char)(150 + (255 - 150) * a / 255);
            }
        pen_x += (int)(g->advance.x >> 6);
    }
    if (!o->tex)
        glGenTextures(1, &o->tex);
    glBindTexture(GL_TEXTURE_2D, o->tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, o->buf);
    glMatrixMode(GL_PROJECTION);
    glPushMatrix();
    glLoadIdentity();
    glOrtho(0, win_w, win_h, 0, -1, 1);
    glMatrixMode(GL_MODELVIEW);
    glPushMatrix();
    glLoadIdentity();
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_TEXTURE_2D);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA); /* text pixels are premultiplied */
    glColor4f(1, 1, 1, 1);
    glBegin(GL_QUADS);
    glTexCoord2f(0, 0), glVertex2i(x0, y0);
    glTexCoord2f(1, 0), glVertex2i(x0 + w, y0);
    glTexCoord2f(1, 1), glVertex2i(x0 + w, y0 + h);
    glTexCoord2f(0, 1), glVertex2i(x0, y0 + h);
    glEnd();
    glDisable(GL_BLEND);
    glDisable(GL_TEXTURE_2D);
    glMatrixMode(GL_PROJECTION);
    glPopMatrix();
    glMatrixMode(GL_MODELVIEW);
    glPopMatrix();
}

double vsv_billboard_depth(const vsv_camera *cam, const double mn[3], const double mx[3])
{
    const double fl = sqrt(cam->dir[0] * cam->dir[0] + cam->dir[1] * cam->dir[1] + cam->dir[2] * cam->dir[2]);
    double d = 0;
    for (int i = 0; i < 3; i++)
        d += (0.5 * (mn[i] + mx[i]) - cam->pos[i]) * cam->dir[i] / (fl > 0 ? fl : 1);
    return d > 0 ? d : 1;
}

void vsv_billboard_upload(GLuint *tex, const unsigned char *rgb, int w, int h)
{
    if (!*tex)
        glGenTextures(1, tex);
    glBindTexture(GL_TEXTURE_2D, *tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB, w, h, 0, GL_RGB, GL_UNSIGNED_BYTE, rgb);
}

void vsv_billboard_quad(const vsv_camera *cam, double d, GLuint tex, int set_projection)
{
    /* the image's window at unit distance */
    double l, r, b, t;
    if (cam->window[0] != cam->window[1] && cam->window[2] != cam->window[3]) {
        l = cam->window[0], r = cam->window[1], b = cam->window[2], t = cam->window[3];
    } else {
        t = cam->fov_deg > 0 ? tan(cam->fov_deg * M_PI / 360) : 1;
        b = -t, r = t * cam->width / cam->height, l = -r;
    }
    if (set_projection) {
        const double n = d / 100;
        glMatrixMode(GL_PROJECTION);
        glLoadIdentity();
        glFrustum(l * n, r * n, b * n, t * n, n, d * 100);
    }
    /* the quad in eye space: facing the eye at that depth, filling the window */
    glMatrixMode(GL_MODELVIEW);
    glPushMatrix();
    glLoadIdentity();
    glBindTexture(GL_TEXTURE_2D, tex);
    glEnable(GL_TEXTURE_2D);
    glDisable(GL_DEPTH_TEST);
    glColor4f(1, 1, 1, 1);
    glBegin(GL_QUADS); /* image row 0 is the top */
    glTexCoord2f(0, 1), glVertex3d(l * d, b * d, -d);
    glTexCoord2f(1, 1), glVertex3d(r * d, b * d, -d);
    glTexCoord2f(1, 0), glVertex3d(r * d, t * d, -d);
    glTexCoord2f(0, 0), glVertex3d(l * d, t * d, -d);
    glEnd();
    glDisable(GL_TEXTURE_2D);
    glPopMatrix();
}

void vsv_billboard_draw(const vsv_camera *cam, double d, const unsigned char *rgb, int w, int h, int set_projection)
{
    static GLuint tex;
    vsv_billboard_upload(&tex, rgb, w, h);
    vsv_billboard_quad(cam, d, tex, set_projection);
}
