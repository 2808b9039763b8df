/*
 * pdtfit cost functions of the paper (section 2.2) on one measured record.
 *
 * A pdt_cost_t is prepared once per data set (pdt_cost_init); everything that
 * does not depend on the model - the DFT magnitudes of u and y and the
 * per-bin weights - is computed there, so one evaluation is O(n) for the
 * time costs and O(N_f / 2) for the frequency cost, with O(1) extra memory.
 *
 * Data: u[0..n-1] and y[0..n-1] sampled every Ts, the plant at rest at the
 * operating point (u0, y0) before sample 0. The costs work on the deviations
 * u(k) = u[k] - u0 and y(k) = y[k] - y0, both taken as 0 for k < 0. The
 * arrays are the caller's; the cost object keeps pointers to them, so they
 * must stay valid and unchanged while it is used.
 *
 * Delay bounds: l_u = delay_max (PDT_DELAY_HALF means n / 2, rounded down)
 * and l_l = delay_min, in samples. A discrete model's order is 1 (FOPDT) or
 * 2 (SOPDT).
 *
 * Costs (all are mean squares in output units squared, so they mix evenly):
 *  - prediction, paper (6)/(7): residual r(k) = y(k) - yhat(k), where yhat(k)
 *    is the model's one-step prediction from the measured y(k-1), y(k-2) and
 *    the input (equation error). Mean of r(k)^2 over the M = n - l_u - order
 *    samples k = l_u + order .. n-1 (0-based), so every candidate delay in
 *    the bounds is scored on the same samples.
 *  - simulation: the model run from rest over the whole record (k = 0 ..
 *    n-1) on the input alone, fed its own past outputs (output error);
 *    r(k) = y(k) - ysim(k), mean of r(k)^2 over the same M samples. Unlike
 *    prediction it is not biased by output noise. Nothing is stored: the
 *    residuals are accumulated as the model runs.
 *  - With estimate_offset, both time costs are mean(r^2) - mean(r)^2 (the
 *    variance of the residual), i.e. the cost minimised over an unknown
 *    constant output offset in closed form. Adding a constant to y then
 *    leaves them unchanged.
 *  - frequency, paper (8)-(10): with U(k), Y(k) the DFTs of the deviations
 *    zero-padded to N_f samples and w_k = 2 pi k / (N_f Ts) rad/s,
 *      Cf = sum_{k=1}^{N_f/2} W(k) m_k (|Y(k)| - |G(j w_k)| |U(k)|)^2 / (N_f n)
 *    with m_k = 2 below the Nyquist bin (each bin stands for its mirror
 *    image) and m_{N_f/2} = 1. The DC bin is left out: it carries the
 *    offset, which the operating point only approximates. The paper divides
 *    by N_f only; the extra 1/n makes Cf a mean square like the time costs:
 *    with W = 1 and G = 0, Parseval gives
 *      Cf = (sum y(k)^2 - (sum y(k))^2 / N_f) / n.
 *    |G| is |K| / sqrt(1 + (w tau)^2) for a FOPDT and
 *    |k| / sqrt((b - w^2)^2 + (a w)^2) for a SOPDT; the dead time does not
 *    enter. N_f is the smallest power of two >= max(2 (n - l_u) - 3, n, 16),
 *    long enough that the linear convolution of the model does not wrap.
 *  - combined, paper (11): phi_t * (time cost of time_kind) + phi_f * Cf.
 *    A term whose weight phi is 0 is left out (so an infinite part there
 *    cannot turn the sum into NaN).
 * A cost that overflows (e.g. an unstable discrete model given directly) is
 * returned as +infinity, never NaN.
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
    pdt_real_t Ts;               /* sampling period, s; finite and > 0. Default 0
                             * (must be set) */
    pdt_real_t u0;               /* input operating point. Default 0 */
    pdt_real_t y0;               /* output operating point. Default 0 */
    size_t delay_min;            /* l_l, samples. Default 0 */
    size_t delay_max;            /* l_u, samples; < n. Default PDT_DELAY_HALF */
    pdt_cost_kind_t kind;        /* what pdt_cost_eval computes. Default COMBINED */
    pdt_cost_kind_t time_kind;   /* time part of COMBINED: PREDICTION or
                                * SIMULATION. Default SIMULATION (the paper
                                * uses PREDICTION, which output noise biases) */
    pdt_delay_mode_t delay_mode; /* Default FRACTIONAL */
    bool whole_record;           /* score the time costs on the whole record
                             * instead of the paper's k = l_u + order ..
                             * n-1: k = 0 .. n-1 for the simulation (its
                             * output from rest is defined from the first
                             * sample), k = order .. n-1 for the prediction
                             * (it needs past outputs). The paper's window
                             * drops the first l_u samples, which is where
                             * a step test shows its dead time;
                             * identification uses the whole record.
                             * Default false (the paper) */
    bool estimate_offset;        /* time costs fit a constant output offset. Default true */
    bool estimate_state;         /* SIMULATION only: the profile
                                  * (pdt_cost_profile and its kin) fits the
                                  * model's free response from the first
                                  * sample too, one sequence for order 1,
                                  * two for order 2 (docs/equations.md).
                                  * pdt_cost_eval ignores it. Default false */
    bool drift;                  /* SIMULATION only: the profile fits a
                                  * linear drift of the output about the
                                  * record's middle. Default false */
    bool use_frequency;          /* prepare spectra (needed for FREQUENCY and
                             * COMBINED; needs a workspace, see
                             * pdt_cost_workspace_size). Default true */
    pdt_real_t phi_t;            /* weight of the time cost in COMBINED, >= 0. Default 1 */
    pdt_real_t phi_f;            /* weight of Cf in COMBINED, >= 0. Default 1 */
    pdt_weight_kind_t weight;    /* Default UNIFORM */
    pdt_real_t f_lo;             /* BAND: lower edge, Hz, >= 0. Default 0 */
    pdt_real_t f_hi;             /* BAND: upper edge, Hz, >= f_lo. Default 0 */
    const pdt_real_t *weights;   /* CUSTOM: N_f/2 + 1 values >= 0 for bins
                                * k = 0 .. N_f/2 (weights[0], the DC bin, is
                                * ignored but must be valid), copied at init,
                                * not used afterwards. Default NULL */
} pdt_cost_config_t;

/* The prepared cost. Fields are private; fill it with pdt_cost_init. */
typedef struct pdt_cost {
    pdt_cost_config_t cfg; /* copy of the config, delay_max resolved */
    const pdt_real_t *u;   /* the record normalised (workspace): */
    const pdt_real_t *y;   /* (u - u0) 2^-u_exp, (y - y0) 2^-y_exp */
    size_t n;              /* samples */
    int u_exp;             /* scales of the normalised record: powers of */
    int y_exp;             /* two, so mapping back is exact */
    pdt_real_t pow2[4];    /* 2^(u_exp - y_exp), 2^(y_exp - u_exp), 2^y_exp,
                              * 4^y_exp, each 0 when not a normal number */
    pdt_real_t ysum[2];    /* sum y and sum (y - mean)^2 of the normalised */
    pdt_real_t yvar[2];    /* y over the simulation's scored samples, by
                              * model order - 1 */
    size_t nf;             /* FFT size N_f (0 without frequency data) */
    size_t k_first;        /* first and last bin with a non-zero weight */
    size_t k_last;         /* (k_first > k_last: none) */
    pdt_real_t *umag;      /* |U(k)| at umag[k - 1], k = 1 .. N_f/2 (workspace) */
    pdt_real_t *ymag;      /* |Y(k)|, same indexing (workspace) */
    pdt_real_t *wgt;       /* W(k) m_k / (N_f n), same indexing (workspace) */
    pdt_real_t w_step;     /* 2 pi / (N_f Ts), rad/s per bin */
} pdt_cost_t;

/* Fills cfg with the documented defaults (Ts is left 0: the caller sets it).
 * Does nothing for NULL. */
void pdt_cost_config_default(pdt_cost_config_t *cfg);

/* N_f for a record of n samples and delay bound delay_max (PDT_DELAY_HALF
 * resolved to n / 2 as in pdt_cost_init), or 0 if unsupported: n = 0,
 * delay_max >= n, or N_f beyond 2^PDT_FFT_MAX_LOG2. */
size_t pdt_cost_fft_size(size_t n, size_t delay_max);

/* Whether cfg's frequency weighting gives no bin of a record of n samples
 * a weight (a band above the Nyquist frequency, custom weights all 0):
 * then pdt_cost_init succeeds with the frequency part empty. False for a
 * config without the frequency part, one pdt_cost_init refuses, or NULL.
 * Writes nothing; O(N_f). */
bool pdt_cost_band_empty(const pdt_cost_config_t *cfg, size_t n);

/* Workspace bytes pdt_cost_init needs for this config and record length,
 * exactly: 2 n reals for the normalised copy of the record (u and y as
 * deviations from the operating point, scaled by powers of two into
 * (-1, 1), so that no cost overflows or underflows in float at any data
 * scale and the inner loops subtract nothing), kept for the life of the
 * cost; with use_frequency, plus 3 N_f/2 reals (|U|, |Y| and the weight
 * per bin, kept) and pdt_fft_workspace_size(N_f) bytes for the FFT's
 * twiddle table, used only during init. The FFT buffer (N_f reals) needed
 * during init lies over the |Y| and weight arrays before they are filled,
 * so it costs nothing extra. With the current FFT the frequency part is
 * 2 N_f reals.
 * Returns 0 when cfg is NULL or n or the delay bound is unsupported
 * (pdt_cost_init then says why). */
size_t pdt_cost_workspace_size(const pdt_cost_config_t *cfg, size_t n);

/* Smallest power of two >= x among 16 .. 2^PDT_FFT_MAX_LOG2, or 0 beyond
 * (x a size_t expression). A constant expression; internal to the macro
 * below. */
#define PDT_COST_POW2_(x)                                                                          \
    ((x) <= 16u          ? (size_t)16u                                                             \
     : (x) <= 32u        ? (size_t)32u                                                             \
     : (x) <= 64u        ? (size_t)64u                                                             \
     : (x) <= 128u       ? (size_t)128u                                                            \
     : (x) <= 256u       ? (size_t)256u                                                            \
     : (x) <= 512u       ? (size_t)512u                                                            \
     : (x) <= 1024u      ? (size_t)1024u                                                           \
     : (x) <= 2048u      ? (size_t)2048u                                                           \
     : (x) <= 4096u      ? (size_t)4096u                                                           \
     : (x) <= 8192u      ? (size_t)8192u                                                           \
     : (x) <= 16384u     ? (size_t)16384u                                                          \
     : (x) <= 32768u     ? (size_t)32768u                                                          \
     : (x) <= 65536ul    ? (size_t)65536ul                                                         \
     : (x) <= 131072ul   ? (size_t)131072ul                                                        \
     : (x) <= 262144ul   ? (size_t)262144ul                                                        \
     : (x) <= 524288ul   ? (size_t)524288ul                                                        \
     : (x) <= 1048576ul  ? (size_t)1048576ul                                                       \
     : (x) <= 2097152ul  ? (size_t)2097152ul                                                       \
     : (x) <= 4194304ul  ? (size_t)4194304ul                                                       \
     : (x) <= 8388608ul  ? (size_t)8388608ul                                                       \
     : (x) <= 16777216ul ? (size_t)16777216ul                                                      \
                         : (size_t)0u)

/* The largest N_f of n samples over all delay bounds (delay_max = 0 gives
 * the longest zero padding: N_f = next power of two >= 2n - 3), or 0 when
 * that exceeds 2^PDT_FFT_MAX_LOG2. Valid for n >= 2. */
#define PDT_COST_FFT_SIZE_MAX(n)                                                                   \
    ((PDT_COST_POW2_(2u * (size_t)(n)-3u) <= ((size_t)1u << PDT_FFT_MAX_LOG2))                     \
         ? PDT_COST_POW2_(2u * (size_t)(n)-3u)                                                     \
         : (size_t)0u)

/* Compile-time workspace bytes for n samples, any delay bound, with
 * use_frequency = true: the formula of pdt_cost_workspace_size at the
 * largest N_f (PDT_COST_FFT_SIZE_MAX), so it equals
 * pdt_cost_workspace_size for delay_max = 0 and bounds it for every other
 * delay bound. Sized by it, a static array of pdt_real_t (for alignment)
 * always fits. It is 0 when n is too long for PDT_FFT_MAX_LOG2, so such an
 * array fails to compile instead of failing at run time. */
#define PDT_COST_WORKSPACE_SIZE(n)                                                                 \
    ((2u * (size_t)(n) + 3u * (PDT_COST_FFT_SIZE_MAX(n) / 2u)) * sizeof(pdt_real_t) +              \
     PDT_FFT_WORKSPACE_SIZE(PDT_COST_FFT_SIZE_MAX(n)))

/* Prepares c for the record u, y of n samples: checks the config and the
 * data, copies the record normalised into work and, with use_frequency,
 * computes the DFT magnitudes and weights there too. c keeps a pointer to
 * work (caller memory, which must stay valid and unchanged while c is
 * used), not to u and y; the rest is copied. work must be aligned for
 * pdt_real_t.
 * Returns:
 *  PDT_ERR_ARG       NULL c/cfg/u/y, Ts not finite and > 0 (or so small
 *                    that 2 pi / (N_f Ts) overflows), an unknown enum,
 *                    time_kind other than PREDICTION or SIMULATION, phi_t
 *                    or phi_f negative or not finite, f_lo or f_hi
 *                    negative or not finite, CUSTOM without weights or
 *                    (with use_frequency) with a negative or non-finite
 *                    weight, misaligned work;
 *  PDT_ERR_TOO_SHORT delay_max >= n, or fewer than PDT_MIN_SAMPLES scored
 *                    samples: n - delay_max - 2 (n - 2 with whole_record);
 *  PDT_ERR_BOUNDS    delay_min > delay_max, or f_lo > f_hi;
 *  PDT_ERR_NONFINITE NaN or infinity in u, y, u0 or y0;
 *  PDT_ERR_OUTLIER   a gross outlier in u or y: a jump between samples
 *                    2^24 times (seven decades) larger than every other
 *                    non-zero jump of that signal, at no more than
 *                    2 + n / 64 places (a logger's bad-value marker, e.g.
 *                    1e20 or -3e38 in a record of order 1);
 *                    pdt_cost_outlier names the sample;
 *  PDT_ERR_LENGTH    N_f beyond 2^PDT_FFT_MAX_LOG2 (only with use_frequency);
 *  PDT_ERR_NOMEM     work NULL or work_len below pdt_cost_workspace_size.
 * Checked in this order: pointers and the config's own values (ARG),
 * lengths (TOO_SHORT), bounds (BOUNDS), data (NONFINITE in u or y, then
 * OUTLIER, then NONFINITE in u0 or y0);
 * then, with use_frequency only: N_f (LENGTH), the bin spacing and custom
 * weight values (ARG); then the workspace (NOMEM if NULL, ARG if
 * misaligned, NOMEM if short). On error *c and work are untouched.
 * Work: O(n) for the checks and the copy, plus O(N_f log N_f) with
 * use_frequency. */
pdt_status_t pdt_cost_init(pdt_cost_t *c, const pdt_cost_config_t *cfg, const pdt_real_t *u,
                           const pdt_real_t *y, size_t n, void *work, size_t work_len);

/* Time costs (prediction, simulation) of a discrete model d (see
 * pdt_discrete.h; its d[] delta form is what is used, a[] is ignored), with
 * the offset handling of cfg.estimate_offset, into *cost (output units
 * squared). Returns PDT_ERR_ARG for NULL, a c not prepared by
 * pdt_cost_init, an order other than 1 or 2, a non-finite coefficient, or a
 * delay outside [delay_min, delay_max]; *cost is then untouched.
 * O(n) time, O(1) memory. */
pdt_status_t pdt_cost_prediction(const pdt_cost_t *c, const pdt_discrete_t *d, pdt_real_t *cost);
pdt_status_t pdt_cost_simulation(const pdt_cost_t *c, const pdt_discrete_t *d, pdt_real_t *cost);

/* Frequency cost Cf of a continuous model (its dead time does not enter)
 * into *cost. Returns PDT_ERR_ARG for NULL, an invalid model
 * (pdt_model_check), or a c prepared without use_frequency; *cost is then
 * untouched. O(N_f / 2), or fewer bins with BAND weights. */
pdt_status_t pdt_cost_frequency(const pdt_cost_t *c, const pdt_model_t *m, pdt_real_t *cost);

/* The cost cfg.kind of model m into *cost. For the time part, m is first
 * discretised with period Ts: FRACTIONAL by pdt_discrete_init (delay
 * l = floor(Td / Ts), so Td must be < (delay_max + 1) Ts), INTEGER by
 * pdt_discrete_init_int with l = round(Td / Ts) (halves round up).
 * Returns PDT_ERR_ARG for NULL, a c not prepared, an invalid model, a
 * delay l outside [delay_min, delay_max] (not checked for FREQUENCY, where
 * Td does not matter), or FREQUENCY / COMBINED on a c prepared without
 * use_frequency; *cost is then untouched. */
pdt_status_t pdt_cost_eval(const pdt_cost_t *c, const pdt_model_t *m, pdt_real_t *cost);

/* The index of a gross outlier in x[0..n-1] as pdt_cost_init refuses it
 * (PDT_ERR_OUTLIER), or n if there is none (also for NULL x or n < 2).
 * The sample named is the first of the jumps (the one after the jump).
 * O(n). */
size_t pdt_cost_outlier(const pdt_real_t *x, size_t n);

/* Result of pdt_cost_profile. */
typedef struct pdt_cost_profile {
    pdt_real_t cost;   /* cfg.kind's cost at the best gain and offset */
    pdt_real_t ncost;  /* the same cost in the normalised units of the cost
                        * object: cost / 4^y_exp exactly (y_exp a field of
                        * pdt_cost_t), but finite and neither 0 by underflow
                        * nor infinite by overflow at any data scale a
                        * float holds. Compare candidates by it. */
    pdt_real_t gain;   /* best multiplier of the shape's gain */
    pdt_real_t offset; /* best output offset, added to y0 (0 for FREQUENCY,
                        * without estimate_offset, and for PREDICTION of
                        * an integrating model, whose A(1) is 0) */
    pdt_real_t ct;     /* time part at that gain (0 for FREQUENCY) */
    pdt_real_t cf;     /* frequency part (0 for PREDICTION, SIMULATION) */
} pdt_cost_profile_t;

/* The cost of cfg.kind minimised over the gain and the output offset, for
 * a model shape (any valid model; its gain is the unit the returned gain
 * multiplies). Every cost here is quadratic in the gain for a given shape
 * (Cf in its magnitude), so the minimum is found in closed form: the time
 * part from the regression of the data on the shape's response, the
 * frequency part from the regression of |Y| on |G||U|, the two joined by
 * their weights; the offset follows from the means. This is what makes the
 * identification search only over shape and dead time.
 * gain_min, gain_max bound the gain; 0, 0 means unbounded.
 * scratch: n reals of caller memory, overwritten (the shape's response).
 * The time part is scored as pdt_cost_simulation / pdt_cost_prediction
 * score it: ct is what they return for the model with the returned gain
 * and the output level y0 + offset, up to rounding; cf is what
 * pdt_cost_frequency returns for that model on the spectra prepared at
 * init (around y0: moving y0 would change the zero-padded spectra). A part
 * weighted 0 in COMBINED is not computed and reads 0. Where the data do not
 * fix the sign of the gain (FREQUENCY, or COMBINED with phi_t = 0), the
 * positive gain is returned.
 * Returns PDT_ERR_ARG (NULL, c not prepared, invalid shape, its delay
 * outside the bounds, FREQUENCY / COMBINED without use_frequency, a bound
 * not finite), PDT_ERR_BOUNDS (gain_min > gain_max); *out untouched then.
 * Work: for the SIMULATION time part, one pass over the record (the
 * shape simulated and the regression sums accumulated together, no
 * per-sample branches), and a second pass only when the fit is so good
 * that the first one's sums would cancel in float (the residual below
 * about 1/17 of the sums it comes from in float; the identification's
 * search spares that pass with a reference fit); for PREDICTION three
 * passes; two passes over the bins for the frequency part. O(n + N_f). */
pdt_status_t pdt_cost_profile(const pdt_cost_t *c, const pdt_model_t *shape, pdt_real_t gain_min,
                              pdt_real_t gain_max, pdt_real_t *scratch, pdt_cost_profile_t *out);

/* A cost in the normalised units of c (pdt_cost_profile_t.ncost) in
 * output units squared: ncost 4^y_exp, +infinity where that overflows.
 * NULL c gives ncost unchanged. */
pdt_real_t pdt_cost_units(const pdt_cost_t *c, pdt_real_t ncost);

/* The fit of model m (engineering units, its gain included) with output
 * offset offset (added to y0) on the record, in percent:
 *   100 (1 - sqrt(sum (y - ysim)^2 / sum (y - mean y)^2)) over k = 0 .. n-1,
 * computed on the normalised record, so it is finite at every data scale;
 * a model whose residual overflows gets -1e30 (never NaN or infinity),
 * and a record whose y does not move gets 0. scratch: n reals,
 * overwritten. Returns PDT_ERR_ARG for NULL, c not prepared, an invalid m
 * or one whose discretisation fails; *fit is then untouched. O(n). */
pdt_status_t pdt_cost_fit(const pdt_cost_t *c, const pdt_model_t *m, pdt_real_t offset,
                          pdt_real_t *scratch, pdt_real_t *fit);

/* The model's simulated output in engineering units: ysim[k] = y0 + the
 * response of d, from rest, to u - u0, for k = 0 .. n-1 (n reals). d may
 * have any delay. Returns PDT_ERR_ARG for NULL, c not prepared, an order
 * other than 1 or 2, or a non-finite coefficient. O(n). */
pdt_status_t pdt_cost_simulate(const pdt_cost_t *c, const pdt_discrete_t *d, pdt_real_t *ysim);

#ifdef __cplusplus
}
#endif

#endif /* PDT_COST_H */
