/*
 * The dead-time profile: a global check of the searches' answer. With the
 * gain and the offset in closed form, a model's cost is a function of its
 * shape and its dead time, and its basins are basins of the dead time. A
 * record of much noise under a fast input narrows the right one to a few
 * samples of dead time, so that two searches can both miss it and agree
 * on another: both end where a long lag makes up for no dead time, say.
 * The profile scores every whole sample of the searched dead-time range
 * (every few where the range is long) at a few fixed shapes, and compares
 * the least cost far from the answer's dead time with the least near it.
 * Both are scored at the same coarse shapes, so neither is favoured: a far
 * point below the near ones is a basin the searches did not see, and it
 * is polished as a search's answer is; the vote then takes the lower.
 */
#include "pdt_ident_priv.h"
#include "pdt_internal.h"

/* Shapes at each dead time: FOPDT time constants (SOPDT lags, critically
 * damped) at 1/5 .. 4/5 of the searched range of their gene. One group of
 * the host's vector lanes. */
#define PROFILE_SHAPES 4u
/* Most dead times scored: a longer range is scored every few samples. */
#define PROFILE_POINTS 128u
/* Steps either side of the answer's dead time that are its basin: the
 * grid points that bracket it. A wider window would hold the right basin
 * itself where the answer is a few samples off it. */
#define PROFILE_NEAR   PDT_R(1.0)

/* The grid: whole samples of the searched record from the least dead time
 * up, every `every` of them, at most PROFILE_POINTS. False where the range
 * holds too few to tell near from far. */
static bool grid_of(pdt_ident_t *c)
{
    pdt_ident_profile_t *p = &c->profile;
    const uint32_t dt = c->genes - 1u;
    const pdt_real_t Ts = c->cost.cfg.Ts;
    const pdt_real_t lo = pdt_ident_td_of_gene(c, c->lo[dt]) / Ts;
    const pdt_real_t hi = pdt_ident_td_of_gene(c, c->hi[dt]) / Ts;
    const pdt_real_t first = pdt_floor(lo + PDT_R(0.999));
    if (!(hi - first >= PDT_R(2.0) * PROFILE_NEAR + PDT_R(2.0))) {
        return false;
    }
    /* A range of a third of the record has at most n / 3 samples: the
     * count fits 32 bits whatever the real type. */
    const pdt_real_t span = hi - first;
    const uint32_t count = (uint32_t)span + 1u;
    const uint32_t every = (count + PROFILE_POINTS - 1u) / PROFILE_POINTS;
    p->points = ((count - 1u) / every) + 1u;
    p->td0 = (first > PDT_R(0.0) ? first : PDT_R(0.0)) * Ts;
    p->step = (pdt_real_t)every * Ts;
    return true;
}

bool pdt_ident_profile_begin(pdt_ident_t *c)
{
    pdt_ident_profile_t *p = &c->profile;
    if (p->stage == 2u) {
        /* Its point's polish ended: the last answer kept is the profile's.
         * It only counts in another basin: back in the searches' basin it
         * found nothing they had not, and their answer, polished on the
         * way they took, stands. */
        const uint32_t k = c->vote.done - 1u;
        bool other = true;
        for (uint32_t i = 0u; i < k; i++) {
            other = other && !pdt_ident_vote_same_basin(c, i, k);
        }
        c->vote.done = other ? c->vote.done : k;
        c->vote.profiled = other ? c->vote.done : 0u;
        p->stage = 3u;
        return false;
    }
    if (p->stage != 0u) {
        return false;
    }
    p->stage = 3u;
    /* The output error only: the searches of the other criteria do not
     * vote, and the frequency criterion scans its dead time already. */
    if (c->cfg.cost != PDT_COST_SIMULATION || c->vote.done == 0u || !grid_of(c)) {
        return false;
    }
    const uint32_t scan = p->points * PROFILE_SHAPES;
    const uint32_t need = scan + c->cfg.refine_evaluations + pdt_ident_late_reserve(&c->cfg);
    if (c->evaluations >= c->cfg.max_evaluations ||
        c->cfg.max_evaluations - c->evaluations < need) {
        return false;
    }
    p->stage = 1u;
    p->next = 0u;
    p->td = pdt_ident_td_of_gene(c, c->vote.genes[pdt_ident_vote_best(c)][c->genes - 1u]);
    p->near = PDT_REAL_MAX;
    p->far = PDT_REAL_MAX;
    c->vote.base = c->evaluations;
    c->vote.budget = scan;
    c->phase = PH_PROFILE;
    return true;
}

uint32_t pdt_ident_profile_group(const pdt_ident_t *c)
{
    const uint32_t left = (c->profile.points * PROFILE_SHAPES) - c->profile.next;
    return left < (uint32_t)PDT_VECTOR_LANES ? left : (uint32_t)PDT_VECTOR_LANES;
}

/* Grid point i: shape i % PROFILE_SHAPES at dead time i / PROFILE_SHAPES. */
static pdt_real_t point_of(const pdt_ident_t *c, uint32_t i, pdt_real_t *x)
{
    const pdt_ident_profile_t *p = &c->profile;
    const uint32_t level = (i % PROFILE_SHAPES) + 1u, G = c->genes;
    const uint32_t d = i / PROFILE_SHAPES;
    const pdt_real_t f = (pdt_real_t)level / ((pdt_real_t)PROFILE_SHAPES + PDT_R(1.0));
    x[0] = c->lo[0] + ((c->hi[0] - c->lo[0]) * f);
    if (G == 3u) {
        /* Critical damping (the damping gene's sqrt(zeta_min)). */
        x[1] = pdt_ident_clamp(c, 1u, pdt_sqrt(c->cfg.zeta_min));
    }
    const pdt_real_t Td = p->td0 + (p->step * (pdt_real_t)d);
    x[G - 1u] = pdt_ident_gene_of_td(c, Td);
    return Td;
}

/* The far point polished as a search's answer is, when it lies below the
 * near ones; the vote otherwise. */
static void scan_end(pdt_ident_t *c)
{
    pdt_ident_profile_t *p = &c->profile;
    if (!(p->far < p->near)) {
        p->stage = 3u;
        pdt_ident_conclude(c);
        return;
    }
    p->stage = 2u;
    c->vote.base = c->evaluations;
    c->vote.budget = c->cfg.refine_evaluations + pdt_ident_late_reserve(&c->cfg);
    pdt_ident_refine_from(c, p->far_x);
}

void pdt_ident_profile_step(pdt_ident_t *c)
{
    pdt_ident_profile_t *p = &c->profile;
    const uint32_t G = c->genes;
    const uint32_t count = pdt_ident_profile_group(c);
    pdt_real_t pts[PDT_COST_MANY * 3u];
    pdt_real_t td[PDT_COST_MANY];
    pdt_real_t cost[PDT_COST_MANY], gains[PDT_COST_MANY], offsets[PDT_COST_MANY];
    /* Every point written: the compiler cannot see that count >= 1. */
    for (uint32_t i = 0; i < (PDT_COST_MANY * 3u); i++) {
        pts[i] = PDT_R(0.0);
    }
    for (uint32_t i = 0; i < count; i++) {
        td[i] = point_of(c, p->next + i, &pts[i * G]);
    }
    if (count > 1u) {
        pdt_ident_evaluate_many(c, pts, count, cost, gains, offsets);
    } else {
        pdt_ident_evaluate(c, pts, cost, gains, offsets);
    }
    for (uint32_t i = 0; i < count; i++) {
        const pdt_real_t d = td[i] > p->td ? td[i] - p->td : p->td - td[i];
        if (d <= PROFILE_NEAR * p->step) {
            p->near = cost[i] < p->near ? cost[i] : p->near;
        } else if (cost[i] < p->far) {
            p->far = cost[i];
            for (uint32_t j = 0; j < G; j++) {
                p->far_x[j] = pts[(i * G) + j];
            }
        } else {
            /* Neither the nearest nor the least far. */
        }
    }
    p->next += count;
    if (p->next >= p->points * PROFILE_SHAPES) {
        scan_end(c);
    }
}
