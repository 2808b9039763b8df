/*
 * Driver of the certainty battery (tools/bench/certainty.py): closed-loop
 * records of known FOPDT/SOPDT plants, each identified by pdt_identify with
 * the library's defaults. It uses the public API only, so it measures the
 * identification as it is on any version of the library. Not part of the
 * library: stdio and malloc are fine here.
 *
 *   pdt_certainty cases
 *       one JSON line per case: its name, loop, model, truth, Ts, n.
 *   pdt_certainty run CASE SEED0 COUNT [DUMP]
 *       seeds SEED0 .. SEED0 + COUNT - 1 of case CASE (0-based): for each,
 *       a record (the seed sets the noise) and one identification (the
 *       same seed is the search's seed); one JSON line per seed. DUMP, if
 *       given, receives every record as n doubles of u, n of the measured
 *       y and n of the noise-free y (native byte order).
 *   pdt_certainty file FILE N Ts fopdt|sopdt SEED0
 *       records made elsewhere: FILE holds records of N samples, each as
 *       N doubles of u then N of y; record j is identified with the seed
 *       SEED0 + j. Same output lines.
 *
 * The plants are simulated exactly by the shared simulator
 * (tools/sim/sim_plant.h: the truth's zero-order-hold sampling with its
 * fractional dead time, in double). The noise is white and Gaussian
 * (sim_rng64: splitmix64, Box-Muller), its deviation the noise-free loop's
 * output deviation over 10^(SNR/20).
 *
 * Loops: a relay with hysteresis around a set-point (levels u0 + bias +/- d
 * as pdt_excite's relay, hysteresis three noise deviations) started after
 * a rest: asymmetric (u0 + 10 / u0 - 5, the set-point away from rest) or
 * symmetric (u0 +/- 10 around the rest point, as a relay autotuner run
 * at the operating point: little information on the static gain); or a
 * PI controller (SIMC, tau_c = 2 theta, on the plant's
 * half-rule FOPDT) following set-point steps up, down and back.
 *
 * When pdt_ident.h defines PDT_IDENT_FLAG_AT_BOUND, the result's `flags`
 * field is printed too (0 otherwise).
 */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "pdt/pdt.h"
#include "sim_plant.h"
#include "sim_rng.h"

#define SNR_DB 25.0
#define U0     40.0
#define Y0     350.0
#define AMP    10.0

enum plant_kind { PLANT_FOPDT, PLANT_SOPDT, PLANT_INTEG };
enum loop_kind { LOOP_RELAY, LOOP_PI, LOOP_RELAY_SYM };

typedef struct bcase {
    const char *name;
    enum loop_kind loop;
    enum plant_kind plant;
    double p1, p2, p3; /* FOPDT: K, tau; SOPDT: K, wn, zeta; INTEG: Ki, T */
    double Td;         /* s */
    double T;          /* record length, s */
    size_t n;          /* samples */
} bcase_t;

/* Record lengths: several relay cycles and a few settling times. */
static const bcase_t cases[] = {
    {"relay FOPDT, tau/Td = 2", LOOP_RELAY, PLANT_FOPDT, 1.0, 2.0, 0.0, 1.03, 40.0, 1200},
    {"relay FOPDT, lag-dominant tau/Td = 10", LOOP_RELAY, PLANT_FOPDT, 2.0, 10.0, 0.0, 1.03, 200.0,
     1200},
    {"relay FOPDT, delay-dominant tau/Td = 0.3", LOOP_RELAY, PLANT_FOPDT, 1.5, 0.6, 0.0, 2.03, 60.0,
     1200},
    {"relay FOPDT, negative gain K = -0.8", LOOP_RELAY, PLANT_FOPDT, -0.8, 3.0, 0.0, 1.23, 60.0,
     1200},
    {"relay SOPDT, overdamped zeta = 1.5", LOOP_RELAY, PLANT_SOPDT, 1.2, 0.5, 1.5, 1.03, 80.0,
     1200},
    {"relay SOPDT, underdamped zeta = 0.7", LOOP_RELAY, PLANT_SOPDT, 1.2, 0.8, 0.7, 1.03, 50.0,
     1200},
    {"relay SOPDT, negative gain K = -2, zeta = 1", LOOP_RELAY, PLANT_SOPDT, -2.0, 0.6, 1.0, 0.73,
     50.0, 1200},
    {"relay integrating, Ki = 0.1, T = 2", LOOP_RELAY, PLANT_INTEG, 0.1, 2.0, 0.0, 1.03, 50.0,
     1200},
    {"PI set-point steps, FOPDT tau/Td = 3", LOOP_PI, PLANT_FOPDT, 1.0, 3.0, 0.0, 1.03, 80.0, 1200},
    {"PI set-point steps, SOPDT zeta = 1.5", LOOP_PI, PLANT_SOPDT, 1.2, 0.5, 1.5, 1.03, 120.0,
     1200},
    {"PI set-point steps, SOPDT zeta = 0.7", LOOP_PI, PLANT_SOPDT, 1.2, 0.8, 0.7, 1.03, 80.0, 1200},
    {"symmetric relay FOPDT, tau/Td = 2", LOOP_RELAY_SYM, PLANT_FOPDT, 1.0, 2.0, 0.0, 1.03, 40.0,
     1200},
    {"symmetric relay SOPDT, zeta = 0.7", LOOP_RELAY_SYM, PLANT_SOPDT, 1.2, 0.8, 0.7, 1.03, 50.0,
     1200},
    {"symmetric relay SOPDT, zeta = 1.5", LOOP_RELAY_SYM, PLANT_SOPDT, 1.2, 0.5, 1.5, 1.03, 80.0,
     1200},
};
#define NCASES (sizeof cases / sizeof cases[0])

/* ------------------------------------------------------------ plant */

/* The simulator of case c at Ts, at rest (deviations from U0, Y0); hist
 * receives its input history. Returns 0, or -1 when hist is too short. */
static int plant_of(const bcase_t *c, double Ts, sim_plant_t *p, double *hist, size_t hist_len)
{
    const double lag[1] = {c->p2};
    sim_plant_desc_t d = sim_plant_desc_lags(c->p1, lag, 1u, c->Td);
    if (c->plant == PLANT_SOPDT) { /* the pair instead of the lag */
        d.lags = NULL;
        d.n_lags = 0u;
        d.wn = c->p2;
        d.zeta = c->p3;
    }
    d.integrating = c->plant == PLANT_INTEG;
    return sim_plant_init(p, &d, Ts, 0.0, 0.0, hist, hist_len);
}

/* ------------------------------------------------------------ loops */

static double dc_gain(const bcase_t *c)
{
    /* an integrator: its output change over the record's first quarter */
    return c->plant == PLANT_INTEG ? c->p1 * 0.25 * c->T : c->p1;
}

/* Half-rule FOPDT (tau, theta) of the plant, for the PI tuning. */
static void half_rule(const bcase_t *c, double *tau, double *theta)
{
    if (c->plant == PLANT_FOPDT) {
        *tau = c->p2;
        *theta = c->Td;
    } else {
        const double wn = c->p2, z = c->p3;
        double t1, t2;
        if (z >= 1.0) {
            const double q1 = wn * (z + sqrt(z * z - 1.0));
            t2 = 1.0 / q1;
            t1 = q1 / (wn * wn);
        } else { /* as a critically damped pair of the same wn */
            t1 = t2 = 1.0 / wn;
        }
        *tau = t1 + 0.5 * t2;
        *theta = c->Td + 0.5 * t2;
    }
}

static int sgn(double x)
{
    return x < 0.0 ? -1 : 1;
}

/* One closed-loop record of plant p from rest: u, y (measured) and yc
 * (noise-free, deviation). sigma = 0 gives the noise-free loop. */
static void loop_record(const bcase_t *c, sim_plant_t *p, double Ts, double sigma, sim_rng64_t *rng,
                        double *u, double *y, double *yc, double *du)
{
    const size_t n = c->n;
    const size_t k0 = n / 20 > 16 ? n / 20 : 16;
    const double K = dc_gain(c);
    const double s = (double)sgn(K);
    const double step = 0.3 * fabs(K) * AMP * s; /* set-point change, output units */
    const double hyst = fmax(3.0 * sigma, 1e-3 * fabs(step));
    double level = 1.0, integ = 0.0, Kc = 0.0, Ti = 1.0;
    if (c->loop == LOOP_PI) {
        double tau, theta;
        half_rule(c, &tau, &theta);
        const double tc = 2.0 * theta;
        Kc = tau / (K * (tc + theta));
        Ti = fmin(tau, 4.0 * (tc + theta));
    }
    sim_plant_reset(p);
    for (size_t k = 0; k < n; k++) {
        yc[k] = sim_plant_output(p);
        const double ym = yc[k] + (sigma > 0.0 ? sigma * sim_rng64_normal(rng) : 0.0);
        y[k] = Y0 + ym;
        du[k] = 0.0;
        if (k >= k0) {
            if (c->loop != LOOP_PI) {
                const int sym = c->loop == LOOP_RELAY_SYM;
                const double err = s * ((sym ? 0.0 : step) - ym);
                if (err > hyst)
                    level = 1.0;
                else if (err < -hyst)
                    level = sym ? -1.0 : -0.5;
                du[k] = AMP * level;
            } else {
                double sp = step;
                if (k >= (size_t)(0.4 * (double)n)) sp = -0.5 * step;
                if (k >= (size_t)(0.7 * (double)n)) sp = 0.0;
                const double e = sp - ym;
                integ += Ts / Ti * e;
                du[k] = Kc * (e + integ);
            }
        }
        u[k] = U0 + du[k];
        sim_plant_apply(p, du[k]);
    }
}

/* The record of case c and seed; returns Ts, or 0 when the case's plant
 * cannot be simulated. */
static double make_record(const bcase_t *c, uint64_t seed, double *u, double *y, double *yc,
                          double *du)
{
    static double hist[4096];
    const double Ts = c->T / (double)c->n;
    sim_plant_t p;
    if (plant_of(c, Ts, &p, hist, sizeof hist / sizeof hist[0]) != 0) return 0.0;
    loop_record(c, &p, Ts, 0.0, NULL, u, y, yc, du);
    double mean = 0.0, var = 0.0;
    for (size_t k = 0; k < c->n; k++) mean += yc[k];
    mean /= (double)c->n;
    for (size_t k = 0; k < c->n; k++) var += (yc[k] - mean) * (yc[k] - mean);
    const double sigma = sqrt(var / (double)c->n) / pow(10.0, SNR_DB / 20.0);
    sim_rng64_t rng = {0x5DEECE66Dull * (seed + 1u) + 0x2545F4914F6CDD1Dull}; /* its own state */
    loop_record(c, &p, Ts, sigma, &rng, u, y, yc, du);
    return Ts;
}

/* ------------------------------------------------------------ identification */

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static unsigned long result_flags(const pdt_ident_result_t *res)
{
#ifdef PDT_IDENT_FLAG_AT_BOUND
    return (unsigned long)res->flags;
#else
    (void)res;
    return 0ul;
#endif
}

/* Identifies one record with the defaults and prints its JSON line. */
static int identify_print(int index, uint64_t seed, pdt_model_kind_t model, double Ts,
                          const double *u, const double *y, size_t n)
{
    pdt_real_t *ur = malloc(n * sizeof *ur), *yr = malloc(n * sizeof *yr);
    if (!ur || !yr) return -1;
    for (size_t k = 0; k < n; k++) {
        ur[k] = (pdt_real_t)u[k];
        yr[k] = (pdt_real_t)y[k];
    }
    pdt_ident_config_t cfg;
    pdt_ident_config_default(&cfg);
    cfg.model = model;
    cfg.Ts = (pdt_real_t)Ts;
    cfg.seed = seed;
    pdt_ident_data_t data = {ur, yr, n};
    const size_t len = pdt_ident_workspace_size(&cfg, n);
    void *work = malloc(len ? len : 1u);
    pdt_ident_t *ctx = malloc(sizeof *ctx);
    if (!work || !ctx) return -1;
    pdt_ident_result_t res;
    memset(&res, 0, sizeof res);
    const double t0 = now_s();
    const pdt_status_t st = pdt_identify(ctx, &cfg, &data, work, len, &res);
    const double dt = now_s() - t0;
    printf("{\"index\":%d,\"seed\":%llu,\"status\":%d,\"status_name\":\"%s\"", index,
           (unsigned long long)seed, (int)st, pdt_status_str(st));
    if (st == PDT_OK) {
        printf(",\"flags\":%lu", result_flags(&res));
        if (res.model.kind == PDT_MODEL_FOPDT) {
            const pdt_model_fopdt_t *m = &res.model.p.fopdt;
            printf(",\"model\":\"fopdt\",\"K\":%.10g,\"tau\":%.10g,\"Td\":%.10g", (double)m->K,
                   (double)m->tau, (double)m->Td);
        } else {
            const pdt_model_sopdt_t *m = &res.model.p.sopdt;
            printf(",\"model\":\"sopdt\",\"k\":%.10g,\"a\":%.10g,\"b\":%.10g,\"Td\":%.10g",
                   (double)m->k, (double)m->a, (double)m->b, (double)m->Td);
        }
        printf(",\"y0\":%.12g,\"cost\":%.9g,\"fit\":%.6g,\"evaluations\":%lu,\"generations\":%lu"
               ",\"coarse\":%lu",
               (double)res.y0, (double)res.cost, (double)res.fit, (unsigned long)res.evaluations,
               (unsigned long)res.generations, (unsigned long)res.coarse);
    }
    printf(",\"seconds\":%.6g}\n", dt);
    free(ur);
    free(yr);
    free(work);
    free(ctx);
    return 0;
}

static void json_str(const char *s)
{
    putchar('"');
    for (; *s; s++) {
        if (*s == '"' || *s == '\\') putchar('\\');
        putchar(*s);
    }
    putchar('"');
}

static const char *plant_names[] = {"fopdt", "sopdt", "integ"};

static void print_cases(void)
{
    for (size_t i = 0; i < NCASES; i++) {
        const bcase_t *c = &cases[i];
        printf("{\"index\":%zu,\"name\":", i);
        json_str(c->name);
        printf(",\"loop\":\"%s\",\"plant\":\"%s\",\"model\":\"%s\",\"p\":[%.10g,%.10g,%.10g],"
               "\"Td\":%.10g,\"T\":%.10g,\"n\":%zu,\"Ts\":%.17g,\"snr_db\":%g}\n",
               c->loop == LOOP_PI ? "pi" : (c->loop == LOOP_RELAY ? "relay" : "relay-sym"),
               plant_names[c->plant], c->plant == PLANT_FOPDT ? "fopdt" : "sopdt", c->p1, c->p2,
               c->p3, c->Td, c->T, c->n, c->T / (double)c->n, SNR_DB);
    }
}

static int run_case(int ci, uint64_t seed0, long count, const char *dump)
{
    if (ci < 0 || (size_t)ci >= NCASES || count < 1) return 2;
    const bcase_t *c = &cases[ci];
    const size_t n = c->n;
    double *buf = malloc(4 * n * sizeof *buf);
    if (!buf) return 2;
    double *u = buf, *y = buf + n, *yc = buf + 2 * n, *du = buf + 3 * n;
    FILE *fd = NULL;
    if (dump && !(fd = fopen(dump, "wb"))) {
        fprintf(stderr, "cannot write %s\n", dump);
        return 2;
    }
    for (long j = 0; j < count; j++) {
        const uint64_t seed = seed0 + (uint64_t)j;
        const double Ts = make_record(c, seed, u, y, yc, du);
        if (Ts == 0.0) return 2;
        if (fd && fwrite(buf, sizeof *buf, 3 * n, fd) != 3 * n) return 2;
        if (identify_print(ci, seed, c->plant == PLANT_FOPDT ? PDT_MODEL_FOPDT : PDT_MODEL_SOPDT,
                           Ts, u, y, n) != 0)
            return 2;
    }
    if (fd) fclose(fd);
    free(buf);
    return 0;
}

static int run_file(const char *path, size_t n, double Ts, pdt_model_kind_t model, uint64_t seed0)
{
    FILE *f = fopen(path, "rb");
    double *buf = malloc(2 * n * sizeof *buf);
    if (!f || !buf || n < 2) {
        fprintf(stderr, "cannot read %s\n", path);
        return 2;
    }
    for (uint64_t j = 0; fread(buf, sizeof *buf, 2 * n, f) == 2 * n; j++) {
        if (identify_print(-1, seed0 + j, model, Ts, buf, buf + n, n) != 0) return 2;
    }
    fclose(f);
    free(buf);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc == 2 && strcmp(argv[1], "cases") == 0) {
        print_cases();
        return 0;
    }
    if ((argc == 5 || argc == 6) && strcmp(argv[1], "run") == 0)
        return run_case(atoi(argv[2]), strtoull(argv[3], NULL, 10), atol(argv[4]),
                        argc == 6 ? argv[5] : NULL);
    if (argc == 7 && strcmp(argv[1], "file") == 0)
        return run_file(argv[2], (size_t)strtoul(argv[3], NULL, 10), strtod(argv[4], NULL),
                        strcmp(argv[5], "sopdt") == 0 ? PDT_MODEL_SOPDT : PDT_MODEL_FOPDT,
                        strtoull(argv[6], NULL, 10));
    fprintf(stderr, "usage: pdt_certainty cases\n"
                    "       pdt_certainty run CASE SEED0 COUNT [DUMP]\n"
                    "       pdt_certainty file FILE N Ts fopdt|sopdt SEED0\n");
    return 2;
}
