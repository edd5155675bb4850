/* vsv_plot_axis.c — the arithmetic of a plot's axes: where the ticks go
 * (1-2-2.5-5 steps, decades, whole minutes, hours and days of the file's
 * calendar) and how they read (one style per axis), and text made safe for
 * cairo and XML. */
#include "vsv_plot_internal.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

double vsv_plot_nice_step(double lo, double hi, int target)
{
    const double span = fabs(hi - lo), raw = span / (target > 1 ? target : 1);
    if (!(raw > 0) || !isfinite(raw))
        return 1;
    const double mag = pow(10, floor(log10(raw)));
    static const double mult[] = {1, 2, 2.5, 5, 10};
    for (int i = 0; i < 5; i++)
        if (mult[i] * mag >= raw * (1 - 1e-9))
            return mult[i] * mag;
    return 10 * mag;
}

/* The decimals that write every multiple of step exactly (at most 12). */
static int decimals(double step)
{
    for (int d = 0; d < 12; d++) {
        const double s = step * pow(10, d);
        if (fabs(s - round(s)) < 1e-6 * s)
            return d;
    }
    return 12;
}

void vsv_plot_ticks_linear(double lo, double hi, int target, plot_ticks *t)
{
    const double a = fmin(lo, hi), b = fmax(lo, hi);
    const double step = vsv_plot_nice_step(a, b, target);
    t->n = 0;
    const double i0 = ceil(a / step - 1e-9), i1 = floor(b / step + 1e-9);
    if (!isfinite(i0) || !isfinite(i1) || i1 - i0 >= PLOT_MAXTICKS)
        return;
    /* one style for the axis: fixed decimals, or a mantissa and exponent
       where fixed would need more than 5 decimals or 7 digits */
    const double big = fmax(fabs(i0 * step), fabs(i1 * step));
    const int d = decimals(step);
    const int sci = d > 5 || big >= 1e7;
    const int md = sci ? decimals(step / pow(10, floor(log10(big > 0 ? big : step)))) : 0;
    for (double i = i0; i <= i1; i++) {
        double v = i * step;
        if (fabs(v) < step * 1e-9)
            v = 0;
        t->v[t->n] = v;
        if (sci)
            snprintf(t->text[t->n], sizeof t->text[t->n], "%.*e", md > 6 ? 6 : md, v);
        else
            snprintf(t->text[t->n], sizeof t->text[t->n], "%.*f", d, v);
        t->n++;
    }
}

void vsv_plot_ticks_log(double lo, double hi, int target, plot_ticks *t)
{
    t->n = 0;
    if (!(lo > 0) || !(hi > lo))
        return;
    const int e0 = (int)floor(log10(lo) + 1e-9), e1 = (int)ceil(log10(hi) - 1e-9);
    /* every decade, or every other one where there are many; 1, 2, 5 where few */
    static const double few[] = {1, 2, 5};
    const int nm = e1 - e0 <= 2 ? 3 : 1, every = (e1 - e0 + 1) / (target > 1 ? target : 1) + 1;
    for (int e = e0; e <= e1 && t->n < PLOT_MAXTICKS; e++) {
        if ((e - e0) % every)
            continue;
        for (int m = 0; m < nm && t->n < PLOT_MAXTICKS; m++) {
            const double v = few[m] * pow(10, e);
            if (v < lo * (1 - 1e-9) || v > hi * (1 + 1e-9))
                continue;
            t->v[t->n] = v;
            snprintf(t->text[t->n], sizeof t->text[t->n], "%.0e", v);
            t->n++;
        }
    }
}

void vsv_plot_ticks_time(double t0, double t1, int target, int cal, plot_ticks *t, char (*date)[32])
{
    /* whole minutes, hours, days: the first that gives at most target ticks */
    static const double steps[] = {60,      120,     300,      600,      900,      1800,      3600,     7200,
                                   10800,   21600,   43200,    86400,    172800,   432000,    864000,   1728000,
                                   4320000, 8640000, 17280000, 31536000, 63072000, 157680000, 315360000};
    const int nsteps = sizeof steps / sizeof *steps;
    double step = steps[nsteps - 1];
    for (int i = 0; i < nsteps; i++)
        if ((t1 - t0) / steps[i] <= (target > 1 ? target : 1)) {
            step = steps[i];
            break;
        }
    t->n = 0;
    char prev[16] = "";
    for (double i = ceil(t0 / step - 1e-9); i * step <= t1 + 1e-6 && t->n < PLOT_MAXTICKS; i++) {
        char iso[32];
        const double v = i * step;
        vsv_cal_format(cal, (int64_t)v, iso, sizeof iso); /* YYYY-MM-DDTHH:MM:SSZ */
        char *tee = strchr(iso, 'T');
        if (!tee)
            continue;
        *tee = 0;
        t->v[t->n] = v;
        if (step >= 86400) {
            snprintf(t->text[t->n], sizeof t->text[t->n], "%s", iso);
            date[t->n][0] = 0;
        } else {
            snprintf(t->text[t->n], sizeof t->text[t->n], "%.5s", tee + 1);
            snprintf(date[t->n], sizeof date[t->n], "%s", strcmp(prev, iso) ? iso : "");
        }
        snprintf(prev, sizeof prev, "%s", iso);
        t->n++;
    }
}

void vsv_plot_num3(double v, char *buf, size_t cap)
{
    const double a = fabs(v);
    if (v == 0 || !isfinite(v)) {
        snprintf(buf, cap, "%g", v == 0 ? 0.0 : v); /* no "-0" */
        return;
    }
    if (a < 1e-4 || a >= 1e6) {
        snprintf(buf, cap, "%.3g", v);
        return;
    }
    /* fixed: 3 significant digits, more for whole numbers over 999, no trailing zeros */
    const int e = (int)floor(log10(a));
    snprintf(buf, cap, "%.*f", e < 2 ? 2 - e : 0, v);
    char *dot = strchr(buf, '.');
    if (dot) {
        char *end = buf + strlen(buf);
        while (end > dot + 1 && end[-1] == '0')
            *--end = 0;
        if (end == dot + 1)
            *dot = 0;
    }
}

void vsv_plot_clean(const char *text, char *out, size_t cap)
{
    size_t n = 0;
    const unsigned char *s = (const unsigned char *)(text ? text : "");
    while (*s && n + 5 < cap) {
        /* the length of a well-formed UTF-8 sequence here, or 0 */
        int len = *s < 0x80 ? 1 : (*s & 0xe0) == 0xc0 ? 2 : (*s & 0xf0) == 0xe0 ? 3 : (*s & 0xf8) == 0xf0 ? 4 : 0;
        if ((*s == 0xc0 || *s == 0xc1 || *s > 0xf4) && len > 1)
            len = 0;
        for (int i = 1; i < len; i++)
            if ((s[i] & 0xc0) != 0x80)
                len = 0;
        if (len == 3 && ((s[0] == 0xe0 && s[1] < 0xa0) || (s[0] == 0xed && s[1] >= 0xa0)))
            len = 0; /* overlong, or a surrogate */
        if (len == 4 && ((s[0] == 0xf0 && s[1] < 0x90) || (s[0] == 0xf4 && s[1] >= 0x90)))
            len = 0;
        if (len == 1 && (*s < 0x20 || *s == 0x7f)) {
            out[n++] = ' ';
            s++;
        } else if (!len) {
            out[n++] = '?';
            s++;
        } else {
            memcpy(out + n, s, (size_t)len);
            n += (size_t)len;
            s += len;
        }
    }
    out[n] = 0;
}
