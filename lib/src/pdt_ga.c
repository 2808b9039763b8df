/*
 * Operators of the real-coded genetic algorithm: the PCG32 generator, bounded
 * SBX, bounded polynomial mutation, fitness sharing and the binary
 * tournament. Contract in pdt_ga.h.
 */
#include "pdt_ga.h"

#include <string.h>

#include "pdt_internal.h"

#define PDT_PCG_MULT 6364136223846793005ULL

/* Parents closer than this fraction of the range are not crossed. Relative
 * to the range, it also bounds the spread factor beta below 1 + 2e14, so
 * nothing in SBX can overflow. */
#define PDT_SBX_MIN_GAP PDT_R(1e-14)

void pdt_rng_seed(pdt_rng_t *r, uint64_t seed, uint64_t stream)
{
    PDT_ASSERT(r != NULL);
    r->state = 0u;
    r->inc = (stream << 1u) | 1u;
    (void)pdt_rng_u32(r);
    r->state += seed;
    (void)pdt_rng_u32(r);
}

uint32_t pdt_rng_u32(pdt_rng_t *r)
{
    PDT_ASSERT(r != NULL);
    uint64_t old = r->state;
    r->state = old * PDT_PCG_MULT + r->inc;
    uint32_t xorshifted = (uint32_t)(((old >> 18u) ^ old) >> 27u);
    uint32_t rot = (uint32_t)(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((0u - rot) & 31u));
}

pdt_real_t pdt_rng_uniform(pdt_rng_t *r)
{
    uint32_t x = pdt_rng_u32(r);
#if PDT_REAL_DOUBLE
    /* All 32 bits fit the 53-bit mantissa: exact, at most 1 - 2^-32. */
    return (pdt_real_t)x * PDT_R(2.3283064365386962890625e-10);
#else
    /* 24 bits fill the float mantissa exactly; more bits could round the
     * largest draws up to 1.0. At most 1 - 2^-24. */
    return (pdt_real_t)(x >> 8u) * PDT_R(5.9604644775390625e-08);
#endif
}

uint32_t pdt_rng_below(pdt_rng_t *r, uint32_t n)
{
    PDT_ASSERT(n >= 1u);
    if (n <= 1u) {
        return 0u;
    }
    uint64_t m = (uint64_t)pdt_rng_u32(r) * n;
    uint32_t low = (uint32_t)m;
    if (low < n) {
        /* 2^32 mod n: the low words below it belong to an incomplete
         * last block of multiples and would bias the result. */
        uint32_t threshold = (0u - n) % n;
        while (low < threshold) {
            m = (uint64_t)pdt_rng_u32(r) * n;
            low = (uint32_t)m;
        }
    }
    return (uint32_t)(m >> 32u);
}

static pdt_real_t clamp(pdt_real_t x, pdt_real_t lo, pdt_real_t hi)
{
    if (x < lo) {
        return lo;
    }
    if (x > hi) {
        return hi;
    }
    return x;
}

/* Spread factor of one child of bounded SBX. room: the distance from the
 * nearer parent to the bound on its side (>= 0), gap: the distance between
 * the parents (> 0). */
/* Whether beta^-e1 lies below a quarter of the real type's epsilon, so
 * that 2 - beta^-e1 rounds to 2 whatever the power's last bits: e1 >= 16
 * and beta^16 >= 8 / eps (four squarings: within 1e-6 of beta^16 in
 * float, so the tail is at most eps / 8 and a part in 10^6).
 * Parents close together far from their bound, as once a search has
 * converged: the tail's power is then not needed. */
static bool sbx_tail_below_eps(pdt_real_t beta, pdt_real_t e1)
{
    pdt_real_t b16 = beta * beta;
    b16 *= b16;
    b16 *= b16;
    b16 *= b16;
    return e1 >= PDT_R(16.0) && b16 >= PDT_R(8.0) / PDT_REAL_EPS;
}

static pdt_real_t sbx_beta_q(pdt_real_t room, pdt_real_t gap, pdt_real_t eta, pdt_real_t u)
{
    pdt_real_t e1 = eta + PDT_R(1.0);
    pdt_real_t beta = PDT_R(1.0) + PDT_R(2.0) * room / gap;
    /* tail = beta^-(eta+1) in [0, 1]: the part of the unbounded
     * distribution beyond the bound, times two. alpha = 2 - tail: 2
     * exactly where the tail is below the rounding, the same bits as with
     * the power and one call of it fewer. */
    const bool below = sbx_tail_below_eps(beta, e1);
    pdt_real_t tail = below ? PDT_R(0.0) : pdt_pow(beta, -e1);
    pdt_real_t alpha = below ? PDT_R(2.0) : PDT_R(2.0) - tail;
    pdt_real_t ua = u * alpha;
    if (ua <= PDT_R(1.0)) {
        return pdt_pow(ua, PDT_R(1.0) / e1);
    }
    if (below) {
        tail = pdt_pow(beta, -e1);
    }
    /* 2 - u alpha written without the cancellation that loses every digit
     * when u is near 1 and alpha near 2; it is at least 2 (1 - u) > 0. */
    pdt_real_t den = PDT_R(2.0) * (PDT_R(1.0) - u) + u * tail;
    if (!(den > PDT_REAL_EPS * PDT_REAL_EPS)) {
        den = PDT_REAL_EPS * PDT_REAL_EPS;
    }
    return pdt_pow(PDT_R(1.0) / den, PDT_R(1.0) / e1);
}

void pdt_ga_sbx(pdt_real_t p1, pdt_real_t p2, pdt_real_t lo, pdt_real_t hi, pdt_real_t eta,
                pdt_real_t u, pdt_real_t *c1, pdt_real_t *c2)
{
    PDT_ASSERT(c1 != NULL && c2 != NULL && lo < hi && eta > PDT_R(0.0));
    PDT_ASSERT(u >= PDT_R(0.0) && u < PDT_R(1.0));
    pdt_real_t y1 = p1 < p2 ? p1 : p2;
    pdt_real_t y2 = p1 < p2 ? p2 : p1;
    pdt_real_t gap = y2 - y1;
    if (!(gap >= PDT_SBX_MIN_GAP * (hi - lo))) {
        *c1 = y1;
        *c2 = y2;
        return;
    }
    /* Parents outside the bounds would make beta < 1; treat them as on the
     * bound instead. */
    pdt_real_t room_lo = y1 - lo;
    pdt_real_t room_hi = hi - y2;
    if (room_lo < PDT_R(0.0)) {
        room_lo = PDT_R(0.0);
    }
    if (room_hi < PDT_R(0.0)) {
        room_hi = PDT_R(0.0);
    }
    pdt_real_t sum = y1 + y2;
    pdt_real_t bq1 = sbx_beta_q(room_lo, gap, eta, u);
    pdt_real_t bq2 = sbx_beta_q(room_hi, gap, eta, u);
    *c1 = clamp(PDT_R(0.5) * (sum - bq1 * gap), lo, hi);
    *c2 = clamp(PDT_R(0.5) * (sum + bq2 * gap), lo, hi);
}

pdt_real_t pdt_ga_mutate(pdt_real_t x, pdt_real_t lo, pdt_real_t hi, pdt_real_t eta, pdt_real_t u)
{
    PDT_ASSERT(lo < hi && eta > PDT_R(0.0) && u >= PDT_R(0.0) && u < PDT_R(1.0));
    pdt_real_t range = hi - lo;
    pdt_real_t e1 = eta + PDT_R(1.0);
    pdt_real_t p = PDT_R(1.0) / e1;
    pdt_real_t dq;
    if (u <= PDT_R(0.5)) {
        pdt_real_t d1 = clamp((x - lo) / range, PDT_R(0.0), PDT_R(1.0));
        pdt_real_t v =
            PDT_R(2.0) * u + (PDT_R(1.0) - PDT_R(2.0) * u) * pdt_pow(PDT_R(1.0) - d1, e1);
        dq = pdt_pow(v, p) - PDT_R(1.0);
    } else {
        pdt_real_t d2 = clamp((hi - x) / range, PDT_R(0.0), PDT_R(1.0));
        pdt_real_t v = PDT_R(2.0) * (PDT_R(1.0) - u) +
                       PDT_R(2.0) * (u - PDT_R(0.5)) * pdt_pow(PDT_R(1.0) - d2, e1);
        dq = PDT_R(1.0) - pdt_pow(v, p);
    }
    return clamp(x + dq * range, lo, hi);
}

/* Genes the sharing scales by precomputed reciprocals of their ranges:
 * the pairs then need no division but the one of the ratio, and a pair
 * outside the niche no square root. The breeding of each generation does
 * P (P - 1) / 2 pairs, the largest fixed cost of a search on a short
 * record. More genes use the division. */
#define SHARE_GENES 4u

/* The sharing function of one pair: 1 - (d / sigma)^alpha inside the
 * niche, 0 outside. inv: 1 / (hi - lo) per gene. Symmetric bit for bit:
 * (xj - xi) is -(xi - xj) exactly, so pair (i, j) and pair (j, i) give
 * the same value. */
static inline pdt_real_t share_pair(const pdt_real_t *xi, const pdt_real_t *xj, size_t g,
                                    const pdt_real_t *inv, pdt_real_t sigma, pdt_real_t alpha)
{
    pdt_real_t d2 = PDT_R(0.0);
    for (size_t k = 0; k < g; k++) {
        pdt_real_t t = (xi[k] - xj[k]) * inv[k];
        d2 += t * t;
    }
    if (!(d2 < sigma * sigma)) {
        return PDT_R(0.0);
    }
    pdt_real_t ratio = pdt_sqrt(d2) / sigma;
    if (!(ratio < PDT_R(1.0))) {
        return PDT_R(0.0);
    }
    return PDT_R(1.0) - (alpha == PDT_R(1.0) ? ratio : pdt_pow(ratio, alpha));
}

/* share_pair for alpha = 1 (the triangle) by the reciprocal of sigma too:
 * no division and no branch. Whether a pair shares a niche is a coin toss
 * to a branch predictor, and a division waits longer than everything else
 * the pair does; the vector lanes take four pairs a turn without one (the
 * scalar pairs test the distance first: share_far2). Symmetric bit for bit
 * like share_pair. */
static inline pdt_real_t share_d2(const pdt_real_t *xi, const pdt_real_t *xj, size_t g,
                                  const pdt_real_t *inv)
{
    pdt_real_t d2 = PDT_R(0.0);
    for (size_t k = 0; k < g; k++) {
        const pdt_real_t t = (xi[k] - xj[k]) * inv[k];
        d2 += t * t;
    }
    return d2;
}

static inline pdt_real_t share_tri_d2(pdt_real_t d2, pdt_real_t inv_sigma)
{
    const pdt_real_t x = PDT_R(1.0) - pdt_sqrt(d2) * inv_sigma;
    /* max(x, 0) exactly, as arithmetic: compilers make a conditional a
     * branch here. */
    return PDT_R(0.5) * (x + pdt_fabs(x));
}

static inline pdt_real_t share_tri(const pdt_real_t *xi, const pdt_real_t *xj, size_t g,
                                   const pdt_real_t *inv, pdt_real_t inv_sigma)
{
    return share_tri_d2(share_d2(xi, xj, g, inv), inv_sigma);
}

/* A squared distance beyond which share_tri is +0 exactly, for the scalar
 * pairs: d2 above (1.03125 sigma)^2, rounded, puts sqrt(d2) / sigma above
 * 1.03 after every rounding, so x < 0 and 0.5 (x + |x|) = +0, which adds
 * nothing to the counts (they start at 1). Skipping such a pair leaves
 * the sums bit for bit and saves the square root of every pair outside
 * a niche: an FPU's takes 14 cycles, software floating point's hundreds
 * of instructions. A radius whose square is not a normal number skips
 * nothing. */
static pdt_real_t share_far2(pdt_real_t sigma)
{
    const pdt_real_t s = sigma * PDT_R(1.03125);
    const pdt_real_t f = s * s;
    return f > PDT_R(1e-30) ? f : PDT_REAL_MAX;
}

#if PDT_VECTOR_LANES == 4
#define SHARE_VECTOR 1
#if PDT_REAL_DOUBLE
typedef int64_t smask_t __attribute__((vector_size(4 * sizeof(int64_t))));
#define SHARE_SIGN ((smask_t){INT64_MIN, INT64_MIN, INT64_MIN, INT64_MIN})
#else
typedef int32_t smask_t __attribute__((vector_size(4 * sizeof(int32_t))));
#define SHARE_SIGN ((smask_t){INT32_MIN, INT32_MIN, INT32_MIN, INT32_MIN})
#endif

/* Row i of the triangle's pairs, four partners j a turn: share_tri in
 * the lanes of a vector, each lane the scalar operations bit for bit (a
 * vector square root rounds as the scalar one does), and the counts added
 * in the order j = i + 1, i + 2, ... as the scalar loop does. The pairs
 * are most of a search's breeding on a short record. Returns the first j
 * left to the scalar loop. */
PDT_FORCE_INLINE size_t share_tri_row(const pdt_real_t *genes, size_t n, size_t g, size_t i,
                                      const pdt_real_t *inv, pdt_real_t inv_sigma,
                                      pdt_real_t *shared, pdt_real_t *m)
{
    const pdt_real_t *xi = genes + i * g;
    size_t j = i + 1u;
    for (; j + 4u <= n; j += 4u) {
        const pdt_real_t *xj = genes + j * g;
        pdt_vec4_t d2 = PDT_VEC4(PDT_R(0.0));
        PDT_UNROLL
        for (size_t k = 0; k < g; k++) {
            const pdt_vec4_t xk = {xj[k], xj[g + k], xj[2u * g + k], xj[3u * g + k]};
            const pdt_vec4_t t = (PDT_VEC4(xi[k]) - xk) * PDT_VEC4(inv[k]);
            d2 += t * t;
        }
        /* Square roots a lane at a time: C has no vector one, and each
         * is the scalar one's result anyway. */
        const pdt_vec4_t r = {pdt_sqrt(d2[0]), pdt_sqrt(d2[1]), pdt_sqrt(d2[2]), pdt_sqrt(d2[3])};
        const pdt_vec4_t x = PDT_VEC4(PDT_R(1.0)) - r * PDT_VEC4(inv_sigma);
        const pdt_vec4_t s = PDT_VEC4(PDT_R(0.5)) * (x + (pdt_vec4_t)((smask_t)x & ~SHARE_SIGN));
        *m += s[0];
        *m += s[1];
        *m += s[2];
        *m += s[3];
        pdt_vec4_t sj;
        (void)memcpy(&sj, &shared[j], sizeof sj);
        sj += s;
        (void)memcpy(&shared[j], &sj, sizeof sj);
    }
    return j;
}

/* share_tri_row with the gene count a constant, so that the loop over the
 * genes unrolls (a FOPDT has two, a SOPDT three). */
static size_t share_row(const pdt_real_t *genes, size_t n, size_t g, size_t i,
                        const pdt_real_t *inv, pdt_real_t inv_sigma, pdt_real_t *shared,
                        pdt_real_t *m)
{
    switch (g) {
    case 2u:
        return share_tri_row(genes, n, 2u, i, inv, inv_sigma, shared, m);
    case 3u:
        return share_tri_row(genes, n, 3u, i, inv, inv_sigma, shared, m);
    default:
        return share_tri_row(genes, n, g, i, inv, inv_sigma, shared, m);
    }
}
#else
#define SHARE_VECTOR 0
#endif

/* The same with the division per gene, for more than SHARE_GENES. */
static pdt_real_t share_pair_wide(const pdt_real_t *xi, const pdt_real_t *xj, size_t g,
                                  const pdt_real_t *lo, const pdt_real_t *hi, pdt_real_t sigma,
                                  pdt_real_t alpha)
{
    pdt_real_t d2 = PDT_R(0.0);
    for (size_t k = 0; k < g; k++) {
        pdt_real_t t = (xi[k] - xj[k]) / (hi[k] - lo[k]);
        d2 += t * t;
    }
    pdt_real_t ratio = pdt_sqrt(d2) / sigma;
    if (!(ratio < PDT_R(1.0))) {
        return PDT_R(0.0);
    }
    return PDT_R(1.0) - (alpha == PDT_R(1.0) ? ratio : pdt_pow(ratio, alpha));
}

static pdt_real_t share_of(const pdt_real_t *xi, const pdt_real_t *xj, size_t g,
                           const pdt_real_t *inv, const pdt_real_t *lo, const pdt_real_t *hi,
                           pdt_real_t sigma, pdt_real_t alpha)
{
    if (g > SHARE_GENES) {
        return share_pair_wide(xi, xj, g, lo, hi, sigma, alpha);
    }
    return alpha == PDT_R(1.0) ? share_tri(xi, xj, g, inv, PDT_R(1.0) / sigma)
                               : share_pair(xi, xj, g, inv, sigma, alpha);
}

void pdt_ga_share(const pdt_real_t *genes, size_t n, size_t g, const pdt_real_t *lo,
                  const pdt_real_t *hi, const pdt_real_t *cost, pdt_real_t sigma, pdt_real_t alpha,
                  pdt_real_t *shared)
{
    PDT_ASSERT(n == 0u || (genes != NULL && cost != NULL && shared != NULL));
    PDT_ASSERT(g == 0u || (lo != NULL && hi != NULL));
    PDT_ASSERT(sigma > PDT_R(0.0) && alpha > PDT_R(0.0));
    pdt_real_t inv[SHARE_GENES] = {PDT_R(0.0), PDT_R(0.0), PDT_R(0.0), PDT_R(0.0)};
    for (size_t k = 0; k < g && k < SHARE_GENES; k++) {
        inv[k] = PDT_R(1.0) / (hi[k] - lo[k]);
    }
    if (shared == cost) {
        /* In place: one row at a time, reading only cost[i] before
         * writing shared[i]. */
        for (size_t i = 0; i < n; i++) {
            pdt_real_t m = PDT_R(1.0); /* j == i */
            for (size_t j = 0; j < n; j++) {
                if (j != i) {
                    m += share_of(genes + i * g, genes + j * g, g, inv, lo, hi, sigma, alpha);
                }
            }
            shared[i] = cost[i] * m;
        }
        return;
    }
    /* Each pair once, half the work: the niche counts gather in shared.
     * Count i still adds its pairs in the order j = 0 .. n - 1 (those with
     * j < i arrive from the earlier rows, in order), so the sums are the
     * row-at-a-time ones bit for bit. */
    for (size_t i = 0; i < n; i++) {
        shared[i] = PDT_R(1.0);
    }
    if (alpha == PDT_R(1.0) && g <= SHARE_GENES) {
        /* The identification's case: the triangle, at most three genes. */
        const pdt_real_t inv_sigma = PDT_R(1.0) / sigma;
        const pdt_real_t far2 = share_far2(sigma);
        for (size_t i = 0; i < n; i++) {
            pdt_real_t m = shared[i];
            size_t j = i + 1u;
#if SHARE_VECTOR
            j = share_row(genes, n, g, i, inv, inv_sigma, shared, &m);
#endif
            for (; j < n; j++) {
                const pdt_real_t d2 = share_d2(genes + i * g, genes + j * g, g, inv);
                if (d2 > far2) {
                    continue; /* +0: share_far2 */
                }
                const pdt_real_t s = share_tri_d2(d2, inv_sigma);
                m += s;
                shared[j] += s;
            }
            shared[i] = m * cost[i];
        }
        return;
    }
    for (size_t i = 0; i < n; i++) {
        /* Row i's count in a register: through shared[i] every pair
         * would wait for the store of the one before. */
        pdt_real_t m = shared[i];
        for (size_t j = i + 1u; j < n; j++) {
            const pdt_real_t s =
                share_of(genes + i * g, genes + j * g, g, inv, lo, hi, sigma, alpha);
            m += s;
            shared[j] += s;
        }
        shared[i] = m * cost[i];
    }
}

size_t pdt_ga_tournament(const pdt_real_t *shared, size_t a, size_t b, uint32_t coin)
{
    PDT_ASSERT(shared != NULL);
    pdt_real_t fa = shared[a];
    pdt_real_t fb = shared[b];
    bool na = isnan(fa) != 0;
    bool nb = isnan(fb) != 0;
    if (na != nb) {
        return na ? b : a;
    }
    if (fa < fb) {
        return a;
    }
    if (fb < fa) {
        return b;
    }
    return coin == 0u ? a : b;
}
