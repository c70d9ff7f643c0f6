/* A strict CSV reader for numeric recordings: one header row of names, then rows of numbers. */
#ifndef OKID_CLI_CSV_READER_H
#define OKID_CLI_CSV_READER_H

#include <stddef.h>
#include <stdio.h>

typedef struct csv_table {
    int num_columns;
    size_t num_rows;
    char **names;    /* num_columns column names (trimmed) */
    double *values;  /* row-major: values[row * num_columns + column] */
} csv_table;

/*
 * Parses text[0..length) (no terminator needed). Separators: ',' (or ';' / tab when the header
 * has no comma); header names are trimmed of blanks and quotes, unique, free of control
 * characters; blank lines and lines starting with '#' are skipped; CRLF is accepted. Every row
 * must have as many fields as the header, every field a finite number.
 * Returns 0 and fills table, or -1 with a one-line message in error (row and column named).
 */
int csv_parse(const char *text, size_t length, csv_table *table, char *error, size_t error_size);

/* Reads a whole stream and parses it. Returns 0, or -1 with a message (the caller names the file). */
int csv_read_stream(FILE *f, csv_table *table, char *error, size_t error_size);

/* Reads a whole file ("-" is standard input) and parses it. Returns 0, or -1 with a message. */
int csv_read_file(const char *path, csv_table *table, char *error, size_t error_size);

/* Index of the column named name, or -1. */
int csv_find_column(const csv_table *table, const char *name);

void csv_free(csv_table *table);

#endif
