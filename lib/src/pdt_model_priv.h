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
#include "pdt_internal.h"

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
 * order: a number, never a way to pick a member of the union (the code
 * that computes by the lag count reads pdt_model_view). */
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

/* Multiplies the model's gain numerator by g (no checks): a shape of unit
 * gain numerator scaled to the gain a cost profiled. */
void pdt_model_scale_gain(pdt_model_t *m, pdt_real_t g);

/* Whether the model integrates: no DC gain, a pole at s = 0 (a SOPDT with
 * b = 0). */
bool pdt_model_integrates(const pdt_model_t *m);

/* The factor num / den that turns a static gain into the multiplier of
 * the model's gain numerator: the numerator per unit of DC gain, or of
 * integrating gain Ki for a model that integrates, over the numerator
 * itself. 1 / 1 for a FOPDT (K is its DC gain), (b, or a for an
 * integrator) / k for a SOPDT (K = k / b, Ki = k / a). Gain bounds given as
 * static gains times it bound the multiplier of a shape's numerator; the
 * two parts come apart so that the caller can keep the quotient within
 * the real type's normal range. */
void pdt_model_static_gain_ratio(const pdt_model_t *m, pdt_real_t *num, pdt_real_t *den);

/* Whether a model of the kind can integrate (a SOPDT with b = 0): the
 * identification's integrating check applies to it. */
static inline bool pdt_model_kind_integrates(pdt_model_kind_t kind)
{
    switch (kind) {
    case PDT_MODEL_FOPDT:
        return false;
    case PDT_MODEL_SOPDT:
        return true;
    }
    return false;
}

/* A model's transfer function in neutral terms, by its lags: one lag,
 * K e^{-Td s} / (tau s + 1); two lags, K e^{-Td s} / (s^2 + a s + b).
 * The code whose algorithm depends on the lag count reads this view and
 * never the union pdt_model_t.p: the discretisation's ZOH, the frequency
 * cost, the tuning's loop and rules, the validation's margin, the
 * reduction, the uncertainty's rows and the identification's gene coding.
 * A kind fills it in pdt_model_view and is made from it in
 * pdt_model_from_view; a kind the view cannot describe (a zero, a third
 * lag) extends the view and each of its readers. */
typedef struct pdt_model_view {
    uint32_t lags;  /* 1 or 2 (pdt_model_kind_lags) */
    pdt_real_t K;   /* the gain numerator (pdt_model_gain_numerator) */
    pdt_real_t tau; /* one lag: its time constant, s; 0 for two */
    pdt_real_t a;   /* two lags: s^2 + a s + b; 0 for one */
    pdt_real_t b;
    pdt_real_t Td; /* the dead time, s */
} pdt_model_view_t;

/* The model's view (no checks; inline: the ZOH and the frequency cost ask
 * once per evaluation). */
static inline void pdt_model_view(const pdt_model_t *m, pdt_model_view_t *v)
{
    v->lags = 0u;
    v->K = PDT_R(0.0);
    v->tau = PDT_R(0.0);
    v->a = PDT_R(0.0);
    v->b = PDT_R(0.0);
    v->Td = PDT_R(0.0);
    switch (m->kind) {
    case PDT_MODEL_FOPDT:
        v->lags = 1u;
        v->K = m->p.fopdt.K;
        v->tau = m->p.fopdt.tau;
        v->Td = m->p.fopdt.Td;
        break;
    case PDT_MODEL_SOPDT:
        v->lags = 2u;
        v->K = m->p.sopdt.k;
        v->a = m->p.sopdt.a;
        v->b = m->p.sopdt.b;
        v->Td = m->p.sopdt.Td;
        break;
    }
}

/* The model of the given kind from its view, whose lag count is the
 * kind's (no checks; inline: the identification decodes a model per
 * evaluation). */
static inline void pdt_model_from_view(pdt_model_kind_t kind, const pdt_model_view_t *v,
                                       pdt_model_t *m)
{
    m->kind = kind;
    switch (kind) {
    case PDT_MODEL_FOPDT:
        m->p.fopdt.K = v->K;
        m->p.fopdt.tau = v->tau;
        m->p.fopdt.Td = v->Td;
        break;
    case PDT_MODEL_SOPDT:
        m->p.sopdt.k = v->K;
        m->p.sopdt.a = v->a;
        m->p.sopdt.b = v->b;
        m->p.sopdt.Td = v->Td;
        break;
    }
}

#endif /* PDT_MODEL_PRIV_H */
