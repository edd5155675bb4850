/* vsv_panel.h — information placed in an immersive display's room: the
 * legend of vsv_legend_draw (the model time in UTC and local time, the
 * caller's lines, a colour bar per visible species with its name, units
 * and range; DejaVu Sans, as vsv-render's annotation) on a quad standing
 * in the room, drawn with legacy OpenGL in each eye's projection, so it
 * has its true depth in stereo. The legend is rasterised at the size its
 * lines have in that view (crisp in a 200-pixel window and a 1024-pixel
 * one), again only when the text or that size changes. One panel per
 * window (its texture belongs to that window's GL context). */
#ifndef VSV_PANEL_H
#define VSV_PANEL_H

#include "vsv_render.h"

typedef struct vsv_panel vsv_panel;

vsv_panel *vsv_panel_create(void);
/* With the panel's GL context current (its texture); NULL is fine. */
void vsv_panel_free(vsv_panel *pn);

/* The panel's size in room units when its lines are lh units apart. 0, or
 * -1 when no font can be had (err says why). */
int vsv_panel_measure(vsv_panel *pn, const vsv_annot *a, const vsv_scene *sc, const char *lines, double lh, double *w,
                      double *h, char *err, size_t cap);

/* Draws it: its top-left corner at `at`, its width along `right` and its
 * height along `down` (unit vectors, room units), lines lh apart, in the
 * view of projection P, model-view MV (room to eye, as loaded) and viewport
 * vp (x, y, w, h). Returns the pixels a room unit gets at the panel's
 * centre in this view, 0 when the panel is not in view. */
double vsv_panel_draw(vsv_panel *pn, const vsv_annot *a, const vsv_scene *sc, const char *lines, const double at[3],
                      const double right[3], const double down[3], double lh, const double P[16], const double MV[16],
                      const int vp[4]);

#endif
