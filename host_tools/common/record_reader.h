/* SPDX-License-Identifier: Apache-2.0 */
/*
 * A recording for okid identify, read so that memory does not grow with the file: one pass
 * through csv_reader's stream parses and checks every row, counts the samples, follows the time
 * stamps and each channel's RMS, and keeps the chosen channels as binary doubles in a temporary
 * file; that comes before the workspace is allocated (the data's sufficiency is known first). The
 * samples then come back from the temporary file in blocks for okid_push_block: the text is
 * parsed once, and standard input or a pipe works like a file. Disk: (r + m) 8 bytes per sample.
 */
#ifndef OKID_CLI_RECORD_READER_H
#define OKID_CLI_RECORD_READER_H

#include <stdio.h>

#include "csv_reader.h"
#include "okid/okid.h"
#include "time_column.h"

/* Which columns are the inputs and outputs; time < 0 without a time column. */
typedef struct record_columns {
    int time;
    double time_unit; /* seconds per unit of the time column */
    int inputs[OKID_MAX_DIMENSION], outputs[OKID_MAX_DIMENSION];
    int r, m;
} record_columns;

/* What the scan found. */
typedef struct record_scan {
    size_t samples;
    time_stamps stamps;                    /* of the time column (count 0 without one) */
    double rms[2 * OKID_MAX_DIMENSION];    /* inputs, then outputs */
    unsigned long long bytes;              /* of CSV text read */
} record_scan;

typedef struct record_reader {
    FILE *in, *samples;    /* samples: the chosen channels of every row, r + m doubles each */
    int owns_in;
    csv_stream stream;
    double *row;           /* one row of every column, then one sample of the chosen channels */
} record_reader;

/* Opens path ("-": standard input) and reads its header (reader->stream.header). 0, or -1 with a message. */
int record_open(record_reader *reader, const char *path, char *error, size_t error_size);

/* The pass over the text: every row parsed and checked, counted, stamps and RMS, samples kept. 0, or -1. */
int record_scan_all(record_reader *reader, const record_columns *cols, record_scan *scan, char *error,
                    size_t error_size);

/* Up to max samples kept by the scan, in order, into u (r per sample) and y (m per sample):
   how many, 0 at the end, -1 with a message. */
long record_read_block(record_reader *reader, const record_columns *cols, size_t max, okid_real *u, okid_real *y,
                       char *error, size_t error_size);

void record_close(record_reader *reader);

#endif
