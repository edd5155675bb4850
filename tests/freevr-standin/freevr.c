/* freevr.c — the test stand-in for FreeVR: the calls the FreeVR back end
 * uses (declared in viewer/freevr/freevr.h, installed as this stand-in's
 * freevr.h), written by the project from ../shared/docs/FREEVR.md alone. It
 * is NOT FreeVR: it exists so that `make test` can run vsv-play-freevr under
 * Xvfb and look at what each wall shows. Built by `make test`, never
 * installed. It behaves the way that page says FreeVR behaves wherever that
 * decides what a wall shows:
 *
 *  - real-world units are feet (the CAVE a 10-foot cube, the floor y = 0);
 *  - configuration in FreeVR's syntax from $FREEVR_HOME/.freevrrc,
 *    $HOME/.freevrrc, ./.freevrrc, the FREEVR variable, then every
 *    command-line argument (none removed; a warning for each one not
 *    understood); none at all: a one-window simulator;
 *  - vrConfigure creates one SysV semaphore set of 250 semaphores; vrExit
 *    removes it (a process that exits without vrExit leaves it);
 *  - one shared arena of exactly the size the first vrShmemInit asked for
 *    (16 MiB by default), from which the stand-in takes its own state too:
 *    445,000 bytes at vrConfigure and, in each render process, its share of
 *    the per-window state measured with FreeVR (525 KB in all with one
 *    window, 765 KB with four, 1,049,736 bytes with eight); when it is full
 *    it prints "Not enough room to amalloc", and a render process that
 *    cannot get its state waits forever (so vrExit never returns);
 *  - vrStart forks one render process per visren process, each opening its
 *    own GLX windows and contexts (named "FreeVR(pid): NAME window"), and one
 *    input process polling the X server every usecmin microseconds (16,667:
 *    60 Hz); Escape is 2switch 0, and vrFrame returns 0 once it is pressed;
 *  - before each eye's display callback it loads glFrustum(near 0.1, far
 *    1000) for that wall from its rw2w_coords corners and the head, and the
 *    modelview (the wall's axes times a translation by minus the eye); it
 *    never clears the colour or depth buffer.
 * Simplifications, all outside what a wall shows: one (mono) eye; the
 * simulated head stays at (0, 5, 0) feet; the simulator window looks from
 * (0, 7, 12) at (0, 4, -3); an xwindows device's 2switches are numbered in
 * the order its inputs are listed; locks are exclusive.
 *
 * Test aid (not FreeVR): with FREEVR_STANDIN_DUMP=DIR every frame of every
 * window is written, as glReadPixels sees the back buffer just before the
 * swap, to DIR/NAME.ppm (a "# frame N" comment counts the frames). */
#include <freevr.h>

#include <GL/gl.h>
#include <GL/glx.h>
#include <X11/Xlib.h>
#include <X11/keysym.h>
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/sem.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

/* what FreeVR loads into OpenGL before each eye's display callback (the
 * header leaves vrRenderInfo opaque: the back end reads the GL matrices) */
typedef struct vrPerspective {
    struct {
        struct {
            double left, right, bottom, top;
        } n;
        double near_clip, far_clip;
    } frustum;
    double eye[3];       /* the eye in real-world feet */
    vrMatrix rw2w_xform; /* real world -> the wall's frame */
} vrPerspective;

struct vrRenderInfo {
    vrPerspective *persp;
    const char *window; /* the window's name */
    int eye;            /* 0: the stand-in renders one (mono) eye */
};

#define NEAR_CLIP 0.1
#define FAR_CLIP 1000.0
#define NSEMS 250
#define BASE_STATE 445000ul
#define MAXWIN 32
#define MAXPROC 40
#define NAMELEN 64
#define NSW 16
#define NVAL 8

/* ---------------------------------------------------------- configuration */

typedef struct {
    char name[NAMELEN];
    int simulator;  /* mount = "simulator" (else fixed) */
    int w, h, x, y; /* geometry */
    double c[9];    /* rw2w_coords: lower-left, lower-right, upper-left */
} win_def;

typedef struct {
    char name[NAMELEN];
    int type; /* 'v' visren, 'i' input, 0 other */
    int nobj;
    char obj[MAXWIN][NAMELEN];
    long usecmin;
} proc_def;

typedef struct {
    char name[NAMELEN];
    int nprocs;
    char procs[MAXPROC][NAMELEN];
} sys_def;

typedef struct {
    char name[NAMELEN];
    int xwindows, nin;
    struct {
        int button;         /* 1..3: a mouse button, else a key */
        unsigned long keysym;
    } in[NSW];
} dev_def;

typedef struct {
    char use[NAMELEN];
    win_def win[MAXWIN * 2];
    int nwin;
    proc_def proc[MAXPROC];
    int nproc;
    sys_def sys[8];
    int nsys;
    dev_def dev[8];
    int ndev;
} config;

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
    /* "2switch(keyboard:key[Escape])" or "2switch(mouse:button[left])" */
    char what[64] = "";
    if (d->nin >= NSW || strncasecmp(spec, "2switch(", 8))
        return;
    const char *b = strchr(spec, '['), *e = b ? strchr(b, ']') : NULL;
    if (!b || !e)
        return;
    snprintf(what, sizeof what, "%.*s", (int)(e - b - 1), b + 1);
    if (strstr(spec, "mouse:")) {
        const int btn = !strcasecmp(what, "left") ? 1 : !strcasecmp(what, "middle") ? 2 : !strcasecmp(what, "right") ? 3 : atoi(what);
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
        } else if (!strcasecmp(key, "rw2w_coords") && nv == 9)
            for (int i = 0; i < 9; i++)
                w->c[i] = atof(vals[i].text);
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
        }
    } else if (kind == 'd') {
        dev_def *d = &c->dev[idx];
        if (!strcasecmp(key, "type") && nv)
            d->xwindows = !strcasecmp(vals[0].text, "xwindows");
        else if (!strcasecmp(key, "input") && sub[0] && nv)
            parse_input(d, vals[0].text);
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
                                      : slot(c->dev, sizeof c->dev[0], &c->ndev, 8, name);
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
    "  input \"right\" = \"2switch(mouse:button[right])\"; }\n";

/* ------------------------------------------------------------- the arena */

typedef struct {
    size_t used, cap;
} arena_head;

/* FreeVR's own state at the start of the arena's first allocation */
typedef struct {
    volatile int quit, started;
    volatile int sw[NSW];
    volatile float val[NVAL];
    double head[3], wand[3];
    double start;
    int nextlock;
    double travel[16];
} base_state;

static size_t g_arena_size = 16ul << 20;
static int g_arena_asked;
static unsigned char *g_arena;
static int g_semid = -1;
static base_state *g_base;
static config g_cfg;
static pid_t g_main, g_children[MAXPROC + 1];
static int g_nchildren;
static size_t g_per_window;
static int g_nwin_used, g_nswitches;

static void sem_add(int idx, int delta)
{
    struct sembuf op = {(unsigned short)idx, (short)delta, SEM_UNDO};
    while (semop(g_semid, &op, 1) == -1 && errno == EINTR)
        ;
}

/* FreeVR's allocator over the shared arena (semaphore 0 guards it). */
static void *amalloc(size_t n)
{
    arena_head *h = (arena_head *)g_arena;
    sem_add(0, -1);
    const size_t off = (h->used + 15) & ~(size_t)15;
    if (off > h->cap || n > h->cap - off) {
        const size_t used = h->used;
        sem_add(0, 1);
        fprintf(stderr, "FreeVR: Not enough room to amalloc %zu bytes (arena of %zu bytes, %zu used)\n", n, h->cap,
                used);
        return NULL;
    }
    h->used = off + n;
    sem_add(0, 1);
    memset(g_arena + off, 0, n);
    return g_arena + off;
}

/* FreeVR's per-window state as measured: 525,000 bytes in all with one
 * window, 765,000 with four, 1,049,736 with eight (linear between, and
 * beyond eight at the last slope), less the base state. */
static size_t per_window_state(int windows)
{
    double total;
    if (windows <= 1)
        total = 525000;
    else if (windows <= 4)
        total = 525000 + (windows - 1) * 80000.0;
    else
        total = 765000 + (windows - 4) * 71184.0;
    return (size_t)((total - BASE_STATE) / (windows > 0 ? windows : 1));
}

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* ------------------------------------------------------------- callbacks */

struct vrCallback {
    void (*fn)(void);
    int argc;
    void *args[4];
};

static vrCallback g_cb[VRFUNC_DISPLAY_EXIT + 1];

static void call0(const vrCallback *cb)
{
    void *const *a = cb->args;
    switch (cb->argc) {
    case 0: ((void (*)(void))cb->fn)(); break;
    case 1: ((void (*)(void *))cb->fn)(a[0]); break;
    case 2: ((void (*)(void *, void *))cb->fn)(a[0], a[1]); break;
    case 3: ((void (*)(void *, void *, void *))cb->fn)(a[0], a[1], a[2]); break;
    default: ((void (*)(void *, void *, void *, void *))cb->fn)(a[0], a[1], a[2], a[3]); break;
    }
}

static void call_ri(const vrCallback *cb, vrRenderInfo *ri)
{
    void *const *a = cb->args;
    switch (cb->argc) {
    case 0: ((void (*)(vrRenderInfo *))cb->fn)(ri); break;
    case 1: ((void (*)(vrRenderInfo *, void *))cb->fn)(ri, a[0]); break;
    case 2: ((void (*)(vrRenderInfo *, void *, void *))cb->fn)(ri, a[0], a[1]); break;
    case 3: ((void (*)(vrRenderInfo *, void *, void *, void *))cb->fn)(ri, a[0], a[1], a[2]); break;
    default: ((void (*)(vrRenderInfo *, void *, void *, void *, void *))cb->fn)(ri, a[0], a[1], a[2], a[3]); break;
    }
}

/* FreeVR's callback functions are unprototyped (void (*)()) */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wstrict-prototypes"
static void store(vrCallback *cb, void (*fn)(), int argc, va_list ap)
{
    cb->fn = (void (*)(void))fn;
    cb->argc = argc < 0 ? 0 : argc > 4 ? 4 : argc;
    for (int i = 0; i < cb->argc; i++)
        cb->args[i] = va_arg(ap, void *);
}

void vrCallbackSet(vrFuncType type, char *name, void (*fn)(), int argc, ...)
{
    (void)name;
    va_list ap;
    va_start(ap, argc);
    if ((int)type >= 0 && type <= VRFUNC_DISPLAY_EXIT)
        store(&g_cb[type], fn, argc, ap);
    va_end(ap);
}

vrCallback *vrCallbackCreate(void (*fn)(), int argc, ...)
{
    vrCallback *cb = calloc(1, sizeof *cb);
    va_list ap;
    va_start(ap, argc);
    if (cb)
        store(cb, fn, argc, ap);
    va_end(ap);
    return cb;
}
#pragma GCC diagnostic pop

void vrFunctionSetCallback(vrFuncType type, vrCallback *cb)
{
    if (cb && (int)type >= 0 && type <= VRFUNC_DISPLAY_EXIT)
        g_cb[type] = *cb;
}

/* ------------------------------------------------------------ life cycle */

long vrShmemInit(size_t bytes)
{
    if (!g_arena_asked && !g_arena) { /* only the first call counts */
        g_arena_asked = 1;
        g_arena_size = bytes;
    }
    return (long)g_arena_size;
}

void *vrShmemAlloc0(size_t bytes)
{
    if (!g_arena) {
        fprintf(stderr, "FreeVR: vrShmemAlloc0 before vrConfigure\n");
        return NULL;
    }
    return amalloc(bytes);
}

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

static const proc_def *find_proc(const char *name)
{
    for (int i = 0; i < g_cfg.nproc; i++)
        if (!strcmp(g_cfg.proc[i].name, name))
            return &g_cfg.proc[i];
    return NULL;
}

static const win_def *find_win(const char *name)
{
    for (int i = 0; i < g_cfg.nwin; i++)
        if (!strcmp(g_cfg.win[i].name, name))
            return &g_cfg.win[i];
    return NULL;
}

static const dev_def *find_dev(const char *name)
{
    for (int i = 0; i < g_cfg.ndev; i++)
        if (!strcmp(g_cfg.dev[i].name, name))
            return &g_cfg.dev[i];
    return NULL;
}

static const sys_def *used_system(void)
{
    for (int i = 0; i < g_cfg.nsys; i++)
        if (!strcmp(g_cfg.sys[i].name, g_cfg.use))
            return &g_cfg.sys[i];
    return NULL;
}

vrContextInfo *vrConfigure(int *argc, char **argv, char **appargs)
{
    (void)appargs;
    g_main = getpid();
    int found = 0;
    const char *dirs[3] = {getenv("FREEVR_HOME"), getenv("HOME"), "."};
    for (int i = 0; i < 3; i++) {
        char *text = read_file(dirs[i], ".freevrrc");
        if (text) {
            parse_config(&g_cfg, text);
            found = 1;
            free(text);
        }
    }
    if (getenv("FREEVR")) {
        parse_config(&g_cfg, getenv("FREEVR"));
        found = 1;
    }
    /* every argument is a configuration string; none is removed */
    for (int i = 1; argc && i < *argc; i++) {
        if (parse_config(&g_cfg, argv[i]) == 0)
            fprintf(stderr, "FreeVR: warning: cannot understand the configuration string '%s'\n", argv[i]);
        else
            found = 1;
    }
    if (!found || !used_system()) {
        if (found)
            fprintf(stderr, "FreeVR: no system '%s' defined: running the simulator\n", g_cfg.use);
        config sim;
        memset(&sim, 0, sizeof sim);
        parse_config(&sim, SIMULATOR);
        g_cfg = sim;
    }
    const sys_def *sys = used_system();
    for (int k = 0; k < sys->nprocs; k++) {
        const proc_def *p = find_proc(sys->procs[k]);
        if (p && p->type == 'v')
            g_nwin_used += p->nobj;
        for (int i = 0; p && p->type == 'i' && i < p->nobj; i++) {
            const dev_def *d = find_dev(p->obj[i]);
            g_nswitches += d && d->xwindows ? d->nin : 0;
        }
    }
    /* the arena: exactly the size the first vrShmemInit asked for */
    g_arena = mmap(NULL, g_arena_size, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
    if (g_arena == MAP_FAILED || g_arena_size < sizeof(arena_head)) {
        fprintf(stderr, "FreeVR: cannot map a shared arena of %zu bytes\n", g_arena_size);
        exit(1);
    }
    ((arena_head *)g_arena)->used = sizeof(arena_head);
    ((arena_head *)g_arena)->cap = g_arena_size;
    g_semid = semget(IPC_PRIVATE, NSEMS, IPC_CREAT | 0600);
    if (g_semid < 0) {
        perror("FreeVR: semget");
        exit(1);
    }
    for (int i = 0; i < NSEMS; i++)
        semctl(g_semid, i, SETVAL, 1);
    fprintf(stderr, "FreeVR stand-in: semaphore set %d (%d semaphores), arena %zu bytes, %d window%s\n", g_semid,
            NSEMS, g_arena_size, g_nwin_used, g_nwin_used == 1 ? "" : "s");
    g_base = amalloc(BASE_STATE);
    if (!g_base) {
        for (;;)
            pause();
    }
    g_base->start = now_s();
    g_base->head[0] = 0, g_base->head[1] = 5, g_base->head[2] = 0;
    g_base->wand[0] = 1, g_base->wand[1] = 4, g_base->wand[2] = -1;
    g_base->nextlock = 1;
    for (int i = 0; i < 16; i++)
        g_base->travel[i] = i % 5 == 0;
    g_per_window = per_window_state(g_nwin_used);
    return (vrContextInfo *)g_base;
}

/* ------------------------------------------------------------ projection */

static void sub3(const double *a, const double *b, double *o) { o[0] = a[0] - b[0], o[1] = a[1] - b[1], o[2] = a[2] - b[2]; }
static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static void cross3(const double *a, const double *b, double *o)
{
    o[0] = a[1] * b[2] - a[2] * b[1], o[1] = a[2] * b[0] - a[0] * b[2], o[2] = a[0] * b[1] - a[1] * b[0];
}
static void norm3(double *a)
{
    const double l = sqrt(dot3(a, a));
    if (l > 0)
        a[0] /= l, a[1] /= l, a[2] /= l;
}

/* The eye's frustum and the real world -> wall rotation for a window:
 * fixed walls from their corners and the head (an off-axis frustum on the
 * wall's plane); the simulator from its own viewpoint (60 degrees high). */
static void perspective(const win_def *w, int width, int height, vrPerspective *p)
{
    double r[3], u[3], n[3], e[3];
    if (w->simulator) {
        const double from[3] = {0, 7, 12}, at[3] = {0, 4, -3}, up[3] = {0, 1, 0};
        memcpy(e, from, sizeof e);
        sub3(from, at, n);
        norm3(n);
        cross3(up, n, r);
        norm3(r);
        cross3(n, r, u);
        const double t = NEAR_CLIP * tan(30 * M_PI / 180), a = (double)width / (height > 0 ? height : 1);
        p->frustum.n.left = -t * a, p->frustum.n.right = t * a, p->frustum.n.bottom = -t, p->frustum.n.top = t;
    } else {
        const double *ll = w->c, *lr = w->c + 3, *ul = w->c + 6;
        double va[3], vb[3], vc[3];
        memcpy(e, g_base->head, sizeof e);
        sub3(lr, ll, r);
        norm3(r);
        sub3(ul, ll, u);
        norm3(u);
        cross3(r, u, n); /* towards the viewer */
        norm3(n);
        sub3(ll, e, va);
        sub3(lr, e, vb);
        sub3(ul, e, vc);
        double d = -dot3(va, n);
        if (!(fabs(d) > 1e-6))
            d = 1e-6;
        p->frustum.n.left = dot3(r, va) * NEAR_CLIP / d;
        p->frustum.n.right = dot3(r, vb) * NEAR_CLIP / d;
        p->frustum.n.bottom = dot3(u, va) * NEAR_CLIP / d;
        p->frustum.n.top = dot3(u, vc) * NEAR_CLIP / d;
    }
    p->frustum.near_clip = NEAR_CLIP;
    p->frustum.far_clip = FAR_CLIP;
    memcpy(p->eye, e, sizeof p->eye);
    double *m = p->rw2w_xform.v;
    memset(m, 0, sizeof p->rw2w_xform.v);
    for (int i = 0; i < 3; i++)
        m[i * 4 + 0] = r[i], m[i * 4 + 1] = u[i], m[i * 4 + 2] = n[i];
    m[15] = 1;
}

static void load_matrices(const vrPerspective *p)
{
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glFrustum(p->frustum.n.left, p->frustum.n.right, p->frustum.n.bottom, p->frustum.n.top, p->frustum.near_clip,
              p->frustum.far_clip);
    glMatrixMode(GL_MODELVIEW);
    glLoadMatrixd(p->rw2w_xform.v);
    glTranslated(-p->eye[0], -p->eye[1], -p->eye[2]);
}

/* The simulator's own drawing: the CAVE's outline, the head (a brown cube)
 * and the wand. */
static void draw_simulator(void)
{
    glDisable(GL_TEXTURE_2D);
    glEnable(GL_DEPTH_TEST);
    glColor3f(0.6f, 0.6f, 0.6f);
    glBegin(GL_LINES);
    for (int i = 0; i < 4; i++) {
        const double x0 = i & 1 ? 5 : -5, z0 = i & 2 ? 5 : -5;
        glVertex3d(x0, 0, z0), glVertex3d(x0, 10, z0);
        glVertex3d(x0, 0, z0), glVertex3d(i & 1 ? -5 : 5, 0, z0);
        glVertex3d(x0, 10, z0), glVertex3d(i & 1 ? -5 : 5, 10, z0);
        glVertex3d(x0, 0, z0), glVertex3d(x0, 0, -z0);
        glVertex3d(x0, 10, z0), glVertex3d(x0, 10, -z0);
    }
    glEnd();
    const double *h = g_base->head, s = 0.25;
    glColor3f(0.55f, 0.35f, 0.15f);
    glBegin(GL_QUADS);
    for (int f = 0; f < 6; f++) {
        const int ax = f / 2, a1 = (ax + 1) % 3, a2 = (ax + 2) % 3;
        const double sg = f % 2 ? s : -s;
        const double q[4][2] = {{-s, -s}, {s, -s}, {s, s}, {-s, s}};
        for (int k = 0; k < 4; k++) {
            double v[3];
            v[ax] = h[ax] + sg, v[a1] = h[a1] + q[k][0], v[a2] = h[a2] + q[k][1];
            glVertex3dv(v);
        }
    }
    glEnd();
    glColor3f(0.8f, 0.8f, 0.2f);
    glBegin(GL_LINES);
    glVertex3dv(g_base->wand);
    glVertex3d(g_base->wand[0], g_base->wand[1], g_base->wand[2] - 1);
    glEnd();
}

/* ------------------------------------------------------- render process */

typedef struct {
    const win_def *def;
    Window xw;
    GLXContext ctx;
    unsigned long frames;
} render_win;

static void dump(const render_win *w, int width, int height)
{
    const char *dir = getenv("FREEVR_STANDIN_DUMP");
    if (!dir || !*dir || width < 1 || height < 1)
        return;
    unsigned char *px = malloc((size_t)width * height * 3);
    if (!px)
        return;
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, px);
    char path[4096], tmp[4200];
    snprintf(path, sizeof path, "%s/%s.ppm", dir, w->def->name);
    snprintf(tmp, sizeof tmp, "%s.tmp.%d", path, (int)getpid());
    FILE *fp = fopen(tmp, "wb");
    if (fp) {
        fprintf(fp, "P6\n# frame %lu\n%d %d\n255\n", w->frames, width, height);
        for (int y = height - 1; y >= 0; y--) /* top row first */
            fwrite(px + (size_t)y * width * 3, 1, (size_t)width * 3, fp);
        if (fclose(fp) == 0)
            rename(tmp, path);
        else
            remove(tmp);
    }
    free(px);
}

static int x_error(Display *d, XErrorEvent *e)
{
    char msg[256];
    XGetErrorText(d, e->error_code, msg, sizeof msg);
    fprintf(stderr, "FreeVR: X error: %s\n", msg);
    return 0;
}

static void render_process(const proc_def *p)
{
    render_win wins[MAXWIN];
    int n = 0;
    Display *dpy = XOpenDisplay(NULL);
    if (!dpy) {
        fprintf(stderr, "FreeVR: cannot open the display '%s'\n", getenv("DISPLAY") ? getenv("DISPLAY") : "");
        g_base->quit = 1;
        _exit(1);
    }
    XSetErrorHandler(x_error);
    int attrs[] = {GLX_RGBA, GLX_DOUBLEBUFFER, GLX_RED_SIZE, 1, GLX_GREEN_SIZE, 1, GLX_BLUE_SIZE, 1, GLX_DEPTH_SIZE, 16,
                   None};
    XVisualInfo *vi = glXChooseVisual(dpy, DefaultScreen(dpy), attrs);
    if (!vi) {
        fprintf(stderr, "FreeVR: no double-buffered RGBA visual with depth\n");
        g_base->quit = 1;
        _exit(1);
    }
    for (int k = 0; k < p->nobj && n < MAXWIN; k++) {
        const win_def *d = find_win(p->obj[k]);
        if (!d) {
            fprintf(stderr, "FreeVR: process '%s': no window '%s'\n", p->name, p->obj[k]);
            continue;
        }
        /* FreeVR's own state for this window, from the shared arena */
        if (!amalloc(g_per_window)) {
            fprintf(stderr, "FreeVR: render process %d (%s window) waits for memory\n", (int)getpid(), d->name);
            for (;;)
                pause();
        }
        render_win *w = &wins[n++];
        memset(w, 0, sizeof *w);
        w->def = d;
        XSetWindowAttributes swa;
        memset(&swa, 0, sizeof swa);
        swa.colormap = XCreateColormap(dpy, RootWindow(dpy, vi->screen), vi->visual, AllocNone);
        swa.event_mask = ExposureMask | StructureNotifyMask;
        w->xw = XCreateWindow(dpy, RootWindow(dpy, vi->screen), d->x, d->y, (unsigned)d->w, (unsigned)d->h, 0,
                              vi->depth, InputOutput, vi->visual, CWColormap | CWEventMask, &swa);
        char title[256];
        snprintf(title, sizeof title, "FreeVR(%d): %s window", (int)getpid(), d->name);
        XStoreName(dpy, w->xw, title);
        XMapWindow(dpy, w->xw);
        w->ctx = glXCreateContext(dpy, vi, NULL, True);
        if (!w->ctx || !glXMakeCurrent(dpy, w->xw, w->ctx)) {
            fprintf(stderr, "FreeVR: cannot create a GLX context for the %s window\n", d->name);
            g_base->quit = 1;
            _exit(1);
        }
        if (g_cb[VRFUNC_DISPLAY_INIT].fn)
            call0(&g_cb[VRFUNC_DISPLAY_INIT]);
    }
    XSync(dpy, False);
    while (!g_base->quit) {
        const double t0 = now_s();
        while (XPending(dpy)) {
            XEvent ev;
            XNextEvent(dpy, &ev);
        }
        for (int k = 0; k < n && !g_base->quit; k++) {
            render_win *w = &wins[k];
            XWindowAttributes wa;
            XGetWindowAttributes(dpy, w->xw, &wa);
            glXMakeCurrent(dpy, w->xw, w->ctx);
            glViewport(0, 0, wa.width, wa.height);
            vrPerspective persp;
            perspective(w->def, wa.width, wa.height, &persp);
            vrRenderInfo ri = {&persp, w->def->name, 0};
            if (g_cb[VRFUNC_DISPLAY_FRAME].fn) {
                load_matrices(&persp);
                call_ri(&g_cb[VRFUNC_DISPLAY_FRAME], &ri);
            }
            load_matrices(&persp); /* no clearing: the application's job */
            if (g_cb[VRFUNC_DISPLAY].fn)
                call_ri(&g_cb[VRFUNC_DISPLAY], &ri);
            if (w->def->simulator) {
                load_matrices(&persp);
                draw_simulator();
            }
            w->frames++;
            dump(w, wa.width, wa.height);
            glXSwapBuffers(dpy, w->xw);
        }
        const double left = 1.0 / 60 - (now_s() - t0); /* at most 60 frames a second */
        if (left > 0)
            nanosleep(&(struct timespec){0, (long)(left * 1e9)}, NULL);
    }
    for (int k = 0; k < n; k++) {
        glXMakeCurrent(dpy, wins[k].xw, wins[k].ctx);
        if (g_cb[VRFUNC_DISPLAY_EXIT].fn)
            call0(&g_cb[VRFUNC_DISPLAY_EXIT]);
        glXMakeCurrent(dpy, None, NULL);
        glXDestroyContext(dpy, wins[k].ctx);
        XDestroyWindow(dpy, wins[k].xw);
    }
    XCloseDisplay(dpy);
    _exit(0);
}

/* -------------------------------------------------------- input process */

static void input_process(const proc_def *p)
{
    Display *dpy = XOpenDisplay(NULL);
    if (!dpy) {
        fprintf(stderr, "FreeVR: input: cannot open the display\n");
        g_base->quit = 1;
        _exit(1);
    }
    const dev_def *devs[MAXWIN];
    int nd = 0;
    for (int k = 0; k < p->nobj; k++) {
        const dev_def *d = find_dev(p->obj[k]);
        if (d && d->xwindows && nd < MAXWIN)
            devs[nd++] = d;
    }
    const KeyCode space = XKeysymToKeycode(dpy, XK_space);
    const long usec = p->usecmin > 0 ? p->usecmin : 16667;
    while (!g_base->quit) {
        char keys[32];
        Window root, child;
        int rx, ry, wx, wy;
        unsigned int mask = 0;
        XQueryKeymap(dpy, keys);
        XQueryPointer(dpy, DefaultRootWindow(dpy), &root, &child, &rx, &ry, &wx, &wy, &mask);
        int sw = 0;
        for (int k = 0; k < nd; k++)
            for (int i = 0; i < devs[k]->nin && sw < NSW; i++, sw++) {
                int on;
                if (devs[k]->in[i].button)
                    on = !!(mask & (Button1Mask << (devs[k]->in[i].button - 1)));
                else {
                    const KeyCode kc = XKeysymToKeycode(dpy, devs[k]->in[i].keysym);
                    on = kc && (keys[kc / 8] >> (kc % 8) & 1);
                }
                g_base->sw[sw] = on;
            }
        if (space && (keys[space / 8] >> (space % 8) & 1)) { /* the pointer is the joystick while space is held */
            const int W = DisplayWidth(dpy, DefaultScreen(dpy)), H = DisplayHeight(dpy, DefaultScreen(dpy));
            g_base->val[0] = (float)(2.0 * rx / W - 1);
            g_base->val[1] = (float)(1 - 2.0 * ry / H);
        } else {
            g_base->val[0] = g_base->val[1] = 0;
        }
        nanosleep(&(struct timespec){usec / 1000000, (usec % 1000000) * 1000}, NULL);
    }
    XCloseDisplay(dpy);
    _exit(0);
}

static void start_child(const proc_def *p)
{
    fflush(NULL);
    const pid_t pid = fork();
    if (pid < 0) {
        perror("FreeVR: fork");
        return;
    }
    if (pid == 0) {
        prctl(PR_SET_PDEATHSIG, SIGKILL); /* never outlive the application */
        if (getppid() != g_main)
            _exit(1);
        if (p->type == 'v')
            render_process(p);
        else
            input_process(p);
        _exit(0);
    }
    g_children[g_nchildren++] = pid;
}

void vrStart(void)
{
    const sys_def *sys = used_system();
    if (!g_base || !sys || g_base->started)
        return;
    g_base->started = 1;
    for (int k = 0; k < sys->nprocs; k++) {
        const proc_def *p = find_proc(sys->procs[k]);
        if (!p)
            fprintf(stderr, "FreeVR: system '%s': no process '%s'\n", sys->name, sys->procs[k]);
        else if (p->type == 'v' || p->type == 'i')
            start_child(p);
    }
}

/* --------------------------------------------------------- main process */

static int g_cur[NSW], g_prev[NSW];
static float g_vcur[NVAL], g_vprev[NVAL];
static int g_quit_seen;

int vrFrame(void)
{
    if (!g_base)
        return 0;
    memcpy(g_prev, g_cur, sizeof g_cur);
    memcpy(g_vprev, g_vcur, sizeof g_vcur);
    for (int i = 0; i < NSW; i++)
        g_cur[i] = g_base->sw[i];
    for (int i = 0; i < NVAL; i++)
        g_vcur[i] = g_base->val[i];
    if (g_cur[0] || g_base->quit)
        g_quit_seen = 1;
    return !g_quit_seen;
}

void vrExit(void)
{
    if (!g_base || getpid() != g_main)
        return;
    g_base->quit = 1;
    for (int i = 0; i < g_nchildren; i++) /* FreeVR waits for every process */
        while (waitpid(g_children[i], NULL, 0) == -1 && errno == EINTR)
            ;
    g_nchildren = 0;
    semctl(g_semid, 0, IPC_RMID);
    g_semid = -1;
    munmap(g_arena, g_arena_size);
    g_arena = NULL;
    g_base = NULL;
}

double vrCurrentSimTime(void) { return g_base ? now_s() - g_base->start : 0; }

int vrGet2switchValue(int n) { return n >= 0 && n < NSW ? g_cur[n] : 0; }
int vrGet2switchDelta(int n) { return n >= 0 && n < NSW ? g_cur[n] - g_prev[n] : 0; }
float vrGetValuatorValue(int n) { return n >= 0 && n < NVAL ? g_vcur[n] : 0; }
float vrGetValuatorDelta(int n) { return n >= 0 && n < NVAL ? g_vcur[n] - g_vprev[n] : 0; }

static const double *sensor(int n) { return n == 0 ? g_base->head : g_base->wand; }

vrMatrix *vrMatrixGet6sensorValues(vrMatrix *m, int n)
{
    memset(m->v, 0, sizeof m->v);
    m->v[0] = m->v[5] = m->v[10] = m->v[15] = 1;
    if (g_base)
        memcpy(m->v + 12, sensor(n), 3 * sizeof(double));
    return m;
}

vrPoint *vrPointGetRWFrom6sensor(vrPoint *p, int n)
{
    if (g_base)
        memcpy(p->v, sensor(n), sizeof p->v);
    return p;
}

vrVector *vrVectorGetRWFrom6sensorDir(vrVector *v, int n, vrDirection d)
{
    (void)n; /* the simulated sensors look along -z */
    static const double dirs[6][3] = {{0, 0, -1}, {0, 0, 1}, {-1, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
    memcpy(v->v, dirs[(int)d >= 0 && d <= VRDIR_DOWN ? d : 0], sizeof v->v);
    return v;
}

int vrInputSet2switchDescription(int n, char *text)
{
    (void)text;
    if (g_base && !g_base->started && n >= g_nswitches)
        fprintf(stderr, "FreeVR: Creating dummy 2switch[%d]\n", n);
    return n;
}

/* ---------------------------------------------------------------- travel */

void vrRenderTransformUserTravel(vrRenderInfo *ri)
{
    (void)ri;
    if (g_base)
        glMultMatrixd(g_base->travel);
}
void vrUserTravelLockSet(int user) { (void)user; }
void vrUserTravelLockRelease(int user) { (void)user; }
void vrUserTravelReset(int user)
{
    (void)user;
    for (int i = 0; g_base && i < 16; i++)
        g_base->travel[i] = i % 5 == 0;
}
void vrUserTravelTranslate3d(int user, double x, double y, double z)
{
    (void)user;
    if (g_base) {
        double *t = g_base->travel;
        for (int i = 0; i < 3; i++)
            t[12 + i] += t[i] * x + t[4 + i] * y + t[8 + i] * z;
    }
}
void vrUserTravelRotateId(int user, int axis, double degrees)
{
    (void)user;
    if (!g_base || axis != VR_Y)
        return;
    const double c = cos(degrees * M_PI / 180), s = sin(degrees * M_PI / 180);
    double *t = g_base->travel, o[8];
    for (int i = 0; i < 4; i++) /* t = t * Ry */
        o[i] = t[i] * c - t[8 + i] * s, o[4 + i] = t[i] * s + t[8 + i] * c;
    for (int i = 0; i < 4; i++)
        t[i] = o[i], t[8 + i] = o[4 + i];
}

/* ----------------------------------------------------------------- locks */

vrLock vrNCLockCreate(void)
{
    if (!g_base)
        return NULL;
    sem_add(0, -1);
    const int idx = g_base->nextlock < NSEMS ? g_base->nextlock++ : NSEMS - 1;
    sem_add(0, 1);
    return (vrLock)(intptr_t)idx;
}
void vrLockWriteSet(vrLock l) { sem_add((int)(intptr_t)l, -1); }
void vrLockWriteRelease(vrLock l) { sem_add((int)(intptr_t)l, 1); }
void vrLockReadSet(vrLock l) { sem_add((int)(intptr_t)l, -1); }
void vrLockReadRelease(vrLock l) { sem_add((int)(intptr_t)l, 1); }
