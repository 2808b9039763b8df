/*
 * pdt_monitor: the loop-performance monitor. The tests and their
 * thresholds are explained in pdt_monitor.h and docs/monitor.md; here are
 * the mechanics. Every statistic is a sum with exponential forgetting,
 * S <- lambda S + x, of deviations from the first sample (so that a float
 * build does not lose the small variations of a large operating point).
 */
#include "pdt/pdt_monitor.h"

#include <string.h>

#include "pdt/pdt_tune.h"
#include "pdt_internal.h"
#include "pdt_model_priv.h"

#define MON_MAGIC PDT_MAGIC('P', 'D', 'M', 'O')

/* Forsman and Stattin's regularity: two half-periods of the same sign are
 * alike when their IAEs differ by less than a factor 1 / MON_ALPHA and
 * their durations by less than 1 / MON_GAMMA. */
#define MON_ALPHA  PDT_R(0.5)
#define MON_GAMMA  PDT_R(0.75)
/* The hysteresis band of the zero crossings, a fraction of std(e). */
#define MON_BAND   PDT_R(0.7)
/* The idle index's low-pass filter: the fraction of the gap closed per
 * sample. */
#define MON_LP     PDT_R(0.25)
/* The reference loop's output range when the config gives no limits. */
#define MON_WIDE   PDT_R(1e30)
/* Weighted half-periods are counted up to this (then only the weights
 * matter). */
#define MON_HP_CAP 4u

void pdt_monitor_config_default(pdt_monitor_config_t *cfg)
{
    if (cfg == NULL) {
        return;
    }
    cfg->Ts = PDT_R(0.1);
    cfg->decimation = 1u;
    cfg->horizon = 3000u;
    cfg->min_samples = 400u;
    cfg->has_model = false;
    const pdt_model_view_t unit = {1u, PDT_R(1.0), PDT_R(1.0), PDT_R(0.0), PDT_R(0.0), PDT_R(0.0)};
    pdt_model_from_view(PDT_MODEL_FOPDT, &unit, &cfg->model);
    cfg->u_min = PDT_R(0.0);
    cfg->u_max = PDT_R(0.0);
    cfg->sat_band = PDT_R(0.005);
    cfg->osc_acf = PDT_R(0.14);
    cfg->stiction_corr = PDT_R(0.35);
    cfg->stiction_corr_v = PDT_R(0.12);
    cfg->sluggish_ratio = PDT_R(2.0);
    cfg->idle_max = PDT_R(0.4);
    cfg->sat_share = PDT_R(0.1);
    cfg->mismatch_gain = PDT_R(0.25);
    cfg->mismatch_t = PDT_R(3.8);
}

static bool in_open01(pdt_real_t x)
{
    return pdt_finite(x) && x > PDT_R(0.0) && x <= PDT_R(1.0);
}

static bool config_ok(const pdt_monitor_config_t *c)
{
    bool ok =
        pdt_finite(c->Ts) && c->Ts > PDT_R(0.0) && c->decimation >= 1u && c->min_samples >= 16u;
    ok = ok && pdt_finite(c->u_min) && pdt_finite(c->u_max) && c->u_min <= c->u_max;
    ok = ok && pdt_finite(c->sat_band) && c->sat_band >= PDT_R(0.0) && c->sat_band < PDT_R(0.5);
    ok = ok && in_open01(c->osc_acf);
    ok = ok && pdt_finite(c->stiction_corr) && c->stiction_corr >= PDT_R(0.0) &&
         c->stiction_corr <= PDT_R(1.0) && pdt_finite(c->stiction_corr_v) &&
         c->stiction_corr_v >= PDT_R(0.0) && c->stiction_corr_v <= PDT_R(1.0);
    ok = ok && pdt_finite(c->sluggish_ratio) && c->sluggish_ratio > PDT_R(1.0) &&
         in_open01(c->idle_max) && in_open01(c->sat_share);
    ok = ok && pdt_finite(c->mismatch_gain) && c->mismatch_gain > PDT_R(0.0) &&
         pdt_finite(c->mismatch_t) && c->mismatch_t > PDT_R(0.0);
    return ok;
}

/* The reference loop: SIMC PI gains on the model (tau_c = its dead time,
 * or one sample when it has none), the PI at the monitor's sample period
 * and the output limits. */
static pdt_status_t reference_make(const pdt_monitor_config_t *c, pdt_real_t Ts, pdt_pid_t *pid)
{
    pdt_tune_config_t tc;
    pdt_tune_result_t tr;
    pdt_tune_config_default(&tc);
    tc.ms_max = PDT_R(0.0);
    pdt_status_t st = pdt_tune_compute(&c->model, PDT_R(100.0), &tc, &tr);
    if (st == PDT_ERR_ARG) {
        tc.tau_c = Ts;
        st = pdt_tune_compute(&c->model, PDT_R(100.0), &tc, &tr);
    }
    if (st == PDT_OK) {
        pdt_pid_config_t pc;
        pdt_pid_config_default(&pc);
        pc.Ts = Ts;
        pc.u_min = -MON_WIDE;
        pc.u_max = MON_WIDE;
        if (c->u_min < c->u_max) {
            pc.u_min = c->u_min;
            pc.u_max = c->u_max;
        }
        st = pdt_pid_init_from_gains(pid, &pc, &tr.ideal, PDT_PID_IDEAL, PDT_R(0.0));
        if (st != PDT_OK) {
            st = PDT_ERR_UNSTABLE;
        }
    }
    return st;
}

pdt_status_t pdt_monitor_init(pdt_monitor_t *mon, const pdt_monitor_config_t *cfg)
{
    if (mon == NULL || cfg == NULL || !config_ok(cfg)) {
        return PDT_ERR_ARG;
    }
    const pdt_real_t Ts = cfg->Ts * (pdt_real_t)cfg->decimation;
    pdt_discrete_t dm = {0u,
                         1u,
                         {PDT_R(0.0), PDT_R(0.0)},
                         {PDT_R(0.0), PDT_R(0.0), PDT_R(0.0)},
                         {PDT_R(0.0), PDT_R(0.0)}};
    pdt_pid_t ref;
    pdt_status_t st = PDT_OK;
    if (cfg->has_model) {
        st = pdt_model_check(&cfg->model);
        if (st == PDT_OK) {
            st = pdt_discrete_init(&cfg->model, Ts, &dm);
        }
        if (st == PDT_OK && dm.delay + 1u >= (size_t)PDT_MONITOR_ORDER) {
            st = PDT_ERR_LENGTH;
        }
        if (st == PDT_OK) {
            st = reference_make(cfg, Ts, &ref);
        }
        if (st != PDT_OK) {
            return st;
        }
    }
    (void)memset(mon, 0, sizeof *mon);
    mon->cfg = *cfg;
    mon->lambda = PDT_R(1.0);
    mon->lambda_s = PDT_R(1.0);
    mon->lambda_c = PDT_R(1.0);
    if (cfg->horizon > 0u) {
        mon->lambda = pdt_exp(PDT_R(-1.0) / (pdt_real_t)cfg->horizon);
        mon->lambda_c = pdt_exp(-(pdt_real_t)PDT_MONITOR_COARSE / (pdt_real_t)cfg->horizon);
        mon->lambda_s =
            pdt_exp(PDT_R(-1.0) / ((pdt_real_t)cfg->horizon * (pdt_real_t)cfg->decimation));
    }
    if (cfg->has_model) {
        mon->dm = dm;
        mon->delay = (uint32_t)dm.delay + 1u;
        mon->ref = ref;
    }
    mon->magic = MON_MAGIC;
    return PDT_OK;
}

/* The oscillation detector, one sample of the centred error ec. */
static void oscillation_step(pdt_monitor_t *m, pdt_real_t ec, pdt_real_t band)
{
    const pdt_real_t l = m->lambda;
    m->n_reg *= l;
    m->n_hp *= l;
    m->s_len *= l;
    m->s_amp *= l;
    if (m->sign == 0) {
        if (ec > band) {
            m->sign = 1;
        } else if (ec < -band) {
            m->sign = -1;
        } else {
            /* still inside the band */
        }
        return;
    }
    const bool crossed = (m->sign > 0 && ec < -band) || (m->sign < 0 && ec > band);
    if (crossed && m->hp_len > 0u) {
        /* The first half-period started mid-way: it is not counted. */
        if (m->hp_seen >= 1u) {
            m->n_hp += PDT_R(1.0);
            m->s_len += PDT_R(2.0) * (pdt_real_t)m->hp_len;
            m->s_amp += PDT_PI * m->hp_iae / (PDT_R(2.0) * (pdt_real_t)m->hp_len);
        }
        if (m->hp_seen >= 3u) {
            /* Compared with the last one of the same sign. */
            const pdt_real_t ra = m->hp_iae / m->prev_iae[1];
            const pdt_real_t rl = (pdt_real_t)m->hp_len / (pdt_real_t)m->prev_len[1];
            if (ra > MON_ALPHA && ra < PDT_R(1.0) / MON_ALPHA && rl > MON_GAMMA &&
                rl < PDT_R(1.0) / MON_GAMMA) {
                m->n_reg += PDT_R(1.0);
            }
        }
        m->prev_iae[1] = m->prev_iae[0];
        m->prev_len[1] = m->prev_len[0];
        m->prev_iae[0] = m->hp_iae;
        m->prev_len[0] = m->hp_len;
        if (m->hp_seen < MON_HP_CAP) {
            m->hp_seen++;
        }
        m->hp_iae = PDT_R(0.0);
        m->hp_len = 0u;
        m->sign = -m->sign;
    }
    m->hp_iae += pdt_fabs(ec);
    m->hp_len++;
}

/* Values x(k-1-l), x(k-2-l), x(k-3-l) of a ring whose newest entry (at
 * `at`) is sample k-1, oldest first, as pdt_discrete_step reads them. */
static void ring_window(const pdt_real_t *ring, uint32_t at, size_t l, pdt_real_t w[3])
{
    for (uint32_t i = 0u; i < 3u; i++) {
        const uint32_t back = (uint32_t)l + i;
        w[2u - i] = ring[(at + PDT_MONITOR_RING - back) % PDT_MONITOR_RING];
    }
}

/* The model part of a sample: its output from u, the reference loop, the
 * mismatch regression. e is the error of this sample. */
static void model_step(pdt_monitor_t *m, pdt_real_t sp, pdt_real_t pv, pdt_real_t u, pdt_real_t e)
{
    const pdt_real_t l = m->lambda;
    const size_t k3 = m->dm.delay + 3u;
    pdt_real_t w[3];
    ring_window(m->u_ring, m->r_at, m->dm.delay, w);
    const pdt_real_t ym = pdt_discrete_step(&m->dm, &m->ym, w, PDT_R(0.0), k3);
    ring_window(m->du_ring, m->r_at, m->dm.delay, w);
    const pdt_real_t yref = pv + pdt_discrete_step(&m->dm, &m->yd, w, PDT_R(0.0), k3);
    pdt_real_t uref = u;
    if (m->n == 1u) {
        (void)pdt_pid_track(&m->ref, sp, yref, u);
    } else if (pdt_pid_update(&m->ref, sp, yref, &uref) != PDT_OK) {
        uref = u;
    } else {
        /* the reference output is finite */
    }
    m->r_at = (m->r_at + 1u) % PDT_MONITOR_RING;
    m->u_ring[m->r_at] = u - m->u0;
    m->du_ring[m->r_at] = uref - u;
    m->s_iae = l * m->s_iae + pdt_fabs(e);
    m->s_iae_ref = l * m->s_iae_ref + pdt_fabs(sp - yref);
    const pdt_real_t z = sp - m->sp0;
    const pdt_real_t v = (pv - m->pv0) - ym;
    m->sz = l * m->sz + z;
    m->szz = l * m->szz + z * z;
    m->sv = l * m->sv + v;
    m->svv = l * m->svv + v * v;
    m->szv = l * m->szv + z * v;
    m->sve = l * m->sve + v * e;
    /* The slot of this sample still holds sample k - ORDER. */
    const uint32_t at = m->el.at;
    m->szzL = l * m->szzL;
    m->svvL = l * m->svvL;
    m->szvL = l * m->szvL;
    m->svzL = l * m->svzL;
    if (m->n > PDT_MONITOR_ORDER) {
        m->szzL += z * m->z_ring[at];
        m->svvL += v * m->v_ring[at];
        m->szvL += z * m->v_ring[at];
        m->svzL += v * m->z_ring[at];
    }
    m->z_ring[at] = z;
    m->v_ring[at] = v;
}

/* The idle index's signs: u and pv low-passed, the signs of their
 * changes compared. */
static void idle_step(pdt_monitor_t *m, pdt_real_t du, pdt_real_t dpv)
{
    const pdt_real_t l = m->lambda;
    const pdt_real_t u_new = m->lp_u + MON_LP * (du - m->lp_u);
    const pdt_real_t pv_new = m->lp_pv + MON_LP * (dpv - m->lp_pv);
    const pdt_real_t prod = (u_new - m->lp_u) * (pv_new - m->lp_pv);
    m->t_pos *= l;
    m->t_neg *= l;
    if (prod > PDT_R(0.0)) {
        m->t_pos += PDT_R(1.0);
    } else if (prod < PDT_R(0.0)) {
        m->t_neg += PDT_R(1.0);
    } else {
        /* no change: counted in neither */
    }
    m->lp_u = u_new;
    m->lp_pv = pv_new;
}

/* x into the lagged products with forgetting l. The ring holds the last
 * PDT_MONITOR_ORDER values: x(k - ORDER) is the entry this one replaces. */
static void lags_push(pdt_monitor_lags_t *g, pdt_real_t x, pdt_real_t l)
{
    if (g->n < UINT32_MAX) {
        g->n++;
    }
    g->w = l * g->w + PDT_R(1.0);
    g->s = l * g->s + x;
    const uint32_t next = (g->at + 1u) % PDT_MONITOR_ORDER;
    const pdt_real_t oldest = g->ring[next];
    g->ring[next] = x;
    g->at = next;
    for (uint32_t j = 0u; j <= PDT_MONITOR_ORDER; j++) {
        g->ss[j] *= l;
        if (j < g->n) {
            const pdt_real_t old =
                (j == PDT_MONITOR_ORDER)
                    ? oldest
                    : g->ring[(g->at + PDT_MONITOR_ORDER - j) % PDT_MONITOR_ORDER];
            g->ss[j] += x * old;
        }
    }
}

/* One sample (block averages). */
static void sample(pdt_monitor_t *m, pdt_real_t sp, pdt_real_t pv, pdt_real_t u)
{
    const pdt_real_t l = m->lambda;
    if (m->n == 0u) {
        m->sp0 = sp;
        m->pv0 = pv;
        m->u0 = u;
    }
    if (m->n < UINT32_MAX) {
        m->n++;
    }
    m->w = l * m->w + PDT_R(1.0);
    m->w2 = l * l * m->w2 + PDT_R(1.0);
    const pdt_real_t e = sp - pv;
    lags_push(&m->el, e, l);
    m->ec_sum += e;
    m->ec_cnt++;
    if (m->ec_cnt == PDT_MONITOR_COARSE) {
        lags_push(&m->ec, m->ec_sum / (pdt_real_t)PDT_MONITOR_COARSE, m->lambda_c);
        m->ec_sum = PDT_R(0.0);
        m->ec_cnt = 0u;
    }
    const pdt_real_t du = u - m->u0;
    m->su = l * m->su + du;
    m->suu = l * m->suu + du * du;
    m->sue = l * m->sue + du * e;
    const pdt_real_t mean = m->el.s / m->el.w;
    const pdt_real_t var = m->el.ss[0] / m->el.w - mean * mean;
    const pdt_real_t band = var > PDT_R(0.0) ? MON_BAND * pdt_sqrt(var) : PDT_R(0.0);
    oscillation_step(m, e - mean, band);
    m->sp_moves *= l;
    if (m->n > 1u &&
        pdt_fabs(sp - m->sp_last) > PDT_R(0.5) * pdt_sqrt(var > PDT_R(0.0) ? var : PDT_R(0.0))) {
        m->sp_moves += PDT_R(1.0);
    }
    m->sp_last = sp;
    if (m->n == 1u) {
        m->lp_u = du;
        m->lp_pv = pv - m->pv0;
    }
    idle_step(m, du, pv - m->pv0);
    if (m->cfg.has_model) {
        model_step(m, sp, pv, u, e);
    }
}

pdt_status_t pdt_monitor_scan(pdt_monitor_t *mon, pdt_real_t sp, pdt_real_t pv, pdt_real_t u)
{
    if (mon == NULL) {
        return PDT_ERR_ARG;
    }
    if (mon->magic != MON_MAGIC) {
        return PDT_ERR_STATE;
    }
    if (!pdt_finite(sp) || !pdt_finite(pv) || !pdt_finite(u)) {
        return PDT_ERR_NONFINITE;
    }
    const pdt_monitor_config_t *c = &mon->cfg;
    if (c->u_min < c->u_max) {
        const pdt_real_t tol = c->sat_band * (c->u_max - c->u_min);
        mon->sat_w = mon->lambda_s * mon->sat_w + PDT_R(1.0);
        mon->sat_hits *= mon->lambda_s;
        if (u <= c->u_min + tol || u >= c->u_max - tol) {
            mon->sat_hits += PDT_R(1.0);
        }
    }
    mon->blk[0] += sp;
    mon->blk[1] += pv;
    mon->blk[2] += u;
    mon->scans++;
    if (mon->scans >= c->decimation) {
        const pdt_real_t inv = PDT_R(1.0) / (pdt_real_t)mon->scans;
        sample(mon, mon->blk[0] * inv, mon->blk[1] * inv, mon->blk[2] * inv);
        mon->blk[0] = PDT_R(0.0);
        mon->blk[1] = PDT_R(0.0);
        mon->blk[2] = PDT_R(0.0);
        mon->scans = 0u;
    }
    return PDT_OK;
}

pdt_status_t pdt_monitor_scan_block(pdt_monitor_t *mon, const pdt_real_t *sp, const pdt_real_t *pv,
                                    const pdt_real_t *u, size_t n, size_t *done)
{
    if (mon == NULL || ((sp == NULL || pv == NULL || u == NULL) && n > 0u)) {
        return PDT_ERR_ARG;
    }
    pdt_status_t st = PDT_OK;
    size_t k = 0u;
    while (k < n && st == PDT_OK) {
        st = pdt_monitor_scan(mon, sp[k], pv[k], u[k]);
        if (st == PDT_OK) {
            k++;
        }
    }
    if (done != NULL && (st == PDT_OK || st == PDT_ERR_NONFINITE)) {
        *done = k;
    }
    return st;
}

/* An autoregressive model of order <= PDT_MONITOR_ORDER of the error from
 * its autocovariances c[0..ORDER], by Levinson-Durbin (stopping at an
 * order whose reflection is not below 1): e(k) = sum a[j] e(k - j) +
 * innovation. Returns the order reached, the innovation variance in *err. */
static uint32_t ar_fit(const pdt_real_t *c, pdt_real_t *a, pdt_real_t *err)
{
    pdt_real_t t[PDT_MONITOR_ORDER + 1u];
    uint32_t p = 0u;
    *err = c[0];
    for (uint32_t i = 0u; i <= PDT_MONITOR_ORDER; i++) {
        a[i] = PDT_R(0.0);
    }
    for (uint32_t i = 1u; i <= PDT_MONITOR_ORDER; i++) {
        pdt_real_t acc = c[i];
        for (uint32_t j = 1u; j < i; j++) {
            acc -= a[j] * c[i - j];
        }
        const pdt_real_t k = acc / *err;
        if (!(pdt_fabs(k) < PDT_R(1.0))) {
            break;
        }
        for (uint32_t j = 1u; j < i; j++) {
            t[j] = a[j] - k * a[i - j];
        }
        for (uint32_t j = 1u; j < i; j++) {
            a[j] = t[j];
        }
        a[i] = k;
        *err *= PDT_R(1.0) - k * k;
        p = i;
    }
    return p;
}

/* The Harris index: the variance of the model's first d impulse-response
 * terms (what no controller can remove) over the variance c0. */
static pdt_real_t harris_index(const pdt_real_t *a, uint32_t p, pdt_real_t err, pdt_real_t c0,
                               uint32_t d)
{
    pdt_real_t psi[PDT_MONITOR_ORDER];
    pdt_real_t sum = PDT_R(0.0);
    for (uint32_t i = 0u; i < d; i++) {
        pdt_real_t x = (i == 0u) ? PDT_R(1.0) : PDT_R(0.0);
        for (uint32_t j = 1u; j <= i && j <= p; j++) {
            x += a[j] * psi[i - j];
        }
        psi[i] = x;
        sum += x * x;
    }
    const pdt_real_t h = err * sum / c0;
    return h < PDT_R(1.0) ? h : PDT_R(1.0);
}

/* The autocorrelation of the error, c[j] / c[0] for j <= ORDER and the AR
 * model's continuation beyond, scanned for its first three zero crossings
 * (up to PDT_MONITOR_ACF_LAGS): the extreme between the first two (m1 < 0)
 * and between the second and third (m2 > 0), and the period (the lags
 * between the first and third crossing, interpolated). */
typedef struct acf_figures {
    pdt_real_t min, max, period, index; /* period in lags, 0: none */
} acf_figures_t;

static void acf_scan(const pdt_real_t *c, const pdt_real_t *a, uint32_t p, acf_figures_t *r)
{
    pdt_real_t ring[PDT_MONITOR_ORDER + 1u]; /* rho(j - ORDER .. j - 1) */
    pdt_real_t z[3] = {PDT_R(0.0), PDT_R(0.0), PDT_R(0.0)};
    pdt_real_t ext[2] = {PDT_R(0.0), PDT_R(0.0)};
    uint32_t nz = 0u;
    pdt_real_t prev = PDT_R(1.0);
    for (uint32_t j = 0u; j <= PDT_MONITOR_ORDER; j++) {
        ring[j] = c[j] / c[0];
    }
    for (uint32_t j = 1u; j < PDT_MONITOR_ACF_LAGS && nz < 3u; j++) {
        pdt_real_t x;
        if (j <= PDT_MONITOR_ORDER) {
            x = ring[j];
        } else {
            /* rho(j) = sum a[i] rho(j - i), ring shifted by one */
            x = PDT_R(0.0);
            for (uint32_t i = 1u; i <= p; i++) {
                x += a[i] * ring[PDT_MONITOR_ORDER + 1u - i];
            }
            for (uint32_t i = 0u; i < PDT_MONITOR_ORDER; i++) {
                ring[i] = ring[i + 1u];
            }
            ring[PDT_MONITOR_ORDER] = x;
        }
        if ((prev > PDT_R(0.0)) != (x > PDT_R(0.0))) {
            z[nz] = (pdt_real_t)j - PDT_R(1.0) + prev / (prev - x);
            nz++;
        }
        if (nz == 1u && x < ext[0]) {
            ext[0] = x;
        }
        if (nz == 2u && x > ext[1]) {
            ext[1] = x;
        }
        prev = x;
    }
    r->min = ext[0];
    r->max = ext[1];
    r->period = (nz == 3u) ? (z[2] - z[0]) : PDT_R(0.0);
    r->index =
        (ext[0] < PDT_R(0.0) && ext[1] > PDT_R(0.0)) ? pdt_sqrt(-ext[0] * ext[1]) : PDT_R(0.0);
}

/* The mismatch regression's figures into r (has_mismatch, gain_ratio,
 * mismatch_t). */
static void mismatch(const pdt_monitor_t *m, pdt_monitor_result_t *r)
{
    const pdt_real_t w = m->w;
    const pdt_real_t mz = m->sz / w;
    const pdt_real_t mv = m->sv / w;
    const pdt_real_t vz = m->szz / w - mz * mz;
    const pdt_real_t vv = m->svv / w - mv * mv;
    const pdt_real_t cv = m->szv / w - mz * mv;
    const pdt_real_t me = m->el.s / w;
    const pdt_real_t ve = m->el.ss[0] / w - me * me;
    if (vv > PDT_R(0.0) && ve > PDT_R(0.0)) {
        r->has_corr_ve = true;
        r->corr_ve = (m->sve / w - mv * me) / pdt_sqrt(vv * ve);
    }
    if (!(vz > PDT_R(1e-6) * (mz * mz + m->sp0 * m->sp0)) || !(vz > PDT_R(0.0)) ||
        !(vv > PDT_R(0.0))) {
        return;
    }
    const pdt_real_t beta = cv / vz;
    const pdt_real_t vr = vv - beta * cv;
    /* The residual r = v - beta z's autocorrelation at lag L = ORDER gives
     * the per-sample correlation rho = rho_L^(1/L) of an AR(1) with the
     * same memory (a lag-1 estimate would see only the measurement noise
     * and take slow disturbances for independent samples). */
    const pdt_real_t cL = (m->svvL / w - mv * mv) -
                          beta * ((m->szvL + m->svzL) / w - PDT_R(2.0) * mz * mv) +
                          beta * beta * (m->szzL / w - mz * mz);
    const pdt_real_t rL = vr > PDT_R(0.0) ? cL / vr : PDT_R(0.0);
    pdt_real_t rho = PDT_R(0.0);
    if (rL > PDT_R(0.0)) {
        rho = rL < PDT_R(1.0) ? pdt_exp(pdt_log(rL) / (pdt_real_t)PDT_MONITOR_ORDER) : PDT_R(1.0);
    }
    rho = rho < PDT_R(0.9999) ? rho : PDT_R(0.9999);
    const pdt_real_t neff = (w * w / m->w2) * (PDT_R(1.0) - rho) / (PDT_R(1.0) + rho);
    const pdt_real_t se2 = (vr > PDT_R(0.0) ? vr : PDT_R(0.0)) / (neff * vz);
    r->has_mismatch = true;
    r->mismatch_t = se2 > PDT_R(0.0) ? pdt_fabs(beta) / pdt_sqrt(se2) : PDT_REAL_MAX;
    /* v follows (1 - K_model / K_process) of the set-point's moves. */
    r->gain_ratio = beta < PDT_R(0.9) ? PDT_R(1.0) / (PDT_R(1.0) - beta) : PDT_R(10.0);
}

/* The autocovariances c[0..ORDER] of g's signal; false when its variance
 * is not positive. */
static bool autocov(const pdt_monitor_lags_t *g, pdt_real_t *c)
{
    const pdt_real_t mean = g->s / g->w;
    for (uint32_t j = 0u; j <= PDT_MONITOR_ORDER; j++) {
        c[j] = g->ss[j] / g->w - mean * mean;
    }
    return c[0] > PDT_R(0.0);
}

/* The figures of the statistics (all but the verdict). */
static void figures(const pdt_monitor_t *m, pdt_monitor_result_t *r)
{
    const pdt_real_t w = m->w;
    const pdt_real_t mean = m->el.s / w;
    pdt_real_t c[PDT_MONITOR_ORDER + 1u];
    pdt_real_t a[PDT_MONITOR_ORDER + 1u];
    pdt_real_t err = PDT_R(0.0);
    acf_figures_t f = {PDT_R(0.0), PDT_R(0.0), PDT_R(0.0), PDT_R(0.0)};
    const bool moves = autocov(&m->el, c);
    const pdt_real_t c0 = c[0];
    const pdt_real_t Ts = m->cfg.Ts * (pdt_real_t)m->cfg.decimation;
    r->std_e = moves ? pdt_sqrt(c0) : PDT_R(0.0);
    r->half_periods = m->n_hp;
    if (m->n_hp > PDT_R(0.0)) {
        r->regularity = m->n_reg / m->n_hp;
        r->period = Ts * m->s_len / m->n_hp;
        r->amplitude = m->s_amp / m->n_hp;
    }
    if (moves) {
        const uint32_t p = ar_fit(c, a, &err);
        acf_scan(c, a, p, &f);
        r->acf_scale = 1u;
        if (m->cfg.has_model) {
            r->has_harris = true;
            r->harris = harris_index(a, p, err, c0, m->delay);
        }
    }
    /* The coarse error, once it has twice its lags (c and a reused). */
    if (m->ec.n > 2u * PDT_MONITOR_ORDER && autocov(&m->ec, c)) {
        acf_figures_t fc;
        acf_scan(c, a, ar_fit(c, a, &err), &fc);
        if (fc.index > f.index) {
            f = fc;
            f.period *= (pdt_real_t)PDT_MONITOR_COARSE;
            r->acf_scale = PDT_MONITOR_COARSE;
        }
    }
    r->oscillation = f.index;
    r->acf_min = f.min;
    r->acf_max = f.max;
    r->acf_period = f.period;
    /* An oscillation at least as slow as the set-point's steps may be
     * their echo (alternate steps make the error alternate). */
    r->sp_moves = m->sp_moves;
    r->forced =
        r->acf_period > PDT_R(0.0) && m->sp_moves > PDT_R(0.0) && r->acf_period * m->sp_moves >= w;
    r->acf_period *= Ts;
    const pdt_real_t mu = m->su / w;
    const pdt_real_t vu = m->suu / w - mu * mu;
    if (vu > PDT_R(0.0) && moves) {
        r->corr_ue = (m->sue / w - mu * mean) / pdt_sqrt(vu * c0);
    }
    if (m->t_pos + m->t_neg > PDT_R(0.0)) {
        r->idle_index = (m->t_pos - m->t_neg) / (m->t_pos + m->t_neg);
    }
    const pdt_monitor_config_t *cf = &m->cfg;
    if (cf->u_min < cf->u_max && m->sat_w > PDT_R(0.0)) {
        r->has_saturation = true;
        r->saturation = m->sat_hits / m->sat_w;
    }
    if (cf->has_model) {
        r->delay_samples = m->delay;
        if (m->s_iae_ref > PDT_R(0.0)) {
            r->has_sluggish = true;
            r->iae_ratio = m->s_iae / m->s_iae_ref;
        }
        mismatch(m, r);
    }
}

static pdt_monitor_verdict_t verdict(const pdt_monitor_t *m, const pdt_monitor_result_t *r,
                                     pdt_monitor_cause_t *cause)
{
    const pdt_monitor_config_t *c = &m->cfg;
    const pdt_real_t g = PDT_R(1.0) + c->mismatch_gain;
    *cause = PDT_MONITOR_CAUSE_NONE;
    if (m->n < c->min_samples) {
        return PDT_MONITOR_NOT_ENOUGH_DATA;
    }
    if (r->has_mismatch && r->mismatch_t > c->mismatch_t &&
        (r->gain_ratio > g || r->gain_ratio * g < PDT_R(1.0))) {
        return PDT_MONITOR_MODEL_CHANGED;
    }
    if (r->has_saturation && r->saturation > c->sat_share) {
        return PDT_MONITOR_SATURATED;
    }
    if (r->oscillation >= c->osc_acf && !r->forced) {
        const bool sticky = r->has_corr_ve ? (r->corr_ve < -c->stiction_corr_v)
                                           : (pdt_fabs(r->corr_ue) < c->stiction_corr);
        *cause = sticky ? PDT_MONITOR_CAUSE_STICTION : PDT_MONITOR_CAUSE_TUNING;
        return PDT_MONITOR_OSCILLATING;
    }
    const bool slow =
        r->has_sluggish ? (r->iae_ratio > c->sluggish_ratio) : (r->idle_index > c->idle_max);
    return slow ? PDT_MONITOR_SLUGGISH : PDT_MONITOR_OK;
}

pdt_status_t pdt_monitor_result(const pdt_monitor_t *mon, pdt_monitor_result_t *out)
{
    if (mon == NULL || out == NULL) {
        return PDT_ERR_ARG;
    }
    if (mon->magic != MON_MAGIC) {
        return PDT_ERR_STATE;
    }
    pdt_monitor_result_t r;
    (void)memset(&r, 0, sizeof r);
    r.samples = mon->n;
    r.weight = mon->w;
    if (mon->n > 0u) {
        figures(mon, &r);
    }
    r.verdict = verdict(mon, &r, &r.cause);
    *out = r;
    return PDT_OK;
}

const char *pdt_monitor_verdict_str(pdt_monitor_verdict_t v)
{
    switch (v) {
    case PDT_MONITOR_NOT_ENOUGH_DATA:
        return "not_enough_data";
    case PDT_MONITOR_OK:
        return "ok";
    case PDT_MONITOR_OSCILLATING:
        return "oscillating";
    case PDT_MONITOR_SLUGGISH:
        return "sluggish";
    case PDT_MONITOR_MODEL_CHANGED:
        return "model_changed";
    case PDT_MONITOR_SATURATED:
        return "saturated";
    default:
        return "?";
    }
}

const char *pdt_monitor_cause_str(pdt_monitor_cause_t c)
{
    switch (c) {
    case PDT_MONITOR_CAUSE_NONE:
        return "none";
    case PDT_MONITOR_CAUSE_TUNING:
        return "tuning";
    case PDT_MONITOR_CAUSE_STICTION:
        return "stiction";
    default:
        return "?";
    }
}
