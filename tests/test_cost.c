/*
 * Tests of the cost functions against the numpy reference
 * (tests/vectors/cost_vectors.h, written by tools/vectorgen/cost.py), plus
 * properties that need no reference: exact models on clean data, Cf not
 * depending on Td, offset invariance, Parseval, workspace size and bounds,
 * and every bad-input status with outputs left untouched.
 */
#include "test_util.h"
#include "sim_rng.h"

#include "cost_vectors.h"

/* Relative tolerance against the double reference. Float: the data are
 * exact in float (quantised to 2^-12), so only the arithmetic differs; the
 * measured worst case is below 1e-5 (printed by the vector tests). */
#if PDT_REAL_DOUBLE
#define COST_RTOL 1e-9
#else
#define COST_RTOL 1e-4
#endif

#define COST_NMAX       600u
#define COST_NSETS      (sizeof cost_vec_sets / sizeof cost_vec_sets[0])
#define COST_WORK_REALS (PDT_COST_WORKSPACE_SIZE(COST_NMAX) / sizeof(pdt_real_t))
/* Long enough that N_f exceeds 2^PDT_FFT_MAX_LOG2 with delay_max = 0. */
#define COST_NLONG      (((size_t)1u << PDT_FFT_MAX_LOG2) / 2u + 2u)

static pdt_real_t g_u[COST_NMAX];
static pdt_real_t g_y[COST_NMAX];
static pdt_real_t g_w[COST_NMAX + 1u];
static pdt_real_t g_work[COST_WORK_REALS + CANARY_COUNT];
static pdt_real_t g_long[COST_NLONG];

/* Worst relative errors seen, reported at the end of each vector test. */
static double g_worst_time;
static double g_worst_freq;
static double g_worst_eval;

static void load_set(const cost_vec_set_t *s)
{
    assert_true(s->n <= COST_NMAX);
    for (size_t k = 0; k < s->n; k++) {
        g_u[k] = (pdt_real_t)s->u[k];
        g_y[k] = (pdt_real_t)s->y[k];
    }
    for (size_t k = 0; k <= s->nf / 2u; k++) {
        g_w[k] = (pdt_real_t)s->weights[k];
    }
}

static void set_config(const cost_vec_set_t *s, pdt_cost_config_t *cfg)
{
    VECTOR_COST_CONFIG(cfg, s);
    cfg->weights = g_w;
}

/* Initialises c on the loaded set with cfg, checking the workspace size and
 * that nothing is written past it. */
static void init_ok(pdt_cost_t *c, const pdt_cost_config_t *cfg, size_t n)
{
    size_t ws = pdt_cost_workspace_size(cfg, n);
    size_t reals = ws / sizeof(pdt_real_t);
    assert_true(ws <= PDT_COST_WORKSPACE_SIZE(n));
    assert_int_equal(ws % sizeof(pdt_real_t), 0);
    canary_fill(g_work + reals, CANARY_COUNT);
    assert_int_equal(pdt_cost_init(c, cfg, g_u, g_y, n, g_work, ws), PDT_OK);
    canary_check(g_work + reals, CANARY_COUNT);
}

static pdt_discrete_t dmodel_of(int order, int delay, const double *coef)
{
    return vector_dmodel(order, delay, coef);
}

static pdt_model_t model_of(const cost_vec_set_t *s, size_t i)
{
    return vector_model(s->kind[i], s->param + 4u * i);
}

static void check_cost(pdt_real_t got, double want, double rtol, double *worst, const char *set,
                       size_t cand, const char *what)
{
    double e = rel_err((double)got, want);
    if (e > *worst) {
        *worst = e;
    }
    if (!(e <= rtol)) {
        fail_msg("%s cand %zu %s: got %.17g want %.17g (rel %.3g > %.3g)", set, cand, what,
                 (double)got, want, e, rtol);
    }
}

/* ---- vectors ---- */

static void test_vectors_time(void **state)
{
    (void)state;
    g_worst_time = 0.0;
    for (size_t si = 0; si < COST_NSETS; si++) {
        const cost_vec_set_t *s = &cost_vec_sets[si];
        pdt_cost_config_t cfg;
        load_set(s);
        set_config(s, &cfg);
        cfg.use_frequency = false;
        for (int ofs = 0; ofs < 2; ofs++) {
            pdt_cost_t c;
            cfg.estimate_offset = (ofs != 0);
            init_ok(&c, &cfg, s->n);
            for (size_t i = 0; i < s->ncand; i++) {
                pdt_discrete_t df = dmodel_of(s->kind[i], s->delay_frac[i], s->coef_frac + 7u * i);
                pdt_discrete_t di = dmodel_of(s->kind[i], s->delay_int[i], s->coef_int + 7u * i);
                const double *want = s->cost + COST_NCOL * i;
                pdt_real_t v[CANARY_COUNT + 1];
                canary_fill(v + 1, CANARY_COUNT);
                assert_int_equal(pdt_cost_prediction(&c, &df, v), PDT_OK);
                check_cost(v[0], want[COST_COL_PRED_FRAC + ofs], COST_RTOL, &g_worst_time, s->name,
                           i, "prediction frac");
                assert_int_equal(pdt_cost_simulation(&c, &df, v), PDT_OK);
                check_cost(v[0], want[COST_COL_SIM_FRAC + ofs], COST_RTOL, &g_worst_time, s->name,
                           i, "simulation frac");
                assert_int_equal(pdt_cost_prediction(&c, &di, v), PDT_OK);
                check_cost(v[0], want[COST_COL_PRED_INT + ofs], COST_RTOL, &g_worst_time, s->name,
                           i, "prediction int");
                assert_int_equal(pdt_cost_simulation(&c, &di, v), PDT_OK);
                check_cost(v[0], want[COST_COL_SIM_INT + ofs], COST_RTOL, &g_worst_time, s->name, i,
                           "simulation int");
                canary_check(v + 1, CANARY_COUNT);
            }
        }
    }
    print_message("worst relative error, time costs: %.3g\n", g_worst_time);
}

static void test_vectors_frequency(void **state)
{
    static const pdt_weight_kind_t kinds[3] = {PDT_WEIGHT_UNIFORM, PDT_WEIGHT_BAND,
                                               PDT_WEIGHT_CUSTOM};
    (void)state;
    g_worst_freq = 0.0;
    for (size_t si = 0; si < COST_NSETS; si++) {
        const cost_vec_set_t *s = &cost_vec_sets[si];
        pdt_cost_config_t cfg;
        load_set(s);
        set_config(s, &cfg);
        assert_int_equal(pdt_cost_fft_size(s->n, cfg.delay_max), s->nf);
        for (int wk = 0; wk < 3; wk++) {
            pdt_cost_t c;
            cfg.weight = kinds[wk];
            init_ok(&c, &cfg, s->n);
            assert_int_equal(c.nf, s->nf);
            assert_int_equal(c.cfg.delay_max, s->delay_max);
            for (size_t i = 0; i < s->ncand; i++) {
                pdt_model_t m = model_of(s, i);
                pdt_real_t v[CANARY_COUNT + 1];
                canary_fill(v + 1, CANARY_COUNT);
                assert_int_equal(pdt_cost_frequency(&c, &m, v), PDT_OK);
                canary_check(v + 1, CANARY_COUNT);
                check_cost(v[0], s->cost[COST_NCOL * i + COST_COL_CF_UNIFORM + (size_t)wk],
                           COST_RTOL, &g_worst_freq, s->name, i, "frequency");
            }
        }
    }
    print_message("worst relative error, frequency costs: %.3g\n", g_worst_freq);
}

/* pdt_cost_eval discretises with the library's pdt_discrete_init(_int). Each
 * config is checked against one column; costs share the one workspace, so
 * each is initialised just before use. */
typedef struct eval_case {
    pdt_cost_kind_t kind;
    pdt_cost_kind_t time_kind;
    pdt_delay_mode_t mode;
    bool offset;
    bool freq;
    double phi_t, phi_f;
    pdt_weight_kind_t weight;
    int col;
    double rtol;
    const char *what;
} eval_case_t;

static void test_vectors_eval(void **state)
{
    static const eval_case_t cases[] = {
        {PDT_COST_COMBINED, PDT_COST_SIMULATION, PDT_DELAY_FRACTIONAL, true, true, COST_PHI_A_T,
         COST_PHI_A_F, PDT_WEIGHT_UNIFORM, COST_COL_COMB_A, COST_RTOL, "combined A"},
        {PDT_COST_COMBINED, PDT_COST_PREDICTION, PDT_DELAY_INTEGER, false, true, COST_PHI_B_T,
         COST_PHI_B_F, PDT_WEIGHT_BAND, COST_COL_COMB_B, COST_RTOL, "combined B"},
        {PDT_COST_SIMULATION, PDT_COST_SIMULATION, PDT_DELAY_FRACTIONAL, true, false, 1.0, 1.0,
         PDT_WEIGHT_UNIFORM, COST_COL_SIM_FRAC_OFS, COST_RTOL, "simulation frac"},
        {PDT_COST_SIMULATION, PDT_COST_SIMULATION, PDT_DELAY_INTEGER, false, false, 1.0, 1.0,
         PDT_WEIGHT_UNIFORM, COST_COL_SIM_INT, COST_RTOL, "simulation int"},
        {PDT_COST_PREDICTION, PDT_COST_SIMULATION, PDT_DELAY_INTEGER, false, false, 1.0, 1.0,
         PDT_WEIGHT_UNIFORM, COST_COL_PRED_INT, COST_RTOL, "prediction int"},
        {PDT_COST_PREDICTION, PDT_COST_SIMULATION, PDT_DELAY_FRACTIONAL, true, false, 1.0, 1.0,
         PDT_WEIGHT_UNIFORM, COST_COL_PRED_FRAC_OFS, COST_RTOL, "prediction frac"},
        /* Cf needs no discretisation: the tight tolerance holds. */
        {PDT_COST_FREQUENCY, PDT_COST_SIMULATION, PDT_DELAY_FRACTIONAL, true, true, 1.0, 1.0,
         PDT_WEIGHT_CUSTOM, COST_COL_CF_CUSTOM, COST_RTOL, "frequency"},
        /* A zero weight drops its term. */
        {PDT_COST_COMBINED, PDT_COST_SIMULATION, PDT_DELAY_FRACTIONAL, false, true, 0.0, 1.0,
         PDT_WEIGHT_BAND, COST_COL_CF_BAND, COST_RTOL, "combined phi_t = 0"},
        {PDT_COST_COMBINED, PDT_COST_PREDICTION, PDT_DELAY_INTEGER, true, true, 1.0, 0.0,
         PDT_WEIGHT_BAND, COST_COL_PRED_INT_OFS, COST_RTOL, "combined phi_f = 0"},
    };
    (void)state;
    g_worst_eval = 0.0;
    for (size_t si = 0; si < COST_NSETS; si++) {
        const cost_vec_set_t *s = &cost_vec_sets[si];
        load_set(s);
        for (size_t ci = 0; ci < sizeof cases / sizeof cases[0]; ci++) {
            const eval_case_t *e = &cases[ci];
            pdt_cost_config_t cfg;
            pdt_cost_t c;
            set_config(s, &cfg);
            cfg.kind = e->kind;
            cfg.time_kind = e->time_kind;
            cfg.delay_mode = e->mode;
            cfg.estimate_offset = e->offset;
            cfg.use_frequency = e->freq;
            cfg.phi_t = (pdt_real_t)e->phi_t;
            cfg.phi_f = (pdt_real_t)e->phi_f;
            cfg.weight = e->weight;
            init_ok(&c, &cfg, s->n);
            for (size_t i = 0; i < s->ncand; i++) {
                pdt_model_t m = model_of(s, i);
                pdt_real_t v[CANARY_COUNT + 1];
                canary_fill(v + 1, CANARY_COUNT);
                assert_int_equal(pdt_cost_eval(&c, &m, v), PDT_OK);
                canary_check(v + 1, CANARY_COUNT);
                check_cost(v[0], s->cost[COST_NCOL * i + (size_t)e->col], e->rtol, &g_worst_eval,
                           s->name, i, e->what);
            }
        }
    }
    print_message("worst relative error, pdt_cost_eval: %.3g\n", g_worst_eval);
}

/* ---- properties ---- */

/* Deterministic input: steps held 5..14 samples at pseudo-random levels. */
static void make_input(pdt_real_t *u, size_t n, pdt_real_t u0, uint32_t seed)
{
    sim_rng64_t x = sim_rng64_seed(seed);
    size_t k = 0;
    while (k < n) {
        const uint64_t v = sim_rng64_next(&x);
        size_t hold = 5u + (size_t)((v >> 16) % 10u);
        pdt_real_t level = u0 + (pdt_real_t)((int)((v >> 8) & 0xFFu) - 128) / ((pdt_real_t)16.0);
        for (size_t j = 0; j < hold && k < n; j++, k++) {
            u[k] = level;
        }
    }
}

/* y = y0 + simulation of d from rest on u - u0, direct form in double. */
static void simulate_ref(const pdt_discrete_t *d, const pdt_real_t *u, pdt_real_t u0, pdt_real_t y0,
                         size_t n, pdt_real_t *y)
{
    double y1 = 0.0;
    double y2 = 0.0;
    double a0 = (double)d->a[0];
    double a1 = d->order == 2 ? (double)d->a[1] : 0.0;
    for (size_t k = 0; k < n; k++) {
        double v = -a0 * y1 - a1 * y2;
        for (size_t j = 0; j < 3; j++) {
            size_t back = d->delay + 1u + j;
            if (k >= back) {
                v += (double)d->b[j] * ((double)u[k - back] - (double)u0);
            }
        }
        y[k] = (pdt_real_t)((double)y0 + v);
        y2 = y1;
        y1 = v;
    }
}

static pdt_discrete_t fopdt_dmodel(double K, double tau, double Ts, size_t delay)
{
    pdt_discrete_t d;
    double p = exp(-Ts / tau);
    memset(&d, 0, sizeof d);
    d.order = 1;
    d.delay = delay;
    d.a[0] = (pdt_real_t)-p;
    d.b[0] = (pdt_real_t)(K * -expm1(-Ts / tau));
    d.d[0] = (pdt_real_t)-expm1(-Ts / tau);
    return d;
}

/* Underdamped pair r e^{+-i th}, fractional-like three-term numerator. */
static pdt_discrete_t sopdt_dmodel(double r, double th, size_t delay)
{
    pdt_discrete_t d;
    memset(&d, 0, sizeof d);
    d.order = 2;
    d.delay = delay;
    d.a[0] = (pdt_real_t)(-2.0 * r * cos(th));
    d.a[1] = (pdt_real_t)(r * r);
    d.d[0] = (pdt_real_t)(2.0 - 2.0 * r * cos(th));
    d.d[1] = (pdt_real_t)(1.0 - 2.0 * r * cos(th) + r * r);
    d.b[0] = ((pdt_real_t)0.01);
    d.b[1] = ((pdt_real_t)0.03);
    d.b[2] = ((pdt_real_t)0.005);
    return d;
}

static double mean_square_dev(const pdt_real_t *y, pdt_real_t y0, size_t n)
{
    double s = 0.0;
    for (size_t k = 0; k < n; k++) {
        double e = (double)y[k] - (double)y0;
        s += e * e;
    }
    return s / (double)n;
}

static void test_exact_model_zero_cost(void **state)
{
    const size_t n = 500;
    const pdt_real_t u0 = ((pdt_real_t)12.5);
    const pdt_real_t y0 = ((pdt_real_t)-40.0);
    pdt_discrete_t models[2];
    (void)state;
    models[0] = fopdt_dmodel(2.5, 4.0, 0.1, 7);
    models[1] = sopdt_dmodel(0.97, 0.12, 3);
    make_input(g_u, n, u0, 12345u);
    for (size_t mi = 0; mi < 2; mi++) {
        const pdt_discrete_t *d = &models[mi];
        pdt_cost_config_t cfg;
        double power;
        simulate_ref(d, g_u, u0, y0, n, g_y);
        power = mean_square_dev(g_y, y0, n);
        pdt_cost_config_default(&cfg);
        cfg.Ts = ((pdt_real_t)0.1);
        cfg.u0 = u0;
        cfg.y0 = y0;
        cfg.delay_max = 20;
        cfg.use_frequency = false;
        for (int ofs = 0; ofs < 2; ofs++) {
            pdt_cost_t c;
            pdt_real_t vp, vs;
            cfg.estimate_offset = (ofs != 0);
            init_ok(&c, &cfg, n);
            assert_int_equal(pdt_cost_prediction(&c, d, &vp), PDT_OK);
            assert_int_equal(pdt_cost_simulation(&c, d, &vs), PDT_OK);
            /* Float: y was rounded to float, so residuals of a few ulps of
             * y remain: a cost near eps^2 times the signal power. */
            assert_true((double)vp <= (PDT_REAL_DOUBLE ? 1e-24 : 1e-11) * power);
            assert_true((double)vs <= (PDT_REAL_DOUBLE ? 1e-24 : 1e-11) * power);
            assert_true(vp >= ((pdt_real_t)0.0) && vs >= ((pdt_real_t)0.0));
        }
    }
}

/* 8000 samples around a large operating point: the blocked sums keep the
 * float costs close to a double computation of the same model on the same
 * (float) data. */
#define COST_NBIG 8000u
static pdt_real_t g_ubig[COST_NBIG];
static pdt_real_t g_ybig[COST_NBIG];
static pdt_real_t g_workbig[2u * COST_NBIG];

static double time_cost_double(const pdt_discrete_t *d, const pdt_real_t *u, const pdt_real_t *y,
                               double u0, double y0, size_t n, size_t lu, bool sim, bool ofs)
{
    double ys = 0.0, dys = 0.0, s1 = 0.0, s2 = 0.0;
    size_t k0 = lu + d->order;
    for (size_t k = 0; k < n; k++) {
        double bu = 0.0;
        double r;
        for (size_t j = 0; j < 3; j++) {
            size_t back = d->delay + 1u + j;
            if (k >= back) {
                bu += (double)d->b[j] * ((double)u[k - back] - u0);
            }
        }
        if (d->order == 1) {
            ys += bu - (double)d->d[0] * ys;
        } else {
            double ys2 = ys - dys;
            dys += bu - (double)d->d[0] * dys - (double)d->d[1] * ys2;
            ys += dys;
        }
        if (k < k0) {
            continue;
        }
        if (sim) {
            r = ((double)y[k] - y0) - ys;
        } else if (d->order == 1) {
            r = ((double)y[k] - y0) - (1.0 - (double)d->d[0]) * ((double)y[k - 1] - y0) - bu;
        } else {
            double y1 = (double)y[k - 1] - y0, y2 = (double)y[k - 2] - y0;
            r = ((double)y[k] - y0) - (2.0 - (double)d->d[0]) * y1 -
                ((double)d->d[0] - 1.0 - (double)d->d[1]) * y2 - bu;
        }
        s1 += r;
        s2 += r * r;
    }
    s1 /= (double)(n - k0);
    s2 /= (double)(n - k0);
    return ofs ? s2 - s1 * s1 : s2;
}

static void test_long_record_accuracy(void **state)
{
    const pdt_real_t u0 = (pdt_real_t)250.0;
    const pdt_real_t y0 = (pdt_real_t)1000.0;
    const size_t lu = 50;
    pdt_discrete_t models[2];
    sim_rng64_t x = sim_rng64_seed(777u);
    double worst = 0.0;
    (void)state;
    models[0] = fopdt_dmodel(2.5, 4.0, 0.1, 7);
    models[1] = sopdt_dmodel(0.97, 0.12, 3);
    make_input(g_ubig, COST_NBIG, u0, 4242u);
    for (size_t mi = 0; mi < 2; mi++) {
        pdt_discrete_t truth = models[mi];
        pdt_discrete_t off = truth;
        pdt_cost_config_t cfg;
        simulate_ref(&truth, g_ubig, u0, y0, COST_NBIG, g_ybig);
        for (size_t k = 0; k < COST_NBIG; k++) {
            g_ybig[k] += (pdt_real_t)(sim_rng64_uniform(&x) - 0.5) * (pdt_real_t)0.02;
        }
        off.b[0] *= (pdt_real_t)1.05;
        pdt_cost_config_default(&cfg);
        cfg.Ts = (pdt_real_t)0.1;
        cfg.u0 = u0;
        cfg.y0 = y0;
        cfg.delay_max = lu;
        cfg.use_frequency = false;
        for (int ofs = 0; ofs < 2; ofs++) {
            pdt_cost_t c;
            cfg.estimate_offset = (ofs != 0);
            assert_int_equal(
                pdt_cost_init(&c, &cfg, g_ubig, g_ybig, COST_NBIG, g_workbig, sizeof g_workbig),
                PDT_OK);
            for (int which = 0; which < 4; which++) {
                const pdt_discrete_t *d = (which & 1) ? &off : &truth;
                bool sim = (which & 2) != 0;
                pdt_real_t v;
                double want = time_cost_double(d, g_ubig, g_ybig, (double)u0, (double)y0, COST_NBIG,
                                               lu, sim, ofs != 0);
                assert_int_equal(
                    sim ? pdt_cost_simulation(&c, d, &v) : pdt_cost_prediction(&c, d, &v), PDT_OK);
                worst = fmax(worst, rel_err((double)v, want));
                assert_close(v, want, COST_RTOL, 0.0);
            }
        }
    }
    print_message("worst relative error, 8000 samples: %.3g\n", worst);
}

static void test_frequency_ignores_dead_time(void **state)
{
    const cost_vec_set_t *s = &cost_vec_sets[1];
    pdt_cost_config_t cfg;
    pdt_cost_t c;
    pdt_real_t v0, v1;
    (void)state;
    load_set(s);
    set_config(s, &cfg);
    init_ok(&c, &cfg, s->n);
    for (size_t i = 0; i < s->ncand; i++) {
        pdt_model_t m = model_of(s, i);
        assert_int_equal(pdt_cost_frequency(&c, &m, &v0), PDT_OK);
        for (int j = 0; j < 3; j++) {
            static const pdt_real_t tds[3] = {((pdt_real_t)0.0), ((pdt_real_t)0.37),
                                              ((pdt_real_t)1000.0)};
            if (m.kind == PDT_MODEL_FOPDT) {
                m.p.fopdt.Td = tds[j];
            } else {
                m.p.sopdt.Td = tds[j];
            }
            assert_int_equal(pdt_cost_frequency(&c, &m, &v1), PDT_OK);
            assert_true(v1 == v0);
        }
    }
}

static void test_offset_invariance(void **state)
{
    const cost_vec_set_t *s = &cost_vec_sets[0];
    const pdt_real_t shift = ((pdt_real_t)7.25); /* exact in float at these levels */
    pdt_cost_config_t cfg;
    (void)state;
    load_set(s);
    set_config(s, &cfg);
    cfg.use_frequency = false;
    for (size_t i = 0; i < s->ncand; i++) {
        pdt_discrete_t d = dmodel_of(s->kind[i], s->delay_frac[i], s->coef_frac + 7u * i);
        pdt_real_t p0, q0, p1, q1, r0, r1;
        pdt_cost_t c;
        load_set(s);
        cfg.estimate_offset = true;
        init_ok(&c, &cfg, s->n);
        assert_int_equal(pdt_cost_prediction(&c, &d, &p0), PDT_OK);
        assert_int_equal(pdt_cost_simulation(&c, &d, &q0), PDT_OK);
        cfg.estimate_offset = false;
        init_ok(&c, &cfg, s->n);
        assert_int_equal(pdt_cost_simulation(&c, &d, &r0), PDT_OK);
        for (size_t k = 0; k < s->n; k++) {
            g_y[k] += shift;
        }
        cfg.estimate_offset = true;
        init_ok(&c, &cfg, s->n);
        assert_int_equal(pdt_cost_prediction(&c, &d, &p1), PDT_OK);
        assert_int_equal(pdt_cost_simulation(&c, &d, &q1), PDT_OK);
        /* The prediction residual moves by d0 * shift (a constant) only
         * through its level: removed by the offset fit. */
        assert_close(p1, p0, COST_RTOL, 0.0);
        assert_close(q1, q0, COST_RTOL, 0.0);
        cfg.estimate_offset = false;
        init_ok(&c, &cfg, s->n);
        assert_int_equal(pdt_cost_simulation(&c, &d, &r1), PDT_OK);
        if (i == 0) {
            /* The truth leaves a near zero-mean residual, so without the
             * offset fit the cost grows by about shift^2. */
            assert_close(r1, (double)r0 + 7.25 * 7.25, 0.0, 0.1);
        }
    }
}

static void test_parseval(void **state)
{
    (void)state;
    for (size_t si = 0; si < COST_NSETS; si++) {
        const cost_vec_set_t *s = &cost_vec_sets[si];
        pdt_cost_config_t cfg;
        pdt_cost_t c;
        pdt_model_t m;
        pdt_real_t v;
        double s1 = 0.0, s2 = 0.0, want;
        load_set(s);
        set_config(s, &cfg);
        init_ok(&c, &cfg, s->n);
        memset(&m, 0, sizeof m);
        m.kind = PDT_MODEL_FOPDT;
        m.p.fopdt.K = ((pdt_real_t)0.0);
        m.p.fopdt.tau = ((pdt_real_t)1.0);
        assert_int_equal(pdt_cost_frequency(&c, &m, &v), PDT_OK);
        for (size_t k = 0; k < s->n; k++) {
            double e = (double)g_y[k] - (double)(pdt_real_t)s->y0;
            s1 += e;
            s2 += e * e;
        }
        want = (s2 - s1 * s1 / (double)s->nf) / (double)s->n;
        assert_close(v, want, COST_RTOL, 0.0);
    }
}

static void test_weights(void **state)
{
    const cost_vec_set_t *s = &cost_vec_sets[3];
    pdt_cost_config_t cfg;
    pdt_cost_t c;
    pdt_model_t m = model_of(s, 1);
    pdt_real_t v0, v1;
    (void)state;
    load_set(s);
    set_config(s, &cfg);
    cfg.weight = PDT_WEIGHT_CUSTOM;
    init_ok(&c, &cfg, s->n);
    assert_int_equal(pdt_cost_frequency(&c, &m, &v0), PDT_OK);
    /* weights[0] (DC) is ignored, and the array is not read after init. */
    g_w[0] = ((pdt_real_t)1e6);
    init_ok(&c, &cfg, s->n);
    g_w[1] = ((pdt_real_t)1e6);
    assert_int_equal(pdt_cost_frequency(&c, &m, &v1), PDT_OK);
    assert_true(v0 == v1);
    /* A band between two bins, or beyond Nyquist, scores nothing. */
    cfg.weight = PDT_WEIGHT_BAND;
    cfg.f_lo = (pdt_real_t)(2.2 / ((double)s->nf * s->Ts));
    cfg.f_hi = (pdt_real_t)(2.8 / ((double)s->nf * s->Ts));
    init_ok(&c, &cfg, s->n);
    assert_int_equal(pdt_cost_frequency(&c, &m, &v1), PDT_OK);
    assert_true(v1 == ((pdt_real_t)0.0));
    cfg.f_lo = ((pdt_real_t)100.0);
    cfg.f_hi = ((pdt_real_t)200.0);
    init_ok(&c, &cfg, s->n);
    assert_int_equal(pdt_cost_frequency(&c, &m, &v1), PDT_OK);
    assert_true(v1 == ((pdt_real_t)0.0));
    /* A band over every bin is the uniform weight. */
    cfg.f_lo = ((pdt_real_t)0.0);
    cfg.f_hi = ((pdt_real_t)100.0);
    init_ok(&c, &cfg, s->n);
    assert_int_equal(pdt_cost_frequency(&c, &m, &v1), PDT_OK);
    assert_close(v1, s->cost[COST_NCOL * 1u + COST_COL_CF_UNIFORM], COST_RTOL, 0.0);
}

static void test_fft_size_and_workspace(void **state)
{
    static const size_t ns[] = {18, 20, 33, 64, 100, 255, 256, 257, 300, 513, 600};
    pdt_cost_config_t cfg;
    (void)state;
    assert_int_equal(pdt_cost_fft_size(300, 40), 1024);
    assert_int_equal(pdt_cost_fft_size(600, PDT_DELAY_HALF), 1024);
    assert_int_equal(pdt_cost_fft_size(2000, PDT_DELAY_HALF), 2048);
    assert_int_equal(pdt_cost_fft_size(20, 0), 64);
    assert_int_equal(pdt_cost_fft_size(20, 15), 32);
    assert_int_equal(pdt_cost_fft_size(20, 19), 32);
    assert_int_equal(pdt_cost_fft_size(1, 0), 16);
    assert_int_equal(pdt_cost_fft_size(0, 0), 0);
    assert_int_equal(pdt_cost_fft_size(100, 100), 0);
    assert_int_equal(pdt_cost_fft_size(COST_NLONG - 1u, 0), (size_t)1u << PDT_FFT_MAX_LOG2);
    assert_int_equal(pdt_cost_fft_size(COST_NLONG, 0), 0);
    assert_int_equal(pdt_cost_fft_size(COST_NLONG, COST_NLONG / 2u),
                     (size_t)1u << PDT_FFT_MAX_LOG2);
    assert_int_equal(PDT_COST_FFT_SIZE_MAX(COST_NLONG - 1u), (size_t)1u << PDT_FFT_MAX_LOG2);
    assert_int_equal(PDT_COST_FFT_SIZE_MAX(COST_NLONG), 0);

    pdt_cost_config_default(&cfg);
    cfg.Ts = ((pdt_real_t)1.0);
    assert_int_equal(pdt_cost_workspace_size(NULL, 100), 0);
    assert_int_equal(pdt_cost_workspace_size(&cfg, 0), 0);
    for (size_t i = 0; i < sizeof ns / sizeof ns[0]; i++) {
        size_t n = ns[i];
        size_t nf;
        cfg.delay_max = 0;
        nf = pdt_cost_fft_size(n, 0);
        assert_int_equal(PDT_COST_FFT_SIZE_MAX(n), nf);
        assert_int_equal(pdt_cost_workspace_size(&cfg, n), PDT_COST_WORKSPACE_SIZE(n));
        assert_int_equal(pdt_cost_workspace_size(&cfg, n),
                         (2u * n + 3u * (nf / 2u)) * sizeof(pdt_real_t) +
                             pdt_fft_workspace_size(nf));
        for (size_t lu = 1; lu < n; lu += 1u + n / 7u) {
            cfg.delay_max = lu;
            assert_true(pdt_cost_workspace_size(&cfg, n) <= PDT_COST_WORKSPACE_SIZE(n));
        }
        cfg.delay_max = PDT_DELAY_HALF;
        assert_true(pdt_cost_workspace_size(&cfg, n) <= PDT_COST_WORKSPACE_SIZE(n));
    }
    cfg.use_frequency = false;
    assert_int_equal(pdt_cost_workspace_size(&cfg, 300), 600u * sizeof(pdt_real_t));
}

/* The exact workspace suffices, one byte less does not, and init writes
 * nothing past it (init_ok checks the canaries). */
static void test_workspace_exact(void **state)
{
    const cost_vec_set_t *s = &cost_vec_sets[1];
    pdt_cost_config_t cfg;
    pdt_cost_t c;
    size_t ws;
    (void)state;
    load_set(s);
    set_config(s, &cfg);
    cfg.delay_max = 0;
    ws = pdt_cost_workspace_size(&cfg, s->n);
    assert_int_equal(ws, PDT_COST_WORKSPACE_SIZE(s->n));
    canary_fill(g_work, COST_WORK_REALS + CANARY_COUNT);
    assert_int_equal(pdt_cost_init(&c, &cfg, g_u, g_y, s->n, g_work, ws - 1u), PDT_ERR_NOMEM);
    canary_check(g_work, COST_WORK_REALS + CANARY_COUNT);
    init_ok(&c, &cfg, s->n);
    /* Without use_frequency only the normalised record is needed. */
    cfg.use_frequency = false;
    ws = pdt_cost_workspace_size(&cfg, s->n);
    assert_int_equal(ws, 2u * s->n * sizeof(pdt_real_t));
    assert_int_equal(pdt_cost_init(&c, &cfg, g_u, g_y, s->n, g_work, ws - 1u), PDT_ERR_NOMEM);
    assert_int_equal(pdt_cost_init(&c, &cfg, g_u, g_y, s->n, NULL, 0), PDT_ERR_NOMEM);
    assert_int_equal(pdt_cost_init(&c, &cfg, g_u, g_y, s->n, g_work, ws), PDT_OK);
    assert_int_equal(c.nf, 0);
}

static void test_diverging_model(void **state)
{
    const cost_vec_set_t *s = &cost_vec_sets[0];
    pdt_cost_config_t cfg;
    pdt_cost_t c;
    pdt_discrete_t d = fopdt_dmodel(1.0, 1.0, 0.1, 3);
    pdt_real_t v;
    (void)state;
    load_set(s);
    set_config(s, &cfg);
    cfg.use_frequency = false;
    d.d[0] = ((pdt_real_t)-999.0); /* pole at 1000: overflows even a double */
    for (int ofs = 0; ofs < 2; ofs++) {
        cfg.estimate_offset = (ofs != 0);
        init_ok(&c, &cfg, s->n);
        assert_int_equal(pdt_cost_simulation(&c, &d, &v), PDT_OK);
        assert_true(isinf(v) && v > ((pdt_real_t)0.0));
    }
}

/* ---- bad inputs ---- */

static void fill_pattern(void *p, size_t n)
{
    memset(p, 0xA5, n);
}

static void assert_pattern(const void *p, size_t n)
{
    const unsigned char *b = (const unsigned char *)p;
    for (size_t i = 0; i < n; i++) {
        if (b[i] != 0xA5u) {
            fail_msg("byte %zu of an output changed on error", i);
        }
    }
}

/* Expects init to fail with want and leave c and the workspace untouched. */
static void init_fails(const pdt_cost_config_t *cfg, const pdt_real_t *u, const pdt_real_t *y,
                       size_t n, void *work, size_t len, pdt_status_t want, int line)
{
    pdt_cost_t c;
    pdt_status_t got;
    fill_pattern(&c, sizeof c);
    canary_fill(g_work, COST_WORK_REALS + CANARY_COUNT);
    got = pdt_cost_init(&c, cfg, u, y, n, work, len);
    if (got != want) {
        fail_msg("line %d: status %d, want %d", line, (int)got, (int)want);
    }
    assert_pattern(&c, sizeof c);
    canary_check(g_work, COST_WORK_REALS + CANARY_COUNT);
}

#define INIT_FAILS(cfg, n, want)                                                                   \
    init_fails((cfg), g_u, g_y, (n), g_work, sizeof g_work, (want), __LINE__)

/* pdt_cost_fit: finite for a candidate and for a model far off, refusals
 * leave the output; pdt_cost_units maps exactly. */
static void test_fit_and_units(void **state)
{
    const cost_vec_set_t *s = &cost_vec_sets[0];
    pdt_cost_config_t cfg;
    pdt_cost_t c;
    pdt_model_t m = vector_model(s->kind[0], s->param);
    pdt_real_t fit = (pdt_real_t)-7.0;
    static pdt_real_t scratch[COST_NMAX];
    (void)state;
    load_set(s);
    set_config(s, &cfg);
    init_ok(&c, &cfg, s->n);
    assert_int_equal(pdt_cost_fit(&c, &m, 0, scratch, &fit), PDT_OK);
    assert_true(isfinite((double)fit) && fit <= (pdt_real_t)100.0);
    if (m.kind == PDT_MODEL_FOPDT) {
        m.p.fopdt.K = (pdt_real_t)1e30;
    } else {
        m.p.sopdt.k = (pdt_real_t)1e30;
    }
    assert_int_equal(pdt_cost_fit(&c, &m, 0, scratch, &fit), PDT_OK);
    assert_true(isfinite((double)fit) && fit < (pdt_real_t)0.0);
    fit = (pdt_real_t)-7.0;
    assert_int_equal(pdt_cost_fit(NULL, &m, 0, scratch, &fit), PDT_ERR_ARG);
    assert_int_equal(pdt_cost_fit(&c, NULL, 0, scratch, &fit), PDT_ERR_ARG);
    assert_int_equal(pdt_cost_fit(&c, &m, 0, NULL, &fit), PDT_ERR_ARG);
    assert_int_equal(pdt_cost_fit(&c, &m, (pdt_real_t)NAN, scratch, &fit), PDT_ERR_ARG);
    m.kind = (pdt_model_kind_t)99;
    assert_int_equal(pdt_cost_fit(&c, &m, 0, scratch, &fit), PDT_ERR_ARG);
    assert_true(fit == (pdt_real_t)-7.0);
    assert_true(pdt_cost_units(NULL, (pdt_real_t)3.0) == (pdt_real_t)3.0);
    assert_true((double)pdt_cost_units(&c, (pdt_real_t)0.75) == ldexp(0.75, 2 * c.y_exp));
}

static void test_init_errors(void **state)
{
    const cost_vec_set_t *s = &cost_vec_sets[0];
    const size_t n = s->n;
    pdt_cost_config_t good, cfg;
    pdt_cost_t c;
    (void)state;
    load_set(s);
    set_config(s, &good);
    good.weight = PDT_WEIGHT_CUSTOM;
    init_ok(&c, &good, n);

    /* PDT_ERR_ARG */
    init_fails(NULL, g_u, g_y, n, g_work, sizeof g_work, PDT_ERR_ARG, __LINE__);
    init_fails(&good, NULL, g_y, n, g_work, sizeof g_work, PDT_ERR_ARG, __LINE__);
    init_fails(&good, g_u, NULL, n, g_work, sizeof g_work, PDT_ERR_ARG, __LINE__);
    assert_int_equal(pdt_cost_init(NULL, &good, g_u, g_y, n, g_work, sizeof g_work), PDT_ERR_ARG);
    {
        static const pdt_real_t bad_ts[4] = {((pdt_real_t)0.0), ((pdt_real_t)-0.1), (pdt_real_t)NAN,
                                             (pdt_real_t)INFINITY};
        for (int i = 0; i < 4; i++) {
            cfg = good;
            cfg.Ts = bad_ts[i];
            INIT_FAILS(&cfg, n, PDT_ERR_ARG);
        }
    }
    cfg = good; /* the smallest subnormal: 2 pi / (N_f Ts) overflows */
    cfg.Ts = (pdt_real_t)(PDT_REAL_DOUBLE ? 4.9406564584124654e-324 : 1.4012984643e-45);
    INIT_FAILS(&cfg, n, PDT_ERR_ARG);
    cfg = good;
    cfg.kind = (pdt_cost_kind_t)7;
    INIT_FAILS(&cfg, n, PDT_ERR_ARG);
    cfg = good;
    cfg.time_kind = PDT_COST_FREQUENCY;
    INIT_FAILS(&cfg, n, PDT_ERR_ARG);
    cfg = good;
    cfg.time_kind = (pdt_cost_kind_t)-1;
    INIT_FAILS(&cfg, n, PDT_ERR_ARG);
    cfg = good;
    cfg.delay_mode = (pdt_delay_mode_t)5;
    INIT_FAILS(&cfg, n, PDT_ERR_ARG);
    cfg = good;
    cfg.weight = (pdt_weight_kind_t)9;
    INIT_FAILS(&cfg, n, PDT_ERR_ARG);
    /* The identification's CONTROL and AUTO (3 and 4) are its own to
     * resolve into a band or UNIFORM: the cost has no model to take a band
     * from. Refused with or without spectra, as any weighting it does not
     * know. */
    {
        static const pdt_weight_kind_t ident_only[2] = {(pdt_weight_kind_t)3, (pdt_weight_kind_t)4};
        for (int i = 0; i < 2; i++) {
            cfg = good;
            cfg.weight = ident_only[i];
            INIT_FAILS(&cfg, n, PDT_ERR_ARG);
            cfg.kind = PDT_COST_FREQUENCY;
            INIT_FAILS(&cfg, n, PDT_ERR_ARG);
            cfg.kind = PDT_COST_SIMULATION;
            cfg.use_frequency = false;
            INIT_FAILS(&cfg, n, PDT_ERR_ARG);
        }
    }
    cfg = good;
    cfg.phi_t = ((pdt_real_t)-1.0);
    INIT_FAILS(&cfg, n, PDT_ERR_ARG);
    cfg = good;
    cfg.phi_t = (pdt_real_t)NAN;
    INIT_FAILS(&cfg, n, PDT_ERR_ARG);
    cfg = good;
    cfg.phi_f = (pdt_real_t)INFINITY;
    INIT_FAILS(&cfg, n, PDT_ERR_ARG);
    cfg = good;
    cfg.f_lo = ((pdt_real_t)-1.0);
    INIT_FAILS(&cfg, n, PDT_ERR_ARG);
    cfg = good;
    cfg.f_hi = (pdt_real_t)NAN;
    INIT_FAILS(&cfg, n, PDT_ERR_ARG);
    cfg = good;
    cfg.weights = NULL;
    INIT_FAILS(&cfg, n, PDT_ERR_ARG);
    cfg.use_frequency = false; /* CUSTOM still needs its weights */
    INIT_FAILS(&cfg, n, PDT_ERR_ARG);
    cfg = good;
    g_w[5] = ((pdt_real_t)-0.5);
    INIT_FAILS(&cfg, n, PDT_ERR_ARG);
    g_w[5] = (pdt_real_t)NAN;
    INIT_FAILS(&cfg, n, PDT_ERR_ARG);
    g_w[0] = (pdt_real_t)INFINITY;
    g_w[5] = ((pdt_real_t)0.0);
    INIT_FAILS(&cfg, n, PDT_ERR_ARG);
    cfg.use_frequency = false; /* values unused without spectra */
    init_ok(&c, &cfg, n);
    load_set(s);
    init_fails(&good, g_u, g_y, n, (char *)g_work + 1, sizeof g_work - 1u, PDT_ERR_ARG, __LINE__);

    /* PDT_ERR_TOO_SHORT */
    cfg = good;
    cfg.delay_max = n;
    INIT_FAILS(&cfg, n, PDT_ERR_TOO_SHORT);
    cfg.delay_max = n - 2u - PDT_MIN_SAMPLES + 1u;
    INIT_FAILS(&cfg, n, PDT_ERR_TOO_SHORT);
    cfg.delay_max = n - 2u - PDT_MIN_SAMPLES;
    init_ok(&c, &cfg, n);
    cfg.delay_max = PDT_DELAY_HALF;
    INIT_FAILS(&cfg, 0, PDT_ERR_TOO_SHORT);
    INIT_FAILS(&cfg, 2u * (PDT_MIN_SAMPLES + 2u) - 2u, PDT_ERR_TOO_SHORT);
    init_ok(&c, &cfg, 2u * (PDT_MIN_SAMPLES + 2u) - 1u);
    cfg.delay_max = 0;
    INIT_FAILS(&cfg, PDT_MIN_SAMPLES + 1u, PDT_ERR_TOO_SHORT);

    /* PDT_ERR_BOUNDS */
    cfg = good;
    cfg.delay_min = s->delay_max + 1u;
    INIT_FAILS(&cfg, n, PDT_ERR_BOUNDS);
    cfg.delay_min = s->delay_max;
    init_ok(&c, &cfg, n);
    cfg = good;
    cfg.f_lo = ((pdt_real_t)2.0);
    cfg.f_hi = ((pdt_real_t)1.0);
    INIT_FAILS(&cfg, n, PDT_ERR_BOUNDS);

    /* PDT_ERR_NONFINITE */
    cfg = good;
    cfg.u0 = (pdt_real_t)NAN;
    INIT_FAILS(&cfg, n, PDT_ERR_NONFINITE);
    cfg = good;
    cfg.y0 = (pdt_real_t)-INFINITY;
    INIT_FAILS(&cfg, n, PDT_ERR_NONFINITE);
    g_u[5] = (pdt_real_t)NAN;
    INIT_FAILS(&good, n, PDT_ERR_NONFINITE);
    load_set(s);
    g_y[n - 1u] = (pdt_real_t)INFINITY;
    INIT_FAILS(&good, n, PDT_ERR_NONFINITE);
    load_set(s);

    /* PDT_ERR_OUTLIER: a bad-value cell, named by pdt_cost_outlier; it is
     * checked before the operating point a level over it would spoil, and
     * after NaN and infinity. */
    g_y[7] = (pdt_real_t)1e20;
    INIT_FAILS(&good, n, PDT_ERR_OUTLIER);
    assert_int_equal(pdt_cost_outlier(g_y, n), 7u);
    cfg = good;
    cfg.y0 = (pdt_real_t)INFINITY;
    INIT_FAILS(&cfg, n, PDT_ERR_OUTLIER);
    g_u[3] = (pdt_real_t)NAN;
    INIT_FAILS(&good, n, PDT_ERR_NONFINITE);
    load_set(s);
    g_u[n / 2u] = (pdt_real_t)-3e38;
    INIT_FAILS(&good, n, PDT_ERR_OUTLIER);
    assert_int_equal(pdt_cost_outlier(g_u, n), n / 2u);
    assert_int_equal(pdt_cost_outlier(g_y, n), n);
    load_set(s);

    /* PDT_ERR_LENGTH: N_f would pass 2^PDT_FFT_MAX_LOG2. */
    cfg = good;
    cfg.weight = PDT_WEIGHT_UNIFORM;
    cfg.delay_max = 0;
    for (size_t k = 0; k < COST_NLONG; k++) {
        g_long[k] = (pdt_real_t)(k % 7u);
    }
    init_fails(&cfg, g_long, g_long, COST_NLONG, g_work, sizeof g_work, PDT_ERR_LENGTH, __LINE__);
    /* Without spectra a long record needs only its normalised copy. */
    cfg.use_frequency = false;
    assert_int_equal(pdt_cost_workspace_size(&cfg, COST_NLONG),
                     2u * COST_NLONG * sizeof(pdt_real_t));
    assert_int_equal(pdt_cost_init(&c, &cfg, g_long, g_long, COST_NLONG, NULL, 0), PDT_ERR_NOMEM);

    /* PDT_ERR_NOMEM */
    init_fails(&good, g_u, g_y, n, NULL, sizeof g_work, PDT_ERR_NOMEM, __LINE__);
    init_fails(&good, g_u, g_y, n, g_work, pdt_cost_workspace_size(&good, n) - 1u, PDT_ERR_NOMEM,
               __LINE__);
    init_fails(&good, g_u, g_y, n, g_work, 0, PDT_ERR_NOMEM, __LINE__);
}

static void test_eval_errors(void **state)
{
    const cost_vec_set_t *s = &cost_vec_sets[0];
    pdt_cost_config_t cfg;
    pdt_cost_t c, cnof, zero;
    pdt_discrete_t d0 = dmodel_of(s->kind[0], s->delay_frac[0], s->coef_frac);
    pdt_discrete_t d;
    pdt_model_t m0 = model_of(s, 0);
    pdt_model_t m;
    pdt_real_t v = ((pdt_real_t)123.0);
    (void)state;
    load_set(s);
    set_config(s, &cfg);
    cfg.delay_min = 3;
    init_ok(&c, &cfg, s->n);
    cfg.use_frequency = false;
    assert_int_equal(pdt_cost_init(&cnof, &cfg, g_u, g_y, s->n, g_work, sizeof g_work), PDT_OK);
    memset(&zero, 0, sizeof zero);

    /* time costs */
    assert_int_equal(pdt_cost_prediction(NULL, &d0, &v), PDT_ERR_ARG);
    assert_int_equal(pdt_cost_prediction(&c, NULL, &v), PDT_ERR_ARG);
    assert_int_equal(pdt_cost_prediction(&c, &d0, NULL), PDT_ERR_ARG);
    assert_int_equal(pdt_cost_simulation(NULL, &d0, &v), PDT_ERR_ARG);
    assert_int_equal(pdt_cost_simulation(&c, NULL, &v), PDT_ERR_ARG);
    assert_int_equal(pdt_cost_simulation(&c, &d0, NULL), PDT_ERR_ARG);
    assert_int_equal(pdt_cost_simulation(&zero, &d0, &v), PDT_ERR_ARG);
    for (int i = 0; i < 8; i++) {
        d = d0;
        switch (i) {
        case 0:
            d.order = 0;
            break;
        case 1:
            d.order = 3;
            break;
        case 2:
            d.delay = s->delay_max + 1u;
            break;
        case 3:
            d.delay = 2;
            break; /* below delay_min = 3 */
        case 4:
            d.b[1] = (pdt_real_t)NAN;
            break;
        case 5:
            d.d[0] = (pdt_real_t)INFINITY;
            break;
        case 6:
            d.order = 2;
            d.d[1] = (pdt_real_t)NAN;
            break;
        default:
            d.delay = (size_t)-1;
            break;
        }
        assert_int_equal(pdt_cost_prediction(&c, &d, &v), PDT_ERR_ARG);
        assert_int_equal(pdt_cost_simulation(&c, &d, &v), PDT_ERR_ARG);
    }
    d = d0; /* a[] is the caller's; NaN there does not matter */
    d.a[1] = (pdt_real_t)NAN;
    d.delay = s->delay_max;
    assert_int_equal(pdt_cost_simulation(&c, &d, &v), PDT_OK);
    assert_true(isfinite(v));
    v = ((pdt_real_t)123.0);

    /* frequency */
    assert_int_equal(pdt_cost_frequency(NULL, &m0, &v), PDT_ERR_ARG);
    assert_int_equal(pdt_cost_frequency(&c, NULL, &v), PDT_ERR_ARG);
    assert_int_equal(pdt_cost_frequency(&c, &m0, NULL), PDT_ERR_ARG);
    assert_int_equal(pdt_cost_frequency(&cnof, &m0, &v), PDT_ERR_ARG);
    assert_int_equal(pdt_cost_frequency(&zero, &m0, &v), PDT_ERR_ARG);
    m = m0;
    m.p.fopdt.tau = ((pdt_real_t)0.0);
    assert_int_equal(pdt_cost_frequency(&c, &m, &v), PDT_ERR_ARG);
    m = m0;
    m.kind = (pdt_model_kind_t)5;
    assert_int_equal(pdt_cost_frequency(&c, &m, &v), PDT_ERR_ARG);

    /* eval */
    assert_int_equal(pdt_cost_eval(NULL, &m0, &v), PDT_ERR_ARG);
    assert_int_equal(pdt_cost_eval(&c, NULL, &v), PDT_ERR_ARG);
    assert_int_equal(pdt_cost_eval(&c, &m0, NULL), PDT_ERR_ARG);
    assert_int_equal(pdt_cost_eval(&zero, &m0, &v), PDT_ERR_ARG);
    assert_int_equal(pdt_cost_eval(&cnof, &m0, &v), PDT_ERR_ARG); /* COMBINED needs spectra */
    m = m0;
    m.p.fopdt.K = (pdt_real_t)NAN;
    assert_int_equal(pdt_cost_eval(&c, &m, &v), PDT_ERR_ARG);
    m = m0; /* fractional: floor(Td / Ts) = delay_max + 1 */
    m.p.fopdt.Td = (pdt_real_t)(((double)s->delay_max + 1.2) * s->Ts);
    assert_int_equal(pdt_cost_eval(&c, &m, &v), PDT_ERR_ARG);
    m.p.fopdt.Td = (pdt_real_t)(2.7 * s->Ts); /* floor 2 < delay_min */
    assert_int_equal(pdt_cost_eval(&c, &m, &v), PDT_ERR_ARG);
    m.p.fopdt.Td = ((pdt_real_t)1e30);
    assert_int_equal(pdt_cost_eval(&c, &m, &v), PDT_ERR_ARG);
    assert_true(v == ((pdt_real_t)123.0));

    cfg.use_frequency = true;
    cfg.delay_mode = PDT_DELAY_INTEGER;
    init_ok(&c, &cfg, s->n);
    m = m0; /* integer: round(Td / Ts) = delay_max + 1 */
    m.p.fopdt.Td = (pdt_real_t)(((double)s->delay_max + 0.7) * s->Ts);
    assert_int_equal(pdt_cost_eval(&c, &m, &v), PDT_ERR_ARG);
    m.p.fopdt.Td = (pdt_real_t)(((double)s->delay_max + 0.3) * s->Ts);
    assert_int_equal(pdt_cost_eval(&c, &m, &v), PDT_OK);
    v = ((pdt_real_t)123.0);
    m.p.fopdt.Td = (pdt_real_t)(2.4 * s->Ts); /* rounds to 2 < delay_min */
    assert_int_equal(pdt_cost_eval(&c, &m, &v), PDT_ERR_ARG);
    m.p.fopdt.Td = (pdt_real_t)(2.6 * s->Ts);
    assert_int_equal(pdt_cost_eval(&c, &m, &v), PDT_OK);
    v = ((pdt_real_t)123.0);
    m.p.fopdt.Td = ((pdt_real_t)1e30);
    assert_int_equal(pdt_cost_eval(&c, &m, &v), PDT_ERR_ARG);
    assert_true(v == ((pdt_real_t)123.0));

    /* FREQUENCY does not look at the dead time at all. */
    cfg.kind = PDT_COST_FREQUENCY;
    init_ok(&c, &cfg, s->n);
    assert_int_equal(pdt_cost_eval(&c, &m, &v), PDT_OK);
    cfg.use_frequency = false;
    assert_int_equal(pdt_cost_init(&cnof, &cfg, g_u, g_y, s->n, g_work, sizeof g_work), PDT_OK);
    v = ((pdt_real_t)123.0);
    assert_int_equal(pdt_cost_eval(&cnof, &m0, &v), PDT_ERR_ARG);
    assert_true(v == ((pdt_real_t)123.0));
}

static void test_config_default(void **state)
{
    pdt_cost_config_t cfg;
    (void)state;
    memset(&cfg, 0x5A, sizeof cfg);
    pdt_cost_config_default(&cfg);
    assert_true(cfg.Ts == ((pdt_real_t)0.0));
    assert_true(cfg.u0 == ((pdt_real_t)0.0) && cfg.y0 == ((pdt_real_t)0.0));
    assert_int_equal(cfg.delay_min, 0);
    assert_int_equal(cfg.delay_max, PDT_DELAY_HALF);
    assert_int_equal(cfg.kind, PDT_COST_COMBINED);
    assert_int_equal(cfg.time_kind, PDT_COST_SIMULATION);
    assert_int_equal(cfg.delay_mode, PDT_DELAY_FRACTIONAL);
    assert_true(cfg.estimate_offset && cfg.use_frequency);
    assert_true(cfg.phi_t == ((pdt_real_t)1.0) && cfg.phi_f == ((pdt_real_t)1.0));
    assert_int_equal(cfg.weight, PDT_WEIGHT_UNIFORM);
    assert_true(cfg.f_lo == ((pdt_real_t)0.0) && cfg.f_hi == ((pdt_real_t)0.0));
    assert_null(cfg.weights);
    pdt_cost_config_default(NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_config_default),
        cmocka_unit_test(test_vectors_time),
        cmocka_unit_test(test_vectors_frequency),
        cmocka_unit_test(test_vectors_eval),
        cmocka_unit_test(test_exact_model_zero_cost),
        cmocka_unit_test(test_long_record_accuracy),
        cmocka_unit_test(test_frequency_ignores_dead_time),
        cmocka_unit_test(test_offset_invariance),
        cmocka_unit_test(test_parseval),
        cmocka_unit_test(test_weights),
        cmocka_unit_test(test_fft_size_and_workspace),
        cmocka_unit_test(test_workspace_exact),
        cmocka_unit_test(test_diverging_model),
        cmocka_unit_test(test_init_errors),
        cmocka_unit_test(test_fit_and_units),
        cmocka_unit_test(test_eval_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
