/* vsv_time.h — times, calendars and durations: the one time grammar of
 * every tool. Part of the public interface of vsv_format.h, which includes
 * it: the error codes VSV_E* its calls return are there. */
#ifndef VSV_TIME_H
#define VSV_TIME_H

#ifndef VSV_API_BEGIN /* (as vsv_format.h defines them) */
#define VSV_API_BEGIN _Pragma("GCC visibility push(default)")
#define VSV_API_END _Pragma("GCC visibility pop")
#endif

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

VSV_API_BEGIN

/* The times a file or stream may hold, seconds: about the years 1..9999
 * of every calendar (readers refuse others as damage, writers as misuse:
 * arithmetic on times stays far from overflow). */
#define VSV_TIME_MIN (-63000000000LL)
#define VSV_TIME_MAX 260000000000LL
#define VSV_TIME_OK(t) ((t) >= VSV_TIME_MIN && (t) <= VSV_TIME_MAX)

/* Times are integer seconds since 1970-01-01T00:00:00Z. Writes
 * "YYYY-MM-DDTHH:MM:SSZ" into buf (cap >= 32). */
void vsv_time_format(int64_t t, char *buf, size_t cap);
/* Parses "YYYY-MM-DD[T ]HH[:MM[:SS]][Z]" or "YYYY-MM-DD"; 0 or VSV_EINVAL. */
int vsv_time_parse(const char *s, int64_t *t);
/* Seconds of a civil date (proleptic Gregorian, UTC). */
int64_t vsv_time_from_civil(int year, int month, int day, int hour, int min, int sec);

/* Calendars, as CF names them: a model's clock. A file whose metadata has
 * the attribute "calendar" (VSV_ATTR_CALENDAR) naming one other than the
 * standard counts its times in it: seconds since 1970-01-01T00:00:00 of
 * that calendar (noleap: every year 365 days; all_leap: 366; 360_day:
 * twelve months of 30 days), so that every step stays its model date and
 * every interval its model length. The functions below take the calendar
 * (VSV_CAL_*); the vsv_time_* above are the standard one. */
enum { VSV_CAL_STANDARD = 0, VSV_CAL_NOLEAP = 1, VSV_CAL_ALL_LEAP = 2, VSV_CAL_360_DAY = 3 };
#define VSV_ATTR_CALENDAR "calendar"
/* The calendar of a CF name (standard, gregorian, proleptic_gregorian,
 * noleap, 365_day, all_leap, 366_day, 360_day; any case), or -1. */
int vsv_calendar_named(const char *name);
/* Its CF name ("standard", "noleap", "all_leap", "360_day"); static. */
const char *vsv_calendar_name(int cal);
int64_t vsv_cal_from_civil(int cal, int year, int month, int day, int hour, int min, int sec);
void vsv_cal_format(int cal, int64_t t, char *buf, size_t cap);
/* As vsv_time_parse, in the calendar: a day the calendar does not have
 * (2001-02-29 in noleap, a 31st in 360_day) is VSV_EINVAL. */
int vsv_cal_parse(int cal, const char *s, int64_t *t);

/* The one time grammar of every tool (--time, --times, the player's seek):
 *   ELEM := a 0-based step index | an ISO time (vsv_time_parse)
 *   SPEC := ELEM | [ELEM]:[ELEM]   (a range; both ends of one kind; ISO
 *                                   times may hold colons of their own)
 * One ELEM selects one step: an index exactly, a time the nearest step
 * (exact = 0 when no step is at that time; halfway goes to the earlier).
 * A range selects the first step at or after A to the last at or before B;
 * an empty end is the first / last step. An index outside 0..n-1 or a time
 * outside [times[0], times[n-1]] is VSV_ERANGE and a range that selects
 * nothing too, a malformed SPEC VSV_EINVAL; msg (caller buffer of cap
 * bytes) then says why and names the valid steps and times. With times
 * NULL only the syntax is checked. */
typedef struct vsv_timesel {
    int first, last; /* the selected steps, first <= last */
    int exact;       /* 0: a single time that fell between steps */
    int range;       /* 1: SPEC was a range */
} vsv_timesel;
enum { VSV_TIMESEL_ONE = 1 /* refuse ranges */ };
/* flags | VSV_TIMESEL_CAL(cal): ISO times are dates of that calendar. */
#define VSV_TIMESEL_CAL(cal) ((cal) << 4)
int vsv_timesel_parse(const char *spec, const int64_t *times, int n, int flags, vsv_timesel *out, char *msg,
                      size_t cap);
/* Parses a duration into seconds (> 0, at most VSV_DURATION_MAX): numbers with their units, largest
 * first and each once ("30s", "10m" or "10min", "1h30m", "2d6h"), or ISO
 * 8601's PnDTnHnMnS (and nW: "PT1H30M", "P1DT12H"). 0; VSV_ERANGE for a
 * duration of zero or less, or ISO years and months (no fixed length);
 * VSV_EINVAL for anything else (a bare number among it: seconds or
 * minutes would be a guess). */
int vsv_duration_parse(const char *s, int64_t *out);
/* The longest duration it takes: 10000 years (VSV_TIME_MAX - VSV_TIME_MIN
 * is about that). */
#define VSV_DURATION_MAX 316000000000LL
/* Why s is not a duration, in words ("" when it is): static text. */
const char *vsv_duration_why(const char *s);
/* Writes d seconds in the largest whole unit ("10m", "1h", "90s"). */
void vsv_duration_format(int64_t d, char *buf, size_t cap);

VSV_API_END

#ifdef __cplusplus
}
#endif

#endif
