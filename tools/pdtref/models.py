"""FOPDT and SOPDT models: forms, conversions, step and frequency responses.

The reference works from the state-space form of each model and a matrix
exponential of its own (``expm``), not from the closed-form step responses the
C library uses, so that agreement between the two checks both.

Models:
    Fopdt(K, tau, Td):    K e^{-Td s} / (tau s + 1)
    Sopdt(k, a, b, Td):   k e^{-Td s} / (s^2 + a s + b)   (paper form (2))
Other SOPDT forms (Natural, Tc, Integ) are conversions of Sopdt.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np


class NoFormError(ValueError):
    """The model has no representation in the requested form."""


class Fopdt(NamedTuple):
    K: float
    tau: float
    Td: float


class Sopdt(NamedTuple):
    k: float
    a: float
    b: float
    Td: float


class Natural(NamedTuple):
    """K wn^2 e^{-Td s} / (s^2 + 2 zeta wn s + wn^2)."""
    K: float
    wn: float
    zeta: float
    Td: float


class Tc(NamedTuple):
    """K e^{-Td s} / ((T1 s + 1)(T2 s + 1)); complex: time constants T1 +/- j T2."""
    K: float
    T1: float
    T2: float
    Td: float
    complex: bool = False


class Integ(NamedTuple):
    """Ki e^{-Td s} / (s (T s + 1))."""
    Ki: float
    T: float
    Td: float


def check(m):
    """Raises ValueError unless m is a valid Fopdt or Sopdt."""
    vals = [float(v) for v in m]
    if not all(math.isfinite(v) for v in vals):
        raise ValueError("non-finite parameter")
    if isinstance(m, Fopdt):
        if m.tau <= 0 or m.Td < 0:
            raise ValueError("need tau > 0, Td >= 0")
    elif isinstance(m, Sopdt):
        if m.a <= 0 or m.b < 0 or m.Td < 0:
            raise ValueError("need a > 0, b >= 0, Td >= 0")
    else:
        raise ValueError("not a model")
    return m


# ---- conversions ---------------------------------------------------------

def sopdt_from_natural(K, wn, zeta, Td):
    if not (wn > 0 and zeta > 0 and Td >= 0):
        raise ValueError("need wn > 0, zeta > 0, Td >= 0")
    return Sopdt(K * wn * wn, 2.0 * zeta * wn, wn * wn, Td)


def sopdt_from_tc(K, T1, T2, Td, complex=False):
    if not (T1 > 0 and T2 > 0 and Td >= 0):
        raise ValueError("need T1 > 0, T2 > 0, Td >= 0")
    if complex:
        # (T1 + j T2 ... ) pair: (T1^2 + T2^2) s^2 + 2 T1 s + 1
        p = T1 * T1 + T2 * T2
        return Sopdt(K / p, 2.0 * T1 / p, 1.0 / p, Td)
    return Sopdt(K / (T1 * T2), (T1 + T2) / (T1 * T2), 1.0 / (T1 * T2), Td)


def sopdt_from_integ(Ki, T, Td):
    if not (T > 0 and Td >= 0):
        raise ValueError("need T > 0, Td >= 0")
    return Sopdt(Ki / T, 1.0 / T, 0.0, Td)


def _poles(m):
    """Poles of the SOPDT denominator s^2 + a s + b, as complex numbers."""
    return np.roots([1.0, m.a, m.b]).astype(complex)


def to_natural(m):
    check(m)
    if m.b == 0:
        raise NoFormError("integrating model has no natural form")
    wn = math.sqrt(m.b)
    return Natural(m.k / m.b, wn, m.a / (2.0 * wn), m.Td)


def to_tc(m):
    """Time constants are -1/pole; a complex pair gives re +/- j im."""
    check(m)
    if m.b == 0:
        raise NoFormError("integrating model has no time-constant form")
    K = m.k / m.b
    if m.a * m.a >= 4.0 * m.b:
        # product of the time constants is 1/b: the larger from the smaller
        disc = math.sqrt(max(m.a * m.a / 4.0 - m.b, 0.0))
        T2 = 1.0 / (m.a / 2.0 + disc)
        T1 = 1.0 / (m.b * T2)
        return Tc(K, T1, T2, m.Td, False)
    p = _poles(m)
    t = -1.0 / p[np.argmax(p.imag)]  # -1/(-s + j w) = (s + j w)/(s^2 + w^2)
    return Tc(K, float(t.real), float(abs(t.imag)), m.Td, True)


def to_integ(m):
    check(m)
    if m.b != 0:
        raise NoFormError("only b = 0 has the integrating form")
    return Integ(m.k / m.a, 1.0 / m.a, m.Td)


def dc_gain(m):
    check(m)
    if isinstance(m, Fopdt):
        return float(m.K)
    if m.b == 0:
        raise NoFormError("integrating model has no DC gain")
    return m.k / m.b


# ---- state space and matrix exponential ----------------------------------

def state_space(m):
    """(A, B, C) of the delay-free model, y = C x, x' = A x + B u."""
    check(m)
    if isinstance(m, Fopdt):
        return (np.array([[-1.0 / m.tau]]), np.array([[m.K / m.tau]]), np.array([[1.0]]))
    # controllable canonical form: z'' + a z' + b z = u, y = k z
    A = np.array([[0.0, 1.0], [-m.b, -m.a]])
    B = np.array([[0.0], [1.0]])
    C = np.array([[m.k, 0.0]])
    return A, B, C


def expm(M):
    """e^M by scaling and squaring of a degree-20 Taylor polynomial."""
    M = np.asarray(M, dtype=float)
    n = M.shape[0]
    norm = float(np.max(np.sum(np.abs(M), axis=1))) if n else 0.0
    s = 0
    if norm > 0.25:
        s = int(math.ceil(math.log2(norm / 0.25)))
    X = M / (2.0 ** s)
    E = np.eye(n)
    term = np.eye(n)
    for j in range(1, 21):
        term = term @ X / j
        E = E + term
    for _ in range(s):
        E = E @ E
    return E


def expm_integral(A, B, t):
    """(e^{A t}, int_0^t e^{A s} ds B) from one exponential of [[A, B], [0, 0]] t."""
    n = A.shape[0]
    p = B.shape[1]
    M = np.zeros((n + p, n + p))
    M[:n, :n] = A * t
    M[:n, n:] = B * t
    E = expm(M)
    return E[:n, :n], E[:n, n:]


def step(m, t):
    """Unit-step response at times t (array), 0 before the dead time."""
    A, B, C = state_space(m)
    t = np.asarray(t, dtype=float)
    out = np.zeros(t.shape)
    flat = out.reshape(-1)
    for i, ti in enumerate(t.reshape(-1)):
        s = ti - m.Td
        if s > 0:
            _, G = expm_integral(A, B, s)
            flat[i] = float((C @ G)[0, 0])
    return out


def freq(m, w):
    """(|G(jw)|, arg G(jw)) at w >= 0 (rad/s).

    The phase is continuous: the sum of the angles of the pole factors (each
    within (-pi/2, pi/2] for a stable pole, -pi/2 for a pole at 0), minus
    w Td, minus pi for a negative gain. The magnitude of an integrator at
    w = 0 is +inf.
    """
    check(m)
    w = np.asarray(w, dtype=float)
    if np.any(w < 0) or not np.all(np.isfinite(w)):
        raise ValueError("need finite w >= 0")
    jw = 1j * w
    if isinstance(m, Fopdt):
        gain = m.K
        poles = [-1.0 / m.tau]
        scale = 1.0 / m.tau
    else:
        gain = m.k
        poles = list(_poles(m))
        if m.b == 0:
            poles = [0.0, -m.a]
        scale = 1.0
    mag = np.full(w.shape, abs(gain) * scale)
    phase = np.zeros(w.shape)
    with np.errstate(divide="ignore"):
        for p in poles:
            f = jw - p
            mag = mag / np.abs(f)
            ang = np.angle(f)
            if p == 0:
                ang = np.full(w.shape, math.pi / 2)
            phase = phase - ang
    if gain == 0:
        mag = np.zeros(w.shape)
    phase = phase - w * m.Td - (math.pi if gain < 0 else 0.0)
    return mag, phase
