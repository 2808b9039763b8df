/*
 * Tests of lib/src/pdt_record.c: decimation, settle window and every abort
 * against the numpy reference (excite_record_vectors.h) with canaries after
 * the caller arrays; non-finite scans, stop, bad inputs; and a whole step
 * experiment: generator, recorder and a simulated FOPDT together.
 */
#include "test_util.h"
#include "sim_plant.h"

#include "pdt/pdt_discrete.h"
#include "pdt/pdt_excite.h"
#include "pdt/pdt_record.h"

#include "excite_record_vectors.h"

#define R(x)    ((pdt_real_t)(x))
#define CAP_MAX 128

static pdt_real_t lim(double x)
{
    if (x >= 1e30) {
        return R(3.4e38);
    }
    if (x <= -1e30) {
        return R(-3.4e38);
    }
    return (pdt_real_t)x;
}

static pdt_record_config_t case_config(int i, size_t *capacity)
{
    const double *p = &rec_par[REC_NPAR * i];
    pdt_record_config_t c;
    pdt_record_config_default(&c);
    c.decimation = (uint32_t)p[REC_P_DECIMATION];
    c.settle = (uint32_t)p[REC_P_SETTLE];
    c.settle_band = R(p[REC_P_SETTLE_BAND]);
    c.u_min = lim(p[REC_P_U_MIN]);
    c.u_max = lim(p[REC_P_U_MAX]);
    c.pv_min = lim(p[REC_P_PV_MIN]);
    c.pv_max = lim(p[REC_P_PV_MAX]);
    c.max_scans = (uint32_t)p[REC_P_MAX_SCANS];
    c.move = (pdt_record_move_t)(int)p[REC_P_MOVE];
    c.setpoint = R(p[REC_P_SETPOINT]);
    *capacity = (size_t)p[REC_P_CAPACITY];
    return c;
}

static void test_defaults(void **state)
{
    (void)state;
    pdt_record_config_t c;
    pdt_record_config_default(NULL);
    pdt_record_config_default(&c);
    assert_int_equal(c.decimation, 1);
    assert_int_equal(c.settle, 10);
    assert_int_equal(c.max_scans, 0);
    assert_int_equal(c.move, PDT_RECORD_MOVE_ANY);
    assert_true(c.settle_band == R(0.0));
    pdt_record_t rec;
    pdt_real_t u[11], y[11];
    assert_int_equal(pdt_record_init(&rec, &c, u, y, 11), PDT_OK);
}

static void test_vectors(void **state)
{
    (void)state;
    double worst = 0.0;
    for (int i = 0; i < REC_CASES; i++) {
        size_t cap;
        pdt_record_config_t c = case_config(i, &cap);
        pdt_real_t u[CAP_MAX + CANARY_COUNT];
        pdt_real_t y[CAP_MAX + CANARY_COUNT];
        pdt_record_t rec;
        pdt_record_result_t res;
        assert_true(cap <= CAP_MAX);
        canary_fill(u, CAP_MAX + CANARY_COUNT);
        canary_fill(y, CAP_MAX + CANARY_COUNT);
        assert_int_equal(pdt_record_init(&rec, &c, u, y, cap), PDT_OK);
        canary_check(u, CAP_MAX + CANARY_COUNT); /* init writes nothing */
        const double *out = &rec_out[REC_NOUT * i];
        int last = (int)out[REC_O_LAST];
        pdt_status_t final = (pdt_status_t)(int)out[REC_O_STATUS];
        for (int k = 0; k < rec_slen[i]; k++) {
            pdt_status_t st = pdt_record_push(&rec, (pdt_real_t)rec_su[rec_soff[i] + k],
                                              (pdt_real_t)rec_spv[rec_soff[i] + k]);
            if (last < 0 || k < last) {
                assert_int_equal(st, PDT_RUNNING);
            } else {
                assert_int_equal(st, final); /* also on every later push */
            }
        }
        assert_int_equal(pdt_record_result(&rec, &res), PDT_OK);
        assert_int_equal(res.status, final);
        assert_int_equal(res.n, (size_t)out[REC_O_N]);
        assert_int_equal(res.settled, out[REC_O_SETTLED] != 0.0);
        assert_int_equal(res.scans, (uint32_t)out[REC_O_SCANS]);
        assert_close(res.u0, out[REC_O_U0], TEST_RTOL, 0.0);
        assert_close(res.y0, out[REC_O_Y0], TEST_RTOL, 0.0);
        assert_close(res.u_safe, out[REC_O_U_SAFE], TEST_RTOL, 0.0);
        for (size_t j = 0; j < res.n; j++) {
            double wy = rec_y[rec_off[i] + (int)j];
            assert_true(u[j] == (pdt_real_t)rec_u[rec_off[i] + (int)j]); /* held value, exact */
            double e = fabs((double)y[j] - wy) / fabs(wy);
            worst = e > worst ? e : worst;
            assert_close(y[j], wy, TEST_RTOL, 0.0);
        }
        canary_check(u + cap, CANARY_COUNT);
        canary_check(y + cap, CANARY_COUNT);
        /* the slots after n are untouched too (dropped partial intervals) */
        canary_check(u + res.n, cap - res.n);
        canary_check(y + res.n, cap - res.n);
    }
    print_message("worst relative error of the decimated pv: %.3g\n", worst);
}

static pdt_record_config_t small(void)
{
    pdt_record_config_t c;
    pdt_record_config_default(&c);
    c.decimation = 2;
    c.settle = 2;
    c.u_min = R(0.0);
    c.u_max = R(100.0);
    c.pv_min = R(-5.0);
    c.pv_max = R(5.0);
    return c;
}

static void test_nonfinite_abort(void **state)
{
    (void)state;
    const pdt_real_t bad[3] = {R(NAN), R(INFINITY), R(-INFINITY)};
    for (int which = 0; which < 2; which++) {
        for (int b = 0; b < 3; b++) {
            pdt_record_config_t c = small();
            pdt_real_t u[8 + CANARY_COUNT], y[8 + CANARY_COUNT];
            pdt_record_t rec;
            pdt_record_result_t res;
            canary_fill(u, 8 + CANARY_COUNT);
            canary_fill(y, 8 + CANARY_COUNT);
            assert_int_equal(pdt_record_init(&rec, &c, u, y, 8), PDT_OK);
            for (int k = 0; k < 5; k++) {
                assert_int_equal(pdt_record_push(&rec, R(20.0), R(1.0)), PDT_RUNNING);
            }
            pdt_status_t st = which == 0 ? pdt_record_push(&rec, bad[b], R(1.0))
                                         : pdt_record_push(&rec, R(20.0), bad[b]);
            assert_int_equal(st, PDT_ERR_NONFINITE);
            assert_int_equal(pdt_record_push(&rec, R(20.0), R(1.0)), PDT_ERR_NONFINITE);
            assert_int_equal(pdt_record_stop(&rec), PDT_ERR_NONFINITE);
            assert_int_equal(pdt_record_result(&rec, &res), PDT_OK);
            assert_int_equal(res.status, PDT_ERR_NONFINITE);
            assert_int_equal(res.n, 2); /* the partial third interval is dropped */
            assert_true(res.settled);
            assert_true(res.u_safe == R(20.0));
            assert_int_equal(res.scans, 5);
            canary_check(u + 2, 6 + CANARY_COUNT);
        }
    }
    /* a NaN output on the very first scan: u_safe is u_min */
    pdt_record_config_t c = small();
    pdt_real_t u[8], y[8];
    pdt_record_t rec;
    pdt_record_result_t res;
    assert_int_equal(pdt_record_init(&rec, &c, u, y, 8), PDT_OK);
    assert_int_equal(pdt_record_push(&rec, R(NAN), R(1.0)), PDT_ERR_NONFINITE);
    assert_int_equal(pdt_record_result(&rec, &res), PDT_OK);
    assert_true(res.u_safe == R(0.0));
    assert_false(res.settled);
    /* a pv limit broken on the first scan keeps the output pushed */
    assert_int_equal(pdt_record_init(&rec, &c, u, y, 8), PDT_OK);
    assert_int_equal(pdt_record_push(&rec, R(42.0), R(6.0)), PDT_ERR_PV_LIMIT);
    assert_int_equal(pdt_record_result(&rec, &res), PDT_OK);
    assert_true(res.u_safe == R(42.0));
    /* an output below u_min on the first scan: u_safe is u_min */
    assert_int_equal(pdt_record_init(&rec, &c, u, y, 8), PDT_OK);
    assert_int_equal(pdt_record_push(&rec, R(-3.0), R(0.0)), PDT_ERR_OUTPUT_LIMIT);
    assert_int_equal(pdt_record_result(&rec, &res), PDT_OK);
    assert_true(res.u_safe == R(0.0));
}

static void test_stop(void **state)
{
    (void)state;
    pdt_record_config_t c = small();
    pdt_real_t u[8 + CANARY_COUNT], y[8 + CANARY_COUNT];
    pdt_record_t rec;
    pdt_record_result_t res;
    canary_fill(u, 8 + CANARY_COUNT);
    canary_fill(y, 8 + CANARY_COUNT);
    assert_int_equal(pdt_record_init(&rec, &c, u, y, 8), PDT_OK);
    assert_int_equal(pdt_record_push(&rec, R(10.0), R(1.0)), PDT_RUNNING);
    assert_int_equal(pdt_record_push(&rec, R(10.0), R(2.0)), PDT_RUNNING);
    assert_int_equal(pdt_record_stop(&rec), PDT_ERR_STATE); /* not settled */
    assert_int_equal(pdt_record_push(&rec, R(11.0), R(3.0)), PDT_RUNNING);
    assert_int_equal(pdt_record_push(&rec, R(12.0), R(4.0)), PDT_RUNNING);
    assert_int_equal(pdt_record_push(&rec, R(30.0), R(4.0)), PDT_RUNNING);
    assert_int_equal(pdt_record_stop(&rec), PDT_OK);
    assert_int_equal(pdt_record_stop(&rec), PDT_OK);
    assert_int_equal(pdt_record_push(&rec, R(30.0), R(4.0)), PDT_OK);
    assert_int_equal(pdt_record_result(&rec, &res), PDT_OK);
    assert_int_equal(res.status, PDT_OK);
    assert_int_equal(res.n, 2);
    /* Both signals are interval means: u 10, 10 -> 10 and 11, 12 -> 11.5. */
    assert_true(res.u0 == R(10.75) && res.u_safe == R(10.75));
    assert_true(res.y0 == R(2.5));
    assert_true(u[0] == R(10.0) && u[1] == R(11.5) && y[0] == R(1.5) && y[1] == R(3.5));
    canary_check(u + 2, 6 + CANARY_COUNT);
    canary_check(y + 2, 6 + CANARY_COUNT);
}

static void expect_init(const pdt_record_config_t *c, pdt_real_t *u, pdt_real_t *y, size_t cap,
                        pdt_status_t want)
{
    pdt_record_t rec;
    pdt_record_t copy;
    memset(&rec, 0xA5, sizeof rec);
    memcpy(&copy, &rec, sizeof rec);
    assert_int_equal(pdt_record_init(&rec, c, u, y, cap), want);
    if (want != PDT_OK) {
        assert_memory_equal(&rec, &copy, sizeof rec);
    }
}

static void test_bad_inputs(void **state)
{
    (void)state;
    pdt_real_t u[16 + CANARY_COUNT], y[16 + CANARY_COUNT];
    canary_fill(u, 16 + CANARY_COUNT);
    canary_fill(y, 16 + CANARY_COUNT);
    pdt_record_t rec;
    pdt_record_config_t c = small();
    assert_int_equal(pdt_record_init(NULL, &c, u, y, 16), PDT_ERR_ARG);
    expect_init(NULL, u, y, 16, PDT_ERR_ARG);
    expect_init(&c, NULL, y, 16, PDT_ERR_ARG);
    expect_init(&c, u, NULL, 16, PDT_ERR_ARG);
    expect_init(&c, u, u, 16, PDT_ERR_ARG);
    expect_init(&c, u, u + 15, 16, PDT_ERR_ARG); /* overlap by one */
    c.decimation = 0;
    expect_init(&c, u, y, 16, PDT_ERR_ARG);
    c = small();
    c.settle = 0;
    expect_init(&c, u, y, 16, PDT_ERR_ARG);
    c = small();
    c.u_max = R(INFINITY);
    expect_init(&c, u, y, 16, PDT_ERR_ARG);
    c = small();
    c.pv_min = R(NAN);
    expect_init(&c, u, y, 16, PDT_ERR_ARG);
    c = small();
    c.settle_band = R(-1.0);
    expect_init(&c, u, y, 16, PDT_ERR_ARG);
    c.settle_band = R(NAN);
    expect_init(&c, u, y, 16, PDT_ERR_ARG);
    c = small();
    c.move = (pdt_record_move_t)3;
    expect_init(&c, u, y, 16, PDT_ERR_ARG);
    c = small();
    c.move = PDT_RECORD_MOVE_UP;
    c.setpoint = R(NAN);
    expect_init(&c, u, y, 16, PDT_ERR_ARG);
    c.move = PDT_RECORD_MOVE_ANY; /* the set-point is not used then */
    expect_init(&c, u, y, 16, PDT_OK);
    c = small();
    c.u_min = R(200.0);
    expect_init(&c, u, y, 16, PDT_ERR_BOUNDS);
    c = small();
    c.pv_min = R(6.0);
    expect_init(&c, u, y, 16, PDT_ERR_BOUNDS);
    c = small();
    c.settle = 16;
    expect_init(&c, u, y, 16, PDT_ERR_TOO_SHORT);
    expect_init(&c, u, y, 17, PDT_OK);
    canary_check(u, 16 + CANARY_COUNT);
    canary_check(y, 16 + CANARY_COUNT);

    pdt_record_result_t res;
    memset(&rec, 0, sizeof rec);
    assert_int_equal(pdt_record_push(NULL, R(0.0), R(0.0)), PDT_ERR_ARG);
    assert_int_equal(pdt_record_push(&rec, R(0.0), R(0.0)), PDT_ERR_STATE);
    assert_int_equal(pdt_record_stop(NULL), PDT_ERR_ARG);
    assert_int_equal(pdt_record_stop(&rec), PDT_ERR_STATE);
    memset(&res, 0x5A, sizeof res);
    pdt_record_result_t rcopy = res;
    assert_int_equal(pdt_record_result(&rec, &res), PDT_ERR_STATE);
    assert_memory_equal(&res, &rcopy, sizeof res);
    c = small();
    assert_int_equal(pdt_record_init(&rec, &c, u, y, 16), PDT_OK);
    assert_int_equal(pdt_record_result(NULL, &res), PDT_ERR_ARG);
    assert_int_equal(pdt_record_result(&rec, NULL), PDT_ERR_ARG);
}

/* A whole experiment: the step generator at the scan rate, a FOPDT plant
 * (the shared simulator) between them, the recorder decimating by 5. Then a rerun
 * whose pv limit the step breaks: the abort comes at the scan where pv
 * passes the limit, with the operating point as the output to apply. */
static void step_experiment(pdt_real_t pv_max, pdt_record_result_t *res, pdt_real_t *u,
                            pdt_real_t *y, size_t cap, int *abort_scan)
{
    const pdt_real_t Ts = R(0.02);
    static double hist[64];
    const double lag[1] = {1.5};
    const sim_plant_desc_t desc = sim_plant_desc_lags(2.0, lag, 1u, 0.4);
    sim_plant_t plant;
    pdt_excite_config_t ec;
    pdt_excite_t g;
    pdt_excite_config_default(&ec, PDT_EXCITE_STEP);
    ec.Ts = Ts;
    ec.u0 = R(30.0);
    ec.amplitude = R(5.0);
    ec.u_min = R(0.0);
    ec.u_max = R(100.0);
    ec.pre = R(1.0); /* 50 scans = 10 samples: the settle window */
    pdt_record_config_t rc;
    pdt_record_config_default(&rc);
    rc.decimation = 5;
    rc.settle = 10;
    rc.settle_band = R(0.5);
    rc.u_min = R(0.0);
    rc.u_max = R(100.0);
    rc.pv_min = R(0.0);
    rc.pv_max = pv_max;
    rc.move = PDT_RECORD_MOVE_UP;
    rc.setpoint = R(65.0);
    pdt_record_t rec;
    assert_int_equal(pdt_excite_init(&g, &ec), PDT_OK);
    assert_int_equal(pdt_record_init(&rec, &rc, u, y, cap), PDT_OK);
    /* the plant at rest: y0 = 60 at u0 */
    assert_int_equal(sim_plant_init(&plant, &desc, (double)Ts, (double)ec.u0, 60.0, hist, 64u), 0);
    enum { NS = 2000 };
    pdt_status_t st = PDT_RUNNING;
    *abort_scan = -1;
    for (int k = 0; k < NS && st == PDT_RUNNING; k++) {
        const pdt_real_t yk = (pdt_real_t)sim_plant_output(&plant);
        pdt_real_t uk;
        (void)pdt_excite_next(&g, yk, &uk);
        st = pdt_record_push(&rec, uk, yk);
        if (st < 0) {
            *abort_scan = k;
        }
        sim_plant_apply(&plant, (double)uk);
    }
    assert_int_equal(pdt_record_result(&rec, res), PDT_OK);
}

static void test_step_experiment(void **state)
{
    (void)state;
    enum { CAP = 120 };
    pdt_real_t u[CAP + CANARY_COUNT], y[CAP + CANARY_COUNT];
    pdt_record_result_t res;
    int abort_scan;
    canary_fill(u, CAP + CANARY_COUNT);
    canary_fill(y, CAP + CANARY_COUNT);
    step_experiment(R(100.0), &res, u, y, CAP, &abort_scan);
    assert_int_equal(res.status, PDT_OK);
    assert_int_equal(res.n, CAP);
    assert_int_equal(res.scans, 5 * CAP);
    assert_true(res.settled);
    assert_close(res.u0, 30.0, 1e-6, 0.0);
    assert_close(res.y0, 60.0, 1e-6, 0.0);
    canary_check(u + CAP, CANARY_COUNT);
    canary_check(y + CAP, CANARY_COUNT);
    /* samples 0..9 at rest, then the step; at the end close to 60 + 2 * 5 */
    for (int j = 0; j < 10; j++) {
        assert_true(u[j] == R(30.0));
        assert_close(y[j], 60.0, 1e-6, 0.0);
    }
    assert_true(u[10] == R(35.0) && u[CAP - 1] == R(35.0));
    assert_close(y[CAP - 1], 70.0, 0.0, 0.05);
    /* sample j averages scans 5j .. 5j+4: the step (scan 50) shows after the
     * dead time of 20 scans, first in sample 14 (scans 70 .. 74), whose
     * mean sees the response of scans 71 .. 74 */
    assert_close(y[13], 60.0, 1e-6, 0.0);
    assert_true(y[14] > R(60.0));

    /* the same with pv_max = 65: aborts once pv passes 65 */
    canary_fill(u, CAP + CANARY_COUNT);
    canary_fill(y, CAP + CANARY_COUNT);
    step_experiment(R(65.0), &res, u, y, CAP, &abort_scan);
    assert_int_equal(res.status, PDT_ERR_PV_LIMIT);
    assert_true(abort_scan > 70);
    assert_int_equal(res.scans, (uint32_t)abort_scan);
    assert_int_equal(res.n, (size_t)(abort_scan / 5));
    assert_close(res.u_safe, 30.0, 1e-6, 0.0);
    assert_true(y[res.n - 1] <= R(65.0));
    canary_check(u + res.n, CAP - res.n + CANARY_COUNT);
    canary_check(y + res.n, CAP - res.n + CANARY_COUNT);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults),        cmocka_unit_test(test_vectors),
        cmocka_unit_test(test_nonfinite_abort), cmocka_unit_test(test_stop),
        cmocka_unit_test(test_bad_inputs),      cmocka_unit_test(test_step_experiment),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
