/* vsv_json.c — the tools' small JSON document builder and printer
 * (vsv_json.h). */
#include "vsv_json.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { J_NULL, J_BOOL, J_NUM, J_INT, J_STR, J_ARR, J_OBJ };

struct vsv_json {
    int type;
    double num;
    long long i;
    char *str;   /* J_STR value */
    char **keys; /* J_OBJ */
    vsv_json **items;
    size_t n, cap;
};

static vsv_json *jnew(int type)
{
    vsv_json *j = calloc(1, sizeof *j);
    if (j)
        j->type = type;
    return j;
}

vsv_json *vsv_json_object(void) { return jnew(J_OBJ); }
vsv_json *vsv_json_array(void) { return jnew(J_ARR); }
vsv_json *vsv_json_null(void) { return jnew(J_NULL); }

vsv_json *vsv_json_number(double v)
{
    vsv_json *j = jnew(isfinite(v) ? J_NUM : J_NULL);
    if (j)
        j->num = v;
    return j;
}

vsv_json *vsv_json_int(long long v)
{
    vsv_json *j = jnew(J_INT);
    if (j)
        j->i = v;
    return j;
}

vsv_json *vsv_json_bool(int v)
{
    vsv_json *j = jnew(J_BOOL);
    if (j)
        j->i = !!v;
    return j;
}

vsv_json *vsv_json_string(const char *s)
{
    vsv_json *j = jnew(J_STR);
    if (j && !(j->str = strdup(s ? s : ""))) {
        free(j);
        return NULL;
    }
    return j;
}

static void jadd(vsv_json *c, char *key, vsv_json *v)
{
    if (!v || !c) {
        free(key);
        vsv_json_free(v);
        return;
    }
    if (c->n == c->cap) {
        size_t cap = c->cap ? 2 * c->cap : 8;
        vsv_json **it = realloc(c->items, cap * sizeof *it);
        char **ks = realloc(c->keys, cap * sizeof *ks);
        if (it)
            c->items = it;
        if (ks)
            c->keys = ks;
        if (!it || !ks) {
            free(key);
            vsv_json_free(v);
            return;
        }
        c->cap = cap;
    }
    c->items[c->n] = v;
    c->keys[c->n] = key;
    c->n++;
}

void vsv_json_set(vsv_json *obj, const char *key, vsv_json *value) { jadd(obj, strdup(key), value); }
void vsv_json_push(vsv_json *arr, vsv_json *value) { jadd(arr, NULL, value); }

void vsv_json_free(vsv_json *v)
{
    if (!v)
        return;
    for (size_t i = 0; i < v->n; i++) {
        vsv_json_free(v->items[i]);
        free(v->keys[i]);
    }
    free(v->items);
    free(v->keys);
    free(v->str);
    free(v);
}

static void print_string(FILE *fp, const char *s)
{
    fputc('"', fp);
    for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
        switch (*p) {
        case '"': fputs("\\\"", fp); break;
        case '\\': fputs("\\\\", fp); break;
        case '\n': fputs("\\n", fp); break;
        case '\t': fputs("\\t", fp); break;
        case '\r': fputs("\\r", fp); break;
        default:
            if (*p < 0x20)
                fprintf(fp, "\\u%04x", *p);
            else
                fputc(*p, fp);
        }
    }
    fputc('"', fp);
}

static void print_number(FILE *fp, double v)
{
    if (v == floor(v) && fabs(v) < 1e15)
        fprintf(fp, "%.0f", v);
    else
        fprintf(fp, "%.9g", v);
}

static void jprint(FILE *fp, const vsv_json *v, int pretty, int depth)
{
    switch (v->type) {
    case J_NULL: fputs("null", fp); return;
    case J_BOOL: fputs(v->i ? "true" : "false", fp); return;
    case J_NUM: print_number(fp, v->num); return;
    case J_INT: fprintf(fp, "%lld", v->i); return;
    case J_STR: print_string(fp, v->str); return;
    default: break;
    }
    const int obj = v->type == J_OBJ;
    /* short arrays of scalars stay on one line */
    int flat = !pretty;
    if (!obj && pretty) {
        flat = v->n <= 8;
        for (size_t i = 0; i < v->n && flat; i++)
            flat = v->items[i]->type != J_OBJ && v->items[i]->type != J_ARR;
    }
    fputc(obj ? '{' : '[', fp);
    for (size_t i = 0; i < v->n; i++) {
        if (i)
            fputc(',', fp);
        if (!flat)
            fprintf(fp, "\n%*s", 2 * (depth + 1), "");
        else if (i && pretty)
            fputc(' ', fp);
        if (obj) {
            print_string(fp, v->keys[i]);
            fputs(pretty ? ": " : ":", fp);
        }
        jprint(fp, v->items[i], pretty, depth + 1);
    }
    if (!flat && v->n)
        fprintf(fp, "\n%*s", 2 * depth, "");
    fputc(obj ? '}' : ']', fp);
}

void vsv_json_print(FILE *fp, const vsv_json *v, int pretty)
{
    jprint(fp, v, pretty, 0);
    fputc('\n', fp);
}

void vsv_json_print_plain(FILE *fp, const vsv_json *v)
{
    if (v->type == J_STR)
        fprintf(fp, "%s\n", v->str);
    else
        vsv_json_print(fp, v, v->type == J_OBJ || v->type == J_ARR);
}

const vsv_json *vsv_json_path(const vsv_json *root, const char *path)
{
    const vsv_json *cur = root;
    char part[128];
    const char *p = path;
    while (*p && cur) {
        size_t n = 0;
        if (*p == '[') {
            p++;
            while (*p && *p != ']' && n < sizeof part - 1)
                part[n++] = *p++;
            if (*p == ']')
                p++;
        } else {
            while (*p && *p != '.' && *p != '[' && n < sizeof part - 1)
                part[n++] = *p++;
        }
        part[n] = 0;
        if (*p == '.')
            p++;
        const vsv_json *next = NULL;
        if (cur->type == J_OBJ) {
            for (size_t i = 0; i < cur->n; i++)
                if (!strcmp(cur->keys[i], part))
                    next = cur->items[i];
        } else if (cur->type == J_ARR) {
            char *end;
            long idx = strtol(part, &end, 10);
            if (*part && !*end && idx >= 0 && (size_t)idx < cur->n)
                next = cur->items[idx];
            for (size_t i = 0; !next && (!*part || *end) && i < cur->n; i++) { /* by name: species.CLW */
                const vsv_json *it = cur->items[i];
                for (size_t k = 0; it->type == J_OBJ && k < it->n; k++)
                    if (!strcmp(it->keys[k], "name") && it->items[k]->type == J_STR && !strcmp(it->items[k]->str, part))
                        next = it;
            }
        }
        cur = next;
    }
    return cur;
}
