/*
 * Every status has a wording (pdt_status_str) and its enumerator's name
 * (pdt_status_name), both unique, for exactly the same contiguous range of
 * values: a status added to the enum but not to both switches fails here.
 */
#include "test_util.h"

static void test_names_and_wordings(void **state)
{
    (void)state;
    int lo = 2, hi = -100;
    for (int a = -100; a <= 2; a++) {
        const char *na = pdt_status_name((pdt_status_t)a);
        const char *wa = pdt_status_str((pdt_status_t)a);
        assert_non_null(na);
        assert_non_null(wa);
        bool known = strcmp(na, "PDT_STATUS_UNKNOWN") != 0;
        assert_int_equal(known, strcmp(wa, "unknown status") != 0);
        if (!known) {
            continue;
        }
        assert_true(strncmp(na, a > 0 ? "PDT_" : (a == 0 ? "PDT_OK" : "PDT_ERR_"),
                            a > 0 ? 4u : (a == 0 ? 6u : 8u)) == 0);
        lo = a < lo ? a : lo;
        hi = a > hi ? a : hi;
        for (int b = -100; b < a; b++) {
            if (strcmp(pdt_status_name((pdt_status_t)b), "PDT_STATUS_UNKNOWN") != 0) {
                assert_string_not_equal(na, pdt_status_name((pdt_status_t)b));
                assert_string_not_equal(wa, pdt_status_str((pdt_status_t)b));
            }
        }
    }
    assert_int_equal(hi, PDT_RUNNING);
    for (int a = lo; a <= hi; a++) {
        assert_string_not_equal(pdt_status_name((pdt_status_t)a), "PDT_STATUS_UNKNOWN");
    }
    assert_string_equal(pdt_status_name(PDT_OK), "PDT_OK");
    assert_string_equal(pdt_status_name(PDT_ERR_POOR_FIT), "PDT_ERR_POOR_FIT");
    assert_string_equal(pdt_status_name(PDT_ERR_MS_LIMIT), "PDT_ERR_MS_LIMIT");
    /* A refusal for robustness names the limit, not the fit. */
    assert_non_null(strstr(pdt_status_str(PDT_ERR_MS_LIMIT), "Ms"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_names_and_wordings),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
