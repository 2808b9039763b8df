/*
 * The record reader of the pdtfit command line, callable on its own (the
 * Python binding loads it from a shared library): one CSV file of a logged
 * test, as PLCs, loggers and spreadsheets export it, into an input and an
 * output series sampled every Ts seconds.
 *
 * The file: optional lines before the header (--skip), comment lines
 * starting with '#' anywhere, a header row naming the columns, then one row
 * per sample. The separator (comma, semicolon or tab) is found in the
 * header unless given; with a semicolon or tab separator a decimal comma is
 * read as a decimal point. Columns are chosen by name or by 1-based index.
 * A name matches with or without its unit, however either is written: case,
 * blanks and double quotes do not count, and a unit in brackets ("y [degC]",
 * "y (degC)", "y {degC}") or after a slash ("y / degC") may be given or
 * left out, in the header and in the option alike; where two columns share
 * a name, the unit given decides. A row of units under the header ("s;%;degC")
 * is skipped: with units_row, or when its cells in the chosen columns are
 * text and the next row's are numbers (reported in units_row). Time is a
 * count in the unit the header gives ("t [ms]", "time_ms", "t (us)",
 * "t_min") or time_unit says, else seconds (a count that looks like epoch
 * milliseconds or microseconds read as seconds is refused), or a date-time:
 * ISO 8601 ("2024-03-01T08:00:00.250", a space for the T, optional Z or
 * +hh:mm), day.month.year as PLCs write it ("01.03.2024 08:00:00,500"),
 * month/day/year with AM/PM as spreadsheets write it
 * ("3/1/2024 8:00:00 AM"), or any form a time_format pattern describes:
 * %Y year, %y two-digit year (2000-2099), %m month, %d day, %H hour
 * (0-23), %I hour (1-12) with %p AM/PM, %M minute, %S second, %f the
 * fraction of a second (any digits), %z Z or +hh[:]mm, %% a percent
 * sign; other characters match themselves, a blank any run of blanks.
 * Month, day, hour and minute take one or two digits.
 *
 * Missing samples: an empty cell, a marker ("NaN", "#N/A", "N/A", "ERR",
 * a spreadsheet error such as "#VALUE!", a historian state such as "Bad
 * Input"), a non-finite number, or one of the declared bad values is no
 * data. By default a missing y is NaN in the series (the identification
 * leaves it out), a missing u repeats the u before it (the first ones the
 * first u read); both are counted. With bad_rows PDTCLI_BAD_ROWS_REFUSE
 * each is refused with its line. A missing time is always refused: a row
 * without its time cannot be placed.
 *
 * Sampling: every interval between rows within PDTCLI_CSV_JITTER of the
 * median interval is accepted. Stamps more than 1 % of Ts off the uniform
 * grid are counted in jitter_warn and Ts is then the median interval;
 * otherwise Ts is the mean interval. A longer interval (a gap, a dropped row) is refused with
 * the line number, or with resample filled by repeating the last row on the
 * grid (zero-order hold; filled counts the rows added). A duplicate or a
 * step back in time is refused with its line number; with resample a
 * duplicate time replaces the row before it.
 *
 * Host code: it allocates and uses stdio, unlike the library.
 */
#ifndef PDTCLI_CSV_H
#define PDTCLI_CSV_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Largest accepted deviation of an interval from the median, a fraction of
 * it. */
#define PDTCLI_CSV_JITTER 0.25

/* Time units of the t column (time_unit); AUTO: the header's, else s. */
enum {
    PDTCLI_TIME_AUTO = -1,
    PDTCLI_TIME_S = 0,
    PDTCLI_TIME_MS = 1,
    PDTCLI_TIME_US = 2,
    PDTCLI_TIME_MIN = 3,
    PDTCLI_TIME_H = 4
};

/* What a missing sample does (bad_rows). */
enum { PDTCLI_BAD_ROWS_MISSING = 0, PDTCLI_BAD_ROWS_REFUSE = 1 };

/* Where the time unit came from (pdtcli_series_t.time_unit_from). */
enum { PDTCLI_UNIT_DEFAULT = 0, PDTCLI_UNIT_HEADER = 1, PDTCLI_UNIT_OPTION = 2 };

/* How many missing samples a series lists by position. */
#define PDTCLI_MISSING_FIRST 8

typedef struct pdtcli_csv_opts {
    const char *t_col, *u_col, *y_col; /* name or 1-based index as text;
                                        * NULL: t, u, y (or pv) */
    char sep;                          /* 0 = detect from the header */
    char decimal;                      /* 0 = '.' */
    unsigned skip;                     /* lines before the header */
    int time_unit;                     /* numbers in t: PDTCLI_TIME_*;
                                        * default AUTO */
    int bad_rows;                      /* PDTCLI_BAD_ROWS_*; default
                                        * MISSING */
    const double *bad_values;          /* declared bad values (sentinels
                                        * such as -9999), n_bad_values */
    size_t n_bad_values;
    int resample;            /* fill gaps by zero-order hold */
    double fs;               /* Hz; 0 = from the time column.
                                        * With a t column it must agree
                                        * within 1 % and is the Ts used */
    double max_abs;          /* largest |cell| of u, y accepted;
                                        * default: what pdt_real_t holds */
    const char *name;        /* the file in messages; NULL: path
                                        * ("stdin" for "-") */
    int units_row;           /* 1: one row of units under the
                                        * header, skipped; 0: detected */
    const char *time_format; /* strftime-like pattern of t
                                        * (pdtcli_csv_read_series); NULL:
                                        * detected */
} pdtcli_csv_opts_t;

typedef struct pdtcli_series {
    double *u, *y; /* n values each (malloc'ed) */
    size_t n;
    double Ts;                               /* s */
    unsigned jitter_warn;                    /* stamps more than 1 % of Ts off the grid */
    unsigned filled;                         /* rows added by resample */
    double t0;                               /* time of the first row, s (epoch s for dates) */
    int has_t;                               /* the file had a time column */
    int time_unit;                           /* the unit the t column was read in */
    int time_unit_from;                      /* PDTCLI_UNIT_*: where that unit came from */
    size_t missing_y;                        /* y samples missing: NaN in y */
    size_t missing_u;                        /* u samples missing: the u before held */
    size_t first_y[PDTCLI_MISSING_FIRST];    /* the first missing y, as
                                           * indices into y */
    size_t first_line[PDTCLI_MISSING_FIRST]; /* the lines of the first
                                              * missing samples, u or y */
    unsigned n_first_y, n_first_line;
    size_t units_row;        /* the line of a units row found under
                                              * the header and skipped (not asked
                                              * for), else 0 */
    const char *time_format; /* the date-time pattern detected in
                                              * t (static text), or NULL */
} pdtcli_series_t;

/* Fills o with the defaults above. */
void pdtcli_csv_opts_default(pdtcli_csv_opts_t *o);

/* Reads the file at path ("-": standard input) into *out (o NULL: the
 * defaults). Returns 0 on success. On failure returns nonzero, leaves *out
 * empty and writes one line into err naming the file, the line and the
 * cause, e.g. "log.csv:7: column y: \"abc\" is not a number". */
int pdtcli_csv_read_series(const char *path, const pdtcli_csv_opts_t *o, pdtcli_series_t *out,
                           char *err, size_t errlen);

/* The same from len bytes of text in memory (a fuzzer's input, a string);
 * messages name the file "text" unless o->name is set. */
int pdtcli_csv_parse_series(const char *text, size_t len, const pdtcli_csv_opts_t *o,
                            pdtcli_series_t *out, char *err, size_t errlen);

/* Frees the series and empties it. Safe on an empty series. */
void pdtcli_series_free(pdtcli_series_t *s);

#ifdef __cplusplus
}
#endif

#endif /* PDTCLI_CSV_H */
