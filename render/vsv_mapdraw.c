/* vsv_mapdraw.c — lines on the ground of a rendered frame: the
 * latitude/longitude graticule (labelled) and the coast, lake and border
 * outlines. Each line's part inside the grid and the view is followed in
 * steps of half a cell (no shorter than a pixel), set on the terrain (the
 * same bilinear surface the renderers draw), and projected with the frame's
 * camera; the frame's depth image hides it where the ground in front is
 * nearer, and dims it where a cloud is. */
#include "vsv_annot_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int vsv_rays_project(const vsv_rays *R, const double p[3], double *px, double *py, double *t)
{
    double v[3], z = 0, s[2] = {0, 0}, len = 0;
    for (int i = 0; i < 3; i++) {
        v[i] = p[i] - R->o[i];
        z += v[i] * R->f[i];
        s[0] += v[i] * R->r[i];
        s[1] += v[i] * R->u[i];
        len += v[i] * v[i];
    }
    if (!(z > 0))
        return 0;
    if (R->persp) {
        s[0] /= z, s[1] /= z;
        *t = sqrt(len);
    } else {
        *t = z;
    }
    /* the inverse of vsv_rays_get */
    *px = ((s[0] - R->cx) / R->kx + 1) * R->w / 2;
    *py = (1 - (s[1] - R->cy) / R->ky) * R->h / 2;
    return 1;
}

/* One frame's drawing state. */
typedef struct pen {
    const vsv_geo *g;
    vsv_rays R;
    const float *depth;
    float *mask; /* coverage of the current kind of line, w*h */
    int w, h;
    double step;      /* world metres between samples along a line */
    double pix_angle; /* world size of a pixel per metre of distance (perspective) */
    double pix_ortho; /* world size of a pixel (orthographic) */
    double slope;     /* 1 / sine of the view's elevation, at most 10 */
    double half;      /* line half-width, pixels */
    double zlo, zhi;  /* the lowest and the highest ground (exaggerated) */
    int seg_cap;      /* the most samples along one segment, and brush steps between two */
    int64_t work;     /* samples set on the terrain and brush steps so far */
    int64_t budget;   /* the most work the frame's lines may take */
    /* the label anchor of the current line: its visible point furthest
     * down (meridians) or left (parallels) on the screen */
    int want; /* 0 none, 1 lowest, 2 leftmost */
    double ax, ay, akey;
} pen;

static double ground_z(const vsv_geo *g, double x, double y) { return g->terrain ? vsv_geo_terrain(g, x, y) : 0; }

/* How much of a line point at distance t is seen at pixel p: 1, 0 behind
 * the ground, 0.3 behind a cloud. */
static float seen(const pen *P, size_t p, double t)
{
    if (!P->depth)
        return 1;
    const double d = P->depth[p];
    const double foot = (P->R.persp ? t * P->pix_angle : P->pix_ortho) * P->slope;
    if (!(d < t - 3 * foot))
        return 1;
    /* something in front: the ground (the depth's point on the terrain) or a cloud */
    double o[3], dir[3];
    vsv_rays_get(&P->R, (int)(p % (size_t)P->w), (int)(p / (size_t)P->w), o, dir);
    const double q[3] = {o[0] + d * dir[0], o[1] + d * dir[1], o[2] + d * dir[2]};
    /* a ground hit lies on the surface up to the depth's float rounding */
    return q[2] <= ground_z(P->g, q[0], q[1]) + 1e-5 * d + 2 * P->g->E ? 0.0f : 0.3f;
}

/* A round brush of the pen's width at screen (sx, sy), distance t. */
static void splat(pen *P, double sx, double sy, double t)
{
    const double r = P->half + 0.5;
    P->work++;
    const int x0 = (int)floor(sx - r), x1 = (int)floor(sx + r), y0 = (int)floor(sy - r), y1 = (int)floor(sy + r);
    float vis_centre = -1;
    for (int y = y0 > 0 ? y0 : 0; y <= y1 && y < P->h; y++)
        for (int x = x0 > 0 ? x0 : 0; x <= x1 && x < P->w; x++) {
            const double ddx = x + 0.5 - sx, ddy = y + 0.5 - sy;
            const double cov = fmin(1, P->half + 0.5 - sqrt(ddx * ddx + ddy * ddy));
            if (cov <= 0)
                continue;
            const size_t p = (size_t)y * P->w + x;
            const float sn = seen(P, p, t), v = (float)cov * sn;
            if (v > P->mask[p])
                P->mask[p] = v;
            if (x == (int)floor(sx) && y == (int)floor(sy))
                vis_centre = sn;
        }
    if (P->want && vis_centre > 0) { /* in the open or behind a cloud, not the ground */
        const double key = P->want == 1 ? sy : -sx;
        if (key > P->akey)
            P->akey = key, P->ax = sx, P->ay = sy;
    }
}

/* Narrows [*f0, *f1] along segment c0-c1 (world x, y) to the part whose
 * column of ground heights (P->zlo to P->zhi) may show on the image, with
 * the brush's margin; 0 when none. The eye's plane and each side of the
 * view bound a half-space whose value is linear along the segment and in
 * height (the same height is the best at both ends), so the part is one
 * interval: a frame pays only for the lines it shows. */
static int view_clip(const pen *P, const double c0[2], const double c1[2], double *f0, double *f1)
{
    const vsv_rays *R = &P->R;
    const double mx = R->kx * (1 + 2 * (P->half + 2) / R->w), my = R->ky * (1 + 2 * (P->half + 2) / R->h);
    /* inside where a s + b u + c f + d >= 0, (s, u, f) the point along the camera's r, u, f */
    const double k = R->persp ? 1 : 0;
    const double pl[5][4] = {{0, 0, 1, 0},
                             {1, 0, -(R->cx - mx) * k, -(R->cx - mx) * (1 - k)},
                             {-1, 0, (R->cx + mx) * k, (R->cx + mx) * (1 - k)},
                             {0, 1, -(R->cy - my) * k, -(R->cy - my) * (1 - k)},
                             {0, -1, (R->cy + my) * k, (R->cy + my) * (1 - k)}};
    double lo = *f0, hi = *f1;
    for (int i = 0; i < 5; i++) {
        double v[2] = {-INFINITY, -INFINITY}; /* at each end, at its best height */
        for (int e = 0; e < 2; e++)
            for (int z = 0; z < 2; z++) {
                const double p[3] = {(e ? c1 : c0)[0], (e ? c1 : c0)[1], z ? P->zhi : P->zlo};
                double s = 0, u = 0, f = 0;
                for (int a = 0; a < 3; a++) {
                    const double d = p[a] - R->o[a];
                    s += d * R->r[a], u += d * R->u[a], f += d * R->f[a];
                }
                v[e] = fmax(v[e], pl[i][0] * s + pl[i][1] * u + pl[i][2] * f + pl[i][3]);
            }
        if (!(v[0] >= 0 || v[1] >= 0)) /* both outside (or not numbers) */
            return 0;
        if (v[0] < 0)
            lo = fmax(lo, v[0] / (v[0] - v[1]));
        else if (v[1] < 0)
            hi = fmin(hi, v[0] / (v[0] - v[1]));
        if (!(lo <= hi))
            return 0;
    }
    *f0 = lo, *f1 = hi;
    return 1;
}

/* How many steps segment c0-c1 (world x, y, inside the grid) is followed
 * in: half a cell apart, so its points sit on the terrain's patches, but
 * never closer than a pixel's width at the segment's nearest to the eye,
 * nor more than P->seg_cap: its cost follows the image, not the grid's
 * spacing. */
static int steps(const pen *P, const double c0[2], const double c1[2])
{
    const double ex = c1[0] - c0[0], ey = c1[1] - c0[1], len = hypot(ex, ey);
    double foot = P->pix_ortho;
    if (P->R.persp) { /* the eye's distance to the segment, then to the ground's heights */
        const double *o = P->R.o, l2 = ex * ex + ey * ey;
        const double f = l2 > 0 ? fmin(1, fmax(0, ((o[0] - c0[0]) * ex + (o[1] - c0[1]) * ey) / l2)) : 0;
        const double dz = o[2] > P->zhi ? o[2] - P->zhi : o[2] < P->zlo ? P->zlo - o[2] : 0;
        foot = hypot(hypot(c0[0] + f * ex - o[0], c0[1] + f * ey - o[1]), dz) * P->pix_angle;
    }
    const double ns = ceil(len / fmax(P->step, foot));
    return ns >= 1 ? (ns < P->seg_cap ? (int)ns : P->seg_cap) : 1;
}

/* The brush from screen point (lx, ly) at distance lt to (sx, sy) at t, in
 * half-pixel steps over the part on the image (with the brush's margin);
 * the first point is already drawn. */
static void stroke(pen *P, double lx, double ly, double lt, double sx, double sy, double t)
{
    const double m0 = -P->half - 2, a[2] = {lx, ly}, b[2] = {sx, sy};
    const double mn[2] = {m0, m0}, mx[2] = {P->w - m0, P->h - m0};
    double g0, g1;
    if (!vsv_segment_clip(a, b, mn, mx, &g0, &g1))
        return;
    const double sl = (g1 - g0) * hypot(sx - lx, sy - ly); /* at most the image's diagonal */
    const int m = sl > 0.5 ? (int)fmin(ceil(sl / 0.5), P->seg_cap) : 1;
    for (int j = 1; j <= m; j++) {
        const double g = g0 + (g1 - g0) * j / m;
        splat(P, lx + g * (sx - lx), ly + g * (sy - ly), lt + g * (t - lt));
    }
}

/* Draws the polyline xy (n world points) into the mask: the parts of its
 * segments inside the grid and the view, each in steps(), while the
 * frame's work is under P->budget. */
static void polyline(pen *P, const double *xy, int n)
{
    const vsv_geo *g = P->g;
    int have = 0;
    double lx = 0, ly = 0, lt = 0;
    for (int i = 0; i + 1 < n && P->work < P->budget; i++) {
        const double *a = xy + 2 * i, *b = a + 2;
        double f0, f1;
        if (!vsv_segment_clip(a, b, g->bmin, g->bmax, &f0, &f1)) {
            have = 0;
            continue;
        }
        double c0[2], c1[2]; /* the part in the grid, held inside against rounding */
        for (int k = 0; k < 2; k++) {
            c0[k] = fmin(g->bmax[k], fmax(g->bmin[k], a[k] + f0 * (b[k] - a[k])));
            c1[k] = fmin(g->bmax[k], fmax(g->bmin[k], a[k] + f1 * (b[k] - a[k])));
        }
        double v0 = 0, v1 = 1;
        if (!view_clip(P, c0, c1, &v0, &v1)) {
            have = 0;
            continue;
        }
        if (f0 > 0 || v0 > 0)
            have = 0;
        double d0[2], d1[2];
        for (int k = 0; k < 2; k++)
            d0[k] = c0[k] + v0 * (c1[k] - c0[k]), d1[k] = c0[k] + v1 * (c1[k] - c0[k]);
        const int ns = steps(P, d0, d1);
        for (int k = have ? 1 : 0; k <= ns; k++) {
            const double f = (double)k / ns, x = d0[0] + f * (d1[0] - d0[0]), y = d0[1] + f * (d1[1] - d0[1]);
            const double p[3] = {x, y, ground_z(g, x, y)};
            double sx, sy, t;
            P->work++;
            if (!vsv_rays_project(&P->R, p, &sx, &sy, &t)) {
                have = 0;
                continue;
            }
            if (have)
                stroke(P, lx, ly, lt, sx, sy, t);
            else
                splat(P, sx, sy, t);
            have = 1, lx = sx, ly = sy, lt = t;
        }
        if (f1 < 1 || v1 < 1)
            have = 0;
    }
}

/* Blends the mask into the frame in colour rgb at opacity alpha, and clears it. */
static void ink(pen *P, float *rgba, const float rgb[3], float alpha)
{
    for (size_t p = 0; p < (size_t)P->w * P->h; p++) {
        const float a = P->mask[p] * alpha;
        if (a <= 0)
            continue;
        float *q = rgba + 4 * p;
        for (int i = 0; i < 3; i++)
            q[i] = rgb[i] * a + q[i] * (1 - a);
        q[3] = a + q[3] * (1 - a);
        P->mask[p] = 0;
    }
}

/* A degree label: "45°N", "120°W", "0°". */
static void degrees(double v, int lat, double step, char *buf, size_t cap)
{
    const double a = fabs(v);
    const char *hemi = v == 0 || (!lat && a == 180) ? "" : lat ? (v > 0 ? "N" : "S") : (v > 0 ? "E" : "W");
    if (step >= 1)
        snprintf(buf, cap, "%.0f°%s", a, hemi);
    else
        snprintf(buf, cap, "%.2f°%s", a, hemi);
}

/* Draws a label at its anchor unless it would fall under the legend or on
 * a label already drawn (boxes: n of them, grown by one); 1 when drawn. */
static int label(const vsv_annot *a, float *rgba, int w, int h, double x, double y, const char *text, int below,
                 const float *legend, int (*boxes)[4], int *n)
{
    if (!a->font)
        return 0;
    const int tw = vsv_text_width(a->font, text), lh = vsv_font_line(a->font);
    int tx = below ? (int)(x - tw / 2.0) : (int)x + 3, ty = below ? (int)y - lh - 2 : (int)(y - lh / 2.0);
    tx = tx < 2 ? 2 : tx + tw > w - 2 ? w - 2 - tw : tx;
    ty = ty < 2 ? 2 : ty + lh > h - 2 ? h - 2 - lh : ty;
    for (int yy = ty; legend && yy < ty + lh && yy < h; yy++) /* not under the legend */
        for (int xx = tx; xx < tx + tw && xx < w; xx++)
            if (yy >= 0 && xx >= 0 && legend[4 * ((size_t)yy * w + xx) + 3] > 0)
                return 0;
    const int box[4] = {tx, ty, tx + tw, ty + lh}; /* with its shadow */
    for (int i = 0; i < *n; i++)                   /* nor on another label, 2 pixels apart */
        if (box[0] <= boxes[i][2] + 2 && boxes[i][0] <= box[2] + 2 && box[1] <= boxes[i][3] + 2 &&
            boxes[i][1] <= box[3] + 2)
            return 0;
    memcpy(boxes[(*n)++], box, sizeof box);
    const float shadow[3] = {0, 0, 0}, fg[3] = {0.85f, 0.85f, 0.85f};
    vsv_text_draw(a->font, rgba, w, h, tx + 1, ty + 1, text, shadow, 0.8f);
    vsv_text_draw(a->font, rgba, w, h, tx, ty, text, fg, 1);
    if (a->placed)
        a->placed(a->placed_ctx, VSV_ANNOT_GRATICULE, box);
    return 1;
}

/* Latitude and longitude lines every `step` degrees over the grid. */
static int graticule(const vsv_annot *a, const vsv_scene *sc, pen *P, float *rgba, const float *legend)
{
    double box[4];
    const vsv_meta *m = sc->meta;
    if (m->proj.kind == VSV_PROJ_NONE || vsv_grid_latlon_box(m, box))
        return 0;
    /* the box without its margin of a degree */
    const double s = fmax(box[0] + 1, -90), n = fmin(box[1] - 1, 90), wl = box[2] + 1, el = box[3] - 1;
    const double span = fmax(n - s, (el - wl) * cos(0.5 * (s + n) * M_PI / 180));
    static const double steps[] = {0.1, 0.2, 0.25, 0.5, 1, 2, 5, 10, 15, 30, 45};
    double step = 45;
    for (size_t i = 0; i < sizeof steps / sizeof *steps; i++)
        if (span / steps[i] <= 7) {
            step = steps[i];
            break;
        }
    /* points along a line: a quarter of the step, and no coarser than half a cell */
    const double cell_deg = fmin(P->g->dx, P->g->dy) / 111195.0;
    const double inc = fmax(fmin(step / 4, cell_deg / 2), (fmax(n - s, el - wl) + 1) / 4000);
    const int npts = (int)ceil(fmax(n - s, el - wl) / inc) + 2;
    double *xy = malloc(2 * (size_t)npts * sizeof *xy);
    if (!xy)
        return VSV_ENOMEM;
    const double x0 = m->origin[0] - 0.5 * m->spacing[0];
    typedef struct lab {
        double x, y;
        char text[32];
        int below;
    } lab;
    lab labs[256];
    int nlab = 0;
    for (int kind = 0; kind < 2; kind++) { /* 0 parallels, 1 meridians */
        const double lo = kind ? wl : s, hi = kind ? el : n;
        for (double v = ceil(lo / step) * step; v <= hi + 1e-9; v += step) {
            if (!kind && fabs(v) >= 90)
                continue;
            if (kind && el - wl >= 359 && v >= wl + 360 - 1e-9)
                continue;
            const double a0 = kind ? s : wl, a1 = kind ? n : el;
            int k = 0;
            for (double u = a0; k < npts; u += inc) {
                const double uu = u > a1 ? a1 : u;
                const double lat = kind ? uu : v, lon = kind ? v : uu;
                double x, y, l2 = lon;
                if (m->proj.kind == VSV_PROJ_LATLON)
                    l2 = x0 + fmod(fmod(lon - x0, 360) + 360, 360);
                if (!vsv_scene_world(m, lat, l2, &x, &y) && isfinite(x) && isfinite(y)) {
                    xy[2 * k] = x, xy[2 * k + 1] = y;
                    k++;
                } else if (k > 1) {
                    break;
                }
                if (u >= a1)
                    break;
            }
            P->want = kind ? 1 : 2;
            P->akey = -INFINITY;
            polyline(P, xy, k);
            if (P->akey > -INFINITY && nlab < 256) {
                lab *L = &labs[nlab++];
                L->x = P->ax, L->y = P->ay, L->below = kind;
                degrees(kind ? remainder(v, 360) : v, !kind, step, L->text, sizeof L->text);
            }
            P->want = 0;
        }
    }
    free(xy);
    const float grey[3] = {0.85f, 0.85f, 0.85f};
    ink(P, rgba, grey, 0.45f);
    int drawn[256][4], nd = 0;
    for (int i = 0; i < nlab; i++)
        label(a, rgba, P->w, P->h, labs[i].x, labs[i].y, labs[i].text, labs[i].below, legend, drawn, &nd);
    return 0;
}

/* 8 units a pixel: a real map (the MM5 domain's coast, lakes, borders and
 * graticule at 828 x 568) takes about a third of one */
int64_t vsv_annot_ground_budget(int w, int h) { return 8 * (int64_t)w * h + 64 * ((int64_t)w + h); }

int vsv_annot_ground(const vsv_annot *a, const vsv_scene *sc, const vsv_camera *cam, float *rgba, const float *depth,
                     const float *legend, int64_t *work)
{
    if (!(a->parts & (VSV_ANNOT_GRATICULE | VSV_ANNOT_OUTLINES)))
        return 0;
    vsv_geo g;
    vsv_scene_geo(sc, &g);
    pen P;
    memset(&P, 0, sizeof P);
    P.g = &g;
    P.w = cam->width, P.h = cam->height;
    P.depth = depth;
    vsv_rays_init(&P.R, cam);
    P.step = 0.5 * fmin(g.dx, g.dy);
    P.pix_angle = 2 * P.R.ky / P.h;
    P.pix_ortho = P.R.persp ? 0 : 2 * P.R.ky / P.h;
    P.slope = fmin(10, 1 / fmax(0.1, fabs(P.R.f[2])));
    P.zlo = g.terrain ? g.bmin[2] : 0; /* below the lowest ground */
    P.zhi = g.terrain ? g.ground_top : 0;
    P.seg_cap = 4 * (P.w + P.h);
    P.budget = vsv_annot_ground_budget(P.w, P.h);
    if (!(P.mask = calloc((size_t)P.w * P.h, sizeof *P.mask)))
        return VSV_ENOMEM;
    int rc = 0;
    if (a->parts & VSV_ANNOT_GRATICULE) {
        P.half = 0.45;
        rc = graticule(a, sc, &P, rgba, legend);
    }
    if (!rc && (a->parts & VSV_ANNOT_OUTLINES) && a->outlines) {
        /* thin state lines, then borders, then the shore on top */
        static const int order[] = {VSV_OUTLINE_STATE, VSV_OUTLINE_BORDER, VSV_OUTLINE_LAKE, VSV_OUTLINE_COAST};
        static const float colour[][4] = {{0.95f, 0.75f, 0.45f, 0.5f},
                                          {1.0f, 0.8f, 0.35f, 0.85f},
                                          {0.75f, 0.9f, 1.0f, 0.9f},
                                          {0.95f, 0.97f, 1.0f, 0.95f}};
        for (int c = 0; c < 4; c++) {
            P.half = order[c] == VSV_OUTLINE_STATE ? 0.4 : 0.7;
            const int nl = vsv_outlines_count(a->outlines);
            for (int i = 0; i < nl; i++) {
                int kind, n;
                const double *xy = vsv_outlines_line(a->outlines, i, &kind, &n);
                if (kind == order[c])
                    polyline(&P, xy, n);
            }
            ink(&P, rgba, colour[c], colour[c][3]);
        }
    }
    free(P.mask);
    if (work)
        *work = P.work;
    return rc;
}
