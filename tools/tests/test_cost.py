"""Checks of the cost reference (pdtref.cost) and of its vector generator
against independent computations: scipy.signal.lfilter, a direct DFT,
exact continuous-time simulation, and the other pdtref modules."""

import numpy as np
import pytest
from scipy import signal

from pdtref import cost as ref
from pdtref import discrete, models
from vectorgen import cost as gen

RECORDS = gen.records()


def _bpoly(dm):
    return np.concatenate([np.zeros(dm.delay + 1), dm.b])


def _apoly(dm):
    return np.concatenate([[1.0], dm.a[:dm.order]])


def _lib_model(m):
    return models.Fopdt(*m) if isinstance(m, gen.Fopdt) else models.Sopdt(*m)


def test_fft_size():
    assert ref.fft_size(300, 40) == 1024
    assert ref.fft_size(600) == 1024
    assert ref.fft_size(2000) == 2048
    assert ref.fft_size(20, 0) == 64
    assert ref.fft_size(20, 19) == 32
    assert ref.fft_size(1, 0) == 16
    with pytest.raises(ValueError):
        ref.fft_size(10, 10)
    for n in range(18, 300, 7):
        for lu in range(0, n - 17, 5):
            nf = ref.fft_size(n, lu)
            assert nf & (nf - 1) == 0
            assert nf >= max(2 * (n - lu) - 3, n, 16) > nf // 2 or nf == 16


@pytest.mark.parametrize("rec", RECORDS, ids=[r["name"] for r in RECORDS])
def test_time_residuals_match_lfilter(rec):
    u0, y0, Ts, lu = rec["u0"], rec["y0"], rec["Ts"], rec["delay_max"]
    ud, yd = rec["u"] - u0, rec["y"] - y0
    for m in rec["cands"]:
        for dm in (gen.zoh(m, Ts), gen.zoh(m, Ts, gen.int_delay(m, Ts))):
            k = ref.time_range(len(yd), lu, dm.order)
            # Prediction: r = A(q) y - B(q) u.
            r = signal.lfilter(_apoly(dm), [1.0], yd) - signal.lfilter(_bpoly(dm), [1.0], ud)
            got = ref.prediction_residuals(rec["u"], rec["y"], dm, u0, y0, lu)
            np.testing.assert_allclose(got, r[k], rtol=0, atol=1e-12 * np.max(np.abs(yd)))
            ys = signal.lfilter(_bpoly(dm), _apoly(dm), ud)
            np.testing.assert_allclose(ref.simulation_output(rec["u"], dm, u0), ys,
                                       rtol=1e-10, atol=1e-10 * np.max(np.abs(ys)))


@pytest.mark.parametrize("rec", RECORDS, ids=[r["name"] for r in RECORDS])
def test_zoh_matches_exact_simulation_and_pdtref_discrete(rec):
    """The generator's discrete models reproduce the continuous response at
    the samples, and agree with pdtref.discrete."""
    Ts, u0 = rec["Ts"], rec["u0"]
    for m in rec["cands"]:
        dm = gen.zoh(m, Ts)
        exact = gen.simulate_exact(m, rec["u"], u0, Ts)
        sim = ref.simulation_output(rec["u"], dm, u0)
        scale = max(1.0, np.max(np.abs(exact)))
        np.testing.assert_allclose(sim, exact, rtol=0, atol=1e-9 * scale)
        other = discrete.zoh(_lib_model(m), Ts)
        assert other.delay == dm.delay and other.order == dm.order
        np.testing.assert_allclose(np.asarray(other.a)[:dm.order], dm.a[:dm.order],
                                   rtol=1e-10, atol=1e-14)
        np.testing.assert_allclose(other.b, dm.b, rtol=1e-8, atol=1e-13)
        l = gen.int_delay(m, Ts)
        di, oi = gen.zoh(m, Ts, l), discrete.zoh_int(_lib_model(m), Ts, l)
        assert oi.delay == di.delay == l
        np.testing.assert_allclose(oi.b, di.b, rtol=1e-8, atol=1e-13)
        # The delta-form denominator is consistent with a[].
        d_from_a = [1.0 + dm.a[0], 0.0] if dm.order == 1 else [2.0 + dm.a[0],
                                                               1.0 + dm.a[0] + dm.a[1]]
        np.testing.assert_allclose(dm.d, d_from_a, rtol=1e-9, atol=1e-15)


def test_simulation_matches_pdtref_discrete():
    rec = RECORDS[1]
    for m in rec["cands"]:
        d = discrete.zoh(_lib_model(m), rec["Ts"])
        np.testing.assert_allclose(ref.simulation_output(rec["u"], d, rec["u0"]),
                                   discrete.simulate(d, rec["u"] - rec["u0"]),
                                   rtol=1e-12, atol=1e-12)


def test_gain_magnitude_matches_models_freq():
    w = np.linspace(0.01, 30.0, 200)
    for m in (models.Fopdt(-2.0, 3.0, 1.0), models.Sopdt(2.16, 0.72, 1.44, 0.8),
              models.Sopdt(0.2, 0.5, 0.0, 0.5), models.Sopdt(1.0, 3.0, 1.0, 0.0)):
        np.testing.assert_allclose(ref.gain_magnitude(m, w), models.freq(m, w)[0], rtol=1e-12)


def test_frequency_cost_by_direct_dft():
    """Cf from an explicit DFT matrix on a short record, all three weights."""
    rec = RECORDS[3]
    n = 40
    u, y = rec["u"][:n], rec["y"][:n]
    lu, Ts = 10, rec["Ts"]
    nf = ref.fft_size(n, lu)
    assert nf == 64
    j = np.arange(n)
    k = np.arange(1, nf // 2 + 1)
    F = np.exp(-2j * np.pi * np.outer(k, j) / nf)
    U, Y = np.abs(F @ (u - rec["u0"])), np.abs(F @ (y - rec["y0"]))
    m = models.Fopdt(-0.7, 6.0, 2.3)
    G = np.abs(m.K / (1 + 1j * 2 * np.pi * k / (nf * Ts) * m.tau))
    mirror = np.where(k < nf // 2, 2.0, 1.0)
    f_lo, f_hi = gen.band_edges(nf, Ts)
    wts = gen.custom_weights(nf)
    for weight, W in (("uniform", np.ones(len(k))),
                      ("band", ((k / (nf * Ts) >= f_lo) & (k / (nf * Ts) <= f_hi)) * 1.0),
                      ("custom", wts[k])):
        want = np.sum(W * mirror * (Y - G * U) ** 2) / (nf * n)
        got = ref.frequency_cost(u, y, m, Ts, rec["u0"], rec["y0"], lu, weight, f_lo, f_hi,
                                 wts)
        assert got == pytest.approx(want, rel=1e-12)


@pytest.mark.parametrize("rec", RECORDS, ids=[r["name"] for r in RECORDS])
def test_parseval_and_dead_time(rec):
    u, y, u0, y0, Ts, lu = (rec[x] for x in ("u", "y", "u0", "y0", "Ts", "delay_max"))
    n = len(y)
    nf = ref.fft_size(n, lu)
    yd = y - y0
    want = (np.sum(yd ** 2) - np.sum(yd) ** 2 / nf) / n
    got = ref.frequency_cost(u, y, models.Fopdt(0.0, 1.0, 0.0), Ts, u0, y0, lu)
    assert got == pytest.approx(want, rel=1e-12)
    for m in rec["cands"]:
        base = ref.frequency_cost(u, y, m, Ts, u0, y0, lu)
        for td in (0.0, 0.37, 50.0):
            assert ref.frequency_cost(u, y, m._replace(Td=td), Ts, u0, y0, lu) == base


def test_offset_invariance_and_exact_model():
    rec = RECORDS[0]
    u, u0, Ts, lu = rec["u"], rec["u0"], rec["Ts"], rec["delay_max"]
    m = rec["cands"][0]
    dm = gen.zoh(m, Ts)
    clean = 20.0 + gen.simulate_exact(m, u, u0, Ts)
    for fn in (ref.prediction_cost, ref.simulation_cost):
        assert fn(u, clean, dm, u0, 20.0, lu, False) < 1e-20
        a = fn(u, rec["y"], dm, u0, 20.0, lu, True)
        b = fn(u, rec["y"] + 7.25, dm, u0, 20.0, lu, True)
        assert b == pytest.approx(a, rel=1e-9)
        # Without the fit the shift shows: by 7.25 in the simulation
        # residual, by d0 * 7.25 (the static part of A(q)) in prediction.
        c = fn(u, rec["y"] + 7.25, dm, u0, 20.0, lu, False)
        step = 7.25 if fn is ref.simulation_cost else 7.25 * dm.d[0]
        assert c == pytest.approx(a + step ** 2, rel=0.05)


def test_truth_scores_best_in_time_costs():
    """A sanity check of the data: the true plant has the lowest simulation
    cost among the candidates of each record."""
    for rec in RECORDS:
        rows = [gen.costs(rec, m) for m in rec["cands"]]
        sim = [r[gen.COLUMNS.index("SIM_FRAC_OFS")] for r in rows]
        assert int(np.argmin(sim)) == 0, rec["name"]


def test_vectors_are_modest():
    text = gen.generate()[gen.FILE]
    assert len(text) < 200_000
