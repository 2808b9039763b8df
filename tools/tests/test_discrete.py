"""Checks of pdtref.discrete against scipy.signal and closed forms."""
import math

import numpy as np
import pytest
import scipy.signal as ss

from pdtref import discrete as D
from pdtref import models as M

MODELS = [
    M.Fopdt(1.5, 2.0, 0.33),
    M.sopdt_from_tc(1.0, 2.0, 1.2, 0.77),
    M.sopdt_from_tc(2.0, 10.0, 0.05, 0.5),
    M.Sopdt(1.0, 2.0, 1.0, 0.3),
    M.sopdt_from_natural(1.3, 2.0, 0.1, 0.4),
    M.sopdt_from_tc(1.0, 2.9, 0.5, 0.79, complex=True),
    M.sopdt_from_integ(0.5, 2.0, 0.33),
]


def tf(m):
    if isinstance(m, M.Fopdt):
        return [m.K], [m.tau, 1.0]
    return [m.k], [1.0, m.a, m.b]


@pytest.mark.parametrize("m", MODELS)
@pytest.mark.parametrize("Ts", [0.005, 0.05, 0.5, 1.0])
def test_integer_delay_matches_cont2discrete(m, Ts):
    num, den, _ = ss.cont2discrete(tf(m), Ts, method="zoh")
    num = np.trim_zeros(np.ravel(num), "f")
    d = D.zoh_int(m, Ts, 3)
    n = d.order
    assert np.allclose(d.a[:n], den[1:], rtol=1e-10, atol=1e-14)
    # scipy's numerator (z^-1 ...): b[0..n-1] with the hold delay
    ref = np.zeros(3)
    ref[3 - len(num) - (3 - n) - 0:n] = num if len(num) == n else num[-n:]
    scale = np.max(np.abs(ref))
    # cont2discrete forms the numerator through ss2tf, which loses digits to
    # cancellation when Ts is small: compare on its precision
    assert np.allclose(d.b, ref, rtol=0, atol=(1e-10 if Ts > 0.01 else 1e-7) * scale)
    assert d.delay == 3


@pytest.mark.parametrize("m", MODELS)
@pytest.mark.parametrize("Ts", [0.01, 0.1, 0.7])
def test_step_equals_continuous_at_samples(m, Ts):
    """The discrete step response is the continuous one sampled, for any
    fractional delay (the defining property of the exact ZOH model)."""
    for f in (0.0, 1e-6, 0.3, 0.5, 0.999):
        mm = m._replace(Td=(2 + f) * Ts)
        d = D.zoh(mm, Ts)
        y = D.simulate(d, np.ones(200))
        yc = M.step(mm, Ts * np.arange(200))
        assert np.max(np.abs(y - yc)) <= 1e-11 * max(1.0, np.max(np.abs(yc)))


@pytest.mark.parametrize("m", MODELS)
def test_lsim_with_fractional_delay(m):
    """A random held input through the discrete model equals scipy's lsim of
    the continuous model with the input delayed by Td."""
    Ts = 0.1
    mm = m._replace(Td=(1 + 0.37) * Ts)
    rng_state = 12345
    u = []
    for _ in range(80):
        rng_state = (1103515245 * rng_state + 12345) & 0x7FFFFFFF
        u.append((rng_state >> 16) / 32768.0 - 0.5)
    u = np.array(u)
    d = D.zoh(mm, Ts)
    y = D.simulate(d, u)
    # fine grid, exact hold and exact delay
    sub = 100
    tf_ = np.arange(80 * sub) * (Ts / sub)
    held = np.repeat(u, sub)
    shift = int(round(mm.Td / (Ts / sub)))
    ud = np.concatenate([np.zeros(shift), held])[:len(tf_)]
    _, yl, _ = ss.lsim(tf(m), ud, tf_, interp=False)
    assert np.max(np.abs(y - yl[::sub])) <= 1e-6 * max(1.0, np.max(np.abs(yl)))


@pytest.mark.parametrize("m", MODELS)
def test_dc_gain_and_delta(m):
    Ts = 0.05
    d = D.zoh(m, Ts)
    dd = D.delta(m, Ts)
    if d.order == 1:
        assert dd[0] == pytest.approx(1 + d.a[0], rel=1e-12)
        den = dd[0]
    else:
        assert dd[0] == pytest.approx(2 + d.a[0], rel=1e-12)
        assert dd[1] == pytest.approx(1 + d.a[0] + d.a[1], rel=1e-9, abs=1e-15)
        den = dd[1]
    if isinstance(m, M.Sopdt) and m.b == 0:
        assert dd[1] == pytest.approx(0.0, abs=1e-15)
    else:
        assert sum(d.b) / den == pytest.approx(M.dc_gain(m), rel=1e-11)


def test_fopdt_closed_form():
    m = M.Fopdt(2.0, 1.5, 0.35)
    Ts = 0.1
    d = D.zoh(m, Ts)
    l, f = 3, 0.5
    alpha = math.exp(-Ts / m.tau)
    assert d.delay == l
    assert d.a == pytest.approx((-alpha, 0.0))
    am = alpha ** (1 - f)
    assert d.b == pytest.approx((m.K * (1 - am), m.K * (am - alpha), 0.0), rel=1e-12)


def test_split_delay():
    l, f = D.split_delay(0.3 * 7, 0.3)  # 7.000000000000001: a tiny fraction stays
    assert l == 7 and f < 1e-14
    assert D.split_delay(0.7 - 1e-17, 0.1) == (7, 0.0)  # 6.999999999999999: whole
    assert D.split_delay(0.0, 0.1) == (0, 0.0)
    l, f = D.split_delay(0.25, 0.1)
    assert l == 2 and f == pytest.approx(0.5)


def test_simulate_predict_lfilter():
    d = D.zoh(M.sopdt_from_natural(1.0, 1.0, 0.3, 0.23), 0.1)
    u = np.sin(0.3 * np.arange(100)) + (np.arange(100) > 10)
    num = np.concatenate([np.zeros(d.delay + 1), d.b])
    den = [1.0, d.a[0], d.a[1]]
    y = D.simulate(d, u)
    assert np.allclose(y, ss.lfilter(num, den, u), rtol=1e-12, atol=1e-12)
    # equation error on the model's own output is zero
    assert np.allclose(D.predict(d, u, y), y, rtol=1e-12, atol=1e-12)
    noisy = y + 0.1 * np.cos(np.arange(100))
    yhat = D.predict(d, u, noisy)
    direct = ss.lfilter(num, [1.0], u) - d.a[0] * np.concatenate([[0], noisy[:-1]]) \
        - d.a[1] * np.concatenate([[0, 0], noisy[:-2]])
    assert np.allclose(yhat, direct, rtol=1e-12, atol=1e-12)
