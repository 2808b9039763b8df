/*
 * pdtfit loop-performance monitor: called once per scan beside the PID with
 * the set-point, the process value and the controller output, it keeps
 * statistics over a moving horizon and says whether the loop needs a
 * retune, and why (docs/monitor.md gives the tests, their thresholds and
 * the reasons for them).
 *
 * The tests, each on the monitor's samples (block averages of `decimation`
 * scans), with the control error e = sp - pv:
 *  - oscillation: the autocorrelation of e (lags up to PDT_MONITOR_ORDER
 *    from the data, beyond by its AR model's continuation), per sample and
 *    per PDT_MONITOR_COARSE samples; the index sqrt(-first minimum x the
 *    maximum after it) and the period. An oscillation at least as slow as
 *    the set-point's steps is `forced` and does not vote. With a model, the
 *    residual v = pv - model output correlated against e names a sticky
 *    valve as the suspected cause; without, the correlation of u with e at
 *    lag zero (Horch). Forsman and Stattin's zero-crossing regularity (the
 *    statistic behind Hagglund's detector) and the amplitude are reported;
 *  - the Harris index: the minimum variance the model's dead time allows
 *    over the variance of e, from an autoregressive model of e of order
 *    PDT_MONITOR_ORDER (autocovariances over the horizon, Levinson-Durbin);
 *  - sluggishness: the IAE of e over the IAE a reference loop would have
 *    had (the model under SIMC PI gains, driven by the same set-point and
 *    the disturbance the model reveals); without a model, Hagglund's idle
 *    index;
 *  - saturation: the share of scans with u at a limit;
 *  - model mismatch: the model's output from the recorded u against pv;
 *    the difference regressed on the set-point, whose moves the
 *    disturbances cannot explain, with a t test corrected for the
 *    difference's autocorrelation.
 *
 * Memory: the caller-owned pdt_monitor_t, nothing else: 1 312 B (float),
 * 2 560 B (double) on the Cortex-M4F (docs/memory.md). Work, bounded:
 * pdt_monitor_scan is O(1) on a scan that only adds to the block and
 * O(PDT_MONITOR_ORDER) on a scan that completes a sample (about 1 300
 * instructions on x86-64); pdt_monitor_result is O(PDT_MONITOR_ORDER x
 * PDT_MONITOR_ACF_LAGS) (about 10 000); pdt_monitor_init runs one
 * pdt_tune_compute. docs/reports/monitor.md measures them.
 */
#ifndef PDT_MONITOR_H
#define PDT_MONITOR_H

#include "pdt/pdt_common.h"
#include "pdt/pdt_discrete.h"
#include "pdt/pdt_model.h"
#include "pdt/pdt_pid.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Order of the autoregressive model of the error (lags kept). The model's
 * dead time must be below PDT_MONITOR_ORDER samples (of Ts * decimation):
 * choose the decimation so. Override before including, 4..64. */
#ifndef PDT_MONITOR_ORDER
#define PDT_MONITOR_ORDER 24u
#endif
#if (PDT_MONITOR_ORDER < 4u) || (PDT_MONITOR_ORDER > 64u)
#error "PDT_MONITOR_ORDER must be in 4..64"
#endif
/* Samples averaged into one of the coarse error, whose autocorrelation
 * sees periods up to PDT_MONITOR_COARSE times longer. */
#define PDT_MONITOR_COARSE   8u
/* Lags of the error's autocorrelation scanned for an oscillation (beyond
 * PDT_MONITOR_ORDER, the AR model's continuation). */
#define PDT_MONITOR_ACF_LAGS (16u * PDT_MONITOR_ORDER)
/* Length of the input histories the model simulations keep. */
#define PDT_MONITOR_RING     (PDT_MONITOR_ORDER + 3u)

typedef enum pdt_monitor_verdict {
    PDT_MONITOR_NOT_ENOUGH_DATA = 0, /* fewer than min_samples samples */
    PDT_MONITOR_OK = 1,
    PDT_MONITOR_OSCILLATING = 2,   /* see `cause` */
    PDT_MONITOR_SLUGGISH = 3,      /* retune for a faster loop */
    PDT_MONITOR_MODEL_CHANGED = 4, /* the process no longer matches the model:
                                    * identify again, then retune */
    PDT_MONITOR_SATURATED = 5      /* the output sits at a limit: no tuning
                                   * helps (actuator size, set-point) */
} pdt_monitor_verdict_t;

typedef enum pdt_monitor_cause {
    PDT_MONITOR_CAUSE_NONE = 0,
    PDT_MONITOR_CAUSE_TUNING = 1,  /* u and e in phase: the loop's own gain */
    PDT_MONITOR_CAUSE_STICTION = 2 /* u and e a quarter period apart: a
                                    * sticky valve (Horch) */
} pdt_monitor_cause_t;

typedef struct pdt_monitor_config {
    pdt_real_t Ts;        /* scan period, s, finite, > 0. Default 0.1 */
    uint32_t decimation;  /* scans averaged into one sample, >= 1. Default 1 */
    uint32_t horizon;     /* memory of the statistics, samples: weights decay
                          * by e^-1 over that many; 0 = no forgetting (a
                          * whole record). Default 3000 */
    uint32_t min_samples; /* samples before any verdict, >= 16. Default 400 */
    bool has_model;       /* `model` is given. Default false */
    pdt_model_t model;    /* the process, u -> pv (pdt_model_check) */
    pdt_real_t u_min;     /* the output's limits, output units; u_min =   */
    pdt_real_t u_max;     /* u_max: no saturation test. Default 0 and 0 */
    pdt_real_t sat_band;  /* "at a limit": within this fraction of
                           * u_max - u_min, in [0, 0.5). Default 0.005 */
    /* Thresholds (docs/monitor.md says why these values). */
    pdt_real_t osc_acf;         /* oscillation index (the error's
                                * autocorrelation), (0, 1]. Default 0.14 */
    pdt_real_t stiction_corr;   /* no model: |corr(u, e)| below this names
                                * stiction, [0, 1]. Default 0.35 */
    pdt_real_t stiction_corr_v; /* with a model: corr(v, e) below minus this
                                 * names stiction (v = pv - model output),
                                 * [0, 1]. Default 0.12 */
    pdt_real_t sluggish_ratio;  /* IAE over the reference loop's, > 1.
                                * Default 2 */
    pdt_real_t idle_max;        /* idle index above this is sluggish (no
                                * model), (0, 1]. Default 0.4 */
    pdt_real_t sat_share;       /* share of scans at a limit, (0, 1].
                                * Default 0.1 */
    pdt_real_t mismatch_gain;   /* |process gain / model gain - 1| the set-
                                * point moves must show, > 0. Default 0.25 */
    pdt_real_t mismatch_t;      /* t statistic of that regression, > 0.
                                * Default 3.8 */
} pdt_monitor_config_t;

/* The verdict and the figures behind it (pdt_monitor_result). A figure
 * whose `has_` flag is false was not computed (no model, too little
 * movement) and is 0. */
typedef struct pdt_monitor_result {
    pdt_monitor_verdict_t verdict;
    pdt_monitor_cause_t cause; /* for PDT_MONITOR_OSCILLATING */
    uint32_t samples;          /* samples seen (capped at UINT32_MAX) */
    pdt_real_t weight;         /* their weight in the statistics (<= samples) */
    /* oscillation */
    pdt_real_t oscillation;  /* sqrt(-acf_min acf_max), [0, 1] */
    pdt_real_t acf_min;      /* the autocorrelation's first minimum (< 0) */
    pdt_real_t acf_max;      /* and the maximum after it (> 0) */
    pdt_real_t acf_period;   /* its period, s (0: fewer than 3 crossings) */
    uint32_t acf_scale;      /* samples per lag of the autocorrelation that
                              * gave them: 1, or PDT_MONITOR_COARSE when the
                              * coarse error's index is higher */
    pdt_real_t sp_moves;     /* weighted count of set-point steps (moves of
                              * more than half std(e) in one sample) */
    bool forced;             /* the period is as long as the mean interval
                              * between set-point steps or longer: the
                              * set-point may drive it; not an oscillation */
    pdt_real_t regularity;   /* share of regular half-period pairs, [0, 1] */
    pdt_real_t half_periods; /* weighted count of half-periods */
    pdt_real_t period;       /* mean oscillation period, s (0: none) */
    pdt_real_t amplitude;    /* mean amplitude of e, pv units (0: none) */
    pdt_real_t corr_ue;      /* corr(u, e) at lag 0, [-1, 1] */
    bool has_corr_ve;        /* a model gave v */
    pdt_real_t corr_ve;      /* corr(pv - model output, e), [-1, 1] */
    /* sluggishness */
    pdt_real_t idle_index; /* Hagglund's idle index, [-1, 1] */
    bool has_sluggish;     /* the model's reference loop ran */
    pdt_real_t iae_ratio;  /* IAE / reference IAE */
    /* saturation */
    bool has_saturation;   /* u_min < u_max */
    pdt_real_t saturation; /* share of scans at a limit, [0, 1] */
    /* variance */
    bool has_harris;        /* a model gave the dead time */
    pdt_real_t harris;      /* minimum variance / variance of e, (0, 1] */
    uint32_t delay_samples; /* the dead time used, samples (incl. the hold) */
    pdt_real_t std_e;       /* standard deviation of e, pv units */
    /* model mismatch */
    bool has_mismatch;     /* the set-point moved enough to test */
    pdt_real_t gain_ratio; /* process gain / model gain, as seen */
    pdt_real_t mismatch_t; /* its t statistic (|.|) */
} pdt_monitor_result_t;

/* Lagged products of one signal with forgetting (the monitor's error at
 * two time scales). */
typedef struct pdt_monitor_lags {
    pdt_real_t ring[PDT_MONITOR_ORDER]; /* the last values, newest at `at` */
    uint32_t at;
    uint32_t n;                            /* values seen (capped) */
    pdt_real_t w;                          /* sum of weights */
    pdt_real_t s;                          /* sum w x */
    pdt_real_t ss[PDT_MONITOR_ORDER + 1u]; /* sum w x(k) x(k - j) */
} pdt_monitor_lags_t;

/* The monitor. Caller-owned; fill it with pdt_monitor_init; the fields are
 * private (read the figures through pdt_monitor_result). */
typedef struct pdt_monitor {
    uint32_t magic;
    pdt_monitor_config_t cfg;
    pdt_real_t lambda;       /* forgetting factor per sample */
    pdt_real_t lambda_s;     /* and per scan */
    uint32_t n;              /* samples seen */
    uint32_t scans;          /* scans in the block being averaged */
    pdt_real_t blk[3];       /* block sums of sp, pv, u */
    pdt_real_t w, w2;        /* sum of weights, of squared weights */
    pdt_real_t sp0, pv0, u0; /* the first sample: the sums are of deviations */
    /* error statistics, per sample and per PDT_MONITOR_COARSE samples */
    pdt_monitor_lags_t el;
    pdt_monitor_lags_t ec;
    pdt_real_t lambda_c; /* forgetting factor per coarse sample */
    pdt_real_t ec_sum;   /* the coarse sample being summed */
    uint32_t ec_cnt;
    /* oscillation: half-periods of e between band crossings */
    int32_t sign;           /* side of the band e is on (0: not yet) */
    uint32_t hp_seen;       /* half-periods completed (capped) */
    pdt_real_t hp_iae;      /* IAE of the running half-period */
    uint32_t hp_len;        /* its samples */
    pdt_real_t prev_iae[2]; /* the two before it, [0] the latest */
    uint32_t prev_len[2];
    pdt_real_t n_reg, n_hp;       /* weighted regular pairs, half-periods */
    pdt_real_t s_len, s_amp;      /* weighted sums of 2 len and of amplitude */
    pdt_real_t sp_last, sp_moves; /* set-point steps, weighted */
    /* u against e; the idle index */
    pdt_real_t su, suu, sue;
    pdt_real_t lp_u, lp_pv, t_pos, t_neg;
    /* saturation, per scan */
    pdt_real_t sat_w, sat_hits;
    /* the model: its output from u, and the reference loop */
    pdt_discrete_t dm;
    uint32_t delay;                       /* whole samples + 1 (the hold) */
    pdt_real_t u_ring[PDT_MONITOR_RING];  /* u - u0, newest at r_at */
    pdt_real_t du_ring[PDT_MONITOR_RING]; /* reference u - u */
    uint32_t r_at;
    pdt_discrete_state_t ym; /* model output from u - u0 */
    pdt_discrete_state_t yd; /* model output from reference u - u */
    pdt_pid_t ref;           /* the reference loop's PI */
    pdt_real_t s_iae, s_iae_ref;
    /* mismatch: v = pv - pv0 - ym regressed on z = sp - sp0 */
    pdt_real_t sz, szz, sv, svv, szv, sve;
    pdt_real_t szzL, svvL, szvL, svzL;    /* products at lag PDT_MONITOR_ORDER */
    pdt_real_t z_ring[PDT_MONITOR_ORDER]; /* z and v, at el.ring's positions */
    pdt_real_t v_ring[PDT_MONITOR_ORDER];
} pdt_monitor_t;

/* Fills cfg with the documented defaults. Does nothing for NULL. */
void pdt_monitor_config_default(pdt_monitor_config_t *cfg);

/* Checks cfg and starts an empty monitor in *mon (caller-owned).
 * Returns PDT_ERR_ARG (NULL, a field outside its documented domain, an
 * invalid model), PDT_ERR_LENGTH (the model's dead time is
 * PDT_MONITOR_ORDER - 1 samples of Ts * decimation or more: raise the
 * decimation), PDT_ERR_UNSTABLE (no stable SIMC PI loop on the model);
 * *mon untouched then. Work: O(PDT_MONITOR_ORDER) plus one pdt_tune_compute. */
pdt_status_t pdt_monitor_init(pdt_monitor_t *mon, const pdt_monitor_config_t *cfg);

/* One scan: the set-point, the process value and the output the controller
 * applies (all sampled now). Returns PDT_ERR_ARG (NULL), PDT_ERR_STATE (not
 * initialised), PDT_ERR_NONFINITE (a value NaN or infinite; nothing
 * changed). Work: O(1), or O(PDT_MONITOR_ORDER) on the scan that completes
 * a sample (every `decimation`-th). */
pdt_status_t pdt_monitor_scan(pdt_monitor_t *mon, pdt_real_t sp, pdt_real_t pv, pdt_real_t u);

/* n scans from arrays (a logged block, oldest first): pdt_monitor_scan on
 * each. The same errors; on PDT_ERR_NONFINITE the scans before the bad one
 * are taken and *done (unless NULL) says how many were. */
pdt_status_t pdt_monitor_scan_block(pdt_monitor_t *mon, const pdt_real_t *sp, const pdt_real_t *pv,
                                    const pdt_real_t *u, size_t n, size_t *done);

/* The verdict and the figures now, into *out. The monitor is not changed
 * (call as often as wanted). Returns PDT_ERR_ARG (NULL), PDT_ERR_STATE (not
 * initialised); *out untouched then. Work: O(PDT_MONITOR_ORDER^2). */
pdt_status_t pdt_monitor_result(const pdt_monitor_t *mon, pdt_monitor_result_t *out);

/* "ok", "oscillating", "sluggish", "model_changed", "saturated",
 * "not_enough_data"; "?" for another value. */
const char *pdt_monitor_verdict_str(pdt_monitor_verdict_t v);
/* "none", "tuning", "stiction"; "?" for another value. */
const char *pdt_monitor_cause_str(pdt_monitor_cause_t c);

#ifdef __cplusplus
}
#endif

#endif /* PDT_MONITOR_H */
