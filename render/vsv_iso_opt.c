/* vsv_iso_opt.c — the --iso SPECIES:VALUE[:COLOUR] option every tool that
 * draws or exports isosurfaces reads alike (vsv_iso_parse). */
#include "vsv_flow.h"
#include "vsv_render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Colours by name: a few that read well over terrain and clouds. */
static const struct {
    const char *name;
    float rgb[3];
} named[] = {{"white", {0.92f, 0.92f, 0.92f}}, {"grey", {0.6f, 0.6f, 0.6f}},     {"red", {0.85f, 0.2f, 0.15f}},
             {"orange", {0.95f, 0.55f, 0.1f}}, {"yellow", {0.95f, 0.85f, 0.2f}}, {"green", {0.3f, 0.7f, 0.3f}},
             {"cyan", {0.3f, 0.8f, 0.9f}},     {"blue", {0.25f, 0.4f, 0.9f}},    {"purple", {0.6f, 0.35f, 0.8f}}};

int vsv_colour_parse(const char *s, float rgb[3])
{
    for (size_t i = 0; i < sizeof named / sizeof *named; i++)
        if (!strcmp(s, named[i].name)) {
            memcpy(rgb, named[i].rgb, sizeof named[i].rgb);
            return 0;
        }
    if (s[0] != '#' || strlen(s) != 7 || strspn(s + 1, "0123456789abcdefABCDEF") != 6)
        return -1;
    const long v = strtol(s + 1, NULL, 16);
    for (int c = 0; c < 3; c++)
        rgb[c] = (float)((v >> (16 - 8 * c)) & 255) / 255;
    return 0;
}

int vsv_iso_parse(const vsv_meta *m, const char *arg, vsv_iso_spec *spec, char *msg, size_t cap)
{
    memset(spec, 0, sizeof *spec);
    memcpy(spec->rgb, named[0].rgb, sizeof spec->rgb);
    const char *c1 = strchr(arg, ':');
    if (!c1 || c1 == arg) {
        snprintf(msg, cap, "--iso %s: expected SPECIES:VALUE[:COLOUR]", arg);
        return VSV_EINVAL;
    }
    const size_t nlen = (size_t)(c1 - arg);
    spec->species = -1;
    for (int v = 0; v < m->nvars; v++)
        if (strlen(m->vars[v].name) == nlen && !strncmp(m->vars[v].name, arg, nlen))
            spec->species = v;
    if (spec->species < 0) {
        int n = snprintf(msg, cap, "--iso %s: no species %.*s (the file has", arg, (int)nlen, arg);
        for (int v = 0; v < m->nvars && n >= 0 && (size_t)n < cap; v++)
            n += snprintf(msg + n, cap - (size_t)n, "%s%s", v ? ", " : " ", m->vars[v].name);
        if (n >= 0 && (size_t)n < cap)
            snprintf(msg + n, cap - (size_t)n, ")");
        return VSV_EINVAL;
    }
    const char *c2 = strchr(c1 + 1, ':');
    char num[64];
    const size_t vlen = c2 ? (size_t)(c2 - c1 - 1) : strlen(c1 + 1);
    char *end = NULL;
    if (vlen && vlen < sizeof num) {
        memcpy(num, c1 + 1, vlen);
        num[vlen] = 0;
        spec->value = strtof(num, &end);
    }
    if (!end || *end || !isfinite(spec->value)) {
        snprintf(msg, cap, "--iso %s: the value must be a finite number", arg);
        return VSV_EINVAL;
    }
    if (c2 && vsv_colour_parse(c2 + 1, spec->rgb)) {
        snprintf(msg, cap,
                 "--iso %s: colour %s: a name (white grey red orange yellow green cyan blue purple) or #RRGGBB", arg,
                 c2 + 1);
        return VSV_EINVAL;
    }
    return 0;
}

int vsv_iso_in_range(const vsv_file *f, const char *arg, const vsv_iso_spec *spec, char *msg, size_t cap)
{
    const vsv_meta *m = vsv_file_meta(f);
    const vsv_quant *q = vsv_file_quant(f, spec->species);
    /* the values seen and the range coded (a log scale codes from 0) */
    const double lo = fmin(fmin(q->lo, q->data_min), q->scale == VSV_SCALE_LOG ? 0 : q->lo);
    const double hi = fmax(q->hi, q->data_max);
    if (spec->value > lo && spec->value < hi)
        return 0;
    snprintf(msg, cap, "--iso %s: no surface: %s runs from %g to %g %s in this file", arg, m->vars[spec->species].name,
             q->data_min, q->data_max, m->vars[spec->species].units);
    return VSV_ERANGE;
}
