/*
 * The dead-time profile: a global check of the searches' answer. With the
 * gain and the offset in closed form, a model's cost is a function of its
 * shape and its dead time, and its basins are basins of the dead time. A
 * record of much noise under a fast input narrows the right one to a few
 * samples of dead time, so that two searches can both miss it and agree
 * on another: both end where a long lag makes up for no dead time, say.
 * The profile scores every whole sample of the searched dead-time range
 * at a few fixed shapes, and compares the least cost far from the
 * answer's dead time with the least near it. A range too long for that is
 * scored every few samples, and every sample of a window about the
 * answer besides: the basins an input's period makes lie one period
 * apart, so a period shorter than two of the grid's steps puts the
 * nearest other basin inside the window, and a longer one puts a grid
 * point in every basin.
 * Both are scored at the same coarse shapes, so neither is favoured: a far
 * point below the near ones is a basin the searches did not see, and it
 * is polished as a search's answer is; the vote then takes the lower.
 * Where neither finds one, what lies within a sample of the answer is
 * beyond both: under an input that moves at nearly every sample, the
 * interval across the answer's nearest kink can hold a lower minimum of
 * its own, with another shape. A short search confined to that interval
 * looks there, and its answer joins the vote in the same way.
 */
#include "pdt_ident_priv.h"
#include "pdt_internal.h"

/* Shapes at each dead time: FOPDT time constants (SOPDT lags, critically
 * damped) at 1/5 .. 4/5 of the searched range of their gene. One group of
 * the host's vector lanes. */
#define PROFILE_SHAPES 4u
/* Most dead times scored: a longer range is scored every few samples. */
#define PROFILE_POINTS 128u
/* Samples either side of the answer's dead time that are its basin: the
 * whole samples that bracket it. A wider window would hold the right basin
 * itself where the answer is a few samples off it. */
#define PROFILE_NEAR   PDT_R(1.0)
/* Most samples the window about the answer reaches either side. */
#define PROFILE_WINDOW 64u

/* The share of the refinement's budget the start across the answer's
 * nearest kink gets. */
#define PROFILE_ACROSS_SHARE 2u

/* The grid: whole samples of the searched record from the least dead time
 * up, every `every` of them, at most PROFILE_POINTS; where `every` > 1,
 * every sample within 2 `every` (at most PROFILE_WINDOW) of the answer's
 * dead time p->td besides. False where the range holds too few to tell
 * near from far. */
static bool grid_of(pdt_ident_t *c)
{
    pdt_ident_profile_t *p = &c->profile;
    const uint32_t dt = c->genes - 1u;
    const pdt_real_t Ts = c->cost.cfg.Ts;
    const pdt_real_t lo = pdt_ident_td_of_gene(c, c->lo[dt]) / Ts;
    const pdt_real_t hi = pdt_ident_td_of_gene(c, c->hi[dt]) / Ts;
    const pdt_real_t first = pdt_floor(lo + PDT_R(0.999));
    if (!(hi - first >= PDT_R(2.0) * PROFILE_NEAR + PDT_R(2.0))) {
        return false;
    }
    /* A range of a third of the record has at most n / 3 samples: the
     * count fits 32 bits whatever the real type. */
    const pdt_real_t span = hi - first;
    const uint32_t count = (uint32_t)span + 1u;
    const uint32_t every = (count + PROFILE_POINTS - 1u) / PROFILE_POINTS;
    p->points = ((count - 1u) / every) + 1u;
    p->td0 = (first > PDT_R(0.0) ? first : PDT_R(0.0)) * Ts;
    p->step = (pdt_real_t)every * Ts;
    p->fine = 0u;
    p->fine_td0 = p->td0;
    if (every > 1u) {
        const uint32_t w = (2u * every) < PROFILE_WINDOW ? 2u * every : PROFILE_WINDOW;
        const pdt_real_t at = pdt_floor((p->td / Ts) + PDT_R(0.5));
        const pdt_real_t a = (at - (pdt_real_t)w) > p->td0 / Ts ? at - (pdt_real_t)w : p->td0 / Ts;
        const pdt_real_t b = (at + (pdt_real_t)w) < hi ? at + (pdt_real_t)w : pdt_floor(hi);
        const pdt_real_t width = b - a;
        p->fine = width >= PDT_R(0.0) ? (uint32_t)width + 1u : 0u;
        p->fine_td0 = a * Ts;
    }
    return true;
}

/* Dead times scored: the window's, then the grid's. */
static uint32_t dead_times(const pdt_ident_profile_t *p)
{
    return p->fine + p->points;
}

pdt_ident_outcome_t pdt_ident_profile_end(pdt_ident_t *c, bool across)
{
    const pdt_ident_profile_t *p = &c->profile;
    if (across) {
        c->lo[c->genes - 1u] = p->bounds[0];
        c->hi[c->genes - 1u] = p->bounds[1];
    }
    /* Its point's polish ended: the last answer kept is the profile's.
     * It only counts in another basin: back in the searches' basin it
     * found nothing they had not, and their answer, polished on the way
     * they took, stands. The search across the kink only counts below the
     * searches' answers: confined to its interval, it may end on the
     * interval's edge, no basin of the whole range to put to the vote as
     * a rival. */
    c->nm.keep_probe = false;
    const uint32_t k = c->vote.done - 1u;
    bool other = true;
    for (uint32_t i = 0u; i < k; i++) {
        other = other && !pdt_ident_vote_same_basin(c, i, k) &&
                (!across || c->vote.cost[k] < c->vote.cost[i]);
    }
    c->vote.done = other ? c->vote.done : k;
    c->vote.profiled = other ? c->vote.done : 0u;
    return OUT_DONE;
}

/* The output error only: the searches of the other criteria do not vote,
 * and the frequency criterion scans its dead time already. */
bool pdt_ident_profiled(const pdt_ident_config_t *cfg)
{
    return cfg->cost == PDT_COST_SIMULATION;
}

pdt_ident_outcome_t pdt_ident_profile_begin(pdt_ident_t *c)
{
    pdt_ident_profile_t *p = &c->profile;
    if (!pdt_ident_profiled(&c->cfg) || c->vote.done == 0u) {
        return OUT_SKIPPED;
    }
    p->td = pdt_ident_td_of_gene(c, c->vote.genes[pdt_ident_vote_best(c)][c->genes - 1u]);
    if (!grid_of(c)) {
        return OUT_SKIPPED;
    }
    const uint32_t scan = dead_times(p) * PROFILE_SHAPES;
    /* On a coarse record, the whole record's polish (at least genes + 1,
     * pdt_ident_coarse_fine) comes after it. */
    const uint32_t fine = c->cost.n < c->data.n ? c->genes + 1u : 0u;
    const uint32_t need = scan + c->cfg.refine_evaluations + pdt_ident_late_reserve(&c->cfg) + fine;
    if (c->evaluations >= c->cfg.max_evaluations ||
        c->cfg.max_evaluations - c->evaluations < need) {
        return OUT_SKIPPED;
    }
    p->next = 0u;
    for (uint32_t k = 0u; k < 2u; k++) {
        p->near[k] = PDT_REAL_MAX;
        p->far[k] = PDT_REAL_MAX;
    }
    c->vote.base = c->evaluations;
    c->vote.budget = scan;
    return OUT_DONE;
}

/* Grid point i's shape (0 .. PROFILE_SHAPES - 1) and dead time (0 ..
 * dead_times - 1). Where each shape's response scores all its dead times
 * (pdt_ident_shift_ok), a shape's points come together, its response
 * computed once; else a dead time's four shapes come together, a group
 * of the host's vector lanes. */
static void point_index(const pdt_ident_t *c, uint32_t i, uint32_t *shape, uint32_t *dt)
{
    const uint32_t D = dead_times(&c->profile);
    if (pdt_ident_shift_ok(c)) {
        *shape = i / D;
        *dt = i % D;
    } else {
        *shape = i % PROFILE_SHAPES;
        *dt = i / PROFILE_SHAPES;
    }
}

uint32_t pdt_ident_profile_group(const pdt_ident_t *c)
{
    const pdt_ident_profile_t *p = &c->profile;
    const uint32_t left = (dead_times(p) * PROFILE_SHAPES) - p->next;
    if (pdt_ident_shift_ok(c)) {
        /* Dead times of the same shape, as many as score no more samples
         * than one evaluation of the whole record (a step's least budget,
         * so a firmware build keeps its bound; a point from the response
         * costs less than an evaluation), at most a group of the cost's
         * and at least one of the host's lanes. Fixed by the record, not
         * by the call's budget. */
        const size_t fit = c->data.n / c->cost.n;
        uint32_t most = fit < (size_t)PDT_COST_MANY ? (uint32_t)fit : PDT_COST_MANY;
        most = most > (uint32_t)PDT_VECTOR_LANES ? most : (uint32_t)PDT_VECTOR_LANES;
        const uint32_t in_shape = dead_times(p) - (p->next % dead_times(p));
        most = in_shape < most ? in_shape : most;
        return left < most ? left : most;
    }
    return left < (uint32_t)PDT_VECTOR_LANES ? left : (uint32_t)PDT_VECTOR_LANES;
}

/* Grid point i's genes in x; returns its dead time and its dead time's
 * index in *at. */
static pdt_real_t point_of(const pdt_ident_t *c, uint32_t i, pdt_real_t *x, uint32_t *at)
{
    const pdt_ident_profile_t *p = &c->profile;
    const uint32_t G = c->genes;
    uint32_t shape, d;
    point_index(c, i, &shape, &d);
    *at = d;
    const uint32_t level = shape + 1u;
    const pdt_real_t f = (pdt_real_t)level / ((pdt_real_t)PROFILE_SHAPES + PDT_R(1.0));
    x[0] = c->lo[0] + ((c->hi[0] - c->lo[0]) * f);
    if (G == 3u) {
        /* Critical damping (the damping gene's sqrt(zeta_min)). */
        x[1] = pdt_ident_clamp(c, 1u, pdt_sqrt(c->cfg.zeta_min));
    }
    pdt_real_t Td = p->fine_td0 + (c->cost.cfg.Ts * (pdt_real_t)d);
    if (d >= p->fine) {
        const uint32_t on_grid = d - p->fine;
        Td = p->td0 + (p->step * (pdt_real_t)on_grid);
    }
    x[G - 1u] = pdt_ident_gene_of_td(c, Td);
    return Td;
}

/* The interval across the nearest kink from the answer: its search
 * confined to it (the dead time's bounds narrowed to its two whole
 * samples, the answer's shape at its middle as the start), else it goes
 * back across the kink it was to look past. False where the dead time is
 * whole samples, the answer lies on a kink (no side to take) or the
 * interval lies beyond the bounds. */
static bool across_begin(pdt_ident_t *c, pdt_real_t *x)
{
    pdt_ident_profile_t *p = &c->profile;
    const uint32_t G = c->genes;
    const pdt_real_t Ts = c->cost.cfg.Ts;
    const pdt_real_t r = p->td / Ts;
    const pdt_real_t whole = pdt_ident_nearest_whole(r);
    if (c->cfg.delay_mode != PDT_DELAY_FRACTIONAL || !(pdt_fabs(r - whole) >= PDT_IDENT_ON_KINK)) {
        return false;
    }
    const pdt_real_t first = r > whole ? whole - PDT_R(1.0) : whole;
    if (!(first >= PDT_R(0.0))) {
        return false;
    }
    /* Clamped to the bounds: the interval's part within them, and a
     * middle beyond them lands on their end. */
    const pdt_real_t lo = pdt_ident_gene_of_td(c, first * Ts);
    const pdt_real_t hi = pdt_ident_gene_of_td(c, (first + PDT_R(1.0)) * Ts);
    const pdt_real_t mid = pdt_ident_gene_of_td(c, (first + PDT_R(0.5)) * Ts);
    if (!(mid > lo && mid < hi)) {
        return false;
    }
    const uint32_t best = pdt_ident_vote_best(c);
    for (uint32_t j = 0; j < G; j++) {
        x[j] = c->vote.genes[best][j];
    }
    x[G - 1u] = mid;
    p->bounds[0] = c->lo[G - 1u];
    p->bounds[1] = c->hi[G - 1u];
    c->lo[G - 1u] = lo;
    c->hi[G - 1u] = hi;
    return true;
}

/* The far point polished as a search's answer is, when it lies below the
 * near ones: the grid's first, else the window's (OUT_POLISH); else the
 * start across the nearest kink with a share of that budget (OUT_KINK);
 * the start in c->start; else the vote (OUT_DONE). */
static pdt_ident_outcome_t scan_end(pdt_ident_t *c)
{
    pdt_ident_profile_t *p = &c->profile;
    pdt_real_t x[3];
    uint32_t k = 1u;
    if (p->far[0] < p->near[0]) {
        k = 0u;
    }
    const pdt_real_t *start = p->far_x[k];
    uint32_t budget = c->cfg.refine_evaluations;
    pdt_ident_outcome_t out = OUT_POLISH;
    if (p->far[k] < p->near[k]) {
        /* The far point's polish. */
    } else if (budget / PROFILE_ACROSS_SHARE >= c->genes + 1u && across_begin(c, x)) {
        out = OUT_KINK;
        budget /= PROFILE_ACROSS_SHARE;
        start = x;
    } else {
        return OUT_DONE;
    }
    pdt_ident_polish_budget(c, budget);
    c->nm.keep_probe = true;
    for (uint32_t j = 0; j < c->genes; j++) {
        c->start[j] = start[j];
    }
    return out;
}

pdt_ident_outcome_t pdt_ident_profile_step(pdt_ident_t *c)
{
    pdt_ident_profile_t *p = &c->profile;
    const uint32_t G = c->genes;
    const uint32_t count = pdt_ident_profile_group(c);
    /* Initialised: the compiler cannot see that count >= 1. */
    pdt_real_t pts[PDT_COST_MANY * 3u] = {PDT_R(0.0)};
    pdt_real_t td[PDT_COST_MANY];
    uint32_t at[PDT_COST_MANY];
    pdt_real_t cost[PDT_COST_MANY], gains[PDT_COST_MANY], offsets[PDT_COST_MANY];
    for (uint32_t i = 0; i < count; i++) {
        td[i] = point_of(c, p->next + i, &pts[i * G], &at[i]);
    }
    bool scored = false;
    if (pdt_ident_shift_ok(c)) {
        /* A shape's first group computes its response into the scratch;
         * the later ones score from it. Each dead time is whole samples
         * of the searched record (grid_of). */
        const bool fresh = (p->next % dead_times(p)) == 0u;
        size_t delay[PDT_COST_MANY];
        for (uint32_t i = 0; i < count; i++) {
            delay[i] = (size_t)pdt_ident_nearest_whole(td[i] / c->cost.cfg.Ts);
        }
        scored = pdt_ident_evaluate_shift(c, pts, delay, count, fresh, cost, gains, offsets);
    }
    if (!scored) {
        pdt_ident_evaluate_many(c, pts, count, cost, gains, offsets);
    }
    for (uint32_t i = 0; i < count; i++) {
        /* The window's points are compared at one sample, the grid's at
         * its step: near the answer each tells its own scale's basin. */
        uint32_t k = 0u;
        if (at[i] < p->fine) {
            k = 1u;
        }
        const pdt_real_t reach = PROFILE_NEAR * (k == 1u ? c->cost.cfg.Ts : p->step);
        const pdt_real_t d = td[i] > p->td ? td[i] - p->td : p->td - td[i];
        if (d <= reach) {
            p->near[k] = cost[i] < p->near[k] ? cost[i] : p->near[k];
        } else if (cost[i] < p->far[k]) {
            p->far[k] = cost[i];
            for (uint32_t j = 0; j < G; j++) {
                p->far_x[k][j] = pts[(i * G) + j];
            }
        } else {
            /* Neither the nearest nor the least far. */
        }
    }
    p->next += count;
    if (p->next >= dead_times(p) * PROFILE_SHAPES) {
        return scan_end(c);
    }
    return OUT_AGAIN;
}
