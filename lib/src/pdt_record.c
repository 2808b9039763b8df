/*
 * pdtfit experiment recorder (pdt_record.h); the experiments and their
 * safety limits are described in docs/experiments.md.
 */
#include "pdt/pdt_record.h"

#include "pdt_internal.h"

#define RECORD_MAGIC PDT_MAGIC('P', 'D', 'R', 'C')

void pdt_record_config_default(pdt_record_config_t *cfg)
{
    if (cfg == NULL) {
        return;
    }
    cfg->decimation = 1u;
    cfg->settle = 10u;
    cfg->settle_band = PDT_R(0.0);
    cfg->u_min = -PDT_REAL_MAX;
    cfg->u_max = PDT_REAL_MAX;
    cfg->pv_min = -PDT_REAL_MAX;
    cfg->pv_max = PDT_REAL_MAX;
    cfg->max_scans = 0u;
    cfg->move = PDT_RECORD_MOVE_ANY;
    cfg->setpoint = PDT_R(0.0);
}

static bool overlap(const pdt_real_t *a, const pdt_real_t *b, size_t n)
{
    /* Compared as integers: relational operators on pointers into
     * different objects are undefined in C. */
    uintptr_t pa = (uintptr_t)a;
    uintptr_t pb = (uintptr_t)b;
    uintptr_t len = (uintptr_t)n * sizeof(pdt_real_t);
    return pa < pb + len && pb < pa + len;
}

pdt_status_t pdt_record_init(pdt_record_t *rec, const pdt_record_config_t *cfg, pdt_real_t *u,
                             pdt_real_t *y, size_t capacity)
{
    if (rec == NULL || cfg == NULL || u == NULL || y == NULL) {
        return PDT_ERR_ARG;
    }
    if ((capacity > 0u && capacity <= PDT_MAX_SAMPLES && overlap(u, y, capacity)) ||
        cfg->decimation == 0u || cfg->settle == 0u || !pdt_finite(cfg->u_min) ||
        !pdt_finite(cfg->u_max) || !pdt_finite(cfg->pv_min) || !pdt_finite(cfg->pv_max) ||
        !pdt_finite(cfg->settle_band) || cfg->settle_band < PDT_R(0.0)) {
        return PDT_ERR_ARG;
    }
    if (cfg->move != PDT_RECORD_MOVE_ANY && cfg->move != PDT_RECORD_MOVE_UP &&
        cfg->move != PDT_RECORD_MOVE_DOWN) {
        return PDT_ERR_ARG;
    }
    if (cfg->move != PDT_RECORD_MOVE_ANY && !pdt_finite(cfg->setpoint)) {
        return PDT_ERR_ARG;
    }
    if (cfg->u_min > cfg->u_max || cfg->pv_min > cfg->pv_max) {
        return PDT_ERR_BOUNDS;
    }
    if (capacity > PDT_MAX_SAMPLES) {
        return PDT_ERR_LENGTH;
    }
    if (capacity <= cfg->settle) {
        return PDT_ERR_TOO_SHORT;
    }
    pdt_record_t r;
    r.cfg = *cfg;
    r.u = u;
    r.y = y;
    r.capacity = capacity;
    r.magic = RECORD_MAGIC;
    r.status = PDT_RUNNING;
    r.n = 0u;
    r.settled = false;
    r.scans = 0u;
    r.pend = 0u;
    r.pend_u = PDT_R(0.0);
    r.pend_sum = PDT_R(0.0);
    r.win_min = PDT_R(0.0);
    r.win_max = PDT_R(0.0);
    r.sum_y = PDT_R(0.0);
    r.u0 = PDT_R(0.0);
    r.y0 = PDT_R(0.0);
    r.u_safe = PDT_R(0.0);
    *rec = r;
    return PDT_OK;
}

static pdt_status_t record_abort(pdt_record_t *rec, pdt_status_t why, pdt_real_t u_applied)
{
    if (rec->scans == 0u) {
        /* No operating point seen at all: the nearest output the limits
         * allow is the least surprising one. */
        const pdt_record_config_t *c = &rec->cfg;
        if (!(u_applied == u_applied)) {
            rec->u_safe = c->u_min;
        } else {
            rec->u_safe =
                u_applied < c->u_min ? c->u_min : (u_applied > c->u_max ? c->u_max : u_applied);
        }
    }
    rec->status = why;
    rec->pend = 0u;
    return why;
}

/* Stores a completed sample of the settle window, restarting the window
 * when the process value is not steady. */
static void settle_sample(pdt_record_t *rec, pdt_real_t us, pdt_real_t ys)
{
    const pdt_record_config_t *c = &rec->cfg;
    if (rec->n > 0u && c->settle_band > PDT_R(0.0)) {
        pdt_real_t hi = ys > rec->win_max ? ys : rec->win_max;
        pdt_real_t lo = ys < rec->win_min ? ys : rec->win_min;
        if (hi - lo > c->settle_band) {
            rec->n = 0u;
        }
    }
    if (rec->n == 0u) {
        rec->win_min = ys;
        rec->win_max = ys;
        rec->sum_y = PDT_R(0.0);
    } else {
        rec->win_min = ys < rec->win_min ? ys : rec->win_min;
        rec->win_max = ys > rec->win_max ? ys : rec->win_max;
    }
    rec->u[rec->n] = us;
    rec->y[rec->n] = ys;
    rec->n++;
    rec->sum_y += ys;
    /* A running mean, so that an output held constant comes back exactly
     * (a sum divided by the count can be 1 ulp off it). */
    rec->u0 = rec->n == 1u ? us : rec->u0 + (us - rec->u0) / (pdt_real_t)rec->n;
    rec->y0 = rec->sum_y / (pdt_real_t)rec->n;
    rec->u_safe = rec->u0;
    if (rec->n == c->settle) {
        rec->settled = true;
    }
}

pdt_status_t pdt_record_push(pdt_record_t *rec, pdt_real_t u_applied, pdt_real_t pv)
{
    if (rec == NULL) {
        return PDT_ERR_ARG;
    }
    if (rec->magic != RECORD_MAGIC) {
        return PDT_ERR_STATE;
    }
    if (rec->status != PDT_RUNNING) {
        return rec->status;
    }
    const pdt_record_config_t *c = &rec->cfg;
    if (c->max_scans != 0u && rec->scans >= c->max_scans) {
        return record_abort(rec, PDT_ERR_TIMEOUT, u_applied);
    }
    if (!pdt_finite(u_applied) || !pdt_finite(pv)) {
        return record_abort(rec, PDT_ERR_NONFINITE, u_applied);
    }
    if (u_applied < c->u_min || u_applied > c->u_max) {
        return record_abort(rec, PDT_ERR_OUTPUT_LIMIT, u_applied);
    }
    if (pv < c->pv_min || pv > c->pv_max) {
        return record_abort(rec, PDT_ERR_PV_LIMIT, u_applied);
    }

    if (rec->scans == 0u) {
        rec->u_safe = u_applied;
    }
    if (rec->scans != UINT32_MAX) {
        rec->scans++;
    }
    if (rec->pend == 0u) {
        rec->pend_u = u_applied;
        rec->pend_sum = PDT_R(0.0);
    }
    /* Both signals are averaged over the interval: an input that changes
     * inside it (a relay switching, a hold that is not a multiple of the
     * decimation) then keeps its area, where its first value would move
     * the change to the interval's start. */
    rec->pend++;
    rec->pend_u += (u_applied - rec->pend_u) / (pdt_real_t)rec->pend;
    rec->pend_sum += pv;
    if (rec->pend < c->decimation) {
        return PDT_RUNNING;
    }
    rec->pend = 0u;
    pdt_real_t ys = rec->pend_sum / (pdt_real_t)c->decimation;
    if (!rec->settled) {
        settle_sample(rec, rec->pend_u, ys);
        if (rec->settled && ((c->move == PDT_RECORD_MOVE_UP && !(c->setpoint > rec->y0)) ||
                             (c->move == PDT_RECORD_MOVE_DOWN && !(c->setpoint < rec->y0)))) {
            rec->status = PDT_ERR_SETPOINT;
            return PDT_ERR_SETPOINT;
        }
    } else {
        rec->u[rec->n] = rec->pend_u;
        rec->y[rec->n] = ys;
        rec->n++;
    }
    if (rec->n == rec->capacity) {
        rec->status = PDT_OK;
        return PDT_OK;
    }
    return PDT_RUNNING;
}

pdt_status_t pdt_record_stop(pdt_record_t *rec)
{
    if (rec == NULL) {
        return PDT_ERR_ARG;
    }
    if (rec->magic != RECORD_MAGIC) {
        return PDT_ERR_STATE;
    }
    if (rec->status != PDT_RUNNING) {
        return rec->status;
    }
    if (!rec->settled) {
        return PDT_ERR_STATE;
    }
    rec->pend = 0u;
    rec->status = PDT_OK;
    return PDT_OK;
}

pdt_status_t pdt_record_result(const pdt_record_t *rec, pdt_record_result_t *out)
{
    if (rec == NULL || out == NULL) {
        return PDT_ERR_ARG;
    }
    if (rec->magic != RECORD_MAGIC) {
        return PDT_ERR_STATE;
    }
    out->status = rec->status;
    out->n = rec->n;
    out->settled = rec->settled;
    out->u0 = rec->n > 0u ? rec->u0 : rec->u_safe;
    out->y0 = rec->y0;
    out->u_safe = rec->u_safe;
    out->scans = rec->scans;
    return PDT_OK;
}
