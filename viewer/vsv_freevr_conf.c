/* vsv_freevr_conf.c — see vsv_freevr_conf.h. A small tokenizer (strings,
 * words, punctuation; # and // comments) and a statement reader that keeps
 * only what decides the window count. */
#include "vsv_freevr_conf.h"

#include <ctype.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>

#define NAMELEN 64
#define MAXDEF 256
#define MAXPROCS 64

typedef struct {
    char name[NAMELEN];
    int visren, objects;
} proc_def;

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
    char windows[MAXDEF][NAMELEN];
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
        if (kind == 's' && !strcasecmp(key, "procs"))
            c->systems[idx].nprocs = 0;
        while (lx->type != T_END && !punct(lx, ';') && !punct(lx, '}')) {
            if (lx->type == T_STR || lx->type == T_WORD) {
                if (kind == 'p' && !strcasecmp(key, "type"))
                    c->procs[idx].visren = !strcasecmp(lx->text, "visren");
                else if (kind == 'p' && !strcasecmp(key, "objects"))
                    c->procs[idx].objects += names(lx->text, NULL, NULL, 0);
                else if (kind == 's' && !strcasecmp(key, "procs"))
                    names(lx->text, c->systems[idx].procs, &c->systems[idx].nprocs, MAXPROCS);
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
        const int kind = !strcasecmp(what, "process") ? 'p'
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
            while (i < c->nwindows && strcmp(c->windows[i], name))
                i++;
            if (i == c->nwindows && c->nwindows < MAXDEF)
                snprintf(c->windows[c->nwindows++], NAMELEN, "%s", name);
            skip_statement(&lx);
            continue;
        }
        if (kind == 'p') {
            while (i < c->nprocs && strcmp(c->procs[i].name, name))
                i++;
            if (i == c->nprocs) {
                if (c->nprocs == MAXDEF) {
                    skip_statement(&lx);
                    continue;
                }
                c->nprocs++;
            }
            c->procs[i] = (proc_def){{0}, 0, 0};
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

void vsv_freevr_layout_count(const char *const *texts, int n, vsv_freevr_layout *out)
{
    static conf c; /* large; the back end calls this once, before any fork */
    memset(&c, 0, sizeof c);
    for (int i = 0; i < n; i++)
        if (texts[i])
            read_text(&c, texts[i]);
    *out = (vsv_freevr_layout){1, 1, 0};
    for (int s = 0; c.use[0] && s < c.nsystems; s++) {
        if (strcmp(c.systems[s].name, c.use))
            continue;
        int w = 0, v = 0;
        for (int k = 0; k < c.systems[s].nprocs; k++)
            for (int p = 0; p < c.nprocs; p++)
                if (!strcmp(c.procs[p].name, c.systems[s].procs[k]) && c.procs[p].visren) {
                    v++;
                    w += c.procs[p].objects > 0 ? c.procs[p].objects : 1;
                }
        if (v > 0) {
            *out = (vsv_freevr_layout){w, v, 1};
            return;
        }
    }
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
