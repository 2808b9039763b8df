/*
 * Model validation: residual tests, parameter uncertainty, order choice and
 * the robust sensitivity bound; see pdt_validate.h.
 */
#include "pdt/pdt_validate.h"

#include "pdt/pdt_discrete.h"
#include "pdt_fisher.h"
#include "pdt_internal.h"
#include "pdt_linalg.h"
#include "pdt_model_priv.h"

/* The lags the Fisher pass sums are the whiteness test's. */
typedef char lags_match[(PDT_VALIDATE_LAGS == PDT_FISHER_LAGS) ? 1 : -1];

/* Points of the frequency grid of the robust bound. */
#define VAL_GRID 200u
/* Standard deviations of the confidence region the bound covers: about the
 * 95 % ellipsoid of four parameters (sqrt of chi-square(4) 0.95 = 3.08). */
#define VAL_CHI  PDT_R(3.0)

size_t pdt_validate_workspace_size(size_t n)
{
    return PDT_VALIDATE_WORKSPACE_SIZE(n);
}

/* 99 % quantile of chi-square with nu degrees of freedom (Wilson and
 * Hilferty), a few percent accurate from nu = 5 on. */
static pdt_real_t chi2_99(pdt_real_t nu)
{
    pdt_real_t c = PDT_R(2.0) / (PDT_R(9.0) * nu);
    pdt_real_t t = PDT_R(1.0) - c + PDT_R(2.3263) * pdt_sqrt(c);
    return nu * t * t * t;
}

/* The pieces every call shares: argument checks, the input's deviation
 * and the simulated output in the workspace, the residual after them. */
typedef struct val_ctx {
    const pdt_real_t *y;
    pdt_real_t *du; /* u - u[0] */
    pdt_real_t *ys; /* simulated output */
    pdt_real_t *e;  /* the residual */
    size_t n;
    pdt_real_t y0;
} val_ctx_t;

static pdt_status_t prepare(const pdt_model_t *m, const pdt_ident_data_t *data, pdt_real_t Ts,
                            pdt_real_t y0, void *work, size_t work_len, size_t need, val_ctx_t *c)
{
    if (m == NULL || data == NULL || data->u == NULL || data->y == NULL ||
        pdt_model_check(m) != PDT_OK || !pdt_finite(Ts) || !(Ts > PDT_R(0.0)) || !pdt_finite(y0)) {
        return PDT_ERR_ARG;
    }
    size_t n = data->n;
    if (n < PDT_MIN_SAMPLES || n <= 2u * (PDT_VALIDATE_LAGS + PDT_VALIDATE_FIR)) {
        return PDT_ERR_TOO_SHORT;
    }
    if (work == NULL || work_len < need) {
        return PDT_ERR_NOMEM;
    }
    if (!pdt_aligned(work)) {
        return PDT_ERR_ARG;
    }
    bool moves = false;
    for (size_t k = 0; k < n; k++) {
        if (!pdt_finite(data->u[k]) || !pdt_finite(data->y[k])) {
            return PDT_ERR_NONFINITE;
        }
        moves = moves || data->u[k] != data->u[0];
    }
    if (!moves) {
        return PDT_ERR_NO_EXCITATION;
    }
    pdt_real_t *w = (pdt_real_t *)work;
    c->y = data->y;
    c->n = n;
    c->y0 = y0;
    c->du = w;
    c->ys = w + n;
    c->e = w + 2u * n;
    for (size_t k = 0; k < n; k++) {
        c->du[k] = data->u[k] - data->u[0];
    }
    pdt_discrete_t d;
    if (pdt_discrete_init(m, Ts, &d) != PDT_OK ||
        pdt_discrete_simulate(&d, c->du, n, c->ys) != PDT_OK) {
        return PDT_ERR_ARG;
    }
    for (size_t k = 0; k < n; k++) {
        if (!pdt_finite(c->ys[k])) {
            return PDT_ERR_NONFINITE;
        }
    }
    return PDT_OK;
}

static pdt_real_t gain_of(const pdt_model_t *m)
{
    return pdt_model_gain_numerator(m);
}

/* What the stages after the preparation carry: the result as it is
 * built, the Fisher pass's matrix and sums, the FIR's normal equations. */
typedef struct val_sums {
    pdt_validate_result_t r;
    val_ctx_t c;
    pdt_fisher_matrix_t F;
    pdt_fisher_sums_t fs;
    pdt_real_t A[PDT_VALIDATE_FIR][PDT_VALIDATE_FIR];
    pdt_real_t bv[PDT_VALIDATE_FIR];
    pdt_real_t r0; /* the mean-free residual's sum of squares */
} val_sums_t;

/* After the Fisher pass: the mean-free residual, the whiteness test, the
 * information criteria, the covariance and the FIR's first lag; A and bv
 * zeroed for the FIR's rows. */
static void val_residual(val_sums_t *S)
{
    pdt_validate_result_t *const r = &S->r;
    const val_ctx_t *const c = &S->c;
    const size_t n = c->n;
    const pdt_real_t sse = S->fs.sse;
    const uint32_t np = S->fs.np;

    pdt_real_t *e = c->e;
    pdt_real_t mean = PDT_R(0.0);
    for (size_t k = 0; k < n; k++) {
        e[k] = c->y[k] - c->y0 - c->ys[k];
        mean += e[k];
    }
    mean /= (pdt_real_t)n;
    for (size_t k = 0; k < n; k++) {
        e[k] -= mean;
    }

    pdt_real_t r0 = PDT_R(0.0);
    for (size_t k = 0; k < n; k++) {
        r0 += e[k] * e[k];
    }
    S->r0 = r0;
    /* Whiteness: the residual's autocorrelations at lags 1..LAGS, summed
     * with the Fisher information. */
    pdt_real_t q = PDT_R(0.0);
    for (size_t lag = 0; lag < PDT_VALIDATE_LAGS; lag++) {
        q += S->fs.rho[lag] * S->fs.rho[lag];
    }
    r->white_stat = (pdt_real_t)n * q;
    r->white_limit = chi2_99((pdt_real_t)PDT_VALIDATE_LAGS);
    r->white = r->white_stat <= r->white_limit;
    r->inflation = pdt_fisher_inflation(&S->fs);

    pdt_real_t ml = sse / (pdt_real_t)n;
    if (!(ml > PDT_R(0.0))) {
        ml = PDT_REAL_EPS * PDT_REAL_EPS;
    }
    r->sigma = pdt_sqrt(sse / (pdt_real_t)(n - np));
    r->aic = (pdt_real_t)n * pdt_log(ml) + PDT_R(2.0) * (pdt_real_t)np;
    r->bic = (pdt_real_t)n * pdt_log(ml) + (pdt_real_t)np * pdt_log((pdt_real_t)n);
    r->std.count = np;
    pdt_fisher_covariance(S->F, np, n, sse, r->inflation, r->std.std, r->std.cov);

    /* The model-error FIR from a few samples before the model's dead time
     * on: e(k) ~ sum_j h_j du(k - L0 - j). */
    size_t l = (size_t)(pdt_model_dead_time(&r->model) / r->Ts);
    size_t L0 = l + 1u > PDT_VALIDATE_FIR / 4u ? l + 1u - PDT_VALIDATE_FIR / 4u : 1u;
    if (L0 < 1u) {
        L0 = 1u;
    }
    if (L0 + PDT_VALIDATE_FIR >= n / 2u) {
        L0 = 1u;
    }
    r->fir_lag = (uint32_t)L0;
    for (uint32_t i = 0; i < PDT_VALIDATE_FIR; i++) {
        S->bv[i] = PDT_R(0.0);
        for (uint32_t j = 0; j < PDT_VALIDATE_FIR; j++) {
            S->A[i][j] = PDT_R(0.0);
        }
    }
}

/* The FIR's normal equations, rows k0 .. k1 - 1 (k0 >= fir_lag). */
static void val_fir_rows(val_sums_t *S, size_t k0, size_t k1)
{
    const size_t L0 = (size_t)S->r.fir_lag;
    const pdt_real_t *const du = S->c.du;
    const pdt_real_t *const e = S->c.e;
    for (size_t k = k0; k < k1; k++) {
        pdt_real_t x[PDT_VALIDATE_FIR];
        for (uint32_t j = 0; j < PDT_VALIDATE_FIR; j++) {
            x[j] = k >= L0 + j ? du[k - L0 - j] : PDT_R(0.0);
        }
        for (uint32_t i = 0; i < PDT_VALIDATE_FIR; i++) {
            S->bv[i] += x[i] * e[k];
            for (uint32_t j = 0; j <= i; j++) {
                S->A[i][j] += x[i] * x[j];
            }
        }
    }
}

/* The FIR solved and the independence test: the result complete. */
static void val_finish(val_sums_t *S)
{
    pdt_validate_result_t *const r = &S->r;
    pdt_real_t(*const A)[PDT_VALIDATE_FIR] = S->A;
    pdt_real_t tr = PDT_R(0.0);
    for (uint32_t i = 0; i < PDT_VALIDATE_FIR; i++) {
        tr += A[i][i];
        for (uint32_t j = 0; j < i; j++) {
            A[j][i] = A[i][j];
        }
    }
    /* A small ridge keeps a step's nearly collinear regressors solvable. */
    pdt_real_t ridge = PDT_R(1e-4) * tr / (pdt_real_t)PDT_VALIDATE_FIR;
    for (uint32_t i = 0; i < PDT_VALIDATE_FIR; i++) {
        A[i][i] += ridge;
    }
    pdt_real_t h[PDT_VALIDATE_FIR];
    for (uint32_t i = 0; i < PDT_VALIDATE_FIR; i++) {
        h[i] = S->bv[i];
    }
    pdt_real_t ess = PDT_R(0.0);
    if (pdt_chol_solve(&A[0][0], PDT_VALIDATE_FIR, PDT_VALIDATE_FIR, PDT_R(0.0), h)) {
        for (uint32_t i = 0; i < PDT_VALIDATE_FIR; i++) {
            ess += h[i] * S->bv[i];
            r->fir[i] = h[i];
        }
    }
    pdt_real_t dof = (pdt_real_t)(S->c.n - S->fs.np - PDT_VALIDATE_FIR);
    pdt_real_t s2 = (S->r0 - ess) / dof;
    r->cross_stat = s2 > PDT_R(0.0) ? ess / s2 : PDT_REAL_MAX;
    r->cross_limit = chi2_99((pdt_real_t)PDT_VALIDATE_FIR);
    r->independent = r->cross_stat <= r->cross_limit;
}

/* The checks, the preparation and the result's head, shared by the two
 * forms. */
static pdt_status_t val_start(const pdt_model_t *m, const pdt_ident_data_t *data, pdt_real_t Ts,
                              pdt_real_t y0, void *work, size_t work_len, size_t need,
                              val_sums_t *S)
{
    /* Zeroed: prepare fills it on success only, and avr-gcc 5 took a
     * field for unset on the success path. */
    val_ctx_t c = {0};
    pdt_status_t st = prepare(m, data, Ts, y0, work, work_len, need, &c);
    if (st != PDT_OK) {
        return st;
    }
    if (gain_of(m) == PDT_R(0.0)) {
        return PDT_ERR_ARG;
    }
    S->c = c;
    S->r = (pdt_validate_result_t){0};
    S->r.model = *m;
    S->r.Ts = Ts;
    S->r.n = c.n;
    return PDT_OK;
}

pdt_status_t pdt_validate_model(const pdt_model_t *m, const pdt_ident_data_t *data, pdt_real_t Ts,
                                pdt_real_t y0, void *work, size_t work_len,
                                pdt_validate_result_t *out)
{
    if (out == NULL) {
        return PDT_ERR_ARG;
    }
    val_sums_t S;
    const size_t need = data != NULL ? pdt_validate_workspace_size(data->n) : 0u;
    pdt_status_t st = val_start(m, data, Ts, y0, work, work_len, need, &S);
    if (st != PDT_OK) {
        return st;
    }
    st = pdt_fisher_sum(m, Ts, data->u, data->y, S.c.n, y0, data->u[0], S.F, &S.fs);
    if (st != PDT_OK) {
        return st;
    }
    val_residual(&S);
    val_fir_rows(&S, (size_t)S.r.fir_lag, S.c.n);
    val_finish(&S);
    *out = S.r;
    return PDT_OK;
}

/* ---- the validation in steps ------------------------------------------ */

#define VAL_RUN_MAGIC PDT_MAGIC('P', 'D', 'V', 'S')

/* Where a validation in steps is (val_run_t.stage). */
#define VS_FISHER   1u
#define VS_RESIDUAL 2u
#define VS_FIR      3u
#define VS_FINISH   4u
#define VS_DONE     5u
#define VS_FAILED   6u

/* The state of a validation in steps, at the head of its workspace; the
 * three records of prepare follow it. */
typedef struct val_run {
    val_sums_t S;
    pdt_fisher_run_t R;
    pdt_status_t status; /* the step's error once VS_FAILED */
    uint32_t magic;
    uint32_t stage;
    size_t k; /* VS_FIR: the next row */
} val_run_t;

/* The public bound covers the state and the padding that aligns it
 * (pdt_validate.h). */
typedef char
    val_run_fits[(sizeof(val_run_t) + sizeof(uintmax_t) <= PDT_VALIDATE_RUN_STATE_SIZE) ? 1 : -1];

/* The state in the workspace: its first address aligned for it. */
static val_run_t *val_run_of(void *work)
{
    return (val_run_t *)pdt_aligned_state(work, PDT_VALIDATE_RUN_STATE_SIZE, sizeof(val_run_t));
}

size_t pdt_validate_run_workspace_size(size_t n)
{
    return PDT_VALIDATE_RUN_WORKSPACE_SIZE(n);
}

pdt_status_t pdt_validate_begin(const pdt_model_t *m, const pdt_ident_data_t *data, pdt_real_t Ts,
                                pdt_real_t y0, void *work, size_t work_len)
{
    if (data == NULL) {
        return PDT_ERR_ARG;
    }
    if (work == NULL || work_len < pdt_validate_run_workspace_size(data->n)) {
        return PDT_ERR_NOMEM;
    }
    if (!pdt_aligned(work)) {
        return PDT_ERR_ARG;
    }
    /* The state first, the records of prepare after the state's bound. */
    val_run_t *const V = val_run_of(work);
    unsigned char *const recs = (unsigned char *)work + PDT_VALIDATE_RUN_STATE_SIZE;
    const size_t need = 3u * data->n * sizeof(pdt_real_t);
    V->magic = 0u;
    pdt_status_t st =
        val_start(m, data, Ts, y0, recs, work_len - PDT_VALIDATE_RUN_STATE_SIZE, need, &V->S);
    if (st == PDT_OK) {
        st = pdt_fisher_begin(&V->R, m, Ts, data->u, data->y, V->S.c.n, y0, data->u[0], V->S.F);
    }
    if (st != PDT_OK) {
        return st;
    }
    V->status = PDT_OK;
    V->stage = VS_FISHER;
    V->k = 0u;
    V->magic = VAL_RUN_MAGIC;
    return PDT_OK;
}

/* One bounded piece of the validation. */
static void val_run_step(val_run_t *V)
{
    switch (V->stage) {
    case VS_FISHER:
        if (pdt_fisher_block(&V->R)) {
            V->status = pdt_fisher_end(&V->R, &V->S.fs);
            V->stage = V->status == PDT_OK ? VS_RESIDUAL : VS_FAILED;
        }
        break;
    case VS_RESIDUAL:
        val_residual(&V->S);
        V->k = (size_t)V->S.r.fir_lag;
        V->stage = VS_FIR;
        break;
    case VS_FIR: {
        const size_t n = V->S.c.n;
        const size_t stop = n - V->k > PDT_VALIDATE_FIR_ROWS ? V->k + PDT_VALIDATE_FIR_ROWS : n;
        val_fir_rows(&V->S, V->k, stop);
        V->k = stop;
        V->stage = stop >= n ? VS_FINISH : VS_FIR;
        break;
    }
    case VS_FINISH:
        val_finish(&V->S);
        V->stage = VS_DONE;
        break;
    default:
        break;
    }
}

pdt_status_t pdt_validate_step(void *work, pdt_validate_result_t *out)
{
    if (work == NULL || out == NULL || !pdt_aligned(work)) {
        return PDT_ERR_ARG;
    }
    val_run_t *const V = val_run_of(work);
    if (V->magic != VAL_RUN_MAGIC) {
        return PDT_ERR_STATE;
    }
    val_run_step(V);
    if (V->stage == VS_FAILED) {
        return V->status;
    }
    if (V->stage != VS_DONE) {
        return PDT_RUNNING;
    }
    *out = V->S.r;
    return PDT_OK;
}

/* The gain determined and the covariance usable: what pdt_validate_margin
 * needs. A shape parameter held at its estimate does not count against
 * a model (a SOPDT's negligible lag, an integrator's lag). */
static bool determined(const pdt_validate_result_t *v)
{
    bool ok = pdt_finite(v->std.std[0]);
    for (uint32_t i = 0; i < v->std.count; i++) {
        for (uint32_t j = 0; j < v->std.count; j++) {
            ok = ok && pdt_finite(v->std.cov[i][j]);
        }
    }
    return ok;
}

pdt_status_t pdt_ident_select_order(const pdt_validate_result_t *fo,
                                    const pdt_validate_result_t *so, pdt_model_kind_t *kind)
{
    /* fo of fewer lags than so: the choice is between a lower and a
     * higher order. */
    if (fo == NULL || so == NULL || kind == NULL || !pdt_model_kind_known(fo->model.kind) ||
        !(pdt_model_kind_lags(fo->model.kind) < pdt_model_kind_lags(so->model.kind))) {
        return PDT_ERR_ARG;
    }
    const pdt_model_kind_t lower = fo->model.kind;
    const pdt_model_kind_t higher = so->model.kind;
    /* A model whose gain the data do not determine, or whose covariance is
     * unusable, loses to one whose are. */
    bool fo_det = determined(fo);
    bool so_det = determined(so);
    if (fo_det != so_det) {
        *kind = fo_det ? lower : higher;
        return PDT_OK;
    }
    if (fo->independent != so->independent) {
        *kind = fo->independent ? lower : higher;
        return PDT_OK;
    }
    *kind = so->bic < fo->bic - PDT_R(2.0) ? higher : lower;
    return PDT_OK;
}

/* ---- the robust bound ------------------------------------------------- */

typedef struct val_c {
    pdt_real_t re;
    pdt_real_t im;
} val_c_t;

static val_c_t c_mul(val_c_t x, val_c_t y)
{
    val_c_t r = {x.re * y.re - x.im * y.im, x.re * y.im + x.im * y.re};
    return r;
}

static val_c_t c_div(val_c_t x, val_c_t y)
{
    pdt_real_t d = y.re * y.re + y.im * y.im;
    val_c_t r = {(x.re * y.re + x.im * y.im) / d, (x.im * y.re - x.re * y.im) / d};
    return r;
}

static pdt_real_t c_abs(val_c_t x)
{
    return pdt_hypot(x.re, x.im);
}

/* The arguments of pdt_validate_margin usable. */
static bool margin_args_ok(const pdt_validate_result_t *v, pdt_real_t dTd,
                           const pdt_tune_gains_t *g)
{
    return v != NULL && g != NULL && pdt_finite(dTd) && pdt_finite(g->Kc) && g->tauI > PDT_R(0.0) &&
           pdt_finite(g->tauI) && g->tauD >= PDT_R(0.0) && g->Tf >= PDT_R(0.0) &&
           pdt_finite(g->tauD) && pdt_finite(g->Tf) && pdt_model_check(&v->model) == PDT_OK &&
           v->Ts > PDT_R(0.0);
}

/* The grid's lowest frequency and its step in log w: from a thousandth of
 * the slowest of the loop's time scales up to the Nyquist frequency. */
static pdt_real_t margin_grid(const pdt_validate_result_t *v, const pdt_model_view_t *p,
                              const pdt_tune_gains_t *g, pdt_real_t Td, pdt_real_t *lr)
{
    pdt_real_t T = g->tauI;
    pdt_real_t tm = p->lags == 1u ? p->tau : p->a / (p->b > PDT_R(0.0) ? p->b : p->a * p->a);
    if (tm > T) {
        T = tm;
    }
    if (Td > T) {
        T = Td;
    }
    pdt_real_t w_lo = PDT_R(1e-3) / T;
    pdt_real_t w_hi = PDT_PI / v->Ts;
    if (!(w_hi > w_lo)) {
        w_hi = PDT_R(10.0) * w_lo;
    }
    *lr = pdt_log(w_hi / w_lo) / (pdt_real_t)(VAL_GRID - 1u);
    return w_lo;
}

/* The bound needs the covariance, and the gain determined: a shape
 * parameter the data do not determine is fixed at its estimate (its effect
 * on the output is within what the others explain), the gain never is. */
static bool margin_cov_ok(const pdt_validate_result_t *v, uint32_t np)
{
    bool std_ok = pdt_finite(v->std.std[0]);
    for (uint32_t i = 0; i < np; i++) {
        for (uint32_t j = 0; j < np; j++) {
            std_ok = std_ok && pdt_finite(v->std.cov[i][j]);
        }
    }
    return std_ok;
}

/* G(jw) of the model p with dead time Td, and in dg its derivatives by the
 * parameters: gain G / K; one lag's tau -s G / (tau s + 1); two lags' a
 * -s G / D, b -G / D; dead time -s G. */
static val_c_t margin_plant(const pdt_model_view_t *p, pdt_real_t w, pdt_real_t Td, val_c_t dg[4])
{
    const bool fo = p->lags == 1u;
    val_c_t s = {PDT_R(0.0), w};
    val_c_t dly = {pdt_cos(w * Td), -pdt_sin(w * Td)};
    val_c_t den;
    const pdt_real_t gain = p->K;
    if (fo) {
        den.re = PDT_R(1.0);
        den.im = w * p->tau;
    } else {
        den.re = p->b - w * w;
        den.im = p->a * w;
    }
    val_c_t one = {gain, PDT_R(0.0)};
    val_c_t G = c_mul(c_div(one, den), dly);
    dg[0] = (val_c_t){G.re / gain, G.im / gain};
    val_c_t sG = c_mul(s, G);
    val_c_t msG = {-sG.re, -sG.im};
    val_c_t mG = {-G.re, -G.im};
    if (fo) {
        dg[1] = c_div(msG, den);
        dg[2] = msG;
    } else {
        dg[1] = c_div(msG, den);
        dg[2] = c_div(mG, den);
        dg[3] = msG;
    }
    return G;
}

/* The parameters' part of the bound on |dG|: VAL_CHI standard deviations
 * of G along the covariance of the np parameters (an integrator's b left
 * out). */
static pdt_real_t margin_dpar(const pdt_validate_result_t *v, const val_c_t dg[4], uint32_t np,
                              bool integ)
{
    pdt_real_t qv = PDT_R(0.0);
    for (uint32_t a = 0; a < np; a++) {
        for (uint32_t b = 0; b < np; b++) {
            if (integ && (a == 2u || b == 2u)) {
                continue;
            }
            qv += v->std.cov[a][b] * (dg[a].re * dg[b].re + dg[a].im * dg[b].im);
        }
    }
    return qv > PDT_R(0.0) ? VAL_CHI * pdt_sqrt(qv) : PDT_R(0.0);
}

/* The part of the input's dynamics the model missed: |sum h_j z^-j| with
 * z^-1 = e^{-j w Ts}. The lag fir_lag is a pure delay and leaves the
 * magnitude alone; the phasor turns by one multiplication per tap (12
 * taps: no drift to speak of in float). */
static pdt_real_t margin_dfir(const pdt_validate_result_t *v, pdt_real_t w)
{
    val_c_t acc = {PDT_R(0.0), PDT_R(0.0)};
    val_c_t zi = {pdt_cos(w * v->Ts), -pdt_sin(w * v->Ts)};
    val_c_t zp = {PDT_R(1.0), PDT_R(0.0)};
    for (uint32_t j = 0; j < PDT_VALIDATE_FIR; j++) {
        acc.re += v->fir[j] * zp.re;
        acc.im += v->fir[j] * zp.im;
        zp = c_mul(zp, zi);
    }
    return c_abs(acc);
}

/* C(jw) = Kc (1 + 1 / (j w tauI) + j w tauD / (1 + j w Tf)). */
static val_c_t margin_controller(const pdt_tune_gains_t *g, pdt_real_t w)
{
    val_c_t C = {PDT_R(1.0), PDT_R(-1.0) / (w * g->tauI)};
    if (g->tauD > PDT_R(0.0)) {
        val_c_t num = {PDT_R(0.0), w * g->tauD};
        val_c_t dd = {PDT_R(1.0), w * g->Tf};
        val_c_t d = c_div(num, dd);
        C.re += d.re;
        C.im += d.im;
    }
    C.re *= g->Kc;
    C.im *= g->Kc;
    return C;
}

pdt_status_t pdt_validate_margin(const pdt_validate_result_t *v, pdt_real_t dTd,
                                 const pdt_tune_gains_t *g, pdt_real_t *ms, bool *fir_part)
{
    if (ms == NULL || !margin_args_ok(v, dTd, g)) {
        return PDT_ERR_ARG;
    }
    const pdt_model_t *m = &v->model;
    pdt_model_view_t p;
    pdt_model_view(m, &p);
    /* An integrator's b is bounded below by 0: its one-sided uncertainty
     * only turns the integration into a slow pole, which the controller's
     * own integral covers; the first-order bound would instead grow without
     * limit at low frequency. */
    const bool integ = pdt_model_integrates(m);
    pdt_real_t Td = pdt_model_dead_time(m) + dTd;
    pdt_real_t lr;
    pdt_real_t w_lo = margin_grid(v, &p, g, Td, &lr);
    const uint32_t np = v->std.count - 1u; /* without y0 */
    bool std_ok = margin_cov_ok(v, np);
    pdt_real_t best = PDT_R(1.0);
    bool best_fir = false;
    for (uint32_t i = 0; i < VAL_GRID; i++) {
        pdt_real_t w = w_lo * pdt_exp(lr * (pdt_real_t)i);
        val_c_t dg[4];
        val_c_t G = margin_plant(&p, w, Td, dg);
        pdt_real_t dpar = std_ok ? margin_dpar(v, dg, np, integ) : PDT_R(0.0);
        pdt_real_t dfir = v->independent ? PDT_R(0.0) : margin_dfir(v, w);
        val_c_t C = margin_controller(g, w);
        val_c_t L = c_mul(C, G);
        pdt_real_t sabs = PDT_R(1.0) / pdt_hypot(PDT_R(1.0) + L.re, L.im);
        pdt_real_t cs = c_abs(C) * sabs * (std_ok ? dpar + dfir : PDT_REAL_MAX);
        pdt_real_t bound = cs < PDT_R(1.0) ? sabs / (PDT_R(1.0) - cs) : (pdt_real_t)INFINITY;
        if (bound > best) {
            best = bound;
            best_fir = std_ok && dfir > dpar;
        }
    }
    *ms = best;
    if (fir_part != NULL) {
        *fir_part = best_fir;
    }
    return PDT_OK;
}
