#include "tune_opts.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

size_t tune_opts_table(tune_opts_t *t, cli_opt_t *tab, int rule_form)
{
    const cli_opt_t rows[] = {
        {"--rule", OPT_CHOICE, &t->rule, &t->have_rule, CHK_ANY, 0, 0, cli_rule_names, "rule", 0},
        {"--form", OPT_CHOICE, &t->form, NULL, CHK_ANY, 0, 0, cli_form_names, "form", 0},
        {"--tau-c", OPT_REAL, &t->tau_c, &t->have_tau_c, CHK_GE0, 0, 0, NULL,
         "a time >= 0 s (0: the dead time)", 0},
        {"--lambda", OPT_REAL, &t->lambda, &t->have_lambda, CHK_GE0, 0, 0, NULL,
         "a time >= 0 s (0: the rule's default)", 0},
        {"--ms-max", OPT_REAL, &t->ms_max, &t->have_ms_max, CHK_LIMIT, 0, 0, NULL,
         "a limit > 1 (or 0 for none)", 0},
        {"--deriv-filter", OPT_REAL, &t->deriv_filter, &t->have_filter, CHK_FILTER, 0, 0, NULL,
         "N >= 1 (or 0 for none)", 0},
        {"--u-span", OPT_REAL, &t->u_span, &t->have_u_span, CHK_GT0, 0, 0, NULL,
         "the span of u > 0 (its range in engineering units)", 0},
        {"--y-span", OPT_REAL, &t->y_span, &t->have_y_span, CHK_GT0, 0, 0, NULL,
         "the span of y > 0 (its range in engineering units)", 0},
        {"--fit-min", OPT_REAL, &t->fit_min, &t->have_fit_min, CHK_GE0, 0, 0, NULL,
         "a fit in percent >= 0 (0: no fit threshold, the default)", 0},
    };
    const size_t skip = rule_form ? 0 : 2, n = sizeof rows / sizeof rows[0] - skip;
    memcpy(tab, rows + skip, n * sizeof rows[0]);
    return n;
}

void tune_opts_spec(const char *cmd, const char *spec, tune_opts_t *t)
{
    char rule[16];
    const char *colon = strchr(spec, ':');
    size_t len = colon ? (size_t)(colon - spec) : strlen(spec);
    if (len >= sizeof rule) len = sizeof rule - 1;
    memcpy(rule, spec, len);
    rule[len] = '\0';
    t->rule = cli_choice(rule, cli_rule_names);
    t->form = colon ? cli_choice(colon + 1, cli_form_names) : 0;
    if (t->rule < 0 || t->form < 0)
        cli_fail(EXIT_USAGE,
                 "%s: --tune needs RULE[:FORM], RULE simc, imc, amigo or zn, FORM pi "
                 "or pid, got '%s'",
                 cmd, spec);
    t->have_rule = 1;
}

void tune_opts_check(const char *cmd, const tune_opts_t *t)
{
    if (t->have_tau_c && t->rule != PDT_TUNE_SIMC)
        cli_fail(EXIT_USAGE, "%s: --tau-c is the knob of --rule simc only", cmd);
    if (t->have_lambda && t->rule != PDT_TUNE_IMC)
        cli_fail(EXIT_USAGE, "%s: --lambda is the knob of --rule imc only", cmd);
    if (t->have_u_span != t->have_y_span)
        cli_fail(EXIT_USAGE, "%s: --u-span and --y-span go together", cmd);
}

void tune_opts_config(const tune_opts_t *t, pdt_tune_config_t *cfg)
{
    cfg->rule = (pdt_tune_rule_t)t->rule;
    cfg->form = (pdt_tune_form_t)t->form;
    if (t->have_tau_c) cfg->tau_c = (pdt_real_t)t->tau_c;
    if (t->have_lambda) cfg->lambda = (pdt_real_t)t->lambda;
    if (t->have_ms_max) cfg->ms_max = (pdt_real_t)t->ms_max;
    if (t->have_filter) cfg->deriv_filter = (pdt_real_t)t->deriv_filter;
    if (t->have_fit_min) cfg->fit_min = (pdt_real_t)t->fit_min;
}

const char *tune_hint(pdt_status_t st, int rule, const pdt_model_t *m)
{
    switch (st) {
    case PDT_ERR_NO_FORM:
        if (rule == PDT_TUNE_ZN)
            return " (zn needs the model's ultimate point, and the phase of this model never "
                   "reaches -180 degrees: it has no dead time; give --Ku and --Pu or use simc, "
                   "imc or amigo)";
        return m && m->kind == PDT_MODEL_SOPDT
                   ? " (complex SOPDT poles: only simc and imc pid apply)"
                   : "";
    case PDT_ERR_UNSTABLE:
        return " (the loop these gains make with the model is unstable)";
    case PDT_ERR_ARG:
        return " (the rule needs dead time: simc with tau_c + Td = 0, amigo with Td = 0; or a "
               "value out of the real type's range)";
    default:
        return "";
    }
}

/* Why the gains of m were refused (st), into why: the figure that decided
 * a limit's refusal, the fit (PDT_ERR_POOR_FIT) or the Ms the gains would
 * have had (PDT_ERR_MS_LIMIT); else the status and its hint. */
static void refusal(pdt_status_t st, const pdt_model_t *m, double fit, const pdt_tune_config_t *cfg,
                    char *why, size_t len)
{
    pdt_tune_config_t open = *cfg;
    open.ms_max = 0;
    pdt_tune_result_t r;
    if (st == PDT_ERR_POOR_FIT)
        snprintf(why, len, "gains refused: fit %.4g%% below %.4g%% (--fit-min)", fit,
                 (double)cfg->fit_min);
    else if (st == PDT_ERR_MS_LIMIT && pdt_tune_compute(m, (pdt_real_t)fit, &open, &r) == PDT_OK)
        snprintf(why, len,
                 "gains refused: Ms %.4g exceeds the limit %.4g (--ms-max; --ms-max 0 "
                 "prints them)",
                 (double)r.fig.Ms, (double)cfg->ms_max);
    else if (st == PDT_ERR_POOR_FIT || st == PDT_ERR_MS_LIMIT)
        snprintf(why, len, "gains refused: %s", pdt_status_str(st));
    else
        snprintf(why, len, "cannot tune: %s%s", pdt_status_str(st),
                 tune_hint(st, (int)cfg->rule, m));
}

pdt_status_t tune_model_try(const char *cmd, const pdt_model_t *m, double fit, const tune_opts_t *t,
                            pdt_tune_result_t *r, char *why, size_t len)
{
    pdt_tune_config_t cfg;
    pdt_tune_config_default(&cfg);
    tune_opts_config(t, &cfg);
    const pdt_status_t st = pdt_tune_compute(m, (pdt_real_t)fit, &cfg, r);
    if (st != PDT_OK) {
        refusal(st, m, fit, &cfg, why, len);
        return st;
    }
    if (t->form == PDT_TUNE_PID && r->ideal.tauD == (pdt_real_t)0)
        cli_warn("%s: %s gives this %s no derivative action (tauD = 0): the pid asked for is a pi",
                 cmd, cli_rule_names[t->rule], cli_model_str(m->kind));
    return PDT_OK;
}

void tune_model(const char *cmd, const pdt_model_t *m, double fit, const tune_opts_t *t,
                pdt_tune_result_t *r)
{
    char why[320];
    if (tune_model_try(cmd, m, fit, t, r, why, sizeof why) != PDT_OK)
        cli_fail(EXIT_REFUSED, "%s: %s", cmd, why);
}

void tune_json(pdtcli_jbuf_t *jb, const tune_opts_t *t, const pdt_tune_result_t *r,
               const pdt_tune_figures_t *fig, double Ku, double Pu)
{
    const double span = t->have_u_span && t->have_y_span ? t->y_span / t->u_span : (double)NAN;
    pdtcli_jb_tune(jb, cli_rule_names[t->rule], cli_form_names[t->form], t->rule == PDT_TUNE_SIMC,
                   t->rule == PDT_TUNE_IMC, r, fig, span, Ku, Pu);
}

/* The text after "key": of the object at b (its top level, before e), or
 * NULL. */
const char *tune_json_top(const char *b, const char *e, const char *key)
{
    const size_t len = strlen(key);
    int depth = 0;
    for (const char *p = b; p < e; p++) {
        if (*p == '{' || *p == '[') depth++;
        if (*p == '}' || *p == ']') depth--;
        if (depth <= 0 && p > b) break;
        if (depth != 1 || *p != '"' || (size_t)(e - p) < len + 3) continue;
        if (memcmp(p + 1, key, len) != 0 || p[len + 1] != '"') continue;
        const char *q = p + len + 2;
        while (q < e && (*q == ' ' || *q == '\t' || *q == '\r' || *q == '\n')) q++;
        if (q >= e || *q != ':') continue;
        for (q++; q < e && (*q == ' ' || *q == '\t' || *q == '\r' || *q == '\n');) q++;
        return q;
    }
    return NULL;
}

int tune_json_flags(const char *b, const char *e, char *names, size_t len)
{
    size_t used = 0;
    int count = 0;
    names[0] = '\0';
    const char *v = tune_json_top(b, e, "flags");
    for (const char *p = v && *v == '[' ? v + 1 : e; p < e && *p != ']'; p++) {
        if (*p != '"') continue;
        const char *q = memchr(p + 1, '"', (size_t)(e - p - 1));
        if (!q) break;
        const int n = snprintf(names + used, len - used, "%s%.*s", count ? ", " : "",
                               (int)(q - p - 1), p + 1);
        used = n > 0 && (size_t)n < len - used ? used + (size_t)n : used;
        count++;
        p = q;
    }
    const char *fit = tune_json_top(b, e, "fit");
    if (fit && strtod(fit, NULL) < 0.0) {
        const int n = snprintf(names + used, len - used, "%sa negative fit (%.4g%%)",
                               count ? ", " : "", strtod(fit, NULL));
        used = n > 0 && (size_t)n < len - used ? used + (size_t)n : used;
        count++;
    }
    return count;
}

int tune_check_flags(const char *cmd, const char *names, int count, int force)
{
    if (count == 0) return 0;
    if (!force)
        cli_fail(EXIT_SUSPECT,
                 "%s: gains refused: the identification flagged the model (%s): it may be "
                 "wrong; --force tunes it anyway",
                 cmd, names);
    cli_warn("%s: gains of a model the identification flagged (%s), as --force asks", cmd, names);
    return 1;
}
