/* See record_reader.h. */
#define _POSIX_C_SOURCE 200809L /* fseeko, ftello */
#include "record_reader.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static int fail(char *error, size_t size, const char *message)
{
    snprintf(error, size, "%s", message);
    return -1;
}

static int start_stream(record_reader *reader, FILE *in, FILE *copy, char *error, size_t error_size)
{
    if (csv_stream_open(&reader->stream, in, copy, error, error_size) != 0) {
        return -1;
    }
    free(reader->row);
    reader->row = malloc(sizeof(double) * (size_t)reader->stream.header.num_columns);
    return reader->row == NULL ? fail(error, error_size, "out of memory") : 0;
}

int record_open(record_reader *reader, const char *path, char *error, size_t error_size)
{
    memset(reader, 0, sizeof *reader);
    if (strcmp(path, "-") == 0) {
        reader->in = stdin;
    } else {
        reader->in = fopen(path, "rb");
        if (reader->in == NULL) {
            snprintf(error, error_size, "cannot open: %s", strerror(errno));
            return -1;
        }
        reader->owns_in = 1;
    }
    reader->start = (long long)ftello(reader->in);
    if (reader->start < 0 || fseeko(reader->in, (off_t)reader->start, SEEK_SET) != 0) {
        reader->spool = tmpfile(); /* a pipe: the scan keeps a copy on disk for the second pass */
        if (reader->spool == NULL) {
            snprintf(error, error_size, "cannot create a temporary file for the second pass: %s", strerror(errno));
            record_close(reader);
            return -1;
        }
    }
    if (start_stream(reader, reader->in, reader->spool, error, error_size) != 0) {
        record_close(reader);
        return -1;
    }
    return 0;
}

/* Running sum of squares scaled by the largest magnitude so far (no overflow or underflow). */
typedef struct square_sum {
    double scale, sum;
} square_sum;

static void square_sum_add(square_sum *s, double v)
{
    const double a = fabs(v);
    if (a == 0) {
        return;
    }
    if (a > s->scale) {
        const double ratio = s->scale / a;
        s->sum = 1 + s->sum * ratio * ratio;
        s->scale = a;
    } else {
        const double ratio = a / s->scale;
        s->sum += ratio * ratio;
    }
}

int record_scan_all(record_reader *reader, const record_columns *cols, record_scan *scan, char *error,
                    size_t error_size)
{
    memset(scan, 0, sizeof *scan);
    time_stamps_start(&scan->stamps, cols->time_unit);
    square_sum sums[2 * OKID_MAX_DIMENSION] = {{0, 0}};
    int rc;
    while ((rc = csv_stream_row(&reader->stream, reader->row, error, error_size)) == 1) {
        if (cols->time >= 0) {
            time_stamps_add(&scan->stamps, reader->row[cols->time]);
        }
        for (int i = 0; i < cols->r; ++i) square_sum_add(&sums[i], reader->row[cols->inputs[i]]);
        for (int a = 0; a < cols->m; ++a) square_sum_add(&sums[cols->r + a], reader->row[cols->outputs[a]]);
        ++scan->samples;
    }
    if (rc < 0) {
        return -1;
    }
    if (scan->samples == 0) {
        return fail(error, error_size, "the file has a header but no data rows");
    }
    for (int c = 0; c < cols->r + cols->m; ++c) {
        scan->rms[c] = sums[c].scale * sqrt(sums[c].sum / (double)scan->samples);
    }
    scan->bytes = reader->stream.bytes_read;
    return 0;
}

int record_rewind(record_reader *reader, char *error, size_t error_size)
{
    /* the first pass's header stays (the caller holds its names); the second one is the same text */
    csv_table header = reader->stream.header;
    memset(&reader->stream.header, 0, sizeof header);
    csv_stream_close(&reader->stream);
    FILE *source = reader->spool != NULL ? reader->spool : reader->in;
    const long long start = reader->spool != NULL ? 0 : reader->start;
    int rc = 0;
    if (fflush(source) != 0 || fseeko(source, (off_t)start, SEEK_SET) != 0) {
        snprintf(error, error_size, "cannot read the input a second time: %s", strerror(errno));
        rc = -1;
    } else {
        rc = start_stream(reader, source, NULL, error, error_size);
    }
    csv_free(&reader->stream.header);
    reader->stream.header = header;
    return rc;
}

long record_read_block(record_reader *reader, const record_columns *cols, size_t max, okid_real *u, okid_real *y,
                       char *error, size_t error_size)
{
    size_t k = 0;
    while (k < max) {
        const int rc = csv_stream_row(&reader->stream, reader->row, error, error_size);
        if (rc < 0) {
            return -1;
        }
        if (rc == 0) {
            break;
        }
        for (int i = 0; i < cols->r; ++i) u[k * (size_t)cols->r + (size_t)i] = (okid_real)reader->row[cols->inputs[i]];
        for (int a = 0; a < cols->m; ++a) y[k * (size_t)cols->m + (size_t)a] = (okid_real)reader->row[cols->outputs[a]];
        ++k;
    }
    return (long)k;
}

void record_close(record_reader *reader)
{
    csv_stream_close(&reader->stream);
    free(reader->row);
    reader->row = NULL;
    if (reader->spool != NULL) {
        fclose(reader->spool);
        reader->spool = NULL;
    }
    if (reader->owns_in && reader->in != NULL) {
        fclose(reader->in);
    }
    reader->in = NULL;
}
