/* vsv_timesel.c — the one time grammar of every tool (--time, --times, the
 * player's seek): an index, an ISO time, or a range A:B of either, where an
 * ISO time may itself hold colons. Written once here so every tool splits,
 * rounds and refuses the same way (see vsv_format.h). */
#include "vsv_format.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { EL_EMPTY, EL_INDEX, EL_TIME, EL_BAD };

/* The kind of one element of n bytes at s, and its value. */
static int element(int cal, const char *s, size_t n, long long *idx, int64_t *t)
{
    char buf[96];
    if (!n)
        return EL_EMPTY;
    if (n >= sizeof buf)
        return EL_BAD;
    memcpy(buf, s, n);
    buf[n] = 0;
    size_t digits = strspn(buf, "0123456789");
    if (digits == n) {
        if (n > 9)
            return EL_BAD;
        *idx = strtoll(buf, NULL, 10);
        return EL_INDEX;
    }
    return vsv_cal_parse(cal, buf, t) ? EL_BAD : EL_TIME;
}

static int fail(char *msg, size_t cap, int rc, const char *fmt, ...) __attribute__((format(printf, 4, 5)));
static int fail(char *msg, size_t cap, int rc, const char *fmt, ...)
{
    if (msg && cap) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(msg, cap, fmt, ap);
        va_end(ap);
    }
    return rc;
}

/* "steps 0..N-1, FIRST .. LAST": the valid range, for messages. */
static void valid_range(int cal, const int64_t *times, int n, char *buf, size_t cap)
{
    char a[40], b[40];
    vsv_cal_format(cal, times[0], a, sizeof a);
    vsv_cal_format(cal, times[n - 1], b, sizeof b);
    if (n == 1)
        snprintf(buf, cap, "the only step is 0, %s", a);
    else
        snprintf(buf, cap, "steps 0..%d, %s .. %s", n - 1, a, b);
}

/* Resolves one element to a step. how: 0 nearest, 1 first at or after,
 * 2 last at or before. */
static int resolve(int cal, const int64_t *times, int n, int kind, long long idx, int64_t t, int how, const char *text,
                   int *step, int *exact, char *msg, size_t cap)
{
    char range[128];
    valid_range(cal, times, n, range, sizeof range);
    if (kind == EL_INDEX) {
        if (idx >= n)
            return fail(msg, cap, VSV_ERANGE, "step %lld is out of range (%s)", idx, range);
        *step = (int)idx;
        *exact = 1;
        return 0;
    }
    if (t < times[0] || t > times[n - 1])
        return fail(msg, cap, VSV_ERANGE, "%s is %s the %s step (%s)", text, t < times[0] ? "before" : "after",
                    t < times[0] ? "first" : "last", range);
    int i = 0; /* the first step at or after t */
    while (i < n - 1 && times[i] < t)
        i++;
    *exact = times[i] == t;
    if (!*exact) {
        if (how == 2)
            i--;
        else if (how == 0 && t - times[i - 1] <= times[i] - t)
            i--; /* nearest; halfway goes to the earlier step */
    }
    *step = i;
    return 0;
}

int vsv_timesel_parse(const char *spec, const int64_t *times, int n, int flags, vsv_timesel *out, char *msg, size_t cap)
{
    memset(out, 0, sizeof *out);
    const int cal = flags >> 4 & 3;
    if (!spec || !*spec)
        return fail(msg, cap, VSV_EINVAL, "an empty time");
    if (times && n < 1)
        return fail(msg, cap, VSV_ERANGE, "'%s': there are no steps", spec);
    const size_t len = strlen(spec);
    long long ia = 0, ib = 0;
    int64_t ta = 0, tb = 0;
    /* one element */
    const int whole = element(cal, spec, len, &ia, &ta);
    if ((whole == EL_INDEX || whole == EL_TIME) && !times)
        return 0;
    if (whole == EL_INDEX || whole == EL_TIME) {
        int s, exact;
        int rc = resolve(cal, times, n, whole, ia, ta, 0, spec, &s, &exact, msg, cap);
        if (rc)
            return rc;
        out->first = out->last = s;
        out->exact = exact;
        return 0;
    }
    /* a range: the one colon whose two sides are elements of one kind
     * (ISO times hold colons of their own; "T01:02" is not a range) */
    int found = 0, ka = 0, kb = 0;
    const char *colon = NULL;
    for (const char *c = strchr(spec, ':'); c; c = strchr(c + 1, ':')) {
        long long xa = 0, xb = 0;
        int64_t ya = 0, yb = 0;
        const int k1 = element(cal, spec, (size_t)(c - spec), &xa, &ya);
        const int k2 = element(cal, c + 1, strlen(c + 1), &xb, &yb);
        if (k1 == EL_BAD || k2 == EL_BAD || (k1 != EL_EMPTY && k2 != EL_EMPTY && k1 != k2))
            continue;
        if (found++)
            return fail(msg, cap, VSV_EINVAL, "'%s' is ambiguous: write both ends in full", spec);
        ka = k1, kb = k2, ia = xa, ib = xb, ta = ya, tb = yb, colon = c;
    }
    if (!found)
        return fail(msg, cap, VSV_EINVAL,
                    "'%s' is neither a step index, an ISO time (YYYY-MM-DDTHH:MM:SSZ) nor a range A:B of them", spec);
    if (flags & VSV_TIMESEL_ONE)
        return fail(msg, cap, VSV_EINVAL, "'%s' is a range; one step is wanted here", spec);
    out->range = 1;
    out->exact = 1;
    if (!times)
        return 0;
    int a = 0, b = n - 1, ex;
    char text[96];
    int rc;
    if (ka != EL_EMPTY) {
        snprintf(text, sizeof text, "%.*s", (int)(colon - spec), spec);
        if ((rc = resolve(cal, times, n, ka, ia, ta, 1, text, &a, &ex, msg, cap)))
            return rc;
    }
    if (kb != EL_EMPTY) {
        snprintf(text, sizeof text, "%s", colon + 1);
        if ((rc = resolve(cal, times, n, kb, ib, tb, 2, text, &b, &ex, msg, cap)))
            return rc;
    }
    if (a > b) {
        char range[128];
        valid_range(cal, times, n, range, sizeof range);
        return fail(msg, cap, VSV_ERANGE, "'%s' selects no step (%s)", spec, range);
    }
    out->first = a;
    out->last = b;
    return 0;
}

/* One number at *p (digits only), advancing p; -1 when there is none or it
 * is out of range. */
static long long number(const char **p)
{
    if (**p < '0' || **p > '9')
        return -1;
    errno = 0;
    char *end;
    const long long v = strtoll(*p, &end, 10);
    if (errno)
        return -1;
    *p = end;
    return v;
}

/* ISO 8601 "PnDTnHnMnS" (and nW), at s after the P: seconds into *out; a
 * year or month (no fixed length) is VSV_ERANGE; any other fault
 * VSV_EINVAL. */
static int iso_duration(const char *s, int64_t *out)
{
    static const struct {
        char c;
        int time; /* after the T */
        long long mul;
    } units[] = {{'Y', 0, 0},    {'M', 0, 0},  {'W', 0, 604800}, {'D', 0, 86400},
                 {'H', 1, 3600}, {'M', 1, 60}, {'S', 1, 1}};
    const char *p = s;
    int at = 0, time = 0, parts = 0;
    long long sum = 0;
    while (*p) {
        if (*p == 'T' && !time) {
            time = 1, p++;
            if (!*p)
                return VSV_EINVAL; /* a T with nothing after it */
            continue;
        }
        const long long v = number(&p);
        if (v < 0)
            return VSV_EINVAL;
        int u = at;
        while (u < 7 && (units[u].c != *p || units[u].time != time))
            u++;
        if (u == 7)
            return VSV_EINVAL; /* no unit, or one out of order */
        if (!units[u].mul)
            return VSV_ERANGE;
        if (v > (INT64_MAX - sum) / units[u].mul)
            return VSV_EINVAL;
        sum += v * units[u].mul;
        at = u + 1, p++, parts++;
    }
    if (!parts)
        return VSV_EINVAL;
    *out = sum;
    return 0;
}

/* Ours: numbers with units, largest first, each once: "1d6h", "1h30m",
 * "90s", "10min". */
static int unit_duration(const char *s, int64_t *out)
{
    static const struct {
        const char *name;
        long long mul;
    } units[] = {{"d", 86400}, {"h", 3600}, {"min", 60}, {"m", 60}, {"s", 1}};
    const char *p = s;
    int at = 0, parts = 0;
    long long sum = 0;
    while (*p) {
        const long long v = number(&p);
        if (v < 0)
            return VSV_EINVAL;
        int u = at;
        while (u < 5 && strncmp(p, units[u].name, strlen(units[u].name)))
            u++;
        if (u == 5)
            return VSV_EINVAL; /* a bare number: seconds or minutes is a guess */
        if (v > (INT64_MAX - sum) / units[u].mul)
            return VSV_EINVAL;
        sum += v * units[u].mul;
        p += strlen(units[u].name);
        at = u + 1 + (u == 2); /* (after "min", not "m" again) */
        parts++;
    }
    if (!parts)
        return VSV_EINVAL;
    *out = sum;
    return 0;
}

int vsv_duration_parse(const char *s, int64_t *out)
{
    if (!s || !*s)
        return VSV_EINVAL;
    int64_t v;
    const int neg = s[0] == '-';
    const char *body = neg || s[0] == '+' ? s + 1 : s;
    const int rc = body[0] == 'P' ? iso_duration(body + 1, &v) : unit_duration(body, &v);
    if (rc)
        return rc;
    if (neg || v == 0 || v > VSV_DURATION_MAX)
        return VSV_ERANGE; /* a time step is more than nothing, and less than a file's span */
    *out = v;
    return 0;
}

const char *vsv_duration_why(const char *s)
{
    int64_t v;
    const int rc = vsv_duration_parse(s, &v);
    if (!rc)
        return "";
    const char *body = s && (s[0] == '-' || s[0] == '+') ? s + 1 : s ? s : "";
    if (rc == VSV_ERANGE && body[0] == 'P' && iso_duration(body + 1, &v) == VSV_ERANGE)
        return "years and months have no fixed length: give days, hours, minutes or seconds";
    if (rc == VSV_ERANGE && s[0] == '-')
        return "a negative duration: it must be more than zero";
    if (rc == VSV_ERANGE && (body[0] == 'P' ? iso_duration(body + 1, &v) : unit_duration(body, &v)) == 0 && v > 0)
        return "longer than 10000 years (no file spans more)";
    if (rc == VSV_ERANGE)
        return "a duration of zero: it must be more than zero";
    return "expected a duration with its units, largest first: 30s, 10m, 1h30m, 1d, or ISO 8601 PT1H30M";
}

void vsv_duration_format(int64_t d, char *buf, size_t cap)
{
    if (d > 0 && d % 86400 == 0)
        snprintf(buf, cap, "%lldd", (long long)(d / 86400));
    else if (d > 0 && d % 3600 == 0)
        snprintf(buf, cap, "%lldh", (long long)(d / 3600));
    else if (d > 0 && d % 60 == 0)
        snprintf(buf, cap, "%lldm", (long long)(d / 60));
    else
        snprintf(buf, cap, "%llds", (long long)d);
}
