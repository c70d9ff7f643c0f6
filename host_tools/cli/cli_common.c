/* SPDX-License-Identifier: Apache-2.0 */
/* See cli_common.h. */
#include "cli_common.h"

#include <stdarg.h>
#include <stdio.h>

int cli_error(int code, const char *format, ...)
{
    va_list args;
    va_start(args, format);
    fputs("okid: ", stderr);
    vfprintf(stderr, format, args);
    fputc('\n', stderr);
    va_end(args);
    return code;
}
