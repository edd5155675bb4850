/* vsv_player_gl.c — an immersive display's eye as a renderer camera: the
 * projection and model-view matrices FreeVR loads, and where the scene is
 * placed in the room, turned into vsv_camera (vsv_player_camera_from_gl). */
#include "vsv_place.h"
#include "vsv_player.h"

#include <math.h>
#include <string.h>

void vsv_player_camera_from_gl(const double place[16], const double P[16], const double MV[16], int w, int h,
                               vsv_camera *cam)
{
    double M[16], Mi[16];
    vsv_mat4_mul(MV, place, M); /* world -> eye */
    memset(cam, 0, sizeof *cam);
    cam->width = w;
    cam->height = h;
    cam->zfar = INFINITY;
    if (!vsv_mat4_invert(M, Mi))
        return;
    for (int i = 0; i < 3; i++) {
        cam->pos[i] = Mi[12 + i] / Mi[15];
        cam->dir[i] = -Mi[8 + i]; /* the eye's -z */
        cam->up[i] = Mi[4 + i];   /* the eye's +y */
    }
    /* the frustum: glFrustum(l, r, b, t, n, f) */
    cam->window[0] = (P[8] - 1) / P[0];
    cam->window[1] = (P[8] + 1) / P[0];
    cam->window[2] = (P[9] - 1) / P[5];
    cam->window[3] = (P[9] + 1) / P[5];
    cam->fov_deg = 2 * atan(0.5 * (cam->window[3] - cam->window[2])) * 180 / M_PI;
    cam->znear = 0;
}
