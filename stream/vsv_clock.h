/* vsv_clock.h — the playback clock: model time (seconds) driven by wall
 * time at a chosen speed, decoupled from it.
 *
 * Model time runs continuously between the first and last step times; the
 * step shown is the last one at or before it (playing backwards: the first
 * at or after it). At speed x1 the model advances `rate` model seconds per
 * wall second (by default the median step interval per 1/4 s, so four
 * steps a second); fast-forward and rewind multiply that by 2, 4 ... 64
 * (negative speeds play backwards). At an end the clock stops, wraps (loop)
 * or turns round (bounce). Looping, the last step stays on screen as long as
 * the one before it (backwards: the first as long as the second) before the
 * wrap, so every step is shown once a lap; model time then runs up to one
 * interval past the last step (before the first). Stepping pauses and moves
 * by whole steps. */
#ifndef VSV_CLOCK_H
#define VSV_CLOCK_H

#include "vsv_format.h"

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

VSV_API_BEGIN

enum { VSV_CLOCK_STOP = 0, VSV_CLOCK_LOOP = 1, VSV_CLOCK_BOUNCE = 2 };

#define VSV_CLOCK_MAX_SPEED 64
#define VSV_CLOCK_HORIZON 1024 /* frames vsv_clock_ahead looks ahead */

typedef struct vsv_clock {
    const int64_t *times; /* step times, increasing (borrowed) */
    int nsteps;
    double model; /* model time now, seconds */
    double rate;  /* model seconds per wall second at speed 1 */
    double speed; /* signed multiplier: 1, 2 ... 64 or -1 ... -64 (any non-zero) */
    int playing;
    int ends; /* VSV_CLOCK_STOP, _LOOP or _BOUNCE */
    int step; /* the step shown */
} vsv_clock;

/* Paused at the first step, speed 1, ends STOP; rate 0 = the default. */
void vsv_clock_init(vsv_clock *c, const int64_t *times, int nsteps, double rate);
/* Advances by dt wall seconds (no effect while paused). Returns the step. */
int vsv_clock_tick(vsv_clock *c, double dt);
void vsv_clock_play(vsv_clock *c);
void vsv_clock_pause(vsv_clock *c);
void vsv_clock_toggle(vsv_clock *c);
/* Pauses and moves n steps (wrapping when looping, else clamped). */
void vsv_clock_step(vsv_clock *c, int n);
/* Jumps to a step / to the step at or before a model time (clamped). */
void vsv_clock_seek_step(vsv_clock *c, int step);
void vsv_clock_seek_time(vsv_clock *c, int64_t t);
/* Sets the signed speed (|x| clamped to 1/64 .. 64; 0 is refused). */
void vsv_clock_set_speed(vsv_clock *c, double x);
/* Fast-forward / rewind: doubles the speed in that direction (from x1; when
 * paused or going the other way: x2) up to x64, and plays. */
void vsv_clock_faster(vsv_clock *c, int dir);
/* The step at or before model time t (the first step before it all). */
int vsv_clock_step_at(const vsv_clock *c, double t);
/* The steps the next frames will show, `frame` wall seconds apart, as the
 * clock would move from now: each step once, nearest first, within the
 * next VSV_CLOCK_HORIZON frames (a step a frame jumps over is not there;
 * wrapping and turning round at the ends as the clock does). Paused: the
 * step a step forward would show.
 * Fills up to max and returns how many (0 at a stopping end). */
int vsv_clock_ahead(const vsv_clock *c, double frame, int *steps, int max);
/* Playing so fast that a frame, `frame` wall seconds, spans several steps:
 * the stride k at which to show them, every k-th step, so that the steps
 * shown (and decoded ahead for the next frames) stay the same from frame
 * to frame whatever the frame times. k never exceeds the steps a frame
 * spans (each frame shows a new step); it changes from `prev` only when
 * that falls below k or reaches 1.2 (k + 1), to r / 1.2 rounded down (frame
 * times vary: a stride that changed would find the steps decoded ahead not
 * wanted). 1 when paused or a frame spans under 2.4 steps. */
int vsv_clock_stride(const vsv_clock *c, double frame, int prev);
/* The step to show for step t at stride k: the last multiple of k at or
 * before t in the direction of play (forward: t rounded down; backward:
 * up, at most the last step). */
int vsv_clock_stride_step(const vsv_clock *c, int t, int k);
/* The steps to decode ahead at stride k: the ones the next frames, `frame`
 * apart, will show (vsv_clock_ahead at stride k), each followed by the
 * steps at stride k on the clock's way to it that it jumps over, then the
 * rest of them: a frame shorter than the ones before finds its step
 * listed too. Each once, nearest first, the one shown left out; up to max. */
int vsv_clock_ahead_stride(const vsv_clock *c, double frame, int k, int *steps, int max);

VSV_API_END

#ifdef __cplusplus
}
#endif

#endif
