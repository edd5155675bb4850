/* vsv_uamiv.c — CAMx UAM-IV reader and writer: Fortran records like MM5's
 * (big-endian, or little-endian by the first marker); four header records,
 * then per hour a time record and nspec × nz data records (species outer,
 * layer inner). The number of hours comes from the file size, which must
 * divide evenly. The source over it: vsv_camx_source.c. */
#include "vsv_uamiv.h"
#include "vsv_f77.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

struct vsv_uamiv {
    const unsigned char *d;
    size_t n;
    vsv_mapped map; /* a file's mapping (open), or none (open_mem) */
    char path[1024];
    char err[512];
    vsv_uamiv_header h;
    size_t hdr_bytes, hour_bytes, rec_bytes;
};

/* n characters stored one per 4-byte word, blanks trimmed. */
static void c4(char *dst, const unsigned char *p, int n, int le)
{
    int k = 0;
    for (int i = 0; i < n; i++) {
        unsigned char ch = le ? p[4 * i] : p[4 * i];
        dst[k++] = ch >= 32 && ch < 127 ? (char)ch : ' ';
    }
    while (k && dst[k - 1] == ' ')
        k--;
    dst[k] = 0;
}

const char *vsv_uamiv_error(const vsv_uamiv *u) { return u ? u->err : "out of memory"; }
const vsv_uamiv_header *vsv_uamiv_header_get(const vsv_uamiv *u) { return &u->h; }

static int ufail(vsv_uamiv *u, int rc, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static int ufail(vsv_uamiv *u, int rc, const char *fmt, ...)
{
    if (vsv_input_cut(&u->map, 1)) { /* zeros read past a new end: not the file's damage */
        vsv_msg(u->err, sizeof u->err, "%s: %s", u->path, VSV_CUT_TEXT);
        return VSV_ETRUNC;
    }
    va_list ap;
    va_start(ap, fmt);
    vsv_vmsg_path(u->err, sizeof u->err, u->path, fmt, ap);
    va_end(ap);
    return rc;
}

int vsv_uamiv_probe(const unsigned char *h, size_t n)
{
    static const char *names[] = {"AVERAGE", "INSTANT", "AIRQUALITY", "EMISSIONS", "BOUNDARY", NULL};
    if (n < 16)
        return 0;
    const int le = h[0] == 0x30 && h[1] == 1 && !h[2] && !h[3];
    const int be = !h[0] && !h[1] && h[2] == 1 && h[3] == 0x30;
    if (!le && !be)
        return 0;
    char name[11];
    c4(name, h + 4, n >= 44 ? 10 : 2, le);
    for (int i = 0; names[i]; i++)
        if (!strncmp(name, names[i], strlen(name)) && name[0])
            return 1;
    return 0;
}

int64_t vsv_uamiv_time(int date, float hour)
{
    int year = date / 1000, jday = date % 1000;
    if (year < 100)
        year += year >= 70 ? 1900 : 2000;
    return vsv_time_from_civil(year, 1, 1, 0, 0, 0) + (int64_t)(jday - 1) * 86400 + (int64_t)llround(hour * 3600.0);
}

/* The record at *at, which must hold `want` bytes; advances *at. */
static int record(vsv_uamiv *u, size_t *at, int recno, uint32_t want, const unsigned char **p)
{
    char msg[300];
    uint32_t len = 0;
    const size_t start = *at;
    const int rc = vsv_f77_record(u->d, u->n, u->h.little_endian, at, recno, p, &len, msg, sizeof msg);
    if (rc)
        return ufail(u, rc, "%s", msg);
    if (len != want) {
        *at = start;
        return ufail(u, VSV_ECORRUPT, "record %d at byte offset %zu: %u bytes, expected %u", recno, start, len, want);
    }
    return 0;
}

static int parse(vsv_uamiv *u)
{
    if (!vsv_uamiv_probe(u->d, u->n))
        return ufail(u, VSV_ENOTVSV, "not a CAMx UAM-IV file");
    vsv_uamiv_header *h = &u->h;
    const int le = h->little_endian = u->d[0] == 0x30;
    size_t at = 0;
    const unsigned char *p;
    int rc;
    if ((rc = record(u, &at, 1, 304, &p)))
        return rc;
    c4(h->name, p, 10, le);
    if (!strcmp(h->name, "BOUNDARY"))
        return ufail(u, VSV_EUNSUPPORTED,
                     "a CAMx lateral boundary file (BOUNDARY): values on the domain's four "
                     "edges, not a 3-D grid");
    c4(h->note, p + 40, 60, le);
    h->nseg_or_tz = (int32_t)vsv_f77_u32(le, p + 280);
    h->nspec = (int32_t)vsv_f77_u32(le, p + 284);
    h->bdate = (int32_t)vsv_f77_u32(le, p + 288);
    h->bhour = vsv_f77_f32(le, p + 292);
    h->edate = (int32_t)vsv_f77_u32(le, p + 296);
    h->ehour = vsv_f77_f32(le, p + 300);
    if (h->nspec < 1 || h->nspec > 10000)
        return ufail(u, VSV_ECORRUPT, "header: %d species", h->nspec);
    if ((rc = record(u, &at, 2, 60, &p)))
        return rc;
    h->plon = vsv_f77_f32(le, p);
    h->plat = vsv_f77_f32(le, p + 4);
    h->iutm = (int32_t)vsv_f77_u32(le, p + 8);
    h->xorg = vsv_f77_f32(le, p + 12);
    h->yorg = vsv_f77_f32(le, p + 16);
    h->dx = vsv_f77_f32(le, p + 20);
    h->dy = vsv_f77_f32(le, p + 24);
    h->nx = (int32_t)vsv_f77_u32(le, p + 28);
    h->ny = (int32_t)vsv_f77_u32(le, p + 32);
    h->nz = (int32_t)vsv_f77_u32(le, p + 36);
    h->iproj = (int32_t)vsv_f77_u32(le, p + 40);
    h->istag = (int32_t)vsv_f77_u32(le, p + 44);
    h->tlat1 = vsv_f77_f32(le, p + 48);
    h->tlat2 = vsv_f77_f32(le, p + 52);
    h->spare = vsv_f77_f32(le, p + 56);
    if (h->nx < 1 || h->ny < 1 || h->nz < 1 || h->nx > VSV_MAX_DIM || h->ny > VSV_MAX_DIM || h->nz > 1000 ||
        !(h->dx > 0) || !(h->dy > 0))
        return ufail(u, VSV_ECORRUPT, "region record: grid %d x %d x %d, cells %g x %g", h->nx, h->ny, h->nz, h->dx,
                     h->dy);
    /* v6+ writes the projection here; CAMx 5 writes zeros (and metres) */
    const int looks_latlon = fabsf(h->xorg) <= 360 && h->dx < 10;
    h->v6 = h->iproj != 0 || h->tlat1 != 0 || h->tlat2 != 0 || h->plon != 0 || h->plat != 0 || looks_latlon;
    if ((rc = record(u, &at, 3, 16, &p)))
        return rc;
    for (int i = 0; i < 4; i++)
        h->rec3[i] = (int32_t)vsv_f77_u32(le, p + 4 * i);
    if ((rc = record(u, &at, 4, (uint32_t)(40 * h->nspec), &p)))
        return rc;
    h->species = calloc((size_t)h->nspec, sizeof *h->species);
    if (!h->species)
        return VSV_ENOMEM;
    for (int s = 0; s < h->nspec; s++)
        c4(h->species[s], p + 40 * s, 10, le);
    u->hdr_bytes = at;
    u->rec_bytes = 8 + 44 + 4 * (size_t)h->nx * h->ny;
    u->hour_bytes = 24 + (size_t)h->nspec * h->nz * u->rec_bytes;
    const size_t body = u->n - at;
    if (body == 0 || body % u->hour_bytes)
        return ufail(u, VSV_ECORRUPT,
                     "file size %zu does not divide into hours: %zu header bytes + a multiple of %zu (expected %zu or "
                     "%zu)",
                     u->n, at, u->hour_bytes, at + (body / u->hour_bytes) * u->hour_bytes,
                     at + (body / u->hour_bytes + 1) * u->hour_bytes);
    h->nhours = (int)(body / u->hour_bytes);
    /* check every time record's framing now (cheap): a damaged file fails at open */
    for (int hr = 0; hr < h->nhours; hr++) {
        size_t t_at = at + (size_t)hr * u->hour_bytes;
        if ((rc = record(u, &t_at, 5 + hr * (1 + h->nspec * h->nz), 16, &p)))
            return rc;
    }
    return 0;
}

int vsv_uamiv_open_mem(const void *data, size_t n, const char *name, vsv_uamiv **out)
{
    vsv_uamiv *u = *out = calloc(1, sizeof *u);
    if (!u)
        return VSV_ENOMEM;
    snprintf(u->path, sizeof u->path, "%s", name);
    u->map = (vsv_mapped){NULL, 0, -1, -1};
    u->d = data;
    u->n = n;
    return parse(u);
}

int vsv_uamiv_open(const char *path, vsv_uamiv **out)
{
    vsv_uamiv *u = *out = calloc(1, sizeof *u);
    if (!u)
        return VSV_ENOMEM;
    snprintf(u->path, sizeof u->path, "%s", path);
    char why[160];
    const int rc = vsv_input_map(path, 16, &u->map, why, sizeof why);
    u->d = u->map.data;
    u->n = u->map.n;
    if (rc < 0)
        return ufail(u, VSV_EIO, "%s", why);
    if (rc > 0)
        return ufail(u, VSV_ENOTVSV, "not a CAMx UAM-IV file");
    const int prc = parse(u);
    return prc || !vsv_input_cut(&u->map, 1) ? prc : ufail(u, VSV_ETRUNC, VSV_CUT_TEXT);
}

void vsv_uamiv_free(vsv_uamiv *u)
{
    if (!u)
        return;
    vsv_input_unmap(&u->map);
    free(u->h.species);
    free(u);
}

void vsv_uamiv_hour(const vsv_uamiv *u, int h, int *bdate, float *bhour, int *edate, float *ehour)
{
    const unsigned char *p = u->d + u->hdr_bytes + (size_t)h * u->hour_bytes + 4;
    const int le = u->h.little_endian;
    *bdate = (int32_t)vsv_f77_u32(le, p);
    *bhour = vsv_f77_f32(le, p + 4);
    *edate = (int32_t)vsv_f77_u32(le, p + 8);
    *ehour = vsv_f77_f32(le, p + 12);
}

int vsv_uamiv_read(vsv_uamiv *u, int hour, int spec, int layer, float *out)
{
    const vsv_uamiv_header *h = &u->h;
    if (hour < 0 || hour >= h->nhours || spec < 0 || spec >= h->nspec || layer < 0 || layer >= h->nz)
        return ufail(u, VSV_ERANGE, "hour %d, species %d, layer %d out of range", hour, spec, layer);
    size_t at = u->hdr_bytes + (size_t)hour * u->hour_bytes + 24 + ((size_t)spec * h->nz + layer) * u->rec_bytes;
    const unsigned char *p;
    const int recno = 5 + hour * (1 + h->nspec * h->nz) + 1 + spec * h->nz + layer;
    int rc = record(u, &at, recno, (uint32_t)(u->rec_bytes - 8), &p);
    if (rc)
        return rc;
    char name[11];
    c4(name, p + 4, 10, h->little_endian);
    if (strcmp(name, h->species[spec]))
        return ufail(u, VSV_ECORRUPT, "record %d at byte offset %zu: species %s where %s was expected", recno,
                     at - u->rec_bytes, name, h->species[spec]);
    const size_t n = (size_t)h->nx * h->ny;
    for (size_t i = 0; i < n; i++)
        out[i] = vsv_f77_f32(h->little_endian, p + 44 + 4 * i);
    /* the values are the file's only if it did not shrink meanwhile */
    return vsv_input_cut(&u->map, 1) ? ufail(u, VSV_ETRUNC, VSV_CUT_TEXT) : 0;
}

/* ------------------------------------------------------------- writer */

typedef struct uw {
    FILE *fp;
    int le, bad;
} uw;

static void uw32(uw *w, uint32_t v)
{
    unsigned char b[4];
    if (w->le)
        vsv_wr32(b, v);
    else
        b[0] = (unsigned char)(v >> 24), b[1] = (unsigned char)(v >> 16), b[2] = (unsigned char)(v >> 8),
        b[3] = (unsigned char)v;
    w->bad |= fwrite(b, 1, 4, w->fp) != 4;
}

static void uwf(uw *w, float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    uw32(w, u);
}

/* n characters, one per 4-byte word, blank padded (bytes: no byte order) */
static void uwc4(uw *w, const char *s, int n)
{
    const size_t len = strlen(s);
    for (int i = 0; i < n; i++) {
        unsigned char b[4] = {' ', ' ', ' ', ' '};
        if ((size_t)i < len)
            b[0] = (unsigned char)s[i];
        w->bad |= fwrite(b, 1, 4, w->fp) != 4;
    }
}

int vsv_uamiv_write(const char *path, const vsv_uamiv_header *h, int le, const int *dates, const float *hours,
                    vsv_uamiv_values fn, void *ctx)
{
    uw w = {fopen(path, "wb"), le, 0};
    if (!w.fp)
        return VSV_EIO;
    const size_t plane = (size_t)h->nx * h->ny;
    float *buf = malloc(plane * sizeof *buf);
    if (!buf) {
        fclose(w.fp);
        return VSV_ENOMEM;
    }
    uw32(&w, 304);
    uwc4(&w, h->name, 10);
    uwc4(&w, h->note, 60);
    uw32(&w, (uint32_t)h->nseg_or_tz);
    uw32(&w, (uint32_t)h->nspec);
    uw32(&w, (uint32_t)h->bdate);
    uwf(&w, h->bhour);
    uw32(&w, (uint32_t)h->edate);
    uwf(&w, h->ehour);
    uw32(&w, 304);
    uw32(&w, 60);
    uwf(&w, h->plon);
    uwf(&w, h->plat);
    uw32(&w, (uint32_t)h->iutm);
    uwf(&w, h->xorg);
    uwf(&w, h->yorg);
    uwf(&w, h->dx);
    uwf(&w, h->dy);
    uw32(&w, (uint32_t)h->nx);
    uw32(&w, (uint32_t)h->ny);
    uw32(&w, (uint32_t)h->nz);
    uw32(&w, (uint32_t)h->iproj);
    uw32(&w, (uint32_t)h->istag);
    uwf(&w, h->tlat1);
    uwf(&w, h->tlat2);
    uwf(&w, h->spare);
    uw32(&w, 60);
    uw32(&w, 16);
    for (int i = 0; i < 4; i++)
        uw32(&w, (uint32_t)h->rec3[i]);
    uw32(&w, 16);
    uw32(&w, (uint32_t)(40 * h->nspec));
    for (int sp = 0; sp < h->nspec; sp++)
        uwc4(&w, h->species[sp], 10);
    uw32(&w, (uint32_t)(40 * h->nspec));
    for (int t = 0; t < h->nhours && !w.bad; t++) {
        uw32(&w, 16);
        uw32(&w, (uint32_t)dates[2 * t]);
        uwf(&w, hours[2 * t]);
        uw32(&w, (uint32_t)dates[2 * t + 1]);
        uwf(&w, hours[2 * t + 1]);
        uw32(&w, 16);
        for (int sp = 0; sp < h->nspec; sp++)
            for (int k = 0; k < h->nz; k++) {
                const uint32_t n = (uint32_t)(44 + 4 * plane);
                fn(ctx, t, sp, k, buf);
                uw32(&w, n);
                uw32(&w, 1);
                uwc4(&w, h->species[sp], 10);
                if (!le) {
                    for (size_t i = 0; i < plane; i++)
                        uwf(&w, buf[i]);
                } else {
                    w.bad |= fwrite(buf, 4, plane, w.fp) != plane; /* little-endian host */
                }
                uw32(&w, n);
            }
    }
    free(buf);
    const int bad = fclose(w.fp) != 0 || w.bad;
    return bad ? VSV_EIO : 0;
}
