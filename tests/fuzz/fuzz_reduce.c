/*
 * Fuzz target: pdt_reduce_half_rule, pdt_reduce_ultimate and
 * pdt_reduce_sung on fuzzed plants and configurations. Contracts checked:
 * OK or a negative status; outputs untouched on error; an OK model is
 * valid (pdt_model_check) and an OK ultimate frequency finite and > 0;
 * n_freq beyond PDT_REDUCE_MAX_FREQ is refused (bounded work).
 */
#include "fuzz_util.h"

#define LAGS_MAX (PDT_REDUCE_MAX_LAGS + 2u)

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_t f = {data, size};
    pdt_real_t lags[LAGS_MAX], zeros[8];
    pdt_reduce_plant_t p;
    p.k = fz_real(&f);
    p.n_lags = fz_u8(&f) % (LAGS_MAX + 1u);
    for (size_t i = 0; i < p.n_lags; i++) {
        lags[i] = fz_bool(&f) ? fz_pos(&f) : fz_real(&f);
    }
    p.lags = lags;
    p.n_zeros = fz_u8(&f) % 9u;
    for (size_t i = 0; i < p.n_zeros; i++) {
        zeros[i] = fz_real(&f);
    }
    p.zeros = (p.n_zeros > 0u || fz_bool(&f)) ? zeros : NULL;
    p.theta0 = fz_bool(&f) ? (pdt_real_t)0.0 : fz_real(&f);

    pdt_reduce_config_t cfg;
    pdt_reduce_config_default(&cfg);
    cfg.model = fz_bool(&f) ? PDT_MODEL_SOPDT : PDT_MODEL_FOPDT;
    if (fz_bool(&f)) {
        cfg.model = (pdt_model_kind_t)fz_u8(&f);
    }
    cfg.h = fz_bool(&f) ? (pdt_real_t)0.0 : fz_real(&f);
    uint8_t nf = fz_u8(&f);
    cfg.n_freq = nf < 0xF0u ? (uint32_t)nf : fz_u32(&f);
    const pdt_reduce_config_t *pc = fz_u8(&f) == 0u ? NULL : &cfg;

    pdt_model_t m, m0;
    pdt_reduce_info_t info, info0;
    memset(&m, 0x5A, sizeof m);
    memset(&info, 0x6B, sizeof info);
    m0 = m;
    info0 = info;

    pdt_status_t st = pdt_reduce_half_rule(&p, pc, &m, &info);
    if (st == PDT_OK) {
        FZ_CHECK(fz_model_sane(&m));
    } else {
        FZ_CHECK(st < 0);
        FZ_CHECK(memcmp(&m, &m0, sizeof m) == 0 && memcmp(&info, &info0, sizeof info) == 0);
    }

    pdt_real_t w = (pdt_real_t)-1.0;
    st = pdt_reduce_ultimate(&p, &w);
    if (st == PDT_OK) {
        FZ_CHECK(isfinite((double)w) && w > (pdt_real_t)0.0);
    } else {
        FZ_CHECK(st < 0 && w == (pdt_real_t)-1.0);
    }

    m = m0;
    info = info0;
    st = pdt_reduce_sung(&p, pc, &m, fz_bool(&f) ? NULL : &info);
    if (st == PDT_OK) {
        FZ_CHECK(fz_model_sane(&m));
        FZ_CHECK(pc == NULL || cfg.n_freq <= PDT_REDUCE_MAX_FREQ);
    } else {
        FZ_CHECK(st < 0);
        FZ_CHECK(memcmp(&m, &m0, sizeof m) == 0 && memcmp(&info, &info0, sizeof info) == 0);
    }
    return 0;
}
