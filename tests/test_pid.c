/*
 * Tests of pdt_pid: scenarios against the numpy reference (two-degree-of-
 * freedom weights, both forms, filters, every anti-windup mode, rate limit,
 * manual/automatic and gain change), closed loops with exactly sampled
 * FOPDT and SOPDT plants against the reference's discrete loop and against
 * the continuous design (within a tolerance proportional to the scan
 * period), the bumpless transfers, the handover from pdt_tune, the limits,
 * and every bad input with the object and the output left untouched.
 */
#include "test_util.h"
#include "sim_plant.h"

#include <float.h>

#include "pdt/pdt_pid.h"

#include "pid_vectors.h"

#include "target/pid_cases.h"

#define R(x) ((pdt_real_t)(x))

#if PDT_REAL_DOUBLE
#define REAL_BIG (DBL_MAX / 4.0)
#else
#define REAL_BIG (FLT_MAX / 4.0f)
#endif

static pdt_pid_config_t pi_config(void)
{
    pdt_pid_config_t c;
    pdt_pid_config_default(&c);
    c.Kc = R(2.0);
    c.Ti = R(3.0);
    c.Td = R(0.5);
    c.u_min = R(-50.0);
    c.u_max = R(50.0);
    return c;
}

static void test_config_default(void **state)
{
    (void)state;
    pdt_pid_config_default(NULL);
    pdt_pid_config_t c;
    pdt_pid_config_default(&c);
    assert_true(c.Ts == R(0.1) && c.form == PDT_PID_IDEAL && c.Kc == R(1.0) && c.Ti == R(10.0) &&
                c.Td == R(0.0) && c.Tf == R(0.0) && c.N == R(10.0) && c.b == R(1.0) &&
                c.c == R(0.0) && c.u_min == R(0.0) && c.u_max == R(100.0) && c.rate_max == R(0.0) &&
                c.antiwindup == PDT_PID_AW_BACK_CALC && c.Tt == R(0.0));
    pdt_pid_t pid;
    assert_int_equal(pdt_pid_init(&pid, &c, R(0.0)), PDT_OK);
}

/* Every scenario, step by step, against the reference. */
static void test_scenarios(void **state)
{
    (void)state;
    for (size_t s = 0; s < PID_SC_COUNT; s++) {
        double worst;
        size_t bad;
        assert_int_equal(pid_case_run(s, 20.0 * TEST_RTOL, &worst, &bad), PDT_OK);
        if (bad != PID_SC_STEPS) {
            fail_msg("scenario %zu: step %zu off the reference (largest error %.3g)", s, bad,
                     worst);
        }
        print_message("scenario %zu: largest error %.2e of the output range\n", s, worst);
    }
}

/* One closed loop: the plant sampled exactly (the reference's realisation
 * on the shared simulator, in double: the plant is not under test),
 * pdt_pid as the controller; y at the grid points into y. */
static void run_loop(size_t i, double *y)
{
    pdt_pid_config_t c = pid_case_config(&pid_cl_cfg[i * PID_CFG_N]);
    const double *pl = &pid_cl_plant[i * 10u];
    int l = pid_cl_l[2u * i];
    int n = pid_cl_l[2u * i + 1u];
    double r = pid_cl_rd[2u * i];
    double d = pid_cl_rd[2u * i + 1u];
    /* pl: Phi (2 x 2), G0 of w(k - l), G1 of w(k - l - 1), C; one state
     * uses the first of each */
    const double Phi1[1] = {pl[0]};
    static double hist[512];
    sim_plant_t plant;
    assert_int_equal(sim_plant_init_discrete(&plant, (size_t)n, (size_t)l, n == 1 ? Phi1 : pl,
                                             pl + 4, pl + 6, pl + 8, hist, 512u),
                     0);
    pdt_pid_t pid;
    assert_int_equal(pdt_pid_init(&pid, &c, R(0.0)), PDT_OK);
    assert_int_equal(pdt_pid_track(&pid, R(0.0), R(0.0), R(0.0)), PDT_OK);
    size_t scans = (size_t)(PID_CL_T / (double)c.Ts + 0.5) + 1u;
    size_t every = (size_t)(PID_CL_GRID / (double)c.Ts + 0.5);
    for (size_t k = 0; k < scans; k++) {
        double yk = sim_plant_output(&plant);
        if (k % every == 0u) {
            y[k / every] = yk;
        }
        pdt_real_t u;
        assert_int_equal(pdt_pid_update(&pid, R(r), (pdt_real_t)yk, &u), PDT_OK);
        sim_plant_apply(&plant, (double)u + d);
    }
}

static void test_closed_loop(void **state)
{
    (void)state;
    for (size_t i = 0; i < PID_CL_COUNT; i++) {
        double y[PID_CL_POINTS];
        run_loop(i, y);
        const double *yd = &pid_cl_yd[i * PID_CL_POINTS];
        const double *yc = &pid_cl_yc[i * PID_CL_POINTS];
        const double *yh = &pid_cl_yh[i * PID_CL_POINTS];
        double e_ref = 0.0;
        double e_cont = 0.0;
        double e_half = 0.0;
        for (size_t k = 0; k < PID_CL_POINTS; k++) {
            e_ref = fmax(e_ref, fabs(y[k] - yd[k]));
            e_cont = fmax(e_cont, fabs(y[k] - yc[k]));
            e_half = fmax(e_half, fabs(y[k] - yh[k]));
        }
        double Ts = pid_cl_cfg[i * PID_CFG_N];
        print_message("loop %zu (%s, %s step, Ts %.2f s): max |y - discrete ref| %.1e, "
                      "max |y - continuous| %.5f, with Td + Ts/2 %.5f\n",
                      i, pid_cl_l[2u * i + 1u] == 1 ? "FOPDT" : "SOPDT",
                      pid_cl_rd[2u * i] != 0.0 ? "set-point" : "load", Ts, e_ref, e_cont, e_half);
        /* The discrete reference: the same loop, computed in double. */
        assert_true(e_ref <= 50.0 * TEST_RTOL);
        /* The continuous design: the error is first order in Ts (measured
         * 0.09 Ts to 0.27 Ts on these unit steps, docs/pid.md). */
        assert_true(e_cont <= 0.3 * Ts + 5e-4);
    }
}

static void test_bumpless_start_and_manual(void **state)
{
    (void)state;
    pdt_pid_config_t c = pi_config();
    pdt_pid_t pid;
    assert_int_equal(pdt_pid_init(&pid, &c, R(12.5)), PDT_OK);
    pdt_real_t u;
    /* The first scan returns the start output exactly, whatever the error. */
    assert_int_equal(pdt_pid_update(&pid, R(5.0), R(1.0), &u), PDT_OK);
    assert_true(u == R(12.5));
    /* From there on it moves only by the integral increment. */
    assert_int_equal(pdt_pid_update(&pid, R(5.0), R(1.0), &u), PDT_OK);
    assert_close(u, 12.5 + 2.0 * 0.1 / 3.0 * 4.0, 1e-5, 1e-5);
    /* Manual: the operator's output ramps, the controller follows it. */
    for (int k = 0; k < 30; k++) {
        assert_int_equal(pdt_pid_track(&pid, R(5.0), R(1.0 + 0.05 * k), R(20.0 + k)), PDT_OK);
    }
    /* Back to automatic: no bump beyond one scan's increments. */
    assert_int_equal(pdt_pid_update(&pid, R(5.0), R(1.0 + 0.05 * 30), &u), PDT_OK);
    assert_close(u, 49.0, 0.0, 0.5);
    /* A start outside the limits is clamped. */
    assert_int_equal(pdt_pid_init(&pid, &c, R(80.0)), PDT_OK);
    assert_int_equal(pdt_pid_update(&pid, R(0.0), R(0.0), &u), PDT_OK);
    assert_true(u == R(50.0));
}

static void test_bumpless_gain_change(void **state)
{
    (void)state;
    pdt_pid_config_t c = pi_config();
    pdt_pid_t a, b;
    assert_int_equal(pdt_pid_init(&a, &c, R(10.0)), PDT_OK);
    pdt_real_t u = R(0.0);
    for (int k = 0; k < 40; k++) {
        assert_int_equal(pdt_pid_update(&a, R(3.0), R(2.0 + 0.01 * k), &u), PDT_OK);
    }
    memcpy(&b, &a, sizeof a);
    pdt_tune_gains_t g;
    g.Kc = R(5.0);
    g.tauI = R(1.0);
    g.tauD = R(2.0);
    g.Tf = R(0.2);
    assert_int_equal(pdt_pid_set_gains(&b, &g, PDT_PID_SERIES), PDT_OK);
    /* Same output now; the next scan differs from the unchanged controller
     * only by the new gains acting on the change since the last scan. */
    assert_true(b.u == a.u);
    pdt_real_t ua, ub;
    assert_int_equal(pdt_pid_update(&a, R(3.0), R(2.40), &ua), PDT_OK);
    assert_int_equal(pdt_pid_update(&b, R(3.0), R(2.40), &ub), PDT_OK);
    assert_close(ub, u, 0.0, 0.5);
    assert_close(ua, u, 0.0, 0.1);
    /* Before the first scan a change replaces the configuration and clamps. */
    pdt_pid_t fresh;
    assert_int_equal(pdt_pid_init(&fresh, &c, R(40.0)), PDT_OK);
    c.u_max = R(30.0);
    assert_int_equal(pdt_pid_set_config(&fresh, &c), PDT_OK);
    assert_int_equal(pdt_pid_update(&fresh, R(1.0), R(0.0), &u), PDT_OK);
    assert_true(u == R(30.0));
}

/* The autotune's handover: the tune result's ideal gains, and its series
 * gains, give the same controller. */
static void test_from_tune(void **state)
{
    (void)state;
    pdt_model_t m;
    m.kind = PDT_MODEL_SOPDT;
    pdt_model_tc_t tcm;
    memset(&tcm, 0, sizeof tcm);
    tcm.K = R(1.0);
    tcm.T1 = R(2.0);
    tcm.T2 = R(1.2);
    tcm.Td = R(0.77);
    assert_int_equal(pdt_model_sopdt_from_tc(&tcm, &m.p.sopdt), PDT_OK);
    pdt_tune_config_t tc;
    pdt_tune_config_default(&tc);
    tc.form = PDT_TUNE_PID;
    pdt_tune_result_t r;
    assert_int_equal(pdt_tune_compute(&m, R(100.0), &tc, &r), PDT_OK);
    pdt_pid_config_t base;
    pdt_pid_config_default(&base);
    base.u_min = R(-100.0);
    pdt_pid_t pi, ps;
    assert_int_equal(pdt_pid_init_from_gains(&pi, &base, &r.ideal, PDT_PID_IDEAL, R(7.0)), PDT_OK);
    assert_int_equal(pdt_pid_init_from_gains(&ps, &base, &r.series, PDT_PID_SERIES, R(7.0)),
                     PDT_OK);
    assert_true(pi.cfg.N == R(0.0) && pi.cfg.Tf == r.ideal.Tf);
    for (int k = 0; k < 50; k++) {
        pdt_real_t ui, us;
        pdt_real_t pv = R(0.3 * sin(0.3 * k));
        assert_int_equal(pdt_pid_update(&pi, R(1.0), pv, &ui), PDT_OK);
        assert_int_equal(pdt_pid_update(&ps, R(1.0), pv, &us), PDT_OK);
        assert_close(us, ui, 50.0 * TEST_RTOL, 50.0 * TEST_RTOL);
        if (k == 0) {
            assert_true(ui == R(7.0));
        }
    }
    /* Gains outside their domain are refused. */
    pdt_tune_gains_t bad = r.ideal;
    bad.tauI = R(0.0);
    assert_int_equal(pdt_pid_init_from_gains(&pi, &base, &bad, PDT_PID_IDEAL, R(0.0)), PDT_ERR_ARG);
    assert_int_equal(pdt_pid_init_from_gains(&pi, &base, &r.ideal, (pdt_pid_form_t)7, R(0.0)),
                     PDT_ERR_ARG);
    assert_int_equal(pdt_pid_init_from_gains(&pi, NULL, &r.ideal, PDT_PID_IDEAL, R(0.0)),
                     PDT_ERR_ARG);
    assert_int_equal(pdt_pid_init_from_gains(&pi, &base, NULL, PDT_PID_IDEAL, R(0.0)), PDT_ERR_ARG);
}

/* Limits and the rate limit hold on every scan; the limited flag says so. */
static void test_limits(void **state)
{
    (void)state;
    pdt_pid_config_t c = pi_config();
    c.u_min = R(-3.0);
    c.u_max = R(4.0);
    c.rate_max = R(10.0);
    pdt_pid_t pid;
    assert_int_equal(pdt_pid_init(&pid, &c, R(0.0)), PDT_OK);
    pdt_real_t prev = R(0.0);
    bool saw_limit = false;
    for (int k = 0; k < 400; k++) {
        pdt_real_t sp = R((k / 50) % 2 == 0 ? 10.0 : -10.0);
        pdt_real_t u;
        assert_int_equal(pdt_pid_update(&pid, sp, R(0.0), &u), PDT_OK);
        assert_true(u >= c.u_min && u <= c.u_max);
        assert_true(fabs((double)(u - prev)) <= 1.0 + 1e-5);
        saw_limit = saw_limit || pid.limited;
        prev = u;
    }
    assert_true(saw_limit);
}

/* Saturation with the proportional term inside the limits and the integral
 * pushing beyond them, then a small error of the other sign: back-
 * calculation and conditional integration hold the integral where the
 * output leaves the limit at once; without anti-windup it stays there for
 * thousands of scans. */
static void test_antiwindup_recovery(void **state)
{
    (void)state;
    const pdt_pid_antiwindup_t modes[] = {PDT_PID_AW_BACK_CALC, PDT_PID_AW_CONDITIONAL,
                                          PDT_PID_AW_BOTH, PDT_PID_AW_NONE};
    int leave[4];
    for (int m = 0; m < 4; m++) {
        pdt_pid_config_t c = pi_config();
        c.Td = R(0.0);
        c.u_min = R(0.0);
        c.u_max = R(10.0);
        c.antiwindup = modes[m];
        pdt_pid_t pid;
        assert_int_equal(pdt_pid_init(&pid, &c, R(0.0)), PDT_OK);
        pdt_real_t u;
        for (int k = 0; k < 200; k++) { /* P = 8, the integral grows */
            assert_int_equal(pdt_pid_update(&pid, R(4.0), R(0.0), &u), PDT_OK);
        }
        assert_close(u, 10.0, 0.0, 1e-4);
        assert_true(pid.limited);
        if (modes[m] == PDT_PID_AW_CONDITIONAL || modes[m] == PDT_PID_AW_BOTH) {
            /* The integral stops where the output reaches the limit, give or
             * take one increment. */
            assert_close(pid.i, 2.0, 0.0, 0.3);
        } else if (modes[m] == PDT_PID_AW_BACK_CALC) {
            /* Back-calculation settles where the tracking balances the
             * integration: i = u - P + Kc e Tt / Ti (Tt = Ti here), to within
             * the discretisation. */
            assert_close(pid.i, 2.0 + 2.0 * 4.0, 0.02, 0.0);
        }
        leave[m] = -1;
        for (int k = 0; k < 2000 && leave[m] < 0; k++) { /* e = -0.1 */
            assert_int_equal(pdt_pid_update(&pid, R(4.0), R(4.1), &u), PDT_OK);
            if (u < R(10.0)) {
                leave[m] = k;
            }
        }
    }
    print_message("scans to leave the upper limit: back-calc %d, conditional %d, both %d, "
                  "none %d (-1: not within 2000)\n",
                  leave[0], leave[1], leave[2], leave[3]);
    assert_true(leave[0] == 0 && leave[1] == 0 && leave[2] == 0);
    assert_true(leave[3] < 0);
}

static void test_bad_inputs(void **state)
{
    (void)state;
    pdt_pid_config_t good = pi_config();
    pdt_pid_t pid;
    pdt_real_t inf = R(1.0) / R(0.0);
    pdt_real_t nan = inf - inf;
    assert_int_equal(pdt_pid_init(NULL, &good, R(0.0)), PDT_ERR_ARG);
    assert_int_equal(pdt_pid_init(&pid, NULL, R(0.0)), PDT_ERR_ARG);
    assert_int_equal(pdt_pid_init(&pid, &good, nan), PDT_ERR_ARG);
    /* Each invalid field, alone: refused, and the object untouched. */
    for (int f = 0; f < 24; f++) {
        pdt_pid_config_t c = good;
        switch (f) {
        case 0:
            c.Ts = R(0.0);
            break;
        case 1:
            c.Ts = nan;
            break;
        case 2:
            c.form = (pdt_pid_form_t)2;
            break;
        case 3:
            c.Kc = R(0.0);
            break;
        case 4:
            c.Kc = inf;
            break;
        case 5:
            c.Ti = R(-1.0);
            break;
        case 6:
            c.Td = R(-0.1);
            break;
        case 7:
            c.Tf = R(-0.1);
            break;
        case 8:
            c.N = R(0.5);
            break;
        case 9:
            c.N = R(-1.0);
            break;
        case 10:
            c.b = R(-0.1);
            break;
        case 11:
            c.c = nan;
            break;
        case 12:
            c.u_min = c.u_max;
            break;
        case 13:
            c.u_max = inf;
            break;
        case 14:
            c.rate_max = R(-1.0);
            break;
        case 15:
            c.antiwindup = (pdt_pid_antiwindup_t)4;
            break;
        case 16:
            c.Tt = R(-1.0);
            break;
        case 17:
            c.Ti = nan;
            break;
        case 18:
            c.u_min = nan;
            break;
        case 19:
            c.rate_max = inf;
            break;
        case 20:
            c.Tt = inf;
            break;
        case 21:
            c.Td = inf;
            break;
        case 22:
            c.b = inf;
            break;
        default:
            c.Kc = REAL_BIG;
            c.Ts = R(1e3);
            c.Ti = R(1e-3);
            break; /* ki overflows */
        }
        memset(&pid, 0x5a, sizeof pid);
        pdt_pid_t copy;
        memcpy(&copy, &pid, sizeof pid);
        if (pdt_pid_init(&pid, &c, R(0.0)) != PDT_ERR_ARG) {
            fail_msg("invalid field %d accepted", f);
        }
        assert_memory_equal(&pid, &copy, sizeof pid);
    }
    /* Calls on an object never initialised. */
    memset(&pid, 0, sizeof pid);
    pdt_real_t u = R(42.0);
    assert_int_equal(pdt_pid_update(&pid, R(0.0), R(0.0), &u), PDT_ERR_STATE);
    assert_int_equal(pdt_pid_track(&pid, R(0.0), R(0.0), R(0.0)), PDT_ERR_STATE);
    assert_int_equal(pdt_pid_set_config(&pid, &good), PDT_ERR_STATE);
    pdt_tune_gains_t g = {R(1.0), R(1.0), R(0.0), R(0.0)};
    assert_int_equal(pdt_pid_set_gains(&pid, &g, PDT_PID_IDEAL), PDT_ERR_STATE);
    assert_true(u == R(42.0));
    /* NULLs. */
    assert_int_equal(pdt_pid_init(&pid, &good, R(1.0)), PDT_OK);
    assert_int_equal(pdt_pid_update(NULL, R(0.0), R(0.0), &u), PDT_ERR_ARG);
    assert_int_equal(pdt_pid_update(&pid, R(0.0), R(0.0), NULL), PDT_ERR_ARG);
    assert_int_equal(pdt_pid_track(NULL, R(0.0), R(0.0), R(0.0)), PDT_ERR_ARG);
    assert_int_equal(pdt_pid_set_config(NULL, &good), PDT_ERR_ARG);
    assert_int_equal(pdt_pid_set_config(&pid, NULL), PDT_ERR_ARG);
    assert_int_equal(pdt_pid_set_gains(NULL, &g, PDT_PID_IDEAL), PDT_ERR_ARG);
    assert_int_equal(pdt_pid_set_gains(&pid, NULL, PDT_PID_IDEAL), PDT_ERR_ARG);
    /* A failed sensor: NaN or infinite sp / pv / tracked output are refused,
     * the output is held and the state unchanged. */
    for (int k = 0; k < 5; k++) {
        assert_int_equal(pdt_pid_update(&pid, R(2.0), R(1.0 + 0.1 * k), &u), PDT_OK);
    }
    pdt_real_t held = u;
    pdt_pid_t copy;
    memcpy(&copy, &pid, sizeof pid);
    const pdt_real_t bad[] = {nan, inf, -inf};
    for (size_t i = 0; i < 3; i++) {
        assert_int_equal(pdt_pid_update(&pid, bad[i], R(1.0), &u), PDT_ERR_NONFINITE);
        assert_int_equal(pdt_pid_update(&pid, R(2.0), bad[i], &u), PDT_ERR_NONFINITE);
        assert_int_equal(pdt_pid_track(&pid, bad[i], R(1.0), R(1.0)), PDT_ERR_NONFINITE);
        assert_int_equal(pdt_pid_track(&pid, R(2.0), bad[i], R(1.0)), PDT_ERR_NONFINITE);
        assert_int_equal(pdt_pid_track(&pid, R(2.0), R(1.0), bad[i]), PDT_ERR_NONFINITE);
        assert_true(u == held);
        assert_memory_equal(&pid, &copy, sizeof pid);
    }
    /* An output that would overflow is refused the same way. */
    assert_int_equal(pdt_pid_update(&pid, REAL_BIG, -REAL_BIG, &u), PDT_ERR_NONFINITE);
    assert_true(u == held);
    assert_memory_equal(&pid, &copy, sizeof pid);
    /* An invalid change leaves the controller in service as it was. */
    pdt_pid_config_t c = good;
    c.Ts = R(-1.0);
    assert_int_equal(pdt_pid_set_config(&pid, &c), PDT_ERR_ARG);
    g.Kc = R(0.0);
    assert_int_equal(pdt_pid_set_gains(&pid, &g, PDT_PID_IDEAL), PDT_ERR_ARG);
    assert_memory_equal(&pid, &copy, sizeof pid);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_config_default),
        cmocka_unit_test(test_scenarios),
        cmocka_unit_test(test_closed_loop),
        cmocka_unit_test(test_bumpless_start_and_manual),
        cmocka_unit_test(test_bumpless_gain_change),
        cmocka_unit_test(test_from_tune),
        cmocka_unit_test(test_limits),
        cmocka_unit_test(test_antiwindup_recovery),
        cmocka_unit_test(test_bad_inputs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
