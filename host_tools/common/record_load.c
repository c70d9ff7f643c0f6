/* SPDX-License-Identifier: Apache-2.0 */
/* See record_load.h. */
#include "record_load.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "record_channels.h"
#include "record_reader.h"

static char *copy_of(const char *text)
{
    char *copy = malloc(strlen(text) + 1);
    if (copy != NULL) strcpy(copy, text);
    return copy;
}

/* The scan's samples into data (names copied: the header goes with the reader). 0 or RECORD_E_DATA. */
static int keep_samples(record_reader *reader, const record_columns *cols, const record_scan *scan,
                        record_data *data, char *error, size_t error_size)
{
    const csv_table *header = &reader->stream.header;
    data->samples = scan->samples;
    data->r = cols->r;
    data->m = cols->m;
    data->u = malloc(sizeof(okid_real) * scan->samples * (size_t)cols->r);
    data->y = malloc(sizeof(okid_real) * scan->samples * (size_t)cols->m);
    int ok = data->u != NULL && data->y != NULL;
    for (int i = 0; ok && i < cols->r; ++i) ok = (data->input_names[i] = copy_of(header->names[cols->inputs[i]])) != NULL;
    for (int a = 0; ok && a < cols->m; ++a) ok = (data->output_names[a] = copy_of(header->names[cols->outputs[a]])) != NULL;
    if (!ok) {
        snprintf(error, error_size, "out of memory");
        return RECORD_E_DATA;
    }
    const long got = record_read_block(reader, cols, scan->samples, data->u, data->y, error, error_size);
    if (got < 0) {
        return RECORD_E_DATA;
    }
    if ((size_t)got != scan->samples) {
        snprintf(error, error_size, "the temporary file of samples holds %ld of %zu samples", got, scan->samples);
        return RECORD_E_DATA;
    }
    return 0;
}

int record_load(const char *path, const record_request *request, record_data *data, char *error, size_t error_size)
{
    memset(data, 0, sizeof *data);
    record_reader reader;
    if (record_open(&reader, path, error, error_size) != 0) {
        return RECORD_E_DATA;
    }
    const csv_table *header = &reader.stream.header;
    int time_col = -1;
    record_columns cols;
    record_scan scan;
    int rc = record_find_time_column(header, &time_col, error, error_size);
    if (rc == 0) {
        rc = record_choose_columns(header, time_col, request->inputs, request->outputs, &cols, error, error_size);
    }
    if (rc == 0 && record_scan_all(&reader, &cols, &scan, error, error_size) != 0) rc = RECORD_E_DATA;
    if (rc == 0) {
        rc = record_dt(&scan, header, time_col, request->have_dt, request->dt, request->ignore_time_column, &data->dt,
                       error, error_size);
    }
    if (rc == 0) rc = keep_samples(&reader, &cols, &scan, data, error, error_size);
    if (rc == 0 && time_col >= 0) {
        data->has_time = 1;
        data->first_stamp = scan.stamps.first * scan.stamps.unit;
    }
    record_close(&reader);
    if (rc != 0) record_data_free(data);
    return rc;
}

void record_data_free(record_data *data)
{
    free(data->u);
    free(data->y);
    for (int i = 0; i < OKID_MAX_DIMENSION; ++i) {
        free(data->input_names[i]);
        free(data->output_names[i]);
    }
    memset(data, 0, sizeof *data);
}
