/* vsv_overlay.h — what vsv-play draws with OpenGL, shared by every display
 * back end: the rendered image on a billboard at the volume's position, and
 * a text overlay (the status line, the help) rasterised with FreeType from
 * the system's monospace font (fontconfig). */
#ifndef VSV_OVERLAY_H
#define VSV_OVERLAY_H

#include "vsv_render.h"

#include <GL/gl.h>

typedef struct vsv_overlay vsv_overlay;

/* Finds and loads the font (px: glyph height in pixels). NULL with the
 * reason in err. */
vsv_overlay *vsv_overlay_create(int px, char *err, size_t cap);
void vsv_overlay_free(vsv_overlay *o);

/* The depth along cam's view of the box mn..mx's centre (the units of
 * cam: world metres), or 1 when it is not in front. */
double vsv_billboard_depth(const vsv_camera *cam, const double mn[3], const double mx[3]);

/* Draws the image (w x h 8-bit RGB, row 0 at the top) rendered for cam as a
 * textured quad facing the eye at `depth` in eye space, filling cam's view
 * window there (drawn in eye space, so world coordinates never meet
 * single-precision GL). Any depth the projection keeps gives the same
 * picture: it must lie between that projection's near and far planes, in
 * its units (FreeVR: feet, 0.1 to 1000). set_projection: load cam's frustum
 * around depth first (the desktop); otherwise keep the projection already
 * loaded (FreeVR loads each eye's). Needs a current GL context. */
void vsv_billboard_draw(const vsv_camera *cam, double depth, const unsigned char *rgb, int w, int h,
                        int set_projection);
/* The same in two parts, for a caller that keeps the image: uploads it
 * into texture *tex (made when 0), then draws that texture's quad. */
void vsv_billboard_upload(GLuint *tex, const unsigned char *rgb, int w, int h);
void vsv_billboard_quad(const vsv_camera *cam, double depth, GLuint tex, int set_projection);

/* Draws text lines ('\n' separated) in window pixels from the top-left
 * corner (x, y) over a translucent dark box; a negative y places the box's
 * bottom -y pixels above the window's. */
void vsv_overlay_text(vsv_overlay *o, int win_w, int win_h, int x, int y, const char *text);

#endif
