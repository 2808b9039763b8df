/*
 * pdtfit status codes and their names (pdt_status.c). Every module gets them
 * through pdt_common.h.
 */
#ifndef PDT_STATUS_H
#define PDT_STATUS_H

#ifdef __cplusplus
extern "C" {
#endif

/*
 * Status returned by every fallible call. PDT_OK is zero, errors are
 * negative, so positive values stay free for calls that report progress.
 * A call that returns an error has written none of its outputs.
 */
typedef enum pdt_status {
    /* Not finished: call again (steppable calls such as pdt_ident_step). */
    PDT_RUNNING = 1,
    PDT_OK = 0,
    /* A pointer is NULL, a number is outside its domain (e.g. Ts <= 0,
     * tau <= 0), an enum value is unknown, or memory is misaligned. */
    PDT_ERR_ARG = -1,
    /* A length the routine does not support, e.g. an FFT size that is not a
     * power of two in [16, 2^PDT_FFT_MAX_LOG2]. */
    PDT_ERR_LENGTH = -2,
    /* The workspace is NULL or smaller than its size query says. */
    PDT_ERR_NOMEM = -3,
    /* The data holds NaN or infinity. */
    PDT_ERR_NONFINITE = -4,
    /* Too few samples: fewer than PDT_MIN_SAMPLES remain after the delay
     * bound, or the delay bound is not below the record length. */
    PDT_ERR_TOO_SHORT = -5,
    /* A lower bound lies above its upper bound. */
    PDT_ERR_BOUNDS = -6,
    /* The model has no representation in the requested form, e.g. real time
     * constants for an underdamped SOPDT, or a DC gain for an integrator. */
    PDT_ERR_NO_FORM = -7,
    /* The data cannot support a model: the input or the output does not
     * move (beyond its quantisation), so nothing about the process can be
     * learnt from it. */
    PDT_ERR_NO_EXCITATION = -8,
    /* A call out of order, e.g. a result asked for before the search is
     * done, or a step on an object that was never initialised. */
    PDT_ERR_STATE = -9,
    /* An experiment stopped for safety: the process value left its limits. */
    PDT_ERR_PV_LIMIT = -10,
    /* An experiment stopped for safety: the output would have to leave its
     * limits. */
    PDT_ERR_OUTPUT_LIMIT = -11,
    /* An experiment stopped: its time limit passed. */
    PDT_ERR_TIMEOUT = -12,
    /* The set-point lies on the wrong side of the process value for the
     * requested experiment (e.g. a relay test that cannot cross it). */
    PDT_ERR_SETPOINT = -13,
    /* Gains refused: the model fits the data too poorly (its fit is below
     * the tuning's fit_min). */
    PDT_ERR_POOR_FIT = -14,
    /* Gains refused: no rule gives a stable loop for this model. */
    PDT_ERR_UNSTABLE = -15,
    /* Stopped by the caller (e.g. an operator cancelled an autotune). */
    PDT_ERR_ABORTED = -16,
    /* The frequency criteria compare the spectra of the whole record, which
     * needs a record that ends at rest (the input back at its start, the
     * output settled); this one does not (a step test, an integrating
     * process). */
    PDT_ERR_NOT_AT_REST = -17,
    /* The data hold a gross outlier: a sample many orders of magnitude off
     * the rest of its signal (a logger's bad-value marker such as 1e20 or
     * -3e38). pdt_cost_outlier names it. */
    PDT_ERR_OUTLIER = -18,
    /* Gains refused: the data contradict the model. Its residuals are
     * explained by the input beyond what any safe retuning can absorb, or
     * the model disagrees with a point the experiment measured directly
     * (a relay's ultimate gain and period). */
    PDT_ERR_MODEL_INVALID = -19,
    /* Gains refused: the data do not determine the model's parameters well
     * enough for any gains to be robust over their confidence region. */
    PDT_ERR_UNCERTAIN = -20,
    /* The experiment was disturbed: something besides the excitation moved
     * the process while it was recorded (a load change, a drift, a relay
     * whose cycles do not repeat), so no model of the record is one of the
     * process. The autotune repeats such an experiment once, then refuses. */
    PDT_ERR_DISTURBED = -21,
    /* Gains refused: the loop they make with the model is not robust
     * enough; its maximum sensitivity Ms exceeds the limit ms_max. */
    PDT_ERR_MS_LIMIT = -22
} pdt_status_t;

/* A short, static, English name of a status ("bad argument", ...). Never
 * returns NULL; unknown values give "unknown status". */
const char *pdt_status_str(pdt_status_t status);

/* The enumerator's own name ("PDT_ERR_POOR_FIT", ...), static: for logs and
 * machine-read output that must not change with the wording of
 * pdt_status_str. Never returns NULL; unknown values give
 * "PDT_STATUS_UNKNOWN". */
const char *pdt_status_name(pdt_status_t status);

#ifdef __cplusplus
}
#endif

#endif /* PDT_STATUS_H */
