#include "uncert.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "model_record.h"
#include "sim_rng.h"

uint32_t pdtcli_printed_values(const pdt_model_t *m, double y0, double v[PDT_IDENT_PAR_COUNT])
{
    uint32_t have = 1u << PDT_IDENT_PAR_Y0 | 1u << PDT_IDENT_PAR_TD;
    for (int i = 0; i < PDT_IDENT_PAR_COUNT; i++) v[i] = (double)NAN;
    v[PDT_IDENT_PAR_Y0] = y0;
    if (m->kind == PDT_MODEL_FOPDT) {
        v[PDT_IDENT_PAR_K] = (double)m->p.fopdt.K;
        v[PDT_IDENT_PAR_TAU] = (double)m->p.fopdt.tau;
        v[PDT_IDENT_PAR_TD] = (double)m->p.fopdt.Td;
        return have | 1u << PDT_IDENT_PAR_K | 1u << PDT_IDENT_PAR_TAU;
    }
    const pdt_model_sopdt_t *s = &m->p.sopdt;
    pdt_model_natural_t nat;
    pdt_model_tc_t tc;
    pdt_model_integ_t in;
    v[PDT_IDENT_PAR_TD] = (double)s->Td;
    v[PDT_IDENT_PAR_A] = (double)s->a;
    v[PDT_IDENT_PAR_B] = (double)s->b;
    have |= 1u << PDT_IDENT_PAR_A | 1u << PDT_IDENT_PAR_B;
    if (pdt_model_sopdt_to_natural(s, &nat) == PDT_OK) {
        v[PDT_IDENT_PAR_K] = (double)nat.K;
        v[PDT_IDENT_PAR_WN] = (double)nat.wn;
        v[PDT_IDENT_PAR_ZETA] = (double)nat.zeta;
        have |= 1u << PDT_IDENT_PAR_K | 1u << PDT_IDENT_PAR_WN | 1u << PDT_IDENT_PAR_ZETA;
        if (pdt_model_sopdt_to_tc(s, &tc) == PDT_OK && !tc.complex) {
            v[PDT_IDENT_PAR_TAU1] = (double)tc.T1;
            v[PDT_IDENT_PAR_TAU2] = (double)tc.T2;
            have |= 1u << PDT_IDENT_PAR_TAU1 | 1u << PDT_IDENT_PAR_TAU2;
        }
    } else if (pdt_model_sopdt_to_integ(s, &in) == PDT_OK) {
        v[PDT_IDENT_PAR_KI] = (double)in.Ki;
        v[PDT_IDENT_PAR_WN] = 0.0;
        v[PDT_IDENT_PAR_TAU2] = (double)in.T;
        have |= 1u << PDT_IDENT_PAR_KI | 1u << PDT_IDENT_PAR_WN | 1u << PDT_IDENT_PAR_TAU2;
    }
    return have;
}

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The residual's samples the noise is measured on: not those the fit left
 * out (a missing y, NaN, and a gross error, beyond 8 scaled median
 * absolute deviations as the library's screen judges). Returns 1 for
 * sample k. */
static int noise_sample(const pdt_real_t *y, const pdt_real_t *ysim, size_t k, double med,
                        double lim)
{
    const double e = (double)(y[k] - ysim[k]);
    return isfinite(e) && (lim <= 0.0 || fabs(e - med) <= lim);
}

/* The median of the finite residuals and the limit of a gross error
 * (0 when it cannot be told). */
static void residual_limit(const pdt_real_t *y, const pdt_real_t *ysim, size_t n, double *med,
                           double *lim)
{
    double *e = malloc((n ? n : 1u) * sizeof *e);
    size_t m = 0;
    *med = 0.0;
    *lim = 0.0;
    if (!e) return;
    for (size_t k = 0; k < n; k++)
        if (isfinite((double)(y[k] - ysim[k]))) e[m++] = (double)(y[k] - ysim[k]);
    if (m > 0) {
        qsort(e, m, sizeof *e, cmp_double);
        *med = e[m / 2];
        for (size_t k = 0; k < m; k++) e[k] = fabs(e[k] - *med);
        qsort(e, m, sizeof *e, cmp_double);
        *lim = 8.0 * 1.4826 * e[m / 2];
    }
    free(e);
}

/* The noise of the bootstrap's records: the residual's standard deviation
 * and lag-one correlation (clamped to [0, 0.95]), over the samples the fit
 * kept. */
static void residual_noise(const pdt_real_t *y, const pdt_real_t *ysim, size_t n, int np,
                           double *sd, double *phi)
{
    double med, lim, mean = 0.0, ss = 0.0, c1 = 0.0;
    size_t m = 0;
    residual_limit(y, ysim, n, &med, &lim);
    for (size_t k = 0; k < n; k++)
        if (noise_sample(y, ysim, k, med, lim)) {
            mean += (double)(y[k] - ysim[k]);
            m++;
        }
    mean /= (double)(m ? m : 1u);
    for (size_t k = 0; k < n; k++) {
        if (!noise_sample(y, ysim, k, med, lim)) continue;
        const double e = (double)(y[k] - ysim[k]) - mean;
        ss += e * e;
        if (k > 0 && noise_sample(y, ysim, k - 1, med, lim))
            c1 += e * ((double)(y[k - 1] - ysim[k - 1]) - mean);
    }
    *sd = sqrt(ss / (double)(m > (size_t)np + 1u ? m - (size_t)np : 1u));
    *phi = ss > 0.0 ? c1 / ss : 0.0;
    *phi = *phi < 0.0 ? 0.0 : *phi > 0.95 ? 0.95 : *phi;
}

/* One bootstrap record identified: its printed values into v. */
static int one_run(const pdt_ident_config_t *cfg, const pdt_real_t *u, pdt_real_t *yb, size_t n,
                   const pdt_real_t *ysim, double sd, double phi, unsigned b, void *work,
                   size_t work_len, pdt_ident_t *ctx, double v[PDT_IDENT_PAR_COUNT], uint32_t *have)
{
    sim_rng64_t rng = {cfg->seed * 0x9E3779B97F4A7C15ull + 7919u * (b + 1u)}; /* its own state */
    double e = sd * sim_rng64_normal(&rng);
    const double w = sd * sqrt(1.0 - phi * phi);
    for (size_t k = 0; k < n; k++) {
        if (k > 0) e = phi * e + w * sim_rng64_normal(&rng);
        yb[k] = (pdt_real_t)((double)ysim[k] + e);
    }
    pdt_ident_config_t c = *cfg;
    c.seed = cfg->seed + 1000003u * (uint64_t)(b + 1u);
    const pdt_ident_data_t data = {u, yb, n};
    pdt_ident_result_t rb;
    if (pdt_identify(ctx, &c, &data, work, work_len, &rb) != PDT_OK) return -1;
    *have = pdtcli_printed_values(&rb.model, (double)rb.y0, v);
    return 0;
}

/* The mean and std of the sorted values x of m runs without the wild
 * ones: a run more than 5 scaled median deviations from the median (a
 * search that ended in another basin, a parameter at a bound) would let
 * one run decide the spread. */
static double robust_mean_std(const double *x, unsigned m, double *sd)
{
    const double med = x[m / 2];
    double *dev = malloc(m * sizeof *dev), mad = 0.0;
    if (dev) {
        for (unsigned b = 0; b < m; b++) dev[b] = fabs(x[b] - med);
        qsort(dev, m, sizeof *dev, cmp_double);
        mad = 1.4826 * dev[m / 2];
        free(dev);
    }
    double s = 0.0, ss = 0.0;
    unsigned k = 0;
    for (unsigned b = 0; b < m; b++)
        if (!(mad > 0.0) || fabs(x[b] - med) <= 5.0 * mad) {
            s += x[b];
            k++;
        }
    const double mean = s / k;
    for (unsigned b = 0; b < m; b++)
        if (!(mad > 0.0) || fabs(x[b] - med) <= 5.0 * mad) ss += (x[b] - mean) * (x[b] - mean);
    *sd = k > 1 ? sqrt(ss / (k - 1)) : (double)NAN;
    return mean;
}

/* Spread, percentiles and covariance of the runs' values (vals[b][i]). */
static void summarise(double (*vals)[PDT_IDENT_PAR_COUNT], const uint32_t *have, unsigned ok,
                      uint32_t want, pdtcli_boot_t *out)
{
    double *col = malloc(ok * sizeof *col), mean[PDT_IDENT_PAR_COUNT] = {0};
    unsigned cnt[PDT_IDENT_PAR_COUNT] = {0};
    for (int i = 0; i < PDT_IDENT_PAR_COUNT; i++) {
        out->std[i] = out->lo[i] = out->hi[i] = (double)NAN;
        unsigned m = 0;
        for (unsigned b = 0; b < ok; b++)
            if ((have[b] >> i) & 1u) col[m++] = vals[b][i];
        cnt[i] = m;
        if (!((want >> i) & 1u) || m < 2 || m * 4u < ok * 3u || !col) continue;
        qsort(col, m, sizeof *col, cmp_double);
        mean[i] = robust_mean_std(col, m, &out->std[i]);
        out->lo[i] = col[(size_t)floor(0.025 * (m - 1) + 0.5)];
        out->hi[i] = col[(size_t)floor(0.975 * (m - 1) + 0.5)];
        out->have |= 1u << i;
    }
    for (int i = 0; i < PDT_IDENT_PAR_COUNT; i++)
        for (int j = 0; j < PDT_IDENT_PAR_COUNT; j++) {
            double c = 0.0;
            unsigned m = 0;
            for (unsigned b = 0; b < ok; b++)
                if (((have[b] >> i) & (have[b] >> j) & 1u) != 0u) {
                    c += (vals[b][i] - mean[i]) * (vals[b][j] - mean[j]);
                    m++;
                }
            const int both = ((out->have >> i) & (out->have >> j) & 1u) != 0u;
            out->cov[i][j] = both && m > 1 ? c / (m - 1) : (double)NAN;
        }
    /* The runs' correlations with the robust std: the diagonal is std^2. */
    double d[PDT_IDENT_PAR_COUNT];
    for (int i = 0; i < PDT_IDENT_PAR_COUNT; i++) d[i] = sqrt(out->cov[i][i]);
    for (int i = 0; i < PDT_IDENT_PAR_COUNT; i++)
        for (int j = 0; j < PDT_IDENT_PAR_COUNT; j++)
            out->cov[i][j] = d[i] > 0.0 && d[j] > 0.0
                                 ? out->cov[i][j] / (d[i] * d[j]) * out->std[i] * out->std[j]
                                 : out->cov[i][j];
    (void)cnt;
    free(col);
}

/* y with each missing sample (not finite) the one before it (the first
 * ones y0): the model is simulated on the record the library checks. */
static pdt_real_t *filled_copy(const pdt_real_t *y, size_t n, pdt_real_t y0)
{
    pdt_real_t *f = malloc((n ? n : 1u) * sizeof *f);
    pdt_real_t last = y0;
    for (size_t k = 0; f && k < n; k++) {
        if (isfinite((double)y[k])) last = y[k];
        f[k] = last;
    }
    return f;
}

int pdtcli_bootstrap(const pdt_ident_config_t *cfg, const pdt_ident_result_t *r,
                     const pdt_real_t *u, const pdt_real_t *y, size_t n, unsigned runs,
                     pdtcli_boot_t *out)
{
    memset(out, 0, sizeof *out);
    const size_t work_len = pdt_ident_workspace_size(cfg, n);
    pdt_real_t *ysim = malloc(n * sizeof *ysim), *yb = malloc(n * sizeof *yb);
    pdt_real_t *yf = filled_copy(y, n, r->y0);
    void *work = work_len ? malloc(work_len) : NULL;
    pdt_ident_t *ctx = malloc(sizeof *ctx);
    double(*vals)[PDT_IDENT_PAR_COUNT] = malloc((runs ? runs : 1u) * sizeof *vals);
    uint32_t *have = malloc((runs ? runs : 1u) * sizeof *have);
    int rc = -1;
    double v0[PDT_IDENT_PAR_COUNT];
    const uint32_t want = pdtcli_printed_values(&r->model, (double)r->y0, v0);
    if (ysim && yb && yf && work && ctx && vals && have &&
        pdtcli_model_on_record(&r->model, (double)cfg->Ts, u, yf, n, r->u0, r->y0, ysim, NULL) ==
            PDT_OK) {
        double sd, phi;
        residual_noise(y, ysim, n, r->model.kind == PDT_MODEL_FOPDT ? 4 : 5, &sd, &phi);
        unsigned ok = 0;
        for (unsigned b = 0; b < runs; b++)
            if (one_run(cfg, u, yb, n, ysim, sd, phi, b, work, work_len, ctx, vals[ok],
                        &have[ok]) == 0)
                ok++;
        out->runs = runs;
        out->ok = ok;
        if (ok >= 2) {
            summarise(vals, have, ok, want, out);
            rc = 0;
        }
    }
    free(have);
    free(vals);
    free(ctx);
    free(work);
    free(yf);
    free(yb);
    free(ysim);
    return rc;
}
