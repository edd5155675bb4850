/* test_regrid.c — MM5's other programs on the real run in
 * ../shared/data/mm5/run1: REGRID's pressure-level fields (YXP, 23 levels,
 * the first the surface) as volumes placed by their geopotential height H,
 * checked against an independent walk of the file's big-endian records and
 * a column interpolation written here; BDYOUT's boundary slabs and LOWBDY's
 * 2-D fields listed by name and refused as volumes. */
#include "vsv_convert.h"
#include "vsv_format.h"
#include "vsv_testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The even grid these checks were written for (vsv-convert --vertical even;
 * the default is the model's own levels). */
static const vsv_source_opts *even(void)
{
    static vsv_source_opts o;
    vsv_source_opts_init(&o);
    o.vertical = VSV_VERT_EVEN;
    return &o;
}

static uint32_t be32(const unsigned char *p) { return (uint32_t)p[0] << 24 | p[1] << 16 | p[2] << 8 | p[3]; }

/* The data of field `name` in period `period` (0-based), as host floats in
 * file order, and its first three extents; NULL if absent. */
static float *raw_field(const unsigned char *d, size_t n, const char *name, int period, int ext[3])
{
    size_t at = 0;
    int p = 0;
    while (at + 8 <= n) {
        uint32_t len = be32(d + at);
        const unsigned char *r = d + at + 4;
        at += 8 + len;
        if (len != 4)
            return NULL;
        const int flag = (int)be32(r);
        if (flag == 0) {
            at += 8 + be32(d + at);
        } else if (flag == 2) {
            p++;
        } else if (flag == 1) {
            const unsigned char *h = d + at + 4;
            at += 8 + be32(d + at);
            const uint32_t dl = be32(d + at);
            const unsigned char *data = d + at + 4;
            at += 8 + dl;
            char nm[10];
            memcpy(nm, h + 72, 9);
            nm[9] = 0;
            for (int i = 8; i >= 0 && nm[i] == ' '; i--)
                nm[i] = 0;
            if (p == period && !strcmp(nm, name)) {
                for (int k = 0; k < 3; k++)
                    ext[k] = (int)be32(h + 20 + 4 * k) - (int)be32(h + 4 + 4 * k) + 1;
                float *v = malloc(dl);
                for (uint32_t i = 0; i < dl / 4; i++) {
                    uint32_t u = be32(data + 4 * i);
                    memcpy(&v[i], &u, 4);
                }
                return v;
            }
        }
    }
    return NULL;
}

static void test_regrid(void)
{
    const char *path = vsv_test_shared("mm5/run1/REGRID_DOMAIN1");
    size_t n;
    if (vsv_test_absent(path, "MM5 REGRID"))
        return;
    unsigned char *d = vsv_test_slurp(path, &n);
    if (!CHECK(d, "REGRID_DOMAIN1 reads"))
        return;
    vsv_source *s = NULL;
    int rc = vsv_source_open(path, even(), &s);
    CHECK(rc == 0, "REGRID_DOMAIN1 opens", "(%s)", vsv_source_error(s));
    if (rc) {
        vsv_source_free(s);
        free(d);
        return;
    }
    const char *want[] = {"T", "U", "V", "RH", "H"};
    int ok = 1;
    for (int i = 0; i < 5; i++) {
        const int f = vsv_source_find_field(s, want[i]);
        ok &= f >= 0 && vsv_source_field(s, f)->is_volume && vsv_source_field(s, f)->is_default &&
              vsv_source_field(s, f)->nlevels == 23;
    }
    CHECK(ok, "REGRID: T U V RH H are default volumes of 23 levels");
    const int fterr = vsv_source_find_field(s, "TERRAIN"), fpres = vsv_source_find_field(s, "PRESSURE");
    CHECK(fterr >= 0 && !vsv_source_field(s, fterr)->is_volume && fpres >= 0 && !vsv_source_field(s, fpres)->is_volume,
          "REGRID: TERRAIN and PRESSURE are not volumes");
    const vsv_meta *g = vsv_source_grid(s);
    CHECK(g->nx == 207 && g->ny == 142 && g->nz == 40 && vsv_source_ntimes(s) == 2 && g->vert_kind == VSV_VERT_EVEN,
          "REGRID: 207 x 142 cross points, 40 even levels, 2 times", "%d %d %d %d", g->nx, g->ny, g->nz,
          vsv_source_ntimes(s));
    const size_t plane = (size_t)g->nx * g->ny, cells = plane * (size_t)g->nz;
    float *h = malloc(cells * sizeof *h), *t = malloc(cells * sizeof *t);
    /* H resampled onto heights is the height itself, wherever there is air */
    vsv_source_read(s, vsv_source_find_field(s, "H"), 1, h);
    double worst = 0;
    size_t air = 0, ground = 0;
    for (int k = 0; k < g->nz; k++)
        for (size_t c = 0; c < plane; c++) {
            const float v = h[(size_t)k * plane + c];
            const double z = g->origin[2] + k * g->spacing[2];
            if (isnan(v)) {
                ground += z < g->terrain[c];
                continue;
            }
            air++;
            worst = fmax(worst, fabs(v - z));
        }
    CHECK(worst < 0.05 && air > cells / 2 && ground > 0, "REGRID: H on even heights equals the height (time 1)",
          "worst %.4f m, %zu cells of air, %zu below ground", worst, air, ground);
    /* T against an independent column interpolation at a few columns */
    int ext[3];
    float *T = raw_field(d, n, "T", 1, ext), *H = raw_field(d, n, "H", 1, ext);
    CHECK(T && H && ext[0] == 143 && ext[1] == 208 && ext[2] == 23, "independent walk finds T and H of period 1");
    vsv_source_read(s, vsv_source_find_field(s, "T"), 1, t);
    const int IX = 143, cols[][2] = {{10, 10}, {100, 70}, {150, 90}, {60, 120}, {200, 30}};
    double terr = 0;
    int checked = 0;
    for (size_t q = 0; T && H && q < sizeof cols / sizeof *cols; q++) {
        const int i = cols[q][0], j = cols[q][1]; /* x (J-1), y (I-1) */
        const size_t fc = (size_t)i * IX + j;
        for (int k = 0; k < g->nz; k++) {
            const double z = g->origin[2] + k * g->spacing[2];
            /* the levels above the surface, in order */
            double zb = H[fc], tb = T[fc], za = zb, ta = tb, expect = NAN;
            if (z >= zb) {
                for (int l = 1; l < 23; l++) {
                    const double hl = H[(size_t)l * 143 * 208 + fc];
                    if (hl <= za)
                        continue; /* below the ground */
                    zb = hl, tb = T[(size_t)l * 143 * 208 + fc];
                    if (z <= zb) {
                        expect = ta + (tb - ta) * (z - za) / (zb - za);
                        break;
                    }
                    za = zb, ta = tb;
                }
            }
            const float got = t[(size_t)k * plane + (size_t)j * g->nx + i];
            if (isnan(expect) != isnan(got)) {
                terr = INFINITY;
            } else if (!isnan(got)) {
                terr = fmax(terr, fabs(got - expect));
                checked++;
            }
        }
    }
    CHECK(terr < 1e-3 && checked > 100, "REGRID: T on even heights equals an independent column interpolation",
          "worst %.5f K over %d cells", terr, checked);
    /* the even levels reach the highest point of the top pressure level (H
     * of the first period, the 100 hPa surface) rounded up to 100 m: 40
     * levels of a fortieth of that, the first half a level up */
    float *H0 = raw_field(d, n, "H", 0, ext);
    double top = 0;
    for (size_t c = 0; H0 && c < (size_t)143 * 208; c++)
        top = fmax(top, H0[(size_t)22 * 143 * 208 + c]);
    const double ztop = ceil(top / 100) * 100;
    CHECK(H0 && top > 15000 && fabs(g->spacing[2] - ztop / 40) < 1e-6 && fabs(g->origin[2] - ztop / 80) < 1e-6,
          "REGRID: the even levels reach the top level's highest point rounded up to 100 m (40 of ztop / 40)",
          "top %.1f m: spacing %g, origin %g, wanted %g, %g", top, g->spacing[2], g->origin[2], ztop / 40, ztop / 80);
    free(H0);
    free(T);
    free(H);
    free(h);
    free(t);
    vsv_source_free(s);
    /* native: the 23 pressure levels with their mean heights */
    vsv_source_opts o;
    vsv_source_opts_init(&o);
    o.vertical = VSV_VERT_NATIVE;
    rc = vsv_source_open(path, &o, &s);
    g = vsv_source_grid(s);
    CHECK(!rc && g->nz == 23 && g->levels && g->levels[0] < g->levels[22] && g->levels[22] > 15000,
          "REGRID native: 23 levels, mean heights up to the 100 hPa level", "%d %g", g->nz,
          g->levels ? g->levels[22] : 0);
    vsv_source_free(s);
    free(d);
}

static void test_boundary_files(void)
{
    const char *bdy = vsv_test_shared("mm5/run1/BDYOUT_DOMAIN1");
    const char *low = vsv_test_shared("mm5/run1/LOWBDY_DOMAIN1");
    vsv_source *s = NULL;
    if (vsv_test_absent(bdy, "MM5 BDYOUT and LOWBDY") || vsv_test_absent(low, "MM5 LOWBDY"))
        return;
    int rc = vsv_source_open(bdy, NULL, &s);
    int f = rc ? -1 : vsv_source_find_field(s, "UEB");
    CHECK(f >= 0 && !vsv_source_field(s, f)->is_volume && strstr(vsv_source_field(s, f)->role, "boundary slab") &&
              !strncmp(vsv_source_field(s, f)->ordering, "YSB", 3) && vsv_source_nfields(s) == 48,
          "BDYOUT: its 48 slab fields are listed as boundary slabs, not volumes", "(%s) %d", vsv_source_error(s),
          rc ? -1 : vsv_source_nfields(s));
    if (f >= 0) {
        float one;
        rc = vsv_source_read(s, f, 0, &one);
        CHECK(rc == VSV_EINVAL && strstr(vsv_source_error(s), "UEB (YSB D) is not a volume") &&
                  strstr(vsv_source_error(s), "boundary slab"),
              "BDYOUT: reading a slab as a volume is refused by name", "(%s)", vsv_source_error(s));
    }
    char *sum = rc == 0 || f >= 0 ? vsv_source_summary(s) : NULL;
    CHECK(sum && strstr(sum, "BDYOUT") && strstr(sum, "UEB") && strstr(sum, "boundary-slab"),
          "BDYOUT: the summary names the program and the slabs", "%.200s", sum ? sum : "");
    free(sum);
    vsv_source_free(s);
    rc = vsv_source_open(low, NULL, &s);
    f = rc ? -1 : vsv_source_find_field(s, "TSEASFC");
    CHECK(f >= 0 && !strcmp(vsv_source_field(s, f)->role, "2-D") && vsv_source_ntimes(s) == 2,
          "LOWBDY: TSEASFC listed as 2-D, two times", "(%s)", vsv_source_error(s));
    vsv_source_free(s);
}

int main(void)
{
    test_regrid();
    test_boundary_files();
    return vsv_test_done();
}
