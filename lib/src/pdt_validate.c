/*
 * Model validation: residual tests, parameter uncertainty, order choice and
 * the robust sensitivity bound; see pdt_validate.h.
 */
#include "pdt/pdt_validate.h"

#include "pdt/pdt_discrete.h"
#include "pdt_internal.h"

/* Partial sums over this many samples before they join the total, so that
 * float sums over long records keep their accuracy. */
#define VAL_BLOCK 256u
/* Points of the frequency grid of the robust bound. */
#define VAL_GRID  200u
/* Standard deviations of the confidence region the bound covers: about the
 * 95 % ellipsoid of four parameters (sqrt of chi-square(4) 0.95 = 3.08). */
#define VAL_CHI   PDT_R(3.0)

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

/* The parameter vector of m, in the documented order (y0 excluded). */
static uint32_t params_of(const pdt_model_t *m, pdt_real_t *p)
{
    if (m->kind == PDT_MODEL_FOPDT) {
        p[0] = m->p.fopdt.K;
        p[1] = m->p.fopdt.tau;
        p[2] = m->p.fopdt.Td;
        return 3u;
    }
    p[0] = m->p.sopdt.k;
    p[1] = m->p.sopdt.a;
    p[2] = m->p.sopdt.b;
    p[3] = m->p.sopdt.Td;
    return 4u;
}

static void params_set(pdt_model_t *m, const pdt_real_t *p)
{
    if (m->kind == PDT_MODEL_FOPDT) {
        m->p.fopdt.K = p[0];
        m->p.fopdt.tau = p[1];
        m->p.fopdt.Td = p[2];
    } else {
        m->p.sopdt.k = p[0];
        m->p.sopdt.a = p[1];
        m->p.sopdt.b = p[2];
        m->p.sopdt.Td = p[3];
    }
}

/* Finite-difference step of parameter i (never 0, and upward for b and Td
 * so that the perturbed model stays valid). */
static pdt_real_t fd_step(const pdt_model_t *m, uint32_t i, const pdt_real_t *p, pdt_real_t Ts)
{
    uint32_t np = m->kind == PDT_MODEL_FOPDT ? 3u : 4u;
    if (i == np - 1u) {
        return PDT_R(0.02) * Ts + PDT_R(1e-3) * p[i];
    }
    if (m->kind == PDT_MODEL_SOPDT && i == 2u && p[2] == PDT_R(0.0)) {
        /* An integrator: b's scale is that of critical damping, a^2 / 4. */
        return PDT_R(2.5e-4) * p[1] * p[1];
    }
    return PDT_R(1e-3) * pdt_fabs(p[i]);
}

/* Solves A x = b in place for a symmetric positive definite n x n A (row
 * stride PDT_VALIDATE_FIR) by Cholesky; false when A is not positive
 * definite. */
static bool chol_solve(pdt_real_t A[PDT_VALIDATE_FIR][PDT_VALIDATE_FIR], pdt_real_t *x, uint32_t n)
{
    for (uint32_t j = 0; j < n; j++) {
        pdt_real_t s = A[j][j];
        for (uint32_t k = 0; k < j; k++) {
            s -= A[j][k] * A[j][k];
        }
        if (!(s > PDT_R(0.0))) {
            return false;
        }
        A[j][j] = pdt_sqrt(s);
        for (uint32_t i = j + 1u; i < n; i++) {
            pdt_real_t t = A[i][j];
            for (uint32_t k = 0; k < j; k++) {
                t -= A[i][k] * A[j][k];
            }
            A[i][j] = t / A[j][j];
        }
    }
    for (uint32_t i = 0; i < n; i++) {
        pdt_real_t t = x[i];
        for (uint32_t k = 0; k < i; k++) {
            t -= A[i][k] * x[k];
        }
        x[i] = t / A[i][i];
    }
    for (uint32_t ii = n; ii-- > 0u;) {
        pdt_real_t t = x[ii];
        for (uint32_t k = ii + 1u; k < n; k++) {
            t -= A[k][ii] * x[k];
        }
        x[ii] = t / A[ii][ii];
    }
    return true;
}

/* Inverse of the symmetric positive semi-definite F (n x n) by Gauss-Jordan
 * on its correlation form, pivoting on the diagonal. A parameter whose
 * pivot falls below tol is not determined by the data (the output does
 * not depend on it beyond what the others explain): it is fixed at its
 * estimate, marked in *undet, and the inverse is that of the others (the
 * covariance conditional on it). Returns false when F is not usable at
 * all (a zero or non-finite diagonal: a parameter the output does not
 * see). */
static bool invert(pdt_real_t F[PDT_VALIDATE_MAX_PARAMS][PDT_VALIDATE_MAX_PARAMS],
                   pdt_real_t Inv[PDT_VALIDATE_MAX_PARAMS][PDT_VALIDATE_MAX_PARAMS], uint32_t n,
                   bool *undet)
{
    pdt_real_t dsc[PDT_VALIDATE_MAX_PARAMS];
    pdt_real_t M[PDT_VALIDATE_MAX_PARAMS][2u * PDT_VALIDATE_MAX_PARAMS];
    for (uint32_t i = 0; i < n; i++) {
        undet[i] = false;
        if (!(F[i][i] > PDT_R(0.0)) || !pdt_finite(F[i][i])) {
            return false;
        }
        dsc[i] = pdt_sqrt(F[i][i]);
    }
    for (uint32_t i = 0; i < n; i++) {
        for (uint32_t j = 0; j < n; j++) {
            M[i][j] = F[i][j] / (dsc[i] * dsc[j]);
            M[i][n + j] = i == j ? PDT_R(1.0) : PDT_R(0.0);
        }
    }
    const pdt_real_t tol = PDT_R(1e3) * PDT_REAL_EPS;
    for (uint32_t c = 0; c < n; c++) {
        /* Diagonal pivots keep the parameter order, so that a small pivot
         * names the parameter the others already explain. */
        if (!(M[c][c] > tol)) {
            undet[c] = true;
            for (uint32_t j = 0; j < 2u * n; j++) {
                M[c][j] = PDT_R(0.0);
            }
            for (uint32_t r = 0; r < n; r++) {
                M[r][c] = PDT_R(0.0);
            }
            M[c][c] = PDT_R(1.0);
            continue;
        }
        pdt_real_t inv = PDT_R(1.0) / M[c][c];
        for (uint32_t j = 0; j < 2u * n; j++) {
            M[c][j] *= inv;
        }
        for (uint32_t r = 0; r < n; r++) {
            if (r != c && M[r][c] != PDT_R(0.0)) {
                pdt_real_t f = M[r][c];
                for (uint32_t j = 0; j < 2u * n; j++) {
                    M[r][j] -= f * M[c][j];
                }
            }
        }
    }
    for (uint32_t i = 0; i < n; i++) {
        for (uint32_t j = 0; j < n; j++) {
            Inv[i][j] = (undet[i] || undet[j]) ? PDT_R(0.0) : M[i][n + j] / (dsc[i] * dsc[j]);
        }
    }
    return true;
}

/* The pieces every call shares: argument checks, the residual and the
 * sensitivities in the workspace. */
typedef struct val_ctx {
    const pdt_real_t *y;
    pdt_real_t *du;      /* u - u[0] */
    pdt_real_t *ys;      /* simulated output */
    pdt_real_t *sens[3]; /* sensitivities of the shape parameters */
    uint32_t np;         /* model parameters (without y0) */
    size_t n;
    pdt_real_t y0;
} val_ctx_t;

static pdt_status_t prepare(const pdt_model_t *m, const pdt_ident_data_t *data, pdt_real_t Ts,
                            pdt_real_t y0, void *work, size_t work_len, val_ctx_t *c)
{
    if (m == NULL || data == NULL || data->u == NULL || data->y == NULL ||
        pdt_model_check(m) != PDT_OK || !pdt_finite(Ts) || !(Ts > PDT_R(0.0)) || !pdt_finite(y0)) {
        return PDT_ERR_ARG;
    }
    size_t n = data->n;
    if (n < PDT_MIN_SAMPLES || n <= 2u * (PDT_VALIDATE_LAGS + PDT_VALIDATE_FIR)) {
        return PDT_ERR_TOO_SHORT;
    }
    if (work == NULL || work_len < pdt_validate_workspace_size(n)) {
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
    for (uint32_t i = 0; i < 3u; i++) {
        c->sens[i] = w + (2u + i) * n;
    }
    for (size_t k = 0; k < n; k++) {
        c->du[k] = data->u[k] - data->u[0];
    }
    pdt_discrete_t d;
    if (pdt_discrete_init(m, Ts, &d) != PDT_OK ||
        pdt_discrete_simulate(&d, c->du, n, c->ys) != PDT_OK) {
        return PDT_ERR_ARG;
    }
    pdt_real_t p[4] = {PDT_R(0.0), PDT_R(0.0), PDT_R(0.0), PDT_R(0.0)};
    c->np = params_of(m, p);
    /* The gain enters linearly (ys / K): only the shape is perturbed. */
    for (uint32_t i = 1; i < c->np; i++) {
        pdt_real_t pp[4] = {p[0], p[1], p[2], p[3]};
        pdt_real_t h = fd_step(m, i, p, Ts);
        pp[i] += h;
        h = pp[i] - p[i];
        pdt_model_t mp = *m;
        params_set(&mp, pp);
        pdt_real_t *s = c->sens[i - 1u];
        if (!(h > PDT_R(0.0)) || pdt_discrete_init(&mp, Ts, &d) != PDT_OK ||
            pdt_discrete_simulate(&d, c->du, n, s) != PDT_OK) {
            return PDT_ERR_ARG;
        }
        for (size_t k = 0; k < n; k++) {
            s[k] = (s[k] - c->ys[k]) / h;
        }
    }
    for (size_t k = 0; k < n; k++) {
        if (!pdt_finite(c->ys[k])) {
            return PDT_ERR_NONFINITE;
        }
    }
    return PDT_OK;
}

/* Column j of the Jacobian at sample k: gain, shape..., offset. */
static pdt_real_t jac(const val_ctx_t *c, pdt_real_t gain, uint32_t j, size_t k)
{
    if (j == 0u) {
        return c->ys[k] / gain;
    }
    if (j < c->np) {
        return c->sens[j - 1u][k];
    }
    return PDT_R(1.0);
}

/* Fisher information J^T J (without 1 / sigma^2) and the residual's sum of
 * squares. */
static void fisher(const val_ctx_t *c, pdt_real_t gain,
                   pdt_real_t F[PDT_VALIDATE_MAX_PARAMS][PDT_VALIDATE_MAX_PARAMS], pdt_real_t *sse)
{
    uint32_t np = c->np + 1u;
    pdt_real_t part[PDT_VALIDATE_MAX_PARAMS][PDT_VALIDATE_MAX_PARAMS] = {{PDT_R(0.0)}};
    pdt_real_t se = PDT_R(0.0);
    pdt_real_t sp = PDT_R(0.0);
    for (uint32_t i = 0; i < np; i++) {
        for (uint32_t j = 0; j < np; j++) {
            F[i][j] = PDT_R(0.0);
        }
    }
    for (size_t k = 0; k < c->n; k++) {
        pdt_real_t jr[PDT_VALIDATE_MAX_PARAMS];
        for (uint32_t i = 0; i < np; i++) {
            jr[i] = jac(c, gain, i, k);
        }
        for (uint32_t i = 0; i < np; i++) {
            for (uint32_t j = i; j < np; j++) {
                part[i][j] += jr[i] * jr[j];
            }
        }
        pdt_real_t e = c->y[k] - c->y0 - c->ys[k];
        sp += e * e;
        if ((k + 1u) % VAL_BLOCK == 0u || k + 1u == c->n) {
            for (uint32_t i = 0; i < np; i++) {
                for (uint32_t j = i; j < np; j++) {
                    F[i][j] += part[i][j];
                    part[i][j] = PDT_R(0.0);
                }
            }
            se += sp;
            sp = PDT_R(0.0);
        }
    }
    for (uint32_t i = 0; i < np; i++) {
        for (uint32_t j = 0; j < i; j++) {
            F[i][j] = F[j][i];
        }
    }
    *sse = se;
}

/* Covariance sigma^2 inflation (J^T J)^-1 into *out. */
static void uncertainty(const val_ctx_t *c, pdt_real_t gain, pdt_real_t sse,
                        pdt_real_t F[PDT_VALIDATE_MAX_PARAMS][PDT_VALIDATE_MAX_PARAMS],
                        pdt_real_t inflation, pdt_ident_std_t *out)
{
    uint32_t np = c->np + 1u;
    pdt_real_t Fc[PDT_VALIDATE_MAX_PARAMS][PDT_VALIDATE_MAX_PARAMS];
    pdt_real_t Inv[PDT_VALIDATE_MAX_PARAMS][PDT_VALIDATE_MAX_PARAMS];
    for (uint32_t i = 0; i < np; i++) {
        for (uint32_t j = 0; j < np; j++) {
            Fc[i][j] = F[i][j];
        }
    }
    (void)gain;
    pdt_real_t s2 = sse / (pdt_real_t)(c->n - np) * inflation;
    bool undet[PDT_VALIDATE_MAX_PARAMS];
    bool ok = invert(Fc, Inv, np, undet);
    *out = (pdt_ident_std_t){0};
    out->count = np;
    for (uint32_t i = 0; i < np; i++) {
        for (uint32_t j = 0; j < np; j++) {
            out->cov[i][j] = ok ? s2 * Inv[i][j] : (pdt_real_t)INFINITY;
        }
        /* An undetermined parameter: std +infinity, covariance 0 (the
         * others' covariance is conditional on it). */
        bool fin = ok && !undet[i] && out->cov[i][i] >= PDT_R(0.0);
        out->std[i] = fin ? pdt_sqrt(out->cov[i][i]) : (pdt_real_t)INFINITY;
    }
}

static pdt_real_t gain_of(const pdt_model_t *m)
{
    return m->kind == PDT_MODEL_FOPDT ? m->p.fopdt.K : m->p.sopdt.k;
}

pdt_status_t pdt_ident_uncertainty(const pdt_model_t *m, const pdt_ident_data_t *data,
                                   pdt_real_t Ts, pdt_real_t y0, void *work, size_t work_len,
                                   pdt_ident_std_t *out)
{
    if (out == NULL) {
        return PDT_ERR_ARG;
    }
    pdt_validate_result_t r;
    pdt_status_t st = pdt_validate_model(m, data, Ts, y0, work, work_len, &r);
    if (st == PDT_OK) {
        *out = r.std;
    }
    return st;
}

pdt_status_t pdt_validate_model(const pdt_model_t *m, const pdt_ident_data_t *data, pdt_real_t Ts,
                                pdt_real_t y0, void *work, size_t work_len,
                                pdt_validate_result_t *out)
{
    if (out == NULL) {
        return PDT_ERR_ARG;
    }
    val_ctx_t c;
    pdt_status_t st = prepare(m, data, Ts, y0, work, work_len, &c);
    if (st != PDT_OK) {
        return st;
    }
    pdt_real_t gain = gain_of(m);
    if (gain == PDT_R(0.0)) {
        return PDT_ERR_ARG;
    }
    const size_t n = c.n;
    pdt_validate_result_t r = {0};
    r.model = *m;
    r.Ts = Ts;
    r.n = n;

    pdt_real_t F[PDT_VALIDATE_MAX_PARAMS][PDT_VALIDATE_MAX_PARAMS];
    pdt_real_t sse;
    fisher(&c, gain, F, &sse);
    const uint32_t np = c.np + 1u;

    /* The residual, kept in the first sensitivity's place no longer
     * needed once the Fisher information is summed. */
    pdt_real_t *e = c.sens[0];
    pdt_real_t mean = PDT_R(0.0);
    for (size_t k = 0; k < n; k++) {
        e[k] = c.y[k] - c.y0 - c.ys[k];
        mean += e[k];
    }
    mean /= (pdt_real_t)n;
    for (size_t k = 0; k < n; k++) {
        e[k] -= mean;
    }

    /* Whiteness: normalised autocorrelations at lags 1..LAGS. */
    pdt_real_t r0 = PDT_R(0.0);
    for (size_t k = 0; k < n; k++) {
        r0 += e[k] * e[k];
    }
    pdt_real_t q = PDT_R(0.0);
    pdt_real_t infl = PDT_R(1.0);
    if (r0 > PDT_R(0.0)) {
        for (size_t lag = 1; lag <= PDT_VALIDATE_LAGS; lag++) {
            pdt_real_t s = PDT_R(0.0);
            for (size_t k = lag; k < n; k++) {
                s += e[k] * e[k - lag];
            }
            pdt_real_t rho = s / r0;
            q += rho * rho;
            infl += PDT_R(2.0) * rho;
        }
    }
    r.white_stat = (pdt_real_t)n * q;
    r.white_limit = chi2_99((pdt_real_t)PDT_VALIDATE_LAGS);
    r.white = r.white_stat <= r.white_limit;
    r.inflation = infl > PDT_R(1.0) ? infl : PDT_R(1.0);

    pdt_real_t ml = sse / (pdt_real_t)n;
    if (!(ml > PDT_R(0.0))) {
        ml = PDT_REAL_EPS * PDT_REAL_EPS;
    }
    r.sigma = pdt_sqrt(sse / (pdt_real_t)(n - np));
    r.aic = (pdt_real_t)n * pdt_log(ml) + PDT_R(2.0) * (pdt_real_t)np;
    r.bic = (pdt_real_t)n * pdt_log(ml) + (pdt_real_t)np * pdt_log((pdt_real_t)n);
    uncertainty(&c, gain, sse, F, r.inflation, &r.std);

    /* The model-error FIR from a few samples before the model's dead time
     * on: e(k) ~ sum_j h_j du(k - L0 - j). */
    size_t l = (size_t)(pdt_model_dead_time(m) / Ts);
    size_t L0 = l + 1u > PDT_VALIDATE_FIR / 4u ? l + 1u - PDT_VALIDATE_FIR / 4u : 1u;
    if (L0 < 1u) {
        L0 = 1u;
    }
    if (L0 + PDT_VALIDATE_FIR >= n / 2u) {
        L0 = 1u;
    }
    r.fir_lag = (uint32_t)L0;
    pdt_real_t A[PDT_VALIDATE_FIR][PDT_VALIDATE_FIR] = {{PDT_R(0.0)}};
    pdt_real_t bv[PDT_VALIDATE_FIR] = {PDT_R(0.0)};
    for (size_t k = L0; k < n; k++) {
        pdt_real_t x[PDT_VALIDATE_FIR];
        for (uint32_t j = 0; j < PDT_VALIDATE_FIR; j++) {
            x[j] = k >= L0 + j ? c.du[k - L0 - j] : PDT_R(0.0);
        }
        for (uint32_t i = 0; i < PDT_VALIDATE_FIR; i++) {
            bv[i] += x[i] * e[k];
            for (uint32_t j = 0; j <= i; j++) {
                A[i][j] += x[i] * x[j];
            }
        }
    }
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
        h[i] = bv[i];
    }
    pdt_real_t ess = PDT_R(0.0);
    if (chol_solve(A, h, PDT_VALIDATE_FIR)) {
        for (uint32_t i = 0; i < PDT_VALIDATE_FIR; i++) {
            ess += h[i] * bv[i];
            r.fir[i] = h[i];
        }
    }
    pdt_real_t dof = (pdt_real_t)(n - np - PDT_VALIDATE_FIR);
    pdt_real_t s2 = (r0 - ess) / dof;
    r.cross_stat = s2 > PDT_R(0.0) ? ess / s2 : PDT_REAL_MAX;
    r.cross_limit = chi2_99((pdt_real_t)PDT_VALIDATE_FIR);
    r.independent = r.cross_stat <= r.cross_limit;
    *out = r;
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
    if (fo == NULL || so == NULL || kind == NULL || fo->model.kind != PDT_MODEL_FOPDT ||
        so->model.kind != PDT_MODEL_SOPDT) {
        return PDT_ERR_ARG;
    }
    /* A model whose gain the data do not determine, or whose covariance is
     * unusable, loses to one whose are. */
    bool fo_det = determined(fo);
    bool so_det = determined(so);
    if (fo_det != so_det) {
        *kind = fo_det ? PDT_MODEL_FOPDT : PDT_MODEL_SOPDT;
        return PDT_OK;
    }
    if (fo->independent != so->independent) {
        *kind = fo->independent ? PDT_MODEL_FOPDT : PDT_MODEL_SOPDT;
        return PDT_OK;
    }
    *kind = so->bic < fo->bic - PDT_R(2.0) ? PDT_MODEL_SOPDT : PDT_MODEL_FOPDT;
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

pdt_status_t pdt_validate_margin(const pdt_validate_result_t *v, pdt_real_t dTd,
                                 const pdt_tune_gains_t *g, pdt_real_t *ms, bool *fir_part)
{
    if (v == NULL || g == NULL || ms == NULL || !pdt_finite(dTd) || !pdt_finite(g->Kc) ||
        !(g->tauI > PDT_R(0.0)) || !pdt_finite(g->tauI) || !(g->tauD >= PDT_R(0.0)) ||
        !(g->Tf >= PDT_R(0.0)) || !pdt_finite(g->tauD) || !pdt_finite(g->Tf) ||
        pdt_model_check(&v->model) != PDT_OK || !(v->Ts > PDT_R(0.0))) {
        return PDT_ERR_ARG;
    }
    const pdt_model_t *m = &v->model;
    const bool fo = m->kind == PDT_MODEL_FOPDT;
    /* An integrator's b is bounded below by 0: its one-sided uncertainty
     * only turns the integration into a slow pole, which the controller's
     * own integral covers; the first-order bound would instead grow without
     * limit at low frequency. */
    const bool integ = !fo && m->p.sopdt.b == PDT_R(0.0);
    pdt_real_t Td = pdt_model_dead_time(m) + dTd;
    pdt_real_t T = g->tauI;
    pdt_real_t tm = fo ? m->p.fopdt.tau
                       : m->p.sopdt.a / (m->p.sopdt.b > PDT_R(0.0) ? m->p.sopdt.b
                                                                   : m->p.sopdt.a * m->p.sopdt.a);
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
    pdt_real_t lr = pdt_log(w_hi / w_lo) / (pdt_real_t)(VAL_GRID - 1u);
    const uint32_t np = v->std.count - 1u; /* without y0 */
    /* The bound needs the covariance, and the gain determined: a shape
     * parameter the data do not determine is fixed at its estimate (its
     * effect on the output is within what the others explain), the gain
     * never is. */
    bool std_ok = pdt_finite(v->std.std[0]);
    for (uint32_t i = 0; i < np; i++) {
        for (uint32_t j = 0; j < np; j++) {
            std_ok = std_ok && pdt_finite(v->std.cov[i][j]);
        }
    }
    pdt_real_t best = PDT_R(1.0);
    bool best_fir = false;
    for (uint32_t i = 0; i < VAL_GRID; i++) {
        pdt_real_t w = w_lo * pdt_exp(lr * (pdt_real_t)i);
        val_c_t s = {PDT_R(0.0), w};
        val_c_t dly = {pdt_cos(w * Td), -pdt_sin(w * Td)};
        val_c_t den;
        pdt_real_t gain;
        if (fo) {
            den.re = PDT_R(1.0);
            den.im = w * m->p.fopdt.tau;
            gain = m->p.fopdt.K;
        } else {
            den.re = m->p.sopdt.b - w * w;
            den.im = m->p.sopdt.a * w;
            gain = m->p.sopdt.k;
        }
        val_c_t one = {gain, PDT_R(0.0)};
        val_c_t G = c_mul(c_div(one, den), dly);
        /* dG/dp: gain G / K; FOPDT tau -s G / (tau s + 1); SOPDT a -s G / D,
         * b -G / D; dead time -s G. */
        val_c_t dg[4];
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
        pdt_real_t dpar = PDT_R(0.0);
        if (std_ok) {
            pdt_real_t qv = PDT_R(0.0);
            for (uint32_t a = 0; a < np; a++) {
                for (uint32_t b = 0; b < np; b++) {
                    if (integ && (a == 2u || b == 2u)) {
                        continue;
                    }
                    qv += v->std.cov[a][b] * (dg[a].re * dg[b].re + dg[a].im * dg[b].im);
                }
            }
            dpar = qv > PDT_R(0.0) ? VAL_CHI * pdt_sqrt(qv) : PDT_R(0.0);
        }
        pdt_real_t dfir = PDT_R(0.0);
        if (!v->independent) {
            /* |sum h_j z^-j| with z^-1 = e^{-j w Ts}: the lag fir_lag is a
             * pure delay and leaves the magnitude alone; the phasor turns
             * by one multiplication per tap (12 taps: no drift to speak
             * of in float). */
            val_c_t acc = {PDT_R(0.0), PDT_R(0.0)};
            val_c_t zi = {pdt_cos(w * v->Ts), -pdt_sin(w * v->Ts)};
            val_c_t zp = {PDT_R(1.0), PDT_R(0.0)};
            for (uint32_t j = 0; j < PDT_VALIDATE_FIR; j++) {
                acc.re += v->fir[j] * zp.re;
                acc.im += v->fir[j] * zp.im;
                zp = c_mul(zp, zi);
            }
            dfir = c_abs(acc);
        }
        /* C(jw) = Kc (1 + 1 / (j w tauI) + j w tauD / (1 + j w Tf)). */
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
