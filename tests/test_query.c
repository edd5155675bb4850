/* test_query.c — the query library (vsv_point_*, vsv_query_*): every cell's
 * latitude/longitude, read back through a .vsv, against the models' own
 * fields (MM5 LATITCRS/LONGICRS, WRF XLAT/XLONG) within 1 m plus the float
 * rounding of those fields; lat/lon back to the same cell; values equal the
 * decoder's; trilinear blends; points, heights and cells outside the grid;
 * trilinear beside no-data cells (NaN only where a NaN cell has weight). */
#include "vsv_convert.h"
#include "vsv_format.h"
#include "vsv_mm5.h"
#include "vsv_testlib.h"

#include <math.h>
#include <netcdf.h>
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

static double dist_m(double lat1, double lon1, double lat2, double lon2)
{
    const double r = M_PI / 180, R = 6370000;
    double dlat = (lat2 - lat1) * r, dlon = (lon2 - lon1) * r;
    double a = sin(dlat / 2) * sin(dlat / 2) + cos(lat1 * r) * cos(lat2 * r) * sin(dlon / 2) * sin(dlon / 2);
    return 2 * R * asin(sqrt(a));
}

/* The float rounding of a model's latitude/longitude, in metres: two units
 * in the last place of each float32 (the models compute them in float32,
 * one rounding, then store them, another). With one unit MM5's own
 * LATITCRS/LONGICRS exceed 1 m + rounding by 0.16 m and wrf_cropped.nc's
 * XLAT/XLONG by 0.54 m: the scatter of the models' own arithmetic. */
static double float_rounding_m(float lat, float lon)
{
    const double m_per_deg = 6370000 * M_PI / 180;
    const double ulat = nextafterf(fabsf(lat), INFINITY) - fabsf(lat),
                 ulon = nextafterf(fabsf(lon), INFINITY) - fabsf(lon);
    return 2 * (ulat * m_per_deg + ulon * m_per_deg * cos(lat * M_PI / 180));
}

/* The grid of a source, written to a one-step .vsv and opened again, so the
 * positions checked are those a reader of the file gets. */
static vsv_file *through_file(const vsv_meta *grid, const char *name)
{
    vsv_meta m;
    vsv_meta_init(&m);
    vsv_meta_copy(&m, grid);
    vsv_meta_add_var(&m, "ZERO", "1", "zeros");
    const size_t cells = (size_t)m.nx * m.ny * m.nz;
    float *z = calloc(cells, sizeof *z);
    const char *path = vsv_test_tmp(name);
    vsv_writer *w = NULL;
    const float *fields[1] = {z};
    vsv_file *f = NULL;
    if (!vsv_writer_create(path, &m, NULL, &w) && !vsv_writer_add_step(w, 0, fields) &&
        !vsv_writer_finish(w, NULL, NULL))
        vsv_file_open(path, &f);
    vsv_writer_free(w);
    free(z);
    vsv_meta_clear(&m);
    return f;
}

/* Every cell of the grid against lat/lon fields la/lo (nx*ny, x fastest):
 * within 1 m plus their rounding, and each field's lat/lon locates its cell. */
static void check_positions(const char *what, const vsv_meta *m, const float *la, const float *lo)
{
    double worst = 0, worst_excess = -1e9;
    long located = 0, n = 0;
    char msg[256], name[256];
    for (int j = 0; j < m->ny; j++)
        for (int i = 0; i < m->nx; i++) {
            const size_t c = (size_t)j * m->nx + i;
            vsv_point p;
            if (vsv_point_cell(m, i, j, 0, &p, msg, sizeof msg))
                continue;
            const double e = dist_m(p.lat, p.lon, la[c], lo[c]);
            worst = fmax(worst, e);
            worst_excess = fmax(worst_excess, e - (1.0 + float_rounding_m(la[c], lo[c])));
            vsv_point q;
            located += !vsv_point_locate(m, la[c], lo[c], NAN, &q, msg, sizeof msg) && q.cell[0] == i && q.cell[1] == j;
            n++;
        }
    snprintf(name, sizeof name, "%s: every cell's lat/lon within 1 m + float rounding of the model's own fields", what);
    CHECK(n == (long)m->nx * m->ny && worst_excess <= 0, name, "worst %.3f m, %.3f m beyond the bound", worst,
          worst_excess);
    snprintf(name, sizeof name, "%s: each cell's own lat/lon locates that cell", what);
    CHECK(located == n, name, "%ld of %ld", located, n);
    printf("  %s: worst %.3f m (bound 1 m + rounding; margin %.3f m)\n", what, worst, -worst_excess);
}

static void test_mm5_positions(void)
{
    const char *path = vsv_test_shared("mm5/run1/MMOUT_DOMAIN1");
    vsv_mm5 *mm = NULL;
    vsv_source *src = NULL;
    if (vsv_test_absent(path, "positions on the MM5 run"))
        return;
    if (!CHECK(vsv_mm5_open(path, &mm) == 0 && vsv_source_open(path, even(), &src) == 0, "MMOUT_DOMAIN1 opens")) {
        vsv_mm5_free(mm);
        vsv_source_free(src);
        return;
    }
    vsv_file *f = through_file(vsv_source_grid(src), "mm5grid.vsv");
    if (CHECK(f != NULL, "MM5 grid through a .vsv")) {
        const vsv_meta *m = vsv_file_meta(f);
        const int IX = vsv_mm5_bhi(mm, 16, 1), JX = vsv_mm5_bhi(mm, 17, 1);
        float *raw_la = malloc((size_t)IX * JX * 4), *raw_lo = malloc((size_t)IX * JX * 4);
        float *la = malloc((size_t)m->nx * m->ny * 4), *lo = malloc((size_t)m->nx * m->ny * 4);
        vsv_mm5_read(mm, vsv_mm5_field_at(mm, vsv_mm5_find(mm, 0, "LATITCRS")), raw_la);
        vsv_mm5_read(mm, vsv_mm5_field_at(mm, vsv_mm5_find(mm, 0, "LONGICRS")), raw_lo);
        /* MM5 file order: I (south-north) fastest; cross points fill all but the last row and column */
        for (int j = 0; j < m->ny; j++)
            for (int i = 0; i < m->nx; i++) {
                la[(size_t)j * m->nx + i] = raw_la[(size_t)i * IX + j];
                lo[(size_t)j * m->nx + i] = raw_lo[(size_t)i * IX + j];
            }
        check_positions("MM5 MMOUT_DOMAIN1 (LATITCRS/LONGICRS)", m, la, lo);
        free(raw_la);
        free(raw_lo);
        free(la);
        free(lo);
    }
    vsv_file_free(f);
    vsv_source_free(src);
    vsv_mm5_free(mm);
}

static void test_wrf_positions(const char *rel)
{
    const char *path = vsv_test_shared(rel);
    vsv_source_opts so;
    vsv_source_opts_init(&so);
    so.vertical = VSV_VERT_NATIVE;
    vsv_source *src = NULL;
    char name[256];
    snprintf(name, sizeof name, "%s opens", rel);
    if (!CHECK(vsv_source_open(path, &so, &src) == 0, name, "%s", vsv_source_error(src))) {
        vsv_source_free(src);
        return;
    }
    vsv_file *f = through_file(vsv_source_grid(src), "wrfgrid.vsv");
    int nc;
    if (f && nc_open(path, NC_NOWRITE, &nc) == NC_NOERR) {
        const vsv_meta *m = vsv_file_meta(f);
        float *la = malloc((size_t)m->nx * m->ny * 4), *lo = malloc((size_t)m->nx * m->ny * 4);
        int id, nd;
        size_t st[3] = {0, 0, 0}, ct[3] = {1, (size_t)m->ny, (size_t)m->nx};
        nc_inq_varid(nc, "XLAT", &id);
        nc_inq_varndims(nc, id, &nd);
        nc_get_vara_float(nc, id, nd == 3 ? st : st + 1, nd == 3 ? ct : ct + 1, la);
        nc_inq_varid(nc, "XLONG", &id);
        nc_get_vara_float(nc, id, nd == 3 ? st : st + 1, nd == 3 ? ct : ct + 1, lo);
        snprintf(name, sizeof name, "WRF %s (XLAT/XLONG)", rel);
        check_positions(name, m, la, lo);
        /* native levels follow the terrain: without a height, level 0 in every column */
        int lowest0 = 0, above_mean = 0;
        char msg[256];
        for (int j = 0; j < m->ny; j++)
            for (int i = 0; i < m->nx; i++) {
                vsv_point p;
                lowest0 += !vsv_point_cell(m, i, j, -1, &p, msg, sizeof msg) && p.cell[2] == 0;
                above_mean += m->terrain && m->terrain[(size_t)j * m->nx + i] > m->levels[0];
            }
        snprintf(name, sizeof name,
                 "%s, native levels: no height means level 0 in every column (%d above level 0's mean height)", rel,
                 above_mean);
        CHECK(lowest0 == m->nx * m->ny, name, "%d of %d", lowest0, m->nx * m->ny);
        /* per-column heights at the last time: the mass levels halfway between w-levels (PH+PHB)/g */
        const int nt = vsv_source_ntimes(src), nk = m->nz;
        const size_t plane = (size_t)m->nx * m->ny;
        float *ph = malloc(plane * (nk + 1) * 4), *phb = malloc(plane * (nk + 1) * 4);
        int vph, vphb;
        size_t s4[4] = {(size_t)nt - 1, 0, 0, 0}, c4[4] = {1, (size_t)nk + 1, (size_t)m->ny, (size_t)m->nx};
        double worst = -1;
        if (!nc_inq_varid(nc, "PH", &vph) && !nc_inq_varid(nc, "PHB", &vphb) &&
            !nc_get_vara_float(nc, vph, s4, c4, ph) && !nc_get_vara_float(nc, vphb, s4, c4, phb)) {
            worst = 0;
            const int64_t tl = vsv_source_time(src, nt - 1);
            for (int k = 0; k < nk; k++)
                for (size_t c = 0; c < plane; c++) {
                    const double zlo = (ph[k * plane + c] + (double)phb[k * plane + c]) / 9.81,
                                 zhi = (ph[(k + 1) * plane + c] + (double)phb[(k + 1) * plane + c]) / 9.81;
                    const double h = vsv_meta_cell_height_at(m, tl, (int)(c % m->nx), (int)(c / m->nx), k);
                    worst = fmax(worst, fabs(h - 0.5 * (zlo + zhi)));
                }
        }
        snprintf(name, sizeof name,
                 "%s: every cell's height at the last time is WRF's mass level from PH+PHB within 0.01 m", rel);
        CHECK(worst >= 0 && worst < 0.01 && m->nheights > 0, name, "worst %.4f m, %d height records", worst,
              m->nheights);
        free(ph);
        free(phb);
        free(la);
        free(lo);
        nc_close(nc);
    }
    vsv_file_free(f);
    vsv_source_free(src);
}

/* Values: every cell of two species at two steps equals the decoder's
 * volume; trilinear at known fractions; out-of-range errors. */
static void test_values(void)
{
    vsv_source *src = NULL;
    if (vsv_test_absent(vsv_test_shared("mm5/run1/MMOUT_DOMAIN1"), "values of the MM5 run"))
        return;
    if (!CHECK(vsv_source_open(vsv_test_shared("mm5/run1/MMOUT_DOMAIN1"), even(), &src) == 0,
               "MMOUT opens for values")) {
        vsv_source_free(src);
        return;
    }
    vsv_meta m;
    vsv_meta_init(&m);
    vsv_meta_copy(&m, vsv_source_grid(src));
    const int fq = vsv_source_find_field(src, "Q"), fc = vsv_source_find_field(src, "CLW");
    vsv_meta_add_var(&m, "Q", "kg/kg", "");
    vsv_meta_add_var(&m, "CLW", "kg/kg", "");
    const size_t cells = (size_t)m.nx * m.ny * m.nz;
    float *q = malloc(cells * 4), *c = malloc(cells * 4), *vol = malloc(cells * 4);
    const char *path = vsv_test_tmp("mm5q.vsv");
    vsv_writer *w = NULL;
    int ok = !vsv_writer_create(path, &m, NULL, &w);
    for (int t = 0; ok && t < 4; t++) {
        const float *fields[2] = {q, c};
        ok = !vsv_source_read(src, fq, t, q) && !vsv_source_read(src, fc, t, c) &&
             !vsv_writer_add_step(w, vsv_source_time(src, t), fields);
    }
    ok = ok && !vsv_writer_finish(w, NULL, NULL);
    vsv_writer_free(w);
    vsv_file *f = NULL;
    vsv_query *qy = NULL;
    vsv_decoder *d = NULL;
    if (CHECK(ok && !vsv_file_open(path, &f) && !vsv_query_create(f, &qy) && !vsv_decoder_create(f, &d),
              "MM5 Q and CLW written and opened")) {
        long same = 0, n = 0;
        for (int t = 1; t < 4; t += 2)
            for (int s = 0; s < 2; s++) {
                vsv_decoder_volume(d, t, s, vol);
                for (int k = 0; k < m.nz; k++)
                    for (int j = 0; j < m.ny; j++)
                        for (int i = 0; i < m.nx; i++) {
                            float v = -1;
                            const float want = vol[((size_t)k * m.ny + j) * m.nx + i];
                            vsv_query_cell(qy, t, s, i, j, k, &v);
                            same += v == want || (isnan(v) && isnan(want));
                            n++;
                        }
            }
        CHECK(same == n, "every cell's value equals the decoder's volume (Q, CLW; steps 1, 3)", "%ld of %ld", same, n);
        /* trilinear at (100.25, 60.5, 20.75): the weighted eight cells */
        vsv_decoder_volume(d, 3, 0, vol);
        const double pos[3] = {100.25, 60.5, 20.75};
        double want = 0;
        for (int cc = 0; cc < 8; cc++) {
            const int i = 100 + (cc & 1), j = 60 + !!(cc & 2), k = 20 + !!(cc & 4);
            const double wt = (cc & 1 ? 0.25 : 0.75) * 0.5 * (cc & 4 ? 0.75 : 0.25);
            want += wt * vol[((size_t)k * m.ny + j) * m.nx + i];
        }
        float v = 0, near = 0;
        vsv_query_sample(qy, 3, 0, pos, VSV_INTERP_LINEAR, &v);
        vsv_query_sample(qy, 3, 0, pos, VSV_INTERP_NEAREST, &near);
        CHECK(v == (float)want && want > 0, "trilinear Q at (100.25, 60.5, 20.75) is the weighted eight cells",
              "%.9g vs %.9g", v, want);
        CHECK(near == vol[((size_t)21 * m.ny + 61) * m.nx + 100],
              "nearest Q at (100.25, 60.5, 20.75) is cell 100,61,21", "%.9g", near);
        CHECK(vsv_query_cell(qy, 4, 0, 0, 0, 0, &v) == VSV_ERANGE &&
                  vsv_query_cell(qy, 0, 0, m.nx, 0, 0, &v) == VSV_ERANGE,
              "a step or cell outside the file is VSV_ERANGE");
        /* points */
        const vsv_meta *fm = vsv_file_meta(f);
        vsv_point p;
        char msg[256];
        int rc = vsv_point_locate(fm, 41.88, -87.63, 3000, &p, msg, sizeof msg);
        CHECK(rc == 0 && p.cell[0] == 127 && p.cell[1] == 85 && p.cell[2] == 8 && fabs(p.height - 3060) < 1e-9,
              "Chicago at 3000 m is cell 127,85,8 (centre 3060 m)", "%d %d,%d,%d %g", rc, p.cell[0], p.cell[1],
              p.cell[2], p.height);
        rc = vsv_point_locate(fm, 41.88, -87.63, NAN, &p, msg, sizeof msg);
        const double ground = fm->terrain[(size_t)85 * fm->nx + 127];
        CHECK(rc == 0 && p.cell[2] == (int)ceil((ground - 180) / 360) && p.height >= ground && p.height - 360 < ground,
              "without a height: the lowest level above Chicago's ground", "k %d, %g m over %g m", p.cell[2], p.height,
              ground);
        rc = vsv_point_locate(fm, 10, 0, NAN, &p, msg, sizeof msg);
        CHECK(rc == VSV_ERANGE && strstr(msg, "outside the grid") && strstr(msg, "latitude 13.4"),
              "a point outside the grid names the range", "%s", msg);
        rc = vsv_point_locate(fm, 41.88, -87.63, 20000, &p, msg, sizeof msg);
        CHECK(rc == VSV_ERANGE && strstr(msg, "0..14400 m"), "a height above the grid names the levels", "%s", msg);
        rc = vsv_point_cell(fm, 207, 0, 0, &p, msg, sizeof msg);
        CHECK(rc == VSV_ERANGE && strstr(msg, "i 0..206, j 0..141, k 0..39"), "a cell outside the grid names the range",
              "%s", msg);
    }
    vsv_decoder_free(d);
    vsv_query_free(qy);
    vsv_file_free(f);
    vsv_meta_clear(&m);
    free(q);
    free(c);
    free(vol);
    vsv_source_free(src);
}

/* Trilinear beside a no-data cell (vsv_format.h: NaN only when a cell with
 * non-zero weight is NaN): a small grid whose cell (3,2,1) is NaN. */
/* One step of species 0 (v) on grid m written to name, opened and queried:
 * 1, or 0 with *f and *q as far as they got (free both either way). */
static int one_step_file(const vsv_meta *m, const float *v, const char *name, vsv_file **f, vsv_query **q)
{
    const char *path = vsv_test_tmp(name);
    vsv_writer *w = NULL;
    const float *fields[1] = {v};
    const int ok = !vsv_writer_create(path, m, NULL, &w) && !vsv_writer_add_step(w, 0, fields) &&
                   !vsv_writer_finish(w, NULL, NULL);
    vsv_writer_free(w);
    return ok && !vsv_file_open(path, f) && !vsv_query_create(*f, q);
}

static void test_nodata(void)
{
    enum { NX = 8, NY = 6, NZ = 4 };
    vsv_meta m;
    vsv_meta_init(&m);
    m.nx = NX, m.ny = NY, m.nz = NZ;
    m.spacing[0] = m.spacing[1] = m.spacing[2] = 1000;
    vsv_meta_add_var(&m, "T", "K", "a ramp with one no-data cell");
    float v[NX * NY * NZ];
    for (int c = 0; c < NX * NY * NZ; c++)
        v[c] = (float)(10 + c % NX + 2 * (c / NX % NY) + 3 * (c / NX / NY));
    v[(1 * NY + 2) * NX + 3] = NAN;
    vsv_file *f = NULL;
    vsv_query *q = NULL;
    const int ok = one_step_file(&m, v, "nodata.vsv", &f, &q);
    vsv_meta_clear(&m);
    if (!CHECK(ok, "a grid with a no-data cell written and opened")) {
        vsv_query_free(q);
        vsv_file_free(f);
        return;
    }
    float nan = 0, left = 0, right = 0, up = 0, got = -1;
    vsv_query_cell(q, 0, 0, 3, 2, 1, &nan);
    vsv_query_cell(q, 0, 0, 2, 2, 1, &left);
    vsv_query_cell(q, 0, 0, 4, 2, 1, &right);
    vsv_query_cell(q, 0, 0, 2, 3, 1, &up);
    CHECK(isnan(nan) && !isnan(left) && !isnan(right) && !isnan(up),
          "cell 3,2,1 decodes to NaN, its neighbours to values");
    const double at_left[3] = {2, 2, 1}, at_right[3] = {4, 2, 1}, between[3] = {2, 2.5, 1}, half[3] = {2.5, 2, 1};
    int rc = vsv_query_sample(q, 0, 0, at_left, VSV_INTERP_LINEAR, &got);
    CHECK(rc == 0 && got == left,
          "trilinear at the centre of cell 2,2,1, beside the NaN cell 3,2,1, is the cell's value",
          "rc %d: %.9g, want %.9g", rc, got, left);
    got = -1;
    rc = vsv_query_sample(q, 0, 0, at_right, VSV_INTERP_LINEAR, &got);
    CHECK(rc == 0 && got == right, "trilinear at the centre of cell 4,2,1 (NaN cell below it in x) is the cell's value",
          "rc %d: %.9g, want %.9g", rc, got, right);
    got = -1;
    rc = vsv_query_sample(q, 0, 0, between, VSV_INTERP_LINEAR, &got);
    CHECK(rc == 0 && got == (float)(0.5 * left + 0.5 * up),
          "trilinear at 2,2.5,1 (zero weight on the NaN cell 3,2,1) blends cells 2,2,1 and 2,3,1", "rc %d: %.9g", rc,
          got);
    got = 0;
    rc = vsv_query_sample(q, 0, 0, half, VSV_INTERP_LINEAR, &got);
    CHECK(rc == 0 && isnan(got), "trilinear at 2.5,2,1 (the NaN cell nearest, as lround has it) is NaN", "rc %d: %.9g",
          rc, got);
    /* nearer cell 2,2,1 than the NaN cell: the cells with data, weighted
     * anew (it was NaN: a profile near the ground lost its lowest levels) */
    const double near_left[3] = {2.3, 2, 1}, near_four[3] = {2.3, 2.4, 1};
    got = 0;
    rc = vsv_query_sample(q, 0, 0, near_left, VSV_INTERP_LINEAR, &got);
    CHECK(rc == 0 && got == left, "trilinear at 2.3,2,1 (nearest 2,2,1, 0.3 on the NaN cell) is cell 2,2,1's value",
          "rc %d: %.9g, want %.9g", rc, got, left);
    float diag = 0;
    vsv_query_cell(q, 0, 0, 3, 3, 1, &diag);
    const float want4 = (float)((0.7 * 0.6 * left + 0.7 * 0.4 * up + 0.3 * 0.4 * diag) / (1 - 0.3 * 0.6));
    got = 0;
    rc = vsv_query_sample(q, 0, 0, near_four, VSV_INTERP_LINEAR, &got);
    CHECK(rc == 0 && fabsf(got - want4) < 1e-5f * fabsf(want4),
          "trilinear at 2.3,2.4,1 blends the three cells with data, weights scaled to 1", "rc %d: %.9g, want %.9g", rc,
          got, want4);
    /* outside the grid: clamped to the edge cells */
    float corner = 0, far = 0;
    vsv_query_cell(q, 0, 0, 0, 2, 1, &corner);
    vsv_query_cell(q, 0, 0, NX - 1, NY - 1, NZ - 1, &far);
    const double below[3] = {-0.7, 2, 1}, above[3] = {NX + 0.3, NY - 0.6, NZ + 2};
    got = -1;
    rc = vsv_query_sample(q, 0, 0, below, VSV_INTERP_LINEAR, &got);
    CHECK(rc == 0 && got == corner, "trilinear at -0.7,2,1 is clamped to cell 0,2,1", "rc %d: %.9g, want %.9g", rc, got,
          corner);
    got = -1;
    rc = vsv_query_sample(q, 0, 0, above, VSV_INTERP_LINEAR, &got);
    CHECK(rc == 0 && got == far, "trilinear past the far corner is clamped to the last cell", "rc %d: %.9g, want %.9g",
          rc, got, far);
    vsv_query_free(q);
    vsv_file_free(f);
}

/* A point in an edge cell's outer half: its position is where it is
 * (past the last centre, before the first), its cell the edge's (the
 * position was clamped to the centres, so vsv-query --json put a point
 * 0.3 cells east of the last centre on it). */
static void test_edge_positions(void)
{
    vsv_meta m;
    vsv_meta_init(&m);
    m.nx = 6, m.ny = 4, m.nz = 3;
    m.proj.kind = VSV_PROJ_LATLON;
    m.spacing[0] = m.spacing[1] = 1, m.spacing[2] = 1000;
    vsv_point p;
    char msg[256] = "";
    int rc = vsv_point_locate(&m, -0.4, 5.3, 2400, &p, msg, sizeof msg);
    CHECK(rc == 0 && fabs(p.pos[0] - 5.3) < 1e-9 && fabs(p.pos[1] + 0.4) < 1e-9 && fabs(p.pos[2] - 2.4) < 1e-9 &&
              p.cell[0] == 5 && p.cell[1] == 0 && p.cell[2] == 2,
          "a point in the edge cells' outer halves is at 5.3,-0.4,2.4, cell 5,0,2",
          "rc %d (%s): %g,%g,%g cell %d,%d,%d", rc, msg, p.pos[0], p.pos[1], p.pos[2], p.cell[0], p.cell[1], p.cell[2]);
    rc = vsv_point_locate(&m, -0.6, 5.3, 2400, &p, msg, sizeof msg);
    CHECK(rc == VSV_ERANGE, "half a cell and more past the edge is outside", "rc %d", rc);
    vsv_meta_clear(&m);
}

/* A global longitude-latitude grid (12 columns of 30 degrees from 0 east):
 * the column past the last is the first, for the nearest cell and for
 * trilinear blending across the seam, and a point west of 0 is found. */
static void test_round_the_globe(void)
{
    enum { NX = 12, NY = 5, NZ = 2 };
    vsv_meta m;
    vsv_meta_init(&m);
    m.nx = NX, m.ny = NY, m.nz = NZ;
    m.proj.kind = VSV_PROJ_LATLON;
    m.origin[0] = 0, m.origin[1] = -60;
    m.spacing[0] = m.spacing[1] = 30, m.spacing[2] = 1000;
    vsv_meta_add_var(&m, "T", "K", "the column index times 10");
    float v[NX * NY * NZ];
    for (int c = 0; c < NX * NY * NZ; c++)
        v[c] = (float)(10 * (c % NX));
    vsv_file *f = NULL;
    vsv_query *q = NULL;
    if (!CHECK(one_step_file(&m, v, "globe.vsv", &f, &q), "a global grid written and opened")) {
        vsv_meta_clear(&m);
        vsv_query_free(q);
        vsv_file_free(f);
        return;
    }
    const vsv_meta *fm = vsv_file_meta(f);
    /* cell centres at 0, 30, ... 330 east: 340 is a third of the way from
     * the last (110) to the first (0), 355 and -5 five sixths */
    const double lons[] = {340, 355, -5, 359, 0};
    const int cell[] = {11, 0, 0, 0, 0};
    const double want[] = {110 * 2 / 3.0, 110 / 6.0, 110 / 6.0, 110 / 30.0, 0};
    for (int i = 0; i < 5; i++) {
        vsv_point pt;
        char msg[256] = "";
        float lin = -1, near = -1;
        int rc = vsv_point_locate(fm, 0, lons[i], 500, &pt, msg, sizeof msg);
        if (!rc)
            rc = vsv_query_sample(q, 0, 0, pt.pos, VSV_INTERP_LINEAR, &lin) ||
                 vsv_query_sample(q, 0, 0, pt.pos, VSV_INTERP_NEAREST, &near);
        const double wl = want[i];
        CHECK(rc == 0 && pt.cell[0] == cell[i] && fabs(lin - wl) < 1e-3 && near == 10 * cell[i],
              "round the globe: longitude blends across the seam",
              "%g: rc %d (%s), cell %d, trilinear %.6g (want %.6g), nearest %g", lons[i], rc, msg, pt.cell[0], lin, wl,
              near);
    }
    /* positions a caller may hand in: a hair below 0, exactly nx, not finite */
    const double edge[3][3] = {{-1e-17, 2, 1}, {NX, 2, 1}, {NAN, 2, 1}};
    for (int i = 0; i < 3; i++) {
        float lin = -1, near = -1;
        const int rc = vsv_query_sample(q, 0, 0, edge[i], VSV_INTERP_LINEAR, &lin) ||
                       vsv_query_sample(q, 0, 0, edge[i], VSV_INTERP_NEAREST, &near);
        CHECK(rc == 0 && fabsf(lin) < 1e-3f && near == 0, "round the globe: x of -1e-17, nx or NaN is column 0",
              "case %d: rc %d, trilinear %g, nearest %g", i, rc, lin, near);
    }
    /* a point a hair west of 0 east lies at x just below 0, not just below nx
     * (a section from there to 10 east goes the short way) */
    vsv_point pt;
    char msg[256] = "";
    const int lrc = vsv_point_locate(fm, 0, -0.3, 500, &pt, msg, sizeof msg);
    CHECK(lrc == 0 && pt.pos[0] < 0 && pt.pos[0] > -0.02 && pt.cell[0] == 0,
          "round the globe: 359.7 east is at x -0.01, cell 0", "rc %d (%s): x %g, cell %d", lrc, msg, pt.pos[0],
          pt.cell[0]);
    vsv_meta_clear(&m);
    vsv_query_free(q);
    vsv_file_free(f);
}

int main(void)
{
    test_mm5_positions();
    test_wrf_positions("wrf/wrf_cropped.nc");
    test_wrf_positions("wrf/wrf_d01_allvars_cropped.nc");
    test_wrf_positions("wrf/katrina_ci_test_file.nc");
    test_values();
    test_nodata();
    test_round_the_globe();
    test_edge_positions();
    return vsv_test_done();
}
