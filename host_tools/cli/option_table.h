/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Option tables of the okid subcommands: one entry per option gives its name, old spellings, value
 * type, valid range, default (read from the command's default option struct) and help. The parser,
 * the value checks, the refusals and the usage text are all made from it.
 */
#ifndef OKID_CLI_OPTION_TABLE_H
#define OKID_CLI_OPTION_TABLE_H

#include <stddef.h>
#include <stdio.h>

#include "cli_common.h"

typedef enum cli_option_kind {
    CLI_FLAG,      /* no value; sets an int to 1 */
    CLI_SWITCH,    /* an int 0 or 1: "--name" alone is 1, "--name=0" and "--name=1" say it */
    CLI_INT,       /* int in [min, max] */
    CLI_REAL,      /* finite real in the range; stored as a double or a float (size) */
    CLI_ENUM,      /* one of the names (stored as an int) */
    CLI_TEXT,      /* the argument as given (checked by the command) */
    CLI_REAL_LIST  /* comma-separated finite reals, at most max of them, each in the range */
} cli_option_kind;

/* Real ranges: [min, max] unless these say otherwise. */
enum {
    CLI_MIN_OPEN = 1,  /* (min, ... */
    CLI_MAX_OPEN = 2,  /* ..., max) */
    CLI_NO_MAX = 4,    /* no upper bound */
    CLI_ZERO_TOO = 8   /* 0 is valid besides the range (it selects an automatic value) */
};

typedef struct cli_option {
    const char *name;      /* "forgetting-factor": the flag is "--forgetting-factor" */
    const char *alias;     /* an old spelling kept for one release ("forgetting"), or NULL */
    cli_option_kind kind;
    size_t offset;         /* where the value goes in the command's option struct */
    size_t size;           /* CLI_REAL: sizeof the stored real (float or double) */
    size_t count_offset;   /* CLI_REAL_LIST: the int that receives the count */
    double min, max;       /* valid range (CLI_REAL_LIST: max is the largest count; give CLI_NO_MAX) */
    unsigned range;        /* CLI_MIN_OPEN | ... for CLI_REAL and CLI_REAL_LIST */
    const cli_name *names; /* CLI_ENUM: the values, ended by a {NULL} entry */
    const char *field;     /* the okid_config field it sets (docs/cli.md), NULL for the command's own */
    const char *metavar;   /* "L" in "--forgetting-factor L" */
    const char *note;      /* said after the range in refusals and usage ("0 = automatic"), or NULL */
    const char *default_text; /* the default in words ("from the time column"); NULL: read from the defaults */
    const char *help;
} cli_option;

typedef struct cli_command {
    const char *name;              /* "identify" */
    const char *synopsis;          /* "usage: okid identify [options] FILE.csv ..." and the text before the options */
    const char *epilogue;          /* after the options (exit status) */
    const cli_option *options;     /* ended by a {NULL} entry */
    const void *defaults;          /* the option struct as it is before parsing (for "(default ...)") */
    int max_operands;              /* arguments that are not options (FILE.csv); 0 for none */
    const char *operand;           /* what an operand is ("input file") */
} cli_command;

/*
 * Parses argv[1..argc-1] into opts (which holds the defaults on entry). Operands (arguments not
 * starting with '-', or "-") go to operands[] (room for max_operands). "--name=value" and
 * "--name value" are both accepted. "--help" prints the usage and exits 0. Returns 0, or
 * EXIT_USAGE after one line on stderr naming the option, the value and the valid range.
 */
int cli_parse_options(const cli_command *cmd, int argc, char **argv, void *opts, const char **operands,
                      int *num_operands);

/* The usage text: synopsis, one entry per option with its range and default, epilogue. */
void cli_print_usage(const cli_command *cmd, FILE *out);

/* The valid range of an option as text ("(0, 1]", "1..1000", "none|auto"), into buf. */
const char *cli_option_range(const cli_option *opt, char *buf, size_t size);

#endif
