"""The plant simulator of pdtfit's Python tools, tests and benchmarks: a
linear plant num(s) / den(s) e^{-L s} (polynomials, highest power first)
driven through a zero-order hold, sampled exactly. Written apart from the
C library (it shares no code with pdt_discrete or tools/sim) and from the
numpy reference pdtref, whose discretisations it checks.

- exact(A, B, t): e^{A t} and int_0^t e^{A s} ds B from one exponential
  (the hold's state-space model over t, as scipy's cont2discrete makes it);
- Fine: the plant stepped on a grid of which the dead time is a whole
  number of steps (the closed loops, the benchmarks' step responses, the
  replay of the command line's simulator);
- fractional(): the plant at its scan period with a fractional dead time
  (x+ = Phi x + G0 u(k-l) + G1 u(k-l-1), Astrom and Wittenmark), the form
  the autotune benchmark's driver steps in C;
- simulate(): a record's samples for a held input (scipy's lsim on a fine
  grid), the command-line tests' and several benchmarks' records;
- first_order(): K / (tau s + 1) with a dead time of whole samples, by its
  exact difference equation (records that the identification's ZOH model
  fits exactly).
"""
import math

import numpy as np
import scipy.linalg as sla
import scipy.signal as ss


def state_space(num, den):
    """(A, B, C, D) of num / den: B and C as vectors, D as a float."""
    A, B, C, D = ss.tf2ss(num, den)
    return A, B[:, 0], C[0, :], float(D[0, 0])


def exact(A, B, t):
    """(e^{A t}, int_0^t e^{A s} ds B) for a vector B, from the exponential
    of [[A, B], [0, 0]] t."""
    n = A.shape[0]
    M = np.zeros((n + 1, n + 1))
    M[:n, :n] = A * t
    M[:n, n] = B * t
    E = sla.expm(M)
    return E[:n, :n], E[:n, n]


class Fine:
    """num / den e^{-L s} from rest on a grid of step h with L = delay h:
    each advance() feeds the hold one input and moves one step on with the
    input of `delay` steps before."""

    def __init__(self, num, den, h, delay):
        A, B, self.C, self.D = state_space(num, den)
        self.Phi, self.G = exact(A, B, h)
        self.x = np.zeros(A.shape[0])
        self.fifo = [0.0] * (int(delay) + 1)  # the inputs, delay steps back
        self.at = 0

    def output(self):
        """y at this step, the plant strictly proper."""
        return float(self.C @ self.x)

    def output_fed(self, w):
        """y at this step with the feedthrough of the delayed input w."""
        return float(self.C @ self.x + self.D * w)

    def advance(self, w):
        """Feeds w and moves one step; returns the input that moved it."""
        self.fifo[self.at] = w
        self.at = (self.at + 1) % len(self.fifo)
        wd = self.fifo[self.at]
        self.x = self.Phi @ self.x + self.G * wd
        return wd


def step_response(num, den, L, h, n):
    """The unit step response at t = k h, k < n (L a whole number of
    steps)."""
    p = Fine(num, den, h, 0)
    m = int(round(L / h))
    y = np.zeros(n)
    for k in range(n):
        y[k] = p.output()
        p.x = p.Phi @ p.x + p.G if k >= m else p.Phi @ p.x
    return y


def fractional(num, den, L, Ts):
    """(Phi, G0, G1, C, l): x(k+1) = Phi x(k) + G0 u(k-l) + G1 u(k-l-1),
    y = C x, for the dead time L = (l + f) Ts, 0 <= f < 1."""
    A, B, C, _ = state_space(num, den)
    x = L / Ts
    l = int(math.floor(x + 1e-9))
    f = x - l
    if f < 1e-9:
        f = 0.0
    Phi, _ = exact(A, B, Ts)
    Pm, Gm = exact(A, B, (1.0 - f) * Ts)
    _, Gf = exact(A, B, f * Ts)
    return Phi, Gm, Pm @ Gf, C, l


def simulate(num, den, Td, u, Ts, sub=20):
    """Samples y(k Ts) of num/den e^{-Td s} for the ZOH input u (deviations),
    from rest. Td must be a multiple of Ts / sub."""
    h = Ts / sub
    shift = round(Td / h)
    assert abs(shift * h - Td) < 1e-9
    uf = np.repeat(u, sub)
    uf = np.concatenate([np.zeros(shift), uf])[: len(uf)]
    t = np.arange(len(uf)) * h
    _, yf, _ = ss.lsim((num, den), uf, t, interp=False)
    return yf[::sub]


def first_order(K, a, du, l=0):
    """x(k), k < len(du), of x(k+1) = a x(k) + K (1 - a) du(k - l) from
    x(0) = 0 (du before the record 0): K e^{-l Ts s} / (tau s + 1) sampled
    exactly behind a hold, a = e^{-Ts / tau}."""
    b = K * (1 - a)
    x = np.zeros(len(du))
    for k in range(1, len(du)):
        x[k] = a * x[k - 1] + b * (du[k - 1 - l] if k - 1 - l >= 0 else 0.0)
    return x
