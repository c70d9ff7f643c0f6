/* SPDX-License-Identifier: Apache-2.0 */
/* See record_channels.h. */
#include "record_channels.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "config_names.h"
#include "time_column.h"

/* The message into error; returns code. */
static int fail(char *error, size_t error_size, int code, const char *format, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;

static int fail(char *error, size_t error_size, int code, const char *format, ...)
{
    va_list args;
    va_start(args, format);
    vsnprintf(error, error_size, format, args);
    va_end(args);
    return code;
}

/*
 * Fills columns[] (room for OKID_MAX_DIMENSION) from NAMES or COUNT (a count starts at column
 * *next). used[] marks the columns already taken (the time column, the inputs): a column is an
 * input or an output, never both, and never twice. A value that names a column is a name; one
 * that could be a count too is refused (docs/cli.md). is_default: the built-in count, never a name.
 * fewest: the smallest count (0 for the inputs: an output-only record, docs/ambient.md).
 */
static int select_columns(const csv_table *t, const char *spec, int *next, char *used, int *columns, int *count,
                          const char *what, int is_default, int fewest, char *error, size_t error_size)
{
    int n = 0;
    *count = 0;
    int left = 0;
    for (int j = *next; j < t->num_columns; ++j) left += !used[j];
    int named = is_default ? -1 : csv_find_column(t, spec);
    int first_free = *next;
    while (first_free < t->num_columns && used[first_free]) ++first_free;
    if (cli_parse_int(spec, &n) == 0 && n == 1 && named == first_free) {
        named = -1; /* the count and the name take the same column */
    }
    if (cli_parse_int(spec, &n) == 0 && named >= 0 && !used[named] && n >= 1 && n <= left &&
        n <= OKID_MAX_DIMENSION) {
        return fail(error, error_size, RECORD_E_USAGE,
                         "--%s %s: ambiguous, both a count (the next %d column(s)) and the name of column %d ('%s'): "
                         "write --%s %s, (a trailing comma: a list of names) for that column, or name the columns "
                         "you mean (--%s A,B)",
                         what, spec, n, named + 1, t->names[named], what, spec, what);
    }
    if (cli_parse_int(spec, &n) == 0 && named < 0) {
        /* a count takes the next columns not yet taken (the time column, named inputs): never one twice */
        if (n < fewest || n > left) {
            return fail(error, error_size, RECORD_E_USAGE, "--%s %d: the file has %d column(s) after the ones already taken", what, n,
                             left);
        }
        if (n > OKID_MAX_DIMENSION) {
            return fail(error, error_size, RECORD_E_USAGE, "--%s %d: at most %d %s", what, n, OKID_MAX_DIMENSION, what);
        }
        for (int j = 0; j < n; ++j) {
            while (used[*next]) ++*next;
            used[*next] = 1;
            columns[j] = (*next)++;
        }
        *count = n;
        return 0;
    }
    char *copy = malloc(strlen(spec) + 1);
    if (copy == NULL) {
        return fail(error, error_size, RECORD_E_DATA, "out of memory");
    }
    strcpy(copy, spec);
    int rc = 0;
    for (char *name = strtok(copy, ","); name != NULL && rc == 0; name = strtok(NULL, ",")) {
        const int col = csv_find_column(t, name);
        if (col < 0) {
            rc = fail(error, error_size, RECORD_E_USAGE, "--%s: no column named '%s' in the file", what, name);
        } else if (used[col]) {
            rc = fail(error, error_size, RECORD_E_USAGE, "--%s: column '%s' is already %s", what, name,
                           time_column_unit(name) > 0 ? "the time column (see docs/robustness.md)" : "an input or an output");
        } else if (*count >= OKID_MAX_DIMENSION) {
            rc = fail(error, error_size, RECORD_E_USAGE, "--%s: at most %d %s", what, OKID_MAX_DIMENSION, what);
        } else {
            used[col] = 1;
            columns[(*count)++] = col;
        }
    }
    free(copy);
    if (rc == 0 && *count == 0) {
        rc = fail(error, error_size, RECORD_E_USAGE, "--%s: no column given", what);
    }
    return rc;
}

int record_find_time_column(const csv_table *t, int *time_col, char *error, size_t error_size)
{
    *time_col = -1;
    for (int j = 0; j < t->num_columns; ++j) {
        if (time_column_unit(t->names[j]) > 0) {
            if (*time_col >= 0) {
                return fail(error, error_size, RECORD_E_DATA, "two time columns ('%s' and '%s'): keep one (docs/robustness.md)",
                            t->names[*time_col], t->names[j]);
            }
            *time_col = j;
        }
    }
    return 0;
}

int record_choose_columns(const csv_table *t, int time_col, const char *inputs, const char *outputs,
                          record_columns *cols, char *error, size_t error_size)
{
    memset(cols, 0, sizeof *cols);
    cols->time = time_col;
    cols->time_unit = time_col >= 0 ? time_column_unit(t->names[time_col]) : 1;
    char *used = calloc((size_t)t->num_columns, 1);
    if (used == NULL) {
        return fail(error, error_size, RECORD_E_DATA, "out of memory");
    }
    if (time_col >= 0) used[time_col] = 1;
    int next = 0;
    int rc = select_columns(t, inputs ? inputs : "1", &next, used, cols->inputs, &cols->r, "inputs", inputs == NULL,
                            0, error, error_size);
    if (rc == 0 && outputs != NULL) {
        rc = select_columns(t, outputs, &next, used, cols->outputs, &cols->m, "outputs", 0, 1, error, error_size);
    } else if (rc == 0) {
        for (int j = 0; j < t->num_columns && rc == 0; ++j) {
            if (used[j]) continue;
            if (cols->m == OKID_MAX_DIMENSION) {
                rc = fail(error, error_size, RECORD_E_USAGE, "more than %d output columns: choose them with --outputs",
                          OKID_MAX_DIMENSION);
            } else {
                cols->outputs[cols->m++] = j;
            }
        }
        if (rc == 0 && cols->m == 0) {
            rc = fail(error, error_size, RECORD_E_USAGE, "no output columns left after the inputs");
        }
    }
    free(used);
    return rc;
}

int record_dt(const record_scan *scan, const csv_table *header, int time_col, int have_dt, double given_dt,
              int ignore_time_column, double *dt, char *error, size_t error_size)
{
    if (have_dt) {
        *dt = given_dt;
        /* --dt with a time column: they must agree (a wrong --dt scales every frequency) */
        if (time_col >= 0 && !ignore_time_column &&
            time_stamps_check_dt(&scan->stamps, header->names[time_col], given_dt, error, error_size) != 0) {
            return RECORD_E_USAGE;
        }
        return 0;
    }
    if (time_col < 0) {
        return fail(error, error_size, RECORD_E_USAGE,
                    "no time column (t, time or timestamp, with an optional unit: docs/robustness.md) in the file: "
                    "give --dt");
    }
    return time_stamps_step(&scan->stamps, header->names[time_col], dt, error, error_size) == 0 ? 0 : RECORD_E_DATA;
}
