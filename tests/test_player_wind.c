/* test_player_wind.c — the wind in the player behind vsv-play and
 * vsv-play-freevr (issue 35): --trajectory drawn up to the step shown,
 * "wind" switching it off and on (the picture without it is the bare one),
 * "trajectory LAT LON HEIGHT" and a seed at a projected point (the wand's
 * tip) adding a path that leaves at the step shown, the seeds passed on
 * with the shared state (vsv-play-freevr's render processes), and a file
 * without wind refused. */
#include "vsv_player.h"
#include "vsv_synth.h"
#include "vsv_testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { W = 160, H = 120 };

static int act(vsv_player *p, const char *a)
{
    char err[512];
    return vsv_player_do(p, a, err, sizeof err);
}

/* The step's picture in a plan view, copied (NULL on failure). */
static unsigned char *shot(vsv_player *p)
{
    char err[512];
    vsv_camera cam;
    if (vsv_player_update(p, 0, 1))
        return NULL;
    vsv_player_camera(p, W, H, &cam);
    const unsigned char *a = vsv_player_image(p, &cam, err, sizeof err);
    unsigned char *c = a ? malloc(W * H * 3) : NULL;
    if (c)
        memcpy(c, a, W * H * 3);
    return c;
}

static int differ(const unsigned char *a, const unsigned char *b)
{
    int n = 0;
    for (int i = 0; a && b && i < W * H; i++)
        n += memcmp(a + 3 * i, b + 3 * i, 3) != 0;
    return n;
}

/* Pixels of the second path's colour (cyan: more blue than red). */
static int cyan(const unsigned char *a)
{
    int n = 0;
    for (int i = 0; a && i < W * H; i++)
        n += a[3 * i + 2] > a[3 * i] + 60;
    return n;
}

static vsv_player *open_player_barbs(const char *path, const char *traj, const char *barbs, char *err, size_t cap)
{
    vsv_player_opts o;
    vsv_player_opts_init(&o);
    o.path = path;
    o.threads = 2;
    o.renderer = VSV_RENDER_RAYCAST;
    o.species = "CLW";
    vsv_player *p = NULL;
    if (traj &&
        (vsv_player_option(&o, "trajectory", traj, err, cap) || vsv_player_option(&o, "traj-from", "0", err, cap)))
        return NULL;
    if (barbs && vsv_player_option(&o, "barbs", barbs, err, cap))
        return NULL;
    return vsv_player_open(&o, &p, err, cap) ? NULL : p;
}

static vsv_player *open_player(const char *path, const char *traj, char *err, size_t cap)
{
    return open_player_barbs(path, traj, NULL, err, cap);
}

int main(void)
{
    const char *path = vsv_test_tmp("player-wind.vsv"), *calm = vsv_test_tmp("player-nowind.vsv");
    char err[512];
    synth_wind w, wn;
    synth_wind_uniform(&w, 5, 0, 0);
    wn = w, wn.vector = 0;
    if (!CHECK(!synth_wind_write(path, &w, err, sizeof err) && !synth_wind_write(calm, &wn, err, sizeof err),
               "write the wind files", "(%s)", err))
        return vsv_test_done();
    vsv_player *p = open_player(path, "40,-100,3000", err, sizeof err);
    if (!CHECK(p != NULL, "the player opens with --trajectory", "(%s)", err))
        return vsv_test_done();
    act(p, "view plan");
    act(p, "seek 2");
    unsigned char *on = shot(p);
    act(p, "wind off");
    unsigned char *off = shot(p);
    act(p, "wind");
    unsigned char *again = shot(p);
    act(p, "seek 1");
    unsigned char *early = shot(p);
    const int n = differ(on, off), n1 = differ(early, off);
    CHECK(on && off && n > 50 && !differ(on, again), "wind off hides the path, wind brings it back",
          "(%d pixels of it)", n);
    CHECK(n1 > 20 && n1 < n * 0.7, "an hour earlier the path is shorter", "(%d pixels against %d)", n1, n);
    act(p, "seek 2");
    CHECK(act(p, "trajectory 40.1 -100 3000") == 0, "the action trajectory LAT LON HEIGHT", " ");
    unsigned char *more = shot(p);
    act(p, "seek 3");
    unsigned char *later = shot(p);
    CHECK(cyan(more) == 0 && cyan(later) > 10 && cyan(on) == 0,
          "it leaves at the step shown (the next colour, cyan: none there, some an hour on)", "(%d, %d pixels)",
          cyan(more), cyan(later));
    CHECK(act(p, "trajectory 50 -100 3000") != 0 && act(p, "trajectory 40 -100") != 0,
          "a seed outside the grid, or without a height, refused", " ");
    vsv_player_free(p);
    /* a --barbs plane above the grid's top: no arrows, the path still drawn */
    p = open_player_barbs(path, "40,-100,3000", "90000", err, sizeof err);
    unsigned char *hi = NULL;
    if (CHECK(p != NULL, "the player opens with --barbs above the top", "(%s)", err)) {
        act(p, "view plan");
        act(p, "seek 2");
        hi = shot(p);
        CHECK(hi && !differ(hi, on), "a --barbs plane with no air: the path drawn as without it", "(%d pixels differ)",
              differ(hi, on));
    }
    vsv_player_free(p);
    free(on), free(off), free(again), free(early), free(more), free(later), free(hi);
    p = open_player(calm, "40,-100,3000", err, sizeof err);
    CHECK(!p && strstr(err, "player-nowind.vsv: no wind stored"), "a file without wind refused", "(%s)", err);
    vsv_player_free(p);
    p = open_player(path, NULL, err, sizeof err); /* no wind option: a seed where the wand points */
    if (!CHECK(p && act(p, "wind") != 0, "no wind option: wind refused", " "))
        return vsv_test_done();
    const double seed[3] = {-20000, -20000, 2000}; /* projected, as from the wand's tip */
    act(p, "view plan");
    act(p, "seek 1");
    unsigned char *s1 = shot(p), *s2 = NULL, *b2 = NULL;
    CHECK(vsv_player_add_seed(p, seed, err, sizeof err) == 0, "a seed at a projected point", "(%s)", err);
    unsigned char *s1w = shot(p);
    act(p, "seek 2");
    s2 = shot(p);
    act(p, "wind off");
    b2 = shot(p);
    CHECK(s1 && s1w && !differ(s1, s1w) && differ(s2, b2) > 20, "drawn from the next step on",
          "(%d pixels at its step, %d an hour on)", differ(s1, s1w), differ(s2, b2));
    /* a render process of vsv-play-freevr: the seed comes with the state */
    act(p, "wind on");
    vsv_player_state st;
    vsv_player_state_get(p, &st);
    vsv_player *q = open_player(path, NULL, err, sizeof err);
    unsigned char *qs = NULL;
    if (q && !vsv_player_state_apply(q, &st, err, sizeof err)) {
        act(q, "view plan");
        qs = shot(q);
    }
    unsigned char *ps = shot(p);
    CHECK(st.nseeds == 1 && qs && ps && !differ(qs, ps) && differ(qs, b2) > 20,
          "another player given the state draws the same path", "(%d seeds; %s)", st.nseeds, err);
    /* the wand's tip: a world point (z exaggerated) back to projected metres and height */
    vsv_scene sc;
    vsv_player_scene(p, &sc);
    const double tip[3] = {-20000, 4000, 2500 * sc.exaggeration};
    vsv_player_state st2;
    const int rc = vsv_player_seed_world(p, tip, err, sizeof err);
    vsv_player_state_get(p, &st2);
    CHECK(!rc && st2.nseeds == 2 && st2.seeds[1][0] == -20000 && st2.seeds[1][1] == 4000 &&
              fabs(st2.seeds[1][2] - 2500) < 1e-9 && st2.seeds[1][3] == 2,
          "a seed at the wand's tip in the world: projected (-20 km, 4 km), 2500 m, at the step shown",
          "(%s; exaggeration %g)", rc ? err : "", sc.exaggeration);
    free(s1), free(s1w), free(s2), free(b2), free(qs), free(ps);
    vsv_player_free(q);
    vsv_player_free(p);
    return vsv_test_done();
}
