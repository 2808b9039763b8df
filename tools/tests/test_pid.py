"""Checks of the PID reference (tools/pdtref/pid.py): the discrete controller
against its z-transfer functions (scipy.signal.lfilter), the continuous loop
against the closed-form closed loop of a delay-free plant (scipy.signal),
the discrete loop's first-order convergence to the continuous one, and the
series form against tune.series_to_ideal."""
import math

import numpy as np
import pytest
from scipy import signal


from pdtref import models as M
from pdtref import pid as P
from pdtref import tune as T
from pdtsupport.rng import SplitMix64


def _inputs(n, seed=3):
    rng = SplitMix64.keyed(seed)
    sp = np.repeat(rng.uniform(n // 10 + 1, lo=-2.0, hi=2.0), 10)[:n]
    pv = np.cumsum(rng.uniform(n, lo=-0.3, hi=0.3))
    return sp, pv


@pytest.mark.parametrize("form", [P.IDEAL, P.SERIES])
def test_linear_part_is_the_transfer_functions(form):
    cfg = P.config(Ts=0.05, form=form, Kc=1.4, Ti=2.0, Td=0.5, N=8.0, b=0.6, c=0.3,
                   u_min=-1e6, u_max=1e6)
    sp, pv = _inputs(300)
    pid = P.Pid(cfg, 0.0)
    pid.track(0.0, 0.0, 0.0)
    u = np.array([pid.update(s, p) for s, p in zip(sp, pv)])
    K, Ti, Td, Tf = P.ideal_gains(cfg)
    Ts = cfg["Ts"]
    ki = K * Ts / (2 * Ti)
    a = math.exp(-Ts / Tf)
    e = sp - pv
    i_part = signal.lfilter([ki, ki], [1.0, -1.0], e)
    d_part = signal.lfilter([K * Td * (1 - a) / Ts, -K * Td * (1 - a) / Ts], [1.0, -a],
                            cfg["c"] * sp - pv)
    want = K * (cfg["b"] * sp - pv) + i_part + d_part
    assert np.max(np.abs(u - want)) < 1e-9 * np.max(np.abs(want))


def test_series_form_is_tune_conversion():
    cfg = P.config(form=P.SERIES, Kc=1.3, Ti=2.0, Td=1.2, Tf=0.12)
    K, Ti, Td, Tf = P.ideal_gains(cfg)
    g = T.series_to_ideal(T.gains(1.3, 2.0, 1.2, 0.12))
    assert (K, Ti, Td, Tf) == pytest.approx((g["Kc"], g["tauI"], g["tauD"], g["Tf"]))
    # N applies to the series derivative time, as pdt_tune's deriv_filter.
    K, Ti, Td, Tf = P.ideal_gains(P.config(form=P.SERIES, Kc=1.0, Ti=2.0, Td=1.0, N=10.0))
    assert Tf == pytest.approx(0.1)


def test_continuous_loop_pi_closed_form():
    m = M.Fopdt(1.0, 2.5, 0.0)
    K, Ti = 1.2, 2.0
    t = np.arange(0, 10.0001, 0.1)
    y = P.continuous_loop(m, (K, Ti, 0.0, 0.0), t)
    num = [K * Ti, K]
    den = np.polyadd(np.polymul([Ti, 0], [2.5, 1]), num)
    _, want = signal.step(signal.TransferFunction(num, den), T=t)
    assert np.max(np.abs(y - want)) < 1e-6


def test_continuous_loop_pid_load_closed_form():
    m = M.sopdt_from_tc(1.0, 2.0, 1.2, 0.0)
    K, Ti, Td, Tf = 2.0, 3.0, 0.7, 0.1
    t = np.arange(0, 10.0001, 0.1)
    y = P.continuous_loop(m, (K, Ti, Td, Tf), t, r=0.0, d=1.0)
    # C = K (Ti s (Tf s + 1) + (Tf s + 1) + Td Ti s^2) / (Ti s (Tf s + 1))
    cn = np.polyadd(np.polyadd(np.polymul([K * Ti, 0], [Tf, 1]), [K * Tf, K]),
                    [K * Td * Ti, 0, 0])
    cd = np.polymul([Ti, 0], [Tf, 1])
    gn, gd = [m.k], [1.0, m.a, m.b]
    num = np.polymul(gn, cd)
    den = np.polyadd(np.polymul(gd, cd), np.polymul(gn, cn))
    _, want = signal.step(signal.TransferFunction(num, den), T=t)
    assert np.max(np.abs(y - want)) < 1e-6


def test_discrete_loop_converges_first_order():
    m = M.Fopdt(1.0, 2.5, 1.47)
    g = (0.85, 2.5, 0.0, 0.0)
    t = np.arange(0, 12.0001, 0.1)
    yc = P.continuous_loop(m, g, t)
    err = []
    for Ts in (0.02, 0.002):
        cfg = P.config(Ts=Ts, Kc=0.85, Ti=2.5, u_min=-100, u_max=100)
        yd, _ = P.discrete_loop(m, cfg, int(round(12 / Ts)) + 1)
        err.append(np.max(np.abs(yd[::int(round(0.1 / Ts))] - yc)))
    assert 8.0 < err[0] / err[1] < 12.0


def test_bumpless_and_limits():
    cfg = P.config(Kc=2.0, Ti=3.0, u_min=0.0, u_max=10.0, rate_max=5.0)
    pid = P.Pid(cfg, 4.0)
    assert pid.update(3.0, 1.0) == 4.0        # the start output, exactly
    u = [pid.update(9.0, 1.0) for _ in range(100)]
    assert max(abs(b - a) for a, b in zip([4.0] + u, u)) <= 0.5 + 1e-12
    assert max(u) == 10.0
    pid.set_config(P.config(Kc=0.5, Ti=1.0, u_min=0.0, u_max=10.0))
    assert pid.update(9.0, 1.0) == pytest.approx(10.0, abs=0.2 * 0.05 * 16 + 1e-9)
