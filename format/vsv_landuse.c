/* vsv_landuse.c — which land-use categories of a file are water (the
 * `landuse_water` attribute the converters write beside LUSE). */
#include "vsv_format_internal.h"

#include <stdlib.h>

uint64_t vsv_meta_water(const vsv_meta *m)
{
    const char *v = m->landuse ? vsv_meta_attr(m, "landuse_water") : NULL;
    uint64_t mask = 0;
    while (v && *v) {
        char *end;
        const long c = strtol(v, &end, 10);
        if (end == v)
            break;
        if (c >= 0 && c < 64)
            mask |= (uint64_t)1 << c;
        v = *end == ',' ? end + 1 : end;
    }
    return mask;
}
