/*
 * Fuzz target: pdt_ident_init / pdt_ident_step / pdt_ident_result with a
 * fuzzed configuration and record. Contracts checked: init returns OK or a
 * negative status and leaves ctx and the workspace untouched on error;
 * nothing is written past the workspace; each step uses at most the
 * evaluations it was given and the whole search at most max_evaluations
 * (bounded work); step ends in OK; the result's model is valid, of the
 * configured kind, with its dead time, a FOPDT's time constant and the
 * gain within the bounds given (to rounding, equal bounds included), a
 * SOPDT's damping at least zeta_min, and its figures are not NaN.
 */
#include "fuzz_util.h"

#define NMAX       512u
#define POP_MAX    16u
#define WORK_BYTES (PDT_IDENT_WORKSPACE_SIZE(NMAX, PDT_IDENT_POPULATION_SOPDT) + 64u)

static pdt_real_t g_u[NMAX], g_y[NMAX];
static _Alignas(16) uint8_t g_work[WORK_BYTES + FZ_CANARY_LEN];
static pdt_real_t g_weights[NMAX + 1u];

/* The long campaign's quick mode (FZ_IDENT_SMALL=1 in the environment,
 * tests/fuzz/campaign.sh): records of at most SMALL_N samples and budgets
 * of at most 40 + 255 / 8 evaluations, about 80 times less work an input;
 * the bytes mean the same otherwise, so the corpora serve both modes. */
#define SMALL_N 24u
static size_t g_nmax = NMAX;
static uint32_t g_budget_div = 1u;

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    const char *small = getenv("FZ_IDENT_SMALL");
    if (small != NULL && strcmp(small, "1") == 0) {
        g_nmax = SMALL_N;
        g_budget_div = 16u;
    }
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_t f = {data, size};
    pdt_ident_config_t cfg;
    pdt_ident_config_default(&cfg);
    cfg.model = fz_bool(&f) ? PDT_MODEL_SOPDT : PDT_MODEL_FOPDT;
    cfg.Ts = fz_pos(&f);
    cfg.cost = (pdt_cost_kind_t)fz_enum(&f, 4);
    cfg.time_kind = (pdt_cost_kind_t)fz_enum(&f, 2);
    cfg.weight = (pdt_ident_weight_t)fz_enum(&f, 5);
    cfg.delay_mode = (pdt_delay_mode_t)fz_enum(&f, 2);
    uint8_t knobs = fz_u8(&f);
    if (knobs & 1u) {
        cfg.phi_t = fz_real(&f);
        cfg.phi_f = fz_real(&f);
    }
    if (knobs & 2u) {
        cfg.f_lo = fz_real(&f);
        cfg.f_hi = fz_real(&f);
    }
    if (knobs & 4u) {
        cfg.tau_min = fz_real(&f);
        cfg.tau_max = fz_real(&f);
    }
    if (knobs & 8u) {
        cfg.Td_min = fz_real(&f);
        cfg.Td_max = fz_real(&f);
    }
    if (knobs & 16u) {
        cfg.K_min = fz_real(&f);
        cfg.K_max = fz_real(&f);
        cfg.zeta_min = fz_real(&f);
        cfg.integrating = fz_bool(&f);
    }
    if (knobs & 32u) {
        cfg.tolerance = fz_real(&f);
        cfg.eta_c = fz_real(&f);
        cfg.eta_m = fz_real(&f);
        cfg.p_crossover = fz_real(&f);
        cfg.p_mutation = fz_real(&f);
        cfg.sigma_share = fz_real(&f);
        cfg.elite = fz_u8(&f) % 8u;
        cfg.stall_generations = fz_u8(&f);
    }
    /* A small search keeps an execution short; the size of the budget is
     * not what is being tested. */
    cfg.population = (uint32_t)(fz_u8(&f) % (POP_MAX + 2u));
    cfg.max_evaluations = 40u + (uint32_t)fz_u8(&f) * 2u / g_budget_div;
    cfg.refine_evaluations = (uint32_t)(fz_u8(&f) % 40u);
    cfg.seed = fz_u32(&f);
    /* Automatic, the whole record, or a coarse record of any factor. */
    cfg.coarse = (uint32_t)(fz_u8(&f) % 12u);
    size_t n = (size_t)((((unsigned)fz_u8(&f) << 8) | fz_u8(&f)) % (g_nmax + 1u));
    for (size_t i = 0; i < NMAX + 1u; i++) {
        g_weights[i] = (pdt_real_t)1.0;
    }
    cfg.weights = (knobs & 64u) ? g_weights : NULL;
    /* The record: u a few levels held for fuzzed lengths, y free. */
    pdt_real_t level = (pdt_real_t)0.0;
    for (size_t i = 0; i < n; i++) {
        if (f.n > 0u && (i % 16u) == 0u) {
            level = fz_real(&f);
        }
        g_u[i] = level;
        g_y[i] = f.n > 0u ? fz_real(&f) : (pdt_real_t)i;
    }
    pdt_ident_data_t d = {g_u, g_y, n};

    size_t need = pdt_ident_workspace_size(&cfg, n);
    FZ_CHECK(need <= WORK_BYTES || need > PDT_IDENT_WORKSPACE_SIZE(NMAX, POP_MAX + 1u));
    size_t len = need != 0u && need <= WORK_BYTES ? need : WORK_BYTES;
    if (knobs & 128u) {
        len = len / 2u; /* a workspace too short */
    }
    memset(g_work, 0x11, len);
    fz_canary_set(g_work + len);

    pdt_ident_t ctx;
    memset(&ctx, 0x5A, sizeof ctx);
    static pdt_ident_t before;
    memcpy(&before, &ctx, sizeof ctx);
    pdt_status_t st = pdt_ident_init(&ctx, &cfg, &d, g_work, len);
    FZ_CHECK(fz_canary_ok(g_work + len));
    if (st != PDT_OK) {
        FZ_CHECK(st < 0);
        FZ_CHECK(memcmp(&ctx, &before, sizeof ctx) == 0);
        /* A record the screen fills first (a missing sample, a value orders
         * of magnitude off) may have its copy in work (pdt_ident_init). */
        bool filled = false;
        for (size_t k = 0; k < n; k++) {
            filled = filled || !isfinite(g_y[k]);
        }
        filled =
            !cfg.refuse_missing && (filled || (!cfg.no_screen && pdt_cost_outlier(g_y, n) < n));
        for (size_t i = 0; !filled && i < len; i++) {
            FZ_CHECK(g_work[i] == 0x11u);
        }
        return 0;
    }
    FZ_CHECK(need != 0u && len >= need);

    pdt_ident_result_t r;
    memset(&r, 0x33, sizeof r);
    pdt_ident_result_t r0 = r;
    FZ_CHECK(pdt_ident_result(&ctx, &r) == PDT_ERR_STATE);
    FZ_CHECK(memcmp(&r, &r0, sizeof r) == 0);

    uint32_t calls = 0;
    do {
        uint32_t chunk = 1u + (uint32_t)(fz_u8(&f) % 16u);
        uint64_t s0 = ctx.samples;
        st = pdt_ident_step(&ctx, chunk);
        /* A group of the population may exceed a smaller budget; the
         * budget is of whole-record evaluations (a coarse one scores
         * n / D samples). */
        FZ_CHECK(ctx.samples - s0 <=
                 (uint64_t)(chunk > PDT_VECTOR_LANES ? chunk : PDT_VECTOR_LANES) * n);
        FZ_CHECK(ctx.evaluations <= cfg.max_evaluations);
        FZ_CHECK(fz_canary_ok(g_work + len));
        calls++;
        /* Every call makes progress or a preparation step: far fewer calls
         * than twice the budget, for the first answer and for each round
         * of the screen for gross errors. */
        FZ_CHECK(calls <= (PDT_IDENT_SCREEN_ROUNDS + 1u) * (2u * cfg.max_evaluations + 64u));
    } while (st == PDT_RUNNING);
    if (st != PDT_OK) {
        /* The screen's refusal (pdt_ident_step): more samples to leave out
         * than max_excluded allows, the first named; or a record the rest
         * no longer makes identifiable. The status stays, and the result
         * is refused untouched. */
        FZ_CHECK(st < 0);
        FZ_CHECK(st != PDT_ERR_OUTLIER || pdt_ident_outlier(&ctx) < n);
        FZ_CHECK(pdt_ident_step(&ctx, 1u) == st);
        FZ_CHECK(pdt_ident_result(&ctx, &r) == st);
        FZ_CHECK(memcmp(&r, &r0, sizeof r) == 0);
        return 0;
    }
    FZ_CHECK(st == PDT_OK);
    FZ_CHECK(pdt_ident_step(&ctx, 1u) == PDT_OK);

    pdt_ident_result_t r_before;
    memset(&r, 0x3C, sizeof r);
    r_before = r;
    st = pdt_ident_result(&ctx, &r);
    FZ_CHECK(fz_canary_ok(g_work + len));
    if (st != PDT_OK) {
        /* Only a model beyond the real type is refused here, and then the
         * result is untouched. */
        FZ_CHECK(st == PDT_ERR_NONFINITE && memcmp(&r, &r_before, sizeof r) == 0);
        return 0;
    }
    FZ_CHECK(fz_model_sane(&r.model));
    FZ_CHECK(r.model.kind == cfg.model);
    if (cfg.Td_min != (pdt_real_t)0.0 || cfg.Td_max != (pdt_real_t)0.0) {
        /* Bounds the caller gave hold to rounding, equal ones too. */
        FZ_CHECK(fz_within(pdt_model_dead_time(&r.model), cfg.Td_min, cfg.Td_max));
    }
    if (cfg.model == PDT_MODEL_FOPDT &&
        (cfg.tau_min != (pdt_real_t)0.0 || cfg.tau_max != (pdt_real_t)0.0)) {
        FZ_CHECK(fz_within(r.model.p.fopdt.tau, cfg.tau_min, cfg.tau_max));
    }
    if (cfg.model == PDT_MODEL_SOPDT && r.model.p.sopdt.b > (pdt_real_t)0.0) {
        /* zeta = a / (2 sqrt(b)) at least zeta_min, where b is a normal
         * number of the real type (below, b = h h has lost the digits that
         * tell; a float's subnormal is a normal double, so the test is on
         * the real type itself). */
        const pdt_model_sopdt_t *p = &r.model.p.sopdt;
        if (isnormal(p->b) && isnormal(p->a)) {
            const double zeta = (double)p->a / (2.0 * sqrt((double)p->b));
            FZ_CHECK(zeta >= (double)cfg.zeta_min * (1.0 - 1e-6));
        }
    }
    if (cfg.K_min != (pdt_real_t)0.0 || cfg.K_max != (pdt_real_t)0.0) {
        /* SOPDT: the DC gain k / b, or the integrating gain k / a. */
        pdt_real_t K = r.model.p.fopdt.K;
        if (r.model.kind == PDT_MODEL_SOPDT) {
            const pdt_model_sopdt_t *p = &r.model.p.sopdt;
            K = p->b > (pdt_real_t)0.0 ? p->k / p->b : p->k / p->a;
        }
        FZ_CHECK(fz_within(K, cfg.K_min, cfg.K_max));
    }
    if (fz_moderate(g_u, n) && fz_moderate(g_y, n)) {
        FZ_CHECK(!isnan((double)r.cost) && !isnan((double)r.fit));
    }
    return 0;
}
