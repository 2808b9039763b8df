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

/* Two reals bit for bit. */
static inline void assert_same_real(pdt_real_t a, pdt_real_t b, const char *what)
{
    if (memcmp(&a, &b, sizeof a) != 0) {
        fail_msg("%s differs: %.17g vs %.17g", what, (double)a, (double)b);
    }
}

/* Two models field by field, bit for bit: memory compares would read the
 * padding and a FOPDT's unused union slot, which hold whatever the stack
 * held (equal on one machine, not on another). */
static inline void assert_same_model(const pdt_model_t *a, const pdt_model_t *b)
{
    assert_int_equal(a->kind, b->kind);
    if (a->kind == PDT_MODEL_FOPDT) {
        assert_same_real(a->p.fopdt.K, b->p.fopdt.K, "K");
        assert_same_real(a->p.fopdt.tau, b->p.fopdt.tau, "tau");
        assert_same_real(a->p.fopdt.Td, b->p.fopdt.Td, "Td");
    } else {
        assert_same_real(a->p.sopdt.k, b->p.sopdt.k, "k");
        assert_same_real(a->p.sopdt.a, b->p.sopdt.a, "a");
        assert_same_real(a->p.sopdt.b, b->p.sopdt.b, "b");
        assert_same_real(a->p.sopdt.Td, b->p.sopdt.Td, "Td");
    }
}

/* Two identifications' answers field by field, bit for bit (the structs
 * may hold padding, which an assignment copies from wherever it was). */
static inline void assert_same_ident(const pdt_ident_result_t *a, const pdt_ident_result_t *b)
{
    assert_same_model(&a->model, &b->model);
    assert_same_real(a->u0, b->u0, "u0");
    assert_same_real(a->y0, b->y0, "y0");
    assert_same_real(a->cost, b->cost, "cost");
    assert_same_real(a->fit, b->fit, "fit");
    assert_int_equal(a->evaluations, b->evaluations);
    assert_int_equal(a->generations, b->generations);
    assert_same_real(a->f_band, b->f_band, "f_band");
    assert_int_equal(a->flags, b->flags);
    assert_same_real(a->evidence, b->evidence, "evidence");
    assert_memory_equal(&a->std, &b->std, sizeof a->std);
}

#endif /* PDT_TEST_UTIL_H */
