/*
 * The identification's local refinement: Nelder-Mead by reverse
 * communication (a run says which point it needs, then takes its cost),
 * from the best of up to three niches of the final population, then a
 * polish of the best point. The niche runs go side by side, one point of
 * each in one pass over the record (pdt_ident_evaluate_many): on the host
 * three candidates in vector lanes cost about what one costs alone.
 */
#include "pdt_ident_priv.h"
#include "pdt_internal.h"

enum { NM_VERTEX = 1, NM_REFLECT, NM_EXPAND, NM_CONTRACT, NM_SHRINK, NM_END };

/* The first simplex's size and the stopping size, in normalised gene
 * units. */
#define NM_STEP PDT_R(0.05)
#define NM_XTOL PDT_R(1e-5)

/* The whole record's polish after searches on a coarse record starts
 * near its optimum: its first simplex is a fifth of the refinement's. */
#define NM_STEP_WHOLE PDT_R(0.01)

/* Most refinement starts (niches refined). */
#define NM_STARTS 3u

/* Niche run k (0 to 2). */
static pdt_ident_simplex_t *run_of(pdt_ident_refine_t *nm, uint32_t k)
{
    return k == 0u ? &nm->run0 : &nm->late.more[k - 1u];
}

static const pdt_ident_simplex_t *run_at(const pdt_ident_refine_t *nm, uint32_t k)
{
    return k == 0u ? &nm->run0 : &nm->late.more[k - 1u];
}

static pdt_real_t step_of(const pdt_ident_t *c)
{
    return c->coarse.whole ? NM_STEP_WHOLE : NM_STEP;
}

/* COMBINED: the spectra re-centred on the output level the model
 * estimated, one more preparation of the cost in its own workspace. */
pdt_ident_outcome_t pdt_ident_refine_recentre(pdt_ident_t *c)
{
    pdt_cost_config_t cc = c->cost.cfg;
    pdt_cost_t nc;
    cc.y0 += c->best.offset;
    if (pdt_cost_init(&nc, &cc, c->data.u, c->data.y, c->data.n, c->cost_work, c->cost_work_len) ==
        PDT_OK) {
        c->cost = nc;
    }
    return OUT_DONE;
}

/* Starting points of the refinement: the best individual, then the best of
 * each other niche (farther than twice the sharing radius from every start
 * so far), up to NM_STARTS, unless the GA ended with its niches resolved.
 * A GA that ends with its best in a wrong basin (e.g. a SOPDT whose second
 * lag has collapsed into the dead time) usually still holds the right
 * basin in another niche: sharing kept it alive. */
static void refine_starts(pdt_ident_t *c)
{
    pdt_ident_refine_t *nm = &c->nm;
    const pdt_ident_ga_t *ga = &c->ga;
    const uint32_t P = c->cfg.population, G = c->genes;
    const pdt_real_t radius = PDT_R(2.0) * c->cfg.sigma_share;
    for (uint32_t j = 0; j < G; j++) {
        nm->starts[0][j] = c->best.genes[j];
    }
    nm->nstarts = 1u;
    /* A population that has resolved its niches has no other: what lies
     * beyond the radius is this generation's mutants, points at random
     * that a simplex would only spend the budget on. */
    while (nm->nstarts < NM_STARTS && !pdt_ident_ga_resolved(c)) {
        size_t chosen = (size_t)P;
        for (size_t i = 0; i < P; i++) {
            bool distinct = ga->pop_cost[i] < PDT_REAL_MAX;
            for (uint32_t s = 0; s < nm->nstarts && distinct; s++) {
                distinct = pdt_ident_distance(c, &ga->pop[i * G], nm->starts[s]) > radius;
            }
            if (distinct && (chosen == P || ga->pop_cost[i] < ga->pop_cost[chosen])) {
                chosen = i;
            }
        }
        if (chosen == P) {
            break;
        }
        for (uint32_t j = 0; j < G; j++) {
            nm->starts[nm->nstarts][j] = ga->pop[chosen * G + j];
        }
        nm->nstarts++;
    }
    nm->start_i = 0u;
}

/* A simplex about x0, within budget. */
static void simplex_start(const pdt_ident_t *c, pdt_ident_simplex_t *sx, const pdt_real_t *x0,
                          uint32_t budget)
{
    const size_t G = (size_t)c->genes;
    for (size_t i = 0; i <= G; i++) {
        for (size_t j = 0; j < G; j++) {
            sx->x[i][j] = x0[j];
        }
        if (i > 0u) {
            size_t j = i - 1u;
            pdt_real_t step = step_of(c) * (c->hi[j] - c->lo[j]);
            pdt_real_t x = x0[j] + step;
            if (x > c->hi[j]) {
                x = x0[j] - step;
            }
            sx->x[i][j] = pdt_ident_clamp(c, j, x);
        }
    }
    sx->state = NM_VERTEX;
    sx->index = 0u;
    sx->budget = budget;
}

/* The niche runs, side by side: they share half of what the refinement
 * has. A last run then polishes the best point found with all that is
 * left (start_i == nstarts): a restarted simplex also escapes the
 * premature collapse Nelder-Mead is prone to. */
static void niches_start(pdt_ident_t *c)
{
    pdt_ident_refine_t *nm = &c->nm;
    const uint32_t G = c->genes;
    const uint32_t left = pdt_ident_left(c);
    /* Fewer starts when half the budget cannot give each a whole simplex;
     * the first always fits (refine_evaluations >= genes + 1). */
    const uint32_t per = (left / 2u) / (G + 1u);
    if (nm->nstarts > per) {
        nm->nstarts = per > 0u ? per : 1u;
    }
    const uint32_t share = (left / 2u) / nm->nstarts;
    uint32_t budget = share > G + 1u ? share : G + 1u;
    budget = budget < left ? budget : left;
    for (uint32_t k = 0; k < nm->nstarts; k++) {
        simplex_start(c, run_of(nm, k), nm->starts[k], budget);
    }
    nm->start_i = 0u;
    nm->next = 0u;
}

/* A simplex given less than this many of its own sizes has no room to
 * move: the polish then keeps nothing back for the probe. */
#define NM_ROOM 4u

/* The polish of the best with what is left, in run0; a polish of the
 * dead-time profile's but for the dead-time probe's share. Its budget is
 * the refinement's alone, from a point far from the searches' answer (or
 * half of it across a kink), and on a long record a Nelder-Mead that
 * used it all left the answer unprobed, 2 % above the optimum. The
 * searches' own polishes take everything: kept back there too, the probe's
 * share cost a benchmark seed 0.4 % of cost and its error target. */
static void polish_start(pdt_ident_t *c)
{
    pdt_ident_refine_t *nm = &c->nm;
    const uint32_t left = pdt_ident_left(c);
    const uint32_t keep = nm->keep_probe ? pdt_ident_probe_reserve(c) : 0u;
    const uint32_t room = NM_ROOM * (c->genes + 1u);
    nm->start_i = nm->nstarts;
    simplex_start(c, &nm->run0, c->best.genes, left >= keep + room ? left - keep : left);
}

/* The refinement from the starts chosen. The cost scale may have changed
 * (re-centred spectra): the best is tracked afresh; the first start
 * re-evaluates it, so nothing is lost. */
static void refine_run(pdt_ident_t *c)
{
    c->best.cost = PDT_REAL_MAX;
    c->nm.near = false;
    niches_start(c);
}

pdt_ident_outcome_t pdt_ident_refine_begin(pdt_ident_t *c)
{
    refine_starts(c);
    refine_run(c);
    return OUT_DONE;
}

static void nm_order(pdt_ident_simplex_t *sx, size_t G)
{
    /* Insertion sort of G + 1 <= 4 vertices by cost. */
    for (size_t i = 1; i <= G; i++) {
        for (size_t k = i; k > 0u && sx->f[k] < sx->f[k - 1u]; k--) {
            pdt_real_t tf = sx->f[k];
            sx->f[k] = sx->f[k - 1u];
            sx->f[k - 1u] = tf;
            for (size_t j = 0; j < G; j++) {
                pdt_real_t t = sx->x[k][j];
                sx->x[k][j] = sx->x[k - 1u][j];
                sx->x[k - 1u][j] = t;
            }
        }
    }
}

/* Point = centroid of the best G vertices + coef (centroid - worst). */
static void nm_point(const pdt_ident_t *c, const pdt_ident_simplex_t *sx, pdt_real_t coef,
                     pdt_real_t *out)
{
    const size_t G = (size_t)c->genes;
    for (size_t j = 0; j < G; j++) {
        pdt_real_t cen = PDT_R(0.0);
        for (size_t i = 0; i < G; i++) {
            cen += sx->x[i][j];
        }
        cen /= (pdt_real_t)G;
        out[j] = pdt_ident_clamp(c, j, cen + coef * (cen - sx->x[G][j]));
    }
}

static bool nm_converged(const pdt_ident_t *c, const pdt_ident_simplex_t *sx)
{
    const size_t G = (size_t)c->genes;
    pdt_real_t size = PDT_R(0.0);
    for (size_t i = 1; i <= G; i++) {
        for (size_t j = 0; j < G; j++) {
            pdt_real_t d = pdt_fabs(sx->x[i][j] - sx->x[0][j]) / (c->hi[j] - c->lo[j]);
            size = d > size ? d : size;
        }
    }
    return size < NM_XTOL;
}

static void nm_replace_worst(pdt_ident_simplex_t *sx, size_t G, const pdt_real_t *x, pdt_real_t f)
{
    for (size_t j = 0; j < G; j++) {
        sx->x[G][j] = x[j];
    }
    sx->f[G] = f;
}

/* Sets up the next trial after the simplex changed; NM_END when done. */
static void nm_next_iteration(const pdt_ident_t *c, pdt_ident_simplex_t *sx)
{
    nm_order(sx, (size_t)c->genes);
    if (sx->budget == 0u || nm_converged(c, sx)) {
        sx->state = NM_END;
        return;
    }
    nm_point(c, sx, PDT_R(1.0), sx->trial);
    sx->state = NM_REFLECT;
}

/* The point a run evaluates next. */
static const pdt_real_t *nm_pending(const pdt_ident_simplex_t *sx)
{
    switch (sx->state) {
    case NM_REFLECT:
        return sx->trial;
    case NM_EXPAND:
    case NM_CONTRACT:
        return sx->trial2;
    default: /* NM_VERTEX, NM_SHRINK */
        return sx->x[sx->index];
    }
}

/* A run takes the cost f of its pending point. */
static void nm_take(const pdt_ident_t *c, pdt_ident_simplex_t *sx, pdt_real_t f)
{
    const uint32_t G = c->genes;
    switch (sx->state) {
    case NM_VERTEX:
    case NM_SHRINK:
        sx->f[sx->index] = f;
        sx->index++;
        if (sx->index > G) {
            nm_next_iteration(c, sx);
        }
        break;
    case NM_REFLECT:
        sx->ftrial = f;
        if (f < sx->f[0]) {
            nm_point(c, sx, PDT_R(2.0), sx->trial2);
            sx->state = NM_EXPAND;
        } else if (f < sx->f[G - 1u]) {
            nm_replace_worst(sx, (size_t)G, sx->trial, f);
            nm_next_iteration(c, sx);
        } else {
            /* Contract outside when the reflection beat the worst, inside
             * otherwise. */
            nm_point(c, sx, f < sx->f[G] ? PDT_R(0.5) : PDT_R(-0.5), sx->trial2);
            sx->state = NM_CONTRACT;
        }
        break;
    case NM_EXPAND:
        if (f < sx->ftrial) {
            nm_replace_worst(sx, (size_t)G, sx->trial2, f);
        } else {
            nm_replace_worst(sx, (size_t)G, sx->trial, sx->ftrial);
        }
        nm_next_iteration(c, sx);
        break;
    case NM_CONTRACT:
        if (f < sx->ftrial && f < sx->f[G]) {
            nm_replace_worst(sx, (size_t)G, sx->trial2, f);
            nm_next_iteration(c, sx);
        } else {
            for (uint32_t i = 1; i <= G; i++) {
                for (uint32_t j = 0; j < G; j++) {
                    sx->x[i][j] = sx->x[0][j] + PDT_R(0.5) * (sx->x[i][j] - sx->x[0][j]);
                }
            }
            sx->state = NM_SHRINK;
            sx->index = 1u;
        }
        break;
    default:
        sx->state = NM_END;
        break;
    }
    if (sx->budget > 0u) {
        sx->budget--;
    }
    if (sx->budget == 0u && sx->state != NM_END && (sx->state != NM_VERTEX || sx->index > G)) {
        sx->state = NM_END;
    }
}

/* The niche runs whose points the next step evaluates: up to
 * PDT_VECTOR_LANES running ones from run `next` on, in turn. Fixed by the
 * runs' states alone, so the answer does not depend on how the work is
 * split into calls. */
static uint32_t niche_group(const pdt_ident_t *c, uint32_t *which)
{
    const pdt_ident_refine_t *nm = &c->nm;
    uint32_t count = 0u;
    for (uint32_t i = 0; i < nm->nstarts && count < (uint32_t)PDT_VECTOR_LANES; i++) {
        const uint32_t k = (nm->next + i) % nm->nstarts;
        if (run_at(nm, k)->state != NM_END) {
            which[count] = k;
            count++;
        }
    }
    return count;
}

uint32_t pdt_ident_refine_group(const pdt_ident_t *c)
{
    uint32_t which[3];
    if (c->nm.start_i >= c->nm.nstarts) {
        return 1u;
    }
    const uint32_t count = niche_group(c, which);
    return count > 0u ? count : 1u;
}

/* One evaluation of each niche run of the group, in one pass over the
 * record where the build has vector lanes. */
static void niches_step(pdt_ident_t *c)
{
    pdt_ident_refine_t *nm = &c->nm;
    const uint32_t G = c->genes;
    uint32_t which[3];
    pdt_real_t pts[3u * 3u] = {PDT_R(0.0)};
    pdt_real_t cost[3], gain[3], offset[3];
    const uint32_t count = niche_group(c, which);
    for (uint32_t i = 0; i < count; i++) {
        const pdt_real_t *x = nm_pending(run_of(nm, which[i]));
        for (uint32_t j = 0; j < G; j++) {
            pts[i * G + j] = x[j];
        }
    }
    if (count == 0u) {
        return;
    }
    if (count == 1u) {
        pdt_ident_evaluate(c, pts, cost, gain, offset);
    } else {
        pdt_ident_evaluate_many(c, pts, count, cost, gain, offset);
    }
    for (uint32_t i = 0; i < count; i++) {
        nm_take(c, run_of(nm, which[i]), cost[i]);
    }
    nm->next = (which[count - 1u] + 1u) % nm->nstarts;
}

static bool niches_running(const pdt_ident_t *c)
{
    for (uint32_t k = 0; k < c->nm.nstarts; k++) {
        if (run_at(&c->nm, k)->state != NM_END) {
            return true;
        }
    }
    return false;
}

pdt_ident_outcome_t pdt_ident_refine_from(pdt_ident_t *c)
{
    for (uint32_t j = 0; j < c->genes; j++) {
        c->nm.starts[0][j] = c->start[j];
    }
    c->nm.nstarts = 1u;
    refine_run(c);
    return OUT_DONE;
}

/* One evaluation (a group of the niche runs); when they end, the polish of
 * the best (start_i == nstarts) if a whole simplex still fits (the Newton
 * polish with the output error), else the refinement's end. */
pdt_ident_outcome_t pdt_ident_refine_step(pdt_ident_t *c)
{
    pdt_ident_refine_t *nm = &c->nm;
    if (nm->start_i < nm->nstarts) {
        niches_step(c);
        if (niches_running(c)) {
            return OUT_AGAIN;
        }
        if (pdt_ident_left(c) >= c->genes + 1u) {
            if (c->cfg.cost == PDT_COST_SIMULATION) {
                /* The output error is smooth enough for Newton steps
                 * (pdt_ident_polish.c), which hand over to Nelder-Mead
                 * where it is not. */
                nm->start_i = nm->nstarts;
                return OUT_POLISH;
            }
            polish_start(c);
            return OUT_AGAIN;
        }
        return OUT_DONE;
    }
    pdt_ident_simplex_t *sx = &nm->run0;
    pdt_real_t f, gain, offset;
    pdt_ident_evaluate(c, nm_pending(sx), &f, &gain, &offset);
    nm_take(c, sx, f);
    return sx->state == NM_END ? OUT_DONE : OUT_AGAIN;
}

pdt_ident_outcome_t pdt_ident_refine_nm_best(pdt_ident_t *c)
{
    pdt_ident_refine_t *nm = &c->nm;
    nm->nstarts = 0u;
    if (pdt_ident_left(c) < c->genes + 1u) {
        return OUT_SKIPPED;
    }
    polish_start(c);
    return OUT_DONE;
}
