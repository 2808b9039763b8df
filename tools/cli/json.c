#include "json.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void pdtcli_jb_init(pdtcli_jbuf_t *jb, char *buf, size_t len)
{
    jb->buf = buf;
    jb->len = len;
    jb->used = 0;
    jb->over = len == 0;
    if (len) buf[0] = '\0';
}

void pdtcli_jb_printf(pdtcli_jbuf_t *jb, const char *fmt, ...)
{
    if (jb->over) return;
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(jb->buf + jb->used, jb->len - jb->used, fmt, ap);
    va_end(ap);
    if (n < 0 || (size_t)n >= jb->len - jb->used) {
        jb->over = 1;
        return;
    }
    jb->used += (size_t)n;
}

void pdtcli_jb_raw(pdtcli_jbuf_t *jb, const char *text)
{
    pdtcli_jb_printf(jb, "%s", text);
}

void pdtcli_jb_num(pdtcli_jbuf_t *jb, double v)
{
    if (isfinite(v))
        pdtcli_jb_printf(jb, "%.9g", v);
    else
        pdtcli_jb_raw(jb, "null");
}

void pdtcli_jb_key(pdtcli_jbuf_t *jb, const char *key, double v)
{
    pdtcli_jb_printf(jb, ",\"%s\":", key);
    pdtcli_jb_num(jb, v);
}

void pdtcli_jb_str(pdtcli_jbuf_t *jb, const char *key, const char *text)
{
    pdtcli_jb_printf(jb, ",\"%s\":\"%s\"", key, text);
}

void pdtcli_jb_uint(pdtcli_jbuf_t *jb, const char *key, unsigned long v)
{
    pdtcli_jb_printf(jb, ",\"%s\":%lu", key, v);
}

int pdtcli_jb_done(const pdtcli_jbuf_t *jb)
{
    return jb->over ? -1 : (int)jb->used;
}

static void operating_point(pdtcli_jbuf_t *jb, const pdt_ident_result_t *r)
{
    if (!r) return;
    pdtcli_jb_key(jb, "y0", (double)r->y0);
    pdtcli_jb_key(jb, "u0", (double)r->u0);
}

static void fopdt_keys(pdtcli_jbuf_t *jb, const pdt_model_fopdt_t *m, const pdt_ident_result_t *r)
{
    pdtcli_jb_raw(jb, "{\"model\":\"fopdt\"");
    pdtcli_jb_key(jb, "K", (double)m->K);
    pdtcli_jb_key(jb, "tau", (double)m->tau);
    pdtcli_jb_key(jb, "Td", (double)m->Td);
    operating_point(jb, r);
}

/* K, wn, zeta, Td, [y0, u0], tau1, tau2 of a SOPDT in whichever form it
 * has: natural, or integrating (K null, Ki after it, wn 0). */
static void sopdt_keys(pdtcli_jbuf_t *jb, const pdt_model_sopdt_t *m, const pdt_ident_result_t *r)
{
    pdt_model_natural_t nat;
    pdt_model_tc_t tc;
    pdt_model_integ_t integ;
    double K = (double)NAN, Ki = (double)NAN, wn = (double)NAN, zeta = (double)NAN;
    double tau1 = (double)NAN, tau2 = (double)NAN;
    int integrating = 0;
    if (pdt_model_sopdt_to_natural(m, &nat) == PDT_OK) {
        K = (double)nat.K;
        wn = (double)nat.wn;
        zeta = (double)nat.zeta;
        if (pdt_model_sopdt_to_tc(m, &tc) == PDT_OK && !tc.complex) {
            tau1 = (double)tc.T1;
            tau2 = (double)tc.T2;
        }
    } else if (pdt_model_sopdt_to_integ(m, &integ) == PDT_OK) {
        integrating = 1;
        Ki = (double)integ.Ki;
        wn = 0.0;
        tau2 = (double)integ.T;
    }
    pdtcli_jb_raw(jb, "{\"model\":\"sopdt\"");
    pdtcli_jb_key(jb, "K", K);
    if (integrating) pdtcli_jb_key(jb, "Ki", Ki);
    pdtcli_jb_key(jb, "wn", wn);
    pdtcli_jb_key(jb, "zeta", zeta);
    pdtcli_jb_key(jb, "Td", (double)m->Td);
    operating_point(jb, r);
    pdtcli_jb_key(jb, "tau1", tau1);
    pdtcli_jb_key(jb, "tau2", tau2);
    pdtcli_jb_key(jb, "a", (double)m->a);
    pdtcli_jb_key(jb, "b", (double)m->b);
}

/* How sure the search is (a GA result): its searches, the runner-up
 * basin's cost ratio and the flags by name (docs/ident-engine.md). */
static void certainty_keys(pdtcli_jbuf_t *jb, const pdt_ident_result_t *r)
{
    static const struct {
        uint32_t bit;
        const char *name;
    } flags[] = {{PDT_IDENT_FLAG_UNCONFIRMED, "unconfirmed"},
                 {PDT_IDENT_FLAG_AMBIGUOUS, "ambiguous"},
                 {PDT_IDENT_FLAG_AT_BOUND, "at_bound"},
                 {PDT_IDENT_FLAG_NO_RELATION, "no_relation"},
                 {PDT_IDENT_FLAG_MID_TRANSIENT, "mid_transient"}};
    pdtcli_jb_uint(jb, "searches", (unsigned long)r->searches);
    pdtcli_jb_uint(jb, "coarse", (unsigned long)r->coarse);
    pdtcli_jb_key(jb, "runner_up", (double)r->runner_up);
    pdtcli_jb_raw(jb, ",\"flags\":[");
    const char *sep = "";
    for (size_t i = 0; i < sizeof flags / sizeof flags[0]; i++) {
        if ((r->flags & flags[i].bit) == 0u) continue;
        pdtcli_jb_printf(jb, "%s\"%s\"", sep, flags[i].name);
        sep = ",";
    }
    pdtcli_jb_raw(jb, "]");
}

/* ,"excluded":{"count":N,"missing":M,"first":[...]}: the samples left out
 * of the fit (missing ones and gross errors), the first of them 0-based. */
static void excluded_keys(pdtcli_jbuf_t *jb, const pdt_ident_result_t *r)
{
    pdtcli_jb_printf(jb, ",\"excluded\":{\"count\":%lu,\"missing\":%lu,\"first\":[",
                     (unsigned long)r->excluded, (unsigned long)r->missing);
    const uint32_t listed =
        r->excluded < PDT_IDENT_EXCLUDED_LIST ? r->excluded : PDT_IDENT_EXCLUDED_LIST;
    for (uint32_t i = 0; i < listed; i++)
        pdtcli_jb_printf(jb, "%s%lu", i ? "," : "", (unsigned long)r->excluded_first[i]);
    pdtcli_jb_raw(jb, "]}");
}

/* ,"initial":"estimate" with the free response at the first sample "x0"
 * (and a SOPDT's slope "dx0", per second) where the state was estimated
 * (no key: the model starts at rest); ,"drift" (output units per second)
 * where one was fitted. The JSON of a record from rest keeps its keys. */
static void initial_keys(pdtcli_jbuf_t *jb, const pdt_model_t *m, const pdt_ident_result_t *r)
{
    if (r->initial == PDT_IDENT_INITIAL_ESTIMATE) {
        pdtcli_jb_raw(jb, ",\"initial\":\"estimate\"");
        pdtcli_jb_key(jb, "x0", (double)r->x0);
        if (m->kind == PDT_MODEL_SOPDT) pdtcli_jb_key(jb, "dx0", (double)r->dx0);
    }
    if (r->drift != (pdt_real_t)0) pdtcli_jb_key(jb, "drift", (double)r->drift);
}

void pdtcli_jb_model(pdtcli_jbuf_t *jb, const pdt_model_t *m, const pdt_ident_result_t *r)
{
    if (m->kind == PDT_MODEL_FOPDT)
        fopdt_keys(jb, &m->p.fopdt, r);
    else
        sopdt_keys(jb, &m->p.sopdt, r);
    if (r) {
        pdtcli_jb_key(jb, "cost", (double)r->cost);
        pdtcli_jb_key(jb, "fit", (double)r->fit);
        pdtcli_jb_uint(jb, "evaluations", (unsigned long)r->evaluations);
        if (r->f_band > (pdt_real_t)0) pdtcli_jb_key(jb, "f_band", (double)r->f_band);
        if (r->searches > 0u) certainty_keys(jb, r);
        if (r->searches > 0u) pdtcli_jb_key(jb, "evidence", (double)r->evidence);
        if (r->searches > 0u) excluded_keys(jb, r);
        if (r->searches > 0u) initial_keys(jb, m, r);
    }
}

/* The printed parameters in the JSON's order and under its names. */
static const struct {
    pdt_ident_par_t par;
    const char *name;
} printed_names[] = {
    {PDT_IDENT_PAR_K, "K"},   {PDT_IDENT_PAR_KI, "Ki"},     {PDT_IDENT_PAR_TAU, "tau"},
    {PDT_IDENT_PAR_WN, "wn"}, {PDT_IDENT_PAR_ZETA, "zeta"}, {PDT_IDENT_PAR_TD, "Td"},
    {PDT_IDENT_PAR_Y0, "y0"}, {PDT_IDENT_PAR_TAU1, "tau1"}, {PDT_IDENT_PAR_TAU2, "tau2"},
    {PDT_IDENT_PAR_A, "a"},   {PDT_IDENT_PAR_B, "b"},
};
#define N_PRINTED (sizeof printed_names / sizeof printed_names[0])

/* Whether the JSON prints parameter k of the table for this model: a
 * FOPDT's four; every SOPDT key (null where the form has none), Ki only
 * for an integrator. */
static int printed(const pdt_model_t *m, const pdt_ident_printed_t *p, size_t k)
{
    const pdt_ident_par_t i = printed_names[k].par;
    if (m->kind == PDT_MODEL_FOPDT) return (p->have >> i) & 1u;
    if (i == PDT_IDENT_PAR_TAU) return 0;
    return i != PDT_IDENT_PAR_KI || ((p->have >> i) & 1u);
}

void pdtcli_jb_std(pdtcli_jbuf_t *jb, const pdt_model_t *m, const pdt_ident_std_t *sd)
{
    pdt_ident_printed_t p;
    if (pdt_ident_std_printed(m, sd, &p) != PDT_OK) {
        pdtcli_jb_raw(jb, ",\"std\":null,\"cov\":null");
        return;
    }
    const char *sep = "{";
    pdtcli_jb_raw(jb, ",\"std\":");
    for (size_t k = 0; k < N_PRINTED; k++) {
        if (!printed(m, &p, k)) continue;
        pdtcli_jb_printf(jb, "%s\"%s\":", sep, printed_names[k].name);
        pdtcli_jb_num(jb, (double)p.std[printed_names[k].par]);
        sep = ",";
    }
    pdtcli_jb_raw(jb, "},\"cov\":");
    sep = "{";
    for (size_t k = 0; k < N_PRINTED; k++) {
        if (!printed(m, &p, k)) continue;
        const pdt_ident_par_t i = printed_names[k].par;
        pdtcli_jb_printf(jb, "%s\"%s\":", sep, printed_names[k].name);
        const char *sep2 = "{";
        for (size_t l = 0; l < N_PRINTED; l++) {
            if (!printed(m, &p, l)) continue;
            const pdt_ident_par_t j = printed_names[l].par;
            pdtcli_jb_printf(jb, "%s\"%s\":", sep2, printed_names[l].name);
            const int both = ((p.have >> i) & 1u) && ((p.have >> j) & 1u);
            pdtcli_jb_num(jb, both ? (double)p.cov[i][j] : (double)NAN);
            sep2 = ",";
        }
        pdtcli_jb_raw(jb, "}");
        sep = ",";
    }
    pdtcli_jb_raw(jb, "}");
}

/* "std", "cov" and "ci95" from a bootstrap b, under the keys printed()
 * gives the model's Fisher uncertainty p. */
static void boot_keys(pdtcli_jbuf_t *jb, const pdt_model_t *m, const pdt_ident_printed_t *p,
                      const pdtcli_boot_t *b)
{
    static const char *const part[3] = {",\"std\":", ",\"cov\":", ",\"ci95\":"};
    for (int w = 0; w < 3; w++) {
        const char *sep = "{";
        pdtcli_jb_raw(jb, part[w]);
        for (size_t k = 0; k < N_PRINTED; k++) {
            if (!printed(m, p, k)) continue;
            const pdt_ident_par_t i = printed_names[k].par;
            const int has = (b->have >> i) & 1u;
            pdtcli_jb_printf(jb, "%s\"%s\":", sep, printed_names[k].name);
            sep = ",";
            if (w == 0) {
                pdtcli_jb_num(jb, has ? b->std[i] : (double)NAN);
            } else if (w == 2) {
                if (!has) {
                    pdtcli_jb_raw(jb, "null");
                    continue;
                }
                pdtcli_jb_raw(jb, "[");
                pdtcli_jb_num(jb, b->lo[i]);
                pdtcli_jb_raw(jb, ",");
                pdtcli_jb_num(jb, b->hi[i]);
                pdtcli_jb_raw(jb, "]");
            } else {
                const char *sep2 = "{";
                for (size_t l = 0; l < N_PRINTED; l++) {
                    if (!printed(m, p, l)) continue;
                    pdtcli_jb_printf(jb, "%s\"%s\":", sep2, printed_names[l].name);
                    pdtcli_jb_num(jb, b->cov[i][printed_names[l].par]);
                    sep2 = ",";
                }
                pdtcli_jb_raw(jb, "}");
            }
        }
        pdtcli_jb_raw(jb, "}");
    }
}

/* "std" and "cov": the standard deviations and covariance of the printed
 * parameters (pdt_ident_std_printed), from the identification's
 * uncertainty (a result of pdt_ls has none: computed here the same way,
 * pdt_ident_uncertainty); null where the record does not determine one or
 * the form has none, both keys null when they cannot be computed. */
static void std_keys(pdtcli_jbuf_t *jb, const pdt_ident_result_t *r, const pdt_real_t *u,
                     const pdt_real_t *y, double Ts, size_t n, const pdtcli_boot_t *boot)
{
    const pdt_ident_data_t d = {u, y, n};
    pdt_ident_std_t sd = r->std;
    if (sd.count == 0u &&
        pdt_ident_uncertainty(&r->model, &d, (pdt_real_t)Ts, r->y0, &sd) != PDT_OK) {
        pdtcli_jb_raw(jb, ",\"std\":null,\"cov\":null,\"uncertainty\":null");
        return;
    }
    pdt_ident_printed_t p;
    if (boot && pdt_ident_std_printed(&r->model, &sd, &p) == PDT_OK) {
        boot_keys(jb, &r->model, &p, boot);
        pdtcli_jb_str(jb, "uncertainty", "bootstrap");
        pdtcli_jb_uint(jb, "bootstrap_runs", (unsigned long)boot->ok);
        return;
    }
    pdtcli_jb_std(jb, &r->model, &sd);
    pdtcli_jb_str(jb, "uncertainty", "fisher");
}

int pdtcli_ident_json_boot(const pdt_ident_result_t *r, const pdt_real_t *u, const pdt_real_t *y,
                           double Ts, size_t n, const pdtcli_boot_t *boot, char *buf, size_t len)
{
    pdtcli_jbuf_t jb;
    if (!r || !buf) return -1;
    pdtcli_jb_init(&jb, buf, len);
    pdtcli_jb_model(&jb, &r->model, r);
    if (u && y) std_keys(&jb, r, u, y, Ts, n, boot);
    pdtcli_jb_key(&jb, "Ts", Ts);
    pdtcli_jb_uint(&jb, "n", (unsigned long)n);
    pdtcli_jb_raw(&jb, "}");
    return pdtcli_jb_done(&jb);
}

pdt_status_t pdtcli_jb_several(pdtcli_jbuf_t *jb, pdt_ident_t *ctx, const char *const *names,
                               size_t count)
{
    unsigned long samples = 0;
    pdtcli_jb_raw(jb, ",\"std\":null,\"cov\":null,\"uncertainty\":null,\"record_fit\":[");
    for (uint32_t r = 0; r < count; r++) {
        pdt_ident_record_fit_t f;
        const pdt_status_t st = pdt_ident_record_result(ctx, r, &f);
        if (st != PDT_OK) return st;
        samples += (unsigned long)f.n;
        pdtcli_jb_printf(jb, "%s{\"n\":%lu", r ? "," : "", (unsigned long)f.n);
        if (names && names[r]) {
            /* The path as a JSON string: quotes, backslashes and control
             * characters escaped. */
            pdtcli_jb_raw(jb, ",\"file\":\"");
            for (const char *c = names[r]; *c; c++) {
                const unsigned char ch = (unsigned char)*c;
                if (ch == '"' || ch == '\\')
                    pdtcli_jb_printf(jb, "\\%c", *c);
                else if (ch < 0x20u)
                    pdtcli_jb_printf(jb, "\\u%04x", (unsigned)ch);
                else
                    pdtcli_jb_printf(jb, "%c", *c);
            }
            pdtcli_jb_raw(jb, "\"");
        }
        pdtcli_jb_key(jb, "Ts", (double)f.Ts);
        pdtcli_jb_key(jb, "u0", (double)f.u0);
        pdtcli_jb_key(jb, "y0", (double)f.y0);
        pdtcli_jb_key(jb, "fit", (double)f.fit);
        pdtcli_jb_key(jb, "cost", (double)f.cost);
        pdtcli_jb_key(jb, "x0", (double)f.x0);
        pdtcli_jb_key(jb, "dx0", (double)f.dx0);
        pdtcli_jb_key(jb, "drift", (double)f.drift);
        pdtcli_jb_raw(jb, "}");
    }
    pdtcli_jb_raw(jb, "]");
    pdtcli_jb_uint(jb, "records", (unsigned long)count);
    pdtcli_jb_uint(jb, "samples", samples);
    return PDT_OK;
}

int pdtcli_ident_json(const pdt_ident_result_t *r, const pdt_real_t *u, const pdt_real_t *y,
                      double Ts, size_t n, char *buf, size_t len)
{
    return pdtcli_ident_json_boot(r, u, y, Ts, n, NULL, buf, len);
}

int pdtcli_model_json(const pdt_model_t *m, char *buf, size_t len)
{
    pdtcli_jbuf_t jb;
    if (!m || !buf) return -1;
    pdtcli_jb_init(&jb, buf, len);
    pdtcli_jb_model(&jb, m, NULL);
    pdtcli_jb_raw(&jb, "}");
    return pdtcli_jb_done(&jb);
}

static void gains_json(pdtcli_jbuf_t *jb, const pdt_tune_gains_t *g)
{
    pdtcli_jb_raw(jb, "{\"Kc\":");
    pdtcli_jb_num(jb, (double)g->Kc);
    pdtcli_jb_key(jb, "tauI", (double)g->tauI);
    pdtcli_jb_key(jb, "tauD", (double)g->tauD);
    pdtcli_jb_key(jb, "Tf", (double)g->Tf);
    pdtcli_jb_raw(jb, "}");
}

/* Kp + Ki / s + Kd s / (Tf s + 1): what most PID blocks and libraries
 * take; scale converts to percent of span. */
static void parallel_json(pdtcli_jbuf_t *jb, const pdt_tune_gains_t *g, double scale)
{
    const double Kc = (double)g->Kc * scale;
    pdtcli_jb_raw(jb, "{\"Kp\":");
    pdtcli_jb_num(jb, Kc);
    pdtcli_jb_key(jb, "Ki", g->tauI > (pdt_real_t)0 ? Kc / (double)g->tauI : 0.0);
    pdtcli_jb_key(jb, "Kd", Kc * (double)g->tauD);
    pdtcli_jb_key(jb, "Tf", (double)g->Tf);
    pdtcli_jb_raw(jb, "}");
}

static void figures_json(pdtcli_jbuf_t *jb, const pdt_tune_figures_t *fig)
{
    const double nan = (double)NAN;
    pdtcli_jb_key(jb, "Ms", fig ? (double)fig->Ms : nan);
    pdtcli_jb_key(jb, "gain_margin", fig ? (double)fig->gain_margin : nan);
    pdtcli_jb_key(jb, "phase_margin_deg", fig ? (double)fig->phase_margin_deg : nan);
    pdtcli_jb_key(jb, "w_ms", fig ? (double)fig->w_ms : nan);
    pdtcli_jb_key(jb, "w_pc", fig && fig->w_pc > 0 ? (double)fig->w_pc : nan);
    pdtcli_jb_key(jb, "w_gc", fig ? (double)fig->w_gc : nan);
}

/* The tuning object of `pdtfit tune` (docs/cli.md): rule and form by
 * name, the ideal gains, the figures (fig NULL: null), series, parallel
 * and, with a finite span ratio y_span / u_span, percent-of-span gains,
 * the knob (tau_c for SIMC, lambda for IMC), and Ku, Pu when finite. */
void pdtcli_jb_tune(pdtcli_jbuf_t *jb, const char *rule, const char *form, int knob_tau_c,
                    int knob_lambda, const pdt_tune_result_t *r, const pdt_tune_figures_t *fig,
                    double span, double Ku, double Pu)
{
    pdtcli_jb_raw(jb, "{\"rule\":\"");
    pdtcli_jb_raw(jb, rule);
    pdtcli_jb_raw(jb, "\"");
    pdtcli_jb_str(jb, "form", form);
    pdtcli_jb_key(jb, "Kc", (double)r->ideal.Kc);
    pdtcli_jb_key(jb, "tauI", (double)r->ideal.tauI);
    pdtcli_jb_key(jb, "tauD", (double)r->ideal.tauD);
    pdtcli_jb_key(jb, "Tf", (double)r->ideal.Tf);
    figures_json(jb, fig);
    pdtcli_jb_raw(jb, ",\"series\":");
    if (r->series_exists || r->series_rule)
        gains_json(jb, &r->series);
    else
        pdtcli_jb_raw(jb, "null");
    /* The pdt_pid settings whose loop has these figures (docs/pid.md). */
    pdtcli_jb_raw(jb, ",\"pid\":{\"form\":\"ideal\",\"Kc\":");
    pdtcli_jb_num(jb, (double)r->ideal.Kc);
    pdtcli_jb_key(jb, "Ti", (double)r->ideal.tauI);
    pdtcli_jb_key(jb, "Td", (double)r->ideal.tauD);
    pdtcli_jb_key(jb, "Tf", (double)r->ideal.Tf);
    pdtcli_jb_raw(jb, ",\"N\":0}");
    pdtcli_jb_raw(jb, ",\"parallel\":");
    parallel_json(jb, &r->ideal, 1.0);
    if (isfinite(span)) {
        /* Output % per process-value %: Kc (y_span / 100) / (u_span / 100). */
        pdtcli_jb_raw(jb, ",\"percent\":");
        parallel_json(jb, &r->ideal, span);
    }
    pdtcli_jb_str(jb, "stated_in", r->series_rule ? "series" : "ideal");
    if (knob_tau_c) pdtcli_jb_key(jb, "tau_c", (double)r->knob);
    if (knob_lambda) pdtcli_jb_key(jb, "lambda", (double)r->knob);
    if (isfinite(Ku)) pdtcli_jb_key(jb, "Ku", Ku);
    if (isfinite(Pu)) pdtcli_jb_key(jb, "Pu", Pu);
    pdtcli_jb_raw(jb, "}");
}

/* The gain's std and the whole covariance finite: the first thing
 * pdt_ident_select_order weighs. */
static int determined(const pdt_validate_result_t *v)
{
    int ok = isfinite((double)v->std.std[0]);
    for (uint32_t i = 0; i < v->std.count; i++)
        for (uint32_t j = 0; j < v->std.count; j++) ok = ok && isfinite((double)v->std.cov[i][j]);
    return ok;
}

void pdtcli_jb_order(pdtcli_jbuf_t *jb, pdt_model_kind_t kept, const pdt_ident_result_t r[2],
                     const pdt_validate_result_t v[2])
{
    static const char *const names[2] = {"fopdt", "sopdt"};
    pdtcli_jb_printf(jb, ",\"order\":{\"kept\":\"%s\"", names[kept == PDT_MODEL_SOPDT]);
    for (int k = 0; k < 2; k++) {
        pdtcli_jb_printf(jb, ",\"%s\":{\"determined\":%s,\"independent\":%s,\"bic\":", names[k],
                         determined(&v[k]) ? "true" : "false", v[k].independent ? "true" : "false");
        pdtcli_jb_num(jb, (double)v[k].bic);
        pdtcli_jb_key(jb, "aic", (double)v[k].aic);
        pdtcli_jb_raw(jb, v[k].white ? ",\"white\":true" : ",\"white\":false");
        pdtcli_jb_key(jb, "sigma", (double)v[k].sigma);
        pdtcli_jb_key(jb, "fit", (double)r[k].fit);
        pdtcli_jb_raw(jb, "}");
    }
    pdtcli_jb_raw(jb, "}");
}
