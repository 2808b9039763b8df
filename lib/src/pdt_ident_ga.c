/*
 * The identification's population stage: the paper's real-coded genetic
 * algorithm (binary tournament on shared costs, bounded SBX, polynomial
 * mutation, elitism), one evaluation per call of a stage function.
 */
#include "pdt_ga.h"
#include "pdt_ident_priv.h"
#include "pdt_internal.h"

/* A Latin hypercube start (each gene's range cut into P strata, one
 * individual per stratum, strata paired across genes at random, so the
 * first generation covers every gene's range evenly; the offspring area
 * holds the permutation meanwhile), its random stream the search's own. */
static void ga_start(pdt_ident_t *c)
{
    pdt_ident_ga_t *ga = &c->ga;
    const size_t P = (size_t)c->cfg.population, G = (size_t)c->genes;
    pdt_rng_seed(&ga->rng, c->cfg.seed, 0x5eed5eedu + c->vote.done);
    for (size_t j = 0; j < G; j++) {
        pdt_real_t *perm = ga->off;
        for (size_t i = 0; i < P; i++) {
            perm[i] = (pdt_real_t)i;
        }
        for (size_t i = P - 1u; i > 0u; i--) {
            size_t k = (size_t)pdt_rng_below(&ga->rng, (uint32_t)(i + 1u));
            pdt_real_t t = perm[i];
            perm[i] = perm[k];
            perm[k] = t;
        }
        for (size_t i = 0; i < P; i++) {
            pdt_real_t f = (perm[i] + pdt_rng_uniform(&ga->rng)) / (pdt_real_t)P;
            ga->pop[i * G + j] = c->lo[j] + (c->hi[j] - c->lo[j]) * f;
        }
    }
    ga->next = 0u;
    ga->stall = 0u;
    ga->resolved = 0u;
    ga->best_history = PDT_REAL_MAX;
    c->vote.base = c->evaluations;
    c->best.cost = PDT_REAL_MAX;
    c->nm.keep_probe = false;
}

pdt_ident_outcome_t pdt_ident_ga_begin(pdt_ident_t *c)
{
    ga_start(c);
    /* The CONTROL weighting's first run: on the time cost, to find the
     * band. */
    return pdt_ident_control_band(&c->cfg) ? OUT_TIME : OUT_DONE;
}

/* Generations the population breeds with one niche left before its GA
 * ends: a few, so that a generation's mutants get to seed another niche. */
#define RESOLVED_GENERATIONS 3u

/* The population has resolved its niches: all but an eighth of it (the
 * generation's mutants) lie within `radius` of the search's best, in
 * genes normalised by their ranges as the sharing measures them. What
 * such a population does next is creep down its one basin, the
 * refinement's work, done with a fraction of the evaluations
 * (docs/ident-engine.md). pdt_ident_distance's measure, squared and by
 * the ranges' reciprocals: no division or root per individual, every
 * generation. */
static bool one_niche(const pdt_ident_t *c, pdt_real_t radius)
{
    const pdt_ident_ga_t *ga = &c->ga;
    const uint32_t P = c->cfg.population, G = c->genes;
    const pdt_real_t r2 = radius * radius;
    pdt_real_t inv[3];
    for (uint32_t j = 0; j < G; j++) {
        inv[j] = PDT_R(1.0) / (c->hi[j] - c->lo[j]);
    }
    uint32_t far = 0u;
    for (uint32_t i = 0; i < P && far <= P / 8u; i++) {
        pdt_real_t d2 = PDT_R(0.0);
        for (uint32_t j = 0; j < G; j++) {
            const pdt_real_t d = (ga->pop[(i * G) + j] - c->best.genes[j]) * inv[j];
            d2 += d * d;
        }
        if (!(d2 < r2)) {
            far++;
        }
    }
    return far <= P / 8u;
}

/* After a generation: the stall bookkeeping; another generation, or the
 * population's end. time: the CONTROL weighting's run on the time cost. */
static pdt_ident_outcome_t generation_end(pdt_ident_t *c, bool time)
{
    pdt_ident_ga_t *ga = &c->ga;
    c->generations++;
    if (c->best.cost < ga->best_history * (PDT_R(1.0) - c->cfg.tolerance) ||
        ga->best_history == PDT_REAL_MAX) {
        ga->best_history = c->best.cost;
        ga->stall = 0u;
    } else {
        ga->stall++;
    }
    const bool first_order = pdt_model_kind_lags(c->cfg.model) == 1u;
    /* One niche: under the output error, a FOPDT's population within
     * twice the sharing radius of its best, the distance at which the
     * refinement counts another niche (pdt_ident_refine.c). The dead time
     * is a FOPDT's only source of other basins, and the dead-time
     * profile that follows (output error only) scores every whole sample
     * of it. A SOPDT's shape genes hold basins of their own, close
     * together (an overdamped one that mimics a lag with more dead time),
     * which no later pass looks for, and the other criteria have no
     * profile: there the population must gather within the sharing
     * radius itself. Not in the CONTROL weighting's time-cost stage: the
     * band is read from that stage's best as it stands, with no
     * refinement to finish its creep. */
    const pdt_real_t radius = (first_order && pdt_ident_profiled(&c->cfg))
                                  ? PDT_R(2.0) * c->cfg.sigma_share
                                  : c->cfg.sigma_share;
    ga->resolved = (!time && one_niche(c, radius)) ? ga->resolved + 1u : 0u;
    uint32_t ga_budget =
        c->vote.budget - c->cfg.refine_evaluations - pdt_ident_late_reserve(&c->cfg);
    if (time) {
        /* The time-cost stage of the CONTROL weighting gets half. */
        ga_budget /= 2u;
    }
    /* A FOPDT search after the first ends its GA once, after as many
     * generations as the stall rule waits, its best lies in the basin of
     * the best answer kept: the refinement and the vote that follow
     * settle it (a disagreement still calls a third search). A SOPDT's
     * searches run their course: on its records the early end saved 1 to
     * 3 % and let a second search settle in a dead-time basin a fraction
     * of a sample from the optimum's (docs/ident-engine.md). */
    const bool caught_up = first_order && !pdt_ident_control_band(&c->cfg) &&
                           pdt_ident_used(c) >= c->cfg.stall_generations * c->cfg.population &&
                           pdt_ident_vote_caught_up(c);
    if (!caught_up && ga->resolved < RESOLVED_GENERATIONS && ga->stall < c->cfg.stall_generations &&
        pdt_ident_used(c) + c->cfg.population <= ga_budget) {
        return OUT_GENERATION;
    }
    return OUT_DONE;
}

bool pdt_ident_ga_resolved(const pdt_ident_t *c)
{
    return c->ga.resolved >= RESOLVED_GENERATIONS;
}

pdt_ident_outcome_t pdt_ident_ga_end(const pdt_ident_t *c)
{
    return c->cost.cfg.kind == PDT_COST_COMBINED ? OUT_RECENTRE : OUT_DONE;
}

uint32_t pdt_ident_ga_group(const pdt_ident_t *c)
{
    const uint32_t left = c->cfg.population - c->ga.next;
    return left < PDT_VECTOR_LANES ? left : PDT_VECTOR_LANES;
}

/* count individuals (genes g, one after another) scored, in one pass
 * where the build has vector lanes. */
static void score(pdt_ident_t *c, const pdt_real_t *g, uint32_t count, pdt_real_t *cost,
                  pdt_real_t *gain, pdt_real_t *offset)
{
    if (count == 1u) {
        pdt_ident_evaluate(c, g, cost, gain, offset);
    } else {
        pdt_ident_evaluate_many(c, g, count, cost, gain, offset);
    }
}

/* A group of individuals from index i: one evaluation each. */
static void eval_group(pdt_ident_t *c, pdt_real_t *genes, pdt_real_t *cost, pdt_real_t *gain,
                       pdt_real_t *offset)
{
    const uint32_t i = c->ga.next, count = pdt_ident_ga_group(c);
    score(c, &genes[i * c->genes], count, &cost[i], &gain[i], &offset[i]);
    c->ga.next += count;
}

pdt_ident_outcome_t pdt_ident_ga_eval_parent(pdt_ident_t *c, bool time)
{
    pdt_ident_ga_t *ga = &c->ga;
    eval_group(c, ga->pop, ga->pop_cost, ga->pop_gain, ga->pop_offset);
    if (ga->next == c->cfg.population) {
        return generation_end(c, time);
    }
    return OUT_AGAIN;
}

static size_t pick(const pdt_ident_t *c, pdt_rng_t *r)
{
    uint32_t P = c->cfg.population;
    size_t a = (size_t)pdt_rng_below(r, P);
    size_t b = (size_t)pdt_rng_below(r, P);
    return pdt_ga_tournament(c->ga.shared, a, b, pdt_rng_u32(r) & 1u);
}

/* Whether genes x are genes p, bit for bit. */
static bool same_genes(const pdt_real_t *x, const pdt_real_t *p, size_t G)
{
    size_t j = 0u;
    while (j < G && x[j] == p[j]) {
        j++;
    }
    return j == G;
}

/* Offspring i's score, when it is a copy of parent k or l (neither
 * crossover nor mutation changed any of its genes): the parent's, which
 * its evaluation would only repeat; else NaN, the mark that it is to be
 * scored (a score is never NaN: pdt_ident_evaluate makes it the largest
 * real). */
static void inherit(pdt_ident_ga_t *ga, size_t G, size_t i, size_t k, size_t l)
{
    const pdt_real_t *x = &ga->off[i * G];
    size_t from = k;
    if (!same_genes(x, &ga->pop[k * G], G)) {
        if (!same_genes(x, &ga->pop[l * G], G)) {
            ga->off_cost[i] = (pdt_real_t)NAN;
            return;
        }
        from = l;
    }
    ga->off_cost[i] = ga->pop_cost[from];
    ga->off_gain[i] = ga->pop_gain[from];
    ga->off_offset[i] = ga->pop_offset[from];
}

/* One generation of offspring from the current population. */
pdt_ident_outcome_t pdt_ident_ga_breed(pdt_ident_t *c)
{
    pdt_ident_ga_t *ga = &c->ga;
    const size_t P = (size_t)c->cfg.population, G = (size_t)c->genes;
    pdt_rng_t *r = &ga->rng;
    pdt_real_t pm = c->cfg.p_mutation > PDT_R(0.0) ? c->cfg.p_mutation : PDT_R(1.0) / (pdt_real_t)G;
    pdt_ga_share(ga->pop, P, G, c->lo, c->hi, ga->pop_cost, c->cfg.sigma_share, PDT_R(1.0),
                 ga->shared);
    for (size_t i = 0; i < P; i += 2u) {
        const size_t k = pick(c, r), l = pick(c, r);
        const pdt_real_t *p1 = &ga->pop[k * G];
        const pdt_real_t *p2 = &ga->pop[l * G];
        pdt_real_t *c1 = &ga->off[i * G];
        pdt_real_t *c2 = &ga->off[(i + 1u) * G];
        bool cross = pdt_rng_uniform(r) < c->cfg.p_crossover;
        for (size_t j = 0; j < G; j++) {
            pdt_real_t x1 = p1[j], x2 = p2[j];
            if (cross && pdt_rng_uniform(r) < PDT_R(0.5)) {
                pdt_ga_sbx(p1[j], p2[j], c->lo[j], c->hi[j], c->cfg.eta_c, pdt_rng_uniform(r), &x1,
                           &x2);
                if ((pdt_rng_u32(r) & 1u) != 0u) {
                    pdt_real_t t = x1;
                    x1 = x2;
                    x2 = t;
                }
            }
            if (pdt_rng_uniform(r) < pm) {
                x1 = pdt_ga_mutate(x1, c->lo[j], c->hi[j], c->cfg.eta_m, pdt_rng_uniform(r));
            }
            if (pdt_rng_uniform(r) < pm) {
                x2 = pdt_ga_mutate(x2, c->lo[j], c->hi[j], c->cfg.eta_m, pdt_rng_uniform(r));
            }
            c1[j] = x1;
            c2[j] = x2;
        }
        inherit(ga, G, i, k, l);
        inherit(ga, G, i + 1u, l, k);
    }
    ga->next = 0u;
    return OUT_DONE;
}

/* Elitism: the best `elite` parents replace the worst offspring when better,
 * then the offspring become the population. */
static void survive(pdt_ident_t *c)
{
    pdt_ident_ga_t *ga = &c->ga;
    const size_t P = (size_t)c->cfg.population, G = (size_t)c->genes;
    for (uint32_t e = 0; e < c->cfg.elite; e++) {
        size_t best = 0u, worst = 0u;
        for (size_t i = 1; i < P; i++) {
            if (ga->pop_cost[i] < ga->pop_cost[best]) {
                best = i;
            }
            if (ga->off_cost[i] > ga->off_cost[worst]) {
                worst = i;
            }
        }
        if (!(ga->pop_cost[best] < ga->off_cost[worst])) {
            break;
        }
        for (size_t j = 0; j < G; j++) {
            ga->off[worst * G + j] = ga->pop[best * G + j];
        }
        ga->off_cost[worst] = ga->pop_cost[best];
        ga->off_gain[worst] = ga->pop_gain[best];
        ga->off_offset[worst] = ga->pop_offset[best];
        /* Take the parent out of the next round of this loop. */
        ga->pop_cost[best] = PDT_REAL_MAX;
    }
    for (size_t i = 0; i < P * G; i++) {
        ga->pop[i] = ga->off[i];
    }
    for (size_t i = 0; i < P; i++) {
        ga->pop_cost[i] = ga->off_cost[i];
        ga->pop_gain[i] = ga->off_gain[i];
        ga->pop_offset[i] = ga->off_offset[i];
    }
}

/* A group of offspring: those inherit marked as copies keep their
 * parent's score, counted as evaluations that scored no sample (the
 * budgets, which count evaluations, see the same search); the others
 * are scored together. */
static void eval_offspring_group(pdt_ident_t *c)
{
    pdt_ident_ga_t *ga = &c->ga;
    const uint32_t first = ga->next, count = pdt_ident_ga_group(c), G = c->genes;
    pdt_real_t genes[PDT_COST_MANY * 3u];
    pdt_real_t cost[PDT_COST_MANY], gain[PDT_COST_MANY], offset[PDT_COST_MANY];
    uint32_t which[PDT_COST_MANY];
    uint32_t fresh = 0u;
    for (uint32_t i = first; i < first + count; i++) {
        if (isnan(ga->off_cost[i]) == 0) {
            pdt_ident_counted(c, 1u, 0u);
            continue;
        }
        for (uint32_t j = 0; j < G; j++) {
            genes[(fresh * G) + j] = ga->off[(i * G) + j];
        }
        which[fresh] = i;
        fresh++;
    }
    if (fresh > 0u) {
        score(c, genes, fresh, cost, gain, offset);
    }
    for (uint32_t f = 0; f < fresh; f++) {
        ga->off_cost[which[f]] = cost[f];
        ga->off_gain[which[f]] = gain[f];
        ga->off_offset[which[f]] = offset[f];
    }
    ga->next += count;
}

pdt_ident_outcome_t pdt_ident_ga_eval_offspring(pdt_ident_t *c, bool time)
{
    pdt_ident_ga_t *ga = &c->ga;
    eval_offspring_group(c);
    if (ga->next == c->cfg.population) {
        survive(c);
        return generation_end(c, time);
    }
    return OUT_AGAIN;
}
