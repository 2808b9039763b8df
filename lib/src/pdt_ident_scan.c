/*
 * The frequency criterion's dead time and gain sign, which magnitudes
 * cannot see: a grid of the time cost over the dead-time range (both signs
 * of the gain at each point), then a golden section around the best point.
 */
#include "pdt_ident_priv.h"
#include "pdt_internal.h"

#define GOLDEN PDT_R(0.6180339887498949)

/* Time cost of the best shape with dead time Td and a fixed gain. */
static pdt_real_t scan_cost(pdt_ident_t *c, pdt_real_t Td, pdt_real_t gain, pdt_real_t *offset)
{
    pdt_real_t g[3];
    pdt_model_t shape;
    pdt_cost_profile_t pr;
    for (uint32_t j = 0; j < c->genes; j++) {
        g[j] = c->best.genes[j];
    }
    g[c->genes - 1u] = pdt_ident_gene_of_td(c, Td);
    pdt_ident_shape(c, g, &shape);
    pdt_ident_counted(c, 1u, c->scan.cost_time.n);
    if (pdt_cost_profile(&c->scan.cost_time, &shape, gain, gain, c->scratch, &pr) != PDT_OK ||
        !(pr.ncost == pr.ncost)) {
        *offset = PDT_R(0.0);
        return PDT_REAL_MAX;
    }
    *offset = pr.offset;
    return pr.ncost;
}

static void consider(pdt_ident_scan_t *s, pdt_real_t Td, pdt_real_t gain, pdt_real_t f,
                     pdt_real_t offset)
{
    if (f < s->best) {
        s->best = f;
        s->td = Td;
        s->gain = gain;
        s->offset = offset;
    }
}

/* The dead-time range of the genes. */
static void td_range(const pdt_ident_t *c, pdt_real_t *lo, pdt_real_t *hi)
{
    const size_t dt = (size_t)c->genes - 1u;
    *lo = pdt_ident_td_of_gene(c, c->lo[dt]);
    *hi = pdt_ident_td_of_gene(c, c->hi[dt]);
}

pdt_ident_outcome_t pdt_ident_scan_start(pdt_ident_t *c)
{
    pdt_ident_scan_t *s = &c->scan;
    pdt_real_t lo, hi;
    td_range(c, &lo, &hi);
    s->cost_time = c->cost;
    s->cost_time.cfg.kind = c->cfg.time_kind;
    s->i = 0u;
    s->step = (hi - lo) / (pdt_real_t)(PDT_IDENT_SCAN_POINTS - 1u);
    s->best = PDT_REAL_MAX;
    s->td = pdt_ident_td_of_gene(c, c->best.genes[c->genes - 1u]);
    s->gain = c->best.gain;
    s->offset = PDT_R(0.0);
    return OUT_DONE;
}

/* Point i / 2 of the grid, the gain's sign by the parity of i. */
pdt_ident_outcome_t pdt_ident_scan_grid(pdt_ident_t *c)
{
    pdt_ident_scan_t *s = &c->scan;
    pdt_real_t td_lo, td_hi, off;
    td_range(c, &td_lo, &td_hi);
    pdt_real_t Td = td_lo + s->step * (pdt_real_t)(s->i / 2u);
    pdt_real_t gain = (s->i % 2u) == 0u ? pdt_fabs(c->best.gain) : -pdt_fabs(c->best.gain);
    Td = Td > td_hi ? td_hi : Td;
    pdt_real_t f = scan_cost(c, Td, gain, &off);
    consider(s, Td, gain, f, off);
    if (++s->i == 2u * PDT_IDENT_SCAN_POINTS) {
        pdt_real_t a = s->td - s->step, b = s->td + s->step;
        s->a = a < td_lo ? td_lo : a;
        s->b = b > td_hi ? td_hi : b;
        s->x1 = s->b - GOLDEN * (s->b - s->a);
        s->x2 = s->a + GOLDEN * (s->b - s->a);
        s->i = 0u;
        return OUT_DONE;
    }
    return OUT_AGAIN;
}

/* The first two calls evaluate x1 and x2, each later call the one new
 * interior point. */
pdt_ident_outcome_t pdt_ident_scan_golden(pdt_ident_t *c)
{
    pdt_ident_scan_t *s = &c->scan;
    pdt_real_t off;
    if (s->i == 0u) {
        s->f1 = scan_cost(c, s->x1, s->gain, &off);
        consider(s, s->x1, s->gain, s->f1, off);
    } else if (s->i == 1u) {
        s->f2 = scan_cost(c, s->x2, s->gain, &off);
        consider(s, s->x2, s->gain, s->f2, off);
    } else if (s->f1 < s->f2) {
        s->b = s->x2;
        s->x2 = s->x1;
        s->f2 = s->f1;
        s->x1 = s->b - GOLDEN * (s->b - s->a);
        s->f1 = scan_cost(c, s->x1, s->gain, &off);
        consider(s, s->x1, s->gain, s->f1, off);
    } else {
        s->a = s->x1;
        s->x1 = s->x2;
        s->f1 = s->f2;
        s->x2 = s->a + GOLDEN * (s->b - s->a);
        s->f2 = scan_cost(c, s->x2, s->gain, &off);
        consider(s, s->x2, s->gain, s->f2, off);
    }
    if (++s->i == PDT_IDENT_GOLDEN_STEPS + 2u) {
        c->best.genes[c->genes - 1u] = pdt_ident_gene_of_td(c, s->td);
        c->best.gain = s->gain;
        c->best.offset = s->offset;
        return OUT_DONE;
    }
    return OUT_AGAIN;
}
