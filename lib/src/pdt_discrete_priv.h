/*
 * The discrete model's private entries: one sample of its simulation,
 * inline for the passes that simulate several models side by side
 * (pdt_discrete_step and the Fisher pass), where a call per model and
 * sample would cost more than the sample's arithmetic; and the
 * discretisation without the checks its caller made.
 */
#ifndef PDT_DISCRETE_PRIV_H
#define PDT_DISCRETE_PRIV_H

#include "pdt/pdt_discrete.h"
#include "pdt_internal.h"

/* pdt_discrete_init for a model and a period its caller has already
 * checked (pdt_model_check, Ts finite and positive): the cost's
 * evaluations, thousands per identification, each of a checked shape. */
pdt_status_t pdt_discrete_init_checked(const pdt_model_t *m, pdt_real_t Ts, pdt_discrete_t *out);

/* B(q) u at sample k, with u = 0 before sample 0 (the start of the record,
 * where the indices k-1-l .. k-3-l may be negative). */
static inline pdt_real_t pdt_discrete_input(const pdt_discrete_t *d, const pdt_real_t *u,
                                            pdt_real_t u0, size_t k)
{
    pdt_real_t s = PDT_R(0.0);
    if (k <= d->delay) {
        return s;
    }
    size_t j = k - d->delay; /* >= 1: u index of b[0] is j - 1 */
    s += d->b[0] * (u[j - 1u] - u0);
    if (j >= 2u) {
        s += d->b[1] * (u[j - 2u] - u0);
    }
    if (j >= 3u) {
        s += d->b[2] * (u[j - 3u] - u0);
    }
    return s;
}

/* pdt_discrete_step without the call. */
static inline pdt_real_t pdt_discrete_advance(const pdt_discrete_t *d, pdt_discrete_state_t *s,
                                              const pdt_real_t *u, pdt_real_t u0, size_t k)
{
    /* The simulation's recurrence (pdt_discrete_simulate), one sample. */
    const pdt_real_t in = pdt_discrete_input(d, u, u0, k);
    if (d->order == 1u) {
        s->y1 = s->y1 - d->d[0] * s->y1 + in;
        return s->y1;
    }
    s->dy = s->dy - d->d[0] * s->dy - d->d[1] * s->y2 + in;
    s->y2 = s->y1;
    s->y1 = s->y1 + s->dy;
    return s->y1;
}

#endif /* PDT_DISCRETE_PRIV_H */
