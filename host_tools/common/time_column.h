/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The time column of a recording (docs/robustness.md, "CSV files"): which header names mark one,
 * in which unit, and the check that its stamps are uniform. A time column is never a data channel.
 */
#ifndef OKID_CLI_TIME_COLUMN_H
#define OKID_CLI_TIME_COLUMN_H

#include <stddef.h>

/*
 * Seconds per unit of the column named name, or 0 when it is not a time column. A time column is
 * named (case, blanks ignored) t, time, timestamp, time_stamp, zeit, elapsed, elapsed_time or
 * seconds, optionally followed by a unit: after ' ', '_', '-' or '/', or in [], () or {}:
 * s, sec, second(s); ms, msec, millisecond(s); us, µs, usec, microsecond(s); ns, nanosecond(s);
 * min, minute(s); h, hour(s). Without a unit: seconds.
 */
double time_column_unit(const char *name);

/* The stamps of one pass: first, last, smallest and largest step (with their data rows), largest |t|. */
typedef struct time_stamps {
    double unit;
    double first, last, previous, largest;
    double min_step, max_step;
    size_t count, min_row, max_row;
} time_stamps;

void time_stamps_start(time_stamps *ts, double unit);
void time_stamps_add(time_stamps *ts, double t);

/*
 * dt in seconds: the mean step (last - first) / (count - 1) times the unit, when every step lies
 * within 1e-4 dt + 8 eps max|t| of it (jitter of printed stamps, and the resolution of stamps far
 * from zero, like Unix epoch seconds). 0, or -1 with a message.
 */
int time_stamps_step(const time_stamps *ts, const char *name, double *dt, char *error, size_t error_size);

/*
 * --dt against the stamps: -1 with a message when dt [s] lies outside the steps the stamps take,
 * [min step - allowed, max step + allowed] times the unit, allowed as in time_stamps_step (for
 * uniform stamps: dt differs from their step by more than the jitter rule). 0 when it lies
 * within, or when the stamps cannot say (fewer than two, not increasing).
 */
int time_stamps_check_dt(const time_stamps *ts, const char *name, double dt, char *error, size_t error_size);

#endif
