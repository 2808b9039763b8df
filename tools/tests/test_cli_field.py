"""Records as loggers make them (docs/ident-engine.md, "Gross errors" and
"No model without evidence"): identify leaves a bad-value marker and a
dropout out of the fit and says so; its evidence against the null model
is what numpy computes from the same model; a PRBS input with an
unrelated output is flagged no_relation, exit 3."""
import json
import math

import numpy as np
import pytest

from pdtsupport.cli import run, write_csv
from pdtsupport.plant import simulate
from pdtsupport.records import N, TS, U0, Y0, multistep_input, noise
from pdtsupport.rng import SplitMix64

pytestmark = pytest.mark.cli  # skipped or failed without a binary: conftest.py

LAGS = 20  # EVIDENCE_LAGS of lib/src/pdt_ident_vote.c


def record():
    u = multistep_input(N, U0, 5.0, 25, 60, 20, seed=7)
    y = Y0 + simulate([2.0], [5.0, 1.0], 1.3, u - U0, TS) + noise(N, 0.02, 11)
    return u, y


def identify(tmp_path, u, y, model="fopdt", extra=()):
    path = write_csv(tmp_path / "rec.csv", {"t": np.arange(len(u)) * TS, "u": u, "y": y})
    sim = tmp_path / "sim.csv"
    res = run(["identify", "--model", model, "--out-sim", str(sim), *extra, path])
    return res, (np.loadtxt(sim, delimiter=",", skiprows=1) if res.returncode in (0, 3) else None)


def evidence(y, ysim):
    """(n / c) ln(SS_null / SS_model), c = 1 + 2 sum rho_x(l) rho_y(l)."""
    n = len(y)
    x, yc = ysim - ysim.mean(), y - y.mean()

    def rho(v, lag):
        return np.dot(v[lag:], v[:-lag]) / np.dot(v, v)

    c = max(1.0, 1.0 + 2.0 * sum(rho(x, k) * rho(yc, k) for k in range(1, LAGS + 1)))
    return n / c * np.log(np.dot(yc, yc) / np.sum((y - ysim) ** 2))


def test_evidence_matches_numpy(tmp_path):
    u, y = record()
    res, sim = identify(tmp_path, u, y)
    assert res.returncode == 0, res.stderr
    out = json.loads(res.stdout)
    assert "no_relation" not in out["flags"]
    assert out["evidence"] == pytest.approx(evidence(sim[:, 2], sim[:, 3]), rel=2e-3)


@pytest.mark.parametrize("model", ["fopdt", "sopdt", "auto"])
def test_unrelated_output_is_flagged(tmp_path, model):
    rng = SplitMix64.keyed(4)
    u = U0 + 5.0 * rng.signs(N, 5)
    y = Y0 + rng.normal(N)
    res, sim = identify(tmp_path, u, y, model)
    assert res.returncode == 3, res.stderr
    out = json.loads(res.stdout)
    assert "no_relation" in out["flags"]
    assert "no better than the output's mean" in res.stderr
    assert out["evidence"] == pytest.approx(evidence(sim[:, 2], sim[:, 3]), rel=2e-3, abs=1e-3)


@pytest.mark.parametrize("model", ["fopdt", "sopdt"])
def test_marker_and_dropout_left_out(tmp_path, model):
    u, y = record()
    clean, _ = identify(tmp_path, u, y, model)
    ref = json.loads(clean.stdout)
    assert ref["excluded"] == {"count": 0, "missing": 0, "first": []}
    bad = y.copy()
    bad[150] = -9999.0
    bad[400:410] = 0.0
    res, _ = identify(tmp_path, u, bad, model)
    assert res.returncode == 0, res.stderr
    out = json.loads(res.stdout)
    assert out["excluded"]["count"] == 11
    assert out["excluded"]["first"] == [150] + list(range(400, 407))
    assert out["K"] == pytest.approx(ref["K"], rel=0.02)
    assert "11 samples left out of the fit (0 missing, 11 gross errors), data rows 151, 401" \
        in res.stderr


def test_too_many_left_out_is_refused(tmp_path):
    u, y = record()
    bad = y.copy()
    bad[100:400:4] = -9999.0
    res, _ = identify(tmp_path, u, bad)
    assert res.returncode == 1
    assert "data row 101" in res.stderr


def test_record_from_the_step(tmp_path):
    """A record that begins at the step: refused with a message naming
    --u-before; with it, the plant (K = 2, tau = 5 s, Td = 1.3 s)."""
    u = np.full(N, U0 + 5.0)
    y = Y0 + simulate([2.0], [5.0, 1.0], 1.3, np.full(N, 5.0), TS) + noise(N, 0.02, 11)
    res, _ = identify(tmp_path, u, y)
    assert res.returncode == 1
    assert "--u-before" in res.stderr
    res, _ = identify(tmp_path, u, y, extra=("--u-before", str(U0)))
    assert res.returncode == 0, res.stderr
    out = json.loads(res.stdout)
    assert out["u0"] == U0
    assert out["K"] == pytest.approx(2.0, rel=0.01)
    assert out["tau"] == pytest.approx(5.0, rel=0.03)
    res = run(["identify", "--model", "auto", "--u-before", "0", "x.csv"])
    assert res.returncode == 2 and "--u-before goes with" in res.stderr


def test_record_cut_mid_transient(tmp_path):
    """A heater's sine test cut while the output still settles: --initial
    auto finds that it does not start at rest and estimates its state, and
    so does --initial estimate: the whole record's plant (K 0.8, tau 15 s,
    Td 1.4 s), the free response in "x0", --out-sim with it; --initial rest
    does not test it."""
    n = N + 200
    k = np.arange(n)
    u = 50.0 + 20.0 * np.sin(2 * np.pi * k / 300.0)
    y = 24.0 + simulate([0.8], [15.0, 1.0], 1.4, u, TS) + noise(n, 0.1, 3)
    for extra in ((), ("--initial", "estimate")):
        res, sim = identify(tmp_path, u[200:], y[200:], extra=extra)
        assert res.returncode == 0, res.stderr
        out = json.loads(res.stdout)
        assert "mid_transient" not in out["flags"] and out["initial"] == "estimate"
        assert out["K"] == pytest.approx(0.8, rel=0.02)
        assert out["tau"] == pytest.approx(15.0, rel=0.05)
        assert out["Td"] == pytest.approx(1.4, abs=2 * TS)
        # the simulated output with the free response: the fit's residual
        assert np.std(sim[:, 4]) == pytest.approx(0.1, rel=0.2)
    assert "was estimated" in res.stderr or extra
    res, _ = identify(tmp_path, u[200:], y[200:], extra=("--initial", "rest"))
    out = json.loads(res.stdout)
    assert "mid_transient" not in out["flags"] and "initial" not in out


def test_drift(tmp_path):
    """A ramp on the output: --drift gives the ramp-free record's model and
    the slope in "drift"; with another criterion it is refused."""
    u, y = record()
    res, _ = identify(tmp_path, u, y)
    clean = json.loads(res.stdout)
    slope = 0.01
    res, _ = identify(tmp_path, u, y + slope * TS * np.arange(len(u)), extra=("--drift",))
    assert res.returncode == 0, res.stderr
    out = json.loads(res.stdout)
    assert out["K"] == pytest.approx(clean["K"], rel=0.01)
    assert out["tau"] == pytest.approx(clean["tau"], rel=0.03)
    assert out["drift"] == pytest.approx(slope, rel=0.05)
    res = run(["identify", "--model", "fopdt", "--drift", "--cost", "prediction", "x.csv"])
    assert res.returncode == 2 and "--cost simulation" in res.stderr


@pytest.mark.parametrize("model", ["fopdt", "sopdt"])
def test_real_record_cut(tmp_path, root, model):
    """The Box-Jenkins gas furnace (tests/data/real/) cut a third of the way
    in: --initial auto estimates the state (the cut's start still moves
    with the inputs before it) and the gain stays within 5 % of the whole
    record's (docs/reports/real-data.md has the figures)."""
    text = (root / "tests" / "data" / "real" / "gas_furnace.csv").read_text()
    lines = [line for line in text.split("\n") if line.strip()]
    cut = tmp_path / "cut.csv"
    cut.write_text("\n".join([lines[0]] + lines[1:][(len(lines) - 1) // 3:]) + "\n")
    opts = ["identify", "--model", model, "--u", "input_gas_rate", "--y", "co2", "--fs",
            "%.17g" % (1.0 / 9.0)]
    whole = json.loads(run(opts + [str(root / "tests" / "data" / "real" / "gas_furnace.csv")])
                       .stdout)
    res = run(opts + [str(cut)])
    assert res.returncode == 0, res.stderr
    out = json.loads(res.stdout)
    assert out["initial"] == "estimate" and "was estimated" in res.stderr

    def gain(j):
        return j["K"] if j["K"] is not None else math.nan

    assert gain(out) == pytest.approx(gain(whole), rel=0.05)
