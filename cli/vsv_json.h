/* vsv_json.h — a tiny JSON document builder for the tools (vsv-info's
 * machine-readable output and -f lookups). Part of the tools' static
 * library (cli/). */
#ifndef VSV_JSON_H
#define VSV_JSON_H

#include <stdio.h>

typedef struct vsv_json vsv_json;

/* Constructors; each returns NULL only when out of memory. */
vsv_json *vsv_json_object(void);
vsv_json *vsv_json_array(void);
vsv_json *vsv_json_number(double v);
vsv_json *vsv_json_int(long long v);
vsv_json *vsv_json_string(const char *s);
vsv_json *vsv_json_bool(int v);
vsv_json *vsv_json_null(void);
/* Adds `value` (ownership passes to the container; NULL values are ignored). */
void vsv_json_set(vsv_json *obj, const char *key, vsv_json *value);
void vsv_json_push(vsv_json *arr, vsv_json *value);
/* Prints pretty (indent 2) or compact. */
void vsv_json_print(FILE *fp, const vsv_json *v, int pretty);
/* Looks up a dotted path ("grid.nx", "species.0.name", "species[0].name",
 * or an array's element by its "name" member: "species.CLW.units"; an
 * index wins over a name that is a number); borrowed, or NULL. */
const vsv_json *vsv_json_path(const vsv_json *root, const char *path);
/* Prints a scalar plainly (strings without quotes) or a container as JSON. */
void vsv_json_print_plain(FILE *fp, const vsv_json *v);
void vsv_json_free(vsv_json *v);

#endif
