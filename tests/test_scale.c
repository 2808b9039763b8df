/*
 * Scale-proof numerics: the same record scaled by 1e-30 .. 1e30 (both
 * signals, or one of them) identifies the same model, with a finite fit,
 * in both real types; a bad-value cell is refused by name, never fitted.
 */
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include "pdt/pdt.h"
#include "sim_plant.h"
#include "sim_rng.h"

#define SC_N   600u
#define SC_TS  0.1
#define SC_K   2.0
#define SC_TAU 3.0
#define SC_TD  1.2
#define SC_U0  5.0
#define SC_Y0  10.0

static double g_ud[SC_N];
static double g_yd[SC_N];
static pdt_real_t g_u[SC_N];
static pdt_real_t g_y[SC_N];
static pdt_real_t
    g_work[PDT_IDENT_WORKSPACE_SIZE(SC_N, PDT_IDENT_POPULATION_SOPDT) / sizeof(pdt_real_t)];

/* The unscaled record: a FOPDT on the shared simulator driven by
 * steps of varying length around SC_U0, with 1 % of deterministic output
 * noise. */
static void make_record(void)
{
    static double hist[64];
    const double lag[1] = {SC_TAU};
    const sim_plant_desc_t d = sim_plant_desc_lags(SC_K, lag, 1u, SC_TD);
    sim_plant_t p;
    assert_int_equal(sim_plant_init(&p, &d, SC_TS, SC_U0, SC_Y0, hist, 64u), 0);
    sim_rng64_t r = sim_rng64_seed(12345u);
    for (size_t k = 0; k < SC_N; k++) {
        g_ud[k] = SC_U0 + (((k / 47u) + (k / 83u)) % 2u == 0u ? 0.0 : 1.0);
    }
    for (size_t k = 0; k < SC_N; k++) {
        g_yd[k] = sim_plant_output(&p) + 0.02 * (sim_rng64_uniform(&r) - 0.5);
        sim_plant_apply(&p, g_ud[k]);
    }
}

static void load(double su, double sy)
{
    for (size_t k = 0; k < SC_N; k++) {
        g_u[k] = (pdt_real_t)(g_ud[k] * su);
        g_y[k] = (pdt_real_t)(g_yd[k] * sy);
    }
}

static bool g_no_screen;

static pdt_status_t identify(pdt_model_kind_t kind, pdt_ident_result_t *res)
{
    pdt_ident_config_t cfg;
    pdt_ident_t ctx;
    pdt_ident_data_t data = {g_u, g_y, SC_N};
    pdt_ident_config_default(&cfg);
    cfg.no_screen = g_no_screen;
    cfg.Ts = (pdt_real_t)SC_TS;
    cfg.model = kind;
    assert_true(pdt_ident_workspace_size(&cfg, SC_N) <= sizeof g_work);
    return pdt_identify(&ctx, &cfg, &data, g_work, sizeof g_work, res);
}

static double rel(double got, double want)
{
    return fabs(got - want) / fabs(want);
}

static double steady_gain(const pdt_model_t *m)
{
    if (m->kind == PDT_MODEL_FOPDT) {
        return (double)m->p.fopdt.K;
    }
    const pdt_model_sopdt_t *p = &m->p.sopdt;
    return (double)p->k / (double)(p->b > (pdt_real_t)0.0 ? p->b : p->a);
}

/* The model, operating point and fit found at scale 1 are found at every
 * scale, mapped by it: K by sy / su, the output level by sy. */
static void check_scales(pdt_model_kind_t kind)
{
    static const double scales[] = {1e-30, 1e-25, 1e-18, 1e-10, 1e-3, 1e3,
                                    1e10,  1e18,  1e20,  1e25,  1e30};
    pdt_ident_result_t ref, r;
    double worst_k = 0.0, worst_fit = 0.0;
    load(1.0, 1.0);
    assert_int_equal(identify(kind, &ref), PDT_OK);
    assert_true((double)ref.fit > 90.0);
    for (size_t i = 0; i < sizeof scales / sizeof scales[0]; i++) {
        for (int which = 0; which < 3; which++) {
            /* both signals, the output only, the input only; a one-sided
             * scale is kept where the gain stays a float */
            const double s = scales[i];
            const double su = (which == 1) ? 1.0 : s;
            const double sy = (which == 2) ? 1.0 : s;
            if (which != 0 && (s < 1e-25 || s > 1e25)) {
                continue;
            }
            load(su, sy);
            assert_int_equal(identify(kind, &r), PDT_OK);
            /* A SOPDT's steady-state gain: its numerator k moves with a
             * second lag the record does not determine (it vanishes on
             * this first-order plant). */
            double Kref = steady_gain(&ref.model);
            double K = steady_gain(&r.model);
            double ek = rel(K, Kref * sy / su);
            worst_k = fmax(worst_k, ek);
            if (ek > 1e-2) {
                print_message("scale %g (%d): K %g, want %g\n", s, which, K, Kref * sy / su);
            }
            assert_true(ek < 1e-2);
            if (kind == PDT_MODEL_FOPDT) {
                assert_true(rel((double)r.model.p.fopdt.tau, (double)ref.model.p.fopdt.tau) < 2e-2);
                assert_true(fabs((double)r.model.p.fopdt.Td - (double)ref.model.p.fopdt.Td) < 0.05);
            }
            assert_true(rel((double)r.y0, (double)ref.y0 * sy) < 1e-3);
            assert_true(isfinite((double)r.fit));
            worst_fit = fmax(worst_fit, fabs((double)r.fit - (double)ref.fit));
            assert_true(fabs((double)r.fit - (double)ref.fit) < 0.5);
            /* The cost in output units squared where a real holds it. */
            assert_true(!isnan((double)r.cost));
            assert_true(r.cost >= (pdt_real_t)0.0);
        }
    }
    print_message("scales 1e-30 .. 1e30: worst K error %.3g, worst fit change %.3g points\n",
                  worst_k, worst_fit);
}

static void test_scales_fopdt(void **state)
{
    (void)state;
    check_scales(PDT_MODEL_FOPDT);
}

static void test_scales_sopdt(void **state)
{
    (void)state;
    check_scales(PDT_MODEL_SOPDT);
}

/* A logger's bad-value marker in one cell is refused with its own status,
 * and pdt_cost_outlier names the cell, at any scale of the rest: in u
 * always, in y without the screen; with it, the cell of y is left out. */
static void test_bad_cells(void **state)
{
    static const double bad[] = {1e20, -3e38, 3e38, -1e25};
    static const size_t at[] = {0u, 5u, 300u, SC_N - 1u};
    (void)state;
    for (size_t s = 0; s < 3; s++) {
        const double scale = (s == 0) ? 1.0 : (s == 1 ? 1e-6 : 1e6);
        for (size_t b = 0; b < sizeof bad / sizeof bad[0]; b++) {
            for (size_t i = 0; i < sizeof at / sizeof at[0]; i++) {
                pdt_ident_result_t r;
                for (int sig = 0; sig < 2; sig++) {
                    load(scale, scale);
                    pdt_real_t *x = (sig == 0) ? g_y : g_u;
                    x[at[i]] = (pdt_real_t)bad[b];
                    assert_int_equal(pdt_cost_outlier(x, SC_N), at[i]);
                    g_no_screen = true;
                    assert_int_equal(identify(PDT_MODEL_FOPDT, &r), PDT_ERR_OUTLIER);
                    g_no_screen = false;
                    if (sig == 0) {
                        assert_int_equal(identify(PDT_MODEL_FOPDT, &r), PDT_OK);
                        assert_true(r.excluded >= 1u);
                        assert_int_equal(r.excluded_first[0], at[i]);
                    } else {
                        assert_int_equal(identify(PDT_MODEL_FOPDT, &r), PDT_ERR_OUTLIER);
                    }
                }
            }
        }
    }
    /* Clean records and clean step or relay signals have none. */
    load(1.0, 1.0);
    assert_int_equal(pdt_cost_outlier(g_y, SC_N), SC_N);
    assert_int_equal(pdt_cost_outlier(g_u, SC_N), SC_N);
    for (size_t k = 0; k < SC_N; k++) {
        g_u[k] = (pdt_real_t)((k < 100u) ? 0.0 : 1.0);
    }
    assert_int_equal(pdt_cost_outlier(g_u, SC_N), SC_N);
    assert_int_equal(pdt_cost_outlier(NULL, SC_N), SC_N);
    assert_int_equal(pdt_cost_outlier(g_u, 1u), 1u);
}

/* A decay into the rounding is no outlier: the jump sizes fill the gap. */
static void test_decay_is_no_outlier(void **state)
{
    (void)state;
    for (size_t k = 0; k < SC_N; k++) {
        g_y[k] = (pdt_real_t)((k < 10u) ? 0.0 : exp(-(double)(k - 10u) / 8.0));
    }
    assert_int_equal(pdt_cost_outlier(g_y, SC_N), SC_N);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_scales_fopdt),
        cmocka_unit_test(test_scales_sopdt),
        cmocka_unit_test(test_bad_cells),
        cmocka_unit_test(test_decay_is_no_outlier),
    };
    make_record();
    return cmocka_run_group_tests(tests, NULL, NULL);
}
