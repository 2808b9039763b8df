/*
 * The identification engine's stages, private to the library. pdt_ident.c
 * checks the configuration and sequences the stages by one const table,
 * PLAN: for each phase, what its stage needs (an evaluation of this
 * call's budget, a group of them, or a call of its own) and the phase
 * after each outcome the stage returns (docs/ident-engine.md draws it).
 * Each stage lives in its own file:
 *
 *   pdt_ident_ga.c      the population: start, breeding, survival (ga)
 *   pdt_ident_band.c    the CONTROL weighting's band, between two GA runs
 *   pdt_ident_refine.c  Nelder-Mead from the best niches (nm)
 *   pdt_ident_polish.c  Newton on differences: one answer polished (polish)
 *   pdt_ident_scan.c    the dead time of the frequency criterion (scan)
 *   pdt_ident_vote.c    the answer of a search, the searches' agreement
 *   pdt_ident_profile.c the dead-time profile: a global check of it (profile)
 *   pdt_ident_rest.c    the output offset from the rest window (rest)
 *   pdt_ident_coarse.c  the searches' coarse record, the whole one after
 *   pdt_ident_screen.c  missing samples and gross errors left out (screen)
 *
 * and the helpers they share, which call no stage:
 *
 *   pdt_ident_genes.c   the gene coding, one candidate's evaluation, the
 *                       budgets
 *   pdt_ident_common.c  the answers kept: the best, one basin or two
 *   pdt_ident_initial.c whether the record started at rest
 *   pdt_ident_multi.c   several records: their costs, the joint profile
 *
 * The stage contract. A stage function returns an outcome and never
 * writes pdt_ident_t.phase; it calls no function of another stage's file
 * (the sequencer's file holds the two restarts, PH_REFIT and
 * PH_SCREEN_RESTART). What it may do in one call is what its phase needs
 * in PLAN: a phase marked EVALUATES does one evaluation, or with GROUP the
 * group its *_group function names (up to PDT_VECTOR_LANES; fewer in the
 * probe where some of its points lie beyond the bounds); a HEAVY phase
 * does one preparation as costly as init (a cost prepared again, a
 * breeding, a block of the Fisher pass, an O(n) step of the screen), and
 * no evaluation; a phase that needs nothing is a decision or the
 * preparation of the next stage's state, does no evaluation and runs in
 * the call that reached it (PH_REFIT, the identification begun again,
 * ends PH_SCREEN's call). A stage reads and writes its own part of
 * pdt_ident_t and the shared part: the configuration, the record and its
 * cost, the gene bounds lo and hi, best (every evaluation updates it),
 * vote (the answers kept; vote.base and vote.budget the running search's
 * or polish's budget, set through pdt_ident_polish_budget), start (the
 * profile's point for PH_REFINE_FROM), the answer (model, y0, fit, flags,
 * evidence, std, extra) and coarse.whole (the coarse answer's polish on
 * the whole record runs: Nelder-Mead's smaller steps). Which answer a
 * polish gives is no stage's state: the way into a search or a polish
 * names in PLAN the phase its PH_FINISH returns to (pdt_ident_t.resume,
 * which only the sequencer writes).
 */
#ifndef PDT_IDENT_PRIV_H
#define PDT_IDENT_PRIV_H

#include "pdt/pdt_ident.h"
#include "pdt_cost_engine.h"
#include "pdt_model_priv.h"

/* The sequencer's phases (pdt_ident_t.phase): the stage that runs next.
 * What each needs and where each leads is the table PLAN in pdt_ident.c
 * (docs/ident-engine.md draws it). A "decision" only chooses the next
 * phase. */
enum {
    PH_INIT_POP = 1,   /* evaluating the initial population */
    PH_BREED,          /* breeding a generation */
    PH_EVAL_OFF,       /* evaluating offspring */
    PH_TIME_POP,       /* CONTROL weighting: the population on the time cost */
    PH_TIME_BREED,     /* its generation bred */
    PH_TIME_OFF,       /* its offspring evaluated */
    PH_GA_END,         /* decision: the spectra or the refinement */
    PH_SHAPE_BEGIN,    /* init's first phase: the searches' budget, the
                        * coarse record's first factor */
    PH_SHAPE,          /* whether the output keeps its shape at that
                        * factor (a call of its own each) */
    PH_PREPARE,        /* the coarse record and its cost (a call of its own) */
    PH_GA_START,       /* a search's population drawn */
    PH_BAND,           /* CONTROL weighting: the band from the time model */
    PH_RECENTRE,       /* COMBINED: the spectra on the estimated offset */
    PH_REFINE_START,   /* the refinement's starts */
    PH_REFINE_FROM,    /* a refinement from pdt_ident_t.start alone */
    PH_REFINE,         /* Nelder-Mead */
    PH_NM_BEST,        /* Nelder-Mead from the polish's best point begun */
    PH_POLISH_BEGIN,   /* a Newton polish from the best begun */
    PH_POLISH,         /* Newton polish of one answer */
    PH_REFINE_END,     /* decision: the dead-time scan, the pinned kink pass,
                        * the dead-time probe or the answer */
    PH_KINK_PINNED,    /* the kink pass with the dead time pinned on the kink */
    PH_KINK_MIRROR,    /* decision: the kink pass across the kink, the probe
                        * or the answer */
    PH_KINK_ACROSS,    /* the kink pass from the mirror image across it */
    PH_KINK_HANDOVER,  /* decision: Nelder-Mead after it, or the probe */
    PH_KINK_NM,        /* Nelder-Mead from its best point begun */
    PH_KINK_REFINE,    /* that Nelder-Mead */
    PH_PROBE_BEGIN,    /* decision: the dead-time probe or the answer */
    PH_PROBE,          /* the dead time about a polished answer, mean delay held */
    PH_SCAN_START,     /* frequency criterion: its dead-time scan begun */
    PH_DELAY_SCAN,     /* frequency criterion: dead time and sign from Ct */
    PH_DELAY_REFINE,   /* its golden section */
    PH_FINISH,         /* a polish's answer; may re-score once (an integrator) */
    PH_SEARCH_END,     /* decision: the answer kept; another search or not */
    PH_PROFILE_BEGIN,  /* decision: the dead-time profile or not */
    PH_PROFILE,        /* the searches' answer checked along the dead time */
    PH_PROFILE_KEEP,   /* the polish of its far point kept as an answer */
    PH_PROFILE_END,    /* and put to the vote, or dropped */
    PH_INTERVAL_KEEP,  /* the search across the answer's kink kept */
    PH_INTERVAL_END,   /* and put to the vote, or dropped */
    PH_CONCLUDE,       /* the answer of all searches, its flags */
    PH_COARSE_CHECK,   /* decision: the whole record after a coarse one */
    PH_FINE,           /* the whole record after the coarse one's searches */
    PH_WHOLE_END,      /* the coarse answer polished on it: its bound flags */
    PH_REST_CHECK,     /* decision: the answer polished on the rest level */
    PH_REST,           /* AUTO offset: the answer polished on the rest level */
    PH_STD,            /* the parameters' uncertainty: its pass begun */
    PH_STD_PASS,       /* its Fisher pass, a block of samples per step */
    PH_EVIDENCE,       /* the answer's evidence against the null model */
    PH_EVIDENCE_LAGS,  /* its autocorrelation factor, four lags a step */
    PH_STATE_TESTS,    /* AUTO: the tests of the initial state on its residual */
    PH_SCREEN,         /* gross errors: the answer's residual */
    PH_REFIT,          /* AUTO initial state: the search again, state estimated */
    PH_SCREEN_HIGH,    /* its high pass, a block of samples per step */
    PH_SCREEN_MEDIAN,  /* the median of its magnitude, in passes */
    PH_SCREEN_BOUND,   /* the samples beyond the bound left out */
    PH_SCREEN_REFILL,  /* the record filled again */
    PH_SCREEN_RESTART, /* and the search run again on it */
    PH_DONE,
    PH_RETURN, /* not a phase: in PLAN, the phase that the way into the
                * running search or polish named (pdt_ident_t.resume) */
    PH_COUNT
};

/* What a stage function returns; PLAN gives the phase that follows each
 * (an outcome a phase never returns leads nowhere: PDT_ERR_STATE). */
typedef enum pdt_ident_outcome {
    OUT_AGAIN = 0,  /* more of the stage's work: the phase runs again */
    OUT_DONE,       /* the stage's work ended; a decision taken */
    OUT_SKIPPED,    /* a decision not taken: nothing to do there */
    OUT_FAILED,     /* a preparation or a pass failed */
    OUT_BEGUN,      /* a pass in several steps begun: its steps next */
    OUT_GENERATION, /* the population: another generation */
    OUT_TIME,       /* CONTROL weighting: a search on the time cost first */
    OUT_RECENTRE,   /* the population ended, COMBINED: its spectra */
    OUT_POLISH,     /* a polish of one answer begins */
    OUT_FALLBACK,   /* the polish hands over to Nelder-Mead */
    OUT_SCAN,       /* frequency criterion: the dead-time scan */
    OUT_KINK,       /* a kink pass begun; the profile: the search across
                     * the answer's nearest kink */
    OUT_PROBE,      /* the dead-time probe begun */
    OUT_SEARCH,     /* another search */
    OUT_REFIT,      /* the identification again with the state estimated */
    OUT_COUNT
} pdt_ident_outcome_t;

/* The frequency criterion cannot see the dead time or the sign of the
 * gain; after its search, Td is scanned on a grid of SCAN_POINTS values of
 * the time cost (both signs of the gain each), then refined by
 * GOLDEN_STEPS of golden-section search around the best grid point. */
#define PDT_IDENT_SCAN_POINTS      64u
#define PDT_IDENT_GOLDEN_STEPS     16u
#define PDT_IDENT_SCAN_EVALUATIONS (2u * PDT_IDENT_SCAN_POINTS + PDT_IDENT_GOLDEN_STEPS + 2u)

/* ---- pdt_ident_genes.c */

/* Whether a criterion has a frequency part. */
bool pdt_ident_uses_frequency(pdt_cost_kind_t kind);

/* The weighting with AUTO resolved, and whether it is CONTROL (the search
 * starts on the time cost to find the band). */
pdt_ident_weight_t pdt_ident_weight_of(const pdt_ident_config_t *cfg);
bool pdt_ident_control_band(const pdt_ident_config_t *cfg);

/* Evaluations kept back after the refinement (the dead-time scan, the
 * re-scoring of an integrator). */
uint32_t pdt_ident_late_reserve(const pdt_ident_config_t *cfg);

/* Evaluations the running search has used. */
uint32_t pdt_ident_used(const pdt_ident_t *c);
/* Evaluations the running search (or polish) may still use before its
 * late reserve. */
uint32_t pdt_ident_left(const pdt_ident_t *c);

/* The least budget of one search of the given population: one population
 * (two with the CONTROL weighting), one simplex and the late reserve. */
uint64_t pdt_ident_search_need(const pdt_ident_config_t *cfg, uint32_t population);

/* The running search's budget set so that pdt_ident_left gives budget
 * evaluations from now on (a polish of one answer, the profile's). */
void pdt_ident_polish_budget(pdt_ident_t *c, uint32_t budget);

/* Books count evaluations, each scoring a record of n samples: the
 * evaluations reported and the samples the step budget counts. */
void pdt_ident_counted(pdt_ident_t *c, uint32_t count, size_t n);

/* Dead time of a dead-time gene, within the caller's bounds, and back
 * (clamped to the gene's range). */
pdt_real_t pdt_ident_td_of_gene(const pdt_ident_t *c, pdt_real_t g);
pdt_real_t pdt_ident_gene_of_td(const pdt_ident_t *c, pdt_real_t Td);

/* Whole delays (PDT_DELAY_INTEGER): the whole number of samples of Ts
 * nearest to Td that lies in [lo, hi] (lo <= Td <= hi), to a few
 * roundings of the bounds; and whether [lo, hi] holds a whole sample at
 * all (init refuses bounds that hold none). */
pdt_real_t pdt_ident_whole_td(pdt_real_t Td, pdt_real_t Ts, pdt_real_t lo, pdt_real_t hi);
bool pdt_ident_whole_between(pdt_real_t Ts, pdt_real_t lo, pdt_real_t hi);

/* The output error's kinks lie at whole samples of dead time: the one
 * nearest r samples, and whether r lies on it (closer than
 * PDT_IDENT_ON_KINK of a sample), for the polish's kink passes and the
 * profile's search across the kink alike. */
#define PDT_IDENT_ON_KINK PDT_R(1e-3)
pdt_real_t pdt_ident_nearest_whole(pdt_real_t r);

/* Gene j clamped to its range; the normalised distance of two genomes. */
pdt_real_t pdt_ident_clamp(const pdt_ident_t *c, size_t j, pdt_real_t x);
pdt_real_t pdt_ident_distance(const pdt_ident_t *c, const pdt_real_t *x, const pdt_real_t *y);

/* The unit-gain model of a genome, and the bounds of its gain multiplier
 * from the caller's K bounds (0, 0: unbounded). */
void pdt_ident_shape(const pdt_ident_t *c, const pdt_real_t *g, pdt_model_t *m);
void pdt_ident_gain_bounds(const pdt_ident_t *c, const pdt_model_t *shape, pdt_real_t *lo,
                           pdt_real_t *hi);

/* A two-lag shape's gain unit (the view's K of s^2 + a s + b): k = b + a / T
 * (T the record's length). It moves smoothly from a lag's DC gain to an
 * integrator's, so one gain multiplier suits every shape near the best
 * (the cost's reference fit). */
pdt_real_t pdt_ident_lags_unit(const pdt_ident_t *c, pdt_real_t a, pdt_real_t b);

/* One evaluation of a genome: its cost (PDT_REAL_MAX when it cannot be
 * scored), gain multiplier and offset; the search's best follows it. */
void pdt_ident_evaluate(pdt_ident_t *c, const pdt_real_t *g, pdt_real_t *cost, pdt_real_t *gain,
                        pdt_real_t *offset);

/* Whether genomes of one shape at whole-sample dead times can be scored
 * from the shape's stored response (pdt_ident_evaluate_shift): one record,
 * and a cost without extra columns. */
bool pdt_ident_shift_ok(const pdt_ident_t *c);

/* count (1 .. PDT_COST_MANY) genomes in a row at g that differ in their
 * dead times only, each delay[i] whole samples of the cost's record,
 * scored from their shape's response in the scratch
 * (pdt_cost_profile_shift) with the best before them as the reference:
 * the results of count evaluations, at a fraction of the work. fresh: the
 * response is computed first (the shape's first group; the scratch keeps
 * it for the next ones until something else writes the scratch). False,
 * with nothing scored or counted, where the cost cannot score them so:
 * the caller evaluates them one by one. */
bool pdt_ident_evaluate_shift(pdt_ident_t *c, const pdt_real_t *g, const size_t *delay,
                              uint32_t count, bool fresh, pdt_real_t *cost, pdt_real_t *gain,
                              pdt_real_t *offset);

/* count (1 .. PDT_COST_MANY) genomes in a row at g, evaluated in one pass
 * over the record where the host can (pdt_cost_profile_many), with the
 * best before them as the reference: the results of count evaluations. */
void pdt_ident_evaluate_many(pdt_ident_t *c, const pdt_real_t *g, uint32_t count, pdt_real_t *cost,
                             pdt_real_t *gain, pdt_real_t *offset);

/* ---- pdt_ident_common.c: the answers kept */

/* The answer kept with the least cost (done >= 1), and the searches among
 * the answers kept (the profile's is not one). */
uint32_t pdt_ident_vote_best(const pdt_ident_t *c);
uint32_t pdt_ident_vote_searches(const pdt_ident_t *c);
/* Answers i and j in one basin (the same structure; costs within 1 % or
 * genes within 1 % of their ranges). */
bool pdt_ident_vote_same_basin(const pdt_ident_t *c, uint32_t i, uint32_t j);
/* The running search's GA best lies in the basin of the best answer kept
 * (pdt_ident_vote_same_basin's test): it has caught up with it. */
bool pdt_ident_vote_caught_up(const pdt_ident_t *c);
/* Flags on the answer's genes (AT_BOUND) after the whole record's polish. */
uint32_t pdt_ident_bound_flags(const pdt_ident_t *c);

/* The same structure: the gain's sign and, for a SOPDT, whether it
 * integrates. */
bool pdt_ident_same_structure(const pdt_model_t *a, const pdt_model_t *b);
/* Cost b within rtol of cost a (normalised costs). */
bool pdt_ident_cost_close(pdt_real_t a, pdt_real_t b, pdt_real_t rtol);
/* The running search's best as a model: the shape's gain unit times the
 * multiplier found. */
void pdt_ident_best_model(const pdt_ident_t *c, pdt_model_t *m);

/* ---- pdt_ident_ga.c */

/* PH_GA_START: a search from scratch, a Latin hypercube population, the
 * GA reset; OUT_TIME where it begins on the CONTROL weighting's time
 * cost. */
pdt_ident_outcome_t pdt_ident_ga_begin(pdt_ident_t *c);
/* The individuals the next population stage evaluates together: up to
 * PDT_VECTOR_LANES from an index that is a multiple of it, fewer at the
 * population's end. Fixed by the index alone, so the answer does not
 * depend on how the work is split into calls. */
uint32_t pdt_ident_ga_group(const pdt_ident_t *c);
/* PH_INIT_POP, PH_EVAL_OFF (PH_TIME_POP, PH_TIME_OFF with time set: the
 * CONTROL weighting's run on the time cost, on half the budget): a group
 * evaluated; at the population's end another generation or the end. */
pdt_ident_outcome_t pdt_ident_ga_eval_parent(pdt_ident_t *c, bool time);
pdt_ident_outcome_t pdt_ident_ga_breed(pdt_ident_t *c);
pdt_ident_outcome_t pdt_ident_ga_eval_offspring(pdt_ident_t *c, bool time);
/* PH_GA_END: the spectra re-centred (COMBINED), else the refinement. */
pdt_ident_outcome_t pdt_ident_ga_end(const pdt_ident_t *c);
/* Whether the search's GA ended with its niches resolved: one niche
 * left, the population outside it this generation's mutants. */
bool pdt_ident_ga_resolved(const pdt_ident_t *c);

/* ---- pdt_ident_band.c */

pdt_ident_outcome_t pdt_ident_band_start(pdt_ident_t *c);

/* ---- pdt_ident_refine.c */

pdt_ident_outcome_t pdt_ident_refine_recentre(pdt_ident_t *c);
pdt_ident_outcome_t pdt_ident_refine_begin(pdt_ident_t *c);
pdt_ident_outcome_t pdt_ident_refine_step(pdt_ident_t *c);
/* PH_REFINE_FROM: a refinement from pdt_ident_t.start alone (the
 * profile's point): Nelder-Mead, then the polish, with the running
 * search's budget. */
pdt_ident_outcome_t pdt_ident_refine_from(pdt_ident_t *c);
/* PH_NM_BEST, PH_KINK_NM: Nelder-Mead from the best with what is left of
 * the polish's budget; OUT_SKIPPED where no simplex fits. */
pdt_ident_outcome_t pdt_ident_refine_nm_best(pdt_ident_t *c);
/* The points the next PH_REFINE step evaluates together: one of each
 * running niche run, up to PDT_VECTOR_LANES; 1 in the final polish. */
uint32_t pdt_ident_refine_group(const pdt_ident_t *c);

/* ---- pdt_ident_scan.c */

pdt_ident_outcome_t pdt_ident_scan_start(pdt_ident_t *c);
pdt_ident_outcome_t pdt_ident_scan_grid(pdt_ident_t *c);
pdt_ident_outcome_t pdt_ident_scan_golden(pdt_ident_t *c);

/* ---- pdt_ident_vote.c */

/* PH_FINISH: the running search's or polish's answer (PLAN returns to
 * the phase that began it). */
pdt_ident_outcome_t pdt_ident_finish(pdt_ident_t *c);
/* PH_SEARCH_END (PH_PROFILE_KEEP, PH_INTERVAL_KEEP: the profile's
 * answer): the answer kept; another search (OUT_SEARCH) or not. */
pdt_ident_outcome_t pdt_ident_search_end(pdt_ident_t *c);
/* PH_CONCLUDE: the answer of all searches (and of the profile's polish):
 * the least cost, confirmed or flagged. */
pdt_ident_outcome_t pdt_ident_conclude(pdt_ident_t *c);

/* ---- pdt_ident_profile.c */

/* Whether the criterion has the dead-time profile after its searches
 * (the niche rule's radius depends on it, pdt_ident_ga.c). */
bool pdt_ident_profiled(const pdt_ident_config_t *cfg);
/* PH_PROFILE_BEGIN, when the searches have ended: OUT_DONE when the
 * profile begins; OUT_SKIPPED where it does not apply or where the budget
 * cannot pay for it. */
pdt_ident_outcome_t pdt_ident_profile_begin(pdt_ident_t *c);
/* PH_PROFILE: the next group of grid points, then the refinement of the
 * far point below the answer's neighbourhood (OUT_POLISH) or the search
 * across the answer's nearest kink (OUT_KINK), its start in
 * pdt_ident_t.start, or the vote. */
pdt_ident_outcome_t pdt_ident_profile_step(pdt_ident_t *c);
/* PH_PROFILE_END, PH_INTERVAL_END (across: the search across the kink,
 * the dead-time bounds it narrowed given back): the last answer kept is
 * the profile's; it stays only in another basin (across: below the
 * searches' answers too). */
pdt_ident_outcome_t pdt_ident_profile_end(pdt_ident_t *c, bool across);
/* The points the next PH_PROFILE step evaluates together. */
uint32_t pdt_ident_profile_group(const pdt_ident_t *c);

/* ---- pdt_ident_rest.c */

/* PH_REST_CHECK, after the searches concluded: OUT_DONE when the
 * answer's fitted offset disagrees with the rest window's level (once:
 * the polish on that level returns to PH_STD). */
pdt_ident_outcome_t pdt_ident_rest_check(const pdt_ident_t *c);
/* PH_REST: the cost on the rest level, the polish's budget set. */
pdt_ident_outcome_t pdt_ident_rest_start(pdt_ident_t *c);

/* ---- pdt_ident_coarse.c */

/* PH_SHAPE_BEGIN, once the searches' count is set: the first decimation
 * D to test in pdt_ident_coarse_factor; OUT_SKIPPED when there is none to
 * test (no coarse record, or the caller's D). */
pdt_ident_outcome_t pdt_ident_coarse_first(pdt_ident_t *c);
/* PH_SHAPE: one test of the output's shape at D: OUT_DONE with D kept, or
 * 1 when no factor is left; OUT_AGAIN with the next D to test. */
pdt_ident_outcome_t pdt_ident_coarse_factor(pdt_ident_t *c);
/* PH_PREPARE, after init prepared the whole record's cost and PH_SHAPE
 * chose D: the coarse record of n / D samples and its cost over the
 * whole one's; the whole record searched when D < 2 or that cost refuses
 * the coarse record (the whole one's prepared again). */
void pdt_ident_coarse_start(pdt_ident_t *c);
/* PH_COARSE_CHECK: OUT_DONE when the searches concluded on the coarse
 * record (the cost's is shorter than the whole one). */
pdt_ident_outcome_t pdt_ident_coarse_pending(const pdt_ident_t *c);
/* PH_FINE: the whole record's cost, then the answer polished on it
 * (OUT_POLISH), or the searches run again on it when the answer is too
 * fast for the coarse record (OUT_SEARCH). */
pdt_ident_outcome_t pdt_ident_coarse_fine(pdt_ident_t *c);
/* PH_WHOLE_END: the coarse answer polished on the whole record; the
 * searches' verdict stands, its bound flags are the polish's. */
pdt_ident_outcome_t pdt_ident_coarse_whole(pdt_ident_t *c);

/* ---- pdt_ident_polish.c: the polish of one answer */

/* PH_POLISH_BEGIN: the Newton polish from the best (its budget set). */
pdt_ident_outcome_t pdt_ident_polish_begin(pdt_ident_t *c);
/* PH_POLISH, PH_KINK_PINNED, PH_KINK_ACROSS (across set: the pass across
 * the kink, which ends at once, OUT_FALLBACK, at a centre no lower than
 * the pinned pass's): the next point or group of the Newton polish;
 * OUT_FALLBACK where Nelder-Mead would take over (PLAN: the answer's
 * polish hands over, the pinned pass just ends, the pass across asks
 * PH_KINK_HANDOVER), OUT_DONE at its end. */
pdt_ident_outcome_t pdt_ident_polish_step(pdt_ident_t *c, bool across);
/* PH_KINK_HANDOVER: Nelder-Mead after the pass across the kink (OUT_DONE)
 * only where its best point lies across the kink, else OUT_SKIPPED. */
pdt_ident_outcome_t pdt_ident_polish_handover(const pdt_ident_t *c);
/* PH_REFINE_END, what follows a refinement: the dead-time scan of the
 * frequency criterion (OUT_SCAN); on the whole record's output error with
 * a fractional dead time, after the answer's polish, the pinned kink pass
 * (OUT_KINK) where its dead time's differences reached a kink, else the
 * dead-time probe (OUT_PROBE); else the answer (OUT_DONE). */
pdt_ident_outcome_t pdt_ident_polish_end(pdt_ident_t *c);
/* PH_KINK_MIRROR, after the pinned pass: the pass across the kink from
 * the answer's mirror image through the pinned pass's point (OUT_KINK),
 * else the probe (OUT_PROBE) or the answer (OUT_DONE). */
pdt_ident_outcome_t pdt_ident_polish_mirror(pdt_ident_t *c);
/* PH_PROBE_BEGIN: the probe begun (OUT_PROBE), or the answer (OUT_DONE)
 * where the budget does not cover it. */
pdt_ident_outcome_t pdt_ident_polish_probe_begin(pdt_ident_t *c);
/* PH_PROBE: the next points of the dead-time probe (a group), then the
 * polish from the lowest where it is below the answer (OUT_POLISH). */
pdt_ident_outcome_t pdt_ident_polish_probe(pdt_ident_t *c);
/* The points the next Newton polish or PH_PROBE step evaluates
 * together. */
uint32_t pdt_ident_polish_group(const pdt_ident_t *c);
uint32_t pdt_ident_probe_group(const pdt_ident_t *c);
/* The evaluations a polish keeps back for its dead-time probe: the
 * probe's and a polish stencil's where the probe applies (the whole
 * record's output error, a fractional dead time), else 0. */
uint32_t pdt_ident_probe_reserve(const pdt_ident_t *c);

/* ---- pdt_ident_vote.c: the answer's uncertainty */

/* PH_STD begins the Fisher pass (OUT_BEGUN), or does it whole with the
 * evidence and the tests (OUT_DONE); PH_STD_PASS sums a block of
 * PDT_FISHER_BLOCK samples per step; PH_EVIDENCE begins the evidence
 * against the null model (OUT_BEGUN; OUT_SKIPPED where the model cannot
 * be simulated), PH_EVIDENCE_LAGS adds four lags of its autocorrelation
 * factor a step (OUT_DONE at the end, OUT_SKIPPED where the tests of the
 * initial state do not apply), PH_STATE_TESTS those tests on the
 * answer's residual. */
pdt_ident_outcome_t pdt_ident_std(pdt_ident_t *c);
pdt_ident_outcome_t pdt_ident_std_pass(pdt_ident_t *c);
pdt_ident_outcome_t pdt_ident_std_evidence(pdt_ident_t *c);
pdt_ident_outcome_t pdt_ident_std_lags(pdt_ident_t *c);
pdt_ident_outcome_t pdt_ident_std_state(pdt_ident_t *c);

/* ---- pdt_ident_screen.c */

/* The most samples that may be left out of a record of n (max_excluded
 * resolved). */
uint32_t pdt_ident_screen_limit(const pdt_ident_config_t *cfg, size_t n);
/* Whether init must prepare the screen's record before the cost: a y
 * sample not finite, or (with the screen) one pdt_cost_outlier names. */
bool pdt_ident_screen_needed(const pdt_ident_config_t *cfg, const pdt_ident_data_t *d);
/* At init, s's yfill and mask set: y copied, its missing samples and the
 * gross outliers pdt_cost_outlier names left out and filled.
 * PDT_ERR_OUTLIER when more than the limit are. */
pdt_status_t pdt_ident_screen_prepare(pdt_ident_screen_t *s, const pdt_ident_config_t *cfg,
                                      const pdt_ident_data_t *d);
/* The answer's residual screened in steps of O(n) or less: PH_SCREEN its
 * residual (OUT_REFIT: AUTO's identification with the state estimated
 * first), PH_SCREEN_HIGH its high pass (OUT_AGAIN for the next block),
 * PH_SCREEN_MEDIAN the median of its magnitude (OUT_AGAIN for the next
 * passes), PH_SCREEN_BOUND the samples left out (OUT_SKIPPED where none
 * are new), PH_SCREEN_REFILL the record filled again; PH_SCREEN_RESTART
 * (pdt_ident.c) begins the identification again on it. */
pdt_ident_outcome_t pdt_ident_screen_step(pdt_ident_t *c);
pdt_ident_outcome_t pdt_ident_screen_high(pdt_ident_t *c);
pdt_ident_outcome_t pdt_ident_screen_median(pdt_ident_t *c);
pdt_ident_outcome_t pdt_ident_screen_bound(pdt_ident_t *c);
pdt_ident_outcome_t pdt_ident_screen_refill(pdt_ident_t *c);
/* The restart failed with st: the status kept, and where the cost
 * refused the refilled record for a value orders of magnitude off, that
 * sample named. */
void pdt_ident_screen_failed(pdt_ident_t *c, pdt_status_t st);
/* The result's excluded, missing and excluded_first. */
void pdt_ident_screen_report(const pdt_ident_screen_t *s, size_t n, pdt_ident_result_t *r);

/* ---- pdt_ident_initial.c */

/* Whether the answer's residual e (n reals) moves over the record's first
 * samples more than the noise and a share of y's range: the output was
 * moving at the start where the model says it was still. */
bool pdt_ident_mid_transient(const pdt_real_t *e, const pdt_real_t *y, size_t n);
/* At the answer (pdt_ident_finish): with extra columns in the cost, its
 * free response and drift into c->extra and its fit with them. */
void pdt_ident_extra_finish(pdt_ident_t *c, const pdt_model_t *m);
/* The answer's output for its discrete model d into out (n reals), less
 * its offset: simulated from rest (pdt_cost_simulate), plus the free
 * response and the drift where the cost fits them. False where the cost refuses d. */
bool pdt_ident_simulate(const pdt_ident_t *c, const pdt_discrete_t *d, pdt_real_t *out);
/* The nuisance parameters fitted beside the model's: the states and the
 * drift. */
uint32_t pdt_ident_nuisance(const pdt_ident_t *c);
/* Whether a failed at-rest test is to be answered by a refit with the
 * state estimated (AUTO, SIMULATION, not yet done). */
bool pdt_ident_want_state(const pdt_ident_t *c);
/* Whether the answer's own free response from the first sample takes up
 * a tenth of its residual and more than chance explains (scratch
 * overwritten). */
bool pdt_ident_state_matters(pdt_ident_t *c);
/* PH_SCREEN's first duty: whether AUTO's test asked for the
 * identification again with the state estimated (auto_state set with
 * initial still AUTO; PH_REFIT, pdt_ident.c, begins it). */
bool pdt_ident_refit_due(const pdt_ident_t *c);

/* ---- pdt_ident_multi.c: several records (pdt_ident_config_t.more) */

/* Whether cfg has records beyond the first. */
bool pdt_ident_multi(const pdt_ident_config_t *cfg);
/* init's checks of the further records and of what they allow
 * (PDT_ERR_ARG); PDT_OK for one record. */
pdt_status_t pdt_ident_multi_check(const pdt_ident_config_t *cfg);
/* The longest record's samples (the scratch's length), n the first's. */
size_t pdt_ident_multi_longest(const pdt_ident_config_t *cfg, size_t n);
/* The workspace's reals for the further records' costs and copies, at
 * its end; 0 for one record. */
size_t pdt_ident_multi_reals(const pdt_ident_config_t *cfg);
/* The shortest record's duration *T and the shortest period *Ts (the
 * default search bounds), n the first record's samples. With one record
 * cfg->Ts n and cfg->Ts. */
void pdt_ident_multi_span(const pdt_ident_config_t *cfg, size_t n, pdt_real_t *T, pdt_real_t *Ts);
/* The further records checked and their costs prepared (cc the first
 * record's configuration; each gets its own period, operating point and
 * delay bound) in work from real index at; *costs their array there,
 * NULL for one record. init's statuses for a record. */
pdt_status_t pdt_ident_multi_prepare(const pdt_ident_config_t *cfg, const pdt_cost_config_t *cc,
                                     pdt_real_t Td_max, void *work, size_t at, pdt_cost_t **costs);
/* The profile of one shape (pdt_cost_profile_hint) or of count shapes
 * (pdt_cost_profile_many) on the context's cost with its scratch: with
 * several records their joint profile (pdt_cost_joint_profile). */
pdt_status_t pdt_ident_profile(pdt_ident_t *c, const pdt_model_t *shape, pdt_real_t glo,
                               pdt_real_t ghi, const pdt_cost_hint_t *hint,
                               pdt_cost_profile_t *out);
pdt_status_t pdt_ident_profile_many(pdt_ident_t *c, const pdt_model_t *shapes, size_t count,
                                    const pdt_real_t *glo, const pdt_real_t *ghi,
                                    const pdt_cost_hint_t *hint, pdt_cost_profile_t *out);
/* Several records: the answer m's joint fit, the first record's offset,
 * state and drift (pdt_ident_extra_finish's part). */
void pdt_ident_multi_finish(pdt_ident_t *c, const pdt_model_t *m);
/* Several records: PH_STD's part (no uncertainty; the joint evidence). */
void pdt_ident_multi_std(pdt_ident_t *c);
/* Record r's part of the answer res (pdt_ident_record_result's work, here
 * so that this file needs nothing of the sequencer's): PDT_ERR_ARG for r
 * past the records, PDT_ERR_NONFINITE where its terms cannot be formed. */
pdt_status_t pdt_ident_multi_record(pdt_ident_t *ctx, const pdt_ident_result_t *res, uint32_t r,
                                    pdt_ident_record_fit_t *out);

#endif /* PDT_IDENT_PRIV_H */
