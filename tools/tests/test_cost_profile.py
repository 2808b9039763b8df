"""Checks of the cost reference's whole-record scoring, gain/offset profile
and simulation (pdtref.cost) against independent computations:
scipy.signal.lfilter, linear least squares (numpy.linalg.lstsq), bounded
scalar minimisation (scipy.optimize), and exact recovery on noise-free
data."""

import numpy as np
import pytest
from scipy import optimize, signal

from pdtref import cost as ref
from pdtsupport.rng import SplitMix64 as Rng
from vectorgen import cost as base
from vectorgen import cost_profile as gen

RECORDS = gen.records()
IDS = [r["name"] for r in RECORDS]


def _bpoly(dm):
    return np.concatenate([np.zeros(dm.delay + 1), dm.b])


def _apoly(dm):
    return np.concatenate([[1.0], dm.a[:dm.order]])


def _opts(rec, cfg, **extra):
    opts = gen._options(rec, cfg)
    opts.update(extra)
    return opts


# ---- whole_record ----

@pytest.mark.parametrize("rec", RECORDS, ids=IDS)
def test_whole_record_scores_every_sample_the_cost_can(rec):
    u, y, u0, y0, Ts, lu = rec["u"], rec["y"], rec["u0"], rec["y0"], rec["Ts"], rec["delay_max"]
    n = len(u)
    for m in rec["shapes"]:
        dm = base.zoh(m, Ts)
        k = ref.time_range(n, lu, dm.order, whole_record=True)
        assert k[0] == dm.order and k[-1] == n - 1 and len(k) == n - dm.order
        ks = ref.time_range(n, lu, dm.order, whole_record=True, simulation=True)
        assert ks[0] == 0 and ks[-1] == n - 1 and len(ks) == n
        ud, yd = u - u0, y - y0
        r_pred = signal.lfilter(_apoly(dm), [1.0], yd) - signal.lfilter(_bpoly(dm), [1.0], ud)
        r_sim = yd - signal.lfilter(_bpoly(dm), _apoly(dm), ud)
        scale = np.max(np.abs(yd))
        np.testing.assert_allclose(ref.prediction_residuals(u, y, dm, u0, y0, lu, True),
                                   r_pred[k], rtol=0, atol=1e-12 * scale)
        np.testing.assert_allclose(ref.simulation_residuals(u, y, dm, u0, y0, lu, True),
                                   r_sim, rtol=0, atol=1e-10 * scale)
        for ofs in (False, True):
            # The prediction over the whole record is the paper's window
            # with delay bound 0; the simulation scores `order` more samples.
            whole = ref.prediction_cost(u, y, dm, u0, y0, lu, ofs, True)
            assert whole == pytest.approx(ref.prediction_cost(u, y, dm, u0, y0, 0, ofs),
                                          rel=1e-13)
            whole = ref.simulation_cost(u, y, dm, u0, y0, lu, ofs, True)
            assert whole == pytest.approx(ref.time_cost(r_sim, ofs), rel=1e-12)
            for fn in (ref.prediction_cost, ref.simulation_cost):
                whole = fn(u, y, dm, u0, y0, lu, ofs, True)
                # The default keeps the paper's window.
                assert fn(u, y, dm, u0, y0, lu, ofs) == fn(u, y, dm, u0, y0, lu, ofs, False)
                if lu > 0:
                    assert whole != fn(u, y, dm, u0, y0, lu, ofs)


# ---- simulate ----

@pytest.mark.parametrize("rec", RECORDS, ids=IDS)
def test_simulate_matches_lfilter(rec):
    u, u0, y0 = rec["u"], rec["u0"], rec["y0"]
    for dm in gen.sim_models(rec):
        want = y0 + signal.lfilter(_bpoly(dm), _apoly(dm), u - u0)
        got = ref.simulate(u, dm, u0, y0)
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-10 * (1.0 + np.max(np.abs(want))))
    # Beyond delay_max the response starts late: zero deviation before it.
    dm = gen.sim_models(rec)[1]
    assert np.all(ref.simulate(u, dm, u0, y0)[:dm.delay + 1] == y0)


# ---- profile ----

def _time_regression(rec, dm, tk, ofs, whole):
    """Gain and offset of the time part by linear least squares of the data
    side on the shape's response (and a constant): the closed form the
    reference does not use."""
    u, y, u0, y0 = rec["u"], rec["y"], rec["u0"], rec["y0"]
    ud, yd = u - u0, y - y0
    k = ref.time_range(len(u), rec["delay_max"], dm.order, whole, tk == "simulation")
    if tk == "simulation":
        x = signal.lfilter(_bpoly(dm), _apoly(dm), ud)[k]
        e = yd[k]
    else:
        x = signal.lfilter(_bpoly(dm), [1.0], ud)[k]
        e = signal.lfilter(_apoly(dm), [1.0], yd)[k]
    cols = [x, np.ones_like(x)] if ofs else [x]
    sol = np.linalg.lstsq(np.column_stack(cols), e, rcond=None)[0]
    return sol[0], (sol[1] if ofs else 0.0)


def _freq_regression(rec, m, weight):
    """Gain magnitude of the frequency part by weighted least squares of |Y|
    on |G||U|, spectra by a direct matrix DFT."""
    u, y, u0, y0, Ts = rec["u"], rec["y"], rec["u0"], rec["y0"], rec["Ts"]
    n = len(u)
    nf = ref.fft_size(n, rec["delay_max"])
    kk = np.arange(1, nf // 2 + 1)
    basis = np.exp(-2j * np.pi * np.outer(kk, np.arange(n)) / nf)
    umag, ymag = np.abs(basis @ (u - u0)), np.abs(basis @ (y - y0))
    f_lo, f_hi = base.band_edges(nf, Ts)
    W = ref.bin_weights(nf, Ts, weight, f_lo, f_hi)[kk] * np.where(kk < nf // 2, 2.0, 1.0)
    g = ref.gain_magnitude(m, 2.0 * np.pi * kk / (nf * Ts)) * umag
    return np.sum(W * g * ymag) / np.sum(W * g * g)


CASES = [(ri, si, ci) for ri, rec in enumerate(RECORDS) for si in range(len(rec["shapes"]))
         for ci in range(len(gen.CONFIGS))]


@pytest.mark.parametrize("ri,si", sorted({(r, s) for r, s, _ in CASES}))
def test_unbounded_single_kinds_match_least_squares(ri, si):
    rec = RECORDS[ri]
    m = rec["shapes"][si]
    for cfg in gen.CONFIGS:
        kind, tk, mode, whole, ofs, bmode = cfg[1], cfg[2], cfg[3], cfg[4], cfg[5], cfg[9]
        if bmode != "none" or kind == "combined":
            continue
        dm = gen._dmodel(m, rec["Ts"], mode)
        res = ref.profile(rec["u"], rec["y"], m, dm, rec["Ts"], kind, **_opts(rec, cfg))
        if kind == "frequency":
            want = _freq_regression(rec, m, cfg[8])
            assert res["gain"] == pytest.approx(abs(want), rel=1e-9)
            assert res["sign_free"] and res["offset"] == 0.0 and res["ct"] == 0.0
            continue
        gain, off = _time_regression(rec, dm, kind, ofs, whole)
        assert res["gain"] == pytest.approx(gain, rel=1e-9, abs=1e-12)
        if kind == "prediction":
            a1 = ref.static_gain(dm)
            off = off / a1 if a1 > 1e-12 else 0.0
        assert res["offset"] == pytest.approx(off, rel=1e-7, abs=1e-9 * (1 + abs(rec["y0"])))
        assert res["cf"] == 0.0 and res["cost"] == res["ct"]


def _total(rec, m, dm, cfg, gain, **extra):
    """The configured cost at a given gain, from the reference's plain cost
    functions (offset profiled by the variance when estimate_offset)."""
    kind, tk, whole, ofs, pt, pf = cfg[1], cfg[2], cfg[4], cfg[5], cfg[6], cfg[7]
    if kind in ("prediction", "simulation"):
        tk = kind
    o = _opts(rec, cfg, **extra)
    t = (ref.prediction_cost if tk == "prediction" else ref.simulation_cost)(
        rec["u"], rec["y"], ref.scaled(dm, gain), rec["u0"], o["y0"], rec["delay_max"], ofs,
        whole)
    f = ref.frequency_cost(rec["u"], rec["y"], ref.scaled(m, gain), rec["Ts"], rec["u0"],
                           rec["y0"], rec["delay_max"], o["weight"], o["f_lo"], o["f_hi"])
    if kind == "combined":
        return ref.combined_cost(t, f, pt, pf), t, f
    return (f if kind == "frequency" else t), t, f


@pytest.mark.parametrize("ri", range(len(RECORDS)), ids=IDS)
def test_profile_is_the_bounded_minimum(ri):
    """Against bounded scalar minimisation on each half-line, and against
    a grid of gains inside the bounds."""
    rec = RECORDS[ri]
    for m in rec["shapes"]:
        for cfg in gen.CONFIGS:
            dm = gen._dmodel(m, rec["Ts"], cfg[3])
            lo, hi, res = gen.profile_case(rec, m, cfg)
            a, b = (lo, hi) if (lo, hi) != (0.0, 0.0) else (-50.0, 50.0)
            assert a <= res["gain"] <= b

            def J(g):
                return _total(rec, m, dm, cfg, g)[0]

            best = np.inf
            for x0, x1 in ((max(a, 0.0), b), (a, min(b, 0.0))):
                if x0 <= x1:
                    r = optimize.minimize_scalar(J, bounds=(x0, x1), method="bounded",
                                                 options={"xatol": 1e-10})
                    best = min(best, r.fun, J(x0), J(x1))
            assert res["cost"] <= best * (1 + 1e-9) + 1e-15
            assert res["cost"] == pytest.approx(best, rel=1e-6)
            grid = np.linspace(a, b, 41)
            assert res["cost"] <= min(J(g) for g in grid) * (1 + 1e-12)
            # The parts are the costs at the returned gain.
            total, t, f = _total(rec, m, dm, cfg, res["gain"])
            assert res["cost"] == pytest.approx(total, rel=1e-12)
            if cfg[1] != "frequency":
                assert res["ct"] == pytest.approx(t, rel=1e-12)
            if cfg[1] != "prediction" and cfg[1] != "simulation":
                assert res["cf"] == pytest.approx(f, rel=1e-12)


@pytest.mark.parametrize("ri", range(len(RECORDS)), ids=IDS)
def test_offset_reproduces_the_profiled_time_cost(ri):
    """Moving y0 by the returned offset and scoring without the offset fit
    gives the variance the profile minimised."""
    rec = RECORDS[ri]
    for m in rec["shapes"]:
        for cfg in gen.CONFIGS:
            if not cfg[5] or cfg[1] == "frequency":
                continue
            dm = gen._dmodel(m, rec["Ts"], cfg[3])
            _, _, res = gen.profile_case(rec, m, cfg)
            tk = cfg[1] if cfg[1] != "combined" else cfg[2]
            if tk == "prediction" and ref.static_gain(dm) <= 1e-12:
                assert res["offset"] == 0.0  # integrating: A(1) = 0
                continue
            fn = ref.prediction_cost if tk == "prediction" else ref.simulation_cost
            shifted = fn(rec["u"], rec["y"], ref.scaled(dm, res["gain"]), rec["u0"],
                         rec["y0"] + res["offset"], rec["delay_max"], False, cfg[4])
            assert shifted == pytest.approx(res["ct"], rel=1e-9)


def test_sign_free_frequency_takes_the_positive_gain():
    rec = RECORDS[0]
    m = rec["shapes"][0]
    dm = base.zoh(m, rec["Ts"])
    cfg = [c for c in gen.CONFIGS if c[0] == "freq"][0]
    res = ref.profile(rec["u"], rec["y"], m, dm, rec["Ts"], "frequency", **_opts(rec, cfg))
    assert res["sign_free"] and res["gain"] > 0
    neg = ref.profile(rec["u"], rec["y"], m, dm, rec["Ts"], "frequency", gain_min=-10.0,
                      gain_max=-0.5, **_opts(rec, cfg))
    assert neg["gain"] == pytest.approx(-res["gain"], rel=1e-12)
    assert not neg["sign_free"] and neg["cost"] == pytest.approx(res["cost"], rel=1e-12)


@pytest.mark.parametrize("order", [1, 2])
def test_exact_recovery_on_clean_data(order):
    """Data made by a discrete model with gain 2.5 and an output offset:
    the profile of the unit-gain shape returns both, at zero cost."""
    n, Ts, u0, y0, true_off = 300, 0.1, 5.0, 40.0, 0.75
    rng = Rng.keyed(99)
    u = u0 + 2.0 * rng.signs(n, 6)
    m = base.Fopdt(1.0, 1.5, 0.63) if order == 1 else base.Sopdt(1.0, 1.2, 0.8, 0.63)
    dm = base.zoh(m, Ts)
    y = y0 + true_off + 2.5 * signal.lfilter(_bpoly(dm), _apoly(dm), u - u0)
    for kind in ("simulation", "prediction"):
        for whole in (False, True):
            res = ref.profile(u, y, m, dm, Ts, kind, u0=u0, y0=y0, delay_max=20,
                              whole_record=whole)
            assert res["gain"] == pytest.approx(2.5, rel=1e-9)
            assert res["offset"] == pytest.approx(true_off, rel=1e-7)
            assert res["cost"] <= 1e-20
            res = ref.profile(u, y, m, dm, Ts, kind, u0=u0, y0=y0, delay_max=20,
                              whole_record=whole, gain_min=-1.0, gain_max=2.0)
            assert res["gain"] == 2.0


def test_bad_arguments():
    rec = RECORDS[0]
    m = rec["shapes"][0]
    dm = base.zoh(m, rec["Ts"])
    with pytest.raises(ValueError):
        ref.profile(rec["u"], rec["y"], m, dm, rec["Ts"], "simulation", gain_min=2.0,
                    gain_max=1.0)
    with pytest.raises(ValueError):
        ref.profile(rec["u"], rec["y"], m, dm, rec["Ts"], "bogus")
    with pytest.raises(ValueError):
        ref.profile(rec["u"], rec["y"], m, dm, rec["Ts"], "combined", time_kind="frequency")


def test_vectors_are_deterministic_and_modest():
    a = gen.generate()
    b = gen.generate()
    assert a == b
    assert sum(len(t) for t in a.values()) < 400_000
