/*
 * Several records of one process (pdt_ident_config_t.more,
 * docs/several-records.md): what the engine needs beyond one record. The
 * first record keeps the context's cost; each further one has its own
 * cost object and normalised copy in the workspace, prepared by init. An
 * evaluation of a shape is the joint profile over all of them
 * (pdt_cost_joint_profile); every stage of the engine reaches the cost
 * through pdt_ident_profile and pdt_ident_profile_many, which with one
 * record are the cost's own calls.
 */
#include "pdt/pdt_ident.h"

#include "pdt_cost_state.h"
#include "pdt_ident_priv.h"
#include "pdt_internal.h"

/* NO_RELATION's bounds, as the one record's (pdt_ident_vote.c). */
#define EVIDENCE_MIN ((pdt_real_t)PDT_IDENT_EVIDENCE_MIN)
#define FIT_FLOOR    ((pdt_real_t)PDT_IDENT_FIT_FLOOR)

bool pdt_ident_multi(const pdt_ident_config_t *cfg)
{
    return cfg->more_count != 0u;
}

pdt_status_t pdt_ident_multi_check(const pdt_ident_config_t *cfg)
{
    if (cfg->more_count == 0u) {
        return PDT_OK;
    }
    if (cfg->more == NULL || cfg->more_count > PDT_IDENT_MAX_RECORDS - 1u ||
        cfg->cost != PDT_COST_SIMULATION || cfg->delay_mode != PDT_DELAY_FRACTIONAL ||
        cfg->coarse > 1u || cfg->offset == PDT_IDENT_OFFSET_REST ||
        cfg->initial == PDT_IDENT_INITIAL_AUTO || !cfg->no_screen) {
        return PDT_ERR_ARG;
    }
    for (uint32_t r = 0u; r < cfg->more_count; r++) {
        const pdt_ident_record_t *rec = &cfg->more[r];
        if (rec->u == NULL || rec->y == NULL || !pdt_finite(rec->Ts) || !(rec->Ts > PDT_R(0.0)) ||
            (rec->u_before_given && !pdt_finite(rec->u_before))) {
            return PDT_ERR_ARG;
        }
    }
    return PDT_OK;
}

/* The cost object's size rounded up to whole reals, plus the padding
 * that aligns the array of them in the workspace. */
static size_t cost_slot(void)
{
    return (sizeof(pdt_cost_t) + sizeof(pdt_real_t) - 1u) / sizeof(pdt_real_t);
}

#define ALIGN_REALS ((sizeof(void *) + sizeof(pdt_real_t) - 1u) / sizeof(pdt_real_t) + 1u)

size_t pdt_ident_multi_longest(const pdt_ident_config_t *cfg, size_t n)
{
    size_t m = n;
    for (uint32_t r = 0u; r < cfg->more_count; r++) {
        m = cfg->more[r].n > m ? cfg->more[r].n : m;
    }
    return m;
}

size_t pdt_ident_multi_reals(const pdt_ident_config_t *cfg)
{
    if (cfg->more_count == 0u) {
        return 0u;
    }
    size_t total = ALIGN_REALS + (size_t)cfg->more_count * cost_slot();
    for (uint32_t r = 0u; r < cfg->more_count; r++) {
        /* The normalised copy of u and y: pdt_cost_workspace_size without
         * spectra. */
        total += 2u * cfg->more[r].n;
    }
    return total;
}

void pdt_ident_multi_span(const pdt_ident_config_t *cfg, size_t n, pdt_real_t *T, pdt_real_t *Ts)
{
    *T = cfg->Ts * (pdt_real_t)n;
    *Ts = cfg->Ts;
    for (uint32_t r = 0u; r < cfg->more_count; r++) {
        const pdt_ident_record_t *rec = &cfg->more[r];
        const pdt_real_t t = rec->Ts * (pdt_real_t)rec->n;
        *T = t < *T ? t : *T;
        *Ts = rec->Ts < *Ts ? rec->Ts : *Ts;
    }
}

/* A further record's checks: finite, excited, long enough for the
 * dead-time bound; its delay bound. */
static pdt_status_t check_more(const pdt_ident_record_t *rec, pdt_real_t Td_max, size_t *delay_max)
{
    if (rec->n < (size_t)PDT_MIN_SAMPLES) {
        return PDT_ERR_TOO_SHORT;
    }
    pdt_real_t umin = rec->u[0], umax = rec->u[0], ymin = rec->y[0], ymax = rec->y[0];
    for (size_t k = 0u; k < rec->n; k++) {
        const pdt_real_t uk = rec->u[k], yk = rec->y[k];
        if (!pdt_finite(uk) || !pdt_finite(yk)) {
            return PDT_ERR_NONFINITE;
        }
        umin = uk < umin ? uk : umin;
        umax = uk > umax ? uk : umax;
        ymin = yk < ymin ? yk : ymin;
        ymax = yk > ymax ? yk : ymax;
    }
    const pdt_real_t ub = rec->u_before_given ? rec->u_before : rec->u[0];
    if (!(umax > umin || ub != rec->u[0]) || !(ymax > ymin)) {
        return PDT_ERR_NO_EXCITATION;
    }
    const pdt_real_t lmax = Td_max / rec->Ts;
    if (!(lmax < (pdt_real_t)rec->n)) {
        return PDT_ERR_TOO_SHORT;
    }
    *delay_max = (size_t)lmax + 1u;
    return PDT_OK;
}

pdt_status_t pdt_ident_multi_prepare(const pdt_ident_config_t *cfg, const pdt_cost_config_t *cc,
                                     pdt_real_t Td_max, void *work, size_t at, pdt_cost_t **costs)
{
    *costs = NULL;
    if (cfg->more_count == 0u) {
        return PDT_OK;
    }
    pdt_real_t *base = &((pdt_real_t *)work)[at];
    /* The cost objects' array aligned for a pointer, the largest member
     * alignment of pdt_cost_t on the targets the library builds for. */
    const uintptr_t a = (uintptr_t)sizeof(void *);
    const size_t pad = (size_t)((a - ((uintptr_t)base % a)) % a);
    pdt_cost_t *objs = (pdt_cost_t *)(void *)((uint8_t *)(void *)base + pad);
    pdt_real_t *copy = &base[ALIGN_REALS + (size_t)cfg->more_count * cost_slot()];
    for (uint32_t r = 0u; r < cfg->more_count; r++) {
        const pdt_ident_record_t *rec = &cfg->more[r];
        size_t delay_max = 0u;
        pdt_status_t st = check_more(rec, Td_max, &delay_max);
        if (st != PDT_OK) {
            return st;
        }
        pdt_cost_config_t rc = *cc;
        rc.Ts = rec->Ts;
        rc.u0 = rec->u_before_given ? rec->u_before : rec->u[0];
        rc.y0 = rec->y[0];
        rc.delay_max = delay_max;
        rc.use_frequency = false;
        const size_t bytes = 2u * rec->n * sizeof(pdt_real_t);
        st = pdt_cost_init(&objs[r], &rc, rec->u, rec->y, rec->n, copy, bytes);
        if (st != PDT_OK) {
            return st;
        }
        copy += 2u * rec->n;
    }
    *costs = objs;
    return PDT_OK;
}

#if PDT_IDENT_MAX_RECORDS > 1
/* The records' costs, the first's first. */
static size_t costs_of(const pdt_ident_t *c, const pdt_cost_t **costs)
{
    costs[0] = &c->cost;
    for (uint32_t r = 0u; r < c->cfg.more_count; r++) {
        costs[1u + r] = &c->more_cost[r];
    }
    return 1u + (size_t)c->cfg.more_count;
}
#endif

pdt_status_t pdt_ident_profile(pdt_ident_t *c, const pdt_model_t *shape, pdt_real_t glo,
                               pdt_real_t ghi, const pdt_cost_hint_t *hint, pdt_cost_profile_t *out)
{
#if PDT_IDENT_MAX_RECORDS > 1
    if (c->cfg.more_count != 0u) {
        const pdt_cost_t *costs[PDT_IDENT_MAX_RECORDS];
        const size_t count = costs_of(c, costs);
        return pdt_cost_joint_profile(costs, count, shape, glo, ghi, hint, c->scratch, out);
    }
#endif
    /* One record (with one allowed, pdt_ident_multi_check refuses more
     * and the joint fit is not linked). */
    return pdt_cost_profile_hint(&c->cost, shape, glo, ghi, hint, c->scratch, out);
}

pdt_status_t pdt_ident_profile_many(pdt_ident_t *c, const pdt_model_t *shapes, size_t count,
                                    const pdt_real_t *glo, const pdt_real_t *ghi,
                                    const pdt_cost_hint_t *hint, pdt_cost_profile_t *out)
{
    if (c->cfg.more_count == 0u) {
        return pdt_cost_profile_many(&c->cost, shapes, count, glo, ghi, hint, c->scratch, out);
    }
    if (count == 0u || count > PDT_COST_MANY) {
        return PDT_ERR_ARG;
    }
    /* Each shape on its own; the caller scores each alone again where one
     * is refused, so out may hold the ones before it. */
    for (size_t i = 0u; i < count; i++) {
        const pdt_status_t st = pdt_ident_profile(c, &shapes[i], glo[i], ghi[i], hint, &out[i]);
        if (st != PDT_OK) {
            return st;
        }
    }
    return PDT_OK;
}

/* Record r's cost (0 the first). */
static const pdt_cost_t *cost_of(const pdt_ident_t *c, uint32_t r)
{
    return (r == 0u) ? &c->cost : &c->more_cost[r - 1u];
}

void pdt_ident_multi_finish(pdt_ident_t *c, const pdt_model_t *m)
{
    pdt_real_t ss = PDT_R(0.0), sst = PDT_R(0.0);
    c->fit = PDT_R(0.0);
    for (uint32_t i = 0u; i < 4u; i++) {
        c->extra[i] = PDT_R(0.0);
    }
    for (uint32_t r = 0u; r <= c->cfg.more_count; r++) {
        const pdt_cost_t *cr = cost_of(c, r);
        pdt_cost_extra_t x;
        pdt_real_t v;
        if (pdt_cost_joint_terms(cr, m, c->scratch, &x, &v) != PDT_OK) {
            return;
        }
        ss += x.ncost * (pdt_real_t)cr->n;
        sst += v;
        if (r == 0u) {
            c->extra[0] = x.state[0];
            c->extra[1] = x.state[1];
            c->extra[2] = x.drift;
            c->y0 = cr->cfg.y0 + x.offset;
        }
    }
    c->extra[3] = ss;
    if (sst > PDT_R(0.0) && pdt_finite(ss)) {
        c->fit = PDT_R(100.0) * (PDT_R(1.0) - pdt_sqrt(ss / sst));
        c->fit = pdt_finite(c->fit) ? c->fit : PDT_R(0.0);
    }
}

void pdt_ident_multi_std(pdt_ident_t *c)
{
    /* The joint uncertainty is not computed (docs/several-records.md):
     * count 0. The evidence is the joint likelihood ratio against each
     * record's own mean, without the one record's correlation
     * inflation. */
    pdt_real_t N = PDT_R(0.0), sst = PDT_R(0.0);
    c->std = (pdt_ident_std_t){0};
    for (uint32_t r = 0u; r <= c->cfg.more_count; r++) {
        const pdt_cost_t *cr = cost_of(c, r);
        pdt_cost_extra_t x;
        pdt_real_t v;
        N += (pdt_real_t)cr->n;
        if (pdt_cost_joint_terms(cr, &c->model, c->scratch, &x, &v) == PDT_OK) {
            sst += v;
        }
    }
    c->evidence = PDT_R(0.0);
    if (c->extra[3] > PDT_R(0.0) && sst > PDT_R(0.0)) {
        c->evidence = N * (pdt_log(sst) - pdt_log(c->extra[3]));
    }
    if (!(c->evidence >= EVIDENCE_MIN) || !(c->fit >= FIT_FLOOR)) {
        c->flags |= PDT_IDENT_FLAG_NO_RELATION;
    }
}

pdt_status_t pdt_ident_multi_record(pdt_ident_t *ctx, const pdt_ident_result_t *res, uint32_t r,
                                    pdt_ident_record_fit_t *out)
{
    if (r > ctx->cfg.more_count) {
        return PDT_ERR_ARG;
    }
    const pdt_cost_t *cr = cost_of(ctx, r);
    pdt_cost_extra_t x;
    pdt_real_t sst;
    pdt_ident_record_fit_t f;
    f.n = cr->n;
    f.Ts = cr->cfg.Ts;
    f.u0 = cr->cfg.u0;
    f.fit = PDT_R(0.0);
    if (ctx->cfg.more_count == 0u && !pdt_cost_extra_on(cr)) {
        /* One record from rest: the result's offset, its fit. */
        f.y0 = res->y0;
        f.x0 = PDT_R(0.0);
        f.dx0 = PDT_R(0.0);
        f.drift = PDT_R(0.0);
        f.cost = res->cost;
        f.fit = res->fit;
        *out = f;
        return PDT_OK;
    }
    if (pdt_cost_joint_terms(cr, &res->model, ctx->scratch, &x, &sst) != PDT_OK) {
        return PDT_ERR_NONFINITE;
    }
    f.y0 = cr->cfg.y0 + x.offset;
    f.x0 = x.state[0];
    f.dx0 = x.state[1];
    f.drift = x.drift;
    f.cost = x.ncost;
    if (sst > PDT_R(0.0)) {
        f.fit = PDT_R(100.0) * (PDT_R(1.0) - pdt_sqrt(x.ncost * (pdt_real_t)cr->n / sst));
        f.fit = pdt_finite(f.fit) ? f.fit : PDT_R(0.0);
    }
    *out = f;
    return PDT_OK;
}
