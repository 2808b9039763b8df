/*
 * Fuzz target: pdt_tune_compute, pdt_tune_robustness, the form conversions
 * and pdt_tune_ziegler_nichols on fuzzed models, gains and configurations.
 * Contracts checked: OK or a negative status; outputs untouched on error;
 * OK gains finite with Kc != 0, tauI > 0, tauD and Tf >= 0 (the domain of
 * pdt_tune_gains_t); OK figures with Ms >= 1 (not NaN), margins not NaN;
 * compute's Ms within ms_max when a limit is set. UBSan catches undefined
 * conversions on the way.
 */
#include "fuzz_util.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static bool gains_ok(const pdt_tune_gains_t *g)
{
    return isfinite((double)g->Kc) && g->Kc != (pdt_real_t)0.0 && isfinite((double)g->tauI) &&
           g->tauI > (pdt_real_t)0.0 && isfinite((double)g->tauD) && g->tauD >= (pdt_real_t)0.0 &&
           isfinite((double)g->Tf) && g->Tf >= (pdt_real_t)0.0;
}

/* What an output holds before a call: no call returns these gains. */
static const pdt_tune_gains_t g_pattern = {(pdt_real_t)-7.0, (pdt_real_t)-7.0, (pdt_real_t)-7.0,
                                           (pdt_real_t)-7.0};

/* The contract of a call that returns gains into *o: valid gains on OK,
 * *o untouched on error. Resets *o to the pattern for the next call. */
static void check_gains_out(pdt_status_t st, pdt_tune_gains_t *o)
{
    if (st == PDT_OK) {
        FZ_CHECK(gains_ok(o));
    } else {
        FZ_CHECK(st < 0 && memcmp(o, &g_pattern, sizeof *o) == 0);
    }
    *o = g_pattern;
}

static bool figures_ok(const pdt_tune_figures_t *fg)
{
    return fg->Ms >= (pdt_real_t)1.0 && !isnan((double)fg->gain_margin) &&
           !isnan((double)fg->phase_margin_deg) && !isnan((double)fg->w_ms) &&
           !isnan((double)fg->w_pc) && !isnan((double)fg->w_gc);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_t f = {data, size};
    pdt_model_t m = fz_model(&f);
    pdt_tune_config_t cfg;
    pdt_tune_config_default(&cfg);
    cfg.rule = (pdt_tune_rule_t)fz_enum(&f, 4);
    cfg.form = (pdt_tune_form_t)fz_enum(&f, 2);
    uint8_t knobs = fz_u8(&f);
    if (knobs & 1u) {
        cfg.tau_c = fz_real(&f);
        cfg.lambda = fz_real(&f);
    }
    if (knobs & 2u) {
        cfg.deriv_filter = fz_real(&f);
    }
    if (knobs & 4u) {
        cfg.fit_min = fz_real(&f);
        cfg.ms_max = fz_real(&f);
    }
    pdt_real_t fit = (knobs & 8u) ? fz_real(&f) : (pdt_real_t)100.0;

    pdt_tune_result_t r, r0;
    memset(&r, 0x5A, sizeof r);
    r0 = r;
    pdt_status_t st = pdt_tune_compute(&m, fit, &cfg, &r);
    if (st == PDT_OK) {
        FZ_CHECK(gains_ok(&r.ideal));
        FZ_CHECK(figures_ok(&r.fig));
        FZ_CHECK(!r.series_exists || gains_ok(&r.series));
        FZ_CHECK(cfg.ms_max == (pdt_real_t)0.0 || r.fig.Ms <= cfg.ms_max);
    } else {
        FZ_CHECK(st < 0 && memcmp(&r, &r0, sizeof r) == 0);
    }

    pdt_tune_gains_t g;
    g.Kc = fz_real(&f);
    g.tauI = fz_pos(&f);
    g.tauD = fz_bool(&f) ? (pdt_real_t)0.0 : fz_pos(&f);
    g.Tf = fz_bool(&f) ? (pdt_real_t)0.0 : fz_pos(&f);
    pdt_tune_figures_t fg, fg0;
    memset(&fg, 0x6B, sizeof fg);
    fg0 = fg;
    st = pdt_tune_robustness(&m, &g, &fg);
    if (st == PDT_OK) {
        FZ_CHECK(figures_ok(&fg));
    } else {
        FZ_CHECK(st < 0 && memcmp(&fg, &fg0, sizeof fg) == 0);
    }

    pdt_tune_gains_t o = g_pattern;
    check_gains_out(pdt_tune_to_series(&g, &o), &o);
    check_gains_out(pdt_tune_to_ideal(&g, &o), &o);
    pdt_real_t Ku = fz_real(&f);
    pdt_real_t Pu = fz_real(&f);
    pdt_tune_form_t form = (pdt_tune_form_t)fz_enum(&f, 2);
    check_gains_out(pdt_tune_ziegler_nichols(Ku, Pu, form, &o), &o);
    return 0;
}
