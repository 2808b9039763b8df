/*
 * Tests of pdt_monitor: the configuration's checks and every bad input with
 * the object left untouched; the verdicts on closed loops of pdt_pid around
 * the shared process simulator (well tuned, aggressive, a process gain
 * changed since the model, an output held at a limit, a record too short);
 * the decimation as block averages; the block call. The figures themselves
 * are checked against the numpy reference through the command line
 * (tools/tests/test_monitor.py).
 */
#include "test_util.h"
#include "sim_process.h"

#include "pdt/pdt_monitor.h"

#define R(x) ((pdt_real_t)(x))

static pdt_monitor_config_t base_config(void)
{
    pdt_monitor_config_t c;
    pdt_monitor_config_default(&c);
    c.Ts = R(0.5);
    c.horizon = 0u;
    c.has_model = true;
    c.model = model_fopdt(1.0, 10.0, 2.0);
    return c;
}

static void test_config_default(void **state)
{
    (void)state;
    pdt_monitor_config_default(NULL);
    pdt_monitor_config_t c;
    pdt_monitor_config_default(&c);
    assert_true(c.Ts == R(0.1) && c.decimation == 1u && c.horizon == 3000u &&
                c.min_samples == 400u && !c.has_model && c.u_min == R(0.0) && c.u_max == R(0.0));
    pdt_monitor_t m;
    assert_int_equal(pdt_monitor_init(&m, &c), PDT_OK);
    pdt_monitor_result_t r;
    assert_int_equal(pdt_monitor_result(&m, &r), PDT_OK);
    assert_int_equal(r.verdict, PDT_MONITOR_NOT_ENOUGH_DATA);
    assert_int_equal(r.samples, 0);
}

static void test_init_refuses(void **state)
{
    (void)state;
    pdt_monitor_t m;
    memset(&m, 0x5a, sizeof m);
    const pdt_monitor_t before = m;
    pdt_monitor_config_t c = base_config();
    assert_int_equal(pdt_monitor_init(NULL, &c), PDT_ERR_ARG);
    assert_int_equal(pdt_monitor_init(&m, NULL), PDT_ERR_ARG);
    pdt_monitor_config_t bad[12];
    for (size_t i = 0; i < 12; i++) {
        bad[i] = c;
    }
    bad[0].Ts = R(0.0);
    bad[1].decimation = 0u;
    bad[2].min_samples = 8u;
    bad[3].u_min = R(1.0); /* above u_max */
    bad[4].sat_band = R(0.5);
    bad[5].osc_acf = R(0.0);
    bad[6].osc_acf = R(1.5);
    bad[7].sluggish_ratio = R(1.0);
    bad[8].mismatch_t = R(-1.0);
    bad[9].model.p.fopdt.tau = R(-1.0);
    bad[10].stiction_corr_v = R(2.0);
    bad[11].sat_share = R(0.0);
    for (size_t i = 0; i < 12; i++) {
        assert_int_equal(pdt_monitor_init(&m, &bad[i]), PDT_ERR_ARG);
    }
    /* A dead time of PDT_MONITOR_ORDER - 1 samples or more. */
    c.model.p.fopdt.Td = R(0.5) * (pdt_real_t)(PDT_MONITOR_ORDER - 1u);
    assert_int_equal(pdt_monitor_init(&m, &c), PDT_ERR_LENGTH);
    assert_memory_equal(&m, &before, sizeof m);
    c.decimation = 2u; /* half as many samples of dead time */
    assert_int_equal(pdt_monitor_init(&m, &c), PDT_OK);
}

static void test_scan_refuses(void **state)
{
    (void)state;
    pdt_monitor_t m;
    memset(&m, 0, sizeof m);
    pdt_monitor_result_t r;
    assert_int_equal(pdt_monitor_scan(NULL, R(0.0), R(0.0), R(0.0)), PDT_ERR_ARG);
    assert_int_equal(pdt_monitor_scan(&m, R(0.0), R(0.0), R(0.0)), PDT_ERR_STATE);
    assert_int_equal(pdt_monitor_result(&m, &r), PDT_ERR_STATE);
    pdt_monitor_config_t c = base_config();
    assert_int_equal(pdt_monitor_init(&m, &c), PDT_OK);
    assert_int_equal(pdt_monitor_result(&m, NULL), PDT_ERR_ARG);
    assert_int_equal(pdt_monitor_scan(&m, R(1.0), R(2.0), R(3.0)), PDT_OK);
    const pdt_monitor_t before = m;
    assert_int_equal(pdt_monitor_scan(&m, R(NAN), R(0.0), R(0.0)), PDT_ERR_NONFINITE);
    assert_int_equal(pdt_monitor_scan(&m, R(0.0), R(INFINITY), R(0.0)), PDT_ERR_NONFINITE);
    assert_int_equal(pdt_monitor_scan(&m, R(0.0), R(0.0), R(NAN)), PDT_ERR_NONFINITE);
    assert_memory_equal(&m, &before, sizeof m);
    const pdt_real_t sp[3] = {R(1.0), R(1.0), R(1.0)};
    const pdt_real_t pv[3] = {R(1.0), R(NAN), R(1.0)};
    size_t done = 99u;
    assert_int_equal(pdt_monitor_scan_block(&m, sp, pv, sp, 3u, &done), PDT_ERR_NONFINITE);
    assert_int_equal(done, 1u);
    assert_int_equal(pdt_monitor_scan_block(&m, NULL, pv, sp, 3u, &done), PDT_ERR_ARG);
    assert_int_equal(pdt_monitor_scan_block(&m, NULL, NULL, NULL, 0u, NULL), PDT_OK);
    assert_string_equal(pdt_monitor_verdict_str(PDT_MONITOR_MODEL_CHANGED), "model_changed");
    assert_string_equal(pdt_monitor_verdict_str((pdt_monitor_verdict_t)99), "?");
    assert_string_equal(pdt_monitor_cause_str(PDT_MONITOR_CAUSE_STICTION), "stiction");
    assert_string_equal(pdt_monitor_cause_str((pdt_monitor_cause_t)99), "?");
}

/* A loop of pdt_pid (gains Kc, Ti) around the process (model m, gain times
 * gain_factor) read with noise, the set-point stepping between two levels
 * at irregular times (a periodic set-point makes the error periodic: an
 * oscillation the monitor cannot tell from the loop's own), the output
 * within [u_lo, u_hi]; n scans into the monitor. */
typedef struct loop_case {
    double Kc, Ti, gain_factor, u_lo, u_hi, sp_amp;
    size_t n;
} loop_case_t;

static pdt_monitor_result_t run_loop(const loop_case_t *lc, pdt_monitor_config_t *c)
{
    static sim_process_t proc;
    pdt_model_t truth = c->model;
    truth.p.fopdt.K *= (pdt_real_t)lc->gain_factor;
    assert_int_equal(sim_process_init(&proc, &truth, (double)c->Ts, 50.0, 20.0, 0.02, 7u), 0);
    pdt_pid_config_t pc;
    pdt_pid_config_default(&pc);
    pc.Ts = c->Ts;
    pc.Kc = (pdt_real_t)lc->Kc;
    pc.Ti = (pdt_real_t)lc->Ti;
    pc.u_min = (pdt_real_t)lc->u_lo;
    pc.u_max = (pdt_real_t)lc->u_hi;
    pdt_pid_t pid;
    assert_int_equal(pdt_pid_init(&pid, &pc, R(50.0)), PDT_OK);
    pdt_monitor_t mon;
    assert_int_equal(pdt_monitor_init(&mon, c), PDT_OK);
    for (size_t k = 0; k < lc->n; k++) {
        static const size_t steps[] = {150u,  380u,  520u,  800u,  1010u, 1300u, 1420u,
                                       1700u, 1950u, 2200u, 2330u, 2600u, 2870u};
        size_t level = 0u;
        for (size_t i = 0; i < sizeof steps / sizeof steps[0]; i++) {
            level += k >= steps[i] ? 1u : 0u;
        }
        const pdt_real_t sp = R(20.0) + ((level % 2u) ? (pdt_real_t)lc->sp_amp : R(0.0));
        const pdt_real_t pv = sim_process_pv(&proc);
        pdt_real_t u;
        assert_int_equal(pdt_pid_update(&pid, sp, pv, &u), PDT_OK);
        assert_int_equal(pdt_monitor_scan(&mon, sp, pv, u), PDT_OK);
        sim_process_apply(&proc, u);
    }
    pdt_monitor_result_t r;
    assert_int_equal(pdt_monitor_result(&mon, &r), PDT_OK);
    return r;
}

static void test_well_tuned_is_ok(void **state)
{
    (void)state;
    pdt_monitor_config_t c = base_config();
    /* SIMC, tau_c = theta: Kc = tau / (K 2 theta), Ti = min(tau, 8 theta). */
    const loop_case_t lc = {2.5, 10.0, 1.0, 0.0, 100.0, 1.0, 3000u};
    const pdt_monitor_result_t r = run_loop(&lc, &c);
    assert_int_equal(r.verdict, PDT_MONITOR_OK);
    assert_true(r.has_harris && r.harris > R(0.0) && r.harris <= R(1.0));
    assert_int_equal(r.delay_samples, 5u);
    assert_true(r.has_mismatch && r.gain_ratio > R(0.8) && r.gain_ratio < R(1.25));
    assert_true(r.has_sluggish && r.iae_ratio < R(1.5));
    assert_false(r.has_saturation);
}

static void test_aggressive_oscillates(void **state)
{
    (void)state;
    pdt_monitor_config_t c = base_config();
    const loop_case_t lc = {6.0, 10.0, 1.0, 0.0, 100.0, 1.0, 3000u};
    const pdt_monitor_result_t r = run_loop(&lc, &c);
    assert_int_equal(r.verdict, PDT_MONITOR_OSCILLATING);
    assert_int_equal(r.cause, PDT_MONITOR_CAUSE_TUNING);
    /* the loop's resonance: between 2 and 6 dead times */
    assert_true(r.acf_period > R(4.0) && r.acf_period < R(12.0));
}

static void test_gain_changed(void **state)
{
    (void)state;
    pdt_monitor_config_t c = base_config();
    const loop_case_t lc = {2.5, 10.0, 0.5, 0.0, 100.0, 1.0, 3000u};
    const pdt_monitor_result_t r = run_loop(&lc, &c);
    assert_int_equal(r.verdict, PDT_MONITOR_MODEL_CHANGED);
    assert_close(r.gain_ratio, 0.5, 0.15, 0.0);
}

static void test_timid_is_sluggish(void **state)
{
    (void)state;
    pdt_monitor_config_t c = base_config();
    const loop_case_t lc = {0.5, 20.0, 1.0, 0.0, 100.0, 1.0, 3000u};
    const pdt_monitor_result_t r = run_loop(&lc, &c);
    assert_int_equal(r.verdict, PDT_MONITOR_SLUGGISH);
    assert_true(r.iae_ratio > c.sluggish_ratio);
}

static void test_saturated(void **state)
{
    (void)state;
    pdt_monitor_config_t c = base_config();
    c.u_min = R(0.0);
    c.u_max = R(51.0);
    /* the upper set-point needs u = 53: held at 51 while it lasts (1730 of
     * the 3000 scans) */
    const loop_case_t lc = {2.5, 10.0, 1.0, 0.0, 51.0, 3.0, 3000u};
    const pdt_monitor_result_t r = run_loop(&lc, &c);
    assert_int_equal(r.verdict, PDT_MONITOR_SATURATED);
    assert_true(r.has_saturation && r.saturation > R(0.55) && r.saturation < R(0.6));
}

static void test_not_enough_data(void **state)
{
    (void)state;
    pdt_monitor_config_t c = base_config();
    const loop_case_t lc = {6.0, 10.0, 1.0, 0.0, 100.0, 1.0, 300u};
    const pdt_monitor_result_t r = run_loop(&lc, &c);
    assert_int_equal(r.verdict, PDT_MONITOR_NOT_ENOUGH_DATA);
    assert_int_equal(r.samples, 300u);
}

/* decimation 3 is the same as the averages of three scans, decimation 1;
 * the block call the same as the scans. */
static void test_decimation_is_block_average(void **state)
{
    (void)state;
    pdt_monitor_config_t c3 = base_config(), c1 = base_config();
    c3.Ts = R(0.5) / R(3.0);
    c3.decimation = 3u;
    static pdt_monitor_t m3, m1, mb;
    assert_int_equal(pdt_monitor_init(&m3, &c3), PDT_OK);
    assert_int_equal(pdt_monitor_init(&m1, &c1), PDT_OK);
    assert_int_equal(pdt_monitor_init(&mb, &c3), PDT_OK);
    sim_rng64_t rng = sim_rng64_seed(3u);
    static pdt_real_t sp[1200], pv[1200], u[1200];
    for (size_t k = 0; k < 1200u; k++) {
        sp[k] = R(1.0);
        pv[k] = (pdt_real_t)(1.0 + 0.3 * sin((double)k * 0.2) + 0.05 * sim_rng64_normal(&rng));
        u[k] = (pdt_real_t)(2.0 + 0.1 * sim_rng64_normal(&rng));
        assert_int_equal(pdt_monitor_scan(&m3, sp[k], pv[k], u[k]), PDT_OK);
    }
    for (size_t k = 0; k < 1200u; k += 3u) {
        const pdt_real_t a = (pv[k] + pv[k + 1u] + pv[k + 2u]) / R(3.0);
        const pdt_real_t b = (u[k] + u[k + 1u] + u[k + 2u]) / R(3.0);
        assert_int_equal(pdt_monitor_scan(&m1, R(1.0), a, b), PDT_OK);
    }
    size_t done = 0;
    assert_int_equal(pdt_monitor_scan_block(&mb, sp, pv, u, 1200u, &done), PDT_OK);
    assert_int_equal(done, 1200u);
    pdt_monitor_result_t r3, r1, rb;
    assert_int_equal(pdt_monitor_result(&m3, &r3), PDT_OK);
    assert_int_equal(pdt_monitor_result(&m1, &r1), PDT_OK);
    assert_int_equal(pdt_monitor_result(&mb, &rb), PDT_OK);
    assert_int_equal(r3.samples, 400u);
    assert_close(r3.std_e, r1.std_e, 1e-4, 0.0);
    assert_close(r3.harris, r1.harris, 1e-3, 0.0);
    assert_close(r3.acf_period, r1.acf_period, 1e-3, 0.0);
    assert_memory_equal(&r3, &rb, sizeof r3);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_config_default),
        cmocka_unit_test(test_init_refuses),
        cmocka_unit_test(test_scan_refuses),
        cmocka_unit_test(test_well_tuned_is_ok),
        cmocka_unit_test(test_aggressive_oscillates),
        cmocka_unit_test(test_gain_changed),
        cmocka_unit_test(test_timid_is_sluggish),
        cmocka_unit_test(test_saturated),
        cmocka_unit_test(test_not_enough_data),
        cmocka_unit_test(test_decimation_is_block_average),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
