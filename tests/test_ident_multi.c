/*
 * Tests of several records of one process (pdt_ident_config_t.more,
 * docs/several-records.md): the joint profile (pdt_cost_joint_profile)
 * against the numpy reference's stacked least squares
 * (tests/vectors/cost_joint_vectors.h, tools/vectorgen/cost_joint.py);
 * two and three records of one FOPDT or SOPDT at different periods and
 * operating points identified together recover the plant and each
 * record's operating point; the per-record results; what several records
 * refuse.
 */
#include "test_util.h"

#include "pdt_cost_state.h"
#include "sim_process.h"
#include "sim_rng.h"

#include "cost_joint_vectors.h"
#include "cost_state_vectors.h"

#if PDT_REAL_DOUBLE
#define CJ_RTOL 1e-7
#else
#define CJ_RTOL 2e-3
#endif

#define CJ_NMAX  300u
#define CJ_WORK  (PDT_COST_WORKSPACE_SIZE(CJ_NMAX) / sizeof(pdt_real_t))
#define CJ_CASES (sizeof cj_cases / sizeof cj_cases[0])

static pdt_real_t g_u[3][CJ_NMAX];
static pdt_real_t g_y[3][CJ_NMAX];
static pdt_real_t g_scratch[CJ_NMAX + CANARY_COUNT];
static pdt_real_t g_work[3][CJ_WORK];

static void prepare(size_t slot, size_t rec, const int *flags, pdt_cost_t *c)
{
    const size_t n = cs_n[rec];
    pdt_cost_config_t cfg;
    assert_true(n <= CJ_NMAX);
    for (size_t k = 0; k < n; k++) {
        g_u[slot][k] = (pdt_real_t)cs_u[rec][k];
        g_y[slot][k] = (pdt_real_t)cs_y[rec][k];
    }
    pdt_cost_config_default(&cfg);
    cfg.Ts = (pdt_real_t)cs_Ts[rec];
    cfg.u0 = (pdt_real_t)cs_u0[rec];
    cfg.y0 = (pdt_real_t)cs_y0[rec];
    cfg.kind = PDT_COST_SIMULATION;
    cfg.use_frequency = false;
    cfg.delay_max = COST_STATE_DELAY_MAX;
    cfg.whole_record = true;
    cfg.estimate_offset = flags[0] != 0;
    cfg.estimate_state = flags[1] != 0;
    cfg.drift = flags[2] != 0;
    assert_int_equal(
        pdt_cost_init(c, &cfg, g_u[slot], g_y[slot], n, g_work[slot], sizeof g_work[slot]), PDT_OK);
}

/* The joint profile against the stacked least squares of the reference. */
static void test_vectors(void **state)
{
    (void)state;
    double worst = 0.0;
    for (size_t i = 0; i < CJ_CASES; i++) {
        const cost_joint_case_t *t = &cj_cases[i];
        pdt_cost_t c[3];
        const pdt_cost_t *costs[3];
        for (size_t r = 0; r < t->count; r++) {
            prepare(r, t->rec[r], t->flags, &c[r]);
            costs[r] = &c[r];
        }
        const pdt_model_t shape = vector_model(t->kind + 1, t->p);
        pdt_cost_profile_t p;
        for (size_t k = 0; k < CANARY_COUNT; k++) {
            g_scratch[CJ_NMAX + k] = CANARY_VALUE;
        }
        assert_int_equal(pdt_cost_joint_profile(costs, t->count, &shape, (pdt_real_t)0.0,
                                                (pdt_real_t)0.0, NULL, g_scratch, &p),
                         PDT_OK);
        canary_check(&g_scratch[CJ_NMAX], CANARY_COUNT);
        const double e[3] = {fabs((double)p.cost - t->want[0]) / t->want[0],
                             fabs((double)p.gain - t->want[1]) / fabs(t->want[1]),
                             fabs((double)p.offset - t->want[2]) / (1.0 + fabs(t->want[2]))};
        for (size_t j = 0; j < 3u; j++) {
            worst = e[j] > worst ? e[j] : worst;
            if (e[j] > CJ_RTOL) {
                print_error("case %zu part %zu: %.9g off\n", i, j, e[j]);
            }
            assert_true(e[j] <= CJ_RTOL);
        }
    }
    print_message("joint profile: %zu cases, worst relative difference %.3g\n", CJ_CASES, worst);
}

/* A gain bound holds in the joint profile too. */
static void test_bounds(void **state)
{
    (void)state;
    const cost_joint_case_t *t = &cj_cases[0];
    pdt_cost_t c[3];
    const pdt_cost_t *costs[3];
    for (size_t r = 0; r < t->count; r++) {
        prepare(r, t->rec[r], t->flags, &c[r]);
        costs[r] = &c[r];
    }
    const pdt_model_t shape = vector_model(t->kind + 1, t->p);
    pdt_cost_profile_t f, b;
    assert_int_equal(pdt_cost_joint_profile(costs, t->count, &shape, (pdt_real_t)0.0,
                                            (pdt_real_t)0.0, NULL, g_scratch, &f),
                     PDT_OK);
    const pdt_real_t hi = f.gain * (pdt_real_t)0.8;
    assert_int_equal(pdt_cost_joint_profile(costs, t->count, &shape, -hi, hi, NULL, g_scratch, &b),
                     PDT_OK);
    assert_true(b.gain == hi);
    assert_true(b.cost > f.cost);
    assert_int_equal(pdt_cost_joint_profile(costs, 0u, &shape, (pdt_real_t)0.0, (pdt_real_t)0.0,
                                            NULL, g_scratch, &b),
                     PDT_ERR_ARG);
}

/* ---- identification */

#define NMAX       800u
#define POP_MAX    40u
#define WORK_REALS (PDT_IDENT_WORKSPACE_SIZE(NMAX, POP_MAX) / sizeof(pdt_real_t) + 4u * NMAX + 512u)

static pdt_real_t g_ru[3][NMAX];
static pdt_real_t g_ry[3][NMAX];
static pdt_real_t g_iwork[WORK_REALS];
static pdt_ident_t g_ctx;

/* An overdamped SOPDT of DC gain K, time constants T1, T2, dead time Td. */
static pdt_model_t sopdt(double K, double T1, double T2, double Td)
{
    pdt_model_t m;
    memset(&m, 0, sizeof m);
    m.kind = PDT_MODEL_SOPDT;
    const pdt_model_tc_t tc = {(pdt_real_t)K, (pdt_real_t)T1, (pdt_real_t)T2, false,
                               (pdt_real_t)Td};
    assert_int_equal(pdt_model_sopdt_from_tc(&tc, &m.p.sopdt), PDT_OK);
    return m;
}

/* A PRBS record of m: n samples every Ts around (u0, y0), amplitude amp,
 * starting at rest, with white noise sd. */
static void record(size_t slot, const pdt_model_t *m, size_t n, pdt_real_t Ts, double u0, double y0,
                   double amp, double sd, uint32_t seed)
{
    pdt_discrete_t d;
    pdt_real_t dev[NMAX];
    /* Seeds 2^32 draws apart: sim_rng64_seed(s + 1) is the stream of s a
     * draw later, and the records of nearby seeds would share it. */
    sim_rng64_t r = sim_rng64_seed((uint64_t)seed << 32);
    double level = amp;
    for (size_t k = 0; k < n; k++) {
        if (k >= 20u && (k % 6u) == 0u && sim_rng64_coin(&r) != 0) {
            level = -level;
        }
        g_ru[slot][k] = (pdt_real_t)(k < 20u ? 0.0 : level);
    }
    assert_int_equal(pdt_discrete_init(m, Ts, &d), PDT_OK);
    assert_int_equal(pdt_discrete_simulate(&d, g_ru[slot], n, dev), PDT_OK);
    for (size_t k = 0; k < n; k++) {
        g_ru[slot][k] = (pdt_real_t)(u0 + (double)g_ru[slot][k]);
        g_ry[slot][k] = (pdt_real_t)(y0 + (double)dev[k] + sd * sim_rng64_normal(&r));
    }
}

static void multi_config(pdt_ident_config_t *cfg, pdt_model_kind_t kind, pdt_real_t Ts)
{
    pdt_ident_config_default(cfg);
    cfg->model = kind;
    cfg->Ts = Ts;
    cfg->initial = PDT_IDENT_INITIAL_REST;
    cfg->no_screen = true;
}

static pdt_status_t identify(const pdt_ident_config_t *cfg, size_t n0, pdt_ident_result_t *res)
{
    const pdt_ident_data_t data = {g_ru[0], g_ry[0], n0};
    return pdt_identify(&g_ctx, cfg, &data, g_iwork, sizeof g_iwork, res);
}

/* Two FOPDT records at 0.5 s and 1 s, different operating points. */
static void test_fopdt_two(void **state)
{
    (void)state;
    pdt_model_t m;
    pdt_ident_config_t cfg;
    pdt_ident_result_t res;
    m = model_fopdt(2.0, 10.0, 3.0);
    record(0, &m, 400u, (pdt_real_t)0.5, 40.0, 300.0, 5.0, 0.05, 3u);
    record(1, &m, 300u, (pdt_real_t)1.0, 60.0, 340.0, 8.0, 0.05, 4u);
    const pdt_ident_record_t more = {g_ru[1], g_ry[1], 300u, (pdt_real_t)1.0, false, 0};
    multi_config(&cfg, PDT_MODEL_FOPDT, (pdt_real_t)0.5);
    cfg.more = &more;
    cfg.more_count = 1u;
    assert_true(pdt_ident_workspace_size(&cfg, 400u) <= sizeof g_iwork);
    assert_int_equal(identify(&cfg, 400u, &res), PDT_OK);
    assert_close(res.model.p.fopdt.K, 2.0, 0.01, 0.0);
    assert_close(res.model.p.fopdt.tau, 10.0, 0.03, 0.0);
    assert_close(res.model.p.fopdt.Td, 3.0, 0.03, 0.0);
    assert_true(res.fit > (pdt_real_t)95.0);
    assert_int_equal(res.std.count, 0u);
    pdt_ident_record_fit_t f0, f1;
    assert_int_equal(pdt_ident_record_result(&g_ctx, 0u, &f0), PDT_OK);
    assert_int_equal(pdt_ident_record_result(&g_ctx, 1u, &f1), PDT_OK);
    assert_int_equal(pdt_ident_record_result(&g_ctx, 2u, &f1), PDT_ERR_ARG);
    assert_close(f0.y0, 300.0, 0.001, 0.0);
    assert_close(f1.y0, 340.0, 0.001, 0.0);
    assert_close(f0.u0, 40.0, 1e-6, 0.0);
    assert_close(f1.u0, 60.0, 1e-6, 0.0);
    assert_true(f0.n == 400u && f1.n == 300u);
    assert_true(f0.fit > (pdt_real_t)90.0 && f1.fit > (pdt_real_t)90.0);
    assert_close(res.y0, f0.y0, 1e-5, 1e-3);
}

/* Three SOPDT records, one with its state estimated. */
static void test_sopdt_three(void **state)
{
    (void)state;
    pdt_model_t m;
    pdt_ident_config_t cfg;
    pdt_ident_result_t res;
    m = sopdt(1.5, 8.0, 3.0, 2.0);
    record(0, &m, 500u, (pdt_real_t)0.5, 0.0, 10.0, 4.0, 0.02, 5u);
    record(1, &m, 400u, (pdt_real_t)0.8, 10.0, 20.0, 4.0, 0.02, 6u);
    record(2, &m, 300u, (pdt_real_t)1.0, -5.0, 0.0, 6.0, 0.02, 7u);
    const pdt_ident_record_t more[2] = {{g_ru[1], g_ry[1], 400u, (pdt_real_t)0.8, false, 0},
                                        {g_ru[2], g_ry[2], 300u, (pdt_real_t)1.0, false, 0}};
    multi_config(&cfg, PDT_MODEL_SOPDT, (pdt_real_t)0.5);
    cfg.more = more;
    cfg.more_count = 2u;
    cfg.initial = PDT_IDENT_INITIAL_ESTIMATE;
    assert_int_equal(identify(&cfg, 500u, &res), PDT_OK);
    pdt_real_t K = res.model.p.sopdt.k / res.model.p.sopdt.b;
    assert_close(K, 1.5, 0.02, 0.0);
    assert_close(res.model.p.sopdt.Td, 2.0, 0.1, 0.0);
    for (uint32_t r = 0; r < 3u; r++) {
        pdt_ident_record_fit_t f;
        assert_int_equal(pdt_ident_record_result(&g_ctx, r, &f), PDT_OK);
        assert_close(f.y0, r == 0u ? 10.0 : (r == 1u ? 20.0 : 0.0), 0.0, 0.05);
        assert_close(f.x0, 0.0, 0.0, 0.1);
    }
}

/* What several records refuse, and one record's result by record. */
static void test_refusals(void **state)
{
    (void)state;
    pdt_model_t m;
    pdt_ident_config_t cfg;
    pdt_ident_result_t res;
    m = model_fopdt(2.0, 10.0, 3.0);
    record(0, &m, 300u, (pdt_real_t)1.0, 40.0, 300.0, 5.0, 0.05, 3u);
    record(1, &m, 300u, (pdt_real_t)1.0, 60.0, 340.0, 8.0, 0.05, 4u);
    pdt_ident_record_t more[PDT_IDENT_MAX_RECORDS];
    for (size_t r = 0; r < PDT_IDENT_MAX_RECORDS; r++) {
        more[r] = (pdt_ident_record_t){g_ru[1], g_ry[1], 300u, (pdt_real_t)1.0, false, 0};
    }
    const pdt_ident_data_t data = {g_ru[0], g_ry[0], 300u};
    for (int what = 0; what < 11; what++) {
        multi_config(&cfg, PDT_MODEL_FOPDT, (pdt_real_t)1.0);
        cfg.more = more;
        cfg.more_count = 1u;
        switch (what) {
        case 0:
            cfg.cost = PDT_COST_COMBINED;
            break;
        case 1:
            cfg.cost = PDT_COST_FREQUENCY;
            break;
        case 2:
            cfg.cost = PDT_COST_PREDICTION;
            break;
        case 3:
            cfg.delay_mode = PDT_DELAY_INTEGER;
            break;
        case 4:
            cfg.coarse = 4u;
            break;
        case 5:
            cfg.offset = PDT_IDENT_OFFSET_REST;
            break;
        case 6:
            cfg.initial = PDT_IDENT_INITIAL_AUTO;
            break;
        case 7:
            cfg.no_screen = false;
            break;
        case 8:
            cfg.more_count = PDT_IDENT_MAX_RECORDS;
            break;
        case 9:
            cfg.more = NULL;
            break;
        default:
            more[0].Ts = (pdt_real_t)0.0;
            break;
        }
        assert_int_equal(pdt_ident_workspace_size(&cfg, 300u), 0u);
        assert_int_equal(pdt_ident_init(&g_ctx, &cfg, &data, g_iwork, sizeof g_iwork), PDT_ERR_ARG);
        more[0].Ts = (pdt_real_t)1.0;
    }
    /* A record's own faults. */
    multi_config(&cfg, PDT_MODEL_FOPDT, (pdt_real_t)1.0);
    cfg.more = more;
    cfg.more_count = 1u;
    more[0].n = 10u;
    assert_int_equal(pdt_ident_init(&g_ctx, &cfg, &data, g_iwork, sizeof g_iwork),
                     PDT_ERR_TOO_SHORT);
    more[0].n = 300u;
    const pdt_real_t keep = g_ry[1][50];
    g_ry[1][50] = (pdt_real_t)NAN;
    assert_int_equal(pdt_ident_init(&g_ctx, &cfg, &data, g_iwork, sizeof g_iwork),
                     PDT_ERR_NONFINITE);
    g_ry[1][50] = keep;
    more[0].u = g_ru[2];
    for (size_t k = 0; k < 300u; k++) {
        g_ru[2][k] = (pdt_real_t)1.0;
    }
    assert_int_equal(pdt_ident_init(&g_ctx, &cfg, &data, g_iwork, sizeof g_iwork),
                     PDT_ERR_NO_EXCITATION);
    more[0].u = g_ru[1];
    /* The result by record before the answer, then of one record. */
    assert_int_equal(pdt_ident_init(&g_ctx, &cfg, &data, g_iwork, sizeof g_iwork), PDT_OK);
    pdt_ident_record_fit_t f;
    assert_int_equal(pdt_ident_record_result(&g_ctx, 0u, &f), PDT_ERR_STATE);
    assert_int_equal(pdt_ident_record_result(NULL, 0u, &f), PDT_ERR_ARG);
    multi_config(&cfg, PDT_MODEL_FOPDT, (pdt_real_t)1.0);
    assert_int_equal(identify(&cfg, 300u, &res), PDT_OK);
    assert_int_equal(pdt_ident_record_result(&g_ctx, 0u, &f), PDT_OK);
    assert_true(f.y0 == res.y0 && f.fit == res.fit && f.u0 == res.u0);
    assert_int_equal(pdt_ident_record_result(&g_ctx, 1u, &f), PDT_ERR_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_vectors),   cmocka_unit_test(test_bounds),
        cmocka_unit_test(test_fopdt_two), cmocka_unit_test(test_sopdt_three),
        cmocka_unit_test(test_refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
