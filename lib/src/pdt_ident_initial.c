/*
 * The state at the record's start (docs/field-data.md, "A record cut
 * mid-transient"). The identification takes the plant at rest before the
 * first sample: its simulated output starts flat. A record cut while the
 * output still settles from earlier inputs breaks that, and the model
 * bends to explain the settling with a long dead time or a wrong gain.
 * With PDT_IDENT_INITIAL_AUTO the answer's residual over the record's
 * first W samples (a twentieth of the record, at least PDT_MIN_SAMPLES)
 * is regressed on a straight line: a change along it of more than
 * MID_SIGMAS of its standard error (the noise's deviation from the
 * residual's first differences, robustly), more than MID_SHARE of y's
 * range and more than MID_OTHERS times the median change over the
 * record's other windows of W samples (a residual that wanders all along,
 * as a coloured disturbance makes it, is no sign of the start) means the
 * output was moving at the start where the model says it was still:
 * PDT_IDENT_FLAG_MID_TRANSIENT.
 */
#include "pdt_cost_state.h"
#include "pdt_ident_priv.h"
#include "pdt_internal.h"

#define MID_SIGMAS   PDT_R(8.0)
#define MID_SHARE    PDT_R(0.05)
#define MID_DIV      20u
#define MID_OTHERS   PDT_R(5.0)
/* Bisection steps of the median: the real type's precision. */
#define MEDIAN_STEPS ((sizeof(pdt_real_t) > 4u) ? 56u : 28u)
/* The changes of the median's last bisection steps kept aside. */
#define MEDIAN_NEAR  32u

/* The median of |e[k+1] - e[k]| over the record, by bisection. Once at
 * most MEDIAN_NEAR changes lie in the interval (lo, hi], they are copied
 * aside and the bisection goes on over them, the count at or below lo
 * added: the same steps, the same answer. */
static pdt_real_t median_step(const pdt_real_t *e, size_t n)
{
    pdt_real_t hi = PDT_R(0.0), lo = PDT_R(0.0);
    for (size_t k = 1u; k < n; k++) {
        const pdt_real_t d = pdt_fabs(e[k] - e[k - 1u]);
        hi = d > hi ? d : hi;
    }
    size_t at_lo = 0u, at_hi = 0u;
    for (size_t k = 1u; k < n; k++) {
        const pdt_real_t d = pdt_fabs(e[k] - e[k - 1u]);
        at_lo += (d <= lo) ? 1u : 0u;
        at_hi += (d <= hi) ? 1u : 0u;
    }
    pdt_real_t near[MEDIAN_NEAR];
    size_t n_near = 0u, base = 0u; /* base: the count at or below lo then */
    bool aside = false;
    for (uint32_t i = 0u; i < MEDIAN_STEPS; i++) {
        if (!aside && at_hi - at_lo <= MEDIAN_NEAR) {
            for (size_t k = 1u; k < n; k++) {
                const pdt_real_t d = pdt_fabs(e[k] - e[k - 1u]);
                if (d > lo && d <= hi && n_near < MEDIAN_NEAR) {
                    near[n_near] = d;
                    n_near++;
                }
            }
            base = at_lo;
            aside = true;
        }
        const pdt_real_t mid = PDT_R(0.5) * (lo + hi);
        size_t below = base;
        if (aside) {
            for (size_t k = 0u; k < n_near; k++) {
                below += (near[k] <= mid) ? 1u : 0u;
            }
        } else {
            for (size_t k = 1u; k < n; k++) {
                below += (pdt_fabs(e[k] - e[k - 1u]) <= mid) ? 1u : 0u;
            }
        }
        if (2u * below >= n - 1u) {
            hi = mid;
            at_hi = below;
        } else {
            lo = mid;
            at_lo = below;
        }
    }
    return hi;
}

/* The change of the least-squares line through e[0..w-1] from its first
 * sample to its last. */
static pdt_real_t trend(const pdt_real_t *e, size_t w)
{
    const size_t last = w - 1u;
    const pdt_real_t kc = PDT_R(0.5) * (pdt_real_t)last;
    pdt_real_t sxy = PDT_R(0.0), sxx = PDT_R(0.0);
    for (size_t k = 0u; k < w; k++) {
        const pdt_real_t x = (pdt_real_t)k - kc;
        sxy += x * (e[k] - e[0]);
        sxx += x * x;
    }
    return sxy / sxx * (pdt_real_t)last;
}

/* The median of the changes' magnitudes over the windows after the
 * first (at least three of them; else the largest real: no record to
 * compare with). */
static pdt_real_t median_others(const pdt_real_t *e, size_t n, size_t w)
{
    pdt_real_t c[MID_DIV];
    const size_t m = n / w < MID_DIV ? n / w : MID_DIV;
    if (m < 4u) {
        return PDT_REAL_MAX;
    }
    for (size_t i = 1u; i < m; i++) {
        const pdt_real_t v = pdt_fabs(trend(&e[i * w], w));
        size_t p = i - 1u;
        while (p > 0u && c[p - 1u] > v) {
            c[p] = c[p - 1u];
            p--;
        }
        c[p] = v;
    }
    const size_t k = m - 1u;
    return (k % 2u) != 0u ? c[k / 2u] : PDT_R(0.5) * (c[k / 2u - 1u] + c[k / 2u]);
}

bool pdt_ident_mid_transient(const pdt_real_t *e, const pdt_real_t *y, size_t n)
{
    const size_t least = (size_t)PDT_MIN_SAMPLES;
    const size_t w = n / MID_DIV < least ? least : n / MID_DIV;
    if (w > n) {
        return false;
    }
    pdt_real_t ymin = y[0], ymax = y[0];
    for (size_t k = 0u; k < n; k++) {
        ymin = y[k] < ymin ? y[k] : ymin;
        ymax = y[k] > ymax ? y[k] : ymax;
    }
    /* Differences of white noise have sqrt(2) times its deviation, and
     * their median absolute value is 0.6745 of theirs. */
    const pdt_real_t sigma = median_step(e, n) / (PDT_R(0.6745) * PDT_R(1.41421356));
    const pdt_real_t wr = (pdt_real_t)w;
    /* The line's change over w samples of white noise: sigma sqrt(12 (w -
     * 1)^2 / (w (w^2 - 1))), about sigma sqrt(12 / w). */
    const pdt_real_t se =
        sigma * pdt_sqrt(PDT_R(12.0) * (wr - PDT_R(1.0)) / (wr * (wr + PDT_R(1.0))));
    const pdt_real_t change = pdt_fabs(trend(e, w));
    return change > MID_SIGMAS * se && change > MID_SHARE * (ymax - ymin) &&
           change > MID_OTHERS * median_others(e, n, w);
}

/* The answer's free response and drift (initial ESTIMATE, drift), and
 * its fit with them: the residual's sum of squares in extra[3]. */
void pdt_ident_extra_finish(pdt_ident_t *c, const pdt_model_t *m)
{
    pdt_cost_extra_t x;
    pdt_discrete_t d;
    if (pdt_ident_multi(&c->cfg)) {
        pdt_ident_multi_finish(c, m);
        return;
    }
    for (uint32_t i = 0u; i < 4u; i++) {
        c->extra[i] = PDT_R(0.0);
    }
    /* On the searches' coarse record the answer is not yet the record's:
     * its whole-record polish comes back here. */
    if (!pdt_cost_extra_on(&c->cost) || c->cost.n != c->data.n ||
        pdt_cost_extra_terms(&c->cost, m, c->scratch, &x) != PDT_OK ||
        pdt_discrete_init(m, c->cfg.Ts, &d) != PDT_OK) {
        return;
    }
    c->extra[0] = x.state[0];
    c->extra[1] = x.state[1];
    c->extra[2] = x.drift;
    if (pdt_ident_simulate(c, &d, c->scratch)) {
        const size_t n = c->data.n;
        const pdt_real_t off = c->y0 - c->cost.cfg.y0;
        pdt_real_t mean = PDT_R(0.0), e2 = PDT_R(0.0), v2 = PDT_R(0.0);
        for (size_t k = 0u; k < n; k++) {
            mean += c->data.y[k] - c->data.y[0];
        }
        mean = c->data.y[0] + mean / (pdt_real_t)n;
        for (size_t k = 0u; k < n; k++) {
            const pdt_real_t e = c->data.y[k] - (c->scratch[k] + off);
            const pdt_real_t v = c->data.y[k] - mean;
            e2 += e * e;
            v2 += v * v;
        }
        c->extra[3] = e2;
        c->fit = (v2 > PDT_R(0.0)) ? PDT_R(100.0) * (PDT_R(1.0) - pdt_sqrt(e2 / v2)) : PDT_R(0.0);
        c->fit = pdt_finite(c->fit) ? c->fit : PDT_R(0.0);
    }
}

bool pdt_ident_simulate(const pdt_ident_t *c, const pdt_discrete_t *d, pdt_real_t *out)
{
    if (pdt_cost_simulate(&c->cost, d, out) != PDT_OK) {
        return false;
    }
    if (pdt_cost_extra_on(&c->cost)) {
        const pdt_cost_extra_t x = {PDT_R(0.0),  PDT_R(0.0), PDT_R(0.0), {c->extra[0], c->extra[1]},
                                    c->extra[2], 0u};
        pdt_cost_extra_add(&c->cost, d, &x, out);
    }
    return true;
}

uint32_t pdt_ident_nuisance(const pdt_ident_t *c)
{
    uint32_t k = 0u;
    if (c->cost.cfg.estimate_state) {
        k += pdt_model_kind_lags(c->cfg.model); /* a state per lag */
    }
    return k + (c->cost.cfg.drift ? 1u : 0u);
}

bool pdt_ident_want_state(const pdt_ident_t *c)
{
    return c->cfg.initial == PDT_IDENT_INITIAL_AUTO && !c->auto_state &&
           c->cfg.cost == PDT_COST_SIMULATION;
}

bool pdt_ident_refit_due(const pdt_ident_t *c)
{
    return c->auto_state && c->cfg.initial == PDT_IDENT_INITIAL_AUTO;
}

/* AUTO's second test: the answer's shape fitted with its state at the
 * first sample estimated lowers the residual's sum of squares by more
 * than chance explains (n ln(SS_rest / SS_state) above STATE_LR, about
 * the 99.9 % quantile of chi-square with 2 degrees of freedom) and by more
 * than STATE_SHARE of it: a model that bent to explain a start
 * mid-transient keeps a residual there that a free response takes up,
 * where on a record from rest it takes up noise (shares below 2 % on the
 * test records). */
#define STATE_LR    PDT_R(16.0)
#define STATE_SHARE PDT_R(0.1)

bool pdt_ident_state_matters(pdt_ident_t *c)
{
    pdt_real_t rest = PDT_R(0.0), state = PDT_R(0.0);
    if (c->cost.n != c->data.n ||
        !pdt_cost_extra_state_gain(&c->cost, &c->model, c->scratch, &rest, &state) ||
        !(state > PDT_R(0.0)) || !(rest > state)) {
        return false;
    }
    const pdt_real_t n = (pdt_real_t)c->cost.n;
    return (n * pdt_log(rest / state) > STATE_LR) && (rest - state > STATE_SHARE * rest);
}
