"""The deterministic random generators of pdtfit's Python tools, in plain
Python integers so that a stream never depends on the numpy version (the
generated vectors and benchmark records must not change with it).

- Lcg32: 32-bit LCG, Numerical Recipes constants (the vector generators,
  and the demo's noise as the paper reproduction regenerates it); the
  stream of sim_rng_* in tools/sim/sim_rng.h;
- Lcg64: 64-bit LCG, Knuth's MMIX constants (the command-line tests'
  records, the monitor report's loops);
- SplitMix64 (the identification benchmark): the stream of sim_rng64_*;
- Xorshift32: Marsaglia's xorshift32 (the GA operators' vectors).
"""
import math

import numpy as np

MASK32 = 0xFFFFFFFF
MASK64 = 2 ** 64 - 1


class Lcg32:
    """state <- 1664525 state + 1013904223 mod 2^32."""

    def __init__(self, seed):
        self.state = seed & MASK32

    def next(self):
        """The next state, an integer in [0, 2^32)."""
        self.state = (1664525 * self.state + 1013904223) & MASK32
        return self.state

    def uniform(self):
        """In [0, 1): the state over 2^32."""
        return self.next() / 4294967296.0

    def uniform24(self):
        """In [0, 1): the top 24 bits (sim_rng_uniform)."""
        return (self.next() >> 8) / 16777216.0

    def normal12(self):
        """Approximately standard normal: twelve uniform24 draws, centred
        (sim_rng_normal)."""
        total = 0.0
        for _ in range(12):
            total += self.uniform24()
        return total - 6.0

    def ints(self, count, shift, offset=0):
        """`count` integers (state >> shift) - offset: the top bits."""
        return [(self.next() >> shift) - offset for _ in range(count)]

    def noise(self, amp, count):
        """Sums of four uniforms, centred: bell-shaped, std amp / sqrt(3)."""
        return np.array([amp * (sum(self.uniform() for _ in range(4)) - 2.0)
                         for _ in range(count)])

    def bits(self, count, hold):
        """+-1 PRBS-like sequence, each level held for `hold` samples."""
        out = []
        while len(out) < count:
            out.extend([1.0 if self.uniform() < 0.5 else -1.0] * hold)
        return np.array(out[:count])


class Lcg64:
    """state <- 6364136223846793005 state + 1442695040888963407 mod 2^64."""

    def __init__(self, state=0x2545F4914F6CDD1D):
        self.state = state & MASK64

    def next(self):
        self.state = (self.state * 6364136223846793005 + 1442695040888963407) & MASK64
        return self.state

    def uniform(self):
        """In [0, 1): the top 53 bits."""
        return (self.next() >> 11) / 2.0 ** 53

    def uniform_open(self):
        """In (0, 1): the top 53 bits and half a step."""
        return ((self.next() >> 11) + 0.5) / 9007199254740992.0

    def gauss(self):
        """Standard normal by Box-Muller (one of the pair)."""
        a = self.uniform_open()
        b = self.uniform_open()
        return np.sqrt(-2.0 * np.log(a)) * np.cos(6.283185307179586 * b)


class SplitMix64:
    """splitmix64, seeded by a scrambled seed: the same stream on every
    platform and numpy version."""

    def __init__(self, seed):
        self.s = (int(seed) * 0x9E3779B97F4A7C15 + 0x2545F4914F6CDD1D) % 2 ** 64

    def next64(self):
        self.s = (self.s + 0x9E3779B97F4A7C15) % 2 ** 64
        z = self.s
        z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) % 2 ** 64
        z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) % 2 ** 64
        return z ^ (z >> 31)

    def uniform(self, n=None):
        if n is None:
            return (self.next64() >> 11) / 2.0 ** 53
        return np.array([(self.next64() >> 11) / 2.0 ** 53 for _ in range(n)])

    def normal(self, n):
        u1 = 1.0 - self.uniform(n)      # (0, 1]
        u2 = self.uniform(n)
        return np.sqrt(-2.0 * np.log(u1)) * np.cos(2.0 * math.pi * u2)


class Xorshift32:
    """Marsaglia's xorshift32 (13, 17, 5), an iterator of floats in [0, 1)
    from the top 24 bits; a zero seed is taken as 1."""

    def __init__(self, seed):
        self.state = seed & MASK32 or 1

    def __iter__(self):
        return self

    def __next__(self):
        s = self.state
        s ^= (s << 13) & MASK32
        s ^= s >> 17
        s ^= (s << 5) & MASK32
        self.state = s
        return (s >> 8) / float(1 << 24)
