/*
 * Host driver of the autotune benchmark (tools/bench/autotune_bench.py):
 * runs the library's autotune and relay test against a simulated true
 * plant, and the library's half rule and tuning rules on known models. Not
 * part of the library: stdio and malloc are fine here.
 *
 * One job per run, read from stdin as whitespace-separated tokens; the
 * answer is printed as `key value` lines.
 *
 *   autotune PLANT NOISE AT        the autotune, one call per scan
 *   at PLANT NOISE AT2             the autotune with any experiment and
 *                                  the evidence options, then its gains
 *                                  in closed loop on the same plant
 *   loop PLANT Kc tauI tauD Tf n_sp n_load
 *                                  the closed loop alone
 *   relay    PLANT NOISE RELAY     a relay test with pdt_excite, then
 *                                  Ziegler-Nichols PI and PID gains
 *   model    KIND P1 P2 P3 [P4]    SIMC PI and PID of a known model
 *                                  (1: K tau Td; 2: k a b Td, form (2))
 *   halfrule k NL lags.. NZ zeros.. theta0
 *                                  half-rule FOPDT and SOPDT, SIMC PI on
 *                                  the FOPDT and PID on the SOPDT
 *
 * PLANT: Ts n l, then Phi (n x n, row-major), Gb (n), Ga (n), C (n): the
 * exact zero-order-hold discretisation at the scan period Ts of a strictly
 * proper plant whose dead time is (l + f) Ts:
 *   x[k+1] = Phi x[k] + Gb u[k-l] + Ga u[k-l-1],   y[k] = C x[k]
 * (Gb carries the last (1 - f) Ts of the interval, Ga the first f Ts;
 * the script computes them), n at most SIM_PLANT_MAX_STATES. It runs on
 * the shared simulator (tools/sim/sim_plant.h), loaded with that
 * realisation. The process value read at scan k is y[k] + noise[k].
 * NOISE: std seed max_scans. White Gaussian noise of that standard
 * deviation (sim_rng64: splitmix64 and Box-Muller, the stream of
 * pdtsupport.rng.SplitMix64(seed)).
 * AT: decimation capacity settle amplitude t_on t_off u_min u_max pv_min
 * pv_max model(0 the library's default order, 1 FOPDT, 2 SOPDT) ident_seed
 * form(0 PI, 1 PID): the autotune's own rule is SIMC of that form.
 * RELAY: d eps skip cycles settle.
 * AT2: kind(0 relay, 1 PRBS, 2 step, 3 pulse) decimation capacity settle
 * tail amplitude(relay: d) p1 p2 u_min u_max pv_min pv_max ident_seed
 * form(0 PI, 1 PID) order(1 the library's default, 0 FOPDT, -1 SOPDT)
 * ms_robust fit_min relay_agree relay_eps relay_skip relay_cycles n_sp
 * n_load direct(relay: 1 for a process of negative gain) relay_settle. p1 p2:
 * pulse t_on t_off; step duration -; PRBS scans per chip, bits.
 * Closed loop (at, loop): a unit set-point step held n_sp scans, then a
 * unit load step at the plant input for n_load scans, noise-free.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pdt/pdt.h"
#include "sim_plant.h"
#include "sim_rng.h"

#define RL(x) ((pdt_real_t)(x))
#define MAXL  200000

typedef struct plant {
    double Ts;
    sim_plant_t sim;
    double *hist; /* the simulator's input history, l + 2 */
} plant_t;

typedef struct noise {
    double std;
    sim_rng64_t rng;
} noise_t;

static int rd(double *v)
{
    return scanf("%lf", v) == 1 ? 0 : -1;
}

static int rdl(long *v)
{
    return scanf("%ld", v) == 1 ? 0 : -1;
}

static void die(const char *what)
{
    fprintf(stderr, "autotune_driver: bad input (%s)\n", what);
    exit(2);
}

static void read_plant(plant_t *p)
{
    long n = 0, l = 0;
    double Phi[SIM_PLANT_MAX_STATES * SIM_PLANT_MAX_STATES];
    double Gb[SIM_PLANT_MAX_STATES], Ga[SIM_PLANT_MAX_STATES], C[SIM_PLANT_MAX_STATES];
    if (rd(&p->Ts) || rdl(&n) || rdl(&l) || n < 1 || n > (long)SIM_PLANT_MAX_STATES || l < 0 ||
        l > MAXL) {
        die("plant header");
    }
    for (long i = 0; i < n * n; i++) {
        if (rd(&Phi[i])) die("Phi");
    }
    for (long i = 0; i < n; i++) {
        if (rd(&Gb[i])) die("Gb");
    }
    for (long i = 0; i < n; i++) {
        if (rd(&Ga[i])) die("Ga");
    }
    for (long i = 0; i < n; i++) {
        if (rd(&C[i])) die("C");
    }
    p->hist = malloc((size_t)(l + 2) * sizeof(double));
    if (p->hist == NULL) die("memory");
    if (sim_plant_init_discrete(&p->sim, (size_t)n, (size_t)l, Phi, Gb, Ga, C, p->hist,
                                (size_t)(l + 2)) != 0) {
        die("plant");
    }
}

static double noise_next(noise_t *z)
{
    return z->std == 0.0 ? 0.0 : z->std * sim_rng64_normal(&z->rng);
}

static void read_noise(noise_t *z, long *max_scans)
{
    long seed = 0;
    if (rd(&z->std) || rdl(&seed) || rdl(max_scans) || z->std < 0.0 || *max_scans < 1) {
        die("noise");
    }
    z->rng = sim_rng64_seed((uint64_t)seed);
}

static void print_gains(const char *tag, const pdt_tune_gains_t *g)
{
    printf("%s_Kc %.9g\n%s_tauI %.9g\n%s_tauD %.9g\n%s_Tf %.9g\n", tag, (double)g->Kc, tag,
           (double)g->tauI, tag, (double)g->tauD, tag, (double)g->Tf);
}

static void print_model(const char *tag, const pdt_model_t *m)
{
    if (m->kind == PDT_MODEL_FOPDT) {
        printf("%s_kind 1\n%s_K %.9g\n%s_tau %.9g\n%s_Td %.9g\n", tag, tag, (double)m->p.fopdt.K,
               tag, (double)m->p.fopdt.tau, tag, (double)m->p.fopdt.Td);
    } else {
        printf("%s_kind 2\n%s_k %.9g\n%s_a %.9g\n%s_b %.9g\n%s_Td %.9g\n", tag, tag,
               (double)m->p.sopdt.k, tag, (double)m->p.sopdt.a, tag, (double)m->p.sopdt.b, tag,
               (double)m->p.sopdt.Td);
    }
}

/* SIMC gains of form `form` for model m, printed under tag with their
 * status; the limits as given. */
static void tune_print(const char *tag, const pdt_model_t *m, pdt_real_t fit, pdt_tune_form_t form,
                       pdt_real_t fit_min, pdt_real_t ms_max)
{
    pdt_tune_config_t tc;
    pdt_tune_config_default(&tc);
    tc.rule = PDT_TUNE_SIMC;
    tc.form = form;
    tc.fit_min = fit_min;
    tc.ms_max = ms_max;
    pdt_tune_result_t r;
    pdt_status_t st = pdt_tune_compute(m, fit, &tc, &r);
    printf("%s_status %d\n", tag, (int)st);
    if (st == PDT_OK) {
        print_gains(tag, &r.ideal);
        printf("%s_Ms_model %.9g\n", tag, (double)r.fig.Ms);
    } else if (st == PDT_ERR_POOR_FIT || st == PDT_ERR_MS_LIMIT || st == PDT_ERR_UNSTABLE) {
        /* The gains the limits refused, for the record. */
        tc.ms_max = RL(0.0);
        tc.fit_min = RL(-1.0);
        if (pdt_tune_compute(m, fit, &tc, &r) == PDT_OK) {
            char t2[64];
            snprintf(t2, sizeof t2, "%s_refused", tag);
            print_gains(t2, &r.ideal);
            printf("%s_Ms_model %.9g\n", t2, (double)r.fig.Ms);
        }
    }
}

/* Runs the autotune of cfg against the plant, one call per scan, until it
 * ends, and prints the common part of its result into r. Returns false
 * when init refused cfg (printed). */
static bool drive_autotune(plant_t *p, noise_t *z, long max_scans, const pdt_autotune_config_t *cfg,
                           pdt_autotune_result_t *r, pdt_status_t *st_out)
{
    size_t ws = pdt_autotune_workspace_size(cfg);
    void *work = malloc(ws ? ws : 1u);
    pdt_autotune_t at;
    pdt_status_t st = pdt_autotune_init(&at, cfg, RL(0.0), work, ws);
    printf("init_status %d\n", (int)st);
    if (st != PDT_OK) {
        free(work);
        return false;
    }
    /* The scans go on through the identification, which takes no process
     * time of its own beyond the scans it needs. */
    for (long k = 0; k < 50L * max_scans; k++) {
        double pv = sim_plant_output(&p->sim) + noise_next(z);
        pdt_real_t u;
        st = pdt_autotune_scan(&at, (pdt_real_t)pv, &u);
        sim_plant_apply(&p->sim, (double)u);
        if (st != PDT_RUNNING) break;
    }
    (void)pdt_autotune_result(&at, r);
    free(work);
    printf("status %d\nfailed_in %d\nscans %lu\nscans_experiment %lu\nsamples %lu\n", (int)st,
           (int)r->failed_in, (unsigned long)r->scans, (unsigned long)r->scans_experiment,
           (unsigned long)r->samples);
    printf("has_model %d\nhas_gains %d\n", (int)r->has_model, (int)r->has_gains);
    printf("shift %.9g\nrelay_spread %.9g\nrepeats %lu\ndrift %.9g\n", (double)r->shift,
           (double)r->relay_spread, (unsigned long)r->repeats, (double)r->drift);
    *st_out = st;
    return true;
}

static int run_autotune(void)
{
    plant_t p;
    noise_t z;
    long max_scans;
    read_plant(&p);
    read_noise(&z, &max_scans);
    double v[13];
    for (int i = 0; i < 13; i++) {
        if (rd(&v[i])) die("autotune config");
    }
    pdt_autotune_config_t cfg;
    pdt_autotune_config_default(&cfg);
    cfg.Ts = (pdt_real_t)p.Ts;
    cfg.decimation = (uint32_t)v[0];
    cfg.capacity = (size_t)v[1];
    cfg.settle = (uint32_t)v[2];
    pdt_excite_config_default(&cfg.excite, PDT_EXCITE_PULSE);
    cfg.excite.amplitude = (pdt_real_t)v[3];
    cfg.excite.t_on = (pdt_real_t)v[4];
    cfg.excite.t_off = (pdt_real_t)v[5];
    cfg.excite.count = 1u;
    cfg.u_min = (pdt_real_t)v[6];
    cfg.u_max = (pdt_real_t)v[7];
    cfg.pv_min = (pdt_real_t)v[8];
    cfg.pv_max = (pdt_real_t)v[9];
    cfg.max_scans = (uint32_t)max_scans;
    pdt_ident_config_default(&cfg.ident);
    if (v[10] != 0.0) {
        /* An order the run fixes; 0 keeps the library's default. */
        cfg.ident.model = v[10] == 1.0 ? PDT_MODEL_FOPDT : PDT_MODEL_SOPDT;
        cfg.order_auto = false;
    }
    cfg.ident.seed = (uint64_t)v[11];
    pdt_tune_config_default(&cfg.tune);
    cfg.tune.rule = PDT_TUNE_SIMC;
    cfg.tune.form = v[12] == 0.0 ? PDT_TUNE_PI : PDT_TUNE_PID;

    pdt_autotune_result_t r;
    pdt_status_t st;
    if (!drive_autotune(&p, &z, max_scans, &cfg, &r, &st)) {
        free(p.hist);
        return 0;
    }
    if (r.has_model) {
        print_model("model", &r.ident.model);
        printf("fit %.9g\nevaluations %lu\n", (double)r.ident.fit,
               (unsigned long)r.ident.evaluations);
        /* The form of cfg.tune.form: the autotune's own answer (its
         * detuning included); the other form by the rule alone on the
         * model the run identified, with the autotune's limits. */
        const char *own = cfg.tune.form == PDT_TUNE_PID ? "pid" : "pi";
        if (cfg.tune.form == PDT_TUNE_PID) {
            tune_print("pi", &r.ident.model, r.ident.fit, PDT_TUNE_PI, cfg.tune.fit_min,
                       cfg.tune.ms_max);
        } else {
            tune_print("pid", &r.ident.model, r.ident.fit, PDT_TUNE_PID, cfg.tune.fit_min,
                       cfg.tune.ms_max);
        }
        printf("%s_status %d\n", own, (int)(r.has_gains ? PDT_OK : st));
        if (r.has_gains) {
            print_gains(own, &r.tune.ideal);
            printf("%s_Ms_model %.9g\ndetune %.9g\n", own, (double)r.tune.fig.Ms, (double)r.detune);
        }
    }
    free(p.hist);
    return 0;
}

/* The closed loop on the true plant (noise-free, from rest): a unit
 * set-point step for n_sp scans, then a unit step added to the plant's
 * input for n_load scans. The ideal-form controller runs every scan: P and
 * I on the error, the derivative on the measurement through its filter
 * (exact first-order filter at the scan period). Prints IAE of each part,
 * the set-point overshoot (fraction of the step) and whether the loop
 * stayed bounded. */
static void closed_loop(plant_t *p, const pdt_tune_gains_t *g, long n_sp, long n_load)
{
    sim_plant_reset(&p->sim);
    double Kc = (double)g->Kc, tI = (double)g->tauI, tD = (double)g->tauD, Tf = (double)g->Tf;
    double I = 0.0, xf = 0.0, iae_sp = 0.0, iae_ld = 0.0, ymax = 0.0;
    double af = Tf > 0.0 ? 1.0 - exp(-p->Ts / Tf) : 1.0;
    int bounded = 1;
    for (long k = 0; k < n_sp + n_load; k++) {
        double y = sim_plant_output(&p->sim);
        if (!isfinite(y) || fabs(y) > 1e6) {
            bounded = 0;
            break;
        }
        double e = 1.0 - y;
        double ud = 0.0;
        if (tD > 0.0) {
            ud = Tf > 0.0 ? -tD * (y - xf) / Tf : -tD * (y - xf) / p->Ts;
            xf += af * (y - xf);
        }
        double u = Kc * (e + I + ud);
        I += p->Ts * e / tI;
        if (k < n_sp) {
            iae_sp += fabs(e) * p->Ts;
            if (y > ymax) ymax = y;
        } else {
            iae_ld += fabs(e) * p->Ts;
        }
        sim_plant_apply(&p->sim, u + (k >= n_sp ? 1.0 : 0.0));
    }
    printf("cl_bounded %d\n", bounded);
    if (bounded) {
        printf("cl_sp_iae %.9g\ncl_overshoot %.9g\ncl_load_iae %.9g\ncl_end_error %.9g\n", iae_sp,
               ymax > 1.0 ? ymax - 1.0 : 0.0, iae_ld, fabs(1.0 - sim_plant_output(&p->sim)));
    }
}

/* What an `at` run identified and validated, one "key value" a line. */
static void print_at_result(const pdt_autotune_result_t *r)
{
    if (r->has_relay) {
        printf("relay_Ku %.9g\nrelay_Pu %.9g\n", (double)r->relay.Ku, (double)r->relay.Pu);
    }
    if (r->has_model) {
        print_model("model", &r->ident.model);
        printf("fit %.9g\n", (double)r->ident.fit);
    }
    if (r->has_valid) {
        const pdt_validate_result_t *vr = &r->valid;
        printf("white %d\nindependent %d\nsigma %.9g\nbic %.9g\nbic_other %.9g\n", (int)vr->white,
               (int)vr->independent, (double)vr->sigma, (double)vr->bic, (double)r->bic_other);
        printf("white_stat %.9g\ncross_stat %.9g\ninflation %.9g\n", (double)vr->white_stat,
               (double)vr->cross_stat, (double)vr->inflation);
        for (uint32_t i = 0; i < vr->std.count; i++) {
            printf("std%u %.9g\n", (unsigned)i, (double)vr->std.std[i]);
        }
    }
}

/* The experiment of an `at` request: its kind's fields from v. */
static void at_experiment(pdt_autotune_config_t *cfg, pdt_excite_kind_t kind, const double *v)
{
    pdt_excite_config_default(&cfg->excite, kind);
    cfg->excite.amplitude = (pdt_real_t)v[5];
    switch (kind) {
    case PDT_EXCITE_PULSE:
        cfg->excite.t_on = (pdt_real_t)v[6];
        cfg->excite.t_off = (pdt_real_t)v[7];
        cfg->excite.count = 1u;
        break;
    case PDT_EXCITE_STEP:
        cfg->excite.duration = (pdt_real_t)v[6];
        break;
    case PDT_EXCITE_PRBS:
        cfg->excite.prbs_hold = (uint32_t)v[6];
        cfg->excite.prbs_bits = (uint32_t)v[7];
        break;
    default:
        cfg->excite.d = (pdt_real_t)v[5];
        cfg->excite.eps = (pdt_real_t)v[18];
        cfg->excite.relay_skip = (uint32_t)v[19];
        cfg->excite.relay_cycles = (uint32_t)v[20];
        cfg->excite.relay_settle = (pdt_real_t)v[24];
        cfg->excite.setpoint = RL(0.0);
        cfg->move = PDT_RECORD_MOVE_ANY;
        break;
    }
}

/* at: the autotune with any experiment and the evidence options, then its
 * gains in closed loop on the same plant. */
static int run_at(void)
{
    plant_t p;
    noise_t z;
    long max_scans;
    read_plant(&p);
    read_noise(&z, &max_scans);
    double v[25];
    for (int i = 0; i < 25; i++) {
        if (rd(&v[i])) die("at config");
    }
    static const pdt_excite_kind_t kinds[4] = {PDT_EXCITE_RELAY, PDT_EXCITE_PRBS, PDT_EXCITE_STEP,
                                               PDT_EXCITE_PULSE};
    int kind = (int)v[0];
    if (kind < 0 || kind > 3) die("experiment kind");
    pdt_autotune_config_t cfg;
    pdt_autotune_config_default(&cfg);
    cfg.Ts = (pdt_real_t)p.Ts;
    cfg.decimation = (uint32_t)v[1];
    cfg.capacity = (size_t)v[2];
    cfg.settle = (uint32_t)v[3];
    cfg.tail = (uint32_t)v[4];
    at_experiment(&cfg, kinds[kind], v);
    cfg.u_min = (pdt_real_t)v[8];
    cfg.u_max = (pdt_real_t)v[9];
    cfg.pv_min = (pdt_real_t)v[10];
    cfg.pv_max = (pdt_real_t)v[11];
    cfg.max_scans = (uint32_t)max_scans;
    cfg.ident.seed = (uint64_t)v[12];
    cfg.tune.rule = PDT_TUNE_SIMC;
    cfg.tune.form = v[13] == 0.0 ? PDT_TUNE_PI : PDT_TUNE_PID;
    if (v[14] != 1.0) {
        /* An order the run fixes; 1 keeps the library's default. */
        cfg.ident.model = v[14] == 0.0 ? PDT_MODEL_FOPDT : PDT_MODEL_SOPDT;
        cfg.order_auto = false;
    }
    cfg.ms_robust = (pdt_real_t)v[15];
    cfg.tune.fit_min = (pdt_real_t)v[16];
    cfg.relay_agree = (pdt_real_t)v[17];
    long n_sp = (long)v[21], n_load = (long)v[22];
    if (kinds[kind] == PDT_EXCITE_RELAY && v[23] != 0.0) cfg.excite.action = PDT_EXCITE_DIRECT;

    pdt_autotune_result_t r;
    pdt_status_t st;
    if (!drive_autotune(&p, &z, max_scans, &cfg, &r, &st)) {
        free(p.hist);
        return 0;
    }
    print_at_result(&r);
    if (r.has_gains) {
        print_gains("at", &r.tune.ideal);
        printf("at_Ms_model %.9g\nms_robust %.9g\ndetune %.9g\n", (double)r.tune.fig.Ms,
               (double)r.ms_robust, (double)r.detune);
        closed_loop(&p, &r.tune.ideal, n_sp, n_load);
    }
    free(p.hist);
    return 0;
}

/* loop: only the closed loop of given gains on the plant. */
static int run_loop(void)
{
    plant_t p;
    read_plant(&p);
    double v[6];
    for (int i = 0; i < 6; i++) {
        if (rd(&v[i])) die("loop");
    }
    pdt_tune_gains_t g = {RL(v[0]), RL(v[1]), RL(v[2]), RL(v[3])};
    closed_loop(&p, &g, (long)v[4], (long)v[5]);
    free(p.hist);
    return 0;
}

static int run_relay(void)
{
    plant_t p;
    noise_t z;
    long max_scans;
    read_plant(&p);
    read_noise(&z, &max_scans);
    double v[5];
    for (int i = 0; i < 5; i++) {
        if (rd(&v[i])) die("relay config");
    }
    pdt_excite_config_t ec;
    pdt_excite_config_default(&ec, PDT_EXCITE_RELAY);
    ec.Ts = (pdt_real_t)p.Ts;
    ec.d = (pdt_real_t)v[0];
    ec.eps = (pdt_real_t)v[1];
    ec.relay_skip = (uint32_t)v[2];
    ec.relay_cycles = (uint32_t)v[3];
    ec.relay_settle = (pdt_real_t)v[4];
    ec.setpoint = RL(0.0);
    pdt_excite_t gen;
    pdt_status_t st = pdt_excite_init(&gen, &ec);
    printf("init_status %d\n", (int)st);
    if (st != PDT_OK) return 0;
    long k;
    for (k = 0; k < max_scans; k++) {
        double pv = sim_plant_output(&p.sim) + noise_next(&z);
        pdt_real_t u;
        st = pdt_excite_next(&gen, (pdt_real_t)pv, &u);
        sim_plant_apply(&p.sim, (double)u);
        if (st != PDT_RUNNING) break;
    }
    printf("status %d\nscans %ld\n", (int)(st == PDT_RUNNING ? PDT_ERR_TIMEOUT : st), k + 1);
    pdt_excite_relay_t rr;
    if (st == PDT_OK && pdt_excite_relay_result(&gen, &rr) == PDT_OK) {
        printf("Ku %.9g\nPu %.9g\na %.9g\ncycles %lu\n", (double)rr.Ku, (double)rr.Pu, (double)rr.a,
               (unsigned long)rr.cycles);
        pdt_tune_gains_t g;
        if (pdt_tune_ziegler_nichols(rr.Ku, rr.Pu, PDT_TUNE_PI, &g) == PDT_OK) {
            print_gains("pi", &g);
        }
        if (pdt_tune_ziegler_nichols(rr.Ku, rr.Pu, PDT_TUNE_PID, &g) == PDT_OK) {
            print_gains("pid", &g);
        }
    }
    free(p.hist);
    return 0;
}

static int run_model(void)
{
    long kind;
    double v[4] = {0, 0, 0, 0};
    if (rdl(&kind) || (kind != 1 && kind != 2)) die("model kind");
    for (int i = 0; i < (kind == 1 ? 3 : 4); i++) {
        if (rd(&v[i])) die("model");
    }
    pdt_model_t m;
    if (kind == 1) {
        m.kind = PDT_MODEL_FOPDT;
        m.p.fopdt = (pdt_model_fopdt_t){(pdt_real_t)v[0], (pdt_real_t)v[1], (pdt_real_t)v[2]};
    } else {
        m.kind = PDT_MODEL_SOPDT;
        m.p.sopdt = (pdt_model_sopdt_t){(pdt_real_t)v[0], (pdt_real_t)v[1], (pdt_real_t)v[2],
                                        (pdt_real_t)v[3]};
    }
    print_model("model", &m);
    tune_print("pi", &m, RL(100.0), PDT_TUNE_PI, RL(0.0), RL(0.0));
    tune_print("pid", &m, RL(100.0), PDT_TUNE_PID, RL(0.0), RL(0.0));
    return 0;
}

static int run_halfrule(void)
{
    double k, th0;
    long nl = 0, nz;
    pdt_real_t lags[PDT_REDUCE_MAX_LAGS], zeros[PDT_REDUCE_MAX_LAGS];
    if (rd(&k) || rdl(&nl) || nl < 1 || nl > (long)PDT_REDUCE_MAX_LAGS) die("lags");
    for (long i = 0; i < nl; i++) {
        double t;
        if (rd(&t)) die("lag");
        lags[i] = (pdt_real_t)t;
    }
    if (rdl(&nz) || nz < 0 || nz > (long)PDT_REDUCE_MAX_LAGS) die("zeros");
    for (long i = 0; i < nz; i++) {
        double t;
        if (rd(&t)) die("zero");
        zeros[i] = (pdt_real_t)t;
    }
    if (rd(&th0)) die("theta0");
    pdt_reduce_plant_t pl = {(pdt_real_t)k, lags, (size_t)nl, zeros, (size_t)nz, (pdt_real_t)th0};
    pdt_reduce_config_t rc;
    pdt_reduce_config_default(&rc);
    pdt_model_t fo, so;
    rc.model = PDT_MODEL_FOPDT;
    pdt_status_t st = pdt_reduce_half_rule(&pl, &rc, &fo, NULL);
    printf("fopdt_status %d\n", (int)st);
    if (st != PDT_OK) return 0;
    print_model("fopdt", &fo);
    tune_print("pi", &fo, RL(100.0), PDT_TUNE_PI, RL(0.0), RL(0.0));
    rc.model = PDT_MODEL_SOPDT;
    st = pdt_reduce_half_rule(&pl, &rc, &so, NULL);
    printf("sopdt_status %d\n", (int)st);
    if (st == PDT_OK) {
        print_model("sopdt", &so);
        tune_print("pid", &so, RL(100.0), PDT_TUNE_PID, RL(0.0), RL(0.0));
    } else {
        /* One lag: SIMC's PID is the PI. */
        tune_print("pid", &fo, RL(100.0), PDT_TUNE_PID, RL(0.0), RL(0.0));
    }
    return 0;
}

int main(void)
{
    char mode[32];
    if (scanf("%31s", mode) != 1) die("mode");
    if (strcmp(mode, "autotune") == 0) return run_autotune();
    if (strcmp(mode, "relay") == 0) return run_relay();
    if (strcmp(mode, "at") == 0) return run_at();
    if (strcmp(mode, "loop") == 0) return run_loop();
    if (strcmp(mode, "model") == 0) return run_model();
    if (strcmp(mode, "halfrule") == 0) return run_halfrule();
    die("unknown mode");
    return 2;
}
