/*
 * The random generators of pdtfit's tests, benchmarks, demo and command
 * line; their streams never change with a compiler or a library version,
 * so records made from a seed are the same on the host and the target.
 * Not for the library (which has its own PCG32).
 *
 * - sim_rng_*: Numerical Recipes' 32-bit LCG, the tests' and the demo's
 *   (tools/pdtsupport/rng.py Lcg32 is the same stream in Python).
 * - sim_rng64_*: splitmix64 with Box-Muller normals, for the benchmarks,
 *   whose statistics over thousands of records need more than a 32-bit
 *   state and twelve-uniform normals give (tools/pdtsupport/rng.py
 *   SplitMix64 is the same generator).
 */
#ifndef SIM_RNG_H
#define SIM_RNG_H

#include <math.h>
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

/* The 64-bit stream's state: any value, its stream splitmix64's from
 * there (callers scramble small seeds into it as they like). */
typedef struct sim_rng64 {
    uint64_t s;
} sim_rng64_t;

static inline sim_rng64_t sim_rng64_seed(uint64_t state)
{
    sim_rng64_t r;
    r.s = state;
    return r;
}

static inline uint64_t sim_rng64_next(sim_rng64_t *r)
{
    uint64_t z = (r->s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* Uniform in [0, 1) from the top 53 bits. */
static inline double sim_rng64_uniform(sim_rng64_t *r)
{
    return (double)(sim_rng64_next(r) >> 11) * (1.0 / 9007199254740992.0);
}

/* Standard normal by Box-Muller, one of the pair (two draws a value). */
static inline double sim_rng64_normal(sim_rng64_t *r)
{
    const double u1 = 1.0 - sim_rng64_uniform(r); /* (0, 1]: log finite */
    const double u2 = sim_rng64_uniform(r);
    return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
}

#endif /* SIM_RNG_H */
