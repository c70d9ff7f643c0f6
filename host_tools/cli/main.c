/* SPDX-License-Identifier: Apache-2.0 */
/* okid: run the OKID/ERA identifier on CSV recordings, or write the paper's experiment as one. */
#include <stdio.h>
#include <string.h>

#include "cli_common.h"

static const char usage[] =
    "usage: okid identify [options] FILE.csv    identify a model and its modes from a recording\n"
    "       okid simulate [options]             write a simulated experiment (the paper's by default)\n"
    "       okid crlb [options]                 the Cramer-Rao bound of that experiment's modes\n"
    "       okid --version | --help\n"
    "\n"
    "Run 'okid identify --help', 'okid simulate --help' or 'okid crlb --help' for the options.\n"
    "Exit status: 0 success, 1 bad data or identification failure, 2 usage error.\n";

int main(int argc, char **argv)
{
    if (argc < 2) { /* like every other usage error: one line, so scripts can show it */
        return cli_error(EXIT_USAGE, "no command (usage: okid identify|simulate [options]; see 'okid --help')");
    }
    if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0) {
        fputs(usage, stdout);
        return 0;
    }
    if (strcmp(argv[1], "--version") == 0) {
        printf("okid %s\n", OKID_VERSION_STRING);
        return 0;
    }
    if (strcmp(argv[1], "identify") == 0) {
        return identify_command(argc - 1, argv + 1);
    }
    if (strcmp(argv[1], "simulate") == 0) {
        return simulate_command(argc - 1, argv + 1);
    }
    if (strcmp(argv[1], "crlb") == 0) {
        return crlb_command(argc - 1, argv + 1);
    }
    return cli_error(EXIT_USAGE, "unknown command '%s' (try 'okid --help')", argv[1]);
}
