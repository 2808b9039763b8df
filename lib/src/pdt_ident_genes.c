/*
 * The identification's common ground: what a genome codes (the unit-gain
 * shape and its dead time) and one candidate's evaluation, with the gain
 * and the offset in closed form, which every stage calls.
 */
#include "pdt_cost_state.h"
#include "pdt_ident_priv.h"
#include "pdt_internal.h"

bool pdt_ident_uses_frequency(pdt_cost_kind_t kind)
{
    return kind == PDT_COST_FREQUENCY || kind == PDT_COST_COMBINED;
}

pdt_ident_weight_t pdt_ident_weight_of(const pdt_ident_config_t *cfg)
{
    if (cfg->weight != PDT_IDENT_WEIGHT_AUTO) {
        return cfg->weight;
    }
    return pdt_model_kind_lags(cfg->model) == 1u && cfg->cost == PDT_COST_COMBINED
               ? PDT_IDENT_WEIGHT_CONTROL
               : PDT_IDENT_WEIGHT_UNIFORM;
}

bool pdt_ident_control_band(const pdt_ident_config_t *cfg)
{
    return pdt_ident_uses_frequency(cfg->cost) &&
           pdt_ident_weight_of(cfg) == PDT_IDENT_WEIGHT_CONTROL;
}

uint32_t pdt_ident_late_reserve(const pdt_ident_config_t *cfg)
{
    uint32_t r = cfg->cost == PDT_COST_FREQUENCY ? PDT_IDENT_SCAN_EVALUATIONS : 0u;
    if (pdt_model_kind_integrates(cfg->model) && cfg->integrating) {
        r += 1u;
    }
    return r;
}

uint64_t pdt_ident_search_need(const pdt_ident_config_t *cfg, uint32_t population)
{
    const uint64_t populations = pdt_ident_control_band(cfg) ? 2u : 1u;
    return populations * population + cfg->refine_evaluations + pdt_ident_late_reserve(cfg);
}

void pdt_ident_polish_budget(pdt_ident_t *c, uint32_t budget)
{
    /* The polish of the best within budget: the running search's budget
     * is set so that pdt_ident_left gives it. */
    c->vote.base = c->evaluations;
    c->vote.budget = budget + pdt_ident_late_reserve(&c->cfg);
}

void pdt_ident_counted(pdt_ident_t *c, uint32_t count, size_t n)
{
    c->evaluations += count;
    c->samples += (uint64_t)count * n;
}

uint32_t pdt_ident_used(const pdt_ident_t *c)
{
    return c->evaluations - c->vote.base;
}

uint32_t pdt_ident_left(const pdt_ident_t *c)
{
    const uint32_t left = c->vote.budget - pdt_ident_late_reserve(&c->cfg);
    const uint32_t used = pdt_ident_used(c);
    return left > used ? left - used : 0u;
}

/* The caller's dead-time bounds (Td_max 0: the derived upper bound, which
 * the gene's range alone keeps). */
static pdt_real_t td_upper(const pdt_ident_t *c)
{
    return c->cfg.Td_max > PDT_R(0.0) ? c->cfg.Td_max : PDT_REAL_MAX;
}

/* Clamped to the caller's bounds: exp(log(Td + c0)) - c0 rounds, and a
 * fixed dead time's gene spans 1e-4 (gene_bounds), which maps to up to
 * 1e-4 (Td + c0) above Td. */
pdt_real_t pdt_ident_td_of_gene(const pdt_ident_t *c, pdt_real_t g)
{
    const pdt_real_t hi = td_upper(c);
    pdt_real_t Td = pdt_exp(g) - c->td_offset;
    Td = Td > c->cfg.Td_min ? Td : c->cfg.Td_min;
    return Td < hi ? Td : hi;
}

/* Within a few roundings of a bound. */
static pdt_real_t slack_of(pdt_real_t bound)
{
    return PDT_R(4.0) * PDT_REAL_EPS * bound;
}

pdt_real_t pdt_ident_whole_td(pdt_real_t Td, pdt_real_t Ts, pdt_real_t lo, pdt_real_t hi)
{
    pdt_real_t k = pdt_ident_nearest_whole(Td / Ts);
    if (k * Ts < lo - slack_of(lo)) {
        k += PDT_R(1.0);
    } else if (k * Ts > hi + slack_of(hi)) {
        k -= PDT_R(1.0);
    } else {
        /* Within the bounds already. */
    }
    return k * Ts;
}

bool pdt_ident_whole_between(pdt_real_t Ts, pdt_real_t lo, pdt_real_t hi)
{
    const pdt_real_t Td = pdt_ident_whole_td(lo, Ts, lo, hi);
    return Td >= lo - slack_of(lo) && Td <= hi + slack_of(hi);
}

pdt_real_t pdt_ident_gene_of_td(const pdt_ident_t *c, pdt_real_t Td)
{
    const uint32_t j = c->genes - 1u;
    return pdt_ident_clamp(c, (size_t)j, pdt_log(Td + c->td_offset));
}

pdt_real_t pdt_ident_nearest_whole(pdt_real_t r)
{
    return pdt_floor(r + PDT_R(0.5));
}

pdt_real_t pdt_ident_clamp(const pdt_ident_t *c, size_t j, pdt_real_t x)
{
    return x < c->lo[j] ? c->lo[j] : (x > c->hi[j] ? c->hi[j] : x);
}

pdt_real_t pdt_ident_distance(const pdt_ident_t *c, const pdt_real_t *x, const pdt_real_t *y)
{
    pdt_real_t d2 = PDT_R(0.0);
    for (uint32_t j = 0; j < c->genes; j++) {
        pdt_real_t d = (x[j] - y[j]) / (c->hi[j] - c->lo[j]);
        d2 += d * d;
    }
    return pdt_sqrt(d2);
}

/* A FOPDT's time constant, within the caller's bounds: exp(log(tau_max))
 * rounds above tau_max by up to a few ulps of the log (1.3e-6 of it at
 * 1e30 in float). */
static pdt_real_t tau_of_gene(const pdt_ident_t *c, pdt_real_t g)
{
    const pdt_real_t tau = pdt_exp(g);
    if (c->cfg.tau_min == PDT_R(0.0) && c->cfg.tau_max == PDT_R(0.0)) {
        return tau;
    }
    return tau < c->cfg.tau_min ? c->cfg.tau_min : (tau > c->cfg.tau_max ? c->cfg.tau_max : tau);
}

pdt_real_t pdt_ident_lags_unit(const pdt_ident_t *c, pdt_real_t a, pdt_real_t b)
{
    return b + a / (c->cfg.Ts * (pdt_real_t)c->data.n);
}

void pdt_ident_shape(const pdt_ident_t *c, const pdt_real_t *g, pdt_model_t *m)
{
    pdt_real_t Td = pdt_ident_td_of_gene(c, g[c->genes - 1u]);
    if (c->cfg.delay_mode == PDT_DELAY_INTEGER) {
        Td = pdt_ident_whole_td(Td, c->cfg.Ts, c->cfg.Td_min, td_upper(c));
    }
    /* The genes by the lag count: one lag, log tau; two, log(1/a) and the
     * damping gene (gene_bounds, pdt_ident.c). */
    pdt_model_view_t v = {
        pdt_model_kind_lags(c->cfg.model), PDT_R(1.0), PDT_R(0.0), PDT_R(0.0), PDT_R(0.0), Td};
    if (v.lags == 1u) {
        v.tau = tau_of_gene(c, g[0]);
    } else {
        pdt_real_t a = pdt_exp(-g[0]);
        pdt_real_t h = PDT_R(0.5) * a * g[1] * g[1] / c->cfg.zeta_min;
        v.a = a;
        v.b = h * h;
        v.K = pdt_ident_lags_unit(c, v.a, v.b);
    }
    pdt_model_from_view(c->cfg.model, &v, m);
}

/* K times the shape's static gain scale num / den. Where num / den falls
 * below the normal range (a SOPDT shape whose b is tiny beside its
 * numerator) it keeps a few digits only, and the bound with them: then
 * the quotient is formed 2^64 times larger, and the product scaled back,
 * exactly unless it is itself below the normal range. */
static pdt_real_t gain_bound(pdt_real_t K, pdt_real_t num, pdt_real_t den)
{
    const pdt_real_t q = num / den;
    if (!(pdt_fabs(q) < PDT_REAL_MIN_NORMAL)) {
        return K * q;
    }
    const pdt_real_t up = PDT_R(18446744073709551616.0); /* 2^64 */
    return (K * ((num * up) / den)) / up;
}

void pdt_ident_gain_bounds(const pdt_ident_t *c, const pdt_model_t *shape, pdt_real_t *lo,
                           pdt_real_t *hi)
{
    if (c->cfg.K_min == PDT_R(0.0) && c->cfg.K_max == PDT_R(0.0)) {
        *lo = PDT_R(0.0);
        *hi = PDT_R(0.0);
        return;
    }
    pdt_real_t num, den;
    pdt_model_static_gain_ratio(shape, &num, &den);
    /* The model's gain parameter at the bounds (a SOPDT's k = K b, or
     * K a where it integrates; a FOPDT's K itself): where neither bound
     * reaches the normal range, the model cannot hold a gain within them
     * to the real type's precision (a subnormal k rounds by parts in 10^5
     * and more, or to 0). An empty interval: the cost refuses the shape. */
    const pdt_real_t reach = pdt_fabs(c->cfg.K_min) > pdt_fabs(c->cfg.K_max)
                                 ? pdt_fabs(c->cfg.K_min)
                                 : pdt_fabs(c->cfg.K_max);
    if (!(reach * pdt_fabs(num) >= PDT_REAL_MIN_NORMAL)) {
        *lo = PDT_R(1.0);
        *hi = PDT_R(-1.0);
        return;
    }
    *lo = gain_bound(c->cfg.K_min, num, den);
    *hi = gain_bound(c->cfg.K_max, num, den);
    if (*lo == PDT_R(0.0) && *hi == PDT_R(0.0)) {
        /* Bounds the shape's gain unit scales below the real type's range
         * (a SOPDT whose b underflows): 0, 0 would tell the cost there is
         * no bound at all. An empty interval instead: the cost refuses the
         * shape, as no gain within the bounds can be represented on it. */
        *lo = PDT_R(1.0);
        *hi = PDT_R(-1.0);
    }
}

/* The search's best follows the candidates. */
static void track_best(pdt_ident_t *c, const pdt_real_t *g, const pdt_cost_profile_t *pr)
{
    pdt_ident_best_t *best = &c->best;
    if (pr->ncost < best->cost) {
        best->cost = pr->ncost;
        best->gain = pr->gain;
        best->offset = pr->offset;
        for (uint32_t j = 0; j < c->genes; j++) {
            best->genes[j] = g[j];
        }
    }
}

static void take(const pdt_cost_profile_t *pr, bool ok, pdt_real_t *cost, pdt_real_t *gain,
                 pdt_real_t *offset)
{
    ok = ok && pr->ncost == pr->ncost;
    *cost = ok ? pr->ncost : PDT_REAL_MAX;
    *gain = ok ? pr->gain : PDT_R(0.0);
    *offset = ok ? pr->offset : PDT_R(0.0);
}

/* The best so far is the reference fit of the cost's one pass. Shapes
 * carry their gain unit (pdt_ident_shape), so the best's gain multiplier
 * suits every shape of the model. */
void pdt_ident_evaluate(pdt_ident_t *c, const pdt_real_t *g, pdt_real_t *cost, pdt_real_t *gain,
                        pdt_real_t *offset)
{
    pdt_model_t shape;
    pdt_cost_profile_t pr;
    pdt_real_t glo, ghi;
    const pdt_cost_hint_t hint = {c->best.gain, c->best.offset, c->best.cost};
    pdt_ident_shape(c, g, &shape);
    pdt_ident_gain_bounds(c, &shape, &glo, &ghi);
    pdt_ident_counted(c, 1u, c->cost.n);
    const bool ok = pdt_ident_profile(c, &shape, glo, ghi, &hint, &pr) == PDT_OK;
    take(&pr, ok, cost, gain, offset);
    if (ok) {
        track_best(c, g, &pr);
    }
}

void pdt_ident_evaluate_many(pdt_ident_t *c, const pdt_real_t *g, uint32_t count, pdt_real_t *cost,
                             pdt_real_t *gain, pdt_real_t *offset)
{
    pdt_model_t shapes[PDT_COST_MANY] = {{0}};
    pdt_real_t glo[PDT_COST_MANY] = {PDT_R(0.0)}, ghi[PDT_COST_MANY] = {PDT_R(0.0)};
    pdt_cost_profile_t pr[PDT_COST_MANY];
    const pdt_cost_hint_t hint = {c->best.gain, c->best.offset, c->best.cost};
    const uint32_t G = c->genes;
    for (uint32_t i = 0; i < count; i++) {
        pdt_ident_shape(c, &g[i * G], &shapes[i]);
        pdt_ident_gain_bounds(c, &shapes[i], &glo[i], &ghi[i]);
    }
    if (pdt_ident_profile_many(c, shapes, (size_t)count, glo, ghi, &hint, pr) != PDT_OK) {
        /* One shape the cost refuses: each on its own, as the single
         * evaluation scores it. */
        for (uint32_t i = 0; i < count; i++) {
            const bool ok =
                pdt_ident_profile(c, &shapes[i], glo[i], ghi[i], &hint, &pr[i]) == PDT_OK;
            take(&pr[i], ok, &cost[i], &gain[i], &offset[i]);
            if (!ok) {
                pr[i].ncost = PDT_REAL_MAX;
            }
        }
    } else {
        for (uint32_t i = 0; i < count; i++) {
            take(&pr[i], true, &cost[i], &gain[i], &offset[i]);
        }
    }
    pdt_ident_counted(c, count, c->cost.n);
    for (uint32_t i = 0; i < count; i++) {
        if (cost[i] < PDT_REAL_MAX) {
            track_best(c, &g[i * G], &pr[i]);
        }
    }
}

bool pdt_ident_shift_ok(const pdt_ident_t *c)
{
    return c->cfg.more_count == 0u && !pdt_cost_extra_on(&c->cost);
}

bool pdt_ident_evaluate_shift(pdt_ident_t *c, const pdt_real_t *g, const size_t *delay,
                              uint32_t count, bool fresh, pdt_real_t *cost, pdt_real_t *gain,
                              pdt_real_t *offset)
{
    pdt_model_t shape;
    pdt_cost_profile_t pr[PDT_COST_MANY];
    pdt_real_t glo, ghi;
    const pdt_cost_hint_t hint = {c->best.gain, c->best.offset, c->best.cost};
    if (count == 0u || count > PDT_COST_MANY || !pdt_ident_shift_ok(c)) {
        return false;
    }
    /* The response first: the later groups of this shape read it whatever
     * becomes of this one. The shape's parameters are every genome's; its
     * dead time, the first's, plays no part. */
    pdt_ident_shape(c, g, &shape);
    if (fresh && pdt_cost_response(&c->cost, &shape, c->scratch) != PDT_OK) {
        return false;
    }
    pdt_ident_gain_bounds(c, &shape, &glo, &ghi);
    if (pdt_cost_profile_shift(&c->cost, &shape, c->scratch, delay, (size_t)count, glo, ghi, &hint,
                               pr) != PDT_OK) {
        return false;
    }
    pdt_ident_counted(c, count, c->cost.n);
    for (uint32_t i = 0; i < count; i++) {
        take(&pr[i], true, &cost[i], &gain[i], &offset[i]);
        if (cost[i] < PDT_REAL_MAX) {
            track_best(c, &g[i * c->genes], &pr[i]);
        }
    }
    return true;
}
