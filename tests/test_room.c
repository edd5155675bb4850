/* test_room.c — what the FreeVR back end is built from, without FreeVR: the
 * room (one decoded copy in shared memory, read by forked processes, and
 * the tick every window must show before the next), the placements and
 * navigation in closed form, the wand's map, the room and pixel density
 * read from FreeVR's configuration, and the in-room legend. */
#include "vsv_freevr_conf.h"
#include "vsv_place.h"
#include "vsv_player.h"
#include "vsv_room.h"
#include "vsv_testlib.h"
#include "vsv_wand.h"

#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

static int near3(const double a[3], double x, double y, double z, double tol)
{
    return fabs(a[0] - x) <= tol && fabs(a[1] - y) <= tol && fabs(a[2] - z) <= tol;
}

/* ------------------------------------------------------------ placement */

static void test_place(void)
{
    const double lo[3] = {-5, 0, -5}, hi[3] = {5, 10, 5};
    /* a domain 4000 km east-west, 3000 km north-south, 0..20 km up */
    const double mn[3] = {-2e6, -1.5e6, 0}, mx[3] = {2e6, 1.5e6, 2e4};
    double M[16], p[3];
    vsv_place_base(VSV_PLACE_TABLE, lo, hi, mn, mx, M);
    const double k = 6.0 / 4e6; /* 0.6 of the 10-foot side over 4000 km */
    vsv_mat4_point(M, (const double[3]){0, 0, 0}, p);
    CHECK(near3(p, 0, 3, -1.5, 1e-9), "table: the domain's centre at sea level on the tabletop, 3 ft up, 1.5 ft ahead",
          "(%g %g %g)", p[0], p[1], p[2]);
    vsv_mat4_point(M, (const double[3]){2e6, 1.5e6, 2e4}, p);
    CHECK(near3(p, 3, 3 + k * 2e4, -1.5 - k * 1.5e6, 1e-9), "table: 6 ft wide, east is +x, north is -z, up is +y",
          "(%g %g %g)", p[0], p[1], p[2]);
    vsv_place_base(VSV_PLACE_ROOM, lo, hi, mn, mx, M);
    double q[3];
    vsv_mat4_point(M, (const double[3]){0, 0, 0}, p);
    vsv_mat4_point(M, (const double[3]){1e5, 0, 2e4}, q);
    CHECK(near3(p, 0, 0, 0, 1e-9) && fabs(q[1] - 10) < 1e-9 && fabs(q[0] - 1e5 * 10 / 2e4) < 1e-9,
          "room: the ground on the floor, the top at the ceiling, one scale for every axis", "(%g %g %g)", q[0], q[1],
          q[2]);
    /* a room of other walls: relative to its floor and box, not to 0 */
    const double lo2[3] = {0, 1, 0}, hi2[3] = {8, 9, 12};
    vsv_place_base(VSV_PLACE_TABLE, lo2, hi2, mn, mx, M);
    vsv_mat4_point(M, (const double[3]){0, 0, 0}, p);
    CHECK(near3(p, 4, 4, 6 - 0.15 * 12, 1e-9), "table: centred in a room of other walls, 3 ft above its floor",
          "(%g %g %g)", p[0], p[1], p[2]);

    double N[16];
    vsv_nav_identity(N);
    vsv_nav_travel(N, (const double[3]){0, 0, -2});
    vsv_mat4_point(N, (const double[3]){1, 2, 3}, p);
    CHECK(near3(p, 1, 2, 5, 1e-12), "travel 2 ft towards the front wall: the scene comes 2 ft nearer", "(%g %g %g)",
          p[0], p[1], p[2]);
    vsv_nav_identity(N);
    vsv_nav_turn(N, (const double[3]){0, 5, 0}, 90);
    vsv_mat4_point(N, (const double[3]){0, 4, -1}, p);
    CHECK(near3(p, 1, 4, 0, 1e-12), "turning left 90 degrees: what was ahead is on the right", "(%g %g %g)", p[0], p[1],
          p[2]);
    vsv_nav_identity(N);
    vsv_nav_scale(N, (const double[3]){1, 0, 0}, 2);
    vsv_mat4_point(N, (const double[3]){2, 1, 0}, p);
    CHECK(near3(p, 3, 2, 0, 1e-12), "scaling by 2 about the wand's tip keeps the tip in place", "(%g %g %g)", p[0],
          p[1], p[2]);
    vsv_nav_travel(N, (const double[3]){1, 2, 3});
    vsv_nav_turn(N, (const double[3]){0, 0, 0}, 33);
    vsv_nav_identity(N);
    vsv_mat4_point(N, (const double[3]){2, 1, 0}, p);
    CHECK(near3(p, 2, 1, 0, 0), "reset: exactly where it started", "(%g %g %g)", p[0], p[1], p[2]);
    double A[16], Ai[16], I[16];
    vsv_place_base(VSV_PLACE_TABLE, lo, hi, mn, mx, A);
    vsv_nav_turn(A, (const double[3]){0, 0, 0}, 20);
    CHECK(vsv_mat4_invert(A, Ai), "a placement inverts", " ");
    vsv_mat4_mul(A, Ai, I);
    double err = 0;
    for (int i = 0; i < 16; i++)
        err = fmax(err, fabs(I[i] - (i % 5 == 0)));
    CHECK(err < 1e-9, "placement times its inverse is the identity", "(off by %g)", err);
}

/* ----------------------------------------------------------------- wand */

static void wand(vsv_wand *w, int b1, int b2, int b3, float jx, float jy, vsv_wand_out *o)
{
    vsv_wand_in in;
    memset(&in, 0, sizeof in);
    in.sw[1] = b1, in.sw[2] = b2, in.sw[3] = b3;
    in.jx = jx, in.jy = jy;
    in.dt = 0.1;
    vsv_wand_update(w, &in, o);
}

static int has_act(const vsv_wand_out *o, const char *a)
{
    for (int i = 0; i < o->nact; i++)
        if (!strcmp(o->act[i], a))
            return 1;
    return 0;
}

static void test_wand(void)
{
    vsv_wand w;
    vsv_wand_out o;
    vsv_wand_init(&w, 4);
    wand(&w, 1, 0, 0, 0, 0, &o);
    CHECK(o.nact == 0, "button 1 pressed: nothing yet (its action is on release)", "(%d)", o.nact);
    wand(&w, 0, 0, 0, 0, 0, &o);
    CHECK(o.nact == 1 && has_act(&o, "toggle-play"), "button 1 released: play / pause", "(%d)", o.nact);
    wand(&w, 0, 0, 0, 0, 1, &o);
    CHECK(fabs(o.travel - 0.4) < 1e-12 && o.turn == 0 && o.scale == 1,
          "joystick up alone: travel at 4 ft/s (0.4 ft in 0.1 s)", "(%g)", o.travel);
    wand(&w, 0, 0, 0, 0, -1, &o);
    CHECK(fabs(o.travel + 0.4) < 1e-12 && o.turn == 0, "joystick down alone: travel back at 4 ft/s (-0.4 ft in 0.1 s)",
          "(%g)", o.travel);
    wand(&w, 0, 0, 0, -1, 0, &o);
    CHECK(fabs(o.turn - 4.5) < 1e-12 && o.travel == 0, "joystick left: turn left, 45 degrees a second", "(%g)", o.turn);
    wand(&w, 0, 0, 0, 0.1f, -0.1f, &o);
    CHECK(o.travel == 0 && o.turn == 0, "inside the dead zone: nothing", "(%g %g)", o.travel, o.turn);
    wand(&w, 0, 0, 0, 1, 0, &o);
    CHECK(fabs(o.turn + 4.5) < 1e-12, "joystick right: turn right, 45 degrees a second", "(%g)", o.turn);
    wand(&w, 1, 0, 0, 0, 1, &o);
    CHECK(fabs(o.scale - pow(2, 0.1)) < 1e-12 && o.travel == 0, "button 1 held, joystick up: scale up, x2 a second",
          "(%g)", o.scale);
    wand(&w, 0, 0, 0, 0, 0, &o);
    CHECK(o.nact == 0, "button 1 used with the joystick: no play / pause on release", "(%d)", o.nact);
    wand(&w, 1, 0, 0, 0, 0, &o);
    wand(&w, 1, 1, 0, 0, 0, &o);
    CHECK(o.reset == 1, "buttons 1 and 2 together: reset", " ");
    wand(&w, 1, 1, 0, 0, 0, &o);
    CHECK(o.reset == 0, "held on: reset once", " ");
    wand(&w, 0, 0, 0, 0, 0, &o);
    CHECK(o.nact == 0, "the chord's buttons do nothing else on release", "(%d)", o.nact);
    wand(&w, 0, 0, 1, 0, 0, &o);
    wand(&w, 0, 0, 1, 0.9f, 0, &o);
    CHECK(has_act(&o, "step +1"), "button 3 held, a flick right: a step forward", " ");
    wand(&w, 0, 0, 1, 1, 0, &o);
    CHECK(o.nact == 0, "the stick held over: one step only", "(%d)", o.nact);
    wand(&w, 0, 0, 1, 0, 0, &o);
    wand(&w, 0, 0, 1, 0, -0.95f, &o);
    CHECK(has_act(&o, "slower"), "a flick down: slower", " ");
    wand(&w, 0, 0, 1, 0, 0, &o);
    wand(&w, 1, 0, 1, 0, 0, &o);
    wand(&w, 0, 0, 1, 0, 0, &o);
    CHECK(has_act(&o, "start"), "button 1 clicked under button 3: the start", " ");
    wand(&w, 0, 0, 0, 0, 0, &o);
    CHECK(o.nact == 0, "button 3 used: no show / hide on its release", "(%d)", o.nact);
    wand(&w, 0, 0, 1, 0, 0, &o);
    wand(&w, 0, 0, 0, 0, 0, &o);
    CHECK(has_act(&o, "toggle"), "button 3 clicked: show / hide the species", " ");
    wand(&w, 0, 1, 0, 0, 0, &o);
    wand(&w, 0, 1, 0, 0, 1, &o);
    CHECK(has_act(&o, "opacity - +0.01"), "button 2 held, joystick up: opacity up", " ");
    wand(&w, 0, 0, 0, 0, 0, &o);
    CHECK(o.nact == 0, "button 2 used: no next species on release", "(%d)", o.nact);
    vsv_wand_in in;
    memset(&in, 0, sizeof in);
    const char *keys[] = {"step +1", "step -1", "start", "end", "faster", "slower"};
    for (int k = 4; k <= 9; k++) {
        in.sw[k] = 1;
        vsv_wand_update(&w, &in, &o);
        in.sw[k] = 0;
        vsv_wand_update(&w, &in, &o);
        char name[64];
        snprintf(name, sizeof name, "switch %d: %s", k, keys[k - 4]);
        in.sw[k] = 1;
        vsv_wand_update(&w, &in, &o);
        CHECK(o.nact == 1 && !strcmp(o.act[0], keys[k - 4]), name, "(%d)", o.nact);
        in.sw[k] = 0;
        vsv_wand_update(&w, &in, &o);
    }
    in.sw[10] = 1;
    vsv_wand_update(&w, &in, &o);
    CHECK(o.reset, "switch 10: reset the view", " ");
    in.sw[10] = 0, in.sw[11] = 1;
    vsv_wand_update(&w, &in, &o);
    CHECK(o.place, "switch 11: table / room", " ");
    in.sw[11] = 0, in.sw[12] = 1;
    vsv_wand_update(&w, &in, &o);
    CHECK(has_act(&o, "loop"), "switch 12: loop", " ");
    in.sw[12] = 0, in.sw[13] = 1;
    vsv_wand_update(&w, &in, &o);
    CHECK(o.seed && !o.nact, "switch 13: a trajectory from the wand's tip", " ");
    vsv_wand_update(&w, &in, &o);
    CHECK(!o.seed, "held on: one trajectory", " ");
}

/* ------------------------------------------------------- configuration */

static void test_conf(void)
{
    vsv_freevr_layout l;
    const char *cave = "system \"cave\" = { procs = \"pf\", \"pb\"; }\n"
                       "window \"front\" = { mount = \"fixed\"; args = \"geometry=200x200+0+0\";\n"
                       "  rw2w_coords = -5,0,-5, 5,0,-5, -5,10,-5; }\n"
                       "window \"floor\" = { mount = \"fixed\"; args = \"geometry=1024x512+0+0\";\n"
                       "  rw2w_coords = -5,0,5, 5,0,5, -5,0,-5; }\n"
                       "process \"pf\" = { type = visren; objects = \"front\"; }\n"
                       "process \"pb\" = { type = visren; objects = \"floor\"; }\n"
                       "usesystem \"cave\";";
    const char *t1[1] = {cave};
    vsv_freevr_layout_count(t1, 1, &l);
    CHECK(l.walls == 2 && near3(l.room_lo, -5, 0, -5, 0) && near3(l.room_hi, 5, 10, 5, 0),
          "the room is the box of the walls' corners", "(%d walls; %g %g %g .. %g %g %g)", l.walls, l.room_lo[0],
          l.room_lo[1], l.room_lo[2], l.room_hi[0], l.room_hi[1], l.room_hi[2]);
    CHECK(fabs(l.px_per_ft - 20) < 1e-9, "the lowest pixel density: 200 px over 10 ft", "(%g)", l.px_per_ft);
    CHECK(!l.missing[0], "a defined system is not missing", "(%s)", l.missing);
    const char *t2[2] = {cave, "usesystem \"cave9\";"};
    vsv_freevr_layout_count(t2, 2, &l);
    CHECK(!strcmp(l.missing, "cave9"), "a system no text defines is missing, by name", "(%s)", l.missing);
    const char *t3[2] = {cave, "usesystem \"simulator\";"};
    vsv_freevr_layout_count(t3, 2, &l);
    CHECK(!l.missing[0] && l.walls == 0 && near3(l.room_hi, 5, 10, 5, 0),
          "FreeVR's simulator: not missing, FreeVR's default 10-foot room", "(%s)", l.missing);
}

/* ------------------------------------------------------------------ room */

/* A child: joins as window `name`, starts two frames, then reports the
 * tick, step and the value at cell (i, j, k) of species s it reads
 * through the room; exits with 0 when the value matches `want`. */
static int child(vsv_room *r, const char *name, int s, int i, int j, int k, float want, int pipe_w)
{
    const int w = vsv_room_join(r, name);
    vsv_room_view v;
    for (int f = 0; f < 200 && vsv_room_frame(r, w, &v); f++)
        usleep(10000);
    usleep(20000);
    if (vsv_room_frame(r, w, &v))
        return 2;
    const vsv_volume *vol = v.vols[s];
    const float got = vol ? vsv_volume_at(vol, i, j, k) : -1;
    char line[128];
    const int n = snprintf(line, sizeof line, "%s %lld %d %.9g\n", name, (long long)v.tick, v.step, got);
    if (write(pipe_w, line, (size_t)n) != n)
        return 3;
    /* stay a while, drawing frames of whatever is newest */
    for (int f = 0; f < 30; f++) {
        usleep(10000);
        vsv_room_frame(r, w, &v);
    }
    return got == want ? 0 : 1;
}

/* A cell of species s with cloud water in it, and its value (0 if none). */
typedef struct {
    int s, i, j, k;
    float want;
} cloudy_cell;

/* The first cell of cur with cloud water in it, in storage order. */
static void find_cloudy(const vsv_volume *cur, cloudy_cell *c)
{
    int ci = 0, cj = 0, ck = 0;
    float want = 0;
    for (int k = 0; k < cur->nz && want == 0; k++)
        for (int j = 0; j < cur->ny && want == 0; j++)
            for (int i = 0; i < cur->nx && want == 0; i++)
                if ((want = vsv_volume_at(cur, i, j, k)) > 0)
                    ci = i, cj = j, ck = k;
    c->i = ci, c->j = cj, c->k = ck, c->want = want;
}

/* Two forked windows join the room, show tick 1 and read the cloudy cell through it; tick 3 waits until a
 * window has shown tick 2. 0 if no pipe could be made (nothing checked). */
static int room_forked_windows(vsv_room *r, vsv_player *p, const cloudy_cell *cell, const vsv_volume **vols, int ns,
                               const double *user, char *err, size_t cap)
{
    int fds[2];
    if (pipe(fds))
        return 0;
    pid_t kids[2];
    for (int c = 0; c < 2; c++) {
        kids[c] = fork();
        if (kids[c] == 0) {
            close(fds[0]);
            _exit(child(r, c ? "left" : "front", cell->s, cell->i, cell->j, cell->k, cell->want, fds[1]));
        }
    }
    close(fds[1]);
    /* the windows join and take tick 1; until each has started a frame
     * after it, tick 2 waits */
    usleep(5000);
    vsv_room_window w[4];
    int joined = 0;
    for (int f = 0; f < 300 && (joined = vsv_room_windows(r, w, 4)) < 2; f++)
        usleep(10000);
    CHECK(joined == 2, "two windows joined", "(%d)", joined);
    int shown_all = 0;
    for (int f = 0; f < 300 && !(shown_all = vsv_room_can_publish(r)); f++)
        usleep(2000);
    CHECK(shown_all, "every window shows tick 1: the next may come", " ");
    vsv_player_do(p, "step", err, cap);
    vsv_player_update(p, 0, 1);
    for (int k = 0; k < ns && k < 64; k++)
        vols[k] = vsv_player_volume(p, k);
    int64_t t2 = 0;
    CHECK(!vsv_room_publish(r, vsv_player_pager(p), 3, vsv_player_step_time(p, 3), NULL, vols, user, &t2, err, cap) &&
              t2 == 2,
          "tick 2", "(%lld)", (long long)t2);
    CHECK(vsv_room_publish(r, vsv_player_pager(p), 3, 0, NULL, vols, user, NULL, err, cap) == VSV_EAGAIN,
          "tick 3 waits: no window has shown tick 2 yet", " ");
    char buf[256] = "";
    size_t got = 0;
    ssize_t n;
    while ((n = read(fds[0], buf + got, sizeof buf - 1 - got)) > 0)
        got += (size_t)n;
    buf[got] = 0;
    close(fds[0]);
    int ok = 1;
    for (int c = 0; c < 2; c++) {
        int st = 0;
        waitpid(kids[c], &st, 0);
        ok &= WIFEXITED(st) && WEXITSTATUS(st) == 0;
    }
    CHECK(ok && strstr(buf, "front 1 2") && strstr(buf, "left 1 2"),
          "both processes read the decoded cell through the room: tick 1, step 2, the same value", "(%s)", buf);
    vsv_room_window after[4];
    vsv_room_windows(r, after, 4);
    CHECK(after[0].frames >= 30 && after[1].frames >= 30 && after[0].shown >= 1,
          "each window's frames are counted, with the tick it showed", "(%llu %llu %lld)",
          (unsigned long long)after[0].frames, (unsigned long long)after[1].frames, (long long)after[0].shown);
    return 1;
}

/* a window of this process: the same step published again keeps its
 * load (renderers keep what they derived), a new step is a new load */
static void room_own_window(const vsv_room_opts *ro, vsv_player_opts *o, int s, int ns, const vsv_volume **vols,
                            const double *user, char *err, size_t cap)
{
    vsv_room *r2 = NULL;
    vsv_player *p2 = NULL;
    o->slab_ctx = NULL;
    if (!vsv_room_create(ro, &r2, err, cap) && (o->slab_ctx = r2) && !vsv_player_open(o, &p2, err, cap)) {
        const int me = vsv_room_join(r2, "here");
        vsv_room_view v;
        uint64_t gens[3];
        const vsv_volume *ptrs[3];
        const int steps[3] = {3, 3, 2};
        for (int i = 0; i < 3; i++) {
            vsv_player_do(p2, i == 2 ? "seek 2" : "seek 3", err, cap);
            vsv_player_update(p2, 0, 1);
            for (int k = 0; k < ns && k < 64; k++)
                vols[k] = vsv_player_volume(p2, k);
            const int rc = vsv_room_publish(r2, vsv_player_pager(p2), steps[i], 0, NULL, vols, user, NULL, err, cap);
            memset(&v, 0, sizeof v);
            const int f1 = vsv_room_frame(r2, me, &v), f2 = vsv_room_frame(r2, me, &v); /* (shown) */
            gens[i] = !f2 && v.vols[s] ? v.vols[s]->gen : 0;
            ptrs[i] = !f2 ? v.vols[s] : NULL;
            CHECK(!rc && !f1 && !f2 && v.tick == i + 1 && v.step == steps[i],
                  "a window of this process takes each tick (one that joined first too)", "(%d %d %lld)", rc, f1,
                  (long long)v.tick);
        }
        CHECK(gens[0] && gens[1] == gens[0] && ptrs[1] == ptrs[0],
              "the same step again: the same volume and gen in the window (no re-render)", "(%llu %llu)",
              (unsigned long long)gens[0], (unsigned long long)gens[1]);
        CHECK(gens[2] != gens[1], "another step: a new gen", "(%llu)", (unsigned long long)gens[2]);
        vsv_room_unpin(r2);
    } else {
        CHECK(0, "a second room and player", "(%s)", err);
    }
    vsv_player_free(p2);
    vsv_room_free(r2);
}

static void test_room(const char *path)
{
    vsv_player_opts o;
    vsv_player_opts_init(&o);
    o.path = path;
    o.clock_only = 1;
    vsv_player *in = NULL;
    char err[1024];
    if (!CHECK(!vsv_player_open(&o, &in, err, sizeof err), "the sample opens", "(%s)", err))
        return;
    vsv_volume *shape = vsv_pager_volume_new(vsv_player_pager(in));
    const vsv_room_opts ro = {(size_t)64 << 20, vsv_player_meta(in)->nvars, shape->nbricks, 2, sizeof(double)};
    vsv_volume_free(shape);
    vsv_player_free(in);
    vsv_room *r = NULL;
    if (!CHECK(!vsv_room_create(&ro, &r, err, sizeof err), "a room for two windows", "(%s)", err))
        return;
    /* the decoding player: its bricks in the room's arena */
    o.clock_only = 0;
    o.cache_bytes = (size_t)32 << 20;
    o.slab_alloc = vsv_room_slab;
    o.slab_ctx = r;
    vsv_player *p = NULL;
    if (!CHECK(!vsv_player_open(&o, &p, err, sizeof err), "the decoding player opens", "(%s)", err))
        return;
    vsv_player_do(p, "seek 2", err, sizeof err);
    vsv_player_update(p, 0, 1);
    const int s = vsv_meta_find_var(vsv_player_meta(p), "CLW");
    const vsv_volume *cur = vsv_player_volume(p, s);
    if (!CHECK(cur && s >= 0, "step 2's CLW is shown", " "))
        return;
    /* a cell with cloud water in it */
    cloudy_cell cell = {s, 0, 0, 0, 0};
    find_cloudy(cur, &cell);
    CHECK(cell.want > 0, "a cloudy cell to read back", " ");
    CHECK(vsv_room_arena_used(r) > 0, "the pager's bricks are in the room's arena", "(%zu bytes)",
          vsv_room_arena_used(r));
    const vsv_volume *vols[64] = {0};
    const int ns = vsv_player_meta(p)->nvars;
    for (int k = 0; k < ns && k < 64; k++)
        vols[k] = vsv_player_volume(p, k);
    const double user = 42.5;
    CHECK(vsv_room_can_publish(r), "an empty room can publish", " ");
    int64_t t1 = 0;
    const int rc1 = vsv_room_publish(r, vsv_player_pager(p), 2, vsv_player_step_time(p, 2), NULL, vols, &user, &t1, err,
                                     sizeof err);
    CHECK(!rc1 && t1 == 1, "the first tick", "(%d %lld: %s)", rc1, (long long)t1, err);
    if (!room_forked_windows(r, p, &cell, vols, ns, &user, err, sizeof err))
        return;
    room_own_window(&ro, &o, s, ns, vols, &user, err, sizeof err);
    vsv_room_fail(r, 2, "first");
    vsv_room_fail(r, 1, "second");
    char why[64];
    CHECK(vsv_room_failed(r, why, sizeof why) == 2 && !strcmp(why, "first"),
          "a failure: the first message and exit status are kept", "(%s)", why);
    vsv_room_unpin(r);
    vsv_player_free(p);
    vsv_room_free(r);
}

/* ---------------------------------------------------------------- legend */

static void test_legend(const char *path)
{
    vsv_player_opts o;
    vsv_player_opts_init(&o);
    o.path = path;
    o.cache_bytes = (size_t)8 << 20;
    vsv_player *p = NULL;
    char err[512];
    if (vsv_player_open(&o, &p, err, sizeof err)) {
        CHECK(0, "the sample opens for the legend", "(%s)", err);
        return;
    }
    vsv_font *font = NULL;
    if (vsv_font_open(NULL, 16, &font, err, sizeof err)) {
        CHECK(1, "the legend: skipped (no font)", " ");
        vsv_player_free(p);
        return;
    }
    int sp[64];
    for (int s = 0; s < 64; s++)
        sp[s] = s;
    vsv_scene sc;
    vsv_player_scene(p, &sc);
    vsv_annot a = {VSV_ANNOT_TIME | VSV_ANNOT_COLOURBAR, font, 0, NULL, sp, NULL, NULL, NULL};
    int w4, h4, w0, h0;
    vsv_legend_size(&a, &sc, "one\ntwo", &w4, &h4);
    vsv_player_do(p, "hide CLW", err, sizeof err);
    vsv_player_scene(p, &sc);
    vsv_legend_size(&a, &sc, "one\ntwo", &w0, &h0);
    const int lh = vsv_font_line(font);
    CHECK(h4 > h0 + lh && w4 >= w0, "a hidden species takes its bar out of the legend", "(%d -> %d px)", h4, h0);
    float *rgba = calloc((size_t)w0 * h0 * 4, sizeof *rgba);
    vsv_legend_draw(&a, &sc, "one\ntwo", rgba, w0, h0);
    /* the last bar's row: its colours from the transfer function, lo to hi */
    int coloured = 0;
    for (int y = h0 - 1; y >= 0 && !coloured; y--)
        coloured = rgba[4 * ((size_t)y * w0 + w0 / 2) + 3] == 1;
    CHECK(coloured, "the legend draws an opaque colour bar", " ");
    free(rgba);
    vsv_font_free(font);
    vsv_player_free(p);
}

int main(void)
{
    test_place();
    test_wand();
    test_conf();
    const char *path = vsv_test_tmp("room-crop.vsv");
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "%s/vsv-convert -q samples/mm5/MMOUT_DOMAIN1_CROP -o %s",
             getenv("B") ? getenv("B") : "build", path);
    if (!CHECK(system(cmd) == 0, "convert the bundled MM5 sample", " "))
        return vsv_test_done();
    test_room(path);
    test_legend(path);
    return vsv_test_done();
}
