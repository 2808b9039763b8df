/*
 * Operators of the real-coded genetic algorithm (Deb 2000; Goldberg and
 * Richardson 1987), private to the library. Each operator is a pure function
 * of its inputs, random numbers included, so it can be checked against the
 * numpy reference value for value; the identification module draws the
 * random numbers and applies the operators.
 *
 * None of them can fail, so none returns a status: the preconditions below
 * (non-NULL pointers, lo < hi, eta > 0, u in [0, 1), ...) are the caller's
 * to keep and are checked only by PDT_ASSERT. For any input that keeps them,
 * SBX and mutation return finite values inside [lo, hi].
 */
#ifndef PDT_GA_H
#define PDT_GA_H

#include "pdt/pdt_common.h"

/* pdt_rng_t (pdt_common.h) is PCG32 (O'Neill 2014, "XSH RR" output, 64-bit
 * LCG state): small, fast on 32-bit cores, statistically sound, and the
 * same sequence on every target. */

/* Seeds the generator as the PCG reference does with initstate = seed and
 * initseq = stream. */
void pdt_rng_seed(pdt_rng_t *r, uint64_t seed, uint64_t stream);

/* Next 32 random bits. */
uint32_t pdt_rng_u32(pdt_rng_t *r);

/* Uniform in [0, 1) from one draw: (x >> 8) * 2^-24 in the float build,
 * x * 2^-32 in the double build. Exactly representable, so the largest value
 * is 1 - 2^-24 (float) or 1 - 2^-32 (double), never 1. */
pdt_real_t pdt_rng_uniform(pdt_rng_t *r);

/* Uniform integer in [0, n), n >= 1, without modulo bias (Lemire's
 * multiply-and-reject: one draw, more only when the low word of the product
 * falls among the 2^32 mod n biased values). n == 1 returns 0 without
 * drawing; n == 0 breaks the precondition and also returns 0. */
uint32_t pdt_rng_below(pdt_rng_t *r, uint32_t n);

/* Bounded simulated binary crossover of one variable (Deb's bounded SBX as
 * in NSGA-II). p1, p2 the parents' values in [lo, hi] (lo < hi), eta the
 * distribution index (> 0), u uniform in [0, 1); the same u serves both
 * children. Writes the two children, clamped to the bounds, ordered so that
 * c1 comes from the lower parent's side and c1 <= c2 (the caller swaps them
 * at random). When the parents differ by less than 1e-14 times (hi - lo),
 * the children are copies of the parents, the smaller in c1 (no crossover).
 * A parent outside the bounds is treated as lying on its bound. */
void pdt_ga_sbx(pdt_real_t p1, pdt_real_t p2, pdt_real_t lo, pdt_real_t hi, pdt_real_t eta,
                pdt_real_t u, pdt_real_t *c1, pdt_real_t *c2);

/* Bounded polynomial mutation of one variable (Deb's, as in NSGA-II):
 * x in [lo, hi], eta the distribution index (> 0), u uniform in [0, 1).
 * u < 1/2 moves x down (u = 0 to lo), u > 1/2 up, u = 1/2 leaves it.
 * Returns the mutated value, clamped to the bounds. */
pdt_real_t pdt_ga_mutate(pdt_real_t x, pdt_real_t lo, pdt_real_t hi, pdt_real_t eta, pdt_real_t u);

/* Fitness sharing. genes: n individuals of g genes each, row-major
 * (genes[i * g + j]); lo, hi: the bounds per gene (lo < hi); cost: the raw
 * costs (>= 0, smaller is better); sigma: the niche radius in normalised
 * gene distance (> 0); alpha: the sharing exponent (> 0).
 * shared[i] = cost[i] * m_i with the niche count
 * m_i = sum_j sh(d_ij), sh(d) = 1 - (d / sigma)^alpha for d < sigma else 0,
 * d_ij = sqrt(sum_k ((x_ik - x_jk) / (hi_k - lo_k))^2), j over all
 * individuals including i (so m_i >= 1). O(n^2 g), each pair once (twice
 * in place), no memory beyond shared[0..n-1]; shared may be the cost
 * array itself (in place). */
void pdt_ga_share(const pdt_real_t *genes, size_t n, size_t g, const pdt_real_t *lo,
                  const pdt_real_t *hi, const pdt_real_t *cost, pdt_real_t sigma, pdt_real_t alpha,
                  pdt_real_t *shared);

/* Binary tournament: the index (a or b) with the smaller shared cost; a tie
 * goes to a if coin is 0 and to b otherwise. A NaN cost loses to any
 * number; two NaN costs are a tie. */
size_t pdt_ga_tournament(const pdt_real_t *shared, size_t a, size_t b, uint32_t coin);

#endif /* PDT_GA_H */
