/*
 * The C side of the Python package pdtfit: flat entry points over the
 * library for ctypes (doubles in, JSON text and doubles out), so that the
 * Python code never mirrors a library struct and the library stays the
 * only implementation of the numerics.
 *
 * A model crosses the boundary as five doubles: kind (1 FOPDT, 2 SOPDT)
 * and the fields of pdt_model_fopdt_t (K, tau, Td) or pdt_model_sopdt_t
 * (k, a, b, Td) in the real type's precision.
 *
 * The CSV reader and every JSON text are the command line's shared layer
 * (tools/cli/csv.h, json.h), compiled into the same shared object.
 *
 * Host code: it allocates and uses stdio, unlike the library.
 */
#include "pdtpy.h"

#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "csv.h"
#include "json.h"
#include "model_record.h"
#include "pdt/pdt.h"
#include "pdt/pdt_ident.h"
#include "pdt/pdt_ls.h"
#include "pdt/pdt_reduce.h"

#if PDT_IDENT_MAX_RECORDS < 2
#error "pdtfit.identify_many fits several records: build with PDT_IDENT_MAX_RECORDS 2 .. 8"
#endif

/* The JSON texts are the command line's (tools/cli/json.h), so that a
 * result's as_dict() equals the program's output. */

/* ------------------------------------------------------------ models */

static void model_out(const pdt_model_t *m, double *out)
{
    out[0] = (double)m->kind;
    if (m->kind == PDT_MODEL_FOPDT) {
        out[1] = (double)m->p.fopdt.K;
        out[2] = (double)m->p.fopdt.tau;
        out[3] = (double)m->p.fopdt.Td;
        out[4] = 0.0;
    } else {
        out[1] = (double)m->p.sopdt.k;
        out[2] = (double)m->p.sopdt.a;
        out[3] = (double)m->p.sopdt.b;
        out[4] = (double)m->p.sopdt.Td;
    }
}

static pdt_status_t model_in(const double *in, pdt_model_t *m)
{
    memset(m, 0, sizeof *m);
    if (in[0] == (double)PDT_MODEL_FOPDT) {
        m->kind = PDT_MODEL_FOPDT;
        m->p.fopdt.K = (pdt_real_t)in[1];
        m->p.fopdt.tau = (pdt_real_t)in[2];
        m->p.fopdt.Td = (pdt_real_t)in[3];
    } else if (in[0] == (double)PDT_MODEL_SOPDT) {
        m->kind = PDT_MODEL_SOPDT;
        m->p.sopdt.k = (pdt_real_t)in[1];
        m->p.sopdt.a = (pdt_real_t)in[2];
        m->p.sopdt.b = (pdt_real_t)in[3];
        m->p.sopdt.Td = (pdt_real_t)in[4];
    } else {
        return PDT_ERR_ARG;
    }
    return pdt_model_check(m);
}

int pdtpy_model_make(int kind, int form, double K, double x1, double x2, double Td, double *out)
{
    pdt_model_t m;
    memset(&m, 0, sizeof m);
    pdt_status_t st;
    if (kind == PDT_MODEL_FOPDT) {
        m.kind = PDT_MODEL_FOPDT;
        m.p.fopdt.K = (pdt_real_t)K;
        m.p.fopdt.tau = (pdt_real_t)x1;
        m.p.fopdt.Td = (pdt_real_t)Td;
        st = PDT_OK;
    } else if (kind == PDT_MODEL_SOPDT && form == PDTPY_SOPDT_NATURAL) {
        m.kind = PDT_MODEL_SOPDT;
        const pdt_model_natural_t nat = {(pdt_real_t)K, (pdt_real_t)x1, (pdt_real_t)x2,
                                         (pdt_real_t)Td};
        st = pdt_model_sopdt_from_natural(&nat, &m.p.sopdt);
    } else if (kind == PDT_MODEL_SOPDT && form == PDTPY_SOPDT_TC) {
        m.kind = PDT_MODEL_SOPDT;
        const pdt_model_tc_t tc = {(pdt_real_t)K, (pdt_real_t)x1, (pdt_real_t)x2, false,
                                   (pdt_real_t)Td};
        st = pdt_model_sopdt_from_tc(&tc, &m.p.sopdt);
    } else if (kind == PDT_MODEL_SOPDT && form == PDTPY_SOPDT_INTEG) {
        m.kind = PDT_MODEL_SOPDT;
        const pdt_model_integ_t in = {(pdt_real_t)K, (pdt_real_t)x1, (pdt_real_t)Td};
        st = pdt_model_sopdt_from_integ(&in, &m.p.sopdt);
    } else {
        st = PDT_ERR_ARG;
    }
    if (st == PDT_OK) st = pdt_model_check(&m);
    if (st == PDT_OK) model_out(&m, out);
    return st;
}

int pdtpy_model_json(const double *model, char *buf, size_t len)
{
    pdt_model_t m;
    if (model_in(model, &m) != PDT_OK) return -1;
    return pdtcli_model_json(&m, buf, len);
}

/* ------------------------------------------------------------ identify */

int pdtpy_real_size(void)
{
    return (int)sizeof(pdt_real_t);
}

static pdt_real_t *to_real(const double *x, size_t n)
{
    pdt_real_t *r = malloc((n ? n : 1) * sizeof *r);
    if (r)
        for (size_t k = 0; k < n; k++) r[k] = (pdt_real_t)x[k];
    return r;
}

/* method ELMS or E-IV-LMS: the least-squares delay scan, reported as
 * `pdtfit identify --method elms|eiv` reports it. */
static int identify_ls(const pdt_real_t *u, const pdt_real_t *y, size_t n, double Ts,
                       const pdtpy_ident_opts_t *o, pdt_ident_result_t *res)
{
    pdt_ls_config_t cfg;
    pdt_ls_config_default(&cfg);
    cfg.model = (pdt_model_kind_t)o->model;
    cfg.method = o->method == PDTPY_METHOD_EIV ? PDT_LS_EIV : PDT_LS_ELMS;
    cfg.Ts = (pdt_real_t)Ts;
    if (!isnan(o->td_max)) {
        /* A bound at or past the record's end is the library's to refuse. */
        double l = floor(o->td_max / Ts + 1e-9);
        cfg.delay_max = l < (double)n ? (size_t)l : n;
    }
    size_t delay_max = isnan(o->td_max) ? n / 4u : cfg.delay_max;
    pdt_ls_t *ctx = malloc(sizeof *ctx);
    if (!ctx) return PDTPY_ERR_NOMEM;
    pdt_ls_result_t r;
    pdt_status_t st = pdt_ls_identify(ctx, &cfg, u, y, n, &r);
    free(ctx);
    if (st != PDT_OK) return st;
    memset(res, 0, sizeof *res);
    res->model = r.model;
    res->u0 = r.u0;
    res->y0 = r.y0;
    res->cost = r.cost;
    res->fit = (pdt_real_t)NAN;
    (void)pdtcli_model_on_record(&r.model, Ts, u, y, n, r.u0, r.y0, NULL, &res->fit);
    res->evaluations = (uint32_t)(delay_max - cfg.delay_min + 1u);
    return PDT_OK;
}

static void ga_config(const pdtpy_ident_opts_t *o, double Ts, pdt_ident_config_t *cfg)
{
    pdt_ident_config_default(cfg);
    cfg->model = (pdt_model_kind_t)o->model;
    cfg->Ts = (pdt_real_t)Ts;
    cfg->cost = (pdt_cost_kind_t)o->cost;
    cfg->seed = o->seed;
    if (o->integer_delay) cfg->delay_mode = PDT_DELAY_INTEGER;
    if (o->evaluations) cfg->max_evaluations = o->evaluations;
    if (o->population) cfg->population = o->population;
    cfg->coarse = o->coarse;
    if (!isnan(o->td_max)) cfg->Td_max = (pdt_real_t)o->td_max;
    if (o->weight >= 0) cfg->weight = (pdt_ident_weight_t)o->weight;
    cfg->offset = (pdt_ident_offset_t)o->offset;
    cfg->f_lo = (pdt_real_t)o->f_lo;
    cfg->f_hi = (pdt_real_t)o->f_hi;
    if (!isnan(o->phi_t)) cfg->phi_t = (pdt_real_t)o->phi_t;
    if (!isnan(o->phi_f)) cfg->phi_f = (pdt_real_t)o->phi_f;
    cfg->u_before_given = !isnan(o->u_before);
    cfg->u_before = cfg->u_before_given ? (pdt_real_t)o->u_before : (pdt_real_t)0;
    cfg->refuse_missing = o->refuse_missing != 0;
    cfg->initial = (pdt_ident_initial_t)o->initial;
    cfg->drift = o->drift != 0;
}

/* pdt_identify of one model kind, as `pdtfit identify` runs it. */
static int ga_run(const pdt_real_t *u, const pdt_real_t *y, size_t n, double Ts,
                  const pdtpy_ident_opts_t *o, int kind, pdt_ident_result_t *res)
{
    pdt_ident_config_t cfg;
    ga_config(o, Ts, &cfg);
    cfg.model = (pdt_model_kind_t)kind;
    pdt_ident_t *ctx = malloc(sizeof *ctx);
    /* A size of 0 means the configuration is refused; pdt_identify then
     * says why, so it is still called. */
    size_t work_len = pdt_ident_workspace_size(&cfg, n);
    void *work = work_len ? malloc(work_len) : NULL;
    int st = PDTPY_ERR_NOMEM;
    if (ctx && (work || !work_len)) {
        const pdt_ident_data_t data = {u, y, n};
        st = pdt_identify(ctx, &cfg, &data, work, work_len, res);
    }
    free(work);
    free(ctx);
    return st;
}

/* --model auto: both models validated on the record and the order the
 * evidence supports (pdt_ident_select_order); *res the kept one. */
static int ga_auto(const pdt_real_t *u, const pdt_real_t *y, size_t n, double Ts,
                   const pdtpy_ident_opts_t *o, pdt_ident_result_t r[2], pdt_validate_result_t v[2],
                   pdt_model_kind_t *kept)
{
    const pdt_ident_data_t data = {u, y, n};
    const size_t wlen = pdt_validate_workspace_size(n);
    int st = ga_run(u, y, n, Ts, o, PDT_MODEL_FOPDT, &r[0]);
    if (st == PDT_OK) st = ga_run(u, y, n, Ts, o, PDT_MODEL_SOPDT, &r[1]);
    void *work = st == PDT_OK && wlen ? malloc(wlen) : NULL;
    if (st == PDT_OK && !work) st = PDTPY_ERR_NOMEM;
    for (int k = 0; k < 2 && st == PDT_OK; k++)
        st = pdt_validate_model(&r[k].model, &data, (pdt_real_t)Ts, r[k].y0, work, wlen, &v[k]);
    free(work);
    return st == PDT_OK ? pdt_ident_select_order(&v[0], &v[1], kept) : st;
}

/* The bootstrap `pdtfit identify --uncertainty` would run, or NULL. */
static const pdtcli_boot_t *bootstrap(const pdt_real_t *u, const pdt_real_t *y, size_t n, double Ts,
                                      const pdtpy_ident_opts_t *o, const pdt_ident_result_t *r,
                                      pdtcli_boot_t *b)
{
    const int on = o->uncertainty == 2 || (o->uncertainty == 0 && r->model.kind == PDT_MODEL_SOPDT);
    if (o->method != PDTPY_METHOD_GA || !on) return NULL;
    pdt_ident_config_t cfg;
    ga_config(o, Ts, &cfg);
    cfg.model = r->model.kind;
    const unsigned runs = o->boot_runs ? o->boot_runs : PDTCLI_BOOT_RUNS;
    return pdtcli_bootstrap(&cfg, r, u, y, n, runs, b) == 0 ? b : NULL;
}

int pdtpy_identify(const double *u, const double *y, size_t n, double Ts,
                   const pdtpy_ident_opts_t *o, double *model, char *json, size_t json_len)
{
    pdt_real_t *ur = to_real(u, n), *yr = to_real(y, n);
    pdt_ident_result_t res, both[2];
    pdt_validate_result_t v[2];
    pdt_model_kind_t kept = PDT_MODEL_FOPDT;
    int st = PDTPY_ERR_NOMEM;
    const int autom = o->method == PDTPY_METHOD_GA && o->model == PDTPY_MODEL_AUTO;
    if (ur && yr && o->method != PDTPY_METHOD_GA)
        st = identify_ls(ur, yr, n, Ts, o, &res);
    else if (ur && yr && autom)
        st = ga_auto(ur, yr, n, Ts, o, both, v, &kept);
    else if (ur && yr)
        st = ga_run(ur, yr, n, Ts, o, o->model, &res);
    if (st == PDT_OK && autom) res = both[kept == PDT_MODEL_SOPDT];
    if (st == PDT_OK) {
        model_out(&res.model, model);
        pdtcli_boot_t boot;
        int len = pdtcli_ident_json_boot(&res, ur, yr, Ts, n,
                                         bootstrap(ur, yr, n, Ts, o, &res, &boot), json, json_len);
        if (len > 0 && autom) {
            /* In place of the closing brace, which comes back after it. */
            pdtcli_jbuf_t jb;
            pdtcli_jb_init(&jb, json + len - 1, json_len - (size_t)len + 1);
            pdtcli_jb_order(&jb, kept, both, v);
            pdtcli_jb_raw(&jb, "}");
            len = pdtcli_jb_done(&jb);
        }
        if (len < 0) st = PDTPY_ERR_NOMEM;
    }
    free(yr);
    free(ur);
    return st;
}

/* Several records of one process identified together (docs/several-records.md):
 * the JSON of `pdtfit identify FILE FILE ...` without the files' names. */
static int many_run(pdt_real_t *const *u, pdt_real_t *const *y, const size_t *n, const double *Ts,
                    size_t count, const pdtpy_ident_opts_t *o, double *model, char *json,
                    size_t json_len)
{
    pdt_ident_record_t more[PDT_IDENT_MAX_RECORDS - 1u];
    pdt_ident_config_t cfg;
    ga_config(o, Ts[0], &cfg);
    cfg.no_screen = true;
    for (size_t r = 1; r < count; r++)
        more[r - 1u] = (pdt_ident_record_t){u[r], y[r], n[r], (pdt_real_t)Ts[r], false, 0};
    cfg.more = more;
    cfg.more_count = (uint32_t)(count - 1u);
    pdt_ident_t *ctx = malloc(sizeof *ctx);
    const size_t work_len = pdt_ident_workspace_size(&cfg, n[0]);
    void *work = work_len ? malloc(work_len) : NULL;
    int st = PDTPY_ERR_NOMEM;
    pdt_ident_result_t res;
    if (ctx && (work || !work_len)) {
        const pdt_ident_data_t data = {u[0], y[0], n[0]};
        st = pdt_identify(ctx, &cfg, &data, work, work_len, &res);
    }
    if (st == PDT_OK) {
        model_out(&res.model, model);
        int len = pdtcli_ident_json_boot(&res, NULL, NULL, Ts[0], n[0], NULL, json, json_len);
        if (len > 0) {
            pdtcli_jbuf_t jb;
            pdtcli_jb_init(&jb, json + len - 1, json_len - (size_t)len + 1);
            st = pdtcli_jb_several(&jb, ctx, NULL, count);
            pdtcli_jb_raw(&jb, "}");
            len = pdtcli_jb_done(&jb);
        }
        if (len < 0) st = PDTPY_ERR_NOMEM;
    }
    free(work);
    free(ctx);
    return st;
}

int pdtpy_identify_many(const double *const *u, const double *const *y, const size_t *n,
                        const double *Ts, size_t count, const pdtpy_ident_opts_t *o, double *model,
                        char *json, size_t json_len)
{
    pdt_real_t *ur[PDT_IDENT_MAX_RECORDS] = {NULL}, *yr[PDT_IDENT_MAX_RECORDS] = {NULL};
    int st = PDT_ERR_ARG;
    if (count >= 2u && count <= PDT_IDENT_MAX_RECORDS) {
        int ok = 1;
        for (size_t r = 0; r < count; r++) {
            ur[r] = to_real(u[r], n[r]);
            yr[r] = to_real(y[r], n[r]);
            ok = ok && ur[r] && yr[r];
        }
        st = ok ? many_run(ur, yr, n, Ts, count, o, model, json, json_len) : PDTPY_ERR_NOMEM;
    }
    for (size_t r = 0; r < PDT_IDENT_MAX_RECORDS; r++) {
        free(ur[r]);
        free(yr[r]);
    }
    return st;
}

size_t pdtpy_outlier(const double *x, size_t n)
{
    pdt_real_t *r = to_real(x, n);
    const size_t k = r ? pdt_cost_outlier(r, n) : n;
    free(r);
    return k;
}

int pdtpy_simulate(const double *model, double Ts, const double *u, const double *y, size_t n,
                   double u0, double y0, double *ysim)
{
    pdt_model_t m;
    pdt_status_t st = model_in(model, &m);
    if (st != PDT_OK) return st;
    pdt_real_t *ur = to_real(u, n), *yr = to_real(y, n), *ys = to_real(y, n);
    st = PDTPY_ERR_NOMEM;
    if (ur && yr && ys) {
        st = pdtcli_model_on_record(&m, Ts, ur, yr, n, (pdt_real_t)u0, (pdt_real_t)y0, ys, NULL);
        if (st == PDT_OK)
            for (size_t k = 0; k < n; k++) ysim[k] = (double)ys[k];
    }
    free(ys);
    free(yr);
    free(ur);
    return st;
}

static const char *const rule_names[] = {"simc", "imc", "amigo", "zn"};
static const char *const form_names[] = {"pi", "pid"};

/* zn from a relay's Ku and Pu (`pdtfit tune --Ku --Pu`); with a model, the
 * figures of those gains on it and the Ms limit. */
static pdt_status_t tune_relay(const pdt_model_t *m, const pdtpy_tune_opts_t *o,
                               const pdt_tune_config_t *cfg, pdt_tune_result_t *r)
{
    pdt_status_t st = pdt_tune_ziegler_nichols((pdt_real_t)o->Ku, (pdt_real_t)o->Pu,
                                               (pdt_tune_form_t)o->form, &r->ideal);
    if (st != PDT_OK) return st;
    r->series_exists = pdt_tune_to_series(&r->ideal, &r->series) == PDT_OK;
    if (!m) return PDT_OK;
    st = pdt_tune_robustness(m, &r->ideal, &r->fig);
    if (st == PDT_OK && cfg->ms_max > 0 && r->fig.Ms > cfg->ms_max) st = PDT_ERR_MS_LIMIT;
    return st;
}

int pdtpy_tune(const double *model, const pdtpy_tune_opts_t *o, double *ms_refused, char *json,
               size_t json_len)
{
    pdt_model_t m;
    pdt_status_t st = model ? model_in(model, &m) : PDT_OK;
    if (st != PDT_OK) return st;
    if (o->rule < 0 || o->rule > 3 || o->form < 0 || o->form > 1) return PDT_ERR_ARG;
    const int relay = !isnan(o->Ku);
    if (!model && !relay) return PDT_ERR_ARG;
    pdt_tune_config_t cfg;
    pdt_tune_config_default(&cfg);
    cfg.rule = (pdt_tune_rule_t)o->rule;
    cfg.form = (pdt_tune_form_t)o->form;
    if (!isnan(o->tau_c)) cfg.tau_c = (pdt_real_t)o->tau_c;
    if (!isnan(o->lambda)) cfg.lambda = (pdt_real_t)o->lambda;
    if (!isnan(o->ms_max)) cfg.ms_max = (pdt_real_t)o->ms_max;
    if (!isnan(o->deriv_filter)) cfg.deriv_filter = (pdt_real_t)o->deriv_filter;
    if (!isnan(o->fit_min)) cfg.fit_min = (pdt_real_t)o->fit_min;
    const pdt_real_t fit = (pdt_real_t)(isnan(o->fit) ? 100.0 : o->fit);
    pdt_tune_result_t r;
    memset(&r, 0, sizeof r);
    st = relay ? tune_relay(model ? &m : NULL, o, &cfg, &r) : pdt_tune_compute(&m, fit, &cfg, &r);
    if (st == PDT_ERR_MS_LIMIT) {
        /* The Ms the refused gains would have had, for the message. */
        pdt_tune_config_t open = cfg;
        open.ms_max = 0;
        pdt_tune_result_t r2;
        memset(&r2, 0, sizeof r2);
        *ms_refused = (relay ? tune_relay(&m, o, &open, &r2)
                             : pdt_tune_compute(&m, fit, &open, &r2)) == PDT_OK
                          ? (double)r2.fig.Ms
                          : (double)NAN;
    }
    if (st != PDT_OK) return st;
    pdtcli_jbuf_t jb;
    pdtcli_jb_init(&jb, json, json_len);
    pdtcli_jb_tune(&jb, rule_names[cfg.rule], form_names[cfg.form], cfg.rule == PDT_TUNE_SIMC,
                   cfg.rule == PDT_TUNE_IMC, &r, model ? &r.fig : NULL, o->span,
                   relay ? o->Ku : (double)NAN, relay ? o->Pu : (double)NAN);
    return pdtcli_jb_done(&jb) < 0 ? PDTPY_ERR_NOMEM : PDT_OK;
}

/* ------------------------------------------------------------ reduce */

int pdtpy_reduce(int method, int kind, double gain, const double *lags, size_t n_lags,
                 const double *zeros, size_t n_zeros, double delay, double h, double *model,
                 char *json, size_t json_len)
{
    pdt_real_t *l = to_real(lags, n_lags), *z = to_real(zeros, n_zeros);
    pdt_status_t st = PDTPY_ERR_NOMEM;
    if (l && z) {
        const pdt_reduce_plant_t plant = {(pdt_real_t)gain,   l,       n_lags,
                                          n_zeros ? z : NULL, n_zeros, (pdt_real_t)delay};
        pdt_reduce_config_t cfg;
        pdt_reduce_config_default(&cfg);
        cfg.model = (pdt_model_kind_t)kind;
        cfg.h = (pdt_real_t)h;
        pdt_model_t out;
        st = method == 0 ? pdt_reduce_half_rule(&plant, &cfg, &out, NULL)
                         : pdt_reduce_sung(&plant, &cfg, &out, NULL);
        if (st == PDT_OK) {
            model_out(&out, model);
            if (pdtcli_model_json(&out, json, json_len) < 0) st = PDTPY_ERR_NOMEM;
        }
    }
    free(z);
    free(l);
    return st;
}

/* ------------------------------------------------------------ CSV */

/* The command line's reader, with the binding's options (a field-for-field
 * mirror, so that Python needs no layout of pdtcli_csv_opts_t); the
 * largest cell accepted is the library real type's. */
int pdtpy_read_series(const char *path, const pdtpy_csv_opts_t *o, pdtpy_series_t *out, char *err,
                      size_t errlen)
{
    pdtcli_csv_opts_t co;
    pdtcli_series_t se;
    pdtcli_csv_opts_default(&co);
    co.t_col = o->t_col;
    co.u_col = o->u_col;
    co.y_col = o->y_col;
    co.sep = o->sep;
    co.decimal = o->decimal;
    co.skip = o->skip;
    co.time_unit = o->time_unit;
    co.resample = o->resample;
    co.fs = o->fs;
    co.units_row = o->units_row;
    co.time_format = o->time_format;
    co.bad_values = o->bad_values;
    co.n_bad_values = o->n_bad_values;
    co.bad_rows = o->bad_rows;
    co.max_abs = sizeof(pdt_real_t) == sizeof(float) ? (double)FLT_MAX : DBL_MAX;
    memset(out, 0, sizeof *out);
    if (pdtcli_csv_read_series(path, &co, &se, err, errlen) != 0) return -1;
    out->u = se.u;
    out->y = se.y;
    out->n = se.n;
    out->Ts = se.Ts;
    out->jitter_warn = se.jitter_warn;
    out->filled = se.filled;
    out->units_row = se.units_row;
    return 0;
}

void pdtpy_series_free(pdtpy_series_t *s)
{
    free(s->u);
    free(s->y);
    memset(s, 0, sizeof *s);
}

const char *pdtpy_status_str(int status)
{
    return pdt_status_str((pdt_status_t)status);
}

const char *pdtpy_status_name(int status)
{
    return pdt_status_name((pdt_status_t)status);
}
