/* vsv_calendar.c — civil time: UTC seconds from a date, ISO 8601 text
 * and back (proleptic Gregorian, no leap seconds), and the same in the
 * models' other calendars (noleap, all_leap, 360_day: CF's). */
#include "vsv_format_internal.h"

#include <stdio.h>
#include <string.h>
#include <strings.h>

int64_t vsv_time_from_civil(int y, int m, int d, int hh, int mm, int ss)
{
    /* Days from civil (H. Hinnant's algorithm), exact for any Gregorian date. */
    y -= m <= 2;
    const int64_t era = (y >= 0 ? y : y - 399) / 400;
    const int64_t yoe = y - era * 400;
    const int64_t doy = (153 * ((int64_t)m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
    const int64_t doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    const int64_t days = era * 146097 + doe - 719468;
    /* in 64 bits: a reader's unchecked hour (22222222, found by fuzz_grads)
     * overflowed an int here */
    return days * 86400 + (int64_t)hh * 3600 + (int64_t)mm * 60 + ss;
}

void vsv_time_format(int64_t t, char *buf, size_t cap)
{
    int64_t days = t / 86400 - (t % 86400 < 0); /* floor, and no -t to overflow */
    int64_t sec = t - days * 86400;
    int64_t z = days + 719468;
    const int64_t era = (z >= 0 ? z : z - 146096) / 146097;
    const int64_t doe = z - era * 146097;
    const int64_t yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
    int64_t y = yoe + era * 400;
    const int64_t doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    const int64_t mp = (5 * doy + 2) / 153;
    const int64_t d = doy - (153 * mp + 2) / 5 + 1;
    const int64_t m = mp + (mp < 10 ? 3 : -9);
    y += m <= 2;
    snprintf(buf, cap, "%04lld-%02lld-%02lldT%02lld:%02lld:%02lldZ", (long long)y, (long long)m, (long long)d,
             (long long)(sec / 3600), (long long)(sec / 60 % 60), (long long)(sec % 60));
}

/* The civil fields of "YYYY-MM-DD[T ]HH[:MM[:SS]][Z]"; 0 or VSV_EINVAL. */
static int civil_fields(const char *s, int f[6])
{
    int y, mo, d, h = 0, mi = 0, se = 0, n = 0;
    if (sscanf(s, "%d-%d-%d%n", &y, &mo, &d, &n) != 3)
        return VSV_EINVAL;
    const char *p = s + n;
    if (*p == 'T' || *p == ' ' || *p == '_') {
        int k = 0;
        if (sscanf(p + 1, "%d%n", &h, &k) != 1)
            return VSV_EINVAL;
        p += 1 + k;
        if (*p == ':') {
            if (sscanf(p + 1, "%d%n", &mi, &k) != 1)
                return VSV_EINVAL;
            p += 1 + k;
            if (*p == ':') {
                if (sscanf(p + 1, "%d%n", &se, &k) != 1)
                    return VSV_EINVAL;
                p += 1 + k;
            }
        }
    }
    if (*p == 'Z')
        p++;
    if (*p || mo < 1 || mo > 12 || d < 1 || d > 31 || h < 0 || h > 24 || mi < 0 || mi > 59 || se < 0 || se > 60)
        return VSV_EINVAL;
    f[0] = y, f[1] = mo, f[2] = d, f[3] = h, f[4] = mi, f[5] = se;
    return 0;
}

static int month_days(int cal, int m);

int vsv_time_parse(const char *s, int64_t *t)
{
    int f[6];
    if (civil_fields(s, f))
        return VSV_EINVAL;
    const int y = f[0], leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
    if (f[2] > month_days(VSV_CAL_STANDARD, f[1]) + (f[1] == 2 && leap)) /* 30 February */
        return VSV_EINVAL;
    *t = vsv_time_from_civil(f[0], f[1], f[2], f[3], f[4], f[5]);
    return 0;
}

/* ------------------------------------------------------------ calendars */

/* Days before month m (1..12) in a 365- or 366-day year. */
static int month_start(int m, int leap)
{
    static const int cum[12] = {0, 31, 59, 90, 120, 151, 181, 212, 243, 273, 304, 334};
    return cum[m - 1] + (leap && m > 2);
}

static int month_days(int cal, int m)
{
    if (cal == VSV_CAL_360_DAY)
        return 30;
    static const int n[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
    return n[m - 1] + (cal == VSV_CAL_ALL_LEAP && m == 2);
}

int vsv_calendar_named(const char *name)
{
    static const struct {
        const char *name;
        int cal;
    } names[] = {
        {"standard", VSV_CAL_STANDARD}, {"gregorian", VSV_CAL_STANDARD}, {"proleptic_gregorian", VSV_CAL_STANDARD},
        {"noleap", VSV_CAL_NOLEAP},     {"365_day", VSV_CAL_NOLEAP},     {"all_leap", VSV_CAL_ALL_LEAP},
        {"366_day", VSV_CAL_ALL_LEAP},  {"360_day", VSV_CAL_360_DAY}};
    for (size_t i = 0; name && i < sizeof names / sizeof *names; i++)
        if (!strcasecmp(name, names[i].name))
            return names[i].cal;
    return -1;
}

const char *vsv_calendar_name(int cal)
{
    return cal == VSV_CAL_NOLEAP     ? "noleap"
           : cal == VSV_CAL_ALL_LEAP ? "all_leap"
           : cal == VSV_CAL_360_DAY  ? "360_day"
                                     : "standard";
}

int vsv_meta_calendar(const vsv_meta *m)
{
    const int cal = vsv_calendar_named(vsv_meta_attr(m, VSV_ATTR_CALENDAR));
    return cal < 0 ? VSV_CAL_STANDARD : cal;
}

/* Days in a year of the calendar (not the standard one). */
static int year_days(int cal) { return cal == VSV_CAL_360_DAY ? 360 : cal == VSV_CAL_ALL_LEAP ? 366 : 365; }

int64_t vsv_cal_from_civil(int cal, int y, int m, int d, int hh, int mm, int ss)
{
    if (cal == VSV_CAL_STANDARD)
        return vsv_time_from_civil(y, m, d, hh, mm, ss);
    const int64_t before = cal == VSV_CAL_360_DAY ? (int64_t)(m - 1) * 30 : month_start(m, cal == VSV_CAL_ALL_LEAP);
    const int64_t days = ((int64_t)y - 1970) * year_days(cal) + before + d - 1;
    return days * 86400 + (int64_t)hh * 3600 + (int64_t)mm * 60 + ss;
}

void vsv_cal_format(int cal, int64_t t, char *buf, size_t cap)
{
    if (cal == VSV_CAL_STANDARD) {
        vsv_time_format(t, buf, cap);
        return;
    }
    const int64_t days = t / 86400 - (t % 86400 < 0), sec = t - days * 86400;
    const int yd = year_days(cal);
    const int64_t years = days / yd - (days % yd < 0);
    int doy = (int)(days - years * yd), m = 1;
    while (m < 12 && doy >= month_days(cal, m))
        doy -= month_days(cal, m++);
    snprintf(buf, cap, "%04lld-%02d-%02dT%02lld:%02lld:%02lldZ", (long long)(1970 + years), m, doy + 1,
             (long long)(sec / 3600), (long long)(sec / 60 % 60), (long long)(sec % 60));
}

int vsv_cal_parse(int cal, const char *s, int64_t *t)
{
    if (cal == VSV_CAL_STANDARD)
        return vsv_time_parse(s, t);
    int f[6];
    if (civil_fields(s, f) || f[2] > month_days(cal, f[1]))
        return VSV_EINVAL;
    *t = vsv_cal_from_civil(cal, f[0], f[1], f[2], f[3], f[4], f[5]);
    return 0;
}
