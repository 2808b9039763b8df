/*
 * pdtfit PID: the controller that runs the gains pdt_tune hands out, one
 * call per scan, in fixed memory (a caller-owned pdt_pid_t, no workspace).
 * docs/pid.md gives the discretisation, the anti-windup and which settings
 * reproduce the robustness figures of pdt_tune.
 *
 * The controller (e = sp - pv, sp the set-point, pv the process value):
 *   u = Kc [ (b sp - pv) + 1 / (Ti s) (sp - pv) + Td s / (Tf s + 1) (c sp - pv) ]
 * in the ideal (parallel, ISA) form; the series form
 *   Kc (Ti s + 1) / (Ti s) (Td s + 1)
 * is turned into the ideal form at configuration (pdt_tune_to_ideal), with
 * the filter on the derivative term of the ideal form, as pdt_tune reads it.
 * With b = 1 and c = 1 this is exactly the C(s) whose figures pdt_tune
 * reports; b and c shape only the response to set-point changes (the
 * loop's robustness and its load response do not depend on them). The
 * default c = 0 puts the derivative on the measurement: no kick on a
 * set-point step.
 *
 * Discretisation, for scan period Ts (docs/pid.md says why):
 *  - integral: trapezoidal (Tustin), Kc Ts / (2 Ti) (e(k) + e(k-1));
 *  - derivative: the filter's exact response to a measurement that is
 *    linear between two scans: with a = e^{-Ts/Tf},
 *    D(k) = a D(k-1) + Kc Td (1 - a) / Ts (y(k) - y(k-1)), y = c sp - pv;
 *    Tf = 0 gives the plain backward difference (a = 0);
 *  - anti-windup by back-calculation: after the output u(k) is limited,
 *    the integral moves toward the value that would have produced it by
 *    the fraction 1 - e^{-Ts/Tt} (the exact decay over one scan of a
 *    tracking loop with time constant Tt); and/or conditional integration:
 *    in a scan where the increment would push the output past a limit,
 *    the integral moves only as far as brings the output to the limit
 *    (not at all if it is already beyond).
 * The output is held constant between scans (zero-order hold), which adds
 * about Ts / 2 of dead time to the loop: docs/pid.md.
 *
 * Modes. pdt_pid_update is automatic: it computes the output. While
 * something else drives the actuator (an operator in manual, the autotune,
 * another controller in a selector) call pdt_pid_track every scan with the
 * output in service instead: the controller follows it, and the first
 * pdt_pid_update after it continues from that output without a bump.
 * pdt_pid_set_config changes gains, weights or limits in service without a
 * bump either.
 *
 * Errors: every call checks its inputs before writing anything; on an
 * error neither the object nor the output is changed, so the caller keeps
 * applying the last output (the output is "held").
 */
#ifndef PDT_PID_H
#define PDT_PID_H

#include "pdt/pdt_common.h"
#include "pdt/pdt_tune.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum pdt_pid_form {
    PDT_PID_IDEAL = 0, /* Kc (1 + 1 / (Ti s) + Td s / (Tf s + 1)) */
    PDT_PID_SERIES = 1 /* Kc (Ti s + 1) / (Ti s) (Td s + 1), filter on the
                         * ideal form's derivative term */
} pdt_pid_form_t;

typedef enum pdt_pid_antiwindup {
    PDT_PID_AW_BACK_CALC = 0,   /* back-calculation with tracking time Tt */
    PDT_PID_AW_CONDITIONAL = 1, /* conditional integration */
    PDT_PID_AW_BOTH = 2,        /* both */
    PDT_PID_AW_NONE = 3         /* neither: the integral winds up */
} pdt_pid_antiwindup_t;

typedef struct pdt_pid_config {
    pdt_real_t Ts;                   /* scan period, s, finite, > 0. Default 0.1 */
    pdt_pid_form_t form;             /* form Kc, Ti, Td are given in. Default ideal */
    pdt_real_t Kc;                   /* proportional gain, output units per pv unit,
                              * finite, non-zero; negative for a direct-
                              * acting loop (pdt_tune's sign). Default 1 */
    pdt_real_t Ti;                   /* integral time, s, finite, > 0, or 0 for no
                              * integral action (P, PD: the integral state
                              * is then a constant bias that the
                              * bumpless transfers set). Default 10 */
    pdt_real_t Td;                   /* derivative time, s, finite, >= 0 (0: PI).
                              * Default 0 */
    pdt_real_t Tf;                   /* derivative filter time constant, s, finite,
                              * >= 0; 0 takes Td / N (Td of `form`), or no
                              * filter when N is 0. Default 0 */
    pdt_real_t N;                    /* filter as a ratio, used when Tf = 0: 0 (no
                              * filter) or finite >= 1. Default 10 */
    pdt_real_t b;                    /* set-point weight of the P term, finite,
                              * >= 0. Default 1 */
    pdt_real_t c;                    /* set-point weight of the D term, finite,
                              * >= 0; 0 is derivative on the measurement.
                              * Default 0 */
    pdt_real_t u_min;                /* output limits, output units, finite, */
    pdt_real_t u_max;                /* u_min < u_max. Default 0 and 100 */
    pdt_real_t rate_max;             /* largest output change, output units per s,
                              * finite, > 0, or 0 for no limit. Default 0 */
    pdt_pid_antiwindup_t antiwindup; /* Default back-calculation */
    pdt_real_t Tt;                   /* back-calculation tracking time, s, finite,
                              * >= 0; 0 takes sqrt(Ti Td) for a PID, Ti for
                              * a PI (Astrom and Hagglund's rule of
                              * thumb); unused without integral action.
                              * Default 0 */
} pdt_pid_config_t;

/* The controller object. Caller-owned; fill it with pdt_pid_init. The
 * fields after `state` may be read (diagnostics), never written. */
typedef struct pdt_pid {
    uint32_t magic;       /* set by pdt_pid_init */
    pdt_pid_config_t cfg; /* the configuration as given */
    /* The ideal-form gains and the discrete coefficients from them. */
    pdt_real_t K;      /* ideal Kc */
    pdt_real_t ki;     /* Kc Ts / (2 Ti), 0 without integral */
    pdt_real_t kd;     /* ideal Kc Td */
    pdt_real_t ad;     /* derivative filter pole e^{-Ts/Tf} */
    pdt_real_t ao;     /* back-calculation fraction 1 - e^{-Ts/Tt} */
    pdt_real_t du_max; /* rate_max Ts, 0 for none */
    bool primed;       /* sp, pv and the states are from a scan */
    /* state */
    pdt_real_t i;       /* the integral term, output units */
    pdt_real_t df;      /* filtered derivative of c sp - pv, pv/s */
    pdt_real_t sp_last; /* sp and pv of the last scan */
    pdt_real_t pv_last;
    pdt_real_t u;      /* the last output (or the tracked one) */
    pdt_real_t p_term; /* the last scan's P, I and D terms, output */
    pdt_real_t i_term; /* units (I before the anti-windup step) */
    pdt_real_t d_term;
    bool limited; /* the last output was limited (range or rate,
                              * or the integral was cut at a limit) */
} pdt_pid_t;

/* Fills cfg with the documented defaults. Does nothing for NULL. */
void pdt_pid_config_default(pdt_pid_config_t *cfg);

/* Checks cfg and starts the controller at output u0 (output units, e.g.
 * the output in service): the first pdt_pid_update returns u0 exactly
 * (clamped to the limits) and sets the integral so that the output moves
 * on from there. Returns PDT_ERR_ARG for NULL, an invalid field (see the
 * config's comments) or a non-finite u0; *pid untouched then. O(1). */
pdt_status_t pdt_pid_init(pdt_pid_t *pid, const pdt_pid_config_t *cfg, pdt_real_t u0);

/* Handover from pdt_tune or the autotune: pdt_pid_init with *base (Ts,
 * limits, weights, anti-windup) whose form, Kc, Ti, Td and Tf are replaced
 * by g in `form` (N = 0: g->Tf is taken as it is, 0 meaning unfiltered, as
 * pdt_tune read it). Pass the result's ideal gains with PDT_PID_IDEAL and
 * u0 = the output in service (the autotune's operating point): the loop
 * starts without a bump. Returns as pdt_pid_init, also PDT_ERR_ARG for
 * gains outside pdt_tune_gains_t's domain or an unknown form. */
pdt_status_t pdt_pid_init_from_gains(pdt_pid_t *pid, const pdt_pid_config_t *base,
                                     const pdt_tune_gains_t *g, pdt_pid_form_t form, pdt_real_t u0);

/* One automatic scan: reads sp and pv (sampled now), writes the output to
 * apply until the next scan into *u. Call once per Ts.
 * Returns PDT_ERR_ARG (NULL), PDT_ERR_STATE (pid not initialised),
 * PDT_ERR_NONFINITE (sp or pv is NaN or infinite, or the output would
 * not be finite: a failed sensor; the object and *u are untouched, so the
 * last output is held). O(1): one comparison chain, no libm call. */
pdt_status_t pdt_pid_update(pdt_pid_t *pid, pdt_real_t sp, pdt_real_t pv, pdt_real_t *u);

/* One scan in which u_applied drives the actuator instead of the
 * controller (manual, autotune, another controller): the controller
 * follows it, so that the next pdt_pid_update continues from u_applied.
 * Returns PDT_ERR_ARG (NULL), PDT_ERR_STATE, PDT_ERR_NONFINITE (sp, pv or
 * u_applied not finite; nothing changed). O(1). */
pdt_status_t pdt_pid_track(pdt_pid_t *pid, pdt_real_t sp, pdt_real_t pv, pdt_real_t u_applied);

/* Replaces the configuration in service (gains, weights, limits, Ts) without
 * a bump: the integral is set so that the last output, recomputed with the
 * new settings at the last sp and pv, is unchanged. Before the first scan
 * it only replaces the configuration. Returns PDT_ERR_ARG (NULL, invalid
 * cfg), PDT_ERR_STATE; nothing changed then. O(1). */
pdt_status_t pdt_pid_set_config(pdt_pid_t *pid, const pdt_pid_config_t *cfg);

/* pdt_pid_set_config with the in-service configuration whose form and
 * gains are replaced by g (as pdt_pid_init_from_gains): a bumpless gain
 * change, e.g. after a new autotune. Same returns. */
pdt_status_t pdt_pid_set_gains(pdt_pid_t *pid, const pdt_tune_gains_t *g, pdt_pid_form_t form);

#ifdef __cplusplus
}
#endif

#endif /* PDT_PID_H */
