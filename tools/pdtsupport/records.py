"""What the command-line tests' records share (simulated by
pdtsupport.plant.simulate): their input, noise, operating point and
length, and the check of a recovered FOPDT."""
import numpy as np
import pytest

from pdtsupport.cli import FOPDT_KEYS
from pdtsupport.rng import SplitMix64


def multistep_input(n, u0, amp, hold_min, hold_max, rest, seed):
    """Steps between random levels around u0 after `rest` samples at u0;
    splitmix64 keeps the record the same on every numpy version."""
    rnd = SplitMix64.keyed(seed).uniform
    u = np.full(n, float(u0))
    k, sign = rest, 1.0
    while k < n:
        hold = hold_min + int(rnd() * (hold_max - hold_min + 1))
        u[k:k + hold] = u0 + sign * amp * (0.4 + 0.6 * rnd())
        sign = -sign
        k += hold
    return u


def noise(n, std, seed):
    """n normal draws of std `std`, from another stream than the input of
    the same seed (SplitMix64.keyed(seed, 1))."""
    return std * SplitMix64.keyed(seed, 1).normal(n)


TS = 0.1
N = 600
U0, Y0 = 50.0, 20.0


def check_fopdt(out, K, tau, Td, rtol=0.02, td_tol=0.05):
    assert list(out) == FOPDT_KEYS
    assert out["model"] == "fopdt"
    assert out["K"] == pytest.approx(K, rel=rtol)
    assert out["tau"] == pytest.approx(tau, rel=rtol)
    assert out["Td"] == pytest.approx(Td, abs=td_tol)
    assert out["u0"] == pytest.approx(U0)
    assert out["y0"] == pytest.approx(Y0, abs=0.05)
    assert out["fit"] > 95.0
    assert out["cost"] >= 0.0 and isinstance(out["evaluations"], int)
    assert out["evaluations"] > 0
