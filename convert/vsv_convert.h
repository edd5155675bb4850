/* vsv_convert.h — model readers behind one "source" interface (grid,
 * projection, times, fields), as DESIGN.md §1 draws them. The format of a
 * file is detected from its content, never from its name. */
#ifndef VSV_CONVERT_H
#define VSV_CONVERT_H

#include "vsv_format.h"

typedef struct vsv_source vsv_source;

/* One field a source offers: plain info. */
typedef struct vsv_field_info {
    char name[64];
    char units[64];
    char description[128];
    int nlevels;       /* 0 for a 2-D field */
    int is_default;    /* extracted when no --vars is given */
} vsv_field_info;

/* Opens a model file, detecting its format from its content. Caller frees
 * with vsv_source_free; on failure *out may hold a handle whose error says
 * why (free it too). */
int vsv_source_open(const char *path, vsv_source **out);
void vsv_source_free(vsv_source *s);
const char *vsv_source_error(const vsv_source *s);
/* Short format name, e.g. "GrADS". */
const char *vsv_source_format(const vsv_source *s);
/* Grid, projection, levels, terrain and source description, with no
 * variables (borrowed, valid until free). */
const vsv_meta *vsv_source_grid(const vsv_source *s);
int vsv_source_nfields(const vsv_source *s);
const vsv_field_info *vsv_source_field(const vsv_source *s, int i);
int vsv_source_find_field(const vsv_source *s, const char *name);
int vsv_source_ntimes(const vsv_source *s);
int64_t vsv_source_time(const vsv_source *s, int t);
/* Reads field i at time t into out (nx*ny*nz floats of the grid, x fastest;
 * levels a field lacks and missing values are NaN). */
int vsv_source_read(vsv_source *s, int field, int t, float *out);

#endif
