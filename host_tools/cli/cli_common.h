/* SPDX-License-Identifier: Apache-2.0 */
/* What the okid subcommands share: exit codes, one-line errors, integer parsing, the names
   of the enumerations (docs/cli.md: the C enumerator's suffix in lower case). */
#ifndef OKID_CLI_COMMON_H
#define OKID_CLI_COMMON_H

#include "okid/okid.h"

/* Exit codes: 0 success, 1 bad data or identification failure, 2 usage error. */
enum { EXIT_DATA = 1, EXIT_USAGE = 2 };

/* Prints "okid: <message>" on stderr (one line) and returns code. */
int cli_error(int code, const char *format, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* Strict conversion of a whole decimal integer; 0 on success, -1 otherwise. */
int cli_parse_int(const char *text, int *out);

/* A named value of an enumeration; an alias (an old spelling) is accepted but never printed. */
typedef struct cli_name {
    const char *name;
    int value;
    int alias;
} cli_name;

/* The enumerations of okid_config, each ended by a {NULL} entry. */
extern const cli_name cli_sensing_names[], cli_realization_names[], cli_scaling_names[], cli_estimator_names[];

/* Value to name (the first entry that is not an alias); "?" when there is none. */
const char *cli_name_of(const cli_name *names, int value);
/* Name (or alias) to value; 0 on success, -1 when the name is not in the list. */
int cli_value_of(const cli_name *names, const char *text, int *value);

int identify_command(int argc, char **argv);
int simulate_command(int argc, char **argv);
int crlb_command(int argc, char **argv);

#endif
