#include "csv.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

/* A field or line as a range of the input buffer (not NUL-terminated). */
typedef struct span {
    const char *b;
    const char *e;
} span_t;

enum { COL_T, COL_U, COL_Y, COL_COUNT };
static const char *const col_names[COL_COUNT] = {"t", "u", "y"};

static void set_err(char *err, size_t err_len, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, err_len, fmt, ap);
    va_end(ap);
}

static int is_blank(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

static span_t trim(span_t s)
{
    while (s.b < s.e && is_blank(*s.b)) s.b++;
    while (s.e > s.b && is_blank(s.e[-1])) s.e--;
    /* Spreadsheets sometimes quote every field; a quoted field may not
     * contain a comma here, since fields are split on commas first. */
    if (s.e - s.b >= 2 && *s.b == '"' && s.e[-1] == '"') {
        s.b++;
        s.e--;
        while (s.b < s.e && is_blank(*s.b)) s.b++;
        while (s.e > s.b && is_blank(s.e[-1])) s.e--;
    }
    return s;
}

static int span_is_name(span_t s, const char *name)
{
    size_t len = strlen(name);
    if ((size_t)(s.e - s.b) != len) return 0;
    for (size_t i = 0; i < len; i++) {
        char c = s.b[i];
        if (c >= 'A' && c <= 'Z') c = (char)(c - 'A' + 'a');
        if (c != name[i]) return 0;
    }
    return 1;
}

/* The cell as it may be printed in one line of a message: at most 24
 * characters, control and non-ASCII bytes shown as '?'. */
static void quote_cell(span_t s, char *buf, size_t buf_len)
{
    size_t j = 0;
    for (const char *p = s.b; p < s.e && j + 4 < buf_len; p++) {
        unsigned char c = (unsigned char)*p;
        if (j >= 24) {
            buf[j++] = '.';
            buf[j++] = '.';
            buf[j++] = '.';
            break;
        }
        buf[j++] = (c >= 0x20 && c < 0x7f) ? (char)c : '?';
    }
    buf[j] = '\0';
}

/* Slurps the whole stream: records are small next to memory, and a buffer
 * lets the rows be counted before the columns are allocated. */
static char *read_all(FILE *in, size_t *len)
{
    size_t cap = 1 << 16, n = 0;
    char *buf = malloc(cap);
    if (!buf) return NULL;
    for (;;) {
        if (n == cap) {
            char *bigger = cap <= ((size_t)-1) / 2 ? realloc(buf, cap * 2) : NULL;
            if (!bigger) {
                free(buf);
                return NULL;
            }
            buf = bigger;
            cap *= 2;
        }
        size_t got = fread(buf + n, 1, cap - n, in);
        n += got;
        if (got == 0) break;
    }
    if (ferror(in)) {
        int why = errno ? errno : EIO;
        free(buf);
        errno = why;
        return NULL;
    }
    *len = n;
    return buf;
}

/* Next line of [*p, end), without its '\n' (a trailing '\r' is a blank). */
static span_t next_line(const char **p, const char *end)
{
    span_t line = {*p, *p};
    while (line.e < end && *line.e != '\n') line.e++;
    *p = line.e < end ? line.e + 1 : end;
    return line;
}

static int line_is_blank(span_t line)
{
    for (const char *c = line.b; c < line.e; c++)
        if (!is_blank(*c)) return 0;
    return 1;
}

/* Splits a line at commas into at most max fields; returns the true count. */
static size_t split(span_t line, span_t *fields, size_t max)
{
    size_t count = 0;
    const char *start = line.b;
    for (const char *c = line.b;; c++) {
        if (c == line.e || *c == ',') {
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

static size_t count_fields(span_t line)
{
    size_t count = 1;
    for (const char *c = line.b; c < line.e; c++)
        if (*c == ',') count++;
    return count;
}

static int parse_cell(span_t raw, const char *name, size_t lineno, const char *col,
                      double max_abs, double *out, char *err, size_t err_len)
{
    span_t s = trim(raw);
    char text[128], shown[32];
    if (s.b == s.e) {
        set_err(err, err_len, "%s:%zu: column %s is empty", name, lineno, col);
        return -1;
    }
    quote_cell(s, shown, sizeof shown);
    size_t len = (size_t)(s.e - s.b);
    if (len >= sizeof text) {
        set_err(err, err_len, "%s:%zu: column %s: \"%s\" is not a number", name, lineno, col,
                shown);
        return -1;
    }
    memcpy(text, s.b, len);
    text[len] = '\0';
    char *stop;
    errno = 0;
    double v = strtod(text, &stop);
    if (stop == text || *stop != '\0' || memchr(text, '\0', len) != NULL) {
        set_err(err, err_len, "%s:%zu: column %s: \"%s\" is not a number", name, lineno, col,
                shown);
        return -1;
    }
    /* strtod accepts "nan", "inf" and overflows to HUGE_VAL; none of them is
     * a measurement. Underflow to zero is harmless and accepted. */
    if (!isfinite(v)) {
        set_err(err, err_len, "%s:%zu: column %s: \"%s\" is not finite", name, lineno, col, shown);
        return -1;
    }
    if (fabs(v) > max_abs) {
        set_err(err, err_len, "%s:%zu: column %s: \"%s\" is out of range (|value| > %g)", name,
                lineno, col, shown, max_abs);
        return -1;
    }
    *out = v;
    return 0;
}

void csv_table_free(csv_table_t *table)
{
    if (!table) return;
    free(table->t);
    free(table->u);
    free(table->y);
    table->t = table->u = table->y = NULL;
    table->rows = 0;
}

int csv_read_tuy(FILE *in, const char *name, double max_abs, csv_table_t *out, char *err,
                 size_t err_len)
{
    csv_table_t tab = {0, NULL, NULL, NULL};
    span_t *fields = NULL;
    size_t len = 0;
    int rc = -1;
    out->rows = 0;
    out->t = out->u = out->y = NULL;

    errno = 0;
    char *buf = read_all(in, &len);
    if (!buf) {
        set_err(err, err_len, "%s: cannot read: %s", name,
                errno ? strerror(errno) : "out of memory");
        return -1;
    }
    const char *p = buf, *end = buf + len;
    /* A UTF-8 byte order mark, as some spreadsheets write it. */
    if (len >= 3 && memcmp(buf, "\xEF\xBB\xBF", 3) == 0) p += 3;

    span_t header = next_line(&p, end);
    if (line_is_blank(header)) {
        set_err(err, err_len, "%s: no header row (expected column names t,u,y or u,y)", name);
        goto done;
    }
    size_t ncols = count_fields(header);
    fields = malloc(ncols * sizeof *fields);
    if (!fields) {
        set_err(err, err_len, "%s: out of memory", name);
        goto done;
    }
    split(header, fields, ncols);
    size_t where[COL_COUNT] = {0, 0, 0};
    int found[COL_COUNT] = {0, 0, 0};
    for (size_t i = 0; i < ncols; i++) {
        span_t s = trim(fields[i]);
        for (int c = 0; c < COL_COUNT; c++) {
            if (!span_is_name(s, col_names[c])) continue;
            if (found[c]) {
                set_err(err, err_len, "%s:1: column %s appears twice in the header", name,
                        col_names[c]);
                goto done;
            }
            found[c] = 1;
            where[c] = i;
        }
    }
    for (int c = COL_U; c <= COL_Y; c++) {
        if (!found[c]) {
            set_err(err, err_len, "%s:1: no column named %s in the header%s", name, col_names[c],
                    ncols == 1 ? " (the separator must be a comma)" : "");
            goto done;
        }
    }

    /* Count the rows and find where the trailing blank lines start. */
    size_t rows = 0;
    const char *data = p, *data_end = p;
    size_t lineno = 1;
    for (const char *q = p; q < end;) {
        span_t line = next_line(&q, end);
        lineno++;
        if (line_is_blank(line)) continue;
        rows++;
        data_end = q;
    }
    /* A blank line before data_end sits between rows: that is an error,
     * reported in the pass below. */
    size_t alloc = rows ? rows : 1;
    tab.u = malloc(alloc * sizeof *tab.u);
    tab.y = malloc(alloc * sizeof *tab.y);
    tab.t = found[COL_T] ? malloc(alloc * sizeof *tab.t) : NULL;
    if (!tab.u || !tab.y || (found[COL_T] && !tab.t)) {
        set_err(err, err_len, "%s: out of memory", name);
        goto done;
    }

    lineno = 1;
    size_t row = 0;
    for (const char *q = data; q < data_end;) {
        span_t line = next_line(&q, data_end);
        lineno++;
        if (line_is_blank(line)) {
            set_err(err, err_len, "%s:%zu: empty row (blank lines may only end the file)", name,
                    lineno);
            goto done;
        }
        size_t got = split(line, fields, ncols);
        if (got != ncols) {
            set_err(err, err_len, "%s:%zu: %zu field%s, but the header has %zu", name, lineno,
                    got, got == 1 ? "" : "s", ncols);
            goto done;
        }
        double *dest[COL_COUNT] = {tab.t, tab.u, tab.y};
        for (int c = 0; c < COL_COUNT; c++) {
            if (!found[c]) continue;
            if (parse_cell(fields[where[c]], name, lineno, col_names[c], max_abs, &dest[c][row],
                           err, err_len) != 0)
                goto done;
        }
        row++;
    }
    tab.rows = row;
    *out = tab;
    tab.t = tab.u = tab.y = NULL;
    rc = 0;

done:
    csv_table_free(&tab);
    free(fields);
    free(buf);
    return rc;
}
