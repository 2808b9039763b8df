"""The PID controller of lib/src/pdt_pid.c, and the continuous-time loop it
is designed to approximate.

Two parts:

- ``Pid``: the discrete controller, written from its definition (docs/pid.md)
  as a plain scalar loop; its linear part is checked in tools/tests against
  the controller's z-transfer functions run through ``scipy.signal.lfilter``.
- ``continuous_loop``: the closed loop of the *continuous* controller
  Kc [(b r - y) + 1/(Ti s)(r - y) + Td s/(Tf s + 1)(c r - y)] with a FOPDT or
  SOPDT plant, a set-point r and a load d at the plant's input. Computed by
  exact (matrix-exponential) sampling of plant and controller at a fine step h,
  twice (h and h/2), combined by Richardson extrapolation, so that the error
  of the fine-step method is O(h^2); checked in tools/tests against the
  closed-form closed loop of a delay-free plant.
- ``discrete_loop``: the same loop with the plant sampled exactly (ZOH,
  fractional dead time) at the scan period and ``Pid`` as the controller:
  what the C tests simulate.
"""
import math

import numpy as np

from . import discrete as D
from . import models as M

IDEAL, SERIES = 0, 1
AW_BACK_CALC, AW_CONDITIONAL, AW_BOTH, AW_NONE = 0, 1, 2, 3


def config(**kw):
    """A configuration with pdt_pid_config_default's values, updated by kw."""
    c = dict(Ts=0.1, form=IDEAL, Kc=1.0, Ti=10.0, Td=0.0, Tf=0.0, N=10.0, b=1.0, c=0.0,
             u_min=0.0, u_max=100.0, rate_max=0.0, antiwindup=AW_BACK_CALC, Tt=0.0)
    for k in kw:
        if k not in c:
            raise KeyError(k)
    c.update(kw)
    return c


def ideal_gains(c):
    """(K, Ti, Td, Tf) of the ideal form the configuration means."""
    K, Ti, Td, Tf = c["Kc"], c["Ti"], c["Td"], c["Tf"]
    if Tf == 0.0 and c["N"] > 0.0:
        Tf = Td / c["N"]
    if c["form"] == SERIES and Ti > 0.0:
        f = 1.0 + Td / Ti
        K, Ti, Td = K * f, Ti * f, Td / f
    return K, Ti, Td, Tf


class Pid:
    """The discrete PID, state for state as docs/pid.md defines it."""

    def __init__(self, cfg, u0):
        self.primed = False
        self.i = 0.0
        self.df = 0.0
        self.sp = self.pv = 0.0
        self._set(cfg)
        self.u = min(max(u0, cfg["u_min"]), cfg["u_max"])

    def _set(self, cfg):
        self.cfg = dict(cfg)
        K, Ti, Td, Tf = ideal_gains(cfg)
        Ts = cfg["Ts"]
        self.K = K
        self.ki = K * Ts / (2.0 * Ti) if Ti > 0 else 0.0
        self.kd = K * Td
        self.ad = math.exp(-Ts / Tf) if Tf > 0 else 0.0
        self.ao = 0.0
        if Ti > 0:
            Tt = cfg["Tt"] or (math.sqrt(Ti * Td) if Td > 0 else Ti)
            self.ao = 1.0 - math.exp(-Ts / Tt)
        self.du = cfg["rate_max"] * Ts

    def _df(self, sp, pv):
        if not self.primed:
            return 0.0
        dy = self.cfg["c"] * (sp - self.sp) - (pv - self.pv)
        return self.ad * self.df + (1.0 - self.ad) * dy / self.cfg["Ts"]

    def update(self, sp, pv):
        c = self.cfg
        p = self.K * (c["b"] * sp - pv)
        df = self._df(sp, pv)
        d = self.kd * df
        lo, hi = c["u_min"], c["u_max"]
        if self.du > 0:
            lo = min(max(self.u - self.du, c["u_min"]), c["u_max"])
            hi = min(max(self.u + self.du, c["u_min"]), c["u_max"])
        if not self.primed:
            ik, v, inc = self.u - p - d, self.u, 0.0
        else:
            inc = self.ki * ((sp - pv) + (self.sp - self.pv))
            ik = self.i + inc
            v = p + ik + d
        if c["antiwindup"] in (AW_CONDITIONAL, AW_BOTH):
            if v > hi and inc > 0:
                ik = max(self.i, hi - p - d)
                v = p + ik + d
            elif v < lo and inc < 0:
                ik = min(self.i, lo - p - d)
                v = p + ik + d
        u = min(max(v, lo), hi)
        if c["antiwindup"] in (AW_BACK_CALC, AW_BOTH):
            ik += self.ao * (u - v)
        self.i, self.df, self.sp, self.pv, self.u = ik, df, sp, pv, u
        self.primed = True
        return u

    def track(self, sp, pv, u):
        p = self.K * (self.cfg["b"] * sp - pv)
        df = self._df(sp, pv)
        self.i = u - p - self.kd * df
        self.df, self.sp, self.pv, self.u = df, sp, pv, u
        self.primed = True

    def set_config(self, cfg):
        self._set(cfg)
        if self.primed:
            p = self.K * (cfg["b"] * self.sp - self.pv)
            self.i = self.u - p - self.kd * self.df
        else:
            self.u = min(max(self.u, cfg["u_min"]), cfg["u_max"])


# ---- closed loops ---------------------------------------------------------

def _controller_ss(K, Ti, Td, Tf, b, c):
    """Continuous controller from (r, y) to u: (A, B, C, D), states the
    integral of e and the filter state; Tf > 0 when Td > 0."""
    A = np.zeros((2, 2))
    B = np.zeros((2, 2))
    Cc = np.zeros((1, 2))
    Dc = np.array([[K * b, -K]])
    if Ti > 0:
        B[0] = [1.0, -1.0]
        Cc[0, 0] = K / Ti
    if Td > 0:
        if not Tf > 0:
            raise ValueError("the continuous reference needs a filtered derivative")
        # D = K Td s/(Tf s + 1) w, w = c r - y: x' = (w - x)/Tf, D = K Td (w - x)/Tf
        A[1, 1] = -1.0 / Tf
        B[1] = [c / Tf, -1.0 / Tf]
        Cc[0, 1] = -K * Td / Tf
        Dc = Dc + np.array([[K * Td * c / Tf, -K * Td / Tf]])
    return A, B, Cc, Dc


def _fine_loop(m, gains, b, c, t_end, h, r, d):
    """The loop stepped at h: controller and plant sampled exactly, the
    plant's dead time a whole number of steps. Returns y at multiples of h."""
    K, Ti, Td, Tf = gains
    Ap, Bp, Cp = M.state_space(m)
    Phip, Gp = M.expm_integral(Ap, Bp, h)
    Ac, Bc, Cc, Dc = _controller_ss(K, Ti, Td, Tf, b, c)
    Phic, Gc = M.expm_integral(Ac, Bc, h)
    L = int(round(m.Td / h))
    if abs(L * h - m.Td) > 1e-9:
        raise ValueError("the dead time must be a multiple of the fine step")
    n = int(round(t_end / h))
    xp = np.zeros(Phip.shape[0])
    xc = np.zeros(2)
    buf = [0.0] * L          # u + d of the last L steps, oldest first
    y = np.zeros(n + 1)
    for k in range(n + 1):
        yk = float(Cp[0] @ xp)
        y[k] = yk
        w = np.array([r, yk])
        u = float(Cc[0] @ xc + Dc[0] @ w)
        buf.append(u + d)
        wk = buf.pop(0)
        xc = Phic @ xc + Gc @ w
        xp = Phip @ xp + Gp[:, 0] * wk
    return y


def continuous_loop(m, gains, t, b=1.0, c=0.0, r=1.0, d=0.0, h=0.001):
    """y(t) of the continuous loop from rest, r and d steps at t = 0.
    gains: ideal (K, Ti, Td, Tf). t: times, multiples of h."""
    t = np.asarray(t, dtype=float)
    t_end = float(t[-1])
    y1 = _fine_loop(m, gains, b, c, t_end, h, r, d)
    y2 = _fine_loop(m, gains, b, c, t_end, h / 2, r, d)
    i1 = np.rint(t / h).astype(int)
    i2 = np.rint(t / (h / 2)).astype(int)
    return 2.0 * y2[i2] - y1[i1]


def plant_sampled(m, Ts):
    """(l, Phi, G0, G1, C) of the plant sampled at Ts: x(k+1) = Phi x(k) +
    G0 w(k-l) + G1 w(k-l-1), y(k) = C x(k), w the input held over a scan."""
    l, f = D.split_delay(m.Td, Ts)
    Phi, G0, G1, C = D._sampled(m, Ts, f)
    return l, Phi, G0[:, 0], G1[:, 0], C[0]


def discrete_loop(m, cfg, n, r=1.0, d=0.0):
    """y(k Ts), u(k Ts), k < n, of the plant sampled at Ts under Pid from
    rest; the controller tracks (r = 0, y = 0, u = 0) one scan before."""
    l, Phi, G0, G1, C = plant_sampled(m, cfg["Ts"])
    pid = Pid(cfg, 0.0)
    pid.track(0.0, 0.0, 0.0)
    x = np.zeros(Phi.shape[0])
    past = [0.0] * (l + 2)   # w(k - j) for j = 0 .. l + 1, newest first
    ys = np.zeros(n)
    us = np.zeros(n)
    for k in range(n):
        y = float(C @ x)
        u = pid.update(r, y)
        ys[k], us[k] = y, u
        past.insert(0, u + d)
        past.pop()
        x = Phi @ x + G0 * past[l] + G1 * past[l + 1]
    return ys, us
