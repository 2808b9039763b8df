/*
 * Autotune: the experiment, the identification and the tuning as one state
 * machine, one call per scan. Each phase delegates to its module; this file
 * only sequences them and keeps the output safe.
 */
#include "pdt/pdt_autotune.h"

#include "pdt_autotune_priv.h"
#include "pdt_internal.h"
#include "pdt_model_priv.h"

#define AUTOTUNE_MAGIC PDT_MAGIC('P', 'D', 'A', 'T')

void pdt_autotune_config_default(pdt_autotune_config_t *cfg)
{
    if (cfg == NULL) {
        return;
    }
    *cfg = (pdt_autotune_config_t){0};
    cfg->Ts = PDT_R(0.0);
    cfg->decimation = 1u;
    cfg->capacity = 0u;
    cfg->settle = 20u;
    cfg->tail = 0u;
    cfg->evals_per_scan = 4u;
    pdt_excite_config_default(&cfg->excite, PDT_EXCITE_PRBS);
    cfg->u_min = -PDT_REAL_MAX;
    cfg->u_max = PDT_REAL_MAX;
    cfg->pv_min = -PDT_REAL_MAX;
    cfg->pv_max = PDT_REAL_MAX;
    cfg->max_scans = 0u;
    cfg->move = PDT_RECORD_MOVE_ANY;
    pdt_ident_config_default(&cfg->ident);
    pdt_tune_config_default(&cfg->tune);
    cfg->order_auto = true;
    cfg->ms_robust = PDT_R(2.0);
    cfg->relay_agree = PDT_R(2.0);
    cfg->shift_max = PDT_R(0.08);
    cfg->relay_spread_max = PDT_R(0.5);
    cfg->repeats = 1u;
    cfg->drift_passes = 3u;
}

static pdt_real_t rmax0(pdt_real_t x)
{
    return x > PDT_R(0.0) ? x : PDT_R(0.0);
}

/* The knob factors the tuning tries, in order, until the evidence accepts
 * the gains: a slower closed loop each time. */
static const pdt_real_t detune_steps[] = {PDT_R(1.0), PDT_R(1.5),  PDT_R(2.0),
                                          PDT_R(3.0), PDT_R(4.0),  PDT_R(6.0),
                                          PDT_R(8.0), PDT_R(12.0), PDT_R(16.0)};
#define DETUNE_STEPS (sizeof detune_steps / sizeof detune_steps[0])

/* The identification's config: the caller's, at the identification rate. */
static pdt_ident_config_t ident_config(const pdt_autotune_config_t *cfg)
{
    pdt_ident_config_t ic = cfg->ident;
    ic.Ts = cfg->Ts * (pdt_real_t)cfg->decimation;
    /* The experiment begins once the settle phase found the plant at
     * rest: AUTO's test (and its refit with the state estimated) is not
     * for it, and the autotune never read its flag. */
    if (ic.initial == PDT_IDENT_INITIAL_AUTO) {
        ic.initial = PDT_IDENT_INITIAL_REST;
    }
    return ic;
}

static pdt_status_t check_config(const pdt_autotune_config_t *cfg)
{
    if (!pdt_finite(cfg->Ts) || !(cfg->Ts > PDT_R(0.0)) || cfg->decimation == 0u ||
        cfg->settle == 0u || cfg->evals_per_scan == 0u) {
        return PDT_ERR_ARG;
    }
    if (!pdt_finite(cfg->ms_robust) ||
        (cfg->ms_robust != PDT_R(0.0) && !(cfg->ms_robust > PDT_R(1.0))) ||
        !pdt_finite(cfg->relay_agree) ||
        (cfg->relay_agree != PDT_R(0.0) && !(cfg->relay_agree >= PDT_R(1.0)))) {
        return PDT_ERR_ARG;
    }
    if (!pdt_finite(cfg->shift_max) || !(cfg->shift_max >= PDT_R(0.0)) ||
        !pdt_finite(cfg->relay_spread_max) || !(cfg->relay_spread_max >= PDT_R(0.0))) {
        return PDT_ERR_ARG;
    }
    if (!pdt_finite(cfg->u_min) || !pdt_finite(cfg->u_max) || !pdt_finite(cfg->pv_min) ||
        !pdt_finite(cfg->pv_max)) {
        return PDT_ERR_ARG;
    }
    if (cfg->u_min > cfg->u_max || cfg->pv_min > cfg->pv_max) {
        return PDT_ERR_BOUNDS;
    }
    if (cfg->capacity > PDT_MAX_SAMPLES) {
        return PDT_ERR_LENGTH;
    }
    if (cfg->capacity < (size_t)cfg->settle + PDT_MIN_SAMPLES) {
        return PDT_ERR_TOO_SHORT;
    }
    return PDT_OK;
}

/* Whether the model is validated: the order choice and the robust bound
 * need it; without either, the validation's workspace is not asked for. */
static bool validates(const pdt_autotune_config_t *cfg)
{
    return cfg->order_auto || cfg->ms_robust > PDT_R(0.0);
}

/* The model the automatic order's identification stage fits: a FOPDT,
 * then a SOPDT. */
static pdt_model_kind_t stage_kind(uint32_t stage)
{
    return stage == 0u ? PDT_MODEL_FOPDT : PDT_MODEL_SOPDT;
}

/* Bytes of the identification's part, for capacity samples. The size grows
 * with the record length, so it covers any shorter record. */
static size_t ident_bytes(const pdt_autotune_config_t *cfg)
{
    pdt_ident_config_t ic = ident_config(cfg);
    size_t b = pdt_ident_workspace_size(&ic, cfg->capacity);
    if (cfg->order_auto) {
        /* The other stage's model: the larger part serves either. */
        ic.model = stage_kind(ic.model == stage_kind(0u) ? 1u : 0u);
        size_t b2 = pdt_ident_workspace_size(&ic, cfg->capacity);
        if (b == 0u || b2 == 0u) {
            return 0u;
        }
        b = b2 > b ? b2 : b;
    }
    size_t v = validates(cfg) ? pdt_validate_run_workspace_size(cfg->capacity) : 0u;
    /* The disturbance check simulates the model beside its input. */
    const size_t c = cfg->shift_max > PDT_R(0.0) ? 2u * cfg->capacity * sizeof(pdt_real_t) : 0u;
    v = c > v ? c : v;
    return b == 0u ? 0u : (v > b ? v : b);
}

size_t pdt_autotune_workspace_size(const pdt_autotune_config_t *cfg)
{
    if (cfg == NULL || check_config(cfg) != PDT_OK) {
        return 0u;
    }
    size_t ib = ident_bytes(cfg);
    if (ib == 0u) {
        return 0u;
    }
    return 2u * cfg->capacity * sizeof(pdt_real_t) + ib;
}

/* The experiment's generator and recorder from u_now, the operating
 * point: the generator holds u_now while the recorder measures the
 * operating point, then excites. */
static pdt_status_t make_experiment(const pdt_autotune_config_t *cfg, pdt_real_t u_now, bool closed,
                                    pdt_real_t *u, pdt_real_t *y, pdt_excite_t *gen,
                                    pdt_record_t *rec)
{
    /* With the loop closed the generator moves the set-point (u_now is
     * then the set-point in service), inside the process value's limits. */
    pdt_excite_config_t ec = cfg->excite;
    ec.Ts = cfg->Ts;
    ec.u0 = u_now;
    ec.u_min = closed ? cfg->pv_min : cfg->u_min;
    ec.u_max = closed ? cfg->pv_max : cfg->u_max;
    ec.pre = cfg->Ts * (pdt_real_t)cfg->decimation * (pdt_real_t)cfg->settle;
    pdt_status_t st = pdt_excite_init(gen, &ec);
    if (st != PDT_OK) {
        return st;
    }
    pdt_record_config_t rc;
    pdt_record_config_default(&rc);
    rc.decimation = cfg->decimation;
    rc.settle = cfg->settle;
    rc.u_min = cfg->u_min;
    rc.u_max = cfg->u_max;
    rc.pv_min = cfg->pv_min;
    rc.pv_max = cfg->pv_max;
    rc.max_scans = cfg->max_scans;
    rc.move = cfg->move;
    rc.move = closed ? PDT_RECORD_MOVE_ANY : cfg->move;
    rc.setpoint = ec.kind == PDT_EXCITE_RELAY ? ec.setpoint : PDT_R(0.0);
    return pdt_record_init(rec, &rc, u, y, cfg->capacity);
}

/* The checks of init shared by both loops, and the workspace split: the
 * record's arrays u and y and the identification's bytes *ib. */
static pdt_status_t check_work(const pdt_autotune_config_t *cfg, void *work, size_t work_len,
                               size_t *ib_out)
{
    size_t ib = ident_bytes(cfg);
    if (ib == 0u) {
        /* The identification refuses its config (or the capacity): say
         * why, as pdt_ident_workspace_size only says no. */
        return PDT_ERR_ARG;
    }
    if (work == NULL) {
        return PDT_ERR_NOMEM;
    }
    if (!pdt_aligned(work)) {
        return PDT_ERR_ARG;
    }
    if (work_len < 2u * cfg->capacity * sizeof(pdt_real_t) + ib) {
        return PDT_ERR_NOMEM;
    }
    *ib_out = ib;
    return PDT_OK;
}

/* Both inits after their checks: u_now is the output (open loop) or the
 * set-point (closed) the experiment starts from. */
static pdt_status_t start(pdt_autotune_t *at, const pdt_autotune_config_t *cfg, pdt_real_t u_now,
                          pdt_pid_t *pid, void *work, size_t work_len)
{
    size_t ib = 0u;
    pdt_status_t st = check_work(cfg, work, work_len, &ib);
    if (st != PDT_OK) {
        return st;
    }
    pdt_real_t *u = (pdt_real_t *)work;
    pdt_real_t *y = u + cfg->capacity;
    pdt_excite_t gen;
    pdt_record_t rec;
    st = make_experiment(cfg, u_now, pid != NULL, u, y, &gen, &rec);
    if (st != PDT_OK) {
        return st;
    }

    /* Nothing failed: only now is *at written. The output in service is
     * the PID's with the loop closed. */
    const pdt_real_t u_out = pid != NULL ? pid->u : u_now;
    at->pid = pid;
    at->sp0 = u_now;
    at->pid_ran = false;
    at->u_last = u_out;
    at->u_pos = u_out;
    at->pv_n = 0u;
    at->pv_d2 = PDT_R(0.0);
    at->pv_prev = PDT_R(0.0);
    at->cfg = *cfg;
    at->phase = PDT_AUTOTUNE_SETTLE;
    at->u_init = u_out;
    at->u_hold = u_out;
    at->u = u;
    at->y = y;
    at->scratch = y + cfg->capacity;
    at->ident_work = (void *)at->scratch;
    at->ident_work_len = ib;
    at->gen = gen;
    at->rec = rec;
    at->tail_end = 0u;
    at->excite_over = false;
    at->ident_started = false;
    at->valid_started = false;
    at->stage = 0u;
    at->tune_try = 0u;
    at->tune_stage = 0u;
    at->tune_why = PDT_OK;
    at->res = (pdt_autotune_result_t){0};
    at->res.detune = PDT_R(1.0);
    at->res.status = PDT_RUNNING;
    at->magic = AUTOTUNE_MAGIC;
    return PDT_OK;
}

pdt_status_t pdt_autotune_init(pdt_autotune_t *at, const pdt_autotune_config_t *cfg,
                               pdt_real_t u_now, void *work, size_t work_len)
{
    if (at == NULL || cfg == NULL || !pdt_finite(u_now)) {
        return PDT_ERR_ARG;
    }
    pdt_status_t st = check_config(cfg);
    if (st != PDT_OK) {
        return st;
    }
    if (u_now < cfg->u_min || u_now > cfg->u_max) {
        return PDT_ERR_OUTPUT_LIMIT;
    }
    return start(at, cfg, u_now, NULL, work, work_len);
}

pdt_status_t pdt_autotune_init_closed(pdt_autotune_t *at, const pdt_autotune_config_t *cfg,
                                      pdt_pid_t *pid, pdt_real_t sp, void *work, size_t work_len)
{
    if (at == NULL || cfg == NULL || pid == NULL || !pdt_finite(sp) ||
        cfg->excite.kind == PDT_EXCITE_RELAY) {
        return PDT_ERR_ARG;
    }
    pdt_status_t st = check_config(cfg);
    if (st != PDT_OK) {
        return st;
    }
    /* A controller that was never initialised has no gains to keep. */
    pdt_pid_t copy = *pid;
    if (pdt_pid_track(&copy, sp, sp, pid->u) != PDT_OK) {
        return PDT_ERR_STATE;
    }
    if (sp < cfg->pv_min || sp > cfg->pv_max) {
        return PDT_ERR_OUTPUT_LIMIT;
    }
    return start(at, cfg, sp, pid, work, work_len);
}

static pdt_status_t fail(pdt_autotune_t *at, pdt_status_t why, pdt_real_t *u)
{
    at->res.status = why;
    at->res.failed_in = at->phase;
    at->phase = PDT_AUTOTUNE_FAILED;
    *u = at->u_hold;
    return why;
}

/* The safety limits that still hold once the experiment is over. */
static pdt_status_t check_pv(const pdt_autotune_t *at, pdt_real_t pv)
{
    if (!pdt_finite(pv)) {
        return PDT_ERR_NONFINITE;
    }
    if (pv < at->cfg.pv_min || pv > at->cfg.pv_max) {
        return PDT_ERR_PV_LIMIT;
    }
    return PDT_OK;
}

/* The record is complete: back to the operating point, identify next. */
static void end_experiment(pdt_autotune_t *at)
{
    pdt_record_result_t rr;
    (void)pdt_record_result(&at->rec, &rr);
    at->u_hold = rr.u0;
    at->res.samples = rr.n;
    if (at->cfg.excite.kind == PDT_EXCITE_RELAY &&
        pdt_excite_relay_result(&at->gen, &at->res.relay) == PDT_OK) {
        at->res.has_relay = true;
    }
    at->phase = PDT_AUTOTUNE_IDENTIFY;
}

/* The process value at rest, scan by scan: its noise from the first
 * differences (sd = rms difference / sqrt 2, blind to a slow trend) and
 * its quantum (the smallest step between two readings). At the end of the
 * settle window a relay's hysteresis is raised to 3 noise sd and one
 * quantum when it is below them, so that neither switches the relay. */
static void settle_scan(pdt_autotune_t *at, pdt_real_t pv)
{
    if (at->pv_n > 0u) {
        const pdt_real_t d = pdt_fabs(pv - at->pv_prev);
        at->pv_d2 += d * d;
        if (d > PDT_R(0.0) && (at->res.quantum == PDT_R(0.0) || d < at->res.quantum)) {
            at->res.quantum = d;
        }
    }
    at->pv_prev = pv;
    at->pv_n++;
    pdt_record_result_t rr;
    (void)pdt_record_result(&at->rec, &rr);
    if (!rr.settled) {
        return;
    }
    at->phase = PDT_AUTOTUNE_EXCITE;
    if (at->pv_n > 1u) {
        const uint32_t m = at->pv_n - 1u;
        at->res.noise = pdt_sqrt(at->pv_d2 / (PDT_R(2.0) * (pdt_real_t)m));
    }
    if (at->gen.cfg.kind == PDT_EXCITE_RELAY) {
        pdt_real_t eps = at->gen.cfg.eps;
        eps = PDT_R(3.0) * at->res.noise > eps ? PDT_R(3.0) * at->res.noise : eps;
        eps = at->res.quantum > eps ? at->res.quantum : eps;
        at->gen.cfg.eps = eps;
    }
    at->res.relay_eps = at->gen.cfg.eps;
}

static pdt_status_t scan_experiment(pdt_autotune_t *at, pdt_real_t pv, pdt_real_t *u)
{
    pdt_real_t un;
    pdt_status_t se = pdt_excite_next(&at->gen, pv, &un);
    if (se != PDT_OK && se != PDT_RUNNING) {
        /* Only a relay fails here (pv not finite): hold the operating point. */
        return fail(at, se, u);
    }
    if (at->pid != NULL) {
        /* Closed loop: the generator gave the set-point; the PID the
         * output recorded. A pv that is not finite ends the experiment;
         * the PID holds its output. */
        const pdt_real_t sp = un;
        if (pdt_pid_update(at->pid, sp, pv, &un) != PDT_OK) {
            return fail(at, PDT_ERR_NONFINITE, u);
        }
        at->pid_ran = true;
    }
    /* Samples complete before this scan: the tail counts from here when the
     * excitation ends in this scan. */
    const size_t n_before = at->rec.n;
    if (at->cfg.actuator_position && !pdt_finite(at->u_pos)) {
        /* A failed position sensor: the recorder's safe output once it has
         * one, the output at init before. */
        pdt_record_result_t rp;
        (void)pdt_record_result(&at->rec, &rp);
        at->u_hold = rp.scans > 0u ? rp.u_safe : at->u_init;
        return fail(at, PDT_ERR_NONFINITE, u);
    }
    /* The actuator as it moved over the last scan, or as commanded now. */
    const pdt_real_t u_rec = at->cfg.actuator_position ? at->u_pos : un;
    pdt_status_t sr = pdt_record_push(&at->rec, u_rec, pv);
    at->res.scans_experiment++;
    if (sr != PDT_OK && sr != PDT_RUNNING) {
        pdt_record_result_t rr;
        (void)pdt_record_result(&at->rec, &rr);
        at->u_hold = rr.u_safe;
        return fail(at, sr, u);
    }
    if (at->phase == PDT_AUTOTUNE_SETTLE) {
        settle_scan(at, pv);
    }
    if (at->cfg.tail != 0u && sr == PDT_RUNNING && (se == PDT_OK || at->excite_over)) {
        /* The excitation is over; the response is not: record `tail` more
         * samples than were complete when it ended. */
        pdt_record_result_t rr;
        (void)pdt_record_result(&at->rec, &rr);
        if (!at->excite_over) {
            at->excite_over = true;
            /* Saturated: tail is any uint32_t, size_t may be narrower. */
            at->tail_end =
                at->cfg.tail < SIZE_MAX - n_before ? n_before + (size_t)at->cfg.tail : SIZE_MAX;
        }
        if (rr.n >= at->tail_end && pdt_record_stop(&at->rec) == PDT_OK) {
            sr = PDT_OK;
        }
    }
    if (sr == PDT_OK) {
        end_experiment(at);
        *u = at->u_hold;
        return PDT_RUNNING;
    }
    *u = un;
    return PDT_RUNNING;
}

/* The model each identification stage fits. */
static pdt_model_kind_t stage_model(const pdt_autotune_t *at)
{
    if (!at->cfg.order_auto) {
        return at->cfg.ident.model;
    }
    return stage_kind(at->stage);
}

/* The recorder pairs the output of an interval's first scan with the mean
 * process value over its scans, which lags that output by
 * (decimation - 1) / 2 scans less than a point sample would: the model saw
 * that much less dead time than the process has. */
static pdt_real_t dead_time_shift(const pdt_autotune_t *at)
{
    /* A position read at a scan is the one held over the scan before: the
     * record's input lags the process's by a scan. */
    const pdt_real_t pos = at->cfg.actuator_position ? at->cfg.Ts : PDT_R(0.0);
    return at->cfg.Ts * (pdt_real_t)(at->cfg.decimation - 1u) * PDT_R(0.5) + pos;
}

/* Fewest steps of the sensor (pdt_autotune_result_t.quantum) the model's
 * response must span. */
#define RESPONSE_QUANTA PDT_R(4.0)

/* The identification's sample period, s (ident_config's Ts). */
static pdt_real_t id_period(const pdt_autotune_config_t *cfg)
{
    return cfg->Ts * (pdt_real_t)cfg->decimation;
}

/* A disturbed experiment once more, from the operating point the last one
 * measured (the output has rested there since it ended). */
static pdt_status_t repeat_experiment(pdt_autotune_t *at, pdt_real_t *u)
{
    /* Into at directly: on an error the autotune fails, and neither is
     * read again. */
    const bool closed = at->pid != NULL;
    pdt_status_t st = make_experiment(&at->cfg, closed ? at->sp0 : at->u_hold, closed, at->u, at->y,
                                      &at->gen, &at->rec);
    if (st != PDT_OK) {
        return fail(at, st, u);
    }
    at->tail_end = 0u;
    at->excite_over = false;
    at->ident_started = false;
    at->valid_started = false;
    at->stage = 0u;
    at->res.repeats++;
    at->pv_n = 0u;
    at->pv_d2 = PDT_R(0.0);
    at->res.quantum = PDT_R(0.0);
    at->res.drift = PDT_R(0.0);
    at->res.drift_passes = 0u;
    at->res.has_relay = false;
    at->res.has_model = false;
    at->res.has_valid = false;
    at->res.samples = 0u;
    at->phase = PDT_AUTOTUNE_SETTLE;
    *u = at->u_hold;
    return PDT_RUNNING;
}

/* The residual is a drift: removed from the record (slope per sample),
 * which is identified again. */
static pdt_status_t refit_drift(pdt_autotune_t *at, pdt_real_t slope)
{
    for (size_t k = 0u; k < at->res.samples; k++) {
        at->y[k] -= slope * (pdt_real_t)k;
    }
    at->res.drift += slope / id_period(&at->cfg);
    at->res.drift_passes++;
    at->ident_started = false;
    at->valid_started = false;
    at->stage = 0u;
    at->res.has_model = false;
    at->res.has_valid = false;
    return PDT_RUNNING;
}

/* The model is chosen: the disturbance check, then the recorder's dead-time
 * shift added back, and the tuning next. */
static pdt_status_t finish_identify(pdt_autotune_t *at, pdt_real_t *u)
{
    const pdt_ident_data_t data = {at->u, at->y, at->res.samples};
    const pdt_autotune_config_t *c = &at->cfg;
    at->res.shift = PDT_R(0.0);
    /* Measured whenever the workspace has room (always when the check is
     * on), checked only with shift_max > 0. */
    if (at->ident_work_len >= 2u * data.n * sizeof(pdt_real_t) &&
        pdt_autotune_shift(&at->res.ident.model, &data, id_period(c), at->res.ident.u0,
                           at->res.ident.y0, at->scratch, &at->res.shift,
                           &at->res.response) != PDT_OK) {
        return fail(at, PDT_ERR_ARG, u);
    }
    at->res.relay_spread = at->res.has_relay ? pdt_autotune_relay_spread(&at->gen) : PDT_R(0.0);
    pdt_real_t shift = dead_time_shift(at);
    pdt_model_add_dead_time(&at->res.ident.model, shift);
    at->res.has_model = true;
    if (at->res.response > PDT_R(0.0) && at->res.response < RESPONSE_QUANTA * at->res.quantum) {
        /* A response of a few steps of the sensor: the experiment is too
         * small for it. */
        return fail(at, PDT_ERR_NO_EXCITATION, u);
    }
    const bool disturbed =
        (c->shift_max > PDT_R(0.0) && at->res.shift > c->shift_max) ||
        (c->relay_spread_max > PDT_R(0.0) && at->res.relay_spread > c->relay_spread_max);
    /* A drift is fitted while the residual still looks like one: past a
     * quarter of the limit once a drift has been found, past the limit
     * before. */
    pdt_real_t slope = PDT_R(0.0);
    const pdt_real_t lim = at->res.drift_passes > 0u ? PDT_R(0.25) * c->shift_max : c->shift_max;
    if (c->shift_max > PDT_R(0.0) && at->res.shift > lim &&
        at->res.drift_passes < c->drift_passes && pdt_autotune_ramp(at->scratch, data.n, &slope)) {
        return refit_drift(at, slope);
    }
    if (disturbed) {
        return at->res.repeats < c->repeats ? repeat_experiment(at, u)
                                            : fail(at, PDT_ERR_DISTURBED, u);
    }
    at->phase = PDT_AUTOTUNE_TUNE;
    return PDT_RUNNING;
}

/* Identification stages: 0 (and 1 with order_auto) identify, one model
 * at a time in the same workspace; then one validation per scan; then the
 * choice of order. */
static pdt_status_t scan_identify(pdt_autotune_t *at, pdt_real_t *u)
{
    pdt_status_t st;
    *u = at->u_hold;
    const uint32_t models = at->cfg.order_auto ? 2u : 1u;
    const pdt_ident_data_t data = {at->u, at->y, at->res.samples};
    if (at->stage < models) {
        if (!at->ident_started) {
            pdt_ident_config_t ic = ident_config(&at->cfg);
            ic.model = stage_model(at);
            st = pdt_ident_init(&at->ident, &ic, &data, at->ident_work, at->ident_work_len);
            if (st != PDT_OK) {
                return fail(at, st, u);
            }
            at->ident_started = true;
            return PDT_RUNNING;
        }
        st = pdt_ident_step(&at->ident, at->cfg.evals_per_scan);
        if (st == PDT_RUNNING) {
            return PDT_RUNNING;
        }
        if (st == PDT_OK) {
            st = pdt_ident_result(&at->ident, at->stage == 0u ? &at->first : &at->res.ident);
        }
        if (st != PDT_OK) {
            return fail(at, st, u);
        }
        if (models == 1u) {
            at->res.ident = at->first;
        }
        at->ident_started = false;
        at->stage++;
        return PDT_RUNNING;
    }
    /* Validation, one model after the other, in bounded steps (one per
     * scan) in the identification's workspace (free now). */
    const uint32_t v = at->stage - models;
    if (v < models && validates(&at->cfg)) {
        const pdt_ident_result_t *ir = v == 0u ? &at->first : &at->res.ident;
        pdt_validate_result_t *vr = v == 0u ? &at->first_valid : &at->res.valid;
        if (!at->valid_started) {
            st = pdt_validate_begin(&ir->model, &data, id_period(&at->cfg), ir->y0, at->ident_work,
                                    at->ident_work_len);
            if (st != PDT_OK) {
                return fail(at, st, u);
            }
            at->valid_started = true;
            return PDT_RUNNING;
        }
        st = pdt_validate_step(at->ident_work, vr);
        if (st == PDT_RUNNING) {
            return PDT_RUNNING;
        }
        if (st != PDT_OK) {
            return fail(at, st, u);
        }
        at->valid_started = false;
        at->stage++;
        return PDT_RUNNING;
    }
    if (models == 1u) {
        at->res.valid = at->first_valid;
        at->res.has_valid = validates(&at->cfg);
    } else {
        pdt_model_kind_t kind;
        st = pdt_ident_select_order(&at->first_valid, &at->res.valid, &kind);
        if (st != PDT_OK) {
            return fail(at, st, u);
        }
        if (kind == at->first.model.kind) {
            at->res.bic_other = at->res.valid.bic;
            at->res.ident = at->first;
            at->res.valid = at->first_valid;
        } else {
            at->res.bic_other = at->first_valid.bic;
        }
        at->res.has_valid = true;
    }
    return finish_identify(at, u);
}

/* Whether the model passes through the point of its frequency response
 * the relay measured: a relay of half swing d and hysteresis eps that
 * cycles with amplitude a and period Pu says, by its describing function,
 * G(j 2 pi / Pu) = -(pi a / (4 d)) e^{j asin(eps / a)}. The magnitudes must
 * agree within the factor relay_agree, the phases within
 * 45 degrees x (relay_agree - 1). */
static bool relay_agrees(const pdt_autotune_t *at)
{
    const pdt_excite_relay_t *rl = &at->res.relay;
    if (!at->res.has_relay || at->cfg.relay_agree == PDT_R(0.0) || !(rl->Pu > PDT_R(0.0)) ||
        !(rl->a > PDT_R(0.0)) || !(rl->d > PDT_R(0.0))) {
        return true;
    }
    pdt_real_t w = PDT_R(2.0) * PDT_PI / rl->Pu;
    pdt_real_t mag, ph;
    if (pdt_model_freq(&at->res.ident.model, &w, 1u, &mag, &ph) != PDT_OK || !(mag > PDT_R(0.0))) {
        return true;
    }
    pdt_real_t gain;
    if (pdt_model_dc_gain(&at->res.ident.model, &gain) == PDT_OK && gain < PDT_R(0.0)) {
        ph += PDT_PI; /* the relay's action took the sign out */
    } else if (pdt_model_gain_numerator(&at->res.ident.model) < PDT_R(0.0)) {
        ph += PDT_PI;
    }
    pdt_real_t x = at->gen.cfg.eps / rl->a; /* the hysteresis used */
    pdt_real_t ph_relay = -PDT_PI + pdt_atan2(x, pdt_sqrt(rmax0(PDT_R(1.0) - x * x)));
    pdt_real_t r = mag * PDT_R(4.0) * rl->d / (PDT_PI * rl->a);
    pdt_real_t f = at->cfg.relay_agree;
    pdt_real_t dph = ph - ph_relay;
    while (dph > PDT_PI) {
        dph -= PDT_R(2.0) * PDT_PI;
    }
    while (dph < -PDT_PI) {
        dph += PDT_R(2.0) * PDT_PI;
    }
    pdt_real_t ph_tol = PDT_PI / PDT_R(4.0) * (f - PDT_R(1.0));
    return r <= f && r >= PDT_R(1.0) / f && pdt_fabs(dph) <= ph_tol;
}

/* The evidence a knob factor's tuning must meet before it is taken. */
static pdt_status_t tune_checks(pdt_autotune_t *at, pdt_real_t *u)
{
    const pdt_tune_config_t *tc = &at->cfg.tune;
    if (!pdt_finite(at->res.ident.fit) || at->res.ident.fit < tc->fit_min) {
        return fail(at, pdt_finite(tc->fit_min) ? PDT_ERR_POOR_FIT : PDT_ERR_ARG, u);
    }
    if (!relay_agrees(at)) {
        return fail(at, PDT_ERR_MODEL_INVALID, u);
    }
    /* The search itself was not sure (searches that disagree, another
     * structure as good, a parameter on its bound): gains from such a
     * model could have the wrong sign or scale. */
    if ((at->res.ident.flags &
         (PDT_IDENT_FLAG_UNCONFIRMED | PDT_IDENT_FLAG_AMBIGUOUS | PDT_IDENT_FLAG_AT_BOUND)) != 0u) {
        return fail(at, PDT_ERR_UNCERTAIN, u);
    }
    return PDT_OK;
}

/* The tuning's config for the knob factor being tried: the caller's limits
 * left to the checks here. */
static pdt_tune_config_t tune_config(const pdt_autotune_t *at)
{
    const pdt_tune_config_t *tc = &at->cfg.tune;
    pdt_tune_config_t c = *tc;
    c.ms_max = PDT_R(0.0);
    c.fit_min = PDT_R(0.0);
    const pdt_real_t base = tc->detune > PDT_R(0.0) ? tc->detune : PDT_R(1.0);
    c.detune = base * detune_steps[at->tune_try];
    return c;
}

/* Where a knob factor's tuning is (pdt_autotune_t.tune_stage). */
#define TUNE_BEGIN  0u /* the rule's gains: pdt_tune_begin */
#define TUNE_FIGURE 1u /* their robustness figures: pdt_tune_step */
#define TUNE_MARGIN 2u /* the robust bound: pdt_validate_margin */

/* The tuning of the knob factor being tried, one bounded step per scan:
 * PDT_RUNNING while it goes on, else its outcome with *r (PDT_OK, or
 * PDT_ERR_UNSTABLE, which the next factor may cure). The figures' state
 * lives in the identification's workspace, free by now. */
static pdt_status_t tune_step(pdt_autotune_t *at, const pdt_tune_config_t *c, pdt_tune_result_t *r)
{
    if (at->tune_stage == TUNE_BEGIN) {
        const pdt_status_t sb = pdt_tune_begin(&at->res.ident.model, at->res.ident.fit, c,
                                               at->ident_work, at->ident_work_len);
        if (sb != PDT_OK) {
            return sb;
        }
        at->tune_stage = TUNE_FIGURE;
        return PDT_RUNNING;
    }
    pdt_status_t st = pdt_tune_step(at->ident_work, r);
    const pdt_tune_config_t *tc = &at->cfg.tune;
    if (st == PDT_OK && tc->ms_max > PDT_R(0.0) && r->fig.Ms > tc->ms_max) {
        return PDT_ERR_MS_LIMIT;
    }
    if (st == PDT_OK && at->cfg.ms_robust > PDT_R(0.0) && at->tune_stage == TUNE_FIGURE) {
        /* The robust bound in a scan of its own. */
        at->tune_stage = TUNE_MARGIN;
        return PDT_RUNNING;
    }
    return st;
}

/* One knob factor at a time, in bounded steps (one per scan): the rule's
 * gains with the knob scaled, checked on the model (Ms <= ms_max, stable)
 * and against the evidence (robust bound <= ms_robust). */
static pdt_status_t scan_tune(pdt_autotune_t *at, pdt_real_t *u)
{
    *u = at->u_hold;
    const pdt_tune_config_t *tc = &at->cfg.tune;
    if (at->tune_try == 0u && at->tune_stage == TUNE_BEGIN) {
        const pdt_status_t sc = tune_checks(at, u);
        if (sc != PDT_OK) {
            return sc;
        }
    }
    const bool knob = tc->rule == PDT_TUNE_SIMC || tc->rule == PDT_TUNE_IMC;
    const pdt_tune_config_t c = tune_config(at);
    pdt_tune_result_t r;
    pdt_status_t st = tune_step(at, &c, &r);
    if (st == PDT_RUNNING) {
        return PDT_RUNNING;
    }
    const bool margin = at->tune_stage == TUNE_MARGIN;
    at->tune_stage = TUNE_BEGIN;
    if (st != PDT_OK && st != PDT_ERR_UNSTABLE && st != PDT_ERR_MS_LIMIT) {
        return fail(at, st, u);
    }
    pdt_real_t ms = PDT_R(0.0);
    bool fir = false;
    if (st == PDT_OK && margin) {
        if (pdt_validate_margin(&at->res.valid, dead_time_shift(at), &r.ideal, &ms, &fir) !=
            PDT_OK) {
            ms = (pdt_real_t)INFINITY;
        }
        if (!(ms <= at->cfg.ms_robust)) {
            st = fir ? PDT_ERR_MODEL_INVALID : PDT_ERR_UNCERTAIN;
        }
    }
    if (st == PDT_OK && at->pid != NULL) {
        /* The hand-over: the new gains take the last output as theirs. */
        pdt_status_t sg = pdt_pid_set_gains(at->pid, &r.ideal, PDT_PID_IDEAL);
        if (sg != PDT_OK) {
            return fail(at, sg, u);
        }
    }
    if (st == PDT_OK) {
        at->res.tune = r;
        at->res.ms_robust = ms;
        at->res.detune = c.detune;
        at->res.has_gains = true;
        at->res.status = PDT_OK;
        at->phase = PDT_AUTOTUNE_DONE;
        return PDT_OK;
    }
    at->tune_why = st;
    at->tune_try++;
    /* Without a knob (AMIGO, ZN) there is nothing to scale. */
    if (!knob || at->tune_try >= DETUNE_STEPS) {
        return fail(at, st, u);
    }
    return PDT_RUNNING;
}

/* One scan of the phase the autotune is in. */
static pdt_status_t scan_phase(pdt_autotune_t *at, pdt_real_t pv, pdt_real_t *u)
{
    switch (at->phase) {
    case PDT_AUTOTUNE_SETTLE:
    case PDT_AUTOTUNE_EXCITE:
        at->res.scans++;
        return scan_experiment(at, pv, u);
    case PDT_AUTOTUNE_IDENTIFY:
    case PDT_AUTOTUNE_TUNE: {
        /* The process is still watched while the output rests at u0. */
        pdt_status_t sp = check_pv(at, pv);
        at->res.scans++;
        if (sp != PDT_OK) {
            return fail(at, sp, u);
        }
        return at->phase == PDT_AUTOTUNE_IDENTIFY ? scan_identify(at, u) : scan_tune(at, u);
    }
    case PDT_AUTOTUNE_DONE:
        *u = at->u_hold;
        return PDT_OK;
    case PDT_AUTOTUNE_FAILED:
    default:
        *u = at->u_hold;
        return at->res.status;
    }
}

static pdt_status_t scan_common(pdt_autotune_t *at, pdt_real_t pv, pdt_real_t *u);

pdt_status_t pdt_autotune_scan(pdt_autotune_t *at, pdt_real_t pv, pdt_real_t *u)
{
    if (at == NULL || u == NULL) {
        return PDT_ERR_ARG;
    }
    if (at->magic != AUTOTUNE_MAGIC) {
        return PDT_ERR_STATE;
    }
    at->pid_ran = false;
    at->u_pos = at->u_last;
    return scan_common(at, pv, u);
}

pdt_status_t pdt_autotune_scan_position(pdt_autotune_t *at, pdt_real_t pv, pdt_real_t u_pos,
                                        pdt_real_t *u)
{
    if (at == NULL || u == NULL) {
        return PDT_ERR_ARG;
    }
    if (at->magic != AUTOTUNE_MAGIC) {
        return PDT_ERR_STATE;
    }
    at->pid_ran = false;
    at->u_pos = u_pos;
    return scan_common(at, pv, u);
}

/* The scan after its checks: the phase's work, then the output. */
static pdt_status_t scan_common(pdt_autotune_t *at, pdt_real_t pv, pdt_real_t *u)
{
    pdt_status_t st = scan_phase(at, pv, u);
    if (at->pid != NULL) {
        /* Closed loop: outside the experiment the PID runs at the set-point
         * in service (with the new gains once handed over); a scan it
         * refuses (pv not finite) holds its last output. */
        if (!at->pid_ran) {
            pdt_real_t uc;
            (void)pdt_pid_update(at->pid, at->sp0, pv, &uc);
        }
        *u = at->pid->u;
    }
    at->u_last = *u;
    return st;
}

pdt_status_t pdt_autotune_abort(pdt_autotune_t *at, pdt_real_t *u)
{
    if (at == NULL || u == NULL) {
        return PDT_ERR_ARG;
    }
    if (at->magic != AUTOTUNE_MAGIC) {
        return PDT_ERR_STATE;
    }
    if (at->phase == PDT_AUTOTUNE_SETTLE || at->phase == PDT_AUTOTUNE_EXCITE) {
        pdt_record_result_t rr;
        (void)pdt_record_result(&at->rec, &rr);
        /* Before the operating point is known, the output at init is it. */
        at->u_hold = rr.settled ? rr.u0 : at->u_init;
    }
    if (at->phase != PDT_AUTOTUNE_DONE && at->phase != PDT_AUTOTUNE_FAILED) {
        (void)fail(at, PDT_ERR_ABORTED, u);
    }
    *u = at->pid != NULL ? at->pid->u : at->u_hold;
    return PDT_OK;
}

pdt_autotune_phase_t pdt_autotune_phase(const pdt_autotune_t *at)
{
    if (at == NULL || at->magic != AUTOTUNE_MAGIC) {
        return (pdt_autotune_phase_t)0;
    }
    return at->phase;
}

pdt_status_t pdt_autotune_result(const pdt_autotune_t *at, pdt_autotune_result_t *out)
{
    if (at == NULL || out == NULL) {
        return PDT_ERR_ARG;
    }
    if (at->magic != AUTOTUNE_MAGIC) {
        return PDT_ERR_STATE;
    }
    /* Written in place (no error is possible from here): a copy on the
     * stack would double the frame. */
    *out = at->res;
    if (at->phase == PDT_AUTOTUNE_SETTLE || at->phase == PDT_AUTOTUNE_EXCITE) {
        pdt_record_result_t rr;
        (void)pdt_record_result(&at->rec, &rr);
        out->samples = rr.n;
    }
    return PDT_OK;
}
