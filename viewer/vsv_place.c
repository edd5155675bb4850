/* vsv_place.c — see vsv_place.h. */
#include "vsv_place.h"

#include <math.h>
#include <string.h>

void vsv_mat4_mul(const double a[16], const double b[16], double out[16])
{
    double o[16];
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++) {
            double s = 0;
            for (int k = 0; k < 4; k++)
                s += a[k * 4 + r] * b[c * 4 + k];
            o[c * 4 + r] = s;
        }
    memcpy(out, o, sizeof o);
}

/* Gauss-Jordan with partial pivoting. */
int vsv_mat4_invert(const double m[16], double out[16])
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

void vsv_mat4_point(const double M[16], const double p[3], double out[3])
{
    double o[3];
    for (int i = 0; i < 3; i++)
        o[i] = M[i] * p[0] + M[4 + i] * p[1] + M[8 + i] * p[2] + M[12 + i];
    memcpy(out, o, sizeof o);
}

void vsv_place_base(int kind, const double room_lo[3], const double room_hi[3], const double mn[3], const double mx[3],
                    double M[16])
{
    const double span = fmax(mx[0] - mn[0], mx[1] - mn[1]), tall = mx[2] - mn[2];
    const double rw = room_hi[0] - room_lo[0], rh = room_hi[1] - room_lo[1], rd = room_hi[2] - room_lo[2];
    const double cx = 0.5 * (room_lo[0] + room_hi[0]), cz = 0.5 * (room_lo[2] + room_hi[2]);
    double k, base, at_z;
    if (kind == VSV_PLACE_ROOM) {
        k = rh / (tall > 0 ? tall : span > 0 ? span : 1);
        base = room_lo[1];
        at_z = cz;
    } else {
        k = 0.6 * fmin(rw, rd) / (span > 0 ? span : 1);
        base = room_lo[1] + VSV_PLACE_TABLE_HEIGHT;
        at_z = cz - 0.15 * rd;
    }
    const double c[2] = {0.5 * (mn[0] + mx[0]), 0.5 * (mn[1] + mx[1])};
    /* x east -> +x, y north -> -z, z up -> +y; the box's bottom at `base` */
    const double W[16] = {k, 0, 0, 0, 0, 0, -k, 0, 0, k, 0, 0, cx - k * c[0], base - k * mn[2], at_z + k * c[1], 1};
    memcpy(M, W, sizeof W);
}

void vsv_nav_identity(double N[16])
{
    memset(N, 0, 16 * sizeof *N);
    N[0] = N[5] = N[10] = N[15] = 1;
}

void vsv_nav_travel(double N[16], const double d[3])
{
    double T[16];
    vsv_nav_identity(T);
    T[12] = -d[0], T[13] = -d[1], T[14] = -d[2];
    vsv_mat4_mul(T, N, N);
}

/* N = T(about) X T(-about) N for a linear X (column order). */
static void about_point(double N[16], const double about[3], const double X[9])
{
    double A[16];
    vsv_nav_identity(A);
    for (int c = 0; c < 3; c++)
        for (int r = 0; r < 3; r++)
            A[c * 4 + r] = X[c * 3 + r];
    for (int r = 0; r < 3; r++) /* translation: about - X about */
        A[12 + r] = about[r] - (X[r] * about[0] + X[3 + r] * about[1] + X[6 + r] * about[2]);
    vsv_mat4_mul(A, N, N);
}

void vsv_nav_turn(double N[16], const double about[3], double deg)
{
    /* the scene turns by -deg about +y (counter-clockwise from above is a
     * positive rotation about +y) */
    const double a = -deg * M_PI / 180, c = cos(a), s = sin(a);
    const double R[9] = {c, 0, -s, 0, 1, 0, s, 0, c};
    about_point(N, about, R);
}

void vsv_nav_scale(double N[16], const double about[3], double f)
{
    const double S[9] = {f, 0, 0, 0, f, 0, 0, 0, f};
    about_point(N, about, S);
}
