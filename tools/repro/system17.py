"""The paper's test system (17), the records of the demo, and the figures of
merit every model is judged by.

(17): G(s) = (-0.3s+1)(0.08s+1) / ((2s+1)(s+1)(0.4s+1)(0.2s+1)(0.05s+1)^3).

The records are those of tools/demo/pdt_demo.c: sampled at 20 Hz behind a
zero-order hold around u0 = 40, y0 = 55, with white Gaussian sensor noise of
std 0.02 drawn as the demo draws it (the shared generator, splitmix64 from
the demo's seed, a Box-Muller normal from each two uniforms:
pdtsupport.rng.SplitMix64 here, sim_rng64_normal of tools/sim/sim_rng.h
there), one stream shared by the records in the order the demo makes them
(chirp for Table 1, chirp again for Table 2, pulse-1, pulse-2). The sampled response is exact here as in the demo (the
matrix exponential of a zero-order hold: pdtsupport.plant's here, the
shared simulator of tools/sim there), so the two agree to rounding.
"""
import math

import numpy as np

from pdtsupport import plant
from pdtsupport.rng import SplitMix64

FS = 20.0
TS = 1.0 / FS
NOISE_STD = 0.02
DEMO_SEED = 0x2545F491  # the demo's generator seed (tools/demo/pdt_demo.c)
U0, Y0 = 40.0, 55.0

LAGS17 = [2.0, 1.0, 0.4, 0.2, 0.05, 0.05, 0.05]
ZEROS17 = [-0.3, 0.08]  # time constants of (Z s + 1); negative: right half plane

# Figures of merit: unit-step response over 0..15 s on a 0.01 s grid, and the
# frequency response on 200 points up to the phase crossover of (17).
IAE_T, IAE_DT = 15.0, 0.01
W_U = 1.186
NFREQ = 200

EXC_LEN = {"chirp": 100.0, "pulse-1": 40.0, "pulse-2": 60.0}


def tf17():
    """Numerator and denominator polynomials of (17) in s."""
    num = np.array([1.0])
    for z in ZEROS17:
        num = np.polymul(num, [z, 1.0])
    den = np.array([1.0])
    for t in LAGS17:
        den = np.polymul(den, [t, 1.0])
    return num, den


def freq17(w):
    """Complex frequency response of (17) at w (rad/s)."""
    s = 1j * np.asarray(w, dtype=float)
    g = np.ones_like(s)
    for z in ZEROS17:
        g = g * (z * s + 1.0)
    for t in LAGS17:
        g = g / (t * s + 1.0)
    return g


def step17(t):
    """Unit-step response of (17) at times t (s, from 0, uniform)."""
    t = np.asarray(t, dtype=float)
    return plant.simulate(*tf17(), 0.0, np.ones(t.size), t[1] - t[0], sub=1)


def excitation(name, t):
    t = np.asarray(t, dtype=float)
    if name == "chirp":  # linear sweep 0 -> 0.5 Hz over the record
        return np.sin(np.pi * 0.5 / EXC_LEN["chirp"] * t * t)
    if name == "pulse-1":  # one pulse of 10 s
        return np.where((t >= 1.0) & (t < 11.0), 1.0, 0.0)
    if name == "pulse-2":  # pulses of 2, 4 and 8 s, alternating sign
        return (np.where((t >= 1.0) & (t < 3.0), 1.0, 0.0)
                - np.where((t >= 10.0) & (t < 14.0), 1.0, 0.0)
                + np.where((t >= 24.0) & (t < 32.0), 1.0, 0.0))
    raise ValueError(name)


def simulate17(ud):
    """y[k]: response of (17) at k Ts, from rest, to ud[0..k-1] held over each
    period (y[0] = 0), as plant17_simulate samples it."""
    return plant.simulate(*tf17(), 0.0, ud, TS, sub=1)


def demo_normal(rng):
    """One standard normal as sim_rng64_normal draws it: Box-Muller on two
    uniforms in turn, with the C library's log and cos (numpy's vectorised
    ones may differ in the last bit)."""
    u1 = 1.0 - rng.uniform()  # (0, 1]
    u2 = rng.uniform()
    return math.sqrt(-2.0 * math.log(u1)) * math.cos(6.283185307179586 * u2)


def records():
    """The demo's four records, in its order: {key: (t, u, y)} with keys
    'chirp' (Table 1), 'chirp-2' (Table 2), 'pulse-1', 'pulse-2'."""
    rng = SplitMix64(DEMO_SEED)  # the demo's noise, from its seed
    out = {}
    for key, exc in (("chirp", "chirp"), ("chirp-2", "chirp"), ("pulse-1", "pulse-1"),
                     ("pulse-2", "pulse-2")):
        n = int(round(EXC_LEN[exc] * FS))
        t = np.arange(n) * TS
        ud = excitation(exc, t)
        yd = simulate17(ud)
        noise = np.array([demo_normal(rng) for _ in range(n)])
        out[key] = (t, U0 + ud, Y0 + yd + NOISE_STD * noise)
    return out


# ----------------------------------------------------------------- models

class Model:
    """A FOPDT or SOPDT, held as K e^{-Td s} / (c2 s^2 + c1 s + 1) (c2 = 0
    for a FOPDT), with the numbers a table shows."""

    def __init__(self, kind, K, c1, c2, Td, label=""):
        self.kind, self.K, self.c1, self.c2, self.Td = kind, K, c1, c2, Td
        self.label = label

    @classmethod
    def fopdt(cls, K, tau, Td, label=""):
        return cls("fopdt", K, tau, 0.0, Td, label)

    @classmethod
    def sopdt_tc(cls, K, T1, T2, Td, label=""):
        """K e^{-Td s} / ((T1 s + 1)(T2 s + 1)); T1, T2 may be a complex pair."""
        return cls("sopdt", K, float(np.real(T1 + T2)), float(np.real(T1 * T2)), Td, label)

    @classmethod
    def from_json(cls, d, label=""):
        if d["model"] == "fopdt":
            return cls.fopdt(d["K"], d["tau"], d["Td"], label)
        if d.get("K") is None:
            raise ValueError("integrating model")
        wn, zeta = d["wn"], d["zeta"]
        return cls("sopdt", d["K"], 2.0 * zeta / wn, 1.0 / wn ** 2, d["Td"], label)

    def time_constants(self):
        """(T1, T2): larger first for a real pair, else re -/+ j im."""
        if self.kind == "fopdt":
            return self.c1, None
        r = np.roots([self.c2, self.c1, 1.0])  # poles
        T = np.sort_complex(-1.0 / r.astype(complex))
        if np.all(np.abs(T.imag) < 1e-12):
            T = np.sort(T.real)[::-1]
            return float(T[0]), float(T[1])
        return complex(T[0].real, -abs(T[0].imag)), complex(T[0].real, abs(T[0].imag))

    def freq(self, w):
        s = 1j * np.asarray(w, dtype=float)
        return self.K * np.exp(-self.Td * s) / (self.c2 * s * s + self.c1 * s + 1.0)

    def step(self, t):
        t = np.asarray(t, dtype=float)
        tt = t - self.Td
        y = np.zeros_like(t)
        on = tt > 0
        if self.kind == "fopdt":
            y[on] = self.K * (1.0 - np.exp(-tt[on] / self.c1))
            return y
        p1, p2 = np.roots([self.c2, self.c1, 1.0]).astype(complex)
        x = tt[on]
        if abs(p1 - p2) > 1e-6 * abs(p1):
            h = 1.0 + (p2 * np.exp(p1 * x) - p1 * np.exp(p2 * x)) / (p1 - p2)
        else:  # repeated pole
            p = 0.5 * (p1 + p2)
            h = 1.0 - (1.0 - p * x) * np.exp(p * x)
        y[on] = self.K * h.real
        return y


def step_response(model, t):
    """Unit-step response of a Model or of (17) (model None)."""
    return step17(t) if model is None else model.step(t)


class Merit:
    def __init__(self, iae, maxdev, ferr):
        self.iae, self.maxdev, self.ferr = iae, maxdev, ferr


def merit(model, _cache={}):
    """IAE and largest deviation of the unit-step response from (17) over
    0..15 s (trapezoid, 0.01 s), and the largest |G - G17| / |G17| over
    w = w_u i / 200, i = 1..200."""
    if "t" not in _cache:
        t = np.arange(int(round(IAE_T / IAE_DT)) + 1) * IAE_DT
        w = W_U * np.arange(1, NFREQ + 1) / NFREQ
        _cache.update(t=t, h17=step17(t), w=w, g17=freq17(w))
    t, w = _cache["t"], _cache["w"]
    e = np.abs(model.step(t) - _cache["h17"])
    iae = float(np.sum((e[1:] + e[:-1]) * 0.5) * IAE_DT)
    ferr = float(np.max(np.abs(model.freq(w) - _cache["g17"]) / np.abs(_cache["g17"])))
    return Merit(iae, float(np.max(e)), ferr)
