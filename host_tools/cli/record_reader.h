/*
 * A recording for okid identify, read twice through csv_reader's stream so that memory does not
 * grow with the file: a scan (rows, time stamps, each channel's RMS) that comes before the
 * workspace is allocated, then the samples again in blocks for okid_push_block. A file is read
 * twice; standard input or a pipe is copied to a temporary file during the scan (disk, not memory).
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
    unsigned long long bytes;
} record_scan;

typedef struct record_reader {
    FILE *in, *spool;      /* spool: the copy of a stream that cannot seek, read by the second pass */
    long long start;       /* offset of the first byte in a seekable input */
    int owns_in;
    csv_stream stream;
    double *row;           /* one row of every column */
} record_reader;

/* Opens path ("-": standard input) and reads its header (reader->stream.header). 0, or -1 with a message. */
int record_open(record_reader *reader, const char *path, char *error, size_t error_size);

/* The first pass: every row parsed and checked, counted, time stamps and channel RMS. 0, or -1. */
int record_scan_all(record_reader *reader, const record_columns *cols, record_scan *scan, char *error,
                    size_t error_size);

/* The second pass from the first data row. 0, or -1 with a message. */
int record_rewind(record_reader *reader, char *error, size_t error_size);

/* Up to max samples of the second pass into u (r per sample) and y (m per sample): how many, 0 at the end, -1. */
long record_read_block(record_reader *reader, const record_columns *cols, size_t max, okid_real *u, okid_real *y,
                       char *error, size_t error_size);

void record_close(record_reader *reader);

#endif
