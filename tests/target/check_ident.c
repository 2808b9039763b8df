/*
 * Identification on the target: records of a FOPDT and a SOPDT plant are
 * simulated here with pdt_discrete_simulate, given deterministic noise, and
 * identified with pdt_identify; the models must land within the host
 * tests' tolerances (tests/test_ident.c uses the same plants, inputs and
 * noise). Also measures the work of one cost evaluation at N = 2000 and of
 * each identification in port ticks (instructions under QEMU -icount).
 */
#include <math.h>
#include <string.h>

#include "target_checks.h"
#include "sim_process.h"
#include "target_util.h"

#include "pdt_port.h"
#include "pdt_port_target.h"
#include "target_config.h"

/* The identification's memory is the shared arena's (target_config.h);
 * the cost work's record of COST_N samples has its own (the full program
 * only). The records: input deviation into u, the model's response into
 * y, then both completed in place. */
#define g_ctx  (t_arena.ident.ctx)
#define g_work (t_arena.ident.work)

/* ---- Data (as tests/test_ident.c makes it) ----------------------------- */

/* Random binary deviation of +-amp: 0 for `quiet` samples, then a level
 * held `hold` samples, flipped with probability 1/2 at each change. */
static void make_prbs(pdt_real_t *g_dev, size_t n, size_t quiet, size_t hold, uint32_t seed,
                      double amp)
{
    sim_rng64_t s = sim_rng64_seed(seed);
    double level = 1.0;
    for (size_t k = 0; k < n; k++) {
        if (k < quiet) {
            g_dev[k] = (pdt_real_t)0.0;
            continue;
        }
        if ((k - quiet) % hold == 0u && sim_rng64_coin(&s) != 0) {
            level = -level;
        }
        g_dev[k] = (pdt_real_t)(amp * level);
    }
}

typedef struct record {
    pdt_model_t m;
    double Ts;
    size_t n;
    double u0, y0;
    double snr_db;
    uint32_t noise_seed;
    double noise_sd; /* set by make_record */
} record_t;

/* u = u0 + the deviation u holds, y = y0 + the model's response + noise
 * at snr_db. */
static bool make_record(record_t *r, pdt_real_t *g_u, pdt_real_t *g_y)
{
    pdt_discrete_t d;
    const pdt_real_t *g_dev = g_u;
    const pdt_real_t *g_sim = g_y;
    if (pdt_discrete_init(&r->m, (pdt_real_t)r->Ts, &d) != PDT_OK ||
        pdt_discrete_simulate(&d, g_u, r->n, g_y) != PDT_OK) {
        return false;
    }
    double mean = 0.0;
    for (size_t k = 0; k < r->n; k++) {
        mean += (double)g_sim[k];
    }
    mean /= (double)r->n;
    double var = 0.0;
    for (size_t k = 0; k < r->n; k++) {
        double e = (double)g_sim[k] - mean;
        var += e * e;
    }
    double sd = r->snr_db > 0.0 ? sqrt(var / (double)r->n) * pow(10.0, -r->snr_db / 20.0) : 0.0;
    r->noise_sd = sd;
    sim_rng64_t s = sim_rng64_seed(r->noise_seed);
    for (size_t k = 0; k < r->n; k++) {
        g_u[k] = (pdt_real_t)(r->u0 + (double)g_dev[k]);
        g_y[k] = (pdt_real_t)(r->y0 + (double)g_sim[k] + sd * sim_rng64_normal(&s));
    }
    return true;
}

static void line_ticks(tline_t *l, uint64_t ticks)
{
    tl_uint(l, ticks);
    tl_str(l, " ticks = ");
    tl_uint(l, t_ticks_to_instructions(ticks));
    tl_str(l, " instructions");
}

/* pdt_identify on the arena's record with exactly the workspace its size query asks
 * for; reports the work in ticks and the stack it used in bytes. */
static pdt_status_t identify(pdt_model_kind_t kind, const record_t *r, pdt_ident_result_t *res,
                             uint64_t *ticks, size_t *stack)
{
    pdt_ident_config_t cfg;
    pdt_ident_config_default(&cfg);
    cfg.model = kind;
    cfg.Ts = (pdt_real_t)r->Ts;
    cfg.no_screen = TARGET_LEAN != 0;
    cfg.refuse_missing = TARGET_LEAN != 0;
    pdt_ident_data_t data = {t_arena.ident.u, t_arena.ident.y, r->n};
    size_t need = pdt_ident_workspace_size(&cfg, r->n);
    if (need == 0u || need > sizeof g_work) {
        return PDT_ERR_NOMEM;
    }
    size_t depth = pdt_port_stack_depth();
    t_stack_repaint();
    uint64_t t0 = pdt_port_ticks();
    pdt_status_t st = pdt_identify(&g_ctx, &cfg, &data, g_work, need, res);
    *ticks = pdt_port_ticks() - t0;
    *stack = pdt_port_stack_used() - depth;
    return st;
}

/* ---- FOPDT ------------------------------------------------------------- */

/* Host test's tolerances at 30 dB: gain 1.5 %, tau 2 %, Td 2 % of tau,
 * fit 95 %, output level 0.5 % of the swing. */
static int check_fopdt(void)
{
    record_t r = {model_fopdt(2.0, 12.0, 4.37), 1.0, TARGET_IDENT_N, 0.0, 0.0, 30.0, 99u, 0.0};
    pdt_ident_result_t res;
    uint64_t ticks = 0;
    size_t stack = 0;
    make_prbs(t_arena.ident.u, r.n, 10u, 8u, 7u, 1.0);
    bool ok = make_record(&r, t_arena.ident.u, t_arena.ident.y);
    pdt_status_t st = ok ? identify(PDT_MODEL_FOPDT, &r, &res, &ticks, &stack) : PDT_ERR_ARG;
    ok = ok && st == PDT_OK && res.model.kind == PDT_MODEL_FOPDT;
    double eK = 1.0, etau = 1.0, eTd = 1.0, ey0 = 1.0;
    if (ok) {
        const pdt_model_fopdt_t *g = &res.model.p.fopdt;
        eK = rel_err((double)g->K, 2.0);
        etau = rel_err((double)g->tau, 12.0);
        eTd = fabs((double)g->Td - 4.37) / 12.0;
        ey0 = fabs((double)res.y0 - r.y0) / 2.0;
        ok = eK <= 0.015 && etau <= 0.02 && eTd <= 0.02 && ey0 <= 0.005 && (double)res.fit >= 95.0;
    }
    tline_t l;
    tl_init(&l);
    tl_str(&l, "identify FOPDT K=2 tau=12 Td=4.37, n=");
    tl_uint(&l, r.n);
    tl_str(&l, ", 30 dB: ");
    if (st != PDT_OK) {
        tl_str(&l, pdt_status_str(st));
        return t_verdict(false, &l);
    }
    tl_fopdt(&l, &res.model.p.fopdt);
    tl_str(&l, " fit ");
    tl_num(&l, (double)res.fit, 4);
    tl_str(&l, "%; errors K ");
    tl_num(&l, eK, 2);
    tl_str(&l, " tau ");
    tl_num(&l, etau, 2);
    tl_str(&l, " Td ");
    tl_num(&l, eTd, 2);
    tl_str(&l, " tau (max 0.015, 0.02, 0.02)");
    int failed = t_verdict(ok, &l);
    tl_init(&l);
    tl_str(&l, "identify FOPDT n=");
    tl_uint(&l, r.n);
    tl_str(&l, ": ");
    tl_uint(&l, res.evaluations);
    tl_str(&l, " evaluations, ");
    tl_uint(&l, res.generations);
    tl_str(&l, " generations, ");
    line_ticks(&l, ticks);
    tl_str(&l, ", stack ");
    tl_uint(&l, stack);
    tl_str(&l, " bytes");
    t_info(&l);
    return failed;
}

/* ---- SOPDT ------------------------------------------------------------- */

/* Host test's tolerances at 30 dB: gain 1.5 %, wn and zeta 4 %, Td 0.05 /
 * wn, fit 90 %, and the time constants T1 3 %, T2 10 %. */
static int check_sopdt(void)
{
    record_t r = {
        model_sopdt_tc(2.0, 10.0, 2.0, 3.3), 0.5, TARGET_IDENT_N, 10.0, 50.0, 30.0, 5u, 0.0};
    pdt_ident_result_t res;
    pdt_model_natural_t g, w;
    pdt_model_tc_t gtc;
    uint64_t ticks = 0;
    size_t stack = 0;
    make_prbs(t_arena.ident.u, r.n, 10u, 12u, 11u, 2.0);
    bool ok = make_record(&r, t_arena.ident.u, t_arena.ident.y) &&
              pdt_model_sopdt_to_natural(&r.m.p.sopdt, &w) == PDT_OK;
    pdt_status_t st = ok ? identify(PDT_MODEL_SOPDT, &r, &res, &ticks, &stack) : PDT_ERR_ARG;
    ok = ok && st == PDT_OK && res.model.kind == PDT_MODEL_SOPDT &&
         pdt_model_sopdt_to_natural(&res.model.p.sopdt, &g) == PDT_OK &&
         pdt_model_sopdt_to_tc(&res.model.p.sopdt, &gtc) == PDT_OK && !gtc.complex;
    double eK = 1.0, ewn = 1.0, ez = 1.0, eTd = 1.0, eT1 = 1.0, eT2 = 1.0;
    if (ok) {
        eK = rel_err((double)g.K, (double)w.K);
        ewn = rel_err((double)g.wn, (double)w.wn);
        ez = rel_err((double)g.zeta, (double)w.zeta);
        eTd = fabs((double)g.Td - (double)w.Td) * (double)w.wn;
        eT1 = rel_err((double)gtc.T1, 10.0);
        eT2 = rel_err((double)gtc.T2, 2.0);
        ok = eK <= 0.015 && ewn <= 0.04 && ez <= 0.04 && eTd <= 0.05 && eT1 <= 0.03 &&
             eT2 <= 0.10 && (double)res.fit >= 90.0;
    }
    tline_t l;
    tl_init(&l);
    tl_str(&l, "identify SOPDT K=2 T1=10 T2=2 Td=3.3, n=");
    tl_uint(&l, r.n);
    tl_str(&l, ", 30 dB: ");
    if (!ok && (st != PDT_OK || res.model.kind != PDT_MODEL_SOPDT)) {
        tl_str(&l, pdt_status_str(st));
        return t_verdict(false, &l);
    }
    tl_tc(&l, &gtc);
    tl_str(&l, " fit ");
    tl_num(&l, (double)res.fit, 4);
    tl_str(&l, "%; errors K ");
    tl_num(&l, eK, 2);
    tl_str(&l, " wn ");
    tl_num(&l, ewn, 2);
    tl_str(&l, " zeta ");
    tl_num(&l, ez, 2);
    tl_str(&l, " Td ");
    tl_num(&l, eTd, 2);
    tl_str(&l, "/wn (max 0.015, 0.04, 0.04, 0.05)");
    int failed = t_verdict(ok, &l);
    tl_init(&l);
    tl_str(&l, "identify SOPDT n=");
    tl_uint(&l, r.n);
    tl_str(&l, ": ");
    tl_uint(&l, res.evaluations);
    tl_str(&l, " evaluations, ");
    tl_uint(&l, res.generations);
    tl_str(&l, " generations, ");
    line_ticks(&l, ticks);
    tl_str(&l, ", stack ");
    tl_uint(&l, stack);
    tl_str(&l, " bytes");
    t_info(&l);
    return failed;
}

int target_check_ident(void)
{
    return check_fopdt() + check_sopdt();
}

/* ---- Cost evaluation at N = 2000 --------------------------------------- */

#if !PDT_TARGET_SMALL

#define COST_N      2000u
#define COST_REPEAT 10u

static pdt_real_t g_cost_work[PDT_COST_WORKSPACE_SIZE(COST_N) / sizeof(pdt_real_t)];
static pdt_real_t g_u[COST_N];
static pdt_real_t g_y[COST_N];
static pdt_real_t g_sim[COST_N];

/* Times COST_REPEAT evaluations of one kind on the SOPDT record of
 * COST_N samples and reports the ticks of one; the value goes to *value.
 * SIMULATION: for the true model the cost is the noise power, within a
 * factor 2 of sd^2. COMBINED: the sum of that time cost (ct) and Cf
 * (pdt_cost_frequency), to rounding. The profile, minimised over the gain
 * as well, may only be lower. */
static int measure_cost(pdt_cost_kind_t kind, const char *name, const record_t *r, double ct,
                        double *value)
{
    pdt_cost_config_t cfg;
    pdt_cost_t c;
    pdt_real_t v = 0;
    pdt_real_t cf = 0;
    pdt_cost_profile_t prof;
    memset(&prof, 0, sizeof prof);
    pdt_cost_config_default(&cfg);
    cfg.Ts = (pdt_real_t)r->Ts;
    cfg.u0 = (pdt_real_t)r->u0;
    cfg.y0 = (pdt_real_t)r->y0;
    cfg.kind = kind;
    cfg.whole_record = true;
    cfg.use_frequency = kind == PDT_COST_COMBINED;
    size_t ws = pdt_cost_workspace_size(&cfg, r->n);
    bool ok = ws <= sizeof g_cost_work &&
              pdt_cost_init(&c, &cfg, g_u, g_y, r->n, g_cost_work, ws) == PDT_OK;
    uint64_t t_eval = 0, t_prof = 0;
    size_t stack_eval = 0, stack_prof = 0;
    if (ok) {
        uint64_t t0 = pdt_port_ticks();
        for (unsigned i = 0; i < COST_REPEAT; i++) {
            ok = pdt_cost_eval(&c, &r->m, &v) == PDT_OK && ok;
        }
        t_eval = (pdt_port_ticks() - t0) / COST_REPEAT;
        t0 = pdt_port_ticks();
        for (unsigned i = 0; i < COST_REPEAT; i++) {
            ok =
                pdt_cost_profile(&c, &r->m, (pdt_real_t)0, (pdt_real_t)0, g_sim, &prof) == PDT_OK &&
                ok;
        }
        t_prof = (pdt_port_ticks() - t0) / COST_REPEAT;
        size_t depth = pdt_port_stack_depth();
        t_stack_repaint();
        ok = pdt_cost_eval(&c, &r->m, &v) == PDT_OK && ok;
        stack_eval = pdt_port_stack_used() - depth;
        t_stack_repaint();
        ok =
            pdt_cost_profile(&c, &r->m, (pdt_real_t)0, (pdt_real_t)0, g_sim, &prof) == PDT_OK && ok;
        stack_prof = pdt_port_stack_used() - depth;
    }
    tline_t l;
    tl_init(&l);
    tl_str(&l, "cost ");
    tl_str(&l, name);
    tl_str(&l, " at N=2000 of the true SOPDT: ");
    tl_num(&l, (double)v, 4);
    if (kind == PDT_COST_COMBINED) {
        ok = ok && pdt_cost_frequency(&c, &r->m, &cf) == PDT_OK;
        double e = rel_err((double)v, ct + (double)cf);
        ok = ok && e <= 1e-4;
        tl_str(&l, " = Ct + Cf to ");
        tl_num(&l, e, 2);
        tl_str(&l, " (max 1e-4)");
    } else {
        double ratio = (double)v / (r->noise_sd * r->noise_sd);
        ok = ok && ratio >= 0.5 && ratio <= 2.0;
        tl_str(&l, " = ");
        tl_num(&l, ratio, 3);
        tl_str(&l, " noise powers (0.5 to 2)");
    }
    ok = ok && (double)prof.cost <= (double)v * (1.0 + 1e-4);
    tl_str(&l, ", profiled ");
    tl_num(&l, (double)prof.cost, 4);
    int failed = t_verdict(ok, &l);
    tl_init(&l);
    tl_str(&l, "one pdt_cost_eval ");
    tl_str(&l, name);
    tl_str(&l, " at N=2000: ");
    line_ticks(&l, t_eval);
    tl_str(&l, ", stack ");
    tl_uint(&l, stack_eval);
    tl_str(&l, " bytes");
    t_info(&l);
    tl_init(&l);
    tl_str(&l, "one pdt_cost_profile ");
    tl_str(&l, name);
    tl_str(&l, " at N=2000: ");
    line_ticks(&l, t_prof);
    tl_str(&l, ", stack ");
    tl_uint(&l, stack_prof);
    tl_str(&l, " bytes");
    t_info(&l);
    *value = (double)v;
    return failed;
}

int target_check_cost_work(void)
{
    record_t r = {model_sopdt_tc(2.0, 10.0, 2.0, 3.3), 0.5, COST_N, 10.0, 50.0, 30.0, 5u, 0.0};
    make_prbs(g_u, r.n, 10u, 12u, 11u, 2.0);
    if (!make_record(&r, g_u, g_y)) {
        tline_t l;
        tl_init(&l);
        tl_str(&l, "cost at N=2000: record not made");
        return t_verdict(false, &l);
    }
    double ct = 0.0;
    double v = 0.0;
    int failed = measure_cost(PDT_COST_SIMULATION, "SIMULATION", &r, 0.0, &ct);
    return failed + measure_cost(PDT_COST_COMBINED, "COMBINED", &r, ct, &v);
}

#endif /* !PDT_TARGET_SMALL */
