/* vsv_png.c — images for people: the float RGBA a renderer produces turned
 * into 8-bit RGB over a background, and PNG files written safely. */
#include "vsv_render.h"

#include <errno.h>
#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

void vsv_image_rgb8(const float *rgba, int w, int h, const float bg[3], unsigned char *rgb)
{
    for (size_t i = 0; i < (size_t)w * h; i++) {
        const float *p = rgba + 4 * i;
        for (int c = 0; c < 3; c++) {
            /* premultiplied over the background, then sRGB-ish gamma */
            float v = p[c] + (1 - p[3]) * bg[c];
            v = v <= 0 ? 0 : v >= 1 ? 1 : powf(v, 1 / 2.2f);
            rgb[3 * i + c] = (unsigned char)lrintf(v * 255);
        }
    }
}

/* libpng's complaints: kept for the message (its default handler prints
 * them), with errno at the time (a failed write's cause) */
typedef struct png_why {
    char msg[128];
    int err;
} png_why;

static void on_png_error(png_structp png, png_const_charp msg)
{
    png_why *w = png_get_error_ptr(png);
    w->err = errno;
    snprintf(w->msg, sizeof w->msg, "%s", msg);
    png_longjmp(png, 1);
}

static void on_png_warning(png_structp png, png_const_charp msg) { (void)png, (void)msg; }

int vsv_png_write(const char *path, const unsigned char *rgb, int w, int h, char *err, size_t cap)
{
    char tmp[4200];
    const int fd = vsv_output_temp(path, NULL, tmp, sizeof tmp);
    FILE *fp = fd >= 0 ? fdopen(fd, "wb") : NULL;
    if (!fp) {
        snprintf(err, cap, "%s: cannot create: %s", path, strerror(errno));
        if (fd >= 0)
            close(fd), vsv_output_discard(tmp);
        return -1;
    }
    png_why why = {"", 0};
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &why, on_png_error, on_png_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!png || !info || setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        const int wrote = ferror(fp); /* a failed write (a full disk), not the encoder */
        fclose(fp);
        vsv_output_discard(tmp);
        if (wrote)
            snprintf(err, cap, "%s: cannot write: %s", path, strerror(why.err ? why.err : EIO));
        else
            snprintf(err, cap, "%s: PNG encoding failed%s%s", path, why.msg[0] ? ": " : "",
                     why.msg[0] ? why.msg
                     : png      ? ""
                                : " (out of memory)");
        return -1;
    }
    png_init_io(png, fp);
    png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (int y = 0; y < h; y++)
        png_write_row(png, (png_const_bytep)(rgb + (size_t)y * w * 3));
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    /* a full disk or a failed write shows at the flush, fsync or close */
    const int bad = fflush(fp) || ferror(fp) || fsync(fileno(fp));
    const int e = errno;
    if (fclose(fp) || bad || vsv_output_publish(tmp, path)) {
        snprintf(err, cap, "%s: cannot write: %s", path, strerror(bad ? e : errno));
        vsv_output_discard(tmp);
        return -1;
    }
    return 0;
}

double vsv_scene_default_exaggeration(const vsv_scene *sc)
{
    vsv_scene s = *sc;
    double mn[3], mx[3];
    s.exaggeration = 1;
    vsv_scene_bounds(&s, mn, mx);
    const double wide = fmax(mx[0] - mn[0], mx[1] - mn[1]), tall = mx[2] - fmin(mn[2], 0);
    return tall > 0 ? fmax(1, round(0.2 * wide / tall)) : 1;
}
