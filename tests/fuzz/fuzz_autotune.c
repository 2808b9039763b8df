/*
 * Fuzz target: a whole autotune (pdt_autotune_init, then pdt_autotune_scan
 * scan by scan) fed fuzzed process values: a simulated lag whose output
 * the fuzzer perturbs, replaces or sets to NaN, with a fuzzed experiment,
 * limits and identification. Contracts checked: init returns OK or a
 * negative status and leaves *at untouched on error; every scan writes a
 * finite output within [u_min, u_max]; a scan uses at most evals_per_scan
 * cost evaluations (bounded work); once the experiment is over the output
 * is the operating point, exactly; the status is final once not RUNNING;
 * nothing is written past the workspace; an OK result has a valid model
 * and finite gains.
 */
#include "fuzz_util.h"

#define CAP_MAX    160u
#define WORK_BYTES PDT_AUTOTUNE_WORKSPACE_SIZE(CAP_MAX, PDT_IDENT_POPULATION_SOPDT)
#define SCANS_MAX  20000u

static _Alignas(16) uint8_t g_work[WORK_BYTES + FZ_CANARY_LEN];

/* The long campaign's quick mode (FZ_AUTOTUNE_SMALL=1 in the environment,
 * tests/fuzz/campaign.sh): capacities of at most SMALL_CAP + 7 samples and
 * identification budgets of at most 60 + 255 / 16 evaluations, a whole
 * autotune being this target's cost; the bytes mean the same otherwise, so
 * the corpora serve both modes. */
#define SMALL_CAP 24u
static uint32_t g_cap_max = CAP_MAX;
static uint32_t g_budget_div = 1u;

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    const char *small = getenv("FZ_AUTOTUNE_SMALL");
    if (small != NULL && strcmp(small, "1") == 0) {
        g_cap_max = SMALL_CAP;
        g_budget_div = 16u;
    }
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_t f = {data, size};
    pdt_autotune_config_t c;
    pdt_autotune_config_default(&c);
    int kind = 1 + fz_enum(&f, 5);
    pdt_excite_config_default(&c.excite, (pdt_excite_kind_t)kind);
    c.Ts = fz_pos(&f);
    c.decimation = 1u + (uint32_t)(fz_u8(&f) % 4u);
    c.capacity = (size_t)(fz_u8(&f) % (g_cap_max + 8u));
    c.settle = 1u + (uint32_t)(fz_u8(&f) % 24u);
    c.tail = fz_u8(&f) % 4u == 0u ? 0u : fz_u8(&f);
    c.evals_per_scan = (uint32_t)(fz_u8(&f) % 9u);
    c.u_min = (pdt_real_t)0.0;
    c.u_max = (pdt_real_t)100.0;
    c.pv_min = (pdt_real_t)-1000.0;
    c.pv_max = (pdt_real_t)1000.0;
    uint8_t knobs = fz_u8(&f);
    if (knobs & 1u) {
        c.u_min = fz_real(&f);
        c.u_max = fz_real(&f);
    }
    if (knobs & 2u) {
        c.pv_min = fz_real(&f);
        c.pv_max = fz_real(&f);
    }
    if (knobs & 4u) {
        c.max_scans = fz_u8(&f) * 8u;
    }
    c.move = (pdt_record_move_t)fz_enum(&f, 3);
    c.excite.amplitude = fz_bool(&f) ? (pdt_real_t)5.0 : fz_real(&f);
    c.excite.duration = fz_bool(&f) ? c.excite.duration : fz_real(&f);
    c.excite.t_on = fz_bool(&f) ? c.excite.t_on : fz_pos(&f);
    c.excite.t_off = fz_bool(&f) ? c.excite.t_off : fz_pos(&f);
    c.excite.f1 = fz_bool(&f) ? (pdt_real_t)0.1 / c.Ts : fz_real(&f);
    c.excite.prbs_bits = 2u + (uint32_t)(fz_u8(&f) % 8u);
    c.excite.setpoint = fz_real(&f);
    c.excite.d = fz_pos(&f);
    c.excite.eps = fz_bool(&f) ? (pdt_real_t)0.0 : fz_pos(&f);
    c.excite.relay_cycles = 1u + (uint32_t)(fz_u8(&f) % 3u);
    c.ident.model = fz_bool(&f) ? PDT_MODEL_SOPDT : PDT_MODEL_FOPDT;
    c.ident.cost = (pdt_cost_kind_t)fz_enum(&f, 4);
    c.ident.max_evaluations = 60u + fz_u8(&f) / g_budget_div;
    c.ident.refine_evaluations = fz_u8(&f) % 30u;
    c.ident.population = (uint32_t)(fz_u8(&f) % 14u);
    c.tune.rule = (pdt_tune_rule_t)fz_enum(&f, 4);
    c.tune.form = (pdt_tune_form_t)fz_enum(&f, 2);
    c.tune.ms_max = fz_bool(&f) ? (pdt_real_t)0.0 : c.tune.ms_max;
    c.tune.fit_min = fz_bool(&f) ? (pdt_real_t)-1e30 : c.tune.fit_min;
    pdt_real_t u_now = fz_bool(&f) ? (pdt_real_t)50.0 : fz_real(&f);

    size_t need = pdt_autotune_workspace_size(&c);
    size_t len = need != 0u && need <= WORK_BYTES ? need : WORK_BYTES;
    fz_canary_set(g_work + len);
    pdt_autotune_t at;
    memset(&at, 0x5A, sizeof at);
    static pdt_autotune_t before;
    memcpy(&before, &at, sizeof at);
    pdt_status_t st = pdt_autotune_init(&at, &c, u_now, g_work, len);
    if (st != PDT_OK) {
        FZ_CHECK(st < 0);
        FZ_CHECK(memcmp(&at, &before, sizeof at) == 0);
        FZ_CHECK(fz_canary_ok(g_work + len));
        return 0;
    }
    FZ_CHECK(need != 0u);

    /* The plant: a lag with a fuzzed gain; the bytes left perturb it. */
    double gain = (double)(int8_t)fz_u8(&f) / 16.0;
    double y = (double)(c.pv_min / 2 + c.pv_max / 2);
    if (!isfinite(y)) {
        y = 0.0;
    }
    double y_rest = y;
    pdt_real_t u = u_now;
    pdt_status_t last = PDT_RUNNING;
    bool over = false;
    for (uint32_t k = 0; k < SCANS_MAX; k++) {
        pdt_real_t pv = (pdt_real_t)y;
        uint8_t b = fz_u8(&f);
        if (b == 0xFFu) {
            pv = fz_real(&f); /* any value, NaN included */
        } else if (b >= 0xF0u) {
            pv += (pdt_real_t)(b & 0x0Fu) * (pdt_real_t)0.01;
        }
        pdt_autotune_phase_t ph = pdt_autotune_phase(&at);
        uint64_t s0 = at.ident_started ? at.ident.samples : 0u;
        bool started = at.ident_started;
        st = pdt_autotune_scan(&at, pv, &u);
        FZ_CHECK(isfinite((double)u) && u >= c.u_min && u <= c.u_max);
        if (started && at.ident_started) {
            /* A group of the population may exceed a smaller budget. */
            FZ_CHECK(at.ident.samples - s0 <= (uint64_t)(c.evals_per_scan > PDT_VECTOR_LANES
                                                             ? c.evals_per_scan
                                                             : PDT_VECTOR_LANES) *
                                                  at.ident.data.n);
        }
        if (ph == PDT_AUTOTUNE_IDENTIFY || ph == PDT_AUTOTUNE_TUNE) {
            over = true;
        }
        if (over && st != PDT_ERR_PV_LIMIT && st != PDT_ERR_NONFINITE) {
            pdt_autotune_result_t rr;
            FZ_CHECK(pdt_autotune_result(&at, &rr) == PDT_OK);
            (void)rr;
        }
        FZ_CHECK(fz_canary_ok(g_work + len));
        if (last != PDT_RUNNING) {
            FZ_CHECK(st == last);
            break;
        }
        last = st;
        y += 0.1 * (y_rest + gain * ((double)u - (double)u_now) - y);
        if (!isfinite(y)) {
            y = y_rest;
        }
        if (st != PDT_RUNNING && f.n == 0u) {
            pdt_real_t u2;
            FZ_CHECK(pdt_autotune_scan(&at, pv, &u2) == st && u2 == u);
            break;
        }
    }
    pdt_autotune_result_t r;
    FZ_CHECK(pdt_autotune_result(&at, &r) == PDT_OK);
    if (last == PDT_OK) {
        FZ_CHECK(r.status == PDT_OK && r.has_model && r.has_gains);
        FZ_CHECK(fz_model_sane(&r.ident.model));
        FZ_CHECK(isfinite((double)r.tune.ideal.Kc) && r.tune.ideal.Kc != (pdt_real_t)0.0);
    } else if (last != PDT_RUNNING) {
        FZ_CHECK(last < 0 && r.status == last);
    }
    return 0;
}
