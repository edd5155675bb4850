/* vsv_clock.c — see vsv_clock.h. */
#include "vsv_clock.h"

#include <math.h>
#include <stdlib.h>

static int cmp_i64(const void *a, const void *b)
{
    const int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return x < y ? -1 : x > y;
}

void vsv_clock_init(vsv_clock *c, const int64_t *times, int nsteps, double rate)
{
    c->times = times;
    c->nsteps = nsteps;
    c->model = nsteps ? (double)times[0] : 0;
    c->speed = 1;
    c->playing = 0;
    c->ends = VSV_CLOCK_STOP;
    c->step = 0;
    c->rate = rate;
    if (!(rate > 0)) { /* the median interval per quarter second */
        double med = 3600;
        if (nsteps > 1) {
            int64_t *d = malloc((size_t)(nsteps - 1) * sizeof *d);
            if (d) {
                for (int i = 0; i + 1 < nsteps; i++)
                    d[i] = times[i + 1] - times[i];
                qsort(d, (size_t)nsteps - 1, sizeof *d, cmp_i64);
                med = (double)d[(nsteps - 1) / 2];
                free(d);
            }
        }
        c->rate = (med > 0 ? med : 1) * 4;
    }
}

int vsv_clock_step_at(const vsv_clock *c, double t)
{
    int lo = 0, hi = c->nsteps - 1;
    if (c->nsteps <= 0)
        return 0;
    if (t <= (double)c->times[0])
        return 0;
    while (lo < hi) { /* the last step with time <= t */
        const int mid = (lo + hi + 1) / 2;
        if ((double)c->times[mid] <= t)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

/* The step shown for the model time: at or before it going forward, at or
 * after it going backward (so both directions show each step as it is
 * reached). */
static void settle(vsv_clock *c)
{
    int k = vsv_clock_step_at(c, c->model);
    if (c->speed < 0 && k + 1 < c->nsteps && (double)c->times[k] < c->model)
        k++;
    c->step = k;
}

/* Looping, the last step is shown for as long as the one before it (and,
 * backwards, the first as long as the second): model time runs over
 * [t0, t1 + dl) forward and (t0 - df, t1] backward, so every step, the last
 * included, is on screen once per lap. */
int vsv_clock_tick(vsv_clock *c, double dt)
{
    if (!c->playing || c->nsteps < 2 || !(dt > 0))
        return c->step;
    const int n = c->nsteps;
    const double t0 = (double)c->times[0], t1 = (double)c->times[n - 1];
    double m = c->model + dt * c->rate * c->speed;
    if (c->ends == VSV_CLOCK_LOOP) {
        const double dl = (double)(c->times[n - 1] - c->times[n - 2]), df = (double)(c->times[1] - c->times[0]);
        const double lo = c->speed < 0 ? t0 - df : t0, hi = c->speed < 0 ? t1 : t1 + dl, lap = hi - lo;
        if (lap > 0 && c->speed > 0 && m >= hi)
            m = lo + fmod(m - lo, lap);
        else if (lap > 0 && c->speed < 0 && m <= lo)
            m = hi - fmod(hi - m, lap);
        c->model = m;
        settle(c);
        return c->step;
    }
    const double span = t1 - t0;
    for (int guard = 0; (m > t1 || m < t0) && guard < 64; guard++) {
        if (c->ends == VSV_CLOCK_BOUNCE && span > 0) {
            m = m > t1 ? t1 - (m - t1) : t0 + (t0 - m);
            c->speed = -c->speed;
        } else {
            m = m > t1 ? t1 : t0;
            c->playing = 0;
        }
    }
    c->model = m < t0 ? t0 : m > t1 ? t1 : m;
    settle(c);
    return c->step;
}

void vsv_clock_play(vsv_clock *c)
{
    /* playing from an end towards it starts over */
    if (c->nsteps > 1 && c->ends == VSV_CLOCK_STOP) {
        if (c->speed > 0 && c->step == c->nsteps - 1)
            vsv_clock_seek_step(c, 0);
        else if (c->speed < 0 && c->step == 0)
            vsv_clock_seek_step(c, c->nsteps - 1);
    }
    c->playing = 1;
}

void vsv_clock_pause(vsv_clock *c) { c->playing = 0; }

void vsv_clock_toggle(vsv_clock *c)
{
    if (c->playing)
        vsv_clock_pause(c);
    else
        vsv_clock_play(c);
}

void vsv_clock_seek_step(vsv_clock *c, int step)
{
    if (c->nsteps <= 0)
        return;
    step = step < 0 ? 0 : step >= c->nsteps ? c->nsteps - 1 : step;
    c->model = (double)c->times[step];
    c->step = step;
}

void vsv_clock_step(vsv_clock *c, int n)
{
    c->playing = 0;
    if (c->nsteps <= 0)
        return;
    long k = (long)c->step + n;
    if (c->ends == VSV_CLOCK_LOOP)
        k = ((k % c->nsteps) + c->nsteps) % c->nsteps;
    vsv_clock_seek_step(c, (int)k);
}

void vsv_clock_seek_time(vsv_clock *c, int64_t t) { vsv_clock_seek_step(c, vsv_clock_step_at(c, (double)t)); }

void vsv_clock_set_speed(vsv_clock *c, double x)
{
    if (!(x != 0) || x != x)
        return;
    const double a = fabs(x) < 1.0 / VSV_CLOCK_MAX_SPEED ? 1.0 / VSV_CLOCK_MAX_SPEED
                     : fabs(x) > VSV_CLOCK_MAX_SPEED     ? VSV_CLOCK_MAX_SPEED
                                                         : fabs(x);
    c->speed = x < 0 ? -a : a;
    settle(c);
}

void vsv_clock_faster(vsv_clock *c, int dir)
{
    const double same = (dir >= 0) == (c->speed > 0);
    double a = same && c->playing ? fabs(c->speed) * 2 : 2;
    if (a > VSV_CLOCK_MAX_SPEED)
        a = VSV_CLOCK_MAX_SPEED;
    vsv_clock_set_speed(c, dir >= 0 ? a : -a);
    vsv_clock_play(c);
}

int vsv_clock_ahead(const vsv_clock *c, double frame, int *steps, int max)
{
    if (max <= 0 || c->nsteps < 2)
        return 0;
    if (!c->playing) {
        vsv_clock k = *c;
        vsv_clock_step(&k, 1);
        steps[0] = k.step;
        return k.step != c->step;
    }
    if (!(frame > 0))
        return 0;
    vsv_clock k = *c;
    int n = 0;
    /* whole frames at a time: to just short of the next step's time, then
     * frame by frame over it (model time moves linearly between ends, so
     * m frames in one tick land where m ticks would) */
    for (long f = 0; f < VSV_CLOCK_HORIZON && n < max && n < c->nsteps - 1 && k.playing;) {
        const double v = fabs(k.rate * k.speed) * frame; /* model seconds a frame */
        const int s = k.step, up = k.speed > 0, last = k.nsteps - 1;
        const int64_t *t = k.times;
        double gap; /* model seconds to the next change of step (looping: past an end, the wrap) */
        if (up)
            gap = (s < last ? (double)t[s + 1] : k.ends == VSV_CLOCK_LOOP ? 2.0 * t[last] - t[last - 1] : 0) - k.model;
        else
            gap = k.model - (s > 0 ? (double)t[s - 1] : k.ends == VSV_CLOCK_LOOP ? 2.0 * t[0] - t[1] : k.model);
        double m = v > 0 && gap > v ? floor(gap / v) : 1;
        m = fmin(m, (double)(VSV_CLOCK_HORIZON - f));
        vsv_clock_tick(&k, m * frame);
        f += (long)m;
        int seen = k.step == c->step; /* a lap or a turn comes back to steps listed */
        for (int i = 0; i < n && !seen; i++)
            seen = steps[i] == k.step;
        if (!seen)
            steps[n++] = k.step;
    }
    return n;
}

int vsv_clock_stride(const vsv_clock *c, double frame, int prev)
{
    if (!c->playing || c->nsteps < 3 || !(frame > 0))
        return 1;
    const double per = (double)(c->times[c->nsteps - 1] - c->times[0]) / (c->nsteps - 1);
    const double r = per > 0 ? fabs(c->rate * c->speed) * frame / per : 0; /* steps a frame spans */
    int k = prev >= 1 ? prev : 1;
    if (r < k || r >= 1.2 * (k + 1)) /* (then r / k in [1.2, 2.4): a change of 1/6 to go back) */
        k = (int)floor(r / 1.2);
    return k >= 2 ? k : 1;
}

int vsv_clock_stride_step(const vsv_clock *c, int t, int k)
{
    if (k <= 1 || t < 0 || t >= c->nsteps)
        return t;
    if (c->speed > 0)
        return t - t % k;
    const int up = t + (k - t % k) % k;
    return up < c->nsteps ? up : c->nsteps - 1;
}

/* Appends t to steps[0 .. *n - 1] unless there, or the one shown, or full. */
static void add_once(int *steps, int *n, int max, int shown, int t)
{
    int seen = t == shown;
    for (int j = 0; j < *n && !seen; j++)
        seen = steps[j] == t;
    if (!seen && *n < max)
        steps[(*n)++] = t;
}

int vsv_clock_ahead_stride(const vsv_clock *c, double frame, int k, int *steps, int max)
{
    int pred[VSV_CLOCK_HORIZON], all[VSV_CLOCK_HORIZON], na = 0, n = 0;
    max = max < VSV_CLOCK_HORIZON ? max : VSV_CLOCK_HORIZON;
    const int shown = vsv_clock_stride_step(c, c->step, k), np = vsv_clock_ahead(c, frame, pred, max);
    const double v = fabs(c->rate * c->speed); /* model seconds a wall second */
    if (c->playing && frame > 0 && v > 0) {    /* every step: frames shorter than the shortest interval */
        double gap = frame * v;
        for (int i = 1; i < c->nsteps; i++)
            if (c->times[i] > c->times[i - 1])
                gap = fmin(gap, 0.5 * (double)(c->times[i] - c->times[i - 1]));
        na = vsv_clock_ahead(c, gap / v, all, (int)fmin(VSV_CLOCK_HORIZON, (double)max * (k > 1 ? k : 1)));
    }
    for (int i = 0; i < na; i++)
        all[i] = vsv_clock_stride_step(c, all[i], k);
    /* each predicted step, then the ones on the way to it */
    int j = 0;
    for (int i = 0; i < np; i++) {
        const int t = vsv_clock_stride_step(c, pred[i], k);
        add_once(steps, &n, max, shown, t);
        int m = j;
        while (m < na && all[m] != t)
            m++;
        for (; m < na && j <= m; j++)
            add_once(steps, &n, max, shown, all[j]);
    }
    for (; j < na; j++)
        add_once(steps, &n, max, shown, all[j]);
    return n;
}
