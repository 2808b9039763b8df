/*
 * Tests of the simulation cost's extra columns (pdt_cost_state.c): the
 * model's free response from the first sample (estimate_state) and a linear
 * drift (drift), fitted with the gain and the offset. The profile's cost,
 * gain and offset and the fitted free response and drift are compared with
 * the numpy reference's least squares on the explicit columns
 * (tests/vectors/cost_state_vectors.h, written by
 * tools/vectorgen/cost_state.py); then properties: a gain bound holds and
 * costs more, and a cost that is not SIMULATION refuses the columns.
 */
#include "test_util.h"

#include "pdt_cost_state.h"

#include "cost_state_vectors.h"

/* Relative tolerance against the double reference (of the cost: its
 * square root is the residual's scale). The records are exact in float,
 * Ts and the shapes are not. */
#if PDT_REAL_DOUBLE
#define CS_RTOL 1e-7
#else
#define CS_RTOL 2e-3
#endif

#define CS_NMAX  300u
#define CS_WORK  (PDT_COST_WORKSPACE_SIZE(CS_NMAX) / sizeof(pdt_real_t))
#define CS_CASES (sizeof cs_cases / sizeof cs_cases[0])

static pdt_real_t g_u[CS_NMAX];
static pdt_real_t g_y[CS_NMAX];
static pdt_real_t g_scratch[CS_NMAX + CANARY_COUNT];
static pdt_real_t g_work[CS_WORK];

static pdt_model_t shape_of(const cost_state_case_t *t)
{
    pdt_model_t m;
    memset(&m, 0, sizeof m);
    if (t->kind == 0) {
        m.kind = PDT_MODEL_FOPDT;
        m.p.fopdt.K = (pdt_real_t)t->p[0];
        m.p.fopdt.tau = (pdt_real_t)t->p[1];
        m.p.fopdt.Td = (pdt_real_t)t->p[2];
    } else {
        m.kind = PDT_MODEL_SOPDT;
        m.p.sopdt.k = (pdt_real_t)t->p[0];
        m.p.sopdt.a = (pdt_real_t)t->p[1];
        m.p.sopdt.b = (pdt_real_t)t->p[2];
        m.p.sopdt.Td = (pdt_real_t)t->p[3];
    }
    return m;
}

static void prepare(const cost_state_case_t *t, pdt_cost_t *c)
{
    const size_t n = cs_n[t->rec];
    pdt_cost_config_t cfg;
    assert_true(n <= CS_NMAX);
    for (size_t k = 0; k < n; k++) {
        g_u[k] = (pdt_real_t)cs_u[t->rec][k];
        g_y[k] = (pdt_real_t)cs_y[t->rec][k];
    }
    pdt_cost_config_default(&cfg);
    cfg.Ts = (pdt_real_t)cs_Ts[t->rec];
    cfg.u0 = (pdt_real_t)cs_u0[t->rec];
    cfg.y0 = (pdt_real_t)cs_y0[t->rec];
    cfg.kind = PDT_COST_SIMULATION;
    cfg.use_frequency = false;
    cfg.delay_max = COST_STATE_DELAY_MAX;
    cfg.estimate_offset = t->flags[0] != 0;
    cfg.estimate_state = t->flags[1] != 0;
    cfg.drift = t->flags[2] != 0;
    cfg.whole_record = t->flags[3] != 0;
    assert_int_equal(pdt_cost_init(c, &cfg, g_u, g_y, n, g_work, sizeof g_work), PDT_OK);
}

/* |got - want| within rtol of scale. */
static void near(double got, double want, double scale, double rtol, double *worst)
{
    const double e = fabs(got - want) / scale;
    *worst = e > *worst ? e : *worst;
    if (!(e <= rtol)) {
        print_message("  got %.10g want %.10g (error %.3g)\n", got, want, e);
    }
    assert_true(e <= rtol);
}

static void test_vectors(void **state)
{
    (void)state;
    double worst[6] = {0};
    for (size_t i = 0; i < CS_CASES; i++) {
        const cost_state_case_t *t = &cs_cases[i];
        pdt_cost_t c;
        pdt_cost_profile_t p;
        pdt_cost_extra_t x;
        prepare(t, &c);
        const pdt_model_t shape = shape_of(t);
        canary_fill(g_scratch + cs_n[t->rec], CANARY_COUNT);
        assert_int_equal(
            pdt_cost_profile(&c, &shape, (pdt_real_t)0.0, (pdt_real_t)0.0, g_scratch, &p), PDT_OK);
        canary_check(g_scratch + cs_n[t->rec], CANARY_COUNT);
        /* The fit's scale: the residual's, with the output's for the
         * linear parameters (a column the record barely tells from the
         * others moves by more). */
        const double rms = sqrt(t->want[0]);
        near((double)p.cost, t->want[0], t->want[0], CS_RTOL, &worst[0]);
        near((double)p.gain, t->want[1], fabs(t->want[1]) + rms, CS_RTOL, &worst[1]);
        near((double)p.offset, t->want[2], fabs(t->want[2]) + 1.0, CS_RTOL, &worst[2]);
        pdt_model_t m = shape;
        if (m.kind == PDT_MODEL_FOPDT) {
            m.p.fopdt.K *= p.gain;
        } else {
            m.p.sopdt.k *= p.gain;
        }
        if (!pdt_cost_extra_on(&c)) {
            assert_int_equal(pdt_cost_extra_terms(&c, &m, g_scratch, &x), PDT_ERR_ARG);
            continue;
        }
        assert_int_equal(pdt_cost_extra_terms(&c, &m, g_scratch, &x), PDT_OK);
        near((double)x.state[0], t->want[3], fabs(t->want[3]) + 1.0, CS_RTOL, &worst[3]);
        near((double)x.state[1], t->want[4], fabs(t->want[4]) + 1.0, CS_RTOL, &worst[4]);
        near((double)x.drift, t->want[5], fabs(t->want[5]) + 1e-3, CS_RTOL, &worst[5]);
    }
    print_message("  %u cases, worst relative error: cost %.2g gain %.2g offset %.2g x0 %.2g "
                  "x1 %.2g drift %.2g\n",
                  (unsigned)CS_CASES, worst[0], worst[1], worst[2], worst[3], worst[4], worst[5]);
}

/* A gain bound below the free optimum: the gain on it, a higher cost. */
static void test_bounds(void **state)
{
    (void)state;
    const cost_state_case_t *t = &cs_cases[0];
    pdt_cost_t c;
    pdt_cost_profile_t free_p, bound_p;
    prepare(t, &c);
    const pdt_model_t shape = shape_of(t);
    assert_int_equal(
        pdt_cost_profile(&c, &shape, (pdt_real_t)0.0, (pdt_real_t)0.0, g_scratch, &free_p), PDT_OK);
    const pdt_real_t hi = free_p.gain * (pdt_real_t)0.8;
    assert_int_equal(pdt_cost_profile(&c, &shape, -hi, hi, g_scratch, &bound_p), PDT_OK);
    assert_true(bound_p.gain == hi);
    assert_true(bound_p.cost > free_p.cost);
}

/* The columns belong to the output error: other criteria refuse them. */
static void test_only_simulation(void **state)
{
    (void)state;
    pdt_cost_config_t cfg;
    pdt_cost_t c;
    for (size_t k = 0; k < CS_NMAX; k++) {
        g_u[k] = (pdt_real_t)(k > 20u ? 1.0 : 0.0);
        g_y[k] = (pdt_real_t)(k > 25u ? 1.0 : 0.0);
    }
    pdt_cost_config_default(&cfg);
    cfg.Ts = (pdt_real_t)1.0;
    cfg.use_frequency = false;
    cfg.kind = PDT_COST_PREDICTION;
    cfg.drift = true;
    assert_int_equal(pdt_cost_init(&c, &cfg, g_u, g_y, CS_NMAX, g_work, sizeof g_work),
                     PDT_ERR_ARG);
    cfg.drift = false;
    cfg.estimate_state = true;
    assert_int_equal(pdt_cost_init(&c, &cfg, g_u, g_y, CS_NMAX, g_work, sizeof g_work),
                     PDT_ERR_ARG);
    cfg.kind = PDT_COST_SIMULATION;
    assert_int_equal(pdt_cost_init(&c, &cfg, g_u, g_y, CS_NMAX, g_work, sizeof g_work), PDT_OK);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_vectors),
        cmocka_unit_test(test_bounds),
        cmocka_unit_test(test_only_simulation),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
