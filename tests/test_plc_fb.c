/*
 * Tests of examples/plc/pdt_fb_autotune.c, the PLC function block over the
 * autotune: the block is driven cycle by cycle, as a PLC task would, against
 * a FOPDT plant on the shared simulator (exact at the scan period
 * with a fractional dead time) with small deterministic measurement noise. Checked:
 * rising-edge start, Busy on every running cycle, Done with a model and
 * gains close to the plant's, the PLCopen end-flag handshake (held while
 * Execute, one cycle when Execute fell early), Error and ErrorID on a pv
 * limit, a time limit, a failed sensor and refused gains, refused starts,
 * the Abort input, re-trigger after Done, an instance moved while busy, the
 * size-checked glue entry points, the instance's size, layout and
 * workspace, and that nothing is written past the instance (canaries).
 * The PID: the handover at Done without a bump, set-point and load steps in
 * automatic, manual/automatic transfers both ways without a bump, a failed
 * sensor holding the output, a refused PID parameter, a refused start that
 * leaves the PID in service, and a new autotune while in automatic.
 */
#include "test_util.h"

#include <time.h>

#include "pdt_fb_autotune.h"
#include "sim_process.h"

#define R(x) ((pdt_real_t)(x))

/* The plant: K e^{-Td s} / (tau s + 1) around an operating point. */
#define PLANT_K    2.0
#define PLANT_TAU  4.0
#define PLANT_TD   1.55
#define PLANT_PV0  20.0 /* pv when u = 0 */
#define SCAN       0.1  /* s */
#define U0         30.0 /* output in service at the start */
#define NOISE      0.01 /* half width of the uniform pv noise */
#define MAX_CYCLES 20000

typedef struct plant {
    sim_plant_t sim;
    double hist[64]; /* the simulator's input history */
    double load;     /* disturbance added to the plant's input */
    sim_rng64_t rng;
} plant_t;

/* At rest with the output held at u_rest. */
static void plant_init(plant_t *p, double u_rest)
{
    const double lag[1] = {PLANT_TAU};
    const sim_plant_desc_t d = sim_plant_desc_lags(PLANT_K, lag, 1u, PLANT_TD);
    assert_int_equal(
        sim_plant_init(&p->sim, &d, SCAN, u_rest, PLANT_PV0 + PLANT_K * u_rest, p->hist, 64u), 0);
    p->load = 0.0;
    p->rng = sim_rng64_seed(12345u);
}

/* pv read in this cycle, with noise uniform in [-NOISE, NOISE). */
static pdt_real_t plant_pv(plant_t *p)
{
    return (pdt_real_t)(sim_plant_output(&p->sim) +
                        NOISE * (2.0 * sim_rng64_uniform(&p->rng) - 1.0));
}

/* The output u applied from this cycle to the next. */
static void plant_apply(plant_t *p, double u)
{
    sim_plant_apply(&p->sim, u + p->load);
}

/* The instance with guards after it. */
typedef struct harness {
    pdt_fb_autotune_t fb;
    pdt_real_t canary[CANARY_COUNT];
    plant_t plant;
    double worst_s; /* longest cycle seen, s */
    long cycles;
} harness_t;

static harness_t *H;

static int setup(void **state)
{
    H = test_malloc(sizeof *H);
    pdt_fb_autotune_init(&H->fb);
    canary_fill(H->canary, CANARY_COUNT);
    plant_init(&H->plant, U0);
    H->worst_s = 0.0;
    H->cycles = 0;
    /* A step of +5 on a gain of 2: pv 80 -> 90. */
    pdt_fb_autotune_t *fb = &H->fb;
    fb->rScanPeriod = R(SCAN);
    fb->udiDecimation = 2u;
    fb->udiSamples = 200u; /* 40 s at 0.2 s: 10 time constants */
    fb->udiSettle = 20u;
    fb->iExperiment = (int16_t)PDT_EXCITE_STEP;
    fb->rAmplitude = R(5.0);
    fb->rOutMin = R(0.0);
    fb->rOutMax = R(100.0);
    fb->rPvMin = R(0.0);
    fb->rPvMax = R(200.0);
    fb->rOutputNow = R(U0);
    *state = H;
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    canary_check(H->canary, CANARY_COUNT);
    test_free(H);
    H = NULL;
    return 0;
}

/* One PLC cycle: read pv, call the block, apply its output while busy or
 * in automatic (the manual output otherwise). */
static void cycle(harness_t *h)
{
    pdt_fb_autotune_t *fb = &h->fb;
    fb->rPV = plant_pv(&h->plant);
    clock_t t0 = clock();
    assert_int_equal(pdt_fb_autotune(fb), PDT_OK);
    double dt = (double)(clock() - t0) / CLOCKS_PER_SEC;
    if (dt > h->worst_s) {
        h->worst_s = dt;
    }
    h->cycles++;
    double u = fb->xBusy || fb->xAutoActive ? (double)fb->rOutput : (double)fb->rOutputNow;
    plant_apply(&h->plant, u);
    /* The end flags exclude each other and Busy. */
    int ends = (int)fb->xDone + (int)fb->xError + (int)fb->xCommandAborted;
    assert_true(ends <= 1);
    assert_false(fb->xBusy && ends != 0);
    assert_false(fb->xBusy && fb->xAutoActive);
    assert_true(fb->sStatus[PDT_FB_AUTOTUNE_STATUS_LEN - 1u] == '\0');
    if (!fb->xError) {
        assert_int_equal(fb->iErrorID, 0);
    }
}

/* Cycles until Busy falls (or the limit); returns the cycles run. */
static long run_until_idle(harness_t *h, long limit)
{
    long n = 0;
    int last_phase = h->fb.iPhase;
    while (h->fb.xBusy && n < limit) {
        cycle(h);
        n++;
        /* The phases only move forward. */
        assert_true(h->fb.iPhase >= last_phase);
        last_phase = h->fb.iPhase;
    }
    assert_false(h->fb.xBusy);
    return n;
}

static void start_edge(harness_t *h)
{
    h->fb.xExecute = true;
    cycle(h);
}

static void test_null_and_init(void **state)
{
    harness_t *h = *state;
    assert_int_equal(pdt_fb_autotune(NULL), PDT_ERR_ARG);
    pdt_fb_autotune_init(NULL);
    pdt_fb_autotune_t *fb = &h->fb;
    pdt_fb_autotune_init(fb);
    assert_false(fb->xExecute || fb->xAbort || fb->xBusy || fb->xDone || fb->xError ||
                 fb->xCommandAborted || fb->xModelValid || fb->xGainsValid);
    assert_true(fb->rScanPeriod == R(0.1));
    assert_int_equal(fb->udiDecimation, 1);
    assert_int_equal(fb->iExperiment, PDT_EXCITE_STEP);
    assert_int_equal(fb->iModel, PDT_FB_AUTOTUNE_MODEL_AUTO);
    assert_int_equal(fb->iRule, PDT_TUNE_SIMC);
    assert_int_equal(fb->iForm, PDT_TUNE_PI);
    assert_true(fb->rFitMin == R(0.0));
    assert_true(fb->rMsMax == R(2.0));
    assert_false(fb->xAuto || fb->xAutoActive || fb->xLimited);
    assert_true(fb->rSpWeightP == R(1.0) && fb->rSpWeightD == R(0.0) && fb->rRateMax == R(0.0) &&
                fb->rTrackTime == R(0.0));
    assert_int_equal(fb->iAntiWindup, PDT_PID_AW_BACK_CALC);
    assert_int_equal(fb->iPidStatus, 0);
    assert_true(fb->rOutMax == R(100.0));
    assert_int_equal(fb->iPhase, 0);
    assert_int_equal(fb->iErrorID, 0);
    assert_string_equal(fb->sStatus, "idle");
}

/* The instance holds everything: workspace big enough for every model and
 * criterion at full capacity, aligned, and a size worth reporting. */
static void test_instance_size(void **state)
{
    harness_t *h = *state;
    const pdt_cost_kind_t kinds[] = {PDT_COST_SIMULATION, PDT_COST_PREDICTION, PDT_COST_FREQUENCY,
                                     PDT_COST_COMBINED};
    for (int model = 0; model <= 2; model++) { /* 0: order_auto, the default */
        for (size_t k = 0; k < sizeof kinds / sizeof kinds[0]; k++) {
            pdt_autotune_config_t c;
            pdt_autotune_config_default(&c);
            c.Ts = R(0.1);
            c.capacity = PDT_FB_AUTOTUNE_CAPACITY;
            c.order_auto = model == 0;
            c.ident.model = model == 0 ? PDT_MODEL_FOPDT : (pdt_model_kind_t)model;
            c.ident.cost = kinds[k];
            size_t need = pdt_autotune_workspace_size(&c);
            assert_true(need > 0u);
            assert_true(need <= sizeof h->fb.internal.work);
        }
    }
    assert_int_equal((uintptr_t)h->fb.internal.work % sizeof(pdt_real_t), 0);
    /* The public part is what the ST declaration lists, in its order, each
     * field at the next offset its own alignment allows (as a PLC lays out
     * an FB instance): nothing hidden, nothing reordered. */
#define F(name)                                                                                    \
    {                                                                                              \
        offsetof(pdt_fb_autotune_t, name), sizeof(((pdt_fb_autotune_t *)0)->name), #name           \
    }
    static const struct {
        size_t off, size;
        const char *name;
    } fields[] = {
        F(xExecute),
        F(xAbort),
        F(xAuto),
        F(rPV),
        F(rSetpoint),
        F(rOutputNow),
        F(rScanPeriod),
        F(udiDecimation),
        F(udiSamples),
        F(udiSettle),
        F(udiEvalsPerScan),
        F(iExperiment),
        F(iModel),
        F(rAmplitude),
        F(rExciteTime),
        F(rFrequency),
        F(rHysteresis),
        F(rOutMin),
        F(rOutMax),
        F(rPvMin),
        F(rPvMax),
        F(rTimeLimit),
        F(iRule),
        F(iForm),
        F(rFitMin),
        F(rMsMax),
        F(rSpWeightP),
        F(rSpWeightD),
        F(rRateMax),
        F(rTrackTime),
        F(iAntiWindup),
        F(rOutput),
        F(xBusy),
        F(xDone),
        F(xError),
        F(xCommandAborted),
        F(iErrorID),
        F(iPhase),
        F(sStatus),
        F(xModelValid),
        F(xGainsValid),
        F(xIntegrating),
        F(rGain),
        F(rTau1),
        F(rTau2),
        F(rZeta),
        F(rDeadTime),
        F(rFit),
        F(rKc),
        F(rTi),
        F(rTd),
        F(rTf),
        F(rMs),
        F(xAutoActive),
        F(xLimited),
        F(iPidStatus),
        F(internal),
    };
#undef F
    size_t next = 0u;
    for (size_t i = 0; i < sizeof fields / sizeof fields[0]; i++) {
        size_t align = fields[i].size;
        if (i + 1 == sizeof fields / sizeof fields[0]) {
            align = 8u; /* the internal part: 8-byte aligned (uint64_t inside) */
        } else if (align == PDT_FB_AUTOTUNE_STATUS_LEN) {
            align = 1u; /* STRING: bytes */
        }
        next = (next + align - 1u) / align * align;
        if (fields[i].off != next) {
            fail_msg("%s at %zu, the declaration puts it at %zu", fields[i].name, fields[i].off,
                     next);
        }
        next += fields[i].size;
    }
    assert_int_equal(next, sizeof(pdt_fb_autotune_t));
    assert_true(sizeof(pdt_fb_autotune_t) ==
                offsetof(pdt_fb_autotune_t, internal) + sizeof(pdt_fb_autotune_internal_t));
    print_message("instance: %zu bytes (public part %zu, autotune %zu, workspace %zu) "
                  "for %u samples, pdt_real_t %zu bytes\n",
                  sizeof(pdt_fb_autotune_t), offsetof(pdt_fb_autotune_t, internal),
                  sizeof(pdt_autotune_t), sizeof h->fb.internal.work,
                  (unsigned)PDT_FB_AUTOTUNE_CAPACITY, sizeof(pdt_real_t));
}

static void test_idle_follows_manual(void **state)
{
    harness_t *h = *state;
    pdt_fb_autotune_t *fb = &h->fb;
    for (int i = 0; i < 20; i++) {
        fb->rOutputNow = R(U0 + 0.5 * i);
        cycle(h);
        assert_false(fb->xBusy);
        assert_true(fb->rOutput == fb->rOutputNow);
        assert_int_equal(fb->iPhase, 0);
    }
    /* Abort without a command does nothing. */
    fb->xAbort = true;
    cycle(h);
    assert_false(fb->xCommandAborted || fb->xBusy);
    assert_string_equal(fb->sStatus, "idle");
}

/* The SIMC gains of the true plant for the block's configuration. */
static pdt_tune_result_t true_gains(const pdt_fb_autotune_t *fb)
{
    const pdt_model_t m = model_fopdt(PLANT_K, PLANT_TAU, PLANT_TD);
    pdt_tune_config_t tc;
    pdt_tune_config_default(&tc);
    tc.rule = (pdt_tune_rule_t)fb->iRule;
    tc.form = (pdt_tune_form_t)fb->iForm;
    pdt_tune_result_t r;
    assert_int_equal(pdt_tune_compute(&m, R(100.0), &tc, &r), PDT_OK);
    return r;
}

static void check_model_and_gains(const pdt_fb_autotune_t *fb)
{
    assert_true(fb->xModelValid);
    assert_true(fb->xGainsValid);
    assert_false(fb->xIntegrating);
    assert_close(fb->rGain, PLANT_K, 0.02, 0.0);
    assert_close(fb->rTau1, PLANT_TAU, 0.05, 0.0);
    assert_close(fb->rDeadTime, PLANT_TD, 0.0, 0.1);
    assert_true(fb->rTau2 == R(0.0));
    assert_true(fb->rFit > R(95.0));
    pdt_tune_result_t t = true_gains(fb);
    assert_close(fb->rKc, t.ideal.Kc, 0.05, 0.0);
    assert_close(fb->rTi, t.ideal.tauI, 0.05, 0.0);
    assert_close(fb->rTd, t.ideal.tauD, 0.0, 1e-6);
    assert_true(fb->rMs > R(1.0) && fb->rMs <= fb->rMsMax);
}

static void test_run_to_done(void **state)
{
    harness_t *h = *state;
    pdt_fb_autotune_t *fb = &h->fb;
    cycle(h);
    assert_false(fb->xBusy);
    /* The rising edge starts in its own cycle: Busy, settling, output held. */
    start_edge(h);
    assert_true(fb->xBusy);
    assert_false(fb->xDone || fb->xError);
    assert_int_equal(fb->iPhase, PDT_AUTOTUNE_SETTLE);
    assert_string_equal(fb->sStatus, "settling");
    assert_true(fb->rOutput == R(U0));
    /* The manual output moving while busy does not move the experiment. */
    fb->rOutputNow = R(U0 + 10.0);
    bool saw_step = false;
    bool saw_identify = false;
    long n = 0;
    while (fb->xBusy && n < MAX_CYCLES) {
        cycle(h);
        n++;
        if (fb->iPhase == PDT_AUTOTUNE_EXCITE && fb->rOutput == R(U0 + 5.0)) {
            saw_step = true;
        }
        if (fb->iPhase == PDT_AUTOTUNE_IDENTIFY) {
            saw_identify = true;
            assert_string_equal(fb->sStatus, "identifying");
            assert_true(fb->rOutput == R(U0));
        }
    }
    assert_true(saw_step);
    assert_true(saw_identify);
    assert_true(fb->xDone);
    assert_false(fb->xError);
    assert_int_equal(fb->iErrorID, 0);
    assert_int_equal(fb->iPhase, PDT_AUTOTUNE_DONE);
    assert_string_equal(fb->sStatus, "done");
    assert_close(fb->rOutput, U0, 1e-6, 0.0);
    check_model_and_gains(fb);
    print_message("done after %ld cycles; K %.4f tau %.4f Td %.4f fit %.2f%%; "
                  "Kc %.4f Ti %.4f Ms %.3f; longest cycle %.1f us\n",
                  n + 1, (double)fb->rGain, (double)fb->rTau1, (double)fb->rDeadTime,
                  (double)fb->rFit, (double)fb->rKc, (double)fb->rTi, (double)fb->rMs,
                  h->worst_s * 1e6);
    /* Done holds while Execute does, the output stays at the operating point. */
    for (int i = 0; i < 10; i++) {
        cycle(h);
        assert_true(fb->xDone);
        assert_false(fb->xBusy);
        assert_close(fb->rOutput, U0, 1e-6, 0.0);
    }
    /* The falling edge clears Done; the results stay for the PID. */
    fb->xExecute = false;
    cycle(h);
    assert_false(fb->xDone);
    assert_true(fb->xGainsValid);
    assert_string_equal(fb->sStatus, "done");
}

/* PLCopen: Execute dropped while busy does not stop the command, and Done
 * is then seen for exactly one cycle. */
static void test_execute_dropped_while_busy(void **state)
{
    harness_t *h = *state;
    pdt_fb_autotune_t *fb = &h->fb;
    start_edge(h);
    fb->xExecute = false;
    cycle(h);
    assert_true(fb->xBusy);
    run_until_idle(h, MAX_CYCLES);
    assert_true(fb->xDone);
    cycle(h);
    assert_false(fb->xDone);
    assert_true(fb->xGainsValid);
}

static void test_retrigger_after_done(void **state)
{
    harness_t *h = *state;
    pdt_fb_autotune_t *fb = &h->fb;
    start_edge(h);
    run_until_idle(h, MAX_CYCLES);
    assert_true(fb->xDone);
    pdt_real_t kc1 = fb->rKc;
    /* Execute still TRUE: no new command. */
    cycle(h);
    assert_false(fb->xBusy);
    fb->xExecute = false;
    cycle(h);
    /* A new rising edge: a new command with fresh outputs. */
    start_edge(h);
    assert_true(fb->xBusy);
    assert_false(fb->xDone);
    assert_false(fb->xModelValid || fb->xGainsValid);
    assert_true(fb->rKc == R(0.0));
    assert_int_equal(fb->iPhase, PDT_AUTOTUNE_SETTLE);
    run_until_idle(h, MAX_CYCLES);
    assert_true(fb->xDone);
    check_model_and_gains(fb);
    assert_close(fb->rKc, kc1, 0.05, 0.0);
}

/* A rising edge while busy is ignored: the command goes on. */
static void test_edge_while_busy_ignored(void **state)
{
    harness_t *h = *state;
    pdt_fb_autotune_t *fb = &h->fb;
    start_edge(h);
    for (int i = 0; i < 100; i++) {
        cycle(h);
    }
    int phase = fb->iPhase;
    assert_int_equal(phase, PDT_AUTOTUNE_EXCITE);
    fb->xExecute = false;
    cycle(h);
    fb->xExecute = true;
    cycle(h);
    assert_true(fb->xBusy);
    assert_int_equal(fb->iPhase, phase);
    run_until_idle(h, MAX_CYCLES);
    assert_true(fb->xDone);
}

static void test_pv_limit(void **state)
{
    harness_t *h = *state;
    pdt_fb_autotune_t *fb = &h->fb;
    /* pv rests at 80 and the step takes it to 90: the limit is at 83. */
    fb->rPvMax = R(PLANT_PV0 + PLANT_K * U0 + 3.0);
    start_edge(h);
    long n = run_until_idle(h, MAX_CYCLES);
    assert_true(n < 1000);
    assert_true(fb->xError);
    assert_false(fb->xDone || fb->xCommandAborted);
    assert_int_equal(fb->iErrorID, PDT_ERR_PV_LIMIT);
    assert_int_equal(fb->iPhase, PDT_AUTOTUNE_FAILED);
    assert_memory_equal(fb->sStatus, "error: ", 7);
    assert_false(fb->xModelValid || fb->xGainsValid);
    /* Back at the operating point, held. */
    assert_close(fb->rOutput, U0, 1e-6, 0.0);
    for (int i = 0; i < 5; i++) {
        cycle(h);
        assert_true(fb->xError);
        assert_int_equal(fb->iErrorID, PDT_ERR_PV_LIMIT);
        assert_close(fb->rOutput, U0, 1e-6, 0.0);
    }
    fb->xExecute = false;
    cycle(h);
    assert_false(fb->xError);
    assert_int_equal(fb->iErrorID, 0);
    /* After the limit is fixed, a new start works. */
    fb->rPvMax = R(200.0);
    start_edge(h);
    run_until_idle(h, MAX_CYCLES);
    if (!fb->xDone) {
        print_message("after the limit: error %d, phase %d, %s\n", (int)fb->iErrorID,
                      (int)fb->iPhase, fb->sStatus);
    }
    assert_true(fb->xDone);
}

static void test_time_limit(void **state)
{
    harness_t *h = *state;
    pdt_fb_autotune_t *fb = &h->fb;
    fb->rTimeLimit = R(10.0); /* the experiment needs 40 s */
    start_edge(h);
    long n = run_until_idle(h, MAX_CYCLES);
    assert_true(fb->xError);
    assert_int_equal(fb->iErrorID, PDT_ERR_TIMEOUT);
    assert_true(n >= 99 && n <= 101);
}

static void test_abort(void **state)
{
    harness_t *h = *state;
    pdt_fb_autotune_t *fb = &h->fb;
    start_edge(h);
    for (int i = 0; i < 100; i++) {
        cycle(h);
    }
    assert_true(fb->xBusy);
    assert_true(fb->rOutput == R(U0 + 5.0));
    fb->xAbort = true;
    cycle(h);
    assert_false(fb->xBusy);
    assert_true(fb->xCommandAborted);
    assert_false(fb->xError || fb->xDone);
    assert_int_equal(fb->iErrorID, 0);
    assert_int_equal(fb->iPhase, PDT_AUTOTUNE_FAILED);
    assert_string_equal(fb->sStatus, "aborted");
    assert_close(fb->rOutput, U0, 1e-6, 0.0);
    cycle(h);
    assert_true(fb->xCommandAborted);
    assert_close(fb->rOutput, U0, 1e-6, 0.0);
    /* While Abort is held, a start is refused as aborted. */
    fb->xExecute = false;
    cycle(h);
    assert_false(fb->xCommandAborted);
    start_edge(h);
    assert_false(fb->xBusy);
    assert_true(fb->xCommandAborted);
    assert_true(fb->rOutput == fb->rOutputNow);
    /* Abort released and the process back at rest (10 time constants at
     * the manual output): a new start runs to the end. */
    fb->xAbort = false;
    fb->xExecute = false;
    for (int i = 0; i < 400; i++) {
        cycle(h);
    }
    start_edge(h);
    assert_true(fb->xBusy);
    run_until_idle(h, MAX_CYCLES);
    assert_true(fb->xDone);
}

/* Abort in the identification phase, and in the same cycle as a start. */
static void test_abort_identify_and_same_cycle(void **state)
{
    harness_t *h = *state;
    pdt_fb_autotune_t *fb = &h->fb;
    start_edge(h);
    while (fb->xBusy && fb->iPhase != PDT_AUTOTUNE_IDENTIFY) {
        cycle(h);
    }
    fb->xAbort = true;
    cycle(h);
    assert_true(fb->xCommandAborted);
    assert_false(fb->xModelValid);
    assert_close(fb->rOutput, U0, 1e-6, 0.0);
    fb->xAbort = false;
    fb->xExecute = false;
    cycle(h);
    fb->xAbort = true;
    fb->xExecute = true;
    cycle(h);
    assert_false(fb->xBusy);
    assert_true(fb->xCommandAborted);
}

/* A bad parameter is refused in the start cycle: no Busy, the output stays
 * in service, ErrorID says why; the next good start runs. */
static void test_refused_start(void **state)
{
    harness_t *h = *state;
    pdt_fb_autotune_t *fb = &h->fb;
    struct {
        int what;
        pdt_status_t want;
    } cases[] = {
        {0, PDT_ERR_ARG},          /* scan period 0 */
        {1, PDT_ERR_ARG},          /* unknown rule */
        {2, PDT_ERR_ARG},          /* unknown form */
        {3, PDT_ERR_ARG},          /* unknown experiment */
        {4, PDT_ERR_ARG},          /* unknown model */
        {5, PDT_ERR_NOMEM},        /* more samples than the instance holds */
        {6, PDT_ERR_OUTPUT_LIMIT}, /* output in service above its limit */
        {7, PDT_ERR_OUTPUT_LIMIT}, /* step beyond the output limit */
        {8, PDT_ERR_BOUNDS},       /* pv limits inverted */
        {9, PDT_ERR_ARG},          /* Ms limit of 1 */
        {10, PDT_ERR_ARG},         /* negative time limit */
        {11, PDT_ERR_TOO_SHORT},   /* record too short */
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        switch (cases[i].what) {
        case 0:
            fb->rScanPeriod = R(0.0);
            break;
        case 1:
            fb->iRule = 7;
            break;
        case 2:
            fb->iForm = -1;
            break;
        case 3:
            fb->iExperiment = 0;
            break;
        case 4:
            fb->iModel = 3;
            break;
        case 5:
            fb->udiSamples = PDT_FB_AUTOTUNE_CAPACITY + 1u;
            break;
        case 6:
            fb->rOutputNow = R(101.0);
            break;
        case 7:
            fb->rAmplitude = R(80.0);
            break;
        case 8:
            fb->rPvMin = R(300.0);
            break;
        case 9:
            fb->rMsMax = R(1.0);
            break;
        case 10:
            fb->rTimeLimit = R(-1.0);
            break;
        case 11:
            fb->udiSamples = 30u;
            break;
        default:
            break;
        }
        start_edge(h);
        assert_false(fb->xBusy);
        assert_true(fb->xError);
        assert_int_equal(fb->iErrorID, cases[i].want);
        assert_int_equal(fb->iPhase, 0);
        assert_memory_equal(fb->sStatus, "refused: ", 9);
        assert_true(fb->rOutput == fb->rOutputNow);
        /* Held while Execute is, cleared with it; rOutput follows manual. */
        fb->rOutputNow = R(U0 - 1.0);
        cycle(h);
        assert_true(fb->xError);
        assert_true(fb->rOutput == R(U0 - 1.0));
        fb->xExecute = false;
        cycle(h);
        assert_false(fb->xError);
        /* Restore the good parameters. */
        pdt_fb_autotune_init(fb);
        fb->rScanPeriod = R(SCAN);
        fb->udiDecimation = 2u;
        fb->udiSamples = 200u;
        fb->udiSettle = 20u;
        fb->rPvMin = R(0.0);
        fb->rPvMax = R(200.0);
        fb->rOutputNow = R(U0);
    }
    plant_init(&h->plant, U0);
    start_edge(h);
    assert_true(fb->xBusy);
    run_until_idle(h, MAX_CYCLES);
    assert_true(fb->xDone);
}

/* A sensor failure (NaN) ends the command with an error, output safe. */
static void test_nonfinite_pv(void **state)
{
    harness_t *h = *state;
    pdt_fb_autotune_t *fb = &h->fb;
    start_edge(h);
    for (int i = 0; i < 60; i++) {
        cycle(h);
    }
    fb->rPV = R(NAN);
    assert_int_equal(pdt_fb_autotune(fb), PDT_OK);
    assert_false(fb->xBusy);
    assert_true(fb->xError);
    assert_int_equal(fb->iErrorID, PDT_ERR_NONFINITE);
    assert_close(fb->rOutput, U0, 1e-6, 0.0);
}

/* Gains refused by the fit limit: an error, with the model still shown. */
static void test_refused_tuning(void **state)
{
    harness_t *h = *state;
    pdt_fb_autotune_t *fb = &h->fb;
    fb->rFitMin = R(100.0); /* unreachable with noise */
    start_edge(h);
    run_until_idle(h, MAX_CYCLES);
    assert_true(fb->xError);
    assert_int_equal(fb->iErrorID, PDT_ERR_POOR_FIT);
    assert_true(fb->xModelValid);
    assert_false(fb->xGainsValid);
    assert_true(fb->rKc == R(0.0));
    assert_close(fb->rGain, PLANT_K, 0.02, 0.0);
    assert_close(fb->rOutput, U0, 1e-6, 0.0);
    assert_int_equal(fb->iPhase, PDT_AUTOTUNE_FAILED);
}

/* Other experiments and the SOPDT through the same block. */
static void test_prbs_sopdt_pid(void **state)
{
    harness_t *h = *state;
    pdt_fb_autotune_t *fb = &h->fb;
    fb->iExperiment = (int16_t)PDT_EXCITE_PRBS;
    fb->rAmplitude = R(3.0);
    fb->rExciteTime = R(1.0); /* chip 1 s: 127 s per period */
    fb->udiDecimation = 5u;   /* 0.5 s samples */
    fb->udiSamples = 300u;
    fb->iModel = (int16_t)PDT_MODEL_SOPDT;
    fb->iForm = (int16_t)PDT_TUNE_PID;
    start_edge(h);
    run_until_idle(h, MAX_CYCLES);
    assert_true(fb->xDone);
    assert_true(fb->xModelValid && fb->xGainsValid);
    assert_close(fb->rGain, PLANT_K, 0.03, 0.0);
    assert_true(fb->rFit > R(95.0));
    /* A FOPDT seen as SOPDT: the second lag is small or it is overdamped. */
    assert_true(fb->rTau2 < R(1.0) || fb->rZeta >= R(1.0));
    assert_true(fb->rTd >= R(0.0));
    print_message("PRBS SOPDT: K %.4f T1 %.4f T2 %.4f zeta %.3f Td %.4f fit %.2f%%; "
                  "PID Kc %.4f Ti %.4f Td %.4f Tf %.4f Ms %.3f; %ld cycles in all\n",
                  (double)fb->rGain, (double)fb->rTau1, (double)fb->rTau2, (double)fb->rZeta,
                  (double)fb->rDeadTime, (double)fb->rFit, (double)fb->rKc, (double)fb->rTi,
                  (double)fb->rTd, (double)fb->rTf, (double)fb->rMs, h->cycles);
}

/* Cycles in automatic; returns the largest |pv - rSetpoint| over the last
 * `tail` of them, and the largest pv - rSetpoint overall in *over. */
static double run_auto(harness_t *h, int cycles, int tail, double *over)
{
    pdt_fb_autotune_t *fb = &h->fb;
    double worst_tail = 0.0;
    double o = -1e30;
    for (int i = 0; i < cycles; i++) {
        cycle(h);
        assert_true(fb->xAutoActive);
        assert_int_equal(fb->iPidStatus, 0);
        assert_true(fb->rOutput >= fb->rOutMin && fb->rOutput <= fb->rOutMax);
        double e = (double)fb->rPV - (double)fb->rSetpoint;
        o = fmax(o, e);
        if (i >= cycles - tail) {
            worst_tail = fmax(worst_tail, fabs(e));
        }
    }
    if (over != NULL) {
        *over = o;
    }
    return worst_tail;
}

/* Done hands the gains to the PID at the operating point; automatic then
 * follows a set-point step and rejects a load step, and the transfers
 * between manual and automatic do not bump the output. */
static void test_pid_after_done(void **state)
{
    harness_t *h = *state;
    pdt_fb_autotune_t *fb = &h->fb;
    /* Automatic requested before any gains: nothing happens. */
    fb->xAuto = true;
    for (int i = 0; i < 5; i++) {
        cycle(h);
        assert_false(fb->xAutoActive);
        assert_true(fb->rOutput == fb->rOutputNow);
    }
    fb->xAuto = false;
    start_edge(h);
    run_until_idle(h, MAX_CYCLES);
    assert_true(fb->xDone && fb->xGainsValid);
    fb->xExecute = false;
    /* Manual: the PID tracks the output in service (U0) at the set-point
     * the operator has entered (a set-point changed in the cycle of the
     * switch would move the output by the P term, b = 1). */
    fb->rSetpoint = R(PLANT_PV0 + PLANT_K * U0);
    for (int i = 0; i < 20; i++) {
        cycle(h);
        assert_false(fb->xAutoActive);
        assert_int_equal(fb->iPidStatus, 0);
    }
    fb->xAuto = true;
    cycle(h);
    assert_true(fb->xAutoActive);
    assert_close(fb->rOutput, U0, 0.0, 0.05);
    double e = run_auto(h, 100, 100, NULL);
    assert_true(e < 0.1);
    /* A set-point step of +5: settles without much overshoot (SIMC PI). */
    double sp0 = (double)fb->rSetpoint;
    fb->rSetpoint = R(sp0 + 5.0);
    double over;
    e = run_auto(h, 600, 100, &over);
    print_message("set-point step +5: overshoot %.3f, |e| over the last 10 s %.4f\n", over, e);
    assert_true(e < 0.05);
    assert_true(over < 0.5);
    /* A load step of -3 output units: pv dips and comes back. */
    h->plant.load = -3.0;
    double dip = 0.0;
    for (int i = 0; i < 100; i++) {
        cycle(h);
        dip = fmax(dip, (double)fb->rSetpoint - (double)fb->rPV);
    }
    e = run_auto(h, 500, 100, NULL);
    print_message("load step -3: largest dip %.3f, |e| over the last 10 s %.4f, output %.3f\n", dip,
                  e, (double)fb->rOutput);
    assert_true(dip > 1.0);
    assert_true(e < 0.05);
    assert_close(fb->rOutput, U0 + 2.5 + 3.0, 0.0, 0.1);
    /* Automatic to manual: the program takes the last output as its manual
     * output; the block's output holds. */
    pdt_real_t last = fb->rOutput;
    fb->rOutputNow = last;
    fb->xAuto = false;
    cycle(h);
    assert_false(fb->xAutoActive);
    assert_true(fb->rOutput == last);
    /* Manual ramp, then automatic again: it continues from the manual output. */
    for (int i = 0; i < 50; i++) {
        fb->rOutputNow = R((double)last + 0.1 * i);
        cycle(h);
        assert_false(fb->xAutoActive);
    }
    pdt_real_t manual = fb->rOutputNow;
    fb->xAuto = true;
    cycle(h);
    assert_true(fb->xAutoActive);
    print_message("manual to automatic: manual %.4f, first automatic output %.4f\n", (double)manual,
                  (double)fb->rOutput);
    /* No bump: only one scan's control action on a pv still moving from
     * the ramp (Kc times its change, plus one integral increment). */
    assert_close(fb->rOutput, manual, 0.0, 0.25);
    e = run_auto(h, 600, 100, NULL);
    assert_true(e < 0.05);
}

/* In automatic: a failed sensor holds the output; a bad PID parameter keeps
 * the loop in manual until fixed; a refused start leaves the PID running;
 * a new autotune takes over and hands back to the PID at its end. */
static void test_pid_faults_and_retune(void **state)
{
    harness_t *h = *state;
    pdt_fb_autotune_t *fb = &h->fb;
    start_edge(h);
    run_until_idle(h, MAX_CYCLES);
    fb->xExecute = false;
    cycle(h);
    fb->rSetpoint = R(PLANT_PV0 + PLANT_K * U0);
    fb->xAuto = true;
    (void)run_auto(h, 100, 1, NULL);
    pdt_real_t held = fb->rOutput;
    pdt_real_t inf = R(1.0) / R(0.0);
    fb->rPV = inf - inf;
    assert_int_equal(pdt_fb_autotune(fb), PDT_OK);
    assert_int_equal(fb->iPidStatus, PDT_ERR_NONFINITE);
    assert_true(fb->xAutoActive);
    assert_true(fb->rOutput == held);
    cycle(h);
    assert_int_equal(fb->iPidStatus, 0);
    /* A bad parameter at the edge into automatic. */
    fb->xAuto = false;
    fb->rOutputNow = fb->rOutput;
    cycle(h);
    fb->iAntiWindup = 9;
    fb->xAuto = true;
    for (int i = 0; i < 3; i++) {
        cycle(h);
        assert_false(fb->xAutoActive);
        assert_int_equal(fb->iPidStatus, PDT_ERR_ARG);
    }
    fb->iAntiWindup = (int16_t)PDT_PID_AW_BOTH;
    cycle(h);
    assert_true(fb->xAutoActive);
    assert_int_equal(fb->internal.pid.cfg.antiwindup, PDT_PID_AW_BOTH);
    (void)run_auto(h, 50, 1, NULL);
    /* A refused start (bad scan period) does not stop the loop. */
    fb->rScanPeriod = R(-1.0);
    start_edge(h);
    assert_true(fb->xError);
    assert_false(fb->xBusy);
    assert_true(fb->xAutoActive);
    fb->xExecute = false;
    fb->rScanPeriod = R(SCAN);
    (void)run_auto(h, 20, 1, NULL);
    /* A new autotune from automatic: the output in service is its operating
     * point; at Done the PID resumes from there. */
    fb->rOutputNow = fb->rOutput;
    start_edge(h);
    assert_true(fb->xBusy);
    assert_false(fb->xAutoActive);
    run_until_idle(h, MAX_CYCLES);
    assert_true(fb->xDone);
    pdt_real_t op = fb->rOutput;
    cycle(h);
    assert_true(fb->xAutoActive);
    assert_close(fb->rOutput, op, 0.0, 1e-6);
    double e = run_auto(h, 400, 100, NULL);
    assert_true(e < 0.05);
}

static void test_relay(void **state)
{
    harness_t *h = *state;
    pdt_fb_autotune_t *fb = &h->fb;
    fb->iExperiment = (int16_t)PDT_EXCITE_RELAY;
    fb->rAmplitude = R(4.0);
    fb->rSetpoint = R(PLANT_PV0 + PLANT_K * U0 + 0.5);
    fb->rHysteresis = R(0.05);
    fb->udiDecimation = 2u;
    fb->udiSamples = 300u;
    start_edge(h);
    run_until_idle(h, MAX_CYCLES);
    assert_true(fb->xDone);
    assert_close(fb->rGain, PLANT_K, 0.05, 0.0);
    assert_close(fb->rDeadTime, PLANT_TD, 0.0, 0.2);
}

/* The glue entry points: refuse a block the PLC declared differently. */
static void test_ext_entry_points(void **state)
{
    harness_t *h = *state;
    pdt_fb_autotune_t *fb = &h->fb;
    uint32_t size = (uint32_t)sizeof *fb;
    fb->xExecute = true;
    assert_int_equal(pdt_fb_autotune_ext_init(NULL, size), PDT_ERR_ARG);
    assert_int_equal(pdt_fb_autotune_ext_cycle(NULL, size), PDT_ERR_ARG);
    assert_int_equal(pdt_fb_autotune_ext_init(fb, size - 8u), PDT_ERR_ARG);
    assert_int_equal(pdt_fb_autotune_ext_cycle(fb, size + 8u), PDT_ERR_ARG);
    void *odd = (char *)fb + 4;
    assert_int_equal(pdt_fb_autotune_ext_init(odd, size), PDT_ERR_ARG);
    assert_int_equal(pdt_fb_autotune_ext_cycle(odd, size), PDT_ERR_ARG);
    /* Nothing was done: still the harness's parameters, no edge seen. */
    assert_int_equal(fb->udiDecimation, 2);
    assert_false(fb->xBusy);
    assert_false(fb->internal.xExecutePrev);

    assert_int_equal(pdt_fb_autotune_ext_init(fb, size), PDT_OK);
    assert_int_equal(fb->udiDecimation, 1);
    assert_false(fb->xExecute);
    fb->rOutputNow = R(U0);
    fb->rPvMin = R(0.0);
    fb->rPvMax = R(200.0);
    fb->xExecute = true;
    fb->rPV = plant_pv(&h->plant);
    assert_int_equal(pdt_fb_autotune_ext_cycle(fb, size), PDT_OK);
    assert_true(fb->xBusy);
    assert_int_equal(fb->iPhase, PDT_AUTOTUNE_SETTLE);
}

/* An instance copied elsewhere while busy (as an online change may do)
 * stops safely instead of following the old copy's pointers. */
static void test_moved_while_busy(void **state)
{
    harness_t *h = *state;
    start_edge(h);
    for (int i = 0; i < 100; i++) {
        cycle(h);
    }
    assert_true(h->fb.xBusy);
    harness_t *h2 = test_malloc(sizeof *h2);
    memcpy(h2, h, sizeof *h2);
    h2->plant.sim.hist = h2->plant.hist; /* the plant moves with its history */
    /* The old copy is gone: poison it so any use through a stale pointer
     * would show. */
    memset(&h->fb.internal.work, 0xA5, sizeof h->fb.internal.work);
    pdt_fb_autotune_t *fb = &h2->fb;
    cycle(h2);
    assert_false(fb->xBusy);
    assert_true(fb->xError);
    assert_int_equal(fb->iErrorID, PDT_ERR_STATE);
    assert_int_equal(fb->iPhase, PDT_AUTOTUNE_FAILED);
    assert_string_equal(fb->sStatus, "error: instance moved");
    assert_true(fb->rOutput == R(U0));
    cycle(h2);
    assert_true(fb->rOutput == R(U0));
    /* A new start in the new place works. */
    fb->xExecute = false;
    for (int i = 0; i < 400; i++) {
        cycle(h2);
    }
    start_edge(h2);
    run_until_idle(h2, MAX_CYCLES);
    assert_true(fb->xDone);
    canary_check(h2->canary, CANARY_COUNT);
    test_free(h2);
}

#define T(f) cmocka_unit_test_setup_teardown(f, setup, teardown)

int main(void)
{
    const struct CMUnitTest tests[] = {
        T(test_null_and_init),
        T(test_instance_size),
        T(test_idle_follows_manual),
        T(test_run_to_done),
        T(test_execute_dropped_while_busy),
        T(test_retrigger_after_done),
        T(test_edge_while_busy_ignored),
        T(test_pv_limit),
        T(test_time_limit),
        T(test_abort),
        T(test_abort_identify_and_same_cycle),
        T(test_refused_start),
        T(test_nonfinite_pv),
        T(test_refused_tuning),
        T(test_prbs_sopdt_pid),
        T(test_pid_after_done),
        T(test_pid_faults_and_retune),
        T(test_relay),
        T(test_ext_entry_points),
        T(test_moved_while_busy),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
