/*
 * pdtfit model validation: what the data say about an identified model,
 * beyond its fit. The standard output-error tests (Ljung 1999, ch. 16):
 *
 *  - whiteness: the residual e = y - y0 - ysim should be uncorrelated with
 *    itself at lags 1..PDT_VALIDATE_LAGS (portmanteau statistic, chi-square
 *    with PDT_VALIDATE_LAGS degrees of freedom);
 *  - independence from past inputs: an FIR of PDT_VALIDATE_FIR taps of the
 *    input is fitted to the residual (the "model error model" of Ljung and
 *    Guo); its explained sum of squares over the residual variance is
 *    chi-square with PDT_VALIDATE_FIR degrees of freedom when the model is
 *    right. The FIR is kept: its frequency response is the model error the
 *    data show (e.g. the high-frequency gain a lead adds to a FOPDT);
 *  - parameter uncertainty: the covariance of the parameters from the
 *    output-error Fisher information at the optimum, J^T J / sigma^2, with
 *    the sensitivities J of the simulated output by finite differences and
 *    sigma^2 from the residual; inflated by the residual's long-run
 *    variance factor when the residual is correlated;
 *  - information criteria (AIC, BIC) of the output error, for the choice of
 *    model order (pdt_ident_select_order).
 *
 * pdt_validate_margin turns the result into a robust bound on the true
 * loop's maximum sensitivity for given gains: the nominal loop's |S| with
 * the model error of the FIR and of the parameters' confidence region
 * added as an additive uncertainty.
 *
 * Fixed memory: a caller workspace of PDT_VALIDATE_WORKSPACE_SIZE(n) bytes
 * (5 n reals), no heap, no recursion.
 */
#ifndef PDT_VALIDATE_H
#define PDT_VALIDATE_H

#include "pdt/pdt_common.h"
#include "pdt/pdt_ident.h"
#include "pdt/pdt_model.h"
#include "pdt/pdt_tune.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Lags of the whiteness test. */
#define PDT_VALIDATE_LAGS       20u
/* Taps of the model-error FIR (the independence test). */
#define PDT_VALIDATE_FIR        12u
/* Most parameters: SOPDT k, a, b, Td and the output offset y0. */
#define PDT_VALIDATE_MAX_PARAMS PDT_IDENT_MAX_PARAMS

/* Workspace bytes for n samples: five records of reals. */
#define PDT_VALIDATE_WORKSPACE_SIZE(n) (5u * (size_t)(n) * sizeof(pdt_real_t))

/* The validation in steps (pdt_validate_begin, pdt_validate_step): its
 * state's bytes at the head of the workspace (an upper bound, checked when
 * the library is built), the FIR's rows of one step, and the workspace:
 * the state and three records of reals, at least
 * PDT_VALIDATE_WORKSPACE_SIZE(n) (so that one workspace serves both
 * forms). */
#define PDT_VALIDATE_RUN_STATE_SIZE (430u * sizeof(pdt_real_t) + 24u * sizeof(void *) + 64u)
#define PDT_VALIDATE_FIR_ROWS       128u
#define PDT_VALIDATE_RUN_WORKSPACE_SIZE(n)                                                         \
    (PDT_VALIDATE_RUN_STATE_SIZE + 3u * (size_t)(n) * sizeof(pdt_real_t) >                         \
             PDT_VALIDATE_WORKSPACE_SIZE(n)                                                        \
         ? PDT_VALIDATE_RUN_STATE_SIZE + 3u * (size_t)(n) * sizeof(pdt_real_t)                     \
         : PDT_VALIDATE_WORKSPACE_SIZE(n))

typedef struct pdt_validate_result {
    pdt_model_t model;                /* the model validated */
    pdt_real_t Ts;                    /* its sampling period, s */
    size_t n;                         /* samples */
    pdt_real_t sigma;                 /* residual standard deviation, output units */
    pdt_real_t aic;                   /* n ln(sigma_ml^2) + 2 p, p = count */
    pdt_real_t bic;                   /* n ln(sigma_ml^2) + p ln n */
    pdt_real_t white_stat;            /* portmanteau statistic of the residual */
    pdt_real_t white_limit;           /* its 99 % chi-square quantile */
    bool white;                       /* white_stat <= white_limit */
    pdt_real_t cross_stat;            /* model-error FIR statistic */
    pdt_real_t cross_limit;           /* its 99 % chi-square quantile */
    bool independent;                 /* cross_stat <= cross_limit */
    pdt_real_t inflation;             /* covariance factor for a correlated
                               * residual, 1 + 2 sum of its
                               * autocorrelations, >= 1 */
    pdt_ident_std_t std;              /* parameter uncertainty, inflated */
    uint32_t fir_lag;                 /* first lag of the FIR, samples */
    pdt_real_t fir[PDT_VALIDATE_FIR]; /* the model-error FIR, output units
                                       * per input unit, tap j at lag
                                       * fir_lag + j */
} pdt_validate_result_t;

/* Workspace bytes pdt_validate_model needs for n samples. */
size_t pdt_validate_workspace_size(size_t n);

/* Validates model m (identified on data at Ts, output offset y0, input
 * operating point data->u[0], the identification's convention) into *out.
 * work: caller memory of pdt_validate_workspace_size(n) bytes, aligned for
 * pdt_real_t, scratch only.
 * Returns PDT_ERR_ARG (NULL, invalid model, Ts or y0 not finite or Ts <= 0,
 * misaligned work), PDT_ERR_TOO_SHORT (fewer than PDT_MIN_SAMPLES or not
 * more samples than the tests' lags and taps), PDT_ERR_NONFINITE (NaN or
 * infinity in the data), PDT_ERR_NO_EXCITATION (the input does not move),
 * PDT_ERR_NOMEM (work NULL or too small); *out untouched on error.
 * Work: O(n) per parameter for the sensitivities (one simulation each),
 * O(n PDT_VALIDATE_LAGS) for the whiteness test, O(n PDT_VALIDATE_FIR^2)
 * for the FIR. */
pdt_status_t pdt_validate_model(const pdt_model_t *m, const pdt_ident_data_t *data, pdt_real_t Ts,
                                pdt_real_t y0, void *work, size_t work_len,
                                pdt_validate_result_t *out);

/* pdt_validate_model in bounded steps, for a caller with a time budget per
 * call (the autotune runs one step per scan): pdt_validate_begin checks
 * the arguments and prepares (the model simulated on the record: O(n));
 * then each pdt_validate_step does one bounded piece, in order:
 * PDT_FISHER_BLOCK (256) samples of the sensitivities' pass (O(256) per
 * parameter plus O(256 PDT_VALIDATE_LAGS)), the residual's statistics
 * (O(n)), PDT_VALIDATE_FIR_ROWS (128) rows of the FIR's normal equations
 * (O(128 PDT_VALIDATE_FIR^2)), or the FIR's solution (O(PDT_VALIDATE_FIR^3)).
 * A record of n samples takes ceil(n / 256) + ceil(n / 128) + 2 steps at
 * most. The state lives in work (caller memory of
 * pdt_validate_run_workspace_size(n) bytes, aligned for pdt_real_t), which
 * must stay untouched, with m's copy and the record data, until the last
 * step; no other memory is kept. The result is pdt_validate_model's, bit
 * for bit (the same operations in the same order).
 * pdt_validate_begin returns what pdt_validate_model returns for the same
 * arguments (PDT_ERR_NOMEM against the size above), PDT_OK when the steps
 * can start. pdt_validate_step returns PDT_ERR_ARG (NULL), PDT_ERR_STATE
 * (work not begun, or begun and failed), PDT_RUNNING (more steps), an
 * error of the pass (PDT_ERR_NONFINITE: the simulation overflowed, and on
 * every later call), or PDT_OK with *out written (once done, every later
 * call writes it again). *out is written only with PDT_OK. */
size_t pdt_validate_run_workspace_size(size_t n);
pdt_status_t pdt_validate_begin(const pdt_model_t *m, const pdt_ident_data_t *data, pdt_real_t Ts,
                                pdt_real_t y0, void *work, size_t work_len);
pdt_status_t pdt_validate_step(void *work, pdt_validate_result_t *out);

/* The model order the data support, from the validations of a FOPDT (fo)
 * and a SOPDT (so) identified on the same record: a model whose gain the
 * data determine and whose covariance is usable is preferred to one whose
 * are not; then a model whose residual is independent of the input to one
 * whose is not; among
 * equals, the smaller BIC, the FOPDT unless the SOPDT's BIC is lower by
 * more than 2 (the usual "positive evidence" step). Returns PDT_ERR_ARG for
 * NULL or results of the wrong kinds; *kind untouched then. O(1). */
pdt_status_t pdt_ident_select_order(const pdt_validate_result_t *fo,
                                    const pdt_validate_result_t *so, pdt_model_kind_t *kind);

/* Robust bound of the true loop's maximum sensitivity for ideal-form gains
 * g on the validated model with its dead time shifted by dTd (s, e.g. the
 * autotune's decimation shift): max over w of |S| / (1 - |C S| D), D the
 * additive model error: the FIR's magnitude (when the independence test
 * failed) plus 3 standard deviations of |G| over the parameters' confidence
 * ellipsoid (first order; an integrating SOPDT's b, bounded below by 0,
 * left out; undetermined shape parameters held at their estimates; an
 * undetermined gain or an unusable covariance gives +infinity). +infinity where |C S| D >= 1. Evaluated on 200
 * log-spaced frequencies from 1e-3 / T (T the slowest of the controller's
 * and the model's times) to pi / Ts (beyond, the data say nothing).
 * *fir_part: whether the FIR's part of D exceeds the parameters' where the
 * bound peaks, false when the covariance is unusable (may be NULL). Returns PDT_ERR_ARG for NULL v, g or ms, or
 * gains outside their domain. Work: 200 x (about 4 PDT_VALIDATE_FIR + 60)
 * multiplications and 4 sines or cosines. */
pdt_status_t pdt_validate_margin(const pdt_validate_result_t *v, pdt_real_t dTd,
                                 const pdt_tune_gains_t *g, pdt_real_t *ms, bool *fir_part);

#ifdef __cplusplus
}
#endif

#endif /* PDT_VALIDATE_H */
