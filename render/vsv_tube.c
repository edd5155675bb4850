/* vsv_tube.c — a scene's line (vsv_scene_line) as triangles: a tube of
 * VSV_TUBE_SIDES sides around the polyline, its rings turned from one
 * point to the next by the least rotation (no twist), with smooth normals,
 * a disc closing each end, and at the last point (with an arrow) a cone
 * whose tip is that point. Built in the exaggerated world, so the tube is
 * round on the screen whatever the exaggeration. */
#include "vsv_renderer.h"

#include <stdlib.h>
#include <string.h>

enum { S = VSV_TUBE_SIDES };

void vsv_tube_free(vsv_tube *t)
{
    free(t->pos);
    free(t->nrm);
    free(t->tri);
    free(t->q);
    memset(t, 0, sizeof *t);
}

static int reserve(vsv_tube *t, int nv, int nt, int nq)
{
    if (nv > t->vcap) {
        float *p = realloc(t->pos, (size_t)nv * 3 * sizeof *p);
        if (p)
            t->pos = p;
        float *n = p ? realloc(t->nrm, (size_t)nv * 3 * sizeof *n) : NULL;
        if (!n)
            return VSV_ENOMEM;
        t->nrm = n, t->vcap = nv;
    }
    if (nt > t->tcap) {
        uint32_t *T = realloc(t->tri, (size_t)nt * 3 * sizeof *T);
        if (!T)
            return VSV_ENOMEM;
        t->tri = T, t->tcap = nt;
    }
    if (nq > t->qcap) {
        double *q = realloc(t->q, (size_t)nq * 3 * sizeof *q);
        if (!q)
            return VSV_ENOMEM;
        t->q = q, t->qcap = nq;
    }
    return 0;
}

static void sub(const double *a, const double *b, double o[3])
{
    o[0] = a[0] - b[0], o[1] = a[1] - b[1], o[2] = a[2] - b[2];
}
static double dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static void cross(const double *a, const double *b, double o[3])
{
    o[0] = a[1] * b[2] - a[2] * b[1], o[1] = a[2] * b[0] - a[0] * b[2], o[2] = a[0] * b[1] - a[1] * b[0];
}

static int vert(vsv_tube *t, const double p[3], const double n[3])
{
    for (int k = 0; k < 3; k++)
        t->pos[3 * t->nv + k] = (float)p[k], t->nrm[3 * t->nv + k] = (float)n[k];
    return t->nv++;
}

static void tri(vsv_tube *t, int a, int b, int c)
{
    uint32_t *T = t->tri + 3 * t->nt++;
    T[0] = (uint32_t)a, T[1] = (uint32_t)b, T[2] = (uint32_t)c;
}

/* A unit vector square to unit t (about the axis t is least along). */
static void perpendicular(const double t[3], double n[3])
{
    const double ax[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    int a = 0;
    for (int k = 1; k < 3; k++)
        if (fabs(t[k]) < fabs(t[a]))
            a = k;
    double c[3];
    cross(t, ax[a], c);
    vsv_normalize(c);
    memcpy(n, c, sizeof c);
}

/* Direction (cos a) n + (sin a) b of side angle a. */
static void around(const double n[3], const double b[3], double a, double o[3])
{
    for (int k = 0; k < 3; k++)
        o[k] = cos(a) * n[k] + sin(a) * b[k];
}

/* A disc of radius rad at c square to unit axis ax (facing along ax),
 * ring basis n, b. */
static void disc(vsv_tube *t, const double c[3], const double ax[3], const double n[3], const double b[3], double rad)
{
    const int c0 = vert(t, c, ax);
    for (int s = 0; s < S; s++) {
        double d[3], p[3];
        around(n, b, 2 * M_PI * s / S, d);
        for (int k = 0; k < 3; k++)
            p[k] = c[k] + rad * d[k];
        vert(t, p, ax);
    }
    for (int s = 0; s < S; s++)
        tri(t, c0, c0 + 1 + s, c0 + 1 + (s + 1) % S);
}

/* The points kept (exaggerated, near repeats dropped) into t->q; with an
 * arrow the last is moved back to the cone's base and *tip set. Their
 * count. */
static int keep_points(vsv_tube *t, const vsv_scene_line *L, double E, double tip[3], int *arrow)
{
    int m = 0;
    for (int i = 0; i < L->npts; i++) {
        const double p[3] = {L->xyz[3 * i], L->xyz[3 * i + 1], L->xyz[3 * i + 2] * E};
        double d[3];
        if (m)
            sub(p, t->q + 3 * (m - 1), d);
        if (!m || sqrt(dot(d, d)) > L->radius * 1e-3)
            memcpy(t->q + 3 * m++, p, sizeof p);
    }
    *arrow = L->arrow && m >= 2;
    if (!*arrow)
        return m;
    memcpy(tip, t->q + 3 * (m - 1), 3 * sizeof *tip);
    double left = VSV_ARROW_LEN * L->radius; /* walk back the cone's length */
    while (m >= 2) {
        double d[3];
        sub(t->q + 3 * (m - 1), t->q + 3 * (m - 2), d);
        const double len = sqrt(dot(d, d));
        if (len > left) { /* the base inside this segment */
            double *e = t->q + 3 * (m - 1);
            for (int k = 0; k < 3; k++)
                e[k] -= d[k] * left / len;
            return m;
        }
        left -= len;
        m--;
    }
    return 1; /* a path shorter than the cone: the cone alone, from the first point */
}

int vsv_tube_build(vsv_tube *t, const vsv_scene_line *L, double E)
{
    t->nv = t->nt = 0;
    if (L->npts < 2)
        return 0;
    if (!(L->radius > 0) || !isfinite(L->radius) || !L->xyz || !(E > 0))
        return VSV_EINVAL;
    for (int i = 0; i < 3 * L->npts; i++)
        if (!isfinite(L->xyz[i]))
            return VSV_EINVAL;
    const int n = L->npts;
    if (reserve(t, n * S + 4 * (S + 1) + 2 * S, (n - 1) * 2 * S + 4 * S, n))
        return VSV_ENOMEM;
    double tip[3], nrm[3] = {0}, bin[3], tan[3] = {0}, prev[3] = {0};
    int arrow = 0;
    const int m = keep_points(t, L, E, tip, &arrow);
    if (m < 2 && !arrow) /* a point: nothing to draw */
        return 0;
    const double r = L->radius;
    int ring = -1;
    for (int i = 0; i < m && m >= 2; i++) { /* the tube's rings */
        const double *q = t->q + 3 * i;
        double a[3] = {0}, b[3] = {0};
        if (i + 1 < m)
            sub(t->q + 3 * (i + 1), q, a), vsv_normalize(a);
        if (i > 0)
            sub(q, t->q + 3 * (i - 1), b), vsv_normalize(b);
        for (int k = 0; k < 3; k++)
            tan[k] = a[k] + b[k];
        vsv_normalize(tan);
        if (dot(tan, tan) < 0.5) /* a path turning straight back */
            memcpy(tan, i > 0 ? b : a, sizeof tan);
        if (i == 0)
            perpendicular(tan, nrm);
        else { /* the last ring's normal, turned square to this tangent */
            const double k0 = dot(prev, tan);
            for (int k = 0; k < 3; k++)
                nrm[k] = prev[k] - k0 * tan[k];
            vsv_normalize(nrm);
            if (dot(nrm, nrm) < 0.5)
                perpendicular(tan, nrm);
        }
        memcpy(prev, nrm, sizeof prev);
        cross(tan, nrm, bin);
        if (i == 0) {
            const double back[3] = {-tan[0], -tan[1], -tan[2]};
            disc(t, q, back, nrm, bin, r);
        }
        const int r0 = t->nv;
        for (int s = 0; s < S; s++) {
            double d[3], p[3];
            around(nrm, bin, 2 * M_PI * s / S, d);
            for (int k = 0; k < 3; k++)
                p[k] = q[k] + r * d[k];
            vert(t, p, d);
        }
        for (int s = 0; s < S && ring >= 0; s++) {
            const int s1 = (s + 1) % S;
            tri(t, ring + s, r0 + s, r0 + s1);
            tri(t, ring + s, r0 + s1, ring + s1);
        }
        ring = r0;
    }
    const double *end = t->q + 3 * (m - 1);
    if (!arrow) {
        disc(t, end, tan, nrm, bin, r);
        return 0;
    }
    double ax[3];
    sub(tip, end, ax);
    const double len = sqrt(dot(ax, ax)), R = VSV_ARROW_WIDTH * r;
    vsv_normalize(ax);
    if (m < 2) /* no tube: the cone's own basis */
        perpendicular(ax, nrm), cross(ax, nrm, bin);
    else { /* the tube's last ring basis, square to the cone's axis */
        const double k0 = dot(nrm, ax);
        for (int k = 0; k < 3; k++)
            nrm[k] -= k0 * ax[k];
        vsv_normalize(nrm);
        if (dot(nrm, nrm) < 0.5)
            perpendicular(ax, nrm);
        cross(ax, nrm, bin);
    }
    const double back[3] = {-ax[0], -ax[1], -ax[2]};
    disc(t, end, back, nrm, bin, R);
    const int b0 = t->nv;
    for (int s = 0; s < 2 * S; s++) { /* the base ring, then the tip once per side */
        const double a = 2 * M_PI * (s < S ? s : s - S + 0.5) / S;
        double d[3], p[3], nn[3];
        around(nrm, bin, a, d);
        for (int k = 0; k < 3; k++) {
            p[k] = s < S ? end[k] + R * d[k] : tip[k];
            nn[k] = d[k] * len + ax[k] * R; /* square to the cone's side */
        }
        vsv_normalize(nn);
        vert(t, p, nn);
    }
    for (int s = 0; s < S; s++)
        tri(t, b0 + s, b0 + (s + 1) % S, b0 + S + s);
    return 0;
}
