/* vsv_vector.c — vector species and the projection's local geometry (see
 * vsv_vector.h). */
#include "vsv_format.h"

#include <math.h>
#include <string.h>

int vsv_meta_vector(const vsv_meta *m, const char *name, int idx[3])
{
    char key[64];
    if (strlen(VSV_VECTOR_ATTR) + strlen(name) >= sizeof key)
        return VSV_ENOTFOUND;
    strcpy(key, VSV_VECTOR_ATTR);
    strcat(key, name);
    const char *v = vsv_meta_attr(m, key);
    if (!v)
        return VSV_ENOTFOUND;
    idx[2] = -1;
    for (int c = 0; c < 3; c++) {
        char one[64];
        size_t n;
        v += strspn(v, " ");
        n = strcspn(v, " ");
        if (!n && c == 2)
            break; /* a horizontal vector */
        if (!n || n >= sizeof one)
            return VSV_ENOTFOUND;
        memcpy(one, v, n);
        one[n] = 0;
        v += n;
        if ((idx[c] = vsv_meta_find_var(m, one)) < 0)
            return VSV_ENOTFOUND;
    }
    return v[strspn(v, " ")] ? VSV_ENOTFOUND : 0;
}

int vsv_meta_var_in_vector(const vsv_meta *m, int v)
{
    const size_t n = strlen(VSV_VECTOR_ATTR);
    for (int a = 0; a < m->nattrs; a++) {
        int idx[3];
        if (strncmp(m->attr_keys[a], VSV_VECTOR_ATTR, n) || vsv_meta_vector(m, m->attr_keys[a] + n, idx))
            continue;
        if (idx[0] == v || idx[1] == v || (idx[2] >= 0 && idx[2] == v))
            return 1;
    }
    return 0;
}

int vsv_proj_jacobian(const vsv_proj *p, double x, double y, double j[2][2])
{
    const double r = (p->radius > 0 ? p->radius : 6370000.0), deg = M_PI / 180.0;
    double lat[4], lon[4];
    if (p->kind == VSV_PROJ_NONE) {
        j[0][0] = j[1][1] = 1, j[0][1] = j[1][0] = 0;
        return 0;
    }
    if (p->kind == VSV_PROJ_LATLON) {
        if (!(fabs(y) < 90))
            return VSV_ERANGE;
        j[0][0] = r * cos(y * deg) * deg, j[1][1] = r * deg, j[0][1] = j[1][0] = 0;
        return 0;
    }
    /* central differences over 2 h = 100 m of the projection's inverse */
    const double h = 50, dx[4] = {h, -h, 0, 0}, dy[4] = {0, 0, h, -h};
    for (int k = 0; k < 4; k++) {
        int rc = vsv_proj_inverse(p, x + dx[k], y + dy[k], &lat[k], &lon[k]);
        if (rc)
            return rc;
    }
    for (int a = 0; a < 2; a++) {
        double dlon = remainder(lon[2 * a] - lon[2 * a + 1], 360.0), dlat = lat[2 * a] - lat[2 * a + 1];
        double mid = (lat[2 * a] + lat[2 * a + 1]) / 2;
        j[a][0] = r * cos(mid * deg) * dlon * deg / (2 * h);
        j[a][1] = r * dlat * deg / (2 * h);
    }
    return 0;
}
