/*
 * Autotune on the AVR: a FOPDT plant (K = 2, tau = 10 s, Td = 3 s, the
 * Cortex-M4F check's) simulated scan by scan by the shared simulator
 * (tools/sim/sim_plant.h) with sensor noise, tuned by one complete
 * pdt_autotune run: 10 scans of settling, a PRBS of 15 chips held 2
 * scans, a record of AVR_AT_CAPACITY samples at Ts = 1 s, the order fixed
 * to a FOPDT and no validation. What 8 KiB hold beside the 3 KiB autotune
 * object and the 2.4 KiB of stack its scans take is in docs/port.md.
 * Checks the model and the gains with the Cortex-M4F check's tolerances
 * and reports the worst scan of each phase in cycles.
 */
#include <math.h>
#include <string.h>

#include "avr_checks.h"
#include "sim_process.h"
#include "sim_rng.h"
#include "target_util.h"

#include "pdt_port.h"
#include "pdt_port_avr.h"

#define AT_PHASES 7u

typedef struct at_run {
    pdt_status_t st;
    uint16_t scans;
    uint32_t worst[AT_PHASES]; /* cycles of the slowest scan of each phase */
    uint16_t calls[AT_PHASES];
    size_t stack;
} at_run_t;

/* The plant read through a sensor with white noise of 0.05. */
static pdt_real_t read_pv(const sim_plant_t *p, sim_rng64_t *rng)
{
    return (pdt_real_t)(sim_plant_output(p) + 0.05 * sim_rng64_normal(rng));
}

/* The configuration of the run, as the Cortex-M4F check's but for the
 * record's length (AVR_AT_CAPACITY). */
static void at_config(pdt_autotune_config_t *c)
{
    pdt_autotune_config_default(c);
    c->Ts = (pdt_real_t)1.0;
    c->capacity = AVR_AT_CAPACITY;
    c->settle = 10u;
    c->excite.kind = PDT_EXCITE_PRBS;
    c->excite.amplitude = (pdt_real_t)5.0;
    c->excite.prbs_bits = 4u;
    c->excite.prbs_hold = 2u;
    c->u_min = (pdt_real_t)0.0;
    c->u_max = (pdt_real_t)100.0;
    c->pv_min = (pdt_real_t)-100.0;
    c->pv_max = (pdt_real_t)200.0;
    c->ident.model = PDT_MODEL_FOPDT;
    /* As the identification check: no screen, no copy of y (RAM). */
    c->ident.no_screen = true;
    c->ident.refuse_missing = true;
    c->order_auto = false;
    c->ms_robust = (pdt_real_t)0.0;
}

/* The plant at rest and the autotune initialised. Not inlined: the
 * configuration (300 bytes) is off the stack while the scans run, which
 * read the object's copy. */
static __attribute__((noinline)) bool at_start(void)
{
    pdt_autotune_config_t c;
    at_config(&c);
    const pdt_model_t m = model_fopdt(2.0, 10.0, 3.0);
    sim_plant_desc_t d;
    double lag = 0.0;
    const size_t need = pdt_autotune_workspace_size(&c);
    return sim_desc_of_model(&m, &lag, &d) == 0 &&
           sim_plant_init(&g_avr_arena.autotune.plant, &d, (double)c.Ts, 40.0, 20.0,
                          g_avr_arena.autotune.hist, AVR_AT_HIST) == 0 &&
           need != 0u && need <= sizeof g_avr_arena.autotune.w.work &&
           pdt_autotune_init(&g_avr_arena.autotune.at, &c, (pdt_real_t)40.0,
                             g_avr_arena.autotune.w.work, need) == PDT_OK;
}

static bool at_run(at_run_t *r)
{
    pdt_autotune_t *at = &g_avr_arena.autotune.at;
    sim_plant_t *plant = &g_avr_arena.autotune.plant;
    memset(r, 0, sizeof *r);
    sim_rng64_t rng = sim_rng64_seed(23u);
    if (!at_start()) {
        return false;
    }
    const size_t depth = pdt_avr_stack_depth();
    t_stack_repaint();
    r->st = PDT_RUNNING;
    while (r->st == PDT_RUNNING && r->scans < 5000u) {
        const pdt_autotune_phase_t ph = pdt_autotune_phase(at);
        const pdt_real_t pv = read_pv(plant, &rng);
        pdt_real_t u;
        const uint64_t t0 = pdt_port_ticks();
        r->st = pdt_autotune_scan(at, pv, &u);
        const uint32_t dt = (uint32_t)(pdt_port_ticks() - t0);
        if ((unsigned)ph < AT_PHASES) {
            r->calls[ph]++;
            r->worst[ph] = dt > r->worst[ph] ? dt : r->worst[ph];
        }
        r->scans++;
        sim_plant_apply(plant, (double)u);
    }
    r->stack = pdt_avr_stack_used() - depth;
    return pdt_autotune_result(at, &g_avr_arena.autotune.w.res) == PDT_OK;
}

static void at_report(const at_run_t *r)
{
    const pdt_autotune_config_t *c = &g_avr_arena.autotune.at.cfg;
    const pdt_autotune_result_t *res = &g_avr_arena.autotune.w.res;
    static const char *const names[AT_PHASES] = {"",     "settle", "excite", "identify",
                                                 "tune", "",       ""};
    const double scan_cycles = (double)c->Ts * (double)pdt_port_ticks_per_second();
    for (unsigned ph = 1u; ph <= 4u; ph++) {
        tline_t l;
        tl_init(&l);
        TL_STR(&l, "autotune FOPDT: worst pdt_autotune_scan in ");
        tl_str(&l, names[ph]);
        TL_STR(&l, " ");
        tl_uint(&l, r->worst[ph]);
        TL_STR(&l, " cycles (");
        tl_num(&l, 100.0 * (double)r->worst[ph] / scan_cycles, 3);
        TL_STR(&l, "% of the scan period; ");
        tl_uint(&l, r->calls[ph]);
        TL_STR(&l, " calls)");
        t_info(&l);
    }
    tline_t l;
    tl_init(&l);
    TL_STR(&l, "autotune FOPDT: ");
    tl_uint(&l, res->ident.evaluations);
    TL_STR(&l, " evaluations in ");
    tl_uint(&l, r->scans);
    TL_STR(&l, " scans; workspace ");
    tl_uint(&l, pdt_autotune_workspace_size(c));
    TL_STR(&l, " + object ");
    tl_uint(&l, sizeof(pdt_autotune_t));
    TL_STR(&l, " bytes, stack ");
    tl_uint(&l, r->stack);
    TL_STR(&l, " bytes");
    t_info(&l);
}

/* K, tau 3 %, Td 3 % of tau; SIMC's PI from the true model: Kc = tau /
 * (K 2 Td) within 6 %, tauI = min(tau, 8 Td) within 3 %; Ms at most 2.
 * Not inlined: its line buffers stay off the stack while the scans run. */
static __attribute__((noinline)) int at_verdict(const at_run_t *r, bool ran)
{
    const pdt_autotune_result_t *res = &g_avr_arena.autotune.w.res;
    bool ok = ran && r->st == PDT_OK && res->has_gains && res->ident.model.kind == PDT_MODEL_FOPDT;
    tline_t l;
    tl_init(&l);
    TL_STR(&l, "autotune FOPDT K=2 tau=10 Td=3, PRBS, capacity ");
    tl_uint(&l, AVR_AT_CAPACITY);
    TL_STR(&l, ", Ts=1: ");
    if (!ok) {
        TL_STR(&l, "status ");
        tl_int(&l, r->st);
        return t_verdict(false, &l);
    }
    const pdt_model_fopdt_t *g = &res->ident.model.p.fopdt;
    const double eK = rel_err((double)g->K, 2.0);
    const double etau = rel_err((double)g->tau, 10.0);
    const double eTd = fabs((double)g->Td - 3.0) / 10.0;
    const double eKc = rel_err((double)res->tune.ideal.Kc, 10.0 / (2.0 * 6.0));
    const double etI = rel_err((double)res->tune.ideal.tauI, 10.0);
    ok = eK <= 0.03 && etau <= 0.03 && eTd <= 0.03 && eKc <= 0.06 && etI <= 0.03 &&
         (double)res->tune.fig.Ms <= 2.0;
    tl_fopdt(&l, g);
    TL_STR(&l, " PI Kc ");
    tl_num(&l, (double)res->tune.ideal.Kc, 4);
    TL_STR(&l, " tauI ");
    tl_num(&l, (double)res->tune.ideal.tauI, 4);
    TL_STR(&l, " Ms ");
    tl_num(&l, (double)res->tune.fig.Ms, 3);
    const int failed = t_verdict(ok, &l);
    at_report(r);
    return failed;
}

int avr_check_autotune(void)
{
    at_run_t r;
    const bool ran = at_run(&r);
    return at_verdict(&r, ran);
}
