/*
 * Tests of lib/src/pdt_discrete.c: ZOH coefficients against the numpy
 * reference (discrete_vectors.h), DC gain, agreement of the sampled step
 * response with the continuous one, simulation and prediction, bad inputs.
 */
#include "test_util.h"

#include "discrete_vectors.h"
#include "model_vectors.h"

#define R(x) ((pdt_real_t)(x))

/* Coefficient tolerance, relative to the largest coefficient of the same
 * polynomial (a near-zero b[2] at f = 0 or tiny f is compared on that
 * scale), and relative per element for the delta form d. */
#if PDT_REAL_DOUBLE
#define COEF_RTOL  1e-12
#define SIM_SNR_DB 250.0
#define STEP_ATOL  1e-11
#else
#define COEF_RTOL  5e-6
#define SIM_SNR_DB 100.0
#define STEP_ATOL  2e-5
#endif

static pdt_model_t vec_model(int i, double Td)
{
    pdt_model_t m;
    const double *p = &model_par[4 * i];
    memset(&m, 0, sizeof m);
    if (model_kind[i] == 1) {
        m.kind = PDT_MODEL_FOPDT;
        m.p.fopdt.K = (pdt_real_t)p[0];
        m.p.fopdt.tau = (pdt_real_t)p[1];
        m.p.fopdt.Td = (pdt_real_t)Td;
    } else {
        m.kind = PDT_MODEL_SOPDT;
        m.p.sopdt.k = (pdt_real_t)p[0];
        m.p.sopdt.a = (pdt_real_t)p[1];
        m.p.sopdt.b = (pdt_real_t)p[2];
        m.p.sopdt.Td = (pdt_real_t)Td;
    }
    return m;
}

static pdt_model_t case_model(int c)
{
    return vec_model(disc_model[c], disc_par[3 * c + 1]);
}

static double max_abs(const double *v, int n)
{
    double s = 0.0;
    for (int i = 0; i < n; i++) {
        s = fabs(v[i]) > s ? fabs(v[i]) : s;
    }
    return s;
}

static void test_zoh_vectors(void **state)
{
    (void)state;
    double worst_b = 0.0;
    double worst_b01 = 0.0;
    double worst_a = 0.0;
    double worst_d = 0.0;
    double worst_int = 0.0;
    for (int c = 0; c < DISC_VEC_COUNT; c++) {
        pdt_model_t m = case_model(c);
        pdt_real_t Ts = (pdt_real_t)disc_par[3 * c];
        pdt_discrete_t d;
        assert_int_equal(pdt_discrete_init(&m, Ts, &d), PDT_OK);
        assert_int_equal((int)d.delay, disc_delay[c]);
        int order = m.kind == PDT_MODEL_FOPDT ? 1 : 2;
        assert_int_equal(d.order, order);
        const double *wa = &disc_a[2 * c];
        const double *wb = &disc_b[3 * c];
        const double *wd = &disc_d[2 * c];
        const double *wi = &disc_int_b[3 * c];
        double sb = max_abs(wb, 3);
        double si = max_abs(wi, 3);
        for (int j = 0; j < 3; j++) {
            double e = fabs((double)d.b[j] - wb[j]) / sb;
            worst_b = e > worst_b ? e : worst_b;
            assert_close(d.b[j], wb[j], 0.0, COEF_RTOL * sb);
            if (j < 2 && fabs(wb[j]) > 1e-3 * sb) {
                double r = fabs((double)d.b[j] - wb[j]) / fabs(wb[j]);
                worst_b01 = r > worst_b01 ? r : worst_b01;
            }
        }
        for (int j = 0; j < order; j++) {
            double e = fabs((double)d.a[j] - wa[j]) / max_abs(wa, 2);
            worst_a = e > worst_a ? e : worst_a;
            assert_close(d.a[j], wa[j], 0.0, COEF_RTOL * max_abs(wa, 2));
            double r = fabs((double)d.d[j] - wd[j]) / fabs(wd[j]);
            worst_d = r > worst_d ? r : worst_d;
            assert_close(d.d[j], wd[j], COEF_RTOL, 0.0);
        }
        if (order == 1) {
            assert_true(d.a[1] == R(0.0) && d.d[1] == R(0.0) && d.b[2] == R(0.0));
        } else if (model_par[4 * disc_model[c] + 2] == 0.0) {
            assert_true(d.d[1] == R(0.0)); /* integrator: a pole at exactly 1 */
        }
        /* the integer-delay model with the same l */
        pdt_discrete_t di;
        assert_int_equal(pdt_discrete_init_int(&m, Ts, (size_t)disc_delay[c], &di), PDT_OK);
        assert_int_equal((int)di.delay, disc_delay[c]);
        assert_memory_equal(di.a, d.a, sizeof d.a);
        assert_memory_equal(di.d, d.d, sizeof d.d);
        for (int j = 0; j < 3; j++) {
            double e = fabs((double)di.b[j] - wi[j]) / si;
            worst_int = e > worst_int ? e : worst_int;
            assert_close(di.b[j], wi[j], 0.0, COEF_RTOL * si);
        }
    }
    print_message("zoh over %d cases: worst error b %.3g (of max |b|), b[0..1] %.3g "
                  "(elementwise), a %.3g, d %.3g (elementwise), integer-delay b %.3g\n",
                  DISC_VEC_COUNT, worst_b, worst_b01, worst_a, worst_d, worst_int);
}

/* Sum of b over the delta form's constant term is the DC gain. */
static void test_dc_gain(void **state)
{
    (void)state;
    double worst = 0.0;
    for (int c = 0; c < DISC_VEC_COUNT; c++) {
        pdt_model_t m = case_model(c);
        pdt_real_t K;
        if (pdt_model_dc_gain(&m, &K) != PDT_OK) {
            continue; /* integrator */
        }
        pdt_discrete_t d;
        assert_int_equal(pdt_discrete_init(&m, (pdt_real_t)disc_par[3 * c], &d), PDT_OK);
        double s = (double)d.b[0] + (double)d.b[1] + (double)d.b[2];
        double g = s / (double)(d.order == 1 ? d.d[0] : d.d[1]);
        double e = fabs(g - (double)K) / fabs((double)K);
        worst = e > worst ? e : worst;
        assert_close(g, K, 10.0 * COEF_RTOL, 0.0);
    }
    print_message("DC gain sum(b)/d: worst relative error %.3g\n", worst);
}

/* The simulated unit step equals the continuous step at t = k Ts. */
static void test_step_matches_continuous(void **state)
{
    (void)state;
    enum { N = 400 };
    static pdt_real_t u[N];
    static pdt_real_t y[N + CANARY_COUNT];
    static pdt_real_t t[N];
    static pdt_real_t yc[N];
    double worst = 0.0;
    for (int i = 0; i < N; i++) {
        u[i] = R(1.0);
    }
    for (int c = 0; c < DISC_VEC_COUNT; c++) {
        pdt_model_t m = case_model(c);
        pdt_real_t Ts = (pdt_real_t)disc_par[3 * c];
        pdt_discrete_t d;
        assert_int_equal(pdt_discrete_init(&m, Ts, &d), PDT_OK);
        canary_fill(y, N + CANARY_COUNT);
        assert_int_equal(pdt_discrete_simulate(&d, u, N, y), PDT_OK);
        canary_check(y + N, CANARY_COUNT);
        for (int i = 0; i < N; i++) {
            t[i] = (pdt_real_t)i * Ts;
        }
        assert_int_equal(pdt_model_step(&m, t, N, yc), PDT_OK);
        double scale = 0.0;
        for (int i = 0; i < N; i++) {
            scale = fabs((double)yc[i]) > scale ? fabs((double)yc[i]) : scale;
        }
        for (int i = 0; i < N; i++) {
            double e = fabs((double)y[i] - (double)yc[i]) / scale;
            worst = e > worst ? e : worst;
            assert_close(y[i], yc[i], 0.0, STEP_ATOL * scale);
        }
    }
    print_message("sampled vs continuous step, %d samples: worst error %.3g of max |y|\n", N,
                  worst);
}

static void test_fraction_zero_is_integer_delay(void **state)
{
    (void)state;
    for (int i = 0; i < MODEL_VEC_COUNT; i++) {
        for (size_t l = 0; l < 5; l++) {
            pdt_real_t Ts = R(0.0625);
            pdt_model_t m = vec_model(i, (double)l * 0.0625);
            pdt_discrete_t a;
            pdt_discrete_t b;
            assert_int_equal(pdt_discrete_init(&m, Ts, &a), PDT_OK);
            assert_int_equal(pdt_discrete_init_int(&m, Ts, l, &b), PDT_OK);
            assert_int_equal(a.delay, l);
            assert_memory_equal(&a.a, &b.a, sizeof a.a);
            assert_memory_equal(&a.b, &b.b, sizeof a.b);
            assert_memory_equal(&a.d, &b.d, sizeof a.d);
            /* with f = 0 the third numerator term vanishes (up to rounding) */
            double sb = fabs((double)a.b[0]) + fabs((double)a.b[1]);
            assert_close(a.b[2], 0.0, 0.0, 10.0 * COEF_RTOL * sb);
        }
    }
    /* a dead time a hair below a whole number of samples counts as whole */
    pdt_model_t m = vec_model(0, 0.3 * 7.0);
    pdt_discrete_t d;
    assert_int_equal(pdt_discrete_init(&m, R(0.3), &d), PDT_OK);
    assert_int_equal(d.delay, 7);
    assert_close(d.b[2], 0.0, 0.0, 1e-5 * fabs((double)d.b[0]));
    /* continuity: a tiny fraction moves the coefficients only a little */
    pdt_discrete_t e;
    m = vec_model(6, 2.0 * 0.0625 + 1e-6);
    assert_int_equal(pdt_discrete_init(&m, R(0.0625), &e), PDT_OK);
    m = vec_model(6, 2.0 * 0.0625);
    assert_int_equal(pdt_discrete_init(&m, R(0.0625), &d), PDT_OK);
    assert_int_equal(e.delay, 2);
    for (int j = 0; j < 3; j++) {
        assert_close(e.b[j], d.b[j], 0.0, 1e-3 * fabs((double)d.b[0]));
    }
}

static void test_integrator_grows_linearly(void **state)
{
    (void)state;
    enum { N = 600 };
    static pdt_real_t u[N];
    static pdt_real_t y[N];
    for (int i = 0; i < N; i++) {
        u[i] = R(1.0);
    }
    pdt_model_integ_t ig = {R(0.5), R(2.0), R(0.33)};
    pdt_model_t m;
    m.kind = PDT_MODEL_SOPDT;
    assert_int_equal(pdt_model_sopdt_from_integ(&ig, &m.p.sopdt), PDT_OK);
    pdt_discrete_t d;
    const pdt_real_t Ts = R(0.125);
    assert_int_equal(pdt_discrete_init(&m, Ts, &d), PDT_OK);
    assert_int_equal(pdt_discrete_simulate(&d, u, N, y), PDT_OK);
    /* after ~18 lags: slope Ki Ts per sample, offset -(Td + T) Ki */
    for (int k = 300; k < N; k++) {
        assert_close(y[k] - y[k - 1], 0.5 * 0.125, 1e-4, 0.0);
        assert_close(y[k], 0.5 * ((double)k * 0.125 - 0.33 - 2.0), 1e-4, 0.0);
    }
}

static void load_ref(int c, pdt_discrete_t *d)
{
    memset(d, 0, sizeof *d);
    d->delay = (size_t)disc_delay[c];
    d->order = model_kind[disc_model[c]] == 1 ? 1u : 2u;
    for (int j = 0; j < 2; j++) {
        /* as the reference rounded them: a and b to float32; d computed from
         * the rounded a in double, then rounded */
        d->a[j] = (pdt_real_t)(float)disc_a[2 * c + j];
    }
    for (int j = 0; j < 3; j++) {
        d->b[j] = (pdt_real_t)(float)disc_b[3 * c + j];
    }
    double a0 = (double)(float)disc_a[2 * c];
    double a1 = (double)(float)disc_a[2 * c + 1];
    if (d->order == 1) {
        d->d[0] = (pdt_real_t)(1.0 + a0);
    } else {
        d->d[0] = (pdt_real_t)(2.0 + a0);
        d->d[1] = (pdt_real_t)(1.0 + a0 + a1);
    }
}

static void test_simulate_predict_vectors(void **state)
{
    (void)state;
    static pdt_real_t u[DISC_SIM_N];
    static pdt_real_t ym[DISC_SIM_N];
    static pdt_real_t y[DISC_SIM_N + CANARY_COUNT];
    static pdt_real_t yh[DISC_SIM_N + CANARY_COUNT];
    for (int s = 0; s < DISC_SIM_CASES; s++) {
        pdt_discrete_t d;
        load_ref(disc_sim_case[s], &d);
        for (int i = 0; i < DISC_SIM_N; i++) {
            u[i] = (pdt_real_t)disc_u[DISC_SIM_N * s + i];
            ym[i] = (pdt_real_t)disc_ymeas[DISC_SIM_N * s + i];
        }
        canary_fill(y, DISC_SIM_N + CANARY_COUNT);
        canary_fill(yh, DISC_SIM_N + CANARY_COUNT);
        assert_int_equal(pdt_discrete_simulate(&d, u, DISC_SIM_N, y), PDT_OK);
        assert_int_equal(pdt_discrete_predict(&d, u, ym, DISC_SIM_N, yh), PDT_OK);
        canary_check(y + DISC_SIM_N, CANARY_COUNT);
        canary_check(yh + DISC_SIM_N, CANARY_COUNT);
        double snr_s = snr_db(y, &disc_ysim[DISC_SIM_N * s], DISC_SIM_N);
        double snr_p = snr_db(yh, &disc_yhat[DISC_SIM_N * s], DISC_SIM_N);
        print_message("case %d (order %d, delay %zu): simulate SNR %.1f dB, predict SNR %.1f dB\n",
                      disc_sim_case[s], d.order, d.delay, snr_s, snr_p);
        assert_true(snr_s >= SIM_SNR_DB);
        assert_true(snr_p >= SIM_SNR_DB);
        /* prediction from the model's own output reproduces it */
        assert_int_equal(pdt_discrete_predict(&d, u, y, DISC_SIM_N, yh), PDT_OK);
        double scale = 0.0;
        for (int i = 0; i < DISC_SIM_N; i++) {
            scale = fabs((double)y[i]) > scale ? fabs((double)y[i]) : scale;
        }
        for (int i = 0; i < DISC_SIM_N; i++) {
            assert_close(yh[i], y[i], 0.0, 1e-5 * scale);
        }
    }
}

/* One sample at a time, with the input taken relative to an operating
 * point, is the whole-array simulation of the deviations, bit for bit. */
static void test_step_is_simulate(void **state)
{
    (void)state;
    static pdt_real_t u[DISC_SIM_N];
    static pdt_real_t du[DISC_SIM_N];
    static pdt_real_t y[DISC_SIM_N];
    const pdt_real_t u0 = R(2.5);
    for (int s = 0; s < DISC_SIM_CASES; s++) {
        pdt_discrete_t d;
        load_ref(disc_sim_case[s], &d);
        for (int i = 0; i < DISC_SIM_N; i++) {
            u[i] = (pdt_real_t)disc_u[DISC_SIM_N * s + i] + u0;
            du[i] = u[i] - u0;
        }
        assert_int_equal(pdt_discrete_simulate(&d, du, DISC_SIM_N, y), PDT_OK);
        pdt_discrete_state_t st = {R(0.0), R(0.0), R(0.0)};
        for (int i = 0; i < DISC_SIM_N; i++) {
            const pdt_real_t yk = pdt_discrete_step(&d, &st, u, u0, (size_t)i);
            assert_memory_equal(&yk, &y[i], sizeof yk);
        }
    }
}

static void test_short_records(void **state)
{
    (void)state;
    /* records shorter than the delay and the start region, and n = 0 */
    pdt_model_t m = vec_model(6, 5.0 * 0.0625 + 0.5 * 0.0625);
    pdt_discrete_t d;
    assert_int_equal(pdt_discrete_init(&m, R(0.0625), &d), PDT_OK);
    assert_int_equal(d.delay, 5);
    pdt_real_t u[12];
    pdt_real_t yl[12];
    for (int i = 0; i < 12; i++) {
        u[i] = (pdt_real_t)(i % 3) - R(0.5);
    }
    assert_int_equal(pdt_discrete_simulate(&d, u, 12, yl), PDT_OK);
    for (size_t n = 0; n < 12; n++) {
        pdt_real_t y[12 + CANARY_COUNT];
        pdt_real_t yh[12 + CANARY_COUNT];
        canary_fill(y, 12 + CANARY_COUNT);
        canary_fill(yh, 12 + CANARY_COUNT);
        assert_int_equal(pdt_discrete_simulate(&d, u, n, y), PDT_OK);
        assert_int_equal(pdt_discrete_predict(&d, u, yl, n, yh), PDT_OK);
        canary_check(y + n, 12 + CANARY_COUNT - n);
        canary_check(yh + n, 12 + CANARY_COUNT - n);
        for (size_t i = 0; i < n; i++) {
            assert_true(y[i] == yl[i]);
            if (i <= 5) {
                assert_true(y[i] == R(0.0));
            }
            assert_close(yh[i], yl[i], 1e-5, 1e-6);
        }
    }
}

/* ---- bad inputs --------------------------------------------------------- */

static void test_bad_discretize(void **state)
{
    (void)state;
    pdt_discrete_t out;
    memset(&out, 0x5c, sizeof out);
    pdt_discrete_t keep = out;
    pdt_model_t good = vec_model(6, 0.1);
    const pdt_real_t bad_ts[5] = {R(0.0), R(-0.1), (pdt_real_t)NAN, (pdt_real_t)INFINITY,
                                  -(pdt_real_t)INFINITY};
    for (int i = 0; i < 5; i++) {
        assert_int_equal(pdt_discrete_init(&good, bad_ts[i], &out), PDT_ERR_ARG);
        assert_int_equal(pdt_discrete_init_int(&good, bad_ts[i], 2, &out), PDT_ERR_ARG);
    }
    assert_int_equal(pdt_discrete_init(NULL, R(0.1), &out), PDT_ERR_ARG);
    assert_int_equal(pdt_discrete_init_int(NULL, R(0.1), 1, &out), PDT_ERR_ARG);
    assert_int_equal(pdt_discrete_init(&good, R(0.1), NULL), PDT_ERR_ARG);
    assert_int_equal(pdt_discrete_init_int(&good, R(0.1), 1, NULL), PDT_ERR_ARG);
    pdt_model_t bad[8];
    bad[0] = vec_model(0, 0.1);
    bad[0].p.fopdt.tau = R(0.0);
    bad[1] = vec_model(0, 0.1);
    bad[1].p.fopdt.K = (pdt_real_t)NAN;
    bad[2] = vec_model(0, -0.1);
    bad[3] = vec_model(6, 0.1);
    bad[3].p.sopdt.a = R(0.0);
    bad[4] = vec_model(6, 0.1);
    bad[4].p.sopdt.b = R(-1.0);
    bad[5] = vec_model(6, 0.1);
    bad[5].p.sopdt.k = (pdt_real_t)INFINITY;
    bad[6] = vec_model(6, (double)INFINITY);
    bad[7] = vec_model(6, 0.1);
    bad[7].kind = (pdt_model_kind_t)7;
    for (int i = 0; i < 8; i++) {
        assert_int_equal(pdt_discrete_init(&bad[i], R(0.1), &out), PDT_ERR_ARG);
        assert_int_equal(pdt_discrete_init_int(&bad[i], R(0.1), 1, &out), PDT_ERR_ARG);
    }
    /* a dead time of more than SIZE_MAX samples */
    pdt_model_t far = vec_model(6, 1e30);
    assert_int_equal(pdt_discrete_init(&far, R(1e-8), &out), PDT_ERR_ARG);
    assert_memory_equal(&out, &keep, sizeof out);
}

static void test_bad_simulate(void **state)
{
    (void)state;
    pdt_model_t m = vec_model(6, 0.1);
    pdt_discrete_t d;
    assert_int_equal(pdt_discrete_init(&m, R(0.05), &d), PDT_OK);
    pdt_real_t u[4] = {R(1.0), R(1.0), R(1.0), R(1.0)};
    pdt_real_t y[4 + CANARY_COUNT];
    canary_fill(y, 4 + CANARY_COUNT);
    assert_int_equal(pdt_discrete_simulate(NULL, u, 4, y), PDT_ERR_ARG);
    assert_int_equal(pdt_discrete_simulate(&d, NULL, 4, y), PDT_ERR_ARG);
    assert_int_equal(pdt_discrete_simulate(&d, u, 4, NULL), PDT_ERR_ARG);
    assert_int_equal(pdt_discrete_predict(NULL, u, u, 4, y), PDT_ERR_ARG);
    assert_int_equal(pdt_discrete_predict(&d, NULL, u, 4, y), PDT_ERR_ARG);
    assert_int_equal(pdt_discrete_predict(&d, u, NULL, 4, y), PDT_ERR_ARG);
    assert_int_equal(pdt_discrete_predict(&d, u, u, 4, NULL), PDT_ERR_ARG);
    const uint8_t orders[3] = {0u, 3u, 255u};
    for (int i = 0; i < 3; i++) {
        pdt_discrete_t b = d;
        b.order = orders[i];
        assert_int_equal(pdt_discrete_simulate(&b, u, 4, y), PDT_ERR_ARG);
        assert_int_equal(pdt_discrete_predict(&b, u, u, 4, y), PDT_ERR_ARG);
    }
    canary_check(y, 4 + CANARY_COUNT);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_zoh_vectors),
        cmocka_unit_test(test_dc_gain),
        cmocka_unit_test(test_step_matches_continuous),
        cmocka_unit_test(test_fraction_zero_is_integer_delay),
        cmocka_unit_test(test_integrator_grows_linearly),
        cmocka_unit_test(test_simulate_predict_vectors),
        cmocka_unit_test(test_step_is_simulate),
        cmocka_unit_test(test_short_records),
        cmocka_unit_test(test_bad_discretize),
        cmocka_unit_test(test_bad_simulate),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
