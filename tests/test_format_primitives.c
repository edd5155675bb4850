/* test_format_primitives.c — the .vsv format library's primitives: CRC-32C
 * against a bitwise reference, the calendar (civil time, formatting,
 * parsing), the time grammar's choice of steps, quantisation within its
 * stated bounds, and dequantisation bit for bit the rule of SPEC.md §6. */
#include "vsv_format_internal.h"
#include "vsv_refread.h"
#include "vsv_testlib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void test_basics(void)
{
    CHECK(vsv_crc32c(0, "123456789", 9) == 0xE3069283u, "crc32c known vector");
    uint64_t st = 7;
    unsigned char buf[1000];
    for (size_t i = 0; i < sizeof buf; i++)
        buf[i] = (unsigned char)vsv_test_rand(&st);
    int same = 1;
    for (size_t n = 0; n < sizeof buf; n += 37)
        same &= vsv_crc32c(0, buf, n) == ref_crc32c(buf, n);
    CHECK(same, "crc32c equals the bitwise reference at many lengths");
    CHECK(vsv_crc32c(vsv_crc32c(0, buf, 300), buf + 300, 700) == vsv_crc32c(0, buf, 1000), "crc32c continues");

    char t[40];
    CHECK(vsv_time_from_civil(1970, 1, 1, 0, 0, 0) == 0, "epoch is 0");
    CHECK(vsv_time_from_civil(2000, 3, 1, 0, 0, 0) == 951868800, "2000-03-01 seconds");
    vsv_time_format(-1, t, sizeof t);
    CHECK(!strcmp(t, "1969-12-31T23:59:59Z"), "negative time formats", "got %s", t);
    vsv_time_format(814492800 + 3 * 3600, t, sizeof t);
    CHECK(!strcmp(t, "1995-10-24T03:00:00Z"), "MM5 run time formats", "got %s", t);
    int64_t p = 0;
    CHECK(!vsv_time_parse("1995-10-24T03:00:00Z", &p) && p == 814492800 + 3 * 3600, "ISO time parses");
    CHECK(!vsv_time_parse("1995-10-24_03:00", &p) && p == 814492800 + 3 * 3600, "MM5-style time parses");
    CHECK(vsv_time_parse("1995-13-24", &p) == VSV_EINVAL, "bad month rejected");
    CHECK(vsv_time_parse("1995-02-30T00:00:00Z", &p) == VSV_EINVAL && vsv_time_parse("1995-04-31", &p) == VSV_EINVAL &&
              vsv_time_parse("1995-02-29", &p) == VSV_EINVAL && vsv_time_parse("1900-02-29", &p) == VSV_EINVAL,
          "a day past its month's end rejected (30 February, 31 April, 29 February of 1995 and 1900)");
    CHECK(!vsv_time_parse("2000-02-29", &p) && p == 951782400 && !vsv_time_parse("1996-02-29T12:00", &p) &&
              !vsv_time_parse("1995-12-31T24:00:00Z", &p) && p == 820454400,
          "29 February of a leap year and the end of a year's last day parse");
    /* January and February belong to the year they are in (the algorithm
     * counts years from March) */
    vsv_time_format(vsv_time_from_civil(1996, 2, 29, 12, 0, 0), t, sizeof t);
    CHECK(!strcmp(t, "1996-02-29T12:00:00Z"), "a leap day formats in its own year", "got %s", t);
    vsv_time_format(vsv_time_from_civil(2001, 1, 1, 0, 0, 0), t, sizeof t);
    CHECK(!strcmp(t, "2001-01-01T00:00:00Z"), "New Year's Day formats in its own year", "got %s", t);
    /* the other calendars: their own month lengths */
    CHECK(vsv_cal_parse(VSV_CAL_STANDARD, "1995-02-30T00:00:00Z", &p) == VSV_EINVAL &&
              !vsv_cal_parse(VSV_CAL_STANDARD, "1996-02-29", &p) && p == 825552000,
          "standard calendar: 30 February refused, 29 February 1996 read");
    CHECK(!vsv_cal_parse(VSV_CAL_360_DAY, "2001-02-30", &p) &&
              vsv_cal_parse(VSV_CAL_360_DAY, "2001-02-31", &p) == VSV_EINVAL,
          "360_day: February 30 exists, February 31 does not");
    CHECK(!vsv_cal_parse(VSV_CAL_NOLEAP, "2000-02-28", &p) &&
              vsv_cal_parse(VSV_CAL_NOLEAP, "2000-02-29", &p) == VSV_EINVAL,
          "noleap: 2000-02-28 exists, 2000-02-29 does not");
    CHECK(!vsv_cal_parse(VSV_CAL_NOLEAP, "2001-12-31T06Z", &p) && (vsv_cal_format(VSV_CAL_NOLEAP, p, t, sizeof t), 1) &&
              !strcmp(t, "2001-12-31T06:00:00Z"),
          "noleap: December 31 parses and formats back", "got %s", t);
    CHECK(!vsv_cal_parse(VSV_CAL_ALL_LEAP, "2001-02-29", &p) && (vsv_cal_format(VSV_CAL_ALL_LEAP, p, t, sizeof t), 1) &&
              !strcmp(t, "2001-02-29T00:00:00Z"),
          "all_leap: 2001-02-29 parses and formats back", "got %s", t);
}

/* vsv_timesel_parse (vsv_time.h): a time selects the nearest step, halfway
 * the earlier one, exact = 0 between steps; a range the first step at or
 * after A to the last at or before B. Steps hourly from 1970-01-01T00Z. */
static void test_timesel(void)
{
    const int64_t times[4] = {0, 3600, 7200, 10800};
    vsv_timesel sel;
    char msg[256];
    int rc = vsv_timesel_parse("1970-01-01T01:30:00Z", times, 4, 0, &sel, msg, sizeof msg);
    CHECK(rc == 0 && sel.first == 1 && sel.last == 1 && sel.exact == 0 && !sel.range,
          "a time halfway between steps 1 and 2 selects step 1 (exact 0)", "rc %d, steps %d..%d, exact %d: %s", rc,
          sel.first, sel.last, sel.exact, rc ? msg : "");
    rc = vsv_timesel_parse("1970-01-01T01:30:01Z", times, 4, 0, &sel, msg, sizeof msg);
    CHECK(rc == 0 && sel.first == 2 && sel.exact == 0, "a second past halfway selects the later step 2",
          "rc %d, step %d, exact %d", rc, sel.first, sel.exact);
    rc = vsv_timesel_parse("1970-01-01T01:29:59Z", times, 4, 0, &sel, msg, sizeof msg);
    CHECK(rc == 0 && sel.first == 1 && sel.exact == 0, "a second before halfway selects step 1", "rc %d, step %d", rc,
          sel.first);
    rc = vsv_timesel_parse("1970-01-01T02:00:00Z", times, 4, 0, &sel, msg, sizeof msg);
    CHECK(rc == 0 && sel.first == 2 && sel.exact == 1, "a step's own time selects it (exact 1)",
          "rc %d, step %d, exact %d", rc, sel.first, sel.exact);
    rc = vsv_timesel_parse("1970-01-01T03:00:00Z", times, 4, 0, &sel, msg, sizeof msg);
    CHECK(rc == 0 && sel.first == 3 && sel.exact == 1, "the last step's time selects step 3", "rc %d, step %d", rc,
          sel.first);
    rc = vsv_timesel_parse("1970-01-01T00:30:00Z:1970-01-01T02:30:00Z", times, 4, 0, &sel, msg, sizeof msg);
    CHECK(rc == 0 && sel.first == 1 && sel.last == 2 && sel.range,
          "a range between steps selects the first at or after A (1) to the last at or before B (2)",
          "rc %d, steps %d..%d: %s", rc, sel.first, sel.last, rc ? msg : "");
    rc = vsv_timesel_parse("3", times, 4, 0, &sel, msg, sizeof msg);
    CHECK(rc == 0 && sel.first == 3 && sel.exact == 1, "index 3 is step 3", "rc %d", rc);
    rc = vsv_timesel_parse("4", times, 4, 0, &sel, msg, sizeof msg);
    CHECK(rc == VSV_ERANGE, "index 4 of 4 steps is out of range", "rc %d", rc);
    rc = vsv_timesel_parse("1970-01-01T03:00:01Z", times, 4, 0, &sel, msg, sizeof msg);
    CHECK(rc == VSV_ERANGE, "a second after the last step is out of range", "rc %d", rc);
}

static void test_quant(void)
{
    vsv_pack_var o;
    vsv_pack_var_init(&o);
    vsv_quant q;
    vsv_quant_plan(&q, &o, 200, 300, 200, 0);
    int ok = 1;
    for (double v = 200; v <= 300; v += 0.0137) {
        unsigned c = vsv_quant_code(&q, (float)v);
        ok &= fabs(vsv_quant_value(&q, c) - (float)v) <= q.max_abs_error;
    }
    CHECK(ok && q.max_abs_error < 100.0 / 65535, "linear 16-bit error within bound", "bound %g", q.max_abs_error);
    CHECK(vsv_quant_code(&q, NAN) == 0 && vsv_quant_code(&q, INFINITY) == 0, "non-finite values are code 0");
    vsv_quant_plan(&q, &o, 200, 300, 200, 1);
    ok = q.missing && vsv_quant_code(&q, 200) == 1 && vsv_quant_code(&q, 300) == 65535 && isnan(vsv_quant_value(&q, 0));
    for (double v = 200; v <= 300; v += 0.0137)
        ok &= fabs(vsv_quant_value(&q, vsv_quant_code(&q, (float)v)) - (float)v) <= q.max_abs_error;
    CHECK(ok, "linear with no-data cells: code 0 decodes to NaN, values within bound");
    o.scale = VSV_SCALE_LOG;
    o.bits = 8;
    vsv_quant_plan(&q, &o, 0, 1e-3, 1e-9, 0);
    CHECK(fabs(q.lo - 1e-6) < 1e-18 && q.hi == 1e-3, "log 8-bit spans 3 decades by default", "lo %g", q.lo);
    ok = 1;
    for (double v = 1e-9; v <= 1e-3; v *= 1.07) {
        unsigned c = vsv_quant_code(&q, (float)v);
        ok &= fabs(vsv_quant_value(&q, c) - (float)v) <= q.max_abs_error;
        ok &= v < q.lo ? c == 0 : c >= 1;
    }
    CHECK(ok, "log 8-bit error within bound, below floor is empty", "bound %g", q.max_abs_error);
    CHECK(vsv_quant_code(&q, 0) == 0 && vsv_quant_value(&q, 0) == 0, "log code 0 is zero");
    /* linear, a non-negative field with round-off below zero (WRF's
     * hydrometeors): 0 stays the floor, so zeros decode to exactly 0 */
    vsv_pack_var_init(&o);
    vsv_quant_plan(&q, &o, -1e-14, 1e-3, 1e-9, 0);
    CHECK(q.lo == 0 && vsv_quant_code(&q, 0) == 0 && vsv_quant_value(&q, 0) == 0 &&
              fabs(vsv_quant_value(&q, vsv_quant_code(&q, -1e-14f)) + 1e-14) <= q.max_abs_error,
          "linear: round-off below zero keeps 0 as the floor (zeros decode to 0)", "lo %g", q.lo);
    vsv_quant_plan(&q, &o, -1e-3, 1e-3, 1e-9, 0);
    CHECK(q.lo == -1e-3, "linear: a field truly below zero keeps its minimum as the floor", "lo %g", q.lo);
}

/* vsv_file_dequantise gives, for every code, the very bits of
 * vsv_quant_value (the rule of SPEC.md §6): linear 16-bit with code 0 as no
 * data (NaN), linear 16-bit without, and 8-bit (its table). */
static void test_dequantise(void)
{
    vsv_meta m;
    vsv_meta_init(&m);
    m.nx = 4, m.ny = 2, m.nz = 1;
    m.spacing[0] = m.spacing[1] = m.spacing[2] = 1;
    vsv_meta_add_var(&m, "gaps", "K", "");
    vsv_meta_add_var(&m, "full", "K", "");
    vsv_meta_add_var(&m, "byte", "K", "");
    vsv_pack_opts o;
    vsv_pack_var pv[3];
    vsv_pack_opts_init(&o);
    o.threads = 1;
    for (int s = 0; s < 3; s++)
        vsv_pack_var_init(&pv[s]);
    pv[2].bits = 8;
    o.vars = pv;
    const float gaps[8] = {201.5f, NAN, 250, 299.25f, 233, 201, 278.125f, 300};
    const float full[8] = {-3.75f, 0.5f, 1e3f, 17, 18, 19, 20, 21}, byte[8] = {1, 2, 3, 4, 5, 6, 7, 8.5f};
    const float *fields[3] = {gaps, full, byte};
    const char *path = vsv_test_tmp("dequant.vsv");
    vsv_writer *w = NULL;
    int rc = vsv_writer_create(path, &m, &o, &w);
    rc = rc ? rc : vsv_writer_add_step(w, 0, fields);
    rc = rc ? rc : vsv_writer_finish(w, NULL, NULL);
    vsv_writer_free(w);
    vsv_meta_clear(&m);
    vsv_file *f = NULL;
    CHECK(!rc && !vsv_file_open(path, &f), "dequantise test file written");
    if (!f)
        return;
    uint16_t *codes = malloc(65536 * sizeof *codes);
    float *got = malloc(65536 * sizeof *got), *want = malloc(65536 * sizeof *want);
    for (unsigned c = 0; c < 65536; c++)
        codes[c] = (uint16_t)c;
    for (int s = 0; s < 3; s++) {
        const vsv_quant *q = vsv_file_quant(f, s);
        const unsigned n = q->bits == 8 ? 256 : 65536;
        for (unsigned c = 0; c < n; c++)
            want[c] = vsv_quant_value(q, c);
        /* odd starts and lengths: the vector loops' edges */
        vsv_file_dequantise(f, s, codes, 3, got);
        vsv_file_dequantise(f, s, codes + 3, n - 3, got + 3);
        unsigned bad = n;
        for (unsigned c = n; c-- > 0;)
            if (memcmp(&got[c], &want[c], sizeof got[c]))
                bad = c;
        CHECK(bad == n && (s != 0 || (q->missing && isnan(got[0]))), "dequantise matches the rule bit for bit",
              "species %d (missing %d, bits %d): code %u gives %.9g, not %.9g", s, q->missing, q->bits, bad,
              bad < n ? got[bad] : 0, bad < n ? want[bad] : 0);
    }
    free(codes);
    free(got);
    free(want);
    vsv_file_free(f);
    unlink(path);
}

int main(void)
{
    test_basics();
    test_timesel();
    test_quant();
    test_dequantise();
    return vsv_test_done();
}
