/* See csv_reader.h. Strict on purpose: a recording with a hole or a typo is an error, not a guess. */
#include "csv_reader.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { MAX_COLUMNS = 4096, MAX_FIELD = 256 };

static int fail(char *error, size_t size, const char *format, ...) __attribute__((format(printf, 3, 4)));

static int fail(char *error, size_t size, const char *format, ...)
{
    va_list args;
    va_start(args, format);
    vsnprintf(error, size, format, args);
    va_end(args);
    return -1;
}

/* One physical line [begin, end) without its line break. */
typedef struct line_cursor {
    const char *text, *end;
    size_t line_number;
} line_cursor;

static int next_line(line_cursor *c, const char **begin, const char **end)
{
    while (c->text < c->end) {
        const char *b = c->text;
        const char *nl = memchr(b, '\n', (size_t)(c->end - b));
        const char *e = nl ? nl : c->end;
        c->text = nl ? nl + 1 : c->end;
        ++c->line_number;
        if (e > b && e[-1] == '\r') {
            --e;
        }
        const char *p = b;
        while (p < e && (*p == ' ' || *p == '\t')) {
            ++p;
        }
        if (p == e || *p == '#') {
            continue; /* blank line or comment */
        }
        *begin = b;
        *end = e;
        return 1;
    }
    return 0;
}

static void trim(const char **b, const char **e)
{
    while (*b < *e && (**b == ' ' || **b == '\t' || **b == '"')) {
        ++*b;
    }
    while (*e > *b && ((*e)[-1] == ' ' || (*e)[-1] == '\t' || (*e)[-1] == '"')) {
        --*e;
    }
}

static int count_fields(const char *b, const char *e, char sep)
{
    int n = 1;
    for (const char *p = b; p < e; ++p) {
        n += (*p == sep);
    }
    return n;
}

static char pick_separator(const char *b, const char *e)
{
    if (memchr(b, ',', (size_t)(e - b))) return ',';
    if (memchr(b, ';', (size_t)(e - b))) return ';';
    if (memchr(b, '\t', (size_t)(e - b))) return '\t';
    return ',';
}

static int parse_header(const char *b, const char *e, char sep, csv_table *t, char *error, size_t size)
{
    const int n = count_fields(b, e, sep);
    if (n > MAX_COLUMNS) {
        return fail(error, size, "header has %d columns (at most %d)", n, MAX_COLUMNS);
    }
    t->names = calloc((size_t)n, sizeof(char *));
    if (t->names == NULL) {
        return fail(error, size, "out of memory");
    }
    t->num_columns = n;
    const char *p = b;
    for (int j = 0; j < n; ++j) {
        const char *q = memchr(p, sep, (size_t)(e - p));
        const char *fe = q ? q : e, *fb = p;
        trim(&fb, &fe);
        if (fb == fe) {
            return fail(error, size, "header column %d has no name", j + 1);
        }
        if (fe - fb > MAX_FIELD) {
            return fail(error, size, "header column %d: name longer than %d characters", j + 1, MAX_FIELD);
        }
        for (const char *q2 = fb; q2 < fe; ++q2) {
            /* A control character in a name would break the one-line error messages that quote it. */
            if ((unsigned char)*q2 < 0x20 || *q2 == 0x7f) {
                return fail(error, size, "header column %d: the name holds a control character", j + 1);
            }
        }
        t->names[j] = malloc((size_t)(fe - fb) + 1);
        if (t->names[j] == NULL) {
            return fail(error, size, "out of memory");
        }
        memcpy(t->names[j], fb, (size_t)(fe - fb));
        t->names[j][fe - fb] = '\0';
        for (int k = 0; k < j; ++k) {
            if (strcmp(t->names[k], t->names[j]) == 0) {
                return fail(error, size, "header names column '%s' twice", t->names[j]);
            }
        }
        p = q ? q + 1 : e;
    }
    /* A header of numbers is a missing header: say so instead of losing the first sample. */
    char *endp = NULL;
    errno = 0;
    strtod(t->names[0], &endp);
    if (endp != t->names[0] && *endp == '\0') {
        return fail(error, size, "the first line must be a header of column names, not numbers");
    }
    return 0;
}

static int parse_number(const char *b, const char *e, double *out)
{
    char field[MAX_FIELD + 1];
    trim(&b, &e);
    if (b == e || e - b > MAX_FIELD) {
        return -1;
    }
    memcpy(field, b, (size_t)(e - b));
    field[e - b] = '\0';
    char *endp = NULL;
    errno = 0;
    *out = strtod(field, &endp);
    return (endp == field || *endp != '\0') ? -1 : 0;
}

static int append_row(csv_table *t, size_t *capacity, const char *b, const char *e, char sep, size_t line,
                      char *error, size_t size)
{
    const int n = t->num_columns;
    if (count_fields(b, e, sep) != n) {
        return fail(error, size, "line %zu has %d fields, the header has %d", line, count_fields(b, e, sep), n);
    }
    if (t->num_rows == *capacity) {
        const size_t grown = *capacity ? 2 * *capacity : 1024;
        double *v = realloc(t->values, grown * (size_t)n * sizeof(double));
        if (v == NULL) {
            return fail(error, size, "out of memory at line %zu", line);
        }
        t->values = v;
        *capacity = grown;
    }
    double *row = t->values + t->num_rows * (size_t)n;
    const char *p = b;
    for (int j = 0; j < n; ++j) {
        const char *q = memchr(p, sep, (size_t)(e - p));
        const char *fe = q ? q : e;
        if (parse_number(p, fe, &row[j]) != 0) {
            return fail(error, size, "line %zu, column '%s': not a number", line, t->names[j]);
        }
        if (!isfinite(row[j])) {
            return fail(error, size, "line %zu, column '%s': %s value", line, t->names[j],
                        isnan(row[j]) ? "NaN" : "infinite");
        }
        p = q ? q + 1 : e;
    }
    ++t->num_rows;
    return 0;
}

int csv_parse(const char *text, size_t length, csv_table *table, char *error, size_t error_size)
{
    memset(table, 0, sizeof *table);
    if (text == NULL) {
        length = 0;
        text = ""; /* no arithmetic on a null pointer */
    }
    line_cursor c = {text, text + length, 0};
    const char *b, *e;
    if (!next_line(&c, &b, &e)) {
        return fail(error, error_size, "the file is empty (a header row and data rows are needed)");
    }
    if (memchr(text, '\0', length) != NULL) {
        csv_free(table);
        return fail(error, error_size, "the file holds NUL bytes: not a text CSV");
    }
    const char sep = pick_separator(b, e);
    if (parse_header(b, e, sep, table, error, error_size) != 0) {
        csv_free(table);
        return -1;
    }
    size_t capacity = 0;
    while (next_line(&c, &b, &e)) {
        if (append_row(table, &capacity, b, e, sep, c.line_number, error, error_size) != 0) {
            csv_free(table);
            return -1;
        }
    }
    if (table->num_rows == 0) {
        csv_free(table);
        return fail(error, error_size, "the file has a header but no data rows");
    }
    return 0;
}

int csv_read_stream(FILE *f, csv_table *table, char *error, size_t error_size)
{
    memset(table, 0, sizeof *table);
    size_t capacity = 1 << 16, length = 0;
    char *text = malloc(capacity);
    while (text != NULL) {
        length += fread(text + length, 1, capacity - length, f);
        if (length < capacity) {
            break;
        }
        char *grown = realloc(text, capacity * 2);
        if (grown == NULL) {
            free(text);
            text = NULL;
            break;
        }
        text = grown;
        capacity *= 2;
    }
    if (text == NULL || ferror(f)) {
        const char *why = ferror(f) ? strerror(errno) : "out of memory";
        free(text);
        return fail(error, error_size, "cannot read: %s", why);
    }
    const int rc = csv_parse(text, length, table, error, error_size);
    free(text);
    return rc;
}

int csv_read_file(const char *path, csv_table *table, char *error, size_t error_size)
{
    memset(table, 0, sizeof *table);
    if (strcmp(path, "-") == 0) {
        return csv_read_stream(stdin, table, error, error_size);
    }
    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        return fail(error, error_size, "cannot open: %s", strerror(errno));
    }
    const int rc = csv_read_stream(f, table, error, error_size);
    fclose(f);
    return rc;
}

int csv_find_column(const csv_table *table, const char *name)
{
    for (int j = 0; j < table->num_columns; ++j) {
        if (strcmp(table->names[j], name) == 0) {
            return j;
        }
    }
    return -1;
}

void csv_free(csv_table *table)
{
    if (table->names != NULL) {
        for (int j = 0; j < table->num_columns; ++j) {
            free(table->names[j]);
        }
    }
    free(table->names);
    free(table->values);
    memset(table, 0, sizeof *table);
}
