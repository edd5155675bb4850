/* vsv_tf.c — transfer functions: colour maps, the small text format, and
 * the lookup tables the renderers sample, and the opacity table. */
#include "vsv_tf_internal.h"
#include "vsv_common.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct cmap {
    const char *name;
    int n;
    unsigned rgb[10];
} cmap;

/* Perceptually uniform maps sampled at ten points (viridis, magma, cividis,
 * inferno, plasma: matplotlib's, by Stefan van der Walt and Nathaniel Smith,
 * CC0; cividis by Nuñez, Anderton and Renslow, PLOS ONE 2018), and simple
 * ramps for hydrometeors. New maps go last: the order decides which map a
 * species that shares one is given (vsv_tf_for_species). */
static const cmap maps[] = {
    {"viridis",
     10,
     {0x440154, 0x482878, 0x3e4989, 0x31688e, 0x26828e, 0x1f9e89, 0x35b779, 0x6ece58, 0xb5de2b, 0xfde725}},
    {"magma", 10, {0x000004, 0x180f3d, 0x440f76, 0x721f81, 0x9e2f7f, 0xcd4071, 0xf1605d, 0xfd9668, 0xfeca8d, 0xfcfdbf}},
    {"cividis",
     10,
     {0x00224e, 0x123570, 0x3b496c, 0x575d6d, 0x707173, 0x8a8779, 0xa69d75, 0xc4b56c, 0xe4cf5b, 0xfee838}},
    {"clouds", 2, {0x8c8c99, 0xffffff}},
    {"rain", 3, {0x1a3399, 0x3366cc, 0x66b3ff}},
    {"ice", 2, {0x12a89a, 0x7ff5dc}},
    {"snow", 2, {0x7a4fd0, 0xc4a8ff}},
    {"graupel", 2, {0xd9822b, 0xffd699}},
    {"greys", 2, {0x404040, 0xe0e0e0}},
    {"inferno",
     10,
     {0x000004, 0x1b0c41, 0x4a0c6b, 0x781c6d, 0xa52c60, 0xcf4446, 0xed6925, 0xfb9b06, 0xf7d13d, 0xfcffa4}},
    {"plasma",
     10,
     {0x0d0887, 0x47039f, 0x7301a8, 0x9c179e, 0xbd3786, 0xd8576b, 0xed7953, 0xfa9f3a, 0xfdc926, 0xf0f921}},
};

const char *const *vsv_tf_colormaps(void)
{
    static const char *names[sizeof maps / sizeof *maps + 1];
    for (size_t i = 0; i < sizeof maps / sizeof *maps; i++)
        names[i] = maps[i].name;
    return names;
}

static const cmap *find_map(const char *name)
{
    for (size_t i = 0; i < sizeof maps / sizeof *maps; i++)
        if (!strcmp(maps[i].name, name))
            return &maps[i];
    return NULL;
}

static void map_colour(const cmap *m, double t, float rgb[3])
{
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    const double x = t * (m->n - 1);
    int i = (int)x;
    if (i >= m->n - 1)
        i = m->n - 2;
    const double f = x - i;
    for (int c = 0; c < 3; c++) {
        const double a = (m->rgb[i] >> (16 - 8 * c) & 0xff) / 255.0, b = (m->rgb[i + 1] >> (16 - 8 * c) & 0xff) / 255.0;
        rgb[c] = (float)(a + (b - a) * f);
    }
}

int vsv_tf_prepare(vsv_tf *tf)
{
    const cmap *m = find_map(tf->colormap);
    if (!m || !(tf->hi > tf->lo) || !isfinite(tf->hi - tf->lo) || tf->nopacity < 2 || tf->nopacity > VSV_TF_MAXPTS ||
        (tf->scale == VSV_SCALE_LOG && !(tf->lo > 0)))
        return VSV_EINVAL;
    tf->base = tf->scale == VSV_SCALE_LOG ? log(tf->lo) : tf->lo;
    tf->inv = (VSV_TF_LUT - 1) / (tf->scale == VSV_SCALE_LOG ? log(tf->hi) - log(tf->lo) : tf->hi - tf->lo);
    for (int i = 0; i < VSV_TF_LUT; i++) {
        const double t = (double)i / (VSV_TF_LUT - 1);
        map_colour(m, t, tf->lut[i]);
        const double x = t * (tf->nopacity - 1);
        int k = (int)x;
        if (k >= tf->nopacity - 1)
            k = tf->nopacity - 2;
        const double f = x - k;
        tf->lut[i][3] = (float)(tf->opacity[k] + (tf->opacity[k + 1] - tf->opacity[k]) * f);
    }
    return 0;
}

void vsv_tf_eval(const vsv_tf *tf, float v, float rgba[4]) { vsv_tf_lookup(tf, v, rgba); }

int vsv_tf_parse(vsv_tf *tf, const char *text, char *msg, size_t cap)
{
    memset(tf, 0, sizeof *tf);
    snprintf(tf->colormap, sizeof tf->colormap, "viridis");
    tf->lo = 0;
    tf->hi = 1;
    tf->nopacity = 2;
    tf->opacity[0] = 0;
    tf->opacity[1] = 1;
    int line = 0;
    const char *p = text;
    while (*p) {
        line++;
        const char *e = strchr(p, '\n');
        size_t n = e ? (size_t)(e - p) : strlen(p);
        char buf[512];
        if (n >= sizeof buf)
            n = sizeof buf - 1;
        memcpy(buf, p, n);
        buf[n] = 0;
        p = e ? e + 1 : p + strlen(p);
        char *c = buf;
        while (isspace((unsigned char)*c))
            c++;
        if (!*c || *c == '#')
            continue;
        char key[32];
        int off = 0;
        if (sscanf(c, "%31s%n", key, &off) != 1)
            continue;
        char *rest = c + off;
        if (!strcmp(key, "colormap")) {
            char name[32];
            if (sscanf(rest, "%31s", name) != 1 || !find_map(name)) {
                snprintf(msg, cap, "line %d: unknown colour map", line);
                return VSV_EINVAL;
            }
            snprintf(tf->colormap, sizeof tf->colormap, "%s", name);
        } else if (!strcmp(key, "range")) {
            /* absolute values in the species' units: two finite numbers, nothing after */
            int used = 0;
            if (sscanf(rest, "%lf %lf %n", &tf->lo, &tf->hi, &used) != 2 || rest[used] || !(tf->hi > tf->lo) ||
                !isfinite(tf->hi - tf->lo)) {
                snprintf(msg, cap, "line %d: range needs finite LO HI with LO < HI (the species' units, nothing after)",
                         line);
                return VSV_EINVAL;
            }
        } else if (!strcmp(key, "scale")) {
            if (strstr(rest, "log"))
                tf->scale = VSV_SCALE_LOG;
            else if (strstr(rest, "linear"))
                tf->scale = VSV_SCALE_LINEAR;
            else {
                snprintf(msg, cap, "line %d: scale is linear or log", line);
                return VSV_EINVAL;
            }
        } else if (!strcmp(key, "opacity")) {
            int k = 0;
            char *q = rest, *end;
            for (;;) {
                errno = 0;
                double v = strtod(q, &end);
                if (end == q)
                    break;
                if (k >= VSV_TF_MAXPTS || !(v >= 0) || !(v <= 1)) {
                    snprintf(msg, cap, "line %d: opacity takes 2..%d values in [0, 1]", line, VSV_TF_MAXPTS);
                    return VSV_EINVAL;
                }
                tf->opacity[k++] = (float)v;
                q = end;
            }
            if (k < 2) {
                snprintf(msg, cap, "line %d: opacity takes 2..%d values in [0, 1]", line, VSV_TF_MAXPTS);
                return VSV_EINVAL;
            }
            tf->nopacity = k;
        } else if (strcmp(key, "kind")) { /* "kind" (the default's origin) carries nothing to draw */
            snprintf(msg, cap, "line %d: unknown key '%s' (colormap, range, scale, opacity)", line, key);
            return VSV_EINVAL;
        }
    }
    if (tf->scale == VSV_SCALE_LOG && !(tf->lo > 0)) {
        snprintf(msg, cap, "a log scale needs a positive range");
        return VSV_EINVAL;
    }
    return vsv_tf_prepare(tf);
}

void vsv_tf_format(const vsv_tf *tf, char *buf, size_t cap)
{
    int n = snprintf(buf, cap, "colormap %s\nrange %.9g %.9g\nscale %s\nopacity", tf->colormap, tf->lo, tf->hi,
                     tf->scale == VSV_SCALE_LOG ? "log" : "linear");
    for (int i = 0; i < tf->nopacity && n > 0 && (size_t)n < cap; i++)
        n += snprintf(buf + n, cap - (size_t)n, " %g", tf->opacity[i]);
    if (n > 0 && (size_t)n < cap)
        snprintf(buf + n, cap - (size_t)n, "\n");
}

/* The first byte of the n bytes at s that no text holds, or -1: a control
 * byte but tab, CR and LF (NUL among them), DEL, a C1 control (U+0080..9F,
 * which terminals act on), or a byte that is not part of a well-formed
 * UTF-8 character (no overlong forms, surrogates or values past U+10FFFF):
 * µg/m³ in a comment is text, a PNG's 0x89 is not. */
static int binary_byte(const unsigned char *s, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        const unsigned c = s[i];
        if ((c < 0x20 && c != '\t' && c != '\r' && c != '\n') || c == 0x7f)
            return (int)c;
        if (c < 0x80)
            continue;
        /* the continuation bytes and the second one's range, by lead byte */
        size_t more = 0;
        unsigned lo = 0x80, hi = 0xbf;
        if (c >= 0xc2 && c <= 0xdf)
            more = 1, lo = c == 0xc2 ? 0xa0 : 0x80;
        else if (c >= 0xe0 && c <= 0xef)
            more = 2, lo = c == 0xe0 ? 0xa0 : 0x80, hi = c == 0xed ? 0x9f : 0xbf;
        else if (c >= 0xf0 && c <= 0xf4)
            more = 3, lo = c == 0xf0 ? 0x90 : 0x80, hi = c == 0xf4 ? 0x8f : 0xbf;
        if (!more || i + more >= n || s[i + 1] < lo || s[i + 1] > hi)
            return (int)c;
        for (size_t k = 2; k <= more; k++)
            if ((s[i + k] & 0xc0) != 0x80)
                return (int)c;
        i += more;
    }
    return -1;
}

/* Reads one line into line (cap bytes), NUL-terminated, its length with
 * the newline in *len (a NUL inside counts: fgets would hide it). 1, 0 at
 * the end of the file, -1 for a line of cap bytes or more. */
static int read_line(FILE *fp, char *line, size_t cap, size_t *len)
{
    size_t n = 0;
    int c = 0;
    while ((c = getc(fp)) != EOF) {
        if (n + 1 >= cap)
            return -1;
        line[n++] = (char)c;
        if (c == '\n')
            break;
    }
    line[n] = 0;
    *len = n;
    return n > 0;
}

int vsv_tf_file_block(const char *path, const char *species, char *buf, size_t cap, char *msg, size_t msgcap)
{
    char why[300];
    FILE *fp = vsv_input_fopen(path, "r", why, sizeof why); /* a directory read as no text before */
    if (!fp) {
        snprintf(msg, msgcap, "%s: %s", path, why);
        return VSV_EIO;
    }
    char line[4096];
    int in = 0, found = 0, any = 0, lineno = 0, emitted = 0, got;
    size_t n = 0, len;
    buf[0] = 0;
    while ((got = read_line(fp, line, sizeof line, &len))) {
        char name[128], word[64];
        lineno++;
        const int b = got < 0 ? -1 : binary_byte((const unsigned char *)line, len);
        if (got < 0 || b >= 0) { /* (never echoed: a binary file's bytes would garble the terminal) */
            if (got < 0)
                snprintf(msg, msgcap, "line %d: longer than %zu bytes: not a text file of transfer functions", lineno,
                         sizeof line - 1);
            else
                snprintf(msg, msgcap, "line %d: byte 0x%02x: not a text file of transfer functions (ASCII or UTF-8)",
                         lineno, b);
            fclose(fp);
            return VSV_EINVAL;
        }
        if (sscanf(line, " species %127s", name) == 1) {
            in = !strcmp(name, species);
            found |= in;
            any = 1;
            continue;
        }
        if (!any && sscanf(line, " %63s", word) == 1 && word[0] != '#') {
            snprintf(msg, msgcap, "line %d: '%s' before any 'species NAME' line", lineno, word);
            fclose(fp);
            return VSV_EINVAL;
        }
        /* the block's lines at their line numbers in the file (empty lines
         * before them), so that a parse error names the file's line */
        while (in && emitted < lineno - 1 && n + 1 < cap) {
            buf[n++] = '\n';
            buf[n] = 0;
            emitted++;
        }
        if (in && n + strlen(line) + 1 < cap) {
            memcpy(buf + n, line, strlen(line) + 1);
            n += strlen(line);
            if (!n || buf[n - 1] != '\n') {
                buf[n++] = '\n';
                buf[n] = 0;
            }
            emitted = lineno;
        }
    }
    const int bad = ferror(fp), e = errno;
    fclose(fp);
    if (bad) {
        snprintf(msg, msgcap, "%s: cannot read: %s", path, strerror(e));
        return VSV_EIO;
    }
    return found ? 0 : VSV_ENOTFOUND;
}

/* Species s's transfer function as written (the --tf file's block, the
 * file's own, or the default); *chosen: 1 when the --tf file gave it. */
static int written_tf(const vsv_file *f, int s, const char *tfpath, vsv_tf *tf, int *chosen, char *msg, size_t cap)
{
    const vsv_meta *m = vsv_file_meta(f);
    char text[4096], why[256], dflt[512];
    const char *src = m->tf && m->tf[s] ? m->tf[s] : NULL;
    *chosen = 0;
    if (tfpath) {
        const int rc = vsv_tf_file_block(tfpath, m->vars[s].name, text, sizeof text, why, sizeof why);
        if (rc == VSV_EIO || rc == VSV_EINVAL) {
            snprintf(msg, cap, "%s", why);
            return rc;
        }
        if (!rc)
            src = text, *chosen = 1;
    }
    if (!src) {
        vsv_tf_default(m->vars[s].name, vsv_file_quant(f, s), dflt, sizeof dflt);
        src = dflt;
    }
    if (vsv_tf_parse(tf, src, why, sizeof why)) {
        snprintf(msg, cap, "transfer function of %s: %s", m->vars[s].name, why);
        return VSV_EINVAL;
    }
    return 0;
}

int vsv_tf_for_species(const vsv_file *f, int s, const char *tfpath, vsv_tf *tf, char *msg, size_t cap)
{
    int chosen;
    int rc = written_tf(f, s, tfpath, tf, &chosen, msg, cap);
    if (rc || chosen)
        return rc;
    /* a colour map an earlier species already shows is swapped for the
     * first one none of them shows, so species drawn together stay apart
     * (the same choice in every tool: it depends on the file alone) */
    enum { MAXS = 64 };
    char shown[MAXS][32];
    const int n = s < MAXS ? s + 1 : MAXS;
    for (int e = 0; e < n; e++) {
        vsv_tf t;
        int c;
        char m2[256];
        if (e == n - 1)
            t = *tf, c = 0;
        else if (written_tf(f, e, tfpath, &t, &c, m2, sizeof m2))
            snprintf(t.colormap, sizeof t.colormap, "?");
        snprintf(shown[e], sizeof shown[e], "%s", t.colormap);
        int taken = 0;
        for (int u = 0; u < e && !c; u++)
            taken |= !strcmp(shown[u], shown[e]);
        for (const char *const *cm = vsv_tf_colormaps(); taken && *cm; cm++) {
            int free_map = 1;
            for (int u = 0; u < e; u++)
                free_map &= strcmp(shown[u], *cm) != 0;
            if (free_map) {
                snprintf(shown[e], sizeof shown[e], "%s", *cm);
                taken = 0;
            }
        }
    }
    if (strcmp(tf->colormap, shown[n - 1])) {
        snprintf(tf->colormap, sizeof tf->colormap, "%s", shown[n - 1]);
        rc = vsv_tf_prepare(tf) ? VSV_EINVAL : 0;
    }
    return rc;
}

int vsv_tf_change_parse(const char *opt, const char *arg, vsv_tf_change *c, char *msg, size_t cap)
{
    memset(c, 0, sizeof *c);
    const char *sep = strcmp(opt, "log") ? strpbrk(arg, !strcmp(opt, "range") ? ":=" : ":") : NULL;
    const size_t n = sep ? (size_t)(sep - arg) : strlen(arg);
    if (!n || n >= sizeof c->species || (strcmp(opt, "log") && !sep)) {
        snprintf(msg, cap, "--%s %s: expected %s", opt, arg,
                 !strcmp(opt, "log")        ? "a species name"
                 : !strcmp(opt, "colormap") ? "SPECIES:NAME"
                                            : "SPECIES:LO:HI");
        return VSV_EINVAL;
    }
    memcpy(c->species, arg, n);
    if (!strcmp(opt, "log")) {
        snprintf(c->line, sizeof c->line, "scale log");
    } else if (!strcmp(opt, "colormap")) {
        if (!find_map(sep + 1)) {
            char names[256] = "";
            for (const char *const *cm = vsv_tf_colormaps(); *cm; cm++)
                snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", *cm, cm[1] ? ", " : "");
            snprintf(msg, cap, "--colormap %s: no colour map '%s' (%s)", arg, sep + 1, names);
            return VSV_EINVAL;
        }
        snprintf(c->line, sizeof c->line, "colormap %s", sep + 1);
    } else if (!strcmp(opt, "range")) {
        double lo, hi;
        int used = 0;
        if (sscanf(sep + 1, "%lf:%lf%n", &lo, &hi, &used) != 2 || sep[1 + used] || !(lo < hi) || !isfinite(hi - lo)) {
            snprintf(msg, cap, "--range %s: expected SPECIES:LO:HI with LO < HI", arg);
            return VSV_EINVAL;
        }
        snprintf(c->line, sizeof c->line, "range %.17g %.17g", lo, hi);
    } else {
        snprintf(msg, cap, "--%s: not a transfer-function option", opt);
        return VSV_EINVAL;
    }
    return 0;
}

int vsv_tf_change_apply(vsv_tf *tf, const vsv_tf_change *c, char *msg, size_t cap)
{
    char text[1024], why[256];
    vsv_tf t = *tf;
    if (!strcmp(c->line, "scale log") && !(t.lo > 0)) {
        if (!(t.hi > 0)) {
            snprintf(msg, cap, "--log %s: its range (%g to %g) has nothing above 0 to put on a log scale", c->species,
                     t.lo, t.hi);
            return VSV_EINVAL;
        }
        t.lo = t.hi * 1e-4; /* four decades below the top */
    }
    vsv_tf_format(&t, text, sizeof text);
    snprintf(text + strlen(text), sizeof text - strlen(text), "\n%s\n", c->line);
    if (vsv_tf_parse(&t, text, why, sizeof why)) {
        snprintf(msg, cap, "%s: %s", c->species,
                 strstr(why, "log scale") ? "a log scale needs a range above 0 (--range SPECIES:LO:HI, LO > 0)" : why);
        return VSV_EINVAL;
    }
    *tf = t;
    return 0;
}

/* Largest opacity of a transfer function over the values [lo, hi]. */
float vsv_tf_max_opacity(const vsv_tf *tf, float lo, float hi)
{
    if (!(hi >= tf->lo))
        return 0; /* all below the range (or no data): transparent */
    double t0, t1;
    if (tf->scale == VSV_SCALE_LOG) {
        const double l0 = log(tf->lo), l1 = log(tf->hi);
        t0 = lo > 0 ? (log(lo) - l0) / (l1 - l0) : 0;
        t1 = (log(hi) - l0) / (l1 - l0);
    } else {
        t0 = (lo - tf->lo) / (tf->hi - tf->lo);
        t1 = (hi - tf->lo) / (tf->hi - tf->lo);
    }
    const int i0 = !(t0 > 0) ? 0 : t0 >= 1 ? VSV_TF_LUT - 1 : (int)(t0 * (VSV_TF_LUT - 1));
    const int i1 = t1 >= 1 ? VSV_TF_LUT - 1 : (int)ceil(t1 * (VSV_TF_LUT - 1));
    float m = 0;
    for (int i = i0; i <= i1; i++)
        m = tf->lut[i][3] > m ? tf->lut[i][3] : m;
    return m;
}

float vsv_opacity_table[VSV_OPACITY_N + 1];

static void opacity_fill(void)
{
    vsv_opacity_table[0] = 1;
    for (int i = 1; i <= VSV_OPACITY_N; i++) {
        const double u = i * (double)VSV_OPACITY_UMAX / VSV_OPACITY_N;
        vsv_opacity_table[i] = (float)(-expm1(-u) / u);
    }
}

void vsv_opacity_init(void)
{
    static pthread_once_t once = PTHREAD_ONCE_INIT;
    pthread_once(&once, opacity_fill);
}
