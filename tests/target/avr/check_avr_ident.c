/*
 * Identification on the AVR: a FOPDT record of AVR_IDENT_N samples (a
 * PRBS through the plant, simulated with pdt_discrete_simulate, around
 * u0 = 10, y0 = 50, with deterministic noise at 30 dB) identified by
 * pdt_identify with the default configuration and Ts = 0.5 s, in a
 * uint8_t-aligned place of the arena as an Arduino sketch would give it.
 * The model must land within the Cortex-M4F check's tolerances; the
 * cycles and the stack of the identification are reported.
 */
#include <math.h>

#include "avr_checks.h"
#include "sim_process.h"
#include "sim_rng.h"
#include "target_util.h"

#include "pdt_port.h"
#include "pdt_port_avr.h"

#define TRUE_K   2.0
#define TRUE_TAU 12.0
#define TRUE_TD  4.37
#define TS       0.5
#define U0       10.0
#define Y0       50.0

/* u: a random binary sequence of +-1 (0 for the first 10 samples, then a
 * level held 8 samples, flipped with probability 1/2 at each change); y:
 * the model's response plus noise at 30 dB; both about the operating
 * point. False if the model could not be simulated. */
static bool make_record(pdt_real_t *u, pdt_real_t *y)
{
    const pdt_model_t m = model_fopdt(TRUE_K, TRUE_TAU, TRUE_TD);
    sim_rng64_t s = sim_rng64_seed(7u);
    double level = 1.0;
    for (size_t k = 0; k < AVR_IDENT_N; k++) {
        if (k >= 10u && (k - 10u) % 8u == 0u && sim_rng64_coin(&s) != 0) {
            level = -level;
        }
        u[k] = (pdt_real_t)(k < 10u ? 0.0 : level);
    }
    pdt_discrete_t d;
    if (pdt_discrete_init(&m, (pdt_real_t)TS, &d) != PDT_OK ||
        pdt_discrete_simulate(&d, u, AVR_IDENT_N, y) != PDT_OK) {
        return false;
    }
    double mean = 0.0;
    for (size_t k = 0; k < AVR_IDENT_N; k++) {
        mean += (double)y[k];
    }
    mean /= (double)AVR_IDENT_N;
    double var = 0.0;
    for (size_t k = 0; k < AVR_IDENT_N; k++) {
        var += ((double)y[k] - mean) * ((double)y[k] - mean);
    }
    const double sd = sqrt(var / (double)AVR_IDENT_N) * pow(10.0, -30.0 / 20.0);
    sim_rng64_t ns = sim_rng64_seed(99u);
    for (size_t k = 0; k < AVR_IDENT_N; k++) {
        u[k] = (pdt_real_t)(U0 + (double)u[k]);
        y[k] = (pdt_real_t)(Y0 + (double)y[k] + sd * sim_rng64_normal(&ns));
    }
    return true;
}

int avr_check_ident(void)
{
    pdt_real_t *u = g_avr_arena.ident.u;
    pdt_real_t *y = g_avr_arena.ident.y;
    pdt_ident_config_t cfg;
    pdt_ident_config_default(&cfg);
    cfg.Ts = (pdt_real_t)TS;
    /* A clean record, and 8 KiB of RAM: no screen and no copy of y. */
    cfg.no_screen = true;
    cfg.refuse_missing = true;
    const pdt_ident_data_t data = {u, y, AVR_IDENT_N};
    /* One byte into the workspace: a float needs no alignment on AVR. */
    uint8_t *work = (uint8_t *)g_avr_arena.ident.work + 1;
    const size_t have = sizeof g_avr_arena.ident.work - 1u;
    const size_t need = pdt_ident_workspace_size(&cfg, AVR_IDENT_N);
    pdt_ident_result_t res;
    pdt_status_t st = PDT_ERR_NOMEM;
    uint64_t cycles = 0u;
    size_t stack = 0u;
    if (make_record(u, y) && need != 0u && need <= have) {
        const size_t depth = pdt_avr_stack_depth();
        t_stack_repaint();
        const uint64_t t0 = pdt_port_ticks();
        st = pdt_identify(&g_avr_arena.ident.ctx, &cfg, &data, work, need, &res);
        cycles = pdt_port_ticks() - t0;
        stack = pdt_avr_stack_used() - depth;
    }
    tline_t l;
    tl_init(&l);
    TL_STR(&l, "identify FOPDT K=2 tau=12 Td=4.37, n=");
    tl_uint(&l, AVR_IDENT_N);
    TL_STR(&l, ", Ts=0.5, 30 dB: ");
    if (st != PDT_OK || res.model.kind != PDT_MODEL_FOPDT) {
        TL_STR(&l, "status ");
        tl_int(&l, st);
        return t_verdict(false, &l);
    }
    /* The Cortex-M4F check's tolerances: gain 1.5 %, tau 2 %, Td 2 % of
     * tau, output level 0.5 % of the swing, fit 95 %. */
    const pdt_model_fopdt_t *g = &res.model.p.fopdt;
    const double eK = rel_err((double)g->K, TRUE_K);
    const double etau = rel_err((double)g->tau, TRUE_TAU);
    const double eTd = fabs((double)g->Td - TRUE_TD) / TRUE_TAU;
    const double ey0 = fabs((double)res.y0 - Y0) / (2.0 * TRUE_K);
    const bool ok =
        eK <= 0.015 && etau <= 0.02 && eTd <= 0.02 && ey0 <= 0.005 && (double)res.fit >= 95.0;
    tl_fopdt(&l, g);
    TL_STR(&l, " fit ");
    tl_num(&l, (double)res.fit, 4);
    TL_STR(&l, "%; errors K ");
    tl_num(&l, eK, 2);
    TL_STR(&l, " tau ");
    tl_num(&l, etau, 2);
    TL_STR(&l, " Td ");
    tl_num(&l, eTd, 2);
    TL_STR(&l, " tau (max 0.015, 0.02, 0.02)");
    const int failed = t_verdict(ok, &l);
    tl_init(&l);
    TL_STR(&l, "identify FOPDT n=");
    tl_uint(&l, AVR_IDENT_N);
    TL_STR(&l, ": ");
    tl_uint(&l, res.evaluations);
    TL_STR(&l, " evaluations, ");
    tl_uint(&l, cycles);
    TL_STR(&l, " cycles (");
    tl_num(&l, (double)cycles / (double)pdt_port_ticks_per_second(), 3);
    TL_STR(&l, " s), workspace ");
    tl_uint(&l, need);
    TL_STR(&l, " + context ");
    tl_uint(&l, sizeof(pdt_ident_t));
    TL_STR(&l, " bytes, stack ");
    tl_uint(&l, stack);
    TL_STR(&l, " bytes");
    t_info(&l);
    /* A 16-bit size_t makes PDT_IDENT_MAX_RECORDS 1: a second record is
     * refused, and the joint fit is not in the program. */
    const pdt_ident_record_t second = {u, y, AVR_IDENT_N, (pdt_real_t)TS, false, 0};
    cfg.more = &second;
    cfg.more_count = 1u;
    const size_t need2 = pdt_ident_workspace_size(&cfg, AVR_IDENT_N);
    const pdt_status_t st2 = pdt_identify(&g_avr_arena.ident.ctx, &cfg, &data, work, have, &res);
    tl_init(&l);
    TL_STR(&l, "identify with a second record (PDT_IDENT_MAX_RECORDS ");
    tl_uint(&l, PDT_IDENT_MAX_RECORDS);
    TL_STR(&l, "): workspace ");
    tl_uint(&l, need2);
    TL_STR(&l, ", status ");
    tl_int(&l, st2);
    return failed + t_verdict(PDT_IDENT_MAX_RECORDS == 1u && need2 == 0u && st2 == PDT_ERR_ARG, &l);
}
