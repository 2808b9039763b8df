/*
 * pdtfit's models on the shared simulator: the models the tests
 * write by their parameters, the simulator's description of any of them,
 * and a process as a controller meets it (the simulator around an
 * operating point, read through a sensor with white noise), for the host
 * and the target tests. C99, no allocation, no stdio.
 */
#ifndef SIM_PROCESS_H
#define SIM_PROCESS_H

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#include "pdt/pdt.h"
#include "sim_plant.h"
#include "sim_rng.h"

/* K e^{-Td s} / (tau s + 1). */
static inline pdt_model_t model_fopdt(double K, double tau, double Td)
{
    pdt_model_t m;
    memset(&m, 0, sizeof m);
    m.kind = PDT_MODEL_FOPDT;
    m.p.fopdt.K = (pdt_real_t)K;
    m.p.fopdt.tau = (pdt_real_t)tau;
    m.p.fopdt.Td = (pdt_real_t)Td;
    return m;
}

/* K e^{-Td s} / ((T1 s + 1)(T2 s + 1)); parameters the library refuses
 * leave a SOPDT of zeros, which every later call refuses too. */
static inline pdt_model_t model_sopdt_tc(double K, double T1, double T2, double Td)
{
    const pdt_model_tc_t tc = {(pdt_real_t)K, (pdt_real_t)T1, (pdt_real_t)T2, false,
                               (pdt_real_t)Td};
    pdt_model_t m;
    memset(&m, 0, sizeof m);
    m.kind = PDT_MODEL_SOPDT;
    (void)pdt_model_sopdt_from_tc(&tc, &m.p.sopdt);
    return m;
}

/* K wn^2 e^{-Td s} / (s^2 + 2 zeta wn s + wn^2); refused parameters as
 * above. */
static inline pdt_model_t model_sopdt_natural(double K, double wn, double zeta, double Td)
{
    const pdt_model_natural_t nat = {(pdt_real_t)K, (pdt_real_t)wn, (pdt_real_t)zeta,
                                     (pdt_real_t)Td};
    pdt_model_t m;
    memset(&m, 0, sizeof m);
    m.kind = PDT_MODEL_SOPDT;
    (void)pdt_model_sopdt_from_natural(&nat, &m.p.sopdt);
    return m;
}

/* Ki e^{-Td s} / (s (T s + 1)); refused parameters as above. */
static inline pdt_model_t model_integ(double Ki, double T, double Td)
{
    const pdt_model_integ_t in = {(pdt_real_t)Ki, (pdt_real_t)T, (pdt_real_t)Td};
    pdt_model_t m;
    memset(&m, 0, sizeof m);
    m.kind = PDT_MODEL_SOPDT;
    (void)pdt_model_sopdt_from_integ(&in, &m.p.sopdt);
    return m;
}

/* The simulator's description of m: a FOPDT as its lag; a SOPDT
 * k / (s^2 + a s + b) as the pair wn^2 = b, 2 zeta wn = a of DC gain k / b,
 * or for b = 0 as an integrator of gain k / a with the lag 1 / a. `lag`
 * holds the description's lag and must outlive its use. Returns 0, or -1
 * for a model the simulator does not take (an unknown kind, b < 0, or
 * a <= 0). */
static inline int sim_desc_of_model(const pdt_model_t *m, double *lag, sim_plant_desc_t *d)
{
    if (m->kind == PDT_MODEL_FOPDT) {
        *lag = (double)m->p.fopdt.tau;
        *d = sim_plant_desc_lags((double)m->p.fopdt.K, lag, 1u, (double)m->p.fopdt.Td);
        return 0;
    }
    memset(d, 0, sizeof *d);
    const double k = (double)m->p.sopdt.k, a = (double)m->p.sopdt.a, b = (double)m->p.sopdt.b;
    if (m->kind != PDT_MODEL_SOPDT || !(a > 0.0) || !(b >= 0.0)) {
        return -1;
    }
    if (b > 0.0) {
        d->K = k / b;
        d->wn = sqrt(b);
        d->zeta = a / (2.0 * d->wn);
    } else {
        *lag = 1.0 / a;
        d->K = k / a;
        d->lags = lag;
        d->n_lags = 1u;
        d->integrating = true;
    }
    d->delay = (double)m->p.sopdt.Td;
    return 0;
}

/* Scans of dead time a sim_process_t holds (a small target's build sets
 * fewer). */
#ifndef SIM_PROCESS_HIST
#define SIM_PROCESS_HIST 1024u
#endif

/* A process around an operating point read through a noisy sensor. Keep it
 * where it was initialised: the simulator points into its history. */
typedef struct sim_process {
    sim_plant_t plant;
    double hist[SIM_PROCESS_HIST];
    double noise_sd; /* the sensor's white noise, output units */
    sim_rng64_t rng;
} sim_process_t;

/* Prepares p at rest: pv y0 (plus noise) with the output held at u0; the
 * plant m sampled every Ts s, the noise's stream picked by seed. Returns
 * 0, or -1 for a model the simulator does not take or a dead time of more
 * than SIM_PROCESS_HIST - 2 scans. */
static inline int sim_process_init(sim_process_t *p, const pdt_model_t *m, double Ts, double u0,
                                   double y0, double noise_sd, uint32_t seed)
{
    sim_plant_desc_t d;
    double lag;
    memset(p, 0, sizeof *p);
    p->noise_sd = noise_sd;
    p->rng = sim_rng64_seed(seed);
    if (sim_desc_of_model(m, &lag, &d) != 0) {
        return -1;
    }
    return sim_plant_init(&p->plant, &d, Ts, u0, y0, p->hist, SIM_PROCESS_HIST);
}

/* The process value read at this scan. */
static inline pdt_real_t sim_process_pv(sim_process_t *p)
{
    const double n = p->noise_sd > 0.0 ? p->noise_sd * sim_rng64_normal(&p->rng) : 0.0;
    return (pdt_real_t)(sim_plant_output(&p->plant) + n);
}

/* Applies u for one scan and advances the process to the next scan. */
static inline void sim_process_apply(sim_process_t *p, pdt_real_t u)
{
    sim_plant_apply(&p->plant, (double)u);
}

#endif /* SIM_PROCESS_H */
