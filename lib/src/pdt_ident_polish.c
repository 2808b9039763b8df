/*
 * The polish of one answer (a search's own last polish with the output
 * error, the whole record's after searches on a coarse one, the rest
 * level's): a Newton iteration on a quadratic model from central
 * differences.
 *
 * The answer comes from a search that already found its basin, so the cost
 * around it is close to a quadratic. Its gradient and Hessian in the genes
 * (2 for a FOPDT, 3 for a SOPDT: gain and offset are closed form) come
 * from G (G + 1) points about the centre, evaluated in groups of up to
 * PDT_VECTOR_LANES in one pass over the record; the Newton step then goes
 * to the model's minimum. Two or three such steps reach where Nelder-Mead
 * took 50 (FOPDT) to 90 (SOPDT) evaluations of the whole record, one at a
 * time. Where the model is not trustworthy (a Hessian that is not
 * positive definite, a centre too close to a gene's bound for the points
 * about it, a step cut to its reach, a step whose tries raised the cost),
 * Nelder-Mead polishes from the best point seen, as before, with what is
 * left of the budget. docs/ident-engine.md, "The polish of one answer".
 */
#include "pdt_ident_priv.h"
#include "pdt_internal.h"
#include "pdt_linalg.h"

/* pdt_ident_polish_t.state */
#define POLISH_CENTRE  1u
#define POLISH_STENCIL 2u
#define POLISH_TRIAL   3u

/* Each gene's difference width is set by how far the cost rose across it:
 * RISE (a tenth of the centre's cost) while the answer is still on its way
 * (wide differences see the basin's shape from farther off), RISE_FINE
 * once a whole Newton step succeeded or the centre stood: the truncation
 * error of differences that wide left the answers of long valleys 1e-4
 * of the cost above their minimum, and a thousandth is still far above
 * the rounding of a float cost. A stencil that rose more than RISE_MAX is
 * too wide for a Newton step at all. */
#define POLISH_RISE      PDT_R(0.1)
#define POLISH_RISE_FINE PDT_R(1e-3)
#define POLISH_RISE_MAX  PDT_R(2.0)

/* The narrowest difference step, normalised gene units. */
#define POLISH_H_MIN PDT_R(1e-6)

/* An accepted step shorter than XTOL (normalised), or one that lowered
 * the cost by less than FTOL of it, ends the polish: the next would not
 * move the answer measurably. */
#define POLISH_XTOL PDT_R(1e-6)
#define POLISH_FTOL (PDT_R(64.0) * PDT_REAL_EPS)

/* A failed step's rise above NOISE FTOL of the cost is the model's
 * failure, not the cost's rounding. */
#define POLISH_NOISE PDT_R(8.0)

/* The first difference step, normalised gene units. The answer of a
 * coarse record's search lies within a few thousandths of the whole
 * record's optimum, and there a SOPDT's cost already rises to twice its
 * minimum 0.01 away: the differences must stay where the cost is close to
 * its quadratic. */
#define POLISH_H0 PDT_R(1e-3)

/* The widest difference step. */
#define POLISH_H_MAX PDT_R(1e-2)

/* A step goes at most this many difference steps from the centre. */
#define POLISH_REACH PDT_R(4.0)

/* Halvings of a step that did not lower the cost before Nelder-Mead. */
#define POLISH_BACKTRACK 2u

/* Newton steps at most. */
#define POLISH_ITERATIONS 8u

/* The output error of a fractional dead time has a kink wherever the dead
 * time is a whole number of samples (the zero-order hold's interpolation
 * between two input samples changes pair there): its minimum often lies
 * on one (a plant whose delay is a whole number of scans, as digital loops
 * have), or the kink is a ridge with a minimum on either side. Between
 * two whole samples the cost is smooth. So the dead time's differences
 * stay on the centre's side of its whole samples (keep_off_kinks), and
 * where they reached a kink, two more passes follow the answer's polish:
 * the other genes polished with the dead time held on the nearest whole
 * sample, then, where the cost falls across it, a polish from the
 * answer's mirror image through the first pass's point
 * (docs/ident-engine.md, step 5 of the polish). An answer closer to a
 * whole sample than PDT_IDENT_ON_KINK of one is on it; differences are
 * kept to one side unless that cuts them below KINK_ROOM of their width. */
#define KINK_ROOM PDT_R(0.125)

/* Points about the centre: +/- each gene, and +/- each pair together. */
static uint32_t points_of(const pdt_ident_t *c)
{
    const uint32_t D = c->nm.late.polish.dims;
    return D * (D + 1u);
}

/* Difference step of gene j, in its own units. */
static pdt_real_t step_of(const pdt_ident_t *c, uint32_t j)
{
    return c->nm.late.polish.w[j] * (c->hi[j] - c->lo[j]);
}

/* Point k of the stencil: k < 2G is +e_i (k even) or -e_i, i = k / 2;
 * after that +(e_i + e_j) or -(e_i + e_j) for the pairs i < j in order. */
static void stencil_point(const pdt_ident_t *c, uint32_t k, pdt_real_t *out)
{
    const uint32_t G = c->nm.late.polish.dims;
    uint32_t i, j;
    for (uint32_t m = 0; m < c->genes; m++) {
        out[m] = c->nm.late.polish.x[m];
    }
    const pdt_real_t sign = (k % 2u == 0u) ? PDT_R(1.0) : PDT_R(-1.0);
    if (k < 2u * G) {
        i = k / 2u;
        out[i] += sign * step_of(c, i);
        return;
    }
    const uint32_t pair = (k - 2u * G) / 2u;
    /* pairs in order (0,1), (0,2), (1,2) */
    if (pair < G - 1u) {
        i = 0u;
        j = pair + 1u;
    } else {
        i = 1u;
        j = 2u;
    }
    out[i] += sign * step_of(c, i);
    out[j] += sign * step_of(c, j);
}

/* Whether every stencil point lies inside the gene bounds. */
static bool stencil_fits(const pdt_ident_t *c)
{
    for (uint32_t j = 0; j < c->nm.late.polish.dims; j++) {
        const pdt_real_t d = step_of(c, j);
        if (!(c->nm.late.polish.x[j] - d >= c->lo[j] && c->nm.late.polish.x[j] + d <= c->hi[j])) {
            return false;
        }
    }
    return true;
}

static pdt_ident_outcome_t stencil_begin(pdt_ident_t *c);

/* Narrow differences from now on: their truncation error (the cost's
 * cubic terms across a rise of POLISH_RISE) leaves the Newton step a few
 * hundredths of a width off the minimum, a rise of 1e-4 of the cost. */
static void go_fine(pdt_ident_polish_t *p, uint32_t G)
{
    const pdt_real_t narrow = pdt_sqrt(POLISH_RISE_FINE / POLISH_RISE);
    p->fine = true;
    for (uint32_t j = 0; j < G; j++) {
        p->w[j] = p->w[j] * narrow < POLISH_H_MIN ? POLISH_H_MIN : p->w[j] * narrow;
    }
}

/* The centre stands at the wide differences' resolution: once more with
 * narrow ones, else the end. */
static pdt_ident_outcome_t settle(pdt_ident_t *c)
{
    if (c->nm.late.polish.fine) {
        return OUT_DONE;
    }
    go_fine(&c->nm.late.polish, c->nm.late.polish.dims);
    return stencil_begin(c);
}

/* Whether the dead time's whole samples are kinks of the cost polished:
 * the whole record's output error with a fractional dead time (the
 * searches' coarse record's cost is shorter). */
static bool has_kinks(const pdt_ident_t *c)
{
    return c->cfg.cost == PDT_COST_SIMULATION && c->cfg.delay_mode == PDT_DELAY_FRACTIONAL &&
           c->cost.n == c->data.n;
}

/* The dead time of gene value g, in samples. */
static pdt_real_t samples_of(const pdt_ident_t *c, pdt_real_t g)
{
    return pdt_ident_td_of_gene(c, g) / c->cfg.Ts;
}

/* The dead-time gene of r samples, not clamped (pdt_ident_gene_of_td
 * clamps to the bounds, where a kink's distance and a pass's bound check
 * need the value itself). */
static pdt_real_t gene_at(const pdt_ident_t *c, pdt_real_t r)
{
    return pdt_log((r * c->cfg.Ts) + c->td_offset);
}

/* The whole sample nearest to r. */
/* Whether the best point lies across the kink from the answer's polish. */
static bool best_across(const pdt_ident_t *c)
{
    const pdt_real_t whole = pdt_ident_nearest_whole(c->nm.r);
    const pdt_real_t r = samples_of(c, c->best.genes[c->genes - 1u]);
    return (r - whole) * (c->nm.r - whole) < PDT_R(0.0);
}

/* Nelder-Mead from the best point seen, with what is left. A kink pass is
 * only a try: the pinned one just ends (Nelder-Mead would move the dead
 * time off the kink: PLAN), the one across the kink only hands over where
 * it made the best point its own. */
pdt_ident_outcome_t pdt_ident_polish_handover(const pdt_ident_t *c)
{
    return best_across(c) ? OUT_DONE : OUT_SKIPPED;
}

/* The Newton step of the quadratic through the stencil, in units of each
 * gene's difference step (x_j + z_j w_j (hi_j - lo_j)): there the
 * differences' Hessian has entries of the same size whatever the genes'
 * scales. False when it is not positive definite. */
static bool newton_step(const pdt_ident_t *c, pdt_real_t *z, pdt_real_t *gz)
{
    const pdt_ident_polish_t *p = &c->nm.late.polish;
    const uint32_t G = p->dims;
    const pdt_real_t f0 = p->f0;
    pdt_real_t g[3], H[3][3];
    for (uint32_t i = 0; i < G; i++) {
        const pdt_real_t fp = p->f[2u * i], fm = p->f[2u * i + 1u];
        g[i] = PDT_R(0.5) * (fp - fm);
        H[i][i] = fp + fm - PDT_R(2.0) * f0;
    }
    uint32_t k = 2u * G;
    for (uint32_t i = 0; i < G; i++) {
        for (uint32_t j = i + 1u; j < G; j++) {
            /* f(+e_i+e_j) + f(-e_i-e_j) - [f(+-e_i)] - [f(+-e_j)] + 2 f0
             * = 2 H_ij + O(w^4). */
            const pdt_real_t sum = p->f[k] + p->f[k + 1u] - p->f[2u * i] - p->f[2u * i + 1u] -
                                   p->f[2u * j] - p->f[2u * j + 1u] + PDT_R(2.0) * f0;
            H[i][j] = PDT_R(0.5) * sum;
            H[j][i] = H[i][j];
            k += 2u;
        }
    }
    /* H z = -g; a pivot that is not clearly positive (relative to the
     * diagonal it came from) means no minimum of the model. */
    for (uint32_t i = 0; i < G; i++) {
        z[i] = -g[i];
    }
    if (!pdt_chol_solve(&H[0][0], 3u, G, PDT_R(64.0) * PDT_REAL_EPS, z)) {
        return false;
    }
    *gz = PDT_R(0.0);
    for (uint32_t i = 0; i < G; i++) {
        if (!pdt_finite(z[i])) {
            return false;
        }
        *gz += g[i] * z[i];
    }
    return true;
}

/* The width of gene j's next differences from how far the cost rose
 * across its last ones: a rise of about POLISH_RISE. */
static pdt_real_t next_width(const pdt_ident_polish_t *p, uint32_t j)
{
    const pdt_real_t fp = p->f[2u * j], fm = p->f[2u * j + 1u];
    const pdt_real_t rise = (fp > fm ? fp : fm) / p->f0 - PDT_R(1.0);
    const pdt_real_t target = p->fine ? POLISH_RISE_FINE : POLISH_RISE;
    pdt_real_t w = rise > PDT_R(0.0) ? p->w[j] * pdt_sqrt(target / rise) : POLISH_H_MAX;
    w = w < POLISH_H_MIN ? POLISH_H_MIN : w;
    return w > POLISH_H_MAX ? POLISH_H_MAX : w;
}

/* After the stencil: the trial point of the Newton step, or Nelder-Mead. */
static pdt_ident_outcome_t propose(pdt_ident_t *c)
{
    pdt_ident_polish_t *p = &c->nm.late.polish;
    const uint32_t G = p->dims;
    pdt_real_t z[3], w[3], gz = PDT_R(0.0);
    pdt_real_t rise = PDT_R(0.0);
    bool narrower = false;
    for (uint32_t k = 0; k < points_of(c); k++) {
        const pdt_real_t r = p->f[k] / p->f0 - PDT_R(1.0);
        rise = r > rise ? r : rise;
    }
    for (uint32_t j = 0; j < G; j++) {
        w[j] = next_width(p, j);
        narrower = narrower || w[j] < p->w[j];
    }
    if (rise > POLISH_RISE_MAX && narrower) {
        for (uint32_t j = 0; j < G; j++) {
            p->w[j] = w[j];
        }
        return stencil_begin(c);
    }
    if (!newton_step(c, z, &gz) || pdt_ident_left(c) < 1u) {
        return OUT_FALLBACK;
    }
    /* Each gene goes at most POLISH_REACH of its wider difference step. */
    pdt_real_t scale = PDT_R(1.0);
    for (uint32_t j = 0; j < G; j++) {
        const pdt_real_t reach = POLISH_REACH * (w[j] > p->w[j] ? w[j] / p->w[j] : PDT_R(1.0));
        const pdt_real_t a = pdt_fabs(z[j]);
        scale = a * scale > reach ? reach / a : scale;
    }
    p->cut = scale < PDT_R(1.0);
    p->back = 0u;
    p->rose = false;
    /* The model's decrease along the step taken: -g.z scale (1 - scale / 2),
     * since H z = -g. */
    p->pred = -gz * scale * (PDT_R(1.0) - PDT_R(0.5) * scale);
    p->len = PDT_R(0.0);
    for (uint32_t j = 0; j < G; j++) {
        const pdt_real_t x =
            pdt_ident_clamp(c, (size_t)j, p->x[j] + scale * z[j] * p->w[j] * (c->hi[j] - c->lo[j]));
        const pdt_real_t d = pdt_fabs(x - p->x[j]) / (c->hi[j] - c->lo[j]);
        p->len = d > p->len ? d : p->len;
        p->trial[j] = x;
        p->w[j] = w[j];
    }
    for (uint32_t j = G; j < c->genes; j++) {
        p->trial[j] = p->x[j];
    }
    p->state = POLISH_TRIAL;
    return OUT_AGAIN;
}

/* The dead time's differences kept (to 0.9 of the room) between the
 * whole samples on either side of the centre, where the cost is smooth:
 * differences across a kink make no quadratic, and answers a tenth of a
 * sample from one stopped 1e-5 of the cost above their minimum. A centre
 * closer to the kink than KINK_ROOM of the differences' own width keeps
 * them (the kink passes try the kink itself). */
static void keep_off_kinks(pdt_ident_t *c)
{
    pdt_ident_polish_t *p = &c->nm.late.polish;
    const uint32_t j = c->genes - 1u;
    if (p->dims < c->genes || !has_kinks(c)) {
        return;
    }
    const pdt_real_t whole = pdt_floor(samples_of(c, p->x[j]));
    const pdt_real_t below = p->x[j] - gene_at(c, whole);
    const pdt_real_t above = gene_at(c, whole + PDT_R(1.0)) - p->x[j];
    const pdt_real_t room = (below < above ? below : above) / (c->hi[j] - c->lo[j]);
    const pdt_real_t w = PDT_R(0.9) * room;
    if (w < p->w[j]) {
        c->nm.near = true;
        if (w >= KINK_ROOM * p->w[j]) {
            p->w[j] = w;
        }
    }
}

/* A stencil about the centre, or Nelder-Mead when it does not fit. */
static pdt_ident_outcome_t stencil_begin(pdt_ident_t *c)
{
    pdt_ident_polish_t *p = &c->nm.late.polish;
    if (p->iter >= POLISH_ITERATIONS || pdt_ident_left(c) < points_of(c) + 1u) {
        return OUT_DONE;
    }
    keep_off_kinks(c);
    if (!stencil_fits(c)) {
        return OUT_FALLBACK;
    }
    p->next = 0u;
    p->state = POLISH_STENCIL;
    return OUT_AGAIN;
}

/* The polish from the best of the first dims genes, the rest held. */
static void newton_start(pdt_ident_t *c, uint32_t dims)
{
    pdt_ident_polish_t *p = &c->nm.late.polish;
    for (uint32_t j = 0; j < c->genes; j++) {
        p->x[j] = c->best.genes[j];
        p->w[j] = POLISH_H0;
    }
    p->dims = dims;
    p->iter = 0u;
    p->fine = false;
    p->state = POLISH_CENTRE;
}

pdt_ident_outcome_t pdt_ident_polish_begin(pdt_ident_t *c)
{
    c->nm.near = false;
    newton_start(c, c->genes);
    return OUT_DONE;
}

/* A kink pass from x (all genes; dims = genes - 1 holds the dead time).
 * False where x's dead time lies outside its bounds or the budget does not
 * cover a stencil and a step. */
static bool kink_pass(pdt_ident_t *c, uint32_t dims, const pdt_real_t *x)
{
    const uint32_t G = c->genes;
    if (!(x[G - 1u] >= c->lo[G - 1u] && x[G - 1u] <= c->hi[G - 1u]) ||
        pdt_ident_left(c) < (dims * (dims + 1u)) + 2u) {
        return false;
    }
    newton_start(c, dims);
    for (uint32_t j = 0; j < G; j++) {
        c->nm.late.polish.x[j] = pdt_ident_clamp(c, (size_t)j, x[j]);
    }
    return true;
}

/* The dead-time probe after the answer's polish and its kink passes:
 * the cost at PROBE_STEPS points on either side of the answer's dead time,
 * PROBE_STEP samples apart, the lags scaled so that the mean delay (the
 * dead time plus the lags' sum) stays the answer's, the damping held
 * (moment_gene). Under an input that moves at nearly every sample, the
 * interval between two whole samples can hold two minima a fraction of a
 * sample apart, closer than any niche the sharing keeps apart, and two
 * agreeing searches can both end in the worse one (docs/ident-engine.md);
 * the polish, local, does not see the other, and with the shape held the
 * other lies higher than the answer: a shorter dead time needs slower
 * lags. A lower point found is polished as the answer was. */
#define PROBE_STEPS 10u
#define PROBE_STEP  PDT_R(0.1)

/* The sum of the lags of the shape g codes, s (a SOPDT's a / b); 0 for
 * an integrator, whose time scale the probe then holds. */
static pdt_real_t lag_sum(const pdt_ident_t *c, const pdt_real_t *g)
{
    pdt_model_t m;
    pdt_model_view_t v;
    pdt_ident_shape(c, g, &m);
    pdt_model_view(&m, &v);
    if (v.lags == 1u) {
        return v.tau;
    }
    return v.b > PDT_R(0.0) && v.a < v.b * PDT_REAL_MAX ? v.a / v.b : PDT_R(0.0);
}

/* The time-scale gene (gene 0: log tau, or log(1 / a), whose damping
 * gene is scale-free) of the probe's point s seconds of dead time from its
 * centre: the lags scaled so that their sum plus the dead time, the
 * response's mean delay, stays; a record fixes the mean delay far better
 * than its split into dead time and lags. Held where the lags cannot give
 * up s (more than three quarters of their sum) or the scaled gene leaves
 * its bounds. */
static pdt_real_t moment_gene(const pdt_ident_t *c, pdt_real_t lags, pdt_real_t s)
{
    const pdt_real_t g = c->nm.probe_x[0];
    if (!(lags > PDT_R(0.0)) || !(lags - s > PDT_R(0.25) * lags)) {
        return g;
    }
    const pdt_real_t x = g + pdt_log((lags - s) / lags);
    return x >= c->lo[0] && x <= c->hi[0] ? x : g;
}

/* The probe's points and a stencil for the polish from its lowest, the
 * budget probe_begin asks for. */
static uint32_t probe_need(const pdt_ident_t *c)
{
    return (2u * PROBE_STEPS) + (c->genes * (c->genes + 1u)) + 2u;
}

uint32_t pdt_ident_probe_reserve(const pdt_ident_t *c)
{
    return has_kinks(c) ? probe_need(c) : 0u;
}

static bool probe_begin(pdt_ident_t *c)
{
    pdt_ident_refine_t *nm = &c->nm;
    if (pdt_ident_left(c) < probe_need(c)) {
        return false;
    }
    nm->probe = 1u;
    nm->probe_f = c->best.cost;
    for (uint32_t j = 0; j < c->genes; j++) {
        nm->probe_x[j] = c->best.genes[j];
    }
    return true;
}

pdt_ident_outcome_t pdt_ident_polish_probe(pdt_ident_t *c)
{
    pdt_ident_refine_t *nm = &c->nm;
    const uint32_t G = c->genes;
    const uint32_t count = pdt_ident_probe_group(c);
    pdt_real_t pts[PDT_COST_MANY * 3u];
    pdt_real_t cost[PDT_COST_MANY], gains[PDT_COST_MANY], offsets[PDT_COST_MANY];
    uint32_t m = 0;
    const pdt_real_t lags = lag_sum(c, nm->probe_x);
    for (uint32_t i = 0; i < count; i++) {
        /* Points 1 .. PROBE_STEPS below the centre, the rest above it. */
        const uint32_t k = nm->probe + i;
        const uint32_t steps = k <= PROBE_STEPS ? PROBE_STEPS + 1u - k : k - PROBE_STEPS;
        const pdt_real_t d = k <= PROBE_STEPS ? -(pdt_real_t)steps : (pdt_real_t)steps;
        pdt_real_t *x = &pts[m * G];
        for (uint32_t j = 0; j < G; j++) {
            x[j] = nm->probe_x[j];
        }
        x[G - 1u] = gene_at(c, samples_of(c, nm->probe_x[G - 1u]) + (d * PROBE_STEP));
        x[0] = moment_gene(c, lags, d * PROBE_STEP * c->cfg.Ts);
        if (x[G - 1u] >= c->lo[G - 1u] && x[G - 1u] <= c->hi[G - 1u]) {
            m++;
        }
    }
    if (m > 1u) {
        pdt_ident_evaluate_many(c, pts, m, cost, gains, offsets);
    } else if (m == 1u) {
        pdt_ident_evaluate(c, pts, cost, gains, offsets);
    } else {
        /* Every point of the group beyond the dead time's bounds. */
    }
    nm->probe += count;
    if (nm->probe <= 2u * PROBE_STEPS) {
        return OUT_AGAIN;
    }
    /* The evaluations kept the best. Where it is lower than the answer,
     * the answer's whole polish again from it (its kink passes and a
     * probe included: each round needs a lower point and the budget for
     * a probe, so the rounds end), else the answer stands. */
    if (!(c->best.cost < nm->probe_f)) {
        return OUT_DONE;
    }
    return OUT_POLISH;
}

pdt_ident_outcome_t pdt_ident_polish_probe_begin(pdt_ident_t *c)
{
    return probe_begin(c) ? OUT_PROBE : OUT_DONE;
}

/* Whether the best point r samples of dead time lies on the kink nearest
 * nm.r (closer than PDT_IDENT_ON_KINK): the answer's minimum, or the
 * pinned pass's (then no ridge to look across). */
static bool on_kink(const pdt_ident_t *c, pdt_real_t r)
{
    const pdt_real_t whole = pdt_ident_nearest_whole(c->nm.r);
    return !(pdt_fabs(r - whole) >= PDT_IDENT_ON_KINK);
}

/* On the whole record's output error with a fractional dead time, after
 * the answer's polish whose dead time's differences reached a kink: the
 * pinned pass on the kink begun (OUT_KINK), else the dead-time probe
 * (OUT_PROBE); OUT_DONE, nothing begun, where none applies or where the
 * budget is spent. */
pdt_ident_outcome_t pdt_ident_polish_end(pdt_ident_t *c)
{
    pdt_ident_refine_t *nm = &c->nm;
    const uint32_t G = c->genes;
    pdt_real_t x[3];
    if (c->cfg.cost == PDT_COST_FREQUENCY) {
        return OUT_SCAN;
    }
    if (!has_kinks(c) || !(c->best.cost < PDT_REAL_MAX)) {
        return OUT_DONE;
    }
    if (!nm->near) {
        /* The dead time's differences never reached a kink: the polish
         * saw a smooth cost. */
        return pdt_ident_polish_probe_begin(c);
    }
    nm->r = samples_of(c, c->best.genes[G - 1u]);
    if (on_kink(c, nm->r)) {
        return pdt_ident_polish_probe_begin(c);
    }
    for (uint32_t j = 0; j < G; j++) {
        x[j] = c->best.genes[j];
    }
    x[G - 1u] = gene_at(c, pdt_ident_nearest_whole(nm->r));
    return kink_pass(c, G - 1u, x) ? OUT_KINK : pdt_ident_polish_probe_begin(c);
}

pdt_ident_outcome_t pdt_ident_polish_mirror(pdt_ident_t *c)
{
    pdt_ident_refine_t *nm = &c->nm;
    const uint32_t G = c->genes;
    pdt_real_t x[3];
    if (!(c->best.cost < PDT_REAL_MAX)) {
        return OUT_DONE;
    }
    if (on_kink(c, samples_of(c, c->best.genes[G - 1u]))) {
        return pdt_ident_polish_probe_begin(c);
    }
    /* The pinned pass's centre is the valley's point on the kink (the
     * other genes follow the dead time along it): the answer's mirror
     * image through it lies in the valley across the kink. */
    const pdt_ident_polish_t *p = &nm->late.polish;
    nm->f_kink = p->f0;
    for (uint32_t j = 0; j < G; j++) {
        x[j] = (PDT_R(2.0) * p->x[j]) - c->best.genes[j];
    }
    return kink_pass(c, G, x) ? OUT_KINK : pdt_ident_polish_probe_begin(c);
}

uint32_t pdt_ident_probe_group(const pdt_ident_t *c)
{
    const uint32_t rest = (2u * PROBE_STEPS) + 1u - c->nm.probe;
    return rest < (uint32_t)PDT_VECTOR_LANES ? rest : (uint32_t)PDT_VECTOR_LANES;
}

uint32_t pdt_ident_polish_group(const pdt_ident_t *c)
{
    const pdt_ident_polish_t *p = &c->nm.late.polish;
    if (p->state != POLISH_STENCIL) {
        return 1u;
    }
    const uint32_t left = points_of(c) - p->next;
    return left < (uint32_t)PDT_VECTOR_LANES ? left : (uint32_t)PDT_VECTOR_LANES;
}

/* The stencil's next group of points evaluated; the model proposed once
 * the stencil is complete. */
static pdt_ident_outcome_t stencil_group(pdt_ident_t *c)
{
    pdt_ident_polish_t *p = &c->nm.late.polish;
    const uint32_t G = c->genes;
    pdt_real_t pts[PDT_COST_MANY * 3u] = {PDT_R(0.0)};
    pdt_real_t cost[PDT_COST_MANY], gains[PDT_COST_MANY], offsets[PDT_COST_MANY];
    const uint32_t count = pdt_ident_polish_group(c);
    for (uint32_t i = 0; i < count; i++) {
        stencil_point(c, p->next + i, &pts[i * G]);
    }
    if (count == 1u) {
        pdt_ident_evaluate(c, pts, cost, gains, offsets);
    } else {
        pdt_ident_evaluate_many(c, pts, count, cost, gains, offsets);
    }
    for (uint32_t i = 0; i < count; i++) {
        p->f[p->next + i] = cost[i];
    }
    p->next += count;
    if (p->next == points_of(c)) {
        return propose(c);
    }
    return OUT_AGAIN;
}

pdt_ident_outcome_t pdt_ident_polish_step(pdt_ident_t *c, bool across)
{
    pdt_ident_polish_t *p = &c->nm.late.polish;
    const uint32_t G = c->genes;
    pdt_real_t f, gain, offset;
    if (p->state == POLISH_CENTRE) {
        pdt_ident_evaluate(c, p->x, &f, &gain, &offset);
        p->f0 = f;
        if (!(f < PDT_REAL_MAX) || (across && !(f < c->nm.f_kink))) {
            /* A minimum across the kink needs the cost to fall away from
             * it along the valley: a mirror image no lower than the
             * valley's point on the kink ends that pass at once. */
            return OUT_FALLBACK;
        }
        return stencil_begin(c);
    }
    if (p->state == POLISH_STENCIL) {
        return stencil_group(c);
    }
    /* POLISH_TRIAL */
    pdt_ident_evaluate(c, p->trial, &f, &gain, &offset);
    if (!(f < p->f0)) {
        /* A rise beyond the cost's rounding where the model expected a
         * fall: not a quadratic there (a FOPDT's cost has a kink where its
         * dead time is a whole number of samples). */
        p->rose = p->rose || f - p->f0 > POLISH_NOISE * POLISH_FTOL * p->f0;
        if (p->len < POLISH_XTOL || (!p->rose && p->pred <= POLISH_FTOL * p->f0)) {
            /* At the resolution of the differences, or a decrease below
             * the cost's rounding: the centre stands. */
            return settle(c);
        }
        if (p->back < POLISH_BACKTRACK && pdt_ident_left(c) >= 1u) {
            /* The model overshot: half the step. */
            for (uint32_t j = 0; j < G; j++) {
                p->trial[j] = p->x[j] + PDT_R(0.5) * (p->trial[j] - p->x[j]);
            }
            p->len *= PDT_R(0.5);
            p->pred *= PDT_R(0.5);
            p->back++;
            return OUT_AGAIN;
        }
        return OUT_FALLBACK;
    }
    p->iter++;
    for (uint32_t j = 0; j < G; j++) {
        p->x[j] = p->trial[j];
    }
    const pdt_real_t gain_f = p->f0 - f;
    p->f0 = f;
    if (p->len < POLISH_XTOL || gain_f <= POLISH_FTOL * (f + gain_f)) {
        return settle(c);
    }
    if (p->cut) {
        /* The model's minimum lies beyond the step's reach: a long valley
         * (a SOPDT's second lag vanishing towards its bound), which
         * Nelder-Mead follows in fewer evaluations than short Newton
         * steps. */
        return OUT_FALLBACK;
    }
    if (!p->fine) {
        go_fine(p, p->dims);
    }
    return stencil_begin(c);
}
