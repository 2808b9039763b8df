/*
 * Least-squares delay scans, ELMS and E-IV-LMS. The equations and their
 * conventions are in docs/ls.md.
 *
 * Numerics for float. The regression is written in delta form around
 * q = 1, which is the same model with better conditioned columns:
 *   FOPDT: dy(k) = p ys(k-1) + beta u(k-l-1) + c'
 *   SOPDT: dy(k) = p ys(k-1) + q dy(k-1) + s u(k-l-2)
 *                  + b1 (u(k-l-1) - u(k-l-2)) + c'
 * with ys = y - y[0], dy(k) = y(k) - y(k-1), u the deviation from u[0],
 * p = -(1 + a1 + a2) (FOPDT alpha - 1), q = a2, s = b1 + b2. With Ts small
 * against the time constants, y(k-1) and y(k-2) (and the two held inputs)
 * are nearly collinear, while ys(k-1) and dy(k-1) are not; and p and s, the
 * small numbers that set the gain, are estimated directly instead of as
 * differences of numbers near 2 and 1. The constant c' is eliminated by
 * centring every column on its window mean (two passes: means, then
 * products), and all sums are accumulated in blocks.
 */
#include "pdt/pdt_ls.h"

#include "pdt_internal.h"
#include "pdt_model_priv.h"

#define LS_MAGIC PDT_MAGIC('P', 'D', 'L', 'S')

/* Samples per partial sum (as in pdt_cost.c): float sums over long records
 * then lose (BLOCK + n / BLOCK) eps instead of n eps. */
#define LS_BLOCK 128u

/* Most regression columns after centring (SOPDT). */
#define LS_PMAX 4u

/* Most sums one pass accumulates: the IV products, 4 x 4 plus 4. */
#define LS_NSUM (LS_PMAX * LS_PMAX + LS_PMAX)

/* A pivot of the equilibrated system below this means no unique solution:
 * the estimate would carry less than ~eps * 1/tol of relative accuracy. */
#define LS_PIVOT_TOL (PDT_R(256.0) * PDT_REAL_EPS)

typedef enum ls_fit_status {
    LS_FIT_OK = 0,
    LS_FIT_SINGULAR = 1,
    LS_FIT_NOFORM = 2
} ls_fit_status_t;

/* Blocked sums of up to LS_NSUM values. */
typedef struct ls_acc {
    pdt_real_t tot[LS_NSUM];
    pdt_real_t blk[LS_NSUM];
    unsigned m;
    unsigned fill;
} ls_acc_t;

static void acc_start(ls_acc_t *a, unsigned m)
{
    for (unsigned i = 0; i < LS_NSUM; i++) {
        a->tot[i] = PDT_R(0.0);
        a->blk[i] = PDT_R(0.0);
    }
    a->m = m;
    a->fill = 0u;
}

static void acc_add(ls_acc_t *a, const pdt_real_t *v)
{
    for (unsigned i = 0; i < a->m; i++) {
        a->blk[i] += v[i];
    }
    if (++a->fill == LS_BLOCK) {
        for (unsigned i = 0; i < a->m; i++) {
            a->tot[i] += a->blk[i];
            a->blk[i] = PDT_R(0.0);
        }
        a->fill = 0u;
    }
}

static void acc_end(ls_acc_t *a)
{
    for (unsigned i = 0; i < a->m; i++) {
        a->tot[i] += a->blk[i];
        a->blk[i] = PDT_R(0.0);
    }
    a->fill = 0u;
}

static unsigned order_of(const pdt_ls_t *c)
{
    return (unsigned)pdt_model_kind_lags(c->cfg.model);
}

/* Input deviation u(k - lag) - u0; the input is at rest before sample 0. */
static pdt_real_t udev(const pdt_ls_t *c, size_t k, size_t lag)
{
    return k >= lag ? c->u[k - lag] - c->u[0] : PDT_R(0.0);
}

/* The regression row of sample k (k >= order) at delay l: target dy(k)
 * into *t, columns into x[0..P-1]. */
static void ls_row(const pdt_ls_t *c, size_t k, size_t l, pdt_real_t *t, pdt_real_t *x)
{
    const pdt_real_t *y = c->y;
    *t = y[k] - y[k - 1u];
    x[0] = y[k - 1u] - y[0];
    if (order_of(c) == 1u) {
        x[1] = udev(c, k, l + 1u);
    } else {
        pdt_real_t ua = udev(c, k, l + 1u);
        pdt_real_t ub = udev(c, k, l + 2u);
        x[1] = y[k - 1u] - y[k - 2u];
        x[2] = ub;
        x[3] = ua - ub;
    }
}

/* The auxiliary model of E-IV-LMS: the least-squares estimate th simulated
 * from rest on the input alone. State x1 = xs(k-1), x2 = xs(k-2); advances
 * to sample k. */
static void aux_advance(const pdt_ls_t *c, const pdt_real_t *th, size_t k, size_t l, pdt_real_t *x1,
                        pdt_real_t *x2)
{
    pdt_real_t x;
    if (order_of(c) == 1u) {
        x = *x1 + th[0] * *x1 + th[1] * udev(c, k, l + 1u);
    } else {
        pdt_real_t ua = udev(c, k, l + 1u);
        pdt_real_t ub = udev(c, k, l + 2u);
        x = *x1 + th[0] * *x1 + th[1] * (*x1 - *x2) + th[2] * ub + th[3] * (ua - ub);
    }
    *x2 = *x1;
    *x1 = x;
}

/* Solves S th = r for the P x P system (P <= 4; S, not modified, may be
 * unsymmetric: IV). Columns are scaled by cs[] (1 / norm of the centred
 * regressor) and rows by their largest entry, then Gaussian elimination
 * with partial pivoting. Returns false, th untouched, when a pivot falls below
 * LS_PIVOT_TOL or the solution is not finite. */
static bool ls_solve(pdt_real_t S[LS_PMAX][LS_PMAX], const pdt_real_t *r, const pdt_real_t *cs,
                     unsigned P, pdt_real_t *th)
{
    pdt_real_t A[LS_PMAX][LS_PMAX + 1u];
    pdt_real_t z[LS_PMAX];
    for (unsigned i = 0; i < P; i++) {
        pdt_real_t big = PDT_R(0.0);
        for (unsigned j = 0; j < P; j++) {
            A[i][j] = S[i][j] * cs[j];
            if (pdt_fabs(A[i][j]) > big) {
                big = pdt_fabs(A[i][j]);
            }
        }
        if (!(big > PDT_R(0.0)) || !pdt_finite(big)) {
            return false;
        }
        for (unsigned j = 0; j < P; j++) {
            A[i][j] /= big;
        }
        A[i][P] = r[i] / big;
    }
    for (unsigned col = 0; col < P; col++) {
        unsigned piv = col;
        for (unsigned i = col + 1u; i < P; i++) {
            if (pdt_fabs(A[i][col]) > pdt_fabs(A[piv][col])) {
                piv = i;
            }
        }
        if (!(pdt_fabs(A[piv][col]) >= LS_PIVOT_TOL)) {
            return false;
        }
        if (piv != col) {
            for (unsigned j = col; j <= P; j++) {
                pdt_real_t tmp = A[col][j];
                A[col][j] = A[piv][j];
                A[piv][j] = tmp;
            }
        }
        for (unsigned i = col + 1u; i < P; i++) {
            pdt_real_t f = A[i][col] / A[col][col];
            for (unsigned j = col; j <= P; j++) {
                A[i][j] -= f * A[col][j];
            }
        }
    }
    for (unsigned ii = P; ii-- > 0u;) {
        pdt_real_t v = A[ii][P];
        for (unsigned j = ii + 1u; j < P; j++) {
            v -= A[ii][j] * z[j];
        }
        z[ii] = v / A[ii][ii];
    }
    for (unsigned j = 0; j < P; j++) {
        z[j] *= cs[j];
        if (!pdt_finite(z[j])) {
            return false;
        }
    }
    for (unsigned j = 0; j < P; j++) {
        th[j] = z[j];
    }
    return true;
}

/* Window means of the target and of the regression columns: m[0] for dy,
 * m[1 + j] for column j. */
static void ls_means(const pdt_ls_t *c, size_t l, pdt_real_t *m)
{
    const unsigned P = 2u * order_of(c);
    const pdt_real_t M = (pdt_real_t)(c->n - c->k0);
    ls_acc_t a;
    pdt_real_t v[LS_PMAX + 1u];
    acc_start(&a, P + 1u);
    for (size_t k = c->k0; k < c->n; k++) {
        ls_row(c, k, l, &v[0], &v[1]);
        acc_add(&a, v);
    }
    acc_end(&a);
    for (unsigned i = 0; i <= P; i++) {
        m[i] = a.tot[i] / M;
    }
}

/* Window means of the auxiliary outputs xs(k-1) and, SOPDT, xs(k-1) -
 * xs(k-2): the instrument columns that differ from the regression's. */
static void iv_means(const pdt_ls_t *c, size_t l, const pdt_real_t *th_ls, pdt_real_t *mz)
{
    const unsigned ord = order_of(c);
    const pdt_real_t M = (pdt_real_t)(c->n - c->k0);
    pdt_real_t x1 = PDT_R(0.0);
    pdt_real_t x2 = PDT_R(0.0);
    pdt_real_t v[2];
    ls_acc_t a;
    acc_start(&a, ord);
    for (size_t k = 0; k < c->n; k++) {
        if (k >= c->k0) {
            v[0] = x1;
            v[1] = x1 - x2;
            acc_add(&a, v);
        }
        aux_advance(c, th_ls, k, l, &x1, &x2);
    }
    acc_end(&a);
    for (unsigned i = 0; i < ord; i++) {
        mz[i] = a.tot[i] / M;
    }
}

/* Centred products: S[i][j] = sum zc_i xc_j, r[i] = sum zc_i tc over the
 * window, with zc the centred instruments (the regressors themselves for
 * least squares, th_ls == NULL; else the auxiliary model th_ls, whose
 * centred outputs take the first `order` instrument columns). */
static void ls_products(const pdt_ls_t *c, size_t l, const pdt_real_t *m, const pdt_real_t *th_ls,
                        const pdt_real_t *mz, pdt_real_t S[LS_PMAX][LS_PMAX], pdt_real_t *r)
{
    const unsigned ord = order_of(c);
    const unsigned P = 2u * ord;
    pdt_real_t x1 = PDT_R(0.0);
    pdt_real_t x2 = PDT_R(0.0);
    pdt_real_t t;
    pdt_real_t x[LS_PMAX];
    pdt_real_t z[LS_PMAX];
    pdt_real_t v[LS_NSUM];
    ls_acc_t a;
    acc_start(&a, P * P + P);
    for (size_t k = (th_ls != NULL) ? 0u : c->k0; k < c->n; k++) {
        if (k >= c->k0) {
            ls_row(c, k, l, &t, x);
            t -= m[0];
            for (unsigned j = 0; j < P; j++) {
                x[j] -= m[1u + j];
                z[j] = x[j];
            }
            if (th_ls != NULL) {
                z[0] = x1 - mz[0];
                if (ord == 2u) {
                    z[1] = (x1 - x2) - mz[1];
                }
            }
            for (unsigned i = 0; i < P; i++) {
                for (unsigned j = 0; j < P; j++) {
                    v[i * P + j] = z[i] * x[j];
                }
                v[P * P + i] = z[i] * t;
            }
            acc_add(&a, v);
        }
        if (th_ls != NULL) {
            aux_advance(c, th_ls, k, l, &x1, &x2);
        }
    }
    acc_end(&a);
    for (unsigned i = 0; i < P; i++) {
        for (unsigned j = 0; j < P; j++) {
            S[i][j] = a.tot[i * P + j];
        }
        r[i] = a.tot[P * P + i];
    }
}

/* Mean squared one-step residual of th over the window. */
static pdt_real_t ls_residual(const pdt_ls_t *c, size_t l, const pdt_real_t *m,
                              const pdt_real_t *th)
{
    const unsigned P = 2u * order_of(c);
    pdt_real_t t;
    pdt_real_t x[LS_PMAX];
    pdt_real_t e;
    ls_acc_t a;
    acc_start(&a, 1u);
    for (size_t k = c->k0; k < c->n; k++) {
        ls_row(c, k, l, &t, x);
        e = t - m[0];
        for (unsigned j = 0; j < P; j++) {
            e -= th[j] * (x[j] - m[1u + j]);
        }
        e *= e;
        acc_add(&a, &e);
    }
    acc_end(&a);
    return a.tot[0] / (pdt_real_t)(c->n - c->k0);
}

/* True when the auxiliary model th is asymptotically stable, so its
 * simulation stays bounded (Jury's conditions in the delta parameters). */
static bool aux_stable(const pdt_ls_t *c, const pdt_real_t *th)
{
    if (order_of(c) == 1u) {
        return th[0] < PDT_R(0.0) && th[0] > PDT_R(-2.0);
    }
    return th[1] < PDT_R(1.0) && th[1] > PDT_R(-1.0) && th[0] < PDT_R(0.0) &&
           th[0] > PDT_R(-2.0) - PDT_R(2.0) * th[1];
}

/* The continuous SOPDT's a and b (s^2 + a s + b) of the delta
 * parameters p and q, from the discrete poles z = 1 + w with
 * w^2 - h w - p = 0. False when they are not the poles of a stable
 * continuous model sampled (a real pole outside (0, 1), |z| >= 1). */
static bool ls_poles(pdt_real_t Ts, pdt_real_t p, pdt_real_t q, pdt_real_t *a, pdt_real_t *b)
{
    const pdt_real_t a1 = -(PDT_R(1.0) + p + q);
    /* The small w near a pole at 1 comes from the product of the roots,
     * without cancellation. */
    const pdt_real_t h = p + q - PDT_R(1.0);
    const pdt_real_t disc = h * h + PDT_R(4.0) * p;
    if (disc >= PDT_R(0.0)) {
        pdt_real_t sq = pdt_sqrt(disc);
        pdt_real_t wb = PDT_R(0.5) * (h < PDT_R(0.0) ? h - sq : h + sq);
        pdt_real_t ws;
        if (wb == PDT_R(0.0)) {
            return false;
        }
        ws = -p / wb;
        if (!(wb > PDT_R(-1.0) && wb < PDT_R(0.0) && ws > PDT_R(-1.0) && ws < PDT_R(0.0))) {
            return false;
        }
        pdt_real_t s1 = pdt_log1p(wb) / Ts;
        pdt_real_t s2 = pdt_log1p(ws) / Ts;
        *a = -(s1 + s2);
        *b = s1 * s2;
    } else {
        /* |z|^2 = a2 = q; arg z from (-a1 +/- j sqrt(-disc)) / 2. */
        if (!(q < PDT_R(1.0) && q > PDT_R(0.0))) {
            return false;
        }
        pdt_real_t sigma = PDT_R(-0.5) * pdt_log(q) / Ts;
        pdt_real_t wd = pdt_atan2(pdt_sqrt(-disc), -a1) / Ts;
        *a = PDT_R(2.0) * sigma;
        *b = sigma * sigma + wd * wd;
    }
    return true;
}

/* The continuous model, the discrete model and the operating point of the
 * estimate th at delay l (window means m). Returns false, *r untouched,
 * when the estimate has no continuous form. */
static bool ls_form(const pdt_ls_t *c, size_t l, const pdt_real_t *m, const pdt_real_t *th,
                    pdt_ls_result_t *r)
{
    const pdt_real_t Ts = c->cfg.Ts;
    const pdt_real_t p = th[0];
    pdt_ls_result_t o;
    pdt_real_t cc = m[0];
    for (unsigned j = 0; j < 2u * order_of(c); j++) {
        cc -= th[j] * m[1u + j];
    }
    /* Every accepted estimate has A(1) = -p > 0. */
    if (!(p < PDT_R(0.0))) {
        return false;
    }
    /* The continuous model by its lags, made of the configured kind. */
    pdt_model_view_t v = {order_of(c), PDT_R(0.0), PDT_R(0.0),
                          PDT_R(0.0),  PDT_R(0.0), (pdt_real_t)l * Ts};
    o.dmodel.delay = l;
    o.dmodel.b[2] = PDT_R(0.0);
    o.u0 = c->u[0];
    o.y0 = c->y[0] - cc / p;
    o.delay = l;
    o.cost = PDT_R(0.0);
    o.skipped = 0u;
    if (order_of(c) == 1u) {
        if (!(p > PDT_R(-1.0))) {
            return false;
        }
        v.tau = -Ts / pdt_log1p(p);
        v.K = -th[1] / p;
        o.dmodel.order = 1u;
        o.dmodel.a[0] = -(PDT_R(1.0) + p);
        o.dmodel.a[1] = PDT_R(0.0);
        o.dmodel.b[0] = th[1];
        o.dmodel.b[1] = PDT_R(0.0);
        o.dmodel.d[0] = -p;
        o.dmodel.d[1] = PDT_R(0.0);
    } else {
        const pdt_real_t q = th[1];
        const pdt_real_t a1 = -(PDT_R(1.0) + p + q);
        pdt_real_t a, b;
        if (!ls_poles(Ts, p, q, &a, &b)) {
            return false;
        }
        v.a = a;
        v.b = b;
        v.K = (-th[2] / p) * b;
        o.dmodel.order = 2u;
        o.dmodel.a[0] = a1;
        o.dmodel.a[1] = q;
        o.dmodel.b[0] = th[3];
        o.dmodel.b[1] = th[2] - th[3];
        o.dmodel.d[0] = PDT_R(1.0) - p - q;
        o.dmodel.d[1] = -p;
    }
    pdt_model_from_view(c->cfg.model, &v, &o.model);
    if (pdt_model_check(&o.model) != PDT_OK || !pdt_finite(o.y0)) {
        return false;
    }
    *r = o;
    return true;
}

/* Fits delay l with the configured method; on LS_FIT_OK fills *r (cost
 * included). */
static ls_fit_status_t ls_fit(const pdt_ls_t *c, size_t l, pdt_ls_result_t *r)
{
    const unsigned P = 2u * order_of(c);
    pdt_real_t m[LS_PMAX + 1u];
    pdt_real_t S[LS_PMAX][LS_PMAX];
    pdt_real_t rhs[LS_PMAX];
    pdt_real_t cs[LS_PMAX];
    pdt_real_t th[LS_PMAX];
    ls_means(c, l, m);
    ls_products(c, l, m, NULL, NULL, S, rhs);
    for (unsigned j = 0; j < P; j++) {
        if (!(S[j][j] > PDT_R(0.0))) {
            return LS_FIT_SINGULAR;
        }
        cs[j] = PDT_R(1.0) / pdt_sqrt(S[j][j]);
    }
    if (!ls_solve(S, rhs, cs, P, th)) {
        return LS_FIT_SINGULAR;
    }
    if (c->cfg.method == PDT_LS_EIV) {
        pdt_real_t mz[2];
        pdt_real_t th_ls[LS_PMAX];
        if (!aux_stable(c, th)) {
            return LS_FIT_NOFORM;
        }
        for (unsigned j = 0; j < P; j++) {
            th_ls[j] = th[j];
        }
        iv_means(c, l, th_ls, mz);
        ls_products(c, l, m, th_ls, mz, S, rhs);
        if (!ls_solve(S, rhs, cs, P, th)) {
            return LS_FIT_SINGULAR;
        }
    }
    pdt_real_t cost = ls_residual(c, l, m, th);
    if (!pdt_finite(cost) || !ls_form(c, l, m, th, r)) {
        return LS_FIT_NOFORM;
    }
    r->cost = cost;
    return LS_FIT_OK;
}

void pdt_ls_config_default(pdt_ls_config_t *cfg)
{
    if (cfg == NULL) {
        return;
    }
    cfg->model = PDT_MODEL_FOPDT;
    cfg->method = PDT_LS_ELMS;
    cfg->Ts = PDT_R(0.0);
    cfg->delay_min = 0u;
    cfg->delay_max = PDT_DELAY_QUARTER;
    cfg->whole_record = false;
}

pdt_status_t pdt_ls_init(pdt_ls_t *ctx, const pdt_ls_config_t *cfg, const pdt_real_t *u,
                         const pdt_real_t *y, size_t n)
{
    if (ctx == NULL || cfg == NULL || u == NULL || y == NULL) {
        return PDT_ERR_ARG;
    }
    if (!pdt_finite(cfg->Ts) || !(cfg->Ts > PDT_R(0.0))) {
        return PDT_ERR_ARG;
    }
    if (!pdt_model_kind_known(cfg->model)) {
        return PDT_ERR_ARG;
    }
    if (cfg->method != PDT_LS_ELMS && cfg->method != PDT_LS_EIV) {
        return PDT_ERR_ARG;
    }
    const size_t order = (size_t)pdt_model_kind_lags(cfg->model);
    const size_t dmax = pdt_delay_bound(n, cfg->delay_max);
    if (dmax >= n) {
        return PDT_ERR_TOO_SHORT;
    }
    const size_t k0 = cfg->whole_record ? order : dmax + order;
    if (n < k0 || n - k0 < (size_t)PDT_MIN_SAMPLES) {
        return PDT_ERR_TOO_SHORT;
    }
    if (cfg->delay_min > dmax) {
        return PDT_ERR_BOUNDS;
    }
    bool u_moves = false;
    bool y_moves = false;
    for (size_t k = 0; k < n; k++) {
        if (!pdt_finite(u[k]) || !pdt_finite(y[k])) {
            return PDT_ERR_NONFINITE;
        }
        u_moves = u_moves || u[k] != u[0];
        y_moves = y_moves || y[k] != y[0];
    }
    if (!u_moves || !y_moves) {
        return PDT_ERR_NO_EXCITATION;
    }
    pdt_ls_t c;
    c.cfg = *cfg;
    c.cfg.delay_max = dmax;
    c.u = u;
    c.y = y;
    c.n = n;
    c.k0 = k0;
    c.magic = LS_MAGIC;
    c.done = false;
    c.next = cfg->delay_min;
    c.singular = 0u;
    c.noform = 0u;
    c.found = false;
    c.best.cost = PDT_R(0.0);
    c.scores = NULL;
    *ctx = c;
    return PDT_OK;
}

pdt_status_t pdt_ls_step(pdt_ls_t *ctx, size_t max_delays)
{
    if (ctx == NULL || max_delays == 0u) {
        return PDT_ERR_ARG;
    }
    if (ctx->magic != LS_MAGIC) {
        return PDT_ERR_STATE;
    }
    for (size_t i = 0; i < max_delays && !ctx->done; i++) {
        const size_t l = ctx->next;
        pdt_ls_result_t r;
        pdt_real_t score = (pdt_real_t)INFINITY;
        switch (ls_fit(ctx, l, &r)) {
        case LS_FIT_OK:
            score = r.cost;
            if (!ctx->found || r.cost < ctx->best.cost) {
                ctx->best = r;
                ctx->found = true;
            }
            break;
        case LS_FIT_SINGULAR:
            ctx->singular++;
            break;
        default:
            ctx->noform++;
            break;
        }
        if (ctx->scores != NULL) {
            ctx->scores[l - ctx->cfg.delay_min] = score;
        }
        if (l == ctx->cfg.delay_max) {
            ctx->done = true;
        } else {
            ctx->next = l + 1u;
        }
    }
    return ctx->done ? PDT_OK : PDT_RUNNING;
}

pdt_status_t pdt_ls_scores(pdt_ls_t *ctx, pdt_real_t *scores, size_t len)
{
    if (ctx == NULL || scores == NULL) {
        return PDT_ERR_ARG;
    }
    if (ctx->magic != LS_MAGIC || ctx->done || ctx->next != ctx->cfg.delay_min) {
        return PDT_ERR_STATE;
    }
    if (len < ctx->cfg.delay_max - ctx->cfg.delay_min + 1u) {
        return PDT_ERR_LENGTH;
    }
    ctx->scores = scores;
    return PDT_OK;
}

pdt_status_t pdt_ls_result(const pdt_ls_t *ctx, pdt_ls_result_t *out)
{
    if (ctx == NULL || out == NULL) {
        return PDT_ERR_ARG;
    }
    if (ctx->magic != LS_MAGIC || !ctx->done) {
        return PDT_ERR_STATE;
    }
    if (!ctx->found) {
        return ctx->noform > 0u ? PDT_ERR_NO_FORM : PDT_ERR_NO_EXCITATION;
    }
    pdt_ls_result_t r = ctx->best;
    r.skipped = ctx->singular + ctx->noform;
    *out = r;
    return PDT_OK;
}

pdt_status_t pdt_ls_identify(pdt_ls_t *ctx, const pdt_ls_config_t *cfg, const pdt_real_t *u,
                             const pdt_real_t *y, size_t n, pdt_ls_result_t *out)
{
    if (out == NULL) {
        return PDT_ERR_ARG;
    }
    pdt_status_t st = pdt_ls_init(ctx, cfg, u, y, n);
    if (st != PDT_OK) {
        return st;
    }
    do {
        st = pdt_ls_step(ctx, (size_t)-1);
    } while (st == PDT_RUNNING);
    if (st != PDT_OK) {
        return st;
    }
    return pdt_ls_result(ctx, out);
}
