/* SPDX-License-Identifier: Apache-2.0 */
/* See option_table.h. */
#include "option_table.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The shortest %g form that reads back as the same double: 1e-10, not 1.0000000000000000364e-10. */
static const char *shortest(double v, char *buf, size_t size)
{
    if (v == floor(v) && fabs(v) < 1e15) {
        snprintf(buf, size, "%.0f", v); /* 20, not 2e+01 */
        return buf;
    }
    for (int digits = 1; digits <= 17; ++digits) {
        snprintf(buf, size, "%.*g", digits, v);
        if (strtod(buf, NULL) == v) {
            break;
        }
    }
    return buf;
}

static int real_in_range(const cli_option *opt, double v)
{
    if (v == 0 && (opt->range & CLI_ZERO_TOO)) {
        return 1;
    }
    const int above = (opt->range & CLI_MIN_OPEN) ? v > opt->min : v >= opt->min;
    const int below = (opt->range & CLI_NO_MAX) || ((opt->range & CLI_MAX_OPEN) ? v < opt->max : v <= opt->max);
    return above && below;
}

const char *cli_option_range(const cli_option *opt, char *buf, size_t size)
{
    char lo[32], hi[32];
    size_t used = 0;
    buf[0] = '\0';
    switch (opt->kind) {
    case CLI_FLAG:
        snprintf(buf, size, "no value");
        break;
    case CLI_SWITCH:
        snprintf(buf, size, "0 or 1");
        break;
    case CLI_INT:
        snprintf(buf, size, "%d..%d", (int)opt->min, (int)opt->max);
        break;
    case CLI_ENUM:
        for (const cli_name *n = opt->names; n->name != NULL && used < size; ++n) {
            if (!n->alias) {
                used += (size_t)snprintf(buf + used, size - used, "%s%s", used ? "|" : "", n->name);
            }
        }
        break;
    case CLI_TEXT:
        break;
    case CLI_REAL:
    case CLI_REAL_LIST:
        if (opt->kind == CLI_REAL_LIST) {
            used = (size_t)snprintf(buf, size, "1..%d values, each ", (int)opt->max);
        }
        if (opt->kind == CLI_REAL && (opt->range & CLI_ZERO_TOO)) {
            used += (size_t)snprintf(buf + used, size - used, "0 or ");
        }
        shortest(opt->min, lo, sizeof lo);
        if (opt->range & CLI_NO_MAX) {
            snprintf(buf + used, size - used, "%s %s", (opt->range & CLI_MIN_OPEN) ? ">" : ">=", lo);
        } else {
            snprintf(buf + used, size - used, "%c%s, %s%c", (opt->range & CLI_MIN_OPEN) ? '(' : '[', lo,
                     shortest(opt->max, hi, sizeof hi), (opt->range & CLI_MAX_OPEN) ? ')' : ']');
        }
        break;
    }
    return buf;
}

static const cli_option *find_option(const cli_option *options, const char *name, size_t length)
{
    for (const cli_option *o = options; o->name != NULL; ++o) {
        if ((strlen(o->name) == length && strncmp(o->name, name, length) == 0) ||
            (o->alias != NULL && strlen(o->alias) == length && strncmp(o->alias, name, length) == 0)) {
            return o;
        }
    }
    return NULL;
}

/* One line: the flag as typed, the value, what is wrong, the valid range and its note. */
static int refuse(const cli_option *opt, const char *flag, const char *value, const char *why)
{
    char range[256];
    cli_option_range(opt, range, sizeof range);
    return cli_error(EXIT_USAGE, "bad value '%s' for %s%s%s%s: %s; valid: %s%s%s%s", value, flag,
                     opt->field ? " (okid_config." : "", opt->field ? opt->field : "", opt->field ? ")" : "", why,
                     range, opt->note ? " (" : "", opt->note ? opt->note : "", opt->note ? ")" : "");
}

/* A real spelled by text up to stop (any length), finite and representable: an underflow to 0 is not 0. */
static const char *read_real(const char *text, const char *stop, double *out)
{
    char *end = NULL;
    errno = 0;
    const double v = strtod(text, &end);
    if (end == text || end != stop) {
        return "not a number";
    }
    if (!isfinite(v)) {
        return "not a finite number";
    }
    if (errno == ERANGE && v == 0) {
        return "too small to be represented (it would read as 0)";
    }
    *out = v;
    return NULL;
}

static const char *store_real(const cli_option *opt, double v, void *where)
{
    if (!real_in_range(opt, v)) {
        return "out of range";
    }
    if (opt->size == sizeof(float)) {
        const float f = (float)v; /* the float build: the stored value must be in range too */
        if (!real_in_range(opt, (double)f)) {
            return "out of range in single precision";
        }
        memcpy(where, &f, sizeof f);
    } else {
        memcpy(where, &v, sizeof v);
    }
    return NULL;
}

static int set_value(const cli_option *opt, const char *flag, const char *value, void *opts)
{
    char *const where = (char *)opts + opt->offset;
    const char *why = NULL;
    switch (opt->kind) {
    case CLI_FLAG:
        return cli_error(EXIT_USAGE, "%s takes no value (got '%s')", flag, value);
    case CLI_SWITCH:
    case CLI_INT: {
        char *end = NULL;
        errno = 0;
        const long v = strtol(value, &end, 10);
        if (end == value || *end != '\0') {
            why = "not an integer";
        } else if (errno == ERANGE || v < (long)opt->min || v > (long)opt->max) {
            why = "out of range";
        } else {
            const int i = (int)v;
            memcpy(where, &i, sizeof i);
        }
        break;
    }
    case CLI_REAL: {
        double v = 0;
        why = read_real(value, value + strlen(value), &v);
        if (why == NULL) why = store_real(opt, v, where);
        break;
    }
    case CLI_ENUM: {
        int v = 0;
        if (cli_value_of(opt->names, value, &v) != 0) {
            why = "unknown name";
        } else {
            memcpy(where, &v, sizeof v);
        }
        break;
    }
    case CLI_TEXT:
        memcpy(where, &value, sizeof value);
        break;
    case CLI_REAL_LIST: {
        double *values = (double *)(void *)where;
        int count = 0;
        for (const char *p = value; why == NULL;) {
            const char *comma = strchr(p, ',');
            double v = 0;
            if (count >= (int)opt->max) {
                why = "too many values";
            } else {
                why = read_real(p, comma ? comma : p + strlen(p), &v);
                if (why == NULL && !real_in_range(opt, v)) why = "a value out of range";
                if (why == NULL) values[count++] = v;
            }
            if (comma == NULL) break;
            p = comma + 1;
        }
        if (why == NULL) memcpy((char *)opts + opt->count_offset, &count, sizeof count);
        break;
    }
    }
    return why ? refuse(opt, flag, value, why) : 0;
}

int cli_parse_options(const cli_command *cmd, int argc, char **argv, void *opts, const char **operands,
                      int *num_operands)
{
    *num_operands = 0;
    for (int i = 1; i < argc; ++i) {
        const char *arg = argv[i];
        if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0) {
            cli_print_usage(cmd, stdout);
            exit(0);
        }
        if (arg[0] != '-' || strcmp(arg, "-") == 0) {
            if (*num_operands >= cmd->max_operands) {
                return cmd->max_operands == 0
                           ? cli_error(EXIT_USAGE, "unexpected argument '%s' (see 'okid %s --help')", arg, cmd->name)
                           : cli_error(EXIT_USAGE, "more than one %s ('%s' and '%s')", cmd->operand, operands[0], arg);
            }
            operands[(*num_operands)++] = arg;
            continue;
        }
        const char *name = arg + 2, *equals = strchr(arg, '=');
        const size_t length = equals ? (size_t)(equals - name) : strlen(name);
        const cli_option *opt = strncmp(arg, "--", 2) == 0 ? find_option(cmd->options, name, length) : NULL;
        if (opt == NULL) {
            return cli_error(EXIT_USAGE, "unknown option '%s' (see 'okid %s --help')", arg, cmd->name);
        }
        char flag[64];
        snprintf(flag, sizeof flag, "--%.*s", (int)(length < 60 ? length : 60), name);
        const char *value = equals ? equals + 1 : NULL;
        if (value == NULL && (opt->kind == CLI_FLAG || opt->kind == CLI_SWITCH)) {
            const int one = 1;
            memcpy((char *)opts + opt->offset, &one, sizeof one);
            continue;
        }
        if (value == NULL) {
            if (i + 1 >= argc) {
                return cli_error(EXIT_USAGE, "option %s needs a value (see 'okid %s --help')", flag, cmd->name);
            }
            value = argv[++i];
        }
        const int rc = set_value(opt, flag, value, opts);
        if (rc != 0) {
            return rc;
        }
    }
    return 0;
}

/* The default as the option struct before parsing holds it, or the option's words for it. */
static const char *default_text(const cli_command *cmd, const cli_option *opt, char *buf, size_t size)
{
    const char *const where = (const char *)cmd->defaults + opt->offset;
    int i = 0;
    buf[0] = '\0';
    if (opt->default_text != NULL) {
        return opt->default_text;
    }
    switch (opt->kind) {
    case CLI_SWITCH:
    case CLI_INT:
        memcpy(&i, where, sizeof i);
        snprintf(buf, size, "%d", i);
        break;
    case CLI_REAL:
        if (opt->size == sizeof(float)) {
            float f;
            memcpy(&f, where, sizeof f);
            shortest((double)f, buf, size);
        } else {
            double d;
            memcpy(&d, where, sizeof d);
            shortest(d, buf, size);
        }
        break;
    case CLI_ENUM:
        memcpy(&i, where, sizeof i);
        snprintf(buf, size, "%s", cli_name_of(opt->names, i));
        break;
    case CLI_REAL_LIST: {
        const double *values = (const double *)(const void *)where;
        size_t used = 0;
        memcpy(&i, (const char *)cmd->defaults + opt->count_offset, sizeof i);
        for (int k = 0; k < i && used < size; ++k) {
            char one[32];
            shortest(values[k], one, sizeof one);
            used += (size_t)snprintf(buf + used, size - used, "%s%s", k ? "," : "", one);
        }
        break;
    }
    case CLI_FLAG:
    case CLI_TEXT:
        return NULL;
    }
    return buf;
}

/* Help text lines after the first are indented under it. */
static void print_indented(FILE *out, const char *text, int indent)
{
    for (const char *p = text; *p != '\0'; ++p) {
        fputc(*p, out);
        if (*p == '\n' && p[1] != '\0') fprintf(out, "%*s", indent, "");
    }
}

void cli_print_usage(const cli_command *cmd, FILE *out)
{
    enum { COLUMN = 27 };
    fputs(cmd->synopsis, out);
    for (const cli_option *o = cmd->options; o->name != NULL; ++o) {
        char head[96], range[256], def[256];
        snprintf(head, sizeof head, "--%s%s%s%s", o->name, o->kind == CLI_SWITCH ? "[=0|1]" : "",
                 o->metavar ? " " : "", o->metavar ? o->metavar : "");
        fprintf(out, "  %-*s", COLUMN - 3, head);
        if (strlen(head) > COLUMN - 4) fprintf(out, "\n%*s", COLUMN, "");
        else fputc(' ', out);
        print_indented(out, o->help, COLUMN);
        const char *d = default_text(cmd, o, def, sizeof def);
        const char *parts[4] = {NULL, o->note, NULL, NULL};
        char with_default[300], with_alias[80];
        if (o->kind != CLI_FLAG && o->kind != CLI_TEXT) parts[0] = cli_option_range(o, range, sizeof range);
        if (d != NULL) snprintf(with_default, sizeof with_default, "default %s", d), parts[2] = with_default;
        if (o->alias) snprintf(with_alias, sizeof with_alias, "old spelling --%s", o->alias), parts[3] = with_alias;
        /* "[range; note; default; old spelling]" under the help, wrapped before column 100 */
        int column = 0;
        for (int k = 0; k < 4; ++k) {
            if (parts[k] == NULL) continue;
            const int length = (int)strlen(parts[k]) + 2;
            if (column == 0 || column + length > 100) {
                fprintf(out, "%s\n%*s%s", column ? ";" : "", COLUMN, "", column ? " " : "[");
                column = COLUMN + 1;
            } else {
                fputs("; ", out);
            }
            fputs(parts[k], out);
            column += length;
        }
        fputs(column ? "]\n" : "\n", out);
    }
    fputs(cmd->epilogue, out);
}
