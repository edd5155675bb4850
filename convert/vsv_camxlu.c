/* vsv_camxlu.c — a CAMx land-use file (INPUT-FORMATS.md §2.1b) found among
 * the --met companions: each cell's dominant category becomes the grid's
 * land use, with the scheme's water category. */
#include "vsv_f77.h"
#include "vsv_source_internal.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A CAMx land-use file (INPUT-FORMATS.md §2.1b: a record "LUCAT11 " or
 * "LUCAT26 ", then ncat x nx*ny fractions): 1 if head starts like one. */
int vsv_camx_is_landuse(const unsigned char *head, size_t n)
{
    return n >= 12 && (!memcmp(head + 4, "LUCAT11 ", 8) || !memcmp(head + 4, "LUCAT26 ", 8));
}

/* Reads it into the grid's land use: each cell's dominant category (1-based),
 * water being category 7 of the 11 (CAMx's "water") or 1 of the 26 (Zhang's
 * "water"). 0 or error. */
int vsv_camx_landuse(vsv_source *s, const char *path)
{
    vsv_meta *g = &s->grid;
    const size_t plane = (size_t)g->nx * g->ny;
    char why[300];
    FILE *fp = vsv_input_fopen(path, "rb", why, sizeof why); /* a regular file: no FIFO to block on */
    if (!fp)
        return vsv_source_fail(s, VSV_EIO, "%s: %s", path, why);
    unsigned char *d = NULL;
    size_t n = 0, cap = 0;
    for (;;) {
        if (n == cap) {
            unsigned char *nd = realloc(d, cap = cap ? 2 * cap : 65536);
            if (!nd) {
                free(d);
                fclose(fp);
                return VSV_ENOMEM;
            }
            d = nd;
        }
        const size_t got = fread(d + n, 1, cap - n, fp);
        n += got;
        if (!got)
            break;
    }
    const int bad = ferror(fp), e = errno;
    fclose(fp);
    if (bad) {
        free(d);
        return vsv_source_fail(s, VSV_EIO, "%s: cannot read: %s", path, strerror(e));
    }
    const int le = n >= 4 && d[0] == 8; /* the first record is 8 bytes long */
    const int ncat = n >= 12 && !memcmp(d + 4, "LUCAT26 ", 8) ? 26 : 11;
    size_t at = 0;
    const unsigned char *p;
    uint32_t len;
    char msg[300];
    int rc = vsv_f77_record(d, n, le, &at, 1, &p, &len, msg, sizeof msg);
    if (!rc)
        rc = vsv_f77_record(d, n, le, &at, 2, &p, &len, msg, sizeof msg);
    if (!rc && len < (uint64_t)ncat * plane * 4) {
        snprintf(msg, sizeof msg, "record 2 holds %u bytes, %d categories of %d x %d cells need %zu", len, ncat, g->nx,
                 g->ny, (size_t)ncat * plane * 4);
        rc = VSV_ECORRUPT;
    }
    if (!rc && !(rc = vsv_meta_alloc_landuse(g))) {
        for (size_t c = 0; c < plane; c++) {
            int best = 0;
            float bf = -1;
            for (int k = 0; k < ncat; k++) {
                const float f = vsv_f77_f32(le, p + 4 * ((size_t)k * plane + c));
                if (f > bf)
                    bf = f, best = k;
            }
            g->landuse[c] = (float)(best + 1);
        }
        vsv_meta_add_attr(g, "landuse_water", ncat == 26 ? "1" : "7");
        vsv_meta_add_attr(g, "landuse", ncat == 26 ? "CAMx LUCAT26 (dominant)" : "CAMx LUCAT11 (dominant)");
    }
    free(d);
    if (rc && rc != VSV_ENOMEM)
        return vsv_source_fail(s, rc, "land-use file %s: %s", path, msg);
    return rc;
}
