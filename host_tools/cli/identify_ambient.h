/* SPDX-License-Identifier: Apache-2.0 */
/* okid identify --inputs 0: output-only identification (identify_ambient.c). */
#ifndef OKID_CLI_IDENTIFY_AMBIENT_H
#define OKID_CLI_IDENTIFY_AMBIENT_H

#include "identify_options.h"
#include "record_reader.h"

/* Identify the scanned record's outputs (cols->r == 0) at dt and print the result; the exit code. */
int identify_ambient(const identify_options *o, record_reader *reader, const record_columns *cols,
                     const record_scan *scan, const char *const *output_names, double dt);

#endif
