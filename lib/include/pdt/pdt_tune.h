/*
 * pdtfit tuning: PI and PID gains from an identified FOPDT or SOPDT model by
 * published rules (SIMC, IMC / lambda, AMIGO, Ziegler-Nichols), with the
 * robustness of the loop they make (maximum sensitivity, gain and phase
 * margins), and a refusal instead of gains when the model or the loop does
 * not deserve trust. docs/tuning.md gives every formula and its source.
 *
 * Units: time in seconds, frequency in rad/s. The controller gain is in
 * input units per output unit (the inverse of the model's gain units), so
 * that the loop gain is dimensionless. A model with a negative gain gives a
 * negative controller gain: the sign of Kc is the controller's action.
 *
 * Controller forms (e = set-point - process value, u the output):
 *  - ideal (parallel, ISA) form, the one every gain set is reported in:
 *      C(s) = Kc (1 + 1 / (tauI s) + tauD s / (Tf s + 1));
 *  - series (cascade, interacting) form, in which SIMC is stated:
 *      C(s) = Kc (tauI s + 1) / (tauI s) (tauD s + 1).
 *    Series to ideal (exact without the filter): with
 *    f = 1 + tauD / tauI, Kc' = Kc f, tauI' = tauI f, tauD' = tauD / f. The
 *    ideal form has a series equivalent only when tauI' >= 4 tauD'.
 * A PI controller is the case tauD = 0 (and Tf = 0).
 *
 * Which model a rule sees. SOPDT models are in form (2),
 * k e^{-Td s} / (s^2 + a s + b):
 *  - real poles (a^2 >= 4 b > 0): time constants T1 >= T2; rules that need
 *    a FOPDT get Skogestad's half rule, tau = T1 + T2 / 2,
 *    theta = Td + T2 / 2;
 *  - complex poles (a^2 < 4 b): the PID rules that cancel the quadratic
 *    (SIMC and IMC PID) keep it; the others get the half rule with the
 *    pair split equally by its real part re = a / (2 b): tau = 1.5 re,
 *    theta = Td + re / 2 (continuous with the real pair at zeta = 1);
 *  - b = 0, the integrator with a lag (k / a) e^{-Td s} / (s (s / a + 1)):
 *    each family's rule for integrating processes, with the lag turned
 *    into dead time (half rule) for PI and AMIGO, cancelled by the
 *    derivative for SIMC and IMC PID.
 *
 * Refusal. Gains are refused, with nothing written, when:
 *  - the model or a knob is invalid (PDT_ERR_ARG);
 *  - the rule has no form for this model (PDT_ERR_NO_FORM);
 *  - the identification's fit is below cfg.fit_min (PDT_ERR_POOR_FIT);
 *  - the loop the gains make with the model is unstable (PDT_ERR_UNSTABLE);
 *  - its maximum sensitivity Ms exceeds cfg.ms_max (PDT_ERR_MS_LIMIT).
 * When the identification itself failed, e.g. PDT_ERR_NO_EXCITATION
 * because the input or the output did not move, there is no model: pass
 * that status on instead of calling this module.
 */
#ifndef PDT_TUNE_H
#define PDT_TUNE_H

#include "pdt/pdt_common.h"
#include "pdt/pdt_model.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Points of the log-spaced frequency grid of pdt_tune_robustness. */
#define PDT_TUNE_GRID 400u

typedef enum pdt_tune_rule {
    PDT_TUNE_SIMC = 0,  /* Skogestad (2003), knob tau_c */
    PDT_TUNE_IMC = 1,   /* IMC / lambda tuning, Rivera, Morari and Skogestad
                         * (1986), knob lambda */
    PDT_TUNE_AMIGO = 2, /* Astrom and Hagglund (2006), no knob */
    PDT_TUNE_ZN = 3     /* Ziegler and Nichols (1942) from the model's
                         * ultimate gain and period, no knob */
} pdt_tune_rule_t;

typedef enum pdt_tune_form { PDT_TUNE_PI = 0, PDT_TUNE_PID = 1 } pdt_tune_form_t;

typedef struct pdt_tune_config {
    pdt_tune_rule_t rule;    /* Default SIMC */
    pdt_tune_form_t form;    /* Default PI */
    pdt_real_t tau_c;        /* SIMC closed-loop time constant, s, >= 0; 0
                            * means theta, the dead time the rule uses
                            * (Skogestad's default). Default 0 */
    pdt_real_t lambda;       /* IMC closed-loop time constant, s, >= 0; 0
                            * means max(tau, 3 theta) of the time constant
                            * and dead time the rule uses (3 theta for an
                            * integrating model). Default 0 */
    pdt_real_t detune;       /* factor on the knob (tau_c or lambda, given
                            * or default), >= 1, or 0 for 1: a slower,
                            * more robust loop. Default 0 */
    pdt_real_t deriv_filter; /* N: the derivative is filtered with
                              * Tf = tauD / N (tauD of the form the rule
                              * is stated in); >= 1, or 0 for no filter.
                              * Default 10 */
    pdt_real_t fit_min;      /* refuse when the fit is below this, percent,
                            * finite; 0 (the default) refuses nothing:
                            * the autotune decides by the evidence of
                            * pdt_validate.h instead */
    pdt_real_t ms_max;       /* refuse when Ms exceeds this; > 1, or 0 for no
                            * limit. Default 2.0 */
} pdt_tune_config_t;

/* One PI/PID gain set, in the form its context says (ideal or series). */
typedef struct pdt_tune_gains {
    pdt_real_t Kc;   /* proportional gain, input units per output unit,
                      * finite, non-zero */
    pdt_real_t tauI; /* integral time, s, finite, > 0 */
    pdt_real_t tauD; /* derivative time, s, finite, >= 0 (0: PI) */
    pdt_real_t Tf;   /* derivative filter time constant, s, finite, >= 0
                      * (0: unfiltered). In the series form the filter
                      * is read the same way, on the derivative term of
                      * the equivalent ideal form */
} pdt_tune_gains_t;

/* Robustness of the loop L(s) = C(s) G(s), dead time included. */
typedef struct pdt_tune_figures {
    pdt_real_t Ms;               /* max over w of |1 / (1 + L(jw))|, >= 1 */
    pdt_real_t w_ms;             /* where it peaks, rad/s; +infinity when the
                                  * supremum is the high-frequency limit
                                  * (|S| -> 1, or 1 / (1 - r) below) */
    pdt_real_t gain_margin;      /* factor: 1 / |L| where L crosses the
                                  * negative real axis farthest out;
                                  * +infinity when it never crosses */
    pdt_real_t w_pc;             /* that phase crossover, rad/s (0 if none) */
    pdt_real_t phase_margin_deg; /* 180 + arg L(j w_gc), degrees, the least
                                  * over the gain crossovers |L| = 1 */
    pdt_real_t w_gc;             /* that gain crossover, rad/s */
} pdt_tune_figures_t;

typedef struct pdt_tune_result {
    pdt_tune_gains_t ideal;  /* the gains, ideal (parallel) form */
    pdt_tune_gains_t series; /* the same controller in series form; valid
                               * only when series_exists (else all 0) */
    bool series_exists;      /* tauI >= 4 tauD in the ideal form */
    bool series_rule;        /* the rule is stated in series form (SIMC):
                               * `series` holds its own numbers */
    pdt_real_t knob;         /* tau_c (SIMC) or lambda (IMC) used, s; 0
                               * for the rules without a knob */
    pdt_tune_figures_t fig;  /* robustness of the ideal gains with the
                               * model (pdt_tune_robustness) */
} pdt_tune_result_t;

/* Fills cfg with the documented defaults. Does nothing for NULL. */
void pdt_tune_config_default(pdt_tune_config_t *cfg);

/* Gains for model m by cfg's rule and form, their series equivalent and
 * the robustness of the loop, into *out (caller-owned).
 * fit: the identification's fit, percent (pdt_ident_result_t.fit); pass
 * 100 for a model known rather than identified.
 * Returns, checked in this order:
 *  PDT_ERR_ARG      NULL pointer, invalid model (pdt_model_check), unknown
 *                   rule or form, a knob negative or not finite,
 *                   deriv_filter in (0, 1), ms_max in (0, 1], fit or
 *                   fit_min not finite, a zero gain, or a rule that needs
 *                   dead time given none: SIMC with tau_c + theta = 0,
 *                   AMIGO with theta = 0;
 *  PDT_ERR_NO_FORM  the rule has no form for this model: ZN on a model
 *                   whose phase never reaches -180 degrees (no dead
 *                   time);
 *  PDT_ERR_POOR_FIT fit < fit_min;
 *  PDT_ERR_UNSTABLE the loop is unstable;
 *  PDT_ERR_MS_LIMIT Ms > ms_max (ms_max != 0).
 * *out is written only on PDT_OK. To see the gains a limit refuses, call
 * again with ms_max = 0 (and fit_min below the fit).
 * Work: the rule is O(1) (ZN adds a 60-step bisection for the ultimate
 * point); the robustness as pdt_tune_robustness. No memory beyond the
 * stack frame. */
pdt_status_t pdt_tune_compute(const pdt_model_t *m, pdt_real_t fit, const pdt_tune_config_t *cfg,
                              pdt_tune_result_t *out);

/* Robustness figures of the ideal-form controller g with model m, into
 * *fig (caller-owned): Ms, gain and phase margins and their frequencies,
 * stability by the Nyquist criterion. Usable on any gains, e.g. a
 * controller already in service or a relay tuner's. Fixed memory, bounded
 * work (at most 64 PDT_TUNE_GRID + 16 + 8 x 42 + 60 per crossing
 * evaluations of L); the grid, refinements and limits are in
 * docs/tuning.md ("Robustness figures").
 * Returns PDT_ERR_ARG (NULL, invalid model, a gain outside its domain as
 * documented on pdt_tune_gains_t, or time scales of model and controller
 * so far apart that the frequency range leaves the real type),
 * PDT_ERR_UNSTABLE (the closed loop is unstable, or cannot be shown
 * stable; *fig is untouched then). */
pdt_status_t pdt_tune_robustness(const pdt_model_t *m, const pdt_tune_gains_t *g,
                                 pdt_tune_figures_t *fig);

/* pdt_tune_compute in bounded steps, for a caller with a time budget per
 * call (the autotune runs one step per scan). pdt_tune_begin checks the
 * arguments and computes the rule's gains (O(1), ZN's bisection aside)
 * and the robustness scan's frequency range; each pdt_tune_step then
 * continues pdt_tune_robustness's scan by about PDT_TUNE_STEP_EVALS
 * evaluations of L: grid intervals until the step has made that many (an
 * interval is never cut: the last can add its sub-steps, at most 64, and a
 * crossing's bisection, 61), then the peaks' refinements (42 each) while
 * the budget lasts. The state lives in work (caller memory of
 * pdt_tune_run_workspace_size() bytes, PDT_TUNE_RUN_WORKSPACE_SIZE), which
 * must stay untouched until the last step; no other memory is kept. The
 * result is pdt_tune_compute's, bit for bit (the same operations in the
 * same order).
 * pdt_tune_begin returns PDT_ERR_NOMEM (work NULL or too small) or what
 * pdt_tune_compute returns before its robustness (PDT_ERR_ARG,
 * PDT_ERR_NO_FORM, PDT_ERR_POOR_FIT, ...), PDT_OK when the steps can
 * start. pdt_tune_step returns PDT_ERR_ARG (NULL), PDT_ERR_STATE (work not
 * begun), PDT_RUNNING (more steps), PDT_ERR_UNSTABLE, PDT_ERR_ARG,
 * PDT_ERR_MS_LIMIT, or PDT_OK with *out written; once finished, every
 * later call returns the same status (and writes *out again on PDT_OK). */
#define PDT_TUNE_STEP_EVALS         128u
#define PDT_TUNE_RUN_WORKSPACE_SIZE (128u * sizeof(pdt_real_t) + 16u * sizeof(void *) + 64u)
size_t pdt_tune_run_workspace_size(void);
pdt_status_t pdt_tune_begin(const pdt_model_t *m, pdt_real_t fit, const pdt_tune_config_t *cfg,
                            void *work, size_t work_len);
pdt_status_t pdt_tune_step(void *work, pdt_tune_result_t *out);

/* Classic Ziegler-Nichols (1942) gains from the ultimate gain Ku (input
 * units per output unit; negative for a reverse-acting loop) and the
 * ultimate period Pu (s), e.g. from a relay test, into *out, ideal form
 * with Tf = 0: PI Kc = 0.45 Ku, tauI = Pu / 1.2; PID Kc = 0.6 Ku,
 * tauI = Pu / 2, tauD = Pu / 8 (a double zero: series Kc = 0.3 Ku,
 * tauI = tauD = Pu / 4). Returns PDT_ERR_ARG for NULL out, Ku zero or not
 * finite, Pu not finite and > 0, an unknown form, or gains that underflow
 * (a Ku or Pu at the bottom of the real range); *out untouched then.
 * O(1). */
pdt_status_t pdt_tune_ziegler_nichols(pdt_real_t Ku, pdt_real_t Pu, pdt_tune_form_t form,
                                      pdt_tune_gains_t *out);

/* The series form of ideal-form gains, when it exists (tauI >= 4 tauD):
 * the larger root of x^2 - tauI x + tauI tauD as the series tauI, the
 * smaller as tauD, Kc scaled by tauI_series / tauI (a factor in
 * [1/2, 1], so finite gains stay finite); Tf copied. Returns
 * PDT_ERR_ARG (NULL, gains outside their domain, series gains that would
 * leave it, e.g. a subnormal Kc halved to 0), PDT_ERR_NO_FORM
 * (tauI < 4 tauD: complex zeros); *series untouched then. O(1). */
pdt_status_t pdt_tune_to_series(const pdt_tune_gains_t *ideal, pdt_tune_gains_t *series);

/* The ideal form of series-form gains: f = 1 + tauD / tauI, Kc f,
 * tauI f, tauD / f; Tf copied. PDT_ERR_ARG for NULL or gains outside their
 * domain; *ideal untouched then. O(1). */
pdt_status_t pdt_tune_to_ideal(const pdt_tune_gains_t *series, pdt_tune_gains_t *ideal);

#ifdef __cplusplus
}
#endif

#endif /* PDT_TUNE_H */
