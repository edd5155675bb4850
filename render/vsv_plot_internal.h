/* vsv_plot_internal.h — the plots (vsv_render.h, "plots") between their
 * files: what vsv_plot.c reads from the file and vsv_plot_draw.c draws, and
 * the axis arithmetic both use (vsv_plot_axis.c). Private to render/. */
#ifndef VSV_PLOT_INTERNAL_H
#define VSV_PLOT_INTERNAL_H

#include "vsv_render.h"

/* One row of the values drawn: a step (series), a level (profile) or a
 * sample's level (section), as vsv-query prints it. */
typedef struct plot_row {
    int64_t time;
    int cell[3];     /* -1,-1,-1: a moving nest away from the point */
    double lat, lon; /* the cell's centre */
    double h;        /* the cell's height (vsv_meta_cell_height_at) */
    double dist;     /* section: km along the line */
    float v[VSV_PLOT_MAXSPECIES];
} plot_row;

struct vsv_plot {
    vsv_plot_opts o; /* title and source NULL: copied below */
    int cal;         /* the file's calendar */
    int nrows;
    plot_row *rows;
    /* a section: ns samples along the line, nz levels each (rows sample
       by sample, level by level); per sample its ground (m, NaN: none; a
       profile: its column's, ground[0]) and
       nz + 1 interfaces between its levels (in the height unit) */
    int ns, nz;
    double *ground, *iface, length; /* length: km */
    int up;                         /* 1: the coordinate grows with k (heights), -1: it falls (pressure) */
    int metres;                     /* the levels are heights in metres */
    double ybot, ytop;              /* the height axis (the level unit) */
    double lo, hi;                  /* the values' range drawn (colour bar, value axis) */
    double vlo, vhi;                /* the value axis (lines): lo, hi widened to ticks */
    char title[512], subtitle[512], source[256];
    char names[VSV_PLOT_MAXSPECIES][64], units[VSV_PLOT_MAXSPECIES][64];
    char hname[80];  /* the height column of the CSV: "height (m)" */
    char yaxis[96];  /* "height (km)", "level (hPa)" */
    char vaxis[256]; /* the value axis: "CLW, SNOW (kg/kg)" */
    int same_units;  /* the species share their units (the legend names them alone) */
    double yscale;   /* height axis units per level unit (1/1000: km) */
};

/* ------------------------------------------------------------- axes */

/* Ticks along an axis: at most max of them, at v[i], labelled text[i]. */
#define PLOT_MAXTICKS 64
typedef struct plot_ticks {
    int n;
    double v[PLOT_MAXTICKS];
    char text[PLOT_MAXTICKS][32];
} plot_ticks;

/* The step of about target ticks over [lo, hi]: 1, 2, 2.5 or 5 times a power of ten. */
double vsv_plot_nice_step(double lo, double hi, int target);
/* Linear ticks over [lo, hi] (either order), about target of them, all labelled alike. */
void vsv_plot_ticks_linear(double lo, double hi, int target, plot_ticks *t);
/* Ticks of a log axis over [lo, hi] (0 < lo < hi): decades, or 1-2-5 where few. */
void vsv_plot_ticks_log(double lo, double hi, int target, plot_ticks *t);
/* Ticks of a time axis over [t0, t1] (seconds, calendar cal): whole
 * minutes, hours or days, labelled HH:MM (days: YYYY-MM-DD); date[i] is
 * the date where it changes (else ""). */
void vsv_plot_ticks_time(double t0, double t1, int target, int cal, plot_ticks *t, char (*date)[32]);
/* A value with 3 significant digits, whole numbers whole (a colour bar's ends). */
void vsv_plot_num3(double v, char *buf, size_t cap);
/* text as valid UTF-8 with no control characters (each bad byte a '?'), into out. */
void vsv_plot_clean(const char *text, char *out, size_t cap);

#endif
