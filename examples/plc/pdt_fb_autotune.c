/*
 * pdt_fb_autotune: the PLC function block over pdt_autotune and pdt_pid.
 * This file only maps the block's inputs to the autotune's and the PID's
 * configs, keeps the PLCopen edge and handshake rules, copies the result to
 * the outputs, and switches the PID between tracking and automatic.
 */
#include "pdt_fb_autotune.h"

#include <math.h>

#include "pdt/pdt_model.h"

#define FB_R(x) ((pdt_real_t)(x))

/* Library defaults the zero parameters stand for. */
#define FB_SETTLE_DEFAULT 20u
#define FB_EVALS_DEFAULT  4u

static bool real_ok(pdt_real_t x)
{
    return isfinite(x) != 0;
}

/* Copies src into the status text, truncated to fit; always terminated. */
static void text_set(char *dst, const char *prefix, const char *src)
{
    size_t i = 0u;
    while (prefix != NULL && *prefix != '\0' && i + 1u < PDT_FB_AUTOTUNE_STATUS_LEN) {
        dst[i++] = *prefix++;
    }
    while (src != NULL && *src != '\0' && i + 1u < PDT_FB_AUTOTUNE_STATUS_LEN) {
        dst[i++] = *src++;
    }
    while (i < PDT_FB_AUTOTUNE_STATUS_LEN) {
        dst[i++] = '\0';
    }
}

static const char *phase_text(pdt_autotune_phase_t ph)
{
    switch (ph) {
    case PDT_AUTOTUNE_SETTLE:
        return "settling";
    case PDT_AUTOTUNE_EXCITE:
        return "experiment";
    case PDT_AUTOTUNE_IDENTIFY:
        return "identifying";
    case PDT_AUTOTUNE_TUNE:
        return "tuning";
    case PDT_AUTOTUNE_DONE:
        return "done";
    case PDT_AUTOTUNE_FAILED:
    default:
        return "failed";
    }
}

/* Seconds to whole scans, rounded; false when out of range. */
static bool seconds_to_scans(pdt_real_t t, pdt_real_t Ts, uint32_t *scans)
{
    pdt_real_t n = t / Ts + FB_R(0.5);
    if (!real_ok(n) || n < FB_R(0.0) || n >= FB_R(4.0e9)) {
        return false;
    }
    *scans = (uint32_t)n;
    return true;
}

/* The parameters the autotune cannot check before the experiment (the tune
 * config is only used at the end), the ones this block converts, and the
 * record length against the instance's capacity. */
static pdt_status_t check_params(const pdt_fb_autotune_t *fb)
{
    if (!real_ok(fb->rScanPeriod) || !(fb->rScanPeriod > FB_R(0.0))) {
        return PDT_ERR_ARG;
    }
    if (fb->iRule < (int16_t)PDT_TUNE_SIMC || fb->iRule > (int16_t)PDT_TUNE_ZN ||
        fb->iForm < (int16_t)PDT_TUNE_PI || fb->iForm > (int16_t)PDT_TUNE_PID) {
        return PDT_ERR_ARG;
    }
    if (!real_ok(fb->rFitMin) || !real_ok(fb->rMsMax) ||
        (fb->rMsMax != FB_R(0.0) && !(fb->rMsMax > FB_R(1.0)))) {
        return PDT_ERR_ARG;
    }
    if (!real_ok(fb->rExciteTime) || fb->rExciteTime < FB_R(0.0) || !real_ok(fb->rTimeLimit) ||
        fb->rTimeLimit < FB_R(0.0) || !real_ok(fb->rFrequency) || fb->rFrequency < FB_R(0.0)) {
        return PDT_ERR_ARG;
    }
    /* The instance's workspace may hold a little more for some configs;
     * the documented capacity is the promise, so it is the limit. */
    if (fb->udiSamples > PDT_FB_AUTOTUNE_CAPACITY) {
        return PDT_ERR_NOMEM;
    }
    uint32_t n;
    if (!seconds_to_scans(fb->rTimeLimit, fb->rScanPeriod, &n) ||
        !seconds_to_scans(fb->rExciteTime, fb->rScanPeriod, &n)) {
        return PDT_ERR_ARG;
    }
    return PDT_OK;
}

/* The autotune's config from the parameters (checked by check_params). */
static void make_config(const pdt_fb_autotune_t *fb, pdt_autotune_config_t *c)
{
    pdt_autotune_config_default(c);
    c->Ts = fb->rScanPeriod;
    c->decimation = fb->udiDecimation != 0u ? fb->udiDecimation : 1u;
    c->capacity = fb->udiSamples != 0u ? (size_t)fb->udiSamples : (size_t)PDT_FB_AUTOTUNE_CAPACITY;
    c->settle = fb->udiSettle != 0u ? fb->udiSettle : FB_SETTLE_DEFAULT;
    c->evals_per_scan = fb->udiEvalsPerScan != 0u ? fb->udiEvalsPerScan : FB_EVALS_DEFAULT;
    c->u_min = fb->rOutMin;
    c->u_max = fb->rOutMax;
    c->pv_min = fb->rPvMin;
    c->pv_max = fb->rPvMax;
    uint32_t scans = 0u;
    (void)seconds_to_scans(fb->rTimeLimit, fb->rScanPeriod, &scans);
    c->max_scans = scans;

    /* An unknown kind is kept: pdt_autotune_init refuses it. */
    pdt_excite_kind_t kind = (pdt_excite_kind_t)fb->iExperiment;
    pdt_excite_config_default(&c->excite, kind);
    pdt_excite_config_t *e = &c->excite;
    e->amplitude = fb->rAmplitude;
    switch (kind) {
    case PDT_EXCITE_STEP:
        e->duration = fb->rExciteTime;
        break;
    case PDT_EXCITE_PULSE:
        e->t_on = fb->rExciteTime;
        e->t_off = fb->rExciteTime;
        break;
    case PDT_EXCITE_CHIRP:
        e->duration = fb->rExciteTime;
        e->f1 = fb->rFrequency;
        break;
    case PDT_EXCITE_PRBS: {
        uint32_t hold = 0u;
        (void)seconds_to_scans(fb->rExciteTime, fb->rScanPeriod, &hold);
        e->prbs_hold = hold != 0u ? hold : 1u;
        break;
    }
    case PDT_EXCITE_RELAY:
        e->amplitude = FB_R(1.0);
        e->d = fb->rAmplitude;
        e->setpoint = fb->rSetpoint;
        e->eps = fb->rHysteresis;
        break;
    default:
        break;
    }
    /* 0 keeps the autotune's default (the data choose the order). An
     * unknown model makes the workspace query fail: init refuses it. */
    if (fb->iModel != PDT_FB_AUTOTUNE_MODEL_AUTO) {
        c->order_auto = false;
        c->ident.model = (pdt_model_kind_t)fb->iModel;
    }
    c->tune.rule = (pdt_tune_rule_t)fb->iRule;
    c->tune.form = (pdt_tune_form_t)fb->iForm;
    c->tune.fit_min = fb->rFitMin;
    c->tune.ms_max = fb->rMsMax;
}

/* The PID's configuration from the parameters; its gains are set apart. */
static void make_pid_config(const pdt_fb_autotune_t *fb, pdt_pid_config_t *c)
{
    pdt_pid_config_default(c);
    c->Ts = fb->rScanPeriod;
    c->u_min = fb->rOutMin;
    c->u_max = fb->rOutMax;
    c->b = fb->rSpWeightP;
    c->c = fb->rSpWeightD;
    c->rate_max = fb->rRateMax;
    c->Tt = fb->rTrackTime;
    /* An unknown value is kept: the PID refuses it. */
    c->antiwindup = (pdt_pid_antiwindup_t)fb->iAntiWindup;
}

/* The tuned gains into the PID, starting from the output in service u0:
 * the handover from the autotune without a bump. */
static void pid_load(pdt_fb_autotune_t *fb, const pdt_tune_gains_t *g, pdt_real_t u0)
{
    pdt_pid_config_t c;
    make_pid_config(fb, &c);
    pdt_status_t st = pdt_pid_init_from_gains(&fb->internal.pid, &c, g, PDT_PID_IDEAL, u0);
    fb->internal.xPidReady = st == PDT_OK;
    fb->iPidStatus = (int16_t)st;
}

/* An idle cycle with gains: automatic (update) or manual (track). */
static void pid_cycle(pdt_fb_autotune_t *fb, bool auto_edge)
{
    pdt_pid_t *pid = &fb->internal.pid;
    pdt_status_t st = PDT_OK;
    if (fb->xAuto && auto_edge) {
        /* Parameters changed while in manual apply now, bumplessly. */
        pdt_pid_config_t c;
        make_pid_config(fb, &c);
        c.form = pid->cfg.form;
        c.Kc = pid->cfg.Kc;
        c.Ti = pid->cfg.Ti;
        c.Td = pid->cfg.Td;
        c.Tf = pid->cfg.Tf;
        c.N = pid->cfg.N;
        st = pdt_pid_set_config(pid, &c);
        if (st != PDT_OK) {
            /* A bad parameter keeps the loop in manual; tried again next
             * cycle, so that fixing it starts automatic. */
            fb->internal.xAutoPrev = false;
        }
    }
    if (fb->xAuto && st == PDT_OK) {
        pdt_real_t u = fb->rOutput;
        st = pdt_pid_update(pid, fb->rSetpoint, fb->rPV, &u);
        fb->rOutput = u; /* held on an error */
        fb->xAutoActive = true;
        fb->xLimited = pid->limited && st == PDT_OK;
    } else {
        pdt_status_t track = pdt_pid_track(pid, fb->rSetpoint, fb->rPV, fb->rOutputNow);
        st = st != PDT_OK ? st : track;
        fb->xAutoActive = false;
        fb->xLimited = false;
    }
    fb->iPidStatus = (int16_t)st;
}

static void clear_results(pdt_fb_autotune_t *fb)
{
    fb->xModelValid = false;
    fb->xGainsValid = false;
    fb->xIntegrating = false;
    fb->rGain = FB_R(0.0);
    fb->rTau1 = FB_R(0.0);
    fb->rTau2 = FB_R(0.0);
    fb->rZeta = FB_R(0.0);
    fb->rDeadTime = FB_R(0.0);
    fb->rFit = FB_R(0.0);
    fb->rKc = FB_R(0.0);
    fb->rTi = FB_R(0.0);
    fb->rTd = FB_R(0.0);
    fb->rTf = FB_R(0.0);
    fb->rMs = FB_R(0.0);
}

/* The model in the terms a process engineer reads: gain, time constants,
 * dead time. Each conversion below exists exactly in the case it is used. */
static void copy_model(pdt_fb_autotune_t *fb, const pdt_ident_result_t *id)
{
    const pdt_model_t *m = &id->model;
    if (m->kind == PDT_MODEL_FOPDT) {
        fb->rGain = m->p.fopdt.K;
        fb->rTau1 = m->p.fopdt.tau;
        fb->rDeadTime = m->p.fopdt.Td;
    } else if (m->p.sopdt.b == FB_R(0.0)) {
        pdt_model_integ_t in;
        if (pdt_model_sopdt_to_integ(&m->p.sopdt, &in) != PDT_OK) {
            return;
        }
        fb->xIntegrating = true;
        fb->rGain = in.Ki;
        fb->rTau1 = in.T;
        fb->rDeadTime = in.Td;
    } else {
        pdt_model_natural_t nat;
        pdt_model_tc_t tc;
        if (pdt_model_sopdt_to_natural(&m->p.sopdt, &nat) != PDT_OK ||
            pdt_model_sopdt_to_tc(&m->p.sopdt, &tc) != PDT_OK) {
            return;
        }
        fb->rGain = nat.K;
        fb->rZeta = nat.zeta;
        if (tc.complex) {
            fb->rTau1 = FB_R(1.0) / nat.wn;
            fb->rTau2 = fb->rTau1;
        } else {
            fb->rTau1 = tc.T1;
            fb->rTau2 = tc.T2;
        }
        fb->rDeadTime = nat.Td;
    }
    fb->rFit = id->fit;
    fb->xModelValid = true;
}

static void copy_gains(pdt_fb_autotune_t *fb, const pdt_tune_result_t *t)
{
    fb->rKc = t->ideal.Kc;
    fb->rTi = t->ideal.tauI;
    fb->rTd = t->ideal.tauD;
    fb->rTf = t->ideal.Tf;
    fb->rMs = t->fig.Ms;
    fb->xGainsValid = true;
}

/* The command has ended with st: flags, outputs, text. */
static void finish(pdt_fb_autotune_t *fb, pdt_status_t st)
{
    pdt_autotune_result_t r;
    if (pdt_autotune_result(&fb->internal.at, &r) == PDT_OK) {
        if (r.has_model) {
            copy_model(fb, &r.ident);
        }
        if (r.has_gains) {
            copy_gains(fb, &r.tune);
            if (st == PDT_OK) {
                pid_load(fb, &r.tune.ideal, fb->rOutput);
            }
        }
    }
    fb->xBusy = false;
    fb->iPhase = (int16_t)pdt_autotune_phase(&fb->internal.at);
    if (st == PDT_OK) {
        fb->xDone = true;
        text_set(fb->sStatus, NULL, "done");
    } else if (st == PDT_ERR_ABORTED) {
        fb->xCommandAborted = true;
        text_set(fb->sStatus, NULL, "aborted");
    } else {
        fb->xError = true;
        fb->iErrorID = (int16_t)st;
        text_set(fb->sStatus, "error: ", pdt_status_str(st));
    }
}

/* A rising edge of xExecute while idle. */
static void start(pdt_fb_autotune_t *fb)
{
    fb->xDone = false;
    fb->xError = false;
    fb->xCommandAborted = false;
    fb->iErrorID = 0;
    clear_results(fb);
    if (fb->xAbort) {
        /* The abort command is still held: no experiment may start. */
        fb->xCommandAborted = true;
        fb->iPhase = 0;
        text_set(fb->sStatus, NULL, "aborted");
        return;
    }
    pdt_status_t st = check_params(fb);
    if (st == PDT_OK) {
        pdt_autotune_config_t cfg;
        make_config(fb, &cfg);
        st = pdt_autotune_init(&fb->internal.at, &cfg, fb->rOutputNow, fb->internal.work,
                               sizeof fb->internal.work);
    }
    if (st != PDT_OK) {
        /* Refused before anything moved: the output stays in service. */
        fb->xError = true;
        fb->iErrorID = (int16_t)st;
        fb->iPhase = 0;
        fb->rOutput = fb->rOutputNow;
        text_set(fb->sStatus, "refused: ", pdt_status_str(st));
        return;
    }
    fb->internal.rStartOutput = fb->rOutputNow;
    fb->internal.self = fb;
    fb->xBusy = true;
    /* The autotune drives the output now; the PID waits for new gains. A
     * refused start above left a running PID in service. */
    fb->internal.xPidReady = false;
    fb->xAutoActive = false;
    fb->xLimited = false;
    fb->iPidStatus = 0;
}

void pdt_fb_autotune_init(pdt_fb_autotune_t *fb)
{
    if (fb == NULL) {
        return;
    }
    /* Byte by byte: a compound literal of the instance would need its size
     * in stack. */
    unsigned char *p = (unsigned char *)fb;
    for (size_t i = 0u; i < sizeof *fb; i++) {
        p[i] = 0u;
    }
    fb->rScanPeriod = FB_R(0.1);
    fb->udiDecimation = 1u;
    fb->iExperiment = (int16_t)PDT_EXCITE_STEP;
    fb->iModel = (int16_t)PDT_FB_AUTOTUNE_MODEL_AUTO;
    fb->rAmplitude = FB_R(5.0);
    fb->rOutMin = FB_R(0.0);
    fb->rOutMax = FB_R(100.0);
    fb->rPvMin = FB_R(-1.0e30);
    fb->rPvMax = FB_R(1.0e30);
    fb->iRule = (int16_t)PDT_TUNE_SIMC;
    fb->iForm = (int16_t)PDT_TUNE_PI;
    fb->rFitMin = FB_R(0.0);
    fb->rMsMax = FB_R(2.0);
    fb->rSpWeightP = FB_R(1.0);
    text_set(fb->sStatus, NULL, "idle");
}

pdt_status_t pdt_fb_autotune(pdt_fb_autotune_t *fb)
{
    if (fb == NULL) {
        return PDT_ERR_ARG;
    }
    pdt_fb_autotune_internal_t *in = &fb->internal;
    bool exec_edge = fb->xExecute && !in->xExecutePrev;
    bool abort_edge = fb->xAbort && !in->xAbortPrev;
    bool auto_edge = fb->xAuto && !in->xAutoPrev;
    in->xExecutePrev = fb->xExecute;
    in->xAbortPrev = fb->xAbort;
    in->xAutoPrev = fb->xAuto;

    /* PLCopen: the end flags follow xExecute; set below in the cycle a
     * command ends, they are seen for this one cycle at least. */
    if (!fb->xExecute) {
        fb->xDone = false;
        fb->xError = false;
        fb->xCommandAborted = false;
        fb->iErrorID = 0;
    }

    if (!fb->xBusy) {
        if (exec_edge) {
            start(fb);
        }
        if (!fb->xBusy) {
            if (fb->iPhase == 0) {
                /* Never started, or refused: nothing to hold. */
                fb->rOutput = fb->rOutputNow;
            }
            if (in->xPidReady) {
                pid_cycle(fb, auto_edge);
            }
            return PDT_OK;
        }
    } else if (in->self != (const void *)fb) {
        /* Moved while busy: the autotune's pointers lead to the old copy,
         * so it must not run again. The output at the start is safe. */
        fb->rOutput = in->rStartOutput;
        fb->xBusy = false;
        fb->xError = true;
        fb->iErrorID = (int16_t)PDT_ERR_STATE;
        fb->iPhase = (int16_t)PDT_AUTOTUNE_FAILED;
        text_set(fb->sStatus, NULL, "error: instance moved");
        return PDT_OK;
    } else if (abort_edge) {
        pdt_real_t u;
        if (pdt_autotune_abort(&in->at, &u) == PDT_OK) {
            fb->rOutput = u;
        }
        finish(fb, PDT_ERR_ABORTED);
        return PDT_OK;
    }

    pdt_real_t u = fb->rOutput;
    pdt_status_t st = pdt_autotune_scan(&in->at, fb->rPV, &u);
    fb->rOutput = u;
    if (st == PDT_RUNNING) {
        pdt_autotune_phase_t ph = pdt_autotune_phase(&in->at);
        fb->iPhase = (int16_t)ph;
        text_set(fb->sStatus, NULL, phase_text(ph));
    } else {
        finish(fb, st);
    }
    return PDT_OK;
}

/* Alignment of the instance, without C11's _Alignof. */
struct fb_align_probe {
    char c;
    pdt_fb_autotune_t fb;
};

static pdt_fb_autotune_t *ext_block(void *block, uint32_t size)
{
    if (block == NULL || (size_t)size != sizeof(pdt_fb_autotune_t) ||
        (uintptr_t)block % offsetof(struct fb_align_probe, fb) != 0u) {
        return NULL;
    }
    return (pdt_fb_autotune_t *)block;
}

pdt_status_t pdt_fb_autotune_ext_init(void *block, uint32_t size)
{
    pdt_fb_autotune_t *fb = ext_block(block, size);
    if (fb == NULL) {
        return PDT_ERR_ARG;
    }
    pdt_fb_autotune_init(fb);
    return PDT_OK;
}

pdt_status_t pdt_fb_autotune_ext_cycle(void *block, uint32_t size)
{
    return pdt_fb_autotune(ext_block(block, size));
}
