/*
 * The evaluation kernel's entry points that serve the identification
 * engine alone (docs/kernel.md): a profile with a reference fit, and up to
 * PDT_COST_MANY shapes in one pass over the record. Private to lib/: the
 * public pdt_cost_profile gives the same results, up to rounding.
 */
#ifndef PDT_COST_ENGINE_H
#define PDT_COST_ENGINE_H

#include "pdt/pdt_cost.h"

/* The reference fit of pdt_cost_profile_hint: what the caller knows of
 * the best fit so far, in the units pdt_cost_profile returns. */
typedef struct pdt_cost_hint {
    pdt_real_t gain;   /* a gain multiplier near the candidate's best */
    pdt_real_t offset; /* an output offset near the candidate's best */
    pdt_real_t ncost;  /* the best normalised cost so far (ncost), or 0 if
                        * none: a candidate whose time part costs more than
                        * 4 times it is scored to about 1e-3 relative
                        * instead of 2e-6 (float; 1e-8 instead of 1e-11 in
                        * double), which spares it the second pass */
} pdt_cost_hint_t;

/* pdt_cost_profile with a reference fit (hint; NULL for none): the
 * reference is subtracted from the data inside the single pass, so that a
 * good candidate's cost is accurate without the second pass. The result
 * is pdt_cost_profile's up to rounding for any gain and offset in the
 * hint: a poor one (or 0, 0) only makes the second pass more likely. A
 * hint value that is not finite is taken as none. This is the call of the
 * identification's search, with the best fit so far as the hint: one pass
 * per candidate. Same returns as pdt_cost_profile. */
pdt_status_t pdt_cost_profile_hint(const pdt_cost_t *c, const pdt_model_t *shape,
                                   pdt_real_t gain_min, pdt_real_t gain_max,
                                   const pdt_cost_hint_t *hint, pdt_real_t *scratch,
                                   pdt_cost_profile_t *out);

/* Most shapes pdt_cost_profile_many takes in one call. */
#define PDT_COST_MANY 4u

/* pdt_cost_profile_hint of count shapes (1 .. PDT_COST_MANY) with one
 * reference fit, into out[0..count-1], each with its own gain bounds
 * gain_min[i], gain_max[i]: the same results as count calls, up to
 * rounding. Where the host has vector registers (GCC or Clang with SSE2
 * or NEON) two to four shapes of one order (all FOPDT or all SOPDT) on a
 * SIMULATION time part are simulated side by side in one pass over the
 * record (fewer than four cost what four cost); elsewhere each shape gets
 * its own pass, as in count calls. The identification's population
 * evaluation calls it with four candidates at a time, its niche runs and
 * its polish with two to four. Returns PDT_ERR_ARG for NULL, count 0 or above PDT_COST_MANY, or
 * any shape pdt_cost_profile refuses (PDT_ERR_BOUNDS for a gain_min above
 * its gain_max); out is then untouched. */
pdt_status_t pdt_cost_profile_many(const pdt_cost_t *c, const pdt_model_t *shapes, size_t count,
                                   const pdt_real_t *gain_min, const pdt_real_t *gain_max,
                                   const pdt_cost_hint_t *hint, pdt_real_t *scratch,
                                   pdt_cost_profile_t *out);

/* The unit-gain response of shape to the record's input from rest, its
 * dead time aside (the normalised units; r: the record's n reals): what
 * pdt_cost_profile_shift scores the shape's whole-sample dead times from.
 * PDT_ERR_ARG where the cost is not a SIMULATION one without extra
 * columns (pdt_cost_config_t.estimate_state, drift) or the shape cannot
 * be discretised; r is then untouched. Work: one pass over the record. */
pdt_status_t pdt_cost_response(const pdt_cost_t *c, const pdt_model_t *shape, pdt_real_t *r);

/* pdt_cost_profile_many of count (1 .. PDT_COST_MANY) copies of shape
 * (its dead time ignored) at the whole-sample delays delay[0..count-1],
 * with one pair of gain bounds, from the shape's response r
 * (pdt_cost_response on the same cost): the results of
 * pdt_cost_profile_many for those shapes with dead times delay[i] Ts
 * without their discretisations and simulations, bit for bit where the
 * cost scores the whole record and takes the dead time in whole samples
 * (PDT_DELAY_INTEGER; in fractional mode delay[i] Ts may round to a
 * fraction of a sample, and the results agree to rounding). A pass over the
 * record for each delay (one for all where the host has vector
 * registers) that only scores; the dead-time profile of the
 * identification scores its grid so. The cost must be a SIMULATION one
 * without extra columns; PDT_ERR_ARG for NULL, count 0 or above
 * PDT_COST_MANY, such a cost or a delay beyond the cost's delay bounds,
 * PDT_ERR_BOUNDS for gain_min above gain_max; out is then untouched. */
pdt_status_t pdt_cost_profile_shift(const pdt_cost_t *c, const pdt_model_t *shape,
                                    const pdt_real_t *r, const size_t *delay, size_t count,
                                    pdt_real_t gain_min, pdt_real_t gain_max,
                                    const pdt_cost_hint_t *hint, pdt_cost_profile_t *out);

#endif /* PDT_COST_ENGINE_H */
