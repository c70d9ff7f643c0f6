/* SPDX-License-Identifier: Apache-2.0 */
/* libFuzzer target: the CLI's CSV reader on arbitrary bytes (malformed headers, ragged rows, huge
   fields, non-UTF-8, empty files): an error message or a consistent table, never a crash. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "csv_reader.h"

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size);

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size)
{
    csv_table table;
    char error[256];
    if (csv_parse((const char *)data, size, &table, error, sizeof error) == 0) {
        if (table.num_columns < 1 || table.num_rows < 1 || table.names == NULL || table.values == NULL) abort();
        for (int j = 0; j < table.num_columns; ++j) {
            if (table.names[j] == NULL || table.names[j][0] == '\0' || csv_find_column(&table, table.names[j]) != j) {
                abort();
            }
        }
        volatile double sum = 0;
        for (size_t i = 0; i < table.num_rows * (size_t)table.num_columns; ++i) sum += table.values[i];
        (void)sum;
        csv_free(&table);
    } else if (memchr(error, '\0', sizeof error) == NULL || error[0] == '\0') {
        abort(); /* every failure says why */
    }
    return 0;
}
