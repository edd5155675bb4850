/* vsv_player_gl.c — an immersive display's eye as a renderer camera: the
 * projection and model-view matrices FreeVR loads turned into vsv_camera
 * (vsv_player_camera_from_gl). */
#include "vsv_player.h"

#include <math.h>
#include <string.h>

/* 4x4 inverse (column order), Gauss-Jordan with partial pivoting; 0 if singular. */
static int invert4(const double m[16], double out[16])
{
    double a[4][8];
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++) {
            a[r][c] = m[c * 4 + r];
            a[r][c + 4] = r == c;
        }
    for (int c = 0; c < 4; c++) {
        int piv = c;
        for (int r = c + 1; r < 4; r++)
            if (fabs(a[r][c]) > fabs(a[piv][c]))
                piv = r;
        if (fabs(a[piv][c]) < 1e-300)
            return 0;
        for (int k = 0; k < 8; k++) {
            const double t = a[c][k];
            a[c][k] = a[piv][k];
            a[piv][k] = t;
        }
        const double d = a[c][c];
        for (int k = 0; k < 8; k++)
            a[c][k] /= d;
        for (int r = 0; r < 4; r++)
            if (r != c) {
                const double f = a[r][c];
                for (int k = 0; k < 8; k++)
                    a[r][k] -= f * a[c][k];
            }
    }
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++)
            out[c * 4 + r] = a[r][c + 4];
    return 1;
}

static void mul4(const double a[16], const double b[16], double out[16])
{
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++) {
            double s = 0;
            for (int k = 0; k < 4; k++)
                s += a[k * 4 + r] * b[c * 4 + k];
            out[c * 4 + r] = s;
        }
}

void vsv_player_camera_from_gl(const vsv_player *p, const double at[3], double size, const double P[16],
                               const double MV[16], int w, int h, vsv_camera *cam)
{
    double mn[3], mx[3];
    vsv_player_bounds(p, mn, mx);
    const double span = fmax(mx[0] - mn[0], mx[1] - mn[1]);
    const double k = size / (span > 0 ? span : 1);
    const double c[3] = {0.5 * (mn[0] + mx[0]), 0.5 * (mn[1] + mx[1]), 0.5 * (mn[2] + mx[2])};
    /* W: world metres -> display units: x east, y up, -z north */
    const double W[16] = {k, 0, 0, 0, 0, 0, -k, 0, 0, k, 0, 0,
                          at[0] - k * c[0], at[1] - k * c[2], at[2] + k * c[1], 1};
    double M[16], Mi[16];
    mul4(MV, W, M); /* world -> eye */
    memset(cam, 0, sizeof *cam);
    cam->width = w;
    cam->height = h;
    cam->zfar = INFINITY;
    if (!invert4(M, Mi))
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
