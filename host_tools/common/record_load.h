/* SPDX-License-Identifier: Apache-2.0 */
/*
 * A whole recording into memory by the CLI's rules (record_reader.h, record_channels.h): the
 * Python package's okid.read_record and the fleet's CSV records read through it, so that a file
 * the CLI refuses is refused there with the same line, and one it reads gives the same samples.
 */
#ifndef OKID_HOST_RECORD_LOAD_H
#define OKID_HOST_RECORD_LOAD_H

#include <stddef.h>

#include "okid/okid.h"

/* What to read: as `okid identify --inputs/--outputs/--dt/--ignore-time-column` take them. */
typedef struct record_request {
    const char *inputs;     /* NULL: one input (the first column that is not the time column) */
    const char *outputs;    /* NULL: every other column */
    int have_dt;            /* dt given */
    double dt;              /* [s] */
    int ignore_time_column; /* the given dt wins over the stamps */
} record_request;

typedef struct record_data {
    size_t samples;
    int r, m;
    double dt;                                /* [s] */
    int has_time;                             /* the file has a time column */
    double first_stamp;                       /* its first stamp [s] (0 without one) */
    okid_real *u, *y;                         /* samples x r, samples x m, row-major */
    char *input_names[OKID_MAX_DIMENSION], *output_names[OKID_MAX_DIMENSION];
} record_data;

/* Reads path into *data (record_data_free releases it). 0, or RECORD_E_DATA / RECORD_E_USAGE with
   one line in error (the file is not named: the caller does). */
int record_load(const char *path, const record_request *request, record_data *data, char *error, size_t error_size);

void record_data_free(record_data *data);

#endif
