"""Checks of pdtref.models against closed forms and scipy.signal."""
import math

import numpy as np
import pytest
import scipy.signal as ss

from pdtref import models as M

SOPDTS = [
    M.sopdt_from_tc(1.0, 2.0, 1.2, 0.77),
    M.sopdt_from_tc(2.0, 10.0, 0.05, 0.5),
    M.Sopdt(1.0, 2.0, 1.0, 0.3),
    M.sopdt_from_natural(1.3, 2.0, 0.1, 0.4),
    M.sopdt_from_natural(-1.3, 2.0, 0.7, 0.0),
    M.sopdt_from_tc(1.0, 2.9, 0.5, 0.79, complex=True),
    M.sopdt_from_integ(0.5, 2.0, 0.33),
]


def closed_step(m, t):
    """The textbook closed forms (REFERENCE section 2), per pole case."""
    s = np.maximum(np.asarray(t, float) - m.Td, 0.0)
    if isinstance(m, M.Fopdt):
        return m.K * (1 - np.exp(-s / m.tau))
    if m.b == 0:
        a = m.a
        return m.k / a * (s - (1 - np.exp(-a * s)) / a)
    K = m.k / m.b
    tc = M.to_tc(m)
    if tc.complex:
        nat = M.to_natural(m)
        sig = nat.zeta * nat.wn
        wd = nat.wn * math.sqrt(1 - nat.zeta ** 2)
        return K * (1 - np.exp(-sig * s) * (np.cos(wd * s) + sig / wd * np.sin(wd * s)))
    if abs(tc.T1 - tc.T2) < 1e-9 * tc.T1:
        T = tc.T1
        return K * (1 - (1 + s / T) * np.exp(-s / T))
    T1, T2 = tc.T1, tc.T2
    return K * (1 - (T1 * np.exp(-s / T1) - T2 * np.exp(-s / T2)) / (T1 - T2))


@pytest.mark.parametrize("m", SOPDTS + [M.Fopdt(1.5, 2.0, 0.33), M.Fopdt(-0.7, 0.05, 0.0)])
def test_step_closed_form_and_scipy(m):
    t = np.linspace(0, 20, 401)
    y = M.step(m, t)
    ref = closed_step(m, t)
    assert np.max(np.abs(y - ref)) <= 1e-12 * max(1.0, np.max(np.abs(ref)))
    if isinstance(m, M.Fopdt):
        num, den = [m.K], [m.tau, 1.0]
    else:
        num, den = [m.k], [1.0, m.a, m.b]
    s = np.linspace(0.0, 20.0, 401)  # time after the dead time, from rest
    _, ys, _ = ss.lsim((num, den), np.ones_like(s), s)
    yd = M.step(m, s + m.Td)
    assert np.max(np.abs(yd - ys)) <= 1e-6 * max(1.0, np.max(np.abs(ys)))
    assert np.all(y[t < m.Td] == 0)


def test_step_small_times_relative():
    """Tiny times: relative accuracy (the C vectors rely on it)."""
    m = M.sopdt_from_tc(1.0, 2.0, 1.2, 0.0)
    t = np.array([1e-6, 1e-4, 1e-2])
    y = M.step(m, t)
    # leading terms of the series: k t^2/2 - k a t^3/6
    approx = m.k * t ** 2 / 2 - m.k * m.a * t ** 3 / 6 + m.k * (m.a ** 2 - m.b) * t ** 4 / 24
    # truncation of the four-term series: relative t^3
    assert np.allclose(y[:2], approx[:2], rtol=1e-11, atol=0)
    assert np.allclose(y[2], approx[2], rtol=1e-6, atol=0)


@pytest.mark.parametrize("m", SOPDTS + [M.Fopdt(1.5, 2.0, 0.33), M.Fopdt(-0.7, 0.05, 0.0)])
def test_freq_scipy(m):
    w = np.logspace(-3, 2, 60)
    mag, ph = M.freq(m, w)
    if isinstance(m, M.Fopdt):
        num, den = [m.K], [m.tau, 1.0]
    else:
        num, den = [m.k], [1.0, m.a, m.b]
    _, h = ss.freqs(num, den, worN=w)
    h = h * np.exp(-1j * w * m.Td)
    assert np.allclose(mag, np.abs(h), rtol=1e-12)
    # same angle modulo 2 pi, and continuous
    assert np.allclose(np.exp(1j * ph), h / np.abs(h), atol=1e-10)
    # without the dead time the phase is continuous, non-increasing, and in
    # [-order pi/2, 0] (shifted by -pi for a negative gain)
    gain = m.K if isinstance(m, M.Fopdt) else m.k
    lag = ph + w * m.Td + (math.pi if gain < 0 else 0.0)
    order = 1 if isinstance(m, M.Fopdt) else 2
    assert np.all(np.diff(lag) <= 1e-12)
    assert np.all(lag <= 1e-12) and np.all(lag >= -order * math.pi / 2 - 1e-12)


def test_freq_integrator_at_zero():
    mag, ph = M.freq(M.sopdt_from_integ(1.0, 0.5, 1.0), [0.0])
    assert np.isinf(mag[0]) and ph[0] == pytest.approx(-math.pi / 2)


def test_conversions_round_trip():
    m = M.sopdt_from_tc(2.0, 3.0, 0.5, 0.25)
    tc = M.to_tc(m)
    assert (tc.T1, tc.T2, tc.complex) == pytest.approx((3.0, 0.5, False))
    n = M.to_natural(m)
    m2 = M.sopdt_from_natural(*n)
    assert m2 == pytest.approx(m)
    c = M.sopdt_from_tc(1.0, 2.9, 0.5, 0.79, complex=True)
    tcc = M.to_tc(c)
    assert tcc.complex and (tcc.T1, tcc.T2) == pytest.approx((2.9, 0.5))
    poles = np.roots([1, c.a, c.b])
    assert np.allclose(sorted(-1 / poles, key=lambda z: z.imag), [2.9 - 0.5j, 2.9 + 0.5j])
    i = M.sopdt_from_integ(-0.4, 1.5, 2.0)
    assert M.to_integ(i) == pytest.approx((-0.4, 1.5, 2.0))
    crit = M.to_tc(M.Sopdt(1.0, 2.0, 1.0, 0.0))
    assert not crit.complex and (crit.T1, crit.T2) == pytest.approx((1.0, 1.0))


def test_no_form_and_bad_input():
    i = M.sopdt_from_integ(1.0, 1.0, 0.0)
    for f in (M.to_natural, M.to_tc, M.dc_gain):
        with pytest.raises(M.NoFormError):
            f(i)
    with pytest.raises(M.NoFormError):
        M.to_integ(M.Sopdt(1.0, 1.0, 1.0, 0.0))
    for bad in (M.Fopdt(1.0, 0.0, 0.0), M.Fopdt(1.0, 1.0, -1.0), M.Sopdt(1.0, 0.0, 1.0, 0.0),
                M.Sopdt(1.0, 1.0, -1.0, 0.0), M.Sopdt(float("nan"), 1.0, 1.0, 0.0)):
        with pytest.raises(ValueError):
            M.step(bad, [1.0])
    with pytest.raises(ValueError):
        M.freq(M.Fopdt(1.0, 1.0, 0.0), [-1.0])


def test_expm_against_eigen():
    A = np.array([[0.0, 1.0], [-4.0, -0.4]])
    for t in (0.01, 1.0, 30.0):
        lam, V = np.linalg.eig(A * t)
        ref = (V @ np.diag(np.exp(lam)) @ np.linalg.inv(V)).real
        assert np.allclose(M.expm(A * t), ref, rtol=1e-12, atol=1e-14)
