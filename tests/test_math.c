/*
 * Tests of lib/src/pdt_math.c, the library's expm1 and log1p for C
 * libraries without them (PDT_MATH_FALLBACK, pdt_config.h; avr-libc's
 * case): against numpy over the arguments the library passes
 * (math_vectors.h), in ulps of the real type, in every host build whatever
 * the configuration selects; and the special values.
 */
#include "test_util.h"

#include "pdt_internal.h"

#include "math_vectors.h"

/* Most error allowed, in units of the real type's epsilon relative to the
 * reference: Kahan's forms are good to a few ulps with the host's exp and
 * log. The float build's cost and discretisation vectors (COEF_RTOL 5e-6,
 * 40 ulps) ask for less. */
#define MATH_ULPS 4.0

static double ulps(double got, double want)
{
    double scale = fabs(want) > 0.0 ? fabs(want) : 1.0;
    return fabs(got - want) / (scale * (double)PDT_REAL_EPS);
}

static void check_table(pdt_real_t (*fn)(pdt_real_t), const double *x, const double *y, size_t n,
                        const char *name)
{
    double worst = 0.0;
    size_t at = 0u;
    for (size_t i = 0; i < n; i++) {
        const double got = (double)fn((pdt_real_t)x[i]);
        const double e = ulps(got, y[i]);
        if (!(e <= worst)) {
            worst = e;
            at = i;
        }
    }
    printf("%s: %zu arguments, largest error %.2f ulps at x = %.9g\n", name, n, worst, x[at]);
    if (!(worst <= MATH_ULPS)) {
        fail_msg("%s(%.9g): %.2f ulps (max %.0f)", name, x[at], worst, MATH_ULPS);
    }
}

static void test_expm1_vectors(void **state)
{
    (void)state;
    check_table(pdt_math_expm1, math_expm1_x, math_expm1_y, MATH_EXPM1_COUNT, "pdt_math_expm1");
}

static void test_log1p_vectors(void **state)
{
    (void)state;
    check_table(pdt_math_log1p, math_log1p_x, math_log1p_y, MATH_LOG1P_COUNT, "pdt_math_log1p");
}

/* What the configuration selects (the C library's or the fallback) meets
 * the same bound. */
static pdt_real_t selected_expm1(pdt_real_t x)
{
    return pdt_expm1(x);
}

static pdt_real_t selected_log1p(pdt_real_t x)
{
    return pdt_log1p(x);
}

static void test_selected_vectors(void **state)
{
    (void)state;
    check_table(selected_expm1, math_expm1_x, math_expm1_y, MATH_EXPM1_COUNT, "pdt_expm1");
    check_table(selected_log1p, math_log1p_x, math_log1p_y, MATH_LOG1P_COUNT, "pdt_log1p");
}

static void test_special_values(void **state)
{
    (void)state;
    const pdt_real_t inf = (pdt_real_t)INFINITY;
    /* zeros keep their sign */
    assert_true(pdt_math_expm1((pdt_real_t)0.0) == (pdt_real_t)0.0);
    assert_true(signbit(pdt_math_expm1((pdt_real_t)-0.0)) != 0);
    assert_true(pdt_math_log1p((pdt_real_t)0.0) == (pdt_real_t)0.0);
    assert_true(signbit(pdt_math_log1p((pdt_real_t)-0.0)) != 0);
    /* expm1: -1 far below 0 and at -inf, +inf above the range and at +inf */
    assert_true(pdt_math_expm1((pdt_real_t)-1000.0) == (pdt_real_t)-1.0);
    assert_true(pdt_math_expm1(-inf) == (pdt_real_t)-1.0);
    assert_true(pdt_math_expm1((pdt_real_t)1000.0) == inf);
    assert_true(pdt_math_expm1(inf) == inf);
    /* log1p: -inf at -1, NaN below, +inf at +inf */
    assert_true(pdt_math_log1p((pdt_real_t)-1.0) == -inf);
    assert_true(isnan(pdt_math_log1p((pdt_real_t)-2.0)));
    assert_true(pdt_math_log1p(inf) == inf);
    /* NaN in, NaN out */
    assert_true(isnan(pdt_math_expm1((pdt_real_t)NAN)));
    assert_true(isnan(pdt_math_log1p((pdt_real_t)NAN)));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_expm1_vectors),
        cmocka_unit_test(test_log1p_vectors),
        cmocka_unit_test(test_selected_vectors),
        cmocka_unit_test(test_special_values),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
