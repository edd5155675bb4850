/* vsv_calendar.c — civil time: UTC seconds from a date, ISO 8601 text
 * and back (proleptic Gregorian, no leap seconds). */
#include "vsv_format_internal.h"

#include <stdio.h>
#include <string.h>

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
    int64_t days = t >= 0 ? t / 86400 : -((-t + 86399) / 86400);
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
    snprintf(buf, cap, "%04lld-%02lld-%02lldT%02lld:%02lld:%02lldZ", (long long)y, (long long)m,
             (long long)d, (long long)(sec / 3600), (long long)(sec / 60 % 60), (long long)(sec % 60));
}

int vsv_time_parse(const char *s, int64_t *t)
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
    if (*p || mo < 1 || mo > 12 || d < 1 || d > 31 || h < 0 || h > 24 || mi < 0 || mi > 59 || se < 0 ||
        se > 60)
        return VSV_EINVAL;
    *t = vsv_time_from_civil(y, mo, d, h, mi, se);
    return 0;
}
