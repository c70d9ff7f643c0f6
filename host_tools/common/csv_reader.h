/* SPDX-License-Identifier: Apache-2.0 */
/*
 * A strict CSV reader for numeric recordings: one header row of names, then rows of numbers. It
 * streams: a file of any size is read through one buffer that holds a chunk (and grows only to
 * hold the longest line), so the reader's memory does not grow with the file.
 *
 * Separators: ',' (or ';' / tab when the header has no comma); header names are trimmed of blanks
 * and quotes, unique, free of control characters; a UTF-8 byte-order mark before the header is
 * skipped (Excel writes one), a UTF-16 or UTF-32 one is refused; blank lines and lines starting
 * with '#' are skipped; CRLF is accepted; a NUL byte anywhere refuses the file. Every row must
 * have as many fields as the header, every field a finite number of at most 4096 characters. A
 * line longer than its fields can fill (4096 names of 256 characters; a row's cells of 4096) is
 * refused as soon as that many bytes are read, not held whole.
 */
#ifndef OKID_CLI_CSV_READER_H
#define OKID_CLI_CSV_READER_H

#include <stddef.h>
#include <stdio.h>

typedef struct csv_table {
    int num_columns;
    size_t num_rows;
    char **names;    /* num_columns column names (trimmed) */
    double *values;  /* row-major: values[row * num_columns + column]; NULL for a stream's header */
} csv_table;

/* A stream over a FILE: the header once opened, then one row at a time. */
typedef struct csv_stream {
    FILE *in;
    char *buf;           /* buf[begin, end) holds bytes read and not yet consumed */
    size_t capacity, begin, end;
    int at_eof;
    size_t line_number;  /* of the last line returned */
    unsigned long long bytes_read;
    char sep;
    csv_table header;    /* names and num_columns; no values */
} csv_stream;

/* Reads up to the header and parses it. Returns 0, or -1 with a one-line message in error (the
   stream is then closed). */
int csv_stream_open(csv_stream *s, FILE *in, char *error, size_t error_size);

/* The next data row into row[num_columns]: 1, 0 at the end, -1 with a message (line and column named). */
int csv_stream_row(csv_stream *s, double *row, char *error, size_t error_size);

/* Frees the buffer and the names (not the FILEs). */
void csv_stream_close(csv_stream *s);

/* Parses text[0..length) (no terminator needed) into a whole table. Returns 0, or -1 with a message. */
int csv_parse(const char *text, size_t length, csv_table *table, char *error, size_t error_size);

/* Reads a whole stream into a table. Returns 0, or -1 with a message (the caller names the file). */
int csv_read_stream(FILE *f, csv_table *table, char *error, size_t error_size);

/* Reads a whole file ("-" is standard input) into a table. Returns 0, or -1 with a message. */
int csv_read_file(const char *path, csv_table *table, char *error, size_t error_size);

/* Index of the column named name, or -1. */
int csv_find_column(const csv_table *table, const char *name);

void csv_free(csv_table *table);

#endif
