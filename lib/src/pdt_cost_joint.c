/*
 * Several records of one process, one model (docs/several-records.md).
 *
 * For a given shape each record's simulated output is linear in the
 * shared gain K and in the record's own columns (its offset, and as the
 * cost fits them its state at the first sample and its drift):
 *   y_r = K s_r + X_r c_r + e_r.
 * The record's own columns are eliminated record by record: with P_r the
 * projection off X_r, the joint least squares is
 *   K = sum_r s_r'P_r y_r / sum_r s_r'P_r s_r,
 * each record's two sums from its own normal equations
 * (pdt_cost_extra_sums, in its own normalised units, brought to the first
 * record's by powers of two, exactly). The residual of each record is
 * then summed directly at that K with its own columns fitted
 * (pdt_cost_extra_solve with the gain held), not from the normal
 * equations, which cancel when the fit is good.
 */
#include "pdt_cost_state.h"

#include "pdt_internal.h"

#if PDT_REAL_DOUBLE
#define ldexp_r ldexp
#else
#define ldexp_r ldexpf
#endif

/* The shape discretised at the record's period, its delay in the
 * record's bounds. */
static bool discretise(const pdt_cost_t *c, const pdt_model_t *shape, pdt_discrete_t *d)
{
    return pdt_discrete_init(shape, c->cfg.Ts, d) == PDT_OK && d->delay >= c->cfg.delay_min &&
           d->delay <= c->cfg.delay_max;
}

/* The scored samples of a record. */
static size_t scored(const pdt_cost_t *c, uint8_t order)
{
    return c->cfg.whole_record ? c->n : c->n - (c->cfg.delay_max + order);
}

pdt_status_t pdt_cost_joint_profile(const pdt_cost_t *const *costs, size_t count,
                                    const pdt_model_t *shape, pdt_real_t gain_min,
                                    pdt_real_t gain_max, pdt_real_t *scratch,
                                    pdt_cost_profile_t *out)
{
    pdt_discrete_t d;
    pdt_real_t sss = PDT_R(0.0), ssy = PDT_R(0.0);
    if (costs == NULL || count == 0u || shape == NULL || scratch == NULL || out == NULL ||
        pdt_model_check(shape) != PDT_OK || !pdt_finite(gain_min) || !pdt_finite(gain_max)) {
        return PDT_ERR_ARG;
    }
    const pdt_cost_t *const c0 = costs[0];
    /* Pass 1: each record's two sums, in the first record's units. */
    for (size_t r = 0u; r < count; r++) {
        const pdt_cost_t *c = costs[r];
        pdt_real_t a, b;
        if (!discretise(c, shape, &d)) {
            return PDT_ERR_ARG;
        }
        pdt_cost_extra_sums(c, &d, scratch, &a, &b);
        const int du = c->u_exp - c0->u_exp, dy = c->y_exp - c0->y_exp;
        sss += ldexp_r(a, 2 * du);
        ssy += ldexp_r(b, du + dy);
    }
    /* The shared gain, in the first record's normalised units. */
    pdt_real_t K = (sss > PDT_R(0.0) && pdt_finite(sss)) ? ssy / sss : PDT_R(0.0);
    const int to_gain = c0->y_exp - c0->u_exp;
    const bool bounded = !(gain_min == PDT_R(0.0) && gain_max == PDT_R(0.0));
    if (bounded) {
        const pdt_real_t lo = ldexp_r(gain_min, -to_gain), hi = ldexp_r(gain_max, -to_gain);
        K = (K < lo || K != K) ? lo : ((K > hi) ? hi : K);
    }
    /* Pass 2: each record's residual at K, its own columns fitted. */
    pdt_real_t ss = PDT_R(0.0), m = PDT_R(0.0), off0 = PDT_R(0.0);
    for (size_t r = 0u; r < count; r++) {
        const pdt_cost_t *c = costs[r];
        pdt_cost_extra_t x;
        (void)discretise(c, shape, &d);
        const int dk = (c0->y_exp - c0->u_exp) - (c->y_exp - c->u_exp);
        const pdt_real_t Kr = ldexp_r(K, dk);
        pdt_cost_extra_solve(c, &d, true, Kr, Kr, scratch, &x);
        const pdt_real_t mr = (pdt_real_t)scored(c, d.order);
        ss += ldexp_r(x.ncost * mr, 2 * (c->y_exp - c0->y_exp));
        m += mr;
        off0 = (r == 0u) ? x.offset : off0;
    }
    pdt_cost_profile_t p = {PDT_R(0.0), PDT_R(0.0), PDT_R(0.0), PDT_R(0.0), PDT_R(0.0), PDT_R(0.0)};
    p.ncost = pdt_finite(ss) ? ss / m : (pdt_real_t)INFINITY;
    p.cost = ldexp_r(p.ncost, 2 * c0->y_exp);
    p.cost = pdt_finite(p.cost) ? p.cost : (pdt_real_t)INFINITY;
    p.ct = p.cost;
    p.gain = ldexp_r(K, to_gain);
    if (bounded) {
        p.gain = p.gain < gain_min ? gain_min : (p.gain > gain_max ? gain_max : p.gain);
    }
    p.offset = ldexp_r(off0, c0->y_exp);
    if (!pdt_finite(p.ncost) || !pdt_finite(p.gain) || !pdt_finite(p.offset)) {
        p.ncost = (pdt_real_t)INFINITY;
        p.cost = (pdt_real_t)INFINITY;
        p.ct = p.cost;
        p.gain = pdt_finite(p.gain) ? p.gain : PDT_R(0.0);
        p.offset = PDT_R(0.0);
    }
    *out = p;
    return PDT_OK;
}

pdt_status_t pdt_cost_joint_terms(const pdt_cost_t *c, const pdt_model_t *m, pdt_real_t *scratch,
                                  pdt_cost_extra_t *out, pdt_real_t *sst)
{
    pdt_discrete_t d;
    pdt_model_t shape;
    pdt_real_t K;
    if (c == NULL || m == NULL || scratch == NULL || out == NULL || sst == NULL ||
        pdt_model_check(m) != PDT_OK) {
        return PDT_ERR_ARG;
    }
    shape = *m;
    if (m->kind == PDT_MODEL_FOPDT) {
        K = m->p.fopdt.K;
        shape.p.fopdt.K = PDT_R(1.0);
    } else {
        K = m->p.sopdt.k;
        shape.p.sopdt.k = PDT_R(1.0);
    }
    if (pdt_discrete_init(&shape, c->cfg.Ts, &d) != PDT_OK) {
        return PDT_ERR_ARG;
    }
    const pdt_real_t Kn = ldexp_r(K, c->u_exp - c->y_exp);
    pdt_cost_extra_t r;
    pdt_cost_extra_solve(c, &d, true, Kn, Kn, scratch, &r);
    const int ey = c->y_exp;
    r.gain = K;
    r.offset = ldexp_r(r.offset, ey);
    r.state[0] = ldexp_r(r.state[0], ey);
    r.state[1] = ldexp_r(r.state[1], ey) / c->cfg.Ts;
    r.drift = ldexp_r(r.drift, ey) / ((pdt_real_t)c->n * c->cfg.Ts);
    r.ncost = ldexp_r(r.ncost, 2 * ey);
    *sst = ldexp_r(c->yvar[d.order - 1u], 2 * ey);
    *out = r;
    return PDT_OK;
}
