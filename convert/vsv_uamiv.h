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
    char name[11]; /* "AVERAGE", ... */
    char note[61];
    int nseg_or_tz; /* v5: nseg; v6+: time zone */
    int nspec;
    int bdate, edate; /* YYJJJ (or YYYYJJJ) */
    float bhour, ehour;
    float plon, plat;
    int iutm;
    float xorg, yorg, dx, dy;
    int nx, ny, nz, iproj, istag;
    float tlat1, tlat2, spare;
    int rec3[4];         /* 1, 1, nx, ny */
    char (*species)[11]; /* nspec names */
    int v6;              /* 1 when the region record carries a projection */
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

/* The CAMx met input files beside an average file (INPUT-FORMATS.md
 * §2.1b), read against its grid (nx, ny, nz): kinds below. */
enum { VSV_MET_ZP, VSV_MET_WIND, VSV_MET_TEMP, VSV_MET_HUMID, VSV_MET_KV, VSV_MET_CLOUD };
typedef struct vsv_camxmet vsv_camxmet;
/* Opens and indexes path; want is the kind required (VSV_MET_ZP for
 * --heights) or -1 to detect it (VSV_ENOTVSV: not a met file at all).
 * main_name names the average file in messages about layers and grid.
 * Caller frees with vsv_camxmet_free; on error *out holds the reason. */
int vsv_camxmet_open(const char *path, int want, int nx, int ny, int nz, const char *main_name, vsv_camxmet **out);
void vsv_camxmet_free(vsv_camxmet *m);
const char *vsv_camxmet_error(const vsv_camxmet *m);
const char *vsv_camxmet_path(const vsv_camxmet *m);
const char *vsv_camxmet_kind_name(int kind);
int vsv_camxmet_kind(const vsv_camxmet *m);
int vsv_camxmet_nhours(const vsv_camxmet *m);
/* Fields the file offers (height/pressure: PRESS; wind: U, V; ...): name,
 * units and description are static strings. */
int vsv_camxmet_nfields(const vsv_camxmet *m);
void vsv_camxmet_field(const vsv_camxmet *m, int i, const char **name, const char **units, const char **desc);
/* The time stamp of hour h as written: YYJJJ and HHMM. */
void vsv_camxmet_stamp(const vsv_camxmet *m, int hour, int *date, float *hhmm);
/* Index of the record of (hour, field, layer) and the bytes before its plane. */
int vsv_camxmet_record(const vsv_camxmet *m, int hour, int field, int layer, size_t *skip);
/* nx*ny floats of field f at (hour, layer 0 = surface); winds staggered to
 * cell faces are averaged to centres. 0 or an error. */
int vsv_camxmet_read(vsv_camxmet *m, int hour, int field, int layer, float *out);
/* Height/pressure files: layer-top heights (m above ground, nz*nx*ny). */
int vsv_camxmet_heights(vsv_camxmet *m, int hour, float *out);
/* What a CAMx input file that is no grid of its own is, from its first n
 * bytes: a phrase for a message (a static string), or NULL; *beside is 1
 * for a met or land use file (read beside an average file), 0 for a point
 * source file. */
const char *vsv_camx_input_kind(const unsigned char *head, size_t n, int *beside);

#endif
