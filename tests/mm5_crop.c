/* mm5_crop.c — the project's MM5-layout writer at work: copies a window of
 * dot points of an MM5 v3 file (all periods, chosen fields) into a new MM5 v3
 * file whose big header places the window where it was, so the geometry stays
 * exact. Makes samples/mm5/MMOUT_CROP from ../shared/data/mm5/run1:
 *   mm5crop IN OUT I0 J0 NI NJ FIELD,FIELD,...   (I0, J0 1-based dot points) */
#include "vsv_mm5.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void put_be32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)(v >> 24);
    p[1] = (unsigned char)(v >> 16);
    p[2] = (unsigned char)(v >> 8);
    p[3] = (unsigned char)v;
}

static int wanted(const char *list, const char *name)
{
    char buf[1024];
    snprintf(buf, sizeof buf, "%s", list);
    for (char *s = NULL, *t = strtok_r(buf, ",", &s); t; t = strtok_r(NULL, ",", &s))
        if (!strcmp(t, name))
            return 1;
    return 0;
}

int main(int argc, char **argv)
{
    if (argc != 8) {
        fprintf(stderr, "usage: mm5crop IN OUT I0 J0 NI NJ FIELDS\n");
        return 2;
    }
    vsv_mm5 *m = NULL;
    if (vsv_mm5_open(argv[1], &m)) {
        fprintf(stderr, "mm5crop: %s\n", vsv_mm5_error(m));
        return 1;
    }
    const int i0 = atoi(argv[3]), j0 = atoi(argv[4]), ni = atoi(argv[5]), nj = atoi(argv[6]);
    const int IX = vsv_mm5_bhi(m, 16, 1), JX = vsv_mm5_bhi(m, 17, 1), r = vsv_mm5_bhi(m, 20, 1);
    if (i0 < 1 || j0 < 1 || ni < 3 || nj < 3 || i0 + ni - 1 > IX || j0 + nj - 1 > JX) {
        fprintf(stderr, "mm5crop: window outside the %dx%d domain\n", IX, JX);
        return 2;
    }
    unsigned char *big = malloc(VSV_MM5_BIGHDR);
    memcpy(big, vsv_mm5_bighdr_bytes(m), VSV_MM5_BIGHDR);
    put_be32(big + 4 * ((1 - 1) * 50 + (16 - 1)), (uint32_t)ni);
    put_be32(big + 4 * ((1 - 1) * 50 + (17 - 1)), (uint32_t)nj);
    float f10 = vsv_mm5_bhr(m, 10, 1) + (float)(i0 - 1) / (float)r,
          f11 = vsv_mm5_bhr(m, 11, 1) + (float)(j0 - 1) / (float)r;
    uint32_t u;
    memcpy(&u, &f10, 4);
    put_be32(big + 4000 + 4 * (10 - 1), u);
    memcpy(&u, &f11, 4);
    put_be32(big + 4000 + 4 * (11 - 1), u);
    FILE *fp = fopen(argv[2], "wb");
    vsv_mm5_writer w = {fp, 0};
    vsv_mm5_write_flag(&w, 0);
    vsv_mm5_write_bighdr(&w, big);
    float *in = malloc((size_t)IX * JX * 64 * sizeof(float)), *out = malloc((size_t)IX * JX * 64 * sizeof(float));
    int period = 0;
    for (int i = 0; i < vsv_mm5_nfields(m); i++) {
        const vsv_mm5_field *f = vsv_mm5_field_at(m, i);
        if (f->period != period) {
            vsv_mm5_write_flag(&w, 2);
            period = f->period;
        }
        if (!wanted(argv[7], f->name))
            continue;
        vsv_mm5_field g = *f;
        vsv_mm5_read(m, f, in);
        const int grid =
            !strcmp(f->order, "YX") || !strcmp(f->order, "YXS") || !strcmp(f->order, "YXW") || !strcmp(f->order, "YXP");
        if (grid) {
            const int nk = f->end[2] - f->start[2] + 1;
            g.end[0] = ni;
            g.end[1] = nj;
            for (int k = 0; k < nk; k++)
                for (int jj = 0; jj < nj; jj++)
                    for (int ii = 0; ii < ni; ii++)
                        out[((size_t)k * nj + jj) * ni + ii] =
                            in[((size_t)k * JX + (j0 - 1 + jj)) * IX + (i0 - 1 + ii)];
            vsv_mm5_write_field(&w, &g, out);
        } else {
            vsv_mm5_write_field(&w, &g, in);
        }
    }
    vsv_mm5_write_flag(&w, 2);
    int bad = fclose(fp) != 0;
    vsv_mm5_free(m);
    free(in);
    free(out);
    free(big);
    return bad;
}
