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

#include "pdt/pdt_discrete.h"
#include "pdt/pdt_model.h"
#include "pdt_internal.h"

/* Parameters: the model's (FOPDT K, tau, Td; SOPDT k, a, b, Td), then the
 * output offset. */
#define PDT_FISHER_MAX 5u

/* Lags of the residual's autocorrelation (PDT_VALIDATE_LAGS); a multiple
 * of four (with vector lanes pdt_fisher.c takes them four a turn). */
#define PDT_FISHER_LAGS 20u

typedef pdt_real_t pdt_fisher_matrix_t[PDT_FISHER_MAX][PDT_FISHER_MAX];
/* One row of it. */
typedef pdt_real_t pdt_fisher_row_t[PDT_FISHER_MAX];

/* Where the host has vector lanes the ring of recent residuals is written
 * twice, LAGS apart, so that the lags are one contiguous run: four a turn
 * in a vector, no wrap. A Cortex-M has no lanes and keeps its stack: one
 * ring, two runs. */
#if PDT_VECTOR_LANES == 4
#define PDT_FISHER_RING_TWICE 1
#define PDT_FISHER_RING_LEN   (2u * PDT_FISHER_LAGS)
#else
#define PDT_FISHER_RING_TWICE 0
#define PDT_FISHER_RING_LEN   PDT_FISHER_LAGS
#endif

/* The residual's lagged products: the running state of one pass. */
typedef struct pdt_fisher_lags {
    /* e(k - 1 - i) at recent[at + i] (modulo LAGS in the one ring) for
     * i = 0 .. LAGS - 1 before sample k is added: the ring is written
     * backwards. Before the record's LAGS-th sample it holds zeros, whose
     * products add +-0 to the sums, which leaves them as they were, so
     * every lag is summed from the first sample on. */
    pdt_real_t recent[PDT_FISHER_RING_LEN];
    pdt_real_t first[PDT_FISHER_LAGS + 1u]; /* sums of the first i residuals */
    pdt_real_t prod[PDT_FISHER_LAGS];       /* sum of e(k) e(k - l) */
    pdt_real_t sum, part_sum;               /* sum of e, its block part */
    size_t at;
} pdt_fisher_lags_t;

/* The running state of the pass: the nominal model and one perturbed
 * model per shape parameter simulated side by side. */
typedef struct pdt_fisher_pass {
    pdt_discrete_t d[4];
    pdt_discrete_state_t s[4];
    pdt_real_t h[4]; /* the shape parameters' steps */
    pdt_real_t gain; /* the nominal gain: the gain's column is ys / K */
    pdt_real_t u0;   /* the input before the record */
} pdt_fisher_pass_t;

/* A pass over the record taken a block at a time (pdt_fisher_begin,
 * pdt_fisher_block, pdt_fisher_end): all its state, so that a caller can
 * keep it in its own memory between the blocks. */
typedef struct pdt_fisher_run {
    pdt_fisher_pass_t P;
    pdt_fisher_lags_t L;
    pdt_fisher_row_t *F; /* the caller's matrix, summed into */
    const pdt_real_t *u;
    const pdt_real_t *y;
    size_t n;
    size_t next; /* the next block's first sample */
    size_t full; /* from this sample on every input tap has arrived */
    pdt_real_t y0;
    pdt_real_t se; /* the residual's sum of squares, whole blocks */
    uint32_t nm;   /* the model's parameters (without y0) */
    bool finite;
} pdt_fisher_run_t;

/* Samples of one pdt_fisher_block call. */
#define PDT_FISHER_BLOCK 256u

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

/* pdt_fisher_sum a block at a time: begin checks and sets up the models
 * (PDT_ERR_ARG as pdt_fisher_sum) and zeroes F, which R then refers to
 * (F must outlive R); each block adds the next PDT_FISHER_BLOCK samples
 * (O(PDT_FISHER_BLOCK) per parameter plus O(PDT_FISHER_BLOCK LAGS)) and
 * returns true once the record is complete; end gives what pdt_fisher_sum
 * gives (PDT_ERR_NONFINITE, or PDT_OK with F symmetric and *out filled).
 * The same operations in the same order as pdt_fisher_sum: the same
 * numbers. */
pdt_status_t pdt_fisher_begin(pdt_fisher_run_t *R, const pdt_model_t *m, pdt_real_t Ts,
                              const pdt_real_t *u, const pdt_real_t *y, size_t n, pdt_real_t y0,
                              pdt_real_t u0, pdt_fisher_matrix_t F);
bool pdt_fisher_block(pdt_fisher_run_t *R);
pdt_status_t pdt_fisher_end(pdt_fisher_run_t *R, pdt_fisher_sums_t *out);

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
