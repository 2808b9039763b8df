/* pdtfit monitor: the loop-performance monitor (pdt_monitor) over one
 * closed-loop record t, sp, pv, u: the verdict and its figures as one JSON
 * object. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "csv.h"
#include "json.h"
#include "model_json.h"

typedef struct mon_args {
    const char *model, *t_col, *sp_col, *pv_col, *u_col, *sep, *decimal, *file;
    double u_min, u_max;
    uint64_t skip, horizon, decimation, min_samples;
    int have_u_min, have_u_max, have_decimation, have_min_samples;
} mon_args_t;

/* The record: the four signals on one grid. */
typedef struct mon_data {
    size_t n;
    double Ts;
    pdt_real_t *sp, *pv, *u;
} mon_data_t;

static char one_char(const char *opt, const char *s, const char *allowed)
{
    if (!s) return 0;
    if (strcmp(s, "tab") == 0 || strcmp(s, "\\t") == 0) return '\t';
    if (strlen(s) != 1 || !strchr(allowed, s[0]))
        cli_fail(EXIT_USAGE, "monitor: %s takes one of \"%s\"", opt, allowed);
    return s[0];
}

static void parse(mon_args_t *a, int argc, char **argv)
{
    const cli_opt_t tab[] = {
        {"--model", OPT_TEXT, &a->model, NULL, 0, 0, 0, NULL, NULL, 0},
        {"--t", OPT_TEXT, &a->t_col, NULL, 0, 0, 0, NULL, NULL, 0},
        {"--sp", OPT_TEXT, &a->sp_col, NULL, 0, 0, 0, NULL, NULL, 0},
        {"--pv", OPT_TEXT, &a->pv_col, NULL, 0, 0, 0, NULL, NULL, 0},
        {"--u", OPT_TEXT, &a->u_col, NULL, 0, 0, 0, NULL, NULL, 0},
        {"--sep", OPT_TEXT, &a->sep, NULL, 0, 0, 0, NULL, NULL, 0},
        {"--decimal", OPT_TEXT, &a->decimal, NULL, 0, 0, 0, NULL, NULL, 0},
        {"--skip", OPT_UINT, &a->skip, NULL, 0, 0, 1000000, NULL, "a line count 0 .. 1000000", 0},
        {"--u-min", OPT_REAL, &a->u_min, &a->have_u_min, CHK_ANY, 0, 0, NULL, NULL, CLI_REAL_FITS},
        {"--u-max", OPT_REAL, &a->u_max, &a->have_u_max, CHK_ANY, 0, 0, NULL, NULL, CLI_REAL_FITS},
        {"--horizon", OPT_UINT, &a->horizon, NULL, 0, 0, UINT32_MAX, NULL,
         "a sample count >= 0 (0: the whole record)", 0},
        {"--decimation", OPT_UINT, &a->decimation, &a->have_decimation, 0, 1, 100000, NULL,
         "a scan count 1 .. 100000", 0},
        {"--min-samples", OPT_UINT, &a->min_samples, &a->have_min_samples, 0, 16, UINT32_MAX, NULL,
         "a sample count >= 16", 0},
    };
    cli_parser_t p = {"monitor", CMD_MONITOR, tab, sizeof tab / sizeof tab[0], &a->file, {0},
                      NULL,      NULL,        0};
    cli_parse(&p, argc, argv);
    if (!a->file) cli_fail(EXIT_USAGE, "monitor: missing FILE (a CSV file, or - for stdin)");
    if (a->have_u_min != a->have_u_max)
        cli_fail(EXIT_USAGE, "monitor: --u-min and --u-max go together");
    if (a->have_u_min && !(a->u_min < a->u_max))
        cli_fail(EXIT_USAGE, "monitor: --u-min must be below --u-max");
}

/* One pass of the reader over the text: column xcol as "u", pv as "y". */
static void read_pair(const mon_args_t *a, const char *text, const char *xcol, const char *xname,
                      pdtcli_series_t *s)
{
    pdtcli_csv_opts_t o;
    pdtcli_csv_opts_default(&o);
    o.t_col = a->t_col;
    o.u_col = xcol ? xcol : xname;
    o.y_col = a->pv_col;
    o.sep = one_char("--sep", a->sep, ",;\t ");
    o.decimal = one_char("--decimal", a->decimal, ".,");
    o.skip = (unsigned)a->skip;
    o.name = strcmp(a->file, "-") == 0 ? "stdin" : a->file;
    char err[600];
    if (pdtcli_csv_parse_series(text, strlen(text), &o, s, err, sizeof err) != 0)
        cli_fail(EXIT_USAGE, "%s", err);
}

static void read_data(const mon_args_t *a, mon_data_t *d)
{
    char *text = pdtcli_slurp(a->file);
    if (!text) cli_fail(EXIT_USAGE, "monitor: cannot read %s", a->file);
    pdtcli_series_t su, ss;
    read_pair(a, text, a->u_col, "u", &su);
    read_pair(a, text, a->sp_col, "sp", &ss);
    free(text);
    const size_t n = su.n;
    d->n = n;
    d->Ts = su.Ts;
    if (n < 16) cli_fail(EXIT_USAGE, "monitor: %zu data rows, at least 16 needed", n);
    if (!((double)(pdt_real_t)d->Ts > 0.0))
        cli_fail(EXIT_USAGE, "monitor: sampling period %.9g s is out of range", d->Ts);
    d->sp = malloc(n * sizeof *d->sp);
    d->pv = malloc(n * sizeof *d->pv);
    d->u = malloc(n * sizeof *d->u);
    if (!d->sp || !d->pv || !d->u) cli_fail(EXIT_REFUSED, "out of memory");
    for (size_t k = 0; k < n; k++) {
        d->sp[k] = (pdt_real_t)ss.u[k];
        d->pv[k] = (pdt_real_t)su.y[k];
        d->u[k] = (pdt_real_t)su.u[k];
    }
    pdtcli_series_free(&su);
    pdtcli_series_free(&ss);
}

/* A limit the output sits on: its extreme value held (to 1e-9 of the
 * range) in at least 2 % of the rows. */
static int limit_held(const mon_data_t *d, int top, double *at)
{
    double lo = (double)d->u[0], hi = lo;
    for (size_t k = 1; k < d->n; k++) {
        lo = fmin(lo, (double)d->u[k]);
        hi = fmax(hi, (double)d->u[k]);
    }
    const double x = top ? hi : lo, tol = 1e-9 * (hi - lo);
    size_t count = 0;
    for (size_t k = 0; k < d->n; k++) count += fabs((double)d->u[k] - x) <= tol;
    *at = x;
    return hi > lo && count * 50 >= d->n;
}

/* The output limits: given, or the extremes the record holds (see
 * limit_held); a side without one is put a range beyond the data. */
static int output_limits(const mon_args_t *a, const mon_data_t *d, pdt_monitor_config_t *c)
{
    if (a->have_u_min) {
        c->u_min = (pdt_real_t)a->u_min;
        c->u_max = (pdt_real_t)a->u_max;
        return 1;
    }
    double lo, hi;
    const int has_lo = limit_held(d, 0, &lo), has_hi = limit_held(d, 1, &hi);
    if (!has_lo && !has_hi) return 0;
    const double span = hi - lo;
    c->u_min = (pdt_real_t)(has_lo ? lo : lo - 2.0 * span);
    c->u_max = (pdt_real_t)(has_hi ? hi : hi + 2.0 * span);
    return 1;
}

/* The decimation: given, or the least that brings the model's dead time
 * below PDT_MONITOR_ORDER - 2 samples. */
static uint32_t decimation(const mon_args_t *a, const mon_data_t *d, const pdt_model_t *m)
{
    if (a->have_decimation) return (uint32_t)a->decimation;
    if (!m) return 1u;
    const double td = (double)pdt_model_dead_time(m);
    const double q = td / (d->Ts * (double)(PDT_MONITOR_ORDER - 3u));
    return q > 1.0 ? (uint32_t)ceil(q) : 1u;
}

/* Without --model: a FOPDT identified from the record itself (output error
 * on u -> pv, as identify does on closed-loop data); 0 when it fails or
 * fits worse than fit_min percent. */
static int identify_model(const mon_data_t *d, pdt_model_t *m, double *fit)
{
    pdt_ident_config_t cfg;
    pdt_ident_config_default(&cfg);
    cfg.Ts = (pdt_real_t)d->Ts;
    cfg.seed = 1;
    const size_t len = pdt_ident_workspace_size(&cfg, d->n);
    void *work = len ? malloc(len) : NULL;
    pdt_ident_t *ctx = malloc(sizeof *ctx);
    pdt_ident_result_t r;
    const pdt_ident_data_t data = {d->u, d->pv, d->n};
    const pdt_status_t st =
        work && ctx ? pdt_identify(ctx, &cfg, &data, work, len, &r) : PDT_ERR_NOMEM;
    free(work);
    free(ctx);
    if (st != PDT_OK || !((double)r.fit >= 50.0)) return 0;
    *m = r.model;
    *fit = (double)r.fit;
    return 1;
}

static void print_result(const pdt_monitor_result_t *r, const pdt_monitor_config_t *c,
                         int model_given, int limits, double fit)
{
    char buf[2048];
    pdtcli_jbuf_t jb;
    pdtcli_jb_init(&jb, buf, sizeof buf);
    pdtcli_jb_printf(&jb, "{\"verdict\":\"%s\"", pdt_monitor_verdict_str(r->verdict));
    pdtcli_jb_str(&jb, "cause", pdt_monitor_cause_str(r->cause));
    pdtcli_jb_uint(&jb, "samples", r->samples);
    pdtcli_jb_key(&jb, "Ts", (double)c->Ts * c->decimation);
    pdtcli_jb_uint(&jb, "decimation", c->decimation);
    pdtcli_jb_key(&jb, "oscillation", (double)r->oscillation);
    pdtcli_jb_key(&jb, "acf_min", (double)r->acf_min);
    pdtcli_jb_key(&jb, "acf_max", (double)r->acf_max);
    pdtcli_jb_key(&jb, "period", r->acf_period > 0 ? (double)r->acf_period : (double)NAN);
    pdtcli_jb_uint(&jb, "acf_scale", r->acf_scale);
    pdtcli_jb_printf(&jb, ",\"forced\":%s", r->forced ? "true" : "false");
    pdtcli_jb_key(&jb, "regularity", (double)r->regularity);
    pdtcli_jb_key(&jb, "half_periods", (double)r->half_periods);
    pdtcli_jb_key(&jb, "half_period_mean", r->period > 0 ? (double)r->period / 2 : (double)NAN);
    pdtcli_jb_key(&jb, "amplitude", r->period > 0 ? (double)r->amplitude : (double)NAN);
    pdtcli_jb_key(&jb, "corr_ue", (double)r->corr_ue);
    pdtcli_jb_key(&jb, "corr_ve", r->has_corr_ve ? (double)r->corr_ve : (double)NAN);
    pdtcli_jb_key(&jb, "idle_index", (double)r->idle_index);
    pdtcli_jb_key(&jb, "std_e", (double)r->std_e);
    pdtcli_jb_key(&jb, "saturation", r->has_saturation ? (double)r->saturation : (double)NAN);
    pdtcli_jb_key(&jb, "u_min", limits ? (double)c->u_min : (double)NAN);
    pdtcli_jb_key(&jb, "u_max", limits ? (double)c->u_max : (double)NAN);
    pdtcli_jb_key(&jb, "harris", r->has_harris ? (double)r->harris : (double)NAN);
    pdtcli_jb_key(&jb, "delay_samples", c->has_model ? (double)r->delay_samples : (double)NAN);
    pdtcli_jb_key(&jb, "iae_ratio", r->has_sluggish ? (double)r->iae_ratio : (double)NAN);
    pdtcli_jb_key(&jb, "gain_ratio", r->has_mismatch ? (double)r->gain_ratio : (double)NAN);
    pdtcli_jb_key(&jb, "mismatch_t", r->has_mismatch ? (double)r->mismatch_t : (double)NAN);
    pdtcli_jb_str(&jb, "model", model_given == 1 ? "given" : model_given ? "identified" : "none");
    if (c->has_model) {
        pdtcli_jb_raw(&jb, ",\"process\":");
        pdtcli_jb_model(&jb, &c->model, NULL);
        pdtcli_jb_key(&jb, "fit", fit);
        pdtcli_jb_raw(&jb, "}");
    }
    if (!model_given)
        pdtcli_jb_str(&jb, "note",
                      "no --model and none could be identified from the record: harris, "
                      "iae_ratio, gain_ratio are null; sluggishness by the idle index");
    else if (model_given == 2)
        pdtcli_jb_str(&jb, "note",
                      "no --model: the model was identified from this record, so it cannot "
                      "show a change of the process (gain_ratio compares the record with "
                      "itself)");
    else if (!r->has_mismatch)
        pdtcli_jb_str(&jb, "note", "the set-point does not move: the model is not tested");
    pdtcli_jb_raw(&jb, "}");
    if (pdtcli_jb_done(&jb) < 0) cli_fail(EXIT_REFUSED, "monitor: result too long");
    puts(buf);
    cli_flush();
}

int cmd_monitor(int argc, char **argv)
{
    mon_args_t a;
    memset(&a, 0, sizeof a);
    parse(&a, argc, argv);
    pdt_model_t m;
    double fit = 100.0;
    if (a.model) (void)pdtcli_model_from_json("monitor", a.model, &m, &fit, NULL, 0u);
    mon_data_t d;
    read_data(&a, &d);
    const int given = a.model ? 1 : identify_model(&d, &m, &fit) ? 2 : 0;
    pdt_monitor_config_t c;
    pdt_monitor_config_default(&c);
    c.Ts = (pdt_real_t)d.Ts;
    c.horizon = (uint32_t)a.horizon;
    c.decimation = decimation(&a, &d, given ? &m : NULL);
    if (a.have_min_samples) c.min_samples = (uint32_t)a.min_samples;
    c.has_model = given != 0;
    if (given) c.model = m;
    const int limits = output_limits(&a, &d, &c);
    pdt_monitor_t mon;
    pdt_status_t st = pdt_monitor_init(&mon, &c);
    if (st == PDT_ERR_LENGTH)
        cli_fail(EXIT_USAGE, "monitor: the model's dead time is too long for --decimation %u",
                 (unsigned)c.decimation);
    if (st != PDT_OK) cli_fail(EXIT_REFUSED, "monitor: %s", pdt_status_str(st));
    size_t done = 0;
    st = pdt_monitor_scan_block(&mon, d.sp, d.pv, d.u, d.n, &done);
    if (st != PDT_OK)
        cli_fail(EXIT_USAGE, "monitor: data row %zu: %s", done + 1u, pdt_status_str(st));
    pdt_monitor_result_t r;
    if (pdt_monitor_result(&mon, &r) != PDT_OK) cli_fail(EXIT_REFUSED, "monitor: no result");
    print_result(&r, &c, given, limits, fit);
    free(d.sp);
    free(d.pv);
    free(d.u);
    return 0;
}
