/* vsv_plot_draw.h — drawing a plot with cairo, between vsv_plot_draw.c
 * (what is drawn) and vsv_plot_out.c (the surfaces and files). Private to
 * render/; the only header of the tree that sees cairo. */
#ifndef VSV_PLOT_DRAW_H
#define VSV_PLOT_DRAW_H

#include "vsv_common.h"
#include "vsv_plot_internal.h"

#include <cairo.h>

/* Where a plot is drawn: a cairo context w x h (pixels, or PDF points), and
 * for SVG the buffer that collects the texts as <text> elements (NULL:
 * cairo draws them). */
typedef struct plot_canvas {
    cairo_t *cr;
    vsv_buf *svg;
    double w, h, fs;       /* fs: the font size of tick labels */
    double x0, y0, x1, y1; /* the frame (whole pixels) */
    int err;               /* a text could not be kept (out of memory) */
} plot_canvas;

/* An axis: values a..b (log: on a log scale; time: seconds) at positions p0..p1, and its ticks. */
typedef struct plot_axis {
    double a, b, p0, p1;
    int log, time;
    plot_ticks t;
    char date[PLOT_MAXTICKS][32];
} plot_axis;

/* Appends text s (no terminator) to b: 0 or VSV_ENOMEM. */
static inline int vsv_plot_put(vsv_buf *b, const char *s) { return vsv_buf_put(b, s, strlen(s)); }

/* Draws p onto c (c->cr, w, h and svg set). 0, VSV_EINVAL or VSV_ENOMEM. */
int vsv_plot_draw(const vsv_plot *p, plot_canvas *c);
/* One line of text: baseline at (x, y), anchor 0 (start), 0.5 or 1 (end)
 * of its width there, turned a quarter left when rot; class cls in SVG. */
void vsv_plot_text(plot_canvas *c, const char *cls, double x, double y, double anchor, int rot, double size, int bold,
                   const char *s);
double vsv_plot_text_width(plot_canvas *c, double size, int bold, const char *s);
/* Position of value v along axis a. */
double vsv_plot_map(const plot_axis *a, double v);
/* The room right of the frame a section's colour bar takes, with its labels. */
double vsv_plot_bar_width(const vsv_plot *p, plot_canvas *c);
/* The table of the plot's colour map (its colours over 0..1). 0 or VSV_EINVAL. */
int vsv_plot_tf(const vsv_plot *p, vsv_tf *tf);

#endif
