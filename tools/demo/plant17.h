/*
 * The paper's test system (17) for the host demo and benchmarks,
 * G(s) = (-0.3s+1)(0.08s+1) / ((2s+1)(s+1)(0.4s+1)(0.2s+1)(0.05s+1)^3),
 * simulated exactly by the shared simulator (tools/sim/sim_plant.h).
 */
#ifndef PLANT17_H
#define PLANT17_H

#include <stddef.h>

/* Output of (17), from rest, for an input held constant over each sampling
 * period Ts (zero-order hold), sampled at the end of each period:
 * y[k] is the response at t = k Ts to u[0..k-1] (y[0] = 0). */
void plant17_simulate(const double *u, size_t n, double Ts, double *y);

/* Unit-step response of (17) at t = i dt_out, i = 0 .. count-1. */
void plant17_step_grid(double dt_out, size_t count, double *out);

/* |G(jw)| and arg G(jw) (rad, continuous) of (17). */
void plant17_freq(double w, double *mag, double *phase);

#endif
