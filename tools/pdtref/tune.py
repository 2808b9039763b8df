"""PI/PID tuning rules and the robustness of the loops they make.

The rules are written from the published formulas (docs/tuning.md cites
them). The robustness figures take an independent route from the C library:
the loop L = C G (dead time included) is evaluated on a dense log-spaced grid
(200000 points by default) with numpy's complex arithmetic; Ms is the grid's
largest |1/(1 + L)| polished on a fine sub-grid around each local maximum,
crossovers come from sign changes refined by a few secant steps, and
stability from np.unwrap of arg(1 + L) (Nyquist criterion).

Gain sets are dicts {"Kc", "tauI", "tauD", "Tf"} in the ideal (parallel) form
Kc (1 + 1/(tauI s) + tauD s/(Tf s + 1)) unless said otherwise.

Statuses are the C codes, read from pdt_status.h: OK, ARG, NO_FORM,
POOR_FIT, UNSTABLE, MS_LIMIT.
"""
from __future__ import annotations

import math

import numpy as np

from pdtsupport.status import STATUS

from .models import Fopdt, Sopdt

OK, ARG, NO_FORM, POOR_FIT, UNSTABLE, MS_LIMIT = (STATUS[name] for name in (
    "OK", "ARG", "NO_FORM", "POOR_FIT", "UNSTABLE", "MS_LIMIT"))
SIMC, IMC, AMIGO, ZN = 0, 1, 2, 3
PI, PID = 0, 1


class TuneError(Exception):
    def __init__(self, status, why=""):
        super().__init__(f"status {status}: {why}")
        self.status = status


def gains(Kc, tauI, tauD=0.0, Tf=0.0):
    return {"Kc": float(Kc), "tauI": float(tauI), "tauD": float(tauD), "Tf": float(Tf)}


# ---- forms -------------------------------------------------------------------

def series_to_ideal(g):
    f = 1.0 + g["tauD"] / g["tauI"]
    return gains(g["Kc"] * f, g["tauI"] * f, g["tauD"] / f, g["Tf"])


def ideal_to_series(g):
    """Series form by the roots of the ideal PID's numerator
    tauI tauD s^2 + tauI s + 1 = (t1 s + 1)(t2 s + 1); None if complex."""
    if g["tauD"] == 0.0:
        return dict(g)
    disc = 1.0 - 4.0 * g["tauD"] / g["tauI"]
    if disc < -1e-12:
        return None
    if disc <= 0.0:  # a double zero (Ziegler-Nichols PID)
        t = [g["tauI"] / 2, g["tauI"] / 2]
    else:
        roots = np.roots([g["tauI"] * g["tauD"], g["tauI"], 1.0])
        t = np.sort(-1.0 / roots.real)[::-1]
    return gains(g["Kc"] * t[0] / g["tauI"], t[0], t[1], g["Tf"])


# ---- what a rule sees --------------------------------------------------------

def view(m):
    """dict: shape ('first', 'real', 'complex', 'integ') and the numbers the
    rules use (half rule for the FOPDT approximations)."""
    if isinstance(m, Fopdt):
        return {"shape": "first", "K": m.K, "tau": m.tau, "theta": m.Td, "Td": m.Td}
    k, a, b, Td = m
    if b == 0.0:
        T = 1.0 / a
        return {"shape": "integ", "K": k / a, "T2": T, "theta": Td + T / 2, "Td": Td,
                "a": a, "b": b, "k": k}
    p = np.roots([1.0, a, b])
    base = {"K": k / b, "Td": Td, "a": a, "b": b, "k": k}
    if a * a < 4.0 * b:
        # half rule on the pair split equally by its real part a / (2 b)
        re = a / (2.0 * b)
        return {**base, "shape": "complex", "tau": 1.5 * re, "theta": Td + re / 2}
    T = np.sort(-1.0 / p.real)[::-1]
    T1, T2 = float(T[0]), float(T[1])
    return {**base, "shape": "real", "T1": T1, "T2": T2, "tau": T1 + T2 / 2,
            "theta": Td + T2 / 2}


def simc(v, form, tau_c=0.0):
    """(gains, series_rule, knob). Skogestad (2003)."""
    pid = form == PID
    theta = v["Td"] if (pid and v["shape"] != "first") else v["theta"]
    tc = tau_c if tau_c > 0 else theta
    if tc + theta <= 0:
        raise TuneError(ARG, "SIMC needs tau_c + theta > 0")
    if v["shape"] == "complex" and pid:
        # 2 zeta tau0 / (K (tc + theta)), tauI = 2 zeta tau0, tauD = tau0 / (2 zeta)
        K, a, b = v["K"], v["a"], v["b"]
        tau0 = 1.0 / math.sqrt(b)
        zeta = a * tau0 / 2.0
        return gains(2 * zeta * tau0 / (K * (tc + theta)), 2 * zeta * tau0,
                     tau0 / (2 * zeta)), False, tc
    if v["shape"] == "integ":
        return gains(1.0 / (v["K"] * (tc + theta)), 4 * (tc + theta),
                     v["T2"] if pid else 0.0), True, tc
    if v["shape"] == "real" and pid:
        T1 = v["T1"]
        return gains(T1 / (v["K"] * (tc + theta)), min(T1, 4 * (tc + theta)), v["T2"]), True, tc
    tau = v["tau"]
    return gains(tau / (v["K"] * (tc + theta)), min(tau, 4 * (tc + theta))), True, tc


def imc(v, form, lam=0.0):
    """IMC / lambda tuning (Rivera, Morari and Skogestad 1986)."""
    pid = form == PID
    shape = v["shape"]
    if lam <= 0:
        if shape == "integ":
            lam = 3 * v["theta"]
        elif pid and shape != "first":
            lam = max(v["a"] / v["b"], 3 * v["Td"])
        else:
            lam = max(v["tau"], 3 * v["theta"])
    if shape == "integ":
        th = v["Td"] if pid else v["theta"]
        g = gains((2 * lam + th) / (v["K"] * (lam + th) ** 2), 2 * lam + th,
                  v["T2"] if pid else 0.0)
        return g, pid, lam
    if not pid:
        return gains(v["tau"] / (v["K"] * (lam + v["theta"])), v["tau"]), False, lam
    if shape == "first":
        tau, th = v["tau"], v["theta"]
        return gains((2 * tau + th) / (v["K"] * (2 * lam + th)), tau + th / 2,
                     tau * th / (2 * tau + th)), False, lam
    # (T1 + T2) / (K (lam + Td)), T1 + T2, T1 T2 / (T1 + T2), from form (2)
    Tsum = v["a"] / v["b"]
    Tprod = 1.0 / v["b"]
    return gains(Tsum / (v["K"] * (lam + v["Td"])), Tsum, Tprod / Tsum), False, lam


def amigo(v, form):
    """AMIGO, Astrom and Hagglund (2006), ch. 7."""
    L = v["theta"]
    if L <= 0:
        raise TuneError(ARG, "AMIGO needs dead time")
    if v["shape"] == "integ":
        Kv = v["K"]
        if form == PID:
            return gains(0.45 / (Kv * L), 8 * L, 0.5 * L), False, 0.0
        return gains(0.35 / (Kv * L), 13.4 * L), False, 0.0
    K, T = v["K"], v["tau"]
    if form == PID:
        return gains((0.2 + 0.45 * T / L) / K, (0.4 * L + 0.8 * T) / (L + 0.1 * T) * L,
                     0.5 * L * T / (0.3 * L + T)), False, 0.0
    return gains((0.15 + (0.35 - L * T / (L + T) ** 2) * T / L) / K,
                 0.35 * L + 13 * L * T * T / (T * T + 12 * L * T + 7 * L * L)), False, 0.0


def ziegler_nichols(Ku, Pu, form):
    if form == PID:
        return gains(0.6 * Ku, Pu / 2, Pu / 8)
    return gains(0.45 * Ku, Pu / 1.2)


def ultimate(m):
    """(Ku, Pu): the model's phase crossover, solved by Newton's method on
    the phase (with the sign of the gain taken out)."""
    Td = m.Td
    if Td <= 0:
        raise TuneError(NO_FORM, "no dead time, no phase crossover")
    if isinstance(m, Fopdt):
        def ph(w):
            return -math.atan(w * m.tau) - w * Td

        def dph(w):
            return -m.tau / (1 + (w * m.tau) ** 2) - Td
    else:
        k, a, b, _ = m

        def ph(w):
            return -math.atan2(a * w, b - w * w) - w * Td

        def dph(w, h=1e-7):
            return (ph(w * (1 + h)) - ph(w * (1 - h))) / (2 * h * w)
    w = 0.5 * math.pi / Td
    lo, hi = 0.0, math.pi / Td
    for _ in range(200):
        f = ph(w) + math.pi
        if f > 0:
            lo = w
        else:
            hi = w
        step = -f / dph(w)
        w_new = w + step
        if not (lo < w_new < hi):
            w_new = 0.5 * (lo + hi)
        if abs(w_new - w) <= 1e-15 * w:
            w = w_new
            break
        w = w_new
    G = freq(m, np.array([w]))[0]
    sign = 1.0 if (m.K if isinstance(m, Fopdt) else m.k) > 0 else -1.0
    return sign / abs(G), 2 * math.pi / w


# ---- the loop ----------------------------------------------------------------

def freq(m, w):
    s = 1j * np.asarray(w, dtype=float)
    if isinstance(m, Fopdt):
        G = m.K / (m.tau * s + 1)
    else:
        G = m.k / (s * s + m.a * s + m.b)
    return G * np.exp(-s * m.Td)


def ctrl(g, w):
    s = 1j * np.asarray(w, dtype=float)
    return g["Kc"] * (1 + 1 / (g["tauI"] * s) + g["tauD"] * s / (g["Tf"] * s + 1))


def loop(m, g, w):
    return ctrl(g, w) * freq(m, w)


def _scales(m, g):
    t = [g["tauI"], g["tauD"], g["Tf"], m.Td]
    if isinstance(m, Fopdt):
        t.append(m.tau)
    else:
        t.append(1.0 / m.a)
        if m.b > 0:
            t += [m.a / m.b, 1.0 / math.sqrt(m.b)]
    t = [x for x in t if x > 0]
    return min(t), max(t)


def robustness(m, g, npts=200000):
    """dict Ms, w_ms, gm (inf if none), w_pc, pm_deg, w_gc, ms2 (the next
    highest local maximum of |S|); raises
    TuneError(UNSTABLE) for an unstable loop."""
    dc = m.K if isinstance(m, Fopdt) else (m.k / m.b if m.b > 0 else m.k / m.a)
    if dc * g["Kc"] < 0:
        raise TuneError(UNSTABLE, "positive feedback")
    # An unfiltered derivative on a FOPDT keeps |L| at r for ever.
    r = 0.0
    if isinstance(m, Fopdt) and g["tauD"] > 0 and g["Tf"] == 0:
        r = abs(g["Kc"] * m.K * g["tauD"] / m.tau)
        if r >= 1:
            raise TuneError(UNSTABLE, "|L(j inf)| >= 1")
    tmin, tmax = _scales(m, g)
    lo, hi = 1e-4 / tmax, 1e4 / tmin
    # widen until the ends are clearly low- and high-frequency
    while abs(loop(m, g, [lo])[0]) < 100:
        lo /= 10
    while abs(loop(m, g, [hi])[0]) > max(0.05, (1 + r) / 2):
        hi *= 10
        if hi > 1e12 / tmin:
            raise ValueError("loop gain does not fall off")
    w = np.geomspace(lo, hi, npts)
    L = loop(m, g, w)
    F = 1 + L

    integ = not isinstance(m, Fopdt) and m.b == 0
    n0 = 2 if integ else 1
    ph = np.unwrap(np.angle(F[::-1]))
    ph -= 2 * math.pi * round(ph[0] / (2 * math.pi))  # |L| << 1 at the top
    if abs(ph[-1] + n0 * math.pi / 2) > math.pi / 2:
        raise TuneError(UNSTABLE, "Nyquist")

    S = 1 / np.abs(F)
    idx = np.flatnonzero((S[1:-1] >= S[:-2]) & (S[1:-1] >= S[2:])) + 1
    best, w_ms = float(S.max()), float(w[S.argmax()])
    peaks = []
    for i in idx[np.argsort(S[idx])[::-1][:5]]:
        ws = np.geomspace(w[i - 1], w[i + 1], 2001)
        Ss = 1 / np.abs(1 + loop(m, g, ws))
        j = int(Ss.argmax())
        peaks.append(float(Ss[j]))
        if Ss[j] > best:
            best, w_ms = float(Ss[j]), float(ws[j])
    peaks.sort(reverse=True)
    # the runner-up local maximum: when it is as high as the peak, where
    # the peak lies is a matter of rounding
    ms2 = peaks[1] if len(peaks) > 1 else 0.0

    def cross(f, i):
        """Root of f between w[i] and w[i+1]: Illinois (bracketed regula
        falsi) in log w."""
        x0, x1 = math.log(w[i]), math.log(w[i + 1])
        f0, f1 = f(math.exp(x0)), f(math.exp(x1))
        if f0 == 0:
            return math.exp(x0)
        side = 0
        for _ in range(100):
            x2 = x1 - f1 * (x1 - x0) / (f1 - f0)
            f2 = f(math.exp(x2))
            if f2 == 0 or abs(x1 - x0) < 1e-14:
                return math.exp(x2)
            if (f2 > 0) == (f1 > 0):
                x1, f1 = x2, f2
                if side == 1:
                    f0 /= 2
                side = 1
            else:
                x0, f0 = x1, f1
                x1, f1 = x2, f2
                side = -1
        return math.exp(x1)

    mag = np.abs(L)
    pm, w_gc = math.inf, 0.0
    for i in np.flatnonzero(np.sign(mag[:-1] - 1) != np.sign(mag[1:] - 1)):
        wc = cross(lambda x: math.log(abs(loop(m, g, [x])[0])), i)
        p = 180 + math.degrees(np.angle(loop(m, g, [wc])[0]))
        if p < pm:
            pm, w_gc = p, wc

    # negative-real-axis crossings: the grid's estimate picks the few worth
    # polishing (the grid is fine enough to be within a fraction of a percent)
    im = L.imag
    ic = np.flatnonzero((np.sign(im[:-1]) != np.sign(im[1:])) &
                        ((L.real[:-1] < 0) | (L.real[1:] < 0)))
    re_pc, w_pc = 0.0, 0.0
    if ic.size:
        est = -np.minimum(L.real[ic], L.real[ic + 1])
        for i in ic[est >= 0.98 * est.max()]:
            wc = cross(lambda x: np.angle(-loop(m, g, [x])[0]), i)
            Lc = loop(m, g, [wc])[0]
            if Lc.real < 0 and -Lc.real > re_pc:
                re_pc, w_pc = -Lc.real, wc
    gm = 1 / re_pc if re_pc > 0 else math.inf
    if best <= 1.0:  # |S| < 1 everywhere: the supremum is 1, at infinity
        best, w_ms = 1.0, math.inf
    if r > 0:
        if 1 / (1 - r) > best:
            best, w_ms = 1 / (1 - r), math.inf
        if 1 / r < gm:
            gm, w_pc = 1 / r, math.inf
    return {"Ms": best, "w_ms": w_ms, "gm": gm, "w_pc": w_pc, "pm_deg": pm, "w_gc": w_gc,
            "ms2": ms2}


# ---- everything at once ------------------------------------------------------

def compute(m, rule, form, knob=0.0, deriv_filter=10.0, fit=100.0, fit_min=0.0, ms_max=0.0):
    """What pdt_tune_compute returns: (status, result dict or None)."""
    try:
        if rule == ZN:
            Ku, Pu = ultimate(m)
            g, series_rule, kn = ziegler_nichols(Ku, Pu, form), False, 0.0
        else:
            v = view(m)
            if v["K"] == 0:
                raise TuneError(ARG, "zero gain")
            if rule == SIMC:
                g, series_rule, kn = simc(v, form, knob)
            elif rule == IMC:
                g, series_rule, kn = imc(v, form, knob)
            else:
                g, series_rule, kn = amigo(v, form)
        if fit < fit_min:
            raise TuneError(POOR_FIT, "fit")
        if deriv_filter > 0 and g["tauD"] > 0:
            g["Tf"] = g["tauD"] / deriv_filter
        if series_rule:
            series, ideal = g, series_to_ideal(g)
        else:
            ideal, series = g, ideal_to_series(g)
        fig = robustness(m, ideal)
        if ms_max > 0 and fig["Ms"] > ms_max:
            raise TuneError(MS_LIMIT, "Ms")
    except TuneError as e:
        return e.status, None
    return OK, {"ideal": ideal, "series": series, "series_rule": series_rule, "knob": kn,
                "fig": fig}
