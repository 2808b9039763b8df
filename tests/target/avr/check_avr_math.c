/*
 * expm1 and log1p on the AVR: avr-libc has neither, so the library uses
 * its own (lib/src/pdt_math.c over avr-libc's exp and log). Checked against
 * numpy over tests/vectors/math_vectors.h, read from flash, with the host
 * test's bound (tests/test_math.c) where the library calls them: expm1 of
 * x <= 0 (every call is e^{-t/T} - 1) and log1p everywhere. Above 0,
 * expm1(x) is e^x - 1 to rounding and carries avr-libc's exp's own error,
 * which grows with x (tens of ulps at x = 30): there the bound is that
 * error plus the host's.
 */
#include <math.h>

#include "avr_checks.h"
#include "pdt_internal.h"
#include "target_util.h"

#define const const __flash
#include "math_vectors.h"
#undef const

#if !PDT_MATH_FALLBACK
#error "avr-libc has no expm1/log1p: the AVR build must use the library's own"
#endif

/* The host test's bound, in ulps of float. */
#define MATH_ULPS 4.0

static double ulps(double got, double want)
{
    const double scale = fabs(want) > 0.0 ? fabs(want) : 1.0;
    return fabs(got - want) / (scale * (double)PDT_REAL_EPS);
}

/* The largest error of fn over the table's arguments x <= 0 (returned)
 * and above 0 (*above), and in *excess the most any lies beyond its bound
 * (<= 0 when all pass). For expm1 above 0 the bound adds avr-libc's exp's
 * error there. */
static double worst_ulps(pdt_real_t (*fn)(pdt_real_t), const __flash double *x,
                         const __flash double *y, size_t n, bool is_expm1, double *above,
                         double *excess)
{
    double worst = 0.0;
    *above = 0.0;
    *excess = -MATH_ULPS;
    for (size_t i = 0; i < n; i++) {
        const double want = y[i];
        const double e = ulps((double)fn((pdt_real_t)x[i]), want);
        double allowed = MATH_ULPS;
        if (is_expm1 && x[i] > 0.0) {
            allowed += ulps((double)pdt_exp((pdt_real_t)x[i]), want + 1.0);
        }
        if (x[i] > 0.0) {
            *above = e > *above || isnan(e) ? e : *above;
        } else {
            worst = e > worst || isnan(e) ? e : worst;
        }
        *excess = e - allowed > *excess || isnan(e) ? e - allowed : *excess;
    }
    return worst;
}

static int check_one(const char *name, pdt_real_t (*fn)(pdt_real_t), const __flash double *x,
                     const __flash double *y, size_t n, bool is_expm1)
{
    double excess = 0.0;
    double above = 0.0;
    const double worst = worst_ulps(fn, x, y, n, is_expm1, &above, &excess);
    tline_t l;
    tl_init(&l);
    tl_str(&l, name);
    TL_STR(&l, ": ");
    tl_uint(&l, n);
    TL_STR(&l, " arguments, largest error ");
    tl_num(&l, worst, 3);
    TL_STR(&l, " ulps at x <= 0, ");
    tl_num(&l, above, 3);
    TL_STR(&l, " above 0");
    if (is_expm1) {
        TL_STR(&l, " ulps (max 4, above 0 4 more than avr-libc's exp)");
    } else {
        TL_STR(&l, " ulps (max 4)");
    }
    return t_verdict(excess <= 0.0, &l);
}

int avr_check_math(void)
{
    return check_one("pdt_math_expm1", pdt_math_expm1, math_expm1_x, math_expm1_y, MATH_EXPM1_COUNT,
                     true) +
           check_one("pdt_math_log1p", pdt_math_log1p, math_log1p_x, math_log1p_y, MATH_LOG1P_COUNT,
                     false);
}
