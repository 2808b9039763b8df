/*
 * pdtfit autotune: one state machine that a PLC task or an MCU loop calls
 * once per scan. It holds the output while it measures the operating point,
 * runs an experiment (step, pulse, chirp, PRBS or relay) inside safety
 * limits while recording, identifies a FOPDT and a SOPDT and keeps the
 * order the data support (or the one model asked for) in bounded steps, and
 * turns the model into PI/PID gains with robustness figures, or refuses.
 *
 * Per scan:
 *
 *   pdt_real_t u;
 *   pdt_status_t st = pdt_autotune_scan(&at, pv, &u);   // read pv, get u
 *   write_output(u);
 *   if (st == PDT_OK)         { pdt_autotune_result(&at, &r); ... }  // gains
 *   else if (st != PDT_RUNNING) { ... }  // aborted or refused: u is safe
 *
 * The output returned is always the one to apply: the excitation while the
 * experiment runs, the operating point u0 before and after it, and u0 after
 * an abort. pv is the process value read in this scan, before the output
 * is written; the output then holds until the next scan (zero-order hold),
 * which is the convention of the identification.
 *
 * Recording: with decimation D, each identification sample pairs the mean
 * output and the mean process value over its D scans (an anti-alias
 * filter; see pdt_record.h). The process value's mean is centred
 * (D - 1) / 2 scans after the interval's start, so the identified dead time
 * is (D - 1) Ts / 2 short; the autotune adds it back to the model it
 * reports.
 *
 * Work per call (worst case): settle and excite, O(1); the first identify
 * call prepares the identification (O(n), plus O(N_f log N_f) for the
 * frequency or combined criterion); every other identify call at most
 * evals_per_scan cost evaluations of the whole record, or PDT_VECTOR_LANES
 * where that is larger (O(n) each, O(N_f) for the frequency part; on the
 * identification's coarse record D evaluations take the time of one,
 * pdt_ident_step) plus one GA breeding
 * step (O(P^2)); the identification's stages that are not evaluations
 * (its screen for gross errors, the parameters' uncertainty) one call
 * each, O(n). Each model's validation in steps, one pdt_validate_step a
 * call (pdt_validate.h: the preparation, O(n); PDT_FISHER_BLOCK samples of
 * the sensitivities' pass; the residual's statistics, O(n);
 * PDT_VALIDATE_FIR_ROWS rows of the FIR). Each knob factor's tuning in
 * steps, one pdt_tune_step a call (pdt_tune.h: the rule's gains, then about
 * PDT_TUNE_STEP_EVALS evaluations of the loop's response a call), then one
 * call for pdt_validate_margin (200 frequencies); at most 9 knob factors.
 * The state of both steps lives in the workspace. The
 * disturbance check: O(n) in the identify call that chooses the order; a
 * drift found repeats the identification (at most drift_passes times), a
 * disturbed record the experiment (at most repeats times). With the loop
 * closed, one pdt_pid_update per call more.
 *
 * With the loop closed (pdt_autotune_init_closed) the caller's pdt_pid
 * stays in control: the experiment moves its set-point, and the new gains
 * are handed to it without a bump (docs/autotune.md, "Retune with the
 * loop closed").
 *
 * Decisions by evidence (docs/autotune.md): the model is validated
 * against the record (residual tests, parameter covariance), by default
 * (order_auto) a FOPDT and a SOPDT are identified and the data choose, and
 * the gains must keep the robust Ms bound at most ms_robust, the knob
 * raised until they do; else PDT_ERR_MODEL_INVALID or PDT_ERR_UNCERTAIN.
 */
#ifndef PDT_AUTOTUNE_H
#define PDT_AUTOTUNE_H

#include "pdt/pdt_common.h"
#include "pdt/pdt_excite.h"
#include "pdt/pdt_ident.h"
#include "pdt/pdt_pid.h"
#include "pdt/pdt_record.h"
#include "pdt/pdt_tune.h"
#include "pdt/pdt_validate.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum pdt_autotune_phase {
    PDT_AUTOTUNE_SETTLE = 1,   /* output held, operating point measured */
    PDT_AUTOTUNE_EXCITE = 2,   /* the experiment runs and is recorded */
    PDT_AUTOTUNE_IDENTIFY = 3, /* output at u0, model identified in steps */
    PDT_AUTOTUNE_TUNE = 4,     /* gains computed (one scan) */
    PDT_AUTOTUNE_DONE = 5,     /* model and gains ready */
    PDT_AUTOTUNE_FAILED = 6    /* aborted or refused: see the status */
} pdt_autotune_phase_t;

typedef struct pdt_autotune_config {
    pdt_real_t Ts;           /* scan period, s, > 0. Default 0 (must be set) */
    uint32_t decimation;     /* scans per identification sample, >= 1: the
                               * identification runs at Ts * decimation.
                               * Default 1 */
    size_t capacity;         /* most samples recorded (identification rate),
                               * PDT_MIN_SAMPLES + settle ..
                               * PDT_MAX_SAMPLES (pdt_config.h, 2^20 by
                               * default; a scan's work grows with it);
                               * sizes the workspace. Default 0 (must be
                               * set) */
    uint32_t settle;         /* identification samples at u0 before the
                               * excitation, to measure the operating point.
                               * Default 20 */
    uint32_t tail;           /* identification samples still recorded after
                               * the excitation ends (the process is still
                               * responding); 0: until the record is full.
                               * Default 0 */
    uint32_t evals_per_scan; /* cost evaluations of the whole record per
                               * scan while identifying (pdt_ident_step),
                               * >= 1. Default 4 */
    /* The experiment. Set kind, levels and timing; the autotune sets Ts
     * (the scan period), u0 (the output at init) and pre (the settle
     * time) itself, and the limits from u_min, u_max below. */
    pdt_excite_config_t excite;
    /* Safety limits, checked every scan until the end (also while
     * identifying, with the output back at u0). */
    pdt_real_t u_min; /* output limits. Default -/+ the largest real */
    pdt_real_t u_max;
    pdt_real_t pv_min;      /* process value limits. Default -/+ the */
    pdt_real_t pv_max;      /* largest real: set them */
    uint32_t max_scans;     /* the experiment's time limit in scans; 0:
                               * none. Default 0 */
    pdt_record_move_t move; /* set-point check of the recorder (a relay's
                               * set-point must be crossable). Default ANY */
    /* The identification: model, criterion, bounds, search. Ts is set by
     * the autotune (Ts * decimation). */
    pdt_ident_config_t ident;
    /* The tuning rule and its refusal limits (fit_min, ms_max). */
    pdt_tune_config_t tune;
    /* Model order. true: a FOPDT and a SOPDT (which covers the
     * underdamped and the integrating process) are identified on the
     * record and pdt_ident_select_order picks one; ident.model is then
     * not used (init still checks it). false: ident.model only, an
     * order the caller fixes. Default true (docs/autotune.md) */
    bool order_auto;
    /* The decision by evidence (pdt_validate.h). The gains must keep the
     * robust bound of the true loop's Ms (pdt_validate_margin: the model
     * error the residual shows and the parameters' confidence region)
     * at most ms_robust, > 1, or 0 for no such check; tau_c (SIMC) or
     * lambda (IMC) is raised in steps until they do. Default 2.0. With
     * 0 and order_auto false the model is not validated (has_valid false)
     * and the workspace is the identification's alone */
    pdt_real_t ms_robust;
    /* A relay test's Ku and Pu and the model's must agree within this
     * factor, >= 1, or 0 for no check. Default 2 */
    pdt_real_t relay_agree;
    /* The disturbance check (docs/autotune.md, "Faults of a real plant").
     * The record is disturbed when the residual of the model kept shifts
     * its level across the record by more than shift_max of the model's
     * output range (pdt_autotune_result_t.shift: a load change or a
     * drift), or a relay's measured cycles spread in length or amplitude
     * by more than relay_spread_max of their mean. A disturbed experiment
     * is repeated from the operating point up to `repeats` times, then
     * refused with PDT_ERR_DISTURBED. shift_max and relay_spread_max
     * >= 0, 0: no such check. Defaults 0.08, 0.5 and 1.
     * A residual that a straight line explains better than a level shift
     * is a drift: it is fitted (removed from the record) and the record
     * identified again, up to drift_passes times, before the experiment
     * is called disturbed; 0: a drift is refused like a load change.
     * Default 3 */
    pdt_real_t shift_max;
    pdt_real_t relay_spread_max;
    uint32_t repeats;
    uint32_t drift_passes;
    /* true: the port reads the actuator's position, passed to
     * pdt_autotune_scan_position each scan, and the record holds the
     * actuator as it moved (a rate limit, a sticky valve) instead of the
     * output as commanded. Default false */
    bool actuator_position;
} pdt_autotune_config_t;

typedef struct pdt_autotune_result {
    pdt_status_t status;            /* PDT_OK, or why it failed: an abort
                               * (PDT_ERR_PV_LIMIT, ...), data that could
                               * not support a model, or refused gains
                               * (PDT_ERR_DISTURBED, PDT_ERR_MODEL_INVALID,
                               * PDT_ERR_UNCERTAIN, PDT_ERR_POOR_FIT,
                               * PDT_ERR_MS_LIMIT, PDT_ERR_UNSTABLE) */
    pdt_autotune_phase_t failed_in; /* the phase that failed (when it did) */
    bool has_model;                 /* the identification finished */
    pdt_ident_result_t ident;       /* the model, fit and operating point */
    bool has_gains;                 /* gains passed the refusal rules */
    pdt_tune_result_t tune;         /* the gains and their robustness */
    bool has_valid;                 /* the model was validated */
    pdt_validate_result_t valid;    /* residual tests, parameter std and
                               * covariance of the model kept (its dead
                               * time before the decimation shift) */
    pdt_real_t bic_other;           /* order_auto: BIC of the model not kept */
    pdt_real_t ms_robust;           /* robust Ms bound of the gains kept */
    pdt_real_t detune;              /* factor on the rule's knob (tau_c,
                               * lambda) the evidence asked for, >= 1 */
    bool has_relay;                 /* the experiment was a relay test */
    pdt_excite_relay_t relay;       /* Ku, Pu measured by the relay */
    size_t samples;                 /* samples recorded */
    uint32_t scans;                 /* scans since init */
    uint32_t scans_experiment;      /* scans of settle + experiment */
    pdt_real_t shift;               /* the residual's level shift, fraction
                               * of the model's output range (the
                               * disturbance check; 0 until computed) */
    pdt_real_t relay_spread;        /* spread of the relay's cycles */
    uint32_t repeats;               /* experiments repeated (disturbed) */
    pdt_real_t drift;               /* the drift fitted and removed from the
                               * record, pv units per s (0: none) */
    uint32_t drift_passes;          /* identifications of the detrended record */
    pdt_real_t noise;               /* pv's noise sd over the settle window,
                               * from its first differences, pv units */
    pdt_real_t quantum;             /* the smallest step between two pv
                               * readings there (a sensor's resolution) */
    pdt_real_t response;            /* range of the model's output over the
                               * record, pv units: it must span at least
                               * 4 quanta, else PDT_ERR_NO_EXCITATION */
    pdt_real_t relay_eps;           /* the relay's hysteresis used: the
                               * config's, raised to 3 noise and one
                               * quantum (other experiments: the config's) */
} pdt_autotune_result_t;

/* The autotune. Fields are private. */
typedef struct pdt_autotune {
    pdt_autotune_config_t cfg;
    uint32_t magic;
    pdt_autotune_phase_t phase;
    pdt_real_t u_init; /* output at init: the operating point */
    pdt_real_t u_hold; /* output applied while identifying */
    pdt_real_t *u;     /* record (workspace) */
    pdt_real_t *y;
    void *ident_work;    /* identification's part of the workspace */
    pdt_real_t *scratch; /* the same memory, as reals */
    size_t ident_work_len;
    size_t tail_end;          /* samples recorded when the tail is complete */
    bool excite_over;         /* the excitation has ended */
    bool ident_started;       /* pdt_ident_init has run */
    bool valid_started;       /* pdt_validate_begin has run */
    uint32_t stage;           /* identify: models done and validated */
    uint32_t tune_try;        /* tune: knob factors tried */
    uint32_t tune_stage;      /* tune: where the factor's tuning is */
    pdt_ident_result_t first; /* order_auto: the FOPDT */
    pdt_validate_result_t first_valid;
    pdt_status_t tune_why; /* why the last knob factor was refused */
    pdt_excite_t gen;
    pdt_record_t rec;
    pdt_ident_t ident;
    pdt_autotune_result_t res;
    pdt_pid_t *pid;     /* closed loop: the controller in service, else NULL */
    pdt_real_t sp0;     /* closed loop: the set-point in service */
    bool pid_ran;       /* closed loop: this scan's output is the PID's */
    pdt_real_t u_last;  /* the output of the last scan */
    uint32_t pv_n;      /* settle: readings seen, the last, and the sum */
    pdt_real_t pv_prev; /* of squared differences */
    pdt_real_t pv_d2;
    pdt_real_t u_pos; /* actuator_position: the position read this scan */
} pdt_autotune_t;

/* Fills cfg with the documented defaults, and its sub-configs with theirs
 * (the experiment a PRBS of 7 bits, amplitude 1). Nothing for NULL. */
void pdt_autotune_config_default(pdt_autotune_config_t *cfg);

/* Workspace bytes for cfg: 2 capacity reals for the record plus the
 * larger of the identification's workspace for capacity samples (either
 * model with order_auto) and the validation's in steps
 * (pdt_validate_run_workspace_size: 5 capacity reals, or 3 and the steps'
 * state when that is more; asked for only with order_auto or
 * ms_robust > 0). 0 when cfg is NULL or
 * not valid (init then says why). */
size_t pdt_autotune_workspace_size(const pdt_autotune_config_t *cfg);

/* Compile-time upper bound of the workspace for a record of capacity
 * samples and a GA population of pop (PDT_IDENT_POPULATION_SOPDT covers both
 * automatic populations), any configuration: for static arrays. */
#define PDT_AUTOTUNE_WORKSPACE_SIZE(capacity, pop)                                                 \
    (2u * (size_t)(capacity) * sizeof(pdt_real_t) +                                                \
     (PDT_IDENT_WORKSPACE_SIZE(capacity, pop) > PDT_VALIDATE_RUN_WORKSPACE_SIZE(capacity)          \
          ? PDT_IDENT_WORKSPACE_SIZE(capacity, pop)                                                \
          : PDT_VALIDATE_RUN_WORKSPACE_SIZE(capacity)))

/* Prepares at for an autotune starting from the output u_now, which is
 * taken as the operating point: the process must be at rest there. work is
 * caller memory of pdt_autotune_workspace_size bytes, aligned for
 * pdt_real_t, owned by at until it is done.
 * Returns PDT_ERR_ARG (NULL, a bad value in cfg or in the identification's
 * config, u_now not finite, misaligned work), PDT_ERR_BOUNDS (limits
 * inverted), PDT_ERR_OUTPUT_LIMIT (u_now or the experiment's levels outside
 * the output limits), PDT_ERR_LENGTH (capacity above PDT_MAX_SAMPLES),
 * PDT_ERR_TOO_SHORT (capacity below settle + PDT_MIN_SAMPLES), PDT_ERR_NOMEM (work NULL or too small), or what
 * pdt_excite_init / pdt_record_init return for the experiment's config; at
 * is untouched on error. O(1). */
pdt_status_t pdt_autotune_init(pdt_autotune_t *at, const pdt_autotune_config_t *cfg,
                               pdt_real_t u_now, void *work, size_t work_len);

/* Prepares at for a retune with the loop closed (docs/autotune.md,
 * "Retune with the loop closed"): pid, the caller's initialised controller
 * in service, stays in control throughout, and the experiment moves its
 * set-point instead of the output. cfg->excite.kind is STEP (a set-point
 * step, held while recorded), PULSE (a step up and back) or PRBS (a small
 * set-point dither); its amplitude is in pv units and the set-point stays
 * inside [pv_min, pv_max]. sp is the set-point in service, to which the
 * loop returns once the record is complete. The model is identified from
 * the closed-loop record (the PID's output u to pv, output error), tuned
 * and checked as in the open loop; on PDT_OK the new gains replace pid's
 * without a bump (pdt_pid_set_gains, ideal form); on a refusal or an abort
 * pid keeps its gains. After the end pdt_autotune_scan goes on running
 * pid at sp, so the caller may keep calling it. pid and its state belong
 * to at until the end; its output limits stay in force, and u_min, u_max
 * are checked as in the open loop.
 * Returns as pdt_autotune_init, also PDT_ERR_ARG for a relay experiment
 * or a sp that is not finite, PDT_ERR_STATE for a pid not initialised,
 * PDT_ERR_OUTPUT_LIMIT for sp outside [pv_min, pv_max]. O(1). */
pdt_status_t pdt_autotune_init_closed(pdt_autotune_t *at, const pdt_autotune_config_t *cfg,
                                      pdt_pid_t *pid, pdt_real_t sp, void *work, size_t work_len);

/* One scan: pv is the process value read now; *u receives the output to
 * apply until the next scan (always written, even on error, when at and u
 * are not NULL and at was initialised).
 * Returns PDT_RUNNING while the autotune goes on, PDT_OK once model and
 * gains are ready (and on every later call), or the status that ended it
 * (an abort, a refusal; the same on every later call). PDT_ERR_ARG for NULL,
 * PDT_ERR_STATE if at was never initialised. Work: see the top of this
 * file. */
pdt_status_t pdt_autotune_scan(pdt_autotune_t *at, pdt_real_t pv, pdt_real_t *u);

/* pdt_autotune_scan for a port that reads the actuator's position: u_pos
 * is the position read now, where the output of the last scan has taken
 * the actuator (input units). With cfg.actuator_position the record holds
 * these positions, each paired with the scan before (the interval it was
 * held over), and the model's dead time is corrected for that scan; the
 * safety limits u_min, u_max then apply to the position. Without it u_pos
 * is not used. pdt_autotune_scan on such an autotune takes the last
 * output as the position. Same returns as pdt_autotune_scan (a position
 * that is not finite aborts the experiment: PDT_ERR_NONFINITE). */
pdt_status_t pdt_autotune_scan_position(pdt_autotune_t *at, pdt_real_t pv, pdt_real_t u_pos,
                                        pdt_real_t *u);

/* Stops the autotune now (e.g. the operator cancels): unless it is already
 * done or failed, the phase becomes FAILED with the status PDT_ERR_ABORTED.
 * *u receives the output to apply: the operating point (the output at init
 * if the operating point is not measured yet); with the loop closed, the
 * PID's last output (the PID, its gains unchanged, goes on at the
 * set-point in service with the next scan). Returns PDT_OK, PDT_ERR_ARG
 * for NULL, PDT_ERR_STATE if never initialised. O(1). */
pdt_status_t pdt_autotune_abort(pdt_autotune_t *at, pdt_real_t *u);

/* The phase now, for display. 0 for NULL or an uninitialised at. */
pdt_autotune_phase_t pdt_autotune_phase(const pdt_autotune_t *at);

/* What happened: model, gains, relay figures, counts. Valid in any phase
 * (fields not reached yet are flagged false). PDT_ERR_ARG for NULL,
 * PDT_ERR_STATE if never initialised. O(1). */
pdt_status_t pdt_autotune_result(const pdt_autotune_t *at, pdt_autotune_result_t *out);

#ifdef __cplusplus
}
#endif

#endif /* PDT_AUTOTUNE_H */
