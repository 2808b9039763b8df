#include "csv.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pdt/pdt.h"

/* A field or line as a range of the input buffer (not NUL-terminated). */
typedef struct span {
    const char *b;
    const char *e;
} span_t;

enum { COL_T, COL_U, COL_Y, COL_COUNT };
static const char *const col_names[COL_COUNT] = {"t", "u", "y"};
static const char *const col_opts[COL_COUNT] = {"--t", "--u", "--y"};

#define MAX_COLS 4096

enum { MISS_U = 1, MISS_Y = 2 };

/* Everything one read needs, freed in one place. */
typedef struct reader {
    const pdtcli_csv_opts_t *o;
    const char *name;
    char *buf;
    const char *p, *end;
    size_t lineno; /* of the line last taken */
    char sep;
    span_t fields[MAX_COLS];
    size_t ncols;
    long col[COL_COUNT]; /* -1: absent */
    double *t, *u, *y;
    size_t *line;        /* each row's line number */
    unsigned char *miss; /* each row's missing cells: MISS_U | MISS_Y */
    size_t rows, cap;
    int unit, unit_from;     /* the time unit taken (PDTCLI_TIME_*, _UNIT_*) */
    char unit_text[24];      /* the header's unit when it is no time unit */
    int iso;                 /* a t cell was a date-time */
    int t_by_time;           /* the t column is a default name past t */
    size_t units_line;       /* a units row detected and skipped, else 0 */
    const char *time_format; /* the date-time pattern of t, once known */
    char *err;
    size_t errlen;
} reader_t;

static int set_err(reader_t *r, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    if (r->err && r->errlen) vsnprintf(r->err, r->errlen, fmt, ap);
    va_end(ap);
    return -1;
}

static int is_blank(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

static span_t trim(span_t s)
{
    while (s.b < s.e && is_blank(*s.b)) s.b++;
    while (s.e > s.b && is_blank(s.e[-1])) s.e--;
    if (s.e - s.b >= 2 && *s.b == '"' && s.e[-1] == '"') {
        s.b++;
        s.e--;
        while (s.b < s.e && is_blank(*s.b)) s.b++;
        while (s.e > s.b && is_blank(s.e[-1])) s.e--;
    }
    return s;
}

/* A header name without its unit: "y [degC]", "y (degC)", "y {degC}" are
 * "y". */
static span_t strip_unit(span_t s)
{
    s = trim(s);
    if (s.e > s.b && (s.e[-1] == ']' || s.e[-1] == ')' || s.e[-1] == '}')) {
        const char open = s.e[-1] == ']' ? '[' : s.e[-1] == ')' ? '(' : '{';
        const char *q = s.e - 1;
        while (q > s.b && *q != open) q--;
        if (q > s.b && *q == open) s.e = q;
        s = trim(s);
    }
    return s;
}

static int span_is(span_t s, const char *name)
{
    size_t len = strlen(name);
    if ((size_t)(s.e - s.b) != len) return 0;
    for (size_t i = 0; i < len; i++) {
        char a = s.b[i], b = name[i];
        if (a >= 'A' && a <= 'Z') a = (char)(a - 'A' + 'a');
        if (b >= 'A' && b <= 'Z') b = (char)(b - 'A' + 'a');
        if (a != b) return 0;
    }
    return 1;
}

/* The cell as it may be printed in one line of a message. */
static void quote_cell(span_t s, char *buf, size_t buf_len)
{
    size_t j = 0;
    for (const char *p = s.b; p < s.e && j + 4 < buf_len; p++) {
        unsigned char c = (unsigned char)*p;
        if (j >= 24) {
            memcpy(buf + j, "...", 3);
            j += 3;
            break;
        }
        buf[j++] = (c >= 0x20 && c < 0x7f) ? (char)c : '?';
    }
    buf[j] = '\0';
}

static char *read_stream(FILE *in, size_t *len)
{
    size_t cap = 1 << 16, n = 0;
    char *buf = malloc(cap + 1);
    while (buf) {
        if (n == cap) {
            char *bigger = cap <= ((size_t)-1) / 4 ? realloc(buf, cap * 2 + 1) : NULL;
            if (!bigger) break;
            buf = bigger;
            cap *= 2;
        }
        size_t got = fread(buf + n, 1, cap - n, in);
        n += got;
        if (got == 0) {
            if (ferror(in)) break;
            *len = n;
            return buf;
        }
    }
    free(buf);
    return NULL;
}

static int load(reader_t *r, const char *path)
{
    const int from_stdin = strcmp(path, "-") == 0;
    FILE *in = from_stdin ? stdin : fopen(path, "rb");
    if (!in) return set_err(r, "cannot open %s: %s", path, strerror(errno));
    size_t len = 0;
    errno = 0;
    r->buf = read_stream(in, &len);
    int why = errno;
    if (!from_stdin) fclose(in);
    if (!r->buf)
        return set_err(r, "%s: cannot read: %s", r->name, why ? strerror(why) : "out of memory");
    r->p = r->buf;
    r->end = r->buf + len;
    /* A UTF-8 byte order mark, as some spreadsheets write it. */
    if (len >= 3 && memcmp(r->buf, "\xEF\xBB\xBF", 3) == 0) r->p += 3;
    return 0;
}

static int has_line(const reader_t *r)
{
    return r->p < r->end;
}

static span_t next_line(reader_t *r)
{
    span_t line = {r->p, r->p};
    while (line.e < r->end && *line.e != '\n') line.e++;
    r->p = line.e < r->end ? line.e + 1 : r->end;
    r->lineno++;
    return line;
}

static int line_is_blank(span_t line)
{
    for (const char *c = line.b; c < line.e; c++)
        if (!is_blank(*c)) return 0;
    return 1;
}

static int line_is_comment(span_t line)
{
    span_t s = trim(line);
    return s.b < s.e && *s.b == '#';
}

/* Splits at the separator outside double quotes; returns the true count. */
static size_t split(span_t line, char sep, span_t *fields, size_t max)
{
    size_t count = 0;
    int quoted = 0;
    const char *start = line.b;
    for (const char *c = line.b;; c++) {
        if (c < line.e && *c == '"') quoted = !quoted;
        if (c == line.e || (*c == sep && !quoted)) {
            if (count < max) {
                fields[count].b = start;
                fields[count].e = c;
            }
            count++;
            if (c == line.e) break;
            start = c + 1;
        }
    }
    return count;
}

/* The separator of the header: the most frequent of tab, semicolon and
 * comma outside quotes (comma on a tie, and with a decimal comma never). */
static char detect_sep(span_t header, char decimal)
{
    static const char cand[3] = {',', ';', '\t'};
    size_t best = 0;
    char sep = ',';
    for (int k = 0; k < 3; k++) {
        if (cand[k] == decimal) continue;
        size_t n = split(header, cand[k], NULL, 0) - 1;
        if (n > best) {
            best = n;
            sep = cand[k];
        }
    }
    if (best == 0 && decimal == ',') sep = ';';
    return sep;
}

/* "t, u, y" of the header as found, for messages. */
static void list_columns(const reader_t *r, char *buf, size_t len)
{
    size_t j = 0;
    buf[0] = '\0';
    for (size_t i = 0; i < r->ncols && i < 12 && j + 40 < len; i++) {
        char cell[32];
        quote_cell(trim(r->fields[i]), cell, sizeof cell);
        j += (size_t)snprintf(buf + j, len - j, "%s%zu \"%s\"", i ? ", " : "", i + 1, cell);
    }
    if (r->ncols > 12 && j + 8 < len) snprintf(buf + j, len - j, ", ...");
}

static int whole_number(const char *s, unsigned long *v)
{
    char *stop;
    if (*s < '0' || *s > '9') return 0;
    errno = 0;
    *v = strtoul(s, &stop, 10);
    return *stop == '\0' && errno == 0;
}

/* A header name without a unit after a slash: "y / degC" is "y". */
static span_t strip_slash_unit(span_t s)
{
    const char *slash = s.e;
    while (slash > s.b && *--slash != '/') {
    }
    if (slash > s.b && *slash == '/') s = trim((span_t){s.b, slash});
    return s;
}

/* The time units a header may name, in PDTCLI_TIME_* order, and their
 * length in seconds. */
static const char *const unit_words[][6] = {
    {"s", "sec", "secs", "second", "seconds", NULL},
    {"ms", "msec", "millisecond", "milliseconds", NULL, NULL},
    {"us", "\xC2\xB5s", "\xCE\xBCs", "usec", "microseconds", NULL},
    {"min", "mins", "minute", "minutes", NULL, NULL},
    {"h", "hr", "hrs", "hour", "hours", NULL},
};
static const double unit_seconds[] = {1.0, 1e-3, 1e-6, 60.0, 3600.0};

/* The PDTCLI_TIME_* a word names, or -1. */
static int unit_of(span_t s)
{
    for (int k = 0; k < (int)(sizeof unit_words / sizeof unit_words[0]); k++)
        for (int w = 0; unit_words[k][w]; w++)
            if (span_is(s, unit_words[k][w])) return k;
    return -1;
}

/* Splits "time_ms" into "time" and its unit; *unit -1 when the name has
 * no unit suffix. */
static span_t split_unit_suffix(span_t s, int *unit)
{
    const char *q = s.e;
    *unit = -1;
    while (q > s.b && q[-1] != '_') q--;
    if (q > s.b + 1) {
        const span_t suffix = {q, s.e};
        *unit = unit_of(suffix);
        if (*unit >= 0) s.e = q - 1;
    }
    return s;
}

/* The default names of the time column, in the order they are looked
 * for. */
static const char *const time_names[] = {"t", "time", "timestamp"};
#define TIME_FAMILIES (sizeof time_names / sizeof time_names[0])

/* Whether a header cell names the time by default: time_names[family],
 * with or without a unit. */
static int is_time_name(span_t s, int family)
{
    int unit;
    s = split_unit_suffix(strip_slash_unit(strip_unit(s)), &unit);
    return span_is(s, time_names[family]);
}

/* A default name of column c in the header cell. */
static int default_name(int c, span_t cell, int family)
{
    if (c == COL_T) return is_time_name(cell, family);
    const span_t s = strip_slash_unit(strip_unit(cell));
    return family == 0 && (span_is(s, col_names[c]) || (c == COL_Y && span_is(s, "pv")));
}

/* A column name as it is compared: case folded, without blanks and double
 * quotes, and with_unit 0 without its unit ("CV [%]", "CV (%)", "CV / %"
 * are "cv"). Returns 0, or -1 when it does not fit. */
static int fold_name(span_t s, int with_unit, char *out, size_t len)
{
    s = with_unit ? trim(s) : strip_slash_unit(strip_unit(s));
    size_t j = 0;
    for (const char *p = s.b; p < s.e; p++) {
        char ch = *p;
        if (is_blank(ch) || ch == '"') continue;
        if (j + 1 >= len) return -1;
        out[j++] = ch >= 'A' && ch <= 'Z' ? (char)(ch - 'A' + 'a') : ch;
    }
    out[j] = '\0';
    return 0;
}

/* The column spec names: with its unit as written if exactly one column
 * has it, else by the name alone (-2 when several share it); -1 absent. */
static long find_named(const reader_t *r, const char *spec)
{
    char want[256], have[256];
    const span_t sp = {spec, spec + strlen(spec)};
    for (int with_unit = 1; with_unit >= 0; with_unit--) {
        long found = -1;
        if (fold_name(sp, with_unit, want, sizeof want) != 0) return -1;
        for (size_t i = 0; i < r->ncols; i++)
            if (fold_name(r->fields[i], with_unit, have, sizeof have) == 0 &&
                strcmp(have, want) == 0)
                found = found < 0 ? (long)i : -2;
        if (found != -1) return found;
    }
    return -1;
}

/* The column chosen by spec (a name, find_named, or a 1-based index), else
 * by the default names (-2 when two match; t before time before
 * timestamp); -1 when absent. */
static long find_column(const reader_t *r, int c, const char *spec)
{
    unsigned long idx;
    if (spec && whole_number(spec, &idx)) return idx >= 1 && idx <= r->ncols ? (long)idx - 1 : -1;
    if (spec) return find_named(r, spec);
    long found = -1;
    for (int family = 0; family < (int)TIME_FAMILIES && found == -1; family++)
        for (size_t i = 0; i < r->ncols; i++)
            if (default_name(c, r->fields[i], family)) found = found < 0 ? (long)i : -2;
    return found;
}

/* The time unit of the t column's header: "t [ms]", "t (us)", "t / ms",
 * "time_ms"; an option overrides it. A bracketed unit that is no time unit is kept
 * as text: numbers in that column are then refused. */
static void header_unit(reader_t *r)
{
    r->unit = r->o->time_unit;
    r->unit_from = PDTCLI_UNIT_OPTION;
    if (r->o->time_unit != PDTCLI_TIME_AUTO) return;
    r->unit = PDTCLI_TIME_S;
    r->unit_from = PDTCLI_UNIT_DEFAULT;
    if (r->col[COL_T] < 0) return;
    const span_t cell = trim(r->fields[r->col[COL_T]]);
    const span_t name = strip_unit(cell), bare = strip_slash_unit(name);
    int unit = -1;
    if (bare.e < name.e) {
        span_t u = {bare.e, name.e};
        while (u.b < u.e && *u.b != '/') u.b++;
        /* Only a time unit: "Date/Time" is a name. */
        unit = unit_of(trim((span_t){u.b + 1, u.e}));
    } else if (name.e < cell.e) {
        span_t u = {name.e, cell.e};
        while (u.b < u.e && *u.b != '[' && *u.b != '(' && *u.b != '{') u.b++;
        u.b++;
        u.e--;
        u = trim(u);
        unit = unit_of(u);
        if (unit < 0) quote_cell(u, r->unit_text, sizeof r->unit_text);
    } else {
        split_unit_suffix(name, &unit);
    }
    if (unit >= 0) {
        r->unit = unit;
        r->unit_from = PDTCLI_UNIT_HEADER;
    }
}

static int header_error(reader_t *r, int c, const char *spec)
{
    char found[400];
    list_columns(r, found, sizeof found);
    if (spec)
        return set_err(r, "%s:%zu: %s %s: no such column (columns found: %s)", r->name, r->lineno,
                       col_opts[c], spec, found);
    return set_err(r, "%s:%zu: no column named %s%s (columns found: %s; choose one with %s)",
                   r->name, r->lineno, col_names[c], c == COL_Y ? " or pv" : "", found,
                   col_opts[c]);
}

static int read_header(reader_t *r)
{
    const pdtcli_csv_opts_t *o = r->o;
    span_t header = {NULL, NULL};
    for (unsigned k = 0; k < o->skip && has_line(r); k++) next_line(r);
    while (has_line(r)) {
        header = next_line(r);
        if (!line_is_blank(header) && !line_is_comment(header)) break;
        header.b = NULL;
    }
    if (!header.b) return set_err(r, "%s: no header row (expected column names t,u,y)", r->name);
    r->sep = o->sep ? o->sep : detect_sep(header, o->decimal);
    r->ncols = split(header, r->sep, r->fields, MAX_COLS);
    if (r->ncols > MAX_COLS)
        return set_err(r, "%s:%zu: more than %d columns", r->name, r->lineno, MAX_COLS);
    const char *spec[COL_COUNT] = {o->t_col, o->u_col, o->y_col};
    for (int c = 0; c < COL_COUNT; c++) {
        r->col[c] = find_column(r, c, spec[c]);
        if (r->col[c] == -2)
            return set_err(r, "%s:%zu: column %s appears twice in the header (choose one with %s)",
                           r->name, r->lineno, spec[c] ? spec[c] : col_names[c], col_opts[c]);
        if (r->col[c] < 0 && (c != COL_T || spec[c])) return header_error(r, c, spec[c]);
    }
    r->t_by_time = !o->t_col && r->col[COL_T] >= 0 && !is_time_name(r->fields[r->col[COL_T]], 0);
    header_unit(r);
    for (int c = 0; c < COL_COUNT; c++)
        for (int d = c + 1; d < COL_COUNT; d++)
            if (r->col[c] >= 0 && r->col[c] == r->col[d])
                return set_err(r, "%s:%zu: %s and %s name the same column", r->name, r->lineno,
                               col_names[c], col_names[d]);
    if (r->col[COL_T] < 0 && !(o->fs > 0.0))
        return set_err(r,
                       "%s: no t column: give the sampling frequency with --fs, or name the "
                       "time column with --t",
                       r->name);
    return 0;
}

/* A cell as text, with a decimal comma made a point where it can only be
 * one. Returns 0, or -1 when it is too long to be a number. */
static int cell_text(const reader_t *r, span_t s, char *text, size_t len)
{
    size_t n = (size_t)(s.e - s.b);
    if (n >= len) return -1;
    memcpy(text, s.b, n);
    text[n] = '\0';
    const int comma = r->o->decimal == ',' || (r->sep != ',' && !memchr(text, '.', n));
    char *c = comma ? strchr(text, ',') : NULL;
    if (c && !strchr(c + 1, ',')) *c = '.';
    return 0;
}

static int cell_error(reader_t *r, int c, span_t s, const char *why)
{
    char shown[32];
    quote_cell(s, shown, sizeof shown);
    return set_err(r, "%s:%zu: column %s: \"%s\" %s", r->name, r->lineno, col_names[c], shown, why);
}

/* What loggers, historians and spreadsheets write where a value is
 * missing (compared without regard to case); an empty cell, a non-finite
 * number and a spreadsheet error ("#VALUE!", "#DIV/0!", "#NAME?") too. */
static const char *const markers[] = {
    "#N/A",      "N/A",         "NA",        "NULL",          "None",    "ERR",
    "ERROR",     "Bad",         "Bad Input", "Bad Data",      "No Data", "I/O Timeout",
    "Comm Fail", "Calc Failed", "Shutdown",  "Not Connected", NULL};

static int is_marker(span_t s)
{
    const ptrdiff_t len = s.e - s.b;
    if (len >= 2 && *s.b == '#' && (s.e[-1] == '!' || s.e[-1] == '?')) return 1;
    for (int k = 0; markers[k]; k++)
        if (span_is(s, markers[k])) return 1;
    return 0;
}

/* A finite decimal number (what strtod takes, less nan, inf, hex); 1 when
 * the cell is a missing sample and missing samples are read as such. */
static int parse_number(reader_t *r, int c, span_t s, double *out)
{
    char text[128];
    const int lenient = r->o->bad_rows == PDTCLI_BAD_ROWS_MISSING && c != COL_T;
    if (s.b == s.e) {
        if (lenient) return 1;
        return set_err(r, "%s:%zu: column %s is empty%s", r->name, r->lineno, col_names[c],
                       c == COL_T ? " (a row without its time cannot be placed)" : "");
    }
    if (is_marker(s)) {
        if (lenient) return 1;
        return cell_error(r, c, s,
                          c == COL_T ? "is a missing time (a row without its time cannot be placed)"
                                     : "is a missing-value marker (--bad-rows refuse)");
    }
    if (cell_text(r, s, text, sizeof text) != 0) return cell_error(r, c, s, "is not a number");
    char *stop;
    double v = strtod(text, &stop);
    if (stop == text || *stop != '\0' || strpbrk(text, "xX") != NULL)
        return cell_error(r, c, s, "is not a number");
    /* strtod takes "nan" and "inf" and overflows to HUGE_VAL; none is a
     * measurement. Underflow to zero is harmless. */
    if (!isfinite(v)) return lenient ? 1 : cell_error(r, c, s, "is not finite");
    for (size_t k = 0; c != COL_T && k < r->o->n_bad_values; k++)
        if (v == r->o->bad_values[k])
            return lenient ? 1 : cell_error(r, c, s, "is a declared bad value (--bad-value)");
    if (c != COL_T && fabs(v) > r->o->max_abs) {
        char why[64];
        snprintf(why, sizeof why, "is out of range (|value| > %g)", r->o->max_abs);
        return cell_error(r, c, s, why);
    }
    *out = v;
    return 0;
}

/* Days from 1970-01-01 to y-m-d of the proleptic Gregorian calendar. */
static double days_from_civil(long y, long m, long d)
{
    y -= m <= 2;
    const long era = (y >= 0 ? y : y - 399) / 400;
    const long yoe = y - era * 400;
    const long doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
    const long doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    return (double)era * 146097.0 + (double)doe - 719468.0;
}

/* Reads n digits at *p into *v. */
static int digits(const char **p, int n, long *v)
{
    *v = 0;
    for (int k = 0; k < n; k++, (*p)++) {
        if (**p < '0' || **p > '9') return 0;
        *v = *v * 10 + (**p - '0');
    }
    return 1;
}

/* ISO 8601 "YYYY-MM-DD[T ]hh:mm[:ss[.f]][Z|+hh[:]mm|-hh[:]mm]", in s since
 * the epoch (UTC when an offset is given, else the clock's own time). */
static int parse_iso(const char *s, double *out)
{
    long Y, M, D, h, m, sec = 0, oh = 0, om = 0;
    const char *p = s;
    if (!digits(&p, 4, &Y) || *p++ != '-' || !digits(&p, 2, &M) || *p++ != '-' ||
        !digits(&p, 2, &D) || (*p != 'T' && *p != ' '))
        return 0;
    p++;
    if (!digits(&p, 2, &h) || *p++ != ':' || !digits(&p, 2, &m)) return 0;
    if (*p == ':') {
        p++;
        if (!digits(&p, 2, &sec)) return 0;
    }
    double frac = 0.0;
    if (*p == '.' || *p == ',') {
        double scale = 0.1;
        for (p++; *p >= '0' && *p <= '9'; p++, scale *= 0.1) frac += (*p - '0') * scale;
    }
    long sign = *p == '-' ? -1 : 1;
    if (*p == 'Z') {
        p++;
    } else if (*p == '+' || *p == '-') {
        p++;
        if (!digits(&p, 2, &oh)) return 0;
        if (*p == ':') p++;
        if (*p && !digits(&p, 2, &om)) return 0;
    }
    if (*p != '\0' || M < 1 || M > 12 || D < 1 || D > 31 || h > 24 || m > 59 || sec > 60) return 0;
    *out = days_from_civil(Y, M, D) * 86400.0 + (double)(h * 3600 + m * 60 + sec) + frac -
           (double)(sign * (oh * 3600 + om * 60));
    return 1;
}

/* The fields of a date-time as a pattern reads them. */
typedef struct when {
    long Y, M, D, h, m, s, oh, om, sign;
    int pm, has_p;
    double frac;
} when_t;

/* One or two digits (n 2) or exactly n digits at *p. */
static int some_digits(const char **p, int n, long *v)
{
    if (n != 2) return digits(p, n, v);
    if (!digits(p, 1, v)) return 0;
    if (**p >= '0' && **p <= '9') *v = *v * 10 + (*(*p)++ - '0');
    return 1;
}

/* One conversion of a pattern (the letter after '%') at *p into w. */
static int convert(char f, const char **p, when_t *w)
{
    switch (f) {
    case 'Y':
        return digits(p, 4, &w->Y);
    case 'y':
        return digits(p, 2, &w->Y) && (w->Y += 2000) > 0;
    case 'm':
        return some_digits(p, 2, &w->M);
    case 'd':
        return some_digits(p, 2, &w->D);
    case 'H':
    case 'I':
        return some_digits(p, 2, &w->h);
    case 'M':
        return some_digits(p, 2, &w->m);
    case 'S':
        return some_digits(p, 2, &w->s);
    case 'f': {
        double scale = 0.1;
        if (**p < '0' || **p > '9') return 0;
        for (; **p >= '0' && **p <= '9'; (*p)++, scale *= 0.1) w->frac += (**p - '0') * scale;
        return 1;
    }
    case 'p':
        w->has_p = 1;
        w->pm = (**p == 'P' || **p == 'p');
        if (!w->pm && **p != 'A' && **p != 'a') return 0;
        (*p)++;
        return **p == 'M' || **p == 'm' ? ((*p)++, 1) : 0;
    case 'z':
        if (**p == 'Z') return (*p)++, 1;
        if (**p != '+' && **p != '-') return 0;
        w->sign = *(*p)++ == '-' ? -1 : 1;
        if (!digits(p, 2, &w->oh)) return 0;
        if (**p == ':') (*p)++;
        return digits(p, 2, &w->om);
    case '%':
        return *(*p)++ == '%';
    default:
        return 0;
    }
}

/* s read by the strftime-like pattern fmt (csv.h), in s since the epoch
 * (UTC when %z gives an offset, else the clock's own time): 1 when it
 * matches the whole text. */
static int parse_format(const char *fmt, const char *s, double *out)
{
    when_t w = {1970, 1, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0.0};
    const char *p = s;
    for (const char *f = fmt; *f; f++) {
        if (*f == '%' && f[1]) {
            if (!convert(*++f, &p, &w)) return 0;
        } else if (*f == ' ') {
            while (*p == ' ' || *p == '\t') p++;
        } else if (*p++ != *f) {
            return 0;
        }
    }
    if (w.has_p && (w.h < 1 || w.h > 12)) return 0;
    if (w.has_p) w.h = w.h % 12 + (w.pm ? 12 : 0);
    if (*p != '\0' || w.M < 1 || w.M > 12 || w.D < 1 || w.D > 31 || w.h > 24 || w.m > 59 ||
        w.s > 60)
        return 0;
    *out = days_from_civil(w.Y, w.M, w.D) * 86400.0 + (double)(w.h * 3600 + w.m * 60 + w.s) +
           w.frac - (double)(w.sign * (w.oh * 3600 + w.om * 60));
    return 1;
}

/* The date-time forms recognised without --time-format, beside ISO 8601:
 * PLC exports (day.month.year, a decimal comma or point) and spreadsheets
 * (month/day/year with AM/PM). */
static const char *const time_forms[] = {
    "%d.%m.%Y %H:%M:%S,%f",    "%d.%m.%Y %H:%M:%S.%f", "%d.%m.%Y %H:%M:%S", "%d.%m.%Y %H:%M",
    "%m/%d/%Y %I:%M:%S.%f %p", "%m/%d/%Y %I:%M:%S %p", "%m/%d/%Y %I:%M %p",
};

/* A time cell that is a date-time: 1 read into *out, 0 not one (a number,
 * perhaps), -1 an error set. The first cell fixes the form for the rest. */
static int parse_date(reader_t *r, span_t s, double *out)
{
    char text[64];
    const size_t n = (size_t)(s.e - s.b);
    if (n >= sizeof text) return 0;
    memcpy(text, s.b, n);
    text[n] = '\0';
    const char *fmt = r->o->time_format ? r->o->time_format : r->time_format;
    if (fmt) {
        if (parse_format(fmt, text, out)) return 1;
        char why[96];
        snprintf(why, sizeof why, "does not match the time format \"%.40s\"", fmt);
        return cell_error(r, COL_T, s, why);
    }
    if (n >= 16 && text[4] == '-')
        return parse_iso(text, out)
                   ? 1
                   : cell_error(r, COL_T, s, "is not a number or an ISO 8601 date-time");
    if (!strpbrk(text, ":/") || (strchr(text, '/') && !strpbrk(text, "AaPp"))) {
        if (strchr(text, '/'))
            return cell_error(r, COL_T, s,
                              "is a date without AM/PM: day/month or month/day? (give "
                              "--time-format, e.g. \"%d/%m/%Y %H:%M:%S\")");
        return 0;
    }
    for (size_t k = 0; k < sizeof time_forms / sizeof time_forms[0]; k++)
        if (parse_format(time_forms[k], text, out)) {
            r->time_format = time_forms[k];
            return 1;
        }
    return cell_error(r, COL_T, s,
                      "is not a number or a known date-time (give its form with --time-format)");
}

static int parse_time(reader_t *r, span_t s, double *out)
{
    const int date = parse_date(r, s, out);
    if (date > 0) r->iso = 1;
    if (date != 0) return date > 0 ? 0 : -1;
    if (parse_number(r, COL_T, s, out) != 0) return -1;
    if (r->unit_text[0] && r->unit_from == PDTCLI_UNIT_DEFAULT)
        return set_err(r,
                       "%s:%zu: column t: the header's unit \"%s\" is not a time unit (s, ms, "
                       "us, min, h): give the unit with --time-unit",
                       r->name, r->lineno, r->unit_text);
    *out *= unit_seconds[r->unit];
    return 0;
}

static int grow(reader_t *r)
{
    size_t cap = r->cap ? r->cap * 2 : 1024;
    double *t = realloc(r->t, cap * sizeof *t);
    if (t) r->t = t;
    double *u = realloc(r->u, cap * sizeof *u);
    if (u) r->u = u;
    double *y = realloc(r->y, cap * sizeof *y);
    if (y) r->y = y;
    size_t *line = realloc(r->line, cap * sizeof *line);
    if (line) r->line = line;
    unsigned char *miss = realloc(r->miss, cap * sizeof *miss);
    if (miss) r->miss = miss;
    if (!t || !u || !y || !line || !miss) return set_err(r, "%s: out of memory", r->name);
    r->cap = cap;
    return 0;
}

static int read_row(reader_t *r, span_t line)
{
    size_t got = split(line, r->sep, r->fields, MAX_COLS);
    if (got != r->ncols)
        return set_err(r, "%s:%zu: %zu field%s, but the header has %zu", r->name, r->lineno, got,
                       got == 1 ? "" : "s", r->ncols);
    if (r->rows == r->cap && grow(r) != 0) return -1;
    double *dest[COL_COUNT] = {&r->t[r->rows], &r->u[r->rows], &r->y[r->rows]};
    static const unsigned char bit[COL_COUNT] = {0, MISS_U, MISS_Y};
    unsigned char miss = 0;
    for (int c = 0; c < COL_COUNT; c++) {
        if (r->col[c] < 0) continue;
        span_t s = trim(r->fields[r->col[c]]);
        int rc = c == COL_T ? parse_time(r, s, dest[c]) : parse_number(r, c, s, dest[c]);
        /* A column "time" or "timestamp" of clock times a file had beside
         * --fs before they were default names: left aside, as then. */
        if (rc < 0 && c == COL_T && r->t_by_time && r->rows == 0 && r->o->fs > 0.0) {
            r->col[COL_T] = -1;
            r->unit_from = PDTCLI_UNIT_DEFAULT;
            rc = 0;
        }
        if (rc < 0) return -1;
        if (rc > 0) {
            miss |= bit[c];
            *dest[c] = (double)NAN;
        }
    }
    r->miss[r->rows] = miss;
    r->line[r->rows++] = r->lineno;
    return 0;
}

/* A comment line, not a row whose first cell is a spreadsheet error
 * ("#N/A", "#VALUE!"). */
static int row_is_comment(const reader_t *r, span_t line)
{
    if (!line_is_comment(line)) return 0;
    span_t first = line;
    split(line, r->sep, &first, 1);
    return !is_marker(trim(first));
}

/* Whether the line is a row of units: the chosen columns' cells hold text
 * and no number (some may be empty). */
static int units_like(const reader_t *r, span_t line)
{
    span_t f[MAX_COLS];
    int text = 0;
    if (split(line, r->sep, f, MAX_COLS) != r->ncols) return 0;
    for (int c = 0; c < COL_COUNT; c++) {
        if (r->col[c] < 0) continue;
        const span_t s = trim(f[r->col[c]]);
        char cell[128], *stop;
        const size_t n = (size_t)(s.e - s.b);
        if (n == 0 || is_marker(s)) continue;
        if (n >= sizeof cell) return 0;
        memcpy(cell, s.b, n);
        cell[n] = '\0';
        (void)strtod(cell, &stop);
        if (stop != cell) return 0;
        text = 1;
    }
    return text;
}

static int read_rows(reader_t *r)
{
    size_t blank_at = 0;
    int first = 1;
    while (has_line(r)) {
        span_t line = next_line(r);
        if (row_is_comment(r, line)) continue;
        /* A units row under the header: skipped when asked for, else when
         * it looks like one (reported in the series). */
        if (first && !line_is_blank(line) && (r->o->units_row || units_like(r, line))) {
            if (!r->o->units_row) r->units_line = r->lineno;
            first = 0;
            continue;
        }
        first = 0;
        if (line_is_blank(line)) {
            if (!blank_at) blank_at = r->lineno;
            continue;
        }
        if (blank_at)
            return set_err(r, "%s:%zu: empty row (blank lines may only end the file)", r->name,
                           blank_at);
        if (read_row(r, line) != 0) return -1;
    }
    return 0;
}

/* A missing u repeats the u before it (the first ones take the first u
 * read); the lines of the first missing cells are kept. A column with no
 * value at all is refused. */
static int hold_missing(reader_t *r, pdtcli_series_t *out)
{
    size_t first_u = r->rows, n_y = 0;
    for (size_t k = 0; k < r->rows; k++) {
        if (!(r->miss[k] & MISS_U) && first_u == r->rows) first_u = k;
        n_y += (r->miss[k] & MISS_Y) != 0;
        if (r->miss[k] && out->n_first_line < PDTCLI_MISSING_FIRST)
            out->first_line[out->n_first_line++] = r->line[k];
        out->missing_u += (r->miss[k] & MISS_U) != 0;
    }
    if (r->rows && (first_u == r->rows || n_y == r->rows))
        return set_err(r, "%s: column %s holds no value, only missing samples", r->name,
                       first_u == r->rows ? "u" : "y");
    for (size_t k = 0; k < r->rows; k++)
        if (r->miss[k] & MISS_U) r->u[k] = k < first_u ? r->u[first_u] : r->u[k - 1];
    return 0;
}

/* The missing y of the series, counted and the first indexed. */
static void count_missing_y(pdtcli_series_t *out)
{
    for (size_t k = 0; k < out->n; k++) {
        if (!isnan(out->y[k])) continue;
        if (out->n_first_y < PDTCLI_MISSING_FIRST) out->first_y[out->n_first_y++] = k;
        out->missing_y++;
    }
}

/* A count read as seconds that looks like epoch milliseconds or
 * microseconds (a start between the years 1998 and 2100, steps of at
 * least one unit) is refused when no unit was given. */
static int check_epoch(reader_t *r, double med)
{
    static const struct {
        double lo, hi;
        const char *unit;
    } epoch[] = {{9e11, 4.2e12, "ms"}, {9e14, 4.2e15, "us"}};
    const double t0 = r->t[0];
    if (r->iso || r->unit_from != PDTCLI_UNIT_DEFAULT) return 0;
    for (size_t k = 0; k < sizeof epoch / sizeof epoch[0]; k++)
        if (t0 >= epoch[k].lo && t0 < epoch[k].hi && med >= 1.0)
            return set_err(r,
                           "%s: t starts at %.15g and steps by %.6g: epoch %s read as seconds? "
                           "Give the unit with --time-unit %s (or --time-unit s if they are "
                           "seconds)",
                           r->name, t0, med, k == 0 ? "milliseconds" : "microseconds",
                           epoch[k].unit);
    return 0;
}

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The median interval between rows; refuses a step back, and a duplicate
 * time unless resampling. */
static int median_interval(reader_t *r, double *med)
{
    const size_t n = r->rows;
    for (size_t k = 1; k < n; k++) {
        const double d = r->t[k] - r->t[k - 1];
        if (d < 0.0 || (d == 0.0 && !r->o->resample))
            return set_err(r, "%s:%zu: t does not increase: %s (%.9g after %.9g on line %zu)%s",
                           r->name, r->line[k], d < 0.0 ? "it steps back" : "a duplicate time",
                           r->t[k], r->t[k - 1], r->line[k - 1],
                           d == 0.0 ? "; --resample keeps the last row" : "");
    }
    double *d = malloc((n - 1) * sizeof *d);
    if (!d) return set_err(r, "%s: out of memory", r->name);
    size_t m = 0;
    for (size_t k = 1; k < n; k++)
        if (r->t[k] > r->t[k - 1]) d[m++] = r->t[k] - r->t[k - 1];
    if (m == 0) {
        free(d);
        return set_err(r, "%s: t does not increase", r->name);
    }
    qsort(d, m, sizeof *d, cmp_double);
    *med = m % 2 ? d[m / 2] : 0.5 * (d[m / 2 - 1] + d[m / 2]);
    free(d);
    return 0;
}

/* Checks every interval against Ts. Returns 1 when one is off by more
 * than the tolerance and resample is set (or a time repeats). */
static int check_intervals(reader_t *r, double Ts)
{
    int irregular = 0;
    for (size_t k = 1; k < r->rows; k++) {
        const double d = r->t[k] - r->t[k - 1], off = fabs(d - Ts);
        if (d == 0.0) {
            irregular = 1;
        } else if (off > PDTCLI_CSV_JITTER * Ts && r->o->resample) {
            irregular = 1;
        } else if (d > 1.5 * Ts) {
            const double missing = floor(d / Ts + 0.5) - 1.0;
            return set_err(
                r,
                "%s:%zu: t is not uniformly sampled: a gap of %.9g s after line %zu "
                "(Ts = %.9g s), %.0f row%s missing; --resample fills %s by zero-order hold",
                r->name, r->line[k], d, r->line[k - 1], Ts, missing, missing > 1 ? "s" : "",
                missing > 1 ? "them" : "it");
        } else if (off > PDTCLI_CSV_JITTER * Ts) {
            return set_err(r,
                           "%s:%zu: t is not uniformly sampled: %.9g s after line %zu, Ts = %.9g "
                           "s (tolerance %g%% of Ts; --resample puts the rows on the grid)",
                           r->name, r->line[k], d, r->line[k - 1], Ts, 100.0 * PDTCLI_CSV_JITTER);
        }
    }
    return irregular;
}

/* The rows held onto the grid t0 + k Ts: each grid point takes the last
 * row at or before it (within half a period), or repeats the one before. */
static int resample(reader_t *r, double Ts, pdtcli_series_t *out)
{
    const double span = r->t[r->rows - 1] - r->t[0];
    const double ng = floor(span / Ts + 0.5) + 1.0;
    /* A stamp far off (a wrong year, a counter's wrap) would fill a gap of
     * millions of rows: no more than a record may have. */
    if (!(ng <= (double)PDT_MAX_SAMPLES))
        return set_err(r,
                       "%s: the t column spans %.0f periods of %.9g s, more than the %u rows a "
                       "record may have (a stamp out of place?)",
                       r->name, ng, Ts, (unsigned)PDT_MAX_SAMPLES);
    const size_t n = (size_t)ng;
    out->u = malloc(n * sizeof *out->u);
    out->y = malloc(n * sizeof *out->y);
    if (!out->u || !out->y) return set_err(r, "%s: out of memory", r->name);
    size_t j = 0;
    for (size_t g = 0; g < n; g++) {
        const double tg = r->t[0] + (double)g * Ts;
        int own = g == 0;
        while (j + 1 < r->rows && r->t[j + 1] <= tg + 0.5 * Ts) {
            j++;
            own = 1;
        }
        out->filled += own ? 0u : 1u;
        out->u[g] = r->u[j];
        out->y[g] = r->y[j];
    }
    out->n = n;
    return 0;
}

static int take_columns(reader_t *r, pdtcli_series_t *out)
{
    out->u = r->u;
    out->y = r->y;
    out->n = r->rows;
    r->u = r->y = NULL;
    return 0;
}

static int sample(reader_t *r, pdtcli_series_t *out)
{
    const double fs = r->o->fs;
    if (r->rows == 0) return set_err(r, "%s: 0 data rows after the header", r->name);
    out->time_unit = r->unit;
    out->time_unit_from = r->unit_from;
    if (r->col[COL_T] < 0 || r->rows < 2) {
        out->Ts = fs > 0.0 ? 1.0 / fs : 0.0;
        return take_columns(r, out);
    }
    double med = 0.0;
    if (median_interval(r, &med) != 0) return -1;
    if (check_epoch(r, med) != 0) return -1;
    const double mean = (r->t[r->rows - 1] - r->t[0]) / (double)(r->rows - 1);
    const double Ts_fs = fs > 0.0 ? 1.0 / fs : med;
    /* Either figure of the stamps will do: the mean is the better one for
     * jittered stamps, the median for a record with gaps. */
    if (fabs(Ts_fs - med) > 0.01 * med && fabs(Ts_fs - mean) > 0.01 * mean)
        return set_err(r,
                       "%s: --fs %.9g Hz (Ts = %.9g s) disagrees with the t column (Ts = %.9g s)",
                       r->name, fs, Ts_fs, med);
    const int irregular = check_intervals(r, Ts_fs);
    if (irregular < 0) return -1;
    /* Jitter: stamps more than 1 % of Ts off the uniform grid. */
    unsigned jitter = 0;
    for (size_t k = 0; !irregular && k < r->rows; k++)
        jitter += fabs(r->t[k] - (r->t[0] + (double)k * mean)) > 0.01 * mean;
    out->jitter_warn = jitter;
    out->has_t = 1;
    out->t0 = r->t[0];
    /* A nominal rate given is exact; jittered stamps get the median, which
     * one late stamp does not move; clean ones the mean, the most precise. */
    out->Ts = fs > 0.0 ? Ts_fs : (jitter || irregular) ? med : mean;
    if (!(out->Ts > 0.0) || !isfinite(out->Ts))
        return set_err(r, "%s: t does not give a usable sampling period", r->name);
    return irregular ? resample(r, out->Ts, out) : take_columns(r, out);
}

void pdtcli_csv_opts_default(pdtcli_csv_opts_t *o)
{
    if (!o) return;
    memset(o, 0, sizeof *o);
    o->max_abs = sizeof(pdt_real_t) == sizeof(float) ? (double)FLT_MAX : DBL_MAX;
    o->time_unit = PDTCLI_TIME_AUTO;
}

void pdtcli_series_free(pdtcli_series_t *s)
{
    if (!s) return;
    free(s->u);
    free(s->y);
    memset(s, 0, sizeof *s);
}

static int check_opts(reader_t *r)
{
    const pdtcli_csv_opts_t *o = r->o;
    if (o->sep && o->sep != ',' && o->sep != ';' && o->sep != '\t' && o->sep != ' ')
        return set_err(r, "the separator must be a comma, semicolon, tab or blank");
    if (o->decimal && o->decimal != '.' && o->decimal != ',')
        return set_err(r, "the decimal mark must be '.' or ','");
    if (o->sep && o->sep == o->decimal)
        return set_err(r, "the separator and the decimal mark must differ");
    if (o->time_unit < PDTCLI_TIME_AUTO || o->time_unit > PDTCLI_TIME_H)
        return set_err(r, "unknown time unit");
    if (o->bad_rows != PDTCLI_BAD_ROWS_MISSING && o->bad_rows != PDTCLI_BAD_ROWS_REFUSE)
        return set_err(r, "unknown bad-rows mode");
    if (o->n_bad_values && !o->bad_values) return set_err(r, "bad values without a list");
    if (!(o->fs >= 0.0) || !isfinite(o->fs)) return set_err(r, "fs must be >= 0 Hz");
    return 0;
}

/* One read, from the file at path or (path NULL) from text. */
static int read_series(const char *path, const char *text, size_t len, const pdtcli_csv_opts_t *o,
                       pdtcli_series_t *out, char *err, size_t errlen)
{
    pdtcli_csv_opts_t def;
    pdtcli_csv_opts_default(&def);
    if (!out || (!path && !text)) return -1;
    memset(out, 0, sizeof *out);
    reader_t *r = calloc(1, sizeof *r);
    if (!r) {
        if (err && errlen) snprintf(err, errlen, "out of memory");
        return -1;
    }
    r->o = o ? o : &def;
    r->name = r->o->name ? r->o->name : !path ? "text" : strcmp(path, "-") == 0 ? "stdin" : path;
    r->err = err;
    r->errlen = errlen;
    int rc = check_opts(r);
    if (rc == 0 && path) rc = load(r, path);
    if (rc == 0 && !path) {
        r->buf = malloc(len + 1);
        if (!r->buf) rc = set_err(r, "%s: out of memory", r->name);
        if (r->buf) memcpy(r->buf, text, len);
        r->p = r->buf;
        r->end = r->buf + len;
    }
    if (rc == 0) rc = read_header(r);
    if (rc == 0) rc = read_rows(r);
    if (rc == 0) rc = hold_missing(r, out);
    if (rc == 0) rc = sample(r, out);
    if (rc == 0) count_missing_y(out);
    if (rc == 0) out->units_row = r->units_line;
    if (rc == 0) out->time_format = r->time_format;
    if (rc != 0) pdtcli_series_free(out);
    free(r->buf);
    free(r->t);
    free(r->u);
    free(r->y);
    free(r->line);
    free(r->miss);
    free(r);
    return rc != 0;
}

int pdtcli_csv_read_series(const char *path, const pdtcli_csv_opts_t *o, pdtcli_series_t *out,
                           char *err, size_t errlen)
{
    return read_series(path, NULL, 0, o, out, err, errlen);
}

int pdtcli_csv_parse_series(const char *text, size_t len, const pdtcli_csv_opts_t *o,
                            pdtcli_series_t *out, char *err, size_t errlen)
{
    return read_series(NULL, text ? text : "", text ? len : 0, o, out, err, errlen);
}
