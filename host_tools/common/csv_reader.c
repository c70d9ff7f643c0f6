/* SPDX-License-Identifier: Apache-2.0 */
/* See csv_reader.h. Strict on purpose: a recording with a hole or a typo is an error, not a guess. */
#define _POSIX_C_SOURCE 200809L /* fmemopen */
#include "csv_reader.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* CHUNK: the bytes read at a time, the buffer's size unless a line is longer. MAX_NUMBER: a data
   cell's characters (a number printed with every digit of a double has some 770; more is no
   number anyone wrote). A line longer than its columns can fill is refused before it is read
   whole: the header holds MAX_COLUMNS names of MAX_FIELD characters (with a few blanks or quotes
   each), a row MAX_COLUMNS cells of MAX_NUMBER. */
enum { MAX_COLUMNS = 4096, MAX_FIELD = 256, MAX_NUMBER = 4096, CHUNK = 1 << 20 };
#define MAX_HEADER_LINE ((size_t)MAX_COLUMNS * (MAX_FIELD + 8))
#define MAX_ROW_LINE ((size_t)MAX_COLUMNS * (MAX_NUMBER + 1))

static int fail(char *error, size_t size, const char *format, ...) __attribute__((format(printf, 3, 4)));

static int fail(char *error, size_t size, const char *format, ...)
{
    va_list args;
    va_start(args, format);
    vsnprintf(error, size, format, args);
    va_end(args);
    return -1;
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

/* 0, -1 not a number, -2 longer than MAX_NUMBER characters. */
static int parse_number(const char *b, const char *e, double *out)
{
    char field[MAX_NUMBER + 1];
    trim(&b, &e);
    if (e - b > MAX_NUMBER) {
        return -2;
    }
    if (b == e) {
        return -1;
    }
    memcpy(field, b, (size_t)(e - b));
    field[e - b] = '\0';
    char *endp = NULL;
    errno = 0;
    *out = strtod(field, &endp);
    return (endp == field || *endp != '\0') ? -1 : 0;
}

/* One row [b, e) (line `line`) into row[num_columns]. */
static int parse_row(const csv_table *t, char sep, const char *b, const char *e, size_t line, double *row, char *error,
                     size_t size)
{
    const int n = t->num_columns;
    if (count_fields(b, e, sep) != n) {
        return fail(error, size, "line %zu has %d fields, the header has %d", line, count_fields(b, e, sep), n);
    }
    const char *p = b;
    for (int j = 0; j < n; ++j) {
        const char *q = memchr(p, sep, (size_t)(e - p));
        const char *fe = q ? q : e;
        const int parsed = parse_number(p, fe, &row[j]);
        if (parsed == -2) {
            return fail(error, size, "line %zu, column '%s': a cell of more than %d characters", line, t->names[j],
                        MAX_NUMBER);
        }
        if (parsed != 0) {
            return fail(error, size, "line %zu, column '%s': not a number", line, t->names[j]);
        }
        if (!isfinite(row[j])) {
            return fail(error, size, "line %zu, column '%s': %s value", line, t->names[j],
                        isnan(row[j]) ? "NaN" : "infinite");
        }
        p = q ? q + 1 : e;
    }
    return 0;
}

/*
 * More bytes into the buffer: the unconsumed ones move to its front, it doubles when a line fills
 * it, and one read appends. 1, 0 at the end of the input, -1 with a message.
 */
static int refill(csv_stream *s, char *error, size_t size)
{
    if (s->begin > 0) {
        memmove(s->buf, s->buf + s->begin, s->end - s->begin);
        s->end -= s->begin;
        s->begin = 0;
    }
    if (s->end == s->capacity) {
        char *grown = realloc(s->buf, 2 * s->capacity);
        if (grown == NULL) {
            return fail(error, size, "out of memory (a line of more than %zu bytes)", s->capacity);
        }
        s->buf = grown;
        s->capacity *= 2;
    }
    const size_t n = fread(s->buf + s->end, 1, s->capacity - s->end, s->in);
    if (n == 0) {
        if (ferror(s->in)) {
            return fail(error, size, "cannot read: %s", strerror(errno));
        }
        s->at_eof = 1;
        return 0;
    }
    const unsigned char *bytes = (const unsigned char *)s->buf + s->end;
    if (s->bytes_read == 0 && n >= 2 && ((bytes[0] == 0xFF && bytes[1] == 0xFE) || (bytes[0] == 0xFE && bytes[1] == 0xFF))) {
        return fail(error, size, "UTF-16 or UTF-32 text (byte-order mark %02X %02X): save the file as UTF-8",
                    bytes[0], bytes[1]);
    }
    if (memchr(bytes, '\0', n) != NULL) {
        return fail(error, size, "the file holds NUL bytes: not a text CSV");
    }
    if (s->bytes_read == 0 && n >= 3 && bytes[0] == 0xEF && bytes[1] == 0xBB && bytes[2] == 0xBF) {
        s->begin += 3; /* the UTF-8 byte-order mark: not part of the first name */
    }
    s->end += n;
    s->bytes_read += n;
    return 1;
}

/* The next line that is not blank or a '#' comment, [*b, *e) without its line break, valid until
   the next call; one longer than limit bytes is refused once that many are read. 1, 0 at the end,
   -1 with a message. */
static int next_line(csv_stream *s, size_t limit, const char **b, const char **e, char *error, size_t size)
{
    for (;;) {
        char *start = s->buf + s->begin;
        char *nl = memchr(start, '\n', s->end - s->begin);
        if (nl == NULL && s->end - s->begin > limit) {
            if (s->header.num_columns == 0) {
                return fail(error, size, "line %zu is longer than %zu bytes, more than a header of %d names of %d "
                            "characters fills", s->line_number + 1, limit, MAX_COLUMNS, MAX_FIELD);
            }
            return fail(error, size, "line %zu is longer than %zu bytes, more than %d cells of %d characters fill",
                        s->line_number + 1, limit, s->header.num_columns, MAX_NUMBER);
        }
        if (nl == NULL && !s->at_eof) {
            if (refill(s, error, size) < 0) {
                return -1;
            }
            continue;
        }
        if (nl == NULL && s->begin == s->end) {
            return 0;
        }
        const char *stop = nl ? nl : s->buf + s->end;
        s->begin = nl ? (size_t)(nl + 1 - s->buf) : s->end;
        ++s->line_number;
        if (stop > start && stop[-1] == '\r') {
            --stop;
        }
        const char *p = start;
        while (p < stop && (*p == ' ' || *p == '\t')) {
            ++p;
        }
        if (p == stop || *p == '#') {
            continue; /* blank line or comment */
        }
        *b = start;
        *e = stop;
        return 1;
    }
}

int csv_stream_open(csv_stream *s, FILE *in, char *error, size_t error_size)
{
    memset(s, 0, sizeof *s);
    s->in = in;
    s->capacity = CHUNK;
    s->buf = malloc(s->capacity);
    if (s->buf == NULL) {
        return fail(error, error_size, "out of memory");
    }
    const char *b, *e;
    const int rc = next_line(s, MAX_HEADER_LINE, &b, &e, error, error_size);
    if (rc <= 0) {
        csv_stream_close(s);
        return rc < 0 ? -1 : fail(error, error_size, "the file is empty (a header row and data rows are needed)");
    }
    s->sep = pick_separator(b, e);
    if (parse_header(b, e, s->sep, &s->header, error, error_size) != 0) {
        csv_stream_close(s);
        return -1;
    }
    return 0;
}

int csv_stream_row(csv_stream *s, double *row, char *error, size_t error_size)
{
    const char *b, *e;
    const size_t limit = (size_t)s->header.num_columns * (MAX_NUMBER + 1);
    const int rc = next_line(s, limit < MAX_ROW_LINE ? limit : MAX_ROW_LINE, &b, &e, error, error_size);
    if (rc <= 0) {
        return rc;
    }
    return parse_row(&s->header, s->sep, b, e, s->line_number, row, error, error_size) == 0 ? 1 : -1;
}

void csv_stream_close(csv_stream *s)
{
    free(s->buf);
    s->buf = NULL;
    csv_free(&s->header);
}

int csv_read_stream(FILE *f, csv_table *table, char *error, size_t error_size)
{
    memset(table, 0, sizeof *table);
    csv_stream s;
    if (csv_stream_open(&s, f, error, error_size) != 0) {
        return -1;
    }
    const size_t n = (size_t)s.header.num_columns;
    size_t capacity = 0;
    double *row = malloc(n * sizeof(double));
    int rc = row == NULL ? fail(error, error_size, "out of memory") : 0;
    while (rc == 0) {
        const int got = csv_stream_row(&s, row, error, error_size);
        if (got <= 0) {
            rc = got;
            break;
        }
        if (table->num_rows == capacity) {
            const size_t grown = capacity ? 2 * capacity : 1024;
            double *v = realloc(table->values, grown * n * sizeof(double));
            if (v == NULL) {
                rc = fail(error, error_size, "out of memory at line %zu", s.line_number);
                break;
            }
            table->values = v;
            capacity = grown;
        }
        memcpy(table->values + table->num_rows++ * n, row, n * sizeof(double));
    }
    free(row);
    if (rc == 0 && table->num_rows == 0) {
        rc = fail(error, error_size, "the file has a header but no data rows");
    }
    if (rc == 0) {
        table->names = s.header.names; /* the table takes the names over */
        table->num_columns = s.header.num_columns;
        s.header.names = NULL;
        s.header.num_columns = 0;
    } else {
        free(table->values);
        table->values = NULL;
        table->num_rows = 0;
    }
    csv_stream_close(&s);
    return rc;
}

int csv_parse(const char *text, size_t length, csv_table *table, char *error, size_t error_size)
{
    memset(table, 0, sizeof *table);
    if (text == NULL || length == 0) {
        return fail(error, error_size, "the file is empty (a header row and data rows are needed)");
    }
    FILE *f = fmemopen((void *)text, length, "rb"); /* the same reader as files and pipes */
    if (f == NULL) {
        return fail(error, error_size, "cannot read: %s", strerror(errno));
    }
    const int rc = csv_read_stream(f, table, error, error_size);
    fclose(f);
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
