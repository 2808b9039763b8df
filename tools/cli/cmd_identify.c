/* pdtfit identify: a FOPDT or SOPDT from one recorded test. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "identify.h"

static const char *const method_names[] = {"ga", "elms", "eiv", NULL};
static const char *const cost_names[] = {"prediction", "simulation", "frequency", "combined", NULL};
static const char *const weight_names[] = {"auto", "control", "uniform", "band", NULL};
static const pdt_ident_weight_t weight_kinds[] = {PDT_IDENT_WEIGHT_AUTO, PDT_IDENT_WEIGHT_CONTROL,
                                                  PDT_IDENT_WEIGHT_UNIFORM, PDT_IDENT_WEIGHT_BAND};
/* --time-unit: in PDTCLI_TIME_* order. */
static const char *const unit_names[] = {"s", "ms", "us", "min", "h", NULL};
/* --bad-rows: in PDTCLI_BAD_ROWS_* order. */
static const char *const bad_rows_names[] = {"missing", "refuse", NULL};
/* --uncertainty: in the order of UNC_*. */
static const char *const uncertainty_names[] = {"auto", "fisher", "bootstrap", NULL};
/* --offset: in pdt_ident_offset_t's order. */
static const char *const offset_names[] = {"auto", "estimate", "rest", NULL};
/* --initial: in pdt_ident_initial_t's order. */
static const char *const initial_names[] = {"auto", "rest", "estimate", NULL};

#define GA CLI_GA_ONLY

/* --model: the two models, or auto (both identified, the order chosen by
 * the evidence, pdt_ident_select_order). */
static const char *const ident_model_names[] = {"fopdt", "sopdt", "auto", NULL};
#define MODEL_AUTO (PDT_MODEL_SOPDT + 1)

static size_t ident_table(ident_args_t *a, cli_opt_t *tab)
{
    const cli_opt_t rows[] = {
        {"--model", OPT_CHOICE, &a->model, &a->have_model, 0, PDT_MODEL_FOPDT, 0, ident_model_names,
         "model", 0},
        {"--method", OPT_CHOICE, &a->method, NULL, 0, 0, 0, method_names, "method", 0},
        {"--td-max", OPT_REAL, &a->td_max, &a->have_td_max, CHK_GE0, 0, 0, NULL,
         "a dead time >= 0 s", 0},
        {"--cost", OPT_CHOICE, &a->cost, NULL, 0, 0, 0, cost_names, "cost", GA},
        {"--weight", OPT_CHOICE, &a->weight, &a->have_weight, 0, 0, 0, weight_names, "weight", GA},
        {"--band", OPT_TEXT, &a->band, NULL, 0, 0, 0, NULL, NULL, GA},
        {"--offset", OPT_CHOICE, &a->offset, NULL, 0, 0, 0, offset_names, "offset", GA},
        {"--initial", OPT_CHOICE, &a->initial, NULL, 0, 0, 0, initial_names, "initial state", GA},
        {"--u-before", OPT_REAL, &a->u_before, &a->have_u_before, 0, 0, 0, NULL,
         "the input before the first row", GA | CLI_REAL_FITS},
        {"--phi-t", OPT_REAL, &a->phi_t, &a->have_phi_t, CHK_GE0, 0, 0, NULL, "a weight >= 0",
         GA | CLI_REAL_FITS},
        {"--phi-f", OPT_REAL, &a->phi_f, &a->have_phi_f, CHK_GE0, 0, 0, NULL, "a weight >= 0",
         GA | CLI_REAL_FITS},
        {"--seed", OPT_UINT, &a->seed, NULL, 0, 0, UINT64_MAX, NULL, "a whole number >= 0", GA},
        {"--evaluations", OPT_UINT, &a->evaluations, &a->have_evaluations, 0, 1, UINT32_MAX, NULL,
         "a whole number >= 1", GA},
        {"--population", OPT_UINT, &a->population, &a->have_population, 0, 4,
         PDT_IDENT_MAX_POPULATION, NULL, "an even number from 4 to the library's maximum",
         GA | CLI_EVEN},
        {"--coarse", OPT_UINT, &a->coarse, NULL, 0, 0, UINT32_MAX, NULL, "a whole number >= 0", GA},
        {"--fs", OPT_REAL, &a->fs, &a->have_fs, CHK_GT0, 0, 0, NULL, "a sampling frequency > 0 Hz",
         0},
        {"--integer-delay", OPT_FLAG, &a->integer_delay, NULL, 0, 0, 0, NULL, NULL, 0},
        {"--drift", OPT_FLAG, &a->drift, NULL, 0, 0, 0, NULL, NULL, GA},
        {"--t", OPT_TEXT, &a->t_col, NULL, 0, 0, 0, NULL, NULL, 0},
        {"--u", OPT_TEXT, &a->u_col, NULL, 0, 0, 0, NULL, NULL, 0},
        {"--y", OPT_TEXT, &a->y_col, NULL, 0, 0, 0, NULL, NULL, 0},
        {"--sep", OPT_TEXT, &a->sep, NULL, 0, 0, 0, NULL, NULL, 0},
        {"--decimal", OPT_TEXT, &a->decimal, NULL, 0, 0, 0, NULL, NULL, 0},
        {"--skip", OPT_UINT, &a->skip, NULL, 0, 0, 1000000, NULL, "a line count 0 .. 1000000", 0},
        {"--time-unit", OPT_CHOICE, &a->time_unit, &a->have_time_unit, 0, 0, 0, unit_names,
         "time unit", 0},
        {"--resample", OPT_FLAG, &a->resample, NULL, 0, 0, 0, NULL, NULL, 0},
        {"--bad-value", OPT_LIST, &a->bad_values, NULL, CHK_ANY, 0, 0, NULL, "a finite number",
         CLI_REPEAT},
        {"--bad-rows", OPT_CHOICE, &a->bad_rows, NULL, 0, 0, 0, bad_rows_names, "bad-rows mode", 0},
        {"--force", OPT_FLAG, &a->force, NULL, 0, 0, 0, NULL, NULL, 0},
        {"--units-row", OPT_FLAG, &a->units_row, NULL, 0, 0, 0, NULL, NULL, 0},
        {"--time-format", OPT_TEXT, &a->time_format, NULL, 0, 0, 0, NULL, NULL, 0},
        {"--uncertainty", OPT_CHOICE, &a->uncertainty, NULL, 0, 0, 0, uncertainty_names,
         "uncertainty", GA},
        {"--bootstrap", OPT_UINT, &a->boot_runs, &a->have_boot_runs, 0, 2, 100000, NULL,
         "a run count 2 .. 100000", GA},
        {"--out-sim", OPT_TEXT, &a->out_sim, NULL, 0, 0, 0, NULL, NULL, 0},
        {"--plot", OPT_TEXT, &a->plot, NULL, 0, 0, 0, NULL, NULL, 0},
        {"--plot-script", OPT_TEXT, &a->plot_script, NULL, 0, 0, 0, NULL, NULL, 0},
        {"--tune", OPT_TEXT, &a->tune, NULL, 0, 0, 0, NULL, NULL, 0},
    };
    memcpy(tab, rows, sizeof rows);
    return sizeof rows / sizeof rows[0] +
           tune_opts_table(&a->t, tab + sizeof rows / sizeof rows[0], 0);
}

#undef GA

static void parse_band(ident_args_t *a)
{
    char lo[64];
    const char *v = a->band, *colon = strchr(v, ':');
    size_t len = colon ? (size_t)(colon - v) : 0;
    if (!colon || len >= sizeof lo)
        cli_fail(EXIT_USAGE, "identify: --band needs F_LO:F_HI in Hz, got '%s'", v);
    memcpy(lo, v, len);
    lo[len] = '\0';
    if (cli_parse_real(lo, &a->f_lo) != 0 || cli_parse_real(colon + 1, &a->f_hi) != 0 ||
        !(a->f_lo >= 0.0) || !(a->f_hi >= a->f_lo) || !isfinite((double)(pdt_real_t)a->f_hi))
        cli_fail(EXIT_USAGE, "identify: --band needs F_LO:F_HI in Hz, 0 <= F_LO <= F_HI, got '%s'",
                 v);
}

static char one_char(const char *opt, const char *v, const char *allowed)
{
    if (!v) return 0;
    if (strcmp(v, "tab") == 0 || strcmp(v, "\\t") == 0) v = "\t";
    if (strcmp(v, "semicolon") == 0) v = ";";
    if (strcmp(v, "comma") == 0) v = ",";
    if (strlen(v) != 1 || !strchr(allowed, v[0]))
        cli_fail(EXIT_USAGE, "identify: %s needs one of %s, got '%s'", opt,
                 strchr(allowed, '\t') ? "',', ';', tab" : "'.', ','", v);
    return v[0];
}

static void check_ident_args(const cli_parser_t *p, ident_args_t *a)
{
    if (!a->have_model) cli_fail(EXIT_USAGE, "identify: --model fopdt|sopdt|auto is required");
    if (a->model == MODEL_AUTO && a->have_u_before)
        cli_fail(EXIT_USAGE, "identify: --u-before goes with --model fopdt or sopdt");
    if ((a->drift || a->initial == PDT_IDENT_INITIAL_ESTIMATE) &&
        (pdt_cost_kind_t)a->cost != PDT_COST_SIMULATION)
        cli_fail(EXIT_USAGE, "identify: --initial estimate and --drift need --cost simulation");
    if (a->model == MODEL_AUTO && a->method != METHOD_GA)
        cli_fail(EXIT_USAGE, "identify: --model auto needs --method ga");
    const int band = a->have_weight && weight_kinds[a->weight] == PDT_IDENT_WEIGHT_BAND;
    if (band && !a->band) cli_fail(EXIT_USAGE, "identify: --weight band needs --band F_LO:F_HI");
    if (a->band && !band) cli_fail(EXIT_USAGE, "identify: --band goes with --weight band");
    if (a->band) parse_band(a);
    if (a->have_phi_t && a->have_phi_f && a->phi_t == 0.0 && a->phi_f == 0.0)
        cli_fail(EXIT_USAGE, "identify: --phi-t and --phi-f cannot both be 0");
    for (size_t k = 0; a->method != METHOD_GA && k < p->n_opt; k++)
        if ((p->opt[k].flags & CLI_GA_ONLY) && p->seen[k])
            cli_fail(EXIT_USAGE, "identify: %s is an option of --method ga only", p->opt[k].name);
    if (a->method == METHOD_GA && a->have_td_max && !(a->td_max > 0.0))
        cli_fail(EXIT_USAGE, "identify: --td-max must be > 0 s with --method ga");
    if (a->tune) tune_opts_spec("identify", a->tune, &a->t);
    if (a->force && !a->tune)
        cli_fail(EXIT_USAGE, "identify: --force goes with --tune (the gains of a flagged model)");
    if (!a->tune && (a->t.have_tau_c || a->t.have_lambda || a->t.have_ms_max || a->t.have_filter ||
                     a->t.have_u_span || a->t.have_y_span))
        cli_fail(EXIT_USAGE, "identify: the tuning options go with --tune RULE[:FORM]");
    tune_opts_check("identify", &a->t);
    if (a->have_boot_runs && a->uncertainty == UNC_FISHER)
        cli_fail(EXIT_USAGE, "identify: --bootstrap goes with --uncertainty auto or bootstrap");
    if (a->plot_script && !a->plot)
        cli_fail(EXIT_USAGE, "identify: --plot-script goes with --plot");
    if (!a->file) cli_fail(EXIT_USAGE, "identify: missing FILE (a CSV file, or - for stdin)");
}

static void parse(ident_args_t *a, int argc, char **argv)
{
    cli_opt_t tab[CLI_MAX_OPTS];
    cli_parser_t p = {"identify", CMD_IDENTIFY, tab, 0, &a->file, {0}, NULL, NULL, 0};
    p.n_opt = ident_table(a, tab);
    p.more = a->more;
    p.n_more = &a->n_more;
    p.max_more = PDT_IDENT_MAX_RECORDS - 1u;
    cli_parse(&p, argc, argv);
    a->have_initial = cli_given(&p, "--initial");
    check_ident_args(&p, a);
}

/* One line for the missing samples the reader found: how many of y (left
 * out of the fit), of u (the u before held), and the first lines. */
static void warn_missing(const char *name, const pdtcli_series_t *s)
{
    if (!s->missing_y && !s->missing_u) return;
    char lines[128];
    size_t used = 0;
    lines[0] = '\0';
    for (unsigned k = 0; k < s->n_first_line && used + 24 < sizeof lines; k++)
        used += (size_t)snprintf(lines + used, sizeof lines - used, "%s%zu", k ? ", " : "",
                                 s->first_line[k]);
    const int more =
        s->n_first_line == PDTCLI_MISSING_FIRST && s->missing_y + s->missing_u > s->n_first_line;
    cli_warn("%s: missing samples (empty cells, markers, --bad-value): %zu of y left out of the "
             "fit, %zu of u holding the u before; line%s %s%s (--bad-rows refuse refuses them)",
             name, s->missing_y, s->missing_u, s->n_first_line > 1 ? "s" : "", lines,
             more ? ", ..." : "");
}

void ident_read(const ident_args_t *a, const char *path, ident_data_t *d)
{
    pdtcli_csv_opts_t o;
    pdtcli_csv_opts_default(&o);
    o.t_col = a->t_col;
    o.u_col = a->u_col;
    o.y_col = a->y_col;
    o.sep = one_char("--sep", a->sep, ",;\t ");
    o.decimal = one_char("--decimal", a->decimal, ".,");
    o.skip = (unsigned)a->skip;
    o.time_unit = a->have_time_unit ? a->time_unit : PDTCLI_TIME_AUTO;
    o.resample = a->resample;
    o.bad_rows = a->bad_rows;
    o.bad_values = a->bad_values.v;
    o.n_bad_values = (size_t)a->bad_values.n;
    o.fs = a->have_fs ? a->fs : 0.0;
    o.units_row = a->units_row;
    o.time_format = a->time_format;
    char err[600];
    if (pdtcli_csv_read_series(path, &o, &d->s, err, sizeof err) != 0)
        cli_fail(EXIT_USAGE, "%s", err);
    const char *name = strcmp(path, "-") == 0 ? "stdin" : path;
    const size_t n = d->s.n;
    if (n < PDT_MIN_SAMPLES)
        cli_fail(EXIT_USAGE, "%s: %zu data row%s, at least %u needed", name, n, n == 1 ? "" : "s",
                 (unsigned)PDT_MIN_SAMPLES);
    if (!((double)(pdt_real_t)d->s.Ts > 0.0) || !isfinite((double)(pdt_real_t)d->s.Ts))
        cli_fail(EXIT_USAGE, "%s: sampling period %.9g s is out of range", name, d->s.Ts);
    if (d->s.units_row)
        cli_warn("%s:%zu: a row of units under the header, skipped (--units-row says so)", name,
                 d->s.units_row);
    if (d->s.jitter_warn)
        cli_warn("%s: %u time stamp%s more than 1%% of Ts off a uniform grid: Ts = %.9g s, the "
                 "median interval",
                 name, d->s.jitter_warn, d->s.jitter_warn == 1 ? "" : "s", d->s.Ts);
    if (d->s.filled)
        cli_warn("%s: --resample filled %u row%s by zero-order hold (Ts = %.9g s)", name,
                 d->s.filled, d->s.filled == 1 ? "" : "s", d->s.Ts);
    if (d->s.has_t && d->s.time_unit_from == PDTCLI_UNIT_DEFAULT && d->s.t0 > 1e11)
        cli_warn("%s: t starts at %.6g: epoch milliseconds or microseconds? (--time-unit ms|us)",
                 name, d->s.t0);
    warn_missing(name, &d->s);
    d->u = malloc(n * sizeof *d->u);
    d->y = malloc(n * sizeof *d->y);
    if (!d->u || !d->y) cli_fail(EXIT_REFUSED, "out of memory");
    for (size_t k = 0; k < n; k++) {
        d->u[k] = (pdt_real_t)d->s.u[k];
        d->y[k] = (pdt_real_t)d->s.y[k];
    }
}

static const char *status_hint(pdt_status_t st)
{
    switch (st) {
    case PDT_ERR_NO_EXCITATION:
        return " (u or y does not move: record a step or other change of the input)";
    case PDT_ERR_TOO_SHORT:
        return " (the record is too short for the dead-time range: record longer)";
    case PDT_ERR_LENGTH:
        return " (the record is too long for the frequency cost: decimate it)";
    case PDT_ERR_ARG:
        return " (a setting is out of range, e.g. a --band outside 0 .. fs/2, or the sampling "
               "period is unusable)";
    case PDT_ERR_NO_FORM:
        return " (no dead time in the scan gave a stable model of this order: try the other "
               "model or --method ga)";
    case PDT_ERR_NOT_AT_REST:
        return " (the frequency and combined costs need u back at its start and y settled at "
               "the end of the record: use --cost simulation)";
    default:
        return "";
    }
}

/* A gross outlier (a logger's bad-value marker): which column, which data
 * row, what value, so that it can be found in the file. */
static void fail_outlier(const ident_data_t *d)
{
    const size_t n = d->s.n;
    const size_t ku = pdt_cost_outlier(d->u, n), ky = pdt_cost_outlier(d->y, n);
    const int in_y = ky < n && (ku >= n || ky <= ku);
    const size_t k = in_y ? ky : ku;
    if (k >= n) cli_fail(EXIT_REFUSED, "cannot identify: %s", pdt_status_str(PDT_ERR_OUTLIER));
    cli_fail(EXIT_REFUSED,
             "cannot identify: %s: %s = %g in data row %zu (counting from 1, after any "
             "--resample fill), orders of magnitude off the rest of the record",
             pdt_status_str(PDT_ERR_OUTLIER), in_y ? "y" : "u", (double)(in_y ? d->y[k] : d->u[k]),
             k + 1u);
}

/* The samples of y that are not finite: missing. */
static size_t missing_of(const ident_data_t *d)
{
    size_t m = 0;
    for (size_t k = 0; k < d->s.n; k++) m += isfinite((double)d->y[k]) ? 0u : 1u;
    return m;
}

/* Whether u is constant over the record while y moves. */
static int still_input(const ident_data_t *d)
{
    int u_moves = 0, y_moves = 0;
    for (size_t k = 1; k < d->s.n; k++) {
        u_moves = u_moves || d->u[k] != d->u[0];
        y_moves = y_moves || (isfinite((double)d->y[k]) && d->y[k] != d->y[0]);
    }
    return !u_moves && y_moves;
}

/* The least --evaluations the library takes with this configuration: the
 * size query refuses a budget below it. */
static uint32_t least_evaluations(pdt_ident_config_t cfg, size_t n)
{
    uint32_t lo = 1, hi = UINT32_MAX / 2;
    cfg.max_evaluations = hi;
    if (pdt_ident_workspace_size(&cfg, n) == 0) return 0;
    while (lo < hi) {
        cfg.max_evaluations = lo + (hi - lo) / 2;
        if (pdt_ident_workspace_size(&cfg, n) > 0)
            hi = cfg.max_evaluations;
        else
            lo = cfg.max_evaluations + 1;
    }
    return lo;
}

void ident_ga_config(const ident_args_t *a, double Ts, pdt_ident_config_t *cfg)
{
    pdt_ident_config_default(cfg);
    cfg->model = (pdt_model_kind_t)a->model;
    cfg->Ts = (pdt_real_t)Ts;
    cfg->cost = (pdt_cost_kind_t)a->cost;
    cfg->seed = a->seed;
    if (a->integer_delay) cfg->delay_mode = PDT_DELAY_INTEGER;
    if (a->have_evaluations) cfg->max_evaluations = (uint32_t)a->evaluations;
    if (a->have_population) cfg->population = (uint32_t)a->population;
    cfg->coarse = (uint32_t)a->coarse;
    if (a->have_td_max) cfg->Td_max = (pdt_real_t)a->td_max;
    if (a->have_weight) cfg->weight = weight_kinds[a->weight];
    cfg->offset = (pdt_ident_offset_t)a->offset;
    cfg->f_lo = (pdt_real_t)a->f_lo;
    cfg->f_hi = (pdt_real_t)a->f_hi;
    if (a->have_phi_t) cfg->phi_t = (pdt_real_t)a->phi_t;
    if (a->have_phi_f) cfg->phi_f = (pdt_real_t)a->phi_f;
    cfg->initial = (pdt_ident_initial_t)a->initial;
    cfg->drift = a->drift != 0;
    cfg->u_before_given = a->have_u_before != 0;
    cfg->u_before = (pdt_real_t)a->u_before;
}

/* The most samples the library leaves out of a record of n (its
 * max_excluded resolved as pdt_ident.h says). */
static unsigned long least_kept(const pdt_ident_config_t *cfg, size_t n)
{
    if (cfg->max_excluded) return cfg->max_excluded;
    return n / 20u > 2u * PDT_IDENT_RUN_MAX ? (unsigned long)(n / 20u) : 2ul * PDT_IDENT_RUN_MAX;
}

/* One identification of the record; with yfit (n reals), the record as
 * the fit saw it. */
static void identify_kind(const ident_args_t *a, const ident_data_t *d, int kind,
                          pdt_ident_result_t *res, pdt_real_t *yfit)
{
    pdt_ident_config_t cfg;
    ident_ga_config(a, d->s.Ts, &cfg);
    cfg.model = (pdt_model_kind_t)kind;
    const size_t n = d->s.n;
    /* A size of 0 means the configuration is refused; pdt_identify then
     * says why, so it is still called. */
    size_t work_len = pdt_ident_workspace_size(&cfg, n);
    void *work = work_len ? malloc(work_len) : NULL;
    pdt_ident_t *ctx = malloc(sizeof *ctx);
    if (!ctx || (work_len && !work)) cli_fail(EXIT_REFUSED, "out of memory");
    const pdt_ident_data_t data = {d->u, d->y, n};
    pdt_status_t st = pdt_identify(ctx, &cfg, &data, work, work_len, res);
    if (st == PDT_ERR_ARG && a->have_evaluations) {
        const uint32_t least = least_evaluations(cfg, n);
        if (least > cfg.max_evaluations)
            cli_fail(EXIT_REFUSED,
                     "cannot identify: --evaluations %lu is below the minimum %lu "
                     "for this model, population and criterion",
                     (unsigned long)a->evaluations, (unsigned long)least);
    }
    if (st == PDT_ERR_OUTLIER && pdt_ident_outlier(ctx) != SIZE_MAX)
        cli_fail(EXIT_REFUSED,
                 "cannot identify: %s: more than %lu samples (%s) to leave out, the first "
                 "at data row %zu (counting from 1): the record is too damaged",
                 pdt_status_str(st), (unsigned long)least_kept(&cfg, n),
                 "missing ones and gross errors", pdt_ident_outlier(ctx) + 1u);
    if (st == PDT_ERR_OUTLIER && missing_of(d) > least_kept(&cfg, n))
        cli_fail(EXIT_REFUSED,
                 "cannot identify: %s: %zu samples of y are missing, more than the %lu that "
                 "may be left out",
                 pdt_status_str(st), missing_of(d), least_kept(&cfg, n));
    if (st == PDT_ERR_OUTLIER) fail_outlier(d);
    if (st == PDT_ERR_NO_EXCITATION && !a->have_u_before && still_input(d))
        cli_fail(EXIT_REFUSED,
                 "cannot identify: %s: u never moves while y does: if the record begins at "
                 "the step, give the input before the first row with --u-before U",
                 pdt_status_str(st));
    if (st != PDT_OK)
        cli_fail(EXIT_REFUSED, "cannot identify: %s%s", pdt_status_str(st), status_hint(st));
    /* The record as the fit saw it: the samples left out replaced by the
     * model's output, for the validation of --model auto. */
    if (yfit) {
        double *ysim = malloc(n * sizeof *ysim);
        if (!ysim) cli_fail(EXIT_REFUSED, "out of memory");
        ident_simulate(&res->model, d->s.Ts, d, res->u0, res->y0, ysim);
        ident_add_state(res, d->s.Ts, n, ysim);
        for (size_t k = 0; k < n; k++)
            yfit[k] = pdt_ident_is_excluded(ctx, k) ? (pdt_real_t)ysim[k] : d->y[k];
        free(ysim);
    }
    free(work);
    free(ctx);
}

/* The samples left out of the fit, on stderr: how many, the first ones. */
static void note_excluded(const pdt_ident_result_t *r)
{
    if (r->excluded == 0u) return;
    char rows[160];
    size_t len = 0;
    const uint32_t listed =
        r->excluded < PDT_IDENT_EXCLUDED_LIST ? r->excluded : PDT_IDENT_EXCLUDED_LIST;
    for (uint32_t i = 0; i < listed && len < sizeof rows; i++)
        len += (size_t)snprintf(rows + len, sizeof rows - len, "%s%lu", i ? ", " : "",
                                (unsigned long)r->excluded_first[i] + 1ul);
    cli_warn("identify: %lu sample%s left out of the fit (%lu missing, %lu gross error%s), data "
             "row%s %s%s (counting from 1)",
             (unsigned long)r->excluded, r->excluded == 1u ? "" : "s", (unsigned long)r->missing,
             (unsigned long)(r->excluded - r->missing), r->excluded - r->missing == 1u ? "" : "s",
             r->excluded == 1u ? "" : "s", rows, r->excluded > listed ? ", ..." : "");
}

/* The model validated on its record (pdt_validate_model), for the order. */
static void validate(const ident_data_t *d, const pdt_real_t *yfit, const pdt_ident_result_t *r,
                     pdt_validate_result_t *v)
{
    const pdt_ident_data_t data = {d->u, yfit, d->s.n};
    const size_t wlen = pdt_validate_workspace_size(d->s.n);
    void *work = wlen ? malloc(wlen) : NULL;
    if (!work) cli_fail(EXIT_REFUSED, "out of memory");
    const pdt_status_t st =
        pdt_validate_model(&r->model, &data, (pdt_real_t)d->s.Ts, r->y0, work, wlen, v);
    free(work);
    if (st != PDT_OK)
        cli_fail(EXIT_REFUSED, "cannot identify: --model auto: validation: %s", pdt_status_str(st));
}

/* --model auto: both models, their validations and the order kept, for
 * the JSON's "order". */
typedef struct order_info {
    int have;
    pdt_model_kind_t kept;
    pdt_ident_result_t r[2]; /* FOPDT, SOPDT */
    pdt_validate_result_t v[2];
} order_info_t;

/* --model auto: a FOPDT and a SOPDT, and the order the evidence supports. */
static void identify_ga(const ident_args_t *a, const ident_data_t *d, pdt_ident_result_t *res,
                        order_info_t *o)
{
    memset(o, 0, sizeof *o);
    if (a->model != MODEL_AUTO) {
        identify_kind(a, d, a->model, res, NULL);
        return;
    }
    const size_t n = d->s.n;
    pdt_real_t *yfit = malloc(2u * n * sizeof *yfit);
    if (!yfit) cli_fail(EXIT_REFUSED, "out of memory");
    identify_kind(a, d, PDT_MODEL_FOPDT, &o->r[0], yfit);
    identify_kind(a, d, PDT_MODEL_SOPDT, &o->r[1], yfit + n);
    validate(d, yfit, &o->r[0], &o->v[0]);
    validate(d, yfit + n, &o->r[1], &o->v[1]);
    free(yfit);
    const pdt_status_t st = pdt_ident_select_order(&o->v[0], &o->v[1], &o->kept);
    if (st != PDT_OK)
        cli_fail(EXIT_REFUSED, "cannot identify: --model auto: %s", pdt_status_str(st));
    o->have = 1;
    *res = o->r[o->kept == PDT_MODEL_SOPDT];
}

/* ,"order":{...} (pdtcli_jb_order). */
static void order_json(pdtcli_jbuf_t *jb, const order_info_t *o)
{
    pdtcli_jb_order(jb, o->kept, o->r, o->v);
}

/* --method elms|eiv: the least-squares delay scan, as a GA result. */
static void identify_ls(const ident_args_t *a, const ident_data_t *d, pdt_ident_result_t *res,
                        size_t *delay_max)
{
    const double Ts = d->s.Ts;
    const size_t n = d->s.n;
    pdt_ls_config_t cfg;
    pdt_ls_config_default(&cfg);
    cfg.model = (pdt_model_kind_t)a->model;
    cfg.method = a->method == METHOD_EIV ? PDT_LS_EIV : PDT_LS_ELMS;
    cfg.Ts = (pdt_real_t)Ts;
    if (a->have_td_max) {
        /* A bound past the record's end is the library's to refuse (too
         * short); the clamp only keeps the conversion defined. */
        double l = floor(a->td_max / Ts + 1e-9);
        cfg.delay_max = l < (double)n ? (size_t)l : n;
    }
    *delay_max = a->have_td_max ? cfg.delay_max : n / 4u;
    pdt_ls_t *ctx = malloc(sizeof *ctx);
    if (!ctx) cli_fail(EXIT_REFUSED, "out of memory");
    pdt_ls_result_t r;
    pdt_status_t st = pdt_ls_identify(ctx, &cfg, d->u, d->y, n, &r);
    free(ctx);
    if (st == PDT_ERR_NONFINITE && d->s.missing_y)
        cli_fail(EXIT_REFUSED,
                 "cannot identify: %s (%zu missing samples of y: --method elms and eiv take "
                 "none; --method ga leaves them out, --bad-rows refuse names the first)",
                 pdt_status_str(st), d->s.missing_y);
    if (st != PDT_OK)
        cli_fail(EXIT_REFUSED, "cannot identify: %s%s", pdt_status_str(st), status_hint(st));
    memset(res, 0, sizeof *res);
    res->model = r.model;
    res->u0 = r.u0;
    res->y0 = r.y0;
    res->cost = r.cost;
    res->fit = (pdt_real_t)ident_simulate(&r.model, Ts, d, r.u0, r.y0, NULL);
    res->evaluations = (uint32_t)(*delay_max - cfg.delay_min + 1u);
}

/* Whether v sits on the bound b of a search (within 0.1 %). */
static int on_bound(double v, double b)
{
    return b > 0.0 && fabs(v - b) <= 1e-3 * b;
}

/* A model that is probably wrong: a fit below that of a constant; for the
 * GA the search's flags, for the scans a dead time on the scan's bound.
 * Returns 1 when warned. */
static int suspect(const ident_args_t *a, const ident_data_t *d, const pdt_ident_result_t *r,
                   size_t delay_max)
{
    const double Ts = d->s.Ts, T = (double)d->s.n * Ts;
    const pdt_model_t *m = &r->model;
    const double Td = m->kind == PDT_MODEL_FOPDT ? (double)m->p.fopdt.Td : (double)m->p.sopdt.Td;
    int warned = 0;
    if (!((double)r->fit >= 0.0)) {
        cli_warn("identify: fit %.4g%% is negative: the model follows the data worse than their "
                 "mean; it is probably wrong",
                 (double)r->fit);
        warned = 1;
    }
    if (a->method != METHOD_GA) {
        const double td_hi = (double)delay_max * Ts;
        if (Td > 0.0 && on_bound(Td, td_hi)) {
            cli_warn("identify: the dead time %.4g s sits on the scan's bound %.4g s (--td-max): "
                     "it is probably wrong",
                     Td, td_hi);
            warned = 1;
        }
        return warned;
    }
    /* The search's own verdict (docs/ident-engine.md). */
    if (r->flags & PDT_IDENT_FLAG_AT_BOUND) {
        cli_warn("identify: a parameter sits on its search bound (a time constant at %.4g s, "
                 "the dead time at %.4g s, or the least damping): the optimum may lie outside; "
                 "record longer or widen --td-max",
                 2.0 * T, a->have_td_max ? a->td_max : T / 3.0);
        warned = 1;
    }
    if (r->flags & PDT_IDENT_FLAG_UNCONFIRMED) {
        cli_warn("identify: the independent searches did not agree (runner-up cost ratio %.4g): "
                 "the model may be a wrong basin; try more --evaluations or a richer excitation",
                 (double)r->runner_up);
        warned = 1;
    }
    if (r->flags & PDT_IDENT_FLAG_NO_RELATION) {
        cli_warn("identify: the model is no better than the output's mean (evidence %.3g, "
                 "at least %g needed; fit %.3g%%, at least %g%% needed): the record shows no "
                 "relation of y to u; check the columns, or record a larger input change",
                 (double)r->evidence, PDT_IDENT_EVIDENCE_MIN, (double)r->fit, PDT_IDENT_FIT_FLOOR);
        warned = 1;
    }
    if (r->flags & PDT_IDENT_FLAG_MID_TRANSIENT) {
        cli_warn("identify: the record does not start at rest, or the model's structure does "
                 "not fit it (a free response from the first row explains its residual): cut the "
                 "record where the process is settled, give --u-before if it begins at a step, "
                 "try --initial estimate, or another --model");
        warned = 1;
    } else if (r->initial == PDT_IDENT_INITIAL_ESTIMATE && a->initial == PDT_IDENT_INITIAL_AUTO) {
        /* A note, not a warning: the answer stands. */
        fprintf(stderr,
                "pdtfit: note: the record does not start at rest: its state at the first row "
                "was estimated (free response %.4g at the first row; --initial estimate)\n",
                (double)r->x0);
    }
    if (r->flags & PDT_IDENT_FLAG_AMBIGUOUS) {
        cli_warn("identify: another structure (the other gain sign, or an integrator for a lag) "
                 "fits about as well: the record cannot tell them apart");
        warned = 1;
    }
    return warned;
}

/* The bootstrap of the answer (--uncertainty: bootstrap, or auto for a
 * SOPDT, whose Fisher information is a poor guide from a step), or NULL
 * when the Fisher information's is reported. */
static const pdtcli_boot_t *bootstrap(const ident_args_t *a, const ident_data_t *d,
                                      const pdt_ident_result_t *r, pdtcli_boot_t *b)
{
    const int on = a->uncertainty == UNC_BOOTSTRAP ||
                   (a->uncertainty == UNC_AUTO && r->model.kind == PDT_MODEL_SOPDT);
    if (a->method != METHOD_GA || !on) return NULL;
    pdt_ident_config_t cfg;
    ident_ga_config(a, d->s.Ts, &cfg);
    cfg.model = r->model.kind;
    const unsigned runs = a->have_boot_runs ? (unsigned)a->boot_runs : PDTCLI_BOOT_RUNS;
    if (pdtcli_bootstrap(&cfg, r, d->u, d->y, d->s.n, runs, b) == 0) return b;
    cli_warn("identify: the bootstrap failed: the Fisher information's uncertainty is printed");
    return NULL;
}

/* ,"tune":{...}: the gains of --tune, or its refusal (status, reason,
 * rule, form) with the model kept. Returns 1 when refused. */
static int tune_json_of(const ident_args_t *a, const pdt_ident_result_t *r, pdtcli_jbuf_t *jb)
{
    pdt_tune_result_t tr;
    memset(&tr, 0, sizeof tr);
    char why[320];
    const pdt_status_t st =
        tune_model_try("identify", &r->model, (double)r->fit, &a->t, &tr, why, sizeof why);
    pdtcli_jb_raw(jb, ",\"tune\":");
    if (st == PDT_OK) {
        tune_json(jb, &a->t, &tr, &tr.fig, (double)NAN, (double)NAN);
        return 0;
    }
    cli_warn("identify: the model is printed, its tuning refused: %s", why);
    /* The reason holds no quote or backslash: it goes in as it is. */
    pdtcli_jb_printf(jb, "{\"status\":\"%s\"", pdt_status_name(st));
    pdtcli_jb_str(jb, "reason", why);
    pdtcli_jb_str(jb, "rule", cli_rule_names[a->t.rule]);
    pdtcli_jb_str(jb, "form", cli_form_names[a->t.form]);
    pdtcli_jb_raw(jb, "}");
    return 1;
}

/* ,"missing":{"count":N,"first":[...],"u_held":M}: the reader's missing
 * samples of y (left out of the fit; the first as indices into the record,
 * from 0) and of u (the u before held), when there are any. */
static void missing_json(pdtcli_jbuf_t *jb, const pdtcli_series_t *s)
{
    pdtcli_jb_printf(jb, ",\"missing\":{\"count\":%zu,\"first\":[", s->missing_y);
    for (unsigned k = 0; k < s->n_first_y; k++)
        pdtcli_jb_printf(jb, "%s%zu", k ? "," : "", s->first_y[k]);
    pdtcli_jb_printf(jb, "],\"u_held\":%zu}", s->missing_u);
}

/* The identification's JSON, with its uncertainty, the reader's missing
 * samples and the order evidence of --model auto; returns its length. */
static int result_json(const ident_args_t *a, const ident_data_t *d, const pdt_ident_result_t *r,
                       const order_info_t *o, char *buf, size_t size)
{
    pdtcli_boot_t boot;
    int len = pdtcli_ident_json_boot(r, d->u, d->y, d->s.Ts, d->s.n, bootstrap(a, d, r, &boot), buf,
                                     size);
    if (len < 0) cli_fail(EXIT_REFUSED, "result too long");
    if (d->s.missing_y || d->s.missing_u) {
        pdtcli_jbuf_t jb;
        pdtcli_jb_init(&jb, buf + len - 1, size - (size_t)len + 1);
        missing_json(&jb, &d->s);
        pdtcli_jb_raw(&jb, "}");
        if (pdtcli_jb_done(&jb) < 0) cli_fail(EXIT_REFUSED, "result too long");
        len = (int)strlen(buf);
    }
    if (o->have) {
        /* In place of the closing brace, which comes back after it. */
        pdtcli_jbuf_t jb;
        pdtcli_jb_init(&jb, buf + len - 1, size - (size_t)len + 1);
        order_json(&jb, o);
        pdtcli_jb_raw(&jb, "}");
        if (pdtcli_jb_done(&jb) < 0) cli_fail(EXIT_REFUSED, "result too long");
        len = (int)strlen(buf);
    }
    return len;
}

/* Prints the result; returns 1 when --tune's gains were refused, *forced
 * 1 when the tuning of a flagged model was forced (exit 3). */
static int print_result(const ident_args_t *a, const ident_data_t *d, const pdt_ident_result_t *r,
                        const order_info_t *o, int *forced)
{
    static char buf[16384];
    const int len = result_json(a, d, r, o, buf, sizeof buf);
    int refused = 0;
    if (a->tune) {
        char flags[256];
        const int n_flags = tune_json_flags(buf, buf + len, flags, sizeof flags);
        *forced = tune_check_flags("identify", flags, n_flags, a->force);
        pdtcli_jbuf_t jb;
        pdtcli_jb_init(&jb, buf + len - 1, sizeof buf - (size_t)len + 1);
        refused = tune_json_of(a, r, &jb);
        pdtcli_jb_raw(&jb, "}");
        if (pdtcli_jb_done(&jb) < 0) cli_fail(EXIT_REFUSED, "result too long");
    }
    if (a->out_sim) ident_write_sim(a->out_sim, d, r);
    if (a->plot) ident_plot(a, d, r);
    puts(buf);
    cli_flush();
    return refused;
}

int cmd_identify(int argc, char **argv)
{
    ident_args_t a;
    memset(&a, 0, sizeof a);
    a.cost = PDT_COST_SIMULATION;
    a.seed = 1;
    parse(&a, argc, argv);
    if (a.n_more > 0u) return ident_several(&a);
    ident_data_t d;
    memset(&d, 0, sizeof d);
    ident_read(&a, a.file, &d);
    pdt_ident_result_t res;
    order_info_t order;
    memset(&order, 0, sizeof order);
    size_t delay_max = 0;
    if (a.method == METHOD_GA)
        identify_ga(&a, &d, &res, &order);
    else
        identify_ls(&a, &d, &res, &delay_max);
    note_excluded(&res);
    int warned = suspect(&a, &d, &res, delay_max), forced = 0;
    const int refused = print_result(&a, &d, &res, &order, &forced);
    warned |= forced;
    free(d.u);
    free(d.y);
    pdtcli_series_free(&d.s);
    return refused ? EXIT_TUNE_REFUSED : warned ? EXIT_SUSPECT : 0;
}
