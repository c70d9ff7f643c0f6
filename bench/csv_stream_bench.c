/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The CLI's CSV reader alone on one file: parses every row through csv_stream_row (the pass okid
 * identify makes) and prints the rate as JSON: MB/s and rows (samples) per second of CPU time.
 * Usage: csv_stream_bench FILE.csv (scripts/bench_stream.sh writes the figures to docs/benchmarks.md).
 */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "csv_reader.h"

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: csv_stream_bench FILE.csv\n");
        return 2;
    }
    FILE *f = fopen(argv[1], "rb");
    if (f == NULL) {
        perror(argv[1]);
        return 1;
    }
    char error[512];
    const clock_t c0 = clock();
    csv_stream s;
    if (csv_stream_open(&s, f, error, sizeof error) != 0) {
        fprintf(stderr, "%s: %s\n", argv[1], error);
        return 1;
    }
    double *row = malloc(sizeof(double) * (size_t)s.header.num_columns);
    unsigned long long rows = 0;
    int rc;
    while (row != NULL && (rc = csv_stream_row(&s, row, error, sizeof error)) == 1) {
        ++rows;
    }
    const double cpu = (double)(clock() - c0) / CLOCKS_PER_SEC;
    if (row == NULL || rc < 0) {
        fprintf(stderr, "%s: %s\n", argv[1], row == NULL ? "out of memory" : error);
        return 1;
    }
    printf("{\"bytes\": %llu, \"rows\": %llu, \"columns\": %d, \"cpu_seconds\": %.3f, \"mb_per_s\": %.1f, "
           "\"rows_per_s\": %.0f}\n",
           s.bytes_read, rows, s.header.num_columns, cpu, (double)s.bytes_read / 1e6 / cpu, (double)rows / cpu);
    free(row);
    csv_stream_close(&s);
    fclose(f);
    return 0;
}
