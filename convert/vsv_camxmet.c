/* vsv_camxmet.c — the CAMx meteorological input files a modeller keeps
 * beside the output (height/pressure, wind, temperature, humidity, vertical
 * diffusivity, cloud/rain; INPUT-FORMATS.md §2.1b): none carries its grid,
 * so each is read against the average file's nx, ny, nz. The kind comes from
 * the record layout (record sizes, records per time stamp, the cloud file's
 * label), humidity and diffusivity (the same layout) from the file name.
 * Every record is indexed at open: a file that does not fit the grid, the
 * layer count or the hours is refused there, naming what differs. A met
 * file may hold more layers than the average file (CAMx writes the lowest
 * layers only, the surface one by default, when 3-D output is off): its
 * lowest nz are read. */
#include "vsv_f77.h"
#include "vsv_uamiv.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

struct vsv_camxmet {
    const unsigned char *d;
    size_t n;
    vsv_mapped map;
    int le, kind, nx, ny, nz, nhours, per_hour, nfields, stagger;
    int mz;        /* the file's own layers: nz or more */
    size_t *rec;   /* payload offset of every record */
    uint32_t *len; /* and its length */
    int nrec;
    char path[1024], err[600];
};

static const char *const kind_names[] = {"height/pressure",      "wind",      "temperature", "humidity",
                                         "vertical diffusivity", "cloud/rain"};
const char *vsv_camxmet_kind_name(int kind) { return kind >= 0 && kind < 6 ? kind_names[kind] : "?"; }
const char *vsv_camxmet_error(const vsv_camxmet *m) { return m ? m->err : "out of memory"; }
int vsv_camxmet_kind(const vsv_camxmet *m) { return m->kind; }
int vsv_camxmet_nhours(const vsv_camxmet *m) { return m->nhours; }
int vsv_camxmet_nfields(const vsv_camxmet *m) { return m->nfields; }
const char *vsv_camxmet_path(const vsv_camxmet *m) { return m->path; }

static int mfail(vsv_camxmet *m, int rc, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static int mfail(vsv_camxmet *m, int rc, const char *fmt, ...)
{
    if (vsv_input_cut(&m->map, 1)) { /* zeros read past a new end: not the file's damage */
        vsv_msg(m->err, sizeof m->err, "%s: %s", m->path, VSV_CUT_TEXT);
        return VSV_ETRUNC;
    }
    va_list ap;
    va_start(ap, fmt);
    vsv_vmsg_path(m->err, sizeof m->err, m->path, fmt, ap);
    va_end(ap);
    return rc;
}

void vsv_camxmet_field(const vsv_camxmet *m, int i, const char **name, const char **units, const char **desc)
{
    static const char *const cloud4[] = {"CWC", "RWC", "SWC", "GWC", "COD"};
    switch (m->kind) {
    case VSV_MET_ZP: *name = "PRESS", *units = "mb", *desc = "pressure (CAMx height/pressure file)"; return;
    case VSV_MET_WIND:
        *name = i ? "V" : "U", *units = "m/s";
        *desc = i ? "north-south wind (CAMx wind file)" : "east-west wind (CAMx wind file)";
        return;
    case VSV_MET_TEMP: *name = "TEMP", *units = "K", *desc = "temperature (CAMx temperature file)"; return;
    case VSV_MET_HUMID: *name = "HUMIDITY", *units = "ppm", *desc = "water vapour (CAMx humidity file)"; return;
    case VSV_MET_KV: *name = "KV", *units = "m2/s", *desc = "vertical diffusivity (CAMx Kv file)"; return;
    default:
        /* named by their count, CAMx's order: cloud water, rain, snow,
         * graupel (g/m3), then cloud optical depth; 3 fields are CAMx 4's
         * cloud water, rain and optical depth */
        *name = m->nfields == 3 && i == 2 ? "COD" : i < 5 ? cloud4[i] : "CLOUDX";
        *units = !strcmp(*name, "COD") ? "1" : "g/m3";
        *desc = "cloud/rain (CAMx cloud/rain file)";
        return;
    }
}

/* The time stamp of record r: HHMM as a float, YYJJJ. */
static void stamp(const vsv_camxmet *m, int r, float *hhmm, int *date)
{
    *hhmm = vsv_f77_f32(m->le, m->d + m->rec[r]);
    *date = (int32_t)vsv_f77_u32(m->le, m->d + m->rec[r] + 4);
}

static int same_stamp(const vsv_camxmet *m, int a, int b) { return !memcmp(m->d + m->rec[a], m->d + m->rec[b], 8); }

/* 1 when every value of the first hour's records (per of them) could be a
 * temperature (150 to 350 K): a temperature file with more layers than the
 * average file is told from a humidity or diffusivity one so. */
static int temperatures(const vsv_camxmet *m, int per)
{
    for (int r = 0; r < per; r++)
        for (uint32_t i = 8; i + 4 <= m->len[r]; i += 4) {
            const float v = vsv_f77_f32(m->le, m->d + m->rec[r] + i);
            if (!(v >= 150 && v <= 350))
                return 0;
        }
    return 1;
}

/* Which kind a file of stamped plane records is, from its records per hour:
 * the layouts of the average file's nz layers first, then of more layers
 * (m->mz), a temperature file told from a height/pressure one by its
 * values, humidity and diffusivity (one layout) by the file name. */
static int stamped_kind(vsv_camxmet *m, int per_hour, const char *base, const char *main_name)
{
    const int nz = m->nz;
    /* height/pressure: even records are layer-top heights (m), rising, odd
     * ones pressures (mb), falling (at the first cell) */
    const float p0 = per_hour >= 2 ? vsv_f77_f32(m->le, m->d + m->rec[1] + 8) : 0;
    int zp = per_hour % 2 == 0 && p0 > 1 && p0 < 1100;
    if (zp && per_hour >= 4) {
        const float h0 = vsv_f77_f32(m->le, m->d + m->rec[0] + 8), h1 = vsv_f77_f32(m->le, m->d + m->rec[2] + 8),
                    p1 = vsv_f77_f32(m->le, m->d + m->rec[3] + 8);
        zp = h0 > 0 && h1 > h0 && p1 < p0;
    }
    const int named = strcasestr(base, "hum") || strcasestr(base, "qv") || strcasestr(base, "h2o") ? VSV_MET_HUMID
                      : strcasestr(base, "diff") || strcasestr(base, "kv")                         ? VSV_MET_KV
                                                                                                   : -1;
    if (per_hour == 2 * nz && zp)
        return VSV_MET_ZP;
    if (per_hour == nz + 1)
        return VSV_MET_TEMP;
    if (per_hour >= nz && named >= 0)
        return m->mz = per_hour, named;
    if (per_hour > nz + 1 && temperatures(m, per_hour))
        return m->mz = per_hour - 1, VSV_MET_TEMP;
    if (per_hour > 2 * nz && zp)
        return m->mz = per_hour / 2, VSV_MET_ZP;
    if (per_hour == nz || (per_hour > nz && !zp))
        return mfail(m, VSV_EUNSUPPORTED,
                     "%d plane records an hour: humidity or vertical diffusivity, which share one layout; name it "
                     "with 'humid' or 'kv' in the file name",
                     per_hour);
    return mfail(m, VSV_EINVAL,
                 "%d plane records an hour, which fits no CAMx met file of the %d layer%s of %s (height/pressure "
                 "needs %d, temperature %d, humidity and diffusivity %d, or more): fewer layers",
                 per_hour, nz, nz == 1 ? "" : "s", main_name, 2 * nz, nz + 1, nz);
}

int vsv_camxmet_open(const char *path, int want, int nx, int ny, int nz, const char *main_name, vsv_camxmet **out)
{
    vsv_camxmet *m = *out = calloc(1, sizeof *m);
    if (!m)
        return VSV_ENOMEM;
    snprintf(m->path, sizeof m->path, "%s", path);
    m->nx = nx, m->ny = ny, m->nz = m->mz = nz, m->kind = -1;
    char why[160];
    const int mapped = vsv_input_map(path, 12, &m->map, why, sizeof why);
    m->d = m->map.data;
    m->n = m->map.n;
    if (mapped < 0)
        return mfail(m, VSV_EIO, "%s", why);
    if (mapped > 0)
        return mfail(m, VSV_ENOTVSV, "not a CAMx met file (too short or not a file)");
    /* byte order from the first marker (a record is under 16 MB here) */
    m->le = vsv_rd32(m->d) < (1u << 24);
    /* index every record */
    size_t at = 0, cap = 0;
    while (at < m->n) {
        const unsigned char *pl;
        uint32_t len;
        char msg[300];
        int rc = vsv_f77_record(m->d, m->n, m->le, &at, m->nrec + 1, &pl, &len, msg, sizeof msg);
        if (rc)
            return mfail(m, want < 0 ? VSV_ENOTVSV : rc, "%s", msg);
        if ((size_t)m->nrec == cap) {
            cap = cap ? 2 * cap : 256;
            size_t *r = realloc(m->rec, cap * sizeof *r);
            uint32_t *l = realloc(m->len, cap * sizeof *l);
            if (r)
                m->rec = r;
            if (l)
                m->len = l;
            if (!r || !l)
                return VSV_ENOMEM;
        }
        m->rec[m->nrec] = (size_t)(pl - m->d);
        m->len[m->nrec++] = len;
    }
    const uint32_t plane = 4u * (uint32_t)nx * (uint32_t)ny;
    const char *base = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
    /* the layout */
    if (m->len[0] == 32 && !memcmp(m->d + m->rec[0], "CAMx", 4)) {
        m->kind = VSV_MET_CLOUD;
        const int cx = (int)vsv_f77_u32(m->le, m->d + m->rec[0] + 20),
                  cy = (int)vsv_f77_u32(m->le, m->d + m->rec[0] + 24),
                  cz = (int)vsv_f77_u32(m->le, m->d + m->rec[0] + 28);
        if (cx != nx || cy != ny || cz < nz)
            return mfail(m, VSV_EINVAL, "cloud/rain grid %d x %d x %d, %s is %d x %d x %d%s", cx, cy, cz, main_name, nx,
                         ny, nz, cx == nx && cy == ny ? " (a met file may have more layers, not fewer)" : "");
        m->mz = cz;
        int r = 2;
        while (r < m->nrec && m->len[r] != 8)
            r++;
        m->per_hour = r - 1;
        if (m->nrec < 2 || m->len[1] != 8 || (m->per_hour - 1) % cz || m->per_hour - 1 < cz)
            return mfail(m, VSV_ECORRUPT, "cloud/rain records do not repeat per hour as 1 + %d layers x fields", cz);
        m->nfields = (m->per_hour - 1) / cz;
        if (m->nfields > 6)
            return mfail(m, VSV_EUNSUPPORTED, "cloud/rain: %d fields per layer (at most 6 known)", m->nfields);
        m->nhours = (m->nrec - 1) / m->per_hour;
        if ((m->nrec - 1) % m->per_hour)
            return mfail(m, VSV_ECORRUPT, "cloud/rain: %d records are not whole hours of %d", m->nrec - 1, m->per_hour);
    } else if ((m->len[0] == 8 || m->len[0] == 12) && m->nrec > 1 && m->len[1] == plane) {
        m->kind = VSV_MET_WIND;
        /* the layers: the planes before the first 4-byte dummy record */
        int r = 1;
        while (r < m->nrec && m->len[r] == plane)
            r++;
        m->mz = (r - 1) / 2 >= nz && r < m->nrec && m->len[r] == 4 ? (r - 1) / 2 : nz;
        m->per_hour = 2 + 2 * m->mz;
        if (m->len[0] == 12)
            m->stagger = (int32_t)vsv_f77_u32(m->le, m->d + m->rec[0] + 8) == 1;
        if (m->nrec % m->per_hour || m->len[m->per_hour - 1] != 4 ||
            (m->nrec > m->per_hour && m->len[m->per_hour] != m->len[0]))
            return mfail(m, VSV_EINVAL,
                         "wind records do not repeat every %d (time, U and V of %d layer%s, dummy): fewer layers than "
                         "%s, or damaged",
                         m->per_hour, m->mz, m->mz == 1 ? "" : "s", main_name);
        m->nhours = m->nrec / m->per_hour;
        m->nfields = 2;
    } else if (m->len[0] == 8 + plane) {
        int per = 1;
        while (per < m->nrec && m->len[per] == 8 + plane && same_stamp(m, 0, per))
            per++;
        const int kind = stamped_kind(m, per, base, main_name);
        if (kind < 0)
            return kind;
        if (want >= 0 && kind != want && !(want == VSV_MET_ZP))
            return mfail(m, VSV_EINVAL, "a %s file where a %s file was wanted", kind_names[kind], kind_names[want]);
        m->kind = kind;
        m->per_hour = per;
        m->nfields = 1;
        if (m->nrec % per)
            return mfail(m, VSV_ECORRUPT, "%d records are not whole hours of %d", m->nrec, per);
        m->nhours = m->nrec / per;
        for (int r = 0; r < m->nrec; r++)
            if (m->len[r] != 8 + plane || !same_stamp(m, r - r % per, r))
                return mfail(m, VSV_ECORRUPT, "record %d: %u bytes or its time differs from its hour's first", r + 1,
                             m->len[r]);
    } else {
        if (m->len[0] == 8 + plane || m->len[1] == plane)
            return mfail(m, VSV_ENOTVSV, "not a CAMx met file");
        return mfail(m, want < 0 ? VSV_ENOTVSV : VSV_EINVAL,
                     "records of %u bytes: not a CAMx met file of the %d x %d grid of %s (a plane is %u bytes)",
                     m->len[0], nx, ny, main_name, plane);
    }
    if (want == VSV_MET_ZP && m->kind != VSV_MET_ZP)
        return mfail(m, VSV_EINVAL, "a %s file, not a height/pressure file", kind_names[m->kind]);
    /* every plane record must be a plane of this grid */
    for (int h = 0; h < m->nhours; h++)
        for (int f = 0; f < m->nfields; f++)
            for (int k = 0; k < m->mz; k++) {
                size_t off;
                int r = vsv_camxmet_record(m, h, f, k, &off);
                if (m->len[r] != plane + off)
                    return mfail(m, VSV_ECORRUPT, "record %d: %u bytes, a %d x %d plane needs %u", r + 1, m->len[r], nx,
                                 ny, plane + (uint32_t)off);
            }
    return vsv_input_cut(&m->map, 1) ? mfail(m, VSV_ETRUNC, VSV_CUT_TEXT) : 0;
}

int vsv_camxmet_record(const vsv_camxmet *m, int hour, int field, int layer, size_t *skip)
{
    const int base = hour * m->per_hour;
    switch (m->kind) {
    case VSV_MET_ZP: *skip = 8; return base + 2 * layer + (field ? 1 : 0);
    case VSV_MET_WIND: *skip = 0; return base + 1 + 2 * layer + field;
    case VSV_MET_TEMP: *skip = 8; return base + 1 + layer;
    case VSV_MET_CLOUD: *skip = 0; return 1 + base + 1 + layer * m->nfields + field;
    default: *skip = 8; return base + layer;
    }
}

void vsv_camxmet_stamp(const vsv_camxmet *m, int hour, int *date, float *hhmm)
{
    const int r = m->kind == VSV_MET_CLOUD ? 1 + hour * m->per_hour : hour * m->per_hour;
    stamp(m, r, hhmm, date);
}

int vsv_camxmet_read(vsv_camxmet *m, int hour, int field, int layer, float *out)
{
    if (hour < 0 || hour >= m->nhours || field < 0 || field >= m->nfields || layer < 0 || layer >= m->nz)
        return mfail(m, VSV_ERANGE, "hour %d, field %d, layer %d out of range", hour, field, layer);
    size_t skip;
    const int r = vsv_camxmet_record(m, hour, m->kind == VSV_MET_ZP ? field + 1 : field, layer, &skip);
    const unsigned char *p = m->d + m->rec[r] + skip;
    const int nx = m->nx, ny = m->ny;
    for (int j = 0; j < ny; j++)
        for (int i = 0; i < nx; i++) {
            const size_t c = (size_t)j * nx + i;
            float v = vsv_f77_f32(m->le, p + 4 * c);
            /* staggered winds: U on east faces, V on north faces → centres */
            if (m->kind == VSV_MET_WIND && m->stagger) {
                const size_t w = field ? (j ? c - (size_t)nx : c) : (i ? c - 1 : c);
                v = 0.5f * (v + vsv_f77_f32(m->le, p + 4 * w));
            }
            out[c] = v;
        }
    /* the values are the file's only if it did not shrink meanwhile */
    return vsv_input_cut(&m->map, 1) ? mfail(m, VSV_ETRUNC, VSV_CUT_TEXT) : 0;
}

int vsv_camxmet_heights(vsv_camxmet *m, int hour, float *out)
{
    if (m->kind != VSV_MET_ZP || hour < 0 || hour >= m->nhours)
        return mfail(m, VSV_ERANGE, "no heights of hour %d", hour);
    const size_t plane = (size_t)m->nx * m->ny;
    for (int k = 0; k < m->nz; k++) {
        size_t skip;
        const unsigned char *p = m->d + m->rec[vsv_camxmet_record(m, hour, 0, k, &skip)] + skip;
        for (size_t c = 0; c < plane; c++)
            out[(size_t)k * plane + c] = vsv_f77_f32(m->le, p + 4 * c);
    }
    return vsv_input_cut(&m->map, 1) ? mfail(m, VSV_ETRUNC, VSV_CUT_TEXT) : 0;
}

/* Whether the 8 bytes at p could be a CAMx time stamp: HHMM (a float,
 * 0 to 2400), then YYJJJ (JJJ a day of the year). */
static int stamp_like(int le, const unsigned char *p)
{
    const float hhmm = vsv_f77_f32(le, p);
    const int32_t date = (int32_t)vsv_f77_u32(le, p + 4);
    return hhmm >= 0 && hhmm <= 2400 && date >= 1 && date <= 99366 && date % 1000 >= 1 && date % 1000 <= 366;
}

const char *vsv_camx_input_kind(const unsigned char *h, size_t n, int *beside)
{
    *beside = 1;
    if (n < 40)
        return NULL;
    const int le = vsv_rd32(h) < (1u << 24);
    const uint32_t l0 = vsv_f77_u32(le, h);
    if (l0 == 32 && !memcmp(h + 4, "CAMx", 4))
        return "a CAMx cloud/rain file";
    if (l0 == 8 && !memcmp(h + 4, "LUCAT", 5))
        return "a CAMx land use file";
    if (h[4] == 'P' && h[8] == 'T' && h[12] == 'S' && h[16] == 'O' && h[20] == 'U' && h[24] == 'R' && h[28] == 'C' &&
        h[32] == 'E')
        return *beside = 0, "a CAMx point source file (PTSOURCE): emissions at stacks, not a 3-D grid";
    if ((l0 == 8 || l0 == 12) && stamp_like(le, h + 4) && vsv_f77_u32(le, h + 8 + l0) % 4 == 0 &&
        vsv_f77_u32(le, h + 8 + l0) >= 4)
        return "a CAMx wind file";
    if (l0 > 8 && (l0 - 8) % 4 == 0 && stamp_like(le, h + 4))
        return "a CAMx met file (height/pressure, temperature, humidity or diffusivity)";
    return NULL;
}

void vsv_camxmet_free(vsv_camxmet *m)
{
    if (!m)
        return;
    vsv_input_unmap(&m->map);
    free(m->rec);
    free(m->len);
    free(m);
}
