/* pdtfit reduce: a FOPDT or SOPDT from a known detailed model. */
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "json.h"

static const char *const method_names[] = {"skogestad", "sung", NULL};

typedef struct reduce_args {
    int method, model, have_method, have_model, have_gain, have_lags, have_h;
    double gain, delay, h;
    cli_list_t lags, zeros;
} reduce_args_t;

static void parse(reduce_args_t *a, int argc, char **argv)
{
    const cli_opt_t tab[] = {
        {"--method", OPT_CHOICE, &a->method, &a->have_method, CHK_ANY, 0, 0, method_names, "method",
         0},
        {"--model", OPT_CHOICE, &a->model, &a->have_model, CHK_ANY, PDT_MODEL_FOPDT, 0,
         cli_model_names, "model", 0},
        {"--gain", OPT_REAL, &a->gain, &a->have_gain, CHK_ANY, 0, 0, NULL, "a finite number", 0},
        {"--lags", OPT_LIST, &a->lags, &a->have_lags, CHK_GT0, 0, 0, NULL,
         "every time constant must be > 0", 0},
        {"--zeros", OPT_LIST, &a->zeros, NULL, CHK_NONZERO, 0, 0, NULL,
         "a zero time constant cannot be 0", 0},
        {"--delay", OPT_REAL, &a->delay, NULL, CHK_GE0, 0, 0, NULL, "a dead time >= 0 s", 0},
        {"--h", OPT_REAL, &a->h, &a->have_h, CHK_GE0, 0, 0, NULL, "a controller period >= 0 s", 0},
    };
    cli_parser_t p = {"reduce", CMD_REDUCE, tab, sizeof tab / sizeof tab[0], NULL, {0},
                      NULL,     NULL,       0};
    cli_parse(&p, argc, argv);
    if (!a->have_method) cli_fail(EXIT_USAGE, "reduce: --method skogestad|sung is required");
    if (!a->have_model) cli_fail(EXIT_USAGE, "reduce: --model fopdt|sopdt is required");
    if (!a->have_gain) cli_fail(EXIT_USAGE, "reduce: --gain K is required");
    if (!a->have_lags) cli_fail(EXIT_USAGE, "reduce: --lags T1,T2,... is required");
    if (a->have_h && a->method == 1)
        cli_fail(EXIT_USAGE, "reduce: --h is an option of --method skogestad only");
}

static const char *reduce_hint(pdt_status_t st, int method)
{
    if (st == PDT_ERR_NO_FORM)
        return method == 0 ? " (a zero has no lag to cancel against, or fewer lags than the "
                             "model's order)"
                           : " (the phase of the model never reaches -180 degrees, or its gain "
                             "is 0)";
    if (st == PDT_ERR_LENGTH) return " (too many lags for the half rule)";
    if (st == PDT_ERR_ARG) return " (a value is out of the real type's range)";
    return "";
}

int cmd_reduce(int argc, char **argv)
{
    reduce_args_t a;
    memset(&a, 0, sizeof a);
    parse(&a, argc, argv);
    pdt_real_t lags[CLI_MAX_LIST], zeros[CLI_MAX_LIST];
    for (int k = 0; k < a.lags.n; k++) lags[k] = (pdt_real_t)a.lags.v[k];
    for (int k = 0; k < a.zeros.n; k++) zeros[k] = (pdt_real_t)a.zeros.v[k];
    const pdt_reduce_plant_t plant = {(pdt_real_t)a.gain, lags,
                                      (size_t)a.lags.n,   a.zeros.n > 0 ? zeros : NULL,
                                      (size_t)a.zeros.n,  (pdt_real_t)a.delay};
    pdt_reduce_config_t cfg;
    pdt_reduce_config_default(&cfg);
    cfg.model = (pdt_model_kind_t)a.model;
    cfg.h = (pdt_real_t)a.h;
    pdt_model_t out;
    pdt_status_t st = a.method == 0 ? pdt_reduce_half_rule(&plant, &cfg, &out, NULL)
                                    : pdt_reduce_sung(&plant, &cfg, &out, NULL);
    if (st != PDT_OK)
        cli_fail(EXIT_REFUSED, "cannot reduce: %s%s", pdt_status_str(st),
                 reduce_hint(st, a.method));
    char buf[1024];
    if (pdtcli_model_json(&out, buf, sizeof buf) < 0) cli_fail(EXIT_REFUSED, "result too long");
    puts(buf);
    cli_flush();
    return 0;
}
