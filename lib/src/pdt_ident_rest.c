/*
 * The output offset from the rest window (PDT_IDENT_OFFSET_AUTO). The
 * searches fit the offset with the model. When the record started at rest
 * and the fitted offset lies more than 4.5 standard errors of the
 * window's mean from the window's level, the model used the offset to make
 * up for what it cannot follow (a FOPDT of a higher-order process lowers
 * its gain and its offset together): the answer is then polished with the
 * offset held at the window's level. Where the two agree the fitted offset
 * stays, since it is the more precise of the two (it uses every sample).
 */
#include "pdt_ident_priv.h"
#include "pdt_internal.h"

/* Standard errors of the window's mean the fitted offset may differ by.
 * Noise alone passes 4.5 once in 150 000 records; a FOPDT fitted to a
 * step test of a higher-order plant (Astrom-Hagglund P3, P4, P5) lies 5
 * to 6.5 away. At 3, noise alone moved 22 of 24000 answers of the
 * certainty battery's exact plants off their optimum. */
#define REST_SE PDT_R(4.5)

/* Evaluations the polish may use: the refinement's share, within what is
 * left of the whole budget after the late reserve. */
static uint32_t polish_budget(const pdt_ident_t *c)
{
    const uint32_t reserve = pdt_ident_late_reserve(&c->cfg);
    const uint32_t used = c->evaluations + reserve;
    const uint32_t left = c->cfg.max_evaluations > used ? c->cfg.max_evaluations - used : 0u;
    return left < c->cfg.refine_evaluations ? left : c->cfg.refine_evaluations;
}

pdt_ident_outcome_t pdt_ident_rest_check(const pdt_ident_t *c)
{
    if (c->rest == 0u || polish_budget(c) < c->genes + 1u) {
        return OUT_SKIPPED;
    }
    /* The residual's mean square (output units), over the window's
     * samples: the variance of the window's mean. */
    const pdt_real_t var = pdt_cost_units(&c->cost, c->best.cost) / (pdt_real_t)c->rest;
    const pdt_real_t d = c->y0 - c->cost.cfg.y0;
    return (d * d > REST_SE * REST_SE * var) ? OUT_DONE : OUT_SKIPPED;
}

pdt_ident_outcome_t pdt_ident_rest_start(pdt_ident_t *c)
{
    pdt_cost_config_t cc = c->cost.cfg;
    pdt_cost_t nc;
    cc.estimate_offset = false;
    /* The same record, sizes and workspace as init, which checked them: if
     * the preparation failed all the same, the fitted offset stays. */
    if (pdt_cost_init(&nc, &cc, c->data.u, c->data.y, c->data.n, c->cost_work, c->cost_work_len) !=
        PDT_OK) {
        return OUT_FAILED;
    }
    c->cost = nc;
    c->best.cost = PDT_REAL_MAX;
    c->best.offset = PDT_R(0.0);
    pdt_ident_polish_budget(c, polish_budget(c));
    return OUT_POLISH;
}
