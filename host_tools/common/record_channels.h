/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Which columns of a recording are its time, its inputs and its outputs, and its sample interval:
 * the rules of `okid identify --inputs/--outputs/--dt/--ignore-time-column` (docs/cli.md,
 * docs/robustness.md), written once for the CLI, the Python package and the fleet. Every function
 * returns 0, or RECORD_E_DATA / RECORD_E_USAGE (the CLI's exit codes) with one line in error.
 */
#ifndef OKID_HOST_RECORD_CHANNELS_H
#define OKID_HOST_RECORD_CHANNELS_H

#include <stddef.h>

#include "csv_reader.h"
#include "record_reader.h"

enum { RECORD_E_DATA = 1, RECORD_E_USAGE = 2 };

/* The time column (time_column.h) into *time_col, -1 without one; two of them are refused. */
int record_find_time_column(const csv_table *t, int *time_col, char *error, size_t error_size);

/*
 * cols from inputs and outputs as --inputs/--outputs take them: a count (the next columns not yet
 * taken; 0 inputs is an output-only record) or comma-separated names; a value that names a column is a name, one that could be a count
 * too is refused as ambiguous. inputs NULL: one input (the built-in count, never a name); outputs
 * NULL: every other column. The time column (time_col, -1: none) is never a channel.
 */
int record_choose_columns(const csv_table *t, int time_col, const char *inputs, const char *outputs,
                          record_columns *cols, char *error, size_t error_size);

/*
 * The sample interval [s] into *dt: the time column's uniform step (time_stamps_step), or the
 * given dt (have_dt), which must agree with the stamps unless ignore_time_column.
 */
int record_dt(const record_scan *scan, const csv_table *header, int time_col, int have_dt, double given_dt,
              int ignore_time_column, double *dt, char *error, size_t error_size);

#endif
