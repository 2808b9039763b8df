/*
 * The autotune's disturbance check: what in a record says that something
 * other than the experiment moved the process (docs/autotune.md, "Faults
 * of a real plant").
 */
#include "pdt_autotune_priv.h"

#include "pdt/pdt_discrete.h"
#include "pdt_internal.h"

/* Standard errors a level shift must exceed to count: the largest of the
 * splits of white noise stays below about 3.5 of them. */
#define SHIFT_Z PDT_R(6.0)

/* The range of the n values of x. */
static pdt_real_t range_of(const pdt_real_t *x, size_t n)
{
    pdt_real_t lo = x[0];
    pdt_real_t hi = x[0];
    for (size_t k = 1u; k < n; k++) {
        lo = x[k] < lo ? x[k] : lo;
        hi = x[k] > hi ? x[k] : hi;
    }
    return hi - lo;
}

pdt_status_t pdt_autotune_shift(const pdt_model_t *m, const pdt_ident_data_t *data, pdt_real_t Ts,
                                pdt_real_t u0, pdt_real_t y0, pdt_real_t *work, pdt_real_t *shift,
                                pdt_real_t *span_out)
{
    pdt_discrete_t d;
    const size_t n = data->n;
    if (pdt_discrete_init(m, Ts, &d) != PDT_OK) {
        return PDT_ERR_ARG;
    }
    pdt_real_t *du = work;
    pdt_real_t *ys = &work[n];
    for (size_t k = 0u; k < n; k++) {
        du[k] = data->u[k] - u0;
    }
    (void)pdt_discrete_simulate(&d, du, n, ys);
    const pdt_real_t span = range_of(ys, n);
    /* The residual, in du's place, and its total. */
    pdt_real_t total = PDT_R(0.0);
    for (size_t k = 0u; k < n; k++) {
        du[k] = data->y[k] - y0 - ys[k];
        total += du[k];
    }
    pdt_real_t sq = PDT_R(0.0);
    for (size_t k = 0u; k < n; k++) {
        const pdt_real_t e = du[k] - total / (pdt_real_t)n;
        sq += e * e;
    }
    const pdt_real_t var = sq / (pdt_real_t)n;
    const size_t edge = n / 8u;
    pdt_real_t before = PDT_R(0.0);
    pdt_real_t best = PDT_R(0.0);
    pdt_real_t best_var = PDT_R(0.0);
    for (size_t k = 0u; k + edge < n; k++) {
        if (k >= edge && k > 0u) {
            const size_t rest = n - k;
            const pdt_real_t a = before / (pdt_real_t)k;
            const pdt_real_t b = (total - before) / (pdt_real_t)rest;
            const pdt_real_t s = pdt_fabs(b - a);
            if (s > best) {
                best = s;
                best_var = var * (PDT_R(1.0) / (pdt_real_t)k + PDT_R(1.0) / (pdt_real_t)rest);
            }
        }
        before += du[k];
    }
    /* A shift the residual's own spread explains (its variance about the
     * whole mean, which the shift only enlarges) counts as none. */
    const bool significant = best * best > SHIFT_Z * SHIFT_Z * best_var;
    *shift = span > PDT_R(0.0) && significant ? best / span : PDT_R(0.0);
    *span_out = span;
    return PDT_OK;
}

pdt_real_t pdt_autotune_relay_spread(const pdt_excite_t *gen)
{
    const uint32_t c = gen->stored;
    if (c < 2u) {
        return PDT_R(0.0);
    }
    /* The last two cycles: the earlier ones may still be the transient
     * from rest (a relay that never met its symmetric cycle). */
    const pdt_real_t p0 = (pdt_real_t)gen->per[c - 2u];
    const pdt_real_t p1 = (pdt_real_t)gen->per[c - 1u];
    const pdt_real_t a0 = gen->amp[c - 2u];
    const pdt_real_t a1 = gen->amp[c - 1u];
    const pdt_real_t sp =
        p0 + p1 > PDT_R(0.0) ? PDT_R(2.0) * pdt_fabs(p1 - p0) / (p0 + p1) : PDT_R(0.0);
    const pdt_real_t sa =
        a0 + a1 > PDT_R(0.0) ? PDT_R(2.0) * pdt_fabs(a1 - a0) / (a0 + a1) : PDT_R(0.0);
    return sp > sa ? sp : sa;
}

bool pdt_autotune_ramp(const pdt_real_t *r, size_t n, pdt_real_t *slope)
{
    *slope = PDT_R(0.0);
    if (n < 8u) {
        return false;
    }
    const size_t last = n - 1u;
    const pdt_real_t kbar = PDT_R(0.5) * (pdt_real_t)last;
    pdt_real_t total = PDT_R(0.0);
    for (size_t k = 0u; k < n; k++) {
        total += r[k];
    }
    const pdt_real_t mean = total / (pdt_real_t)n;
    pdt_real_t sxx = PDT_R(0.0);
    pdt_real_t sxy = PDT_R(0.0);
    pdt_real_t syy = PDT_R(0.0);
    for (size_t k = 0u; k < n; k++) {
        const pdt_real_t dx = (pdt_real_t)k - kbar;
        const pdt_real_t dy = r[k] - mean;
        sxx += dx * dx;
        sxy += dx * dy;
        syy += dy * dy;
    }
    /* The best single shift's sum of squares between its two levels. */
    const size_t edge = n / 8u;
    pdt_real_t before = PDT_R(0.0);
    pdt_real_t ssb = PDT_R(0.0);
    for (size_t k = 0u; k + edge < n; k++) {
        if (k >= edge && k > 0u) {
            const size_t rest = n - k;
            const pdt_real_t a = before / (pdt_real_t)k;
            const pdt_real_t b = (total - before) / (pdt_real_t)rest;
            const pdt_real_t w = (pdt_real_t)k * ((pdt_real_t)rest / (pdt_real_t)n);
            const pdt_real_t sb = w * (b - a) * (b - a);
            ssb = sb > ssb ? sb : ssb;
        }
        before += r[k];
    }
    const pdt_real_t line = sxy * sxy / sxx;
    *slope = sxy / sxx;
    /* The line leaves syy - line, the shift syy - ssb. */
    return line >= ssb && syy > PDT_R(0.0);
}
