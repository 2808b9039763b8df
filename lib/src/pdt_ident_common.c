/*
 * The answers kept (pdt_ident_t.vote) and what the stages ask of them:
 * the best, whether two lie in one basin, whether the running search has
 * caught up with one, whether an answer lies on a bound. Part of the
 * engine's shared part: it calls no stage.
 */
#include "pdt_ident_priv.h"
#include "pdt_internal.h"

/* Costs closer than this (relative) are one basin. */
#define AGREE_RTOL  PDT_R(0.01)
/* Answers this close in normalised genes are one basin whatever their
 * costs (an exact fit's cost is all rounding, its ratios meaningless). */
#define AGREE_GENES PDT_R(0.01)
/* A gene this close to its bound (normalised) lies on it. */
#define BOUND_TOL   PDT_R(1e-3)

/* The same structure: the gain's sign and whether it integrates. */
bool pdt_ident_same_structure(const pdt_model_t *a, const pdt_model_t *b)
{
    if ((pdt_model_gain_numerator(a) < PDT_R(0.0)) != (pdt_model_gain_numerator(b) < PDT_R(0.0))) {
        return false;
    }
    return pdt_model_integrates(a) == pdt_model_integrates(b);
}

/* Cost b within rtol of cost a (normalised costs: the record lies in
 * (-1, 1), so a few ulps of 1 are the floor of an exact fit). */
bool pdt_ident_cost_close(pdt_real_t a, pdt_real_t b, pdt_real_t rtol)
{
    pdt_real_t lo = a < b ? a : b;
    pdt_real_t d = a < b ? b - a : a - b;
    return d <= rtol * lo + PDT_R(64.0) * PDT_REAL_EPS * PDT_REAL_EPS;
}

/* A model m with cost and genes g lies in the basin of answer i: the same
 * structure, and costs within 1 % or genes within AGREE_GENES. */
static bool in_basin_of(const pdt_ident_t *c, uint32_t i, const pdt_model_t *m, pdt_real_t cost,
                        const pdt_real_t *g)
{
    return pdt_ident_same_structure(&c->vote.found[i], m) &&
           (pdt_ident_cost_close(c->vote.cost[i], cost, AGREE_RTOL) ||
            pdt_ident_distance(c, c->vote.genes[i], g) < AGREE_GENES);
}

/* Searches i and j ended in one basin. */
bool pdt_ident_vote_same_basin(const pdt_ident_t *c, uint32_t i, uint32_t j)
{
    return in_basin_of(c, i, &c->vote.found[j], c->vote.cost[j], c->vote.genes[j]);
}

/* The running search's best as a model: the shape's gain unit times the
 * multiplier found. */
void pdt_ident_best_model(const pdt_ident_t *c, pdt_model_t *m)
{
    pdt_ident_shape(c, c->best.genes, m);
    pdt_model_scale_gain(m, c->best.gain);
}

bool pdt_ident_vote_caught_up(const pdt_ident_t *c)
{
    if (c->vote.done == 0u || !(c->best.cost < PDT_REAL_MAX)) {
        return false;
    }
    pdt_model_t m;
    pdt_ident_best_model(c, &m);
    return in_basin_of(c, pdt_ident_vote_best(c), &m, c->best.cost, c->best.genes);
}

static bool on_bound(const pdt_ident_t *c, const pdt_real_t *g)
{
    for (uint32_t j = 0; j < c->genes; j++) {
        const pdt_real_t t = (g[j] - c->lo[j]) / (c->hi[j] - c->lo[j]);
        /* Only the upper bounds: a time constant below a quarter sample
         * (a lag too short to matter, or a SOPDT's second lag vanishing),
         * no dead time and 1/zeta = 0 (an integrator) are answers. */
        if (t > PDT_R(1.0) - BOUND_TOL) {
            return true;
        }
    }
    return false;
}

static bool gain_on_bound(const pdt_ident_t *c, pdt_real_t K)
{
    const pdt_real_t lo = c->cfg.K_min, hi = c->cfg.K_max;
    if (!(hi > lo)) {
        return false;
    }
    const pdt_real_t tol = BOUND_TOL * (hi - lo);
    return K <= lo + tol || K >= hi - tol;
}

uint32_t pdt_ident_vote_best(const pdt_ident_t *c)
{
    uint32_t best = 0u;
    for (uint32_t i = 1u; i < c->vote.done; i++) {
        if (c->vote.cost[i] < c->vote.cost[best]) {
            best = i;
        }
    }
    return best;
}

uint32_t pdt_ident_vote_searches(const pdt_ident_t *c)
{
    return c->vote.done - (c->vote.profiled != 0u ? 1u : 0u);
}

uint32_t pdt_ident_bound_flags(const pdt_ident_t *c)
{
    return (on_bound(c, c->best.genes) || gain_on_bound(c, pdt_model_gain_numerator(&c->model)))
               ? PDT_IDENT_FLAG_AT_BOUND
               : 0u;
}
