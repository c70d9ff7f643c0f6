/* SPDX-License-Identifier: Apache-2.0 */
/* See record_reader.h. */
#include "record_reader.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

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
    if (csv_stream_open(&reader->stream, reader->in, error, error_size) != 0) {
        record_close(reader);
        return -1;
    }
    reader->row = malloc(sizeof(double) * (size_t)reader->stream.header.num_columns);
    if (reader->row == NULL) {
        snprintf(error, error_size, "out of memory");
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
    reader->samples = tmpfile();
    if (reader->samples == NULL) {
        snprintf(error, error_size, "cannot create a temporary file for the samples: %s", strerror(errno));
        return -1;
    }
    const int channels = cols->r + cols->m;
    double sample[2 * OKID_MAX_DIMENSION];
    square_sum sums[2 * OKID_MAX_DIMENSION] = {{0, 0}};
    int rc;
    while ((rc = csv_stream_row(&reader->stream, reader->row, error, error_size)) == 1) {
        if (cols->time >= 0) {
            time_stamps_add(&scan->stamps, reader->row[cols->time]);
        }
        for (int i = 0; i < cols->r; ++i) sample[i] = reader->row[cols->inputs[i]];
        for (int a = 0; a < cols->m; ++a) sample[cols->r + a] = reader->row[cols->outputs[a]];
        for (int c = 0; c < channels; ++c) square_sum_add(&sums[c], sample[c]);
        if (fwrite(sample, sizeof(double), (size_t)channels, reader->samples) != (size_t)channels) {
            snprintf(error, error_size, "cannot write the temporary file of samples: %s", strerror(errno));
            return -1;
        }
        ++scan->samples;
    }
    if (rc < 0) {
        return -1;
    }
    if (scan->samples == 0) {
        snprintf(error, error_size, "the file has a header but no data rows");
        return -1;
    }
    for (int c = 0; c < channels; ++c) {
        scan->rms[c] = sums[c].scale * sqrt(sums[c].sum / (double)scan->samples);
    }
    scan->bytes = reader->stream.bytes_read;
    if (fflush(reader->samples) != 0 || fseek(reader->samples, 0, SEEK_SET) != 0) {
        snprintf(error, error_size, "cannot read the temporary file of samples: %s", strerror(errno));
        return -1;
    }
    return 0;
}

long record_read_block(record_reader *reader, const record_columns *cols, size_t max, okid_real *u, okid_real *y,
                       char *error, size_t error_size)
{
    const size_t channels = (size_t)(cols->r + cols->m);
    double sample[2 * OKID_MAX_DIMENSION];
    size_t k = 0;
    for (; k < max; ++k) {
        const size_t got = fread(sample, sizeof(double), channels, reader->samples);
        if (got != channels) {
            if (ferror(reader->samples) || got != 0) {
                snprintf(error, error_size, "cannot read the temporary file of samples: %s", strerror(errno));
                return -1;
            }
            break;
        }
        for (int i = 0; i < cols->r; ++i) u[k * (size_t)cols->r + (size_t)i] = (okid_real)sample[i];
        for (int a = 0; a < cols->m; ++a) y[k * (size_t)cols->m + (size_t)a] = (okid_real)sample[cols->r + a];
    }
    return (long)k;
}

void record_close(record_reader *reader)
{
    csv_stream_close(&reader->stream);
    free(reader->row);
    reader->row = NULL;
    if (reader->samples != NULL) {
        fclose(reader->samples); /* a tmpfile: removed on close */
        reader->samples = NULL;
    }
    if (reader->owns_in && reader->in != NULL) {
        fclose(reader->in);
    }
    reader->in = NULL;
}
