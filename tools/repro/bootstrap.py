"""The bootstrap of the paper's section 4.5: a higher-order model estimated
from the chirp record, then reduced to a FOPDT or SOPDT by a rule that needs
a known model (Skogestad's half rule, Sung et al.).

Estimate. For each order n = 3..6 and whole-sample delay d = 0..D, an ARX
model of the deviations from the operating point,
    y(k) + a_1 y(k-1) + ... + a_n y(k-n) = b_1 u(k-1-d) + ... + b_n u(k-n-d) + c,
is fitted by linear least squares and then refined as an output-error model
(the same structure, B/A simulated on u alone, fitted to y by nonlinear least
squares from the ARX start), which sensor noise does not bias. The order and
delay with the smallest Bayesian (Schwarz) criterion BIC = N ln(V) + p ln(N)
of the output error (V its mean square over the N samples, p = 2n + 1
parameters) are kept, among the candidates whose continuous counterpart
exists: every discrete pole inside the unit circle and off the negative real
axis. BIC rather than Akaike's criterion: their likelihoods differ by a few
units between orders 3 and 6 here, and BIC's larger penalty per parameter
settles on the smallest order that reaches the noise floor.

The record is first decimated (same zero-phase low-pass on u and y, which
leaves their relation unchanged): the chirp excites only 0-0.5 Hz, and at
20 Hz a model of order 3-6 spends its extra poles near z = 0 and on
near-cancelling pole-zero pairs outside that band.

Continuous model. The discrete B/A (without the delay) is turned into the
continuous system it samples behind a zero-order hold (the matrix logarithm
of the state matrix); its poles p and zeros z give lags T = -1/p and zero
time constants Z = -1/z (Z s + 1), the delay is d Ts, and the gain is the
DC gain. Where a pair is complex, each member is replaced by the real part
of its time constant: Re(T) + Re(conj T) = T + conj T, so the pair's
contribution to the sum of time constants (the mean residence time, which
the half rule distributes) is kept. A zero time constant whose magnitude is
below 1e-3 s is dropped (a zero beyond 1000 rad/s does nothing in band).
"""
import warnings

import numpy as np
import scipy.linalg as sl
import scipy.optimize as so
import scipy.signal as ss

ORDERS = (3, 4, 5, 6)


def _arx(u, y, n, d):
    """Least-squares ARX fit: theta = [a_1..a_n, b_1..b_n, c]."""
    N = len(y)
    k0 = n + d
    rows = []
    for k in range(k0, N):
        rows.append(np.concatenate([-y[k - n:k][::-1], u[k - n - d:k - d][::-1], [1.0]]))
    Phi = np.array(rows)
    theta, *_ = np.linalg.lstsq(Phi, y[k0:], rcond=None)
    return theta


def _simulate(theta, u, n, d):
    a = np.concatenate([[1.0], theta[:n]])
    b = np.concatenate([np.zeros(1 + d), theta[n:2 * n]])
    # c enters as a constant input through 1/A: an output offset c / A(1).
    return ss.lfilter(b, a, u) + theta[2 * n] / np.sum(a)


def _stable(theta, n):
    p = np.roots(np.concatenate([[1.0], theta[:n]]))
    return bool(np.all(np.abs(p) < 1.0)), p


def _oe(u, y, n, d, theta0):
    def resid(th):
        if not _stable(th, n)[0]:
            return np.full(len(y), 1e3)  # steer the search back inside
        return y - _simulate(th, u, n, d)
    sol = so.least_squares(resid, theta0, method="lm", max_nfev=200 * (2 * n + 1))
    return sol.x


def to_continuous(theta, n, Ts):
    """(K, poles, zeros) of the continuous system whose ZOH sampling is
    B/A, or None where it does not exist."""
    a = np.concatenate([[1.0], theta[:n]])
    b = np.concatenate([[0.0], theta[n:2 * n]])
    pz = np.roots(a)
    if np.any(np.abs(pz) >= 1.0) or np.any((np.abs(pz.imag) < 1e-9) & (pz.real <= 0.0)):
        return None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ss.BadCoefficients)
        A, B, C, D = ss.tf2ss(b, a)
    Ac = sl.logm(A) / Ts
    if np.max(np.abs(Ac.imag)) > 1e-6:
        return None
    Ac = Ac.real
    Bc = np.linalg.solve(A - np.eye(n), Ac @ B)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ss.BadCoefficients)
        z, p, _ = ss.ss2zpk(Ac, Bc, C, D)
    K = float((C @ np.linalg.solve(-Ac, Bc)).item())
    return K, p, z


def time_constants(roots, drop_below=0.0):
    """-1/r, real part of each member of a complex pair; near-infinite
    roots (|1/r| < drop_below) dropped."""
    out = []
    for r in roots:
        T = -1.0 / r
        if abs(T) < drop_below:
            continue
        out.append(float(np.real(T)))
    return sorted(out, key=lambda v: -abs(v))


def estimate(u, y, Ts, max_delay):
    """The best output-error model by BIC and every candidate tried, each a
    dict: n, d, V, bic, cont ((K, poles, zeros) or None), theta. u and y
    are deviations from the operating point (the first sample is taken as
    it)."""
    u = u - u[0]
    y = y - y[0]
    N = len(y)
    table = []
    best = None
    for n in ORDERS:
        # Delays ranked by the ARX estimate's simulated error (cheap); the
        # output-error refinement at the best three.
        arx_v = []
        for d in range(0, max_delay + 1):
            th = _arx(u, y, n, d)
            e = y - _simulate(th, u, n, d) if _stable(th, n)[0] else None
            arx_v.append((d, th, e))
        scored = []
        for d, th, e in arx_v:
            if e is None:
                continue
            scored.append((float(np.mean(e ** 2)), d, th))
        scored.sort(key=lambda s: s[0])
        for _, d, th in scored[:3]:
            th_oe = _oe(u, y, n, d, th)
            e = y - _simulate(th_oe, u, n, d)
            V = float(np.mean(e ** 2))
            bic = N * np.log(V) + (2 * n + 1) * np.log(N)
            cont = to_continuous(th_oe, n, Ts)
            row = dict(n=n, d=d, V=V, bic=bic, cont=cont, theta=th_oe)
            table.append(row)
            if cont is not None and cont[0] > 0 and (best is None or bic < best["bic"]):
                best = row
    return best, table
