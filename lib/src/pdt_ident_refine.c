/*
 * The identification's local refinement: Nelder-Mead by reverse
 * communication (propose a point, take its cost), from the best of up to
 * three niches of the final population, then a polish of the best point.
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

static pdt_real_t step_of(const pdt_ident_t *c)
{
    return c->coarse.stage == 2u ? NM_STEP_WHOLE : NM_STEP;
}

/* Evaluations the running search may still use before its late reserve. */
static uint32_t left_of(const pdt_ident_t *c)
{
    const uint32_t left = c->vote.budget - pdt_ident_late_reserve(&c->cfg);
    const uint32_t used = pdt_ident_used(c);
    return left > used ? left - used : 0u;
}

/* COMBINED: the spectra re-centred on the output level the model
 * estimated, one more preparation of the cost in its own workspace. */
void pdt_ident_refine_recentre(pdt_ident_t *c)
{
    pdt_cost_config_t cc = c->cost.cfg;
    pdt_cost_t nc;
    cc.y0 += c->best.offset;
    if (pdt_cost_init(&nc, &cc, c->data.u, c->data.y, c->data.n, c->cost_work, c->cost_work_len) ==
        PDT_OK) {
        c->cost = nc;
    }
    c->phase = PH_REFINE_START;
}

/* Starting points of the refinement: the best individual, then the best of
 * each other niche (farther than twice the sharing radius from every start
 * so far), up to NM_STARTS. A GA that ends with its best in a wrong basin
 * (e.g. a SOPDT whose second lag has collapsed into the dead time) usually
 * still holds the right basin in another niche: sharing kept it alive. */
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
    while (nm->nstarts < NM_STARTS) {
        size_t chosen = P;
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

/* A Nelder-Mead run from starts[start_i]. The niche runs share half of
 * what the refinement has; a last run then polishes the best point found
 * with all that is left (start_i == nstarts): a restarted simplex also
 * escapes the premature collapse Nelder-Mead is prone to. */
static void nm_start(pdt_ident_t *c)
{
    pdt_ident_refine_t *nm = &c->nm;
    const size_t G = c->genes;
    const pdt_real_t *x0 = nm->start_i < nm->nstarts ? nm->starts[nm->start_i] : c->best.genes;
    for (size_t i = 0; i <= G; i++) {
        for (size_t j = 0; j < G; j++) {
            nm->x[i][j] = x0[j];
        }
        if (i > 0u) {
            size_t j = i - 1u;
            pdt_real_t step = step_of(c) * (c->hi[j] - c->lo[j]);
            pdt_real_t x = x0[j] + step;
            if (x > c->hi[j]) {
                x = x0[j] - step;
            }
            nm->x[i][j] = pdt_ident_clamp(c, j, x);
        }
    }
    nm->state = NM_VERTEX;
    nm->index = 0u;
    const uint32_t left = left_of(c);
    if (nm->start_i == 0u) {
        /* Fewer starts when half the budget cannot give each a whole
         * simplex; the first always fits (refine_evaluations >= genes + 1). */
        uint32_t per = (left / 2u) / (uint32_t)(G + 1u);
        if (nm->nstarts > per) {
            nm->nstarts = per > 0u ? per : 1u;
        }
        nm->half = left / 2u;
    }
    if (nm->start_i < nm->nstarts) {
        uint32_t share = nm->half / nm->nstarts;
        nm->budget = share > G + 1u ? share : (uint32_t)(G + 1u);
        nm->budget = nm->budget < left ? nm->budget : left;
    } else {
        nm->budget = left;
    }
}

/* The cost scale may have changed (re-centred spectra): the best is
 * tracked afresh; the first start re-evaluates the GA's best, so nothing
 * is lost. */
void pdt_ident_refine_begin(pdt_ident_t *c)
{
    c->best.cost = PDT_REAL_MAX;
    refine_starts(c);
    nm_start(c);
    c->phase = PH_REFINE;
}

static void nm_order(pdt_ident_refine_t *nm, size_t G)
{
    /* Insertion sort of G + 1 <= 4 vertices by cost. */
    for (size_t i = 1; i <= G; i++) {
        for (size_t k = i; k > 0u && nm->f[k] < nm->f[k - 1u]; k--) {
            pdt_real_t tf = nm->f[k];
            nm->f[k] = nm->f[k - 1u];
            nm->f[k - 1u] = tf;
            for (size_t j = 0; j < G; j++) {
                pdt_real_t t = nm->x[k][j];
                nm->x[k][j] = nm->x[k - 1u][j];
                nm->x[k - 1u][j] = t;
            }
        }
    }
}

/* Point = centroid of the best G vertices + coef (centroid - worst). */
static void nm_point(const pdt_ident_t *c, pdt_real_t coef, pdt_real_t *out)
{
    const pdt_ident_refine_t *nm = &c->nm;
    const size_t G = c->genes;
    for (size_t j = 0; j < G; j++) {
        pdt_real_t cen = PDT_R(0.0);
        for (size_t i = 0; i < G; i++) {
            cen += nm->x[i][j];
        }
        cen /= (pdt_real_t)G;
        out[j] = pdt_ident_clamp(c, j, cen + coef * (cen - nm->x[G][j]));
    }
}

static bool nm_converged(const pdt_ident_t *c)
{
    const pdt_ident_refine_t *nm = &c->nm;
    const size_t G = c->genes;
    pdt_real_t size = PDT_R(0.0);
    for (size_t i = 1; i <= G; i++) {
        for (size_t j = 0; j < G; j++) {
            pdt_real_t d = pdt_fabs(nm->x[i][j] - nm->x[0][j]) / (c->hi[j] - c->lo[j]);
            size = d > size ? d : size;
        }
    }
    return size < NM_XTOL;
}

static void nm_replace_worst(pdt_ident_refine_t *nm, size_t G, const pdt_real_t *x, pdt_real_t f)
{
    for (size_t j = 0; j < G; j++) {
        nm->x[G][j] = x[j];
    }
    nm->f[G] = f;
}

/* Sets up the next trial after the simplex changed; NM_END when done. */
static void nm_next_iteration(pdt_ident_t *c)
{
    pdt_ident_refine_t *nm = &c->nm;
    nm_order(nm, c->genes);
    if (nm->budget == 0u || nm_converged(c)) {
        nm->state = NM_END;
        return;
    }
    nm_point(c, PDT_R(1.0), nm->trial);
    nm->state = NM_REFLECT;
}

/* One Nelder-Mead evaluation. */
static void nm_advance(pdt_ident_t *c)
{
    pdt_ident_refine_t *nm = &c->nm;
    const uint32_t G = c->genes;
    pdt_real_t f, gain, offset;
    switch (nm->state) {
    case NM_VERTEX:
    case NM_SHRINK:
        pdt_ident_evaluate(c, nm->x[nm->index], &f, &gain, &offset);
        nm->f[nm->index] = f;
        nm->index++;
        if (nm->index > G) {
            nm_next_iteration(c);
        }
        break;
    case NM_REFLECT:
        pdt_ident_evaluate(c, nm->trial, &f, &gain, &offset);
        nm->ftrial = f;
        if (f < nm->f[0]) {
            nm_point(c, PDT_R(2.0), nm->trial2);
            nm->state = NM_EXPAND;
        } else if (f < nm->f[G - 1u]) {
            nm_replace_worst(nm, G, nm->trial, f);
            nm_next_iteration(c);
        } else {
            /* Contract outside when the reflection beat the worst, inside
             * otherwise. */
            nm_point(c, f < nm->f[G] ? PDT_R(0.5) : PDT_R(-0.5), nm->trial2);
            nm->state = NM_CONTRACT;
        }
        break;
    case NM_EXPAND:
        pdt_ident_evaluate(c, nm->trial2, &f, &gain, &offset);
        if (f < nm->ftrial) {
            nm_replace_worst(nm, G, nm->trial2, f);
        } else {
            nm_replace_worst(nm, G, nm->trial, nm->ftrial);
        }
        nm_next_iteration(c);
        break;
    case NM_CONTRACT:
        pdt_ident_evaluate(c, nm->trial2, &f, &gain, &offset);
        if (f < nm->ftrial && f < nm->f[G]) {
            nm_replace_worst(nm, G, nm->trial2, f);
            nm_next_iteration(c);
        } else {
            for (uint32_t i = 1; i <= G; i++) {
                for (uint32_t j = 0; j < G; j++) {
                    nm->x[i][j] = nm->x[0][j] + PDT_R(0.5) * (nm->x[i][j] - nm->x[0][j]);
                }
            }
            nm->state = NM_SHRINK;
            nm->index = 1u;
        }
        break;
    default:
        nm->state = NM_END;
        break;
    }
    if (nm->budget > 0u) {
        nm->budget--;
    }
    if (nm->budget == 0u && nm->state != NM_END && (nm->state != NM_VERTEX || nm->index > G)) {
        nm->state = NM_END;
    }
}

/* One evaluation; when a run ends, the next niche, then the polish of the
 * best (start_i == nstarts) if a whole simplex still fits, then the
 * frequency criterion's dead-time scan or the answer. */
void pdt_ident_refine_step(pdt_ident_t *c)
{
    pdt_ident_refine_t *nm = &c->nm;
    nm_advance(c);
    if (nm->state != NM_END) {
        return;
    }
    if (nm->start_i < nm->nstarts) {
        const uint32_t left = left_of(c);
        nm->start_i++;
        if (left >= c->genes + 1u) {
            nm_start(c);
            return;
        }
    }
    pdt_ident_refine_end(c);
}

void pdt_ident_refine_end(pdt_ident_t *c)
{
    if (c->cfg.cost == PDT_COST_FREQUENCY) {
        pdt_ident_scan_start(c);
    } else {
        c->phase = PH_FINISH;
    }
}

void pdt_ident_refine_polish(pdt_ident_t *c, uint32_t budget)
{
    /* The polish of the best (start_i == nstarts) within budget: the
     * running search's budget is set so that left_of gives it. */
    c->vote.base = c->evaluations;
    c->vote.budget = budget + pdt_ident_late_reserve(&c->cfg);
    pdt_ident_polish_begin(c);
}

void pdt_ident_refine_nm_best(pdt_ident_t *c)
{
    pdt_ident_refine_t *nm = &c->nm;
    nm->nstarts = 0u;
    nm->start_i = 0u;
    if (left_of(c) < c->genes + 1u) {
        pdt_ident_refine_end(c);
        return;
    }
    nm_start(c);
    c->phase = PH_REFINE;
}
