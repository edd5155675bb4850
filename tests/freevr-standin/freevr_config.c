/* freevr_config.c — the FreeVR stand-in's configuration: FreeVR's
 * configuration language (window, process, system, inputdevice and user
 * definitions, usesystem) read after FreeVR's own default (the one-window
 * simulator) from its files, $FREEVR and the arguments, and the simulator
 * with boring input when the system asked for is not defined. */
#include "freevr_standin.h"

#include <X11/Xlib.h>
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

config fvs_cfg;

enum { TK_END, TK_STR, TK_WORD, TK_PUNCT };
typedef struct {
    int type;
    char text[512];
} token;

typedef struct {
    token *t;
    int n, i;
} tokens;

static void tokenize(const char *s, tokens *out)
{
    int cap = 64;
    out->t = malloc((size_t)cap * sizeof *out->t);
    out->n = out->i = 0;
    for (;;) {
        while (*s && isspace((unsigned char)*s))
            s++;
        if (*s == '#' || (s[0] == '/' && s[1] == '/')) {
            s += strcspn(s, "\n");
            continue;
        }
        if (out->n + 1 >= cap) {
            cap *= 2;
            out->t = realloc(out->t, (size_t)cap * sizeof *out->t);
        }
        token *t = &out->t[out->n];
        size_t k = 0;
        if (!*s) {
            t->type = TK_END;
            t->text[0] = 0;
            return;
        }
        out->n++;
        if (*s == '"') {
            for (s++; *s && *s != '"'; s++)
                if (k + 1 < sizeof t->text)
                    t->text[k++] = *s;
            s += *s == '"';
            t->type = TK_STR;
        } else if (isalnum((unsigned char)*s) || strchr("_.-+", *s)) {
            for (; *s && (isalnum((unsigned char)*s) || strchr("_.-+", *s)); s++)
                if (k + 1 < sizeof t->text)
                    t->text[k++] = *s;
            t->type = TK_WORD;
        } else {
            t->text[k++] = *s++;
            t->type = TK_PUNCT;
        }
        t->text[k] = 0;
    }
}

static const token *peek(const tokens *tk) { return &tk->t[tk->i]; }
static const token *take(tokens *tk) { return tk->i < tk->n ? &tk->t[tk->i++] : &tk->t[tk->n]; }
static int is_punct(const token *t, char c) { return t->type == TK_PUNCT && t->text[0] == c; }

/* past the end of a statement (a ';' outside braces, or a closing brace) */
static void skip(tokens *tk)
{
    int depth = 0;
    while (peek(tk)->type != TK_END) {
        const token *t = take(tk);
        if (is_punct(t, '{'))
            depth++;
        else if (is_punct(t, '}') && --depth <= 0) {
            if (is_punct(peek(tk), ';'))
                take(tk);
            return;
        } else if (is_punct(t, ';') && depth == 0)
            return;
    }
}

/* the names in a list of strings / words ("a, b", "c") into out */
static int split_names(const char *text, char (*out)[NAMELEN], int n, int cap)
{
    for (const char *p = text; *p;) {
        p += strspn(p, ", \t");
        const size_t len = strcspn(p, ", \t");
        if (!len)
            break;
        if (n < cap)
            snprintf(out[n++], NAMELEN, "%.*s", (int)len, p);
        p += len;
    }
    return n;
}

static void parse_input(dev_def *d, const char *spec)
{
    /* "6sensor(sim6[0])": a 6-sensor, numbered in the order listed; the
     * stand-in reads no tracker, so each stays at its device's origin */
    if (!strncasecmp(spec, "6sensor(", 8)) {
        d->nsensor++;
        return;
    }
    /* "2switch(keyboard:key[Escape])" or "2switch(mouse:button[left])" */
    char what[64] = "";
    if (d->nin >= NSW || strncasecmp(spec, "2switch(", 8))
        return;
    const char *b = strchr(spec, '['), *e = b ? strchr(b, ']') : NULL;
    if (!b || !e)
        return;
    snprintf(what, sizeof what, "%.*s", (int)(e - b - 1), b + 1);
    if (strstr(spec, "mouse:")) {
        const int btn = !strcasecmp(what, "left")     ? 1
                        : !strcasecmp(what, "middle") ? 2
                        : !strcasecmp(what, "right")  ? 3
                                                      : atoi(what);
        if (btn >= 1 && btn <= 3)
            d->in[d->nin++].button = btn;
    } else if (strstr(spec, "keyboard:")) {
        const KeySym k = XStringToKeysym(what);
        if (k != NoSymbol) {
            d->in[d->nin].button = 0;
            d->in[d->nin++].keysym = k;
        }
    }
}

/* A visrenmode value: FreeVR's names (its visren usage notes: default,
 * mono, left, right, dualvp, dualfb, anaglyphic, checkerboard, vibrate);
 * those the stand-in does not simulate render mono. */
static int visren_mode(const char *v)
{
    static const struct {
        const char *name;
        int mode;
    } modes[] = {{"default", FVS_VISREN_DEFAULT}, {"mono", FVS_VISREN_MONO},     {"left", FVS_VISREN_LEFT},
                 {"right", FVS_VISREN_RIGHT},     {"dualvp", FVS_VISREN_DUALVP}, {"anaglyphic", FVS_VISREN_ANAGLYPHIC}};
    for (size_t i = 0; i < sizeof modes / sizeof modes[0]; i++)
        if (!strcasecmp(v, modes[i].name))
            return modes[i].mode;
    fprintf(stderr, "FreeVR stand-in: visrenmode \"%s\" is not simulated: mono\n", v);
    return FVS_VISREN_MONO;
}

/* One `key [= values];` inside a definition's braces. */
static void parse_item(tokens *tk, config *c, int kind, int idx)
{
    char key[NAMELEN], sub[NAMELEN] = "";
    snprintf(key, sizeof key, "%s", take(tk)->text);
    if (peek(tk)->type == TK_STR)
        snprintf(sub, sizeof sub, "%s", take(tk)->text);
    if (!is_punct(peek(tk), '=')) {
        skip(tk);
        return;
    }
    take(tk);
    token vals[32];
    int nv = 0;
    while (peek(tk)->type != TK_END && !is_punct(peek(tk), ';') && !is_punct(peek(tk), '}')) {
        const token *t = take(tk);
        if ((t->type == TK_STR || t->type == TK_WORD) && nv < 32)
            vals[nv++] = *t;
    }
    if (is_punct(peek(tk), ';'))
        take(tk);
    if (kind == 'w') {
        win_def *w = &c->win[idx];
        if (!strcasecmp(key, "mount") && nv)
            w->simulator = !strcasecmp(vals[0].text, "simulator");
        else if (!strcasecmp(key, "args") && nv) {
            const char *g = strstr(vals[0].text, "geometry");
            if (g && (g = strchr(g, '=')))
                sscanf(g + 1, " %dx%d+%d+%d", &w->w, &w->h, &w->x, &w->y);
        } else if (!strcasecmp(key, "rw2w_coords") && nv == 9) {
            for (int i = 0; i < 9; i++)
                w->c[i] = atof(vals[i].text);
        } else if (!strcasecmp(key, "visrenmode") && nv)
            w->visren = visren_mode(vals[0].text);
    } else if (kind == 'p') {
        proc_def *p = &c->proc[idx];
        if (!strcasecmp(key, "type") && nv)
            p->type = !strcasecmp(vals[0].text, "visren") ? 'v' : !strcasecmp(vals[0].text, "input") ? 'i' : 0;
        else if (!strcasecmp(key, "objects")) {
            p->nobj = 0;
            for (int i = 0; i < nv; i++)
                p->nobj = split_names(vals[i].text, p->obj, p->nobj, MAXWIN);
        } else if (!strcasecmp(key, "usecmin") && nv)
            p->usecmin = atol(vals[0].text);
    } else if (kind == 's') {
        sys_def *s = &c->sys[idx];
        if (!strcasecmp(key, "procs")) {
            s->nprocs = 0;
            for (int i = 0; i < nv; i++)
                s->nprocs = split_names(vals[i].text, s->procs, s->nprocs, MAXPROC);
        } else if (!strcasecmp(key, "visrenmode") && nv)
            s->visren = visren_mode(vals[0].text);
    } else if (kind == 'd') {
        dev_def *d = &c->dev[idx];
        if (!strcasecmp(key, "type") && nv)
            d->xwindows = !strcasecmp(vals[0].text, "xwindows");
        else if (!strcasecmp(key, "input") && sub[0] && nv)
            parse_input(d, vals[0].text);
        else if (!strcasecmp(key, "t2rw_translate") && nv == 3)
            for (int i = 0; i < 3; i++)
                d->t2rw[i] = atof(vals[i].text);
    } else if (kind == 'u') {
        if (!strcasecmp(key, "iod") && nv)
            c->iod = atof(vals[0].text);
    }
}

/* Finds or adds (cleared) a definition by name in a table of structs that
 * each start with their name; -1 when the table is full. */
static int slot(void *table, size_t size, int *n, int cap, const char *name)
{
    unsigned char *t = table;
    int i = 0;
    while (i < *n && strcmp((const char *)(t + (size_t)i * size), name))
        i++;
    if (i == *n) {
        if (*n == cap)
            return -1;
        (*n)++;
    }
    memset(t + (size_t)i * size, 0, size);
    snprintf((char *)(t + (size_t)i * size), NAMELEN, "%s", name);
    return i;
}

/* Reads one configuration text; returns how many statements it understood. */
static int parse_config(config *c, const char *text)
{
    tokens tk;
    int understood = 0;
    tokenize(text, &tk);
    while (peek(&tk)->type != TK_END) {
        const token *t = peek(&tk);
        if (t->type != TK_WORD) {
            skip(&tk);
            continue;
        }
        char what[NAMELEN];
        snprintf(what, sizeof what, "%s", take(&tk)->text);
        if (!strcasecmp(what, "usesystem") && peek(&tk)->type == TK_STR) {
            snprintf(c->use, sizeof c->use, "%s", take(&tk)->text);
            skip(&tk);
            understood++;
            continue;
        }
        const int kind = !strcasecmp(what, "window")        ? 'w'
                         : !strcasecmp(what, "process")     ? 'p'
                         : !strcasecmp(what, "system")      ? 's'
                         : !strcasecmp(what, "inputdevice") ? 'd'
                         : !strcasecmp(what, "user")        ? 'u'
                                                            : 0;
        if (!kind || peek(&tk)->type != TK_STR) {
            skip(&tk);
            continue;
        }
        char name[NAMELEN];
        snprintf(name, sizeof name, "%s", take(&tk)->text);
        if (!is_punct(peek(&tk), '=') || (take(&tk), !is_punct(peek(&tk), '{'))) {
            skip(&tk);
            continue;
        }
        take(&tk);
        const int idx = kind == 'w'   ? slot(c->win, sizeof c->win[0], &c->nwin, MAXWIN * 2, name)
                        : kind == 'p' ? slot(c->proc, sizeof c->proc[0], &c->nproc, MAXPROC, name)
                        : kind == 's' ? slot(c->sys, sizeof c->sys[0], &c->nsys, 8, name)
                        : kind == 'd' ? slot(c->dev, sizeof c->dev[0], &c->ndev, 8, name)
                                      : 0; /* the one user: only its iod is kept */
        if (idx < 0) {
            skip(&tk);
            continue;
        }
        if (kind == 'w') /* FreeVR's simulator window size until told */
            c->win[idx].w = 400, c->win[idx].h = 300;
        if (kind == 'p')
            c->proc[idx].usecmin = 16667;
        while (peek(&tk)->type != TK_END && !is_punct(peek(&tk), '}')) {
            if (peek(&tk)->type == TK_WORD)
                parse_item(&tk, c, kind, idx);
            else
                take(&tk);
        }
        take(&tk);
        if (is_punct(peek(&tk), ';'))
            take(&tk);
        understood++;
    }
    free(tk.t);
    return understood;
}

/* FreeVR's default configuration, read before any other (its user guide's
 * start-up report: "Reading string "Default Config String"" then "Using
 * system 'simulator'"). */
static const char SIMULATOR[] =
    "usesystem \"simulator\";\n"
    "system \"simulator\" = { type = \"simulator\"; procs = \"sim-render\", \"sim-input\"; }\n"
    "window \"simulator\" = { mount = \"simulator\"; GraphicsType = \"glx\";"
    " args = \"geometry=400x300+0+0; decoration=window\"; }\n"
    "process \"sim-render\" = { type = visren; objects = \"simulator\"; }\n"
    "process \"sim-input\" = { type = input; usecmin = 16667; objects = \"xin\"; }\n"
    "inputdevice \"xin\" = { type = \"xwindows\"; args = \"window = simulator;\";\n"
    "  input \"Escape Key\" = \"2switch(keyboard:key[Escape])\";\n"
    "  input \"left\" = \"2switch(mouse:button[left])\";\n"
    "  input \"middle\" = \"2switch(mouse:button[middle])\";\n"
    "  input \"right\" = \"2switch(mouse:button[right])\";\n"
    "  input \"head\" = \"6sensor(sim6[0])\";\n"
    "  input \"wand\" = \"6sensor(sim6[1])\"; }\n";

/* What FreeVR runs when `usesystem` names a system that is not defined
 * (FREEVR.md, "A named system that is not defined"): one simulator window
 * and an input process whose input maps nothing, so Escape does nothing. */
static const char BORING[] =
    "usesystem \"default\";\n"
    "system \"default\" = { type = \"simulator\"; procs = \"default-render\", \"default-input\"; }\n"
    "window \"simulator\" = { mount = \"simulator\"; GraphicsType = \"glx\";"
    " args = \"geometry=400x300+0+0; decoration=window\"; }\n"
    "process \"default-render\" = { type = visren; objects = \"simulator\"; }\n"
    "process \"default-input\" = { type = input; usecmin = 16667; }\n";

static char *read_file(const char *dir, const char *name)
{
    char path[4096];
    if (!dir || !*dir)
        return NULL;
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *fp = fopen(path, "r");
    if (!fp)
        return NULL;
    fseek(fp, 0, SEEK_END);
    const long n = ftell(fp);
    fseek(fp, 0, SEEK_SET);
    char *buf = n >= 0 ? malloc((size_t)n + 1) : NULL;
    if (buf) {
        const size_t got = fread(buf, 1, (size_t)n, fp);
        buf[got] = 0;
    }
    fclose(fp);
    return buf;
}

const proc_def *fvs_find_proc(const char *name)
{
    for (int i = 0; i < fvs_cfg.nproc; i++)
        if (!strcmp(fvs_cfg.proc[i].name, name))
            return &fvs_cfg.proc[i];
    return NULL;
}

const win_def *fvs_find_win(const char *name)
{
    for (int i = 0; i < fvs_cfg.nwin; i++)
        if (!strcmp(fvs_cfg.win[i].name, name))
            return &fvs_cfg.win[i];
    return NULL;
}

const dev_def *fvs_find_dev(const char *name)
{
    for (int i = 0; i < fvs_cfg.ndev; i++)
        if (!strcmp(fvs_cfg.dev[i].name, name))
            return &fvs_cfg.dev[i];
    return NULL;
}

const sys_def *fvs_used_system(void)
{
    for (int i = 0; i < fvs_cfg.nsys; i++)
        if (!strcmp(fvs_cfg.sys[i].name, fvs_cfg.use))
            return &fvs_cfg.sys[i];
    return NULL;
}

int fvs_config_count(int type)
{
    const sys_def *sys = fvs_used_system();
    int n = 0;
    for (int k = 0; sys && k < sys->nprocs; k++) {
        const proc_def *p = fvs_find_proc(sys->procs[k]);
        if (p && p->type == 'v' && type == 'v')
            n += p->nobj;
        for (int i = 0; p && p->type == 'i' && type == 'i' && i < p->nobj; i++) {
            const dev_def *d = fvs_find_dev(p->obj[i]);
            n += d && d->xwindows ? d->nin : 0;
        }
    }
    return n;
}

int fvs_config_visren(const win_def *w)
{
    const sys_def *sys = fvs_used_system();
    if (w->visren != FVS_VISREN_DEFAULT)
        return w->visren;
    if (sys && sys->visren != FVS_VISREN_DEFAULT)
        return sys->visren;
    return FVS_VISREN_MONO;
}

int fvs_config_sensor(int n, double pos[3])
{
    const sys_def *sys = fvs_used_system();
    pos[0] = pos[1] = pos[2] = 0;
    for (int k = 0; sys && k < sys->nprocs; k++) {
        const proc_def *p = fvs_find_proc(sys->procs[k]);
        for (int i = 0; p && p->type == 'i' && i < p->nobj; i++) {
            const dev_def *d = fvs_find_dev(p->obj[i]);
            if (!d)
                continue;
            if (n < d->nsensor) {
                memcpy(pos, d->t2rw, 3 * sizeof(double));
                return 1;
            }
            n -= d->nsensor;
        }
    }
    return 0;
}

void fvs_config_load(int *argc, char **argv)
{
    memset(&fvs_cfg, 0, sizeof fvs_cfg);
    fvs_cfg.iod = FVS_DEFAULT_IOD;
    parse_config(&fvs_cfg, SIMULATOR);
    const char *dirs[3] = {getenv("FREEVR_HOME"), getenv("HOME"), "."};
    for (int i = 0; i < 3; i++) {
        char *text = read_file(dirs[i], ".freevrrc");
        if (text) {
            parse_config(&fvs_cfg, text);
            free(text);
        }
    }
    if (getenv("FREEVR"))
        parse_config(&fvs_cfg, getenv("FREEVR"));
    /* every argument is a configuration string; none is removed */
    for (int i = 1; argc && i < *argc; i++)
        if (parse_config(&fvs_cfg, argv[i]) == 0)
            fprintf(stderr, "FreeVR: warning: cannot understand the configuration string '%s'\n", argv[i]);
    if (!fvs_used_system()) {
        /* FreeVR's words (FREEVR.md, "A named system that is not defined") */
        fprintf(stderr, "FreeVR config: could not find system \"%s\", using default (with boring input)\n",
                fvs_cfg.use);
        const double iod = fvs_cfg.iod;
        memset(&fvs_cfg, 0, sizeof fvs_cfg);
        fvs_cfg.iod = iod;
        parse_config(&fvs_cfg, BORING);
    }
}
