"""Exact ZOH discretisation with a fractional dead time; simulation, prediction.

Route (independent of the C library's closed forms): the state-space model,
its matrix exponential, and the classic sampled model with a fractional
input delay (Astrom and Wittenmark, Computer-Controlled Systems, sec. 2.3).
With Td = (l + f) h, 0 <= f < 1, tau' = f h:

    x(k+1) = Phi x(k) + Gamma0 u(k-l) + Gamma1 u(k-l-1),  y = C x
    Phi    = e^{A h}
    Gamma0 = int_0^{h - tau'} e^{A s} ds B
    Gamma1 = e^{A (h - tau')} int_0^{tau'} e^{A s} ds B

and then the transfer function C (zI - Phi)^{-1} (Gamma0 + Gamma1 z^-1) z^-l,
written in the convention of lib/include/pdt/pdt_discrete.h:

    (1 + a[0] q + a[1] q^2) y(k) = (b[0] q + b[1] q^2 + b[2] q^3) q^l u(k).
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from . import models


class Discrete(NamedTuple):
    delay: int
    order: int
    a: tuple
    b: tuple


def split_delay(Td, Ts):
    """(l, f) with Td = (l + f) Ts; a fraction within rounding of 1 counts as 1."""
    r = Td / Ts
    l = math.floor(r)
    f = r - l
    if f >= 1.0 - 8.0 * np.finfo(float).eps * (1.0 + r):
        l, f = l + 1, 0.0
    return int(l), float(f)


def _sampled(m, Ts, f):
    """(Phi, Gamma0, Gamma1, C) of the fractional-delay sampled model."""
    A, B, C = models.state_space(m)
    tp = f * Ts
    Phi, _ = models.expm_integral(A, B, Ts)
    E0, G0 = models.expm_integral(A, B, Ts - tp)
    _, I1 = models.expm_integral(A, B, tp)
    G1 = E0 @ I1
    return Phi, G0, G1, C


def _zoh(m, Ts, l, f):
    if not (math.isfinite(Ts) and Ts > 0):
        raise ValueError("need finite Ts > 0")
    Phi, G0, G1, C = _sampled(m, Ts, f)
    if Phi.shape == (1, 1):
        phi = Phi[0, 0]
        c = C[0, 0]
        return Discrete(l, 1, (float(-phi), 0.0), (float(c * G0[0, 0]), float(c * G1[0, 0]), 0.0))
    # adj(zI - Phi) = zI - adj(Phi) for 2x2
    adj = np.array([[Phi[1, 1], -Phi[0, 1]], [-Phi[1, 0], Phi[0, 0]]])
    a0 = -(Phi[0, 0] + Phi[1, 1])
    a1 = Phi[0, 0] * Phi[1, 1] - Phi[0, 1] * Phi[1, 0]
    b0 = (C @ G0)[0, 0]
    b1 = (C @ G1)[0, 0] - (C @ adj @ G0)[0, 0]
    b2 = -(C @ adj @ G1)[0, 0]
    return Discrete(l, 2, (float(a0), float(a1)), (float(b0), float(b1), float(b2)))


def zoh(m, Ts):
    """Exact ZOH model of m at period Ts, fractional dead time included."""
    models.check(m)
    if not (math.isfinite(Ts) and Ts > 0):
        raise ValueError("need finite Ts > 0")
    l, f = split_delay(m.Td, Ts)
    return _zoh(m, Ts, l, f)


def zoh_int(m, Ts, l):
    """The paper's integer-delay model: m with its dead time replaced by l Ts."""
    models.check(m)
    if int(l) != l or l < 0:
        raise ValueError("need an integer l >= 0")
    return _zoh(m, Ts, int(l), 0.0)


def delta(m, Ts):
    """The delta form d of the denominator (pdt_discrete.h) from I - Phi.

    I - Phi = -A int_0^h e^{As} ds keeps full relative accuracy when the poles
    are near 1: d[0] = trace(I - Phi), d[1] = det(I - Phi) (0 for order 1).
    """
    A, _, _ = models.state_space(m)
    n = A.shape[0]
    _, W = models.expm_integral(A, np.eye(n), Ts)
    D = -A @ W
    if n == 1:
        return (float(D[0, 0]), 0.0)
    return (float(D[0, 0] + D[1, 1]), float(D[0, 0] * D[1, 1] - D[0, 1] * D[1, 0]))


def simulate(d, u):
    """Output of the difference equation from rest, fed its own outputs."""
    u = np.asarray(u, dtype=float)
    n = u.size
    a = list(d.a)[:d.order]
    y = np.zeros(n)
    upad = np.concatenate([np.zeros(d.delay + 3), u])
    off = d.delay + 3
    for k in range(n):
        acc = 0.0
        for i, bi in enumerate(d.b):
            acc += bi * upad[off + k - 1 - d.delay - i]
        for i, ai in enumerate(a):
            if k - 1 - i >= 0:
                acc -= ai * y[k - 1 - i]
        y[k] = acc
    return y


def predict(d, u, y):
    """One-step prediction from measured past outputs (0 before sample 0)."""
    u = np.asarray(u, dtype=float)
    y = np.asarray(y, dtype=float)
    n = u.size
    if y.size != n:
        raise ValueError("u and y differ in length")

    def shifted(x, s):
        out = np.zeros(n)
        if s < n:
            out[s:] = x[:n - s]
        return out

    yhat = np.zeros(n)
    for i, bi in enumerate(d.b):
        yhat += bi * shifted(u, d.delay + 1 + i)
    for i, ai in enumerate(list(d.a)[:d.order]):
        yhat -= ai * shifted(y, 1 + i)
    return yhat
