/*
 * pdtfit model reduction: Skogestad's half rule and Sung et al.'s
 * frequency-response method. Equations and conventions: docs/reduce.md.
 */
#include "pdt/pdt_reduce.h"

#include "pdt_internal.h"
#include "pdt_model_priv.h"

/* Scan of the phase for the ultimate frequency: ratio 2^(1/8) per point. */
#define SCAN_RATIO       PDT_R(1.0905077326652577)
#define SCAN_MAX_POINTS  4096u
#define BISECT_MAX_STEPS 64u

/* Marks a lag that no zero is cancelled against. */
#define NO_ZERO ((size_t)-1)

void pdt_reduce_config_default(pdt_reduce_config_t *cfg)
{
    if (cfg == NULL) {
        return;
    }
    cfg->model = PDT_MODEL_FOPDT;
    cfg->h = PDT_R(0.0);
    cfg->n_freq = 0u;
}

static pdt_status_t check_plant(const pdt_reduce_plant_t *p)
{
    if (p == NULL) {
        return PDT_ERR_ARG;
    }
    if (p->n_lags == 0u) {
        return PDT_ERR_LENGTH;
    }
    if (p->lags == NULL || (p->n_zeros > 0u && p->zeros == NULL)) {
        return PDT_ERR_ARG;
    }
    if (!pdt_finite(p->k) || !pdt_finite(p->theta0)) {
        return PDT_ERR_NONFINITE;
    }
    for (size_t i = 0; i < p->n_lags; i++) {
        if (!pdt_finite(p->lags[i])) {
            return PDT_ERR_NONFINITE;
        }
    }
    for (size_t j = 0; j < p->n_zeros; j++) {
        if (!pdt_finite(p->zeros[j])) {
            return PDT_ERR_NONFINITE;
        }
    }
    if (p->theta0 < PDT_R(0.0)) {
        return PDT_ERR_ARG;
    }
    for (size_t i = 0; i < p->n_lags; i++) {
        if (!(p->lags[i] > PDT_R(0.0))) {
            return PDT_ERR_ARG;
        }
    }
    for (size_t j = 0; j < p->n_zeros; j++) {
        if (p->zeros[j] == PDT_R(0.0)) {
            return PDT_ERR_ARG;
        }
    }
    return PDT_OK;
}

/* Copies cfg (or the defaults) into *c after checking it. */
static pdt_status_t check_config(const pdt_reduce_config_t *cfg, pdt_reduce_config_t *c)
{
    pdt_reduce_config_default(c);
    if (cfg == NULL) {
        c->n_freq = PDT_REDUCE_N_FREQ_DEFAULT;
        return PDT_OK;
    }
    if (!pdt_model_kind_known(cfg->model)) {
        return PDT_ERR_ARG;
    }
    if (!pdt_finite(cfg->h)) {
        return PDT_ERR_NONFINITE;
    }
    if (cfg->h < PDT_R(0.0)) {
        return PDT_ERR_ARG;
    }
    *c = *cfg;
    if (c->n_freq == 0u) {
        c->n_freq = PDT_REDUCE_N_FREQ_DEFAULT;
    }
    return PDT_OK;
}

/* ------------------------------------------------------------------------ */
/* Half rule                                                                */

/* Sorts l[0..n-1] into descending order (insertion sort: n is small). */
static void sort_descending(pdt_real_t *l, size_t n)
{
    for (size_t i = 1; i < n; i++) {
        pdt_real_t v = l[i];
        size_t j = i;
        while (j > 0u && l[j - 1u] < v) {
            l[j] = l[j - 1u];
            j--;
        }
        l[j] = v;
    }
}

/* The half rule proper on lags l[0..n-1] sorted descending: time constants
 * t[0] (and t[1] for order 2) and the dead time base + what the lags beyond
 * the model's order give. Lags missing for the order count as 0. */
static pdt_real_t half_split(const pdt_real_t *l, size_t n, size_t order, pdt_real_t base,
                             pdt_real_t t[2])
{
    pdt_real_t theta = base;
    t[0] = PDT_R(0.0);
    t[1] = PDT_R(0.0);
    for (size_t i = 0; i < n; i++) {
        if (i < order - 1u) {
            t[i] = l[i];
        } else if (i == order - 1u) {
            t[i] += l[i];
        } else if (i == order) {
            /* the first lag beyond the order is shared half and half */
            t[order - 1u] += PDT_R(0.5) * l[i];
            theta += PDT_R(0.5) * l[i];
        } else {
            theta += l[i];
        }
    }
    return theta;
}

/* Which lag each left-half-plane zero is cancelled against: zero[i] is the
 * index of the zero paired with lag i, or NO_ZERO. The zeros are taken from
 * the largest down, so the most significant one chooses first; each takes
 * the smallest free lag >= T0 (rules T2/T3 then only shorten or remove a lag
 * that dominates the zero anyway), or, when the zero is larger than every
 * free lag, the largest free lag (rules T1). Returns false when a zero finds
 * no free lag. */
static bool pair_zeros(const pdt_reduce_plant_t *p, size_t zero[])
{
    for (size_t i = 0; i < p->n_lags; i++) {
        zero[i] = NO_ZERO;
    }
    size_t prev = NO_ZERO;
    for (;;) {
        /* next zero in descending order of T0 (ties: lower index first) */
        size_t next = NO_ZERO;
        for (size_t j = 0; j < p->n_zeros; j++) {
            pdt_real_t v = p->zeros[j];
            if (v <= PDT_R(0.0)) {
                continue;
            }
            if (prev != NO_ZERO) {
                pdt_real_t pv = p->zeros[prev];
                if (v > pv || (v == pv && j <= prev)) {
                    continue;
                }
            }
            if (next == NO_ZERO || v > p->zeros[next]) {
                next = j;
            }
        }
        if (next == NO_ZERO) {
            return true;
        }
        pdt_real_t T0 = p->zeros[next];
        size_t above = NO_ZERO;
        size_t below = NO_ZERO;
        for (size_t i = 0; i < p->n_lags; i++) {
            pdt_real_t l = p->lags[i];
            if (zero[i] != NO_ZERO) {
                continue;
            }
            if (l >= T0) {
                if (above == NO_ZERO || l < p->lags[above]) {
                    above = i;
                }
            } else if (below == NO_ZERO || l > p->lags[below]) {
                below = i;
            }
        }
        size_t pick = (above != NO_ZERO) ? above : below;
        if (pick == NO_ZERO) {
            return false;
        }
        zero[pick] = next;
        prev = next;
    }
}

/* Dead time that does not depend on the lags: the plant's own, half the
 * digital controller's period and the right-half-plane zeros. */
static pdt_real_t half_base(const pdt_reduce_plant_t *plant, pdt_real_t h)
{
    pdt_real_t base = plant->theta0 + PDT_R(0.5) * h;
    for (size_t j = 0; j < plant->n_zeros; j++) {
        if (plant->zeros[j] < PDT_R(0.0)) {
            base -= plant->zeros[j];
        }
    }
    return base;
}

/* One pass of Skogestad's rules for the zeros with the effective delay
 * tau_c: the lags left in eff[0..*n_eff-1] (unsorted), the rules applied in
 * *rules; returns the gain. */
static pdt_real_t half_pass(const pdt_reduce_plant_t *plant, const size_t zero[], pdt_real_t tau_c,
                            pdt_real_t eff[], size_t *n_eff, uint32_t *rules)
{
    pdt_real_t gain = plant->k;
    size_t n = 0;
    *rules = 0u;
    for (size_t i = 0; i < plant->n_lags; i++) {
        pdt_real_t tau0 = plant->lags[i];
        if (zero[i] == NO_ZERO) {
            eff[n++] = tau0;
            continue;
        }
        pdt_real_t T0 = plant->zeros[zero[i]];
        if (T0 > tau0) {
            if (tau0 >= tau_c) {
                gain *= T0 / tau0;
                *rules |= PDT_REDUCE_RULE_T1;
            } else if (T0 >= tau_c) {
                gain *= T0 / tau_c;
                *rules |= PDT_REDUCE_RULE_T1A;
            } else {
                *rules |= PDT_REDUCE_RULE_T1B;
            }
        } else if (T0 >= PDT_R(5.0) * tau_c) {
            gain *= T0 / tau0;
            *rules |= PDT_REDUCE_RULE_T2;
        } else {
            pdt_real_t tt = PDT_R(5.0) * tau_c;
            if (tt > tau0) {
                tt = tau0;
            }
            gain *= tt / tau0;
            *rules |= PDT_REDUCE_RULE_T3;
            if (tt > T0) {
                eff[n++] = tt - T0;
            }
        }
    }
    *n_eff = n;
    return gain;
}

/* The model of the kind (of order lags) from the half rule's gain, time
 * constants and dead time; false when it is no valid model. */
static bool half_model(pdt_model_kind_t kind, size_t order, pdt_real_t gain, const pdt_real_t t[2],
                       pdt_real_t theta, pdt_model_t *m)
{
    pdt_model_view_t v = {1u, gain, t[0], PDT_R(0.0), PDT_R(0.0), theta};
    if (order != 1u) {
        pdt_model_tc_t tc;
        pdt_model_sopdt_t two;
        tc.K = gain;
        tc.T1 = t[0];
        tc.T2 = t[1];
        tc.complex = false;
        tc.Td = theta;
        if (pdt_model_sopdt_from_tc(&tc, &two) != PDT_OK) {
            return false;
        }
        v.lags = 2u;
        v.K = two.k;
        v.tau = PDT_R(0.0);
        v.a = two.a;
        v.b = two.b;
        v.Td = two.Td;
    }
    pdt_model_from_view(kind, &v, m);
    return pdt_model_check(m) == PDT_OK;
}

pdt_status_t pdt_reduce_half_rule(const pdt_reduce_plant_t *plant, const pdt_reduce_config_t *cfg,
                                  pdt_model_t *out, pdt_reduce_info_t *info)
{
    pdt_reduce_config_t c;
    pdt_status_t st = check_plant(plant);
    if (st != PDT_OK) {
        return st;
    }
    st = check_config(cfg, &c);
    if (st != PDT_OK) {
        return st;
    }
    if (out == NULL) {
        return PDT_ERR_ARG;
    }
    if (plant->n_lags > PDT_REDUCE_MAX_LAGS) {
        return PDT_ERR_LENGTH;
    }
    const size_t n = plant->n_lags;
    const size_t order = (size_t)pdt_model_kind_lags(c.model);
    size_t zero[PDT_REDUCE_MAX_LAGS];
    pdt_real_t eff[PDT_REDUCE_MAX_LAGS];
    if (!pair_zeros(plant, zero)) {
        return PDT_ERR_NO_FORM;
    }
    const pdt_real_t base = half_base(plant, c.h);

    /* First guess of the effective delay: the zeros left out. */
    pdt_real_t t[2];
    for (size_t i = 0; i < n; i++) {
        eff[i] = plant->lags[i];
    }
    sort_descending(eff, n);
    pdt_real_t tau_c = half_split(eff, n, order, base, t);

    pdt_real_t gain = plant->k;
    pdt_real_t theta = tau_c;
    size_t n_eff = 0;
    uint32_t rules = 0u;
    uint32_t passes = 0u;
    bool converged = false;
    while (passes < PDT_REDUCE_MAX_PASSES && !converged) {
        passes++;
        gain = half_pass(plant, zero, tau_c, eff, &n_eff, &rules);
        sort_descending(eff, n_eff);
        theta = half_split(eff, n_eff, order, base, t);
        converged = pdt_fabs(theta - tau_c) <= PDT_R(8.0) * PDT_REAL_EPS * theta;
        tau_c = theta;
    }
    pdt_model_t m;
    if (n_eff < order) {
        return PDT_ERR_NO_FORM;
    }
    if (!half_model(c.model, order, gain, t, theta, &m)) {
        return PDT_ERR_ARG;
    }
    *out = m;
    if (info != NULL) {
        info->rules = rules;
        info->passes = passes;
        info->converged = converged;
        info->fallback = false;
        info->w_u = PDT_R(0.0);
    }
    return PDT_OK;
}

/* ------------------------------------------------------------------------ */
/* Sung et al.                                                              */

/* Continuous phase of G(jw) / k, rad. */
static pdt_real_t phase_of(const pdt_reduce_plant_t *p, pdt_real_t w)
{
    pdt_real_t ph = -w * p->theta0;
    for (size_t i = 0; i < p->n_lags; i++) {
        ph -= pdt_atan(p->lags[i] * w);
    }
    for (size_t j = 0; j < p->n_zeros; j++) {
        ph += pdt_atan(p->zeros[j] * w);
    }
    return ph;
}

/* Ultimate frequency of a checked plant. */
static pdt_status_t ultimate(const pdt_reduce_plant_t *p, pdt_real_t *w_u)
{
    pdt_real_t span = p->theta0;
    pdt_real_t shortest = PDT_REAL_MAX;
    size_t n_lhp = 0;
    for (size_t i = 0; i < p->n_lags; i++) {
        span += p->lags[i];
        if (p->lags[i] < shortest) {
            shortest = p->lags[i];
        }
    }
    for (size_t j = 0; j < p->n_zeros; j++) {
        pdt_real_t a = pdt_fabs(p->zeros[j]);
        span += a;
        if (a < shortest) {
            shortest = a;
        }
        if (p->zeros[j] > PDT_R(0.0)) {
            n_lhp++;
        }
    }
    /* Below w_start every term is within 1e-3 rad of 0, so the phase is
     * above -pi there; beyond w_end every atan is within 1e-4 rad of its
     * limit and a dead time alone has turned the phase past -pi. */
    pdt_real_t w = PDT_R(1e-3) / span;
    pdt_real_t w_end = PDT_R(1e4) / shortest;
    if (p->theta0 > PDT_R(0.0)) {
        pdt_real_t wd =
            PDT_R(2.0) * PDT_PI * (PDT_R(1.0) + PDT_R(0.5) * (pdt_real_t)n_lhp) / p->theta0;
        if (wd > w_end) {
            w_end = wd;
        }
    }
    if (!(pdt_finite(w_end) && w > PDT_R(0.0))) {
        return PDT_ERR_ARG;
    }
    pdt_real_t lo = PDT_R(0.0);
    pdt_real_t hi = PDT_R(0.0);
    bool found = false;
    for (uint32_t s = 0; s < SCAN_MAX_POINTS && w <= w_end; s++) {
        if (phase_of(p, w) <= -PDT_PI) {
            hi = w;
            found = true;
            break;
        }
        lo = w;
        w *= SCAN_RATIO;
    }
    if (!found || lo <= PDT_R(0.0)) {
        return PDT_ERR_NO_FORM;
    }
    for (uint32_t s = 0; s < BISECT_MAX_STEPS; s++) {
        pdt_real_t mid = PDT_R(0.5) * (lo + hi);
        if (mid <= lo || mid >= hi) {
            break;
        }
        if (phase_of(p, mid) <= -PDT_PI) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    *w_u = PDT_R(0.5) * (lo + hi);
    return PDT_OK;
}

pdt_status_t pdt_reduce_ultimate(const pdt_reduce_plant_t *plant, pdt_real_t *w_u)
{
    pdt_status_t st = check_plant(plant);
    if (st != PDT_OK) {
        return st;
    }
    if (w_u == NULL) {
        return PDT_ERR_ARG;
    }
    pdt_real_t w;
    st = ultimate(plant, &w);
    if (st == PDT_OK) {
        *w_u = w;
    }
    return st;
}

/* g = |G(jw) / k|^2 and 1 - g, the latter without cancellation when w is
 * small: with prod(1 + x) - 1 accumulated directly for the numerator (E_P)
 * and the denominator (E_Q), 1 - g = (E_Q - E_P) / (1 + E_Q). */
static pdt_real_t mag2_of(const pdt_reduce_plant_t *p, pdt_real_t w, pdt_real_t *one_minus)
{
    pdt_real_t eq = PDT_R(0.0);
    pdt_real_t ep = PDT_R(0.0);
    for (size_t i = 0; i < p->n_lags; i++) {
        pdt_real_t x = p->lags[i] * w;
        eq += x * x * (PDT_R(1.0) + eq);
    }
    for (size_t j = 0; j < p->n_zeros; j++) {
        pdt_real_t x = p->zeros[j] * w;
        ep += x * x * (PDT_R(1.0) + ep);
    }
    *one_minus = (eq - ep) / (PDT_R(1.0) + eq);
    return (PDT_R(1.0) + ep) / (PDT_R(1.0) + eq);
}

/* The normal equations of Sung et al.'s least squares. */
typedef struct sung_sums {
    pdt_real_t s11;
    pdt_real_t s12;
    pdt_real_t s22;
    pdt_real_t r1;
    pdt_real_t r2;
} sung_sums_t;

/* Least squares in the dimensionless x = w / w_u, divided through by k^2:
 * psi = 1 - g on the columns c1 = g x^2 and c2 = g x^4, whose coefficients
 * are (tau w_u)^2 for the FOPDT and q1 = p1 w_u^2, q2 = p2 w_u^4 for the
 * SOPDT. Scaling keeps the normal equations well conditioned whatever the
 * time scale. */
static void sung_sums(const pdt_reduce_plant_t *plant, uint32_t n_freq, pdt_real_t w_u,
                      sung_sums_t *S)
{
    pdt_real_t s11 = PDT_R(0.0);
    pdt_real_t s12 = PDT_R(0.0);
    pdt_real_t s22 = PDT_R(0.0);
    pdt_real_t r1 = PDT_R(0.0);
    pdt_real_t r2 = PDT_R(0.0);
    const pdt_real_t inv_m = PDT_R(1.0) / (pdt_real_t)n_freq;
    for (uint32_t i = 1; i <= n_freq; i++) {
        pdt_real_t x = (pdt_real_t)i * inv_m;
        pdt_real_t psi;
        pdt_real_t g = mag2_of(plant, x * w_u, &psi);
        pdt_real_t c1 = g * x * x;
        pdt_real_t c2 = c1 * x * x;
        s11 += c1 * c1;
        s12 += c1 * c2;
        s22 += c2 * c2;
        r1 += c1 * psi;
        r2 += c2 * psi;
    }
    S->s11 = s11;
    S->s12 = s12;
    S->s22 = s22;
    S->r1 = r1;
    S->r2 = r2;
}

/* The model of the kind (of two lags) from the two-column fit into *m;
 * false, *m untouched, when the fit gives none (the caller keeps the
 * FOPDT). */
static bool sung_pair(const pdt_reduce_plant_t *plant, pdt_real_t w_u, const sung_sums_t *S,
                      pdt_model_kind_t kind, pdt_model_t *m)
{
    pdt_real_t det = S->s11 * S->s22 - S->s12 * S->s12;
    pdt_real_t q1 = (S->r1 * S->s22 - S->r2 * S->s12) / det;
    pdt_real_t q2 = (S->s11 * S->r2 - S->s12 * S->r1) / det;
    if (!(pdt_finite(q1) && pdt_finite(q2) && q2 > PDT_R(0.0))) {
        return false;
    }
    pdt_real_t v2 = pdt_sqrt(q2); /* (tau w_u)^2 */
    pdt_real_t z2 = PDT_R(0.25) * (q1 / v2 + PDT_R(2.0));
    if (!(z2 > PDT_R(0.0))) {
        return false;
    }
    pdt_real_t v = pdt_sqrt(v2);
    pdt_real_t zeta = pdt_sqrt(z2);
    pdt_model_natural_t nat;
    nat.K = plant->k;
    nat.wn = w_u / v;
    nat.zeta = zeta;
    nat.Td = (PDT_PI - pdt_atan2(PDT_R(2.0) * zeta * v, PDT_R(1.0) - v2)) / w_u;
    pdt_model_sopdt_t two;
    if (pdt_model_sopdt_from_natural(&nat, &two) != PDT_OK) {
        return false;
    }
    const pdt_model_view_t pair = {2u, two.k, PDT_R(0.0), two.a, two.b, two.Td};
    pdt_model_from_view(kind, &pair, m);
    return true;
}

pdt_status_t pdt_reduce_sung(const pdt_reduce_plant_t *plant, const pdt_reduce_config_t *cfg,
                             pdt_model_t *out, pdt_reduce_info_t *info)
{
    pdt_reduce_config_t c;
    pdt_status_t st = check_plant(plant);
    if (st != PDT_OK) {
        return st;
    }
    st = check_config(cfg, &c);
    if (st != PDT_OK) {
        return st;
    }
    /* A fit of two lags needs two frequencies. */
    if (out == NULL || c.n_freq < pdt_model_kind_lags(c.model)) {
        return PDT_ERR_ARG;
    }
    if (c.n_freq > PDT_REDUCE_MAX_FREQ) {
        return PDT_ERR_LENGTH;
    }
    if (plant->k == PDT_R(0.0)) {
        return PDT_ERR_NO_FORM;
    }
    pdt_real_t w_u;
    st = ultimate(plant, &w_u);
    if (st != PDT_OK) {
        return st;
    }
    sung_sums_t S;
    sung_sums(plant, c.n_freq, w_u, &S);
    pdt_real_t u2 = S.r1 / S.s11;
    if (!(pdt_finite(u2) && u2 > PDT_R(0.0))) {
        return PDT_ERR_NO_FORM;
    }
    pdt_real_t u = pdt_sqrt(u2);
    /* The first-order fit, the answer when the kind asked has one lag and
     * the fallback when a two-lag pair is not found. */
    const pdt_model_view_t fo = {1u,         plant->k,   u / w_u,
                                 PDT_R(0.0), PDT_R(0.0), (PDT_PI - pdt_atan(u)) / w_u};
    pdt_model_t m;
    pdt_model_from_view(PDT_MODEL_FOPDT, &fo, &m);
    bool fallback = false;
    if (pdt_model_kind_lags(c.model) > 1u) {
        fallback = !sung_pair(plant, w_u, &S, c.model, &m);
    }
    if (pdt_model_check(&m) != PDT_OK) {
        return PDT_ERR_ARG;
    }
    *out = m;
    if (info != NULL) {
        info->rules = 0u;
        info->passes = 0u;
        info->converged = true;
        info->fallback = fallback;
        info->w_u = w_u;
    }
    return PDT_OK;
}
