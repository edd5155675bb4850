/* vsv_derive.c — derived variables at conversion (--derive): a spec
 * NAME=EXPR[:UNITS] compiled by vsv_expr.c over the file's 3-D fields and
 * `pressure`, or a built-in written as such an expression for the model at
 * hand; the inputs each needs read once per frame, selected or not.
 *
 * Built-ins (vsv-convert(1) says the same):
 *   condensate  the sum of the hydrometeor mixing ratios present (MM5 CLW RNW
 *               ICE SNOW GRAUPEL, WRF QCLOUD QRAIN QICE QSNOW QGRAUP), kg/kg
 *   wind_speed  sqrt(U^2+V^2) of the winds as the source gives them, at mass
 *               points (MM5 dot points and WRF faces averaged), m/s
 *   theta       T*(100000/pressure)^0.2857, K; WRF: T+300 (its T is theta-300)
 *   rh          100*e/es, e = Q*pressure/(0.622+Q), es = 611.2*exp(17.67*
 *               (T-273.15)/(T-29.65)) Pa (Bolton 1980, over water), %, not
 *               clipped; WRF: T = (T+300)*(pressure/100000)^0.2857; CAMx:
 *               e = HUMIDITY*1e-6*pressure (HUMIDITY a mole fraction in ppm)
 * pressure (Pa): MM5 PSTARCRS*SIGMAH+PTOP+PP (vsv_mm5_pressure), WRF P+PB,
 * CAMx (--met) PRESS*100. */
#include "vsv_derive.h"
#include "vsv_common.h"
#include "vsv_source_internal.h"

#include <ctype.h>
#include <stdlib.h>
#include <string.h>

enum { MAX_DERIVED = 32, MAX_INPUTS = 64 };
/* how the model's pressure is had */
enum { PRES_NONE, PRES_MM5, PRES_SUM, PRES_SCALE };
#define PRESSURE "pressure"

typedef struct derived {
    vsv_var var;
    char formula[256];
    vsv_expr *e;
    int nnames;
    int *slot;         /* per name of the compile table: input slot, or -1 */
    const float **ptr; /* per name: that slot's buffer, set per frame */
} derived;

struct vsv_derive {
    derived v[MAX_DERIVED];
    int n;
    char in[MAX_INPUTS][64]; /* the inputs: field names, and PRESSURE */
    float *buf[MAX_INPUTS];
    int nin;
    int pres;     /* PRES_*, when PRESSURE is an input */
    size_t cells; /* of the buffers, allocated at the first frame */
};

vsv_derive *vsv_derive_create(void) { return calloc(1, sizeof(vsv_derive)); }
int vsv_derive_count(const vsv_derive *d) { return d->n; }
const vsv_var *vsv_derive_var(const vsv_derive *d, int i) { return &d->v[i].var; }
const char *vsv_derive_formula(const vsv_derive *d, int i) { return d->v[i].formula; }

void vsv_derive_free(vsv_derive *d)
{
    if (!d)
        return;
    for (int i = 0; i < d->n; i++) {
        vsv_expr_free(d->v[i].e);
        free(d->v[i].slot);
        free(d->v[i].ptr);
    }
    for (int i = 0; i < d->nin; i++)
        free(d->buf[i]);
    free(d);
}

static int has(const vsv_source *s, const char *name)
{
    const int f = vsv_source_find_field(s, name);
    return f >= 0 && vsv_source_field(s, f)->is_volume;
}

/* How s gives the pressure (PRES_*), with the formula said in the file. */
static int pressure_how(const vsv_source *s, const char **how)
{
    const vsv_meta *g = vsv_source_grid(s);
    if (!strcmp(g->model, "MM5 v3") && has(s, "PP") && g->vert_kind != VSV_VERT_INDEX && !has(s, PRESSURE)) {
        *how = "PSTARCRS*SIGMAH+PTOP+PP";
        return PRES_MM5;
    }
    if (has(s, "P") && has(s, "PB")) {
        *how = "P+PB";
        return PRES_SUM;
    }
    if (has(s, "PRESS")) {
        *how = "PRESS*100";
        return PRES_SCALE;
    }
    *how = NULL;
    return PRES_NONE;
}

/* What s lacks to have a pressure, for the messages. */
static const char *no_pressure(const vsv_source *s)
{
    const char *model = vsv_source_grid(s)->model;
    if (!strcmp(model, "MM5 v3"))
        return vsv_source_grid(s)->vert_kind == VSV_VERT_INDEX
                   ? "sigma levels with a reference state (pressure = PSTARCRS*SIGMAH+PTOP+PP)"
                   : "PP (pressure = PSTARCRS*SIGMAH+PTOP+PP)";
    if (!strcmp(model, "WRF"))
        return "P or PB (pressure = P+PB)";
    if (!strcmp(model, "CAMx"))
        return "PRESS (pressure = PRESS*100 from the height/pressure file: --met)";
    return "a pressure (MM5: PP; WRF: P and PB; CAMx: PRESS of --met)";
}

/* A built-in's expression for s into expr (cap bytes), its units and title;
 * 1 if name is no built-in; VSV_ENOTFOUND naming what s lacks. */
static int builtin(const vsv_source *s, const char *name, char *expr, size_t cap, const char **units,
                   const char **title, char *msg, size_t mcap)
{
    const char *fmt = vsv_source_format(s);
    if (!strcmp(name, "condensate")) {
        static const char *const q[] = {"CLW",    "RNW",   "ICE",  "SNOW",  "GRAUPEL",
                                        "QCLOUD", "QRAIN", "QICE", "QSNOW", "QGRAUP"};
        expr[0] = 0;
        for (size_t i = 0; i < sizeof q / sizeof *q; i++)
            if (has(s, q[i]))
                snprintf(expr + strlen(expr), cap - strlen(expr), "%s%s", expr[0] ? "+" : "", q[i]);
        *units = "kg kg-1", *title = "total condensate";
        if (!expr[0])
            vsv_msg(msg, mcap,
                    "--derive condensate: this %s file has no hydrometeor mixing ratio (MM5: CLW RNW ICE SNOW "
                    "GRAUPEL; WRF: QCLOUD QRAIN QICE QSNOW QGRAUP)",
                    fmt);
        return expr[0] ? 0 : VSV_ENOTFOUND;
    }
    if (!strcmp(name, "wind_speed")) {
        const int mcip = !has(s, "U") && has(s, "UWIND") && has(s, "VWIND");
        *units = "m s-1", *title = "wind speed at mass points";
        if (!mcip && !(has(s, "U") && has(s, "V"))) {
            vsv_msg(msg, mcap, "--derive wind_speed: this %s file has no 3-D U and V (nor UWIND and VWIND)", fmt);
            return VSV_ENOTFOUND;
        }
        vsv_msg(expr, cap, mcip ? "sqrt(UWIND^2+VWIND^2)" : "sqrt(U^2+V^2)");
        return 0;
    }
    const int theta = !strcmp(name, "theta");
    if (!theta && strcmp(name, "rh"))
        return 1;
    const char *how;
    const int wrf = !strcmp(vsv_source_grid(s)->model, "WRF"), camx = has(s, "TEMP");
    const char *t = camx ? "TEMP" : "T", *q = wrf ? "QVAPOR" : camx ? "HUMIDITY" : "Q";
    const int need_p = !(theta && wrf) && pressure_how(s, &how) == PRES_NONE;
    if (!has(s, t) || (!theta && !has(s, q)) || need_p) {
        char lack[256] = "";
        if (!has(s, t))
            snprintf(lack, sizeof lack, "%s", t);
        if (!theta && !has(s, q))
            snprintf(lack + strlen(lack), sizeof lack - strlen(lack), "%s%s", lack[0] ? ", " : "", q);
        if (need_p)
            snprintf(lack + strlen(lack), sizeof lack - strlen(lack), "%s%s", lack[0] ? ", " : "", no_pressure(s));
        vsv_msg(msg, mcap, "--derive %s: this %s file lacks %s (%s needs %s%s%s and the pressure)", name, fmt, lack,
                name, t, theta ? "" : " ", theta ? "" : q);
        return VSV_ENOTFOUND;
    }
    if (theta) {
        *units = "K", *title = wrf ? "potential temperature (WRF's T is theta-300)" : "potential temperature";
        vsv_msg(expr, cap, wrf ? "T+300" : "%s*(100000/" PRESSURE ")^0.2857", t);
        return 0;
    }
    *units = "%", *title = "relative humidity over water (Bolton 1980), not clipped";
    /* es of Bolton (1980) in Pa; e from the mixing ratio (MM5, WRF) or the
     * mole fraction in ppm (CAMx) */
    const char *tk = wrf ? "((T+300)*(" PRESSURE "/100000)^0.2857)" : t;
    char e[96];
    if (camx)
        vsv_msg(e, sizeof e, "HUMIDITY*1e-6*" PRESSURE);
    else
        vsv_msg(e, sizeof e, "%s*" PRESSURE "/(0.622+%s)", q, q);
    vsv_msg(expr, cap, "100*(%s)/(611.2*exp(17.67*(%s-273.15)/(%s-29.65)))", e, tk, tk);
    return 0;
}

/* The input slot of name, added when new; -1 when full. */
static int slot_of(vsv_derive *d, const char *name)
{
    for (int i = 0; i < d->nin; i++)
        if (!strcmp(d->in[i], name))
            return i;
    if (d->nin >= MAX_INPUTS)
        return -1;
    snprintf(d->in[d->nin], sizeof d->in[0], "%s", name);
    return d->nin++;
}

/* NAME=EXPR[:UNITS] or a built-in: its parts; 0 or VSV_EINVAL. */
static int split(const char *spec, char *name, size_t ncap, const char **expr, size_t *elen, char *units, size_t ucap,
                 char *msg, size_t cap)
{
    const char *eq = strchr(spec, '=');
    const size_t n = eq ? (size_t)(eq - spec) : strlen(spec);
    int ok = n > 0 && n < ncap && n <= 55 && (spec[0] == '_' || isalpha((unsigned char)spec[0]));
    for (size_t i = 0; ok && i < n; i++)
        ok = spec[i] == '_' || spec[i] == '.' || isalnum((unsigned char)spec[i]);
    if (!ok)
        return vsv_msg(msg, cap,
                       "--derive '%s': the name must be 1 to 55 letters, digits, '_' or '.', starting with a letter "
                       "(NAME=EXPR[:UNITS], or condensate, wind_speed, theta, rh)",
                       spec),
               VSV_EINVAL;
    memcpy(name, spec, n);
    name[n] = 0;
    units[0] = 0;
    *expr = eq ? eq + 1 : NULL;
    *elen = eq ? strlen(eq + 1) : 0;
    const char *colon = eq ? strrchr(eq + 1, ':') : NULL;
    if (colon) {
        if (strlen(colon + 1) >= ucap)
            return vsv_msg(msg, cap, "--derive '%s': units longer than %zu characters", spec, ucap - 1), VSV_EINVAL;
        snprintf(units, ucap, "%s", colon + 1);
        *elen = (size_t)(colon - (eq + 1));
        for (const unsigned char *u = (const unsigned char *)units; *u; u++)
            if (*u < 0x20 || *u == 0x7f) /* (the file would refuse them, naming only a variable number) */
                return vsv_msg(msg, cap, "--derive %s: its units hold control byte 0x%02x (at character %d)", name, *u,
                               (int)(u - (const unsigned char *)units) + 1),
                       VSV_EINVAL;
    }
    if (eq && *elen > 200)
        return vsv_msg(msg, cap, "--derive '%s': the expression is longer than 200 characters", spec), VSV_EINVAL;
    return 0;
}

/* The compile table: s's 3-D fields, and PRESSURE unless one is so named. */
static const char **names_of(const vsv_source *s, int *n)
{
    const char **names = calloc((size_t)vsv_source_nfields(s) + 1, sizeof *names);
    *n = 0;
    for (int i = 0; names && i < vsv_source_nfields(s); i++)
        if (vsv_source_field(s, i)->is_volume)
            names[(*n)++] = vsv_source_field(s, i)->name;
    if (names && !has(s, PRESSURE))
        names[(*n)++] = PRESSURE;
    return names;
}

/* An unknown name: the message says what the file has. */
static void unknown(const vsv_source *s, const char *spec, const char *what, int at, char *msg, size_t cap)
{
    size_t n = (size_t)snprintf(msg, cap, "--derive '%s': %s at character %d; the file's 3-D fields:", spec, what, at);
    for (int i = 0; i < vsv_source_nfields(s) && n < cap; i++)
        if (vsv_source_field(s, i)->is_volume)
            n += (size_t)snprintf(msg + n, cap - n, " %s", vsv_source_field(s, i)->name);
    const char *how;
    if (n < cap && pressure_how(s, &how) != PRES_NONE)
        snprintf(msg + n, cap - n, "; and " PRESSURE " (%s)", how);
}

/* The variable's description and formula: the expression, with what
 * pressure is when used; a title first where it fits. */
static void describe(derived *v, const char *title, const char *expr, const char *how)
{
    char f[256], whole[256], desc[sizeof v->var.description];
    snprintf(f, sizeof f, "%s%s%s%s", expr, how ? "; " PRESSURE " = " : "", how ? how : "", how ? " (Pa)" : "");
    snprintf(whole, sizeof whole, "%s%s%s", title ? title : "", title ? ": " : "", f);
    if (strlen(whole) < sizeof desc)
        snprintf(desc, sizeof desc, "%s", whole);
    else if (strlen(f) < sizeof desc)
        snprintf(desc, sizeof desc, "%s", f);
    else
        snprintf(desc, sizeof desc, "%s (formula: attribute \"derived %s\")", title ? title : "derived", v->var.name);
    memcpy(v->formula, whole, sizeof whole);
    memcpy(v->var.description, desc, sizeof desc);
}

int vsv_derive_add(vsv_derive *d, const vsv_source *s, const vsv_meta *m, const char *spec, char *msg, size_t cap)
{
    if (d->n >= MAX_DERIVED)
        return vsv_msg(msg, cap, "more than %d --derive", MAX_DERIVED), VSV_EINVAL;
    derived *v = &d->v[d->n];
    memset(v, 0, sizeof *v);
    if (cap)
        msg[0] = 0;
    const int nin0 = d->nin; /* a spec refused adds no input */
    const char *etext, *units = NULL, *title = NULL;
    size_t elen;
    int rc = split(spec, v->var.name, sizeof v->var.name, &etext, &elen, v->var.units, sizeof v->var.units, msg, cap);
    if (rc)
        return rc;
    int taken = vsv_source_find_field(s, v->var.name) >= 0 || !strncmp(v->var.name, "wind.", 5);
    for (int i = 0; i < m->nvars; i++)
        taken |= !strcmp(m->vars[i].name, v->var.name);
    for (int i = 0; i < d->n; i++)
        taken |= !strcmp(d->v[i].var.name, v->var.name);
    if (taken)
        return vsv_msg(msg, cap,
                       "--derive '%s': %s is taken (a field of %s, a variable or wind.*): choose another name", spec,
                       v->var.name, vsv_source_format(s)),
               VSV_EINVAL;
    static const char *const builtins[] = {"condensate", "wind_speed", "theta", "rh"};
    for (size_t i = 0; etext && i < sizeof builtins / sizeof *builtins; i++)
        if (!strcmp(v->var.name, builtins[i]))
            return vsv_msg(msg, cap,
                           "--derive '%s': %s is a built-in's name (--derive %s): an expression takes another, so a "
                           "file's %s is always the built-in",
                           spec, v->var.name, v->var.name, v->var.name),
                   VSV_EINVAL;
    char text[256];
    if (!etext) {
        if ((rc = builtin(s, v->var.name, text, sizeof text, &units, &title, msg, cap)) == 1)
            return vsv_msg(msg, cap,
                           "--derive '%s': no such built-in (condensate, wind_speed, theta, rh); an expression is "
                           "NAME=EXPR[:UNITS]",
                           spec),
                   VSV_EINVAL;
        if (rc)
            return rc;
        snprintf(v->var.units, sizeof v->var.units, "%s", units);
    } else {
        memcpy(text, etext, elen);
        text[elen] = 0;
    }
    int nnames, pos;
    const char **names = names_of(s, &nnames);
    if (!names)
        return vsv_msg(msg, cap, "--derive '%s': out of memory", spec), VSV_ENOMEM;
    char why[160];
    rc = vsv_expr_compile(text, names, nnames, &v->e, why, sizeof why, &pos);
    const int off = etext ? (int)(etext - spec) : 0;
    if (rc == VSV_EINVAL && !strncmp(why, "unknown name", 12)) {
        unknown(s, spec, why, off + pos, msg, cap);
        rc = VSV_ENOTFOUND;
    } else if (rc == VSV_EINVAL) {
        vsv_msg(msg, cap, "--derive '%s': %s at character %d", spec, why, off + pos);
    }
    const char *how = NULL;
    const int pi = nnames - 1; /* PRESSURE, when it is the table's own */
    if (!rc && !has(s, PRESSURE) && vsv_expr_uses(v->e, pi)) {
        d->pres = pressure_how(s, &how);
        if (d->pres == PRES_NONE)
            rc = VSV_ENOTFOUND, vsv_msg(msg, cap, "--derive '%s': pressure: this %s file lacks %s", spec,
                                        vsv_source_format(s), no_pressure(s));
        /* the fields the pressure is made of are inputs before it */
        static const char *const parts[][2] = {{NULL, NULL}, {NULL, NULL}, {"P", "PB"}, {"PRESS", NULL}};
        for (int k = 0; k < 2 && !rc && parts[d->pres][k]; k++)
            if (slot_of(d, parts[d->pres][k]) < 0)
                rc = VSV_EINVAL;
    }
    if (!rc &&
        (!(v->slot = malloc((size_t)nnames * sizeof *v->slot)) || !(v->ptr = calloc((size_t)nnames, sizeof *v->ptr))))
        rc = VSV_ENOMEM;
    for (int i = 0; !rc && i < nnames; i++)
        if ((v->slot[i] = vsv_expr_uses(v->e, i) ? slot_of(d, names[i]) : -1) < 0 && vsv_expr_uses(v->e, i))
            rc = VSV_EINVAL;
    if (rc == VSV_EINVAL && !*msg)
        vsv_msg(msg, cap, "--derive '%s': more than %d input fields in all", spec, MAX_INPUTS);
    if (rc == VSV_ENOMEM)
        vsv_msg(msg, cap, "--derive '%s': out of memory", spec);
    v->nnames = nnames;
    free(names);
    if (rc) {
        d->nin = nin0;
        vsv_expr_free(v->e);
        free(v->slot);
        free(v->ptr);
        return rc;
    }
    describe(v, title, text, how);
    d->n++;
    return 0;
}

const char *vsv_derive_missing(const vsv_derive *d, const vsv_source *s)
{
    for (int i = 0; i < d->nin; i++)
        if (strcmp(d->in[i], PRESSURE) && !has(s, d->in[i]))
            return d->in[i];
    return NULL;
}

/* The pressure from the inputs read (P and PB, PRESS) or the MM5 source. */
static int pressure(vsv_derive *d, vsv_source *s, int t, float *out)
{
    if (d->pres == PRES_MM5)
        return vsv_mm5_pressure(s, t, out);
    const float *a = d->buf[slot_of(d, d->pres == PRES_SUM ? "P" : "PRESS")];
    const float *b = d->pres == PRES_SUM ? d->buf[slot_of(d, "PB")] : NULL;
    for (size_t c = 0; c < d->cells; c++)
        out[c] = b ? a[c] + b[c] : a[c] * 100.0f; /* mb → Pa */
    return 0;
}

int vsv_derive_frame(vsv_derive *d, vsv_source *s, int t, float *const *out, char *msg, size_t cap)
{
    const vsv_meta *g = vsv_source_grid(s);
    const size_t cells = (size_t)g->nx * g->ny * g->nz;
    /* the buffers of the inputs: at the first frame (and for inputs added
     * since, or a grid of another size) */
    for (int i = 0; i < d->nin; i++)
        if (!d->buf[i] || d->cells != cells) {
            free(d->buf[i]);
            if (!(d->buf[i] = malloc(cells * sizeof(float))))
                return vsv_msg(msg, cap, "out of memory"), VSV_ENOMEM;
        }
    d->cells = cells;
    int pslot = -1, rc = 0;
    for (int i = 0; i < d->nin && !rc; i++) {
        if (!strcmp(d->in[i], PRESSURE) && !has(s, PRESSURE)) {
            pslot = i;
            continue;
        }
        const int f = vsv_source_find_field(s, d->in[i]);
        rc = f < 0 ? vsv_source_fail(s, VSV_ENOTFOUND, "no field %s (an input of --derive)", d->in[i])
                   : vsv_source_read(s, f, t, d->buf[i]);
    }
    if (!rc && pslot >= 0)
        rc = pressure(d, s, t, d->buf[pslot]);
    if (rc)
        return vsv_msg(msg, cap, "%s", vsv_source_error(s)), rc;
    for (int k = 0; k < d->n; k++) {
        derived *v = &d->v[k];
        for (int i = 0; i < v->nnames; i++)
            v->ptr[i] = v->slot[i] >= 0 ? d->buf[v->slot[i]] : NULL;
        vsv_expr_eval(v->e, v->ptr, cells, out[k]);
    }
    return 0;
}
