/*
 * Tests of the identification (pdt_ident.h): recovery of known FOPDT and
 * SOPDT models from simulated records (noise, operating points, quantised
 * sensor, every model shape, integer delay, every criterion), the
 * control-band weighting (its band against the true model's phase
 * crossover, and where it does not apply), the steppable API against the
 * blocking call bit for bit, determinism, gain
 * bounds, every bad-input status with the context and result left
 * untouched, and the workspace (size query against the compile-time
 * macro, canaries after its end through a whole run).
 *
 * The records are made here: the true model discretised with
 * pdt_discrete_init and run with pdt_discrete_simulate on the input's
 * deviation, then shifted to an operating point and given noise from a
 * small LCG (same numbers on every platform and in both real types).
 * Each recovery case prints its measured errors.
 */
#include "test_util.h"

#include "sim_process.h"
#include "sim_rng.h"

#define NMAX       4000u
#define POP_MAX    64u
#define WORK_REALS (PDT_IDENT_WORKSPACE_SIZE(NMAX, POP_MAX) / sizeof(pdt_real_t) + 1u)

static pdt_real_t g_u[NMAX];
static pdt_real_t g_y[NMAX];
static pdt_real_t g_dev[NMAX];
static pdt_real_t g_sim[NMAX];
static pdt_real_t g_work[WORK_REALS + CANARY_COUNT];
static pdt_real_t g_work2[WORK_REALS + CANARY_COUNT];
static pdt_ident_t g_ctx;
static pdt_ident_t g_ctx2;

/* Random binary signal of amplitude +-1 (deviation): 0 for the first
 * `quiet` samples, then a level held for `hold` samples, flipped with
 * probability 1/2 at each change. */
static void make_prbs(pdt_real_t *u, size_t n, size_t quiet, size_t hold, uint32_t seed)
{
    /* 2^32 draws from the noise's stream of the same small seed:
     * sim_rng64_seed(s + 1) is the stream of s a draw later, so an input
     * and a noise of nearby seeds would share draws. */
    sim_rng64_t r = sim_rng64_seed((uint64_t)seed << 32);
    pdt_real_t level = (pdt_real_t)1.0;
    for (size_t k = 0; k < n; k++) {
        if (k < quiet) {
            u[k] = (pdt_real_t)0.0;
            continue;
        }
        if ((k - quiet) % hold == 0u && sim_rng64_coin(&r) != 0) {
            level = -level;
        }
        u[k] = level;
    }
}

/* The input of a record made to end at rest, as the frequency criteria
 * need (pdt_ident.c ends_at_rest: the last twentieth's means within a fifth
 * of the ranges): u back at 0 over its last `tail` samples, long enough for
 * the response to settle. A random binary signal alone ends at rest by
 * chance only (29 of seeds 1 to 60 of the 400-sample one below do). */
static void settle_tail(pdt_real_t *u, size_t n, size_t tail)
{
    for (size_t k = n - tail; k < n; k++) {
        u[k] = (pdt_real_t)0.0;
    }
}

/* Pulses that start and end at rest: +1 on [a0, a1), -1 on [b0, b1), +1 on
 * [c0, c1), 0 elsewhere (in fractions of n: the last pulse ends at 0.55 n,
 * so the response has the rest of the record to decay). */
static void make_pulses(pdt_real_t *u, size_t n)
{
    for (size_t k = 0; k < n; k++) {
        double f = (double)k / (double)n;
        pdt_real_t v = (pdt_real_t)0.0;
        if (f >= 0.05 && f < 0.20) {
            v = (pdt_real_t)1.0;
        } else if (f >= 0.30 && f < 0.38) {
            v = (pdt_real_t)-1.0;
        } else if (f >= 0.45 && f < 0.55) {
            v = (pdt_real_t)1.0;
        }
        u[k] = v;
    }
}

/* Record of the model m driven by the deviation input g_dev[0..n-1]:
 * g_u = u0 + amp * dev, g_y = y0 + response + noise at snr_db (none when
 * snr_db <= 0), optionally quantised to 1 % of the noise-free output's
 * range. Returns the noise-free response's range. */
typedef struct record_spec {
    pdt_model_t m;
    pdt_real_t Ts;
    size_t n;
    double u0, y0, amp;
    double snr_db;
    bool quantise;
    uint32_t noise_seed;
} record_spec_t;

static double make_record(const record_spec_t *s)
{
    pdt_discrete_t d;
    assert_true(s->n <= NMAX);
    for (size_t k = 0; k < s->n; k++) {
        g_dev[k] = (pdt_real_t)(s->amp * (double)g_dev[k]);
    }
    assert_int_equal(pdt_discrete_init(&s->m, s->Ts, &d), PDT_OK);
    assert_int_equal(pdt_discrete_simulate(&d, g_dev, s->n, g_sim), PDT_OK);
    double mean = 0.0, lo = 0.0, hi = 0.0;
    for (size_t k = 0; k < s->n; k++) {
        double v = (double)g_sim[k];
        mean += v;
        lo = fmin(lo, v);
        hi = fmax(hi, v);
    }
    mean /= (double)s->n;
    double var = 0.0;
    for (size_t k = 0; k < s->n; k++) {
        double e = (double)g_sim[k] - mean;
        var += e * e;
    }
    double sd = s->snr_db > 0.0 ? sqrt(var / (double)s->n) * pow(10.0, -s->snr_db / 20.0) : 0.0;
    double q = 0.01 * (hi - lo);
    sim_rng64_t r = sim_rng64_seed(s->noise_seed);
    for (size_t k = 0; k < s->n; k++) {
        double y = s->y0 + (double)g_sim[k] + sd * sim_rng64_normal(&r);
        if (s->quantise) {
            y = floor(y / q + 0.5) * q;
        }
        g_u[k] = (pdt_real_t)(s->u0 + (double)g_dev[k]);
        g_y[k] = (pdt_real_t)y;
    }
    return hi - lo;
}

/* ---- Running ---------------------------------------------------------- */

static pdt_ident_config_t base_config(pdt_model_kind_t kind, pdt_real_t Ts)
{
    pdt_ident_config_t cfg;
    pdt_ident_config_default(&cfg);
    cfg.model = kind;
    cfg.Ts = Ts;
    return cfg;
}

/* pdt_identify on g_u, g_y with exactly the workspace the size query asks
 * for, canaries after it checked; the result's bookkeeping checked. */
static void identify(const pdt_ident_config_t *cfg, size_t n, pdt_ident_result_t *res)
{
    pdt_ident_data_t data = {g_u, g_y, n};
    size_t need = pdt_ident_workspace_size(cfg, n);
    assert_true(need > 0u);
    assert_true(need % sizeof(pdt_real_t) == 0u);
    assert_true(need <= PDT_IDENT_WORKSPACE_SIZE(NMAX, POP_MAX));
    size_t reals = need / sizeof(pdt_real_t);
    canary_fill(g_work + reals, CANARY_COUNT);
    assert_int_equal(pdt_identify(&g_ctx, cfg, &data, g_work, need, res), PDT_OK);
    canary_check(g_work + reals, CANARY_COUNT);
    assert_int_equal(pdt_model_check(&res->model), PDT_OK);
    assert_int_equal(res->model.kind, cfg->model);
    assert_true(res->evaluations <= cfg->max_evaluations);
    assert_true(res->evaluations == g_ctx.evaluations);
    assert_true(res->generations >= 1u);
    assert_true(res->u0 == g_u[0]);
    assert_true(isfinite((double)res->cost) && res->cost >= (pdt_real_t)0.0);
    assert_true(isfinite((double)res->fit) && res->fit <= (pdt_real_t)100.0);
}

/* Errors of a FOPDT result: gain and tau relative, Td in units of tau (a
 * relative error would be meaningless for short dead times). */
typedef struct fopdt_err {
    double K, tau, Td;
} fopdt_err_t;

static fopdt_err_t check_fopdt(const char *name, const pdt_ident_result_t *res,
                               const pdt_model_t *truth, double tol_K, double tol_tau,
                               double tol_Td)
{
    const pdt_model_fopdt_t *g = &res->model.p.fopdt, *w = &truth->p.fopdt;
    fopdt_err_t e;
    assert_int_equal(res->model.kind, PDT_MODEL_FOPDT);
    e.K = rel_err((double)g->K, (double)w->K);
    e.tau = rel_err((double)g->tau, (double)w->tau);
    e.Td = fabs((double)g->Td - (double)w->Td) / (double)w->tau;
    print_message("    %-22s K %8.4f (%.2e)  tau %8.4f (%.2e)  Td %8.4f (%.2e tau)  fit %6.2f  "
                  "evals %u\n",
                  name, (double)g->K, e.K, (double)g->tau, e.tau, (double)g->Td, e.Td,
                  (double)res->fit, (unsigned)res->evaluations);
    if (!(e.K <= tol_K && e.tau <= tol_tau && e.Td <= tol_Td)) {
        fail_msg("%s: K %.6g tau %.6g Td %.6g, want %.6g %.6g %.6g", name, (double)g->K,
                 (double)g->tau, (double)g->Td, (double)w->K, (double)w->tau, (double)w->Td);
    }
    return e;
}

/* Errors of a SOPDT with a DC gain: K, wn and zeta relative, Td in units
 * of 1 / wn. */
static void check_sopdt(const char *name, const pdt_ident_result_t *res, const pdt_model_t *truth,
                        double tol_K, double tol_wn, double tol_zeta, double tol_Td)
{
    pdt_model_natural_t g, w;
    assert_int_equal(res->model.kind, PDT_MODEL_SOPDT);
    assert_int_equal(pdt_model_sopdt_to_natural(&truth->p.sopdt, &w), PDT_OK);
    if (pdt_model_sopdt_to_natural(&res->model.p.sopdt, &g) != PDT_OK) {
        fail_msg("%s: no DC gain: k %g a %g b %g", name, (double)res->model.p.sopdt.k,
                 (double)res->model.p.sopdt.a, (double)res->model.p.sopdt.b);
    }
    double eK = rel_err((double)g.K, (double)w.K);
    double ewn = rel_err((double)g.wn, (double)w.wn);
    double ez = rel_err((double)g.zeta, (double)w.zeta);
    double eTd = fabs((double)g.Td - (double)w.Td) * (double)w.wn;
    print_message("    %-22s K %8.4f (%.2e)  wn %8.4f (%.2e)  zeta %6.3f (%.2e)  Td %7.3f "
                  "(%.2e/wn)  fit %6.2f  evals %u\n",
                  name, (double)g.K, eK, (double)g.wn, ewn, (double)g.zeta, ez, (double)g.Td, eTd,
                  (double)res->fit, (unsigned)res->evaluations);
    if (!(eK <= tol_K && ewn <= tol_wn && ez <= tol_zeta && eTd <= tol_Td)) {
        fail_msg("%s: K %.6g wn %.6g zeta %.6g Td %.6g, want %.6g %.6g %.6g %.6g", name,
                 (double)g.K, (double)g.wn, (double)g.zeta, (double)g.Td, (double)w.K, (double)w.wn,
                 (double)w.zeta, (double)w.Td);
    }
}

/* At 30 dB the noise alone leaves a fit of 100 (1 - 10^(-30/20)) = 96.8 %;
 * the recovery cases ask for 95. */
static void check_fit(const pdt_ident_result_t *res, double min_fit)
{
    if (!((double)res->fit >= min_fit)) {
        fail_msg("fit %.4g below %.4g", (double)res->fit, min_fit);
    }
}

/* ---- Recovery --------------------------------------------------------- */

/* The standard FOPDT record: random binary input held 8 samples, 800
 * samples of Ts = 1 s, 30 dB of output noise. */
static void fopdt_case(const char *name, pdt_model_t truth, double u0, double y0, double amp,
                       double snr, bool quantise, double tol_K, double tol_tau, double tol_Td,
                       double min_fit)
{
    record_spec_t s = {truth, (pdt_real_t)1.0, 800u, u0, y0, amp, snr, quantise, 99u};
    pdt_ident_result_t res;
    make_prbs(g_dev, s.n, 10u, 8u, 7u);
    make_record(&s);
    pdt_ident_config_t cfg = base_config(PDT_MODEL_FOPDT, s.Ts);
    identify(&cfg, s.n, &res);
    check_fopdt(name, &res, &truth, tol_K, tol_tau, tol_Td);
    check_fit(&res, min_fit);
    /* The output level to 0.5 % of the output's swing (measured: below
     * 0.1 %). */
    double swing = fabs(amp * (double)truth.p.fopdt.K);
    print_message("    %-22s y0 %.4f (error %.2e of the swing)\n", "", (double)res.y0,
                  fabs((double)res.y0 - y0) / swing);
    assert_close(res.y0, y0, 0.0, 0.005 * swing);
}

/* Tolerances at 30 dB: the errors are those of one noise realisation (the
 * same in both builds, a few tenths of a percent measured), so the bounds
 * are a few times the worst measured: gain 1.5 %, tau 2 %, Td 2 % of tau. */
#define FO_K   0.015
#define FO_TAU 0.02
#define FO_TD  0.02

static void test_recover_fopdt(void **state)
{
    (void)state;
    /* Noise-free: the search itself must land on the truth. */
    fopdt_case("no noise", model_fopdt(2.0, 12.0, 4.37), 0.0, 0.0, 1.0, 0.0, false, 1e-3, 1e-3,
               1e-3, 99.9);
    /* Fractional dead time, 30 dB. */
    fopdt_case("fractional Td", model_fopdt(2.0, 12.0, 4.37), 0.0, 0.0, 1.0, 30.0, false, FO_K,
               FO_TAU, FO_TD, 95.0);
    /* Long dead time, Td = 3 tau. */
    fopdt_case("Td = 3 tau", model_fopdt(1.5, 6.0, 18.0), 0.0, 0.0, 1.0, 30.0, false, FO_K, FO_TAU,
               FO_TD, 95.0);
    /* Short dead time, Td = 0.1 tau. */
    fopdt_case("Td = 0.1 tau", model_fopdt(0.8, 25.0, 2.5), 0.0, 0.0, 1.0, 30.0, false, FO_K,
               FO_TAU, FO_TD, 95.0);
    /* Reverse acting. */
    fopdt_case("reverse acting", model_fopdt(-1.7, 10.0, 3.3), 0.0, 0.0, 1.0, 30.0, false, FO_K,
               FO_TAU, FO_TD, 95.0);
    /* Engineering units: u around 40 (+-5), y around 350; y0 estimated. */
    fopdt_case("u0 = 40, y0 = 350", model_fopdt(3.0, 15.0, 6.6), 40.0, 350.0, 5.0, 30.0, false,
               FO_K, FO_TAU, FO_TD, 95.0);
    /* Quantised sensor: 1 % of the output range, no other noise (an
     * error of 0.29 % of the range rms: about 40 dB here). */
    fopdt_case("quantised 1 %", model_fopdt(2.0, 12.0, 4.37), 40.0, 350.0, 5.0, 0.0, true, FO_K,
               FO_TAU, FO_TD, 95.0);
}

/* SOPDT tolerances at 30 dB, a few times the worst measured (K 0.2 %, wn
 * and zeta 1.3 %, Td 0.01 / wn): the shape of a second-order lag is less
 * well determined by the data than its gain. */
#define SO_K    0.015
#define SO_WN   0.04
#define SO_ZETA 0.04
#define SO_TD   0.05

/* The standard SOPDT record: random binary input held 12 samples, 1000
 * samples of Ts = 0.5 s, 30 dB. */
static void sopdt_record(pdt_model_t truth, double snr)
{
    record_spec_t s = {truth, (pdt_real_t)0.5, 1000u, 10.0, 50.0, 2.0, snr, false, 5u};
    make_prbs(g_dev, s.n, 10u, 12u, 11u);
    make_record(&s);
}

static void test_recover_sopdt(void **state)
{
    pdt_ident_result_t res;
    pdt_ident_config_t cfg = base_config(PDT_MODEL_SOPDT, (pdt_real_t)0.5);
    (void)state;
    /* Overdamped, T1 = 5 T2. */
    pdt_model_t m = model_sopdt_tc(2.0, 10.0, 2.0, 3.3);
    sopdt_record(m, 30.0);
    identify(&cfg, 1000u, &res);
    check_sopdt("overdamped T1 = 5 T2", &res, &m, SO_K, SO_WN, SO_ZETA, SO_TD);
    check_fit(&res, 95.0);
    {
        pdt_model_tc_t g;
        assert_int_equal(pdt_model_sopdt_to_tc(&res.model.p.sopdt, &g), PDT_OK);
        assert_false(g.complex);
        print_message("    %-22s T1 %.4f  T2 %.4f\n", "", (double)g.T1, (double)g.T2);
        assert_close(g.T1, 10.0, 0.03, 0.0);
        assert_close(g.T2, 2.0, 0.10, 0.0);
    }
    /* Critically damped. */
    m = model_sopdt_natural(1.2, 0.2, 1.0, 2.2);
    sopdt_record(m, 30.0);
    identify(&cfg, 1000u, &res);
    check_sopdt("critically damped", &res, &m, SO_K, SO_WN, SO_ZETA, SO_TD);
    check_fit(&res, 95.0);
    /* Underdamped, zeta 0.3. */
    m = model_sopdt_natural(-0.9, 0.3, 0.3, 4.1);
    sopdt_record(m, 30.0);
    identify(&cfg, 1000u, &res);
    check_sopdt("underdamped zeta 0.3", &res, &m, SO_K, SO_WN, SO_ZETA, SO_TD);
    check_fit(&res, 95.0);
}

static void test_recover_integrating(void **state)
{
    pdt_ident_result_t res;
    pdt_ident_config_t cfg = base_config(PDT_MODEL_SOPDT, (pdt_real_t)0.5);
    pdt_model_integ_t g;
    (void)state;
    /* Integrator with a lag: a symmetric random binary input keeps the
     * output bounded. At 30 dB the lag and the dead time trade against
     * each other: over 60 noise realisations (seeds 7919 i) Ki stays within
     * 0.4 %, T within 5 % of 3 in 54 (at worst 8.0 %), Td within 0.1 s in
     * 47, both in 47. Noise seed 2000 is a typical one (T 3.07, Td 2.70). */
    pdt_model_t m = model_integ(0.05, 3.0, 2.7);
    record_spec_t s = {m, (pdt_real_t)0.5, 1000u, 10.0, 50.0, 2.0, 30.0, false, 2000u};
    make_prbs(g_dev, s.n, 10u, 12u, 11u);
    make_record(&s);
    identify(&cfg, s.n, &res);
    const pdt_model_sopdt_t *p = &res.model.p.sopdt;
    double bscale = (double)p->a * (double)p->a;
    print_message("    %-22s k %.5g a %.5g b %.3g (b / a^2 %.2e)  Td %.4f  fit %6.2f  evals %u\n",
                  "integrating", (double)p->k, (double)p->a, (double)p->b, (double)p->b / bscale,
                  (double)p->Td, (double)res.fit, (unsigned)res.evaluations);
    /* b = 0 exactly, or so small that the slow lag (about a / b) is at
     * least 20 record lengths: in this record that is an integrator (the
     * library itself reports b = 0 from 100 record lengths). */
    assert_true((double)p->b <= (double)p->a / (20.0 * 1000.0 * 0.5));
    if (p->b == (pdt_real_t)0.0) {
        assert_int_equal(pdt_model_sopdt_to_integ(p, &g), PDT_OK);
    } else {
        pdt_model_sopdt_t q = *p;
        q.b = (pdt_real_t)0.0;
        assert_int_equal(pdt_model_sopdt_to_integ(&q, &g), PDT_OK);
    }
    print_message("    %-22s Ki %.5f (%.2e)  T %.4f (%.2e)\n", "", (double)g.Ki,
                  rel_err((double)g.Ki, 0.05), (double)g.T, rel_err((double)g.T, 3.0));
    assert_close(g.Ki, 0.05, 0.02, 0.0);
    assert_close(g.T, 3.0, 0.05, 0.0);
    assert_close(g.Td, 2.7, 0.0, 0.1);
    check_fit(&res, 95.0);
}

static void test_recover_integer_delay(void **state)
{
    pdt_ident_result_t res;
    (void)state;
    pdt_model_t m = model_fopdt(2.0, 12.0, 5.0);
    record_spec_t s = {m, (pdt_real_t)1.0, 800u, 0.0, 0.0, 1.0, 30.0, false, 99u};
    make_prbs(g_dev, s.n, 10u, 8u, 7u);
    make_record(&s);
    pdt_ident_config_t cfg = base_config(PDT_MODEL_FOPDT, s.Ts);
    cfg.delay_mode = PDT_DELAY_INTEGER;
    identify(&cfg, s.n, &res);
    check_fopdt("integer delay", &res, &m, 0.03, 0.05, 0.01);
    double l = (double)res.model.p.fopdt.Td / (double)s.Ts;
    assert_true(fabs(l - floor(l + 0.5)) <= 1e-5 * fmax(1.0, l));
    assert_close(res.model.p.fopdt.Td, 5.0, 0.0, 1e-4);
}

/* Noise-free random binary record: the one-step prediction criterion of
 * the paper recovers the model exactly (it is biased only by noise). */
static void test_recover_prediction(void **state)
{
    pdt_ident_result_t res;
    (void)state;
    pdt_model_t m = model_fopdt(2.0, 12.0, 4.37);
    record_spec_t s = {m, (pdt_real_t)1.0, 800u, 40.0, 350.0, 5.0, 0.0, false, 1u};
    make_prbs(g_dev, s.n, 10u, 8u, 7u);
    make_record(&s);
    pdt_ident_config_t cfg = base_config(PDT_MODEL_FOPDT, s.Ts);
    cfg.cost = PDT_COST_PREDICTION;
    identify(&cfg, s.n, &res);
    check_fopdt("prediction, no noise", &res, &m, 0.01, 0.01, 0.01);
    check_fit(&res, 99.0);
    assert_close(res.y0, 350.0, 0.0, 0.05);

    m = model_sopdt_tc(2.0, 10.0, 2.0, 3.3);
    sopdt_record(m, 0.0);
    cfg = base_config(PDT_MODEL_SOPDT, (pdt_real_t)0.5);
    cfg.cost = PDT_COST_PREDICTION;
    identify(&cfg, 1000u, &res);
    check_sopdt("prediction SOPDT", &res, &m, 0.01, 0.01, 0.02, 0.05);
    check_fit(&res, 99.0);
}

/* Pulse record (at rest at both ends) for the frequency-domain criteria. */
static void pulse_record(pdt_model_t truth, double snr)
{
    record_spec_t s = {truth, (pdt_real_t)1.0, 600u, 20.0, 100.0, 4.0, snr, false, 3u};
    make_pulses(g_dev, s.n);
    make_record(&s);
}

static void test_recover_criteria_pulse(void **state)
{
    pdt_ident_result_t res;
    (void)state;
    pdt_model_t m = model_fopdt(1.5, 10.0, 4.6);
    static const pdt_cost_kind_t kinds[] = {PDT_COST_SIMULATION, PDT_COST_COMBINED,
                                            PDT_COST_FREQUENCY};
    static const char *const names[] = {"pulses, simulation", "pulses, combined",
                                        "pulses, frequency"};
    for (size_t i = 0; i < 3u; i++) {
        pulse_record(m, 30.0);
        pdt_ident_config_t cfg = base_config(PDT_MODEL_FOPDT, (pdt_real_t)1.0);
        cfg.cost = kinds[i];
        cfg.Td_max = (pdt_real_t)20.0;
        identify(&cfg, 600u, &res);
        check_fopdt(names[i], &res, &m, FO_K, 0.03, FO_TD);
        check_fit(&res, 95.0);
        assert_close(res.y0, 100.0, 0.0, 0.1);
    }
}

/* ---- Steppable API, determinism, bounds -------------------------------- */

/* Steps ctx to the end with calls of at most `bound` evaluations each,
 * checking the protocol on the way; returns the number of calls. */
static size_t step_to_end(pdt_ident_t *ctx, uint32_t bound)
{
    pdt_ident_result_t early, copy;
    size_t calls = 0;
    pdt_status_t st;
    memset(&early, 0x5a, sizeof early);
    copy = early;
    do {
        uint32_t before = ctx->evaluations;
        uint64_t scored = ctx->samples;
        assert_int_equal(pdt_ident_result(ctx, &early), PDT_ERR_STATE);
        assert_memory_equal(&early, &copy, sizeof early);
        st = pdt_ident_step(ctx, bound);
        calls++;
        assert_true(st == PDT_RUNNING || st == PDT_OK);
        assert_true(ctx->evaluations >= before);
        /* A call asked for fewer than a population group may do one; the
         * budget is of whole-record evaluations (a coarse one scores
         * n / D samples). */
        const uint32_t most = bound > PDT_VECTOR_LANES ? bound : PDT_VECTOR_LANES;
        if (ctx->samples - scored > (uint64_t)most * ctx->data.n) {
            fail_msg("call %zu: %u evaluations (%llu samples) for a bound of %u", calls,
                     (unsigned)(ctx->evaluations - before),
                     (unsigned long long)(ctx->samples - scored), (unsigned)bound);
        }
    } while (st == PDT_RUNNING);
    /* Done stays done and does nothing more. */
    uint32_t done = ctx->evaluations;
    for (int i = 0; i < 3; i++) {
        assert_int_equal(pdt_ident_step(ctx, bound), PDT_OK);
        assert_int_equal(ctx->evaluations, done);
    }
    return calls;
}

/* The result both ways gave, for the caller's own checks. */
static pdt_ident_result_t stepping_matches_blocking(const pdt_ident_config_t *cfg, size_t n,
                                                    uint32_t bound)
{
    pdt_ident_data_t data = {g_u, g_y, n};
    pdt_ident_result_t blocking, stepped;
    size_t need = pdt_ident_workspace_size(cfg, n);
    assert_int_equal(pdt_identify(&g_ctx, cfg, &data, g_work, need, &blocking), PDT_OK);
    assert_int_equal(pdt_ident_init(&g_ctx2, cfg, &data, g_work2, need), PDT_OK);
    size_t calls = step_to_end(&g_ctx2, bound);
    assert_int_equal(pdt_ident_result(&g_ctx2, &stepped), PDT_OK);
    assert_same_ident(&blocking, &stepped);
    assert_true(stepped.evaluations <= cfg->max_evaluations);
    if (bound == 1u) {
        /* One evaluation's samples of the whole record a call, or one
         * group of the population: on a coarse record of n / D samples
         * (and the dead-time profile's points scored from one response)
         * a call makes up to D evaluations. */
        assert_true((uint64_t)calls * PDT_VECTOR_LANES * n >= g_ctx2.samples);
    }
    return stepped;
}

static void test_stepping(void **state)
{
    (void)state;
    pdt_model_t m = model_fopdt(2.0, 12.0, 4.37);
    record_spec_t s = {m, (pdt_real_t)1.0, 400u, 40.0, 350.0, 5.0, 30.0, false, 99u};
    make_prbs(g_dev, s.n, 10u, 8u, 7u);
    settle_tail(g_dev, s.n, 60u);
    make_record(&s);
    static const pdt_cost_kind_t kinds[] = {PDT_COST_SIMULATION, PDT_COST_PREDICTION,
                                            PDT_COST_COMBINED, PDT_COST_FREQUENCY};
    /* CONTROL (the FOPDT's default) switches from the time cost to its
     * band between two evaluations, with a cost preparation of its own:
     * it must land on the same evaluation whatever the calls' bounds.
     * UNIFORM keeps the single-stage search covered. */
    static const pdt_ident_weight_t weights[] = {PDT_IDENT_WEIGHT_CONTROL,
                                                 PDT_IDENT_WEIGHT_UNIFORM};
    for (size_t i = 0; i < 4u; i++) {
        for (size_t w = 0; w < 2u; w++) {
            if (i < 2u && w == 1u) {
                continue; /* no frequency part: the weighting changes nothing */
            }
            pdt_ident_config_t cfg = base_config(PDT_MODEL_FOPDT, s.Ts);
            cfg.cost = kinds[i];
            cfg.weight = weights[w];
            cfg.max_evaluations = 1200u;
            stepping_matches_blocking(&cfg, s.n, 1u);
            stepping_matches_blocking(&cfg, s.n, 7u);
            pdt_ident_result_t res = stepping_matches_blocking(&cfg, s.n, UINT32_MAX);
            bool banded = i >= 2u && w == 0u;
            assert_true(banded ? res.f_band > (pdt_real_t)0.0 : res.f_band == (pdt_real_t)0.0);
        }
    }
    /* SOPDT, plain and integrating. */
    pdt_model_t so = model_sopdt_tc(2.0, 10.0, 2.0, 3.3);
    record_spec_t s2 = {so, (pdt_real_t)0.5, 500u, 10.0, 50.0, 2.0, 30.0, false, 5u};
    make_prbs(g_dev, s2.n, 10u, 12u, 11u);
    make_record(&s2);
    pdt_ident_config_t cfg = base_config(PDT_MODEL_SOPDT, s2.Ts);
    cfg.max_evaluations = 1500u;
    stepping_matches_blocking(&cfg, s2.n, 1u);
}

/* The answer's uncertainty runs in blocks of samples over calls, its
 * state in the population's part of the workspace; a population too
 * small to hold it has the pass in one step. Either way the covariance is
 * pdt_ident_uncertainty's, bit for bit. */
static void test_std_steps(void **state)
{
    (void)state;
    pdt_model_t m = model_fopdt(2.0, 12.0, 4.37);
    record_spec_t s = {m, (pdt_real_t)1.0, 400u, 40.0, 350.0, 5.0, 30.0, false, 99u};
    make_prbs(g_dev, s.n, 10u, 8u, 7u);
    make_record(&s);
    static const uint32_t pops[] = {4u, 0u};
    for (size_t i = 0; i < 2u; i++) {
        pdt_ident_config_t cfg = base_config(PDT_MODEL_FOPDT, s.Ts);
        cfg.population = pops[i];
        cfg.max_evaluations = 1200u;
        const pdt_ident_result_t res = stepping_matches_blocking(&cfg, s.n, 1u);
        pdt_ident_data_t data = {g_u, g_y, s.n};
        pdt_ident_std_t sd;
        assert_int_equal(pdt_ident_uncertainty(&res.model, &data, s.Ts, res.y0, &sd), PDT_OK);
        assert_true(sd.count == 4u);
        assert_memory_equal(&sd, &res.std, sizeof sd);
    }
}

/* The evaluation count never passes max_evaluations, down to the
 * smallest budget the configuration check accepts (the default refinement
 * share). */
static void test_budget(void **state)
{
    pdt_ident_result_t res;
    (void)state;
    pdt_model_t m = model_fopdt(2.0, 12.0, 4.37);
    record_spec_t s = {m, (pdt_real_t)1.0, 400u, 0.0, 0.0, 1.0, 30.0, false, 99u};
    make_prbs(g_dev, s.n, 10u, 8u, 7u);
    settle_tail(g_dev, s.n, 60u);
    make_record(&s);
    for (int model = 1; model <= 2; model++) {
        for (int kind = 0; kind < 4; kind++) {
            pdt_ident_config_t cfg = base_config((pdt_model_kind_t)model, s.Ts);
            uint32_t P = model == 2 ? PDT_IDENT_POPULATION_SOPDT : PDT_IDENT_POPULATION_FOPDT;
            /* 2 P + 1: the GA gets two generations, not three. The scan
             * of the frequency criterion keeps 146 evaluations back, and a
             * SOPDT one more for re-scoring an integrator. */
            uint32_t ga = 2u * P + 1u;
            cfg.cost = (pdt_cost_kind_t)kind;
            /* One stage: CONTROL's own budget is checked below. */
            cfg.weight = PDT_IDENT_WEIGHT_UNIFORM;
            cfg.max_evaluations = ga + cfg.refine_evaluations +
                                  (kind == PDT_COST_FREQUENCY ? 146u : 0u) +
                                  (model == PDT_MODEL_SOPDT ? 1u : 0u);
            identify(&cfg, s.n, &res);
            assert_true(res.generations <= 2u);
            cfg.max_evaluations -= ga - P;
            identify(&cfg, s.n, &res);
            assert_int_equal(res.generations, 1u);
            cfg.max_evaluations--;
            assert_int_equal(pdt_ident_workspace_size(&cfg, s.n), 0u);
        }
    }
    /* CONTROL at the smallest budget the check accepts: the population is
     * scored on the time cost and again on the band, both out of the
     * budget (identify checks it is kept), and the band is still found. */
    for (int model = 1; model <= 2; model++) {
        for (int kind = PDT_COST_FREQUENCY; kind <= PDT_COST_COMBINED; kind++) {
            pdt_ident_config_t cfg = base_config((pdt_model_kind_t)model, s.Ts);
            uint32_t P = model == 2 ? PDT_IDENT_POPULATION_SOPDT : PDT_IDENT_POPULATION_FOPDT;
            cfg.cost = (pdt_cost_kind_t)kind;
            cfg.weight = PDT_IDENT_WEIGHT_CONTROL;
            cfg.max_evaluations = 2u * P + cfg.refine_evaluations +
                                  (kind == PDT_COST_FREQUENCY ? 146u : 0u) +
                                  (model == PDT_MODEL_SOPDT ? 1u : 0u);
            identify(&cfg, s.n, &res);
            assert_true(res.f_band > (pdt_real_t)0.0);
            assert_int_equal(res.generations, 2u);
            cfg.max_evaluations--;
            assert_int_equal(pdt_ident_workspace_size(&cfg, s.n), 0u);
        }
    }
}

/* The FOPDT record of the determinism tests (800 samples of a PRBS,
 * 30 dB) into the globals, and its configuration with seed 12345. */
static pdt_ident_config_t seeded_fopdt_record(record_spec_t *s)
{
    *s = (record_spec_t){
        model_fopdt(2.0, 12.0, 4.37), (pdt_real_t)1.0, 800u, 0.0, 0.0, 1.0, 30.0, false, 99u};
    make_prbs(g_dev, s->n, 10u, 8u, 7u);
    make_record(s);
    pdt_ident_config_t cfg = base_config(PDT_MODEL_FOPDT, s->Ts);
    cfg.seed = 12345u;
    return cfg;
}

static void test_determinism(void **state)
{
    pdt_ident_result_t a, b, c;
    record_spec_t s;
    (void)state;
    pdt_ident_config_t cfg = seeded_fopdt_record(&s);
    const pdt_model_t m = s.m;
    identify(&cfg, s.n, &a);
    identify(&cfg, s.n, &b);
    assert_same_ident(&a, &b);
    /* A restart with the context's own settings: init reads them before
     * it writes the context. */
    size_t need = pdt_ident_workspace_size(&cfg, s.n);
    assert_int_equal(pdt_identify(&g_ctx, &g_ctx.cfg, &g_ctx.data, g_work, need, &b), PDT_OK);
    assert_same_ident(&a, &b);
    for (uint64_t seed = 2u; seed < 6u; seed++) {
        cfg.seed = seed;
        identify(&cfg, s.n, &c);
        check_fopdt("another seed", &c, &m, FO_K, FO_TAU, FO_TD);
        /* Two seeds land on the same optimum, up to the refinement's
         * stopping size. */
        assert_close(c.model.p.fopdt.K, a.model.p.fopdt.K, 0.01, 0.0);
        assert_close(c.model.p.fopdt.tau, a.model.p.fopdt.tau, 0.01, 0.0);
        assert_close(c.model.p.fopdt.Td, a.model.p.fopdt.Td, 0.0, 0.05);
    }
}

/* A search after the first ends its GA once it has caught up with the
 * first's answer (after the stall rule's generations): the second search
 * breeds at most half the first's generations, and the two still agree.
 * A sharing radius of 0.01 keeps the populations from gathering within
 * the niche rule's radius (test_resolved_niches) early, so that this rule
 * alone ends the second GA: the first search alone (searches = 1, the
 * same stream) breeds 43 generations, the second 10. */
static void test_second_search_ends_early(void **state)
{
    pdt_ident_result_t one, two;
    record_spec_t s;
    (void)state;
    pdt_ident_config_t cfg = seeded_fopdt_record(&s);
    const pdt_model_t m = s.m;
    cfg.sigma_share = (pdt_real_t)0.01;
    cfg.searches = 1u;
    identify(&cfg, s.n, &one);
    cfg.searches = 0u;
    identify(&cfg, s.n, &two);
    assert_int_equal(two.searches, 2u);
    assert_int_equal(two.flags, 0u);
    const uint32_t second = two.generations - one.generations;
    assert_true(second >= cfg.stall_generations);
    assert_true(second <= one.generations / 2u);
    check_fopdt("two searches", &two, &m, FO_K, FO_TAU, FO_TD);
    assert_close(two.cost, one.cost, 0.01, 0.0);
}

/* A search whose population has resolved its niches (for a FOPDT under
 * the output error, all but an eighth of it within twice the sharing
 * radius of its best, three generations in a row) ends its GA before the
 * stall rule would: the refinement finishes the creep down its one
 * basin, from the best alone. One search on the seeded record: 8 generations (55 under the
 * stall rule alone), and the same model to the test's tolerances. */
static void test_resolved_niches(void **state)
{
    pdt_ident_result_t one;
    record_spec_t s;
    (void)state;
    pdt_ident_config_t cfg = seeded_fopdt_record(&s);
    const pdt_model_t m = s.m;
    cfg.searches = 1u;
    /* Stepped to its refinement: no other niche to start from, the best
     * alone (with seed 6 the generation's mutants beyond the radius would
     * have started two more runs). */
    cfg.seed = 6u;
    pdt_ident_data_t data = {g_u, g_y, s.n};
    assert_int_equal(
        pdt_ident_init(&g_ctx, &cfg, &data, g_work, pdt_ident_workspace_size(&cfg, s.n)), PDT_OK);
    pdt_status_t st = PDT_RUNNING;
    assert_int_equal(g_ctx.nm.nstarts, 0u);
    while (st == PDT_RUNNING && g_ctx.nm.nstarts == 0u) {
        st = pdt_ident_step(&g_ctx, 1u);
    }
    assert_int_equal(g_ctx.ga.resolved, 3u);
    assert_int_equal(g_ctx.nm.nstarts, 1u);
    cfg.seed = 12345u;
    identify(&cfg, s.n, &one);
    assert_int_equal(g_ctx.ga.resolved, 3u);
    assert_true(g_ctx.ga.stall < cfg.stall_generations);
    assert_true(one.generations < 2u * cfg.stall_generations);
    assert_int_equal(one.flags, 0u);
    check_fopdt("niches resolved", &one, &m, FO_K, FO_TAU, FO_TD);
}

static void test_gain_bounds(void **state)
{
    pdt_ident_result_t res;
    pdt_real_t K;
    (void)state;
    pdt_model_t m = model_fopdt(2.0, 12.0, 4.37);
    record_spec_t s = {m, (pdt_real_t)1.0, 600u, 0.0, 0.0, 1.0, 30.0, false, 99u};
    make_prbs(g_dev, s.n, 10u, 8u, 7u);
    make_record(&s);
    pdt_ident_config_t cfg = base_config(PDT_MODEL_FOPDT, s.Ts);
    cfg.K_min = (pdt_real_t)0.5;
    cfg.K_max = (pdt_real_t)1.5;
    identify(&cfg, s.n, &res);
    assert_true(res.model.p.fopdt.K >= cfg.K_min && res.model.p.fopdt.K <= cfg.K_max);
    assert_close(res.model.p.fopdt.K, 1.5, 1e-5, 0.0);
    cfg.K_min = (pdt_real_t)2.5;
    cfg.K_max = (pdt_real_t)4.0;
    identify(&cfg, s.n, &res);
    assert_true(res.model.p.fopdt.K >= cfg.K_min && res.model.p.fopdt.K <= cfg.K_max);
    assert_close(res.model.p.fopdt.K, 2.5, 1e-5, 0.0);
    /* A box that contains the truth changes nothing much. */
    cfg.K_min = (pdt_real_t)1.0;
    cfg.K_max = (pdt_real_t)3.0;
    identify(&cfg, s.n, &res);
    check_fopdt("K in [1, 3]", &res, &m, FO_K, FO_TAU, FO_TD);
    /* Reverse acting data, positive box: the sign cannot flip. */
    for (size_t k = 0; k < s.n; k++) {
        g_y[k] = -g_y[k];
    }
    cfg.K_min = (pdt_real_t)0.0;
    cfg.K_max = (pdt_real_t)5.0;
    identify(&cfg, s.n, &res);
    assert_true(res.model.p.fopdt.K >= (pdt_real_t)0.0);

    /* SOPDT: the bound is on the DC gain. */
    m = model_sopdt_tc(2.0, 10.0, 2.0, 3.3);
    sopdt_record(m, 30.0);
    cfg = base_config(PDT_MODEL_SOPDT, (pdt_real_t)0.5);
    cfg.integrating = false;
    cfg.K_min = (pdt_real_t)0.5;
    cfg.K_max = (pdt_real_t)1.5;
    identify(&cfg, 1000u, &res);
    assert_int_equal(pdt_model_dc_gain(&res.model, &K), PDT_OK);
    print_message("    SOPDT DC gain in [0.5, 1.5]: %.6f\n", (double)K);
    assert_true(K >= cfg.K_min * (pdt_real_t)(1.0 - 1e-5) &&
                K <= cfg.K_max * (pdt_real_t)(1.0 + 1e-5));
}

/* ---- Control-band weighting ------------------------------------------- */

/* Half the phase crossover of K e^{-Td s} / (tau s + 1), in Hz. w180
 * solves w Td + atan(w tau) = pi; the phase falls monotonically and the
 * dead time alone reaches pi at pi / Td, so bisection on [0, pi / Td]
 * finds it (60 halvings reach double precision). Computed here rather
 * than taken from the library, which uses the same rule. */
static double half_crossover_hz(double tau, double Td)
{
    const double pi = acos(-1.0);
    double lo = 0.0, hi = pi / Td;
    for (int i = 0; i < 60; i++) {
        double mid = 0.5 * (lo + hi);
        if (mid * Td + atan(mid * tau) >= pi) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    return 0.5 * (0.5 * (lo + hi)) / (2.0 * pi);
}

/* A noise-free pulse record that starts and ends at rest (the frequency
 * criteria compare the spectra of the record as it is): 400 samples of
 * 0.2 s, the last pulse over at 44 s, seven time constants of 5 s
 * before the end. */
#define CB_TS 0.2
#define CB_N  400u

static void control_record(pdt_model_t truth)
{
    record_spec_t s = {truth, (pdt_real_t)CB_TS, CB_N, 20.0, 100.0, 4.0, 0.0, false, 3u};
    make_pulses(g_dev, s.n);
    make_record(&s);
}

static void test_control_default(void **state)
{
    pdt_ident_config_t cfg;
    (void)state;
    memset(&cfg, 0x5a, sizeof cfg);
    pdt_ident_config_default(&cfg);
    assert_int_equal(cfg.weight, PDT_IDENT_WEIGHT_AUTO);
    assert_true(cfg.f_lo == (pdt_real_t)0.0 && cfg.f_hi == (pdt_real_t)0.0);
    assert_null(cfg.weights);
    assert_true(cfg.phi_t == (pdt_real_t)1.0 && cfg.phi_f == (pdt_real_t)1.0);
    pdt_ident_config_default(NULL);
}

static void test_control_band(void **state)
{
    pdt_ident_result_t res, res_auto;
    const pdt_model_t m = model_fopdt(2.0, 5.0, 2.0);
    const double want = half_crossover_hz(5.0, 2.0);
    (void)state;
    /* scipy.optimize.brentq on the same equation gives w180 =
     * 0.8952895808286974 rad/s. */
    assert_close(want, 0.5 * 0.8952895808286974 / (2.0 * acos(-1.0)), 1e-12, 0.0);
    control_record(m);

    pdt_ident_config_t cfg = base_config(PDT_MODEL_FOPDT, (pdt_real_t)CB_TS);
    cfg.cost = PDT_COST_COMBINED;
    cfg.weight = PDT_IDENT_WEIGHT_CONTROL;
    identify(&cfg, CB_N, &res);
    check_fopdt("control, combined", &res, &m, FO_K, 0.03, FO_TD);
    check_fit(&res, 99.0);
    assert_close(res.y0, 100.0, 0.0, 0.1);
    /* The band comes from the time-cost stage's GA best, before any
     * refinement: close to the truth's (within 2 %: its crossover moves with
     * the unrefined tau and Td), not equal to it. */
    print_message("    %-22s f_band %.6f Hz, want %.6f (%.2e)\n", "", (double)res.f_band, want,
                  rel_err((double)res.f_band, want));
    assert_close(res.f_band, want, 0.02, 0.0);

    /* AUTO is CONTROL for a FOPDT: the same search, bit for bit. */
    cfg.weight = PDT_IDENT_WEIGHT_AUTO;
    identify(&cfg, CB_N, &res_auto);
    assert_same_ident(&res, &res_auto);

    /* Stepped one evaluation at a time, the same as the blocking call. */
    cfg.weight = PDT_IDENT_WEIGHT_CONTROL;
    stepping_matches_blocking(&cfg, CB_N, 1u);

    /* The frequency criterion alone. */
    cfg.cost = PDT_COST_FREQUENCY;
    identify(&cfg, CB_N, &res);
    check_fopdt("control, frequency", &res, &m, FO_K, 0.03, FO_TD);
    check_fit(&res, 99.0);
    print_message("    %-22s f_band %.6f Hz\n", "", (double)res.f_band);
    assert_true(isfinite((double)res.f_band) && res.f_band > (pdt_real_t)0.0);
    assert_true((double)res.f_band <= 0.5 / CB_TS);
    stepping_matches_blocking(&cfg, CB_N, 1u);
}

/* Every other weighting, criterion or model leaves f_band at 0. */
static void test_control_band_off(void **state)
{
    pdt_ident_result_t res, res_uniform;
    (void)state;
    control_record(model_fopdt(2.0, 5.0, 2.0));
    pdt_ident_config_t cfg = base_config(PDT_MODEL_FOPDT, (pdt_real_t)CB_TS);

    cfg.cost = PDT_COST_COMBINED;
    cfg.weight = PDT_IDENT_WEIGHT_UNIFORM;
    identify(&cfg, CB_N, &res);
    assert_true(res.f_band == (pdt_real_t)0.0);
    cfg.cost = PDT_COST_FREQUENCY;
    identify(&cfg, CB_N, &res);
    assert_true(res.f_band == (pdt_real_t)0.0);
    cfg.cost = PDT_COST_COMBINED;
    cfg.weight = PDT_IDENT_WEIGHT_BAND;
    cfg.f_lo = (pdt_real_t)0.0;
    cfg.f_hi = (pdt_real_t)0.5;
    identify(&cfg, CB_N, &res);
    assert_true(res.f_band == (pdt_real_t)0.0);

    /* The time criteria have no frequency weighting to choose: CONTROL,
     * AUTO and UNIFORM run the same search. */
    static const pdt_cost_kind_t time_kinds[] = {PDT_COST_SIMULATION, PDT_COST_PREDICTION};
    for (size_t i = 0; i < 2u; i++) {
        cfg = base_config(PDT_MODEL_FOPDT, (pdt_real_t)CB_TS);
        cfg.cost = time_kinds[i];
        cfg.weight = PDT_IDENT_WEIGHT_UNIFORM;
        identify(&cfg, CB_N, &res_uniform);
        assert_true(res_uniform.f_band == (pdt_real_t)0.0);
        cfg.weight = PDT_IDENT_WEIGHT_CONTROL;
        identify(&cfg, CB_N, &res);
        assert_same_ident(&res, &res_uniform);
        cfg.weight = PDT_IDENT_WEIGHT_AUTO;
        identify(&cfg, CB_N, &res);
        assert_same_ident(&res, &res_uniform);
    }

    /* AUTO is UNIFORM for a SOPDT. */
    pdt_model_t so = model_sopdt_tc(2.0, 5.0, 1.5, 2.0);
    control_record(so);
    cfg = base_config(PDT_MODEL_SOPDT, (pdt_real_t)CB_TS);
    cfg.cost = PDT_COST_COMBINED;
    identify(&cfg, CB_N, &res);
    assert_true(res.f_band == (pdt_real_t)0.0);
    cfg.weight = PDT_IDENT_WEIGHT_UNIFORM;
    identify(&cfg, CB_N, &res_uniform);
    assert_same_ident(&res, &res_uniform);
    /* CONTROL asked for explicitly bands a SOPDT too, from its own phase:
     * w Td + atan(w T1) + atan(w T2) = pi at w180 = 0.587963092662129
     * rad/s (scipy.optimize.brentq). The time-cost stage's SOPDT, not yet
     * refined, is looser than a FOPDT's (2 % measured). */
    cfg.weight = PDT_IDENT_WEIGHT_CONTROL;
    identify(&cfg, CB_N, &res);
    const double want_so = 0.5 * 0.587963092662129 / (2.0 * acos(-1.0));
    print_message("    %-22s f_band %.6f Hz, want %.6f (%.2e)\n", "SOPDT, control",
                  (double)res.f_band, want_so, rel_err((double)res.f_band, want_so));
    assert_close(res.f_band, want_so, 0.05, 0.0);
}

/* No dead time: the time-cost stage's model has none or a tiny one, whose
 * phase crossover lies at or beyond the Nyquist frequency. The band is
 * then the whole spectrum, and nothing fails. */
/* ---- The coarse record (docs/ident-engine.md) ------------------------ */

/* A slow process sampled finely: the searches run on a coarse record and
 * the polished answer is the whole record's optimum, the one the whole
 * record's searches find. */
static void test_coarse_default(void **state)
{
    pdt_ident_result_t coarse, whole;
    (void)state;
    record_spec_t s = {
        model_fopdt(2.0, 12.0, 4.37), (pdt_real_t)0.1, 1200u, 0.0, 0.0, 1.0, 30.0, false, 3u};
    make_prbs(g_dev, s.n, 20u, 40u, 11u);
    make_record(&s);
    pdt_ident_config_t cfg = base_config(PDT_MODEL_FOPDT, s.Ts);
    identify(&cfg, s.n, &coarse);
    assert_true(coarse.coarse >= 2u);
    assert_int_equal(coarse.flags, 0u);
    cfg.coarse = 1u;
    identify(&cfg, s.n, &whole);
    assert_int_equal(whole.coarse, 1u);
    assert_true(fabs((double)(coarse.cost - whole.cost)) <= 1e-3 * (double)whole.cost);
    assert_true(fabs((double)(coarse.model.p.fopdt.K / whole.model.p.fopdt.K) - 1.0) < 1e-3);
    assert_true(fabs((double)(coarse.model.p.fopdt.Td - whole.model.p.fopdt.Td)) < 0.01);
}

/* An offspring that neither crossover nor mutation changed keeps its
 * parent's score: it counts as an evaluation (the budgets see the same
 * search) and scores no sample. Without crossover and with next to no
 * mutation every offspring is a copy: the samples scored fall short of
 * one whole record per evaluation by at least the offspring of the
 * generations the stall rule waits. */
static void test_copies_not_scored(void **state)
{
    pdt_ident_result_t res;
    (void)state;
    record_spec_t s = {
        model_fopdt(2.0, 12.0, 4.37), (pdt_real_t)1.0, 600u, 0.0, 0.0, 1.0, 30.0, false, 99u};
    make_prbs(g_dev, s.n, 10u, 8u, 7u);
    make_record(&s);
    pdt_ident_config_t cfg = base_config(PDT_MODEL_FOPDT, s.Ts);
    cfg.coarse = 1u;
    cfg.searches = 1u;
    cfg.p_crossover = (pdt_real_t)0.0;
    cfg.p_mutation = (pdt_real_t)1e-6;
    identify(&cfg, s.n, &res);
    const uint64_t waited = (uint64_t)cfg.stall_generations * PDT_IDENT_POPULATION_FOPDT;
    assert_true(res.evaluations > waited);
    assert_true(g_ctx.samples + (waited * s.n) <= (uint64_t)res.evaluations * s.n);
}

/* Steps until the first evaluation, each call's budget 100 evaluations;
 * the identification then run to its end into res. */
static uint32_t calls_before_evaluating(const pdt_ident_config_t *cfg, size_t n,
                                        pdt_ident_result_t *res)
{
    pdt_ident_data_t data = {g_u, g_y, n};
    size_t need = pdt_ident_workspace_size(cfg, n);
    uint32_t calls = 0u;
    assert_int_equal(pdt_ident_init(&g_ctx, cfg, &data, g_work, need), PDT_OK);
    pdt_status_t st = PDT_RUNNING;
    while (st == PDT_RUNNING && g_ctx.evaluations == 0u) {
        st = pdt_ident_step(&g_ctx, 100u);
        calls += g_ctx.evaluations == 0u ? 1u : 0u;
    }
    while (st == PDT_RUNNING) {
        st = pdt_ident_step(&g_ctx, 100u);
    }
    assert_int_equal(st, PDT_OK);
    assert_int_equal(pdt_ident_result(&g_ctx, res), PDT_OK);
    return calls;
}

/* The coarse record's factor is found one shape test a call: a record of
 * 1000 samples tries 7 (too coarse for this output), then 3, and
 * prepares the coarse record in a third call; the caller's 3 skips the
 * tests. The two searches are then the same bit for bit. */
static void test_coarse_steps(void **state)
{
    pdt_ident_result_t found, given;
    (void)state;
    record_spec_t s = {
        model_fopdt(2.0, 12.0, 4.37), (pdt_real_t)1.0, 1000u, 0.0, 0.0, 1.0, 30.0, false, 99u};
    make_prbs(g_dev, s.n, 10u, 8u, 7u);
    make_record(&s);
    pdt_ident_config_t cfg = base_config(PDT_MODEL_FOPDT, s.Ts);
    assert_int_equal(calls_before_evaluating(&cfg, s.n, &found), 3u);
    assert_int_equal(found.coarse, 3u);
    cfg.coarse = 3u;
    assert_int_equal(calls_before_evaluating(&cfg, s.n, &given), 1u);
    assert_int_equal(given.coarse, 3u);
    assert_int_equal(found.evaluations, given.evaluations);
    assert_same_model(&found.model, &given.model);
}

/* A process too fast for the decimation asked for: the coarse answer is
 * not trusted, the whole record is searched within the same budget. */
static void test_coarse_fallback(void **state)
{
    pdt_ident_result_t res;
    (void)state;
    record_spec_t s = {
        model_fopdt(-1.5, 0.4, 0.3), (pdt_real_t)0.1, 1200u, 0.0, 0.0, 1.0, 30.0, false, 5u};
    make_prbs(g_dev, s.n, 20u, 6u, 12u);
    make_record(&s);
    pdt_ident_config_t cfg = base_config(PDT_MODEL_FOPDT, s.Ts);
    cfg.coarse = 8u;
    identify(&cfg, s.n, &res);
    assert_int_equal(res.coarse, 1u);
    assert_true(res.evaluations <= cfg.max_evaluations);
    assert_true(fabs((double)res.model.p.fopdt.K / -1.5 - 1.0) < 0.02);
    assert_true(fabs((double)res.model.p.fopdt.tau / 0.4 - 1.0) < 0.05);
    assert_true(fabs((double)res.model.p.fopdt.Td - 0.3) < 0.02);
    /* Automatic: the output of this record changes within a few samples,
     * so the whole record is searched from the start. */
    cfg.coarse = 0u;
    identify(&cfg, s.n, &res);
    assert_true(res.coarse <= 2u);
}

/* Only the output error with fractional dead times searches a coarse
 * record; the others, the whole one. */
static void test_coarse_criteria(void **state)
{
    pdt_ident_result_t res;
    (void)state;
    record_spec_t s = {
        model_fopdt(2.0, 12.0, 4.37), (pdt_real_t)0.1, 1200u, 0.0, 0.0, 1.0, 30.0, false, 3u};
    make_prbs(g_dev, s.n, 20u, 40u, 11u);
    make_record(&s);
    for (int kind = PDT_COST_PREDICTION; kind <= PDT_COST_SIMULATION; kind++) {
        for (int integer = 0; integer <= 1; integer++) {
            pdt_ident_config_t cfg = base_config(PDT_MODEL_FOPDT, s.Ts);
            cfg.cost = (pdt_cost_kind_t)kind;
            cfg.delay_mode = integer ? PDT_DELAY_INTEGER : PDT_DELAY_FRACTIONAL;
            cfg.coarse = 4u;
            identify(&cfg, s.n, &res);
            const bool coarse = kind == PDT_COST_SIMULATION && !integer;
            assert_int_equal(res.coarse, coarse ? 4u : 1u);
        }
    }
}

/* ---- Dead times of whole samples (docs/ident-engine.md) -------------- */

#define KINK_N 1200u

static pdt_real_t g_kink_scratch[KINK_N];
static pdt_real_t g_kink_work[PDT_COST_WORKSPACE_SIZE(KINK_N) / sizeof(pdt_real_t) + 1u];

/* The output error of a unit-gain FOPDT (tau, Td), gain and offset fitted. */
static double kink_cost(const pdt_cost_t *c, double tau, double Td)
{
    pdt_cost_profile_t pr;
    const pdt_model_t m = model_fopdt(1.0, tau, Td);
    assert_int_equal(pdt_cost_profile(c, &m, (pdt_real_t)0.0, (pdt_real_t)0.0, g_kink_scratch, &pr),
                     PDT_OK);
    return (double)pr.cost;
}

/* The least cost over tau at dead time Td: golden section on log tau. */
static double kink_best_over_tau(const pdt_cost_t *c, double tau0, double Td)
{
    const double gr = 0.5 * (sqrt(5.0) - 1.0);
    double a = log(tau0) - 0.05, b = log(tau0) + 0.05;
    double x1 = b - gr * (b - a), x2 = a + gr * (b - a);
    double f1 = kink_cost(c, exp(x1), Td), f2 = kink_cost(c, exp(x2), Td);
    for (int i = 0; i < 40; i++) {
        if (f1 < f2) {
            b = x2;
            x2 = x1;
            f2 = f1;
            x1 = b - gr * (b - a);
            f1 = kink_cost(c, exp(x1), Td);
        } else {
            a = x1;
            x1 = x2;
            f1 = f2;
            x2 = a + gr * (b - a);
            f2 = kink_cost(c, exp(x2), Td);
        }
    }
    return fmin(f1, f2);
}

/* A plant whose dead time is a whole number of samples (digital loops have
 * them): the output error's minimum over the dead time sits on its kink
 * there, and the answer must reach it, not stop 1e-5 of the cost short
 * (the Newton polish's differences straddle the kink). Checked against a
 * scan of the dead time in hundredths of a sample about the answer, tau
 * minimised at each (the cost at each point from the public cost API). */
static void test_whole_sample_delay(void **state)
{
    pdt_ident_result_t res;
    pdt_cost_t cost;
    pdt_cost_config_t cc;
    (void)state;
    /* The noise realisation puts the minimum on the kink (most put it a
     * few hundredths of a sample off, where the differences now stay on
     * its side of the kink): of noise seeds 1000, 2000, ..., 32000, 16000,
     * 20000 and 27000 do, and on 16000 the answer is the kink's. */
    record_spec_t s = {
        model_fopdt(2.0, 12.0, 4.0), (pdt_real_t)0.1, KINK_N, 0.0, 0.0, 1.0, 30.0, false, 16000u};
    make_prbs(g_dev, s.n, 20u, 40u, 11u);
    make_record(&s);
    pdt_ident_config_t cfg = base_config(PDT_MODEL_FOPDT, s.Ts);
    cfg.offset = PDT_IDENT_OFFSET_ESTIMATE;
    identify(&cfg, s.n, &res);
    pdt_cost_config_default(&cc);
    cc.Ts = s.Ts;
    cc.u0 = g_u[0];
    cc.delay_max = s.n / 2u;
    cc.kind = PDT_COST_SIMULATION;
    cc.whole_record = true;
    cc.use_frequency = false;
    assert_int_equal(pdt_cost_init(&cost, &cc, g_u, g_y, s.n, g_kink_work, sizeof g_kink_work),
                     PDT_OK);
    const double tau = (double)res.model.p.fopdt.tau, r = (double)res.model.p.fopdt.Td / 0.1;
    double best = (double)INFINITY, best_r = 0.0;
    for (int i = -100; i <= 100; i++) {
        const double ri = floor(r + 0.5) + 0.01 * i;
        const double f = kink_best_over_tau(&cost, tau, ri * 0.1);
        if (f < best) {
            best = f;
            best_r = ri;
        }
    }
    const double gap = (double)res.cost / best - 1.0;
    print_message("    whole-sample Td: answer %.4f samples, scan's minimum %.2f; cost %.2e "
                  "above it\n",
                  r, best_r, gap);
    /* The scan's minimum lies on the whole sample, and so does the answer;
     * its cost is the minimum's to the float cost's rounding. */
    assert_true(fabs(best_r - floor(best_r + 0.5)) < 1e-9);
    assert_true(fabs(r - best_r) < 1e-3);
    assert_true(gap < 2e-6);
}

/* A record of m at Ts = 1 s: 40 samples at rest, then a square wave
 * whose level flips after every bit samples, white noise at snr_db from
 * seed. */
static void square_record(pdt_model_t m, size_t n, size_t bit, double snr_db, uint32_t seed)
{
    const record_spec_t s = {m, (pdt_real_t)1.0, n, 40.0, 350.0, 1.0, snr_db, false, seed};
    for (size_t k = 0; k < n; k++) {
        g_dev[k] =
            k < 40u ? (pdt_real_t)0.0 : (pdt_real_t)((((k - 40u) / bit) % 2u) == 0u ? 1.0 : -1.0);
    }
    make_record(&s);
}

/* A SOPDT whose time constant is 4 samples under an input that flips at
 * every sample: between two whole samples of dead time the output error
 * has two minima, at 4.3 and near 5 s, a fraction of a sample apart, far
 * inside the niches' sharing radius (docs/ident-engine.md). On this
 * record (noise and search seed 167) both searches ended near 5 s (fit
 * 92.0 % for 96.9 %) without the polish's probe of the dead time about the
 * answer in tenths of a sample (3 such answers in 1200 seeds without it, 0
 * with it). */
static void test_dead_time_probe(void **state)
{
    pdt_ident_result_t res;
    (void)state;
    square_record(model_sopdt_tc(1.5, 4.0, 4.0 / 3.0, 4.3), 1200u, 1u, 30.0, 167u);
    pdt_ident_config_t cfg = base_config(PDT_MODEL_SOPDT, (pdt_real_t)1.0);
    cfg.seed = 167u;
    identify(&cfg, 1200u, &res);
    print_message("    one-sample input: Td %.4f s (4.3), fit %.2f %%, %u evaluations\n",
                  (double)res.model.p.sopdt.Td, (double)res.fit, (unsigned)res.evaluations);
    assert_true(fabs((double)res.model.p.sopdt.Td - 4.3) < 0.05);
    assert_true(res.fit > (pdt_real_t)95.0);
}

/* A FOPDT under a square wave of period 8 samples (bits of a third of tau)
 * at 10 dB: the cost along the dead time repeats with the input's period,
 * and a long lag one period early, or a short one a period late, is a
 * basin of 1.2 times the optimum's cost, a few samples from the right one.
 * On these records (noise and search seeds 175 and 768, one of each) both
 * searches ended in it and agreed without the profile (10 such answers in
 * 3000 seeds, 0 with the profile); the dead-time profile finds the lower
 * basin and its polish becomes the answer. */
static void test_dead_time_profile(void **state)
{
    static const uint32_t seeds[] = {175u, 768u};
    (void)state;
    for (size_t i = 0; i < 2u; i++) {
        pdt_ident_result_t res;
        square_record(model_fopdt(1.5, 12.0, 8.3), 1200u, 4u, 10.0, seeds[i]);
        pdt_ident_config_t cfg = base_config(PDT_MODEL_FOPDT, (pdt_real_t)1.0);
        cfg.seed = seeds[i];
        identify(&cfg, 1200u, &res);
        print_message("    square wave, seed %u: Td %.3f s (8.3), tau %.2f s (12), fit %.2f %%, "
                      "%u evaluations, flags %u\n",
                      (unsigned)seeds[i], (double)res.model.p.fopdt.Td,
                      (double)res.model.p.fopdt.tau, (double)res.fit, (unsigned)res.evaluations,
                      (unsigned)res.flags);
        assert_true(fabs((double)res.model.p.fopdt.Td - 8.3) < 0.5);
        assert_true(fabs((double)res.model.p.fopdt.tau - 12.0) < 3.0);
        assert_int_equal(res.flags, 0u);
        assert_true(res.searches >= 2u && res.searches <= PDT_IDENT_MAX_SEARCHES);
    }
}

/* The SOPDT of test_dead_time_probe on a long record (4000 samples, 10 dB)
 * from seed (noise and search): the dead time found within 0.3 s of 4.3 s,
 * and no flag where unflagged is asserted. */
static void long_square_check(const char *what, uint32_t seed, bool unflagged)
{
    pdt_ident_result_t res;
    square_record(model_sopdt_tc(1.5, 4.0, 4.0 / 3.0, 4.3), 4000u, 1u, 10.0, seed);
    pdt_ident_config_t cfg = base_config(PDT_MODEL_SOPDT, (pdt_real_t)1.0);
    cfg.seed = seed;
    identify(&cfg, 4000u, &res);
    print_message("    %s, seed %u: Td %.3f s (4.3), fit %.2f %%, %u evaluations, flags %u\n", what,
                  (unsigned)seed, (double)res.model.p.sopdt.Td, (double)res.fit,
                  (unsigned)res.evaluations, (unsigned)res.flags);
    assert_true(fabs((double)res.model.p.sopdt.Td - 4.3) < 0.3);
    if (unflagged) {
        assert_int_equal(res.flags, 0u);
    }
}

/* The dead-time range of those records (a third of the record) holds 1333
 * samples, so the profile's grid steps 11 of them, and the input's period
 * of 2 samples puts a basin of 1.05 times the optimum's cost 1.6 samples
 * early (Td 2.7 s for 4.3), near the answer on that grid. On these records
 * (seeds 46 and 159) both searches ended there and agreed without the
 * window (4 such answers in 600 seeds, 0 with the window); the profile's
 * window of whole samples about the answer finds the right basin. */
static void test_dead_time_profile_window(void **state)
{
    (void)state;
    long_square_check("long record", 46u, true);
    long_square_check("long record", 159u, true);
}

/* The same records: between whole samples of dead time the cost holds a
 * minimum of its own, a ridge away from the kink, so the answer near 5 s,
 * the profile (whole samples, near the answer) and the probe (shape held)
 * all missed the right one at 4.3 s, 1.6 % lower, status OK. The search
 * across the answer's nearest kink, confined to that interval, finds it
 * (on seeds 8 and 19 among them: 9 such answers in 600 seeds without it, 8
 * with status OK and no flag, 0 with it). */
static void test_dead_time_across_kink(void **state)
{
    (void)state;
    long_square_check("across the kink", 8u, true);
    long_square_check("across the kink", 19u, true);
}

/* The same records: the dead-time probe moves the dead time along the
 * answer's mean delay (the lags scaled to keep the dead time plus their
 * sum). With the lags held, seeds 322 and 393 were right but flagged
 * UNCONFIRMED in every build (float, double, the sanitizer's), and seed
 * 460 in double ended at 4.95 s, status OK and no flag: the probe's points
 * near 4.3 s lay above the answer with its lags. */
static void test_dead_time_probe_mean_delay(void **state)
{
    (void)state;
    long_square_check("mean-delay probe", 322u, true);
    long_square_check("mean-delay probe", 393u, true);
    long_square_check("mean-delay probe", 460u, true);
}

static void test_control_band_no_dead_time(void **state)
{
    pdt_ident_result_t res;
    const pdt_model_t m = model_fopdt(2.0, 5.0, 0.0);
    (void)state;
    control_record(m);
    static const pdt_cost_kind_t kinds[] = {PDT_COST_COMBINED, PDT_COST_FREQUENCY};
    for (size_t i = 0; i < 2u; i++) {
        pdt_ident_config_t cfg = base_config(PDT_MODEL_FOPDT, (pdt_real_t)CB_TS);
        cfg.cost = kinds[i];
        cfg.weight = PDT_IDENT_WEIGHT_CONTROL;
        identify(&cfg, CB_N, &res);
        check_fopdt(i == 0u ? "Td = 0, combined" : "Td = 0, frequency", &res, &m, FO_K, 0.03,
                    FO_TD);
        print_message("    %-22s f_band %.6f Hz (Nyquist %.1f)\n", "", (double)res.f_band,
                      0.5 / CB_TS);
        assert_true(isfinite((double)res.f_band) && res.f_band > (pdt_real_t)0.0);
        assert_true((double)res.f_band <= 0.5 / CB_TS);
    }
}

/* ---- Bad inputs ------------------------------------------------------- */

/* A valid record and config for the error tests. */
#define ERR_N 200u

static void error_record(void)
{
    pdt_model_t m = model_fopdt(2.0, 8.0, 3.0);
    record_spec_t s = {m, (pdt_real_t)1.0, ERR_N, 40.0, 350.0, 5.0, 30.0, false, 99u};
    make_prbs(g_dev, s.n, 5u, 6u, 7u);
    /* Back at rest for the last 60 samples (7 time constants), as the
     * frequency criteria need. */
    for (size_t k = s.n - 60u; k < s.n; k++) {
        g_dev[k] = (pdt_real_t)0.0;
    }
    make_record(&s);
}

/* pdt_ident_init and pdt_identify both fail with want, leaving the
 * context and the result untouched. */
static void expect_init_error(const pdt_ident_config_t *cfg, const pdt_ident_data_t *data,
                              void *work, size_t work_len, pdt_status_t want, const char *what)
{
    pdt_ident_result_t out, out_copy;
    memset(&g_ctx, 0xa5, sizeof g_ctx);
    memcpy(&g_ctx2, &g_ctx, sizeof g_ctx);
    memset(&out, 0x3c, sizeof out);
    memcpy(&out_copy, &out, sizeof out);
    pdt_status_t st = pdt_ident_init(&g_ctx, cfg, data, work, work_len);
    if (st != want) {
        fail_msg("%s: pdt_ident_init returned %d (%s), want %d (%s)", what, (int)st,
                 pdt_status_str(st), (int)want, pdt_status_str(want));
    }
    assert_memory_equal(&g_ctx, &g_ctx2, sizeof g_ctx);
    st = pdt_identify(&g_ctx, cfg, data, work, work_len, &out);
    if (st != want) {
        fail_msg("%s: pdt_identify returned %d (%s), want %d (%s)", what, (int)st,
                 pdt_status_str(st), (int)want, pdt_status_str(want));
    }
    assert_memory_equal(&g_ctx, &g_ctx2, sizeof g_ctx);
    assert_memory_equal(&out, &out_copy, sizeof out);
}

static void test_errors_pointers(void **state)
{
    pdt_ident_config_t cfg = base_config(PDT_MODEL_FOPDT, (pdt_real_t)1.0);
    pdt_ident_data_t data = {g_u, g_y, ERR_N};
    pdt_ident_data_t bad;
    pdt_ident_result_t out, out_copy;
    (void)state;
    error_record();
    size_t need = pdt_ident_workspace_size(&cfg, ERR_N);
    assert_true(need > 0u);
    assert_int_equal(pdt_ident_init(NULL, &cfg, &data, g_work, need), PDT_ERR_ARG);
    memset(&out, 0x3c, sizeof out);
    out_copy = out;
    assert_int_equal(pdt_identify(NULL, &cfg, &data, g_work, need, &out), PDT_ERR_ARG);
    assert_memory_equal(&out, &out_copy, sizeof out);
    expect_init_error(NULL, &data, g_work, need, PDT_ERR_ARG, "cfg NULL");
    expect_init_error(&cfg, NULL, g_work, need, PDT_ERR_ARG, "data NULL");
    bad = data;
    bad.u = NULL;
    expect_init_error(&cfg, &bad, g_work, need, PDT_ERR_ARG, "u NULL");
    bad = data;
    bad.y = NULL;
    expect_init_error(&cfg, &bad, g_work, need, PDT_ERR_ARG, "y NULL");
    /* result NULL */
    memset(&g_ctx, 0xa5, sizeof g_ctx);
    memcpy(&g_ctx2, &g_ctx, sizeof g_ctx);
    assert_int_equal(pdt_identify(&g_ctx, &cfg, &data, g_work, need, NULL), PDT_ERR_ARG);
    assert_memory_equal(&g_ctx, &g_ctx2, sizeof g_ctx);
    /* Workspace: NULL or one byte short is NOMEM, misaligned is ARG. */
    expect_init_error(&cfg, &data, NULL, need, PDT_ERR_NOMEM, "work NULL");
    expect_init_error(&cfg, &data, g_work, need - 1u, PDT_ERR_NOMEM, "work one byte short");
    expect_init_error(&cfg, &data, g_work, 0u, PDT_ERR_NOMEM, "work_len 0");
    expect_init_error(&cfg, &data, (char *)g_work + 1, need, PDT_ERR_ARG, "work misaligned");
    /* The exact size works. */
    assert_int_equal(pdt_ident_init(&g_ctx, &cfg, &data, g_work, need), PDT_OK);
    /* Step and result with NULL. */
    assert_int_equal(pdt_ident_step(NULL, 10u), PDT_ERR_ARG);
    assert_int_equal(pdt_ident_result(NULL, &out), PDT_ERR_ARG);
    assert_int_equal(pdt_ident_result(&g_ctx, NULL), PDT_ERR_ARG);
}

static void test_errors_config(void **state)
{
    pdt_ident_config_t good = base_config(PDT_MODEL_FOPDT, (pdt_real_t)1.0);
    pdt_ident_data_t data = {g_u, g_y, ERR_N};
    pdt_ident_config_t cfg;
    (void)state;
    error_record();
    size_t need = WORK_REALS * sizeof(pdt_real_t);

#define EXPECT_CFG(change, want)                                                                   \
    do {                                                                                           \
        cfg = good;                                                                                \
        change;                                                                                    \
        expect_init_error(&cfg, &data, g_work, need, want, #change);                               \
        assert_int_equal(pdt_ident_workspace_size(&cfg, ERR_N), 0u);                               \
    } while (0)

    EXPECT_CFG(cfg.Ts = (pdt_real_t)0.0, PDT_ERR_ARG);
    EXPECT_CFG(cfg.Ts = (pdt_real_t)-1.0, PDT_ERR_ARG);
    EXPECT_CFG(cfg.Ts = (pdt_real_t)NAN, PDT_ERR_ARG);
    EXPECT_CFG(cfg.Ts = (pdt_real_t)INFINITY, PDT_ERR_ARG);
    EXPECT_CFG(cfg.population = 7u, PDT_ERR_ARG);
    EXPECT_CFG(cfg.population = 2u, PDT_ERR_ARG);
    EXPECT_CFG(cfg.population = PDT_IDENT_MAX_POPULATION + 2u, PDT_ERR_ARG);
    EXPECT_CFG((cfg.population = 8u, cfg.elite = 8u), PDT_ERR_ARG);
    EXPECT_CFG((cfg.population = 8u, cfg.elite = 9u), PDT_ERR_ARG);
    EXPECT_CFG(cfg.max_evaluations = PDT_IDENT_POPULATION_FOPDT + 300u - 1u, PDT_ERR_ARG);
    EXPECT_CFG((cfg.cost = PDT_COST_FREQUENCY, cfg.max_evaluations = 24u + 300u + 100u),
               PDT_ERR_ARG);
    EXPECT_CFG(cfg.model = (pdt_model_kind_t)0, PDT_ERR_ARG);
    EXPECT_CFG(cfg.model = (pdt_model_kind_t)3, PDT_ERR_ARG);
    EXPECT_CFG(cfg.cost = (pdt_cost_kind_t)4, PDT_ERR_ARG);
    EXPECT_CFG(cfg.cost = (pdt_cost_kind_t)-1, PDT_ERR_ARG);
    EXPECT_CFG(cfg.delay_mode = (pdt_delay_mode_t)2, PDT_ERR_ARG);
    EXPECT_CFG(cfg.stall_generations = 0u, PDT_ERR_ARG);
    EXPECT_CFG(cfg.eta_c = (pdt_real_t)0.0, PDT_ERR_ARG);
    EXPECT_CFG(cfg.eta_m = (pdt_real_t)NAN, PDT_ERR_ARG);
    EXPECT_CFG(cfg.p_crossover = (pdt_real_t)1.5, PDT_ERR_ARG);
    EXPECT_CFG(cfg.p_mutation = (pdt_real_t)-0.1, PDT_ERR_ARG);
    EXPECT_CFG(cfg.sigma_share = (pdt_real_t)0.0, PDT_ERR_ARG);
    EXPECT_CFG(cfg.tolerance = (pdt_real_t)-1.0, PDT_ERR_ARG);
    EXPECT_CFG(cfg.K_min = (pdt_real_t)NAN, PDT_ERR_ARG);
    EXPECT_CFG(cfg.K_max = (pdt_real_t)INFINITY, PDT_ERR_ARG);
    EXPECT_CFG((cfg.model = PDT_MODEL_SOPDT, cfg.zeta_min = (pdt_real_t)0.0), PDT_ERR_ARG);
    EXPECT_CFG((cfg.tau_min = (pdt_real_t)-1.0, cfg.tau_max = (pdt_real_t)10.0), PDT_ERR_ARG);
    EXPECT_CFG((cfg.Td_min = (pdt_real_t)-1.0, cfg.Td_max = (pdt_real_t)10.0), PDT_ERR_ARG);
    EXPECT_CFG(cfg.tau_max = (pdt_real_t)NAN, PDT_ERR_ARG);
    /* Bounds the wrong way round. */
    EXPECT_CFG((cfg.tau_min = (pdt_real_t)10.0, cfg.tau_max = (pdt_real_t)10.0), PDT_ERR_BOUNDS);
    EXPECT_CFG((cfg.tau_min = (pdt_real_t)10.0, cfg.tau_max = (pdt_real_t)5.0), PDT_ERR_BOUNDS);
    EXPECT_CFG((cfg.Td_min = (pdt_real_t)6.0, cfg.Td_max = (pdt_real_t)5.0), PDT_ERR_BOUNDS);
    EXPECT_CFG((cfg.K_min = (pdt_real_t)2.0, cfg.K_max = (pdt_real_t)1.0), PDT_ERR_BOUNDS);
#undef EXPECT_CFG

    /* A weighting past AUTO, the last one, whether or not the criterion
     * has a frequency part. (The size query does not look at the
     * weighting: only init refuses it.) */
    cfg = good;
    cfg.weight = (pdt_ident_weight_t)(PDT_IDENT_WEIGHT_AUTO + 1);
    expect_init_error(&cfg, &data, g_work, need, PDT_ERR_ARG, "weight past AUTO");
    cfg.cost = PDT_COST_COMBINED;
    expect_init_error(&cfg, &data, g_work, need, PDT_ERR_ARG, "weight past AUTO, combined");

    /* Equal Td bounds (a fixed dead time) and equal K bounds are allowed. */
    cfg = good;
    cfg.Td_min = (pdt_real_t)3.0;
    cfg.Td_max = (pdt_real_t)3.0;
    cfg.K_min = (pdt_real_t)2.0;
    cfg.K_max = (pdt_real_t)2.0;
    need = pdt_ident_workspace_size(&cfg, ERR_N);
    assert_int_equal(pdt_ident_init(&g_ctx, &cfg, &data, g_work, need), PDT_OK);
}

static void test_errors_data(void **state)
{
    pdt_ident_config_t cfg = base_config(PDT_MODEL_FOPDT, (pdt_real_t)1.0);
    pdt_ident_data_t data = {g_u, g_y, ERR_N};
    size_t need = WORK_REALS * sizeof(pdt_real_t);
    static const float bad_values[] = {NAN, INFINITY, -INFINITY};
    static const size_t where[] = {0u, 1u, ERR_N / 2u, ERR_N - 1u};
    (void)state;
    error_record();
    /* A non-finite y is a missing sample unless refused (test_ident_field.c). */
    cfg.refuse_missing = true;
    for (size_t v = 0; v < 3u; v++) {
        for (size_t w = 0; w < 4u; w++) {
            pdt_real_t *arr[2] = {g_u, g_y};
            for (size_t a = 0; a < 2u; a++) {
                pdt_real_t keep = arr[a][where[w]];
                arr[a][where[w]] = (pdt_real_t)bad_values[v];
                expect_init_error(&cfg, &data, g_work, need, PDT_ERR_NONFINITE,
                                  a == 0u ? "non-finite u" : "non-finite y");
                arr[a][where[w]] = keep;
            }
        }
    }
    cfg.refuse_missing = false;
    /* Too short: fewer than PDT_MIN_SAMPLES, or a dead-time bound at or
     * beyond the record. */
    data.n = PDT_MIN_SAMPLES - 1u;
    expect_init_error(&cfg, &data, g_work, need, PDT_ERR_TOO_SHORT, "n < PDT_MIN_SAMPLES");
    /* n = 0 with explicit bounds (the default bounds are derived from the
     * record length, which n = 0 makes empty). */
    data.n = 0u;
    cfg.tau_min = (pdt_real_t)1.0;
    cfg.tau_max = (pdt_real_t)100.0;
    cfg.Td_max = (pdt_real_t)10.0;
    expect_init_error(&cfg, &data, g_work, need, PDT_ERR_TOO_SHORT, "n = 0");
    cfg = base_config(PDT_MODEL_FOPDT, (pdt_real_t)1.0);
    data.n = ERR_N;
    cfg.Td_max = (pdt_real_t)ERR_N;
    expect_init_error(&cfg, &data, g_work, need, PDT_ERR_TOO_SHORT, "Td_max = record");
    cfg.Td_max = (pdt_real_t)(2.0 * ERR_N);
    expect_init_error(&cfg, &data, g_work, need, PDT_ERR_TOO_SHORT, "Td_max beyond record");
    /* A dead-time bound just inside the record is accepted: the whole
     * record is scored, not only the samples after the bound. */
    cfg.Td_max = (pdt_real_t)(ERR_N - 5u);
    assert_true(pdt_ident_workspace_size(&cfg, ERR_N) > 0u);
    cfg.Td_max = (pdt_real_t)0.0;
    /* No excitation: constant u, constant y. */
    for (size_t k = 0; k < ERR_N; k++) {
        g_dev[k] = g_u[k];
        g_u[k] = (pdt_real_t)40.0;
    }
    expect_init_error(&cfg, &data, g_work, need, PDT_ERR_NO_EXCITATION, "constant u");
    for (size_t k = 0; k < ERR_N; k++) {
        g_u[k] = g_dev[k];
        g_sim[k] = g_y[k];
        g_y[k] = (pdt_real_t)350.0;
    }
    expect_init_error(&cfg, &data, g_work, need, PDT_ERR_NO_EXCITATION, "constant y");
    for (size_t k = 0; k < ERR_N; k++) {
        g_y[k] = g_sim[k];
    }
    /* The data are usable again. */
    assert_int_equal(pdt_ident_init(&g_ctx, &cfg, &data, g_work, need), PDT_OK);
    /* The frequency criteria on a record that does not end at rest: a step
     * that stays up, then an output that ends off its starting level (an
     * integrator's pulse response) while u is back. The time costs take
     * both. */
    pdt_model_t m = model_fopdt(2.0, 8.0, 3.0);
    record_spec_t step = {m, (pdt_real_t)1.0, ERR_N, 40.0, 350.0, 5.0, 30.0, false, 99u};
    for (size_t k = 0; k < ERR_N; k++) {
        g_dev[k] = k < 10u ? (pdt_real_t)0.0 : (pdt_real_t)1.0;
    }
    make_record(&step);
    for (int pass = 0; pass < 2; pass++) {
        for (int kind = PDT_COST_FREQUENCY; kind <= PDT_COST_COMBINED; kind++) {
            pdt_ident_config_t fc = base_config(PDT_MODEL_FOPDT, (pdt_real_t)1.0);
            fc.cost = (pdt_cost_kind_t)kind;
            size_t fneed = pdt_ident_workspace_size(&fc, ERR_N);
            assert_true(fneed > 0u);
            expect_init_error(&fc, &data, g_work, fneed, PDT_ERR_NOT_AT_REST,
                              pass == 0 ? "step record" : "output off its start");
            fc.cost = PDT_COST_SIMULATION;
            fneed = pdt_ident_workspace_size(&fc, ERR_N);
            assert_int_equal(pdt_ident_init(&g_ctx, &fc, &data, g_work, fneed), PDT_OK);
        }
        /* u back at rest for the second half, y held at its end level. */
        for (size_t k = ERR_N / 2u; k < ERR_N; k++) {
            g_u[k] = g_u[0];
        }
    }
    /* A record at rest again passes. */
    error_record();
    pdt_ident_config_t fc = base_config(PDT_MODEL_FOPDT, (pdt_real_t)1.0);
    fc.cost = PDT_COST_COMBINED;
    size_t fneed = pdt_ident_workspace_size(&fc, ERR_N);
    assert_int_equal(pdt_ident_init(&g_ctx, &fc, &data, g_work, fneed), PDT_OK);
}

static void test_errors_state(void **state)
{
    pdt_ident_config_t cfg = base_config(PDT_MODEL_FOPDT, (pdt_real_t)1.0);
    pdt_ident_data_t data = {g_u, g_y, ERR_N};
    pdt_ident_result_t out, copy;
    (void)state;
    error_record();
    /* A context never initialised. */
    memset(&g_ctx, 0, sizeof g_ctx);
    memcpy(&g_ctx2, &g_ctx, sizeof g_ctx);
    memset(&out, 0x3c, sizeof out);
    copy = out;
    assert_int_equal(pdt_ident_step(&g_ctx, 10u), PDT_ERR_STATE);
    assert_int_equal(pdt_ident_result(&g_ctx, &out), PDT_ERR_STATE);
    assert_memory_equal(&g_ctx, &g_ctx2, sizeof g_ctx);
    assert_memory_equal(&out, &copy, sizeof out);
    /* Initialised, not done. */
    size_t need = pdt_ident_workspace_size(&cfg, ERR_N);
    assert_int_equal(pdt_ident_init(&g_ctx, &cfg, &data, g_work, need), PDT_OK);
    assert_int_equal(pdt_ident_result(&g_ctx, &out), PDT_ERR_STATE);
    assert_memory_equal(&out, &copy, sizeof out);
    /* max_evaluations = 0 is refused and does nothing. */
    memcpy(&g_ctx2, &g_ctx, sizeof g_ctx);
    assert_int_equal(pdt_ident_step(&g_ctx, 0u), PDT_ERR_ARG);
    assert_memory_equal(&g_ctx, &g_ctx2, sizeof g_ctx);
    /* The first call prepares the searches and evaluates nothing. */
    assert_int_equal(pdt_ident_step(&g_ctx, 5u), PDT_RUNNING);
    assert_int_equal(g_ctx.evaluations, 0u);
    assert_int_equal(pdt_ident_step(&g_ctx, 5u), PDT_RUNNING);
    /* Whole groups of the population only: 4 (one group) with vector
     * lanes, else 5. */
    assert_int_equal(g_ctx.evaluations, PDT_VECTOR_LANES == 4 ? 4u : 5u);
    memcpy(&g_ctx2, &g_ctx, sizeof g_ctx);
    assert_int_equal(pdt_ident_step(&g_ctx, 0u), PDT_ERR_ARG);
    assert_memory_equal(&g_ctx, &g_ctx2, sizeof g_ctx);
    assert_int_equal(pdt_ident_result(&g_ctx, &out), PDT_ERR_STATE);
    assert_memory_equal(&out, &copy, sizeof out);
}

/* ---- Memory ----------------------------------------------------------- */

static void test_workspace_size(void **state)
{
    static const size_t ns[] = {PDT_MIN_SAMPLES + 8u, 100u, 257u, 600u, 1200u, NMAX};
    static const pdt_cost_kind_t kinds[] = {PDT_COST_PREDICTION, PDT_COST_SIMULATION,
                                            PDT_COST_FREQUENCY, PDT_COST_COMBINED};
    static const uint32_t pops[] = {0u, 4u, 24u, 40u, 64u};
    (void)state;
    assert_int_equal(pdt_ident_workspace_size(NULL, 100u), 0u);
    for (size_t in = 0; in < sizeof ns / sizeof ns[0]; in++) {
        for (int model = 1; model <= 2; model++) {
            for (size_t ik = 0; ik < 4u; ik++) {
                for (size_t ip = 0; ip < sizeof pops / sizeof pops[0]; ip++) {
                    for (int mode = 0; mode < 2; mode++) {
                        for (int td = 0; td < 2; td++) {
                            pdt_ident_config_t cfg =
                                base_config((pdt_model_kind_t)model, (pdt_real_t)1.0);
                            cfg.cost = kinds[ik];
                            cfg.population = pops[ip];
                            cfg.delay_mode = (pdt_delay_mode_t)mode;
                            if (td == 1) {
                                /* The shortest delay bound: the longest
                                 * zero padding. */
                                cfg.Td_max = (pdt_real_t)0.5;
                            }
                            uint32_t pop = pops[ip] != 0u
                                               ? pops[ip]
                                               : (model == 2 ? PDT_IDENT_POPULATION_SOPDT
                                                             : PDT_IDENT_POPULATION_FOPDT);
                            size_t got = pdt_ident_workspace_size(&cfg, ns[in]);
                            assert_true(got > 0u);
                            assert_true(got % sizeof(pdt_real_t) == 0u);
                            if (got > PDT_IDENT_WORKSPACE_SIZE(ns[in], pop)) {
                                fail_msg("n %zu model %d cost %d pop %u: size %zu > macro %zu",
                                         ns[in], model, (int)kinds[ik], (unsigned)pop, got,
                                         (size_t)PDT_IDENT_WORKSPACE_SIZE(ns[in], pop));
                            }
                            /* The automatic populations are covered by
                             * the SOPDT one, as the header says. */
                            if (pops[ip] == 0u) {
                                assert_true(got <= PDT_IDENT_WORKSPACE_SIZE(
                                                       ns[in], PDT_IDENT_POPULATION_SOPDT));
                            }
                        }
                    }
                }
            }
        }
    }
}

/* Whole runs with the workspace sized by the query, canaries after it
 * (identify() checks them), for every model and criterion; and the size
 * does not depend on the data. */
static void test_workspace_canaries(void **state)
{
    static const pdt_cost_kind_t kinds[] = {PDT_COST_PREDICTION, PDT_COST_SIMULATION,
                                            PDT_COST_FREQUENCY, PDT_COST_COMBINED};
    pdt_ident_result_t res;
    (void)state;
    error_record();
    for (int model = 1; model <= 2; model++) {
        for (size_t ik = 0; ik < 4u; ik++) {
            pdt_ident_config_t cfg = base_config((pdt_model_kind_t)model, (pdt_real_t)1.0);
            cfg.cost = kinds[ik];
            cfg.max_evaluations = 800u;
            identify(&cfg, ERR_N, &res);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_errors_pointers),
        cmocka_unit_test(test_errors_config),
        cmocka_unit_test(test_errors_data),
        cmocka_unit_test(test_errors_state),
        cmocka_unit_test(test_workspace_size),
        cmocka_unit_test(test_workspace_canaries),
        cmocka_unit_test(test_stepping),
        cmocka_unit_test(test_std_steps),
        cmocka_unit_test(test_budget),
        cmocka_unit_test(test_determinism),
        cmocka_unit_test(test_second_search_ends_early),
        cmocka_unit_test(test_resolved_niches),
        cmocka_unit_test(test_gain_bounds),
        cmocka_unit_test(test_recover_fopdt),
        cmocka_unit_test(test_recover_sopdt),
        cmocka_unit_test(test_recover_integrating),
        cmocka_unit_test(test_recover_integer_delay),
        cmocka_unit_test(test_recover_prediction),
        cmocka_unit_test(test_recover_criteria_pulse),
        cmocka_unit_test(test_control_default),
        cmocka_unit_test(test_control_band),
        cmocka_unit_test(test_control_band_off),
        cmocka_unit_test(test_control_band_no_dead_time),
        cmocka_unit_test(test_coarse_default),
        cmocka_unit_test(test_coarse_steps),
        cmocka_unit_test(test_copies_not_scored),
        cmocka_unit_test(test_coarse_fallback),
        cmocka_unit_test(test_coarse_criteria),
        cmocka_unit_test(test_whole_sample_delay),
        cmocka_unit_test(test_dead_time_probe),
        cmocka_unit_test(test_dead_time_profile),
        cmocka_unit_test(test_dead_time_profile_window),
        cmocka_unit_test(test_dead_time_across_kink),
        cmocka_unit_test(test_dead_time_probe_mean_delay),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
