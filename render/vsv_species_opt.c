/* vsv_species_opt.c — the --species NAME[:OPACITY],... option the tools
 * that draw species read alike (vsv_species_parse: vsv-render, vsv-play,
 * vsv-play-freevr). */
#include "vsv_render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int vsv_species_parse(const vsv_meta *m, const char *list, const char *file, float *opac, char *msg, size_t cap)
{
    const size_t len = strlen(list);
    char *seen = calloc((size_t)m->nvars + 1, 1), *item = malloc(len + 1);
    int rc = 0;
    if (!seen || !item) {
        snprintf(msg, cap, "out of memory");
        rc = VSV_ENOMEM;
    }
    for (const char *p = list; !rc; p++) {
        const size_t n = strcspn(p, ",");
        memcpy(item, p, n);
        item[n] = 0;
        char *colon = strchr(item, ':'), *end = NULL;
        double op = 1;
        if (colon) {
            *colon = 0;
            op = strtod(colon + 1, &end);
        }
        const int s = vsv_meta_find_var(m, item);
        if (!*item) {
            snprintf(msg, cap, "--species %s: an empty species name", list);
            rc = VSV_EINVAL;
        } else if (colon && (end == colon + 1 || *end || !(op >= 0) || !isfinite(op))) {
            snprintf(msg, cap, "--species %s: opacity must be a finite number >= 0", list);
            rc = VSV_EINVAL;
        } else if (s < 0) {
            snprintf(msg, cap, "--species: %s has no species '%s'", file, item);
            rc = VSV_EINVAL;
        } else if (seen[s]++) {
            snprintf(msg, cap, "--species: '%s' named twice", item);
            rc = VSV_EINVAL;
        } else {
            opac[s] = (float)op;
        }
        if (!p[n])
            break;
        p += n;
    }
    free(seen);
    free(item);
    return rc;
}
