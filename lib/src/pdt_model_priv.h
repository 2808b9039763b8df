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

#endif /* PDT_MODEL_PRIV_H */
