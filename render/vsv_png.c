/* vsv_png.c — images for people: the float RGBA a renderer produces turned
 * into 8-bit RGB over a background, and PNG files written safely. */
#include "vsv_render.h"

#include <errno.h>
#include <math.h>
#include <png.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* The byte of a value v in [0, 1]: lrintf(255 v^(1/2.2)), sRGB-ish gamma. */
static unsigned char gamma_byte(float v) { return (unsigned char)lrintf(powf(v, 1 / 2.2f) * 255); }

/* gamma_byte without a powf a pixel: from[k], the smallest float giving byte
 * k (found once by bisection over the floats in [0, 1], which order as their
 * bit patterns); guess[c], the byte of the smallest value of cell c of 1024
 * equal cells. A value's byte: its cell's guess, moved up past every
 * from[] it reaches (a few steps in the darkest cells) — gamma_byte's exactly. */
static float from[257];
static unsigned char guess[1025];
static pthread_once_t gamma_once = PTHREAD_ONCE_INIT;

static void gamma_init(void)
{
    from[0] = 0;
    for (int k = 1; k <= 255; k++) {
        uint32_t lo = 0, hi = 0x3f800000u; /* bits of 0 and of 1: gamma_byte(1) = 255 >= k */
        while (lo < hi) {
            const uint32_t mid = lo + (hi - lo) / 2;
            float v;
            memcpy(&v, &mid, sizeof v);
            if (gamma_byte(v) >= k)
                hi = mid;
            else
                lo = mid + 1;
        }
        memcpy(&from[k], &lo, sizeof lo);
    }
    from[256] = INFINITY;
    for (int c = 0; c <= 1024; c++)
        guess[c] = gamma_byte(c / 1024.0f);
}

static inline unsigned char to_byte(float v)
{
    if (!(v > 0))
        return 0;
    if (v >= 1)
        return 255;
    unsigned k = guess[(int)(v * 1024)];
    while (v >= from[k + 1])
        k++;
    return (unsigned char)k;
}

void vsv_image_rgb8(const float *rgba, int w, int h, const float bg[3], unsigned char *rgb)
{
    pthread_once(&gamma_once, gamma_init);
    for (size_t i = 0; i < (size_t)w * h; i++) {
        const float *p = rgba + 4 * i;
        for (int c = 0; c < 3; c++) /* premultiplied over the background, then the gamma */
            rgb[3 * i + c] = to_byte(p[c] + (1 - p[3]) * bg[c]);
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
    return tall > 0 ? fmin(VSV_MAX_EXAGGERATION, fmax(1, round(0.2 * wide / tall))) : 1;
}
