"""Checks of the tuning reference (tools/pdtref/tune.py): published numbers,
closed forms of the figures, scipy's optimiser and closed-loop poles as
independent routes, and the limits that tie the rules together."""
import math
import pathlib

import numpy as np
import pytest
from scipy import optimize

from pdtref import models as M
from pdtref import tune as T
from vectorgen._emit import vectors_differ

ROOT = pathlib.Path(__file__).resolve().parents[2]


def test_simc_paper_17():
    # Skogestad's half-rule models of (17): PI 0.85 / 2.5, PID 1.30 / 2 / 1.2
    g, series, tc = T.simc(T.view(M.Fopdt(1.0, 2.5, 1.47)), T.PI)
    assert series and tc == 1.47
    assert round(g["Kc"], 2) == 0.85 and g["tauI"] == 2.5 and g["tauD"] == 0
    g, series, _ = T.simc(T.view(M.sopdt_from_tc(1.0, 2.0, 1.2, 0.77)), T.PID)
    assert round(g["Kc"], 2) == 1.30
    assert g["tauI"] == pytest.approx(2.0) and g["tauD"] == pytest.approx(1.2)


def test_simc_pi_figures_closed_form():
    # tauI = tau: L = e^{-theta s} / (2 theta s), so GM = pi, w_pc = pi / (2 theta),
    # w_gc = 1 / (2 theta), PM = 90 deg - 0.5 rad.
    th = 1.47
    st, res = T.compute(M.Fopdt(1.0, 2.5, th), T.SIMC, T.PI)
    f = res["fig"]
    assert st == T.OK
    assert f["gm"] == pytest.approx(math.pi, rel=1e-9)
    assert f["w_pc"] == pytest.approx(math.pi / (2 * th), rel=1e-9)
    assert f["w_gc"] == pytest.approx(1 / (2 * th), rel=1e-9)
    assert f["pm_deg"] == pytest.approx(90 - math.degrees(0.5), rel=1e-9)
    assert f["Ms"] == pytest.approx(1.59, abs=0.005)


CASES = [
    (M.Fopdt(1.0, 2.5, 1.47), T.AMIGO, T.PID),
    (M.Fopdt(2.0, 10.0, 1.0), T.IMC, T.PID),
    (M.sopdt_from_tc(1.0, 2.0, 1.2, 0.77), T.SIMC, T.PID),
    (M.sopdt_from_natural(1.3, 2.0, 0.5, 0.4), T.IMC, T.PID),
    (M.sopdt_from_integ(0.5, 2.0, 0.33), T.AMIGO, T.PI),
    (M.Fopdt(1.0, 2.5, 1.47), T.ZN, T.PID),
]


@pytest.mark.parametrize("m,rule,form", CASES)
def test_ms_by_optimiser(m, rule, form):
    st, res = T.compute(m, rule, form)
    assert st == T.OK
    f, g = res["fig"], res["ideal"]

    def neg_s(x):
        return -1 / abs(1 + T.loop(m, g, [math.exp(x)])[0])

    x = math.log(f["w_ms"])
    opt = optimize.minimize_scalar(neg_s, bounds=(x - 0.05, x + 0.05), method="bounded",
                                   options={"xatol": 1e-10})
    assert -opt.fun == pytest.approx(f["Ms"], rel=1e-9)
    # and the figures satisfy their definitions
    L = T.loop(m, g, [f["w_gc"]])[0]
    assert abs(L) == pytest.approx(1.0, rel=1e-9)
    assert 180 + math.degrees(np.angle(L)) == pytest.approx(f["pm_deg"], rel=1e-9)
    L = T.loop(m, g, [f["w_pc"]])[0]
    assert abs(L.imag) < 1e-9 * abs(L) and L.real < 0
    assert -1 / L.real == pytest.approx(f["gm"], rel=1e-9)


@pytest.mark.parametrize("m,rule,form", CASES)
def test_gain_margin_is_the_stability_limit(m, rule, form):
    st, res = T.compute(m, rule, form)
    g, gm = res["ideal"], res["fig"]["gm"]
    T.robustness(m, dict(g, Kc=g["Kc"] * gm * 0.99))
    with pytest.raises(T.TuneError) as e:
        T.robustness(m, dict(g, Kc=g["Kc"] * gm * 1.01))
    assert e.value.status == T.UNSTABLE


def test_stability_verdict_against_closed_loop_poles():
    # SOPDT without dead time, PI: tauI s (s^2 + a s + b) + Kc k (tauI s + 1)
    k, a, b = 1.0, 0.6, 0.5
    m = M.Sopdt(k, a, b, 0.0)
    for Kc in np.geomspace(0.05, 50, 40):
        for tauI in (0.3, 1.0, 4.0):
            g = T.gains(Kc, tauI)
            poles = np.roots([tauI, tauI * a, tauI * b + Kc * k * tauI, Kc * k])
            stable = bool(np.all(poles.real < 0))
            if abs(np.max(poles.real)) < 1e-6:
                continue
            try:
                T.robustness(m, g)
                verdict = True
            except T.TuneError:
                verdict = False
            assert verdict == stable, (Kc, tauI, poles)


def test_integrating_stability_against_poles():
    # integrator with lag, no dead time, PI: tauI s^2 (T s + 1) + Ki Kc (tauI s + 1)
    Ki, T_ = 0.5, 2.0
    m = M.sopdt_from_integ(Ki, T_, 0.0)
    for Kc in np.geomspace(0.01, 10, 30):
        for tauI in (1.0, 3.0, 10.0, 40.0):
            poles = np.roots([tauI * T_, tauI, Ki * Kc * tauI, Ki * Kc])
            stable = bool(np.all(poles.real < 0))
            if abs(np.max(poles.real)) < 1e-6:
                continue
            try:
                T.robustness(m, T.gains(Kc, tauI))
                verdict = True
            except T.TuneError:
                verdict = False
            assert verdict == stable, (Kc, tauI)


def test_amigo_integrating_limit():
    # K = Kv T with T -> infinity: the FOPDT rules tend to the integrating ones
    Kv, L, big = 0.5, 1.0, 1e7
    vf = T.view(M.Fopdt(Kv * big, big, L))
    vi = T.view(M.sopdt_from_integ(Kv, 1e-9, L))
    for form, rel in ((T.PID, 1e-5), (T.PI, 0.004)):   # PI: 13.35 L vs the 13.4 L published
        gf, _, _ = T.amigo(vf, form)
        gi, _, _ = T.amigo(vi, form)
        for key in ("Kc", "tauI", "tauD"):
            assert gf[key] == pytest.approx(gi[key], rel=rel)


def test_imc_pid_is_pole_cancelling():
    # IMC PID on a FOPDT: series form (tau s + 1)(theta/2 s + 1) / (K (lam + theta/2) s)
    tau, th, lam, K = 3.0, 1.0, 2.0, 2.0
    g, _, _ = T.imc(T.view(M.Fopdt(K, tau, th)), T.PID, lam)
    s = T.ideal_to_series(g)
    assert s["tauI"] == pytest.approx(tau) and s["tauD"] == pytest.approx(th / 2)
    assert s["Kc"] == pytest.approx(tau / (K * (lam + th / 2)))
    # on a SOPDT, the ideal PID's numerator is the model's denominator
    m = M.sopdt_from_natural(1.0, 2.0, 0.3, 0.5)
    g, _, _ = T.imc(T.view(m), T.PID, 1.0)
    num = np.array([g["tauI"] * g["tauD"], g["tauI"], 1.0])
    assert num / num[0] == pytest.approx(np.array([1.0, m.a, m.b]))


def test_forms_round_trip():
    for s in (T.gains(1.3, 2.0, 1.2), T.gains(-0.5, 0.2, 3.0), T.gains(2.0, 5.0)):
        back = T.ideal_to_series(T.series_to_ideal(s))
        for key in ("Kc", "tauI", "tauD"):
            t = sorted([s["tauI"], s["tauD"]])[::-1]
            want = {"Kc": s["Kc"] * t[0] / s["tauI"], "tauI": t[0], "tauD": t[1]}[key]
            assert back[key] == pytest.approx(want)
    assert T.ideal_to_series(T.gains(1.0, 1.0, 0.3)) is None


@pytest.mark.parametrize("m", [M.Fopdt(1.0, 2.5, 1.47), M.sopdt_from_tc(1.0, 2.0, 1.2, 0.77),
                               M.sopdt_from_integ(0.5, 2.0, 0.33)])
def test_ultimate_point(m):
    Ku, Pu = T.ultimate(m)
    wu = 2 * math.pi / Pu
    G = T.freq(m, [wu])[0]
    assert abs(Ku * G) == pytest.approx(1.0, rel=1e-12)
    assert np.angle(G) == pytest.approx(math.pi, rel=1e-9) or \
        np.angle(G) == pytest.approx(-math.pi, rel=1e-9)
    # brentq on the continuous phase, as an independent solver
    if isinstance(m, M.Fopdt):
        w2 = optimize.brentq(lambda w: math.atan(w * m.tau) + w * m.Td - math.pi, 1e-9,
                             math.pi / m.Td)
        assert w2 == pytest.approx(wu, rel=1e-12)


def test_refusals():
    m = M.Fopdt(1.0, 2.5, 1.47)
    assert T.compute(m, T.SIMC, T.PI, fit=79.0)[0] == T.OK  # fit_min off by default
    assert T.compute(m, T.SIMC, T.PI, fit=79.0, fit_min=80.0)[0] == T.POOR_FIT
    assert T.compute(m, T.ZN, T.PID, ms_max=2.0)[0] == T.MS_LIMIT
    assert T.compute(M.Fopdt(1.0, 0.1, 10.0), T.ZN, T.PID)[0] == T.UNSTABLE
    # complex poles: the half rule of the pair split by its real part
    under = M.sopdt_from_natural(1.0, 1.0, 0.8, 0.5)
    for rule in (T.SIMC, T.IMC, T.AMIGO):
        assert T.compute(under, rule, T.PI)[0] == T.OK
    st, r = T.compute(under, T.SIMC, T.PI)
    assert r["ideal"]["Kc"] == pytest.approx(1.2 / 1.8) and r["ideal"]["tauI"] == pytest.approx(1.2)
    assert T.compute(M.Fopdt(1.0, 1.0, 0.0), T.AMIGO, T.PI)[0] == T.ARG
    assert T.compute(M.Fopdt(1.0, 1.0, 0.0), T.ZN, T.PI)[0] == T.NO_FORM


def test_vectors_current():
    from vectorgen import tune as gen
    for name, text in gen.generate().items():
        assert vectors_differ((ROOT / "tests" / "vectors" / name).read_text(), text) is None
