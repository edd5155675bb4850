/* test_wind.c — vector species (vsv_vector.h) and the wind's rotation
 * (vsv_wind_rotation): the attribute parsed with three and two components
 * and refused when it names a missing species; components never drawn by
 * default; on a Lambert grid the rotation is the cone factor times the
 * longitude from the central meridian (computed here from the projection's
 * formula, not the library's), on Mercator and latitude-longitude grids none
 * (the poles too); vsv_wind_rotate keeps the speed. */
#include "vsv_convert.h"
#include "vsv_testlib.h"

#include <math.h>
#include <string.h>

static void vectors(void)
{
    vsv_meta m;
    vsv_meta_init(&m);
    static const char *const names[] = {"CLW", "wind_east", "wind_north", "wind_up", "Q"};
    for (int v = 0; v < 5; v++)
        vsv_meta_add_var(&m, names[v], "1", "");
    int idx[3] = {9, 9, 9};
    CHECK(vsv_meta_vector(&m, "wind", idx) == VSV_ENOTFOUND, "no attribute: no vector", "");
    CHECK(!vsv_meta_var_in_vector(&m, 1) && vsv_meta_default_shown(&m, 1), "no vector: wind_east drawn", "");
    vsv_meta_add_attr(&m, "vector:wind", "wind_east wind_north wind_up");
    CHECK(vsv_meta_vector(&m, "wind", idx) == 0 && idx[0] == 1 && idx[1] == 2 && idx[2] == 3, "three components",
          "%d %d %d", idx[0], idx[1], idx[2]);
    int in = 0, shown = 0;
    for (int v = 0; v < 5; v++)
        in |= vsv_meta_var_in_vector(&m, v) << v, shown |= vsv_meta_default_shown(&m, v) << v;
    CHECK(in == 0xe && shown == 0x1, "components: in the vector, not drawn by default (CLW is, Q vapour is not)",
          "in %#x shown %#x", in, shown);
    vsv_meta_clear(&m);

    vsv_meta_init(&m);
    vsv_meta_add_var(&m, "wind_east", "m s-1", "");
    vsv_meta_add_var(&m, "wind_north", "m s-1", "");
    vsv_meta_add_var(&m, "Q", "kg/kg", "");
    vsv_meta_add_attr(&m, "vector:wind", "wind_east wind_north");
    idx[2] = 9;
    CHECK(vsv_meta_vector(&m, "wind", idx) == 0 && idx[0] == 0 && idx[1] == 1 && idx[2] == -1,
          "two components: a horizontal vector, up -1", "%d %d %d", idx[0], idx[1], idx[2]);
    CHECK(vsv_meta_default_shown(&m, 2) && !vsv_meta_default_shown(&m, 0),
          "vapour and a vector only: the vapour drawn, the wind not", "");
    vsv_meta_add_attr(&m, "vector:gust", "wind_east nope");
    CHECK(vsv_meta_vector(&m, "gust", idx) == VSV_ENOTFOUND, "a vector naming a missing species is none", "");
    vsv_meta_add_attr(&m, "vector:one", "wind_east");
    CHECK(vsv_meta_vector(&m, "one", idx) == VSV_ENOTFOUND, "one component is no vector", "");
    vsv_meta_clear(&m);
}

/* A 5 x 4 grid of 32 km on projection p, its first cell at (x0, y0). */
static vsv_meta grid(vsv_proj p, double x0, double y0, double dx)
{
    vsv_meta m;
    vsv_meta_init(&m);
    m.nx = 5, m.ny = 4, m.nz = 1;
    m.origin[0] = x0, m.origin[1] = y0, m.spacing[0] = m.spacing[1] = dx;
    m.proj = p;
    return m;
}

static void rotation(void)
{
    /* Lambert true at 33 and 50, centred at 38N 97W (the MM5 run's) */
    vsv_proj lcc = {0};
    lcc.kind = VSV_PROJ_LCC, lcc.lat0 = 38, lcc.lon0 = -97, lcc.lat1 = 33, lcc.lat2 = 50;
    const double d = M_PI / 180, t1 = 33 * d, t2 = 50 * d;
    const double cone = log(cos(t1) / cos(t2)) / log(tan(M_PI / 4 + t2 / 2) / tan(M_PI / 4 + t1 / 2));
    vsv_meta m = grid(lcc, -2.4e6, 9.44e5, 32000);
    float rot[4 * 20];
    int rc = vsv_wind_rotation(&m, m.origin, rot);
    double worst = 0;
    for (int j = 0; !rc && j < m.ny; j++)
        for (int i = 0; i < m.nx; i++) {
            double lat, lon;
            vsv_proj_inverse(&lcc, m.origin[0] + i * m.spacing[0], m.origin[1] + j * m.spacing[1], &lat, &lon);
            const double a = cone * (lon - lcc.lon0) * d;
            const float *r = rot + 4 * (j * m.nx + i);
            /* east = u cos a + v sin a, north = -u sin a + v cos a */
            const double e[4] = {cos(a), sin(a), -sin(a), cos(a)};
            for (int k = 0; k < 4; k++)
                worst = fmax(worst, fabs(r[k] - e[k]));
        }
    CHECK(!rc && worst < 1e-6, "Lambert: the rotation is the cone's (n = 0.6651) angle", "rc %d, worst %.3g", rc,
          worst);
    /* the speed is kept */
    float u[20], v[20];
    for (int c = 0; c < 20; c++)
        u[c] = 3, v[c] = 4;
    vsv_wind_rotate(rot, 20, 1, u, v);
    int kept = 1;
    for (int c = 0; c < 20; c++)
        kept &= fabsf(hypotf(u[c], v[c]) - 5) < 1e-5f;
    CHECK(kept, "the rotation keeps the speed", "");
    vsv_meta_clear(&m);

    vsv_proj merc = {0};
    merc.kind = VSV_PROJ_MERCATOR, merc.lat0 = 0, merc.lon0 = -89, merc.lat1 = 0;
    m = grid(merc, -3e5, 2.5e6, 10000);
    rc = vsv_wind_rotation(&m, m.origin, rot);
    worst = 0;
    for (int c = 0; !rc && c < 20; c++)
        worst =
            fmax(worst, fabs(rot[4 * c] - 1) + fabs(rot[4 * c + 1]) + fabs(rot[4 * c + 2]) + fabs(rot[4 * c + 3] - 1));
    CHECK(!rc && worst < 1e-6, "Mercator: no rotation", "rc %d, worst %.3g", rc, worst);
    vsv_meta_clear(&m);

    vsv_proj ll = {0};
    ll.kind = VSV_PROJ_LATLON;
    m = grid(ll, 0, -90, 60); /* rows at -90 .. 90: both poles */
    rc = vsv_wind_rotation(&m, m.origin, rot);
    worst = 0;
    for (int c = 0; !rc && c < 20; c++)
        worst =
            fmax(worst, fabs(rot[4 * c] - 1) + fabs(rot[4 * c + 1]) + fabs(rot[4 * c + 2]) + fabs(rot[4 * c + 3] - 1));
    CHECK(!rc && worst == 0, "latitude-longitude: no rotation, the poles too", "rc %d, worst %.3g", rc, worst);
    vsv_meta_clear(&m);
}

int main(void)
{
    vectors();
    rotation();
    return vsv_test_done();
}
