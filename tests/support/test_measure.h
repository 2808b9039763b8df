/*
 * The measures and guards every pdtfit test uses, on the host (CMocka,
 * tests/test_util.h) and on the target (tests/target): canaries after
 * output buffers, SNR and error against reference vectors, and the models a
 * vector row describes. C99, no stdio, no test framework.
 */
#ifndef PDT_TEST_MEASURE_H
#define PDT_TEST_MEASURE_H

#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <string.h>

#include "pdt/pdt.h"

/* Guard elements written after each output buffer: nothing may be written
 * there. */
#define CANARY_COUNT 8
#define CANARY_VALUE ((pdt_real_t)-31415.9265)

static inline void canary_fill(pdt_real_t *p, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        p[i] = CANARY_VALUE;
    }
}

/* True when p[0..n-1] still hold the canary. */
static inline bool canary_intact(const pdt_real_t *p, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        if (p[i] != CANARY_VALUE) {
            return false;
        }
    }
    return true;
}

/* 10 log10(sum ref^2 / sum (got - ref)^2) in dB; 400 for an exact match. */
static inline double snr_db(const pdt_real_t *got, const double *ref, size_t n)
{
    double sig = 0.0;
    double err = 0.0;
    for (size_t i = 0; i < n; i++) {
        double e = (double)got[i] - ref[i];
        sig += ref[i] * ref[i];
        err += e * e;
    }
    return (err == 0.0) ? 400.0 : 10.0 * log10(sig / err);
}

/* Largest |got - ref|. */
static inline double max_abs_err(const pdt_real_t *got, const double *ref, size_t n)
{
    double e = 0.0;
    for (size_t i = 0; i < n; i++) {
        e = fmax(e, fabs((double)got[i] - ref[i]));
    }
    return e;
}

/* Largest |ref|. */
static inline double peak_abs(const double *ref, size_t n)
{
    double p = 0.0;
    for (size_t i = 0; i < n; i++) {
        p = fmax(p, fabs(ref[i]));
    }
    return p;
}

/* |got - want| / |want|, or |got - want| when want is 0. */
static inline double rel_err(double got, double want)
{
    double e = fabs(got - want);
    return (want == 0.0) ? e : e / fabs(want);
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

/* The cost configuration of a generated vector set s (cost_vectors.h and
 * cost_profile_vectors.h name these fields alike): the defaults, then the
 * set's period, operating point, dead-time range and band. */
#define VECTOR_COST_CONFIG(cfg, s)                                                                 \
    vector_cost_config((cfg), (s)->Ts, (s)->u0, (s)->y0, (s)->delay_min, (s)->delay_max,           \
                       (s)->delay_max_auto != 0, (s)->f_lo, (s)->f_hi)

static inline void vector_cost_config(pdt_cost_config_t *cfg, double Ts, double u0, double y0,
                                      size_t delay_min, size_t delay_max, bool delay_max_auto,
                                      double f_lo, double f_hi)
{
    pdt_cost_config_default(cfg);
    cfg->Ts = (pdt_real_t)Ts;
    cfg->u0 = (pdt_real_t)u0;
    cfg->y0 = (pdt_real_t)y0;
    cfg->delay_min = delay_min;
    cfg->delay_max = delay_max_auto ? PDT_DELAY_HALF : delay_max;
    cfg->f_lo = (pdt_real_t)f_lo;
    cfg->f_hi = (pdt_real_t)f_hi;
}

#endif /* PDT_TEST_MEASURE_H */
