/*
 * Fuzz target: pdt_cost_init with a fuzzed configuration and record, then
 * pdt_cost_eval, pdt_cost_frequency and pdt_cost_profile with fuzzed
 * models. Contracts checked: statuses are OK or negative; on error *c, the
 * workspace and every output are untouched; nothing is written past the
 * workspace or the scratch; an OK cost is >= 0 and not NaN; an OK profile's
 * parts are not NaN and its gain lies within given bounds.
 */
#include "fuzz_util.h"

#define NMAX       600u
#define WORK_BYTES PDT_COST_WORKSPACE_SIZE(NMAX)

static pdt_real_t g_u[NMAX], g_y[NMAX];
static pdt_real_t g_scratch[NMAX + FZ_CANARY_LEN];
static _Alignas(16) uint8_t g_work[WORK_BYTES + FZ_CANARY_LEN];
static pdt_real_t g_weights[NMAX * 2u];

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_t f = {data, size};
    pdt_cost_config_t cfg;
    pdt_cost_config_default(&cfg);
    cfg.Ts = fz_pos(&f);
    uint8_t knobs = fz_u8(&f);
    cfg.kind = (pdt_cost_kind_t)fz_enum(&f, 4);
    cfg.time_kind = (pdt_cost_kind_t)fz_enum(&f, 2);
    cfg.delay_mode = (pdt_delay_mode_t)fz_enum(&f, 2);
    cfg.weight = (pdt_weight_kind_t)fz_enum(&f, 5);
    cfg.whole_record = fz_bool(&f);
    cfg.estimate_offset = fz_bool(&f);
    cfg.use_frequency = fz_bool(&f);
    cfg.delay_min = fz_u8(&f) % 8u;
    cfg.delay_max = (knobs & 1u) ? (size_t)fz_u8(&f) : cfg.delay_max;
    if (knobs & 2u) {
        cfg.u0 = fz_real(&f);
        cfg.y0 = fz_real(&f);
    }
    if (knobs & 4u) {
        cfg.phi_t = fz_real(&f);
        cfg.phi_f = fz_real(&f);
    }
    if (knobs & 8u) {
        cfg.f_lo = fz_real(&f);
        cfg.f_hi = fz_real(&f);
    }
    for (size_t i = 0; i < sizeof g_weights / sizeof g_weights[0]; i++) {
        g_weights[i] = (knobs & 16u) ? (pdt_real_t)(i % 3u) : (pdt_real_t)1.0;
    }
    cfg.weights = (knobs & 32u) ? g_weights : NULL;
    size_t n = (size_t)((((unsigned)fz_u8(&f) << 8) | fz_u8(&f)) % (NMAX + 1u));
    pdt_real_t level = (pdt_real_t)0.0;
    for (size_t i = 0; i < n; i++) {
        if (f.n > 0u && (i % 8u) == 0u) {
            level = fz_real(&f);
        }
        g_u[i] = level;
        g_y[i] = f.n > 0u ? fz_real(&f) : (pdt_real_t)0.0;
    }

    size_t need = pdt_cost_workspace_size(&cfg, n);
    size_t len = need <= WORK_BYTES ? need : WORK_BYTES;
    if (knobs & 64u) {
        len = WORK_BYTES;
    }
    memset(g_work, 0x22, len);
    fz_canary_set(g_work + len);
    pdt_cost_t c;
    memset(&c, 0x5A, sizeof c);
    pdt_cost_t before = c;
    void *work = (knobs & 128u) ? NULL : g_work;
    pdt_status_t st = pdt_cost_init(&c, &cfg, g_u, g_y, n, work, len);
    FZ_CHECK(fz_canary_ok(g_work + len));
    if (st != PDT_OK) {
        FZ_CHECK(st < 0);
        FZ_CHECK(memcmp(&c, &before, sizeof c) == 0);
        for (size_t i = 0; i < len; i++) {
            FZ_CHECK(g_work[i] == 0x22u);
        }
        return 0;
    }

    for (int round = 0; round < 4 && f.n > 0u; round++) {
        pdt_model_t m = fz_model(&f);
        const pdt_real_t sentinel = (pdt_real_t)-12345.0;
        pdt_real_t cost = sentinel;
        st = pdt_cost_eval(&c, &m, &cost);
        if (st == PDT_OK) {
            FZ_CHECK(cost >= (pdt_real_t)0.0);
        } else {
            FZ_CHECK(st < 0 && cost == sentinel);
        }
        cost = sentinel;
        st = pdt_cost_frequency(&c, &m, &cost);
        if (st == PDT_OK) {
            FZ_CHECK(cost >= (pdt_real_t)0.0);
        } else {
            FZ_CHECK(st < 0 && cost == sentinel);
        }
        pdt_real_t gmin = (pdt_real_t)0.0;
        pdt_real_t gmax = (pdt_real_t)0.0;
        if (fz_bool(&f)) {
            gmin = fz_real(&f);
            gmax = fz_real(&f);
        }
        fz_canary_set(g_scratch + n);
        pdt_cost_profile_t p;
        memset(&p, 0x44, sizeof p);
        pdt_cost_profile_t p0 = p;
        st = pdt_cost_profile(&c, &m, gmin, gmax, g_scratch, &p);
        FZ_CHECK(fz_canary_ok(g_scratch + n));
        if (st == PDT_OK && fz_moderate(g_u, n) && fz_moderate(g_y, n)) {
            FZ_CHECK(!isnan((double)p.cost) && !isnan((double)p.gain) && !isnan((double)p.offset));
            FZ_CHECK(!isnan((double)p.ct) && !isnan((double)p.cf));
        }
        if (st == PDT_OK) {
            if (gmin != (pdt_real_t)0.0 || gmax != (pdt_real_t)0.0) {
                FZ_CHECK(p.gain >= gmin && p.gain <= gmax);
            }
        } else {
            FZ_CHECK(st < 0 && memcmp(&p, &p0, sizeof p) == 0);
        }
    }
    FZ_CHECK(fz_canary_ok(g_work + len));
    return 0;
}
