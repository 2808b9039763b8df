/*
 * Tests of the limits every call keeps at the edges of its domain: counts
 * that drive work are bounded (pdt_reduce_sung's n_freq, the capacity of a
 * record and of an autotune), conversions and figures that would leave the
 * real type give a status instead of an infinity or undefined behaviour,
 * and an output held constant comes back from the recorder and the
 * autotune exactly, not 1 ulp off.
 */
#include "test_util.h"

#include "pdt/pdt_autotune.h"
#include "pdt/pdt_record.h"
#include "pdt/pdt_reduce.h"
#include "pdt/pdt_tune.h"

#define R(x) ((pdt_real_t)(x))

static pdt_model_t fopdt(pdt_real_t K, pdt_real_t tau, pdt_real_t Td)
{
    pdt_model_t m;
    memset(&m, 0, sizeof m);
    m.kind = PDT_MODEL_FOPDT;
    m.p.fopdt.K = K;
    m.p.fopdt.tau = tau;
    m.p.fopdt.Td = Td;
    return m;
}

/* K = 1e10, tau = 1e-30: the scan's top frequency leaves float's range. The
 * float build must refuse; the double build may answer, but only with
 * figures that mean something. */
static void test_robustness_extreme_scales(void **state)
{
    (void)state;
    const pdt_real_t scales[][3] = {
        {R(1e10), R(1e-30), R(0.0)}, {R(1e-10), R(1e30), R(0.0)}, {R(1e10), R(1e-30), R(1e-30)},
        {R(1e30), R(1.0), R(1.0)},   {R(1.0), R(1e-37), R(0.0)},
    };
    const pdt_tune_gains_t gains[] = {
        {R(1.0), R(1.0), R(0.0), R(0.0)},
        {R(1e-10), R(1e-30), R(0.0), R(0.0)},
        {R(1.0), R(1e30), R(0.0), R(0.0)},
    };
    for (size_t i = 0; i < sizeof scales / sizeof scales[0]; i++) {
        pdt_model_t m = fopdt(scales[i][0], scales[i][1], scales[i][2]);
        for (size_t j = 0; j < sizeof gains / sizeof gains[0]; j++) {
            pdt_tune_figures_t f;
            memset(&f, 0xA5, sizeof f);
            pdt_tune_figures_t before = f;
            pdt_status_t st = pdt_tune_robustness(&m, &gains[j], &f);
            if (st != PDT_OK) {
                assert_true(st < 0);
                assert_memory_equal(&f, &before, sizeof f);
                continue;
            }
            assert_true(f.Ms >= R(1.0) && isfinite((double)f.Ms));
            assert_false(isnan((double)f.gain_margin) || isnan((double)f.phase_margin_deg));
            assert_false(isnan((double)f.w_ms) || isnan((double)f.w_gc) || isnan((double)f.w_pc));
        }
    }
#if !PDT_REAL_DOUBLE
    /* The case of the report: OK with Ms = 1 before, from a NaN cast. */
    pdt_model_t m = fopdt(R(1e10), R(1e-30), R(0.0));
    pdt_tune_figures_t f;
    assert_int_equal(pdt_tune_robustness(&m, &gains[0], &f), PDT_ERR_ARG);
#endif
}

static void test_to_series_large(void **state)
{
    (void)state;
    const pdt_tune_gains_t cases[] = {
        {R(1e30), R(1e30), R(0.0), R(0.0)},
        {R(1e30), R(1e30), R(1e29), R(0.0)},
        {R(-3e38), R(3e38), R(7e37), R(1.0)},
        {R(1e-30), R(1e-30), R(2.5e-31), R(0.0)},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        pdt_tune_gains_t s;
        assert_int_equal(pdt_tune_to_series(&cases[i], &s), PDT_OK);
        assert_true(isfinite((double)s.Kc) && s.Kc != R(0.0));
        assert_true(isfinite((double)s.tauI) && s.tauI > R(0.0));
        assert_true(isfinite((double)s.tauD) && s.tauD >= R(0.0));
        /* The series Kc is the ideal one times a factor in [1/2, 1]. */
        double ratio = (double)s.Kc / (double)cases[i].Kc;
        assert_true(ratio >= 0.5 - 1e-6 && ratio <= 1.0 + 1e-6);
    }
}

static void test_reduce_n_freq_bound(void **state)
{
    (void)state;
    const pdt_real_t lags[] = {R(2.0), R(1.0), R(0.4)};
    pdt_reduce_plant_t p = {R(1.0), lags, 3u, NULL, 0u, R(0.5)};
    pdt_reduce_config_t c;
    pdt_reduce_config_default(&c);
    pdt_model_t m;
    memset(&m, 0x5A, sizeof m);
    pdt_model_t before = m;
    const uint32_t too_many[] = {PDT_REDUCE_MAX_FREQ + 1u, UINT32_MAX};
    for (int model = 0; model < 2; model++) {
        c.model = model == 0 ? PDT_MODEL_FOPDT : PDT_MODEL_SOPDT;
        for (size_t i = 0; i < 2u; i++) {
            c.n_freq = too_many[i];
            assert_int_equal(pdt_reduce_sung(&p, &c, &m, NULL), PDT_ERR_LENGTH);
            assert_memory_equal(&m, &before, sizeof m);
        }
        c.n_freq = PDT_REDUCE_MAX_FREQ;
        assert_int_equal(pdt_reduce_sung(&p, &c, &m, NULL), PDT_OK);
        m = before;
    }
}

static pdt_real_t g_u[64], g_y[64];

static void test_record_capacity_bound(void **state)
{
    (void)state;
    pdt_record_config_t c;
    pdt_record_config_default(&c);
    pdt_record_t rec;
    memset(&rec, 0x3C, sizeof rec);
    pdt_record_t before = rec;
    /* The arrays are far shorter than the capacity: a call that accepted
     * the capacity could not be checked, but none of these may. */
    const size_t caps[] = {(size_t)PDT_MAX_SAMPLES + 1u, SIZE_MAX / sizeof(pdt_real_t), SIZE_MAX};
    for (size_t i = 0; i < sizeof caps / sizeof caps[0]; i++) {
        assert_int_equal(pdt_record_init(&rec, &c, g_u, g_y, caps[i]), PDT_ERR_LENGTH);
        assert_memory_equal(&rec, &before, sizeof rec);
    }
}

static void test_autotune_capacity_bound(void **state)
{
    (void)state;
    pdt_autotune_config_t c;
    pdt_autotune_config_default(&c);
    c.Ts = R(0.1);
    c.u_min = R(0.0);
    c.u_max = R(100.0);
    c.pv_min = R(-1000.0);
    c.pv_max = R(1000.0);
    const size_t caps[] = {(size_t)PDT_MAX_SAMPLES + 1u, 100000000u, SIZE_MAX};
    for (size_t i = 0; i < sizeof caps / sizeof caps[0]; i++) {
        c.capacity = caps[i];
        assert_int_equal(pdt_autotune_workspace_size(&c), 0u);
        pdt_autotune_t at;
        memset(&at, 0x77, sizeof at);
        unsigned char probe[sizeof at];
        memcpy(probe, &at, sizeof at);
        static pdt_real_t work[256];
        assert_int_equal(pdt_autotune_init(&at, &c, R(50.0), work, sizeof work), PDT_ERR_LENGTH);
        assert_memory_equal(&at, probe, sizeof at);
    }
}

/* A held output that is no sum of powers of two comes back exactly from
 * the recorder's means, whatever the decimation. */
static void test_record_exact_operating_point(void **state)
{
    (void)state;
    const pdt_real_t held[] = {R(0.1), R(1.0) / R(3.0), R(-7.7), R(12345.678)};
    for (uint32_t dec = 1u; dec <= 7u; dec++) {
        for (size_t h = 0; h < sizeof held / sizeof held[0]; h++) {
            pdt_record_config_t c;
            pdt_record_config_default(&c);
            c.decimation = dec;
            c.settle = 13u;
            pdt_record_t rec;
            assert_int_equal(pdt_record_init(&rec, &c, g_u, g_y, 64u), PDT_OK);
            for (uint32_t k = 0; k < dec * c.settle; k++) {
                assert_int_equal(pdt_record_push(&rec, held[h], R(2.0) + R(0.01) * (pdt_real_t)k),
                                 PDT_RUNNING);
            }
            pdt_record_result_t rr;
            assert_int_equal(pdt_record_result(&rec, &rr), PDT_OK);
            assert_true(rr.settled);
            assert_true(rr.u0 == held[h]);
            assert_true(rr.u_safe == held[h]);
            for (uint32_t i = 0; i < c.settle; i++) {
                assert_true(g_u[i] == held[h]);
            }
        }
    }
}

#define AT_CAP 400u
static pdt_real_t
    g_work[PDT_AUTOTUNE_WORKSPACE_SIZE(AT_CAP, PDT_IDENT_POPULATION_SOPDT) / sizeof(pdt_real_t)];

/* After the experiment the autotune holds the operating point it started
 * from, bit for bit, through identification, tuning and the end. */
static void test_autotune_returns_exact_output(void **state)
{
    (void)state;
    const pdt_real_t starts[] = {R(10.1), R(33.3), R(71.17)};
    for (uint32_t dec = 1u; dec <= 3u; dec++) {
        for (size_t s = 0; s < sizeof starts / sizeof starts[0]; s++) {
            pdt_autotune_config_t c;
            pdt_autotune_config_default(&c);
            c.Ts = R(0.05);
            c.decimation = dec;
            c.capacity = AT_CAP;
            c.u_min = R(0.0);
            c.u_max = R(100.0);
            c.pv_min = R(-1000.0);
            c.pv_max = R(1000.0);
            c.excite.amplitude = R(5.0);
            size_t need = pdt_autotune_workspace_size(&c);
            assert_true(need > 0u && need <= sizeof g_work);
            pdt_autotune_t at;
            pdt_real_t u0 = starts[s];
            assert_int_equal(pdt_autotune_init(&at, &c, u0, g_work, need), PDT_OK);
            /* A first-order lag with a two-scan delay, in double. */
            double y = 0.0;
            double d1 = 0.0, d2 = 0.0;
            pdt_real_t u = u0;
            pdt_status_t st = PDT_RUNNING;
            uint32_t scans = 0;
            while (st == PDT_RUNNING && scans < 200000u) {
                pdt_autotune_phase_t ph = pdt_autotune_phase(&at);
                st = pdt_autotune_scan(&at, (pdt_real_t)(10.0 + y), &u);
                if (ph == PDT_AUTOTUNE_IDENTIFY || ph == PDT_AUTOTUNE_TUNE) {
                    assert_true(u == u0);
                }
                y += 0.02 * (2.0 * d2 - y);
                d2 = d1;
                d1 = (double)u - (double)u0;
                scans++;
            }
            assert_true(st != PDT_RUNNING);
            assert_true(u == u0);
            assert_int_equal(pdt_autotune_scan(&at, R(10.0), &u), st);
            assert_true(u == u0);
        }
    }
}

/* The identification's size query covers what init uses, for every record
 * length and criterion: the frequency cost's FFT shrinks as the delay bound
 * grows, so the query must take init's own bound (found by fuzz_autotune:
 * init wrote past a workspace of the queried size). */
static void test_ident_workspace_covers_init(void **state)
{
    (void)state;
    static pdt_real_t u[400], y[400];
    static unsigned char work[1u << 16];
    static pdt_ident_t ctx;
    for (size_t k = 0; k < 400u; k++) {
        u[k] = (k >= 5u && k < 200u) ? (pdt_real_t)1 : (pdt_real_t)0;
        y[k] = (pdt_real_t)(k >= 8u ? 0.5 : 0.0) * (k < 203u ? (pdt_real_t)1 : (pdt_real_t)0);
    }
    const pdt_cost_kind_t kinds[] = {PDT_COST_SIMULATION, PDT_COST_FREQUENCY, PDT_COST_COMBINED};
    for (size_t ik = 0; ik < 3u; ik++) {
        for (size_t n = 24u; n <= 400u; n += 7u) {
            pdt_ident_config_t cfg;
            pdt_ident_config_default(&cfg);
            cfg.Ts = (pdt_real_t)0.1;
            cfg.cost = kinds[ik];
            cfg.max_evaluations = 120u;
            cfg.refine_evaluations = 4u;
            cfg.population = 6u;
            size_t need = pdt_ident_workspace_size(&cfg, n);
            if (need == 0u || need + 64u > sizeof work) {
                continue;
            }
            memset(work, 0xCD, sizeof work);
            pdt_ident_data_t d = {u, y, n};
            pdt_status_t st = pdt_ident_init(&ctx, &cfg, &d, work, need);
            while (st == PDT_OK || st == PDT_RUNNING) {
                st = pdt_ident_step(&ctx, 50u);
                if (st == PDT_OK) {
                    break;
                }
            }
            for (size_t i = 0; i < 64u; i++) {
                if (work[need + i] != 0xCDu) {
                    fail_msg("cost %d, n %zu: written past the queried %zu bytes", (int)kinds[ik],
                             n, need);
                }
            }
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_robustness_extreme_scales),
        cmocka_unit_test(test_to_series_large),
        cmocka_unit_test(test_reduce_n_freq_bound),
        cmocka_unit_test(test_record_capacity_bound),
        cmocka_unit_test(test_autotune_capacity_bound),
        cmocka_unit_test(test_record_exact_operating_point),
        cmocka_unit_test(test_autotune_returns_exact_output),
        cmocka_unit_test(test_ident_workspace_covers_init),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
