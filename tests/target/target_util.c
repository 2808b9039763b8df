/* Output and measures of the target test program (see target_util.h). */
#include "target_util.h"

#include <math.h>

#include "pdt_port.h"
#include "pdt_port_target.h"

static unsigned g_run;
static unsigned g_failed;
static size_t g_stack_max;

void tl_init(tline_t *l)
{
    l->n = 0;
}

static void tl_char(tline_t *l, char c)
{
    if (l->n < sizeof l->buf) {
        l->buf[l->n++] = c;
    }
}

void tl_str(tline_t *l, const char *s)
{
    while (*s != '\0') {
        tl_char(l, *s++);
    }
}

void tl_uint(tline_t *l, uint64_t v)
{
    char tmp[20];
    size_t n = 0;
    do {
        tmp[n++] = (char)('0' + (int)(v % 10u));
        v /= 10u;
    } while (v != 0u);
    while (n > 0u) {
        tl_char(l, tmp[--n]);
    }
}

void tl_int(tline_t *l, int64_t v)
{
    if (v < 0) {
        tl_char(l, '-');
        tl_uint(l, (uint64_t)0 - (uint64_t)v);
    } else {
        tl_uint(l, (uint64_t)v);
    }
}

void tl_num(tline_t *l, double v, int digits)
{
    if (isnan(v)) {
        tl_str(l, "nan");
        return;
    }
    if (v < 0.0) {
        tl_char(l, '-');
        v = -v;
    }
    if (isinf(v)) {
        tl_str(l, "inf");
        return;
    }
    if (v == 0.0) {
        tl_char(l, '0');
        return;
    }
    digits = digits < 1 ? 1 : (digits > 9 ? 9 : digits);
    uint64_t scale = 1u;
    for (int i = 1; i < digits; i++) {
        scale *= 10u;
    }
    int e = (int)floor(log10(v));
    uint64_t q = (uint64_t)(v / pow(10.0, (double)e) * (double)scale + 0.5);
    /* log10 may land one off near powers of ten, and rounding may carry. */
    while (q >= 10u * scale) {
        q = (q + 5u) / 10u;
        e++;
    }
    while (q < scale) {
        q *= 10u;
        e--;
    }
    char d[9];
    for (int i = digits - 1; i >= 0; i--) {
        d[i] = (char)('0' + (int)(q % 10u));
        q /= 10u;
    }
    /* significant digits actually needed (trailing zeros dropped) */
    int used = digits;
    while (used > 1 && d[used - 1] == '0') {
        used--;
    }
    if (e < -4 || e >= digits) {
        tl_char(l, d[0]);
        if (used > 1) {
            tl_char(l, '.');
            for (int i = 1; i < used; i++) {
                tl_char(l, d[i]);
            }
        }
        tl_char(l, 'e');
        tl_char(l, e < 0 ? '-' : '+');
        int ae = e < 0 ? -e : e;
        if (ae < 10) {
            tl_char(l, '0');
        }
        tl_uint(l, (uint64_t)ae);
    } else if (e >= 0) {
        for (int i = 0; i <= e; i++) {
            tl_char(l, i < digits ? d[i] : '0');
        }
        if (used > e + 1) {
            tl_char(l, '.');
            for (int i = e + 1; i < used; i++) {
                tl_char(l, d[i]);
            }
        }
    } else {
        tl_str(l, "0.");
        for (int i = 0; i < -e - 1; i++) {
            tl_char(l, '0');
        }
        for (int i = 0; i < used; i++) {
            tl_char(l, d[i]);
        }
    }
}

/* "name value" pairs, 5 digits each, one space apart. */
static void tl_params(tline_t *l, const char *const *names, const double *v, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        tl_str(l, i > 0u ? " " : "");
        tl_str(l, names[i]);
        tl_str(l, " ");
        tl_num(l, v[i], 5);
    }
}

void tl_fopdt(tline_t *l, const pdt_model_fopdt_t *m)
{
    static const char *const names[3] = {"K", "tau", "Td"};
    const double v[3] = {(double)m->K, (double)m->tau, (double)m->Td};
    tl_params(l, names, v, 3u);
}

void tl_tc(tline_t *l, const pdt_model_tc_t *tc)
{
    static const char *const names[4] = {"K", "T1", "T2", "Td"};
    const double v[4] = {(double)tc->K, (double)tc->T1, (double)tc->T2, (double)tc->Td};
    tl_params(l, names, v, 4u);
}

void tl_emit(tline_t *l)
{
    tl_char(l, '\n');
    if (l->buf[l->n - 1u] != '\n') {
        l->buf[l->n - 1u] = '\n';
    }
    pdt_port_write(l->buf, l->n);
}

int t_verdict(bool ok, tline_t *detail)
{
    tline_t out;
    tl_init(&out);
    tl_str(&out, ok ? "PASS " : "FAIL ");
    for (size_t i = 0; i < detail->n; i++) {
        tl_char(&out, detail->buf[i]);
    }
    tl_emit(&out);
    g_run++;
    if (!ok) {
        g_failed++;
    }
    return ok ? 0 : 1;
}

void t_info(tline_t *detail)
{
    tline_t out;
    tl_init(&out);
    tl_str(&out, "info ");
    for (size_t i = 0; i < detail->n; i++) {
        tl_char(&out, detail->buf[i]);
    }
    tl_emit(&out);
}

uint64_t t_ticks_to_instructions(uint64_t ticks)
{
    /* ticks * 1e9 / hz without overflow for any run shorter than 2^64 ns */
    uint64_t hz = pdt_port_ticks_per_second();
    return hz == 0u ? 0u : ticks / hz * 1000000000u + ticks % hz * 1000000000u / hz;
}

unsigned t_checks_run(void)
{
    return g_run;
}

unsigned t_checks_failed(void)
{
    return g_failed;
}

void t_stack_repaint(void)
{
    (void)t_stack_max();
    pdt_port_stack_paint();
}

size_t t_stack_max(void)
{
    size_t used = pdt_port_stack_used();
    if (used > g_stack_max) {
        g_stack_max = used;
    }
    return g_stack_max;
}
