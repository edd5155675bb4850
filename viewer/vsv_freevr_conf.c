/* vsv_freevr_conf.c — see vsv_freevr_conf.h. A small tokenizer (strings,
 * words, punctuation; # and // comments) and a statement reader that keeps
 * only what decides the window count. */
#include "vsv_freevr_conf.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define NAMELEN 64
#define MAXDEF 256
#define MAXPROCS 64

typedef struct {
    char name[NAMELEN];
    int visren, objects;
    char obj[16][NAMELEN]; /* the first 16 windows it draws */
    int nobj;
} proc_def;

typedef struct {
    char name[NAMELEN];
    int fixed;    /* mount = "fixed" (a wall) */
    int w, h;     /* geometry=WxH..., 0 when not given */
    int ncorners; /* numbers of rw2w_coords read (9: all) */
    double c[9];  /* lower-left, lower-right, upper-left corners (feet) */
} win_def;

typedef struct {
    char name[NAMELEN];
    int nprocs;
    char procs[MAXPROCS][NAMELEN];
} sys_def;

typedef struct {
    char use[NAMELEN];
    proc_def procs[MAXDEF];
    int nprocs;
    sys_def systems[16];
    int nsystems;
    win_def windows[MAXDEF];
    int nwindows;
} conf;

enum { T_END, T_STR, T_WORD, T_PUNCT };

typedef struct {
    const char *s;
    int type;
    char text[256];
} lexer;

static int next(lexer *lx)
{
    for (;;) {
        while (*lx->s && isspace((unsigned char)*lx->s))
            lx->s++;
        if (*lx->s == '#' || (lx->s[0] == '/' && lx->s[1] == '/')) {
            lx->s += strcspn(lx->s, "\n");
            continue;
        }
        break;
    }
    size_t n = 0;
    const char *s = lx->s;
    if (!*s)
        return lx->type = T_END;
    if (*s == '"') {
        for (s++; *s && *s != '"'; s++)
            if (n + 1 < sizeof lx->text)
                lx->text[n++] = *s;
        lx->text[n] = 0;
        lx->s = *s ? s + 1 : s;
        return lx->type = T_STR;
    }
    if (isalnum((unsigned char)*s) || strchr("_.-+", *s)) {
        while (*s && (isalnum((unsigned char)*s) || strchr("_.-+", *s))) {
            if (n + 1 < sizeof lx->text)
                lx->text[n++] = *s;
            s++;
        }
        lx->text[n] = 0;
        lx->s = s;
        return lx->type = T_WORD;
    }
    lx->text[0] = *s, lx->text[1] = 0;
    lx->s = s + 1;
    return lx->type = T_PUNCT;
}

static int punct(const lexer *lx, char c) { return lx->type == T_PUNCT && lx->text[0] == c; }

/* Skips to the end of the statement: past the ';' at brace depth 0, or past
 * a closing brace that ends a block statement with no ';'. */
static void skip_statement(lexer *lx)
{
    int depth = 0;
    while (lx->type != T_END) {
        if (punct(lx, '{'))
            depth++;
        else if (punct(lx, '}') && --depth <= 0) {
            next(lx);
            if (punct(lx, ';'))
                next(lx);
            return;
        } else if (punct(lx, ';') && depth == 0) {
            next(lx);
            return;
        }
        next(lx);
    }
}

/* Adds the names in a string ("a, b c") or a word to list (may be NULL);
 * returns how many. */
static int names(const char *text, char (*list)[NAMELEN], int *n, int cap)
{
    int count = 0;
    for (const char *p = text; *p;) {
        p += strspn(p, ", \t");
        const size_t len = strcspn(p, ", \t");
        if (!len)
            break;
        if (list && *n < cap) {
            snprintf(list[*n], NAMELEN, "%.*s", (int)len, p);
            (*n)++;
        }
        count++;
        p += len;
    }
    return count;
}

/* One value of a window's key: its mount, its size from the args'
 * "geometry=WxH+X+Y", and its corners (rw2w_coords: nine numbers, read one
 * word at a time since the lexer splits them at the commas). */
static void window_value(win_def *w, const char *key, const char *text)
{
    if (!strcasecmp(key, "mount"))
        w->fixed = !strcasecmp(text, "fixed");
    else if (!strcasecmp(key, "args")) {
        const char *g = strstr(text, "geometry");
        int gw, gh;
        if (g && (g = strchr(g, '=')) && sscanf(g + 1, " %dx%d", &gw, &gh) == 2 && gw > 0 && gh > 0)
            w->w = gw, w->h = gh;
    } else if (!strcasecmp(key, "rw2w_coords") && w->ncorners < 9) {
        char *end;
        const double v = strtod(text, &end);
        if (end != text && !*end)
            w->c[w->ncorners++] = v;
    }
}

/* Reads `{ key = values; ... }` after the '=' of a definition, calling
 * back for each key with the lexer on its first value. */
static void read_block(lexer *lx, conf *c, int kind, int idx)
{
    if (!punct(lx, '{')) {
        skip_statement(lx);
        return;
    }
    next(lx);
    while (lx->type != T_END && !punct(lx, '}')) {
        char key[64];
        if (lx->type != T_WORD && lx->type != T_STR) {
            next(lx);
            continue;
        }
        snprintf(key, sizeof key, "%s", lx->text);
        next(lx);
        if (!punct(lx, '=')) {
            skip_statement(lx);
            continue;
        }
        next(lx);
        if (kind == 'p' && !strcasecmp(key, "objects"))
            c->procs[idx].objects = 0;
        if (kind == 'p' && !strcasecmp(key, "objects"))
            c->procs[idx].nobj = 0;
        if (kind == 's' && !strcasecmp(key, "procs"))
            c->systems[idx].nprocs = 0;
        if (kind == 'w' && !strcasecmp(key, "rw2w_coords"))
            c->windows[idx].ncorners = 0;
        while (lx->type != T_END && !punct(lx, ';') && !punct(lx, '}')) {
            if (lx->type == T_STR || lx->type == T_WORD) {
                if (kind == 'p' && !strcasecmp(key, "type"))
                    c->procs[idx].visren = !strcasecmp(lx->text, "visren");
                else if (kind == 'p' && !strcasecmp(key, "objects"))
                    c->procs[idx].objects += names(lx->text, c->procs[idx].obj, &c->procs[idx].nobj, 16);
                else if (kind == 's' && !strcasecmp(key, "procs"))
                    names(lx->text, c->systems[idx].procs, &c->systems[idx].nprocs, MAXPROCS);
                else if (kind == 'w')
                    window_value(&c->windows[idx], key, lx->text);
            }
            next(lx);
        }
        if (punct(lx, ';'))
            next(lx);
    }
    if (punct(lx, '}'))
        next(lx);
    if (punct(lx, ';'))
        next(lx);
}

static void read_text(conf *c, const char *text)
{
    lexer lx = {text, T_END, ""};
    next(&lx);
    while (lx.type != T_END) {
        if (lx.type != T_WORD) {
            skip_statement(&lx);
            continue;
        }
        char what[32];
        snprintf(what, sizeof what, "%s", lx.text);
        next(&lx);
        if (!strcasecmp(what, "usesystem") && lx.type == T_STR) {
            snprintf(c->use, sizeof c->use, "%s", lx.text);
            skip_statement(&lx);
            continue;
        }
        const int kind = !strcasecmp(what, "process")  ? 'p'
                         : !strcasecmp(what, "system") ? 's'
                         : !strcasecmp(what, "window") ? 'w'
                                                       : 0;
        if (!kind || lx.type != T_STR) {
            skip_statement(&lx);
            continue;
        }
        char name[NAMELEN];
        snprintf(name, sizeof name, "%s", lx.text);
        next(&lx);
        if (!punct(&lx, '=')) {
            skip_statement(&lx);
            continue;
        }
        next(&lx);
        int i = 0;
        if (kind == 'w') {
            while (i < c->nwindows && strcmp(c->windows[i].name, name))
                i++;
            if (i == c->nwindows) {
                if (c->nwindows == MAXDEF) {
                    skip_statement(&lx);
                    continue;
                }
                c->nwindows++;
            }
            c->windows[i] = (win_def){{0}, 0, 0, 0, 0, {0}};
            snprintf(c->windows[i].name, NAMELEN, "%s", name);
        } else if (kind == 'p') {
            while (i < c->nprocs && strcmp(c->procs[i].name, name))
                i++;
            if (i == c->nprocs) {
                if (c->nprocs == MAXDEF) {
                    skip_statement(&lx);
                    continue;
                }
                c->nprocs++;
            }
            memset(&c->procs[i], 0, sizeof c->procs[i]);
            snprintf(c->procs[i].name, NAMELEN, "%s", name);
        } else {
            while (i < c->nsystems && strcmp(c->systems[i].name, name))
                i++;
            if (i == c->nsystems) {
                if (c->nsystems == (int)(sizeof c->systems / sizeof c->systems[0])) {
                    skip_statement(&lx);
                    continue;
                }
                c->nsystems++;
            }
            memset(&c->systems[i], 0, sizeof c->systems[i]);
            snprintf(c->systems[i].name, NAMELEN, "%s", name);
        }
        read_block(&lx, c, kind, i);
    }
}

/* The used system's fixed walls: the room's box (feet) and the lowest
 * pixel density among them (pixels per foot along the wall's width and
 * height), into out. */
static void walls(const conf *c, const sys_def *sys, vsv_freevr_layout *out)
{
    double lo[3] = {1e30, 1e30, 1e30}, hi[3] = {-1e30, -1e30, -1e30}, dens = 0;
    int n = 0;
    for (int k = 0; k < sys->nprocs; k++)
        for (int p = 0; p < c->nprocs; p++) {
            if (strcmp(c->procs[p].name, sys->procs[k]) || !c->procs[p].visren)
                continue;
            for (int o = 0; o < c->procs[p].nobj; o++)
                for (int wi = 0; wi < c->nwindows; wi++) {
                    const win_def *w = &c->windows[wi];
                    if (strcmp(w->name, c->procs[p].obj[o]) || !w->fixed || w->ncorners < 9)
                        continue;
                    double wide = 0, tall = 0;
                    for (int a = 0; a < 3; a++) {
                        const double ur = w->c[3 + a] + w->c[6 + a] - w->c[a]; /* the fourth corner */
                        const double v[4] = {w->c[a], w->c[3 + a], w->c[6 + a], ur};
                        for (int q = 0; q < 4; q++)
                            lo[a] = v[q] < lo[a] ? v[q] : lo[a], hi[a] = v[q] > hi[a] ? v[q] : hi[a];
                        wide += (w->c[3 + a] - w->c[a]) * (w->c[3 + a] - w->c[a]);
                        tall += (w->c[6 + a] - w->c[a]) * (w->c[6 + a] - w->c[a]);
                    }
                    n++;
                    if (w->w > 0 && w->h > 0 && wide > 0 && tall > 0) {
                        const double dw = w->w / sqrt(wide), dh = w->h / sqrt(tall);
                        const double d = dw < dh ? dw : dh;
                        dens = dens == 0 || d < dens ? d : dens;
                    }
                }
        }
    out->walls = n;
    out->px_per_ft = dens;
    if (n) {
        for (int a = 0; a < 3; a++)
            out->room_lo[a] = lo[a], out->room_hi[a] = hi[a];
        /* walls alone (a single front wall, say) span no depth: the room
         * reaches as deep in front of them as the walls are wide */
        for (int a = 0; a < 3; a += 2)
            if (out->room_hi[a] - out->room_lo[a] < 1e-6) {
                const double span = out->room_hi[2 - a] - out->room_lo[2 - a];
                out->room_hi[a] = out->room_lo[a] + (span > 0 ? span : 10);
            }
    }
}

void vsv_freevr_layout_count(const char *const *texts, int n, vsv_freevr_layout *out)
{
    static conf c; /* large; the back end calls this once, before any fork */
    memset(&c, 0, sizeof c);
    for (int i = 0; i < n; i++)
        if (texts[i])
            read_text(&c, texts[i]);
    memset(out, 0, sizeof *out);
    out->windows = out->visren = 1;
    /* FreeVR's default room: a 10-foot CAVE, the floor's centre at 0 */
    const double lo[3] = {-5, 0, -5}, hi[3] = {5, 10, 5};
    memcpy(out->room_lo, lo, sizeof lo);
    memcpy(out->room_hi, hi, sizeof hi);
    int found = 0;
    for (int s = 0; c.use[0] && s < c.nsystems; s++) {
        if (strcmp(c.systems[s].name, c.use))
            continue;
        found = 1;
        int w = 0, v = 0;
        for (int k = 0; k < c.systems[s].nprocs; k++)
            for (int p = 0; p < c.nprocs; p++)
                if (!strcmp(c.procs[p].name, c.systems[s].procs[k]) && c.procs[p].visren) {
                    v++;
                    w += c.procs[p].objects > 0 ? c.procs[p].objects : 1;
                }
        if (v > 0) {
            out->windows = w, out->visren = v, out->explicit = 1;
            walls(&c, &c.systems[s], out);
            return;
        }
    }
    if (c.use[0] && !found && strcasecmp(c.use, "simulator"))
        snprintf(out->missing, sizeof out->missing, "%s", c.use);
    /* no usable system: an upper bound from everything defined */
    int w = 0, v = 0;
    for (int p = 0; p < c.nprocs; p++)
        if (c.procs[p].visren) {
            v++;
            w += c.procs[p].objects > 0 ? c.procs[p].objects : 1;
        }
    out->visren = v > 1 ? v : 1;
    out->windows = w > c.nwindows ? w : c.nwindows;
    if (out->windows < out->visren)
        out->windows = out->visren;
}

unsigned long vsv_freevr_arena_bytes(const vsv_freevr_layout *l, unsigned long app)
{
    const unsigned long floor = 16ul << 20;
    const unsigned long need = (1ul << 20) + (unsigned long)l->windows * (256ul << 10) + app;
    return need > floor ? need : floor;
}
