"""Closed-loop records for the loop-performance monitor's tests and report:
a PI controller (velocity form, its own discretisation) around a
continuous plant simulated on a fine grid (pdtsupport.plant.Fine), with
a valve (limits, stiction), load disturbances at the plant input,
measurement noise and set-point steps. Written apart from the C
library: it shares no code with pdt_monitor, pdt_pid or pdt_discrete."""
from dataclasses import dataclass, field

import numpy as np
import scipy.signal as ss

from pdtsupport.plant import Fine
from pdtsupport.rng import SplitMix64


@dataclass
class Plant:
    """K prod(1 / (T s + 1)) e^{-Td s}, sampled every Ts by the loop."""
    name: str
    K: float
    lags: tuple
    Td: float
    Ts: float

    def tf(self, gain=None):
        den = np.array([1.0])
        for T in self.lags:
            den = np.polymul(den, [T, 1.0])
        return np.array([self.K if gain is None else gain]), den

    def model(self):
        """The model the monitor is given: the plant itself as FOPDT or
        SOPDT when it is one, else Skogestad's half rule to a FOPDT."""
        lags = sorted(self.lags, reverse=True)
        if len(lags) == 1:
            return {"model": "fopdt", "K": self.K, "tau": lags[0], "Td": self.Td}
        if len(lags) == 2:
            T1, T2 = lags
            return {"model": "sopdt", "K": self.K, "a": (T1 + T2) / (T1 * T2),
                    "b": 1.0 / (T1 * T2), "Td": self.Td}
        tau = lags[0] + lags[1] / 2.0
        theta = self.Td + lags[1] / 2.0 + sum(lags[2:])
        return {"model": "fopdt", "K": self.K, "tau": tau, "Td": theta}

    def fopdt(self):
        """(K, tau, theta) by the half rule, for the tuning rules."""
        lags = sorted(self.lags, reverse=True)
        if len(lags) == 1:
            return self.K, lags[0], self.Td
        return (self.K, lags[0] + lags[1] / 2.0,
                self.Td + lags[1] / 2.0 + sum(lags[2:]))


PLANTS = (
    Plant("lag", 2.0, (10.0,), 2.0, 0.5),
    Plant("two-lag", 1.0, (6.0, 2.0), 1.5, 0.5),
    Plant("dead-time", 0.5, (3.0,), 5.0, 0.5),
    Plant("four-lag", 1.5, (1.0, 1.0, 1.0, 1.0), 0.0, 0.25),
)


def simc_pi(plant):
    """SIMC PI, tau_c = theta (Skogestad 2003), on the half-rule FOPDT."""
    K, tau, theta = plant.fopdt()
    Kc = tau / (K * 2.0 * theta)
    return Kc, min(tau, 8.0 * theta)


def ms_of(plant, Kc, Ti):
    """Peak of |1 / (1 + L)| with L the PI (with the hold's Ts / 2 of
    delay) on the true plant."""
    w = np.logspace(-4, np.log10(np.pi / plant.Ts), 4000)
    num, den = plant.tf()
    s = 1j * w
    G = np.polyval(num, s) / np.polyval(den, s) * np.exp(-s * (plant.Td + plant.Ts / 2))
    L = Kc * (1 + 1 / (Ti * s)) * G
    return float(np.max(np.abs(1 / (1 + L))))


def gain_for_ms(plant, Ti, target):
    """The Kc of a PI with integral time Ti whose Ms is target (bisection)."""
    lo, hi = 1e-6, simc_pi(plant)[0]
    while ms_of(plant, hi, Ti) < target:
        lo, hi = hi, hi * 2
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if ms_of(plant, mid, Ti) < target else (lo, mid)
    return 0.5 * (lo + hi)


@dataclass
class Scenario:
    """What the loop is and what happens to it."""
    Kc: float
    Ti: float
    n: int = 4000
    gain_factor: float = 1.0    # true plant gain over the model's
    noise: float = 0.02         # measurement noise std, pv units
    load_std: float = 0.05      # filtered load noise std, u units (steady)
    load_tau: float = 20.0      # its filter time constant, s
    load_steps: int = 3         # random load steps in the record
    load_step: float = 0.3      # their size, u units
    sp_amp: float = 1.0         # set-point step size, pv units
    sp_every: int = 600         # samples between set-point steps (0: none)
    u_lim: tuple = (-1e9, 1e9)  # output limits, deviation units
    stiction: float = 0.0       # valve sticks until u moved this much
    u0: float = 50.0            # operating point of the output
    pv0: float = 20.0           # and of the process value
    sp_ramp: tuple = field(default_factory=tuple)  # (k0, k1, level): sp held
                                                   # at level from k0 to k1


def _disturbances(sc, plant, rng):
    """Per-sample load (u units), set-point (deviation) and noise."""
    n = sc.n
    a = np.exp(-plant.Ts / sc.load_tau)
    rnd = rng.uniform
    white = rng.normal(n) * sc.load_std * np.sqrt(1 - a * a)
    load = ss.lfilter([1.0], [1.0, -a], white)
    for _ in range(sc.load_steps):
        k = int(rnd() * n)
        load[k:] += sc.load_step * (1 if rnd() < 0.5 else -1)
    sp = np.zeros(n)
    if sc.sp_every:
        level, k = 0.0, sc.sp_every // 2
        while k < n:
            level = sc.sp_amp * (1 if level <= 0 else -1) * (0.5 + 0.5 * rnd())
            sp[k:] = level
            k += int(sc.sp_every * (0.7 + 0.6 * rnd()))
    if sc.sp_ramp:
        k0, k1, level = sc.sp_ramp
        sp[k0:k1] = level
    return load, sp, sc.noise * rng.normal(n)


def simulate(plant, sc, seed, sub=4):
    """One record: dict of arrays t, sp, pv, u (absolute units)."""
    load, sp, noise = _disturbances(sc, plant, SplitMix64.keyed(seed))
    h = plant.Ts / sub
    sim = Fine(*plant.tf(plant.K * sc.gain_factor), h, int(round(plant.Td / h)))
    u = np.zeros(sc.n)
    pv = np.zeros(sc.n)
    uk, valve, e_last, y = 0.0, 0.0, 0.0, 0.0
    for k in range(sc.n):
        pv[k] = y + noise[k]
        e = sp[k] - pv[k]
        du = sc.Kc * ((e - e_last) + plant.Ts / sc.Ti * e) if k else 0.0
        uk = min(max(uk + du, sc.u_lim[0]), sc.u_lim[1])
        e_last = e
        u[k] = uk
        if abs(uk - valve) > sc.stiction:
            valve = uk
        for _ in range(sub):
            w = sim.advance(valve + load[k])
        y = sim.output_fed(w)
    return {"t": np.arange(sc.n) * plant.Ts, "sp": sp + sc.pv0, "pv": pv + sc.pv0,
            "u": u + sc.u0}


def write_csv(path, rec):
    """The record as the CSV `pdtfit monitor` reads (t,sp,pv,u)."""
    data = np.column_stack([rec["t"], rec["sp"], rec["pv"], rec["u"]])
    np.savetxt(path, data, delimiter=",", header="t,sp,pv,u", comments="", fmt="%.9g")


KINDS = ("well", "aggressive", "timid", "gain_changed", "stiction", "saturated")
# The verdict the monitor should give on a record of each kind.
EXPECTED = {"well": "ok", "aggressive": "oscillating", "timid": "sluggish",
            "gain_changed": "model_changed", "stiction": "oscillating",
            "saturated": "saturated"}


def scenario(kind, plant, seed, n=4000):
    """The loop of a record of one kind on plant, its disturbances drawn
    from seed: noise 1-5 % of the set-point step, load noise and steps."""
    rnd = SplitMix64.keyed(seed, 1).uniform
    Kc, Ti = simc_pi(plant)
    u_unit = 1.0 / plant.K  # output move that moves pv by one unit
    sc = Scenario(Kc=Kc, Ti=Ti, n=n, noise=0.01 + 0.04 * rnd(),
                  load_std=0.1 * u_unit, load_tau=5.0 * sum(plant.lags),
                  load_step=0.3 * u_unit, sp_every=int(40 * sum(plant.fopdt()[1:]) / plant.Ts))
    if kind == "aggressive":
        sc.Kc = gain_for_ms(plant, Ti, 3.5)
    elif kind == "timid":
        sc.Kc, sc.Ti = Kc / 4.0, Ti * 2.0
    elif kind == "gain_changed":
        sc.gain_factor = 2.0 if seed % 2 == 0 else 0.5
    elif kind == "stiction":
        sc.stiction = 0.6 * u_unit
        sc.load_std, sc.sp_every = 0.3 * sc.load_std, 0
    elif kind == "saturated":
        sc.u_lim = (-1e9, 1.5 * u_unit)
        sc.sp_ramp = (n // 3, 2 * n // 3, 2.5)
    elif kind != "well":
        raise ValueError(kind)
    return sc
