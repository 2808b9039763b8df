/*
 * pdtfit discretisation: the zero-order-hold (ZOH) sampled model of a FOPDT or
 * SOPDT, and simulation / one-step prediction over sample arrays.
 *
 * Convention. With Td = (l + f) Ts, l an integer >= 0 and 0 <= f < 1, the
 * exact ZOH model is
 *
 *   A(q) y(k) = B(q) u(k),   q = unit delay,
 *   A(q) = 1 + a[0] q + a[1] q^2            (a[1] = 0 for a FOPDT)
 *   B(q) = (b[0] q + b[1] q^2 + b[2] q^3) q^l
 *
 * i.e. y(k) depends on u(k-1-l) ... u(k-3-l). The "1" in k-1-l is the hold:
 * a sample taken at k cannot see the input applied at k. For f = 0 the last
 * numerator term is zero, and the model is the paper's prediction model (3)
 * (FOPDT: y(k) = alpha y(k-1) + beta u(k-l-1)) or (5) (SOPDT: two input
 * terms u(k-l-1), u(k-l-2)). So the paper's integer delay l means Td = l Ts.
 *
 * All signals are deviations from the operating point; the system is at rest
 * before sample 0 (u and y are 0 for k < 0).
 */
#ifndef PDT_DISCRETE_H
#define PDT_DISCRETE_H

#include "pdt/pdt_common.h"
#include "pdt/pdt_model.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pdt_discrete {
    size_t delay;    /* l: whole samples of dead time */
    uint8_t order;   /* 1 (FOPDT) or 2 (SOPDT): number of used a[] */
    pdt_real_t a[2]; /* A(q) = 1 + a[0] q + a[1] q^2 */
    pdt_real_t b[3]; /* B(q) = (b[0] q + b[1] q^2 + b[2] q^3) q^l */
    /* The same A(q) written around q = 1, kept because near-1 poles make
     * a[] lose the small numbers that set the gain:
     *   A(q) = (1 - q)^2 + d[0] q (1 - q) + d[1] q^2         (order 2)
     *   A(q) = (1 - q) + d[0] q                              (order 1)
     * so d[1] = 1 + a[0] + a[1] (order 2), d[0] = 1 + a[0] (order 1).
     * The simulation and prediction use d[]; a[] is for the caller. */
    pdt_real_t d[2];
} pdt_discrete_t;

/* Exact ZOH discretisation of m at sampling period Ts (s, > 0), with the
 * fractional part of the dead time carried by the third numerator term.
 * Returns PDT_ERR_ARG for NULL, an invalid model, or Ts not finite and > 0.
 * Dead times beyond SIZE_MAX samples are also PDT_ERR_ARG. */
pdt_status_t pdt_discrete_init(const pdt_model_t *m, pdt_real_t Ts, pdt_discrete_t *out);

/* The paper's integer-delay prediction model (3) / (5): the ZOH
 * discretisation of m with its dead time replaced by exactly l Ts. m's own
 * Td is ignored. Same errors as pdt_discrete_init. */
pdt_status_t pdt_discrete_init_int(const pdt_model_t *m, pdt_real_t Ts, size_t l,
                                   pdt_discrete_t *out);

/* Simulation (output error): y[k] for k = 0..n-1 from u[0..n-1], the model
 * fed its own past outputs, from rest. y must not overlap u.
 * Returns PDT_ERR_ARG for NULL or an order other than 1 or 2. */
pdt_status_t pdt_discrete_simulate(const pdt_discrete_t *d, const pdt_real_t *u, size_t n,
                                   pdt_real_t *y);

/* One-step prediction (equation error): yhat[k] from the measured y[k-1],
 * y[k-2] and u, for k = 0..n-1, with y and u taken as 0 before sample 0.
 * yhat must not overlap u or y. Same errors as pdt_discrete_simulate. */
pdt_status_t pdt_discrete_predict(const pdt_discrete_t *d, const pdt_real_t *u, const pdt_real_t *y,
                                  size_t n, pdt_real_t *yhat);

/* The simulation's state between samples (pdt_discrete_step); all 0 is
 * rest. */
typedef struct pdt_discrete_state {
    pdt_real_t y1; /* y(k-1) */
    pdt_real_t y2; /* y(k-2) */
    pdt_real_t dy; /* y(k-1) - y(k-2), carried (see pdt_discrete_simulate) */
} pdt_discrete_state_t;

/* Sample k of the simulation from rest of d on the input u[0..k] taken
 * relative to u0 (u - u0), given the state after sample k - 1 (all 0
 * before sample 0), which it advances: the same numbers as
 * pdt_discrete_simulate on u - u0, one sample at a time and no array,
 * for models simulated side by side. No checks (d from
 * pdt_discrete_init, s and u not NULL, k in order); O(1). */
pdt_real_t pdt_discrete_step(const pdt_discrete_t *d, pdt_discrete_state_t *s, const pdt_real_t *u,
                             pdt_real_t u0, size_t k);

#ifdef __cplusplus
}
#endif

#endif /* PDT_DISCRETE_H */
