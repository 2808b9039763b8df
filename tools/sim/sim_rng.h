/*
 * The random generator of pdtfit's tests, benchmarks, demo and command
 * line: splitmix64, 53-bit uniforms, Box-Muller normals. Its stream never
 * changes with a compiler or a library version, so records made from a
 * seed are the same on the host and the target, and
 * tools/pdtsupport/rng.py SplitMix64 is the same stream in Python. Not for
 * the library, whose own PCG32 is part of the GA's results.
 */
#ifndef SIM_RNG_H
#define SIM_RNG_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>

/* The state: any value, its stream splitmix64's from there. A caller that
 * keeps a stream from a state of its own sets s directly. */
typedef struct sim_rng64 {
    uint64_t s;
} sim_rng64_t;

/* The stream of a seed, any small integer included: the state is the seed
 * scrambled as pdtsupport.rng.SplitMix64(seed) scrambles it. */
static inline sim_rng64_t sim_rng64_seed(uint64_t seed)
{
    sim_rng64_t r;
    r.s = seed * 0x9E3779B97F4A7C15ull + 0x2545F4914F6CDD1Dull;
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

/* A fair coin: the top bit, 1 exactly when sim_rng64_uniform would have
 * given at least 0.5. */
static inline int sim_rng64_coin(sim_rng64_t *r)
{
    return (int)(sim_rng64_next(r) >> 63);
}

/* Standard normal by Box-Muller, one of the pair (two draws a value). */
static inline double sim_rng64_normal(sim_rng64_t *r)
{
    const double u1 = 1.0 - sim_rng64_uniform(r); /* (0, 1]: log finite */
    const double u2 = sim_rng64_uniform(r);
    return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
}

#endif /* SIM_RNG_H */
