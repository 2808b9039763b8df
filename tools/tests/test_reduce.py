"""Checks of pdtref.reduce: the paper's figures for system (17), each
left-half-plane zero rule on a hand-worked case, exact recovery of models
already in the target form, and Sung's method against an implementation
through scipy (analytic phase + brentq, scipy.signal.freqs, scipy lstsq)."""
import math

import numpy as np
import pytest
from scipy import linalg, optimize, signal

from pdtref import reduce as R

P17 = R.paper_plant()


def test_paper_half_rule():
    f = R.half_rule(P17, 1)
    assert f.K == pytest.approx(1.0)
    assert f.T[0] == pytest.approx(2.5)
    assert f.Td == pytest.approx(1.47)
    assert f.rules == R.RULE_T3 and f.converged
    s = R.half_rule(P17, 2)
    assert s.T == pytest.approx((2.0, 1.2))
    assert s.Td == pytest.approx(0.77)
    assert R.half_rule(P17, 2, h=0.1).Td == pytest.approx(0.82)


def test_paper_sung():
    f = R.sung(P17, 1)
    assert f.w_u == pytest.approx(1.1852, abs=1e-4)
    assert f.tau == pytest.approx(2.8564, abs=1e-4)   # paper 2.86
    assert f.Td == pytest.approx(1.5677, abs=1e-4)    # paper 1.57
    s = R.sung(P17, 2)
    assert s.kind == "sopdt" and s.zeta > 1
    roots = np.roots([s.tau ** 2, 2 * s.zeta * s.tau, 1])
    assert sorted(-1 / roots) == pytest.approx([1.217, 1.866], abs=2e-3)
    assert s.Td == pytest.approx(0.870, abs=1e-3)


# (plant, order, rule, K, time constants, Td), worked by hand from the rules
RULE_CASES = [
    (R.Plant(1, (3.0, 0.5), (4.0,), 0.2), 1, R.RULE_T1, 4 / 3, (0.5,), 0.2),
    (R.Plant(1, (0.5, 0.3), (0.8,), 0.6), 1, R.RULE_T1A, 0.8 / 0.6, (0.3,), 0.6),
    (R.Plant(1, (0.5, 0.3), (0.8,), 1.0), 1, R.RULE_T1B, 1.0, (0.3,), 1.0),
    (R.Plant(1, (10.0, 1.0), (9.0,), 0.0), 1, R.RULE_T2, 0.9, (1.0,), 0.0),
    # 5 theta = 4 < 10: (2s+1)/(10s+1) -> 0.4/(2s+1); lags 2, 1
    (R.Plant(1, (10.0, 1.0), (2.0,), 0.3), 1, R.RULE_T3, 0.4, (2.5,), 0.8),
    (R.Plant(1.5, (3.0, 2.0, 0.5), (4.0,), 0.2), 2, R.RULE_T1, 2.0, (2.0, 0.5), 0.2),
    (R.Plant(1, (0.5, 0.4, 0.3), (0.8,), 0.6), 2, R.RULE_T1A, 0.8 / 0.6, (0.4, 0.3), 0.6),
    (R.Plant(1, (0.5, 0.4, 0.3), (0.8,), 1.0), 2, R.RULE_T1B, 1.0, (0.4, 0.3), 1.0),
    (R.Plant(1, (10.0, 3.0, 1.0), (9.0,), 0.0), 2, R.RULE_T2, 0.9, (3.0, 1.0), 0.0),
    # 5 theta = 3 < 4: (2s+1)/(4s+1) -> 0.75/(s+1); lags 10, 1, 1
    (R.Plant(1, (10.0, 4.0, 1.0), (2.0,), 0.1), 2, R.RULE_T3, 0.75, (10.0, 1.5), 0.6),
]


@pytest.mark.parametrize("plant,order,rule,K,T,Td", RULE_CASES)
def test_rules(plant, order, rule, K, T, Td):
    r = R.half_rule(plant, order)
    assert r.rules == rule
    assert r.converged
    assert r.K == pytest.approx(K)
    assert r.T == pytest.approx(T)
    assert r.Td == pytest.approx(Td, abs=1e-12)


def test_half_rule_no_form():
    with pytest.raises(R.NoFormError):
        R.half_rule(R.Plant(1, (1.0,), (0.5, 0.2), 0.5), 1)
    with pytest.raises(R.NoFormError):
        R.half_rule(R.Plant(1, (1.0,), (), 0.5), 2)


def test_half_rule_lag_order_irrelevant():
    shuffled = R.Plant(1, (0.05, 0.2, 1.0, 0.05, 2.0, 0.4, 0.05), (0.08, -0.3), 0.0)
    for order in (1, 2):
        a, b = R.half_rule(P17, order), R.half_rule(shuffled, order)
        assert a.T == pytest.approx(b.T) and a.Td == pytest.approx(b.Td)


def test_sung_recovers_fopdt_and_sopdt():
    f = R.sung(R.Plant(1.5, (2.0,), (), 0.8), 1)
    assert (f.K, f.tau, f.Td) == pytest.approx((1.5, 2.0, 0.8), rel=1e-9)
    s = R.sung(R.Plant(1.5, (2.0, 0.5), (), 0.8), 2)
    assert s.kind == "sopdt"
    assert s.tau == pytest.approx(1.0, rel=1e-9)            # sqrt(2 * 0.5)
    assert s.zeta == pytest.approx(2.5 / 2.0, rel=1e-9)     # (2 + 0.5) / (2 tau)
    assert s.Td == pytest.approx(0.8, rel=1e-9)


def _scipy_sung(plant, order, n_freq=10):
    """Sung's method through scipy: w_u by brentq on the analytic phase,
    |G| by scipy.signal.freqs, the fit by scipy.linalg.lstsq."""
    def phase(w):
        return (sum(math.atan(T * w) for T in plant.zeros)
                - sum(math.atan(t * w) for t in plant.lags) - w * plant.theta0)

    grid = np.geomspace(1e-4, 1e4, 40001)
    j = next(i for i, w in enumerate(grid) if phase(w) <= -math.pi)
    wu = optimize.brentq(lambda w: phase(w) + math.pi, grid[j - 1], grid[j], xtol=1e-15,
                         rtol=1e-15)
    num, den = R.polys(plant)
    w = wu * np.arange(1, n_freq + 1) / n_freq
    _, g = signal.freqs(num * plant.k, den, worN=w)
    G2 = np.abs(g) ** 2
    psi = plant.k ** 2 - G2
    cols = [G2 * w ** 2] + ([G2 * w ** 4] if order == 2 else [])
    p, *_ = linalg.lstsq(np.column_stack(cols), psi)
    return wu, p


@pytest.mark.parametrize("plant", [
    P17,
    R.Plant(2.0, (5.0, 2.0, 1.0, 0.5, 0.1), (1.5, 0.3, -0.2), 0.7),
    R.Plant(1.0, (1.0, 1.0, 1.0), (-0.5,), 0.0),
    R.Plant(-0.7, (4.0, 4.0, 0.7, 0.2), (0.6, 0.15, -0.4, -0.1), 0.25),
])
def test_sung_against_scipy(plant):
    wu, (tau2,) = _scipy_sung(plant, 1)
    f = R.sung(plant, 1)
    assert f.w_u == pytest.approx(wu, rel=1e-12)
    assert f.tau == pytest.approx(math.sqrt(tau2), rel=1e-10)
    assert f.Td == pytest.approx((math.pi - math.atan(math.sqrt(tau2) * wu)) / wu, rel=1e-10)
    _, (p1, p2) = _scipy_sung(plant, 2)
    s = R.sung(plant, 2)
    assert s.q == pytest.approx((p1 * wu ** 2, p2 * wu ** 4), rel=1e-8)


def test_sung_no_crossover():
    with pytest.raises(R.NoFormError):
        R.sung(R.Plant(1, (2.0, 1.0), (), 0.0), 1)


def test_step_iae_of_published_reductions():
    """IAE over 0-15 s of each FOPDT against the step response of (17):
    0.22 for the half rule and 0.44 for Sung's (as recorded for the team)."""
    num, den = R.polys(P17)
    t = np.linspace(0.0, 15.0, 15001)
    _, y = signal.step((num, den), T=t)

    def iae(tau, Td):
        m = np.where(t > Td, 1 - np.exp(-(t - Td) / tau), 0.0)
        return np.trapezoid(np.abs(y - m), t) if hasattr(np, "trapezoid") else \
            np.trapz(np.abs(y - m), t)

    h = R.half_rule(P17, 1)
    s = R.sung(P17, 1)
    assert iae(h.T[0], h.Td) == pytest.approx(0.22, abs=0.01)
    assert iae(s.tau, s.Td) == pytest.approx(0.44, abs=0.01)


def test_vectors_deterministic():
    from vectorgen import reduce as V
    a = V.generate()
    b = V.generate()
    assert a == b
    assert sum(len(v) for v in a.values()) < 200_000


def test_iteration_leaves_an_unstable_fixed_point():
    """A clamped T3 lag that lands in the dead time makes the delay map
    theta -> (5 theta - T0) / 2 (slope 2.5): the iteration moves away from
    its fixed point until rule T2 removes the lag."""
    p = R.Plant(1.0, (0.36512213, 0.021476748), (0.032494574,))
    r = R.half_rule(p, 1)
    assert r.converged and r.passes == 7
    assert r.rules == R.RULE_T2
    assert r.Td == 0.0 and r.T == pytest.approx((0.021476748,))
    assert r.K == pytest.approx(0.032494574 / 0.36512213)
