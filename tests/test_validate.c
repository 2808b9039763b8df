/*
 * Model validation (pdt_validate.h): the residual tests accept the true
 * model and reject a wrong one at their stated rates, the parameter std
 * matches the spread of real identifications over noise seeds, the order
 * choice, the robust bound, and the statuses.
 */
#include "test_util.h"

#include "sim_process.h"
#include "validate_vectors.h"

#define N  400u
#define TS 0.5

static pdt_real_t g_u[N];
static pdt_real_t g_y[N];
static pdt_real_t g_dev[N];
static pdt_real_t g_clean[N];
static pdt_real_t g_work[5u * N + CANARY_COUNT];
static unsigned char g_idwork[PDT_IDENT_WORKSPACE_SIZE(N, PDT_IDENT_POPULATION_SOPDT)];

/* A random binary input around u0 = 10 (deviation +-1, chip 8 samples),
 * at rest for the first 10 samples. */
static void make_input(uint64_t seed)
{
    sim_rng64_t r = sim_rng64_seed(seed);
    pdt_real_t level = (pdt_real_t)1.0;
    for (size_t k = 0; k < N; k++) {
        if (k >= 10u && (k - 10u) % 8u == 0u && sim_rng64_uniform(&r) < 0.5) {
            level = -level;
        }
        g_dev[k] = k < 10u ? (pdt_real_t)0.0 : level;
        g_u[k] = (pdt_real_t)10.0 + g_dev[k];
    }
}

/* The record of plant m (any shape: m is simulated exactly by the
 * library's discretisation) around y0 = 5 with white noise of std sd. */
static void make_output(const pdt_model_t *m, double sd, uint64_t seed)
{
    pdt_discrete_t d;
    assert_int_equal(pdt_discrete_init(m, (pdt_real_t)TS, &d), PDT_OK);
    assert_int_equal(pdt_discrete_simulate(&d, g_dev, N, g_clean), PDT_OK);
    sim_rng64_t r = sim_rng64_seed(~seed); /* a stream apart from the input's */
    for (size_t k = 0; k < N; k++) {
        g_y[k] = (pdt_real_t)(5.0 + (double)g_clean[k] + sd * sim_rng64_normal(&r));
    }
}

static pdt_validate_result_t validate(const pdt_model_t *m, double y0)
{
    pdt_ident_data_t data = {g_u, g_y, N};
    pdt_validate_result_t v;
    canary_fill(g_work + 5u * N, CANARY_COUNT);
    assert_int_equal(pdt_validate_model(m, &data, (pdt_real_t)TS, (pdt_real_t)y0, g_work,
                                        sizeof(pdt_real_t) * 5u * N, &v),
                     PDT_OK);
    canary_check(g_work + 5u * N, CANARY_COUNT);
    return v;
}

/* The true model with white noise: both tests pass at close to their 99 %
 * level, and sigma is the noise's std. */
static void test_true_model_accepted(void **state)
{
    (void)state;
    pdt_model_t m = model_fopdt(2.0, 5.0, 1.5);
    int white = 0, indep = 0;
    const int runs = 200;
    for (int s = 0; s < runs; s++) {
        make_input((uint64_t)s + 1u);
        make_output(&m, 0.05, (uint64_t)s + 1000u);
        pdt_validate_result_t v = validate(&m, 5.0);
        white += v.white;
        indep += v.independent;
        assert_close(v.sigma, 0.05, 0.15, 0.0);
        assert_int_equal(v.std.count, 4u);
    }
    print_message("true model: white %d, independent %d of %d\n", white, indep, runs);
    /* 99 % tests: expect about 198; binomial 3 sigma below is 194. */
    assert_true(white >= 190);
    assert_true(indep >= 190);
}

/* A FOPDT of a lead-lag process: the residual is explained by the input;
 * the model error FIR shows the high-frequency gain the zero adds. */
static void test_wrong_model_rejected(void **state)
{
    (void)state;
    /* (2s + 1) / ((4s + 1)(s + 1)) = (2/3) / (4s + 1) + (1/3) / (s + 1),
     * dead time 0.5: simulated as the sum of two FOPDTs. */
    make_input(3u);
    pdt_model_t a = model_fopdt(2.0 / 3.0, 4.0, 0.5);
    pdt_model_t b = model_fopdt(1.0 / 3.0, 1.0, 0.5);
    pdt_real_t ya[N];
    make_output(&a, 0.0, 1u);
    memcpy(ya, g_clean, sizeof ya);
    make_output(&b, 0.0, 1u);
    sim_rng64_t r = sim_rng64_seed(99u);
    for (size_t k = 0; k < N; k++) {
        g_y[k] =
            (pdt_real_t)(5.0 + (double)ya[k] + (double)g_clean[k] + 0.01 * sim_rng64_normal(&r));
    }
    /* The FOPDT a least-squares fit would give is close to this one. */
    pdt_model_t m = model_fopdt(1.0, 3.0, 0.6);
    pdt_validate_result_t v = validate(&m, 5.0);
    print_message("lead-lag as FOPDT: cross %.3g (limit %.3g), white %.3g (limit %.3g)\n",
                  (double)v.cross_stat, (double)v.cross_limit, (double)v.white_stat,
                  (double)v.white_limit);
    assert_false(v.independent);
    assert_false(v.white);
    /* The error's FIR carries gain near the dead time. */
    double sum = 0.0;
    for (uint32_t j = 0; j < PDT_VALIDATE_FIR; j++) {
        sum += fabs((double)v.fir[j]);
    }
    assert_true(sum > 0.05);
}

/* The reported std against the spread of real identifications (the
 * library's own GA and refinement) over noise seeds, the input fixed. */
static void test_std_monte_carlo(void **state)
{
    (void)state;
    pdt_model_t m = model_fopdt(2.0, 5.0, 1.5);
    const int runs = 30;
    double sum[3] = {0}, sum2[3] = {0}, rep[3] = {0};
    make_input(5u);
    for (int s = 0; s < runs; s++) {
        make_output(&m, 0.1, (uint64_t)s + 500u);
        pdt_ident_config_t ic;
        pdt_ident_config_default(&ic);
        ic.Ts = (pdt_real_t)TS;
        ic.seed = (uint64_t)s + 1u;
        pdt_ident_t ctx;
        pdt_ident_result_t res;
        pdt_ident_data_t data = {g_u, g_y, N};
        assert_int_equal(pdt_identify(&ctx, &ic, &data, g_idwork, sizeof g_idwork, &res), PDT_OK);
        pdt_ident_std_t sd;
        assert_int_equal(pdt_ident_uncertainty(&res.model, &data, (pdt_real_t)TS, res.y0, &sd),
                         PDT_OK);
        /* The identification reports the same for its own answer. */
        assert_memory_equal(&sd, &res.std, sizeof sd);
        double p[3] = {(double)res.model.p.fopdt.K, (double)res.model.p.fopdt.tau,
                       (double)res.model.p.fopdt.Td};
        for (int i = 0; i < 3; i++) {
            sum[i] += p[i];
            sum2[i] += p[i] * p[i];
            rep[i] += (double)sd.std[i] / runs;
        }
    }
    const char *names[3] = {"K", "tau", "Td"};
    for (int i = 0; i < 3; i++) {
        double mean = sum[i] / runs;
        double spread = sqrt((sum2[i] - runs * mean * mean) / (runs - 1));
        print_message("%s: mean %.4g, spread %.3g, reported %.3g (ratio %.2f)\n", names[i], mean,
                      spread, rep[i], rep[i] / spread);
        /* 30 seeds: the spread itself is known to about +-26 % (2 sigma). */
        assert_true(rep[i] / spread > 0.6 && rep[i] / spread < 1.6);
    }
}

/* The order: a FOPDT's record keeps the FOPDT, a clear SOPDT's the SOPDT. */
static void test_select_order(void **state)
{
    (void)state;
    pdt_model_kind_t kind = (pdt_model_kind_t)0;
    make_input(7u);
    pdt_model_t f = model_fopdt(2.0, 5.0, 1.5);
    pdt_model_t s = model_sopdt_tc(2.0, 4.0, 2.0, 0.5);
    /* Data of the FOPDT; the SOPDT closest to it (a tiny second lag). */
    make_output(&f, 0.05, 11u);
    pdt_validate_result_t vf = validate(&f, 5.0);
    pdt_model_t s_near = model_sopdt_tc(2.0, 5.0, 0.01, 1.495);
    pdt_validate_result_t vs = validate(&s_near, 5.0);
    assert_int_equal(pdt_ident_select_order(&vf, &vs, &kind), PDT_OK);
    assert_int_equal(kind, PDT_MODEL_FOPDT);
    /* Data of the SOPDT; a FOPDT of it fails the independence test. */
    make_output(&s, 0.01, 12u);
    vs = validate(&s, 5.0);
    pdt_model_t f_near = model_fopdt(2.0, 5.0, 1.6);
    vf = validate(&f_near, 5.0);
    assert_int_equal(pdt_ident_select_order(&vf, &vs, &kind), PDT_OK);
    assert_int_equal(kind, PDT_MODEL_SOPDT);
    /* The near-FOPDT SOPDT's second lag is not determined by FOPDT data:
     * its std is infinite, the others' finite (conditional on it). */
    make_output(&f, 0.05, 11u);
    vs = validate(&s_near, 5.0);
    print_message("SOPDT of FOPDT data: std k %.3g a %.3g b %.3g Td %.3g\n", (double)vs.std.std[0],
                  (double)vs.std.std[1], (double)vs.std.std[2], (double)vs.std.std[3]);
    /* Wrong kinds, NULL: refused, kind untouched. */
    kind = (pdt_model_kind_t)0;
    assert_int_equal(pdt_ident_select_order(&vs, &vf, &kind), PDT_ERR_ARG);
    assert_int_equal(pdt_ident_select_order(NULL, &vs, &kind), PDT_ERR_ARG);
    assert_int_equal(pdt_ident_select_order(&vf, &vs, NULL), PDT_ERR_ARG);
    assert_int_equal((int)kind, 0);
}

/* The robust bound: with no uncertainty it is the nominal Ms; it grows
 * with the uncertainty and becomes infinite when nothing is known. */
static void test_margin(void **state)
{
    (void)state;
    make_input(9u);
    pdt_model_t m = model_fopdt(2.0, 5.0, 1.5);
    make_output(&m, 0.05, 13u);
    pdt_validate_result_t v = validate(&m, 5.0);
    pdt_tune_config_t tc;
    pdt_tune_config_default(&tc);
    pdt_tune_result_t tr;
    assert_int_equal(pdt_tune_compute(&m, (pdt_real_t)100.0, &tc, &tr), PDT_OK);
    pdt_validate_result_t v0 = v;
    memset(&v0.std.cov, 0, sizeof v0.std.cov);
    v0.independent = true;
    pdt_real_t ms0 = 0, ms = 0;
    bool fir = true;
    assert_int_equal(pdt_validate_margin(&v0, (pdt_real_t)0.0, &tr.ideal, &ms0, &fir), PDT_OK);
    assert_close(ms0, tr.fig.Ms, 0.02, 0.0);
    assert_false(fir);
    assert_int_equal(pdt_validate_margin(&v, (pdt_real_t)0.0, &tr.ideal, &ms, NULL), PDT_OK);
    assert_true(ms > ms0 && ms < (pdt_real_t)2.0);
    /* Detuned gains are more robust. */
    tc.detune = (pdt_real_t)2.0;
    pdt_tune_result_t tr2;
    assert_int_equal(pdt_tune_compute(&m, (pdt_real_t)100.0, &tc, &tr2), PDT_OK);
    pdt_real_t ms2 = 0;
    assert_int_equal(pdt_validate_margin(&v, (pdt_real_t)0.0, &tr2.ideal, &ms2, NULL), PDT_OK);
    assert_true(ms2 < ms);
    /* An undetermined shape parameter is held at its estimate; an
     * undetermined gain or an unusable covariance leaves no bound. */
    v0.std.std[1] = (pdt_real_t)INFINITY;
    assert_int_equal(pdt_validate_margin(&v0, (pdt_real_t)0.0, &tr.ideal, &ms, NULL), PDT_OK);
    assert_close(ms, ms0, 1e-6, 0.0);
    v0.std.std[0] = (pdt_real_t)INFINITY;
    assert_int_equal(pdt_validate_margin(&v0, (pdt_real_t)0.0, &tr.ideal, &ms, NULL), PDT_OK);
    assert_true(!isfinite((double)ms));
    v0.std.std[0] = (pdt_real_t)1e-3;
    v0.std.cov[1][2] = (pdt_real_t)INFINITY;
    assert_int_equal(pdt_validate_margin(&v0, (pdt_real_t)0.0, &tr.ideal, &ms, NULL), PDT_OK);
    assert_true(!isfinite((double)ms));
    pdt_tune_gains_t bad = tr.ideal;
    bad.tauI = (pdt_real_t)0.0;
    assert_int_equal(pdt_validate_margin(&v, (pdt_real_t)0.0, &bad, &ms, NULL), PDT_ERR_ARG);
    assert_int_equal(pdt_validate_margin(NULL, (pdt_real_t)0.0, &tr.ideal, &ms, NULL), PDT_ERR_ARG);
}

static void test_bad_inputs(void **state)
{
    (void)state;
    make_input(1u);
    pdt_model_t m = model_fopdt(2.0, 5.0, 1.5);
    make_output(&m, 0.05, 1u);
    pdt_ident_data_t data = {g_u, g_y, N};
    pdt_validate_result_t v, before;
    memset(&v, 0x5a, sizeof v);
    before = v;
    size_t len = pdt_validate_workspace_size(N);
    assert_int_equal(len, PDT_VALIDATE_WORKSPACE_SIZE(N));
    assert_int_equal(pdt_validate_model(NULL, &data, (pdt_real_t)TS, 5, g_work, len, &v),
                     PDT_ERR_ARG);
    assert_int_equal(pdt_validate_model(&m, NULL, (pdt_real_t)TS, 5, g_work, len, &v), PDT_ERR_ARG);
    assert_int_equal(pdt_validate_model(&m, &data, (pdt_real_t)0.0, 5, g_work, len, &v),
                     PDT_ERR_ARG);
    assert_int_equal(
        pdt_validate_model(&m, &data, (pdt_real_t)TS, (pdt_real_t)NAN, g_work, len, &v),
        PDT_ERR_ARG);
    assert_int_equal(pdt_validate_model(&m, &data, (pdt_real_t)TS, 5, NULL, len, &v),
                     PDT_ERR_NOMEM);
    assert_int_equal(pdt_validate_model(&m, &data, (pdt_real_t)TS, 5, g_work, len - 1u, &v),
                     PDT_ERR_NOMEM);
    assert_int_equal(pdt_validate_model(&m, &data, (pdt_real_t)TS, 5, (char *)g_work + 1, len, &v),
                     PDT_ERR_ARG);
    pdt_ident_data_t shortd = {g_u, g_y, 40u};
    assert_int_equal(pdt_validate_model(&m, &shortd, (pdt_real_t)TS, 5, g_work, len, &v),
                     PDT_ERR_TOO_SHORT);
    pdt_model_t bad = m;
    bad.p.fopdt.tau = (pdt_real_t)-1.0;
    assert_int_equal(pdt_validate_model(&bad, &data, (pdt_real_t)TS, 5, g_work, len, &v),
                     PDT_ERR_ARG);
    assert_memory_equal(&v, &before, sizeof v);
    pdt_real_t keep = g_y[100];
    g_y[100] = (pdt_real_t)NAN;
    assert_int_equal(pdt_validate_model(&m, &data, (pdt_real_t)TS, 5, g_work, len, &v),
                     PDT_ERR_NONFINITE);
    g_y[100] = keep;
    for (size_t k = 0; k < N; k++) {
        g_u[k] = (pdt_real_t)10.0;
    }
    assert_int_equal(pdt_validate_model(&m, &data, (pdt_real_t)TS, 5, g_work, len, &v),
                     PDT_ERR_NO_EXCITATION);
    assert_memory_equal(&v, &before, sizeof v);
    pdt_ident_std_t sd;
    assert_int_equal(pdt_ident_uncertainty(&m, &data, (pdt_real_t)TS, 5, NULL), PDT_ERR_ARG);
    assert_int_equal(pdt_ident_uncertainty(&m, &data, (pdt_real_t)TS, 5, &sd),
                     PDT_ERR_NO_EXCITATION);
}

/* The same real, bit for bit. */
static bool same_bits(pdt_real_t a, pdt_real_t b)
{
    return memcmp(&a, &b, sizeof a) == 0;
}

static void assert_same_result(const pdt_validate_result_t *a, const pdt_validate_result_t *b)
{
    assert_true(same_bits(a->sigma, b->sigma) && same_bits(a->aic, b->aic) &&
                same_bits(a->bic, b->bic));
    assert_true(same_bits(a->white_stat, b->white_stat) &&
                same_bits(a->white_limit, b->white_limit) && a->white == b->white);
    assert_true(same_bits(a->cross_stat, b->cross_stat) &&
                same_bits(a->cross_limit, b->cross_limit) && a->independent == b->independent);
    assert_true(same_bits(a->inflation, b->inflation) && same_bits(a->Ts, b->Ts) && a->n == b->n &&
                a->fir_lag == b->fir_lag);
    assert_int_equal(a->std.count, b->std.count);
    for (uint32_t i = 0; i < a->std.count; i++) {
        assert_true(same_bits(a->std.std[i], b->std.std[i]));
        for (uint32_t j = 0; j < a->std.count; j++) {
            assert_true(same_bits(a->std.cov[i][j], b->std.cov[i][j]));
        }
    }
    for (uint32_t i = 0; i < PDT_VALIDATE_FIR; i++) {
        assert_true(same_bits(a->fir[i], b->fir[i]));
    }
}

/* pdt_validate_begin / pdt_validate_step give pdt_validate_model's result
 * bit for bit (a FOPDT, a SOPDT and an integrator, right and wrong models,
 * several records), in ceil(n / 256) + ceil(n / 128) + 2 steps at most,
 * nothing written past the size asked for; and the misuses. */
static void test_steps(void **state)
{
    (void)state;
    const size_t len = pdt_validate_run_workspace_size(N);
    assert_int_equal(len, PDT_VALIDATE_RUN_WORKSPACE_SIZE(N));
    assert_true(len + CANARY_COUNT * sizeof(pdt_real_t) <= sizeof g_work);
    pdt_real_t *const tail = (pdt_real_t *)(void *)((unsigned char *)g_work + len);
    const pdt_model_t plants[3] = {model_fopdt(2.0, 5.0, 1.5), model_sopdt_tc(1.5, 6.0, 2.0, 1.0),
                                   model_integ(0.2, 3.0, 1.0)};
    const pdt_model_t tried[3] = {model_fopdt(1.8, 6.0, 1.0), model_sopdt_tc(1.5, 6.0, 2.0, 1.0),
                                  model_fopdt(2.0, 5.0, 1.5)};
    const unsigned most = (N + 255u) / 256u + (N + 127u) / 128u + 2u;
    for (uint64_t seed = 1u; seed <= 3u; seed++) {
        for (size_t p = 0; p < 3u; p++) {
            make_input(seed);
            make_output(&plants[p], 0.05, seed + 50u);
            pdt_ident_data_t data = {g_u, g_y, N};
            const pdt_model_t *mods[2] = {&plants[p], &tried[p]};
            for (size_t k = 0; k < 2u; k++) {
                pdt_validate_result_t one, st_r;
                assert_int_equal(pdt_validate_model(mods[k], &data, (pdt_real_t)TS, (pdt_real_t)5.0,
                                                    g_work, pdt_validate_workspace_size(N), &one),
                                 PDT_OK);
                canary_fill(tail, CANARY_COUNT);
                assert_int_equal(pdt_validate_begin(mods[k], &data, (pdt_real_t)TS, (pdt_real_t)5.0,
                                                    g_work, len),
                                 PDT_OK);
                pdt_status_t st;
                unsigned steps = 0u;
                do {
                    st = pdt_validate_step(g_work, &st_r);
                    steps++;
                } while (st == PDT_RUNNING && steps <= most);
                canary_check(tail, CANARY_COUNT);
                assert_int_equal(st, PDT_OK);
                assert_true(steps <= most);
                assert_same_result(&st_r, &one);
                pdt_validate_result_t again;
                assert_int_equal(pdt_validate_step(g_work, &again), PDT_OK);
                assert_same_result(&again, &one);
            }
        }
    }
    /* Misuse: the begin's statuses are pdt_validate_model's; a failed begin
     * leaves nothing to step. */
    pdt_ident_data_t data = {g_u, g_y, N};
    pdt_validate_result_t v;
    pdt_model_t bad = plants[0];
    bad.p.fopdt.tau = (pdt_real_t)-1.0;
    assert_int_equal(pdt_validate_begin(&plants[0], NULL, (pdt_real_t)TS, 5, g_work, len),
                     PDT_ERR_ARG);
    assert_int_equal(pdt_validate_begin(&plants[0], &data, (pdt_real_t)TS, 5, NULL, len),
                     PDT_ERR_NOMEM);
    assert_int_equal(pdt_validate_begin(&plants[0], &data, (pdt_real_t)TS, 5, g_work, len - 1u),
                     PDT_ERR_NOMEM);
    assert_int_equal(
        pdt_validate_begin(&plants[0], &data, (pdt_real_t)TS, 5, (char *)g_work + 1, len),
        PDT_ERR_ARG);
    assert_int_equal(pdt_validate_begin(&bad, &data, (pdt_real_t)TS, 5, g_work, len), PDT_ERR_ARG);
    assert_int_equal(pdt_validate_step(g_work, &v), PDT_ERR_STATE);
    assert_int_equal(pdt_validate_step(NULL, &v), PDT_ERR_ARG);
    assert_int_equal(pdt_validate_begin(&plants[0], &data, (pdt_real_t)TS, 5, g_work, len), PDT_OK);
    assert_int_equal(pdt_validate_step(g_work, NULL), PDT_ERR_ARG);
}

/* The statuses this module's callers add have their own names. */
static void test_status_names(void **state)
{
    (void)state;
    assert_string_equal(pdt_status_str(PDT_ERR_MODEL_INVALID), "data contradict the model");
    assert_string_equal(pdt_status_str(PDT_ERR_UNCERTAIN), "model too uncertain for robust gains");
}

/* Against the numpy reference (tools/pdtref/validate.py): its sensitivities
 * are central differences in double, the library's forward differences in
 * the build's real type, so the std agrees to the differences' truncation
 * (about 1e-3) rather than to rounding. */
static void test_vectors(void **state)
{
    (void)state;
    static pdt_real_t u[VAL_VEC_N], y[VAL_VEC_N];
    for (int c = 0; c < VAL_VEC_COUNT; c++) {
        const double *p = &val_vec_par[5 * c];
        pdt_model_t m;
        memset(&m, 0, sizeof m);
        if (val_vec_kind[c] == 1) {
            m = model_fopdt(p[0], p[1], p[2]);
        } else {
            m.kind = PDT_MODEL_SOPDT;
            m.p.sopdt = (pdt_model_sopdt_t){(pdt_real_t)p[0], (pdt_real_t)p[1], (pdt_real_t)p[2],
                                            (pdt_real_t)p[3]};
        }
        double y0 = p[4];
        for (int k = 0; k < VAL_VEC_N; k++) {
            u[k] = (pdt_real_t)val_vec_u[VAL_VEC_N * c + k];
            y[k] = (pdt_real_t)val_vec_y[VAL_VEC_N * c + k];
        }
        pdt_ident_data_t data = {u, y, VAL_VEC_N};
        pdt_validate_result_t v;
        assert_int_equal(pdt_validate_model(&m, &data, (pdt_real_t)VAL_VEC_TS, (pdt_real_t)y0,
                                            g_work, sizeof(pdt_real_t) * 5u * N, &v),
                         PDT_OK);
        const double *o = &val_vec_out[VAL_VEC_NOUT * c];
        assert_close(v.sigma, o[0], 1e-3, 0.0);
        assert_close(v.aic, o[1], 0.0, 0.05);
        assert_close(v.bic, o[2], 0.0, 0.05);
        assert_close(v.white_stat, o[3], 2e-2, 0.0);
        assert_close(v.inflation, o[4], 1e-2, 0.0);
        assert_close(v.cross_stat, o[5], 3e-2, 0.05);
        assert_int_equal(v.fir_lag, (uint32_t)o[6]);
        double fmax = 0.0;
        for (uint32_t j = 0; j < PDT_VALIDATE_FIR; j++) {
            fmax = fmax > fabs(o[7 + j]) ? fmax : fabs(o[7 + j]);
        }
        for (uint32_t j = 0; j < PDT_VALIDATE_FIR; j++) {
            assert_close(v.fir[j], o[7 + j], 2e-2, 2e-3 * fmax);
        }
        for (uint32_t i = 0; i < v.std.count; i++) {
            assert_close(v.std.std[i], o[7 + PDT_VALIDATE_FIR + i], 2e-2, 0.0);
        }
        const double *gg = &val_vec_gains[4 * c];
        pdt_tune_gains_t g = {(pdt_real_t)gg[0], (pdt_real_t)gg[1], (pdt_real_t)gg[2],
                              (pdt_real_t)gg[3]};
        pdt_real_t ms;
        assert_int_equal(pdt_validate_margin(&v, (pdt_real_t)0.0, &g, &ms, NULL), PDT_OK);
        assert_close(ms, o[VAL_VEC_NOUT - 1], 1e-2, 0.0);
        print_message("validate vector %d: sigma %.4g cross %.4g white %.4g Ms bound %.4g\n", c,
                      (double)v.sigma, (double)v.cross_stat, (double)v.white_stat, (double)ms);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_vectors),
        cmocka_unit_test(test_true_model_accepted),
        cmocka_unit_test(test_wrong_model_rejected),
        cmocka_unit_test(test_std_monte_carlo),
        cmocka_unit_test(test_select_order),
        cmocka_unit_test(test_margin),
        cmocka_unit_test(test_bad_inputs),
        cmocka_unit_test(test_steps),
        cmocka_unit_test(test_status_names),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
