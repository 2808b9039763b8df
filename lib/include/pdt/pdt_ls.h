/*
 * pdtfit least-squares delay scans: the "extended" least-squares methods
 * the paper's Part One compares with the genetic algorithm, ELMS and
 * E-IV-LMS, for a FOPDT or SOPDT model with a whole-sample dead time.
 *
 * For every integer delay l in [delay_min, delay_max] the scan fits the
 * paper's prediction model (pdt_discrete.h convention: y(k) depends on
 * u(k-1-l), so Td = l Ts)
 *   FOPDT (3): y(k) = alpha y(k-1) + beta u(k-l-1) + c
 *   SOPDT (5): y(k) = -a1 y(k-1) - a2 y(k-2) + b1 u(k-l-1) + b2 u(k-l-2) + c
 * where u is the deviation of the input from its operating point u0 = u[0]
 * and the constant c carries the unknown output operating point. The fit is
 *  - ELMS: ordinary least squares of the one-step prediction;
 *  - EIV: instrumental variables. The instruments are the input terms, the
 *    constant and, in place of the measured past outputs, the output of an
 *    auxiliary model: the ELMS estimate of the same delay simulated from rest
 *    on the input alone. Output noise then no longer biases the estimate.
 * Every delay is scored by the mean squared one-step prediction residual of
 * its estimate over one common window of samples, and the delay with the
 * smallest score wins (the smaller delay on a tie). The discrete estimate is
 * then turned into the continuous model: FOPDT tau = -Ts / ln(alpha),
 * K = beta / (1 - alpha); SOPDT in form (2) from the continuous poles
 * ln(z) / Ts of the discrete ones and the DC gain (b1 + b2) / (1 + a1 + a2).
 * A delay whose estimate has no such form is skipped: alpha outside (0, 1),
 * a real discrete pole outside (0, 1) (an integrating, unstable or
 * oscillating-every-sample estimate), a complex pair on or outside the unit
 * circle. Integrating processes are for pdt_ident. docs/ls.md gives the
 * equations and the numerics.
 *
 * Memory: the context alone (no workspace); the data stay in the caller's
 * arrays. Work: O(n) per delay, a few passes over the record.
 */
#ifndef PDT_LS_H
#define PDT_LS_H

#include "pdt/pdt_common.h"
#include "pdt/pdt_discrete.h"
#include "pdt/pdt_model.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum pdt_ls_method {
    PDT_LS_ELMS = 0, /* least squares per delay */
    PDT_LS_EIV = 1   /* instrumental variables per delay (E-IV-LMS) */
} pdt_ls_method_t;

typedef struct pdt_ls_config {
    pdt_model_kind_t model; /* FOPDT or SOPDT. Default FOPDT */
    pdt_ls_method_t method; /* Default ELMS */
    pdt_real_t Ts;          /* sampling period, s; finite and > 0. Default 0
                              * (must be set) */
    size_t delay_min;       /* l_l, samples. Default 0 */
    size_t delay_max;       /* l_u, samples. Default PDT_DELAY_QUARTER: n / 4
                              * (the paper's window loses the first l_u
                              * samples; a quarter keeps three quarters) */
    bool whole_record;      /* score on k = order .. n-1 instead of the
                              * paper's k = delay_max + order .. n-1, taking
                              * the input at rest (u0) before sample 0; for
                              * records that start with a step at steady
                              * state. Default false (the paper) */
} pdt_ls_config_t;

typedef struct pdt_ls_result {
    pdt_model_t model;     /* continuous model, Td = delay Ts */
    pdt_discrete_t dmodel; /* the estimate as a discrete model of the
                           * deviations from (u0, y0), pdt_discrete.h
                           * convention (b[2] = 0); usable with
                           * pdt_discrete_simulate and pdt_cost_* */
    pdt_real_t u0;         /* input operating point: u[0] */
    pdt_real_t y0;         /* output operating point: the estimate's steady
                           * output at u = u0, c / (1 + a1 + a2) (FOPDT
                           * c / (1 - alpha)) */
    pdt_real_t cost;       /* score of the chosen delay: mean squared one-step
                           * residual, output units squared */
    size_t delay;          /* chosen l, samples */
    size_t skipped;        /* delays of the scan without a model */
} pdt_ls_result_t;

/* The scan context. Fields are private. */
typedef struct pdt_ls {
    pdt_ls_config_t cfg; /* copy, delay_max resolved */
    const pdt_real_t *u; /* caller's data */
    const pdt_real_t *y;
    size_t n;
    size_t k0;      /* first scored sample */
    uint32_t magic; /* set by init: catches use before init */
    bool done;
    size_t next;     /* next delay to fit */
    size_t singular; /* delays skipped: no unique solution */
    size_t noform;   /* delays skipped: no continuous form */
    bool found;
    pdt_ls_result_t best;
    pdt_real_t *scores; /* pdt_ls_scores: caller memory, or NULL */
} pdt_ls_t;

/* Fills cfg with the documented defaults (Ts left 0). Nothing for NULL. */
void pdt_ls_config_default(pdt_ls_config_t *cfg);

/* Prepares ctx for a scan of the record u[0..n-1], y[0..n-1] (engineering
 * units, sampled every cfg->Ts s, at steady state at sample 0). ctx keeps
 * pointers to u and y: they must stay valid and unchanged until the scan is
 * done. No delay is fitted here; O(n) checks.
 * Returns, checked in this order:
 *  PDT_ERR_ARG           NULL ctx, cfg, u or y; Ts not finite and > 0; an
 *                        unknown model or method;
 *  PDT_ERR_TOO_SHORT     delay_max (resolved) >= n, or fewer than
 *                        PDT_MIN_SAMPLES scored samples (n - delay_max -
 *                        order, or n - order with whole_record);
 *  PDT_ERR_BOUNDS        delay_min > delay_max (resolved);
 *  PDT_ERR_NONFINITE     NaN or infinity in u or y;
 *  PDT_ERR_NO_EXCITATION u or y constant over the record.
 * ctx is untouched on error. */
pdt_status_t pdt_ls_init(pdt_ls_t *ctx, const pdt_ls_config_t *cfg, const pdt_real_t *u,
                         const pdt_real_t *y, size_t n);

/* Fits at most max_delays more delays (each O(n): three passes over the
 * record for ELMS, five for EIV, and one or two 2x2 or 4x4 solves),
 * writing their scores where pdt_ls_scores asked. Returns PDT_RUNNING while
 * delays remain, PDT_OK
 * once all are done (also on every later call), PDT_ERR_ARG for NULL or
 * max_delays = 0, PDT_ERR_STATE if ctx was not initialised. */
pdt_status_t pdt_ls_step(pdt_ls_t *ctx, size_t max_delays);

/* Asks the scan to write the score of every delay it fits into
 * scores[l - delay_min], l = delay_min .. delay_max (resolved): the
 * score, or +infinity for a delay without a model. Call after pdt_ls_init
 * and before the first pdt_ls_step. scores is caller memory of at least
 * delay_max - delay_min + 1 reals, written only by pdt_ls_step, and must
 * not overlap the data. Returns PDT_OK, PDT_ERR_ARG for NULL,
 * PDT_ERR_STATE when ctx is not initialised or the scan has begun,
 * PDT_ERR_LENGTH when len is too small; ctx is untouched on error. */
pdt_status_t pdt_ls_scores(pdt_ls_t *ctx, pdt_real_t *scores, size_t len);

/* The best delay's model once pdt_ls_step has returned PDT_OK. Returns
 * PDT_OK, PDT_ERR_ARG for NULL, PDT_ERR_STATE before the scan is done,
 * PDT_ERR_NO_EXCITATION when no delay had a unique solution (the scored
 * window does not excite the model: e.g. the input does not move after
 * delay_max), PDT_ERR_NO_FORM when some had one but none had a continuous
 * form. *out is written only on PDT_OK. O(1). */
pdt_status_t pdt_ls_result(const pdt_ls_t *ctx, pdt_ls_result_t *out);

/* Blocking convenience: init, step until done, result. Same statuses as
 * those three; *out is written only on PDT_OK. O(n (delays)). */
pdt_status_t pdt_ls_identify(pdt_ls_t *ctx, const pdt_ls_config_t *cfg, const pdt_real_t *u,
                             const pdt_real_t *y, size_t n, pdt_ls_result_t *out);

#ifdef __cplusplus
}
#endif

#endif /* PDT_LS_H */
