"""The deterministic random generator of pdtfit's Python tools: splitmix64,
the stream of sim_rng64_* in tools/sim/sim_rng.h. Every record, vector and
test input the tools draw comes from it, in integer arithmetic (plain
Python integers for one draw, numpy uint64, which wraps mod 2^64, for
many), so that a stream never depends on the platform or the numpy
version.

The state after k draws is seed + k * GAMMA mod 2^64, each output a mix
of it; an array of n draws is therefore computed at once, and equals n
scalar draws (tools/tests/test_rng.py).
"""
import math

import numpy as np

MASK64 = 2 ** 64 - 1
GAMMA = 0x9E3779B97F4A7C15
MIX1 = 0xBF58476D1CE4E5B9
MIX2 = 0x94D049BB133111EB


def _mix(z):
    """splitmix64's output function of a state, on an int or uint64 array."""
    if isinstance(z, np.ndarray):
        z = (z ^ (z >> np.uint64(30))) * np.uint64(MIX1)
        z = (z ^ (z >> np.uint64(27))) * np.uint64(MIX2)
        return z ^ (z >> np.uint64(31))
    z = ((z ^ (z >> 30)) * MIX1) & MASK64
    z = ((z ^ (z >> 27)) * MIX2) & MASK64
    return z ^ (z >> 31)


class SplitMix64:
    """splitmix64, seeded by a scrambled seed: the same stream on every
    platform and numpy version. A method's `n` None draws one value (a
    Python number), an integer n an array of n."""

    def __init__(self, seed):
        self.s = (int(seed) * GAMMA + 0x2545F4914F6CDD1D) & MASK64

    @classmethod
    def keyed(cls, *keys):
        """The stream of a tuple of integer keys. The constructor's stream of
        seed k + 1 is that of seed k one draw on (both states are points of
        one sequence, GAMMA apart), so records drawn from neighbouring seeds
        share their draws; a keyed stream starts at a hash of its keys (each
        folded in by a splitmix64 output), far from every other key's."""
        h = 0
        for k in keys:
            h = cls((h ^ int(k)) & MASK64).next64()
        return cls(h)

    def next64(self, n=None):
        """The next output, an integer in [0, 2^64); n of them as uint64."""
        if n is None:
            self.s = (self.s + GAMMA) & MASK64
            return _mix(self.s)
        k = np.arange(1, n + 1, dtype=np.uint64)
        with np.errstate(over="ignore"):
            z = _mix(np.uint64(self.s) + k * np.uint64(GAMMA))
        self.s = (self.s + n * GAMMA) & MASK64
        return z

    def uniform(self, n=None, lo=0.0, hi=1.0):
        """In [lo, hi): the top 53 bits over 2^53, scaled (sim_rng64_uniform
        for the default range)."""
        if n is None:
            u = (self.next64() >> 11) / 2.0 ** 53
        else:
            u = (self.next64(n) >> np.uint64(11)).astype(float) / 2.0 ** 53
        return u if (lo, hi) == (0.0, 1.0) else lo + (hi - lo) * u

    def normal(self, n=None):
        """Standard normal by Box-Muller, one of the pair (sim_rng64_normal);
        an array draws its n first uniforms, then its n second ones."""
        if n is None:
            return float(self.normal(1)[0])
        u1 = 1.0 - self.uniform(n)      # (0, 1]
        u2 = self.uniform(n)
        return np.sqrt(-2.0 * np.log(u1)) * np.cos(2.0 * math.pi * u2)

    def integers(self, lo, hi, n=None):
        """Integers in [lo, hi): lo + floor(uniform (hi - lo))."""
        if n is None:
            return lo + int(self.uniform() * (hi - lo))
        return lo + (self.uniform(n) * (hi - lo)).astype(np.int64)

    def bits(self, nbits, n=None, offset=0):
        """The top `nbits` bits of the output, less `offset`."""
        if n is None:
            return (self.next64() >> (64 - nbits)) - offset
        return [int(x >> np.uint64(64 - nbits)) - offset for x in self.next64(n)]

    def permutation(self, n):
        """A random order of 0 .. n-1 (the ranks of n uniforms)."""
        return np.argsort(self.uniform(n), kind="stable")

    def choice(self, n, count):
        """`count` distinct integers of 0 .. n-1."""
        return self.permutation(n)[:count]

    def signs(self, count, hold):
        """+-1 PRBS-like sequence, each level held for `hold` samples."""
        levels = np.where(self.uniform(-(-count // hold)) < 0.5, 1.0, -1.0)
        return np.repeat(levels, hold)[:count]

    def noise(self, amp, count):
        """Bounded bell-shaped noise: sums of four uniforms, centred, times
        amp (std amp / sqrt(3), never beyond 2 amp)."""
        u = self.uniform(4 * count).reshape(count, 4)
        return amp * (u[:, 0] + u[:, 1] + u[:, 2] + u[:, 3] - 2.0)
