/* vsv_text.c — text drawn into a rendered frame: glyphs rasterised by
 * FreeType from a TrueType font (DejaVu Sans from fonts-dejavu-core unless
 * told otherwise) and blended into the premultiplied RGBA float image. */
#include "vsv_render.h"

#include <ft2build.h>
#include FT_FREETYPE_H
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define VSV_FONT_DEFAULT "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"

struct vsv_font {
    FT_Library lib;
    FT_Face face;
    int px, ascent, line;
};

int vsv_font_open(const char *path, int px, vsv_font **out, char *err, size_t cap)
{
    *out = NULL;
    if (px < 4 || px > 512) {
        snprintf(err, cap, "font size %d pixels: 4..512", px);
        return VSV_EINVAL;
    }
    if (!path || !*path)
        path = getenv("VSV_FONT");
    if (!path || !*path)
        path = VSV_FONT_DEFAULT;
    if (access(path, R_OK)) {
        snprintf(err, cap, "%s: no such font%s", path,
                 strcmp(path, VSV_FONT_DEFAULT) ? "" : " (apt-get install fonts-dejavu-core)");
        return VSV_ENOTFOUND;
    }
    vsv_font *f = calloc(1, sizeof *f);
    if (!f) {
        snprintf(err, cap, "out of memory");
        return VSV_ENOMEM;
    }
    FT_Error fe = FT_Init_FreeType(&f->lib);
    if (fe) {
        snprintf(err, cap, "FreeType does not start%s", fe == FT_Err_Out_Of_Memory ? ": out of memory" : "");
        free(f);
        return fe == FT_Err_Out_Of_Memory ? VSV_ENOMEM : VSV_EUNSUPPORTED;
    }
    if ((fe = FT_New_Face(f->lib, path, 0, &f->face)) || (fe = FT_Set_Pixel_Sizes(f->face, 0, (FT_UInt)px))) {
        if (fe == FT_Err_Out_Of_Memory)
            snprintf(err, cap, "%s: out of memory opening the font", path);
        else
            snprintf(err, cap, "%s: not a font FreeType reads at %d pixels", path, px);
        vsv_font_free(f);
        return fe == FT_Err_Out_Of_Memory ? VSV_ENOMEM : VSV_EINVAL;
    }
    f->px = px;
    f->ascent = (int)((f->face->size->metrics.ascender + 63) >> 6);
    f->line = (int)((f->face->size->metrics.height + 63) >> 6);
    *out = f;
    return 0;
}

void vsv_font_free(vsv_font *f)
{
    if (!f)
        return;
    if (f->face)
        FT_Done_Face(f->face);
    if (f->lib)
        FT_Done_FreeType(f->lib);
    free(f);
}

int vsv_font_line(const vsv_font *f) { return f->line; }

/* The next code point of UTF-8 text (a malformed byte stands for itself). */
static unsigned next_char(const char **s)
{
    const unsigned char *p = (const unsigned char *)*s;
    unsigned c = *p++;
    int more = c >= 0xf0 && c < 0xf8 ? 3 : c >= 0xe0 ? 2 : c >= 0xc0 ? 1 : 0;
    if (c >= 0xf8)
        more = 0;
    unsigned v = more == 3 ? c & 7 : more == 2 ? c & 15 : more == 1 ? c & 31 : c;
    for (int i = 0; i < more; i++) {
        if ((p[i] & 0xc0) != 0x80) { /* malformed: the lead byte alone */
            *s = (const char *)p;
            return c;
        }
        v = v << 6 | (p[i] & 63u);
    }
    *s = (const char *)(p + more);
    return v;
}

int vsv_text_width(vsv_font *f, const char *text)
{
    int x = 0;
    for (const char *s = text; *s;) {
        const unsigned c = next_char(&s);
        if (!FT_Load_Char(f->face, c, FT_LOAD_DEFAULT))
            x += (int)((f->face->glyph->advance.x + 32) >> 6);
    }
    return x;
}

void vsv_text_draw(vsv_font *f, float *rgba, int w, int h, int x, int y, const char *text, const float rgb[3],
                   float alpha)
{
    int pen = x;
    const int base = y + f->ascent;
    for (const char *s = text; *s;) {
        const unsigned c = next_char(&s);
        if (FT_Load_Char(f->face, c, FT_LOAD_RENDER))
            continue;
        const FT_GlyphSlot g = f->face->glyph;
        const FT_Bitmap *bm = &g->bitmap;
        for (unsigned r = 0; r < bm->rows; r++) {
            const int py = base - g->bitmap_top + (int)r;
            if (py < 0 || py >= h)
                continue;
            for (unsigned col = 0; col < bm->width; col++) {
                const int px = pen + g->bitmap_left + (int)col;
                if (px < 0 || px >= w)
                    continue;
                const float a = alpha * bm->buffer[(size_t)r * (size_t)bm->pitch + col] * (1.0f / 255);
                if (a <= 0)
                    continue;
                float *q = rgba + 4 * ((size_t)py * w + px);
                for (int i = 0; i < 3; i++)
                    q[i] = rgb[i] * a + q[i] * (1 - a);
                q[3] = a + q[3] * (1 - a);
            }
        }
        pen += (int)((g->advance.x + 32) >> 6);
    }
}
