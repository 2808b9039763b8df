/*
 * The model module's private part.
 *
 * A model's frequency response at one frequency, written once: the public
 * pdt_model_freq, the costs, the tuning rules and the identification's
 * control band all call these (no checks: the callers hold valid models).
 *
 * The model-kind layer: what the other modules ask of a kind. pdt_model.c
 * and this header (the facts of a kind, inline: some are asked per
 * sample) are the one place that tells the kinds apart, with one switch
 * per operation and no default, so that -Wswitch names every operation a
 * new kind must fill (docs/design.md, "Adding a model kind").
 */
#ifndef PDT_MODEL_PRIV_H
#define PDT_MODEL_PRIV_H

#include "pdt/pdt_model.h"

/* |G(j w)|, dead time and gain sign aside (|K| / |den|); +infinity for an
 * integrating SOPDT at w = 0 (0 when k = 0). */
pdt_real_t pdt_model_magnitude_at(const pdt_model_t *m, pdt_real_t w);

/* arg G(j w) for a positive gain, continuous, -w Td included: the phase
 * that decides the crossover. */
pdt_real_t pdt_model_shape_phase(const pdt_model_t *m, pdt_real_t w);

/* The phase crossover, rad/s: where pdt_model_shape_phase reaches -pi.
 * The phase falls monotonically and the dead time alone reaches -pi at
 * pi / Td, so bisection on [0, pi / Td] finds it; 0 without a dead time. */
pdt_real_t pdt_model_phase_crossover(const pdt_model_t *m);

/* The step response of k = 1, dead time 0, of the SOPDT 1 / (s^2 + a s +
 * b) at t (0 for t <= 0): what pdt_model_step gives per time, without its
 * checks, for the discretisation's three samples per evaluation. */
pdt_real_t pdt_model_sopdt_unit_step(pdt_real_t a, pdt_real_t b, pdt_real_t t);

/* The model's gain numerator (a FOPDT's K, a SOPDT's k) split from its
 * shape: *shape is m with that numerator 1, as the costs profile it. */
pdt_real_t pdt_model_split_gain(const pdt_model_t *m, pdt_model_t *shape);

/* ---- the model-kind layer ------------------------------------------------ */

/* A parameter's name in a kind's parameter vector (pdt_model_params_get). */
typedef enum pdt_model_param {
    PDT_MODEL_PARAM_K,   /* the gain numerator: a FOPDT's K, a SOPDT's k */
    PDT_MODEL_PARAM_TAU, /* a FOPDT's time constant */
    PDT_MODEL_PARAM_A,   /* a SOPDT's a */
    PDT_MODEL_PARAM_B,   /* a SOPDT's b, 0 for an integrator */
    PDT_MODEL_PARAM_TD,  /* the dead time, last in every kind */
    PDT_MODEL_PARAM_NONE /* past the kind's parameters, or not a kind */
} pdt_model_param_t;

/* Whether kind is a model kind: the configurations' check. */
static inline bool pdt_model_kind_known(pdt_model_kind_t kind)
{
    switch (kind) {
    case PDT_MODEL_FOPDT:
    case PDT_MODEL_SOPDT:
        return true;
    }
    return false;
}

/* The kind's lags, the poles beside the dead time: 1 for a FOPDT, 2 for a
 * SOPDT (0 for no kind). The discretisation's pole count, the LS
 * regression's order, the initial states a cost estimates, the reduction's
 * order. A kind of one lag holds its parameters in p.fopdt, a kind of two
 * in p.sopdt: the code that reads the union by the lag count relies on it. */
static inline uint32_t pdt_model_kind_lags(pdt_model_kind_t kind)
{
    switch (kind) {
    case PDT_MODEL_FOPDT:
        return 1u;
    case PDT_MODEL_SOPDT:
        return 2u;
    }
    return 0u;
}

/* The number of the kind's parameters, the dead time included and an
 * output offset not: 3 for a FOPDT (K, tau, Td), 4 for a SOPDT (k, a, b,
 * Td); 0 for no kind. The Fisher matrix's size; less the gain (which the
 * costs profile), the identification's genes. */
static inline uint32_t pdt_model_kind_params(pdt_model_kind_t kind)
{
    switch (kind) {
    case PDT_MODEL_FOPDT:
        return 3u;
    case PDT_MODEL_SOPDT:
        return 4u;
    }
    return 0u;
}

/* The name of parameter i of the kind's vector (PDT_MODEL_PARAM_NONE past
 * its end). */
pdt_model_param_t pdt_model_kind_param(pdt_model_kind_t kind, uint32_t i);

/* The model's parameters into p[0..] in the kind's order (K, tau, Td or
 * k, a, b, Td); returns their number (pdt_model_kind_params). */
uint32_t pdt_model_params_get(const pdt_model_t *m, pdt_real_t *p);

/* The model's parameters from p[0..] in the kind's order; m->kind is kept. */
void pdt_model_params_set(pdt_model_t *m, const pdt_real_t *p);

/* The model's gain numerator: a FOPDT's K, a SOPDT's k. Its sign is the
 * gain's sign. */
pdt_real_t pdt_model_gain_numerator(const pdt_model_t *m);

/* Adds dTd to the model's dead time (no checks). */
void pdt_model_add_dead_time(pdt_model_t *m, pdt_real_t dTd);

#endif /* PDT_MODEL_PRIV_H */
