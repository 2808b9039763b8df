/*
 * The simulation cost's extra columns (pdt_cost_state.c), private to the
 * cost and identification modules: the model's free response from the
 * record's first sample (pdt_cost_config_t.estimate_state) and a linear
 * drift of the output (pdt_cost_config_t.drift), fitted in closed form
 * with the gain and the offset (docs/equations.md, "The state at the
 * record's start and drift").
 */
#ifndef PDT_COST_STATE_H
#define PDT_COST_STATE_H

#include "pdt/pdt_cost.h"
#include "pdt/pdt_discrete.h"
#include "pdt_cost_engine.h"

/* Most columns of the least squares: gain, offset, drift, two states. */
#define PDT_COST_STATE_COLS 5u

/* One fit. In the normalised units of the cost object from
 * pdt_cost_extra_solve; in output units (state[1] and drift per second)
 * from pdt_cost_extra_terms. */
typedef struct pdt_cost_extra {
    pdt_real_t ncost;    /* mean square residual, normalised units */
    pdt_real_t gain;     /* multiplier of the shape's gain */
    pdt_real_t offset;   /* output offset added to y0 (its level at the
                          * record's middle when drift is fitted) */
    pdt_real_t state[2]; /* the free response at the first sample and
                          * (order 2) its change over the first sample */
    pdt_real_t drift;    /* the output's drift */
    uint32_t dropped;    /* bit j: column j (0 gain, 1 offset, 2 drift,
                          * 3 and 4 the states) not fitted or not
                          * determined by the record, held at 0 */
} pdt_cost_extra_t;

/* Whether c fits columns beyond the gain and the offset. */
bool pdt_cost_extra_on(const pdt_cost_t *c);

/* The least squares of the simulation over the scored samples for the
 * discrete shape d (unit gain, normalised units), the gain held in [lo,
 * hi] when bounded. scratch: n reals. Work: two passes over the record
 * (pdt_cost_state.c gives the count). */
void pdt_cost_extra_solve(const pdt_cost_t *c, const pdt_discrete_t *d, bool bounded, pdt_real_t lo,
                          pdt_real_t hi, pdt_real_t *scratch, pdt_cost_extra_t *out);

/* The fit of model m (its gain free) in output units. scratch: n reals.
 * PDT_ERR_ARG for a cost without extra columns or a model it cannot
 * discretise. */
pdt_status_t pdt_cost_extra_terms(const pdt_cost_t *c, const pdt_model_t *m, pdt_real_t *scratch,
                                  pdt_cost_extra_t *out);

/* Adds the free response and the drift of ex (output units, from
 * pdt_cost_extra_terms for d's model) to ysim[0..n-1]. */
void pdt_cost_extra_add(const pdt_cost_t *c, const pdt_discrete_t *d, const pdt_cost_extra_t *ex,
                        pdt_real_t *ysim);

/* The residual sums of squares of model m's shape (its gain free) from
 * rest (*rest) and with its state at the first sample estimated (*state),
 * normalised units, on a SIMULATION cost whatever its estimate_state.
 * False where they cannot be computed. scratch: n reals. */
bool pdt_cost_extra_state_gain(const pdt_cost_t *c, const pdt_model_t *m, pdt_real_t *scratch,
                               pdt_real_t *rest, pdt_real_t *state);

/* The sums the shared gain of several records takes from this one
 * (docs/several-records.md): with P the projection off the record's own
 * columns (offset, drift, states as c fits them, gain excluded), *sss =
 * s'P s and *ssy = s'P y of the shape d's response s, normalised units,
 * from the normal equations. scratch: n reals. One pass over the record
 * and two solves. */
void pdt_cost_extra_sums(const pdt_cost_t *c, const pdt_discrete_t *d, pdt_real_t *scratch,
                         pdt_real_t *sss, pdt_real_t *ssy);

/* One simulation pass's regression sums (pdt_cost.c), normalised units,
 * around the reference fit (K0, c0): m scored samples, sum s, sum e (e = y
 * - K0 s - c0), the co-moments vss, ves, vee centred with the offset, and
 * the raw sums ss, |es|, ee they come from. */
typedef struct pdt_cost_sim {
    pdt_real_t m, sum_s, sum_e, vss, ves, vee, ss, es, ee;
} pdt_cost_sim_t;

/* One pass of the kernel over c for the discrete shape d around (K0, c0):
 * pdt_cost_profile's time part before its gain is chosen. A SIMULATION
 * cost without extra columns. */
void pdt_cost_sim_sums(const pdt_cost_t *c, const pdt_discrete_t *d, pdt_real_t K0, pdt_real_t c0,
                       pdt_cost_sim_t *out);

/* Most records pdt_cost_joint_profile takes. */
#define PDT_COST_JOINT_MAX 8u

/* The joint profile of several records of one process (pdt_cost_joint.c):
 * costs[0 .. count - 1] (count 1 .. PDT_COST_JOINT_MAX), each a SIMULATION cost of its own record and
 * period, with its own offset (and state, drift as it fits them); the
 * shape's gain shared. As pdt_cost_profile for one record: ncost the
 * summed squared residual over the summed scored samples in costs[0]'s
 * normalised units, cost the same in output units squared, gain the
 * shared multiplier (clamped to [gain_min, gain_max] unless both are 0),
 * offset costs[0]'s; ct = cost, cf = 0. scratch: the longest record's n
 * reals. hint (NULL: none) as pdt_cost_profile_hint's, its offset the
 * first record's. PDT_ERR_ARG where a record's cost cannot discretise the
 * shape or its delay exceeds the record's delay bound; *out untouched
 * then. Work: with the offset the only own column, one kernel pass over
 * each record (pdt_cost_sim_sums; up to three more where the sums cancel,
 * as in pdt_cost_profile); with states or drift, three passes over each
 * record (pdt_cost_extra_sums, then pdt_cost_extra_solve at the shared
 * gain). */
pdt_status_t pdt_cost_joint_profile(const pdt_cost_t *const *costs, size_t count,
                                    const pdt_model_t *shape, pdt_real_t gain_min,
                                    pdt_real_t gain_max, const pdt_cost_hint_t *hint,
                                    pdt_real_t *scratch, pdt_cost_profile_t *out);

/* One record's own terms at model m's gain (its gain fixed, the record's
 * own columns fitted): offset, state, drift in output units as
 * pdt_cost_extra_terms gives them, ncost in output units squared, and
 * *sst the record's sum of (y - mean y)^2 in output units squared.
 * scratch: n reals. PDT_ERR_ARG for a model c cannot discretise. */
pdt_status_t pdt_cost_joint_terms(const pdt_cost_t *c, const pdt_model_t *m, pdt_real_t *scratch,
                                  pdt_cost_extra_t *out, pdt_real_t *sst);

#endif /* PDT_COST_STATE_H */
