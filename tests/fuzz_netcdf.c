/* fuzz_netcdf.c — fuzz target for the netCDF model readers (WRF, IOAPI for
 * CMAQ and CAMx, CF): the bytes become a file that vsv_source_open detects
 * and reads whole, with native and with even levels. Inputs in netCDF-4
 * (HDF5) form are skipped: their damage crashes inside libhdf5 itself (a
 * library the project does not own; the tools open them in a bounded child
 * process), so the seeds are the real files converted to netCDF classic.
 * Classic inputs whose header declares more bytes than the file holds are
 * skipped too: libnetcdf allocates such an attribute before it reads it
 * and keeps the memory when the open then fails (found by this target:
 * gigabytes per input, tests/FUZZING.md).
 * Built for libFuzzer by `make fuzz`; also runs as a regression test over
 * tests/corpus/netcdf (fuzz_main.c). */
#include "fuzz_source.h"

#include <stdio.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
const char *const fuzz_default_dirs[4] = {"tests/corpus/netcdf", NULL, NULL, NULL};
const char fuzz_label[] = "netCDF readers (WRF, IOAPI, CF)";
const long fuzz_mutations = 300;

static int hdf5(const uint8_t *d, size_t n)
{
    for (size_t at = 0; at + 8 <= n; at = at ? 2 * at : 512)
        if (!memcmp(d + at, "\x89HDF\r\n\x1a\n", 8))
            return 1;
    return 0;
}

/* The classic header (CDF-1, -2, -5) walked as netCDF's file format
 * specification lays it out: 0 when every list and value it declares fits
 * in the file, -1 otherwise. */
typedef struct cur {
    const uint8_t *d;
    size_t n, at;
    int w; /* 4, or 8 for CDF-5 counts */
} cur;

static int take(cur *c, int w, uint64_t *v)
{
    if (c->n - c->at < (size_t)w)
        return -1;
    *v = 0;
    for (int i = 0; i < w; i++)
        *v = *v << 8 | c->d[c->at++];
    return 0;
}

static int skip(cur *c, uint64_t bytes)
{
    if (bytes > c->n - c->at)
        return -1;
    c->at += (size_t)((bytes + 3) / 4 * 4 <= c->n - c->at ? (bytes + 3) / 4 * 4 : bytes);
    return 0;
}

static int name(cur *c)
{
    uint64_t len;
    return take(c, c->w, &len) || skip(c, len);
}

static int attrs(cur *c)
{
    uint64_t tag, n, type, m;
    static const int tsize[] = {0, 1, 1, 2, 4, 4, 8, 1, 2, 4, 8, 8};
    if (take(c, 4, &tag) || take(c, c->w, &n))
        return -1;
    for (uint64_t i = 0; i < n; i++) {
        if (name(c) || take(c, 4, &type) || type < 1 || type > 11 || take(c, c->w, &m) ||
            m > (c->n - c->at) / (uint64_t)tsize[type] || skip(c, m * (uint64_t)tsize[type]))
            return -1;
    }
    return 0;
}

static int classic_fits(const uint8_t *d, size_t size)
{
    if (size < 8 || memcmp(d, "CDF", 3))
        return 0;
    cur c = {d, size, 4, d[3] == 5 ? 8 : 4};
    uint64_t recs, tag, n, len, ndims, type;
    if (take(&c, c.w, &recs) || take(&c, 4, &tag) || take(&c, c.w, &n))
        return -1;
    for (uint64_t i = 0; i < n; i++)
        if (name(&c) || take(&c, c.w, &len))
            return -1;
    if (attrs(&c) || take(&c, 4, &tag) || take(&c, c.w, &n))
        return -1;
    for (uint64_t i = 0; i < n; i++) {
        if (name(&c) || take(&c, c.w, &ndims) || ndims > (c.n - c.at) / (uint64_t)c.w || skip(&c, ndims * (uint64_t)c.w) ||
            attrs(&c) || take(&c, 4, &type) || take(&c, c.w, &len) || take(&c, d[3] == 1 ? 4 : 8, &len))
            return -1;
    }
    return 0;
}

static long n_runs, n_skipped, n_opened;

int fuzz_report(char *msg, size_t cap);
int fuzz_report(char *msg, size_t cap)
{
    snprintf(msg, cap, "%ld classic inputs: %ld skipped (a header larger than the file), %ld opened",
             n_runs, n_skipped, n_opened);
    return n_opened * 10 > n_runs && n_skipped * 2 < n_runs ? 0 : -1;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 4 || hdf5(data, size))
        return 0;
    n_runs++;
    if (classic_fits(data, size)) {
        n_skipped++;
        return 0;
    }
    const char *path = fuzz_put("in.nc", data, size);
    if (!path)
        return 0;
    vsv_source_opts o;
    vsv_source_opts_init(&o);
    o.vertical = VSV_VERT_NATIVE;
    if (fuzz_source_read_all(path, &o) >= 0)
        n_opened++;
    o.vertical = VSV_VERT_EVEN;
    o.nz = 8;
    (void)fuzz_source_read_all(path, &o);
    return 0;
}
