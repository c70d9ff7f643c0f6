/* SPDX-License-Identifier: Apache-2.0 */
/* okid identify --decimation-method lift: the record lifted (okid_lift) before the identification. */
#ifndef OKID_CLI_IDENTIFY_LIFT_H
#define OKID_CLI_IDENTIFY_LIFT_H

#include "record_reader.h"

/* --decimation-method: the anti-alias filter of okid_config::decimation, or lifting */
enum { DECIMATION_FILTER = 0, DECIMATION_LIFT = 1 };

/* Room for the lifted inputs' names ("force[0]" ... "force[K-1]"). */
typedef struct lifted_names {
    char text[OKID_MAX_DIMENSION][72];
} lifted_names;

/*
 * Replace the scan's samples by the lifted record of factor K (okid_lift): K r inputs, input i
 * at offset j of each block of K samples becomes input j r + i named "<name>[j]" into names and
 * input_names, the outputs of each block's first sample; the last samples % K samples are
 * dropped; scan->samples and scan->rms follow. 0, or an exit code after one line on stderr
 * (K r above OKID_MAX_DIMENSION, fewer than K samples, the temporary file).
 */
int identify_lift_record(int factor, record_reader *reader, record_columns *cols, record_scan *scan,
                         const char **input_names, lifted_names *names);

#endif
