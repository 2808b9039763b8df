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

#endif /* PDT_COST_STATE_H */
