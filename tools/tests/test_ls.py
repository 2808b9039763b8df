"""Checks of the least-squares delay scans reference (pdtref.ls): exact
recovery on noise-free data, the continuous conversion against scipy's ZOH
discretisation, the skip rules, and E-IV less biased than ELMS on noisy
FOPDT data over several noise seeds."""

import numpy as np
import pytest
from scipy import signal

from pdtref import ls as ref
from pdtsupport.rng import SplitMix64 as Rng
from vectorgen import ls as gen


def _record(name):
    return next(r for r in gen.records() if r["name"] == name)


def _order(rec):
    return 1 if rec["truth"][0] == "fopdt" else 2


@pytest.mark.parametrize("name", ["fopdt_clean", "sopdt_clean", "sopdt_step"])
@pytest.mark.parametrize("method", ["elms", "eiv"])
def test_noise_free_recovery(name, method):
    rec = _record(name)
    whole = name == "sopdt_step"
    costs, best = ref.scan(rec["u"], rec["y"], rec["Ts"], _order(rec), method, 0, 20, whole)
    assert best["delay"] == rec["delay"]
    truth = rec["truth"][1:]
    got = ([best["model"]["K"], best["model"]["tau"]] if _order(rec) == 1
           else [best["model"]["k"], best["model"]["a"], best["model"]["b"]])
    np.testing.assert_allclose(got, truth, rtol=1e-8)
    assert best["y0"] == pytest.approx(350.0, abs=1e-8)
    assert best["cost"] < 1e-18
    # Every other surviving delay scores clearly worse.
    others = np.delete(costs, best["delay"])
    assert np.all(others[np.isfinite(others)] > 1e3 * max(best["cost"], 1e-20))


@pytest.mark.parametrize("model", [("sopdt", 0.5, 1.2, 0.3), ("sopdt", 0.2, 0.35, 0.25),
                                   ("sopdt", 1.0, 2.0, 1.0), ("fopdt", 2.0, 5.0)])
def test_conversion_matches_scipy_zoh(model):
    """The discrete model scipy makes from the continuous one converts back
    to it (checks ln of real and complex poles and the DC gain)."""
    Ts = 0.3
    if model[0] == "fopdt":
        num, den = [model[1]], [model[2], 1.0]
    else:
        num, den = [model[1]], [1.0, model[2], model[3]]
    numd, dend, _ = signal.cont2discrete((num, den), Ts, method="zoh")
    numd = np.trim_zeros(np.ravel(numd), "f")
    back = ref.to_continuous(np.asarray(dend), numd, Ts)
    if model[0] == "fopdt":
        assert back["K"] == pytest.approx(model[1], rel=1e-10)
        assert back["tau"] == pytest.approx(model[2], rel=1e-10)
    else:
        assert back["k"] == pytest.approx(model[1], rel=1e-9)
        assert back["a"] == pytest.approx(model[2], rel=1e-9)
        assert back["b"] == pytest.approx(model[3], rel=1e-9)


def test_no_form_cases():
    Ts = 1.0
    assert ref.to_continuous(np.array([1.0, -1.0]), np.array([1.0]), Ts) is None  # integrator
    assert ref.to_continuous(np.array([1.0, -1.05]), np.array([1.0]), Ts) is None  # unstable
    assert ref.to_continuous(np.array([1.0, 0.5]), np.array([1.0]), Ts) is None  # alpha < 0
    # z^2 - 0.2 z - 0.48 = (z - 0.8)(z + 0.6): a negative real pole.
    assert ref.to_continuous(np.array([1.0, -0.2, -0.48]), np.array([1.0, 0.0]), Ts) is None
    # (z - 1)(z - 0.5): integrating.
    assert ref.to_continuous(np.array([1.0, -1.5, 0.5]), np.array([1.0, 0.0]), Ts) is None
    # complex pair with |z|^2 = 1.1.
    assert ref.to_continuous(np.array([1.0, -1.0, 1.1]), np.array([1.0, 0.0]), Ts) is None


@pytest.mark.slow
def test_eiv_less_biased_over_seeds():
    """Output noise biases ELMS (tau and K too small); E-IV removes most of
    it. Over ten seeds the mean relative errors must shrink by half at
    least (measured: about a fifth)."""
    Ts, n, truth, delay = 1.0, 600, ("fopdt", 2.0, 10.0), 4
    err = {"elms": [], "eiv": []}
    for seed in range(10):
        u = 40.0 + 5.0 * Rng.keyed(0x2000 + seed).signs(n, 12)
        y = gen.quantise(350.0 + gen.simulate(truth, delay, u, Ts)
                         + Rng.keyed(0x3000 + seed).noise(2.0, n))
        for method in err:
            _, best = ref.scan(u, y, Ts, 1, method, 0, 20)
            m = best["model"]
            err[method].append((abs(m["K"] / 2.0 - 1.0), abs(m["tau"] / 10.0 - 1.0)))
    elms = np.mean(err["elms"], axis=0)
    eiv = np.mean(err["eiv"], axis=0)
    assert np.all(eiv < 0.5 * elms), (elms, eiv)
    assert eiv[1] < 0.15


def test_vectors_consistent():
    """The chosen delay is the argmin of the stored cost curve."""
    for c in gen.cases():
        costs = c["costs"]
        assert c["best"]["delay"] == c["dmin"] + int(np.argmin(costs))
