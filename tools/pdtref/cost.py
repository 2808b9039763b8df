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
- delay_max None means n // 2 (the C PDT_DELAY_AUTO).
"""
import numpy as np

__all__ = [
    "resolve_delay_max", "fft_size", "time_range", "prediction_residuals",
    "simulation_output", "simulation_residuals", "time_cost", "prediction_cost",
    "simulation_cost", "gain_magnitude", "spectra", "bin_weights",
    "frequency_cost", "combined_cost",
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


def time_range(n, delay_max, order):
    """The sample indices k the time costs average over."""
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


def prediction_residuals(u, y, dm, u0=0.0, y0=0.0, delay_max=None):
    """r(k) = y(k) - yhat(k), yhat from measured past outputs (equation
    error), for k = l_u + order .. n-1."""
    ud, yd = _deviation(u, u0), _deviation(y, y0)
    order, l, a, b = _coefs(dm)
    k = time_range(len(yd), delay_max, order)
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


def simulation_residuals(u, y, dm, u0=0.0, y0=0.0, delay_max=None):
    yd = _deviation(y, y0)
    order = int(dm.order)
    k = time_range(len(yd), delay_max, order)
    return yd[k] - simulation_output(u, dm, u0)[k]


def time_cost(r, estimate_offset):
    """Mean square of the residuals, or their variance with an offset fit."""
    r = np.asarray(r, dtype=float)
    return float(np.var(r)) if estimate_offset else float(np.mean(r * r))


def prediction_cost(u, y, dm, u0=0.0, y0=0.0, delay_max=None, estimate_offset=True):
    return time_cost(prediction_residuals(u, y, dm, u0, y0, delay_max), estimate_offset)


def simulation_cost(u, y, dm, u0=0.0, y0=0.0, delay_max=None, estimate_offset=True):
    return time_cost(simulation_residuals(u, y, dm, u0, y0, delay_max), estimate_offset)


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
