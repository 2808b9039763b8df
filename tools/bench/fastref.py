"""A fast output-error reference fit, independent of the C library.

The model is simulated exactly (zero-order hold, fractional dead time) by one
`scipy.signal.lfilter` per evaluation, from closed forms of the step
response; the gain and the output offset are solved in closed form for each
shape (variable projection), so the search runs over the shape and the dead
time only: (log tau, Td) for a FOPDT, (log a, 1/zeta, Td) for a SOPDT in
form (2), `k / (s^2 + a s + b)` with `b = (a / (2 zeta))^2` (1/zeta = 0 is
the integrator). Each start is polished by a bounded Levenberg-Marquardt iteration
(forward-difference Jacobian; numpy solves the small normal equations):
scipy.optimize.least_squares does the same steps with several times the
overhead per step on problems this small. The bounds are
pdtfit's defaults: time constants in [Ts/4, 2T] (SOPDT 1/a from Ts/8),
Td in [0, T/3], 1/zeta in [0, 5].

The criterion is pdtfit's: the mean square, over the whole record, of
y - g x - c, x the unit-gain simulated response to u - u[0] from rest and
(g, c) its least-squares gain and offset.
"""
from __future__ import annotations

import math

import numpy as np
import scipy.signal as ss

from pdtbench.benchlib import models

ZETA_MIN = 0.2


def split_delay(Td, Ts):
    r = Td / Ts
    l = math.floor(r + 1e-12)
    f = r - l
    if f >= 1.0 - 1e-12:
        l, f = l + 1, 0.0
    return int(l), max(f, 0.0)


def _e(p, t):
    """(1 - e^{-p t}) / p, t at p = 0."""
    return t if p == 0.0 else -math.expm1(-p * t) / p


def _h_real(p1, p2, t):
    """Step response of 1 / ((s + p1)(s + p2)), p1 >= p2 >= 0."""
    if p1 - p2 <= 1e-6 * p1:
        p = 0.5 * (p1 + p2)
        return -math.expm1(-p * t) / (p * p) - t * math.exp(-p * t) / p
    return (_e(p2, t) - _e(p1, t)) / (p1 - p2)


def _h_cplx(sig, wd, t):
    """Step response of 1 / (s^2 + 2 sig s + sig^2 + wd^2)."""
    return (1.0 - math.exp(-sig * t) * (math.cos(wd * t) + sig / wd * math.sin(wd * t))) / \
        (sig * sig + wd * wd)


def fopdt_filter(tau, Td, Ts):
    """(num, den, shift) of the unit-gain FOPDT at Ts: the output is
    lfilter(num, den, u) delayed by shift samples (the dead time as a shift
    rather than leading zeros of num, which lfilter would multiply)."""
    l, f = split_delay(Td, Ts)
    m = 1.0 - f
    a = math.exp(-Ts / tau)
    am = math.exp(-m * Ts / tau)
    return np.array([1.0 - am, am - a]), np.array([1.0, -a]), l + 1


def sopdt_filter(a, rz, Td, Ts, scale=1.0):
    """(num, den, shift) of scale / (s^2 + a s + b), b = (a rz / 2)^2, at Ts."""
    l, f = split_delay(Td, Ts)
    m = 1.0 - f
    sig = 0.5 * a
    wn = sig * rz
    b = wn * wn
    if rz > 1.0:
        wd = math.sqrt(b - sig * sig)
        A1 = -2.0 * math.exp(-sig * Ts) * math.cos(wd * Ts)

        def h(t):
            return _h_cplx(sig, wd, t)
    else:
        beta = sig * math.sqrt(max(0.0, 1.0 - rz * rz))
        p1 = sig + beta
        p2 = b / p1
        A1 = -(math.exp(-p1 * Ts) + math.exp(-p2 * Ts))

        def h(t):
            return _h_real(p1, p2, t)
    A2 = math.exp(-a * Ts)
    h1, h2, h3 = (scale * h(k * Ts) for k in (m, 1.0 + m, 2.0 + m))
    g1, g2, g3 = h1, h2 - h1, h3 - h2
    return (np.array([g1, g2 + A1 * g1, g3 + A1 * g2 + A2 * g1]), np.array([1.0, A1, A2]),
            l + 1)


def shifted_filter(num, den, shift, u):
    """lfilter(num, den) of u delayed by shift samples, from rest."""
    out = np.zeros(u.size)
    if shift < u.size:
        out[shift:] = ss.lfilter(num, den, u[:u.size - shift])
    return out


class FastRef:
    """Nine-start (by default) output-error fit of a FOPDT or SOPDT."""

    def __init__(self, u, y, Ts, model):
        self.y = np.asarray(y, float)
        self.du = np.asarray(u, float) - float(u[0])
        self.n = self.y.size
        self.Ts = float(Ts)
        self.T = self.n * self.Ts
        self.kind = model
        self.yc = self.y - self.y.mean()
        self.yy = float(self.yc @ self.yc)
        self.nfev = 0
        T, Ts = self.T, self.Ts
        if model == "fopdt":
            self.lo = np.array([math.log(Ts / 4.0), 0.0])
            self.hi = np.array([math.log(2.0 * T), T / 3.0])
        else:
            self.lo = np.array([math.log(1.0 / (2.0 * T)), 0.0, 0.0])
            self.hi = np.array([math.log(8.0 / Ts), 1.0 / ZETA_MIN, T / 3.0])

    # -- the model of a parameter vector
    def unit(self, x):
        """Unit-gain (or unit-scale) response to du."""
        if self.kind == "fopdt":
            num, den, s = fopdt_filter(math.exp(x[0]), x[1], self.Ts)
        else:
            a = math.exp(x[0])
            b = (0.5 * a * x[1]) ** 2
            num, den, s = sopdt_filter(a, x[1], x[2], self.Ts, scale=b + a / self.T)
        return shifted_filter(num, den, s, self.du)

    def resid(self, x):
        self.nfev += 1
        w = self.unit(x)
        wc = w - w.mean()
        ww = float(wc @ wc)
        if not ww > 0.0:
            return self.yc
        return self.yc - (float(wc @ self.yc) / ww) * wc

    def cost(self, x):
        r = self.resid(x)
        return float(r @ r) / self.n

    def model_of(self, x):
        """pdtref model (with its least-squares gain) and offset of x."""
        w = self.unit(x)
        A = np.column_stack([w, np.ones(self.n)])
        g, off = np.linalg.lstsq(A, self.y, rcond=None)[0]
        if self.kind == "fopdt":
            return models.Fopdt(float(g), math.exp(x[0]), float(x[1])), float(off)
        a = math.exp(x[0])
        b = (0.5 * a * x[1]) ** 2
        return models.Sopdt(float(g) * (b + a / self.T), a, b, float(x[2])), float(off)

    def x_of(self, m):
        """Parameter vector of a pdtref model (FOPDT or SOPDT form (2)),
        clipped into the bounds."""
        if self.kind == "fopdt":
            x = [math.log(max(m.tau, 1e-300)), m.Td]
        else:
            a = max(m.a, 1e-300)
            x = [math.log(a), 2.0 * math.sqrt(max(m.b, 0.0)) / a, m.Td]
        return np.clip(np.array(x, float), self.lo, self.hi)

    # -- the search
    def polish(self, x0, max_iter=60):
        """Levenberg-Marquardt from x0 within the bounds: forward-difference
        Jacobian, a parameter held at a bound while the gradient pushes it
        out. Returns (cost, x)."""
        lo, hi = self.lo, self.hi
        x = np.clip(np.asarray(x0, float), lo, hi)
        p = x.size
        hstep = 1e-7 * (hi - lo)
        r = self.resid(x)
        f = float(r @ r)
        lam = 1e-3
        for _ in range(max_iter):
            J = np.empty((r.size, p))
            for i in range(p):
                xi = x.copy()
                h = hstep[i] if x[i] + hstep[i] <= hi[i] else -hstep[i]
                xi[i] += h
                J[:, i] = (self.resid(xi) - r) / h
            g = J.T @ r
            H = J.T @ J
            free = ~(((x <= lo) & (g > 0)) | ((x >= hi) & (g < 0)))
            if not free.any():
                break
            Hf = H[np.ix_(free, free)]
            gf = g[free]
            d = np.diag(Hf).copy()
            d[d <= 0] = 1e-30
            improved = False
            while lam < 1e12:
                try:
                    step = -np.linalg.solve(Hf + lam * np.diag(d), gf)
                except np.linalg.LinAlgError:
                    lam *= 10.0
                    continue
                xn = x.copy()
                xn[free] += step
                xn = np.clip(xn, lo, hi)
                rn = self.resid(xn)
                fn = float(rn @ rn)
                if fn < f:
                    improved = True
                    break
                lam *= 4.0
            if not improved:
                break
            dec = f - fn
            moved = np.max(np.abs(xn - x) / (hi - lo))
            x, r, f = xn, rn, fn
            lam = max(lam / 3.0, 1e-12)
            if dec <= 1e-10 * f or moved <= 1e-10:
                break
        return f / self.n, x

    def starts(self, nstarts=9):
        """Dead times spread evenly over [0, T/3]; the shape a time constant
        of T/20, for a SOPDT with 1/zeta cycling through 2.5, 1 and 0.5 (a
        critically damped start alone misses lightly damped plants)."""
        c = self.T / 20.0
        out = []
        for j in range(nstarts):
            td = (j + 0.5) / nstarts * self.T / 3.0
            out.append([math.log(c), td] if self.kind == "fopdt" else
                       [math.log(2.0 / c), (2.5, 1.0, 0.5)[j % 3], td])
        return out

    def cost_of(self, m):
        """The criterion at a pdtref model's shape (its gain re-fitted)."""
        if self.kind == "fopdt":
            return self.cost([math.log(m.tau), m.Td])
        return self.cost([math.log(m.a), 2.0 * math.sqrt(max(m.b, 0.0)) / m.a, m.Td])

    def fit(self, nstarts=9, extra=()):
        """Best of the polished starts (and of any extra start vectors):
        (cost, x)."""
        best = (math.inf, None)
        for x0 in list(self.starts(nstarts)) + list(extra):
            c, x = self.polish(x0)
            if c < best[0]:
                best = (c, x)
        return best

    def grid_fit(self, ntd=64, keep=4):
        """A dense grid over the dead time (ntd values over [0, T/3]) times a
        coarse grid of shapes, each point one evaluation; the best points of
        the keep best dead-time neighbourhoods are then polished. Slower than
        fit() but not misled by records whose cost repeats with a period
        (relay cycles put a local minimum at every period of dead time).
        Returns (cost, x)."""
        lo, hi = self.lo, self.hi
        tds = np.linspace(0.0, hi[-1], ntd)
        if self.kind == "fopdt":
            shapes = [[v] for v in np.linspace(lo[0], hi[0], 8)[1:-1]]
        else:
            shapes = [[la, rz] for la in np.linspace(lo[0], hi[0], 7)[1:-1]
                      for rz in (0.0, 0.5, 1.0, 2.5)]
        best = np.full(ntd, math.inf)
        arg = [None] * ntd
        for i, td in enumerate(tds):
            for sh in shapes:
                x = np.array(sh + [td])
                c = self.cost(x)
                if c < best[i]:
                    best[i], arg[i] = c, x
        order = np.argsort(best)
        chosen = []
        for i in order:
            if all(abs(int(i) - j) > 2 for j in chosen):
                chosen.append(int(i))
            if len(chosen) == keep:
                break
        out = (math.inf, None)
        for i in chosen:
            c, x = self.polish(arg[i])
            if c < out[0]:
                out = (c, x)
        return out
