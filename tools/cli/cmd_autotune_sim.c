/* pdtfit autotune-sim: the on-device autotune run scan by scan against a
 * simulated plant (tools/sim/sim_plant.h). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "loop_sim.h"
#include "sim_plant.h"
#include "sim_rng.h"
#include "tune_opts.h"

#define PI_VALUE 3.14159265358979323846

/* --model auto (the default): the autotune's own default, order_auto (both
 * orders, the one the evidence supports); fopdt or sopdt fix the order. */
static const char *const at_model_names[] = {"fopdt", "sopdt", "auto", NULL};
#define AT_MODEL_AUTO (PDT_MODEL_SOPDT + 1)

static const char *const kind_names[] = {"step", "pulse", "chirp", "prbs", "relay", NULL};
static const char *const phase_names[] = {"settle", "excite", "identify", "tune"};
static const char *const failed_names[] = {"init", "settle", "excite", "identify",
                                           "tune", "done",   "failed"};

typedef struct at_args {
    tune_opts_t t;
    cli_list_t lags, zeros;
    int have_gain, have_lags, have_ts, have_sp, model, kind, integrating, have_wn;
    double gain, delay, amplitude, Ts, noise, u0, y0, sp, wn, zeta, shift_max, spread_max;
    int have_shift_max, have_spread_max, have_repeats, closed, have_gains, have_dpasses, act_pos;
    uint64_t drift_passes;
    cli_list_t gains; /* --initial-gains Kc,Ti[,Td] */
    uint64_t repeats;
    int have_lim[4];
    double lim[4]; /* pv_min, pv_max, u_min, u_max */
    uint64_t seed, decimation, capacity, evaluations;
    const char *trace, *load_step;
    fault_cfg_t fault;
} at_args_t;

static void parse(at_args_t *a, int argc, char **argv)
{
    const cli_opt_t rows[] = {
        {"--plant-gain", OPT_REAL, &a->gain, &a->have_gain, CHK_NONZERO, 0, 0, NULL,
         "a gain other than 0", 0},
        {"--plant-lags", OPT_LIST, &a->lags, &a->have_lags, CHK_GT0, 0, 0, NULL,
         "every time constant must be > 0", 0},
        {"--plant-zeros", OPT_LIST, &a->zeros, NULL, CHK_NONZERO, 0, 0, NULL,
         "a zero time constant cannot be 0", 0},
        {"--plant-delay", OPT_REAL, &a->delay, NULL, CHK_GE0, 0, 0, NULL, "a dead time >= 0 s", 0},
        {"--plant-wn", OPT_REAL, &a->wn, &a->have_wn, CHK_GT0, 0, 0, NULL,
         "a natural frequency > 0 rad/s", 0},
        {"--plant-zeta", OPT_REAL, &a->zeta, NULL, CHK_GT0, 0, 0, NULL, "a damping > 0", 0},
        {"--plant-integrating", OPT_FLAG, &a->integrating, NULL, 0, 0, 0, NULL, NULL, 0},
        {"--experiment", OPT_CHOICE, &a->kind, NULL, 0, PDT_EXCITE_STEP, 0, kind_names,
         "experiment", 0},
        {"--amplitude", OPT_REAL, &a->amplitude, NULL, CHK_NONZERO, 0, 0, NULL,
         "an amplitude other than 0", 0},
        {"--scan-period", OPT_REAL, &a->Ts, &a->have_ts, CHK_GT0, 0, 0, NULL, "a period > 0 s", 0},
        {"--decimation", OPT_UINT, &a->decimation, NULL, 0, 1, 1000000, NULL,
         "a whole number 1 .. 1000000", 0},
        {"--capacity", OPT_UINT, &a->capacity, NULL, 0, 1, 100000000, NULL,
         "a whole number 1 .. 100000000", 0},
        {"--model", OPT_CHOICE, &a->model, NULL, 0, PDT_MODEL_FOPDT, 0, at_model_names, "model", 0},
        {"--evaluations", OPT_UINT, &a->evaluations, NULL, 0, 1, UINT32_MAX, NULL,
         "a whole number >= 1", 0},
        {"--noise", OPT_REAL, &a->noise, NULL, CHK_GE0, 0, 0, NULL, "a standard deviation >= 0", 0},
        {"--seed", OPT_UINT, &a->seed, NULL, 0, 0, UINT64_MAX, NULL, "a whole number >= 0", 0},
        {"--u0", OPT_REAL, &a->u0, NULL, CHK_ANY, 0, 0, NULL, NULL, 0},
        {"--y0", OPT_REAL, &a->y0, NULL, CHK_ANY, 0, 0, NULL, NULL, 0},
        {"--setpoint", OPT_REAL, &a->sp, &a->have_sp, CHK_ANY, 0, 0, NULL, NULL, 0},
        {"--pv-min", OPT_REAL, &a->lim[0], &a->have_lim[0], CHK_ANY, 0, 0, NULL, NULL, 0},
        {"--pv-max", OPT_REAL, &a->lim[1], &a->have_lim[1], CHK_ANY, 0, 0, NULL, NULL, 0},
        {"--u-min", OPT_REAL, &a->lim[2], &a->have_lim[2], CHK_ANY, 0, 0, NULL, NULL, 0},
        {"--u-max", OPT_REAL, &a->lim[3], &a->have_lim[3], CHK_ANY, 0, 0, NULL, NULL, 0},
        {"--trace", OPT_TEXT, &a->trace, NULL, 0, 0, 0, NULL, NULL, 0},
        {"--shift-max", OPT_REAL, &a->shift_max, &a->have_shift_max, CHK_GE0, 0, 0, NULL,
         "a fraction >= 0", 0},
        {"--relay-spread-max", OPT_REAL, &a->spread_max, &a->have_spread_max, CHK_GE0, 0, 0, NULL,
         "a fraction >= 0", 0},
        {"--repeats", OPT_UINT, &a->repeats, &a->have_repeats, 0, 0, 100, NULL,
         "a whole number 0 .. 100", 0},
        {"--drift-passes", OPT_UINT, &a->drift_passes, &a->have_dpasses, 0, 0, 100, NULL,
         "a whole number 0 .. 100", 0},
        {"--actuator-position", OPT_FLAG, &a->act_pos, NULL, 0, 0, 0, NULL, NULL, 0},
        {"--closed-loop", OPT_FLAG, &a->closed, NULL, 0, 0, 0, NULL, NULL, 0},
        {"--initial-gains", OPT_LIST, &a->gains, &a->have_gains, CHK_ANY, 0, 0, NULL, NULL, 0},
        {"--load-step", OPT_TEXT, &a->load_step, &a->fault.has_load, 0, 0, 0, NULL, NULL, 0},
        {"--drift", OPT_REAL, &a->fault.drift, NULL, CHK_ANY, 0, 0, NULL, NULL, 0},
        {"--quantise", OPT_REAL, &a->fault.quant, NULL, CHK_GT0, 0, 0, NULL, "a step > 0", 0},
        {"--u-rate", OPT_REAL, &a->fault.u_rate, NULL, CHK_GT0, 0, 0, NULL, "a rate > 0 per s", 0},
        {"--stiction", OPT_REAL, &a->fault.stiction, NULL, CHK_GT0, 0, 0, NULL, "a band > 0", 0},
    };
    cli_opt_t tab[CLI_MAX_OPTS];
    const size_t n = sizeof rows / sizeof rows[0];
    memcpy(tab, rows, sizeof rows);
    cli_parser_t p = {
        "autotune-sim", CMD_AUTOTUNE, tab, n + tune_opts_table(&a->t, tab + n, 1), NULL, {0},
        NULL,           NULL,         0};
    cli_parse(&p, argc, argv);
}

static void check_args(const at_args_t *a)
{
    const char *cmd = "autotune-sim";
    if (!a->have_gain) cli_fail(EXIT_USAGE, "%s: --plant-gain K is required", cmd);
    const int poles = a->lags.n + (a->have_wn ? 2 : 0) + (a->integrating ? 1 : 0);
    if (!a->have_lags && !a->have_wn && !a->integrating)
        cli_fail(EXIT_USAGE,
                 "%s: --plant-lags T1,T2,... (or --plant-wn, --plant-integrating) is "
                 "required",
                 cmd);
    if (a->zeros.n > poles)
        cli_fail(EXIT_USAGE, "%s: more zeros (%d) than poles (%d): the plant is improper", cmd,
                 a->zeros.n, poles);
    if (a->have_wn && !(a->zeta > 0.0))
        cli_fail(EXIT_USAGE, "%s: --plant-wn needs --plant-zeta Z > 0", cmd);
    if (a->have_sp && a->kind != PDT_EXCITE_RELAY)
        cli_fail(EXIT_USAGE, "%s: --setpoint is an option of --experiment relay only", cmd);
    if ((a->have_lim[0] && a->have_lim[1] && a->lim[0] > a->lim[1]) ||
        (a->have_lim[2] && a->have_lim[3] && a->lim[2] > a->lim[3]))
        cli_fail(EXIT_USAGE, "%s: a lower limit lies above its upper limit", cmd);
    tune_opts_check(cmd, &a->t);
    if (a->closed && !a->have_gains)
        cli_fail(EXIT_USAGE, "%s: --closed-loop needs --initial-gains Kc,Ti[,Td]", cmd);
    if (a->have_gains && !a->closed)
        cli_fail(EXIT_USAGE, "%s: --initial-gains is an option of --closed-loop", cmd);
    if (a->closed && (a->gains.n < 2 || a->gains.n > 3 || a->gains.v[0] == 0.0 ||
                      !(a->gains.v[1] > 0.0) || (a->gains.n == 3 && a->gains.v[2] < 0.0)))
        cli_fail(EXIT_USAGE,
                 "%s: --initial-gains takes Kc,Ti[,Td] with Kc != 0, Ti > 0 s and "
                 "Td >= 0 s",
                 cmd);
    if (a->closed && a->kind == PDT_EXCITE_RELAY)
        cli_fail(EXIT_USAGE,
                 "%s: --closed-loop moves the set-point: --experiment step, pulse, "
                 "chirp or prbs",
                 cmd);
}

/* --load-step T:D, a time >= 0 s and a load in input units. */
static void parse_load(at_args_t *a)
{
    if (!a->fault.has_load) return;
    const char *s = a->load_step, *colon = strchr(s, ':');
    char t[64];
    const size_t n = colon ? (size_t)(colon - s) : 0u;
    if (!colon || n == 0u || n >= sizeof t)
        cli_fail(EXIT_USAGE, "autotune-sim: --load-step takes T:D (time s, load in input units)");
    memcpy(t, s, n);
    t[n] = '\0';
    if (cli_parse_real(t, &a->fault.load_t) != 0 || !(a->fault.load_t >= 0.0) ||
        cli_parse_real(colon + 1, &a->fault.load) != 0)
        cli_fail(EXIT_USAGE,
                 "autotune-sim: --load-step takes T:D with a time T >= 0 s and a "
                 "finite load D, not \"%s\"",
                 s);
}

/* The simulated process as the shared simulator takes it. */
static sim_plant_desc_t plant_desc(const at_args_t *a)
{
    sim_plant_desc_t d;
    memset(&d, 0, sizeof d);
    d.K = a->gain;
    d.lags = a->lags.v;
    d.n_lags = (size_t)a->lags.n;
    d.zeros = a->zeros.v;
    d.n_zeros = (size_t)a->zeros.n;
    d.delay = a->delay;
    d.wn = a->have_wn ? a->wn : 0.0;
    d.zeta = a->have_wn ? a->zeta : 0.0;
    d.integrating = a->integrating != 0;
    return d;
}

/* The plant's time scales: the sum of its lags (a complex pair counts
 * 2 zeta / wn, its a / b; an integrator the sum again, at least 1 s) and
 * the largest. */
static void time_scales(const at_args_t *a, double *sum_out, double *T1_out)
{
    double sum = 0.0, T1 = 0.0;
    for (int k = 0; k < a->lags.n; k++) {
        sum += a->lags.v[k];
        if (a->lags.v[k] > T1) T1 = a->lags.v[k];
    }
    if (a->have_wn) {
        const double Tp = 2.0 * a->zeta / a->wn > 1.0 / a->wn ? 2.0 * a->zeta / a->wn : 1.0 / a->wn;
        sum += Tp;
        T1 = Tp > T1 ? Tp : T1;
    }
    if (a->integrating) {
        const double Ti = sum > 1.0 ? sum : 1.0;
        sum += Ti;
        T1 = Ti > T1 ? Ti : T1;
    }
    *sum_out = sum;
    *T1_out = T1;
}

/* The experiment's settings from the plant's time scales; returns the
 * experiment's time after the settle window, s. */
static double experiment_config(const at_args_t *a, double Ts_id, pdt_excite_config_t *ec)
{
    double sum, T1;
    time_scales(a, &sum, &T1);
    const double T_scale = sum + a->delay, T_settle = 4.0 * sum + a->delay;
    const sim_plant_desc_t desc = plant_desc(a);
    const double wu = sim_plant_ultimate_w(&desc, T_scale);
    const double amp = fabs(a->amplitude);
    pdt_excite_config_default(ec, (pdt_excite_kind_t)a->kind);
    switch (a->kind) {
    case PDT_EXCITE_STEP:
        ec->amplitude = (pdt_real_t)a->amplitude;
        ec->duration = 0;
        return 2.0 * T_settle;
    case PDT_EXCITE_PULSE: {
        /* Whole identification samples, as the PRBS chips. */
        const double on = floor(0.5 * T_settle / Ts_id + 0.5);
        ec->amplitude = (pdt_real_t)a->amplitude;
        ec->t_on = (pdt_real_t)((on < 1.0 ? 1.0 : on) * Ts_id);
        ec->t_off = (pdt_real_t)(floor(T_settle / Ts_id + 0.5) * Ts_id);
        ec->count = 1;
        return 2.0 * T_settle;
    }
    case PDT_EXCITE_CHIRP: {
        double f1 = (wu > 0.0 ? 1.5 * wu : 3.0 / T1) / (2.0 * PI_VALUE);
        if (f1 > 0.25 / a->Ts) f1 = 0.25 / a->Ts;
        ec->amplitude = (pdt_real_t)amp;
        ec->f0 = 0;
        ec->f1 = (pdt_real_t)f1;
        ec->duration = (pdt_real_t)(5.0 * T_settle);
        return 6.0 * T_settle;
    }
    case PDT_EXCITE_PRBS: {
        /* Chips of whole identification samples: the recorder averages
         * each sample, so a change inside one would be smeared. */
        const double chips = floor(T1 / Ts_id + 0.5);
        const double hold = (chips < 1.0 ? 1.0 : chips) * (double)a->decimation;
        ec->amplitude = (pdt_real_t)amp;
        ec->prbs_bits = 6;
        ec->prbs_hold = hold > 1e8 ? 100000000u : (uint32_t)hold;
        ec->periods = 1;
        return 63.0 * (double)ec->prbs_hold * a->Ts + T_settle;
    }
    default: {
        const double Pu = wu > 0.0 ? 2.0 * PI_VALUE / wu : 2.0 * T_scale;
        ec->d = (pdt_real_t)amp;
        ec->setpoint = (pdt_real_t)(a->have_sp ? a->sp : a->y0);
        ec->eps = (pdt_real_t)(3.0 * a->noise);
        ec->action = a->gain > 0.0 ? PDT_EXCITE_REVERSE : PDT_EXCITE_DIRECT;
        return 8.0 * Pu + T_settle;
    }
    }
}

static void autotune_config(at_args_t *a, pdt_autotune_config_t *cfg)
{
    double sum, T1;
    time_scales(a, &sum, &T1);
    if (!a->have_ts) a->Ts = (sum + a->delay) / 200.0;
    if (!a->decimation) a->decimation = 4u;
    const uint32_t settle = 20;
    pdt_autotune_config_default(cfg);
    const double window = experiment_config(a, a->Ts * (double)a->decimation, &cfg->excite);
    if (!a->capacity) {
        const double c = (double)settle + ceil(window / (a->Ts * (double)a->decimation));
        a->capacity = c > 1e8 ? 100000000u : (uint64_t)c;
    }
    cfg->Ts = (pdt_real_t)a->Ts;
    cfg->decimation = (uint32_t)a->decimation;
    cfg->capacity = (size_t)a->capacity;
    cfg->settle = settle;
    if (a->have_lim[0]) cfg->pv_min = (pdt_real_t)a->lim[0];
    if (a->have_lim[1]) cfg->pv_max = (pdt_real_t)a->lim[1];
    if (a->have_lim[2]) cfg->u_min = (pdt_real_t)a->lim[2];
    if (a->have_lim[3]) cfg->u_max = (pdt_real_t)a->lim[3];
    if (a->model != AT_MODEL_AUTO) {
        cfg->order_auto = false;
        cfg->ident.model = (pdt_model_kind_t)a->model;
    }
    cfg->ident.seed = a->seed;
    if (a->evaluations) cfg->ident.max_evaluations = (uint32_t)a->evaluations;
    if (a->closed) {
        /* The set-point moves by the open loop's response to the same
         * input change. */
        const double scale = fabs(a->gain) * (a->integrating ? sum + a->delay : 1.0);
        cfg->excite.amplitude = (pdt_real_t)(a->amplitude * scale);
    }
    if (a->have_shift_max) cfg->shift_max = (pdt_real_t)a->shift_max;
    if (a->have_spread_max) cfg->relay_spread_max = (pdt_real_t)a->spread_max;
    if (a->have_repeats) cfg->repeats = (uint32_t)a->repeats;
    if (a->have_dpasses) cfg->drift_passes = (uint32_t)a->drift_passes;
    cfg->actuator_position = a->act_pos != 0;
    tune_opts_config(&a->t, &cfg->tune);
}

/* One run: the autotune's state, the plant and what the loop counted. */
typedef struct at_run {
    pdt_autotune_config_t cfg;
    pdt_autotune_result_t res;
    pdt_status_t st;
    int initialised;
    uint32_t phase_scans[4];
    uint64_t scans;
    int has_loop;
    loop_figs_t loop;
    pdt_pid_t pid;       /* --closed-loop: the controller in service */
    pdt_tune_gains_t g0; /* its initial gains */
    loop_figs_t loop0;   /* and their loop on the true plant */
    double handover_du;  /* the output's change in the hand-over scan */
    double du_max;       /* the largest change of the output in a scan */
} at_run_t;

/* The trace's columns: t,u,pv and, with a fault, what the faults did. */
static void trace_header(const at_args_t *a, FILE *tf)
{
    fputs(fault_any(&a->fault) ? "t,u,pv,u_valve,load,y\n" : "t,u,pv\n", tf);
}

static void run_loop(const at_args_t *a, at_run_t *run, pdt_autotune_t *at, sim_plant_t *plant,
                     FILE *tf)
{
    /* The sensor noise: the shared generator, its stream picked by --seed. */
    sim_rng64_t ng = sim_rng64_seed(a->seed);
    /* Scans can only end the experiment (capacity, relay) and the search
     * (its evaluations); this bound only guards the host against a bug. */
    const uint64_t guard = 4ull * a->capacity * a->decimation + 10000000ull;
    const int faults = fault_any(&a->fault);
    fault_state_t fs;
    fault_init(&fs, a->u0);
    double u_last = a->u0;
    for (;;) {
        const double t = (double)run->scans * a->Ts, y = sim_plant_output(plant);
        double pv = y;
        if (a->noise > 0.0) pv += a->noise * sim_rng64_normal(&ng);
        pv = fault_sensor(&a->fault, pv, t);
        pdt_autotune_phase_t ph = pdt_autotune_phase(at);
        if (ph >= PDT_AUTOTUNE_SETTLE && ph <= PDT_AUTOTUNE_TUNE) run->phase_scans[ph - 1]++;
        pdt_real_t u;
        /* With --actuator-position the port reads where the valve stood
         * over the last scan. */
        pdt_status_t ss =
            a->act_pos ? pdt_autotune_scan_position(at, (pdt_real_t)pv, (pdt_real_t)fs.pos, &u)
                       : pdt_autotune_scan(at, (pdt_real_t)pv, &u);
        if (run->scans > 0) {
            const double du = fabs((double)u - u_last);
            run->du_max = du > run->du_max ? du : run->du_max;
            if (ss == PDT_OK && ph == PDT_AUTOTUNE_TUNE) run->handover_du = du;
        }
        u_last = (double)u;
        const double pos = fault_actuator(&a->fault, &fs, (double)u, a->Ts);
        const double load = fault_load(&a->fault, t);
        if (tf && faults)
            fprintf(tf, "%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", t, (double)u, pv, pos, load, y);
        else if (tf)
            fprintf(tf, "%.9g,%.9g,%.9g\n", t, (double)u, pv);
        sim_plant_apply(plant, pos + load);
        run->scans++;
        if (ss == PDT_RUNNING && run->scans < guard) continue;
        if (ss == PDT_RUNNING) (void)pdt_autotune_abort(at, &u);
        break;
    }
}

static void simulate(const at_args_t *a, at_run_t *run)
{
    sim_plant_t plant;
    const sim_plant_desc_t desc = plant_desc(a);
    const size_t hist_len = SIM_PLANT_HIST_LEN(a->delay, a->Ts);
    double *hist = malloc(hist_len * sizeof *hist);
    if (!hist) cli_fail(EXIT_REFUSED, "out of memory (%zu scans of dead time)", hist_len);
    if (sim_plant_init(&plant, &desc, a->Ts, a->u0, a->y0, hist, hist_len) != 0)
        cli_fail(EXIT_USAGE, "%s: the plant cannot be simulated (at most %u lags)", "autotune-sim",
                 SIM_PLANT_MAX_STATES);
    FILE *tf = NULL;
    if (a->trace) {
        tf = fopen(a->trace, "w");
        if (!tf) cli_fail(EXIT_USAGE, "cannot open %s: %s", a->trace, strerror(errno));
        trace_header(a, tf);
    }
    pdt_autotune_t *at = malloc(sizeof *at);
    const size_t work_len = pdt_autotune_workspace_size(&run->cfg);
    void *work = work_len ? malloc(work_len) : NULL;
    if (!at || (work_len && !work))
        cli_fail(EXIT_REFUSED, "out of memory (%zu bytes of workspace)", work_len);
    memset(&run->res, 0, sizeof run->res);
    if (a->closed) {
        pdt_pid_config_t pc;
        pdt_pid_config_default(&pc);
        pc.Ts = (pdt_real_t)a->Ts;
        pc.u_min = run->cfg.u_min;
        pc.u_max = run->cfg.u_max;
        run->g0 = (pdt_tune_gains_t){(pdt_real_t)a->gains.v[0], (pdt_real_t)a->gains.v[1],
                                     (pdt_real_t)(a->gains.n == 3 ? a->gains.v[2] : 0.0),
                                     (pdt_real_t)(a->gains.n == 3 ? a->gains.v[2] / 10.0 : 0.0)};
        if (pdt_pid_init_from_gains(&run->pid, &pc, &run->g0, PDT_PID_IDEAL, (pdt_real_t)a->u0) !=
            PDT_OK)
            cli_fail(EXIT_USAGE, "autotune-sim: the PID refuses --initial-gains");
        run->st =
            pdt_autotune_init_closed(at, &run->cfg, &run->pid, (pdt_real_t)a->y0, work, work_len);
    } else {
        run->st = pdt_autotune_init(at, &run->cfg, (pdt_real_t)a->u0, work, work_len);
    }
    run->initialised = run->st == PDT_OK;
    if (run->initialised) {
        run_loop(a, run, at, &plant, tf);
        (void)pdt_autotune_result(at, &run->res);
        run->st = run->res.status;
    }
    if (tf && (fflush(tf) != 0 || ferror(tf) || fclose(tf) != 0))
        cli_fail(EXIT_REFUSED, "cannot write %s", a->trace);
    free(work);
    free(at);
    free(hist);
}

static void experiment_json(pdtcli_jbuf_t *jb, const at_args_t *a, const at_run_t *run)
{
    const pdt_excite_config_t *ec = &run->cfg.excite;
    pdtcli_jb_raw(jb, ",\"experiment\":{\"kind\":\"");
    pdtcli_jb_raw(jb, kind_names[a->kind - PDT_EXCITE_STEP]);
    pdtcli_jb_raw(jb, "\"");
    pdtcli_jb_key(jb, "duration", (double)run->res.scans_experiment * a->Ts);
    pdtcli_jb_uint(jb, "scans", (unsigned long)run->res.scans_experiment);
    pdtcli_jb_key(jb, "noise", (double)run->res.noise);
    pdtcli_jb_key(jb, "quantum", (double)run->res.quantum);
    if (a->kind != PDT_EXCITE_RELAY) pdtcli_jb_key(jb, "amplitude", (double)ec->amplitude);
    if (a->kind == PDT_EXCITE_PULSE) {
        pdtcli_jb_key(jb, "t_on", (double)ec->t_on);
        pdtcli_jb_key(jb, "t_off", (double)ec->t_off);
    } else if (a->kind == PDT_EXCITE_CHIRP) {
        pdtcli_jb_key(jb, "f0", (double)ec->f0);
        pdtcli_jb_key(jb, "f1", (double)ec->f1);
        pdtcli_jb_key(jb, "sweep", (double)ec->duration);
    } else if (a->kind == PDT_EXCITE_PRBS) {
        pdtcli_jb_uint(jb, "bits", (unsigned long)ec->prbs_bits);
        pdtcli_jb_key(jb, "hold", (double)ec->prbs_hold * a->Ts);
    } else if (a->kind == PDT_EXCITE_RELAY) {
        pdtcli_jb_key(jb, "d", (double)ec->d);
        pdtcli_jb_key(jb, "eps", (double)ec->eps);
        pdtcli_jb_key(jb, "eps_used", (double)run->res.relay_eps);
        pdtcli_jb_key(jb, "setpoint", (double)ec->setpoint);
        pdtcli_jb_str(jb, "action", ec->action == PDT_EXCITE_REVERSE ? "reverse" : "direct");
    }
    pdtcli_jb_raw(jb, "}");
}

/* "loop": the gains run by pdt_pid on the true plant, beside the model's
 * Ms; null without gains. */
static void loop_json(pdtcli_jbuf_t *jb, const at_run_t *run)
{
    pdtcli_jb_raw(jb, ",\"loop\":");
    if (!run->has_loop) {
        pdtcli_jb_raw(jb, "null");
        return;
    }
    pdtcli_jb_printf(jb, "{\"Ms_true\":");
    pdtcli_jb_num(jb, run->loop.Ms);
    pdtcli_jb_key(jb, "Ms_model", (double)run->res.tune.fig.Ms);
    pdtcli_jb_key(jb, "iae_setpoint", run->loop.iae_sp);
    pdtcli_jb_key(jb, "overshoot_pct", run->loop.overshoot);
    pdtcli_jb_key(jb, "iae_load", run->loop.iae_load);
    pdtcli_jb_raw(jb, run->loop.stable ? ",\"stable\":true}" : ",\"stable\":false}");
}

/* "order": the model order kept and both models' BIC with order_auto;
 * null with a fixed order or before the order was chosen. */
static void order_json(pdtcli_jbuf_t *jb, const at_run_t *run)
{
    const pdt_autotune_result_t *res = &run->res;
    pdtcli_jb_raw(jb, ",\"order\":");
    if (!run->cfg.order_auto || !res->has_model || !res->has_valid) {
        pdtcli_jb_raw(jb, "null");
        return;
    }
    const int sopdt = res->ident.model.kind == PDT_MODEL_SOPDT;
    pdtcli_jb_printf(jb, "{\"kept\":\"%s\",\"fopdt\":{\"bic\":", sopdt ? "sopdt" : "fopdt");
    pdtcli_jb_num(jb, (double)(sopdt ? res->bic_other : res->valid.bic));
    pdtcli_jb_raw(jb, "},\"sopdt\":{\"bic\":");
    pdtcli_jb_num(jb, (double)(sopdt ? res->valid.bic : res->bic_other));
    pdtcli_jb_raw(jb, "}}");
}

static void results_json(pdtcli_jbuf_t *jb, const at_args_t *a, const at_run_t *run)
{
    const pdt_autotune_result_t *res = &run->res;
    pdtcli_jb_raw(jb, ",\"phases\":{");
    for (int k = 0; k < 4; k++)
        pdtcli_jb_printf(jb, "%s\"%s\":%lu", k ? "," : "", phase_names[k],
                         (unsigned long)run->phase_scans[k]);
    pdtcli_jb_raw(jb, "},\"ident\":");
    if (res->has_model) {
        pdtcli_jb_model(jb, &res->ident.model, &res->ident);
        pdtcli_jb_raw(jb, "}");
    } else {
        pdtcli_jb_raw(jb, "null");
    }
    order_json(jb, run);
    pdtcli_jb_raw(jb, ",\"tune\":");
    if (res->has_gains)
        tune_json(jb, &a->t, &res->tune, &res->tune.fig, (double)NAN, (double)NAN);
    else
        pdtcli_jb_raw(jb, "null");
    loop_json(jb, run);
    if (a->kind != PDT_EXCITE_RELAY) return;
    pdtcli_jb_raw(jb, ",\"relay\":");
    if (!res->has_relay) {
        pdtcli_jb_raw(jb, "null");
        return;
    }
    pdtcli_jb_printf(jb, "{\"Ku\":");
    pdtcli_jb_num(jb, (double)res->relay.Ku);
    pdtcli_jb_key(jb, "Pu", (double)res->relay.Pu);
    pdtcli_jb_key(jb, "a", (double)res->relay.a);
    pdtcli_jb_key(jb, "d", (double)res->relay.d);
    pdtcli_jb_uint(jb, "cycles", (unsigned long)res->relay.cycles);
    pdtcli_jb_key(jb, "spread", (double)res->relay_spread);
    pdtcli_jb_raw(jb, "}");
}

/* "faults": the simulator's faults as given; the key only with a fault. */
static void faults_json(pdtcli_jbuf_t *jb, const at_args_t *a)
{
    const fault_cfg_t *f = &a->fault;
    if (!fault_any(f)) return;
    pdtcli_jb_raw(jb, ",\"faults\":{\"load_step\":");
    if (f->has_load) {
        pdtcli_jb_raw(jb, "{\"t\":");
        pdtcli_jb_num(jb, f->load_t);
        pdtcli_jb_key(jb, "d", f->load);
        pdtcli_jb_raw(jb, "}");
    } else {
        pdtcli_jb_raw(jb, "null");
    }
    pdtcli_jb_key(jb, "drift", f->drift);
    pdtcli_jb_key(jb, "quantise", f->quant);
    pdtcli_jb_key(jb, "u_rate", f->u_rate);
    pdtcli_jb_key(jb, "stiction", f->stiction);
    pdtcli_jb_raw(jb, "}");
}

/* "closed_loop": the retune's starting gains and their loop on the true
 * plant, which gains run at the end, and the output's change in the
 * hand-over scan beside its largest change in any scan; the key only with
 * --closed-loop. */
static void closed_json(pdtcli_jbuf_t *jb, const at_args_t *a, const at_run_t *run)
{
    if (!a->closed) return;
    pdtcli_jb_raw(jb, ",\"closed_loop\":{\"initial\":{\"Kc\":");
    pdtcli_jb_num(jb, (double)run->g0.Kc);
    pdtcli_jb_key(jb, "Ti", (double)run->g0.tauI);
    pdtcli_jb_key(jb, "Td", (double)run->g0.tauD);
    pdtcli_jb_raw(jb, "}");
    pdtcli_jb_key(jb, "Ms_before", run->loop0.Ms);
    pdtcli_jb_raw(jb, run->loop0.stable ? ",\"stable_before\":true" : ",\"stable_before\":false");
    pdtcli_jb_str(jb, "gains", run->st == PDT_OK ? "new" : "old");
    pdtcli_jb_key(jb, "handover_du", run->handover_du);
    pdtcli_jb_key(jb, "du_max", run->du_max);
    pdtcli_jb_raw(jb, "}");
}

static void print_run(const at_args_t *a, const at_run_t *run)
{
    static char buf[8192];
    pdtcli_jbuf_t jb;
    pdtcli_jb_init(&jb, buf, sizeof buf);
    pdtcli_jb_printf(&jb, "{\"status\":\"%s\"", pdt_status_name(run->st));
    pdtcli_jb_str(&jb, "reason", pdt_status_str(run->st));
    if (run->st != PDT_OK) {
        const int fi = run->initialised ? (int)run->res.failed_in : 0;
        pdtcli_jb_str(&jb, "failed_in", fi >= 0 && fi <= 6 ? failed_names[fi] : "unknown");
    }
    pdtcli_jb_key(&jb, "scan_period", a->Ts);
    pdtcli_jb_uint(&jb, "decimation", (unsigned long)a->decimation);
    pdtcli_jb_uint(&jb, "capacity", (unsigned long)a->capacity);
    pdtcli_jb_uint(&jb, "samples", (unsigned long)run->res.samples);
    pdtcli_jb_uint(&jb, "scans", (unsigned long)run->scans);
    pdtcli_jb_uint(&jb, "repeats", (unsigned long)run->res.repeats);
    pdtcli_jb_key(&jb, "shift", (double)run->res.shift);
    pdtcli_jb_key(&jb, "drift", (double)run->res.drift);
    pdtcli_jb_key(&jb, "response", (double)run->res.response);
    experiment_json(&jb, a, run);
    results_json(&jb, a, run);
    faults_json(&jb, a);
    closed_json(&jb, a, run);
    pdtcli_jb_raw(&jb, "}");
    if (pdtcli_jb_done(&jb) < 0) cli_fail(EXIT_REFUSED, "autotune-sim: result too long");
    puts(buf);
    cli_flush();
}

/* The reason of a failed run on stderr, with the figure that decided a
 * refusal of the gains. */
static void fail_run(const at_run_t *run)
{
    const pdt_status_t st = run->st;
    const int fi = run->initialised ? (int)run->res.failed_in : 0;
    const char *where = fi >= 0 && fi <= 4 ? failed_names[fi] : "?";
    const pdt_autotune_result_t *res = &run->res;
    if (st == PDT_ERR_POOR_FIT && res->has_model && res->ident.fit < run->cfg.tune.fit_min)
        cli_fail(EXIT_REFUSED,
                 "autotune-sim: %s (in %s): fit %.4g%% below %.4g%%: too much noise "
                 "or too little excitation",
                 pdt_status_str(st), where, (double)res->ident.fit, (double)run->cfg.tune.fit_min);
    if (st == PDT_ERR_MS_LIMIT && res->has_model) {
        pdt_tune_config_t open = run->cfg.tune;
        open.ms_max = 0;
        pdt_tune_result_t tr;
        if (pdt_tune_compute(&res->ident.model, res->ident.fit, &open, &tr) == PDT_OK)
            cli_fail(EXIT_REFUSED,
                     "autotune-sim: %s (in %s): Ms %.4g exceeds the limit %.4g "
                     "(--ms-max, a slower knob or another rule)",
                     pdt_status_str(st), where, (double)tr.fig.Ms, (double)run->cfg.tune.ms_max);
    }
    cli_fail(EXIT_REFUSED, "autotune-sim: %s (in %s)", pdt_status_str(st), where);
}

/* After gains: the same plant under pdt_pid, a set-point step of the
 * experiment's size in output units and a load step, noise-free. */
static void close_loop(const at_args_t *a, at_run_t *run)
{
    double sum, T1;
    time_scales(a, &sum, &T1);
    const sim_plant_desc_t d = plant_desc(a);
    const double t_scale = sum + a->delay;
    const double step = fabs(a->gain) * fabs(a->amplitude) * (a->integrating ? t_scale : 1.0);
    const double horizon = 20.0 * t_scale > 10.0 * a->Ts ? 20.0 * t_scale : 10.0 * a->Ts;
    if (a->closed)
        loop_sim_run(&d, a->Ts, &run->g0, a->u0, a->y0, (double)run->cfg.u_min,
                     (double)run->cfg.u_max, step, horizon, &run->loop0);
    if (run->st != PDT_OK || !run->res.has_gains) return;
    loop_sim_run(&d, a->Ts, &run->res.tune.ideal, a->u0, a->y0, (double)run->cfg.u_min,
                 (double)run->cfg.u_max, step, horizon, &run->loop);
    run->has_loop = 1;
}

int cmd_autotune_sim(int argc, char **argv)
{
    at_args_t a;
    memset(&a, 0, sizeof a);
    a.amplitude = 1.0;
    a.seed = 1;
    a.kind = PDT_EXCITE_PRBS;
    a.model = AT_MODEL_AUTO;
    parse(&a, argc, argv);
    check_args(&a);
    parse_load(&a);
    at_run_t *run = calloc(1, sizeof *run);
    if (!run) cli_fail(EXIT_REFUSED, "out of memory");
    autotune_config(&a, &run->cfg);
    simulate(&a, run);
    close_loop(&a, run);
    print_run(&a, run);
    if (run->st != PDT_OK) fail_run(run);
    free(run);
    return 0;
}
