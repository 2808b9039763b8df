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
#include "pdt_model_priv.h"

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

/* The kernel's sums may exceed the residual they give by this factor
 * before float rounding costs more than about 2e-6 of it (1e-11 in
 * double), as in pdt_cost_profile; beyond, the pass runs again around the
 * fit found, at most SIM_PASSES times. */
#if PDT_REAL_DOUBLE
#define CANCEL_RATIO (PDT_R(1e-11) / PDT_REAL_EPS)
#else
#define CANCEL_RATIO (PDT_R(2e-6) / PDT_REAL_EPS)
#endif
#define SIM_PASSES 3u

/* The offset-only joint fit's state: each record's reference and sums. */
typedef struct joint_sim {
    pdt_real_t K0[PDT_COST_JOINT_MAX]; /* references, each record's units */
    pdt_real_t c0[PDT_COST_JOINT_MAX];
    pdt_cost_sim_t s[PDT_COST_JOINT_MAX];
} joint_sim_t;

/* The shared gain from the records' sums, first record's units. */
static pdt_real_t joint_gain(const pdt_cost_t *const *costs, size_t count, const joint_sim_t *j)
{
    pdt_real_t a = PDT_R(0.0), b = PDT_R(0.0);
    const pdt_cost_t *c0 = costs[0];
    for (size_t r = 0u; r < count; r++) {
        const int du = costs[r]->u_exp - c0->u_exp, dy = costs[r]->y_exp - c0->y_exp;
        a += ldexp_r(j->s[r].vss, 2 * du);
        b += ldexp_r(j->s[r].ves + j->K0[r] * j->s[r].vss, du + dy);
    }
    return (a > PDT_R(0.0) && pdt_finite(a)) ? b / a : PDT_R(0.0);
}

/* The shared gain K (first record's units) in record c's. */
static pdt_real_t gain_in(const pdt_cost_t *c0, const pdt_cost_t *c, pdt_real_t K)
{
    return ldexp_r(K, (c0->y_exp - c0->u_exp) - (c->y_exp - c->u_exp));
}

/* The residual at K summed over the records (first record's units), and
 * whether the sums it came from cancel. */
static pdt_real_t joint_rss(const pdt_cost_t *const *costs, size_t count, const joint_sim_t *j,
                            pdt_real_t K, bool *cancels)
{
    pdt_real_t rss = PDT_R(0.0), big = PDT_R(0.0);
    for (size_t r = 0u; r < count; r++) {
        const pdt_cost_sim_t *s = &j->s[r];
        const pdt_real_t dk = gain_in(costs[0], costs[r], K) - j->K0[r];
        pdt_real_t v = s->vee - dk * (PDT_R(2.0) * s->ves - dk * s->vss);
        v = (v > PDT_R(0.0)) ? v : PDT_R(0.0);
        const int dy = 2 * (costs[r]->y_exp - costs[0]->y_exp);
        rss += ldexp_r(v, dy);
        big += ldexp_r(s->ee + pdt_fabs(dk) * (PDT_R(2.0) * s->es + pdt_fabs(dk) * s->ss), dy);
    }
    *cancels = pdt_finite(rss) && !(big <= CANCEL_RATIO * rss);
    return (rss == rss) ? rss : (pdt_real_t)INFINITY;
}

/* One pass over every record around its reference. */
static void joint_pass(const pdt_cost_t *const *costs, size_t count, const pdt_discrete_t *d,
                       joint_sim_t *j)
{
    for (size_t r = 0u; r < count; r++) {
        pdt_cost_sim_sums(costs[r], &d[r], j->K0[r], j->c0[r], &j->s[r]);
    }
}

/* The offset-only joint profile: the kernel's sums of each record. */
static void joint_offset(const pdt_cost_t *const *costs, size_t count, const pdt_discrete_t *d,
                         const pdt_real_t *bounds, const pdt_cost_hint_t *hint,
                         pdt_cost_profile_t *p)
{
    const pdt_cost_t *c0 = costs[0];
    const int to_gain = c0->y_exp - c0->u_exp;
    joint_sim_t j;
    pdt_real_t Kh = PDT_R(0.0);
    if (hint != NULL && pdt_finite(hint->gain)) {
        Kh = ldexp_r(hint->gain, -to_gain);
    }
    for (size_t r = 0u; r < count; r++) {
        j.K0[r] = gain_in(c0, costs[r], Kh);
        j.c0[r] = costs[r]->ysum[d[r].order - 1u] / (pdt_real_t)(costs[r]->n);
    }
    joint_pass(costs, count, d, &j);
    bool cancels = false;
    pdt_real_t K = joint_gain(costs, count, &j), rss;
    K = (bounds != NULL) ? ((K < bounds[0] || K != K) ? bounds[0] : (K > bounds[1] ? bounds[1] : K))
                         : K;
    rss = joint_rss(costs, count, &j, K, &cancels);
    for (uint32_t pass = 0u; pass < SIM_PASSES && cancels; pass++) {
        for (size_t r = 0u; r < count; r++) {
            const pdt_cost_sim_t *s = &j.s[r];
            const pdt_real_t Kr = gain_in(c0, costs[r], K);
            j.c0[r] += (s->sum_e - (Kr - j.K0[r]) * s->sum_s) / s->m;
            j.K0[r] = Kr;
        }
        joint_pass(costs, count, d, &j);
        K = joint_gain(costs, count, &j);
        K = (bounds != NULL)
                ? ((K < bounds[0] || K != K) ? bounds[0] : (K > bounds[1] ? bounds[1] : K))
                : K;
        rss = joint_rss(costs, count, &j, K, &cancels);
    }
    pdt_real_t m = PDT_R(0.0);
    for (size_t r = 0u; r < count; r++) {
        m += j.s[r].m;
    }
    const pdt_cost_sim_t *s0 = &j.s[0];
    p->ncost = rss / m;
    p->gain = ldexp_r(K, to_gain);
    p->offset = ldexp_r(j.c0[0] + (s0->sum_e - (K - j.K0[0]) * s0->sum_s) / s0->m, c0->y_exp);
}

/* The joint profile with states or drift: each record's sums from its
 * normal equations, then its residual at the shared gain. */
static void joint_extra(const pdt_cost_t *const *costs, size_t count, const pdt_discrete_t *d,
                        const pdt_real_t *bounds, pdt_real_t *scratch, pdt_cost_profile_t *p)
{
    const pdt_cost_t *const c0 = costs[0];
    pdt_real_t sss = PDT_R(0.0), ssy = PDT_R(0.0);
    for (size_t r = 0u; r < count; r++) {
        const pdt_cost_t *c = costs[r];
        pdt_real_t a, b;
        pdt_cost_extra_sums(c, &d[r], scratch, &a, &b);
        const int du = c->u_exp - c0->u_exp, dy = c->y_exp - c0->y_exp;
        sss += ldexp_r(a, 2 * du);
        ssy += ldexp_r(b, du + dy);
    }
    pdt_real_t K = (sss > PDT_R(0.0) && pdt_finite(sss)) ? ssy / sss : PDT_R(0.0);
    if (bounds != NULL) {
        K = (K < bounds[0] || K != K) ? bounds[0] : ((K > bounds[1]) ? bounds[1] : K);
    }
    pdt_real_t ss = PDT_R(0.0), m = PDT_R(0.0), off0 = PDT_R(0.0);
    for (size_t r = 0u; r < count; r++) {
        const pdt_cost_t *c = costs[r];
        pdt_cost_extra_t x;
        const pdt_real_t Kr = gain_in(c0, c, K);
        pdt_cost_extra_solve(c, &d[r], true, Kr, Kr, scratch, &x);
        const pdt_real_t mr = (pdt_real_t)scored(c, d[r].order);
        ss += ldexp_r(x.ncost * mr, 2 * (c->y_exp - c0->y_exp));
        m += mr;
        off0 = (r == 0u) ? x.offset : off0;
    }
    p->ncost = pdt_finite(ss) ? ss / m : (pdt_real_t)INFINITY;
    p->gain = ldexp_r(K, c0->y_exp - c0->u_exp);
    p->offset = ldexp_r(off0, c0->y_exp);
}

pdt_status_t pdt_cost_joint_profile(const pdt_cost_t *const *costs, size_t count,
                                    const pdt_model_t *shape, pdt_real_t gain_min,
                                    pdt_real_t gain_max, const pdt_cost_hint_t *hint,
                                    pdt_real_t *scratch, pdt_cost_profile_t *out)
{
    pdt_discrete_t d[PDT_COST_JOINT_MAX];
    if (costs == NULL || count == 0u || count > PDT_COST_JOINT_MAX || shape == NULL ||
        scratch == NULL || out == NULL || pdt_model_check(shape) != PDT_OK ||
        !pdt_finite(gain_min) || !pdt_finite(gain_max)) {
        return PDT_ERR_ARG;
    }
    for (size_t r = 0u; r < count; r++) {
        if (!discretise(costs[r], shape, &d[r])) {
            return PDT_ERR_ARG;
        }
    }
    const pdt_cost_t *const c0 = costs[0];
    const int to_gain = c0->y_exp - c0->u_exp;
    const bool bounded = !(gain_min == PDT_R(0.0) && gain_max == PDT_R(0.0));
    const pdt_real_t bounds[2] = {ldexp_r(gain_min, -to_gain), ldexp_r(gain_max, -to_gain)};
    pdt_cost_profile_t p = {PDT_R(0.0), PDT_R(0.0), PDT_R(0.0), PDT_R(0.0), PDT_R(0.0), PDT_R(0.0)};
    if (pdt_cost_extra_on(c0)) {
        joint_extra(costs, count, d, bounded ? bounds : NULL, scratch, &p);
    } else {
        joint_offset(costs, count, d, bounded ? bounds : NULL, hint, &p);
    }
    p.cost = ldexp_r(p.ncost, 2 * c0->y_exp);
    p.cost = pdt_finite(p.cost) ? p.cost : (pdt_real_t)INFINITY;
    p.ct = p.cost;
    if (bounded) {
        p.gain = p.gain < gain_min ? gain_min : (p.gain > gain_max ? gain_max : p.gain);
    }
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
    K = pdt_model_split_gain(m, &shape);
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
