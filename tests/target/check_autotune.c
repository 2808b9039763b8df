/*
 * Autotune on the target: a FOPDT and a SOPDT plant simulated scan by scan
 * by the shared simulator (tools/sim/sim_process.h: exact at the
 * scan period, deterministic sensor noise), each tuned by one complete
 * pdt_autotune run with a PRBS experiment and a record of 600 samples (the
 * configuration docs/autotune.md tabulates). Checks the model and the gains against the
 * plant, and reports the worst-case work of one pdt_autotune_scan call in
 * each phase, in port ticks and instructions (QEMU -icount), and the stack
 * the calls used.
 */
#include <math.h>
#include <string.h>

#include "target_checks.h"
#include "sim_process.h"
#include "target_util.h"

#include "pdt_port.h"
#include "pdt_port_target.h"
#include "target_config.h"

/* Registered in target_main.c. */
int target_check_autotune(void);

#define AT_CAPACITY TARGET_AT_CAPACITY

/* The shared arena's (target_config.h). */
#define g_at_work (t_arena.autotune.work)
#define g_at      (t_arena.autotune.at)
#define g_process (t_arena.autotune.process)

/* A run's record and the configuration live in the arena as well: on
 * the Cortex-M0 their 1 KiB is more than the stack can spare. */
typedef target_at_run_t at_run_t;

/* One autotune to the end, timing every call. The stack is painted once
 * and read at the end: the deepest of all the calls (and of the plant's
 * small helpers, which sit at the same depth). */
static bool at_run(const pdt_autotune_config_t *c, sim_process_t *p, at_run_t *r)
{
    memset(r, 0, sizeof *r);
    size_t need = pdt_autotune_workspace_size(c);
    if (need == 0u || need > sizeof g_at_work ||
        pdt_autotune_init(&g_at, c, (pdt_real_t)p->plant.u0, g_at_work, need) != PDT_OK) {
        return false;
    }
    size_t depth = pdt_port_stack_depth();
    t_stack_repaint();
    r->st = PDT_RUNNING;
    while (r->st == PDT_RUNNING && r->scans < 100000u) {
        pdt_autotune_phase_t ph = pdt_autotune_phase(&g_at);
        pdt_real_t pv = sim_process_pv(p);
        pdt_real_t u;
        bool counting = ph == PDT_AUTOTUNE_IDENTIFY && g_at.ident_started;
        /* After the searches: the validation, the order's choice. */
        const bool after =
            ph == PDT_AUTOTUNE_IDENTIFY && g_at.stage >= (g_at.cfg.order_auto ? 2u : 1u);
        /* The call that begins an identification (pdt_ident_init). */
        const bool begins = ph == PDT_AUTOTUNE_IDENTIFY && !after && !g_at.ident_started;
        uint64_t s0 = counting ? g_at.ident.samples : 0u;
        uint64_t t0 = pdt_port_ticks();
        r->st = pdt_autotune_scan(&g_at, pv, &u);
        uint64_t dt = pdt_port_ticks() - t0;
        if (counting) {
            /* Whole-record evaluations' worth (a coarse one is a D-th). */
            const uint64_t n = g_at.ident.data.n;
            const uint32_t de = (uint32_t)((g_at.ident.samples - s0 + n - 1u) / n);
            r->max_evals = de > r->max_evals ? de : r->max_evals;
            if (g_at.ident.samples != s0 && g_at.ident_started && dt > r->worst_search) {
                r->worst_search = dt;
            }
        }
        if (after && dt > r->worst_valid) {
            r->worst_valid = dt;
        }
        if (begins && dt > r->worst_init) {
            r->worst_init = dt;
        }
        if (ph == PDT_AUTOTUNE_IDENTIFY && !begins && dt > r->worst_step) {
            r->worst_step = dt;
        }
        if ((unsigned)ph < 7u) {
            r->calls[ph]++;
            if (dt > r->worst[ph]) {
                r->worst[ph] = dt;
            }
        }
        r->scans++;
        sim_process_apply(p, u);
    }
    r->stack = pdt_port_stack_used() - depth;
    return pdt_autotune_result(&g_at, &r->res) == PDT_OK;
}

static void at_config(pdt_autotune_config_t *c, double Ts, pdt_model_kind_t kind, uint32_t hold,
                      double amp)
{
    pdt_autotune_config_default(c);
    c->Ts = (pdt_real_t)Ts;
    c->capacity = AT_CAPACITY;
    c->excite.kind = PDT_EXCITE_PRBS;
    c->excite.amplitude = (pdt_real_t)amp;
    /* The small program's record holds 112 samples: a PRBS of 5 bits held 3 scans. */
    c->excite.prbs_bits = PDT_TARGET_SMALL ? 5u : 7u;
    c->excite.prbs_hold = hold;
    c->ident.no_screen = TARGET_LEAN != 0; /* target_config.h */
    c->ident.refuse_missing = TARGET_LEAN != 0;
    c->u_min = (pdt_real_t)0.0;
    c->u_max = (pdt_real_t)100.0;
    c->pv_min = (pdt_real_t)-100.0;
    c->pv_max = (pdt_real_t)200.0;
    /* Not used by the default order choice, which the checks below expect
     * to keep the plant's order. */
    c->ident.model = kind;
}

static void at_report(const char *name, const at_run_t *r)
{
    static const char *const names[7] = {"", "settle", "excite", "identify", "tune", "", ""};
    for (unsigned ph = 1u; ph <= 4u; ph++) {
        tline_t l;
        tl_init(&l);
        tl_str(&l, "autotune ");
        tl_str(&l, name);
        tl_str(&l, ": worst pdt_autotune_scan in ");
        tl_str(&l, names[ph]);
        tl_str(&l, " ");
        tl_uint(&l, t_ticks_to_instructions(r->worst[ph]));
        tl_str(&l, " instructions (");
        tl_uint(&l, r->calls[ph]);
        tl_str(&l, " calls)");
        t_info(&l);
    }
    tline_t lv;
    tl_init(&lv);
    tl_str(&lv, "autotune ");
    tl_str(&lv, name);
    tl_str(&lv, ": worst pdt_autotune_scan in identify after the searches (validation, order) ");
    tl_uint(&lv, t_ticks_to_instructions(r->worst_valid));
    tl_str(&lv, " instructions");
    t_info(&lv);
    tline_t li;
    tl_init(&li);
    tl_str(&li, "autotune ");
    tl_str(&li, name);
    tl_str(&li, ": worst pdt_autotune_scan in identify that begins an identification ");
    tl_str(&li, "(pdt_ident_init) ");
    tl_uint(&li, t_ticks_to_instructions(r->worst_init));
    tl_str(&li, " instructions, of the others ");
    tl_uint(&li, t_ticks_to_instructions(r->worst_step));
    t_info(&li);
    tline_t l;
    tl_init(&l);
    tl_str(&l, "autotune ");
    tl_str(&l, name);
    tl_str(&l, ": ");
    tl_uint(&l, r->res.ident.evaluations);
    tl_str(&l, " evaluations, at most ");
    tl_uint(&l, r->max_evals);
    tl_str(&l, " per call, the slowest such call ");
    tl_uint(&l, t_ticks_to_instructions(r->worst_search));
    tl_str(&l, " instructions; ");
    tl_uint(&l, r->scans);
    tl_str(&l, " scans; stack ");
    tl_uint(&l, r->stack);
    tl_str(&l, " bytes; workspace ");
    tl_uint(&l, pdt_autotune_workspace_size(&g_at.cfg));
    tl_str(&l, " bytes");
    t_info(&l);
}

/* The work of one pdt_autotune_scan, at most TARGET_SCAN_BOUND
 * instructions a call in the identification (every stage of
 * pdt_ident_step, the validation, the order's choice, the call that
 * begins an identification with pdt_ident_init) and the tuning: the
 * Cortex-M4F's float build; elsewhere reported only. */
static int at_bound(const char *name, const at_run_t *r)
{
#if defined(TARGET_SCAN_BOUND) && !PDT_REAL_DOUBLE
    const uint64_t tune = t_ticks_to_instructions(r->worst[PDT_AUTOTUNE_TUNE]);
    const uint64_t ident = t_ticks_to_instructions(r->worst_step);
    const uint64_t init = t_ticks_to_instructions(r->worst_init);
    tline_t l;
    tl_init(&l);
    tl_str(&l, "autotune ");
    tl_str(&l, name);
    tl_str(&l, ": worst scan of the tuning ");
    tl_uint(&l, tune);
    tl_str(&l, ", of the identification ");
    tl_uint(&l, ident);
    tl_str(&l, ", of its init ");
    tl_uint(&l, init);
    tl_str(&l, " instructions (max ");
    tl_uint(&l, TARGET_SCAN_BOUND);
    tl_str(&l, ")");
    return t_verdict(
        tune <= TARGET_SCAN_BOUND && ident <= TARGET_SCAN_BOUND && init <= TARGET_SCAN_BOUND, &l);
#else
    (void)name;
    (void)r;
    return 0;
#endif
}

static void at_gains(tline_t *l, const at_run_t *r)
{
    tl_str(l, " fit ");
    tl_num(l, (double)r->res.ident.fit, 4);
    tl_str(l, "%; PI Kc ");
    tl_num(l, (double)r->res.tune.ideal.Kc, 4);
    tl_str(l, " tauI ");
    tl_num(l, (double)r->res.tune.ideal.tauI, 4);
    tl_str(l, " Ms ");
    tl_num(l, (double)r->res.tune.fig.Ms, 3);
}

/* Host test's tolerances: K, tau 3 %, Td 3 % of tau. The gains are SIMC's
 * PI from the true model: Kc = tau / (K 2 Td), tauI = min(tau, 8 Td). */
static int check_fopdt(void)
{
    pdt_autotune_config_t *const c = &t_arena.autotune.cfg;
    at_config(c, 0.5, PDT_MODEL_FOPDT, PDT_TARGET_SMALL ? 3u : 4u, 3.0);
    const pdt_model_t m = model_fopdt(2.0, 10.0, 3.0);
    at_run_t *const r = &t_arena.autotune.run;
    bool ok = sim_process_init(&g_process, &m, (double)c->Ts, 40.0, 20.0, 0.05, 23u) == 0 &&
              at_run(c, &g_process, r) && r->st == PDT_OK && r->res.has_gains &&
              r->res.ident.model.kind == PDT_MODEL_FOPDT;
    tline_t l;
    tl_init(&l);
    tl_str(&l, "autotune FOPDT K=2 tau=10 Td=3, PRBS, capacity ");
    tl_uint(&l, AT_CAPACITY);
    tl_str(&l, ": ");
    if (!ok) {
        tl_str(&l, pdt_status_str(r->st));
        return t_verdict(false, &l);
    }
    const pdt_model_fopdt_t *g = &r->res.ident.model.p.fopdt;
    double eK = rel_err((double)g->K, 2.0);
    double etau = rel_err((double)g->tau, 10.0);
    double eTd = fabs((double)g->Td - 3.0) / 10.0;
    double eKc = rel_err((double)r->res.tune.ideal.Kc, 10.0 / (2.0 * 6.0));
    double etI = rel_err((double)r->res.tune.ideal.tauI, 10.0);
    ok = eK <= 0.03 && etau <= 0.03 && eTd <= 0.03 && eKc <= 0.06 && etI <= 0.03 &&
         r->max_evals <= c->evals_per_scan && (double)r->res.tune.fig.Ms <= 2.0;
    tl_fopdt(&l, g);
    at_gains(&l, r);
    int failed = t_verdict(ok, &l);
    at_report("FOPDT", r);
    return failed + at_bound("FOPDT", r);
}

/* K = 1.5, T1 = 8, T2 = 3, Td = 2: DC gain 3 %, Td within 0.3 s. */
static int check_sopdt(void)
{
    pdt_autotune_config_t *const c = &t_arena.autotune.cfg;
    at_config(c, 0.5, PDT_MODEL_SOPDT, PDT_TARGET_SMALL ? 3u : 4u, 3.0);
    const pdt_model_t m = model_sopdt_tc(1.5, 8.0, 3.0, 2.0);
    at_run_t *const r = &t_arena.autotune.run;
    pdt_model_tc_t gtc;
    bool ok = sim_process_init(&g_process, &m, (double)c->Ts, 50.0, 10.0, 0.03, 5u) == 0 &&
              at_run(c, &g_process, r) && r->st == PDT_OK && r->res.has_gains &&
              r->res.ident.model.kind == PDT_MODEL_SOPDT &&
              pdt_model_sopdt_to_tc(&r->res.ident.model.p.sopdt, &gtc) == PDT_OK;
    tline_t l;
    tl_init(&l);
    tl_str(&l, "autotune SOPDT K=1.5 T1=8 T2=3 Td=2, PRBS, capacity ");
    tl_uint(&l, AT_CAPACITY);
    tl_str(&l, ": ");
    if (!ok) {
        tl_str(&l, pdt_status_str(r->st));
        return t_verdict(false, &l);
    }
    double eK = rel_err((double)gtc.K, 1.5);
    double eT = rel_err((double)gtc.T1 + (double)gtc.T2, 11.0);
    double eTd = fabs((double)gtc.Td - 2.0);
    ok = !gtc.complex && eK <= 0.03 && eT <= 0.05 && eTd <= 0.3 &&
         r->max_evals <= c->evals_per_scan && (double)r->res.tune.fig.Ms <= 2.0;
    tl_tc(&l, &gtc);
    at_gains(&l, r);
    int failed = t_verdict(ok, &l);
    at_report("SOPDT", r);
    return failed + at_bound("SOPDT", r);
}

int target_check_autotune(void)
{
    return check_fopdt() + check_sopdt();
}
