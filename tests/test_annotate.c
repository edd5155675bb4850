/* test_annotate.c — what a frame says about itself: text drawn by FreeType
 * covers its box and nothing else. */
#include "vsv_format.h"
#include "vsv_render.h"
#include "vsv_testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void test_text(void)
{
    vsv_font *f = NULL;
    char err[256];
    const int rc = vsv_font_open(NULL, 16, &f, err, sizeof err);
    if (!CHECK(rc == 0, "a font opens (DejaVu Sans, fonts-dejavu-core)", "%s", err))
        return;
    enum { W = 240, H = 40 };
    float *img = calloc((size_t)W * H * 4, sizeof *img);
    const char *s = "Vesuvius 1995 \xc3\x97";
    const int tw = vsv_text_width(f, s), lh = vsv_font_line(f);
    CHECK(tw > 80 && tw < 200 && lh >= 16 && lh <= 24, "text has a plausible size", "width %d, line %d", tw, lh);
    CHECK(vsv_text_width(f, "WWWW") > vsv_text_width(f, "iiii"), "glyph widths differ (a proportional font)", "");
    const float white[3] = {1, 1, 1};
    vsv_text_draw(f, img, W, H, 10, 8, s, white, 1);
    int in = 0, out = 0, bad = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const float *q = img + 4 * ((size_t)y * W + x);
            if (q[3] <= 0)
                continue;
            bad += fabsf(q[0] - q[3]) > 1e-6f; /* white, premultiplied */
            if (x >= 10 && x < 10 + tw + 2 && y >= 8 && y < 8 + lh)
                in += q[3] > 0.5f;
            else
                out++;
        }
    CHECK(in > 150, "text pixels fill its box", "%d pixels over half covered", in);
    CHECK(out == 0, "no text pixels outside its box", "%d", out);
    CHECK(bad == 0, "text is premultiplied white", "%d pixels", bad);
    /* clipped at the edges, never written outside */
    vsv_text_draw(f, img, W, H, W - 5, H - 5, s, white, 1);
    vsv_text_draw(f, img, W, H, -50, -10, s, white, 1);
    CHECK(1, "text past the image's edges is clipped", "");
    free(img);
    vsv_font_free(f);
    CHECK(vsv_font_open("/nonexistent/font.ttf", 16, &f, err, sizeof err) == VSV_ENOTFOUND && !f &&
              strstr(err, "/nonexistent/font.ttf"),
          "a missing font is VSV_ENOTFOUND naming it", "%s", err);
}

int main(void)
{
    test_text();
    return vsv_test_done();
}
