/* pdtfit tune: PI/PID gains of a known model, given by its parameters or
 * read from the JSON identify printed (--from). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model_json.h"
#include "tune_opts.h"

enum { P_K, P_TAU, P_TD, P_WN, P_ZETA, P_TAU1, P_TAU2, P_KU, P_PU, P_COUNT };
static const char *const pname[P_COUNT] = {"--K",    "--tau",  "--Td", "--wn", "--zeta",
                                           "--tau1", "--tau2", "--Ku", "--Pu"};

typedef struct tune_args {
    tune_opts_t t;
    int model; /* 0 none, else pdt_model_kind_t */
    double par[P_COUNT];
    int have[P_COUNT];
    const char *from;
    int force; /* tune a flagged model */
} tune_args_t;

static void parse(tune_args_t *a, int argc, char **argv)
{
    cli_opt_t tab[CLI_MAX_OPTS];
    size_t n = tune_opts_table(&a->t, tab, 1);
    const cli_opt_t model = {"--model",       OPT_CHOICE, &a->model,       NULL,    CHK_ANY,
                             PDT_MODEL_FOPDT, 0,          cli_model_names, "model", 0};
    const cli_opt_t from = {"--from", OPT_TEXT, &a->from, NULL, CHK_ANY, 0, 0, NULL, NULL, 0};
    const cli_opt_t force = {"--force", OPT_FLAG, &a->force, NULL, CHK_ANY, 0, 0, NULL, NULL, 0};
    tab[n++] = model;
    tab[n++] = from;
    tab[n++] = force;
    for (int k = 0; k < P_COUNT; k++) {
        const cli_opt_t p = {pname[k], OPT_REAL, &a->par[k], &a->have[k], CHK_ANY,
                             0,        0,        NULL,       NULL,        0};
        tab[n++] = p;
    }
    cli_parser_t p = {"tune", CMD_TUNE, tab, n, NULL, {0}, NULL, NULL, 0};
    cli_parse(&p, argc, argv);
}

/* Which parameters a model kind takes, refusing foreign and missing ones. */
static void check_params(const tune_args_t *a)
{
    int allowed[P_COUNT] = {0};
    allowed[P_K] = allowed[P_TD] = allowed[P_KU] = allowed[P_PU] = 1;
    const int natural = a->have[P_WN] || a->have[P_ZETA];
    const int tc = a->have[P_TAU1] || a->have[P_TAU2];
    if (a->model == PDT_MODEL_FOPDT) {
        allowed[P_TAU] = 1;
    } else {
        if (natural && tc)
            cli_fail(EXIT_USAGE,
                     "tune: give the sopdt as --wn --zeta or as --tau1 --tau2, not both");
        allowed[P_WN] = allowed[P_ZETA] = !tc;
        allowed[P_TAU1] = allowed[P_TAU2] = !natural;
    }
    for (int k = 0; k < P_COUNT; k++)
        if (a->have[k] && !allowed[k])
            cli_fail(EXIT_USAGE, "tune: %s is not a parameter of --model %s", pname[k],
                     a->model == PDT_MODEL_FOPDT ? "fopdt"
                                                 : "sopdt (--K, --Td and --wn, --zeta or --tau1, "
                                                   "--tau2)");
    static const int need1[] = {P_K, P_TAU, P_TD}, need2n[] = {P_K, P_WN, P_ZETA, P_TD},
                     need2t[] = {P_K, P_TAU1, P_TAU2, P_TD};
    const int *need = a->model == PDT_MODEL_FOPDT ? need1 : tc ? need2t : need2n;
    for (int k = 0; k < (a->model == PDT_MODEL_FOPDT ? 3 : 4); k++)
        if (!a->have[need[k]])
            cli_fail(EXIT_USAGE, "tune: --model %s needs %s",
                     cli_model_str((pdt_model_kind_t)a->model), pname[need[k]]);
    if (a->par[P_K] == 0.0) cli_fail(EXIT_USAGE, "tune: --K must not be 0");
    if (!(a->par[P_TD] >= 0.0)) cli_fail(EXIT_USAGE, "tune: --Td needs a dead time >= 0 s");
    for (int k = P_TAU; k <= P_TAU2; k++)
        if (k != P_TD && a->have[k] && !(a->par[k] > 0.0))
            cli_fail(EXIT_USAGE, "tune: %s must be > 0", pname[k]);
}

static void model_from_params(const tune_args_t *a, pdt_model_t *m)
{
    const double *par = a->par;
    pdt_status_t st = PDT_OK;
    check_params(a);
    memset(m, 0, sizeof *m);
    m->kind = (pdt_model_kind_t)a->model;
    if (a->model == PDT_MODEL_FOPDT) {
        m->p.fopdt.K = (pdt_real_t)par[P_K];
        m->p.fopdt.tau = (pdt_real_t)par[P_TAU];
        m->p.fopdt.Td = (pdt_real_t)par[P_TD];
    } else if (a->have[P_WN]) {
        const pdt_model_natural_t nat = {(pdt_real_t)par[P_K], (pdt_real_t)par[P_WN],
                                         (pdt_real_t)par[P_ZETA], (pdt_real_t)par[P_TD]};
        st = pdt_model_sopdt_from_natural(&nat, &m->p.sopdt);
    } else {
        const pdt_model_tc_t tc = {(pdt_real_t)par[P_K], (pdt_real_t)par[P_TAU1],
                                   (pdt_real_t)par[P_TAU2], false, (pdt_real_t)par[P_TD]};
        st = pdt_model_sopdt_from_tc(&tc, &m->p.sopdt);
    }
    if (st == PDT_OK) st = pdt_model_check(m);
    if (st != PDT_OK)
        cli_fail(EXIT_USAGE, "tune: the model is out of the real type's range (%s)",
                 pdt_status_str(st));
}

static void check_args(const tune_args_t *a)
{
    if (!a->t.have_rule) cli_fail(EXIT_USAGE, "tune: --rule simc|imc|amigo|zn is required");
    tune_opts_check("tune", &a->t);
    if (a->have[P_KU] || a->have[P_PU]) {
        if (a->t.rule != PDT_TUNE_ZN)
            cli_fail(EXIT_USAGE, "tune: --Ku and --Pu are inputs of --rule zn only");
        if (!a->have[P_KU] || !a->have[P_PU])
            cli_fail(EXIT_USAGE, "tune: --Ku and --Pu go together");
        if (a->par[P_KU] == 0.0) cli_fail(EXIT_USAGE, "tune: --Ku must not be 0");
        if (!(a->par[P_PU] > 0.0)) cli_fail(EXIT_USAGE, "tune: --Pu needs a period > 0 s");
    }
    if (a->from && a->model) cli_fail(EXIT_USAGE, "tune: --from reads the model; give no --model");
    if (a->force && !a->from)
        cli_fail(EXIT_USAGE, "tune: --force goes with --from (a flagged model)");
    if (!a->model || a->from)
        for (int k = 0; k < P_KU; k++)
            if (a->have[k])
                cli_fail(EXIT_USAGE, "tune: %s needs --model%s", pname[k],
                         a->from ? " (and no --from)" : "");
    if (!a->model && !a->from && !a->have[P_KU])
        cli_fail(EXIT_USAGE, "tune: --model fopdt|sopdt is required (or --from FILE.json, or --Ku "
                             "and --Pu with --rule zn)");
}

/* Classic Ziegler-Nichols from an ultimate gain and period; with a model,
 * the figures of those gains on it. */
static void tune_relay(const tune_args_t *a, const pdt_model_t *m, pdt_tune_result_t *r)
{
    pdt_tune_config_t cfg;
    pdt_tune_config_default(&cfg);
    tune_opts_config(&a->t, &cfg);
    pdt_status_t st = pdt_tune_ziegler_nichols((pdt_real_t)a->par[P_KU], (pdt_real_t)a->par[P_PU],
                                               (pdt_tune_form_t)a->t.form, &r->ideal);
    if (st != PDT_OK)
        cli_fail(EXIT_REFUSED, "tune: cannot tune: %s (Ku or Pu out of the real type's range)",
                 pdt_status_str(st));
    r->series_exists = pdt_tune_to_series(&r->ideal, &r->series) == PDT_OK;
    if (!m) return;
    st = pdt_tune_robustness(m, &r->ideal, &r->fig);
    if (st != PDT_OK)
        cli_fail(EXIT_REFUSED, "tune: cannot tune: %s%s", pdt_status_str(st),
                 tune_hint(st, a->t.rule, m));
    if (cfg.ms_max > 0 && r->fig.Ms > cfg.ms_max)
        cli_fail(EXIT_REFUSED,
                 "tune: gains refused: Ms %.4g exceeds the limit %.4g (--ms-max 0 "
                 "prints them)",
                 (double)r->fig.Ms, (double)cfg.ms_max);
}

int cmd_tune(int argc, char **argv)
{
    tune_args_t a;
    memset(&a, 0, sizeof a);
    parse(&a, argc, argv);
    check_args(&a);
    pdt_model_t m;
    double fit = 100.0;
    const int have_model = a.model || a.from;
    memset(&m, 0, sizeof m);
    char flags[256];
    int suspect = 0;
    if (a.from)
        suspect = tune_check_flags(
            "tune", flags, pdtcli_model_from_json("tune", a.from, &m, &fit, flags, sizeof flags),
            a.force);
    else if (have_model)
        model_from_params(&a, &m);
    pdt_tune_result_t r;
    memset(&r, 0, sizeof r);
    const int relay = a.have[P_KU];
    if (relay)
        tune_relay(&a, have_model ? &m : NULL, &r);
    else
        tune_model("tune", &m, fit, &a.t, &r);
    char buf[2048];
    pdtcli_jbuf_t jb;
    pdtcli_jb_init(&jb, buf, sizeof buf);
    tune_json(&jb, &a.t, &r, have_model ? &r.fig : NULL, relay ? a.par[P_KU] : (double)NAN,
              relay ? a.par[P_PU] : (double)NAN);
    if (pdtcli_jb_done(&jb) < 0) cli_fail(EXIT_REFUSED, "tune: result too long");
    puts(buf);
    cli_flush();
    return suspect ? EXIT_SUSPECT : 0;
}
