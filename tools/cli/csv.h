/*
 * The CSV reader of the pdtfit command line: a header row naming the
 * columns, then one row of numbers per sample. Only the columns t, u and y
 * are read (names compared case-insensitively, surrounding blanks and one
 * pair of double quotes removed); every other column is carried along
 * unread, so it may hold anything without a comma.
 *
 * Host code: it allocates and uses stdio, unlike the library.
 */
#ifndef PDTFIT_CLI_CSV_H
#define PDTFIT_CLI_CSV_H

#include <stddef.h>
#include <stdio.h>

/* The columns of one record, each `rows` values long (malloc'ed; free with
 * csv_table_free). t is NULL when the file has no t column. */
typedef struct csv_table {
    size_t rows;
    double *t;
    double *u;
    double *y;
} csv_table_t;

/*
 * Reads all of `in` into *out. `name` is the file's name in messages.
 * Every cell of t, u and y must be a finite decimal number of magnitude at
 * most max_abs (the largest value the caller can store). Rows must have as
 * many fields as the header; blank lines may follow the last row only.
 * Returns 0 on success. On failure returns -1, leaves *out empty and
 * writes one line (no newline) into err, naming the line and column:
 * "data.csv:7: column y: \"abc\" is not a number".
 */
int csv_read_tuy(FILE *in, const char *name, double max_abs, csv_table_t *out, char *err,
                 size_t err_len);

/* Frees the columns and empties *table. Safe on an empty table. */
void csv_table_free(csv_table_t *table);

#endif /* PDTFIT_CLI_CSV_H */
