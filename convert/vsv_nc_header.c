/* vsv_nc_header.c — the header of a classic netCDF file (CDF-1, CDF-2,
 * CDF-5) walked as the netCDF file format specification lays it out, before
 * libnetcdf opens the file. libnetcdf allocates what an attribute's count
 * says and then copies that many values through its header buffer before it
 * finds the file too short: one damaged count byte (a global attribute of a
 * CMAQ file declaring 1.8·10⁹ doubles) cost 55 s and 14 GB of page faults
 * in nc_open, and the memory stayed allocated after the failed open. Here
 * every list, name and value the header declares must lie inside the file,
 * so such a file is refused at once, naming the record and its offset.
 * The header is read through one window of the file, moved only when a
 * value lies outside it: a skip is arithmetic, not a seek (a seek a name
 * had cost the fuzz target a third of its time in lseek). */
#include "vsv_source_internal.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

typedef struct cur {
    FILE *fp;
    uint64_t size, at;
    int w; /* counts and lengths: 4 bytes, 8 in CDF-5 */
    char *msg;
    size_t cap;
    uint64_t base; /* the file offset of buf[0] */
    size_t have;   /* the bytes of the file in buf */
    unsigned char buf[8192];
} cur;

/* the n bytes at c->at (n at most sizeof buf) into out; -1 when the file
 * holds fewer */
static int peek(cur *c, size_t n, unsigned char *out)
{
    if (c->at < c->base || c->at - c->base > c->have || n > c->have - (size_t)(c->at - c->base)) {
        if (fseeko(c->fp, (off_t)c->at, SEEK_SET))
            return -1;
        c->base = c->at;
        c->have = fread(c->buf, 1, sizeof c->buf, c->fp);
        if (n > c->have)
            return -1;
    }
    memcpy(out, c->buf + (c->at - c->base), n);
    return 0;
}

static int fail(cur *c, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(c->msg, c->cap, fmt, ap);
    va_end(ap);
    return -1;
}

/* a big-endian integer of w bytes; -1 past the end of the file */
static int take(cur *c, int w, uint64_t *v, const char *what)
{
    unsigned char b[8];
    *v = 0;
    if (c->size - c->at < (uint64_t)w || peek(c, (size_t)w, b))
        return fail(c, "netCDF header ends inside the %s at offset %llu (file of %llu bytes)", what,
                    (unsigned long long)c->at, (unsigned long long)c->size);
    for (int i = 0; i < w; i++)
        *v = *v << 8 | b[i];
    c->at += (uint64_t)w;
    return 0;
}

/* n bytes and the padding to 4 after them, which must lie in the file */
static int skip(cur *c, uint64_t n, uint64_t from, const char *what, const char *name)
{
    const uint64_t left = c->size - c->at;
    if (n > left)
        return fail(c,
                    "netCDF header: %s%s%s%s at offset %llu declares %llu bytes, past the end of the file (%llu bytes)",
                    what, name[0] ? " \"" : "", name, name[0] ? "\"" : "", (unsigned long long)from,
                    (unsigned long long)n, (unsigned long long)c->size);
    const uint64_t pad = n % 4 ? 4 - n % 4 : 0;
    const uint64_t step = n + (pad <= left - n ? pad : left - n);
    c->at += step;
    return 0;
}

/* a name (length, bytes); its first bytes, printable, in out */
static int name(cur *c, const char *what, char *out, size_t cap)
{
    uint64_t len;
    const uint64_t from = c->at;
    out[0] = 0;
    if (take(c, c->w, &len, what))
        return -1;
    if (len > c->size - c->at)
        return fail(c,
                    "netCDF header: the name of a %s at offset %llu declares %llu bytes, past the end of the file "
                    "(%llu bytes)",
                    what, (unsigned long long)from, (unsigned long long)len, (unsigned long long)c->size);
    size_t k = len < cap - 1 ? (size_t)len : cap - 1;
    if (peek(c, k, (unsigned char *)out))
        return fail(c, "netCDF header: cannot read the name at offset %llu", (unsigned long long)from);
    out[k] = 0;
    for (size_t i = 0; i < k; i++)
        if (out[i] < 0x20 || out[i] > 0x7e)
            out[i] = '?';
    return skip(c, len, from, "the name of a ", what);
}

/* a list's tag (0 when absent, else want) and its count, at most what the
 * rest of the file holds at min bytes an element */
static int list(cur *c, uint32_t want, int min, const char *what, uint64_t *n)
{
    uint64_t tag;
    const uint64_t from = c->at;
    if (take(c, 4, &tag, what) || take(c, c->w, n, what))
        return -1;
    if (tag != want && !(tag == 0 && *n == 0))
        return fail(c, "netCDF header: bad %s tag 0x%llx at offset %llu", what, (unsigned long long)tag,
                    (unsigned long long)from);
    if (*n > (c->size - c->at) / (uint64_t)min)
        return fail(c, "netCDF header: %s at offset %llu declares %llu entries, more than the file (%llu bytes) holds",
                    what, (unsigned long long)from, (unsigned long long)*n, (unsigned long long)c->size);
    return 0;
}

static int attrs(cur *c, const char *owner)
{
    static const int tsize[] = {0, 1, 1, 2, 4, 4, 8, 1, 2, 4, 8, 8};
    uint64_t n, type, m;
    char nm[64];
    if (list(c, 0x0C, 2 * c->w + 4, "attribute list", &n))
        return -1;
    for (uint64_t i = 0; i < n; i++) {
        const uint64_t from = c->at;
        if (name(c, "attribute", nm, sizeof nm) || take(c, 4, &type, "attribute type") ||
            take(c, c->w, &m, "attribute count"))
            return -1;
        if (type < 1 || type > (c->w == 8 ? 11u : 6u))
            return fail(c, "netCDF header: attribute \"%s\" of %s at offset %llu has an unknown type %llu", nm, owner,
                        (unsigned long long)from, (unsigned long long)type);
        const uint64_t sz = (uint64_t)tsize[type];
        if (m > (c->size - c->at) / sz)
            return fail(c,
                        "netCDF header: attribute \"%s\" of %s at offset %llu declares %llu values of %llu bytes, "
                        "past the end of the file (%llu bytes)",
                        nm, owner, (unsigned long long)from, (unsigned long long)m, (unsigned long long)sz,
                        (unsigned long long)c->size);
        if (skip(c, m * sz, from, "attribute", nm))
            return -1;
    }
    return 0;
}

/* The bytes of a variable's values: the product of its dimensions' lengths
 * (the record dimension's left out) times its type's size, as libnetcdf
 * sizes it (the header's own size field is redundant and may be rounded);
 * UINT64_MAX when not known (an unknown dimension, or too large). */
static uint64_t values_size(const uint64_t *dimlen, uint64_t ndimlen, const uint64_t *ids, uint64_t ndims,
                            uint64_t recdim, uint64_t type)
{
    static const int tsize[] = {0, 1, 1, 2, 4, 4, 8, 1, 2, 4, 8, 8};
    uint64_t bytes = (uint64_t)tsize[type];
    for (uint64_t d = 0; d < ndims; d++) {
        if (d == 0 && ids[0] == recdim)
            continue;
        if (ids[d] >= ndimlen)
            return UINT64_MAX;
        const uint64_t l = dimlen[ids[d]];
        if (l && bytes > UINT64_MAX / 2 / l)
            return UINT64_MAX;
        bytes *= l;
    }
    return bytes;
}

int vsv_nc_classic_check(FILE *fp, uint64_t size, char *msg, size_t cap)
{
    unsigned char magic[4];
    cur c;
    c.fp = fp, c.size = size, c.at = 0, c.msg = msg, c.cap = cap, c.base = 0, c.have = 0;
    if (size < 4 || peek(&c, 4, magic) || memcmp(magic, "CDF", 3) || (magic[3] != 1 && magic[3] != 2 && magic[3] != 5))
        return 1;
    c.at = 4;
    c.w = magic[3] == 5 ? 8 : 4;
    uint64_t recs, n, len, ndims, type, recsize = 0, recbegin = UINT64_MAX;
    int nrec = 0, big = 0;
    char nm[64], owner[96];
    /* where the data ends, from the dimensions' lengths: the largest end of
     * a fixed variable (fix_end), of a record variable's values in the
     * first record (rec_end), and a record's size (rec_pad: the values of
     * each record variable rounded up to 4 bytes; rec_one: of the only one,
     * not rounded). known: every size could be worked out */
    enum { MAXDIMS = 1024 }; /* libnetcdf's NC_MAX_DIMS */
    uint64_t dimlen[MAXDIMS], ids[MAXDIMS], fix_end = 0, rec_end = 0, rec_pad = 0, rec_one = 0;
    int known = 1;
    char fix_name[64] = "", rec_name[64] = "";
    if (take(&c, c.w, &recs, "record count") || list(&c, 0x0A, 2 * c.w, "dimension list", &n))
        return -1;
    const uint64_t ndimlen = n < MAXDIMS ? n : MAXDIMS;
    known = n <= MAXDIMS;
    uint64_t recdim = UINT64_MAX; /* the dimension of length 0: the records */
    for (uint64_t i = 0; i < n; i++) {
        if (name(&c, "dimension", nm, sizeof nm) || take(&c, c.w, &len, "dimension length"))
            return -1;
        if (len == 0 && recdim == UINT64_MAX)
            recdim = i;
        if (i < MAXDIMS)
            dimlen[i] = len;
    }
    if (attrs(&c, "the file") || list(&c, 0x0B, 5 * c.w + 8, "variable list", &n))
        return -1;
    for (uint64_t i = 0; i < n; i++) {
        const uint64_t from = c.at;
        if (name(&c, "variable", nm, sizeof nm) || take(&c, c.w, &ndims, "variable rank"))
            return -1;
        if (ndims > (c.size - c.at) / (uint64_t)c.w)
            return fail(&c,
                        "netCDF header: variable \"%s\" at offset %llu declares %llu dimensions, more than the "
                        "file (%llu bytes) holds",
                        nm, (unsigned long long)from, (unsigned long long)ndims, (unsigned long long)c.size);
        snprintf(owner, sizeof owner, "variable \"%s\"", nm);
        uint64_t first = UINT64_MAX, begin;
        for (uint64_t d = 0; d < ndims; d++) {
            uint64_t id;
            if (take(&c, c.w, &id, "variable dimension"))
                return -1;
            if (d == 0)
                first = id;
            if (d < MAXDIMS)
                ids[d] = id;
        }
        if (attrs(&c, owner) || take(&c, 4, &type, "variable type") || take(&c, c.w, &len, "variable size") ||
            take(&c, magic[3] == 1 ? 4 : 8, &begin, "variable offset"))
            return -1;
        /* libnetcdf sizes a variable of a type the format lacks as 0 bytes
         * a value, then divides by that size (SIGFPE in NC_check_vlen) */
        if (type < 1 || type > (c.w == 8 ? 11u : 6u))
            return fail(&c, "netCDF header: variable \"%s\" at offset %llu has an unknown type %llu", nm,
                        (unsigned long long)from, (unsigned long long)type);
        const int rec = first == recdim && recdim != UINT64_MAX;
        const uint64_t vs =
            ndims <= MAXDIMS ? values_size(dimlen, ndimlen, ids, ndims, rec ? recdim : UINT64_MAX, type) : UINT64_MAX;
        if (vs == UINT64_MAX || begin > UINT64_MAX / 4 - vs) {
            known = 0;
        } else if (vs) {
            uint64_t *const end = rec ? &rec_end : &fix_end;
            if (begin + vs > *end) {
                *end = begin + vs;
                snprintf(rec ? rec_name : fix_name, sizeof fix_name, "%s", nm);
            }
            if (rec)
                rec_pad += (vs + 3) & ~(uint64_t)3, rec_one = vs;
        }
        if (rec) {
            nrec++;
            big |= c.w == 4 && len == UINT32_MAX; /* a size too large for the field */
            recsize = len > UINT64_MAX - recsize ? UINT64_MAX : recsize + len;
            if (begin < recbegin)
                recbegin = begin;
        }
    }
    /* every record but the last begins inside the file: libnetcdf reads a
     * record variable record by record, a seek and a short read each, so a
     * damaged record count (16.7 million records in a 17 KB file) cost it
     * 20 s per variable read. The format's "streaming" count (all bits
     * set) is no exception: libnetcdf 4.9 takes it as 4,294,967,295
     * records (and the WRF reader then asked for 81 GB of times) */
    if (nrec == 1) /* one record variable: its records are not padded */
        recsize = recsize > 3 ? recsize - 3 : 0;
    if (nrec && !big && recsize && recs > 1 && (recbegin > size || recs - 1 > (size - recbegin) / recsize))
        return fail(&c,
                    "netCDF header: the file declares %llu records of at least %llu bytes from offset %llu, past "
                    "the end of the file (%llu bytes)",
                    (unsigned long long)recs, (unsigned long long)recsize, (unsigned long long)recbegin,
                    (unsigned long long)size);
    /* and the file holds every variable's data: libnetcdf reads a file cut
     * inside its data as zeros past the end, without an error */
    if (!known)
        return 0;
    if (fix_end > size)
        return fail(&c, "netCDF: the file is cut short: variable \"%s\"'s data ends at byte %llu, the file has %llu",
                    fix_name, (unsigned long long)fix_end, (unsigned long long)size);
    const uint64_t rs = nrec == 1 ? rec_one : rec_pad; /* a record's bytes */
    if (nrec && recs && (rec_end > size || (rs && recs - 1 > (size - rec_end) / rs))) {
        const uint64_t last = rs && recs - 1 > (UINT64_MAX - rec_end) / rs ? UINT64_MAX : rec_end + (recs - 1) * rs;
        return fail(&c,
                    "netCDF: the file is cut short: record %llu of %llu (variable \"%s\") ends at byte %llu, the "
                    "file has %llu",
                    (unsigned long long)recs, (unsigned long long)recs, rec_name, (unsigned long long)last,
                    (unsigned long long)size);
    }
    return 0;
}
