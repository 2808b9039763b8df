"""Model validation (lib/src/pdt_validate.c), written independently in numpy.

The statistics follow their definitions (Ljung 1999, ch. 16) in double
precision. Where the C code must approximate, this takes a different route:
the parameter sensitivities are central differences with small steps (the C
library uses forward differences of the float simulation), the normal
equations of the model-error FIR are solved by numpy, and the robust bound
evaluates the FIR's frequency response by direct exponentials.

validate(m, u, y, Ts, y0) -> dict with sigma, aic, bic, white_stat,
inflation, cross_stat, fir_lag, fir (12), std (count), cov.
margin(res, gains, dTd) -> the robust Ms bound on the same 200-point grid.
"""
from __future__ import annotations

import math

import numpy as np

from . import discrete
from .models import Fopdt, Sopdt

LAGS = 20
FIR = 12
CHI = 3.0
GRID = 200


def _params(m):
    return list(m) if isinstance(m, Fopdt) else list(m)


def _with(m, p):
    return Fopdt(*p) if isinstance(m, Fopdt) else Sopdt(*p)


def _sim(m, du, Ts):
    return discrete.simulate(discrete.zoh(m, Ts), du)


def validate(m, u, y, Ts, y0):
    u = np.asarray(u, float)
    y = np.asarray(y, float)
    n = u.size
    du = u - u[0]
    ys = _sim(m, du, Ts)
    e_raw = y - y0 - ys
    p = _params(m)
    npar = len(p) + 1
    # Jacobian: the gain (linear), the shape by central differences, y0.
    J = np.zeros((n, npar))
    J[:, 0] = ys / p[0]
    for i in range(1, len(p)):
        h = 1e-6 * max(abs(p[i]), 1e-3 * Ts)
        lo = list(p)
        hi = list(p)
        hi[i] += h
        if i == len(p) - 1 or (isinstance(m, Sopdt) and i == 2):
            # Td and b stay in their domain (>= 0): one-sided there
            J[:, i] = (_sim(_with(m, hi), du, Ts) - ys) / h
        else:
            lo[i] -= h
            J[:, i] = (_sim(_with(m, hi), du, Ts) - _sim(_with(m, lo), du, Ts)) / (2 * h)
    J[:, -1] = 1.0
    sse = float(e_raw @ e_raw)
    e = e_raw - e_raw.mean()
    r0 = float(e @ e)
    rho = np.array([float(e[lag:] @ e[:-lag]) / r0 for lag in range(1, LAGS + 1)])
    white = n * float(rho @ rho)
    infl = max(1.0, 1.0 + 2.0 * float(rho.sum()))
    s2 = sse / (n - npar)
    cov = s2 * infl * np.linalg.inv(J.T @ J)
    ml = sse / n
    # Model-error FIR from a few samples before the model's dead time.
    l = int(m.Td / Ts)
    L0 = l + 1 - FIR // 4 if l + 1 > FIR // 4 else 1
    L0 = max(L0, 1)
    if L0 + FIR >= n // 2:
        L0 = 1
    X = np.zeros((n, FIR))
    for j in range(FIR):
        lag = L0 + j
        X[lag:, j] = du[:n - lag]
    X = X[L0:]
    ee = e[L0:]
    A = X.T @ X
    b = X.T @ ee
    A += 1e-4 * np.trace(A) / FIR * np.eye(FIR)
    h = np.linalg.solve(A, b)
    ess = float(h @ b)
    s2f = (r0 - ess) / (n - npar - FIR)
    return dict(model=m, Ts=Ts, n=n, sigma=math.sqrt(s2), aic=n * math.log(ml) + 2 * npar,
                bic=n * math.log(ml) + npar * math.log(n), white_stat=white, inflation=infl,
                cross_stat=ess / s2f, fir_lag=L0, fir=h, std=np.sqrt(np.diag(cov)), cov=cov)


def chi2_99(nu):
    """99 % quantile of chi-square (Wilson and Hilferty), as the C code."""
    c = 2.0 / (9.0 * nu)
    return nu * (1 - c + 2.3263 * math.sqrt(c)) ** 3


def margin(res, g, dTd=0.0, independent=None):
    """max |S| / (1 - |C S| D) over the C library's grid; D the FIR's
    magnitude (unless independent) plus CHI std of |G| (first order)."""
    m = res["model"]
    Ts = res["Ts"]
    if independent is None:
        independent = res["cross_stat"] <= chi2_99(FIR)
    Kc, tI, tD, Tf = g
    Td = m.Td + dTd
    if isinstance(m, Fopdt):
        tm = m.tau
    else:
        tm = m.a / (m.b if m.b > 0 else m.a * m.a)
    T = max(tI, tm, Td)
    w = (1e-3 / T) * np.exp(np.log((math.pi / Ts) / (1e-3 / T)) * np.arange(GRID) / (GRID - 1))
    s = 1j * w
    if isinstance(m, Fopdt):
        den = m.tau * s + 1
        gain = m.K
    else:
        den = s * s + m.a * s + m.b
        gain = m.k
    G = gain * np.exp(-Td * s) / den
    if isinstance(m, Fopdt):
        dg = [G / gain, -s * G / den, -s * G]
    else:
        dg = [G / gain, -s * G / den, -G / den, -s * G]
    cov = res["cov"][:len(dg), :len(dg)]
    q = np.zeros(GRID)
    for a in range(len(dg)):
        for b in range(len(dg)):
            if not isinstance(m, Fopdt) and m.b == 0 and (a == 2 or b == 2):
                continue
            q += cov[a, b] * (dg[a].real * dg[b].real + dg[a].imag * dg[b].imag)
    dpar = CHI * np.sqrt(np.maximum(q, 0.0))
    dfir = np.zeros(GRID)
    if not independent:
        lags = res["fir_lag"] + np.arange(FIR)
        dfir = np.abs(np.exp(-1j * np.outer(w * Ts, lags)) @ res["fir"])
    C = Kc * (1 + 1 / (tI * s) + tD * s / (Tf * s + 1))
    S = 1 / np.abs(1 + C * G)
    cs = np.abs(C) * S * (dpar + dfir)
    bound = np.where(cs < 1, S / np.maximum(1 - cs, 1e-300), np.inf)
    return float(max(1.0, bound.max()))
