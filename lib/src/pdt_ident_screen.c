/*
 * Gross errors and missing samples (docs/field-data.md, "Gross
 * errors"). The record's y is kept in the workspace (screen.yfill) with
 * a bit per sample (screen.mask) for the samples left out of the fit:
 * the missing ones (not finite in the caller's y), marked at init, and
 * the gross errors the screen finds after each answer. A sample left out
 * is filled by a straight line between the nearest kept samples, so that
 * its bad value no longer enters any cost; the identification then runs
 * again on the filled record (at most PDT_IDENT_SCREEN_ROUNDS times).
 *
 * The screen: the answer's output error e = y - ysim, high-passed by its
 * running median over 2 PDT_IDENT_SCREEN_HALF + 1 samples (h = e - med e),
 * so that a smooth misfit of the model (a FOPDT of a higher-order plant)
 * is not taken for an error while a run of up to PDT_IDENT_RUN_MAX bad
 * samples is (the median of a window over a whole run is a good sample).
 * A sample is left out where |h| exceeds SCREEN_SIGMAS robust standard
 * deviations of h (1.4826 times its median absolute value over the kept
 * samples), SCREEN_RANGE of the range of the model's output and
 * SCREEN_TOP of the largest |h| kept: an error no FOPDT or SOPDT plus
 * noise explains, large enough to move the model, and among the largest
 * of the round. Its neighbours of the same sign with |h| above half that
 * bound go with it (the edges of a run); a sample of an earlier round
 * whose measured value the answer explains within half the bound is
 * taken back.
 */
#include "pdt_ident_priv.h"
#include "pdt_internal.h"

/* Robust standard deviations of the high-passed residual: beyond what
 * Gaussian noise reaches (6 once in 5e8 samples) and what a FOPDT's misfit
 * of a SOPDT under a PRBS reached (6.0) in the screen's tests. */
#define SCREEN_SIGMAS PDT_R(8.0)
/* The least error left out, as a share of the range of the model's
 * output: a smaller one cannot decide the model (a FOPDT's misfit of a
 * SOPDT reached a quarter). */
#define SCREEN_RANGE  PDT_R(0.5)
/* The least error left out, as a share of the largest in this round. */
#define SCREEN_TOP    PDT_R(0.5)
/* 1 / Phi^-1(3/4): the median absolute value of a Gaussian in standard
 * deviations. */
#define MAD_TO_SIGMA  PDT_R(1.4826)
/* Bisection steps of the median: the real type's precision. */
#define MEDIAN_STEPS  ((sizeof(pdt_real_t) > 4u) ? 56u : 28u)
/* The samples of the median's last bisection steps kept aside. */
#define MEDIAN_NEAR   32u

#define SCREEN_WINDOW (2u * PDT_IDENT_SCREEN_HALF + 1u)
/* Samples high-passed a step: some 50 000 instructions on a Cortex-M4F. */
#define SCREEN_BLOCK  128u

PDT_INLINE_TINY bool is_out(const uint8_t *m, size_t k)
{
    return ((uint32_t)m[k >> 3u] & (1u << (k & 7u))) != 0u;
}

static void set_out(uint8_t *m, size_t k)
{
    m[k >> 3u] = (uint8_t)((uint32_t)m[k >> 3u] | (1u << (k & 7u)));
}

static void set_in(uint8_t *m, size_t k)
{
    m[k >> 3u] = (uint8_t)((uint32_t)m[k >> 3u] & ~(1u << (k & 7u)));
}

/* The samples left out of y, filled by straight lines between the
 * nearest kept samples (at the ends, the nearest one). O(n). */
static void fill_gaps(pdt_real_t *y, const uint8_t *m, size_t n)
{
    size_t last = n; /* the last kept sample, n: none yet */
    size_t k = 0u;
    while (k < n) {
        if (!is_out(m, k)) {
            last = k;
            k++;
            continue;
        }
        size_t j = k;
        while (j < n && is_out(m, j)) {
            j++;
        }
        for (size_t i = k; i < j; i++) {
            if (last == n) {
                y[i] = (j < n) ? y[j] : PDT_R(0.0);
            } else if (j == n) {
                y[i] = y[last];
            } else {
                const size_t step = i - last, gap = j - last;
                const pdt_real_t w = (pdt_real_t)step / (pdt_real_t)gap;
                y[i] = y[last] + w * (y[j] - y[last]);
            }
        }
        k = j;
    }
}

/* The first sample left out, and the count, after the mask changed. */
static void recount(pdt_ident_screen_t *s, size_t n)
{
    uint32_t count = 0u;
    s->first = n;
    for (size_t k = 0u; k < n; k++) {
        if (is_out(s->mask, k)) {
            s->first = (s->first == n) ? k : s->first;
            count++;
        }
    }
    s->excluded = count;
}

uint32_t pdt_ident_screen_limit(const pdt_ident_config_t *cfg, size_t n)
{
    if (cfg->max_excluded != 0u) {
        return cfg->max_excluded;
    }
    const size_t share = n / 20u;
    return share > 2u * PDT_IDENT_RUN_MAX ? (uint32_t)share : 2u * PDT_IDENT_RUN_MAX;
}

bool pdt_ident_screen_needed(const pdt_ident_config_t *cfg, const pdt_ident_data_t *d)
{
    for (size_t k = 0u; k < d->n; k++) {
        if (!pdt_finite(d->y[k])) {
            return true;
        }
    }
    return !cfg->no_screen && pdt_cost_outlier(d->y, d->n) < d->n;
}

pdt_status_t pdt_ident_screen_prepare(pdt_ident_screen_t *s, const pdt_ident_config_t *cfg,
                                      const pdt_ident_data_t *d)
{
    const size_t n = d->n;
    for (size_t k = 0u; k < (n + 7u) / 8u; k++) {
        s->mask[k] = 0u;
    }
    uint32_t missing = 0u;
    for (size_t k = 0u; k < n; k++) {
        s->yfill[k] = d->y[k];
        if (!pdt_finite(d->y[k])) {
            set_out(s->mask, k);
            missing++;
        }
    }
    s->limit = pdt_ident_screen_limit(cfg, n);
    s->missing = missing;
    s->y_in = d->y;
    fill_gaps(s->yfill, s->mask, n);
    /* Values orders of magnitude off the rest (pdt_cost_outlier: 1e20 in
     * a record of order 1), which the cost refuses: one at a time. */
    for (uint32_t i = 0u; !cfg->no_screen && i < 2u * PDT_IDENT_RUN_MAX; i++) {
        const size_t k = pdt_cost_outlier(s->yfill, n);
        if (k >= n) {
            break;
        }
        set_out(s->mask, k);
        fill_gaps(s->yfill, s->mask, n);
    }
    recount(s, n);
    return s->excluded > s->limit ? PDT_ERR_OUTLIER : PDT_OK;
}

/* The median of the window about k of the residual e, whose samples
 * before k were overwritten and are kept in ring (index mod the window). */
static pdt_real_t window_median(const pdt_real_t *e, const pdt_real_t *ring, const uint8_t *mask,
                                size_t n, size_t k)
{
    pdt_real_t w[SCREEN_WINDOW];
    const size_t len = n < SCREEN_WINDOW ? n : SCREEN_WINDOW;
    size_t s = k > PDT_IDENT_SCREEN_HALF ? k - PDT_IDENT_SCREEN_HALF : 0u;
    s = (s + len > n) ? n - len : s;
    size_t kept = 0u;
    for (size_t i = 0u; i < SCREEN_WINDOW; i++) {
        w[i] = PDT_R(0.0);
    }
    /* The samples left out are filled, not measured: not in the median. */
    for (size_t i = 0u; i < len; i++) {
        const size_t j = s + i;
        if (is_out(mask, j)) {
            continue;
        }
        const pdt_real_t v = (j < k) ? ring[j % SCREEN_WINDOW] : e[j];
        size_t p = kept;
        while (p > 0u && w[p - 1u] > v) {
            w[p] = w[p - 1u];
            p--;
        }
        w[p] = v;
        kept++;
    }
    if (kept == 0u) {
        return PDT_R(0.0);
    }
    return (kept % 2u) != 0u ? w[kept / 2u] : PDT_R(0.5) * (w[kept / 2u - 1u] + w[kept / 2u]);
}

/* The window of kept samples sorted as window_median sorts it: by
 * value, equal values in the order of their index. */
typedef struct {
    pdt_real_t v[SCREEN_WINDOW];
    size_t at[SCREEN_WINDOW];
    size_t kept;
} sorted_window_t;

static void window_add(sorted_window_t *w, pdt_real_t v, size_t j)
{
    size_t p = w->kept;
    while (p > 0u && w->v[p - 1u] > v) {
        w->v[p] = w->v[p - 1u];
        w->at[p] = w->at[p - 1u];
        p--;
    }
    w->v[p] = v;
    w->at[p] = j;
    w->kept++;
}

/* The place of sample j of value v in the window: a bisection in the
 * order of (value, index). */
static size_t window_find(const sorted_window_t *w, pdt_real_t v, size_t j)
{
    size_t lo = 0u, hi = w->kept;
    while (lo < hi) {
        const size_t m = lo + (hi - lo) / 2u;
        if (w->v[m] < v || (!(v < w->v[m]) && w->at[m] < j)) {
            lo = m + 1u;
        } else {
            hi = m;
        }
    }
    return lo;
}

static void window_drop(sorted_window_t *w, pdt_real_t v, size_t j)
{
    for (size_t p = window_find(w, v, j); p + 1u < w->kept; p++) {
        w->v[p] = w->v[p + 1u];
        w->at[p] = w->at[p + 1u];
    }
    w->kept--;
}

/* Sample j of value v in place of the one at p: it has the largest
 * index, so it goes after the values equal to it. */
static void window_swap(sorted_window_t *w, size_t at, pdt_real_t v, size_t j)
{
    size_t p = at;
    while (p > 0u && w->v[p - 1u] > v) {
        w->v[p] = w->v[p - 1u];
        w->at[p] = w->at[p - 1u];
        p--;
    }
    while (p + 1u < w->kept && !(w->v[p + 1u] > v)) {
        w->v[p] = w->v[p + 1u];
        w->at[p] = w->at[p + 1u];
        p++;
    }
    w->v[p] = v;
    w->at[p] = j;
}

static pdt_real_t window_mid(const sorted_window_t *w)
{
    const size_t m = w->kept;
    if (m == 0u) {
        return PDT_R(0.0);
    }
    return (m % 2u) != 0u ? w->v[m / 2u] : PDT_R(0.5) * (w->v[m / 2u - 1u] + w->v[m / 2u]);
}

/* The high pass's state between its blocks. */
typedef struct {
    sorted_window_t w;
    pdt_real_t ring[SCREEN_WINDOW]; /* the window's samples overwritten */
    size_t k;                       /* the next sample */
    size_t s;                       /* the window's first sample */
    bool finite;                    /* e finite: the window kept sorted */
} high_run_t;

/* e high-passed in place: e - its running median over the kept samples.
 * The window slides by one sample at a time, so its sorted values are
 * kept from one sample to the next: O(W) a sample. Where e is not finite
 * (a NaN has no place in the order) the median is sorted afresh at each
 * sample: O(W^2 / 4). Both give the same medians bit for bit. The
 * beginning: O(n). */
static void high_begin(high_run_t *r, const pdt_real_t *e, const uint8_t *mask, size_t n)
{
    bool finite = true;
    for (size_t k = 0u; k < n; k++) {
        finite = finite && pdt_finite(e[k]);
    }
    r->finite = finite;
    r->k = 0u;
    r->s = 0u;
    r->w.kept = 0u;
    const size_t len = n < SCREEN_WINDOW ? n : SCREEN_WINDOW;
    for (size_t j = 0u; finite && j < len; j++) {
        if (!is_out(mask, j)) {
            window_add(&r->w, e[j], j);
        }
    }
}

/* The next SCREEN_BLOCK samples high-passed; true at the
 * record's end. */
static bool high_block(high_run_t *r, pdt_real_t *e, const uint8_t *mask, size_t n)
{
    const size_t len = n < SCREEN_WINDOW ? n : SCREEN_WINDOW;
    const size_t end = (n - r->k > SCREEN_BLOCK) ? r->k + SCREEN_BLOCK : n;
    for (size_t k = r->k; k < end; k++) {
        if (!r->finite) {
            const pdt_real_t med = window_median(e, r->ring, mask, n, k);
            r->ring[k % SCREEN_WINDOW] = e[k];
            e[k] -= med;
            continue;
        }
        size_t want = k > PDT_IDENT_SCREEN_HALF ? k - PDT_IDENT_SCREEN_HALF : 0u;
        want = (want + len > n) ? n - len : want;
        if (want != r->s) {
            /* want == s + 1: the first sample leaves (its value is in
             * ring: e[s] was overwritten), the one after the last
             * enters. */
            const size_t s = r->s;
            const pdt_real_t gone = r->ring[s % SCREEN_WINDOW];
            const bool drop = !is_out(mask, s), add = !is_out(mask, s + len);
            if (drop && add) {
                window_swap(&r->w, window_find(&r->w, gone, s), e[s + len], s + len);
            } else if (drop) {
                window_drop(&r->w, gone, s);
            } else if (add) {
                window_add(&r->w, e[s + len], s + len);
            } else {
                /* neither is kept: the window's values stay */
            }
            r->s = want;
        }
        r->ring[k % SCREEN_WINDOW] = e[k];
        e[k] -= window_mid(&r->w);
    }
    r->k = end;
    return end == n;
}

/* The median of |h| over the kept samples, by bisection of [0, top]
 * (top: the largest kept |h|), in steps. Once at most MEDIAN_NEAR samples
 * lie in the interval (lo, hi], they are copied aside and the bisection
 * goes on over them, the count at or below lo added: the same steps, the
 * same answer. */
typedef struct {
    pdt_real_t near[MEDIAN_NEAR];
    pdt_real_t lo, hi, top;
    size_t kept, at_lo, at_hi; /* the kept samples, those at or below lo, hi */
    size_t base;               /* the count at or below lo when set aside */
    size_t n_near;
    uint32_t step;
    bool aside;
} median_run_t;

/* The largest kept |h| and the counts: two passes over the record. A top
 * not finite leaves no step to take (the bound is then the real type's
 * largest). */
static void median_begin(median_run_t *r, const pdt_real_t *h, const uint8_t *m, size_t n)
{
    pdt_real_t top = PDT_R(0.0);
    for (size_t k = 0u; k < n; k++) {
        const pdt_real_t a = is_out(m, k) ? PDT_R(0.0) : pdt_fabs(h[k]);
        top = a > top ? a : top;
    }
    r->top = top;
    r->lo = PDT_R(0.0);
    r->hi = top;
    r->n_near = 0u;
    r->base = 0u;
    r->aside = false;
    r->step = 0u;
    const bool finite = pdt_finite(top);
    size_t kept = 0u, at_lo = 0u, at_hi = 0u;
    for (size_t k = 0u; finite && k < n; k++) {
        const bool in = !is_out(m, k);
        kept += in ? 1u : 0u;
        at_lo += (in && pdt_fabs(h[k]) <= PDT_R(0.0)) ? 1u : 0u;
        at_hi += (in && pdt_fabs(h[k]) <= top) ? 1u : 0u;
    }
    r->kept = kept;
    r->at_lo = at_lo;
    r->at_hi = at_hi;
}

/* The median's bisection steps, at most `passes` of them over the whole
 * record (the steps over the samples set aside are not counted: O(1)
 * each); true when all MEDIAN_STEPS are taken (the median is r->hi). */
static bool median_steps(median_run_t *r, const pdt_real_t *h, const uint8_t *m, size_t n,
                         uint32_t passes)
{
    uint32_t used = 0u;
    const bool finite = pdt_finite(r->top);
    while (finite && r->step < MEDIAN_STEPS && (r->aside || used < passes)) {
        if (!r->aside && r->at_hi - r->at_lo <= MEDIAN_NEAR) {
            for (size_t k = 0u; k < n; k++) {
                const pdt_real_t a = pdt_fabs(h[k]);
                if (!is_out(m, k) && a > r->lo && a <= r->hi && r->n_near < MEDIAN_NEAR) {
                    r->near[r->n_near] = a;
                    r->n_near++;
                }
            }
            r->base = r->at_lo;
            r->aside = true;
            used++;
        }
        const pdt_real_t mid = PDT_R(0.5) * (r->lo + r->hi);
        size_t below = r->base;
        if (r->aside) {
            for (size_t k = 0u; k < r->n_near; k++) {
                below += (r->near[k] <= mid) ? 1u : 0u;
            }
        } else {
            for (size_t k = 0u; k < n; k++) {
                below += (!is_out(m, k) && pdt_fabs(h[k]) <= mid) ? 1u : 0u;
            }
            used++;
        }
        if (2u * below >= r->kept) {
            r->hi = mid;
            r->at_hi = below;
        } else {
            r->lo = mid;
            r->at_lo = below;
        }
        r->step++;
    }
    return !finite || r->step >= MEDIAN_STEPS;
}

/* The answer's output error into e (n reals) and the range of its
 * simulated output; false when the model cannot be simulated. */
static bool residual(const pdt_ident_t *c, pdt_real_t *e, pdt_real_t *range)
{
    pdt_discrete_t d;
    if (pdt_discrete_init(&c->model, c->cfg.Ts, &d) != PDT_OK || !pdt_ident_simulate(c, &d, e)) {
        return false;
    }
    const pdt_real_t off = c->y0 - c->cost.cfg.y0;
    pdt_real_t lo = e[0], hi = e[0];
    for (size_t k = 0u; k < c->data.n; k++) {
        lo = e[k] < lo ? e[k] : lo;
        hi = e[k] > hi ? e[k] : hi;
        e[k] = c->screen.yfill[k] - (e[k] + off);
    }
    *range = hi - lo;
    return pdt_finite(*range);
}

/* Marks the samples beyond bound, then (grow) their neighbours beyond
 * half of it; returns how many were marked. */
static uint32_t mark(pdt_ident_screen_t *s, const pdt_real_t *h, size_t n, pdt_real_t bound,
                     bool grow)
{
    uint32_t added = 0u;
    for (size_t k = 0u; k < n; k++) {
        if (!is_out(s->mask, k) && pdt_fabs(h[k]) > bound) {
            set_out(s->mask, k);
            s->fresh[k >> 3u] = (uint8_t)((uint32_t)s->fresh[k >> 3u] | (1u << (k & 7u)));
            added++;
        }
    }
    const pdt_real_t edge = PDT_R(0.5) * bound;
    for (size_t i = 1u; grow && added > 0u && i < 2u * n; i++) {
        /* Forward, then backward: a run's edges on either side. */
        const size_t k = i < n ? i : 2u * n - 1u - i;
        const size_t from = i < n ? k - 1u : k + 1u;
        /* Of the run's sign: a model the run bent errs the other way
         * beside it. */
        if (k < n && from < n && is_out(s->fresh, from) && !is_out(s->mask, k) &&
            pdt_fabs(h[k]) > edge && (h[k] > PDT_R(0.0)) == (h[from] > PDT_R(0.0))) {
            set_out(s->mask, k);
            set_out(s->fresh, k);
            added++;
        }
    }
    return added;
}

/* The bound of this round (top: the largest kept |h|, median: the
 * median of the kept |h|): an error no model plus noise explains
 * (SCREEN_SIGMAS), large enough to move the model (SCREEN_RANGE), and
 * among the largest (SCREEN_TOP): a model that a gross error bent makes
 * errors of its own, smaller ones, which the next round sees without it.
 * *grow: the bound is the first two's, so a run's edges go with it (with
 * a bent model they wait for the next round). */
static pdt_real_t bound_of(pdt_real_t top, pdt_real_t median, pdt_real_t range, bool *grow)
{
    if (!pdt_finite(top)) {
        *grow = false;
        return PDT_REAL_MAX;
    }
    const pdt_real_t sigma = MAD_TO_SIGMA * median;
    pdt_real_t bound = SCREEN_SIGMAS * sigma;
    bound = SCREEN_RANGE * range > bound ? SCREEN_RANGE * range : bound;
    *grow = !(SCREEN_TOP * top > bound);
    return *grow ? bound : SCREEN_TOP * top;
}

/* The samples left out in earlier rounds filled with the answer's output
 * (ysim: n reals), the new ones (fresh) by straight lines. */
static void refill(pdt_ident_screen_t *s, const pdt_real_t *ysim, size_t n)
{
    for (size_t k = 0u; k < n; k++) {
        if (is_out(s->mask, k) && !is_out(s->fresh, k)) {
            s->yfill[k] = ysim[k];
        }
    }
    fill_gaps(s->yfill, s->fresh, n);
}

/* The samples of earlier rounds that the answer explains after all (a
 * model a gross error bent erred beside it): measured values within half
 * the bound (h holds their high-passed residual) are taken back. Missing
 * samples never are. Returns how many. */
static uint32_t restore(pdt_ident_screen_t *s, const pdt_real_t *h, size_t n, pdt_real_t bound)
{
    uint32_t back = 0u;
    for (size_t k = 0u; k < n; k++) {
        if (is_out(s->mask, k) && pdt_finite(s->y_in[k]) && pdt_fabs(h[k]) <= PDT_R(0.5) * bound) {
            set_in(s->mask, k);
            s->yfill[k] = s->y_in[k];
            back++;
        }
    }
    return back;
}

/* h of the samples left out as their measured values would have it: the
 * fill's residual moved by the measured value's distance from the fill
 * (the running median does not see them). */
static void measured_h(const pdt_ident_screen_t *s, pdt_real_t *h, size_t n)
{
    for (size_t k = 0u; k < n; k++) {
        if (is_out(s->mask, k) && pdt_finite(s->y_in[k])) {
            h[k] += s->y_in[k] - s->yfill[k];
        }
    }
}

/* The screen in steps: PH_SCREEN the answer's residual, PH_SCREEN_HIGH
 * its high pass (a block of SCREEN_BLOCK samples a step),
 * PH_SCREEN_MEDIAN the median of its magnitude (at most
 * SCREEN_MEDIAN_PASSES passes over the record a step), PH_SCREEN_BOUND
 * the samples it leaves out, PH_SCREEN_REFILL the record filled again,
 * and PH_SCREEN_RESTART the identification started again on it. h lies
 * in the scratch from the first to the fourth.
 *
 * What the steps hand on lies in the workspace's population part, which
 * nothing reads once the searches are done (the restart carves it
 * again): first the residual's range and the median's figures (the part
 * holds at least 44 reals), then the passes' state where it fits. Where a
 * small population leaves the part too short for it, the high pass and
 * the median are one step, PH_SCREEN_HIGH's, and PH_SCREEN_MEDIAN has
 * nothing left to do. The same figures either way. */
#define SCREEN_MEDIAN_PASSES 4u

/* The figures handed on, reals at the population part's beginning. */
#define KEPT_RANGE  0u /* of the answer's simulated output */
#define KEPT_TOP    1u /* the largest kept |h| */
#define KEPT_MEDIAN 2u /* the median of the kept |h| */
#define KEPT_COUNT  3u

/* The passes' state. */
typedef struct {
    high_run_t high;
    median_run_t median;
} screen_run_t;

/* The passes' state after the figures, its first address aligned for it;
 * NULL where it does not fit before the scratch. */
static screen_run_t *run_of(const pdt_ident_t *c)
{
    pdt_real_t *const base = &c->ga.pop[KEPT_COUNT];
    const ptrdiff_t reals = c->scratch - base;
    return (screen_run_t *)pdt_aligned_state(base, (size_t)reals * sizeof(pdt_real_t),
                                             sizeof(screen_run_t));
}

/* The median's figures kept for the bound. */
static void median_keep(pdt_ident_t *c, const median_run_t *r)
{
    c->ga.pop[KEPT_TOP] = r->top;
    c->ga.pop[KEPT_MEDIAN] = r->hi;
}

pdt_ident_outcome_t pdt_ident_screen_step(pdt_ident_t *c)
{
    pdt_ident_screen_t *s = &c->screen;
    if (pdt_ident_refit_due(c)) {
        return OUT_REFIT;
    }
    /* Where no candidate scored (every gain the bounds allow costs beyond
     * the real type) there is no answer to screen with: the result refuses
     * it. */
    if (c->cfg.no_screen || s->rounds >= PDT_IDENT_SCREEN_ROUNDS || s->settled ||
        !(c->best.cost < PDT_REAL_MAX) || !residual(c, c->scratch, &c->ga.pop[KEPT_RANGE])) {
        return OUT_SKIPPED;
    }
    screen_run_t *const run = run_of(c);
    if (run != NULL) {
        high_begin(&run->high, c->scratch, s->mask, c->data.n);
    }
    return OUT_DONE;
}

pdt_ident_outcome_t pdt_ident_screen_high(pdt_ident_t *c)
{
    const size_t n = c->data.n;
    pdt_real_t *const h = c->scratch;
    screen_run_t *const run = run_of(c);
    if (run == NULL) {
        screen_run_t whole;
        high_begin(&whole.high, h, c->screen.mask, n);
        while (!high_block(&whole.high, h, c->screen.mask, n)) {
            /* the next block */
        }
        measured_h(&c->screen, h, n);
        median_begin(&whole.median, h, c->screen.mask, n);
        /* As many passes as steps: the whole bisection. */
        (void)median_steps(&whole.median, h, c->screen.mask, n, MEDIAN_STEPS);
        median_keep(c, &whole.median);
        return OUT_DONE;
    }
    if (!high_block(&run->high, h, c->screen.mask, n)) {
        return OUT_AGAIN;
    }
    measured_h(&c->screen, h, n);
    median_begin(&run->median, h, c->screen.mask, n);
    return OUT_DONE;
}

pdt_ident_outcome_t pdt_ident_screen_median(pdt_ident_t *c)
{
    screen_run_t *const run = run_of(c);
    if (run == NULL) {
        return OUT_DONE;
    }
    if (!median_steps(&run->median, c->scratch, c->screen.mask, c->data.n, SCREEN_MEDIAN_PASSES)) {
        return OUT_AGAIN;
    }
    median_keep(c, &run->median);
    return OUT_DONE;
}

pdt_ident_outcome_t pdt_ident_screen_bound(pdt_ident_t *c)
{
    pdt_ident_screen_t *s = &c->screen;
    const size_t n = c->data.n;
    const pdt_real_t *h = c->scratch;
    const pdt_real_t *const kept = c->ga.pop;
    for (size_t k = 0u; k < (n + 7u) / 8u; k++) {
        s->fresh[k] = 0u;
    }
    bool grow = false;
    const pdt_real_t bound = bound_of(kept[KEPT_TOP], kept[KEPT_MEDIAN], kept[KEPT_RANGE], &grow);
    const uint32_t back = restore(s, h, n, bound);
    const uint32_t added = mark(s, h, n, bound, grow);
    if (added == 0u && back == 0u && s->excluded == 0u) {
        return OUT_SKIPPED;
    }
    recount(s, n);
    if (s->excluded > s->limit) {
        s->status = PDT_ERR_OUTLIER;
        return OUT_FAILED;
    }
    /* Without new samples or ones taken back, this round only fills the
     * old ones with a model that did not see them: the next answer is the
     * last. */
    s->settled = added == 0u && back == 0u;
    return OUT_DONE;
}

pdt_ident_outcome_t pdt_ident_screen_refill(pdt_ident_t *c)
{
    pdt_ident_screen_t *s = &c->screen;
    const size_t n = c->data.n;
    pdt_real_t *h = c->scratch;
    pdt_real_t range;
    /* The answer's output again (h was overwritten), for the refill. */
    if (!residual(c, h, &range)) {
        return OUT_FAILED;
    }
    for (size_t k = 0u; k < n; k++) {
        h[k] = s->yfill[k] - h[k];
    }
    refill(s, h, n);
    s->rounds++;
    return OUT_DONE;
}

void pdt_ident_screen_failed(pdt_ident_t *c, pdt_status_t st)
{
    pdt_ident_screen_t *s = &c->screen;
    const size_t n = c->data.n;
    c->screen.status = st;
    /* The cost refused the refilled record for a value orders of
     * magnitude off: that sample is the one to name. */
    const size_t k = pdt_cost_outlier(s->yfill, n);
    if (st == PDT_ERR_OUTLIER && k < n) {
        s->first = k;
    }
}

void pdt_ident_screen_report(const pdt_ident_screen_t *s, size_t n, pdt_ident_result_t *r)
{
    uint32_t listed = 0u;
    r->excluded = s->excluded;
    r->missing = s->missing;
    for (uint32_t i = 0u; i < PDT_IDENT_EXCLUDED_LIST; i++) {
        r->excluded_first[i] = 0u;
    }
    for (size_t k = 0u; s->excluded > 0u && k < n && listed < PDT_IDENT_EXCLUDED_LIST; k++) {
        if (is_out(s->mask, k)) {
            r->excluded_first[listed] = (uint32_t)k;
            listed++;
        }
    }
}

bool pdt_ident_is_excluded(const pdt_ident_t *ctx, size_t k)
{
    return ctx != NULL && ctx->phase == PH_DONE && ctx->screen.mask != NULL && k < ctx->data.n &&
           is_out(ctx->screen.mask, k);
}
