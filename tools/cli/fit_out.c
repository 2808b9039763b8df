/* identify --out-sim and --plot: the record against the model. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>

#include "identify.h"
#include "model_record.h"

double ident_simulate(const pdt_model_t *m, double Ts, const ident_data_t *d, pdt_real_t u0,
                      pdt_real_t y0, double *ysim)
{
    const size_t n = d->s.n;
    pdt_real_t *ys = malloc(n * sizeof *ys);
    if (!ys) cli_fail(EXIT_REFUSED, "out of memory");
    pdt_real_t fit = 0;
    const pdt_status_t st = pdtcli_model_on_record(m, Ts, d->u, d->y, n, u0, y0, ys, &fit);
    if (st == PDT_ERR_NOMEM) cli_fail(EXIT_REFUSED, "out of memory");
    for (size_t k = 0; ysim && k < n; k++) ysim[k] = st == PDT_OK ? (double)ys[k] : (double)NAN;
    free(ys);
    return st == PDT_OK ? (double)fit : (double)NAN;
}

void ident_add_state(const pdt_ident_result_t *r, double Ts, size_t n, double *ysim)
{
    pdt_discrete_t dm;
    if (r->initial != PDT_IDENT_INITIAL_ESTIMATE && r->drift == (pdt_real_t)0) return;
    if (pdt_discrete_init(&r->model, (pdt_real_t)Ts, &dm) != PDT_OK) return;
    /* The free response by A(q)'s direct form from y(0) = x0 and, for a
     * SOPDT, y(-1) = x0 - dx0 Ts; the drift about the record's middle. */
    double f1 = (double)r->x0, f2 = (double)r->x0 - (double)r->dx0 * Ts;
    for (size_t k = 0; k < n; k++) {
        double f = f1;
        if (k > 0) {
            f = -(double)dm.a[0] * f1 - (dm.order == 2u ? (double)dm.a[1] * f2 : 0.0);
            f2 = f1;
            f1 = f;
        }
        if (r->initial != PDT_IDENT_INITIAL_ESTIMATE) f = 0.0;
        ysim[k] += f + (double)r->drift * ((double)k - 0.5 * (double)(n - 1)) * Ts;
    }
}

void ident_write_sim(const char *path, const ident_data_t *d, const pdt_ident_result_t *r)
{
    const size_t n = d->s.n;
    double *ysim = malloc(n * sizeof *ysim);
    if (!ysim) cli_fail(EXIT_REFUSED, "out of memory");
    ident_simulate(&r->model, d->s.Ts, d, r->u0, r->y0, ysim);
    ident_add_state(r, d->s.Ts, n, ysim);
    FILE *f = fopen(path, "w");
    if (!f) cli_fail(EXIT_USAGE, "cannot open %s for writing", path);
    fputs("t,u,y,ysim,residual\n", f);
    for (size_t k = 0; k < n; k++)
        fprintf(f, "%.9g,%.9g,%.9g,%.9g,%.9g\n", (double)k * d->s.Ts, (double)d->u[k],
                (double)d->y[k], ysim[k], (double)d->y[k] - ysim[k]);
    free(ysim);
    if (fflush(f) != 0 || ferror(f) || fclose(f) != 0)
        cli_fail(EXIT_REFUSED, "cannot write %s", path);
}

/* s in single quotes for the shell, into buf. */
static int shell_quote(const char *s, char *buf, size_t len)
{
    size_t j = 0;
    if (len < 3) return -1;
    buf[j++] = '\'';
    for (; *s; s++) {
        if (j + 6 >= len) return -1;
        if (*s == '\'') {
            memcpy(buf + j, "'\\''", 4);
            j += 4;
        } else {
            buf[j++] = *s;
        }
    }
    buf[j++] = '\'';
    buf[j] = '\0';
    return 0;
}

static int readable(const char *path)
{
    FILE *f = fopen(path, "r");
    if (f) fclose(f);
    return f != NULL;
}

/* --plot-script, else $PDTFIT_PLOT_SCRIPT, else beside the program: in
 * the source tree (build/<dir>/tools/pdtfit) or an install (bin/pdtfit,
 * share/pdtfit/plot_fit.py). */
static int find_script(const ident_args_t *a, char *out, size_t len)
{
    const char *env = getenv("PDTFIT_PLOT_SCRIPT");
    const char *given = a->plot_script ? a->plot_script : env;
    if (given) {
        snprintf(out, len, "%s", given);
        return readable(out);
    }
    static const char *const rel[] = {"../../../tools/plot_fit.py", "../share/pdtfit/plot_fit.py",
                                      "../../tools/plot_fit.py", "plot_fit.py"};
    const char *slash = strrchr(cli_argv0, '/');
    const int dir_len = slash ? (int)(slash - cli_argv0) : 1;
    const char *dir = slash ? cli_argv0 : ".";
    for (size_t k = 0; k < sizeof rel / sizeof rel[0]; k++) {
        snprintf(out, len, "%.*s/%s", dir_len, dir, rel[k]);
        if (readable(out)) return 1;
    }
    return 0;
}

static void plot_title(const pdt_ident_result_t *r, char *buf, size_t len)
{
    const pdt_model_t *m = &r->model;
    if (m->kind == PDT_MODEL_FOPDT)
        snprintf(buf, len, "fopdt K=%.4g tau=%.4g s Td=%.4g s fit=%.4g%%", (double)m->p.fopdt.K,
                 (double)m->p.fopdt.tau, (double)m->p.fopdt.Td, (double)r->fit);
    else
        snprintf(buf, len, "sopdt a=%.4g b=%.4g Td=%.4g s fit=%.4g%%", (double)m->p.sopdt.a,
                 (double)m->p.sopdt.b, (double)m->p.sopdt.Td, (double)r->fit);
}

void ident_plot(const ident_args_t *a, const ident_data_t *d, const pdt_ident_result_t *r)
{
    char script[1024], csv[1100], title[160], q[4][1200], cmd[5200];
    if (!find_script(a, script, sizeof script))
        cli_fail(EXIT_USAGE,
                 "--plot: plot script not found (%s; give --plot-script or set "
                 "PDTFIT_PLOT_SCRIPT)",
                 script);
    snprintf(csv, sizeof csv, "%s", a->out_sim ? a->out_sim : a->plot);
    if (!a->out_sim) {
        snprintf(csv, sizeof csv, "%s.sim.csv", a->plot);
        ident_write_sim(csv, d, r);
    }
    plot_title(r, title, sizeof title);
    if (shell_quote(script, q[0], sizeof q[0]) || shell_quote(csv, q[1], sizeof q[1]) ||
        shell_quote(a->plot, q[2], sizeof q[2]) || shell_quote(title, q[3], sizeof q[3]))
        cli_fail(EXIT_USAGE, "--plot: path too long");
    snprintf(cmd, sizeof cmd, "python3 %s %s %s --title %s", q[0], q[1], q[2], q[3]);
    fflush(stdout);
    const int rc = system(cmd);
    const int code = rc == -1 ? -1 : (rc >> 8) & 0xff;
    if (!a->out_sim) remove(csv);
    if (code == -1 || code == 127)
        cli_fail(EXIT_REFUSED, "--plot: cannot run python3 (is it installed and on PATH?)");
    if (code == 4)
        cli_fail(EXIT_REFUSED, "--plot: python3 has no matplotlib (pip install matplotlib)");
    if (code != 0) cli_fail(EXIT_REFUSED, "--plot: the plot script failed (exit status %d)", code);
}
