/*
 * The searches' coarse record. A search spends nearly all its evaluations
 * telling basins apart, and a basin is a feature of the record at the
 * scale of the process's time constants, not of its sampling: records are
 * sampled ten to a hundred times faster than the process moves. So the
 * searches run on a record D times coarser (the input's mean over each
 * block of D samples, the output's centred mean at the block's start: the
 * same zero-order-hold model at the period D Ts), and only the answer is
 * polished on the whole record. Two checks keep the coarse record honest:
 * before, the output must keep its shape when seen only every D samples;
 * after, the answer must be slow against D Ts. An answer that fails the
 * second is searched for again on the whole record.
 */
#include "pdt_ident_priv.h"
#include "pdt_internal.h"

/* The output's variance the coarse record may lose (its centred means,
 * joined by straight lines, against the output), noise apart: 0.2 %.
 * docs/ident-engine.md gives the factors that passes on step and relay
 * records; the check of the answer (COARSE_SCALE) catches what it lets
 * through. */
#define COARSE_LOSS  PDT_R(0.002)
/* The answer's time scale must be at least this many coarse periods:
 * below, the block means blur its response. */
#define COARSE_SCALE PDT_R(2.0)
/* Largest automatic decimation. */
#define COARSE_MAX   32u

/* Centred mean of y over [k - h, k + h], clipped to the record. */
static pdt_real_t centred_mean(const pdt_real_t *y, size_t n, size_t k, size_t h)
{
    const size_t a = k > h ? k - h : 0u;
    const size_t b = k + h < n ? k + h : n - 1u;
    pdt_real_t s = PDT_R(0.0);
    for (size_t i = a; i <= b; i++) {
        s += y[i] - y[k];
    }
    const size_t count = b - a + 1u;
    return y[k] + (s / (pdt_real_t)count);
}

/* Whether the output keeps its shape at decimation D: the variance of y
 * about the coarse record's means, joined linearly, is at most
 * COARSE_LOSS of y's variance, both less the noise's. The noise's
 * variance comes from the second differences (6 sigma^2 for white noise;
 * a process sampled this finely adds little to them). */
static bool keeps_shape(const pdt_real_t *y, size_t n, size_t D)
{
    const size_t blocks = n / D;
    const size_t m = blocks * D; /* the samples the coarse record covers */
    /* Sums of squares in units of the output's range: no underflow or
     * overflow at any scale the record has. */
    pdt_real_t lo = y[0], hi = y[0];
    for (size_t i = 0; i < m; i++) {
        lo = y[i] < lo ? y[i] : lo;
        hi = y[i] > hi ? y[i] : hi;
    }
    const pdt_real_t r = PDT_R(1.0) / (hi - lo);
    pdt_real_t mean = PDT_R(0.0), d2 = PDT_R(0.0);
    for (size_t i = 0; i < m; i++) {
        mean += (y[i] - y[0]) * r;
        if (i >= 2u) {
            const pdt_real_t e = ((y[i] - y[i - 1u]) - (y[i - 1u] - y[i - 2u])) * r;
            d2 += e * e;
        }
    }
    mean = mean / (pdt_real_t)m;
    const size_t diffs = m - 2u;
    const pdt_real_t noise = d2 / (PDT_R(6.0) * (pdt_real_t)diffs) * (pdt_real_t)m;
    pdt_real_t var = PDT_R(0.0), lost = PDT_R(0.0);
    pdt_real_t prev = centred_mean(y, n, 0u, D / 2u);
    for (size_t k = 0; k < blocks; k++) {
        /* The line from this block's point to the next one's (the last
         * block holds its level). */
        const size_t next = (k + 1u) * D;
        const pdt_real_t nextv = next < n ? centred_mean(y, n, next, D / 2u) : prev;
        for (size_t j = 0; j < D; j++) {
            const size_t i = k * D + j;
            const pdt_real_t line = prev + (nextv - prev) * (pdt_real_t)j / (pdt_real_t)D;
            const pdt_real_t e = (y[i] - line) * r, d = (y[i] - y[0]) * r - mean;
            lost += e * e;
            var += d * d;
        }
        prev = nextv;
    }
    return var > noise && lost - noise <= COARSE_LOSS * (var - noise);
}

/* PH_SHAPE_BEGIN: 1 where the criterion, the dead-time mode or the budget
 * has no coarse record, the caller's D, or the first to test: n /
 * PDT_IDENT_COARSE_SAMPLES, at most COARSE_MAX. The searches on the
 * coarse record leave the polish its share of the budget: a budget too
 * small for both searches the whole record. */
pdt_ident_outcome_t pdt_ident_coarse_first(pdt_ident_t *c)
{
    const pdt_ident_config_t *cfg = &c->cfg;
    const size_t n = c->data.n;
    const uint32_t each = (cfg->max_evaluations - cfg->refine_evaluations) / c->vote.searches;
    c->coarse.factor = 1u;
    if (cfg->cost != PDT_COST_SIMULATION || cfg->delay_mode != PDT_DELAY_FRACTIONAL ||
        cfg->coarse == 1u || each < pdt_ident_search_need(cfg, cfg->population)) {
        return OUT_SKIPPED;
    }
    if (cfg->coarse != 0u) {
        c->coarse.factor = (n / cfg->coarse >= (size_t)PDT_MIN_SAMPLES) ? cfg->coarse : 1u;
        return OUT_SKIPPED;
    }
    const size_t D = n / PDT_IDENT_COARSE_SAMPLES;
    if (D < 2u) {
        return OUT_SKIPPED;
    }
    c->coarse.factor = (uint32_t)(D < COARSE_MAX ? D : COARSE_MAX);
    return OUT_DONE;
}

/* PH_SHAPE: the largest power-of-two fraction of the first D at which the
 * output keeps its shape, one test a call (each O(n)). */
pdt_ident_outcome_t pdt_ident_coarse_factor(pdt_ident_t *c)
{
    const size_t D = (size_t)c->coarse.factor; /* at most COARSE_MAX */
    if (keeps_shape(c->data.y, c->data.n, D)) {
        return OUT_DONE;
    }
    c->coarse.factor = (uint32_t)(D / 2u >= 2u ? D / 2u : 1u);
    return c->coarse.factor >= 2u ? OUT_AGAIN : OUT_DONE;
}

/* The decimation D and the coarse record of n / D samples in the scratch
 * (u, then y), cc changed to its cost's configuration; 0 when the record
 * is searched whole (cc unchanged). */
static size_t coarse_prepare(pdt_ident_t *c, pdt_cost_config_t *cc)
{
    const size_t D = (size_t)c->coarse.factor; /* PH_SHAPE's, at most n */
    c->coarse.factor = 1u;
    c->coarse.whole = false;
    c->coarse.delay_max = (uint32_t)cc->delay_max;
    if (D < 2u) {
        return 0u;
    }
    /* The coarse record in the scratch (2 n / D <= n reals), until its
     * cost has copied it. */
    const size_t nc = c->data.n / D;
    pdt_real_t *u = c->scratch, *y = c->scratch + nc;
    for (size_t k = 0; k < nc; k++) {
        pdt_real_t s = PDT_R(0.0);
        for (size_t j = 0; j < D; j++) {
            s += c->data.u[(k * D) + j] - c->data.u[k * D];
        }
        u[k] = c->data.u[k * D] + (s / (pdt_real_t)D);
        y[k] = centred_mean(c->data.y, c->data.n, k * D, D / 2u);
    }
    /* The whole record's configuration at the coarse period: the polish
     * gets it back from the coarse cost's copy (Ts, delay_max). */
    cc->Ts = c->cfg.Ts * (pdt_real_t)D;
    cc->delay_max = ((size_t)c->coarse.delay_max / D) + 2u;
    cc->delay_max = cc->delay_max < nc ? cc->delay_max : nc - 1u;
    c->coarse.factor = (uint32_t)D;
    return nc;
}

/* Whether the coarse record's cost was prepared: if not, cc is set back
 * and the whole record is searched. */
static void coarse_begin(pdt_ident_t *c, bool prepared, pdt_cost_config_t *cc)
{
    if (!prepared) {
        /* Searched whole: the configuration back to the whole record's. */
        c->coarse.factor = 1u;
        cc->Ts = c->cfg.Ts;
        cc->delay_max = (size_t)c->coarse.delay_max;
        return;
    }
    c->vote.budget = (c->cfg.max_evaluations - c->cfg.refine_evaluations) / c->vote.searches;
}

void pdt_ident_coarse_start(pdt_ident_t *c)
{
    /* The configuration init prepared the whole record's cost with, from
     * that cost's copy: its delay bound as given, the caller's weights. */
    pdt_cost_config_t cc = c->cost.cfg;
    cc.delay_max = (size_t)c->coarse.delay_max;
    cc.weights = c->cfg.weights;
    /* The coarse cost over the whole one's, in the same workspace (PH_FINE
     * prepares the whole one again). */
    const size_t nc = coarse_prepare(c, &cc);
    if (nc != 0u) {
        const bool ok = pdt_cost_init(&c->cost, &cc, c->scratch, &c->scratch[nc], nc, c->cost_work,
                                      pdt_cost_workspace_size(&cc, nc)) == PDT_OK;
        coarse_begin(c, ok, &cc);
        if (!ok) {
            /* Not a record its cost takes (a block mean left the input
             * still): the whole one, prepared again over what was written. */
            (void)pdt_cost_init(&c->cost, &cc, c->data.u, c->data.y, c->data.n, c->cost_work,
                                c->cost_work_len);
        }
    }
}

pdt_ident_outcome_t pdt_ident_coarse_pending(const pdt_ident_t *c)
{
    return c->cost.n < c->data.n ? OUT_DONE : OUT_SKIPPED;
}

/* The answer's time scale, s: how fast its response moves. A FOPDT's
 * tau; a SOPDT's sum of time constants a / b when overdamped, 1 / wn when
 * underdamped, its lag 1 / a when it integrates. */
static pdt_real_t time_scale(const pdt_model_t *m)
{
    pdt_model_view_t v;
    pdt_model_view(m, &v);
    if (v.lags == 1u) {
        return v.tau;
    }
    const pdt_real_t a = v.a, b = v.b;
    if (!(b > PDT_R(0.0))) {
        return PDT_R(1.0) / a;
    }
    return a * a >= PDT_R(4.0) * b ? a / b : PDT_R(1.0) / pdt_sqrt(b);
}

pdt_ident_outcome_t pdt_ident_coarse_fine(pdt_ident_t *c)
{
    const pdt_real_t period = c->cfg.Ts * (pdt_real_t)c->coarse.factor;
    /* The whole record's cost over the coarse one's, in the same
     * workspace: init prepared it once, so it cannot fail now. */
    pdt_cost_config_t cc = c->cost.cfg;
    cc.Ts = c->cfg.Ts;
    cc.delay_max = (size_t)c->coarse.delay_max;
    if (pdt_cost_init(&c->cost, &cc, c->data.u, c->data.y, c->data.n, c->cost_work,
                      c->cost_work_len) != PDT_OK) {
        /* Should it fail all the same, the coarse answer stands, said to
         * be unconfirmed on the whole record. */
        c->flags |= PDT_IDENT_FLAG_UNCONFIRMED;
        return OUT_FAILED;
    }
    c->best.cost = PDT_REAL_MAX;
    c->best.gain = PDT_R(0.0);
    c->best.offset = PDT_R(0.0);
    const uint32_t left =
        c->cfg.max_evaluations > c->evaluations ? c->cfg.max_evaluations - c->evaluations : 0u;
    const uint64_t need = pdt_ident_search_need(&c->cfg, c->cfg.population);
    if (!(time_scale(&c->model) >= COARSE_SCALE * period)) {
        if (left >= need) {
            /* Too fast for the coarse record: its basins may not be the
             * whole record's. The searches again, on the whole record,
             * with what is left of the budget. */
            uint32_t searches = (uint32_t)(left / need);
            searches = searches < c->vote.searches ? searches : c->vote.searches;
            c->coarse.factor = 1u;
            c->vote.searches = searches;
            c->vote.done = 0u;
            c->vote.profiled = 0u;
            c->vote.budget = left / searches;
            c->flags = 0u;
            c->runner_up = PDT_R(0.0);
            return OUT_SEARCH;
        }
        /* No budget left to search the whole record: the answer is
         * polished, but nothing on the whole record confirmed it. */
        c->flags |= PDT_IDENT_FLAG_UNCONFIRMED;
    }
    c->coarse.whole = true;
    const uint32_t reserve = pdt_ident_late_reserve(&c->cfg);
    const uint32_t room = left > reserve ? left - reserve : 0u;
    const uint32_t budget = room < c->cfg.refine_evaluations ? room : c->cfg.refine_evaluations;
    pdt_ident_polish_budget(c, budget > c->genes + 1u ? budget : c->genes + 1u);
    return OUT_POLISH;
}

pdt_ident_outcome_t pdt_ident_coarse_whole(pdt_ident_t *c)
{
    c->coarse.whole = false;
    c->flags = (c->flags & ~PDT_IDENT_FLAG_AT_BOUND) | pdt_ident_bound_flags(c);
    return OUT_DONE;
}
