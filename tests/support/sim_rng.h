/*
 * The one random generator of pdtfit's tests, benchmarks, demo and command
 * line: Numerical Recipes' 32-bit LCG. Its streams never change with a
 * compiler or a library version, so records made from a seed are the same
 * on the host and the target. Not for the library (which has its own PCG32).
 */
#ifndef SIM_RNG_H
#define SIM_RNG_H

#include <stddef.h>
#include <stdint.h>

/* The state: the seed is any value, its stream the LCG's from there. */
typedef uint32_t sim_rng_t;

static inline sim_rng_t sim_rng_seed(uint32_t seed)
{
    return seed;
}

static inline uint32_t sim_rng_next(sim_rng_t *r)
{
    *r = *r * 1664525u + 1013904223u;
    return *r;
}

/* Uniform in [0, 1) from the top 24 bits (the low bits of an LCG are
 * poor). */
static inline double sim_rng_uniform(sim_rng_t *r)
{
    return (double)(sim_rng_next(r) >> 8) / 16777216.0;
}

/* Approximately standard normal: twelve uniforms, centred (variance 1,
 * tails cut at 6, which a noise model of sensors does not miss). */
static inline double sim_rng_normal(sim_rng_t *r)
{
    double sum = 0.0;
    for (int i = 0; i < 12; i++) {
        sum += sim_rng_uniform(r);
    }
    return sum - 6.0;
}

/* A fair coin from the top bit. */
static inline int sim_rng_coin(sim_rng_t *r)
{
    return (int)(sim_rng_next(r) >> 31);
}

#endif /* SIM_RNG_H */
