/* vsv_wand.c — see vsv_wand.h. */
#include "vsv_wand.h"

#include <math.h>
#include <string.h>

enum { B1 = 1, B2 = 2, B3 = 3 };

/* the further switches, 4 .. 12 (the simulator's keys, or more buttons) */
static const char *const KEYS[] = {"step +1", "step -1", "start", "end", "faster", "slower", NULL, NULL, "loop"};
enum { SW_FIRST = 4, SW_RESET = 10, SW_PLACE = 11, SW_SEED = 13 };

void vsv_wand_init(vsv_wand *w, double speed)
{
    memset(w, 0, sizeof *w);
    w->speed = speed > 0 ? speed : 4;
}

static void act(vsv_wand_out *o, const char *a)
{
    if (o->nact < VSV_WAND_MAXACT)
        o->act[o->nact++] = a;
}

/* A flick of one axis: +1 / -1 once when it passes VSV_WAND_FLICK, 0 else;
 * it re-arms when the stick comes back under 0.3. */
static int flick(int *state, float v)
{
    if (*state && fabsf(v) < 0.3f)
        *state = 0;
    if (!*state && fabsf(v) > VSV_WAND_FLICK) {
        *state = v > 0 ? 1 : -1;
        return *state;
    }
    return 0;
}

/* The continuous part of an axis beyond the dead zone, -1..1. */
static double deflect(float v)
{
    const double a = fabs(v) <= VSV_WAND_DEAD ? 0 : (fabs(v) - VSV_WAND_DEAD) / (1 - VSV_WAND_DEAD);
    return v < 0 ? -fmin(a, 1) : fmin(a, 1);
}

void vsv_wand_update(vsv_wand *w, const vsv_wand_in *in, vsv_wand_out *o)
{
    memset(o, 0, sizeof *o);
    o->scale = 1;
    const int *sw = in->sw;
    const double dx = deflect(in->jx), dy = deflect(in->jy);
    const int stick = dx != 0 || dy != 0;
    /* presses: a button pressed while another is held uses both */
    for (int b = B1; b <= B3; b++)
        if (sw[b] && !w->held[b]) {
            w->held[b] = 1, w->used[b] = 0;
            for (int c = B1; c <= B3; c++)
                if (c != b && w->held[c] && sw[c])
                    w->used[c] = 1;
        }
    if (sw[B1] && sw[B2] && !w->chord) { /* the chord: once while both are down */
        o->reset = 1;
        w->chord = 1;
        w->used[B1] = w->used[B2] = 1;
    } else if (!sw[B1] || !sw[B2]) {
        w->chord = 0;
    }
    /* the joystick, by the button held */
    const int fx = flick(&w->flick_x, in->jx), fy = flick(&w->flick_y, in->jy);
    if (w->held[B3] && sw[B3]) {
        if (fx)
            act(o, fx > 0 ? "step +1" : "step -1");
        if (fy)
            act(o, fy > 0 ? "faster" : "slower");
        if (stick)
            w->used[B3] = 1;
    } else if (w->held[B2] && sw[B2]) {
        if (fx)
            act(o, fx > 0 ? "select +1" : "select -1");
        if (dy > 0)
            act(o, "opacity - +0.01");
        else if (dy < 0)
            act(o, "opacity - -0.01");
        if (stick)
            w->used[B2] = 1;
    } else if (w->held[B1] && sw[B1]) {
        o->scale = pow(2, dy * in->dt);
        if (stick)
            w->used[B1] = 1;
    } else {
        o->travel = dy * w->speed * in->dt;
        o->turn = -dx * VSV_WAND_TURN * in->dt;
    }
    /* releases: a button's own action, when it was used for nothing else */
    for (int b = B1; b <= B3; b++)
        if (!sw[b] && w->held[b]) {
            w->held[b] = 0;
            if (w->used[b])
                continue;
            if (w->held[B3] && (b == B1 || b == B2)) { /* under button 3: the ends */
                act(o, b == B1 ? "start" : "end");
                w->used[B3] = 1;
            } else {
                act(o, b == B1 ? "toggle-play" : b == B2 ? "select +1" : "toggle");
            }
        }
    /* the further switches act when pressed */
    for (int k = SW_FIRST; k < VSV_WAND_SWITCHES; k++) {
        const int press = sw[k] && !w->held[k];
        w->held[k] = sw[k];
        if (!press)
            continue;
        if (k == SW_RESET)
            o->reset = 1;
        else if (k == SW_PLACE)
            o->place = 1;
        else if (k == SW_SEED)
            o->seed = 1;
        else if (k - SW_FIRST < (int)(sizeof KEYS / sizeof *KEYS) && KEYS[k - SW_FIRST])
            act(o, KEYS[k - SW_FIRST]);
    }
}

const char *vsv_wand_help(void)
{
    return "joystick           up/down: travel along the wand; left/right: turn about the\n"
           "                   vertical (45 degrees a second at full deflection)\n"
           "button 1 (left)    play / pause; held with the joystick up/down: scale the\n"
           "                   scene about the wand's tip (x2 a second)\n"
           "button 2 (middle)  next species; held with the joystick: up/down its opacity,\n"
           "                   a flick right/left the next / previous species\n"
           "button 3 (right)   show / hide the species; held: a joystick flick right/left\n"
           "                   steps one step forward / back, up/down plays faster /\n"
           "                   slower; with button 1 pressed: the start, button 2: the end\n"
           "buttons 1 and 2    together: the scene back where it started\n"
           "switch 4 .. 12     step forward, step back, start, end, faster, slower,\n"
           "                   reset the view, table / room, loop (map keys to them)\n"
           "switch 13          a trajectory from the wand's tip, leaving at the step shown\n"
           "                   (drawn where the file has wind; see --trajectory)\n"
           "switch 0           quit (Escape in the simulator)\n";
}
