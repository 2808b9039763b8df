"""Checks of pdtref.excite against its definitions, scipy and closed forms."""
import math

import numpy as np
import pytest
import scipy.signal as ss

from pdtref import excite as E
from vectorgen import excite as V


def gf2_mulmod(a, b, p, n):
    r = 0
    while b:
        if b & 1:
            r ^= a
        b >>= 1
        a <<= 1
        if (a >> n) & 1:
            a ^= p
    return r


def gf2_xpow(e, p, n):
    """x^e mod p over GF(2)."""
    r, b = 1, 2
    while e:
        if e & 1:
            r = gf2_mulmod(r, b, p, n)
        b = gf2_mulmod(b, b, p, n)
        e >>= 1
    return r


def prime_factors(m):
    f, d = set(), 2
    while d * d <= m:
        while m % d == 0:
            f.add(d)
            m //= d
        d += 1
    if m > 1:
        f.add(m)
    return f


@pytest.mark.parametrize("n", range(2, 32))
def test_polynomial_is_primitive(n):
    """x has order exactly 2^n - 1 modulo the polynomial: it is primitive,
    so the register runs through every non-zero state."""
    p = E.poly_mask(n)
    N = 2 ** n - 1
    assert gf2_xpow(N, p, n) == 1
    for q in prime_factors(N):
        assert gf2_xpow(N // q, p, n) != 1


@pytest.mark.parametrize("n", range(2, 15))
def test_msequence_period_and_balance(n):
    N = 2 ** n - 1
    a = E.msequence(n, 1, 2 * N + n)
    assert np.array_equal(a[:N], a[N:2 * N])
    # no shorter period: every window of n chips differs within a period
    words = {tuple(a[i:i + n]) for i in range(N)}
    assert len(words) == N
    assert int(a[:N].sum()) == 2 ** (n - 1)  # one more 1 than 0s
    # two-level autocorrelation of the +/-1 sequence
    s = 2.0 * a[:N] - 1.0
    for lag in (1, 2, N // 2):
        assert np.dot(s, np.roll(s, lag)) == -1.0


def test_prbs_output_is_held_sequence():
    c = E.config(kind=E.PRBS, Ts=0.1, u0=2.0, amplitude=0.5, pre=0.3, prbs_bits=6, prbs_hold=4,
                 prbs_seed=0b101101, periods=2)
    L = E.length(c)
    assert L == 3 + 2 * 63 * 4
    u, status = E.open_loop(c, L + 5)
    body = u[3:L]
    chips = body[::4]
    assert np.all(body.reshape(-1, 4) == chips[:, None])
    assert np.array_equal(chips[:63], chips[63:])
    assert np.isclose(np.mean(chips[:63]), 2.0 + 0.5 / 63)
    assert np.all(u[L:] == 2.0) and np.all(status[L:] == E.OK) and np.all(status[:L] == E.RUNNING)


def test_chirp_matches_scipy():
    c = E.config(kind=E.CHIRP, Ts=0.05, u0=0.5, amplitude=1.5, pre=0.5, duration=40.0, f0=0.1,
                 f1=0.5)
    u, _ = E.open_loop(c, 820)
    t = 0.05 * np.arange(800)
    ref = 0.5 + 1.5 * ss.chirp(t, 0.1, 40.0, 0.5, method="linear", phi=-90.0)
    assert np.max(np.abs(u[10:810] - ref)) < 1e-12
    assert np.all(u[:10] == 0.5) and np.all(u[810:] == 0.5)


def test_chirp_instantaneous_frequency():
    """Upward zero crossings interpolated: the inverse of their spacing is
    the instantaneous frequency f0 + (f1 - f0) t / T at the midpoint."""
    Ts, T, f0, f1 = 0.01, 30.0, 0.2, 3.0
    c = E.config(kind=E.CHIRP, Ts=Ts, amplitude=1.0, duration=T, f0=f0, f1=f1)
    u, _ = E.open_loop(c, 3000)
    i = np.nonzero((u[:-1] < 0) & (u[1:] >= 0))[0]
    tz = (i + u[i] / (u[i] - u[i + 1])) * Ts
    f_meas = 1.0 / np.diff(tz)
    f_want = f0 + (f1 - f0) * 0.5 * (tz[1:] + tz[:-1]) / T
    assert np.max(np.abs(f_meas / f_want - 1.0)) < 2e-3


def fopdt_relay(K, tau, L, Ts, c, n):
    """The relay closing the loop on a FOPDT sampled exactly (ZOH, L a whole
    number of samples): pv(k+1) = a pv(k) + K (1 - a) u(k - l)."""
    a = math.exp(-Ts / tau)
    l = int(round(L / Ts))
    g = E.config(**c)
    pv = np.zeros(n)
    u = np.zeros(n)
    # run the relay loop sample by sample with the reference relay itself:
    # the reference relay is a function of the whole pv sequence, so grow it
    state = None
    for k in range(n - 1):
        e = g["setpoint"] - pv[k]
        if state is None:
            state = e >= 0
        elif state and e < -g["eps"]:
            state = False
        elif not state and e > g["eps"]:
            state = True
        u[k] = g["d"] if state else -g["d"]
        uk = u[k - l] if k >= l else 0.0
        pv[k + 1] = a * pv[k] + K * (1 - a) * uk
    return pv


def test_relay_on_fopdt_matches_closed_form():
    K, tau, L, Ts = 1.5, 1.0, 2.0, 0.002
    c = dict(kind=E.RELAY, Ts=Ts, d=1.0, relay_skip=2, relay_cycles=4)
    pv = fopdt_relay(K, tau, L, Ts, c, 20000)
    _, status, res = E.relay(E.config(**c), pv)
    assert res is not None and res["cycles"] == 4
    Ku, Pu, a = E.relay_fopdt_exact(K, tau, L, 1.0)
    # sampled switching adds up to one sample of delay
    assert res["Pu"] == pytest.approx(Pu, rel=2e-3)
    assert res["a"] == pytest.approx(a, rel=2e-3)
    assert res["Ku"] == pytest.approx(Ku, rel=2e-3)
    # the describing function's prediction (the true ultimate point) is
    # within a few percent at L / tau = 2
    Ku_df, Pu_df = E.fopdt_ultimate(K, tau, L)
    assert res["Ku"] == pytest.approx(Ku_df, rel=0.05)
    assert res["Pu"] == pytest.approx(Pu_df, rel=0.05)


def test_record_decimation_by_hand():
    c, cap, u, y = V.rec_cases()[0]
    r = E.record(c, cap, u, y)
    D = c["decimation"]
    for j in range(r["n"]):
        assert r["u"][j] == pytest.approx(sum(u[j * D + i] for i in range(D)) / D, rel=1e-15)
        assert r["y"][j] == pytest.approx(sum(y[j * D + i] for i in range(D)) / D, rel=1e-15)
    assert r["status"] == E.OK and r["n"] == cap


def test_record_settle_restart():
    c, cap, u, y = V.rec_cases()[1]
    r = E.record(c, cap, u, y)
    D = c["decimation"]
    ys = y.reshape(-1, D).mean(axis=1)
    # the stored record starts where the last settle window started
    s = next(i for i in range(len(ys)) if np.allclose(ys[i:i + cap], r["y"]))
    assert s > 0
    assert np.ptp(ys[s:s + c["settle"]]) <= c["settle_band"]
    assert np.ptp(ys[s - 1:s + c["settle"]]) > c["settle_band"] or s == 0


def test_vectors_deterministic():
    assert V.generate() == V.generate()
