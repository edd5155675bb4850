/* vsv_geo.h — a scene's world geometry, the terrain, and camera rays
 * (vsv_camera.c, vsv_ground.c). Private to render/. */
#ifndef VSV_GEO_H
#define VSV_GEO_H

#include "vsv_render.h"

#include <math.h>

/* Scales v to unit length (a zero vector stays). */
static inline void vsv_normalize(double v[3])
{
    const double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (n > 0) {
        const double k = 1 / n;
        for (int i = 0; i < 3; i++)
            v[i] *= k;
    }
}

/* World geometry of a scene: cell centres at (ox + i dx, oy + j dy, (oz + k dz) E). */
typedef struct vsv_geo {
    double ox, oy, oz, dx, dy, dz, E;
    double idx, idy; /* 1 / dx, 1 / dy */
    double ux, uy;   /* world metres per unit of the file's x, y (vsv_scene_units) */
    double bmin[3], bmax[3];
    int nx, ny, nz;
    const float *terrain;
    double ground_top;    /* the highest ground, exaggerated (with a terrain) */
    const float *landuse; /* with a terrain and water categories: the land use */
    uint64_t water;       /* its categories that are water (vsv_meta_water) */
} vsv_geo;

void vsv_scene_geo(const vsv_scene *sc, vsv_geo *g);

/* Native levels at their heights (vsv_native.c): for a scene whose file has
 * per-column heights, *out is the same scene over the volumes resampled
 * onto the even axis of vsv_heights_axis (valid until the next call);
 * otherwise *out is in. */
typedef struct vsv_native {
    const vsv_meta *m;
    vsv_resampler **rs; /* per layer */
    vsv_layer *layers;
    int cap;
    vsv_scene sc;
} vsv_native;
int vsv_native_scene(vsv_native *n, const vsv_scene *in, const vsv_scene **out);
void vsv_native_free(vsv_native *n);
/* Exaggerated terrain height at world (x, y), bilinear between cell centres. */
double vsv_geo_terrain(const vsv_geo *g, double x, double y);
/* Ground colour at (x, y): by height, shaded by slope. */
void vsv_geo_terrain_colour(const vsv_geo *g, double x, double y, float rgb[3]);
/* Slab intersection of a ray with a box: [t0, t1]; 0 if missed. Without
 * branches: the renderer runs it over several rays at once. */
static inline int vsv_box_hit(const double o[3], const double d[3], const double mn[3], const double mx[3], double *t0,
                              double *t1)
{
    double lo = -INFINITY, hi = INFINITY;
    int out = 0;
    for (int a = 0; a < 3; a++) {
        const double inv = 1 / d[a], ta = (mn[a] - o[a]) * inv, tb = (mx[a] - o[a]) * inv;
        const double near = ta > tb ? tb : ta, far = ta > tb ? ta : tb;
        const int flat = d[a] == 0; /* parallel to the slab: in it or not */
        out |= flat & (o[a] < mn[a] || o[a] > mx[a]);
        lo = !flat && near > lo ? near : lo;
        hi = !flat && far < hi ? far : hi;
    }
    *t0 = lo;
    *t1 = hi;
    return !out & (hi >= lo) & (hi > 0);
}
/* The part of segment a-b (x, y) inside the rectangle [mn, mx] (x, y; a
 * box's first two axes): the parameters f0 <= f1 along it, in [0, 1]; 0
 * when no part is inside or a coordinate is not finite. Lines are drawn
 * only over their part inside the grid or the image, so their cost follows
 * that part, not how long they are. */
static inline int vsv_segment_clip(const double a[2], const double b[2], const double mn[2], const double mx[2],
                                   double *f0, double *f1)
{
    double lo = 0, hi = 1;
    for (int k = 0; k < 2; k++) {
        const double d = b[k] - a[k];
        if (!isfinite(a[k]) || !isfinite(d))
            return 0;
        if (d == 0) {
            if (a[k] < mn[k] || a[k] > mx[k])
                return 0;
            continue;
        }
        const double ta = (mn[k] - a[k]) / d, tb = (mx[k] - a[k]) / d;
        lo = fmax(lo, fmin(ta, tb));
        hi = fmin(hi, fmax(ta, tb));
    }
    *f0 = lo, *f1 = hi;
    return lo <= hi;
}
/* Distance along the ray (o, d) where it first meets the ground (the
 * bilinear height field through the cell centres, flat beyond them) between
 * t0 and t1: exact, patch by patch; INFINITY if never. */
double vsv_geo_terrain_hit(const vsv_geo *g, const double o[3], const double d[3], double t0, double t1);
/* A camera's rays: the basis worked out once per frame. */
typedef struct vsv_rays {
    double o[3], f[3], r[3], u[3], kx, ky, cx, cy, w, h;
    int persp;
    int x0, x1, y0, y1; /* the pixels whose rays may meet the scene (the renderer's) */
} vsv_rays;
void vsv_rays_init(vsv_rays *R, const vsv_camera *cam);
/* Ray origin and unit direction of pixel (px, py). */
void vsv_rays_get(const vsv_rays *R, int px, int py, double o[3], double d[3]);
/* Narrows R's pixel rectangle (x0..y1) to the pixels whose rays can meet
 * the box [mn, mx]. */
void vsv_rays_cull(vsv_rays *R, const double mn[3], const double mx[3]);
/* The same, for one pixel (works out the basis each call). */
void vsv_pixel_ray(const vsv_camera *cam, int px, int py, double o[3], double d[3]);

/* Where each pixel's ray meets the ground (t, INFINITY when it does not) and
 * the ground's colour there: worked out once per camera and scene geometry
 * (the renderer keeps it while only the time step or the species change). */
typedef vsv_surface vsv_ground; /* (vsv_render.h's, for marchers) */

#endif
