/*
 * The output-error Fisher information and the covariance it gives; see
 * pdt_fisher.h.
 */
#include "pdt_fisher.h"

#include <string.h>

#include "pdt_discrete_priv.h"
#include "pdt_internal.h"
#include "pdt_model_priv.h"

/* Partial sums over this many samples before they join the total, so that
 * float sums over long records keep their accuracy. */
#define FISHER_BLOCK PDT_FISHER_BLOCK

/* Finite-difference step of parameter i of the vector p
 * (pdt_model_params_get's order; never 0, and upward for b and Td so that
 * the perturbed model stays valid). */
static pdt_real_t fd_step(const pdt_model_t *m, uint32_t i, const pdt_real_t *p, pdt_real_t Ts)
{
    const pdt_model_param_t name = pdt_model_kind_param(m->kind, i);
    if (name == PDT_MODEL_PARAM_TD) {
        return PDT_R(0.02) * Ts + PDT_R(1e-3) * p[i];
    }
    if (name == PDT_MODEL_PARAM_B && p[i] == PDT_R(0.0)) {
        /* An integrator: b's scale is that of critical damping, a^2 / 4,
         * with a the parameter before b. */
        return PDT_R(2.5e-4) * p[i - 1u] * p[i - 1u];
    }
    return PDT_R(1e-3) * pdt_fabs(p[i]);
}

/* Inverse of the symmetric positive semi-definite F (n x n) by Gauss-Jordan
 * on its correlation form, pivoting on the diagonal. A parameter whose
 * pivot falls below tol is not determined by the data (the output does
 * not depend on it beyond what the others explain): it is fixed at its
 * estimate, marked in *undet, and the inverse is that of the others (the
 * covariance conditional on it). Returns false when F is not usable at
 * all (a zero or non-finite diagonal: a parameter the output does not
 * see). */
static bool invert(pdt_fisher_matrix_t F, pdt_fisher_matrix_t Inv, uint32_t n, bool *undet)
{
    pdt_real_t dsc[PDT_FISHER_MAX] = {PDT_R(0.0)};
    pdt_real_t M[PDT_FISHER_MAX][2u * PDT_FISHER_MAX];
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

/* e(k - 1 - i) before sample k is added. */
static pdt_real_t lag_back(const pdt_fisher_lags_t *L, size_t i)
{
    const size_t j = L->at + i;
    return L->recent[(PDT_FISHER_RING_TWICE != 0 || j < PDT_FISHER_LAGS) ? j : j - PDT_FISHER_LAGS];
}

PDT_FORCE_INLINE void lags_add(pdt_fisher_lags_t *L, pdt_real_t e, size_t k)
{
#if PDT_FISHER_RING_TWICE
    const pdt_real_t *back = &L->recent[L->at];
    PDT_UNROLL
    for (size_t l = 0; l < PDT_FISHER_LAGS; l += 4u) {
        pdt_vec4_t p, b;
        (void)memcpy(&p, &L->prod[l], sizeof p);
        (void)memcpy(&b, &back[l], sizeof b);
        p += PDT_VEC4(e) * b;
        (void)memcpy(&L->prod[l], &p, sizeof p);
    }
#else
    const size_t run = PDT_FISHER_LAGS - L->at; /* the lags before the wrap */
    size_t l = 0;
    for (; l < run; l++) {
        L->prod[l] += e * L->recent[L->at + l];
    }
    for (; l < PDT_FISHER_LAGS; l++) {
        L->prod[l] += e * L->recent[l - run];
    }
#endif
    L->at = (L->at == 0u) ? PDT_FISHER_LAGS - 1u : L->at - 1u;
    L->recent[L->at] = e;
#if PDT_FISHER_RING_TWICE
    L->recent[L->at + PDT_FISHER_LAGS] = e;
#endif
    L->part_sum += e;
    if (k < PDT_FISHER_LAGS) {
        L->first[k + 1u] = L->first[k] + e;
    }
}

static void lags_flush(pdt_fisher_lags_t *L)
{
    L->sum += L->part_sum;
    L->part_sum = PDT_R(0.0);
}

/* The autocorrelations of e - mean e from the raw sums: lag l's products
 * of the mean-free residual are prod - m (sum of the later n - l + sum of
 * the earlier n - l) + (n - l) m^2. */
static void lags_rho(const pdt_fisher_lags_t *L, size_t n, pdt_real_t sse, pdt_real_t *rho)
{
    const pdt_real_t m = L->sum / (pdt_real_t)n;
    const pdt_real_t r0 = sse - (pdt_real_t)n * m * m;
    pdt_real_t tail = PDT_R(0.0); /* the last l residuals */
    for (size_t l = 1; l <= PDT_FISHER_LAGS; l++) {
        rho[l - 1u] = PDT_R(0.0);
        if (l >= n) {
            continue;
        }
        tail += lag_back(L, l - 1u); /* e(n - l) */
        const pdt_real_t later = L->sum - L->first[l];
        const pdt_real_t earlier = L->sum - tail;
        const pdt_real_t s = L->prod[l - 1u] - m * (later + earlier) + (pdt_real_t)(n - l) * m * m;
        rho[l - 1u] = r0 > PDT_R(0.0) ? s / r0 : PDT_R(0.0);
    }
}

/* The input term of model d at sample k once every input tap has
 * arrived (k >= delay + 3): pdt_discrete_input's sum without its tests,
 * the same operations in the same order. */
PDT_FORCE_INLINE pdt_real_t input_full(const pdt_discrete_t *d, const pdt_real_t *u, pdt_real_t u0,
                                       size_t k)
{
    const pdt_real_t *uj = &u[k - d->delay - 3u];
    pdt_real_t s = PDT_R(0.0) + d->b[0] * (uj[2] - u0);
    s += d->b[1] * (uj[1] - u0);
    return s + d->b[2] * (uj[0] - u0);
}

/* Model i of the pass advanced to sample k, its output. full: every
 * input tap has arrived. */
PDT_FORCE_INLINE pdt_real_t model_at(pdt_fisher_pass_t *P, uint32_t i, const pdt_real_t *u,
                                     size_t k, bool full)
{
    const pdt_discrete_t *d = &P->d[i];
    pdt_discrete_state_t *s = &P->s[i];
    if (!full) {
        return pdt_discrete_advance(d, s, u, P->u0, k);
    }
    if (d->order == 1u) {
        s->y1 = s->y1 - d->d[0] * s->y1 + input_full(d, u, P->u0, k);
        return s->y1;
    }
    s->dy = s->dy - d->d[0] * s->dy - d->d[1] * s->y2 + input_full(d, u, P->u0, k);
    s->y2 = s->y1;
    s->y1 = s->y1 + s->dy;
    return s->y1;
}

/* One sample k into the pass: the models advanced, the Jacobian's row
 * into part, the residual into *sp and the lags, whether the nominal
 * output is finite into *finite. nm, the model's
 * parameters, is a constant at each fast call, so that the loops over
 * them unroll. */
PDT_FORCE_INLINE void fisher_sample(pdt_fisher_pass_t *P, pdt_fisher_matrix_t part,
                                    pdt_fisher_lags_t *L, pdt_real_t *sp, bool *finite,
                                    const pdt_real_t *u, const pdt_real_t *y, pdt_real_t y0,
                                    size_t k, bool full, uint32_t nm)
{
    pdt_real_t jr[PDT_FISHER_MAX];
    const pdt_real_t ys = model_at(P, 0u, u, k, full);
    *finite = *finite && pdt_finite(ys);
    jr[0] = ys / P->gain;
    PDT_UNROLL
    for (uint32_t i = 1; i < nm; i++) {
        jr[i] = (model_at(P, i, u, k, full) - ys) / P->h[i];
    }
    jr[nm] = PDT_R(1.0);
    PDT_UNROLL
    for (uint32_t i = 0; i <= nm; i++) {
        PDT_UNROLL
        for (uint32_t j = i; j <= nm; j++) {
            part[i][j] += jr[i] * jr[j];
        }
    }
    const pdt_real_t e = y[k] - y0 - ys;
    *sp += e * e;
    lags_add(L, e, k);
}

pdt_status_t pdt_fisher_begin(pdt_fisher_run_t *R, const pdt_model_t *m, pdt_real_t Ts,
                              const pdt_real_t *u, const pdt_real_t *y, size_t n, pdt_real_t y0,
                              pdt_real_t u0, pdt_fisher_matrix_t F)
{
    pdt_real_t p[4] = {PDT_R(0.0), PDT_R(0.0), PDT_R(0.0), PDT_R(0.0)};
    const uint32_t nm = pdt_model_params_get(m, p);
    const uint32_t nj = nm + 1u;
    /* The nominal model, then one per shape parameter: the gain enters
     * linearly (ys / K), the offset as a constant. */
    pdt_fisher_pass_t *const P = &R->P;
    *P = (pdt_fisher_pass_t){.gain = p[0], .u0 = u0};
    if (P->gain == PDT_R(0.0) || pdt_discrete_init(m, Ts, &P->d[0]) != PDT_OK) {
        return PDT_ERR_ARG;
    }
    /* From this sample on every model's input taps have arrived. */
    size_t full = P->d[0].delay;
    for (uint32_t i = 1; i < nm; i++) {
        pdt_real_t pp[4] = {p[0], p[1], p[2], p[3]};
        pp[i] += fd_step(m, i, p, Ts);
        P->h[i] = pp[i] - p[i];
        pdt_model_t mp = *m;
        pdt_model_params_set(&mp, pp);
        if (!(P->h[i] > PDT_R(0.0)) || pdt_discrete_init(&mp, Ts, &P->d[i]) != PDT_OK) {
            return PDT_ERR_ARG;
        }
        full = P->d[i].delay > full ? P->d[i].delay : full;
    }
    R->full = (n > 3u && full < n - 3u) ? full + 3u : n;
    R->L =
        (pdt_fisher_lags_t){{PDT_R(0.0)}, {PDT_R(0.0)}, {PDT_R(0.0)}, PDT_R(0.0), PDT_R(0.0), 0u};
    R->F = F;
    R->u = u;
    R->y = y;
    R->n = n;
    R->next = 0u;
    R->y0 = y0;
    R->se = PDT_R(0.0);
    R->nm = nm;
    R->finite = true;
    for (uint32_t i = 0; i < nj; i++) {
        for (uint32_t j = 0; j < nj; j++) {
            F[i][j] = PDT_R(0.0);
        }
    }
    return PDT_OK;
}

/* Blocks of FISHER_BLOCK samples: a block's sums join the totals at its
 * end. For speed, the samples from `full` on take the straight input, with
 * the parameters' count a constant in each loop; for size, one loop takes
 * the tested input throughout (the same numbers). */
bool pdt_fisher_block(pdt_fisher_run_t *R)
{
    const size_t n = R->n;
    const size_t first = R->next;
    if (first >= n) {
        return true;
    }
    /* nm is 3 or 4 (pdt_fisher_begin); the bound says so to the
     * compiler, which otherwise sees model_at index past the pass's four
     * models. */
    const uint32_t nm = (R->nm < 4u) ? R->nm : 4u;
    const uint32_t nj = nm + 1u;
    const pdt_real_t *const u = R->u;
    const pdt_real_t *const y = R->y;
    const pdt_real_t y0 = R->y0;
    const size_t full = R->full;
    pdt_fisher_pass_t *const P = &R->P;
    pdt_fisher_lags_t *const L = &R->L;
    pdt_fisher_matrix_t part = {{PDT_R(0.0)}};
    pdt_real_t sp = PDT_R(0.0); /* the block's residual sum of squares */
    bool finite = R->finite;
    const size_t stop = (n - first > FISHER_BLOCK) ? first + FISHER_BLOCK : n;
    size_t k = first;
#if PDT_SPEED_OVER_SIZE
    for (; k < stop && k < full; k++) {
        fisher_sample(P, part, L, &sp, &finite, u, y, y0, k, false, nm);
    }
    if (nm == 3u) {
        for (; k < stop; k++) {
            fisher_sample(P, part, L, &sp, &finite, u, y, y0, k, true, 3u);
        }
    } else {
        for (; k < stop; k++) {
            fisher_sample(P, part, L, &sp, &finite, u, y, y0, k, true, 4u);
        }
    }
#else
    (void)full;
    for (; k < stop; k++) {
        fisher_sample(P, part, L, &sp, &finite, u, y, y0, k, false, nm);
    }
#endif
    for (uint32_t i = 0; i < nj; i++) {
        for (uint32_t j = i; j < nj; j++) {
            R->F[i][j] += part[i][j];
        }
    }
    R->se += sp;
    lags_flush(L);
    R->finite = finite;
    R->next = stop;
    return stop >= n;
}

pdt_status_t pdt_fisher_end(pdt_fisher_run_t *R, pdt_fisher_sums_t *out)
{
    if (!R->finite) {
        return PDT_ERR_NONFINITE;
    }
    const uint32_t nj = R->nm + 1u;
    for (uint32_t i = 0; i < nj; i++) {
        for (uint32_t j = 0; j < i; j++) {
            R->F[i][j] = R->F[j][i];
        }
    }
    out->sse = R->se;
    out->np = nj;
    lags_rho(&R->L, R->n, R->se, out->rho);
    return PDT_OK;
}

pdt_status_t pdt_fisher_sum(const pdt_model_t *m, pdt_real_t Ts, const pdt_real_t *u,
                            const pdt_real_t *y, size_t n, pdt_real_t y0, pdt_real_t u0,
                            pdt_fisher_matrix_t F, pdt_fisher_sums_t *out)
{
    pdt_fisher_run_t R;
    pdt_status_t st = pdt_fisher_begin(&R, m, Ts, u, y, n, y0, u0, F);
    if (st != PDT_OK) {
        return st;
    }
    while (!pdt_fisher_block(&R)) {
    }
    return pdt_fisher_end(&R, out);
}

pdt_real_t pdt_fisher_inflation(const pdt_fisher_sums_t *s)
{
    pdt_real_t infl = PDT_R(1.0);
    for (size_t l = 0; l < PDT_FISHER_LAGS; l++) {
        infl += PDT_R(2.0) * s->rho[l];
    }
    return infl > PDT_R(1.0) ? infl : PDT_R(1.0);
}

void pdt_fisher_covariance(pdt_fisher_matrix_t F, uint32_t np, size_t n, pdt_real_t sse,
                           pdt_real_t inflation, pdt_real_t *sd, pdt_fisher_matrix_t cov)
{
    pdt_fisher_matrix_t Inv;
    const pdt_real_t s2 = sse / (pdt_real_t)(n - np) * inflation;
    bool undet[PDT_FISHER_MAX];
    const bool ok = invert(F, Inv, np, undet);
    for (uint32_t i = 0; i < np; i++) {
        for (uint32_t j = 0; j < np; j++) {
            cov[i][j] = ok ? s2 * Inv[i][j] : (pdt_real_t)INFINITY;
        }
        /* An undetermined parameter: std +infinity, covariance 0 (the
         * others' covariance is conditional on it). */
        const bool fin = ok && !undet[i] && cov[i][i] >= PDT_R(0.0);
        sd[i] = fin ? pdt_sqrt(cov[i][i]) : (pdt_real_t)INFINITY;
    }
}
