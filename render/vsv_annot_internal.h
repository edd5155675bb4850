/* vsv_annot_internal.h — what the annotation's parts share (vsv_annotate.c,
 * vsv_mapdraw.c, vsv_outlines.c). Private to render/. */
#ifndef VSV_ANNOT_INTERNAL_H
#define VSV_ANNOT_INTERNAL_H

#include "vsv_geo.h"

/* The latitude/longitude box under a grid, with a degree of margin:
 * box = south, north, west, east (longitudes unwrapped around the grid's
 * centre; the whole circle when a pole is inside). 0 or VSV_EUNSUPPORTED. */
int vsv_grid_latlon_box(const vsv_meta *m, double box[4]);

/* Screen position (px, py: pixel centres at +0.5) of world point p and its
 * distance along the pixel's ray (the units of the depth image); 0 when p
 * is not in front of the eye. */
int vsv_rays_project(const vsv_rays *R, const double p[3], double *px, double *py, double *t);

/* A translucent dark box behind text: pixels x0..x1, y0..y1 (clipped). */
void vsv_annot_box(float *rgba, int w, int h, int x0, int y0, int x1, int y1, float alpha);

/* The frame's time line: t as ISO UTC, then local time where m's "time
 * zone" attribute starts with the hours its file is behind UTC (as CAMx's
 * reader records it): "2002-06-03T17:00:00Z   local 2002-06-03T12:00 UTC-5".
 * buf of cap bytes. */
void vsv_annot_time_line(const vsv_meta *m, int64_t t, char *buf, size_t cap);

/* Draws the graticule and the outlines on the ground (the parts of a that
 * ask for them), labels with a's font where the legend, an RGBA overlay of
 * the frame's size, leaves the frame clear (alpha 0). Only the parts of
 * lines inside the grid and the view are followed, in steps no shorter
 * than a pixel, and the lines stop at vsv_annot_ground_budget(w, h) units
 * of work (a point set on the terrain, a brush step), whatever the grid's
 * spacing; *work (when not NULL) gets the units spent, for tests. 0 or
 * VSV_ENOMEM. */
int vsv_annot_ground(const vsv_annot *a, const vsv_scene *sc, const vsv_camera *cam, float *rgba, const float *depth,
                     const float *legend, int64_t *work);
/* The most work vsv_annot_ground spends on a frame of w x h pixels. */
int64_t vsv_annot_ground_budget(int w, int h);

#endif
