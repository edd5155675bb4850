/* vsv_expr.c — the expression grammar of --derive (vsv_convert.h): a
 * recursive-descent parser that compiles the text once into a postfix
 * program, evaluated cell by cell over float arrays with a fixed stack, so
 * the per-cell loop allocates nothing and never recurses. */
#include "vsv_convert.h"
#include "vsv_common.h"

#include <ctype.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

enum {
    OP_CONST,
    OP_INPUT,
    OP_NEG,
    OP_ADD,
    OP_SUB,
    OP_MUL,
    OP_DIV,
    OP_POW,
    OP_SQRT,
    OP_EXP,
    OP_LOG,
    OP_ABS,
    OP_MIN,
    OP_MAX
};

typedef struct op {
    int code;
    int input; /* OP_INPUT: which */
    double value;
} op;

struct vsv_expr {
    op prog[VSV_EXPR_MAX_OPS];
    int nops;
    unsigned char *uses; /* per input name: 1 if read */
    int ninputs;
};

/* The parser's state: the text, where it is, the names, the program being
 * built and its stack depth, the first error. */
typedef struct parser {
    const char *text;
    size_t at;
    const char *const *names;
    int nnames;
    vsv_expr *e;
    int depth, maxdepth, nest;
    char *msg;
    size_t cap;
    int pos; /* 1-based character of the error, 0 = none yet */
} parser;

static int perr(parser *p, size_t at, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static int perr(parser *p, size_t at, const char *fmt, ...)
{
    if (p->pos)
        return VSV_EINVAL; /* the first error is the one said */
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(p->msg, p->cap, fmt, ap);
    va_end(ap);
    p->pos = (int)at + 1;
    return VSV_EINVAL;
}

static void skip(parser *p)
{
    while (p->text[p->at] == ' ' || p->text[p->at] == '\t')
        p->at++;
}

/* Appends one operation; its effect on the stack depth is `push` (1 for a
 * value, 0 for a function of one, -1 for one of two). */
static int emit(parser *p, int code, int input, double value, int push)
{
    if (p->e->nops >= VSV_EXPR_MAX_OPS)
        return perr(p, p->at, "too long (more than %d operations)", VSV_EXPR_MAX_OPS);
    p->e->prog[p->e->nops++] = (op){code, input, value};
    p->depth += push;
    if (p->depth > p->maxdepth)
        p->maxdepth = p->depth;
    if (p->maxdepth > VSV_EXPR_MAX_DEPTH)
        return perr(p, p->at, "too deeply nested (more than %d values pending)", VSV_EXPR_MAX_DEPTH);
    return 0;
}

static int expr(parser *p);

/* A number: digits, an optional fraction, an optional exponent. */
static int number(parser *p)
{
    const char *s = p->text + p->at;
    size_t n = 0;
    while (isdigit((unsigned char)s[n]))
        n++;
    if (s[n] == '.')
        for (n++; isdigit((unsigned char)s[n]);)
            n++;
    if (n == 1 && s[0] == '.')
        return perr(p, p->at, "malformed number");
    if (s[n] == 'e' || s[n] == 'E') {
        size_t m = n + 1;
        if (s[m] == '+' || s[m] == '-')
            m++;
        if (!isdigit((unsigned char)s[m]))
            return perr(p, p->at + n, "malformed exponent");
        while (isdigit((unsigned char)s[m]))
            m++;
        n = m;
    }
    char buf[64];
    if (n >= sizeof buf)
        return perr(p, p->at, "number too long");
    memcpy(buf, s, n);
    buf[n] = 0;
    const double v = strtod(buf, NULL);
    if (!isfinite(v))
        return perr(p, p->at, "number out of range");
    p->at += n;
    return emit(p, OP_CONST, 0, v, 1);
}

/* A function call's arguments after the name: how many, into *nargs. */
static int arguments(parser *p, int *nargs)
{
    p->at++; /* '(' */
    *nargs = 0;
    for (;;) {
        int rc = expr(p);
        if (rc)
            return rc;
        ++*nargs;
        skip(p);
        if (p->text[p->at] == ',') {
            p->at++;
            continue;
        }
        if (p->text[p->at] != ')')
            return perr(p, p->at, "expected ',' or ')'");
        p->at++;
        return 0;
    }
}

static int call(parser *p, const char *name, size_t start)
{
    static const struct {
        const char *name;
        int code, min, max;
    } fn[] = {{"sqrt", OP_SQRT, 1, 1}, {"exp", OP_EXP, 1, 1},  {"log", OP_LOG, 1, 1},
              {"abs", OP_ABS, 1, 1},   {"min", OP_MIN, 2, 64}, {"max", OP_MAX, 2, 64}};
    size_t k = 0;
    while (k < sizeof fn / sizeof *fn && strcmp(fn[k].name, name))
        k++;
    if (k == sizeof fn / sizeof *fn)
        return perr(p, start, "unknown function '%s' (there are sqrt exp log abs min max)", name);
    int nargs, rc;
    if ((rc = arguments(p, &nargs)))
        return rc;
    if (nargs < fn[k].min || nargs > fn[k].max)
        return perr(p, start, "%s takes %s argument%s, not %d", name, fn[k].min == 1 ? "one" : "two or more",
                    fn[k].min == 1 ? "" : "s", nargs);
    /* min and max of several: a chain of pairs */
    for (int i = 1; i < nargs && !rc; i++)
        rc = emit(p, fn[k].code, 0, 0, -1);
    return nargs == 1 ? emit(p, fn[k].code, 0, 0, 0) : rc;
}

/* A name: an input, or a function when '(' follows. Names are letters,
 * digits, '_' and '.', starting with a letter or '_'; "double quotes" take
 * any other name (MM5's "RAD TEND"). */
static int name(parser *p)
{
    const size_t start = p->at;
    char buf[96];
    size_t n = 0;
    if (p->text[p->at] == '"') {
        const char *end = strchr(p->text + p->at + 1, '"');
        if (!end)
            return perr(p, start, "unterminated quoted name");
        n = (size_t)(end - (p->text + p->at + 1));
        if (n >= sizeof buf)
            return perr(p, start, "name too long");
        memcpy(buf, p->text + p->at + 1, n);
        p->at += n + 2;
    } else {
        while (isalnum((unsigned char)p->text[p->at + n]) || p->text[p->at + n] == '_' || p->text[p->at + n] == '.')
            n++;
        if (n >= sizeof buf)
            return perr(p, start, "name too long");
        memcpy(buf, p->text + p->at, n);
        p->at += n;
    }
    buf[n] = 0;
    skip(p);
    if (p->text[start] != '"' && p->text[p->at] == '(')
        return call(p, buf, start);
    for (int i = 0; i < p->nnames; i++)
        if (!strcmp(p->names[i], buf)) {
            p->e->uses[i] = 1;
            return emit(p, OP_INPUT, i, 0, 1);
        }
    return perr(p, start, "unknown name '%s'", buf);
}

static int primary(parser *p)
{
    skip(p);
    const char c = p->text[p->at];
    if (isdigit((unsigned char)c) || c == '.')
        return number(p);
    if (isalpha((unsigned char)c) || c == '_' || c == '"')
        return name(p);
    if (c == '(') {
        p->at++;
        int rc = expr(p);
        if (rc)
            return rc;
        skip(p);
        if (p->text[p->at] != ')')
            return perr(p, p->at, "expected ')'");
        p->at++;
        return 0;
    }
    return perr(p, p->at, "expected a value");
}

static int unary(parser *p);

/* power := primary ['^' unary]: right-associative, and above unary minus
 * (-2^2 is -4; 2^-1 is 0.5) as in Fortran and most calculators. */
static int power(parser *p)
{
    int rc = primary(p);
    if (rc)
        return rc;
    skip(p);
    if (p->text[p->at] != '^')
        return 0;
    p->at++;
    return (rc = unary(p)) ? rc : emit(p, OP_POW, 0, 0, -1);
}

static int unary(parser *p)
{
    skip(p);
    if (p->text[p->at] == '-' || p->text[p->at] == '+') {
        const int neg = p->text[p->at] == '-';
        if (++p->nest > VSV_EXPR_MAX_DEPTH)
            return perr(p, p->at, "too deeply nested");
        p->at++;
        int rc = unary(p);
        p->nest--;
        return rc || !neg ? rc : emit(p, OP_NEG, 0, 0, 0);
    }
    return power(p);
}

static int term(parser *p)
{
    int rc = unary(p);
    for (skip(p); !rc && (p->text[p->at] == '*' || p->text[p->at] == '/'); skip(p)) {
        const int code = p->text[p->at++] == '*' ? OP_MUL : OP_DIV;
        rc = unary(p);
        if (!rc)
            rc = emit(p, code, 0, 0, -1);
    }
    return rc;
}

static int expr(parser *p)
{
    if (++p->nest > VSV_EXPR_MAX_DEPTH)
        return perr(p, p->at, "too deeply nested");
    int rc = term(p);
    for (skip(p); !rc && (p->text[p->at] == '+' || p->text[p->at] == '-'); skip(p)) {
        const int code = p->text[p->at++] == '+' ? OP_ADD : OP_SUB;
        rc = term(p);
        if (!rc)
            rc = emit(p, code, 0, 0, -1);
    }
    p->nest--;
    return rc;
}

int vsv_expr_compile(const char *text, const char *const *names, int nnames, vsv_expr **out, char *msg, size_t cap,
                     int *pos)
{
    *out = NULL;
    *pos = 0;
    if (cap)
        msg[0] = 0;
    vsv_expr *e = calloc(1, sizeof *e);
    if (!e || !(e->uses = calloc((size_t)nnames + 1, 1))) {
        free(e);
        return VSV_ENOMEM;
    }
    e->ninputs = nnames;
    parser p = {text, 0, names, nnames, e, 0, 0, 0, msg, cap, 0};
    int rc = expr(&p);
    skip(&p);
    if (!rc && p.text[p.at])
        rc = perr(&p, p.at, "expected an operator or the end, not '%c'", p.text[p.at]);
    *pos = p.pos;
    if (rc) {
        vsv_expr_free(e);
        return rc;
    }
    *out = e;
    return 0;
}

int vsv_expr_uses(const vsv_expr *e, int input) { return input >= 0 && input < e->ninputs && e->uses[input]; }

/* One operation of two: NaN in either is NaN out, also where C's pow and
 * fmin would return a number (pow(NaN, 0) = 1, fmin(NaN, 1) = 1). */
static double binary(int code, double a, double b)
{
    if (isnan(a) || isnan(b))
        return NAN;
    switch (code) {
    case OP_ADD: return a + b;
    case OP_SUB: return a - b;
    case OP_MUL: return a * b;
    case OP_DIV: return a / b;
    case OP_POW: return pow(a, b);
    case OP_MIN: return a < b ? a : b;
    default: return a > b ? a : b;
    }
}

void vsv_expr_eval(const vsv_expr *e, const float *const *inputs, size_t n, float *out)
{
    double st[VSV_EXPR_MAX_DEPTH + 1];
    for (size_t c = 0; c < n; c++) {
        int sp = 0;
        for (int i = 0; i < e->nops; i++) {
            const op *o = &e->prog[i];
            switch (o->code) {
            case OP_CONST: st[sp++] = o->value; break;
            case OP_INPUT: st[sp++] = inputs[o->input][c]; break;
            case OP_NEG: st[sp - 1] = -st[sp - 1]; break;
            case OP_SQRT: st[sp - 1] = sqrt(st[sp - 1]); break;
            case OP_EXP: st[sp - 1] = exp(st[sp - 1]); break;
            case OP_LOG: st[sp - 1] = log(st[sp - 1]); break;
            case OP_ABS: st[sp - 1] = fabs(st[sp - 1]); break;
            default:
                sp--;
                st[sp - 1] = binary(o->code, st[sp - 1], st[sp]);
                break;
            }
        }
        /* no infinities in a file: what is not a finite float is no data */
        const double v = st[0];
        out[c] = isfinite(v) && fabs(v) <= FLT_MAX ? (float)v : NAN;
    }
}

void vsv_expr_free(vsv_expr *e)
{
    if (!e)
        return;
    free(e->uses);
    free(e);
}
