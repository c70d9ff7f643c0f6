/* SPDX-License-Identifier: Apache-2.0 */
/* What the okid subcommands share: exit codes, one-line errors; the enumerations'
   names and the integer parse come from the host library (config_names.h). */
#ifndef OKID_CLI_COMMON_H
#define OKID_CLI_COMMON_H

#include "config_names.h"
#include "okid/okid.h"

/* Exit codes: 0 success, 1 bad data or identification failure, 2 usage error. */
enum { EXIT_DATA = 1, EXIT_USAGE = 2 };

/* Prints "okid: <message>" on stderr (one line) and returns code. */
int cli_error(int code, const char *format, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

int identify_command(int argc, char **argv);
int simulate_command(int argc, char **argv);
int crlb_command(int argc, char **argv);

#endif
