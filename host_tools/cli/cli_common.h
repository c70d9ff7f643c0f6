/* What the okid subcommands share: exit codes, one-line errors, option value parsing. */
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

/* Strict conversions of a whole option value; 0 on success, -1 otherwise. */
int cli_parse_int(const char *text, int *out);
int cli_parse_real(const char *text, double *out);
/* Comma-separated finite reals; *count receives how many (at most max). */
int cli_parse_real_list(const char *text, double *out, int max, int *count);
/* acceleration|velocity|displacement */
int cli_parse_sensing(const char *text, okid_sensing *out);
const char *cli_sensing_name(okid_sensing sensing);

int identify_command(int argc, char **argv);
int simulate_command(int argc, char **argv);

#endif
