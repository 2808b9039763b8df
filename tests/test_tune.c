/*
 * Tests of the tuning rules and robustness figures against the numpy
 * reference (tests/vectors/tune_vectors.h, written by
 * tools/vectorgen/tune.py), plus the published SIMC numbers of the paper's
 * test system (17), form conversions, Ziegler-Nichols, the figures checked
 * from their definitions, every refusal path and every bad input with the
 * outputs left untouched.
 */
#include "test_util.h"

#include "pdt/pdt_tune.h"

#include "tune_vectors.h"

#define TR(x) ((pdt_real_t)(x))

/* Gains are closed-form: the build's rounding only (float: a few ulps of
 * the float32 model through one conversion of form (2)). */
#if PDT_REAL_DOUBLE
#define GAIN_RTOL 1e-9
#define FIG_RTOL  1e-6
#define WMS_RTOL  1e-3
#else
#define GAIN_RTOL TEST_RTOL
#define FIG_RTOL  1e-3
#define WMS_RTOL  2e-2
#endif
/* The frequency of the peak of |S| is a flat maximum: its location is
 * known to about the square root of the value's precision, so it is
 * checked more loosely (WMS_RTOL) than Ms itself. */

typedef struct guarded_result {
    pdt_tune_result_t r;
    pdt_real_t canary[CANARY_COUNT];
} guarded_result_t;

typedef struct guarded_fig {
    pdt_tune_figures_t f;
    pdt_real_t canary[CANARY_COUNT];
} guarded_fig_t;

typedef struct guarded_gains {
    pdt_tune_gains_t g;
    pdt_real_t canary[CANARY_COUNT];
} guarded_gains_t;

static double g_worst_gain;
static double g_worst_fig;
static double g_worst_wms;

static void note(double *worst, double got, double want)
{
    double e = fabs(got - want) / (fabs(want) > 1e-300 ? fabs(want) : 1.0);
    if (e > *worst) {
        *worst = e;
    }
}

static pdt_model_t model_of(int kind, const double *p)
{
    return vector_model(kind, p);
}

static pdt_model_t fopdt(double K, double tau, double Td)
{
    double p[4] = {K, tau, Td, 0.0};
    return model_of(1, p);
}

static pdt_model_t sopdt_tc(double K, double T1, double T2, double Td)
{
    pdt_model_tc_t tc = {(pdt_real_t)K, (pdt_real_t)T1, (pdt_real_t)T2, false, (pdt_real_t)Td};
    pdt_model_t m;
    memset(&m, 0, sizeof m);
    m.kind = PDT_MODEL_SOPDT;
    assert_int_equal(pdt_model_sopdt_from_tc(&tc, &m.p.sopdt), PDT_OK);
    return m;
}

/* Figures compared with the reference's row: Ms, w_ms (0: not compared,
 * two peaks of about the same height; -1: +infinity), GM (0: none), w_pc, PM, w_gc. */
static void check_figs(const pdt_tune_figures_t *f, const double *want)
{
    assert_close(f->Ms, want[0], FIG_RTOL, 0.0);
    note(&g_worst_fig, (double)f->Ms, want[0]);
    if (want[1] < 0.0) {
        assert_true(isinf(f->w_ms) && f->w_ms > 0);
    } else if (want[1] != 0.0) {
        assert_close(f->w_ms, want[1], WMS_RTOL, 0.0);
        note(&g_worst_wms, (double)f->w_ms, want[1]);
    }
    if (want[2] == 0.0) {
        assert_true(isinf(f->gain_margin) && f->gain_margin > 0);
        assert_true(f->w_pc == TR(0.0));
    } else {
        assert_close(f->gain_margin, want[2], FIG_RTOL, 0.0);
        assert_close(f->w_pc, want[3], FIG_RTOL, 0.0);
        note(&g_worst_fig, (double)f->gain_margin, want[2]);
        note(&g_worst_fig, (double)f->w_pc, want[3]);
    }
    assert_close(f->phase_margin_deg, want[4], FIG_RTOL, 0.0);
    assert_close(f->w_gc, want[5], FIG_RTOL, 0.0);
    note(&g_worst_fig, (double)f->phase_margin_deg, want[4]);
    note(&g_worst_fig, (double)f->w_gc, want[5]);
}

static void check_gains(const pdt_tune_gains_t *g, const double *want)
{
    assert_close(g->Kc, want[0], GAIN_RTOL, 0.0);
    assert_close(g->tauI, want[1], GAIN_RTOL, 0.0);
    assert_close(g->tauD, want[2], GAIN_RTOL, 1e-30);
    assert_close(g->Tf, want[3], GAIN_RTOL, 1e-30);
    for (int i = 0; i < 4; i++) {
        const pdt_real_t *v[4] = {&g->Kc, &g->tauI, &g->tauD, &g->Tf};
        note(&g_worst_gain, (double)*v[i], want[i]);
    }
}

static pdt_tune_config_t config(pdt_tune_rule_t rule, pdt_tune_form_t form)
{
    pdt_tune_config_t c;
    pdt_tune_config_default(&c);
    c.rule = rule;
    c.form = form;
    return c;
}

static void test_compute_vectors(void **state)
{
    (void)state;
    for (size_t i = 0; i < TUNE_VEC_COUNT; i++) {
        pdt_model_t m = model_of(tune_vec_kind[i], &tune_vec_par[4u * i]);
        pdt_tune_config_t c =
            config((pdt_tune_rule_t)tune_vec_rule[i], (pdt_tune_form_t)tune_vec_form[i]);
        c.tau_c = (pdt_real_t)tune_vec_cfg[2u * i];
        c.lambda = (pdt_real_t)tune_vec_cfg[2u * i];
        c.deriv_filter = (pdt_real_t)tune_vec_cfg[2u * i + 1u];
        c.ms_max = TR(0.0);
        guarded_result_t out;
        memset(&out.r, 0x5a, sizeof out.r);
        canary_fill(out.canary, CANARY_COUNT);
        pdt_tune_result_t before = out.r;
        pdt_status_t st = pdt_tune_compute(&m, TR(100.0), &c, &out.r);
        canary_check(out.canary, CANARY_COUNT);
        if ((int)st != tune_vec_status[i]) {
            fail_msg("case %zu: status %d, want %d", i, (int)st, tune_vec_status[i]);
        }
        if (st != PDT_OK) {
            assert_memory_equal(&out.r, &before, sizeof before);
            continue;
        }
        const double *w = &tune_vec_out[TUNE_VEC_NOUT * i];
        check_gains(&out.r.ideal, w);
        if (out.r.series_exists != (w[8] != 0.0) || out.r.series_rule != (w[9] != 0.0)) {
            fail_msg("case %zu: series flags %d %d, want %g %g", i, out.r.series_exists,
                     out.r.series_rule, w[8], w[9]);
        }
        if (out.r.series_exists) {
            check_gains(&out.r.series, w + 4);
        } else {
            assert_true(out.r.series.Kc == TR(0.0) && out.r.series.tauI == TR(0.0));
        }
        assert_close(out.r.knob, w[10], GAIN_RTOL, 0.0);
        check_figs(&out.r.fig, w + 11);
    }
    print_message("compute vectors: %u cases, worst rel. error gains %.2e, Ms/GM/PM/w %.2e, "
                  "w_ms %.2e\n",
                  (unsigned)TUNE_VEC_COUNT, g_worst_gain, g_worst_fig, g_worst_wms);
}

static void test_robustness_vectors(void **state)
{
    (void)state;
    for (size_t i = 0; i < TUNE_ROB_COUNT; i++) {
        pdt_model_t m = model_of(tune_rob_kind[i], &tune_rob_par[4u * i]);
        const double *gv = &tune_rob_gain[4u * i];
        pdt_tune_gains_t g = {(pdt_real_t)gv[0], (pdt_real_t)gv[1], (pdt_real_t)gv[2],
                              (pdt_real_t)gv[3]};
        guarded_fig_t out;
        memset(&out.f, 0x5a, sizeof out.f);
        canary_fill(out.canary, CANARY_COUNT);
        pdt_tune_figures_t before = out.f;
        pdt_status_t st = pdt_tune_robustness(&m, &g, &out.f);
        canary_check(out.canary, CANARY_COUNT);
        if ((int)st != tune_rob_status[i]) {
            fail_msg("robustness case %zu: status %d, want %d", i, (int)st, tune_rob_status[i]);
        }
        if (st != PDT_OK) {
            assert_memory_equal(&out.f, &before, sizeof before);
            continue;
        }
        check_figs(&out.f, &tune_rob_out[6u * i]);
    }
    print_message("robustness vectors: %u cases, worst rel. error %.2e, w_ms %.2e\n",
                  (unsigned)TUNE_ROB_COUNT, g_worst_fig, g_worst_wms);
}

/* Skogestad (2003) on the half-rule models of (17): PI Kc = 0.85,
 * tauI = 2.5; PID (series) Kc = 1.30, tauI = 2, tauD = 1.2. */
static void test_simc_paper_17(void **state)
{
    (void)state;
    pdt_tune_result_t r;
    pdt_model_t f = fopdt(1.0, 2.5, 1.47);
    pdt_tune_config_t c = config(PDT_TUNE_SIMC, PDT_TUNE_PI);
    assert_int_equal(pdt_tune_compute(&f, TR(100.0), &c, &r), PDT_OK);
    assert_close(r.ideal.Kc, 0.85, 0.0, 0.005);
    assert_close(r.ideal.tauI, 2.5, 1e-6, 0.0);
    assert_close(r.ideal.tauD, 0.0, 0.0, 0.0);
    assert_close(r.knob, 1.47, 1e-6, 0.0);
    assert_true(r.series_rule && r.series_exists);
    /* SIMC with tau_c = theta on a FOPDT: GM = pi, PM about 61 deg,
     * Ms about 1.59 (Skogestad 2003). */
    assert_close(r.fig.gain_margin, 3.1416, 1e-3, 0.0);
    assert_close(r.fig.phase_margin_deg, 61.4, 2e-3, 0.0);
    assert_close(r.fig.Ms, 1.59, 3e-3, 0.0);

    pdt_model_t s = sopdt_tc(1.0, 2.0, 1.2, 0.77);
    c.form = PDT_TUNE_PID;
    assert_int_equal(pdt_tune_compute(&s, TR(100.0), &c, &r), PDT_OK);
    assert_true(r.series_rule && r.series_exists);
    assert_close(r.series.Kc, 1.30, 0.0, 0.005);
    assert_close(r.series.tauI, 2.0, 1e-5, 0.0);
    assert_close(r.series.tauD, 1.2, 1e-5, 0.0);
    /* ideal form: f = 1 + 1.2 / 2 = 1.6 */
    assert_close(r.ideal.Kc, 1.6 * 2.0 / 1.54, 1e-5, 0.0);
    assert_close(r.ideal.tauI, 3.2, 1e-5, 0.0);
    assert_close(r.ideal.tauD, 0.75, 1e-5, 0.0);
    assert_close(r.ideal.Tf, 0.12, 1e-5, 0.0); /* series tauD / 10 */
}

static void test_forms(void **state)
{
    (void)state;
    pdt_tune_gains_t s = {TR(1.3), TR(2.0), TR(1.2), TR(0.1)};
    pdt_tune_gains_t i2;
    pdt_tune_gains_t s2;
    assert_int_equal(pdt_tune_to_ideal(&s, &i2), PDT_OK);
    assert_close(i2.Kc, 1.3 * 1.6, 1e-6, 0.0);
    assert_close(i2.tauI, 3.2, 1e-6, 0.0);
    assert_close(i2.tauD, 0.75, 1e-6, 0.0);
    assert_true(i2.Tf == s.Tf);
    assert_int_equal(pdt_tune_to_series(&i2, &s2), PDT_OK);
    assert_close(s2.Kc, 1.3, 1e-6, 0.0);
    assert_close(s2.tauI, 2.0, 1e-6, 0.0);
    assert_close(s2.tauD, 1.2, 1e-6, 0.0);
    /* a series tauD larger than tauI comes back ordered: tauI the larger */
    pdt_tune_gains_t s3 = {TR(1.0), TR(0.5), TR(4.0), TR(0.0)};
    assert_int_equal(pdt_tune_to_ideal(&s3, &i2), PDT_OK);
    assert_int_equal(pdt_tune_to_series(&i2, &s2), PDT_OK);
    assert_close(s2.tauI, 4.0, 1e-5, 0.0);
    assert_close(s2.tauD, 0.5, 1e-5, 0.0);
    assert_close((double)s2.Kc * (1.0 + (double)(s2.tauD / s2.tauI)), i2.Kc, 1e-5, 0.0);
    /* PI: series = ideal */
    pdt_tune_gains_t pi = {TR(-0.7), TR(3.0), TR(0.0), TR(0.0)};
    assert_int_equal(pdt_tune_to_series(&pi, &s2), PDT_OK);
    assert_close(s2.Kc, -0.7, 1e-6, 0.0);
    assert_close(s2.tauI, 3.0, 1e-6, 0.0);
    assert_true(s2.tauD == TR(0.0) && s2.Tf == TR(0.0));
    /* complex zeros: no series form; output untouched */
    pdt_tune_gains_t cz = {TR(1.0), TR(1.0), TR(0.26), TR(0.0)};
    guarded_gains_t o;
    memset(&o.g, 0x5a, sizeof o.g);
    canary_fill(o.canary, CANARY_COUNT);
    pdt_tune_gains_t before = o.g;
    assert_int_equal(pdt_tune_to_series(&cz, &o.g), PDT_ERR_NO_FORM);
    assert_memory_equal(&o.g, &before, sizeof before);
    /* exactly 4 tauD: a double zero */
    cz.tauD = TR(0.25);
    assert_int_equal(pdt_tune_to_series(&cz, &o.g), PDT_OK);
    canary_check(o.canary, CANARY_COUNT);
    assert_close(o.g.tauI, 0.5, 1e-6, 0.0);
    assert_close(o.g.tauD, 0.5, 1e-6, 0.0);
    assert_close(o.g.Kc, 0.5, 1e-6, 0.0);
}

static void test_ziegler_nichols(void **state)
{
    (void)state;
    guarded_gains_t o;
    canary_fill(o.canary, CANARY_COUNT);
    assert_int_equal(pdt_tune_ziegler_nichols(TR(4.0), TR(6.0), PDT_TUNE_PI, &o.g), PDT_OK);
    assert_close(o.g.Kc, 1.8, 1e-6, 0.0);
    assert_close(o.g.tauI, 5.0, 1e-6, 0.0);
    assert_true(o.g.tauD == TR(0.0) && o.g.Tf == TR(0.0));
    assert_int_equal(pdt_tune_ziegler_nichols(TR(-4.0), TR(6.0), PDT_TUNE_PID, &o.g), PDT_OK);
    canary_check(o.canary, CANARY_COUNT);
    assert_close(o.g.Kc, -2.4, 1e-6, 0.0);
    assert_close(o.g.tauI, 3.0, 1e-6, 0.0);
    assert_close(o.g.tauD, 0.75, 1e-6, 0.0);
    pdt_tune_gains_t s;
    assert_int_equal(pdt_tune_to_series(&o.g, &s), PDT_OK);
    assert_close(s.Kc, -1.2, 1e-5, 0.0);
    assert_close(s.tauI, 1.5, 2e-3, 0.0); /* double root: sqrt of rounding */
    assert_close(s.tauD, 1.5, 2e-3, 0.0);

    /* The rule from the model's ultimate point agrees with the one from
     * (Ku, Pu): FOPDT (1, 2.5, 1.47), phase -atan(w tau) - w Td = -pi. */
    pdt_model_t m = fopdt(1.0, 2.5, 1.47);
    double lo = 0.0;
    double hi = 3.14159265358979 / 1.47;
    for (int i = 0; i < 200; i++) {
        double mid = 0.5 * (lo + hi);
        if (-atan(mid * 2.5) - mid * 1.47 > -3.14159265358979) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    double Ku = sqrt(1.0 + (lo * 2.5) * (lo * 2.5));
    double Pu = 2.0 * 3.14159265358979 / lo;
    pdt_tune_config_t c = config(PDT_TUNE_ZN, PDT_TUNE_PI);
    c.ms_max = TR(0.0);
    pdt_tune_result_t r;
    assert_int_equal(pdt_tune_compute(&m, TR(100.0), &c, &r), PDT_OK);
    assert_close(r.ideal.Kc, 0.45 * Ku, 1e-5, 0.0);
    assert_close(r.ideal.tauI, Pu / 1.2, 1e-5, 0.0);
    for (int bad = 0; bad < 6; bad++) {
        pdt_real_t k = TR(1.0);
        pdt_real_t p = TR(1.0);
        int form = PDT_TUNE_PI;
        pdt_tune_gains_t *out = &o.g;
        switch (bad) {
        case 0:
            k = TR(0.0);
            break;
        case 1:
            k = (pdt_real_t)NAN;
            break;
        case 2:
            p = TR(0.0);
            break;
        case 3:
            p = (pdt_real_t)INFINITY;
            break;
        case 4:
            form = 7;
            break;
        default:
            out = NULL;
            break;
        }
        memset(&o.g, 0x5a, sizeof o.g);
        pdt_tune_gains_t before = o.g;
        assert_int_equal(pdt_tune_ziegler_nichols(k, p, (pdt_tune_form_t)form, out), PDT_ERR_ARG);
        assert_memory_equal(&o.g, &before, sizeof before);
    }
}

/* L(jw) = C(jw) G(jw) in double from the library's own model response, to
 * check the figures against their definitions. */
static void loop_at(const pdt_model_t *m, const pdt_tune_gains_t *g, double w, double *re,
                    double *im)
{
    pdt_real_t wr = (pdt_real_t)w;
    pdt_real_t mag;
    pdt_real_t ph;
    assert_int_equal(pdt_model_freq(m, &wr, 1, &mag, &ph), PDT_OK);
    double gr = (double)mag * cos((double)ph);
    double gi = (double)mag * sin((double)ph);
    double tf = (double)g->Tf;
    double td = (double)g->tauD;
    double den = 1.0 + w * w * tf * tf;
    double cr = 1.0 + w * w * td * tf / den;
    double ci = -1.0 / (w * (double)g->tauI) + w * td / den;
    cr *= (double)g->Kc;
    ci *= (double)g->Kc;
    *re = cr * gr - ci * gi;
    *im = cr * gi + ci * gr;
}

static void test_figures_by_definition(void **state)
{
    (void)state;
    pdt_model_t ms[4];
    ms[0] = fopdt(1.0, 2.5, 1.47);
    ms[1] = sopdt_tc(1.0, 2.0, 1.2, 0.77);
    ms[2] = fopdt(-2.0, 10.0, 1.0);
    memset(&ms[3], 0, sizeof ms[3]);
    ms[3].kind = PDT_MODEL_SOPDT;
    ms[3].p.sopdt.k = TR(0.25);
    ms[3].p.sopdt.a = TR(0.5);
    ms[3].p.sopdt.b = TR(0.0);
    ms[3].p.sopdt.Td = TR(0.33);
    for (int i = 0; i < 4; i++) {
        for (int rule = 0; rule < 4; rule++) {
            pdt_tune_config_t c = config((pdt_tune_rule_t)rule, PDT_TUNE_PID);
            c.ms_max = TR(0.0);
            pdt_tune_result_t r;
            assert_int_equal(pdt_tune_compute(&ms[i], TR(100.0), &c, &r), PDT_OK);
            double re;
            double im;
            loop_at(&ms[i], &r.ideal, (double)r.fig.w_gc, &re, &im);
            assert_close(hypot(re, im), 1.0, 1e-4, 0.0);
            assert_close(180.0 + atan2(im, re) * 180.0 / 3.14159265358979, r.fig.phase_margin_deg,
                         1e-3, 0.0);
            loop_at(&ms[i], &r.ideal, (double)r.fig.w_pc, &re, &im);
            assert_true(re < 0.0);
            assert_close(im / re, 0.0, 0.0, 1e-4);
            assert_close(-1.0 / re, r.fig.gain_margin, 1e-4, 0.0);
            loop_at(&ms[i], &r.ideal, (double)r.fig.w_ms, &re, &im);
            assert_close(1.0 / hypot(1.0 + re, im), r.fig.Ms, 1e-4, 0.0);
            /* no sample of a fine sweep beats the reported peak */
            for (int k = 0; k < 2000; k++) {
                double w = (double)r.fig.w_ms * pow(10.0, -2.0 + 4.0 * k / 1999.0);
                loop_at(&ms[i], &r.ideal, w, &re, &im);
                assert_true(1.0 / hypot(1.0 + re, im) <= (double)r.fig.Ms * (1.0 + 1e-4));
            }

            /* The gain margin is where the loop goes unstable. */
            pdt_tune_gains_t g = r.ideal;
            pdt_tune_figures_t f;
            g.Kc = r.ideal.Kc * r.fig.gain_margin * TR(0.98);
            assert_int_equal(pdt_tune_robustness(&ms[i], &g, &f), PDT_OK);
            assert_true(f.gain_margin > TR(1.0) && f.gain_margin < TR(1.03));
            assert_true(f.Ms > TR(20.0));
            g.Kc = r.ideal.Kc * r.fig.gain_margin * TR(1.02);
            assert_int_equal(pdt_tune_robustness(&ms[i], &g, &f), PDT_ERR_UNSTABLE);
        }
    }
}

static void test_unfiltered_derivative_limit(void **state)
{
    (void)state;
    /* IMC PID on a FOPDT without the derivative filter: |L(j inf)| =
     * r = Kc K tauD / tau = theta / (2 lambda + theta). */
    pdt_model_t m = fopdt(1.0, 1.0, 2.0);
    pdt_tune_config_t c = config(PDT_TUNE_IMC, PDT_TUNE_PID);
    c.deriv_filter = TR(0.0);
    c.lambda = TR(0.5);
    c.ms_max = TR(0.0);
    pdt_tune_result_t r;
    assert_int_equal(pdt_tune_compute(&m, TR(100.0), &c, &r), PDT_OK);
    assert_true(r.ideal.Tf == TR(0.0));
    double rr = 2.0 / 3.0;
    assert_true((double)r.fig.Ms >= 1.0 / (1.0 - rr) * (1.0 - 1e-5));
    assert_true((double)r.fig.gain_margin <= 1.0 / rr * (1.0 + 1e-5));
    /* a derivative that alone keeps |L| >= 1 at every high frequency */
    pdt_tune_gains_t g = {TR(1.0), TR(1.0), TR(1.0), TR(0.0)};
    pdt_tune_figures_t f;
    assert_int_equal(pdt_tune_robustness(&m, &g, &f), PDT_ERR_UNSTABLE);
    /* ... and with the filter the same gains are judged on the grid */
    g.Kc = TR(0.3);
    g.tauI = TR(1.5);
    g.Tf = TR(0.1);
    assert_int_equal(pdt_tune_robustness(&m, &g, &f), PDT_OK);
    assert_true(isfinite(f.w_ms) && f.Ms >= TR(1.0));
}

static void test_refusals(void **state)
{
    (void)state;
    guarded_result_t out;
    pdt_tune_result_t before;
    pdt_model_t m = fopdt(1.0, 2.5, 1.47);
    pdt_tune_config_t c = config(PDT_TUNE_SIMC, PDT_TUNE_PI);
    memset(&out.r, 0x5a, sizeof out.r);
    canary_fill(out.canary, CANARY_COUNT);
    before = out.r;

    /* fit below the threshold, and just at it (the default is off) */
    assert_int_equal(pdt_tune_compute(&m, TR(10.0), &c, &out.r), PDT_OK);
    out.r = before;
    c.fit_min = TR(80.0);
    assert_int_equal(pdt_tune_compute(&m, TR(79.9), &c, &out.r), PDT_ERR_POOR_FIT);
    assert_memory_equal(&out.r, &before, sizeof before);
    c.fit_min = TR(50.0);
    assert_int_equal(pdt_tune_compute(&m, TR(79.9), &c, &out.r), PDT_OK);
    c.fit_min = TR(80.0);
    assert_int_equal(pdt_tune_compute(&m, TR(80.0), &c, &out.r), PDT_OK);
    canary_check(out.canary, CANARY_COUNT);
    out.r = before;

    /* Ms above the limit: ZN PID (Ms about 2.75 here) */
    c = config(PDT_TUNE_ZN, PDT_TUNE_PID);
    assert_int_equal(pdt_tune_compute(&m, TR(100.0), &c, &out.r), PDT_ERR_MS_LIMIT);
    assert_memory_equal(&out.r, &before, sizeof before);
    c.ms_max = TR(3.0);
    assert_int_equal(pdt_tune_compute(&m, TR(100.0), &c, &out.r), PDT_OK);
    assert_true(out.r.fig.Ms > TR(2.0) && out.r.fig.Ms < TR(3.0));
    out.r = before;

    /* unstable loop: ZN PID on a strongly delay-dominant process */
    pdt_model_t d = fopdt(1.0, 0.1, 10.0);
    c.ms_max = TR(0.0);
    assert_int_equal(pdt_tune_compute(&d, TR(100.0), &c, &out.r), PDT_ERR_UNSTABLE);
    assert_memory_equal(&out.r, &before, sizeof before);

    /* complex poles: the PI rules and AMIGO see the half rule of the pair
     * split by its real part; ZN without dead time has no form */
    pdt_model_natural_t nat = {TR(1.0), TR(1.0), TR(0.4), TR(0.5)};
    pdt_model_t u;
    memset(&u, 0, sizeof u);
    u.kind = PDT_MODEL_SOPDT;
    assert_int_equal(pdt_model_sopdt_from_natural(&nat, &u.p.sopdt), PDT_OK);
    const pdt_tune_rule_t rules[3] = {PDT_TUNE_SIMC, PDT_TUNE_IMC, PDT_TUNE_AMIGO};
    pdt_model_natural_t nat8 = {TR(1.0), TR(1.0), TR(0.8), TR(0.5)};
    pdt_model_t u8 = u;
    assert_int_equal(pdt_model_sopdt_from_natural(&nat8, &u8.p.sopdt), PDT_OK);
    for (int i = 0; i < 3; i++) {
        c = config(rules[i], PDT_TUNE_PI);
        assert_int_equal(pdt_tune_compute(&u8, TR(100.0), &c, &out.r), PDT_OK);
        assert_true(out.r.ideal.tauD == TR(0.0));
        out.r = before;
    }
    /* SIMC PI: re = a / (2 b) = zeta / wn = 0.8, tau = 1.2, theta = 0.9 */
    c = config(PDT_TUNE_SIMC, PDT_TUNE_PI);
    assert_int_equal(pdt_tune_compute(&u8, TR(100.0), &c, &out.r), PDT_OK);
    assert_true(fabs((double)out.r.ideal.Kc - 1.2 / 1.8) < 1e-5);
    assert_true(fabs((double)out.r.ideal.tauI - 1.2) < 1e-5);
    out.r = before;
    c = config(PDT_TUNE_AMIGO, PDT_TUNE_PID);
    assert_int_equal(pdt_tune_compute(&u8, TR(100.0), &c, &out.r), PDT_OK);
    out.r = before;
    c = config(PDT_TUNE_SIMC, PDT_TUNE_PID);
    assert_int_equal(pdt_tune_compute(&u, TR(100.0), &c, &out.r), PDT_OK);
    assert_false(out.r.series_exists);
    assert_false(out.r.series_rule);
    out.r = before;
    pdt_model_t nd = fopdt(1.0, 1.0, 0.0);
    c = config(PDT_TUNE_ZN, PDT_TUNE_PI);
    assert_int_equal(pdt_tune_compute(&nd, TR(100.0), &c, &out.r), PDT_ERR_NO_FORM);
    /* rules that need dead time given none, with their default knob */
    c = config(PDT_TUNE_SIMC, PDT_TUNE_PI);
    assert_int_equal(pdt_tune_compute(&nd, TR(100.0), &c, &out.r), PDT_ERR_ARG);
    c = config(PDT_TUNE_AMIGO, PDT_TUNE_PI);
    assert_int_equal(pdt_tune_compute(&nd, TR(100.0), &c, &out.r), PDT_ERR_ARG);
    assert_memory_equal(&out.r, &before, sizeof before);
    /* ... and SIMC with tau_c set works: the loop without dead time has no
     * phase crossover */
    c = config(PDT_TUNE_SIMC, PDT_TUNE_PI);
    c.tau_c = TR(0.5);
    assert_int_equal(pdt_tune_compute(&nd, TR(100.0), &c, &out.r), PDT_OK);
    assert_true(isinf(out.r.fig.gain_margin));
    assert_close(out.r.ideal.Kc, 2.0, 1e-6, 0.0);
    canary_check(out.canary, CANARY_COUNT);
}

static void test_bad_inputs(void **state)
{
    (void)state;
    guarded_result_t out;
    memset(&out.r, 0x5a, sizeof out.r);
    canary_fill(out.canary, CANARY_COUNT);
    const pdt_tune_result_t before = out.r;
    pdt_model_t m = fopdt(1.0, 2.5, 1.47);
    pdt_tune_config_t good = config(PDT_TUNE_SIMC, PDT_TUNE_PID);

    assert_int_equal(pdt_tune_compute(NULL, TR(100.0), &good, &out.r), PDT_ERR_ARG);
    assert_int_equal(pdt_tune_compute(&m, TR(100.0), NULL, &out.r), PDT_ERR_ARG);
    assert_int_equal(pdt_tune_compute(&m, TR(100.0), &good, NULL), PDT_ERR_ARG);
    assert_int_equal(pdt_tune_compute(&m, (pdt_real_t)NAN, &good, &out.r), PDT_ERR_ARG);
    assert_int_equal(pdt_tune_compute(&m, (pdt_real_t)INFINITY, &good, &out.r), PDT_ERR_ARG);
    for (int bad = 0; bad < 14; bad++) {
        pdt_tune_config_t c = good;
        switch (bad) {
        case 0:
            c.rule = (pdt_tune_rule_t)9;
            break;
        case 1:
            c.form = (pdt_tune_form_t)-1;
            break;
        case 2:
            c.tau_c = TR(-0.1);
            break;
        case 3:
            c.tau_c = (pdt_real_t)NAN;
            break;
        case 4:
            c.lambda = TR(-1.0);
            break;
        case 5:
            c.lambda = (pdt_real_t)INFINITY;
            break;
        case 6:
            c.deriv_filter = TR(0.5);
            break;
        case 7:
            c.deriv_filter = TR(-10.0);
            break;
        case 8:
            c.deriv_filter = (pdt_real_t)NAN;
            break;
        case 9:
            c.fit_min = (pdt_real_t)NAN;
            break;
        case 10:
            c.ms_max = TR(1.0);
            break;
        case 11:
            c.ms_max = TR(-2.0);
            break;
        case 12:
            c.ms_max = (pdt_real_t)INFINITY;
            break;
        default:
            c.fit_min = (pdt_real_t)-INFINITY;
            break;
        }
        if (pdt_tune_compute(&m, TR(100.0), &c, &out.r) != PDT_ERR_ARG) {
            fail_msg("bad config %d accepted", bad);
        }
    }
    /* invalid models, and a zero gain */
    pdt_model_t bm[5];
    bm[0] = fopdt(1.0, 0.0, 1.0);
    bm[1] = fopdt(1.0, 1.0, -1.0);
    bm[2] = fopdt(0.0, 1.0, 1.0);
    bm[3] = m;
    bm[3].kind = (pdt_model_kind_t)5;
    bm[4] = sopdt_tc(1.0, 2.0, 1.0, 0.5);
    bm[4].p.sopdt.a = TR(0.0);
    for (int i = 0; i < 5; i++) {
        assert_int_equal(pdt_tune_compute(&bm[i], TR(100.0), &good, &out.r), PDT_ERR_ARG);
    }
    assert_memory_equal(&out.r, &before, sizeof before);
    canary_check(out.canary, CANARY_COUNT);

    /* robustness: NULLs, models, gains */
    guarded_fig_t fo;
    memset(&fo.f, 0x5a, sizeof fo.f);
    canary_fill(fo.canary, CANARY_COUNT);
    const pdt_tune_figures_t fbefore = fo.f;
    pdt_tune_gains_t g = {TR(0.85), TR(2.5), TR(0.0), TR(0.0)};
    assert_int_equal(pdt_tune_robustness(NULL, &g, &fo.f), PDT_ERR_ARG);
    assert_int_equal(pdt_tune_robustness(&m, NULL, &fo.f), PDT_ERR_ARG);
    assert_int_equal(pdt_tune_robustness(&m, &g, NULL), PDT_ERR_ARG);
    for (int i = 0; i < 5; i++) {
        assert_int_equal(pdt_tune_robustness(&bm[i], &g, &fo.f), PDT_ERR_ARG);
    }
    for (int bad = 0; bad < 8; bad++) {
        pdt_tune_gains_t b = g;
        switch (bad) {
        case 0:
            b.Kc = TR(0.0);
            break;
        case 1:
            b.Kc = (pdt_real_t)NAN;
            break;
        case 2:
            b.tauI = TR(0.0);
            break;
        case 3:
            b.tauI = (pdt_real_t)INFINITY;
            break;
        case 4:
            b.tauD = TR(-1.0);
            break;
        case 5:
            b.tauD = (pdt_real_t)NAN;
            break;
        case 6:
            b.Tf = TR(-0.1);
            break;
        default:
            b.Tf = (pdt_real_t)INFINITY;
            break;
        }
        assert_int_equal(pdt_tune_robustness(&m, &b, &fo.f), PDT_ERR_ARG);
        guarded_gains_t go;
        memset(&go.g, 0x5a, sizeof go.g);
        pdt_tune_gains_t gbefore = go.g;
        assert_int_equal(pdt_tune_to_series(&b, &go.g), PDT_ERR_ARG);
        assert_int_equal(pdt_tune_to_ideal(&b, &go.g), PDT_ERR_ARG);
        assert_memory_equal(&go.g, &gbefore, sizeof gbefore);
    }
    assert_memory_equal(&fo.f, &fbefore, sizeof fbefore);
    canary_check(fo.canary, CANARY_COUNT);
    assert_int_equal(pdt_tune_to_series(NULL, &g), PDT_ERR_ARG);
    assert_int_equal(pdt_tune_to_series(&g, NULL), PDT_ERR_ARG);
    assert_int_equal(pdt_tune_to_ideal(NULL, &g), PDT_ERR_ARG);
    assert_int_equal(pdt_tune_to_ideal(&g, NULL), PDT_ERR_ARG);
}

/* The same real, bit for bit. */
static bool same_bits(pdt_real_t a, pdt_real_t b)
{
    return memcmp(&a, &b, sizeof a) == 0;
}

static bool same_gains(const pdt_tune_gains_t *a, const pdt_tune_gains_t *b)
{
    return same_bits(a->Kc, b->Kc) && same_bits(a->tauI, b->tauI) && same_bits(a->tauD, b->tauD) &&
           same_bits(a->Tf, b->Tf);
}

/* pdt_tune_begin / pdt_tune_step give pdt_tune_compute's status and result
 * bit for bit on every vector case, with and without an Ms limit, in a
 * bounded number of steps; nothing is written past the state. */
static void test_steps(void **state)
{
    (void)state;
    static pdt_real_t work[PDT_TUNE_RUN_WORKSPACE_SIZE / sizeof(pdt_real_t) + 1u + CANARY_COUNT];
    const size_t len = PDT_TUNE_RUN_WORKSPACE_SIZE;
    assert_int_equal(pdt_tune_run_workspace_size(), len);
    unsigned most = 0u;
    for (size_t i = 0; i < 2u * TUNE_VEC_COUNT; i++) {
        const size_t v = i % TUNE_VEC_COUNT;
        pdt_model_t m = model_of(tune_vec_kind[v], &tune_vec_par[4u * v]);
        pdt_tune_config_t c =
            config((pdt_tune_rule_t)tune_vec_rule[v], (pdt_tune_form_t)tune_vec_form[v]);
        c.tau_c = (pdt_real_t)tune_vec_cfg[2u * v];
        c.lambda = (pdt_real_t)tune_vec_cfg[2u * v];
        c.deriv_filter = (pdt_real_t)tune_vec_cfg[2u * v + 1u];
        c.ms_max = i < TUNE_VEC_COUNT ? TR(0.0) : TR(1.6);
        pdt_tune_result_t one, st_r;
        const pdt_status_t want = pdt_tune_compute(&m, TR(100.0), &c, &one);
        canary_fill((pdt_real_t *)(void *)((unsigned char *)work + len), CANARY_COUNT);
        pdt_status_t st = pdt_tune_begin(&m, TR(100.0), &c, work, len);
        unsigned steps = 0u;
        while (st == PDT_OK || st == PDT_RUNNING) {
            st = pdt_tune_step(work, &st_r);
            steps++;
            if (st != PDT_RUNNING) {
                break;
            }
        }
        canary_check((pdt_real_t *)(void *)((unsigned char *)work + len), CANARY_COUNT);
        most = steps > most ? steps : most;
        if (st != want) {
            fail_msg("case %zu: steps give status %d, pdt_tune_compute %d", i, (int)st, (int)want);
        }
        if (st != PDT_OK) {
            continue;
        }
        assert_true(same_gains(&st_r.ideal, &one.ideal));
        assert_true(same_gains(&st_r.series, &one.series));
        assert_true(st_r.series_exists == one.series_exists);
        assert_true(st_r.series_rule == one.series_rule);
        assert_true(same_bits(st_r.knob, one.knob));
        assert_true(same_bits(st_r.fig.Ms, one.fig.Ms) && same_bits(st_r.fig.w_ms, one.fig.w_ms));
        assert_true(same_bits(st_r.fig.gain_margin, one.fig.gain_margin) &&
                    same_bits(st_r.fig.w_pc, one.fig.w_pc));
        assert_true(same_bits(st_r.fig.phase_margin_deg, one.fig.phase_margin_deg) &&
                    same_bits(st_r.fig.w_gc, one.fig.w_gc));
        /* Done: the next call gives the same again. */
        pdt_tune_result_t again;
        assert_int_equal(pdt_tune_step(work, &again), PDT_OK);
        assert_true(same_bits(again.fig.Ms, one.fig.Ms));
    }
    print_message("tuning in steps: %u cases as pdt_tune_compute, at most %u steps\n",
                  (unsigned)(2u * TUNE_VEC_COUNT), most);
    /* Misuse. */
    pdt_model_t m = model_of(tune_vec_kind[0], &tune_vec_par[0]);
    pdt_tune_config_t c =
        config((pdt_tune_rule_t)tune_vec_rule[0], (pdt_tune_form_t)tune_vec_form[0]);
    pdt_tune_result_t r;
    assert_int_equal(pdt_tune_begin(&m, TR(100.0), &c, NULL, len), PDT_ERR_NOMEM);
    assert_int_equal(pdt_tune_begin(&m, TR(100.0), &c, work, len - 1u), PDT_ERR_NOMEM);
    assert_int_equal(pdt_tune_begin(NULL, TR(100.0), &c, work, len), PDT_ERR_ARG);
    assert_int_equal(pdt_tune_step(work, &r), PDT_ERR_STATE);
    assert_int_equal(pdt_tune_step(NULL, &r), PDT_ERR_ARG);
    assert_int_equal(pdt_tune_begin(&m, TR(100.0), &c, work, len), PDT_OK);
    assert_int_equal(pdt_tune_step(work, NULL), PDT_ERR_ARG);
}

static void test_config_default(void **state)
{
    (void)state;
    pdt_tune_config_t c;
    memset(&c, 0x5a, sizeof c);
    pdt_tune_config_default(&c);
    assert_int_equal(c.rule, PDT_TUNE_SIMC);
    assert_int_equal(c.form, PDT_TUNE_PI);
    assert_true(c.tau_c == TR(0.0) && c.lambda == TR(0.0));
    assert_true(c.deriv_filter == TR(10.0));
    assert_true(c.fit_min == TR(0.0));
    assert_true(c.ms_max == TR(2.0));
    pdt_tune_config_default(NULL);

    /* The defaults give a gain set for every rule and form on a typical
     * model (ZN aside: its Ms is above 2). */
    pdt_model_t m = fopdt(1.0, 2.4, 1.55);
    for (int rule = 0; rule < 3; rule++) {
        for (int form = 0; form < 2; form++) {
            c.rule = (pdt_tune_rule_t)rule;
            c.form = (pdt_tune_form_t)form;
            pdt_tune_result_t r;
            assert_int_equal(pdt_tune_compute(&m, TR(95.0), &c, &r), PDT_OK);
            assert_true(r.fig.Ms < TR(2.0) && r.fig.gain_margin > TR(1.5) &&
                        r.fig.phase_margin_deg > TR(40.0));
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_compute_vectors),
        cmocka_unit_test(test_robustness_vectors),
        cmocka_unit_test(test_simc_paper_17),
        cmocka_unit_test(test_forms),
        cmocka_unit_test(test_ziegler_nichols),
        cmocka_unit_test(test_figures_by_definition),
        cmocka_unit_test(test_unfiltered_derivative_limit),
        cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_bad_inputs),
        cmocka_unit_test(test_steps),
        cmocka_unit_test(test_config_default),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
