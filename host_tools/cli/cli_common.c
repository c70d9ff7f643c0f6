/* See cli_common.h. */
#include "cli_common.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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

int cli_parse_int(const char *text, int *out)
{
    char *end = NULL;
    errno = 0;
    const long v = strtol(text, &end, 10);
    if (end == text || *end != '\0' || errno != 0 || v < INT_MIN || v > INT_MAX) {
        return -1;
    }
    *out = (int)v;
    return 0;
}

int cli_parse_real(const char *text, double *out)
{
    char *end = NULL;
    errno = 0;
    const double v = strtod(text, &end);
    if (end == text || *end != '\0' || !isfinite(v)) {
        return -1;
    }
    *out = v;
    return 0;
}

int cli_parse_real_list(const char *text, double *out, int max, int *count)
{
    *count = 0;
    const char *p = text;
    for (;;) {
        char *end = NULL;
        errno = 0;
        const double v = strtod(p, &end);
        if (end == p || !isfinite(v) || *count >= max || (*end != ',' && *end != '\0')) {
            return -1;
        }
        out[(*count)++] = v;
        if (*end == '\0') {
            return 0;
        }
        p = end + 1;
    }
}

int cli_parse_sensing(const char *text, okid_sensing *out)
{
    static const char *const names[3] = {"displacement", "velocity", "acceleration"};
    for (int i = 0; i < 3; ++i) {
        if (strcmp(text, names[i]) == 0) {
            *out = (okid_sensing)i;
            return 0;
        }
    }
    return -1;
}

const char *cli_sensing_name(okid_sensing sensing)
{
    switch (sensing) {
    case OKID_SENSING_DISPLACEMENT: return "displacement";
    case OKID_SENSING_VELOCITY: return "velocity";
    default: return "acceleration";
    }
}
