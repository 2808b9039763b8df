/*
 * pdtfit experiment recorder: stores the input u and the process value y of
 * an identification experiment into caller arrays at the identification
 * rate, finds the operating point before the excitation starts, and stops
 * the experiment safely when a limit is broken.
 *
 * Scans and samples. The application calls pdt_record_push once per scan
 * (its control cycle) with the output it applied and the process value it
 * read. Every `decimation` scans make one identification sample:
 *   u[j] = the mean of the outputs pushed in the decimation scans of the
 *          interval: the held value when the output does not change in
 *          the interval, and the right area when it does (a relay
 *          switching, a hold that is not a multiple of the decimation);
 *   y[j] = the mean of the process values of the same scans (a boxcar
 *          anti-alias filter).
 * The process value's mean is centred (decimation - 1) / 2 scans after the
 * interval's start, so a model identified from the record shows a dead time
 * shorter by that much than the process's (pdt_autotune adds it back).
 *
 * Phases.
 *  1. Settle: the application holds its output at the operating point. The
 *     first `settle` samples are the settle window; u0 and y0 are the means
 *     of u[] and y[] over it. With settle_band > 0, the process value must
 *     be steady: whenever the samples of the window so far spread (largest
 *     minus smallest y) by more than settle_band, the window restarts at
 *     the newest sample, which becomes sample 0 of the record. When the
 *     window is complete the recorder is "settled" (pdt_record_result) and
 *     the set-point check below is made once.
 *  2. Excitation: the application applies its excitation and goes on
 *     pushing; the record is complete (PDT_OK) when `capacity` samples are
 *     stored, or when the application calls pdt_record_stop.
 *
 * Safety. Each scan is checked, in this order, before it is used; the first
 * failure aborts the experiment for good:
 *   PDT_ERR_TIMEOUT      the scan comes after max_scans scans were accepted;
 *   PDT_ERR_NONFINITE    u or pv is NaN or infinite (a failed sensor or a
 *                        broken computation);
 *   PDT_ERR_OUTPUT_LIMIT u outside [u_min, u_max];
 *   PDT_ERR_PV_LIMIT     pv outside [pv_min, pv_max];
 * and, once, at the end of the settle window:
 *   PDT_ERR_SETPOINT     move = UP and setpoint <= y0, or move = DOWN and
 *                        setpoint >= y0: the experiment is meant to take the
 *                        process value toward (a relay test: across) the
 *                        set-point, which lies on the other side.
 * On abort the aborting scan is not recorded, the samples already stored
 * stay in u[] and y[] (a partly averaged interval is dropped), and the
 * result's u_safe is the output to apply: the operating point u0 (see
 * pdt_record_result_t).
 */
#ifndef PDT_RECORD_H
#define PDT_RECORD_H

#include "pdt/pdt_common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The direction the experiment must move the process value. */
typedef enum pdt_record_move {
    PDT_RECORD_MOVE_ANY = 0, /* no set-point check */
    PDT_RECORD_MOVE_UP = 1,  /* the set-point must lie above y0 */
    PDT_RECORD_MOVE_DOWN = 2 /* the set-point must lie below y0 */
} pdt_record_move_t;

typedef struct pdt_record_config {
    uint32_t decimation;    /* scans per identification sample, >= 1.
                             * Default 1 */
    uint32_t settle;        /* samples in the settle window, >= 1 and below
                             * the capacity. Default 10 */
    pdt_real_t settle_band; /* largest pv spread over the settle window, pv
                             * units, >= 0; 0: not checked. Default 0 */
    pdt_real_t u_min;       /* output limits, output units, finite. Default */
    pdt_real_t u_max;       /* -/+ the largest finite real (none) */
    pdt_real_t pv_min;      /* process value limits, pv units, finite.
                             * Default -/+ the largest finite real (none): */
    pdt_real_t pv_max;      /* set them to what the process may safely see */
    uint32_t max_scans;     /* scans accepted before PDT_ERR_TIMEOUT; 0: no
                             * limit. Default 0 */
    pdt_record_move_t move; /* set-point check. Default ANY */
    pdt_real_t setpoint;    /* pv units, finite when move is not ANY.
                             * Default 0 */
} pdt_record_config_t;

/* The state of the experiment (pdt_record_result). */
typedef struct pdt_record_result {
    pdt_status_t status; /* PDT_RUNNING, PDT_OK (complete), or the error
                           * that aborted it */
    size_t n;            /* samples stored in u[0..n-1], y[0..n-1] */
    bool settled;        /* the settle window is complete */
    pdt_real_t u0;       /* operating point: means of u and y over the */
    pdt_real_t y0;       /* settle window (so far, before settled) */
    pdt_real_t u_safe;   /* the output to apply after an abort or the end:
                           * u0; before any sample is complete, the output
                           * of the first scan accepted; if no scan was
                           * accepted, the aborting scan's output limited to
                           * [u_min, u_max] (u_min if it was not a number) */
    uint32_t scans;      /* scans accepted */
} pdt_record_result_t;

/* The recorder. Fields are private; fill it with pdt_record_init. */
typedef struct pdt_record {
    pdt_record_config_t cfg;
    pdt_real_t *u; /* caller arrays of capacity samples */
    pdt_real_t *y;
    size_t capacity;
    uint32_t magic;
    pdt_status_t status;
    size_t n; /* samples stored */
    bool settled;
    uint32_t scans;      /* scans accepted */
    uint32_t pend;       /* scans in the open interval */
    pdt_real_t pend_u;   /* mean of its outputs so far */
    pdt_real_t pend_sum; /* sum of its process values */
    pdt_real_t win_min;  /* y extremes of the settle window */
    pdt_real_t win_max;
    pdt_real_t sum_y; /* sum of y over the settle window */
    pdt_real_t u0;
    pdt_real_t y0;
    pdt_real_t u_safe;
} pdt_record_t;

/* Fills cfg with the documented defaults. Nothing for NULL. */
void pdt_record_config_default(pdt_record_config_t *cfg);

/* Prepares rec (caller-owned) to record into u[0..capacity-1] and
 * y[0..capacity-1] (caller arrays, kept by pointer, written only by
 * pdt_record_push; they must not overlap). The config is copied.
 * Returns:
 *  PDT_ERR_ARG       NULL rec, cfg, u or y; u and y overlap; decimation or
 *                    settle 0; a limit or settle_band not finite, or
 *                    settle_band negative; unknown move; setpoint not
 *                    finite with move other than ANY;
 *  PDT_ERR_BOUNDS    u_min > u_max or pv_min > pv_max;
 *  PDT_ERR_LENGTH    capacity > PDT_MAX_SAMPLES (pdt_config.h, 2^20 by
 *                    default);
 *  PDT_ERR_TOO_SHORT capacity <= settle (no room for the excitation).
 * Checked in that order; rec is untouched on error. O(1). */
pdt_status_t pdt_record_init(pdt_record_t *rec, const pdt_record_config_t *cfg, pdt_real_t *u,
                             pdt_real_t *y, size_t capacity);

/* One scan: u_applied is the output applied during this scan (output
 * units), pv the process value read in it (pv units). Checks the scan (see
 * Safety above), adds it to the open interval, and stores a sample when the
 * interval is complete.
 * Returns:
 *  PDT_RUNNING   recording goes on;
 *  PDT_OK        the record is complete (full, or stopped): nothing is
 *                recorded from now on, and every later push returns PDT_OK;
 *  PDT_ERR_ARG   NULL rec; PDT_ERR_STATE rec was never initialised (both
 *                leave rec untouched);
 *  PDT_ERR_TIMEOUT, PDT_ERR_NONFINITE, PDT_ERR_OUTPUT_LIMIT,
 *  PDT_ERR_PV_LIMIT, PDT_ERR_SETPOINT: the experiment is aborted (see
 *                Safety): apply the result's u_safe. Every later push
 *                returns the same error and records nothing.
 * O(1). */
pdt_status_t pdt_record_push(pdt_record_t *rec, pdt_real_t u_applied, pdt_real_t pv);

/* Ends the experiment before the record is full (e.g. the excitation is
 * over): a partly averaged interval is dropped, later pushes return PDT_OK.
 * Returns PDT_OK, or the abort error if it was already aborted (nothing
 * changes then), PDT_ERR_ARG for NULL, PDT_ERR_STATE if not initialised or
 * not yet settled (the record would have no operating point). O(1). */
pdt_status_t pdt_record_stop(pdt_record_t *rec);

/* The state of the experiment into *out. Returns PDT_ERR_ARG for NULL,
 * PDT_ERR_STATE if rec was never initialised (*out untouched). O(1). */
pdt_status_t pdt_record_result(const pdt_record_t *rec, pdt_record_result_t *out);

#ifdef __cplusplus
}
#endif

#endif /* PDT_RECORD_H */
