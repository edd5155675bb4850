/* vsv_refread.c — the reference reader (see vsv_refread.h): plain loops,
 * a bitwise CRC, every rule of SPEC.md checked in the most literal way. */
#include "vsv_refread.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zstd.h>

static uint64_t get(const unsigned char *p, int bytes)
{
    uint64_t v = 0;
    for (int i = bytes - 1; i >= 0; i--)
        v = (v << 8) | p[i];
    return v;
}

static double getd(const unsigned char *p)
{
    uint64_t u = get(p, 8);
    double d;
    memcpy(&d, &u, 8);
    return d;
}

uint32_t ref_crc32c(const unsigned char *p, size_t n)
{
    uint32_t c = 0xFFFFFFFFu;
    for (size_t i = 0; i < n; i++) {
        c ^= p[i];
        for (int k = 0; k < 8; k++)
            c = (c & 1) ? (c >> 1) ^ 0x82F63B78u : c >> 1;
    }
    return c ^ 0xFFFFFFFFu;
}

#define FAIL(...)                                                                                                      \
    do {                                                                                                               \
        snprintf(err, cap, __VA_ARGS__);                                                                               \
        return -1;                                                                                                     \
    } while (0)

int ref_open(ref_file *rf, const unsigned char *d, size_t n, char *err, size_t cap)
{
    memset(rf, 0, sizeof *rf);
    rf->d = d;
    rf->n = n;
    if (n < 160 || memcmp(d, "\x89VSV\r\n\x1a\n", 8))
        FAIL("not a .vsv file");
    const unsigned major = (unsigned)get(d + 8, 2);
    if (major < 1 || major > 4 || get(d + 12, 4) != 128)
        FAIL("version/header size");
    if (ref_crc32c(d, 124) != get(d + 124, 4))
        FAIL("header crc");
    if (get(d + 16, 8) != n)
        FAIL("file size");
    rf->nsteps = (unsigned)get(d + 44, 4);
    rf->nspecies = (unsigned)get(d + 68, 4);
    rf->nx = (unsigned)get(d + 72, 4);
    rf->ny = (unsigned)get(d + 76, 4);
    rf->nz = (unsigned)get(d + 80, 4);
    rf->brick = (unsigned)get(d + 84, 4);
    rf->keyframe = (unsigned)get(d + 88, 4);
    rf->codec = (unsigned)get(d + 92, 4);
    rf->major = major;
    rf->toc = get(d + 48, 8);
    uint64_t msz = get(d + 32, 8);
    if (get(d + 24, 8) != 128 || 128 + msz > n || ref_crc32c(d + 128, msz) != get(d + 40, 4))
        FAIL("metadata crc");
    if (rf->toc + 24ull * rf->nsteps + 32 != n || ref_crc32c(d + rf->toc, 24ull * rf->nsteps) != get(d + 64, 4))
        FAIL("toc crc");
    const unsigned char *tr = d + n - 32;
    if (memcmp(tr, "\x89VSVEND\n", 8) || ref_crc32c(tr, 28) != get(tr + 28, 4) || get(tr + 8, 8) != rf->toc)
        FAIL("end marker");
    rf->sp = calloc(rf->nspecies ? rf->nspecies : 1, sizeof *rf->sp);
    if (!rf->sp)
        FAIL("memory");
    /* walk the records, keep what decoding needs */
    uint64_t at = 128;
    unsigned nvar = 0, nquan = 0;
    for (;;) {
        if (at + 8 > 128 + msz)
            FAIL("records overrun");
        const unsigned char *r = d + at;
        uint64_t len = get(r + 4, 4);
        if (!memcmp(r, "END ", 4))
            break;
        if (!memcmp(r, "VAR ", 4) && nvar < rf->nspecies) {
            uint64_t sl = get(r + 8, 4);
            if (sl > 63)
                FAIL("name length");
            memcpy(rf->sp[nvar].name, r + 12, sl);
            nvar++;
        }
        if (!memcmp(r, "QUAN", 4)) {
            unsigned s = (unsigned)get(r + 8, 4);
            if (s >= rf->nspecies || len != 64)
                FAIL("QUAN");
            rf->sp[s].bits = (unsigned)get(r + 12, 4);
            rf->sp[s].scale = (unsigned)get(r + 16, 4);
            rf->sp[s].missing = (unsigned)get(r + 20, 4) & 1;
            rf->sp[s].lo = getd(r + 24);
            rf->sp[s].hi = getd(r + 32);
            rf->sp[s].threshold = getd(r + 40);
            rf->sp[s].max_abs_error = getd(r + 48);
            nquan++;
        }
        at += 8 + (len + 7) / 8 * 8;
    }
    if (nvar != rf->nspecies || nquan != rf->nspecies)
        FAIL("species count");
    return 0;
}

int64_t ref_time(const ref_file *rf, unsigned t) { return (int64_t)get(rf->d + rf->toc + 24ull * t + 16, 8); }

static float value(const ref_species *sp, unsigned c)
{
    double M = sp->bits == 8 ? 255 : 65535;
    if (sp->scale == 0 && sp->missing)
        return c == 0 ? NAN : (float)(sp->lo + (c - 1) * ((sp->hi - sp->lo) / (M - 1)));
    if (sp->scale == 0)
        return (float)(sp->lo + c * ((sp->hi - sp->lo) / M));
    if (c == 0)
        return 0;
    return (float)exp(log(sp->lo) + (c - 1) * ((log(sp->hi) - log(sp->lo)) / (M - 1)));
}

static unsigned nodes_of(const ref_file *rf)
{
    unsigned d[3] = {(rf->nx + rf->brick - 1) / rf->brick, (rf->ny + rf->brick - 1) / rf->brick,
                     (rf->nz + rf->brick - 1) / rf->brick};
    unsigned total = 0;
    for (;;) {
        total += d[0] * d[1] * d[2];
        if (d[0] == 1 && d[1] == 1 && d[2] == 1)
            return total;
        for (int a = 0; a < 3; a++)
            d[a] = (d[a] + 1) / 2;
    }
}

/* Kinds 6 and 7 (SPEC.md §7 "Rice coding"): the zigzagged residuals of a box
 * of ex x ey x ez cells, one bit at a time, into buf as planes (low bytes,
 * then high bytes for 16 bits); 0 or -1. */
static int rice_planes(const unsigned char *p, size_t size, unsigned bits, unsigned ex, unsigned ey, unsigned ez,
                       unsigned char *buf)
{
    const size_t n = (size_t)ex * ey * ez, head = 20 + 12;
    if (size < head)
        return -1;
    size_t start[5], end[4];
    start[0] = head;
    for (int t = 0; t < 3; t++) {
        end[t] = start[t] + get(p + 20 + 4 * t, 4);
        if (end[t] > size)
            return -1;
        start[t + 1] = end[t];
    }
    end[3] = size;
    size_t pos[4]; /* bit positions */
    for (int t = 0; t < 4; t++)
        pos[t] = 8 * start[t];
    unsigned *z = calloc(n ? n : 1, sizeof *z);
    if (!z)
        return -1;
    int bad = 0;
#define BIT(t) (pos[t] < 8 * end[t] ? (p[pos[t] >> 3] >> (pos[t] & 7)) & 1 : (bad = 1, 0u))
    for (unsigned k = 0; k < ez && !bad; k++)
        for (unsigned j = 0; j < ey && !bad; j++)
            for (unsigned i = 0; i < ex && !bad; i++) {
                unsigned t = 0;
                if (j > 0) {
                    t += 2 * z[i + ex * (j - 1 + ey * k)];
                    t += i > 0 ? z[i - 1 + ex * (j - 1 + ey * k)] : 0;
                    t += i + 1 < ex ? z[i + 1 + ex * (j - 1 + ey * k)] : 0;
                }
                t += k > 0 ? 2 * z[i + ex * (j + ey * (k - 1))] : 0;
                unsigned q = 0;
                while (t >> q)
                    q++;
                const unsigned K = p[q], st = i % 4;
                if (K > bits)
                    bad = 1;
                unsigned u = 0;
                while (u < 8 && !bad && BIT(st) == 0) {
                    u++;
                    pos[st]++;
                }
                unsigned v = 0;
                if (u < 8) {
                    pos[st]++; /* the one that ends the run of zeros */
                    for (unsigned b = 0; b < K && !bad; b++, pos[st]++)
                        v |= BIT(st) << b;
                    v += u << K;
                } else {
                    for (unsigned b = 0; b < bits && !bad; b++, pos[st]++)
                        v |= BIT(st) << b;
                }
                if (v >> bits)
                    bad = 1;
                z[i + ex * (j + ey * k)] = v;
            }
    for (int t = 0; t < 4 && !bad; t++) /* each stream ends in its last byte, zero bits after the last code */
        for (bad = (pos[t] + 7) / 8 != end[t]; !bad && pos[t] < 8 * end[t]; pos[t]++)
            bad = BIT(t);
#undef BIT
    for (size_t m = 0; m < n; m++) {
        buf[m] = (unsigned char)z[m];
        if (bits == 16)
            buf[n + m] = (unsigned char)(z[m] >> 8);
    }
    free(z);
    return bad ? -1 : 0;
}

int ref_decode(const ref_file *rf, unsigned t, unsigned s, uint16_t *codes, float *values, char *err, size_t cap)
{
    const unsigned B = rf->brick;
    const unsigned bx = (rf->nx + B - 1) / B, by = (rf->ny + B - 1) / B, bz = (rf->nz + B - 1) / B;
    const unsigned nb = bx * by * bz, cells = B * B * B;
    const size_t O = (4 * (size_t)nodes_of(rf) + 7) / 8 * 8, S = O + 24 * (size_t)nb;
    const ref_species *sp = &rf->sp[s];
    const unsigned mask = sp->bits == 8 ? 0xff : 0xffff;
    uint16_t *state = calloc((size_t)nb * cells, 2);
    unsigned char *buf = malloc(4 * (size_t)cells);
    if (!state || !buf)
        FAIL("memory");
    uint16_t *const lor = (uint16_t *)(buf + 2 * (size_t)cells); /* the 3-D kinds' rebuilt values */
    for (unsigned u = 0; u <= t; u++) {
        const unsigned char *te = rf->d + rf->toc + 24ull * u;
        const unsigned char *c = rf->d + get(te, 8);
        const size_t index_bytes = rf->nspecies * S;
        if (memcmp(c, "VCHK", 4) || get(c + 4, 4) != u || get(c + 16, 4) != index_bytes) {
            free(state);
            free(buf);
            FAIL("chunk %u header", u);
        }
        unsigned char *tmp = malloc(28 + index_bytes);
        memcpy(tmp, c, 28);
        memcpy(tmp + 28, c + 32, index_bytes);
        uint32_t crc = ref_crc32c(tmp, 28 + index_bytes);
        free(tmp);
        if (crc != get(c + 28, 4)) {
            free(state);
            free(buf);
            FAIL("chunk %u index crc", u);
        }
        for (unsigned b = 0; b < nb; b++) {
            const unsigned char *e = c + 32 + s * S + O + 24ull * b;
            unsigned kind = e[0];
            uint16_t *st = state + (size_t)b * cells;
            if (kind == 0) {
                memset(st, 0, 2ull * cells);
                continue;
            }
            if (kind == 1)
                continue;
            /* kinds 4 (ABS3) and 5 (DELTA3) from major 2 on, 6 and 7 (their Rice-coded forms)
             * from 4; absolute kinds at keyframes */
            if (kind > (rf->major >= 4   ? 7u
                        : rf->major >= 2 ? 5u
                                         : 3u) ||
                (u % rf->keyframe == 0 && kind != 2 && kind != 4 && kind != 6)) {
                free(state);
                free(buf);
                FAIL("chunk %u brick %u kind %u", u, b, kind);
            }
            unsigned inside = 1;
            for (int a = 0; a < 3; a++) {
                unsigned n = a == 0 ? rf->nx : a == 1 ? rf->ny : rf->nz;
                unsigned idx = a == 0 ? b % bx : a == 1 ? b / bx % by : b / (bx * by);
                inside *= n - idx * B < B ? n - idx * B : B;
            }
            const size_t raw = sp->bits == 8 ? inside : 2 * (size_t)inside;
            const unsigned char *p = c + get(e + 8, 8);
            size_t size = get(e + 16, 4);
            if (ref_crc32c(p, size) != get(e + 4, 4)) {
                free(state);
                free(buf);
                FAIL("chunk %u brick %u payload crc", u, b);
            }
            if (kind >= 6) {
                const unsigned box[3] = {rf->nx - (b % bx) * B < B ? rf->nx - (b % bx) * B : B,
                                         rf->ny - (b / bx % by) * B < B ? rf->ny - (b / bx % by) * B : B,
                                         rf->nz - (b / (bx * by)) * B < B ? rf->nz - (b / (bx * by)) * B : B};
                if (rice_planes(p, size, sp->bits, box[0], box[1], box[2], buf)) {
                    free(state);
                    free(buf);
                    FAIL("chunk %u brick %u rice", u, b);
                }
                kind -= 2; /* the residuals of kind 4 or 5 */
            } else if (rf->codec == 1) {
                size_t got = ZSTD_decompress(buf, raw, p, size);
                if (ZSTD_isError(got) || got != raw) {
                    free(state);
                    free(buf);
                    FAIL("chunk %u brick %u zstd", u, b);
                }
            } else {
                if (size != raw) {
                    free(state);
                    free(buf);
                    FAIL("raw size");
                }
                memcpy(buf, p, raw);
            }
            /* the payload covers the brick's cells inside the grid only */
            unsigned prev = 0, m = 0;
            for (unsigned k = 0; k < B; k++)
                for (unsigned j = 0; j < B; j++)
                    for (unsigned i = 0; i < B; i++) {
                        if ((b % bx) * B + i >= rf->nx || (b / bx % by) * B + j >= rf->ny ||
                            (b / (bx * by)) * B + k >= rf->nz)
                            continue;
                        unsigned z = sp->bits == 8 ? buf[m] : (unsigned)buf[m] | ((unsigned)buf[inside + m] << 8);
                        /* undo zigzag: s = (z >> 1) ^ -(z & 1), as a bits-wide integer */
                        unsigned r = ((z >> 1) ^ (0u - (z & 1))) & mask;
                        unsigned at = i + B * (j + B * k);
                        unsigned v;
                        if (kind == 4 || kind == 5) {
                            /* the Lorenzo prediction from the seven cells before it
                             * (0 outside the box's low faces), of the codes (4) or
                             * of their change since the step before (5: lor holds it) */
                            unsigned pred = 0;
                            for (unsigned nb7 = 1; nb7 < 8; nb7++) {
                                const unsigned di = nb7 & 1, dj = nb7 >> 1 & 1, dk = nb7 >> 2;
                                if (i < di || j < dj || k < dk)
                                    continue;
                                const unsigned q = lor[(i - di) + B * ((j - dj) + B * (k - dk))];
                                pred += (di + dj + dk) % 2 ? q : 0u - q;
                            }
                            lor[at] = (uint16_t)((pred + r) & mask);
                            v = kind == 4 ? lor[at] : (st[at] + lor[at]) & mask;
                        } else {
                            v = kind == 2 ? (prev + r) & mask : (st[at] + r) & mask;
                        }
                        st[at] = (uint16_t)v;
                        prev = v;
                        m++;
                    }
        }
    }
    for (unsigned k = 0; k < rf->nz; k++)
        for (unsigned j = 0; j < rf->ny; j++)
            for (unsigned i = 0; i < rf->nx; i++) {
                unsigned b = i / B + bx * (j / B + by * (k / B));
                unsigned local = i % B + B * (j % B + B * (k % B));
                size_t g = i + (size_t)rf->nx * (j + (size_t)rf->ny * k);
                codes[g] = state[(size_t)b * cells + local];
                values[g] = value(sp, codes[g]);
            }
    free(state);
    free(buf);
    return 0;
}

void ref_close(ref_file *rf) { free(rf->sp); }
