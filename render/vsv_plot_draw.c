/* vsv_plot_draw.c — a plot drawn with cairo (vsv_render.h, "plots"): the
 * frame and its ticks, the axes' titles, the section's values as an image
 * in the colours of a colour map with its colour bar, the lines of a series
 * or profile with their legend, the title and subtitle. Text goes through
 * cairo (PNG, PDF) or, for SVG, into <text> elements (vsv_plot_out.c). */
#include "vsv_plot_draw.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------------- text */

static void font(plot_canvas *c, double size, int bold)
{
    cairo_select_font_face(c->cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL,
                           bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(c->cr, size);
}

double vsv_plot_text_width(plot_canvas *c, double size, int bold, const char *s)
{
    cairo_text_extents_t e;
    font(c, size, bold);
    cairo_text_extents(c->cr, s, &e);
    return e.x_advance;
}

/* XML's five escapes. */
static void xml_put(vsv_buf *b, const char *s, int *err)
{
    for (; *s && !*err; s++) {
        const char *e = *s == '&' ? "&amp;" : *s == '<' ? "&lt;" : *s == '>' ? "&gt;" : *s == '"' ? "&quot;" : NULL;
        *err |= e ? vsv_plot_put(b, e) : vsv_buf_put(b, s, 1);
    }
}

void vsv_plot_text(plot_canvas *c, const char *cls, double x, double y, double anchor, int rot, double size, int bold,
                   const char *s)
{
    const double w = vsv_plot_text_width(c, size, bold, s), edge = size * 0.15;
    if (!rot) /* inside the canvas: a label at an edge moves in */
        x += fmax(0, edge - (x - anchor * w)) - fmax(0, x + (1 - anchor) * w - (c->w - edge));
    if (c->svg) {
        char head[320];
        snprintf(head, sizeof head, "<text class=\"%s\" x=\"%.2f\" y=\"%.2f\" font-size=\"%.2f\"%s%s", cls, x, y, size,
                 anchor == 0.5 ? " text-anchor=\"middle\""
                 : anchor == 1 ? " text-anchor=\"end\""
                               : "",
                 bold ? " font-weight=\"bold\"" : "");
        c->err |= vsv_plot_put(c->svg, head);
        if (rot) {
            snprintf(head, sizeof head, " transform=\"rotate(-90 %.2f %.2f)\"", x, y);
            c->err |= vsv_plot_put(c->svg, head);
        }
        c->err |= vsv_plot_put(c->svg, ">");
        xml_put(c->svg, s, &c->err);
        c->err |= vsv_plot_put(c->svg, "</text>\n");
        return;
    }
    cairo_save(c->cr);
    cairo_set_source_rgb(c->cr, 0, 0, 0);
    cairo_translate(c->cr, x, y);
    if (rot)
        cairo_rotate(c->cr, -M_PI / 2);
    cairo_move_to(c->cr, -anchor * w, 0);
    cairo_show_text(c->cr, s);
    cairo_restore(c->cr);
}

/* ------------------------------------------------------------- axes */

double vsv_plot_map(const plot_axis *a, double v)
{
    const double f = a->log ? (log(v) - log(a->a)) / (log(a->b) - log(a->a)) : (v - a->a) / (a->b - a->a);
    return a->p0 + f * (a->p1 - a->p0);
}

/* The ticks of axis a, about target of them. */
static void axis_ticks(plot_axis *a, int target, int cal)
{
    if (a->time)
        vsv_plot_ticks_time(a->a, a->b, target, cal, &a->t, a->date);
    else if (a->log)
        vsv_plot_ticks_log(fmin(a->a, a->b), fmax(a->a, a->b), target, &a->t);
    else
        vsv_plot_ticks_linear(a->a, a->b, target, &a->t);
}

/* The plot's two axes (x along, y up), their ticks and the frame's margins. */
static void layout(const vsv_plot *p, plot_canvas *c, plot_axis *x, plot_axis *y)
{
    const double fs = c->fs, W = c->w, H = c->h;
    memset(x, 0, sizeof *x);
    memset(y, 0, sizeof *y);
    if (p->o.kind == VSV_PLOT_SECTION) {
        x->a = 0, x->b = p->length > 0 ? p->length : 1;
    } else if (p->o.kind == VSV_PLOT_SERIES) {
        x->time = 1;
        x->a = (double)p->rows[0].time, x->b = (double)p->rows[p->nrows - 1].time;
        if (!(x->b > x->a))
            x->a -= 1800, x->b += 1800;
    } else {
        x->a = p->vlo, x->b = p->vhi, x->log = p->o.log;
    }
    if (p->o.kind == VSV_PLOT_SERIES)
        y->a = p->vlo, y->b = p->vhi, y->log = p->o.log;
    else
        y->a = p->ybot * p->yscale, y->b = p->ytop * p->yscale;
    /* the margins: the y ticks' widest label and the axis title at the
       left, the title block on top, ticks, dates and the axis title below,
       the colour bar (a section) at the right */
    axis_ticks(y, (int)fmax(3, (H - 9 * fs) / (3.2 * fs)), p->cal);
    double wy = 0;
    for (int i = 0; i < y->t.n; i++)
        wy = fmax(wy, vsv_plot_text_width(c, fs, 0, y->t.text[i]));
    c->x0 = round(fs * 2.4 + wy + fs * 0.9);
    c->y0 = round(fs * 4.6);
    c->y1 = round(H - fs * (x->time ? 4.9 : 3.8));
    c->x1 = round(W - (p->o.kind == VSV_PLOT_SECTION ? vsv_plot_bar_width(p, c) : fs * 1.5));
    axis_ticks(x, (int)fmax(2, (c->x1 - c->x0) / (fs * (x->time ? 5.5 : 6.5))), p->cal);
    x->p0 = c->x0, x->p1 = c->x1;
    y->p0 = c->y1, y->p1 = c->y0;
}

/* The frame, its ticks and their labels, grid lines (lines: at every tick), the axes' titles. */
static void frame(const vsv_plot *p, plot_canvas *c, const plot_axis *x, const plot_axis *y)
{
    cairo_t *cr = c->cr;
    const double fs = c->fs, tick = fs * 0.45, grid = p->o.kind != VSV_PLOT_SECTION;
    cairo_set_line_width(cr, fmax(1, fs / 13));
    for (int i = 0; i < x->t.n; i++) {
        const double px = vsv_plot_map(x, x->t.v[i]);
        if (grid) {
            cairo_set_source_rgb(cr, 0.86, 0.86, 0.86);
            cairo_move_to(cr, px, c->y0);
            cairo_line_to(cr, px, c->y1);
            cairo_stroke(cr);
        }
        cairo_set_source_rgb(cr, 0, 0, 0);
        cairo_move_to(cr, px, c->y1);
        cairo_line_to(cr, px, c->y1 + tick);
        cairo_stroke(cr);
        vsv_plot_text(c, "xtick", px, c->y1 + tick + fs * 1.1, 0.5, 0, fs, 0, x->t.text[i]);
        if (x->time && x->date[i][0])
            vsv_plot_text(c, "xdate", px, c->y1 + tick + fs * 2.4, 0.5, 0, fs, 0, x->date[i]);
    }
    for (int i = 0; i < y->t.n; i++) {
        const double py = vsv_plot_map(y, y->t.v[i]);
        if (grid) {
            cairo_set_source_rgb(cr, 0.86, 0.86, 0.86);
            cairo_move_to(cr, c->x0, py);
            cairo_line_to(cr, c->x1, py);
            cairo_stroke(cr);
        }
        cairo_set_source_rgb(cr, 0, 0, 0);
        cairo_move_to(cr, c->x0, py);
        cairo_line_to(cr, c->x0 - tick, py);
        cairo_stroke(cr);
        vsv_plot_text(c, "ytick", c->x0 - tick - fs * 0.35, py + fs * 0.36, 1, 0, fs, 0, y->t.text[i]);
    }
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_rectangle(cr, c->x0, c->y0, c->x1 - c->x0, c->y1 - c->y0);
    cairo_stroke(cr);
    char xl[300];
    const char *yl = p->o.kind == VSV_PLOT_SERIES ? p->vaxis : p->yaxis;
    if (p->o.kind == VSV_PLOT_SECTION)
        snprintf(xl, sizeof xl, "distance (km)");
    else if (x->time)
        snprintf(xl, sizeof xl, "time (UTC%s%s)", p->cal ? ", " : "", p->cal ? vsv_calendar_name(p->cal) : "");
    else
        snprintf(xl, sizeof xl, "%s", p->vaxis);
    vsv_plot_text(c, "xlabel", 0.5 * (c->x0 + c->x1), c->h - fs * 0.8, 0.5, 0, fs * 1.1, 0, xl);
    vsv_plot_text(c, "ylabel", fs * 1.4, 0.5 * (c->y0 + c->y1), 0.5, 1, fs * 1.1, 0, yl);
}

/* The title (shrunk to fit the width) and the subtitle, over the frame. */
static void titles(const vsv_plot *p, plot_canvas *c)
{
    const double fs = c->fs, room = c->w - 2 * fs;
    double ts = fs * 1.35, ss = fs;
    const double tw = vsv_plot_text_width(c, ts, 1, p->title), sw = vsv_plot_text_width(c, ss, 0, p->subtitle);
    if (tw > room)
        ts *= room / tw;
    if (sw > room)
        ss *= room / sw;
    vsv_plot_text(c, "title", 0.5 * c->w, fs * 1.9, 0.5, 0, ts, 1, p->title);
    vsv_plot_text(c, "subtitle", 0.5 * c->w, fs * 3.4, 0.5, 0, ss, 0, p->subtitle);
}

/* --------------------------------------------------------- colours */

/* The 8-bit colour of value v in the plot's colour map over its range. */
static void colour(const vsv_plot *p, const vsv_tf *tf, double v, unsigned char rgb[3])
{
    double f = p->o.log ? (log(v) - log(p->lo)) / (log(p->hi) - log(p->lo)) : (v - p->lo) / (p->hi - p->lo);
    f = !(f > 0) ? 0 : f > 1 ? 1 : f; /* below the range (or 0 on a log scale): its first colour */
    const double x = f * (VSV_TF_LUT - 1);
    const int i = x >= VSV_TF_LUT - 1 ? VSV_TF_LUT - 2 : (int)x;
    for (int k = 0; k < 3; k++) {
        const double a = tf->lut[i][k], b = tf->lut[i + 1][k];
        rgb[k] = (unsigned char)lround(255 * fmin(1, fmax(0, a + (b - a) * (x - i))));
    }
}

int vsv_plot_tf(const vsv_plot *p, vsv_tf *tf)
{
    memset(tf, 0, sizeof *tf);
    snprintf(tf->colormap, sizeof tf->colormap, "%s", p->o.colormap[0] ? p->o.colormap : "viridis");
    tf->lo = 0, tf->hi = 1, tf->scale = VSV_SCALE_LINEAR; /* the table spans the map: colour() places values */
    tf->nopacity = 2;
    tf->opacity[0] = tf->opacity[1] = 1;
    return vsv_tf_prepare(tf);
}

/* Puts an RGB24 image of w x h pixels (rows of stride bytes) into the rectangle (x, y, rw, rh). */
static int put_image(plot_canvas *c, unsigned char *px, int w, int h, int stride, double x, double y, double rw,
                     double rh, int nearest)
{
    cairo_surface_t *img = cairo_image_surface_create_for_data(px, CAIRO_FORMAT_RGB24, w, h, stride);
    if (cairo_surface_status(img)) {
        cairo_surface_destroy(img);
        return VSV_ENOMEM;
    }
    cairo_save(c->cr);
    cairo_rectangle(c->cr, x, y, rw, rh);
    cairo_clip(c->cr);
    cairo_translate(c->cr, x, y);
    cairo_scale(c->cr, rw / w, rh / h);
    cairo_set_source_surface(c->cr, img, 0, 0);
    cairo_pattern_set_filter(cairo_get_source(c->cr), nearest ? CAIRO_FILTER_NEAREST : CAIRO_FILTER_BILINEAR);
    cairo_paint(c->cr);
    cairo_restore(c->cr);
    cairo_surface_destroy(img);
    return 0;
}

static void set_px(unsigned char *q, const unsigned char rgb[3])
{
    q[0] = rgb[2], q[1] = rgb[1], q[2] = rgb[0], q[3] = 255; /* CAIRO_FORMAT_RGB24: native-endian 0xXXRRGGBB */
}

/* The section's values as an image filling the frame: each pixel column
 * the sample nearest its distance, each pixel row that sample's level at
 * its height; the ground and no data grey, above the model's top white. */
static int section_image(const vsv_plot *p, plot_canvas *c, const vsv_tf *tf)
{
    const int w = (int)(c->x1 - c->x0), h = (int)(c->y1 - c->y0), nz = p->nz;
    const int stride = cairo_format_stride_for_width(CAIRO_FORMAT_RGB24, w);
    unsigned char *px = malloc((size_t)stride * h);
    if (!px)
        return VSV_ENOMEM;
    static const unsigned char grey[3] = {153, 153, 153}, white[3] = {255, 255, 255};
    int s = 0;
    for (int x = 0; x < w; x++) {
        const double d = p->length * (x + 0.5) / w;
        while (s + 1 < p->ns && fabs(p->rows[(size_t)(s + 1) * nz].dist - d) <= fabs(p->rows[(size_t)s * nz].dist - d))
            s++;
        const double *z = p->iface + (size_t)s * (nz + 1);
        int k = 0;
        for (int y = h - 1; y >= 0; y--) { /* bottom up: along the levels */
            const double yv = p->ytop + (p->ybot - p->ytop) * (y + 0.5) / h;
            unsigned char *q = px + (size_t)y * stride + 4 * (size_t)x, rgb[3];
            while (k < nz && (yv - z[k + 1]) * p->up >= 0)
                k++;
            const double v = k < nz ? p->rows[(size_t)s * nz + k].v[0] : NAN;
            if ((p->metres && yv < p->ground[s]) || (yv - z[0]) * p->up < 0 || (k < nz && isnan(v)))
                set_px(q, grey);
            else if (k >= nz)
                set_px(q, white);
            else
                colour(p, tf, v, rgb), set_px(q, rgb);
        }
    }
    const int rc = put_image(c, px, w, h, stride, c->x0, c->y0, w, h, 1);
    free(px);
    return rc;
}

double vsv_plot_bar_width(const vsv_plot *p, plot_canvas *c)
{
    double wl = 0;
    char lo[32], hi[32];
    vsv_plot_num3(p->lo, lo, sizeof lo);
    vsv_plot_num3(p->hi, hi, sizeof hi);
    wl = fmax(vsv_plot_text_width(c, c->fs, 0, lo), vsv_plot_text_width(c, c->fs, 0, hi));
    plot_ticks t;
    if (p->o.log)
        vsv_plot_ticks_log(p->lo, p->hi, 6, &t);
    else
        vsv_plot_ticks_linear(p->lo, p->hi, 6, &t);
    for (int i = 0; i < t.n; i++)
        wl = fmax(wl, vsv_plot_text_width(c, c->fs, 0, t.text[i]));
    return c->fs * (1.2 + 1.3 + 0.5 + 0.4) + wl + c->fs * 2.6;
}

/* The colour bar right of the frame: the map from lo (bottom) to hi, its
 * ends labelled with their values, ticks between, the species and units. */
static int colour_bar(const vsv_plot *p, plot_canvas *c, const vsv_tf *tf)
{
    const double fs = c->fs, bx = c->x1 + fs * 1.2, bw = fs * 1.3, y0 = c->y0, y1 = c->y1;
    enum { N = 256 };
    unsigned char px[N * 4];
    for (int i = 0; i < N; i++) {
        const double f = (N - 1 - i + 0.5) / N;
        const double v = p->o.log ? exp(log(p->lo) + f * (log(p->hi) - log(p->lo))) : p->lo + f * (p->hi - p->lo);
        unsigned char rgb[3];
        colour(p, tf, v, rgb);
        set_px(px + 4 * i, rgb);
    }
    int rc = put_image(c, px, 1, N, 4, bx, y0, bw, y1 - y0, 0);
    cairo_t *cr = c->cr;
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, fmax(1, fs / 13));
    cairo_rectangle(cr, bx, y0, bw, y1 - y0);
    cairo_stroke(cr);
    const plot_axis a = {.a = p->lo, .b = p->hi, .log = p->o.log, .p0 = y1, .p1 = y0};
    plot_ticks t;
    if (p->o.log)
        vsv_plot_ticks_log(p->lo, p->hi, (int)fmax(2, (y1 - y0) / (fs * 3.5)), &t);
    else
        vsv_plot_ticks_linear(p->lo, p->hi, (int)fmax(2, (y1 - y0) / (fs * 3.5)), &t);
    const double tx = bx + bw + fs * 0.4;
    /* the ends, then the ticks clear of them, in order of value */
    char end[2][32];
    vsv_plot_num3(p->lo, end[0], sizeof end[0]);
    vsv_plot_num3(p->hi, end[1], sizeof end[1]);
    for (int i = -1; i <= t.n; i++) {
        const double v = i < 0 ? p->lo : i == t.n ? p->hi : t.v[i], py = vsv_plot_map(&a, v);
        if (i >= 0 && i < t.n && (fabs(py - y0) < fs * 1.2 || fabs(py - y1) < fs * 1.2))
            continue;
        cairo_move_to(cr, bx + bw, py);
        cairo_line_to(cr, bx + bw + fs * 0.3, py);
        cairo_stroke(cr);
        vsv_plot_text(c, "cbar-tick", tx, py + fs * 0.36, 0, 0, fs, 0, i < 0 ? end[0] : i == t.n ? end[1] : t.text[i]);
    }
    vsv_plot_text(c, "cbar-label", c->w - fs * 0.7, 0.5 * (y0 + y1), 0.5, 1, fs * 1.1, 0, p->vaxis);
    return rc;
}

/* ------------------------------------------------------------ lines */

/* The colour of line l: tab10 (matplotlib's, from Tableau), or --colormap's colours spread. */
static void line_colour(const vsv_plot *p, const vsv_tf *tf, int l, double rgb[3])
{
    static const unsigned tab[] = {0x1f77b4, 0xff7f0e, 0x2ca02c, 0xd62728, 0x9467bd, 0x8c564b, 0xe377c2, 0x7f7f7f};
    if (p->o.colormap[0]) {
        const int i = (int)((l + 0.5) / p->o.nspecies * (VSV_TF_LUT - 1));
        for (int k = 0; k < 3; k++)
            rgb[k] = tf->lut[i][k];
        return;
    }
    for (int k = 0; k < 3; k++)
        rgb[k] = (tab[l % 8] >> (16 - 8 * k) & 0xff) / 255.0;
}

/* The series' or profile's lines, clipped to the frame: a line per
 * species through its points (a circle at each), broken where there is no
 * value (or none above 0 on a log scale). */
static void lines(const vsv_plot *p, plot_canvas *c, const plot_axis *x, const plot_axis *y, const vsv_tf *tf)
{
    cairo_t *cr = c->cr;
    const int series = p->o.kind == VSV_PLOT_SERIES;
    cairo_save(cr);
    cairo_rectangle(cr, c->x0, c->y0, c->x1 - c->x0, c->y1 - c->y0);
    cairo_clip(cr);
    if (!series && p->metres && p->ground && isfinite(p->ground[0]) && p->ground[0] > p->ybot) {
        const double g = vsv_plot_map(y, p->ground[0] * p->yscale); /* the ground under the column */
        cairo_set_source_rgb(cr, 0.6, 0.6, 0.6);
        cairo_rectangle(cr, c->x0, g, c->x1 - c->x0, c->y1 - g);
        cairo_fill(cr);
    }
    cairo_set_line_width(cr, fmax(1.2, c->fs / 7));
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    for (int l = 0; l < p->o.nspecies; l++) {
        double rgb[3];
        line_colour(p, tf, l, rgb);
        cairo_set_source_rgb(cr, rgb[0], rgb[1], rgb[2]);
        int on = 0;
        for (int r = 0; r < p->nrows; r++) {
            const double v = p->rows[r].v[l], h = p->rows[r].h * p->yscale;
            if (!isfinite(v) || (p->o.log && !(v > 0)) || (!series && !isfinite(h))) {
                on = 0;
                continue;
            }
            const double px = series ? vsv_plot_map(x, (double)p->rows[r].time) : vsv_plot_map(x, v);
            const double py = series ? vsv_plot_map(y, v) : vsv_plot_map(y, h);
            if (on)
                cairo_line_to(cr, px, py);
            else
                cairo_move_to(cr, px, py);
            on = 1;
        }
        cairo_stroke(cr);
        for (int r = 0; r < p->nrows; r++) {
            const double v = p->rows[r].v[l], h = p->rows[r].h * p->yscale;
            if (!isfinite(v) || (p->o.log && !(v > 0)) || (!series && !isfinite(h)))
                continue;
            const double px = series ? vsv_plot_map(x, (double)p->rows[r].time) : vsv_plot_map(x, v);
            const double py = series ? vsv_plot_map(y, v) : vsv_plot_map(y, h);
            cairo_new_sub_path(cr);
            cairo_arc(cr, px, py, c->fs * 0.22, 0, 2 * M_PI);
        }
        cairo_fill(cr);
    }
    cairo_restore(cr);
}

/* The legend at the frame's top right: a line sample and each species'
 * name (with its units where the species' differ). */
static void legend(const vsv_plot *p, plot_canvas *c, const vsv_tf *tf)
{
    cairo_t *cr = c->cr;
    const double fs = c->fs, lh = fs * 1.45, sample = fs * 2;
    char text[VSV_PLOT_MAXSPECIES][160];
    double tw = 0;
    for (int l = 0; l < p->o.nspecies; l++) {
        if (p->same_units || !p->units[l][0])
            snprintf(text[l], sizeof text[l], "%s", p->names[l]);
        else
            snprintf(text[l], sizeof text[l], "%s (%s)", p->names[l], p->units[l]);
        tw = fmax(tw, vsv_plot_text_width(c, fs, 0, text[l]));
    }
    const double bw = fs * 0.6 + sample + fs * 0.5 + tw + fs * 0.6, bh = lh * p->o.nspecies + fs * 0.5;
    const double bx = c->x1 - fs * 0.6 - bw, by = c->y0 + fs * 0.6;
    cairo_set_source_rgba(cr, 1, 1, 1, 0.85);
    cairo_rectangle(cr, bx, by, bw, bh);
    cairo_fill_preserve(cr);
    cairo_set_source_rgb(cr, 0.6, 0.6, 0.6);
    cairo_set_line_width(cr, fmax(1, fs / 13));
    cairo_stroke(cr);
    for (int l = 0; l < p->o.nspecies; l++) {
        const double ly = by + fs * 0.25 + lh * (l + 0.5);
        double rgb[3];
        line_colour(p, tf, l, rgb);
        cairo_set_source_rgb(cr, rgb[0], rgb[1], rgb[2]);
        cairo_set_line_width(cr, fmax(1.2, fs / 7));
        cairo_move_to(cr, bx + fs * 0.6, ly);
        cairo_line_to(cr, bx + fs * 0.6 + sample, ly);
        cairo_stroke(cr);
        cairo_arc(cr, bx + fs * 0.6 + sample / 2, ly, fs * 0.22, 0, 2 * M_PI);
        cairo_fill(cr);
        vsv_plot_text(c, "legend", bx + fs * 1.1 + sample, ly + fs * 0.36, 0, 0, fs, 0, text[l]);
    }
}

int vsv_plot_draw(const vsv_plot *p, plot_canvas *c)
{
    vsv_tf tf;
    if (vsv_plot_tf(p, &tf))
        return VSV_EINVAL;
    c->fs = fmin(40, fmax(9, round(13 * fmin(c->w / 800.0, c->h / 600.0))));
    cairo_set_source_rgb(c->cr, 1, 1, 1);
    cairo_paint(c->cr);
    plot_axis x, y;
    layout(p, c, &x, &y);
    int rc = 0;
    if (p->o.kind == VSV_PLOT_SECTION) {
        if (!(rc = section_image(p, c, &tf)))
            rc = colour_bar(p, c, &tf);
        frame(p, c, &x, &y);
    } else {
        frame(p, c, &x, &y);
        lines(p, c, &x, &y, &tf);
        legend(p, c, &tf);
    }
    titles(p, c);
    return rc ? rc : c->err ? VSV_ENOMEM : 0;
}
