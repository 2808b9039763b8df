/*
 * Tests of the real FFT against numpy.fft.rfft (tests/vectors/fft_vectors.h,
 * written by tools/vectorgen/fft.py), plus properties that need no
 * reference: round trip, Parseval, single tones, canaries, bad inputs.
 */
#include "test_util.h"

#include "fft_cases.h"

/* SNR the transforms must reach against the double-precision reference. */
#if PDT_REAL_DOUBLE
#define FFT_MIN_SNR_DB 250.0
/* Largest error allowed relative to the peak of the compared data. */
#define FFT_PEAK_RTOL  1e-12
#else
#define FFT_MIN_SNR_DB 100.0
#define FFT_PEAK_RTOL  1e-5
#endif

#define FFT_NMAX_VEC 8192u
#define FFT_NMAX     ((size_t)1u << PDT_FFT_MAX_LOG2)

/* Large buffers are static to keep them off the test's stack. */
static pdt_real_t g_work[FFT_NMAX / 2u + CANARY_COUNT];
static pdt_real_t g_buf[FFT_NMAX + CANARY_COUNT];
static pdt_real_t g_mag[FFT_NMAX / 2u + 1u + CANARY_COUNT];
static double g_ref[FFT_NMAX];

static void init_ok(pdt_fft_t *f, size_t n)
{
    size_t ws = pdt_fft_workspace_size(n);
    assert_int_equal(ws, PDT_FFT_WORKSPACE_SIZE(n));
    canary_fill(g_work + ws / sizeof(pdt_real_t), CANARY_COUNT);
    assert_int_equal(pdt_fft_init(f, n, g_work, ws), PDT_OK);
    canary_check(g_work + ws / sizeof(pdt_real_t), CANARY_COUNT);
}

static void load_input(const fft_case_t *c, pdt_real_t *buf)
{
    for (size_t j = 0; j < c->n; j++) {
        buf[j] = (pdt_real_t)c->q[j] / (pdt_real_t)FFT_VEC_DENOM;
    }
}

static void load_input_ref(const fft_case_t *c, double *ref)
{
    for (size_t j = 0; j < c->n; j++) {
        ref[j] = (double)c->q[j] / (double)FFT_VEC_DENOM;
    }
}

/* SNR at least FFT_MIN_SNR_DB and every element within FFT_PEAK_RTOL of the
 * reference's peak. */
static void check_against(const char *what, size_t n, const pdt_real_t *got, const double *ref,
                          size_t len)
{
    double snr = snr_db(got, ref, len);
    double peak = peak_abs(ref, len);
    double err = max_abs_err(got, ref, len);
    print_message("    %-10s n = %5zu: SNR %6.1f dB, max error / peak %.2e\n", what, n, snr,
                  err / peak);
    if (snr < FFT_MIN_SNR_DB) {
        fail_msg("%s n = %zu: SNR %.1f dB below %.1f dB", what, n, snr, FFT_MIN_SNR_DB);
    }
    for (size_t i = 0; i < len; i++) {
        assert_close(got[i], ref[i], 0.0, FFT_PEAK_RTOL * peak);
    }
}

static void test_workspace_size(void **state)
{
    (void)state;
    for (size_t n = 16u; n <= FFT_NMAX; n *= 2u) {
        assert_int_equal(pdt_fft_workspace_size(n), n / 2u * sizeof(pdt_real_t));
        assert_int_equal(pdt_fft_workspace_size(n), PDT_FFT_WORKSPACE_SIZE(n));
    }
    const size_t bad[] = {0u,
                          1u,
                          2u,
                          8u,
                          15u,
                          17u,
                          24u,
                          48u,
                          1000u,
                          FFT_NMAX - 1u,
                          FFT_NMAX + 1u,
                          2u * FFT_NMAX,
                          3u * FFT_NMAX / 2u};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        assert_int_equal(pdt_fft_workspace_size(bad[i]), 0u);
    }
}

static void test_forward_vectors(void **state)
{
    (void)state;
    for (size_t c = 0; c < FFT_NCASES; c++) {
        const fft_case_t *tc = &fft_cases[c];
        pdt_fft_t f;
        init_ok(&f, tc->n);
        load_input(tc, g_buf);
        canary_fill(g_buf + tc->n, CANARY_COUNT);
        assert_int_equal(pdt_fft_forward(&f, g_buf), PDT_OK);
        canary_check(g_buf + tc->n, CANARY_COUNT);
        check_against("forward", tc->n, g_buf, tc->spec, tc->n);
    }
}

static void test_inverse_vectors(void **state)
{
    (void)state;
    for (size_t c = 0; c < FFT_NCASES; c++) {
        const fft_case_t *tc = &fft_cases[c];
        pdt_fft_t f;
        init_ok(&f, tc->n);
        for (size_t i = 0; i < tc->n; i++) {
            g_buf[i] = (pdt_real_t)tc->spec[i];
        }
        canary_fill(g_buf + tc->n, CANARY_COUNT);
        assert_int_equal(pdt_fft_inverse(&f, g_buf), PDT_OK);
        canary_check(g_buf + tc->n, CANARY_COUNT);
        load_input_ref(tc, g_ref);
        check_against("inverse", tc->n, g_buf, g_ref, tc->n);
    }
}

static void test_round_trip(void **state)
{
    (void)state;
    for (size_t c = 0; c < FFT_NCASES; c++) {
        const fft_case_t *tc = &fft_cases[c];
        pdt_fft_t f;
        init_ok(&f, tc->n);
        load_input(tc, g_buf);
        canary_fill(g_buf + tc->n, CANARY_COUNT);
        assert_int_equal(pdt_fft_forward(&f, g_buf), PDT_OK);
        assert_int_equal(pdt_fft_inverse(&f, g_buf), PDT_OK);
        canary_check(g_buf + tc->n, CANARY_COUNT);
        load_input_ref(tc, g_ref);
        check_against("roundtrip", tc->n, g_buf, g_ref, tc->n);
    }
}

/* The largest size the build accepts (no stored vectors): a round trip of
 * the 8192-point input repeated, whose spectrum is that of 8192 points
 * scaled and spread to every (FFT_NMAX / 8192)-th bin. */
static void test_largest_size(void **state)
{
    (void)state;
    const fft_case_t *tc = &fft_cases[FFT_NCASES - 1u];
    const size_t n = FFT_NMAX;
    if (n < tc->n) {
        skip();
    }
    const size_t rep = n / tc->n;
    pdt_fft_t f;
    init_ok(&f, n);
    for (size_t r = 0; r < rep; r++) {
        load_input(tc, g_buf + r * tc->n);
    }
    canary_fill(g_buf + n, CANARY_COUNT);
    assert_int_equal(pdt_fft_forward(&f, g_buf), PDT_OK);
    canary_check(g_buf + n, CANARY_COUNT);

    /* Expected: X[k rep] = rep X8192[k], all other bins zero. */
    for (size_t i = 0; i < n; i++) {
        g_ref[i] = 0.0;
    }
    const double s = (double)rep;
    const size_t h = tc->n / 2u;
    g_ref[0] = s * tc->spec[0];
    g_ref[1] = s * tc->spec[1];
    for (size_t k = 1u; k < h; k++) {
        g_ref[2u * k * rep] = s * tc->spec[2u * k];
        g_ref[2u * k * rep + 1u] = s * tc->spec[2u * k + 1u];
    }
    check_against("forward", n, g_buf, g_ref, n);

    assert_int_equal(pdt_fft_inverse(&f, g_buf), PDT_OK);
    canary_check(g_buf + n, CANARY_COUNT);
    for (size_t r = 0; r < rep; r++) {
        load_input_ref(tc, g_ref + r * tc->n);
    }
    check_against("roundtrip", n, g_buf, g_ref, n);
}

/* sum x^2 = (X0^2 + X[n/2]^2 + 2 sum_{k=1}^{n/2-1} |X_k|^2) / n. */
static void test_parseval(void **state)
{
    (void)state;
    for (size_t c = 0; c < FFT_NCASES; c++) {
        const fft_case_t *tc = &fft_cases[c];
        pdt_fft_t f;
        init_ok(&f, tc->n);
        load_input(tc, g_buf);
        double ex = 0.0;
        for (size_t j = 0; j < tc->n; j++) {
            ex += (double)g_buf[j] * (double)g_buf[j];
        }
        assert_int_equal(pdt_fft_forward(&f, g_buf), PDT_OK);
        double es = (double)g_buf[0] * (double)g_buf[0] + (double)g_buf[1] * (double)g_buf[1];
        for (size_t i = 2u; i < tc->n; i++) {
            es += 2.0 * (double)g_buf[i] * (double)g_buf[i];
        }
        es /= (double)tc->n;
        assert_close(es, ex, FFT_PEAK_RTOL, 0.0);
    }
}

static void test_magnitude_vectors(void **state)
{
    (void)state;
    for (size_t c = 0; c < FFT_NCASES; c++) {
        const fft_case_t *tc = &fft_cases[c];
        const size_t nm = tc->n / 2u + 1u;
        pdt_fft_t f;
        init_ok(&f, tc->n);

        /* From numpy's spectrum: only the magnitude step is measured. */
        for (size_t i = 0; i < tc->n; i++) {
            g_buf[i] = (pdt_real_t)tc->spec[i];
        }
        canary_fill(g_buf + tc->n, CANARY_COUNT);
        canary_fill(g_mag + nm, CANARY_COUNT);
        assert_int_equal(pdt_fft_magnitude(&f, g_buf, g_mag), PDT_OK);
        canary_check(g_mag + nm, CANARY_COUNT);
        canary_check(g_buf + tc->n, CANARY_COUNT);
        for (size_t k = 0; k < nm; k++) {
            assert_close(g_mag[k], tc->mag[k], TEST_RTOL, 0.0);
        }
        /* The spectrum is only read. */
        for (size_t i = 0; i < tc->n; i++) {
            assert_true(g_buf[i] == (pdt_real_t)tc->spec[i]);
        }

        /* From the library's own forward transform. */
        load_input(tc, g_buf);
        assert_int_equal(pdt_fft_forward(&f, g_buf), PDT_OK);
        assert_int_equal(pdt_fft_magnitude(&f, g_buf, g_mag), PDT_OK);
        canary_check(g_mag + nm, CANARY_COUNT);
        check_against("magnitude", tc->n, g_mag, tc->mag, nm);

        /* In place gives the same numbers. */
        assert_int_equal(pdt_fft_magnitude(&f, g_buf, g_buf), PDT_OK);
        canary_check(g_buf + tc->n, CANARY_COUNT);
        for (size_t k = 0; k < nm; k++) {
            assert_true(g_buf[k] == g_mag[k]);
        }
    }
}

/* A tone on bin b: cos gives X[b] = n/2 (n at b = 0 and b = n/2), sin gives
 * Im X[b] = -n/2; every other packed value stays near zero. */
static void check_tone(const pdt_fft_t *f, size_t n, size_t b, bool sine)
{
    for (size_t j = 0; j < n; j++) {
        /* (j b) mod n keeps the argument of the double cos small and exact. */
        double a = 2.0 * 3.14159265358979323846 * (double)((j * b) % n) / (double)n;
        g_buf[j] = (pdt_real_t)(sine ? sin(a) : cos(a));
    }
    canary_fill(g_buf + n, CANARY_COUNT);
    assert_int_equal(pdt_fft_forward(f, g_buf), PDT_OK);
    canary_check(g_buf + n, CANARY_COUNT);

    for (size_t i = 0; i < n; i++) {
        g_ref[i] = 0.0;
    }
    const double half = (double)n / 2.0;
    if (b == 0u) {
        g_ref[0] = sine ? 0.0 : (double)n;
    } else if (b == n / 2u) {
        g_ref[1] = sine ? 0.0 : (double)n;
    } else if (sine) {
        g_ref[2u * b + 1u] = -half;
    } else {
        g_ref[2u * b] = half;
    }
    /* The input itself is rounded to the real type, so leakage into other
     * bins is of the order of that rounding times sqrt(n). */
    for (size_t i = 0; i < n; i++) {
        assert_close(g_buf[i], g_ref[i], 0.0, FFT_PEAK_RTOL * half);
    }

    assert_int_equal(pdt_fft_magnitude(f, g_buf, g_mag), PDT_OK);
    size_t best = 0u;
    for (size_t k = 1u; k <= n / 2u; k++) {
        if (g_mag[k] > g_mag[best]) {
            best = k;
        }
    }
    if (!(sine && (b == 0u || b == n / 2u))) {
        assert_int_equal(best, b);
    }
}

static void test_tones(void **state)
{
    (void)state;
    const size_t sizes[] = {16u, 64u, 1024u, FFT_NMAX};
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
        const size_t n = sizes[s];
        const size_t bins[] = {0u,     1u,          3u,          n / 8u + 1u, n / 4u - 1u,
                               n / 4u, n / 4u + 1u, n / 2u - 1u, n / 2u};
        pdt_fft_t f;
        init_ok(&f, n);
        for (size_t i = 0; i < sizeof bins / sizeof bins[0]; i++) {
            check_tone(&f, n, bins[i], false);
            check_tone(&f, n, bins[i], true);
        }
    }
}

/* Linearity in the packed layout, and an impulse gives a flat spectrum:
 * exercises every twiddle with a known answer. */
static void test_impulse(void **state)
{
    (void)state;
    const size_t n = 256u;
    pdt_fft_t f;
    init_ok(&f, n);
    for (size_t d = 0; d < 5u; d++) {
        for (size_t j = 0; j < n; j++) {
            g_buf[j] = (pdt_real_t)0;
        }
        g_buf[d] = (pdt_real_t)1;
        assert_int_equal(pdt_fft_forward(&f, g_buf), PDT_OK);
        /* X[k] = e^{-2 pi i k d / n} */
        for (size_t k = 1u; k < n / 2u; k++) {
            double a = 2.0 * 3.14159265358979323846 * (double)((k * d) % n) / (double)n;
            assert_close(g_buf[2u * k], cos(a), 0.0, FFT_PEAK_RTOL);
            assert_close(g_buf[2u * k + 1u], -sin(a), 0.0, FFT_PEAK_RTOL);
        }
        assert_close(g_buf[0], 1.0, 0.0, FFT_PEAK_RTOL);
        assert_close(g_buf[1], (d % 2u) ? -1.0 : 1.0, 0.0, FFT_PEAK_RTOL);
    }
}

static void test_init_errors(void **state)
{
    (void)state;
    pdt_fft_t f;
    pdt_fft_t before;
    memset(&f, 0xA5, sizeof f);
    memcpy(&before, &f, sizeof f);
    const size_t n = 64u;
    const size_t ws = pdt_fft_workspace_size(n);
    const size_t wn = ws / sizeof(pdt_real_t);
    canary_fill(g_work, wn + CANARY_COUNT);

    assert_int_equal(pdt_fft_init(NULL, n, g_work, ws), PDT_ERR_ARG);

    const size_t bad_n[] = {0u, 8u, 15u, 17u, 48u, 100u, FFT_NMAX + 1u, 2u * FFT_NMAX};
    for (size_t i = 0; i < sizeof bad_n / sizeof bad_n[0]; i++) {
        assert_int_equal(pdt_fft_init(&f, bad_n[i], g_work, sizeof g_work), PDT_ERR_LENGTH);
    }
    assert_int_equal(pdt_fft_init(&f, n, NULL, ws), PDT_ERR_NOMEM);
    assert_int_equal(pdt_fft_init(&f, n, g_work, ws - 1u), PDT_ERR_NOMEM);
    assert_int_equal(pdt_fft_init(&f, n, g_work, ws - sizeof(pdt_real_t)), PDT_ERR_NOMEM);
    assert_int_equal(pdt_fft_init(&f, n, g_work, 0u), PDT_ERR_NOMEM);
    /* Misaligned by one byte, with plenty of room. */
    assert_int_equal(pdt_fft_init(&f, n, (unsigned char *)g_work + 1, ws + 64u), PDT_ERR_ARG);

    assert_memory_equal(&f, &before, sizeof f);
    canary_check(g_work, wn + CANARY_COUNT);

    /* Exactly the queried size is enough. */
    assert_int_equal(pdt_fft_init(&f, n, g_work, ws), PDT_OK);
    canary_check(g_work + wn, CANARY_COUNT);
}

static void test_transform_errors(void **state)
{
    (void)state;
    const size_t n = 32u;
    pdt_fft_t f;
    init_ok(&f, n);
    pdt_fft_t zero;
    memset(&zero, 0, sizeof zero);
    pdt_fft_t no_table = f;
    no_table.twid = NULL;
    pdt_fft_t bad_n = f;
    bad_n.n = 24u;

    const pdt_fft_t *bad[] = {NULL, &zero, &no_table, &bad_n};
    canary_fill(g_buf, n + CANARY_COUNT);
    canary_fill(g_mag, n / 2u + 1u + CANARY_COUNT);
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        assert_int_equal(pdt_fft_forward(bad[i], g_buf), PDT_ERR_ARG);
        assert_int_equal(pdt_fft_inverse(bad[i], g_buf), PDT_ERR_ARG);
        assert_int_equal(pdt_fft_magnitude(bad[i], g_buf, g_mag), PDT_ERR_ARG);
    }
    assert_int_equal(pdt_fft_forward(&f, NULL), PDT_ERR_ARG);
    assert_int_equal(pdt_fft_inverse(&f, NULL), PDT_ERR_ARG);
    assert_int_equal(pdt_fft_magnitude(&f, NULL, g_mag), PDT_ERR_ARG);
    assert_int_equal(pdt_fft_magnitude(&f, g_buf, NULL), PDT_ERR_ARG);
    canary_check(g_buf, n + CANARY_COUNT);
    canary_check(g_mag, n / 2u + 1u + CANARY_COUNT);
}

/* Transforms read the instance and its table only: one table serves many
 * transforms, and a copy of the instance works the same. */
static void test_table_constant(void **state)
{
    (void)state;
    const size_t n = 128u;
    const size_t wn = n / 2u;
    pdt_fft_t f;
    init_ok(&f, n);
    pdt_real_t saved[64];
    memcpy(saved, g_work, sizeof saved);
    assert_int_equal(wn, sizeof saved / sizeof saved[0]);

    const fft_case_t *tc = &fft_cases[3];
    assert_int_equal(tc->n, n);
    pdt_fft_t copy = f;
    load_input(tc, g_buf);
    assert_int_equal(pdt_fft_forward(&copy, g_buf), PDT_OK);
    assert_int_equal(pdt_fft_magnitude(&f, g_buf, g_mag), PDT_OK);
    assert_int_equal(pdt_fft_inverse(&f, g_buf), PDT_OK);
    assert_memory_equal(saved, g_work, sizeof saved);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_workspace_size),    cmocka_unit_test(test_forward_vectors),
        cmocka_unit_test(test_inverse_vectors),   cmocka_unit_test(test_round_trip),
        cmocka_unit_test(test_largest_size),      cmocka_unit_test(test_parseval),
        cmocka_unit_test(test_magnitude_vectors), cmocka_unit_test(test_tones),
        cmocka_unit_test(test_impulse),           cmocka_unit_test(test_init_errors),
        cmocka_unit_test(test_transform_errors),  cmocka_unit_test(test_table_constant),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
