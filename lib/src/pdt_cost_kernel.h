/*
 * The simulation cost's inner loop (pdt_cost_kernel.c), private to the cost
 * module. It works on the normalised copies of the record that
 * pdt_cost_init keeps in its workspace: u and y are deviations from the
 * operating point scaled into (-1, 1), so nothing is subtracted per sample.
 */
#ifndef PDT_COST_KERNEL_H
#define PDT_COST_KERNEL_H

#include "pdt/pdt_common.h"
#include "pdt/pdt_discrete.h"

#if PDT_VECTOR_LANES == 4
#define PDT_COST_KERNEL_VECTOR 1
#else
#define PDT_COST_KERNEL_VECTOR 0
#endif

/* One pass of the unit-gain shape response s over the scored samples
 * k0 .. n-1, against the residual of a reference fit e = y - K0 s - c0:
 *   s = sum s, ss = sum s^2, ee = sum e^2, es = sum e s.
 * Everything else the closed-form gain and offset need follows from these
 * and the data's own sums (sum e = sum y - K0 sum s - m c0). The reference
 * fit is what keeps float accurate: the residual sum of squares at the best
 * gain is ee minus corrections of the size of (K - K0)^2 ss, so when K0 is
 * near the best gain nothing large cancels. With K0 = c0 = 0 this is the
 * plain regression (ee = sum y^2). */
typedef struct pdt_cost_sums {
    pdt_real_t s, ss, ee, es;
} pdt_cost_sums_t;

/* d: order 1 or 2, coefficients finite, in the normalised units; k0 <= n. */
void pdt_cost_kernel(const pdt_real_t *u, const pdt_real_t *y, size_t n, size_t k0,
                     const pdt_discrete_t *d, pdt_real_t K0, pdt_real_t c0, pdt_cost_sums_t *out);

/* The same for count candidates d[0..count-1] with one reference fit, into
 * out[0..count-1]. Where the compiler offers vector registers (GCC or
 * Clang with SSE2 or NEON) two to four candidates of one order run in one
 * pass, a lane each (the free lanes repeat the first); otherwise, and for
 * one candidate, one pass each. */
void pdt_cost_kernel_many(const pdt_real_t *u, const pdt_real_t *y, size_t n, size_t k0,
                          const pdt_discrete_t *d, size_t count, pdt_real_t K0, pdt_real_t c0,
                          pdt_cost_sums_t *out);

/* The unit-gain response of d to u from rest, its delay aside: r[j] is
 * the s that pdt_cost_kernel scores j samples after the input reaches the
 * model (output sample j + d->delay + 1), bit for bit where the kernel
 * scores from the input's arrival on (k0 <= d->delay + 1: the whole
 * record); after a stretch it simulates unscored, to rounding. r: n
 * reals. */
void pdt_cost_kernel_response(const pdt_real_t *u, size_t n, const pdt_discrete_t *d,
                              pdt_real_t *r);

/* pdt_cost_kernel_many's sums of count (1 .. 4) candidates that share one
 * response r (pdt_cost_kernel_response of their coefficients) and differ
 * in their delays delay[0..count-1] only, into out[0..count-1]: the same
 * sums without the simulation, a pass each (where the host has vector
 * registers, one pass for all four, a lane each). */
void pdt_cost_kernel_shift(const pdt_real_t *r, const pdt_real_t *y, size_t n, size_t k0,
                           const size_t *delay, size_t count, pdt_real_t K0, pdt_real_t c0,
                           pdt_cost_sums_t *out);

#endif /* PDT_COST_KERNEL_H */
