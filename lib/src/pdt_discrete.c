/*
 * pdtfit discretisation: exact ZOH models with a fractional dead time, and
 * their simulation and one-step prediction.
 *
 * The denominator is built from the poles with expm1 and half-angle forms, so
 * that its delta form d[] (the numbers that set the gain when the poles are
 * close to 1) keeps full relative accuracy; the numerator comes from samples
 * of the delay-free step response (pdt_model_sopdt_unit_step), itself free of
 * cancellation at small times.
 */
#include "pdt/pdt_discrete.h"

#include "pdt_discrete_priv.h"
#include "pdt_internal.h"
#include "pdt_model_priv.h"

/* Splits Td/Ts into whole samples l and a fraction f in [0, 1). A fraction
 * within rounding of 1 means Td was meant as a whole number of samples. */
static pdt_status_t split_delay(pdt_real_t Td, pdt_real_t Ts, size_t *l, pdt_real_t *f)
{
    pdt_real_t r = Td / Ts;
    if (!(pdt_finite(r) && r < (pdt_real_t)SIZE_MAX)) {
        return PDT_ERR_ARG;
    }
    pdt_real_t whole = pdt_floor(r);
    pdt_real_t frac = r - whole;
    pdt_real_t tol = PDT_R(8.0) * PDT_REAL_EPS * (PDT_R(1.0) + r);
    if (frac >= PDT_R(1.0) - tol) {
        whole += PDT_R(1.0);
        frac = PDT_R(0.0);
        if (!(whole < (pdt_real_t)SIZE_MAX)) {
            return PDT_ERR_ARG;
        }
    }
    *l = (size_t)whole;
    *f = frac;
    return PDT_OK;
}

/* e^{-x} from em = e^{-x} - 1 where 1 + em keeps its accuracy (x below
 * a half: |em| < 0.4), else by its own call. The evaluation discretises
 * every candidate, and most have Ts well below their time constant. */
static pdt_real_t exp_from_expm1(pdt_real_t x, pdt_real_t em)
{
    return x < PDT_R(0.5) ? PDT_R(1.0) + em : pdt_exp(-x);
}

/* One lag: alpha = e^{-Ts/tau}, b0 = K (1 - alpha^m), b1 = K alpha^m (1 - alpha^f). */
static void zoh_lag(const pdt_model_view_t *p, pdt_real_t Ts, pdt_real_t f, pdt_discrete_t *out)
{
    pdt_real_t x = Ts / p->tau;
    pdt_real_t m = PDT_R(1.0) - f;
    pdt_real_t e1 = pdt_expm1(-x);
    pdt_real_t em = pdt_expm1(-m * x);
    out->order = 1u;
    out->a[0] = -exp_from_expm1(x, e1);
    out->a[1] = PDT_R(0.0);
    out->d[0] = -e1;
    out->d[1] = PDT_R(0.0);
    out->b[0] = -p->K * em;
    out->b[1] = -p->K * exp_from_expm1(m * x, em) * pdt_expm1(-f * x);
    out->b[2] = PDT_R(0.0);
}

/* Two lags, any pole pair. Poles at -(sigma +/- sqrt(sigma^2 - b)). */
static void zoh_pair(const pdt_model_view_t *p, pdt_real_t Ts, pdt_real_t f, pdt_discrete_t *out)
{
    pdt_real_t sigma = PDT_R(0.5) * p->a;
    pdt_real_t disc = sigma * sigma - p->b;
    pdt_real_t a0;
    pdt_real_t a1;
    pdt_real_t d0;
    pdt_real_t d1;
    if (disc >= PDT_R(0.0)) {
        /* Real poles z_i = e^{-l_i Ts}; 1 - z_i = -expm1(-l_i Ts). The slow
         * pole from the product of the poles (= b) so it does not cancel. */
        pdt_real_t l2 = sigma + pdt_sqrt(disc);
        pdt_real_t l1 = p->b / l2;
        pdt_real_t e1 = pdt_expm1(-l1 * Ts);
        pdt_real_t e2 = pdt_expm1(-l2 * Ts);
        d0 = -(e1 + e2);
        d1 = e1 * e2;
        a0 = -(PDT_R(2.0) + e1 + e2);
        /* a1 = e^{-a Ts} = z1 z2 */
        a1 = exp_from_expm1(l1 * Ts, e1) * exp_from_expm1(l2 * Ts, e2);
    } else {
        /* z = e^{-sigma Ts} e^{+/- j wd Ts}: 1 - 2 E cos + E^2 written as
         * (1 - E)^2 + 4 E sin^2(wd Ts / 2), and 2 - 2 E cos likewise. */
        pdt_real_t wd = pdt_sqrt(-disc);
        pdt_real_t em = pdt_expm1(-sigma * Ts);
        pdt_real_t e = exp_from_expm1(sigma * Ts, em);
        pdt_real_t s = pdt_sin(PDT_R(0.5) * wd * Ts);
        pdt_real_t q = PDT_R(4.0) * e * s * s;
        d0 = q - PDT_R(2.0) * em;
        d1 = em * em + q;
        a0 = PDT_R(-2.0) * e * pdt_cos(wd * Ts);
        a1 = e * e; /* e^{-a Ts}, a = 2 sigma */
    }

    /* Numerator from the delay-free step response at m Ts, (1+m) Ts,
     * (2+m) Ts (m = 1 - f): with g the increments of those samples,
     * b0 = g1, b1 = g2 + a0 g1, b2 = g3 + a0 g2 + a1 g1. */
    pdt_real_t m = PDT_R(1.0) - f;
    pdt_real_t h[3];
    for (size_t i = 0; i < 3u; i++) {
        h[i] = p->K * pdt_model_sopdt_unit_step(p->a, p->b, ((pdt_real_t)i + m) * Ts);
    }
    pdt_real_t g1 = h[0];
    pdt_real_t g2 = h[1] - h[0];
    pdt_real_t g3 = h[2] - h[1];

    out->order = 2u;
    out->a[0] = a0;
    out->a[1] = a1;
    out->d[0] = d0;
    out->d[1] = d1;
    out->b[0] = g1;
    out->b[1] = g2 + a0 * g1;
    out->b[2] = g3 + a0 * g2 + a1 * g1;
}

static pdt_status_t zoh(const pdt_model_t *m, pdt_real_t Ts, size_t l, pdt_real_t f,
                        pdt_discrete_t *out)
{
    pdt_discrete_t r;
    pdt_model_view_t v;
    pdt_model_view(m, &v);
    r.delay = l;
    if (v.lags == 1u) {
        zoh_lag(&v, Ts, f, &r);
    } else {
        zoh_pair(&v, Ts, f, &r);
    }
    for (size_t i = 0; i < 3u; i++) {
        if (!pdt_finite(r.b[i])) {
            return PDT_ERR_ARG; /* parameters so extreme that a number overflows */
        }
    }
    *out = r;
    return PDT_OK;
}

static bool ts_valid(pdt_real_t Ts)
{
    return pdt_finite(Ts) && Ts > PDT_R(0.0);
}

pdt_status_t pdt_discrete_init(const pdt_model_t *m, pdt_real_t Ts, pdt_discrete_t *out)
{
    if (out == NULL || !ts_valid(Ts) || pdt_model_check(m) != PDT_OK) {
        return PDT_ERR_ARG;
    }
    /* pdt_discrete_init_checked's lines, not a call: a frame fewer on the
     * deepest stack chains (tools/stack_bound.py). */
    size_t l;
    pdt_real_t f;
    if (split_delay(pdt_model_dead_time(m), Ts, &l, &f) != PDT_OK) {
        return PDT_ERR_ARG;
    }
    return zoh(m, Ts, l, f, out);
}

pdt_status_t pdt_discrete_init_checked(const pdt_model_t *m, pdt_real_t Ts, pdt_discrete_t *out)
{
    size_t l;
    pdt_real_t f;
    if (split_delay(pdt_model_dead_time(m), Ts, &l, &f) != PDT_OK) {
        return PDT_ERR_ARG;
    }
    return zoh(m, Ts, l, f, out);
}

pdt_status_t pdt_discrete_init_int(const pdt_model_t *m, pdt_real_t Ts, size_t l,
                                   pdt_discrete_t *out)
{
    if (out == NULL || !ts_valid(Ts) || pdt_model_check(m) != PDT_OK) {
        return PDT_ERR_ARG;
    }
    return zoh(m, Ts, l, PDT_R(0.0), out);
}

/* ---- simulation and prediction ------------------------------------------ */

static bool dmodel_valid(const pdt_discrete_t *d)
{
    return d != NULL && (d->order == 1u || d->order == 2u);
}

/* u - 0 is u exactly: the simulation's start is the step's input. */
static pdt_real_t input_at_start(const pdt_discrete_t *d, const pdt_real_t *u, size_t k)
{
    return pdt_discrete_input(d, u, PDT_R(0.0), k);
}

static size_t start_len(const pdt_discrete_t *d, size_t n)
{
    if (d->delay >= n || n - d->delay <= 3u) {
        return n;
    }
    return d->delay + 3u;
}

pdt_status_t pdt_discrete_simulate(const pdt_discrete_t *d, const pdt_real_t *u, size_t n,
                                   pdt_real_t *y)
{
    if (!dmodel_valid(d) || u == NULL || y == NULL) {
        return PDT_ERR_ARG;
    }
    const size_t head = start_len(d, n);
    const size_t l = d->delay;
    const pdt_real_t b0 = d->b[0];
    const pdt_real_t b1 = d->b[1];
    const pdt_real_t b2 = d->b[2];
    const pdt_real_t d0 = d->d[0];
    /* The increment dy = y(k) - y(k-1) is carried as a state of its own:
     * with poles near 1 it is much smaller than y and would lose its low
     * bits if it were recomputed from two rounded outputs. */
    pdt_real_t y1 = PDT_R(0.0);
    if (d->order == 1u) {
        for (size_t k = 0; k < head; k++) {
            y1 = y1 - d0 * y1 + input_at_start(d, u, k);
            y[k] = y1;
        }
        for (size_t k = head; k < n; k++) {
            const pdt_real_t *uk = &u[k - l - 3u];
            y1 = y1 - d0 * y1 + (b0 * uk[2] + b1 * uk[1] + b2 * uk[0]);
            y[k] = y1;
        }
        return PDT_OK;
    }
    const pdt_real_t d1 = d->d[1];
    pdt_real_t dy = PDT_R(0.0);
    pdt_real_t y2 = PDT_R(0.0);
    for (size_t k = 0; k < head; k++) {
        dy = dy - d0 * dy - d1 * y2 + input_at_start(d, u, k);
        y2 = y1;
        y1 = y1 + dy;
        y[k] = y1;
    }
    for (size_t k = head; k < n; k++) {
        const pdt_real_t *uk = &u[k - l - 3u];
        dy = dy - d0 * dy - d1 * y2 + (b0 * uk[2] + b1 * uk[1] + b2 * uk[0]);
        y2 = y1;
        y1 = y1 + dy;
        y[k] = y1;
    }
    return PDT_OK;
}

pdt_status_t pdt_discrete_predict(const pdt_discrete_t *d, const pdt_real_t *u, const pdt_real_t *y,
                                  size_t n, pdt_real_t *yhat)
{
    if (!dmodel_valid(d) || u == NULL || y == NULL || yhat == NULL) {
        return PDT_ERR_ARG;
    }
    const size_t head = start_len(d, n);
    const size_t l = d->delay;
    const pdt_real_t b0 = d->b[0];
    const pdt_real_t b1 = d->b[1];
    const pdt_real_t b2 = d->b[2];
    const pdt_real_t d0 = d->d[0];
    if (d->order == 1u) {
        for (size_t k = 0; k < head; k++) {
            pdt_real_t y1 = k >= 1u ? y[k - 1u] : PDT_R(0.0);
            yhat[k] = y1 - d0 * y1 + input_at_start(d, u, k);
        }
        for (size_t k = head; k < n; k++) {
            const pdt_real_t *uk = &u[k - l - 3u];
            pdt_real_t y1 = y[k - 1u];
            yhat[k] = y1 - d0 * y1 + (b0 * uk[2] + b1 * uk[1] + b2 * uk[0]);
        }
        return PDT_OK;
    }
    const pdt_real_t d1 = d->d[1];
    for (size_t k = 0; k < head; k++) {
        pdt_real_t y1 = k >= 1u ? y[k - 1u] : PDT_R(0.0);
        pdt_real_t y2 = k >= 2u ? y[k - 2u] : PDT_R(0.0);
        pdt_real_t dy = y1 - y2;
        yhat[k] = y1 + (dy - d0 * dy - d1 * y2 + input_at_start(d, u, k));
    }
    /* head >= 3 whenever this loop runs, so y[k - 2] exists */
    for (size_t k = head; k < n; k++) {
        const pdt_real_t *uk = &u[k - l - 3u];
        pdt_real_t y1 = y[k - 1u];
        pdt_real_t y2 = y[k - 2u];
        pdt_real_t dy = y1 - y2;
        yhat[k] = y1 + (dy - d0 * dy - d1 * y2 + (b0 * uk[2] + b1 * uk[1] + b2 * uk[0]));
    }
    return PDT_OK;
}

pdt_real_t pdt_discrete_step(const pdt_discrete_t *d, pdt_discrete_state_t *s, const pdt_real_t *u,
                             pdt_real_t u0, size_t k)
{
    return pdt_discrete_advance(d, s, u, u0, k);
}
