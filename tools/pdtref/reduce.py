"""Model reduction: Skogestad's half rule (2003) and Sung et al. (1998).

The detailed model is

    G(s) = k * prod_j (T_j s + 1) / prod_i (tau_i s + 1) * exp(-theta0 s),

tau_i > 0 (lags), T_j != 0 (T_j < 0: right-half-plane zero). Conventions as
in docs/reduce.md.

Half rule: written from the rule table (each left-half-plane rule is selected
by testing its own condition as published, not by a decision tree).

Sung: the frequency response comes from the expanded polynomials
(np.polyval of the numerator and denominator at j w), the ultimate frequency
from a dense logarithmic grid of the unwrapped phase refined by bisection,
and the least squares from np.linalg.lstsq on the unscaled columns - a
different route from the library's factor-by-factor sums, so agreement
between the two checks both.
"""
from __future__ import annotations

import math
from typing import NamedTuple, Sequence

import numpy as np

MAX_PASSES = 48
N_FREQ = 10

RULE_T1 = 0x01
RULE_T1A = 0x02
RULE_T1B = 0x04
RULE_T2 = 0x08
RULE_T3 = 0x10


class NoFormError(ValueError):
    """The reduction has no result of the requested form."""


class Plant(NamedTuple):
    k: float
    lags: tuple
    zeros: tuple = ()
    theta0: float = 0.0


class HalfResult(NamedTuple):
    K: float
    T: tuple          # (tau,) for FOPDT, (T1, T2) for SOPDT
    Td: float
    rules: int        # RULE_* bits used in the final pass
    passes: int
    converged: bool
    margin: float     # smallest relative gap of a rule comparison (ties)


class SungResult(NamedTuple):
    kind: str         # "fopdt" or "sopdt"
    K: float
    tau: float        # FOPDT tau, or SOPDT 1/wn
    zeta: float       # SOPDT damping (nan for FOPDT)
    Td: float
    w_u: float
    fallback: bool
    q: tuple          # SOPDT fit: (p1 w_u^2, p2 w_u^4); () for FOPDT


def _gap(a, b):
    """Relative distance of a and b (how far a comparison is from a tie)."""
    s = max(abs(a), abs(b))
    return abs(a - b) / s if s > 0 else math.inf


def _pairs(plant: Plant):
    """[(lag index, zero value)] for every left-half-plane zero.

    Largest zero first; each takes the smallest unused lag >= T0, else the
    largest unused lag."""
    lhp = sorted(((T, -j) for j, T in enumerate(plant.zeros) if T > 0), reverse=True)
    free = set(range(len(plant.lags)))
    out = []
    for T0, _ in lhp:
        above = [i for i in free if plant.lags[i] >= T0]
        if above:
            i = min(above, key=lambda i: (plant.lags[i], i))
        elif free:
            i = max(free, key=lambda i: (plant.lags[i], -i))
        else:
            raise NoFormError("a left-half-plane zero has no lag to cancel")
        free.remove(i)
        out.append((i, T0))
    return out, free


def _split(lags, order, base):
    """Half rule on a list of lags: (time constants, dead time)."""
    l = sorted(lags, reverse=True) + [0.0] * 3
    if order == 1:
        return (l[0] + l[1] / 2,), base + l[1] / 2 + sum(l[2:])
    return (l[0], l[1] + l[2] / 2), base + l[2] / 2 + sum(l[3:])


def _rule(T0, tau0, tc):
    """(rule bit, gain, remaining lag or None) for (T0 s + 1)/(tau0 s + 1)."""
    t = min(tau0, 5 * tc)
    table = [
        (RULE_T1, T0 > tau0 and tau0 >= tc, T0 / tau0, None),
        (RULE_T1A, T0 > tau0 and T0 >= tc > tau0, T0 / tc if tc > 0 else 0.0, None),
        (RULE_T1B, T0 > tau0 and tc > T0, 1.0, None),
        (RULE_T2, tau0 >= T0 >= 5 * tc, T0 / tau0, None),
        (RULE_T3, tau0 >= T0 and t >= T0 and T0 < 5 * tc, t / tau0, t - T0),
    ]
    hits = [r for r in table if r[1]]
    assert len(hits) == 1, (T0, tau0, tc, hits)
    bit, _, gain, lag = hits[0]
    return bit, gain, lag


def half_rule(plant: Plant, order: int = 1, h: float = 0.0) -> HalfResult:
    """Skogestad's half rule to a FOPDT (order 1) or SOPDT (order 2)."""
    if order not in (1, 2):
        raise ValueError("order is 1 or 2")
    if not plant.lags or any(t <= 0 for t in plant.lags) or any(T == 0 for T in plant.zeros):
        raise ValueError("lags > 0, zeros != 0")
    if plant.theta0 < 0 or h < 0:
        raise ValueError("theta0 >= 0, h >= 0")
    pairs, free = _pairs(plant)
    base = plant.theta0 + sum(-T for T in plant.zeros if T < 0) + h / 2
    _, tc = _split(list(plant.lags), order, base)
    passes = 0
    converged = False
    while passes < MAX_PASSES and not converged:
        passes += 1
        gain = plant.k
        rules = 0
        lags = [plant.lags[i] for i in sorted(free)]
        margin = math.inf
        for i, T0 in pairs:
            tau0 = plant.lags[i]
            bit, g, lag = _rule(T0, tau0, tc)
            rules |= bit
            gain *= g
            if lag is not None and lag > 0:
                lags.append(lag)
            margin = min(margin, _gap(T0, tau0), _gap(tau0, tc), _gap(T0, tc),
                         _gap(T0, 5 * tc), _gap(tau0, 5 * tc))
        T, theta = _split(lags, order, base)
        converged = abs(theta - tc) <= 8 * np.finfo(float).eps * theta
        tc = theta
    if len(lags) < order:
        raise NoFormError("fewer lags than the model's order remain")
    for i, T0 in pairs:
        margin = min(margin, *(_gap(T0, t) for t in plant.lags))
    if not pairs:
        margin = math.inf
    return HalfResult(gain, T, theta, rules, passes, converged, margin)


# --------------------------------------------------------------------------
# Sung et al.

def polys(plant: Plant):
    """Numerator and denominator of G / k (without the delay), highest power
    first, as numpy coefficient arrays."""
    num = np.array([1.0])
    for T in plant.zeros:
        num = np.polymul(num, [T, 1.0])
    den = np.array([1.0])
    for t in plant.lags:
        den = np.polymul(den, [t, 1.0])
    return num, den


def response(plant: Plant, w):
    """G(jw) / k without the delay, from the polynomials."""
    num, den = polys(plant)
    s = 1j * np.asarray(w, dtype=float)
    return np.polyval(num, s) / np.polyval(den, s)


def ultimate(plant: Plant, points_per_decade: int = 2000) -> float:
    """First w > 0 where the continuous phase of G/k reaches -pi."""
    span = plant.theta0 + sum(plant.lags) + sum(abs(T) for T in plant.zeros)
    shortest = min(list(plant.lags) + [abs(T) for T in plant.zeros])
    w0 = 1e-3 / span
    w1 = 1e4 / shortest
    if plant.theta0 > 0:
        n_lhp = sum(1 for T in plant.zeros if T > 0)
        w1 = max(w1, 2 * math.pi * (1 + 0.5 * n_lhp) / plant.theta0)
    n = int(math.ceil(points_per_decade * math.log10(w1 / w0))) + 1
    w = np.geomspace(w0, w1, n)
    ph = np.unwrap(np.angle(response(plant, w))) - w * plant.theta0
    # the first point is within 1e-3 rad of 0, so the unwrapped phase is the
    # continuous phase from w = 0
    below = np.nonzero(ph <= -math.pi)[0]
    if below.size == 0:
        raise NoFormError("no phase crossover")
    j = int(below[0])
    lo, hi = float(w[j - 1]), float(w[j])
    w_ref, ph_ref = lo, float(ph[j - 1])
    g_ref = response(plant, w_ref)

    def phase(x):
        step = np.angle(response(plant, x) / g_ref)  # small within the bracket
        return ph_ref + step - (x - w_ref) * plant.theta0

    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        if phase(mid) <= -math.pi:
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)


def sung(plant: Plant, order: int = 1, n_freq: int = N_FREQ) -> SungResult:
    """Sung et al.'s FOPDT (order 1) or SOPDT (order 2) from G up to w_u."""
    if plant.k == 0:
        raise NoFormError("k = 0")
    wu = ultimate(plant)
    w = wu * np.arange(1, n_freq + 1) / n_freq
    K = plant.k
    G2 = (K * np.abs(response(plant, w))) ** 2
    psi = K ** 2 - G2
    phi1 = G2 * w ** 2
    tau2 = float(phi1 @ psi / (phi1 @ phi1))
    if not tau2 > 0:
        raise NoFormError("tau^2 <= 0")
    tau = math.sqrt(tau2)
    fop = SungResult("fopdt", K, tau, math.nan, (math.pi - math.atan(tau * wu)) / wu,
                     wu, False, ())
    if order == 1:
        return fop
    A = np.column_stack([phi1, G2 * w ** 4])
    (p1, p2), *_ = np.linalg.lstsq(A, psi, rcond=None)
    q = (float(p1 * wu ** 2), float(p2 * wu ** 4))
    if p2 <= 0:
        return fop._replace(fallback=True, q=q)
    T = p2 ** 0.25
    z2 = (p1 / T ** 2 + 2) / 4
    if z2 <= 0:
        return fop._replace(fallback=True, q=q)
    zeta = math.sqrt(z2)
    Td = (math.pi - math.atan2(2 * zeta * T * wu, 1 - T ** 2 * wu ** 2)) / wu
    return SungResult("sopdt", K, float(T), zeta, float(Td), wu, False, q)


def sopdt_form2(K, T1, T2):
    """(k, a, b) of form (2) for K / ((T1 s + 1)(T2 s + 1))."""
    b = 1.0 / (T1 * T2)
    return K * b, 1.0 / T1 + 1.0 / T2, b


def sopdt_natural_form2(K, tau, zeta):
    """(k, a, b) of form (2) for K / (tau^2 s^2 + 2 zeta tau s + 1)."""
    b = 1.0 / tau ** 2
    return K * b, 2 * zeta / tau, b


def paper_plant() -> Plant:
    """The paper's test system (17)."""
    return Plant(1.0, (2.0, 1.0, 0.4, 0.2, 0.05, 0.05, 0.05), (-0.3, 0.08), 0.0)
