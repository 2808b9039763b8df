/*
 * The CONTROL weighting's band, between its two GA runs: the first runs on
 * the time cost; from its model, the band up to half the phase crossover
 * (the whole spectrum if it has none below the Nyquist frequency, at least
 * one bin), Cf scaled by the bins' share, and the population scored again
 * on the criterion. The crossover bounds the bandwidth any controller can
 * reach; half of it covers the closed-loop band of the usual tuning rules.
 */
#include "pdt_ident_priv.h"
#include "pdt_internal.h"
#include "pdt_model_priv.h"

pdt_ident_outcome_t pdt_ident_band_start(pdt_ident_t *c)
{
    pdt_model_t m;
    pdt_ident_shape(c, c->best.genes, &m);
    const pdt_real_t Ts = c->cfg.Ts;
    const size_t nf = c->cost.nf, nb = nf / 2u;
    pdt_real_t f = PDT_R(0.5) * pdt_model_phase_crossover(&m) / (PDT_R(2.0) * PDT_PI);
    pdt_real_t f_nyq = PDT_R(0.5) / Ts, f_bin = PDT_R(1.0) / ((pdt_real_t)nf * Ts);
    if (!(f > PDT_R(0.0)) || f > f_nyq) {
        f = f_nyq;
    }
    f = f < f_bin ? f_bin : f;
    /* The ratio in reals first: at the ends of the real range (a bin width
     * that underflows, a Nyquist frequency that overflows) it is infinite
     * or NaN, which no integer holds; the whole spectrum then. */
    const pdt_real_t ratio = f / f_bin;
    size_t bins = (ratio < (pdt_real_t)nb) ? (size_t)ratio : nb;
    bins = bins < 1u ? 1u : bins;
    pdt_cost_config_t cc = c->cost.cfg;
    pdt_cost_t nc;
    cc.kind = c->cfg.cost;
    cc.y0 += c->best.offset;
    cc.weight = PDT_WEIGHT_BAND;
    cc.f_lo = PDT_R(0.0);
    cc.f_hi = f;
    cc.phi_f = c->cfg.phi_f * (pdt_real_t)nb / (pdt_real_t)bins;
    /* The same record, sizes and workspace as init, which checked them:
     * this cannot fail; if it did, the search would go on with the time
     * cost and f_band stay 0. */
    if (pdt_cost_init(&nc, &cc, c->data.u, c->data.y, c->data.n, c->cost_work, c->cost_work_len) ==
        PDT_OK) {
        c->cost = nc;
        c->f_band = f;
    }
    c->best.cost = PDT_REAL_MAX;
    c->ga.best_history = PDT_REAL_MAX;
    c->ga.stall = 0u;
    c->ga.next = 0u;
    return OUT_DONE;
}
