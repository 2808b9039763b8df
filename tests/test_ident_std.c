/*
 * pdt_ident_std_printed: the uncertainty of a model's own parameters
 * carried to the printed ones. Checked against central differences of the
 * model's own conversions (pdt_model_sopdt_to_natural, _to_tc, _to_integ)
 * in double arithmetic; its statuses, and *out untouched on error.
 */
#include "test_util.h"

#include "pdt/pdt_ident.h"

/* A covariance with correlations: L L^T of a fixed lower triangle. */
static void make_cov(uint32_t np, const double *scale, pdt_ident_std_t *s)
{
    static const double L[5][5] = {{1.0, 0, 0, 0, 0},
                                   {0.6, 0.8, 0, 0, 0},
                                   {-0.3, 0.5, 0.81, 0, 0},
                                   {0.2, -0.4, 0.3, 0.84, 0},
                                   {0.1, 0.1, -0.2, 0.1, 0.96}};
    memset(s, 0, sizeof *s);
    s->count = np;
    for (uint32_t i = 0; i < np; i++) {
        for (uint32_t j = 0; j < np; j++) {
            double c = 0.0;
            for (uint32_t k = 0; k < np; k++) c += L[i][k] * L[j][k];
            s->cov[i][j] = (pdt_real_t)(c * scale[i] * scale[j]);
        }
        s->std[i] = (pdt_real_t)sqrt((double)s->cov[i][i]);
    }
}

/* The printed parameters of the SOPDT x = (k, a, b, Td), by the model's own
 * conversions; NaN where the form has none. */
static void printed_of(const double x[4], double v[PDT_IDENT_PAR_COUNT])
{
    pdt_model_sopdt_t s = {(pdt_real_t)x[0], (pdt_real_t)x[1], (pdt_real_t)x[2], (pdt_real_t)x[3]};
    pdt_model_natural_t nat;
    pdt_model_tc_t tc;
    for (int i = 0; i < PDT_IDENT_PAR_COUNT; i++) v[i] = (double)NAN;
    v[PDT_IDENT_PAR_TD] = x[3];
    v[PDT_IDENT_PAR_Y0] = 0.0; /* the offset's row is J's last column alone */
    v[PDT_IDENT_PAR_A] = x[1];
    v[PDT_IDENT_PAR_B] = x[2];
    if (pdt_model_sopdt_to_natural(&s, &nat) == PDT_OK) {
        v[PDT_IDENT_PAR_K] = (double)nat.K;
        v[PDT_IDENT_PAR_WN] = (double)nat.wn;
        v[PDT_IDENT_PAR_ZETA] = (double)nat.zeta;
    }
    if (pdt_model_sopdt_to_tc(&s, &tc) == PDT_OK && !tc.complex) {
        v[PDT_IDENT_PAR_TAU1] = (double)tc.T1;
        v[PDT_IDENT_PAR_TAU2] = (double)tc.T2;
    }
}

/* J cov J^T with J by central differences of printed_of (step 1e-3 of each
 * parameter: a relative truncation error below 1e-5). */
static void check_sopdt(const double x[4], const pdt_ident_std_t *s, const pdt_ident_printed_t *p)
{
    double J[PDT_IDENT_PAR_COUNT][5] = {{0}};
    for (int j = 0; j < 4; j++) {
        double xp[4], xm[4], vp[PDT_IDENT_PAR_COUNT], vm[PDT_IDENT_PAR_COUNT];
        memcpy(xp, x, sizeof xp);
        memcpy(xm, x, sizeof xm);
        const double h = 1e-3 * fabs(x[j]);
        xp[j] += h;
        xm[j] -= h;
        printed_of(xp, vp);
        printed_of(xm, vm);
        for (int i = 0; i < PDT_IDENT_PAR_COUNT; i++) J[i][j] = (vp[i] - vm[i]) / (2.0 * h);
    }
    J[PDT_IDENT_PAR_Y0][4] = 1.0;
    for (int i = 0; i < PDT_IDENT_PAR_COUNT; i++) {
        if (!((p->have >> i) & 1u)) continue;
        double c = 0.0;
        for (int j = 0; j < 5; j++)
            for (int l = 0; l < 5; l++) c += J[i][j] * (double)s->cov[j][l] * J[i][l];
        assert_close((double)p->std[i], sqrt(c), PDT_REAL_DOUBLE ? 1e-4 : 2e-3, 0.0);
    }
}

static void test_sopdt_overdamped(void **state)
{
    (void)state;
    const double x[4] = {0.25, 5.5 / 6.0, 1.0 / 6.0, 0.83}; /* K 1.5, tau 4 and 1.5 */
    const double scale[5] = {0.004, 0.05, 0.01, 0.1, 0.002};
    pdt_ident_std_t s;
    make_cov(5, scale, &s);
    const pdt_model_t m = {
        .kind = PDT_MODEL_SOPDT,
        .p.sopdt = {(pdt_real_t)x[0], (pdt_real_t)x[1], (pdt_real_t)x[2], (pdt_real_t)x[3]}};
    pdt_ident_printed_t p;
    assert_int_equal(pdt_ident_std_printed(&m, &s, &p), PDT_OK);
    assert_true((p.have >> PDT_IDENT_PAR_TAU1) & 1u);
    assert_false((p.have >> PDT_IDENT_PAR_TAU) & 1u);
    assert_true(isnan((double)p.std[PDT_IDENT_PAR_TAU]));
    check_sopdt(x, &s, &p);
    /* The printed a, b, Td, y0 are the model's own. */
    assert_close((double)p.cov[PDT_IDENT_PAR_A][PDT_IDENT_PAR_B], (double)s.cov[1][2], 1e-6, 0.0);
}

static void test_sopdt_underdamped_and_undetermined(void **state)
{
    (void)state;
    const double x[4] = {1.0, 0.4, 1.0, 0.5}; /* zeta 0.2: no real time constants */
    const double scale[5] = {0.01, 0.02, 0.02, 0.05, 0.001};
    pdt_ident_std_t s;
    make_cov(5, scale, &s);
    const pdt_model_t m = {.kind = PDT_MODEL_SOPDT, .p.sopdt = {1.0f, 0.4f, 1.0f, 0.5f}};
    pdt_ident_printed_t p;
    assert_int_equal(pdt_ident_std_printed(&m, &s, &p), PDT_OK);
    assert_false((p.have >> PDT_IDENT_PAR_TAU1) & 1u);
    check_sopdt(x, &s, &p);
    /* b undetermined: everything that depends on it is. */
    s.std[2] = (pdt_real_t)INFINITY;
    assert_int_equal(pdt_ident_std_printed(&m, &s, &p), PDT_OK);
    assert_true(isinf((double)p.std[PDT_IDENT_PAR_K]) && isinf((double)p.std[PDT_IDENT_PAR_WN]));
    assert_true(isfinite((double)p.std[PDT_IDENT_PAR_TD]));
    assert_true(isnan((double)p.cov[PDT_IDENT_PAR_K][PDT_IDENT_PAR_TD]));
}

static void test_fopdt_and_integrator(void **state)
{
    (void)state;
    const double scale[5] = {0.01, 0.1, 0.02, 0.003, 0.0};
    pdt_ident_std_t s;
    make_cov(4, scale, &s);
    const pdt_model_t f = {.kind = PDT_MODEL_FOPDT, .p.fopdt = {2.0f, 5.0f, 1.3f}};
    pdt_ident_printed_t p;
    assert_int_equal(pdt_ident_std_printed(&f, &s, &p), PDT_OK);
    for (uint32_t i = 0; i < 4; i++) {
        static const pdt_ident_par_t par[4] = {PDT_IDENT_PAR_K, PDT_IDENT_PAR_TAU, PDT_IDENT_PAR_TD,
                                               PDT_IDENT_PAR_Y0};
        assert_close((double)p.std[par[i]], (double)s.std[i], 1e-6, 0.0);
    }
    /* Ki = k / a, T = 1 / a of k / (s (s + a)). */
    const double scale5[5] = {0.01, 0.02, 0.0, 0.05, 0.001};
    make_cov(5, scale5, &s);
    s.std[2] = 0;
    const pdt_model_t in = {.kind = PDT_MODEL_SOPDT, .p.sopdt = {0.5f, 0.25f, 0.0f, 1.0f}};
    assert_int_equal(pdt_ident_std_printed(&in, &s, &p), PDT_OK);
    assert_true((p.have >> PDT_IDENT_PAR_KI) & 1u);
    const double dKi_dk = 1.0 / 0.25, dKi_da = -0.5 / (0.25 * 0.25);
    const double var = dKi_dk * dKi_dk * (double)s.cov[0][0] +
                       2.0 * dKi_dk * dKi_da * (double)s.cov[0][1] +
                       dKi_da * dKi_da * (double)s.cov[1][1];
    assert_close((double)p.std[PDT_IDENT_PAR_KI], sqrt(var), 1e-5, 0.0);
}

static void test_statuses(void **state)
{
    (void)state;
    pdt_ident_std_t s;
    const double scale[5] = {1, 1, 1, 1, 1};
    make_cov(4, scale, &s);
    const pdt_model_t f = {.kind = PDT_MODEL_FOPDT, .p.fopdt = {2.0f, 5.0f, 1.3f}};
    const pdt_model_t bad = {.kind = PDT_MODEL_FOPDT, .p.fopdt = {2.0f, -5.0f, 1.3f}};
    pdt_ident_printed_t p, before;
    memset(&p, 0x5a, sizeof p);
    before = p;
    assert_int_equal(pdt_ident_std_printed(NULL, &s, &p), PDT_ERR_ARG);
    assert_int_equal(pdt_ident_std_printed(&f, NULL, &p), PDT_ERR_ARG);
    assert_int_equal(pdt_ident_std_printed(&f, &s, NULL), PDT_ERR_ARG);
    assert_int_equal(pdt_ident_std_printed(&bad, &s, &p), PDT_ERR_ARG);
    s.count = 5;
    assert_int_equal(pdt_ident_std_printed(&f, &s, &p), PDT_ERR_ARG);
    assert_memory_equal(&p, &before, sizeof p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sopdt_overdamped),
        cmocka_unit_test(test_sopdt_underdamped_and_undetermined),
        cmocka_unit_test(test_fopdt_and_integrator),
        cmocka_unit_test(test_statuses),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
