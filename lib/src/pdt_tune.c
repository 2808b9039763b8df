/*
 * pdtfit tuning rules and loop robustness; see pdt_tune.h and
 * docs/tuning.md.
 */
#include "pdt/pdt_tune.h"

#include "pdt_internal.h"
#include "pdt_model_priv.h"

/* Decades the frequency range may grow each way beyond its first guess. */
#define TUNE_WIDEN        8
/* Sub-steps of a grid interval in which the phase turns quickly: at
 * least TUNE_SPLIT when L or 1 + L turns by more than pi/4, enough for
 * pi/4 per step of the dead time's own turn, at most TUNE_SPLIT_MAX. */
#define TUNE_SPLIT        8
#define TUNE_SPLIT_MAX    64
/* Below this |L| the grid is not refined: there |S| < 1 / (1 - 0.02). */
#define TUNE_QUIET        PDT_R(0.02)
/* Local maxima of |S| refined, and the refinement steps. */
#define TUNE_PEAKS        8
#define TUNE_GOLDEN_STEPS 40
#define TUNE_BISECT_STEPS 60

typedef struct tune_cplx {
    pdt_real_t re;
    pdt_real_t im;
} tune_cplx_t;

/* The loop C G, flattened for evaluation. */
typedef struct tune_loop {
    pdt_model_view_t p; /* the plant */
    pdt_real_t Kc;
    pdt_real_t tauI;
    pdt_real_t tauD;
    pdt_real_t Tf;
} tune_loop_t;

/* 1 / (c + j d) without overflow in the intermediate products (Smith). */
static tune_cplx_t cinv(pdt_real_t c, pdt_real_t d)
{
    tune_cplx_t r;
    if (pdt_fabs(c) >= pdt_fabs(d)) {
        pdt_real_t q = d / c;
        pdt_real_t den = c + d * q;
        r.re = PDT_R(1.0) / den;
        r.im = -q / den;
    } else {
        pdt_real_t q = c / d;
        pdt_real_t den = c * q + d;
        r.re = q / den;
        r.im = PDT_R(-1.0) / den;
    }
    return r;
}

static tune_cplx_t cmul(tune_cplx_t x, tune_cplx_t y)
{
    tune_cplx_t r;
    r.re = x.re * y.re - x.im * y.im;
    r.im = x.re * y.im + x.im * y.re;
    return r;
}

static tune_cplx_t loop_eval(const tune_loop_t *lp, pdt_real_t w)
{
    tune_cplx_t g;
    const pdt_model_view_t *p = &lp->p;
    if (p->lags == 1u) {
        g = cinv(PDT_R(1.0), w * p->tau);
    } else {
        g = cinv(p->b - w * w, p->a * w);
    }
    g.re *= p->K;
    g.im *= p->K;
    if (p->Td > PDT_R(0.0)) {
        tune_cplx_t dly;
        dly.re = pdt_cos(w * p->Td);
        dly.im = -pdt_sin(w * p->Td);
        g = cmul(g, dly);
    }
    tune_cplx_t c;
    c.re = PDT_R(1.0);
    c.im = PDT_R(-1.0) / (w * lp->tauI);
    if (lp->tauD > PDT_R(0.0)) {
        /* j w tauD / (1 + j w Tf) */
        tune_cplx_t d = cinv(PDT_R(1.0), w * lp->Tf);
        c.re -= w * lp->tauD * d.im;
        c.im += w * lp->tauD * d.re;
    }
    c.re *= lp->Kc;
    c.im *= lp->Kc;
    return cmul(c, g);
}

static pdt_real_t abs2(tune_cplx_t x)
{
    return x.re * x.re + x.im * x.im;
}

/* |1 + L|^2: its minimum is 1 / Ms^2. */
static pdt_real_t dist2(tune_cplx_t L)
{
    tune_cplx_t s;
    s.re = PDT_R(1.0) + L.re;
    s.im = L.im;
    return abs2(s);
}

/* x wrapped into (-pi, pi]. */
static pdt_real_t wrap_pi(pdt_real_t x)
{
    while (x > PDT_PI) {
        x -= PDT_R(2.0) * PDT_PI;
    }
    while (x <= -PDT_PI) {
        x += PDT_R(2.0) * PDT_PI;
    }
    return x;
}

static pdt_real_t arg_of(tune_cplx_t x)
{
    return pdt_atan2(x.im, x.re);
}

static pdt_real_t arg_1p(tune_cplx_t L)
{
    return pdt_atan2(L.im, PDT_R(1.0) + L.re);
}

static bool gains_valid(const pdt_tune_gains_t *g)
{
    return pdt_finite(g->Kc) && pdt_finite(g->tauI) && pdt_finite(g->tauD) && pdt_finite(g->Tf) &&
           g->Kc != PDT_R(0.0) && g->tauI > PDT_R(0.0) && g->tauD >= PDT_R(0.0) &&
           g->Tf >= PDT_R(0.0);
}

static pdt_real_t rmax(pdt_real_t x, pdt_real_t y)
{
    return x > y ? x : y;
}

static pdt_real_t rmin(pdt_real_t x, pdt_real_t y)
{
    return x < y ? x : y;
}

/* Folds a positive time scale into [*tmin, *tmax]. */
static void scale_add(pdt_real_t t, pdt_real_t *tmin, pdt_real_t *tmax)
{
    if (t > PDT_R(0.0) && pdt_finite(t)) {
        *tmin = rmin(*tmin, t);
        *tmax = rmax(*tmax, t);
    }
}

/* The scan's memory of the best candidates. */
typedef struct tune_scan {
    pdt_real_t peak_d2[TUNE_PEAKS]; /* |1 + L|^2 at the local minima */
    pdt_real_t peak_lo[TUNE_PEAKS]; /* their brackets, rad/s */
    pdt_real_t peak_hi[TUNE_PEAKS];
    int npeaks;
    pdt_real_t best_d2; /* least |1 + L|^2 sampled, and where */
    pdt_real_t best_w;
    pdt_real_t pm; /* least phase margin, degrees, and where */
    pdt_real_t w_gc;
    pdt_real_t re_pc; /* largest |Re L| on the negative real axis */
    pdt_real_t w_pc;
    pdt_real_t phase; /* arg(1 + L), followed continuously */
    /* the last two points, for the local minima of |1 + L| */
    pdt_real_t w1, d1, w2, d2;
    int seen;
    uint32_t evals; /* evaluations of L so far */
} tune_scan_t;

static void peak_keep(tune_scan_t *s, pdt_real_t d2, pdt_real_t lo, pdt_real_t hi)
{
    int worst = 0;
    if (s->npeaks < TUNE_PEAKS) {
        worst = s->npeaks;
        s->npeaks++;
    } else {
        for (int i = 1; i < TUNE_PEAKS; i++) {
            if (s->peak_d2[i] > s->peak_d2[worst]) {
                worst = i;
            }
        }
        if (d2 >= s->peak_d2[worst]) {
            return;
        }
    }
    s->peak_d2[worst] = d2;
    s->peak_lo[worst] = lo;
    s->peak_hi[worst] = hi;
}

/* Gain crossover between wa and wb (|L| - 1 changes sign): bisection in
 * log w. */
static void refine_gc(const tune_loop_t *lp, tune_scan_t *s, pdt_real_t wa, pdt_real_t wb,
                      bool a_above)
{
    for (int i = 0; i < TUNE_BISECT_STEPS; i++) {
        pdt_real_t wm = pdt_sqrt(wa * wb);
        if (wm == wa || wm == wb) {
            break;
        }
        bool above = abs2(loop_eval(lp, wm)) > PDT_R(1.0);
        s->evals++;
        if (above == a_above) {
            wa = wm;
        } else {
            wb = wm;
        }
    }
    pdt_real_t w = pdt_sqrt(wa * wb);
    tune_cplx_t L = loop_eval(lp, w);
    s->evals++;
    pdt_real_t pm = PDT_R(180.0) + arg_of(L) * (PDT_R(180.0) / PDT_PI);
    if (pm < s->pm) {
        s->pm = pm;
        s->w_gc = w;
    }
}

/* Crossing of the real axis between wa and wb (Im L changes sign). */
static void refine_pc(const tune_loop_t *lp, tune_scan_t *s, pdt_real_t wa, pdt_real_t wb,
                      bool a_pos)
{
    for (int i = 0; i < TUNE_BISECT_STEPS; i++) {
        pdt_real_t wm = pdt_sqrt(wa * wb);
        if (wm == wa || wm == wb) {
            break;
        }
        bool pos = loop_eval(lp, wm).im > PDT_R(0.0);
        s->evals++;
        if (pos == a_pos) {
            wa = wm;
        } else {
            wb = wm;
        }
    }
    pdt_real_t w = pdt_sqrt(wa * wb);
    tune_cplx_t L = loop_eval(lp, w);
    s->evals++;
    if (L.re < PDT_R(0.0) && -L.re > s->re_pc) {
        s->re_pc = -L.re;
        s->w_pc = w;
    }
}

/* One step of the scan from (wa, La) to (wb, Lb). */
static void scan_step(const tune_loop_t *lp, tune_scan_t *s, pdt_real_t wa, tune_cplx_t La,
                      pdt_real_t wb, tune_cplx_t Lb)
{
    s->phase += wrap_pi(arg_1p(Lb) - arg_1p(La));

    pdt_real_t db = dist2(Lb);
    if (db < s->best_d2) {
        s->best_d2 = db;
        s->best_w = wb;
    }
    /* a local minimum of |1 + L| at the previous point */
    if (s->seen >= 2 && s->d1 < s->d2 && s->d1 <= db) {
        peak_keep(s, s->d1, s->w2, wb);
    }
    s->w2 = s->w1;
    s->d2 = s->d1;
    s->w1 = wb;
    s->d1 = db;
    s->seen++;

    pdt_real_t ma = abs2(La);
    pdt_real_t mb = abs2(Lb);
    bool a_above = ma > PDT_R(1.0);
    if (a_above != (mb > PDT_R(1.0))) {
        refine_gc(lp, s, wa, wb, a_above);
    }
    bool a_pos = La.im > PDT_R(0.0);
    if (a_pos != (Lb.im > PDT_R(0.0)) && (La.re < PDT_R(0.0) || Lb.re < PDT_R(0.0))) {
        /* Only a crossing that could move the gain margin is refined: the
         * loop's magnitude on the interval is about max(|La|, |Lb|). */
        pdt_real_t bound = PDT_R(1.5) * pdt_sqrt(rmax(ma, mb));
        if (bound > s->re_pc) {
            refine_pc(lp, s, wa, wb, a_pos);
        }
    }
}

/* Golden-section search of the least |1 + L|^2 over log w in [lo, hi]. */
static void refine_peak(const tune_loop_t *lp, tune_scan_t *s, pdt_real_t lo, pdt_real_t hi)
{
    const pdt_real_t gr = PDT_R(0.6180339887498949);
    pdt_real_t a = pdt_log(lo);
    pdt_real_t b = pdt_log(hi);
    pdt_real_t x1 = b - gr * (b - a);
    pdt_real_t x2 = a + gr * (b - a);
    pdt_real_t f1 = dist2(loop_eval(lp, pdt_exp(x1)));
    pdt_real_t f2 = dist2(loop_eval(lp, pdt_exp(x2)));
    for (int i = 0; i < TUNE_GOLDEN_STEPS; i++) {
        if (f1 < f2) {
            b = x2;
            x2 = x1;
            f2 = f1;
            x1 = b - gr * (b - a);
            f1 = dist2(loop_eval(lp, pdt_exp(x1)));
        } else {
            a = x1;
            x1 = x2;
            f1 = f2;
            x2 = a + gr * (b - a);
            f2 = dist2(loop_eval(lp, pdt_exp(x2)));
        }
    }
    s->evals += 2u + (uint32_t)TUNE_GOLDEN_STEPS;
    if (f1 < s->best_d2) {
        s->best_d2 = f1;
        s->best_w = pdt_exp(x1);
    }
    if (f2 < s->best_d2) {
        s->best_d2 = f2;
        s->best_w = pdt_exp(x2);
    }
}

/* The robustness figures' computation as a state: pdt_tune_robustness
 * runs it whole, the tuning in steps a budget of evaluations at a time. */
typedef struct tune_rob {
    tune_loop_t lp;
    tune_scan_t s;
    pdt_real_t r; /* |L(j inf)| */
    pdt_real_t top_big;
    pdt_real_t w_lo;
    pdt_real_t llo;
    pdt_real_t dl;
    pdt_real_t wa; /* the grid's last point and L there */
    tune_cplx_t La;
    int n0;       /* poles of L at s = 0 */
    unsigned i;   /* the grid's points left */
    int peak;     /* the next peak to refine */
    bool nyquist; /* the grid is done and the encirclement checked */
} tune_rob_t;

/* What the scan's frequency range is drawn from. */
typedef struct rob_scale {
    pdt_real_t kdc;  /* sign and size of L near w = 0 */
    pdt_real_t r;    /* |L(j inf)| */
    pdt_real_t tmin; /* the loop's shortest and longest time scales */
    pdt_real_t tmax;
    int n0; /* poles of L at s = 0 */
} rob_scale_t;

/* The loop of model m under gains g, with the plant's time scales. */
static void rob_loop(const pdt_model_t *m, const pdt_tune_gains_t *g, tune_loop_t *lp,
                     rob_scale_t *k)
{
    k->n0 = 1;
    k->r = PDT_R(0.0);
    k->tmin = PDT_REAL_MAX;
    k->tmax = PDT_R(0.0);
    lp->Kc = g->Kc;
    lp->tauI = g->tauI;
    lp->tauD = g->tauD;
    lp->Tf = g->tauD > PDT_R(0.0) ? g->Tf : PDT_R(0.0);
    pdt_model_view(m, &lp->p);
    const pdt_model_view_t *p = &lp->p;
    if (p->lags == 1u) {
        k->kdc = p->K;
        scale_add(p->tau, &k->tmin, &k->tmax);
        if (lp->tauD > PDT_R(0.0) && lp->Tf == PDT_R(0.0)) {
            k->r = pdt_fabs(lp->Kc * p->K * lp->tauD / p->tau);
        }
    } else {
        if (p->b > PDT_R(0.0)) {
            k->kdc = p->K / p->b;
            scale_add(p->a / p->b, &k->tmin, &k->tmax);
            scale_add(PDT_R(1.0) / pdt_sqrt(p->b), &k->tmin, &k->tmax);
        } else {
            k->kdc = p->K / p->a;
            k->n0 = 2;
        }
        scale_add(PDT_R(1.0) / p->a, &k->tmin, &k->tmax);
    }
}

/* The scan's range [*w_lo, *w_hi]: two decades beyond the loop's time
 * scales, widened until |L| is large at the bottom and below the top's
 * level at the top. False when it leaves the real type. */
static bool rob_range(const tune_loop_t *lp, const rob_scale_t *k, pdt_real_t *w_lo,
                      pdt_real_t *w_hi)
{
    pdt_real_t lo = PDT_R(0.01) / k->tmax;
    pdt_real_t hi = PDT_R(100.0) / k->tmin;
    pdt_real_t top = k->r > PDT_R(0.0) ? PDT_R(0.5) * (PDT_R(1.0) + k->r) : PDT_R(0.1);
    for (int i = 0; i < TUNE_WIDEN && abs2(loop_eval(lp, lo)) <= PDT_R(100.0); i++) {
        lo *= PDT_R(0.1);
    }
    for (int i = 0; i < TUNE_WIDEN && abs2(loop_eval(lp, hi)) >= top * top; i++) {
        hi *= PDT_R(10.0);
    }
    *w_lo = lo;
    *w_hi = hi;
    /* Time scales so far apart that the range the scan needs leaves the
     * real type: nothing below could be trusted. */
    return lo > PDT_R(0.0) && pdt_finite(hi);
}

/* The scan at its first point, w_hi, where L is La. */
static void scan_start(tune_scan_t *s, pdt_real_t w_hi, tune_cplx_t La)
{
    s->npeaks = 0;
    s->best_d2 = PDT_REAL_MAX;
    s->best_w = w_hi;
    s->pm = (pdt_real_t)INFINITY;
    s->w_gc = PDT_R(0.0);
    s->re_pc = PDT_R(0.0);
    s->w_pc = PDT_R(0.0);
    s->seen = 0;
    s->evals = 0u;
    s->w1 = s->w2 = s->d1 = s->d2 = PDT_R(0.0);
    s->phase = arg_1p(La);
    s->best_d2 = dist2(La);
    s->w1 = w_hi;
    s->d1 = s->best_d2;
    s->seen = 1;
}

/* Everything before the grid's scan: the loop, the frequency range and the
 * scan's first point. *R is its owner's scratch, written also on an error
 * (the loop in place saves a copy of it on the stack). */
static pdt_status_t rob_begin(const pdt_model_t *m, const pdt_tune_gains_t *g, tune_rob_t *R)
{
    if (m == NULL || g == NULL || pdt_model_check(m) != PDT_OK || !gains_valid(g)) {
        return PDT_ERR_ARG;
    }
    tune_loop_t *const lp = &R->lp;
    rob_scale_t k;
    rob_loop(m, g, lp, &k);
    if (k.kdc == PDT_R(0.0) || !pdt_finite(k.kdc)) {
        return PDT_ERR_ARG;
    }
    /* Positive feedback at low frequency, or a loop that keeps a gain of 1
     * or more at every high frequency behind a dead time: no stable loop. */
    if (k.kdc * lp->Kc < PDT_R(0.0) || k.r >= PDT_R(1.0)) {
        return PDT_ERR_UNSTABLE;
    }
    scale_add(lp->p.Td, &k.tmin, &k.tmax);
    scale_add(lp->tauI, &k.tmin, &k.tmax);
    scale_add(lp->tauD, &k.tmin, &k.tmax);
    scale_add(lp->Tf, &k.tmin, &k.tmax);

    pdt_real_t w_lo;
    pdt_real_t w_hi;
    if (!rob_range(lp, &k, &w_lo, &w_hi)) {
        return PDT_ERR_ARG;
    }
    /* From the top down, where |L| < 1 makes the principal arg(1 + L)
     * the continuous one. */
    pdt_real_t llo = pdt_log(w_lo);
    pdt_real_t lhi = pdt_log(w_hi);
    tune_cplx_t La = loop_eval(lp, w_hi);
    scan_start(&R->s, w_hi, La);
    R->r = k.r;
    R->top_big = rmax(PDT_R(0.5), PDT_R(0.5) * (PDT_R(1.0) + k.r));
    R->w_lo = w_lo;
    R->llo = llo;
    R->dl = (lhi - llo) / (pdt_real_t)(PDT_TUNE_GRID - 1u);
    R->wa = w_hi;
    R->La = La;
    R->n0 = k.n0;
    R->i = PDT_TUNE_GRID - 1u;
    R->peak = 0;
    R->nyquist = false;
    return PDT_OK;
}

/* The grid's intervals from the top down until the scan has made budget
 * evaluations of L (an interval is never cut): PDT_OK once the grid is
 * done, PDT_RUNNING before, PDT_ERR_UNSTABLE. */
static pdt_status_t rob_grid(tune_rob_t *R, uint32_t budget)
{
    const tune_loop_t *const lp = &R->lp;
    tune_scan_t *const s = &R->s;
    const pdt_real_t w_lo = R->w_lo;
    const pdt_real_t llo = R->llo;
    const pdt_real_t dl = R->dl;
    const pdt_real_t top_big = R->top_big;
    pdt_real_t wa = R->wa;
    tune_cplx_t La = R->La;
    const uint32_t start = s->evals;
    while (R->i > 0u) {
        R->i--;
        const unsigned i = R->i;
        pdt_real_t wb = i == 0u ? w_lo : pdt_exp(llo + (pdt_real_t)i * dl);
        tune_cplx_t Lb = loop_eval(lp, wb);
        s->evals++;
        int nsub = 1;
        pdt_real_t mag2 = rmax(abs2(La), abs2(Lb));
        if (mag2 >= TUNE_QUIET * TUNE_QUIET) {
            /* The dead time turns L by (wa - wb) Td over the interval,
             * which the principal arguments below cannot see past 2 pi. */
            const pdt_real_t eighth = PDT_R(0.25) * PDT_PI;
            pdt_real_t turn_d = (wa - wb) * lp->p.Td;
            pdt_real_t turn_l = pdt_fabs(wrap_pi(arg_of(Lb) - arg_of(La)));
            pdt_real_t turn_s = pdt_fabs(wrap_pi(arg_1p(Lb) - arg_1p(La)));
            if (!(turn_d <= (pdt_real_t)TUNE_SPLIT_MAX * eighth)) {
                /* Unresolvable: a loop gain near 1 where the dead time
                 * spins the phase this fast cannot be shown stable. */
                if (mag2 >= top_big * top_big) {
                    return PDT_ERR_UNSTABLE;
                }
                nsub = TUNE_SPLIT_MAX;
            } else {
                nsub = (int)(turn_d / eighth) + 1;
            }
            if ((turn_l > eighth || turn_s > eighth) && nsub < TUNE_SPLIT) {
                nsub = TUNE_SPLIT;
            }
        }
        if (nsub > 1) {
            pdt_real_t lwa = pdt_log(wa);
            pdt_real_t step = (pdt_log(wb) - lwa) / (pdt_real_t)nsub;
            pdt_real_t wp = wa;
            tune_cplx_t Lp = La;
            for (int k = 1; k < nsub; k++) {
                pdt_real_t wq = pdt_exp(lwa + (pdt_real_t)k * step);
                tune_cplx_t Lq = loop_eval(lp, wq);
                s->evals++;
                scan_step(lp, s, wp, Lp, wq, Lq);
                wp = wq;
                Lp = Lq;
            }
            scan_step(lp, s, wp, Lp, wb, Lb);
        } else {
            scan_step(lp, s, wa, La, wb, Lb);
        }
        wa = wb;
        La = Lb;
        wa = wb;
        La = Lb;
        if (s->evals - start >= budget) {
            break;
        }
    }
    R->wa = wa;
    R->La = La;
    return R->i == 0u ? PDT_OK : PDT_RUNNING;
}

/* One bounded part of the figures: the grid (budget evaluations of L, as
 * rob_grid), then the peaks, each refined whole, while the budget lasts.
 * PDT_OK with *fig written once complete, PDT_RUNNING before,
 * PDT_ERR_UNSTABLE. */
static pdt_status_t rob_step(tune_rob_t *R, uint32_t budget, pdt_tune_figures_t *fig)
{
    const uint32_t start = R->s.evals;
    if (!R->nyquist) {
        const pdt_status_t st = rob_grid(R, budget);
        if (st != PDT_OK) {
            return st;
        }
        /* Nyquist: arg(1 + L) at w -> 0+ must be -n0 pi / 2 (no RHP pole). */
        pdt_real_t want = -(pdt_real_t)R->n0 * PDT_R(0.5) * PDT_PI;
        if (pdt_fabs(R->s.phase - want) >= PDT_R(0.5) * PDT_PI) {
            return PDT_ERR_UNSTABLE;
        }
        R->nyquist = true;
    }
    tune_scan_t *const sp = &R->s;
    while (R->peak < sp->npeaks) {
        if (sp->evals - start >= budget) {
            return PDT_RUNNING;
        }
        refine_peak(&R->lp, sp, sp->peak_hi[R->peak], sp->peak_lo[R->peak]);
        R->peak++;
    }
    const tune_scan_t *const s = sp;
    const pdt_real_t r = R->r;
    pdt_tune_figures_t f;
    f.Ms = PDT_R(1.0) / pdt_sqrt(s->best_d2);
    f.w_ms = s->best_w;
    f.phase_margin_deg = s->pm;
    f.w_gc = s->w_gc;
    if (s->re_pc > PDT_R(0.0)) {
        f.gain_margin = PDT_R(1.0) / s->re_pc;
        f.w_pc = s->w_pc;
    } else {
        f.gain_margin = (pdt_real_t)INFINITY;
        f.w_pc = PDT_R(0.0);
    }
    if (r > PDT_R(0.0)) {
        pdt_real_t ms_lim = PDT_R(1.0) / (PDT_R(1.0) - r);
        if (ms_lim > f.Ms) {
            f.Ms = ms_lim;
            f.w_ms = (pdt_real_t)INFINITY;
        }
        if (PDT_R(1.0) / r < f.gain_margin) {
            f.gain_margin = PDT_R(1.0) / r;
            f.w_pc = (pdt_real_t)INFINITY;
        }
    }
    if (!(f.Ms > PDT_R(1.0))) {
        /* |S| < 1 at every finite frequency: its supremum is the limit 1
         * at w -> infinity. */
        f.Ms = PDT_R(1.0);
        f.w_ms = (pdt_real_t)INFINITY;
    }
    *fig = f;
    return PDT_OK;
}

pdt_status_t pdt_tune_robustness(const pdt_model_t *m, const pdt_tune_gains_t *g,
                                 pdt_tune_figures_t *fig)
{
    if (fig == NULL) {
        return PDT_ERR_ARG;
    }
    tune_rob_t R;
    pdt_status_t st = rob_begin(m, g, &R);
    if (st != PDT_OK) {
        return st;
    }
    return rob_step(&R, UINT32_MAX, fig);
}

/* ---- form conversions --------------------------------------------------- */

pdt_status_t pdt_tune_to_series(const pdt_tune_gains_t *ideal, pdt_tune_gains_t *series)
{
    if (ideal == NULL || series == NULL || !gains_valid(ideal)) {
        return PDT_ERR_ARG;
    }
    pdt_real_t disc = PDT_R(1.0) - PDT_R(4.0) * ideal->tauD / ideal->tauI;
    if (disc < PDT_R(0.0)) {
        /* A double zero (tauI = 4 tauD, e.g. Ziegler-Nichols) must not be
         * lost to the rounding of the ratio. */
        if (disc < PDT_R(-16.0) * PDT_REAL_EPS) {
            return PDT_ERR_NO_FORM;
        }
        disc = PDT_R(0.0);
    }
    /* Series tauI and tauD are the roots of x^2 - tauI' x + tauI' tauD';
     * the smaller from the product, so it does not cancel. */
    pdt_real_t ti = PDT_R(0.5) * ideal->tauI * (PDT_R(1.0) + pdt_sqrt(disc));
    pdt_tune_gains_t r;
    r.tauI = ti;
    r.tauD = ideal->tauD * (ideal->tauI / ti);
    r.Kc = ideal->Kc * (ti / ideal->tauI);
    r.Tf = ideal->Tf;
    if (!gains_valid(&r)) {
        return PDT_ERR_ARG;
    }
    *series = r;
    return PDT_OK;
}

pdt_status_t pdt_tune_to_ideal(const pdt_tune_gains_t *series, pdt_tune_gains_t *ideal)
{
    if (series == NULL || ideal == NULL || !gains_valid(series)) {
        return PDT_ERR_ARG;
    }
    pdt_real_t f = PDT_R(1.0) + series->tauD / series->tauI;
    pdt_tune_gains_t r;
    r.Kc = series->Kc * f;
    r.tauI = series->tauI * f;
    r.tauD = series->tauD / f;
    r.Tf = series->Tf;
    if (!gains_valid(&r)) {
        return PDT_ERR_ARG;
    }
    *ideal = r;
    return PDT_OK;
}

pdt_status_t pdt_tune_ziegler_nichols(pdt_real_t Ku, pdt_real_t Pu, pdt_tune_form_t form,
                                      pdt_tune_gains_t *out)
{
    if (out == NULL || !pdt_finite(Ku) || !pdt_finite(Pu) || Ku == PDT_R(0.0) ||
        !(Pu > PDT_R(0.0)) || (form != PDT_TUNE_PI && form != PDT_TUNE_PID)) {
        return PDT_ERR_ARG;
    }
    pdt_tune_gains_t r;
    if (form == PDT_TUNE_PI) {
        r.Kc = PDT_R(0.45) * Ku;
        r.tauI = Pu / PDT_R(1.2);
        r.tauD = PDT_R(0.0);
    } else {
        r.Kc = PDT_R(0.6) * Ku;
        r.tauI = PDT_R(0.5) * Pu;
        r.tauD = PDT_R(0.125) * Pu;
    }
    r.Tf = PDT_R(0.0);
    /* An ultimate gain at the bottom of the real range makes a gain that
     * underflows to 0, which is no controller. */
    if (r.Kc == PDT_R(0.0) || !(r.tauI > PDT_R(0.0))) {
        return PDT_ERR_ARG;
    }
    *out = r;
    return PDT_OK;
}

/* ---- the rules ---------------------------------------------------------- */

void pdt_tune_config_default(pdt_tune_config_t *cfg)
{
    if (cfg == NULL) {
        return;
    }
    cfg->rule = PDT_TUNE_SIMC;
    cfg->form = PDT_TUNE_PI;
    cfg->tau_c = PDT_R(0.0);
    cfg->lambda = PDT_R(0.0);
    cfg->detune = PDT_R(0.0);
    cfg->deriv_filter = PDT_R(10.0);
    cfg->fit_min = PDT_R(0.0);
    cfg->ms_max = PDT_R(2.0);
}

/* What a rule sees of the model. */
typedef enum tune_shape {
    SHAPE_FIRST = 0,   /* FOPDT */
    SHAPE_REAL = 1,    /* SOPDT, real poles T1 >= T2 */
    SHAPE_COMPLEX = 2, /* SOPDT, complex poles */
    SHAPE_INTEG = 3    /* SOPDT, b = 0 */
} tune_shape_t;

typedef struct tune_view {
    tune_shape_t shape;
    pdt_real_t K;     /* DC gain; integrating: Ki = k / a */
    pdt_real_t tau;   /* FOPDT tau or half-rule tau (FIRST, REAL) */
    pdt_real_t theta; /* Td or half-rule dead time (FIRST, REAL, INTEG) */
    pdt_real_t T1;    /* REAL: time constants; INTEG: T1 = 0, T2 = lag */
    pdt_real_t T2;
    pdt_real_t Td; /* the model's own dead time */
    pdt_real_t a;  /* SOPDT form (2) */
    pdt_real_t b;
    pdt_real_t k;
} tune_view_t;

static void view_of(const pdt_model_t *m, tune_view_t *v)
{
    pdt_model_view_t mv;
    pdt_model_view(m, &mv);
    v->T1 = v->T2 = v->a = v->b = v->k = PDT_R(0.0);
    if (mv.lags == 1u) {
        v->shape = SHAPE_FIRST;
        v->K = mv.K;
        v->tau = mv.tau;
        v->Td = v->theta = mv.Td;
        return;
    }
    /* Two lags: form (2), whose time constants the model module gives. */
    const pdt_model_sopdt_t two = {mv.K, mv.a, mv.b, mv.Td};
    const pdt_model_sopdt_t *p = &two;
    v->a = p->a;
    v->b = p->b;
    v->k = p->k;
    v->Td = p->Td;
    pdt_model_tc_t tc;
    if (p->b == PDT_R(0.0) || pdt_model_sopdt_to_tc(p, &tc) != PDT_OK) {
        v->shape = SHAPE_INTEG;
        v->K = p->k / p->a;
        v->T2 = PDT_R(1.0) / p->a;
        v->tau = PDT_R(0.0);
        v->theta = p->Td + PDT_R(0.5) * v->T2;
        return;
    }
    v->K = tc.K;
    if (tc.complex) {
        /* The rules that need a FOPDT get the half rule with the pair
         * split equally by its real part re = a / (2 b): tau = 1.5 re,
         * theta = Td + re / 2, continuous with the real pair at zeta = 1. */
        v->shape = SHAPE_COMPLEX;
        v->T1 = v->T2 = tc.T1;
        v->tau = PDT_R(1.5) * tc.T1;
        v->theta = p->Td + PDT_R(0.5) * tc.T1;
        return;
    }
    v->shape = SHAPE_REAL;
    v->T1 = tc.T1;
    v->T2 = tc.T2;
    v->tau = tc.T1 + PDT_R(0.5) * tc.T2;
    v->theta = p->Td + PDT_R(0.5) * tc.T2;
}

/* The rule's gains. series_rule: g holds series-form numbers. */
typedef struct tune_out {
    pdt_tune_gains_t g;
    bool series_rule;
    pdt_real_t knob;
} tune_out_t;

static pdt_real_t detune_of(const pdt_tune_config_t *cfg)
{
    return cfg->detune > PDT_R(0.0) ? cfg->detune : PDT_R(1.0);
}

static pdt_status_t rule_simc(const tune_view_t *v, const pdt_tune_config_t *cfg, tune_out_t *o)
{
    bool pid = cfg->form == PDT_TUNE_PID;
    /* SOPDT PID cancels the poles and keeps the model's own dead time; the
     * others see the half-rule FOPDT. */
    pdt_real_t theta = (pid && v->shape != SHAPE_FIRST) ? v->Td : v->theta;
    pdt_real_t tc = (cfg->tau_c > PDT_R(0.0) ? cfg->tau_c : theta) * detune_of(cfg);
    pdt_real_t tt = tc + theta;
    if (!(tt > PDT_R(0.0))) {
        return PDT_ERR_ARG;
    }
    o->knob = tc;
    o->series_rule = true;
    o->g.tauD = PDT_R(0.0);
    switch (v->shape) {
    case SHAPE_FIRST:
        o->g.Kc = v->tau / (v->K * tt);
        o->g.tauI = rmin(v->tau, PDT_R(4.0) * tt);
        break;
    case SHAPE_COMPLEX:
        if (pid) {
            /* Ideal PID whose zeros cancel the complex pair. */
            o->series_rule = false;
            o->g.Kc = v->a / (v->k * tt);
            o->g.tauI = v->a / v->b;
            o->g.tauD = PDT_R(1.0) / v->a;
        } else {
            o->g.Kc = v->tau / (v->K * tt);
            o->g.tauI = rmin(v->tau, PDT_R(4.0) * tt);
        }
        break;
    case SHAPE_REAL:
        if (pid) {
            o->g.Kc = v->T1 / (v->K * tt);
            o->g.tauI = rmin(v->T1, PDT_R(4.0) * tt);
            o->g.tauD = v->T2;
        } else {
            o->g.Kc = v->tau / (v->K * tt);
            o->g.tauI = rmin(v->tau, PDT_R(4.0) * tt);
        }
        break;
    case SHAPE_INTEG:
    default:
        o->g.Kc = PDT_R(1.0) / (v->K * tt);
        o->g.tauI = PDT_R(4.0) * tt;
        if (pid) {
            o->g.tauD = v->T2;
        }
        break;
    }
    return PDT_OK;
}

static pdt_status_t rule_imc(const tune_view_t *v, const pdt_tune_config_t *cfg, tune_out_t *o)
{
    bool pid = cfg->form == PDT_TUNE_PID;
    pdt_real_t lam = cfg->lambda;
    if (!(lam > PDT_R(0.0))) {
        if (v->shape == SHAPE_INTEG) {
            lam = PDT_R(3.0) * v->theta;
        } else if (pid && v->shape != SHAPE_FIRST) {
            lam = rmax(v->a / v->b, PDT_R(3.0) * v->Td);
        } else {
            lam = rmax(v->tau, PDT_R(3.0) * v->theta);
        }
    }
    lam *= detune_of(cfg);
    o->knob = lam;
    o->series_rule = false;
    o->g.tauD = PDT_R(0.0);
    if (v->shape == SHAPE_INTEG) {
        /* PID: the derivative cancels the lag (series form) and the PI
         * part sees the dead time alone. */
        pdt_real_t th = pid ? v->Td : v->theta;
        pdt_real_t lt = lam + th;
        o->g.Kc = (PDT_R(2.0) * lam + th) / (v->K * lt * lt);
        o->g.tauI = PDT_R(2.0) * lam + th;
        if (pid) {
            o->g.tauD = v->T2;
            o->series_rule = true;
        }
    } else if (!pid) {
        o->g.Kc = v->tau / (v->K * (lam + v->theta));
        o->g.tauI = v->tau;
    } else if (v->shape == SHAPE_FIRST) {
        pdt_real_t tau = v->tau;
        pdt_real_t th = v->theta;
        o->g.Kc = (PDT_R(2.0) * tau + th) / (v->K * (PDT_R(2.0) * lam + th));
        o->g.tauI = tau + PDT_R(0.5) * th;
        o->g.tauD = tau * th / (PDT_R(2.0) * tau + th);
    } else {
        /* SOPDT, either kind of pole pair: the zeros cancel the poles. */
        o->g.Kc = v->a / (v->k * (lam + v->Td));
        o->g.tauI = v->a / v->b;
        o->g.tauD = PDT_R(1.0) / v->a;
    }
    return PDT_OK;
}

static pdt_status_t rule_amigo(const tune_view_t *v, const pdt_tune_config_t *cfg, tune_out_t *o)
{
    bool pid = cfg->form == PDT_TUNE_PID;
    pdt_real_t L = v->theta;
    if (!(L > PDT_R(0.0))) {
        return PDT_ERR_ARG;
    }
    o->knob = PDT_R(0.0);
    o->series_rule = false;
    o->g.tauD = PDT_R(0.0);
    if (v->shape == SHAPE_INTEG) {
        if (pid) {
            o->g.Kc = PDT_R(0.45) / (v->K * L);
            o->g.tauI = PDT_R(8.0) * L;
            o->g.tauD = PDT_R(0.5) * L;
        } else {
            o->g.Kc = PDT_R(0.35) / (v->K * L);
            o->g.tauI = PDT_R(13.4) * L;
        }
        return PDT_OK;
    }
    pdt_real_t T = v->tau;
    if (pid) {
        o->g.Kc = (PDT_R(0.2) + PDT_R(0.45) * T / L) / v->K;
        o->g.tauI = (PDT_R(0.4) * L + PDT_R(0.8) * T) / (L + PDT_R(0.1) * T) * L;
        o->g.tauD = PDT_R(0.5) * L * T / (PDT_R(0.3) * L + T);
    } else {
        pdt_real_t s = L + T;
        o->g.Kc = (PDT_R(0.15) + (PDT_R(0.35) - L * T / (s * s)) * T / L) / v->K;
        o->g.tauI = PDT_R(0.35) * L +
                    PDT_R(13.0) * L * T * T / (T * T + PDT_R(12.0) * L * T + PDT_R(7.0) * L * L);
    }
    return PDT_OK;
}

static pdt_status_t rule_zn(const pdt_model_t *m, const pdt_tune_config_t *cfg, tune_out_t *o)
{
    pdt_real_t Td = pdt_model_dead_time(m);
    if (!(Td > PDT_R(0.0))) {
        return PDT_ERR_NO_FORM;
    }
    const pdt_real_t wu = pdt_model_phase_crossover(m);
    /* Ku carries the gain's sign: the rule's Kc has it. */
    const pdt_real_t gain = pdt_model_gain_numerator(m);
    pdt_real_t mag = pdt_model_magnitude_at(m, wu);
    mag = gain < PDT_R(0.0) ? -mag : mag;
    pdt_real_t Ku = PDT_R(1.0) / mag;
    pdt_real_t Pu = PDT_R(2.0) * PDT_PI / wu;
    if (pdt_tune_ziegler_nichols(Ku, Pu, cfg->form, &o->g) != PDT_OK) {
        return PDT_ERR_NO_FORM;
    }
    o->series_rule = false;
    o->knob = PDT_R(0.0);
    return PDT_OK;
}

static bool config_valid(const pdt_tune_config_t *cfg)
{
    bool rule_ok = cfg->rule == PDT_TUNE_SIMC || cfg->rule == PDT_TUNE_IMC ||
                   cfg->rule == PDT_TUNE_AMIGO || cfg->rule == PDT_TUNE_ZN;
    bool form_ok = cfg->form == PDT_TUNE_PI || cfg->form == PDT_TUNE_PID;
    return rule_ok && form_ok && pdt_finite(cfg->tau_c) && cfg->tau_c >= PDT_R(0.0) &&
           pdt_finite(cfg->lambda) && cfg->lambda >= PDT_R(0.0) && pdt_finite(cfg->detune) &&
           (cfg->detune == PDT_R(0.0) || cfg->detune >= PDT_R(1.0)) &&
           pdt_finite(cfg->deriv_filter) &&
           (cfg->deriv_filter == PDT_R(0.0) || cfg->deriv_filter >= PDT_R(1.0)) &&
           pdt_finite(cfg->fit_min) && pdt_finite(cfg->ms_max) &&
           (cfg->ms_max == PDT_R(0.0) || cfg->ms_max > PDT_R(1.0));
}

/* The rule's gains in both forms into *out (its figures not yet): what
 * pdt_tune_compute does before the robustness. */
static pdt_status_t tune_gains(const pdt_model_t *m, pdt_real_t fit, const pdt_tune_config_t *cfg,
                               pdt_tune_result_t *out)
{
    if (m == NULL || cfg == NULL || pdt_model_check(m) != PDT_OK || !config_valid(cfg) ||
        !pdt_finite(fit)) {
        return PDT_ERR_ARG;
    }
    tune_view_t v;
    view_of(m, &v);
    if (v.K == PDT_R(0.0) || !pdt_finite(v.K)) {
        return PDT_ERR_ARG;
    }
    tune_out_t o;
    pdt_status_t st;
    switch (cfg->rule) {
    case PDT_TUNE_SIMC:
        st = rule_simc(&v, cfg, &o);
        break;
    case PDT_TUNE_IMC:
        st = rule_imc(&v, cfg, &o);
        break;
    case PDT_TUNE_AMIGO:
        st = rule_amigo(&v, cfg, &o);
        break;
    case PDT_TUNE_ZN:
    default:
        st = rule_zn(m, cfg, &o);
        break;
    }
    if (st != PDT_OK) {
        return st;
    }
    if (fit < cfg->fit_min) {
        return PDT_ERR_POOR_FIT;
    }
    o.g.Tf = (cfg->deriv_filter > PDT_R(0.0) && o.g.tauD > PDT_R(0.0))
                 ? o.g.tauD / cfg->deriv_filter
                 : PDT_R(0.0);
    if (!gains_valid(&o.g)) {
        return PDT_ERR_ARG;
    }

    out->knob = o.knob;
    out->series_rule = o.series_rule;
    if (o.series_rule) {
        out->series = o.g;
        out->series_exists = true;
        st = pdt_tune_to_ideal(&o.g, &out->ideal);
        if (st != PDT_OK) {
            return st;
        }
    } else {
        out->ideal = o.g;
        out->series_exists = pdt_tune_to_series(&o.g, &out->series) == PDT_OK;
        if (!out->series_exists) {
            out->series.Kc = out->series.tauI = out->series.tauD = out->series.Tf = PDT_R(0.0);
        }
    }
    return PDT_OK;
}

pdt_status_t pdt_tune_compute(const pdt_model_t *m, pdt_real_t fit, const pdt_tune_config_t *cfg,
                              pdt_tune_result_t *out)
{
    if (out == NULL) {
        return PDT_ERR_ARG;
    }
    pdt_tune_result_t r;
    pdt_status_t st = tune_gains(m, fit, cfg, &r);
    if (st != PDT_OK) {
        return st;
    }
    st = pdt_tune_robustness(m, &r.ideal, &r.fig);
    if (st != PDT_OK) {
        return st;
    }
    if (cfg->ms_max > PDT_R(0.0) && r.fig.Ms > cfg->ms_max) {
        return PDT_ERR_MS_LIMIT;
    }
    *out = r;
    return PDT_OK;
}

/* ---- the tuning in steps ------------------------------------------------ */

#define TUNE_RUN_MAGIC PDT_MAGIC('P', 'D', 'T', 'S')

/* The state of a tuning in steps, in its workspace. */
typedef struct tune_run {
    tune_rob_t R;
    pdt_tune_result_t r;
    pdt_real_t ms_max;
    pdt_status_t status; /* PDT_RUNNING, then the outcome */
    uint32_t magic;
} tune_run_t;

/* The public bound covers the state and the padding that aligns it
 * (pdt_tune.h). */
typedef char
    tune_run_fits[(sizeof(tune_run_t) + sizeof(uintmax_t) <= PDT_TUNE_RUN_WORKSPACE_SIZE) ? 1 : -1];

/* The state in the workspace: its first address aligned for it. */
static tune_run_t *tune_run_of(void *work)
{
    return (tune_run_t *)pdt_aligned_state(work, PDT_TUNE_RUN_WORKSPACE_SIZE, sizeof(tune_run_t));
}

size_t pdt_tune_run_workspace_size(void)
{
    return PDT_TUNE_RUN_WORKSPACE_SIZE;
}

pdt_status_t pdt_tune_begin(const pdt_model_t *m, pdt_real_t fit, const pdt_tune_config_t *cfg,
                            void *work, size_t work_len)
{
    if (work == NULL || work_len < PDT_TUNE_RUN_WORKSPACE_SIZE) {
        return PDT_ERR_NOMEM;
    }
    tune_run_t *const T = tune_run_of(work);
    T->magic = 0u;
    pdt_status_t st = tune_gains(m, fit, cfg, &T->r);
    if (st == PDT_OK) {
        st = rob_begin(m, &T->r.ideal, &T->R);
    }
    if (st != PDT_OK) {
        return st;
    }
    T->ms_max = cfg->ms_max;
    T->status = PDT_RUNNING;
    T->magic = TUNE_RUN_MAGIC;
    return PDT_OK;
}

pdt_status_t pdt_tune_step(void *work, pdt_tune_result_t *out)
{
    if (work == NULL || out == NULL) {
        return PDT_ERR_ARG;
    }
    tune_run_t *const T = tune_run_of(work);
    if (T->magic != TUNE_RUN_MAGIC) {
        return PDT_ERR_STATE;
    }
    if (T->status == PDT_RUNNING) {
        pdt_status_t st = rob_step(&T->R, PDT_TUNE_STEP_EVALS, &T->r.fig);
        if (st == PDT_OK && T->ms_max > PDT_R(0.0) && T->r.fig.Ms > T->ms_max) {
            st = PDT_ERR_MS_LIMIT;
        }
        T->status = st;
    }
    if (T->status == PDT_OK) {
        *out = T->r;
    }
    return T->status;
}
