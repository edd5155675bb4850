/* vsv_mesh_draw.c — a scene's opaque meshes: its isosurfaces
 * (vsv_scene_iso, extracted per brick by vsv_iso.c, kept across steps) and
 * its lines (vsv_scene_line, tubes built by vsv_tube.c), each triangle
 * met by the rays of the pixels its screen box covers, the
 * nearest hit per pixel written into the surface buffer the volume's rays
 * stop at, as the ground and the slices are. Exact ray-triangle hits, not
 * a projected rasteriser, so a pixel's surface distance is measured along
 * the very ray the raycaster marches. */
#include "vsv_renderer.h"

#include <stdlib.h>
#include <string.h>

#define MESH_BAND 8 /* image rows a pool item */

/* This frame's triangles of every mesh (kept between frames: the arrays
 * grow, never shrink). */
typedef struct vsv_mesh_frame {
    double *wp; /* nv * 3: world position, z exaggerated */
    double *sp; /* nv * 2: pixel coordinates (valid in front of the eye) */
    float *nrm; /* nv * 3: unit normal in the exaggerated world */
    uint32_t *tri;
    int *box;             /* nt * 4: the pixels x0, x1, y0, y1 its rays may meet */
    uint32_t *which;      /* nt: its colour (index in rgb) */
    unsigned char *front; /* nt: wholly in front of the eye (sp valid) */
    size_t vcap, tcap, nv, nt;
    /* the triangles per band of MESH_BAND rows: band b's are blist[bstart[b]
     * .. bstart[b + 1] - 1], in the order gathered */
    int *bstart, *bfill, bcap;
    uint32_t *blist;
    size_t blcap;
    float (*rgb)[3]; /* ncol linear colours */
    int ncol, colcap;
    vsv_tube tube; /* a line's tube, built here */
} vsv_mesh_frame;

void vsv_rc_meshes_free(vsv_renderer *r)
{
    for (int i = 0; i < VSV_SCENE_ISO_MAX; i++)
        vsv_iso_free(r->iso[i]);
    if (r->meshf) {
        free(r->meshf->wp);
        free(r->meshf->sp);
        free(r->meshf->nrm);
        free(r->meshf->front);
        free(r->meshf->bstart);
        free(r->meshf->bfill);
        free(r->meshf->blist);
        free(r->meshf->tri);
        free(r->meshf->box);
        free(r->meshf->which);
        free(r->meshf->rgb);
        vsv_tube_free(&r->meshf->tube);
    }
    free(r->meshf);
}

static int grow(vsv_mesh_frame *F, size_t nv, size_t nt)
{
    if (nv > F->vcap) {
        double *wp = realloc(F->wp, nv * 3 * sizeof *wp);
        if (wp)
            F->wp = wp;
        double *sp = wp ? realloc(F->sp, nv * 2 * sizeof *sp) : NULL;
        if (sp)
            F->sp = sp;
        float *nrm = sp ? realloc(F->nrm, nv * 3 * sizeof *nrm) : NULL;
        if (!nrm)
            return VSV_ENOMEM;
        F->nrm = nrm;
        F->vcap = nv;
    }
    if (nt > F->tcap) {
        uint32_t *tri = realloc(F->tri, nt * 3 * sizeof *tri);
        if (tri)
            F->tri = tri;
        int *box = tri ? realloc(F->box, nt * 4 * sizeof *box) : NULL;
        if (box)
            F->box = box;
        uint32_t *which = box ? realloc(F->which, nt * sizeof *which) : NULL;
        if (which)
            F->which = which;
        unsigned char *front = which ? realloc(F->front, nt) : NULL;
        if (!front)
            return VSV_ENOMEM;
        F->front = front;
        F->tcap = nt;
    }
    return 0;
}

/* Pixel coordinates (x, y; pixel centres at whole numbers) of world point p
 * as vsv_rays_get casts them: 1; 0 when p is not in front of the eye. */
static int project(const vsv_rays *R, const double p[3], double *x, double *y)
{
    double v[3] = {p[0] - R->o[0], p[1] - R->o[1], p[2] - R->o[2]};
    double sx = v[0] * R->r[0] + v[1] * R->r[1] + v[2] * R->r[2];
    double sy = v[0] * R->u[0] + v[1] * R->u[1] + v[2] * R->u[2];
    if (R->persp) {
        const double z = v[0] * R->f[0] + v[1] * R->f[1] + v[2] * R->f[2];
        if (!(z > 1e-9))
            return 0;
        sx /= z, sy /= z;
    }
    *x = ((sx - R->cx) / R->kx + 1) * R->w / 2 - 0.5;
    *y = (1 - (sy - R->cy) / R->ky) * R->h / 2 - 0.5;
    return 1;
}

/* Colour rgb (as given: gamma-encoded, 0..1) added to F's, linear: its
 * index, or -1 (out of memory). */
static int add_colour(vsv_mesh_frame *F, const float rgb[3])
{
    if (F->ncol == F->colcap) {
        const int cap = F->colcap ? 2 * F->colcap : 16;
        float(*c)[3] = realloc(F->rgb, (size_t)cap * sizeof *c);
        if (!c)
            return -1;
        F->rgb = c, F->colcap = cap;
    }
    for (int k = 0; k < 3; k++) /* the image is linear */
        F->rgb[F->ncol][k] = powf(fminf(fmaxf(rgb[k], 0), 1), 2.2f);
    return F->ncol++;
}

/* Gathers mesh b's triangles into F in colour col: world positions with z
 * times E, normals for that scale, the screen box of each triangle (none
 * when it lies behind the eye, the whole image when it crosses the eye's
 * plane). */
static int gather(vsv_mesh_frame *F, const vsv_iso_mesh *b, int col, const vsv_rays *R, double E, int w, int h)
{
    if (grow(F, F->nv + (size_t)b->nverts, F->nt + (size_t)b->ntris))
        return VSV_ENOMEM;
    const size_t v0 = F->nv;
    for (int v = 0; v < b->nverts; v++) {
        double *p = F->wp + 3 * (F->nv + v), n[3] = {b->nrm[3 * v], b->nrm[3 * v + 1], b->nrm[3 * v + 2] / E};
        p[0] = b->pos[3 * v], p[1] = b->pos[3 * v + 1], p[2] = (double)b->pos[3 * v + 2] * E;
        vsv_normalize(n); /* a normal under z scaled by E: z divided by E */
        for (int k = 0; k < 3; k++)
            F->nrm[3 * (F->nv + v) + k] = (float)n[k];
    }
    for (int t = 0; t < b->ntris; t++) {
        uint32_t *T = F->tri + 3 * F->nt;
        int *box = F->box + 4 * F->nt;
        double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
        int nfront = 0;
        for (int k = 0; k < 3; k++) {
            T[k] = (uint32_t)v0 + b->tri[3 * t + k];
            double *x = F->sp + 2 * T[k];
            if (project(R, F->wp + 3 * T[k], &x[0], &x[1]))
                nfront++, x0 = fmin(x0, x[0]), x1 = fmax(x1, x[0]), y0 = fmin(y0, x[1]), y1 = fmax(y1, x[1]);
        }
        if (!nfront) /* wholly behind the eye (an eye among the clouds) */
            continue;
        const int front = nfront == 3; /* else it crosses the eye's plane: every pixel may see it */
        box[0] = front ? (int)fmax(0, floor(x0)) : 0;
        box[1] = front ? (int)fmin(w - 1, ceil(x1)) : w - 1;
        box[2] = front ? (int)fmax(0, floor(y0)) : 0;
        box[3] = front ? (int)fmin(h - 1, ceil(y1)) : h - 1;
        if (box[0] > box[1] || box[2] > box[3])
            continue; /* off the image */
        F->front[F->nt] = (unsigned char)front;
        F->which[F->nt++] = (uint32_t)col;
    }
    F->nv += (size_t)b->nverts;
    return 0;
}

/* Möller and Trumbore's ray-triangle test: the distance along (o, d) and
 * the barycentric weights (u, v) of corners 1 and 2; INFINITY if missed.
 * The weights may stray EDGE_EPS outside the triangle: a ray through an
 * edge two triangles share would otherwise miss both by rounding now and
 * then (pinholes in a closed surface). */
#define EDGE_EPS 1e-7
static double hit(const double *a, const double *b, const double *c, const double o[3], const double d[3], double *u,
                  double *v)
{
    const double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double p[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2], d[0] * e2[1] - d[1] * e2[0]};
    const double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    if (det == 0)
        return INFINITY;
    const double inv = 1 / det, s[3] = {o[0] - a[0], o[1] - a[1], o[2] - a[2]};
    *u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) * inv;
    if (*u < -EDGE_EPS || *u > 1 + EDGE_EPS)
        return INFINITY;
    const double q[3] = {s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2], s[0] * e1[1] - s[1] * e1[0]};
    *v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) * inv;
    if (*v < -EDGE_EPS || *u + *v > 1 + EDGE_EPS)
        return INFINITY;
    return (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) * inv;
}

/* Where a pixel centre may lie for a triangle in front of the eye: its
 * screen triangle grown by PIX_MARGIN pixels (the exact test decides; this
 * only spares it the pixels plainly outside). */
#define PIX_MARGIN 1e-3
typedef struct screen_tri {
    double e[3][3]; /* per edge: a x + b y + c >= 0 inside (a, b unit) */
    int on;         /* 0: no test (behind the eye's plane, or edge-on) */
} screen_tri;

static void screen_setup(const vsv_mesh_frame *F, size_t t, screen_tri *S)
{
    const uint32_t *T = F->tri + 3 * t;
    const double *p[3] = {F->sp + 2 * T[0], F->sp + 2 * T[1], F->sp + 2 * T[2]};
    const double area = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
    S->on = F->front[t] && fabs(area) > 1e-9;
    for (int k = 0; k < 3 && S->on; k++) {
        const double *a = p[k], *b = p[(k + 1) % 3];
        const double dx = b[0] - a[0], dy = b[1] - a[1], len = sqrt(dx * dx + dy * dy), sg = area > 0 ? 1 : -1;
        if (!(len > 0)) {
            S->on = 0;
            break;
        }
        S->e[k][0] = -dy * sg / len, S->e[k][1] = dx * sg / len;
        S->e[k][2] = -(S->e[k][0] * a[0] + S->e[k][1] * a[1]) + PIX_MARGIN;
    }
}

/* Triangle t over rows ya..yb of its box: the nearest hit per pixel. */
static void draw_tri(vsv_renderer *r, size_t t, int ya, int yb, double tmin)
{
    const vsv_mesh_frame *F = r->meshf;
    const vsv_scene *sc = r->sc;
    const int *box = F->box + 4 * t, w = r->cam->width;
    const uint32_t *T = F->tri + 3 * t;
    const double *A = F->wp + 3 * T[0], *Bv = F->wp + 3 * T[1], *C = F->wp + 3 * T[2];
    screen_tri S;
    screen_setup(F, t, &S);
    for (int py = ya; py <= yb; py++)
        for (int px = box[0]; px <= box[1]; px++) {
            if (S.on &&
                (S.e[0][0] * px + S.e[0][1] * py + S.e[0][2] < 0 || S.e[1][0] * px + S.e[1][1] * py + S.e[1][2] < 0 ||
                 S.e[2][0] * px + S.e[2][1] * py + S.e[2][2] < 0))
                continue;
            double o[3], d[3], u = 0, v = 0;
            vsv_rays_get(&r->rays, px, py, o, d);
            const double th = hit(A, Bv, C, o, d, &u, &v);
            vsv_ground *out = &r->surf[(size_t)py * w + px];
            if (!(th >= tmin && th < out->t))
                continue;
            double n[3], ndl = 0, ndd = 0;
            for (int k = 0; k < 3; k++) {
                n[k] = (1 - u - v) * F->nrm[3 * T[0] + k] + u * F->nrm[3 * T[1] + k] + v * F->nrm[3 * T[2] + k];
                ndd += n[k] * d[k];
            }
            vsv_normalize(n);
            for (int k = 0; k < 3; k++) /* the side the eye sees; lit by the sun, else from the eye */
                ndl += (ndd > 0 ? -n[k] : n[k]) * (sc->light ? sc->light_dir[k] : -d[k]);
            const float shade = fminf(1, VSV_LIGHT_AMBIENT + VSV_LIGHT_DIFFUSE * (float)fmax(0, ndl));
            out->t = (float)th;
            for (int k = 0; k < 3; k++)
                out->rgb[k] = F->rgb[F->which[t]][k] * shade;
        }
}

/* Pool job: image rows band * MESH_BAND onwards; the band's triangles in
 * the order gathered (so a tie in depth goes to the same one whatever the
 * threads). */
static void band_job(void *ctx, int band, int thread)
{
    vsv_renderer *r = ctx;
    const vsv_mesh_frame *F = r->meshf;
    const int h = r->cam->height, py0 = band * MESH_BAND,
              py1 = py0 + MESH_BAND - 1 < h - 1 ? py0 + MESH_BAND - 1 : h - 1;
    const double tmin = r->cam->znear > 0 ? r->cam->znear : 0;
    (void)thread;
    for (int i = F->bstart[band]; i < F->bstart[band + 1]; i++) {
        const int *box = F->box + 4 * F->blist[i];
        draw_tri(r, F->blist[i], box[2] > py0 ? box[2] : py0, box[3] < py1 ? box[3] : py1, tmin);
    }
}

/* Lists each triangle under every band of rows its box meets. */
static int bin_bands(vsv_mesh_frame *F, int nbands)
{
    if (nbands + 1 > F->bcap) {
        int *st = realloc(F->bstart, (size_t)(nbands + 1) * sizeof *st);
        if (st)
            F->bstart = st;
        int *fi = st ? realloc(F->bfill, (size_t)(nbands + 1) * sizeof *fi) : NULL;
        if (!fi)
            return VSV_ENOMEM;
        F->bfill = fi;
        F->bcap = nbands + 1;
    }
    memset(F->bstart, 0, (size_t)(nbands + 1) * sizeof *F->bstart);
    for (size_t t = 0; t < F->nt; t++)
        for (int b = F->box[4 * t + 2] / MESH_BAND; b <= F->box[4 * t + 3] / MESH_BAND; b++)
            F->bstart[b + 1]++;
    for (int b = 0; b < nbands; b++)
        F->bstart[b + 1] += F->bstart[b];
    const size_t n = (size_t)F->bstart[nbands];
    if (n > F->blcap) {
        uint32_t *bl = realloc(F->blist, n * sizeof *bl);
        if (!bl)
            return VSV_ENOMEM;
        F->blist = bl;
        F->blcap = n;
    }
    memcpy(F->bfill, F->bstart, (size_t)nbands * sizeof *F->bfill);
    for (size_t t = 0; t < F->nt; t++)
        for (int b = F->box[4 * t + 2] / MESH_BAND; b <= F->box[4 * t + 3] / MESH_BAND; b++)
            F->blist[F->bfill[b]++] = (uint32_t)t;
    return 0;
}

/* The scene's isosurfaces gathered into F. */
static int gather_isos(vsv_renderer *r, const vsv_scene *in, const vsv_camera *cam)
{
    vsv_mesh_frame *F = r->meshf;
    if (in->nisos < 0 || in->nisos > VSV_SCENE_ISO_MAX || (in->nisos && !in->isos))
        return VSV_EINVAL;
    for (int q = 0; q < in->nisos; q++) {
        const vsv_scene_iso *I = &in->isos[q];
        if (I->layer < 0 || I->layer >= in->nlayers || !in->layers[I->layer].vol)
            return VSV_EINVAL;
        if (!r->iso[q]) {
            if (vsv_iso_create(1, &r->iso[q]))
                return VSV_ENOMEM;
            vsv_iso_use_pool(r->iso[q], &r->pool);
        }
        int rc = vsv_iso_extract(r->iso[q], in->meta, in->layers[I->layer].vol, I->value);
        if (rc)
            return rc;
        const int col = add_colour(F, I->rgb);
        if (col < 0)
            return VSV_ENOMEM;
        vsv_iso_mesh b;
        for (int i = 0; vsv_iso_brick(r->iso[q], i, &b) == 0; i++)
            if ((rc = gather(F, &b, col, &r->rays, r->g.E, cam->width, cam->height)))
                return rc;
    }
    return 0;
}

/* The scene's lines' tubes gathered into F. */
static int gather_lines(vsv_renderer *r, const vsv_scene *in, const vsv_camera *cam)
{
    vsv_mesh_frame *F = r->meshf;
    if (in->nlines < 0 || (in->nlines && !in->lines))
        return VSV_EINVAL;
    for (int q = 0; q < in->nlines; q++) {
        const vsv_scene_line *L = &in->lines[q];
        int rc = vsv_tube_build(&F->tube, L, r->g.E);
        if (rc)
            return rc;
        const int col = add_colour(F, L->rgb);
        if (col < 0)
            return VSV_ENOMEM;
        const vsv_iso_mesh b = {F->tube.pos, F->tube.nrm, F->tube.tri, F->tube.nv, F->tube.nt};
        if ((rc = gather(F, &b, col, &r->rays, 1, cam->width, cam->height))) /* built exaggerated */
            return rc;
    }
    return 0;
}

int vsv_rc_meshes(vsv_renderer *r, const vsv_scene *in, const vsv_camera *cam)
{
    if (!r->meshf && !(r->meshf = calloc(1, sizeof *r->meshf)))
        return VSV_ENOMEM;
    vsv_mesh_frame *F = r->meshf;
    const size_t n = (size_t)cam->width * cam->height;
    if (vsv_rc_surf_reserve(r, n))
        return VSV_ENOMEM;
    if (r->surf_read != r->surf) { /* the ground (or nothing) under the meshes */
        for (size_t i = 0; i < n; i++)
            r->surf[i] = r->surf_read ? r->surf_read[i] : (vsv_ground){INFINITY, {0, 0, 0}};
        r->surf_read = r->surf;
    }
    F->nv = F->nt = 0;
    F->ncol = 0;
    int rc = gather_isos(r, in, cam);
    if (rc || (rc = gather_lines(r, in, cam)))
        return rc;
    const int nbands = (cam->height + MESH_BAND - 1) / MESH_BAND;
    if (bin_bands(F, nbands))
        return VSV_ENOMEM;
    r->cam = cam;
    r->sc = in;
    vsv_pool_run(&r->pool, band_job, r, nbands);
    return 0;
}
