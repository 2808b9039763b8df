/*
 * The output-error Fisher information of a FOPDT or SOPDT at its estimate
 * and the covariance it gives, private to the library: the identification
 * reports the parameters' standard deviations with its answer, and the
 * validation inflates them for a coloured residual. Fixed memory: the
 * sensitivities are simulated side by side, sample by sample, and never
 * stored.
 */
#ifndef PDT_FISHER_H
#define PDT_FISHER_H

#include "pdt/pdt_model.h"

/* Parameters: the model's (FOPDT K, tau, Td; SOPDT k, a, b, Td), then the
 * output offset. */
#define PDT_FISHER_MAX 5u

/* Lags of the residual's autocorrelation (PDT_VALIDATE_LAGS); a multiple
 * of four (with vector lanes pdt_fisher.c takes them four a turn). */
#define PDT_FISHER_LAGS 20u

typedef pdt_real_t pdt_fisher_matrix_t[PDT_FISHER_MAX][PDT_FISHER_MAX];

/* What one pass over the record gives besides F. */
typedef struct pdt_fisher_sums {
    pdt_real_t sse;                  /* the residual's sum of squares */
    uint32_t np;                     /* parameters */
    pdt_real_t rho[PDT_FISHER_LAGS]; /* autocorrelations of the mean-free
                                       * residual at lags 1 .. LAGS (0 past
                                       * the record or for a zero residual) */
} pdt_fisher_sums_t;

/* J^T J (without 1 / sigma^2) of the simulated output of m (gain not 0) at
 * sampling period Ts on the record u, y of n samples, input relative to
 * u0 (the input before the record, u[0] unless given), output to y0, with the Jacobian's shape columns by forward
 * differences; the residual's sums into *out. Returns PDT_ERR_ARG when m
 * or a perturbed model cannot be discretised, PDT_ERR_NONFINITE when the
 * simulation overflows; O(n) per parameter plus O(n LAGS), no memory
 * beyond the stack. */
pdt_status_t pdt_fisher_sum(const pdt_model_t *m, pdt_real_t Ts, const pdt_real_t *u,
                            const pdt_real_t *y, size_t n, pdt_real_t y0, pdt_real_t u0,
                            pdt_fisher_matrix_t F, pdt_fisher_sums_t *out);

/* The covariance's factor for a correlated residual, 1 + 2 sum of its
 * autocorrelations (its long-run variance over its variance), >= 1. */
pdt_real_t pdt_fisher_inflation(const pdt_fisher_sums_t *s);

/* The covariance sigma^2 inflation F^-1, sigma^2 = sse / (n - np), into cov
 * and the standard deviations into sd (np of each; F is only read). A parameter the data
 * do not determine (a pivot of F's correlation form below 1e3 eps) is held
 * at its estimate: std +infinity, covariance row and column 0, the others'
 * conditional on it. An F without a usable diagonal gives +infinity
 * everywhere. */
void pdt_fisher_covariance(pdt_fisher_matrix_t F, uint32_t np, size_t n, pdt_real_t sse,
                           pdt_real_t inflation, pdt_real_t *sd, pdt_fisher_matrix_t cov);

#endif /* PDT_FISHER_H */
