/* SPDX-License-Identifier: Apache-2.0 */
/* See time_column.h. */
#include "time_column.h"

#include <ctype.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

/* name lower-cased without blanks into out (size bytes); 0 when it does not fit. */
static int squeeze(const char *name, char *out, size_t size)
{
    size_t n = 0;
    for (const char *p = name; *p != '\0'; ++p) {
        if (*p == ' ' || *p == '\t') {
            continue;
        }
        if (n + 1 >= size) {
            return 0;
        }
        out[n++] = (char)tolower((unsigned char)*p);
    }
    out[n] = '\0';
    return 1;
}

/* Seconds per unit of the unit's name, or 0. */
static double unit_seconds(const char *unit)
{
    static const struct {
        const char *name;
        double seconds;
    } units[] = {{"s", 1},           {"sec", 1},          {"secs", 1},          {"second", 1},     {"seconds", 1},
                 {"ms", 1e-3},       {"msec", 1e-3},      {"millisecond", 1e-3}, {"milliseconds", 1e-3},
                 {"us", 1e-6},       {"\xc2\xb5s", 1e-6}, {"\xce\xbcs", 1e-6},  {"usec", 1e-6},
                 {"microsecond", 1e-6}, {"microseconds", 1e-6}, {"ns", 1e-9},   {"nanosecond", 1e-9},
                 {"nanoseconds", 1e-9}, {"min", 60},      {"minute", 60},       {"minutes", 60},
                 {"h", 3600},        {"hour", 3600},      {"hours", 3600}};
    for (size_t i = 0; i < sizeof units / sizeof units[0]; ++i) {
        if (strcmp(unit, units[i].name) == 0) {
            return units[i].seconds;
        }
    }
    return 0;
}

/* The unit after a base name: "", "_ms", "/s", "-s", "[ms]", "(s)", "{s}" (blanks already gone). */
static double unit_suffix(const char *rest)
{
    if (*rest == '\0') {
        return 1;
    }
    static const char *const open = "[({", *const close = "])}";
    const char *bracket = strchr(open, *rest);
    if (bracket != NULL) {
        const size_t len = strlen(rest);
        char unit[32];
        if (len < 3 || len - 2 >= sizeof unit || rest[len - 1] != close[bracket - open]) {
            return 0;
        }
        memcpy(unit, rest + 1, len - 2);
        unit[len - 2] = '\0';
        return unit_seconds(unit);
    }
    if (*rest == '_' || *rest == '-' || *rest == '/') {
        return unit_seconds(rest + 1);
    }
    return 0;
}

double time_column_unit(const char *name)
{
    static const char *const bases[] = {"timestamp", "time_stamp", "elapsed_time", "elapsed", "seconds",
                                        "time", "zeit", "t"};
    char squeezed[64];
    if (!squeeze(name, squeezed, sizeof squeezed)) {
        return 0;
    }
    for (size_t i = 0; i < sizeof bases / sizeof bases[0]; ++i) {
        const size_t len = strlen(bases[i]);
        if (strncmp(squeezed, bases[i], len) == 0) {
            const double unit = unit_suffix(squeezed + len);
            if (unit > 0) {
                return strcmp(bases[i], "seconds") == 0 && squeezed[len] != '\0' ? 0 : unit;
            }
        }
    }
    return 0;
}

void time_stamps_start(time_stamps *ts, double unit)
{
    memset(ts, 0, sizeof *ts);
    ts->unit = unit;
}

void time_stamps_add(time_stamps *ts, double t)
{
    if (ts->count == 0) {
        ts->first = t;
    } else {
        const double step = t - ts->previous;
        if (ts->count == 1 || step < ts->min_step) {
            ts->min_step = step;
            ts->min_row = ts->count + 1; /* data rows counted from 1 */
        }
        if (ts->count == 1 || step > ts->max_step) {
            ts->max_step = step;
            ts->max_row = ts->count + 1;
        }
    }
    ts->largest = fmax(ts->largest, fabs(t));
    ts->previous = ts->last = t;
    ++ts->count;
}

int time_stamps_step(const time_stamps *ts, const char *name, double *dt, char *error, size_t error_size)
{
    if (ts->count < 2) {
        snprintf(error, error_size, "one row is not enough to find dt from the time column '%s'", name);
        return -1;
    }
    if (!(ts->min_step > 0)) {
        snprintf(error, error_size, "the time column '%s' does not increase (data row %zu steps by %g)", name,
                 ts->min_row, ts->min_step);
        return -1;
    }
    const double mean = (ts->last - ts->first) / (double)(ts->count - 1);
    /* 1e-4: stamps printed with a few digits jitter, a real gap or a resampling is far larger;
       8 eps max|t|: two stamps far from zero (epoch seconds) differ by no better than their ulps */
    const double allowed = 1e-4 * mean + 8 * DBL_EPSILON * ts->largest;
    const int low = mean - ts->min_step > ts->max_step - mean;
    const double worst = low ? ts->min_step : ts->max_step;
    if (fabs(worst - mean) > allowed) {
        snprintf(error, error_size,
                 "the time column '%s' is not uniform (data row %zu steps by %.9g, the mean step is %.9g, "
                 "%.3g allowed): resample it or give --dt",
                 name, low ? ts->min_row : ts->max_row, worst, mean, allowed);
        return -1;
    }
    *dt = mean * ts->unit;
    return 0;
}

int time_stamps_check_dt(const time_stamps *ts, const char *name, double dt, char *error, size_t error_size)
{
    if (ts->count < 2 || !(ts->min_step > 0)) {
        return 0;
    }
    const double mean = (ts->last - ts->first) / (double)(ts->count - 1);
    const double allowed = 1e-4 * mean + 8 * DBL_EPSILON * ts->largest; /* time_stamps_step's jitter rule */
    const double low = (ts->min_step - allowed) * ts->unit, high = (ts->max_step + allowed) * ts->unit;
    if (dt >= low && dt <= high) {
        return 0;
    }
    if (ts->min_step == ts->max_step || high - low <= 4 * allowed * ts->unit) {
        snprintf(error, error_size,
                 "--dt %.9g disagrees with the time column '%s', whose stamps step by %.9g s (%.3g s allowed): "
                 "drop --dt, or give --ignore-time-column to use --dt anyway",
                 dt, name, mean * ts->unit, allowed * ts->unit);
    } else {
        snprintf(error, error_size,
                 "--dt %.9g disagrees with the time column '%s', whose stamps step by %.9g to %.9g s: "
                 "drop --dt, or give --ignore-time-column to use --dt anyway",
                 dt, name, ts->min_step * ts->unit, ts->max_step * ts->unit);
    }
    return -1;
}
