/* vsv_uamiv.h — CAMx binary UAM-IV files (AVERAGE, INSTANT, AIRQUALITY,
 * EMISSIONS) and their height/pressure companion: the header as read, and
 * field access by hour, species and layer. INPUT-FORMATS.md §2.1. Private to
 * convert/ and the tests. */
#ifndef VSV_UAMIV_H
#define VSV_UAMIV_H

#include <stddef.h>
#include <stdint.h>

/* Everything the header records hold: plain info. */
typedef struct vsv_uamiv_header {
    char name[11];        /* "AVERAGE", ... */
    char note[61];
    int nseg_or_tz;       /* v5: nseg; v6+: time zone */
    int nspec;
    int bdate, edate;     /* YYJJJ (or YYYYJJJ) */
    float bhour, ehour;
    float plon, plat;
    int iutm;
    float xorg, yorg, dx, dy;
    int nx, ny, nz, iproj, istag;
    float tlat1, tlat2, spare;
    int rec3[4];          /* 1, 1, nx, ny */
    char (*species)[11];  /* nspec names */
    int v6;               /* 1 when the region record carries a projection */
    int little_endian;
    int nhours;
} vsv_uamiv_header;

typedef struct vsv_uamiv vsv_uamiv;

/* Maps and checks `path` (size = header + hours × hour size). Caller frees
 * with vsv_uamiv_free; on error *out may hold a handle whose error says why. */
int vsv_uamiv_open(const char *path, vsv_uamiv **out);
int vsv_uamiv_open_mem(const void *data, size_t n, const char *name, vsv_uamiv **out);
/* 1 if the bytes begin like a UAM-IV file. */
int vsv_uamiv_probe(const unsigned char *h, size_t n);
void vsv_uamiv_free(vsv_uamiv *u);
const char *vsv_uamiv_error(const vsv_uamiv *u);
const vsv_uamiv_header *vsv_uamiv_header_get(const vsv_uamiv *u);
/* Begin and end of hour h as written: date (YYJJJ) and decimal hour. */
void vsv_uamiv_hour(const vsv_uamiv *u, int h, int *bdate, float *bhour, int *edate, float *ehour);
/* Seconds since 1970 of a YYJJJ / YYYYJJJ date and a decimal hour. */
int64_t vsv_uamiv_time(int date, float hour);
/* nx*ny floats of (hour, species, layer 0 = surface); 0 or error (a record
 * whose species name or segment disagrees is named). */
int vsv_uamiv_read(vsv_uamiv *u, int hour, int spec, int layer, float *out);

/* Writes a UAM-IV file: the header from h (nhours hours), per hour the
 * dates/decimal hours dates[2t], hours[2t] (begin) and [2t+1] (end), and the
 * values from fn(ctx, hour, species, layer, plane) filling nx*ny floats.
 * Big-endian unless le. 0 or an error code. */
typedef void (*vsv_uamiv_values)(void *ctx, int hour, int spec, int layer, float *plane);
int vsv_uamiv_write(const char *path, const vsv_uamiv_header *h, int le, const int *dates, const float *hours,
                    vsv_uamiv_values fn, void *ctx);

/* The companion height/pressure file (no header): per hour and layer a
 * record of layer-top heights (m above ground), then one of pressures (mb). */
typedef struct vsv_zp vsv_zp;
int vsv_zp_open(const char *path, int nx, int ny, int nz, vsv_zp **out);
void vsv_zp_free(vsv_zp *z);
const char *vsv_zp_error(const vsv_zp *z);
int vsv_zp_nhours(const vsv_zp *z);
/* Layer-top heights (nz*nx*ny, layer-major) of hour h. */
int vsv_zp_heights(vsv_zp *z, int hour, float *out);

#endif
