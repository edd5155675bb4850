/* test_viewer.c — the player behind vsv-play: the action language, the
 * status line, playback through the pager, images, shared state, the
 * camera an immersive display's matrices give, and the window count the
 * FreeVR back end reads from FreeVR's configuration. */
#include "vsv_freevr_conf.h"
#include "vsv_player.h"
#include "vsv_testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static int act(vsv_player *p, const char *a)
{
    char err[512];
    return vsv_player_do(p, a, err, sizeof err);
}

static void test_actions(vsv_player *p)
{
    char err[512], st[2048];
    vsv_player_status(p, st, sizeof st);
    CHECK(strstr(st, "1995-10-24T00:00:00Z") && strstr(st, "step 0 [0-3]") && strstr(st, "PAUSE") &&
              strstr(st, "[Q off]") && strstr(st, "CLW 1.0"),
          "status: model time, step, paused, species with opacity (water vapour hidden, as vsv-render)", "(%s)", st);
    struct {
        const char *action, *why;
    } bad[] = {{"speed 0", "non-zero"},
               {"seek 99", "out of range"},
               {"seek yesterday", "neither"},
               {"toggle NOPE", "NOPE"},
               {"opacity Q x", ">= 0"},
               {"frobnicate", "unknown action"},
               {"renderer gpu", "raycast"},
               {"camera 10", "AZ EL"},
               {"loop sometimes", "on, off"},
               {"screenshot", "FILE.png"},
               {"step many", "not a number"},
               {"zoom 0", "> 0"},
               {"seek 1995-10-25T00:00:00Z", "after the last step (steps 0..3"},
               {"seek 1995-10-23T00:00:00Z", "before the first step"},
               {"seek 0:2", "one step is wanted"},
               /* found by fuzzing (tests/corpus/player/edge-values): an int
                * conversion out of range, infinities taken as numbers */
               {"step 1e300", "not a number of steps"},
               {"speed inf", "non-zero number"},
               {"camera 10 nan", "AZ EL"},
               {"pan inf 0", "DX DY"}};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        const int rc = vsv_player_do(p, bad[i].action, err, sizeof err);
        char name[128];
        snprintf(name, sizeof name, "'%s' is refused with a reason", bad[i].action);
        CHECK(rc == -1 && strstr(err, bad[i].why), name, "(%s)", err);
    }
    act(p, "hide CLW");
    act(p, "select ICE");
    act(p, "opacity - 0.5");
    act(p, "opacity - +0.2");
    act(p, "loop bounce");
    act(p, "speed -4");
    vsv_player_status(p, st, sizeof st);
    CHECK(strstr(st, "CLW off") && strstr(st, "[ICE 0.7]") && strstr(st, "bounce") && strstr(st, "-x4"),
          "status follows hide, select, opacity (absolute and relative), loop and speed", "(%s)", st);
    act(p, "show CLW");
    act(p, "opacity ICE 1");
    act(p, "loop off");
    act(p, "speed 1");
    act(p, "select Q");
    act(p, "select -1");
    vsv_player_status(p, st, sizeof st);
    const int last = strstr(st, "[wind_up off]") != NULL; /* (the last species: the wind's, hidden) */
    act(p, "select +1");
    vsv_player_status(p, st, sizeof st);
    CHECK(last && strstr(st, "[Q off]"), "select -1 from the first species selects the last (wind_up), +1 wraps back",
          "(%s)", st);
    const char *shot = vsv_player_take_screenshot(p);
    act(p, "screenshot /tmp/x.png");
    const char *s2 = vsv_player_take_screenshot(p);
    CHECK(!shot && s2 && !strcmp(s2, "/tmp/x.png") && !vsv_player_take_screenshot(p),
          "a screenshot action is handed to the display once", " ");
    char longname[1100] = "screenshot ", err2[256] = "";
    memset(longname + 11, 'a', 1050);
    longname[1061] = 0;
    const int lrc = vsv_player_do(p, longname, err2, sizeof err2);
    CHECK(lrc != 0 && strstr(err2, "screenshot: a name of at most 1023 bytes") && !vsv_player_take_screenshot(p),
          "a screenshot name too long for the player is refused as such", "(rc %d: %s)", lrc, err2);
    act(p, "screenshot   /tmp/my shots/frame 1.png  ");
    const char *t3 = vsv_player_take_screenshot(p);
    char s3[256] = "";
    snprintf(s3, sizeof s3, "%s", t3 ? t3 : "none"); /* (the player's buffer: the next action reuses it) */
    act(p, "screenshot \"/tmp/q.png\"");
    const char *s4 = vsv_player_take_screenshot(p);
    CHECK(!strcmp(s3, "/tmp/my shots/frame 1.png") && s4 && !strcmp(s4, "/tmp/q.png"),
          "a screenshot's name is the rest of the line (blanks inside kept), quotes around it dropped", "(%s, %s)", s3,
          s4 ? s4 : "none");
    CHECK(!vsv_player_quit(p) && !act(p, "quit") && vsv_player_quit(p), "quit", " ");
}

static void test_playback(vsv_player *p)
{
    act(p, "seek 0");
    CHECK(!vsv_player_update(p, 0, 0) && vsv_player_shown_step(p) == 0, "paused at the start: step 0 shown", " ");
    act(p, "play");
    int ok = 1, last = 0;
    for (int i = 0; i < 40; i++) { /* 40 frames of 1/40 s at 4 steps a second */
        if (vsv_player_update(p, 1.0 / 40, 0))
            ok = 0;
        const int s = vsv_player_shown_step(p);
        if (s < last || s > vsv_player_clock(p)->step)
            ok = 0;
        last = s;
    }
    CHECK(ok, "playing: the shown step never runs ahead of the clock or backwards", " ");
    CHECK(!vsv_player_update(p, 0, 1) && vsv_player_shown_step(p) == 3 && !vsv_player_clock(p)->playing,
          "after a second at x1 the 4-step run has ended on its last step", "(step %d)", vsv_player_shown_step(p));
    act(p, "step -2");
    vsv_player_update(p, 0, 0);
    CHECK(vsv_player_shown_step(p) == 1, "step -2 shows step 1", "(%d)", vsv_player_shown_step(p));
    vsv_pager_stats st;
    vsv_player_pager_stats(p, &st);
    CHECK(st.bricks_decoded > 0 && st.misses > 0 && st.budget == 1 << 20,
          "playback went through the pager (a 1 MB budget, under one step)", "(decoded %llu, misses %llu)",
          (unsigned long long)st.bricks_decoded, (unsigned long long)st.misses);
}

static void test_images(vsv_player *p)
{
    char err[512];
    vsv_camera cam;
    vsv_player_camera(p, 96, 64, &cam);
    const unsigned char *a = vsv_player_image(p, &cam, err, sizeof err);
    unsigned char *first = a ? malloc(96 * 64 * 3) : NULL;
    if (!CHECK(first != NULL, "the player renders an image", "(%s)", err))
        return;
    memcpy(first, a, 96 * 64 * 3);
    act(p, "opacity Q 0");
    act(p, "opacity CLW 4");
    const unsigned char *b = vsv_player_image(p, &cam, err, sizeof err);
    CHECK(b && memcmp(first, b, 96 * 64 * 3), "changing opacities changes the image", " ");
    act(p, "opacity Q 1");
    act(p, "opacity CLW 1");
    const unsigned char *c = vsv_player_image(p, &cam, err, sizeof err);
    CHECK(c && !memcmp(first, c, 96 * 64 * 3), "and setting them back gives the same image", " ");
    act(p, "renderer raycast");
    const unsigned char *d = vsv_player_image(p, &cam, err, sizeof err);
    CHECK(d && memcmp(first, d, 96 * 64 * 3), "the raycaster draws the same scene (not byte for byte)", " ");
    act(p, "renderer shearwarp");
    free(first);
}

static void test_state(vsv_player *p, const char *path)
{
    vsv_player_opts o;
    vsv_player_opts_init(&o);
    o.path = path;
    o.clock_only = 1;
    vsv_player *q = NULL;
    char err[512], a[2048], b[2048];
    if (!CHECK(vsv_player_open(&o, &q, err, sizeof err) == 0, "a clock-only player opens", "(%s)", err))
        return;
    act(q, "seek 2");
    act(q, "hide RNW");
    act(q, "opacity SNOW 0.3");
    act(q, "select SNOW");
    act(q, "speed 8");
    vsv_player_state st;
    vsv_player_state_get(q, &st);
    CHECK(!vsv_player_state_apply(p, &st, err, sizeof err) && !vsv_player_update(p, 0, 1) &&
              vsv_player_shown_step(p) == 2,
          "state handed from an input process is shown by a display process", "(%s)", err);
    vsv_player_status(p, a, sizeof a);
    vsv_player_status(q, b, sizeof b);
    CHECK(!strcmp(a, b), "both show the same status line", "(%s | %s)", a, b);
    /* a step past either end (another file's, a torn copy) is clamped to the steps there are */
    st.step = vsv_player_clock(p)->nsteps;
    int rc = vsv_player_state_apply(p, &st, err, sizeof err), step = vsv_player_clock(p)->step;
    CHECK(!rc && step == 3 && !vsv_player_update(p, 0, 1) && vsv_player_shown_step(p) == 3,
          "a state's step 4 of 4 steps is shown as the last, step 3", "(%d)", step);
    st.step = -1;
    rc = vsv_player_state_apply(p, &st, err, sizeof err), step = vsv_player_clock(p)->step;
    CHECK(!rc && step == 0, "a state's step -1 is shown as step 0", "(%d)", step);
    vsv_player_free(q);
}

/* An eye whose matrices FreeVR would load: the camera derived from them
 * sits at that eye, looks where it looks, with its off-axis window. */
static void test_camera_from_gl(vsv_player *p)
{
    const double at[3] = {0, 4, -3}, size = 8;
    double mn[3], mx[3];
    vsv_player_bounds(p, mn, mx);
    const double k = size / fmax(mx[0] - mn[0], mx[1] - mn[1]);
    /* eye at (1, 5.5, 2) feet looking along -z (into the front wall), y up */
    const double eye[3] = {1, 5.5, 2};
    const double MV[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -eye[0], -eye[1], -eye[2], 1};
    const double l = -0.7, r = 0.4, b = -0.5, t = 0.3, n = 0.1, f = 100;
    const double P[16] = {2 * n / (r - l),
                          0,
                          0,
                          0,
                          0,
                          2 * n / (t - b),
                          0,
                          0,
                          (r + l) / (r - l),
                          (t + b) / (t - b),
                          -(f + n) / (f - n),
                          -1,
                          0,
                          0,
                          -2 * f * n / (f - n),
                          0};
    vsv_camera cam;
    /* the scene k feet a metre, its box's centre at `at` */
    const double c0[3] = {0.5 * (mn[0] + mx[0]), 0.5 * (mn[1] + mx[1]), 0.5 * (mn[2] + mx[2])};
    const double place[16] = {
        k, 0, 0, 0, 0, 0, -k, 0, 0, k, 0, 0, at[0] - k * c0[0], at[1] - k * c0[2], at[2] + k * c0[1], 1};
    vsv_player_camera_from_gl(place, P, MV, 200, 100, &cam);
    /* the eye in world metres: east = x, north = -z, up = y */
    const double cx = 0.5 * (mn[0] + mx[0]), cy = 0.5 * (mn[1] + mx[1]), cz = 0.5 * (mn[2] + mx[2]);
    const double want[3] = {cx + (eye[0] - at[0]) / k, cy - (eye[2] - at[2]) / k, cz + (eye[1] - at[1]) / k};
    double err = 0;
    for (int i = 0; i < 3; i++)
        err = fmax(err, fabs(cam.pos[i] - want[i]));
    const double dl = sqrt(cam.dir[0] * cam.dir[0] + cam.dir[1] * cam.dir[1] + cam.dir[2] * cam.dir[2]);
    CHECK(err < 1e-6 * (mx[0] - mn[0]), "the eye's position in world metres", "(off by %g m)", err);
    CHECK(fabs(cam.dir[1] / dl - 1) < 1e-9 && fabs(cam.up[2]) > 0 && fabs(cam.up[0]) < 1e-12,
          "looking into the front wall is looking north, up is up", "(dir %g %g %g)", cam.dir[0], cam.dir[1],
          cam.dir[2]);
    CHECK(fabs(cam.window[0] - l / n) < 1e-9 && fabs(cam.window[1] - r / n) < 1e-9 &&
              fabs(cam.window[2] - b / n) < 1e-9 && fabs(cam.window[3] - t / n) < 1e-9,
          "the off-axis window comes from the frustum", "(%g %g %g %g)", cam.window[0], cam.window[1], cam.window[2],
          cam.window[3]);
    /* and the renderer takes it: an off-axis view renders */
    char e[256];
    CHECK(vsv_player_image(p, &cam, e, sizeof e) != NULL, "an off-axis camera renders", "(%s)", e);
}

/* FreeVR configurations in FreeVR's syntax, read in FreeVR's order. */
static void test_freevr_layout(void)
{
    vsv_freevr_layout l;
    vsv_freevr_layout_count(NULL, 0, &l);
    CHECK(l.windows == 1 && l.visren == 1 && !l.explicit, "no configuration: FreeVR's simulator, one window", "(%d %d)",
          l.windows, l.visren);
    const char *cave =
        "# four walls\n"
        "system \"cave\" = { type = \"cave\"; procs = \"pf\", \"pl\", \"pr\", \"pb\", \"pin\"; }\n"
        "window \"front\" = { mount = \"fixed\"; args = \"geometry=300x300+320+10; decoration=window\";\n"
        "  rw2w_coords = -5,0,-5, 5,0,-5, -5,10,-5; }\n"
        "process \"pf\" = { type = visren; objects = \"front\"; }\n"
        "process \"pl\" = { type = visren; objects = \"left\"; }\n"
        "process \"pr\" = { type = visren; objects = \"right\"; }\n"
        "process \"pb\" = { type = \"visren\"; objects = \"floor\"; } // the floor\n"
        "process \"pin\" = { type = input; usecmin = 15000; objects = \"xin\"; }\n"
        "inputdevice \"xin\" = { type = \"xwindows\"; input \"Escape Key\" = \"2switch(keyboard:key[Escape])\"; }\n";
    const char *texts[3] = {cave, NULL, "usesystem \"cave\";"};
    vsv_freevr_layout_count(texts, 3, &l);
    CHECK(l.windows == 4 && l.visren == 4 && l.explicit, "a four-wall system chosen by a later string: 4 and 4",
          "(%d %d %d)", l.windows, l.visren, l.explicit);
    const char *more[3] = {cave, "usesystem \"cave\"; process \"pb\" = { type = visren; objects = \"floor, ceil\"; }",
                           "process \"pl\" = { type = input; }"};
    vsv_freevr_layout_count(more, 3, &l);
    CHECK(l.windows == 4 && l.visren == 3, "later definitions override: two windows in one process, one not visren",
          "(%d %d)", l.windows, l.visren);
    const char *nosys[1] = {"usesystem \"none\"; window \"a\" = {} window \"b\" = {}\n"
                            "process \"p\" = { type = visren; objects = \"a\"; }"};
    vsv_freevr_layout_count(nosys, 1, &l);
    CHECK(l.windows == 2 && l.visren == 1 && !l.explicit, "an unknown system: a bound from every definition", "(%d %d)",
          l.windows, l.visren);
    l = (vsv_freevr_layout){.windows = 8, .visren = 8, .explicit = 1};
    CHECK(vsv_freevr_arena_bytes(&l, 1000) == 16ul << 20, "eight windows: FreeVR's default arena, 16 MiB", " ");
    l = (vsv_freevr_layout){.windows = 100, .visren = 100, .explicit = 1};
    CHECK(vsv_freevr_arena_bytes(&l, 1000) == (1ul << 20) + 100 * (256ul << 10) + 1000,
          "a hundred windows: 1 MiB + 256 KiB a window", " ");
}

/* A copy of path with step 2's chunk index damaged (its checksum fails):
 * the player reports it once, on screen and through vsv_player_damage, and
 * plays on past it (it exited with the error before; issue 18). */
static void test_damaged(const char *path, vsv_player_opts o)
{
    const char *bad = vsv_test_tmp("viewer-damaged.vsv");
    FILE *fp = fopen(path, "rb");
    static unsigned char d[1 << 21];
    const size_t n = fp ? fread(d, 1, sizeof d, fp) : 0;
    if (fp)
        fclose(fp);
    uint64_t toc = 0, off = 0;
    memcpy(&toc, d + 48, 8); /* (little-endian hosts) */
    if (toc + 72 <= n)
        memcpy(&off, d + toc + 48, 8);
    if (!CHECK(n > 0 && n < sizeof d && off + 29 <= n, "a copy to damage", "(%zu bytes)", n))
        return;
    d[off + 28] ^= 0xff;
    fp = fopen(bad, "wb");
    CHECK(fp && fwrite(d, 1, n, fp) == n && !fclose(fp), "the damaged copy written", " ");
    o.path = bad;
    vsv_player *p = NULL;
    char err[512], status[2048];
    if (!CHECK(vsv_player_open(&o, &p, err, sizeof err) == 0, "the player opens the damaged copy", "(%s)", err))
        return;
    const char *why = NULL;
    CHECK(!vsv_player_do(p, "seek 1", err, sizeof err) && !vsv_player_update(p, 0, 1) &&
              vsv_player_shown_step(p) == 1 && vsv_player_damage(p, &why) == -1,
          "step 1 shows, nothing damaged", " ");
    const int rc = !vsv_player_do(p, "seek 2", err, sizeof err) ? vsv_player_update(p, 0, 1) : -2;
    CHECK(rc == 0, "the damaged step is not an error of update", "(%d: %s)", rc, vsv_player_error(p));
    const int t = vsv_player_damage(p, &why);
    CHECK(t == 2 && why && strstr(why, bad) && strstr(why, "chunk 2"), "reported once: the file and the step",
          "(step %d: %s)", t, why ? why : "-");
    CHECK(vsv_player_damage(p, NULL) == -1, "and only once", " ");
    vsv_player_status(p, status, sizeof status);
    CHECK(vsv_player_shown_step(p) == 2 && strstr(status, "step 2 DAMAGED, not drawn") && strstr(status, "chunk 2"),
          "the status line says it", "(%s)", status);
    vsv_camera cam;
    vsv_player_camera(p, 64, 48, &cam);
    CHECK(vsv_player_image(p, &cam, err, sizeof err) != NULL, "the damaged step draws (nothing of it)", "(%s)", err);
    CHECK(!vsv_player_update(p, 0, 1) && vsv_player_damage(p, NULL) == -1, "paused on it: not reported again", " ");
    /* step 3 keeps bricks of step 2 (UNCHANGED): it cannot be drawn either,
     * and says so naming chunk 2 */
    CHECK(!vsv_player_do(p, "seek 3", err, sizeof err) && !vsv_player_update(p, 0, 1) &&
              vsv_player_shown_step(p) == 3 && vsv_player_damage(p, &why) == 3 && strstr(why, "chunk 2"),
          "step 3, which keeps bricks of step 2, is reported too", "(%s)", why ? why : "-");
    CHECK(!vsv_player_do(p, "seek 0", err, sizeof err) && !vsv_player_update(p, 0, 1) &&
              vsv_player_shown_step(p) == 0 && vsv_player_damage(p, NULL) == -1,
          "step 0 shows", " ");
    vsv_player_status(p, status, sizeof status);
    CHECK(!strstr(status, "DAMAGED"), "and the status no longer says damaged", "(%s)", status);
    /* playing through from the start: the damaged steps pass, the end is reached */
    vsv_player_do(p, "play", err, sizeof err);
    const vsv_clock *c = vsv_player_clock(p);
    const double dt = (double)(c->times[1] - c->times[0]) / c->rate / 4;
    int fails = 0, i = 0;
    for (; i < 400 && c->playing; i++)
        fails += vsv_player_update(p, dt, 0) != 0;
    CHECK(!fails && vsv_player_shown_step(p) == 3, "playing through it reaches the last step",
          "(%d failed updates, step %d after %d ticks)", fails, vsv_player_shown_step(p), i);
    vsv_player_free(p);
}

/* Waits until the pager's workers stop decoding (no new payload for 60 ms;
 * at most 10 s). */
static void settle(vsv_player *p)
{
    vsv_pager_stats st;
    uint64_t last = UINT64_MAX;
    for (int quiet = 0, i = 0; quiet < 3 && i < 500; i++) {
        vsv_player_pager_stats(p, &st);
        quiet = st.payloads_decoded == last ? quiet + 1 : 0;
        last = st.payloads_decoded;
        usleep(20000);
    }
}

/* Playing 1.25 steps a frame on a budget that holds one step beside the one
 * shown: the step decoded ahead is the one the next frame shows (the clock
 * predicts it), so the frames that jump over a step never find it missing.
 * (Decoding the next step in order instead, a quarter of the frames stall.) */
static void test_skipping(const char *path, vsv_player_opts o)
{
    o.path = path;
    o.species = "Q,CLW,RNW,ICE,SNOW";
    o.cache_bytes = (size_t)1 << 30;
    vsv_player *p = NULL;
    char err[512];
    if (!CHECK(vsv_player_open(&o, &p, err, sizeof err) == 0, "the player opens the 5-minute series", "(%s)", err))
        return;
    const int nsteps = vsv_player_clock(p)->nsteps;
    const double interval = (double)(vsv_player_clock(p)->times[1] - vsv_player_clock(p)->times[0]);
    size_t step = 0; /* the largest step's decoded bytes */
    for (int t = 0; t < nsteps; t++) {
        char a[32];
        snprintf(a, sizeof a, "seek %d", t);
        act(p, a);
        vsv_player_update(p, 0, 1);
        vsv_pager_stats st;
        vsv_player_pager_stats(p, &st);
        step = st.pinned_bytes > step ? st.pinned_bytes : step;
    }
    vsv_player_free(p);
    o.cache_bytes = step * 7 / 2;
    o.rate = 1.25 * interval * 30; /* 1.25 steps a frame at 30 frames a second */
    if (!CHECK(vsv_player_open(&o, &p, err, sizeof err) == 0, "the player opens it on 3.5 steps' bytes", "(%s)", err))
        return;
    vsv_player_update(p, 0, 1);
    settle(p);
    act(p, "play");
    int frames = 0, behind = 0, depth = 0;
    vsv_pager_stats st0, st;
    vsv_player_pager_stats(p, &st0);
    while (vsv_player_clock(p)->playing && frames < 100) {
        vsv_player_update(p, 1.0 / 30, 0);
        frames++;
        behind += vsv_player_shown_step(p) != vsv_player_clock(p)->step;
        vsv_player_pager_stats(p, &st);
        depth = st.prefetch_depth > depth ? st.prefetch_depth : depth;
        settle(p);
    }
    vsv_player_pager_stats(p, &st);
    CHECK(depth == 1 && frames >= 25, "1.25 steps a frame with one step decoded ahead",
          "(depth %d, %d frames, %zu bytes a step)", depth, frames, step);
    CHECK(st.stalls == st0.stalls && behind == 0,
          "a frame that jumps over a step finds the step it shows decoded (no stall)",
          "(%llu stalls in %d frames; %d behind the clock)", (unsigned long long)(st.stalls - st0.stalls), frames,
          behind);
    vsv_player_free(p);
}

/* Frames that draw take 0.1 s at x8 (3.2 steps), one in ten 0.02 s (a
 * cheap picture); a frame that finds nothing new to draw, 0.01 s. The
 * stride follows the drawing frames (2: even steps shown), not the mean of
 * all, which the quick idle frames after a cheap picture pull down */
static void test_idle_frames(const char *path, vsv_player_opts o)
{
    o.path = path;
    o.cache_bytes = (size_t)1 << 30;
    vsv_player *p = NULL;
    char err[512];
    if (!CHECK(vsv_player_open(&o, &p, err, sizeof err) == 0, "the player opens the 5-minute series", "(%s)", err))
        return;
    vsv_player_update(p, 0, 1);
    act(p, "loop on");
    act(p, "speed 8");
    act(p, "play");
    vsv_camera cam;
    vsv_player_camera(p, 48, 32, &cam);
    double dur = 0.1;
    int odd = 0, idle = 0, drawn = 0, last = -1;
    for (int f = 0; f < 200; f++) {
        vsv_player_update(p, dur, 0);
        odd += f >= 20 && vsv_player_target_step(p) % 2;
        vsv_player_image(p, &cam, err, sizeof err);
        const int shown = vsv_player_shown_step(p), drew = shown != last;
        last = shown;
        drawn += drew, idle += !drew;
        dur = !drew ? 0.01 : drawn % 10 ? 0.1 : 0.02;
    }
    CHECK(odd == 0 && idle >= 20 && drawn >= 20,
          "drawing frames of 3.2 steps, quick idle ones between: every other step shown",
          "(%d odd steps meant, %d idle frames, %d drawn)", odd, idle, drawn);
    vsv_player_free(p);
}

int main(void)
{
    test_freevr_layout();
    const char *path = vsv_test_tmp("viewer-crop.vsv");
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "%s/vsv-convert -q samples/mm5/MMOUT_DOMAIN1_CROP -o %s",
             getenv("B") ? getenv("B") : "build", path);
    if (!CHECK(system(cmd) == 0, "convert the bundled MM5 sample", " "))
        return vsv_test_done();
    vsv_player_opts o;
    vsv_player_opts_init(&o);
    o.path = path;
    o.cache_bytes = 1 << 20; /* smaller than one step */
    o.threads = 2;
    vsv_player *p = NULL;
    char err[512];
    if (!CHECK(vsv_player_open(&o, &p, err, sizeof err) == 0, "the player opens the sample", "(%s)", err))
        return vsv_test_done();
    test_actions(p);
    test_playback(p);
    test_images(p);
    test_state(p, path);
    test_camera_from_gl(p);
    vsv_player_free(p);
    test_damaged(path, o);
    const char *path5 = vsv_test_tmp("viewer-crop-5m.vsv");
    snprintf(cmd, sizeof cmd, "%s/vsv-convert -q --time-res 5m samples/mm5/MMOUT_DOMAIN1_CROP -o %s",
             getenv("B") ? getenv("B") : "build", path5);
    if (CHECK(system(cmd) == 0, "convert the bundled MM5 sample at 5-minute steps", " "))
        test_skipping(path5, o), test_idle_frames(path5, o);
    o.path = "/nonexistent/x.vsv";
    CHECK(vsv_player_open(&o, &p, err, sizeof err) == -1 && strstr(err, "/nonexistent/x.vsv"),
          "a missing file is an error naming it", "(%s)", err);
    vsv_player_free(p);
    return vsv_test_done();
}
