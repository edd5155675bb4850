/* vsv_deftf.c — the default transfer function a writer stores for a
 * species, from its name (cloud water, rain, ozone ...) and its range. */
#include "vsv_format_internal.h"

#include <stdio.h>
#include <string.h>
#include <strings.h>

static int name_is(const char *name, const char *const *list)
{
    for (; *list; list++)
        if (!strcasecmp(name, *list) || (strlen(*list) > 2 && !strncasecmp(name, *list, strlen(*list))))
            return 1;
    return 0;
}

static const char *const vapour[] = {"Q", "QVAPOR", "QV", "H2O", NULL};

/* Exactly one of the vapour names (H2O2 is not vapour). */
static int is_vapour(const char *name)
{
    for (const char *const *v = vapour; *v; v++)
        if (!strcasecmp(name, *v))
            return 1;
    return 0;
}

int vsv_meta_default_shown(const vsv_meta *m, int s)
{
    if (s < 0 || s >= m->nvars || vsv_meta_var_in_vector(m, s))
        return 0; /* a wind component is no cloud: drawn only when named */
    if (!is_vapour(m->vars[s].name))
        return 1;
    for (int i = 0; i < m->nvars; i++)
        if (!is_vapour(m->vars[i].name) && !vsv_meta_var_in_vector(m, i))
            return 0;
    return 1; /* nothing but vapour (and vectors) */
}

void vsv_tf_default(const char *name, const vsv_quant *q, char *buf, size_t cap)
{
    static const char *const cloud[] = {"CLW", "QCLOUD", "QC", "CLOUD", NULL};
    static const char *const rain[] = {"RNW", "QRAIN", "QR", "RAIN", NULL};
    static const char *const ice[] = {"ICE", "QICE", "QI", "NCI", NULL};
    static const char *const graupel[] = {"GRAUPEL", "QGRAUP", "QG", NULL};
    static const char *const snow[] = {"SNOW", "QSNOW", "QS", NULL};
    static const char *const ozone[] = {"O3", "OZONE", NULL};
    static const char *const nox[] = {"NO", "NO2", "NOX", "NOY", NULL};
    static const char *const pm[] = {"PM25", "PM2.5", "PM10", "PM",   "PSO4", "PNO3", "PNH4", "POA",
                                     "PEC",  "SOA",   "ASO4", "ANO3", "ANH4", "AEC",  "AORG", NULL};
    static const char *const smoke[] = {"SMOKE", "BC", "OC", "CO", NULL};
    const char *map = "viridis", *kind = "other", *opacity = "0 0.05 0.2 0.45 0.8";
    if (name_is(name, cloud))
        map = "clouds", kind = "cloud";
    else if (name_is(name, rain))
        map = "rain", kind = "rain";
    else if (name_is(name, ice))
        map = "ice", kind = "ice";
    else if (name_is(name, graupel))
        map = "graupel", kind = "graupel";
    else if (name_is(name, snow))
        map = "snow", kind = "snow";
    else if (name_is(name, ozone))
        map = "viridis", kind = "ozone";
    else if (name_is(name, nox))
        map = "magma", kind = "nox";
    else if (name_is(name, pm))
        map = "cividis", kind = "pm";
    else if (name_is(name, smoke))
        map = "greys", kind = "smoke";
    else if (name_is(name, vapour)) /* everywhere in the air: a faint veil */
        map = "cividis", kind = "vapour", opacity = "0 0.005 0.01 0.02 0.04";
    /* values at the floor are transparent; opacity rises with concentration */
    snprintf(buf, cap, "kind %s\ncolormap %s\nrange %.9g %.9g\nscale %s\nopacity %s\n", kind, map, q->lo,
             q->hi > q->lo ? q->hi : q->lo + 1, q->scale == VSV_SCALE_LOG ? "log" : "linear", opacity);
}
