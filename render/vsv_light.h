/* vsv_light.h — gradient shading (vsv_render.h's lighting rule) as both
 * renderers apply it, inline: the raycaster at every sample, the shear-warp
 * at every voxel it classifies. Private to render/. */
#ifndef VSV_LIGHT_H
#define VSV_LIGHT_H

#include "vsv_geo.h"

#include <math.h>

/* What the shading of a frame needs, worked out once. */
typedef struct vsv_light {
    int on;
    float dir[3];      /* unit, toward the light, world (exaggerated) axes */
    float inv_cell[3]; /* 1 / the world cell edges dx, dy, dz E */
} vsv_light;

static inline void vsv_light_init(vsv_light *lt, const vsv_scene *sc, const vsv_geo *g)
{
    double d[3] = {sc->light_dir[0], sc->light_dir[1], sc->light_dir[2]};
    vsv_normalize(d);
    lt->on = sc->light && (d[0] != 0 || d[1] != 0 || d[2] != 0);
    for (int a = 0; a < 3; a++)
        lt->dir[a] = (float)d[a];
    lt->inv_cell[0] = (float)(1 / g->dx);
    lt->inv_cell[1] = (float)(1 / g->dy);
    lt->inv_cell[2] = (float)(1 / (g->dz * g->E));
}

/* 1 / the span of a transfer function's range, in the values it is
 * classified on (log values for a log scale). */
static inline float vsv_light_inv_span(const vsv_tf *tf)
{
    const double span = tf->scale == VSV_SCALE_LOG ? log(tf->hi) - log(tf->lo) : tf->hi - tf->lo;
    return span > 0 && isfinite(span) ? (float)(1 / span) : 0;
}

/* The factor a sample's colour is multiplied by: v its value, d[a] half the
 * difference of the values one cell ahead and one behind along axis a (the
 * central difference, per cell). The gradient in fractions of the range per
 * cell (of ln v on a log scale) gives the strength w = min(1, |g| /
 * VSV_LIGHT_GFULL) and, per world metre, the normal n = -g / |g|: factor
 * 1 - w + w (VSV_LIGHT_AMBIENT + VSV_LIGHT_DIFFUSE max(0, n . L)). Where
 * the value does not change the factor is exactly 1. */
static inline float vsv_light_shade(const vsv_light *lt, float v, const float d[3], int logscale, float inv_span)
{
    float k = inv_span;
    if (logscale)
        k = v > 0 ? inv_span / v : 0;
    const float g[3] = {d[0] * k, d[1] * k, d[2] * k};
    const float m2 = g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
    if (!(m2 > 0) || !isfinite(m2))
        return 1;
    float gw[3], n2 = 0, gl = 0;
    for (int a = 0; a < 3; a++) {
        gw[a] = g[a] * lt->inv_cell[a];
        n2 += gw[a] * gw[a];
        gl += gw[a] * lt->dir[a];
    }
    const float ndotl = n2 > 0 ? -gl / sqrtf(n2) : 0;
    const float w = fminf(1, sqrtf(m2) * (1 / VSV_LIGHT_GFULL));
    const float lam = VSV_LIGHT_AMBIENT + VSV_LIGHT_DIFFUSE * (ndotl > 0 ? ndotl : 0);
    return 1 + w * (lam - 1);
}

#endif
