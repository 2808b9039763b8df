/*
 * Tests of lib/src/pdt_autotune.c: whole autotunes of plants simulated here
 * scan by scan (a FOPDT, a SOPDT, an integrating process and a
 * reverse-acting one), with each experiment kind and with decimation 1 and
 * above; the phases, the output applied in each, the work of each call,
 * the model and the gains; every safety abort, the refusals, and every bad
 * input with the autotune left untouched.
 *
 * The plants: the shared simulator (tools/sim/sim_process.h),
 * exact at the scan period, independent of the library's discretisation,
 * read through a sensor with deterministic white noise. pv of scan k is
 * read before the output of scan k is applied, as the autotune's header
 * says.
 */
#include "test_util.h"
#include "sim_process.h"

#include "pdt/pdt_autotune.h"

#define R(x) ((pdt_real_t)(x))

/* ---- The plant ----------------------------------------------------------- */

typedef struct plant {
    sim_process_t proc;
    double disturb; /* added to pv (a test's upset) */
    uint32_t mark;  /* a test's bookmark (scan number) */
} plant_t;

static void plant_init(plant_t *p, const pdt_model_t *m, double Ts, double u0, double y0,
                       double noise_sd, uint32_t seed)
{
    memset(p, 0, sizeof *p);
    assert_int_equal(sim_process_init(&p->proc, m, Ts, u0, y0, noise_sd, seed), 0);
}

/* The process value read at this scan. */
static pdt_real_t plant_pv(plant_t *p)
{
    return sim_process_pv(&p->proc) + R(p->disturb);
}

/* Applies u for one scan and advances the plant to the next scan. */
static void plant_apply(plant_t *p, pdt_real_t u)
{
    sim_process_apply(&p->proc, u);
}

/* ---- The autotune run ---------------------------------------------------- */

#define WORK_REALS 40000u
static pdt_real_t g_work[WORK_REALS + CANARY_COUNT];

/* The workspace the size query asks for, with canaries right after it. */
static size_t work_prepare(const pdt_autotune_config_t *c)
{
    size_t need = pdt_autotune_workspace_size(c);
    assert_true(need > 0u);
    if (c->ident.population == 0u) {
        assert_true(need <= PDT_AUTOTUNE_WORKSPACE_SIZE(c->capacity, PDT_IDENT_POPULATION_SOPDT));
    }
    size_t reals = (need + sizeof(pdt_real_t) - 1u) / sizeof(pdt_real_t);
    assert_true(reals <= WORK_REALS);
    canary_fill(g_work, WORK_REALS + CANARY_COUNT);
    return need;
}

static void work_check(const pdt_autotune_config_t *c)
{
    size_t need = pdt_autotune_workspace_size(c);
    size_t reals = (need + sizeof(pdt_real_t) - 1u) / sizeof(pdt_real_t);
    canary_check(g_work + reals, CANARY_COUNT);
}

/* The autotune's shared part of the workspace with order_auto: the
 * largest of both identifications' and the validation's. */
static size_t share(const pdt_ident_config_t *ic, size_t cap)
{
    pdt_ident_config_t a = *ic;
    a.model = PDT_MODEL_FOPDT;
    size_t f = pdt_ident_workspace_size(&a, cap);
    a.model = PDT_MODEL_SOPDT;
    size_t s = pdt_ident_workspace_size(&a, cap);
    size_t v = pdt_validate_workspace_size(cap);
    size_t m = f > s ? f : s;
    return m > v ? m : v;
}

static void base_config(pdt_autotune_config_t *c, double Ts, uint32_t dec, size_t cap,
                        pdt_excite_kind_t kind, pdt_model_kind_t model)
{
    pdt_autotune_config_default(c);
    c->Ts = R(Ts);
    c->decimation = dec;
    c->capacity = cap;
    pdt_excite_config_default(&c->excite, kind);
    c->u_min = R(0.0);
    c->u_max = R(100.0);
    c->pv_min = R(-1000.0);
    c->pv_max = R(1000.0);
    c->ident.model = model;
}

typedef void (*upset_fn)(plant_t *p, pdt_autotune_phase_t phase, uint32_t scan);

typedef struct run {
    pdt_status_t st; /* status of the last call */
    pdt_autotune_result_t res;
    uint32_t scans;              /* calls made */
    pdt_autotune_phase_t seq[8]; /* phases seen, in order, without repeats */
    int nseq;
    uint32_t phase_scans[7]; /* calls made in each phase */
    uint32_t max_evals;      /* most cost evaluations in one call */
    pdt_real_t u_last;
    double u_err; /* largest output error against the expected */
} run_t;

/*
 * Runs the autotune until it stops running (or `limit` scans). A shadow
 * generator fed the same pv gives the excitation the output must equal
 * while the experiment runs; otherwise the output must be the operating
 * point (u_now until it is measured, then the recorder's mean, which for
 * a held output is u_now to rounding). `upset` may disturb the plant.
 */
static void run_autotune(pdt_autotune_t *at, const pdt_autotune_config_t *c, plant_t *p,
                         pdt_real_t u_now, uint32_t limit, upset_fn upset, run_t *out)
{
    memset(out, 0, sizeof *out);
    size_t need = work_prepare(c);
    assert_int_equal(pdt_autotune_init(at, c, u_now, g_work, need), PDT_OK);
    assert_int_equal(pdt_autotune_phase(at), PDT_AUTOTUNE_SETTLE);

    pdt_excite_config_t ec = c->excite;
    ec.Ts = c->Ts;
    ec.u0 = u_now;
    ec.u_min = c->u_min;
    ec.u_max = c->u_max;
    ec.pre = c->Ts * (pdt_real_t)c->decimation * (pdt_real_t)c->settle;
    pdt_excite_t shadow;
    assert_int_equal(pdt_excite_init(&shadow, &ec), PDT_OK);

    out->st = PDT_RUNNING;
    while (out->st == PDT_RUNNING && out->scans < limit) {
        pdt_autotune_phase_t before = pdt_autotune_phase(at);
        if (upset != NULL) {
            upset(p, before, out->scans);
        }
        pdt_real_t pv = plant_pv(p);
        uint64_t s0 = 0;
        bool counting = before == PDT_AUTOTUNE_IDENTIFY && at->ident_started;
        if (counting) {
            s0 = at->ident.samples;
        }
        pdt_real_t u = R(-777.0);
        out->st = pdt_autotune_scan(at, pv, &u);
        out->scans++;
        out->phase_scans[before]++;
        if (counting && at->ident_started) {
            /* Evaluations of the whole record's worth (pdt_ident_step): a
             * coarse record's take a D-th each. */
            const uint64_t n = at->ident.data.n;
            uint32_t de = (uint32_t)((at->ident.samples - s0 + n - 1u) / n);
            if (de > out->max_evals) {
                out->max_evals = de;
            }
        }
        pdt_autotune_phase_t after = pdt_autotune_phase(at);
        if (out->nseq == 0 || out->seq[out->nseq - 1] != before) {
            assert_true(out->nseq < 8);
            out->seq[out->nseq++] = before;
        }
        if (out->st != PDT_RUNNING && out->seq[out->nseq - 1] != after) {
            assert_true(out->nseq < 8);
            out->seq[out->nseq++] = after;
        }
        /* The output expected. */
        double want;
        if ((before == PDT_AUTOTUNE_SETTLE || before == PDT_AUTOTUNE_EXCITE) &&
            (after == PDT_AUTOTUNE_SETTLE || after == PDT_AUTOTUNE_EXCITE)) {
            pdt_real_t us;
            (void)pdt_excite_next(&shadow, pv, &us);
            want = (double)us;
        } else {
            if (before == PDT_AUTOTUNE_SETTLE || before == PDT_AUTOTUNE_EXCITE) {
                pdt_real_t us;
                (void)pdt_excite_next(&shadow, pv, &us);
            }
            want = (double)u_now;
        }
        double e = fabs((double)u - want);
        if (e > out->u_err) {
            out->u_err = e;
        }
        out->u_last = u;
        plant_apply(p, u);
    }
    assert_int_equal(pdt_autotune_result(at, &out->res), PDT_OK);
    work_check(c);
}

/* The phases of a successful run, in order. */
static void assert_phases_ok(const run_t *r)
{
    static const pdt_autotune_phase_t want[] = {PDT_AUTOTUNE_SETTLE, PDT_AUTOTUNE_EXCITE,
                                                PDT_AUTOTUNE_IDENTIFY, PDT_AUTOTUNE_TUNE,
                                                PDT_AUTOTUNE_DONE};
    assert_int_equal(r->nseq, 5);
    for (int i = 0; i < 5; i++) {
        assert_int_equal(r->seq[i], want[i]);
    }
    /* The first knob factor taken, in bounded steps: the gains, the
     * robustness scan about 128 evaluations of L a scan, the robust bound. */
    assert_in_range(r->phase_scans[PDT_AUTOTUNE_TUNE], 3, 30);
}

/* Output tolerance: u0 comes back as the mean of the settle window. */
#define U_ATOL 1e-4

/* Everything a successful run must show; then the model's own checks. */
static void assert_success(pdt_autotune_t *at, const pdt_autotune_config_t *c, const run_t *r,
                           double K_true)
{
    assert_int_equal(r->st, PDT_OK);
    assert_phases_ok(r);
    assert_true(r->u_err <= U_ATOL);
    assert_true(r->max_evals >= 1u && r->max_evals <= c->evals_per_scan);
    const pdt_autotune_result_t *s = &r->res;
    assert_int_equal(s->status, PDT_OK);
    assert_true(s->has_model && s->has_gains);
    assert_int_equal(s->scans, r->scans);
    assert_true(s->samples >= (size_t)c->settle + PDT_MIN_SAMPLES && s->samples <= c->capacity);
    assert_true(s->scans_experiment >= s->samples * c->decimation);
    /* Identification calls: one to prepare, then at least the whole
     * record's evaluations' worth / evals_per_scan (the last model's
     * search alone gives a lower bound). */
    assert_true((uint64_t)r->phase_scans[PDT_AUTOTUNE_IDENTIFY] * c->evals_per_scan *
                        at->ident.data.n +
                    at->ident.data.n >=
                at->ident.samples);
    assert_true((double)s->ident.fit >= (double)c->tune.fit_min);
    /* Sane robustness; the controller acts against the process gain. */
    assert_true((double)s->tune.fig.Ms >= 1.0 && (double)s->tune.fig.Ms <= 2.0);
    assert_true((double)s->tune.fig.gain_margin >= 1.7);
    assert_true((double)s->tune.fig.phase_margin_deg >= 30.0);
    assert_true((double)s->tune.ideal.Kc * K_true > 0.0);
    assert_true((double)s->tune.ideal.tauI > 0.0);
    /* Every later call: the same answer and the operating point. */
    for (int i = 0; i < 3; i++) {
        pdt_real_t u = R(-1.0);
        assert_int_equal(pdt_autotune_scan(at, R(1e30), &u), PDT_OK);
        assert_close(u, r->u_last, 0.0, 0.0);
    }
    assert_int_equal(pdt_autotune_phase(at), PDT_AUTOTUNE_DONE);
}

static void report(const char *name, const run_t *r)
{
    const pdt_model_t *m = &r->res.ident.model;
    if (m->kind == PDT_MODEL_FOPDT) {
        print_message("%s: K %.5g tau %.5g Td %.5g", name, (double)m->p.fopdt.K,
                      (double)m->p.fopdt.tau, (double)m->p.fopdt.Td);
    } else {
        print_message("%s: k %.5g a %.5g b %.5g Td %.5g", name, (double)m->p.sopdt.k,
                      (double)m->p.sopdt.a, (double)m->p.sopdt.b, (double)m->p.sopdt.Td);
    }
    print_message(" fit %.4g%%, %u evaluations, %u scans (%u identifying, at most %u "
                  "evaluations per call), Kc %.4g tauI %.4g Ms %.3g GM %.3g PM %.3g\n",
                  (double)r->res.ident.fit, (unsigned)r->res.ident.evaluations, (unsigned)r->scans,
                  (unsigned)r->phase_scans[PDT_AUTOTUNE_IDENTIFY], (unsigned)r->max_evals,
                  (double)r->res.tune.ideal.Kc, (double)r->res.tune.ideal.tauI,
                  (double)r->res.tune.fig.Ms, (double)r->res.tune.fig.gain_margin,
                  (double)r->res.tune.fig.phase_margin_deg);
}

static void assert_fopdt(const run_t *r, double K, double tau, double Td, double rtol)
{
    const pdt_model_t *m = &r->res.ident.model;
    assert_int_equal(m->kind, PDT_MODEL_FOPDT);
    assert_close(m->p.fopdt.K, K, rtol, 0.0);
    assert_close(m->p.fopdt.tau, tau, rtol, 0.0);
    assert_close(m->p.fopdt.Td, Td, 0.0, rtol * tau);
}

/* SOPDT by DC gain, natural frequency, damping and dead time (the dead time
 * against 1 / wn). */
static void assert_sopdt(const run_t *r, const pdt_model_t *truth, double rtol)
{
    const pdt_model_t *m = &r->res.ident.model;
    pdt_model_natural_t g, w;
    assert_int_equal(m->kind, PDT_MODEL_SOPDT);
    assert_int_equal(pdt_model_sopdt_to_natural(&m->p.sopdt, &g), PDT_OK);
    assert_int_equal(pdt_model_sopdt_to_natural(&truth->p.sopdt, &w), PDT_OK);
    assert_close(g.K, w.K, rtol, 0.0);
    assert_close(g.wn, w.wn, 2.0 * rtol, 0.0);
    assert_close(g.zeta, w.zeta, 2.0 * rtol, 0.0);
    assert_close(g.Td, w.Td, 0.0, 2.0 * rtol / (double)w.wn);
}

static pdt_autotune_t g_at;

/* ---- Successful autotunes ---------------------------------------------- */

/* A FOPDT, step with an end and a tail, no decimation. */
static void test_fopdt_step_tail(void **state)
{
    (void)state;
    pdt_autotune_config_t c;
    base_config(&c, 0.5, 1u, 400u, PDT_EXCITE_STEP, PDT_MODEL_FOPDT);
    c.excite.amplitude = R(5.0);
    c.excite.duration = R(60.0);
    c.tail = 120u;
    plant_t p;
    pdt_model_t m = model_fopdt(2.0, 10.0, 3.0);
    plant_init(&p, &m, 0.5, 30.0, 60.0, 0.05, 17u);
    run_t r;
    run_autotune(&g_at, &c, &p, R(30.0), 100000u, NULL, &r);
    report("FOPDT step + tail", &r);
    assert_success(&g_at, &c, &r, 2.0);
    /* settle 20 + 120 step + 120 tail samples: stopped by the tail */
    assert_int_equal(r.res.samples, 20u + 120u + 120u);
    assert_fopdt(&r, 2.0, 10.0, 3.0, 0.03);
    assert_close(r.res.ident.u0, 30.0, 1e-6, 0.0);
    assert_close(r.res.ident.y0, 60.0, 0.0, 0.02);
}

/* The same FOPDT, PRBS at decimation 4: the dead time comes back whole. */
static void test_fopdt_prbs_decimated(void **state)
{
    (void)state;
    pdt_autotune_config_t c;
    base_config(&c, 0.125, 4u, 600u, PDT_EXCITE_PRBS, PDT_MODEL_FOPDT);
    c.excite.amplitude = R(3.0);
    c.excite.prbs_bits = 7u;
    c.excite.prbs_hold = 16u; /* 2 s chips */
    plant_t p;
    pdt_model_t m = model_fopdt(2.0, 10.0, 3.0);
    plant_init(&p, &m, 0.125, 40.0, 20.0, 0.1, 23u);
    run_t r;
    run_autotune(&g_at, &c, &p, R(40.0), 100000u, NULL, &r);
    report("FOPDT PRBS, decimation 4", &r);
    assert_success(&g_at, &c, &r, 2.0);
    assert_int_equal(r.res.samples, 600u);
    assert_fopdt(&r, 2.0, 10.0, 3.0, 0.03);
}

/* The SOPDT plant of the pulse tests and its experiment: one pulse,
 * decimation 2. */
static void pulse_setup(pdt_autotune_config_t *c, plant_t *p, pdt_model_t *m,
                        pdt_model_kind_t model)
{
    base_config(c, 0.5, 2u, 300u, PDT_EXCITE_PULSE, model);
    c->excite.amplitude = R(4.0);
    c->excite.t_on = R(40.0);
    c->excite.t_off = R(0.0);
    c->excite.count = 1u;
    *m = model_sopdt_tc(1.5, 8.0, 3.0, 2.0);
    plant_init(p, m, 0.5, 50.0, 10.0, 0.03, 5u);
}

/* A SOPDT, one pulse, decimation 2. */
static void test_sopdt_pulse(void **state)
{
    (void)state;
    pdt_autotune_config_t c;
    plant_t p;
    pdt_model_t m;
    pulse_setup(&c, &p, &m, PDT_MODEL_SOPDT);
    c.order_auto = false; /* the order an explicit ident.model fixes */
    run_t r;
    run_autotune(&g_at, &c, &p, R(50.0), 100000u, NULL, &r);
    report("SOPDT pulse, decimation 2", &r);
    assert_success(&g_at, &c, &r, 1.5);
    assert_sopdt(&r, &m, 0.04);
}

static void step_setup(pdt_autotune_config_t *c, plant_t *p, double noise_sd);

/* The order chosen by the data (order_auto, the default): the SOPDT plant
 * of the pulse test keeps a SOPDT, the FOPDT plant of the step test a
 * FOPDT; either way the model is validated and the gains pass the robust
 * bound. */
static void test_order_auto(void **state)
{
    (void)state;
    pdt_autotune_config_t c;
    plant_t p;
    pdt_model_t m;
    pulse_setup(&c, &p, &m, PDT_MODEL_FOPDT);
    run_t r;
    run_autotune(&g_at, &c, &p, R(50.0), 100000u, NULL, &r);
    report("order auto, SOPDT plant", &r);
    assert_success(&g_at, &c, &r, 1.5);
    assert_int_equal(r.res.ident.model.kind, PDT_MODEL_SOPDT);
    assert_true(r.res.has_valid && r.res.valid.model.kind == PDT_MODEL_SOPDT);
    assert_true(r.res.bic_other > r.res.valid.bic);
    assert_true(r.res.ms_robust >= r.res.tune.fig.Ms * R(0.98) && r.res.ms_robust <= c.ms_robust);
    assert_sopdt(&r, &m, 0.04);

    step_setup(&c, &p, 0.05);
    c.ident.model = PDT_MODEL_SOPDT; /* ignored: the data choose */
    run_autotune(&g_at, &c, &p, R(30.0), 100000u, NULL, &r);
    report("order auto, FOPDT plant", &r);
    assert_success(&g_at, &c, &r, 2.0);
    assert_int_equal(r.res.ident.model.kind, PDT_MODEL_FOPDT);
    assert_fopdt(&r, 2.0, 10.0, 3.0, 0.03);
    /* The parameter std is small against the parameters here. */
    assert_true(r.res.valid.std.count == 4u);
    assert_true(r.res.valid.std.std[0] < R(0.05) && r.res.valid.std.std[1] < R(0.5));

    /* Neither the order choice nor the robust bound: no validation. */
    step_setup(&c, &p, 0.05);
    c.order_auto = false;
    c.ms_robust = R(0.0);
    run_autotune(&g_at, &c, &p, R(30.0), 100000u, NULL, &r);
    assert_success(&g_at, &c, &r, 2.0);
    assert_false(r.res.has_valid);
    assert_true(r.res.detune == R(1.0));
}

/* The same SOPDT, a chirp, no decimation, PID. */
static void test_sopdt_chirp(void **state)
{
    (void)state;
    pdt_autotune_config_t c;
    base_config(&c, 0.5, 1u, 600u, PDT_EXCITE_CHIRP, PDT_MODEL_SOPDT);
    c.excite.amplitude = R(4.0);
    c.excite.f0 = R(0.0);
    c.excite.f1 = R(0.1);
    c.excite.duration = R(200.0);
    c.tune.form = PDT_TUNE_PID;
    plant_t p;
    pdt_model_t m = model_sopdt_tc(1.5, 8.0, 3.0, 2.0);
    plant_init(&p, &m, 0.5, 50.0, 10.0, 0.03, 9u);
    run_t r;
    run_autotune(&g_at, &c, &p, R(50.0), 100000u, NULL, &r);
    report("SOPDT chirp", &r);
    assert_success(&g_at, &c, &r, 1.5);
    assert_sopdt(&r, &m, 0.04);
    assert_true((double)r.res.tune.ideal.tauD > 0.0);
}

/* An integrating process (b = 0): one pulse, the level moves and stays. */
static void test_integrating_pulse(void **state)
{
    (void)state;
    pdt_autotune_config_t c;
    base_config(&c, 0.5, 1u, 400u, PDT_EXCITE_PULSE, PDT_MODEL_SOPDT);
    c.excite.amplitude = R(2.0);
    c.excite.t_on = R(30.0);
    c.excite.t_off = R(0.0);
    c.excite.count = 1u;
    plant_t p;
    pdt_model_t m = model_integ(0.05, 4.0, 2.0);
    plant_init(&p, &m, 0.5, 20.0, 5.0, 0.01, 31u);
    run_t r;
    run_autotune(&g_at, &c, &p, R(20.0), 100000u, NULL, &r);
    report("integrating pulse", &r);
    assert_success(&g_at, &c, &r, 0.05);
    const pdt_model_sopdt_t *s = &r.res.ident.model.p.sopdt;
    assert_int_equal(r.res.ident.model.kind, PDT_MODEL_SOPDT);
    /* Integrating (b = 0), or a slowest pole below 1/4000 s^-1: b / a at
     * most 1/20 of 1 / the record length. Its integrating gain is k / a. */
    assert_true((double)s->b / (double)s->a * 200.0 <= 0.05);
    pdt_model_integ_t gi;
    pdt_model_sopdt_t gz = *s;
    gz.b = R(0.0);
    assert_int_equal(pdt_model_sopdt_to_integ(&gz, &gi), PDT_OK);
    assert_close(gi.Ki, 0.05, 0.04, 0.0);
    assert_close(gi.T + gi.Td, 6.0, 0.04, 0.0);
}

/* A reverse-acting process (negative gain): relay, direct action, around
 * the operating point, and a tail after the cycles. */
static void reverse_relay(uint32_t dec, double Ts, double rtol, run_t *r)
{
    pdt_autotune_config_t c;
    base_config(&c, Ts, dec, 1000u / dec, PDT_EXCITE_RELAY, PDT_MODEL_FOPDT);
    c.excite.action = PDT_EXCITE_DIRECT;
    c.excite.d = R(2.0);
    c.excite.eps = R(0.05);
    c.excite.setpoint = R(70.0);
    c.excite.relay_cycles = 3u;
    c.tail = 200u / dec;
    plant_t p;
    pdt_model_t m = model_fopdt(-1.5, 6.0, 1.5);
    plant_init(&p, &m, Ts, 60.0, 70.0, 0.005, 41u);
    run_autotune(&g_at, &c, &p, R(60.0), 100000u, NULL, r);
    assert_success(&g_at, &c, r, -1.5);
    assert_fopdt(r, -1.5, 6.0, 1.5, rtol);
    assert_true(r->res.has_relay);
    /* The relay ends at its first symmetric cycle (relay_settle). */
    assert_int_equal(r->res.relay.cycles, 1u);
    assert_true((double)r->res.relay.Pu > 0.0 && (double)r->res.relay.Ku > 0.0);
}

static void test_reverse_relay(void **state)
{
    (void)state;
    run_t r;
    reverse_relay(1u, 0.25, 0.03, &r);
    report("reverse-acting relay", &r);
    reverse_relay(2u, 0.125, 0.05, &r);
    report("reverse-acting relay, decimation 2", &r);
}

/* ---- Safety ------------------------------------------------------------ */

/* The step test's plant and config, the base of the abort tests. */
static void step_setup(pdt_autotune_config_t *c, plant_t *p, double noise_sd)
{
    base_config(c, 0.5, 1u, 400u, PDT_EXCITE_STEP, PDT_MODEL_FOPDT);
    c->excite.amplitude = R(5.0);
    c->excite.duration = R(60.0);
    c->tail = 120u;
    pdt_model_t m = model_fopdt(2.0, 10.0, 3.0);
    plant_init(p, &m, 0.5, 30.0, 60.0, noise_sd, 17u);
}

/* After a failure: every later call gives the same status and u0. */
static void assert_failed(pdt_autotune_t *at, const run_t *r, pdt_status_t why,
                          pdt_autotune_phase_t in, double u0)
{
    assert_int_equal(r->st, why);
    assert_int_equal(r->res.status, why);
    assert_int_equal(r->res.failed_in, in);
    assert_int_equal(pdt_autotune_phase(at), PDT_AUTOTUNE_FAILED);
    assert_false(r->res.has_gains);
    assert_close(r->u_last, u0, 0.0, U_ATOL);
    for (int i = 0; i < 3; i++) {
        pdt_real_t u = R(-1.0);
        assert_int_equal(pdt_autotune_scan(at, R(60.0), &u), why);
        assert_close(u, u0, 0.0, U_ATOL);
    }
    pdt_real_t u = R(-1.0);
    assert_int_equal(pdt_autotune_abort(at, &u), PDT_OK); /* no change now */
    assert_close(u, u0, 0.0, U_ATOL);
    pdt_autotune_result_t res;
    assert_int_equal(pdt_autotune_result(at, &res), PDT_OK);
    assert_int_equal(res.status, why);
}

/* pv passes its upper limit while the step drives it up (y = 60 + 10 at
 * the end): the abort comes during the experiment. */
static void test_pv_limit_experiment(void **state)
{
    (void)state;
    pdt_autotune_config_t c;
    plant_t p;
    run_t r;
    step_setup(&c, &p, 0.0);
    c.pv_max = R(65.0);
    run_autotune(&g_at, &c, &p, R(30.0), 100000u, NULL, &r);
    assert_failed(&g_at, &r, PDT_ERR_PV_LIMIT, PDT_AUTOTUNE_EXCITE, 30.0);
    assert_false(r.res.has_model);
    assert_true(r.u_err <= U_ATOL);
    /* the step had pushed pv past the half-way point, 65, at that scan */
    assert_true(sim_plant_output(&p.proc.plant) >= 64.9);
}

/* pv leaves its limits while the output rests at u0 for the
 * identification (an upset from elsewhere). */
static void upset_identify(plant_t *p, pdt_autotune_phase_t phase, uint32_t scan)
{
    if (phase == PDT_AUTOTUNE_IDENTIFY && p->mark == 0u) {
        p->mark = scan;
    }
    if (p->mark != 0u && scan == p->mark + 20u) {
        p->disturb = 50.0; /* 20 calls into the search */
    }
}

static void test_pv_limit_identify(void **state)
{
    (void)state;
    pdt_autotune_config_t c;
    plant_t p;
    run_t r;
    step_setup(&c, &p, 0.0);
    c.pv_max = R(100.0);
    run_autotune(&g_at, &c, &p, R(30.0), 100000u, upset_identify, &r);
    assert_failed(&g_at, &r, PDT_ERR_PV_LIMIT, PDT_AUTOTUNE_IDENTIFY, 30.0);
    assert_false(r.res.has_model);
    assert_int_equal(r.scans, p.mark + 21u);
    assert_true(r.u_err <= U_ATOL);
    /* A non-finite pv while identifying is refused too. */
    pdt_real_t u;
    size_t need = work_prepare(&c);
    assert_int_equal(pdt_autotune_init(&g_at, &c, R(30.0), g_work, need), PDT_OK);
    step_setup(&c, &p, 0.0);
    pdt_status_t st = PDT_RUNNING;
    while (st == PDT_RUNNING && pdt_autotune_phase(&g_at) != PDT_AUTOTUNE_IDENTIFY) {
        st = pdt_autotune_scan(&g_at, plant_pv(&p), &u);
        plant_apply(&p, u);
    }
    assert_int_equal(st, PDT_RUNNING);
    assert_int_equal(pdt_autotune_scan(&g_at, (pdt_real_t)NAN, &u), PDT_ERR_NONFINITE);
    assert_close(u, 30.0, 0.0, U_ATOL);
}

static void test_output_limit(void **state)
{
    (void)state;
    pdt_autotune_config_t c;
    plant_t p;
    step_setup(&c, &p, 0.0);
    size_t need = work_prepare(&c);
    /* u_now outside the limits */
    assert_int_equal(pdt_autotune_init(&g_at, &c, R(101.0), g_work, need), PDT_ERR_OUTPUT_LIMIT);
    assert_int_equal(pdt_autotune_init(&g_at, &c, R(-0.5), g_work, need), PDT_ERR_OUTPUT_LIMIT);
    /* the step's level outside them: 98 + 5 */
    assert_int_equal(pdt_autotune_init(&g_at, &c, R(98.0), g_work, need), PDT_ERR_OUTPUT_LIMIT);
    /* a relay's levels */
    base_config(&c, 0.5, 1u, 400u, PDT_EXCITE_RELAY, PDT_MODEL_FOPDT);
    c.excite.d = R(10.0);
    need = work_prepare(&c);
    assert_int_equal(pdt_autotune_init(&g_at, &c, R(95.0), g_work, need), PDT_ERR_OUTPUT_LIMIT);
    assert_int_equal(pdt_autotune_init(&g_at, &c, R(50.0), g_work, need), PDT_OK);
}

static void test_timeout(void **state)
{
    (void)state;
    pdt_autotune_config_t c;
    plant_t p;
    run_t r;
    step_setup(&c, &p, 0.0);
    c.max_scans = 100u; /* the experiment needs 260 */
    run_autotune(&g_at, &c, &p, R(30.0), 100000u, NULL, &r);
    assert_failed(&g_at, &r, PDT_ERR_TIMEOUT, PDT_AUTOTUNE_EXCITE, 30.0);
    assert_int_equal(r.scans, 101u);
    assert_int_equal(r.res.scans_experiment, 101u);
}

/* A relay whose set-point the process value would have to cross upward,
 * but the set-point lies below the operating point. */
static void test_setpoint(void **state)
{
    (void)state;
    pdt_autotune_config_t c;
    plant_t p;
    run_t r;
    base_config(&c, 0.5, 1u, 400u, PDT_EXCITE_RELAY, PDT_MODEL_FOPDT);
    c.excite.setpoint = R(55.0);
    c.excite.eps = R(0.1);
    c.move = PDT_RECORD_MOVE_UP;
    pdt_model_t m = model_fopdt(2.0, 10.0, 3.0);
    plant_init(&p, &m, 0.5, 30.0, 60.0, 0.0, 3u);
    run_autotune(&g_at, &c, &p, R(30.0), 100000u, NULL, &r);
    assert_failed(&g_at, &r, PDT_ERR_SETPOINT, PDT_AUTOTUNE_SETTLE, 30.0);
    assert_int_equal(r.scans, c.settle);
}

static void test_abort(void **state)
{
    (void)state;
    pdt_autotune_config_t c;
    plant_t p;
    pdt_real_t u;
    pdt_autotune_result_t res;
    const uint32_t stop_at[] = {5u, 100u, 300u};
    for (int i = 0; i < 3; i++) {
        step_setup(&c, &p, 0.01);
        size_t need = work_prepare(&c);
        assert_int_equal(pdt_autotune_init(&g_at, &c, R(30.0), g_work, need), PDT_OK);
        for (uint32_t k = 0; k < stop_at[i]; k++) {
            assert_int_equal(pdt_autotune_scan(&g_at, plant_pv(&p), &u), PDT_RUNNING);
            plant_apply(&p, u);
        }
        pdt_autotune_phase_t ph = pdt_autotune_phase(&g_at);
        u = R(-1.0);
        assert_int_equal(pdt_autotune_abort(&g_at, &u), PDT_OK);
        assert_close(u, 30.0, 0.0, U_ATOL);
        assert_int_equal(pdt_autotune_phase(&g_at), PDT_AUTOTUNE_FAILED);
        assert_int_equal(pdt_autotune_result(&g_at, &res), PDT_OK);
        assert_int_equal(res.status, PDT_ERR_ABORTED);
        assert_int_equal(res.failed_in, ph);
        assert_false(res.has_gains);
        assert_int_equal(pdt_autotune_scan(&g_at, plant_pv(&p), &u), PDT_ERR_ABORTED);
        assert_close(u, 30.0, 0.0, U_ATOL);
        work_check(&c);
    }
    /* Once done, an abort changes nothing. */
    run_t r;
    step_setup(&c, &p, 0.01);
    run_autotune(&g_at, &c, &p, R(30.0), 100000u, NULL, &r);
    assert_int_equal(r.st, PDT_OK);
    assert_int_equal(pdt_autotune_abort(&g_at, &u), PDT_OK);
    assert_close(u, 30.0, 0.0, U_ATOL);
    assert_int_equal(pdt_autotune_scan(&g_at, R(60.0), &u), PDT_OK);
    assert_int_equal(pdt_autotune_phase(&g_at), PDT_AUTOTUNE_DONE);
}

/* ---- Refusals ------------------------------------------------------------ */

/* A process that does not respond: without noise the identification finds
 * nothing to fit; with noise only, whatever it fits is refused. */
static void test_flat_process(void **state)
{
    (void)state;
    pdt_autotune_config_t c;
    plant_t p;
    run_t r;
    step_setup(&c, &p, 0.0);
    pdt_model_t m = model_fopdt(0.0, 10.0, 3.0);
    plant_init(&p, &m, 0.5, 30.0, 60.0, 0.0, 17u);
    run_autotune(&g_at, &c, &p, R(30.0), 100000u, NULL, &r);
    assert_failed(&g_at, &r, PDT_ERR_NO_EXCITATION, PDT_AUTOTUNE_IDENTIFY, 30.0);
    assert_false(r.res.has_model);
    plant_init(&p, &m, 0.5, 30.0, 60.0, 0.2, 17u);
    run_autotune(&g_at, &c, &p, R(30.0), 100000u, NULL, &r);
    print_message("flat process with noise: %s, fit %.3g%%\n", pdt_status_str(r.st),
                  (double)r.res.ident.fit);
    assert_true(r.st < 0);
    assert_false(r.res.has_gains);
    assert_int_equal(pdt_autotune_phase(&g_at), PDT_AUTOTUNE_FAILED);
    assert_close(r.u_last, 30.0, 0.0, U_ATOL);
}

/* Noise as large as the response: a model, but no gains. */
static void test_poor_fit(void **state)
{
    (void)state;
    pdt_autotune_config_t c;
    plant_t p;
    run_t r;
    step_setup(&c, &p, 5.0);
    /* By default the evidence decides: gains only if robust over what the
     * data leave uncertain. */
    run_autotune(&g_at, &c, &p, R(30.0), 100000u, NULL, &r);
    print_message("heavy noise: %s, fit %.3g%%, robust Ms bound %.3g, detune %.3g\n",
                  pdt_status_str(r.st), (double)r.res.ident.fit, (double)r.res.ms_robust,
                  (double)r.res.detune);
    assert_true(r.st == PDT_OK || r.st == PDT_ERR_UNCERTAIN || r.st == PDT_ERR_MODEL_INVALID);
    assert_true(r.res.has_valid);
    if (r.st == PDT_OK) {
        assert_true(r.res.ms_robust <= c.ms_robust);
    }
    /* fit_min, when set, refuses at once. */
    step_setup(&c, &p, 5.0);
    c.tune.fit_min = R(80.0);
    run_autotune(&g_at, &c, &p, R(30.0), 100000u, NULL, &r);
    assert_failed(&g_at, &r, PDT_ERR_POOR_FIT, PDT_AUTOTUNE_TUNE, 30.0);
    assert_true(r.res.has_model);
    assert_true((double)r.res.ident.fit < (double)c.tune.fit_min);
    assert_int_equal(r.phase_scans[PDT_AUTOTUNE_TUNE], 1);
}

/* ---- Bad inputs ---------------------------------------------------------- */

typedef void (*spoil_fn)(pdt_autotune_config_t *c);
static void sp_ts0(pdt_autotune_config_t *c)
{
    c->Ts = R(0.0);
}
static void sp_ts_nan(pdt_autotune_config_t *c)
{
    c->Ts = (pdt_real_t)NAN;
}
static void sp_dec0(pdt_autotune_config_t *c)
{
    c->decimation = 0u;
}
static void sp_settle0(pdt_autotune_config_t *c)
{
    c->settle = 0u;
}
static void sp_evals0(pdt_autotune_config_t *c)
{
    c->evals_per_scan = 0u;
}
static void sp_umin_inf(pdt_autotune_config_t *c)
{
    c->u_min = (pdt_real_t)-INFINITY;
}
static void sp_pvmax_nan(pdt_autotune_config_t *c)
{
    c->pv_max = (pdt_real_t)NAN;
}
static void sp_model(pdt_autotune_config_t *c)
{
    c->ident.model = (pdt_model_kind_t)7;
}
static void sp_pop(pdt_autotune_config_t *c)
{
    c->ident.population = 3u;
}
static void sp_amp0(pdt_autotune_config_t *c)
{
    c->excite.amplitude = R(0.0);
}
static void sp_kind(pdt_autotune_config_t *c)
{
    c->excite.kind = (pdt_excite_kind_t)9;
}
static void sp_msrob(pdt_autotune_config_t *c)
{
    c->ms_robust = R(1.0);
}
static void sp_agree(pdt_autotune_config_t *c)
{
    c->relay_agree = R(0.5);
}
static void sp_u_inv(pdt_autotune_config_t *c)
{
    c->u_min = R(101.0);
}
static void sp_pv_inv(pdt_autotune_config_t *c)
{
    c->pv_min = R(2000.0);
}
static void sp_cap(pdt_autotune_config_t *c)
{
    c->capacity = c->settle + PDT_MIN_SAMPLES - 1u;
}

static void test_bad_inputs(void **state)
{
    (void)state;
    static const struct {
        spoil_fn spoil;
        pdt_status_t want;
    } cases[] = {
        {sp_ts0, PDT_ERR_ARG},       {sp_ts_nan, PDT_ERR_ARG},    {sp_dec0, PDT_ERR_ARG},
        {sp_settle0, PDT_ERR_ARG},   {sp_evals0, PDT_ERR_ARG},    {sp_umin_inf, PDT_ERR_ARG},
        {sp_pvmax_nan, PDT_ERR_ARG}, {sp_model, PDT_ERR_ARG},     {sp_pop, PDT_ERR_ARG},
        {sp_amp0, PDT_ERR_ARG},      {sp_kind, PDT_ERR_ARG},      {sp_u_inv, PDT_ERR_BOUNDS},
        {sp_pv_inv, PDT_ERR_BOUNDS}, {sp_cap, PDT_ERR_TOO_SHORT}, {sp_msrob, PDT_ERR_ARG},
        {sp_agree, PDT_ERR_ARG},
    };
    pdt_autotune_config_t good, c;
    plant_t p;
    step_setup(&good, &p, 0.0);
    size_t need = work_prepare(&good);
    pdt_autotune_t pattern;
    memset(&pattern, 0xA5, sizeof pattern);
    pdt_autotune_t at = pattern;

    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        c = good;
        cases[i].spoil(&c);
        assert_int_equal(
            pdt_autotune_init(&at, &c, R(30.0), g_work, WORK_REALS * sizeof(pdt_real_t)),
            cases[i].want);
        assert_memory_equal(&at, &pattern, sizeof at);
        /* the ident's config errors and the experiment's are found at init;
         * the size query says 0 for what it checks itself */
        if (cases[i].spoil != sp_amp0 && cases[i].spoil != sp_kind) {
            assert_int_equal(pdt_autotune_workspace_size(&c), 0u);
        }
    }
    /* NULLs, a non-finite u_now, and the workspace */
    assert_int_equal(pdt_autotune_init(NULL, &good, R(30.0), g_work, need), PDT_ERR_ARG);
    assert_int_equal(pdt_autotune_init(&at, NULL, R(30.0), g_work, need), PDT_ERR_ARG);
    assert_int_equal(pdt_autotune_init(&at, &good, (pdt_real_t)NAN, g_work, need), PDT_ERR_ARG);
    assert_int_equal(pdt_autotune_init(&at, &good, (pdt_real_t)INFINITY, g_work, need),
                     PDT_ERR_ARG);
    assert_int_equal(pdt_autotune_init(&at, &good, R(30.0), NULL, need), PDT_ERR_NOMEM);
    assert_int_equal(pdt_autotune_init(&at, &good, R(30.0), g_work, need - 1u), PDT_ERR_NOMEM);
    assert_int_equal(pdt_autotune_init(&at, &good, R(30.0), g_work, 0u), PDT_ERR_NOMEM);
    assert_int_equal(pdt_autotune_init(&at, &good, R(30.0), (char *)g_work + 1, need), PDT_ERR_ARG);
    assert_memory_equal(&at, &pattern, sizeof at);
    canary_check(g_work, WORK_REALS + CANARY_COUNT); /* nothing written to work */

    /* The size query: 2 capacity reals plus the identification's share. */
    assert_int_equal(pdt_autotune_workspace_size(NULL), 0u);
    pdt_ident_config_t ic = good.ident;
    ic.Ts = good.Ts;
    c = good;
    c.order_auto = true;
    assert_int_equal(pdt_autotune_workspace_size(&c),
                     2u * c.capacity * sizeof(pdt_real_t) + share(&ic, c.capacity));
    c.decimation = 3u;
    ic.Ts = R(1.5);
    assert_int_equal(pdt_autotune_workspace_size(&c),
                     2u * c.capacity * sizeof(pdt_real_t) + share(&ic, c.capacity));
    c.order_auto = false;
    ic.model = c.ident.model;
    size_t only = pdt_ident_workspace_size(&ic, c.capacity);
    size_t val = pdt_validate_workspace_size(c.capacity);
    assert_int_equal(pdt_autotune_workspace_size(&c),
                     2u * c.capacity * sizeof(pdt_real_t) + (only > val ? only : val));
    /* No validation asked for: the identification's share alone. */
    c.ms_robust = R(0.0);
    assert_int_equal(pdt_autotune_workspace_size(&c), 2u * c.capacity * sizeof(pdt_real_t) + only);
    /* The default (order_auto): both models and the validation. */
    ic.Ts = good.Ts;
    assert_int_equal(need, 2u * good.capacity * sizeof(pdt_real_t) + share(&ic, good.capacity));
    /* exactly the size asked for works */
    assert_int_equal(pdt_autotune_init(&at, &good, R(30.0), g_work, need), PDT_OK);

    /* The other calls. */
    pdt_real_t u = R(-5.0);
    pdt_autotune_result_t res;
    memset(&res, 0x5A, sizeof res);
    pdt_autotune_result_t res0 = res;
    pdt_autotune_t zero;
    memset(&zero, 0, sizeof zero);
    assert_int_equal(pdt_autotune_scan(NULL, R(1.0), &u), PDT_ERR_ARG);
    assert_int_equal(pdt_autotune_scan(&at, R(1.0), NULL), PDT_ERR_ARG);
    assert_int_equal(pdt_autotune_scan(&zero, R(1.0), &u), PDT_ERR_STATE);
    assert_int_equal(pdt_autotune_abort(NULL, &u), PDT_ERR_ARG);
    assert_int_equal(pdt_autotune_abort(&at, NULL), PDT_ERR_ARG);
    assert_int_equal(pdt_autotune_abort(&zero, &u), PDT_ERR_STATE);
    assert_true(u == R(-5.0));
    assert_int_equal(pdt_autotune_result(NULL, &res), PDT_ERR_ARG);
    assert_int_equal(pdt_autotune_result(&at, NULL), PDT_ERR_ARG);
    assert_int_equal(pdt_autotune_result(&zero, &res), PDT_ERR_STATE);
    assert_memory_equal(&res, &res0, sizeof res);
    assert_int_equal(pdt_autotune_phase(NULL), 0);
    assert_int_equal(pdt_autotune_phase(&zero), 0);
    pdt_autotune_config_default(NULL);
}

static void test_defaults(void **state)
{
    (void)state;
    pdt_autotune_config_t c;
    memset(&c, 0x77, sizeof c);
    pdt_autotune_config_default(&c);
    assert_true(c.Ts == R(0.0));
    assert_int_equal(c.decimation, 1u);
    assert_int_equal(c.capacity, 0u);
    assert_int_equal(c.settle, 20u);
    assert_int_equal(c.tail, 0u);
    assert_int_equal(c.evals_per_scan, 4u);
    assert_int_equal(c.max_scans, 0u);
    assert_int_equal(c.move, PDT_RECORD_MOVE_ANY);
    assert_int_equal(c.excite.kind, PDT_EXCITE_PRBS);
    assert_int_equal(c.excite.prbs_bits, 7u);
    assert_true(c.excite.amplitude == R(1.0));
    assert_true(c.u_min < R(-1e30) && c.u_max > R(1e30));
    assert_true(c.pv_min < R(-1e30) && c.pv_max > R(1e30));
    assert_int_equal(c.ident.model, PDT_MODEL_FOPDT);
    assert_int_equal(c.tune.rule, PDT_TUNE_SIMC);
    assert_true(c.tune.fit_min == R(0.0));
    assert_true(c.order_auto);
    assert_true(c.ms_robust == R(2.0) && c.relay_agree == R(2.0));
    /* Ts and capacity must be set: the defaults alone are refused */
    assert_int_equal(pdt_autotune_workspace_size(&c), 0u);
    c.Ts = R(1.0);
    assert_int_equal(pdt_autotune_workspace_size(&c), 0u);
    c.capacity = 100u;
    assert_true(pdt_autotune_workspace_size(&c) > 0u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fopdt_step_tail),
        cmocka_unit_test(test_fopdt_prbs_decimated),
        cmocka_unit_test(test_sopdt_pulse),
        cmocka_unit_test(test_sopdt_chirp),
        cmocka_unit_test(test_order_auto),
        cmocka_unit_test(test_integrating_pulse),
        cmocka_unit_test(test_reverse_relay),
        cmocka_unit_test(test_pv_limit_experiment),
        cmocka_unit_test(test_pv_limit_identify),
        cmocka_unit_test(test_output_limit),
        cmocka_unit_test(test_timeout),
        cmocka_unit_test(test_setpoint),
        cmocka_unit_test(test_abort),
        cmocka_unit_test(test_flat_process),
        cmocka_unit_test(test_poor_fit),
        cmocka_unit_test(test_bad_inputs),
        cmocka_unit_test(test_defaults),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
