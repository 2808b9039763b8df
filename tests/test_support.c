/*
 * Tests of the shared simulator (tools/sim/sim_plant.c) against
 * closed forms: the exact sampled FOPDT with a fractional dead time
 * (docs/equations.md), step responses of a lag with a zero on either side,
 * of a complex pair, of an integrator, and the refusals; a realisation
 * loaded from outside and a reset give the same outputs; the 64-bit
 * generator's stream and normals.
 */
#include "test_util.h"

#include "sim_plant.h"
#include "sim_rng.h"

static double g_hist[4096];

/* y(k) = a y(k-1) + b1 u(k-1-l) + b2 u(k-2-l), the exact ZOH FOPDT. */
static void test_fopdt_exact(void **state)
{
    (void)state;
    const double K = 1.7, T = 2.3, Ts = 0.1, Td = 0.73;
    const double lags[1] = {T};
    sim_plant_desc_t d = sim_plant_desc_lags(K, lags, 1u, Td);
    sim_plant_t p;
    assert_int_equal(sim_plant_init(&p, &d, Ts, 5.0, 20.0, g_hist, 4096u), 0);
    const double a = exp(-Ts / T);
    const size_t l = 7u;
    const double m = 1.0 - (Td / Ts - (double)l);
    const double b1 = K * (1.0 - pow(a, m)), b2 = K * (pow(a, m) - a);
    double u[400], yr = 0.0;
    sim_rng64_t r = sim_rng64_seed(3u);
    for (size_t k = 0; k < 400u; k++) {
        u[k] = 5.0 + (sim_rng64_coin(&r) ? 1.0 : -1.0);
    }
    for (size_t k = 0; k < 400u; k++) {
        double uk1 = (k >= l + 1u) ? u[k - l - 1u] - 5.0 : 0.0;
        double uk2 = (k >= l + 2u) ? u[k - l - 2u] - 5.0 : 0.0;
        if (k > 0u) {
            yr = a * yr + b1 * uk1 + b2 * uk2;
        }
        assert_close(sim_plant_output(&p), 20.0 + yr, 1e-12, 1e-12);
        sim_plant_apply(&p, u[k]);
    }
}

/* Step of K (Z s + 1) / (T s + 1) e^{-D s}: K (1 - (1 - Z/T) e^{-(t-D)/T}). */
static void test_lag_with_zero(void **state)
{
    (void)state;
    const double lags[1] = {1.5};
    for (int sgn = -1; sgn <= 1; sgn += 2) {
        const double zeros[1] = {0.6 * sgn};
        sim_plant_desc_t d = sim_plant_desc_lags(2.0, lags, 1u, 0.25);
        d.zeros = zeros;
        d.n_zeros = 1u;
        sim_plant_t p;
        assert_int_equal(sim_plant_init(&p, &d, 0.1, 0.0, 0.0, g_hist, 4096u), 0);
        for (size_t k = 0; k < 100u; k++) {
            double t = 0.1 * (double)k;
            /* read before the switch: the step (applied at 0) acts from D */
            double want = (t > 0.25 + 1e-9)
                              ? 2.0 * (1.0 - (1.0 - zeros[0] / 1.5) * exp(-(t - 0.25) / 1.5))
                              : 0.0;
            assert_close(sim_plant_output(&p), want, 1e-10, 1e-10);
            sim_plant_apply(&p, 1.0);
        }
    }
}

/* Step of a complex pair: 1 - e^{-s t}(cos wd t + s/wd sin wd t). */
static void test_complex_pair(void **state)
{
    (void)state;
    sim_plant_desc_t d = sim_plant_desc_lags(1.3, NULL, 0u, 0.0);
    d.wn = 0.8;
    d.zeta = 0.3;
    sim_plant_t p;
    assert_int_equal(sim_plant_init(&p, &d, 0.05, 0.0, 0.0, g_hist, 4096u), 0);
    const double sg = 0.24, wd = 0.8 * sqrt(1.0 - 0.09);
    for (size_t k = 0; k < 600u; k++) {
        double t = 0.05 * (double)k;
        double want = 1.3 * (1.0 - exp(-sg * t) * (cos(wd * t) + sg / wd * sin(wd * t)));
        assert_close(sim_plant_output(&p), want, 1e-10, 1e-10);
        sim_plant_apply(&p, 1.0);
    }
}

/* Step of Ki / (s (T s + 1)): Ki (t - T (1 - e^{-t/T})). */
static void test_integrator(void **state)
{
    (void)state;
    const double lags[1] = {0.7};
    sim_plant_desc_t d = sim_plant_desc_lags(0.4, lags, 1u, 0.0);
    d.integrating = true;
    sim_plant_t p;
    assert_int_equal(sim_plant_init(&p, &d, 0.2, 1.0, 3.0, g_hist, 4096u), 0);
    for (size_t k = 0; k < 200u; k++) {
        double t = 0.2 * (double)k;
        double want = 3.0 + 0.4 * (t - 0.7 * (1.0 - exp(-t / 0.7)));
        assert_close(sim_plant_output(&p), want, 1e-10, 1e-10);
        sim_plant_apply(&p, 2.0);
    }
}

/* Equal numerator and denominator degrees: the feedthrough shows at once. */
static void test_biproper(void **state)
{
    (void)state;
    const double lags[1] = {1.0};
    const double zeros[1] = {3.0};
    sim_plant_desc_t d = sim_plant_desc_lags(1.0, lags, 1u, 0.0);
    d.zeros = zeros;
    d.n_zeros = 1u;
    sim_plant_t p;
    assert_int_equal(sim_plant_init(&p, &d, 0.1, 0.0, 0.0, g_hist, 4096u), 0);
    sim_plant_apply(&p, 1.0);
    /* one scan after the step: 1 - (1 - 3) e^{-0.1} */
    assert_close(sim_plant_output(&p), 1.0 + 2.0 * exp(-0.1), 1e-12, 1e-12);
}

/* A realisation loaded as such (the benchmark's way) runs as the plant it
 * came from, and a reset starts the same run again. */
static void test_discrete_and_reset(void **state)
{
    (void)state;
    const double lags[2] = {2.0, 0.7};
    sim_plant_desc_t d = sim_plant_desc_lags(-1.2, lags, 2u, 0.37);
    d.wn = 1.3;
    d.zeta = 0.3;
    sim_plant_t p, q;
    static double hq[64];
    assert_int_equal(sim_plant_init(&p, &d, 0.1, 0.0, 0.0, g_hist, 4096u), 0);
    assert_int_equal(p.l, 3u);
    assert_int_equal(sim_plant_init_discrete(&q, p.n, p.l, p.Phi, p.Gam, p.Gam_prev, p.C, hq, 64u),
                     0);
    double first[300];
    sim_rng64_t r = sim_rng64_seed(11u);
    for (int pass = 0; pass < 2; pass++) {
        for (size_t k = 0; k < 300u; k++) {
            const double u = pass == 0 ? sim_rng64_uniform(&r) : 0.0;
            if (pass == 0) {
                first[k] = u;
            }
            assert_close(sim_plant_output(&q), sim_plant_output(&p), 0.0, 1e-15);
            sim_plant_apply(&p, first[k]);
            sim_plant_apply(&q, first[k]);
        }
        if (pass == 0) {
            assert_true(fabs(sim_plant_output(&p)) > 0.1);
            sim_plant_reset(&p);
            sim_plant_reset(&q);
            assert_true(sim_plant_output(&p) == 0.0 && sim_plant_output(&q) == 0.0);
        }
    }
    /* refusals: no states, too many, a NaN, a history too short */
    assert_int_equal(sim_plant_init_discrete(&q, 0u, 0u, p.Phi, p.Gam, p.Gam_prev, p.C, hq, 64u),
                     -1);
    assert_int_equal(sim_plant_init_discrete(&q, SIM_PLANT_MAX_STATES + 1u, 0u, p.Phi, p.Gam,
                                             p.Gam_prev, p.C, hq, 64u),
                     -1);
    p.Gam[1] = (double)NAN;
    assert_int_equal(sim_plant_init_discrete(&q, p.n, 0u, p.Phi, p.Gam, p.Gam_prev, p.C, hq, 64u),
                     -1);
    p.Gam[1] = 0.0;
    assert_int_equal(sim_plant_init_discrete(&q, p.n, 63u, p.Phi, p.Gam, p.Gam_prev, p.C, hq, 64u),
                     -1);
}

/* splitmix64's published first outputs from state 0, the first output of
 * seed 7 as pdtsupport.rng.SplitMix64(7).next64() gives it, and normals of
 * mean 0 and deviation 1. */
static void test_rng64(void **state)
{
    (void)state;
    sim_rng64_t r = {0u};
    assert_true(sim_rng64_next(&r) == 0xE220A8397B1DCDAFull);
    assert_true(sim_rng64_next(&r) == 0x6E789E6AA1B965F4ull);
    r = sim_rng64_seed(7u);
    assert_true(sim_rng64_next(&r) == 0x4BAF8CAC4784CB12ull);
    r = sim_rng64_seed(12345u);
    double s1 = 0.0, s2 = 0.0;
    const int n = 100000;
    for (int i = 0; i < n; i++) {
        const double z = sim_rng64_normal(&r);
        s1 += z;
        s2 += z * z;
    }
    assert_close(s1 / n, 0.0, 0.0, 0.01);
    assert_close(s2 / n, 1.0, 0.0, 0.02);
}

static void test_refusals(void **state)
{
    (void)state;
    const double lags[2] = {1.0, -1.0};
    const double zeros[2] = {1.0, 2.0};
    sim_plant_t p;
    sim_plant_desc_t d = sim_plant_desc_lags(1.0, lags, 1u, 0.0);
    assert_int_equal(sim_plant_init(NULL, &d, 0.1, 0.0, 0.0, g_hist, 4096u), -1);
    assert_int_equal(sim_plant_init(&p, &d, 0.0, 0.0, 0.0, g_hist, 4096u), -1);
    d.zeros = zeros;
    d.n_zeros = 2u; /* improper */
    assert_int_equal(sim_plant_init(&p, &d, 0.1, 0.0, 0.0, g_hist, 4096u), -1);
    d = sim_plant_desc_lags(1.0, lags, 2u, 0.0); /* a negative lag */
    assert_int_equal(sim_plant_init(&p, &d, 0.1, 0.0, 0.0, g_hist, 4096u), -1);
    d = sim_plant_desc_lags(1.0, lags, 1u, 10.0); /* 100 scans of delay, 10 of history */
    assert_int_equal(sim_plant_init(&p, &d, 0.1, 0.0, 0.0, g_hist, 10u), -1);
    assert_int_equal(sim_plant_init(&p, &d, 0.1, 0.0, 0.0, g_hist, SIM_PLANT_HIST_LEN(10.0, 0.1)),
                     0);
}

/* The frequency response against the closed form of a lag, a zero, a
 * complex pair and an integrator in series, and the ultimate frequency of
 * K e^{-s} / (s + 1), where atan(w) + w = pi. */
static void test_frequency(void **state)
{
    (void)state;
    const double lags[1] = {2.0};
    const double zeros[1] = {-0.5};
    sim_plant_desc_t d = sim_plant_desc_lags(-1.5, lags, 1u, 0.3);
    d.zeros = zeros;
    d.n_zeros = 1u;
    d.wn = 3.0;
    d.zeta = 0.4;
    d.integrating = true;
    const double w = 0.7;
    double mag, ph;
    sim_plant_freq(&d, w, &mag, &ph);
    const double re = 1.0 - (w / 3.0) * (w / 3.0), im = 0.8 * w / 3.0;
    assert_close(mag, 1.5 * hypot(1.0, 0.5 * w) / hypot(1.0, 2.0 * w) / hypot(re, im) / w, 1e-14,
                 0.0);
    assert_close(ph, -M_PI - 0.3 * w - atan(2.0 * w) + atan(-0.5 * w) - atan2(im, re) - M_PI / 2,
                 1e-14, 0.0);
    const double one[1] = {1.0};
    sim_plant_desc_t f = sim_plant_desc_lags(2.0, one, 1u, 1.0);
    const double wu = sim_plant_ultimate_w(&f, 1.0);
    assert_close(atan(wu) + wu, M_PI, 1e-12, 0.0);
    f.K = -2.0; /* the sign of the gain does not move the crossover */
    assert_close(sim_plant_ultimate_w(&f, 1.0), wu, 1e-12, 0.0);
    f.delay = 0.0; /* a lag alone never reaches -pi */
    assert_true(sim_plant_ultimate_w(&f, 1.0) == 0.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fopdt_exact),  cmocka_unit_test(test_lag_with_zero),
        cmocka_unit_test(test_complex_pair), cmocka_unit_test(test_integrator),
        cmocka_unit_test(test_biproper),     cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_frequency),    cmocka_unit_test(test_discrete_and_reset),
        cmocka_unit_test(test_rng64),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
