"""Reference of the cost functions (paper section 2.2), straight from the
definitions in lib/include/pdt/pdt_cost.h.

Written with whole-array numpy operations where the definition allows it
(prediction residuals, spectra, weights) and a plain loop over the direct-form
difference equation for the simulation, so it shares no structure with the
C code (which streams residuals through a delta-form recursion in blocks).

Conventions:
- Data are arrays u, y of n samples; deviations u - u0, y - y0 are zero
  before sample 0.
- A discrete model is any object with ``delay`` (int), ``order`` (1 or 2),
  ``a`` (2 values: A(q) = 1 + a[0] q + a[1] q^2) and ``b`` (3 values:
  B(q) = (b[0] q + b[1] q^2 + b[2] q^3) q^delay), as pdtref.discrete's
  Discrete.
- A continuous model is any object with ``K``, ``tau`` (FOPDT) or ``k``,
  ``a``, ``b`` (SOPDT, form (2)) attributes, as pdtref.models' Fopdt and
  Sopdt.
- delay_max None means n // 2 (the C PDT_DELAY_HALF).
- whole_record True scores the time costs on the whole record instead of
  k = l_u + order .. n-1: k = order .. n-1 for the prediction (it needs past
  outputs), k = 0 .. n-1 for the simulation (its output from rest is known
  from the first sample).

profile() minimises a cost over the gain multiplier and the output offset by
evaluating the cost functions above at a few gains and fitting the exact
parabola of each half-line of the gain; it does not use the regression
formulas the C code is built on.
"""
from types import SimpleNamespace

import numpy as np

__all__ = [
    "resolve_delay_max", "fft_size", "time_range", "prediction_residuals",
    "simulation_output", "simulation_residuals", "time_cost", "prediction_cost",
    "simulation_cost", "gain_magnitude", "spectra", "bin_weights",
    "frequency_cost", "combined_cost", "scaled", "static_gain", "profile",
    "simulate", "free_response", "profile_state",
]


def resolve_delay_max(n, delay_max=None):
    return n // 2 if delay_max is None else int(delay_max)


def fft_size(n, delay_max=None):
    """N_f: smallest power of two >= max(2 (n - l_u) - 3, n, 16)."""
    lu = resolve_delay_max(n, delay_max)
    if not 0 <= lu < n:
        raise ValueError("delay_max must be below n")
    need = max(2 * (n - lu) - 3, n, 16)
    return 1 << (need - 1).bit_length()


def time_range(n, delay_max, order, whole_record=False, simulation=False):
    """The sample indices k the time costs average over."""
    if whole_record:
        return np.arange(0 if simulation else order, n)
    return np.arange(resolve_delay_max(n, delay_max) + order, n)


def _deviation(x, x0):
    return np.asarray(x, dtype=float) - float(x0)


def _delayed(xd, k, back):
    """x(k - back) for an index array k, zero before the record."""
    idx = k - back
    return np.where(idx >= 0, xd[np.maximum(idx, 0)], 0.0)


def _coefs(dm):
    order = int(dm.order)
    if order not in (1, 2):
        raise ValueError("order must be 1 or 2")
    a = np.zeros(2)
    a[:order] = np.asarray(dm.a, dtype=float)[:order]
    b = np.asarray(dm.b, dtype=float)
    return order, int(dm.delay), a, b


def prediction_residuals(u, y, dm, u0=0.0, y0=0.0, delay_max=None, whole_record=False):
    """r(k) = y(k) - yhat(k), yhat from measured past outputs (equation
    error), for k = l_u + order .. n-1 (order .. n-1 with whole_record)."""
    ud, yd = _deviation(u, u0), _deviation(y, y0)
    order, l, a, b = _coefs(dm)
    k = time_range(len(yd), delay_max, order, whole_record)
    yhat = -a[0] * yd[k - 1]
    if order == 2:
        yhat = yhat - a[1] * yd[k - 2]
    for j in range(3):
        yhat = yhat + b[j] * _delayed(ud, k, l + 1 + j)
    return yd[k] - yhat


def simulation_output(u, dm, u0=0.0):
    """The model's output from rest over the whole record (output error)."""
    ud = _deviation(u, u0)
    order, l, a, b = _coefs(dm)
    n = len(ud)
    upad = np.concatenate([np.zeros(l + 3), ud])  # upad[i + l + 3] = u(i)
    ys = [0.0, 0.0]  # ysim(k-1), ysim(k-2)
    out = np.empty(n)
    for k in range(n):
        v = (-a[0] * ys[0] - a[1] * ys[1]
             + b[0] * upad[k + 2] + b[1] * upad[k + 1] + b[2] * upad[k])
        out[k] = v
        ys[1] = ys[0]
        ys[0] = v
    return out


def simulation_residuals(u, y, dm, u0=0.0, y0=0.0, delay_max=None, whole_record=False):
    yd = _deviation(y, y0)
    order = int(dm.order)
    k = time_range(len(yd), delay_max, order, whole_record, simulation=True)
    return yd[k] - simulation_output(u, dm, u0)[k]


def time_cost(r, estimate_offset):
    """Mean square of the residuals, or their variance with an offset fit."""
    r = np.asarray(r, dtype=float)
    return float(np.var(r)) if estimate_offset else float(np.mean(r * r))


def prediction_cost(u, y, dm, u0=0.0, y0=0.0, delay_max=None, estimate_offset=True,
                    whole_record=False):
    return time_cost(prediction_residuals(u, y, dm, u0, y0, delay_max, whole_record),
                     estimate_offset)


def simulation_cost(u, y, dm, u0=0.0, y0=0.0, delay_max=None, estimate_offset=True,
                    whole_record=False):
    return time_cost(simulation_residuals(u, y, dm, u0, y0, delay_max, whole_record),
                     estimate_offset)


def gain_magnitude(model, w):
    """|G(j w)| of the rational part, evaluated as a complex ratio."""
    s = 1j * np.asarray(w, dtype=float)
    if hasattr(model, "tau"):
        return np.abs(model.K / (model.tau * s + 1.0))
    return np.abs(model.k / (s * s + model.a * s + model.b))


def spectra(u, y, u0, y0, nf):
    """|U(k)|, |Y(k)| for k = 0 .. nf/2 of the zero-padded deviations."""
    return (np.abs(np.fft.rfft(_deviation(u, u0), nf)),
            np.abs(np.fft.rfft(_deviation(y, y0), nf)))


def bin_weights(nf, Ts, weight="uniform", f_lo=0.0, f_hi=0.0, weights=None):
    """W(k) for k = 0 .. nf/2 (W(0) is never used)."""
    k = np.arange(nf // 2 + 1)
    if weight == "uniform":
        return np.ones(len(k))
    if weight == "band":
        f = k / (nf * Ts)
        return ((f >= f_lo) & (f <= f_hi)).astype(float)
    if weight == "custom":
        w = np.asarray(weights, dtype=float)
        if w.shape != k.shape:
            raise ValueError("custom weights need nf/2 + 1 values")
        return w
    raise ValueError(weight)


def frequency_cost(u, y, model, Ts, u0=0.0, y0=0.0, delay_max=None,
                   weight="uniform", f_lo=0.0, f_hi=0.0, weights=None):
    """Cf = sum_{k=1}^{nf/2} W m_k (|Y| - |G| |U|)^2 / (nf n)."""
    n = len(u)
    nf = fft_size(n, delay_max)
    umag, ymag = spectra(u, y, u0, y0, nf)
    W = bin_weights(nf, Ts, weight, f_lo, f_hi, weights)
    k = np.arange(1, nf // 2 + 1)
    mirror = np.where(k < nf // 2, 2.0, 1.0)
    g = gain_magnitude(model, 2.0 * np.pi * k / (nf * Ts))
    e = ymag[k] - g * umag[k]
    return float(np.sum(W[k] * mirror * e * e) / (nf * n))


def combined_cost(time_value, freq_value, phi_t=1.0, phi_f=1.0):
    """phi_t Ct + phi_f Cf, a zero weight dropping its term."""
    total = 0.0
    if phi_t > 0:
        total += phi_t * time_value
    if phi_f > 0:
        total += phi_f * freq_value
    return total


def scaled(model, gain):
    """A copy of a discrete model (B(q) times gain) or of a continuous one
    (its gain times gain), as a plain attribute object."""
    if hasattr(model, "order"):
        return SimpleNamespace(delay=int(model.delay), order=int(model.order),
                               a=list(model.a), b=[gain * v for v in model.b],
                               d=list(getattr(model, "d", [0.0, 0.0])))
    if hasattr(model, "tau"):
        return SimpleNamespace(K=gain * model.K, tau=model.tau, Td=model.Td)
    return SimpleNamespace(k=gain * model.k, a=model.a, b=model.b, Td=model.Td)


def static_gain(dm):
    """A(1) of a discrete model: from its delta form d[] when it has one
    (exact for poles near 1), else 1 + a[0] + a[1]."""
    order = int(dm.order)
    if hasattr(dm, "d"):
        return float(dm.d[order - 1])
    return 1.0 + sum(float(v) for v in list(dm.a)[:order])


_EPS = 2.220446049250313e-16


def _quad_argmin(q, lo, hi):
    """Minimiser of q[0] + q[1] x + q[2] x^2 over [lo, hi] (ends may be
    infinite)."""
    if q[2] > 0.0:
        return min(max(-q[1] / (2.0 * q[2]), lo), hi)
    ends = [x for x in (lo, hi) if np.isfinite(x)]
    if len(ends) < 2 and q[1] != 0.0:
        raise ValueError("cost unbounded below in the gain")
    if not ends:
        return 0.0
    return min(ends, key=lambda x: q[0] + q[1] * x)


def profile(u, y, shape, dm, Ts, kind, u0=0.0, y0=0.0, delay_max=None,
            time_kind="simulation", estimate_offset=True, whole_record=False,
            phi_t=1.0, phi_f=1.0, gain_min=0.0, gain_max=0.0,
            weight="uniform", f_lo=0.0, f_hi=0.0, weights=None):
    """The cost `kind` ("prediction", "simulation", "frequency", "combined")
    minimised over the multiplier K of the shape's gain and, with
    estimate_offset, over a constant output offset.

    shape is the continuous model (for the frequency part) and dm its
    discrete model (for the time part), both at gain multiplier 1.
    gain_min = gain_max = 0 means unbounded.

    Method: the time cost of the model scaled by K is an exact quadratic in
    K, and the frequency cost one in |K|, so each is sampled at three gains
    (multiples of the data's own gain unit, the ratio of the ranges of y and
    u, so that a record whose gain is 1e20 is sampled where its parabola
    shows) and its parabola solved from the samples; the total is then a quadratic
    on each half-line of K, minimised there over the bounds, and the better
    half-line wins (the positive one on an exact tie). The result's costs
    are evaluated again directly at the chosen gain.

    Returns a dict: cost, gain, offset, ct, cf (as pdt_cost_profile_t),
    plus sign_free (the cost does not depend on the sign of K and -K is
    also allowed: the sign is arbitrary) and margin (relative gap between
    the two half-line minima; 0 if only one half-line is allowed or one of
    the minima is at 0, the point both share).
    """
    if kind in ("prediction", "simulation"):
        wt, wf, tk = 1.0, 0.0, kind
    elif kind == "frequency":
        wt, wf, tk = 0.0, 1.0, None
    elif kind == "combined":
        if time_kind not in ("prediction", "simulation"):
            raise ValueError(time_kind)
        wt, wf, tk = float(phi_t), float(phi_f), time_kind
    else:
        raise ValueError(kind)
    if gain_min > gain_max:
        raise ValueError("gain_min > gain_max")
    if gain_min == 0.0 and gain_max == 0.0:
        lo, hi = -np.inf, np.inf
    else:
        lo, hi = float(gain_min), float(gain_max)
    tfun = prediction_cost if tk == "prediction" else simulation_cost
    rfun = prediction_residuals if tk == "prediction" else simulation_residuals

    def tcost(g):
        if wt <= 0.0:
            return 0.0
        return tfun(u, y, scaled(dm, g), u0, y0, delay_max, estimate_offset, whole_record)

    def fcost(g):
        if wf <= 0.0:
            return 0.0
        return frequency_cost(u, y, scaled(shape, g), Ts, u0, y0, delay_max,
                              weight, f_lo, f_hi, weights)

    def total(g):
        return wt * tcost(g) + wf * fcost(abs(g))

    uspan = float(np.max(np.abs(np.asarray(u, dtype=float) - u0)))
    yspan = float(np.max(np.abs(np.asarray(y, dtype=float) - y0)))
    gs = yspan / uspan if uspan > 0.0 and yspan > 0.0 else 1.0
    # The quadratics below are in t = K / gs.
    tm, t0, tp = tcost(-gs), tcost(0.0), tcost(gs)
    ct_q = (t0, 0.5 * (tp - tm), 0.5 * (tp + tm) - t0)
    f0, f1, f2 = fcost(0.0), fcost(gs), fcost(2.0 * gs)
    cf_2 = 0.5 * (f2 - 2.0 * f1 + f0)
    cf_q = (f0, f1 - f0 - cf_2, cf_2)
    pos = [wt * ct_q[i] + wf * cf_q[i] for i in range(3)]
    neg = [wt * ct_q[0] + wf * cf_q[0], wt * ct_q[1] - wf * cf_q[1],
           wt * ct_q[2] + wf * cf_q[2]]

    def argmin(q, a, b):
        # back in gains, clamped again: a bound divided and multiplied by gs
        # may have moved by a rounding
        return min(max(gs * _quad_argmin(q, a / gs, b / gs), a), b)

    cands = []
    if max(lo, 0.0) <= hi:
        cands.append(argmin(pos, max(lo, 0.0), hi))
    if lo <= min(hi, 0.0):
        cands.append(argmin(neg, lo, min(hi, 0.0)))
    values = [total(g) for g in cands]
    best = 0
    if len(cands) == 2 and values[1] < values[0]:
        best = 1
    gain = float(cands[best])
    margin = 0.0
    # Zero belongs to both half-lines: a candidate there never competes.
    if len(cands) == 2 and cands[0] != 0.0 and cands[1] != 0.0:
        margin = abs(values[0] - values[1]) / max(abs(values[0]), abs(values[1]), 1e-300)

    offset = 0.0
    ct = tcost(gain)
    if wt > 0.0 and estimate_offset:
        mean_r = float(np.mean(rfun(u, y, scaled(dm, gain), u0, y0, delay_max, whole_record)))
        if tk == "simulation":
            offset = mean_r
        else:
            a1 = static_gain(dm)
            offset = mean_r / a1 if a1 > _EPS else 0.0
    cf = fcost(abs(gain))
    if kind == "combined":
        cost = combined_cost(ct, cf, wt, wf)
    else:
        cost = cf if kind == "frequency" else ct
    return dict(cost=float(cost), gain=gain, offset=float(offset), ct=float(ct),
                cf=float(cf), sign_free=(wt <= 0.0 and lo <= -gain <= hi), margin=margin)


def simulate(u, dm, u0=0.0, y0=0.0):
    """y0 + the response of dm, from rest, to u - u0 (engineering units)."""
    return float(y0) + simulation_output(u, dm, u0)


def free_response(dm, n):
    """The free response of dm's A(q) from sample 0, as columns: order 1
    the sequence with y(0) = 1; order 2 those with (y(0), y(0) - y(-1)) =
    (1, 0) and (0, 1). Direct-form recursion y(k) = -a0 y(k-1) - a1 y(k-2)."""
    order, _, a, _ = _coefs(dm)
    starts = [(1.0, 1.0)] if order == 1 else [(1.0, 1.0), (0.0, -1.0)]
    cols = []
    for y0, ym1 in starts:
        f = np.empty(n)
        prev, prev2 = y0, ym1
        f[0] = y0
        for k in range(1, n):
            v = -a[0] * prev - (a[1] * prev2 if order == 2 else 0.0)
            f[k] = v
            prev2, prev = prev, v
        cols.append(f)
    return cols


def profile_state(u, y, dm, Ts, u0=0.0, y0=0.0, delay_max=None, estimate_offset=True,
                  estimate_state=True, drift=False, whole_record=True):
    """The simulation cost of the unit-gain discrete shape dm minimised over
    its gain, the offset (estimate_offset), the free response of its state
    at the first sample (estimate_state) and a drift d (k - (n-1)/2) / n
    (drift), by numpy's least squares on the explicit columns.

    Returns a dict: cost (mean square residual over the scored samples),
    gain, offset, x0 (free response at sample 0), x1 (a second-order
    model's free change over the first sample, per second), drift (output
    units per second)."""
    yd = _deviation(y, y0)
    n = len(yd)
    k = time_range(n, delay_max, int(dm.order), whole_record, simulation=True)
    cols, names = [simulation_output(u, dm, u0)], ["gain"]
    if estimate_offset:
        cols.append(np.ones(n))
        names.append("offset")
    if drift:
        cols.append((np.arange(n) - 0.5 * (n - 1)) / n)
        names.append("drift")
    if estimate_state:
        for i, f in enumerate(free_response(dm, n)):
            cols.append(f)
            names.append("x%d" % i)
    A = np.column_stack(cols)[k]
    coef = np.linalg.lstsq(A, yd[k], rcond=None)[0]
    r = yd[k] - A @ coef
    got = dict(zip(names, coef))
    return dict(cost=float(np.mean(r * r)), gain=float(got["gain"]),
                offset=float(got.get("offset", 0.0)), x0=float(got.get("x0", 0.0)),
                x1=float(got.get("x1", 0.0)) / Ts,
                drift=float(got.get("drift", 0.0)) / (n * Ts))


def profile_joint(records, estimate_offset=True, estimate_state=False, drift=False):
    """Several records of one process: the simulation cost of a shape
    minimised over one gain shared by all records and each record's own
    offset (estimate_offset), free response of its state at the first
    sample (estimate_state) and drift (drift), by numpy's least squares on
    the stacked explicit columns (the own columns block-diagonal), every
    record scored whole.

    records: a list of dicts with u, y, dm (the unit-gain shape discretised
    at the record's period), Ts, u0, y0. Returns a dict: cost (mean square
    residual over all samples), gain, offsets (each record's, added to its
    y0)."""
    blocks, ys, names = [], [], []
    for r, rec in enumerate(records):
        yd = _deviation(rec["y"], rec["y0"])
        n = len(yd)
        cols = []
        if estimate_offset:
            cols.append((np.ones(n), ("offset", r)))
        if drift:
            cols.append(((np.arange(n) - 0.5 * (n - 1)) / n, ("drift", r)))
        if estimate_state:
            for i, f in enumerate(free_response(rec["dm"], n)):
                cols.append((f, ("x%d" % i, r)))
        blocks.append((simulation_output(rec["u"], rec["dm"], rec["u0"]), cols))
        ys.append(yd)
    total = sum(len(y) for y in ys)
    own = [name for _, cols in blocks for _, name in cols]
    A = np.zeros((total, 1 + len(own)))
    at = 0
    for s, cols in blocks:
        n = len(s)
        A[at:at + n, 0] = s
        for col, name in cols:
            A[at:at + n, 1 + own.index(name)] = col
        at += n
    y = np.concatenate(ys)
    coef = np.linalg.lstsq(A, y, rcond=None)[0]
    res = y - A @ coef
    offsets = [float(coef[1 + own.index(("offset", r))]) if estimate_offset else 0.0
               for r in range(len(records))]
    return dict(cost=float(np.mean(res * res)), gain=float(coef[0]), offsets=offsets)
