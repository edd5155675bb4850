/* vsv_annotate.c — what a frame says about itself, drawn into it: the model
 * time and run (top left), a colour bar per visible species with its name,
 * units and range (bottom right), the vertical exaggeration and a scale bar
 * (bottom left; in a plan view, which has no exaggeration to state, at the
 * top of the bars' column), over the ground lines of vsv_mapdraw.c. A plan
 * view framed by vsv_annotate_insets keeps all of it off the map. */
#include "vsv_annot_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void vsv_annot_box(float *rgba, int w, int h, int x0, int y0, int x1, int y1, float alpha)
{
    x0 = x0 < 0 ? 0 : x0, y0 = y0 < 0 ? 0 : y0;
    x1 = x1 >= w ? w - 1 : x1, y1 = y1 >= h ? h - 1 : y1;
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++) {
            float *q = rgba + 4 * ((size_t)y * w + x);
            for (int i = 0; i < 3; i++)
                q[i] *= 1 - alpha;
            q[3] = alpha + q[3] * (1 - alpha);
        }
}

/* Where the legend goes: sizes from the font and the image. */
typedef struct layout {
    int lh, pad, margin;
    int bar_w, bar_h, block;
    int x0, x1; /* the bars' columns */
    int nvis;
    int plan; /* an orthographic map view: the scale in the bars' column */
    int top;  /* the height of the time block's band (0 without it) */
} layout;

static void placed(const vsv_annot *a, unsigned part, int x0, int y0, int x1, int y1)
{
    const int box[4] = {x0, y0, x1, y1};
    if (a->placed)
        a->placed(a->placed_ctx, part, box);
}

static int visible(const vsv_layer *l) { return l->visible && l->opacity > 0 && l->tf; }

/* Bar k (0..nlayers): layer k's when it is visible, the slices' for
 * k = nlayers when the scene has slices; its transfer function, or NULL. */
static const vsv_tf *bar_tf(const vsv_scene *sc, int k)
{
    if (k < sc->nlayers)
        return visible(&sc->layers[k]) ? sc->layers[k].tf : NULL;
    if (k == sc->nlayers && sc->nslices > 0 && sc->slice_layer >= 0 && sc->slice_layer < sc->nlayers)
        return sc->slice_tf ? sc->slice_tf : sc->layers[sc->slice_layer].tf;
    return NULL;
}

static void lay_out_size(const vsv_annot *a, const vsv_scene *sc, int w, int plan, layout *L)
{
    L->lh = a->font ? vsv_font_line(a->font) : 12;
    L->pad = L->lh / 4 + 2;
    L->margin = L->lh / 2 + 2;
    L->bar_w = w / 4 < 80 ? 80 : w / 4 > 360 ? 360 : w / 4;
    if (L->bar_w > w - 2 * (L->margin + L->pad))
        L->bar_w = w - 2 * (L->margin + L->pad);
    L->bar_h = L->lh * 7 / 10 > 6 ? L->lh * 7 / 10 : 6;
    L->block = (a->font ? 2 * L->lh : 0) + L->bar_h + 2 * L->pad;
    L->x1 = w - 1 - L->margin - L->pad;
    L->x0 = L->x1 - L->bar_w + 1;
    L->nvis = 0;
    for (int l = 0; l <= sc->nlayers; l++)
        L->nvis += bar_tf(sc, l) != NULL;
    L->nvis += sc->nisos > 0 && sc->isos ? sc->nisos : 0; /* an entry per isosurface, after the bars */
    L->plan = plan;
    L->top = (a->parts & VSV_ANNOT_TIME) && a->font ? L->margin + 2 * L->lh + 2 * L->pad : 0;
}

static void lay_out(const vsv_annot *a, const vsv_scene *sc, const vsv_camera *cam, layout *L)
{
    lay_out_size(a, sc, cam->width, cam->fov_deg <= 0 && cam->ortho_height > 0, L);
}

/* The scale block's lines (plan: no exaggeration, a plan view has none to
 * show) and its bar's length in pixels; 0 lines when it has none. */
static int scale_lines(const vsv_annot *a, const vsv_scene *sc, const vsv_camera *cam, const layout *L, char *ex,
                       char *km, size_t cap, double *len_px);

void vsv_annotate_insets(const vsv_annot *a, const vsv_scene *sc, int w, int h, int inset[4])
{
    (void)h;
    layout L;
    lay_out_size(a, sc, w, 1, &L);
    inset[0] = inset[1] = inset[2] = inset[3] = 0;
    if (L.top)
        inset[1] = L.top + L.margin;
    const int bars = (a->parts & VSV_ANNOT_COLOURBAR) && L.nvis > 0 && L.bar_w >= 8;
    if (bars || (a->parts & VSV_ANNOT_SCALEBAR))
        inset[2] = L.bar_w + 2 * L.pad + 2 * L.margin;
}

/* The bar of the k-th visible layer: its top row. */
static int bar_top(const vsv_annot *a, const layout *L, int h, int k)
{
    const int block_top = h - L->margin - (L->nvis - k) * (L->block + L->pad);
    return block_top + L->pad + (a->font ? L->lh : 0);
}

int vsv_annotate_bar_box(const vsv_annot *a, const vsv_scene *sc, const vsv_camera *cam, int l, int box[4])
{
    if (!(a->parts & VSV_ANNOT_COLOURBAR) || l < 0 || l > sc->nlayers || !bar_tf(sc, l))
        return VSV_ERANGE;
    layout L;
    lay_out(a, sc, cam, &L);
    int k = 0;
    for (int i = 0; i < l; i++)
        k += bar_tf(sc, i) != NULL;
    const int top = bar_top(a, &L, cam->height, k);
    if (L.bar_w < 8 || top < 0)
        return VSV_ERANGE;
    box[0] = L.x0, box[1] = L.x1, box[2] = top, box[3] = top + L.bar_h - 1;
    return 0;
}

static void fmt_value(double v, char *buf, size_t cap)
{
    if (v == 0)
        snprintf(buf, cap, "0");
    else
        snprintf(buf, cap, "%.3g", v);
}

static void text(const vsv_annot *a, float *rgba, int w, int h, int x, int y, const char *s)
{
    static const float fg[3] = {0.95f, 0.95f, 0.95f};
    if (a->font)
        vsv_text_draw(a->font, rgba, w, h, x, y, s, fg, 1);
}

static int width(const vsv_annot *a, const char *s) { return a->font ? vsv_text_width(a->font, s) : 0; }

/* The name line of bar l (layer l, or the slices' for l = nlayers): the
 * variable, its units and scale, and its description where the line stays
 * within `room` pixels. */
static void bar_name(const vsv_annot *a, const vsv_scene *sc, int l, const vsv_tf *tf, int room, char *name, size_t cap)
{
    const vsv_meta *m = sc->meta;
    const int slices = l == sc->nlayers;
    const int s = a->species ? a->species[slices ? sc->slice_layer : l] : -1;
    const vsv_var *v = s >= 0 && s < m->nvars ? &m->vars[s] : NULL;
    char units[80] = "";
    if (v && v->units[0])
        snprintf(units, sizeof units, " (%s)", v->units);
    /* one form for every bar: the name, its units, its scale; a slices'
     * bar says where they are (a horizontal one's height, or a curtain) */
    char where[96] = "";
    if (slices) {
        int nz = 0, nc = 0;
        double z = 0;
        for (int i = 0; i < sc->nslices; i++) {
            if (sc->slices[i].kind == VSV_SLICE_Z)
                z = sc->slices[i].z, nz++;
            else
                nc++;
        }
        if (nz == 1 && !nc)
            snprintf(where, sizeof where, ", slice at %.0f m", z);
        else if (nc == 1 && !nz)
            snprintf(where, sizeof where, ", vertical slice");
        else
            snprintf(where, sizeof where, ", %d slices", sc->nslices);
    }
    snprintf(name, cap, "%s%s%s%s", v ? v->name : "?", units, tf->scale == VSV_SCALE_LOG ? ", log" : "", where);
    if (width(a, name) > room && slices) /* the short form where the long one does not fit */
        snprintf(name, cap, "%s%s%s", v ? v->name : "?", units, where);
}

/* A bar's colours in pixel rows top .. top + bar_h - 1, columns x0 .. x1:
 * column c at value lo + (c + 0.5) / n (hi - lo), or geometrically on a
 * log scale. */
static void bar_fill(const vsv_tf *tf, int x0, int x1, int top, int bar_h, float *rgba, int w, int h)
{
    const int n = x1 - x0 + 1;
    for (int c = 0; c < n; c++) {
        const double f = (c + 0.5) / n;
        const double val = tf->scale == VSV_SCALE_LOG && tf->lo > 0 ? tf->lo * pow(tf->hi / tf->lo, f)
                                                                    : tf->lo + f * (tf->hi - tf->lo);
        float col[4];
        vsv_tf_eval(tf, (float)val, col);
        for (int y = top; y < top + bar_h; y++) {
            if (y < 0 || y >= h || x0 + c < 0 || x0 + c >= w)
                continue;
            float *q = rgba + 4 * ((size_t)y * w + x0 + c);
            q[0] = col[0], q[1] = col[1], q[2] = col[2], q[3] = 1;
        }
    }
}

static void iso_entries(const vsv_annot *a, const vsv_scene *sc, const layout *L, int k, float *rgba, int w, int h);
static void iso_entry(const vsv_annot *a, const vsv_scene *sc, int q, char *name, size_t cap, float rgb[3]);

static void colour_bars(const vsv_annot *a, const vsv_scene *sc, const vsv_camera *cam, const layout *L, float *rgba)
{
    const int w = cam->width, h = cam->height;
    for (int l = 0, k = 0; l <= sc->nlayers; l++) {
        const vsv_tf *tf = bar_tf(sc, l);
        if (!tf)
            continue;
        const int top = bar_top(a, L, h, k++);
        if (L->bar_w < 8 || top - (a->font ? L->lh : 0) - L->pad < 0)
            continue;
        char name[512];
        bar_name(a, sc, l, tf, L->bar_w + 4 * L->lh, name, sizeof name);
        const int nw = width(a, name);
        const int bx0 = (L->x1 + 1 - nw < L->x0 ? L->x1 + 1 - nw : L->x0) - L->pad;
        vsv_annot_box(rgba, w, h, bx0, top - (a->font ? L->lh : 0) - L->pad, L->x1 + L->pad,
                      top + L->bar_h - 1 + (a->font ? L->lh : 0) + L->pad, 0.55f);
        placed(a, VSV_ANNOT_COLOURBAR, bx0, top - (a->font ? L->lh : 0) - L->pad, L->x1 + L->pad,
               top + L->bar_h - 1 + (a->font ? L->lh : 0) + L->pad);
        text(a, rgba, w, h, L->x1 + 1 - nw, top - L->lh, name);
        bar_fill(tf, L->x0, L->x1, top, L->bar_h, rgba, w, h);
        char lo[32], hi[32];
        fmt_value(tf->lo, lo, sizeof lo);
        fmt_value(tf->hi, hi, sizeof hi);
        text(a, rgba, w, h, L->x0, top + L->bar_h + 1, lo);
        text(a, rgba, w, h, L->x1 + 1 - width(a, hi), top + L->bar_h + 1, hi);
    }
    int k = 0;
    for (int l = 0; l <= sc->nlayers; l++)
        k += bar_tf(sc, l) != NULL;
    iso_entries(a, sc, L, k, rgba, w, h);
}

/* Isosurface q's entry: its name line ("CLW = 5e-05 (kg/kg), isosurface")
 * and its colour as the image holds it (linear: the colour given is
 * gamma-encoded). */
static void iso_entry(const vsv_annot *a, const vsv_scene *sc, int q, char *name, size_t cap, float rgb[3])
{
    const vsv_scene_iso *I = &sc->isos[q];
    const int s = a->species && I->layer >= 0 && I->layer < sc->nlayers ? a->species[I->layer] : -1;
    const vsv_var *v = s >= 0 && s < sc->meta->nvars ? &sc->meta->vars[s] : NULL;
    char val[32];
    fmt_value(I->value, val, sizeof val);
    snprintf(name, cap, "%s = %s%s%s%s, isosurface", v ? v->name : "?", val, v && v->units[0] ? " (" : "",
             v ? v->units : "", v && v->units[0] ? ")" : "");
    for (int k = 0; k < 3; k++)
        rgb[k] = powf(fminf(fmaxf(I->rgb[k], 0), 1), 2.2f);
}

/* The isosurfaces' entries below the colour bars: bar k onwards, each a
 * name line over a swatch of its colour. */
static void iso_entries(const vsv_annot *a, const vsv_scene *sc, const layout *L, int k, float *rgba, int w, int h)
{
    for (int q = 0; q < sc->nisos && sc->isos; q++) {
        const int top = bar_top(a, L, h, k++);
        if (L->bar_w < 8 || top - (a->font ? L->lh : 0) - L->pad < 0)
            continue;
        char name[256];
        float rgb[3];
        iso_entry(a, sc, q, name, sizeof name, rgb);
        const int nw = width(a, name), bx0 = (L->x1 + 1 - nw < L->x0 ? L->x1 + 1 - nw : L->x0) - L->pad;
        const int y0 = top - (a->font ? L->lh : 0) - L->pad, y1 = top + L->bar_h - 1 + L->pad;
        vsv_annot_box(rgba, w, h, bx0, y0, L->x1 + L->pad, y1, 0.55f);
        placed(a, VSV_ANNOT_COLOURBAR, bx0, y0, L->x1 + L->pad, y1);
        text(a, rgba, w, h, L->x1 + 1 - nw, top - L->lh, name);
        for (int y = top < 0 ? 0 : top; y < top + L->bar_h && y < h; y++)
            for (int x = L->x0 < 0 ? 0 : L->x0; x <= L->x1 && x < w; x++) {
                float *px = rgba + 4 * ((size_t)y * w + x);
                px[0] = rgb[0], px[1] = rgb[1], px[2] = rgb[2], px[3] = 1;
            }
    }
}

void vsv_annot_time_line(const vsv_meta *m, int64_t t, char *buf, size_t cap)
{
    char iso[40];
    const int cal = vsv_meta_calendar(m);
    vsv_cal_format(cal, t, iso, sizeof iso);
    snprintf(buf, cap, "%s", iso);
    int64_t first, every;
    if (vsv_meta_outputs(m, &first, &every) && t > first && (t - first) % every) {
        /* between two of the model's outputs: say which */
        const int64_t a = first + (t - first) / every * every, b = a + every;
        char ta[40], tb[40];
        vsv_cal_format(cal, a, ta, sizeof ta);
        vsv_cal_format(cal, b, tb, sizeof tb);
        const int same_day = !strncmp(ta, tb, 10) && !strncmp(ta, iso, 10);
        const size_t n = strlen(buf);
        snprintf(buf + n, cap - n, "   interpolated between %.*s and %.*s", same_day ? 5 : 16, ta + (same_day ? 11 : 0),
                 same_day ? 5 : 16, tb + (same_day ? 11 : 0));
    }
    const char *tz = vsv_meta_attr(m, "time zone");
    char *end = NULL;
    const long behind = tz ? strtol(tz, &end, 10) : 0;
    if (tz && end != tz && behind != 0 && behind >= -14 && behind <= 14) {
        char local[40];
        vsv_cal_format(cal, t - behind * 3600, local, sizeof local);
        local[16] = 0; /* YYYY-MM-DDTHH:MM */
        const size_t n = strlen(buf);
        snprintf(buf + n, cap - n, "   local %s UTC%+ld", local, -behind);
    }
}

/* The time line and the file, model and run under it. */
static void time_block(const vsv_annot *a, const vsv_scene *sc, const vsv_camera *cam, const layout *L, float *rgba)
{
    const vsv_meta *m = sc->meta;
    char line1[160], line2[512];
    vsv_annot_time_line(m, a->time, line1, sizeof line1);
    snprintf(line2, sizeof line2, "%s%s%s%s%s", a->source ? a->source : "",
             a->source && (m->model[0] || m->run[0]) ? " \xc2\xb7 " : "", m->model,
             m->model[0] && m->run[0] ? ": " : "", m->run);
    /* no wider than the image */
    const int w = cam->width, h = cam->height, room = w - 2 * (L->margin + L->pad);
    if (width(a, line2) > room) { /* cut to whole characters, with an ellipsis */
        char full[512];
        snprintf(full, sizeof full, "%s", line2);
        for (size_t len = strlen(full); len > 0 && width(a, line2) > room; len--) {
            if ((full[len] & 0xc0) == 0x80)
                continue;
            snprintf(line2, sizeof line2, "%.*s\xe2\x80\xa6", (int)len, full);
        }
    }
    const int tw = width(a, line1) > width(a, line2) ? width(a, line1) : width(a, line2);
    vsv_annot_box(rgba, w, h, L->margin, L->margin, L->margin + tw + 2 * L->pad - 1,
                  L->margin + 2 * L->lh + 2 * L->pad - 1, 0.55f);
    placed(a, VSV_ANNOT_TIME, L->margin, L->margin, L->margin + tw + 2 * L->pad - 1,
           L->margin + 2 * L->lh + 2 * L->pad - 1);
    text(a, rgba, w, h, L->margin + L->pad, L->margin + L->pad, line1);
    text(a, rgba, w, h, L->margin + L->pad, L->margin + L->pad + L->lh, line2);
}

/* The ground's scale at the image's centre: metres per pixel along the
 * screen's horizontal, from where the centre's ray meets sea level; 0 when
 * it does not. */
static double metres_per_pixel(const vsv_camera *cam)
{
    vsv_rays R;
    vsv_rays_init(&R, cam);
    double o[3], d[3];
    vsv_rays_get(&R, cam->width / 2, cam->height / 2, o, d);
    if (!(d[2] < -1e-6))
        return 0;
    const double t = -o[2] / d[2];
    const double p[3] = {o[0] + t * d[0], o[1] + t * d[1], 0};
    double hx[3] = {R.r[0], R.r[1], 0};
    vsv_normalize(hx);
    const double L = 1000;
    const double q[3] = {p[0] + L * hx[0], p[1] + L * hx[1], 0};
    double x0, y0, x1, y1, t0, t1;
    if (!vsv_rays_project(&R, p, &x0, &y0, &t0) || !vsv_rays_project(&R, q, &x1, &y1, &t1))
        return 0;
    const double px = hypot(x1 - x0, y1 - y0);
    return px > 0 ? L / px : 0;
}

static int scale_lines(const vsv_annot *a, const vsv_scene *sc, const vsv_camera *cam, const layout *L, char *ex,
                       char *km, size_t cap, double *len_px)
{
    ex[0] = km[0] = 0;
    *len_px = 0;
    if ((a->parts & VSV_ANNOT_EXAGGERATION) && !L->plan) {
        const double e = sc->exaggeration > 0 ? sc->exaggeration : 1;
        snprintf(ex, cap, e >= 100 ? "vertical \xc3\x97%.0f" : "vertical \xc3\x97%.3g", e);
    }
    if (a->parts & VSV_ANNOT_SCALEBAR) {
        const double mpp = metres_per_pixel(cam);
        /* a round length near a sixth of the image's width (in a plan
         * view, at most the bars' column); none where that has no room (a
         * plan view a few pixels wide: its bars' column is negative, and
         * log10 of it made the bar's length NaN, found by fuzz_argv) */
        const double want = mpp * (L->plan ? fmin(cam->width / 6.0, L->bar_w) : cam->width / 6.0);
        if (mpp > 0 && want > 0 && isfinite(want)) {
            const double p10 = pow(10, floor(log10(want)));
            const double len = want >= 5 * p10 ? 5 * p10 : want >= 2 * p10 ? 2 * p10 : p10;
            *len_px = len / mpp;
            if (len >= 1000)
                snprintf(km, cap, "%g km%s", len / 1000, cam->fov_deg > 0 ? " (at centre)" : "");
            else
                snprintf(km, cap, "%g m%s", len, cam->fov_deg > 0 ? " (at centre)" : "");
        }
    }
    return (ex[0] != 0) + (km[0] ? 2 : 0);
}

static void scale_block(const vsv_annot *a, const vsv_scene *sc, const vsv_camera *cam, const layout *L, float *rgba)
{
    const int w = cam->width, h = cam->height;
    char ex[64], km[64];
    double len_px;
    const int lines = scale_lines(a, sc, cam, L, ex, km, sizeof ex, &len_px);
    if (!lines)
        return;
    int bw = width(a, ex) > width(a, km) ? width(a, ex) : width(a, km);
    if ((int)len_px > bw)
        bw = (int)len_px;
    int x0, y0, y1;
    if (L->plan) { /* the top of the bars' column, under the time block's band */
        x0 = L->x1 + L->pad - bw - 2 * L->pad;
        y0 = (L->top ? L->top + L->margin : L->margin);
        y1 = y0 + lines * L->lh + 2 * L->pad - 1;
    } else {
        y1 = h - 1 - L->margin, y0 = y1 - lines * L->lh - 2 * L->pad + 1;
        x0 = L->margin;
    }
    if (y0 < 0 || y1 >= h || x0 < 0)
        return;
    vsv_annot_box(rgba, w, h, x0, y0, x0 + bw + 2 * L->pad, y1, 0.55f);
    placed(a, a->parts & VSV_ANNOT_SCALEBAR ? VSV_ANNOT_SCALEBAR : VSV_ANNOT_EXAGGERATION, x0, y0, x0 + bw + 2 * L->pad,
           y1);
    int y = y0 + L->pad;
    if (ex[0]) {
        text(a, rgba, w, h, x0 + L->pad, y, ex);
        y += L->lh;
    }
    if (km[0]) {
        text(a, rgba, w, h, x0 + L->pad, y, km);
        y += L->lh;
        /* the bar: a white line with end ticks, half a line high */
        const int by = y + L->lh / 2, bx0 = x0 + L->pad, bx1 = bx0 + (int)lround(len_px);
        for (int yy = by - L->lh / 4; yy <= by + 1; yy++)
            for (int xx = bx0; xx <= bx1; xx++) {
                if (xx >= w || yy < 0 || yy >= h)
                    continue;
                const int on = yy >= by || xx <= bx0 + 1 || xx >= bx1 - 1;
                if (!on)
                    continue;
                float *q = rgba + 4 * ((size_t)yy * w + xx);
                q[0] = q[1] = q[2] = 0.95f;
                q[3] = 1;
            }
    }
}

int vsv_annotate(const vsv_annot *a, const vsv_scene *sc, const vsv_camera *cam, float *rgba, const float *depth)
{
    /* the legend first, as a layer of its own, so the ground's labels keep
     * out of it; then laid over the frame (the same pixels as drawing it
     * there: "over" is associative) */
    const size_t n = (size_t)cam->width * cam->height;
    float *legend = calloc(4 * n, sizeof *legend);
    if (!legend)
        return VSV_ENOMEM;
    layout L;
    lay_out(a, sc, cam, &L);
    if (a->parts & VSV_ANNOT_COLOURBAR)
        colour_bars(a, sc, cam, &L, legend);
    if ((a->parts & VSV_ANNOT_TIME) && a->font)
        time_block(a, sc, cam, &L, legend);
    if (a->parts & (VSV_ANNOT_EXAGGERATION | VSV_ANNOT_SCALEBAR))
        scale_block(a, sc, cam, &L, legend);
    const int rc = vsv_annot_ground(a, sc, cam, rgba, depth, legend, NULL);
    for (size_t p = 0; !rc && p < n; p++) {
        const float *o = legend + 4 * p;
        if (o[3] <= 0)
            continue;
        float *q = rgba + 4 * p;
        for (int i = 0; i < 4; i++)
            q[i] = o[i] + q[i] * (1 - o[3]);
    }
    free(legend);
    return rc;
}

/* ------------------------------------------------------------- the legend */

/* The legend, drawn (rgba non-NULL) or measured: the time line, the
 * caller's lines, then per bar its name with its range at the right of the
 * same line ("lo to hi") and the bar under them, as wide as the panel. */
static void legend(const vsv_annot *a, const vsv_scene *sc, const char *lines, float *rgba, int w, int h, int *need_w,
                   int *need_h)
{
    const int lh = a->font ? vsv_font_line(a->font) : 12, pad = lh / 4 + 2;
    const int bar_h = lh * 6 / 10 > 4 ? lh * 6 / 10 : 4;
    int y = pad, wide = 10 * lh; /* bars at least ten lines wide */
    char line[512];
    vsv_annot_time_line(sc->meta, a->time, line, sizeof line);
    if (rgba)
        text(a, rgba, w, h, pad, y, line);
    wide = width(a, line) > wide ? width(a, line) : wide;
    y += lh;
    for (const char *p = lines ? lines : ""; *p;) { /* the caller's lines */
        const size_t n = strcspn(p, "\n");
        snprintf(line, sizeof line, "%.*s", (int)(n < sizeof line ? n : sizeof line - 1), p);
        if (rgba)
            text(a, rgba, w, h, pad, y, line);
        wide = width(a, line) > wide ? width(a, line) : wide;
        y += lh;
        p += n + (p[n] == '\n');
    }
    for (int l = 0; l <= sc->nlayers; l++) {
        const vsv_tf *tf = bar_tf(sc, l);
        if (!tf)
            continue;
        char lo[32], hi[32], range[80];
        fmt_value(tf->lo, lo, sizeof lo);
        fmt_value(tf->hi, hi, sizeof hi);
        snprintf(range, sizeof range, "%s to %s", lo, hi);
        const int rw = width(a, range), gap = lh;
        y += pad;
        /* measured without the description: drawn with it where it fits */
        bar_name(a, sc, l, tf, rgba ? w - 2 * pad - rw - gap : 0, line, sizeof line);
        if (!rgba) {
            wide = width(a, line) + gap + rw > wide ? width(a, line) + gap + rw : wide;
        } else {
            text(a, rgba, w, h, pad, y, line);
            text(a, rgba, w, h, w - pad - rw, y, range);
            bar_fill(tf, pad, w - 1 - pad, y + lh, bar_h, rgba, w, h);
        }
        y += lh + bar_h;
    }
    for (int q = 0; q < sc->nisos && sc->isos; q++) { /* the isosurfaces: a name over a swatch */
        float rgb[3];
        iso_entry(a, sc, q, line, sizeof line, rgb);
        y += pad;
        wide = width(a, line) > wide ? width(a, line) : wide;
        for (int yy = y + lh; rgba && yy < y + lh + bar_h && yy < h; yy++)
            for (int x = pad; x < w - pad; x++) {
                float *px = rgba + 4 * ((size_t)yy * w + x);
                px[0] = rgb[0], px[1] = rgb[1], px[2] = rgb[2], px[3] = 1;
            }
        if (rgba)
            text(a, rgba, w, h, pad, y, line);
        y += lh + bar_h;
    }
    if (need_w)
        *need_w = wide + 2 * pad;
    if (need_h)
        *need_h = y + pad;
}

void vsv_legend_size(const vsv_annot *a, const vsv_scene *sc, const char *lines, int *w, int *h)
{
    legend(a, sc, lines, NULL, 0, 0, w, h);
}

void vsv_legend_draw(const vsv_annot *a, const vsv_scene *sc, const char *lines, float *rgba, int w, int h)
{
    memset(rgba, 0, (size_t)w * h * 4 * sizeof *rgba);
    vsv_annot_box(rgba, w, h, 0, 0, w - 1, h - 1, 0.7f);
    legend(a, sc, lines, rgba, w, h, NULL, NULL);
}
