/*
 * Tests of lib/src/pdt_excite.c: every kind against the numpy reference
 * (excite_vectors.h) with canaries after the output buffer, PRBS period and
 * balance, chirp instantaneous frequency, the relay's Ku and Pu on a
 * simulated FOPDT loop against the closed-form limit cycle and the
 * describing function, and every bad-input status.
 */
#include "test_util.h"
#include "sim_process.h"

#include "pdt/pdt_discrete.h"
#include "pdt/pdt_excite.h"

#include "excite_vectors.h"

#define PI 3.14159265358979323846

#define R(x) ((pdt_real_t)(x))
#define MAXN 1024

static pdt_real_t lim(double x)
{
    if (x >= EXC_BIG) {
        return R(3.4e38);
    }
    if (x <= -EXC_BIG) {
        return R(-3.4e38);
    }
    return (pdt_real_t)x;
}

static pdt_excite_config_t case_config(int i)
{
    const double *p = &exc_par[EXC_NPAR * i];
    pdt_excite_config_t c;
    pdt_excite_config_default(&c, (pdt_excite_kind_t)(int)p[EXC_P_KIND]);
    c.Ts = R(p[EXC_P_TS]);
    c.u0 = R(p[EXC_P_U0]);
    c.u_min = lim(p[EXC_P_U_MIN]);
    c.u_max = lim(p[EXC_P_U_MAX]);
    c.clamp = p[EXC_P_CLAMP] != 0.0;
    c.pre = R(p[EXC_P_PRE]);
    c.amplitude = R(p[EXC_P_AMPLITUDE]);
    c.duration = R(p[EXC_P_DURATION]);
    c.t_on = R(p[EXC_P_T_ON]);
    c.t_off = R(p[EXC_P_T_OFF]);
    c.count = (uint32_t)p[EXC_P_COUNT];
    c.f0 = R(p[EXC_P_F0]);
    c.f1 = R(p[EXC_P_F1]);
    c.prbs_bits = (uint32_t)p[EXC_P_PRBS_BITS];
    c.prbs_hold = (uint32_t)p[EXC_P_PRBS_HOLD];
    c.prbs_seed = (uint32_t)p[EXC_P_PRBS_SEED];
    c.periods = (uint32_t)p[EXC_P_PERIODS];
    c.setpoint = R(p[EXC_P_SETPOINT]);
    c.d = R(p[EXC_P_D]);
    c.bias = R(p[EXC_P_BIAS]);
    c.eps = R(p[EXC_P_EPS]);
    c.action = (pdt_excite_action_t)(int)p[EXC_P_ACTION];
    c.relay_skip = (uint32_t)p[EXC_P_RELAY_SKIP];
    c.relay_cycles = (uint32_t)p[EXC_P_RELAY_CYCLES];
    c.relay_settle = R(0.0); /* the reference measures every cycle */
    return c;
}

static void test_defaults(void **state)
{
    (void)state;
    pdt_excite_config_t c;
    pdt_excite_config_default(NULL, PDT_EXCITE_STEP);
    pdt_excite_config_default(&c, PDT_EXCITE_CHIRP);
    assert_int_equal(c.kind, PDT_EXCITE_CHIRP);
    assert_true(c.Ts == R(0.0));
    assert_true(c.amplitude == R(1.0));
    assert_int_equal(c.prbs_bits, 7);
    assert_int_equal(c.relay_cycles, 3);
    assert_int_equal(c.relay_skip, 0);
    assert_true(c.relay_settle == R(0.1));
    assert_false(c.clamp);
    /* defaults work once Ts is set (the chirp needs its sweep too) */
    pdt_excite_t g;
    for (int k = PDT_EXCITE_STEP; k <= PDT_EXCITE_RELAY; k++) {
        pdt_excite_config_default(&c, (pdt_excite_kind_t)k);
        c.Ts = R(0.1);
        if (k == PDT_EXCITE_CHIRP) {
            c.duration = R(10.0);
            c.f1 = R(1.0);
        }
        assert_int_equal(pdt_excite_init(&g, &c), PDT_OK);
    }
}

/* Every case of the reference: outputs, statuses, length, canaries. */
static void test_vectors(void **state)
{
    (void)state;
    double worst = 0.0;
    for (int i = 0; i < EXC_CASES; i++) {
        pdt_excite_config_t c = case_config(i);
        pdt_excite_t g;
        pdt_real_t buf[MAXN + CANARY_COUNT];
        int n = exc_len[i];
        assert_true(n <= MAXN);
        assert_int_equal(pdt_excite_init(&g, &c), PDT_OK);
        assert_int_equal((long)pdt_excite_length(&g), exc_length[i]);
        canary_fill(buf, MAXN + CANARY_COUNT);
        const double *want = &exc_u[exc_off[i]];
        const double *pv = &exc_pv[exc_off[i]];
        double scale = fabs((double)c.u0) + fabs((double)c.amplitude) + fabs((double)c.d);
        for (int k = 0; k < n; k++) {
            pdt_status_t st = pdt_excite_next(&g, (pdt_real_t)pv[k], &buf[k]);
            int first_ok = exc_first_ok[i];
            assert_int_equal(st, (first_ok >= 0 && k >= first_ok) ? PDT_OK : PDT_RUNNING);
        }
        canary_check(buf + n, CANARY_COUNT);
        for (int k = 0; k < n; k++) {
            double err = fabs((double)buf[k] - want[k]) / scale;
            worst = err > worst ? err : worst;
            assert_close(buf[k], want[k], 0.0, TEST_RTOL * scale);
        }
        if (c.kind == PDT_EXCITE_CHIRP) {
            assert_true(snr_db(buf, want, (size_t)n) > (PDT_REAL_DOUBLE ? 200.0 : 90.0));
        }
        if (c.kind == PDT_EXCITE_PRBS || c.kind == PDT_EXCITE_STEP || c.kind == PDT_EXCITE_PULSE) {
            for (int k = 0; k < n; k++) {
                assert_true(buf[k] == (pdt_real_t)want[k]); /* levels are exact */
            }
        }
    }
    print_message("worst output error / scale: %.3g\n", worst);
}

static void test_relay_vectors(void **state)
{
    (void)state;
    for (int r = 0; r < EXC_RELAY_CASES; r++) {
        int i = exc_relay_case[r];
        pdt_excite_config_t c = case_config(i);
        pdt_excite_t g;
        pdt_excite_relay_t res;
        pdt_real_t u;
        assert_int_equal(pdt_excite_init(&g, &c), PDT_OK);
        assert_int_equal(pdt_excite_relay_result(&g, &res), PDT_ERR_STATE);
        for (int k = 0; k < exc_len[i]; k++) {
            (void)pdt_excite_next(&g, (pdt_real_t)exc_pv[exc_off[i] + k], &u);
        }
        assert_int_equal(pdt_excite_relay_result(&g, &res), PDT_OK);
        const double *w = &exc_relay[5 * r];
        assert_close(res.Ku, w[0], TEST_RTOL, 0.0);
        assert_close(res.Pu, w[1], TEST_RTOL, 0.0);
        assert_close(res.a, w[2], TEST_RTOL, 0.0);
        assert_close(res.d, w[3], TEST_RTOL, 0.0);
        assert_int_equal(res.cycles, (int)w[4]);
    }
}

/* PRBS: period exactly 2^n - 1 chips (no proper divisor is a period) and
 * one more high chip than low ones per period, for every n up to 16, with
 * a seed that uses all n bits. */
static void test_prbs_period_balance(void **state)
{
    (void)state;
    static unsigned char bits[2u * 65535u];
    for (uint32_t n = 2; n <= 16; n++) {
        pdt_excite_config_t c;
        pdt_excite_t g;
        pdt_excite_config_default(&c, PDT_EXCITE_PRBS);
        c.Ts = R(1.0);
        c.u0 = R(3.0);
        c.amplitude = R(0.5);
        c.prbs_bits = n;
        c.prbs_seed = 0xFFFFFFFFu;
        c.periods = 2;
        uint32_t N = (1u << n) - 1u;
        assert_int_equal(pdt_excite_init(&g, &c), PDT_OK);
        assert_int_equal(pdt_excite_length(&g), 2u * N);
        uint32_t high = 0;
        for (uint32_t k = 0; k < 2u * N; k++) {
            pdt_real_t u;
            assert_int_equal(pdt_excite_next(&g, R(0.0), &u), PDT_RUNNING);
            assert_true(u == R(3.5) || u == R(2.5));
            bits[k] = (unsigned char)(u > R(3.0));
            high += (k < N) ? bits[k] : 0u;
        }
        assert_int_equal(high, (1u << (n - 1u)));
        for (uint32_t k = 0; k < N; k++) {
            assert_int_equal(bits[k], bits[k + N]);
        }
        for (uint32_t p = 1; p < N; p++) {
            if (N % p != 0u) {
                continue;
            }
            uint32_t k = 0;
            while (k < N && bits[k] == bits[k + p]) {
                k++;
            }
            assert_true(k < N); /* p is not a period */
        }
        pdt_real_t u;
        assert_int_equal(pdt_excite_next(&g, R(0.0), &u), PDT_OK);
        assert_true(u == R(3.0));
    }
}

/* Chirp: the spacing of upward zero crossings gives the instantaneous
 * frequency f0 + (f1 - f0) t / T at their midpoint. */
static void test_chirp_frequency(void **state)
{
    (void)state;
    enum { N = 6000 };
    static pdt_real_t u[N];
    pdt_excite_config_t c;
    pdt_excite_t g;
    pdt_excite_config_default(&c, PDT_EXCITE_CHIRP);
    c.Ts = R(0.005);
    c.duration = R(30.0);
    c.f0 = R(0.2);
    c.f1 = R(4.0);
    c.u0 = R(10.0);
    c.amplitude = R(2.0);
    assert_int_equal(pdt_excite_init(&g, &c), PDT_OK);
    assert_int_equal(pdt_excite_length(&g), N);
    for (int k = 0; k < N; k++) {
        assert_int_equal(pdt_excite_next(&g, R(0.0), &u[k]), PDT_RUNNING);
    }
    double t_prev = -1.0;
    double worst = 0.0;
    int crossings = 0;
    for (int k = 0; k + 1 < N; k++) {
        double a = (double)u[k] - 10.0;
        double b = (double)u[k + 1] - 10.0;
        if (a < 0.0 && b >= 0.0) {
            double t = ((double)k + a / (a - b)) * 0.005;
            if (t_prev >= 0.0) {
                double f = 1.0 / (t - t_prev);
                double want = 0.2 + 3.8 * 0.5 * (t + t_prev) / 30.0;
                double e = fabs(f / want - 1.0);
                worst = e > worst ? e : worst;
            }
            t_prev = t;
            crossings++;
        }
    }
    /* (f0 + f1) / 2 T = 63 cycles */
    assert_in_range(crossings, 62, 64);
    print_message("chirp: worst relative frequency error %.3g\n", worst);
    assert_true(worst < 3e-3);
}

/* The relay closes the loop around K e^{-L s} / (tau s + 1), simulated by
 * the shared simulator. The ideal relay's limit cycle is known in
 * closed form: half period tau ln(2 e^{L/tau} - 1), amplitude
 * K d (1 - e^{-L/tau}). */
static void relay_fopdt(pdt_real_t eps, double *Ku, double *Pu, double *a_out)
{
    enum { NMAX = 20000 };
    static pdt_real_t uu[NMAX];
    static pdt_real_t pv[NMAX];
    static pdt_real_t ysim[NMAX];
    static double hist[512];
    const double K = 1.5, tau = 1.0, L = 2.0, Ts = 0.005, d = 1.0;
    const double lag[1] = {tau};
    const sim_plant_desc_t desc = sim_plant_desc_lags(K, lag, 1u, L);
    sim_plant_t plant;
    assert_int_equal(sim_plant_init(&plant, &desc, Ts, 0.0, 0.0, hist, 512u), 0);
    pdt_excite_config_t c;
    pdt_excite_t g;
    pdt_excite_config_default(&c, PDT_EXCITE_RELAY);
    c.Ts = R(Ts);
    c.u0 = R(0.0);
    c.d = R(d);
    c.eps = eps;
    c.setpoint = R(0.0);
    c.relay_skip = 2;
    c.relay_cycles = 4;
    c.relay_settle = R(0.0);
    assert_int_equal(pdt_excite_init(&g, &c), PDT_OK);
    size_t n = 0;
    pdt_status_t st = PDT_RUNNING;
    while (st == PDT_RUNNING) {
        assert_true(n < NMAX);
        pv[n] = (pdt_real_t)sim_plant_output(&plant);
        st = pdt_excite_next(&g, pv[n], &uu[n]);
        sim_plant_apply(&plant, (double)uu[n]);
        n++;
    }
    assert_int_equal(st, PDT_OK);
    /* the loop's pv is the library's sampled model's response to the
     * relay's output too */
    pdt_model_t m = model_fopdt(K, tau, L);
    pdt_discrete_t dm;
    assert_int_equal(pdt_discrete_init(&m, R(Ts), &dm), PDT_OK);
    assert_int_equal(pdt_discrete_simulate(&dm, uu, n, ysim), PDT_OK);
    for (size_t k = 0; k < n; k++) {
        assert_close(ysim[k], pv[k], 0.0, 1e3 * TEST_RTOL);
    }
    pdt_excite_relay_t res;
    assert_int_equal(pdt_excite_relay_result(&g, &res), PDT_OK);
    assert_int_equal(res.cycles, 4);
    assert_close(res.d, d, 0.0, 1e-12);
    *Ku = (double)res.Ku;
    *Pu = (double)res.Pu;
    *a_out = (double)res.a;
}

static void test_relay_fopdt(void **state)
{
    (void)state;
    const double K = 1.5, tau = 1.0, L = 2.0, d = 1.0;
    double Ku, Pu, a;
    relay_fopdt(R(0.0), &Ku, &Pu, &a);
    double a_cf = K * d * (1.0 - exp(-L / tau));
    double Pu_cf = 2.0 * tau * log(2.0 * exp(L / tau) - 1.0);
    double Ku_cf = 4.0 * d / (PI * a_cf);
    /* describing function: the FOPDT's phase crossover, w L + atan(w tau) = pi */
    double lo = 1e-6, hi = PI / L;
    for (int i = 0; i < 200; i++) {
        double w = 0.5 * (lo + hi);
        if (w * L + atan(w * tau) < PI) {
            lo = w;
        } else {
            hi = w;
        }
    }
    double wu = 0.5 * (lo + hi);
    double Ku_df = sqrt(1.0 + wu * wu * tau * tau) / K;
    double Pu_df = 2.0 * PI / wu;
    print_message("relay: Ku %.5g (limit cycle %.5g, DF %.5g), Pu %.5g (%.5g, %.5g)\n", Ku, Ku_cf,
                  Ku_df, Pu, Pu_cf, Pu_df);
    /* sampled switching adds up to one sample (0.1 % of Pu) */
    assert_close(Ku, Ku_cf, 5e-3, 0.0);
    assert_close(a, a_cf, 5e-3, 0.0);
    assert_close(Pu, Pu_cf, 5e-3, 0.0);
    assert_close(Ku, Ku_df, 0.05, 0.0);
    assert_close(Pu, Pu_df, 0.05, 0.0);

    /* a small hysteresis moves the point little */
    double Ku2, Pu2, a2;
    relay_fopdt(R(0.02), &Ku2, &Pu2, &a2);
    assert_close(Ku2, Ku_cf, 0.05, 0.0);
    assert_close(Pu2, Pu_cf, 0.05, 0.0);
    assert_true(Pu2 > Pu); /* hysteresis lengthens the cycle */
}

/* Reverse and direct action switch the other way round on the same pv. */
static void test_relay_action(void **state)
{
    (void)state;
    pdt_excite_config_t c;
    pdt_excite_t g;
    pdt_real_t u;
    pdt_excite_config_default(&c, PDT_EXCITE_RELAY);
    c.Ts = R(1.0);
    c.u0 = R(10.0);
    c.d = R(2.0);
    c.setpoint = R(5.0);
    c.eps = R(0.5);
    assert_int_equal(pdt_excite_init(&g, &c), PDT_OK);
    assert_int_equal(pdt_excite_next(&g, R(4.0), &u), PDT_RUNNING);
    assert_true(u == R(12.0)); /* below the set-point: high */
    assert_int_equal(pdt_excite_next(&g, R(5.4), &u), PDT_RUNNING);
    assert_true(u == R(12.0)); /* inside the band: holds */
    assert_int_equal(pdt_excite_next(&g, R(5.6), &u), PDT_RUNNING);
    assert_true(u == R(8.0));
    c.action = PDT_EXCITE_DIRECT;
    assert_int_equal(pdt_excite_init(&g, &c), PDT_OK);
    assert_int_equal(pdt_excite_next(&g, R(4.0), &u), PDT_RUNNING);
    assert_true(u == R(8.0));
    assert_int_equal(pdt_excite_next(&g, R(5.6), &u), PDT_RUNNING);
    assert_true(u == R(12.0));
}

static pdt_excite_config_t good(pdt_excite_kind_t kind)
{
    pdt_excite_config_t c;
    pdt_excite_config_default(&c, kind);
    c.Ts = R(0.1);
    c.u_min = R(-10.0);
    c.u_max = R(10.0);
    c.duration = R(5.0);
    c.f1 = R(1.0);
    return c;
}

static void expect_init(pdt_excite_config_t c, pdt_status_t want)
{
    pdt_excite_t g;
    pdt_excite_t copy;
    memset(&g, 0xA5, sizeof g);
    memcpy(&copy, &g, sizeof g);
    assert_int_equal(pdt_excite_init(&g, &c), want);
    if (want != PDT_OK) {
        assert_memory_equal(&g, &copy, sizeof g);
    }
}

static void test_bad_config(void **state)
{
    (void)state;
    pdt_excite_t g;
    pdt_excite_config_t c = good(PDT_EXCITE_STEP);
    assert_int_equal(pdt_excite_init(NULL, &c), PDT_ERR_ARG);
    assert_int_equal(pdt_excite_init(&g, NULL), PDT_ERR_ARG);
    for (int k = PDT_EXCITE_STEP; k <= PDT_EXCITE_RELAY; k++) {
        expect_init(good((pdt_excite_kind_t)k), PDT_OK);
        c = good((pdt_excite_kind_t)k);
        c.Ts = R(0.0);
        expect_init(c, PDT_ERR_ARG);
        c = good((pdt_excite_kind_t)k);
        c.Ts = R(NAN);
        expect_init(c, PDT_ERR_ARG);
        c = good((pdt_excite_kind_t)k);
        c.u0 = R(INFINITY);
        expect_init(c, PDT_ERR_ARG);
        c = good((pdt_excite_kind_t)k);
        c.u_max = R(INFINITY);
        expect_init(c, PDT_ERR_ARG);
        c = good((pdt_excite_kind_t)k);
        c.pre = R(-1.0);
        expect_init(c, PDT_ERR_ARG);
        c = good((pdt_excite_kind_t)k);
        c.u_min = R(1.0);
        c.u_max = R(-1.0);
        expect_init(c, PDT_ERR_BOUNDS);
        c = good((pdt_excite_kind_t)k);
        c.u0 = R(11.0);
        expect_init(c, PDT_ERR_OUTPUT_LIMIT);
        c.clamp = true;
        expect_init(c, PDT_ERR_OUTPUT_LIMIT); /* u0 itself must fit */
        c = good((pdt_excite_kind_t)k);
        c.pre = R(1e9);
        expect_init(c, PDT_ERR_LENGTH);
    }
    c = good((pdt_excite_kind_t)0);
    expect_init(c, PDT_ERR_ARG);
    c = good((pdt_excite_kind_t)6);
    expect_init(c, PDT_ERR_ARG);

    /* STEP */
    c = good(PDT_EXCITE_STEP);
    c.amplitude = R(0.0);
    expect_init(c, PDT_ERR_ARG);
    c = good(PDT_EXCITE_STEP);
    c.duration = R(-1.0);
    expect_init(c, PDT_ERR_ARG);
    c = good(PDT_EXCITE_STEP);
    c.duration = R(NAN);
    expect_init(c, PDT_ERR_ARG);
    c = good(PDT_EXCITE_STEP);
    c.duration = R(4.5e8);
    expect_init(c, PDT_ERR_LENGTH);
    c = good(PDT_EXCITE_STEP);
    c.amplitude = R(10.5);
    expect_init(c, PDT_ERR_OUTPUT_LIMIT);
    c.clamp = true;
    expect_init(c, PDT_OK);
    c.u0 = R(10.0);
    expect_init(c, PDT_ERR_OUTPUT_LIMIT); /* clamped to no step at all */
    c = good(PDT_EXCITE_STEP);
    c.amplitude = R(-20.0);
    expect_init(c, PDT_ERR_OUTPUT_LIMIT);

    /* PULSE */
    c = good(PDT_EXCITE_PULSE);
    c.t_on = R(0.04);
    expect_init(c, PDT_ERR_ARG);
    c = good(PDT_EXCITE_PULSE);
    c.t_off = R(-0.1);
    expect_init(c, PDT_ERR_ARG);
    c = good(PDT_EXCITE_PULSE);
    c.t_on = R(INFINITY);
    expect_init(c, PDT_ERR_ARG);
    c = good(PDT_EXCITE_PULSE);
    c.amplitude = R(0.0);
    expect_init(c, PDT_ERR_ARG);
    c = good(PDT_EXCITE_PULSE);
    c.count = 100000;
    c.t_on = R(5000.0);
    expect_init(c, PDT_ERR_LENGTH);
    c = good(PDT_EXCITE_PULSE);
    c.amplitude = R(-10.5);
    expect_init(c, PDT_ERR_OUTPUT_LIMIT);

    /* CHIRP */
    c = good(PDT_EXCITE_CHIRP);
    c.duration = R(0.04);
    expect_init(c, PDT_ERR_ARG);
    c = good(PDT_EXCITE_CHIRP);
    c.amplitude = R(-1.0);
    expect_init(c, PDT_ERR_ARG);
    c = good(PDT_EXCITE_CHIRP);
    c.f1 = R(5.01);
    expect_init(c, PDT_ERR_ARG);
    c.f1 = R(5.0); /* Nyquist itself is allowed */
    expect_init(c, PDT_OK);
    c = good(PDT_EXCITE_CHIRP);
    c.f0 = R(-0.1);
    expect_init(c, PDT_ERR_ARG);
    c = good(PDT_EXCITE_CHIRP);
    c.f0 = R(NAN);
    expect_init(c, PDT_ERR_ARG);
    c = good(PDT_EXCITE_CHIRP);
    c.u0 = R(9.5);
    expect_init(c, PDT_ERR_OUTPUT_LIMIT); /* u0 + 1 > 10 */
    c.clamp = true;
    expect_init(c, PDT_OK);

    /* PRBS */
    c = good(PDT_EXCITE_PRBS);
    c.prbs_bits = 1;
    expect_init(c, PDT_ERR_ARG);
    c.prbs_bits = 32;
    expect_init(c, PDT_ERR_ARG);
    c.prbs_bits = 31;
    expect_init(c, PDT_OK);
    c.periods = 2;
    expect_init(c, PDT_ERR_LENGTH);
    c = good(PDT_EXCITE_PRBS);
    c.prbs_hold = 0;
    expect_init(c, PDT_ERR_ARG);
    c = good(PDT_EXCITE_PRBS);
    c.prbs_seed = 0x100; /* low 7 bits all zero */
    expect_init(c, PDT_ERR_ARG);
    c = good(PDT_EXCITE_PRBS);
    c.amplitude = R(0.0);
    expect_init(c, PDT_ERR_ARG);
    c = good(PDT_EXCITE_PRBS);
    c.u0 = R(-9.5);
    expect_init(c, PDT_ERR_OUTPUT_LIMIT);

    /* RELAY */
    c = good(PDT_EXCITE_RELAY);
    c.d = R(0.0);
    expect_init(c, PDT_ERR_ARG);
    c = good(PDT_EXCITE_RELAY);
    c.eps = R(-0.1);
    expect_init(c, PDT_ERR_ARG);
    c = good(PDT_EXCITE_RELAY);
    c.setpoint = R(NAN);
    expect_init(c, PDT_ERR_ARG);
    c = good(PDT_EXCITE_RELAY);
    c.bias = R(INFINITY);
    expect_init(c, PDT_ERR_ARG);
    c = good(PDT_EXCITE_RELAY);
    c.action = (pdt_excite_action_t)2;
    expect_init(c, PDT_ERR_ARG);
    c = good(PDT_EXCITE_RELAY);
    c.relay_cycles = 0;
    expect_init(c, PDT_ERR_ARG);
    c.relay_cycles = PDT_EXCITE_RELAY_MAX_CYCLES + 1u;
    expect_init(c, PDT_ERR_ARG);
    c.relay_cycles = PDT_EXCITE_RELAY_MAX_CYCLES;
    expect_init(c, PDT_OK);
    c = good(PDT_EXCITE_RELAY);
    c.bias = R(9.5);
    expect_init(c, PDT_ERR_OUTPUT_LIMIT);
    c.clamp = true;
    expect_init(c, PDT_OK);
    c.bias = R(20.0); /* both levels clamp to u_max */
    expect_init(c, PDT_ERR_OUTPUT_LIMIT);
}

static void test_bad_calls(void **state)
{
    (void)state;
    pdt_excite_t g;
    pdt_excite_relay_t res;
    pdt_real_t u = R(7.0);
    memset(&g, 0, sizeof g);
    assert_int_equal(pdt_excite_next(NULL, R(0.0), &u), PDT_ERR_ARG);
    assert_int_equal(pdt_excite_next(&g, R(0.0), NULL), PDT_ERR_ARG);
    assert_int_equal(pdt_excite_next(&g, R(0.0), &u), PDT_ERR_STATE);
    assert_true(u == R(7.0));
    assert_int_equal(pdt_excite_length(NULL), 0);
    assert_int_equal(pdt_excite_length(&g), 0);
    assert_int_equal(pdt_excite_relay_result(&g, &res), PDT_ERR_STATE);
    assert_int_equal(pdt_excite_relay_result(NULL, &res), PDT_ERR_ARG);

    pdt_excite_config_t c = good(PDT_EXCITE_STEP);
    assert_int_equal(pdt_excite_init(&g, &c), PDT_OK);
    assert_int_equal(pdt_excite_relay_result(&g, &res), PDT_ERR_ARG); /* not a relay */
    /* open-loop kinds ignore pv, NaN included */
    assert_int_equal(pdt_excite_next(&g, R(NAN), &u), PDT_RUNNING);
    assert_true(u == R(1.0));

    c = good(PDT_EXCITE_RELAY);
    assert_int_equal(pdt_excite_init(&g, &c), PDT_OK);
    assert_int_equal(pdt_excite_relay_result(&g, NULL), PDT_ERR_ARG);
    pdt_excite_t copy = g;
    u = R(7.0);
    assert_int_equal(pdt_excite_next(&g, R(NAN), &u), PDT_ERR_NONFINITE);
    assert_int_equal(pdt_excite_next(&g, R(-INFINITY), &u), PDT_ERR_NONFINITE);
    assert_true(u == R(7.0));
    assert_memory_equal(&g, &copy, sizeof g);
    assert_int_equal(pdt_excite_length(&g), 0);
    memset(&res, 0x5A, sizeof res);
    pdt_excite_relay_t rcopy = res;
    assert_int_equal(pdt_excite_relay_result(&g, &res), PDT_ERR_STATE);
    assert_memory_equal(&res, &rcopy, sizeof res);
}

/* After the end every kind outputs u0 and returns PDT_OK for good. */
static void test_end(void **state)
{
    (void)state;
    pdt_excite_config_t c = good(PDT_EXCITE_PULSE);
    pdt_excite_t g;
    pdt_real_t u;
    c.u0 = R(2.0);
    c.pre = R(0.2);
    c.t_on = R(0.3);
    c.t_off = R(0.0);
    c.count = 2;
    assert_int_equal(pdt_excite_init(&g, &c), PDT_OK);
    assert_int_equal(pdt_excite_length(&g), 8u);
    const pdt_real_t want[8] = {2, 2, 3, 3, 3, 3, 3, 3};
    for (int k = 0; k < 8; k++) {
        assert_int_equal(pdt_excite_next(&g, R(0.0), &u), PDT_RUNNING);
        assert_true(u == want[k]);
    }
    for (int k = 0; k < 3; k++) {
        assert_int_equal(pdt_excite_next(&g, R(0.0), &u), PDT_OK);
        assert_true(u == R(2.0));
    }
    /* STEP with a duration under half a sample lasts one sample */
    c = good(PDT_EXCITE_STEP);
    c.duration = R(0.01);
    assert_int_equal(pdt_excite_init(&g, &c), PDT_OK);
    assert_int_equal(pdt_excite_length(&g), 1u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults),        cmocka_unit_test(test_vectors),
        cmocka_unit_test(test_relay_vectors),   cmocka_unit_test(test_prbs_period_balance),
        cmocka_unit_test(test_chirp_frequency), cmocka_unit_test(test_relay_fopdt),
        cmocka_unit_test(test_relay_action),    cmocka_unit_test(test_bad_config),
        cmocka_unit_test(test_bad_calls),       cmocka_unit_test(test_end),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
