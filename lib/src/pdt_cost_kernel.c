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

static void add_sums(pdt_cost_sums_t *t, pdt_real_t s, pdt_real_t ss, pdt_real_t ee, pdt_real_t es)
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

/* head_sum of [k0, end[i]) for count (1 .. 4) ends, in one pass to the
 * farthest: each sum is taken where its range ends, from the same blocks
 * in the same order, so each is head_sum's bit for bit. The profile's
 * delays of one shape share their output's head this way instead of
 * summing it once each. */
static void head_sums(const pdt_real_t *y, size_t k0, const size_t *end, size_t count,
                      pdt_real_t c0, pdt_real_t *out)
{
    bool done[4] = {false, false, false, false};
    pdt_real_t total = PDT_R(0.0), blk = PDT_R(0.0);
    size_t k = k0, bend = k0 + KERNEL_BLOCK;
    for (size_t taken = 0; taken < count; taken++) {
        size_t next = count;
        for (size_t i = 0; i < count; i++) {
            if (!done[i] && (next == count || end[i] < end[next])) {
                next = i;
            }
        }
        while (k < end[next]) {
            const size_t stop = (end[next] < bend) ? end[next] : bend;
            for (; k < stop; k++) {
                const pdt_real_t e = y[k] - c0;
                blk += e * e;
            }
            if (k == bend) {
                total += blk;
                blk = PDT_R(0.0);
                bend += KERNEL_BLOCK;
            }
        }
        out[next] = total + blk;
        done[next] = true;
    }
}

/* Any order and taps, one sample at a time: the paper's unscored samples
 * (score false) and a first-order model with a third input tap, which the
 * FOPDT discretisation never makes. ud[j] is the delayed input u(j) for
 * the output sample j + l + 1, yd the output from that sample on. */
static void generic(const pdt_real_t *ud, const pdt_real_t *yd, size_t j, size_t jend,
                    const pdt_discrete_t *d, pdt_real_t K0, pdt_real_t c0, bool score, kstate_t *st,
                    pdt_cost_sums_t *t)
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

/* First order, two input taps (every FOPDT): s += b0 u1 + b1 p1 - d0 s.
 * BODY1_STEP is one sample with input ua, tap pa = u(k-2-l) and output
 * yk; single samples up to a multiple of four, then four a turn, as in
 * body2: the same operations in the same order, the loop's control
 * shared. */
#define BODY1_STEP(ua, pa, yk)                                                                     \
    do {                                                                                           \
        ys += (b0 * (ua) + b1 * (pa)) - d0 * ys;                                                   \
        e = ((yk)-c0) - K0 * ys;                                                                   \
        s += ys;                                                                                   \
        ss += ys * ys;                                                                             \
        ee += e * e;                                                                               \
        es += e * ys;                                                                              \
    } while (0)

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
        pdt_real_t e;
        for (size_t r = (stop - j) & 3u; r > 0u; r--) {
            pdt_real_t ua = *up++;
            BODY1_STEP(ua, p1, *yp);
            yp++;
            p1 = ua;
        }
        while (up != uend) {
            pdt_real_t ua = up[0], ub = up[1], uc = up[2], uq = up[3];
            up += 4;
            BODY1_STEP(ua, p1, yp[0]);
            BODY1_STEP(ub, ua, yp[1]);
            BODY1_STEP(uc, ub, yp[2]);
            BODY1_STEP(uq, uc, yp[3]);
            yp += 4;
            p1 = uq;
        }
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
 * with one operation fewer than the textbook arrangement.
 * BODY2_STEP is one sample with input ua, taps pa = u(k-2-l) and
 * pb = u(k-3-l), output yk; a macro, so that the unrolled loop is one body
 * that the compiler schedules freely at any optimisation level. */
#define BODY2_STEP(ua, pa, pb, yk)                                                                 \
    do {                                                                                           \
        dys += ((b0 * (ua) + b1 * (pa) + b2 * (pb)) - e0 * dys) - d1 * ys;                         \
        ys += dys;                                                                                 \
        e = ((yk)-c0) - K0 * ys;                                                                   \
        s += ys;                                                                                   \
        ss += ys * ys;                                                                             \
        ee += e * e;                                                                               \
        es += e * ys;                                                                              \
    } while (0)

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
        /* Single samples up to a multiple of four, then four a turn: the
         * input taps rotate through the loaded values instead of being
         * moved every sample, and the loop's control is shared. */
        for (size_t r = (stop - j) & 3u; r > 0u; r--) {
            pdt_real_t ua = *up++;
            BODY2_STEP(ua, p1, p2, *yp);
            yp++;
            p2 = p1;
            p1 = ua;
        }
        while (up != uend) {
            pdt_real_t ua = up[0], ub = up[1], uc = up[2], uq = up[3];
            up += 4;
            BODY2_STEP(ua, p1, p2, yp[0]);
            BODY2_STEP(ub, ua, p1, yp[1]);
            BODY2_STEP(uc, ub, ua, yp[2]);
            BODY2_STEP(uq, uc, ub, yp[3]);
            yp += 4;
            p2 = uc;
            p1 = uq;
        }
        add_sums(t, s, ss, ee, es);
        j = stop;
    }
    st->ys = ys;
    st->dys = dys;
    st->p1 = p1;
    st->p2 = p2;
}

/* Output samples [k0, kend) of one candidate, from state st, into t. */
static void kernel_range(const pdt_real_t *u, const pdt_real_t *y, size_t n, size_t k0, size_t kend,
                         const pdt_discrete_t *d, pdt_real_t K0, pdt_real_t c0, kstate_t *st,
                         pdt_cost_sums_t *t)
{
    /* The first output sample the input reaches: u(0) acts on s(l + 1). */
    const size_t l1 = (d->delay < n) ? d->delay + 1u : n;
    const pdt_real_t *yd = y + l1;
    size_t body = l1;

    if (k0 < l1) {
        t->ee += head_sum(y, k0, (l1 < kend) ? l1 : kend, c0);
    } else {
        generic(u, yd, 0u, ((k0 < kend) ? k0 : kend) - l1, d, K0, c0, false, st, t);
        body = k0;
    }
    if (body >= kend) {
        return;
    }
    /* Output sample k reads u(k - l1) = ud[j] and y(k) = yd[j], j = k - l1. */
    if (d->order == 2u) {
        body2(u, yd, body - l1, kend - l1, d, K0, c0, st, t);
    } else if (d->b[2] == PDT_R(0.0)) {
        body1(u, yd, body - l1, kend - l1, d, K0, c0, st, t);
    } else {
        generic(u, yd, body - l1, kend - l1, d, K0, c0, true, st, t);
    }
}

void pdt_cost_kernel(const pdt_real_t *u, const pdt_real_t *y, size_t n, size_t k0,
                     const pdt_discrete_t *d, pdt_real_t K0, pdt_real_t c0, pdt_cost_sums_t *out)
{
    pdt_cost_sums_t t = {PDT_R(0.0), PDT_R(0.0), PDT_R(0.0), PDT_R(0.0)};
    kstate_t st = {PDT_R(0.0), PDT_R(0.0), PDT_R(0.0), PDT_R(0.0)};
    kernel_range(u, y, n, k0, n, d, K0, c0, &st, &t);
    *out = t;
}

/* The response the kernel's loops simulate, stored: body2's update for a
 * second-order model, body1's for a first-order one (generic's where the
 * model has a third input tap: the same values, the tap's zero product
 * added exactly where it has none), so that each r[j] is the s the kernel
 * scores j samples after the input reaches the model, whatever its
 * delay. Once per shape, not per candidate: one loop for both orders. */
void pdt_cost_kernel_response(const pdt_real_t *u, size_t n, const pdt_discrete_t *d, pdt_real_t *r)
{
    const pdt_real_t b0 = d->b[0], b1 = d->b[1], b2 = d->b[2], d1 = d->d[1];
    const pdt_real_t e0 = d->d[0] - d1;
    const bool two = (d->order == 2u);
    pdt_real_t ys = PDT_R(0.0), dys = PDT_R(0.0), p1 = PDT_R(0.0), p2 = PDT_R(0.0);
    for (size_t j = 0; j < n; j++) {
        const pdt_real_t bu = b0 * u[j] + b1 * p1 + b2 * p2;
        if (two) {
            dys += (bu - e0 * dys) - d1 * ys;
            ys += dys;
        } else {
            ys += bu - d->d[0] * ys;
        }
        r[j] = ys;
        p2 = p1;
        p1 = u[j];
    }
}

/* Scoring of one sample of a stored response s against output yk: the
 * kernel's BODY1_STEP less the simulation, the sums in the same order. */
#define SHIFT_STEP(sk, yk)                                                                         \
    do {                                                                                           \
        const pdt_real_t sv = (sk);                                                                \
        const pdt_real_t e = ((yk)-c0) - K0 * sv;                                                  \
        s += sv;                                                                                   \
        ss += sv * sv;                                                                             \
        ee += e * e;                                                                               \
        es += e * sv;                                                                              \
    } while (0)

/* The heads shift_range reads for count (1 .. 4) candidates reaching the
 * output l1[i] samples after their input, scored over [k0, kend): one
 * pass for all. */
static void heads(const pdt_real_t *y, size_t k0, size_t kend, const size_t *l1, size_t count,
                  pdt_real_t c0, pdt_real_t *head)
{
    size_t end[4] = {k0, k0, k0, k0};
    for (size_t i = 0; i < count; i++) {
        const size_t e = (l1[i] < kend) ? l1[i] : kend;
        end[i] = (e > k0) ? e : k0;
    }
    head_sums(y, k0, end, count, c0, head);
}

/* Output samples [k0, kend) of a candidate whose response r reaches the
 * output l1 samples after its input, into t: kernel_range's sums, blocks
 * and order, without the simulation. head: head_sum of [k0, min(l1,
 * kend)), read where k0 < l1. */
static void shift_range(const pdt_real_t *r, const pdt_real_t *y, size_t k0, size_t kend, size_t l1,
                        pdt_real_t head, pdt_real_t K0, pdt_real_t c0, pdt_cost_sums_t *t)
{
    size_t j = 0u;
    if (k0 < l1) {
        t->ee += head;
    } else {
        j = k0 - l1;
    }
    if (l1 >= kend) {
        return;
    }
    const size_t jend = kend - l1;
    const pdt_real_t *yd = y + l1;
    while (j < jend) {
        const size_t stop = (jend - j > KERNEL_BLOCK) ? j + KERNEL_BLOCK : jend;
        const pdt_real_t *rp = r + j, *yp = yd + j;
        const pdt_real_t *const rend = r + stop;
        pdt_real_t s = PDT_R(0.0), ss = PDT_R(0.0), ee = PDT_R(0.0), es = PDT_R(0.0);
        /* As body1: single samples up to a multiple of four, then four a
         * turn, the loop's control shared (12 instructions a sample on
         * the Cortex-M4F one at a time, under 9 so). */
        for (size_t k = (stop - j) & 3u; k > 0u; k--) {
            SHIFT_STEP(*rp, *yp);
            rp++;
            yp++;
        }
        while (rp != rend) {
            SHIFT_STEP(rp[0], yp[0]);
            SHIFT_STEP(rp[1], yp[1]);
            SHIFT_STEP(rp[2], yp[2]);
            SHIFT_STEP(rp[3], yp[3]);
            rp += 4;
            yp += 4;
        }
        add_sums(t, s, ss, ee, es);
        j = stop;
    }
}

#if PDT_COST_KERNEL_VECTOR
/* Four candidates side by side in the lanes of a vector: where the host
 * has vector registers, one instruction serves all four, and the loop's
 * loads of y and its control are shared. Each lane reads its own delayed
 * input; the lanes start together once every candidate's input has
 * arrived (before that each runs alone). */
/* The scoring of sample k in every lane, shared by both orders' loops. */
#define KV_SCORE(yk)                                                                               \
    do {                                                                                           \
        pdt_vec4_t e = (PDT_VEC4(yk) - vc0) - vk0 * ys;                                            \
        s += ys;                                                                                   \
        ss += ys * ys;                                                                             \
        ee += e * e;                                                                               \
        es += e * ys;                                                                              \
    } while (0)

static void many_body(const pdt_real_t *u, const pdt_real_t *y, size_t k, size_t n,
                      const pdt_discrete_t *d, const size_t l1[4], pdt_real_t K0, pdt_real_t c0,
                      kstate_t st[4], pdt_cost_sums_t t[4])
{
    const pdt_vec4_t b0 = {d[0].b[0], d[1].b[0], d[2].b[0], d[3].b[0]};
    const pdt_vec4_t b1 = {d[0].b[1], d[1].b[1], d[2].b[1], d[3].b[1]};
    const pdt_vec4_t b2 = {d[0].b[2], d[1].b[2], d[2].b[2], d[3].b[2]};
    const pdt_vec4_t dd0 = {d[0].d[0], d[1].d[0], d[2].d[0], d[3].d[0]};
    const pdt_vec4_t dd1 = (d[0].order == 2u)
                               ? (pdt_vec4_t){d[0].d[1], d[1].d[1], d[2].d[1], d[3].d[1]}
                               : PDT_VEC4(PDT_R(0.0));
    const pdt_vec4_t e0 = dd0 - dd1;
    const pdt_vec4_t vk0 = PDT_VEC4(K0), vc0 = PDT_VEC4(c0);
    const bool taps2 = d[0].b[2] == PDT_R(0.0) && d[1].b[2] == PDT_R(0.0) &&
                       d[2].b[2] == PDT_R(0.0) && d[3].b[2] == PDT_R(0.0);
    pdt_vec4_t ys = {st[0].ys, st[1].ys, st[2].ys, st[3].ys};
    pdt_vec4_t dys = {st[0].dys, st[1].dys, st[2].dys, st[3].dys};
    pdt_vec4_t p1 = {st[0].p1, st[1].p1, st[2].p1, st[3].p1};
    pdt_vec4_t p2 = {st[0].p2, st[1].p2, st[2].p2, st[3].p2};
    pdt_vec4_t ts = PDT_VEC4(PDT_R(0.0)), tss = ts, tee = ts, tes = ts;
    while (k < n) {
        size_t stop = (n - k > KERNEL_BLOCK) ? k + KERNEL_BLOCK : n;
        pdt_vec4_t s = PDT_VEC4(PDT_R(0.0)), ss = s, ee = s, es = s;
        if (d[0].order == 2u) {
            /* Two samples a turn: the input taps rotate instead of being
             * moved, and the loop's control is shared. */
            for (; k + 2u <= stop; k += 2u) {
                pdt_vec4_t ua = {u[k - l1[0]], u[k - l1[1]], u[k - l1[2]], u[k - l1[3]]};
                pdt_vec4_t ub = {u[k + 1u - l1[0]], u[k + 1u - l1[1]], u[k + 1u - l1[2]],
                                 u[k + 1u - l1[3]]};
                dys += ((b0 * ua + b1 * p1 + b2 * p2) - e0 * dys) - dd1 * ys;
                ys += dys;
                KV_SCORE(y[k]);
                dys += ((b0 * ub + b1 * ua + b2 * p1) - e0 * dys) - dd1 * ys;
                ys += dys;
                KV_SCORE(y[k + 1u]);
                p2 = ua;
                p1 = ub;
            }
            if (k < stop) {
                pdt_vec4_t uk = {u[k - l1[0]], u[k - l1[1]], u[k - l1[2]], u[k - l1[3]]};
                dys += ((b0 * uk + b1 * p1 + b2 * p2) - e0 * dys) - dd1 * ys;
                ys += dys;
                p2 = p1;
                p1 = uk;
                KV_SCORE(y[k]);
                k++;
            }
        } else if (taps2) {
            /* Every FOPDT: no third tap to multiply by zero. */
            for (; k < stop; k++) {
                pdt_vec4_t uk = {u[k - l1[0]], u[k - l1[1]], u[k - l1[2]], u[k - l1[3]]};
                ys += (b0 * uk + b1 * p1) - dd0 * ys;
                p1 = uk;
                KV_SCORE(y[k]);
            }
        } else {
            for (; k < stop; k++) {
                pdt_vec4_t uk = {u[k - l1[0]], u[k - l1[1]], u[k - l1[2]], u[k - l1[3]]};
                ys += (b0 * uk + b1 * p1 + b2 * p2) - dd0 * ys;
                p2 = p1;
                p1 = uk;
                KV_SCORE(y[k]);
            }
        }
        ts += s;
        tss += ss;
        tee += ee;
        tes += es;
    }
    for (size_t i = 0; i < 4u; i++) {
        add_sums(&t[i], ts[i], tss[i], tee[i], tes[i]);
    }
}
#endif

void pdt_cost_kernel_many(const pdt_real_t *u, const pdt_real_t *y, size_t n, size_t k0,
                          const pdt_discrete_t *d, size_t count, pdt_real_t K0, pdt_real_t c0,
                          pdt_cost_sums_t *out)
{
    size_t i;
#if PDT_COST_KERNEL_VECTOR
    bool same = count >= 2u && count <= 4u;
    for (i = 1; i < count && same; i++) {
        same = d[i].order == d[0].order;
    }
    if (same) {
        /* Two or three candidates still take one pass: the free lanes
         * repeat the first (the pass costs what four cost, less than two
         * alone). */
        pdt_discrete_t dl[4];
        pdt_cost_sums_t t[4];
        kstate_t st[4];
        size_t l1[4], kmax = k0;
        for (i = 0; i < 4u; i++) {
            dl[i] = d[i < count ? i : 0u];
            l1[i] = (dl[i].delay < n) ? dl[i].delay + 1u : n;
            kmax = (l1[i] > kmax) ? l1[i] : kmax;
        }
        for (i = 0; i < 4u; i++) {
            t[i] = (pdt_cost_sums_t){PDT_R(0.0), PDT_R(0.0), PDT_R(0.0), PDT_R(0.0)};
            st[i] = (kstate_t){PDT_R(0.0), PDT_R(0.0), PDT_R(0.0), PDT_R(0.0)};
            if (i < count) {
                kernel_range(u, y, n, k0, kmax, &dl[i], K0, c0, &st[i], &t[i]);
            }
        }
        if (kmax < n) {
            many_body(u, y, kmax, n, dl, l1, K0, c0, st, t);
        }
        for (i = 0; i < count; i++) {
            out[i] = t[i];
        }
        return;
    }
#endif
    for (i = 0; i < count; i++) {
        pdt_cost_kernel(u, y, n, k0, &d[i], K0, c0, &out[i]);
    }
}

#if PDT_COST_KERNEL_VECTOR
/* Four delays of one stored response in the lanes of a vector, from
 * sample k on (every lane's input arrived): KV_SCORE on the gathered
 * responses, many_body's sums and blocks. */
static void shift_body(const pdt_real_t *r, const pdt_real_t *y, size_t k, size_t n,
                       const size_t l1[4], pdt_real_t K0, pdt_real_t c0, pdt_cost_sums_t t[4])
{
    const pdt_vec4_t vk0 = PDT_VEC4(K0), vc0 = PDT_VEC4(c0);
    pdt_vec4_t ts = PDT_VEC4(PDT_R(0.0)), tss = ts, tee = ts, tes = ts;
    while (k < n) {
        const size_t stop = (n - k > KERNEL_BLOCK) ? k + KERNEL_BLOCK : n;
        pdt_vec4_t s = PDT_VEC4(PDT_R(0.0)), ss = s, ee = s, es = s;
        for (; k < stop; k++) {
            const pdt_vec4_t ys = {r[k - l1[0]], r[k - l1[1]], r[k - l1[2]], r[k - l1[3]]};
            KV_SCORE(y[k]);
        }
        ts += s;
        tss += ss;
        tee += ee;
        tes += es;
    }
    for (size_t i = 0; i < 4u; i++) {
        add_sums(&t[i], ts[i], tss[i], tee[i], tes[i]);
    }
}
#endif

#if PDT_COST_KERNEL_VECTOR
/* pdt_cost_kernel_shift of two to four delays: as pdt_cost_kernel_many,
 * each lane alone until every input has arrived, then the four together
 * (the free lanes repeat the first). */
static void shift_many(const pdt_real_t *r, const pdt_real_t *y, size_t n, size_t k0,
                       const size_t *delay, size_t count, pdt_real_t K0, pdt_real_t c0,
                       pdt_cost_sums_t *out)
{
    size_t i, l1[4], kmax = k0;
    pdt_cost_sums_t t[4];
    for (i = 0; i < 4u; i++) {
        const size_t l = delay[i < count ? i : 0u];
        l1[i] = (l < n) ? l + 1u : n;
        kmax = (l1[i] > kmax) ? l1[i] : kmax;
        t[i] = (pdt_cost_sums_t){PDT_R(0.0), PDT_R(0.0), PDT_R(0.0), PDT_R(0.0)};
    }
    pdt_real_t head[4];
    heads(y, k0, kmax, l1, count, c0, head);
    for (i = 0; i < count; i++) {
        shift_range(r, y, k0, kmax, l1[i], head[i], K0, c0, &t[i]);
    }
    if (kmax < n) {
        shift_body(r, y, kmax, n, l1, K0, c0, t);
    }
    for (i = 0; i < count; i++) {
        out[i] = t[i];
    }
}
#endif

void pdt_cost_kernel_shift(const pdt_real_t *r, const pdt_real_t *y, size_t n, size_t k0,
                           const size_t *delay, size_t count, pdt_real_t K0, pdt_real_t c0,
                           pdt_cost_sums_t *out)
{
#if PDT_COST_KERNEL_VECTOR
    if (count >= 2u) {
        shift_many(r, y, n, k0, delay, count, K0, c0, out);
        return;
    }
#endif
    size_t l1[4] = {n, n, n, n};
    pdt_real_t head[4];
    for (size_t i = 0; i < count; i++) {
        l1[i] = (delay[i] < n) ? delay[i] + 1u : n;
    }
    heads(y, k0, n, l1, count, c0, head);
    for (size_t i = 0; i < count; i++) {
        pdt_cost_sums_t t = {PDT_R(0.0), PDT_R(0.0), PDT_R(0.0), PDT_R(0.0)};
        shift_range(r, y, k0, n, l1[i], head[i], K0, c0, &t);
        out[i] = t;
    }
}
