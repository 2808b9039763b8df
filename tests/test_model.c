/*
 * Tests of lib/src/pdt_model.c: checks, conversions, step and frequency
 * responses against the numpy reference (model_vectors.h), and bad inputs.
 */
#include "test_util.h"

#include "model_vectors.h"

#define R(x) ((pdt_real_t)(x))

#if PDT_REAL_DOUBLE
#define STEP_RTOL 1e-12
#define FREQ_RTOL 1e-13
#else
#define STEP_RTOL 2e-6
#define FREQ_RTOL 1e-6
#endif

static pdt_model_t vec_model(int i)
{
    return vector_model(model_kind[i], &model_par[4 * i]);
}

static void test_step_vectors(void **state)
{
    (void)state;
    double worst = 0.0;
    for (int i = 0; i < MODEL_VEC_COUNT; i++) {
        pdt_model_t m = vec_model(i);
        pdt_real_t t[MODEL_VEC_NT];
        pdt_real_t y[MODEL_VEC_NT + CANARY_COUNT];
        for (int j = 0; j < MODEL_VEC_NT; j++) {
            t[j] = (pdt_real_t)model_t[MODEL_VEC_NT * i + j];
        }
        canary_fill(y, MODEL_VEC_NT + CANARY_COUNT);
        assert_int_equal(pdt_model_step(&m, t, MODEL_VEC_NT, y), PDT_OK);
        canary_check(y + MODEL_VEC_NT, CANARY_COUNT);
        for (int j = 0; j < MODEL_VEC_NT; j++) {
            double want = model_step[MODEL_VEC_NT * i + j];
            if (want == 0.0) {
                assert_true(y[j] == R(0.0));
                continue;
            }
            double rel = fabs((double)y[j] - want) / fabs(want);
            if (rel > worst) {
                worst = rel;
            }
            assert_close(y[j], want, STEP_RTOL, 0.0);
        }
    }
    print_message("step: worst relative error %.3g\n", worst);
}

static void test_freq_vectors(void **state)
{
    (void)state;
    double worst_mag = 0.0;
    double worst_ph = 0.0;
    for (int i = 0; i < MODEL_VEC_COUNT; i++) {
        pdt_model_t m = vec_model(i);
        pdt_real_t w[MODEL_VEC_NW];
        pdt_real_t mag[MODEL_VEC_NW + CANARY_COUNT];
        pdt_real_t ph[MODEL_VEC_NW + CANARY_COUNT];
        for (int j = 0; j < MODEL_VEC_NW; j++) {
            w[j] = (pdt_real_t)model_w[MODEL_VEC_NW * i + j];
        }
        canary_fill(mag, MODEL_VEC_NW + CANARY_COUNT);
        canary_fill(ph, MODEL_VEC_NW + CANARY_COUNT);
        assert_int_equal(pdt_model_freq(&m, w, MODEL_VEC_NW, mag, ph), PDT_OK);
        canary_check(mag + MODEL_VEC_NW, CANARY_COUNT);
        canary_check(ph + MODEL_VEC_NW, CANARY_COUNT);
        bool integ = m.kind == PDT_MODEL_SOPDT && m.p.sopdt.b == R(0.0);
        for (int j = 0; j < MODEL_VEC_NW; j++) {
            double wm = model_mag[MODEL_VEC_NW * i + j];
            double wp = model_phase[MODEL_VEC_NW * i + j];
            if (integ && w[j] == R(0.0)) {
                assert_true(isinf(mag[j]) && mag[j] > 0);
            } else {
                double rel = fabs((double)mag[j] - wm) / fabs(wm);
                worst_mag = rel > worst_mag ? rel : worst_mag;
                assert_close(mag[j], wm, FREQ_RTOL, 0.0);
            }
            /* phase error relative to its size, w Td included */
            double e = fabs((double)ph[j] - wp) / (1.0 + fabs(wp));
            worst_ph = e > worst_ph ? e : worst_ph;
            assert_close(ph[j], wp, FREQ_RTOL, FREQ_RTOL);
        }
        /* either output may be left out */
        pdt_real_t only[MODEL_VEC_NW];
        assert_int_equal(pdt_model_freq(&m, w, MODEL_VEC_NW, NULL, only), PDT_OK);
        assert_memory_equal(only, ph, sizeof only);
        assert_int_equal(pdt_model_freq(&m, w, MODEL_VEC_NW, only, NULL), PDT_OK);
        assert_memory_equal(only, mag, sizeof only);
    }
    print_message("freq: worst relative error magnitude %.3g, phase %.3g\n", worst_mag, worst_ph);
}

static void test_conversions_vectors(void **state)
{
    (void)state;
    const double rt = TEST_RTOL * 0.01;
    for (int i = 0; i < MODEL_VEC_COUNT; i++) {
        if (model_kind[i] != 2) {
            continue;
        }
        pdt_model_t m = vec_model(i);
        const pdt_model_sopdt_t *s = &m.p.sopdt;
        pdt_model_natural_t nat;
        pdt_model_tc_t tc;
        pdt_model_integ_t integ;
        pdt_model_sopdt_t back;
        int mask = model_forms[i];
        if (mask & 1) {
            const double *v = &model_natural[4 * i];
            assert_int_equal(pdt_model_sopdt_to_natural(s, &nat), PDT_OK);
            assert_close(nat.K, v[0], rt, 0.0);
            assert_close(nat.wn, v[1], rt, 0.0);
            assert_close(nat.zeta, v[2], rt, 0.0);
            assert_close(nat.Td, v[3], 0.0, 0.0);
            assert_int_equal(pdt_model_sopdt_from_natural(&nat, &back), PDT_OK);
            assert_close(back.k, s->k, rt, 0.0);
            assert_close(back.a, s->a, rt, 0.0);
            assert_close(back.b, s->b, rt, 0.0);
            assert_close(back.Td, s->Td, 0.0, 0.0);
        } else {
            memset(&nat, 0x5a, sizeof nat);
            pdt_model_natural_t keep = nat;
            assert_int_equal(pdt_model_sopdt_to_natural(s, &nat), PDT_ERR_NO_FORM);
            assert_memory_equal(&nat, &keep, sizeof nat);
        }
        if (mask & 2) {
            const double *v = &model_tc[5 * i];
            assert_int_equal(pdt_model_sopdt_to_tc(s, &tc), PDT_OK);
            assert_int_equal(tc.complex ? 1 : 0, v[3] != 0.0 ? 1 : 0);
            assert_close(tc.K, v[0], rt, 0.0);
            /* near critical damping the split of the pair is a square root
             * of a difference: its error is sqrt(eps) of the time constant */
            double ttol = fabs(v[1] - v[2]) < 0.1 * v[1] ? 3e-3 : rt;
            assert_close(tc.T1, v[1], ttol, 0.0);
            assert_close(tc.T2, v[2], ttol, ttol * v[1]);
            assert_int_equal(pdt_model_sopdt_from_tc(&tc, &back), PDT_OK);
            assert_close(back.k, s->k, rt, 0.0);
            assert_close(back.a, s->a, rt, 0.0);
            assert_close(back.b, s->b, rt, 0.0);
        } else {
            memset(&tc, 0x5a, sizeof tc);
            pdt_model_tc_t keep = tc;
            assert_int_equal(pdt_model_sopdt_to_tc(s, &tc), PDT_ERR_NO_FORM);
            assert_memory_equal(&tc, &keep, sizeof tc);
        }
        if (mask & 4) {
            const double *v = &model_integ[3 * i];
            assert_int_equal(pdt_model_sopdt_to_integ(s, &integ), PDT_OK);
            assert_close(integ.Ki, v[0], rt, 0.0);
            assert_close(integ.T, v[1], rt, 0.0);
            assert_int_equal(pdt_model_sopdt_from_integ(&integ, &back), PDT_OK);
            assert_close(back.k, s->k, rt, 0.0);
            assert_close(back.a, s->a, rt, 0.0);
            assert_true(back.b == R(0.0));
        } else {
            memset(&integ, 0x5a, sizeof integ);
            pdt_model_integ_t keep = integ;
            assert_int_equal(pdt_model_sopdt_to_integ(s, &integ), PDT_ERR_NO_FORM);
            assert_memory_equal(&integ, &keep, sizeof integ);
        }
    }
}

static void test_conversions_round_trip(void **state)
{
    (void)state;
    const double rt = 1e-5 > TEST_RTOL * 0.01 ? TEST_RTOL * 0.01 : 1e-5;
    pdt_model_tc_t in[3] = {{R(2.0), R(3.0), R(0.5), false, R(0.25)},
                            {R(-1.0), R(0.5), R(3.0), false, R(0.0)},
                            {R(1.0), R(2.9), R(0.5), true, R(0.79)}};
    for (int i = 0; i < 3; i++) {
        pdt_model_sopdt_t s;
        pdt_model_tc_t out;
        assert_int_equal(pdt_model_sopdt_from_tc(&in[i], &s), PDT_OK);
        assert_int_equal(pdt_model_sopdt_to_tc(&s, &out), PDT_OK);
        /* to_tc orders a real pair: larger first */
        pdt_real_t hi = in[i].complex || in[i].T1 > in[i].T2 ? in[i].T1 : in[i].T2;
        pdt_real_t lo = in[i].complex || in[i].T1 > in[i].T2 ? in[i].T2 : in[i].T1;
        assert_int_equal(out.complex, in[i].complex);
        assert_close(out.K, in[i].K, rt, 0.0);
        assert_close(out.T1, hi, rt, 0.0);
        assert_close(out.T2, lo, rt, 0.0);
        assert_close(out.Td, in[i].Td, 0.0, 0.0);
        pdt_model_natural_t n;
        pdt_model_sopdt_t s2;
        assert_int_equal(pdt_model_sopdt_to_natural(&s, &n), PDT_OK);
        assert_int_equal(pdt_model_sopdt_from_natural(&n, &s2), PDT_OK);
        assert_close(s2.k, s.k, rt, 0.0);
        assert_close(s2.a, s.a, rt, 0.0);
        assert_close(s2.b, s.b, rt, 0.0);
    }
    /* zeta = 1 exactly gives a repeated real pair */
    pdt_model_natural_t crit = {R(1.0), R(2.0), R(1.0), R(0.0)};
    pdt_model_sopdt_t s;
    pdt_model_tc_t tc;
    assert_int_equal(pdt_model_sopdt_from_natural(&crit, &s), PDT_OK);
    assert_int_equal(pdt_model_sopdt_to_tc(&s, &tc), PDT_OK);
    assert_false(tc.complex);
    assert_close(tc.T1, 0.5, rt, 0.0);
    assert_close(tc.T2, 0.5, rt, 0.0);
    pdt_model_integ_t ig = {R(-0.4), R(1.5), R(2.0)};
    pdt_model_integ_t ig2;
    assert_int_equal(pdt_model_sopdt_from_integ(&ig, &s), PDT_OK);
    assert_int_equal(pdt_model_sopdt_to_integ(&s, &ig2), PDT_OK);
    assert_close(ig2.Ki, ig.Ki, rt, 0.0);
    assert_close(ig2.T, ig.T, rt, 0.0);
    assert_close(ig2.Td, ig.Td, 0.0, 0.0);
}

static void test_dc_gain_and_dead_time(void **state)
{
    (void)state;
    for (int i = 0; i < MODEL_VEC_COUNT; i++) {
        pdt_model_t m = vec_model(i);
        pdt_real_t g = R(-7.0);
        pdt_status_t st = pdt_model_dc_gain(&m, &g);
        assert_int_equal(pdt_model_check(&m), PDT_OK);
        if (m.kind == PDT_MODEL_FOPDT) {
            assert_int_equal(st, PDT_OK);
            assert_true(g == m.p.fopdt.K);
            assert_true(pdt_model_dead_time(&m) == m.p.fopdt.Td);
        } else if (m.p.sopdt.b == R(0.0)) {
            assert_int_equal(st, PDT_ERR_NO_FORM);
            assert_true(g == R(-7.0));
        } else {
            assert_int_equal(st, PDT_OK);
            assert_close(g, (double)m.p.sopdt.k / (double)m.p.sopdt.b, 1e-6, 0.0);
            assert_true(pdt_model_dead_time(&m) == m.p.sopdt.Td);
            /* the step response settles at the DC gain */
            pdt_real_t t = m.p.sopdt.Td + R(200.0) / m.p.sopdt.a * R(40.0);
            pdt_real_t y;
            assert_int_equal(pdt_model_step(&m, &t, 1, &y), PDT_OK);
            assert_close(y, g, 1e-4, 0.0);
        }
    }
    assert_true(pdt_model_dead_time(NULL) == R(0.0));
}

static void test_step_properties(void **state)
{
    (void)state;
    /* integrator: slope Ki at large times, and y = Ki (t - Td - T) there */
    pdt_model_integ_t ig = {R(0.5), R(2.0), R(0.33)};
    pdt_model_t m;
    m.kind = PDT_MODEL_SOPDT;
    assert_int_equal(pdt_model_sopdt_from_integ(&ig, &m.p.sopdt), PDT_OK);
    pdt_real_t t[4] = {R(40.0), R(60.0), R(80.0), R(100.0)};
    pdt_real_t y[4];
    assert_int_equal(pdt_model_step(&m, t, 4, y), PDT_OK);
    for (int j = 0; j < 4; j++) {
        assert_close(y[j], 0.5 * ((double)t[j] - 0.33 - 2.0), 1e-5, 0.0);
    }
    for (int j = 1; j < 4; j++) {
        assert_close(y[j] - y[j - 1], 0.5 * 20.0, 1e-5, 0.0);
    }
    /* continuity across the branches of the SOPDT formula: zeta just below,
     * at and above 1 give nearly the same response */
    double prev[3][8];
    const pdt_real_t zetas[3] = {R(0.9999), R(1.0), R(1.0001)};
    for (int z = 0; z < 3; z++) {
        pdt_model_natural_t n = {R(1.0), R(1.0), zetas[z], R(0.0)};
        assert_int_equal(pdt_model_sopdt_from_natural(&n, &m.p.sopdt), PDT_OK);
        for (int j = 0; j < 8; j++) {
            pdt_real_t tj = R(0.01) * (pdt_real_t)(1 << (2 * j));
            pdt_real_t yj;
            assert_int_equal(pdt_model_step(&m, &tj, 1, &yj), PDT_OK);
            prev[z][j] = (double)yj;
        }
    }
    for (int j = 0; j < 8; j++) {
        assert_close(prev[0][j], prev[1][j], 2e-4, 1e-7);
        assert_close(prev[2][j], prev[1][j], 2e-4, 1e-7);
    }
    /* widely separated poles at large times: no overflow, settles at K */
    pdt_model_tc_t tc = {R(1.0), R(1.0), R(0.6), false, R(0.0)};
    assert_int_equal(pdt_model_sopdt_from_tc(&tc, &m.p.sopdt), PDT_OK);
    pdt_real_t tl[3] = {R(200.0), R(1e4), R(1e30)};
    pdt_real_t yl[3];
    assert_int_equal(pdt_model_step(&m, tl, 3, yl), PDT_OK);
    for (int j = 0; j < 3; j++) {
        assert_close(yl[j], 1.0, 1e-5, 0.0);
    }
    /* n = 0 is a no-op */
    assert_int_equal(pdt_model_step(&m, tl, 0, yl), PDT_OK);
    assert_int_equal(pdt_model_freq(&m, tl, 0, yl, yl), PDT_OK);
}

static void test_negative_gain_phase(void **state)
{
    (void)state;
    pdt_model_t p;
    pdt_model_t n;
    p.kind = n.kind = PDT_MODEL_FOPDT;
    p.p.fopdt = (pdt_model_fopdt_t){R(2.0), R(1.0), R(0.5)};
    n.p.fopdt = (pdt_model_fopdt_t){R(-2.0), R(1.0), R(0.5)};
    pdt_real_t w[3] = {R(0.0), R(1.0), R(3.0)};
    pdt_real_t mp[3], pp[3], mn[3], pn[3];
    assert_int_equal(pdt_model_freq(&p, w, 3, mp, pp), PDT_OK);
    assert_int_equal(pdt_model_freq(&n, w, 3, mn, pn), PDT_OK);
    for (int j = 0; j < 3; j++) {
        assert_true(mp[j] == mn[j]);
        assert_close(pn[j], (double)pp[j] - 3.14159265358979, 1e-6, 1e-6);
    }
    /* integrator at w = 0: +inf, -pi/2 */
    pdt_model_t ig;
    ig.kind = PDT_MODEL_SOPDT;
    ig.p.sopdt = (pdt_model_sopdt_t){R(1.0), R(2.0), R(0.0), R(1.0)};
    assert_int_equal(pdt_model_freq(&ig, w, 1, mp, pp), PDT_OK);
    assert_true(isinf(mp[0]) && mp[0] > 0);
    assert_close(pp[0], -1.5707963267949, 1e-6, 0.0);
}

/* ---- bad inputs --------------------------------------------------------- */

static pdt_model_t good_sopdt(void)
{
    pdt_model_t m;
    m.kind = PDT_MODEL_SOPDT;
    m.p.sopdt = (pdt_model_sopdt_t){R(1.0), R(1.5), R(0.5), R(0.2)};
    return m;
}

static pdt_model_t good_fopdt(void)
{
    pdt_model_t m;
    m.kind = PDT_MODEL_FOPDT;
    m.p.fopdt = (pdt_model_fopdt_t){R(1.0), R(1.5), R(0.2)};
    return m;
}

/* A list of invalid models: each differs from a good one in one field. */
static size_t bad_models(pdt_model_t *out)
{
    const pdt_real_t nan = (pdt_real_t)NAN;
    const pdt_real_t inf = (pdt_real_t)INFINITY;
    size_t n = 0;
    pdt_model_t m;
    m = good_fopdt();
    m.p.fopdt.tau = R(0.0);
    out[n++] = m;
    m = good_fopdt();
    m.p.fopdt.tau = R(-1.0);
    out[n++] = m;
    m = good_fopdt();
    m.p.fopdt.Td = R(-0.1);
    out[n++] = m;
    m = good_fopdt();
    m.p.fopdt.K = nan;
    out[n++] = m;
    m = good_fopdt();
    m.p.fopdt.tau = inf;
    out[n++] = m;
    m = good_fopdt();
    m.p.fopdt.Td = inf;
    out[n++] = m;
    m = good_sopdt();
    m.p.sopdt.a = R(0.0);
    out[n++] = m;
    m = good_sopdt();
    m.p.sopdt.a = R(-1.0);
    out[n++] = m;
    m = good_sopdt();
    m.p.sopdt.b = R(-0.1);
    out[n++] = m;
    m = good_sopdt();
    m.p.sopdt.Td = R(-0.1);
    out[n++] = m;
    m = good_sopdt();
    m.p.sopdt.k = inf;
    out[n++] = m;
    m = good_sopdt();
    m.p.sopdt.a = nan;
    out[n++] = m;
    m = good_sopdt();
    m.p.sopdt.b = nan;
    out[n++] = m;
    m = good_sopdt();
    m.p.sopdt.Td = nan;
    out[n++] = m;
    m = good_sopdt();
    m.kind = (pdt_model_kind_t)0;
    out[n++] = m;
    m = good_sopdt();
    m.kind = (pdt_model_kind_t)3;
    out[n++] = m;
    return n;
}

static void test_bad_models(void **state)
{
    (void)state;
    pdt_model_t bad[32];
    size_t nb = bad_models(bad);
    pdt_real_t t[2] = {R(0.5), R(1.0)};
    for (size_t i = 0; i < nb; i++) {
        pdt_real_t y[2 + CANARY_COUNT];
        pdt_real_t y2[2 + CANARY_COUNT];
        canary_fill(y, 2 + CANARY_COUNT);
        canary_fill(y2, 2 + CANARY_COUNT);
        assert_int_equal(pdt_model_check(&bad[i]), PDT_ERR_ARG);
        assert_int_equal(pdt_model_step(&bad[i], t, 2, y), PDT_ERR_ARG);
        assert_int_equal(pdt_model_freq(&bad[i], t, 2, y, y2), PDT_ERR_ARG);
        pdt_real_t g = CANARY_VALUE;
        assert_int_equal(pdt_model_dc_gain(&bad[i], &g), PDT_ERR_ARG);
        canary_check(y, 2 + CANARY_COUNT);
        canary_check(y2, 2 + CANARY_COUNT);
        canary_check(&g, 1);
        if (bad[i].kind == PDT_MODEL_SOPDT) {
            pdt_model_natural_t n;
            pdt_model_tc_t tc;
            pdt_model_integ_t ig;
            memset(&n, 0x33, sizeof n);
            memset(&tc, 0x33, sizeof tc);
            memset(&ig, 0x33, sizeof ig);
            pdt_model_natural_t n0 = n;
            pdt_model_tc_t tc0 = tc;
            pdt_model_integ_t ig0 = ig;
            assert_int_equal(pdt_model_sopdt_to_natural(&bad[i].p.sopdt, &n), PDT_ERR_ARG);
            assert_int_equal(pdt_model_sopdt_to_tc(&bad[i].p.sopdt, &tc), PDT_ERR_ARG);
            assert_int_equal(pdt_model_sopdt_to_integ(&bad[i].p.sopdt, &ig), PDT_ERR_ARG);
            assert_memory_equal(&n, &n0, sizeof n);
            assert_memory_equal(&tc, &tc0, sizeof tc);
            assert_memory_equal(&ig, &ig0, sizeof ig);
        }
    }
    pdt_model_t m = good_sopdt();
    pdt_real_t y[2 + CANARY_COUNT];
    canary_fill(y, 2 + CANARY_COUNT);
    assert_int_equal(pdt_model_check(NULL), PDT_ERR_ARG);
    assert_int_equal(pdt_model_step(NULL, t, 2, y), PDT_ERR_ARG);
    assert_int_equal(pdt_model_step(&m, NULL, 2, y), PDT_ERR_ARG);
    assert_int_equal(pdt_model_step(&m, t, 2, NULL), PDT_ERR_ARG);
    assert_int_equal(pdt_model_freq(NULL, t, 2, y, y), PDT_ERR_ARG);
    assert_int_equal(pdt_model_freq(&m, NULL, 2, y, y), PDT_ERR_ARG);
    assert_int_equal(pdt_model_dc_gain(NULL, y), PDT_ERR_ARG);
    assert_int_equal(pdt_model_dc_gain(&m, NULL), PDT_ERR_ARG);
    canary_check(y, 2 + CANARY_COUNT);
}

static void test_bad_samples(void **state)
{
    (void)state;
    pdt_model_t ms[2] = {good_sopdt(), good_fopdt()};
    const pdt_real_t bads[3] = {(pdt_real_t)NAN, (pdt_real_t)INFINITY, -(pdt_real_t)INFINITY};
    for (int k = 0; k < 2; k++) {
        for (int b = 0; b < 3; b++) {
            pdt_real_t t[3] = {R(0.5), R(1.0), bads[b]};
            pdt_real_t y[3 + CANARY_COUNT];
            pdt_real_t y2[3 + CANARY_COUNT];
            canary_fill(y, 3 + CANARY_COUNT);
            canary_fill(y2, 3 + CANARY_COUNT);
            assert_int_equal(pdt_model_step(&ms[k], t, 3, y), PDT_ERR_NONFINITE);
            assert_int_equal(pdt_model_freq(&ms[k], t, 3, y, y2), PDT_ERR_NONFINITE);
            canary_check(y, 3 + CANARY_COUNT);
            canary_check(y2, 3 + CANARY_COUNT);
        }
        pdt_real_t w[3] = {R(0.5), R(-1e-3), R(1.0)};
        pdt_real_t y[3 + CANARY_COUNT];
        pdt_real_t y2[3 + CANARY_COUNT];
        canary_fill(y, 3 + CANARY_COUNT);
        canary_fill(y2, 3 + CANARY_COUNT);
        assert_int_equal(pdt_model_freq(&ms[k], w, 3, y, y2), PDT_ERR_ARG);
        canary_check(y, 3 + CANARY_COUNT);
        canary_check(y2, 3 + CANARY_COUNT);
    }
}

static void test_bad_conversions(void **state)
{
    (void)state;
    const pdt_real_t nan = (pdt_real_t)NAN;
    pdt_model_sopdt_t out;
    memset(&out, 0x44, sizeof out);
    pdt_model_sopdt_t keep = out;
    pdt_model_natural_t nb[5] = {{R(1.0), R(0.0), R(0.5), R(0.0)},
                                 {R(1.0), R(1.0), R(0.0), R(0.0)},
                                 {R(1.0), R(1.0), R(0.5), R(-1.0)},
                                 {nan, R(1.0), R(0.5), R(0.0)},
                                 {R(1.0), R(-1.0), R(0.5), R(0.0)}};
    for (int i = 0; i < 5; i++) {
        assert_int_equal(pdt_model_sopdt_from_natural(&nb[i], &out), PDT_ERR_ARG);
    }
    pdt_model_tc_t tb[5] = {{R(1.0), R(0.0), R(0.5), false, R(0.0)},
                            {R(1.0), R(1.0), R(-0.5), false, R(0.0)},
                            {R(1.0), R(1.0), R(0.0), true, R(0.0)},
                            {R(1.0), R(1.0), R(0.5), true, R(-1.0)},
                            {R(1.0), nan, R(0.5), false, R(0.0)}};
    for (int i = 0; i < 5; i++) {
        assert_int_equal(pdt_model_sopdt_from_tc(&tb[i], &out), PDT_ERR_ARG);
    }
    pdt_model_integ_t ib[3] = {{R(1.0), R(0.0), R(0.0)},
                               {R(1.0), R(1.0), R(-1.0)},
                               {(pdt_real_t)INFINITY, R(1.0), R(0.0)}};
    for (int i = 0; i < 3; i++) {
        assert_int_equal(pdt_model_sopdt_from_integ(&ib[i], &out), PDT_ERR_ARG);
    }
    assert_int_equal(pdt_model_sopdt_from_natural(NULL, &out), PDT_ERR_ARG);
    assert_int_equal(pdt_model_sopdt_from_tc(NULL, &out), PDT_ERR_ARG);
    assert_int_equal(pdt_model_sopdt_from_integ(NULL, &out), PDT_ERR_ARG);
    assert_memory_equal(&out, &keep, sizeof out);
    assert_int_equal(pdt_model_sopdt_from_natural(&nb[0], NULL), PDT_ERR_ARG);
    assert_int_equal(pdt_model_sopdt_from_tc(&tb[0], NULL), PDT_ERR_ARG);
    assert_int_equal(pdt_model_sopdt_from_integ(&ib[0], NULL), PDT_ERR_ARG);
    pdt_model_sopdt_t s = good_sopdt().p.sopdt;
    assert_int_equal(pdt_model_sopdt_to_natural(NULL, NULL), PDT_ERR_ARG);
    assert_int_equal(pdt_model_sopdt_to_natural(&s, NULL), PDT_ERR_ARG);
    assert_int_equal(pdt_model_sopdt_to_tc(&s, NULL), PDT_ERR_ARG);
    assert_int_equal(pdt_model_sopdt_to_integ(&s, NULL), PDT_ERR_ARG);
    /* a non-integrating model has no integrating form */
    pdt_model_integ_t ig;
    memset(&ig, 0x21, sizeof ig);
    pdt_model_integ_t ig0 = ig;
    assert_int_equal(pdt_model_sopdt_to_integ(&s, &ig), PDT_ERR_NO_FORM);
    assert_memory_equal(&ig, &ig0, sizeof ig);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_step_vectors),          cmocka_unit_test(test_freq_vectors),
        cmocka_unit_test(test_conversions_vectors),   cmocka_unit_test(test_conversions_round_trip),
        cmocka_unit_test(test_dc_gain_and_dead_time), cmocka_unit_test(test_step_properties),
        cmocka_unit_test(test_negative_gain_phase),   cmocka_unit_test(test_bad_models),
        cmocka_unit_test(test_bad_samples),           cmocka_unit_test(test_bad_conversions),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
