/* pdtfit identify FILE FILE ...: several records of one process, one
 * model (docs/several-records.md). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "identify.h"

/* The options one record's identification has and several records'
 * does not: a one-line reason, exit 2. */
static void check_several(const ident_args_t *a)
{
    const char *why = NULL;
    if (a->method != METHOD_GA)
        why = "--method elms and eiv take one record";
    else if (a->model != PDT_MODEL_FOPDT && a->model != PDT_MODEL_SOPDT)
        why = "--model auto takes one record: give --model fopdt or sopdt";
    else if ((pdt_cost_kind_t)a->cost != PDT_COST_SIMULATION)
        why = "only --cost simulation joins records (the frequency criteria do not)";
    else if (a->have_weight || a->band || a->have_phi_t || a->have_phi_f)
        why = "--weight, --band, --phi-t and --phi-f belong to the frequency criteria";
    else if (a->integer_delay)
        why = "--integer-delay: whole-sample dead times differ between periods";
    else if (a->coarse > 1u)
        why = "--coarse: the searches run on the whole records";
    else if (a->offset == PDT_IDENT_OFFSET_REST)
        why = "--offset rest: each record's offset is estimated";
    else if (a->have_initial && a->initial == PDT_IDENT_INITIAL_AUTO)
        why = "--initial auto's test and refit take one record: give rest or estimate";
    else if (a->have_u_before)
        why = "--u-before would give every record one input level";
    else if (a->uncertainty == UNC_BOOTSTRAP || a->have_boot_runs)
        why = "--uncertainty bootstrap and --bootstrap take one record";
    else if (a->out_sim || a->plot)
        why = "--out-sim and --plot write one record";
    else if (a->tune)
        why = "--tune: tune the printed model with pdtfit tune";
    if (why) cli_fail(EXIT_USAGE, "identify: several records: %s", why);
}

/* A record's missing samples are refused with several records. */
static void check_missing(const char *path, const ident_data_t *d)
{
    size_t m = 0, first = 0;
    for (size_t k = 0; k < d->s.n; k++) {
        if (!isfinite((double)d->y[k]) && m++ == 0) first = k;
    }
    if (m)
        cli_fail(EXIT_REFUSED,
                 "cannot identify: %s: %zu missing samples of y (the first at data row %zu): "
                 "several records take none",
                 path, m, first + 1u);
}

/* The result's JSON with the records' part; 1 when a flag was warned. */
static int print_several(const ident_args_t *a, pdt_ident_t *ctx, const pdt_ident_result_t *r,
                         const ident_data_t *d, size_t count)
{
    static char buf[16384];
    int len = pdtcli_ident_json_boot(r, NULL, NULL, d[0].s.Ts, d[0].s.n, NULL, buf, sizeof buf);
    if (len < 0) cli_fail(EXIT_REFUSED, "result too long");
    pdtcli_jbuf_t jb;
    pdtcli_jb_init(&jb, buf + len - 1, sizeof buf - (size_t)len + 1);
    const char *names[PDT_IDENT_MAX_RECORDS];
    names[0] = a->file;
    for (size_t k = 1; k < count; k++) names[k] = a->more[k - 1u];
    const pdt_status_t st = pdtcli_jb_several(&jb, ctx, names, count);
    if (st != PDT_OK) cli_fail(EXIT_REFUSED, "cannot identify: %s", pdt_status_str(st));
    pdtcli_jb_raw(&jb, "}");
    if (pdtcli_jb_done(&jb) < 0) cli_fail(EXIT_REFUSED, "result too long");
    puts(buf);
    cli_flush();
    if (r->flags != 0u)
        cli_warn("identify: the search could not settle everything (flags 0x%lx, "
                 "docs/ident-engine.md): check the model before acting on it",
                 (unsigned long)r->flags);
    return r->flags != 0u;
}

int ident_several(const ident_args_t *a)
{
    check_several(a);
    const size_t count = 1u + a->n_more;
    ident_data_t d[PDT_IDENT_MAX_RECORDS];
    pdt_ident_record_t more[PDT_IDENT_MAX_RECORDS - 1u];
    memset(d, 0, sizeof d);
    for (size_t r = 0; r < count; r++) {
        const char *path = r ? a->more[r - 1u] : a->file;
        ident_read(a, path, &d[r]);
        check_missing(path, &d[r]);
        if (r)
            more[r - 1u] =
                (pdt_ident_record_t){d[r].u, d[r].y, d[r].s.n, (pdt_real_t)d[r].s.Ts, false, 0};
    }
    pdt_ident_config_t cfg;
    ident_ga_config(a, d[0].s.Ts, &cfg);
    cfg.no_screen = true;
    cfg.initial = a->have_initial ? (pdt_ident_initial_t)a->initial : PDT_IDENT_INITIAL_REST;
    cfg.more = more;
    cfg.more_count = (uint32_t)a->n_more;
    const size_t work_len = pdt_ident_workspace_size(&cfg, d[0].s.n);
    void *work = work_len ? malloc(work_len) : NULL;
    pdt_ident_t *ctx = malloc(sizeof *ctx);
    if (!ctx || (work_len && !work)) cli_fail(EXIT_REFUSED, "out of memory");
    const pdt_ident_data_t data = {d[0].u, d[0].y, d[0].s.n};
    pdt_ident_result_t res;
    const pdt_status_t st = pdt_identify(ctx, &cfg, &data, work, work_len, &res);
    if (st != PDT_OK) cli_fail(EXIT_REFUSED, "cannot identify: %s", pdt_status_str(st));
    const int warned = print_several(a, ctx, &res, d, count);
    free(work);
    free(ctx);
    for (size_t r = 0; r < count; r++) {
        free(d[r].u);
        free(d[r].y);
        pdtcli_series_free(&d[r].s);
    }
    return warned ? EXIT_SUSPECT : 0;
}
