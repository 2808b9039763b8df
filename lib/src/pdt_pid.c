/*
 * pdt_pid: the PID controller that runs pdt_tune's gains, one scan per call.
 * The discretisation and the anti-windup are explained in pdt_pid.h and
 * docs/pid.md; here are only the mechanics.
 */
#include "pdt/pdt_pid.h"

#include "pdt_internal.h"

#define PID_MAGIC PDT_MAGIC('P', 'D', 'P', 'I')

/* Ideal-form gains and the discrete coefficients of one configuration. */
typedef struct pid_coef {
    pdt_real_t K, ki, kd, ad, ao, du_max;
} pid_coef_t;

void pdt_pid_config_default(pdt_pid_config_t *cfg)
{
    if (cfg == NULL) {
        return;
    }
    cfg->Ts = PDT_R(0.1);
    cfg->form = PDT_PID_IDEAL;
    cfg->Kc = PDT_R(1.0);
    cfg->Ti = PDT_R(10.0);
    cfg->Td = PDT_R(0.0);
    cfg->Tf = PDT_R(0.0);
    cfg->N = PDT_R(10.0);
    cfg->b = PDT_R(1.0);
    cfg->c = PDT_R(0.0);
    cfg->u_min = PDT_R(0.0);
    cfg->u_max = PDT_R(100.0);
    cfg->rate_max = PDT_R(0.0);
    cfg->antiwindup = PDT_PID_AW_BACK_CALC;
    cfg->Tt = PDT_R(0.0);
}

static bool nonneg(pdt_real_t x)
{
    return pdt_finite(x) && x >= PDT_R(0.0);
}

/* Checks cfg and derives the coefficients; false for any invalid field. */
static bool coef_make(const pdt_pid_config_t *cfg, pid_coef_t *c)
{
    if (!pdt_finite(cfg->Ts) || !(cfg->Ts > PDT_R(0.0)) ||
        (cfg->form != PDT_PID_IDEAL && cfg->form != PDT_PID_SERIES) || !pdt_finite(cfg->Kc) ||
        cfg->Kc == PDT_R(0.0) || !nonneg(cfg->Ti) || !nonneg(cfg->Td) || !nonneg(cfg->Tf) ||
        !nonneg(cfg->N) || (cfg->N != PDT_R(0.0) && cfg->N < PDT_R(1.0)) || !nonneg(cfg->b) ||
        !nonneg(cfg->c) || !pdt_finite(cfg->u_min) || !pdt_finite(cfg->u_max) ||
        !(cfg->u_min < cfg->u_max) || !nonneg(cfg->rate_max) || !nonneg(cfg->Tt) ||
        (unsigned)cfg->antiwindup > (unsigned)PDT_PID_AW_NONE) {
        return false;
    }
    pdt_tune_gains_t g;
    g.Kc = cfg->Kc;
    g.tauI = cfg->Ti;
    g.tauD = cfg->Td;
    g.Tf = cfg->Tf;
    if (g.Tf == PDT_R(0.0) && cfg->N > PDT_R(0.0)) {
        /* N applies to the derivative time of the form given, as in
         * pdt_tune's deriv_filter. */
        g.Tf = g.tauD / cfg->N;
    }
    if (cfg->form == PDT_PID_SERIES && g.tauI > PDT_R(0.0)) {
        pdt_tune_gains_t s = g;
        if (pdt_tune_to_ideal(&s, &g) != PDT_OK) {
            return false;
        }
    }
    /* Without integral action the series form is Kc (Td s + 1), already
     * ideal. */
    const pdt_real_t Ts = cfg->Ts;
    c->K = g.Kc;
    c->ki = g.tauI > PDT_R(0.0) ? g.Kc * Ts / (PDT_R(2.0) * g.tauI) : PDT_R(0.0);
    c->kd = g.Kc * g.tauD;
    c->ad = g.Tf > PDT_R(0.0) ? pdt_exp(-Ts / g.Tf) : PDT_R(0.0);
    c->ao = PDT_R(0.0);
    if (g.tauI > PDT_R(0.0)) {
        pdt_real_t Tt = cfg->Tt;
        if (Tt == PDT_R(0.0)) {
            Tt = g.tauD > PDT_R(0.0) ? pdt_sqrt(g.tauI * g.tauD) : g.tauI;
        }
        c->ao = -pdt_expm1(-Ts / Tt);
    }
    c->du_max = cfg->rate_max * Ts;
    return pdt_finite(c->ki) && pdt_finite(c->kd) && pdt_finite(c->du_max) && pdt_finite(c->ao);
}

static void coef_store(pdt_pid_t *pid, const pdt_pid_config_t *cfg, const pid_coef_t *c)
{
    pid->cfg = *cfg;
    pid->K = c->K;
    pid->ki = c->ki;
    pid->kd = c->kd;
    pid->ad = c->ad;
    pid->ao = c->ao;
    pid->du_max = c->du_max;
}

static pdt_real_t clamp(pdt_real_t x, pdt_real_t lo, pdt_real_t hi)
{
    return x < lo ? lo : (x > hi ? hi : x);
}

/* The config with its form and gains replaced by g (filter taken as is). */
static bool config_with_gains(const pdt_pid_config_t *base, const pdt_tune_gains_t *g,
                              pdt_pid_form_t form, pdt_pid_config_t *out)
{
    if (base == NULL || g == NULL || !pdt_finite(g->Kc) || g->Kc == PDT_R(0.0) ||
        !pdt_finite(g->tauI) || !(g->tauI > PDT_R(0.0)) || !nonneg(g->tauD) || !nonneg(g->Tf)) {
        return false;
    }
    *out = *base;
    out->form = form;
    out->Kc = g->Kc;
    out->Ti = g->tauI;
    out->Td = g->tauD;
    out->Tf = g->Tf;
    out->N = PDT_R(0.0);
    return true;
}

pdt_status_t pdt_pid_init(pdt_pid_t *pid, const pdt_pid_config_t *cfg, pdt_real_t u0)
{
    pid_coef_t c;
    if (pid == NULL || cfg == NULL || !pdt_finite(u0) || !coef_make(cfg, &c)) {
        return PDT_ERR_ARG;
    }
    coef_store(pid, cfg, &c);
    pid->primed = false;
    pid->i = PDT_R(0.0);
    pid->df = PDT_R(0.0);
    pid->sp_last = PDT_R(0.0);
    pid->pv_last = PDT_R(0.0);
    pid->u = clamp(u0, cfg->u_min, cfg->u_max);
    pid->p_term = PDT_R(0.0);
    pid->i_term = pid->u;
    pid->d_term = PDT_R(0.0);
    pid->limited = pid->u != u0;
    pid->magic = PID_MAGIC;
    return PDT_OK;
}

pdt_status_t pdt_pid_init_from_gains(pdt_pid_t *pid, const pdt_pid_config_t *base,
                                     const pdt_tune_gains_t *g, pdt_pid_form_t form, pdt_real_t u0)
{
    pdt_pid_config_t cfg;
    if (!config_with_gains(base, g, form, &cfg)) {
        return PDT_ERR_ARG;
    }
    return pdt_pid_init(pid, &cfg, u0);
}

static pdt_status_t check(const pdt_pid_t *pid, pdt_real_t sp, pdt_real_t pv)
{
    if (pid == NULL) {
        return PDT_ERR_ARG;
    }
    if (pid->magic != PID_MAGIC) {
        return PDT_ERR_STATE;
    }
    if (!pdt_finite(sp) || !pdt_finite(pv)) {
        return PDT_ERR_NONFINITE;
    }
    return PDT_OK;
}

/* The filtered derivative after a scan that measured c sp - pv = y. */
static pdt_real_t df_next(const pdt_pid_t *pid, pdt_real_t sp, pdt_real_t pv)
{
    if (!pid->primed) {
        return PDT_R(0.0);
    }
    pdt_real_t dy = pid->cfg.c * (sp - pid->sp_last) - (pv - pid->pv_last);
    return pid->ad * pid->df + (PDT_R(1.0) - pid->ad) * dy / pid->cfg.Ts;
}

pdt_status_t pdt_pid_update(pdt_pid_t *pid, pdt_real_t sp, pdt_real_t pv, pdt_real_t *u)
{
    if (u == NULL) {
        return PDT_ERR_ARG;
    }
    pdt_status_t st = check(pid, sp, pv);
    if (st != PDT_OK) {
        return st;
    }
    const pdt_pid_config_t *cfg = &pid->cfg;
    const pdt_real_t e = sp - pv;
    const pdt_real_t p = pid->K * (cfg->b * sp - pv);
    const pdt_real_t df = df_next(pid, sp, pv);
    const pdt_real_t d = pid->kd * df;
    pdt_real_t lo = cfg->u_min;
    pdt_real_t hi = cfg->u_max;
    if (pid->du_max > PDT_R(0.0)) {
        lo = clamp(pid->u - pid->du_max, cfg->u_min, cfg->u_max);
        hi = clamp(pid->u + pid->du_max, cfg->u_min, cfg->u_max);
    }
    pdt_real_t inc = PDT_R(0.0);
    pdt_real_t i_prev = pid->i;
    pdt_real_t ik;
    pdt_real_t v;
    if (!pid->primed) {
        /* Bumpless start: the integral takes what the output in service
         * needs, and the output is that one exactly (no rounding through
         * p + i + d); nothing to integrate yet. */
        i_prev = pid->u - p - d;
        ik = i_prev;
        v = pid->u;
    } else {
        inc = pid->ki * (e + (pid->sp_last - pid->pv_last));
        ik = i_prev + inc;
        v = p + ik + d;
    }
    const pdt_pid_antiwindup_t aw = cfg->antiwindup;
    bool cut = false;
    if (aw == PDT_PID_AW_CONDITIONAL || aw == PDT_PID_AW_BOTH) {
        /* Integrate at most up to the limit the increment pushes toward,
         * never back past where the integral was. */
        if (v > hi && inc > PDT_R(0.0)) {
            ik = hi - p - d > i_prev ? hi - p - d : i_prev;
            v = p + ik + d;
            cut = true;
        } else if (v < lo && inc < PDT_R(0.0)) {
            ik = lo - p - d < i_prev ? lo - p - d : i_prev;
            v = p + ik + d;
            cut = true;
        }
    }
    if (!pdt_finite(v) || !pdt_finite(df)) {
        return PDT_ERR_NONFINITE;
    }
    const pdt_real_t out = clamp(v, lo, hi);
    pdt_real_t i_next = ik;
    if (aw == PDT_PID_AW_BACK_CALC || aw == PDT_PID_AW_BOTH) {
        i_next += pid->ao * (out - v);
    }
    pid->i = i_next;
    pid->df = df;
    pid->sp_last = sp;
    pid->pv_last = pv;
    pid->u = out;
    pid->p_term = p;
    pid->i_term = ik;
    pid->d_term = d;
    pid->limited = cut || out != v;
    pid->primed = true;
    *u = out;
    return PDT_OK;
}

pdt_status_t pdt_pid_track(pdt_pid_t *pid, pdt_real_t sp, pdt_real_t pv, pdt_real_t u_applied)
{
    pdt_status_t st = check(pid, sp, pv);
    if (st != PDT_OK) {
        return st;
    }
    if (!pdt_finite(u_applied)) {
        return PDT_ERR_NONFINITE;
    }
    const pdt_real_t p = pid->K * (pid->cfg.b * sp - pv);
    const pdt_real_t df = df_next(pid, sp, pv);
    const pdt_real_t d = pid->kd * df;
    const pdt_real_t i = u_applied - p - d;
    if (!pdt_finite(i)) {
        return PDT_ERR_NONFINITE;
    }
    pid->i = i;
    pid->df = df;
    pid->sp_last = sp;
    pid->pv_last = pv;
    pid->u = u_applied;
    pid->p_term = p;
    pid->i_term = i;
    pid->d_term = d;
    pid->limited = false;
    pid->primed = true;
    return PDT_OK;
}

pdt_status_t pdt_pid_set_config(pdt_pid_t *pid, const pdt_pid_config_t *cfg)
{
    pid_coef_t c;
    if (pid == NULL || cfg == NULL || !coef_make(cfg, &c)) {
        return PDT_ERR_ARG;
    }
    if (pid->magic != PID_MAGIC) {
        return PDT_ERR_STATE;
    }
    pdt_real_t i = pid->i;
    pdt_real_t u = pid->u;
    if (pid->primed) {
        /* The output recomputed at the last sp and pv, with the new P and D,
         * stays the last output: the integral absorbs the difference. The
         * filtered derivative is a signal (pv/s) and keeps its value. */
        pdt_real_t p = c.K * (cfg->b * pid->sp_last - pid->pv_last);
        i = u - p - c.kd * pid->df;
        if (!pdt_finite(i)) {
            return PDT_ERR_ARG;
        }
    } else {
        u = clamp(u, cfg->u_min, cfg->u_max);
    }
    coef_store(pid, cfg, &c);
    pid->i = i;
    pid->u = u;
    return PDT_OK;
}

pdt_status_t pdt_pid_set_gains(pdt_pid_t *pid, const pdt_tune_gains_t *g, pdt_pid_form_t form)
{
    if (pid == NULL) {
        return PDT_ERR_ARG;
    }
    if (pid->magic != PID_MAGIC) {
        return PDT_ERR_STATE;
    }
    pdt_pid_config_t cfg;
    if (!config_with_gains(&pid->cfg, g, form, &cfg)) {
        return PDT_ERR_ARG;
    }
    return pdt_pid_set_config(pid, &cfg);
}
