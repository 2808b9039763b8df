/*
 * Identification: the configuration, the workspace, and the sequencer that
 * runs the engine's stages (pdt_ident_priv.h) within each call's budget.
 */
#include "pdt/pdt_ident.h"

#include "pdt_ident_priv.h"
#include "pdt_internal.h"

#define IDENT_MAGIC PDT_MAGIC('P', 'D', 'I', 'D')

/* The dead-time gene is linear below a sixteenth of its range, then
 * logarithmic (see td_offset). */
#define TD_OFFSET_DIV PDT_R(16.0)

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
    cfg->weight = PDT_IDENT_WEIGHT_AUTO;
    cfg->offset = PDT_IDENT_OFFSET_AUTO;
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
    cfg->coarse = 0u;
}

static uint32_t genes_of(pdt_model_kind_t kind)
{
    return pdt_model_kind_params(kind) - 1u; /* the gain is profiled */
}

/* The population, the automatic one resolved: a 2-gene FOPDT search needs
 * fewer individuals than a 3-gene SOPDT one to cover its space. */
static uint32_t population_of(const pdt_ident_config_t *cfg)
{
    if (cfg->population != 0u) {
        return cfg->population;
    }
    return pdt_model_kind_lags(cfg->model) == 2u ? PDT_IDENT_POPULATION_SOPDT
                                                 : PDT_IDENT_POPULATION_FOPDT;
}

/* The cost's weighting: the identification's own, CONTROL uniform until
 * its band is known. */
static pdt_weight_kind_t cost_weight(const pdt_ident_config_t *cfg)
{
    switch (pdt_ident_weight_of(cfg)) {
    case PDT_IDENT_WEIGHT_BAND:
        return PDT_WEIGHT_BAND;
    case PDT_IDENT_WEIGHT_CUSTOM:
        return PDT_WEIGHT_CUSTOM;
    default:
        return PDT_WEIGHT_UNIFORM;
    }
}

/* The cost configuration the identification runs on. */
static void cost_config(const pdt_ident_config_t *cfg, pdt_real_t u0, pdt_real_t y0, bool rest,
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
    if (pdt_ident_control_band(cfg)) {
        /* First stage: the time cost; the spectra are prepared all the
         * same, so the workspace is sized for the second. */
        cc->kind = cfg->time_kind;
    }
    cc->delay_mode = cfg->delay_mode;
    /* The output offset: the level of the rest window, or fitted with the
     * model (see rest_offset). */
    cc->estimate_offset = !rest;
    cc->estimate_state = (cfg->initial == PDT_IDENT_INITIAL_ESTIMATE);
    cc->drift = cfg->drift;
    /* The paper's window would drop the first Td_max / Ts samples: where a
     * step test shows its dead time. */
    cc->whole_record = true;
    cc->use_frequency = pdt_ident_uses_frequency(cfg->cost);
    cc->phi_t = cfg->phi_t;
    cc->phi_f = cfg->phi_f;
    cc->weight = cost_weight(cfg);
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
    pdt_real_t T, Ts;
    /* Several records: the shortest one's duration, the shortest period. */
    pdt_ident_multi_span(cfg, n, &T, &Ts);
    b->tau_min = cfg->tau_min;
    b->tau_max = cfg->tau_max;
    if (b->tau_min == PDT_R(0.0) && b->tau_max == PDT_R(0.0)) {
        b->tau_min = Ts * PDT_R(0.25);
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
    /* Whole delays cannot meet bounds that hold no whole sample. */
    if (cfg->delay_mode == PDT_DELAY_INTEGER &&
        !pdt_ident_whole_between(cfg->Ts, b->Td_min, b->Td_max)) {
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
    if (pdt_model_kind_lags(cfg->model) == 1u) {
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

/* The least budget of one search: one population (two with the CONTROL
 * weighting, which scores it once per cost), one simplex and the late
 * reserve. */
static uint64_t search_need(const pdt_ident_config_t *cfg)
{
    return pdt_ident_search_need(cfg, population_of(cfg));
}

/* Independent searches: the time criteria only (the frequency criteria
 * re-centre their spectra during a search); as asked, or as many as the
 * budget gives each a whole search, up to PDT_IDENT_MAX_SEARCHES. 0 when
 * the budget does not cover the searches asked for. */
static uint32_t searches_of(const pdt_ident_config_t *cfg)
{
    const uint64_t need = search_need(cfg);
    if (pdt_ident_uses_frequency(cfg->cost)) {
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
    case PDT_IDENT_WEIGHT_UNIFORM:
    case PDT_IDENT_WEIGHT_CONTROL:
    case PDT_IDENT_WEIGHT_AUTO:
        break;
    case PDT_IDENT_WEIGHT_BAND:
        if (!pdt_finite(cfg->f_lo) || !pdt_finite(cfg->f_hi) || cfg->f_lo < PDT_R(0.0)) {
            return PDT_ERR_ARG;
        }
        if (cfg->f_lo > cfg->f_hi) {
            return PDT_ERR_BOUNDS;
        }
        break;
    case PDT_IDENT_WEIGHT_CUSTOM:
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
    if (!pdt_model_kind_known(cfg->model)) {
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
    if (cfg->offset != PDT_IDENT_OFFSET_AUTO && cfg->offset != PDT_IDENT_OFFSET_ESTIMATE &&
        cfg->offset != PDT_IDENT_OFFSET_REST) {
        return PDT_ERR_ARG;
    }
    if (cfg->delay_mode != PDT_DELAY_FRACTIONAL && cfg->delay_mode != PDT_DELAY_INTEGER) {
        return PDT_ERR_ARG;
    }
    if (cfg->initial != PDT_IDENT_INITIAL_AUTO && cfg->initial != PDT_IDENT_INITIAL_REST &&
        cfg->initial != PDT_IDENT_INITIAL_ESTIMATE) {
        return PDT_ERR_ARG;
    }
    /* The free response and the drift are columns of the output error's
     * least squares. */
    if ((cfg->initial == PDT_IDENT_INITIAL_ESTIMATE || cfg->drift) &&
        cfg->cost != PDT_COST_SIMULATION) {
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
    if (pdt_model_kind_lags(cfg->model) == 2u &&
        (!(cfg->zeta_min > PDT_R(0.0)) || !pdt_finite(cfg->zeta_min))) {
        return PDT_ERR_ARG;
    }
    if (!pdt_finite(cfg->K_min) || !pdt_finite(cfg->K_max) ||
        (cfg->u_before_given && !pdt_finite(cfg->u_before))) {
        return PDT_ERR_ARG;
    }
    if (cfg->K_min > cfg->K_max) {
        return PDT_ERR_BOUNDS;
    }
    return pdt_ident_multi_check(cfg);
}

/* Whole samples in a time t >= 0 at period Ts, at most cap: a ratio past
 * the record (or past size_t) is the record's end, never a float-to-size
 * overflow. */
static size_t samples_in(pdt_real_t t, pdt_real_t Ts, size_t cap)
{
    const pdt_real_t q = t / Ts;
    return (q >= PDT_R(0.0) && q < (pdt_real_t)cap) ? (size_t)q : cap;
}

/* The screen's part of the workspace, in reals: the filled y and two
 * bits per sample; none where the configuration needs no screen. */
static size_t screen_reals(const pdt_ident_config_t *cfg, size_t n)
{
    /* Without the screen and with missing samples refused, y is never
     * filled or screened: a small part's RAM is spared the copy. */
    if ((cfg->no_screen && cfg->refuse_missing) || pdt_ident_multi(cfg)) {
        return 0u;
    }
    const size_t bits = 8u * sizeof(pdt_real_t);
    return n + 2u * ((n + bits - 1u) / bits);
}

/* Layout of the workspace after the cost's own part, in reals. */
static size_t own_reals(const pdt_ident_config_t *cfg, uint32_t pop, uint32_t genes, size_t n)
{
    return 2u * (size_t)pop * ((size_t)genes + 3u) + (size_t)pop + pdt_ident_multi_longest(cfg, n) +
           screen_reals(cfg, n) + pdt_ident_multi_reals(cfg);
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
    cost_config(cfg, PDT_R(0.0), PDT_R(0.0), false, samples_in(b.Td_max, cfg->Ts, n) + 1u, &cc);
    size_t cost_bytes = pdt_cost_workspace_size(&cc, n);
    if (cc.use_frequency && cost_bytes == 0u) {
        return 0u;
    }
    /* Round the cost part up so the rest stays aligned for pdt_real_t. */
    cost_bytes = (cost_bytes + sizeof(pdt_real_t) - 1u) / sizeof(pdt_real_t) * sizeof(pdt_real_t);
    return cost_bytes +
           own_reals(cfg, population_of(cfg), genes_of(cfg->model), n) * sizeof(pdt_real_t);
}

/* The input before the record: u_before when given, else u[0]. */
static pdt_real_t input_before(const pdt_ident_config_t *cfg, const pdt_ident_data_t *d)
{
    return cfg->u_before_given ? cfg->u_before : d->u[0];
}

/* Samples before the input first moves, and the shortest dead time after
 * them (at most half the record): the rest window. */
static size_t rest_window(const pdt_ident_data_t *d, size_t quiet_extra)
{
    size_t k = 1u;
    while (k < d->n && d->u[k] == d->u[0]) {
        k++;
    }
    k += quiet_extra;
    if (k > d->n / 2u) {
        k = d->n / 2u > 0u ? d->n / 2u : 1u;
    }
    return k;
}

/* The rest window's level as the output offset (pdt_ident_rest.c). A model
 * that cannot follow the process exactly (a FOPDT of a higher order
 * process) trades its gain against a fitted offset: on the
 * Astrom-Hagglund batch the fitted offset pulled K of 1/(s+1)^4 down by
 * 1-2 %. The level of a record that starts at rest is information the fit
 * need not guess. AUTO considers it when the window holds at least
 * REST_MIN_DIV-th of the record (and PDT_MIN_SAMPLES) and the output is
 * flat over it. */
#define REST_MIN_DIV 40u

/* Whether y over its first k samples is flat: the means of the two halves
 * differ by at most four standard errors of the noise about them. A
 * process still settling from an earlier move (a test restarted too soon)
 * is not at rest, and its level is no operating point. */
static bool flat(const pdt_real_t *y, size_t k)
{
    const size_t h = k / 2u;
    pdt_real_t m[2] = {PDT_R(0.0), PDT_R(0.0)};
    pdt_real_t ss = PDT_R(0.0);
    for (size_t i = 0; i < 2u * h; i++) {
        m[i / h] += y[i] - y[0];
    }
    m[0] /= (pdt_real_t)h;
    m[1] /= (pdt_real_t)h;
    for (size_t i = 0; i < 2u * h; i++) {
        const pdt_real_t e = y[i] - y[0] - m[i / h];
        ss += e * e;
    }
    const pdt_real_t var = ss / (pdt_real_t)(2u * h - 2u);
    const pdt_real_t d = m[1] - m[0];
    return d * d <= PDT_R(16.0) * PDT_R(2.0) * var / (pdt_real_t)h;
}

/* AUTO: the rest window's samples when the record has one to use (a time
 * criterion, the window long and flat), else 0. */
static uint32_t rest_usable(const pdt_ident_config_t *cfg, const pdt_ident_data_t *d,
                            size_t quiet_extra)
{
    if (cfg->offset != PDT_IDENT_OFFSET_AUTO || pdt_ident_uses_frequency(cfg->cost) ||
        input_before(cfg, d) != d->u[0]) {
        return 0u;
    }
    const size_t k = rest_window(d, quiet_extra);
    return (k >= PDT_MIN_SAMPLES && k >= d->n / REST_MIN_DIV && flat(d->y, k)) ? (uint32_t)k : 0u;
}

/* The output level before the input first moves: the mean of y over that
 * stretch (and the shortest dead time after it), at least one sample. Only
 * the start of the search uses it; the model re-estimates the offset. */
static pdt_real_t initial_level(const pdt_ident_data_t *d, size_t quiet_extra)
{
    const size_t k = rest_window(d, quiet_extra);
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

/* The record's checks of init (the data in order: not finite, too short
 * for the dead-time bound, no excitation, not at rest for the frequency
 * criteria) and the delay bound of the cost. */
static pdt_status_t check_record(const pdt_ident_config_t *cfg, const pdt_ident_data_t *data,
                                 const bounds_t *b, size_t *delay_max)
{
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
    const pdt_real_t ub = input_before(cfg, data);
    if (!(umax > umin || ub != data->u[0]) || !(ymax > ymin)) {
        return PDT_ERR_NO_EXCITATION;
    }
    if (pdt_ident_uses_frequency(cfg->cost) &&
        !ends_at_rest(data, initial_level(data, samples_in(b->Td_min, cfg->Ts, data->n)),
                      umax - umin, ymax - ymin)) {
        return PDT_ERR_NOT_AT_REST;
    }
    pdt_real_t lmax = b->Td_max / cfg->Ts;
    if (!(lmax < (pdt_real_t)(data->n))) {
        return PDT_ERR_TOO_SHORT;
    }
    *delay_max = (size_t)lmax + 1u;
    return PDT_OK;
}

/* The workspace's checks of init: NULL, misaligned, too short. */
static pdt_status_t check_work(const pdt_ident_config_t *cfg, size_t n, const void *work,
                               size_t work_len)
{
    if (work == NULL) {
        return PDT_ERR_NOMEM;
    }
    if (!pdt_aligned(work)) {
        return PDT_ERR_ARG;
    }
    size_t need = pdt_ident_workspace_size(cfg, n);
    if (need == 0u) {
        return PDT_ERR_ARG;
    }
    return work_len < need ? PDT_ERR_NOMEM : PDT_OK;
}

/* The workspace (aligned for pdt_real_t, checked by init) in reals. */
static pdt_real_t *reals_of(void *work)
{
    return (pdt_real_t *)work;
}

/* The screen's part at the workspace's end: the filled y (n reals), then
 * its mask (n bits). */
static void screen_layout(const pdt_ident_config_t *cfg, size_t n, void *work,
                          pdt_ident_screen_t *s)
{
    const size_t reals = screen_reals(cfg, n);
    s->work = work;
    if (reals == 0u) {
        s->yfill = NULL;
        s->mask = NULL;
        s->fresh = NULL;
        return;
    }
    const size_t at = pdt_ident_workspace_size(cfg, n) / sizeof(pdt_real_t) - reals;
    const size_t bits = 8u * sizeof(pdt_real_t);
    s->yfill = &reals_of(work)[at];
    /* Bytes of the reals after the filled y: a character type may alias
     * any object. */
    s->mask = (uint8_t *)&s->yfill[n];
    s->fresh = (uint8_t *)&s->yfill[n + (n + bits - 1u) / bits];
}

/* The GA's arrays and the scratch, after the cost's part of the
 * workspace (cost_bytes). */
static void carve(pdt_ident_t *c, void *work, size_t cost_bytes)
{
    const size_t whole = (cost_bytes + sizeof(pdt_real_t) - 1u) / sizeof(pdt_real_t);
    /* work is aligned for pdt_real_t and the cost's part a whole number
     * of reals, so the rest of the workspace is addressed in reals. */
    pdt_real_t *p = &reals_of(work)[whole];
    size_t P = (size_t)c->cfg.population, G = (size_t)c->genes;
    c->ga.pop = p;
    p += P * G;
    c->ga.pop_cost = p;
    p += P;
    c->ga.pop_gain = p;
    p += P;
    c->ga.pop_offset = p;
    p += P;
    c->ga.off = p;
    p += P * G;
    c->ga.off_cost = p;
    p += P;
    c->ga.off_gain = p;
    p += P;
    c->ga.off_offset = p;
    p += P;
    c->ga.shared = p;
    p += P;
    c->scratch = p;
}

/* The screen's state of a new context: as prepared (screen), or with
 * nothing left out and y copied. The context's record becomes the filled
 * one (the caller's own where the workspace has no screen part). */
static void screen_begin(pdt_ident_t *c, const pdt_ident_screen_t *screen, void *work,
                         size_t work_len)
{
    const size_t n = c->data.n;
    if (screen != NULL) {
        c->screen = *screen;
    } else {
        screen_layout(&c->cfg, n, work, &c->screen);
        for (size_t k = 0; (c->screen.yfill != NULL) && (k < n); k++) {
            c->screen.yfill[k] = c->data.y[k];
        }
        for (size_t k = 0; (c->screen.mask != NULL) && (k < (n + 7u) / 8u); k++) {
            c->screen.mask[k] = 0u;
        }
        c->screen.first = n;
        c->screen.limit = pdt_ident_screen_limit(&c->cfg, n);
        c->screen.y_in = c->data.y;
    }
    c->screen.work = work;
    c->screen.work_len = work_len;
    c->screen.status = PDT_OK;
    if (c->screen.yfill != NULL) {
        c->data.y = c->screen.yfill;
    }
}

/* init's work once the configuration and the workspace are known to be
 * good: the record checked, the cost prepared, the context written. screen
 * is the screen's state to keep (a record with samples left out), or NULL.
 * cfg, data and screen may lie in *ctx. */

static pdt_status_t start(pdt_ident_t *ctx, const pdt_ident_config_t *cfg,
                          const pdt_ident_data_t *data, void *work, size_t work_len,
                          const pdt_ident_screen_t *screen)
{
    bounds_t b;
    pdt_real_t glo[3], ghi[3];
    size_t delay_max = 0u;
    pdt_status_t st = resolve_bounds(cfg, data->n, &b);
    st = (st == PDT_OK) ? gene_bounds(cfg, &b, glo, ghi) : st;
    st = (st == PDT_OK) ? check_record(cfg, data, &b, &delay_max) : st;
    st = (st == PDT_OK) ? check_work(cfg, data->n, work, work_len) : st;
    if (st != PDT_OK) {
        return st;
    }
    /* The checks that can still fail write only into locals and the
     * workspace; *ctx is written once they passed (a copy of the whole
     * context would double the stack init needs). */
    const size_t quiet = samples_in(b.Td_min, cfg->Ts, data->n);
    pdt_real_t y0 = initial_level(data, quiet);
    pdt_cost_config_t cc;
    cost_config(cfg, input_before(cfg, data), y0, cfg->offset == PDT_IDENT_OFFSET_REST, delay_max,
                &cc);
    size_t cost_bytes = pdt_cost_workspace_size(&cc, data->n);
    /* A band or custom weights that select no bin of this record (e.g. a
     * band above the Nyquist frequency) would leave the frequency part
     * empty and the search blind in it; checked before the cost writes
     * into the workspace. */
    if ((cfg->cost == PDT_COST_FREQUENCY ||
         (cfg->cost == PDT_COST_COMBINED && cfg->phi_f > PDT_R(0.0))) &&
        pdt_cost_band_empty(&cc, data->n)) {
        return PDT_ERR_ARG;
    }
    pdt_cost_t cost;
    st = pdt_cost_init(&cost, &cc, data->u, data->y, data->n, work, cost_bytes);
    if (st != PDT_OK) {
        return st;
    }
    /* cfg, data and screen may lie in *ctx (a restart with its own
     * settings). */
    const pdt_ident_config_t cfg_in = *cfg;
    const pdt_ident_data_t data_in = *data;
    pdt_ident_screen_t screen_in = {0};
    if (screen != NULL) {
        screen_in = *screen;
    }
    pdt_ident_t *const c = ctx;
    *c = (pdt_ident_t){0};
    c->cfg = cfg_in;
    c->cfg.population = population_of(&cfg_in);
    c->data = data_in;
    c->genes = genes_of(cfg_in.model);
    c->cost = cost;
    if (pdt_ident_multi(&cfg_in)) {
        /* Several records: the searches run on the whole records. */
        c->cfg.coarse = 1u;
    }
    c->cost_work = work;
    c->cost_work_len = cost_bytes;
    carve(c, work, cost_bytes);
    screen_begin(c, screen != NULL ? &screen_in : NULL, work, work_len);
    for (size_t j = 0; j < c->genes; j++) {
        c->lo[j] = glo[j];
        c->hi[j] = ghi[j];
    }
    c->td_offset = td_offset(&cfg_in, &b);
    /* With the state estimated the record's start is no rest window; with
     * a drift the offset is the level at the record's middle, not the rest
     * window's. */
    c->rest =
        (cfg_in.initial == PDT_IDENT_INITIAL_ESTIMATE || cfg_in.drift || pdt_ident_multi(&cfg_in))
            ? 0u
            : rest_usable(&cfg_in, &c->data, quiet);
    /* The searches begin in calls of their own: each test of the coarse
     * record's shape, and the coarse record with its cost, weigh as much
     * as the checks above (a scan of a control task's budget each). */
    c->coarse.delay_max = (uint32_t)cc.delay_max;
    c->phase = PH_SHAPE_BEGIN;
    c->magic = IDENT_MAGIC;
    return PDT_OK;
}

/* PH_SHAPE_BEGIN: the searches' budget, the coarse record's first factor. */
static pdt_ident_outcome_t begin_search(pdt_ident_t *c)
{
    c->vote.searches = searches_of(&c->cfg);
    c->vote.budget = c->cfg.max_evaluations / c->vote.searches;
    return pdt_ident_coarse_first(c);
}

/* PH_PREPARE: the coarse record and its cost. */
static pdt_ident_outcome_t prepare_search(pdt_ident_t *c)
{
    pdt_ident_coarse_start(c);
    return OUT_DONE;
}

/* Several records: the further records' costs prepared after the rest of
 * the workspace, before start (its stack stays one record's). */
static pdt_status_t prepare_more(const pdt_ident_config_t *cfg, const pdt_ident_data_t *data,
                                 void *work, size_t work_len, pdt_cost_t **more)
{
    bounds_t b;
    pdt_cost_config_t cc;
    pdt_status_t st = check_work(cfg, data->n, work, work_len);
    st = (st == PDT_OK) ? resolve_bounds(cfg, data->n, &b) : st;
    if (st != PDT_OK) {
        return st;
    }
    cost_config(cfg, PDT_R(0.0), PDT_R(0.0), false, 0u, &cc);
    size_t delay_max = 0u;
    if (check_record(cfg, data, &b, &delay_max) != PDT_OK) {
        /* start gives the first record's status. */
        return PDT_OK;
    }
    cc.delay_max = delay_max;
    const size_t at =
        (pdt_cost_workspace_size(&cc, data->n) + sizeof(pdt_real_t) - 1u) / sizeof(pdt_real_t) +
        own_reals(cfg, population_of(cfg), genes_of(cfg->model), data->n) -
        pdt_ident_multi_reals(cfg);
    return pdt_ident_multi_prepare(cfg, &cc, b.Td_max, work, at, more);
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
    if (pdt_ident_multi(cfg)) {
        pdt_cost_t *more = NULL;
        st = prepare_more(cfg, data, work, work_len, &more);
        st = (st == PDT_OK) ? start(ctx, cfg, data, work, work_len, NULL) : st;
        if (st == PDT_OK) {
            ctx->more_cost = more;
        }
        return st;
    }
    if (cfg->refuse_missing || !pdt_ident_screen_needed(cfg, data)) {
        return start(ctx, cfg, data, work, work_len, NULL);
    }
    /* Missing samples or gross outliers: the record filled in the
     * workspace first, then checked and prepared as any other. */
    for (size_t k = 0; k < data->n; k++) {
        if (!pdt_finite(data->u[k])) {
            return PDT_ERR_NONFINITE;
        }
    }
    st = check_work(cfg, data->n, work, work_len);
    if (st != PDT_OK) {
        return st;
    }
    pdt_ident_screen_t s = {0};
    screen_layout(cfg, data->n, work, &s);
    st = pdt_ident_screen_prepare(&s, cfg, data);
    if (st != PDT_OK) {
        return st;
    }
    const pdt_ident_data_t filled = {data->u, s.yfill, data->n};
    return start(ctx, cfg, &filled, work, work_len, &s);
}

/* The identification prepared again, as init does, on the screen's
 * filled record, the screen's state kept; its status. */
static pdt_status_t restart(pdt_ident_t *c)
{
    /* start copies what it keeps before it writes *c. */
    c->screen.prior += c->evaluations;
    /* The count of samples scored goes on across the rounds, so that a
     * caller's per-call measure of the work never runs backwards. */
    const uint64_t samples = c->samples;
    const pdt_status_t st =
        start(c, &c->cfg, &c->data, c->screen.work, c->screen.work_len, &c->screen);
    c->samples = samples;
    return st;
}

size_t pdt_ident_outlier(const pdt_ident_t *ctx)
{
    if (ctx == NULL || ctx->magic != IDENT_MAGIC || ctx->screen.status != PDT_ERR_OUTLIER) {
        return SIZE_MAX;
    }
    return ctx->screen.first;
}

/* PH_REFIT: AUTO's at-rest test failed (auto_state set, initial still
 * AUTO): the identification begun again with the state estimated. */
static pdt_ident_outcome_t state_refit(pdt_ident_t *c)
{
    c->cfg.initial = PDT_IDENT_INITIAL_ESTIMATE;
    const pdt_status_t st = restart(c);
    c->auto_state = true;
    if (st != PDT_OK) {
        c->screen.status = st;
        return OUT_FAILED;
    }
    return OUT_DONE;
}

/* PH_SCREEN_RESTART: the identification begun again on the record the
 * screen filled. */
static pdt_ident_outcome_t screen_restart(pdt_ident_t *c)
{
    const pdt_status_t st = restart(c);
    if (st != PDT_OK) {
        pdt_ident_screen_failed(c, st);
        return OUT_FAILED;
    }
    return OUT_DONE;
}

/* What a phase needs before its stage runs (plan_t.needs); a phase that
 * needs nothing is a decision or the rest of the stage before it, and
 * runs in the call that reached it. */
#define NEEDS_BUDGET 1u /* an evaluation left in this call */
#define EVALUATES    2u /* uses them: one, or one per evaluation made */
#define HEAVY        4u /* as costly as init: one per call */
#define GROUP        8u /* evaluates a group of the population at once */

#define NEEDS_EVAL  (NEEDS_BUDGET | EVALUATES)
#define NEEDS_GROUP (NEEDS_BUDGET | EVALUATES | GROUP)

/* The plan: for each phase, what it needs and the phase that follows each
 * outcome its stage returns (none, 0: an outcome it never returns). A way
 * into a search or a polish names the phase its PH_FINISH returns to
 * (then; PH_RETURN leads there). docs/ident-engine.md draws it
 * (tools/engine_plan.py). */
#define PLAN_WAYS 4u /* outcomes a phase has at most */

typedef struct plan_way {
    uint8_t out;  /* an outcome of the phase's stage */
    uint8_t next; /* the phase after it */
    uint8_t then; /* 0, or the phase PH_RETURN leads to from now on */
} plan_way_t;

typedef struct plan {
    uint8_t needs;
    plan_way_t way[PLAN_WAYS];
} plan_t;

static const plan_t PLAN[PH_COUNT] PDT_ROM = {
    /* The population (pdt_ident_ga.c, pdt_ident_band.c). */
    [PH_INIT_POP] = {NEEDS_GROUP,
                     {{OUT_AGAIN, PH_INIT_POP, 0u},
                      {OUT_GENERATION, PH_BREED, 0u},
                      {OUT_DONE, PH_GA_END, 0u}}},
    [PH_BREED] = {NEEDS_BUDGET | HEAVY, {{OUT_DONE, PH_EVAL_OFF, 0u}}},
    [PH_EVAL_OFF] = {NEEDS_GROUP,
                     {{OUT_AGAIN, PH_EVAL_OFF, 0u},
                      {OUT_GENERATION, PH_BREED, 0u},
                      {OUT_DONE, PH_GA_END, 0u}}},
    [PH_TIME_POP] = {NEEDS_GROUP,
                     {{OUT_AGAIN, PH_TIME_POP, 0u},
                      {OUT_GENERATION, PH_TIME_BREED, 0u},
                      {OUT_DONE, PH_BAND, 0u}}},
    [PH_TIME_BREED] = {NEEDS_BUDGET | HEAVY, {{OUT_DONE, PH_TIME_OFF, 0u}}},
    [PH_TIME_OFF] = {NEEDS_GROUP,
                     {{OUT_AGAIN, PH_TIME_OFF, 0u},
                      {OUT_GENERATION, PH_TIME_BREED, 0u},
                      {OUT_DONE, PH_BAND, 0u}}},
    [PH_GA_END] = {0u, {{OUT_RECENTRE, PH_RECENTRE, 0u}, {OUT_DONE, PH_REFINE_START, 0u}}},
    [PH_SHAPE_BEGIN] = {0u, {{OUT_DONE, PH_SHAPE, 0u}, {OUT_SKIPPED, PH_PREPARE, 0u}}},
    [PH_SHAPE] = {HEAVY, {{OUT_AGAIN, PH_SHAPE, 0u}, {OUT_DONE, PH_PREPARE, 0u}}},
    [PH_PREPARE] = {HEAVY, {{OUT_DONE, PH_GA_START, PH_SEARCH_END}}},
    [PH_GA_START] = {0u, {{OUT_DONE, PH_INIT_POP, 0u}, {OUT_TIME, PH_TIME_POP, 0u}}},
    [PH_BAND] = {HEAVY, {{OUT_DONE, PH_INIT_POP, 0u}}},
    /* The refinement and the polish (pdt_ident_refine.c,
     * pdt_ident_polish.c, pdt_ident_scan.c). */
    [PH_RECENTRE] = {HEAVY, {{OUT_DONE, PH_REFINE_START, 0u}}},
    [PH_REFINE_START] = {0u, {{OUT_DONE, PH_REFINE, 0u}}},
    [PH_REFINE_FROM] = {0u, {{OUT_DONE, PH_REFINE, 0u}}},
    [PH_REFINE] = {NEEDS_GROUP,
                   {{OUT_AGAIN, PH_REFINE, 0u},
                    {OUT_POLISH, PH_POLISH_BEGIN, 0u},
                    {OUT_DONE, PH_REFINE_END, 0u}}},
    [PH_NM_BEST] = {0u, {{OUT_DONE, PH_REFINE, 0u}, {OUT_SKIPPED, PH_REFINE_END, 0u}}},
    [PH_POLISH_BEGIN] = {0u, {{OUT_DONE, PH_POLISH, 0u}}},
    [PH_POLISH] = {NEEDS_GROUP,
                   {{OUT_AGAIN, PH_POLISH, 0u},
                    {OUT_FALLBACK, PH_NM_BEST, 0u},
                    {OUT_DONE, PH_REFINE_END, 0u}}},
    [PH_REFINE_END] = {0u,
                       {{OUT_SCAN, PH_SCAN_START, 0u},
                        {OUT_KINK, PH_KINK_PINNED, 0u},
                        {OUT_PROBE, PH_PROBE, 0u},
                        {OUT_DONE, PH_FINISH, 0u}}},
    [PH_KINK_PINNED] = {NEEDS_GROUP,
                        {{OUT_AGAIN, PH_KINK_PINNED, 0u},
                         {OUT_FALLBACK, PH_KINK_MIRROR, 0u},
                         {OUT_DONE, PH_KINK_MIRROR, 0u}}},
    [PH_KINK_MIRROR] = {0u,
                        {{OUT_KINK, PH_KINK_ACROSS, 0u},
                         {OUT_PROBE, PH_PROBE, 0u},
                         {OUT_DONE, PH_FINISH, 0u}}},
    [PH_KINK_ACROSS] = {NEEDS_GROUP,
                        {{OUT_AGAIN, PH_KINK_ACROSS, 0u},
                         {OUT_FALLBACK, PH_KINK_HANDOVER, 0u},
                         {OUT_DONE, PH_PROBE_BEGIN, 0u}}},
    [PH_KINK_HANDOVER] = {0u, {{OUT_DONE, PH_KINK_NM, 0u}, {OUT_SKIPPED, PH_PROBE_BEGIN, 0u}}},
    [PH_KINK_NM] = {0u, {{OUT_DONE, PH_KINK_REFINE, 0u}, {OUT_SKIPPED, PH_PROBE_BEGIN, 0u}}},
    [PH_KINK_REFINE] = {NEEDS_GROUP,
                        {{OUT_AGAIN, PH_KINK_REFINE, 0u}, {OUT_DONE, PH_PROBE_BEGIN, 0u}}},
    [PH_PROBE_BEGIN] = {0u, {{OUT_PROBE, PH_PROBE, 0u}, {OUT_DONE, PH_FINISH, 0u}}},
    [PH_PROBE] = {NEEDS_GROUP,
                  {{OUT_AGAIN, PH_PROBE, 0u},
                   {OUT_POLISH, PH_POLISH_BEGIN, 0u},
                   {OUT_DONE, PH_FINISH, 0u}}},
    [PH_SCAN_START] = {0u, {{OUT_DONE, PH_DELAY_SCAN, 0u}}},
    [PH_DELAY_SCAN] = {NEEDS_EVAL,
                       {{OUT_AGAIN, PH_DELAY_SCAN, 0u}, {OUT_DONE, PH_DELAY_REFINE, 0u}}},
    [PH_DELAY_REFINE] = {NEEDS_EVAL, {{OUT_AGAIN, PH_DELAY_REFINE, 0u}, {OUT_DONE, PH_FINISH, 0u}}},
    /* The answers and the searches' vote (pdt_ident_vote.c,
     * pdt_ident_profile.c, pdt_ident_coarse.c, pdt_ident_rest.c). */
    [PH_FINISH] = {NEEDS_EVAL, {{OUT_DONE, PH_RETURN, 0u}}},
    [PH_SEARCH_END] = {0u,
                       {{OUT_SEARCH, PH_GA_START, PH_SEARCH_END},
                        {OUT_DONE, PH_PROFILE_BEGIN, 0u}}},
    [PH_PROFILE_BEGIN] = {0u, {{OUT_DONE, PH_PROFILE, 0u}, {OUT_SKIPPED, PH_CONCLUDE, 0u}}},
    [PH_PROFILE] = {NEEDS_GROUP,
                    {{OUT_AGAIN, PH_PROFILE, 0u},
                     {OUT_POLISH, PH_REFINE_FROM, PH_PROFILE_KEEP},
                     {OUT_KINK, PH_REFINE_FROM, PH_INTERVAL_KEEP},
                     {OUT_DONE, PH_CONCLUDE, 0u}}},
    [PH_PROFILE_KEEP] = {0u,
                         {{OUT_SEARCH, PH_GA_START, PH_PROFILE_KEEP},
                          {OUT_DONE, PH_PROFILE_END, 0u}}},
    [PH_PROFILE_END] = {0u, {{OUT_DONE, PH_CONCLUDE, 0u}}},
    [PH_INTERVAL_KEEP] = {0u,
                          {{OUT_SEARCH, PH_GA_START, PH_INTERVAL_KEEP},
                           {OUT_DONE, PH_INTERVAL_END, 0u}}},
    [PH_INTERVAL_END] = {0u, {{OUT_DONE, PH_CONCLUDE, 0u}}},
    [PH_CONCLUDE] = {0u, {{OUT_DONE, PH_COARSE_CHECK, 0u}}},
    [PH_COARSE_CHECK] = {0u, {{OUT_DONE, PH_FINE, 0u}, {OUT_SKIPPED, PH_REST_CHECK, 0u}}},
    [PH_FINE] = {HEAVY,
                 {{OUT_FAILED, PH_DONE, 0u},
                  {OUT_SEARCH, PH_GA_START, PH_SEARCH_END},
                  {OUT_POLISH, PH_POLISH_BEGIN, PH_WHOLE_END}}},
    [PH_WHOLE_END] = {0u, {{OUT_DONE, PH_REST_CHECK, 0u}}},
    [PH_REST_CHECK] = {0u, {{OUT_DONE, PH_REST, 0u}, {OUT_SKIPPED, PH_STD, 0u}}},
    [PH_REST] = {HEAVY, {{OUT_FAILED, PH_STD, 0u}, {OUT_POLISH, PH_POLISH_BEGIN, PH_STD}}},
    /* The answer's uncertainty and evidence (pdt_ident_vote.c). */
    [PH_STD] = {HEAVY,
                {{OUT_BEGUN, PH_STD_PASS, 0u},
                 {OUT_DONE, PH_SCREEN, 0u},
                 {OUT_FAILED, PH_SCREEN, 0u}}},
    [PH_STD_PASS] = {HEAVY,
                     {{OUT_AGAIN, PH_STD_PASS, 0u},
                      {OUT_DONE, PH_EVIDENCE, 0u},
                      {OUT_FAILED, PH_SCREEN, 0u}}},
    [PH_EVIDENCE] = {HEAVY, {{OUT_BEGUN, PH_EVIDENCE_LAGS, 0u}, {OUT_SKIPPED, PH_SCREEN, 0u}}},
    [PH_EVIDENCE_LAGS] = {HEAVY,
                          {{OUT_AGAIN, PH_EVIDENCE_LAGS, 0u},
                           {OUT_DONE, PH_STATE_TESTS, 0u},
                           {OUT_SKIPPED, PH_SCREEN, 0u}}},
    [PH_STATE_TESTS] = {HEAVY, {{OUT_DONE, PH_SCREEN, 0u}}},
    /* The screen for gross errors (pdt_ident_screen.c) and the rounds
     * begun again (here). */
    [PH_SCREEN] = {HEAVY,
                   {{OUT_REFIT, PH_REFIT, 0u},
                    {OUT_SKIPPED, PH_DONE, 0u},
                    {OUT_DONE, PH_SCREEN_HIGH, 0u}}},
    [PH_REFIT] = {0u, {{OUT_DONE, PH_SHAPE_BEGIN, 0u}, {OUT_FAILED, PH_DONE, 0u}}},
    [PH_SCREEN_HIGH] = {HEAVY, {{OUT_AGAIN, PH_SCREEN_HIGH, 0u}, {OUT_DONE, PH_SCREEN_MEDIAN, 0u}}},
    [PH_SCREEN_MEDIAN] = {HEAVY,
                          {{OUT_AGAIN, PH_SCREEN_MEDIAN, 0u}, {OUT_DONE, PH_SCREEN_BOUND, 0u}}},
    [PH_SCREEN_BOUND] = {HEAVY,
                         {{OUT_SKIPPED, PH_DONE, 0u},
                          {OUT_FAILED, PH_DONE, 0u},
                          {OUT_DONE, PH_SCREEN_REFILL, 0u}}},
    [PH_SCREEN_REFILL] = {HEAVY, {{OUT_FAILED, PH_DONE, 0u}, {OUT_DONE, PH_SCREEN_RESTART, 0u}}},
    [PH_SCREEN_RESTART] = {HEAVY, {{OUT_FAILED, PH_DONE, 0u}, {OUT_DONE, PH_SHAPE_BEGIN, 0u}}},
};

/* What phase needs, and the phase after it when its stage returned out
 * (PH_RETURN resolved; 0 where it has no way for out); a way that names
 * the phase to return to sets it. */
static uint32_t needs_of(uint32_t phase)
{
    return PDT_ROM_U8(&PLAN[phase].needs);
}

static uint32_t next_of(pdt_ident_t *c, uint32_t phase, pdt_ident_outcome_t out)
{
    for (uint32_t i = 0u; i < PLAN_WAYS; i++) {
        const plan_way_t *w = &PLAN[phase].way[i];
        const uint8_t way_out = PDT_ROM_U8(&w->out);
        const uint8_t way_next = PDT_ROM_U8(&w->next);
        const uint8_t way_then = PDT_ROM_U8(&w->then);
        if (way_out == (uint8_t)out && way_next != 0u) {
            const uint32_t next = (way_next == (uint8_t)PH_RETURN) ? c->resume : way_next;
            c->resume = (way_then != 0u) ? way_then : c->resume;
            return next;
        }
    }
    return 0u;
}

/* The candidates a GROUP stage evaluates together. */
static uint32_t group_of(const pdt_ident_t *c)
{
    switch (c->phase) {
    case PH_POLISH:
    case PH_KINK_PINNED:
    case PH_KINK_ACROSS:
        return pdt_ident_polish_group(c);
    case PH_PROBE:
        return pdt_ident_probe_group(c);
    case PH_PROFILE:
        return pdt_ident_profile_group(c);
    case PH_REFINE:
    case PH_KINK_REFINE:
        return pdt_ident_refine_group(c);
    default: /* PH_INIT_POP, PH_EVAL_OFF, PH_TIME_POP, PH_TIME_OFF */
        return pdt_ident_ga_group(c);
    }
}

/* The stages of the population, the refinement and the polish. */
static pdt_ident_outcome_t run_search(pdt_ident_t *c)
{
    switch (c->phase) {
    case PH_INIT_POP:
        return pdt_ident_ga_eval_parent(c, false);
    case PH_BREED:
    case PH_TIME_BREED:
        return pdt_ident_ga_breed(c);
    case PH_EVAL_OFF:
        return pdt_ident_ga_eval_offspring(c, false);
    case PH_TIME_POP:
        return pdt_ident_ga_eval_parent(c, true);
    case PH_TIME_OFF:
        return pdt_ident_ga_eval_offspring(c, true);
    case PH_GA_END:
        return pdt_ident_ga_end(c);
    case PH_SHAPE_BEGIN:
        return begin_search(c);
    case PH_SHAPE:
        return pdt_ident_coarse_factor(c);
    case PH_PREPARE:
        return prepare_search(c);
    case PH_GA_START:
        return pdt_ident_ga_begin(c);
    case PH_BAND:
        return pdt_ident_band_start(c);
    case PH_RECENTRE:
        return pdt_ident_refine_recentre(c);
    case PH_REFINE_START:
        return pdt_ident_refine_begin(c);
    case PH_REFINE_FROM:
        return pdt_ident_refine_from(c);
    case PH_REFINE:
    case PH_KINK_REFINE:
        return pdt_ident_refine_step(c);
    case PH_NM_BEST:
    case PH_KINK_NM:
        return pdt_ident_refine_nm_best(c);
    case PH_POLISH_BEGIN:
        return pdt_ident_polish_begin(c);
    case PH_POLISH:
    case PH_KINK_PINNED:
        return pdt_ident_polish_step(c, false);
    case PH_REFINE_END:
        return pdt_ident_polish_end(c);
    case PH_KINK_MIRROR:
        return pdt_ident_polish_mirror(c);
    case PH_KINK_ACROSS:
        return pdt_ident_polish_step(c, true);
    case PH_KINK_HANDOVER:
        return pdt_ident_polish_handover(c);
    case PH_PROBE_BEGIN:
        return pdt_ident_polish_probe_begin(c);
    case PH_PROBE:
        return pdt_ident_polish_probe(c);
    case PH_SCAN_START:
        return pdt_ident_scan_start(c);
    case PH_DELAY_SCAN:
        return pdt_ident_scan_grid(c);
    default: /* PH_DELAY_REFINE */
        return pdt_ident_scan_golden(c);
    }
}

/* The stages after a search's refinement: the answers, the uncertainty,
 * the screen. */
static pdt_ident_outcome_t run_answer(pdt_ident_t *c)
{
    switch (c->phase) {
    case PH_FINISH:
        return pdt_ident_finish(c);
    case PH_SEARCH_END:
    case PH_PROFILE_KEEP:
    case PH_INTERVAL_KEEP:
        return pdt_ident_search_end(c);
    case PH_PROFILE_BEGIN:
        return pdt_ident_profile_begin(c);
    case PH_PROFILE:
        return pdt_ident_profile_step(c);
    case PH_PROFILE_END:
        return pdt_ident_profile_end(c, false);
    case PH_INTERVAL_END:
        return pdt_ident_profile_end(c, true);
    case PH_CONCLUDE:
        return pdt_ident_conclude(c);
    case PH_COARSE_CHECK:
        return pdt_ident_coarse_pending(c);
    case PH_FINE:
        return pdt_ident_coarse_fine(c);
    case PH_WHOLE_END:
        return pdt_ident_coarse_whole(c);
    case PH_REST_CHECK:
        return pdt_ident_rest_check(c);
    case PH_REST:
        return pdt_ident_rest_start(c);
    case PH_STD:
        return pdt_ident_std(c);
    case PH_STD_PASS:
        return pdt_ident_std_pass(c);
    case PH_EVIDENCE:
        return pdt_ident_std_evidence(c);
    case PH_EVIDENCE_LAGS:
        return pdt_ident_std_lags(c);
    case PH_STATE_TESTS:
        return pdt_ident_std_state(c);
    case PH_SCREEN:
        return pdt_ident_screen_step(c);
    case PH_REFIT:
        return state_refit(c);
    case PH_SCREEN_HIGH:
        return pdt_ident_screen_high(c);
    case PH_SCREEN_MEDIAN:
        return pdt_ident_screen_median(c);
    case PH_SCREEN_BOUND:
        return pdt_ident_screen_bound(c);
    case PH_SCREEN_REFILL:
        return pdt_ident_screen_refill(c);
    default: /* PH_SCREEN_RESTART */
        return screen_restart(c);
    }
}

/* A switch, not a table of function pointers: the call graph stays static,
 * so the stack bound stays provable (tools/stack_bound.py). */
static pdt_ident_outcome_t run_stage(pdt_ident_t *c)
{
    return c->phase < PH_FINISH ? run_search(c) : run_answer(c);
}

pdt_status_t pdt_ident_step(pdt_ident_t *ctx, uint32_t max_evaluations)
{
    if (ctx == NULL || max_evaluations == 0u) {
        return PDT_ERR_ARG;
    }
    if (ctx->magic != IDENT_MAGIC) {
        return PDT_ERR_STATE;
    }
    /* The budget counts the samples the evaluations score: an evaluation
     * of a coarse record of n / D samples is a D-th of one of the whole. */
    const uint64_t cap = (uint64_t)max_evaluations * ctx->data.n;
    uint64_t budget = cap;
    bool heavy = false;
    while (ctx->phase != PH_DONE) {
        if (ctx->phase < PH_INIT_POP || ctx->phase >= PH_DONE) {
            return PDT_ERR_STATE;
        }
        const uint32_t phase = ctx->phase;
        const uint32_t needs = needs_of(phase);
        const uint64_t one = ctx->cost.n;
        /* A population group needs the budget for all its members; one
         * larger than a whole call's budget still runs, alone. */
        uint64_t want = ((needs & GROUP) != 0u ? group_of(ctx) : 1u) * one;
        want = want < cap ? want : cap;
        /* A heavy stage has the call to itself: it runs only before any
         * evaluation of the call, and the call ends after it and the
         * phases that need nothing. */
        if ((heavy && needs != 0u) || ((needs & NEEDS_BUDGET) != 0u && budget < want) ||
            ((needs & HEAVY) != 0u && budget < cap)) {
            return PDT_RUNNING;
        }
        const uint64_t before = ctx->samples;
        const pdt_ident_outcome_t out = run_stage(ctx);
        ctx->phase = next_of(ctx, phase, out);
        if ((needs & EVALUATES) != 0u) {
            const uint64_t used = ctx->samples - before;
            const uint64_t units = used > one ? used : one;
            budget = budget > units ? budget - units : 0u;
        }
        heavy = heavy || (needs & HEAVY) != 0u;
    }
    return ctx->screen.status;
}

pdt_status_t pdt_ident_result(const pdt_ident_t *ctx, pdt_ident_result_t *out)
{
    if (ctx == NULL || out == NULL) {
        return PDT_ERR_ARG;
    }
    if (ctx->magic != IDENT_MAGIC || ctx->phase != PH_DONE) {
        return PDT_ERR_STATE;
    }
    if (ctx->screen.status != PDT_OK) {
        return ctx->screen.status;
    }
    /* The search runs on the normalised record; mapped back, a gain can
     * lie beyond the real type (a tiny input driving a huge output). No
     * candidate scored at all where every gain the bounds allow gives a
     * cost beyond the real type: the model is then none of the bounds'. */
    if (pdt_model_check(&ctx->model) != PDT_OK || !(ctx->best.cost < PDT_REAL_MAX)) {
        return PDT_ERR_NONFINITE;
    }
    pdt_ident_result_t r;
    r.model = ctx->model;
    r.u0 = ctx->cost.cfg.u0;
    r.y0 = ctx->y0;
    r.cost = pdt_cost_units(&ctx->cost, ctx->best.cost);
    r.fit = ctx->fit;
    r.evaluations = ctx->evaluations + ctx->screen.prior;
    r.generations = ctx->generations;
    r.f_band = ctx->f_band;
    r.flags = ctx->flags;
    r.searches = pdt_ident_vote_searches(ctx);
    r.runner_up = ctx->runner_up;
    r.std = ctx->std;
    r.evidence = ctx->evidence;
    r.coarse = ctx->coarse.factor;
    r.initial = (ctx->cfg.initial == PDT_IDENT_INITIAL_ESTIMATE) ? PDT_IDENT_INITIAL_ESTIMATE
                                                                 : PDT_IDENT_INITIAL_REST;
    r.x0 = ctx->extra[0];
    r.dx0 = ctx->extra[1];
    r.drift = ctx->extra[2];
    pdt_ident_screen_report(&ctx->screen, ctx->data.n, &r);
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

pdt_status_t pdt_ident_record_result(pdt_ident_t *ctx, uint32_t r, pdt_ident_record_fit_t *out)
{
    pdt_ident_result_t res;
    if (ctx == NULL || out == NULL) {
        return PDT_ERR_ARG;
    }
    const pdt_status_t st = pdt_ident_result(ctx, &res);
    if (st != PDT_OK) {
        return st;
    }
    return pdt_ident_multi_record(ctx, &res, r, out);
}
