"""The joint output-error optimum of several records of one process, by
scipy, independent of pdtfit's engine (docs/several-records.md).

Each record r has its own input operating point u0_r, sampling period
Ts_r, output offset and, with initial "estimate", the free response of
the model's state at its first sample; the dynamics are shared. For given
dynamics (FOPDT log tau, Td; SOPDT log a, 1/zeta, Td) the simulated
output is linear in the shared gain and in each record's own columns: the
stacked least squares (a block-diagonal design for the own columns) gives
them, and scipy.optimize.least_squares polishes the dynamics from the six
best points of a grid and from any starts given (variable projection, as
tools/bench/real_data.py's reference for one record). Every record is
scored whole; the cost is the mean square residual over all samples.
"""
from __future__ import annotations

import math

import numpy as np
import scipy.optimize as so

from pdtbench import benchlib as bl
from pdtbench.benchlib import models
from pdtsupport import plant, records


# The test cases of several records (python/tests/test_several.py and
# tools/bench/several_records.py): name: kind, (numerator, denominator,
# dead time) of the plant, each record's (n, Ts, u0, y0, amplitude), noise.
PLANTS = {
    "fopdt_slow": ("fopdt", ([1.8], [30.0, 1.0], 12.0),
                   [(400, 1.0, 40.0, 300.0, 5.0), (300, 2.0, 55.0, 320.0, 8.0)], 0.05),
    "fopdt_fast": ("fopdt", ([-0.7], [8.0, 1.0], 3.0),
                   [(300, 0.5, 10.0, 3.0, 2.0), (500, 0.25, 0.0, -4.0, 3.0)], 0.01),
    "sopdt_lag": ("sopdt", ([1.5], list(np.polymul([20.0, 1.0], [6.0, 1.0])), 5.0),
                  [(500, 1.0, 0.0, 10.0, 4.0), (400, 0.5, 20.0, 40.0, 6.0)], 0.02),
}


def make_record(num, den, Td, n, Ts, u0, y0, amp, noise, seed):
    """(u, y, fs): steps around u0 after a rest, the plant's response
    behind a zero-order hold around y0, white noise of std `noise`."""
    u = records.multistep_input(n, u0, amp, 15, 45, 10, seed)
    y = y0 + plant.simulate(num, den, Td, u - u0, Ts)
    return u, y + records.noise(n, noise, seed), 1.0 / Ts


def plant_records(name, seed):
    """The records of case `name` at noise seed `seed`: (kind, [(u, y, fs)])."""
    kind, (num, den, Td), recs, noise = PLANTS[name]
    return kind, [make_record(num, den, Td, *rec, noise, seed + 10 * i)
                  for i, rec in enumerate(recs)]


def model_of(r):
    """The pdtref model of a result (attributes or a dict of the JSON)."""
    g = r.get if isinstance(r, dict) else (lambda k: getattr(r, k))
    if g("model") == "fopdt":
        return models.Fopdt(g("K"), g("tau"), g("Td"))
    return models.Sopdt(g("K") * g("b"), g("a"), g("b"), g("Td"))


def compare(kind, records, mine, initial="rest"):
    """pdtfit's model against the reference's joint optimum: ((worst
    relative difference, its parameter), each record's offset, the cost
    ratio of pdtfit's model over the reference's)."""
    ref = JointReference(kind, [(u, y, 1.0 / fs) for u, y, fs in records], initial)
    m_ref, offsets, c_ref = ref.fit(starts=[mine])
    return worst_difference(mine, m_ref), offsets, ref.cost_of(mine) / c_ref


def free_columns(m, Ts, n):
    """The free response of the model's state from the first sample, one
    column per state, from the lag's poles."""
    t = np.arange(n) * Ts
    if isinstance(m, models.Fopdt):
        return [np.exp(-t / m.tau)]
    disc = m.a * m.a - 4.0 * m.b
    if disc > 1e-12 * m.a * m.a:
        r = math.sqrt(disc)
        return [np.exp((-m.a + r) / 2 * t), np.exp((-m.a - r) / 2 * t)]
    if disc < -1e-12 * m.a * m.a:
        w = math.sqrt(-disc) / 2
        e = np.exp(-m.a / 2 * t)
        return [e * np.cos(w * t), e * np.sin(w * t)]
    e = np.exp(-m.a / 2 * t)
    return [e, t * e]


class JointReference:
    """records: a list of (u, y, Ts) (u0 each record's u[0]); kind "fopdt"
    or "sopdt"; initial "rest" or "estimate"."""

    def __init__(self, kind, records, initial="rest"):
        self.kind, self.initial = kind, initial
        self.recs = [(np.asarray(u, float), np.asarray(y, float), float(Ts))
                     for u, y, Ts in records]
        self.T = min(len(u) * Ts for u, _, Ts in self.recs)
        Ts_min = min(Ts for _, _, Ts in self.recs)
        if kind == "fopdt":
            self.lo = np.array([math.log(Ts_min / 4), 0.0])
            self.hi = np.array([math.log(2 * self.T), self.T / 3])
        else:
            self.lo = np.array([math.log(1.0 / (2 * self.T)), 0.0, 0.0])
            self.hi = np.array([math.log(8.0 / Ts_min), 5.0, self.T / 3])

    def unit_model(self, x):
        if self.kind == "fopdt":
            return models.Fopdt(1.0, math.exp(x[0]), x[1])
        a = math.exp(x[0])
        b = (a * x[1] / 2.0) ** 2
        return models.Sopdt(b + a / self.T, a, b, x[2])

    def design(self, m):
        """The stacked design (shared gain first, then each record's own
        columns) and the stacked output."""
        blocks, ys = [], []
        for u, y, Ts in self.recs:
            resp = bl.simulate(m, Ts, u - u[0])
            own = [np.ones(len(u))]
            if self.initial == "estimate":
                own += free_columns(m, Ts, len(u))
            blocks.append((resp, own))
            ys.append(y)
        width = 1 + sum(len(own) for _, own in blocks)
        A = np.zeros((sum(len(y) for y in ys), width))
        row, col = 0, 1
        for resp, own in blocks:
            n = len(resp)
            A[row:row + n, 0] = resp
            for c in own:
                A[row:row + n, col] = c
                col += 1
            row += n
        return A, np.concatenate(ys)

    def resid(self, x):
        A, y = self.design(self.unit_model(x))
        coef = np.linalg.lstsq(A, y, rcond=None)[0]
        return y - A @ coef, coef

    def grid(self):
        td = np.linspace(0.0, self.T / 3, 25)
        if self.kind == "fopdt":
            return [np.array([lt, d]) for lt in np.linspace(self.lo[0], self.hi[0], 16)
                    for d in td]
        return [np.array([la, iz, d]) for la in np.linspace(self.lo[0], self.hi[0], 12)
                for iz in (0.3, 0.8, 1.4, 2.0, 3.0, 4.5) for d in td]

    def start_of(self, m):
        if isinstance(m, models.Fopdt):
            return np.array([math.log(max(m.tau, 1e-9)), m.Td])
        iz = 2.0 * math.sqrt(max(m.b, 0.0)) / m.a if m.a > 0 else 0.0
        return np.array([math.log(max(m.a, 1e-12)), iz, m.Td])

    def fit(self, starts=()):
        """(model with its gain, [each record's offset], cost)."""
        scored = sorted((float(np.mean(self.resid(x)[0] ** 2)), i, x)
                        for i, x in enumerate(self.grid()))
        best = None
        for x0 in [x for _, _, x in scored[:6]] + [self.start_of(s) for s in starts]:
            x0 = np.clip(x0, self.lo + 1e-9, self.hi - 1e-9)
            r = so.least_squares(lambda x: self.resid(x)[0], x0, bounds=(self.lo, self.hi),
                                 method="trf", x_scale="jac", xtol=1e-12, ftol=1e-12,
                                 gtol=1e-12, max_nfev=600)
            c = float(np.mean(r.fun ** 2))
            if best is None or c < best[0]:
                best = (c, r.x)
        c, x = best
        m = self.unit_model(x)
        _, coef = self.resid(x)
        g = coef[0]
        per = 1 + (len(free_columns(m, 1.0, 1)) if self.initial == "estimate" else 0)
        offsets = [float(coef[1 + r * per]) for r in range(len(self.recs))]
        if self.kind == "fopdt":
            return models.Fopdt(g, m.tau, m.Td), offsets, c
        return models.Sopdt(g * m.k, m.a, m.b, m.Td), offsets, c

    def cost_of(self, m):
        """The mean square residual of m's dynamics and gain, each
        record's own columns fitted."""
        unit = m._replace(K=1.0) if isinstance(m, models.Fopdt) else m._replace(k=1.0)
        g = m.K if isinstance(m, models.Fopdt) else m.k
        A, y = self.design(unit)
        coef = np.linalg.lstsq(A[:, 1:], y - g * A[:, 0], rcond=None)[0]
        r = y - g * A[:, 0] - A[:, 1:] @ coef
        return float(np.mean(r * r))


def printed(m):
    """{K, tau, Td} of a FOPDT; {K, tau1, tau2, Td} of an overdamped SOPDT,
    {K, wn, zeta, Td} of an underdamped one."""
    if isinstance(m, models.Fopdt):
        return {"K": m.K, "tau": m.tau, "Td": m.Td}
    out = {"K": m.k / m.b, "Td": m.Td}
    disc = m.a * m.a - 4.0 * m.b
    if disc >= 0:
        r = math.sqrt(disc)
        out.update(tau1=2.0 / (m.a - r), tau2=2.0 / (m.a + r))
    else:
        out.update(wn=math.sqrt(m.b), zeta=m.a / (2.0 * math.sqrt(m.b)))
    return out


def worst_difference(m_pdt, m_ref):
    """The largest relative difference of the printed parameters (a dead
    time relative to the largest time constant, so that Td = 0 is no
    division by 0) and its name."""
    a, b = printed(m_pdt), printed(m_ref)
    if set(a) != set(b):
        return math.inf, "structure"
    scale = max(v for k, v in b.items() if k in ("tau", "tau1", "tau2")) if "wn" not in b \
        else 1.0 / b["wn"]
    worst, name = 0.0, ""
    for k in b:
        den = scale if k == "Td" else abs(b[k])
        d = abs(a[k] - b[k]) / den
        if d > worst:
            worst, name = d, k
    return worst, name
