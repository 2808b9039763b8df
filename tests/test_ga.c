/*
 * Tests of the GA operators (lib/src/pdt_ga.h) against the numpy reference
 * (tests/vectors/ga_vectors.h, written by tools/vectorgen/ga.py), plus their
 * properties: bounds, finiteness on edge cases, mean preservation and
 * spread of SBX, niche-count limits, tie handling.
 *
 * The operators have no status to return: their preconditions (lo < hi,
 * eta > 0, u in [0, 1), n >= 1) are programmer errors guarded by
 * PDT_ASSERT. What the tests check instead is that inputs at the edges of
 * those preconditions still give finite values inside the bounds.
 */
#include "test_util.h"

#include "pdt_ga.h"
#include "pdt_internal.h"

#include "ga_vectors.h"

/* SBX and mutation against the double reference. The error is measured
 * relative to max(|want|, |lo|, |hi|): the inputs are themselves known to
 * the build's precision relative to their magnitude, and the children are
 * sums mid +- spread whose rounding scales with the bounds, not with the
 * (possibly near-zero) result. With that scale the float build stays within
 * 1e-5; the spread factor's pow(beta, -(eta + 1)) multiplies the rounding of
 * beta by eta + 1 (up to 101 here), but the final root to 1/(eta + 1) divides
 * it back out. */
#if PDT_REAL_DOUBLE
#define GA_RTOL 1e-12
#else
#define GA_RTOL 1e-5
#endif

/* Worst errors seen, printed at the end of each vector test. */
typedef struct err_track {
    double worst_scaled;
    double worst_plain;
} err_track_t;

static void check_close(err_track_t *t, pdt_real_t got, double want, double lo, double hi,
                        const char *what, size_t idx)
{
    double scale = fmax(fabs(want), fmax(fabs(lo), fabs(hi)));
    double err = fabs((double)got - want);
    double scaled = scale > 0.0 ? err / scale : err;
    double plain = want != 0.0 ? err / fabs(want) : err;
    t->worst_scaled = fmax(t->worst_scaled, scaled);
    t->worst_plain = fmax(t->worst_plain, plain);
    if (!(scaled <= GA_RTOL)) {
        fail_msg("%s case %zu: got %.17g, want %.17g (error / scale %.3g)", what, idx, (double)got,
                 want, scaled);
    }
}

static void report(const char *what, const err_track_t *t)
{
    print_message("    %-14s worst error / max(|want|, |lo|, |hi|) %.2e, / |want| %.2e\n", what,
                  t->worst_scaled, t->worst_plain);
}

/* ---- PCG32 ------------------------------------------------------------ */

static void test_pcg_demo_values(void **state)
{
    (void)state;
    static const uint32_t want[6] = {0xa15c02b7u, 0x7b47f409u, 0xba1d3330u,
                                     0x83d2f293u, 0xbfa4784bu, 0xcbed606eu};
    pdt_rng_t r;
    pdt_rng_seed(&r, 42u, 54u);
    for (size_t i = 0; i < 6u; i++) {
        assert_int_equal(pdt_rng_u32(&r), want[i]);
    }
}

static void test_pcg_vectors(void **state)
{
    (void)state;
    for (size_t p = 0; p < GA_PCG_PAIRS; p++) {
        pdt_rng_t r;
        pdt_rng_seed(&r, ga_pcg_seed[p], ga_pcg_stream[p]);
        for (size_t i = 0; i < GA_PCG_COUNT; i++) {
            assert_int_equal(pdt_rng_u32(&r), ga_pcg_out[p * GA_PCG_COUNT + i]);
        }
        pdt_rng_seed(&r, ga_pcg_seed[p], ga_pcg_stream[p]);
        for (size_t i = 0; i < GA_PCG_COUNT; i++) {
#if PDT_REAL_DOUBLE
            double want = ga_pcg_unif_d[p * GA_PCG_COUNT + i];
#else
            double want = ga_pcg_unif_f[p * GA_PCG_COUNT + i];
#endif
            /* exact: the scaling is a power of two of an integer that fits */
            assert_true((double)pdt_rng_uniform(&r) == want);
        }
    }
}

static void test_uniform_largest_draw_below_one(void **state)
{
    (void)state;
    /* A state whose next output is 0xffffffff: bits 41..58 set makes the
     * xorshifted word all ones with a zero rotation. */
    pdt_rng_t r = {UINT64_C(0x07fffe0000000000), 1u};
    pdt_rng_t r2 = r;
    assert_int_equal(pdt_rng_u32(&r), 0xffffffffu);
    pdt_real_t u = pdt_rng_uniform(&r2);
    assert_true(u < PDT_R(1.0));
#if PDT_REAL_DOUBLE
    assert_true(u == 1.0 - 0x1p-32);
#else
    assert_true(u == 1.0f - 0x1p-24f);
#endif
}

static void test_uniform_statistics(void **state)
{
    (void)state;
    pdt_rng_t r;
    pdt_rng_seed(&r, 12345u, 678u);
    const size_t n = 100000u;
    double sum = 0.0;
    size_t bins[10] = {0};
    for (size_t i = 0; i < n; i++) {
        pdt_real_t u = pdt_rng_uniform(&r);
        assert_true(u >= PDT_R(0.0) && u < PDT_R(1.0));
        sum += (double)u;
        bins[(size_t)((double)u * 10.0)]++;
    }
    assert_close(sum / (double)n, 0.5, 0.0, 0.005);
    for (size_t b = 0; b < 10u; b++) {
        /* 10000 expected, sd about 95 */
        assert_in_range(bins[b], 9500u, 10500u);
    }
}

static void test_below_vectors(void **state)
{
    (void)state;
    for (size_t k = 0; k < GA_BELOW_CASES; k++) {
        pdt_rng_t r;
        pdt_rng_seed(&r, GA_BELOW_SEED + k, GA_BELOW_STREAM);
        for (size_t i = 0; i < GA_BELOW_COUNT; i++) {
            uint32_t v = pdt_rng_below(&r, ga_below_n[k]);
            assert_int_equal(v, ga_below_out[k * GA_BELOW_COUNT + i]);
            assert_true(v < ga_below_n[k]);
        }
    }
}

static void test_below_properties(void **state)
{
    (void)state;
    pdt_rng_t r;
    pdt_rng_seed(&r, 99u, 5u);
    pdt_rng_t before = r;
    /* n = 1 needs no random bits */
    assert_int_equal(pdt_rng_below(&r, 1u), 0u);
    assert_true(r.state == before.state);
    size_t counts[6] = {0};
    for (size_t i = 0; i < 60000u; i++) {
        uint32_t v = pdt_rng_below(&r, 6u);
        assert_true(v < 6u);
        counts[v]++;
    }
    for (size_t b = 0; b < 6u; b++) {
        assert_in_range(counts[b], 9500u, 10500u);
    }
    /* n = 2^31 + 1 rejects almost half of the draws; unbiased means the
     * upper half of the range is hit as often as the lower half. */
    size_t upper = 0;
    for (size_t i = 0; i < 20000u; i++) {
        upper += pdt_rng_below(&r, 0x80000001u) >= 0x40000000u ? 1u : 0u;
    }
    assert_in_range(upper, 9600u, 10400u);
}

/* ---- SBX ---------------------------------------------------------------- */

static void test_sbx_grid(void **state)
{
    (void)state;
    err_track_t t = {0.0, 0.0};
    size_t idx = 0;
    for (size_t bi = 0; bi < GA_NBOUNDS; bi++) {
        pdt_real_t lo = (pdt_real_t)ga_lo[bi];
        pdt_real_t hi = (pdt_real_t)ga_hi[bi];
        for (size_t pi = 0; pi < GA_SBX_NPAIRS; pi++) {
            pdt_real_t p1 = (pdt_real_t)ga_sbx_p1[bi * GA_SBX_NPAIRS + pi];
            pdt_real_t p2 = (pdt_real_t)ga_sbx_p2[bi * GA_SBX_NPAIRS + pi];
            for (size_t ei = 0; ei < GA_NETA; ei++) {
                for (size_t ui = 0; ui < GA_SBX_NU; ui++, idx++) {
                    pdt_real_t c[2 + CANARY_COUNT];
                    canary_fill(c, 2 + CANARY_COUNT);
                    pdt_ga_sbx(p1, p2, lo, hi, (pdt_real_t)ga_eta[ei], (pdt_real_t)ga_sbx_u[ui],
                               &c[0], &c[1]);
                    canary_check(c + 2, CANARY_COUNT);
                    check_close(&t, c[0], ga_sbx_c[2u * idx], ga_lo[bi], ga_hi[bi], "sbx c1", idx);
                    check_close(&t, c[1], ga_sbx_c[2u * idx + 1u], ga_lo[bi], ga_hi[bi], "sbx c2",
                                idx);
                }
            }
        }
    }
    report("sbx grid", &t);
}

static void test_sbx_random(void **state)
{
    (void)state;
    err_track_t t = {0.0, 0.0};
    for (size_t i = 0; i < GA_SBX_NRAND; i++) {
        const double *row = ga_sbx_rand + 8u * i;
        pdt_real_t c1;
        pdt_real_t c2;
        pdt_ga_sbx((pdt_real_t)row[0], (pdt_real_t)row[1], (pdt_real_t)row[2], (pdt_real_t)row[3],
                   (pdt_real_t)row[4], (pdt_real_t)row[5], &c1, &c2);
        check_close(&t, c1, row[6], row[2], row[3], "sbx random c1", i);
        check_close(&t, c2, row[7], row[2], row[3], "sbx random c2", i);
    }
    report("sbx random", &t);
}

/* Largest u the build's uniform numbers can take, and a few in between. */
#define GA_U_TOP (PDT_R(1.0) - PDT_REAL_EPS * PDT_R(0.5))
static const pdt_real_t edge_u[] = {PDT_R(0.0),       PDT_R(1e-30),     PDT_R(1e-7), PDT_R(0.25),
                                    PDT_R(0.5),       PDT_R(0.5000001), PDT_R(0.75), PDT_R(0.999),
                                    PDT_R(0.9999999), GA_U_TOP};
#define GA_NEDGE_U (sizeof edge_u / sizeof edge_u[0])

static const pdt_real_t edge_eta[] = {PDT_R(1e-3),  PDT_R(1.0),  PDT_R(2.0),
                                      PDT_R(5.0),   PDT_R(20.0), PDT_R(50.0),
                                      PDT_R(100.0), PDT_R(1e6),  PDT_R(1e30)};
#define GA_NEDGE_ETA (sizeof edge_eta / sizeof edge_eta[0])

/* Bounds including tiny ranges, a range far from zero and a denormal one. */
static const pdt_real_t edge_lo[] = {PDT_R(0.0),  PDT_R(-1e-30), PDT_R(100.0),
                                     PDT_R(-1e6), PDT_R(1.0),    PDT_R(0.0)};
static const pdt_real_t edge_hi[] = {PDT_R(1.0), PDT_R(1e-30),     PDT_R(100.0001),
                                     PDT_R(1e6), PDT_R(1.0000005), PDT_R(1e-40)};
#define GA_NEDGE_B (sizeof edge_lo / sizeof edge_lo[0])

static void test_sbx_edges_finite_inside(void **state)
{
    (void)state;
    /* Parent positions as fractions of the range: on the bounds, equal,
     * one step apart, reversed. */
    static const pdt_real_t fa[] = {PDT_R(0.0), PDT_R(1.0), PDT_R(0.0), PDT_R(0.5),
                                    PDT_R(0.3), PDT_R(1.0), PDT_R(0.0), PDT_R(0.999999)};
    static const pdt_real_t fb[] = {PDT_R(1.0),       PDT_R(0.0), PDT_R(0.0),  PDT_R(0.5),
                                    PDT_R(0.3000001), PDT_R(1.0), PDT_R(1e-7), PDT_R(1.0)};
    size_t checked = 0;
    for (size_t bi = 0; bi < GA_NEDGE_B; bi++) {
        pdt_real_t lo = edge_lo[bi];
        pdt_real_t hi = edge_hi[bi];
        assert_true(lo < hi);
        for (size_t pi = 0; pi < sizeof fa / sizeof fa[0]; pi++) {
            pdt_real_t p1 = fa[pi] >= PDT_R(1.0) ? hi : lo + fa[pi] * (hi - lo);
            pdt_real_t p2 = fb[pi] >= PDT_R(1.0) ? hi : lo + fb[pi] * (hi - lo);
            assert_true(p1 >= lo && p1 <= hi && p2 >= lo && p2 <= hi);
            for (size_t ei = 0; ei < GA_NEDGE_ETA; ei++) {
                for (size_t ui = 0; ui < GA_NEDGE_U; ui++) {
                    pdt_real_t c1 = PDT_R(-7.0);
                    pdt_real_t c2 = PDT_R(-7.0);
                    pdt_ga_sbx(p1, p2, lo, hi, edge_eta[ei], edge_u[ui], &c1, &c2);
                    if (!(isfinite(c1) && isfinite(c2) && c1 >= lo && c1 <= hi && c2 >= lo &&
                          c2 <= hi && c1 <= c2)) {
                        fail_msg("sbx p1 %.9g p2 %.9g [%.9g, %.9g] eta %g u %.9g -> %.9g %.9g",
                                 (double)p1, (double)p2, (double)lo, (double)hi,
                                 (double)edge_eta[ei], (double)edge_u[ui], (double)c1, (double)c2);
                    }
                    checked++;
                }
            }
        }
    }
    print_message("    sbx edge cases: %zu, all finite, inside the bounds, c1 <= c2\n", checked);
}

static void test_sbx_equal_parents_copied(void **state)
{
    (void)state;
    pdt_real_t c1;
    pdt_real_t c2;
    pdt_ga_sbx(PDT_R(0.25), PDT_R(0.25), PDT_R(0.0), PDT_R(1.0), PDT_R(15.0), PDT_R(0.9), &c1, &c2);
    assert_true(c1 == PDT_R(0.25) && c2 == PDT_R(0.25));
    /* ordered: c1 the lower parent */
    pdt_ga_sbx(PDT_R(0.75), PDT_R(0.25), PDT_R(0.0), PDT_R(1.0), PDT_R(15.0), PDT_R(0.0), &c1, &c2);
    assert_true(c1 == PDT_R(0.5) && c2 == PDT_R(0.5)); /* u = 0: both at the mean */
    pdt_ga_sbx(PDT_R(0.75), PDT_R(0.25), PDT_R(0.0), PDT_R(1.0), PDT_R(15.0), PDT_R(0.9), &c1, &c2);
    assert_true(c1 < PDT_R(0.25) && c2 > PDT_R(0.75));
}

static void test_sbx_mean_preserved(void **state)
{
    (void)state;
    /* Bounds far away: both children get the same spread factor, so the
     * mean is kept for every u (up to rounding). */
    for (size_t i = 0; i < 1000u; i++) {
        pdt_real_t u = (pdt_real_t)i / PDT_R(1000.0);
        pdt_real_t c1;
        pdt_real_t c2;
        pdt_ga_sbx(PDT_R(0.4), PDT_R(0.6), PDT_R(-1e6), PDT_R(1e6), PDT_R(2.0), u, &c1, &c2);
        assert_close(PDT_R(0.5) * (c1 + c2), 0.5, 0.0, 1e6 * (double)PDT_REAL_EPS);
    }
    /* Bounds in reach of a few children: over many u the average child is
     * still the parents' mean. */
    double sum = 0.0;
    const size_t n = 10000u;
    for (size_t i = 0; i < n; i++) {
        pdt_real_t u = ((pdt_real_t)i + PDT_R(0.5)) / (pdt_real_t)n;
        pdt_real_t c1;
        pdt_real_t c2;
        pdt_ga_sbx(PDT_R(0.45), PDT_R(0.55), PDT_R(0.0), PDT_R(1.0), PDT_R(10.0), u, &c1, &c2);
        sum += (double)c1 + (double)c2;
    }
    assert_close(sum / (2.0 * (double)n), 0.5, 0.0, 1e-4);
}

static void test_sbx_spread_grows_as_eta_falls(void **state)
{
    (void)state;
    static const pdt_real_t etas[] = {PDT_R(100.0), PDT_R(50.0), PDT_R(20.0), PDT_R(15.0),
                                      PDT_R(5.0),   PDT_R(2.0),  PDT_R(1.0)};
    double prev = 0.0;
    for (size_t e = 0; e < sizeof etas / sizeof etas[0]; e++) {
        double spread = 0.0;
        for (size_t i = 0; i < 4096u; i++) {
            pdt_real_t u = ((pdt_real_t)i + PDT_R(0.5)) / PDT_R(4096.0);
            pdt_real_t c1;
            pdt_real_t c2;
            pdt_ga_sbx(PDT_R(0.4), PDT_R(0.6), PDT_R(0.0), PDT_R(1.0), etas[e], u, &c1, &c2);
            spread += (double)(c2 - c1);
        }
        assert_true(spread > prev);
        prev = spread;
    }
}

/* ---- polynomial mutation ---------------------------------------------- */

static void test_mutate_grid(void **state)
{
    (void)state;
    err_track_t t = {0.0, 0.0};
    size_t idx = 0;
    for (size_t bi = 0; bi < GA_NBOUNDS; bi++) {
        for (size_t xi = 0; xi < GA_MUT_NX; xi++) {
            pdt_real_t x = (pdt_real_t)ga_mut_x[bi * GA_MUT_NX + xi];
            for (size_t ei = 0; ei < GA_NETA; ei++) {
                for (size_t ui = 0; ui < GA_MUT_NU; ui++, idx++) {
                    pdt_real_t y = pdt_ga_mutate(x, (pdt_real_t)ga_lo[bi], (pdt_real_t)ga_hi[bi],
                                                 (pdt_real_t)ga_eta[ei], (pdt_real_t)ga_mut_u[ui]);
                    check_close(&t, y, ga_mut_y[idx], ga_lo[bi], ga_hi[bi], "mutate", idx);
                }
            }
        }
    }
    report("mutate grid", &t);
}

static void test_mutate_random(void **state)
{
    (void)state;
    err_track_t t = {0.0, 0.0};
    for (size_t i = 0; i < GA_MUT_NRAND; i++) {
        const double *row = ga_mut_rand + 6u * i;
        pdt_real_t y = pdt_ga_mutate((pdt_real_t)row[0], (pdt_real_t)row[1], (pdt_real_t)row[2],
                                     (pdt_real_t)row[3], (pdt_real_t)row[4]);
        check_close(&t, y, row[5], row[1], row[2], "mutate random", i);
    }
    report("mutate random", &t);
}

static void test_mutate_edges_finite_inside(void **state)
{
    (void)state;
    static const pdt_real_t fx[] = {PDT_R(0.0), PDT_R(1e-7), PDT_R(0.5), PDT_R(0.9999999),
                                    PDT_R(1.0)};
    size_t checked = 0;
    for (size_t bi = 0; bi < GA_NEDGE_B; bi++) {
        pdt_real_t lo = edge_lo[bi];
        pdt_real_t hi = edge_hi[bi];
        for (size_t xi = 0; xi < sizeof fx / sizeof fx[0]; xi++) {
            pdt_real_t x = fx[xi] >= PDT_R(1.0) ? hi : lo + fx[xi] * (hi - lo);
            for (size_t ei = 0; ei < GA_NEDGE_ETA; ei++) {
                for (size_t ui = 0; ui < GA_NEDGE_U; ui++) {
                    pdt_real_t y = pdt_ga_mutate(x, lo, hi, edge_eta[ei], edge_u[ui]);
                    if (!(isfinite(y) && y >= lo && y <= hi)) {
                        fail_msg("mutate x %.9g [%.9g, %.9g] eta %g u %.9g -> %.9g", (double)x,
                                 (double)lo, (double)hi, (double)edge_eta[ei], (double)edge_u[ui],
                                 (double)y);
                    }
                    checked++;
                }
                /* u = 1/2 is the centre of the distribution: no change */
                assert_true(pdt_ga_mutate(x, lo, hi, edge_eta[ei], PDT_R(0.5)) == x);
            }
        }
    }
    print_message("    mutation edge cases: %zu, all finite and inside the bounds\n", checked);
}

static void test_mutate_direction_and_reach(void **state)
{
    (void)state;
    /* u = 0 moves to the lower bound, u -> 1 to (nearly) the upper one;
     * small u moves down, large u moves up. */
    assert_true(pdt_ga_mutate(PDT_R(0.3), PDT_R(0.0), PDT_R(1.0), PDT_R(20.0), PDT_R(0.0)) ==
                PDT_R(0.0));
    assert_true(pdt_ga_mutate(PDT_R(0.3), PDT_R(0.0), PDT_R(1.0), PDT_R(20.0), PDT_R(0.2)) <
                PDT_R(0.3));
    assert_true(pdt_ga_mutate(PDT_R(0.3), PDT_R(0.0), PDT_R(1.0), PDT_R(20.0), PDT_R(0.8)) >
                PDT_R(0.3));
    assert_true(pdt_ga_mutate(PDT_R(0.3), PDT_R(0.0), PDT_R(1.0), PDT_R(1.0), GA_U_TOP) >
                PDT_R(0.99));
}

/* ---- fitness sharing ---------------------------------------------------- */

#define GA_SHARE_NMAX 16u

static void test_share_vectors(void **state)
{
    (void)state;
    size_t og = 0;
    size_t ob = 0;
    size_t oc = 0;
    double worst = 0.0;
    for (size_t c = 0; c < GA_SHARE_CASES; c++) {
        size_t n = ga_share_n[c];
        size_t g = ga_share_g[c];
        assert_true(n <= GA_SHARE_NMAX && n * g <= 64u && g <= 8u);
        pdt_real_t genes[64];
        pdt_real_t lo[8];
        pdt_real_t hi[8];
        pdt_real_t cost[GA_SHARE_NMAX];
        pdt_real_t shared[GA_SHARE_NMAX + CANARY_COUNT];
        for (size_t i = 0; i < n * g; i++) {
            genes[i] = (pdt_real_t)ga_share_genes[og + i];
        }
        for (size_t k = 0; k < g; k++) {
            lo[k] = (pdt_real_t)ga_share_lo[ob + k];
            hi[k] = (pdt_real_t)ga_share_hi[ob + k];
        }
        for (size_t i = 0; i < n; i++) {
            cost[i] = (pdt_real_t)ga_share_cost[oc + i];
        }
        canary_fill(shared, GA_SHARE_NMAX + CANARY_COUNT);
        pdt_ga_share(genes, n, g, lo, hi, cost, (pdt_real_t)ga_share_sigma[c],
                     (pdt_real_t)ga_share_alpha[c], shared);
        canary_check(shared + n, CANARY_COUNT);
        for (size_t i = 0; i < n; i++) {
            double want = ga_share_want[oc + i];
            /* m_i is a sum of n terms each within a few eps of the
             * reference; compare relative to cost_i n. */
            double scale = ga_share_cost[oc + i] * (double)n;
            assert_close(shared[i], want, 0.0, GA_RTOL * scale);
            assert_true(shared[i] >= cost[i]);
            if (scale > 0.0) {
                worst = fmax(worst, fabs((double)shared[i] - want) / scale);
            }
        }
        og += n * g;
        ob += g;
        oc += n;
    }
    print_message("    share: worst error / (cost n) %.2e\n", worst);
}

static void test_share_properties(void **state)
{
    (void)state;
    pdt_real_t lo[3] = {PDT_R(-1.0), PDT_R(0.0), PDT_R(10.0)};
    pdt_real_t hi[3] = {PDT_R(1.0), PDT_R(5.0), PDT_R(20.0)};
    pdt_real_t cost[8];
    pdt_real_t shared[8 + CANARY_COUNT];
    pdt_real_t genes[8 * 3];

    /* identical individuals: m = n */
    for (size_t i = 0; i < 8u; i++) {
        genes[3u * i] = PDT_R(0.25);
        genes[3u * i + 1u] = PDT_R(2.0);
        genes[3u * i + 2u] = PDT_R(13.0);
        cost[i] = (pdt_real_t)(i + 1u);
    }
    canary_fill(shared, 8 + CANARY_COUNT);
    pdt_ga_share(genes, 8u, 3u, lo, hi, cost, PDT_R(0.1), PDT_R(2.0), shared);
    canary_check(shared + 8, CANARY_COUNT);
    for (size_t i = 0; i < 8u; i++) {
        assert_true(shared[i] == PDT_R(8.0) * cost[i]);
    }

    /* corners of the box: normalised distances >= 1, beyond sigma = 0.9 */
    for (size_t i = 0; i < 8u; i++) {
        for (size_t k = 0; k < 3u; k++) {
            genes[3u * i + k] = ((i >> k) & 1u) ? hi[k] : lo[k];
        }
    }
    canary_fill(shared, 8 + CANARY_COUNT);
    pdt_ga_share(genes, 8u, 3u, lo, hi, cost, PDT_R(0.9), PDT_R(1.0), shared);
    canary_check(shared + 8, CANARY_COUNT);
    for (size_t i = 0; i < 8u; i++) {
        assert_true(shared[i] == cost[i]);
    }

    /* in place (shared is the cost array), against a separate output; and
     * 1 <= m_i <= n for a spread population */
    pdt_rng_t r;
    pdt_rng_seed(&r, 5u, 6u);
    for (size_t i = 0; i < 8u * 3u; i++) {
        size_t k = i % 3u;
        genes[i] = lo[k] + pdt_rng_uniform(&r) * (hi[k] - lo[k]);
    }
    pdt_real_t inplace[8];
    for (size_t i = 0; i < 8u; i++) {
        cost[i] = PDT_R(0.5) + (pdt_real_t)i;
        inplace[i] = cost[i];
    }
    canary_fill(shared, 8 + CANARY_COUNT);
    pdt_ga_share(genes, 8u, 3u, lo, hi, cost, PDT_R(0.8), PDT_R(1.0), shared);
    canary_check(shared + 8, CANARY_COUNT);
    pdt_ga_share(genes, 8u, 3u, lo, hi, inplace, PDT_R(0.8), PDT_R(1.0), inplace);
    int some_shared = 0;
    for (size_t i = 0; i < 8u; i++) {
        assert_true(inplace[i] == shared[i]);
        assert_true(shared[i] >= cost[i] && shared[i] <= PDT_R(8.0) * cost[i]);
        some_shared |= shared[i] > cost[i];
    }
    assert_true(some_shared);

    /* At the niche's edge: partners at distances just inside and just
     * beyond sigma (the pair-once path skips the far ones without their
     * square root), and a radius whose square is not a normal number (no
     * pair skipped), bit for bit the in-place path, which skips none.
     * Three individuals: their pairs are the scalar ones on every build. */
    const pdt_real_t sig[2] = {PDT_R(0.1), PDT_R(1e-20)};
    for (size_t c = 0; c < 2u; c++) {
        for (int step = -40; step <= 80; step++) {
            const pdt_real_t f = PDT_R(1.0) + (pdt_real_t)step * PDT_R(0.001);
            const pdt_real_t d = f * sig[c] * (hi[0] - lo[0]);
            const pdt_real_t x[3] = {PDT_R(0.0), d, -d * PDT_R(0.999)};
            for (size_t i = 0; i < 3u; i++) {
                genes[3u * i] = x[i];
                genes[3u * i + 1u] = PDT_R(2.0);
                genes[3u * i + 2u] = PDT_R(13.0);
                cost[i] = PDT_R(1.0) + (pdt_real_t)i;
                inplace[i] = cost[i];
            }
            pdt_ga_share(genes, 3u, 3u, lo, hi, cost, sig[c], PDT_R(1.0), shared);
            pdt_ga_share(genes, 3u, 3u, lo, hi, inplace, sig[c], PDT_R(1.0), inplace);
            for (size_t i = 0; i < 3u; i++) {
                assert_memory_equal(&inplace[i], &shared[i], sizeof shared[i]);
            }
            /* The first shares a niche only with partners inside it. */
            if (f <= PDT_R(0.99)) {
                assert_true(shared[0] > cost[0]);
            } else if (f >= PDT_R(1.01)) {
                assert_true(shared[0] == cost[0]);
            }
        }
    }

    /* n = 0 writes nothing */
    canary_fill(shared, 8 + CANARY_COUNT);
    pdt_ga_share(genes, 0u, 3u, lo, hi, cost, PDT_R(0.8), PDT_R(1.0), shared);
    canary_check(shared, 8 + CANARY_COUNT);
}

/* ---- tournament --------------------------------------------------------- */

static void test_tournament_vectors(void **state)
{
    (void)state;
    pdt_real_t shared[8];
    for (size_t i = 0; i < 8u; i++) {
        shared[i] = (pdt_real_t)ga_tour_shared[i];
    }
    for (size_t c = 0; c < GA_TOUR_CASES; c++) {
        const uint32_t *row = ga_tour + 4u * c;
        assert_int_equal(pdt_ga_tournament(shared, row[0], row[1], row[2]), row[3]);
    }
}

static void test_tournament_nan_loses(void **state)
{
    (void)state;
    pdt_real_t shared[3] = {PDT_R(1.0), (pdt_real_t)NAN, (pdt_real_t)NAN};
    assert_int_equal(pdt_ga_tournament(shared, 0u, 1u, 1u), 0u);
    assert_int_equal(pdt_ga_tournament(shared, 1u, 0u, 0u), 0u);
    assert_int_equal(pdt_ga_tournament(shared, 1u, 2u, 0u), 1u);
    assert_int_equal(pdt_ga_tournament(shared, 1u, 2u, 3u), 2u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pcg_demo_values),
        cmocka_unit_test(test_pcg_vectors),
        cmocka_unit_test(test_uniform_largest_draw_below_one),
        cmocka_unit_test(test_uniform_statistics),
        cmocka_unit_test(test_below_vectors),
        cmocka_unit_test(test_below_properties),
        cmocka_unit_test(test_sbx_grid),
        cmocka_unit_test(test_sbx_random),
        cmocka_unit_test(test_sbx_edges_finite_inside),
        cmocka_unit_test(test_sbx_equal_parents_copied),
        cmocka_unit_test(test_sbx_mean_preserved),
        cmocka_unit_test(test_sbx_spread_grows_as_eta_falls),
        cmocka_unit_test(test_mutate_grid),
        cmocka_unit_test(test_mutate_random),
        cmocka_unit_test(test_mutate_edges_finite_inside),
        cmocka_unit_test(test_mutate_direction_and_reach),
        cmocka_unit_test(test_share_vectors),
        cmocka_unit_test(test_share_properties),
        cmocka_unit_test(test_tournament_vectors),
        cmocka_unit_test(test_tournament_nan_loses),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
