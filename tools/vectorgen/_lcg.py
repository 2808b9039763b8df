"""The deterministic pseudo-random numbers of the vector generators (numpy's
own streams may change between versions, the vectors must not)."""
import numpy as np


class Lcg:
    """32-bit LCG (Numerical Recipes constants) in plain Python integers."""

    def __init__(self, seed):
        self.state = seed & 0xFFFFFFFF

    def uniform(self):
        self.state = (1664525 * self.state + 1013904223) & 0xFFFFFFFF
        return self.state / 4294967296.0

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
