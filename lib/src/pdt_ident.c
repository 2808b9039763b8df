/*
 * Identification: genetic algorithm over the model shape, Nelder-Mead
 * refinement, closed-form gain and offset, all as a resumable state machine
 * so that each pdt_ident_step call does a bounded amount of work.
 */
#include "pdt/pdt_ident.h"

#include "pdt/pdt_discrete.h"
#include "pdt_ga.h"
#include "pdt_internal.h"
#include "pdt_model_priv.h"

#define IDENT_MAGIC PDT_MAGIC('P', 'D', 'I', 'D')

enum phase {
    PH_INIT_POP = 1, /* evaluating the initial population */
    PH_BREED,        /* next call breeds a generation */
    PH_EVAL_OFF,     /* evaluating offspring */
    PH_BAND,         /* CONTROL weighting: the band from the time model */
    PH_REFINE_PREP,  /* re-centre the spectra on the estimated offset */
    PH_REFINE,       /* Nelder-Mead */
    PH_DELAY_SCAN,   /* frequency criterion: dead time and sign from Ct */
    PH_DELAY_REFINE,
    PH_FINISH, /* the answer; may re-score once (an integrator) */
    PH_DONE
};

enum nm_state { NM_VERTEX = 1, NM_REFLECT, NM_EXPAND, NM_CONTRACT, NM_SHRINK, NM_END };

/* Nelder-Mead coefficients (the standard ones) and its stopping size in
 * normalised gene units. */
#define NM_STEP PDT_R(0.05)
#define NM_XTOL PDT_R(1e-5)

/* Most refinement starts (niches refined). */
#define NM_STARTS 3u

/* The dead-time gene is linear below a sixteenth of its range, then
 * logarithmic (see td_offset). */
#define TD_OFFSET_DIV PDT_R(16.0)

/* The frequency criterion cannot see the dead time or the sign of the gain;
 * after its search, Td is scanned on a grid of SCAN_POINTS values of the
 * time cost (both signs of the gain each), then refined by GOLDEN_STEPS of
 * golden-section search around the best grid point. */
#define SCAN_POINTS      64u
#define GOLDEN_STEPS     16u
#define SCAN_EVALUATIONS (2u * SCAN_POINTS + GOLDEN_STEPS + 2u)
#define GOLDEN           PDT_R(0.6180339887498949)

void pdt_ident_config_default(pdt_ident_config_t *cfg)
{
    if (cfg == NULL) {
        return;
    }
    *cfg = (pdt_ident_config_t){0};
    cfg->model = PDT_MODEL_FOPDT;
    cfg->cost = PDT_COST_SIMULATION;
    cfg->time_kind = PDT_COST_SIMULATION;
    cfg->phi_t = PDT_R(1.0);
    cfg->phi_f = PDT_R(1.0);
    cfg->weight = PDT_WEIGHT_AUTO;
    cfg->delay_mode = PDT_DELAY_FRACTIONAL;
    cfg->zeta_min = PDT_R(0.2);
    cfg->integrating = true;
    cfg->population = 0u;
    cfg->max_evaluations = 9000u;
    cfg->searches = 0u;
    cfg->refine_evaluations = 300u;
    cfg->tolerance = PDT_R(1e-4);
    cfg->stall_generations = 10u;
    cfg->seed = 1u;
    cfg->eta_c = PDT_R(15.0);
    cfg->eta_m = PDT_R(20.0);
    cfg->p_crossover = PDT_R(0.9);
    cfg->p_mutation = PDT_R(0.0);
    cfg->sigma_share = PDT_R(0.1);
    cfg->elite = 2u;
}

static uint32_t genes_of(pdt_model_kind_t kind)
{
    return kind == PDT_MODEL_SOPDT ? 3u : 2u;
}

/* The population, the automatic one resolved: a 2-gene FOPDT search needs
 * fewer individuals than a 3-gene SOPDT one to cover its space. */
static uint32_t population_of(const pdt_ident_config_t *cfg)
{
    if (cfg->population != 0u) {
        return cfg->population;
    }
    return cfg->model == PDT_MODEL_SOPDT ? PDT_IDENT_POPULATION_SOPDT : PDT_IDENT_POPULATION_FOPDT;
}

static bool uses_frequency(pdt_cost_kind_t kind)
{
    return kind == PDT_COST_FREQUENCY || kind == PDT_COST_COMBINED;
}

/* The weighting with AUTO resolved. */
static pdt_weight_kind_t weight_of(const pdt_ident_config_t *cfg)
{
    if (cfg->weight != PDT_WEIGHT_AUTO) {
        return cfg->weight;
    }
    return cfg->model == PDT_MODEL_FOPDT && cfg->cost == PDT_COST_COMBINED ? PDT_WEIGHT_CONTROL
                                                                           : PDT_WEIGHT_UNIFORM;
}

/* Whether the search starts on the time cost to find the control band. */
static bool control_band(const pdt_ident_config_t *cfg)
{
    return uses_frequency(cfg->cost) && weight_of(cfg) == PDT_WEIGHT_CONTROL;
}

/* The cost configuration the identification runs on. */
static void cost_config(const pdt_ident_config_t *cfg, pdt_real_t u0, pdt_real_t y0,
                        size_t delay_max, pdt_cost_config_t *cc)
{
    pdt_cost_config_default(cc);
    cc->Ts = cfg->Ts;
    cc->u0 = u0;
    cc->y0 = y0;
    cc->delay_min = 0u;
    cc->delay_max = delay_max;
    cc->kind = cfg->cost;
    cc->time_kind = cfg->time_kind;
    if (control_band(cfg)) {
        /* First stage: the time cost; the spectra are prepared all the
         * same, so the workspace is sized for the second. */
        cc->kind = cfg->time_kind;
    }
    cc->delay_mode = cfg->delay_mode;
    cc->estimate_offset = true;
    /* The paper's window would drop the first Td_max / Ts samples: where a
     * step test shows its dead time. */
    cc->whole_record = true;
    cc->use_frequency = uses_frequency(cfg->cost);
    cc->phi_t = cfg->phi_t;
    cc->phi_f = cfg->phi_f;
    cc->weight = weight_of(cfg) == PDT_WEIGHT_CONTROL ? PDT_WEIGHT_UNIFORM : weight_of(cfg);
    cc->f_lo = cfg->f_lo;
    cc->f_hi = cfg->f_hi;
    cc->weights = cfg->weights;
}

/* Bounds with the defaults filled in, checked. */
typedef struct bounds {
    pdt_real_t tau_min, tau_max, Td_min, Td_max;
} bounds_t;

static pdt_status_t resolve_bounds(const pdt_ident_config_t *cfg, size_t n, bounds_t *b)
{
    pdt_real_t T = cfg->Ts * (pdt_real_t)n;
    b->tau_min = cfg->tau_min;
    b->tau_max = cfg->tau_max;
    if (b->tau_min == PDT_R(0.0) && b->tau_max == PDT_R(0.0)) {
        b->tau_min = cfg->Ts * PDT_R(0.25);
        b->tau_max = PDT_R(2.0) * T;
    }
    b->Td_min = cfg->Td_min;
    b->Td_max = cfg->Td_max;
    if (b->Td_min == PDT_R(0.0) && b->Td_max == PDT_R(0.0)) {
        b->Td_max = T / PDT_R(3.0);
    }
    if (!pdt_finite(b->tau_min) || !pdt_finite(b->tau_max) || !pdt_finite(b->Td_min) ||
        !pdt_finite(b->Td_max) || !(b->tau_min > PDT_R(0.0)) || b->Td_min < PDT_R(0.0)) {
        return PDT_ERR_ARG;
    }
    if (b->tau_min >= b->tau_max || b->Td_min > b->Td_max) {
        return PDT_ERR_BOUNDS;
    }
    return PDT_OK;
}

/* Offset of the dead-time gene log(Td + c0): below c0 the scale is about
 * linear, above it logarithmic, so long dead times get as much room per
 * decade as short ones, but dead times below c0 (a sixteenth of the range)
 * share one stretch. With c0 = Ts instead, a third of the range went to
 * dead times of a few samples, and on a relay record (periodic: a half
 * period of delay looks like a sign change) 10 of 40 seeds ended at Td = 0
 * with the wrong sign; with a sixteenth, none. */
static pdt_real_t td_offset(const pdt_ident_config_t *cfg, const bounds_t *b)
{
    pdt_real_t c0 = (b->Td_max - b->Td_min) / TD_OFFSET_DIV;
    return c0 > cfg->Ts ? c0 : cfg->Ts;
}

/* Gene bounds of the search: shape genes first, the dead-time gene last.
 * Checked here, before anything is written, and by the size query. */
static pdt_status_t gene_bounds(const pdt_ident_config_t *cfg, const bounds_t *b, pdt_real_t *lo,
                                pdt_real_t *hi)
{
    const uint32_t G = genes_of(cfg->model);
    if (cfg->model == PDT_MODEL_FOPDT) {
        lo[0] = pdt_log(b->tau_min);
        hi[0] = pdt_log(b->tau_max);
    } else {
        /* 1/a = T1 T2 / (T1 + T2) lies in [T2 / 2, T2] for T1 >= T2. */
        lo[0] = pdt_log(b->tau_min * PDT_R(0.5));
        hi[0] = pdt_log(b->tau_max);
        /* Damping gene v = sqrt(zeta_min / zeta): 0 is the integrator, 1 the
         * least damping searched, sqrt(zeta_min) critical damping. The
         * square root gives the overdamped and the (nearly) integrating
         * models as much room as the underdamped ones; on 1/zeta itself a
         * random population often has no member near the integrator. */
        pdt_real_t r = b->tau_max / b->tau_min;
        pdt_real_t inv_zeta_lo = PDT_R(2.0) * pdt_sqrt(r) / (PDT_R(1.0) + r);
        lo[1] = cfg->integrating ? PDT_R(0.0) : pdt_sqrt(inv_zeta_lo * cfg->zeta_min);
        hi[1] = PDT_R(1.0);
        if (!(lo[1] < hi[1])) {
            return PDT_ERR_BOUNDS;
        }
    }
    /* Dead-time gene log(Td + Ts): every decade of dead time gets the same
     * room, so a dead time of a few samples is as easy to find as one of a
     * third of the record. */
    const pdt_real_t c0 = td_offset(cfg, b);
    lo[G - 1u] = pdt_log(b->Td_min + c0);
    hi[G - 1u] = pdt_log(b->Td_max + c0);
    if (!(hi[G - 1u] > lo[G - 1u])) {
        /* A fixed dead time: a range of zero width the operators can still
         * handle. */
        hi[G - 1u] = lo[G - 1u] + PDT_R(1e-4);
    }
    return PDT_OK;
}

/* Evaluations kept back after the refinement: the dead-time scan of the
 * frequency criterion, and the re-scoring of a SOPDT reported as an
 * integrator. */
static uint32_t late_reserve(const pdt_ident_config_t *cfg)
{
    uint32_t r = cfg->cost == PDT_COST_FREQUENCY ? SCAN_EVALUATIONS : 0u;
    if (cfg->model == PDT_MODEL_SOPDT && cfg->integrating) {
        r += 1u;
    }
    return r;
}

/* The least budget of one search: one population (two with the CONTROL
 * weighting, which scores it once per cost), one simplex and the late
 * reserve. */
static uint64_t search_need(const pdt_ident_config_t *cfg)
{
    const uint64_t populations = control_band(cfg) ? 2u : 1u;
    return populations * population_of(cfg) + cfg->refine_evaluations + late_reserve(cfg);
}

/* Independent searches: the time criteria only (the frequency criteria
 * re-centre their spectra during a search); as asked, or as many as the
 * budget gives each a whole search, up to PDT_IDENT_MAX_SEARCHES. 0 when
 * the budget does not cover the searches asked for. */
static uint32_t searches_of(const pdt_ident_config_t *cfg)
{
    const uint64_t need = search_need(cfg);
    if (uses_frequency(cfg->cost)) {
        return cfg->max_evaluations >= need ? 1u : 0u;
    }
    if (cfg->searches != 0u) {
        return (uint64_t)cfg->max_evaluations >= need * cfg->searches ? cfg->searches : 0u;
    }
    uint64_t k = (uint64_t)cfg->max_evaluations / need;
    return (uint32_t)(k > PDT_IDENT_MAX_SEARCHES ? PDT_IDENT_MAX_SEARCHES : k);
}

/* The weighting and the criterion's weights, checked here so that the size
 * query refuses what init would. */
static pdt_status_t check_weight(const pdt_ident_config_t *cfg)
{
    switch (cfg->weight) {
    case PDT_WEIGHT_UNIFORM:
    case PDT_WEIGHT_CONTROL:
    case PDT_WEIGHT_AUTO:
        break;
    case PDT_WEIGHT_BAND:
        if (!pdt_finite(cfg->f_lo) || !pdt_finite(cfg->f_hi) || cfg->f_lo < PDT_R(0.0)) {
            return PDT_ERR_ARG;
        }
        if (cfg->f_lo > cfg->f_hi) {
            return PDT_ERR_BOUNDS;
        }
        break;
    case PDT_WEIGHT_CUSTOM:
        if (cfg->weights == NULL) {
            return PDT_ERR_ARG;
        }
        break;
    default:
        return PDT_ERR_ARG;
    }
    if (!pdt_finite(cfg->phi_t) || !pdt_finite(cfg->phi_f) || cfg->phi_t < PDT_R(0.0) ||
        cfg->phi_f < PDT_R(0.0)) {
        return PDT_ERR_ARG;
    }
    /* Both parts weighted 0 leave nothing to minimise. */
    if (cfg->cost == PDT_COST_COMBINED && !(cfg->phi_t > PDT_R(0.0)) &&
        !(cfg->phi_f > PDT_R(0.0))) {
        return PDT_ERR_ARG;
    }
    return PDT_OK;
}

static pdt_status_t check_config(const pdt_ident_config_t *cfg)
{
    if (cfg->model != PDT_MODEL_FOPDT && cfg->model != PDT_MODEL_SOPDT) {
        return PDT_ERR_ARG;
    }
    if (!pdt_finite(cfg->Ts) || !(cfg->Ts > PDT_R(0.0))) {
        return PDT_ERR_ARG;
    }
    const uint32_t P = population_of(cfg);
    if (P < 4u || P > PDT_IDENT_MAX_POPULATION || (P % 2u) != 0u) {
        return PDT_ERR_ARG;
    }
    if (cfg->cost != PDT_COST_PREDICTION && cfg->cost != PDT_COST_SIMULATION &&
        cfg->cost != PDT_COST_FREQUENCY && cfg->cost != PDT_COST_COMBINED) {
        return PDT_ERR_ARG;
    }
    if (cfg->delay_mode != PDT_DELAY_FRACTIONAL && cfg->delay_mode != PDT_DELAY_INTEGER) {
        return PDT_ERR_ARG;
    }
    const pdt_status_t wst = check_weight(cfg);
    if (wst != PDT_OK) {
        return wst;
    }
    /* The refinement needs at least one simplex: genes + 1 evaluations;
     * the CONTROL weighting scores the population twice (once per cost). */
    if (cfg->elite >= P || cfg->stall_generations == 0u ||
        cfg->refine_evaluations < genes_of(cfg->model) + 1u ||
        cfg->searches > PDT_IDENT_MAX_SEARCHES || searches_of(cfg) == 0u) {
        return PDT_ERR_ARG;
    }
    if (!(cfg->eta_c > PDT_R(0.0)) || !(cfg->eta_m > PDT_R(0.0)) || !pdt_finite(cfg->eta_c) ||
        !pdt_finite(cfg->eta_m) || !(cfg->p_crossover >= PDT_R(0.0)) ||
        !(cfg->p_crossover <= PDT_R(1.0)) || !(cfg->p_mutation >= PDT_R(0.0)) ||
        !(cfg->p_mutation <= PDT_R(1.0)) || !(cfg->sigma_share > PDT_R(0.0)) ||
        !pdt_finite(cfg->sigma_share) || !(cfg->tolerance >= PDT_R(0.0)) ||
        !pdt_finite(cfg->tolerance)) {
        return PDT_ERR_ARG;
    }
    if (cfg->model == PDT_MODEL_SOPDT &&
        (!(cfg->zeta_min > PDT_R(0.0)) || !pdt_finite(cfg->zeta_min))) {
        return PDT_ERR_ARG;
    }
    if (!pdt_finite(cfg->K_min) || !pdt_finite(cfg->K_max)) {
        return PDT_ERR_ARG;
    }
    if (cfg->K_min > cfg->K_max) {
        return PDT_ERR_BOUNDS;
    }
    return PDT_OK;
}

/* Whole samples in a time t >= 0 at period Ts, at most cap: a ratio past
 * the record (or past size_t) is the record's end, never a float-to-size
 * overflow. */
static size_t samples_in(pdt_real_t t, pdt_real_t Ts, size_t cap)
{
    const pdt_real_t q = t / Ts;
    return (q >= PDT_R(0.0) && q < (pdt_real_t)cap) ? (size_t)q : cap;
}

/* Layout of the workspace after the cost's own part, in reals. */
static size_t own_reals(uint32_t pop, uint32_t genes, size_t n)
{
    return 2u * (size_t)pop * (genes + 3u) + (size_t)pop + n;
}

size_t pdt_ident_workspace_size(const pdt_ident_config_t *cfg, size_t n)
{
    bounds_t b;
    pdt_cost_config_t cc;
    pdt_real_t lo[3], hi[3];
    if (cfg == NULL || n < PDT_MIN_SAMPLES || check_config(cfg) != PDT_OK ||
        resolve_bounds(cfg, n, &b) != PDT_OK || gene_bounds(cfg, &b, lo, hi) != PDT_OK) {
        return 0u;
    }
    /* The delay bound init gives the cost (a smaller FFT for a larger
     * bound: the size must be init's own). */
    cost_config(cfg, PDT_R(0.0), PDT_R(0.0), samples_in(b.Td_max, cfg->Ts, n) + 1u, &cc);
    size_t cost_bytes = pdt_cost_workspace_size(&cc, n);
    if (cc.use_frequency && cost_bytes == 0u) {
        return 0u;
    }
    /* Round the cost part up so the rest stays aligned for pdt_real_t. */
    cost_bytes = (cost_bytes + sizeof(pdt_real_t) - 1u) / sizeof(pdt_real_t) * sizeof(pdt_real_t);
    return cost_bytes + own_reals(population_of(cfg), genes_of(cfg->model), n) * sizeof(pdt_real_t);
}

/* The output level before the input first moves: the mean of y over that
 * stretch (and the shortest dead time after it), at least one sample. Only
 * the start of the search uses it; the model re-estimates the offset. */
static pdt_real_t initial_level(const pdt_ident_data_t *d, size_t quiet_extra)
{
    size_t k = 1u;
    while (k < d->n && d->u[k] == d->u[0]) {
        k++;
    }
    k += quiet_extra;
    if (k > d->n / 2u) {
        k = d->n / 2u > 0u ? d->n / 2u : 1u;
    }
    pdt_real_t shift = d->y[0];
    pdt_real_t sum = PDT_R(0.0);
    for (size_t i = 0; i < k; i++) {
        sum += d->y[i] - shift;
    }
    return shift + sum / (pdt_real_t)k;
}

/* Whether the record ends at rest, as the frequency criteria need: over
 * the last twentieth (at least 8 samples) the means of u and y lie within
 * REST_TOLERANCE of their ranges from the starting levels. A coarse guard
 * against a step test or an integrating process, whose spectra Cf would
 * compare as if the record were whole; a chirp that stops mid-cycle
 * passes. */
#define REST_TOLERANCE PDT_R(0.2)

static bool ends_at_rest(const pdt_ident_data_t *d, pdt_real_t y_start, pdt_real_t u_range,
                         pdt_real_t y_range)
{
    size_t tail = d->n / 20u;
    tail = tail < 8u ? 8u : tail;
    pdt_real_t su = PDT_R(0.0), sy = PDT_R(0.0);
    for (size_t k = d->n - tail; k < d->n; k++) {
        su += d->u[k] - d->u[0];
        sy += d->y[k] - y_start;
    }
    return pdt_fabs(su / (pdt_real_t)tail) <= REST_TOLERANCE * u_range &&
           pdt_fabs(sy / (pdt_real_t)tail) <= REST_TOLERANCE * y_range;
}

/* A search from scratch, its random stream the search's own: a Latin
 * hypercube start (each gene's range cut into P strata, one individual per
 * stratum, strata paired across genes at random, so the first generation
 * covers every gene's range evenly; the offspring area holds the
 * permutation meanwhile) and the GA's state reset. */
static void search_start(pdt_ident_t *c)
{
    const size_t P = c->cfg.population, G = c->genes;
    pdt_rng_t rng;
    pdt_rng_seed(&rng, c->cfg.seed, 0x5eed5eedu + c->search);
    for (size_t j = 0; j < G; j++) {
        pdt_real_t *perm = c->off;
        for (size_t i = 0; i < P; i++) {
            perm[i] = (pdt_real_t)i;
        }
        for (size_t i = P - 1u; i > 0u; i--) {
            size_t k = pdt_rng_below(&rng, (uint32_t)(i + 1u));
            pdt_real_t t = perm[i];
            perm[i] = perm[k];
            perm[k] = t;
        }
        for (size_t i = 0; i < P; i++) {
            pdt_real_t f = (perm[i] + pdt_rng_uniform(&rng)) / (pdt_real_t)P;
            c->pop[i * G + j] = c->lo[j] + (c->hi[j] - c->lo[j]) * f;
        }
    }
    c->rng_state = rng.state;
    c->rng_inc = rng.inc;
    c->next = 0u;
    c->search_base = c->evaluations;
    c->stall = 0u;
    c->best_cost = PDT_REAL_MAX;
    c->best_history = PDT_REAL_MAX;
    c->stage = control_band(&c->cfg) ? 1u : 0u;
    c->phase = PH_INIT_POP;
}

pdt_status_t pdt_ident_init(pdt_ident_t *ctx, const pdt_ident_config_t *cfg,
                            const pdt_ident_data_t *data, void *work, size_t work_len)
{
    if (ctx == NULL || cfg == NULL || data == NULL || data->u == NULL || data->y == NULL) {
        return PDT_ERR_ARG;
    }
    pdt_status_t st = check_config(cfg);
    if (st != PDT_OK) {
        return st;
    }
    if (data->n < PDT_MIN_SAMPLES) {
        return PDT_ERR_TOO_SHORT;
    }
    bounds_t b;
    pdt_real_t glo[3], ghi[3];
    st = resolve_bounds(cfg, data->n, &b);
    if (st == PDT_OK) {
        st = gene_bounds(cfg, &b, glo, ghi);
    }
    if (st != PDT_OK) {
        return st;
    }
    pdt_real_t umin = data->u[0], umax = data->u[0], ymin = data->y[0], ymax = data->y[0];
    for (size_t k = 0; k < data->n; k++) {
        pdt_real_t uk = data->u[k], yk = data->y[k];
        if (!pdt_finite(uk) || !pdt_finite(yk)) {
            return PDT_ERR_NONFINITE;
        }
        umin = uk < umin ? uk : umin;
        umax = uk > umax ? uk : umax;
        ymin = yk < ymin ? yk : ymin;
        ymax = yk > ymax ? yk : ymax;
    }
    if (!(umax > umin) || !(ymax > ymin)) {
        return PDT_ERR_NO_EXCITATION;
    }
    if (uses_frequency(cfg->cost) &&
        !ends_at_rest(data, initial_level(data, samples_in(b.Td_min, cfg->Ts, data->n)),
                      umax - umin, ymax - ymin)) {
        return PDT_ERR_NOT_AT_REST;
    }
    pdt_real_t lmax = b.Td_max / cfg->Ts;
    if (!(lmax < (pdt_real_t)(data->n))) {
        return PDT_ERR_TOO_SHORT;
    }
    size_t delay_max = (size_t)lmax + 1u;
    if (work == NULL) {
        return PDT_ERR_NOMEM;
    }
    if (!pdt_aligned(work)) {
        return PDT_ERR_ARG;
    }
    size_t need = pdt_ident_workspace_size(cfg, data->n);
    if (need == 0u) {
        return PDT_ERR_ARG;
    }
    if (work_len < need) {
        return PDT_ERR_NOMEM;
    }

    /* Everything below writes only into locals and the workspace until the
     * final copy into *ctx. */
    pdt_ident_t c;
    c = (pdt_ident_t){0};
    c.cfg = *cfg;
    c.cfg.population = population_of(cfg);
    c.data = *data;
    c.genes = genes_of(cfg->model);
    pdt_real_t y0 = initial_level(data, samples_in(b.Td_min, cfg->Ts, data->n));
    pdt_cost_config_t cc;
    cost_config(cfg, data->u[0], y0, delay_max, &cc);
    size_t cost_bytes = pdt_cost_workspace_size(&cc, data->n);
    st = pdt_cost_init(&c.cost, &cc, data->u, data->y, data->n, work, cost_bytes);
    if (st != PDT_OK) {
        return st;
    }
    /* A band or custom weights that select no bin of this record (e.g. a
     * band above the Nyquist frequency) would leave the frequency part
     * empty and the search blind in it. */
    if ((cfg->cost == PDT_COST_FREQUENCY ||
         (cfg->cost == PDT_COST_COMBINED && cfg->phi_f > PDT_R(0.0))) &&
        c.cost.k_first > c.cost.k_last) {
        return PDT_ERR_ARG;
    }
    c.cost_work = work;
    c.cost_work_len = cost_bytes;
    cost_bytes = (cost_bytes + sizeof(pdt_real_t) - 1u) / sizeof(pdt_real_t) * sizeof(pdt_real_t);
    /* work is aligned for pdt_real_t and cost_bytes a whole number of
     * reals, so the rest of the workspace is addressed in reals. */
    pdt_real_t *p = (pdt_real_t *)work + cost_bytes / sizeof(pdt_real_t);
    size_t P = c.cfg.population, G = c.genes;
    c.pop = p;
    p += P * G;
    c.pop_cost = p;
    p += P;
    c.pop_gain = p;
    p += P;
    c.pop_offset = p;
    p += P;
    c.off = p;
    p += P * G;
    c.off_cost = p;
    p += P;
    c.off_gain = p;
    p += P;
    c.off_offset = p;
    p += P;
    c.shared = p;
    p += P;
    c.scratch = p;

    for (size_t j = 0; j < G; j++) {
        c.lo[j] = glo[j];
        c.hi[j] = ghi[j];
    }
    c.td_offset = td_offset(cfg, &b);

    c.searches = searches_of(cfg);
    c.search_budget = cfg->max_evaluations / c.searches;
    search_start(&c);
    c.magic = IDENT_MAGIC;
    *ctx = c;
    return PDT_OK;
}

/* Dead time of a dead-time gene, and back. */
static pdt_real_t td_of_gene(const pdt_ident_t *c, pdt_real_t g)
{
    pdt_real_t Td = pdt_exp(g) - c->td_offset;
    return Td > PDT_R(0.0) ? Td : PDT_R(0.0);
}

static pdt_real_t gene_of_td(const pdt_ident_t *c, pdt_real_t Td)
{
    pdt_real_t g = pdt_log(Td + c->td_offset);
    const uint32_t j = c->genes - 1u;
    return g < c->lo[j] ? c->lo[j] : (g > c->hi[j] ? c->hi[j] : g);
}

/* The unit-gain model of a gene vector. */
static void shape_of(const pdt_ident_t *c, const pdt_real_t *g, pdt_model_t *m)
{
    pdt_real_t Td = td_of_gene(c, g[c->genes - 1u]);
    if (c->cfg.delay_mode == PDT_DELAY_INTEGER) {
        Td = pdt_floor(Td / c->cfg.Ts + PDT_R(0.5)) * c->cfg.Ts;
    }
    if (c->cfg.model == PDT_MODEL_FOPDT) {
        m->kind = PDT_MODEL_FOPDT;
        m->p.fopdt.K = PDT_R(1.0);
        m->p.fopdt.tau = pdt_exp(g[0]);
        m->p.fopdt.Td = Td;
    } else {
        pdt_real_t a = pdt_exp(-g[0]);
        pdt_real_t h = PDT_R(0.5) * a * g[1] * g[1] / c->cfg.zeta_min;
        m->kind = PDT_MODEL_SOPDT;
        m->p.sopdt.k = PDT_R(1.0);
        m->p.sopdt.a = a;
        m->p.sopdt.b = h * h;
        m->p.sopdt.Td = Td;
    }
}

/* Bounds on the multiplier of the shape's gain from the caller's K bounds. */
static void gain_bounds(const pdt_ident_t *c, const pdt_model_t *shape, pdt_real_t *lo,
                        pdt_real_t *hi)
{
    pdt_real_t scale = PDT_R(1.0);
    if (c->cfg.K_min == PDT_R(0.0) && c->cfg.K_max == PDT_R(0.0)) {
        *lo = PDT_R(0.0);
        *hi = PDT_R(0.0);
        return;
    }
    if (shape->kind == PDT_MODEL_SOPDT) {
        scale = shape->p.sopdt.b > PDT_R(0.0) ? shape->p.sopdt.b : shape->p.sopdt.a;
    }
    *lo = c->cfg.K_min * scale;
    *hi = c->cfg.K_max * scale;
}

static void evaluate(pdt_ident_t *c, const pdt_real_t *g, pdt_real_t *cost, pdt_real_t *gain,
                     pdt_real_t *offset)
{
    pdt_model_t shape;
    pdt_cost_profile_t pr;
    pdt_real_t glo, ghi;
    shape_of(c, g, &shape);
    gain_bounds(c, &shape, &glo, &ghi);
    c->evaluations++;
    /* The best so far is the reference fit of the cost's one pass, its gain
     * carried over to this shape's unit: b + a / T (T the record's length)
     * moves smoothly from a lag's DC gain to an integrator's. */
    pdt_cost_hint_t hint = {c->best_gain, c->best_offset, c->best_cost};
    if (shape.kind == PDT_MODEL_SOPDT && c->best_cost < PDT_REAL_MAX) {
        pdt_model_t best;
        const pdt_real_t T = c->cfg.Ts * (pdt_real_t)c->data.n;
        shape_of(c, c->best, &best);
        hint.gain = c->best_gain * (shape.p.sopdt.b + shape.p.sopdt.a / T) /
                    (best.p.sopdt.b + best.p.sopdt.a / T);
    }
    if (pdt_cost_profile_hint(&c->cost, &shape, glo, ghi, &hint, c->scratch, &pr) != PDT_OK ||
        !(pr.ncost == pr.ncost)) {
        *cost = PDT_REAL_MAX;
        *gain = PDT_R(0.0);
        *offset = PDT_R(0.0);
        return;
    }
    *cost = pr.ncost;
    *gain = pr.gain;
    *offset = pr.offset;
    if (pr.ncost < c->best_cost) {
        c->best_cost = pr.ncost;
        c->best_gain = pr.gain;
        c->best_offset = pr.offset;
        for (uint32_t j = 0; j < c->genes; j++) {
            c->best[j] = g[j];
        }
    }
}

static pdt_rng_t rng_load(const pdt_ident_t *c)
{
    pdt_rng_t r;
    r.state = c->rng_state;
    r.inc = c->rng_inc;
    return r;
}

static void rng_store(pdt_ident_t *c, const pdt_rng_t *r)
{
    c->rng_state = r->state;
    c->rng_inc = r->inc;
}

static size_t pick(const pdt_ident_t *c, pdt_rng_t *r)
{
    uint32_t P = c->cfg.population;
    size_t a = pdt_rng_below(r, P);
    size_t b = pdt_rng_below(r, P);
    return pdt_ga_tournament(c->shared, a, b, pdt_rng_u32(r) & 1u);
}

/* One generation of offspring from the current population. */
static void breed(pdt_ident_t *c)
{
    const size_t P = c->cfg.population, G = c->genes;
    pdt_rng_t r = rng_load(c);
    pdt_real_t pm = c->cfg.p_mutation > PDT_R(0.0) ? c->cfg.p_mutation : PDT_R(1.0) / (pdt_real_t)G;
    pdt_ga_share(c->pop, P, G, c->lo, c->hi, c->pop_cost, c->cfg.sigma_share, PDT_R(1.0),
                 c->shared);
    for (size_t i = 0; i < P; i += 2u) {
        const pdt_real_t *p1 = &c->pop[pick(c, &r) * G];
        const pdt_real_t *p2 = &c->pop[pick(c, &r) * G];
        pdt_real_t *c1 = &c->off[i * G];
        pdt_real_t *c2 = &c->off[(i + 1u) * G];
        bool cross = pdt_rng_uniform(&r) < c->cfg.p_crossover;
        for (size_t j = 0; j < G; j++) {
            pdt_real_t x1 = p1[j], x2 = p2[j];
            if (cross && pdt_rng_uniform(&r) < PDT_R(0.5)) {
                pdt_ga_sbx(p1[j], p2[j], c->lo[j], c->hi[j], c->cfg.eta_c, pdt_rng_uniform(&r), &x1,
                           &x2);
                if ((pdt_rng_u32(&r) & 1u) != 0u) {
                    pdt_real_t t = x1;
                    x1 = x2;
                    x2 = t;
                }
            }
            if (pdt_rng_uniform(&r) < pm) {
                x1 = pdt_ga_mutate(x1, c->lo[j], c->hi[j], c->cfg.eta_m, pdt_rng_uniform(&r));
            }
            if (pdt_rng_uniform(&r) < pm) {
                x2 = pdt_ga_mutate(x2, c->lo[j], c->hi[j], c->cfg.eta_m, pdt_rng_uniform(&r));
            }
            c1[j] = x1;
            c2[j] = x2;
        }
    }
    rng_store(c, &r);
}

static void copy_individual(pdt_ident_t *c, pdt_real_t *dst_genes, size_t di, const pdt_real_t *src,
                            size_t si, pdt_real_t cost, pdt_real_t gain, pdt_real_t offset)
{
    (void)si;
    for (uint32_t j = 0; j < c->genes; j++) {
        dst_genes[di * c->genes + j] = src[j];
    }
    c->off_cost[di] = cost;
    c->off_gain[di] = gain;
    c->off_offset[di] = offset;
}

/* Elitism: the best `elite` parents replace the worst offspring when better,
 * then the offspring become the population. */
static void survive(pdt_ident_t *c)
{
    const size_t P = c->cfg.population, G = c->genes;
    for (uint32_t e = 0; e < c->cfg.elite; e++) {
        size_t best = 0u, worst = 0u;
        for (size_t i = 1; i < P; i++) {
            if (c->pop_cost[i] < c->pop_cost[best]) {
                best = i;
            }
            if (c->off_cost[i] > c->off_cost[worst]) {
                worst = i;
            }
        }
        if (!(c->pop_cost[best] < c->off_cost[worst])) {
            break;
        }
        copy_individual(c, c->off, worst, &c->pop[best * G], best, c->pop_cost[best],
                        c->pop_gain[best], c->pop_offset[best]);
        /* Take the parent out of the next round of this loop. */
        c->pop_cost[best] = PDT_REAL_MAX;
    }
    for (size_t i = 0; i < P * G; i++) {
        c->pop[i] = c->off[i];
    }
    for (size_t i = 0; i < P; i++) {
        c->pop_cost[i] = c->off_cost[i];
        c->pop_gain[i] = c->off_gain[i];
        c->pop_offset[i] = c->off_offset[i];
    }
}

/* After a generation: stall bookkeeping and whether the GA goes on. */
static bool ga_continues(pdt_ident_t *c)
{
    c->generations++;
    if (c->best_cost < c->best_history * (PDT_R(1.0) - c->cfg.tolerance) ||
        c->best_history == PDT_REAL_MAX) {
        c->best_history = c->best_cost;
        c->stall = 0u;
    } else {
        c->stall++;
    }
    uint32_t ga_budget = c->search_budget - c->cfg.refine_evaluations - late_reserve(&c->cfg);
    if (c->stage == 1u) {
        /* The time-cost stage of the CONTROL weighting gets half. */
        ga_budget /= 2u;
    }
    return c->stall < c->cfg.stall_generations &&
           (c->evaluations - c->search_base) + c->cfg.population <= ga_budget;
}

/* Where the search goes when the GA stops. */
static uint32_t ga_done(const pdt_ident_t *c)
{
    return c->stage == 1u ? PH_BAND : PH_REFINE_PREP;
}

/* ---- Nelder-Mead, by reverse communication: propose a point, take its cost. */

static pdt_real_t clampg(const pdt_ident_t *c, size_t j, pdt_real_t x)
{
    return x < c->lo[j] ? c->lo[j] : (x > c->hi[j] ? c->hi[j] : x);
}

/* Normalised distance between two gene vectors. */
static pdt_real_t gene_distance(const pdt_ident_t *c, const pdt_real_t *x, const pdt_real_t *y)
{
    pdt_real_t d2 = PDT_R(0.0);
    for (uint32_t j = 0; j < c->genes; j++) {
        pdt_real_t d = (x[j] - y[j]) / (c->hi[j] - c->lo[j]);
        d2 += d * d;
    }
    return pdt_sqrt(d2);
}

/* Starting points of the refinement: the best individual, then the best of
 * each other niche (farther than twice the sharing radius from every start
 * so far), up to NM_STARTS. A GA that ends with its best in a wrong basin
 * (e.g. a SOPDT whose second lag has collapsed into the dead time) usually
 * still holds the right basin in another niche: sharing kept it alive. */
static void refine_starts(pdt_ident_t *c)
{
    const uint32_t P = c->cfg.population, G = c->genes;
    const pdt_real_t radius = PDT_R(2.0) * c->cfg.sigma_share;
    for (uint32_t j = 0; j < G; j++) {
        c->starts[0][j] = c->best[j];
    }
    c->nstarts = 1u;
    while (c->nstarts < NM_STARTS) {
        size_t chosen = P;
        for (size_t i = 0; i < P; i++) {
            bool distinct = c->pop_cost[i] < PDT_REAL_MAX;
            for (uint32_t s = 0; s < c->nstarts && distinct; s++) {
                distinct = gene_distance(c, &c->pop[i * G], c->starts[s]) > radius;
            }
            if (distinct && (chosen == P || c->pop_cost[i] < c->pop_cost[chosen])) {
                chosen = i;
            }
        }
        if (chosen == P) {
            break;
        }
        for (uint32_t j = 0; j < G; j++) {
            c->starts[c->nstarts][j] = c->pop[chosen * G + j];
        }
        c->nstarts++;
    }
    c->start_i = 0u;
}

/* A Nelder-Mead run from starts[start_i]. The niche runs share half of
 * what the refinement has; a last run then polishes the best point found
 * with all that is left (start_i == nstarts): a restarted simplex also
 * escapes the premature collapse Nelder-Mead is prone to. */
static void nm_start(pdt_ident_t *c)
{
    const size_t G = c->genes;
    const pdt_real_t *x0 = c->start_i < c->nstarts ? c->starts[c->start_i] : c->best;
    for (size_t i = 0; i <= G; i++) {
        for (size_t j = 0; j < G; j++) {
            c->nm_x[i][j] = x0[j];
        }
        if (i > 0u) {
            size_t j = i - 1u;
            pdt_real_t step = NM_STEP * (c->hi[j] - c->lo[j]);
            pdt_real_t x = x0[j] + step;
            if (x > c->hi[j]) {
                x = x0[j] - step;
            }
            c->nm_x[i][j] = clampg(c, j, x);
        }
    }
    c->nm_state = NM_VERTEX;
    c->nm_index = 0u;
    uint32_t left = c->search_budget - late_reserve(&c->cfg);
    left = left > c->evaluations - c->search_base ? left - (c->evaluations - c->search_base) : 0u;
    if (c->start_i == 0u) {
        /* Fewer starts when half the budget cannot give each a whole
         * simplex; the first always fits (refine_evaluations >= genes + 1). */
        uint32_t per = (left / 2u) / (uint32_t)(G + 1u);
        if (c->nstarts > per) {
            c->nstarts = per > 0u ? per : 1u;
        }
        c->refine_half = left / 2u;
    }
    if (c->start_i < c->nstarts) {
        uint32_t share = c->refine_half / c->nstarts;
        c->nm_budget = share > G + 1u ? share : (uint32_t)(G + 1u);
        c->nm_budget = c->nm_budget < left ? c->nm_budget : left;
    } else {
        c->nm_budget = left;
    }
}

static void nm_order(pdt_ident_t *c)
{
    const size_t G = c->genes;
    /* Insertion sort of G + 1 <= 4 vertices by cost. */
    for (size_t i = 1; i <= G; i++) {
        for (size_t k = i; k > 0u && c->nm_f[k] < c->nm_f[k - 1u]; k--) {
            pdt_real_t tf = c->nm_f[k];
            c->nm_f[k] = c->nm_f[k - 1u];
            c->nm_f[k - 1u] = tf;
            for (size_t j = 0; j < G; j++) {
                pdt_real_t t = c->nm_x[k][j];
                c->nm_x[k][j] = c->nm_x[k - 1u][j];
                c->nm_x[k - 1u][j] = t;
            }
        }
    }
}

/* Point = centroid of the best G vertices + coef (centroid - worst). */
static void nm_point(pdt_ident_t *c, pdt_real_t coef, pdt_real_t *out)
{
    const size_t G = c->genes;
    for (size_t j = 0; j < G; j++) {
        pdt_real_t cen = PDT_R(0.0);
        for (size_t i = 0; i < G; i++) {
            cen += c->nm_x[i][j];
        }
        cen /= (pdt_real_t)G;
        out[j] = clampg(c, j, cen + coef * (cen - c->nm_x[G][j]));
    }
}

static bool nm_converged(const pdt_ident_t *c)
{
    const size_t G = c->genes;
    pdt_real_t size = PDT_R(0.0);
    for (size_t i = 1; i <= G; i++) {
        for (size_t j = 0; j < G; j++) {
            pdt_real_t d = pdt_fabs(c->nm_x[i][j] - c->nm_x[0][j]) / (c->hi[j] - c->lo[j]);
            size = d > size ? d : size;
        }
    }
    return size < NM_XTOL;
}

static void nm_replace_worst(pdt_ident_t *c, const pdt_real_t *x, pdt_real_t f)
{
    for (uint32_t j = 0; j < c->genes; j++) {
        c->nm_x[c->genes][j] = x[j];
    }
    c->nm_f[c->genes] = f;
}

/* Sets up the next trial after the simplex changed; NM_END when done. */
static void nm_next_iteration(pdt_ident_t *c)
{
    nm_order(c);
    if (c->nm_budget == 0u || nm_converged(c)) {
        c->nm_state = NM_END;
        return;
    }
    nm_point(c, PDT_R(1.0), c->nm_trial);
    c->nm_state = NM_REFLECT;
}

/* One Nelder-Mead evaluation. */
static void nm_advance(pdt_ident_t *c)
{
    const uint32_t G = c->genes;
    pdt_real_t f, gain, offset;
    switch (c->nm_state) {
    case NM_VERTEX:
    case NM_SHRINK:
        evaluate(c, c->nm_x[c->nm_index], &f, &gain, &offset);
        c->nm_f[c->nm_index] = f;
        c->nm_index++;
        if (c->nm_index > G) {
            nm_next_iteration(c);
        }
        break;
    case NM_REFLECT:
        evaluate(c, c->nm_trial, &f, &gain, &offset);
        c->nm_ftrial = f;
        if (f < c->nm_f[0]) {
            nm_point(c, PDT_R(2.0), c->nm_trial2);
            c->nm_state = NM_EXPAND;
        } else if (f < c->nm_f[G - 1u]) {
            nm_replace_worst(c, c->nm_trial, f);
            nm_next_iteration(c);
        } else {
            /* Contract outside when the reflection beat the worst, inside
             * otherwise. */
            nm_point(c, f < c->nm_f[G] ? PDT_R(0.5) : PDT_R(-0.5), c->nm_trial2);
            c->nm_state = NM_CONTRACT;
        }
        break;
    case NM_EXPAND:
        evaluate(c, c->nm_trial2, &f, &gain, &offset);
        if (f < c->nm_ftrial) {
            nm_replace_worst(c, c->nm_trial2, f);
        } else {
            nm_replace_worst(c, c->nm_trial, c->nm_ftrial);
        }
        nm_next_iteration(c);
        break;
    case NM_CONTRACT:
        evaluate(c, c->nm_trial2, &f, &gain, &offset);
        if (f < c->nm_ftrial && f < c->nm_f[G]) {
            nm_replace_worst(c, c->nm_trial2, f);
            nm_next_iteration(c);
        } else {
            for (uint32_t i = 1; i <= G; i++) {
                for (uint32_t j = 0; j < G; j++) {
                    c->nm_x[i][j] = c->nm_x[0][j] + PDT_R(0.5) * (c->nm_x[i][j] - c->nm_x[0][j]);
                }
            }
            c->nm_state = NM_SHRINK;
            c->nm_index = 1u;
        }
        break;
    default:
        c->nm_state = NM_END;
        break;
    }
    if (c->nm_budget > 0u) {
        c->nm_budget--;
    }
    if (c->nm_budget == 0u && c->nm_state != NM_END &&
        (c->nm_state != NM_VERTEX || c->nm_index > G)) {
        c->nm_state = NM_END;
    }
}

static void finish(pdt_ident_t *c);

/* CONTROL weighting, between the stages: the band up to half the phase
 * crossover of the time model (the whole spectrum if it has none below
 * the Nyquist frequency, at least one bin), Cf scaled by the bins' share,
 * and the population evaluated again on the criterion. The crossover
 * bounds the bandwidth any controller can reach; half of it covers the
 * closed-loop band of the usual tuning rules. */
static void band_start(pdt_ident_t *c)
{
    pdt_model_t m;
    shape_of(c, c->best, &m);
    const pdt_real_t Ts = c->cfg.Ts;
    const size_t nf = c->cost.nf, nb = nf / 2u;
    pdt_real_t f = PDT_R(0.5) * pdt_model_phase_crossover(&m) / (PDT_R(2.0) * PDT_PI);
    pdt_real_t f_nyq = PDT_R(0.5) / Ts, f_bin = PDT_R(1.0) / ((pdt_real_t)nf * Ts);
    if (!(f > PDT_R(0.0)) || f > f_nyq) {
        f = f_nyq;
    }
    f = f < f_bin ? f_bin : f;
    size_t bins = (size_t)(f / f_bin);
    bins = bins < 1u ? 1u : (bins > nb ? nb : bins);
    pdt_cost_config_t cc = c->cost.cfg;
    pdt_cost_t nc;
    cc.kind = c->cfg.cost;
    cc.y0 += c->best_offset;
    cc.weight = PDT_WEIGHT_BAND;
    cc.f_lo = PDT_R(0.0);
    cc.f_hi = f;
    cc.phi_f = c->cfg.phi_f * (pdt_real_t)nb / (pdt_real_t)bins;
    /* The same record, sizes and workspace as init, which checked them:
     * this cannot fail; if it did, the search would go on with the time
     * cost and f_band stay 0. */
    if (pdt_cost_init(&nc, &cc, c->data.u, c->data.y, c->data.n, c->cost_work, c->cost_work_len) ==
        PDT_OK) {
        c->cost = nc;
        c->f_band = f;
    }
    c->stage = 2u;
    c->best_cost = PDT_REAL_MAX;
    c->best_history = PDT_REAL_MAX;
    c->stall = 0u;
    c->next = 0u;
    c->phase = PH_INIT_POP;
}

/* ---- Dead time of the frequency criterion, from the time cost. */

/* Time cost of the best shape with dead time Td and a fixed gain. */
static pdt_real_t scan_cost(pdt_ident_t *c, pdt_real_t Td, pdt_real_t gain, pdt_real_t *offset)
{
    pdt_real_t g[3];
    pdt_model_t shape;
    pdt_cost_profile_t pr;
    for (uint32_t j = 0; j < c->genes; j++) {
        g[j] = c->best[j];
    }
    g[c->genes - 1u] = gene_of_td(c, Td);
    shape_of(c, g, &shape);
    c->evaluations++;
    if (pdt_cost_profile(&c->cost_time, &shape, gain, gain, c->scratch, &pr) != PDT_OK ||
        !(pr.ncost == pr.ncost)) {
        *offset = PDT_R(0.0);
        return PDT_REAL_MAX;
    }
    *offset = pr.offset;
    return pr.ncost;
}

static void scan_start(pdt_ident_t *c)
{
    pdt_real_t lo = td_of_gene(c, c->lo[c->genes - 1u]), hi = td_of_gene(c, c->hi[c->genes - 1u]);
    c->cost_time = c->cost;
    c->cost_time.cfg.kind = c->cfg.time_kind;
    c->scan_i = 0u;
    c->scan_step = (hi - lo) / (pdt_real_t)(SCAN_POINTS - 1u);
    c->scan_best = PDT_REAL_MAX;
    c->scan_td = td_of_gene(c, c->best[c->genes - 1u]);
    c->scan_gain = c->best_gain;
    c->scan_offset = PDT_R(0.0);
    c->phase = PH_DELAY_SCAN;
}

static void scan_consider(pdt_ident_t *c, pdt_real_t Td, pdt_real_t gain, pdt_real_t f,
                          pdt_real_t offset)
{
    if (f < c->scan_best) {
        c->scan_best = f;
        c->scan_td = Td;
        c->scan_gain = gain;
        c->scan_offset = offset;
    }
}

static void scan_advance(pdt_ident_t *c)
{
    const size_t dt = c->genes - 1u;
    const pdt_real_t td_lo = td_of_gene(c, c->lo[dt]), td_hi = td_of_gene(c, c->hi[dt]);
    pdt_real_t off;
    if (c->phase == PH_DELAY_SCAN) {
        /* Point i / 2 of the grid, gain sign by the parity of i. */
        pdt_real_t Td = td_lo + c->scan_step * (pdt_real_t)(c->scan_i / 2u);
        pdt_real_t gain = (c->scan_i % 2u) == 0u ? pdt_fabs(c->best_gain) : -pdt_fabs(c->best_gain);
        Td = Td > td_hi ? td_hi : Td;
        pdt_real_t f = scan_cost(c, Td, gain, &off);
        scan_consider(c, Td, gain, f, off);
        if (++c->scan_i == 2u * SCAN_POINTS) {
            pdt_real_t a = c->scan_td - c->scan_step, b = c->scan_td + c->scan_step;
            c->gs_a = a < td_lo ? td_lo : a;
            c->gs_b = b > td_hi ? td_hi : b;
            c->gs_x1 = c->gs_b - GOLDEN * (c->gs_b - c->gs_a);
            c->gs_x2 = c->gs_a + GOLDEN * (c->gs_b - c->gs_a);
            c->scan_i = 0u;
            c->phase = PH_DELAY_REFINE;
        }
        return;
    }
    /* Golden section: the first two calls evaluate x1 and x2, each later
     * call the one new interior point. */
    if (c->scan_i == 0u) {
        c->gs_f1 = scan_cost(c, c->gs_x1, c->scan_gain, &off);
        scan_consider(c, c->gs_x1, c->scan_gain, c->gs_f1, off);
    } else if (c->scan_i == 1u) {
        c->gs_f2 = scan_cost(c, c->gs_x2, c->scan_gain, &off);
        scan_consider(c, c->gs_x2, c->scan_gain, c->gs_f2, off);
    } else if (c->gs_f1 < c->gs_f2) {
        c->gs_b = c->gs_x2;
        c->gs_x2 = c->gs_x1;
        c->gs_f2 = c->gs_f1;
        c->gs_x1 = c->gs_b - GOLDEN * (c->gs_b - c->gs_a);
        c->gs_f1 = scan_cost(c, c->gs_x1, c->scan_gain, &off);
        scan_consider(c, c->gs_x1, c->scan_gain, c->gs_f1, off);
    } else {
        c->gs_a = c->gs_x1;
        c->gs_x1 = c->gs_x2;
        c->gs_f1 = c->gs_f2;
        c->gs_x2 = c->gs_a + GOLDEN * (c->gs_b - c->gs_a);
        c->gs_f2 = scan_cost(c, c->gs_x2, c->scan_gain, &off);
        scan_consider(c, c->gs_x2, c->scan_gain, c->gs_f2, off);
    }
    if (++c->scan_i == GOLDEN_STEPS + 2u) {
        c->best[dt] = gene_of_td(c, c->scan_td);
        c->best_gain = c->scan_gain;
        c->best_offset = c->scan_offset;
        c->phase = PH_FINISH;
    }
}

/* The final model in engineering units, its operating point and its fit. */
/* ---- Independent searches: they must agree. */

/* Costs closer than this (relative) are one basin; a different structure
 * this close is an ambiguity. */
#define AGREE_RTOL     PDT_R(0.01)
#define AMBIGUOUS_RTOL PDT_R(0.05)
/* Answers this close in normalised genes are one basin whatever their
 * costs (an exact fit's cost is all rounding, its ratios meaningless). */
#define AGREE_GENES    PDT_R(0.01)
/* A gene this close to its bound (normalised) lies on it. */
#define BOUND_TOL      PDT_R(1e-3)

static pdt_real_t model_gain(const pdt_model_t *m)
{
    return m->kind == PDT_MODEL_FOPDT ? m->p.fopdt.K : m->p.sopdt.k;
}

/* The same structure: the gain's sign and, for a SOPDT, whether it
 * integrates. */
static bool same_structure(const pdt_model_t *a, const pdt_model_t *b)
{
    if ((model_gain(a) < PDT_R(0.0)) != (model_gain(b) < PDT_R(0.0))) {
        return false;
    }
    return a->kind != PDT_MODEL_SOPDT ||
           ((a->p.sopdt.b > PDT_R(0.0)) == (b->p.sopdt.b > PDT_R(0.0)));
}

/* Cost b within rtol of cost a (normalised costs: the record lies in
 * (-1, 1), so a few ulps of 1 are the floor of an exact fit). */
static bool cost_close(pdt_real_t a, pdt_real_t b, pdt_real_t rtol)
{
    pdt_real_t lo = a < b ? a : b;
    pdt_real_t d = a < b ? b - a : a - b;
    return d <= rtol * lo + PDT_R(64.0) * PDT_REAL_EPS * PDT_REAL_EPS;
}

/* Searches i and j ended in one basin: the same structure, and costs
 * within 1 % or genes within AGREE_GENES. */
static bool same_basin(const pdt_ident_t *c, uint32_t i, uint32_t j)
{
    return same_structure(&c->found[i], &c->found[j]) &&
           (cost_close(c->found_cost[i], c->found_cost[j], AGREE_RTOL) ||
            gene_distance(c, c->found_genes[i], c->found_genes[j]) < AGREE_GENES);
}

static bool on_bound(const pdt_ident_t *c, const pdt_real_t *g)
{
    for (uint32_t j = 0; j < c->genes; j++) {
        const pdt_real_t t = (g[j] - c->lo[j]) / (c->hi[j] - c->lo[j]);
        /* Only the upper bounds: a time constant below a quarter sample
         * (a lag too short to matter, or a SOPDT's second lag vanishing),
         * no dead time and 1/zeta = 0 (an integrator) are answers. */
        if (t > PDT_R(1.0) - BOUND_TOL) {
            return true;
        }
    }
    return false;
}

static bool gain_on_bound(const pdt_ident_t *c, pdt_real_t K)
{
    const pdt_real_t lo = c->cfg.K_min, hi = c->cfg.K_max;
    if (!(hi > lo)) {
        return false;
    }
    const pdt_real_t tol = BOUND_TOL * (hi - lo);
    return K <= lo + tol || K >= hi - tol;
}

/* The answer of all searches: the least cost; confirmed by another search
 * in its basin, flagged otherwise, the runner-up basin's cost ratio. */
static void searches_conclude(pdt_ident_t *c)
{
    uint32_t best = 0u;
    for (uint32_t i = 1u; i < c->search; i++) {
        if (c->found_cost[i] < c->found_cost[best]) {
            best = i;
        }
    }
    const pdt_real_t cb = c->found_cost[best];
    bool confirmed = c->search < 2u;
    uint32_t flags = 0u;
    pdt_real_t runner = PDT_R(0.0);
    for (uint32_t i = 0u; i < c->search; i++) {
        if (i == best) {
            continue;
        }
        const bool same = same_structure(&c->found[i], &c->found[best]);
        if (same_basin(c, i, best)) {
            confirmed = true;
            continue;
        }
        if (!same && cost_close(cb, c->found_cost[i], AMBIGUOUS_RTOL)) {
            flags |= PDT_IDENT_FLAG_AMBIGUOUS;
        }
        const pdt_real_t ratio = cb > PDT_R(0.0) ? c->found_cost[i] / cb : PDT_REAL_MAX;
        if (runner == PDT_R(0.0) || ratio < runner) {
            runner = ratio;
        }
    }
    if (!confirmed) {
        flags |= PDT_IDENT_FLAG_UNCONFIRMED;
    }
    if (on_bound(c, c->found_genes[best]) || gain_on_bound(c, model_gain(&c->found[best]))) {
        flags |= PDT_IDENT_FLAG_AT_BOUND;
    }
    c->model = c->found[best];
    c->y0 = c->found_y0[best];
    c->fit = c->found_fit[best];
    c->best_cost = cb;
    c->flags = flags;
    c->runner_up = runner;
    c->phase = PH_DONE;
}

/* A search ended: keep what it found, then another search or the answer.
 * The second always runs; the third only when the first two disagree. */
static void search_end(pdt_ident_t *c)
{
    const uint32_t k = c->search;
    c->found[k] = c->model;
    c->found_cost[k] = c->best_cost;
    c->found_y0[k] = c->y0;
    c->found_fit[k] = c->fit;
    for (uint32_t j = 0; j < c->genes; j++) {
        c->found_genes[k][j] = c->best[j];
    }
    c->search = k + 1u;
    bool agreed = false;
    for (uint32_t i = 0u; i < k; i++) {
        agreed = agreed || same_basin(c, i, k);
    }
    if (c->search < c->searches && (c->search < 2u || !agreed)) {
        search_start(c);
        return;
    }
    searches_conclude(c);
}

static void finish(pdt_ident_t *c)
{
    pdt_model_t m;
    shape_of(c, c->best, &m);
    if (m.kind == PDT_MODEL_FOPDT) {
        m.p.fopdt.K = c->best_gain;
    } else {
        m.p.sopdt.k = c->best_gain;
    }
    if (m.kind == PDT_MODEL_SOPDT && c->cfg.integrating && m.p.sopdt.b > PDT_R(0.0)) {
        /* A lag a hundred records long cannot be told from an integrator in
         * this record: report the integrator (b = 0) rather than a DC gain
         * the data do not determine. Its cost is scored again. */
        pdt_real_t a = m.p.sopdt.a, b = m.p.sopdt.b, disc = a * a - PDT_R(4.0) * b;
        pdt_real_t T = c->cfg.Ts * (pdt_real_t)c->data.n;
        if (disc >= PDT_R(0.0) && PDT_R(2.0) * b * PDT_R(100.0) * T < a + pdt_sqrt(disc)) {
            pdt_cost_profile_t pr;
            pdt_model_t shape = m;
            pdt_real_t glo, ghi;
            shape.p.sopdt.b = PDT_R(0.0);
            shape.p.sopdt.k = PDT_R(1.0);
            gain_bounds(c, &shape, &glo, &ghi);
            c->evaluations++;
            /* Gain and offset solved again for the integrator (the
             * frequency criterion keeps its gain: its sign came from the
             * dead-time scan). */
            if (c->cfg.cost == PDT_COST_FREQUENCY) {
                glo = c->best_gain;
                ghi = c->best_gain;
            }
            if (pdt_cost_profile(&c->cost, &shape, glo, ghi, c->scratch, &pr) == PDT_OK) {
                m.p.sopdt.b = PDT_R(0.0);
                m.p.sopdt.k = pr.gain;
                c->best_gain = pr.gain;
                c->best_cost = pr.ncost;
                c->best_offset = (c->cfg.cost == PDT_COST_FREQUENCY) ? c->best_offset : pr.offset;
            }
        }
    }
    c->model = m;
    c->y0 = c->cost.cfg.y0 + c->best_offset;
    if (pdt_cost_fit(&c->cost, &m, c->best_offset, c->scratch, &c->fit) != PDT_OK) {
        c->fit = PDT_R(0.0);
    }
    search_end(c);
}

pdt_status_t pdt_ident_step(pdt_ident_t *ctx, uint32_t max_evaluations)
{
    if (ctx == NULL || max_evaluations == 0u) {
        return PDT_ERR_ARG;
    }
    if (ctx->magic != IDENT_MAGIC) {
        return PDT_ERR_STATE;
    }
    pdt_ident_t *c = ctx;
    const uint32_t P = c->cfg.population;
    uint32_t budget = max_evaluations;
    bool bred = false;
    while (c->phase != PH_DONE) {
        switch (c->phase) {
        case PH_INIT_POP:
            if (budget == 0u) {
                return PDT_RUNNING;
            }
            evaluate(c, &c->pop[c->next * c->genes], &c->pop_cost[c->next], &c->pop_gain[c->next],
                     &c->pop_offset[c->next]);
            budget--;
            if (++c->next == P) {
                c->phase = ga_continues(c) ? PH_BREED : ga_done(c);
            }
            break;
        case PH_BREED:
            /* At most one breeding per call keeps the call's work bounded. */
            if (bred || budget == 0u) {
                return PDT_RUNNING;
            }
            breed(c);
            bred = true;
            c->next = 0u;
            c->phase = PH_EVAL_OFF;
            break;
        case PH_EVAL_OFF:
            if (budget == 0u) {
                return PDT_RUNNING;
            }
            evaluate(c, &c->off[c->next * c->genes], &c->off_cost[c->next], &c->off_gain[c->next],
                     &c->off_offset[c->next]);
            budget--;
            if (++c->next == P) {
                survive(c);
                c->phase = ga_continues(c) ? PH_BREED : ga_done(c);
            }
            break;
        case PH_BAND:
            /* A cost preparation, as much work as init: a call of its own. */
            if (bred) {
                return PDT_RUNNING;
            }
            band_start(c);
            bred = true;
            break;
        case PH_REFINE_PREP:
            if (c->cost.cfg.kind == PDT_COST_COMBINED) {
                /* Re-centre the spectra on the output level the model
                 * estimated: one more preparation of the cost, in its own
                 * workspace. It is as much work as init, so it gets a call
                 * of its own. */
                if (bred) {
                    return PDT_RUNNING;
                }
                pdt_cost_config_t cc = c->cost.cfg;
                pdt_cost_t nc;
                cc.y0 += c->best_offset;
                if (pdt_cost_init(&nc, &cc, c->data.u, c->data.y, c->data.n, c->cost_work,
                                  c->cost_work_len) == PDT_OK) {
                    c->cost = nc;
                }
                bred = true;
            }
            /* The cost scale may have changed (re-centred spectra): the
             * best is tracked afresh; the first start re-evaluates the GA's
             * best, so nothing is lost. */
            c->best_cost = PDT_REAL_MAX;
            refine_starts(c);
            nm_start(c);
            c->phase = PH_REFINE;
            break;
        case PH_REFINE:
            if (c->nm_state == NM_END && c->start_i < c->nstarts) {
                /* Next niche, then the polish of the best (start_i ==
                 * nstarts), if a whole simplex still fits. */
                uint32_t left = c->search_budget - late_reserve(&c->cfg);
                left = left > c->evaluations - c->search_base
                           ? left - (c->evaluations - c->search_base)
                           : 0u;
                c->start_i++;
                if (left >= c->genes + 1u) {
                    nm_start(c);
                    break;
                }
            }
            if (c->nm_state == NM_END) {
                if (c->cfg.cost == PDT_COST_FREQUENCY) {
                    scan_start(c);
                } else {
                    c->phase = PH_FINISH;
                }
                break;
            }
            if (budget == 0u) {
                return PDT_RUNNING;
            }
            nm_advance(c);
            budget--;
            break;
        case PH_FINISH:
            if (budget == 0u) {
                return PDT_RUNNING;
            }
            finish(c);
            budget--;
            break;
        case PH_DELAY_SCAN:
        case PH_DELAY_REFINE:
            if (budget == 0u) {
                return PDT_RUNNING;
            }
            scan_advance(c);
            budget--;
            break;
        default:
            return PDT_ERR_STATE;
        }
    }
    return PDT_OK;
}

pdt_status_t pdt_ident_result(const pdt_ident_t *ctx, pdt_ident_result_t *out)
{
    if (ctx == NULL || out == NULL) {
        return PDT_ERR_ARG;
    }
    if (ctx->magic != IDENT_MAGIC || ctx->phase != PH_DONE) {
        return PDT_ERR_STATE;
    }
    /* The search runs on the normalised record; mapped back, a gain can
     * lie beyond the real type (a tiny input driving a huge output). */
    if (pdt_model_check(&ctx->model) != PDT_OK) {
        return PDT_ERR_NONFINITE;
    }
    pdt_ident_result_t r;
    r.model = ctx->model;
    r.u0 = ctx->cost.cfg.u0;
    r.y0 = ctx->y0;
    r.cost = pdt_cost_units(&ctx->cost, ctx->best_cost);
    r.fit = ctx->fit;
    r.evaluations = ctx->evaluations;
    r.generations = ctx->generations;
    r.f_band = ctx->f_band;
    r.flags = ctx->flags;
    r.searches = ctx->search;
    r.runner_up = ctx->runner_up;
    *out = r;
    return PDT_OK;
}

pdt_status_t pdt_identify(pdt_ident_t *ctx, const pdt_ident_config_t *cfg,
                          const pdt_ident_data_t *data, void *work, size_t work_len,
                          pdt_ident_result_t *out)
{
    if (out == NULL) {
        return PDT_ERR_ARG;
    }
    pdt_status_t st = pdt_ident_init(ctx, cfg, data, work, work_len);
    while (st == PDT_OK || st == PDT_RUNNING) {
        st = pdt_ident_step(ctx, cfg->max_evaluations);
        if (st == PDT_OK) {
            return pdt_ident_result(ctx, out);
        }
    }
    return st;
}
