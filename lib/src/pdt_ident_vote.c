/*
 * The end of a search and of the identification: the model in engineering
 * units with its operating point and fit, then the agreement of the
 * independent searches: the answer is the best, confirmed by another
 * search in its basin, flagged where the searches could not settle it.
 */
#include "pdt_fisher.h"
#include "pdt_ident_priv.h"
#include "pdt_internal.h"

/* A different structure this close (relative) is an ambiguity. */
#define AMBIGUOUS_RTOL PDT_R(0.05)
/* 99 % quantile of chi-square with one degree of freedom. */
#define CHI2_1_99      PDT_R(6.635)
/* Normalised costs closer than this are the real type's rounding, not the
 * data's (float: an RMS of about 1e-4 of the record's range): a noise-free
 * integrator's fit is not beaten by a lag that fits its rounding. */
#define COST_FLOOR     (PDT_REAL_EPS / PDT_R(8.0))
/* The answer of all searches: the least cost; confirmed by another search
 * in its basin, flagged otherwise, the runner-up basin's cost ratio. The
 * profile's answer confirms one in its basin, and stands on its own where
 * it is the least: the profile saw the whole dead-time range, and its
 * point lay below everything near the searches' answer. */
pdt_ident_outcome_t pdt_ident_conclude(pdt_ident_t *c)
{
    const uint32_t best = pdt_ident_vote_best(c);
    const pdt_real_t cb = c->vote.cost[best];
    bool confirmed = pdt_ident_vote_searches(c) < 2u || best + 1u == c->vote.profiled;
    uint32_t flags = 0u;
    pdt_real_t runner = PDT_R(0.0);
    for (uint32_t i = 0u; i < c->vote.done; i++) {
        if (i == best) {
            continue;
        }
        const bool same = pdt_ident_same_structure(&c->vote.found[i], &c->vote.found[best]);
        if (pdt_ident_vote_same_basin(c, i, best)) {
            confirmed = true;
            continue;
        }
        if (!same && pdt_ident_cost_close(cb, c->vote.cost[i], AMBIGUOUS_RTOL)) {
            flags |= PDT_IDENT_FLAG_AMBIGUOUS;
        }
        const pdt_real_t ratio = cb > PDT_R(0.0) ? c->vote.cost[i] / cb : PDT_REAL_MAX;
        if (runner == PDT_R(0.0) || ratio < runner) {
            runner = ratio;
        }
    }
    if (!confirmed) {
        flags |= PDT_IDENT_FLAG_UNCONFIRMED;
    }
    c->model = c->vote.found[best];
    c->y0 = c->vote.y0[best];
    c->fit = c->vote.fit[best];
    c->best.cost = cb;
    c->runner_up = runner;
    for (uint32_t j = 0; j < c->genes; j++) {
        c->best.genes[j] = c->vote.genes[best][j];
    }
    c->flags = flags | pdt_ident_bound_flags(c);
    return OUT_DONE;
}

/* A search ended: keep what it found, then another search (OUT_SEARCH) or
 * the answer (OUT_DONE). The second always runs; the third only when the
 * first two disagree. */
pdt_ident_outcome_t pdt_ident_search_end(pdt_ident_t *c)
{
    const uint32_t k = c->vote.done;
    c->vote.found[k] = c->model;
    c->vote.cost[k] = c->best.cost;
    c->vote.y0[k] = c->y0;
    c->vote.fit[k] = c->fit;
    for (uint32_t j = 0; j < c->genes; j++) {
        c->vote.genes[k][j] = c->best.genes[j];
    }
    c->vote.done = k + 1u;
    bool agreed = false;
    for (uint32_t i = 0u; i < k; i++) {
        agreed = agreed || pdt_ident_vote_same_basin(c, i, k);
    }
    return (c->vote.done < c->vote.searches && (c->vote.done < 2u || !agreed)) ? OUT_SEARCH
                                                                               : OUT_DONE;
}

/* The running search's answer: the model in engineering units, its
 * operating point and its fit. */
pdt_ident_outcome_t pdt_ident_finish(pdt_ident_t *c)
{
    pdt_model_t m;
    pdt_ident_best_model(c, &m);
    if (c->cfg.integrating && pdt_model_kind_integrates(m.kind) && !pdt_model_integrates(&m)) {
        /* A lag a hundred records long may not be told from an integrator
         * in this record: then report the integrator (b = 0) rather than a
         * DC gain the data do not determine. Told apart means the lag's
         * cost is lower by more than chance explains: n ln(C_int / C_lag)
         * above the 99 % quantile of chi-square with one degree of freedom
         * (the one parameter b), the likelihood-ratio test, and by more
         * than the real type's rounding (COST_FLOOR). Reporting the
         * integrator whatever the costs left the answer 1 % above the
         * optimum on 9 of 24000 records of the certainty battery. */
        pdt_model_view_t v;
        pdt_model_view(&m, &v);
        pdt_real_t a = v.a, b = v.b, disc = a * a - PDT_R(4.0) * b;
        pdt_real_t T = c->cfg.Ts * (pdt_real_t)c->data.n;
        if (disc >= PDT_R(0.0) && PDT_R(2.0) * b * PDT_R(100.0) * T < a + pdt_sqrt(disc)) {
            pdt_cost_profile_t pr;
            pdt_model_t shape;
            pdt_real_t glo, ghi;
            v.b = PDT_R(0.0);
            v.K = pdt_ident_lags_unit(c, v.a, v.b);
            pdt_model_from_view(m.kind, &v, &shape);
            pdt_ident_gain_bounds(c, &shape, &glo, &ghi);
            pdt_ident_counted(c, 1u, c->cost.n);
            /* Gain and offset solved again for the integrator (the
             * frequency criterion keeps its gain: its sign came from the
             * dead-time scan). */
            if (c->cfg.cost == PDT_COST_FREQUENCY) {
                glo = c->best.gain;
                ghi = c->best.gain;
            }
            if (pdt_ident_profile(c, &shape, glo, ghi, NULL, &pr) == PDT_OK &&
                !(pr.ncost >
                  c->best.cost * pdt_exp(CHI2_1_99 / (pdt_real_t)c->cost.n) + COST_FLOOR)) {
                v.K *= pr.gain;
                pdt_model_from_view(m.kind, &v, &m);
                c->best.gain = pr.gain;
                c->best.cost = pr.ncost;
                c->best.offset = (c->cfg.cost == PDT_COST_FREQUENCY) ? c->best.offset : pr.offset;
            }
        }
    }
    c->model = m;
    c->y0 = c->cost.cfg.y0 + c->best.offset;
    if (pdt_cost_fit(&c->cost, &m, c->best.offset, c->scratch, &c->fit) != PDT_OK) {
        c->fit = PDT_R(0.0);
    }
    pdt_ident_extra_finish(c, &m);
    return OUT_DONE;
}

/* The covariance lives in the result's type: its size must be the Fisher
 * module's. */
typedef char std_fits_fisher[(PDT_IDENT_MAX_PARAMS == PDT_FISHER_MAX) ? 1 : -1];

/* The checks of pdt_ident_uncertainty; *before: the input before the
 * record (u0 when given, else the first sample). */
static pdt_status_t uncertainty_check(const pdt_model_t *m, const pdt_ident_data_t *data,
                                      pdt_real_t Ts, pdt_real_t y0, const pdt_real_t *u0,
                                      const pdt_ident_std_t *out, pdt_real_t *before)
{
    if (m == NULL || data == NULL || data->u == NULL || data->y == NULL || out == NULL ||
        pdt_model_check(m) != PDT_OK || !pdt_finite(Ts) || !(Ts > PDT_R(0.0)) || !pdt_finite(y0)) {
        return PDT_ERR_ARG;
    }
    if (data->n < PDT_MIN_SAMPLES) {
        return PDT_ERR_TOO_SHORT;
    }
    bool moves = false;
    for (size_t k = 0; k < data->n; k++) {
        if (!pdt_finite(data->u[k]) || !pdt_finite(data->y[k])) {
            return PDT_ERR_NONFINITE;
        }
        moves = moves || data->u[k] != data->u[0];
    }
    *before = (u0 != NULL) ? *u0 : data->u[0];
    if (!moves && *before == data->u[0]) {
        return PDT_ERR_NO_EXCITATION;
    }
    return PDT_OK;
}

/* The covariance from the Fisher information F and its sums fs over n
 * samples: with the answer of ctx (not NULL) and parameters fitted beside
 * the model's (the free response, the drift; docs/field-data.md), the
 * covariance is conditional on them at their estimates, and the
 * residual's variance is that of the residual with them over n less them
 * too. */
static void uncertainty_end(pdt_fisher_matrix_t F, pdt_fisher_sums_t *fs, size_t n,
                            const pdt_ident_t *ctx, pdt_ident_std_t *out)
{
    pdt_ident_std_t r = {0};
    r.count = fs->np;
    size_t dof_n = n;
    const uint32_t nu = (ctx != NULL) ? pdt_ident_nuisance(ctx) : 0u;
    if (nu > 0u && n > (size_t)nu + (size_t)fs->np) {
        fs->sse = ctx->extra[3];
        dof_n -= (size_t)nu;
    }
    pdt_fisher_covariance(F, fs->np, dof_n, fs->sse, pdt_fisher_inflation(fs), r.std, r.cov);
    *out = r;
}

/* pdt_ident_uncertainty, with the residual's sum of squares and its
 * autocorrelation's inflation (pdt_fisher_inflation) into *fs_out, and
 * the answer of ctx (not NULL) as uncertainty_end takes it. */
static pdt_status_t uncertainty(const pdt_model_t *m, const pdt_ident_data_t *data, pdt_real_t Ts,
                                pdt_real_t y0, const pdt_real_t *u0, const pdt_ident_t *ctx,
                                pdt_ident_std_t *out, pdt_fisher_sums_t *fs_out)
{
    pdt_real_t before = PDT_R(0.0);
    pdt_status_t st = uncertainty_check(m, data, Ts, y0, u0, out, &before);
    if (st != PDT_OK) {
        return st;
    }
    pdt_fisher_matrix_t F;
    st = pdt_fisher_sum(m, Ts, data->u, data->y, data->n, y0, before, F, fs_out);
    if (st != PDT_OK) {
        return st;
    }
    uncertainty_end(F, fs_out, data->n, ctx, out);
    return PDT_OK;
}

pdt_status_t pdt_ident_uncertainty(const pdt_model_t *m, const pdt_ident_data_t *data,
                                   pdt_real_t Ts, pdt_real_t y0, pdt_ident_std_t *out)
{
    pdt_fisher_sums_t fs;
    return uncertainty(m, data, Ts, y0, NULL, NULL, out, &fs);
}

/* The mean of x[0..n-1] (about x[0], so that a large level does not
 * cost precision). */
static pdt_real_t mean_of(const pdt_real_t *x, size_t n)
{
    pdt_real_t s = PDT_R(0.0);
    for (size_t k = 0; k < n; k++) {
        s += x[k] - x[0];
    }
    return s / (pdt_real_t)n + x[0];
}

/* The autocorrelations of x (mean m) at lags l .. l + 3, over its
 * variance v, into r (0 where v is not positive). One pass serves the
 * four lags; each lag's products are still summed in the order of k. */
static void autocorr4(const pdt_real_t *x, size_t n, pdt_real_t m, pdt_real_t v, size_t l,
                      pdt_real_t r[4])
{
    /* Four sums in registers (no array indexed at run time). */
    pdt_real_t s0 = PDT_R(0.0), s1 = PDT_R(0.0), s2 = PDT_R(0.0), s3 = PDT_R(0.0);
    /* The samples before all four lags have begun: lag l + i from
     * k = l + i on. */
    for (size_t k = l; k < l + 3u && k < n; k++) {
        const pdt_real_t xk = x[k] - m;
        s0 += xk * (x[k - l] - m);
        if (k >= l + 1u) {
            s1 += xk * (x[k - l - 1u] - m);
        }
        if (k >= l + 2u) {
            s2 += xk * (x[k - l - 2u] - m);
        }
    }
    for (size_t k = l + 3u; k < n; k++) {
        const pdt_real_t xk = x[k] - m;
        s0 += xk * (x[k - l] - m);
        s1 += xk * (x[k - l - 1u] - m);
        s2 += xk * (x[k - l - 2u] - m);
        s3 += xk * (x[k - l - 3u] - m);
    }
    r[0] = v > PDT_R(0.0) ? s0 / v : PDT_R(0.0);
    r[1] = v > PDT_R(0.0) ? s1 / v : PDT_R(0.0);
    r[2] = v > PDT_R(0.0) ? s2 / v : PDT_R(0.0);
    r[3] = v > PDT_R(0.0) ? s3 / v : PDT_R(0.0);
}

static pdt_real_t sum_sq(const pdt_real_t *x, size_t n, pdt_real_t m)
{
    pdt_real_t s = PDT_R(0.0);
    for (size_t k = 0; k < n; k++) {
        s += (x[k] - m) * (x[k] - m);
    }
    return s;
}

/* The model against the null model (docs/field-data.md, "No model
 * without evidence"): the likelihood-ratio statistic (n / c)
 * ln(SS_null / SS_model), where c = 1 + 2 sum_{l=1..L}
 * rho_x(l) rho_y(l) (at least 1) is Bartlett's factor of the variance of
 * a correlation between the model's output x and the output y, both
 * autocorrelated: a slowly wandering output is not taken as evidence for
 * a slow model; L = EVIDENCE_LAGS, as for the uncertainty's inflation.
 * NO_RELATION below EVIDENCE_MIN or a fit below
 * FIT_FLOOR. x: the model's simulated output (n reals). */
#define EVIDENCE_MIN  ((pdt_real_t)PDT_IDENT_EVIDENCE_MIN)
#define EVIDENCE_LAGS 20u
#define FIT_FLOOR     ((pdt_real_t)PDT_IDENT_FIT_FLOOR)

/* The evidence's sums, from one step to the next. */
typedef struct {
    pdt_real_t mx, my;  /* the means of x and y */
    pdt_real_t vx, ss0; /* their sums of squares about them */
    pdt_real_t c;       /* Bartlett's factor so far */
    size_t lag;         /* the next group's first lag; past EVIDENCE_LAGS: none */
} evidence_run_t;

/* The means and the sums of squares: four passes. No lags where the
 * statistic does not need them (it is then the real type's largest). */
static void evidence_begin(evidence_run_t *e, const pdt_real_t *x, const pdt_real_t *y, size_t n,
                           pdt_real_t sse)
{
    e->mx = mean_of(x, n);
    e->my = mean_of(y, n);
    e->vx = sum_sq(x, n, e->mx);
    e->ss0 = sum_sq(y, n, e->my);
    e->c = PDT_R(1.0);
    e->lag = 1u;
    if (!(sse > PDT_R(0.0)) || !(e->ss0 > PDT_R(0.0))) {
        e->lag = EVIDENCE_LAGS + 1u;
    }
}

/* The next four lags of Bartlett's factor: two passes. True when no lag
 * is left. */
static bool evidence_lags(evidence_run_t *e, const pdt_real_t *x, const pdt_real_t *y, size_t n)
{
    const size_t l = e->lag;
    if (l <= EVIDENCE_LAGS && l < n) {
        pdt_real_t rx[4], ry[4];
        autocorr4(x, n, e->mx, e->vx, l, rx);
        autocorr4(y, n, e->my, e->ss0, l, ry);
        for (size_t i = 0u; i < 4u && l + i <= EVIDENCE_LAGS && l + i < n; i++) {
            e->c += PDT_R(2.0) * rx[i] * ry[i];
        }
        e->lag = l + 4u;
    }
    return !(e->lag <= EVIDENCE_LAGS && e->lag < n);
}

static pdt_real_t evidence_end(const evidence_run_t *e, size_t n, pdt_real_t sse)
{
    if (!(sse > PDT_R(0.0)) || !(e->ss0 > PDT_R(0.0))) {
        return PDT_REAL_MAX;
    }
    const pdt_real_t c = e->c > PDT_R(1.0) ? e->c : PDT_R(1.0);
    return (pdt_real_t)n / c * (pdt_log(e->ss0) - pdt_log(sse));
}

/* The answer's evidence begun: the model's simulated output into the
 * scratch (kept there for the tests of the initial state) and the sums;
 * false where the model cannot be simulated (no evidence). */
static bool evidence_start(pdt_ident_t *c, evidence_run_t *e, const pdt_fisher_sums_t *fs)
{
    pdt_discrete_t d;
    c->evidence = PDT_R(0.0);
    if (pdt_discrete_init(&c->model, c->cfg.Ts, &d) != PDT_OK ||
        !pdt_ident_simulate(c, &d, c->scratch)) {
        return false;
    }
    evidence_begin(e, c->scratch, c->data.y, c->data.n, fs->sse);
    return true;
}

/* The statistic from the sums (or 0, none), and NO_RELATION. */
static void evidence_set(pdt_ident_t *c, const evidence_run_t *e, const pdt_fisher_sums_t *fs)
{
    c->evidence = (e != NULL) ? evidence_end(e, c->data.n, fs->sse) : PDT_R(0.0);
    if (!(c->evidence >= EVIDENCE_MIN) || !(c->fit >= FIT_FLOOR)) {
        c->flags |= PDT_IDENT_FLAG_NO_RELATION;
    }
}

/* The whole evidence in one step. */
static void evidence(pdt_ident_t *c, const pdt_fisher_sums_t *fs)
{
    evidence_run_t e;
    if (!evidence_start(c, &e, fs)) {
        evidence_set(c, NULL, fs);
        return;
    }
    while (!evidence_lags(&e, c->scratch, c->data.y, c->data.n)) {
        /* the next four lags */
    }
    evidence_set(c, &e, fs);
}

/* Whether the tests of the initial state apply: AUTO (or its refit) and
 * an evidence, which means the scratch holds the simulated output. */
static bool state_tests_due(const pdt_ident_t *c)
{
    return (c->cfg.initial == PDT_IDENT_INITIAL_AUTO || c->auto_state) && c->evidence > PDT_R(0.0);
}

/* The tests of the initial state on the answer's residual. */
static void state_tests(pdt_ident_t *c)
{
    /* The residual in place of the simulated output. */
    const size_t n = c->data.n;
    for (size_t k = 0; k < n; k++) {
        c->scratch[k] = c->data.y[k] - c->scratch[k];
    }
    /* Where the trend test fails, AUTO answers it with the state
     * estimated (PH_SCREEN begins that identification); the flag stays
     * where it cannot. Only the answer's own free response taking up its
     * residual (the second test) is what a start mid-transient and a
     * structure that does not fit the plant (a lag fitted to an
     * integrator's record from rest) leave alike: a refit would invent a
     * state and hide the misfit, so that answer is flagged and not
     * refitted. */
    const bool want = pdt_ident_want_state(c);
    const bool trend = pdt_ident_mid_transient(c->scratch, c->data.y, n);
    const bool shape = !trend && want && pdt_ident_state_matters(c);
    if (trend && want) {
        c->auto_state = true;
    }
    if ((trend && !want) || shape) {
        c->flags |= PDT_IDENT_FLAG_MID_TRANSIENT;
    }
}

/* The answer's uncertainty in steps (PH_STD, PH_STD_PASS, PH_EVIDENCE,
 * PH_EVIDENCE_LAGS, PH_STATE_TESTS): the Fisher pass in blocks of
 * PDT_FISHER_BLOCK samples, as the validation's, then the evidence (its
 * sums, then four lags of its factor a step), then the tests of the
 * initial state where they apply. Its state lies in the workspace's
 * population part, which nothing reads once the searches are done (a
 * restart carves it again); where a small population leaves that part
 * too short, the whole pass is one step. The same sums either way. */
typedef struct std_run {
    pdt_fisher_sums_t fs; /* first: the evidence reads it, scratch not */
    pdt_fisher_run_t R;
    pdt_fisher_matrix_t F;
    evidence_run_t e;
} std_run_t;

/* The state in the population part, its first address aligned for it;
 * NULL where it does not fit before the scratch. */
static std_run_t *std_run_of(const pdt_ident_t *c)
{
    const ptrdiff_t reals = c->scratch - c->ga.pop;
    return (std_run_t *)pdt_aligned_state(c->ga.pop, (size_t)reals * sizeof(pdt_real_t),
                                          sizeof(std_run_t));
}

/* The uncertainty that could not be computed: count 0, no evidence. */
static pdt_ident_outcome_t std_failed(pdt_ident_t *c)
{
    c->evidence = PDT_R(0.0);
    c->flags |= (c->fit >= FIT_FLOOR) ? 0u : PDT_IDENT_FLAG_NO_RELATION;
    return OUT_FAILED;
}

pdt_ident_outcome_t pdt_ident_std(pdt_ident_t *c)
{
    c->std = (pdt_ident_std_t){0};
    std_run_t *const run = std_run_of(c);
    if (pdt_ident_multi(&c->cfg)) {
        /* Several records: no uncertainty, their joint evidence, in one
         * step (docs/several-records.md). */
        pdt_ident_multi_std(c);
        return OUT_DONE;
    }
    if (run == NULL) {
        pdt_fisher_sums_t fs;
        if (uncertainty(&c->model, &c->data, c->cfg.Ts, c->y0, &c->cost.cfg.u0, c, &c->std, &fs) ==
            PDT_OK) {
            evidence(c, &fs);
            if (state_tests_due(c)) {
                state_tests(c);
            }
            return OUT_DONE;
        }
        return std_failed(c);
    }
    pdt_real_t before = PDT_R(0.0);
    pdt_status_t st =
        uncertainty_check(&c->model, &c->data, c->cfg.Ts, c->y0, &c->cost.cfg.u0, &c->std, &before);
    if (st == PDT_OK) {
        st = pdt_fisher_begin(&run->R, &c->model, c->cfg.Ts, c->data.u, c->data.y, c->data.n, c->y0,
                              before, run->F);
    }
    if (st != PDT_OK) {
        return std_failed(c);
    }
    return OUT_BEGUN;
}

pdt_ident_outcome_t pdt_ident_std_pass(pdt_ident_t *c)
{
    std_run_t *const run = std_run_of(c);
    if (!pdt_fisher_block(&run->R)) {
        return OUT_AGAIN;
    }
    if (pdt_fisher_end(&run->R, &run->fs) != PDT_OK) {
        return std_failed(c);
    }
    uncertainty_end(run->F, &run->fs, c->data.n, c, &c->std);
    return OUT_DONE;
}

pdt_ident_outcome_t pdt_ident_std_evidence(pdt_ident_t *c)
{
    std_run_t *const run = std_run_of(c);
    if (!evidence_start(c, &run->e, &run->fs)) {
        evidence_set(c, NULL, &run->fs);
        return OUT_SKIPPED;
    }
    return OUT_BEGUN;
}

pdt_ident_outcome_t pdt_ident_std_lags(pdt_ident_t *c)
{
    std_run_t *const run = std_run_of(c);
    if (!evidence_lags(&run->e, c->scratch, c->data.y, c->data.n)) {
        return OUT_AGAIN;
    }
    evidence_set(c, &run->e, &run->fs);
    return state_tests_due(c) ? OUT_DONE : OUT_SKIPPED;
}

pdt_ident_outcome_t pdt_ident_std_state(pdt_ident_t *c)
{
    state_tests(c);
    return OUT_DONE;
}
