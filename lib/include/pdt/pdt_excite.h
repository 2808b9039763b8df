/*
 * pdtfit excitation generators: the input signals of an identification
 * experiment on a live process, one sample per call, in fixed memory.
 *
 * Kinds (equations and polynomial table in docs/experiments.md):
 *  - STEP:  u0 until the excitation starts, then u0 + amplitude.
 *  - PULSE: count pulses of u0 + amplitude for t_on seconds, each followed
 *           by u0 for t_off seconds.
 *  - CHIRP: u0 + amplitude sin(phi(t)), a linear sweep from f0 to f1 Hz over
 *           duration seconds, phi(t) = 2 pi (f0 t + (f1 - f0) t^2 / (2 T)),
 *           so the instantaneous frequency is f0 + (f1 - f0) t / T.
 *  - PRBS:  u0 +/- amplitude from a maximum-length linear feedback shift
 *           register of prbs_bits (2 .. 31) bits, each chip held prbs_hold
 *           samples; one period is 2^prbs_bits - 1 chips.
 *  - RELAY: closed loop. The output switches between u0 + bias + d and
 *           u0 + bias - d on the control error with a hysteresis band eps;
 *           the generator measures the oscillation it causes and gives the
 *           ultimate gain Ku = 4 d / (pi a) and period Pu.
 *
 * Time: sample k (0, 1, 2, ...) is the k-th call of pdt_excite_next, at
 * t = k Ts. Every kind first holds u0 for `pre` seconds; the excitation's
 * own time t starts after that. Times in seconds are rounded to the nearest
 * whole sample.
 *
 * Output limits: every level the excitation asks for (u0 itself, and the
 * levels listed on each kind) must lie in [u_min, u_max], or init refuses
 * with PDT_ERR_OUTPUT_LIMIT. With `clamp` set, levels beyond the limits are
 * accepted and the output is clamped to [u_min, u_max] sample by sample
 * instead; init still refuses when u0 is outside the limits or when the
 * clamped excitation would not move the output at all.
 *
 * End: once an excitation's length has passed (kinds with a length), or a
 * relay has measured its cycles, pdt_excite_next returns PDT_OK and outputs
 * u0 from then on.
 */
#ifndef PDT_EXCITE_H
#define PDT_EXCITE_H

#include "pdt/pdt_common.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum pdt_excite_kind {
    PDT_EXCITE_STEP = 1,
    PDT_EXCITE_PULSE = 2,
    PDT_EXCITE_CHIRP = 3,
    PDT_EXCITE_PRBS = 4,
    PDT_EXCITE_RELAY = 5
} pdt_excite_kind_t;

/* Which way the relay acts (ISA convention). */
typedef enum pdt_excite_action {
    /* Output high while the process value is below the set-point: for a
     * process whose gain is positive (heating with a heater). */
    PDT_EXCITE_REVERSE = 0,
    /* Output high while the process value is above the set-point: for a
     * process whose gain is negative (cooling with a chiller). */
    PDT_EXCITE_DIRECT = 1
} pdt_excite_action_t;

/* Longest excitation, in samples (the counters are 32 bits). */
#define PDT_EXCITE_MAX_SAMPLES 4000000000u

/* Most relay cycles averaged (size of the generator's cycle memory). */
#define PDT_EXCITE_RELAY_MAX_CYCLES 8u

typedef struct pdt_excite_config {
    pdt_excite_kind_t kind; /* Default: the kind given to the default filler */
    pdt_real_t Ts;          /* sampling period (time between two calls), s,
                             * finite and > 0. Default 0 (must be set) */
    pdt_real_t u0;          /* operating point, output units. Default 0 */
    pdt_real_t u_min;       /* output limits, output units, finite. Default */
    pdt_real_t u_max;       /* -/+ the largest finite real (none): set them
                             * to the actuator's range */
    bool clamp;             /* clamp levels beyond the limits instead of
                             * refusing them. Default false */
    pdt_real_t pre;         /* time at u0 before the excitation, s, >= 0.
                             * Default 0 */
    pdt_real_t amplitude;   /* STEP, PULSE: the change, either sign, != 0;
                             * CHIRP, PRBS: the half swing, > 0. Output
                             * units. Default 1 */
    pdt_real_t duration;    /* STEP: time at u0 + amplitude, s, 0 = no end;
                             * CHIRP: sweep time T, s, at least one sample.
                             * Default 0 */
    /* PULSE */
    pdt_real_t t_on;  /* pulse width, s, at least one sample. Default 1 */
    pdt_real_t t_off; /* time at u0 after each pulse, s, >= 0. Default 1 */
    uint32_t count;   /* pulses, 0 = no end. Default 1 */
    /* CHIRP */
    pdt_real_t f0; /* start frequency, Hz, 0 .. 1 / (2 Ts). Default 0 */
    pdt_real_t f1; /* end frequency, Hz, 0 .. 1 / (2 Ts). Default 0
                             * (must be set above f0 for a sweep) */
    /* PRBS */
    uint32_t prbs_bits; /* register length n, 2 .. 31. Default 7 */
    uint32_t prbs_hold; /* samples per chip, >= 1. Default 1 */
    uint32_t prbs_seed; /* initial register, low n bits, not all zero.
                             * Default 1 */
    uint32_t periods;   /* PRBS periods of 2^n - 1 chips, 0 = no end.
                             * Default 1 */
    /* RELAY */
    pdt_real_t setpoint;        /* process value the relay switches around, pv
                             * units, finite. Default 0 */
    pdt_real_t d;               /* relay half swing, output units, > 0. Default 1 */
    pdt_real_t bias;            /* added to both relay levels, output units.
                             * Default 0 */
    pdt_real_t eps;             /* hysteresis: switch when the error passes
                             * +/- eps, pv units, >= 0. Default 0 (set it
                             * above the noise band of pv) */
    pdt_excite_action_t action; /* Default REVERSE */
    uint32_t relay_skip;        /* first complete cycles not measured (the
                             * transient). Default 0: relay_settle tells a
                             * settled cycle from the transient instead */
    uint32_t relay_cycles;      /* cycles averaged; the relay ends after
                             * relay_skip + relay_cycles complete cycles,
                             * 1 .. PDT_EXCITE_RELAY_MAX_CYCLES. Default 3 */
    pdt_real_t relay_settle;    /* the relay ends early at the first measured
                              * cycle that is symmetric, as the limit cycle
                              * of a relay without bias is: its high and low
                              * halves differ by at most this fraction of
                              * its length, and its peaks lie this
                              * fraction of the peak-to-peak or closer to
                              * symmetric about the set-point; it alone is
                              * then the measurement. In [0, 1); 0: always
                              * relay_skip + relay_cycles cycles. Default
                              * 0.1 (docs/reports/autotune-benchmark.md: median
                              * 2.8 T against 7.3 T for 1 + 3 cycles, the
                              * same median accuracy) */
} pdt_excite_config_t;

/* What a relay has measured (pdt_excite_relay_result). */
typedef struct pdt_excite_relay {
    pdt_real_t Ku;   /* 4 d / (pi a): the describing-function ultimate
                        * gain, output units per pv unit */
    pdt_real_t Pu;   /* mean cycle time, s */
    pdt_real_t a;    /* mean half peak-to-peak of pv per cycle, pv units */
    pdt_real_t d;    /* half swing the relay actually applied (after
                        * clamping), output units */
    uint32_t cycles; /* cycles averaged */
} pdt_excite_relay_t;

/* The generator. Fields are private; fill it with pdt_excite_init. */
typedef struct pdt_excite {
    pdt_excite_config_t cfg; /* copy of the config */
    uint32_t magic;          /* set by init */
    bool done;               /* the excitation has ended */
    uint32_t k;              /* samples produced (saturates) */
    uint32_t n_pre;          /* samples at u0 first */
    uint32_t n_total;        /* whole length in samples, 0 = no end */
    uint32_t n_on;           /* PULSE: samples on, off */
    uint32_t n_off;
    uint32_t pos;  /* PULSE: sample within the pulse period;
                               * PRBS: sample within the chip */
    pdt_real_t hi; /* clamped output levels: u0 + amplitude (STEP, */
    pdt_real_t lo; /* PULSE: lo = u0), u0 +/- amplitude, relay */
    pdt_real_t c1; /* CHIRP: phase in cycles is j (c1 + c2 j) */
    pdt_real_t c2;
    uint32_t lfsr; /* PRBS register: bit i is the (i+1)-th next chip */
    uint32_t taps; /* PRBS feedback mask */
    /* RELAY */
    bool started;        /* the first pv has been seen */
    bool high;           /* the output is at the high level */
    bool rose;           /* a low-to-high switch has been seen */
    uint32_t since_rise; /* samples since the last low-to-high switch */
    uint32_t fall_at;    /* since_rise at the high-to-low switch */
    uint32_t seen;       /* complete cycles seen */
    uint32_t stored;     /* cycles measured after the skipped ones */
    pdt_real_t pv_max;   /* pv extremes over the current cycle */
    pdt_real_t pv_min;
    uint32_t per[PDT_EXCITE_RELAY_MAX_CYCLES];   /* cycle lengths, samples */
    pdt_real_t amp[PDT_EXCITE_RELAY_MAX_CYCLES]; /* half peak-to-peak */
} pdt_excite_t;

/* Fills cfg with the documented defaults for `kind` (Ts left 0: the caller
 * sets it). Does nothing for NULL. An unknown kind is stored as given and
 * refused by pdt_excite_init. */
void pdt_excite_config_default(pdt_excite_config_t *cfg, pdt_excite_kind_t kind);

/* Checks cfg and prepares gen (caller-owned; the config is copied). The
 * fields that do not belong to cfg->kind are not checked.
 * Returns:
 *  PDT_ERR_ARG          NULL gen or cfg; unknown kind or action; Ts not
 *                       finite and > 0; u0, u_min, u_max, pre, amplitude,
 *                       duration, t_on, t_off, f0, f1, setpoint, d, bias or
 *                       eps not finite; pre, t_off, duration (STEP) or eps
 *                       negative; amplitude 0 (STEP, PULSE) or <= 0 (CHIRP,
 *                       PRBS); d <= 0; t_on or the CHIRP duration shorter
 *                       than half a sample; f0 or f1 outside 0 .. 1/(2 Ts);
 *                       prbs_bits outside 2 .. 31; prbs_hold 0; a seed
 *                       whose low prbs_bits bits are all 0; relay_cycles
 *                       outside 1 .. PDT_EXCITE_RELAY_MAX_CYCLES;
 *  PDT_ERR_BOUNDS       u_min > u_max;
 *  PDT_ERR_LENGTH       a time or the whole length beyond
 *                       PDT_EXCITE_MAX_SAMPLES samples;
 *  PDT_ERR_OUTPUT_LIMIT u0 outside [u_min, u_max]; without clamp, a level
 *                       outside them; with clamp, clamped levels that do
 *                       not differ (no excitation left).
 * Checked in that order; gen is untouched on error. O(1). */
pdt_status_t pdt_excite_init(pdt_excite_t *gen, const pdt_excite_config_t *cfg);

/* The output for the next sample, in output units, into *u: apply it until
 * the next call. pv is the process value at this sample (pv units): read by
 * RELAY only, ignored (any value, NaN too) by the open-loop kinds.
 * Returns:
 *  PDT_RUNNING        the excitation goes on;
 *  PDT_OK             it has ended (length passed, or relay cycles
 *                     measured); *u = u0, on this and every later call;
 *  PDT_ERR_ARG        NULL gen or u;
 *  PDT_ERR_STATE      gen was never initialised;
 *  PDT_ERR_NONFINITE  RELAY: pv is NaN or infinite (the sample is not
 *                     counted: apply u0, or stop).
 * *u and gen are untouched on error. O(1); PRBS O(prbs_bits) once per chip. */
pdt_status_t pdt_excite_next(pdt_excite_t *gen, pdt_real_t pv, pdt_real_t *u);

/* Whole length in samples, pre included: the number of calls that return
 * PDT_RUNNING. 0 when the kind has no fixed length (STEP with duration 0,
 * PULSE with count 0, PRBS with periods 0, RELAY) or gen is NULL or not
 * initialised. */
uint32_t pdt_excite_length(const pdt_excite_t *gen);

/* The relay's measurement, averaged over the cycles measured so far after
 * the relay_skip first ones (relay_cycles of them once the relay has
 * ended); may be asked while the relay runs.
 * A cycle runs from one low-to-high switch to the next: its length is Pu,
 * and half the difference between the largest and smallest pv seen in it
 * is a. Ku = 4 d / (pi a) is the describing function of the relay (with
 * hysteresis, the point of G(jw) it measures has phase
 * -pi + asin(eps / a) rather than -pi; keep eps small against a).
 * (a > 0 always: a cycle holds a sample below setpoint - eps and one above
 * setpoint + eps.)
 * Returns PDT_ERR_ARG (NULL, or gen is not a relay), PDT_ERR_STATE (not
 * initialised, or no cycle measured yet); *out untouched then.
 * O(relay_cycles). */
pdt_status_t pdt_excite_relay_result(const pdt_excite_t *gen, pdt_excite_relay_t *out);

#ifdef __cplusplus
}
#endif

#endif /* PDT_EXCITE_H */
