/* test_advect.c — time interpolation along the winds (--interp advect):
 * a cloud carried by a uniform wind comes out whole where linear
 * interpolation shows two ghosts; a calm gives linear interpolation bit for
 * bit; originals pass through exactly; no new extremes; winds never
 * emitted; advect without winds is an error naming them. */
#include "vsv_convert.h"
#include "vsv_format.h"
#include "vsv_testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { NX = 40, NY = 6, NZ = 16, NC = NX * NY * NZ, MAXF = 16 };

typedef struct frames {
    int n, nf;
    int64_t t[MAXF];
    float *f[MAXF][4];
} frames;

static int keep(void *ctx, int64_t t, const float *const *f)
{
    frames *fr = ctx;
    if (fr->n >= MAXF)
        return -1;
    fr->t[fr->n] = t;
    for (int v = 0; v < fr->nf; v++) {
        fr->f[fr->n][v] = malloc(NC * sizeof(float));
        memcpy(fr->f[fr->n][v], f[v], NC * sizeof(float));
    }
    fr->n++;
    return 0;
}

static void frames_free(frames *fr)
{
    for (int i = 0; i < fr->n; i++)
        for (int v = 0; v < fr->nf; v++)
            free(fr->f[i][v]);
    fr->n = 0;
}

/* A grid of NX x NY x NZ cells, 1 km x 1 km x 500 m, no projection, and
 * the variables named. */
static void grid(vsv_meta *m, const char *const *names, int n)
{
    vsv_meta_init(m);
    m->nx = NX, m->ny = NY, m->nz = NZ;
    m->spacing[0] = m->spacing[1] = 1000;
    m->spacing[2] = 500;
    m->vert_kind = VSV_VERT_EVEN;
    for (int i = 0; i < n; i++)
        vsv_meta_add_var(m, names[i], "", "");
}

/* A round cloud of peak 1 centred at (x, 3, z) cells. */
static void cloud(float *f, double x, double z)
{
    for (int k = 0; k < NZ; k++)
        for (int j = 0; j < NY; j++)
            for (int i = 0; i < NX; i++) {
                const double r2 = (i - x) * (i - x) + (j - 3.0) * (j - 3.0) + (k - z) * (k - z);
                f[(k * NY + j) * NX + i] = (float)exp(-r2 / 8);
            }
}

static void fill(float *f, float v)
{
    for (int i = 0; i < NC; i++)
        f[i] = v;
}

static float maxval(const float *f)
{
    float m = -INFINITY;
    for (int i = 0; i < NC; i++)
        m = f[i] > m ? f[i] : m;
    return m;
}

/* Cells whose trajectories of up to 9 cells along x and 3 along z stay in
 * the grid (elsewhere the air came from outside it). */
static int inside(int c)
{
    const int i = c % NX, k = c / (NX * NY);
    return i >= 9 && i <= NX - 10 && k >= 3 && k <= NZ - 4;
}

/* Runs two frames (0 s and 3600 s) through an interpolator every 900 s. */
static int run(int method, const vsv_meta *m, const float *const *a, const float *const *b, frames *fr)
{
    vsv_interp_opts o = {method, 2};
    vsv_interp *ip = NULL;
    int rc = vsv_interp_open(900, m, &o, keep, fr, &ip);
    if (!rc)
        rc = vsv_interp_push(ip, 0, a);
    if (!rc)
        rc = vsv_interp_push(ip, 3600, b);
    vsv_interp_free(ip);
    return rc;
}

static void test_uniform_wind(void)
{
    static const char *const names[] = {"CLW", VSV_WIND_U, VSV_WIND_V, VSV_WIND_W};
    vsv_meta m;
    grid(&m, names, 4);
    float *a[4], *b[4], *truth = malloc(NC * sizeof(float));
    for (int v = 0; v < 4; v++) {
        a[v] = malloc(NC * sizeof(float));
        b[v] = malloc(NC * sizeof(float));
    }
    /* the cloud moves 12 cells east (12 km) and 4 cells up (2 km) in an hour */
    cloud(a[0], 10, 4);
    cloud(b[0], 22, 8);
    fill(a[1], 12000 / 3600.0f), fill(b[1], 12000 / 3600.0f);
    fill(a[2], 0), fill(b[2], 0);
    fill(a[3], 2000 / 3600.0f), fill(b[3], 2000 / 3600.0f);
    frames adv = {0, 1, {0}, {{0}}}, lin = {0, 1, {0}, {{0}}};
    const int rc = run(VSV_TIME_ADVECT, &m, (const float *const *)a, (const float *const *)b, &adv);
    run(VSV_TIME_LINEAR, &m, (const float *const *)a, (const float *const *)b, &lin);
    if (CHECK(rc == 0 && adv.n == 5 && lin.n == 5, "advect: five frames from two an hour apart at 15 min",
              "rc %d, %d frames", rc, adv.n)) {
        /* half way: the cloud at (16, 6), whole */
        cloud(truth, 16, 6);
        double e_adv = 0, e_lin = 0;
        for (int i = 0; i < NC; i++) {
            if (!inside(i))
                continue;
            e_adv = fmax(e_adv, fabs(adv.f[2][0][i] - truth[i]));
            e_lin = fmax(e_lin, fabs(lin.f[2][0][i] - truth[i]));
        }
        CHECK(e_adv < 1e-4, "advect: a cloud in a uniform 3-D wind is rebuilt exactly half way", "max error %.3g",
              e_adv);
        CHECK(maxval(lin.f[2][0]) < 0.51f && e_lin > 0.9, "linear: the same cloud is two half-bright ghosts half way",
              "peak %.3f, max error %.3g", maxval(lin.f[2][0]), e_lin);
        CHECK(maxval(adv.f[2][0]) > 0.999f && maxval(adv.f[2][0]) <= 1.0f, "advect: the cloud keeps its peak", "%.4f",
              maxval(adv.f[2][0]));
        /* a quarter of the way: 3 cells east, 1 up; off-grid samples smooth it a little */
        cloud(truth, 13, 5);
        double e1 = 0;
        for (int i = 0; i < NC; i++)
            if (inside(i))
                e1 = fmax(e1, fabs(adv.f[1][0][i] - truth[i]));
        CHECK(e1 < 1e-4, "advect: rebuilt a quarter of the way too", "max error %.3g", e1);
        CHECK(!memcmp(adv.f[0][0], a[0], NC * 4) && !memcmp(adv.f[4][0], b[0], NC * 4) && adv.t[4] == 3600,
              "advect: the originals pass through bit for bit");
    }
    frames_free(&adv);
    frames_free(&lin);
    /* a sheared, turning wind: values stay within the inputs' range, none negative */
    for (int i = 0; i < NC; i++) {
        const int x = i % NX, k = i / (NX * NY);
        a[1][i] = 20 * sinf(0.3f * k), b[1][i] = 15 * cosf(0.2f * x);
        a[2][i] = 8 * cosf(0.4f * x), b[2][i] = -6;
        a[3][i] = 0.3f * sinf(0.1f * x), b[3][i] = 0.1f;
        a[0][i] = (x * 7919 + k * 104729) % 13 == 0 ? NAN : (float)((i * 2654435761u) % 1000) / 1000;
        b[0][i] = (float)((i * 40503u) % 997) / 997;
    }
    run(VSV_TIME_ADVECT, &m, (const float *const *)a, (const float *const *)b, &adv);
    int bad = 0, nans = 0;
    for (int f = 1; f < 4 && adv.n == 5; f++)
        for (int i = 0; i < NC; i++) {
            const float v = adv.f[f][0][i];
            if (isnan(a[0][i]))
                nans += isnan(v);
            else
                bad += !(v >= 0 && v <= 1);
        }
    int nan_in = 0;
    for (int i = 0; i < NC; i++)
        nan_in += isnan(a[0][i]);
    CHECK(adv.n == 5 && !bad && nans == 3 * nan_in,
          "advect in a sheared wind: no value outside the inputs' range, none negative, NaN where linear has it",
          "%d bad, %d NaN of %d", bad, nans, 3 * nan_in);
    frames_free(&adv);
    for (int v = 0; v < 4; v++)
        free(a[v]), free(b[v]);
    free(truth);
    vsv_meta_clear(&m);
}

/* Clouds travel slower than the air that carries them: the cloud moves 6
 * cells east and 2 up in the hour while the wind would carry it 12 and 4.
 * advect fits half the wind's displacement and rebuilds it; wind (the
 * air's full displacement) overshoots. */
static void test_fitted_scale(void)
{
    static const char *const names[] = {"CLW", "SNOW", VSV_WIND_U, VSV_WIND_V, VSV_WIND_W};
    vsv_meta m;
    grid(&m, names, 5);
    float *a[5], *b[5], *truth = malloc(NC * sizeof(float));
    for (int v = 0; v < 5; v++) {
        a[v] = malloc(NC * sizeof(float));
        b[v] = malloc(NC * sizeof(float));
    }
    cloud(a[0], 10, 4), cloud(b[0], 16, 6), cloud(truth, 13, 5);
    cloud(a[1], 10, 4), cloud(b[1], 22, 8); /* SNOW moves with the air */
    fill(a[2], 12000 / 3600.0f), fill(b[2], 12000 / 3600.0f);
    fill(a[3], 0), fill(b[3], 0);
    fill(a[4], 2000 / 3600.0f), fill(b[4], 2000 / 3600.0f);
    frames adv = {0, 2, {0}, {{0}}}, wind = {0, 2, {0}, {{0}}};
    vsv_interp_opts o = {VSV_TIME_ADVECT, 2};
    vsv_interp *ip = NULL;
    int rc = vsv_interp_open(900, &m, &o, keep, &adv, &ip);
    if (!rc)
        rc = vsv_interp_push(ip, 0, (const float *const *)a);
    if (!rc)
        rc = vsv_interp_push(ip, 3600, (const float *const *)b);
    int nb = 0, half = 0, whole = 0;
    const float *al = rc ? NULL : vsv_interp_scales(ip, &nb);
    for (int k = 0; al && k < nb; k++)
        half += al[k] == 0.5f, whole += al[nb + k] == 1.0f;
    CHECK(al && nb == 8 && half == nb && whole == nb,
          "advect fits half the wind's displacement for CLW, all of it for SNOW, in every band of levels",
          "%d bands, %d at 0.5, %d at 1", nb, half, whole);
    vsv_interp_free(ip);
    run(VSV_TIME_WIND, &m, (const float *const *)a, (const float *const *)b, &wind);
    double ea = 1, ew = 0, es = 1;
    if (adv.n == 5 && wind.n == 5) {
        ea = es = 0;
        cloud(a[1], 16, 6); /* SNOW's truth half way */
        for (int i = 0; i < NC; i++)
            if (inside(i)) {
                ea = fmax(ea, fabs(adv.f[2][0][i] - truth[i]));
                ew = fmax(ew, fabs(wind.f[2][0][i] - truth[i]));
                es = fmax(es, fabs(adv.f[2][1][i] - a[1][i]));
            }
    }
    CHECK(ea < 1e-4 && es < 1e-4, "advect: a cloud moving at half the wind is rebuilt half way, one at the wind too",
          "max error %.3g and %.3g", ea, es);
    CHECK(ew > 0.5, "wind: the same cloud carried at the wind's speed is far off half way", "max error %.3g", ew);
    frames_free(&adv);
    frames_free(&wind);
    for (int v = 0; v < 5; v++)
        free(a[v]), free(b[v]);
    free(truth);
    vsv_meta_clear(&m);
}

static void test_calm(void)
{
    static const char *const names[] = {VSV_WIND_U, "Q", VSV_WIND_V, "SNOW"};
    vsv_meta m;
    grid(&m, names, 4);
    float *a[4], *b[4];
    uint64_t st = 7;
    for (int v = 0; v < 4; v++) {
        a[v] = malloc(NC * sizeof(float));
        b[v] = malloc(NC * sizeof(float));
        for (int i = 0; i < NC; i++) {
            a[v][i] = (float)(vsv_test_rand(&st) % 100000) / 7;
            b[v][i] = (float)(vsv_test_rand(&st) % 100000) / 3;
        }
    }
    fill(a[0], 0), fill(b[0], 0), fill(a[2], 0), fill(b[2], 0);
    a[1][5] = NAN, b[3][77] = NAN;
    frames adv = {0, 2, {0}, {{0}}}, lin = {0, 2, {0}, {{0}}};
    run(VSV_TIME_ADVECT, &m, (const float *const *)a, (const float *const *)b, &adv);
    run(VSV_TIME_LINEAR, &m, (const float *const *)a, (const float *const *)b, &lin);
    int same = adv.n == 5 && lin.n == 5;
    for (int f = 0; same && f < 5; f++)
        same = adv.t[f] == lin.t[f] && !memcmp(adv.f[f][0], lin.f[f][0], NC * 4) &&
               !memcmp(adv.f[f][1], lin.f[f][1], NC * 4);
    CHECK(same, "advect in a calm equals linear interpolation bit for bit (NaN cells too)");
    frames wind = {0, 2, {0}, {{0}}};
    run(VSV_TIME_WIND, &m, (const float *const *)a, (const float *const *)b, &wind);
    same = wind.n == 5;
    for (int f = 0; same && f < 5; f++)
        same = !memcmp(wind.f[f][0], lin.f[f][0], NC * 4) && !memcmp(wind.f[f][1], lin.f[f][1], NC * 4);
    CHECK(same, "wind in a calm equals linear interpolation bit for bit");
    frames_free(&wind);
    CHECK(adv.n == 5 && isnan(adv.f[2][0][5]) && isnan(adv.f[2][1][77]) && adv.f[2][1][78] == lin.f[2][1][78],
          "only Q and SNOW are emitted, in order; the winds are consumed");
    frames_free(&adv);
    frames_free(&lin);
    for (int v = 0; v < 4; v++)
        free(a[v]), free(b[v]);
    vsv_meta_clear(&m);
}

static void test_meta_and_errors(void)
{
    static const char *const names[] = {"CLW", "SNOW", VSV_WIND_U, VSV_WIND_V};
    vsv_meta m, out;
    grid(&m, names, 4);
    vsv_meta_add_attr(&m, "model run", "x");
    vsv_meta_add_attr(&m, VSV_WINDS_ATTR, "U V of test");
    vsv_meta_init(&out);
    vsv_interp_opts o = {VSV_TIME_ADVECT, 1};
    vsv_interp *ip = NULL;
    frames fr = {0, 2, {0}, {{0}}};
    int rc = vsv_interp_open(600, &m, &o, keep, &fr, &ip);
    CHECK(rc == 0, "advect opens with wind.u and wind.v (no wind.w)", "%s", vsv_interp_error(ip));
    rc = vsv_interp_meta(ip, &m, &out);
    CHECK(!rc && out.nvars == 2 && !strcmp(out.vars[1].name, "SNOW") && !vsv_meta_attr(&out, VSV_WINDS_ATTR) &&
              vsv_meta_attr(&out, "model run") && vsv_meta_attr(&out, "time interpolation") &&
              strstr(vsv_meta_attr(&out, "time interpolation"), "U V of test (horizontal only)"),
          "emitted metadata: species only, the winds' origin recorded as the interpolation", "%d vars, %s", out.nvars,
          vsv_meta_attr(&out, "time interpolation") ? vsv_meta_attr(&out, "time interpolation") : "-");
    vsv_interp_free(ip);
    vsv_meta_clear(&out);
    vsv_meta_clear(&m);
    static const char *const nowind[] = {"CLW", VSV_WIND_V};
    grid(&m, nowind, 2);
    rc = vsv_interp_open(600, &m, &o, keep, &fr, &ip);
    CHECK(rc == VSV_ENOTFOUND && strstr(vsv_interp_error(ip), "no wind.u") &&
              !strstr(vsv_interp_error(ip), "no wind.v"),
          "advect without wind.u is an error naming it", "%d: %s", rc, vsv_interp_error(ip));
    vsv_interp_free(ip);
    o.method = VSV_TIME_LINEAR;
    rc = vsv_interp_open(600, &m, &o, keep, &fr, &ip);
    CHECK(rc == 0, "linear needs no winds");
    vsv_interp_free(ip);
    vsv_meta_clear(&m);
    CHECK(vsv_interp_method("advect") == VSV_TIME_ADVECT && vsv_interp_method("linear") == VSV_TIME_LINEAR &&
              vsv_interp_method("wind") == VSV_TIME_WIND && vsv_interp_method("cubic") < 0,
          "method names");
}

/* On a map projection a metre of wind is m/dx cells: on a latitude/
 * longitude grid at 60N a degree of longitude is half as long as at the
 * equator, so an east wind of 18.53 m/s crosses 12 cells of 0.1 degree in
 * an hour. */
static void test_map_scale(void)
{
    static const char *const names[] = {"CLW", VSV_WIND_U, VSV_WIND_V};
    vsv_meta m;
    grid(&m, names, 3);
    m.proj.kind = VSV_PROJ_LATLON;
    m.spacing[0] = m.spacing[1] = 0.1;
    m.origin[0] = 10, m.origin[1] = 59.7; /* row 3 at 60N */
    float *a[3], *b[3], *truth = malloc(NC * sizeof(float));
    for (int v = 0; v < 3; v++) {
        a[v] = malloc(NC * sizeof(float));
        b[v] = malloc(NC * sizeof(float));
    }
    const float u = (float)(12 * 0.1 * M_PI / 180 * 6370000 * 0.5 / 3600);
    cloud(a[0], 10, 8), cloud(b[0], 22, 8), cloud(truth, 16, 8);
    fill(a[1], u), fill(b[1], u), fill(a[2], 0), fill(b[2], 0);
    frames adv = {0, 1, {0}, {{0}}};
    run(VSV_TIME_ADVECT, &m, (const float *const *)a, (const float *const *)b, &adv);
    double e = 1;
    if (adv.n == 5) {
        e = 0;
        for (int i = 0; i < NC; i++)
            if (inside(i))
                e = fmax(e, fabs(adv.f[2][0][i] - truth[i]));
    }
    CHECK(e < 0.03, "advect on a latitude/longitude grid: the wind in m/s is scaled to degrees at 60N",
          "max error %.3g", e);
    /* where the air came from outside the grid, that end is the cell's own
     * value: at x = 2 the earlier frame's, blended with the later frame's
     * from 6 cells downwind */
    double ee = adv.n == 5 ? 0 : 1;
    for (int k = 0; adv.n == 5 && k < NZ; k++)
        for (int j = 0; j < NY; j++) {
            const int c = (k * NY + j) * NX + 2;
            ee = fmax(ee, fabs(adv.f[2][0][c] - (a[0][c] + ((double)b[0][c + 6] - a[0][c]) * 0.5)));
        }
    CHECK(ee < 1e-4, "advect: a trajectory from outside the grid takes the cell's own value for that end",
          "max error %.3g", ee);
    frames_free(&adv);
    for (int v = 0; v < 3; v++)
        free(a[v]), free(b[v]);
    free(truth);
    vsv_meta_clear(&m);
}

/* A latitude-longitude grid whose last row lies on the North Pole: its
 * cells have no width, so a wind there is (near) infinite in cells. The
 * interpolation ends (it stepped a millionth of a cell at a time there, for
 * minutes on a global grid), and the pole row, whose trajectories cannot be
 * followed, is linear interpolation's. */
static void test_pole(void)
{
    static const char *const names[] = {"CLW", VSV_WIND_U, VSV_WIND_V};
    vsv_meta m;
    grid(&m, names, 3);
    m.proj.kind = VSV_PROJ_LATLON;
    m.spacing[0] = m.spacing[1] = 2;
    m.origin[0] = 0, m.origin[1] = 90 - 2 * (NY - 1); /* row NY - 1 at 90N */
    float *a[3], *b[3];
    for (int v = 0; v < 3; v++) {
        a[v] = malloc(NC * sizeof(float));
        b[v] = malloc(NC * sizeof(float));
    }
    cloud(a[0], 10, 8), cloud(b[0], 22, 8);
    fill(a[1], 20), fill(b[1], 20), fill(a[2], 5), fill(b[2], 5);
    for (int k = 0; k < NZ; k++) /* at the pole the wind turns from cell to cell */
        for (int i = 0; i < NX; i++)
            a[1][(k * NY + NY - 1) * NX + i] = b[1][(k * NY + NY - 1) * NX + i] = i & 1 ? -20 : 20;
    frames adv = {0, 1, {0}, {{0}}};
    const int rc = run(VSV_TIME_ADVECT, &m, (const float *const *)a, (const float *const *)b, &adv);
    double e = 1;
    if (rc == 0 && adv.n == 5) {
        e = 0;
        for (int k = 0; k < NZ; k++)
            for (int i = 0; i < NX; i++) {
                const int c = (k * NY + NY - 1) * NX + i;
                e = fmax(e, fabs(adv.f[2][0][c] - (a[0][c] + ((double)b[0][c] - a[0][c]) * 0.5)));
            }
    }
    CHECK(e < 1e-6, "advect on a grid reaching the pole: it ends, the pole row linear interpolation's",
          "rc %d, %d frames, max difference %.3g", rc, adv.n, e);
    frames_free(&adv);
    for (int v = 0; v < 3; v++)
        free(a[v]), free(b[v]);
    vsv_meta_clear(&m);
}

/* Most of a hydrometeor's grid is +0, and a sample whose 8 cells are all
 * +0 is answered without reading them: the same cloud (cut at 1e-3) on a +0 background
 * and on a 1e-30 one (where that shortcut never applies), carried through a
 * sheared, turning wind, differ by no more than the background; the +0 one
 * is +0 wherever the other is at most the background. */
static void test_zero_shortcut(void)
{
    static const char *const names[] = {"ICE", "SNOW", VSV_WIND_U, VSV_WIND_V, VSV_WIND_W};
    vsv_meta m;
    grid(&m, names, 5);
    float *a[5], *b[5];
    for (int v = 0; v < 5; v++) {
        a[v] = malloc(NC * sizeof(float));
        b[v] = malloc(NC * sizeof(float));
    }
    cloud(a[0], 12, 5), cloud(b[0], 20, 9);
    for (int i = 0; i < NC; i++) {
        const int x = i % NX, k = i / (NX * NY);
        a[0][i] = a[0][i] < 1e-3f ? 0 : a[0][i], b[0][i] = b[0][i] < 1e-3f ? 0 : b[0][i];
        a[1][i] = a[0][i] + 1e-30f, b[1][i] = b[0][i] + 1e-30f;
        a[2][i] = 3 + 2 * sinf(0.3f * k), b[2][i] = 2 + cosf(0.2f * x);
        a[3][i] = 0.5f * cosf(0.4f * x), b[3][i] = -0.3f;
        a[4][i] = 0.2f * sinf(0.1f * x), b[4][i] = 0.1f;
    }
    frames fr = {0, 2, {0}, {{0}}};
    const int rc = run(VSV_TIME_WIND, &m, (const float *const *)a, (const float *const *)b, &fr);
    double e = rc || fr.n != 5 ? 1 : 0;
    int zeros = 0, bad = 0;
    for (int f = 1; f < 4 && fr.n == 5; f++)
        for (int i = 0; i < NC; i++) {
            const float z = fr.f[f][0][i], t = fr.f[f][1][i];
            e = fmax(e, fabs((double)z - t));
            if (t <= 1e-30f) {
                zeros++;
                bad += z != 0 || signbit(z);
            }
        }
    CHECK(e <= 2e-30 && zeros > NC && !bad,
          "advect: all-zero samples skipped give what sampling gives (+0 against a 1e-30 background)",
          "max difference %.3g, %d zero cells, %d not +0", e, zeros, bad);
    frames_free(&fr);
    /* fitted: the cloud runs 20 cells an hour east in a wind of 16 up to
     * the grid's east edge (alpha 1.25), so samples are carried past the
     * edge and clamped onto its cells, where the later output has cloud */
    for (int i = 0; i < NC; i++) {
        const int x = i % NX, y = i / NX % NY, k = i / (NX * NY);
        const double r0 = (x - 18.0) * (x - 18.0) + (y - 3.0) * (y - 3.0) + (k - 7.0) * (k - 7.0);
        const double r1 = (x - 38.0) * (x - 38.0) + (y - 3.0) * (y - 3.0) + (k - 7.0) * (k - 7.0);
        a[0][i] = r0 > 12 ? 0 : (float)exp(-r0 / 8), b[0][i] = r1 > 12 ? 0 : (float)exp(-r1 / 8);
        a[1][i] = a[0][i] + 1e-30f, b[1][i] = b[0][i] + 1e-30f;
        a[2][i] = b[2][i] = 16000 / 3600.0f;
        a[3][i] = b[3][i] = a[4][i] = b[4][i] = 0;
    }
    const int rc2 = run(VSV_TIME_ADVECT, &m, (const float *const *)a, (const float *const *)b, &fr);
    e = rc2 || fr.n != 5 ? 1 : 0;
    for (int f = 1; f < 4 && fr.n == 5; f++)
        for (int i = 0; i < NC; i++)
            e = fmax(e, fabs((double)fr.f[f][0][i] - fr.f[f][1][i]));
    /* half way, cell 31 of the cloud's row: its earlier end from 10 cells
     * west (cell 21), its later end from 10 east, past the edge: cell 39 */
    const int c31 = (7 * NY + 3) * NX + 31;
    const float want = (float)(a[0][c31 - 10] + ((double)b[0][c31 + 8] - a[0][c31 - 10]) * 0.5);
    const float got = fr.n == 5 ? fr.f[2][0][c31] : NAN;
    CHECK(e <= 2e-30 && fabsf(got - want) < 1e-6f,
          "advect: ... and so do samples carried past the grid's edge (a fitted scale above 1), "
          "which take the edge's values",
          "max difference %.3g; %g, not %g", e, got, want);
    frames_free(&fr);
    for (int v = 0; v < 5; v++)
        free(a[v]), free(b[v]);
    vsv_meta_clear(&m);
}

/* Trajectories are traced from every second column and row, and the cells
 * between take the mean of the 4 around them: in a wind sheared with
 * height (4 cells an hour east below level 8, 8 above) each level's
 * displacement is uniform, so every cell, traced or between, rebuilds its
 * level's cloud where it has gone, at a quarter, half and three quarters. */
static void test_coarse_shear(void)
{
    static const char *const names[] = {"CLW", VSV_WIND_U, VSV_WIND_V, VSV_WIND_W};
    vsv_meta m;
    grid(&m, names, 4);
    float *a[4], *b[4];
    for (int v = 0; v < 4; v++) {
        a[v] = malloc(NC * sizeof(float));
        b[v] = malloc(NC * sizeof(float));
    }
    /* the cloud at (12, 3, 7): a level's part moves u(k) cells in the hour */
    for (int i = 0; i < NC; i++) {
        const int x = i % NX, y = i / NX % NY, k = i / (NX * NY), u = k < 8 ? 4 : 8;
        const double r0 = (x - 12.0) * (x - 12.0) + (y - 3.0) * (y - 3.0) + (k - 7.0) * (k - 7.0);
        const double r1 = (x - 12.0 - u) * (x - 12.0 - u) + (y - 3.0) * (y - 3.0) + (k - 7.0) * (k - 7.0);
        a[0][i] = (float)exp(-r0 / 8), b[0][i] = (float)exp(-r1 / 8);
        a[1][i] = b[1][i] = u * 1000 / 3600.0f;
        a[2][i] = b[2][i] = a[3][i] = b[3][i] = 0;
    }
    frames fr = {0, 1, {0}, {{0}}};
    const int rc = run(VSV_TIME_WIND, &m, (const float *const *)a, (const float *const *)b, &fr);
    double e = rc || fr.n != 5 ? 1 : 0;
    for (int f = 1; f < 4 && fr.n == 5; f++)
        for (int i = 0; i < NC; i++) {
            const int x = i % NX, y = i / NX % NY, k = i / (NX * NY), u = k < 8 ? 4 : 8;
            const double cx = 12.0 + u * f / 4.0;
            const double r = (x - cx) * (x - cx) + (y - 3.0) * (y - 3.0) + (k - 7.0) * (k - 7.0);
            /* where neither trajectory left the grid (those ends take the cell's own value) */
            if (x > u * f / 4 && x < NX - 1 - u * (4 - f) / 4)
                e = fmax(e, fabs(fr.f[f][0][i] - exp(-r / 8)));
        }
    CHECK(e < 1e-4,
          "advect: a wind sheared with height moves each level's part of a cloud its own way, "
          "traced cells and cells between alike",
          "max error %.3g", e);
    frames_free(&fr);
    for (int v = 0; v < 4; v++)
        free(a[v]), free(b[v]);
    vsv_meta_clear(&m);
}

/* A wind that changes in time: calm at the first output, 16 cells an hour
 * east at the second, uniform in space. The air moves u(s) = 16 s cells
 * per hour at interval time s, so a parcel starting at x0 is at
 * x0 + 8 s^2 at s: the cloud at 10 at the start, 18 at the end, and half
 * way at 12 (the earlier end sampled 2 cells back, the later 6 on: whole
 * cells, so no smoothing). Midpoint steps sample the wind at each step's
 * middle time and are exact for it; at the step's start they would fall
 * short forward and overshoot back. */
static void test_wind_in_time(void)
{
    static const char *const names[] = {"CLW", VSV_WIND_U, VSV_WIND_V};
    vsv_meta m;
    grid(&m, names, 3);
    float *a[3], *b[3], *truth = malloc(NC * sizeof(float));
    for (int v = 0; v < 3; v++) {
        a[v] = malloc(NC * sizeof(float));
        b[v] = malloc(NC * sizeof(float));
    }
    cloud(a[0], 10, 8), cloud(b[0], 18, 8), cloud(truth, 12, 8);
    fill(a[1], 0), fill(b[1], 16000 / 3600.0f), fill(a[2], 0), fill(b[2], 0);
    frames fr = {0, 1, {0}, {{0}}};
    const int rc = run(VSV_TIME_WIND, &m, (const float *const *)a, (const float *const *)b, &fr);
    double e = rc || fr.n != 5 ? 1 : 0;
    for (int i = 0; fr.n == 5 && i < NC; i++)
        if (inside(i))
            e = fmax(e, fabs(fr.f[2][0][i] - truth[i]));
    CHECK(e < 1e-4,
          "advect: in a wind rising from calm to 16 cells an hour the cloud is 2 cells on half way "
          "(x0 + 8 s^2)",
          "max error %.3g", e);
    frames_free(&fr);
    for (int v = 0; v < 3; v++)
        free(a[v]), free(b[v]);
    free(truth);
    vsv_meta_clear(&m);
}

/* Linear interpolation over a second interval weighs by the time since
 * that interval's start: fields 1, 3 and 11 at 0, 1 h and 2 h give 5, 7
 * and 9 at 1:15, 1:30 and 1:45. */
static void test_linear_second_interval(void)
{
    static const char *const names[] = {"Q"};
    vsv_meta m;
    grid(&m, names, 1);
    float *f[3];
    for (int i = 0; i < 3; i++)
        f[i] = malloc(NC * sizeof(float));
    fill(f[0], 1), fill(f[1], 3), fill(f[2], 11);
    frames fr = {0, 1, {0}, {{0}}};
    vsv_interp_opts o = {VSV_TIME_LINEAR, 1};
    vsv_interp *ip = NULL;
    int rc = vsv_interp_open(900, &m, &o, keep, &fr, &ip);
    for (int i = 0; i < 3 && !rc; i++)
        rc = vsv_interp_push(ip, 3600 * i, (const float *const *)&f[i]);
    vsv_interp_free(ip);
    int ok = !rc && fr.n == 9;
    for (int s = 5; ok && s < 8; s++)
        for (int i = 0; i < NC; i++)
            ok &= fr.t[s] == 900 * s && fr.f[s][0][i] == (float)(3 + 8 * (s - 4) / 4.0);
    CHECK(ok, "linear: 1, 3, 11 at 0, 1 h, 2 h give 5, 7, 9 at 1:15, 1:30, 1:45 (weights from the interval's start)",
          "rc %d, %d frames; at 1:30 %g", rc, fr.n, fr.n == 9 ? fr.f[6][0][0] : NAN);
    frames_free(&fr);
    for (int i = 0; i < 3; i++)
        free(f[i]);
    vsv_meta_clear(&m);
}

int main(void)
{
    test_uniform_wind();
    test_linear_second_interval();
    test_wind_in_time();
    test_coarse_shear();
    test_fitted_scale();
    test_calm();
    test_zero_shortcut();
    test_meta_and_errors();
    test_map_scale();
    test_pole();
    return vsv_test_done();
}
