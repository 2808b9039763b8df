/*
 * pdtfit identification: a FOPDT or SOPDT model from one measured record,
 * found by a real-coded genetic algorithm (Yang and Seested 2013, section 3)
 * followed by a local Nelder-Mead refinement, in fixed memory, in steps of
 * bounded work so that a PLC or MCU task can spread it over scan cycles.
 *
 * The search. The dead time makes the cost non-convex, so a global search
 * runs over the model's shape: for a FOPDT the genes are log(tau) and
 * log(Td + c0), for a SOPDT log(1/a), 1/zeta and log(Td + c0) (form (2)
 * with b = (a / (2 zeta))^2, which covers overdamped, critically damped,
 * underdamped and, at 1/zeta = 0, the integrating process; c0 is a
 * sixteenth of the dead-time range, so the gene is linear near 0). The gain and the output offset are not
 * searched: for a given shape the cost is quadratic in them, so each
 * evaluation solves for them in closed form and writes the gain back into
 * the individual (see pdt_cost_profile). Selection is a binary tournament
 * on shared costs (fitness sharing keeps several dead-time niches alive),
 * variation is bounded SBX and polynomial mutation, the best individuals
 * survive each generation, and the random numbers come from the library's
 * own PCG32 seeded by the caller: the same seed, data and build give the
 * same result.
 *
 * Certainty. With a time criterion, up to three independent searches
 * (each its own random stream) run one after the other; the answer is the
 * best one, confirmed when another search ended in its basin, and the
 * result's flags say what could not be settled (docs/ident-engine.md).
 *
 * Data as it comes from plants: u and y in engineering units around an
 * operating point. The record should start at steady state (initial AUTO
 * tests it and, where it does not, estimates the state at the first
 * sample); the input operating point is u[0] (or u_before), the output
 * operating point is estimated with the model (never from a few noisy
 * samples).
 */
#ifndef PDT_IDENT_H
#define PDT_IDENT_H

#include "pdt/pdt_common.h"
#include "pdt/pdt_cost.h"
#include "pdt/pdt_model.h"
#include "pdt/private/pdt_ident_state.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Most individuals a population may have (sizes the context's fixed
 * arrays only through the workspace; this bounds the O(P^2) sharing work). */
#define PDT_IDENT_MAX_POPULATION 256u

/* The samples the automatic decimation aims the coarse record at. */
#define PDT_IDENT_COARSE_SAMPLES 128u

/* The automatic population (population = 0) of each model. */
#define PDT_IDENT_POPULATION_FOPDT 24u
#define PDT_IDENT_POPULATION_SOPDT 40u

/* Frequency weighting of FREQUENCY and COMBINED in the identification: the
 * cost's own three (pdt_weight_kind_t), and two the identification
 * resolves itself. docs/equations.md and docs/reports/benchmarks.md give the why. */
typedef enum pdt_ident_weight {
    PDT_IDENT_WEIGHT_UNIFORM = 0, /* every bin alike (the paper's W = 1) */
    PDT_IDENT_WEIGHT_BAND = 1,    /* the bins in [f_lo, f_hi], Hz */
    PDT_IDENT_WEIGHT_CUSTOM = 2,  /* weights[k], k = 0 .. N_f / 2 */
    PDT_IDENT_WEIGHT_CONTROL = 3, /* a band up to half the phase crossover
                                   * of the model the time cost finds */
    PDT_IDENT_WEIGHT_AUTO = 4     /* CONTROL for a FOPDT with COMBINED,
                                   * else UNIFORM */
} pdt_ident_weight_t;

/* The output operating point y0 of the answer. */
typedef enum pdt_ident_offset {
    PDT_IDENT_OFFSET_AUTO = 0,     /* ESTIMATE, then, for a time criterion on
                                    * a record that starts with a rest window
                                    * (the input still, plus Td_min) of at
                                    * least n / 40 samples and
                                    * PDT_MIN_SAMPLES over which the output is
                                    * flat, REST when the fitted offset lies
                                    * more than 4.5 standard errors from
                                    * the window's level: the answer is then
                                    * polished on that level */
    PDT_IDENT_OFFSET_ESTIMATE = 1, /* fitted with the model */
    PDT_IDENT_OFFSET_REST = 2      /* the output's mean over the rest window */
} pdt_ident_offset_t;

/* The plant's state at the record's start. */
typedef enum pdt_ident_initial {
    PDT_IDENT_INITIAL_AUTO = 0,    /* at rest, tested: an answer whose
                                    * residual keeps a decay from the first
                                    * sample is identified again with
                                    * ESTIMATE (SIMULATION criterion; other
                                    * criteria keep the flag), and gets
                                    * PDT_IDENT_FLAG_MID_TRANSIENT only where
                                    * that answer's residual still keeps
                                    * one */
    PDT_IDENT_INITIAL_REST = 1,    /* at rest, not tested */
    PDT_IDENT_INITIAL_ESTIMATE = 2 /* the model's state at the first sample
                                    * estimated: its free response fitted in
                                    * closed form with the gain and the
                                    * offset, one sequence for a FOPDT, two
                                    * for a SOPDT (docs/field-data.md).
                                    * SIMULATION criterion only */
} pdt_ident_initial_t;

/* Most records one identification fits together, the first
 * (pdt_ident_data_t) and up to PDT_IDENT_MAX_RECORDS - 1 more
 * (pdt_ident_config_t.more): a build setting of pdt_config.h. */

/* A further record of the same process (docs/several-records.md): n
 * samples of u and y every Ts seconds, in the caller's memory, unchanged
 * while the identification runs. Its input operating point is u_before
 * when given, else u[0]; its output offset (and, with initial ESTIMATE,
 * its state at the first sample, with drift its drift) is its own; the
 * dynamics are those of the other records. */
typedef struct pdt_ident_record {
    const pdt_real_t *u;
    const pdt_real_t *y;
    size_t n;
    pdt_real_t Ts;       /* s, finite and > 0 */
    bool u_before_given; /* as pdt_ident_config_t's, for this record */
    pdt_real_t u_before;
} pdt_ident_record_t;

typedef struct pdt_ident_config {
    pdt_model_kind_t model;    /* FOPDT or SOPDT. Default FOPDT */
    pdt_real_t Ts;             /* sampling period, s. Must be set (> 0) */
    pdt_cost_kind_t cost;      /* criterion. Default SIMULATION: the output
                               * error, unbiased under measurement noise */
    pdt_cost_kind_t time_kind; /* time part of COMBINED. Default SIMULATION */
    pdt_real_t phi_t;          /* COMBINED weights, >= 0. Default 1, 1 */
    pdt_real_t phi_f;
    pdt_ident_weight_t weight; /* Default AUTO */
    pdt_real_t f_lo;
    pdt_real_t f_hi;
    const pdt_real_t *weights;
    pdt_ident_offset_t offset;   /* Default AUTO */
    pdt_delay_mode_t delay_mode; /* FRACTIONAL: Td continuous (default);
                                  * INTEGER: Td in whole samples, the paper */
    /* Search bounds. A pair left at 0, 0 is derived from Ts and the record
     * length T = n Ts: time constants in [Ts / 4, 2 T], dead time in
     * [0, T / 3]. */
    pdt_real_t tau_min;  /* s: FOPDT tau; SOPDT 1/a = T1 T2 / (T1 + T2)
                               * from tau_min / 2 */
    pdt_real_t tau_max;  /* s */
    pdt_real_t Td_min;   /* s; Td_min = Td_max > 0 fixes the dead time. The
                          * result's Td lies within them to rounding */
    pdt_real_t Td_max;   /* s */
    pdt_real_t zeta_min; /* SOPDT: least damping searched. Default 0.2 */
    bool integrating;    /* SOPDT: allow b = 0 (1/zeta down to 0).
                               * Default true */
    /* Gain bounds (output units per input unit; SOPDT: the DC gain, or the
     * integrating gain when b = 0). 0, 0 means unbounded. */
    pdt_real_t K_min;
    pdt_real_t K_max;
    /* The search. */
    uint32_t population;         /* individuals, 4 .. PDT_IDENT_MAX_POPULATION,
                               * even; 0: PDT_IDENT_POPULATION_FOPDT or
                               * _SOPDT by the model. Default 0 */
    uint32_t max_evaluations;    /* cost evaluations in all, every search
                               * included; each of the screen's rounds
                               * (at most PDT_IDENT_SCREEN_ROUNDS more, only
                               * where it leaves samples out) has as many
                               * again. Default 9000 */
    uint32_t searches;           /* independent searches that must agree, 1 .. 3
                               * (time criteria; the frequency criteria run
                               * one): each gets max_evaluations / searches,
                               * the third runs only when the first two
                               * disagree. 0: as many as the budget allows,
                               * up to 3 (the default) */
    uint32_t refine_evaluations; /* of those, kept for the refinement, at
                                  * least genes + 1. Default 300: up to
                                  * three niches' runs share half of what
                                  * is left after the GA, a polish of the
                                  * best gets the rest */
    pdt_real_t tolerance;        /* stop the GA when the best cost improved by
                               * less than this fraction over stall_generations.
                               * Default 1e-4. The GA also stops once its
                               * population has one niche left (all but an
                               * eighth within sigma_share of its best,
                               * twice that for a FOPDT under the output
                               * error) for three generations */
    uint32_t stall_generations;  /* Default 10. A FOPDT search after the
                               * first also stops its GA once, after this
                               * many generations, its best lies in the
                               * best answer's basin */
    uint64_t seed;               /* PCG32 seed. Default 1 */
    pdt_real_t eta_c;            /* SBX distribution index. Default 15 */
    pdt_real_t eta_m;            /* mutation distribution index. Default 20 */
    pdt_real_t p_crossover;      /* per pair. Default 0.9 */
    pdt_real_t p_mutation;       /* per gene; 0 means 1 / genes. Default 0 */
    pdt_real_t sigma_share;      /* niche radius, normalised distance. Default 0.1 */
    uint32_t elite;              /* best individuals kept each generation. Default 2 */
    uint32_t coarse;             /* SIMULATION with FRACTIONAL dead times:
                               * the searches run on a record D times
                               * coarser (blocks of D samples), then the
                               * answer is polished on the whole record
                               * (docs/ident-engine.md). 1: the whole
                               * record throughout. 0: automatic, about
                               * PDT_IDENT_COARSE_SAMPLES samples, coarser
                               * only where the output keeps its shape.
                               * Either way the whole record is searched
                               * again when the answer is too fast for the
                               * coarse record. Default 0 */
    /* Gross errors and missing samples (docs/field-data.md, "Gross
     * errors"). A y sample that is not finite (NaN, infinity: a logger's
     * empty cell or bad-value marker) is a missing sample: left out of the
     * fit, counted in pdt_ident_result_t.excluded and .missing. After the
     * answer, the screen leaves out the samples its residual cannot
     * explain and the identification runs again without them. */
    bool refuse_missing;   /* true: a non-finite y is refused
                            * (PDT_ERR_NONFINITE), as a non-finite u
                            * always is. Default false */
    bool no_screen;        /* true: no screen for gross errors (missing
                            * samples are still left out). With
                            * refuse_missing too, the workspace has no
                            * copy of y: n + n / 16 reals less, for parts
                            * short of RAM. Default false */
    uint32_t max_excluded; /* most samples left out, missing ones and
                            * gross errors together; more is refused with
                            * PDT_ERR_OUTLIER. 0: n / 20, at least
                            * 2 PDT_IDENT_RUN_MAX. Default 0 */
    /* The input before the first sample, for a record that begins at
     * the step (a heater switched on at the first row): the plant is
     * taken at rest at u_before, and the result's u0 is it. Without it
     * (u_before_given false) the input before the record is u[0], and a
     * record whose u never moves is refused (PDT_ERR_NO_EXCITATION). */
    bool u_before_given;         /* Default false */
    pdt_ident_initial_t initial; /* Default AUTO */
    pdt_real_t u_before;         /* input units; finite when given */
    /* A linear drift of the output, d (t - t_mid) with t_mid the record's
     * middle, fitted in closed form with the gain and the offset, for
     * records whose output wanders slowly (docs/field-data.md). y0 is
     * then the operating point at the record's middle. SIMULATION
     * criterion only. Default false */
    bool drift;
    /* Further records of the same process, identified with the first as
     * one model (docs/several-records.md): more[0 .. more_count - 1],
     * more_count <= PDT_IDENT_MAX_RECORDS - 1, in the caller's memory for
     * the life of the identification. 0 (the default): one record. With
     * more records only the SIMULATION criterion, FRACTIONAL dead times,
     * coarse 0 or 1 (the searches run on the whole records), offset AUTO
     * or ESTIMATE (AUTO is ESTIMATE: no rest window), initial REST or
     * ESTIMATE and no_screen are accepted; anything else is PDT_ERR_ARG,
     * and a missing (non-finite) sample in any record is
     * PDT_ERR_NONFINITE. */
    const pdt_ident_record_t *more;
    uint32_t more_count;
} pdt_ident_config_t;

/* One record: n samples of input u and output y, every Ts seconds, in the
 * caller's memory, unchanged while the identification runs. */
typedef struct pdt_ident_data {
    const pdt_real_t *u;
    const pdt_real_t *y;
    size_t n;
} pdt_ident_data_t;

/* Most parameters of a model with its offset: SOPDT k, a, b, Td, y0. */
#define PDT_IDENT_MAX_PARAMS 5u

/* The screen for gross errors: the longest run of neighbouring bad
 * samples it takes for one error (a logger's dropout), the half width of
 * its running median (more than twice the run, so that the median of a
 * window over a whole run is a good sample), its rounds (identifications
 * after the first), and the indices a result lists. */
#define PDT_IDENT_RUN_MAX       10u
#define PDT_IDENT_SCREEN_HALF   15u
#define PDT_IDENT_SCREEN_ROUNDS 4u
#define PDT_IDENT_EXCLUDED_LIST 8u

/* Standard deviations and covariance of the identified parameters, in the
 * order FOPDT K, tau, Td, y0 (count 4) or SOPDT k, a, b, Td, y0 (count 5),
 * in the model's units; count 0 when they could not be computed. From the
 * output-error Fisher information at the estimate and the residual's
 * variance, inflated by 1 + 2 sum of the residual's autocorrelations (lags
 * 1..20) when it is correlated, as pdt_validate_model does. A parameter the
 * data do not determine (the Fisher information singular in its
 * direction, e.g. the second lag of a SOPDT fitted to a first-order
 * process) has std +infinity and covariance row and column 0: it is held
 * at its estimate and the others' covariance is conditional on it. A
 * Fisher information without a usable diagonal gives +infinity
 * everywhere. */
typedef struct pdt_ident_std {
    uint32_t count;
    pdt_real_t std[PDT_IDENT_MAX_PARAMS];
    pdt_real_t cov[PDT_IDENT_MAX_PARAMS][PDT_IDENT_MAX_PARAMS];
} pdt_ident_std_t;

typedef struct pdt_ident_result {
    pdt_model_t model;    /* the identified model, in engineering units */
    pdt_real_t u0;        /* input operating point: u[0], or the
                               * configuration's u_before */
    pdt_real_t y0;        /* output operating point, estimated */
    pdt_real_t cost;      /* the criterion's value at the model */
    pdt_real_t fit;       /* normalised RMS fit of the simulated output,
                               * percent: 100 (1 - |y - ysim| / |y - mean y|);
                               * 100 is perfect, 0 no better than a constant */
    uint32_t evaluations; /* cost evaluations used */
    uint32_t generations; /* GA generations run (with the CONTROL
                               * weighting, the population's scoring on the
                               * criterion counts as one) */
    pdt_real_t f_band;    /* CONTROL weighting: the band's upper edge,
                               * Hz; 0 when the criterion has no frequency
                               * part or another weighting */
    uint32_t flags;       /* PDT_IDENT_FLAG_*: what the search could not
                               * settle; 0 for an answer it is sure of */
    uint32_t searches;    /* independent searches run */
    pdt_real_t runner_up; /* cost of the best answer of another basin
                               * that a search ended in, over the answer's
                               * (> 1.01); 0 when every search agreed */
    pdt_ident_std_t std;  /* the parameters' uncertainty */
    uint32_t coarse;      /* the searches' record was D times coarser;
                               * 1: they searched the whole record */
    pdt_real_t evidence;  /* the likelihood-ratio statistic of the model
                           * against the null model (the output's mean):
                           * (n / c) ln(SS_null / SS_model), c the
                           * residual's autocorrelation inflation (as in
                           * std); 0 when it could not be computed */
    uint32_t excluded;    /* samples left out of the fit: missing ones and
                           * gross errors the screen found */
    uint32_t missing;     /* of them, the non-finite y samples */
    uint32_t excluded_first[PDT_IDENT_EXCLUDED_LIST]; /* the first
                           * min(excluded, PDT_IDENT_EXCLUDED_LIST)
                           * of them, 0-based, ascending; the rest 0 */
    pdt_ident_initial_t initial;                      /* REST: the model starts at rest;
                           * ESTIMATE: its state at the first sample was
                           * estimated (asked for, or AUTO's test failed) */
    pdt_real_t x0;                                    /* ESTIMATE: the free response at the first
                           * sample, output units: the output's deviation
                           * there from the model driven from rest plus
                           * y0. 0 otherwise */
    pdt_real_t dx0;                                   /* ESTIMATE, SOPDT: the free response's slope
                           * over the first sample, output units per
                           * second. 0 otherwise */
    pdt_real_t drift;                                 /* with drift: output units per second. 0
                           * otherwise */
} pdt_ident_result_t;

/* pdt_ident_result_t.flags. An answer with any flag set is the best the
 * search found, but firmware should not act on it unattended
 * (docs/ident-engine.md):
 *  UNCONFIRMED  no two independent searches ended in the answer's basin
 *               (same structure, cost within 1 %);
 *  AMBIGUOUS    a structurally different model (the other gain sign, an
 *               integrator for a lag or back) fits within 5 % of its cost;
 *  AT_BOUND     a parameter lies on an upper search bound (a time
 *               constant, the dead time, the least damping) or a gain
 *               bound: the optimum may lie outside;
 *  NO_RELATION  the model is not significantly better than the output's
 *               mean (evidence below PDT_IDENT_EVIDENCE_MIN), or its fit
 *               is below PDT_IDENT_FIT_FLOOR: the record shows no
 *               relation of y to u (docs/field-data.md);
 *  MID_TRANSIENT the record does not start at rest: the answer's residual
 *               keeps a decay from the first sample (initial AUTO), and
 *               the model bent to explain it (docs/field-data.md). */
#define PDT_IDENT_FLAG_UNCONFIRMED   0x1u
#define PDT_IDENT_FLAG_AMBIGUOUS     0x2u
#define PDT_IDENT_FLAG_AT_BOUND      0x4u
#define PDT_IDENT_FLAG_NO_RELATION   0x8u
#define PDT_IDENT_FLAG_MID_TRANSIENT 0x10u

/* NO_RELATION's bounds: the least evidence (pdt_ident_result_t.evidence;
 * about the 99.9 % quantile of chi-square with 3 degrees of freedom) and
 * the least fit, percent. */
#define PDT_IDENT_EVIDENCE_MIN 16.0
#define PDT_IDENT_FIT_FLOOR    5.0

/* Most independent searches: 3, one answer each beside the dead-time
 * profile's in the context. */
#define PDT_IDENT_MAX_SEARCHES (PDT_IDENT_VOTES - 1u)

/* The identification context. Its parts, one per stage of the engine
 * (docs/ident-engine.md), are defined in pdt/private/pdt_ident_state.h:
 * the caller allocates pdt_ident_t, so their sizes must be visible, but
 * everything in them is private. Read the answer with pdt_ident_result;
 * the layout may change in any release. */
typedef struct pdt_ident {
    pdt_ident_config_t cfg;
    pdt_ident_data_t data;
    pdt_cost_t cost;
    void *cost_work; /* the cost's part of the workspace */
    size_t cost_work_len;
    pdt_real_t *scratch; /* n reals of the workspace */
    uint32_t magic;      /* set by init: catches use before init */
    uint32_t phase;      /* the sequencer's stage */
    uint32_t genes;
    uint32_t evaluations;
    uint32_t generations;
    uint64_t samples; /* samples the evaluations scored: n each on the whole
                       * record, n / D on a coarse one; what the budget of
                       * pdt_ident_step counts */
    pdt_real_t lo[3]; /* gene bounds */
    pdt_real_t hi[3];
    pdt_real_t td_offset; /* c0 of the dead-time gene log(Td + c0), s */
    pdt_real_t f_band;    /* CONTROL weighting: the band's edge, Hz */
    uint32_t rest;        /* AUTO offset: the rest window's samples, 0 when
                           * the record has none to use */
    uint32_t resume;      /* the phase the running search or polish returns
                           * to: the sequencer's, from its plan */
    pdt_ident_best_t best;
    pdt_real_t start[3]; /* the next refinement's start (PH_REFINE_FROM) */
    pdt_ident_ga_t ga;
    pdt_ident_refine_t nm; /* with the polish's state */
    pdt_ident_scan_t scan;
    pdt_ident_vote_t vote;
    pdt_ident_profile_t profile;
    pdt_ident_coarse_t coarse;
    pdt_ident_screen_t screen;
    /* The answer, once done. */
    pdt_model_t model;
    pdt_real_t y0;
    pdt_real_t fit;
    uint32_t flags;
    pdt_real_t runner_up;
    pdt_ident_std_t std;
    pdt_real_t evidence;
    pdt_real_t extra[4];   /* the answer's x0, dx0, drift (result units) and
                          * the residual's sum of squares with them */
    bool auto_state;       /* AUTO's refit with the state estimated ran */
    pdt_cost_t *more_cost; /* the costs of cfg.more's records (workspace),
                            * NULL with one record */
} pdt_ident_t;

/* Fills cfg with the documented defaults (Ts left 0). Nothing for NULL. */
void pdt_ident_config_default(pdt_ident_config_t *cfg);

/* Workspace bytes pdt_ident_init needs for cfg and n samples (of the first
 * record; cfg->more's records are counted from cfg: each one's cost object
 * and normalised copy, and the scratch is the longest record's); 0 when
 * cfg is NULL or the configuration is unsupported (init then says why). */
size_t pdt_ident_workspace_size(const pdt_ident_config_t *cfg, size_t n);

/* Compile-time upper bound of the workspace for n samples and a population
 * of pop (PDT_IDENT_POPULATION_SOPDT covers both automatic populations),
 * any configuration of one record: for static arrays. */
#define PDT_IDENT_WORKSPACE_SIZE(n, pop)                                                           \
    (PDT_COST_WORKSPACE_SIZE(n) +                                                                  \
     (2u * (size_t)(n) + (size_t)(n) / 16u + 13u * (size_t)(pop) + 3u) * sizeof(pdt_real_t))

/* Prepares ctx for one identification: checks cfg and the data, derives the
 * bounds, prepares the cost (O(n), plus O(N_f log N_f) when the criterion
 * uses the frequency domain). Does no cost evaluation.
 * Returns PDT_ERR_ARG (NULL, bad config value, a frequency weighting that
 * selects no bin of the record, max_evaluations below the population (two
 * with the CONTROL weighting) plus the refinement and the late reserve),
 * PDT_ERR_BOUNDS (a lower bound above its upper bound, tau_min = tau_max, or
 * with PDT_DELAY_INTEGER dead-time bounds that hold no whole sample),
 * PDT_ERR_NONFINITE
 * (NaN or infinity in the data), PDT_ERR_TOO_SHORT (fewer samples than the dead-time bound and
 * PDT_MIN_SAMPLES need), PDT_ERR_NO_EXCITATION (u or y constant),
 * PDT_ERR_NOT_AT_REST (FREQUENCY or COMBINED on a record that does not end
 * at rest: over its last twentieth, at least 8 samples, the mean of u or
 * of y lies more than a fifth of its range from its starting level),
 * PDT_ERR_LENGTH (record too long for the FFT), PDT_ERR_NOMEM (work NULL or
 * too small); with several records (cfg->more) also PDT_ERR_ARG for a
 * setting they do not take and the statuses above for any record. ctx is
 * left untouched on error; so is work, except with several records (their
 * costs are prepared first) and for a
 * record with a missing sample or, without no_screen, a value
 * pdt_cost_outlier names: its screened copy of y is written into work before
 * the checks that can still refuse it. */
pdt_status_t pdt_ident_init(pdt_ident_t *ctx, const pdt_ident_config_t *cfg,
                            const pdt_ident_data_t *data, void *work, size_t work_len);

/* Advances the search by at most max_evaluations cost evaluations of the
 * whole record, or one group of PDT_VECTOR_LANES (pdt_config.h) when
 * asked for fewer (each O(n) time domain, O(N_f / 2) frequency domain;
 * with several records each evaluation scores every record, three passes
 * over each: O(n_1 + ... + n_R)).
 * The budget counts the samples scored: a search on a coarse record of
 * n / D samples makes D evaluations for one (each still has the fixed
 * part of discretising its model, a few hundred instructions). Or, in a
 * call of its own with no evaluation, one heavier step: a test of
 * whether the output keeps its shape at one factor of the coarse record
 * (O(n); the first calls, one for each factor tried, at most five:
 * 32, 16, 8, 4, 2), the beginning of the searches
 * (the coarse record and its cost, O(n), and the first population), a
 * breeding step
 * (O(P^2 genes) for the sharing), a preparation (of the spectra,
 * O(N_f log N_f) as in init: COMBINED re-centres them once before the
 * refinement, and the CONTROL weighting sets its band once; of the whole
 * record's cost after a coarse one's searches, O(n)), a block of the
 * answer's uncertainty (PDT_FISHER_BLOCK = 256 samples, O(1) per sample and
 * parameter; the whole pass in one call where the population is too small
 * to hold its state), its evidence (its simulated output and sums, O(n);
 * four lags of its autocorrelation factor, two passes over the record),
 * the tests of the initial state (AUTO; O(n)), or one of the screen's
 * steps (its residual, O(n); a block of 128 samples of its running
 * median, O(PDT_IDENT_SCREEN_HALF) a sample; at most four passes over
 * the record of its bound's median; the samples it leaves out, O(n); the
 * refill, O(n); the running median and the median whole in one call
 * where the population is too small to hold their state; a restart on
 * the filled record costs what init does). Returns PDT_RUNNING
 * while there is work left, PDT_OK when done (also on every later call),
 * PDT_ERR_ARG for NULL or
 * max_evaluations = 0, PDT_ERR_STATE if ctx was not initialised. Once the
 * screen has left samples out, the identification starts again on the
 * record without them: PDT_ERR_OUTLIER when more are to be left out than
 * max_excluded allows (pdt_ident_outlier names the first), or a status
 * pdt_ident_init gives a record that the rest no longer passes (e.g.
 * PDT_ERR_NO_EXCITATION); every later call and pdt_ident_result then
 * return it. */
pdt_status_t pdt_ident_step(pdt_ident_t *ctx, uint32_t max_evaluations);

/* The result once pdt_ident_step has returned PDT_OK. PDT_ERR_STATE before
 * that, PDT_ERR_ARG for NULL, PDT_ERR_NONFINITE when the model found does
 * not fit the real type (a gain beyond its range: the record's output is
 * too many decades above its input) or no model could be scored (gain
 * bounds that only allow fits whose cost lies beyond the real type). O(1):
 * the fit and the uncertainty were computed by the last step. */
pdt_status_t pdt_ident_result(const pdt_ident_t *ctx, pdt_ident_result_t *out);

/* The parameters' uncertainty of any model m of this record (at period Ts,
 * output offset y0, input relative to data->u[0]), as pdt_ident_result_t.std
 * gives it for the identification's own answer: for a model found another
 * way (pdt_ls) or changed by the caller. No workspace: the sensitivities
 * are simulated side by side. Returns PDT_ERR_ARG (NULL, an invalid model
 * or a gain of 0, Ts or y0 not finite or Ts <= 0), PDT_ERR_TOO_SHORT (fewer
 * than PDT_MIN_SAMPLES), PDT_ERR_NONFINITE (NaN or infinity in the data,
 * or a simulation that overflows), PDT_ERR_NO_EXCITATION (u constant);
 * *out untouched on error. O(n) per parameter. */
pdt_status_t pdt_ident_uncertainty(const pdt_model_t *m, const pdt_ident_data_t *data,
                                   pdt_real_t Ts, pdt_real_t y0, pdt_ident_std_t *out);

/* After pdt_ident_step or pdt_ident_result returned PDT_ERR_OUTLIER (more
 * samples to leave out than max_excluded allows): the first of them,
 * 0-based; SIZE_MAX otherwise (also for NULL, before init, and when
 * init refused the record). */
size_t pdt_ident_outlier(const pdt_ident_t *ctx);

/* Whether sample k was left out of the fit (missing, or a gross error the
 * screen found), once pdt_ident_step has returned PDT_OK or
 * PDT_ERR_OUTLIER; false for NULL, before init and for k past the record.
 * For a caller that scores the model on the record without them. O(1). */
bool pdt_ident_is_excluded(const pdt_ident_t *ctx, size_t k);

/* The parameters a model is printed with (the command line's JSON keys,
 * in its order): FOPDT K, tau, Td, y0; SOPDT K (Ki for an integrator),
 * wn, zeta, Td, y0, tau1, tau2 (a real pair only; T of an integrator is
 * tau2), a, b. */
typedef enum pdt_ident_par {
    PDT_IDENT_PAR_K = 0,
    PDT_IDENT_PAR_KI = 1,
    PDT_IDENT_PAR_TAU = 2,
    PDT_IDENT_PAR_WN = 3,
    PDT_IDENT_PAR_ZETA = 4,
    PDT_IDENT_PAR_TD = 5,
    PDT_IDENT_PAR_Y0 = 6,
    PDT_IDENT_PAR_TAU1 = 7,
    PDT_IDENT_PAR_TAU2 = 8,
    PDT_IDENT_PAR_A = 9,
    PDT_IDENT_PAR_B = 10,
    PDT_IDENT_PAR_COUNT = 11
} pdt_ident_par_t;

/* The uncertainty of the printed parameters: bit i of have set where
 * parameter i (pdt_ident_par_t) exists for the model; std (NaN where it
 * does not) and the covariance in the printed parameters' units. */
typedef struct pdt_ident_printed {
    uint32_t have;
    pdt_real_t std[PDT_IDENT_PAR_COUNT];
    pdt_real_t cov[PDT_IDENT_PAR_COUNT][PDT_IDENT_PAR_COUNT];
} pdt_ident_printed_t;

/* The uncertainty s of the parameters of m (pdt_ident_result_t.std, in the
 * model's own form, y0 the offset) carried to the printed parameters by
 * the delta method: cov_p = J cov J^T with J the derivatives of the printed
 * parameters by the model's (K = k / b, wn = sqrt b, zeta = a / (2 sqrt b),
 * tau1, tau2 the roots' time constants; Ki = k / a, T = 1 / a). A printed
 * parameter that depends on one the record does not determine (std
 * +infinity) has std +infinity and covariance NaN; one whose derivative
 * does not exist (tau1 = tau2, zeta = 1) std +infinity. A local, linear
 * guide: docs/uncertainty.md says where it holds. Returns PDT_ERR_ARG (NULL,
 * an invalid model, or s->count not the model's 4 or 5); *out untouched
 * then. O(1), no memory beyond the stack frame. */
pdt_status_t pdt_ident_std_printed(const pdt_model_t *m, const pdt_ident_std_t *s,
                                   pdt_ident_printed_t *out);

/* One record's part of the answer of several (docs/several-records.md):
 * its operating point, its own terms at the shared model and its fit. */
typedef struct pdt_ident_record_fit {
    size_t n;         /* samples */
    pdt_real_t Ts;    /* s */
    pdt_real_t u0;    /* input operating point: u[0] or its u_before */
    pdt_real_t y0;    /* output operating point, estimated */
    pdt_real_t x0;    /* initial ESTIMATE: its free response at the first
                      * sample, output units; else 0 */
    pdt_real_t dx0;   /* initial ESTIMATE, SOPDT: its slope, per second */
    pdt_real_t drift; /* drift: output units per second; else 0 */
    pdt_real_t cost;  /* mean square residual, output units squared */
    pdt_real_t fit;   /* percent, as pdt_ident_result_t.fit, of this record */
} pdt_ident_record_fit_t;

/* Record r's part of the answer once pdt_ident_step has returned PDT_OK:
 * r = 0 the first record (data of init), r = 1 .. more_count cfg.more's.
 * With one record, r = 0 gives the result's own u0, y0, x0, dx0, drift
 * and a fit with them. Uses the workspace's scratch (it must still be the
 * one init had); O(n_r). PDT_ERR_ARG for NULL or r past the records,
 * PDT_ERR_STATE before the answer, the identification's error status
 * after one; *out untouched on error. */
pdt_status_t pdt_ident_record_result(pdt_ident_t *ctx, uint32_t r, pdt_ident_record_fit_t *out);

/* Blocking convenience: init, step until done, result. Same statuses. */
pdt_status_t pdt_identify(pdt_ident_t *ctx, const pdt_ident_config_t *cfg,
                          const pdt_ident_data_t *data, void *work, size_t work_len,
                          pdt_ident_result_t *out);

#ifdef __cplusplus
}
#endif

#endif /* PDT_IDENT_H */
