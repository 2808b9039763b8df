/*
 * A model's frequency response at one frequency, written once: the public
 * pdt_model_freq, the costs, the tuning rules and the identification's
 * control band all call these (no checks: the callers hold valid models).
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

#endif /* PDT_MODEL_PRIV_H */
