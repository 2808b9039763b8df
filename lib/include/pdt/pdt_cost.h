/*
 * pdtfit cost functions of the paper (section 2.2) on one measured record.
 *
 * A pdt_cost_t is prepared once per data set (pdt_cost_init); everything that
 * does not depend on the model — the DFT magnitudes of u and y, the weights,
 * constant sums — is computed there, so one evaluation is O(N) for the time
 * costs and O(N_f / 2) for the frequency cost.
 *
 * Data: u[0..n-1] and y[0..n-1] sampled every Ts, the plant at rest at the
 * operating point (u0, y0) before sample 0. The costs work on deviations
 * u - u0 and y - y0. The arrays are the caller's; the cost object keeps
 * pointers to them, so they must stay valid and unchanged while it is used.
 *
 * Costs (all are mean squares in output units squared, so they mix evenly):
 *  - prediction, paper (6)/(7): one-step prediction from measured past
 *    outputs (equation error), mean over k = l_u + order .. n-1.
 *  - simulation: the model fed its own past outputs (output error), mean
 *    over the same samples. Unbiased under output noise, unlike prediction.
 *  - frequency, paper (8)-(10): sum_k W(k) (|Y(k)| - |G(j w_k)| |U(k)|)^2
 *    over k = 1 .. N_f/2 with w_k = 2 pi k / (N_f Ts), counting each bin
 *    below Nyquist twice (for its mirror image), divided by N_f n. The
 *    paper divides by N_f only; our extra 1/n makes Cf a mean square like Ct.
 *    N_f is the smallest power of two >= max(2 (n - l_u) - 3, n, 16).
 *  - combined, paper (11): phi_t * (time cost) + phi_f * Cf.
 * With estimate_offset, the time costs remove the mean residual, i.e. they
 * are minimised over an unknown constant output offset in closed form.
 */
#ifndef PDT_COST_H
#define PDT_COST_H

#include "pdt/pdt_common.h"
#include "pdt/pdt_discrete.h"
#include "pdt/pdt_fft.h"
#include "pdt/pdt_model.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum pdt_cost_kind {
    PDT_COST_PREDICTION = 0,
    PDT_COST_SIMULATION = 1,
    PDT_COST_FREQUENCY = 2,
    PDT_COST_COMBINED = 3
} pdt_cost_kind_t;

/* Frequency weighting W(k). */
typedef enum pdt_weight_kind {
    PDT_WEIGHT_UNIFORM = 0, /* W = 1 at every bin */
    PDT_WEIGHT_BAND = 1,    /* W = 1 for f_lo <= f <= f_hi (Hz), else 0 */
    PDT_WEIGHT_CUSTOM = 2   /* W(k) = weights[k], k = 0 .. N_f/2 */
} pdt_weight_kind_t;

/* How pdt_cost_eval turns the model's dead time into samples. */
typedef enum pdt_delay_mode {
    PDT_DELAY_FRACTIONAL = 0, /* exact ZOH with fractional dead time */
    PDT_DELAY_INTEGER = 1     /* paper: l = round(Td / Ts), Td taken as l Ts */
} pdt_delay_mode_t;

typedef struct pdt_cost_config {
    pdt_real_t Ts;          /* sampling period, s; > 0. Default: 0 (must be set) */
    pdt_real_t u0;          /* input operating point. Default 0 */
    pdt_real_t y0;          /* output operating point. Default 0 */
    size_t delay_min;       /* l_l, samples. Default 0 */
    size_t delay_max;       /* l_u, samples; < n. Default PDT_DELAY_AUTO */
    pdt_cost_kind_t kind;   /* what pdt_cost_eval computes. Default COMBINED */
    pdt_cost_kind_t time_kind; /* time part of COMBINED: PREDICTION or
                                * SIMULATION. Default SIMULATION (the paper
                                * uses PREDICTION; see the docs) */
    pdt_delay_mode_t delay_mode; /* Default FRACTIONAL */
    bool estimate_offset;   /* time costs fit a constant output offset. Default true */
    bool use_frequency;     /* prepare spectra (needed for FREQUENCY and
                             * COMBINED; costs 7 N_f/4 + 3 reals). Default true */
    pdt_real_t phi_t;       /* weight of the time cost in COMBINED. Default 1 */
    pdt_real_t phi_f;       /* weight of Cf in COMBINED. Default 1 */
    pdt_weight_kind_t weight; /* Default UNIFORM */
    pdt_real_t f_lo;        /* BAND: lower edge, Hz, >= 0. Default 0 */
    pdt_real_t f_hi;        /* BAND: upper edge, Hz, >= f_lo. Default 0 */
    const pdt_real_t *weights; /* CUSTOM: N_f/2 + 1 values >= 0, copied at init */
} pdt_cost_config_t;

/* delay_max value meaning "n / 2". */
#define PDT_DELAY_AUTO ((size_t)-1)

/* The prepared cost. Fields are private; fill it with pdt_cost_init. */
typedef struct pdt_cost {
    pdt_cost_config_t cfg;   /* copy of the config, delay_max resolved */
    const pdt_real_t *u;     /* caller's data */
    const pdt_real_t *y;
    size_t n;                /* samples */
    size_t nf;               /* FFT size N_f (0 without frequency data) */
    size_t nbins;            /* bins used: N_f / 2 */
    pdt_real_t *umag;        /* |U(k)|, k = 1 .. N_f/2 (workspace) */
    pdt_real_t *ymag;        /* |Y(k)| (workspace) */
    pdt_real_t *wgt;         /* W(k) times the mirror factor and 1/(N_f n) (workspace) */
    pdt_real_t yy;           /* sum_k wgt(k) |Y(k)|^2 */
    pdt_real_t w_step;       /* 2 pi / (N_f Ts), rad/s per bin */
} pdt_cost_t;

/* Fills cfg with the documented defaults (Ts is left 0: the caller sets it). */
void pdt_cost_config_default(pdt_cost_config_t *cfg);

/* N_f for a record of n samples and delay bound delay_max (resolved as in
 * pdt_cost_init), or 0 if unsupported (too long for PDT_FFT_MAX_LOG2). */
size_t pdt_cost_fft_size(size_t n, size_t delay_max);

/* Workspace bytes pdt_cost_init needs for this config and record length:
 * 0 when use_frequency is false, and 0 when cfg is NULL or n or the delay
 * bound is unsupported (pdt_cost_init then says why). */
size_t pdt_cost_workspace_size(const pdt_cost_config_t *cfg, size_t n);

/* Compile-time upper bound of the workspace for n samples, any delay bound,
 * use_frequency = true: for static arrays. N_f <= 4 n here. */
#define PDT_COST_WORKSPACE_SIZE(n) \
    ((size_t)(4u * 2u * (size_t)(n) + 4u * 3u * (size_t)(n) / 4u + 3u) * sizeof(pdt_real_t) \
     + 4u * (size_t)(n) * sizeof(pdt_real_t))

/* Prepares c for the record u, y of n samples.
 * Returns:
 *  PDT_ERR_ARG       NULL c/cfg/u/y, Ts not finite and > 0, an unknown enum,
 *                    phi_t or phi_f negative or not finite, CUSTOM without
 *                    weights or with a negative or non-finite weight,
 *                    misaligned work;
 *  PDT_ERR_BOUNDS    delay_min > delay_max, or f_lo > f_hi;
 *  PDT_ERR_TOO_SHORT delay_max >= n, or n - delay_max - 2 < PDT_MIN_SAMPLES;
 *  PDT_ERR_NONFINITE NaN or infinity in u, y, u0 or y0;
 *  PDT_ERR_LENGTH    N_f beyond 2^PDT_FFT_MAX_LOG2;
 *  PDT_ERR_NOMEM     work NULL or smaller than pdt_cost_workspace_size
 *                    (only when use_frequency is true).
 * Work: O(n) for the checks, plus O(N_f log N_f) with use_frequency. */
pdt_status_t pdt_cost_init(pdt_cost_t *c, const pdt_cost_config_t *cfg, const pdt_real_t *u,
                           const pdt_real_t *y, size_t n, void *work, size_t work_len);

/* Time costs of a discrete model. PDT_ERR_ARG for NULL, a bad order, or a
 * delay outside [delay_min, delay_max]. O(n). */
pdt_status_t pdt_cost_prediction(const pdt_cost_t *c, const pdt_dmodel_t *d, pdt_real_t *cost);
pdt_status_t pdt_cost_simulation(const pdt_cost_t *c, const pdt_dmodel_t *d, pdt_real_t *cost);

/* Frequency cost of a continuous model (its dead time does not enter).
 * PDT_ERR_ARG for NULL, an invalid model, or a cost prepared without
 * use_frequency. O(N_f / 2). */
pdt_status_t pdt_cost_frequency(const pdt_cost_t *c, const pdt_model_t *m, pdt_real_t *cost);

/* The cost cfg.kind of model m: discretises m (per delay_mode) for the time
 * part. PDT_ERR_ARG as above, including a dead time outside the delay bounds. */
pdt_status_t pdt_cost_eval(const pdt_cost_t *c, const pdt_model_t *m, pdt_real_t *cost);

#ifdef __cplusplus
}
#endif

#endif /* PDT_COST_H */
