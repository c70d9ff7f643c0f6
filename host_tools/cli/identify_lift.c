/* SPDX-License-Identifier: Apache-2.0 */
/* okid identify --decimation-method lift (identify_lift.h). */
#include "identify_lift.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli_common.h"

int identify_lift_record(int factor, record_reader *reader, record_columns *cols, record_scan *scan,
                         const char **input_names, lifted_names *names)
{
    const int r = cols->r, m = cols->m, rl = factor * r;
    if (rl > OKID_MAX_DIMENSION) {
        return cli_error(EXIT_USAGE, "--decimation-method lift with --decimation %d and %d inputs: %d lifted inputs, "
                         "at most %d (OKID_MAX_DIMENSION)", factor, r, rl, OKID_MAX_DIMENSION);
    }
    if (scan->samples < (size_t)factor) {
        return cli_error(EXIT_DATA, "--decimation-method lift: %zu samples, fewer than --decimation %d", scan->samples,
                         factor);
    }
    /* blocks of a multiple of K samples: only the record's last block leaves samples over */
    const size_t block = (size_t)(4096 / factor) * (size_t)factor;
    okid_real *u = malloc(sizeof(okid_real) * block * (size_t)r), *y = malloc(sizeof(okid_real) * block * (size_t)m);
    okid_real *ul = malloc(sizeof(okid_real) * block * (size_t)r), *yl = malloc(sizeof(okid_real) * block * (size_t)m);
    double *row = malloc(sizeof(double) * (size_t)(rl + m));
    FILE *lifted_file = tmpfile();
    char error[512];
    int rc = 0;
    size_t total = 0;
    if (u == NULL || y == NULL || ul == NULL || yl == NULL || row == NULL) {
        rc = cli_error(EXIT_DATA, "out of memory");
    } else if (lifted_file == NULL || fseek(reader->samples, 0, SEEK_SET) != 0) {
        rc = cli_error(EXIT_DATA, "cannot write a temporary file of samples: %s", strerror(errno));
    }
    while (rc == 0) {
        const long got = record_read_block(reader, cols, block, u, y, error, sizeof error);
        if (got < 0) {
            rc = cli_error(EXIT_DATA, "%s", error);
            break;
        }
        size_t lifted = 0;
        if (got == 0 || okid_lift(r, m, factor, (size_t)got, u, (size_t)r, y, (size_t)m, ul, yl, &lifted) != OKID_OK) {
            break;
        }
        for (size_t k = 0; k < lifted && rc == 0; ++k) {
            for (int i = 0; i < rl; ++i) row[i] = (double)ul[k * (size_t)rl + (size_t)i];
            for (int i = 0; i < m; ++i) row[rl + i] = (double)yl[k * (size_t)m + (size_t)i];
            if (fwrite(row, sizeof(double), (size_t)(rl + m), lifted_file) != (size_t)(rl + m)) {
                rc = cli_error(EXIT_DATA, "cannot write a temporary file of samples: %s", strerror(errno));
            }
        }
        total += lifted;
    }
    free(u), free(y), free(ul), free(yl), free(row);
    if (rc == 0 && fseek(lifted_file, 0, SEEK_SET) != 0) {
        rc = cli_error(EXIT_DATA, "cannot read a temporary file of samples: %s", strerror(errno));
    }
    if (rc != 0) {
        if (lifted_file != NULL) fclose(lifted_file);
        return rc;
    }
    fclose(reader->samples); /* the scan's tmpfile: removed on close */
    reader->samples = lifted_file;
    /* the lifted channels: inputs by offset, then the outputs; their RMS are the original channels' */
    double rms[2 * OKID_MAX_DIMENSION];
    memcpy(rms, scan->rms, sizeof rms);
    for (int j = 0; j < factor; ++j) {
        for (int i = 0; i < r; ++i) {
            const int c = j * r + i;
            snprintf(names->text[c], sizeof names->text[c], "%s[%d]", input_names[i], j);
            scan->rms[c] = rms[i];
        }
    }
    for (int i = 0; i < m; ++i) scan->rms[rl + i] = rms[r + i];
    for (int c = 0; c < rl; ++c) input_names[c] = names->text[c];
    for (int c = r; c < rl; ++c) cols->inputs[c] = cols->inputs[c % r];
    cols->r = rl;
    scan->samples = total;
    return 0;
}
