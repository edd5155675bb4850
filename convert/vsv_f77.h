/* vsv_f77.h — Fortran unformatted sequential records, [u32 n][n bytes][u32 n]
 * in either byte order, as MM5 and CAMx write them. Shared by the MM5 and
 * UAM-IV readers. Private to convert/. */
#ifndef VSV_F77_H
#define VSV_F77_H

#include "vsv_common.h"

/* A 4-byte word of a big-endian (le = 0) or little-endian file. */
static inline uint32_t vsv_f77_u32(int le, const unsigned char *p)
{
    return le ? vsv_rd32(p) : ((uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3]);
}

static inline float vsv_f77_f32(int le, const unsigned char *p)
{
    const uint32_t u = vsv_f77_u32(le, p);
    float f;
    memcpy(&f, &u, 4);
    return f;
}

/* The record at *at of the n bytes at d: its payload and length; advances
 * *at. On error returns VSV_ETRUNC or VSV_ECORRUPT with "record R at byte
 * offset O: what" in msg. */
static inline int vsv_f77_record(const unsigned char *d, size_t n, int le, size_t *at, int recno,
                                 const unsigned char **payload, uint32_t *len, char *msg, size_t cap)
{
    if (n - *at < 4) {
        vsv_msg(msg, cap, "record %d at byte offset %zu: file ends inside the record's length marker", recno, *at);
        return VSV_ETRUNC;
    }
    const uint32_t l = vsv_f77_u32(le, d + *at);
    if ((uint64_t)l + 8 > n - *at) {
        vsv_msg(msg, cap, "record %d at byte offset %zu: file ends inside the record (%u bytes announced, %zu left)",
                recno, *at, l, n - *at - 4);
        return VSV_ETRUNC;
    }
    if (vsv_f77_u32(le, d + *at + 4 + l) != l) {
        vsv_msg(msg, cap, "record %d at byte offset %zu: trailing length marker %u differs from leading %u", recno, *at,
                vsv_f77_u32(le, d + *at + 4 + l), l);
        return VSV_ECORRUPT;
    }
    *payload = d + *at + 4;
    *len = l;
    *at += (size_t)l + 8;
    return 0;
}

#endif
