/*
 * Shared helpers for the CMocka tests: tolerances per real type, canaries
 * after output buffers, SNR against reference vectors.
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

/* Relative tolerance a routine of the library is expected to meet against
 * the double-precision reference, for the build's real type. */
#if PDT_REAL_DOUBLE
#define TEST_RTOL 1e-9
#else
#define TEST_RTOL 2e-4
#endif

/* Number of guard elements written after each output buffer. */
#define CANARY_COUNT 8
#define CANARY_VALUE ((pdt_real_t)-31415.9265)

static inline void canary_fill(pdt_real_t *p, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        p[i] = CANARY_VALUE;
    }
}

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
#define assert_close(got, want, rtol, atol) \
    assert_close_at((double)(got), (double)(want), (rtol), (atol), #got, __FILE__, __LINE__)

static inline void assert_close_at(double got, double want, double rtol, double atol,
                                   const char *what, const char *file, int line)
{
    double err = fabs(got - want);
    if (!(err <= atol + rtol * fabs(want))) {
        fail_msg("%s:%d: %s = %.17g, want %.17g (err %.3g, rtol %.3g, atol %.3g)", file,
                 line, what, got, want, err, rtol, atol);
    }
}

/* Signal-to-noise ratio of got against ref in dB: 10 log10(sum ref^2 /
 * sum (got - ref)^2); 400 dB for an exact match. */
static inline double snr_db(const pdt_real_t *got, const double *ref, size_t n)
{
    double sig = 0.0;
    double err = 0.0;
    for (size_t i = 0; i < n; i++) {
        double e = (double)got[i] - ref[i];
        sig += ref[i] * ref[i];
        err += e * e;
    }
    if (err == 0.0) {
        return 400.0;
    }
    return 10.0 * log10(sig / err);
}

/* The model a vector row describes: kind 1 is a FOPDT (p: K, tau, Td),
 * kind 2 a SOPDT in form (2) (p: k, a, b, Td). */
static inline pdt_model_t vector_model(int kind, const double *p)
{
    pdt_model_t m;
    memset(&m, 0, sizeof m);
    if (kind == 1) {
        m.kind = PDT_MODEL_FOPDT;
        m.p.fopdt.K = (pdt_real_t)p[0];
        m.p.fopdt.tau = (pdt_real_t)p[1];
        m.p.fopdt.Td = (pdt_real_t)p[2];
    } else {
        m.kind = PDT_MODEL_SOPDT;
        m.p.sopdt.k = (pdt_real_t)p[0];
        m.p.sopdt.a = (pdt_real_t)p[1];
        m.p.sopdt.b = (pdt_real_t)p[2];
        m.p.sopdt.Td = (pdt_real_t)p[3];
    }
    return m;
}

/* The discrete model a vector row describes: coef holds a[0], a[1], b[0],
 * b[1], b[2], d[0], d[1]. */
static inline pdt_discrete_t vector_dmodel(int order, int delay, const double *coef)
{
    pdt_discrete_t d;
    memset(&d, 0, sizeof d);
    d.order = (uint8_t)order;
    d.delay = (size_t)delay;
    d.a[0] = (pdt_real_t)coef[0];
    d.a[1] = (pdt_real_t)coef[1];
    for (int j = 0; j < 3; j++) {
        d.b[j] = (pdt_real_t)coef[2 + j];
    }
    d.d[0] = (pdt_real_t)coef[5];
    d.d[1] = (pdt_real_t)coef[6];
    return d;
}

#endif /* PDT_TEST_UTIL_H */
