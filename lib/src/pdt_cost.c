/*
 * pdtfit cost functions: time-domain (prediction, simulation), frequency-
 * domain and combined costs of a model on one record. See pdt_cost.h.
 */
#include "pdt/pdt_cost.h"

#include "pdt_cost_engine.h"
#include "pdt_cost_kernel.h"
#include "pdt_cost_state.h"
#include "pdt_discrete_priv.h"
#include "pdt_internal.h"
#include "pdt_model_priv.h"

#if PDT_REAL_DOUBLE
#define pdt_ldexp ldexp
#define pdt_frexp frexp
#else
#define pdt_ldexp ldexpf
#define pdt_frexp frexpf
#endif

/* Samples per partial sum. Summing blocks first and then the block totals
 * keeps the rounding error of a float sum over thousands of samples near
 * (BLOCK + n / BLOCK) eps instead of n eps. */
#define PDT_COST_BLOCK 128u

void pdt_cost_config_default(pdt_cost_config_t *cfg)
{
    if (cfg == NULL) {
        return;
    }
    cfg->Ts = PDT_R(0.0);
    cfg->u0 = PDT_R(0.0);
    cfg->y0 = PDT_R(0.0);
    cfg->delay_min = 0u;
    cfg->delay_max = PDT_DELAY_HALF;
    cfg->kind = PDT_COST_COMBINED;
    cfg->time_kind = PDT_COST_SIMULATION;
    cfg->delay_mode = PDT_DELAY_FRACTIONAL;
    cfg->whole_record = false;
    cfg->estimate_offset = true;
    cfg->estimate_state = false;
    cfg->drift = false;
    cfg->use_frequency = true;
    cfg->phi_t = PDT_R(1.0);
    cfg->phi_f = PDT_R(1.0);
    cfg->weight = PDT_WEIGHT_UNIFORM;
    cfg->f_lo = PDT_R(0.0);
    cfg->f_hi = PDT_R(0.0);
    cfg->weights = NULL;
}

static size_t resolve_delay_max(size_t n, size_t delay_max)
{
    return pdt_delay_bound(n, delay_max);
}

size_t pdt_cost_fft_size(size_t n, size_t delay_max)
{
    const size_t max_nf = (size_t)1u << PDT_FFT_MAX_LOG2;
    size_t lu = resolve_delay_max(n, delay_max);
    size_t need = n;
    size_t nf = 16u;

    if (n == 0u || lu >= n || n > max_nf) {
        return 0u;
    }
    /* n <= 2^24 here, so 2 (n - lu) cannot overflow. */
    if (n - lu >= 2u && 2u * (n - lu) - 3u > need) {
        need = 2u * (n - lu) - 3u;
    }
    while (nf < need) {
        nf <<= 1u;
    }
    return (nf <= max_nf) ? nf : 0u;
}

/* Workspace bytes of the frequency part for FFT size nf, 0 if the FFT
 * does not support nf. */
static size_t spectra_bytes(size_t nf)
{
    size_t fft = pdt_fft_workspace_size(nf);
    if (fft == 0u) {
        return 0u;
    }
    return 3u * (nf / 2u) * sizeof(pdt_real_t) + fft;
}

size_t pdt_cost_workspace_size(const pdt_cost_config_t *cfg, size_t n)
{
    const size_t record = 2u * n * sizeof(pdt_real_t);
    size_t nf;
    if (cfg == NULL || n == 0u || n > ((size_t)1u << PDT_FFT_MAX_LOG2) ||
        pdt_delay_bound(n, cfg->delay_max) >= n) {
        return 0u;
    }
    if (!cfg->use_frequency) {
        return record;
    }
    nf = pdt_cost_fft_size(n, cfg->delay_max);
    return (nf == 0u) ? 0u : record + spectra_bytes(nf);
}

static bool kind_ok(pdt_cost_kind_t k)
{
    switch (k) {
    case PDT_COST_PREDICTION:
    case PDT_COST_SIMULATION:
    case PDT_COST_FREQUENCY:
    case PDT_COST_COMBINED:
        return true;
    default:
        return false;
    }
}

static bool weight_ok(pdt_weight_kind_t w)
{
    switch (w) {
    case PDT_WEIGHT_UNIFORM:
    case PDT_WEIGHT_BAND:
    case PDT_WEIGHT_CUSTOM:
        return true;
    default:
        return false;
    }
}

static bool mode_ok(pdt_delay_mode_t m)
{
    return m == PDT_DELAY_FRACTIONAL || m == PDT_DELAY_INTEGER;
}

/* The PDT_ERR_ARG checks of a config that need neither n nor N_f. */
static bool config_ok(const pdt_cost_config_t *cfg)
{
    if (!pdt_finite(cfg->Ts) || !(cfg->Ts > PDT_R(0.0))) {
        return false;
    }
    if (!kind_ok(cfg->kind) || !weight_ok(cfg->weight) || !mode_ok(cfg->delay_mode)) {
        return false;
    }
    if (cfg->time_kind != PDT_COST_PREDICTION && cfg->time_kind != PDT_COST_SIMULATION) {
        return false;
    }
    if (!pdt_finite(cfg->phi_t) || cfg->phi_t < PDT_R(0.0) || !pdt_finite(cfg->phi_f) ||
        cfg->phi_f < PDT_R(0.0)) {
        return false;
    }
    if (!pdt_finite(cfg->f_lo) || cfg->f_lo < PDT_R(0.0) || !pdt_finite(cfg->f_hi) ||
        cfg->f_hi < PDT_R(0.0)) {
        return false;
    }
    if (cfg->weight == PDT_WEIGHT_CUSTOM && cfg->weights == NULL) {
        return false;
    }
    /* The extra columns are the simulation's (pdt_cost_state.c). */
    return !(cfg->estimate_state || cfg->drift) || cfg->kind == PDT_COST_SIMULATION;
}

/* FFT of the zero-padded deviations x - x0 in buf (nf reals), then
 * |X(k)|, k = 1 .. nf/2, compacted in place into buf[0 .. nf/2 - 1]. Bin k
 * is read from buf[2k], buf[2k+1] and written to buf[k - 1], below
 * anything still to be read, once the Nyquist value in buf[1] is saved. */
static pdt_status_t spectrum_magnitude(const pdt_fft_t *f, const pdt_real_t *x, pdt_real_t x0,
                                       size_t n, size_t nf, pdt_real_t *buf)
{
    pdt_status_t st;
    pdt_real_t nyquist;
    size_t k;

    for (k = 0u; k < n; k++) {
        buf[k] = x[k] - x0;
    }
    for (k = n; k < nf; k++) {
        buf[k] = PDT_R(0.0);
    }
    st = pdt_fft_forward(f, buf);
    if (st != PDT_OK) {
        return st;
    }
    nyquist = pdt_fabs(buf[1]);
    for (k = 1u; k < nf / 2u; k++) {
        buf[k - 1u] = pdt_hypot(buf[2u * k], buf[2u * k + 1u]);
    }
    buf[nf / 2u - 1u] = nyquist;
    return PDT_OK;
}

/* W(k) m_k / (N_f n), bin k of 1 .. nf/2 (m_k = 2 below the Nyquist bin). */
static pdt_real_t bin_weight(const pdt_cost_config_t *cfg, size_t n, size_t nf, size_t k)
{
    const pdt_real_t scale = PDT_R(1.0) / ((pdt_real_t)nf * (pdt_real_t)n);
    pdt_real_t w = PDT_R(1.0);
    if (cfg->weight == PDT_WEIGHT_BAND) {
        pdt_real_t fk = (pdt_real_t)k / ((pdt_real_t)nf * cfg->Ts);
        w = (fk >= cfg->f_lo && fk <= cfg->f_hi) ? PDT_R(1.0) : PDT_R(0.0);
    } else if (cfg->weight == PDT_WEIGHT_CUSTOM) {
        w = cfg->weights[k];
    }
    w *= scale;
    if (k < nf / 2u) {
        w *= PDT_R(2.0);
    }
    return w;
}

/* Fills wgt[k - 1] = W(k) m_k / (N_f n) for k = 1 .. nf/2 and the range of
 * non-zero weights. */
static void fill_weights(const pdt_cost_config_t *cfg, size_t n, size_t nf, pdt_real_t *wgt,
                         size_t *k_first, size_t *k_last)
{
    const size_t nb = nf / 2u;
    size_t first = nb + 1u;
    size_t last = 0u;
    size_t k;

    for (k = 1u; k <= nb; k++) {
        const pdt_real_t w = bin_weight(cfg, n, nf, k);
        wgt[k - 1u] = w;
        if (w != PDT_R(0.0)) {
            if (first > nb) {
                first = k;
            }
            last = k;
        }
    }
    *k_first = first;
    *k_last = last;
}

bool pdt_cost_band_empty(const pdt_cost_config_t *cfg, size_t n)
{
    if (cfg == NULL || !cfg->use_frequency || !config_ok(cfg) || n == 0u) {
        return false;
    }
    const size_t nf = pdt_cost_fft_size(n, resolve_delay_max(n, cfg->delay_max));
    for (size_t k = 1u; k <= nf / 2u; k++) {
        if (bin_weight(cfg, n, nf, k) != PDT_R(0.0)) {
            return false;
        }
    }
    return nf != 0u;
}

/* Jumps between samples are compared at half scale, so that the
 * difference of two finite floats cannot overflow. */
static pdt_real_t half_jump(const pdt_real_t *x, size_t k)
{
    return pdt_fabs(PDT_R(0.5) * x[k] - PDT_R(0.5) * x[k - 1u]);
}

/* A gross outlier is a gap in the sizes of a signal's jumps: a few jumps
 * at least OUTLIER_GAP times the largest of all the other non-zero ones.
 * A level never enters (the test is blind to the operating point, which a
 * bad cell in the rest window would spoil); a clean step or relay signal
 * has no other non-zero jumps and passes; a response that decays into the
 * rounding fills the sizes between and passes too. */
#define OUTLIER_GAP PDT_R(16777216.0)

size_t pdt_cost_outlier(const pdt_real_t *x, size_t n)
{
    pdt_real_t top = PDT_R(0.0), thr, below = PDT_R(0.0), low_high;
    size_t k, high = 0u, first = n;
    if (x == NULL || n < 2u) {
        return n;
    }
    for (k = 1u; k < n; k++) {
        pdt_real_t j = half_jump(x, k);
        top = j > top ? j : top;
    }
    if (!(top > PDT_R(0.0)) || !pdt_finite(top)) {
        return n;
    }
    thr = top / OUTLIER_GAP;
    low_high = top;
    for (k = 1u; k < n; k++) {
        pdt_real_t j = half_jump(x, k);
        if (j >= thr) {
            high++;
            first = (first == n) ? k : first;
            low_high = j < low_high ? j : low_high;
        } else if (j > below) {
            below = j;
        }
    }
    if (!(below > PDT_R(0.0)) || high > 2u + n / 64u || low_high < below * OUTLIER_GAP) {
        return n;
    }
    /* A lone jump at the start is the first sample standing off. */
    return (high == 1u && first == 1u) ? 0u : first;
}

/* The record's scales as multipliers (pdt_cost_t.pow2): a product with a
 * normal power of two rounds exactly as ldexp does, and costs a fraction
 * of the call the evaluation would otherwise make several times. */
#define POW2_TO_NORM_GAIN 0u
#define POW2_TO_GAIN      1u
#define POW2_TO_OUT       2u
#define POW2_TO_COST      3u

static pdt_real_t pow2_of(int e)
{
    const pdt_real_t s = pdt_ldexp(PDT_R(1.0), e);
    return (s >= PDT_REAL_MIN_NORMAL && s <= PDT_REAL_MAX) ? s : PDT_R(0.0);
}

/* v 2^e, by the multiplier s = pow2_of(e) when it is one. */
static pdt_real_t by_pow2(pdt_real_t v, pdt_real_t s, int e)
{
    return (s > PDT_R(0.0)) ? v * s : pdt_ldexp(v, e);
}

/* Copies x - x0 into out scaled by a power of two into (-1, 1) and
 * returns the exponent e: x - x0 = out 2^e. The difference is formed at
 * half scale, which cannot overflow. */
static int normalise(const pdt_real_t *x, pdt_real_t x0, size_t n, pdt_real_t *out)
{
    const pdt_real_t h0 = PDT_R(0.5) * x0;
    pdt_real_t top = PDT_R(0.0);
    int e = 0;
    size_t k;
    for (k = 0u; k < n; k++) {
        pdt_real_t dv = pdt_fabs(PDT_R(0.5) * x[k] - h0);
        top = dv > top ? dv : top;
    }
    if (top > PDT_R(0.0)) {
        (void)pdt_frexp(top, &e);
    }
    const pdt_real_t s = pow2_of(-e);
    for (k = 0u; k < n; k++) {
        out[k] = by_pow2(PDT_R(0.5) * x[k] - h0, s, -e);
    }
    return e + 1;
}

/* Sum and centred sum of squares of x[k0..n-1], in blocks. */
static void window_moments(const pdt_real_t *x, size_t k0, size_t n, pdt_real_t *sum,
                           pdt_real_t *var)
{
    pdt_real_t s = PDT_R(0.0), v = PDT_R(0.0), blk = PDT_R(0.0), mean;
    size_t k;
    for (k = k0; k < n; k++) {
        blk += x[k];
        if ((k - k0) % PDT_COST_BLOCK == PDT_COST_BLOCK - 1u) {
            s += blk;
            blk = PDT_R(0.0);
        }
    }
    s += blk;
    mean = s / (pdt_real_t)(n - k0);
    blk = PDT_R(0.0);
    for (k = k0; k < n; k++) {
        pdt_real_t d = x[k] - mean;
        blk += d * d;
        if ((k - k0) % PDT_COST_BLOCK == PDT_COST_BLOCK - 1u) {
            v += blk;
            blk = PDT_R(0.0);
        }
    }
    *sum = s;
    *var = v + blk;
}

static size_t first_scored(const pdt_cost_t *c, uint8_t order, bool pred);

/* pdt_cost_init's checks of its arguments and of the record, in the order
 * of its documented statuses; *lu the delay bound resolved. */
static pdt_status_t init_check(const pdt_cost_config_t *cfg, const pdt_real_t *u,
                               const pdt_real_t *y, size_t n, size_t *lu)
{
    size_t k;
    *lu = resolve_delay_max(n, cfg->delay_max);
    if (*lu >= n || n - (cfg->whole_record ? 0u : *lu) < (size_t)PDT_MIN_SAMPLES + 2u) {
        return PDT_ERR_TOO_SHORT;
    }
    if (cfg->delay_min > *lu || cfg->f_lo > cfg->f_hi) {
        return PDT_ERR_BOUNDS;
    }
    for (k = 0u; k < n; k++) {
        if (!pdt_finite(u[k]) || !pdt_finite(y[k])) {
            return PDT_ERR_NONFINITE;
        }
    }
    /* Before the operating point: a caller's level estimated from a
     * stretch with a bad cell in it may have overflowed on it. */
    if (pdt_cost_outlier(u, n) != n || pdt_cost_outlier(y, n) != n) {
        return PDT_ERR_OUTLIER;
    }
    if (!pdt_finite(cfg->u0) || !pdt_finite(cfg->y0)) {
        return PDT_ERR_NONFINITE;
    }
    return PDT_OK;
}

/* The frequency part's size: its FFT length *nf, the bin spacing in
 * t->w_step, and the workspace bytes *need grown by the spectra's (0 when
 * they overflow); the custom weights checked. */
static pdt_status_t init_frequency_size(const pdt_cost_config_t *cfg, size_t n, size_t lu,
                                        pdt_cost_t *t, size_t *nf, size_t *need)
{
    size_t k;
    *nf = pdt_cost_fft_size(n, lu);
    if (*nf == 0u) {
        return PDT_ERR_LENGTH;
    }
    t->w_step = (PDT_R(2.0) * PDT_PI) / ((pdt_real_t)*nf * cfg->Ts);
    if (!pdt_finite(t->w_step)) {
        return PDT_ERR_ARG;
    }
    if (cfg->weight == PDT_WEIGHT_CUSTOM) {
        for (k = 0u; k <= *nf / 2u; k++) {
            if (!pdt_finite(cfg->weights[k]) || cfg->weights[k] < PDT_R(0.0)) {
                return PDT_ERR_ARG;
            }
        }
    }
    *need = (spectra_bytes(*nf) == 0u) ? 0u : *need + spectra_bytes(*nf);
    return PDT_OK;
}

/* The record normalised into the workspace's first 2 n reals, with its
 * scales and the output's moments over the scored windows. */
static void init_normalise(pdt_cost_t *t, const pdt_cost_config_t *cfg, const pdt_real_t *u,
                           const pdt_real_t *y, size_t n, pdt_real_t *un)
{
    size_t k;
    pdt_real_t *yn = un + n;
    t->u_exp = normalise(u, cfg->u0, n, un);
    t->y_exp = normalise(y, cfg->y0, n, yn);
    t->pow2[POW2_TO_NORM_GAIN] = pow2_of(t->u_exp - t->y_exp);
    t->pow2[POW2_TO_GAIN] = pow2_of(t->y_exp - t->u_exp);
    t->pow2[POW2_TO_OUT] = pow2_of(t->y_exp);
    t->pow2[POW2_TO_COST] = pow2_of(2 * t->y_exp);
    t->u = un;
    t->y = yn;
    for (k = 0u; k < 2u; k++) {
        window_moments(yn, first_scored(t, (uint8_t)(k + 1u), false), n, &t->ysum[k], &t->yvar[k]);
    }
}

/* The frequency part's spectra after the normalised record (base), nf
 * points, in the workspace's remaining work_len bytes. */
static pdt_status_t init_spectra(pdt_cost_t *t, const pdt_cost_config_t *cfg, size_t n, size_t nf,
                                 pdt_real_t *base, size_t work_len)
{
    const size_t nb = nf / 2u;
    pdt_fft_t fft;
    pdt_status_t st;
    /* Layout (reals): [0, nb) |U|, [nb, 2nb) |Y|, [2nb, 3nb) weights,
     * then the twiddles. u's FFT buffer is [0, 2nb) and leaves |U| at
     * its start; y's is [nb, 3nb) and leaves |Y| at its start; the
     * weights come last, over the end of y's buffer. The spectra are of
     * the normalised record, like everything else. */
    st = pdt_fft_init(&fft, nf, base + 3u * nb, work_len - (2u * n + 3u * nb) * sizeof(pdt_real_t));
    if (st == PDT_OK) {
        st = spectrum_magnitude(&fft, t->u, PDT_R(0.0), n, nf, base);
    }
    if (st == PDT_OK) {
        st = spectrum_magnitude(&fft, t->y, PDT_R(0.0), n, nf, base + nb);
    }
    if (st != PDT_OK) {
        /* Cannot happen for an nf that pdt_cost_fft_size returned. */
        return st;
    }
    fill_weights(cfg, n, nf, base + 2u * nb, &t->k_first, &t->k_last);
    t->nf = nf;
    t->umag = base;
    t->ymag = base + nb;
    t->wgt = base + 2u * nb;
    return PDT_OK;
}

pdt_status_t pdt_cost_init(pdt_cost_t *c, const pdt_cost_config_t *cfg, const pdt_real_t *u,
                           const pdt_real_t *y, size_t n, void *work, size_t work_len)
{
    pdt_cost_t t;
    size_t lu;
    size_t nf = 0u;
    size_t need = 2u * n * sizeof(pdt_real_t);
    pdt_status_t st;

    if (c == NULL || cfg == NULL || u == NULL || y == NULL || !config_ok(cfg)) {
        return PDT_ERR_ARG;
    }
    st = init_check(cfg, u, y, n, &lu);
    if (st != PDT_OK) {
        return st;
    }

    t.cfg = *cfg;
    t.cfg.delay_max = lu;
    t.n = n;
    t.nf = 0u;
    t.k_first = 1u;
    t.k_last = 0u;
    t.umag = NULL;
    t.ymag = NULL;
    t.wgt = NULL;
    t.w_step = PDT_R(0.0);

    if (cfg->use_frequency) {
        st = init_frequency_size(cfg, n, lu, &t, &nf, &need);
        if (st != PDT_OK) {
            return st;
        }
    }
    if (work == NULL) {
        return PDT_ERR_NOMEM;
    }
    if (!pdt_aligned(work)) {
        return PDT_ERR_ARG;
    }
    if (need == 0u || work_len < need) {
        return PDT_ERR_NOMEM;
    }

    pdt_real_t *const un = (pdt_real_t *)work;
    init_normalise(&t, cfg, u, y, n, un);
    if (cfg->use_frequency) {
        st = init_spectra(&t, cfg, n, nf, un + 2u * n, work_len);
        if (st != PDT_OK) {
            return st;
        }
    }
    /* Only the weights were needed from the caller's array; do not keep a
     * pointer that the caller may let go. */
    t.cfg.weights = NULL;
    *c = t;
    return PDT_OK;
}

/* Sum of squares (and of values) of residuals, in blocks, shifted by the
 * first residual when the mean is to be removed: the variance then comes
 * from numbers near the residual's own spread instead of from two large
 * sums that cancel. */
typedef struct pdt_cost_acc {
    pdt_real_t shift;
    pdt_real_t s1, s2; /* completed blocks */
    pdt_real_t b1, b2; /* current block */
    unsigned fill;
    bool started;
    bool offset;
} pdt_cost_acc_t;

static void acc_start(pdt_cost_acc_t *a, bool offset)
{
    a->shift = PDT_R(0.0);
    a->s1 = PDT_R(0.0);
    a->s2 = PDT_R(0.0);
    a->b1 = PDT_R(0.0);
    a->b2 = PDT_R(0.0);
    a->fill = 0u;
    a->started = false;
    a->offset = offset;
}

static inline void acc_add(pdt_cost_acc_t *a, pdt_real_t r)
{
    pdt_real_t e;
    if (!a->started) {
        a->started = true;
        if (a->offset) {
            a->shift = r;
        }
    }
    e = r - a->shift;
    a->b1 += e;
    a->b2 += e * e;
    if (++a->fill == PDT_COST_BLOCK) {
        a->s1 += a->b1;
        a->s2 += a->b2;
        a->b1 = PDT_R(0.0);
        a->b2 = PDT_R(0.0);
        a->fill = 0u;
    }
}

static pdt_real_t acc_result(const pdt_cost_acc_t *a, size_t count)
{
    pdt_real_t cnt = (pdt_real_t)count;
    pdt_real_t m2 = (a->s2 + a->b2) / cnt;
    pdt_real_t v = m2;
    if (a->offset) {
        pdt_real_t m1 = (a->s1 + a->b1) / cnt;
        v = m2 - m1 * m1;
        if (v < PDT_R(0.0)) {
            v = PDT_R(0.0); /* rounding of an (almost) constant residual */
        }
    }
    if (!pdt_finite(v)) {
        v = (pdt_real_t)INFINITY;
    }
    return v;
}

static bool prepared(const pdt_cost_t *c)
{
    return c != NULL && c->u != NULL && c->y != NULL && c->n != 0u;
}

static pdt_status_t check_dmodel(const pdt_cost_t *c, const pdt_discrete_t *d)
{
    size_t i;
    if (d->order != 1u && d->order != 2u) {
        return PDT_ERR_ARG;
    }
    if (d->delay < c->cfg.delay_min || d->delay > c->cfg.delay_max) {
        return PDT_ERR_ARG;
    }
    for (i = 0u; i < 3u; i++) {
        if (!pdt_finite(d->b[i])) {
            return PDT_ERR_ARG;
        }
    }
    if (!pdt_finite(d->d[0]) || (d->order == 2u && !pdt_finite(d->d[1]))) {
        return PDT_ERR_ARG;
    }
    return PDT_OK;
}

/* The first sample the time costs score. Over the whole record the
 * simulation starts at k = 0, where its output from rest is known; the
 * prediction needs `order` measured outputs before k. Leaving out the
 * first two samples of a simulation moved the minimum of a near-integrating
 * SOPDT along its flat valley by a tenth of its dead time. */
static size_t first_scored(const pdt_cost_t *c, uint8_t order, bool pred)
{
    if (c->cfg.whole_record) {
        return pred ? order : 0u;
    }
    return c->cfg.delay_max + order;
}

/* Normalised input u(k - back), 0 before the record. */
PDT_INLINE_TINY pdt_real_t u_dev(const pdt_cost_t *c, size_t k, size_t back)
{
    return (k >= back) ? c->u[k - back] : PDT_R(0.0);
}

/* What the response of a model to the normalised input is multiplied by to
 * be in the normalised output's units. */
static pdt_real_t unit_ratio(const pdt_cost_t *c)
{
    return by_pow2(PDT_R(1.0), c->pow2[POW2_TO_NORM_GAIN], c->u_exp - c->y_exp);
}

/* A normalised cost (mean square) in output units squared. */
static pdt_real_t cost_units(const pdt_cost_t *c, pdt_real_t v)
{
    return by_pow2(v, c->pow2[POW2_TO_COST], 2 * c->y_exp);
}

/* Simulation state in delta form: ys = ysim(k-1), dys = ysim(k-1) -
 * ysim(k-2), so a slow pole updates the output by small steps instead of
 * recomputing it from large terms that nearly cancel; p1, p2 hold the two
 * previous delayed inputs. */
typedef struct sim_state {
    pdt_real_t p1, p2, ys, dys;
} sim_state_t;

/* One sample of the simulation: u1 = u(k-1-l); returns ysim(k). */
PDT_INLINE_TINY pdt_real_t sim_step(const pdt_discrete_t *d, sim_state_t *s, pdt_real_t u1)
{
    pdt_real_t bu = d->b[0] * u1 + d->b[1] * s->p1 + d->b[2] * s->p2;
    if (d->order == 1u) {
        s->ys += bu - d->d[0] * s->ys;
    } else {
        pdt_real_t ys2 = s->ys - s->dys;
        s->dys += bu - d->d[0] * s->dys - d->d[1] * ys2;
        s->ys += s->dys;
    }
    s->p2 = s->p1;
    s->p1 = u1;
    return s->ys;
}

/* The time costs of d, whose input part is multiplied by g, in normalised
 * units. */
static pdt_real_t prediction_cost(const pdt_cost_t *c, const pdt_discrete_t *d, pdt_real_t g)
{
    const pdt_real_t *y = c->y;
    const size_t l = d->delay;
    const size_t k0 = first_scored(c, d->order, true);
    pdt_real_t p1 = u_dev(c, k0, l + 2u); /* u(k-2-l) and u(k-3-l) at k = k0 */
    pdt_real_t p2 = u_dev(c, k0, l + 3u);
    pdt_cost_acc_t acc;
    size_t k;

    acc_start(&acc, c->cfg.estimate_offset);
    for (k = k0; k < c->n; k++) {
        pdt_real_t u1 = u_dev(c, k, l + 1u);
        pdt_real_t bu = d->b[0] * u1 + d->b[1] * p1 + d->b[2] * p2;
        pdt_real_t dy = y[k] - y[k - 1u];
        pdt_real_t r;
        if (d->order == 1u) {
            /* A(q) y = (1 - q) y + d0 q y */
            r = dy + d->d[0] * y[k - 1u] - g * bu;
        } else {
            /* A(q) y = (1 - q)^2 y + d0 q (1 - q) y + d1 q^2 y */
            pdt_real_t dy1 = y[k - 1u] - y[k - 2u];
            r = (dy - dy1) + d->d[0] * dy1 + d->d[1] * y[k - 2u] - g * bu;
        }
        acc_add(&acc, r);
        p2 = p1;
        p1 = u1;
    }
    return acc_result(&acc, c->n - k0);
}

static pdt_real_t simulation_cost(const pdt_cost_t *c, const pdt_discrete_t *d, pdt_real_t g)
{
    const pdt_real_t *y = c->y;
    const size_t l = d->delay;
    const size_t k0 = first_scored(c, d->order, false);
    sim_state_t st = {PDT_R(0.0), PDT_R(0.0), PDT_R(0.0), PDT_R(0.0)};
    pdt_cost_acc_t acc;
    size_t k;

    acc_start(&acc, c->cfg.estimate_offset);
    for (k = 0u; k < c->n; k++) {
        pdt_real_t ys = sim_step(d, &st, u_dev(c, k, l + 1u));
        if (k >= k0) {
            acc_add(&acc, y[k] - g * ys);
        }
    }
    return acc_result(&acc, c->n - k0);
}

pdt_status_t pdt_cost_prediction(const pdt_cost_t *c, const pdt_discrete_t *d, pdt_real_t *cost)
{
    if (!prepared(c) || d == NULL || cost == NULL || check_dmodel(c, d) != PDT_OK) {
        return PDT_ERR_ARG;
    }
    *cost = cost_units(c, prediction_cost(c, d, unit_ratio(c)));
    return PDT_OK;
}

pdt_status_t pdt_cost_simulation(const pdt_cost_t *c, const pdt_discrete_t *d, pdt_real_t *cost)
{
    if (!prepared(c) || d == NULL || cost == NULL || check_dmodel(c, d) != PDT_OK) {
        return PDT_ERR_ARG;
    }
    *cost = cost_units(c, simulation_cost(c, d, unit_ratio(c)));
    return PDT_OK;
}

/* Cf of a checked model on a cost prepared with spectra, normalised. */
static pdt_real_t frequency_cost(const pdt_cost_t *c, const pdt_model_t *m)
{
    const pdt_real_t ratio = unit_ratio(c);
    pdt_model_view_t v;
    pdt_model_view(m, &v);
    const bool first_order = (v.lags == 1u);
    const pdt_real_t gain = pdt_fabs(v.K) * ratio;
    const pdt_real_t tau = v.tau;
    const pdt_real_t a = v.a;
    const pdt_real_t b = v.b;
    pdt_real_t s = PDT_R(0.0);
    pdt_real_t blk = PDT_R(0.0);
    unsigned fill = 0u;
    size_t k;

    for (k = c->k_first; k <= c->k_last; k++) {
        pdt_real_t w = (pdt_real_t)k * c->w_step;
        pdt_real_t g;
        pdt_real_t e;
        if (first_order) {
            pdt_real_t wt = w * tau;
            g = gain / pdt_sqrt(PDT_R(1.0) + wt * wt);
        } else {
            pdt_real_t re = b - w * w;
            pdt_real_t im = a * w;
            g = gain / pdt_sqrt(re * re + im * im);
        }
        e = c->ymag[k - 1u] - g * c->umag[k - 1u];
        blk += c->wgt[k - 1u] * e * e;
        if (++fill == PDT_COST_BLOCK) {
            s += blk;
            blk = PDT_R(0.0);
            fill = 0u;
        }
    }
    s += blk;
    return pdt_finite(s) ? s : (pdt_real_t)INFINITY;
}

pdt_status_t pdt_cost_frequency(const pdt_cost_t *c, const pdt_model_t *m, pdt_real_t *cost)
{
    if (!prepared(c) || m == NULL || cost == NULL || c->nf == 0u || pdt_model_check(m) != PDT_OK) {
        return PDT_ERR_ARG;
    }
    *cost = cost_units(c, frequency_cost(c, m));
    return PDT_OK;
}

/* The discrete model pdt_cost_eval scores m with, per delay_mode. */
static pdt_status_t eval_discretize(const pdt_cost_t *c, const pdt_model_t *m, pdt_discrete_t *d)
{
    const pdt_real_t Ts = c->cfg.Ts;
    pdt_status_t st;

    if (c->cfg.delay_mode == PDT_DELAY_INTEGER) {
        pdt_real_t x = pdt_floor(pdt_model_dead_time(m) / Ts + PDT_R(0.5));
        size_t l;
        /* Range check in reals first: the conversion of a value beyond
         * size_t would be undefined. delay_max < n <= 2^24 fits exactly. */
        if (!pdt_finite(x) || x < PDT_R(0.0) || x > (pdt_real_t)c->cfg.delay_max) {
            return PDT_ERR_ARG;
        }
        l = (size_t)x;
        st = pdt_discrete_init_int(m, Ts, l, d);
    } else {
        /* Every caller checked m, and init checked Ts. */
        st = pdt_discrete_init_checked(m, Ts, d);
    }
    if (st != PDT_OK) {
        return PDT_ERR_ARG;
    }
    return check_dmodel(c, d);
}

/* The criterion's value, normalised, from its time part ct and its
 * frequency part cf: pdt_cost_eval's and the profile's. */
static pdt_real_t cost_total(const pdt_cost_t *c, pdt_real_t ct, pdt_real_t cf)
{
    const pdt_cost_kind_t kind = c->cfg.kind;
    if (kind != PDT_COST_COMBINED) {
        return (kind == PDT_COST_FREQUENCY) ? cf : ct;
    }
    pdt_real_t total = PDT_R(0.0);
    if (c->cfg.phi_t > PDT_R(0.0)) {
        total += c->cfg.phi_t * ct;
    }
    if (c->cfg.phi_f > PDT_R(0.0)) {
        total += c->cfg.phi_f * cf;
    }
    if (!pdt_finite(total)) {
        total = (pdt_real_t)INFINITY;
    }
    return total;
}

pdt_status_t pdt_cost_eval(const pdt_cost_t *c, const pdt_model_t *m, pdt_real_t *cost)
{
    pdt_cost_kind_t kind;
    pdt_cost_kind_t tkind;
    pdt_real_t ct = PDT_R(0.0);
    pdt_real_t cf = PDT_R(0.0);
    pdt_real_t total;
    pdt_discrete_t d;
    bool need_time;
    bool need_freq;

    if (!prepared(c) || m == NULL || cost == NULL || pdt_model_check(m) != PDT_OK) {
        return PDT_ERR_ARG;
    }
    kind = c->cfg.kind;
    tkind = (kind == PDT_COST_COMBINED) ? c->cfg.time_kind : kind;
    need_freq = (kind == PDT_COST_FREQUENCY || kind == PDT_COST_COMBINED);
    need_time = (kind != PDT_COST_FREQUENCY);
    if (need_freq && c->nf == 0u) {
        return PDT_ERR_ARG;
    }
    if (need_time) {
        if (eval_discretize(c, m, &d) != PDT_OK) {
            return PDT_ERR_ARG;
        }
        /* A zero weight leaves the time cost out of COMBINED: skip its O(n). */
        if (kind != PDT_COST_COMBINED || c->cfg.phi_t > PDT_R(0.0)) {
            ct = (tkind == PDT_COST_PREDICTION) ? prediction_cost(c, &d, unit_ratio(c))
                                                : simulation_cost(c, &d, unit_ratio(c));
        }
    }
    if (need_freq && (kind != PDT_COST_COMBINED || c->cfg.phi_f > PDT_R(0.0))) {
        cf = frequency_cost(c, m);
    }
    total = cost_total(c, ct, cf);
    *cost = cost_units(c, total);
    return PDT_OK;
}

/* Response of d, from rest, to the input deviations u - u0, into out[0..n-1]. */
static void simulate_dev(const pdt_cost_t *c, const pdt_discrete_t *d, pdt_real_t *out)
{
    const size_t l = d->delay;
    sim_state_t st = {PDT_R(0.0), PDT_R(0.0), PDT_R(0.0), PDT_R(0.0)};
    size_t k;

    if (l >= c->n) {
        /* No input reaches the record (and l + 1 could wrap around). */
        for (k = 0u; k < c->n; k++) {
            out[k] = PDT_R(0.0);
        }
        return;
    }
    for (k = 0u; k < c->n; k++) {
        out[k] = sim_step(d, &st, u_dev(c, k, l + 1u));
    }
}

/* The equation-error regressor: B(q) applied to the input deviations,
 * i.e. the prediction's input part, into out[0..n-1]. */
static void filter_input(const pdt_cost_t *c, const pdt_discrete_t *d, pdt_real_t *out)
{
    const size_t l = d->delay;
    size_t k;
    for (k = 0u; k < c->n; k++) {
        out[k] = d->b[0] * u_dev(c, k, l + 1u) + d->b[1] * u_dev(c, k, l + 2u) +
                 d->b[2] * u_dev(c, k, l + 3u);
    }
}

/* The data side of the time part at sample k: y(k) for the simulation,
 * A(q) y at k for the prediction (k >= order), normalised. */
static inline pdt_real_t data_side(const pdt_cost_t *c, const pdt_discrete_t *d, bool pred,
                                   size_t k)
{
    const pdt_real_t *y = c->y;
    if (!pred) {
        return y[k];
    }
    if (d->order == 1u) {
        return (y[k] - y[k - 1u]) + d->d[0] * y[k - 1u];
    }
    pdt_real_t dy1 = y[k - 1u] - y[k - 2u];
    return ((y[k] - y[k - 1u]) - dy1) + d->d[0] * dy1 + d->d[1] * y[k - 2u];
}

/* Blocked sum, as the residual accumulator: accurate float sums over long
 * records without a wider type. */
typedef struct bsum {
    pdt_real_t total, block;
    unsigned fill;
} bsum_t;

PDT_INLINE_TINY void bsum_add(bsum_t *s, pdt_real_t x)
{
    s->block += x;
    if (++s->fill == PDT_COST_BLOCK) {
        s->total += s->block;
        s->block = PDT_R(0.0);
        s->fill = 0u;
    }
}

static inline pdt_real_t bsum_get(const bsum_t *s)
{
    return s->total + s->block;
}

/* J(K) = a (K - kt)^2 + b (|K| - kf)^2 up to constants: the profiled
 * combined cost's dependence on the gain. */
static pdt_real_t gain_objective(pdt_real_t a, pdt_real_t kt, pdt_real_t b, pdt_real_t kf,
                                 pdt_real_t K)
{
    pdt_real_t et = K - kt;
    pdt_real_t ef = pdt_fabs(K) - kf;
    return a * et * et + b * ef * ef;
}

static pdt_real_t clamp_gain(pdt_real_t K, bool bounded, pdt_real_t lo, pdt_real_t hi)
{
    if (!bounded) {
        return K;
    }
    return K < lo ? lo : (K > hi ? hi : K);
}

/* The gain minimising J over the bounds. J is a convex quadratic on each
 * half-line, so its minimum is one of the two half-line minima, clamped,
 * or a bound. */
static pdt_real_t best_gain(pdt_real_t a, pdt_real_t kt, pdt_real_t b, pdt_real_t kf, bool bounded,
                            pdt_real_t lo, pdt_real_t hi)
{
    pdt_real_t cand[4];
    size_t nc = 0u;
    pdt_real_t w = a + b;
    if (w > PDT_R(0.0)) {
        pdt_real_t kp = (a * kt + b * kf) / w;
        pdt_real_t kn = (a * kt - b * kf) / w;
        cand[nc++] = clamp_gain(kp > PDT_R(0.0) ? kp : PDT_R(0.0), bounded, lo, hi);
        cand[nc++] = clamp_gain(kn < PDT_R(0.0) ? kn : PDT_R(0.0), bounded, lo, hi);
    } else {
        cand[nc++] = clamp_gain(PDT_R(0.0), bounded, lo, hi);
    }
    if (bounded) {
        cand[nc++] = lo;
        cand[nc++] = hi;
    }
    pdt_real_t best = cand[0];
    pdt_real_t jbest = gain_objective(a, kt, b, kf, best);
    for (size_t i = 1u; i < nc; i++) {
        pdt_real_t j = gain_objective(a, kt, b, kf, cand[i]);
        if (j < jbest) {
            jbest = j;
            best = cand[i];
        }
    }
    return best;
}

/* Gain bounds of the caller (multipliers of the shape in engineering
 * units) in normalised units, saturated. */
static pdt_real_t gain_to_norm(const pdt_cost_t *c, pdt_real_t g)
{
    pdt_real_t v = by_pow2(g, c->pow2[POW2_TO_NORM_GAIN], c->u_exp - c->y_exp);
    if (!pdt_finite(v)) {
        v = (v > PDT_R(0.0)) ? PDT_REAL_MAX : -PDT_REAL_MAX;
    }
    return v;
}

/* The sums that cancel in the residual sum of squares at the best gain
 * may exceed it by this factor before the rounding costs more than about
 * 2e-6 of it in float (1e-11 in double); beyond, the pass is run again
 * around the fit it found. */
#if PDT_REAL_DOUBLE
#define CANCEL_RATIO (PDT_R(1e-11) / PDT_REAL_EPS)
#define LOOSE_RATIO  (PDT_R(1e-8) / PDT_REAL_EPS)
#else
#define CANCEL_RATIO (PDT_R(2e-6) / PDT_REAL_EPS)
#define LOOSE_RATIO  (PDT_R(1e-3) / PDT_REAL_EPS)
#endif

/* The simulation's time part: one kernel pass around the reference fit
 * (K0, c0) and the regression summaries of it, normalised units. */
typedef struct sim_fit {
    pdt_real_t m;             /* scored samples */
    pdt_real_t K0, c0;        /* the reference fit */
    pdt_real_t sum_s;         /* sum s */
    pdt_real_t sum_e;         /* sum (y - K0 s - c0) */
    pdt_real_t vss, ves, vee; /* (centred with the offset) co-moments */
    pdt_real_t ss, ee, es;    /* the raw sums they come from */
} sim_fit_t;

/* The summaries of the kernel's sums q, taken around (K0, c0). */
static void sim_derive(const pdt_cost_t *c, const pdt_discrete_t *d, size_t k0, pdt_real_t K0,
                       pdt_real_t c0, const pdt_cost_sums_t *qs, sim_fit_t *f)
{
    const size_t o = d->order - 1u;
    const pdt_cost_sums_t q = *qs;
    pdt_real_t m = (pdt_real_t)(c->n - k0);
    f->m = m;
    f->K0 = K0;
    f->c0 = c0;
    f->sum_s = q.s;
    f->sum_e = (c->ysum[o] - K0 * q.s) - m * c0;
    f->vss = q.ss;
    f->ves = q.es;
    f->vee = q.ee;
    f->ss = q.ss;
    f->ee = q.ee;
    f->es = pdt_fabs(q.es);
    if (c->cfg.estimate_offset) {
        pdt_real_t sm = q.s / m;
        f->vss -= q.s * sm;
        f->ves -= f->sum_e * sm;
        f->vee -= f->sum_e * (f->sum_e / m);
    }
}

static void sim_pass(const pdt_cost_t *c, const pdt_discrete_t *d, size_t k0, pdt_real_t K0,
                     pdt_real_t c0, sim_fit_t *f)
{
    pdt_cost_sums_t q;
    pdt_cost_kernel(c->u, c->y, c->n, k0, d, K0, c0, &q);
    sim_derive(c, d, k0, K0, c0, &q, f);
}

/* The reference fit of a simulation pass in normalised units: the
 * caller's hint, or without one the data's own mean. Without an offset
 * fit the reference offset is 0. */
static void sim_reference(const pdt_cost_t *c, uint8_t order, const pdt_cost_hint_t *hint,
                          pdt_real_t *K0, pdt_real_t *c0)
{
    const size_t k0 = first_scored(c, order, false);
    if (hint != NULL && pdt_finite(hint->gain) && pdt_finite(hint->offset)) {
        *K0 = gain_to_norm(c, hint->gain);
        *c0 = pdt_ldexp(hint->offset, -c->y_exp);
    }
    if (hint == NULL || !pdt_finite(hint->gain) || !pdt_finite(hint->offset) ||
        (hint->gain == PDT_R(0.0) && hint->offset == PDT_R(0.0))) {
        /* No reference: the data's own mean, so that at least a record
         * far from its operating point does not cancel. */
        *K0 = PDT_R(0.0);
        *c0 = c->ysum[order - 1u] / (pdt_real_t)(c->n - k0);
    }
    if (!c->cfg.estimate_offset) {
        *c0 = PDT_R(0.0);
    }
}

/* Whether the residual sum of squares rss at gain K came from sums so
 * much larger that float rounding shows in it. Near the best cost so far
 * (ncost_ref, normalised, 0 if unknown) that is 2e-6 of it; a candidate
 * four times worse is allowed 1e-3: its rank among poor candidates is all
 * the search takes from it, and the second pass would double its price
 * whenever the reference fit does not suit its shape. */
static bool sim_cancels(const sim_fit_t *f, pdt_real_t K, pdt_real_t rss, pdt_real_t ncost_ref)
{
    pdt_real_t dk = pdt_fabs(K - f->K0);
    pdt_real_t big = f->ee + dk * (PDT_R(2.0) * f->es + dk * f->ss);
    bool poor = ncost_ref > PDT_R(0.0) && rss > PDT_R(4.0) * ncost_ref * f->m;
    return pdt_finite(rss) && !(big <= (poor ? LOOSE_RATIO : CANCEL_RATIO) * rss);
}

/* Whether rounding may have taken all of rss: the fit found is then no
 * better a reference than none. */
static bool sim_lost(const sim_fit_t *f, pdt_real_t K, pdt_real_t rss)
{
    pdt_real_t dk = pdt_fabs(K - f->K0);
    pdt_real_t big = f->ee + dk * (PDT_R(2.0) * f->es + dk * f->ss);
    return !(big * (PDT_R(64.0) * PDT_REAL_EPS) < rss);
}

/* Passes after the first, at most: one around the fit found normally
 * suffices; a caller's reference far off takes one more, and a fit whose
 * first refinement still cancels a third. */
#define SIM_PASSES 3u

/* Residual sum of squares of the fit with gain K (and the best offset),
 * from the pass's summaries. */
static pdt_real_t sim_rss(const sim_fit_t *f, pdt_real_t K)
{
    pdt_real_t dk = K - f->K0;
    pdt_real_t r = f->vee - dk * (PDT_R(2.0) * f->ves - dk * f->vss);
    if (r != r) {
        return (pdt_real_t)INFINITY; /* sums that overflowed */
    }
    return r > PDT_R(0.0) ? r : PDT_R(0.0);
}

/* Whether a pass's sums all came out finite. */
static bool sim_finite(const sim_fit_t *f)
{
    return pdt_finite(f->vee) && pdt_finite(f->ves) && pdt_finite(f->vss) && pdt_finite(f->sum_e) &&
           pdt_finite(f->sum_s);
}

static pdt_real_t sim_offset(const pdt_cost_t *c, const sim_fit_t *f, pdt_real_t K)
{
    if (!c->cfg.estimate_offset) {
        return PDT_R(0.0);
    }
    return f->c0 + (f->sum_e - (K - f->K0) * f->sum_s) / f->m;
}

/* The time part's summary a (K - kt)^2 of the pass. */
static void sim_summary(const sim_fit_t *f, pdt_real_t *at, pdt_real_t *kt)
{
    *at = PDT_R(0.0);
    *kt = PDT_R(0.0);
    if (f->vss > PDT_R(0.0) && pdt_finite(f->vss) && pdt_finite(f->ves)) {
        *kt = f->K0 + f->ves / f->vss;
        *at = f->vss / f->m;
    }
}

/* The frequency part's summary b (|K| - kf)^2, normalised units. */
static void freq_summary(const pdt_cost_t *c, const pdt_model_t *shape, pdt_real_t *af,
                         pdt_real_t *kf)
{
    bsum_t sgg = {PDT_R(0.0), PDT_R(0.0), 0u}, syg = {PDT_R(0.0), PDT_R(0.0), 0u};
    size_t k;
    for (k = c->k_first; k <= c->k_last; k++) {
        pdt_real_t g = pdt_model_magnitude_at(shape, (pdt_real_t)k * c->w_step) * c->umag[k - 1u];
        pdt_real_t wg = c->wgt[k - 1u] * g;
        bsum_add(&sgg, wg * g);
        bsum_add(&syg, wg * c->ymag[k - 1u]);
    }
    pdt_real_t vgg = bsum_get(&sgg);
    *af = PDT_R(0.0);
    *kf = PDT_R(0.0);
    if (vgg > PDT_R(0.0) && pdt_finite(vgg)) {
        *kf = bsum_get(&syg) / vgg;
        *af = vgg;
    }
}

static pdt_real_t freq_at(const pdt_cost_t *c, const pdt_model_t *shape, pdt_real_t gain)
{
    bsum_t s2 = {PDT_R(0.0), PDT_R(0.0), 0u};
    pdt_real_t gabs = pdt_fabs(gain);
    size_t k;
    for (k = c->k_first; k <= c->k_last; k++) {
        pdt_real_t g = pdt_model_magnitude_at(shape, (pdt_real_t)k * c->w_step) * c->umag[k - 1u];
        pdt_real_t e = c->ymag[k - 1u] - gabs * g;
        bsum_add(&s2, c->wgt[k - 1u] * e * e);
    }
    pdt_real_t v = bsum_get(&s2);
    return pdt_finite(v) ? v : (pdt_real_t)INFINITY;
}

/* The prediction's time part (three passes over the regressor B(q) u in
 * scratch): summary, then the cost and offset at the chosen gain. */
static void pred_summary(const pdt_cost_t *c, const pdt_discrete_t *d, pdt_real_t *scratch,
                         pdt_real_t *smean, pdt_real_t *emean, pdt_real_t *at, pdt_real_t *kt)
{
    const size_t k0 = first_scored(c, d->order, true);
    const size_t m = c->n - k0;
    size_t k;
    filter_input(c, d, scratch);
    *smean = PDT_R(0.0);
    *emean = PDT_R(0.0);
    if (c->cfg.estimate_offset) {
        bsum_t ss = {PDT_R(0.0), PDT_R(0.0), 0u}, se = {PDT_R(0.0), PDT_R(0.0), 0u};
        for (k = k0; k < c->n; k++) {
            bsum_add(&ss, scratch[k]);
            bsum_add(&se, data_side(c, d, true, k));
        }
        *smean = bsum_get(&ss) / (pdt_real_t)m;
        *emean = bsum_get(&se) / (pdt_real_t)m;
    }
    bsum_t sxx = {PDT_R(0.0), PDT_R(0.0), 0u}, sxy = {PDT_R(0.0), PDT_R(0.0), 0u};
    for (k = k0; k < c->n; k++) {
        pdt_real_t x = scratch[k] - *smean;
        bsum_add(&sxx, x * x);
        bsum_add(&sxy, x * (data_side(c, d, true, k) - *emean));
    }
    pdt_real_t vxx = bsum_get(&sxx);
    *at = PDT_R(0.0);
    *kt = PDT_R(0.0);
    if (vxx > PDT_R(0.0) && pdt_finite(vxx)) {
        *kt = bsum_get(&sxy) / vxx;
        *at = vxx / (pdt_real_t)m;
    }
}

/* The cost at the chosen gain, summed directly rather than from the
 * regression sums, which cancel when the fit is good. */
static pdt_real_t pred_at(const pdt_cost_t *c, const pdt_discrete_t *d, const pdt_real_t *scratch,
                          pdt_real_t gain, pdt_real_t off)
{
    const size_t k0 = first_scored(c, d->order, true);
    bsum_t s2 = {PDT_R(0.0), PDT_R(0.0), 0u};
    size_t k;
    for (k = k0; k < c->n; k++) {
        pdt_real_t e = data_side(c, d, true, k) - gain * scratch[k] - off;
        bsum_add(&s2, e * e);
    }
    return bsum_get(&s2) / (pdt_real_t)(c->n - k0);
}

/* The checks of a profile call and the shape's discrete model (none for
 * FREQUENCY). */
static pdt_status_t profile_check(const pdt_cost_t *c, const pdt_model_t *shape,
                                  pdt_real_t gain_min, pdt_real_t gain_max, pdt_discrete_t *d)
{
    const pdt_cost_kind_t kind = c->cfg.kind;
    if (shape == NULL || pdt_model_check(shape) != PDT_OK || !pdt_finite(gain_min) ||
        !pdt_finite(gain_max)) {
        return PDT_ERR_ARG;
    }
    if (gain_min > gain_max) {
        return PDT_ERR_BOUNDS;
    }
    if ((kind == PDT_COST_FREQUENCY || kind == PDT_COST_COMBINED) && c->nf == 0u) {
        return PDT_ERR_ARG;
    }
    /* The delay bounds hold for every criterion that has a time part, even
     * one weighted 0, as in pdt_cost_eval. */
    if (kind != PDT_COST_FREQUENCY && eval_discretize(c, shape, d) != PDT_OK) {
        return PDT_ERR_ARG;
    }
    return PDT_OK;
}

/* Whether the profile has a simulation time part, the kernel's work. */
static bool sim_time(const pdt_cost_t *c)
{
    const pdt_cost_kind_t kind = c->cfg.kind;
    if (kind == PDT_COST_COMBINED) {
        return c->cfg.phi_t > PDT_R(0.0) && c->cfg.time_kind == PDT_COST_SIMULATION;
    }
    return kind == PDT_COST_SIMULATION;
}

/* The profile with the extra columns (a SIMULATION cost, config_ok). */
static void extra_profile(const pdt_cost_t *c, const pdt_discrete_t *d, pdt_real_t gain_min,
                          pdt_real_t gain_max, pdt_real_t *scratch, pdt_cost_profile_t *out)
{
    const bool bounded = !(gain_min == PDT_R(0.0) && gain_max == PDT_R(0.0));
    pdt_cost_extra_t x;
    pdt_cost_extra_solve(c, d, bounded, gain_to_norm(c, gain_min), gain_to_norm(c, gain_max),
                         scratch, &x);
    pdt_cost_profile_t r = {PDT_R(0.0), PDT_R(0.0), PDT_R(0.0), PDT_R(0.0), PDT_R(0.0), PDT_R(0.0)};
    r.ncost = x.ncost;
    r.cost = cost_units(c, x.ncost);
    r.ct = r.cost;
    r.gain = by_pow2(x.gain, c->pow2[POW2_TO_GAIN], c->y_exp - c->u_exp);
    if (bounded) {
        r.gain = r.gain < gain_min ? gain_min : (r.gain > gain_max ? gain_max : r.gain);
    }
    r.offset = by_pow2(x.offset, c->pow2[POW2_TO_OUT], c->y_exp);
    *out = r;
}

/* A profile's regression of the gain, normalised units: the time part
 * at (K - kt)^2 and the frequency part af (|K| - kf)^2, each up to its
 * constant and weighted, and the gain's bounds. */
typedef struct prof_reg {
    pdt_real_t at;
    pdt_real_t kt;
    pdt_real_t af;
    pdt_real_t kf;
    pdt_real_t lo;
    pdt_real_t hi;
    bool bounded;
} prof_reg_t;

static pdt_real_t prof_gain(const prof_reg_t *g)
{
    return best_gain(g->at, g->kt, g->af, g->kf, g->bounded, g->lo, g->hi);
}

/* The simulation's first pass: from the caller's sums pre around (K0, c0)
 * when given, else the kernel's. */
static void prof_sim_first(const pdt_cost_t *c, const pdt_discrete_t *d, size_t k0, pdt_real_t K0,
                           pdt_real_t c0, const pdt_cost_sums_t *pre, sim_fit_t *f)
{
    if (pre != NULL) {
        sim_derive(c, d, k0, K0, c0, pre, f);
    } else {
        sim_pass(c, d, k0, K0, c0, f);
    }
    if (!sim_finite(f) && K0 != PDT_R(0.0)) {
        /* A reference far off this shape (its residual overflowed): once
         * more without one. */
        sim_reference(c, d->order, NULL, &K0, &c0);
        sim_pass(c, d, k0, K0, c0, f);
    }
}

/* The simulation's time part from the first pass f and the gain K it
 * gives: passes again while too much of the residual cancels, then the
 * cost ct and offset off. Returns the gain. */
static pdt_real_t prof_sim_fit(const pdt_cost_t *c, const pdt_discrete_t *d, size_t k0,
                               pdt_real_t ncost_ref, prof_reg_t *g, sim_fit_t *f, pdt_real_t K,
                               pdt_real_t *ct, pdt_real_t *off)
{
    const bool combined = (c->cfg.kind == PDT_COST_COMBINED);
    pdt_real_t rss = sim_rss(f, K);
    /* The time part's own share of the reference cost. */
    const pdt_real_t ref = combined ? ncost_ref / c->cfg.phi_t : ncost_ref;
    const bool hinted = (f->K0 != PDT_R(0.0));
    pdt_real_t K0 = PDT_R(0.0), c0 = PDT_R(0.0);
    for (unsigned pass = 0u; pass < SIM_PASSES && sim_cancels(f, K, rss, ref); pass++) {
        /* Too much of the reference fit's residual cancelled: again
         * around the fit just found, or, where a caller's reference
         * was so far off this shape that nothing was left, around the
         * data's mean first. */
        if (pass == 0u && hinted && sim_lost(f, K, rss)) {
            sim_reference(c, d->order, NULL, &K0, &c0);
        } else {
            K0 = K;
            c0 = sim_offset(c, f, K);
        }
        sim_pass(c, d, k0, K0, c0, f);
        sim_summary(f, &g->at, &g->kt);
        if (combined) {
            g->at *= c->cfg.phi_t;
        }
        K = prof_gain(g);
        rss = sim_rss(f, K);
    }
    *ct = rss / f->m;
    *off = sim_offset(c, f, K);
    return K;
}

/* The profile of a checked shape with discrete model d. pre: the kernel's
 * sums around the reference (K0, c0) when a caller already ran them, else
 * NULL. */
static void profile_run(const pdt_cost_t *c, const pdt_model_t *shape, const pdt_discrete_t *d,
                        pdt_real_t gain_min, pdt_real_t gain_max, pdt_real_t K0, pdt_real_t c0,
                        pdt_real_t ncost_ref, const pdt_cost_sums_t *pre, pdt_real_t *scratch,
                        pdt_cost_profile_t *out)
{
    const pdt_cost_kind_t kind = c->cfg.kind;
    const bool combined = (kind == PDT_COST_COMBINED);
    const bool bounded = !(gain_min == PDT_R(0.0) && gain_max == PDT_R(0.0));
    const bool need_freq = (kind == PDT_COST_FREQUENCY) || (combined && c->cfg.phi_f > PDT_R(0.0));
    const bool need_time = (kind != PDT_COST_FREQUENCY) && (!combined || c->cfg.phi_t > PDT_R(0.0));
    const bool pred = need_time && !sim_time(c);
    prof_reg_t g = {PDT_R(0.0),
                    PDT_R(0.0),
                    PDT_R(0.0),
                    PDT_R(0.0),
                    gain_to_norm(c, gain_min),
                    gain_to_norm(c, gain_max),
                    bounded};
    pdt_cost_profile_t r = {PDT_R(0.0), PDT_R(0.0), PDT_R(0.0), PDT_R(0.0), PDT_R(0.0), PDT_R(0.0)};
    pdt_real_t smean = PDT_R(0.0), emean = PDT_R(0.0), K, ct = PDT_R(0.0);
    pdt_real_t cf = PDT_R(0.0), off = PDT_R(0.0), total;
    sim_fit_t f;
    size_t k0 = 0u;

    if (need_time) {
        if (pred) {
            pred_summary(c, d, scratch, &smean, &emean, &g.at, &g.kt);
        } else {
            k0 = first_scored(c, d->order, false);
            prof_sim_first(c, d, k0, K0, c0, pre, &f);
            sim_summary(&f, &g.at, &g.kt);
        }
        if (combined) {
            g.at *= c->cfg.phi_t;
        }
    }
    if (need_freq) {
        freq_summary(c, shape, &g.af, &g.kf);
        if (combined) {
            g.af *= c->cfg.phi_f;
        }
    }
    K = prof_gain(&g);
    if (need_time && !pred) {
        K = prof_sim_fit(c, d, k0, ncost_ref, &g, &f, K, &ct, &off);
    } else if (need_time) {
        pdt_real_t o = emean - K * smean;
        /* In the equation error the offset enters through A(1). */
        pdt_real_t a1 = (d->order == 1u) ? d->d[0] : d->d[1];
        ct = pred_at(c, d, scratch, K, o);
        off = (a1 > PDT_REAL_EPS) ? o / a1 : PDT_R(0.0);
    }
    if (!pdt_finite(ct)) {
        ct = (pdt_real_t)INFINITY;
    }
    /* A shape whose response overflows leaves no fit: its cost is +inf,
     * and the gain and offset stay numbers (0 * inf in the offset's
     * closed form would be NaN). */
    if (!pdt_finite(K) || !pdt_finite(off)) {
        K = pdt_finite(K) ? K : PDT_R(0.0);
        off = PDT_R(0.0);
        ct = (pdt_real_t)INFINITY;
    }
    if (need_freq) {
        cf = freq_at(c, shape, K);
    }
    total = cost_total(c, ct, cf);
    r.ncost = total;
    r.cost = cost_units(c, total);
    r.ct = cost_units(c, ct);
    r.cf = cost_units(c, cf);
    r.gain = by_pow2(K, c->pow2[POW2_TO_GAIN], c->y_exp - c->u_exp);
    /* A bound near the end of the real range does not map exactly into the
     * normalised units (underflow, or clamped at the largest real): the
     * gain returned keeps the caller's bounds exactly. */
    if (bounded) {
        r.gain = r.gain < gain_min ? gain_min : (r.gain > gain_max ? gain_max : r.gain);
    }
    r.offset = by_pow2(off, c->pow2[POW2_TO_OUT], c->y_exp);
    *out = r;
}

/* The reference cost of a hint, 0 when there is none. */
static pdt_real_t hint_ncost(const pdt_cost_hint_t *hint)
{
    if (hint == NULL || !pdt_finite(hint->ncost) || !(hint->ncost > PDT_R(0.0))) {
        return PDT_R(0.0);
    }
    return hint->ncost;
}

pdt_status_t pdt_cost_profile_hint(const pdt_cost_t *c, const pdt_model_t *shape,
                                   pdt_real_t gain_min, pdt_real_t gain_max,
                                   const pdt_cost_hint_t *hint, pdt_real_t *scratch,
                                   pdt_cost_profile_t *out)
{
    pdt_discrete_t d;
    pdt_real_t K0 = PDT_R(0.0), c0 = PDT_R(0.0);
    pdt_status_t st;
    if (!prepared(c) || scratch == NULL || out == NULL) {
        return PDT_ERR_ARG;
    }
    st = profile_check(c, shape, gain_min, gain_max, &d);
    if (st != PDT_OK) {
        return st;
    }
    if (pdt_cost_extra_on(c)) {
        extra_profile(c, &d, gain_min, gain_max, scratch, out);
        return PDT_OK;
    }
    if (sim_time(c)) {
        sim_reference(c, d.order, hint, &K0, &c0);
    }
    profile_run(c, shape, &d, gain_min, gain_max, K0, c0, hint_ncost(hint), NULL, scratch, out);
    return PDT_OK;
}

pdt_status_t pdt_cost_profile_many(const pdt_cost_t *c, const pdt_model_t *shapes, size_t count,
                                   const pdt_real_t *gain_min, const pdt_real_t *gain_max,
                                   const pdt_cost_hint_t *hint, pdt_real_t *scratch,
                                   pdt_cost_profile_t *out)
{
    pdt_discrete_t d[PDT_COST_MANY];
    pdt_cost_sums_t q[PDT_COST_MANY];
    pdt_real_t K0 = PDT_R(0.0), c0 = PDT_R(0.0);
    bool shared = false;
    size_t i;
    if (!prepared(c) || shapes == NULL || gain_min == NULL || gain_max == NULL || scratch == NULL ||
        out == NULL || count == 0u || count > PDT_COST_MANY) {
        return PDT_ERR_ARG;
    }
    for (i = 0; i < count; i++) {
        pdt_status_t st = profile_check(c, &shapes[i], gain_min[i], gain_max[i], &d[i]);
        if (st != PDT_OK) {
            return st;
        }
    }
    if (sim_time(c) && !pdt_cost_extra_on(c)) {
        /* One pass for all when they share an order, hence a reference. */
        shared = true;
        for (i = 1; i < count; i++) {
            shared = shared && d[i].order == d[0].order;
        }
        if (shared) {
            sim_reference(c, d[0].order, hint, &K0, &c0);
            pdt_cost_kernel_many(c->u, c->y, c->n, first_scored(c, d[0].order, false), d, count, K0,
                                 c0, q);
        }
    }
    for (i = 0; i < count; i++) {
        pdt_real_t k0i = K0, c0i = c0;
        if (pdt_cost_extra_on(c)) {
            extra_profile(c, &d[i], gain_min[i], gain_max[i], scratch, &out[i]);
            continue;
        }
        if (sim_time(c) && !shared) {
            sim_reference(c, d[i].order, hint, &k0i, &c0i);
        }
        profile_run(c, &shapes[i], &d[i], gain_min[i], gain_max[i], k0i, c0i, hint_ncost(hint),
                    shared ? &q[i] : NULL, scratch, &out[i]);
    }
    return PDT_OK;
}

/* The shape's discrete model at a whole-sample dead time (the fraction
 * 0): its coefficients are those of every such dead time. The delay is
 * the least the cost takes, for the caller to set. */
static pdt_status_t shift_model(const pdt_cost_t *c, const pdt_model_t *shape, pdt_discrete_t *d)
{
    if (!prepared(c) || shape == NULL || c->cfg.kind != PDT_COST_SIMULATION ||
        pdt_cost_extra_on(c) ||
        pdt_discrete_init_int(shape, c->cfg.Ts, c->cfg.delay_min, d) != PDT_OK) {
        return PDT_ERR_ARG;
    }
    return check_dmodel(c, d);
}

pdt_status_t pdt_cost_response(const pdt_cost_t *c, const pdt_model_t *shape, pdt_real_t *r)
{
    pdt_discrete_t d;
    if (r == NULL || shift_model(c, shape, &d) != PDT_OK) {
        return PDT_ERR_ARG;
    }
    pdt_cost_kernel_response(c->u, c->n, &d, r);
    return PDT_OK;
}

pdt_status_t pdt_cost_profile_shift(const pdt_cost_t *c, const pdt_model_t *shape,
                                    const pdt_real_t *r, const size_t *delay, size_t count,
                                    pdt_real_t gain_min, pdt_real_t gain_max,
                                    const pdt_cost_hint_t *hint, pdt_cost_profile_t *out)
{
    pdt_discrete_t d;
    pdt_cost_sums_t q[PDT_COST_MANY];
    pdt_real_t K0 = PDT_R(0.0), c0 = PDT_R(0.0);
    if (r == NULL || delay == NULL || out == NULL || count == 0u || count > PDT_COST_MANY ||
        shift_model(c, shape, &d) != PDT_OK || !pdt_finite(gain_min) || !pdt_finite(gain_max)) {
        return PDT_ERR_ARG;
    }
    for (size_t i = 0; i < count; i++) {
        if (delay[i] < c->cfg.delay_min || delay[i] > c->cfg.delay_max) {
            return PDT_ERR_ARG;
        }
    }
    if (gain_min > gain_max) {
        return PDT_ERR_BOUNDS;
    }
    sim_reference(c, d.order, hint, &K0, &c0);
    pdt_cost_kernel_shift(r, c->y, c->n, first_scored(c, d.order, false), delay, count, K0, c0, q);
    for (size_t i = 0; i < count; i++) {
        d.delay = delay[i];
        profile_run(c, shape, &d, gain_min, gain_max, K0, c0, hint_ncost(hint), &q[i], NULL,
                    &out[i]);
    }
    return PDT_OK;
}

pdt_status_t pdt_cost_profile(const pdt_cost_t *c, const pdt_model_t *shape, pdt_real_t gain_min,
                              pdt_real_t gain_max, pdt_real_t *scratch, pdt_cost_profile_t *out)
{
    return pdt_cost_profile_hint(c, shape, gain_min, gain_max, NULL, scratch, out);
}

pdt_real_t pdt_cost_units(const pdt_cost_t *c, pdt_real_t ncost)
{
    return (c == NULL) ? ncost : cost_units(c, ncost);
}

pdt_status_t pdt_cost_fit(const pdt_cost_t *c, const pdt_model_t *m, pdt_real_t offset,
                          pdt_real_t *scratch, pdt_real_t *fit)
{
    pdt_discrete_t d;
    pdt_real_t mean, e2 = PDT_R(0.0), v2 = PDT_R(0.0), off, v;
    size_t k;
    if (!prepared(c) || m == NULL || scratch == NULL || fit == NULL ||
        pdt_model_check(m) != PDT_OK || !pdt_finite(offset) ||
        pdt_discrete_init(m, c->cfg.Ts, &d) != PDT_OK) {
        return PDT_ERR_ARG;
    }
    simulate_dev(c, &d, scratch);
    off = pdt_ldexp(offset, -c->y_exp);
    {
        bsum_t s = {PDT_R(0.0), PDT_R(0.0), 0u};
        for (k = 0u; k < c->n; k++) {
            bsum_add(&s, c->y[k]);
        }
        mean = bsum_get(&s) / (pdt_real_t)c->n;
    }
    {
        const int sh = c->u_exp - c->y_exp;
        const pdt_real_t ratio = c->pow2[POW2_TO_NORM_GAIN];
        bsum_t se = {PDT_R(0.0), PDT_R(0.0), 0u}, sv = {PDT_R(0.0), PDT_R(0.0), 0u};
        for (k = 0u; k < c->n; k++) {
            pdt_real_t e = c->y[k] - (by_pow2(scratch[k], ratio, sh) + off);
            pdt_real_t dv = c->y[k] - mean;
            bsum_add(&se, e * e);
            bsum_add(&sv, dv * dv);
        }
        e2 = bsum_get(&se);
        v2 = bsum_get(&sv);
    }
    v = PDT_R(0.0);
    if (v2 > PDT_R(0.0)) {
        v = PDT_R(100.0) * (PDT_R(1.0) - pdt_sqrt(e2 / v2));
        if (!pdt_finite(v)) {
            v = PDT_R(-1e30);
        }
    }
    *fit = v;
    return PDT_OK;
}

pdt_status_t pdt_cost_simulate(const pdt_cost_t *c, const pdt_discrete_t *d, pdt_real_t *ysim)
{
    size_t k;
    if (!prepared(c) || d == NULL || ysim == NULL || (d->order != 1u && d->order != 2u) ||
        !pdt_finite(d->b[0]) || !pdt_finite(d->b[1]) || !pdt_finite(d->b[2]) ||
        !pdt_finite(d->d[0]) || (d->order == 2u && !pdt_finite(d->d[1]))) {
        return PDT_ERR_ARG;
    }
    simulate_dev(c, d, ysim);
    const pdt_real_t s = pow2_of(c->u_exp);
    for (k = 0u; k < c->n; k++) {
        ysim[k] = by_pow2(ysim[k], s, c->u_exp) + c->cfg.y0;
    }
    return PDT_OK;
}

void pdt_cost_sim_sums(const pdt_cost_t *c, const pdt_discrete_t *d, pdt_real_t K0, pdt_real_t c0,
                       pdt_cost_sim_t *out)
{
    sim_fit_t f;
    sim_pass(c, d, first_scored(c, d->order, false), K0, c0, &f);
    out->m = f.m;
    out->sum_s = f.sum_s;
    out->sum_e = f.sum_e;
    out->vss = f.vss;
    out->ves = f.ves;
    out->vee = f.vee;
    out->ss = f.ss;
    out->es = f.es;
    out->ee = f.ee;
}
