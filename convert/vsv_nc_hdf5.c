/* vsv_nc_hdf5.c — the length a netCDF-4 (HDF5) file declares, against the
 * file's own. libhdf5 answers a copy cut short with "NetCDF: HDF error" and
 * nothing more; its superblock (HDF5 File Format Specification, "Disk Format:
 * Level 0A") holds the end-of-file address, so a short file is named as
 * such, with both lengths, before the library opens it. */
#include "vsv_source_internal.h"

#include <stdio.h>
#include <string.h>

/* The little-endian unsigned integer of n bytes at p. */
static uint64_t le(const unsigned char *p, int n)
{
    uint64_t v = 0;
    for (int i = n - 1; i >= 0; i--)
        v = v << 8 | p[i];
    return v;
}

int vsv_nc_hdf5_check(FILE *fp, uint64_t size, char *msg, size_t cap)
{
    unsigned char b[64] = {0};
    const size_t got = fseeko(fp, 0, SEEK_SET) ? 0 : fread(b, 1, sizeof b, fp);
    if (got < 8 || memcmp(b, "\x89HDF\r\n\x1a\n", 8))
        return 1;
    /* versions 0 and 1: sizes of offsets at byte 13, then the base, free
     * space, end-of-file addresses from byte 24 (28 in version 1); versions
     * 2 and 3: sizes at byte 9, the base, extension, end-of-file addresses
     * from byte 12 */
    const int version = b[8];
    int o, at;
    if (version <= 1)
        o = b[13], at = version ? 28 : 24;
    else if (version <= 3)
        o = b[9], at = 12;
    else
        return 0; /* a later version: the library's to judge */
    if (!(o == 2 || o == 4 || o == 8) || at + 3 * o > (int)sizeof b)
        return 0;
    if (got < (size_t)(at + 3 * o)) { /* (the superblock itself cut) */
        snprintf(msg, cap, "cut short: %llu bytes, inside its HDF5 superblock", (unsigned long long)got);
        return -1;
    }
    const uint64_t base = le(b + at, o), eof = le(b + at + 2 * o, o);
    const uint64_t undefined = o == 8 ? UINT64_MAX : (UINT64_C(1) << (8 * o)) - 1;
    if (base == undefined || eof == undefined || eof > undefined - base)
        return 0;
    if (base + eof > size) {
        snprintf(msg, cap,
                 "cut short: %llu bytes of the %llu its HDF5 superblock declares (a copy or download that did "
                 "not finish?)",
                 (unsigned long long)size, (unsigned long long)(base + eof));
        return -1;
    }
    return 0;
}
