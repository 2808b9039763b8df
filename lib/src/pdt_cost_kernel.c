/*
 * The simulation cost's inner loop: the evaluation the identification
 * repeats thousands of times. See pdt_cost_kernel.h.
 *
 * The record is cut where the branches would be: the samples before the
 * input reaches the model (the response is 0 there, only the residual
 * y - c0 is summed), the samples the paper's window simulates but does not
 * score, and the body, with one loop per model order so that nothing is
 * decided per sample. Sums are taken in blocks: the rounding error of a
 * float sum over thousands of samples stays near (BLOCK + n / BLOCK) eps
 * instead of n eps.
 */
#include "pdt_cost_kernel.h"

#include "pdt_internal.h"

#define KERNEL_BLOCK 128u

/* Simulation state in delta form (see pdt_discrete.h): ys = s(k-1),
 * dys = s(k-1) - s(k-2), p1, p2 the two previous delayed inputs. */
typedef struct kstate {
    pdt_real_t ys, dys, p1, p2;
} kstate_t;

static void add_sums(pdt_cost_sums_t *t, pdt_real_t s, pdt_real_t ss, pdt_real_t ee,
                     pdt_real_t es)
{
    t->s += s;
    t->ss += ss;
    t->ee += ee;
    t->es += es;
}

/* Samples [k, end) where the model's input is still 0: s = 0, e = y - c0. */
static pdt_real_t head_sum(const pdt_real_t *y, size_t k, size_t end, pdt_real_t c0)
{
    pdt_real_t total = PDT_R(0.0);
    while (k < end) {
        size_t stop = (end - k > KERNEL_BLOCK) ? k + KERNEL_BLOCK : end;
        pdt_real_t blk = PDT_R(0.0);
        for (; k < stop; k++) {
            pdt_real_t e = y[k] - c0;
            blk += e * e;
        }
        total += blk;
    }
    return total;
}

/* Any order and taps, one sample at a time: the paper's unscored samples
 * (score false) and a first-order model with a third input tap, which the
 * FOPDT discretisation never makes. ud[j] is the delayed input u(j) for
 * the output sample j + l + 1, yd the output from that sample on. */
static void generic(const pdt_real_t *ud, const pdt_real_t *yd, size_t j, size_t jend,
                    const pdt_discrete_t *d, pdt_real_t K0, pdt_real_t c0, bool score,
                    kstate_t *st, pdt_cost_sums_t *t)
{
    for (; j < jend; j++) {
        pdt_real_t u1 = ud[j];
        pdt_real_t bu = d->b[0] * u1 + d->b[1] * st->p1 + d->b[2] * st->p2;
        if (d->order == 1u) {
            st->ys += bu - d->d[0] * st->ys;
        } else {
            pdt_real_t ys2 = st->ys - st->dys;
            st->dys += bu - d->d[0] * st->dys - d->d[1] * ys2;
            st->ys += st->dys;
        }
        st->p2 = st->p1;
        st->p1 = u1;
        if (score) {
            pdt_real_t s = st->ys;
            pdt_real_t e = (yd[j] - c0) - K0 * s;
            add_sums(t, s, s * s, e * e, e * s);
        }
    }
}

/* First order, two input taps (every FOPDT): s += b0 u1 + b1 p1 - d0 s. */
static void body1(const pdt_real_t *ud, const pdt_real_t *yd, size_t j, size_t jend,
                  const pdt_discrete_t *d, pdt_real_t K0, pdt_real_t c0, kstate_t *st,
                  pdt_cost_sums_t *t)
{
    const pdt_real_t b0 = d->b[0], b1 = d->b[1], d0 = d->d[0];
    pdt_real_t ys = st->ys, p1 = st->p1;
    while (j < jend) {
        size_t stop = (jend - j > KERNEL_BLOCK) ? j + KERNEL_BLOCK : jend;
        const pdt_real_t *up = ud + j, *yp = yd + j;
        const pdt_real_t *const uend = ud + stop;
        pdt_real_t s = PDT_R(0.0), ss = PDT_R(0.0), ee = PDT_R(0.0), es = PDT_R(0.0);
        /* A block is never empty: the pointer test alone ends the loop. */
        do {
            pdt_real_t u1 = *up++;
            ys += (b0 * u1 + b1 * p1) - d0 * ys;
            p1 = u1;
            pdt_real_t e = (*yp++ - c0) - K0 * ys;
            s += ys;
            ss += ys * ys;
            ee += e * e;
            es += e * ys;
        } while (up != uend);
        add_sums(t, s, ss, ee, es);
        j = stop;
    }
    st->ys = ys;
    st->p1 = p1;
}

/* Second order. The delta form's update
 *   dys' = dys + bu - d0 dys - d1 (ys - dys) = dys + (bu - (d0 - d1) dys - d1 ys)
 * keeps the small numbers d0 and d1 that set a slow model's time constant
 * and gain (1 - d0 + d1, the product of the poles, would round them away)
 * with one operation fewer than the textbook arrangement. */
static void body2(const pdt_real_t *ud, const pdt_real_t *yd, size_t j, size_t jend,
                  const pdt_discrete_t *d, pdt_real_t K0, pdt_real_t c0, kstate_t *st,
                  pdt_cost_sums_t *t)
{
    const pdt_real_t b0 = d->b[0], b1 = d->b[1], b2 = d->b[2], d1 = d->d[1];
    const pdt_real_t e0 = d->d[0] - d1;
    pdt_real_t ys = st->ys, dys = st->dys, p1 = st->p1, p2 = st->p2;
    while (j < jend) {
        size_t stop = (jend - j > KERNEL_BLOCK) ? j + KERNEL_BLOCK : jend;
        const pdt_real_t *up = ud + j, *yp = yd + j;
        const pdt_real_t *const uend = ud + stop;
        pdt_real_t s = PDT_R(0.0), ss = PDT_R(0.0), ee = PDT_R(0.0), es = PDT_R(0.0);
        pdt_real_t e;
        if (((stop - j) & 1u) != 0u) {
            /* An odd block: one sample, then pairs. */
            pdt_real_t u1 = *up++;
            dys += ((b0 * u1 + b1 * p1 + b2 * p2) - e0 * dys) - d1 * ys;
            ys += dys;
            p2 = p1;
            p1 = u1;
            e = (*yp++ - c0) - K0 * ys;
            s += ys;
            ss += ys * ys;
            ee += e * e;
            es += e * ys;
        }
        /* Two samples a turn: the input taps rotate through the loaded
         * values instead of being moved every sample. */
        while (up != uend) {
            pdt_real_t ua = up[0], ub = up[1];
            up += 2;
            dys += ((b0 * ua + b1 * p1 + b2 * p2) - e0 * dys) - d1 * ys;
            ys += dys;
            e = (yp[0] - c0) - K0 * ys;
            s += ys;
            ss += ys * ys;
            ee += e * e;
            es += e * ys;
            dys += ((b0 * ub + b1 * ua + b2 * p1) - e0 * dys) - d1 * ys;
            ys += dys;
            e = (yp[1] - c0) - K0 * ys;
            yp += 2;
            s += ys;
            ss += ys * ys;
            ee += e * e;
            es += e * ys;
            p2 = ua;
            p1 = ub;
        }
        add_sums(t, s, ss, ee, es);
        j = stop;
    }
    st->ys = ys;
    st->dys = dys;
    st->p1 = p1;
    st->p2 = p2;
}

void pdt_cost_kernel(const pdt_real_t *u, const pdt_real_t *y, size_t n, size_t k0,
                     const pdt_discrete_t *d, pdt_real_t K0, pdt_real_t c0,
                     pdt_cost_sums_t *out)
{
    /* The first output sample the input reaches: u(0) acts on s(l + 1). */
    const size_t l1 = (d->delay < n) ? d->delay + 1u : n;
    const pdt_real_t *yd = y + l1;
    pdt_cost_sums_t t = {PDT_R(0.0), PDT_R(0.0), PDT_R(0.0), PDT_R(0.0)};
    kstate_t st = {PDT_R(0.0), PDT_R(0.0), PDT_R(0.0), PDT_R(0.0)};
    size_t body = l1;

    if (k0 < l1) {
        t.ee = head_sum(y, k0, l1, c0);
    } else {
        generic(u, yd, 0u, k0 - l1, d, K0, c0, false, &st, &t);
        body = k0;
    }
    /* Output sample k reads u(k - l1) = ud[j] and y(k) = yd[j], j = k - l1. */
    if (d->order == 2u) {
        body2(u, yd, body - l1, n - l1, d, K0, c0, &st, &t);
    } else if (d->b[2] == PDT_R(0.0)) {
        body1(u, yd, body - l1, n - l1, d, K0, c0, &st, &t);
    } else {
        generic(u, yd, body - l1, n - l1, d, K0, c0, true, &st, &t);
    }
    *out = t;
}
