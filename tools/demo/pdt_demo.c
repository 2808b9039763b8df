/*
 * pdtfit demo: models of the paper's test system (17), their exact sampled
 * form, their step responses, and the paper's costs on chirp data of (17).
 *
 * The data is what the paper's experiment records: a chirp from 0 to 0.5 Hz
 * sampled at 20 Hz, applied to (17) around an operating point, with
 * measurement noise. The candidate models are the published ones (Table 1
 * and 2) and Skogestad's half-rule approximations of (17).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "pdt/pdt.h"
#include "plant17.h"

#define FS 20.0
#define TS (1.0 / FS)
#define DURATION 60.0
#define N ((size_t)(DURATION * FS))
#define NOISE_STD 0.01
#define U0 40.0 /* operating point, e.g. % valve opening */
#define Y0 55.0 /* e.g. degC */

static pdt_real_t u[N];
static pdt_real_t y[N];
static pdt_real_t work[PDT_COST_WORKSPACE_SIZE(N) / sizeof(pdt_real_t) + 1];

/* Deterministic noise: a 64-bit LCG feeding a Box-Muller pair. */
static unsigned long long lcg_state = 0x2545F4914F6CDD1DULL;
static double uniform01(void)
{
    lcg_state = lcg_state * 6364136223846793005ULL + 1442695040888963407ULL;
    return ((double)(lcg_state >> 11) + 0.5) / 9007199254740992.0;
}
static double gauss(void)
{
    return sqrt(-2.0 * log(uniform01())) * cos(6.283185307179586 * uniform01());
}

static void die(const char *what, pdt_status_t st)
{
    fprintf(stderr, "pdt_demo: %s: %s\n", what, pdt_status_str(st));
    exit(1);
}

struct candidate {
    const char *name;
    pdt_model_t model;
};

static pdt_model_t fopdt(double K, double tau, double Td)
{
    pdt_model_t m;
    m.kind = PDT_MODEL_FOPDT;
    m.p.fopdt.K = (pdt_real_t)K;
    m.p.fopdt.tau = (pdt_real_t)tau;
    m.p.fopdt.Td = (pdt_real_t)Td;
    return m;
}

static pdt_model_t sopdt_tc(double K, double T1, double T2, double Td)
{
    pdt_sopdt_tc_t tc = {(pdt_real_t)K, (pdt_real_t)T1, (pdt_real_t)T2, false, (pdt_real_t)Td};
    pdt_model_t m;
    m.kind = PDT_MODEL_SOPDT;
    pdt_status_t st = pdt_sopdt_from_tc(&tc, &m.p.sopdt);
    if (st != PDT_OK) die("pdt_sopdt_from_tc", st);
    return m;
}

static double step_iae(const pdt_model_t *m)
{
    /* Integral of |model - (17)| over 0..15 s of the unit-step responses. */
    const double dt = 0.01;
    double iae = 0.0;
    for (int i = 0; i <= 1500; i++) {
        pdt_real_t t = (pdt_real_t)(i * dt), h;
        pdt_status_t st = pdt_model_step(m, &t, 1, &h);
        if (st != PDT_OK) die("pdt_model_step", st);
        double e = fabs((double)h - plant17_step(i * dt, 0.001));
        iae += (i == 0 || i == 1500 ? 0.5 : 1.0) * e * dt;
    }
    return iae;
}

int main(void)
{
    printf("pdtfit %s demo (pdt_real_t = %s)\n\n", PDT_VERSION_STRING,
           sizeof(pdt_real_t) == sizeof(float) ? "float" : "double");

    struct candidate cand[] = {
        {"paper GA FOPDT (Table 1)", fopdt(1.0, 2.4, 1.55)},
        {"half rule FOPDT", fopdt(1.0, 2.5, 1.47)},
        {"paper ELMS FOPDT (Table 1)", fopdt(1.04, 3.28, 1.4)},
        {"half rule SOPDT", sopdt_tc(1.0, 2.0, 1.2, 0.77)},
        {"paper GA SOPDT pulse-2", sopdt_tc(1.0, 1.8, 1.29, 0.85)},
    };
    const size_t ncand = sizeof cand / sizeof cand[0];

    /* 1. The exact sampled model of the half-rule SOPDT. */
    pdt_dmodel_t d;
    pdt_status_t st = pdt_discretize(&cand[3].model, (pdt_real_t)TS, &d);
    if (st != PDT_OK) die("pdt_discretize", st);
    printf("Half-rule SOPDT of (17): e^{-0.77 s} / ((2 s + 1)(1.2 s + 1)), Ts = %.3g s\n", TS);
    printf("  y(k) = %.9f y(k-1) + %.9f y(k-2)\n", -(double)d.a[0], -(double)d.a[1]);
    printf("         + %.9g u(k-%zu) + %.9g u(k-%zu) + %.9g u(k-%zu)\n\n", (double)d.b[0],
           d.delay + 1, (double)d.b[1], d.delay + 2, (double)d.b[2], d.delay + 3);

    /* 2. Its step response: continuous model, sampled model, true (17). */
    {
        pdt_real_t us[301], ys[301];
        for (size_t k = 0; k < 301; k++) us[k] = PDT_R(1.0);
        st = pdt_dmodel_simulate(&d, us, 301, ys);
        if (st != PDT_OK) die("pdt_dmodel_simulate", st);
        printf("  t [s]   continuous   sampled      system (17)\n");
        for (size_t k = 0; k <= 300; k += 20) {
            pdt_real_t t = (pdt_real_t)((double)k * TS), h;
            st = pdt_model_step(&cand[3].model, &t, 1, &h);
            if (st != PDT_OK) die("pdt_model_step", st);
            printf("  %5.1f   %10.6f   %10.6f   %10.6f\n", (double)t, (double)h, (double)ys[k],
                   plant17_step((double)t, 0.001));
        }
        printf("\n");
    }

    /* 3. Chirp data of (17) around an operating point, with noise. */
    {
        static double ud[N], yd[N];
        for (size_t k = 0; k < N; k++) {
            double t = (double)k * TS;
            /* Linear sweep 0 -> 0.5 Hz: phase 2 pi (f1 / (2 T)) t^2. */
            ud[k] = sin(2.0 * 3.141592653589793 * 0.5 / (2.0 * DURATION) * t * t);
        }
        plant17_simulate(ud, N, TS, 20, yd);
        for (size_t k = 0; k < N; k++) {
            u[k] = (pdt_real_t)(U0 + ud[k]);
            y[k] = (pdt_real_t)(Y0 + yd[k] + NOISE_STD * gauss());
        }
    }
    printf("Chirp 0 -> 0.5 Hz, %.0f s at %.0f Hz (N = %zu), operating point u0 = %.0f, "
           "y0 = %.0f, noise std %.2g\n",
           DURATION, FS, N, U0, Y0, NOISE_STD);

    pdt_cost_config_t cfg;
    pdt_cost_config_default(&cfg);
    cfg.Ts = (pdt_real_t)TS;
    cfg.u0 = (pdt_real_t)U0;
    cfg.y0 = (pdt_real_t)Y0;
    cfg.delay_max = (size_t)(5.0 * FS); /* dead times up to 5 s */
    size_t need = pdt_cost_workspace_size(&cfg, N);
    pdt_cost_t cost;
    st = pdt_cost_init(&cost, &cfg, u, y, N, work, sizeof work);
    if (st != PDT_OK) die("pdt_cost_init", st);
    printf("cost workspace: %zu bytes (N_f = %zu)\n\n", need, pdt_cost_fft_size(N, cfg.delay_max));

    printf("%-28s %11s %11s %11s %11s %9s\n", "model", "prediction", "simulation", "frequency",
           "combined", "step IAE");
    for (size_t i = 0; i < ncand; i++) {
        pdt_dmodel_t dm;
        pdt_real_t cp, cs, cf, cc;
        st = pdt_discretize(&cand[i].model, (pdt_real_t)TS, &dm);
        if (st != PDT_OK) die("pdt_discretize", st);
        if ((st = pdt_cost_prediction(&cost, &dm, &cp)) != PDT_OK) die("prediction", st);
        if ((st = pdt_cost_simulation(&cost, &dm, &cs)) != PDT_OK) die("simulation", st);
        if ((st = pdt_cost_frequency(&cost, &cand[i].model, &cf)) != PDT_OK) die("frequency", st);
        if ((st = pdt_cost_eval(&cost, &cand[i].model, &cc)) != PDT_OK) die("combined", st);
        printf("%-28s %11.4e %11.4e %11.4e %11.4e %9.3f\n", cand[i].name, (double)cp, (double)cs,
               (double)cf, (double)cc, step_iae(&cand[i].model));
    }
    printf("\nCosts are mean squares in output units^2 (noise variance %.1e); the step IAE\n"
           "is against the true system (17) over 0-15 s.\n",
           NOISE_STD * NOISE_STD);
    return 0;
}
