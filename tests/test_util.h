/*
 * Helpers of the CMocka tests: tolerances per real type and the asserting
 * forms of the shared measures (tests/support/test_measure.h).
 */
#ifndef PDT_TEST_UTIL_H
#define PDT_TEST_UTIL_H

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "pdt/pdt.h"
#include "test_measure.h"

/* Relative tolerance a routine of the library is expected to meet against
 * the double-precision reference, for the build's real type. */
#if PDT_REAL_DOUBLE
#define TEST_RTOL 1e-9
#else
#define TEST_RTOL 2e-4
#endif

/* Asserts that p[0..n-1] still hold the canary: nothing was written there. */
static inline void canary_check(const pdt_real_t *p, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        if (p[i] != CANARY_VALUE) {
            fail_msg("canary %zu overwritten", i);
        }
    }
}

/* |got - want| <= atol + rtol |want|, with a readable failure message. */
#define assert_close(got, want, rtol, atol)                                                        \
    assert_close_at((double)(got), (double)(want), (rtol), (atol), #got, __FILE__, __LINE__)

static inline void assert_close_at(double got, double want, double rtol, double atol,
                                   const char *what, const char *file, int line)
{
    double err = fabs(got - want);
    if (!(err <= atol + rtol * fabs(want))) {
        fail_msg("%s:%d: %s = %.17g, want %.17g (err %.3g, rtol %.3g, atol %.3g)", file, line, what,
                 got, want, err, rtol, atol);
    }
}

#endif /* PDT_TEST_UTIL_H */
